//! Stage 7 of the pipeline: the contact solvers. The linear complementarity problem (LCP) of
//! frictionless contact solved by Lemke's complementary pivot method; the frictional step LCP
//! of a load increment ([`friction`], docs/method.md §8); the searches of a force-driven
//! obstacle and a body held by contact ([`load_driven`], §4.6–4.7); the primal–dual active-set
//! iteration ([`active_set`], §5.1) over any system that implements its traits (the sparse
//! contact systems on the bodies' matrices are [`crate::contact::sparse`]).
//!
//! This module is pure algebra: it imports nothing from the rest of the crate (the
//! architecture test holds it to that), so its algorithms can be tested, reused and read
//! without bodies, matrices or problem files.
//!
//! Given a dense, generally non-symmetric matrix M ∈ ℝⁿˣⁿ and a vector q ∈ ℝⁿ, the LCP(q, M) asks
//! for z ∈ ℝⁿ with
//!
//! ```text
//!     z ≥ 0,   w = M z + q ≥ 0,   zᵀw = 0   (i.e. z_i w_i = 0 for every i).
//! ```
//!
//! In the contact pipeline z holds the contact pressures (or gap multipliers) of the n contact
//! candidates and w the corresponding gaps; complementarity says that a candidate either carries
//! load (z_i > 0, w_i = 0) or is open (z_i = 0, w_i ≥ 0).
//!
//! [`lemke()`] implements Lemke's method with covering vector d = e = (1, …, 1) and the
//! lexicographic minimum-ratio rule, which guarantees termination on degenerate problems
//! (Cottle, Pang & Stone, *The Linear Complementarity Problem*, Academic Press 1992, ch. 4,
//! cited as \[CPS92\] throughout this module). It ends either with a solution or on a secondary
//! ray; by [CPS92, §4.4] the latter proves that no solution exists when M is
//! copositive-plus (for instance positive semidefinite), and it cannot happen for P-matrices.
//! [`enumerate_solutions`] is an exponential brute-force reference used by the tests.
//! [`load_driven`] finds the displacement of a rigid obstacle pressed by a prescribed force
//! and the translation of a body held by the contact, one LCP per trial.

pub mod active_set;
mod enumerate;
pub mod friction;
mod lemke;
pub mod load_driven;

pub use enumerate::enumerate_solutions;
pub use friction::{
    ContactState, FrictionMethod, FrictionProblem, FrictionResiduals, FrictionSolution,
    FrictionlessStep, solve_frictionless_step, solve_step,
};
pub use lemke::{LemkeParams, Polish, closed_set_residual, lemke, lemke_observed, polish};

/// A linear complementarity problem LCP(q, M): find z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0
/// [CPS92, §1.1].
///
/// M is stored densely in row-major order (`M[i][j]` at index `i * n + j`). All entries are
/// checked to be finite on construction.
#[derive(Clone, Debug)]
pub struct Lcp {
    n: usize,
    m: Vec<f64>,
    q: Vec<f64>,
}

impl Lcp {
    /// Builds LCP(q, M) from the size n, the n·n entries of M in row-major order and the n
    /// entries of q.
    ///
    /// # Errors
    /// [`LcpError::DimensionMismatch`] if `m_row_major.len() != n * n` or `q.len() != n`;
    /// [`LcpError::NonFinite`] if an entry of M or q is NaN or infinite (the index is the
    /// row-major index for M).
    pub fn new(n: usize, m_row_major: Vec<f64>, q: Vec<f64>) -> Result<Self, LcpError> {
        let expected = n.checked_mul(n).ok_or(LcpError::DimensionMismatch {
            what: "M (n·n overflows)",
            expected: usize::MAX,
            found: m_row_major.len(),
        })?;
        if m_row_major.len() != expected {
            return Err(LcpError::DimensionMismatch {
                what: "M (row-major entries)",
                expected,
                found: m_row_major.len(),
            });
        }
        if q.len() != n {
            return Err(LcpError::DimensionMismatch { what: "q", expected: n, found: q.len() });
        }
        if let Some(index) = m_row_major.iter().position(|x| !x.is_finite()) {
            return Err(LcpError::NonFinite { what: "M", index });
        }
        if let Some(index) = q.iter().position(|x| !x.is_finite()) {
            return Err(LcpError::NonFinite { what: "q", index });
        }
        Ok(Self { n, m: m_row_major, q })
    }

    /// Builds LCP(q, M) from the rows of M (`rows[i][j]` = M_ij); n is `rows.len()`.
    ///
    /// # Errors
    /// As [`Lcp::new`]; a row whose length differs from n gives
    /// [`LcpError::DimensionMismatch`] with `what = "row of M"`.
    pub fn from_rows(rows: &[Vec<f64>], q: Vec<f64>) -> Result<Self, LcpError> {
        let n = rows.len();
        let mut m = Vec::with_capacity(n * n);
        for row in rows {
            if row.len() != n {
                return Err(LcpError::DimensionMismatch {
                    what: "row of M",
                    expected: n,
                    found: row.len(),
                });
            }
            m.extend_from_slice(row);
        }
        Self::new(n, m, q)
    }

    /// The problem size n (number of complementary pairs (z_i, w_i)).
    pub fn size(&self) -> usize {
        self.n
    }

    /// The entry M_ij (row i, column j).
    ///
    /// # Panics
    /// If `i >= n` or `j >= n`.
    pub fn m(&self, i: usize, j: usize) -> f64 {
        assert!(i < self.n && j < self.n, "index ({i}, {j}) out of range for n = {}", self.n);
        self.m[i * self.n + j]
    }

    /// The entries of M in row-major order (M_ij at index i·n + j).
    pub fn m_row_major(&self) -> &[f64] {
        &self.m
    }

    /// The vector q.
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// w = M z + q, computed from the original data.
    ///
    /// # Panics
    /// If `z.len() != n`.
    pub fn w(&self, z: &[f64]) -> Vec<f64> {
        assert_eq!(z.len(), self.n, "z has the wrong length");
        if self.n == 0 {
            return Vec::new();
        }
        self.m
            .chunks_exact(self.n)
            .zip(&self.q)
            .map(|(row, &qi)| row.iter().zip(z).map(|(a, b)| a * b).sum::<f64>() + qi)
            .collect()
    }

    /// Residuals of a candidate solution z, with w = M z + q recomputed from the original data
    /// (so `equation_residual` is 0). See [`LcpResiduals`] for the definitions and scaling.
    ///
    /// # Panics
    /// If `z.len() != n`.
    pub fn residuals(&self, z: &[f64]) -> LcpResiduals {
        let w = self.w(z);
        self.residuals_with_w(z, &w)
    }

    /// Residuals of a candidate pair (z, w) where w was obtained otherwise (for instance by
    /// pivoting); `equation_residual` measures ‖w − (M z + q)‖∞. See [`LcpResiduals`].
    ///
    /// # Panics
    /// If `z.len() != n` or `w.len() != n`.
    pub fn residuals_with_w(&self, z: &[f64], w: &[f64]) -> LcpResiduals {
        assert_eq!(w.len(), self.n, "w has the wrong length");
        let w_true = self.w(z);
        let max_abs = |v: &[f64]| v.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()));
        let z_max = max_abs(z);
        let scale = 1.0_f64.max(max_abs(&self.q)).max(max_abs(&self.m) * z_max);
        let min_z = z.iter().copied().fold(f64::INFINITY, f64::min);
        let min_w = w.iter().copied().fold(f64::INFINITY, f64::min);
        let compl = z.iter().zip(w).fold(0.0_f64, |acc, (a, b)| acc.max((a * b).abs()));
        let eq = w.iter().zip(&w_true).fold(0.0_f64, |acc, (a, b)| acc.max((a - b).abs()));
        let (min_z, min_w) = if self.n == 0 { (0.0, 0.0) } else { (min_z, min_w) };
        LcpResiduals {
            min_z: min_z / scale,
            min_w: min_w / scale,
            max_complementarity: compl / (scale * z_max.max(1.0)),
            equation_residual: eq / scale,
            scale,
        }
    }
}

/// Residuals of an approximate LCP solution (z, w), all divided by a common data scale.
///
/// With `scale` = s = max(1, maxᵢ|q_i|, maxᵢⱼ|M_ij| · maxⱼ|z_j|), the fields are
///
/// * `min_z` = minᵢ z_i / s (negative means infeasible z),
/// * `min_w` = minᵢ w_i / s (negative means infeasible w),
/// * `max_complementarity` = maxᵢ |z_i w_i| / (s · max(1, maxᵢ|z_i|)),
/// * `equation_residual` = ‖w − (M z + q)‖∞ / s.
///
/// This is the residual test of the project's LCP test suite: a solution is accepted at
/// tolerance τ if `min_z ≥ −τ`, `min_w ≥ −τ`, `max_complementarity ≤ τ` and
/// `equation_residual ≤ τ` (see [`LcpResiduals::max_violation`]). For an empty problem
/// (n = 0) all residuals are 0.
#[derive(Clone, Copy, Debug)]
pub struct LcpResiduals {
    /// minᵢ z_i / s.
    pub min_z: f64,
    /// minᵢ w_i / s.
    pub min_w: f64,
    /// maxᵢ |z_i w_i| / (s · max(1, ‖z‖∞)).
    pub max_complementarity: f64,
    /// ‖w − (M z + q)‖∞ / s; 0 when w was recomputed from z. For [`lemke()`] it is the
    /// discrepancy between the basic values maintained by the pivoting and the recomputed w,
    /// a measure of the accumulated round-off.
    pub equation_residual: f64,
    /// The scale s = max(1, ‖q‖∞, max|M_ij| · ‖z‖∞) the other fields are divided by.
    pub scale: f64,
}

impl LcpResiduals {
    /// The largest scaled violation max(0, −min_z, −min_w, max_complementarity,
    /// equation_residual); a solution passes at tolerance τ iff this is ≤ τ.
    pub fn max_violation(&self) -> f64 {
        0.0_f64
            .max(-self.min_z)
            .max(-self.min_w)
            .max(self.max_complementarity)
            .max(self.equation_residual)
    }
}

/// A solution of LCP(q, M) found by [`lemke()`].
#[derive(Clone, Debug)]
pub struct LcpSolution {
    /// z ≥ 0 (tiny negative round-off clipped to 0).
    pub z: Vec<f64>,
    /// w = M z + q, recomputed from the original data with the final z.
    pub w: Vec<f64>,
    /// Number of pivots (basis changes), counting z0 entering and z0 leaving; 0 when q ≥ 0.
    pub pivots: usize,
    /// Residuals of (z, w); see [`LcpResiduals`] for the scaling.
    pub residuals: LcpResiduals,
}

/// Errors of LCP construction and of Lemke's method.
#[derive(Debug, thiserror::Error)]
pub enum LcpError {
    /// An input array has the wrong length.
    #[error("LCP dimension mismatch: {what} has length {found}, expected {expected}")]
    DimensionMismatch {
        /// Which array.
        what: &'static str,
        /// The required length.
        expected: usize,
        /// The actual length.
        found: usize,
    },
    /// An input entry is NaN or infinite.
    #[error("LCP data not finite: {what}[{index}] is NaN or infinite")]
    NonFinite {
        /// `"M"` (row-major index) or `"q"`.
        what: &'static str,
        /// Index of the offending entry.
        index: usize,
    },
    /// Lemke's method stopped on a secondary ray: the entering column had no positive entry
    /// while the artificial variable z0 was still positive [CPS92, §4.4]. For copositive-plus M
    /// this proves the LCP infeasible [CPS92, §4.4]; for other M a solution may still
    /// exist.
    #[error(
        "Lemke's method ended on a secondary ray after {pivots} pivots (the entering column has \
         no positive entry); no solution was found (for copositive-plus M none exists)"
    )]
    RayTermination {
        /// Pivots made before the failed ratio test.
        pivots: usize,
    },
    /// The pivot limit was reached before z0 left the basis.
    #[error("Lemke's method reached the limit of {limit} pivots without finding a solution")]
    PivotLimit {
        /// The limit that was reached.
        limit: usize,
    },
    /// A parameter of [`LemkeParams`] is out of range.
    #[error("invalid Lemke parameter: {what} = {value} (must be finite and in [0, 1))")]
    InvalidParameter {
        /// The parameter's name.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// Lemke's method terminated, but the verified residuals of the result exceed the
    /// acceptance threshold (round-off destroyed the solution, typically because the final
    /// basis is nearly singular).
    #[error(
        "Lemke's method finished after {pivots} pivots but the result fails verification: \
         scaled min z = {min_z:.3e}, min w = {min_w:.3e}, complementarity = \
         {max_complementarity:.3e} (threshold {threshold:.1e})"
    )]
    InaccurateSolution {
        /// Pivots made.
        pivots: usize,
        /// Scaled min z (see [`LcpResiduals`]).
        min_z: f64,
        /// Scaled min w.
        min_w: f64,
        /// Scaled complementarity residual.
        max_complementarity: f64,
        /// The acceptance threshold that was exceeded.
        threshold: f64,
    },
    /// Neither Lemke on the step LCP nor the fixed point with the active-set step produced an
    /// answer of one frictional step meeting the residual tolerance (docs/method.md §8).
    #[error(
        "the frictional contact step did not converge: Lemke on the step LCP failed ({lemke}); \
         the fixed point made {fixed_point_rounds} rounds (last relative change \
         {fixed_point_change:.3e}) and the active-set step {active_set_rounds}, ending at scaled \
         residual {residual:.3e} (tolerance 1e-9); the friction problem may have no solution or \
         several (try a smaller friction coefficient or smaller load steps)"
    )]
    FrictionNotConverged {
        /// Fixed-point rounds made.
        fixed_point_rounds: usize,
        /// Active-set rounds made.
        active_set_rounds: usize,
        /// The scaled residual of the last answer.
        residual: f64,
        /// The fixed point's last relative change of the forces.
        fixed_point_change: f64,
        /// Why Lemke's answer was not accepted.
        lemke: String,
    },
    /// The active-set solver failed ([`active_set`]).
    #[error(transparent)]
    ActiveSet(#[from] active_set::ActiveSetError),
    /// A rigid obstacle pressed by a force: its displacement was not found
    /// ([`load_driven`]).
    #[error(transparent)]
    LoadDriven(#[from] load_driven::LoadDrivenError),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn construction_checks_sizes_and_finiteness() {
        assert!(matches!(
            Lcp::new(2, vec![1.0; 3], vec![0.0; 2]),
            Err(LcpError::DimensionMismatch { expected: 4, found: 3, .. })
        ));
        assert!(matches!(
            Lcp::new(2, vec![1.0; 4], vec![0.0; 3]),
            Err(LcpError::DimensionMismatch { what: "q", expected: 2, found: 3 })
        ));
        assert!(matches!(
            Lcp::new(2, vec![1.0, f64::NAN, 0.0, 1.0], vec![0.0; 2]),
            Err(LcpError::NonFinite { what: "M", index: 1 })
        ));
        assert!(matches!(
            Lcp::new(1, vec![1.0], vec![f64::INFINITY]),
            Err(LcpError::NonFinite { what: "q", index: 0 })
        ));
        assert!(matches!(
            Lcp::from_rows(&[vec![1.0, 2.0], vec![3.0]], vec![0.0; 2]),
            Err(LcpError::DimensionMismatch { what: "row of M", expected: 2, found: 1 })
        ));
    }

    #[test]
    fn accessors_and_residuals() {
        let lcp = Lcp::from_rows(&[vec![2.0, 1.0], vec![1.0, 2.0]], vec![-5.0, -6.0]).unwrap();
        assert_eq!(lcp.size(), 2);
        assert_eq!(lcp.m(0, 1), 1.0);
        assert_eq!(lcp.m(1, 0), 1.0);
        assert_eq!(lcp.q(), &[-5.0, -6.0]);
        let r = lcp.residuals(&[4.0 / 3.0, 7.0 / 3.0]);
        assert!(r.max_violation() < 1e-15, "{r:?}");
        assert_eq!(r.scale, 6.0);
        // z = 0 violates w ≥ 0 by 6, scaled by s = 6.
        let r = lcp.residuals(&[0.0, 0.0]);
        assert_eq!(r.min_w, -1.0);
        let r = lcp.residuals_with_w(&[0.0, 0.0], &[-5.0, -5.0]);
        assert_eq!(r.equation_residual, 1.0 / 6.0);
    }

    #[test]
    fn error_messages_are_readable() {
        let e = LcpError::RayTermination { pivots: 3 };
        assert!(e.to_string().contains("after 3 pivots"));
        let e = LcpError::PivotLimit { limit: 10 };
        assert!(e.to_string().contains("10 pivots"));
    }
}
