//! Accuracy per cost of the stabilised MFVM variants (method.md §3.9), Hertz case: on an
//! elastic cylinder pressed onto a rigid flat (problems/hertz_cylinder.toml: a quarter disk of
//! radius 1 with curved boundaries, plane strain), at several node spacings.
//! The variants are those of examples/studies/beta_study.rs (the beam study).
//!
//! Measured as in tests/validation/hertz.rs: the resultant per unit length of the whole
//! cylinder is `P = 2 × total contact force`; Hertz (Johnson §4.3) gives `a = √(4PR/(πE*))`,
//! `p₀ = 2P/(πa)`, `E* = E/(1 − ν²)`; `a_fit` and `p0_fit` come from a least-squares line
//! through `(x_c², p_c²)` over the closed candidates. Printed per variant and spacing: nodes,
//! nonzeros of `K`, `a_fit/a − 1`, `p0_fit/p₀ − 1`, the profile error
//! `max |p_c − p(x_c)| / p₀` over closed candidates, the pressure ripple (largest second
//! difference over closed candidates with closed neighbours, relative to the peak, as in the
//! beam study) and wall time per stage. A variant that fails (refused, `M` check, LCP) is a
//! row saying why.
//!
//! ```text
//! cargo run --release --features studies --example beta_study_hertz -- [--finest 0.01] [--only 2]
//! ```
//!
//! `--finest h`: the finest spacing of the ladder 0.04, 0.02, … (default 0.005); `--only k`:
//! just variant `k` of the list, 1-based. Results: docs/dev/beta_study.md.
//!
//! The problem is loaded from the problem file, not from test code; nothing is tuned toward
//! any number of the paper.

mod args;
mod study;

use clap::Parser;
use mlpg_contact::problem::Problem;
use std::time::Instant;
use study::{ChartSpec, VARIANTS, Variant};

const RADIUS: f64 = 1.0;

struct Row {
    nodes: usize,
    nonzeros: usize,
    /// Resultant per unit length of the whole cylinder.
    load: f64,
    a_over_r: f64,
    /// `a_fit/a − 1`.
    half_width: f64,
    /// `p0_fit/p₀ − 1`.
    peak: f64,
    /// `max |p_c − p(x_c)| / p₀` over closed candidates.
    profile: f64,
    ripple: f64,
    closed: usize,
    intervals: usize,
    /// Smallest eigenvalue of the symmetric part of `M`.
    m_min_eig: f64,
    /// (MLS at nodes and faces, assembly, factorisation, condensation, lemke, total) [s].
    times: [f64; 6],
}

fn run(base: &Problem, v: &Variant, h: f64) -> Result<Row, String> {
    let p = study::substitute(base, v, h);
    let t0 = Instant::now();
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&p, &mut silent).map_err(|e| e.to_string())?;
    let nonzeros = model.system.matrix.values.len();
    let (_, _, s) =
        mlpg_contact::solve_model(&p, model, None, &mut silent).map_err(|e| e.to_string())?;
    let total = t0.elapsed().as_secs_f64();
    let c = s.contact().ok_or("no contact solution")?;

    let e_star = p.material.young / (1.0 - p.material.poisson.powi(2));
    let load = 2.0 * c.total_force;
    let a = (4.0 * load * RADIUS / (std::f64::consts::PI * e_star)).sqrt();
    let p0 = 2.0 * load / (std::f64::consts::PI * a);
    // Least squares p² = α + γ x² over the closed candidates.
    let pts: Vec<(f64, f64)> = (0..c.closed.len())
        .filter(|&i| c.closed[i] && c.pressure[i] > 0.0)
        .map(|i| (c.candidates.points[i][0].powi(2), c.pressure[i].powi(2)))
        .collect();
    let (p0_fit, a_fit) = if pts.len() >= 2 {
        let n = pts.len() as f64;
        let (mx, my) = pts.iter().fold((0.0, 0.0), |s, q| (s.0 + q.0 / n, s.1 + q.1 / n));
        let sxy: f64 = pts.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
        let sxx: f64 = pts.iter().map(|q| (q.0 - mx).powi(2)).sum();
        let gamma = sxy / sxx;
        let alpha = my - gamma * mx;
        (alpha.sqrt(), (-alpha / gamma).sqrt())
    } else {
        (f64::NAN, f64::NAN)
    };
    let profile = (0..c.closed.len())
        .filter(|&i| c.closed[i])
        .map(|i| {
            let x = c.candidates.points[i][0];
            let exact = p0 * (1.0 - (x / a).powi(2)).max(0.0).sqrt();
            (c.pressure[i] - exact).abs() / p0
        })
        .fold(0.0, f64::max);
    let peak = c.pressure.iter().copied().fold(0.0, f64::max);
    let ripple = study::ripple(c, peak);
    Ok(Row {
        nodes: s.displacement.len(),
        nonzeros,
        load,
        a_over_r: a / RADIUS,
        half_width: a_fit / a - 1.0,
        peak: p0_fit / p0 - 1.0,
        profile,
        ripple,
        closed: c.closed.iter().filter(|&&b| b).count(),
        intervals: c.onset.closed_intervals,
        m_min_eig: c.condensed.as_ref().unwrap().min_symmetric_eigenvalue,
        times: study::stage_times(&s, total),
    })
}

/// Accuracy per cost of the stabilised MFVM variants on the Hertz cylinder, one Markdown table
/// per variant.
#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    ladder: args::Ladder,
    #[command(flatten)]
    only: args::Only,
}

fn main() {
    let cli: Cli = args::parse(&[("finest", "0.005")]);
    let base = study::load("hertz_cylinder.toml");
    let spacings = study::spacings(0.04, cli.ladder.finest);
    let mut results: Vec<(&str, Vec<Row>)> = Vec::new();
    for (k, v) in VARIANTS.iter().enumerate() {
        if !cli.only.runs(k) {
            continue;
        }
        let mut rows = Vec::new();
        println!("**{}**\n", v.name);
        println!(
            "| h | nodes | nnz(K) | nnz/row | P | a/R | a error | p0 error | profile error | ripple | closed | λ_min(M+Mᵀ)/2 | MLS [s] | assembly [s] | LU [s] | condense [s] | Lemke [s] | total [s] |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        for &h in &spacings {
            let r = match run(&base, v, h) {
                Ok(r) => r,
                Err(e) => {
                    println!("| {h} | failed: {} |", e.replace('|', "/"));
                    continue;
                }
            };
            let closed = if r.intervals == 1 {
                r.closed.to_string()
            } else {
                format!("{} ({} intervals)", r.closed, r.intervals)
            };
            println!(
                "| {} | {} | {} | {:.1} | {:.5e} | {:.4} | {:+.2e} | {:+.2e} | {:.2e} | {:.1e} | {} | {:.2e} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} | {:.2} |",
                h,
                r.nodes,
                r.nonzeros,
                r.nonzeros as f64 / (2 * r.nodes) as f64,
                r.load,
                r.a_over_r,
                r.half_width,
                r.peak,
                r.profile,
                r.ripple,
                closed,
                r.m_min_eig,
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
            "half_width_vs_dofs",
            "log10 DOFs",
            |r| (2.0 * r.nodes as f64).log10(),
            "log10 |a_fit/a − 1|",
            |r| r.half_width.abs().log10(),
        ),
        (
            "half_width_vs_time",
            "log10 total time [s]",
            |r| r.times[5].log10(),
            "log10 |a_fit/a − 1|",
            |r| r.half_width.abs().log10(),
        ),
        (
            "profile_vs_dofs",
            "log10 DOFs",
            |r| (2.0 * r.nodes as f64).log10(),
            "log10 max |p − p_Hertz|/p0",
            |r| r.profile.log10(),
        ),
        (
            "profile_vs_time",
            "log10 total time [s]",
            |r| r.times[5].log10(),
            "log10 max |p − p_Hertz|/p0",
            |r| r.profile.log10(),
        ),
    ];
    study::write_charts("beta_study_hertz", "Hertz cylinder", &results, &charts);
}
