//! A matrix given as a base matrix with some of its rows replaced
//! ([`ReplacedRows`]): the row-replaced `K` of the active-set method (docs/method.md §5.1),
//! factorised without a copy of `K` held next to its factors
//! ([`Factorisation::with_replaced_rows`](super::Factorisation::with_replaced_rows)).
//!
//! The static-pivoting LU refines every solve against the matrix it factorised, which it
//! otherwise keeps by rows (a copy of `K`: 1.6 GB at 10⁶ nodes). With replaced rows it keeps
//! only the new rows and refines against the caller's `K` (its columns) and them. The
//! products below take the same operations in the same order as the row-wise ones of a
//! copy (each row's terms in ascending columns, starting from the same value), so the
//! refined solutions are bit-identical.

use crate::assembly::SystemMatrix;

/// The rows replacing some rows of an `n × n` base matrix: `(row, entries)` with entries
/// `(column, value)` in ascending columns (repeated columns summed in their given order),
/// at most one per row.
#[derive(Clone, Debug)]
pub struct ReplacedRows {
    n: usize,
    rows: Vec<(usize, Vec<(usize, f64)>)>,
    replaced: Vec<bool>,
}

impl ReplacedRows {
    /// Rows `(row, entries)` replacing those of an `n × n` matrix; entries need not be
    /// sorted (a stable sort by column, repeated columns summed in order); no row may be
    /// given twice.
    pub fn new(n: usize, rows: impl IntoIterator<Item = (usize, Vec<(usize, f64)>)>) -> Self {
        let mut replaced = vec![false; n];
        let mut by_row: Vec<(usize, Vec<(usize, f64)>)> = Vec::new();
        for (r, mut entries) in rows {
            entries.sort_by_key(|e| e.0);
            let mut merged: Vec<(usize, f64)> = Vec::with_capacity(entries.len());
            for (c, v) in entries {
                match merged.last_mut() {
                    Some(last) if last.0 == c => last.1 += v,
                    _ => merged.push((c, v)),
                }
            }
            replaced[r] = true;
            by_row.push((r, merged));
        }
        by_row.sort_by_key(|e| e.0);
        debug_assert!(by_row.windows(2).all(|w| w[0].0 < w[1].0), "a row replaced twice");
        let rows = by_row;
        Self { n, rows, replaced }
    }

    /// Order of the matrix.
    pub fn size(&self) -> usize {
        self.n
    }

    /// Number of replaced rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether no row is replaced.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The matrix: `base` with these rows replaced, compressed by columns.
    pub fn matrix(&self, base: &SystemMatrix) -> SystemMatrix {
        let n = base.n;
        debug_assert_eq!(n, self.n);
        let mut extra: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for (d, row) in &self.rows {
            for &(col, v) in row {
                extra[col].push((*d, v));
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(base.row_idx.len());
        let mut values = Vec::with_capacity(base.values.len());
        col_ptr.push(0);
        let mut column: Vec<(usize, f64)> = Vec::new();
        for col in 0..n {
            column.clear();
            for k in base.col_ptr[col]..base.col_ptr[col + 1] {
                if !self.replaced[base.row_idx[k]] {
                    column.push((base.row_idx[k], base.values[k]));
                }
            }
            column.extend_from_slice(&extra[col]);
            column.sort_by_key(|e| e.0);
            for &(r, v) in &column {
                if row_idx.last() == Some(&r) && row_idx.len() > col_ptr[col] {
                    *values.last_mut().expect("an entry was pushed") += v;
                } else {
                    row_idx.push(r);
                    values.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        SystemMatrix { n, col_ptr, row_idx, values }
    }

    /// `‖A‖∞` of the replaced matrix `A` (largest absolute row sum, each row summed in
    /// ascending columns).
    pub(super) fn norm(&self, base: &SystemMatrix) -> f64 {
        let mut sums = vec![0.0f64; self.n];
        self.scatter(base, |r, _, v| sums[r] += v.abs());
        for (d, row) in &self.rows {
            sums[*d] = row.iter().fold(0.0, |s, &(_, v)| s + v.abs());
        }
        sums.into_iter().fold(0.0f64, f64::max)
    }

    /// Calls `f(row, column, value)` for every entry of `base` outside the replaced rows,
    /// columns ascending (so each row's entries come in ascending columns).
    fn scatter(&self, base: &SystemMatrix, mut f: impl FnMut(usize, usize, f64)) {
        for c in 0..base.n {
            for k in base.col_ptr[c]..base.col_ptr[c + 1] {
                let r = base.row_idx[k];
                if !self.replaced[r] {
                    f(r, c, base.values[k]);
                }
            }
        }
    }

    /// `res ← res − A x` for `ka` columns stored row-major (`x[c * ka + j]`,
    /// `res[r * ka + j]`): each entry of `res` less its row's terms in ascending columns.
    pub(super) fn subtract_product(
        &self,
        base: &SystemMatrix,
        x: &[f64],
        res: &mut [f64],
        ka: usize,
    ) {
        if ka == 1 {
            self.scatter(base, |r, c, v| res[r] -= v * x[c]);
            for (d, row) in &self.rows {
                let mut s = res[*d];
                for &(c, v) in row {
                    s -= v * x[c];
                }
                res[*d] = s;
            }
            return;
        }
        self.scatter(base, |r, c, v| {
            for (s, &xc) in res[r * ka..(r + 1) * ka].iter_mut().zip(&x[c * ka..(c + 1) * ka]) {
                *s -= v * xc;
            }
        });
        for (d, row) in &self.rows {
            let out = &mut res[d * ka..(d + 1) * ka];
            for &(c, v) in row {
                for (s, &xc) in out.iter_mut().zip(&x[c * ka..(c + 1) * ka]) {
                    *s -= v * xc;
                }
            }
        }
    }

    /// `y = A x` (each row summed in ascending columns from zero).
    pub(super) fn product(&self, base: &SystemMatrix, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        self.scatter(base, |r, c, v| y[r] += v * x[c]);
        for (d, row) in &self.rows {
            let mut s = 0.0;
            for &(c, v) in row {
                s += v * x[c];
            }
            y[*d] = s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5 × 5 matrix with a few off-diagonal entries.
    fn base() -> SystemMatrix {
        let dense = [
            [4.0, 1.0, 0.0, 0.0, 0.5],
            [1.0, 5.0, 2.0, 0.0, 0.0],
            [0.0, 2.0, 6.0, 1.0, 0.0],
            [0.0, 0.0, 1.0, 7.0, 3.0],
            [0.5, 0.0, 0.0, 3.0, 8.0],
        ];
        let mut m = SystemMatrix { n: 5, col_ptr: vec![0], row_idx: vec![], values: vec![] };
        for c in 0..5 {
            for (r, row) in dense.iter().enumerate() {
                if row[c] != 0.0 {
                    m.row_idx.push(r);
                    m.values.push(row[c]);
                }
            }
            m.col_ptr.push(m.row_idx.len());
        }
        m
    }

    #[test]
    fn products_equal_those_of_the_assembled_matrix_bit_for_bit() {
        let base = base();
        let rows = ReplacedRows::new(
            5,
            [(3, vec![(4, 0.3), (0, 1.7), (4, 0.1)]), (1, vec![(2, -2.5), (1, 0.25)])],
        );
        let a = rows.matrix(&base);
        // Row-wise, from the assembled matrix.
        let mut by_row = vec![Vec::new(); 5];
        for c in 0..5 {
            for k in a.col_ptr[c]..a.col_ptr[c + 1] {
                by_row[a.row_idx[k]].push((c, a.values[k]));
            }
        }
        assert_eq!(by_row[3], vec![(0, 1.7), (4, 0.3 + 0.1)]);
        let x = [0.3, -1.1, 2.7, 0.9, -0.4, 1.3, 0.2, -0.8, 0.6, 1.9];
        for ka in [1, 2] {
            let b: Vec<f64> = (0..5 * ka).map(|i| 1.0 + 0.37 * i as f64).collect();
            let mut res = b.clone();
            rows.subtract_product(&base, &x[..5 * ka], &mut res, ka);
            for (r, row) in by_row.iter().enumerate() {
                for j in 0..ka {
                    let mut s = b[r * ka + j];
                    for &(c, v) in row {
                        s -= v * x[c * ka + j];
                    }
                    assert_eq!(s.to_bits(), res[r * ka + j].to_bits());
                }
            }
        }
        let mut y = vec![0.0; 5];
        rows.product(&base, &x[..5], &mut y);
        let norm = by_row
            .iter()
            .map(|row| row.iter().map(|e| e.1.abs()).sum::<f64>())
            .fold(0.0f64, f64::max);
        assert_eq!(norm.to_bits(), rows.norm(&base).to_bits());
        for (r, row) in by_row.iter().enumerate() {
            let mut s = 0.0;
            for &(c, v) in row {
                s += v * x[c];
            }
            assert_eq!(s.to_bits(), y[r].to_bits());
        }
    }
}
