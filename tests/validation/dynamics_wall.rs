//! A block sliding with Coulomb friction along a rigid floor onto a rigid wall
//! (`problems/block_onto_wall_friction.toml`, docs/dev/dynamics.md increment 12): one elastic
//! body, two `[[contact]]` pairs against rigid lines (the floor with `μ`, the wall without),
//! restitution 0, against rigid-body mechanics.
//!
//! Reference, derived here. A rigid block of mass `m` on a floor under gravity `g`, sliding at
//! `v0` towards a wall `d` away: the floor's normal force is `m g`, its friction `μ m g`
//! against the motion, so `v(t) = v0 − μ g t` and `x(t) = v0 t − μ g t² / 2`; `x(t1) = d`
//! gives the arrival time `t1 = (v0 − √(v0² − 2 μ g d)) / (μ g)` and speed
//! `v1 = √(v0² − 2 μ g d)` (the smaller root: the block reaches the wall before it would stop,
//! `v0² > 2 μ g d`). At the velocity level (Moreau) the law holds per step: while every floor
//! contact slides, each step's tangential impulses are `−μ` times its normal ones, and the only
//! other external impulse is the weight's, so the momenta obey
//! `p_x + μ p_y = m v0 − μ m g t` exactly (the MFVM momentum is exact: the interior fluxes
//! cancel). The elastic block's mean velocity `p_x / m` then differs from `v0 − μ g t` by
//! `μ p_y / m`, its vertical mean velocity: the settling under the weight applied at t = 0.
//! Its size: suddenly loaded, a linear elastic body's load does at most twice the static work
//! (`fᵀu ≤ 2 fᵀK⁻¹f` where `fᵀu = ½ uᵀKu` at a turning point, by Cauchy–Schwarz), so its kinetic
//! energy stays below `2 m g Δ` with `Δ = ρ g H² / (3 E)` the static drop of the centre of mass
//! of a column of height `H` under its weight; `½ m v_y² ≤ 2 m g Δ` gives
//! `|v_y| ≤ 2 √(g Δ)` (9.1e-3 here), so `|p_x / m − (v0 − μ g t)| ≤ 2 μ √(g Δ)` (2.7e-3, 0.55 %
//! of `v0`; friction and the θ-method's damping only take energy).
//!
//! The arrival on the discrete run: a candidate enters the index set when its gap predicted
//! at mid-step, `g(q + h/2 v)`, is closed, so the wall's first impulse comes in the step that
//! starts within `h/2` of `t1`, shifted by the θ-method's position lag `(θ − ½) h (v0 − v)`
//! (1.4e-4 here, 4e-4 in time): the first wall step starts within `h` of `t1`, and the mean
//! speed at that step's start is the Coulomb speed there, within one step's deceleration
//! `μ g h` of `v1`. The penetration: a candidate not yet in the set at a step start has a
//! predicted gap `g + h U / 2 > 0`, so after that step its gap is above `−h |U| / 2`; once in
//! the set its end-of-step rate is `U⁺ ≥ 0` and the θ-method moves it by
//! `h (θ U⁺ + (1 − θ) U)`, at most `(1 − θ) h |U|` further in: every gap stays above
//! `−(3/2 − θ) h v1` (the velocity-level law restores no position, docs/method.md §10.3).

use mlpg_contact::contact::Candidates;
use mlpg_contact::dynamics::mass;
use mlpg_contact::pipeline::dynamics::{DynamicOutcome, solve};
use mlpg_contact::problem::Problem;
use mlpg_contact::progress::Silent;

/// The file's figures (checked against the text below).
const V0: f64 = 0.5;
const MU: f64 = 0.3;
const G: f64 = 1.0;
const HEIGHT: f64 = 0.25;
const YOUNG: f64 = 1000.0;
const DENSITY: f64 = 1.0;

/// The shipped file's text, checked to say the figures of the constants above.
fn shipped_text() -> String {
    let path = format!("{}/problems/block_onto_wall_friction.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    for line in [
        "initial_velocity = [0.5, 0.0]",
        "friction = 0.3",
        "body_force = [0.0, -1.0]",
        "y = [0.0, 0.25]",
        "young = 1000.0",
        "density = 1.0",
        "restitution = 0.0",
    ] {
        assert!(text.contains(line), "the file says {line}");
    }
    text
}

/// Every candidate's gap in every snapshot (the nodal displacement `Φ q` at the candidate's
/// node along its normal; the candidates are nodes), the smallest over the run.
fn smallest_gap(outcome: &DynamicOutcome, candidates: &Candidates) -> f64 {
    let mut smallest = f64::INFINITY;
    for frame in &outcome.simulation.frames {
        let u = &frame.bodies[0].displacement;
        for (k, &node) in candidates.nodes.iter().enumerate() {
            let (d, n) = (u[node as usize], candidates.normals[k]);
            smallest = smallest.min(candidates.initial_gap[k] + d[0] * n[0] + d[1] * n[1]);
        }
    }
    smallest
}

/// The block against rigid-body mechanics (module documentation). Checked:
/// - until the wall's first impulse, `p_x + μ p_y = m v0 − μ m g t` at every record to 1e-10
///   of `m v0` (exact while every floor contact slides) and the mean velocity within
///   `2 μ √(g Δ)` of `v0 − μ g t` (the settling's bound, 2.7e-3; measured: the identity to
///   2.3e-13, the velocity to 9.8e-4 = 36 % of the bound, at the first step, where the
///   settling starts);
/// - the wall's first impulse in the step starting within `h` of `t1` = 0.46482 (measured
///   0.47), the mean speed at that step's start within `2 μ √(g Δ)` of the Coulomb speed there
///   and within `μ g h + 2 μ √(g Δ)` of `v1` = 0.36056 (measured 0.35900);
/// - every floor and wall gap in every step (snapshots every step) above `−(3/2 − θ) h v1`
///   = −3.24e-3 (measured floor −2.2e-4, wall −3.19e-3: the bound's worst case nearly occurs,
///   the arrival falls 2e-4 after a step's mid-point, so the wall is missed by one step's
///   prediction and closed by the next), and the wall gaps open at the end (0.072: it left);
/// - after the wall contact ends, the block's mean velocity is away from the wall (not into
///   it: restitution 0) and below `v1` in size (measured rebound 0.235, then friction slows
///   it: 0.093 at t = 1);
/// - energy: never gained (`figures.energy_growth`, the positive part of
///   `E(t) − E(0) − W(t) + loss(t)`, is 0), the contacts' cumulative loss `≥ 0` at every
///   record, and `E − W` lower at the end than before the impact (measured 1.61e-2 before,
///   1.07e-3 at the end; θ = 0.6 damps the impact's high modes: `energy_balance_error` 0.185);
/// - Coulomb's cone at every step: the floor's tangential impulse (`Δp_x + h F_wall`: the wall
///   pushes along −x without friction, the weight acts along y) within `μ` times its normal
///   impulse `h F_floor` (to 1e-12 of `m v0`), with equality before the wall (every contact
///   slides forward);
/// - every step LCP's residual within the run's check (1e-9).
///
/// `contact.solver = "active_set"` is refused at the first step, naming `contact[0].solver`:
/// the corner node (1, 0) owns a candidate of each pair (a floor candidate with friction and
/// a wall candidate), which the sparse step's row replacement cannot take (the floor's
/// tangential and the wall's normal force act on one row; without the floor's friction it is
/// taken: `dynamics_active_set`).
#[test]
fn block_slides_onto_a_wall_as_a_rigid_block_would() {
    let text = shipped_text();
    let frames = text.replace("restitution = 0.0", "restitution = 0.0\noutput.every = 1");
    let problem = Problem::from_toml(&frames).expect("the wall file");
    let outcome = solve(&problem, &mut Silent).expect("the wall run");
    let h = outcome.dynamics.time_step;
    let theta = outcome.dynamics.theta;
    let m = mass::total(&outcome.simulation.mass);
    let records = &outcome.simulation.history.records;
    let pairs = &outcome.bodies.as_ref().expect("two pairs").pairs;
    let (floor, wall) = (&pairs[0].candidates, &pairs[1].candidates);
    let d = wall.initial_gap.iter().copied().fold(f64::INFINITY, f64::min);
    assert!((records[0].momentum[0] - m * V0).abs() <= 1e-12 * m * V0, "starts at v0");

    let mu_g = MU * G;
    let v1 = (V0 * V0 - 2.0 * mu_g * d).sqrt();
    let t1 = (V0 - v1) / mu_g;
    let settle = 2.0 * MU * (G * DENSITY * G * HEIGHT * HEIGHT / (3.0 * YOUNG)).sqrt();
    let p0 = m * V0;

    // The wall's first impulse: record `first` ends the first step with one.
    let first = records.iter().position(|r| r.pair_forces[1] > 0.0).expect("hits the wall");
    let start = records[first - 1].time;
    let mut identity: f64 = 0.0;
    let mut mean: f64 = 0.0;
    for r in &records[..first] {
        let exact = p0 - MU * m * G * r.time;
        identity = identity.max((r.momentum[0] + MU * r.momentum[1] - exact).abs() / p0);
        mean = mean.max((r.momentum[0] / m - (V0 - mu_g * r.time)).abs());
    }
    let arrival = records[first - 1].momentum[0] / m;

    let (on_floor, on_wall) = (smallest_gap(&outcome, floor), smallest_gap(&outcome, wall));
    let lowest = on_floor.min(on_wall);
    let offset = pairs[1].offset;
    let final_wall = outcome.simulation.final_gap[offset..offset + wall.nodes.len()]
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let bound = (1.5 - theta) * h * v1;

    let last_wall = records.iter().rposition(|r| r.pair_forces[1] > 0.0).unwrap();
    let after: Vec<f64> = records[last_wall..].iter().map(|r| r.momentum[0] / m).collect();
    let rebound = after.iter().copied().fold(f64::INFINITY, f64::min);
    let away = after.iter().copied().fold(f64::NEG_INFINITY, f64::max);

    let f = outcome.simulation.figures(h);
    let lost = records.iter().map(|r| r.contact_loss).fold(f64::INFINITY, f64::min);
    let net = |r: &mlpg_contact::dynamics::Record| r.energy() - r.external_work;
    let (before, end) = (net(&records[first - 1]), net(&records[records.len() - 1]));

    let mut cone: f64 = 0.0;
    let mut sliding: f64 = 0.0;
    for (k, (a, b)) in records.iter().zip(&records[1..]).enumerate() {
        let tangential = b.momentum[0] - a.momentum[0] + h * b.pair_forces[1];
        let normal = h * b.pair_forces[0];
        cone = cone.max(tangential.abs() - MU * normal);
        if k + 1 < first {
            sliding = sliding.max((tangential + MU * normal).abs());
        }
    }
    println!(
        "wall: d = {d}, t1 = {t1:.5}, v1 = {v1:.5}; identity {identity:.2e}, mean velocity {mean:.2e} \
         (bound {settle:.2e}); first wall step from {start:.4}, speed there {arrival:.5} (Coulomb {:.5}); \
         lowest gap floor {on_floor:.2e}, wall {on_wall:.2e} (bound −{bound:.2e}), wall at the end {final_wall:.2e}; after the wall: from {rebound:.5} to {:.5}, at most {away:.2e}; \
         energy growth {:.1e}, loss ≥ {lost:.2e}, E − W {before:.4e} before, {end:.4e} at the end; \
         cone excess {:.1e}, sliding equality {:.1e} (of m v0); residual {:.1e}",
        V0 - mu_g * start,
        after[after.len() - 1],
        f.energy_growth,
        cone / p0,
        sliding / p0,
        f.max_step_residual
    );
    assert!((d - 0.2).abs() < 1e-12, "the wall is {d} away");
    assert!(identity <= 1e-10, "p_x + μ p_y off by {identity:e} of m v0");
    assert!(mean <= settle, "mean velocity off Coulomb's by {mean:e} (bound {settle:e})");
    assert!((start - t1).abs() <= h + 1e-12, "first wall step from {start} against t1 = {t1}");
    assert!((arrival - (V0 - mu_g * start)).abs() <= settle, "speed {arrival} at {start}");
    assert!((arrival - v1).abs() <= mu_g * h + settle, "arrival speed {arrival} against {v1}");
    assert!(lowest >= -bound, "a gap of {lowest:e} (bound −{bound:e})");
    assert!(final_wall > 0.0, "still at the wall at the end: {final_wall}");
    assert!(away <= 0.0, "moves into the wall at {away} after the impact");
    assert!(rebound >= -v1, "rebounds at {rebound}, faster than it arrived ({v1})");
    assert!(f.energy_growth <= 0.0, "energy gained: {f:?}");
    assert!(lost >= 0.0, "the contacts gave energy: {lost:e}");
    assert!(end < before, "E − W {end} at the end against {before} before the impact");
    assert!(cone <= 1e-12 * p0, "the floor's tangential impulse beyond μ N by {cone:e}");
    assert!(sliding <= 1e-10 * p0, "the floor does not slide before the wall: {sliding:e}");
    assert!(f.max_step_residual <= mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE, "{f:?}");

    let sparse = text.replace("[[contact]]  ", "[[contact]]\nsolver = \"active_set\"\n#");
    assert_eq!(sparse.matches("\nsolver = \"active_set\"\n").count(), 2, "both pairs");
    let problem = Problem::from_toml(&sparse).expect("the wall file on the active set");
    let err = solve(&problem, &mut Silent).err().expect("refused").to_string();
    println!("active set: {err}");
    assert!(err.contains("contact[0].solver") && err.contains("corner"), "{err}");
    assert!(err.contains("with friction"), "{err}");
}
