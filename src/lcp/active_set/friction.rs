//! The frictional step (docs/method.md §8) by the active-set method, without the dense
//! blocks `M_nn, M_nt, M_tn, M_tt` (docs/method.md §5.1, "Friction").
//!
//! Each candidate is open, sticking or slipping along `±t`; the linear problem of a guess of
//! the states is "open: `P = T = 0`; closed: `g = 0` and stick: `Δs = 0`, slip±: `T = ∓μP`".
//! The next guess moves every candidate whose sign condition fails, with the rules of
//! `lcp::friction`'s exact active-set step: open with `g < 0` → stick (slip along `Δs` when
//! `|Δs| > μ(−g)`, the test of the min-function form at `P = T = 0`); closed with `P < 0`
//! → open; stick with `T > μP` → slip−, `T < −μP` → slip+; slip+ with `Δs < 0`, slip− with
//! `Δs > 0` → stick. The guess that repeats itself is the answer (semismooth Newton on the
//! min-function form of the step's conditions). The step's matrix is not a P-matrix and the
//! iteration can cycle: when a guess comes back, or after [`ActiveSetParams::max_iterations`]
//! solves, the candidates whose state changed within the cycle (resp. since the last rescue)
//! are handed to the Lemke-based step solver
//! ([`crate::lcp::solve_step`]) on their reduced blocks (the others held at their states),
//! and the iteration resumes from its answer; after [`ActiveSetParams::max_fallbacks`]
//! rescues, or when the settled answer misses [`FRICTION_TOLERANCE`], the step fails with
//! [`ActiveSetError::NotConverged`]: an unconverged answer is never returned.

use super::{
    ActiveSetEnd, ActiveSetError, ActiveSetParams, CLOSED, Mode, OPEN, SLIP_NEGATIVE,
    SLIP_POSITIVE, STICK,
};
use crate::lcp::friction::{
    ContactState, FRICTION_TOLERANCE, FrictionMethod, FrictionProblem, FrictionResiduals,
    FrictionSolution, solve_states, solve_step as lemke_step,
};
use std::collections::HashMap;

/// `(q_n, q_t)`: gaps and tangential displacements without contact forces.
pub type FreeResponse = (Vec<f64>, Vec<f64>);

/// Forces and displacements of the linear problem of a guess of the states.
#[derive(Clone, Debug)]
pub struct StateResponse {
    /// `P` (0 where open).
    pub normal: Vec<f64>,
    /// `T` (0 where open).
    pub tangential: Vec<f64>,
    /// `g` (0 where closed, up to round-off).
    pub gap: Vec<f64>,
    /// `s`, the tangential displacements relative to the obstacle.
    pub tangential_displacement: Vec<f64>,
}

/// A frictional contact problem the active-set method can iterate on.
pub trait FrictionSystem {
    /// Number of candidates.
    fn size(&self) -> usize;
    /// `μ_c` per candidate.
    fn friction(&self) -> Vec<f64>;
    /// `(q_n, q_t)`: gaps and tangential displacements without contact forces, or `None`
    /// when the body cannot be solved without them.
    ///
    /// # Errors
    /// A failed solve other than that.
    fn free_response(&mut self) -> Result<Option<FreeResponse>, ActiveSetError>;
    /// `g0`: the gaps without displacement (their scale when `q_n` is unknown).
    fn initial_gap(&self) -> Vec<f64>;
    /// The linear problem of `states` with the previous tangential displacements `previous`.
    ///
    /// # Errors
    /// A failed solve.
    fn solve_states(
        &mut self,
        states: &[ContactState],
        previous: &[f64],
    ) -> Result<StateResponse, ActiveSetError>;
    /// The step problem of the candidates `free` (indices), the others held at `states`:
    /// its four blocks and free responses (`2|free| + 1` solves).
    ///
    /// # Errors
    /// A failed solve.
    fn reduced_problem(
        &mut self,
        states: &[ContactState],
        free: &[usize],
        previous: &[f64],
    ) -> Result<FrictionProblem, ActiveSetError>;
}

/// The answer of [`solve_friction_step`].
#[derive(Clone, Debug)]
pub struct FrictionStepSolution {
    /// Forces, gaps, tangential displacements, slip increments, states (classified from the
    /// slip increments as `lcp::solve_step` does), residuals; `method` is
    /// [`FrictionMethod::ActiveSet`], `pivots` the rescues' Lemke pivots and `iterations`
    /// the linear solves.
    pub step: FrictionSolution,
    /// The states the iteration settled on (the next step's start).
    pub states: Vec<ContactState>,
    /// `q_n` (or `g0` when unknown).
    pub free_gap: Vec<f64>,
    /// Candidates whose state changed after each iteration (the last is 0).
    pub changes: Vec<usize>,
    /// Lemke rescues, with the candidates each handled.
    pub rescues: Vec<usize>,
    /// How it ended.
    pub end: ActiveSetEnd,
}

impl FrictionStepSolution {
    /// The answer of the frictionless active-set method ([`super::solve`]) as a step's with
    /// every `μ_c = 0` (a one-shot sparse path: one frictionless step of one increment): its
    /// forces `P = z` and gaps `g = w` as it gave them, `T = 0` and no tangential
    /// displacement, each candidate sticking where its final active set closed it and open
    /// elsewhere, its linear solves as `iterations`.
    pub fn frictionless(answer: super::ActiveSetSolution) -> Self {
        let m = answer.active.len();
        let zeros = vec![0.0; m];
        let (p, g) = (answer.lcp.z, answer.lcp.w);
        let residuals =
            friction_residuals((&answer.free_gap, &zeros), (&p, &zeros), &g, &zeros, (&zeros, 0.0));
        let states: Vec<ContactState> = answer
            .active
            .iter()
            .map(|&a| if a { ContactState::Stick } else { ContactState::Open })
            .collect();
        let step = FrictionSolution {
            normal: p,
            tangential: zeros.clone(),
            gap: g,
            tangential_displacement: zeros.clone(),
            slip_increment: zeros,
            state: states.clone(),
            residuals,
            method: FrictionMethod::ActiveSet,
            pivots: 0,
            iterations: answer.iterations,
            lemke_failure: None,
        };
        let (free_gap, changes, rescues, end) =
            (answer.free_gap, answer.changes, answer.rescues, answer.end);
        Self { step, states, free_gap, changes, rescues, end }
    }
}

/// The scaled residuals of a step's answer (docs/method.md §8) without the blocks: the
/// displacement scale `U = max(‖q_n‖∞, ‖q_t − s_prev‖∞, ‖g − q_n‖∞, ‖Δs − (q_t − s_prev)‖∞)`
/// (the last two are `M` times the forces, where `lcp::solve_step` uses the bound
/// `max|M| F`). The force scale is the largest force, at least `force_floor`
/// ([`ActiveSetParams::force_scale`](super::ActiveSetParams::force_scale)).
pub fn friction_residuals(
    free: (&[f64], &[f64]),
    forces: (&[f64], &[f64]),
    gap: &[f64],
    slip_increment: &[f64],
    (mu, force_floor): (&[f64], f64),
) -> FrictionResiduals {
    let ((qn, dq), (p, t)) = (free, forces);
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let diff =
        |a: &[f64], b: &[f64]| a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    let f = inf(p).max(inf(t)).max(force_floor);
    let f = if f > 0.0 { f } else { 1.0 };
    let u = inf(qn)
        .max(inf(dq))
        .max(diff(gap, qn))
        .max(diff(slip_increment, dq))
        .max(f64::MIN_POSITIVE);
    let mut r = FrictionResiduals { force_scale: f, displacement_scale: u, ..Default::default() };
    for c in 0..p.len() {
        let (pc, tc, ds) = (p[c], t[c], slip_increment[c]);
        r.negative_force = r.negative_force.max(-pc / f);
        r.penetration = r.penetration.max(-gap[c] / u);
        r.normal_complementarity = r.normal_complementarity.max((pc * gap[c]).abs() / (f * u));
        r.cone = r.cone.max((tc.abs() - mu[c] * pc.max(0.0)) / f);
        let slack = (mu[c] * pc - tc.abs()).clamp(0.0, f);
        let fc = (tc * ds).max(0.0).max(slack * ds.abs());
        r.friction_complementarity = r.friction_complementarity.max(fc / (f * u));
    }
    r
}

/// Solves one frictional step of `system` from the previous tangential displacements
/// `previous` by the active-set method (see the module documentation), starting from
/// `start` (the previous step's states: warm start) or, without it, from the candidates with
/// a negative free gap sticking.
///
/// # Errors
/// [`ActiveSetError::NotConverged`] when the rescues do not settle it or the settled answer
/// misses [`FRICTION_TOLERANCE`]; [`ActiveSetError::Rescue`] when a rescue fails; solve
/// failures.
pub fn solve_friction_step(
    system: &mut dyn FrictionSystem,
    previous: &[f64],
    start: Option<&[ContactState]>,
    params: &ActiveSetParams,
) -> Result<FrictionStepSolution, ActiveSetError> {
    let m = system.size();
    let mu = system.friction();
    let inf = |v: &[f64]| v.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let free = system.free_response()?;
    let (qn, dq) = match &free {
        Some((qn, qt)) => (qn.clone(), qt.iter().zip(previous).map(|(a, b)| a - b).collect()),
        None => (system.initial_gap(), vec![0.0; m]),
    };
    let mut states: Vec<ContactState> = match (start, &free) {
        (Some(s), _) => s.to_vec(),
        (None, Some(_)) => {
            let q_max = inf(&qn);
            qn.iter()
                .map(|&g| {
                    if g < -params.tolerance * q_max {
                        ContactState::Stick
                    } else {
                        ContactState::Open
                    }
                })
                .collect()
        }
        (None, None) => vec![ContactState::Stick; m],
    };
    let key = |s: &[ContactState]| s.iter().map(|&x| x as u8).collect::<Vec<u8>>();
    // Every guess since the last rescue, with the iteration that made it, and the candidates
    // each iteration changed.
    let mut seen: HashMap<Vec<u8>, usize> = HashMap::new();
    seen.insert(key(&states), 0);
    let mut moved: Vec<Vec<usize>> = Vec::new();
    let (mut iterations, mut since_rescue, mut pivots) = (0, 0, 0);
    let (mut changes, mut rescues) = (Vec::new(), Vec::new());
    let scale_u = inf(&qn).max(inf(&dq));
    loop {
        let r = system.solve_states(&states, previous)?;
        iterations += 1;
        since_rescue += 1;
        let ds: Vec<f64> =
            r.tangential_displacement.iter().zip(previous).map(|(a, b)| a - b).collect();
        let tol_f = params.tolerance * inf(&r.normal).max(inf(&r.tangential));
        let tol_u = params.tolerance * scale_u.max(inf(&r.gap)).max(inf(&ds));
        let next: Vec<ContactState> = (0..m)
            .map(|c| {
                let (p, t, bound) = (r.normal[c], r.tangential[c], mu[c] * r.normal[c]);
                match states[c] {
                    // Closing: stick when the slip increment is within μ times the
                    // penetration (the min-function form's test |Δs| ≤ μ(−g) at P = T = 0),
                    // else slip along Δs.
                    ContactState::Open if r.gap[c] < -tol_u => {
                        if mu[c] > 0.0 && ds[c].abs() > -mu[c] * r.gap[c] {
                            if ds[c] > 0.0 {
                                ContactState::SlipPositive
                            } else {
                                ContactState::SlipNegative
                            }
                        } else {
                            ContactState::Stick
                        }
                    }
                    ContactState::Open => ContactState::Open,
                    _ if p < -tol_f => ContactState::Open,
                    s if mu[c] == 0.0 => s,
                    ContactState::Stick if t > bound + tol_f => ContactState::SlipNegative,
                    ContactState::Stick if t < -bound - tol_f => ContactState::SlipPositive,
                    ContactState::SlipPositive if ds[c] < -tol_u => ContactState::Stick,
                    ContactState::SlipNegative if ds[c] > tol_u => ContactState::Stick,
                    s => s,
                }
            })
            .collect();
        let changed = (0..m).filter(|&c| next[c] != states[c]).count();
        changes.push(changed);
        if changed == 0 {
            let mu = (mu.as_slice(), params.force_scale);
            let step = finish(&r, &states, previous, (&qn, &dq), mu, pivots, iterations);
            let residual = step.residuals.max();
            if residual > FRICTION_TOLERANCE {
                return Err(ActiveSetError::NotConverged {
                    iterations,
                    fallbacks: rescues.len(),
                    reason: "the settled states' answer misses the residual tolerance",
                });
            }
            let end = if rescues.is_empty() {
                ActiveSetEnd::Converged
            } else {
                ActiveSetEnd::ConvergedAfterRescue
            };
            return Ok(FrictionStepSolution { step, states, free_gap: qn, changes, rescues, end });
        }
        moved.push((0..m).filter(|&c| next[c] != states[c]).collect());
        let back = seen.insert(key(&next), moved.len());
        let cycled = back.is_some();
        if !cycled && since_rescue < params.max_iterations {
            states = next;
            continue;
        }
        let reason = if cycled { "a set of states came back" } else { "iteration limit" };
        if rescues.len() >= params.max_fallbacks {
            return Err(ActiveSetError::NotConverged {
                iterations,
                fallbacks: rescues.len(),
                reason,
            });
        }
        // The Lemke-based step solver on the candidates that changed within the cycle (after
        // the limit: since the last rescue), the others held.
        let from = back.unwrap_or(0);
        let mut in_cycle = vec![false; m];
        for &c in moved[from..].iter().flatten() {
            in_cycle[c] = true;
        }
        let free_set: Vec<usize> = (0..m).filter(|&c| in_cycle[c]).collect();
        let reduced = system.reduced_problem(&next, &free_set, previous)?;
        let answer = lemke_step(&reduced).map_err(|e| ActiveSetError::Rescue(Box::new(e)))?;
        pivots += answer.pivots;
        states = next;
        for (k, &c) in free_set.iter().enumerate() {
            states[c] = answer.state[k];
        }
        rescues.push(free_set.len());
        seen.clear();
        seen.insert(key(&states), 0);
        moved.clear();
        since_rescue = 0;
    }
}

/// The answer from the settled states' response: exact zeros where the conditions are
/// equations (open forces, closed gaps, stick increments), negative round-off of `P` clipped.
fn finish(
    r: &StateResponse,
    states: &[ContactState],
    previous: &[f64],
    free: (&[f64], &[f64]),
    (mu, force_floor): (&[f64], f64),
    pivots: usize,
    iterations: usize,
) -> FrictionSolution {
    let m = states.len();
    let (mut p, mut t, mut g) = (r.normal.clone(), r.tangential.clone(), r.gap.clone());
    let mut s = r.tangential_displacement.clone();
    for c in 0..m {
        match states[c] {
            ContactState::Open => {
                p[c] = 0.0;
                t[c] = 0.0;
            }
            state => {
                p[c] = p[c].max(0.0);
                g[c] = 0.0;
                if state == ContactState::Stick && mu[c] > 0.0 {
                    s[c] = previous[c];
                }
            }
        }
    }
    let ds: Vec<f64> = s.iter().zip(previous).map(|(a, b)| a - b).collect();
    let residuals = friction_residuals(free, (&p, &t), &g, &ds, (mu, force_floor));
    // Reported as `lcp::solve_step` classifies its answers.
    let state = crate::lcp::friction::classify(&p, &ds, residuals.displacement_scale);
    FrictionSolution {
        normal: p,
        tangential: t,
        gap: g,
        tangential_displacement: s,
        slip_increment: ds,
        state,
        residuals,
        method: FrictionMethod::ActiveSet,
        pivots,
        iterations,
        lemke_failure: None,
    }
}

/// A [`FrictionProblem`] (dense blocks) as a frictional active-set system: for tests and
/// small problems.
pub struct DenseFriction<'a> {
    problem: &'a FrictionProblem,
}

impl<'a> DenseFriction<'a> {
    /// The system of `problem` (its `previous_tangential` is ignored: [`solve_friction_step`]
    /// passes its own).
    pub fn new(problem: &'a FrictionProblem) -> Self {
        Self { problem }
    }

    /// Solves the 2m linear conditions: `fixed[c] = Some((P, T))` prescribes a candidate's
    /// forces, the others follow `states`; `with_free` includes `q_n`, `q_t − s_prev` (else
    /// the response to the prescribed forces alone).
    fn solve(
        &self,
        states: &[ContactState],
        fixed: &[Option<(f64, f64)>],
        previous: &[f64],
        with_free: bool,
    ) -> Result<StateResponse, ActiveSetError> {
        let pr = self.problem;
        let m = pr.size();
        let (qn, qt): (Vec<f64>, Vec<f64>) = if with_free {
            (pr.free_gap.clone(), pr.free_tangential.clone())
        } else {
            (vec![0.0; m], vec![0.0; m])
        };
        let prev: Vec<f64> = if with_free { previous.to_vec() } else { vec![0.0; m] };
        let (p, t) = solve_states(pr, states, fixed, (&qn, &qt), &prev)
            .ok_or(ActiveSetError::Singular { what: "the dense frictional step" })?;
        let dot = |row: &[f64], v: &[f64]| row.iter().zip(v).map(|(x, y)| x * y).sum::<f64>();
        let gap = (0..m)
            .map(|i| {
                qn[i] + dot(&pr.nn[i * m..(i + 1) * m], &p) + dot(&pr.nt[i * m..(i + 1) * m], &t)
            })
            .collect();
        let s = (0..m)
            .map(|i| {
                qt[i] + dot(&pr.tn[i * m..(i + 1) * m], &p) + dot(&pr.tt[i * m..(i + 1) * m], &t)
            })
            .collect();
        Ok(StateResponse { normal: p, tangential: t, gap, tangential_displacement: s })
    }
}

impl FrictionSystem for DenseFriction<'_> {
    fn size(&self) -> usize {
        self.problem.size()
    }
    fn friction(&self) -> Vec<f64> {
        self.problem.friction.clone()
    }
    fn free_response(&mut self) -> Result<Option<FreeResponse>, ActiveSetError> {
        Ok(Some((self.problem.free_gap.clone(), self.problem.free_tangential.clone())))
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.problem.free_gap.clone()
    }
    fn solve_states(
        &mut self,
        states: &[ContactState],
        previous: &[f64],
    ) -> Result<StateResponse, ActiveSetError> {
        self.solve(states, &vec![None; self.size()], previous, true)
    }
    fn reduced_problem(
        &mut self,
        states: &[ContactState],
        free: &[usize],
        previous: &[f64],
    ) -> Result<FrictionProblem, ActiveSetError> {
        let m = self.size();
        let mut fixed = vec![None; m];
        for &c in free {
            fixed[c] = Some((0.0, 0.0));
        }
        let base = self.solve(states, &fixed, previous, true)?;
        let columns = (0..2 * free.len())
            .map(|j| {
                let mut fx = fixed.clone();
                let c = free[j % free.len()];
                fx[c] = Some(if j < free.len() { (1.0, 0.0) } else { (0.0, 1.0) });
                self.solve(states, &fx, previous, false)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(reduced_blocks(&base, &columns, free, previous, &self.problem.friction))
    }
}

/// The reduced [`FrictionProblem`] of the candidates `free` from the held problem's response
/// `base` and the responses `columns` to unit `P` (first `|free|`) and `T` (then) on each.
pub fn reduced_blocks(
    base: &StateResponse,
    columns: &[StateResponse],
    free: &[usize],
    previous: &[f64],
    mu: &[f64],
) -> FrictionProblem {
    let k = free.len();
    let block = |offset: usize, normal: bool| {
        let mut out = vec![0.0; k * k];
        for j in 0..k {
            let col = &columns[offset + j];
            for (i, &c) in free.iter().enumerate() {
                out[i * k + j] = if normal { col.gap[c] } else { col.tangential_displacement[c] };
            }
        }
        out
    };
    FrictionProblem {
        nn: block(0, true),
        nt: block(k, true),
        tn: block(0, false),
        tt: block(k, false),
        free_gap: free.iter().map(|&c| base.gap[c]).collect(),
        free_tangential: free.iter().map(|&c| base.tangential_displacement[c]).collect(),
        previous_tangential: free.iter().map(|&c| previous[c]).collect(),
        friction: free.iter().map(|&c| mu[c]).collect(),
    }
}

/// The mode of a candidate with friction coefficient `mu` in `state` (a rigid obstacle's or
/// two bodies' rows).
pub fn mode_of(mu: f64, state: ContactState) -> Mode {
    match state {
        ContactState::Open => OPEN,
        _ if mu == 0.0 => CLOSED,
        ContactState::Stick => STICK,
        ContactState::SlipPositive => SLIP_POSITIVE,
        ContactState::SlipNegative => SLIP_NEGATIVE,
    }
}
