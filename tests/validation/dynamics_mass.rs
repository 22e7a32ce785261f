//! The finite elements' consistent mass `ρ ∫ N_a N_b dA` against the HRZ lumped one
//! (`[dynamics] mass = "consistent"`, docs/method.md §10.1; docs/dev/dynamics.md, section
//! "Consistent against lumped FE mass"): the total mass, the FE bar impact against the exact
//! 1-D wave solution, a free vibrating cantilever's first period against Euler–Bernoulli, the
//! energy balance at θ = ½ without contact, and the active-set step against Lemke's on the
//! consistent `M̂`.
//!
//! The bar (as `tests/validation/dynamics.rs`): L = 1, H = 0.1, E = ρ = 1, ν = 0, plane
//! stress, v0 = 0.1 towards a rigid wall at g = 0.01; exact: contact from 0.1 for 2 L / c = 2
//! under ρ c v0 H = 0.01, rebound at +v0.

use mlpg_contact::pipeline::dynamics::{DynamicBody, DynamicOutcome, solve};
use mlpg_contact::problem::Problem;
use mlpg_contact::progress::Silent;

const L: f64 = 1.0;
const H: f64 = 0.1;
const V0: f64 = 0.1;
const GAP: f64 = 0.01;

/// The FE bar at element size `size`, step `size / 2c`, until after the rebound, with
/// `mass` and the contact `solver`.
fn bar(size: f64, mass: &str, solver: &str) -> Problem {
    let h = size / 2.0;
    let end = GAP / V0 + 2.0 * L + 0.5;
    let text = format!(
        r#"
        [geometry]
        kind = "rectangle"
        x = [0.0, {L}]
        y = [0.0, {H}]
        [nodes]
        spacing = {size}
        layout = "structured"
        [discretisation]
        method = "fem"
        [material]
        young = 1.0
        poisson = 0.0
        plane = "stress"
        density = 1.0
        [contact]
        edge = "left"
        obstacle_point = [{}, 0.0]
        obstacle_normal = [1.0, 0.0]
        solver = "{solver}"
        [dynamics]
        end_time = {end}
        time_step = {h}
        initial_velocity = [-{V0}, 0.0]
        mass = "{mass}"
        "#,
        -GAP
    );
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("bar problem: {e}"))
}

/// The bar's errors relative to the exact solution: contact duration, mean force, rebound
/// velocity, and the force's oscillation about the exact force (rms of the per-step force
/// over t ∈ [0.5, 1.7], inside the contact, relative).
fn bar_errors(outcome: &DynamicOutcome) -> [f64; 4] {
    let f = outcome.simulation.figures(outcome.dynamics.time_step);
    let exact = 2.0 * L * V0 * H / (2.0 * L);
    let duration = f.contact.contact_duration.expect("contact");
    let force = f.contact.mean_contact_force.expect("a force");
    let inside: Vec<f64> = outcome
        .simulation
        .history
        .records
        .iter()
        .filter(|r| (0.5..=1.7).contains(&r.time))
        .map(|r| (r.contact_force - exact).powi(2))
        .collect();
    let spread = (inside.iter().sum::<f64>() / inside.len() as f64).sqrt() / exact;
    [
        (duration - 2.0 * L) / (2.0 * L),
        (force - exact) / exact,
        (f.final_velocity[0] - V0) / V0,
        spread,
    ]
}

/// The consistent mass's total equals the lumped one's and `ρ L H` (its entries summed per
/// direction), and both start with the exact momentum; the bar impact with either mass is
/// within 3 %/3 %/5 % of the exact duration, mean force and rebound at L/40 (measured:
/// docs/dev/dynamics.md), and the consistent mass's errors fall from L/20 to L/40.
#[test]
fn fe_bar_impact_with_the_consistent_and_the_lumped_mass() {
    let mut errors = Vec::new();
    for mass in ["lumped", "consistent"] {
        for n in [20.0, 40.0] {
            let outcome = solve(&bar(L / n, mass, "lemke"), &mut Silent).expect("the run");
            let total: f64 = outcome.simulation.mass.iter().step_by(2).sum();
            assert!((total - L * H).abs() < 1e-14, "{mass}: total mass {total}");
            let p0 = outcome.simulation.history.records[0].momentum[0];
            assert!((p0 + L * H * V0).abs() < 1e-15, "{mass}: initial momentum {p0}");
            let e = bar_errors(&outcome);
            println!(
                "FE bar {mass} L/{n}: duration {:+.2} %, mean force {:+.2} %, rebound {:+.2} %, force spread {:.1} %",
                100.0 * e[0],
                100.0 * e[1],
                100.0 * e[2],
                100.0 * e[3]
            );
            if n == 40.0 {
                assert!(
                    e[0].abs() < 0.03 && e[1].abs() < 0.03 && e[2].abs() < 0.05,
                    "{mass}: {e:?}"
                );
            }
            errors.push(e);
        }
    }
    let (coarse, fine) = (errors[2], errors[3]);
    for k in 0..3 {
        assert!(fine[k].abs() <= coarse[k].abs(), "consistent error {k}: {coarse:?} to {fine:?}");
    }
}

/// Contact on the consistent `M̂`: the active-set step (the sparse `Bodies` on `M̂` with the
/// gap rows) equals Lemke's on `W = G M̂⁻¹ E` for the FE bar at L/40 (forces within 1e-9 of
/// the peak, as `dynamics_active_set.rs`), the same index sets at every step.
#[test]
fn consistent_mass_active_set_equals_lemke() {
    let lemke = solve(&bar(L / 40.0, "consistent", "lemke"), &mut Silent).expect("Lemke");
    let sparse = solve(&bar(L / 40.0, "consistent", "active_set"), &mut Silent).expect("sparse");
    let (a, b) = (&lemke.simulation.history.records, &sparse.simulation.history.records);
    assert_eq!(a.len(), b.len());
    let peak = a.iter().fold(0.0_f64, |m, r| m.max(r.contact_force));
    let mut force: f64 = 0.0;
    for (r, s) in a.iter().zip(b) {
        assert_eq!(r.active, s.active, "index sets at t = {}", r.time);
        force = force.max((r.contact_force - s.contact_force).abs());
    }
    let velocity = lemke
        .simulation
        .velocity
        .iter()
        .zip(&sparse.simulation.velocity)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    println!(
        "consistent FE bar L/40: active set against Lemke: forces {:.2e} of the peak, final velocities {:.2e} of v0",
        force / peak,
        velocity / V0
    );
    assert!(peak > 0.0 && force <= 1e-9 * peak, "forces differ by {force:e} (peak {peak:e})");
    assert!(velocity <= 1e-9 * V0, "final velocities differ by {velocity:e}");
}

/// The cantilever of length `LENGTH` (ν = 0, E = ρ = 1), clamped at x = 0.
const LENGTH: f64 = 1.0;
/// The steps per Euler–Bernoulli period (the θ = ½ step lengthens the period by
/// `(ω h)² / 12` = 8e-5).
const STEPS_PER_PERIOD: f64 = 206.0;
/// The periods run after the ramp.
const PERIODS: f64 = 8.0;

/// Euler–Bernoulli's first period of the cantilever of `depth`: `ω = 1.8751² √(E I / (ρ A
/// L⁴))`, per unit thickness `I = H³/12`, `A = H`.
fn euler_bernoulli_period(depth: f64) -> f64 {
    let lambda: f64 = 1.875_104_068_711_961;
    let omega = lambda * lambda * (depth * depth / 12.0).sqrt() / (LENGTH * LENGTH);
    2.0 * std::f64::consts::PI / omega
}

/// The cantilever of `depth`, Q9 of size `size`, under a tip shear ramped over half a period
/// then held, θ = ½, with `mass`.
fn cantilever(depth: f64, size: f64, mass: &str) -> Problem {
    let period = euler_bernoulli_period(depth);
    let (step, ramp) = (period / STEPS_PER_PERIOD, period / 2.0);
    let end = ramp + PERIODS * period;
    let text = format!(
        r#"
        [geometry]
        kind = "rectangle"
        x = [0.0, {LENGTH}]
        y = [0.0, {depth}]
        [nodes]
        spacing = {size}
        layout = "structured"
        [discretisation]
        method = "fem"
        [material]
        young = 1.0
        poisson = 0.0
        plane = "stress"
        density = 1.0
        [[boundary]]
        edge = "left"
        displacement = {{ x = 0.0, y = 0.0 }}
        [[boundary]]
        edge = "right"
        traction = {{ y = -1e-6 }}
        [dynamics]
        end_time = {end}
        time_step = {step}
        load_ramp = {ramp}
        mass = "{mass}"
        [dynamics.output]
        every = 1
        "#
    );
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("cantilever problem: {e}"))
}

/// The cantilever's first period from its free vibration after the ramp: the mean spacing of
/// the downward zero crossings of the tip's (x = L, y = H/2) transverse velocity (linearly
/// interpolated between steps) over the run's periods; and the run's energy balance error.
fn cantilever_period(depth: f64, size: f64, mass: &str) -> (f64, f64) {
    let problem = cantilever(depth, size, mass);
    let outcome = solve(&problem, &mut Silent).expect("the cantilever run");
    let ramp = problem.dynamics.as_ref().and_then(|d| d.load_ramp).expect("a ramp");
    let DynamicBody::Fem(parts) = &outcome.body else { panic!("an FE body") };
    let tip = parts
        .nodes
        .points
        .iter()
        .position(|p| (p[0] - LENGTH).abs() < 1e-12 && (p[1] - depth / 2.0).abs() < 1e-12)
        .expect("a node at the tip's mid-depth");
    let samples: Vec<(f64, f64)> = outcome
        .simulation
        .frames
        .iter()
        .map(|f| (f.time, f.bodies[0].velocity[tip][1]))
        .filter(|&(t, _)| t >= ramp)
        .collect();
    let crossings: Vec<f64> = samples
        .windows(2)
        .filter(|w| w[0].1 > 0.0 && w[1].1 <= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1))
        .collect();
    assert!(crossings.len() >= 4, "crossings {crossings:?}");
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let f = outcome.simulation.figures(outcome.dynamics.time_step);
    (period, f.energy_balance_error)
}

/// The slender cantilever (L/H = 20, where Timoshenko's shear and rotary inertia lengthen
/// the first period by about 0.12 %) at Q9 of size H/2 (40 × 2 elements): the first period
/// with either mass within 0.5 % of Euler–Bernoulli's (measured +0.146 %), the two masses'
/// periods within 1e-4 of each other (measured 2e-7: the first mode is resolved, the mass's
/// form does not matter), and at θ = ½ without contact the energy kept to 1e-8 of its
/// largest value by both (1.6e-10). Then the thick one (L/H = 5, 10 × 2 and 20 × 4 elements)
/// is printed (docs/dev/dynamics.md, with the finer meshes).
#[test]
fn cantilever_period_with_the_consistent_and_the_lumped_mass() {
    let depth = 0.05;
    let exact = euler_bernoulli_period(depth);
    for size in [depth / 2.0] {
        let mut periods = Vec::new();
        for mass in ["lumped", "consistent"] {
            let (period, balance) = cantilever_period(depth, size, mass);
            let error = (period - exact) / exact;
            println!(
                "cantilever L/H = 20, Q9 {:.0}×{:.0} {mass}: first period {period:.5} (Euler–Bernoulli {exact:.5}, {:+.4} %), energy balance {balance:.1e}",
                LENGTH / size,
                depth / size,
                100.0 * error
            );
            assert!(error.abs() < 0.005, "{mass} at {size}: period {period} against {exact}");
            assert!(balance < 1e-8, "{mass} at {size}: energy balance {balance:e}");
            periods.push(period);
        }
        let apart = (periods[1] - periods[0]) / periods[0];
        println!("consistent against lumped: {apart:+.2e}");
        assert!(apart.abs() < 1e-4, "consistent {} against lumped {}", periods[1], periods[0]);
    }
    let depth = 0.2;
    let exact = euler_bernoulli_period(depth);
    for size in [depth / 2.0, depth / 4.0] {
        for mass in ["lumped", "consistent"] {
            let (period, balance) = cantilever_period(depth, size, mass);
            println!(
                "cantilever L/H = 5, Q9 {:.0}×{:.0} {mass}: first period {period:.5} ({:+.4} % of Euler–Bernoulli's {exact:.5}), energy balance {balance:.1e}",
                LENGTH / size,
                depth / size,
                100.0 * (period - exact) / exact
            );
        }
    }
}

/// The MFVM refuses the consistent mass, naming the key and the remedy.
#[test]
fn the_mfvm_refuses_the_consistent_mass() {
    let text = r#"
        [geometry]
        kind = "rectangle"
        x = [0.0, 1.0]
        y = [0.0, 0.1]
        [nodes]
        spacing = 0.05
        [material]
        young = 1.0
        poisson = 0.0
        plane = "stress"
        density = 1.0
        [dynamics]
        end_time = 1.0
        time_step = 0.1
        mass = "consistent"
        "#;
    let message = Problem::from_toml(text).expect_err("refused").to_string();
    assert!(message.contains("dynamics.mass"), "{message}");
    assert!(message.contains("method = \"fem\""), "{message}");
}

/// A moving support with the consistent mass: `problems/bar_displacement_pulse.toml` by Q9
/// keeps the energy balance to round-off with either mass (the consistent mass's free rows
/// feel the support's inertia `−M_fc Δv_c`, counted in the loads' work: without it the
/// balance was off by 1.0e-2; measured 5.4e-15, lumped 6.3e-15).
#[test]
fn a_moving_support_keeps_the_energy_balance_with_the_consistent_mass() {
    let path = format!("{}/problems/bar_displacement_pulse.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("the shipped file");
    for mass in ["lumped", "consistent"] {
        let text = text
            .replace("[material]", "[discretisation]\nmethod = \"fem\"\n\n[material]")
            .replace("[dynamics]\n", &format!("[dynamics]\nmass = \"{mass}\"\n"));
        let problem = Problem::from_toml(&text).unwrap_or_else(|e| panic!("{e}"));
        let outcome = solve(&problem, &mut Silent).expect("the run");
        let f = outcome.simulation.figures(outcome.dynamics.time_step);
        println!(
            "FE displacement pulse, {mass} mass: energy balance {:.1e}",
            f.energy_balance_error
        );
        assert!(f.external_work > 0.0, "the support works on the bar");
        assert!(f.energy_balance_error < 1e-12, "{mass}: {:e}", f.energy_balance_error);
    }
}
