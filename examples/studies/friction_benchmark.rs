//! Cost of friction on the paper's beam: `problems/beam_on_foundation_friction.toml` (μ = 0.3,
//! the load in 10 increments) against the frictionless run of the same problem (μ = 0, one
//! step: `problems/beam_on_foundation.toml`'s answer) and against μ = 0 along the same 10
//! increments (the frictionless LCP per increment). Run with
//!
//! ```text
//! cargo run --release --features studies --example friction_benchmark -- [--spacing h] [--mu μ] [--increments n] [--repeats r] [--fem]
//! ```
//!
//! (defaults `--spacing 0.25 --mu 0.3 --increments 10 --repeats 3`; `--fem` also runs the Q2
//! finite elements). Each run is repeated and the fastest kept. Prints, per run, the stage
//! times (the condensation among them) and, with steps, a table per increment: LCP size
//! (`3m` for the Stewart–Trinkle step LCP, `m` without friction), the solver that answered,
//! Lemke pivots, fixed-point and active-set rounds, seconds; then the ratio of the total
//! times, frictional / frictionless (target < 3). Nothing is asserted.

mod args;

use clap::Parser;
use mlpg_contact::problem::{Method, Problem};
use mlpg_contact::{Silent, Solution, discretise, solve_model};
use std::time::Instant;

/// Friction against frictionless on the paper's beam.
#[derive(Parser)]
struct Cli {
    /// Node spacing h
    #[arg(long, value_name = "H", default_value_t = 0.25, value_parser = args::positive)]
    spacing: f64,
    /// Friction coefficient μ
    #[arg(long, value_name = "MU", default_value_t = 0.3, value_parser = args::positive)]
    mu: f64,
    /// Load increments
    #[arg(long, default_value_t = 10)]
    increments: usize,
    /// Runs per case (the fastest is kept)
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Also run the Q2 finite elements
    #[arg(long)]
    fem: bool,
}

/// The shipped frictional beam with spacing `h`, method, `μ`, and `increments` increments
/// (`increments = 0`: no steps, the full load at once).
fn beam(h: f64, method: Method, mu: f64, increments: usize) -> Problem {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems/beam_on_foundation_friction.toml");
    let text = std::fs::read_to_string(path).expect("the shipped problem file");
    let text = if increments == 0 {
        // The top load given directly, no [[step]] table.
        let cut = text.find("[[step]]").expect("the file has a step");
        let end = text[cut..].find("[contact]").expect("[contact] follows the step") + cut;
        format!("{}{}", &text[..cut], &text[end..])
            .replace("traction = { y = 0.0 }", "traction = { y = -1.0 }")
    } else {
        text.replace("increments = 10", &format!("increments = {increments}"))
    };
    let mut p = Problem::from_toml(&text).expect("a valid problem");
    p.node_spacing = h;
    p.discretisation.method = method;
    p.contact_mut().expect("contact").friction = mu;
    p
}

/// The fastest of `repeats` runs: (total seconds, the solution).
fn timed(problem: &Problem, repeats: usize) -> (f64, Solution) {
    let mut best: Option<(f64, Solution)> = None;
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        let model = discretise(problem, &mut Silent).expect("discretised");
        let (_, _, s) = solve_model(problem, model, None, &mut Silent).expect("solved");
        let seconds = t.elapsed().as_secs_f64();
        if best.as_ref().is_none_or(|b| seconds < b.0) {
            best = Some((seconds, s));
        }
    }
    best.expect("at least one run")
}

fn report(label: &str, seconds: f64, s: &Solution) {
    let c = s.contact().expect("contact");
    let stages: Vec<String> =
        s.timings.iter().map(|t| format!("{} {:.3}", t.stage, t.seconds)).collect();
    println!("\n{label}: {seconds:.3} s total; m = {} candidates", c.candidates.len());
    println!("  stages: {}", stages.join(", "));
    let Some(f) = &c.friction else {
        println!("  one LCP of size {}: {} Lemke pivots", c.candidates.len(), c.lcp.pivots);
        return;
    };
    println!(
        "  {:>4} {:>6} {:>24} {:>7} {:>6} {:>9} {:>10} {:>10} {:>5} {:>5}",
        "inc", "size", "solver", "pivots", "rounds", "seconds", "ΣP", "ΣT", "stick", "slip"
    );
    let size = |solver: mlpg_contact::lcp::FrictionMethod| match solver {
        mlpg_contact::lcp::FrictionMethod::Frictionless => c.candidates.len(),
        _ => 3 * c.candidates.len(),
    };
    for r in &f.increments {
        println!(
            "  {:>4} {:>6} {:>24} {:>7} {:>6} {:>9.4} {:>10.5} {:>10.5} {:>5} {:>5}",
            r.increment,
            size(r.solver),
            format!("{:?}", r.solver),
            r.pivots,
            r.iterations,
            r.seconds,
            r.normal_force,
            r.tangential_force,
            r.stick,
            r.slip
        );
    }
    let sum: f64 = f.increments.iter().map(|r| r.seconds).sum();
    println!("  increments together: {sum:.3} s");
}

fn main() {
    let cli: Cli = args::parse(&[]);
    println!(
        "beam on a rough foundation, h = {}, μ = {}, {} increments; {} rayon threads; fastest of {} runs",
        cli.spacing,
        cli.mu,
        cli.increments,
        rayon::current_num_threads(),
        cli.repeats
    );
    let mut methods = vec![Method::Mfvm];
    if cli.fem {
        methods.push(Method::Fem);
    }
    for method in methods {
        let (t0, s0) = timed(&beam(cli.spacing, method, 0.0, 0), cli.repeats);
        report(&format!("{method:?}, frictionless, one step"), t0, &s0);
        let (ts, ss) = timed(&beam(cli.spacing, method, 0.0, cli.increments), cli.repeats);
        report(&format!("{method:?}, μ = 0, {} increments", cli.increments), ts, &ss);
        let (tf, sf) = timed(&beam(cli.spacing, method, cli.mu, cli.increments), cli.repeats);
        report(&format!("{method:?}, μ = {}, {} increments", cli.mu, cli.increments), tf, &sf);
        println!(
            "\n{method:?}: frictional / frictionless (one step) = {:.2}; frictional / μ = 0 with the same increments = {:.2}",
            tf / t0,
            tf / ts
        );
    }
}
