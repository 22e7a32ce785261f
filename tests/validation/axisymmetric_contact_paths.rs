//! Axisymmetric contact along load paths (docs/method.md §9.6, §8, §4.6): the rings' forces
//! through load steps, an obstacle pressed by a force, a rigid sphere (a circle obstacle) and
//! friction, on the Hertz sphere of `axisymmetric_contact.rs` (the quarter-disk section
//! `R = 1` about `(0, 1)`, the MFVM with a box refined to `h` around the contact).
//!
//! 1. **Frictionless steps equal one step**: the top pushed down by 0.015 in two steps (4 and
//!    2 increments) gives the one-step answer (the frictionless problem has no path).
//! 2. **μ → 0 is frictionless**: `μ = 1e-12` in 3 increments equals the frictionless run.
//! 3. **A rigid flat pressed by a force**: the top held, the flat pushed up by
//!    `obstacle_force = [0, F]`, `F` the total force over the circumference: the rings carry
//!    `F`, the top's reaction per radian is `−F/2π`, and the displacement-driven run at the
//!    displacement found gives the same forces.
//! 4. **A rigid sphere pressed into a cylinder** (the circle obstacle `R = 1` centred on the
//!    axis, a block `[0, 2] × [−2, 0]` clamped at its bottom, pushed in by 0.015): Hertz's
//!    `a`, `p₀` for the computed force within 2 % (the block's finite size: `a` is 1/16 of its
//!    radius and depth), Lemke and the active set alike.
//! 5. **Friction** `μ = 0.3`, the sphere pressed in 6 increments: Coulomb's cone holds on every
//!    ring (`|T| ≤ μF`), each increment's complementarity and balance pass, and every loaded
//!    increment has a central stick zone inside a slip annulus (`0 < c < a`, `c` and `a` the
//!    outermost sticking and closed candidates). With 6 equal increments `c/a` climbs (0.50,
//!    0.73, 0.79, 0.81, 0.83, 0.85) at every box spacing down to 0.0025: the climb is the
//!    load path's discretisation (each increment is solved as one step, the first from no
//!    contact), not the nodes' (docs/dev/axisymmetric.md, 7b).
//! 6. **Spence's self-similar stick zone**: in 20 geometric increments (each adds the same
//!    fraction of the load) `c/a` stays within one candidate spacing `h/a` of its mean
//!    0.882 from the second increment on (box 0.005; observed at most 0.63 `h/a`).
//! 7. **Held by the contact alone** (docs/method.md §4.7): the sphere pressed by a pressure `p`
//!    on its top with no axial displacement condition; its axial translation, pinned, is
//!    found so that the rings carry the load: total force `p π R²` (the load per radian times
//!    2π; a body held by contact balances its load through the contact alone) to 1e-10, with
//!    complementarity and the body's balance; Lemke and the active set alike (forces to 1e-8
//!    of the largest, the same translation down onto the flat to 1e-8). The same by finite
//!    elements: the FE ball of `problems/ball_impact_axisymmetric_fem.toml` pressed by a
//!    traction on its cap carries its load times 2π.

use super::axisymmetric_contact::SPHERE_SECTION;
use super::common::*;
use mlpg_contact::Solution;
use mlpg_contact::lcp::ContactState;
use mlpg_contact::problem::Problem;
use std::f64::consts::TAU;

const SPACING: f64 = 0.01;

/// The Hertz sphere with `top` the top edge's declared condition, `contact` extra keys of
/// `[contact]` and `tail` further tables (steps).
fn sphere(top: &str, contact: &str, tail: &str) -> Problem {
    sphere_at(SPACING, top, contact, tail)
}

/// [`sphere`] with the box around the contact at `spacing` (`examples/studies/spence.rs`).
pub(super) fn sphere_at(spacing: f64, top: &str, contact: &str, tail: &str) -> Problem {
    Problem::from_toml(&format!(
        r#"
        {SPHERE_SECTION}
        [nodes]
        spacing = 0.05
        [[nodes.refine]]
        x = [0.0, 0.2]
        y = [0.0, 0.05]
        spacing = {spacing}
        [material]
        young = 1.0
        poisson = 0.3
        plane = "axisymmetric"
        [discretisation]
        beta = 0.5
        [[boundary]]
        edge = "top"
        displacement = {{ y = {top} }}
        [contact]
        edge = "arc"
        obstacle_point = [0.0, 0.0]
        obstacle_normal = [0.0, 1.0]
        {contact}
        {tail}
        "#
    ))
    .unwrap()
}

fn solve(p: &Problem) -> Solution {
    mlpg_contact::solve(p).unwrap()
}

/// The largest difference of two force vectors over the largest force.
fn difference(a: &Solution, b: &Solution) -> f64 {
    let (za, zb) = (&a.contact().unwrap().lcp.z, &b.contact().unwrap().lcp.z);
    assert_eq!(za.len(), zb.len());
    let scale = za.iter().copied().fold(0.0, f64::max);
    za.iter().zip(zb).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

#[test]
fn frictionless_steps_and_vanishing_friction_equal_one_step() {
    let one = solve(&sphere("-0.015", "", ""));
    let steps = solve(&sphere(
        "0.0",
        "",
        r#"
        [[step]]
        increments = 4
        boundary = [{ edge = "top", displacement = { y = -0.0075 } }]
        [[step]]
        increments = 2
        boundary = [{ edge = "top", displacement = { y = -0.015 } }]"#,
    ));
    let tiny = solve(&sphere(
        "0.0",
        "friction = 1e-12",
        r#"
        [[step]]
        increments = 3
        boundary = [{ edge = "top", displacement = { y = -0.015 } }]"#,
    ));
    for (label, s) in [("steps", &steps), ("μ = 1e-12", &tiny)] {
        let d = difference(&one, s);
        println!("axisymmetric sphere: {label} against one step {d:.2e}");
        assert!(d < 1e-10, "{label}: {d:.3e}");
        let c = s.contact().unwrap();
        assert_lcp_residuals(label, &c.lcp.residuals, 1e-9);
        assert!(s.equilibrium_error < 1e-8, "{label}: {}", s.equilibrium_error);
    }
}

#[test]
fn a_rigid_flat_pressed_by_a_force_carries_it_over_the_rings() {
    let force = 2.88e-3;
    let by_force =
        solve(&sphere("0.0", "", &format!("[[step]]\nobstacle_force = [0.0, {force:?}]")));
    let c = by_force.contact().unwrap();
    assert!((c.total_force - force).abs() < 1e-10 * force, "{}", c.total_force);
    let per_radian = force / TAU;
    let reaction = by_force.reaction_force[1];
    assert!((reaction + per_radian).abs() < 1e-8 * per_radian, "{reaction}");
    let s = c.load_driven.as_ref().unwrap().displacement;
    println!("axisymmetric sphere pressed by {force:e}: the flat moves by {s:?}");
    let by_displacement =
        solve(&sphere("0.0", "", &format!("[[step]]\nobstacle_displacement = [0.0, {:?}]", s[1])));
    let d = difference(&by_force, &by_displacement);
    assert!(d < 1e-8, "force- and displacement-driven runs differ by {d:.3e}");
}

/// A rigid sphere (a circle obstacle centred on the axis) pressed into a cylinder block.
fn indenter(spacing: f64, solver: &str) -> Problem {
    Problem::from_toml(&format!(
        r#"
        [geometry]
        kind = "rectangle"
        x = [0.0, 2.0]
        y = [-2.0, 0.0]
        [nodes]
        spacing = 0.1
        [[nodes.refine]]
        x = [0.0, 0.25]
        y = [-0.15, 0.0]
        spacing = {spacing}
        [material]
        young = 1.0
        poisson = 0.3
        plane = "axisymmetric"
        [discretisation]
        beta = 0.5
        [[boundary]]
        edge = "bottom"
        displacement = {{ x = 0.0, y = 0.0 }}
        [[obstacle]]
        name = "sphere"
        kind = "circle"
        centre = [0.0, 1.0]
        radius = 1.0
        [contact]
        edge = "top"
        target = "sphere"
        solver = "{solver}"
        [[step]]
        obstacle_displacement = [0.0, -0.015]
        "#
    ))
    .unwrap()
}

#[test]
fn a_rigid_sphere_pressed_into_a_cylinder_meets_hertz() {
    let lemke = solve(&indenter(0.005, "lemke"));
    let active = solve(&indenter(0.005, "active_set"));
    let d = difference(&lemke, &active);
    assert!(d < 1e-9, "active set against Lemke {d:.3e}");
    let out = super::axisymmetric_contact::measure("rigid sphere h = 0.005", &lemke);
    let c = lemke.contact().unwrap();
    let axial = c.candidates.normals.iter().zip(&c.lcp.z).map(|(n, f)| n[1] * f).sum::<f64>();
    println!("rigid sphere: total {:.6e}, axial {axial:.6e}", c.total_force);
    assert!(out.radius_error.abs() < 0.02, "a error {}", out.radius_error);
    assert!(out.peak_error.abs() < 0.02, "p0 error {}", out.peak_error);
}

#[test]
fn friction_keeps_a_central_stick_zone_inside_a_slip_annulus() {
    let mu = 0.3;
    let mut p = sphere(
        "0.0",
        &format!("friction = {mu:?}"),
        r#"
        [[step]]
        increments = 6
        boundary = [{ edge = "top", displacement = { y = -0.015 } }]"#,
    );
    p.write_steps = true;
    let ratios = stick_ratios(&solve(&p), mu);
    for (k, &(ratio, a)) in ratios.iter().enumerate() {
        println!("axisymmetric sphere μ = {mu}: increment {} a {a:.4} c/a {ratio:.3}", k + 1);
    }
    assert_eq!(ratios.len(), 6);
    assert!(ratios.iter().all(|&(_, a)| a > 0.0), "an increment without contact: {ratios:?}");
    assert!(ratios.iter().all(|&(q, _)| q > 0.0 && q < 1.0), "c/a {ratios:?}");
}

/// `c/a` and `a` of each increment: `a` the outermost closed and `c` the outermost sticking
/// candidate's radius, after checking Coulomb's cone on every ring.
fn stick_ratios(s: &Solution, mu: f64) -> Vec<(f64, f64)> {
    let c = s.contact().unwrap();
    let f = c.friction.as_ref().unwrap();
    assert!(f.increments.iter().all(|r| r.complementarity < 1e-9 && r.equilibrium_error < 1e-8));
    let r = |k: usize| c.candidates.points[k][0];
    f.snapshots
        .iter()
        .map(|snap| {
            for (k, (t, n)) in snap.tangential.iter().zip(&snap.normal).enumerate() {
                assert!(t.abs() <= mu * n * (1.0 + 1e-9) + 1e-15, "ring {k}: |T| {t:e} > μF {n:e}");
            }
            let outer = |pick: &dyn Fn(ContactState) -> bool| {
                (0..snap.state.len()).filter(|&k| pick(snap.state[k])).map(r).fold(0.0, f64::max)
            };
            let a = outer(&|s| s != ContactState::Open);
            (outer(&|s| s == ContactState::Stick) / a, a)
        })
        .collect()
}

/// Spence's self-similarity: pressed in 20 geometric increments (the top's displacement
/// `0.015 q^(k − 20)`, `q = 1.1`, one `[[step]]` each, so every increment adds the same
/// fraction of the load), `c/a` is the same at every increment after the first (a one-step
/// problem from no contact, `c/a` = 0.5) to within one candidate spacing `h/a` of the mean.
/// With equal increments it is not: the first ones are large fractions of the load, and
/// `c/a` climbs from 0.5 (docs/dev/axisymmetric.md, 7b; `examples/studies/spence.rs`).
#[test]
fn the_stick_zone_is_self_similar_under_geometric_increments() {
    let (mu, q, n, h) = (0.3, 1.1_f64, 20, 0.005);
    let steps: String = (1..=n)
        .map(|k| {
            let top = -0.015 * q.powi(k - n);
            format!(
                "[[step]]\nboundary = [{{ edge = \"top\", displacement = {{ y = {top:?} }} }}]\n"
            )
        })
        .collect();
    let mut p = sphere_at(h, "0.0", &format!("friction = {mu:?}"), &steps);
    p.write_steps = true;
    let ratios = stick_ratios(&solve(&p), mu);
    assert_eq!(ratios.len(), n as usize);
    let later = &ratios[1..];
    let mean = later.iter().map(|r| r.0).sum::<f64>() / later.len() as f64;
    for (k, &(ratio, a)) in ratios.iter().enumerate() {
        println!(
            "axisymmetric sphere μ = {mu}, geometric increment {}: a {a:.5} c/a {ratio:.3} (c/a − mean)/(h/a) {:+.2}",
            k + 1,
            (ratio - mean) / (h / a)
        );
    }
    println!("mean c/a over increments 2–{n}: {mean:.4}");
    assert!(mean > 0.5 && mean < 1.0, "mean c/a {mean}");
    for (k, &(ratio, a)) in later.iter().enumerate() {
        assert!(
            (ratio - mean).abs() <= h / a,
            "increment {}: c/a {ratio:.3}, mean {mean:.3}",
            k + 2
        );
    }
}

/// The Hertz sphere pressed by `pressure` on its top (every node of the top free), the box
/// at 0.02, by `solver`: the contact alone holds its axial translation.
fn sphere_pressed(pressure: f64, solver: &str) -> Problem {
    Problem::from_toml(&format!(
        r#"
        {SPHERE_SECTION}
        [nodes]
        spacing = 0.05
        [[nodes.refine]]
        x = [0.0, 0.2]
        y = [0.0, 0.05]
        spacing = 0.02
        [material]
        young = 1.0
        poisson = 0.3
        plane = "axisymmetric"
        [discretisation]
        beta = 0.5
        [[boundary]]
        edge = "top"
        pressure = {pressure:?}
        [contact]
        edge = "arc"
        obstacle_point = [0.0, 0.0]
        obstacle_normal = [0.0, 1.0]
        solver = "{solver}"
        "#
    ))
    .unwrap()
}

/// The checks of a body held along the axis by the contact alone, solved by Lemke and by the
/// active set (`runs`, `label` naming the body): the rings carry `total` (each run's expected
/// total force) to 1e-10, complementarity and the body's balance hold, both systems give the
/// same forces (1e-8) and the same translation down onto the flat (1e-8).
fn check_held(label: &str, make: impl Fn(&str) -> Problem, total: impl Fn(&Solution) -> f64) {
    let runs: Vec<Solution> = ["lemke", "active_set"].iter().map(|s| solve(&make(s))).collect();
    for (solver, s) in ["lemke", "active_set"].iter().zip(&runs) {
        let c = s.contact().unwrap();
        let mode = c.rigid_mode.as_ref().expect("the axial translation is held by the contact");
        let total = total(s);
        println!(
            "{label} held by contact ({solver}): total force {:.12e} against {total:.12e}, translation {:?}",
            c.total_force, mode.translation
        );
        assert!((c.total_force - total).abs() <= 1e-10 * total, "{solver}: {}", c.total_force);
        assert_lcp_residuals(solver, &c.lcp.residuals, 1e-9);
        assert!(s.equilibrium_error < 1e-8, "{solver}: {}", s.equilibrium_error);
    }
    let d = difference(&runs[0], &runs[1]);
    assert!(d < 1e-8, "Lemke against the active set: {d:.3e}");
    let t = runs.iter().map(|s| s.contact().unwrap().rigid_mode.as_ref().unwrap().translation[1]);
    let t: Vec<f64> = t.collect();
    assert!(t[0] < 0.0 && (t[0] - t[1]).abs() <= 1e-8 * t[0].abs(), "translations {t:?}");
}

#[test]
fn a_sphere_held_by_the_contact_alone_carries_its_load() {
    let p = 1e-3;
    // p π R² (R = 1).
    check_held("sphere", |s| sphere_pressed(p, s), |_| p * std::f64::consts::PI);
}

/// The FE ball (`problems/ball_impact_axisymmetric_fem.msh`, Q9, R = 10 mm) with a traction
/// `1e6` down on its cap and no axial condition, on a rigid flat, by `solver`.
fn fe_ball_pressed(solver: &str) -> Problem {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mesh = root.join("problems/ball_impact_axisymmetric_fem.msh");
    Problem::from_toml(&format!(
        r#"
        [geometry]
        kind = "gmsh"
        file = "{}"
        surface = "ball"
        [nodes]
        from = "mesh"
        [material]
        young = 210e9
        poisson = 0.3
        plane = "axisymmetric"
        [discretisation]
        method = "fem"
        [[boundary]]
        edge = "cap"
        traction = {{ y = -1e6 }}
        [contact]
        edge = "contact"
        obstacle_point = [0.0, -1e-6]
        obstacle_normal = [0.0, 1.0]
        solver = "{solver}"
        "#,
        mesh.display()
    ))
    .unwrap()
}

#[test]
fn an_fe_ball_held_by_the_contact_alone_carries_its_load() {
    // The load per radian (the cap's traction weighted by r) times 2π.
    check_held("FE ball", fe_ball_pressed, |s| -TAU * s.applied_force[1]);
}
