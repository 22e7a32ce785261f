//! Plate with a circular hole under remote uniaxial tension (Kirsch 1898; e.g. Timoshenko &
//! Goodier [TG70, §35]; the displacement field as in Barber, *Elasticity*, §8.4.1), plane
//! stress. Hole radius `a = 1`, remote stress `σ₀ = 1` along `x`, `E = 1000`, `ν = 0.3`.
//!
//! `σ_xx = σ₀[1 − a²/r² (3/2 cos 2θ + cos 4θ) + 3a⁴/(2r⁴) cos 4θ]`,
//! `σ_yy = σ₀[−a²/r² (1/2 cos 2θ − cos 4θ) − 3a⁴/(2r⁴) cos 4θ]`,
//! `τ_xy = σ₀[−a²/r² (1/2 sin 2θ + sin 4θ) + 3a⁴/(2r⁴) sin 4θ]`,
//! `u_x = σ₀a/(8μ)[(κ+1) r/a cos θ + 2a/r ((1+κ) cos θ + cos 3θ) − 2a³/r³ cos 3θ]`,
//! `u_y = σ₀a/(8μ)[(κ−3) r/a sin θ + 2a/r ((1−κ) sin θ + sin 3θ) − 2a³/r³ sin 3θ]`,
//! `μ = E/(2(1+ν))`, `κ = (3−ν)/(1+ν)`. (Checked here: far field `u_x → σ₀x/E`,
//! `u_y → −νσ₀y/E`; traction-free hole; `σ_xx(0, a) = 3σ₀`.)
//!
//! The quarter `[0, 5]²` outside the hole (the hole's boundary is a clockwise arc, the domain
//! non-convex): rollers on the symmetry lines, the exact traction on `x = 5` and `y = 5`, so
//! the exact solution of the finite quarter plate is Kirsch's. Checks at three spacings: the
//! relative max-norm displacement error, the relative energy-norm error (nodal quadrature
//! over the cells), the stress concentration `σ_xx(0, a)/σ₀` (exact 3), each with its
//! observed rate.

use super::common::*;
use mlpg_contact::geometry::{Curve, Domain, Point};
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{ComponentCondition, EdgeCondition, Field, Problem};
use std::sync::Arc;

const A: f64 = 1.0;
const SIDE: f64 = 5.0;
pub(super) const YOUNG: f64 = 1000.0;
pub(super) const POISSON: f64 = 0.3;

pub(super) fn exact_stress(p: Point) -> [f64; 3] {
    let (r, th) = (p[0].hypot(p[1]), p[1].atan2(p[0]));
    let (a2, a4) = ((A / r).powi(2), (A / r).powi(4));
    [
        1.0 - a2 * (1.5 * (2.0 * th).cos() + (4.0 * th).cos()) + 1.5 * a4 * (4.0 * th).cos(),
        -a2 * (0.5 * (2.0 * th).cos() - (4.0 * th).cos()) - 1.5 * a4 * (4.0 * th).cos(),
        -a2 * (0.5 * (2.0 * th).sin() + (4.0 * th).sin()) + 1.5 * a4 * (4.0 * th).sin(),
    ]
}

pub(super) fn exact_displacement(p: Point) -> [f64; 2] {
    let (r, th) = (p[0].hypot(p[1]), p[1].atan2(p[0]));
    let mu = YOUNG / (2.0 * (1.0 + POISSON));
    let kappa = (3.0 - POISSON) / (1.0 + POISSON);
    let c = A / (8.0 * mu);
    let (q, q3) = (A / r, (A / r).powi(3));
    [
        c * ((kappa + 1.0) * th.cos() / q
            + 2.0 * q * ((1.0 + kappa) * th.cos() + (3.0 * th).cos())
            - 2.0 * q3 * (3.0 * th).cos()),
        c * ((kappa - 3.0) * th.sin() / q
            + 2.0 * q * ((1.0 - kappa) * th.sin() + (3.0 * th).sin())
            - 2.0 * q3 * (3.0 * th).sin()),
    ]
}

pub fn quarter_plate() -> Domain {
    Domain::from_curves(
        vec![
            Curve::Segment { a: [A, 0.0], b: [SIDE, 0.0] },
            Curve::Segment { a: [SIDE, 0.0], b: [SIDE, SIDE] },
            Curve::Segment { a: [SIDE, SIDE], b: [0.0, SIDE] },
            Curve::Segment { a: [0.0, SIDE], b: [0.0, A] },
            Curve::arc_between([0.0, A], [A, 0.0], [0.0, 0.0], false),
        ],
        ["bottom", "right", "top", "left", "hole"].iter().map(|s| s.to_string()).collect(),
    )
    .unwrap()
}

pub struct Errors {
    pub displacement: f64,
    pub energy: f64,
    pub concentration: f64,
}

fn roller(axis: usize) -> EdgeCondition {
    let zero = || Field::Constant(0.0);
    let mut c = [ComponentCondition::Traction(zero()), ComponentCondition::Traction(zero())];
    c[axis] = ComponentCondition::Displacement(zero());
    EdgeCondition::Components(c)
}

/// The errors on `domain` (a quarter plate with edges named `bottom`, `right`, `top`, `left`
/// and `hole`, in any order) at spacing `h`.
pub fn run_on(domain: Domain, h: f64, layout: Layout) -> Errors {
    errors(kirsch_problem(domain, h, layout))
}

/// The Kirsch problem on `domain` (as [`run_on`]): rollers on `bottom` and `left`, the exact
/// traction on `right` and `top`.
pub fn kirsch_problem(domain: Domain, h: f64, layout: Layout) -> Problem {
    let edge = |name: &str| domain.edge_index(name).unwrap();
    let [bottom, right, top, left] = ["bottom", "right", "top", "left"].map(edge);
    let mut problem = base_problem(domain, h, layout, plane_stress(YOUNG, POISSON));
    problem.boundary[bottom] = roller(1);
    problem.boundary[right] = traction(Arc::new(|p| {
        let s = exact_stress(p);
        [s[0], s[2]]
    }));
    problem.boundary[top] = traction(Arc::new(|p| {
        let s = exact_stress(p);
        [s[2], s[1]]
    }));
    problem.boundary[left] = roller(0);
    problem
}

/// Solves a Kirsch problem and measures its errors.
pub fn errors(problem: Problem) -> Errors {
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&problem, &mut silent).unwrap();
    let (model, _, s) = mlpg_contact::solve_model(&problem, model, None, &mut silent).unwrap();
    assert!(s.relative_residual < 1e-10, "residual {}", s.relative_residual);
    assert!(s.equilibrium_error < 1e-9, "equilibrium {}", s.equilibrium_error);
    measure(&model, &s)
}

/// The errors of a solution on a Kirsch quarter plate (any MFVM node set, uniform or graded):
/// the relative max-norm displacement error over the nodes, the relative energy-norm error
/// (nodal quadrature over the cells) and `σ_xx` at the node `(0, a)`.
pub fn measure(model: &mlpg_contact::Model, s: &mlpg_contact::Solution) -> Errors {
    let max_u = model
        .nodes
        .points
        .iter()
        .map(|&p| {
            let u = exact_displacement(p);
            u[0].hypot(u[1])
        })
        .fold(0.0, f64::max);
    let compliance = |s: [f64; 3]| {
        let e = YOUNG;
        [(s[0] - POISSON * s[1]) / e, (s[1] - POISSON * s[0]) / e, 2.0 * (1.0 + POISSON) * s[2] / e]
    };
    let (mut err_u, mut e_num, mut e_den) = (0.0f64, 0.0, 0.0);
    let mut concentration = f64::NAN;
    for (i, &p) in model.nodes.points.iter().enumerate() {
        let ue = exact_displacement(p);
        let u = s.displacement[i];
        err_u = err_u.max((u[0] - ue[0]).hypot(u[1] - ue[1]));
        let se = exact_stress(p);
        let ds = [s.stress[i][0] - se[0], s.stress[i][1] - se[1], s.stress[i][2] - se[2]];
        let (de, ee) = (compliance(ds), compliance(se));
        let area = model.mfvm().expect("an MFVM model").cells[i].area();
        e_num += area * (ds[0] * de[0] + ds[1] * de[1] + ds[2] * de[2]);
        e_den += area * (se[0] * ee[0] + se[1] * ee[1] + se[2] * ee[2]);
        if p[0].abs() < 1e-12 && (p[1] - A).abs() < 1e-12 {
            concentration = s.stress[i][0];
        }
    }
    Errors { displacement: err_u / max_u, energy: (e_num / e_den).sqrt(), concentration }
}

#[test]
fn closed_form_checks() {
    // Far field, traction-free hole, concentration.
    let u = exact_displacement([200.0, 0.0]);
    assert!((u[0] - 200.0 / YOUNG).abs() < 1e-4 * 200.0 / YOUNG);
    let u = exact_displacement([0.0, 200.0]);
    assert!((u[1] + POISSON * 200.0 / YOUNG).abs() < 1e-4 * 200.0 / YOUNG);
    for th in [0.1f64, 0.7, 1.3] {
        let p = [A * th.cos(), A * th.sin()];
        let s = exact_stress(p);
        let n = [-th.cos(), -th.sin()];
        let t = [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]];
        assert!(t[0].abs() < 1e-14 && t[1].abs() < 1e-14);
    }
    assert!((exact_stress([0.0, A])[0] - 3.0).abs() < 1e-14);
}

fn study(name: &str, layout: Layout, h: &[f64]) -> ([f64; 3], [f64; 3]) {
    study_on(name, &|_| quarter_plate(), layout, h)
}

/// Errors and observed rates (displacement, energy, concentration) on `domain(h)` at each
/// spacing of `h`: the rates and the finest errors.
pub fn study_on(
    name: &str,
    domain: &dyn Fn(f64) -> Domain,
    layout: Layout,
    h: &[f64],
) -> ([f64; 3], [f64; 3]) {
    let mut rows = Vec::new();
    let (mut du, mut de, mut dk) = (Vec::new(), Vec::new(), Vec::new());
    for &hi in h {
        let e = run_on(domain(hi), hi, layout);
        println!(
            "kirsch {name}: h = {hi:<5} displacement {:.3e}  energy {:.3e}  sigma_xx(0,a) = {:.5}",
            e.displacement, e.energy, e.concentration
        );
        rows.push(vec![hi, e.displacement, e.energy, e.concentration]);
        du.push(e.displacement);
        de.push(e.energy);
        dk.push((e.concentration - 3.0).abs());
    }
    write_table(
        "kirsch",
        &format!("{name}.csv"),
        "h,displacement_error,energy_error,sigma_xx_at_hole",
        &rows,
    );
    let rates = [convergence_rate(h, &du), convergence_rate(h, &de), convergence_rate(h, &dk)];
    println!(
        "kirsch {name} rates: displacement {:.2}, energy {:.2}, concentration {:.2}",
        rates[0], rates[1], rates[2]
    );
    let last = h.len() - 1;
    (rates, [du[last], de[last], dk[last]])
}

// Observed (α_s = 2, 2 Gauss points; h = 0.2, 0.1, 0.05):
// structured: displacement 1.04e-2, 4.29e-3, 9.9e-4 (rate 1.69); energy 1.75e-2, 5.63e-3,
//   2.03e-3 (1.56); σ_xx(0, a) = 2.915, 3.016, 2.9996 (|error| rate 3.8: the error changes
//   sign, so the finest value is partly luck);
// jittered (0.25 h, seed 3): 1.19e-3 / 3.89e-3 / σ_xx = 2.991 at h = 0.05, rates 1.75, 1.30,
//   1.65. The bounds below are the finest values with ~25 % headroom (the concentration's
//   with more, for the sign change); the rate floors sit below the observed rates because
//   three spacings give a noisy slope.
fn check(rates: [f64; 3], finest: [f64; 3], min_rates: [f64; 3], bounds: [f64; 3]) {
    let what = ["displacement", "energy", "concentration"];
    for k in 0..3 {
        assert!(rates[k] > min_rates[k], "{} rate {} below {}", what[k], rates[k], min_rates[k]);
        assert!(
            finest[k] < bounds[k],
            "finest {} error {} above {}",
            what[k],
            finest[k],
            bounds[k]
        );
    }
}

#[test]
fn kirsch_structured() {
    let (rates, finest) = study("structured", Layout::Structured, &[0.2, 0.1, 0.05]);
    check(rates, finest, [1.4, 1.3, 1.5], [1.25e-3, 2.6e-3, 0.005]);
}

#[test]
fn kirsch_jittered() {
    let layout = Layout::Jittered { amplitude: 0.25, seed: 3 };
    let (rates, finest) = study("jittered", layout, &[0.2, 0.1, 0.05]);
    check(rates, finest, [1.4, 1.1, 1.3], [1.5e-3, 4.9e-3, 0.012]);
}
