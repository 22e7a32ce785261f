//! The condensation onto the contact unknowns — the paper's Schur complement in the form that
//! is exact for MLS (method.md §4.2).
//!
//! Eliminating `û` from `K û = f + E P` and `g = g0 + G û` gives the LCP
//! <div>$$ g = q + M P \ge 0,\quad P \ge 0,\quad g^\top P = 0,\qquad
//! M = G K^{-1} E,\quad q = g_0 + G K^{-1} f. $$</div>
//! `M` is the Schur complement of `K` in the bordered matrix `[[K, −E], [G, 0]]` (compliance
//! form). The paper's stiffness form (eqs. 22–27) coincides with it only when nodal values
//! interpolate, which MLS values do not.

use super::{Candidates, ContactError};
use crate::linear_solve::Factorisation;
use crate::mls::ShapeSet;
use faer::Mat;
use rayon::prelude::*;

/// Right-hand sides per blocked solve. Fixed (not derived from the thread count) so results
/// are bit-identical whatever the number of threads.
const BLOCK: usize = 32;

/// The condensed contact problem.
#[derive(Clone, Debug)]
pub struct CondensedContact {
    /// `M = G K⁻¹ E`, row-major `m × m` (compliance: gap change per unit force).
    pub compliance: Vec<f64>,
    /// `q = g0 + G K⁻¹ f`: the gaps without contact forces.
    pub free_gap: Vec<f64>,
    /// `K⁻¹ f`: the solution without contact forces.
    pub free_solution: Vec<f64>,
    /// Smallest diagonal entry of `M`.
    pub min_diagonal: f64,
    /// Smallest eigenvalue of `(M + Mᵀ)/2`.
    pub min_symmetric_eigenvalue: f64,
    /// Largest eigenvalue of `(M + Mᵀ)/2`.
    pub max_symmetric_eigenvalue: f64,
    /// `‖M − Mᵀ‖_F / ‖M + Mᵀ‖_F`.
    pub skew_ratio: f64,
}

/// Forms `M` and `q` with one factorisation: `K⁻¹E` in blocks of [`BLOCK`] right-hand sides
/// (in parallel over blocks), each block reduced to its `G` rows at once.
///
/// # Errors
/// [`ContactError::Solve`] when a solve is not finite.
pub fn condense(
    factorisation: &Factorisation,
    rhs: &[f64],
    candidates: &Candidates,
    node_shapes: &ShapeSet,
) -> Result<CondensedContact, ContactError> {
    let m = candidates.len();
    let n = factorisation.size();
    let free_solution = factorisation.solve(rhs)?;
    let g_free = candidates.normal_displacement(node_shapes, &free_solution);
    let free_gap: Vec<f64> =
        candidates.initial_gap.iter().zip(&g_free).map(|(a, b)| a + b).collect();
    let starts: Vec<usize> = (0..m).step_by(BLOCK).collect();
    // Column blocks of M (column c = G K⁻¹ e_c).
    let blocks: Vec<Vec<Vec<f64>>> = starts
        .par_iter()
        .map(|&start| {
            let width = BLOCK.min(m - start);
            let mut x = Mat::<f64>::zeros(n, width);
            for j in 0..width {
                let mut force = vec![0.0; m];
                force[start + j] = 1.0;
                let mut col = vec![0.0; n];
                candidates.add_forces(&force, &mut col);
                for (r, v) in col.into_iter().enumerate() {
                    if v != 0.0 {
                        x[(r, j)] = v;
                    }
                }
            }
            factorisation.solve_in_place(x.as_mut());
            (0..width)
                .map(|j| {
                    let col: Vec<f64> = (0..n).map(|r| x[(r, j)]).collect();
                    candidates.normal_displacement(node_shapes, &col)
                })
                .collect()
        })
        .collect();
    let mut compliance = vec![0.0; m * m];
    for (b, &start) in starts.iter().enumerate() {
        for (j, col) in blocks[b].iter().enumerate() {
            for (i, &v) in col.iter().enumerate() {
                compliance[i * m + start + j] = v;
            }
        }
    }
    if let Some(i) = compliance.iter().position(|v| !v.is_finite()) {
        return Err(crate::linear_solve::SolveError::Singular {
            detail: format!("non-finite compliance entry {i}"),
        }
        .into());
    }
    let min_diagonal = (0..m).map(|i| compliance[i * m + i]).fold(f64::INFINITY, f64::min);
    let sym =
        Mat::<f64>::from_fn(m, m, |i, j| 0.5 * (compliance[i * m + j] + compliance[j * m + i]));
    let eig = sym
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .map_err(|e| crate::linear_solve::SolveError::Backend(format!("{e:?}")))?;
    let min_symmetric_eigenvalue = eig.iter().copied().fold(f64::INFINITY, f64::min);
    let max_symmetric_eigenvalue = eig.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (mut skew, mut symm) = (0.0, 0.0);
    for i in 0..m {
        for j in 0..m {
            let (a, b) = (compliance[i * m + j], compliance[j * m + i]);
            skew += (a - b) * (a - b);
            symm += (a + b) * (a + b);
        }
    }
    Ok(CondensedContact {
        compliance,
        free_gap,
        free_solution,
        min_diagonal,
        min_symmetric_eigenvalue,
        max_symmetric_eigenvalue,
        skew_ratio: (skew / symm.max(f64::MIN_POSITIVE)).sqrt(),
    })
}
