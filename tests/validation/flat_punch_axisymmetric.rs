//! A rigid flat circular punch on a large elastic cylinder, axisymmetric
//! (`problems/flat_punch_axisymmetric.toml`): the punch of radius `a = 0.1`, sharp corners, is
//! pushed `δ = 0.001` onto the top of the cylinder `[0, W] × [−W, 0]` (bottom clamped, `E = 1`,
//! `ν = 0.3`). Half-space (Boussinesq; Sneddon 1946): `P = 2 a E* δ`, `E* = E/(1 − ν²)`.
//!
//! The node set: a box `[0, 1.5a] × [−0.5a, 0]` at the spacing `h`, a near-field box
//! `[0, 4a] × [−4a, 0]` at `4h`, the far spacing `W/16` (the quadtree grades between them,
//! docs/method.md §2.1). `examples/studies/flat_punch.rs` runs this over (`h`, `W`) and
//! extrapolates to the half-space; the numbers are in docs/dev/axisymmetric.md (increment 8b).

use super::common::assert_lcp_residuals;
use mlpg_contact::Solution;
use mlpg_contact::problem::Problem;
use std::f64::consts::TAU;

const TOML: &str = include_str!("../../problems/flat_punch_axisymmetric.toml");
/// The punch's radius `a`.
pub const RADIUS: f64 = 0.1;
/// The punch's displacement `δ`.
pub const DEPTH: f64 = 0.001;
const YOUNG: f64 = 1.0;
const POISSON: f64 = 0.3;

/// Sneddon's half-space force `P = 2 a E* δ`.
pub fn sneddon() -> f64 {
    2.0 * RADIUS * YOUNG / (1.0 - POISSON * POISSON) * DEPTH
}

/// The shipped problem with the punch's box spacing `h` (the near field at `4h`), the block
/// size `w` and the far spacing `far`. `far / h` must be a power of two (quadtree levels).
pub fn punch(h: f64, w: f64, far: f64) -> Problem {
    let swap = |text: String, from: &str, to: String| {
        assert!(text.contains(from), "flat_punch_axisymmetric.toml: `{from}` not found");
        text.replace(from, &to)
    };
    let mut text = TOML.to_string();
    text = swap(text, "x = [0.0, 6.4]", format!("x = [0.0, {w}]"));
    text = swap(text, "y = [-6.4, 0.0]", format!("y = [-{w}, 0.0]"));
    text = swap(text, "spacing = 0.4 ", format!("spacing = {far} "));
    text = swap(text, "spacing = 0.003125", format!("spacing = {h}"));
    text = swap(text, "spacing = 0.0125", format!("spacing = {}", 4.0 * h));
    Problem::from_toml(&text).unwrap()
}

/// What a run measures.
pub struct Punch {
    /// The punch's force `P = −Σ ν_z F_c` (the rings' total forces).
    pub force: f64,
    /// Nodes of the run.
    pub nodes: usize,
    /// Closed candidates.
    pub closed: usize,
}

/// Checks a punch solution (complementarity, the per-radian axial balance, one closed interval
/// ending exactly at the punch's edge) and returns its force.
pub fn measure(label: &str, s: &Solution) -> Punch {
    let c = s.contact().unwrap();
    assert_lcp_residuals(label, &c.lcp.residuals, 1e-9);
    assert!(s.equilibrium_error < 1e-8, "{label}: equilibrium {}", s.equilibrium_error);
    assert_eq!(c.onset.closed_intervals, 1, "{label}");
    let axial: f64 = c.candidates.normals.iter().zip(&c.lcp.z).map(|(n, f)| n[1] * f).sum();
    // The reactions per radian balance the rings' axial force per radian.
    let balance = s.reaction_force[1] + axial / TAU;
    assert!(balance.abs() < 1e-8 * axial.abs() / TAU, "{label}: balance {balance}");
    // Sharp corners: every candidate under the punch is closed, none outside it.
    let r = |k: usize| c.candidates.points[k][0];
    for k in 0..c.closed.len() {
        let under = r(k) <= RADIUS * (1.0 + 1e-9);
        assert_eq!(c.closed[k], under, "{label}: candidate at r = {} closed {}", r(k), c.closed[k]);
    }
    let closed = c.closed.iter().filter(|&&k| k).count();
    Punch { force: -axial, nodes: s.displacement.len(), closed }
}

/// The limit `h → 0` at `W = 6.4` (far spacing 0.4) of the study
/// (`cargo run --release --features studies --example flat_punch`): Richardson over
/// `h = a/16, a/32, a/64` (P = 2.249087e-4, 2.236985e-4, 2.231184e-4) with the measured rate
/// 1.06; with the rate fixed at 1 it is 2.225383e-4 (−0.02 %).
const FINITE_BLOCK: f64 = 2.225842e-4;

/// The shipped file (its values: `punch` changes nothing): `h = a/32`, `W = 6.4` (`a/W = 1/64`), far spacing `W/16`.
///
/// The study (docs/dev/axisymmetric.md, increment 8b) measures both errors positive and
/// monotone, each at rate ≈ 1: the discretisation (`h`: rate 1.05–1.06 at every `W`) and the
/// finite block (`a/W`: rate 1.04 at every `h`). Extrapolated in both (either order) the
/// half-space limit is 2.199121e-4, Sneddon +0.06 %.
/// Bounds: against this block's limit [`FINITE_BLOCK`], `P` is above it by the discretisation
/// error at `a/32`, measured +0.50 % here (+0.51 to +0.55 % at `W` = 3.2 … 0.8): asserted in
/// `(0, 0.6 %)`, 0.1 % for the extrapolation (its two rates give limits 0.02 % apart).
/// Against Sneddon: within the 2 % (observed +1.78 %: +1.28 % the finite block, +0.50 %
/// the spacing; both shrink under refinement and enlargement, towards +0.06 %).
#[test]
fn flat_punch_axisymmetric_stiffness() {
    let s = mlpg_contact::solve(&punch(RADIUS / 32.0, 6.4, 0.4)).unwrap();
    let p = measure("punch h = a/32, W = 6.4", &s);
    let exact = sneddon();
    let (block, half_space) = (p.force / FINITE_BLOCK - 1.0, p.force / exact - 1.0);
    println!(
        "flat punch: nodes {}  closed {}  P = {:.6e}  P/P_W − 1 = {block:+.3e}  P/Sneddon − 1 = {half_space:+.3e}",
        p.nodes, p.closed, p.force
    );
    assert_eq!(p.closed, 33, "a/32: 33 candidates under the punch");
    assert!(block > 0.0 && block < 0.006, "P against the block's limit: {block:+e}");
    assert!(half_space.abs() < 0.02, "P against Sneddon: {half_space:+e}");
}
