//! The contact core's load path (docs/dev/contact_core.md): friction, load steps and a body
//! held by contact combine for several bodies and pairs, and for either body of a pair; two
//! bodies held at once.
//!
//! **Problems.** `problems/three_block_stack.toml` (three blocks, two pairs, the middle block
//! held in y by the contacts alone) with `friction = 0.3` on both pairs, pressed in one
//! `[[step]]` of 2 increments, and both; `problems/cattaneo_mindlin.toml` with a second pair
//! against an obstacle far away (so that it takes the several-pairs path) against the file as
//! shipped; `problems/two_blocks.toml` with the upper block held only by contact (a roller in
//! x, pressure 1 on its top edge of length 2).
//!
//! **References and tolerances.**
//! - The frictionless stack is uniaxial (`stack.rs`): the forces of a proportional load path
//!   do not depend on the increments, so two increments equal one step to round-off (1e-9 of
//!   the force).
//! - With friction no closed form is at hand; the answer is checked against its own
//!   conditions: each increment's step residuals (complementarity, cone, sign; scaled as
//!   `lcp::FrictionResiduals`) ≤ 1e-9, `|T_c| ≤ μ P_c` at every candidate to round-off, each
//!   body's force balance (`equilibrium_error`, contact and tangential forces included) ≤
//!   1e-8, and the middle block's y balance (no load on it: the two interfaces carry the same
//!   normal force) to 1e-9.
//! - A pair solved on the several-pairs path is the same LCP as on the two-body path (the
//!   extra pair's candidates stay open): forces equal to 1e-9 of the largest.
//! - The held upper block carries its load: the contact force equals the applied 2.0 to 1e-8,
//!   and its translation is the closed form `−p (1/E_lower + 0.5/E_upper)` (p = 1, uniaxial
//!   stress; the pin is at the block's centre) to 1e-8 relative.

use mlpg_contact::Solution;
use mlpg_contact::problem::Problem;

fn shipped_text(file: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems").join(file);
    std::fs::read_to_string(path).unwrap()
}

/// The stack with `friction = mu` on both pairs (none for 0), and with the top edge's push
/// given by one `[[step]]` of `increments` increments (`None`: no steps).
fn stack(mu: f64, increments: Option<usize>) -> Problem {
    Problem::from_toml(&stack_text(mu, increments)).unwrap()
}

/// The text of [`stack`]'s problem.
fn stack_text(mu: f64, increments: Option<usize>) -> String {
    let mut text = shipped_text("three_block_stack.toml");
    if mu > 0.0 {
        text = text.replace(
            "target_edge = \"top\"\n",
            &format!("target_edge = \"top\"\nfriction = {mu}\n"),
        );
    }
    if let Some(n) = increments {
        text = text.replace("displacement = { y = -0.01 }", "displacement = { y = 0.0 }");
        text.push_str(&format!(
            "\n[[step]]\nincrements = {n}\nboundary = [{{ body = \"top\", edge = \"top\", displacement = {{ y = -0.01 }} }}]\n"
        ));
    }
    text
}

/// Every pair's total normal force.
fn pair_forces(s: &Solution) -> Vec<f64> {
    s.multibody().unwrap().pairs.iter().map(|c| c.total_force).collect()
}

/// The checks every frictional several-pairs answer must pass (module docs).
fn assert_frictional_checks(label: &str, s: &Solution, mu: f64) {
    let ms = s.multibody().unwrap();
    for (k, c) in ms.pairs.iter().enumerate() {
        let f = c
            .friction
            .as_ref()
            .unwrap_or_else(|| panic!("{label}: pair {k} has no friction record"));
        let r = f.step.residuals.max();
        assert!(r <= 1e-9, "{label}: pair {k} step residual {r:e}");
        let scale = c.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        for (i, (p, t)) in c.lcp.z.iter().zip(&f.step.tangential).enumerate() {
            assert!(*p >= -1e-12 * scale, "{label}: pair {k} candidate {i}: P = {p:e}");
            assert!(
                t.abs() <= mu * p + 1e-12 * scale,
                "{label}: pair {k} candidate {i}: |T| = {:e} > μP = {:e}",
                t.abs(),
                mu * p
            );
        }
        for snapshot in &f.increments {
            assert!(snapshot.complementarity <= 1e-9, "{label}: pair {k}: {snapshot:?}");
        }
    }
    let bodies = std::iter::once(s).chain(ms.bodies.iter());
    for (b, body) in bodies.enumerate() {
        assert!(body.equilibrium_error <= 1e-8, "{label}: body {b}: {:e}", body.equilibrium_error);
    }
    let forces = pair_forces(s);
    let balance = (forces[0] - forces[1]).abs() / forces[0];
    println!("{label}: pair forces {forces:?}, middle block balance {balance:.1e}");
    assert!(balance <= 1e-9, "{label}: the middle block's y balance {balance:e}");
    let held = ms.contact.held.first().expect("the middle block is held by the contacts");
    assert_eq!(held.0, 1);
}

#[test]
fn stack_with_friction_solves_with_its_checks() {
    let s = mlpg_contact::solve(&stack(0.3, None)).unwrap();
    assert_frictional_checks("friction", &s, 0.3);
    // Friction acts: the interfaces carry tangential forces and the stack is stiffer than
    // the frictionless one (the rollers and the blocks' different lateral strains).
    let ms = s.multibody().unwrap();
    let tangential: f64 =
        ms.pairs.iter().map(|c| c.friction.as_ref().unwrap().total_force.abs()).sum();
    assert!(tangential > 1e-2, "tangential forces {tangential:e}");
    let frictionless = pair_forces(&mlpg_contact::solve(&stack(0.0, None)).unwrap());
    assert!(pair_forces(&s)[0] > frictionless[0] * (1.0 + 1e-3));
}

#[test]
fn stack_in_two_increments_equals_one_step() {
    let one = mlpg_contact::solve(&stack(0.0, None)).unwrap();
    let two = mlpg_contact::solve(&stack(0.0, Some(2))).unwrap();
    let (f1, f2) = (pair_forces(&one), pair_forces(&two));
    for (a, b) in f1.iter().zip(&f2) {
        assert!((a - b).abs() <= 1e-9 * a.abs(), "one step {f1:?}, two increments {f2:?}");
    }
    let t = |s: &Solution| s.multibody().unwrap().contact.held.first().unwrap().1.translation[1];
    let (t1, t2) = (t(&one), t(&two));
    println!("held translation: one step {t1:.15e}, two increments {t2:.15e}");
    assert!((t1 - t2).abs() <= 1e-9 * t1.abs());
    // Every candidate's force, not only the totals.
    let ms = (one.multibody().unwrap(), two.multibody().unwrap());
    for (c1, c2) in ms.0.pairs.iter().zip(ms.1.pairs) {
        let scale = c1.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        for (a, b) in c1.lcp.z.iter().zip(&c2.lcp.z) {
            assert!((a - b).abs() <= 1e-9 * scale, "{a} against {b}");
        }
    }
}

#[test]
fn stack_with_friction_in_two_increments_solves_with_its_checks() {
    let s = mlpg_contact::solve(&stack(0.3, Some(2))).unwrap();
    assert_frictional_checks("friction, two increments", &s, 0.3);
    let ms = s.multibody().unwrap();
    for c in ms.pairs {
        assert_eq!(c.friction.as_ref().unwrap().increments.len(), 2);
    }
}

#[test]
fn a_pair_on_the_several_pairs_path_equals_the_two_body_path() {
    let text = shipped_text("cattaneo_mindlin.toml");
    let two = mlpg_contact::solve(&Problem::from_toml(&text).unwrap()).unwrap();
    let several = text.replace("[contact]\n", "[[contact]]\n")
        + "\n[[contact]]\nbody = \"block\"\nedge = \"left\"\nobstacle_point = [-5.0, 0.0]\nobstacle_normal = [1.0, 0.0]\n";
    let problem = Problem::from_toml(&several).unwrap();
    assert!(problem.multibody().is_some());
    let many = mlpg_contact::solve(&problem).unwrap();
    let c2 = two.contact().unwrap();
    let ms = many.multibody().unwrap();
    let cm = &ms.pairs[0];
    assert!(ms.pairs[1].lcp.z.iter().all(|&p| p == 0.0), "the far pair stays open");
    let (f2, fm) = (c2.friction.as_ref().unwrap(), cm.friction.as_ref().unwrap());
    let scale = c2.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let mut largest: f64 = 0.0;
    for c in 0..c2.lcp.z.len() {
        largest = largest
            .max((c2.lcp.z[c] - cm.lcp.z[c]).abs())
            .max((f2.step.tangential[c] - fm.step.tangential[c]).abs());
        assert_eq!(f2.step.state[c], fm.step.state[c], "candidate {c}");
    }
    println!("Cattaneo–Mindlin, two-body path against several pairs: {:.1e}", largest / scale);
    assert!(largest <= 1e-9 * scale);
    assert_eq!(f2.increments.len(), fm.increments.len());
}

/// The held upper block on both contact systems: the condensed path (Lemke inside the
/// search) and the sparse path (the pair walked as a scene of one pair, its held body searched
/// over warm-started solves) each carry the load, and agree to 1e-9 of the largest force.
#[test]
fn two_blocks_upper_held_by_contact_carries_its_load() {
    let text = shipped_text("two_blocks.toml").replace(
        "{ edge = \"top\", displacement = { y = -0.01 } }",
        "{ edge = \"top\", pressure = 1.0 }",
    );
    let mut forces = Vec::new();
    for solver in ["lemke", "active_set"] {
        let text = text.replace("[contact]\n", &format!("[contact]\nsolver = \"{solver}\"\n"));
        let s = mlpg_contact::solve(&Problem::from_toml(&text).unwrap()).unwrap();
        let c = s.contact().unwrap();
        println!("held upper block ({solver}): contact force {:.15e}", c.total_force);
        assert_eq!(c.active_set.is_some(), solver == "active_set", "{solver}: the system taken");
        assert!((c.total_force - 2.0).abs() <= 1e-8 * 2.0, "{solver}");
        let r = c.rigid_mode.as_ref().expect("the upper block's translation in y is held");
        let exact = -(1.0 / 1000.0 + 0.5 / 1000.0);
        let t = r.translation[1];
        assert!((t - exact).abs() <= 1e-8 * exact.abs(), "{solver}: {:?}", r.translation);
        assert!(s.equilibrium_error <= 1e-8, "{solver}");
        assert!(s.body(1).unwrap().equilibrium_error <= 1e-8, "{solver}");
        forces.push(c.lcp.z.clone());
    }
    let scale = forces[0].iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let largest = forces[0].iter().zip(&forces[1]).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!(
        "held upper block: active set against Lemke {:.1e} of the largest force",
        largest / scale
    );
    assert!(largest <= 1e-9 * scale);
}

#[test]
fn several_pairs_with_friction_and_steps_on_the_active_set_equal_lemkes_path() {
    for (mu, increments) in [(0.3, None), (0.3, Some(2)), (0.0, Some(2))] {
        let label = format!("active set, μ = {mu}, increments {increments:?}");
        let lemke = mlpg_contact::solve(&stack(mu, increments)).unwrap();
        let text = stack_text(mu, increments)
            .replace("target_edge = \"top\"\n", "target_edge = \"top\"\nsolver = \"active_set\"\n");
        let sparse = mlpg_contact::solve(&Problem::from_toml(&text).unwrap()).unwrap();
        assert_frictional_checks(&label, &sparse, mu);
        let (ml, ms) = (lemke.multibody().unwrap(), sparse.multibody().unwrap());
        assert!(
            ml.contact.active_set.is_none() && ms.contact.active_set.is_some(),
            "{label}: the solvers taken"
        );
        let mut largest: f64 = 0.0;
        for (cl, cs) in ml.pairs.iter().zip(ms.pairs) {
            let scale = cl.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
            let (fl, fs) = (cl.friction.as_ref().unwrap(), cs.friction.as_ref().unwrap());
            for c in 0..cl.lcp.z.len() {
                let normal = (cl.lcp.z[c] - cs.lcp.z[c]).abs();
                let tangential = (fl.step.tangential[c] - fs.step.tangential[c]).abs();
                largest = largest.max(normal.max(tangential) / scale);
                assert_eq!(fl.step.state[c], fs.step.state[c], "{label}: candidate {c}");
            }
            assert_eq!(fl.increments.len(), fs.increments.len(), "{label}");
        }
        let t = |m: mlpg_contact::solution::MultibodySolution| {
            m.contact.held.first().unwrap().1.translation[1]
        };
        let (tl, ts) = (t(ml), t(ms));
        println!(
            "{label}: forces to {largest:.1e} of Lemke's, held translation {ts:.15e} ({tl:.15e})"
        );
        assert!(largest <= 1e-9, "{label}: {largest:e}");
        assert!((tl - ts).abs() <= 1e-9 * tl.abs(), "{label}: {ts} against {tl}");
    }
}

/// `"auto"` on several pairs falls back to the active-set method when Lemke fails (provoked by
/// a pivot limit of half the pivots Lemke needs, as `lemke_fallback.rs` does for one pair):
/// the answer equals Lemke's unconstrained one to 1e-10 of the largest force (the active set
/// equals Lemke on the stack to ~1e-13, `stack.rs`), the record says why; `"lemke"` refuses.
#[test]
fn several_pairs_fall_back_from_lemke_to_the_active_set_with_auto() {
    let problem = stack(0.0, None);
    let reference = mlpg_contact::solve(&problem).unwrap();
    let pivots = reference.multibody().unwrap().contact.lcp.pivots;
    let params = mlpg_contact::lcp::LemkeParams {
        max_pivots: Some(pivots / 2),
        ..mlpg_contact::lcp::LemkeParams::default()
    };
    let s = mlpg_contact::solve_with_lemke(&problem, &params).unwrap();
    let ms = s.multibody().unwrap();
    assert!(ms.contact.active_set.is_some(), "the active set answered");
    let why = ms.contact.fallback_from.as_deref().expect("the record of Lemke's failure");
    assert!(why.contains("pivot"), "{why}");
    let (z, z_ref) = (&ms.contact.lcp.z, &reference.multibody().unwrap().contact.lcp.z);
    let scale = z_ref.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let largest = z.iter().zip(z_ref).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!("several pairs, auto after Lemke's failure: forces within {:.1e}", largest / scale);
    assert!(largest <= 1e-10 * scale);
    let mut lemke_only = problem.clone();
    for pair in &mut lemke_only.contact_pairs {
        pair.spec.solver = mlpg_contact::problem::ContactSolver::Lemke;
    }
    let err = mlpg_contact::solve_with_lemke(&lemke_only, &params).unwrap_err();
    assert!(matches!(err, mlpg_contact::Error::LemkeRefused(_)), "{err}");
}

/// The load path over several pairs falls back as the one-shot does: the stack pressed in one
/// `[[step]]` of 2 increments (the middle block held by the contacts: Lemke inside its
/// search) with a pivot limit of 1 on Lemke's frictionless steps; `"auto"` is answered by the
/// sparse path, equal to `"active_set"` (forces and the held translation to 1e-9), the
/// record says why; `"lemke"` refuses inside the first increment.
#[test]
fn several_pairs_on_the_load_path_fall_back_from_lemke_with_auto() {
    use mlpg_contact::problem::ContactSolver;
    let problem = stack(0.0, Some(2));
    let with = |solver: ContactSolver| {
        let mut p = problem.clone();
        p.contact_pairs.iter_mut().for_each(|c| c.spec.solver = solver);
        p
    };
    let params = mlpg_contact::lcp::LemkeParams {
        max_pivots: Some(1),
        ..mlpg_contact::lcp::LemkeParams::default()
    };
    let s = mlpg_contact::solve_with_lemke(&problem, &params).unwrap();
    let ms = s.multibody().unwrap();
    assert!(
        ms.contact.active_set.is_some() && ms.contact.condensed.is_none(),
        "the active set answered"
    );
    let why = ms.contact.fallback_from.as_deref().expect("the record of Lemke's failure");
    assert!(why.starts_with("load step 1, increment 1 of 2: Lemke's method"), "{why}");
    let direct = mlpg_contact::solve(&with(ContactSolver::ActiveSet)).unwrap();
    let md = direct.multibody().unwrap();
    assert!(md.contact.fallback_from.is_none());
    let scale = md.contact.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let largest = ms
        .contact
        .lcp
        .z
        .iter()
        .zip(&md.contact.lcp.z)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let t = |m: mlpg_contact::solution::MultibodySolution| m.contact.held[0].1.translation[1];
    println!(
        "stack on the path, auto after Lemke's failure: forces within {:.1e}",
        largest / scale
    );
    assert!(scale > 0.0 && largest <= 1e-9 * scale, "{largest:e}");
    assert!((t(ms) - t(md)).abs() <= 1e-9 * t(md).abs(), "{} against {}", t(ms), t(md));
    let err = mlpg_contact::solve_with_lemke(&with(ContactSolver::Lemke), &params).unwrap_err();
    let mlpg_contact::Error::Increment { step: 1, increment: 1, cause, .. } = &err else {
        panic!("not the first increment's failure: {err}")
    };
    assert!(matches!(cause.as_ref(), mlpg_contact::Error::LemkeRefused(_)), "{err}");
}

/// The upper block held by contact with no load at all: every upward translation answers, so
/// the run is refused naming the body and the mode instead of reporting one of them.
#[test]
fn a_held_body_with_nothing_determining_it_is_refused() {
    let text = shipped_text("two_blocks.toml")
        .replace("  { edge = \"top\", displacement = { y = -0.01 } },\n", "");
    let err = mlpg_contact::solve(&Problem::from_toml(&text).unwrap()).unwrap_err().to_string();
    assert!(err.contains("body `upper`") && err.contains("not determined"), "{err}");
}

/// `problem` solved by the adaptive loop with its own `[refinement]`.
fn adaptive(problem: &Problem) -> mlpg_contact::pipeline::adaptive::AdaptiveRun {
    let a = problem.adaptive.expect("the problem has [refinement]");
    mlpg_contact::pipeline::adaptive::solve_adaptive(
        problem,
        &a,
        &mut mlpg_contact::Silent,
        &mut |_, _, _, _| {},
    )
    .unwrap()
}

/// The stack refined adaptively (two refinement steps), frictionless, and with `friction =
/// 0.3` pressed in one `[[step]]` of 2 increments: every step's node sets grow on all three
/// bodies and the frictionless pair forces stay 30/7 at every step (uniaxial stress: every
/// node set reproduces it; to 1e-9); the frictional answer passes the checks of the one-step
/// frictional stack.
///
/// `beta = 0.5` (what `"auto"` reaches from the command line), no `allow_indefinite`: on the
/// graded, non-matching node sets of the refinement steps the condensed compliance's symmetric
/// part has a small negative eigenvalue (λ_min/λ_max ≈ −2.5e-4 at the second step;
/// docs/dev/contact_core.md), only in force patterns within one cell of a target body, so the
/// run proceeds with a warning (docs/method.md §4.3); the answers are checked here.
#[test]
fn the_stack_refines_adaptively_with_friction_and_steps() {
    let refined = |mu: f64, increments: Option<usize>| {
        let text = stack_text(mu, increments)
            .replace("[discretisation]\n", "[discretisation]\nbeta = 0.5\n")
            + "\n[refinement]\nsteps = 2\n";
        adaptive(&Problem::from_toml(&text).unwrap())
    };
    let run = refined(0.0, None);
    assert_eq!(run.summary.steps.len(), 3);
    let exact = 30.0 / 7.0;
    for (k, row) in run.summary.steps.iter().enumerate() {
        let bodies = row.bodies.as_ref().expect("one row per body");
        let pairs = row.pairs.as_ref().expect("one row per pair");
        assert_eq!((bodies.len(), pairs.len()), (3, 2));
        if k > 0 {
            let before = run.summary.steps[k - 1].bodies.as_ref().unwrap();
            for (b, (now, then)) in bodies.iter().zip(before).enumerate() {
                assert!(now.nodes > then.nodes, "step {k}, body {b}: {} nodes", now.nodes);
            }
        }
        for p in pairs {
            let error = (p.total_contact_force - exact).abs() / exact;
            println!("refined stack, step {k}, pair {}: force error {error:.1e}", p.pair);
            assert!(error <= 1e-9, "step {k}, pair {}: {}", p.pair, p.total_contact_force);
        }
    }
    assert_eq!(run.others.len(), 2);
    let run = refined(0.3, Some(2));
    assert_eq!(run.summary.steps.len(), 3);
    assert_frictional_checks("refined, friction, two increments", &run.solution, 0.3);
}

/// The two-body Hertz problem refined adaptively, with a second pair against an obstacle far
/// away so that it takes the several-pairs path, refines exactly as the two-body loop: the
/// same node counts per body at every step and the same contact force to 1e-9 (the far pair
/// never closes, so its marks are none and the two loops see the same LCP).
#[test]
fn a_pair_refines_on_the_several_pairs_path_as_on_the_two_body_path() {
    let text = shipped_text("hertz_two_bodies_adaptive.toml")
        .replace("steps = 5 ", "steps = 2 ")
        .replace("max_nodes = 30000", "max_nodes = 3000");
    let two = adaptive(&Problem::from_toml(&text).unwrap());
    let several = text.replace("[contact]\n", "[[contact]]\n").replace(
        "[refinement]",
        "[[contact]]\nbody = \"block\"\nedge = \"right\"\nobstacle_point = [6.5, 0.0]\nobstacle_normal = [-1.0, 0.0]\n\n[refinement]",
    );
    let many = adaptive(&Problem::from_toml(&several).unwrap());
    assert_eq!(two.summary.steps.len(), 3);
    assert_eq!(two.summary.steps.len(), many.summary.steps.len());
    assert_eq!(two.summary.stopped_by, many.summary.stopped_by);
    for (a, b) in two.summary.steps.iter().zip(&many.summary.steps) {
        let counts = |r: &mlpg_contact::post::summary::AdaptiveStep| -> Vec<usize> {
            r.bodies.as_ref().unwrap().iter().map(|b| b.nodes).collect()
        };
        assert_eq!(counts(a), counts(b), "step {}", a.step);
        let f = a.total_contact_force.unwrap();
        let pairs = b.pairs.as_ref().unwrap();
        assert_eq!(pairs[1].total_contact_force, 0.0, "the far pair stays open");
        let error = (pairs[0].total_contact_force - f).abs() / f;
        println!("Hertz, step {}: several-pairs loop against two-body loop {error:.1e}", a.step);
        assert!(error <= 1e-9, "step {}: {f} against {}", a.step, pairs[0].total_contact_force);
        assert_eq!(a.nodes, b.nodes);
    }
}

/// Two bodies held by contact alone (docs/method.md §4.7, nested searches): the stack with a
/// pressure `p = 10` on the top block's top edge instead of its push, so that the middle and
/// the top block are both free in y. Uniaxial stress: each interface carries `2 p = 20`
/// (1e-8), and each held block's translation is the exact `u_y` at its pin,
/// `−p (1/E_bottom + (y − 1)/E_middle)` in the middle block and
/// `−p (1/E_bottom + 1/E_middle + (y − 2)/E_top)` in the top one (1e-8 relative: the MFVM
/// reproduces linear fields); frictionless on both solvers. With `friction = 0.3` in two
/// increments the interfaces' tangential forces are horizontal, so each interface still
/// carries 20, but sticking restrains the blocks' different lateral strains and the
/// translations differ from the uniaxial ones (by ~1 %); there Lemke's forces and
/// translations equal the active set's to 1e-9.
#[test]
fn two_bodies_held_by_contact_carry_their_load() {
    let p = 10.0;
    let exact = |y: f64| {
        if y <= 2.0 {
            -p * (1.0 / 1000.0 + (y - 1.0) / 300.0)
        } else {
            -p * (1.0 / 1000.0 + 1.0 / 300.0 + (y - 2.0) / 3000.0)
        }
    };
    for (mu, increments) in [(0.0, None), (0.3, Some(2))] {
        let mut answers = Vec::new();
        for solver in ["lemke", "active_set"] {
            let label = format!("{solver}, μ = {mu}, increments {increments:?}");
            // The top edge's push (or the step's, after a zero first value) becomes the
            // pressure; the bottom block keeps its support.
            let push = "edge = \"top\", displacement = { y = -0.01 }";
            let text = stack_text(mu, increments)
                .replace(push, &format!("edge = \"top\", pressure = {p}"))
                .replace(
                    "edge = \"top\", displacement = { y = 0.0 }",
                    "edge = \"top\", pressure = 0.0",
                )
                .replace(
                    "target_edge = \"top\"\n",
                    &format!("target_edge = \"top\"\nsolver = \"{solver}\"\n"),
                );
            let s = mlpg_contact::solve(&Problem::from_toml(&text).unwrap())
                .unwrap_or_else(|e| panic!("{label}: {e}"));
            let ms = s.multibody().unwrap();
            let forces = pair_forces(&s);
            println!("{label}: pair forces {forces:?}");
            for f in &forces {
                assert!((f - 2.0 * p).abs() <= 1e-8 * 2.0 * p, "{label}: {forces:?}");
            }
            assert_eq!(ms.contact.held.iter().map(|h| h.0).collect::<Vec<_>>(), [1, 2], "{label}");
            for (b, r) in &ms.contact.held {
                let u = exact(r.pin_point[1]);
                println!(
                    "{label}: body {b} translation {:.15e} (frictionless {u:.15e})",
                    r.translation[1]
                );
                if mu == 0.0 {
                    assert!((r.translation[1] - u).abs() <= 1e-8 * u.abs(), "{label}: body {b}");
                }
            }
            let bodies = std::iter::once(&s).chain(ms.bodies.iter());
            for (b, body) in bodies.enumerate() {
                assert!(body.equilibrium_error <= 1e-8, "{label}: body {b}");
            }
            let r = &ms.contact.lcp.residuals;
            assert!(r.max_complementarity <= 1e-9, "{label}: {r:?}");
            assert!(r.min_z >= -1e-12 && r.min_w >= -1e-9, "{label}: {r:?}");
            let forces = ms.pairs.iter().flat_map(|c| c.lcp.z.clone()).collect::<Vec<f64>>();
            let translations: Vec<f64> =
                ms.contact.held.iter().map(|h| h.1.translation[1]).collect();
            answers.push((forces, translations));
        }
        let scale = answers[0].0.iter().fold(0.0f64, |m, z| m.max(z.abs()));
        for (a, b) in answers[0].0.iter().zip(&answers[1].0) {
            assert!((a - b).abs() <= 1e-9 * scale, "μ = {mu}: Lemke {a} against {b}");
        }
        for (a, b) in answers[0].1.iter().zip(&answers[1].1) {
            assert!((a - b).abs() <= 1e-9 * a.abs(), "μ = {mu}: translation {a} against {b}");
        }
    }
}
