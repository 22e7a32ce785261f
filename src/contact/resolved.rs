//! The contact compliance on the force patterns an elastic target resolves (docs/method.md
//! §4.3, "A target coarser than the candidates").
//!
//! A candidate's force reaches the target body through its overlap shares `S` (row `c`: the
//! target nodes whose cells receive it, weights summing to 1), while its gap reads the target
//! at the candidate's closest point. The two are not adjoint, and when the candidates are finer
//! than a softer target the symmetric part of `M` can be indefinite in force patterns that
//! vary *within* one target cell. Those patterns are invisible to the target's equilibrium
//! (`Sᵀ z = 0`). The check here restricts `(M + Mᵀ)/2` to the patterns the target does see,
//! `z = S y` (forces interpolated from target-node values with the same shares), and asks
//! whether it is positive definite there: `Qᵀ (M + Mᵀ)/2 Q`, `Q` an orthonormal basis of the
//! shares' column space.

use super::BodyOperator;
use super::spectrum::symmetric_eigenvalues;
use crate::linear_solve::SolveError;
use faer::Mat;

/// One contact pair's candidates in the global numbering of `M` and its elastic target
/// (`None`: rigid obstacles, whose every force pattern counts as resolved).
pub type PairTarget<'a> = (std::ops::Range<usize>, Option<&'a BodyOperator>);

/// The extreme eigenvalues `(λ_min, λ_max)` of `(M + Mᵀ)/2` (row-major `m × m`) restricted
/// to the force patterns the pairs' targets resolve (module documentation): for a pair with
/// an elastic target `z = S y` over its candidates, its target's shares `S` (one column per
/// target node, per pair); for a pair against rigid obstacles every pattern of its candidates.
///
/// # Errors
/// A failed eigenvalue decomposition.
pub fn target_resolved_extremes(
    compliance: &[f64],
    pairs: &[PairTarget<'_>],
) -> Result<(f64, f64), SolveError> {
    let m = pairs.iter().map(|(r, _)| r.end).max().unwrap_or(0);
    let mut columns: Vec<Vec<(usize, f64)>> = Vec::new();
    for (range, target) in pairs {
        match target {
            Some(op) => {
                let mut nodes: Vec<u32> = op.owners.iter().flatten().map(|&(n, _)| n).collect();
                nodes.sort_unstable();
                nodes.dedup();
                let first = columns.len();
                columns.resize(first + nodes.len(), Vec::new());
                for (c, owners) in op.owners.iter().enumerate() {
                    for &(node, weight) in owners {
                        if let Ok(j) = nodes.binary_search(&node) {
                            columns[first + j].push((range.start + c, weight));
                        }
                    }
                }
            }
            None => columns.extend(range.clone().map(|c| vec![(c, 1.0)])),
        }
    }
    let mut shares = Mat::<f64>::zeros(m, columns.len());
    for (j, column) in columns.iter().enumerate() {
        for &(c, weight) in column {
            shares[(c, j)] += weight;
        }
    }
    let basis = orthonormal_columns(&shares);
    let symmetric =
        Mat::<f64>::from_fn(m, m, |i, j| 0.5 * (compliance[i * m + j] + compliance[j * m + i]));
    let restricted = basis.transpose() * &symmetric * &basis;
    let values = symmetric_eigenvalues(restricted.as_ref())?;
    match (values.first(), values.last()) {
        (Some(&min), Some(&max)) => Ok((min, max)),
        _ => Ok((0.0, 0.0)),
    }
}

/// An orthonormal basis of the column space of `a`, by modified Gram–Schmidt applied twice
/// per column (sequential, so the result does not depend on the thread count); a column
/// whose remainder is below `10⁻¹⁰` of its norm is dependent on the earlier ones and dropped
/// (target nodes outnumber the candidates where the target is the finer side).
fn orthonormal_columns(a: &Mat<f64>) -> Mat<f64> {
    let m = a.nrows();
    let mut kept: Vec<Vec<f64>> = Vec::new();
    for j in 0..a.ncols() {
        let mut v: Vec<f64> = (0..m).map(|i| a[(i, j)]).collect();
        let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            continue;
        }
        for _ in 0..2 {
            for q in &kept {
                let dot: f64 = q.iter().zip(&v).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(q).for_each(|(x, y)| *x -= dot * y);
            }
        }
        let rest = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if rest > 1e-10 * norm {
            v.iter_mut().for_each(|x| *x /= rest);
            kept.push(v);
        }
    }
    Mat::from_fn(m, kept.len(), |i, j| kept[j][i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mls::ShapeSet;

    fn operator(owners: Vec<Vec<(u32, f64)>>) -> BodyOperator {
        let m = owners.len();
        BodyOperator { shapes: ShapeSet::default(), owners, directions: vec![[0.0, 1.0]; m] }
    }

    /// Two candidates share one target node: the pattern `(1, −1)` is invisible to the target,
    /// so an indefinite `M` in that pattern only is positive definite on what the target sees.
    #[test]
    fn an_indefinite_pattern_within_one_target_cell_is_not_seen() {
        // (M + Mᵀ)/2 = [[1, 1.5], [1.5, 1]]: eigenvalues 2.5 (1, 1) and −0.5 (1, −1).
        let m = [1.0, 2.0, 1.0, 1.0];
        let shared = operator(vec![vec![(7, 1.0)], vec![(7, 1.0)]]);
        let (min, max) = target_resolved_extremes(&m, &[(0..2, Some(&shared))]).unwrap();
        assert!((min - 2.5).abs() < 1e-14 && (max - 2.5).abs() < 1e-14, "{min} {max}");
        // Each candidate on its own target node: the restriction is the whole matrix.
        let own = operator(vec![vec![(3, 1.0)], vec![(4, 1.0)]]);
        let (min, max) = target_resolved_extremes(&m, &[(0..2, Some(&own))]).unwrap();
        assert!((min + 0.5).abs() < 1e-14 && (max - 2.5).abs() < 1e-14, "{min} {max}");
        // Rigid obstacles: every pattern is resolved.
        let (min, _) = target_resolved_extremes(&m, &[(0..2, None)]).unwrap();
        assert!((min + 0.5).abs() < 1e-14, "{min}");
        // Two pairs, one candidate each, both on one target node: still separate patterns.
        let one = operator(vec![vec![(7, 1.0)]]);
        let (min, _) =
            target_resolved_extremes(&m, &[(0..1, Some(&one)), (1..2, Some(&one))]).unwrap();
        assert!((min + 0.5).abs() < 1e-14, "{min}");
    }
}
