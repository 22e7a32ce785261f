//! One quasi-static step of 2-D Coulomb friction on the condensed contact problem
//! (docs/method.md §8), independent of the discretisation:
//!
//! ```text
//! g = q_n + M_nn P + M_nt T,     s = q_t + M_tn P + M_tt T,     Δs = s − s_prev,
//! 0 ≤ P ⊥ g ≥ 0,   |T| ≤ μ P,   |T| < μ P ⇒ Δs = 0,   Δs ≠ 0 ⇒ T = −μ P Δs/|Δs|.
//! ```
//!
//! [`solve_step`] tries Lemke on the Stewart–Trinkle LCP of the step (3m unknowns `P`,
//! `a = T + μP`, `λ`); when that fails (the matrix is not a P-matrix: Lemke may end on a ray)
//! or its answer does not meet the residual tolerance, it runs Panagiotopoulos' fixed point
//! (normal LCP with `T` frozen, Tresca problem with `P` frozen) and finishes with an exact
//! active-set step. The answer says which method produced it; no answer meeting the
//! tolerance is an error ([`LcpError::FrictionNotConverged`]).

use super::{Lcp, LcpError, LcpSolution, LemkeParams, Polish, lemke, lemke_observed};
use faer::Mat;
use faer::linalg::solvers::Solve;
use serde::Serialize;

/// Scaled residual below which a step's answer is accepted (docs/method.md §8).
pub const FRICTION_TOLERANCE: f64 = 1e-9;
/// Lemke's pivot tolerance for the second try on the step LCP when the first answer (at
/// [`LemkeParams::default`]'s 1e-11) misses the tolerance: on the Q2 beam at h = 0.25
/// (3m = 1152) the first increment's answer had residual 4.7e-5 at 1e-11, 7e-3 at 1e-13 and
/// 7e-16 at 1e-9 and 1e-7 (near-zero pivots accepted).
pub const STRICT_PIVOT_TOLERANCE: f64 = 1e-9;
/// Rounds of the fixed point at most.
const MAX_FIXED_POINT: usize = 100;
/// Rounds of the active-set step at most.
const MAX_ACTIVE_SET: usize = 50;
/// Fixed-point rounds between two tries of a short active-set step (at most
/// `SHORT_ACTIVE_SET` rounds) that ends the iteration when it meets the tolerance: the fixed
/// point converges linearly, the active-set step finishes as soon as the sets are right.
const ACTIVE_SET_EVERY: usize = 10;
/// Rounds of the intermediate active-set tries.
const SHORT_ACTIVE_SET: usize = 5;

/// One frictional step on `m` candidates; the blocks are row-major `m × m`.
#[derive(Clone, Debug)]
pub struct FrictionProblem {
    /// `M_nn`: gap per unit normal force.
    pub nn: Vec<f64>,
    /// `M_nt`: gap per unit tangential force.
    pub nt: Vec<f64>,
    /// `M_tn`: tangential displacement per unit normal force.
    pub tn: Vec<f64>,
    /// `M_tt`: tangential displacement per unit tangential force.
    pub tt: Vec<f64>,
    /// `q_n`: gaps without contact forces.
    pub free_gap: Vec<f64>,
    /// `q_t`: tangential displacements without contact forces.
    pub free_tangential: Vec<f64>,
    /// `s_prev`: tangential displacements at the end of the previous step (zero before the
    /// first).
    pub previous_tangential: Vec<f64>,
    /// `μ_c ≥ 0` per candidate (0 makes a candidate frictionless).
    pub friction: Vec<f64>,
}

/// The state of a candidate at the end of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactState {
    /// `P = 0`.
    Open,
    /// Closed, no slip increment, `|T| ≤ μP`.
    Stick,
    /// Closed, slipping along `+t` (`Δs > 0`, `T = −μP`).
    SlipPositive,
    /// Closed, slipping along `−t` (`Δs < 0`, `T = +μP`).
    SlipNegative,
}

impl ContactState {
    /// `"open"`, `"stick"`, `"slip+"`, `"slip-"` (the `contact.csv` column).
    pub fn label(self) -> &'static str {
        match self {
            Self::Open => "open",
            Self::Stick => "stick",
            Self::SlipPositive => "slip+",
            Self::SlipNegative => "slip-",
        }
    }
    /// Whether the candidate slips.
    pub fn is_slip(self) -> bool {
        matches!(self, Self::SlipPositive | Self::SlipNegative)
    }
}

/// Which method produced a step's answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrictionMethod {
    /// Every `μ_c = 0`: the normal LCP alone, by Lemke (the frictionless computation).
    Frictionless,
    /// Lemke on the Stewart–Trinkle LCP of the step.
    Lemke,
    /// Panagiotopoulos' fixed point finished by the exact active-set step.
    FixedPointActiveSet,
    /// Lemke's answer missed the tolerance; Lemke again with the stricter pivot tolerance
    /// [`STRICT_PIVOT_TOLERANCE`], which skips the near-zero pivots that spoiled it, answered.
    LemkeStrictPivots,
    /// The active-set method on the sparse system, without the blocks (docs/method.md
    /// §5.1, `lcp::active_set::solve_friction_step`).
    ActiveSet,
}

/// The scaled residuals of a step's answer (docs/method.md §8). `F = max(‖P‖∞, ‖T‖∞)` (1 when
/// both vanish) and `U = max(‖q_n‖∞, ‖q_t − s_prev‖∞, max|M| F)`.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct FrictionResiduals {
    /// `max(−min P, 0) / F`.
    pub negative_force: f64,
    /// `max(−min g, 0) / U`.
    pub penetration: f64,
    /// `max |P g| / (F U)`.
    pub normal_complementarity: f64,
    /// `max (|T| − μP)⁺ / F`.
    pub cone: f64,
    /// `max(max(T Δs, 0), min((μP − |T|)⁺, F) |Δs|) / (F U)`: slip opposite to `T`, only on
    /// the cone.
    pub friction_complementarity: f64,
    /// `F`.
    pub force_scale: f64,
    /// `U`.
    pub displacement_scale: f64,
}

impl FrictionResiduals {
    /// The largest of the five residuals.
    pub fn max(&self) -> f64 {
        self.negative_force
            .max(self.penetration)
            .max(self.normal_complementarity)
            .max(self.cone)
            .max(self.friction_complementarity)
    }
}

/// The answer of one step.
#[derive(Clone, Debug)]
pub struct FrictionSolution {
    /// Normal forces `P ≥ 0`.
    pub normal: Vec<f64>,
    /// Tangential forces `T` (on the body, along `t`).
    pub tangential: Vec<f64>,
    /// Gaps `g = q_n + M_nn P + M_nt T`.
    pub gap: Vec<f64>,
    /// Tangential displacements `s = q_t + M_tn P + M_tt T` (the next step's `s_prev`).
    pub tangential_displacement: Vec<f64>,
    /// Slip increments `Δs = s − s_prev`.
    pub slip_increment: Vec<f64>,
    /// State per candidate.
    pub state: Vec<ContactState>,
    /// Residuals of the answer.
    pub residuals: FrictionResiduals,
    /// Which method produced it.
    pub method: FrictionMethod,
    /// Lemke pivots (of the step LCP, or summed over the fixed point's LCPs).
    pub pivots: usize,
    /// Fixed-point rounds plus active-set rounds (0 for Lemke).
    pub iterations: usize,
    /// Why Lemke on the step LCP was not accepted, when it was not.
    pub lemke_failure: Option<String>,
}

impl FrictionProblem {
    /// Number of candidates `m`.
    pub fn size(&self) -> usize {
        self.free_gap.len()
    }

    fn check(&self) -> Result<(), LcpError> {
        let m = self.size();
        let blocks =
            [("M_nn", &self.nn), ("M_nt", &self.nt), ("M_tn", &self.tn), ("M_tt", &self.tt)];
        // A normal-only step (every μ = 0) may leave the tangential blocks empty.
        let normal_only = self.is_frictionless();
        for (what, b) in blocks {
            if b.len() != m * m && !(normal_only && what != "M_nn" && b.is_empty()) {
                return Err(LcpError::DimensionMismatch { what, expected: m * m, found: b.len() });
            }
        }
        let vectors = [
            ("q_t", &self.free_tangential),
            ("s_prev", &self.previous_tangential),
            ("μ", &self.friction),
        ];
        for (what, v) in vectors {
            if v.len() != m {
                return Err(LcpError::DimensionMismatch { what, expected: m, found: v.len() });
            }
        }
        for (what, v) in blocks.into_iter().chain([("q_n", &self.free_gap)]).chain(vectors) {
            if let Some(index) = v.iter().position(|x| !x.is_finite()) {
                return Err(LcpError::NonFinite { what, index });
            }
        }
        if let Some(index) = self.friction.iter().position(|&mu| mu < 0.0) {
            return Err(LcpError::NonFinite { what: "μ (negative)", index });
        }
        Ok(())
    }

    /// Whether every `μ_c` is 0.
    pub fn is_frictionless(&self) -> bool {
        self.friction.iter().all(|&mu| mu == 0.0)
    }

    /// `(g, s)` for forces `(P, T)` (an empty block counts as zero: a normal-only step).
    pub fn response(&self, p: &[f64], t: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let m = self.size();
        let product = |a: &[f64], x: &[f64], i: usize| match a.is_empty() {
            true => None,
            false => Some(a[i * m..(i + 1) * m].iter().zip(x).map(|(x, y)| x * y).sum::<f64>()),
        };
        let row = |a: &[f64], b: &[f64], q: f64, i: usize| {
            let mut v = q;
            for part in [product(a, p, i), product(b, t, i)].into_iter().flatten() {
                v += part;
            }
            v
        };
        let g = (0..m).map(|i| row(&self.nn, &self.nt, self.free_gap[i], i)).collect();
        let s = (0..m).map(|i| row(&self.tn, &self.tt, self.free_tangential[i], i)).collect();
        (g, s)
    }

    /// The scaled residuals of forces `(P, T)` (see [`FrictionResiduals`]).
    pub fn residuals(&self, p: &[f64], t: &[f64]) -> FrictionResiduals {
        let (g, s) = self.response(p, t);
        let inf = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let f = inf(p).max(inf(t));
        let f = if f > 0.0 { f } else { 1.0 };
        let ds: Vec<f64> = s.iter().zip(&self.previous_tangential).map(|(a, b)| a - b).collect();
        let dq: Vec<f64> = self
            .free_tangential
            .iter()
            .zip(&self.previous_tangential)
            .map(|(a, b)| a - b)
            .collect();
        let max_m = inf(&self.nn).max(inf(&self.nt)).max(inf(&self.tn)).max(inf(&self.tt));
        let u = inf(&self.free_gap).max(inf(&dq)).max(max_m * f).max(f64::MIN_POSITIVE);
        let mut r =
            FrictionResiduals { force_scale: f, displacement_scale: u, ..Default::default() };
        for c in 0..self.size() {
            let (pc, tc, mu) = (p[c], t[c], self.friction[c]);
            r.negative_force = r.negative_force.max(-pc / f);
            r.penetration = r.penetration.max(-g[c] / u);
            r.normal_complementarity = r.normal_complementarity.max((pc * g[c]).abs() / (f * u));
            r.cone = r.cone.max((tc.abs() - mu * pc.max(0.0)) / f);
            // The slack of the cone counts up to F only: a huge μ must not amplify round-off
            // in the Δs of a sticking candidate.
            let slack = (mu * pc - tc.abs()).clamp(0.0, f);
            let fc = (tc * ds[c]).max(0.0).max(slack * ds[c].abs());
            r.friction_complementarity = r.friction_complementarity.max(fc / (f * u));
        }
        r
    }

    /// The full answer for forces `(P, T)`.
    fn answer(
        &self,
        p: Vec<f64>,
        t: Vec<f64>,
        method: FrictionMethod,
        pivots: usize,
        iterations: usize,
    ) -> FrictionSolution {
        let residuals = self.residuals(&p, &t);
        let (gap, s) = self.response(&p, &t);
        let ds: Vec<f64> = s.iter().zip(&self.previous_tangential).map(|(a, b)| a - b).collect();
        let state = classify(&p, &ds, residuals.displacement_scale);
        FrictionSolution {
            normal: p,
            tangential: t,
            gap,
            tangential_displacement: s,
            slip_increment: ds,
            state,
            residuals,
            method,
            pivots,
            iterations,
            lemke_failure: None,
        }
    }
}

/// The state of each candidate from its normal force `p` and slip increment `ds`: open
/// without force, stick when the slip increment is round-off (`|Δs| ≤ 1e-10 u`, `u` the
/// problem's displacement scale; also without friction, e.g. a candidate held tangentially by
/// a support), else slip in the direction of `Δs`.
pub(crate) fn classify(p: &[f64], ds: &[f64], displacement_scale: f64) -> Vec<ContactState> {
    p.iter()
        .zip(ds)
        .map(|(&p, &ds)| {
            if p <= 0.0 {
                ContactState::Open
            } else if ds.abs() <= 1e-10 * displacement_scale {
                ContactState::Stick
            } else if ds >= 0.0 {
                ContactState::SlipPositive
            } else {
                ContactState::SlipNegative
            }
        })
        .collect()
}

/// Solves one frictional step (docs/method.md §8): with every `μ_c = 0`, Lemke on the normal
/// LCP `(M_nn, q_n)` alone (bit for bit the frictionless computation); otherwise Lemke on the
/// step LCP; if its answer misses [`FRICTION_TOLERANCE`], Lemke again with the stricter
/// [`STRICT_PIVOT_TOLERANCE`]; if that misses too, or Lemke fails, the fixed point finished
/// by the active-set step.
///
/// # Errors
/// [`LcpError::DimensionMismatch`] / [`LcpError::NonFinite`] for malformed data (a negative
/// `μ` included); the frictionless path's Lemke errors; [`LcpError::FrictionNotConverged`]
/// when neither method reaches the tolerance.
pub fn solve_step(problem: &FrictionProblem) -> Result<FrictionSolution, LcpError> {
    problem.check()?;
    let params = LemkeParams::default();
    if problem.is_frictionless() {
        return frictionless(problem, &params, &mut |_, _| {}).map(|f| f.step);
    }
    let lemke_failure = match step_lcp_lemke(problem, &params) {
        Ok(sol) if sol.residuals.max() <= FRICTION_TOLERANCE => return Ok(sol),
        Ok(sol) => {
            // Inaccurate rather than failed: near-zero pivots; Lemke again with a stricter
            // pivot tolerance, far cheaper than the fixed point's LCPs.
            let why = format!("Lemke's answer has residual {:.3e}", sol.residuals.max());
            let strict =
                LemkeParams { pivot_tolerance: STRICT_PIVOT_TOLERANCE, ..LemkeParams::default() };
            match step_lcp_lemke(problem, &strict) {
                Ok(mut again) if again.residuals.max() <= FRICTION_TOLERANCE => {
                    again.method = FrictionMethod::LemkeStrictPivots;
                    again.pivots += sol.pivots;
                    again.lemke_failure = Some(why);
                    return Ok(again);
                }
                Ok(again) => format!(
                    "{why} (pivot tolerance {STRICT_PIVOT_TOLERANCE:e}: {:.3e})",
                    again.residuals.max()
                ),
                Err(e) => format!("{why} (pivot tolerance {STRICT_PIVOT_TOLERANCE:e}: {e})"),
            }
        }
        Err(e) => e.to_string(),
    };
    // The fixed point in chunks of ACTIVE_SET_EVERY rounds, each followed by a short
    // active-set try; the last (converged, stalled or at MAX_FIXED_POINT) by the full one.
    let m = problem.size();
    let (mut p, mut t) = (vec![0.0; m], vec![0.0; m]);
    let (mut pivots, mut rounds) = (0, 0);
    let mut fixed_point_change: f64;
    let (sol, active_rounds) = loop {
        let chunk = ACTIVE_SET_EVERY.min(MAX_FIXED_POINT - rounds);
        let (p1, t1, piv, r, change) = fixed_point(problem, &params, p, t, chunk);
        (p, t) = (p1, t1);
        pivots += piv;
        rounds += r;
        fixed_point_change = change;
        let last = r < chunk || rounds >= MAX_FIXED_POINT;
        let limit = if last { MAX_ACTIVE_SET } else { SHORT_ACTIVE_SET };
        let (pa, ta, ar) = active_set(problem, p.clone(), t.clone(), limit);
        let sol = problem.answer(pa, ta, FrictionMethod::FixedPointActiveSet, pivots, rounds + ar);
        if last || sol.residuals.max() <= FRICTION_TOLERANCE {
            break (sol, ar);
        }
    };
    let mut sol = sol;
    sol.lemke_failure = Some(lemke_failure.clone());
    let residual = sol.residuals.max();
    if residual <= FRICTION_TOLERANCE {
        Ok(sol)
    } else {
        Err(LcpError::FrictionNotConverged {
            fixed_point_rounds: rounds,
            active_set_rounds: active_rounds,
            residual,
            fixed_point_change,
            lemke: lemke_failure,
        })
    }
}

/// A frictionless step's answer with the normal LCP's own: Lemke's `(z, w)`, its residuals
/// and pivots.
#[derive(Clone, Debug)]
pub struct FrictionlessStep {
    /// The step's answer (`T = 0`).
    pub step: FrictionSolution,
    /// The normal LCP `(M_nn, q_n)`'s answer, as Lemke gave it.
    pub lcp: LcpSolution,
}

impl FrictionlessStep {
    /// Polishes the normal answer on its closed set ([`super::polish`]); when the polish is
    /// accepted, the step's answer becomes the polished forces'.
    ///
    /// # Errors
    /// As [`Lcp::new`] for `problem`'s `(M_nn, q_n)`.
    pub fn polish(&mut self, problem: &FrictionProblem) -> Result<Polish, LcpError> {
        let m = problem.size();
        let lcp = Lcp::new(m, problem.nn.clone(), problem.free_gap.clone())?;
        let record = super::polish(&lcp, &mut self.lcp);
        if record.accepted {
            let (z, t) = (self.lcp.z.clone(), vec![0.0; m]);
            self.step = problem.answer(z, t, FrictionMethod::Frictionless, self.lcp.pivots, 0);
        }
        Ok(record)
    }
}

/// A step with every `μ_c = 0`: Lemke on LCP `(M_nn, q_n)` alone with `params` (reporting
/// `(pivots, expected)` to `progress`). The tangential blocks may be empty (a normal-only
/// step: `s = q_t`).
///
/// # Errors
/// As [`solve_step`]; [`LcpError::InvalidParameter`] when a `μ_c` is not 0.
pub fn solve_frictionless_step(
    problem: &FrictionProblem,
    params: &LemkeParams,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<FrictionlessStep, LcpError> {
    problem.check()?;
    if let Some(&mu) = problem.friction.iter().find(|&&mu| mu != 0.0) {
        return Err(LcpError::InvalidParameter {
            what: "friction of a frictionless step",
            value: mu,
        });
    }
    frictionless(problem, params, progress)
}

/// [`solve_frictionless_step`] on checked data.
fn frictionless(
    problem: &FrictionProblem,
    params: &LemkeParams,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<FrictionlessStep, LcpError> {
    let m = problem.size();
    let lcp = Lcp::new(m, problem.nn.clone(), problem.free_gap.clone())?;
    let r = lemke_observed(&lcp, params, progress)?;
    let t = vec![0.0; m];
    let step = problem.answer(r.z.clone(), t, FrictionMethod::Frictionless, r.pivots, 0);
    Ok(FrictionlessStep { step, lcp: r })
}

/// Lemke on the Stewart–Trinkle LCP: `z = (P, a, λ)`, `w = (g, Δs + λ, 2μP − a)` with
/// `T = a − μP` (docs/method.md §8).
fn step_lcp_lemke(
    problem: &FrictionProblem,
    params: &LemkeParams,
) -> Result<FrictionSolution, LcpError> {
    let m = problem.size();
    let n = 3 * m;
    let mu = &problem.friction;
    let mut a = vec![0.0; n * n];
    for i in 0..m {
        for j in 0..m {
            let (nt, tt) = (problem.nt[i * m + j], problem.tt[i * m + j]);
            a[i * n + j] = problem.nn[i * m + j] - mu[j] * nt;
            a[i * n + m + j] = nt;
            a[(m + i) * n + j] = problem.tn[i * m + j] - mu[j] * tt;
            a[(m + i) * n + m + j] = tt;
        }
        a[(m + i) * n + 2 * m + i] = 1.0;
        a[(2 * m + i) * n + i] = 2.0 * mu[i];
        a[(2 * m + i) * n + m + i] = -1.0;
    }
    let mut q = problem.free_gap.clone();
    q.extend(problem.free_tangential.iter().zip(&problem.previous_tangential).map(|(a, b)| a - b));
    q.extend(std::iter::repeat_n(0.0, m));
    let r = lemke(&Lcp::new(n, a, q)?, params)?;
    let p = r.z[..m].to_vec();
    let t = (0..m).map(|c| r.z[m + c] - mu[c] * p[c]).collect();
    Ok(problem.answer(p, t, FrictionMethod::Lemke, r.pivots, 0))
}

/// Panagiotopoulos' fixed point from `(P, T)`: the normal LCP with `T` frozen, then the
/// Tresca problem with `P` frozen, until both change by less than 1e-12 of their size (at
/// most `max_rounds` rounds). Returns `(P, T, pivots, rounds, last relative change)`; a
/// failed inner LCP ends the iteration with the last iterate (rounds < `max_rounds` then, as
/// on convergence).
fn fixed_point(
    problem: &FrictionProblem,
    params: &LemkeParams,
    mut p: Vec<f64>,
    mut t: Vec<f64>,
    max_rounds: usize,
) -> (Vec<f64>, Vec<f64>, usize, usize, f64) {
    let m = problem.size();
    let mu = &problem.friction;
    let (mut pivots, mut change) = (0, f64::INFINITY);
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let dot = |row: &[f64], x: &[f64]| row.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
    for round in 1..=max_rounds {
        // Normal LCP: g = (q_n + M_nt T) + M_nn P.
        let q: Vec<f64> = (0..m)
            .map(|i| problem.free_gap[i] + dot(&problem.nt[i * m..(i + 1) * m], &t))
            .collect();
        let Ok(normal) = Lcp::new(m, problem.nn.clone(), q).and_then(|l| lemke(&l, params)) else {
            return (p, t, pivots, round, change);
        };
        pivots += normal.pivots;
        let p_new = normal.z;
        // Tresca: z = (a, λ), a = T + μP, w = (Δs + λ, 2μP − a), matrix [[M_tt, I], [−I, 0]].
        let n = 2 * m;
        let mut a = vec![0.0; n * n];
        let mut q = vec![0.0; n];
        for i in 0..m {
            let row = &problem.tt[i * m..(i + 1) * m];
            a[i * n..i * n + m].copy_from_slice(row);
            a[i * n + m + i] = 1.0;
            a[(m + i) * n + i] = -1.0;
            let mu_p: Vec<f64> = (0..m).map(|j| mu[j] * p_new[j]).collect();
            q[i] = problem.free_tangential[i] - problem.previous_tangential[i]
                + dot(&problem.tn[i * m..(i + 1) * m], &p_new)
                - dot(row, &mu_p);
            q[m + i] = 2.0 * mu[i] * p_new[i];
        }
        let Ok(tresca) = Lcp::new(n, a, q).and_then(|l| lemke(&l, params)) else {
            return (p_new, t, pivots, round, change);
        };
        pivots += tresca.pivots;
        let t_new: Vec<f64> = (0..m).map(|c| tresca.z[c] - mu[c] * p_new[c]).collect();
        let size = inf(&p_new).max(inf(&t_new)).max(f64::MIN_POSITIVE);
        let dp: Vec<f64> = p_new.iter().zip(&p).map(|(a, b)| a - b).collect();
        let dt: Vec<f64> = t_new.iter().zip(&t).map(|(a, b)| a - b).collect();
        change = inf(&dp).max(inf(&dt)) / size;
        p = p_new;
        t = t_new;
        if change <= 1e-12 {
            return (p, t, pivots, round, change);
        }
    }
    (p, t, pivots, max_rounds, change)
}

/// The forces `(P, T)` of fixed states (docs/method.md §8): the 2m linear conditions "open:
/// `P = T = 0`; closed: `g = 0` and stick: `Δs = 0` (with `μ_c > 0`), slip±: `T = ∓μP`
/// (`T = 0` with `μ_c = 0`)", one dense LU. `fixed[c] = Some((P, T))` prescribes a
/// candidate's forces instead; `free = (q_n, q_t)` and `previous = s_prev` are the right-hand
/// sides (zeros give the response to the prescribed forces alone). `None` when the system is
/// singular (a non-finite solution). Serves the exact active-set step here and the dense
/// frictional system of `lcp::active_set`.
pub(crate) fn solve_states(
    problem: &FrictionProblem,
    states: &[ContactState],
    fixed: &[Option<(f64, f64)>],
    free: (&[f64], &[f64]),
    previous: &[f64],
) -> Option<(Vec<f64>, Vec<f64>)> {
    let m = problem.size();
    let mu = &problem.friction;
    let (qn, qt) = free;
    let n = 2 * m;
    let mut a = Mat::<f64>::zeros(n, n);
    let mut b = Mat::<f64>::zeros(n, 1);
    for c in 0..m {
        if let Some((pf, tf)) = fixed[c] {
            a[(c, c)] = 1.0;
            a[(m + c, m + c)] = 1.0;
            b[(c, 0)] = pf;
            b[(m + c, 0)] = tf;
            continue;
        }
        match states[c] {
            ContactState::Open => {
                a[(c, c)] = 1.0;
                a[(m + c, m + c)] = 1.0;
            }
            closed => {
                for j in 0..m {
                    a[(c, j)] = problem.nn[c * m + j];
                    a[(c, m + j)] = problem.nt[c * m + j];
                }
                b[(c, 0)] = -qn[c];
                match closed {
                    ContactState::Stick if mu[c] > 0.0 => {
                        for j in 0..m {
                            a[(m + c, j)] = problem.tn[c * m + j];
                            a[(m + c, m + j)] = problem.tt[c * m + j];
                        }
                        b[(m + c, 0)] = previous[c] - qt[c];
                    }
                    // T = −μP (slip+), T = +μP (slip−); T = 0 when μ = 0.
                    ContactState::SlipPositive | ContactState::Stick => {
                        a[(m + c, m + c)] = 1.0;
                        a[(m + c, c)] = mu[c];
                    }
                    _ => {
                        a[(m + c, m + c)] = 1.0;
                        a[(m + c, c)] = -mu[c];
                    }
                }
            }
        }
    }
    let x = a.partial_piv_lu().solve(&b);
    if (0..n).any(|i| !x[(i, 0)].is_finite()) {
        return None;
    }
    Some(((0..m).map(|c| x[(c, 0)]).collect(), (0..m).map(|c| x[(m + c, 0)]).collect()))
}

/// The exact active-set step from forces `(P, T)`: solve the linear conditions of the current
/// open / stick / slip± sets, move every candidate whose sign condition fails, repeat (at most
/// `max_rounds` rounds). Returns the last forces and the rounds made.
fn active_set(
    problem: &FrictionProblem,
    p0: Vec<f64>,
    t0: Vec<f64>,
    max_rounds: usize,
) -> (Vec<f64>, Vec<f64>, usize) {
    let m = problem.size();
    let mu = &problem.friction;
    let start = problem.answer(p0.clone(), t0.clone(), FrictionMethod::FixedPointActiveSet, 0, 0);
    let mut state = start.state;
    let (mut p, mut t) = (p0, t0);
    let r0 = problem.residuals(&p, &t);
    let (fs, us) = (r0.force_scale, r0.displacement_scale);
    let (tol_f, tol_u) = (1e-13 * fs, 1e-13 * us);
    for round in 1..=max_rounds {
        let free = (&problem.free_gap[..], &problem.free_tangential[..]);
        let Some(forces) =
            solve_states(problem, &state, &vec![None; m], free, &problem.previous_tangential)
        else {
            return (p, t, round);
        };
        (p, t) = forces;
        for c in 0..m {
            if state[c] == ContactState::Open {
                p[c] = 0.0;
                t[c] = 0.0;
            }
        }
        let (g, s) = problem.response(&p, &t);
        let mut moved = false;
        for c in 0..m {
            let ds = s[c] - problem.previous_tangential[c];
            let bound = mu[c] * p[c];
            let next = match state[c] {
                ContactState::Open if g[c] < -tol_u => ContactState::Stick,
                ContactState::Open => ContactState::Open,
                _ if p[c] < -tol_f => ContactState::Open,
                _ if mu[c] == 0.0 => state[c],
                ContactState::Stick if t[c] > bound + tol_f => ContactState::SlipNegative,
                ContactState::Stick if t[c] < -bound - tol_f => ContactState::SlipPositive,
                ContactState::SlipPositive if ds < -tol_u => ContactState::Stick,
                ContactState::SlipNegative if ds > tol_u => ContactState::Stick,
                other => other,
            };
            moved |= next != state[c];
            state[c] = next;
        }
        if !moved {
            for v in p.iter_mut() {
                *v = v.max(0.0);
            }
            return (p, t, round);
        }
    }
    (p, t, max_rounds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;

    fn uniform(rng: &mut SplitMix64, a: f64, b: f64) -> f64 {
        a + (b - a) * rng.uniform()
    }

    fn one(nn: f64, nt: f64, tn: f64, tt: f64, qn: f64, qt: f64, mu: f64) -> FrictionProblem {
        FrictionProblem {
            nn: vec![nn],
            nt: vec![nt],
            tn: vec![tn],
            tt: vec![tt],
            free_gap: vec![qn],
            free_tangential: vec![qt],
            previous_tangential: vec![0.0],
            friction: vec![mu],
        }
    }

    /// A random problem whose 2m × 2m compliance `[[M_nn, M_nt], [M_tn, M_tt]]` has a positive
    /// definite symmetric part (`B Bᵀ + m I` plus a small skew part).
    fn random_problem(rng: &mut SplitMix64, m: usize, mu: f64) -> FrictionProblem {
        let n = 2 * m;
        let b: Vec<f64> = (0..n * n).map(|_| uniform(rng, -1.0, 1.0)).collect();
        let mut full = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let bb: f64 = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum();
                full[i * n + j] = bb / n as f64 + if i == j { 1.0 } else { 0.0 };
            }
        }
        for i in 0..n {
            for j in 0..i {
                let s = 0.05 * uniform(rng, -1.0, 1.0);
                full[i * n + j] += s;
                full[j * n + i] -= s;
            }
        }
        let block = |r: usize, c: usize| {
            let mut out = vec![0.0; m * m];
            for i in 0..m {
                for j in 0..m {
                    out[i * m + j] = full[(r * m + i) * n + c * m + j];
                }
            }
            out
        };
        FrictionProblem {
            nn: block(0, 0),
            nt: block(0, 1),
            tn: block(1, 0),
            tt: block(1, 1),
            free_gap: (0..m).map(|_| uniform(rng, -1.0, 0.5)).collect(),
            free_tangential: (0..m).map(|_| uniform(rng, -1.0, 1.0)).collect(),
            previous_tangential: (0..m).map(|_| uniform(rng, -0.2, 0.2)).collect(),
            friction: vec![mu; m],
        }
    }

    #[test]
    fn zero_friction_is_the_frictionless_lcp_bit_for_bit() {
        let mut rng = SplitMix64::new(7);
        let mut problem = random_problem(&mut rng, 12, 0.0);
        problem.friction = vec![0.0; 12];
        let sol = solve_step(&problem).unwrap();
        let lcp = Lcp::new(12, problem.nn.clone(), problem.free_gap.clone()).unwrap();
        let reference = lemke(&lcp, &LemkeParams::default()).unwrap();
        assert_eq!(sol.normal, reference.z);
        assert!(sol.tangential.iter().all(|&t| t == 0.0));
        assert_eq!(sol.method, FrictionMethod::Frictionless);
        assert!(sol.normal.iter().any(|&p| p > 0.0));
    }

    #[test]
    fn single_candidate_pushed_sideways_slips_on_the_cone() {
        // Pressed by q_n = −1 (P = 1 with M_nn = 1), pulled along +t by q_t = 1 ≫ μP M_tt.
        let mu = 0.3;
        let problem = one(1.0, 0.0, 0.0, 1.0, -1.0, 1.0, mu);
        let sol = solve_step(&problem).unwrap();
        assert!((sol.normal[0] - 1.0).abs() < 1e-14, "{sol:?}");
        assert!((sol.tangential[0] + mu * sol.normal[0]).abs() < 1e-14, "{sol:?}");
        assert!((sol.slip_increment[0] - (1.0 - mu)).abs() < 1e-14);
        assert_eq!(sol.state, vec![ContactState::SlipPositive]);
        // With coupling: g = −1 + P + 0.2 T, so P = 1 + 0.2 μ P ⇒ P = 1/(1 − 0.2 μ).
        let sol = solve_step(&one(1.0, 0.2, 0.1, 1.0, -1.0, 1.0, mu)).unwrap();
        let p = 1.0 / (1.0 - 0.2 * mu);
        assert!((sol.normal[0] - p).abs() < 1e-14 && (sol.tangential[0] + mu * p).abs() < 1e-14);
        assert_eq!(sol.state, vec![ContactState::SlipPositive]);
        // Pushed along −t: T = +μP, slip−.
        let sol = solve_step(&one(1.0, 0.0, 0.0, 1.0, -1.0, -1.0, mu)).unwrap();
        assert!((sol.tangential[0] - mu).abs() < 1e-14);
        assert_eq!(sol.state, vec![ContactState::SlipNegative]);
        // Within the cone: stick with T = −q_t / M_tt.
        let sol = solve_step(&one(1.0, 0.0, 0.0, 1.0, -1.0, 0.1, mu)).unwrap();
        assert!((sol.tangential[0] + 0.1).abs() < 1e-14);
        assert_eq!(sol.state, vec![ContactState::Stick]);
        // Open: no force at all.
        let sol = solve_step(&one(1.0, 0.0, 0.0, 1.0, 0.5, 1.0, mu)).unwrap();
        assert_eq!((sol.normal[0], sol.tangential[0]), (0.0, 0.0));
        assert_eq!(sol.state, vec![ContactState::Open]);
    }

    #[test]
    fn huge_friction_gives_the_tied_solution() {
        let mut rng = SplitMix64::new(11);
        let mut checked = 0;
        for _ in 0..20 {
            let mut problem = random_problem(&mut rng, 6, 1e8);
            // Every candidate pressed: the tied solution has P > 0 when q_n is very negative.
            problem.free_gap = vec![-10.0; 6];
            let sol = solve_step(&problem).unwrap();
            // Tied: g = 0 and Δs = 0 for all, a 12 × 12 linear system.
            let m = 6;
            let n = 12;
            let full = Mat::<f64>::from_fn(n, n, |i, j| {
                let (a, r, b, c) = (i / m, i % m, j / m, j % m);
                [[&problem.nn, &problem.nt], [&problem.tn, &problem.tt]][a][b][r * m + c]
            });
            let rhs = Mat::<f64>::from_fn(n, 1, |i, _| {
                if i < m {
                    -problem.free_gap[i]
                } else {
                    problem.previous_tangential[i - m] - problem.free_tangential[i - m]
                }
            });
            let x = full.partial_piv_lu().solve(&rhs);
            if (0..m).any(|c| x[(c, 0)] <= 0.0) {
                continue;
            }
            for c in 0..m {
                assert!((sol.normal[c] - x[(c, 0)]).abs() < 1e-10, "{c}: {sol:?}");
                assert!((sol.tangential[c] - x[(m + c, 0)]).abs() < 1e-10, "{c}: {sol:?}");
                assert_eq!(sol.state[c], ContactState::Stick);
            }
            checked += 1;
        }
        assert!(checked >= 10, "only {checked} tied cases with P > 0");
    }

    #[test]
    fn random_problems_satisfy_every_condition() {
        let mut rng = SplitMix64::new(2024);
        let mut methods = [0usize; 4];
        for case in 0..200 {
            let m = 1 + case % 10;
            let mu = [0.1, 0.3, 0.8, 2.0][case % 4];
            let problem = random_problem(&mut rng, m, mu);
            let sol = solve_step(&problem).unwrap_or_else(|e| panic!("case {case}: {e}"));
            let r = sol.residuals;
            assert!(r.max() <= 1e-12, "case {case} ({:?}): {r:?}", sol.method);
            methods[sol.method as usize] += 1;
            // The states agree with the forces.
            for c in 0..m {
                let (p, t) = (sol.normal[c], sol.tangential[c]);
                match sol.state[c] {
                    ContactState::Open => assert!(p == 0.0 && t.abs() <= 1e-12),
                    ContactState::Stick => assert!(t.abs() <= mu * p * (1.0 + 1e-12)),
                    ContactState::SlipPositive => assert!((t + mu * p).abs() <= 1e-10 * (1.0 + p)),
                    ContactState::SlipNegative => assert!((t - mu * p).abs() <= 1e-10 * (1.0 + p)),
                }
            }
        }
        println!(
            "methods used (frictionless, lemke, fixed point + active set, lemke with strict pivots): {methods:?}"
        );
        assert!(methods[1] > 0);
    }

    #[test]
    fn fixed_point_and_active_set_solve_what_lemke_solves() {
        let mut rng = SplitMix64::new(99);
        for case in 0..50 {
            let problem = random_problem(&mut rng, 2 + case % 8, 0.4);
            let zero = vec![0.0; problem.size()];
            let (p, t, _, _, _) =
                fixed_point(&problem, &LemkeParams::default(), zero.clone(), zero, MAX_FIXED_POINT);
            let (p, t, _) = active_set(&problem, p, t, MAX_ACTIVE_SET);
            let r = problem.residuals(&p, &t);
            assert!(r.max() <= 1e-12, "case {case}: {r:?}");
        }
    }

    #[test]
    fn non_convergence_is_reported_with_rounds_and_residual() {
        let e = LcpError::FrictionNotConverged {
            fixed_point_rounds: 100,
            active_set_rounds: 50,
            residual: 3.2e-4,
            fixed_point_change: 0.5,
            lemke: "ray".into(),
        };
        let text = e.to_string();
        for part in ["100 rounds", "active-set step 50", "3.200e-4", "5.000e-1", "(ray)"] {
            assert!(text.contains(part), "{part} missing from: {text}");
        }
    }

    #[test]
    fn malformed_data_are_refused() {
        let mut problem = one(1.0, 0.0, 0.0, 1.0, -1.0, 1.0, 0.3);
        problem.friction = vec![-0.1];
        assert!(solve_step(&problem).is_err());
        problem.friction = vec![0.1];
        problem.tt = vec![1.0, 2.0];
        assert!(matches!(
            solve_step(&problem),
            Err(LcpError::DimensionMismatch { what: "M_tt", .. })
        ));
    }
}
