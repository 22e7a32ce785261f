//! Stage 6: sparse LU factorisation of `K` (faer), kept for many solves.
//!
//! The factorisation runs sequentially on purpose: faer's parallel kernels may sum in a
//! thread-dependent order, and outputs must be bit-identical whatever the thread count.

use crate::assembly::SystemMatrix;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::lu::{
    LuRef, LuSymbolicParams, NumericLu, SymbolicLu, factorize_symbolic_lu,
};
use faer::sparse::{SparseColMatRef, linalg::LuError};
use faer::{Conj, MatMut, Par};

/// Failures of the linear solve.
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    /// The matrix is structurally or numerically singular.
    #[error(
        "the system matrix is singular ({detail}); is the body held by enough displacement conditions?"
    )]
    Singular {
        /// What was detected.
        detail: String,
    },
    /// faer failed for another reason (e.g. memory).
    #[error("sparse LU failed: {0}")]
    Backend(String),
}

/// A sparse LU factorisation `P K Q = L U` of the system matrix.
pub struct Factorisation {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    n: usize,
}

impl std::fmt::Debug for Factorisation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Factorisation {{ n: {} }}", self.n)
    }
}

impl Factorisation {
    /// Factorises `matrix` (symbolic analysis with COLAMD, then numeric LU with partial pivoting).
    ///
    /// # Errors
    /// [`SolveError::Singular`] for a structurally singular matrix, [`SolveError::Backend`]
    /// otherwise. Numerical singularity shows up in [`Self::solve`].
    pub fn new(matrix: &SystemMatrix) -> Result<Self, SolveError> {
        let n = matrix.n;
        let symbolic_ref =
            SymbolicSparseColMatRef::new_checked(n, n, &matrix.col_ptr, None, &matrix.row_idx);
        let mat = SparseColMatRef::new(symbolic_ref, &matrix.values);
        let symbolic = factorize_symbolic_lu(symbolic_ref, LuSymbolicParams::default())
            .map_err(|e| SolveError::Backend(format!("{e:?}")))?;
        let mut numeric = NumericLu::new();
        let par = Par::Seq;
        let req = symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default());
        let mut buf = MemBuffer::try_new(req).map_err(|e| SolveError::Backend(format!("{e:?}")))?;
        symbolic
            .factorize_numeric_lu(
                &mut numeric,
                mat,
                par,
                MemStack::new(&mut buf),
                Default::default(),
            )
            .map_err(|e| match e {
                LuError::SymbolicSingular { index } => {
                    SolveError::Singular { detail: format!("no pivot at step {index} of {n}") }
                }
                LuError::Generic(g) => SolveError::Backend(format!("{g:?}")),
            })?;
        Ok(Self { symbolic, numeric, n })
    }

    /// Order of the matrix.
    pub fn size(&self) -> usize {
        self.n
    }

    /// Solves `K X = B` in place for the columns of `rhs` (`n × k`).
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        let par = Par::Seq;
        let req = self.symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), par);
        let mut buf = MemBuffer::new(req);
        LuRef::new_unchecked(&self.symbolic, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            rhs,
            par,
            MemStack::new(&mut buf),
        );
    }

    /// Solves `K x = b`.
    ///
    /// # Errors
    /// [`SolveError::Singular`] when the result is not finite (numerically singular `K`).
    pub fn solve(&self, b: &[f64]) -> Result<Vec<f64>, SolveError> {
        let mut x = b.to_vec();
        self.solve_in_place(MatMut::from_column_major_slice_mut(&mut x, self.n, 1));
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::Singular { detail: format!("non-finite solution at DOF {i}") });
        }
        Ok(x)
    }
}

/// `y = A x` for a compressed-column matrix.
pub fn mul(matrix: &SystemMatrix, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; matrix.n];
    for (c, &xc) in x.iter().enumerate() {
        for k in matrix.col_ptr[c]..matrix.col_ptr[c + 1] {
            y[matrix.row_idx[k]] += matrix.values[k] * xc;
        }
    }
    y
}
