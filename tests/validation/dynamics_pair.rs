//! Two elastic bodies in elastodynamic contact (docs/method.md §10, increment 10 of
//! docs/dev/dynamics.md): St Venant's impact of two equal free bars.
//!
//! Reference: two strips of length `L`, height `H`, plane stress with ν = 0 (exactly
//! one-dimensional), `E = ρ = 1` (`c = 1`). The striker moves at `v0` towards the struck bar
//! at rest across a gap `g`. The 1-D wave solution (Graff, Wave Motion in Elastic Solids,
//! §2.3): contact from `g / v0` for `2 L / c` under the force `ρ c (v0 / 2) H` per unit
//! thickness; after it the striker is at rest and the struck bar moves at `v0`. The
//! problem is `problems/two_bars_impact.toml`'s at spacing L/80 (the shipped file is at L/40).

use mlpg_contact::pipeline::dynamics::solve;
use mlpg_contact::problem::Problem;
use mlpg_contact::progress::Silent;

const L: f64 = 1.0;
const H: f64 = 0.1;
const V0: f64 = 0.1;
const GAP: f64 = 0.01;

/// The two bars at `spacing`, step `spacing / (2 c)`, until after the separation; `extra` is
/// appended to the file.
fn bars(spacing: f64, extra: &str) -> String {
    let h = spacing / 2.0;
    let end = GAP / V0 + 2.0 * L + 0.5;
    let body = |name: &str, x0: f64, velocity: &str| {
        format!(
            "[[body]]\nname = \"{name}\"\ngeometry = {{ kind = \"rectangle\", x = [{x0}, {}], y = [0.0, {H}] }}\nnodes = {{ spacing = {spacing}, layout = \"structured\" }}\nmaterial = {{ young = 1.0, poisson = 0.0, plane = \"stress\", density = 1.0 }}\n{velocity}\n",
            x0 + L
        )
    };
    format!(
        "{}{}[contact]\nedge = \"right\"\ntarget_edge = \"left\"\n{extra}\n[dynamics]\nend_time = {end}\ntime_step = {h}\n",
        body("striker", 0.0, &format!("initial_velocity = [{V0}, 0.0]")),
        body("struck", L + GAP, ""),
    )
}

/// At L/80: the contact duration within 2 % of `2L/c`, the mean force within 3 % of
/// `ρ c (v0/2) H`, the bars' velocities after the separation within 5 % of `v0` (the striker
/// at rest, the struck bar at `v0`), the total momentum `ρ L H v0` at every step to round-off,
/// and every step's impulses complementary to the post-step relative velocities. Measured:
/// duration +1.25 %, force −2.37 % (the one-body bar's errors at L/80; they halve with the
/// spacing, docs/dev/dynamics.md), velocities ±1.15 % of `v0`. The force is within 2 % only at L/160, which
/// takes ~7 s: too slow for CI, so 3 % here.
#[test]
fn equal_bars_exchange_their_velocities() {
    let problem = Problem::from_toml(&bars(L / 80.0, "")).unwrap();
    let outcome = solve(&problem, &mut Silent).expect("the two-bar run");
    let h = outcome.dynamics.time_step;
    let f = outcome.simulation.figures(h);
    let duration = f.contact_duration.expect("the bars touch");
    let force = f.mean_contact_force.expect("a contact force");
    let start = f.contact_start.expect("contact");
    assert!((start - GAP / V0).abs() <= h + 1e-12, "contact starts at {start}");
    let rel = |a: f64, b: f64| (a - b) / b;
    let errors = [rel(duration, 2.0 * L), rel(force, V0 / 2.0 * H)];
    let pair = outcome.pair.as_ref().expect("two bodies");
    let [striker, struck] = [&pair.ends[0], &pair.ends[1]];
    let velocities = [striker.mean_velocity()[0] / V0, rel(struck.mean_velocity()[0], V0)];
    println!(
        "duration {:+.3e}, force {:+.3e}; striker {:+.3e} v0, struck {:+.3e}",
        errors[0], errors[1], velocities[0], velocities[1]
    );
    assert!(errors[0].abs() <= 0.02, "duration {duration} ({:+.2e})", errors[0]);
    assert!(errors[1].abs() <= 0.03, "mean force {force} ({:+.2e})", errors[1]);
    assert!(velocities[0].abs() <= 0.05, "striker after: {:?}", striker.mean_velocity());
    assert!(velocities[1].abs() <= 0.05, "struck after: {:?}", struck.mean_velocity());
    // Momentum: no load acts, the impulses are equal and opposite.
    let p0 = L * H * V0;
    for r in &outcome.simulation.history.records {
        let p = r.momentum;
        assert!(
            (p[0] - p0).abs() <= 1e-12 * p0 && p[1].abs() <= 1e-12 * p0,
            "t = {}: {p:?}",
            r.time
        );
    }
    // The final impulses of the last contact step are non-negative; the bars separate.
    assert!(outcome.simulation.final_impulses.iter().all(|&z| z >= 0.0));
    assert!(outcome.simulation.final_gap.iter().all(|&g| g > 0.0), "the bars separate");
    assert!(f.contact_steps > 0 && f.energy_balance_error < 0.01, "{f:?}");
}

/// What the two-body time stepping does not support is refused naming the key.
#[test]
fn two_body_dynamics_refusals_name_the_key() {
    let refused = |extra: &str, key: &str| {
        let err = Problem::from_toml(&bars(0.05, extra)).unwrap_err().to_string();
        assert!(err.contains(key), "{extra}: {err}");
    };
    refused("interference = 0.001", "contact.interference");
    let text =
        bars(0.05, "").replace("[dynamics]\n", "[dynamics]\ninitial_velocity = [0.1, 0.0]\n");
    let err = Problem::from_toml(&text).unwrap_err().to_string();
    assert!(err.contains("body[0].initial_velocity") && err.contains("not both"), "{err}");
    let text =
        bars(0.05, "").replace("initial_velocity = [0.1, 0.0]", "initial_velocity = [1e300, 0.0]");
    let err = Problem::from_toml(&text).unwrap_err().to_string();
    assert!(err.contains("body[0].initial_velocity"), "{err}");
    let text = bars(0.05, "").replace("[dynamics]\n", "[dynamics.output]\nevery = 5\n[dynamics]\n");
    assert!(Problem::from_toml(&text).is_err());
    let statics = bars(0.05, "");
    let statics = &statics[..statics.find("[dynamics]").unwrap()];
    let err = Problem::from_toml(statics).unwrap_err().to_string();
    assert!(err.contains("body[0].initial_velocity"), "{err}");
}

/// A block `[0, 1] × [0, 0.25]` (E = 1000, ν = 0.3, ρ = 1, gravity `g = 1`) sliding at `v0`
/// on an elastic slab `[−0.25, 1.5] × [−0.25, 0]` (the same material, no gravity) held on its
/// bottom edge, with Coulomb friction `μ` between them; spacing 0.05, h = 0.01, θ = 0.6.
fn block_on_slab(mu: f64, v0: f64, end_time: f64) -> Problem {
    let body = |name: &str, y: [f64; 2], x: [f64; 2], extra: &str| {
        format!(
            "[[body]]\nname = \"{name}\"\ngeometry = {{ kind = \"rectangle\", x = [{}, {}], y = [{}, {}] }}\nnodes = {{ spacing = 0.05 }}\nmaterial = {{ young = 1000.0, poisson = 0.3, plane = \"stress\", density = 1.0 }}\n{extra}\n",
            x[0], x[1], y[0], y[1]
        )
    };
    let text = format!(
        "{}{}[contact]\nedge = \"bottom\"\ntarget_edge = \"top\"\nfriction = {mu}\n[dynamics]\nend_time = {end_time}\ntime_step = 0.01\ntheta = 0.6\n",
        body(
            "block",
            [0.0, 0.25],
            [0.0, 1.0],
            &format!("body_force = [0.0, -1.0]\ninitial_velocity = [{v0}, 0.0]")
        ),
        body(
            "slab",
            [-0.25, 0.0],
            [-0.25, 1.5],
            "boundary = [{ edge = \"bottom\", displacement = { x = 0.0, y = 0.0 } }]"
        ),
    );
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("block on a slab: {e}"))
}

/// Friction between two bodies: while every contact slides, each step's tangential impulses
/// are `−μ` times its normal ones on the block, so the block's momenta obey
/// `p_x + μ p_y = m v0 − μ m g t` whatever the slab does (checked at 0.9 of the analytic
/// stopping time `v0 / (μ g)` to 1e-10 of `m v0`; measured 6.3e-13), and its mean velocity
/// is Coulomb's `v0 − μ g t` within 1e-3 v0 (measured 1.7e-4 v0: `p_y` oscillates about
/// `0`); the block stops near that time and stays (its mean velocity at 1.5 times it below
/// 1e-2 v0, measured 1.7e-3 v0: the slab's and its own vibration). Frictionless (μ = 0) it
/// keeps `v0` to 1e-10 (measured 2e-13).
#[test]
fn block_on_elastic_slab_decelerates_at_mu_g() {
    let (mu, v0, g) = (0.3, 0.3, 1.0);
    let stop = v0 / (mu * g);
    let end = |mu: f64, t: f64| {
        let outcome = solve(&block_on_slab(mu, v0, t), &mut Silent).expect("the block run");
        let pair = outcome.pair.expect("two bodies");
        let [block, _] = pair.ends;
        (block.mass, block.momentum)
    };
    let t = 0.9 * stop;
    let (m, p) = end(mu, t);
    let identity = (p[0] + mu * p[1] - (m * v0 - mu * m * g * t)).abs() / (m * v0);
    let (_, after) = end(mu, 1.5 * stop);
    let (_, free) = end(0.0, 0.5);
    println!(
        "block on slab (m = {m}): identity at 0.9 t_stop {identity:.3e}, v_x at 0.9 t_stop {:.4e} (Coulomb {:.4e}), at 1.5 t_stop {:.3e}; frictionless {:.3e}",
        p[0] / m,
        v0 - mu * g * t,
        after[0] / m,
        free[0] / m - v0
    );
    assert!(identity < 1e-10, "p_x + μ p_y off by {identity}");
    let coulomb = v0 - mu * g * t;
    assert!((p[0] / m - coulomb).abs() < 1e-3 * v0, "v_x {} against {coulomb}", p[0] / m);
    assert!((after[0] / m).abs() < 1e-2 * v0, "slides on at {}", after[0] / m);
    assert!((free[0] - m * v0).abs() < 1e-10 * m * v0, "frictionless p_x {}", free[0]);
}
