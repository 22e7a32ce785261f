//! Spence's self-similar stick zone (docs/dev/axisymmetric.md, increment 7b): the elastic
//! Hertz sphere of `tests/validation/axisymmetric_contact_paths.rs` (`R = 1`, `E = 1`,
//! `ν = 0.3`, MFVM, `β = 0.5`) pressed onto a rigid flat with Coulomb friction `μ` in load
//! increments of the top's displacement (to 0.015). Under monotonic normal loading the
//! stick radius `c` grows with the contact radius `a` so that `c/a` is the same at every
//! load (Spence 1975; its value depends on `β/μ`, `β = (1 − 2ν)/(2(1 − ν))` the Dundurs
//! constant of an elastic body on a rigid one). Prints, per box spacing `h` and increment,
//! the closed and sticking rings, `a` and `c` (the outermost closed and sticking candidates'
//! radii, and the midpoints to the next candidate outward) and `c/a` both ways. Every
//! increment's complementarity and balance are checked; nothing else is asserted.
//!
//! `cargo run --release --features studies --example spence -- [--spacings 0.01,0.005,0.0025]
//! [--mu 0.3] [--increments 6] [--ratio 1.1]`

mod args;
#[path = "../../tests/validation/axisymmetric_contact.rs"]
#[allow(dead_code, unused_imports)]
mod axisymmetric_contact;
#[path = "../../tests/validation/axisymmetric_contact_paths.rs"]
#[allow(dead_code, unused_imports)]
mod axisymmetric_contact_paths;
#[path = "../../tests/validation/common.rs"]
#[allow(dead_code)]
mod common;

use axisymmetric_contact_paths::sphere_at;
use mlpg_contact::lcp::ContactState;
use std::time::Instant;

/// The frictional Hertz sphere over box spacings.
#[derive(clap::Parser)]
struct Cli {
    /// Box spacings h around the contact
    #[arg(long, value_name = "H,…", value_delimiter = ',', value_parser = args::positive,
          default_values_t = [0.01, 0.005, 0.0025])]
    spacings: Vec<f64>,
    /// Friction coefficient
    #[arg(long, value_name = "MU", value_parser = args::positive, default_value_t = 0.3)]
    mu: f64,
    /// Load increments
    #[arg(long, value_name = "N", default_value_t = 6)]
    increments: usize,
    /// Geometric increments instead of equal ones: the top's displacement 0.015 q^(k − N)
    /// at increment k = 1 … N (one `[[step]]` each), so every increment adds the same
    /// fraction `1 − 1/q` of the load: the discrete path is self-similar too
    #[arg(long, value_name = "Q")]
    ratio: Option<f64>,
}

fn main() {
    let cli: Cli = args::parse(&[]);
    let beta = (1.0 - 2.0 * 0.3) / (2.0 * (1.0 - 0.3));
    println!("μ = {}, β = {beta:.4}, β/μ = {:.4}", cli.mu, beta / cli.mu);
    println!(
        "{:>8} {:>4} {:>9} {:>6} {:>6} {:>8} {:>8} {:>7} {:>8} {:>8} {:>7} {:>7}",
        "h", "inc", "top", "closed", "stick", "a", "c", "c/a", "a mid", "c mid", "c/a mid", "time"
    );
    for &h in &cli.spacings {
        let n = cli.increments;
        // The top's displacement at the end of increment k (1-based).
        let top = |k: usize| match cli.ratio {
            Some(q) => -0.015 * q.powi(k as i32 - n as i32),
            None => -0.015 * k as f64 / n as f64,
        };
        let steps = match cli.ratio {
            Some(_) => (1..=n)
                .map(|k| {
                    format!(
                        "[[step]]\nboundary = [{{ edge = \"top\", displacement = {{ y = {:?} }} }}]\n",
                        top(k)
                    )
                })
                .collect::<String>(),
            None => format!(
                "[[step]]\nincrements = {n}\nboundary = [{{ edge = \"top\", displacement = {{ y = -0.015 }} }}]"
            ),
        };
        let mut p = sphere_at(h, "0.0", &format!("friction = {:?}", cli.mu), &steps);
        p.write_steps = true;
        let start = Instant::now();
        let s = mlpg_contact::solve(&p).expect("solve");
        let time = start.elapsed().as_secs_f64();
        let c = s.contact().unwrap();
        let f = c.friction.as_ref().unwrap();
        for r in &f.increments {
            assert!(r.complementarity < 1e-9 && r.equilibrium_error < 1e-8, "{r:?}");
        }
        let radius = |k: usize| c.candidates.points[k][0];
        for snap in &f.snapshots {
            // The outermost candidate in `pick`, and the midpoint to the next one outward.
            let outer = |pick: &dyn Fn(ContactState) -> bool| -> (f64, f64, usize) {
                let n = snap.state.len();
                let ks: Vec<usize> = (0..n).filter(|&k| pick(snap.state[k])).collect();
                match ks.iter().copied().max_by(|&i, &j| radius(i).total_cmp(&radius(j))) {
                    None => (0.0, 0.0, 0),
                    Some(k) => {
                        let next = (0..n)
                            .map(radius)
                            .filter(|&r| r > radius(k))
                            .fold(f64::INFINITY, f64::min);
                        let mid =
                            if next.is_finite() { 0.5 * (radius(k) + next) } else { radius(k) };
                        (radius(k), mid, ks.len())
                    }
                }
            };
            let (a, a_mid, closed) = outer(&|s| s != ContactState::Open);
            let (st, st_mid, sticking) = outer(&|s| s == ContactState::Stick);
            let k = match cli.ratio {
                Some(_) => snap.step,
                None => snap.increment,
            };
            println!(
                "{h:>8} {k:>4} {:>9.3e} {closed:>6} {sticking:>6} {a:>8.5} {st:>8.5} {:>7.3} {a_mid:>8.5} {st_mid:>8.5} {:>7.3} {time:>6.2}s",
                -top(k),
                st / a,
                st_mid / a_mid
            );
        }
    }
}
