//! Adaptive refinement of an axisymmetric body against uniform node sets (docs/method.md §2.2,
//! §9.7): the Hertz sphere on a rigid flat (`tests/validation/axisymmetric_adaptive.rs`, the
//! quarter-disk section of `problems/sphere_on_flat_axisymmetric.toml`, `a/R ≈ 0.125`).
//! Results and reading: docs/dev/axisymmetric.md (increment 7d).
//!
//! Prints, for the uniform structured sets (`β = 0` as the earlier series, and `β = 0.5`, the
//! loop's blend) and for every solve of the adaptive loop: nodes, the axial force `F`, the
//! errors of the fitted `a` and `p₀` against Hertz for that `F`, the same against the FE on
//! Gmsh mesh 2 (the independent reference: the ratio fit/Hertz of each run divided by the FE's),
//! the closed candidates and the time (the loop's: cumulative).
//!
//! `cargo run --release --features studies --example axisymmetric_adaptive -- [--uniform
//! 0.02,0.015,0.0125,0.01] [--start 0.05] [--steps 8] [--fraction 0.5] [--max-nodes 20000]`

mod args;
#[path = "../../tests/validation/axisymmetric_adaptive.rs"]
#[allow(dead_code)]
mod axisymmetric_adaptive;
#[path = "../../tests/validation/axisymmetric_contact.rs"]
#[allow(dead_code, unused_imports)]
mod axisymmetric_contact;
#[path = "../../tests/validation/common.rs"]
#[allow(dead_code)]
mod common;

use axisymmetric_adaptive::{Row, row, sphere_adaptive, sphere_uniform};
use std::time::Instant;

/// Uniform node sets and the adaptive loop on the axisymmetric Hertz sphere.
#[derive(clap::Parser)]
struct Cli {
    /// Uniform node spacings
    #[arg(long, value_name = "H,…", value_delimiter = ',', value_parser = args::positive,
          default_values_t = [0.02, 0.015, 0.0125, 0.01])]
    uniform: Vec<f64>,
    /// Blends β of the uniform sets
    #[arg(long, value_name = "B,…", value_delimiter = ',', default_values_t = [0.0, 0.5])]
    beta: Vec<f64>,
    /// The loop's initial uniform spacing h0
    #[arg(long, value_name = "H", value_parser = args::positive, default_value_t = 0.05)]
    start: f64,
    /// Refinement steps at most
    #[arg(long, default_value_t = 8)]
    steps: usize,
    /// Dörfler fraction θ
    #[arg(long, default_value_t = 0.5)]
    fraction: f64,
    /// The loop's node limit
    #[arg(long, default_value_t = 20_000)]
    max_nodes: usize,
}

/// `(a, p₀)` as the ratio fit/Hertz of the FE on mesh 2.
fn reference() -> [f64; 2] {
    let t = Instant::now();
    let s = mlpg_contact::solve(&axisymmetric_contact::sphere_fem(2, "lemke")).unwrap();
    let r = row("FE mesh 2", &s);
    let o = r.sphere.expect("the FE mesh 2 closes enough candidates");
    println!("reference FE mesh 2: {} nodes, {:.1} s", r.nodes, t.elapsed().as_secs_f64());
    [1.0 + o.radius_error, 1.0 + o.peak_error]
}

/// One line of the table.
fn print(label: &str, r: &Row, reference: [f64; 2], seconds: f64) {
    let pct = |v: f64| format!("{:+.3} %", 100.0 * v);
    match r.sphere {
        Some(o) => println!(
            "{label:<22} {:>6} nodes  F {:.6e}  a {}  p0 {}  | vs FE a {}  p0 {}  closed {:>3}  {seconds:.2} s",
            r.nodes,
            o.force,
            pct(o.radius_error),
            pct(o.peak_error),
            pct((1.0 + o.radius_error) / reference[0] - 1.0),
            pct((1.0 + o.peak_error) / reference[1] - 1.0),
            r.closed,
        ),
        None => println!(
            "{label:<22} {:>6} nodes  (too few closed candidates to fit: {})  {seconds:.2} s",
            r.nodes, r.closed
        ),
    }
}

fn main() {
    let cli: Cli = args::parse(&[]);
    let reference = reference();
    for &beta in &cli.beta {
        for &h in &cli.uniform {
            let t = Instant::now();
            let s = mlpg_contact::solve(&sphere_uniform(h, beta)).unwrap();
            let label = format!("uniform h={h} β={beta}");
            let r = row(&label, &s);
            print(&label, &r, reference, t.elapsed().as_secs_f64());
        }
    }
    let problem = sphere_adaptive(cli.start, cli.steps, cli.fraction, cli.max_nodes);
    let adaptive = problem.adaptive.unwrap();
    let t = Instant::now();
    let mut step = 0;
    let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
        &problem,
        &adaptive,
        &mut mlpg_contact::Silent,
        &mut |_, _, s, e| {
            let label = format!("adaptive step {step} (η {:.2e})", e.relative);
            let r = row(&label, s);
            print(&label, &r, reference, t.elapsed().as_secs_f64());
            step += 1;
        },
    )
    .unwrap();
    println!("stopped by {}", run.summary.stopped_by);
}
