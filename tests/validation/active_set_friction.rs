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
//! equilibrium (≤ 1e-8), of both bodies where there are two. Two bodies
//! (`contact::sparse::TwoBodies` with friction): `problems/cattaneo_mindlin.toml` (a cylinder
//! cap pressed onto a block, then sheared with friction; all 5 increments), and two blocks
//! pressed, sheared into partial slip and back by moving the other body (matching and
//! non-matching layouts, and two FE blocks), with the same 1e-10.

use super::active_set::shipped;
use super::friction::{block_text, check_frictional, check_increments};
use mlpg_contact::lcp::{ContactState, FrictionMethod};
use mlpg_contact::problem::{ContactSolver, Problem};
use mlpg_contact::solution::Solution;

/// Agreement of the two solvers (see the module documentation).
const AGREEMENT: f64 = 1e-10;

fn solve_with(problem: &Problem, solver: ContactSolver) -> Solution {
    let mut p = problem.clone();
    p.contact_mut().unwrap().solver = solver;
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
    let (a, b) = (active.contact().unwrap(), lemke.contact().unwrap());
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
    if let (Some(a2), Some(b2)) = (active.body(1), lemke.body(1)) {
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
    let f = s.contact().unwrap().friction.as_ref().unwrap();
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
    problem.contact_mut().unwrap().friction = 0.3;
    compare("beam_on_foundation_fem.toml, μ = 0.3", &problem);
}

/// `problems/cattaneo_mindlin.toml` as shipped (a cylinder cap on a block, h = 0.01 on both,
/// a frictionless press then a shear in 4 increments with μ = 0.3): two bodies with friction
/// and `[[step]]` on the active-set path (`contact::sparse::TwoBodies`) against Lemke's path,
/// every increment; both bodies' equilibrium is in each increment's record
/// (`check_frictional`).
#[test]
fn cattaneo_mindlin_equals_lemke() {
    let problem = shipped("cattaneo_mindlin.toml");
    compare("cattaneo_mindlin.toml", &problem);
    let s = solve_with(&problem, ContactSolver::ActiveSet);
    let f = s.contact().unwrap().friction.as_ref().unwrap();
    assert!(f.increments.iter().any(|r| r.stick > 0 && r.slip > 0), "no partial slip");
}

/// Two identical 2 × 1 blocks (h = 0.1, E = 1000, ν = 0.3, plane stress), the lower one
/// clamped at its bottom, the upper one's top pressed by 0.01 (2 increments) and sheared by
/// `shear` (4 increments), then the lower block's bottom moved by −0.02 along x (4
/// increments: the relative shear reverses to `shear + 0.02`): stick, slip and its reversal
/// between two bodies, each body moved by its own step values; `upper_spacing` sets the upper
/// block's spacing (0.1: matching layouts, 0.08: not) and `method` the discretisation.
fn two_blocks_path(method: &str, upper_spacing: f64, mu: f64, shear: f64) -> Problem {
    let steps = format!(
        r#"
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
    );
    Problem::from_toml(&two_blocks_text(method, upper_spacing, mu, "{ x = 0.0, y = 0.0 }", &steps))
        .unwrap()
}

/// The text of the two blocks of [`two_blocks_path`] with the upper top's displacement `top`
/// and the `[[step]]` tables `steps`.
fn two_blocks_text(method: &str, upper_spacing: f64, mu: f64, top: &str, steps: &str) -> String {
    format!(
        r#"
        [discretisation]
        method = "{method}"
        [[body]]
        name = "upper"
        geometry = {{ kind = "rectangle", x = [0.0, 2.0], y = [1.0, 2.0] }}
        nodes = {{ spacing = {upper_spacing:e} }}
        material = {{ young = 1000.0, poisson = 0.3, plane = "stress" }}
        boundary = [{{ edge = "top", displacement = {top} }}]
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
        {steps}
        "#
    )
}

/// The sparse two-body frictional system (`contact::sparse::TwoBodies` with friction) against
/// the dense step problem of the same two blocks (non-matching layouts, pressed by 0.01 and
/// sheared by 0.009 in one step, μ = 0.3: partial slip): the four blocks and `q` summed over
/// both bodies' condensations (`contact::condense_blocks`, what Lemke's path uses) as a
/// `DenseFriction`. The free response, the forces and displacements of a guess of the states
/// (Lemke's final states with every third sticking candidate sent to slip+; gaps and
/// tangential displacements relative to the free ones, since every candidate is closed and
/// the closed gaps are round-off), and the reduced step problem of a rescue (every other candidate free, the others held at the guess: the
/// blocks from solves with the modes' row changes) must agree to 1e-10 of their largest entry
/// (`AGREEMENT`; both are round-off of solves with the same `K`s). Then a forced rescue (one
/// solve allowed before the Lemke-based step takes over) ends at Lemke's answer.
#[test]
fn two_body_frictional_system_equals_the_dense_blocks() {
    use mlpg_contact::contact::condense_blocks;
    use mlpg_contact::contact::sparse::{BodyParts, TwoBodies};
    use mlpg_contact::lcp::FrictionProblem;
    use mlpg_contact::lcp::active_set::{
        ActiveSetEnd, ActiveSetParams, DenseFriction, FrictionSystem, solve_friction_step,
    };
    let text = two_blocks_text("mfvm", 0.08, 0.3, "{ x = -0.009, y = -0.01 }", "");
    let problem = Problem::from_toml(&text).unwrap();
    let lemke = solve_with(&problem, ContactSolver::Lemke);
    let c = lemke.contact().unwrap();
    let f = c.friction.as_ref().unwrap();
    assert!(f.step.state.iter().any(|s| s.is_slip()), "no slip: {:?}", f.step.state);
    let silent = &mut mlpg_contact::Silent;
    let m1 = mlpg_contact::discretise(&problem, silent).unwrap();
    let m2 = mlpg_contact::discretise(problem.body(1).unwrap(), silent).unwrap();
    let (target, target_t) = (c.target.as_ref().unwrap(), f.target_operator.as_ref().unwrap());
    let b1 =
        condense_blocks(&m1.factorisation, &m1.system.rhs, &c.candidates.operator, &f.operator)
            .unwrap();
    let b2 = condense_blocks(&m2.factorisation, &m2.system.rhs, target, target_t).unwrap();
    let add = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x + y).collect::<Vec<f64>>();
    let m = c.candidates.len();
    let mu: Vec<f64> = f.tangentially_free.iter().map(|&t| if t { 0.3 } else { 0.0 }).collect();
    let dense = FrictionProblem {
        nn: add(&b1.nn, &b2.nn),
        nt: add(&b1.nt, &b2.nt),
        tn: add(&b1.tn, &b2.tn),
        tt: add(&b1.tt, &b2.tt),
        free_gap: add(&add(&b1.free_gap, &b2.free_gap), &c.candidates.initial_gap),
        free_tangential: add(&b1.free_tangential, &b2.free_tangential),
        previous_tangential: vec![0.0; m],
        friction: mu.clone(),
    };
    fn parts<'a>(
        model: &'a mlpg_contact::model::Model,
        operator: &'a mlpg_contact::contact::BodyOperator,
    ) -> BodyParts<'a> {
        BodyParts {
            matrix: &model.system.matrix,
            rhs: &model.system.rhs,
            factorisation: &model.factorisation,
            operator,
            points: Some(&model.nodes.points),
        }
    }
    let new_system = || {
        let mut s = TwoBodies::two(
            parts(&m1, &c.candidates.operator),
            parts(&m2, target),
            &c.candidates.initial_gap,
            m1.system.collocation_scale,
        )
        .unwrap();
        s.set_friction(&mu, vec![(&f.operator, Some(target_t))]).unwrap();
        s
    };
    // Gaps and tangential displacements relative to the free ones (closed gaps are round-off).
    let u_scale = max_abs(&dense.free_gap).max(max_abs(&dense.free_tangential));
    let close = |what: &str, x: &[f64], y: &[f64]| {
        let scale = max_abs(x).max(max_abs(y)).max(1e-300);
        let scale = if what.starts_with("g ") || what.starts_with("s ") { u_scale } else { scale };
        let d = diff(x, y) / scale;
        println!("{what}: relative difference {d:.1e}");
        assert!(d < AGREEMENT, "{what}: {d:e}");
    };
    let mut sparse = new_system();
    let mut reference = DenseFriction::new(&dense);
    let (qn, qt) = sparse.free_response().unwrap().unwrap();
    close("q_n", &qn, &dense.free_gap);
    close("q_t", &qt, &dense.free_tangential);
    let mut guess = f.step.state.clone();
    for (i, s) in guess.iter_mut().enumerate() {
        if i % 3 == 0 && *s == ContactState::Stick {
            *s = ContactState::SlipPositive;
        }
    }
    let previous = vec![0.0; m];
    let rs = sparse.solve_states(&guess, &previous).unwrap();
    let rd = reference.solve_states(&guess, &previous).unwrap();
    close("P of a guess", &rs.normal, &rd.normal);
    close("T of a guess", &rs.tangential, &rd.tangential);
    close("g of a guess", &rs.gap, &rd.gap);
    close("s of a guess", &rs.tangential_displacement, &rd.tangential_displacement);
    let free: Vec<usize> = (0..m).step_by(2).collect();
    let ps = sparse.reduced_problem(&guess, &free, &previous).unwrap();
    let pd = reference.reduced_problem(&guess, &free, &previous).unwrap();
    close("reduced M_nn", &ps.nn, &pd.nn);
    close("reduced M_nt", &ps.nt, &pd.nt);
    close("reduced M_tn", &ps.tn, &pd.tn);
    close("reduced M_tt", &ps.tt, &pd.tt);
    close("reduced q_n", &ps.free_gap, &pd.free_gap);
    close("reduced q_t", &ps.free_tangential, &pd.free_tangential);
    let params =
        ActiveSetParams { max_iterations: 1, max_fallbacks: 10, ..ActiveSetParams::default() };
    let answer = solve_friction_step(&mut new_system(), &previous, None, &params).unwrap();
    println!("forced rescues: {:?}, changes {:?}", answer.rescues, answer.changes);
    assert_eq!(answer.end, ActiveSetEnd::ConvergedAfterRescue, "{:?}", answer.changes);
    close("P after rescues", &answer.step.normal, &f.step.normal);
    close("T after rescues", &answer.step.tangential, &f.step.tangential);
    assert_eq!(answer.step.state, f.step.state);
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
        let f = s.contact().unwrap().friction.as_ref().unwrap();
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
    problem.contact_mut().unwrap().solver = ContactSolver::ActiveSet;
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
    let c = s.contact().unwrap();
    assert_eq!(c.candidates.len(), threshold);
    assert!(c.active_set.is_some(), "auto did not take the active-set solver");
    check_frictional(&s, "frictional strip at the threshold");
    let below = strip((threshold - 1) as f64 / 4.0);
    let s = mlpg_contact::solve(&below).unwrap();
    let c = s.contact().unwrap();
    assert_eq!(c.candidates.len(), threshold - 1);
    assert!(c.active_set.is_none(), "auto left Lemke below the threshold");
    assert_eq!(c.friction.as_ref().unwrap().step.method, FrictionMethod::Lemke);
}

/// `"auto"` for two bodies with friction: the active-set solver from
/// [`ContactSolver::FRICTION_PAIR_AUTO_THRESHOLD`] candidates, Lemke's path below. The strip
/// `L × 1` at h = 0.25 on an elastic block (`strip_on_block`, μ = 0.3) has `4 L` candidates.
/// The active set's answer at the threshold is checked on its own (step residual, gaps, both
/// bodies' equilibrium); below it, only the path and the step residual: on this slender strip
/// Lemke's step LCP ends inaccurate and the fixed point answers (observed residual 2.4e-11),
/// whose recovered gaps miss its step gaps by 1.5e-11, its own round-off.
#[test]
fn auto_switches_at_the_pair_friction_threshold() {
    let pair = |length: f64| {
        let mut p = super::strip::strip_on_block(0.25, length);
        p.contact_mut().unwrap().friction = 0.3;
        p
    };
    let threshold = ContactSolver::FRICTION_PAIR_AUTO_THRESHOLD;
    for (candidates, active_set) in [(threshold, true), (threshold - 1, false)] {
        let s = mlpg_contact::solve(&pair(candidates as f64 / 4.0)).unwrap();
        let c = s.contact().unwrap();
        assert_eq!(c.candidates.len(), candidates);
        assert_eq!(c.active_set.is_some(), active_set, "{candidates} candidates");
        let method = c.friction.as_ref().unwrap().step.method;
        assert_eq!(method == FrictionMethod::ActiveSet, active_set, "{method:?}");
        let f = c.friction.as_ref().unwrap();
        assert!(f.step.residuals.max() <= 1e-9, "{candidates}: {:?}", f.step.residuals);
        if active_set {
            check_frictional(&s, &format!("frictional pair, {candidates} candidates"));
        }
        let s2 = s.body(1).unwrap();
        assert!(s2.equilibrium_error <= 1e-8, "body 2 equilibrium {}", s2.equilibrium_error);
    }
}
