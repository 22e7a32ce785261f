//! Two elastic spheres of revolution pressed together (docs/method.md §9.6, "A curved
//! target"): the candidates are rings on the upper sphere's arc, the target the lower sphere's
//! arc, each candidate paired with its closest point on that circle, the normal the target's
//! there.
//!
//! **Hertz** (Hertz 1882; Johnson, *Contact Mechanics* (1985), §4.2, eqs. 4.22–4.24): with
//! `1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂` and `1/R = 1/R₁ + 1/R₂`, for the axial force `F`
//! `a = (3FR/(4E*))^(1/3)` and `p₀ = 3F/(2πa²)`; `a`, `p₀` fitted from `p²` linear in `r²` over
//! the closed rings (as `axisymmetric_contact.rs`). The upper sphere `R₁ = 1`, `E₁ = 1`,
//! `ν₁ = 0.3`, its equatorial plane pushed down by 0.008; the lower `R₂ = 2`, `E₂ = 2`,
//! `ν₂ = 0.25`, its equatorial plane on a roller. `R = 2/3`, `a/R ≈ 0.11` (`a/R₁ ≈ 0.074`).
//! The approach is not compared (it includes both hemispheres' bulk compression).
//!
//! Measured by the CLI on the same file (docs/dev/axisymmetric.md, increment 7e; far spacing
//! 0.05, box `[0, 0.15]` by 0.03 around the contact): box spacing 0.01, 0.005, 0.0025 give
//! `a` +0.29 %, +0.42 %, +0.14 % and `p₀` −0.56 %, −0.44 %, −0.43 % against Hertz. The test
//! runs the box at 0.01 and asks for 2 % (the task's bound; Hertz's idealisation at
//! `a/R ≈ 0.11` and the far field's spacing leave about half a percent, which the refinement
//! above does not remove).

use super::common::*;
use mlpg_contact::Solution;
use mlpg_contact::problem::Problem;
use std::f64::consts::TAU;

const E1: f64 = 1.0;
const NU1: f64 = 0.3;
const R1: f64 = 1.0;
const E2: f64 = 2.0;
const NU2: f64 = 0.25;
const R2: f64 = 2.0;

/// The two hemispheres' sections with the box around the contact at spacing `h` (0.05
/// elsewhere), MFVM, `β = 0.5`.
fn spheres(h: f64) -> Problem {
    Problem::from_toml(&format!(
        r#"
        [discretisation]
        beta = 0.5
        [[body]]
        name = "upper"
        [body.geometry]
        kind = "curves"
        start = [0.0, 0.0]
        curves = [
            {{ name = "arc", to = [0.5, 0.1339745962155614], center = [0.0, {R1:?}] }},
            {{ name = "rim", to = [1.0, 1.0], center = [0.0, {R1:?}] }},
            {{ name = "top", to = [0.0, 1.0] }},
            {{ name = "axis", to = [0.0, 0.0] }},
        ]
        [body.nodes]
        spacing = 0.05
        [[body.nodes.refine]]
        x = [0.0, 0.15]
        y = [0.0, 0.03]
        spacing = {h:?}
        [body.material]
        young = {E1:?}
        poisson = {NU1:?}
        plane = "axisymmetric"
        [[body.boundary]]
        edge = "top"
        displacement = {{ y = -0.008 }}
        [[body]]
        name = "lower"
        [body.geometry]
        kind = "curves"
        start = [0.0, -2.0]
        curves = [
            {{ name = "bottom", to = [2.0, -2.0] }},
            {{ name = "rim", to = [1.0, -0.2679491924311228], center = [0.0, -{R2:?}] }},
            {{ name = "arc", to = [0.0, 0.0], center = [0.0, -{R2:?}] }},
            {{ name = "axis", to = [0.0, -2.0] }},
        ]
        [body.nodes]
        spacing = 0.05
        [[body.nodes.refine]]
        x = [0.0, 0.15]
        y = [-0.03, 0.0]
        spacing = {h:?}
        [body.material]
        young = {E2:?}
        poisson = {NU2:?}
        plane = "axisymmetric"
        [[body.boundary]]
        edge = "bottom"
        displacement = {{ y = 0.0 }}
        [contact]
        edge = "arc"
        target_edge = "arc"
        "#
    ))
    .unwrap()
}

/// Complementarity, both bodies' balance and the pair's (the rings' axial force per radian
/// leaves the upper body and enters the lower; each ring's target weights sum to its own
/// `1/2π`), then Hertz's `a` and `p₀` within 2 % (see the header).
#[test]
fn two_elastic_spheres_against_hertz() {
    let s: Solution = mlpg_contact::solve(&spheres(0.01)).unwrap();
    let c = s.contact.as_ref().unwrap();
    assert_lcp_residuals("spheres", &c.lcp.residuals, 1e-9);
    let lower = s.second_body.as_deref().expect("the lower sphere");
    assert!(s.equilibrium_error < 1e-8, "upper equilibrium {}", s.equilibrium_error);
    assert!(lower.equilibrium_error < 1e-8, "lower equilibrium {}", lower.equilibrium_error);
    let axial: f64 = c.candidates.normals.iter().zip(&c.lcp.z).map(|(n, f)| n[1] * f).sum();
    assert!(axial > 0.0, "the rings push the upper sphere up: {axial}");
    let scale = axial / TAU;
    let upper_balance = s.reaction_force[1] + axial / TAU;
    let lower_balance = lower.reaction_force[1] - axial / TAU;
    assert!(upper_balance.abs() < 1e-8 * scale, "upper balance {upper_balance}");
    assert!(lower_balance.abs() < 1e-8 * scale, "lower balance {lower_balance}");
    // Newton's third law ring by ring: opposite directions, equal weights.
    let target = c.target.as_ref().expect("the target's operator");
    for k in 0..c.candidates.len() {
        let (d1, d2) = (c.candidates.operator.direction(k), target.direction(k));
        assert!((d1[0] + d2[0]).abs() + (d1[1] + d2[1]).abs() == 0.0, "ring {k}: {d1:?} {d2:?}");
        let w1: f64 = c.candidates.operator.owners[k].iter().map(|o| o.1).sum();
        let w2: f64 = target.owners[k].iter().map(|o| o.1).sum();
        assert!((w1 - w2).abs() < 1e-14, "ring {k}: weights {w1} {w2}");
    }
    let e_star = 1.0 / ((1.0 - NU1 * NU1) / E1 + (1.0 - NU2 * NU2) / E2);
    let radius = 1.0 / (1.0 / R1 + 1.0 / R2);
    let a = (3.0 * axial * radius / (4.0 * e_star)).cbrt();
    let p0 = 3.0 * axial / (TAU * a * a);
    let (peak, fitted, closed) = hertz_fit(c);
    assert_eq!(c.onset.closed_intervals, 1);
    assert!(closed >= 6, "only {} closed rings", closed);
    let (ea, ep) = (fitted / a - 1.0, peak / p0 - 1.0);
    println!(
        "two spheres: F = {axial:.6e}  a/R = {:.4}  a {ea:+.3e}  p0 {ep:+.3e}  closed {}",
        a / radius,
        closed
    );
    assert!(ea.abs() < 0.02 && ep.abs() < 0.02, "a {ea:+.3e}, p0 {ep:+.3e}");
}
