//! Timing of Lemke's method (`mlpg_contact::lcp::lemke`) on random dense LCPs of contact size.
//!
//! M = AᵀA/n + I + K, with A uniform in [−1, 1]ⁿˣⁿ and K skew-symmetric with entries uniform in
//! [−0.05, 0.05]/√n (so M is non-symmetric with positive definite symmetric part, a P-matrix),
//! and q uniform in [−1, 1]ⁿ (about half negative). Run with
//!
//! ```text
//! cargo run --release --features studies --example lemke_timing -- [n1 n2 ...]
//! ```
//!
//! (default sizes 250, 500, 1000, 2000). Prints n, pivots, seconds and the scaled residuals.

mod args;

use clap::Parser;
use std::time::Instant;

use mlpg_contact::lcp::{Lcp, LemkeParams, lemke};
use mlpg_contact::random::SplitMix64;

/// x·y with eight partial sums, so that the compiler can vectorise it.
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0; 8];
    let (xc, yc) = (x.chunks_exact(8), y.chunks_exact(8));
    let tail: f64 = xc.remainder().iter().zip(yc.remainder()).map(|(a, b)| a * b).sum();
    for (a, b) in xc.zip(yc) {
        for l in 0..8 {
            acc[l] += a[l] * b[l];
        }
    }
    acc.iter().sum::<f64>() + tail
}

/// The random test problem of size n described in the file header.
pub fn random_problem(n: usize, seed: u64) -> Lcp {
    let mut rng = SplitMix64::new(seed);
    // The columns of A, stored contiguously (A is uniform, so any layout is equally random);
    // (AᵀA)_ij is the dot product of columns i and j.
    let a_cols: Vec<f64> = (0..n * n).map(|_| rng.uniform_symmetric()).collect();
    let col = |i: usize| &a_cols[i * n..(i + 1) * n];
    let mut m = vec![0.0; n * n];
    // Blocks of 16 columns i share each column j while it is in cache.
    for i0 in (0..n).step_by(16) {
        let i1 = (i0 + 16).min(n);
        for j in 0..i1 {
            for i in i0.max(j)..i1 {
                let v = dot(col(i), col(j));
                m[i * n + j] = v;
                m[j * n + i] = v;
            }
        }
    }
    let inv_n = 1.0 / n as f64;
    let skew = 0.05 / (n as f64).sqrt();
    for i in 0..n {
        m[i * n + i] = m[i * n + i] * inv_n + 1.0;
        for j in 0..i {
            let s = skew * rng.uniform_symmetric();
            m[i * n + j] = m[i * n + j] * inv_n + s;
            m[j * n + i] = m[j * n + i] * inv_n - s;
        }
    }
    let q: Vec<f64> = (0..n).map(|_| rng.uniform_symmetric()).collect();
    match Lcp::new(n, m, q) {
        Ok(lcp) => lcp,
        Err(e) => panic!("random problem is invalid: {e}"),
    }
}

/// Runs Lemke on `lcp` and prints one table row.
fn run(label: &str, lcp: &Lcp, setup: f64) {
    let n = lcp.size();
    let t = Instant::now();
    match lemke(lcp, &LemkeParams::default()) {
        Ok(s) => {
            let secs = t.elapsed().as_secs_f64();
            let active = s.z.iter().filter(|&&z| z > 0.0).count();
            let r = s.residuals;
            println!(
                "{n:>6} {label:>9} {:>7} {active:>7} {setup:>8.3} {secs:>8.3} {:>9.1e} {:>9.1e} \
                 {:>9.1e} {:>9.1e}",
                s.pivots, r.min_z, r.min_w, r.max_complementarity, r.equation_residual
            );
        }
        Err(e) => {
            println!("{n:>6} {label:>9} failed after {:.3} s: {e}", t.elapsed().as_secs_f64())
        }
    }
}

/// Timing of Lemke's method on random dense LCPs of contact size.
#[derive(Parser)]
struct Cli {
    /// LCP sizes n, written 2000 or 2k
    #[arg(value_name = "N", value_parser = args::count, default_values_t = [250, 500, 1000, 2000])]
    sizes: Vec<usize>,
}

fn main() {
    let sizes = args::parse::<Cli>(&[]).sizes;
    println!(
        "q \"uniform\": q_i uniform in [-1, 1]; q \"25% zero\": the same with q_i = 0 for i = 0 mod 4"
    );
    println!("(degenerate: many tied ratio tests resolved by the lexicographic rule).");
    println!("Residuals are scaled as documented in LcpResiduals; setup = building M.");
    println!(
        "{:>6} {:>9} {:>7} {:>7} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}",
        "n", "q", "pivots", "active", "setup s", "lemke s", "min z", "min w", "compl", "eq"
    );
    for n in sizes {
        let t0 = Instant::now();
        let lcp = random_problem(n, 0x5EED_0000 + n as u64);
        let setup = t0.elapsed().as_secs_f64();
        run("uniform", &lcp, setup);
        let q: Vec<f64> =
            lcp.q().iter().enumerate().map(|(i, &x)| if i % 4 == 0 { 0.0 } else { x }).collect();
        match Lcp::new(n, lcp.m_row_major().to_vec(), q) {
            Ok(degenerate) => run("25% zero", &degenerate, setup),
            Err(e) => println!("{n:>6} invalid degenerate problem: {e}"),
        }
    }
}
