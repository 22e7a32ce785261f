//! Accuracy per cost of the stabilised MFVM variants (method.md §3.9: the blend β of the
//! collocated and the direct MLS strains, larger supports, the quadratic basis) on the paper's
//! beam on a rigid foundation (problems/beam_on_foundation.toml), at several node spacings.
//! Prints one Markdown table per variant: contact onset `l_c` (both estimators), total
//! contact force `F_c`, peak pressure, pressure ripple, tip deflection, node and nonzero counts,
//! and wall time per stage; then the errors against the independent Q2 FE reference
//! (`F_c = 32.3476 ± 1e-4`, `l_c = 19.810 ± 0.005`, `u_y(48, 0) = −0.01009996`; see
//! tests/validation/beam_on_foundation.rs).
//!
//! ```text
//! cargo run --release --features studies --example beta_study -- [--finest 0.0625] [--only 2]
//! ```
//!
//! `--finest h`: the finest spacing of the ladder 1, 0.5, … (default 0.125); `--only k`: just
//! variant `k` of the list, 1-based. Results: docs/dev/beta_study.md.
//!
//! No parameter is tuned toward any number of the paper; the Hertz case of the study is
//! examples/studies/beta_study_hertz.rs.

mod args;
mod study;

use clap::Parser;
use mlpg_contact::problem::Problem;
use std::time::Instant;
use study::{ChartSpec, VARIANTS, Variant};

/// FE reference (see the module doc).
const FE_FORCE: f64 = 32.3476;
const FE_ONSET: f64 = 19.810;

struct Row {
    h: f64,
    nodes: usize,
    nonzeros: usize,
    force: f64,
    onset_gap: f64,
    onset_pressure: f64,
    peak: f64,
    ripple: f64,
    tip: f64,
    /// (MLS at nodes and faces, assembly, factorisation, condensation, lemke, total) [s].
    times: [f64; 6],
}

fn run(base: &Problem, v: &Variant, h: f64) -> Result<Row, mlpg_contact::Error> {
    let p = study::substitute(base, v, h);
    let t0 = Instant::now();
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&p, &mut silent)?;
    let nonzeros = model.system.matrix.values.len();
    let (_, _, s) = mlpg_contact::solve_model(&p, model, None, &mut silent)?;
    let total = t0.elapsed().as_secs_f64();
    let c = s.contact().expect("contact");
    let points = mlpg_contact::nodes::generate(&p.domain, h, p.layout).expect("nodes").points;
    let tip = points
        .iter()
        .position(|q| q[0] == 48.0 && q[1] == 0.0)
        .map(|i| s.displacement[i][1])
        .unwrap_or(f64::NAN);
    let peak = c.pressure.iter().copied().fold(0.0, f64::max);
    let ripple = study::ripple(c, peak);
    Ok(Row {
        h,
        nodes: s.displacement.len(),
        nonzeros,
        force: c.total_force,
        onset_gap: c.onset.from_gap.unwrap_or(f64::NAN),
        onset_pressure: c.onset.from_pressure.unwrap_or(f64::NAN),
        peak,
        ripple,
        tip,
        times: study::stage_times(&s, total),
    })
}

/// Accuracy per cost of the stabilised MFVM variants on the beam on a rigid foundation, one
/// Markdown table per variant.
#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    ladder: args::Ladder,
    #[command(flatten)]
    only: args::Only,
}

fn main() {
    let cli: Cli = args::parse(&[("finest", "0.125")]);
    let base = study::load("beam_on_foundation.toml");
    let spacings = study::spacings(1.0, cli.ladder.finest);
    println!("FE reference: F_c = {FE_FORCE}, l_c = {FE_ONSET}\n");
    let mut results: Vec<(&str, Vec<Row>)> = Vec::new();
    for (k, v) in VARIANTS.iter().enumerate() {
        if !cli.only.runs(k) {
            continue;
        }
        let mut rows = Vec::new();
        println!("**{}**\n", v.name);
        println!(
            "| h | nodes | nnz(K) | nnz/row | F_c | F_c − FE | l_c (gap) | l_c (pressure) | l_c − FE | peak p | ripple | u_y(48,0) | MLS [s] | assembly [s] | LU [s] | condense [s] | Lemke [s] | total [s] |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        for &h in &spacings {
            let r = match run(&base, v, h) {
                Ok(r) => r,
                Err(e) => {
                    println!("| {h} | failed: {e} |");
                    continue;
                }
            };
            println!(
                "| {} | {} | {} | {:.1} | {:.6} | {:+.2e} | {:.4} | {:.4} | {:+.3} | {:.5} | {:.1e} | {:.8e} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} | {:.2} |",
                r.h,
                r.nodes,
                r.nonzeros,
                r.nonzeros as f64 / (2 * r.nodes) as f64,
                r.force,
                r.force - FE_FORCE,
                r.onset_gap,
                r.onset_pressure,
                r.onset_gap - FE_ONSET,
                r.peak,
                r.ripple,
                r.tip,
                r.times[0],
                r.times[1],
                r.times[2],
                r.times[3],
                r.times[4],
                r.times[5]
            );
            rows.push(r);
        }
        println!();
        results.push((v.name, rows));
    }
    let charts: [ChartSpec<Row>; 4] = [
        (
            "force_vs_dofs",
            "log10 DOFs",
            |r| (2.0 * r.nodes as f64).log10(),
            "log10 |F_c − F_FE|",
            |r| (r.force - FE_FORCE).abs().log10(),
        ),
        (
            "force_vs_time",
            "log10 total time [s]",
            |r| r.times[5].log10(),
            "log10 |F_c − F_FE|",
            |r| (r.force - FE_FORCE).abs().log10(),
        ),
        (
            "onset_vs_dofs",
            "log10 DOFs",
            |r| (2.0 * r.nodes as f64).log10(),
            "log10 |l_c − l_FE|",
            |r| (r.onset_gap - FE_ONSET).abs().log10(),
        ),
        (
            "onset_vs_time",
            "log10 total time [s]",
            |r| r.times[5].log10(),
            "log10 |l_c − l_FE|",
            |r| (r.onset_gap - FE_ONSET).abs().log10(),
        ),
    ];
    study::write_charts("beta_study", "beam on a rigid foundation", &results, &charts);
}
