//! Coulomb friction in the time stepping (docs/dev/dynamics.md increment 9) on the bodies the
//! static friction covers: finite element bodies beside MFVM ones, and axisymmetric rings.
//!
//! Reference (a block on a rigid floor, derived here). A block of mass `m` on a rigid flat
//! under its weight `m g` and a uniform horizontal body force `m a` (`body_force = [a, −g]`
//! with `ρ = 1`) starting at `v0` along the flat. At the velocity level (Moreau) Coulomb's law
//! holds per step: the floor's tangential impulse `T_n = Δp_x − h m a` and its normal impulse
//! `N_n = Δp_y + h m g` (the momentum changes by the loads' and the contacts' impulses only:
//! the interior forces of the MFVM's fluxes and of the FE's `K` sum to zero) obey
//! `|T_n| ≤ μ N_n` every step, with `T_n = −μ N_n sign(v)` while every contact slides. So
//! while the block slides forward `p_x + μ p_y = m v0 + (a − μ g) m t` exactly: at `a = 0` it
//! decelerates at `μ g` and stops at `v0 / (μ g)`; from rest with `a > μ g` it accelerates at
//! `a − μ g`; with `a < μ g` the floor holds it (stick) and only the elastic shear the push
//! stores moves it.

use mlpg_contact::dynamics::{Record, mass};
use mlpg_contact::pipeline::dynamics::{DynamicOutcome, solve};
use mlpg_contact::problem::{Method, Problem};
use mlpg_contact::progress::Silent;

const MU: f64 = 0.3;
const G: f64 = 1.0;
const H: f64 = 0.01;
const FEM: &str = "[discretisation]\nmethod = \"fem\"";

/// The block `[0, 1] × [0, 0.25]` (E = 1000, ν = 0.3, ρ = 1, spacing 0.05: Q9 of that size
/// with `FEM`) on a rigid flat with friction `mu`, under `body_force = [push, −1]`, starting
/// at `[v0, 0]`, step 0.01, θ = 0.6 (the sliding block of `dynamics.rs`), `extra` appended.
pub(super) fn block(mu: f64, v0: f64, push: f64, end_time: f64, extra: &str) -> Problem {
    let text = format!(
        r#"
        body_force = [{push}, -1.0]
        [geometry]
        kind = "rectangle"
        x = [0.0, 1.0]
        y = [0.0, 0.25]
        [nodes]
        spacing = 0.05
        [material]
        young = 1000.0
        poisson = 0.3
        plane = "stress"
        density = 1.0
        [contact]
        edge = "bottom"
        obstacle_point = [0.0, 0.0]
        obstacle_normal = [0.0, 1.0]
        friction = {mu}
        {extra}
        [dynamics]
        end_time = {end_time}
        time_step = {H}
        theta = 0.6
        initial_velocity = [{v0}, 0.0]
        "#
    );
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("block: {e}"))
}

fn run(problem: &Problem) -> (DynamicOutcome, f64) {
    let outcome = solve(problem, &mut Silent).expect("the dynamic run");
    let m = mass::total(&outcome.simulation.mass);
    (outcome, m)
}

/// Per step: the floor's tangential impulse `T_n` and normal impulse `N_n` from the momenta
/// (module documentation), and `N_n` from the contact force the run records.
fn impulses(records: &[Record], m: f64, push: f64) -> Vec<(f64, f64, f64)> {
    records
        .windows(2)
        .map(|w| {
            let (a, b) = (&w[0], &w[1]);
            let t = b.momentum[0] - a.momentum[0] - H * m * push;
            let n = b.momentum[1] - a.momentum[1] + H * m * G;
            (t, n, H * b.contact_force)
        })
        .collect()
}

/// The checks every frictional block run passes: the momenta's normal impulse equals the
/// recorded contact impulse (1e-10), Coulomb's cone every step (1e-11: the FE momenta carry
/// the round-off of `K`'s row sums, measured 1.8e-12, the MFVM's 1.5e-14), no energy gained,
/// every step LCP's residual within the run's check. Returns the largest
/// `|N_momenta − N_recorded|`, the cone's largest excess (both relative to `scale`) and the
/// energy growth.
fn common_checks(outcome: &DynamicOutcome, m: f64, push: f64, scale: f64) -> [f64; 3] {
    let records = &outcome.simulation.history.records;
    let mut normal: f64 = 0.0;
    let mut cone: f64 = 0.0;
    for (t, n, recorded) in impulses(records, m, push) {
        normal = normal.max((n - recorded).abs() / scale);
        cone = cone.max((t.abs() - MU * n) / scale);
    }
    let f = outcome.simulation.figures(H);
    assert!(normal <= 1e-10, "the momenta's normal impulse off the recorded one by {normal:e}");
    assert!(cone <= 1e-11, "the tangential impulse beyond μ N by {cone:e}");
    assert!(f.energy_growth <= 0.0, "energy gained: {f:?}");
    assert!(f.max_step_residual <= mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE, "{f:?}");
    [normal, cone, f.energy_growth]
}

/// The sliding block as Q9 finite elements (HRZ lumped mass) and as the MFVM: while it
/// slides, `p_x + μ p_y = m v0 − μ m g t` to 1e-9 of `m v0` (the steps' round-off summed: FE
/// measured 9.4e-11 over 90 steps of 1e-12 each, MFVM 5.1e-13) and `T_n = −μ N_n` every step
/// (to 1e-12); Coulomb's cone every step, no energy gained, residuals (`common_checks`); it
/// stops within two steps of `v0 / (μ g)` = 1 and stays (`|v_x|` below 1e-3 v0 from 1.3 times
/// that). The FE and MFVM mean velocities agree within 1e-3 v0 while sliding (both follow
/// `v0 − μ g t` up to the settling's `μ v_y`). With `μ = 1e-9` the FE block keeps `v0` to
/// 1e-8 (frictionless: exactly).
#[test]
fn fe_block_slides_and_stops_as_coulomb_says_and_as_the_mfvm_block() {
    let v0 = 0.3;
    let stop = v0 / (MU * G);
    let mut sliding_velocity = Vec::new();
    for (name, extra) in [("MFVM", ""), ("FE", FEM)] {
        let (outcome, m) = run(&block(MU, v0, 0.0, 1.5 * stop, extra));
        let records = &outcome.simulation.history.records;
        let p0 = m * v0;
        let [normal, cone, growth] = common_checks(&outcome, m, 0.0, p0);
        let mut identity: f64 = 0.0;
        let mut sliding: f64 = 0.0;
        for (r, (t, n, _)) in records[1..].iter().zip(impulses(records, m, 0.0)) {
            if r.time <= 0.9 * stop {
                let exact = p0 - MU * m * G * r.time;
                identity = identity.max((r.momentum[0] + MU * r.momentum[1] - exact).abs() / p0);
                sliding = sliding.max((t + MU * n).abs() / p0);
            }
        }
        let stopped = records.iter().find(|r| r.momentum[0] <= 1e-3 * p0).expect("it stops");
        let after = records.iter().filter(|r| r.time >= 1.3 * stop);
        let drift = after.map(|r| (r.momentum[0] / m).abs()).fold(0.0, f64::max);
        let at = |t: f64| {
            let r = records.iter().find(|r| (r.time - t).abs() < 0.5 * H).expect("a record");
            r.momentum[0] / m
        };
        let v = [at(0.25), at(0.5), at(0.75)];
        println!(
            "{name} block (m = {m}, {} nodes): identity {identity:.2e}, sliding T + μN {sliding:.2e}, \
             N momenta − recorded {normal:.1e}, cone excess {cone:.1e} (of m v0), growth {growth:.1e}; \
             v at 0.25/0.5/0.75 {v:.6?} (Coulomb {:.3?}); stops at {:.4} (analytic {stop:.4}), |v_x| after {drift:.2e}",
            outcome.nodes(),
            [0.225, 0.15, 0.075],
            stopped.time
        );
        assert!(identity <= 1e-9, "{name}: p_x + μ p_y off by {identity:e} of m v0");
        assert!(sliding <= 1e-11, "{name}: T ≠ −μ N while sliding by {sliding:e}");
        assert!(
            (stopped.time - stop).abs() <= 2.0 * H + 1e-12,
            "{name}: stops at {}",
            stopped.time
        );
        assert!(drift < 1e-3 * v0, "{name}: slides on at {drift}");
        sliding_velocity.push(v);
    }
    let apart = (0..3).map(|k| (sliding_velocity[0][k] - sliding_velocity[1][k]).abs());
    let apart = apart.fold(0.0, f64::max);
    println!("MFVM against FE while sliding: {apart:.2e}");
    assert!(apart <= 1e-3 * v0, "the FE and MFVM blocks slide apart by {apart:e}");

    let (vanishing, m) = run(&block(1e-9, v0, 0.0, 0.5, FEM));
    let records = &vanishing.simulation.history.records;
    let px = records[records.len() - 1].momentum[0];
    println!(
        "FE block, μ = 1e-9: p_x at 0.5 off m v0 by {:.2e} of it",
        (px - m * v0).abs() / (m * v0)
    );
    assert!((px - m * v0).abs() <= 1e-8 * m * v0, "μ = 1e-9: p_x {px} against {}", m * v0);
}

/// A block at rest pushed along the floor by `a = push` (per unit mass), MFVM and FE. Below
/// `μ g` it sticks: Coulomb's cone every step (`common_checks`) and its mean velocity stays
/// within the shear column's bound `2 √(a Δ_s)`, `Δ_s = ρ a H² / (3 G)` the static shift of
/// the centre of mass of a column of height `H` held at its foot under the uniform push (the
/// settling bound of `dynamics_wall.rs` with the shear modulus `G = E / 2(1 + ν)`: suddenly
/// loaded, a linear body's kinetic energy stays below twice the static work). Above `μ g`
/// it slides: every contact slides from the first step, `T_n = −μ N_n` every step (to 1e-11
/// of `m a T`), the momenta grow as `p_x + μ p_y = (a − μ g) m t` (to 1e-9 of `m a T`) and
/// the mean velocity at the end is within `2 √(a Δ_s) + 2 μ √(g Δ)` of `(a − μ g) T` (the
/// two settlings). Measured: stuck `|v_x|` ≤ 8.2e-4 (MFVM), 8.4e-4 (FE) against the bound
/// 2.2e-3 (the push alone would give 7.5e-2); sliding `v_x(0.5)` = 0.150001 (both) against
/// 0.15.
#[test]
fn pushed_block_sticks_below_mu_g_and_accelerates_at_a_minus_mu_g_above() {
    let end = 0.5;
    let (height, young, poisson) = (0.25, 1000.0, 0.3);
    let shear = young / (2.0 * (1.0 + poisson));
    let bound = |a: f64| 2.0 * (a * a * height * height / (3.0 * shear)).sqrt();
    let settle = 2.0 * MU * (G * G * height * height / (3.0 * young)).sqrt();
    for (name, extra) in [("MFVM", ""), ("FE", FEM)] {
        let a = 0.5 * MU * G;
        let (outcome, m) = run(&block(MU, 0.0, a, end, extra));
        let [_, cone, _] = common_checks(&outcome, m, a, m * a * end);
        let records = &outcome.simulation.history.records;
        let fastest = records.iter().map(|r| (r.momentum[0] / m).abs()).fold(0.0, f64::max);
        println!(
            "{name} block pushed at a = μg/2: |v_x| ≤ {fastest:.3e} (bound {:.3e}, the push alone would give {:.3e}); cone excess {cone:.1e}",
            bound(a),
            a * end
        );
        assert!(fastest <= bound(a), "{name}: moves at {fastest} under a push below μ m g");

        let a = 2.0 * MU * G;
        let (outcome, m) = run(&block(MU, 0.0, a, end, extra));
        let scale = m * a * end;
        let [_, cone, _] = common_checks(&outcome, m, a, scale);
        let records = &outcome.simulation.history.records;
        let steps = impulses(records, m, a);
        let slides = |s: &(f64, f64, f64)| (s.0 + MU * s.1).abs() <= 1e-11 * scale;
        let from = steps.iter().rposition(|s| !slides(s)).map_or(0, |k| k + 1);
        let last = &records[records.len() - 1];
        let velocity = last.momentum[0] / m;
        let exact = (a - MU * G) * end;
        println!(
            "{name} block pushed at a = 2μg: every contact slides from step {} of {}; v_x at {end} {velocity:.6} \
             (Coulomb {exact:.6}, bound {:.2e}); cone excess {cone:.1e}",
            from + 1,
            steps.len(),
            bound(a) + settle
        );
        let mut identity: f64 = 0.0;
        for r in &records[from..] {
            let exact = (a - MU * G) * m * r.time;
            identity = identity.max((r.momentum[0] + MU * r.momentum[1] - exact).abs() / scale);
        }
        println!(
            "{name} block pushed at a = 2μg: p_x + μ p_y off (a − μg) m t by {identity:.2e} of m a T"
        );
        assert!(from == 0, "{name}: slides only from step {}", from + 1);
        assert!(identity <= 1e-9, "{name}: p_x + μ p_y off by {identity:e}");
        assert!((velocity - exact).abs() <= bound(a) + settle, "{name}: v_x {velocity} at {end}");
    }
}

/// `problems/ball_impact_axisymmetric.toml` (the steel ball on a rigid flat) with
/// `friction = mu` and its snapshots at time 0 and `end` only.
fn ball(mu: f64, end: f64) -> Problem {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/ball_impact_axisymmetric.toml");
    let text = std::fs::read_to_string(path).expect("the shipped ball");
    let text = text
        .replace("edge = \"contact\"\n", &format!("edge = \"contact\"\nfriction = {mu}\n"))
        .replace("end_time = 70e-6", &format!("end_time = {end}\noutput.every = 1000000"));
    assert!(text.contains(&format!("friction = {mu}")) && text.contains("output.every"));
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("ball: {e}"))
}

/// The radial velocity `v_r` at the candidates pressing at the end of the run (impulse > 0)
/// and the candidates' largest `|v_r|`, relative to the impact speed 1 m/s.
fn pressing_radial_velocity(outcome: &DynamicOutcome) -> (usize, f64) {
    let candidates = outcome.candidates.as_ref().expect("candidates");
    let frame = outcome.simulation.frames.last().expect("the last snapshot");
    let v = &frame.bodies[0].velocity;
    let pressing: Vec<usize> =
        (0..candidates.len()).filter(|&c| outcome.simulation.final_impulses[c] > 0.0).collect();
    let fastest =
        pressing.iter().map(|&c| v[candidates.nodes[c] as usize][0].abs()).fold(0.0, f64::max);
    (pressing.len(), fastest)
}

/// Friction on rings (the radial slip of the static axisymmetric friction, docs/method.md
/// §9.6): the steel ball's impact with Coulomb friction, Lemke's frictional step on the rings'
/// `W_nn, W_nt, W_tn, W_tt`. Over the whole impact (μ = 0, 1e-9, 0.3): every step LCP's
/// residual (the cone's included) within the run's check; the peak force within 5 % of
/// Hertz's frictionless 2 300.9 N (measured +1.64 % frictionless, +2.32 % at μ = 0.3); the
/// energy at the end with friction not above the frictionless run's (measured 1.000278 E0
/// against 1.000638 E0: the shipped ball at θ = ½ gains 6e-4 of its energy in either run,
/// docs/dev/dynamics.md increment 14; friction takes 1.2e-3 E0 more at the contacts).
/// `μ = 1e-9` equals the frictionless run (contact duration exactly, peak force and rebound
/// to 1e-6). Half-way through the contact with `μ = 10` (full stick) every pressing ring's
/// radial velocity is zero to 1e-9 m/s (measured 1.8e-13 on 14 rings), where without
/// friction the rings slide (up to 8.7e-3 m/s: the ball's surface spreads over the flat).
#[test]
fn ball_impact_with_friction_on_rings() {
    let (h, duration) = (0.25e-6, 52.18e-6);
    let mut figures = Vec::new();
    for mu in [0.0, 1e-9, 0.3] {
        let (outcome, _) = run(&ball(mu, 70e-6));
        let f = outcome.simulation.figures(h);
        let records = &outcome.simulation.history.records;
        let lost = records.iter().map(|r| r.contact_loss).fold(f64::INFINITY, f64::min);
        println!(
            "ball μ = {mu}: duration {:?}, peak {:.2}, rebound {:.6}, final energy {:.6e} of E0, loss {:.3e} of E0 (lowest {:.2e}), growth {:.1e}, residual {:.1e}",
            f.contact.contact_duration,
            f.contact.peak_contact_force,
            f.final_velocity[1],
            f.final_energy / f.initial_energy,
            f.contact_loss / f.initial_energy,
            lost / f.initial_energy,
            f.energy_growth,
            f.max_step_residual
        );
        if let Some(free) = figures.first() {
            let free: &mlpg_contact::dynamics::Figures = free;
            assert!(
                f.final_energy <= free.final_energy * (1.0 + 1e-9),
                "μ = {mu}: ends with {} against the frictionless run's {}",
                f.final_energy,
                free.final_energy
            );
        }
        assert!(f.max_step_residual <= mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE);
        let peak = (f.contact.peak_contact_force - 2300.9) / 2300.9;
        assert!(peak.abs() < 0.05, "μ = {mu}: peak force off Hertz's by {peak}");
        figures.push(f);
    }
    let (free, vanishing) = (&figures[0], &figures[1]);
    assert_eq!(free.contact.contact_duration, vanishing.contact.contact_duration);
    let peak = (free.contact.peak_contact_force - vanishing.contact.peak_contact_force).abs();
    let rebound = (free.final_velocity[1] - vanishing.final_velocity[1]).abs();
    println!("μ = 1e-9 against frictionless: peak {peak:.2e} N, rebound {rebound:.2e} m/s");
    assert!(peak <= 1e-6 * free.contact.peak_contact_force, "peak apart by {peak}");
    assert!(rebound <= 1e-6, "rebound apart by {rebound}");

    let half = 1e-6 + 0.5 * duration;
    let (stuck, slid) = (run(&ball(10.0, half)).0, run(&ball(0.0, half)).0);
    let (n, stick) = pressing_radial_velocity(&stuck);
    let (n0, slip) = pressing_radial_velocity(&slid);
    println!(
        "half-way: μ = 10: {n} rings pressing, |v_r| ≤ {stick:.2e} m/s; frictionless: {n0} rings, |v_r| up to {slip:.2e} m/s"
    );
    assert!(n >= 3 && n0 >= 3, "pressing rings: {n}, {n0}");
    assert!(stick <= 1e-9, "a stuck ring moves radially at {stick}");
    assert!(slip >= 1e3 * stick.max(1e-12), "frictionless rings do not slide: {slip}");
}

/// The block of [`block`] at `v0` on the elastic slab `[−0.25, 1.5] × [−0.25, 0]` (the same
/// material, weightless, held on its bottom edge) with `μ` between them
/// (`problems/block_on_slab_friction.toml`'s pair, dynamics_pair.rs), until `end_time`; the
/// block's and the slab's methods `methods` (MFVM or Q9 of the spacing).
fn block_on_slab(mu: f64, v0: f64, end_time: f64, methods: [Method; 2]) -> Problem {
    let mut problem = super::dynamics_pair::block_on_slab(mu, v0, end_time);
    for (k, method) in methods.into_iter().enumerate() {
        problem.body_mut(k).expect("two bodies").discretisation.method = method;
    }
    problem
}

/// Friction between FE bodies: the block on the elastic slab with Q9 bodies (both, and an FE
/// block on an MFVM slab), checked as the MFVM pair is in dynamics_pair.rs: the block's
/// `p_x + μ p_y = m v0 − μ m g t` at 0.9 of the stopping time `v0 / (μ g)` to 1e-9 of `m v0`
/// (whatever the slab does), its mean velocity there Coulomb's within 1e-3 v0, below 1e-2 v0
/// at 1.5 times the stopping time (stopped: the bodies' vibration); no energy gained, every
/// step LCP's residual within the run's check. Measured (identity, v_x at 0.9 against
/// Coulomb's 0.03, v_x at 1.5): MFVM on MFVM 5.9e-13, 0.030034, 6.2e-4; FE on FE 9.5e-11,
/// 0.030025, 5.6e-4; FE on MFVM 9.6e-11, 0.030037, 6.1e-4.
#[test]
fn fe_block_on_an_elastic_slab_with_friction() {
    let v0 = 0.3;
    let stop = v0 / (MU * G);
    let t = 0.9 * stop;
    for (name, methods) in [
        ("MFVM on MFVM", [Method::Mfvm, Method::Mfvm]),
        ("FE on FE", [Method::Fem, Method::Fem]),
        ("FE on MFVM", [Method::Fem, Method::Mfvm]),
    ] {
        let end = |end_time: f64| {
            let outcome = solve(&block_on_slab(MU, v0, end_time, methods), &mut Silent)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let f = outcome.simulation.figures(H);
            let bodies = outcome.bodies.expect("two bodies");
            (bodies.ends[0].mass, bodies.ends[0].momentum, f)
        };
        let (m, p, f) = end(t);
        let identity = (p[0] + MU * p[1] - (m * v0 - MU * m * G * t)).abs() / (m * v0);
        let coulomb = v0 - MU * G * t;
        let (_, after, g) = end(1.5 * stop);
        println!(
            "{name}: identity at 0.9 t_stop {identity:.2e}, v_x there {:.6} (Coulomb {coulomb:.6}), at 1.5 t_stop {:.2e}; growth {:.1e}, {:.1e}; residual {:.1e}",
            p[0] / m,
            after[0] / m,
            f.energy_growth,
            g.energy_growth,
            g.max_step_residual
        );
        assert!(identity <= 1e-9, "{name}: p_x + μ p_y off by {identity:e}");
        assert!((p[0] / m - coulomb).abs() <= 1e-3 * v0, "{name}: v_x {}", p[0] / m);
        assert!((after[0] / m).abs() <= 1e-2 * v0, "{name}: slides on at {}", after[0] / m);
        for f in [&f, &g] {
            assert!(f.energy_growth <= 0.0, "{name}: energy gained: {f:?}");
            let tolerance = mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE;
            assert!(f.max_step_residual <= tolerance, "{name}: {f:?}");
        }
    }
}

/// A solid cylinder (radius 0.5, length 1: the section `[0, 0.5] × [0, 1]`, E = 1000, ν = 0.3,
/// ρ = 1, spacing 0.05, MFVM or Q9) landing at 0.1 on a rigid flat it touches at time 0, with
/// friction `mu`, step 0.0025 until `end`.
fn cylinder(mu: f64, end: f64, extra: &str) -> Problem {
    let text = format!(
        r#"
        [geometry]
        kind = "rectangle"
        x = [0.0, 0.5]
        y = [0.0, 1.0]
        [nodes]
        spacing = 0.05
        [material]
        young = 1000.0
        poisson = 0.3
        plane = "axisymmetric"
        density = 1.0
        [contact]
        edge = "bottom"
        obstacle_point = [0.0, 0.0]
        obstacle_normal = [0.0, 1.0]
        friction = {mu}
        {extra}
        [dynamics]
        end_time = {end}
        time_step = 0.0025
        initial_velocity = [0.0, -0.1]
        output.every = 1000000
        "#
    );
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("cylinder: {e}"))
}

/// Friction on the rings of an axisymmetric FE body (and the MFVM twin): a solid cylinder
/// landing flat on a rigid floor. Half-way through the contact (the end face presses for
/// `2 L / c` ≈ 0.063) with μ = 10 every pressing ring's radial velocity is zero to 1e-9 of
/// the landing speed (full stick), where without friction the face spreads (Poisson); μ = 1e-9
/// equals the frictionless run (peak force to 1e-6); residuals within the run's check.
/// Measured: MFVM 11 rings, stuck `|v_r|` ≤ 7.7e-16, frictionless up to 2.7e-2, μ = 1e-9
/// 1.7e-10; FE (Q9) 21 rings, 2.9e-15, 1.7e-2, 9.5e-11. The FE run is the axisymmetric FE
/// time stepping's first test (increment 14 wired it).
#[test]
fn axisymmetric_fe_cylinder_sticks_with_friction() {
    let half = 0.03;
    for (name, extra) in [("MFVM", ""), ("FE", FEM)] {
        let (stuck, slid) =
            (run(&cylinder(10.0, half, extra)).0, run(&cylinder(0.0, half, extra)).0);
        let (n, stick) = pressing_radial_velocity(&stuck);
        let (n0, slip) = pressing_radial_velocity(&slid);
        let vanishing = run(&cylinder(1e-9, half, extra)).0;
        let peak = |o: &DynamicOutcome| o.simulation.figures(0.0025).contact.peak_contact_force;
        let apart = (peak(&vanishing) - peak(&slid)).abs() / peak(&slid);
        let residual = stuck.simulation.figures(0.0025).max_step_residual;
        println!(
            "{name} cylinder at t = {half}: μ = 10: {n} rings pressing, |v_r| ≤ {stick:.2e}; frictionless: {n0}, |v_r| up to {slip:.2e}; μ = 1e-9 peak apart {apart:.1e}; residual {residual:.1e}"
        );
        assert!(n >= 3 && n0 >= 3, "{name}: pressing rings {n}, {n0}");
        assert!(stick <= 1e-9 * 0.1, "{name}: a stuck ring moves radially at {stick}");
        assert!(slip >= 1e3 * stick.max(1e-15), "{name}: frictionless rings do not slide: {slip}");
        assert!(apart <= 1e-6, "{name}: μ = 1e-9 peak apart by {apart}");
        assert!(residual <= mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE, "{name}");
    }
}

/// A step's own friction in time (`[[step]] friction` with `time`, docs/method.md §10.6): the
/// block sliding at `v0 = 0.3` on the floor of `μ = 0.3` with a first step setting `friction
/// = 0` until `t1 = 0.5` and a second setting 0.3 again (during `(0.5, 1]`, held after). A
/// step's coefficient holds during the step, so the block keeps `m v0` to round-off until
/// `t1` (1e-10), then obeys `Δp_x + μ Δp_y = −μ m g (t − t1)` from `t1` while it slides (1e-10,
/// as the sliding block of `dynamics.rs`) and stops at `t1 + v0 / (μ g)` (within two steps);
/// Lemke and the active set agree (momenta to 1e-10 of `m v0`).
#[test]
fn a_steps_friction_holds_during_the_step() {
    let (v0, t1) = (0.3, 0.5);
    let stop = t1 + v0 / (MU * G);
    let steps =
        format!("[[step]]\ntime = {t1}\nfriction = 0.0\n[[step]]\ntime = 1.0\nfriction = {MU}\n");
    let runs: Vec<(DynamicOutcome, f64)> = ["", "solver = \"active_set\"\n"]
        .iter()
        .map(|solver| run(&block(MU, v0, 0.0, stop + 0.3, &format!("{solver}{steps}"))))
        .collect();
    for (k, (outcome, m)) in runs.iter().enumerate() {
        let records = &outcome.simulation.history.records;
        let at = records.iter().position(|r| (r.time - t1).abs() < 1e-9).expect("t1 a record");
        let (p1, free) = (records[at].momentum, &records[..=at]);
        let frictionless = free.iter().map(|r| (r.momentum[0] - m * v0).abs()).fold(0.0, f64::max);
        let sliding = records[at..].iter().filter(|r| r.time <= t1 + 0.9 * (stop - t1));
        let coulomb = sliding
            .map(|r| {
                let dp = [r.momentum[0] - p1[0], r.momentum[1] - p1[1]];
                (dp[0] + MU * dp[1] + MU * m * G * (r.time - t1)).abs()
            })
            .fold(0.0, f64::max);
        let stopped =
            records.iter().find(|r| r.momentum[0] <= 1e-3 * m * v0).expect("it stops").time;
        println!(
            "{}: frictionless to t1 {:.2e}, Coulomb after {:.2e} of m v0, stops at {stopped:.4} (exact {stop:.4})",
            ["Lemke", "active set"][k],
            frictionless / (m * v0),
            coulomb / (m * v0)
        );
        assert!(frictionless < 1e-10 * m * v0, "slowed before t1: {frictionless}");
        assert!(coulomb < 1e-10 * m * v0, "Coulomb's identity off by {coulomb}");
        assert!((stopped - stop).abs() <= 2.0 * H + 1e-12, "stops at {stopped}");
    }
    let (lemke, active) = (&runs[0].0.simulation.history.records, &runs[1].0.simulation.history);
    let m = runs[0].1;
    let apart = lemke
        .iter()
        .zip(&active.records)
        .map(|(a, b)| {
            (a.momentum[0] - b.momentum[0]).abs().max((a.momentum[1] - b.momentum[1]).abs())
        })
        .fold(0.0, f64::max);
    println!("Lemke against the active set: momenta {:.2e} of m v0", apart / (m * v0));
    assert!(apart < 1e-10 * m * v0, "the solvers differ by {apart}");
    // The same block as a scene of pairs (`[[body]]`, `[[contact]]`: the several bodies' path,
    // each pair's coefficients per step) gives the same momenta.
    let scene = format!(
        r#"
        [[body]]
        name = "block"
        geometry = {{ kind = "rectangle", x = [0.0, 1.0], y = [0.0, 0.25] }}
        nodes = {{ spacing = 0.05 }}
        material = {{ young = 1000.0, poisson = 0.3, plane = "stress", density = 1.0 }}
        body_force = [0.0, -1.0]
        initial_velocity = [{v0}, 0.0]
        [[contact]]
        body = "block"
        edge = "bottom"
        obstacle_point = [0.0, 0.0]
        obstacle_normal = [0.0, 1.0]
        friction = {MU}
        [dynamics]
        end_time = {}
        time_step = {H}
        theta = 0.6
        {steps}
        "#,
        stop + 0.3
    );
    let (pairs, _) = run(&Problem::from_toml(&scene).expect("the scene"));
    let apart = lemke
        .iter()
        .zip(&pairs.simulation.history.records)
        .map(|(a, b)| {
            (a.momentum[0] - b.momentum[0]).abs().max((a.momentum[1] - b.momentum[1]).abs())
        })
        .fold(0.0, f64::max);
    println!("[contact] against [[contact]]: momenta {:.2e} of m v0", apart / (m * v0));
    assert!(apart < 1e-10 * m * v0, "the scene of pairs differs by {apart}");
}
