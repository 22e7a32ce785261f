//! Lemke's complementary pivot method with covering vector e and the lexicographic
//! minimum-ratio rule [CPS92, §4.4 and §4.9]; see [`lemke()`].

use super::{Lcp, LcpError, LcpSolution};

/// Scaled residual above which a terminated Lemke run is reported as
/// [`LcpError::InaccurateSolution`] rather than as a solution (see [`super::LcpResiduals`] for
/// the scaling). It is a sanity check against a numerically destroyed basis, not a precision
/// target: well-conditioned problems end with residuals near 10⁻¹⁵.
const ACCEPTANCE_THRESHOLD: f64 = 1e-6;

/// Relative tolerance below which negative round-off in the scaled z is clipped to 0.
const CLIP_TOLERANCE: f64 = 1e-9;

/// Parameters of [`lemke()`].
#[derive(Clone, Debug)]
pub struct LemkeParams {
    /// Maximum number of pivots (z0 entering and z0 leaving included); reaching it gives
    /// [`LcpError::PivotLimit`]. `None` means 100·(n + 1), far above the ≈ 0.6·n pivots typical
    /// of contact problems but below the 2ⁿ of Murty's worst-case example (Murty 1988, ch. 6).
    pub max_pivots: Option<usize>,
    /// Relative tolerance τ of the pivoting, applied to the internally scaled data (unit-size
    /// M̂ and q̂, see [`lemke()`]):
    ///
    /// * an entry d_i of the entering column counts as positive iff d_i > τ · max(1, ‖d‖∞);
    /// * two quantities a, b of the lexicographic ratio test count as tied iff
    ///   |a − b| ≤ τ · max(1, |a|, |b|);
    /// * at secondary-ray termination, a basic z0 ≤ τ · max(1, ‖x_B‖∞) counts as 0 (the basic
    ///   point then already solves the LCP and is returned).
    ///
    /// Must be finite and in [0, 1). Default 10⁻¹¹.
    pub pivot_tolerance: f64,
}

impl Default for LemkeParams {
    fn default() -> Self {
        Self { max_pivots: None, pivot_tolerance: 1e-11 }
    }
}

impl LemkeParams {
    /// The effective pivot limit for a problem of size n: `max_pivots`, or 100·(n + 1).
    pub fn pivot_limit(&self, n: usize) -> usize {
        self.max_pivots.unwrap_or_else(|| n.saturating_add(1).saturating_mul(100))
    }
}

/// Solves LCP(q, M) (find z ≥ 0 with w = M z + q ≥ 0 and zᵀw = 0) by Lemke's method with
/// covering vector e = (1, …, 1) and the lexicographic minimum-ratio rule [CPS92, §4.4, §4.9].
///
/// The pivot count includes the first pivot (z0 enters) and the last (z0 leaves); it is 0 when
/// q ≥ 0. Lemke's method always succeeds when M is a P-matrix (then the solution is unique),
/// and for copositive-plus M (e.g. positive semidefinite) a ray proves the LCP infeasible
/// [CPS92, §4.4].
///
/// # Algorithm
///
/// Lemke's method works on the augmented system
///
/// ```text
///     w − M z − e z0 = q,   w, z, z0 ≥ 0,   z_i w_i = 0 (i = 1..n),
/// ```
///
/// whose variables are w1..wn, z1..zn and the artificial z0; the constraint columns are
/// A(w_k) = e_k, A(z_k) = −M_{:,k} and A(z0) = −e. A basis B holds n of these columns, and the
/// basic values are x_B = B⁻¹q.
///
/// 1. If q ≥ 0, z = 0 solves the LCP (0 pivots).
/// 2. Otherwise z0 enters at the row r of the smallest q_r (ties: the lexicographic minimum of
///    the rows [q_i, e_iᵀ], i.e. the largest index), which makes every basic value nonnegative.
/// 3. Complementary pivoting: the entering variable is the complement of the one that just left
///    (w_k ↔ z_k). Its column d = B⁻¹A(v) is computed; the leaving row is the lexicographic
///    minimum of the rows [x_i, (B⁻¹)_{i,1..n}] / d_i over the rows with d_i > 0, with the
///    columns of B⁻¹ in the natural order w1..wn. This is the minimum-ratio test of the
///    perturbed problem q + (ε, ε², …, εⁿ), whose bases are all nondegenerate, so no basis
///    repeats and the method terminates [CPS92, §4.9].
/// 4. Stop when z0 leaves (the basic solution solves the LCP), or when no d_i is positive
///    (secondary ray, [`LcpError::RayTermination`]).
///
/// # Implementation and cost
///
/// The data are first scaled by powers of two, M̂ = M / σ_M and q̂ = q / σ_q with σ_M ≈ max|M_ij|
/// and σ_q ≈ max|q_i|; with w = σ_q ŵ and z = (σ_q / σ_M) ẑ this is the same LCP, Lemke follows
/// the same path (the lexicographic order is invariant under positive scalings), and the scaling
/// is exact in floating point. All tolerances are then relative to data of unit size.
///
/// B⁻¹ is kept explicitly, column-major. Its column k is the unit vector e_ρ while w_k is basic
/// in row ρ, so only the columns of the nonbasic w's (at most one more than the number of basic
/// z's) are stored densely and updated. A pivot on row r with entering column d is the
/// product-form update B⁻¹ ← B⁻¹ − (d − e_r)(B⁻¹)_{r,:} / d_r applied to those columns, fused with
/// the computation of the next entering column B⁻¹A(v) in the same pass over memory (four columns
/// per pass). The cost per pivot is O(n·k) with k the number of basic z's, at most O(n²), on
/// contiguous memory; no O(n²) work is spent on the unit columns.
///
/// After termination the basic values receive one step of iterative refinement against the
/// scaled data, z is read off, entries in [−τ_c, 0) are clipped to 0 (τ_c = 10⁻⁹ in units of
/// max(1, ‖ẑ‖∞)), and w = M z + q is recomputed from the original data. The result is verified
/// with [`Lcp::residuals`]; if a scaled violation (−min z, −min w or the complementarity
/// residual) exceeds 10⁻⁶, [`LcpError::InaccurateSolution`] is returned instead.
///
/// # Example
///
/// ```
/// use mlpg_contact::lcp::{Lcp, LcpError, LemkeParams, lemke};
///
/// // M symmetric positive definite: the unique solution is z = (4/3, 7/3), w = 0.
/// let lcp = Lcp::from_rows(&[vec![2.0, 1.0], vec![1.0, 2.0]], vec![-5.0, -6.0])?;
/// let sol = lemke(&lcp, &LemkeParams::default())?;
/// assert!((sol.z[0] - 4.0 / 3.0).abs() < 1e-14 && (sol.z[1] - 7.0 / 3.0).abs() < 1e-14);
/// assert_eq!(sol.pivots, 3);
/// assert!(sol.residuals.max_violation() < 1e-14);
///
/// // w = −z − 1 < 0 for every z ≥ 0: no solution, Lemke stops on a secondary ray.
/// let infeasible = Lcp::from_rows(&[vec![-1.0]], vec![-1.0])?;
/// let err = lemke(&infeasible, &LemkeParams::default()).unwrap_err();
/// assert!(matches!(err, LcpError::RayTermination { pivots: 1 }));
/// # Ok::<(), LcpError>(())
/// ```
///
/// # Errors
/// * [`LcpError::RayTermination`]: the entering column had no positive entry while z0 > 0;
/// * [`LcpError::PivotLimit`]: `params.pivot_limit(n)` pivots were made without termination;
/// * [`LcpError::InvalidParameter`]: `pivot_tolerance` is not finite or not in [0, 1);
/// * [`LcpError::InaccurateSolution`]: the run terminated but the verified residuals exceed
///   10⁻⁶ (scaled).
pub fn lemke(lcp: &Lcp, params: &LemkeParams) -> Result<LcpSolution, LcpError> {
    let tol = params.pivot_tolerance;
    if !(tol.is_finite() && (0.0..1.0).contains(&tol)) {
        return Err(LcpError::InvalidParameter { what: "pivot_tolerance", value: tol });
    }
    let n = lcp.size();
    let q = lcp.q();
    if q.iter().all(|&x| x >= 0.0) {
        let z = vec![0.0; n];
        let residuals = lcp.residuals(&z);
        return Ok(LcpSolution { z, w: q.to_vec(), pivots: 0, residuals });
    }
    let limit = params.pivot_limit(n);
    if limit == 0 {
        return Err(LcpError::PivotLimit { limit });
    }

    // Exact power-of-two scaling to unit-size data.
    let sigma_m = pow2_scale(max_abs(lcp.m_row_major()));
    let sigma_q = pow2_scale(max_abs(q));
    let m = lcp.m_row_major();
    let mut mcol = vec![0.0; n * n];
    for (j, col) in mcol.chunks_exact_mut(n).enumerate() {
        for (i, c) in col.iter_mut().enumerate() {
            *c = m[i * n + j] / sigma_m;
        }
    }
    let qhat: Vec<f64> = q.iter().map(|&x| x / sigma_q).collect();
    let mut t = Basis::new(mcol, &qhat);

    // First pivot: z0 enters at the lexicographic minimum of [q_i, e_iᵀ]: the smallest q_i,
    // ties broken towards the largest index.
    let qmin = qhat.iter().copied().fold(f64::INFINITY, f64::min);
    let tie = tol * qmin.abs().max(1.0);
    let r0 = qhat.iter().rposition(|&x| x <= qmin + tie).unwrap_or(0);
    let mut d = vec![-1.0; n];
    let mut dnext = vec![0.0; n];
    let mut entering = Var::Z(r0);
    t.pivot(r0, &d, Var::Z0, Some(entering), &mut dnext);
    let mut pivots = 1;

    loop {
        std::mem::swap(&mut d, &mut dnext);
        let Some(r) = t.ratio_test(&d, tol) else {
            // Secondary ray, unless z0 is already (numerically) zero: then the basic point
            // is complementary and solves the LCP.
            let xmax = max_abs(&t.x).max(1.0);
            let z0_is_zero =
                t.basis.iter().position(|&v| v == Var::Z0).is_some_and(|rz| t.x[rz] <= tol * xmax);
            if z0_is_zero {
                break;
            }
            return Err(LcpError::RayTermination { pivots });
        };
        if pivots >= limit {
            return Err(LcpError::PivotLimit { limit });
        }
        let next = t.basis[r].complement();
        t.pivot(r, &d, entering, next, &mut dnext);
        pivots += 1;
        match next {
            Some(v) => entering = v,
            None => break,
        }
    }

    t.refine(&qhat);
    let mut z = vec![0.0; n];
    let mut w_pivot = vec![0.0; n];
    for (&v, &x) in t.basis.iter().zip(&t.x) {
        match v {
            Var::W(k) => w_pivot[k] = x * sigma_q,
            Var::Z(k) => z[k] = x,
            Var::Z0 => {}
        }
    }
    let clip = CLIP_TOLERANCE * max_abs(&z).max(1.0);
    let z_unit = sigma_q / sigma_m;
    for zi in &mut z {
        if *zi < 0.0 && *zi >= -clip {
            *zi = 0.0;
        }
        *zi *= z_unit;
    }
    let w = lcp.w(&z);
    let mut residuals = lcp.residuals_with_w(&z, &w);
    residuals.equation_residual = lcp.residuals_with_w(&z, &w_pivot).equation_residual;
    let worst = residuals.max_complementarity.max(-residuals.min_z).max(-residuals.min_w);
    if worst.is_nan() || worst > ACCEPTANCE_THRESHOLD {
        return Err(LcpError::InaccurateSolution {
            pivots,
            min_z: residuals.min_z,
            min_w: residuals.min_w,
            max_complementarity: residuals.max_complementarity,
            threshold: ACCEPTANCE_THRESHOLD,
        });
    }
    Ok(LcpSolution { z, w, pivots, residuals })
}

/// max |v_i| (0 for an empty slice).
fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()))
}

/// The power of two nearest (in log scale) to x > 0, or 1 for x = 0; dividing by it is exact.
fn pow2_scale(x: f64) -> f64 {
    if x > 0.0 && x.is_finite() {
        // The clamp keeps the result a normal number; the cast is exact after rounding.
        let e = x.log2().round().clamp(-1000.0, 1000.0) as i32;
        2.0_f64.powi(e)
    } else {
        1.0
    }
}

/// A variable of the augmented system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Var {
    /// w_k (0-based k).
    W(usize),
    /// z_k (0-based k).
    Z(usize),
    /// The artificial variable z0.
    Z0,
}

impl Var {
    /// The complementary variable (w_k ↔ z_k); z0 has none.
    fn complement(self) -> Option<Var> {
        match self {
            Var::W(k) => Some(Var::Z(k)),
            Var::Z(k) => Some(Var::W(k)),
            Var::Z0 => None,
        }
    }
}

/// Marker for "w_k is not basic" in [`Basis::w_row`].
const NONE: usize = usize::MAX;

/// The current basis of the augmented system, with B⁻¹ kept explicitly.
struct Basis {
    n: usize,
    /// Scaled M̂, column-major: M̂_ij at j·n + i.
    mcol: Vec<f64>,
    /// B⁻¹, column-major: (B⁻¹)_ik at k·n + i. Unit columns are stored too (exactly).
    binv: Vec<f64>,
    /// For each k, the row where w_k is basic (then column k of B⁻¹ is e_row), or NONE (then
    /// column k is a general dense column).
    w_row: Vec<usize>,
    /// Basic values x_B = B⁻¹ q̂.
    x: Vec<f64>,
    /// Basic variable of each row.
    basis: Vec<Var>,
}

impl Basis {
    /// The initial basis B = I (all w basic), x_B = q̂.
    fn new(mcol: Vec<f64>, qhat: &[f64]) -> Self {
        let n = qhat.len();
        let mut binv = vec![0.0; n * n];
        for k in 0..n {
            binv[k * n + k] = 1.0;
        }
        Self {
            n,
            mcol,
            binv,
            w_row: (0..n).collect(),
            x: qhat.to_vec(),
            basis: (0..n).map(Var::W).collect(),
        }
    }

    /// (B⁻¹)_ik.
    fn entry(&self, i: usize, k: usize) -> f64 {
        match self.w_row[k] {
            NONE => self.binv[k * self.n + i],
            row => f64::from(u8::from(row == i)),
        }
    }

    /// The leaving row for entering column d: the lexicographic minimum of
    /// [x_i, (B⁻¹)_{i,:}] / d_i over the rows with d_i > τ·max(1, ‖d‖∞); None for a ray.
    fn ratio_test(&self, d: &[f64], tol: f64) -> Option<usize> {
        let piv_tol = tol * max_abs(d).max(1.0);
        let mut best: Option<usize> = None;
        for (i, &di) in d.iter().enumerate() {
            if di > piv_tol {
                best = match best {
                    Some(b) if !self.lex_less(i, b, d, tol) => Some(b),
                    _ => Some(i),
                };
            }
        }
        best
    }

    /// Whether row i is lexicographically smaller than row j in the ratio test.
    fn lex_less(&self, i: usize, j: usize, d: &[f64], tol: f64) -> bool {
        // Negative basic values are round-off of zeros.
        let (xi, xj) = (self.x[i].max(0.0) / d[i], self.x[j].max(0.0) / d[j]);
        if let Some(less) = cmp_tol(xi, xj, tol) {
            return less;
        }
        for k in 0..self.n {
            let (yi, yj) = (self.entry(i, k) / d[i], self.entry(j, k) / d[j]);
            if let Some(less) = cmp_tol(yi, yj, tol) {
                return less;
            }
        }
        // Rows equal to within the tolerance (B⁻¹ numerically singular): keep the first.
        false
    }

    /// Pivots `entering` (with column d = B⁻¹A(entering)) into row r, and writes the column
    /// B⁻¹A(next) of the following entering variable, in the new basis, into `dnext`.
    fn pivot(&mut self, r: usize, d: &[f64], entering: Var, next: Option<Var>, dnext: &mut [f64]) {
        let n = self.n;
        let dr = d[r];
        let xr = self.x[r] / dr;
        for (xi, &di) in self.x.iter_mut().zip(d) {
            *xi -= di * xr;
        }
        self.x[r] = xr;

        // Structural changes: the leaving w's column stops being a unit vector (it is stored
        // as e_r, so the generic update below applies); the entering w's becomes e_r.
        if let Var::W(j) = self.basis[r] {
            self.w_row[j] = NONE;
        }
        if let Var::W(j) = entering {
            self.w_row[j] = r;
            let col = &mut self.binv[j * n..(j + 1) * n];
            col.fill(0.0);
            col[r] = 1.0;
        }
        self.basis[r] = entering;

        // Product-form update of the non-unit columns, fused with dnext = B⁻¹(−M̂_{:,j}) when
        // z_j enters next. Columns are visited in increasing order (sequential memory).
        let a = match next {
            Some(Var::Z(j)) => Some(&self.mcol[j * n..(j + 1) * n]),
            _ => None,
        };
        let w_row = &self.w_row;
        let mut cols: Vec<Column<'_>> = self
            .binv
            .chunks_exact_mut(n)
            .enumerate()
            .filter(|(k, _)| w_row[*k] == NONE)
            .map(|(k, col)| Column { f: col[r] / dr, ak: a.map_or(0.0, |a| -a[k]), col })
            .collect();
        dnext.fill(0.0);
        update_columns(&mut cols, r, d, dnext);
        drop(cols);

        if let Some(a) = a {
            for (&row, &akj) in self.w_row.iter().zip(a) {
                if row != NONE {
                    dnext[row] -= akj;
                }
            }
        }
        if let Some(Var::W(j)) = next {
            // w_j is nonbasic (z_j just left), so its column is stored densely.
            dnext.copy_from_slice(&self.binv[j * n..(j + 1) * n]);
        }
    }

    /// v ↦ B⁻¹ v.
    fn apply_binv(&self, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        for ((&row, &vk), col) in self.w_row.iter().zip(v).zip(self.binv.chunks_exact(self.n)) {
            if row != NONE {
                out[row] += vk;
            } else if vk != 0.0 {
                for (o, &c) in out.iter_mut().zip(col) {
                    *o += c * vk;
                }
            }
        }
        out
    }

    /// q̂ − B x_B, with the columns A(w_k) = e_k, A(z_k) = −M̂_{:,k}, A(z0) = −e.
    fn basis_residual(&self, qhat: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut res = qhat.to_vec();
        for (&v, &x) in self.basis.iter().zip(&self.x) {
            match v {
                Var::W(k) => res[k] -= x,
                Var::Z(k) => {
                    for (r, &m) in res.iter_mut().zip(&self.mcol[k * n..(k + 1) * n]) {
                        *r += m * x;
                    }
                }
                Var::Z0 => res.iter_mut().for_each(|r| *r += x),
            }
        }
        res
    }

    /// One step of iterative refinement x_B ← x_B + B⁻¹(q̂ − B x_B), kept only if it reduces
    /// the residual.
    fn refine(&mut self, qhat: &[f64]) {
        let res = self.basis_residual(qhat);
        let before = max_abs(&res);
        if before == 0.0 {
            return;
        }
        let delta = self.apply_binv(&res);
        let old = self.x.clone();
        for (x, dx) in self.x.iter_mut().zip(&delta) {
            *x += dx;
        }
        let after = max_abs(&self.basis_residual(qhat));
        if after.is_nan() || after >= before {
            self.x = old;
        }
    }
}

/// A non-unit column of B⁻¹ during a pivot on row r with pivot element d_r.
struct Column<'a> {
    /// The column (n entries), updated in place.
    col: &'a mut [f64],
    /// Its multiplier (B⁻¹)_rk / d_r.
    f: f64,
    /// Its weight −M̂_kj in the next entering column (0 if the next variable is not a z).
    ak: f64,
}

/// Applies the product-form update B⁻¹ ← B⁻¹ − (d − e_r)(B⁻¹)_{r,:} / d_r to `cols` and adds
/// Σ_k (B⁻¹_new)_{:,k} ak to `acc`. Four columns are processed per pass over d and `acc`, which
/// cuts the memory traffic of the fused update.
fn update_columns(cols: &mut [Column<'_>], r: usize, d: &[f64], acc: &mut [f64]) {
    let mut quads = cols.chunks_exact_mut(4);
    for quad in &mut quads {
        if let [c0, c1, c2, c3] = quad {
            let (f0, f1, f2, f3) = (c0.f, c1.f, c2.f, c3.f);
            let (a0, a1, a2, a3) = (c0.ak, c1.ak, c2.ak, c3.ak);
            let cols4 = c0.col.iter_mut().zip(c1.col.iter_mut()).zip(c2.col.iter_mut());
            for ((((x0, x1), x2), x3), (&di, s)) in
                cols4.zip(c3.col.iter_mut()).zip(d.iter().zip(acc.iter_mut()))
            {
                *x0 -= di * f0;
                *x1 -= di * f1;
                *x2 -= di * f2;
                *x3 -= di * f3;
                *s += *x0 * a0 + *x1 * a1 + *x2 * a2 + *x3 * a3;
            }
            for c in [c0, c1, c2, c3] {
                fix_pivot_row(c, r, acc);
            }
        }
    }
    for c in quads.into_remainder() {
        let (f, ak) = (c.f, c.ak);
        for (x, (&di, s)) in c.col.iter_mut().zip(d.iter().zip(acc.iter_mut())) {
            *x -= di * f;
            *s += *x * ak;
        }
        fix_pivot_row(c, r, acc);
    }
}

/// Sets the pivot-row entry of an updated column to its exact value f (the generic update
/// leaves round-off of 0 there) and corrects its contribution to `acc`.
fn fix_pivot_row(c: &mut Column<'_>, r: usize, acc: &mut [f64]) {
    let computed = c.col[r];
    c.col[r] = c.f;
    acc[r] += (c.f - computed) * c.ak;
}

/// Compares a and b with tolerance τ·max(1, |a|, |b|): Some(true) if a < b, Some(false) if
/// a > b, None if tied.
fn cmp_tol(a: f64, b: f64, tol: f64) -> Option<bool> {
    let t = tol * a.abs().max(b.abs()).max(1.0);
    if a < b - t {
        Some(true)
    } else if a > b + t {
        Some(false)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solve(rows: &[Vec<f64>], q: &[f64]) -> Result<LcpSolution, LcpError> {
        let lcp = Lcp::from_rows(rows, q.to_vec()).unwrap();
        lemke(&lcp, &LemkeParams::default())
    }

    /// Murty's upper-triangular example with q giving 2ⁿ pivots (Murty 1988, ch. 6).
    fn murty(n: usize) -> (Vec<Vec<f64>>, Vec<f64>) {
        let rows = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        if j == i {
                            1.0
                        } else if j > i {
                            2.0
                        } else {
                            0.0
                        }
                    })
                    .collect()
            })
            .collect();
        let q =
            (0..n).map(|i| -(2.0_f64.powi(n as i32 + 1) - 2.0_f64.powi(i as i32 + 1))).collect();
        (rows, q)
    }

    #[test]
    fn nonnegative_q_gives_zero_without_pivots() {
        let s = solve(&[vec![-1.0, 5.0], vec![3.0, -2.0]], &[0.0, 2.0]).unwrap();
        assert_eq!(s.z, vec![0.0, 0.0]);
        assert_eq!(s.w, vec![0.0, 2.0]);
        assert_eq!(s.pivots, 0);
        assert_eq!(s.residuals.max_violation(), 0.0);
    }

    #[test]
    fn empty_problem() {
        let lcp = Lcp::new(0, vec![], vec![]).unwrap();
        let s = lemke(&lcp, &LemkeParams::default()).unwrap();
        assert!(s.z.is_empty() && s.pivots == 0);
    }

    #[test]
    fn one_by_one() {
        let s = solve(&[vec![2.0]], &[-4.0]).unwrap();
        assert_eq!(s.z, vec![2.0]);
        assert_eq!(s.w, vec![0.0]);
        assert_eq!(s.pivots, 2);
    }

    #[test]
    fn two_by_two_positive_definite() {
        let s = solve(&[vec![2.0, 1.0], vec![1.0, 2.0]], &[-5.0, -6.0]).unwrap();
        assert!((s.z[0] - 4.0 / 3.0).abs() < 1e-15 && (s.z[1] - 7.0 / 3.0).abs() < 1e-15);
        assert_eq!(s.pivots, 3);
        assert!(s.residuals.max_violation() < 1e-15);
    }

    #[test]
    fn ray_cases() {
        assert!(matches!(
            solve(&[vec![-1.0]], &[-1.0]),
            Err(LcpError::RayTermination { pivots: 1 })
        ));
        assert!(matches!(
            solve(&[vec![0.0]], &[-1.0]),
            Err(LcpError::RayTermination { pivots: 1 })
        ));
        let rows = [vec![-2.0, 1.0], vec![1.0, -2.0]];
        assert!(matches!(solve(&rows, &[-1.0, -1.0]), Err(LcpError::RayTermination { pivots: 1 })));
    }

    #[test]
    fn pivot_limit() {
        let (rows, q) = murty(6);
        let lcp = Lcp::from_rows(&rows, q).unwrap();
        let s = lemke(&lcp, &LemkeParams::default()).unwrap();
        assert_eq!(s.pivots, 64);
        assert_eq!(s.z, vec![0.0, 0.0, 0.0, 0.0, 0.0, 64.0]);
        let exact = LemkeParams { max_pivots: Some(64), ..LemkeParams::default() };
        assert_eq!(lemke(&lcp, &exact).unwrap().pivots, 64);
        let short = LemkeParams { max_pivots: Some(63), ..LemkeParams::default() };
        assert!(matches!(lemke(&lcp, &short), Err(LcpError::PivotLimit { limit: 63 })));
        let zero = LemkeParams { max_pivots: Some(0), ..LemkeParams::default() };
        assert!(matches!(lemke(&lcp, &zero), Err(LcpError::PivotLimit { limit: 0 })));
        assert_eq!(LemkeParams::default().pivot_limit(6), 700);
    }

    #[test]
    fn invalid_tolerance() {
        let lcp = Lcp::from_rows(&[vec![1.0]], vec![-1.0]).unwrap();
        for bad in [f64::NAN, -1.0, 1.0, f64::INFINITY] {
            let p = LemkeParams { pivot_tolerance: bad, ..LemkeParams::default() };
            assert!(matches!(lemke(&lcp, &p), Err(LcpError::InvalidParameter { .. })));
        }
    }

    #[test]
    fn kostreva_cycling_example_terminates() {
        let rows = [vec![1.0, 2.0, 0.0], vec![0.0, 1.0, 2.0], vec![2.0, 0.0, 1.0]];
        let s = solve(&rows, &[-1.0, -1.0, -1.0]).unwrap();
        assert_eq!(s.pivots, 4);
        for zi in &s.z {
            assert!((zi - 1.0 / 3.0).abs() < 1e-15);
        }
    }

    #[test]
    fn scaling_does_not_change_the_path() {
        let rows = [vec![11.0, 0.0, 10.0, -1.0], vec![0.0, 11.0, 10.0, -1.0]];
        let rows = [
            rows[0].clone(),
            rows[1].clone(),
            vec![10.0, 10.0, 21.0, -1.0],
            vec![1.0, 1.0, 1.0, 0.0],
        ];
        let q = [50.0, 50.0, 3.0, -6.0];
        let base = solve(&rows, &q).unwrap();
        for (sm, sq) in [(1e6, 1e-3), (3e-7, 7e5), (0.1, 0.1)] {
            let rs: Vec<Vec<f64>> =
                rows.iter().map(|r| r.iter().map(|x| x * sm).collect()).collect();
            let qs: Vec<f64> = q.iter().map(|x| x * sq).collect();
            let s = solve(&rs, &qs).unwrap();
            assert_eq!(s.pivots, base.pivots);
            for (a, b) in s.z.iter().zip(&base.z) {
                assert!((a - b * sq / sm).abs() <= 1e-12 * (b * sq / sm).abs().max(1e-300));
            }
            assert!(s.residuals.max_violation() < 1e-14, "{:?}", s.residuals);
        }
    }

    #[test]
    fn inverse_stays_consistent_on_random_problem() {
        // A 60×60 positive definite, non-symmetric M: Lemke must solve it with tiny residuals
        // and the maintained B⁻¹ must be the inverse of the final basis.
        let n = 60;
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let a: Vec<f64> = (0..n * n).map(|_| rnd()).collect();
        let mut m = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let ata: f64 = (0..n).map(|k| a[k * n + i] * a[k * n + j]).sum();
                m[i * n + j] = ata / n as f64 + if i == j { 1.0 } else { 0.0 };
            }
        }
        for i in 0..n {
            for j in 0..i {
                let s = 0.1 * rnd();
                m[i * n + j] += s;
                m[j * n + i] -= s;
            }
        }
        let q: Vec<f64> = (0..n).map(|_| rnd()).collect();
        let lcp = Lcp::new(n, m.clone(), q.clone()).unwrap();
        let s = lemke(&lcp, &LemkeParams::default()).unwrap();
        assert!(s.residuals.max_violation() < 1e-13, "{:?}", s.residuals);

        // Re-run the pivoting by hand to inspect the final basis.
        let mut mcol = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                mcol[j * n + i] = m[i * n + j];
            }
        }
        let mut t = Basis::new(mcol.clone(), &q);
        let qmin = q.iter().copied().fold(f64::INFINITY, f64::min);
        let r0 = q.iter().rposition(|&x| x == qmin).unwrap();
        let (mut d, mut dn) = (vec![-1.0; n], vec![0.0; n]);
        let mut entering = Var::Z(r0);
        t.pivot(r0, &d, Var::Z0, Some(entering), &mut dn);
        let mut pivots = 1;
        loop {
            std::mem::swap(&mut d, &mut dn);
            let r = t.ratio_test(&d, 1e-11).unwrap();
            let next = t.basis[r].complement();
            t.pivot(r, &d, entering, next, &mut dn);
            pivots += 1;
            match next {
                Some(v) => entering = v,
                None => break,
            }
        }
        assert_eq!(pivots, s.pivots);
        // B · B⁻¹ = I with the columns A(w_k) = e_k, A(z_k) = −M_{:,k}, A(z0) = −e.
        let mut worst = 0.0_f64;
        for k in 0..n {
            for i in 0..n {
                let mut acc = 0.0;
                for (row, &v) in t.basis.iter().enumerate() {
                    let bik = match v {
                        Var::W(j) => f64::from(u8::from(j == i)),
                        Var::Z(j) => -mcol[j * n + i],
                        Var::Z0 => -1.0,
                    };
                    acc += bik * t.entry(row, k);
                }
                worst = worst.max((acc - f64::from(u8::from(i == k))).abs());
            }
        }
        assert!(worst < 1e-12, "‖B B⁻¹ − I‖max = {worst:e}");
    }

    #[test]
    fn cmp_tol_ties() {
        assert_eq!(cmp_tol(1.0, 1.0 + 1e-13, 1e-11), None);
        assert_eq!(cmp_tol(1.0, 1.1, 1e-11), Some(true));
        assert_eq!(cmp_tol(1.1, 1.0, 1e-11), Some(false));
        assert_eq!(pow2_scale(0.0), 1.0);
        assert_eq!(pow2_scale(3.0), 4.0);
        assert_eq!(pow2_scale(2.3e5), 262_144.0);
    }
}
