//! The extreme eigenvalues of the symmetric part `S = (M + Mᵀ)/2` of the compliance — the
//! run-time checks of [`super::CondensedContact::combine`] — without a full eigen-decomposition.
//!
//! 1. A dense Cholesky factorisation `S = L Lᵀ` decides positive definiteness (`n³/3` flops
//!    at matrix–matrix speed, against the `4n³/3`, half of them matrix–vector, of the
//!    tridiagonalisation in a full eigen-decomposition: 0.2 s against 2 s at n = 2 000).
//! 2. `λ_max(S)` is the largest Ritz value of Lanczos on `S`, and `λ_min(S) = 1/μ_max` with
//!    `μ_max` the largest Ritz value of Lanczos on `S⁻¹ = L⁻ᵀ L⁻¹` (two triangular solves per
//!    step). Both runs reorthogonalise fully (classical Gram–Schmidt, twice) and start from the
//!    same fixed pseudo-random vector; a run stops when the residual bound of its Ritz pair
//!    `r = β_k |s_k|` is at most [`RESIDUAL_TOLERANCE`] times the Ritz value `θ`, or when the
//!    Krylov space is invariant.
//!
//! Accuracy: in exact arithmetic `θ` lies inside the spectrum (`θ ≤ λ_max`, `1/μ ≥ λ_min`)
//! and within `r` of an eigenvalue, so each reported value is within a relative 10⁻⁸ of an
//! eigenvalue of `S` — the extreme one unless the start vector is (to rounding) orthogonal to
//! its eigenvector — and its error is of order `r²/gap`, far smaller. Rounding makes the
//! estimates extreme eigenvalues of `S + δS` with `‖δS‖ = O(n ε ‖S‖)` (the backward error of
//! the Cholesky factor and the solves), which is the accuracy of a full eigen-decomposition as
//! well: an absolute `O(n ε λ_max)` in `λ_min`. On the 2 000-candidate strip
//! (`examples/studies/contact_timing.rs`, `λ_max/λ_min ≈ 10⁹`) the estimates and all eigenvalues agree
//! to 1.6·10⁻⁹ relative in `λ_min` and 1.5·10⁻¹⁵ in `λ_max`; the unit tests compare them on
//! matrices with known spectra (condition numbers up to 10⁶, double extreme eigenvalues).
//!
//! The full eigenvalues ([`EigenvalueMethod::Full`]) are still computed when the Cholesky
//! factorisation fails (`S` is not positive definite: the exact negative or zero eigenvalue is
//! then reported, and the caller refuses `M`), when the estimate is within a factor 100 of the
//! caller's refusal threshold (`λ_min ≤ 10⁻¹⁰ λ_max`, so that decision is taken on the exact
//! eigenvalue as before), or when a Lanczos run has not converged after [`MAX_STEPS`] steps.
//!
//! Everything runs sequentially (`Par::Seq`) with a fixed start vector, so the reported values
//! are bit-identical whatever the number of threads.

use crate::linear_solve::SolveError;
use crate::random::SplitMix64;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::evd::{ComputeEigenvectors, self_adjoint_evd, self_adjoint_evd_scratch};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Accum, Mat, MatMut, MatRef, Par};
use serde::Serialize;

/// A Lanczos run stops when its residual bound is at most this fraction of the Ritz value
/// (10⁻⁸: the strip's `λ_min` run then takes 46 steps instead of 54 for 10⁻¹⁰, and the
/// Ritz value's actual error, of order `r²/gap`, is already at rounding level).
pub const RESIDUAL_TOLERANCE: f64 = 1e-8;

/// Lanczos steps after which a run gives up and the full eigenvalues are computed (the
/// 2 000-candidate strip needs 5 steps for `λ_max` and 46 for `λ_min`).
pub const MAX_STEPS: usize = 200;

/// Estimates `λ_min ≤ NEAR_SINGULAR · λ_max` are replaced by the full eigenvalues (the contact
/// pipeline refuses `M` at `λ_min ≤ 10⁻¹² λ_max`).
const NEAR_SINGULAR: f64 = 1e-10;

/// How [`SymmetricExtremes`] were obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EigenvalueMethod {
    /// Cholesky factorisation (positive definite) and Lanczos estimates.
    Lanczos,
    /// All eigenvalues (the matrix is not positive definite, nearly singular, or a Lanczos run
    /// did not converge).
    Full,
}

/// The smallest and largest eigenvalue of a symmetric matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SymmetricExtremes {
    /// Smallest eigenvalue (`+∞` for an empty matrix).
    pub min: f64,
    /// Largest eigenvalue (`−∞` for an empty matrix).
    pub max: f64,
    /// How they were computed.
    pub method: EigenvalueMethod,
}

/// The extreme eigenvalues of the symmetric matrix `a` (both halves are read: `a` must be
/// symmetric); see the module documentation for the method and its accuracy.
///
/// # Errors
/// [`SolveError::Backend`] when a dense eigenvalue problem fails or memory runs out.
pub fn symmetric_extremes(a: MatRef<'_, f64>) -> Result<SymmetricExtremes, SolveError> {
    let n = a.nrows();
    if n == 0 {
        return Ok(SymmetricExtremes {
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            method: EigenvalueMethod::Full,
        });
    }
    if let Some(l) = cholesky(a)? {
        let largest = lanczos_largest(n, |x, y| {
            matmul(y, Accum::Replace, a, x, 1.0, Par::Seq);
        })?;
        let inverse_largest = lanczos_largest(n, |x, mut y| {
            y.copy_from(x);
            solve_lower_triangular_in_place(l.as_ref(), y.as_mut(), Par::Seq);
            solve_upper_triangular_in_place(l.as_ref().transpose(), y.as_mut(), Par::Seq);
        })?;
        if let (Some(max), Some(mu)) = (largest, inverse_largest) {
            let min = 1.0 / mu;
            if min > NEAR_SINGULAR * max && min.is_finite() {
                return Ok(SymmetricExtremes { min, max, method: EigenvalueMethod::Lanczos });
            }
        }
    }
    let eig = symmetric_eigenvalues(a)?;
    Ok(SymmetricExtremes {
        min: eig.iter().copied().fold(f64::INFINITY, f64::min),
        max: eig.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        method: EigenvalueMethod::Full,
    })
}

fn buffer(req: StackReq) -> Result<MemBuffer, SolveError> {
    MemBuffer::try_new(req).map_err(|e| SolveError::Backend(format!("{e:?}")))
}

/// The lower Cholesky factor of `a` (lower half read), or `None` if a pivot is not positive.
fn cholesky(a: MatRef<'_, f64>) -> Result<Option<Mat<f64>>, SolveError> {
    use faer::linalg::cholesky::llt::factor::{cholesky_in_place, cholesky_in_place_scratch};
    let n = a.nrows();
    let mut l = a.to_owned();
    let mut buf = buffer(cholesky_in_place_scratch::<f64>(n, Par::Seq, Default::default()))?;
    let factored = cholesky_in_place(
        l.as_mut(),
        Default::default(),
        Par::Seq,
        MemStack::new(&mut buf),
        Default::default(),
    );
    Ok(factored.ok().map(|_| l))
}

/// The largest Ritz value of Lanczos with full reorthogonalisation (classical Gram–Schmidt,
/// twice) on the symmetric operator `apply(x, y): y ← A x`, from a fixed pseudo-random unit
/// vector, once the residual bound `β_k |s_k|` of its Ritz pair is at most
/// [`RESIDUAL_TOLERANCE`] times the Ritz value or the Krylov space is invariant; `None` after
/// [`MAX_STEPS`] steps.
fn lanczos_largest(
    n: usize,
    mut apply: impl FnMut(MatRef<'_, f64>, MatMut<'_, f64>),
) -> Result<Option<f64>, SolveError> {
    let steps = MAX_STEPS.min(n);
    // The Lanczos vectors, one per column.
    let mut q = Mat::<f64>::zeros(n, steps + 1);
    let mut rng = SplitMix64::new(0x5DEE_CE66_D1CE_4E5B);
    for i in 0..n {
        q[(i, 0)] = rng.uniform_symmetric();
    }
    let norm = q.col(0).norm_l2();
    q.col_mut(0).iter_mut().for_each(|x| *x /= norm);
    let (mut alpha, mut beta) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
    let mut w = Mat::<f64>::zeros(n, 1);
    let mut c = Mat::<f64>::zeros(steps, 1);
    for k in 0..steps {
        apply(q.as_ref().subcols(k, 1), w.as_mut());
        let a_k = q.col(k).transpose() * w.col(0);
        alpha.push(a_k);
        // Orthogonalise against all previous vectors (this includes the three-term
        // recurrence's α_k q_k + β_{k−1} q_{k−1}), twice.
        let basis = q.as_ref().subcols(0, k + 1);
        for _ in 0..2 {
            let mut ck = c.as_mut().subrows_mut(0, k + 1);
            matmul(ck.as_mut(), Accum::Replace, basis.transpose(), w.as_ref(), 1.0, Par::Seq);
            matmul(w.as_mut(), Accum::Add, basis, ck.as_ref(), -1.0, Par::Seq);
        }
        let b_k = w.col(0).norm_l2();
        let (theta, last) = largest_ritz_pair(&alpha, &beta)?;
        if b_k * last.abs() <= RESIDUAL_TOLERANCE * theta.abs() || k + 1 == n {
            return Ok(Some(theta));
        }
        beta.push(b_k);
        q.col_mut(k + 1).iter_mut().zip(w.col(0).iter()).for_each(|(x, &y)| *x = y / b_k);
    }
    Ok(None)
}

/// The largest eigenvalue of the symmetric tridiagonal matrix with diagonal `alpha` and
/// off-diagonal `beta` (one shorter), and the last component of its unit eigenvector.
fn largest_ritz_pair(alpha: &[f64], beta: &[f64]) -> Result<(f64, f64), SolveError> {
    let k = alpha.len();
    let t = Mat::<f64>::from_fn(k, k, |i, j| {
        if i == j {
            alpha[i]
        } else if i == j + 1 {
            beta[j]
        } else if j == i + 1 {
            beta[i]
        } else {
            0.0
        }
    });
    let par = Par::Seq;
    let req = self_adjoint_evd_scratch::<f64>(k, ComputeEigenvectors::Yes, par, Default::default());
    let mut buf = buffer(req)?;
    let mut s = faer::diag::Diag::<f64>::zeros(k);
    let mut u = Mat::<f64>::zeros(k, k);
    self_adjoint_evd(
        t.as_ref(),
        s.as_mut(),
        Some(u.as_mut()),
        par,
        MemStack::new(&mut buf),
        Default::default(),
    )
    .map_err(|e| SolveError::Backend(format!("{e:?}")))?;
    let mut best = 0;
    for i in 1..k {
        if s[i] > s[best] {
            best = i;
        }
    }
    Ok((s[best], u[(k - 1, best)]))
}

/// All eigenvalues of a symmetric matrix (lower half read), computed sequentially: faer's
/// convenience method follows the global parallelism setting and then sums in a
/// thread-dependent order, which changed the last digits of the reported eigenvalue between
/// thread counts at ~400 candidates.
pub(crate) fn symmetric_eigenvalues(a: MatRef<'_, f64>) -> Result<Vec<f64>, SolveError> {
    let n = a.nrows();
    let par = Par::Seq;
    let req = self_adjoint_evd_scratch::<f64>(n, ComputeEigenvectors::No, par, Default::default());
    let mut buf = buffer(req)?;
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    self_adjoint_evd(a, s.as_mut(), None, par, MemStack::new(&mut buf), Default::default())
        .map_err(|e| SolveError::Backend(format!("{e:?}")))?;
    Ok((0..n).map(|i| s[i]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Q diag(values) Qᵀ` with `Q` a product of three Householder reflectors of pseudo-random
    /// directions (so the eigenvalues are known exactly up to rounding in the product).
    fn with_spectrum(values: &[f64], seed: u64) -> Mat<f64> {
        let n = values.len();
        let mut a = Mat::<f64>::from_fn(n, n, |i, j| if i == j { values[i] } else { 0.0 });
        let mut rng = SplitMix64::new(seed);
        for _ in 0..3 {
            let v: Vec<f64> = (0..n).map(|_| rng.uniform_symmetric()).collect();
            let vv: f64 = v.iter().map(|x| x * x).sum();
            // A ← H A H with H = I − 2 v vᵀ / vᵀv.
            for pass in 0..2 {
                for j in 0..n {
                    let dot: f64 = (0..n).map(|i| v[i] * a[(i, j)]).sum::<f64>() * 2.0 / vv;
                    for i in 0..n {
                        a[(i, j)] -= dot * v[i];
                    }
                }
                if pass == 0 {
                    a = a.transpose().to_owned();
                }
            }
        }
        // Exactly symmetric.
        Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
    }

    fn exact(a: &Mat<f64>) -> (f64, f64) {
        let eig = symmetric_eigenvalues(a.as_ref()).unwrap();
        let min = eig.iter().copied().fold(f64::INFINITY, f64::min);
        (min, eig.iter().copied().fold(f64::NEG_INFINITY, f64::max))
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn lanczos_matches_the_full_eigenvalues() {
        // Spectra: geometric (condition 10⁶), a compliance-like 1/k decay with a cluster at
        // the bottom, a double smallest and a double largest eigenvalue, and a small matrix
        // that Lanczos exhausts.
        let n = 300;
        let geometric: Vec<f64> = (0..n).map(|i| 10f64.powf(-6.0 * i as f64 / 299.0)).collect();
        let decay: Vec<f64> = (0..n).map(|i| 1.0 / (1.0 + i as f64)).collect();
        let mut double: Vec<f64> = (0..n).map(|i| 2.0 + (i as f64 * 0.37).sin()).collect();
        double[5] = 0.5;
        double[17] = 0.5;
        double[40] = 4.0;
        double[41] = 4.0;
        let small = vec![3.0, 1.0, 2.0, 0.25];
        for (label, values) in
            [("geometric", geometric), ("decay", decay), ("double", double), ("small", small)]
        {
            let a = with_spectrum(&values, 0xC0FFEE ^ values.len() as u64);
            let got = symmetric_extremes(a.as_ref()).unwrap();
            let (min, max) = exact(&a);
            assert_eq!(got.method, EigenvalueMethod::Lanczos, "{label}");
            // λ_min carries the rounding of both methods, O(n ε λ_max). Observed: 1e-12 / 2e-14
            // (geometric), ≤ 5e-15 for the others.
            let min_tol = 1e-10 + 1e-13 * max / min;
            assert!(rel(got.min, min) <= min_tol, "{label}: {} vs {min}", got.min);
            assert!(rel(got.max, max) <= 1e-12, "{label}: {} vs {max}", got.max);
        }
    }

    #[test]
    fn not_positive_definite_reports_the_exact_eigenvalues() {
        let n = 50;
        let mut values: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        values[7] = -1e-3;
        let a = with_spectrum(&values, 7);
        let got = symmetric_extremes(a.as_ref()).unwrap();
        assert_eq!(got.method, EigenvalueMethod::Full);
        assert_eq!((got.min, got.max), exact(&a));
        assert!((got.min + 1e-3).abs() < 1e-12);
        // Nearly singular but positive definite: also the full eigenvalues.
        values[7] = 1e-13;
        let a = with_spectrum(&values, 7);
        let got = symmetric_extremes(a.as_ref()).unwrap();
        assert_eq!(got.method, EigenvalueMethod::Full);
        assert_eq!((got.min, got.max), exact(&a));
    }

    #[test]
    fn trivial_sizes() {
        let empty = symmetric_extremes(Mat::<f64>::zeros(0, 0).as_ref()).unwrap();
        assert_eq!((empty.min, empty.max), (f64::INFINITY, f64::NEG_INFINITY));
        let one = symmetric_extremes(Mat::<f64>::from_fn(1, 1, |_, _| 2.5).as_ref()).unwrap();
        assert_eq!((one.min, one.max, one.method), (2.5, 2.5, EigenvalueMethod::Lanczos));
        let two = Mat::<f64>::from_fn(2, 2, |i, j| if i == j { 2.0 } else { 1.0 });
        let got = symmetric_extremes(two.as_ref()).unwrap();
        assert!(rel(got.min, 1.0) < 1e-14 && rel(got.max, 3.0) < 1e-14, "{got:?}");
    }
}
