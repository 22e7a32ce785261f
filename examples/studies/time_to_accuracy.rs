//! Time to accuracy on the paper's beam on a rigid foundation, the benchmark that chose the
//! presets: for each discretisation (the five MFVM variants of the β study and the built-in
//! Q2 finite elements), the wall time of the coarsest node spacing at which the contact onset
//! `l_c` is within `0.05` and the total contact force `F_c` within `0.1 %` of the converged
//! value (the accuracy targets set for the method), in one run.
//!
//! ```text
//! cargo run --release --features studies --example time_to_accuracy -- [--finest 0.0625] [--only k] [--fe-reference h]
//! ```
//!
//! * **Converged value**: computed in the same run with the FE discretisation at element size
//!   `--fe-reference` (default 0.125, ~30 s); its uncertainty is printed as the change from
//!   the next coarser FE spacing. Nothing is taken from the paper.
//! * **Ladder**: h = 1, 0.5, 0.25, … down to `--finest` (default 0.0625). A variant stops once
//!   two consecutive spacings meet both tolerances (the first of them is the answer, confirmed
//!   by the second) or once one spacing meets them and took more than `CONFIRM_LIMIT` seconds
//!   (a finer confirmation would take ~4–8× as long; reported as unconfirmed).
//! * **Time**: wall seconds of `discretise` + `solve_model` (nodes, MLS, assembly, LU,
//!   condensation, Lemke, recovery; no output files), one run per spacing. The load average at
//!   the start and end is printed: on a shared machine the times are only as good as it is.
//! * `l_c` is `contact.onset_x` of `summary.json` (`gap^(2/3)` extrapolation clipped to the
//!   bracket [last open, first closed]).
//!
//! `--only k` runs MFVM variant `k` (1-based, as in `examples/studies/study/mod.rs`), or the FE
//! ladder for `k = 6`. Nothing is asserted; the results go into docs/dev/beta_study.md and the
//! notes.

mod args;
#[allow(dead_code)] // the β-study helpers this benchmark does not use
mod study;

use clap::Parser;
use mlpg_contact::problem::{Method, Problem};
use std::time::Instant;
use study::VARIANTS;

/// The accuracy targets: `l_c` within 0.05, `F_c` within 0.1 %.
const ONSET_TOLERANCE: f64 = 0.05;
const FORCE_TOLERANCE: f64 = 1e-3;
/// A spacing that meets the tolerances after more than this many seconds is not confirmed by
/// a finer run.
const CONFIRM_LIMIT: f64 = 20.0;

struct Run {
    h: f64,
    nodes: usize,
    dofs: usize,
    candidates: usize,
    force: f64,
    onset: f64,
    seconds: f64,
}

fn run(base: &Problem, fe: bool, v: usize, h: f64) -> Result<Run, mlpg_contact::Error> {
    let p = if fe {
        let mut p = base.clone();
        p.node_spacing = h;
        p.discretisation.method = Method::Fem;
        p
    } else {
        study::substitute(base, &VARIANTS[v], h)
    };
    let mut silent = mlpg_contact::Silent;
    let t0 = Instant::now();
    let model = mlpg_contact::discretise(&p, &mut silent)?;
    let dofs = model.system.matrix.n;
    let (_, _, s) = mlpg_contact::solve_model(&p, model, None, &mut silent)?;
    let seconds = t0.elapsed().as_secs_f64();
    let c = s.contact().expect("the beam has contact");
    Ok(Run {
        h,
        nodes: s.displacement.len(),
        dofs,
        candidates: c.pressure.len(),
        force: c.total_force,
        onset: c.onset.from_gap.unwrap_or(f64::NAN),
        seconds,
    })
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// Time to accuracy of the five MFVM variants and Q2 finite elements on the beam on a rigid
/// foundation (`--only 6`: the FE ladder).
#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    ladder: args::Ladder,
    #[command(flatten)]
    only: args::Only,
    /// Element size of the FE run that gives the converged value
    #[arg(long, value_name = "H", default_value_t = 0.125, value_parser = args::positive)]
    fe_reference: f64,
}

fn main() {
    let cli: Cli = args::parse(&[("finest", "0.0625")]);
    let finest = cli.ladder.finest;
    let fe_h = cli.fe_reference;
    let base = study::load("beam_on_foundation.toml");
    println!("load average at start: {}", load_average());
    let wall = Instant::now();

    let reference = run(&base, true, 0, fe_h).expect("FE reference");
    let coarser = run(&base, true, 0, 2.0 * fe_h).expect("FE reference, one spacing coarser");
    println!(
        "converged value: FE Q2 at h = {fe_h} ({} nodes, {} DOFs, {:.1} s): F_c = {:.8}, l_c = {:.4}; change from h = {}: F_c {:+.2e}, l_c {:+.4}\n",
        reference.nodes,
        reference.dofs,
        reference.seconds,
        reference.force,
        reference.onset,
        2.0 * fe_h,
        reference.force - coarser.force,
        reference.onset - coarser.onset
    );
    let within = |r: &Run| {
        (r.onset - reference.onset).abs() <= ONSET_TOLERANCE
            && ((r.force - reference.force) / reference.force).abs() <= FORCE_TOLERANCE
    };

    let mut names: Vec<&str> = VARIANTS.iter().map(|v| v.name).collect();
    names.push("FE Q2 (element size h)");
    let mut summary = Vec::new();
    for (k, name) in names.iter().enumerate() {
        if !cli.only.runs(k) {
            continue;
        }
        let fe = k == VARIANTS.len();
        println!("**{name}**\n");
        println!(
            "| h | nodes | DOFs | candidates | F_c | F_c rel. error | l_c | l_c error | within | time [s] |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|");
        let mut first: Option<(Run, bool)> = None;
        for h in study::spacings(1.0, finest) {
            if fe && h <= fe_h * 1.001 {
                break; // the reference itself
            }
            let r = match run(&base, fe, k, h) {
                Ok(r) => r,
                Err(e) => {
                    println!("| {h} | failed: {e} |");
                    first = None;
                    continue;
                }
            };
            let ok = within(&r);
            println!(
                "| {} | {} | {} | {} | {:.6} | {:+.2e} | {:.4} | {:+.4} | {} | {:.2} |",
                r.h,
                r.nodes,
                r.dofs,
                r.candidates,
                r.force,
                (r.force - reference.force) / reference.force,
                r.onset,
                r.onset - reference.onset,
                if ok { "yes" } else { "no" },
                r.seconds
            );
            let slow = r.seconds > CONFIRM_LIMIT;
            match (ok, first.take()) {
                (false, _) => {}
                (true, Some((f, _))) => {
                    first = Some((f, true));
                    break;
                }
                (true, None) => {
                    first = Some((r, false));
                    if slow {
                        break;
                    }
                }
            }
        }
        println!();
        summary.push((*name, first));
    }

    println!(
        "Time to reach l_c within {ONSET_TOLERANCE} and F_c within {} % of the converged value:\n",
        100.0 * FORCE_TOLERANCE
    );
    println!("| discretisation | h | nodes | DOFs | time [s] | confirmed by h/2 |");
    println!("|---|---|---|---|---|---|");
    for (name, first) in &summary {
        match first {
            Some((r, confirmed)) => println!(
                "| {name} | {} | {} | {} | {:.2} | {} |",
                r.h,
                r.nodes,
                r.dofs,
                r.seconds,
                if *confirmed { "yes" } else { "not run" }
            ),
            None => println!("| {name} | not reached by h = {finest} | | | | |"),
        }
    }
    println!(
        "\nload average at end: {}; whole run {:.0} s",
        load_average(),
        wall.elapsed().as_secs_f64()
    );
}
