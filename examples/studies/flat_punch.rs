//! The flat punch stiffness, axisymmetric (docs/dev/axisymmetric.md, increment 8b): a rigid
//! flat circular punch of radius `a = 0.1`, sharp corners, pushed `δ = 0.001` onto a cylinder
//! `[0, W] × [−W, 0]` with a clamped bottom (`problems/flat_punch_axisymmetric.toml`), against
//! Sneddon's half-space force `P = 2 a E* δ`.
//!
//! Runs the grid of punch spacings `h = a/2^j` (a box `[0, 1.5a] × [−0.5a, 0]` at `h`, a
//! near field `[0, 4a] × [−4a, 0]` at `4h`) and block sizes `W` (far spacing `W/16`, or
//! `W/16/far-refine`), prints `P` per run, then extrapolates to the half-space both ways:
//! in `h` at each `W` (Richardson with the rate measured from the last three `h`), then in
//! `a/W` (the rate from the last three `W`); and in `a/W` at each `h`, then in `h`.
//! Nothing is asserted (the test `validation flat_punch_axisymmetric` uses one run).
//!
//! `cargo run --release --features studies --example flat_punch -- [--levels 4,5,6]
//! [--widths 0.8,1.6,3.2,6.4] [--far-refine 1]`

mod args;
#[path = "../../tests/validation/common.rs"]
#[allow(dead_code)]
mod common;
#[path = "../../tests/validation/flat_punch_axisymmetric.rs"]
#[allow(dead_code)]
mod flat_punch_axisymmetric;

use flat_punch_axisymmetric::{RADIUS, measure, punch, sneddon};
use std::time::Instant;

/// The flat punch over punch spacings and block sizes.
#[derive(clap::Parser)]
struct Cli {
    /// Levels j of the punch spacing h = a/2^j
    #[arg(long, value_name = "J,…", value_delimiter = ',', default_values_t = [4, 5, 6])]
    levels: Vec<u32>,
    /// Block sizes W (W/16 must be a power-of-two multiple of a/2^j)
    #[arg(long, value_name = "W,…", value_delimiter = ',', value_parser = args::positive,
          default_values_t = [0.8, 1.6, 3.2, 6.4])]
    widths: Vec<f64>,
    /// Divide the far spacing W/16 by this power of two
    #[arg(long, value_name = "K", default_value_t = 1)]
    far_refine: u32,
}

/// Richardson from the last three values of a sequence whose parameter halves each step:
/// `(rate, limit)`; the rate from the ratio of the last two differences.
fn richardson(v: &[f64]) -> Option<(f64, f64)> {
    let n = v.len();
    if n < 3 {
        return None;
    }
    let (d1, d2) = (v[n - 2] - v[n - 3], v[n - 1] - v[n - 2]);
    let rate = (d1 / d2).log2();
    Some((rate, v[n - 1] + d2 / (2f64.powf(rate) - 1.0)))
}

fn main() {
    let cli: Cli = args::parse(&[]);
    let exact = sneddon();
    println!("Sneddon P = 2 a E* δ = {exact:.6e}");
    println!(
        "{:>4} {:>8} {:>7} {:>7} {:>7} {:>13} {:>10} {:>7}",
        "j", "h", "W", "a/W", "nodes", "P", "P/Sn − 1", "time"
    );
    // p[iw][ih]
    let mut p = vec![vec![0.0; cli.levels.len()]; cli.widths.len()];
    for (iw, &w) in cli.widths.iter().enumerate() {
        for (ih, &j) in cli.levels.iter().enumerate() {
            let h = RADIUS / 2f64.powi(j as i32);
            let far = w / 16.0 / cli.far_refine as f64;
            let start = Instant::now();
            let label = format!("h = a/{}, W = {w}", 1 << j);
            let s = mlpg_contact::solve(&punch(h, w, far)).unwrap();
            let m = measure(&label, &s);
            p[iw][ih] = m.force;
            println!(
                "{j:>4} {h:>8.6} {w:>7} {:>7.4} {:>7} {:>13.6e} {:>+9.3}% {:>6.1}s",
                RADIUS / w,
                m.nodes,
                m.force,
                100.0 * (m.force / exact - 1.0),
                start.elapsed().as_secs_f64()
            );
        }
    }
    let pct = |v: f64| 100.0 * (v / exact - 1.0);
    println!("\nIn h at each W (Richardson, rate from the last three h), then in a/W:");
    let mut limits_h = Vec::new();
    for (iw, &w) in cli.widths.iter().enumerate() {
        if let Some((rate, limit)) = richardson(&p[iw]) {
            println!("  W = {w:<5} rate {rate:.3}  P(h→0) = {limit:.6e} ({:+.3} %)", pct(limit));
            limits_h.push(limit);
        }
    }
    if let Some((rate, limit)) = richardson(&limits_h) {
        println!("  then a/W → 0: rate {rate:.3}  P = {limit:.6e} ({:+.3} %)", pct(limit));
    }
    println!("In a/W at each h (rate from the last three W), then in h:");
    let mut limits_w = Vec::new();
    for (ih, &j) in cli.levels.iter().enumerate() {
        let column: Vec<f64> = p.iter().map(|row| row[ih]).collect();
        if let Some((rate, limit)) = richardson(&column) {
            println!(
                "  h = a/{:<4} rate {rate:.3}  P(a/W→0) = {limit:.6e} ({:+.3} %)",
                1 << j,
                pct(limit)
            );
            limits_w.push(limit);
        }
    }
    if let Some((rate, limit)) = richardson(&limits_w) {
        println!("  then h → 0: rate {rate:.3}  P = {limit:.6e} ({:+.3} %)", pct(limit));
    }
}
