//! Cantilever under a parabolic end shear, plane stress [TG70, §21]; the closed form (Augarde
//! & Deeks 2008) is in `end_shear_exact.rs`.
//!
//! Boundary conditions: the exact displacement on `x = 0`, the exact traction on `x = L`,
//! traction-free top and bottom. Checks, on structured and jittered nodes at 3–4 spacings:
//! the relative max-norm displacement error and the relative energy-norm error (nodal
//! quadrature over the cells), an absolute bound at the finest spacing and the observed rate.

use super::common::*;
use mlpg_contact::geometry::Domain;
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{RefineBox, Refinement};
use std::sync::Arc;

use super::end_shear_exact::{DEPTH, LENGTH, POISSON, YOUNG, exact_displacement, exact_stress};

struct Errors {
    displacement: f64,
    energy: f64,
}

/// Discretisation variant: `(α_s, β)`; `β = 0` beyond `α_s = 2.25` needs `allow_unstable`.
#[derive(Clone, Copy)]
struct Variant {
    support_factor: f64,
    beta: f64,
}

/// The paper's mixed method at the default support.
const DEFAULT: Variant = Variant { support_factor: 2.0, beta: 0.0 };

fn run(h: f64, layout: Layout, variant: Variant) -> Errors {
    run_refined(h, layout, variant, Refinement::default()).0
}

/// [`run`] on a graded node set; also returns the node count and where the largest nodal
/// stress error (von Mises of the difference) sits.
fn run_refined(
    h: f64,
    layout: Layout,
    variant: Variant,
    refinement: Refinement,
) -> (Errors, usize, [f64; 2]) {
    let domain = Domain::rectangle([0.0, LENGTH], [-DEPTH / 2.0, DEPTH / 2.0]).unwrap();
    let material = plane_stress(YOUNG, POISSON);
    let mut problem = base_problem(domain, h, layout, material);
    problem.refinement = refinement;
    problem.discretisation.mls.support_factor = variant.support_factor;
    problem.discretisation.beta = variant.beta;
    problem.discretisation.allow_unstable = true;
    // Edges: bottom, right, top, left.
    let t: VectorField = Arc::new(|p| {
        let s = exact_stress(p);
        [s[0], s[2]] // n = (1, 0) on x = L
    });
    problem.boundary[1] = traction(t);
    problem.boundary[3] = displacement(Arc::new(exact_displacement));
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&problem, &mut silent).unwrap();
    let (model, _, s) = mlpg_contact::solve_model(&problem, model, None, &mut silent).unwrap();
    assert!(s.relative_residual < 1e-10, "residual {}", s.relative_residual);
    assert!(s.equilibrium_error < 1e-9, "equilibrium {}", s.equilibrium_error);

    let max_u =
        model.nodes.points.iter().map(|&p| exact_displacement(p)[1].abs()).fold(0.0, f64::max);
    let mut err_u = 0.0f64;
    let (mut e_num, mut e_den) = (0.0, 0.0);
    let compliance = |s: [f64; 3]| {
        // ε = D⁻¹σ for plane stress.
        let e = YOUNG;
        [(s[0] - POISSON * s[1]) / e, (s[1] - POISSON * s[0]) / e, 2.0 * (1.0 + POISSON) * s[2] / e]
    };
    let (mut worst, mut worst_at) = (0.0f64, [0.0; 2]);
    for (i, &p) in model.nodes.points.iter().enumerate() {
        let ue = exact_displacement(p);
        let u = s.displacement[i];
        err_u = err_u.max((u[0] - ue[0]).hypot(u[1] - ue[1]));
        let se = exact_stress(p);
        let ds = [s.stress[i][0] - se[0], s.stress[i][1] - se[1], s.stress[i][2] - se[2]];
        let dev = (ds[0] * ds[0] - ds[0] * ds[1] + ds[1] * ds[1] + 3.0 * ds[2] * ds[2]).sqrt();
        if dev > worst {
            (worst, worst_at) = (dev, p);
        }
        let de = compliance(ds);
        let ee = compliance(se);
        let area = model.mfvm().expect("an MFVM model").cells[i].area();
        e_num += area * (ds[0] * de[0] + ds[1] * de[1] + ds[2] * de[2]);
        e_den += area * (se[0] * ee[0] + se[1] * ee[1] + se[2] * ee[2]);
    }
    let errors = Errors { displacement: err_u / max_u, energy: (e_num / e_den).sqrt() };
    (errors, model.nodes.len(), worst_at)
}

fn study(name: &str, layout: Layout, spacings: &[f64], variant: Variant) -> (Vec<f64>, Vec<f64>) {
    let mut du = Vec::new();
    let mut de = Vec::new();
    let mut rows = Vec::new();
    for &h in spacings {
        let e = run(h, layout, variant);
        println!("{name}: h = {h:<6} displacement {:.3e}  energy {:.3e}", e.displacement, e.energy);
        rows.push(vec![h, e.displacement, e.energy]);
        du.push(e.displacement);
        de.push(e.energy);
    }
    write_table(
        "cantilever_end_shear",
        &format!("{name}.csv"),
        "h,displacement_error,energy_error",
        &rows,
    );
    (du, de)
}

#[test]
fn cantilever_structured() {
    let h = [1.0, 0.5, 0.25, 0.125];
    let (du, de) = study("structured", Layout::Structured, &h, DEFAULT);
    let (ru, re) = (convergence_rate(&h, &du), convergence_rate(&h, &de));
    println!("structured rates: displacement {ru:.2}, energy {re:.2}");
    assert!(du[3] < DISPLACEMENT_BOUND_STRUCTURED, "finest displacement error {}", du[3]);
    assert!(de[3] < ENERGY_BOUND_STRUCTURED, "finest energy error {}", de[3]);
    assert!(ru > 1.6, "displacement rate {ru}");
    assert!(re > 1.7, "energy rate {re}");
}

#[test]
fn cantilever_jittered() {
    let h = [1.0, 0.5, 0.25, 0.125];
    let (du, de) = study("jittered", Layout::Jittered { amplitude: 0.25, seed: 3 }, &h, DEFAULT);
    let (ru, re) = (convergence_rate(&h, &du), convergence_rate(&h, &de));
    println!("jittered rates: displacement {ru:.2}, energy {re:.2}");
    assert!(du[3] < DISPLACEMENT_BOUND_JITTERED, "finest displacement error {}", du[3]);
    assert!(de[3] < ENERGY_BOUND_JITTERED, "finest energy error {}", de[3]);
    assert!(ru > 1.7, "displacement rate {ru}");
    assert!(re > 0.85, "energy rate {re}");
}

// Bounds at h = 0.125: observed values (structured 2.37e-5 / 1.02e-4, jittered 8.8e-6 /
// 2.59e-3, α_s = 2, 2 Gauss points) with ~25 % headroom. Observed rates over h = 1…0.125:
// structured 1.77 (1.91 over the last halving) / 1.90 (nodal stresses superconverge on the
// uniform grid); jittered 2.05 / 1.05 (the expected ~2 and ~1 for a linear basis).
const DISPLACEMENT_BOUND_STRUCTURED: f64 = 3.0e-5;
const ENERGY_BOUND_STRUCTURED: f64 = 1.3e-4;
const DISPLACEMENT_BOUND_JITTERED: f64 = 1.2e-5;
const ENERGY_BOUND_JITTERED: f64 = 3.3e-3;

/// The stabilised blend (docs/method.md §3.9): on jittered nodes at `α_s = 3` the stabilised `β = 1` converges,
/// while the pure mixed method (`β = 0`, accepted only with `allow_unstable`) does not: its
/// near-free checkerboard modes pollute the solution (the documented negative case).
#[test]
fn cantilever_jittered_large_support() {
    let h = [1.0, 0.5, 0.25];
    let layout = Layout::Jittered { amplitude: 0.25, seed: 3 };
    let primal = Variant { support_factor: 3.0, beta: 1.0 };
    let (du, de) = study("jittered_alpha3_beta1", layout, &h, primal);
    let (ru, re) = (convergence_rate(&h, &du), convergence_rate(&h, &de));
    println!("jittered α_s = 3, β = 1 rates: displacement {ru:.2}, energy {re:.2}");
    let mixed = Variant { support_factor: 3.0, beta: 0.0 };
    let (mu, me) = study("jittered_alpha3_beta0", layout, &h, mixed);
    let (rmu, rme) = (convergence_rate(&h, &mu), convergence_rate(&h, &me));
    println!("jittered α_s = 3, β = 0 rates: displacement {rmu:.2}, energy {rme:.2}");
    // β = 1: bounds at h = 0.25 and rates over h = 1, 0.5, 0.25 (observed 2.10e-5 / 3.30e-3,
    // rates 2.18 / 1.11; bounds with ~25 % headroom).
    assert!(du[2] < 2.6e-5, "β = 1: finest displacement error {}", du[2]);
    assert!(de[2] < 4.2e-3, "β = 1: finest energy error {}", de[2]);
    assert!(du.windows(2).all(|w| w[1] < w[0]) && de.windows(2).all(|w| w[1] < w[0]));
    assert!(ru > 1.5, "β = 1: displacement rate {ru}");
    assert!(re > 0.9, "β = 1: energy rate {re}");
    // β = 0: clearly worse at every spacing (observed 10–120× in displacement, 6.6–40× in
    // energy), and not converging: the energy error grows from h = 1 to h = 0.5 (observed
    // 0.101 → 0.294 → 0.052).
    for k in 0..h.len() {
        assert!(mu[k] > 4.0 * du[k], "h = {}: β = 0 {} vs β = 1 {}", h[k], mu[k], du[k]);
        assert!(me[k] > 4.0 * de[k], "h = {}: β = 0 {} vs β = 1 {}", h[k], me[k], de[k]);
    }
    assert!(me[1] > me[0], "β = 0 energy errors {me:?}: expected no convergence");
}

/// Graded node sets (docs/method.md §2.1): bands of spacing `h₀/2` and width `2 h₀` along
/// the top and bottom edges (where the bending stress peaks), at `h₀ = 1, 0.5, 0.25`, with the
/// stabilised blend `β = 0.5` (the pure mixed method is not robust at the transitions);
/// MEASURED rows are printed (the table in docs/dev/adaptive.md). The end-shear solution is
/// smooth, its error is spread over the whole beam, and local refinement does not beat the
/// uniform set at the fine spacing here (the contact edge of the beam is where it pays:
/// `beam_on_foundation.rs`). Worse: the transitions cost the structured grid its second-order
/// displacement convergence (observed rate 1.02 against 2 uniform: a 2:1 transition is not
/// symmetric, so the O(h) truncation terms no longer cancel).
///
/// Asserted (observed values in brackets, bounds with the margin stated): the energy error
/// decreases at every halving; its rate is above 1.1 structured (1.31) and 0.65 jittered
/// (0.80; the uniform jittered rate is ~1); at each `h₀` the graded energy error is at most
/// 1.3 times the uniform one (≤ 1.16: the transitions cost under 30 %); at `h₀ = 0.25` the
/// graded displacement error is at most 3 times the uniform one (2.26 structured, 0.74
/// jittered: the rate-1 loss above, bounded).
#[test]
fn cantilever_graded_converges() {
    let h = [1.0, 0.5, 0.25];
    let variant = Variant { support_factor: 2.0, beta: 0.5 };
    let bands = |h0: f64| Refinement {
        boxes: vec![
            RefineBox {
                x: [0.0, LENGTH],
                y: [-DEPTH / 2.0, -DEPTH / 2.0 + 2.0 * h0],
                spacing: h0 / 2.0,
            },
            RefineBox {
                x: [0.0, LENGTH],
                y: [DEPTH / 2.0 - 2.0 * h0, DEPTH / 2.0],
                spacing: h0 / 2.0,
            },
        ],
    };
    for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.25, seed: 3 }] {
        let (mut du, mut de) = (Vec::new(), Vec::new());
        for &h0 in &h {
            let (uniform, n_uniform, _) = run_refined(h0, layout, variant, Refinement::default());
            let (e, n, _) = run_refined(h0, layout, variant, bands(h0));
            println!(
                "MEASURED {layout:?} h0 = {h0}: uniform {n_uniform} nodes, displacement {:.3e}, energy {:.3e}; graded {n} nodes, displacement {:.3e}, energy {:.3e}",
                uniform.displacement, uniform.energy, e.displacement, e.energy
            );
            du.push(e.displacement);
            de.push(e.energy);
            assert!(
                e.energy <= 1.3 * uniform.energy,
                "h0 = {h0}: energy {:e} vs {:e}",
                e.energy,
                uniform.energy
            );
            if h0 == 0.25 {
                assert!(
                    e.displacement <= 3.0 * uniform.displacement,
                    "displacement {:e} vs {:e}",
                    e.displacement,
                    uniform.displacement
                );
            }
        }
        let (ru, re) = (convergence_rate(&h, &du), convergence_rate(&h, &de));
        println!("MEASURED {layout:?} graded rates: displacement {ru:.2}, energy {re:.2}");
        assert!(de.windows(2).all(|w| w[1] < w[0]), "energy errors {de:?}");
        let bound = if layout == Layout::Structured { 1.1 } else { 0.65 };
        assert!(re > bound, "energy rate {re}");
    }
}
