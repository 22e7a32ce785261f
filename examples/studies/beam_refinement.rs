//! Refinement study of the paper's beam on a rigid foundation (problems/beam_on_foundation.toml):
//! node spacing, then support factor and quadrature at one spacing. Prints Markdown tables
//! (the user guide's, docs/guide/src/validation.md) and the successive differences of the headline values.
//!
//! ```text
//! cargo run --release --features studies --example beam_refinement -- [--finest 0.0625]
//! ```
//!
//! `--finest h`: the finest spacing of the ladder 0.5, 0.25, … (default 0.0625).

mod args;

use clap::Parser;
use mlpg_contact::contact::Condensation;
use mlpg_contact::problem::Problem;
use std::time::Instant;

struct Row {
    h: f64,
    alpha: f64,
    quad: usize,
    nodes: usize,
    candidates: usize,
    pivots: usize,
    force: f64,
    onset_gap: f64,
    onset_pressure: f64,
    last_open: f64,
    first_closed: f64,
    tip: f64,
    seconds: f64,
}

fn run(base: &Problem, h: f64, alpha: f64, quad: usize) -> Row {
    run_with(base, h, alpha, quad, Condensation::Compliance).0
}

/// One run; also returns `max_c |g_MLS − w_c|`: how far the LCP's gaps are from the MLS gaps
/// (round-off for the compliance form; the approximation of the stiffness form).
fn run_with(
    base: &Problem,
    h: f64,
    alpha: f64,
    quad: usize,
    condensation: Condensation,
) -> (Row, f64) {
    let mut p = base.clone();
    if let Some(c) = p.contact_mut() {
        c.condensation = condensation;
    }
    p.node_spacing = h;
    p.discretisation.mls.support_factor = alpha;
    p.discretisation.quadrature_points = quad;
    let t0 = Instant::now();
    let s = mlpg_contact::solve(&p).expect("solve");
    let seconds = t0.elapsed().as_secs_f64();
    let c = s.contact().expect("contact");
    let nodes = s.displacement.len();
    let points = mlpg_contact::nodes::generate(&p.domain, h, p.layout).expect("nodes").points;
    let tip = points
        .iter()
        .position(|q| q[0] == 48.0 && q[1] == 0.0)
        .map(|i| s.displacement[i][1])
        .unwrap_or(f64::NAN);
    let mismatch = c.gap.iter().zip(&c.lcp.w).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    let row = Row {
        h,
        alpha,
        quad,
        nodes,
        candidates: c.candidates.len(),
        pivots: c.lcp.pivots,
        force: c.total_force,
        onset_gap: c.onset.from_gap.unwrap_or(f64::NAN),
        onset_pressure: c.onset.from_pressure.unwrap_or(f64::NAN),
        last_open: c.onset.last_open.unwrap_or(f64::NAN),
        first_closed: c.onset.first_closed.unwrap_or(f64::NAN),
        tip,
        seconds,
    };
    (row, mismatch)
}

fn print_table(rows: &[Row]) {
    println!(
        "| h | α_s | Gauss | nodes | candidates | pivots | F_c | l_c (gap) | l_c (pressure) | last open | first closed | u_y(48, 0) | time [s] |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        println!(
            "| {} | {} | {} | {} | {} | {} | {:.6} | {:.4} | {:.4} | {:.4} | {:.4} | {:.7e} | {:.2} |",
            r.h,
            r.alpha,
            r.quad,
            r.nodes,
            r.candidates,
            r.pivots,
            r.force,
            r.onset_gap,
            r.onset_pressure,
            r.last_open,
            r.first_closed,
            r.tip,
            r.seconds
        );
    }
}

/// Successive differences and, where they shrink, the observed order (halving h each level).
/// The onset jumps between candidates, so F_c converges irregularly: read the differences.
fn differences(name: &str, v: &[f64]) {
    let d: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
    let text: Vec<String> = d.iter().map(|x| format!("{x:.3e}")).collect();
    println!("{name}: successive differences {}", text.join(", "));
}

/// Refinement study of the beam on a rigid foundation: node spacing, support factor,
/// quadrature, and the paper's stiffness form of the contact condensation.
#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    ladder: args::Ladder,
}

fn main() {
    let cli: Cli = args::parse(&[("finest", "0.0625")]);
    let finest = cli.ladder.finest;
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/beam_on_foundation.toml");
    let base = Problem::from_toml(&std::fs::read_to_string(path).expect("problem file"))
        .expect("valid problem");
    let mut spacings = vec![0.5];
    while spacings.last().copied().unwrap_or(0.0) / 2.0 >= finest * 0.999 {
        let next = spacings.last().copied().unwrap_or(0.5) / 2.0;
        spacings.push(next);
    }
    println!("## Node spacing (α_s = 2, 2 Gauss points)\n");
    let rows: Vec<Row> = spacings.iter().map(|&h| run(&base, h, 2.0, 2)).collect();
    print_table(&rows);
    println!();
    differences("F_c", &rows.iter().map(|r| r.force).collect::<Vec<_>>());
    differences("l_c (gap)", &rows.iter().map(|r| r.onset_gap).collect::<Vec<_>>());
    differences("u_y(48, 0)", &rows.iter().map(|r| r.tip).collect::<Vec<_>>());
    let h = 0.125;
    println!("\n## Support factor and quadrature at h = {h}\n");
    let mut rows = Vec::new();
    for alpha in [1.75, 2.0, 2.25] {
        rows.push(run(&base, h, alpha, 2));
    }
    for quad in [1, 3, 4] {
        rows.push(run(&base, h, 2.0, quad));
    }
    print_table(&rows);
    println!(
        "\n## The paper's stiffness form (nodal parameters as displacements) vs the default\n"
    );
    println!(
        "| h | F_c compliance | F_c stiffness | l_c compliance | l_c stiffness | max abs(MLS gap − LCP gap), stiffness form |"
    );
    println!("|---|---|---|---|---|---|");
    for &h in &spacings {
        let (a, _) = run_with(&base, h, 2.0, 2, Condensation::Compliance);
        let (b, gap) = run_with(&base, h, 2.0, 2, Condensation::Stiffness);
        println!(
            "| {h} | {:.6} | {:.6} | {:.4} | {:.4} | {gap:.3e} |",
            a.force, b.force, a.onset_gap, b.onset_gap
        );
    }
}
