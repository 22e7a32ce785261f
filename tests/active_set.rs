//! The primal–dual active-set solver's dense entry point (`lcp::active_set::DenseSystem`,
//! docs/method.md §5.1) against Lemke's method: the P-matrix cases of the external LCP suite
//! (`tests/data/lcp-suite`), random P-matrix problems checked against brute-force
//! enumeration, and the safeguard on a problem where the plain iteration cycles; and the
//! frictional active-set step (`DenseFriction`) against the Lemke-based step
//! (`lcp::solve_step`): random steps, a load path with reversal, and cycling.

mod lcp_support;

use lcp_support::{load_suite, max_abs, permuted_triangular, positive_definite_plus_skew};
use mlpg_contact::lcp::active_set::{
    ActiveSetEnd, ActiveSetError, ActiveSetParams, DenseFriction, DenseSystem,
    FrictionStepSolution, solve, solve_friction_step,
};
use mlpg_contact::lcp::{
    ContactState, FrictionProblem, Lcp, LemkeParams, enumerate_solutions, lemke, solve_step,
};
use proptest::prelude::*;

/// `max |a − b| / max(1, ‖b‖∞)`.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs())) / max_abs(b).max(1.0)
}

/// Every case of the suite whose M is marked a P-matrix (unique solution): the active-set
/// answer equals Lemke's to 1e-10 (both are exact up to round-off on these n ≤ 30 problems;
/// Lemke's own acceptance threshold is 1e-9) and passes the scaled residual test.
#[test]
fn p_matrix_suite_cases_equal_lemke() {
    let mut checked = 0;
    for case in load_suite().iter().filter(|c| c.p_matrix) {
        let (name, lcp) = (&case.name, &case.lcp);
        let reference = lemke(lcp, &LemkeParams::default()).unwrap();
        let answer = solve(&mut DenseSystem::new(lcp), &ActiveSetParams::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let r = lcp.residuals(&answer.lcp.z);
        assert!(r.max_violation() < 1e-10, "{name}: residuals {r:?}");
        let d = distance(&answer.lcp.z, &reference.z);
        assert!(d < 1e-10, "{name}: |z − z_Lemke| = {d:e}");
        checked += 1;
    }
    assert!(checked >= 5, "only {checked} P-matrix cases found");
}

/// A 3 × 3 P-matrix problem (integer data, found by a search over random P-matrices) on which
/// the plain iteration from the candidates with negative `q` visits {0, 2}, {1, 2}, ∅ and
/// comes back to {0, 2}. Without rescues the solver must say so; with them (the default) it
/// hands the changing candidates to Lemke and returns the unique solution.
#[test]
fn cycling_is_detected_and_rescued_by_lemke() {
    let lcp = Lcp::from_rows(
        &[vec![1.0, -3.0, 3.0], vec![3.0, 2.0, 1.0], vec![0.0, -1.0, 1.0]],
        vec![-1.0, 3.0, -1.0],
    )
    .unwrap();
    let plain = ActiveSetParams { max_fallbacks: 0, ..ActiveSetParams::default() };
    match solve(&mut DenseSystem::new(&lcp), &plain) {
        Err(ActiveSetError::NotConverged { iterations, fallbacks, reason }) => {
            assert_eq!((iterations, fallbacks), (3, 0));
            assert_eq!(reason, "an active set came back");
        }
        other => panic!("expected a cycle, got {other:?}"),
    }
    let answer = solve(&mut DenseSystem::new(&lcp), &ActiveSetParams::default()).unwrap();
    assert_eq!(answer.end, ActiveSetEnd::ConvergedAfterRescue);
    assert_eq!(answer.rescues.len(), 1);
    let all = enumerate_solutions(&lcp);
    assert_eq!(all.len(), 1, "a P-matrix LCP has one solution");
    assert!(distance(&answer.lcp.z, &all[0]) < 1e-12, "{:?} vs {:?}", answer.lcp.z, all[0]);
    assert!(lcp.residuals(&answer.lcp.z).max_violation() < 1e-12);
}

/// The active-set answer (rescues allowed) against the unique enumerated solution.
fn check(n: usize, m: Vec<f64>, q: Vec<f64>) -> Result<(), TestCaseError> {
    let lcp = Lcp::new(n, m, q).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let answer = solve(&mut DenseSystem::new(&lcp), &ActiveSetParams::default())
        .map_err(|e| TestCaseError::fail(format!("active set failed: {e}")))?;
    let all = enumerate_solutions(&lcp);
    prop_assert_eq!(all.len(), 1);
    let d = distance(&answer.lcp.z, &all[0]);
    prop_assert!(d <= 1e-9, "z {:?} vs {:?}", answer.lcp.z, all[0]);
    prop_assert!(lcp.residuals(&answer.lcp.z).max_violation() < 1e-10);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { failure_persistence: None, ..ProptestConfig::default() })]

    /// M = AᵀA + δI + (S − Sᵀ): positive definite symmetric part plus a skew part (the
    /// character of the contact compliance).
    #[test]
    fn matches_enumeration_positive_definite(
        (n, a, s, delta, skew, q) in (1usize..=6).prop_flat_map(|n| (
            Just(n),
            prop::collection::vec(-1.0..1.0_f64, n * n),
            prop::collection::vec(-1.0..1.0_f64, n * n),
            0.01..1.0_f64,
            0.0..2.0_f64,
            prop::collection::vec(-1.0..1.0_f64, n),
        ))
    ) {
        let m = positive_definite_plus_skew(n, &a, &s, delta, skew);
        check(n, m, q)?;
    }

    /// M = P L Pᵀ with L lower triangular: a P-matrix far from positive definite, where the
    /// plain iteration may cycle and the rescue must settle it.
    #[test]
    fn matches_enumeration_permuted_triangular(
        (n, l, diag, perm, q) in (1usize..=6).prop_flat_map(|n| (
            Just(n),
            prop::collection::vec(-2.0..2.0_f64, n * n),
            prop::collection::vec(0.5..2.0_f64, n),
            Just((0..n).collect::<Vec<usize>>()).prop_shuffle(),
            prop::collection::vec(-1.0..1.0_f64, n),
        ))
    ) {
        let m = permuted_triangular(n, &l, &diag, &perm);
        check(n, m, q)?;
    }
}

// Friction (docs/method.md §5.1 "Friction", §8): the frictional active-set step on the dense
// blocks (`DenseFriction`) against the Lemke-based step `lcp::solve_step`.

/// A random step problem whose 2m × 2m compliance `[[M_nn, M_nt], [M_tn, M_tt]]` has a
/// positive definite symmetric part (`B Bᵀ/2m + I`) plus a skew part of size `skew` (the
/// coupling of a finite body), pressed (`q_n ∈ [−1, 0.5]`) and pulled (`q_t ∈ [−1, 1]`).
fn friction_problem(seed: u64, m: usize, mu: f64, skew: f64) -> FrictionProblem {
    let mut state = seed;
    let mut uniform = |a: f64, b: f64| {
        // SplitMix64.
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        a + (b - a) * (z >> 11) as f64 / (1u64 << 53) as f64
    };
    let n = 2 * m;
    let b: Vec<f64> = (0..n * n).map(|_| uniform(-1.0, 1.0)).collect();
    let mut full = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let bb: f64 = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum();
            full[i * n + j] = bb / n as f64 + if i == j { 1.0 } else { 0.0 };
        }
    }
    for i in 0..n {
        for j in 0..i {
            let s = skew * uniform(-1.0, 1.0);
            full[i * n + j] += s;
            full[j * n + i] -= s;
        }
    }
    let block = |r: usize, c: usize| {
        let mut out = vec![0.0; m * m];
        for i in 0..m {
            for j in 0..m {
                out[i * m + j] = full[(r * m + i) * n + c * m + j];
            }
        }
        out
    };
    FrictionProblem {
        nn: block(0, 0),
        nt: block(0, 1),
        tn: block(1, 0),
        tt: block(1, 1),
        free_gap: (0..m).map(|_| uniform(-1.0, 0.5)).collect(),
        free_tangential: (0..m).map(|_| uniform(-1.0, 1.0)).collect(),
        previous_tangential: vec![0.0; m],
        friction: vec![mu; m],
    }
}

/// Both step solvers on `problem` from `previous`: forces, gaps, slip increments within
/// 1e-10 of their scales (both are exact up to round-off on these well-conditioned m ≤ 12
/// problems, whose answers were unique in every case tried), the same states, and the active-set answer's residuals ≤ 1e-12. Returns the
/// active-set answer.
fn check_friction_step(
    name: &str,
    problem: &FrictionProblem,
    start: Option<&[ContactState]>,
) -> FrictionStepSolution {
    let reference = solve_step(problem).unwrap_or_else(|e| panic!("{name}: Lemke: {e}"));
    let answer = solve_friction_step(
        &mut DenseFriction::new(problem),
        &problem.previous_tangential,
        start,
        &ActiveSetParams::default(),
    )
    .unwrap_or_else(|e| panic!("{name}: active set: {e}"));
    let s = &answer.step;
    let f = max_abs(&reference.normal).max(max_abs(&reference.tangential)).max(1.0);
    let u = max_abs(&reference.gap).max(max_abs(&reference.slip_increment)).max(1.0);
    let d = |a: &[f64], b: &[f64]| a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    let df = d(&s.normal, &reference.normal).max(d(&s.tangential, &reference.tangential)) / f;
    let du = d(&s.gap, &reference.gap).max(d(&s.slip_increment, &reference.slip_increment)) / u;
    assert!(df < 1e-10 && du < 1e-10, "{name}: forces {df:e}, gaps/slips {du:e}");
    assert_eq!(s.state, reference.state, "{name}: states");
    // The answer on its own: the residuals against the dense blocks (lcp::solve_step's).
    let r = problem.residuals(&s.normal, &s.tangential);
    assert!(r.max() <= 1e-12, "{name}: residuals {r:?}");
    assert!(s.residuals.max() <= 1e-12, "{name}: own residuals {:?}", s.residuals);
    answer
}

/// Random single steps (m = 1 … 12, μ = 0.1, 0.3 and 3, coupling skew 0.05): the same answer
/// as the Lemke-based step; stick, slip and mixed answers all occur.
#[test]
fn frictional_steps_equal_the_lemke_step() {
    let (mut stick, mut slip, mut mixed) = (0, 0, 0);
    for case in 0..120_u64 {
        let (m, mu) = (1 + (case as usize) % 12, [0.1, 0.3, 3.0][(case % 3) as usize]);
        let problem = friction_problem(case, m, mu, 0.05);
        let answer = check_friction_step(&format!("case {case}"), &problem, None);
        let st = &answer.step.state;
        let sticks = st.iter().filter(|&&s| s == ContactState::Stick).count();
        let slips = st.iter().filter(|s| s.is_slip()).count();
        match (sticks > 0, slips > 0) {
            (true, true) => mixed += 1,
            (true, false) => stick += 1,
            (false, true) => slip += 1,
            _ => {}
        }
    }
    println!("stick only {stick}, slip only {slip}, mixed {mixed}");
    assert!(stick > 0 && slip > 0 && mixed > 0, "stick {stick}, slip {slip}, mixed {mixed}");
}

/// A load path of several steps: the pull `q_t` grows, then reverses (`q_t = λ q̂_t`,
/// λ = 0.3, 0.6, 1, 0.5, 0, −0.5, −1) with the press held; each solver carries its own
/// `s_prev` and the active set starts from its previous states (warm start). Both chains stay
/// equal, and some candidate slips both ways.
#[test]
fn frictional_load_path_with_reversal_equals_the_lemke_step() {
    let mut reversals = 0;
    for case in 0..20_u64 {
        let base = friction_problem(1000 + case, 4 + (case as usize) % 6, 0.3, 0.05);
        let q_t = base.free_tangential.clone();
        let mut problem = base.clone();
        let mut states: Option<Vec<ContactState>> = None;
        let mut signs = vec![(false, false); base.size()];
        for (k, lambda) in [0.3, 0.6, 1.0, 0.5, 0.0, -0.5, -1.0].into_iter().enumerate() {
            problem.free_tangential = q_t.iter().map(|q| lambda * q).collect();
            let answer =
                check_friction_step(&format!("case {case}, step {k}"), &problem, states.as_deref());
            for (c, s) in answer.step.state.iter().enumerate() {
                signs[c].0 |= *s == ContactState::SlipPositive;
                signs[c].1 |= *s == ContactState::SlipNegative;
            }
            problem.previous_tangential = answer.step.tangential_displacement.clone();
            states = Some(answer.states);
        }
        reversals += signs.iter().filter(|s| s.0 && s.1).count();
    }
    assert!(reversals > 0, "no candidate slipped both ways");
}

/// The 3 × 3 problem on which the frictionless iteration cycles, as the normal block of a
/// frictional step with μ = 0.2 (no coupling, `M_tt = I`, no pull: `T = 0`, every closed
/// candidate sticks): the plain iteration cycles through the same sets; without rescues the
/// solver reports it (`NotConverged`, never an answer); with them it settles on the unique
/// solution, which the Lemke-based step also finds.
#[test]
fn frictional_cycling_is_reported_or_rescued() {
    let problem = FrictionProblem {
        nn: vec![1.0, -3.0, 3.0, 3.0, 2.0, 1.0, 0.0, -1.0, 1.0],
        nt: vec![0.0; 9],
        tn: vec![0.0; 9],
        tt: vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        free_gap: vec![-1.0, 3.0, -1.0],
        free_tangential: vec![0.0; 3],
        previous_tangential: vec![0.0; 3],
        friction: vec![0.2; 3],
    };
    let plain = ActiveSetParams { max_fallbacks: 0, ..ActiveSetParams::default() };
    let previous = vec![0.0; 3];
    match solve_friction_step(&mut DenseFriction::new(&problem), &previous, None, &plain) {
        Err(ActiveSetError::NotConverged { iterations, fallbacks, reason }) => {
            assert_eq!((iterations, fallbacks), (3, 0));
            assert_eq!(reason, "a set of states came back");
        }
        other => panic!("expected a cycle, got {other:?}"),
    }
    let answer = check_friction_step("cycling", &problem, None);
    assert_eq!(answer.end, ActiveSetEnd::ConvergedAfterRescue);
    assert_eq!(answer.rescues.len(), 1);
}

/// The suite's cases whose `M` is not marked a P-matrix (no solution, several, or one that
/// Lemke's method may miss): the active-set solver either answers with an `z` that passes
/// the residual test (1e-9, Lemke's acceptance threshold), or reports that it could not
/// converge (its cycle detection, the iteration limit or a failed Lemke rescue) or that a
/// linear problem of a guess is singular — never an unconverged answer. On a case stated to
/// have no solution it must report.
#[test]
fn other_suite_cases_answer_or_report() {
    let (mut answered, mut reported) = (Vec::new(), Vec::new());
    for case in load_suite().iter().filter(|c| !c.p_matrix) {
        let (name, lcp) = (&case.name, &case.lcp);
        match solve(&mut DenseSystem::new(lcp), &ActiveSetParams::default()) {
            Ok(answer) => {
                let r = lcp.residuals(&answer.lcp.z);
                assert!(r.max_violation() < 1e-9, "{name}: an answer with residuals {r:?}");
                assert!(case.solution_exists, "{name}: has no solution, yet answered");
                answered.push(name.clone());
            }
            Err(
                e @ (ActiveSetError::NotConverged { .. }
                | ActiveSetError::Rescue(_)
                | ActiveSetError::Solve(_)
                | ActiveSetError::Singular { .. }),
            ) => reported.push(format!("{name}: {e}")),
            Err(e) => panic!("{name}: unexpected {e}"),
        }
    }
    println!("answered: {answered:?}");
    for r in &reported {
        println!("reported: {r}");
    }
    assert!(answered.len() + reported.len() >= 5, "few non-P-matrix cases in the suite");
}
