//! The condensation onto the contact unknowns — the paper's Schur complement in the form that
//! is exact for MLS (docs/method.md §4.2).
//!
//! Eliminating `û` from `K û = f + E P` and `g = g0 + G û` gives the LCP
//! <div>$$ g = q + M P \ge 0,\quad P \ge 0,\quad g^\top P = 0,\qquad
//! M = G K^{-1} E,\quad q = g_0 + G K^{-1} f. $$</div>
//! For two bodies `M = M_1 + M_2` and `q = g0 + G_1 K_1⁻¹ f_1 + G_2 K_2⁻¹ f_2` (springs in
//! series, docs/method.md §4.3).
//! `M` is the Schur complement of `K` in the bordered matrix `[[K, −E], [G, 0]]` (compliance
//! form). The paper's stiffness form (eqs. 22–27) coincides with it only when nodal values
//! interpolate, which MLS values do not.

use super::spectrum::{EigenvalueMethod, symmetric_extremes};
use super::{BodyOperator, ContactError};
use crate::linear_solve::{ColumnOrdering, FactorMethod, FactorOptions, Factorisation, SolveError};
use crate::model::Model;
use crate::nodes::{Axis, dof};
use faer::Mat;
use rayon::prelude::*;

/// Right-hand sides per blocked solve. Fixed (not derived from the thread count) so results
/// are bit-identical whatever the number of threads (a column's arithmetic does not depend on
/// its block: `M` was bit-identical for 32, 64, 128 and 256). On the 2 000-candidate strip
/// (`examples/studies/contact_timing.rs`) 64 and 128 ran in 13–25 s against 25–33 s for 32 (noisy,
/// shared machine); 64 keeps a block's `n × 64` right-hand sides small for large bodies.
const BLOCK: usize = 64;

/// One body's share of the condensed problem.
#[derive(Clone, Debug)]
pub struct CondensedPart {
    /// `M_k = G_k K_k⁻¹ E_k`, row-major `m × m`.
    pub compliance: Vec<f64>,
    /// `G_k K_k⁻¹ f_k`: this body's gap contribution without contact forces.
    pub free_gap: Vec<f64>,
}

/// The condensed contact problem `g = q + M P` with its run-time checks.
#[derive(Clone, Debug)]
pub struct CondensedContact {
    /// `M = Σ_k G_k K_k⁻¹ E_k`, row-major `m × m` (compliance: gap change per unit force).
    pub compliance: Vec<f64>,
    /// `q = g0 + Σ_k G_k K_k⁻¹ f_k`: the gaps without contact forces.
    pub free_gap: Vec<f64>,
    /// Smallest diagonal entry of `M`.
    pub min_diagonal: f64,
    /// Smallest eigenvalue of `(M + Mᵀ)/2`: a Lanczos estimate with the Cholesky factor when
    /// the symmetric part is positive definite (relative accuracy 10⁻¹⁰ plus rounding of order
    /// `m ε λ_max`, see [`super::spectrum`]), else the exact value from all eigenvalues.
    pub min_symmetric_eigenvalue: f64,
    /// Largest eigenvalue of `(M + Mᵀ)/2` (Lanczos estimate or exact, as the smallest).
    pub max_symmetric_eigenvalue: f64,
    /// How the two eigenvalues were computed.
    pub eigenvalue_method: EigenvalueMethod,
    /// `‖M − Mᵀ‖_F / ‖M + Mᵀ‖_F`.
    pub skew_ratio: f64,
}

/// One body's `M_k` and `G_k K_k⁻¹ f_k` with one factorisation: by reach-restricted solves
/// in the factorisation's own supernodal factors when they apply and pay
/// ([`sparse_compliance`]: the static-pivoting LU with a nested-dissection order), otherwise
/// `K⁻¹E` in blocks of `BLOCK` right-hand sides (in parallel over blocks), each block reduced
/// to its `G` rows at once.
///
/// # Errors
/// [`ContactError::Solve`] when a solve is not finite.
pub fn condense(
    factorisation: &Factorisation,
    rhs: &[f64],
    operator: &BodyOperator,
) -> Result<CondensedPart, ContactError> {
    condense_with(factorisation, rhs, operator, BLOCK, true, &mut |_, _| {})
}

/// From this many candidates, [`condense_model_observed`] factorises a body's `K` a second
/// time (static pivoting, nested dissection) when its own factorisation is faer's, to
/// condense by reach-restricted solves: on the 2 000-candidate strip (84k unknowns) the
/// second factorisation and the sparse condensation took 2.8 s + 0.5 s against 16.8 s for
/// the blocked solves in the same minutes (docs/dev/performance.md, "Sparse condensation
/// for the Lemke path").
/// Below it the blocked solves are kept (and every shipped problem's outputs with them).
pub const SPARSE_CONDENSATION_MIN_CANDIDATES: usize = 1000;

/// From this many candidates on a *graded* node set (refinement regions, e.g. every step of
/// the adaptive loop after the first), the pipeline factorises the body's `K` by the
/// static-pivoting LU with nested dissection and condenses by reach-restricted solves
/// ([`sparse_compliance`]) instead of [`SPARSE_CONDENSATION_MIN_CANDIDATES`]: on the adaptive
/// beam (12 567 nodes, 297 candidates at the last step) the condensation took 0.8 s against
/// 2.0 s by the blocked solves, the factorisation the same, in the same minutes
/// (docs/dev/time_to_accuracy.md). The uniform sets keep the blocked solves below 1 000
/// candidates (and their outputs with them).
pub const GRADED_SPARSE_CONDENSATION_MIN_CANDIDATES: usize = 100;

/// One body's condensation for the Lemke path: [`condense_observed`] with the model's
/// factorisation, except from [`SPARSE_CONDENSATION_MIN_CANDIDATES`] candidates on a model
/// factorised by faer's LU, where `M` comes from reach-restricted solves
/// ([`sparse_compliance`]) in a second factorisation with static pivoting and nested
/// dissection; `G K⁻¹ f` always comes from the model's own factorisation (the one the final
/// displacements are solved with). Falls back to [`condense_observed`] when the second
/// factorisation refuses the sparse route (perturbed pivots). The pipeline's `discretise`
/// builds that static LU as the model's own factorisation when it foresees the Lemke path
/// with this many candidates on a body; then the sparse route runs in it, with no second
/// factorisation.
///
/// # Errors
/// [`ContactError::Solve`] when a solve or the second factorisation fails.
pub fn condense_model_observed(
    model: &Model,
    operator: &BodyOperator,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<CondensedPart, ContactError> {
    let (factorisation, rhs) = (&model.factorisation, &model.system.rhs);
    let matrix = &model.system.matrix;
    let points = &model.nodes.points;
    let m = operator.len();
    if m >= SPARSE_CONDENSATION_MIN_CANDIDATES
        && factorisation.stats().method != FactorMethod::StaticPivoting
        && 2 * points.len() == matrix.n
    {
        let second = Factorisation::with_options(
            matrix,
            ColumnOrdering::NestedDissection(points),
            &FactorOptions::nested_dissection_static(),
        )?;
        if let Some(compliance) = sparse_compliance(&second, operator)? {
            drop(second);
            let free_gap = operator.gap_contribution(&factorisation.solve(rhs)?);
            progress(m, m);
            return Ok(CondensedPart { compliance, free_gap });
        }
    }
    condense_observed(factorisation, rhs, operator, progress)
}

/// [`condense`] by blocked full solves with `block` right-hand sides each, never by
/// [`sparse_compliance`] (for tuning and comparisons; results may differ from [`condense`]'s
/// in the last bits, but never with the thread count).
///
/// # Errors
/// [`ContactError::Solve`] when a solve is not finite.
pub fn condense_blocked(
    factorisation: &Factorisation,
    rhs: &[f64],
    operator: &BodyOperator,
    block: usize,
) -> Result<CondensedPart, ContactError> {
    condense_with(factorisation, rhs, operator, block, false, &mut |_, _| {})
}

/// [`condense`], reporting `(columns done, columns)` to `progress` as the column blocks
/// finish (a few blocks per thread at a time; the result is the same bits).
///
/// # Errors
/// [`ContactError::Solve`] when a solve is not finite.
pub fn condense_observed(
    factorisation: &Factorisation,
    rhs: &[f64],
    operator: &BodyOperator,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<CondensedPart, ContactError> {
    condense_with(factorisation, rhs, operator, BLOCK, true, progress)
}

fn condense_with(
    factorisation: &Factorisation,
    rhs: &[f64],
    operator: &BodyOperator,
    block: usize,
    sparse: bool,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<CondensedPart, ContactError> {
    let m = operator.len();
    let n = factorisation.size();
    let block = block.max(1);
    let free_solution = factorisation.solve(rhs)?;
    let free_gap = operator.gap_contribution(&free_solution);
    if sparse && let Some(compliance) = sparse_compliance(factorisation, operator)? {
        progress(m, m);
        return Ok(CondensedPart { compliance, free_gap });
    }
    let starts: Vec<usize> = (0..m).step_by(block).collect();
    // Column blocks of M (column c = G K⁻¹ E e_c), each `m × width` column-major.
    let column_block = |&start: &usize| {
        let width = block.min(m - start);
        let mut x = Mat::<f64>::zeros(n, width);
        for j in 0..width {
            // E e_c: the force d_c on the owners' rows (as `BodyOperator::add_forces`).
            let d = operator.direction(start + j);
            for &(i, w) in &operator.owners[start + j] {
                x[(dof(i as usize, Axis::X), j)] += d[0] * w;
                x[(dof(i as usize, Axis::Y), j)] += d[1] * w;
            }
        }
        factorisation.solve_in_place(x.as_mut());
        let mut out = Vec::with_capacity(m * width);
        for j in 0..width {
            out.extend(operator.gap_contribution(x.col_as_slice(j)));
        }
        out
    };
    // Blocks are independent: computing them a few per thread at a time, to report progress
    // in between, gives the same bits as computing them all at once.
    let chunk = 4 * rayon::current_num_threads().max(1);
    let mut blocks: Vec<Vec<f64>> = Vec::with_capacity(starts.len());
    for group in starts.chunks(chunk) {
        blocks.extend(group.par_iter().map(column_block).collect::<Vec<_>>());
        progress(blocks.len().saturating_mul(block).min(m), m);
    }
    let mut compliance = vec![0.0; m * m];
    for (b, &start) in starts.iter().enumerate() {
        for (j, col) in blocks[b].chunks_exact(m).enumerate() {
            for (i, &v) in col.iter().enumerate() {
                compliance[i * m + start + j] = v;
            }
        }
    }
    if let Some(i) = compliance.iter().position(|v| !v.is_finite()) {
        return Err(
            SolveError::Singular { detail: format!("non-finite compliance entry {i}") }.into()
        );
    }
    Ok(CondensedPart { compliance, free_gap })
}

/// The columns of `E` (`E e_c`: the force `d_c` on the owners' rows, as
/// [`BodyOperator::add_forces`]) and the rows of `G` (`G_c û = d_c·u^h(x_c)`, as
/// [`BodyOperator::gap_contribution`]) as `(DOF, value)` lists.
#[allow(clippy::type_complexity)]
fn sparse_operator(operator: &BodyOperator) -> (Vec<Vec<(usize, f64)>>, Vec<Vec<(usize, f64)>>) {
    let m = operator.len();
    let columns = (0..m)
        .map(|c| {
            let d = operator.direction(c);
            operator.owners[c]
                .iter()
                .flat_map(|&(i, w)| {
                    [(dof(i as usize, Axis::X), d[0] * w), (dof(i as usize, Axis::Y), d[1] * w)]
                })
                .collect()
        })
        .collect();
    let rows = (0..m)
        .map(|c| {
            let d = operator.direction(c);
            let shapes = &operator.shapes;
            shapes
                .support(c)
                .iter()
                .zip(shapes.phi(c))
                .flat_map(|(&j, &p)| {
                    [(dof(j as usize, Axis::X), d[0] * p), (dof(j as usize, Axis::Y), d[1] * p)]
                })
                .collect()
        })
        .collect();
    (columns, rows)
}

/// `M = G K⁻¹ E` by reach-restricted solves in the factorisation's own supernodal factors
/// ([`Factorisation::sparse_products`]), or `None` when that route does not apply (faer's
/// LU, perturbed pivots) or is estimated to cost more than the blocked full solves of
/// [`condense`] (a banded order).
///
/// # Errors
/// [`ContactError::Solve`] when an entry is not finite.
pub fn sparse_compliance(
    factorisation: &Factorisation,
    operator: &BodyOperator,
) -> Result<Option<Vec<f64>>, ContactError> {
    let (columns, rows) = sparse_operator(operator);
    let Some(products) = factorisation.sparse_products(&columns, &rows) else { return Ok(None) };
    if let Some(i) = products.values.iter().position(|v| !v.is_finite()) {
        return Err(
            SolveError::Singular { detail: format!("non-finite compliance entry {i}") }.into()
        );
    }
    Ok(Some(products.values))
}

impl CondensedContact {
    /// `M = Σ M_k`, `q = g0 + Σ G_k K_k⁻¹ f_k`, and the checks of `M`.
    ///
    /// The symmetric part's positive definiteness is decided by a dense Cholesky factorisation
    /// and its extreme eigenvalues estimated by Lanczos ([`super::spectrum`]); all eigenvalues
    /// are computed only when it is not positive definite or nearly singular.
    ///
    /// # Errors
    /// [`ContactError::Solve`] when a dense eigenvalue problem fails.
    pub fn combine(initial_gap: &[f64], parts: &[CondensedPart]) -> Result<Self, ContactError> {
        let m = initial_gap.len();
        let mut compliance = vec![0.0; m * m];
        let mut free_gap = initial_gap.to_vec();
        for part in parts {
            for (a, b) in compliance.iter_mut().zip(&part.compliance) {
                *a += b;
            }
            for (a, b) in free_gap.iter_mut().zip(&part.free_gap) {
                *a += b;
            }
        }
        let min_diagonal = (0..m).map(|i| compliance[i * m + i]).fold(f64::INFINITY, f64::min);
        // (M + Mᵀ)/2 and the norms of M ± Mᵀ in one pass over square tiles (cache-friendly
        // for both M and Mᵀ).
        let mut sym = Mat::<f64>::zeros(m, m);
        let (mut skew, mut symm) = (0.0, 0.0);
        const TILE: usize = 64;
        for j0 in (0..m).step_by(TILE) {
            for i0 in (0..m).step_by(TILE) {
                for j in j0..(j0 + TILE).min(m) {
                    for i in i0..(i0 + TILE).min(m) {
                        let (a, b) = (compliance[i * m + j], compliance[j * m + i]);
                        sym[(i, j)] = 0.5 * (a + b);
                        skew += (a - b) * (a - b);
                        symm += (a + b) * (a + b);
                    }
                }
            }
        }
        let extremes = symmetric_extremes(sym.as_ref())?;
        Ok(Self {
            compliance,
            free_gap,
            min_diagonal,
            min_symmetric_eigenvalue: extremes.min,
            max_symmetric_eigenvalue: extremes.max,
            eigenvalue_method: extremes.method,
            skew_ratio: (skew / symm.max(f64::MIN_POSITIVE)).sqrt(),
        })
    }
}

/// The condensed blocks of frictional contact (docs/method.md §8): with the normal operator
/// (`G_n`, `E_n`, direction `ν`) and the tangential operator (`G_t`, `E_t`, direction `t`) of
/// the same candidates,
///
/// ```text
/// g = q_n + M_nn P + M_nt T,      s = q_t + M_tn P + M_tt T,
/// M_ab = Σ_k G_a,k K_k⁻¹ E_b,k,   q_n = g0 + Σ_k G_n,k K_k⁻¹ f_k,   q_t = Σ_k G_t,k K_k⁻¹ f_k.
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct CondensedBlocks {
    /// Candidates `m`.
    pub size: usize,
    /// `M_nn` (the frictionless `M`), row-major `m × m`.
    pub nn: Vec<f64>,
    /// `M_nt`: gap change per unit tangential force.
    pub nt: Vec<f64>,
    /// `M_tn`: tangential displacement per unit normal force.
    pub tn: Vec<f64>,
    /// `M_tt`: tangential compliance.
    pub tt: Vec<f64>,
    /// `q_n`: the gaps without contact forces.
    pub free_gap: Vec<f64>,
    /// `q_t`: the tangential displacements `t·u^h(x_c)` without contact forces.
    pub free_tangential: Vec<f64>,
}

impl CondensedBlocks {
    /// The blocks of one body ([`condense_blocks`]) with the initial gaps added to `q_n`.
    pub fn with_initial_gap(mut self, initial_gap: &[f64]) -> Self {
        for (q, g0) in self.free_gap.iter_mut().zip(initial_gap) {
            *q += g0;
        }
        self
    }
}

/// One body's four blocks `G_a K⁻¹ E_b` (`a, b ∈ {n, t}`) and `G_a K⁻¹ f` from one
/// factorisation: `K⁻¹ [E_n E_t]` in blocks of `BLOCK` right-hand sides (in parallel over
/// blocks), each solved column read by both `G_n` and `G_t`. `normal` and `tangential` must
/// have the same contact points (as [`super::Candidates::tangential_operator`] builds them).
/// `free_gap` holds `G_n K⁻¹ f` only (add `g0` with [`CondensedBlocks::with_initial_gap`]).
///
/// # Errors
/// [`ContactError::Solve`] when a solve is not finite.
pub fn condense_blocks(
    factorisation: &Factorisation,
    rhs: &[f64],
    normal: &BodyOperator,
    tangential: &BodyOperator,
) -> Result<CondensedBlocks, ContactError> {
    let m = normal.len();
    assert_eq!(tangential.len(), m, "normal and tangential operators of different sizes");
    let n = factorisation.size();
    let free_solution = factorisation.solve(rhs)?;
    let ops = [normal, tangential];
    // Column j < m: E_n e_j; column m + j: E_t e_j.
    let starts: Vec<usize> = (0..2 * m).step_by(BLOCK).collect();
    let blocks: Vec<[Vec<f64>; 2]> = starts
        .par_iter()
        .map(|&start| {
            let width = BLOCK.min(2 * m - start);
            let mut x = Mat::<f64>::zeros(n, width);
            for j in 0..width {
                let col = start + j;
                let op = ops[col / m];
                let d = op.direction(col % m);
                for &(i, w) in &op.owners[col % m] {
                    x[(dof(i as usize, Axis::X), j)] += d[0] * w;
                    x[(dof(i as usize, Axis::Y), j)] += d[1] * w;
                }
            }
            factorisation.solve_in_place(x.as_mut());
            let mut out = [Vec::with_capacity(m * width), Vec::with_capacity(m * width)];
            for j in 0..width {
                for (a, op) in ops.iter().enumerate() {
                    out[a].extend(op.gap_contribution(x.col_as_slice(j)));
                }
            }
            out
        })
        .collect();
    // full[a][b]: row-major m × m block G_a K⁻¹ E_b.
    let mut full = [[vec![0.0; m * m], vec![0.0; m * m]], [vec![0.0; m * m], vec![0.0; m * m]]];
    for (blk, &start) in blocks.iter().zip(&starts) {
        for (a, rows) in blk.iter().enumerate() {
            for (j, col) in rows.chunks_exact(m.max(1)).enumerate() {
                let (b, c) = ((start + j) / m, (start + j) % m);
                for (i, &v) in col.iter().enumerate() {
                    full[a][b][i * m + c] = v;
                }
            }
        }
    }
    let [[nn, nt], [tn, tt]] = full;
    for block in [&nn, &nt, &tn, &tt] {
        if let Some(i) = block.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::Singular {
                detail: format!("non-finite frictional compliance entry {i}"),
            }
            .into());
        }
    }
    Ok(CondensedBlocks {
        size: m,
        nn,
        nt,
        tn,
        tt,
        free_gap: normal.gap_contribution(&free_solution),
        free_tangential: tangential.gap_contribution(&free_solution),
    })
}
