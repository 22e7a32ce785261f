//! Adaptive refinement (docs/method.md §2.2), measured:
//!
//! 1. **Indicators against the true error** on the cantilever under end shear, whose closed
//!    form is known (`tests/validation/end_shear_exact.rs`): per node, the true error
//!    `e_I² = h_I² (σ^h_I − σ_I)ᵀ D⁻¹ (σ^h_I − σ_I)` and each indicator `η_I²`; printed: the
//!    correlation of `η_I` with `e_I` (Pearson, and Spearman's of the ranks) and the
//!    effectivity `(Σ η_I² / Σ e_I²)^(1/2)`.
//! 2. **Cantilever, error against nodes**: uniform spacings against the adaptive loop from
//!    `h₀ = 2`, structured and jittered nodes (relative energy-norm error by nodal quadrature, `(Σ e_I² / Σ h_I² σ_Iᵀ D⁻¹
//!    σ_I)^(1/2)`).
//! 3. **Beam on the rigid foundation** (`problems/beam_on_foundation_adaptive.toml`): every
//!    step against the FE reference, and the wall-clock time of the adaptive run (all steps)
//!    against uniform spacings of the same blend, in one run.
//!
//! `cargo run --release --features studies --example adaptive_refinement` (about two minutes; `--quick` leaves
//! out the jittered cantilever and the uniform beam at h = 0.0625).

#[path = "../../tests/validation/end_shear_exact.rs"]
mod end_shear_exact;

use end_shear_exact::{
    DEPTH, LENGTH, POISSON, YOUNG, energy_density, exact_displacement, exact_stress,
};
use mlpg_contact::pipeline::adaptive;
use mlpg_contact::problem::{
    Adaptive, ComponentCondition, EdgeCondition, Field, Indicator, Layout, Problem,
};
use mlpg_contact::refine::{self, Estimate};
use mlpg_contact::{Model, Silent, Solution};
use std::sync::Arc;
use std::time::Instant;

/// The independent Q2 FE reference of the beam (docs/dev/adaptive.md): `ΣP`, `l_c`.
const BEAM_FORCE: f64 = 32.3476;
const BEAM_ONSET: f64 = 19.810;

fn load(name: &str) -> Problem {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems").join(name);
    Problem::from_toml(&std::fs::read_to_string(path).expect("problem file")).expect("valid")
}

/// `problems/cantilever.toml` with the closed form's end conditions, `β = 0.5`.
fn cantilever(h: f64, layout: Layout) -> Problem {
    let mut p = load("cantilever.toml");
    assert_eq!(p.domain.bounding_box(), ([0.0, -DEPTH / 2.0], [LENGTH, DEPTH / 2.0]));
    assert!(p.material.young == YOUNG && p.material.poisson == POISSON);
    p.node_spacing = h;
    p.layout = layout;
    p.discretisation.beta = 0.5;
    let component = |f: fn([f64; 2]) -> f64| Field::Function(Arc::new(f));
    let left = p.domain.edge_index("left").expect("edge left");
    let right = p.domain.edge_index("right").expect("edge right");
    p.boundary[left] = EdgeCondition::Components([
        ComponentCondition::Displacement(component(|q| exact_displacement(q)[0])),
        ComponentCondition::Displacement(component(|q| exact_displacement(q)[1])),
    ]);
    p.boundary[right] = EdgeCondition::Components([
        ComponentCondition::Traction(component(|q| exact_stress(q)[0])),
        ComponentCondition::Traction(component(|q| exact_stress(q)[2])),
    ]);
    p
}

/// Per-node true error `e_I²` and the relative energy-norm error.
fn true_error(model: &Model, s: &Solution) -> (Vec<f64>, f64) {
    let (mut num, mut den, mut e) = (0.0, 0.0, Vec::new());
    for (i, &p) in model.nodes.points.iter().enumerate() {
        let (se, sh, a) = (exact_stress(p), s.stress[i], model.nodes.spacing[i].powi(2));
        let d = [sh[0] - se[0], sh[1] - se[1], sh[2] - se[2]];
        e.push(a * energy_density(d));
        num += a * energy_density(d);
        den += a * energy_density(se);
    }
    (e, (num / den).sqrt())
}

fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

fn ranks(a: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..a.len()).collect();
    order.sort_by(|&i, &j| a[i].total_cmp(&a[j]));
    let mut r = vec![0.0; a.len()];
    for (k, &i) in order.iter().enumerate() {
        r[i] = k as f64;
    }
    r
}

fn indicators() {
    println!("## 1. Indicators against the true error (cantilever, β = 0.5, α_s = 2)\n");
    println!("| layout | h | nodes | indicator | Pearson(η, e) | Spearman(η, e) | effectivity |");
    println!("|---|---|---|---|---|---|---|");
    for (layout, name) in [
        (Layout::Structured, "structured"),
        (Layout::Jittered { amplitude: 0.25, seed: 1 }, "jittered 0.25"),
    ] {
        for h in [1.0, 0.5] {
            let p = cantilever(h, layout);
            let mut silent = Silent;
            let model = mlpg_contact::discretise(&p, &mut silent).expect("discretise");
            let (model, _, s) =
                mlpg_contact::solve_model(&p, model, None, &mut silent).expect("solve");
            let (e2, _) = true_error(&model, &s);
            let e: Vec<f64> = e2.iter().map(|v| v.sqrt()).collect();
            for ind in [Indicator::Recovery, Indicator::Gradient] {
                let Estimate { node, .. } = refine::estimate(&p, &model, &s, ind);
                let eta: Vec<f64> = node.iter().map(|v| v.sqrt()).collect();
                let eff = (node.iter().sum::<f64>() / e2.iter().sum::<f64>()).sqrt();
                println!(
                    "| {name} | {h} | {} | {} | {:.3} | {:.3} | {:.3} |",
                    model.nodes.len(),
                    ind.name(),
                    pearson(&eta, &e),
                    pearson(&ranks(&eta), &ranks(&e)),
                    eff
                );
            }
        }
    }
    println!();
}

fn cantilever_study(layout: Layout, name: &str) {
    println!("## 2. Cantilever: relative energy-norm error against nodes ({name}, β = 0.5)\n");
    println!(
        "| run | step | nodes | min h_I | estimated (the run's indicator; uniform: gradient) | true energy error |"
    );
    println!("|---|---|---|---|---|---|");
    let mut finest = (0, 0.0);
    for h in [2.0, 1.0, 0.5, 0.25] {
        let p = cantilever(h, layout);
        let mut silent = Silent;
        let model = mlpg_contact::discretise(&p, &mut silent).expect("discretise");
        let (model, _, s) = mlpg_contact::solve_model(&p, model, None, &mut silent).expect("solve");
        let (_, err) = true_error(&model, &s);
        let est = refine::estimate(&p, &model, &s, Indicator::Gradient).relative;
        println!("| uniform h = {h} | – | {} | {h} | {est:.3e} | {err:.3e} |", model.nodes.len());
        finest = (model.nodes.len(), err);
    }
    for ind in [Indicator::Recovery, Indicator::Gradient] {
        for fraction in [0.5, 0.7] {
            let p = cantilever(2.0, layout);
            let a = Adaptive {
                steps: 12,
                max_nodes: finest.0,
                fraction,
                indicator: ind,
                contact: false,
                ..Adaptive::default()
            };
            let mut step = 0;
            let mut reached = None;
            let run = adaptive::solve_adaptive(&p, &a, &mut Silent, &mut |_, m, s, est| {
                let (_, err) = true_error(m, s);
                let hmin = m.nodes.spacing.iter().copied().fold(f64::INFINITY, f64::min);
                println!(
                    "| adaptive {} θ = {fraction} | {step} | {} | {hmin:.4} | {:.3e} | {err:.3e} |",
                    ind.name(),
                    m.nodes.len(),
                    est.relative
                );
                if reached.is_none() && err <= finest.1 {
                    reached = Some(m.nodes.len());
                }
                step += 1;
            });
            if let Err(e) = run {
                println!("| adaptive {} θ = {fraction} | failed: {e} | | | | |", ind.name());
            }
            match reached {
                Some(n) => println!(
                    "| adaptive {} θ = {fraction} | reached the uniform h = 0.25 error ({:.3e}) with {n} nodes ({:.2} of {}) | | | | |",
                    ind.name(),
                    finest.1,
                    n as f64 / finest.0 as f64,
                    finest.0
                ),
                None => println!(
                    "| adaptive {} θ = {fraction} | did not reach the uniform h = 0.25 error ({:.3e}) within {} nodes | | | | |",
                    ind.name(),
                    finest.1,
                    finest.0
                ),
            }
        }
    }
    println!();
}

fn beam_study(quick: bool) {
    println!(
        "## 3. Beam on the rigid foundation, β = 0.5 (reference ΣP = {BEAM_FORCE}, l_c = {BEAM_ONSET})\n"
    );
    println!(
        "| run | nodes | ΣP | ΣP/ref − 1 | l_c | l_c − ref | bracket | KKT | equilibrium | seconds |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let row = |name: &str, s: &Solution, nodes: usize, seconds: f64| {
        let c = s.contact().expect("contact");
        let lc = c.onset.from_gap.unwrap_or(f64::NAN);
        println!(
            "| {name} | {nodes} | {:.6} | {:+.1e} | {lc:.4} | {:+.4} | [{}, {}] | {:.1e} | {:.1e} | {seconds:.2} |",
            c.total_force,
            c.total_force / BEAM_FORCE - 1.0,
            lc - BEAM_ONSET,
            c.onset.last_open.unwrap_or(f64::NAN),
            c.onset.first_closed.unwrap_or(f64::NAN),
            c.lcp.residuals.max_complementarity,
            s.equilibrium_error
        );
    };
    let p = load("beam_on_foundation_adaptive.toml");
    let a = p.adaptive.expect("[refinement]");
    let t = Instant::now();
    let mut step = 0;
    let run = adaptive::solve_adaptive(&p, &a, &mut Silent, &mut |_, m, s, _| {
        row(&format!("adaptive step {step}"), s, m.nodes.len(), t.elapsed().as_secs_f64());
        step += 1;
    })
    .expect("adaptive beam");
    let adaptive_seconds = t.elapsed().as_secs_f64();
    row("adaptive (all steps)", &run.solution, run.model.nodes.len(), adaptive_seconds);
    let spacings: &[f64] = if quick { &[0.25, 0.125] } else { &[0.25, 0.125, 0.0625] };
    for &h in spacings {
        let mut u = p.clone();
        u.adaptive = None;
        u.node_spacing = h;
        let t = Instant::now();
        let s = mlpg_contact::solve(&u).expect("uniform beam");
        row(&format!("uniform h = {h}"), &s, s.displacement.len(), t.elapsed().as_secs_f64());
    }
    println!();
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    indicators();
    cantilever_study(Layout::Structured, "structured");
    if !quick {
        cantilever_study(Layout::Jittered { amplitude: 0.25, seed: 1 }, "jittered 0.25");
    }
    beam_study(quick);
}
