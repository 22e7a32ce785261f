//! The active-set solver per time step (docs/dev/dynamics.md increment 11): each step's
//! contact on the sparse system of the bodies' `M̂` (no condensed `W`) against Lemke's
//! method on `W`, on the shipped bar impact (one body against a rigid wall), Newton's
//! cradle (three bodies, two pairs), both at L/40, and the block on a slab with friction.
//!
//! Both solve the same LCP `0 ≤ Π ⊥ U_free + W Π + e U ≥ 0` on the same index set; Lemke's
//! answer is exact up to the dense pivoting's round-off, the active-set one up to the sparse
//! solves' (the row-replaced `M̂` solved by Woodbury updates and refined to ~1e-14). The
//! difference grows through the steps only as round-off does (the θ-method at θ = ½ is
//! neutrally stable), so 1e-9 of the run's largest force (resp. velocity) bounds it with
//! five digits of room above the ~1e-14 per step while far below any physical difference (a
//! candidate that enters the index set a step apart changes the force by its whole value).

use mlpg_contact::pipeline::dynamics::{DynamicOutcome, solve};
use mlpg_contact::problem::Problem;
use mlpg_contact::progress::Silent;

/// The shipped problem `name` with every contact pair on `solver`.
fn shipped(name: &str, solver: &str) -> Problem {
    let text = shipped_text(name, solver);
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("{name} with {solver}: {e}"))
}

/// The file of [`shipped`].
fn shipped_text(name: &str, solver: &str) -> String {
    let path = format!("{}/problems/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    // After each `[contact]` or `[[contact]]` header (a comment may follow it).
    let mut out = String::new();
    for line in text.lines() {
        out.push_str(line);
        out.push('\n');
        if line.starts_with("[contact]") || line.starts_with("[[contact]]") {
            out.push_str(&format!("solver = \"{solver}\"\n"));
        }
    }
    assert!(out.contains(&format!("solver = \"{solver}\"")), "{name} has a contact table");
    out
}

/// The largest difference between the runs' per-record contact forces (total and each
/// pair's) relative to the largest force, and between their final velocities relative to the
/// largest velocity; checks that the runs have the same records, index sets and contact.
fn differences(lemke: &DynamicOutcome, active_set: &DynamicOutcome) -> [f64; 2] {
    let (a, b) = (&lemke.simulation.history.records, &active_set.simulation.history.records);
    assert_eq!(a.len(), b.len(), "records");
    let largest = |x: &mut dyn Iterator<Item = f64>| x.fold(0.0_f64, |m, v| m.max(v.abs()));
    let peak = largest(&mut a.iter().map(|r| r.contact_force));
    assert!(peak > 0.0, "the run has contact");
    let mut force: f64 = 0.0;
    for (k, (r, s)) in a.iter().zip(b).enumerate() {
        assert_eq!(r.active, s.active, "record {k}: index set sizes");
        assert_eq!(r.pair_forces.len(), s.pair_forces.len());
        force = force.max((r.contact_force - s.contact_force).abs());
        for (p, q) in r.pair_forces.iter().zip(&s.pair_forces) {
            force = force.max((p - q).abs());
        }
    }
    let (v, w) = (&lemke.simulation.velocity, &active_set.simulation.velocity);
    assert_eq!(v.len(), w.len());
    let speed = largest(&mut v.iter().copied());
    let velocity = largest(&mut v.iter().zip(w).map(|(a, b)| a - b));
    [force / peak, velocity / speed]
}

/// The bar of `problems/bar_impact.toml` (L/40, 240 steps, up to 41 candidates in the index
/// set): the active-set run equals Lemke's within 1e-9 (module documentation), and its
/// every step's residual passes the run's check.
#[test]
fn bar_impact_on_the_active_set_equals_lemke() {
    let lemke = solve(&shipped("bar_impact", "lemke"), &mut Silent).expect("Lemke's run");
    let sparse = solve(&shipped("bar_impact", "active_set"), &mut Silent).expect("the sparse run");
    let [force, velocity] = differences(&lemke, &sparse);
    let h = sparse.dynamics.time_step;
    let f = sparse.simulation.figures(h);
    println!(
        "bar: forces differ by {force:.2e} of the peak, final velocities by {velocity:.2e}; residual {:.1e}; rebound {:.6} (Lemke {:.6})",
        f.max_step_residual,
        f.final_velocity[0],
        lemke.simulation.figures(h).final_velocity[0]
    );
    assert!(force <= 1e-9, "forces differ by {force:e} of the peak");
    assert!(velocity <= 1e-9, "final velocities differ by {velocity:e}");
    assert!(f.max_step_residual <= mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE, "{f:?}");
}

/// Newton's cradle of `problems/newtons_cradle.toml` (three bars at L/40, two pairs between
/// bodies): the same comparison, each pair's force included.
#[test]
fn newtons_cradle_on_the_active_set_equals_lemke() {
    let lemke = solve(&shipped("newtons_cradle", "lemke"), &mut Silent).expect("Lemke's run");
    let sparse =
        solve(&shipped("newtons_cradle", "active_set"), &mut Silent).expect("the sparse run");
    let [force, velocity] = differences(&lemke, &sparse);
    let f = sparse.simulation.figures(sparse.dynamics.time_step);
    println!(
        "cradle: forces differ by {force:.2e} of the peak, final velocities by {velocity:.2e}; residual {:.1e}",
        f.max_step_residual
    );
    assert!(force <= 1e-9, "forces differ by {force:e} of the peak");
    assert!(velocity <= 1e-9, "final velocities differ by {velocity:e}");
    assert!(f.max_step_residual <= mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE, "{f:?}");
}

/// The block sliding on an elastic slab with Coulomb friction of
/// `problems/block_on_slab_friction.toml` (two bodies, μ = 0.5, 50 steps): Moreau's law on the
/// active set (stick rows `G_t Δv = −U_t`, each candidate started from its last state) against
/// Lemke's frictional step LCP on `W`: the same comparison (measured 1.5e-13 of the peak
/// force, 1.6e-12 of the largest velocity: Lemke's frictional step is not polished, so its
/// answers carry ~1e-15 relative round-off per step, which the 50 steps accumulate).
#[test]
fn block_on_slab_friction_on_the_active_set_equals_lemke() {
    let name = "block_on_slab_friction";
    let lemke = solve(&shipped(name, "lemke"), &mut Silent).expect("Lemke's run");
    let sparse = solve(&shipped(name, "active_set"), &mut Silent).expect("the sparse run");
    let [force, velocity] = differences(&lemke, &sparse);
    let f = sparse.simulation.figures(sparse.dynamics.time_step);
    println!(
        "block on slab: forces differ by {force:.2e} of the peak, final velocities by {velocity:.2e}; residual {:.1e}",
        f.max_step_residual
    );
    assert!(force <= 1e-9, "forces differ by {force:e} of the peak");
    assert!(velocity <= 1e-9, "final velocities differ by {velocity:e}");
    assert!(f.max_step_residual <= mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE, "{f:?}");
}

/// Runs `name` (with `extra` appended to the file) on Lemke's method and on the active set,
/// checks the comparison of [`differences`] and the sparse run's step residuals, and returns
/// the differences.
fn compare(name: &str, extra: &str) -> [f64; 2] {
    let on = |solver: &str| {
        let mut problem = shipped(name, solver);
        if !extra.is_empty() {
            let text = shipped_text(name, solver) + extra;
            problem = Problem::from_toml(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        solve(&problem, &mut Silent).unwrap_or_else(|e| panic!("{name} on {solver}: {e}"))
    };
    let (lemke, sparse) = (on("lemke"), on("active_set"));
    let [force, velocity] = differences(&lemke, &sparse);
    let f = sparse.simulation.figures(sparse.dynamics.time_step);
    println!(
        "{name}{extra:?}: {} nodes; forces differ by {force:.2e} of the peak, final velocities by {velocity:.2e}; residual {:.1e}",
        sparse.nodes(),
        f.max_step_residual
    );
    assert!(force <= 1e-9, "{name}: forces differ by {force:e} of the peak");
    assert!(velocity <= 1e-9, "{name}: final velocities differ by {velocity:e}");
    assert!(f.max_step_residual <= mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE, "{f:?}");
    [force, velocity]
}

/// Finite element bodies (Q9 of the spacing, HRZ mass, identity `Φ`, eliminated rows in
/// `M̂ = M + h²θ²K`): the bar of `problems/bar_impact.toml` (729 nodes, one body against a
/// rigid wall) and Newton's cradle of `problems/newtons_cradle.toml` (three FE bars, two
/// pairs between bodies), both at L/40: the active-set run equals Lemke's within 1e-9 (module
/// documentation).
#[test]
fn finite_element_bodies_on_the_active_set_equal_lemke() {
    let fem = "[discretisation]\nmethod = \"fem\"\n";
    compare("bar_impact", fem);
    compare("newtons_cradle", fem);
}

/// An axisymmetric body (mass per radian, ring candidates, the collocation rows and the gap
/// rows scaled by `h²θ²` in `M̂`): the steel ball of `problems/ball_impact_axisymmetric.toml`
/// (396 nodes, 280 steps, curved contact edge against a rigid flat): the active-set run
/// equals Lemke's within 1e-9 (measured: forces 2.1e-13 of the peak, final velocities
/// 2.8e-10 of the largest). The velocities agree less closely than the bars' because `M̂` is
/// worse conditioned here (masses `ρ r dA` from the 50 µm cells at the axis to the 1 mm
/// cells at the rim, a graded β = 0.5 `K`): throughout the run the nodal parameters of the
/// two runs differ by ~5e-9 m/s (measured at t = 10, 20, …, 70 µs: up to 1.6e-8 of the
/// largest during the contact, 2.8e-10 at the end, where the largest is a 15 m/s parameter
/// of the graded nodes), while the momentum agrees to 1e-15 and the kinetic energy to
/// 1e-13 at every one of those times.
#[test]
fn axisymmetric_ball_on_the_active_set_equals_lemke() {
    compare("ball_impact_axisymmetric", "");
}

/// Two axisymmetric bodies: the spheres of `problems/spheres_impact_axisymmetric.toml` (two
/// balls at ±1 m/s, 792 nodes, rings on the upper sphere against the lower one's curved arc):
/// the active-set run equals Lemke's within 1e-9 (measured: forces 1.9e-13 of the peak,
/// final velocities 3.5e-10 of the largest, as the one ball: its graded `M̂`).
#[test]
fn axisymmetric_spheres_on_the_active_set_equal_lemke() {
    compare("spheres_impact_axisymmetric", "");
}

/// A node owning candidates of two pairs: the block of `problems/block_onto_wall_friction.toml`
/// without the floor's friction (it slides at `v0` = 0.5 and reaches the wall 0.2 away at
/// t = 0.4). Its corner node (1, 0) owns a floor candidate (ν = (0, 1)) and a wall candidate
/// (ν = (−1, 0)), each replacing its own row of the node. The active-set run equals Lemke's
/// within 1e-9 to t = 1 (module documentation), and to t = 0.42 (the wall's second step) with
/// both corner candidates closed in the last step on both solvers, so that the comparison
/// covers the node carrying both forces.
#[test]
fn a_corner_node_of_two_frictionless_pairs_on_the_active_set_equals_lemke() {
    let name = "block_onto_wall_friction";
    let frictionless = |solver: &str| shipped_text(name, solver).replace("friction = 0.3\n", "");
    assert!(!frictionless("lemke").contains("friction = "), "the floor's friction is removed");
    let run = |solver: &str, end: &str| {
        let text = frictionless(solver).replace("end_time = 1.0", &format!("end_time = {end}"));
        let problem = Problem::from_toml(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        solve(&problem, &mut Silent).unwrap_or_else(|e| panic!("{name} on {solver}: {e}"))
    };
    for end in ["1.0", "0.42"] {
        let (lemke, sparse) = (run("lemke", end), run("active_set", end));
        let [force, velocity] = differences(&lemke, &sparse);
        let f = sparse.simulation.figures(sparse.dynamics.time_step);
        // The corner's candidate of each pair and its impulse in the last step.
        let corner = |o: &DynamicOutcome| -> Vec<f64> {
            let pairs = &o.bodies.as_ref().expect("two pairs").pairs;
            let (floor, wall) = (&pairs[0].candidates, &pairs[1].candidates);
            let node = floor.nodes.iter().find(|i| wall.nodes.contains(i)).expect("a corner");
            pairs
                .iter()
                .map(|p| {
                    let c = p.candidates.nodes.iter().position(|i| i == node).expect("on both");
                    o.simulation.final_impulses[p.offset + c]
                })
                .collect()
        };
        let (a, b) = (corner(&lemke), corner(&sparse));
        println!(
            "corner block to t = {end}: forces differ by {force:.2e} of the peak, final velocities by {velocity:.2e}; residual {:.1e}; the corner's last impulses {a:?} (Lemke), {b:?}",
            f.max_step_residual
        );
        assert!(force <= 1e-9, "forces differ by {force:e} of the peak");
        assert!(velocity <= 1e-9, "final velocities differ by {velocity:e}");
        assert!(f.max_step_residual <= mlpg_contact::solution::COMPLEMENTARITY_TOLERANCE, "{f:?}");
        if end == "0.42" {
            assert!(a.iter().chain(&b).all(|&p| p > 0.0), "the corner closed on both: {a:?} {b:?}");
        }
    }
}

/// What the active-set step does not do is refused naming `contact.solver`: pairs on
/// different solvers (each step solves all pairs together). The corner node shared by two
/// pairs is refused at step 0 (`tests/validation/dynamics_wall.rs`).
#[test]
fn active_set_dynamics_refusals_name_the_key() {
    let text = shipped_text("newtons_cradle", "active_set");
    let mixed = text.replacen("solver = \"active_set\"", "solver = \"lemke\"", 1);
    let err = Problem::from_toml(&mixed).expect_err("mixed solvers").to_string();
    assert!(err.contains("contact[1].solver") && err.contains("same solver"), "{err}");
}
