//! A step's rigid obstacles moved or pressed by a force in a scene of several bodies and
//! pairs (docs/method.md §4.6): every rigid obstacle of every pair moves together, the pairs
//! between bodies do not move.
//!
//! **Problem.** Two elastic blocks `[0, 2] × [0, 1]` (E = 1000) and `[0, 2] × [1, 2]`
//! (E = 300), ν = 0.3, plane stress, rollers on their left edges, non-matching spacings; the
//! upper block's top edge fixed in y; the lower block on a rigid flat `y = 0` which a
//! `[[step]]` moves or presses up. The lower block is held in y by its two contacts alone
//! (docs/method.md §4.7): with a force-driven flat, two searches at once.
//!
//! **References and tolerances.**
//! - Frictionless, the stack is uniaxial: a flat moved up by `δ` puts the force
//!   `2 δ / (1/E₀ + 1/E₁)` through both interfaces, exactly for the MFVM (linear fields on
//!   any node set): 1e-8 relative.
//! - A flat pressed by `F` carries `F` through both interfaces (the lower block's and the
//!   flat's balance), with or without friction (the tangential forces are horizontal):
//!   1e-8 relative.
//! - The force search and the motion are one problem read two ways: the flat moved by the
//!   displacement the force search found carries that force (1e-8; one increment each, so
//!   that the frictional answers are the same single LCP).
//! - Lemke's condensed path and the active set's sparse path answer the same LCPs: normal and
//!   tangential forces equal to 1e-8 of the largest, a slanted motion (whose tangential part
//!   moves the stick targets of the flat's candidates) included; `|T| ≤ μP` at every
//!   candidate, each body's equilibrium ≤ 1e-8.

use mlpg_contact::Solution;
use mlpg_contact::problem::Problem;

/// The two-block stack on a rigid flat, with `keys` added to both pairs and `step` as the
/// `[[step]]` table's keys.
fn stack(keys: &str, step: &str) -> Problem {
    let text = format!(
        r#"[discretisation]
support_factor = 2.0
[[body]]
name = "lower"
geometry = {{ kind = "rectangle", x = [0.0, 2.0], y = [0.0, 1.0] }}
nodes = {{ spacing = 0.1 }}
material = {{ young = 1000.0, poisson = 0.3, plane = "stress" }}
boundary = [{{ edge = "left", displacement = {{ x = 0.0 }} }}]
[[body]]
name = "upper"
geometry = {{ kind = "rectangle", x = [0.0, 2.0], y = [1.0, 2.0] }}
nodes = {{ spacing = 0.125 }}
material = {{ young = 300.0, poisson = 0.3, plane = "stress" }}
boundary = [{{ edge = "left", displacement = {{ x = 0.0 }} }}, {{ edge = "top", displacement = {{ y = 0.0 }} }}]
[[contact]]
body = "lower"
edge = "bottom"
obstacle_point = [0.0, 0.0]
obstacle_normal = [0.0, 1.0]
{keys}
[[contact]]
body = "upper"
edge = "bottom"
target_body = "lower"
target_edge = "top"
{keys}
[[step]]
{step}
"#
    );
    Problem::from_toml(&text).unwrap()
}

fn solve(keys: &str, step: &str) -> Solution {
    mlpg_contact::solve(&stack(keys, step)).unwrap()
}

/// Both pairs' normal and tangential forces, candidate by candidate.
fn forces(s: &Solution) -> (Vec<f64>, Vec<f64>) {
    let ms = s.multibody().unwrap();
    let normal = ms.pairs.iter().flat_map(|c| c.lcp.z.iter().copied()).collect();
    let tangential = ms
        .pairs
        .iter()
        .flat_map(|c| {
            c.friction.as_ref().map_or(vec![0.0; c.lcp.z.len()], |f| f.step.tangential.clone())
        })
        .collect();
    (normal, tangential)
}

fn totals(s: &Solution) -> Vec<f64> {
    s.multibody().unwrap().pairs.iter().map(|c| c.total_force).collect()
}

fn assert_totals(label: &str, s: &Solution, exact: f64) {
    for f in totals(s) {
        assert!((f - exact).abs() <= 1e-8 * exact, "{label}: {f} against {exact}");
    }
}

/// `|T| ≤ μP`, `P ≥ 0` and each body's equilibrium.
fn assert_checks(label: &str, s: &Solution, mu: f64) {
    let ms = s.multibody().unwrap();
    for c in ms.pairs {
        let scale = c.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        let t = c.friction.as_ref().map_or(vec![0.0; c.lcp.z.len()], |f| f.step.tangential.clone());
        for (p, t) in c.lcp.z.iter().zip(&t) {
            assert!(
                *p >= -1e-12 * scale && t.abs() <= mu * p + 1e-12 * scale,
                "{label}: P {p}, T {t}"
            );
        }
    }
    for body in std::iter::once(s).chain(ms.bodies.iter()) {
        assert!(
            body.equilibrium_error <= 1e-8,
            "{label}: equilibrium {:e}",
            body.equilibrium_error
        );
    }
}

/// Lemke's and the active set's forces agree to 1e-8 of the largest.
fn assert_same(label: &str, a: &Solution, b: &Solution) {
    let ((pa, ta), (pb, tb)) = (forces(a), forces(b));
    let scale = pa.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    for (x, y) in pa.iter().zip(&pb).chain(ta.iter().zip(&tb)) {
        assert!((x - y).abs() <= 1e-8 * scale, "{label}: Lemke {x} against the active set {y}");
    }
}

#[test]
fn a_flat_moved_under_a_stack_carries_the_uniaxial_force() {
    let exact = 2.0 * 0.01 / (1.0 / 1000.0 + 1.0 / 300.0);
    let step = "increments = 2\nobstacle_displacement = [0.0, 0.01]";
    let lemke = solve("solver = \"lemke\"", step);
    let active = solve("solver = \"active_set\"", step);
    println!("moved by 0.01: {:?} (exact {exact})", totals(&lemke));
    assert_totals("Lemke", &lemke, exact);
    assert_totals("active set", &active, exact);
    assert_same("moved", &lemke, &active);
}

#[test]
fn a_flat_pressed_by_a_force_moves_as_far_as_the_motion_that_carries_it() {
    let keys = |solver: &str| format!("friction = 0.3\nsolver = \"{solver}\"");
    let pressed = solve(&keys("lemke"), "obstacle_force = [0.0, 20.0]");
    assert_totals("pressed", &pressed, 20.0);
    assert_checks("pressed", &pressed, 0.3);
    let active = solve(&keys("active_set"), "obstacle_force = [0.0, 20.0]");
    assert_totals("pressed, active set", &active, 20.0);
    assert_same("pressed", &pressed, &active);
    let found = pressed.multibody().unwrap().pairs[0].load_driven.clone().unwrap();
    let d = found.displacement;
    let moved = solve(&keys("lemke"), &format!("obstacle_displacement = [{:?}, {:?}]", d[0], d[1]));
    println!("pressed by 20: displaced by {d:?}; moved as far: {:?}", totals(&moved));
    assert_totals("moved as far", &moved, 20.0);
    assert!(moved.multibody().unwrap().pairs[0].load_driven.is_none());
}

#[test]
fn a_slanted_motion_with_friction_is_the_same_on_both_solvers() {
    let step = "increments = 2\nobstacle_displacement = [0.003, 0.01]";
    let lemke = solve("friction = 0.3\nsolver = \"lemke\"", step);
    let active = solve("friction = 0.3\nsolver = \"active_set\"", step);
    assert_checks("slanted, Lemke", &lemke, 0.3);
    assert_checks("slanted, active set", &active, 0.3);
    assert_same("slanted", &lemke, &active);
    // The flat's tangential motion drags the lower block: tangential forces on its pair.
    let t = lemke.multibody().unwrap().pairs[0].friction.as_ref().unwrap().total_force;
    println!("slanted motion: normal {:?}, tangential {t}", totals(&lemke));
    assert!(t.abs() > 1e-2, "tangential force {t}");
}
