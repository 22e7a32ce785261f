//! Lamé's thick-walled sphere under internal pressure, axisymmetric (docs/method.md §9): the
//! section is the quarter annulus `9 ≤ ρ ≤ 11`, `r, z ≥ 0` (`ρ = √(r² + z²)`), bounded by two
//! arcs, the axis edge `r = 0` (made a radial roller by validation) and the equatorial edge
//! `z = 0` (a roller, `u_z = 0`); pressure `p = 10` on the inner arc, the outer arc free;
//! `E = 1e5`, `ν = 0.3`. MFVM only: the FE path meshes rectangles and Gmsh meshes, not a
//! `curves` section (validation refuses `method = "fem"` with `kind = "curves"`).
//!
//! **Reference, derived here.** A radial field `u = u(ρ) e_ρ` has `ε_ρρ = u'`,
//! `ε_θθ = ε_φφ = u/ρ`, and equilibrium `dσ_ρρ/dρ + 2(σ_ρρ − σ_θθ)/ρ = 0` reduces with Hooke's
//! law to `(1/ρ² (ρ² u)')' = 0`, so `u = A ρ + B/ρ²`. Then
//! `σ_ρρ = E/(1−2ν) A − 2E/(1+ν) B/ρ³`; `σ_ρρ(a) = −p`, `σ_ρρ(b) = 0` give
//! `A = (1−2ν) p a³ / (E (b³ − a³))`, `B = (1+ν) p a³ b³ / (2E (b³ − a³))`
//! (Timoshenko & Goodier, *Theory of Elasticity*, 3rd ed. 1970, §141). With `a = 9`, `b = 11`:
//! `b³ − a³ = 602`, `A = 4.843854e-5`, `B = 0.1047665`, so `u(9) = 4.35947e-4 + 1.293414e-3 =
//! 1.729360e-3` and `u(11) = 5.32824e-4 + 8.65839e-4 = 1.398663e-3`: the issue's 1.72936e-3 and
//! 1.39866e-3 check (the last digit of the second rounds 1.3986628e-3 down).
//!
//! **Energy.** The exact strain energy per radian equals half the pressure's work on the inner
//! arc, `U = ½ ∫ p u(a) r ds = ½ p a² u(a)` (`r = a cos φ`, `ds = a dφ`, `φ ∈ [0, π/2]`). The
//! computed one is `½ ∫ p u_ρ^h r ds` over the inner arc's nodes (trapezoid in `φ`; its own
//! quadrature error on the exact field is below 2e-5 relative at the coarsest spacing). It is
//! a compliance, not an energy-norm error (the MFVM is not a Galerkin method, so the two are
//! not tied by the Galerkin orthogonality).
//!
//! Tolerances: the issue's 0.1 % on `u(9)` and `u(11)` at `h = 0.25` (observed −0.081 % and
//! −0.084 %); the error bounds are the observed ones plus about 25 %, the rates asserted above
//! 1.6 (observed 1.80 for `u(9)`, 1.66 for the max norm, 1.96 for the energy).

use super::common::*;
use mlpg_contact::problem::Problem;

const INNER: f64 = 9.0;
const OUTER: f64 = 11.0;
const PRESSURE: f64 = 10.0;
const YOUNG: f64 = 1.0e5;
const POISSON: f64 = 0.3;

const SECTION: &str = r#"
name = "thick_sphere_axisymmetric"

[geometry]
kind = "curves"
start = [9.0, 0.0]
curves = [
    { name = "bottom", to = [11.0, 0.0] },
    { name = "outer", to = [0.0, 11.0], center = [0.0, 0.0] },
    { name = "axis", to = [0.0, 9.0] },
    { name = "inner", to = [9.0, 0.0], center = [0.0, 0.0], turn = "cw" },
]

[nodes]
spacing = 0.25

[material]
young = 1.0e5
poisson = 0.3
plane = "axisymmetric"

[[boundary]]
edge = "bottom"
displacement = { y = 0.0 }

[[boundary]]
edge = "inner"
pressure = 10.0
"#;

/// `(A, B)` of `u = A ρ + B/ρ²`.
fn lame_sphere() -> (f64, f64) {
    let (a3, b3) = (INNER.powi(3), OUTER.powi(3));
    let big_a = (1.0 - 2.0 * POISSON) * PRESSURE * a3 / (YOUNG * (b3 - a3));
    let big_b = (1.0 + POISSON) * PRESSURE * a3 * b3 / (2.0 * YOUNG * (b3 - a3));
    (big_a, big_b)
}

fn exact_u(rho: f64) -> f64 {
    let (a, b) = lame_sphere();
    a * rho + b / (rho * rho)
}

/// Errors at one spacing: (nodes, `u(9)` and `u(11)` relative, max-norm relative, energy relative).
struct Errors {
    nodes: usize,
    inner: f64,
    outer: f64,
    max: f64,
    energy: f64,
}

fn solve(h: f64) -> Errors {
    let mut problem = Problem::from_toml(SECTION).unwrap();
    problem.node_spacing = h;
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&problem, &mut silent).unwrap();
    let (model, _, s) = mlpg_contact::solve_model(&problem, model, None, &mut silent).unwrap();
    assert!(s.equilibrium_error < 1e-10, "axial balance {:.3e}", s.equilibrium_error);
    let scale = exact_u(INNER);
    let (mut max, mut inner, mut outer) = (0.0_f64, None, None);
    let mut arc = Vec::new(); // (φ, u_ρ) on the inner arc
    for (p, u) in model.nodes.points.iter().zip(&s.displacement) {
        let rho = p[0].hypot(p[1]);
        let e = exact_u(rho);
        max = max.max((u[0] - e * p[0] / rho).abs()).max((u[1] - e * p[1] / rho).abs());
        let u_rho = (u[0] * p[0] + u[1] * p[1]) / rho;
        if p[1].abs() < 1e-12 && (p[0] - INNER).abs() < 1e-9 {
            inner = Some(u[0]);
        }
        if p[1].abs() < 1e-12 && (p[0] - OUTER).abs() < 1e-9 {
            outer = Some(u[0]);
        }
        if (rho - INNER).abs() < 1e-9 {
            arc.push((p[1].atan2(p[0]), u_rho));
        }
    }
    arc.sort_by(|x, y| x.0.total_cmp(&y.0));
    // ½ ∫ p u_ρ r ds, r = a cos φ, ds = a dφ: trapezoid in φ.
    let work: f64 = arc
        .windows(2)
        .map(|w| 0.5 * (w[1].0 - w[0].0) * (w[0].1 * w[0].0.cos() + w[1].1 * w[1].0.cos()))
        .sum::<f64>()
        * 0.5
        * PRESSURE
        * INNER
        * INNER;
    let exact_energy = 0.5 * PRESSURE * INNER * INNER * scale;
    Errors {
        nodes: s.displacement.len(),
        inner: inner.unwrap() / scale - 1.0,
        outer: outer.unwrap() / exact_u(OUTER) - 1.0,
        max: max / scale,
        energy: work / exact_energy - 1.0,
    }
}

#[test]
fn lame_thick_sphere_reference() {
    // The issue's quoted values, from the closed form above.
    assert!((exact_u(INNER) / 1.72936e-3 - 1.0).abs() < 1e-5, "{:.6e}", exact_u(INNER));
    assert!((exact_u(OUTER) / 1.39866e-3 - 1.0).abs() < 1e-5, "{:.6e}", exact_u(OUTER));
}

/// (spacing, bound on |u(9) error|, bound on the max-norm error, bound on |energy error|).
const SERIES: [(f64, f64, f64, f64); 3] = [
    (0.5, 3.7e-3, 6.1e-3, 2.9e-3),
    (0.25, 1.0e-3, 1.7e-3, 6.0e-4),
    (0.125, 3.0e-4, 6.1e-4, 1.9e-4),
];

#[test]
fn lame_thick_sphere_mfvm() {
    let mut rows = Vec::new();
    for &(h, b_point, b_max, b_energy) in &SERIES {
        let e = solve(h);
        println!(
            "thick sphere h = {h}: {} nodes, u(9) {:+.3e}, u(11) {:+.3e}, max {:.3e}, energy {:+.3e}",
            e.nodes, e.inner, e.outer, e.max, e.energy
        );
        assert!(e.inner.abs() < b_point && e.outer.abs() < b_point, "h = {h}: u(9), u(11)");
        assert!(e.max < b_max, "h = {h}: max-norm {:.3e} over {b_max:.1e}", e.max);
        assert!(e.energy.abs() < b_energy, "h = {h}: energy {:.3e}", e.energy);
        rows.push(vec![h, e.nodes as f64, e.inner, e.outer, e.max, e.energy]);
    }
    let hs: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    let col = |k: usize| rows.iter().map(|r| r[k].abs()).collect::<Vec<f64>>();
    let (point, max, energy) = (
        convergence_rate(&hs, &col(2)),
        convergence_rate(&hs, &col(4)),
        convergence_rate(&hs, &col(5)),
    );
    println!("thick sphere rates: u(9) {point:.2}, max norm {max:.2}, energy {energy:.2}");
    write_table("axisymmetric", "thick_sphere.csv", "h,nodes,u9,u11,max,energy", &rows);
    for (name, rate) in [("u(9)", point), ("max norm", max), ("energy", energy)] {
        assert!(rate > 1.6, "thick sphere {name} rate {rate:.2}");
    }
}
