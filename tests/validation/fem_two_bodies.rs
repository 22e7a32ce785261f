//! FE oracle, two elastic bodies (the setting of `two_bodies.rs`): two blocks pressed
//! together, exact solution uniaxial stress with uniform contact pressure `p = E δ / (H_1 + H_2)`.
//! The FE target reads the gap at the closest point of the other block's edge and spreads
//! the reaction over the candidate's tributary segment (`fem::target_operator`), so a uniform
//! pressure loads the target consistently: the linear field is reproduced to round-off on
//! matching and non-matching meshes (a contact patch test), with both bodies in equilibrium.

use super::common::*;
use mlpg_contact::contact::{ContactSpec, ContactTarget};
use mlpg_contact::geometry::Domain;
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{ComponentCondition, EdgeCondition, Field, Method, Problem};

const YOUNG: f64 = 1000.0;
const PRESS: f64 = 0.01;

fn block(y: [f64; 2], h: f64, top: bool) -> Problem {
    let domain = Domain::rectangle([0.0, 2.0], y).unwrap();
    let mut p = base_problem(domain, h, Layout::Structured, plane_stress(YOUNG, 0.3));
    p.discretisation.method = Method::Fem;
    let free = || ComponentCondition::Traction(Field::Constant(0.0));
    let fixed = |v: f64| ComponentCondition::Displacement(Field::Constant(v));
    p.boundary[3] = EdgeCondition::Components([fixed(0.0), free()]);
    let (edge, v) = if top { (2, -PRESS) } else { (0, 0.0) };
    p.boundary[edge] = EdgeCondition::Components([free(), fixed(v)]);
    p
}

/// The two FE blocks at mesh spacings `h_upper` and `h_lower`.
pub fn fem_two_blocks(h_upper: f64, h_lower: f64) -> Problem {
    let mut upper = block([1.0, 2.0], h_upper, true);
    let mut lower = block([0.0, 1.0], h_lower, false);
    lower.name = "lower".into();
    upper.set_contact(ContactSpec {
        edge: 0,
        target: ContactTarget::Body { edge: 2 },
        gap_tolerance: None,
        allow_indefinite: false,
        condensation: Default::default(),
        friction: 0.0,
        solver: Default::default(),
        interference: 0.0,
    });
    upper.with_second_body(lower)
}

/// (max |p − p_exact| / p_exact, |ΣP − exact| / exact).
fn run(h_upper: f64, h_lower: f64) -> (f64, f64) {
    let upper = fem_two_blocks(h_upper, h_lower);
    let s = mlpg_contact::solve(&upper).unwrap();
    let c = s.contact().unwrap();
    assert!(c.lcp.residuals.max_violation() < 1e-9);
    assert!(s.equilibrium_error < 1e-9, "upper body equilibrium {}", s.equilibrium_error);
    let s2 = s.body(1).unwrap();
    assert!(s2.equilibrium_error < 1e-9, "lower body equilibrium {}", s2.equilibrium_error);
    let exact = YOUNG * PRESS / 2.0;
    let pointwise = c.pressure.iter().map(|p| (p - exact).abs()).fold(0.0, f64::max) / exact;
    let total = (c.total_force - 2.0 * exact).abs() / (2.0 * exact);
    println!(
        "FE two blocks h = {h_upper}/{h_lower}: pressure error {pointwise:.2e}, total {total:.2e}"
    );
    (pointwise, total)
}

#[test]
fn fem_two_blocks_matching_meshes_are_exact() {
    let (pointwise, total) = run(0.25, 0.25);
    assert!(pointwise < 1e-10 && total < 1e-10, "{pointwise:.3e} {total:.3e}");
}

#[test]
fn fem_two_blocks_non_matching_meshes_are_exact() {
    // With the reaction at the closest point only (node-to-segment) this case had 14 %
    // pointwise and 2.4e-4 total error; the tributary spreading removes it.
    let (pointwise, total) = run(0.1, 0.125);
    assert!(pointwise < 1e-10 && total < 1e-10, "{pointwise:.3e} {total:.3e}");
}
