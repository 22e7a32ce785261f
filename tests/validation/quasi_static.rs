//! The quasi-static limit of the elastodynamic contact (docs/dev/dynamics.md, increment 12):
//! the paper's beam on a rigid foundation (`problems/beam_on_foundation.toml`, spacing 1,
//! density 1) with its load ramped from 0 over a time `T_r` (`[dynamics] load_ramp`) and
//! θ > ½ for numerical damping. As `T_r` grows the state at the ramp's end approaches the
//! static solution of the same file, which is the reference: it is computed by the static
//! solver of this repository (the factorised `K`, the condensed compliance `G K⁻¹ E`, Lemke),
//! an independent path from the time stepping (the factorised `M Φ + h²θ² K`, the condensed
//! `G M̂⁻¹ E`, one velocity-level LCP per step).
//!
//! Spacing 1 (343 nodes), step h = 0.7 (the first bending period is ≈ 14), θ = 0.6 (damping
//! per step ≈ (θ − ½) h² ω² ≈ 1 % at the first mode). Measured in
//! `cargo test --release --test validation quasi_static -- --nocapture` (docs/dev/dynamics.md):
//! at T_r = 280, 560, 1120 the total contact force's error is 1.1e-3, 5.6e-4, 3.0e-4 (rate
//! ≈ 1: the lag of a damped response behind a ramp is proportional to the ramp's rate), the
//! kinetic energy over the strain energy 5.2e-8, 1.3e-8, 3.3e-9 (rate 2). The displacements
//! and the candidates' forces keep an error of about 1 % that does not shrink with `T_r`:
//! velocity-level contact leaves the penetration of the first impact (the tip closes the gap
//! 0.01 within a fraction of the first period whatever the ramp, at a speed of about 1e-2,
//! and penetrates O(h v) ≈ 1e-4 = 1 % of the gap; nothing restores positions). The same run
//! without contact reaches the static displacement to 1.4e-8 at T_r = 560.

use mlpg_contact::dynamics::energy;
use mlpg_contact::pipeline::dynamics::{DynamicBody, solve};
use mlpg_contact::problem::{Problem, ProblemFile, file::DynamicsFile};
use mlpg_contact::progress::Silent;

fn shipped_with_gap(gap: f64, spacing: f64) -> ProblemFile {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/beam_on_foundation.toml");
    let text = std::fs::read_to_string(path).expect("the shipped beam");
    let text = text.replace(
        "obstacle_point = [0.0, -3.01]",
        &format!("obstacle_point = [0.0, {}]", -3.0 - gap),
    );
    assert!(text.contains(&format!("{}]", -3.0 - gap)), "the obstacle moved");
    let mut file = ProblemFile::from_toml(&text).expect("parse");
    file.nodes.as_mut().expect("nodes").spacing = Some(spacing);
    file
}

/// The dynamic beam: density 1, the load ramped over `ramp` and held until `end`, step `h`.
fn dynamic_beam(ramp: f64, end: f64, h: f64, theta: f64, gap: f64, spacing: f64) -> Problem {
    let mut file = shipped_with_gap(gap, spacing);
    file.material.as_mut().expect("material").density = Some(1.0);
    file.dynamics = Some(DynamicsFile {
        end_time: end,
        time_step: h,
        theta: Some(theta),
        load_ramp: Some(ramp),
        ..DynamicsFile::default()
    });
    Problem::try_from(file).expect("valid")
}

/// What the dynamic run gives at its end, relative to the static solution.
#[derive(Debug)]
struct Limit {
    /// `|Σ Π / h − Σ P| / Σ P`.
    force: f64,
    /// `max_c |Π_c / h − P_c| / Σ P`.
    pressure: f64,
    /// `max_I |u^h(x_I) − u_static(x_I)| / max_I |u_static(x_I)|`.
    displacement: f64,
    /// `|E_strain − E_strain,static| / E_strain,static` (the same collocated measure).
    strain_energy: f64,
    /// `E_kin / E_strain`.
    kinetic: f64,
    /// The energy taken by the contact impulses over the run, relative to the loads' work.
    contact_loss: f64,
    /// Whether a candidate has a positive impulse over the last step exactly where the
    /// static solution has a positive force.
    same_contact_set: bool,
    /// The smallest final gap relative to the initial gap (negative: penetration).
    penetration: f64,
    /// The largest |gap| of a candidate with a positive impulse, relative to the initial gap.
    pushing_gap: f64,
    /// The smallest impulse of the last step (Lemke's `z ≥ 0`).
    least_impulse: f64,
}

/// The beam with its load ramped over `ramp`, the ramp's end compared with the static solve.
fn limit(ramp: f64, h: f64, theta: f64, gap: f64, spacing: f64) -> Limit {
    let static_problem = Problem::try_from(shipped_with_gap(gap, spacing)).expect("valid");
    let reference = mlpg_contact::solve(&static_problem).expect("the static solve");
    let contact = reference.contact().expect("contact");
    let problem = dynamic_beam(ramp, ramp, h, theta, gap, spacing);
    let outcome = solve(&problem, &mut Silent).expect("dynamic run");
    let sim = &outcome.simulation;
    let DynamicBody::Mfvm(parts) = &outcome.body else { panic!("an MFVM body") };
    let candidates = outcome.candidates.as_ref().expect("candidates");
    assert_eq!(candidates.points, contact.candidates.points, "the same candidates");
    let total = contact.total_force;
    let forces: Vec<f64> = sim.final_impulses.iter().map(|p| p / h).collect();
    let pressure =
        forces.iter().zip(&contact.lcp.z).map(|(f, p)| (f - p).abs() / total).fold(0.0, f64::max);
    let shapes = &parts.node_shapes;
    let mut worst: f64 = 0.0;
    for (i, s) in reference.displacement.iter().enumerate() {
        let u = shapes.interpolate(i, &sim.displacement);
        worst = worst.max((u[0] - s[0]).hypot(u[1] - s[1]));
    }
    let largest = reference.displacement.iter().map(|s| s[0].hypot(s[1])).fold(0.0, f64::max);
    let d = static_problem.material.constitutive();
    let static_energy = energy::strain(shapes, &parts.mfvm.cells, &d, &reference.nodal_parameters);
    let last = sim.history.records.last().expect("records");
    let impulses = &sim.final_impulses;
    Limit {
        force: (forces.iter().sum::<f64>() - total).abs() / total,
        pressure,
        displacement: worst / largest,
        strain_energy: (last.strain_energy - static_energy).abs() / static_energy,
        kinetic: last.kinetic_energy / last.strain_energy,
        contact_loss: sim.figures(h).contact_loss / last.external_work,
        same_contact_set: impulses
            .iter()
            .zip(&contact.lcp.z)
            .all(|(a, b)| (*a > 0.0) == (*b > 0.0)),
        penetration: sim.final_gap.iter().copied().fold(f64::INFINITY, f64::min) / gap,
        pushing_gap: impulses
            .iter()
            .zip(&sim.final_gap)
            .filter(|(p, _)| **p > 0.0)
            .map(|(_, g)| g.abs() / gap)
            .fold(0.0, f64::max),
        least_impulse: impulses.iter().copied().fold(f64::INFINITY, f64::min),
    }
}

/// The quasi-static limit on the shipped beam (gap 0.01, spacing 1): as the ramp time doubles
/// (280, 560, 1120) the total contact force's error against the static solve halves (a
/// factor of at least 1.5 per doubling: the lag behind a ramp is first order in its rate;
/// measured 2.0, 1.9) and is below 1e-3 at the slowest (measured 3.0e-4); the kinetic energy
/// vanishes (a factor of at least 3 per doubling: the velocity is first order, the energy
/// second; measured 4.0, 4.0); the strain energy is the static one's within 2e-3 (measured
/// 7.0e-4 … 1.3e-3); the energy the impacts take, relative to the loads' work, decreases
/// and is below 5e-3 at the slowest (measured 2.0e-2, 6.9e-3, 2.1e-4). Complementarity at the end: the candidates pushing are exactly the
/// static solution's closed set, every impulse is ≥ 0 (Lemke), and every gap, open or
/// pushing, is within 5 % of the initial gap of zero or positive: the velocity-level floor of
/// the first impact's penetration (measured 0.9–1.6 %, not shrinking with `T_r`, module
/// docs); the displacements and the candidates' forces are within 3 % of the static ones
/// (that floor again; measured 0.9–1.6 % and 0.8–1.4 %).
#[test]
fn slow_ramp_approaches_the_static_contact_solution() {
    let ramps = [280.0, 560.0, 1120.0];
    let limits: Vec<Limit> = ramps.iter().map(|&r| limit(r, 0.7, 0.6, 0.01, 1.0)).collect();
    for (ramp, l) in ramps.iter().zip(&limits) {
        println!("T_r = {ramp}: {l:?}");
        assert!(l.same_contact_set, "T_r = {ramp}: the pushing set differs from the static one");
        assert!(l.least_impulse >= 0.0, "T_r = {ramp}: impulse {}", l.least_impulse);
        assert!(l.penetration > -0.05, "T_r = {ramp}: penetration {}", l.penetration);
        assert!(l.pushing_gap < 0.05, "T_r = {ramp}: a pushing candidate's gap {}", l.pushing_gap);
        assert!(l.displacement < 0.03, "T_r = {ramp}: displacement error {}", l.displacement);
        assert!(l.pressure < 0.03, "T_r = {ramp}: candidate force error {}", l.pressure);
        assert!(l.strain_energy < 2e-3, "T_r = {ramp}: strain energy error {}", l.strain_energy);
    }
    for (pair, r) in limits.windows(2).zip(ramps.windows(2)) {
        let force_rate = pair[0].force / pair[1].force;
        let kinetic_rate = pair[0].kinetic / pair[1].kinetic;
        println!(
            "T_r {} → {}: force error ÷ {force_rate:.2}, kinetic ÷ {kinetic_rate:.2}",
            r[0], r[1]
        );
        assert!(force_rate > 1.5, "force error {} → {}", pair[0].force, pair[1].force);
        assert!(kinetic_rate > 3.0, "kinetic {} → {}", pair[0].kinetic, pair[1].kinetic);
        assert!(pair[1].contact_loss < pair[0].contact_loss, "contact loss grows");
    }
    let slowest = &limits[limits.len() - 1];
    assert!(slowest.force < 1e-3, "force error {}", slowest.force);
    assert!(slowest.contact_loss < 5e-3, "contact loss {}", slowest.contact_loss);
}

/// `[dynamics] load_ramp` is checked: positive and at most `end_time`.
#[test]
fn load_ramp_is_checked_naming_the_key() {
    for (ramp, end) in [(-1.0, 10.0), (0.0, 10.0), (20.0, 10.0), (f64::NAN, 10.0)] {
        let mut file = shipped_with_gap(0.01, 1.0);
        file.material.as_mut().expect("material").density = Some(1.0);
        file.dynamics = Some(DynamicsFile {
            end_time: end,
            time_step: 1.0,
            load_ramp: Some(ramp),
            ..DynamicsFile::default()
        });
        let err = Problem::try_from(file).expect_err("refused").to_string();
        assert!(err.contains("dynamics.load_ramp"), "{ramp}: {err}");
    }
}

/// Without an impact there is no floor: started in contact (gap 1e-9, every candidate
/// touching at rest, so nothing closes by an impact) the displacements and the candidates'
/// forces converge to the static ones at rate 1 with the ramp time, like the total force —
/// the penetration is `O(h v)` with the closing speed `v ∝ 1/T_r`. Measured at T_r = 280,
/// 560, 1120: displacement 0.285, 0.143, 0.071 (÷ 2.00 per doubling), candidate force
/// 9.7e-5, 4.8e-5, 2.4e-5, total force 2.2e-3, 1.1e-3, 5.4e-4; the pushing set is the static
/// one. The tolerance (÷ 1.8 per doubling) asks for first order; the static displacement here
/// is the beam's small compression, so the relative error is large at these ramps (1e-3 needs
/// T_r ≈ 8e4: `examples/studies/quasi_static_limit.rs`, docs/dev/dynamics.md).
#[test]
fn ramp_started_in_contact_converges_without_a_floor() {
    let ramps = [280.0, 560.0, 1120.0];
    let limits: Vec<Limit> = ramps.iter().map(|&r| limit(r, 0.7, 0.6, 1e-9, 1.0)).collect();
    for (ramp, l) in ramps.iter().zip(&limits) {
        println!("T_r = {ramp}: {l:?}");
        assert!(l.same_contact_set, "T_r = {ramp}: the pushing set differs from the static one");
        assert!(l.least_impulse >= 0.0, "T_r = {ramp}: impulse {}", l.least_impulse);
        assert!(l.pressure < 2e-4, "T_r = {ramp}: candidate force error {}", l.pressure);
    }
    for pair in limits.windows(2) {
        for (what, a, b) in [
            ("displacement", pair[0].displacement, pair[1].displacement),
            ("candidate force", pair[0].pressure, pair[1].pressure),
            ("total force", pair[0].force, pair[1].force),
        ] {
            println!("{what}: {a:.3e} → {b:.3e} (÷ {:.2})", a / b);
            assert!(a / b > 1.8, "{what} error {a} → {b}: not first order");
        }
    }
}
