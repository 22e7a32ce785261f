//! Issue 7 study: accuracy per cost of the stabilised MFVM variants (method.md §3.9) on the
//! paper's beam on a rigid foundation (problems/beam_on_foundation.toml), at several node
//! spacings. Prints one Markdown table per variant: contact onset `l_c` (both estimators), total
//! contact force `F_c`, peak pressure, pressure ripple, tip deflection, node and nonzero counts,
//! and wall time per stage; then the errors against the independent Q2 FE reference
//! (`F_c = 32.3476 ± 1e-4`, `l_c = 19.810 ± 0.005`, `u_y(48, 0) = −0.01009996`; see
//! tests/validation/beam_on_foundation.rs).
//!
//! `cargo run --release --example beta_study [-- --finest 0.0625] [--only 2]` (`--only k`:
//! just variant `k` of the list, 1-based).
//!
//! No parameter is tuned toward any number of the paper; the Hertz case of the issue is
//! examples/beta_study_hertz.rs.

use mlpg_contact::mls::Basis;
use mlpg_contact::post::plot;
use mlpg_contact::problem::Problem;
use std::time::Instant;

/// FE reference (see the module doc).
const FE_FORCE: f64 = 32.3476;
const FE_ONSET: f64 = 19.810;

struct Variant {
    name: &'static str,
    basis: Basis,
    support_factor: f64,
    beta: f64,
}

const VARIANTS: [Variant; 5] = [
    Variant {
        name: "mixed β=0, α_s=2 (paper)",
        basis: Basis::Linear,
        support_factor: 2.0,
        beta: 0.0,
    },
    Variant { name: "β=1, α_s=2", basis: Basis::Linear, support_factor: 2.0, beta: 1.0 },
    Variant { name: "β=1, α_s=3", basis: Basis::Linear, support_factor: 3.0, beta: 1.0 },
    Variant { name: "β=0.5, α_s=3", basis: Basis::Linear, support_factor: 3.0, beta: 0.5 },
    Variant {
        name: "quadratic β=0, α_s=2.5",
        basis: Basis::Quadratic,
        support_factor: 2.5,
        beta: 0.0,
    },
];

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

/// One error-against-cost chart: file stem, x label, x of a row, y label, y of a row.
type ChartSpec = (&'static str, &'static str, fn(&Row) -> f64, &'static str, fn(&Row) -> f64);

fn stage(s: &mlpg_contact::Solution, names: &[&str]) -> f64 {
    s.timings.iter().filter(|t| names.contains(&t.stage)).map(|t| t.seconds).sum()
}

fn run(base: &Problem, v: &Variant, h: f64) -> Result<Row, mlpg_contact::Error> {
    let mut p = base.clone();
    p.node_spacing = h;
    p.discretisation.mls.basis = v.basis;
    p.discretisation.mls.support_factor = v.support_factor;
    p.discretisation.beta = v.beta;
    let t0 = Instant::now();
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&p, &mut silent)?;
    let nonzeros = model.system.matrix.values.len();
    let (_, _, s) = mlpg_contact::solve_model(&p, model, None, &mut silent)?;
    let total = t0.elapsed().as_secs_f64();
    let c = s.contact.as_ref().expect("contact");
    let points = mlpg_contact::nodes::generate(&p.domain, h, p.layout).expect("nodes").points;
    let tip = points
        .iter()
        .position(|q| q[0] == 48.0 && q[1] == 0.0)
        .map(|i| s.displacement[i][1])
        .unwrap_or(f64::NAN);
    let peak = c.pressure.iter().copied().fold(0.0, f64::max);
    // Node-to-node ripple: largest second difference of the pressure over closed candidates
    // whose neighbours are closed too, relative to the peak pressure.
    let ripple = (1..c.pressure.len().saturating_sub(1))
        .filter(|&k| c.closed[k - 1] && c.closed[k] && c.closed[k + 1])
        .map(|k| (c.pressure[k] - 0.5 * (c.pressure[k - 1] + c.pressure[k + 1])).abs())
        .fold(0.0, f64::max)
        / peak.max(f64::MIN_POSITIVE);
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
        times: [
            stage(&s, &["mls_nodes", "mls_faces"]),
            stage(&s, &["assembly"]),
            stage(&s, &["factorisation"]),
            stage(&s, &["condensation"]),
            stage(&s, &["lemke"]),
            total,
        ],
    })
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let finest = args
        .iter()
        .position(|a| a == "--finest")
        .and_then(|i| args.get(i + 1))
        .map(|v| v.parse::<f64>().expect("--finest takes a number"))
        .unwrap_or(0.125);
    let only = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|i| args.get(i + 1))
        .map(|v| v.parse::<usize>().expect("--only takes a variant number"));
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/beam_on_foundation.toml");
    let base = Problem::from_toml(&std::fs::read_to_string(path).expect("problem file"))
        .expect("valid problem");
    let mut spacings = vec![1.0];
    while spacings.last().copied().unwrap_or(0.0) / 2.0 >= finest * 0.999 {
        let h = spacings[spacings.len() - 1] / 2.0;
        spacings.push(h);
    }
    println!("FE reference: F_c = {FE_FORCE}, l_c = {FE_ONSET}\n");
    let mut results: Vec<(&str, Vec<Row>)> = Vec::new();
    for (k, v) in VARIANTS.iter().enumerate() {
        if only.is_some_and(|o| o != k + 1) {
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
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/beta_study");
    std::fs::create_dir_all(&dir).expect("output directory");
    let charts: [ChartSpec; 4] = [
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
    for (stem, x_label, x, y_label, y) in charts {
        let chart = plot::Chart {
            title: format!("beam on a rigid foundation: {y_label} against {x_label}"),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: results
                .iter()
                .enumerate()
                .map(|(k, (name, rows))| plot::Series {
                    label: (*name).into(),
                    points: rows.iter().map(|r| (x(r), y(r))).filter(|p| p.1.is_finite()).collect(),
                    style: plot::Style::Line,
                    colour: k,
                })
                .collect(),
        };
        plot::write_chart(&dir.join(stem), &chart).expect("plot");
    }
    println!("plots: {}", dir.display());
}
