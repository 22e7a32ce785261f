//! Axisymmetric bodies (docs/method.md §9): `x` is the radius `r`, `y` the axis `z`, loads and
//! forces per radian. Three exact solutions, MFVM and finite elements:
//!
//! 1. **Patch test**: `u_r = a r`, `u_z = b z + c` (uniform stress, `σ_rr = σ_θθ`) prescribed
//!    on the whole boundary is reproduced to round-off inside, on a section touching the axis
//!    and on a hollow one, structured and jittered nodes, every blend `β` (MFVM), and by the
//!    Q2 elements. Each cell's `∮ r t_r dΓ = σ_rr A` equals `∫ σ_θθ dA = σ_θθ A` exactly
//!    (§9.4), so the bound is round-off.
//! 2. **Lamé's thick-walled cylinder** under internal pressure `p`, long (plane strain along
//!    the axis: `u_z = 0` on the two ends), radii `a < b`: `u_r = A r + B/r`,
//!    `A = (1+ν)(1−2ν) p a² / (E (b² − a²))`, `B = (1+ν) p a² b² / (E (b² − a²))`
//!    (Timoshenko & Goodier, *Theory of Elasticity*, 3rd ed. 1970, §28, with `ε_zz = 0`).
//!    Errors at three spacings and the observed rate; MFVM against FE.
//! 3. **Solid cylinders on the axis**: axial compression with a free lateral surface
//!    (`u_r = ν σ r / E`, `u_z = −σ z / E`: exact, so round-off through the axis and loads),
//!    and a long cylinder spinning about its axis (body force `b_r = k r`, `k = ρω²`, `u_z = 0`
//!    on the ends): `u_r = C r − k r³ / (8 M)`, `M = λ + 2μ`,
//!    `C = (3M + λ) k R² / (8 M (M + λ))` from `M (1/r (r u)')' = −k r` and `σ_rr(R) = 0`
//!    (Timoshenko & Goodier §32, the plane-strain rotating disk), which tests the hoop limit
//!    `ε_θθ = ε_rr` of the nodes on the axis under a field the basis does not reproduce.

use super::common::*;
use mlpg_contact::geometry::{Domain, Point};
use mlpg_contact::material::{Material, PlaneState};
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{
    BodyForce, ComponentCondition, EdgeCondition, Field, Method, Problem, RefineBox, Refinement,
};
use std::sync::Arc;

const YOUNG: f64 = 1.0e5;
const POISSON: f64 = 0.3;
/// Relative max-norm error of the exact (linear) cases: round-off with a margin.
const ROUND_OFF: f64 = 1e-10;
const JITTER: Layout = Layout::Jittered { amplitude: 0.3, seed: 5 };

fn axisymmetric() -> Material {
    Material { young: YOUNG, poisson: POISSON, plane: PlaneState::Axisymmetric }
}

/// `λ` and `M = λ + 2μ`.
fn lame() -> (f64, f64) {
    let (e, nu) = (YOUNG, POISSON);
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    (lambda, lambda + e / (1.0 + nu))
}

fn constant(v: f64) -> Field {
    Field::Constant(v)
}

/// `u_r` free (zero traction) and `u_z` given: a roller along the axis direction.
fn axial_roller(uz: f64) -> EdgeCondition {
    EdgeCondition::Components([
        ComponentCondition::Traction(constant(0.0)),
        ComponentCondition::Displacement(constant(uz)),
    ])
}

/// The axis `r = 0`: `u_r = 0`, no axial traction (what validation makes of an axis edge).
fn axis() -> EdgeCondition {
    EdgeCondition::Components([
        ComponentCondition::Displacement(constant(0.0)),
        ComponentCondition::Traction(constant(0.0)),
    ])
}

fn edge(problem: &Problem, name: &str) -> usize {
    problem.domain.edge_index(name).unwrap()
}

fn with_method(mut problem: Problem, method: Method, beta: f64) -> Problem {
    problem.discretisation.method = method;
    problem.discretisation.beta = beta;
    problem
}

/// Solves `problem`; the node positions and the solution.
fn solve(problem: &Problem) -> (Vec<Point>, mlpg_contact::solution::Solution) {
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(problem, &mut silent).unwrap();
    let (model, _, s) = mlpg_contact::solve_model(problem, model, None, &mut silent).unwrap();
    assert!(s.equilibrium_error < 1e-10, "axial balance {:.3e}", s.equilibrium_error);
    (model.nodes.points.clone(), s)
}

/// Max over the nodes of `|u^h − u|` (both components) over `scale`.
fn max_error(problem: &Problem, exact: impl Fn(Point) -> [f64; 2], scale: f64) -> f64 {
    let (points, s) = solve(problem);
    points
        .iter()
        .zip(&s.displacement)
        .map(|(p, u)| {
            let e = exact(*p);
            (u[0] - e[0]).abs().max((u[1] - e[1]).abs()) / scale
        })
        .fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------------------
// 1. Patch test.

fn patch_exact(p: Point) -> [f64; 2] {
    [2e-3 * p[0], -0.7e-3 * p[1] + 0.5e-3]
}

fn patch_problem(r: [f64; 2], h: f64, layout: Layout) -> Problem {
    let domain = Domain::rectangle(r, [0.0, 2.0]).unwrap();
    let mut p = base_problem(domain, h, layout, axisymmetric());
    p.boundary = vec![displacement(Arc::new(patch_exact)); 4];
    p
}

#[test]
fn axisymmetric_patch_test_mfvm() {
    for (name, r) in [("on the axis", [0.0, 2.0]), ("hollow", [0.5, 2.5])] {
        for layout in [Layout::Structured, JITTER] {
            for (beta, alpha) in [(0.0, 2.0), (0.1, 2.0), (0.5, 2.0), (1.0, 2.0), (1.0, 3.0)] {
                let mut p = with_method(patch_problem(r, 0.2, layout), Method::Mfvm, beta);
                p.discretisation.mls.support_factor = alpha;
                let err = max_error(&p, patch_exact, 5e-3);
                println!("MFVM patch {name}, {layout:?}, α_s = {alpha}, β = {beta}: {err:.3e}");
                assert!(err < ROUND_OFF, "{name} {layout:?} β = {beta}: {err:.3e}");
            }
        }
    }
}

/// The patch field on graded node sets with nodes on the axis: a band of `h₀/2` along the
/// axis, a box of `h₀/4` at the axis's lower corner (two transition levels meeting the axis),
/// and both; structured and jittered seeds (the quadtree grades between the spacings).
#[test]
fn axisymmetric_patch_test_graded() {
    let band = RefineBox { x: [0.0, 0.3], y: [0.0, 2.0], spacing: 0.1 };
    let corner = RefineBox { x: [0.0, 0.5], y: [0.0, 0.4], spacing: 0.05 };
    let gradings = [("band", vec![band]), ("corner", vec![corner]), ("both", vec![band, corner])];
    for (name, boxes) in gradings {
        for layout in [Layout::Structured, JITTER] {
            for beta in [0.0, 1.0] {
                let mut p = with_method(patch_problem([0.0, 2.0], 0.2, layout), Method::Mfvm, beta);
                p.refinement = Refinement { boxes: boxes.clone() };
                let err = max_error(&p, patch_exact, 5e-3);
                println!("MFVM graded patch {name}, {layout:?}, β = {beta}: {err:.3e}");
                assert!(err < ROUND_OFF, "graded {name} {layout:?} β = {beta}: {err:.3e}");
            }
        }
    }
}

#[test]
fn axisymmetric_patch_test_fem() {
    for (name, r) in [("on the axis", [0.0, 2.0]), ("hollow", [0.5, 2.5])] {
        let p = with_method(patch_problem(r, 0.25, Layout::Structured), Method::Fem, 0.0);
        let err = max_error(&p, patch_exact, 5e-3);
        println!("FE patch {name}: {err:.3e}");
        assert!(err < ROUND_OFF, "FE patch {name}: {err:.3e}");
    }
}

/// The uniform stress of the patch field also comes out at the nodes, hoop stress included
/// (`σ_θθ = σ_rr`), on the axis too.
#[test]
fn axisymmetric_patch_test_stress() {
    let (lambda, m) = lame();
    let e = [2e-3, -0.7e-3, 0.0, 2e-3];
    let s_rr = m * e[0] + lambda * (e[1] + e[3]);
    let s_zz = m * e[1] + lambda * (e[0] + e[3]);
    for method in [Method::Mfvm, Method::Fem] {
        let p = with_method(patch_problem([0.0, 2.0], 0.25, Layout::Structured), method, 0.0);
        let (_, s) = solve(&p);
        let worst = s
            .stress
            .iter()
            .zip(&s.hoop)
            .map(|(t, h)| {
                [t[0] - s_rr, t[1] - s_zz, t[2], h[1] - s_rr, h[0] - e[3]]
                    .iter()
                    .fold(0.0f64, |w, v| w.max(v.abs()))
            })
            .fold(0.0, f64::max)
            / s_rr.abs();
        println!("{method:?} patch stress: {worst:.3e}");
        assert!(worst < ROUND_OFF, "{method:?}: {worst:.3e}");
    }
}

// ---------------------------------------------------------------------------------------
// 2. Lamé's thick-walled cylinder.

const INNER: f64 = 1.0;
const OUTER: f64 = 2.0;
const PRESSURE: f64 = 10.0;

fn lame_exact(p: Point) -> [f64; 2] {
    let (a, b, nu, e) = (INNER, OUTER, POISSON, YOUNG);
    let big_a = (1.0 + nu) * (1.0 - 2.0 * nu) * PRESSURE * a * a / (e * (b * b - a * a));
    let big_b = (1.0 + nu) * PRESSURE * a * a * b * b / (e * (b * b - a * a));
    [big_a * p[0] + big_b / p[0], 0.0]
}

fn lame_problem(h: f64, method: Method, beta: f64) -> Problem {
    let domain = Domain::rectangle([INNER, OUTER], [0.0, 0.5]).unwrap();
    let mut p = base_problem(domain, h, Layout::Structured, axisymmetric());
    let (bottom, top, left) = (edge(&p, "bottom"), edge(&p, "top"), edge(&p, "left"));
    p.boundary[bottom] = axial_roller(0.0);
    p.boundary[top] = axial_roller(0.0);
    p.boundary[left] = EdgeCondition::Pressure(constant(PRESSURE));
    with_method(p, method, beta)
}

/// (spacing, bound on the relative max-norm error of `u`), `β = 0`. Bounds: the errors
/// observed when the case was written, plus about 25 %; the rate is asserted above 1.7
/// (observed 1.91 for `β = 0`, 2.03 for `β = 1`, 3.95 for FE with a bound of 3.5).
const LAME_MFVM: [(f64, f64); 3] = [(0.1, 7.6e-3), (0.05, 2.1e-3), (0.025, 5.4e-4)];
/// The same with `β = 1` (docs/method.md §3.9).
const LAME_MFVM_STABILISED: [(f64, f64); 3] = [(0.1, 1.7e-3), (0.05, 4.0e-4), (0.025, 9.8e-5)];
/// Q2 elements of size `h` (nodal values superconverge: rate ≈ 4).
const LAME_FEM: [(f64, f64); 3] = [(0.25, 7.9e-5), (0.125, 5.3e-6), (0.0625, 3.4e-7)];

fn lame_series(method: Method, beta: f64, series: &[(f64, f64)], rate: f64) {
    let scale = lame_exact([INNER, 0.0])[0];
    let mut errors = Vec::new();
    for &(h, bound) in series {
        let err = max_error(&lame_problem(h, method, beta), lame_exact, scale);
        println!("{method:?} β = {beta} Lamé h = {h}: {err:.3e} (bound {bound:.1e})");
        errors.push(err);
        assert!(err < bound, "{method:?} Lamé h = {h}: {err:.3e} over {bound:.1e}");
    }
    let hs: Vec<f64> = series.iter().map(|s| s.0).collect();
    let observed = convergence_rate(&hs, &errors);
    println!("{method:?} β = {beta} Lamé rate {observed:.2}");
    let rows: Vec<Vec<f64>> = hs.iter().zip(&errors).map(|(h, e)| vec![*h, *e]).collect();
    write_table("axisymmetric", &format!("lame_{method:?}_beta{beta}.csv"), "h,error", &rows);
    assert!(observed > rate, "{method:?} Lamé rate {observed:.2} below {rate}");
}

#[test]
fn lame_thick_cylinder_mfvm() {
    lame_series(Method::Mfvm, 0.0, &LAME_MFVM, 1.7);
    lame_series(Method::Mfvm, 1.0, &LAME_MFVM_STABILISED, 1.7);
}

#[test]
fn lame_thick_cylinder_fem() {
    lame_series(Method::Fem, 0.0, &LAME_FEM, 3.5);
}

/// The plane-strain ring of the Lamé section: a quarter annulus `1 ≤ ρ ≤ 2` (symmetry rollers
/// on its straight edges, the pressure on the inner arc), MFVM `β = 1` at spacing `h`.
fn plane_strain_ring(h: f64) -> Problem {
    let text = format!(
        r#"
        [geometry]
        kind = "curves"
        start = [{INNER:?}, 0.0]
        curves = [
            {{ name = "bottom", to = [{OUTER:?}, 0.0] }},
            {{ name = "outer", to = [0.0, {OUTER:?}], center = [0.0, 0.0] }},
            {{ name = "left", to = [0.0, {INNER:?}] }},
            {{ name = "inner", to = [{INNER:?}, 0.0], center = [0.0, 0.0], turn = "cw" }},
        ]
        [nodes]
        spacing = {h:?}
        [material]
        young = {YOUNG:?}
        poisson = {POISSON:?}
        plane = "strain"
        [discretisation]
        beta = 1.0
        [[boundary]]
        edge = "bottom"
        displacement = {{ y = 0.0 }}
        [[boundary]]
        edge = "left"
        displacement = {{ x = 0.0 }}
        [[boundary]]
        edge = "inner"
        pressure = {PRESSURE:?}
        "#
    );
    Problem::from_toml(&text).unwrap()
}

/// The radial displacements `(ρ, u_ρ)` of a solution at its nodes (the cylinder's `r` is `x`).
fn radial(points: &[Point], s: &mlpg_contact::solution::Solution, ring: bool) -> Vec<(f64, f64)> {
    let radial = |p: &Point, u: &[f64; 2]| match ring {
        true => {
            let rho = p[0].hypot(p[1]);
            (rho, (u[0] * p[0] + u[1] * p[1]) / rho)
        }
        false => (p[0], u[0]),
    };
    points.iter().zip(&s.displacement).map(|(p, u)| radial(p, u)).collect()
}

/// Issue item: a long thick cylinder (`u_z = 0` on its ends) equals the plane-strain ring of
/// the same section. Both converge to Lamé (the cylinder's `u_r` and the ring's `u_ρ`, each
/// against `lame_exact`; the ring's tangential part is zero by symmetry and not compared), and
/// their mean radial displacements on the inner and outer radius differ by no more than the
/// two errors together, the difference shrinking with `h`. MFVM `β = 1`. Measured (`u_r` max
/// norm over `u(a)`) at h = 0.1, 0.05, 0.025: the cylinder 9.22e-4, 2.13e-4, 5.07e-5, the ring
/// 5.69e-3, 1.50e-3, 3.27e-4 (rate 2.06; its arcs' chords), the difference 4.12e-3, 1.10e-3,
/// 2.29e-4 (rate 2.08); the rates are asserted above 1.7 and 1.5.
#[test]
fn long_cylinder_equals_the_plane_strain_ring() {
    let scale = lame_exact([INNER, 0.0])[0];
    let hs = [0.1, 0.05, 0.025];
    let (mut ring_errors, mut differences) = (Vec::new(), Vec::new());
    for h in hs {
        let mean_at = |values: &[(f64, f64)], r: f64| {
            let on: Vec<f64> =
                values.iter().filter(|(rho, _)| (rho - r).abs() < 1e-9).map(|v| v.1).collect();
            on.iter().sum::<f64>() / on.len() as f64
        };
        let (points, s) = solve(&plane_strain_ring(h));
        let ring = radial(&points, &s, true);
        let (points, s) = solve(&lame_problem(h, Method::Mfvm, 1.0));
        let cylinder = radial(&points, &s, false);
        let error = |values: &[(f64, f64)]| {
            values
                .iter()
                .map(|(r, u)| (u - lame_exact([*r, 0.0])[0]).abs() / scale)
                .fold(0.0, f64::max)
        };
        let (e_ring, e_cyl) = (error(&ring), error(&cylinder));
        let difference = [INNER, OUTER]
            .map(|r| (mean_at(&ring, r) - mean_at(&cylinder, r)).abs() / scale)
            .into_iter()
            .fold(0.0, f64::max);
        println!(
            "h = {h}: ring {e_ring:.3e}, cylinder {e_cyl:.3e}, ring − cylinder at a, b {difference:.3e}"
        );
        assert!(difference <= e_ring + e_cyl, "h = {h}: {difference:.3e}");
        ring_errors.push(e_ring);
        differences.push(difference);
    }
    let (rate_ring, rate_difference) =
        (convergence_rate(&hs, &ring_errors), convergence_rate(&hs, &differences));
    println!("rates: ring {rate_ring:.2}, difference {rate_difference:.2}");
    assert!(rate_ring > 1.7 && rate_difference > 1.5, "{rate_ring:.2}, {rate_difference:.2}");
}

// ---------------------------------------------------------------------------------------
// 3. Solid cylinders touching the axis.

const RADIUS: f64 = 1.0;
const SIGMA: f64 = 50.0;

fn compression_exact(p: Point) -> [f64; 2] {
    [POISSON * SIGMA * p[0] / YOUNG, -SIGMA * p[1] / YOUNG]
}

fn compression_problem(h: f64, layout: Layout, method: Method, beta: f64) -> Problem {
    let domain = Domain::rectangle([0.0, RADIUS], [0.0, 2.0]).unwrap();
    let mut p = base_problem(domain, h, layout, axisymmetric());
    let (bottom, top, left) = (edge(&p, "bottom"), edge(&p, "top"), edge(&p, "left"));
    p.boundary[bottom] = axial_roller(0.0);
    p.boundary[top] = EdgeCondition::Pressure(constant(SIGMA));
    p.boundary[left] = axis();
    with_method(p, method, beta)
}

#[test]
fn solid_cylinder_in_compression() {
    let scale = SIGMA * 2.0 / YOUNG;
    for layout in [Layout::Structured, JITTER] {
        for beta in [0.0, 1.0] {
            let err = max_error(
                &compression_problem(0.1, layout, Method::Mfvm, beta),
                compression_exact,
                scale,
            );
            println!("MFVM compression {layout:?} β = {beta}: {err:.3e}");
            assert!(err < ROUND_OFF, "{layout:?} β = {beta}: {err:.3e}");
        }
    }
    let err = max_error(
        &compression_problem(0.25, Layout::Structured, Method::Fem, 0.0),
        compression_exact,
        scale,
    );
    println!("FE compression: {err:.3e}");
    assert!(err < ROUND_OFF, "FE: {err:.3e}");
}

/// `ρω²` of the spinning cylinder.
const SPIN: f64 = 1.0e3;

fn spin_exact(p: Point) -> [f64; 2] {
    let (lambda, m) = lame();
    let c = (3.0 * m + lambda) * SPIN * RADIUS * RADIUS / (8.0 * m * (m + lambda));
    [c * p[0] - SPIN * p[0].powi(3) / (8.0 * m), 0.0]
}

fn spin_problem(h: f64, method: Method, beta: f64) -> Problem {
    let domain = Domain::rectangle([0.0, RADIUS], [0.0, 0.5]).unwrap();
    let mut p = base_problem(domain, h, Layout::Structured, axisymmetric());
    let (bottom, top, left) = (edge(&p, "bottom"), edge(&p, "top"), edge(&p, "left"));
    p.boundary[bottom] = axial_roller(0.0);
    p.boundary[top] = axial_roller(0.0);
    p.boundary[left] = axis();
    p.body_force = Some(BodyForce(Arc::new(|p: Point| [SPIN * p[0], 0.0])));
    with_method(p, method, beta)
}

/// (spacing, bound) for `β = 0` and `β = 1`, as for Lamé (observed rates 1.92 and 2.02).
const SPIN_MFVM: [[(f64, f64); 3]; 2] = [
    [(0.1, 8.4e-3), (0.05, 2.3e-3), (0.025, 5.9e-4)],
    [(0.1, 1.3e-3), (0.05, 3.1e-4), (0.025, 7.6e-5)],
];
/// Q2 at `h = 0.125` (observed 2.7e-5).
const SPIN_FEM: f64 = 3.4e-5;

#[test]
fn spinning_solid_cylinder() {
    let scale = spin_exact([RADIUS, 0.0])[0];
    for (beta, series) in [0.0, 1.0].into_iter().zip(SPIN_MFVM) {
        let mut errors = Vec::new();
        for &(h, bound) in &series {
            let err = max_error(&spin_problem(h, Method::Mfvm, beta), spin_exact, scale);
            println!("MFVM spin β = {beta}, h = {h}: {err:.3e}");
            errors.push(err);
            assert!(err < bound, "spin β = {beta}, h = {h}: {err:.3e} over {bound:.1e}");
        }
        let hs: Vec<f64> = series.iter().map(|s| s.0).collect();
        let rate = convergence_rate(&hs, &errors);
        println!("MFVM spin β = {beta} rate {rate:.2}");
        assert!(rate > 1.7, "spin β = {beta} rate {rate:.2}");
    }
    let err = max_error(&spin_problem(0.125, Method::Fem, 0.0), spin_exact, scale);
    println!("FE spin h = 0.125: {err:.3e}");
    assert!(err < SPIN_FEM, "FE spin: {err:.3e}");
}
