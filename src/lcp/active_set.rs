//! The primal–dual active-set method (semismooth Newton, Hintermüller, Ito & Kunisch, SIAM J.
//! Optim. 13(3):865–888, 2002) for frictionless contact, without the dense compliance `M`
//! (docs/method.md §5.1).
//!
//! Each iteration solves the linear problem of a guessed active set `A`: gap `g_c = 0` for
//! `c ∈ A`, force `P_c = 0` for `c ∉ A`; the next guess keeps the active candidates whose force
//! is not negative and adds the inactive candidates whose gap is negative. The method stops
//! when the guess repeats itself, which makes `(P, g)` a solution of the LCP
//! `g = q + M P ≥ 0, P ≥ 0, gᵀP = 0` (to the tolerances of [`ActiveSetParams`]).
//!
//! `M` is neither symmetric nor (in general) an M-matrix, so plain PDAS can cycle. The
//! safeguard: when a guess comes back that was tried before, or the iteration limit is
//! reached, the candidates whose status ever changed are handed to Lemke's method as a small
//! LCP ([`ActiveSetSystem::reduced_lcp`]) with every other candidate held at its status, and
//! the iteration resumes from Lemke's answer. After [`ActiveSetParams::max_fallbacks`] such
//! rescues the solver gives up with [`ActiveSetError::NotConverged`]: it never returns an
//! unconverged answer.
//!
//! [`DenseSystem`] implements [`ActiveSetSystem`] for an [`Lcp`] with its dense `M` (tests and
//! small problems). The sparse systems of contact on the body's matrix `K` (a body against a
//! rigid obstacle, several elastic bodies: the gap condition of an active candidate replaces
//! its normal equilibrium row, as a displacement condition is collocated, docs/method.md §5.1)
//! implement it next to the contact operators, in `contact::sparse`; this module knows
//! nothing of bodies or matrices.

use super::{Lcp, LcpError, LcpResiduals, LcpSolution, LemkeParams, lemke};
use serde::Serialize;
use std::collections::HashSet;

mod friction;
pub use friction::{
    DenseFriction, FreeResponse, FrictionStepSolution, FrictionSystem, StateResponse,
    friction_residuals, mode_of, reduced_blocks, solve_friction_step,
};

/// Failures of the active-set solver.
#[derive(Debug, thiserror::Error)]
pub enum ActiveSetError {
    /// The iteration did not settle, even after the Lemke rescues.
    #[error(
        "the active-set contact solver did not converge: {iterations} iterations, {fallbacks} Lemke rescues of the changing candidates ({reason}); use contact.solver = \"lemke\""
    )]
    NotConverged {
        /// Linear solves done.
        iterations: usize,
        /// Lemke rescues done.
        fallbacks: usize,
        /// Why the last attempt stopped.
        reason: &'static str,
    },
    /// The contact forces do not enter the candidates' own rows only (a force shared between
    /// nodes of the candidate body): the row replacement does not apply.
    #[error(
        "the active-set contact solver needs each candidate's force on its own node's rows of the candidate body; candidate {candidate} does not: use contact.solver = \"lemke\""
    )]
    Unsupported {
        /// The first offending candidate.
        candidate: usize,
    },
    /// A node owns a candidate of one contact pair and receives the target forces of another
    /// on its rows (a body one node thick, or a corner node shared by two contact edges): the
    /// removed row would hold two unknown forces (docs/method.md §5.1).
    #[error(
        "the active-set contact solver cannot take contact[{pair}] and contact[{other}] together: node {node} of body[{body}] {what}, so the row it would take a force from holds two unknown forces; use contact[{pair}].solver = \"lemke\" (and the same for every pair)"
    )]
    OwnerConflict {
        /// The body (index among the problem's bodies).
        body: usize,
        /// The node (index in the body).
        node: usize,
        /// The pair whose candidate the node owns.
        pair: usize,
        /// The other pair (whose candidate or target forces also reach the node).
        other: usize,
        /// How the two pairs meet at the node.
        what: &'static str,
    },
    /// A linear solve of the system failed (the system's own error, e.g. a singular
    /// row-replaced matrix of the sparse systems in `contact::sparse`).
    #[error(transparent)]
    Solve(Box<dyn std::error::Error + Send + Sync>),
    /// A dense block of [`DenseSystem`] is singular.
    #[error("{what} is singular")]
    Singular {
        /// Which block.
        what: &'static str,
    },
    /// The Lemke rescue failed.
    #[error("Lemke's method on the changing candidates failed: {0}")]
    Rescue(Box<LcpError>),
}

/// Tuning of [`solve`].
#[derive(Clone, Copy, Debug)]
pub struct ActiveSetParams {
    /// Linear solves before a Lemke rescue (default 50).
    pub max_iterations: usize,
    /// Lemke rescues before giving up (default 3; 0 = report the first cycle as an error).
    pub max_fallbacks: usize,
    /// Relative tolerance `τ` of the status decisions (default 1e-10): an inactive candidate
    /// enters when `g_c < −τ max(‖q‖∞, ‖g‖∞)`, an active one leaves when
    /// `P_c < −τ ‖P‖∞`.
    pub tolerance: f64,
    /// A floor of the force scale the settled answer's residuals are measured against
    /// (default 0: the answer's own largest force). The searches over an obstacle's or a
    /// held body's position (docs/method.md §4.6–4.7) set it to the force they aim at: a
    /// trial that barely touches carries forces at round-off, and measured against its own
    /// scale the round-off reads as a violated cone.
    pub force_scale: f64,
}

impl Default for ActiveSetParams {
    fn default() -> Self {
        Self { max_iterations: 50, max_fallbacks: 3, tolerance: 1e-10, force_scale: 0.0 }
    }
}

/// How the solver ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ActiveSetEnd {
    /// The guess repeated itself without help.
    Converged,
    /// It settled after at least one Lemke rescue.
    ConvergedAfterRescue,
}

/// The answer of [`solve`].
#[derive(Clone, Debug)]
pub struct ActiveSetSolution {
    /// The LCP view of the answer: `z = P` (round-off below the tolerance clipped to 0),
    /// `w = g`, `pivots` = linear solves, and residuals as [`residuals`]
    /// describes.
    pub lcp: LcpSolution,
    /// The active set at the end.
    pub active: Vec<bool>,
    /// The gaps without contact forces `q` ([`ActiveSetSystem::free_gap`]), or the initial
    /// gaps `g0` when `q` could not be computed.
    pub free_gap: Vec<f64>,
    /// Linear solves (iterations).
    pub iterations: usize,
    /// Candidates whose status changed after each iteration (the last is 0).
    pub changes: Vec<usize>,
    /// Lemke rescues, with the number of candidates each one handled.
    pub rescues: Vec<usize>,
    /// How it ended.
    pub end: ActiveSetEnd,
}

/// A contact problem the active-set method can iterate on.
pub trait ActiveSetSystem {
    /// Number of candidates.
    fn size(&self) -> usize;
    /// `q`: the gaps without contact forces, or `None` when the body cannot be solved without
    /// them (held by contact alone, or too ill-conditioned for the solver's accuracy check).
    ///
    /// # Errors
    /// A failed solve other than that.
    fn free_gap(&mut self) -> Result<Option<Vec<f64>>, ActiveSetError>;
    /// `g0`: the initial gaps (the scale of the gaps when `q` is unknown).
    fn initial_gap(&self) -> Vec<f64>;
    /// Forces `P` and gaps `g` of the problem of `active` (`g_c = 0` on it, `P_c = 0` off it).
    ///
    /// # Errors
    /// A failed solve.
    fn solve_active(&mut self, active: &[bool]) -> Result<(Vec<f64>, Vec<f64>), ActiveSetError>;
    /// The LCP of the candidates `free` (indices), the others held at their status in
    /// `active` (active: gap 0; inactive: force 0): `g_F = q_F + M_F P_F`.
    ///
    /// # Errors
    /// A failed solve.
    fn reduced_lcp(&mut self, active: &[bool], free: &[usize]) -> Result<Lcp, ActiveSetError>;
}

/// Solves the contact problem of `system` by the primal–dual active-set method, starting from
/// the candidates with a negative free gap, with Lemke rescues of the changing candidates when
/// the iteration cycles (see the module documentation).
///
/// # Errors
/// [`ActiveSetError::NotConverged`] when the rescues do not settle it; solve failures.
pub fn solve(
    system: &mut dyn ActiveSetSystem,
    params: &ActiveSetParams,
) -> Result<ActiveSetSolution, ActiveSetError> {
    let m = system.size();
    let max_abs = |v: &[f64]| v.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    // Start from the candidates that the free body would push through the obstacle; without
    // a free solution, from all of them (and g0 stands in for q in the scales).
    let (q, mut active) = match system.free_gap()? {
        Some(q) => {
            let q_max = max_abs(&q);
            let active = q.iter().map(|&g| g < -params.tolerance * q_max).collect();
            (q, active)
        }
        None => (system.initial_gap(), vec![true; m]),
    };
    let q_max = max_abs(&q);
    let mut seen: HashSet<Vec<bool>> = HashSet::new();
    seen.insert(active.clone());
    let mut ever_changed = vec![false; m];
    let (mut iterations, mut since_rescue) = (0, 0);
    let mut changes = Vec::new();
    let mut rescues = Vec::new();
    loop {
        let (p, g) = system.solve_active(&active)?;
        iterations += 1;
        since_rescue += 1;
        let tol_g = params.tolerance * q_max.max(max_abs(&g));
        let tol_p = params.tolerance * max_abs(&p);
        let next: Vec<bool> =
            (0..m).map(|c| if active[c] { p[c] >= -tol_p } else { g[c] < -tol_g }).collect();
        let changed = (0..m).filter(|&c| next[c] != active[c]).count();
        changes.push(changed);
        if changed == 0 {
            let z: Vec<f64> = p.iter().map(|&v| v.max(0.0)).collect();
            let residuals = residuals(&q, &z, &g);
            let end = if rescues.is_empty() {
                ActiveSetEnd::Converged
            } else {
                ActiveSetEnd::ConvergedAfterRescue
            };
            return Ok(ActiveSetSolution {
                lcp: LcpSolution { z, w: g, pivots: iterations, residuals },
                active,
                free_gap: q,
                iterations,
                changes,
                rescues,
                end,
            });
        }
        for c in 0..m {
            ever_changed[c] |= next[c] != active[c];
        }
        let cycled = !seen.insert(next.clone());
        if !cycled && since_rescue < params.max_iterations {
            active = next;
            continue;
        }
        let reason = if cycled { "an active set came back" } else { "iteration limit" };
        if rescues.len() >= params.max_fallbacks {
            return Err(ActiveSetError::NotConverged {
                iterations,
                fallbacks: rescues.len(),
                reason,
            });
        }
        // Lemke on the candidates that ever changed, the others held at their status.
        let free: Vec<usize> = (0..m).filter(|&c| ever_changed[c]).collect();
        let lcp = system.reduced_lcp(&next, &free)?;
        let answer = lemke(&lcp, &LemkeParams::default())
            .map_err(|e| ActiveSetError::Rescue(Box::new(e)))?;
        active = next;
        for (k, &c) in free.iter().enumerate() {
            active[c] = answer.z[k] > 0.0;
        }
        rescues.push(free.len());
        seen.clear();
        seen.insert(active.clone());
        since_rescue = 0;
    }
}

/// The Lemke path's scaled residuals ([`LcpResiduals`]) without `M`: the scale is
/// `s = max(1, ‖q‖∞, ‖g − q‖∞)` (`g − q = M P`, where the Lemke path uses `max|M_ij| ‖P‖∞`,
/// an upper bound of it), and `equation_residual` is 0 (the gaps are computed from the
/// displacements, not from `M`; equilibrium is checked on the recovered solution).
pub fn residuals(q: &[f64], z: &[f64], w: &[f64]) -> LcpResiduals {
    let max_abs = |v: &[f64]| v.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let mz = w.iter().zip(q).fold(0.0_f64, |a, (w, q)| a.max((w - q).abs()));
    let scale = 1.0_f64.max(max_abs(q)).max(mz);
    let z_max = max_abs(z);
    let n = z.len();
    let min_z = if n == 0 { 0.0 } else { z.iter().copied().fold(f64::INFINITY, f64::min) };
    let min_w = if n == 0 { 0.0 } else { w.iter().copied().fold(f64::INFINITY, f64::min) };
    let compl = z.iter().zip(w).fold(0.0_f64, |acc, (a, b)| acc.max((a * b).abs()));
    LcpResiduals {
        min_z: min_z / scale,
        min_w: min_w / scale,
        max_complementarity: compl / (scale * z_max.max(1.0)),
        equation_residual: 0.0,
        scale,
    }
}

/// LU with partial pivoting of a small dense column-major `k × k` matrix, in place; returns
/// the row permutation, or `None` when a pivot is exactly zero.
pub fn dense_lu(a: &mut [f64], k: usize) -> Option<Vec<usize>> {
    let mut perm: Vec<usize> = (0..k).collect();
    for j in 0..k {
        let p = (j..k).max_by(|&x, &y| a[j * k + x].abs().total_cmp(&a[j * k + y].abs()))?;
        if a[j * k + p] == 0.0 {
            return None;
        }
        if p != j {
            perm.swap(j, p);
            for c in 0..k {
                a.swap(c * k + j, c * k + p);
            }
        }
        let pivot = a[j * k + j];
        for i in j + 1..k {
            a[j * k + i] /= pivot;
        }
        for c in j + 1..k {
            let f = a[c * k + j];
            if f != 0.0 {
                for i in j + 1..k {
                    a[c * k + i] -= a[j * k + i] * f;
                }
            }
        }
    }
    Some(perm)
}

/// Solves with the factors of [`dense_lu`]; `b` is overwritten with the solution.
pub fn dense_lu_solve(lu: &[f64], perm: &[usize], k: usize, b: &mut [f64]) {
    let x: Vec<f64> = perm.iter().map(|&p| b[p]).collect();
    b.copy_from_slice(&x);
    for j in 0..k {
        let v = b[j];
        for i in j + 1..k {
            b[i] -= lu[j * k + i] * v;
        }
    }
    for j in (0..k).rev() {
        b[j] /= lu[j * k + j];
        let v = b[j];
        for i in 0..j {
            b[i] -= lu[j * k + i] * v;
        }
    }
}

/// An [`Lcp`] (dense `M`, `q`) as an active-set system.
pub struct DenseSystem<'a> {
    lcp: &'a Lcp,
}

impl<'a> DenseSystem<'a> {
    /// The system of `lcp`.
    pub fn new(lcp: &'a Lcp) -> Self {
        Self { lcp }
    }

    /// `M_AA⁻¹ r` for the index list `a`.
    fn solve_block(&self, a: &[usize], r: &mut [f64]) -> Result<(), ActiveSetError> {
        let k = a.len();
        let mut block = vec![0.0; k * k];
        for (j, &cj) in a.iter().enumerate() {
            for (i, &ci) in a.iter().enumerate() {
                block[j * k + i] = self.lcp.m(ci, cj);
            }
        }
        let perm = dense_lu(&mut block, k)
            .ok_or(ActiveSetError::Singular { what: "M on the active set" })?;
        dense_lu_solve(&block, &perm, k, r);
        Ok(())
    }
}

impl ActiveSetSystem for DenseSystem<'_> {
    fn size(&self) -> usize {
        self.lcp.size()
    }
    fn free_gap(&mut self) -> Result<Option<Vec<f64>>, ActiveSetError> {
        Ok(Some(self.lcp.q().to_vec()))
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.lcp.q().to_vec()
    }
    fn solve_active(&mut self, active: &[bool]) -> Result<(Vec<f64>, Vec<f64>), ActiveSetError> {
        let n = self.size();
        let a: Vec<usize> = (0..n).filter(|&c| active[c]).collect();
        let mut pa: Vec<f64> = a.iter().map(|&c| -self.lcp.q()[c]).collect();
        self.solve_block(&a, &mut pa)?;
        let mut p = vec![0.0; n];
        for (&c, &v) in a.iter().zip(&pa) {
            p[c] = v;
        }
        let mut g = self.lcp.w(&p);
        for &c in &a {
            g[c] = 0.0;
        }
        Ok((p, g))
    }
    fn reduced_lcp(&mut self, active: &[bool], free: &[usize]) -> Result<Lcp, ActiveSetError> {
        let n = self.size();
        let is_free: Vec<bool> = {
            let mut v = vec![false; n];
            free.iter().for_each(|&c| v[c] = true);
            v
        };
        let a: Vec<usize> = (0..n).filter(|&c| active[c] && !is_free[c]).collect();
        // Schur complement: M_FF − M_FA M_AA⁻¹ M_AF, q_F − M_FA M_AA⁻¹ q_A.
        let k = free.len();
        let mut m = vec![0.0; k * k];
        let mut q = vec![0.0; k];
        for (col, cj) in free.iter().map(Some).chain([None]).enumerate() {
            let mut r: Vec<f64> =
                a.iter().map(|&ci| cj.map_or(self.lcp.q()[ci], |&cj| self.lcp.m(ci, cj))).collect();
            self.solve_block(&a, &mut r)?;
            for (row, &fi) in free.iter().enumerate() {
                let base = cj.map_or(self.lcp.q()[fi], |&cj| self.lcp.m(fi, cj));
                let corr: f64 = a.iter().zip(&r).map(|(&ci, x)| self.lcp.m(fi, ci) * x).sum();
                match cj {
                    Some(_) => m[row * k + col] = base - corr,
                    None => q[row] = base - corr,
                }
            }
        }
        Lcp::new(k, m, q).map_err(|e| ActiveSetError::Rescue(Box::new(e)))
    }
}

/// A candidate's mode in a sparse contact system (`contact::sparse`): which of its rows are
/// replaced. `OPEN`: none;
/// `CLOSED`: the frictionless rows (gap row, tangential balance); `STICK`: gap row and the
/// tangential displacement condition; `SLIP_POSITIVE` / `SLIP_NEGATIVE`: gap row and
/// `T = ∓μP` (docs/method.md §5.1, §8).
pub type Mode = u8;
/// No row replaced (`P = T = 0`).
pub const OPEN: Mode = 0;
/// Frictionless contact (`g = 0`, `T = 0`).
pub const CLOSED: Mode = 1;
/// `g = 0`, `s = s_prev`.
pub const STICK: Mode = 2;
/// `g = 0`, `T = −μP`.
pub const SLIP_POSITIVE: Mode = 3;
/// `g = 0`, `T = +μP`.
pub const SLIP_NEGATIVE: Mode = 4;
