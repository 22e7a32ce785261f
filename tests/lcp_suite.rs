//! Lemke's method against the external LCP test suite (`tests/data/lcp-suite`, see its
//! README.md: 20 cases converted from Siconos under Apache-2.0 and 9 hand-made ones), plus
//! property tests against brute-force enumeration on random P-matrix problems.

use mlpg_contact::lcp::{Lcp, LcpError, LemkeParams, enumerate_solutions, lemke};
use proptest::prelude::*;
mod lcp_support;

use lcp_support::{
    load_suite, max_abs, permuted_triangular, positive_definite_plus_skew, suite_dir,
};

/// Scaled residual tolerance of the suite's README ("How a test should check a result").
const SUITE_TOL: f64 = 1e-9;

/// Runs every case and checks it as the suite's README prescribes; collects all failures and
/// prints a table of outcomes (visible with `--nocapture`).
#[test]
fn lcp_suite_all_cases() {
    let cases = load_suite();
    assert_eq!(cases.len(), 29, "the suite has 29 cases");
    let params = LemkeParams::default();
    let mut failures = Vec::new();
    println!(
        "{:<32} {:>3} {:>9} {:>9} {:>7} {:>7} {:>10} {:>10}",
        "case", "n", "expected", "outcome", "pivots", "ref", "residual", "|z-z_ref|"
    );
    for case in &cases {
        let name = &case.name;
        let result = lemke(&case.lcp, &params);
        let (outcome, pivots, residual) = match &result {
            Ok(s) => ("solution", Some(s.pivots), s.residuals.max_violation()),
            Err(LcpError::RayTermination { pivots }) => ("ray", Some(*pivots), f64::NAN),
            Err(_) => ("error", None, f64::NAN),
        };
        // Distance to the stored z (informational unless M is a P-matrix).
        let z_dist = match (&result, &case.z) {
            (Ok(s), Some(zref)) => {
                s.z.iter().zip(zref).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
            }
            _ => f64::NAN,
        };
        println!(
            "{name:<32} {:>3} {:>9} {outcome:>9} {:>7} {:>7} {residual:>10.1e} {z_dist:>10.1e}",
            case.lcp.size(),
            case.expected,
            pivots.map_or("-".into(), |p| p.to_string()),
            case.lemke_pivots.map_or("-".into(), |p| p.to_string())
        );
        match (case.expected.as_str(), &result) {
            ("solution", Ok(s)) => {
                // The README's residual test, in the scaling of `LcpResiduals`.
                let r = case.lcp.residuals(&s.z);
                let expected_scale = 1.0_f64
                    .max(max_abs(case.lcp.q()))
                    .max(max_abs(case.lcp.m_row_major()) * max_abs(&s.z));
                if (r.scale - expected_scale).abs() > 1e-12 * expected_scale {
                    failures
                        .push(format!("{name}: residual scale {} != {expected_scale}", r.scale));
                }
                if r.min_z < -SUITE_TOL || r.min_w < -SUITE_TOL || r.max_complementarity > SUITE_TOL
                {
                    failures.push(format!("{name}: residuals too large: {r:?}"));
                }
                if s.residuals.max_violation() > SUITE_TOL {
                    failures.push(format!("{name}: reported residuals {:?}", s.residuals));
                }
                let w = case.lcp.w(&s.z);
                if s.w.iter().zip(&w).any(|(a, b)| a != b) {
                    failures.push(format!("{name}: returned w is not M z + q"));
                }
                // Compare z only where the solution is unique (M is a P-matrix).
                if case.p_matrix {
                    let zref = case.z.as_deref().unwrap_or_default();
                    let err = s.z.iter().zip(zref).fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
                    if zref.len() != s.z.len() || err > 1e-8 * max_abs(zref).max(1.0) {
                        failures.push(format!("{name}: z = {:?}, reference {zref:?}", s.z));
                    }
                }
            }
            ("ray", Err(LcpError::RayTermination { .. })) => {
                // Where the suite proves infeasibility, enumeration must find nothing either.
                if !case.solution_exists && !enumerate_solutions(&case.lcp).is_empty() {
                    failures.push(format!("{name}: enumeration found a solution"));
                }
            }
            (exp, res) => failures.push(format!("{name}: expected {exp}, got {res:?}")),
        }
        // Our rule is exactly the reference rule (lexicographic on [B⁻¹q, B⁻¹], natural
        // order, largest index at the first pivot, pivots counted with z0 in and out).
        if let (Some(p), Some(reference)) = (pivots, case.lemke_pivots) {
            if p != reference {
                failures.push(format!("{name}: {p} pivots, reference {reference}"));
            }
        }
    }
    assert!(failures.is_empty(), "{} failure(s):\n{}", failures.len(), failures.join("\n"));
}

/// The suite directory carries its licence and attribution next to the data.
#[test]
fn lcp_suite_has_licence_and_readme() {
    let dir = suite_dir();
    let licence = std::fs::read_to_string(dir.join("LICENSE-APACHE-2.0.txt")).unwrap();
    assert!(licence.contains("Apache License"));
    let readme = std::fs::read_to_string(dir.join("README.md")).unwrap();
    assert!(readme.contains("Siconos") && readme.contains("Apache"));
}

/// The cases with a stored z: the stored z passes the residual test (checks the loader and
/// `Lcp::residuals` against the suite's own verification).
#[test]
fn lcp_suite_stored_solutions_pass_residual_test() {
    for case in load_suite() {
        if let Some(z) = &case.z {
            let r = case.lcp.residuals(z);
            assert!(r.max_violation() <= SUITE_TOL, "{}: {r:?}", case.name);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Property tests: Lemke against brute-force enumeration on problems with a unique solution.
// ---------------------------------------------------------------------------------------------

/// Lemke must solve LCP(q, M) for a P-matrix M, and agree with the unique enumerated solution.
fn check_against_enumeration(n: usize, m: Vec<f64>, q: Vec<f64>) -> Result<(), TestCaseError> {
    let lcp = Lcp::new(n, m, q).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let s = lemke(&lcp, &LemkeParams::default())
        .map_err(|e| TestCaseError::fail(format!("lemke failed: {e}")))?;
    prop_assert!(s.residuals.max_violation() < 1e-12, "residuals {:?}", s.residuals);
    let all = enumerate_solutions(&lcp);
    prop_assert_eq!(all.len(), 1, "P-matrix LCP must have exactly one solution: {:?}", all);
    let err = s.z.iter().zip(&all[0]).fold(0.0_f64, |acc, (a, b)| acc.max((a - b).abs()));
    prop_assert!(err <= 1e-9 * max_abs(&s.z).max(1.0), "z {:?} vs {:?}", s.z, all[0]);
    Ok(())
}

/// q entries: mostly uniform, with exact zeros and repeated values to provoke degeneracy.
fn q_entry() -> impl Strategy<Value = f64> {
    prop_oneof![4 => -1.0..1.0_f64, 1 => Just(0.0), 1 => Just(-1.0), 1 => Just(0.5)]
}

proptest! {
    // No regression files: a failure prints its (shrunk) input.
    #![proptest_config(ProptestConfig { failure_persistence: None, ..ProptestConfig::default() })]

    /// Any M (small integers: highly degenerate): the lexicographic rule guarantees
    /// termination, so the outcome is a verified solution or a secondary ray, never a pivot
    /// limit or an inaccurate result.
    #[test]
    fn lemke_terminates_on_general_matrices(
        (n, m, q) in (1usize..=6).prop_flat_map(|n| (
            Just(n),
            prop::collection::vec(-3i32..=3, n * n),
            prop::collection::vec(-3i32..=3, n),
        ))
    ) {
        let m: Vec<f64> = m.iter().map(|&x| f64::from(x)).collect();
        let q: Vec<f64> = q.iter().map(|&x| f64::from(x)).collect();
        let lcp = Lcp::new(n, m, q).map_err(|e| TestCaseError::fail(e.to_string()))?;
        match lemke(&lcp, &LemkeParams::default()) {
            Ok(s) => {
                prop_assert!(s.residuals.max_violation() < 1e-12, "residuals {:?}", s.residuals);
                prop_assert!(lcp.residuals(&s.z).max_violation() < 1e-12);
            }
            Err(LcpError::RayTermination { pivots }) => {
                prop_assert!(pivots >= 1);
            }
            Err(e) => prop_assert!(false, "unexpected error: {}", e),
        }
    }

    /// M = AᵀA + δI + (S − Sᵀ): positive definite symmetric part plus a skew part.
    #[test]
    fn lemke_matches_enumeration_positive_definite(
        (n, a, s, delta, skew, q) in (1usize..=6).prop_flat_map(|n| (
            Just(n),
            prop::collection::vec(-1.0..1.0_f64, n * n),
            prop::collection::vec(-1.0..1.0_f64, n * n),
            0.01..1.0_f64,
            0.0..2.0_f64,
            prop::collection::vec(q_entry(), n),
        ))
    ) {
        let m = positive_definite_plus_skew(n, &a, &s, delta, skew);
        check_against_enumeration(n, m, q)?;
    }

    /// Non-symmetric, strictly row diagonally dominant with positive diagonal (a P-matrix whose
    /// symmetric part need not be positive definite), with integer-valued data for many ties.
    #[test]
    fn lemke_matches_enumeration_diagonally_dominant(
        (n, off, margin, q) in (1usize..=6).prop_flat_map(|n| (
            Just(n),
            prop::collection::vec(-3i32..=3, n * n),
            prop::collection::vec(1i32..=3, n),
            prop::collection::vec(-3i32..=3, n),
        ))
    ) {
        let mut m: Vec<f64> = off.iter().map(|&x| f64::from(x)).collect();
        for i in 0..n {
            let row_sum: f64 = (0..n).filter(|&j| j != i).map(|j| m[i * n + j].abs()).sum();
            m[i * n + i] = row_sum + f64::from(margin[i]);
        }
        check_against_enumeration(n, m, q.iter().map(|&x| f64::from(x)).collect())?;
    }

    /// M = P L Pᵀ with L lower triangular, positive diagonal, large off-diagonal entries: a
    /// P-matrix far from positive definite (Murty-like, many pivots).
    #[test]
    fn lemke_matches_enumeration_permuted_triangular(
        (n, l, diag, perm, q) in (1usize..=6).prop_flat_map(|n| (
            Just(n),
            prop::collection::vec(-2.0..2.0_f64, n * n),
            prop::collection::vec(0.5..2.0_f64, n),
            Just((0..n).collect::<Vec<usize>>()).prop_shuffle(),
            prop::collection::vec(q_entry(), n),
        ))
    ) {
        let m = permuted_triangular(n, &l, &diag, &perm);
        check_against_enumeration(n, m, q)?;
    }
}
