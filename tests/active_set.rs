//! The primal–dual active-set solver's dense entry point (`lcp::active_set::DenseSystem`,
//! docs/method.md §5.1) against Lemke's method: the P-matrix cases of the external LCP suite
//! (`tests/data/lcp-suite`), random P-matrix problems checked against brute-force
//! enumeration, and the safeguard on a problem where the plain iteration cycles.

mod lcp_support;

use lcp_support::{load_suite, max_abs, permuted_triangular, positive_definite_plus_skew};
use mlpg_contact::lcp::active_set::{
    ActiveSetEnd, ActiveSetError, ActiveSetParams, DenseSystem, solve,
};
use mlpg_contact::lcp::{Lcp, LemkeParams, enumerate_solutions, lemke};
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
