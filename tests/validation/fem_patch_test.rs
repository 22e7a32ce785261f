//! FE oracle: the Q2 discretisation reproduces a linear displacement field
//! exactly, with the field imposed on the whole boundary, and with the constant-stress
//! tractions of that field on three edges (the fourth prescribed). Also global equilibrium
//! (applied load + reactions = 0) under a body force, a linear traction and a pressure, plane
//! strain.

use super::common::*;
use mlpg_contact::geometry::{Domain, Point};
use mlpg_contact::material::{Material, PlaneState};
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{BodyForce, ComponentCondition, EdgeCondition, Field, Method, Problem};
use std::sync::Arc;

/// Relative max-norm error bound: round-off with a margin.
const TOLERANCE: f64 = 1e-10;
const YOUNG: f64 = 1000.0;
const POISSON: f64 = 0.3;

fn exact(p: Point) -> [f64; 2] {
    [1e-3 * (1.0 + 2.0 * p[0] - 3.0 * p[1]), 1e-3 * (-0.5 + 1.5 * p[0] + 0.7 * p[1])]
}

/// Plane-stress stress of `exact`: `ε = 1e-3 (2, 0.7, −3 + 1.5)`.
fn exact_stress() -> [f64; 3] {
    let e = [2e-3, 0.7e-3, -1.5e-3];
    let c = YOUNG / (1.0 - POISSON * POISSON);
    [c * (e[0] + POISSON * e[1]), c * (e[1] + POISSON * e[0]), c * (1.0 - POISSON) / 2.0 * e[2]]
}

fn fem(mut p: Problem) -> Problem {
    p.discretisation.method = Method::Fem;
    p
}

fn max_error(problem: &Problem) -> (f64, f64) {
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(problem, &mut silent).unwrap();
    let (model, _, s) = mlpg_contact::solve_model(problem, model, None, &mut silent).unwrap();
    let scale = 1e-3 * 6.0;
    let err = model
        .nodes
        .points
        .iter()
        .zip(&s.displacement)
        .map(|(p, u)| {
            let e = exact(*p);
            (u[0] - e[0]).abs().max((u[1] - e[1]).abs()) / scale
        })
        .fold(0.0, f64::max);
    let se = exact_stress();
    let stress_err = s
        .stress
        .iter()
        .map(|t| (0..3).map(|c| (t[c] - se[c]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max)
        / se.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    (err, stress_err)
}

#[test]
fn fem_patch_test_dirichlet() {
    let domain = Domain::rectangle([0.0, 2.0], [0.0, 2.0]).unwrap();
    let mut problem =
        fem(base_problem(domain, 0.4, Layout::Structured, plane_stress(YOUNG, POISSON)));
    problem.boundary = vec![displacement(Arc::new(exact)); 4];
    let (err, stress_err) = max_error(&problem);
    println!("FE patch test (Dirichlet): displacement {err:.3e}, stress {stress_err:.3e}");
    assert!(err < TOLERANCE, "displacement error {err:.3e}");
    assert!(stress_err < TOLERANCE, "stress error {stress_err:.3e}");
}

#[test]
fn fem_patch_test_tractions() {
    let domain = Domain::rectangle([0.0, 3.0], [0.0, 2.0]).unwrap();
    let mut problem =
        fem(base_problem(domain, 0.5, Layout::Structured, plane_stress(YOUNG, POISSON)));
    let s = exact_stress();
    // Edges: bottom n = (0, −1), right (1, 0), top (0, 1); the left edge prescribed.
    let t = |n: [f64; 2]| -> VectorField {
        Arc::new(move |_| [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]])
    };
    problem.boundary[0] = traction(t([0.0, -1.0]));
    problem.boundary[1] = traction(t([1.0, 0.0]));
    problem.boundary[2] = traction(t([0.0, 1.0]));
    problem.boundary[3] = displacement(Arc::new(exact));
    let (err, stress_err) = max_error(&problem);
    println!("FE patch test (tractions): displacement {err:.3e}, stress {stress_err:.3e}");
    assert!(err < TOLERANCE, "displacement error {err:.3e}");
    assert!(stress_err < TOLERANCE, "stress error {stress_err:.3e}");
}

#[test]
fn fem_applied_load_plus_reactions_vanish() {
    let domain = Domain::rectangle([0.0, 10.0], [0.0, 2.0]).unwrap();
    let material = Material { young: 2.0e5, poisson: 0.3, plane: PlaneState::Strain };
    let mut problem = fem(base_problem(domain, 0.25, Layout::Structured, material));
    problem.body_force = Some(BodyForce::constant([0.5, -2.0]));
    problem.boundary[0] = EdgeCondition::Components([
        ComponentCondition::Traction(Field::Linear { start: 1.0, end: -2.0 }),
        ComponentCondition::Traction(Field::Constant(0.0)),
    ]);
    problem.boundary[1] = EdgeCondition::Pressure(Field::Constant(3.0));
    // Left: clamped (both components prescribed, one as a linear field).
    problem.boundary[3] = EdgeCondition::Components([
        ComponentCondition::Displacement(Field::Constant(0.0)),
        ComponentCondition::Displacement(Field::Linear { start: 0.0, end: 0.0 }),
    ]);
    let s = mlpg_contact::solve(&problem).unwrap();
    let expected = [10.0 - 5.0 - 6.0, -40.0];
    let f = s.applied_force;
    assert!((f[0] - expected[0]).abs() < 1e-12 * 40.0, "applied {f:?}");
    assert!((f[1] - expected[1]).abs() < 1e-12 * 40.0, "applied {f:?}");
    println!(
        "FE equilibrium error {:.3e}, residual {:.3e}",
        s.equilibrium_error, s.relative_residual
    );
    assert!(s.equilibrium_error < 1e-9, "equilibrium error {:.3e}", s.equilibrium_error);
    // Observed 5.8e-11 (plane strain, 40 × 8 elements; the eliminated K has cond ~1e8).
    assert!(s.relative_residual < 1e-9, "residual {:.3e}", s.relative_residual);
}
