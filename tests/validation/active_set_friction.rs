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
    if let (Some(a2), Some(b2)) = (active.second_body.as_deref(), lemke.second_body.as_deref()) {
        let du2 = a2
            .displacement
            .iter()
            .zip(&b2.displacement)
            .fold(0.0_f64, |m, (p, q)| m.max((p[0] - q[0]).hypot(p[1] - q[1])));
        assert!(du2 < AGREEMENT * scale, "{name}: body 2 displacements differ by {du2:e}");
        assert!(a2.equilibrium_error <= 1e-8, "{name}: body 2 equilibrium");
    }
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

/// `problems/cattaneo_mindlin.toml` as shipped (a cylinder cap on a block, h = 0.01 on both,
/// a frictionless press then a shear in 4 increments with μ = 0.3): two bodies with friction
/// and `[[step]]` on the active-set path (`lcp::active_set::TwoBodies`) against Lemke's path,
/// every increment; both bodies' equilibrium is in each increment's record
/// (`check_frictional`).
#[test]
fn cattaneo_mindlin_equals_lemke() {
    let problem = shipped("cattaneo_mindlin.toml");
    compare("cattaneo_mindlin.toml", &problem);
    let s = solve_with(&problem, ContactSolver::ActiveSet);
    let f = s.contact.as_ref().unwrap().friction.as_ref().unwrap();
    assert!(f.increments.iter().any(|r| r.stick > 0 && r.slip > 0), "no partial slip");
}

/// Two identical 2 × 1 blocks (h = 0.1, E = 1000, ν = 0.3, plane stress), the lower one
/// clamped at its bottom, the upper one's top pressed by 0.01 (2 increments) and sheared by
/// `shear` (4 increments), then the lower block's bottom moved by −0.02 along x (4
/// increments: the relative shear reverses to `shear + 0.02`): stick, slip and its reversal
/// between two bodies, each body moved by its own step values; `upper_spacing` sets the upper
/// block's spacing (0.1: matching layouts, 0.08: not) and `method` the discretisation.
fn two_blocks_path(method: &str, upper_spacing: f64, mu: f64, shear: f64) -> Problem {
    Problem::from_toml(&format!(
        r#"
        [discretisation]
        method = "{method}"
        [[body]]
        name = "upper"
        geometry = {{ kind = "rectangle", x = [0.0, 2.0], y = [1.0, 2.0] }}
        nodes = {{ spacing = {upper_spacing:e} }}
        material = {{ young = 1000.0, poisson = 0.3, plane = "stress" }}
        boundary = [{{ edge = "top", displacement = {{ x = 0.0, y = 0.0 }} }}]
        [[body]]
        name = "lower"
        geometry = {{ kind = "rectangle", x = [0.0, 2.0], y = [0.0, 1.0] }}
        nodes = {{ spacing = 0.1 }}
        material = {{ young = 1000.0, poisson = 0.3, plane = "stress" }}
        boundary = [{{ edge = "bottom", displacement = {{ x = 0.0, y = 0.0 }} }}]
        [contact]
        edge = "bottom"
        target_edge = "top"
        friction = {mu:e}
        [output]
        steps = true
        [[step]]
        increments = 2
        boundary = [{{ body = "upper", edge = "top", displacement = {{ y = -0.01 }} }}]
        [[step]]
        increments = 4
        boundary = [{{ body = "upper", edge = "top", displacement = {{ x = {shear:e} }} }}]
        [[step]]
        increments = 4
        boundary = [{{ body = "lower", edge = "bottom", displacement = {{ x = -0.02 }} }}]
        "#
    ))
    .unwrap()
}

/// Two blocks pressed, sheared into partial slip and back (the last step moves the lower
/// block), matching and non-matching layouts: equal to Lemke's
/// path at every increment, and the path visits stick, both slip directions and a mixed
/// state.
#[test]
fn two_blocks_press_shear_and_reverse_equal_lemke() {
    for (spacing, name) in [(0.1, "matching"), (0.08, "non-matching")] {
        let problem = two_blocks_path("mfvm", spacing, 0.3, -0.012);
        let name = format!("two blocks, {name} layouts");
        compare(&name, &problem);
        let s = solve_with(&problem, ContactSolver::ActiveSet);
        let f = s.contact.as_ref().unwrap().friction.as_ref().unwrap();
        let seen = |state: ContactState| f.snapshots.iter().any(|x| x.state.contains(&state));
        assert!(seen(ContactState::Stick), "{name}: no stick");
        assert!(seen(ContactState::SlipPositive), "{name}: no slip+");
        assert!(seen(ContactState::SlipNegative), "{name}: no slip−");
        assert!(f.increments.iter().any(|r| r.stick > 0 && r.slip > 0), "{name}: no mixed");
    }
}

/// The same path on two finite element blocks (nodal candidates, the target's forces spread
/// over tributary segments).
#[test]
fn fem_two_blocks_press_shear_and_reverse_equal_lemke() {
    compare("two FE blocks", &two_blocks_path("fem", 0.1, 0.3, -0.012));
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
