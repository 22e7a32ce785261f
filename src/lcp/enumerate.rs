//! Brute-force enumeration of the complementary basic solutions of an LCP, a reference for
//! tests [CPS92, §1.1].

use super::Lcp;

/// Largest n accepted by [`enumerate_solutions`] (2²⁰ ≈ 10⁶ index sets).
const MAX_ENUMERATION_SIZE: usize = 20;

/// Scaled residual (see [`super::LcpResiduals`]) up to which a candidate counts as a solution.
const ENUMERATION_TOLERANCE: f64 = 1e-9;

/// All complementary basic solutions of LCP(q, M), found by brute force over the 2ⁿ
/// complementary index sets α ⊆ {1..n}. **The cost is exponential, O(2ⁿ n³)**: this is a
/// reference for tests with n ≲ 12, not a solver.
///
/// For each α with M_αα nonsingular the candidate z_α = −M_αα⁻¹ q_α, z_ᾱ = 0 (so w_α = 0) is
/// kept if it passes the residual test of [`Lcp::residuals`] at scaled tolerance 10⁻⁹; tiny
/// negative round-off in z is clipped to 0, and solutions that agree to 10⁻⁹·max(1, ‖z‖∞) are
/// reported once, in the order of the index sets (α as a bit mask, increasing). A principal
/// block counts as singular when Gaussian elimination with partial pivoting meets a pivot
/// below 10⁻¹² · max|M_αα|; solutions that need a singular block (for example the non-vertex
/// points of a continuum of solutions) are not listed. For a P-matrix the result is the unique
/// solution [CPS92, §3.3].
///
/// # Panics
/// If n > 20.
pub fn enumerate_solutions(lcp: &Lcp) -> Vec<Vec<f64>> {
    let n = lcp.size();
    assert!(
        n <= MAX_ENUMERATION_SIZE,
        "enumerate_solutions is exponential; n = {n} exceeds {MAX_ENUMERATION_SIZE}"
    );
    let q = lcp.q();
    let mut solutions: Vec<Vec<f64>> = Vec::new();
    for mask in 0u32..(1u32 << n) {
        let alpha: Vec<usize> = (0..n).filter(|&i| mask >> i & 1 == 1).collect();
        let k = alpha.len();
        let mut a = Vec::with_capacity(k * k);
        for &i in &alpha {
            a.extend(alpha.iter().map(|&j| lcp.m(i, j)));
        }
        let b: Vec<f64> = alpha.iter().map(|&i| -q[i]).collect();
        let Some(z_alpha) = solve_dense(k, a, b) else { continue };
        let mut z = vec![0.0; n];
        for (&i, &v) in alpha.iter().zip(&z_alpha) {
            z[i] = v;
        }
        if lcp.residuals(&z).max_violation() > ENUMERATION_TOLERANCE {
            continue;
        }
        z.iter_mut().for_each(|v| *v = v.max(0.0));
        let zmax = z.iter().fold(1.0_f64, |acc, v| acc.max(v.abs()));
        let duplicate = solutions
            .iter()
            .any(|s| s.iter().zip(&z).all(|(a, b)| (a - b).abs() <= ENUMERATION_TOLERANCE * zmax));
        if !duplicate {
            solutions.push(z);
        }
    }
    solutions
}

/// Solves the k×k system A x = b (A row-major) by Gaussian elimination with partial pivoting;
/// None if a pivot falls below 10⁻¹² · max|A_ij|.
fn solve_dense(k: usize, mut a: Vec<f64>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let amax = a.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()));
    let tiny = 1e-12 * amax;
    for c in 0..k {
        let p = (c..k).max_by(|&i, &j| a[i * k + c].abs().total_cmp(&a[j * k + c].abs()))?;
        if a[p * k + c].abs() <= tiny || a[p * k + c] == 0.0 {
            return None;
        }
        if p != c {
            for j in 0..k {
                a.swap(p * k + j, c * k + j);
            }
            b.swap(p, c);
        }
        let piv = a[c * k + c];
        for i in c + 1..k {
            let f = a[i * k + c] / piv;
            if f != 0.0 {
                for j in c..k {
                    a[i * k + j] -= f * a[c * k + j];
                }
                b[i] -= f * b[c];
            }
        }
    }
    let mut x = vec![0.0; k];
    for i in (0..k).rev() {
        let s: f64 = (i + 1..k).map(|j| a[i * k + j] * x[j]).sum();
        x[i] = (b[i] - s) / a[i * k + i];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unique_solution_of_p_matrix() {
        let lcp = Lcp::from_rows(&[vec![2.0, 1.0], vec![1.0, 2.0]], vec![-5.0, -6.0]).unwrap();
        let s = enumerate_solutions(&lcp);
        assert_eq!(s.len(), 1);
        assert!((s[0][0] - 4.0 / 3.0).abs() < 1e-14 && (s[0][1] - 7.0 / 3.0).abs() < 1e-14);
    }

    #[test]
    fn several_and_no_solutions() {
        // Bimatrix game of Cottle, Pang & Stone: three solutions.
        let rows = [
            vec![0.0, 0.0, 10.0, 20.0],
            vec![0.0, 0.0, 30.0, 15.0],
            vec![10.0, 20.0, 0.0, 0.0],
            vec![30.0, 15.0, 0.0, 0.0],
        ];
        let lcp = Lcp::from_rows(&rows, vec![-1.0; 4]).unwrap();
        assert_eq!(enumerate_solutions(&lcp).len(), 3);
        // Infeasible: w = −z − 1 < 0.
        let lcp = Lcp::from_rows(&[vec![-1.0]], vec![-1.0]).unwrap();
        assert!(enumerate_solutions(&lcp).is_empty());
        // q ≥ 0 with M = −I: z = 0 only (z_i > 0 would need w_i = −z_i + q_i = 0).
        let lcp = Lcp::from_rows(&[vec![-1.0, 0.0], vec![0.0, -1.0]], vec![1.0, 1.0]).unwrap();
        assert_eq!(enumerate_solutions(&lcp).len(), 4);
    }

    #[test]
    fn solve_dense_detects_singularity() {
        assert!(solve_dense(2, vec![1.0, 2.0, 2.0, 4.0], vec![1.0, 1.0]).is_none());
        let x = solve_dense(2, vec![0.0, 1.0, 1.0, 0.0], vec![3.0, 4.0]).unwrap();
        assert_eq!(x, vec![4.0, 3.0]);
        assert_eq!(solve_dense(0, vec![], vec![]), Some(vec![]));
    }
}
