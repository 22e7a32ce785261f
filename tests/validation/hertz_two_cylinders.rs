//! Two elastic cylinders in plane strain pressed together along their length (docs/method.md
//! §4.3 and §9.6, "A curved target"): the candidates are the upper half-disk's arc, the target
//! the lower half-disk's arc, each candidate paired with its closest point on the lower
//! circle, the normal the bisector of the two circles' normals there
//! (`contact::TargetEdge::bisector`).
//!
//! **Hertz, two cylinders** (Johnson, *Contact Mechanics* (1985), §4.2(b), eqs. 4.43–4.45):
//! with `1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂` and `1/R = 1/R₁ + 1/R₂`, for the force per unit
//! length `P` the half-width is `b = √(4PR/(πE*))` and the peak pressure `p₀ = 2P/(πb)`;
//! `b`, `p₀` fitted from `p²` linear in `x²` over the closed candidates. The upper half-disk
//! `R₁ = 1` (`E₁ = 1`, `ν₁ = 0.3`), its flat side pushed down by 0.005 (and held along `x`);
//! the lower `R₂ = 2` (`E₂ = 2`, `ν₂ = 0.25`), its flat side fixed. `R = 2/3`, `b/R ≈ 0.06`.
//! The approach is not compared (in plane it depends on the bodies' size).
//!
//! Measured by the CLI on the same problem (docs/dev/axisymmetric.md, increment 7e; far
//! spacing 0.05, box `[−0.15, 0.15]` by 0.03 at `h`): `h` = 0.01, 0.005, 0.0025 give `b`
//! +1.80 %, −0.02 %, +0.20 % and `p₀` −0.65 %, −0.27 %, −0.27 %; a far spacing of 0.025 at
//! 0.0025 changes them by < 0.02 % (with the target's normal; with the bisector `h = 0.005`
//! gives `b` −0.07 %, `p₀` −0.23 %). The test runs `h = 0.005` and asks for 2 % (the task's
//! bound; at 0.01 only four candidates per side are closed and `b` is at +1.8 %).

use super::common::*;
use mlpg_contact::problem::Problem;

const E1: f64 = 1.0;
const NU1: f64 = 0.3;
const R1: f64 = 1.0;
const E2: f64 = 2.0;
const NU2: f64 = 0.25;
const R2: f64 = 2.0;

/// The two half-disks with the box around the contact at spacing `h` (0.05 elsewhere),
/// MFVM, `β = 0.5`, plane strain.
fn cylinders(h: f64) -> Problem {
    Problem::from_toml(&format!(
        r#"
        [discretisation]
        beta = 0.5
        [[body]]
        name = "upper"
        [body.geometry]
        kind = "curves"
        start = [-1.0, 1.0]
        curves = [
            {{ name = "left", to = [-0.5, 0.1339745962155614], center = [0.0, {R1:?}] }},
            {{ name = "arc", to = [0.5, 0.1339745962155614], center = [0.0, {R1:?}] }},
            {{ name = "right", to = [1.0, 1.0], center = [0.0, {R1:?}] }},
            {{ name = "top", to = [-1.0, 1.0] }},
        ]
        [body.nodes]
        spacing = 0.05
        [[body.nodes.refine]]
        x = [-0.15, 0.15]
        y = [0.0, 0.03]
        spacing = {h:?}
        [body.material]
        young = {E1:?}
        poisson = {NU1:?}
        plane = "strain"
        [[body.boundary]]
        edge = "top"
        displacement = {{ x = 0.0, y = -0.005 }}
        [[body]]
        name = "lower"
        [body.geometry]
        kind = "curves"
        start = [-2.0, -2.0]
        curves = [
            {{ name = "bottom", to = [2.0, -2.0] }},
            {{ name = "right", to = [1.0, -0.2679491924311228], center = [0.0, -{R2:?}] }},
            {{ name = "arc", to = [-1.0, -0.2679491924311228], center = [0.0, -{R2:?}] }},
            {{ name = "left", to = [-2.0, -2.0], center = [0.0, -{R2:?}] }},
        ]
        [body.nodes]
        spacing = 0.05
        [[body.nodes.refine]]
        x = [-0.15, 0.15]
        y = [-0.03, 0.0]
        spacing = {h:?}
        [body.material]
        young = {E2:?}
        poisson = {NU2:?}
        plane = "strain"
        [[body.boundary]]
        edge = "bottom"
        displacement = {{ x = 0.0, y = 0.0 }}
        [contact]
        edge = "arc"
        target_edge = "arc"
        "#
    ))
    .unwrap()
}

/// Complementarity, both bodies' balance and the pair's (the contact resultant leaves the
/// upper body and enters the lower), then Hertz's `b` and `p₀` within 2 % (see the header).
#[test]
fn two_elastic_cylinders_against_hertz() {
    let s = mlpg_contact::solve(&cylinders(0.005)).unwrap();
    let c = s.contact().unwrap();
    assert_lcp_residuals("cylinders", &c.lcp.residuals, 1e-9);
    let lower = s.body(1).expect("the lower cylinder");
    assert!(s.equilibrium_error < 1e-8, "upper equilibrium {}", s.equilibrium_error);
    assert!(lower.equilibrium_error < 1e-8, "lower equilibrium {}", lower.equilibrium_error);
    let resultant = c.candidates.operator.resultant(&c.lcp.z);
    let target = c.target.as_ref().expect("the target's operator").resultant(&c.lcp.z);
    let force = resultant[1];
    assert!(force > 0.0, "the contact pushes the upper body up: {resultant:?}");
    for k in 0..2 {
        let pair = resultant[k] + target[k];
        assert!(pair.abs() <= 1e-12 * force, "pair's balance along {k}: {pair}");
        let (up, low) = (s.reaction_force[k] + resultant[k], lower.reaction_force[k] + target[k]);
        assert!(up.abs() < 1e-8 * force && low.abs() < 1e-8 * force, "{k}: {up} {low}");
    }
    let e_star = 1.0 / ((1.0 - NU1 * NU1) / E1 + (1.0 - NU2 * NU2) / E2);
    let radius = 1.0 / (1.0 / R1 + 1.0 / R2);
    let b = (4.0 * force * radius / (std::f64::consts::PI * e_star)).sqrt();
    let p0 = 2.0 * force / (std::f64::consts::PI * b);
    let (peak, half, closed) = hertz_fit(c);
    assert_eq!(c.onset.closed_intervals, 1);
    assert!(closed >= 12, "only {} closed candidates", closed);
    let (eb, ep) = (half / b - 1.0, peak / p0 - 1.0);
    println!(
        "two cylinders: P = {force:.6e}  b/R = {:.4}  b {eb:+.3e}  p0 {ep:+.3e}  closed {}",
        b / radius,
        closed
    );
    assert!(eb.abs() < 0.02 && ep.abs() < 0.02, "b {eb:+.3e}, p0 {ep:+.3e}");
}
