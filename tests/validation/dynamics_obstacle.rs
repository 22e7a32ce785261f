//! A rigid obstacle moving in time (docs/method.md §10.6): `[[step]]` tables with `time` and
//! `obstacle_displacement` under `[dynamics]`.
//!
//! Reference: Galilean invariance. A wall moving at the constant velocity `V` into a body at
//! rest is, in the wall's frame, the body moving at `−V` onto a wall at rest. The discrete
//! scheme keeps that invariance: a uniform translation of the nodal parameters is a rigid
//! motion (`K` annihilates it, the θ-method adds it, the gap operator reads `ν·` of it), and the
//! velocity law is written on the velocities relative to the obstacle's, the index set on the
//! gaps predicted at the same time. So the runs in the two frames give the same contact
//! forces every step to round-off, momenta shifted by `m V`, and the same energy taken at the
//! contact (the work of the forces on the relative motion); the wall's work on the body is
//! the history's `external_work`. The bar is `problems/wall_hits_bar.toml` against
//! `problems/bar_impact.toml` (the exact 1-D wave solution: contact from `g / V` for `2 L / c`
//! under `ρ c V H`; the bar leaves at `2 V`).

use mlpg_contact::dynamics::{Figures, Record, mass};
use mlpg_contact::pipeline::dynamics::{DynamicOutcome, solve};
use mlpg_contact::problem::Problem;
use mlpg_contact::progress::Silent;

const L: f64 = 1.0;
const H: f64 = 0.1;
const V: f64 = 0.1;
const GAP: f64 = 0.01;
/// `c = √(E / ρ)` of the bars (E = ρ = 1).
const C: f64 = 1.0;
const FEM: &str = "\n[discretisation]\nmethod = \"fem\"\n";
const ACTIVE_SET: &str = "[contact]\nsolver = \"active_set\"\n";

/// The shipped file `name` at `spacing` (step `spacing / 2c`, end `end_time`), with `extra`
/// appended and `[contact]` replaced by `contact` when given.
fn shipped(name: &str, spacing: f64, end_time: f64, contact: Option<&str>, extra: &str) -> Problem {
    let path = format!("{}/problems/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).expect("the shipped file");
    let mut text = text
        .replace("spacing = 0.025", &format!("spacing = {spacing}"))
        .replace("time_step = 0.0125", &format!("time_step = {}", spacing / (2.0 * C)))
        .replace("end_time = 3.0", &format!("end_time = {end_time}"));
    if let Some(c) = contact {
        text = text.replace("[contact]\n", c);
    }
    text.push_str(extra);
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn run(problem: &Problem) -> (DynamicOutcome, Figures) {
    let outcome = solve(problem, &mut Silent).expect("the dynamic run");
    let figures = outcome.simulation.figures(outcome.dynamics.time_step);
    (outcome, figures)
}

/// The largest difference of `f` over the records of two runs, relative to `scale`.
fn apart(a: &[Record], b: &[Record], f: impl Fn(&Record) -> f64, scale: f64) -> f64 {
    shifted(a, b, f, 0.0, scale)
}

/// The largest `|f(a) − f(b) − shift|` over the records of two runs, relative to `scale`.
fn shifted(a: &[Record], b: &[Record], f: impl Fn(&Record) -> f64, shift: f64, scale: f64) -> f64 {
    assert_eq!(a.len(), b.len(), "the same steps");
    a.iter().zip(b).map(|(a, b)| (f(a) - f(b) - shift).abs() / scale).fold(0.0, f64::max)
}

/// The largest contact force of a run.
fn peak(records: &[Record]) -> f64 {
    records.iter().map(|r| r.contact_force).fold(0.0, f64::max)
}

/// The wall hitting the bar at rest is the bar impact in the wall's frame, MFVM and FE at
/// L/40, Lemke and the active set: the contact force of every step equal to round-off (1e-10
/// of the peak), the momentum shifted by `m V` (1e-10 of `m V`), the energy taken at the
/// contact equal (1e-10 of the initial kinetic energy of the bar impact), and the wall's work
/// closes the energy balance as the loads' does (the MFVM's collocated strain energy: to
/// 1e-2, as the free flight of `dynamics.rs`; FE at θ = ½ to 1e-9). The wall's work at the end
/// is the bar's kinetic energy gained, about `2 m V²` (within the run's 4 % force error at L/40).
#[test]
fn a_wall_hitting_a_bar_at_rest_is_the_bar_impact_in_the_walls_frame() {
    let end = 2.5;
    for (method, extra) in [("MFVM", ""), ("FE", FEM)] {
        let (impact, fi) = run(&shipped("bar_impact", L / 40.0, end, None, extra));
        let m = mass::total(&impact.simulation.mass);
        let ri = &impact.simulation.history.records;
        let top = peak(ri);
        let e0 = fi.initial_energy;
        for (solver, contact) in [("Lemke", None), ("active set", Some(ACTIVE_SET))] {
            let (wall, fw) = run(&shipped("wall_hits_bar", L / 40.0, end, contact, extra));
            let rw = &wall.simulation.history.records;
            let force = apart(rw, ri, |r| r.contact_force, top);
            let momentum = shifted(rw, ri, |r| r.momentum[0], m * V, m * V);
            let momentum_y = apart(rw, ri, |r| r.momentum[1], m * V);
            let loss = apart(rw, ri, |r| r.contact_loss, e0);
            let gained = rw[rw.len() - 1].energy() - rw[0].energy();
            let work = rw[rw.len() - 1].external_work;
            println!(
                "{method} {solver}: force {force:.2e} of the peak {top:.4e}, momentum {momentum:.2e} (y {momentum_y:.2e}) of m V, contact loss {loss:.2e} of E0; wall's work {work:.6e} (2 m V² = {:.6e}), energy gained {gained:.6e}, balance error {:.2e} (bar impact {:.2e}); final velocity {:.5}",
                2.0 * m * V * V,
                fw.energy_balance_error,
                fi.energy_balance_error,
                fw.final_velocity[0]
            );
            assert!(force < 1e-10, "{method} {solver}: forces {force}");
            assert!(momentum < 1e-10 && momentum_y < 1e-10, "{method} {solver}: momenta");
            assert!(loss < 1e-10, "{method} {solver}: contact loss {loss}");
            assert!((work - 2.0 * m * V * V).abs() < 0.04 * 2.0 * m * V * V, "wall's work {work}");
            let balance = if extra.is_empty() { 1e-2 } else { 1e-9 };
            assert!(fw.energy_balance_error < balance, "balance {}", fw.energy_balance_error);
        }
    }
}

/// The wall hitting the bar against the exact 1-D answer at L/160 (the bar impact test's
/// resolution and tolerances): contact from `g / V` (within a step) for `2 L / c` and the
/// mean force `ρ c V H` within 2 %, the bar leaving at `2 V` within 5 % of `V` (the bar
/// impact's rebound error in the wall's frame).
#[test]
fn a_wall_hitting_a_bar_matches_the_wave_solution() {
    let spacing = L / 160.0;
    let (_, f) = run(&shipped("wall_hits_bar", spacing, GAP / V + 2.0 * L / C + 0.5, None, ""));
    let start = f.contact.contact_start.expect("the wall touches the bar");
    let duration = f.contact.contact_duration.expect("contact") / (2.0 * L / C) - 1.0;
    let force = f.contact.mean_contact_force.expect("a force") / (1.0 * C * V * H) - 1.0;
    let leaves = (f.final_velocity[0] - 2.0 * V) / V;
    println!(
        "wall hits bar at L/160: start {start:.5} (exact {}), duration {duration:+.3e}, mean force {force:+.3e}, leaving velocity {leaves:+.3e} of V",
        GAP / V
    );
    assert!((start - GAP / V).abs() <= spacing / (2.0 * C) + 1e-12, "contact starts at {start}");
    assert!(duration.abs() < 0.02, "contact duration error {duration}");
    assert!(force.abs() < 0.02, "mean force error {force}");
    assert!(leaves.abs() < 0.05, "leaving velocity error {leaves}");
}

/// Two bars `a` (`0 ≤ x ≤ 1`) and `b` (`1.001 ≤ x ≤ 2.001`) of the bar's section at L/40, each
/// at `[vx, 0]`: `[[contact]]` pair 0 is `a`'s left end against the rigid wall `x = −g`, pair
/// 1 `a`'s right end against `b`'s left (with `solver` lines); `extra` is appended.
fn two_bars(vx: f64, solver: &str, extra: &str) -> Problem {
    let bar = |name: &str, x0: f64| {
        format!(
            "[[body]]\nname = \"{name}\"\ngeometry = {{ kind = \"rectangle\", x = [{x0}, {}], y = [0.0, {H}] }}\nnodes = {{ spacing = 0.025, layout = \"structured\" }}\nmaterial = {{ young = 1.0, poisson = 0.0, plane = \"stress\", density = 1.0 }}\ninitial_velocity = [{vx}, 0.0]\n",
            x0 + L
        )
    };
    let text = format!(
        "{}{}[[contact]]\nbody = \"a\"\nedge = \"left\"\nobstacle_point = [{}, 0.0]\nobstacle_normal = [1.0, 0.0]\n[[contact]]\nbody = \"a\"\nedge = \"right\"\ntarget_body = \"b\"\ntarget_edge = \"left\"\n{solver}[dynamics]\nend_time = 2.5\ntime_step = 0.0125\n{extra}",
        bar("a", 0.0),
        bar("b", 1.001),
        -GAP
    );
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("two bars: {e}"))
}

/// N bodies: the wall (moving at `V`) hits the first of two bars at rest, which passes the
/// pulse to the second; in the wall's frame both bars move at `−V` onto the wall at rest. The
/// pairs against rigid obstacles move with the wall, the pair between the bars does not: each
/// pair's force every step equal to round-off (1e-10 of the peak) and the momentum shifted by
/// `2 m V`, with Lemke and with the active set (`[[contact]] solver`).
#[test]
fn a_wall_hitting_two_bars_is_their_impact_in_the_walls_frame() {
    let (rest, _) = run(&two_bars(-V, "", ""));
    let rr = &rest.simulation.history.records;
    let m = mass::total(&rest.simulation.mass);
    let top = peak(rr);
    let moving = "[[step]]\ntime = 2.5\nobstacle_displacement = [0.25, 0.0]\n";
    for (name, solver) in [("Lemke", ""), ("active set", "solver = \"active_set\"\n")] {
        let (wall, _) = run(&two_bars(0.0, solver, moving));
        let rw = &wall.simulation.history.records;
        let pairs = (0..2).map(|k| apart(rw, rr, |r| r.pair_forces[k], top)).fold(0.0, f64::max);
        let momentum = shifted(rw, rr, |r| r.momentum[0], m * V, m * V);
        let bodies = wall.bodies.as_ref().expect("two bodies");
        let last = bodies.ends[1].mean_velocity()[0];
        println!(
            "two bars, {name}: pair forces {pairs:.2e} of the peak {top:.4e}, momentum {momentum:.2e} of m V (m both bars'); the second bar leaves at {last:.5}"
        );
        assert!(pairs < 1e-10, "{name}: pair forces {pairs}");
        assert!(momentum < 1e-10, "{name}: momentum {momentum}");
        assert!(rw.iter().any(|r| r.pair_forces[1] > 0.1 * top), "the bars touch");
    }
}

/// Friction: a floor moving at `−v0` under a block at rest (gravity 1, `μ = 0.3`) drags it
/// until it moves with the floor; in the floor's frame it is the block sliding at `v0` that
/// decelerates at `μ g` and sticks (`dynamics.rs`). The tangential velocity law is written on
/// the velocities relative to the floor's: the momenta shifted by `m v0` and the contact
/// force every step to round-off (1e-10), Lemke and the active set.
#[test]
fn a_floor_moving_under_a_block_drags_it_as_the_sliding_block() {
    let (mu, v0, end) = (0.3, 0.3, 1.3);
    let block = |v: f64, extra: &str| super::dynamics_friction::block(mu, v, 0.0, end, extra);
    let (sliding, _) = run(&block(v0, ""));
    let rs = &sliding.simulation.history.records;
    let m = mass::total(&sliding.simulation.mass);
    let top = peak(rs);
    let floor = format!("[[step]]\ntime = {end}\nobstacle_displacement = [{}, 0.0]\n", -v0 * end);
    for (name, solver) in [("Lemke", ""), ("active set", "solver = \"active_set\"\n")] {
        let (dragged, _) = run(&block(0.0, &format!("{solver}{floor}")));
        let rd = &dragged.simulation.history.records;
        let force = apart(rd, rs, |r| r.contact_force, top);
        let px = shifted(rd, rs, |r| r.momentum[0], -m * v0, m * v0);
        let py = apart(rd, rs, |r| r.momentum[1], m * v0);
        let end_velocity = rd[rd.len() - 1].momentum[0] / m;
        println!(
            "dragged block, {name}: force {force:.2e} of {top:.4e}, momenta {px:.2e}, {py:.2e} of m v0; velocity at the end {end_velocity:.6} (the floor's {})",
            -v0
        );
        assert!(force < 1e-10, "{name}: forces {force}");
        assert!(px < 1e-10 && py < 1e-10, "{name}: momenta {px} {py}");
        assert!((end_velocity + v0).abs() < 1e-3 * v0, "moves with the floor: {end_velocity}");
    }
}
