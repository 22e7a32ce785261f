//! Lemke's complementary pivot method with covering vector e and the lexicographic
//! minimum-ratio rule [CPS92, §4.4 and §4.9]; see [`lemke()`].

use super::{Lcp, LcpError, LcpSolution};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use serde::Serialize;

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
/// B⁻¹ is kept explicitly. Its column k is the unit vector e_ρ while w_k is basic in row ρ,
/// so only the columns of the nonbasic w's (at most one more than the number of basic z's, k)
/// are stored, densely (n × k). A pivot on row r with entering column d is the product-form
/// update B⁻¹ ← B⁻¹ − (d − e_r)(B⁻¹)_{r,:} / d_r; row r of the result is written at once, the
/// other rows' rank-1 updates are held back for 32 pivots and then applied in one matrix
/// product. The next entering column B⁻¹A(v) of a z is B⁻¹ times a column of −M̂, again a
/// product with the stored columns; each such pass also forms the columns of the z's that
/// will probably enter next (the complements of the basic w's with the next smallest ratios),
/// up to 15 at once, and keeps them current until they are used. So the stored columns are
/// read and written in matrix–matrix products (cache-blocked, SIMD) rather than once per
/// pivot in memory-bound loops: the cost per pivot is still O(n·k) flops but runs at the
/// processor's arithmetic speed. On the 2 000-candidate strip, where contact closes along a
/// front and every guess enters in turn, 1 888 pivots take 2.4–2.8× less time than the
/// previous per-pivot update (`examples/studies/lemke_timing.rs`, `examples/studies/contact_timing.rs`;
/// `docs/dev/performance.md`). All products run sequentially, so results do not depend on the
/// number of threads.
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
    lemke_observed(lcp, params, &mut |_, _| {})
}

/// [`lemke`], reporting `(pivots, expected pivots)` to `progress` every 16 pivots; the
/// expected count is `n + 1` (a complementary basis with every candidate closed) and grows
/// with the pivots beyond it (the limit is [`LemkeParams::pivot_limit`]).
///
/// # Errors
/// As [`lemke`].
pub fn lemke_observed(
    lcp: &Lcp,
    params: &LemkeParams,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<LcpSolution, LcpError> {
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
    // M̂ column-major, transposed in square tiles (cache-friendly for both layouts).
    let mut mcol = vec![0.0; n * n];
    const TILE: usize = 64;
    for j0 in (0..n).step_by(TILE) {
        for i0 in (0..n).step_by(TILE) {
            for j in j0..(j0 + TILE).min(n) {
                for i in i0..(i0 + TILE).min(n) {
                    mcol[j * n + i] = m[i * n + j] / sigma_m;
                }
            }
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
        if pivots % 16 == 0 {
            progress(pivots, pivots.max(n + 1));
        }
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

/// Steps of iterative refinement at most in [`polish`]'s dense solve (each kept only while it
/// reduces the residual of the closed rows).
const POLISH_REFINEMENT_STEPS: usize = 3;

/// What [`polish`] did to an LCP answer.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Polish {
    /// Size of the closed set A = {i : z_i > 0} the dense solve was made on.
    pub closed: usize,
    /// [`closed_set_residual`] of the answer given to [`polish`].
    pub residual_before: f64,
    /// [`closed_set_residual`] of the polished answer (NaN when `M_AA` was numerically
    /// singular; the given answer's when A is empty).
    pub residual_after: f64,
    /// Steps of iterative refinement kept after the first solve.
    pub refinement_steps: usize,
    /// Whether the polished answer replaced the given one.
    pub accepted: bool,
}

/// The residual of an LCP answer (z, w) on its own closed set, relative to the data:
/// max(maxᵢ{|w_i| : z_i > 0}, maxᵢ(−w_i), 0) / s with the scale s of [`super::LcpResiduals`]
/// (`residuals.scale`): the closed gaps (0 in exact arithmetic) and any negative gap.
pub fn closed_set_residual(z: &[f64], w: &[f64], scale: f64) -> f64 {
    let worst = z.iter().zip(w).fold(0.0_f64, |acc, (&zi, &wi)| {
        let r = if zi > 0.0 { wi.abs() } else { (-wi).max(0.0) };
        if r.is_nan() { f64::NAN } else { acc.max(r) }
    });
    worst / scale
}

/// Polishes an answer of LCP(q, M) on its closed set A = {i : z_i > 0} (for Lemke's answer,
/// the z's of its final complementary basis that are positive): solves `M_AA z_A = −q_A` by a
/// dense LU factorisation with partial pivoting (sequential, so the result does not depend on
/// the number of threads) and up to three steps of iterative refinement with the residual
/// `−q_A − M_AA z_A` computed in f64 from the original data, sets `z_I = 0` elsewhere, clips
/// entries of z_A in [−10⁻⁹ ‖z‖∞, 0) to 0 and recomputes `w = M z + q`.
///
/// The polished answer replaces `solution` only if no entry of z_A is below that clipping
/// bound and its [`closed_set_residual`] is smaller than the given answer's (both relative
/// to the given answer's scale); otherwise `solution` is left as it was. The replaced
/// answer's `residuals` are those of the polished (z, w) (`equation_residual` 0: w is
/// recomputed); `pivots` stays.
///
/// Lemke's tableau carries the round-off of every pivot's product-form update (on the refined
/// beam, κ(M) = 2.9·10⁵: closed gaps 2.3·10⁻¹⁵ against 5·10⁻¹⁸ for the active-set solver);
/// a backward-stable solve on the final basis leaves only the solve's own error
/// (docs/dev/performance.md, "Lemke's final accuracy and one factorisation at 2 000
/// candidates"). Cost: one LU of |A|², (2/3)|A|³ flops.
///
/// # Example
///
/// ```
/// use mlpg_contact::lcp::{Lcp, LemkeParams, lemke, polish};
///
/// let lcp = Lcp::from_rows(&[vec![2.0, 1.0], vec![1.0, 2.0]], vec![-5.0, 1.0])?;
/// let mut sol = lemke(&lcp, &LemkeParams::default())?;
/// let record = polish(&lcp, &mut sol);
/// assert_eq!(record.closed, 1);
/// assert!(record.residual_after <= record.residual_before);
/// assert_eq!(sol.z, vec![2.5, 0.0]);
/// # Ok::<(), mlpg_contact::lcp::LcpError>(())
/// ```
pub fn polish(lcp: &Lcp, solution: &mut LcpSolution) -> Polish {
    let n = lcp.size();
    let scale = solution.residuals.scale;
    let before = closed_set_residual(&solution.z, &accurate_w(lcp, &solution.z), scale);
    let closed: Vec<usize> = (0..n).filter(|&i| solution.z[i] > 0.0).collect();
    let k = closed.len();
    let mut record = Polish {
        closed: k,
        residual_before: before,
        residual_after: before,
        refinement_steps: 0,
        accepted: false,
    };
    if k == 0 || before == 0.0 {
        return record;
    }
    let (m, q) = (lcp.m_row_major(), lcp.q());
    let m_aa = Mat::<f64>::from_fn(k, k, |r, c| m[closed[r] * n + closed[c]]);
    let Some(lu) = DenseLu::new(m_aa.as_ref()) else {
        record.residual_after = f64::NAN;
        return record;
    };
    // r = −q_A − M_AA z_A from the original entries, summed with compensation.
    let residual = |z_a: &[f64]| -> Vec<f64> {
        closed
            .iter()
            .map(|&i| {
                let row = &m[i * n..(i + 1) * n];
                -dot2(q[i], closed.iter().zip(z_a).map(|(&j, &zj)| (row[j], zj)))
            })
            .collect()
    };
    let mut z_a: Vec<f64> = closed.iter().map(|&i| -q[i]).collect();
    lu.solve(&mut z_a);
    let mut r = residual(&z_a);
    for _ in 0..POLISH_REFINEMENT_STEPS {
        let norm = max_abs(&r);
        if norm == 0.0 {
            break;
        }
        let mut dz = r.clone();
        lu.solve(&mut dz);
        let trial: Vec<f64> = z_a.iter().zip(&dz).map(|(a, b)| a + b).collect();
        let r_trial = residual(&trial);
        if r_trial.iter().any(|x| x.is_nan()) || max_abs(&r_trial) >= norm {
            break;
        }
        (z_a, r) = (trial, r_trial);
        record.refinement_steps += 1;
    }
    let mut z = vec![0.0; n];
    for (&i, &zi) in closed.iter().zip(&z_a) {
        z[i] = zi;
    }
    let clip = CLIP_TOLERANCE * max_abs(&z);
    if z.iter().any(|&zi| zi.is_nan() || zi < -clip) {
        record.residual_after = closed_set_residual(&z, &accurate_w(lcp, &z), scale);
        return record;
    }
    for zi in &mut z {
        if *zi < 0.0 {
            *zi = 0.0;
        }
    }
    record.residual_after = closed_set_residual(&z, &accurate_w(lcp, &z), scale);
    if record.residual_after < before {
        record.accepted = true;
        let w = lcp.w(&z);
        solution.residuals = lcp.residuals_with_w(&z, &w);
        solution.z = z;
        solution.w = w;
    }
    record
}

/// `M z + q` with each row's sum compensated ([`dot2`]): the closed gaps of an accurate z,
/// below the round-off of the plain sum.
fn accurate_w(lcp: &Lcp, z: &[f64]) -> Vec<f64> {
    let n = lcp.size();
    let (m, q) = (lcp.m_row_major(), lcp.q());
    (0..n)
        .map(|i| dot2(q[i], m[i * n..(i + 1) * n].iter().copied().zip(z.iter().copied())))
        .collect()
}

/// `start + Σ a_k b_k` in twice the working precision, rounded once (Ogita, Rump & Oishi,
/// "Accurate sum and dot product", SIAM J. Sci. Comput. 26, 2005, Dot2: error-free products
/// by a fused multiply–add and error-free sums).
fn dot2(start: f64, terms: impl Iterator<Item = (f64, f64)>) -> f64 {
    let (mut s, mut c) = (start, 0.0);
    for (a, b) in terms {
        let p = a * b;
        let pe = a.mul_add(b, -p);
        let t = s + p;
        let z = t - s;
        let se = (s - (t - z)) + (p - z);
        s = t;
        c += pe + se;
    }
    s + c
}

/// A dense LU factorisation with partial pivoting, computed and applied sequentially.
struct DenseLu {
    lu: Mat<f64>,
    /// Row i of P A (= L U) is row `perm[i]` of A.
    perm: Vec<usize>,
}

impl DenseLu {
    /// Factorises `a`; `None` when a pivot is zero or a factor not finite.
    fn new(a: MatRef<'_, f64>) -> Option<Self> {
        use faer::dyn_stack::{MemBuffer, MemStack};
        use faer::linalg::lu::partial_pivoting::factor::{lu_in_place, lu_in_place_scratch};
        let k = a.nrows();
        let mut lu = a.to_owned();
        let (mut perm, mut perm_inv) = (vec![0usize; k], vec![0usize; k]);
        let req = lu_in_place_scratch::<usize, f64>(k, k, Par::Seq, Default::default());
        let mut buf = MemBuffer::try_new(req).ok()?;
        lu_in_place(
            lu.as_mut(),
            &mut perm,
            &mut perm_inv,
            Par::Seq,
            MemStack::new(&mut buf),
            Default::default(),
        );
        let ok = (0..k).all(|i| lu[(i, i)] != 0.0)
            && (0..k).all(|j| lu.col_as_slice(j).iter().all(|x| x.is_finite()));
        ok.then_some(Self { lu, perm })
    }

    /// x ← A⁻¹ x.
    fn solve(&self, x: &mut [f64]) {
        use faer::linalg::triangular_solve::{
            solve_unit_lower_triangular_in_place, solve_upper_triangular_in_place,
        };
        let k = x.len();
        let mut y = Mat::<f64>::from_fn(k, 1, |i, _| x[self.perm[i]]);
        solve_unit_lower_triangular_in_place(self.lu.as_ref(), y.as_mut(), Par::Seq);
        solve_upper_triangular_in_place(self.lu.as_ref(), y.as_mut(), Par::Seq);
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = y[(i, 0)];
        }
    }
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

/// Marker for "w_k is not basic" in [`Basis::w_row`] and "no stored column" in [`Basis::slot`].
const NONE: usize = usize::MAX;

/// Pivots whose rank-1 updates of B⁻¹ are held back and then applied to the stored columns
/// in one matrix product (see [`Basis`]).
const DELAY: usize = 32;

/// Most entering columns computed ahead of need in one pass over the stored columns (see
/// [`Basis`]).
const MAX_AHEAD: usize = 15;

/// The current basis of the augmented system, with B⁻¹ kept explicitly.
///
/// Column k of B⁻¹ is the unit vector e_ρ while w_k is basic in row ρ (nothing is stored). The
/// other columns (nonbasic w's) are stored densely in slots, with the last `pending` rank-1
/// updates held back: (B⁻¹)_{:,k} = S_{:,s} − Σ_t u_t V_{t,s} for k in slot s, where the pivot
/// on row r with entering column d contributed u_t = (d − e_r)/d_r and V_{t,:} = row r of
/// B⁻¹ before that pivot. Every [`DELAY`] pivots S ← S − U V (one matrix product).
///
/// The entering column B⁻¹(−M̂_{:,j}) of a z_j needs S w with w_s = −M̂_{k_s j}: a pass over
/// all stored columns. Each pass also computes S w for up to [`MAX_AHEAD`] guessed future
/// entering z's (one matrix product with several right-hand sides, so the stored columns are
/// read once for all of them): the complements of the basic w's with the next smallest ratios
/// x_i/d_i in the ratio test that triggered the pass. These products are kept current while
/// columns are added, removed and updated (O(n) per product and event), and a guessed z that
/// enters needs no pass. The number of guesses adapts (2h + 1 after h of the previous guesses
/// entered). When contact closes along a front, as on the 2 000-candidate strip, every guess
/// enters in turn and a pass serves 16 pivots.
struct Basis {
    n: usize,
    /// Scaled M̂, column-major: M̂_ij at j·n + i.
    mcol: Vec<f64>,
    /// For each k, the row where w_k is basic (then column k of B⁻¹ is e_row), or NONE.
    w_row: Vec<usize>,
    /// For each k, the slot of its stored column (w_k nonbasic), or NONE.
    slot: Vec<usize>,
    /// The column index k stored in each used slot.
    slot_col: Vec<usize>,
    /// Stored columns S, slot-major: S_{i,s} at s·n + i (capacity n slots).
    stored: Vec<f64>,
    /// Pending u_t, t < `pending`: entry i at t·n + i.
    u: Vec<f64>,
    /// Pending V_{t,s}, slot-major: at s·DELAY + t.
    v: Vec<f64>,
    /// Number of pending updates.
    pending: usize,
    /// Products S w^(j) for the z_j in `ahead_cols` (entry i of the c-th at c·n + i).
    ahead: Vec<f64>,
    /// The z indices j of the products in `ahead`.
    ahead_cols: Vec<usize>,
    /// Guesses made at the next pass.
    guesses: usize,
    /// Guesses of the last pass that entered.
    hits: usize,
    /// Passes over the stored columns so far.
    passes: usize,
    /// Basic values x_B = B⁻¹ q̂.
    x: Vec<f64>,
    /// Basic variable of each row.
    basis: Vec<Var>,
}

impl Basis {
    /// The initial basis B = I (all w basic), x_B = q̂.
    fn new(mcol: Vec<f64>, qhat: &[f64]) -> Self {
        let n = qhat.len();
        Self {
            n,
            mcol,
            w_row: (0..n).collect(),
            slot: vec![NONE; n],
            slot_col: Vec::with_capacity(n),
            stored: vec![0.0; n * n],
            u: vec![0.0; n * DELAY],
            v: vec![0.0; n * DELAY],
            pending: 0,
            ahead: Vec::new(),
            ahead_cols: Vec::new(),
            guesses: 1,
            hits: 0,
            passes: 0,
            x: qhat.to_vec(),
            basis: (0..n).map(Var::W).collect(),
        }
    }

    /// The pending coefficients V_{t,s}, t < `pending`, of slot s.
    fn pending_of(&self, s: usize) -> &[f64] {
        &self.v[s * DELAY..s * DELAY + self.pending]
    }

    /// (B⁻¹)_ik.
    fn entry(&self, i: usize, k: usize) -> f64 {
        match (self.w_row[k], self.slot[k]) {
            (NONE, s) => {
                let mut e = self.stored[s * self.n + i];
                for (t, &vt) in self.pending_of(s).iter().enumerate() {
                    e -= self.u[t * self.n + i] * vt;
                }
                e
            }
            (row, _) => f64::from(u8::from(row == i)),
        }
    }

    /// Column k of B⁻¹ into `out`.
    fn column(&self, k: usize, out: &mut [f64]) {
        let n = self.n;
        match (self.w_row[k], self.slot[k]) {
            (NONE, s) => {
                out.copy_from_slice(&self.stored[s * n..(s + 1) * n]);
                for (t, &vt) in self.pending_of(s).iter().enumerate() {
                    for (o, &ut) in out.iter_mut().zip(&self.u[t * n..(t + 1) * n]) {
                        *o -= ut * vt;
                    }
                }
            }
            (row, _) => {
                out.fill(0.0);
                out[row] = 1.0;
            }
        }
    }

    /// out ← B⁻¹ a given out = S w (w_s = a_{k_s}): adds the unit columns and the pending
    /// updates, out −= Σ_t u_t (V_{t,:} w).
    fn finish(&self, a: impl Fn(usize) -> f64, out: &mut [f64]) {
        for (k, &row) in self.w_row.iter().enumerate() {
            if row != NONE {
                out[row] += a(k);
            }
        }
        self.subtract_pending(a, out);
    }

    /// out −= Σ_t u_t (V_{t,:} w), w_s = a_{k_s}.
    fn subtract_pending(&self, a: impl Fn(usize) -> f64, out: &mut [f64]) {
        let n = self.n;
        if self.pending == 0 {
            return;
        }
        let mut c = [0.0; DELAY];
        for (s, &k) in self.slot_col.iter().enumerate() {
            let w = a(k);
            for (ct, &vt) in c.iter_mut().zip(self.pending_of(s)) {
                *ct += vt * w;
            }
        }
        for (t, &ct) in c[..self.pending].iter().enumerate() {
            if ct != 0.0 {
                for (o, &ut) in out.iter_mut().zip(&self.u[t * n..(t + 1) * n]) {
                    *o -= ut * ct;
                }
            }
        }
    }

    /// out ← B⁻¹ a, with a_k given by `a(k)`.
    fn apply(&self, a: impl Fn(usize) -> f64, out: &mut [f64]) {
        let n = self.n;
        out.fill(0.0);
        let weights: Vec<f64> = self.slot_col.iter().map(|&k| a(k)).collect();
        add_stored_times(&self.stored[..n * weights.len()], &weights, out);
        self.finish(a, out);
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

    /// The z's that may enter after the pivot on row r with entering column d: the
    /// complements of the basic w's in the `count` rows i ≠ r with d_i > 0 and the smallest
    /// ratios x_i / d_i (ties by row), i.e. the rows that would leave next if the basic values
    /// kept decreasing along d.
    fn guess(&self, r: usize, d: &[f64], count: usize) -> Vec<usize> {
        let mut best: Vec<(f64, usize)> = Vec::with_capacity(count + 1);
        for (i, &di) in d.iter().enumerate() {
            if i == r || di <= 0.0 || !matches!(self.basis[i], Var::W(_)) {
                continue;
            }
            let ratio = self.x[i].max(0.0) / di;
            if best.len() == count && best.last().is_some_and(|&(b, _)| ratio >= b) {
                continue;
            }
            let at = best.partition_point(|&(b, _)| b <= ratio);
            best.insert(at, (ratio, i));
            best.truncate(count);
        }
        best.into_iter()
            .filter_map(|(_, i)| match self.basis[i] {
                Var::W(k) => Some(k),
                _ => None,
            })
            .collect()
    }

    /// Adds `sign` · S_{:,s} · (−M̂_{k j}) to each product computed ahead (k the column stored
    /// in slot s, j the product's z).
    fn ahead_add_slot(&mut self, s: usize, sign: f64) {
        let n = self.n;
        let k = self.slot_col[s];
        let col = &self.stored[s * n..(s + 1) * n];
        for (c, &j) in self.ahead_cols.iter().enumerate() {
            let w = -sign * self.mcol[j * n + k];
            for (p, &sv) in self.ahead[c * n..(c + 1) * n].iter_mut().zip(col) {
                *p += sv * w;
            }
        }
    }

    /// Pivots `entering` (with column d = B⁻¹A(entering)) into row r, and writes the column
    /// B⁻¹A(next) of the following entering variable, in the new basis, into `dnext`.
    fn pivot(&mut self, r: usize, d: &[f64], entering: Var, next: Option<Var>, dnext: &mut [f64]) {
        let n = self.n;
        // Guesses for a pass over the stored columns, from this ratio test's x.
        let ahead_at = match next {
            Some(Var::Z(j)) => self.ahead_cols.iter().position(|&c| c == j),
            _ => None,
        };
        let guesses = match (next, ahead_at) {
            (Some(Var::Z(_)), None) => {
                self.guesses = (2 * self.hits + 1).min(MAX_AHEAD);
                self.hits = 0;
                self.guess(r, d, self.guesses)
            }
            _ => Vec::new(),
        };

        let dr = d[r];
        let xr = self.x[r] / dr;
        for (xi, &di) in self.x.iter_mut().zip(d) {
            *xi -= di * xr;
        }
        self.x[r] = xr;

        // The update B⁻¹ ← B⁻¹ − (d − e_r)(row r of B⁻¹)/d_r. Its part in the rows i ≠ r,
        // u = d/d_r with u_r = 0, joins the pending list with V_{t,:} = row r of B⁻¹ (unit
        // columns have 0 there, except the leaving w's, handled below); row r of the new B⁻¹,
        // V_{t,:}/d_r, is written into S at once (exactly, as the pending u's are 0 in row r).
        let t = self.pending;
        let mut ur = [0.0; DELAY];
        for (tt, x) in ur[..t].iter_mut().enumerate() {
            *x = std::mem::take(&mut self.u[tt * n + r]);
        }
        let mut row = Vec::with_capacity(self.slot_col.len());
        for s in 0..self.slot_col.len() {
            let vs = &self.v[s * DELAY..s * DELAY + t];
            let e = self.stored[s * n + r] - vs.iter().zip(&ur).map(|(a, b)| a * b).sum::<f64>();
            self.v[s * DELAY + t] = e;
            self.stored[s * n + r] = e / dr;
            row.push(e / dr);
        }
        let ut = &mut self.u[t * n..(t + 1) * n];
        for (ui, &di) in ut.iter_mut().zip(d) {
            *ui = di / dr;
        }
        ut[r] = 0.0;
        self.pending = t + 1;
        for (c, &j) in self.ahead_cols.iter().enumerate() {
            let a = &self.mcol[j * n..(j + 1) * n];
            let dot: f64 = row.iter().zip(&self.slot_col).map(|(&x, &k)| x * -a[k]).sum();
            self.ahead[c * n + r] = dot;
        }

        // The leaving w's column e_r becomes e_r − (d − e_r)/d_r: stored, with this update
        // applied.
        if let Var::W(j) = self.basis[r] {
            self.w_row[j] = NONE;
            let s = self.slot_col.len();
            self.slot[j] = s;
            self.slot_col.push(j);
            let col = &mut self.stored[s * n..(s + 1) * n];
            for (c, &ui) in col.iter_mut().zip(&self.u[t * n..(t + 1) * n]) {
                *c = -ui;
            }
            col[r] = 1.0 / dr;
            self.v[s * DELAY..(s + 1) * DELAY].fill(0.0);
            self.ahead_add_slot(s, 1.0);
        }
        // The entering w's column becomes e_r: its slot is freed (the last slot moves in).
        if let Var::W(j) = entering {
            let s = self.slot[j];
            self.ahead_add_slot(s, -1.0);
            let last = self.slot_col.len() - 1;
            if s != last {
                self.stored.copy_within(last * n..(last + 1) * n, s * n);
                self.v.copy_within(last * DELAY..(last + 1) * DELAY, s * DELAY);
                let moved = self.slot_col[last];
                self.slot_col[s] = moved;
                self.slot[moved] = s;
            }
            self.slot_col.pop();
            self.slot[j] = NONE;
            self.w_row[j] = r;
        }
        self.basis[r] = entering;
        if self.pending == DELAY {
            self.flush();
        }

        match next {
            Some(Var::Z(j)) => {
                match ahead_at {
                    Some(c) => {
                        dnext.copy_from_slice(&self.ahead[c * n..(c + 1) * n]);
                        self.hits += 1;
                    }
                    None => self.pass(j, &guesses, dnext),
                }
                let a = &self.mcol[j * n..(j + 1) * n];
                self.finish(|k| -a[k], dnext);
            }
            // w_j is nonbasic (z_j just left), so its column is stored.
            Some(Var::W(j)) => self.column(j, dnext),
            _ => {}
        }
    }

    /// One pass over the stored columns: `out` ← S w^(j) and, kept for later, S w^(g) for the
    /// guesses g ≠ j (w^(j)_s = −M̂_{k_s j}).
    fn pass(&mut self, j: usize, guesses: &[usize], out: &mut [f64]) {
        let n = self.n;
        self.passes += 1;
        let mut cols = vec![j];
        cols.extend(guesses.iter().copied().filter(|&g| g != j));
        let slots = self.slot_col.len();
        let w = Mat::<f64>::from_fn(cols.len(), slots, |c, s| {
            -self.mcol[cols[c] * n + self.slot_col[s]]
        });
        let mut prod = Mat::<f64>::zeros(cols.len(), n);
        let stored = MatRef::from_column_major_slice(&self.stored[..n * slots], n, slots);
        matmul(prod.as_mut(), Accum::Replace, w.as_ref(), stored.transpose(), 1.0, Par::Seq);
        out.iter_mut().enumerate().for_each(|(i, o)| *o = prod[(0, i)]);
        self.ahead.clear();
        for c in 1..cols.len() {
            self.ahead.extend((0..n).map(|i| prod[(c, i)]));
        }
        cols.remove(0);
        self.ahead_cols = cols;
    }

    /// Applies the pending updates to the stored columns, S ← S − U V, and to the products
    /// computed ahead.
    fn flush(&mut self) {
        let (n, slots, t) = (self.n, self.slot_col.len(), self.pending);
        if t > 0 && slots > 0 {
            let mut ahead = std::mem::take(&mut self.ahead);
            for (c, &j) in self.ahead_cols.iter().enumerate() {
                let a = &self.mcol[j * n..(j + 1) * n];
                self.subtract_pending(|k| -a[k], &mut ahead[c * n..(c + 1) * n]);
            }
            self.ahead = ahead;
            let u = MatRef::from_column_major_slice(&self.u[..n * t], n, t);
            let v = MatRef::from_column_major_slice_with_stride(&self.v, t, slots, DELAY);
            let s = MatMut::from_column_major_slice_mut(&mut self.stored[..n * slots], n, slots);
            matmul(s, Accum::Add, u, v, -1.0, Par::Seq);
        }
        self.pending = 0;
    }

    /// v ↦ B⁻¹ v.
    fn apply_binv(&self, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        self.apply(|k| v[k], &mut out);
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

/// out += S w for the stored columns S (slot-major, `w.len()` slots of `out.len()` entries),
/// four columns per pass over `out`. Each entry sums its terms in slot order.
fn add_stored_times(stored: &[f64], w: &[f64], out: &mut [f64]) {
    let n = out.len();
    let mut cols = stored.chunks_exact(n).zip(w);
    let mut quads = w.len() / 4;
    while quads > 0 {
        quads -= 1;
        let mut next = || cols.next().map_or((&[][..], 0.0), |(c, &w)| (c, w));
        let ((c0, w0), (c1, w1), (c2, w2), (c3, w3)) = (next(), next(), next(), next());
        for ((((o, &a0), &a1), &a2), &a3) in out.iter_mut().zip(c0).zip(c1).zip(c2).zip(c3) {
            *o += a0 * w0 + a1 * w1 + a2 * w2 + a3 * w3;
        }
    }
    for (c, &wk) in cols {
        for (o, &a) in out.iter_mut().zip(c) {
            *o += a * wk;
        }
    }
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

    /// A positive definite, non-symmetric n×n M (row-major) and a q, pseudo-random.
    fn random_pd(n: usize) -> (Vec<f64>, Vec<f64>) {
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
        (m, q)
    }

    /// Re-runs the pivoting of [`lemke()`] on unscaled data by hand and checks after every
    /// pivot that the maintained B⁻¹ is the inverse of the basis (B · B⁻¹ = I with the columns
    /// A(w_k) = e_k, A(z_k) = −M_{:,k}, A(z0) = −e) and that every entering column computed
    /// ahead equals B⁻¹(−M_{:,j}) computed afresh. Returns the pivots and the passes over the
    /// stored columns.
    fn walk(m: &[f64], q: &[f64]) -> (usize, usize) {
        let n = q.len();
        let mut mcol = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                mcol[j * n + i] = m[i * n + j];
            }
        }
        let mut t = Basis::new(mcol.clone(), q);
        let qmin = q.iter().copied().fold(f64::INFINITY, f64::min);
        let r0 = q.iter().rposition(|&x| x == qmin).unwrap();
        let (mut d, mut dn) = (vec![-1.0; n], vec![0.0; n]);
        let mut entering = Var::Z(r0);
        t.pivot(r0, &d, Var::Z0, Some(entering), &mut dn);
        let mut pivots = 1;
        loop {
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
            assert!(worst < 1e-12, "pivot {pivots}: ‖B B⁻¹ − I‖max = {worst:e}");
            for (c, &j) in t.ahead_cols.iter().enumerate() {
                let a = &mcol[j * n..(j + 1) * n];
                let mut ahead = t.ahead[c * n..(c + 1) * n].to_vec();
                t.finish(|k| -a[k], &mut ahead);
                let fresh = t.apply_binv(&a.iter().map(|x| -x).collect::<Vec<_>>());
                let err = ahead.iter().zip(&fresh).fold(0.0_f64, |e, (x, y)| e.max((x - y).abs()));
                assert!(err < 1e-12 * max_abs(&fresh).max(1.0), "pivot {pivots}, z{j}: {err:e}");
            }
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
        (pivots, t.passes)
    }

    #[test]
    fn inverse_stays_consistent() {
        // A 100×100 positive definite, non-symmetric M (more pivots than DELAY): Lemke must
        // solve it with tiny residuals, and B⁻¹ and the columns computed ahead stay exact.
        let (m, q) = random_pd(100);
        let lcp = Lcp::new(100, m.clone(), q.clone()).unwrap();
        let s = lemke(&lcp, &LemkeParams::default()).unwrap();
        assert!(s.residuals.max_violation() < 1e-13, "{:?}", s.residuals);
        let (pivots, passes) = walk(&m, &q);
        assert_eq!(pivots, s.pivots);
        assert!(passes < pivots, "{passes} passes for {pivots} pivots");
        // Murty's example: z's leave and w's enter again (stored columns removed), 128 pivots.
        let (rows, q) = murty(7);
        let m: Vec<f64> = rows.concat();
        assert_eq!(walk(&m, &q).0, 128);
    }

    #[test]
    fn polish_reaches_the_closed_set_solution_of_an_ill_conditioned_lcp() {
        // M = A + A_skew with eigenvalues of its symmetric part spread over 10⁻⁷ … 1 (a
        // Hilbert-like decay), q mixed: many pivots, closed and open candidates.
        let n = 60;
        let (r, q) = random_pd(n);
        let mut m = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let (di, dj) = (
                    10f64.powf(-7.0 * i as f64 / n as f64),
                    10f64.powf(-7.0 * j as f64 / n as f64),
                );
                m[i * n + j] = r[i * n + j] * (di * dj).sqrt();
            }
        }
        let lcp = Lcp::new(n, m.clone(), q).unwrap();
        let mut sol = lemke(&lcp, &LemkeParams::default()).unwrap();
        let lemke_z = sol.z.clone();
        let record = polish(&lcp, &mut sol);
        assert!(record.closed > 0 && record.closed < n, "{record:?}");
        assert!(record.accepted && record.residual_after < record.residual_before, "{record:?}");
        // Same closed set; the polished z solves the closed rows to the compensated
        // residual's accuracy and the open rows' w stay nonnegative.
        for (a, b) in lemke_z.iter().zip(&sol.z) {
            assert_eq!(*a > 0.0, *b > 0.0);
        }
        let w = accurate_w(&lcp, &sol.z);
        let scale = sol.residuals.scale;
        for (&zi, &wi) in sol.z.iter().zip(&w) {
            assert!(zi >= 0.0);
            if zi > 0.0 {
                assert!(wi.abs() <= 1e-20 * scale, "closed gap {wi:e}");
            } else {
                assert!(wi >= 0.0, "open gap {wi:e}");
            }
        }
    }

    #[test]
    fn polish_keeps_the_answer_when_the_closed_set_is_wrong() {
        // The solution of M = [[2, 1], [1, 2]], q = (−1, 1) is z = (1/2, 0); an answer that
        // calls candidate 2 closed gives z = (1, −1) on that set: refused, answer kept.
        let lcp = Lcp::from_rows(&[vec![2.0, 1.0], vec![1.0, 2.0]], vec![-1.0, 1.0]).unwrap();
        let z = vec![0.5, 1e-3];
        let w = lcp.w(&z);
        let residuals = lcp.residuals_with_w(&z, &w);
        let mut sol = LcpSolution { z: z.clone(), w: w.clone(), pivots: 2, residuals };
        let record = polish(&lcp, &mut sol);
        assert_eq!(record.closed, 2);
        assert!(!record.accepted);
        assert_eq!((sol.z, sol.w), (z, w));
        // Nothing to polish: z = 0.
        let mut zero =
            lemke(&Lcp::from_rows(&[vec![1.0]], vec![1.0]).unwrap(), &LemkeParams::default())
                .unwrap();
        let record = polish(&Lcp::from_rows(&[vec![1.0]], vec![1.0]).unwrap(), &mut zero);
        assert_eq!((record.closed, record.accepted), (0, false));
    }

    #[test]
    fn compensated_dot_product() {
        let terms = [(1.0, 1e16), (1.0, 1.0), (1.0, -1e16)];
        assert_eq!(terms.iter().map(|(a, b)| a * b).sum::<f64>(), 0.0);
        assert_eq!(dot2(0.0, terms.into_iter()), 1.0);
        assert_eq!(dot2(0.5, [(3.0, 0.1)].into_iter()), 0.5 + 3.0 * 0.1);
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
