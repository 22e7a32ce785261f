//! Issue 7 study, Hertz case: accuracy per cost of the stabilised MFVM variants (method.md
//! §3.9) on an elastic cylinder pressed onto a rigid flat (problems/hertz_cylinder.toml: a
//! quarter disk of radius 1 with curved boundaries, plane strain), at several node spacings.
//! The variants are those of examples/beta_study.rs (the beam study).
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
//! `cargo run --release --example beta_study_hertz [-- --finest 0.01] [--only 2]` (`--only k`:
//! just variant `k` of the list, 1-based). Spacings 0.04, 0.02, 0.01, 0.005 by default.
//!
//! The problem is loaded from the problem file, not from test code; nothing is tuned toward
//! any number of the paper.

use mlpg_contact::mls::Basis;
use mlpg_contact::post::plot;
use mlpg_contact::problem::Problem;
use std::time::Instant;

const RADIUS: f64 = 1.0;

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

/// One error-against-cost chart: file stem, x label, x of a row, y label, y of a row.
type ChartSpec = (&'static str, &'static str, fn(&Row) -> f64, &'static str, fn(&Row) -> f64);

fn stage(s: &mlpg_contact::Solution, names: &[&str]) -> f64 {
    s.timings.iter().filter(|t| names.contains(&t.stage)).map(|t| t.seconds).sum()
}

fn run(base: &Problem, v: &Variant, h: f64) -> Result<Row, String> {
    let mut p = base.clone();
    p.node_spacing = h;
    p.discretisation.mls.basis = v.basis;
    p.discretisation.mls.support_factor = v.support_factor;
    p.discretisation.beta = v.beta;
    let t0 = Instant::now();
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&p, &mut silent).map_err(|e| e.to_string())?;
    let nonzeros = model.system.matrix.values.len();
    let (_, _, s) =
        mlpg_contact::solve_model(&p, model, None, &mut silent).map_err(|e| e.to_string())?;
    let total = t0.elapsed().as_secs_f64();
    let c = s.contact.as_ref().ok_or("no contact solution")?;

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
    // Node-to-node ripple as in the beam study: largest second difference of the pressure over
    // closed candidates whose neighbours are closed too, relative to the peak pressure.
    let ripple = (1..c.pressure.len().saturating_sub(1))
        .filter(|&k| c.closed[k - 1] && c.closed[k] && c.closed[k + 1])
        .map(|k| (c.pressure[k] - 0.5 * (c.pressure[k - 1] + c.pressure[k + 1])).abs())
        .fold(0.0, f64::max)
        / peak.max(f64::MIN_POSITIVE);
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
        m_min_eig: c.condensed.min_symmetric_eigenvalue,
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
        .unwrap_or(0.005);
    let only = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|i| args.get(i + 1))
        .map(|v| v.parse::<usize>().expect("--only takes a variant number"));
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/hertz_cylinder.toml");
    let base = Problem::from_toml(&std::fs::read_to_string(path).expect("problem file"))
        .expect("valid problem");
    let mut spacings = vec![0.04];
    while spacings.last().copied().unwrap_or(0.0) / 2.0 >= finest * 0.999 {
        let h = spacings[spacings.len() - 1] / 2.0;
        spacings.push(h);
    }
    let mut results: Vec<(&str, Vec<Row>)> = Vec::new();
    for (k, v) in VARIANTS.iter().enumerate() {
        if only.is_some_and(|o| o != k + 1) {
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
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/beta_study_hertz");
    std::fs::create_dir_all(&dir).expect("output directory");
    let charts: [ChartSpec; 4] = [
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
    for (stem, x_label, x, y_label, y) in charts {
        let chart = plot::Chart {
            title: format!("Hertz cylinder: {y_label} against {x_label}"),
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
