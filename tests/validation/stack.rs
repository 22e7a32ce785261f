//! Three elastic blocks stacked and pressed together: several bodies and contact pairs in one
//! LCP (`problems/three_block_stack.toml`).
//!
//! **Problem.** Blocks `[0, 2] × [0, 1]` (bottom, `E_1 = 1000`, spacing 0.1),
//! `[0, 2] × [1, 2]` (middle, `E_2 = 300`, spacing 0.125) and `[0, 2] × [2, 3]` (top,
//! `E_3 = 3000`, spacing 1/12), `ν = 0.3`, plane stress, so that no two interfaces have
//! matching nodes. Two frictionless pairs: the middle block's bottom edge against the bottom
//! block's top edge, the top block's bottom edge against the middle block's top edge. The top
//! block's top edge is pushed down by `δ = 0.01`, the bottom block's bottom edge is on a roller
//! (`u_y = 0`), every left edge on a roller (`u_x = 0`). The middle block is held vertically by
//! the contacts only: its translation in y is pinned at its central node and found from the
//! pin's zero reaction (docs/method.md §4.7; asserted: the pin carries nothing, and the
//! translation is the exact displacement of the pinned point).
//!
//! **Reference (closed form).** Every block is in uniaxial stress `σ_yy = −p`,
//! `σ_xx = σ_xy = 0`: this satisfies equilibrium in each block, the traction-free right
//! edges, the rollers (zero shear, `u_x = 0` at `x = 0`), and continuity of the normal traction
//! without shear across the frictionless interfaces, which stay closed. Compatibility: the
//! blocks shorten by `p L_i / E_i` (`L_i = 1`) and together by `δ`, so
//!
//! ```text
//! p = δ / Σ L_i/E_i = 0.01 / (1/1000 + 1/300 + 1/3000) = 15/7,
//! ```
//!
//! the contact pressure on both interfaces (total force `2p` each). In block `i`, with
//! `y_i` its bottom, `u_y(y) = u_y(y_i) − (p/E_i)(y − y_i)` and `u_x = ν p x / E_i`
//! (`ε_xx = −ν σ_yy / E_i`); the interfaces move by `u_y(1) = −p/E_1 = −3/1400` and
//! `u_y(2) = u_y(1) − p/E_2 = −13/1400`, and `u_y(3) = u_y(2) − p/E_3 = −δ`.
//!
//! **Tolerance.** The exact field is linear in each block, which the linear MLS basis
//! reproduces, and the condensation is exact for MLS (docs/method.md §4.2, §4.5): the
//! discretisation error is zero and only round-off remains. Asserted to 1e-8 (relative to `δ`
//! for displacements, to `p` for pressures), as for two blocks (`two_bodies.rs`); measured:
//! see the printed values (`--nocapture`).

use super::common::{assert_lcp_residuals, shipped_problem};
use mlpg_contact::Solution;
use mlpg_contact::pipeline::multibody::discretise_others;
use mlpg_contact::problem::Problem;

const DELTA: f64 = 0.01;
const YOUNG: [f64; 3] = [1000.0, 300.0, 3000.0];
const POISSON: f64 = 0.3;

/// The exact contact pressure `δ / Σ L_i/E_i` (`L_i = 1`).
fn exact_pressure() -> f64 {
    DELTA / YOUNG.iter().map(|e| 1.0 / e).sum::<f64>()
}

/// The exact displacement of block `i` (0 bottom, 1 middle, 2 top) at `x`.
fn exact(i: usize, x: [f64; 2]) -> [f64; 2] {
    let p = exact_pressure();
    let base: f64 = (0..i).map(|k| -p / YOUNG[k]).sum();
    [POISSON * p * x[0] / YOUNG[i], base - p / YOUNG[i] * (x[1] - i as f64)]
}

fn stack() -> Problem {
    shipped_problem("three_block_stack.toml", 0.1)
}

fn solve_on(threads: usize, problem: &Problem) -> Solution {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| mlpg_contact::solve(problem).unwrap())
}

#[test]
fn three_block_stack_is_uniaxial_to_round_off() {
    let problem = stack();
    let several = problem.multibody().expect("several bodies");
    assert_eq!(several.bodies.len(), 2);
    assert_eq!(several.pairs.len(), 2);
    let s = mlpg_contact::solve(&problem).unwrap();
    let ms = s.multibody().unwrap();
    let p = exact_pressure();
    assert!((p - 15.0 / 7.0).abs() < 1e-14);

    // One LCP over both pairs: complementarity, every candidate closed, pressures uniform.
    assert_lcp_residuals("stack", &ms.contact.lcp.residuals, 1e-10);
    assert_eq!(ms.contact.lcp.z.len(), ms.pairs.iter().map(|c| c.candidates.len()).sum::<usize>());
    for (k, c) in ms.pairs.iter().enumerate() {
        let worst = c.pressure.iter().map(|v| (v / p - 1.0).abs()).fold(0.0, f64::max);
        println!(
            "pair {k}: {} candidates, total {:.15} (exact {:.15}), max |p/p_exact − 1| = {worst:.2e}",
            c.candidates.len(),
            c.total_force,
            2.0 * p
        );
        assert!(c.closed.iter().all(|&v| v), "pair {k}: an open candidate");
        assert!(worst < 1e-8, "pair {k}: pressure deviates by {worst:.3e}");
        assert!((c.total_force / (2.0 * p) - 1.0).abs() < 1e-8, "pair {k}: {}", c.total_force);
        assert!(c.gap.iter().all(|g| g.abs() < 1e-8 * DELTA), "pair {k}: gaps {:?}", c.gap);
    }

    // Every body's displacement field, the interfaces included.
    let models: Vec<_> =
        std::iter::once(mlpg_contact::discretise(&problem, &mut mlpg_contact::Silent).unwrap())
            .chain(discretise_others(&problem, &mut mlpg_contact::Silent).unwrap())
            .collect();
    let bodies: Vec<&Solution> = std::iter::once(&s).chain(ms.bodies.iter()).collect();
    for (i, (b, m)) in bodies.iter().zip(&models).enumerate() {
        let worst = m
            .nodes
            .points
            .iter()
            .zip(&b.displacement)
            .map(|(&x, u)| {
                let e = exact(i, x);
                (u[0] - e[0]).abs().max((u[1] - e[1]).abs())
            })
            .fold(0.0, f64::max);
        println!("body {i}: max |u − u_exact| / δ = {:.2e}", worst / DELTA);
        assert!(worst < 1e-8 * DELTA, "body {i}: displacement error {worst:.3e}");
    }
    for (k, (c, y, body)) in
        [(&ms.pairs[0], 1.0, 1), (&ms.pairs[1], 2.0, 2)].into_iter().enumerate()
    {
        let interface = exact(body - 1, [0.0, y])[1];
        assert!((interface - exact(body, [0.0, y])[1]).abs() < 1e-15);
        let worst = c
            .candidates
            .nodes
            .iter()
            .map(|&n| (bodies[body].displacement[n as usize][1] - interface).abs())
            .fold(0.0, f64::max);
        println!(
            "interface {k} (y = {y}): u_y exact {interface:.15}, max error / δ {:.2e}",
            worst / DELTA
        );
        assert!(worst < 1e-8 * DELTA, "interface {k}: {worst:.3e}");
    }
    assert!((exact(1, [0.0, 1.0])[1] + 3.0 / 1400.0).abs() < 1e-15);
    assert!((exact(2, [0.0, 2.0])[1] + 13.0 / 1400.0).abs() < 1e-15);
    assert!((exact(2, [0.0, 3.0])[1] + DELTA).abs() < 1e-15);

    // Equilibrium of every body: contact force in = contact force out = support reaction.
    let force = 2.0 * p;
    for (i, b) in bodies.iter().enumerate() {
        println!(
            "body {i}: equilibrium {:.2e}, contact force {:?}, reaction {:?}",
            b.equilibrium_error, b.contact_force, b.reaction_force
        );
        assert!(b.equilibrium_error < 1e-9, "body {i}: {}", b.equilibrium_error);
    }
    let close = |a: f64, b: f64| (a - b).abs() < 1e-8 * force;
    // Bottom: pushed down by pair 0, held up by its roller.
    assert!(close(s.contact_force[1], -force) && close(s.reaction_force[1], force));
    // Middle: pushed up by pair 0 and down by pair 1; held by them alone: pinned at one node
    // in y, whose reaction vanishes, and translated by the exact displacement of that node.
    let middle = bodies[1];
    assert!(close(middle.contact_force[1], 0.0) && close(middle.reaction_force[1], 0.0));
    let pin = models[1].system.pinned.expect("the middle block's free translation is pinned");
    assert_eq!(pin.axis, mlpg_contact::nodes::Axis::Y);
    let pin_reaction = middle
        .reactions
        .iter()
        .find(|r| r.0 == pin.node && r.1 == pin.axis)
        .expect("the pin's reaction")
        .2;
    println!("middle block: pin reaction {pin_reaction:.2e} (contact force {force})");
    assert!(pin_reaction.abs() < 1e-8 * force, "pin reaction {pin_reaction:.3e}");
    assert!(middle.reactions.iter().all(|r| r.2.abs() < 1e-8 * force), "middle reactions");
    let (held, mode) = ms.contact.held.first().expect("the middle block is held by contact");
    assert_eq!((*held, mode.mode), (1, "translation in y"));
    let x_pin = models[1].nodes.points[pin.node as usize];
    assert_eq!(mode.pin_point, x_pin);
    let exact_pin = exact(1, x_pin);
    println!(
        "middle block: translation {:.15} at ({}, {}), exact {:.15}, {} LCP solves",
        mode.translation[1], x_pin[0], x_pin[1], exact_pin[1], mode.evaluations
    );
    assert!(mode.translation[0] == 0.0 && mode.load == 0.0);
    assert!((mode.translation[1] - exact_pin[1]).abs() < 1e-8 * DELTA);
    assert!((middle.displacement[pin.node as usize][1] - mode.translation[1]).abs() < 1e-8 * DELTA);
    // Top: pushed up by pair 1, pushed down by its prescribed edge.
    assert!(close(bodies[2].contact_force[1], force) && close(bodies[2].reaction_force[1], -force));
}

#[test]
fn three_block_stack_is_identical_on_one_and_two_threads() {
    let problem = stack();
    let (a, b) = (solve_on(1, &problem), solve_on(2, &problem));
    let (ma, mb) = (a.multibody().unwrap(), b.multibody().unwrap());
    assert_eq!(ma.contact.lcp.z, mb.contact.lcp.z);
    assert_eq!(
        ma.contact.condensed.as_ref().unwrap().compliance,
        mb.contact.condensed.as_ref().unwrap().compliance
    );
    let bodies = |s: &Solution, m: mlpg_contact::solution::MultibodySolution| {
        std::iter::once(s.displacement.clone())
            .chain(m.bodies.iter().map(|b| b.displacement.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(bodies(&a, ma), bodies(&b, mb));
    assert_eq!(ma.contact.held, mb.contact.held, "the middle block's translation");
}

/// Two blocks pressed together (`problems/two_blocks.toml`, identical blocks, non-matching
/// layouts) with the pair reversed: the candidates on the lower block's top edge against the
/// upper block's bottom edge, `[[contact]] body = "lower"` — the several-pairs path. Exact
/// answer as for the usual pair: uniform pressure `E δ / (H_1 + H_2) = 5`, total 10, and the
/// linear fields; the usual pair's solution (also exact) must be reproduced to round-off, by
/// the MFVM and by the finite elements (Q2 reproduces linear fields exactly too). Asserted to
/// 1e-8 as above (round-off only).
#[test]
fn reversed_pair_reproduces_the_two_blocks() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/two_blocks.toml");
    let usual = std::fs::read_to_string(path).unwrap();
    let from = "[contact]\nedge = \"bottom\"";
    assert!(usual.contains(from));
    let reversed = usual
        .replace(from, "[[contact]]\nbody = \"lower\"\nedge = \"top\"\ntarget_body = \"upper\"\n")
        .replace("target_edge = \"top\"", "target_edge = \"bottom\"");
    for method in ["mfvm", "fem"] {
        let with = |text: &str| {
            let text = text.replace(
                "support_factor = 2.0",
                &format!("support_factor = 2.0\nmethod = \"{method}\""),
            );
            let problem = Problem::from_toml(&text).unwrap();
            let s = mlpg_contact::solve(&problem).unwrap();
            (problem, s)
        };
        let (p_usual, s_usual) = with(&usual);
        let (p_rev, s_rev) = with(&reversed);
        assert!(p_usual.multibody().is_none() && p_rev.multibody().is_some());
        let ms = s_rev.multibody().unwrap();
        let c = &ms.pairs[0];
        assert_lcp_residuals(method, &ms.contact.lcp.residuals, 1e-10);
        let worst = c.pressure.iter().map(|v| (v / 5.0 - 1.0).abs()).fold(0.0, f64::max);
        println!("{method}: reversed pair, max |p/5 − 1| = {worst:.2e}, total {}", c.total_force);
        assert!(worst < 1e-8 && (c.total_force / 10.0 - 1.0).abs() < 1e-8);
        let lower_usual = s_usual.body(1).unwrap();
        for (a, b, what) in [(&s_usual, &s_rev, "upper"), (lower_usual, &ms.bodies[0], "lower")] {
            let worst = a
                .displacement
                .iter()
                .zip(&b.displacement)
                .map(|(u, v)| (u[0] - v[0]).abs().max((u[1] - v[1]).abs()))
                .fold(0.0, f64::max);
            println!(
                "{method}: {what} block, max |u_reversed − u_usual| / δ = {:.2e}",
                worst / 0.01
            );
            assert!(worst < 1e-8 * 0.01, "{method} {what}: {worst:.3e}");
            assert!(b.equilibrium_error < 1e-9, "{method} {what}: {}", b.equilibrium_error);
        }
    }
}

/// One body and two contact pairs against rigid lines: the block `[0, 2] × [0, 1]` (`E =
/// 1000`, `ν = 0.3`, plane stress, spacing 0.1) on a rigid floor `y = 0` (pair 0: its bottom
/// edge) beside a rigid wall `x = 2` (pair 1: its right edge), both touching at the start, its
/// left edge on a roller and its top edge pushed down by `δ = 0.01`.
///
/// **Reference.** The uniform state `ε_yy = −δ`, `ε_xx = 0` (`u = (0, −δ y)`): the wall stops
/// the Poisson expansion, so `σ_yy = −E δ/(1 − ν²)`, `σ_xx = ν σ_yy`, `σ_xy = 0`; both walls
/// are pressed (`σ < 0`): floor pressure `E δ/(1 − ν²) = 10/0.91`, wall pressure `ν` times
/// that. Linear field: exact up to round-off, asserted to 1e-8.
#[test]
fn block_between_floor_and_wall_is_exact() {
    let text = walls("walls", "displacement = { y = -0.01 }");
    let problem = Problem::from_toml(&text).unwrap();
    let model = mlpg_contact::discretise(&problem, &mut mlpg_contact::Silent).unwrap();
    let s = mlpg_contact::solve(&problem).unwrap();
    let ms = s.multibody().unwrap();
    assert!(ms.bodies.is_empty());
    assert_lcp_residuals("walls", &ms.contact.lcp.residuals, 1e-10);
    let floor = 1000.0 * DELTA / (1.0 - POISSON * POISSON);
    for (k, (c, exact)) in
        [(&ms.pairs[0], floor), (&ms.pairs[1], POISSON * floor)].into_iter().enumerate()
    {
        let worst = c.pressure.iter().map(|v| (v / exact - 1.0).abs()).fold(0.0, f64::max);
        println!(
            "walls, pair {k}: {} candidates, max |p/p_exact − 1| = {worst:.2e}",
            c.candidates.len()
        );
        assert!(worst < 1e-8, "pair {k}: {worst:.3e}");
        // The wall's contact-free gaps vanish (the top's motion is a rigid translation along
        // the wall): the closed set's tolerance comes from both pairs' gaps.
        assert!(c.closed.iter().all(|&v| v), "pair {k}: an open candidate");
    }
    let worst = model
        .nodes
        .points
        .iter()
        .zip(&s.displacement)
        .map(|(x, u)| u[0].abs().max((u[1] + DELTA * x[1]).abs()))
        .fold(0.0, f64::max);
    println!(
        "walls: max |u − u_exact| / δ = {:.2e}, equilibrium {:.2e}",
        worst / DELTA,
        s.equilibrium_error
    );
    assert!(worst < 1e-8 * DELTA);
    assert!(s.equilibrium_error < 1e-9);
    // The floor's and the wall's forces are the top's and the roller's reactions.
    let (fy, fx) = (2.0 * floor, POISSON * floor);
    assert!(
        (s.contact_force[1] - fy).abs() < 1e-8 * fy && (s.contact_force[0] + fx).abs() < 1e-8 * fy
    );
}

/// The block between a floor and a wall of `block_between_floor_and_wall_is_exact`, pressed by
/// a uniform traction `q = 10` on its top instead of a displacement: nothing but the floor
/// holds it in y, so its translation in y is left to the two obstacle pairs (docs/method.md
/// §4.7, "Between bodies", with `F_r = −2q ≠ 0`).
///
/// **Reference.** The uniform state `σ_yy = −q`, `σ_xx = ν σ_yy` (the wall stops the Poisson
/// expansion), `σ_xy = 0`: floor pressure `q`, wall pressure `ν q`, `u = (0, −(1 − ν²) q y / E)`
/// (`u_x = 0` on the roller and at the wall). Linear: round-off only, asserted to 1e-8.
#[test]
fn block_pressed_between_floor_and_wall_is_held_by_them() {
    let text = walls("walls_pressed", "traction = { y = -10.0 }");
    let q = 10.0;
    let problem = Problem::from_toml(&text).unwrap();
    let model = mlpg_contact::discretise(&problem, &mut mlpg_contact::Silent).unwrap();
    let pin = model.system.pinned.expect("y is left to the contacts");
    let s = mlpg_contact::solve(&problem).unwrap();
    let ms = s.multibody().unwrap();
    assert_lcp_residuals("walls pressed", &ms.contact.lcp.residuals, 1e-10);
    for (k, (c, exact)) in [(&ms.pairs[0], q), (&ms.pairs[1], POISSON * q)].into_iter().enumerate()
    {
        let worst = c.pressure.iter().map(|v| (v / exact - 1.0).abs()).fold(0.0, f64::max);
        println!("walls pressed, pair {k}: max |p/p_exact − 1| = {worst:.2e}");
        assert!(worst < 1e-8, "pair {k}: {worst:.3e}");
    }
    let strain = (1.0 - POISSON * POISSON) * q / 1000.0;
    let worst = model
        .nodes
        .points
        .iter()
        .zip(&s.displacement)
        .map(|(x, u)| u[0].abs().max((u[1] + strain * x[1]).abs()))
        .fold(0.0, f64::max);
    let (held, mode) = ms.contact.held.first().expect("held by the contacts");
    let x_pin = model.nodes.points[pin.node as usize];
    let pin_reaction =
        s.reactions.iter().find(|r| r.0 == pin.node && r.1 == pin.axis).expect("pin").2;
    println!(
        "walls pressed: max |u − u_exact| / (strain) = {:.2e}, translation {:.15} (exact {:.15}), load {}, pin reaction {pin_reaction:.2e}, {} LCP solves",
        worst / strain,
        mode.translation[1],
        -strain * x_pin[1],
        mode.load,
        mode.evaluations
    );
    assert_eq!(*held, 0);
    assert!(worst < 1e-8 * strain);
    assert!((mode.load + 2.0 * q).abs() < 1e-12 * q);
    assert!((mode.translation[1] + strain * x_pin[1]).abs() < 1e-8 * strain);
    assert!(pin_reaction.abs() < 1e-8 * q, "{pin_reaction:e}");
    assert!(s.equilibrium_error < 1e-9);
}

/// The block `[0, 2] × [0, 1]` of the floor-and-wall cases: a rigid floor `y = 0` under its
/// bottom edge and a rigid wall `x = 2` beside its right edge (two obstacle pairs), a roller on
/// its left edge and `top` (a condition of `[[boundary]]`) on its top edge.
fn walls(name: &str, top: &str) -> String {
    format!(
        r#"
name = "{name}"
[discretisation]
support_factor = 2.0
[geometry]
kind = "rectangle"
x = [0.0, 2.0]
y = [0.0, 1.0]
[nodes]
spacing = 0.1
[material]
young = 1000.0
poisson = 0.3
plane = "stress"
[[boundary]]
edge = "left"
displacement = {{ x = 0.0 }}
[[boundary]]
edge = "top"
{top}
[[contact]]
edge = "bottom"
obstacle_point = [0.0, 0.0]
obstacle_normal = [0.0, 1.0]
[[contact]]
edge = "right"
obstacle_point = [2.0, 0.0]
obstacle_normal = [-1.0, 0.0]
"#
    )
}

/// `text` with `solver = "<solver>"` added to every `[[contact]]` table.
fn with_pair_solver(text: &str, solver: &str) -> String {
    text.replace("[[contact]]\n", &format!("[[contact]]\nsolver = \"{solver}\"\n"))
}

/// The active-set solver (docs/method.md §5.1, [`mlpg_contact::contact::sparse::Bodies`])
/// against Lemke's method on this file's problems with several pairs: the stack (its middle
/// block held by the two contacts, the translation found by the search over warm-started
/// solves, docs/method.md §4.7) and the reversed pair (MFVM and FE) as
/// `active_set::compare_multibody` checks them (each answer's complementarity and every
/// body's equilibrium; forces and gaps within 1e-10 of the largest, the same closed sets, the
/// held translation within 1e-10), plus this file's exact answers for the stack on the active
/// set's own solution. The floor-and-wall block has a corner node on both contact edges: it
/// is refused, naming the pairs and `contact[k].solver` (docs/dev/active_set.md).
#[test]
fn several_pairs_on_the_active_set_equal_lemke() {
    use super::active_set::compare_multibody;
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let read = |name: &str| std::fs::read_to_string(file.join(name)).unwrap();
    let stack_text = read("three_block_stack.toml");
    let usual = read("two_blocks.toml");
    let reversed = usual
        .replace(
            "[contact]\nedge = \"bottom\"",
            "[[contact]]\nbody = \"lower\"\nedge = \"top\"\ntarget_body = \"upper\"\n",
        )
        .replace("target_edge = \"top\"", "target_edge = \"bottom\"");
    let fem = reversed.replace("support_factor = 2.0", "support_factor = 2.0\nmethod = \"fem\"");
    for (name, text) in [("stack", &stack_text), ("reversed", &reversed), ("reversed fem", &fem)] {
        let solve = |solver: &str| {
            let problem = Problem::from_toml(&with_pair_solver(text, solver)).unwrap();
            mlpg_contact::solve(&problem).unwrap()
        };
        let (lemke, active) = (solve("lemke"), solve("active_set"));
        let (force, gap, t) = compare_multibody(name, &lemke, &active);
        let ms = active.multibody().unwrap();
        let record = ms.contact.active_set.as_ref().unwrap();
        println!(
            "{name}: forces {force:.1e}, gaps {gap:.1e}, translation {t:.1e}; {} linear solves, {} factorisations, {} update columns",
            record.iterations, record.work.factorisations, record.work.update_columns
        );
        if name == "stack" {
            // The exact answer (module documentation) on the active set's own solution.
            let p = exact_pressure();
            for (k, c) in ms.pairs.iter().enumerate() {
                let worst = c.pressure.iter().map(|v| (v / p - 1.0).abs()).fold(0.0, f64::max);
                assert!(worst < 1e-8, "pair {k}: max |p/p_exact − 1| = {worst:.3e}");
            }
            let (held, mode) = ms.contact.held.first().expect("the middle block is held");
            assert_eq!(*held, 1);
            let exact_t = exact(1, mode.pin_point)[1];
            assert!((mode.translation[1] - exact_t).abs() < 1e-8 * DELTA, "{mode:?}");
        }
    }
    for (name, top) in
        [("walls", "displacement = { y = -0.01 }"), ("walls pressed", "traction = { y = -10.0 }")]
    {
        let problem = Problem::from_toml(&with_pair_solver(&walls(name, top), "active_set"));
        let err = mlpg_contact::solve(&problem.unwrap()).unwrap_err().to_string();
        println!("{name}: {err}");
        assert!(
            err.contains("contact[0]") && err.contains("contact[1]") && err.contains("solver"),
            "{name}: {err}"
        );
    }
}

/// A node that owns a candidate of one pair and receives another pair's target forces on the
/// same rows (docs/dev/active_set.md): the block `[0, 1] × [1, 2]` on a floor block (pair 0:
/// its bottom edge), pressed from the right by a third block (pair 1: the third block's left
/// edge against the block's right edge). The block's corner `(1, 1)` owns a candidate of pair
/// 0 and the target cell of pair 1's lowest candidate: the active set refuses, naming both
/// pairs and `contact[0].solver`; mixing the solvers of the pairs is refused by the problem's
/// validation (one LCP).
#[test]
fn owner_conflict_between_pairs_is_refused() {
    let text = r#"
name = "corner"
[discretisation]
support_factor = 2.0
[[body]]
name = "floor"
geometry = { kind = "rectangle", x = [0.0, 2.0], y = [0.0, 1.0] }
nodes = { spacing = 0.25 }
material = { young = 1000.0, poisson = 0.3, plane = "stress" }
boundary = [{ edge = "bottom", displacement = { x = 0.0, y = 0.0 } }]
[[body]]
name = "block"
geometry = { kind = "rectangle", x = [0.0, 1.0], y = [1.0, 2.0] }
nodes = { spacing = 0.25 }
material = { young = 1000.0, poisson = 0.3, plane = "stress" }
boundary = [
  { edge = "left", displacement = { x = 0.0 } },
  { edge = "top", displacement = { y = -0.01 } },
]
[[body]]
name = "pusher"
geometry = { kind = "rectangle", x = [1.0, 2.0], y = [1.0, 2.0] }
nodes = { spacing = 0.2 }
material = { young = 1000.0, poisson = 0.3, plane = "stress" }
boundary = [{ edge = "right", displacement = { x = -0.01, y = 0.0 } }]
[[contact]]
body = "block"
edge = "bottom"
target_body = "floor"
target_edge = "top"
[[contact]]
body = "pusher"
edge = "left"
target_body = "block"
target_edge = "right"
"#;
    let problem = Problem::from_toml(&with_pair_solver(text, "active_set")).unwrap();
    let err = mlpg_contact::solve(&problem).unwrap_err().to_string();
    println!("corner: {err}");
    assert!(
        err.contains("contact[0].solver")
            && err.contains("contact[1]")
            && err.contains("receives the target forces"),
        "{err}"
    );
    let mixed = text.replacen("[[contact]]\n", "[[contact]]\nsolver = \"active_set\"\n", 1);
    let mixed = mixed.replacen(
        "[[contact]]\nbody = \"pusher\"",
        "[[contact]]\nsolver = \"lemke\"\nbody = \"pusher\"",
        1,
    );
    let err = Problem::from_toml(&mixed).unwrap_err().to_string();
    println!("mixed: {err}");
    assert!(err.contains("contact[1].solver") && err.contains("contact[0].solver"), "{err}");
}
