//! Friction on the active-set path (docs/method.md §5.1 "Friction", §8): the sparse
//! frictional active-set step against the Lemke-based step on the condensed blocks
//! (`lcp::solve_step`), increment by increment, on the shipped frictional problem with a rigid
//! obstacle (`problems/beam_on_foundation_friction.toml`, 10 increments), on the 2 × 1 block
//! pressed, sheared and sheared back (stick, slip, reversal), on the same path with the
//! obstacle moving instead of the top, and on the FE beam with friction. Both solve the same
//! step problem exactly, so forces, gaps, slip increments and states must agree to round-off:
//! 1e-10 of the largest force (resp. displacement scale) leaves room for the conditioning of
//! the two routes (the dense blocks' eigenvalue ratios are ≈ 1e-5 here) times the double
//! precision ε, or, where more, the round-off bound of the closed gaps over the smallest
//! eigenvalue of `M_nn`'s symmetric part (the FE beam: Lemke's closed gaps 1.6e-15 over
//! 3.2e-5, as in the frictionless comparison). Each answer is also checked on its own: the scaled step residuals
//! (complementarity, cone, friction complementarity ≤ 1e-9 at every increment) and global
//! equilibrium (≤ 1e-8). `problems/cattaneo_mindlin.toml` is two bodies: refused with
//! `solver = "active_set"` (checked here), Lemke's path with `"auto"`.

use super::active_set::shipped;
use super::friction::{block_text, check_frictional, check_increments};
use mlpg_contact::lcp::{ContactState, FrictionMethod};
use mlpg_contact::problem::{ContactSolver, Problem};
use mlpg_contact::solution::Solution;

/// Agreement of the two solvers (see the module documentation).
const AGREEMENT: f64 = 1e-10;

fn solve_with(problem: &Problem, solver: ContactSolver) -> Solution {
    let mut p = problem.clone();
    p.contact.as_mut().unwrap().solver = solver;
    p.write_steps = true;
    mlpg_contact::solve(&p).unwrap()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

fn diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Both solvers on `problem`, every increment compared (forces, gaps, accumulated slip,
/// states); returns (largest force difference, largest displacement difference), relative.
fn compare(name: &str, problem: &Problem) -> (f64, f64) {
    let lemke = solve_with(problem, ContactSolver::Lemke);
    let active = solve_with(problem, ContactSolver::ActiveSet);
    check_frictional(&lemke, name);
    check_frictional(&active, name);
    check_increments(&active, name);
    let (a, b) = (active.contact.as_ref().unwrap(), lemke.contact.as_ref().unwrap());
    assert!(a.condensed.is_none() && a.active_set.is_some(), "{name}: not the active-set path");
    assert!(b.condensed.is_some() && b.active_set.is_none(), "{name}: not the Lemke path");
    let (fa, fb) = (a.friction.as_ref().unwrap(), b.friction.as_ref().unwrap());
    assert_eq!(fa.step.method, FrictionMethod::ActiveSet, "{name}");
    assert_eq!(fa.snapshots.len(), fb.snapshots.len(), "{name}: increments");
    assert!(!fa.snapshots.is_empty());
    // As for the frictionless comparison (`validation/active_set.rs`): each answer's closed
    // gaps (recovered from its displacements, 0 in exact arithmetic) over the smallest
    // eigenvalue of M_nn's symmetric part bound how far the other's forces may be.
    let closed_gap = |c: &mlpg_contact::ContactSolution| {
        c.gap.iter().zip(&c.closed).filter(|p| *p.1).fold(0.0_f64, |m, (g, _)| m.max(g.abs()))
    };
    let lambda_min = b.condensed.as_ref().unwrap().min_symmetric_eigenvalue;
    let gap_bound = 4.0 * closed_gap(a).max(closed_gap(b)) / lambda_min;
    let (mut force, mut disp) = (0.0_f64, 0.0_f64);
    for (sa, sb) in fa.snapshots.iter().zip(&fb.snapshots) {
        let at = format!("{name}, step {} increment {}", sa.step, sa.increment);
        let f_max = max_abs(&sb.normal).max(max_abs(&sb.tangential));
        let df = diff(&sa.normal, &sb.normal).max(diff(&sa.tangential, &sb.tangential)) / f_max;
        // Displacement scale: the gaps' and slips' size, at least the press (0.01).
        let u_max = max_abs(&sb.gap).max(max_abs(&sb.slip)).max(0.01);
        let du = diff(&sa.gap, &sb.gap).max(diff(&sa.slip, &sb.slip)) / u_max;
        let bound = AGREEMENT.max(gap_bound / f_max);
        assert!(df < bound, "{at}: forces differ by {df:e} of {f_max:e} (bound {bound:e})");
        assert!(du < AGREEMENT, "{at}: gaps or slips differ by {du:e} of {u_max:e}");
        assert_eq!(sa.state, sb.state, "{at}: states differ");
        force = force.max(df);
        disp = disp.max(du);
    }
    // The final solution: displacements, the recovered gaps and the totals.
    let du = active
        .displacement
        .iter()
        .zip(&lemke.displacement)
        .fold(0.0_f64, |m, (p, q)| m.max((p[0] - q[0]).hypot(p[1] - q[1])));
    let scale = lemke.displacement.iter().fold(0.0_f64, |m, p| m.max(p[0].hypot(p[1])));
    assert!(du < AGREEMENT * scale, "{name}: displacements differ by {du:e} of {scale:e}");
    let iterations: Vec<usize> = fa.increments.iter().map(|r| r.iterations).collect();
    println!(
        "{name}: closed gaps: active set {:.1e}, Lemke {:.1e}, λ_min {lambda_min:.2e}",
        closed_gap(a),
        closed_gap(b)
    );
    println!(
        "{name}: {} candidates, forces {force:.1e}, gaps/slips {disp:.1e}, displacements {:.1e}; solves per increment {iterations:?}, rescues {:?}",
        a.candidates.len(),
        du / scale,
        a.active_set.as_ref().unwrap().rescues
    );
    (force, disp)
}

#[test]
fn shipped_frictional_beam_equals_lemke() {
    let problem = shipped("beam_on_foundation_friction.toml");
    compare("beam_on_foundation_friction.toml", &problem);
}

/// The 2 × 1 block pressed by 0.01 (3 increments), sheared by 0.004 (4), which slips at the
/// edges and sticks inside, then sheared back to −0.002 (4): the slip reverses.
#[test]
fn block_press_shear_and_reverse_equals_lemke() {
    let steps = "[[step]]\nincrements = 3\nboundary = [{ edge = \"top\", displacement = { y = -0.01 } }]\n\
                 [[step]]\nincrements = 4\nboundary = [{ edge = \"top\", displacement = { x = 0.004 } }]\n\
                 [[step]]\nincrements = 4\nboundary = [{ edge = \"top\", displacement = { x = -0.002 } }]\n";
    let problem = Problem::from_toml(&block_text("mfvm", 0.0, Some(0.3), steps)).unwrap();
    compare("block press, shear, reverse", &problem);
    // The path visits stick, both slip directions and a mixed state.
    let s = solve_with(&problem, ContactSolver::ActiveSet);
    let f = s.contact.as_ref().unwrap().friction.as_ref().unwrap();
    let seen = |state: ContactState| f.snapshots.iter().any(|x| x.state.contains(&state));
    assert!(seen(ContactState::Stick) && seen(ContactState::SlipPositive));
    assert!(seen(ContactState::SlipNegative), "no reversal");
    assert!(f.increments.iter().any(|r| r.stick > 0 && r.slip > 0), "no mixed increment");
}

/// The same block with its top held after the press and the rigid line moving instead
/// (`[[step]] obstacle_displacement`): the gap and tangential conditions carry `d·ν`, `d·t`.
#[test]
fn moving_obstacle_equals_lemke() {
    let steps = "[[step]]\nincrements = 2\nboundary = [{ edge = \"top\", displacement = { y = -0.01 } }]\n\
                 [[step]]\nincrements = 3\nobstacle_displacement = [-0.003, 0.002]\n";
    let problem = Problem::from_toml(&block_text("mfvm", 0.0, Some(0.4), steps)).unwrap();
    compare("block, moving obstacle", &problem);
}

/// The FE beam (`problems/beam_on_foundation_fem.toml`) with μ = 0.3 in one step: nodal
/// candidates and nodal gap rows.
#[test]
fn fem_beam_with_friction_equals_lemke() {
    let mut problem = shipped("beam_on_foundation_fem.toml");
    problem.contact.as_mut().unwrap().friction = 0.3;
    compare("beam_on_foundation_fem.toml, μ = 0.3", &problem);
}

/// Two bodies with friction: `"active_set"` is refused with the key path; `"auto"` solves
/// `problems/cattaneo_mindlin.toml`'s kind of problem on Lemke's path.
#[test]
fn two_bodies_with_friction_are_refused() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/cattaneo_mindlin.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let text = text.replacen("[contact]\n", "[contact]\nsolver = \"active_set\"\n", 1);
    let e = Problem::from_toml(&text).unwrap_err().to_string();
    assert!(e.contains("contact.solver") && e.contains("rigid obstacles only"), "{e}");
}

/// `summary.json` of a frictional active-set run: the solver, its iterations, the changes per
/// iteration of every increment, the residuals.
#[test]
fn frictional_summary_records_the_solver() {
    let steps = "[[step]]\nincrements = 2\nboundary = [{ edge = \"top\", displacement = { x = 0.003, y = -0.01 } }]\n";
    let mut problem = Problem::from_toml(&block_text("mfvm", 0.0, Some(0.3), steps)).unwrap();
    problem.contact.as_mut().unwrap().solver = ContactSolver::ActiveSet;
    let out = std::env::temp_dir().join(format!("mlpg-asf-summary-{}", std::process::id()));
    let report =
        mlpg_contact::run(&problem, &out, serde_json::Value::Null, &mut mlpg_contact::Silent)
            .unwrap();
    let json: serde_json::Value = serde_json::from_str(&report.summary.to_json()).unwrap();
    std::fs::remove_dir_all(&out).unwrap();
    assert_eq!(json["lcp"]["solver"], "active_set");
    assert_eq!(json["lcp"]["active_set"]["end"], "converged");
    let steps = json["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 2);
    for step in steps {
        assert_eq!(step["solver"], "active_set");
        let changes = step["active_set_changes"].as_array().unwrap();
        assert_eq!(changes.len() as u64, step["iterations"].as_u64().unwrap());
        assert_eq!(changes.last().unwrap(), 0);
        assert!(step["complementarity"].as_f64().unwrap() <= 1e-9);
    }
}

/// `"auto"` with friction against a rigid obstacle: the active-set solver from
/// [`ContactSolver::FRICTION_AUTO_THRESHOLD`] candidates, Lemke's path below. The strip
/// `L × 1` (clamped left, load 1 on top, rigid floor 0.01 below, μ = 0.3) at h = 0.25 has
/// `4 L` candidates (the clamped corner is none). The answer at the threshold is checked on its
/// own (on this slender strip Lemke's recovered gaps miss its step gaps by 1e-11, its own
/// round-off, so no comparison here).
#[test]
fn auto_switches_at_the_friction_threshold() {
    let strip = |length: f64| {
        let mut p = super::active_set::plain_strip(length, 0.25, "friction = 0.3");
        p.write_steps = true;
        p
    };
    let threshold = ContactSolver::FRICTION_AUTO_THRESHOLD;
    let at = strip(threshold as f64 / 4.0);
    let s = mlpg_contact::solve(&at).unwrap();
    let c = s.contact.as_ref().unwrap();
    assert_eq!(c.candidates.len(), threshold);
    assert!(c.active_set.is_some(), "auto did not take the active-set solver");
    check_frictional(&s, "frictional strip at the threshold");
    let below = strip((threshold - 1) as f64 / 4.0);
    let s = mlpg_contact::solve(&below).unwrap();
    let c = s.contact.as_ref().unwrap();
    assert_eq!(c.candidates.len(), threshold - 1);
    assert!(c.active_set.is_none(), "auto left Lemke below the threshold");
    assert_eq!(c.friction.as_ref().unwrap().step.method, FrictionMethod::Lemke);
}
