//! Global equilibrium (docs/method.md §3.5–3.6): with tiling cells interior-face contributions
//! cancel pairwise, so the applied load plus the recovered reactions vanish to round-off.
//! Loads: a body force, a linearly varying traction and a pressure, on jittered nodes, plane
//! strain. Also checks that the applied load equals its closed-form total (the load rules
//! are exact for these polynomial loads).

use super::common::*;
use mlpg_contact::geometry::Domain;
use mlpg_contact::material::{Material, PlaneState};
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{BodyForce, ComponentCondition, EdgeCondition, Field};
use std::sync::Arc;

/// Relative tolerance: round-off of sums over ~10⁴ terms.
const TOLERANCE: f64 = 1e-9;

#[test]
fn applied_load_plus_reactions_vanish() {
    let domain = Domain::rectangle([0.0, 10.0], [0.0, 2.0]).unwrap();
    let material = Material { young: 2.0e5, poisson: 0.3, plane: PlaneState::Strain };
    let mut problem =
        base_problem(domain, 0.1, Layout::Jittered { amplitude: 0.3, seed: 9 }, material);
    problem.body_force = Some(BodyForce::constant([0.5, -2.0]));
    // bottom: linear shear traction; right: pressure 3; top: free; left: clamped.
    problem.boundary[0] = EdgeCondition::Components([
        ComponentCondition::Traction(Field::Linear { start: 1.0, end: -2.0 }),
        ComponentCondition::Traction(Field::Constant(0.0)),
    ]);
    problem.boundary[1] = EdgeCondition::Pressure(Field::Constant(3.0));
    problem.boundary[3] = displacement(Arc::new(|_| [0.0, 0.0]));
    let s = mlpg_contact::solve(&problem).unwrap();
    // Σf: body 20·(0.5, −2) + bottom ∫(1 − 3t)·10 dt = −5 in x + pressure −3·2 in x.
    let expected = [10.0 - 5.0 - 6.0, -40.0];
    let f = s.applied_force;
    assert!((f[0] - expected[0]).abs() < 1e-12 * 40.0, "applied {f:?}");
    assert!((f[1] - expected[1]).abs() < 1e-12 * 40.0, "applied {f:?}");
    println!("equilibrium error {:.3e}, residual {:.3e}", s.equilibrium_error, s.relative_residual);
    assert!(s.equilibrium_error < TOLERANCE, "equilibrium error {:.3e}", s.equilibrium_error);
    let r = s.reaction_force;
    assert!((r[0] + f[0]).abs() < TOLERANCE * 40.0 && (r[1] + f[1]).abs() < TOLERANCE * 40.0);
}
