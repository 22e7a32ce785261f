//! Scaling of the two contact solvers (docs/method.md §5 and §5.1) with the number
//! of contact candidates: one case and one solver per process, so that the peak resident
//! memory (`VmHWM` of `/proc/self/status`) is that of this run. Cases:
//!
//! - `strip`: a strip `L × 1` clamped on its left edge, uniform load 1 downward on its top
//!   edge, rigid foundation 0.01 below its bottom edge (the beam on foundation, stretched;
//!   `examples/studies/contact_timing.rs`); plane stress, `E = 30 000`, `ν = 0.3`, linear
//!   basis, `α_s = 2`, the paper's operator (`β = 0`);
//! - `beam`: `problems/beam_on_foundation.toml` at the given spacing;
//! - `blocks`: the strip on an elastic block `L × 1` (spacing `1.25 h`, fixed on its bottom)
//!   instead of the rigid foundation: two bodies (`examples/studies/strip.rs`).
//!
//! ```text
//! cargo run --release --features studies --example contact_scaling -- --case strip --length 100 --spacing 0.05 --solver active_set
//! cargo run --release --features studies --example contact_scaling -- --case strip --length 100 --spacing 0.05 --solver lemke --friction 0.3
//! ```
//!
//! `--friction μ` makes the contact frictional (one load step; docs/method.md §8).
//!
//! prints one table row: candidates, nodes, solver, discretisation seconds, contact seconds
//! (per stage), iterations / pivots, changes per iteration, factorisations, update columns,
//! total force, scaled complementarity, equilibrium error, peak memory. Nothing is asserted.

mod args;
mod strip;

use strip::{strip, strip_on_block};

use clap::Parser;
use std::time::Instant;

use mlpg_contact::problem::{ContactSolver, Problem};
use mlpg_contact::{Silent, discretise, solve_model};

fn beam(h: f64) -> Problem {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/beam_on_foundation.toml");
    let mut p = Problem::from_toml(&std::fs::read_to_string(path).expect("shipped problem"))
        .unwrap_or_else(|e| panic!("{e}"));
    p.node_spacing = h;
    p
}

/// Peak resident memory of this process in GB.
fn peak_gb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0 / 1024.0)
}

/// One case, one solver: a row of the scaling table of docs/dev/active_set.md.
#[derive(Parser)]
struct Cli {
    /// `strip` (L × 1 on a rigid foundation), `blocks` (the strip on an elastic block) or
    /// `beam` (the shipped beam problem)
    #[arg(long, default_value = "strip")]
    case: String,
    /// Node spacing h
    #[arg(long, value_name = "H", default_value_t = 0.05, value_parser = args::positive)]
    spacing: f64,
    /// Length L of the strip
    #[arg(long, value_name = "L", default_value_t = 25.0, value_parser = args::positive)]
    length: f64,
    /// `lemke`, `active_set` or `auto`
    #[arg(long, default_value = "active_set")]
    solver: String,
    /// Coulomb coefficient μ of the contact (0: frictionless; docs/method.md §8)
    #[arg(long, value_name = "MU", default_value_t = 0.0)]
    friction: f64,
    /// Print the header line first
    #[arg(long)]
    header: bool,
}

fn main() {
    let cli = Cli::parse();
    let mut problem = match cli.case.as_str() {
        "strip" => strip(cli.spacing, cli.length),
        "beam" => beam(cli.spacing),
        "blocks" => strip_on_block(cli.spacing, cli.length),
        other => panic!("unknown case {other}: strip, blocks or beam"),
    };
    let solver = match cli.solver.as_str() {
        "lemke" => ContactSolver::Lemke,
        "active_set" => ContactSolver::ActiveSet,
        "auto" => ContactSolver::Auto,
        other => panic!("unknown solver {other}"),
    };
    problem.contact_mut().expect("a contact problem").solver = solver;
    problem.contact_mut().expect("a contact problem").friction = cli.friction;
    if cli.header {
        println!(
            "| case | h | candidates | nodes | solver | discretise s | contact stages s | iterations | changes per iteration | factorisations / update columns | total force | complementarity | equilibrium | peak GB |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    }
    let t = Instant::now();
    let model = discretise(&problem, &mut Silent).unwrap_or_else(|e| panic!("{e}"));
    let second = problem
        .second_body()
        .map(|p2| discretise(p2, &mut Silent).unwrap_or_else(|e| panic!("{e}")));
    let t_disc = t.elapsed().as_secs_f64();
    let nodes = model.nodes.len() + second.as_ref().map_or(0, |m| m.nodes.len());
    let st = model.factorisation.stats();
    eprintln!(
        "K: bound_flops {:.3e}, bound_nnz {}, factor_nnz {}, numeric {:.2} s, symbolic {:.2} s, ordering {:.2} s",
        st.bound_flops,
        st.bound_nnz,
        st.factor_nnz,
        st.numeric_seconds,
        st.symbolic_seconds,
        st.ordering_seconds
    );
    let (_, _, s) =
        solve_model(&problem, model, second, &mut Silent).unwrap_or_else(|e| panic!("{e}"));
    let c = s.contact().expect("contact");
    let stages: Vec<String> = s
        .timings
        .iter()
        .filter(|t| {
            [
                "contact_candidates",
                "condensation",
                "lemke",
                "lemke_polish",
                "active_set",
                "solve",
                "friction",
            ]
            .contains(&t.stage)
        })
        .map(|t| format!("{} {:.2}", t.stage, t.seconds))
        .collect();
    let (iterations, changes, work) = match &c.active_set {
        Some(a) => (
            a.iterations.to_string(),
            format!("{:?}", a.changes),
            format!(
                "{} / {} ({:.1} s / {:.1} s), {} refined, rescues {:?}",
                a.work.factorisations,
                a.work.update_columns,
                a.work.factorisation_seconds,
                a.work.update_seconds,
                a.work.refinements,
                a.rescues
            ),
        ),
        None => match &c.friction {
            Some(f) => {
                (format!("{} pivots ({:?})", c.lcp.pivots, f.step.method), "-".into(), "-".into())
            }
            None => (format!("{} pivots", c.lcp.pivots), "-".into(), "-".into()),
        },
    };
    if let Some(f) = &c.friction {
        eprintln!(
            "friction μ = {}: ΣT {:.6}, stick {} slip {} open {}, step residual {:.1e}",
            cli.friction,
            f.total_force,
            f.step.state.iter().filter(|s| **s == mlpg_contact::lcp::ContactState::Stick).count(),
            f.step.state.iter().filter(|s| s.is_slip()).count(),
            f.step.state.iter().filter(|s| **s == mlpg_contact::lcp::ContactState::Open).count(),
            f.step.residuals.max()
        );
    }
    println!(
        "| {} {} | {} | {} | {} | {} | {:.1} | {} | {} | {} | {} | {:.6} | {:.1e} | {:.1e} | {:.2} |",
        cli.case,
        if cli.case == "beam" { String::new() } else { format!("{} × 1", cli.length) },
        cli.spacing,
        c.candidates.len(),
        nodes,
        if c.active_set.is_some() { "active_set" } else { "lemke" },
        t_disc,
        stages.join(", "),
        iterations,
        changes,
        work,
        c.total_force,
        c.lcp.residuals.max_complementarity,
        s.second_body()
            .map_or(s.equilibrium_error, |s2| s.equilibrium_error.max(s2.equilibrium_error)),
        peak_gb()
    );
}
