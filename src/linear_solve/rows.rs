//! A matrix by rows for products `K x` on two tasks, bit-identical to [`super::mul`].

use crate::assembly::SystemMatrix;

/// Products with fewer stored entries than this run on one task.
const PARALLEL_ENTRIES: usize = 1 << 17;

/// `K` by rows (compressed sparse rows, columns ascending within a row). Each row's product
/// sums its terms in ascending columns from zero, as [`super::mul`] does column after column,
/// so the two give the same bits; the rows' halves go on two tasks.
pub struct RowProduct {
    row_ptr: Vec<usize>,
    col_idx: Vec<usize>,
    values: Vec<f64>,
}

impl RowProduct {
    /// `matrix` copied by rows.
    pub fn new(matrix: &SystemMatrix) -> Self {
        let (row_ptr, col_idx, values) =
            super::symmetric::transpose(matrix.n, &matrix.col_ptr, &matrix.row_idx, &matrix.values);
        Self { row_ptr, col_idx, values }
    }

    /// `K x`.
    pub fn mul(&self, x: &[f64]) -> Vec<f64> {
        let n = self.row_ptr.len() - 1;
        let mut y = vec![0.0; n];
        let rows = |out: &mut [f64], first: usize| {
            for (yr, r) in out.iter_mut().zip(first..) {
                let mut s = 0.0;
                for k in self.row_ptr[r]..self.row_ptr[r + 1] {
                    s += self.values[k] * x[self.col_idx[k]];
                }
                *yr = s;
            }
        };
        let half = n / 2;
        let (a, b) = y.split_at_mut(half);
        if self.values.len() > PARALLEL_ENTRIES {
            rayon::join(|| rows(a, 0), || rows(b, half));
        } else {
            rows(a, 0);
            rows(b, half);
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The product by rows gives the bits of the product by columns.
    #[test]
    fn rows_multiply_as_columns_bit_for_bit() {
        let n = 800;
        let mut m = SystemMatrix { n, col_ptr: vec![0], row_idx: Vec::new(), values: Vec::new() };
        for c in 0..n {
            for r in (0..n).filter(|r| (r * 7 + c * 3) % 11 < 3 || *r == c) {
                m.row_idx.push(r);
                m.values.push(((r * 13 + c * 5) % 19) as f64 / 7.0 - 1.3);
            }
            m.col_ptr.push(m.row_idx.len());
        }
        assert!(m.values.len() > PARALLEL_ENTRIES, "two tasks");
        let x: Vec<f64> = (0..n).map(|i| ((i * 29) % 31) as f64 / 3.0 - 5.0).collect();
        let (by_columns, by_rows) = (super::super::mul(&m, &x), RowProduct::new(&m).mul(&x));
        assert!(by_columns.iter().zip(&by_rows).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}
