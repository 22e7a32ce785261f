//! The step's contact on the sparse system, without `W` (increment 11 of
//! docs/dev/dynamics.md; `contact.solver = "active_set"`).
//!
//! The step's problem on the index set `A` is the static sparse problem of
//! [`Bodies`] (one body against rigid obstacles is one pair without a target) with other
//! symbols: the unknowns are the velocity changes `Δv_b = v_b⁺ − v_b`,
//!
//! ```text
//! M̂_b Δv_b = r_b + E_b Π          r_b = h (s f_b − K_b (q_b + hθ v_b))   (the free step's)
//! g_c     = (1 + e) U_c + Σ_b G_b Δv_b = U⁺_c + e U_c,   0 ≤ Π_c ⊥ g_c ≥ 0   on A
//! ```
//!
//! i.e. the static `K_b û_b = f_b + E_b P`, `g = g0 + Σ G_b û_b` with `K_b → M̂_b`,
//! `f_b → r_b`, `û_b → Δv_b`, `g0_c → (1 + e) U_c` (`U = Σ_b G_b v_b` at the step's start),
//! solved by the primal–dual active-set method ([`crate::lcp::active_set::solve`]) on the
//! candidates of `A` (the others held open: `Π_c = 0`). A gap row replaces the owner node's
//! row of `M̂_b`, scaled by the body's collocation scale times `h²θ²` (the scale of its
//! collocation rows in `M̂`). `M̂_b`'s factorisation is the base; the Woodbury columns of
//! the candidates that close are kept from step to step while `M̂` is unchanged (the
//! system's own cache), so a step whose set repeats the last one's costs one solve and the
//! low-rank correction. No `m × m` compliance and no `n × m` `M̂⁻¹ E` is formed.
//!
//! The bodies are whatever the stepping takes: MFVM (rows replaced in `M Φ + h²θ² K`, its
//! collocation rows scaled by `h²θ²`) or finite elements (identity `Φ`, the eliminated rows
//! of `K` in `M + h²θ² K`), plane or axisymmetric (the mass per radian; ring candidates,
//! whose whole ring's force acts per radian on the owner: weights over 2π): the gap row
//! replaces an owner's row as for any other; `tests/validation/dynamics_active_set.rs` compares each with Lemke's run.
//!
//! The method starts from every candidate of `A` closed (the index set as the first guess;
//! the system's free solve is skipped, see [`OnSet`]'s `free_gap`): on the bar of
//! docs/dev/dynamics.md every contact step then settles in one solve.

use super::impacts::{StepImpulses, coefficients_at};
use super::loads::ObstacleStep;
use super::{DynamicsError, Friction, Impacts, Iteration, Term};
use crate::contact::BodyOperator;
use crate::contact::sparse::{Bodies, BodyParts, PairParts, PairTangential};
use crate::geometry::Point;
use crate::lcp::active_set::{
    ActiveSetError, ActiveSetParams, ActiveSetSystem, FreeResponse, FrictionSystem, StateResponse,
    solve, solve_friction_step,
};
use crate::lcp::{ContactState, FrictionProblem, Lcp};

/// The sparse system of the bodies' `M̂` and the contact pairs.
pub(super) struct SparseStep<'a> {
    system: Bodies<'a>,
    /// Every candidate's `g0` held for [`Bodies::set_initial_gap`].
    gaps: Vec<f64>,
    /// With friction: the tangential terms (the rates `U_t`) and each candidate's state at
    /// the last step it was in the index set (the next step's start).
    friction: Option<(Vec<Term<'a>>, Vec<ContactState>)>,
    /// With friction changing in time ([`Friction::schedule`]): the schedule, the pairs'
    /// tangential operators (to set the system's coefficients again) and the coefficients
    /// the system holds.
    schedule: Option<Schedule<'a>>,
}

/// The friction coefficients in time of a [`SparseStep`].
struct Schedule<'a> {
    base: Vec<f64>,
    steps: Vec<(usize, Vec<f64>)>,
    tangential: Vec<PairTangential<'a>>,
    current: Vec<f64>,
}

impl<'a> SparseStep<'a> {
    /// The system of the bodies' iteration matrices `iterations` (with their node
    /// `points`, the columns' ordering) and the `normal` terms (each pair's candidate body's
    /// term, then its target's at the same offset; pairs in candidate order); `zeros[b]` is a
    /// zero right-hand side of body `b`'s size.
    ///
    /// # Errors
    /// [`DynamicsError::ActiveSet`] (step 0) when the terms do not form pairs in order, a
    /// candidate's force is not on one node of its body, or a node owns candidates of two
    /// pairs that are not frictionless along different axes ([`Bodies::sharing_corners`],
    /// [`Bodies::set_friction`]).
    pub fn new(
        iterations: &'a [Iteration<'_>],
        points: &[&'a [Point]],
        zeros: &'a [Vec<f64>],
        normal: &[Term<'a>],
        candidates: usize,
        friction: Option<&Friction<'a>>,
    ) -> Result<Self, DynamicsError> {
        let refused = |e| DynamicsError::ActiveSet { step: 0, cause: e };
        let unsupported = || refused(ActiveSetError::Unsupported { candidate: 0 });
        let any: &'a BodyOperator = normal.first().ok_or_else(unsupported)?.operator;
        let bodies = iterations
            .iter()
            .zip(points)
            .zip(zeros)
            .map(|((it, &points), rhs)| BodyParts {
                matrix: it.matrix(),
                rhs,
                factorisation: &it.factorisation,
                operator: any,
                points: Some(points),
            })
            .collect();
        let grouped = pairs_of(normal, candidates).ok_or_else(unsupported)?;
        let pairs = grouped
            .iter()
            .map(|&(term, target)| PairParts {
                body: term.body,
                operator: term.operator,
                target: target.map(|t| (t.body, t.operator)),
                scale: iterations[term.body].gap_row_scale(),
            })
            .collect();
        let gaps = vec![0.0; candidates];
        let mut system = Bodies::sharing_corners(bodies, pairs, &gaps).map_err(refused)?;
        let mut schedule = None;
        let friction = match friction {
            Some(f) => {
                let tangential: Vec<PairTangential<'a>> = pairs_of(&f.terms, candidates)
                    .filter(|t| t.len() == grouped.len())
                    .ok_or_else(unsupported)?
                    .into_iter()
                    .map(|(t1, t2)| (t1.operator, t2.map(|t| t.operator)))
                    .collect();
                let first = f.at_step(1).to_vec();
                if !f.schedule.is_empty() {
                    schedule = Some(Schedule {
                        base: f.coefficients.clone(),
                        steps: f.schedule.clone(),
                        tangential: tangential.clone(),
                        current: first.clone(),
                    });
                }
                system.set_friction(&first, tangential).map_err(refused)?;
                Some((f.terms.clone(), vec![ContactState::Stick; candidates]))
            }
            None => None,
        };
        Ok(Self { system, gaps, friction, schedule })
    }

    /// The step on the index set `active` (not empty): each body's velocity `v_b⁺` and the
    /// impulses, from the free step's right-hand sides `rhs` and the velocities `v` at the
    /// step's start; with moving obstacles (`obstacle`) the gap rows hold the velocities
    /// relative to theirs, `g0_c = (1 + e) U_c − ν_c·(w_{n+1} + e w_n)`, and the stick rows
    /// `G_t Δv = t_c·w_{n+1} − U_t` (docs/method.md §10.6).
    ///
    /// # Errors
    /// [`DynamicsError::ActiveSet`] when the active-set method fails.
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        impacts: &Impacts<'_>,
        active: &[usize],
        rhs: &[Vec<f64>],
        v: &[&[f64]],
        restitution: f64,
        step: usize,
        obstacle: Option<&ObstacleStep<'_>>,
    ) -> Result<(Vec<Vec<f64>>, StepImpulses), DynamicsError> {
        let failed = |e| DynamicsError::ActiveSet { step, cause: e };
        for (b, r) in rhs.iter().enumerate() {
            self.system.set_body_load(b, r);
        }
        let u = impacts.normal_velocities(v);
        self.gaps.iter_mut().for_each(|g| *g = 0.0);
        for &c in active {
            self.gaps[c] = (1.0 + restitution) * u[c];
        }
        if let Some(o) = obstacle {
            let (end, start) = (o.along(o.end_velocity), o.along(o.start_velocity));
            for &c in active {
                self.gaps[c] -= end[c] + restitution * start[c];
            }
        }
        self.system.set_initial_gap(&self.gaps);
        let m = self.gaps.len();
        if let Some(s) = &mut self.schedule {
            let mu = coefficients_at(&s.base, &s.steps, step);
            if mu != s.current.as_slice() {
                self.system.set_friction(mu, s.tangential.clone()).map_err(failed)?;
                s.current = mu.to_vec();
            }
        }
        if let Some((terms, last)) = &mut self.friction {
            let moving = obstacle.map(|o| o.across(o.end_velocity));
            return frictional(&mut self.system, terms, last, active, v, moving, step);
        }
        let mut on = OnSet { inner: &mut self.system, set: active, m };
        let answer = solve(&mut on, &ActiveSetParams::default()).map_err(failed)?;
        let closed = on.expand(&answer.active);
        let dv = self.system.final_body_displacements(&closed).map_err(failed)?;
        let velocities = v
            .iter()
            .zip(dv)
            .map(|(v, dv)| v.iter().zip(&dv).map(|(v, dv)| v + dv).collect())
            .collect();
        let mut impulses = vec![0.0; m];
        for (&c, z) in active.iter().zip(&answer.lcp.z) {
            impulses[c] = *z;
        }
        Ok((
            velocities,
            StepImpulses {
                impulses,
                tangential: Vec::new(),
                active: active.len(),
                pivots: answer.iterations,
                residual: answer.lcp.residuals.max_violation(),
            },
        ))
    }
}

/// Each pair's terms, the candidate body's and the target's (same offset, next in `terms`),
/// when the pairs follow each other from candidate 0 to `candidates`.
fn pairs_of<'a>(
    terms: &[Term<'a>],
    candidates: usize,
) -> Option<Vec<(Term<'a>, Option<Term<'a>>)>> {
    let (mut pairs, mut next, mut k) = (Vec::new(), 0, 0);
    while k < terms.len() {
        let term = terms[k];
        if term.offset != next {
            return None;
        }
        let target = terms.get(k + 1).filter(|t| t.offset == term.offset).copied();
        k += 1 + usize::from(target.is_some());
        next += term.operator.len();
        pairs.push((term, target));
    }
    (next == candidates).then_some(pairs)
}

/// The frictional step on the index set `active` (Moreau's law at the velocity level, as
/// Lemke's `Impacts` step): the stick rows hold `G_t Δv = −U_t` (`U_t = Σ G_t,b v_b` at the
/// step's start, so the slip increment `s − s_prev` is the end-of-step tangential velocity
/// `U_t⁺`), started from each candidate's state at its last step in the set (stick when
/// new); relative to a moving obstacle's tangential velocity `moving` (`t_c·w_{n+1}` per
/// candidate); the gaps and loads are set by the caller.
fn frictional(
    system: &mut Bodies<'_>,
    terms: &[Term<'_>],
    last: &mut [ContactState],
    active: &[usize],
    v: &[&[f64]],
    moving: Option<Vec<f64>>,
    step: usize,
) -> Result<(Vec<Vec<f64>>, StepImpulses), DynamicsError> {
    let failed = |e| DynamicsError::ActiveSet { step, cause: e };
    let m = last.len();
    let mut u_t = vec![0.0; m];
    for t in terms {
        let g = t.operator.gap_contribution(v[t.body]);
        u_t[t.offset..].iter_mut().zip(g).for_each(|(u, g)| *u += g);
    }
    if let Some(w) = moving {
        u_t.iter_mut().zip(w).for_each(|(u, w)| *u -= w);
    }
    let previous: Vec<f64> = active.iter().map(|&c| -u_t[c]).collect();
    let start: Vec<ContactState> = active.iter().map(|&c| last[c]).collect();
    let mut on = OnSet { inner: system, set: active, m };
    let answer = solve_friction_step(&mut on, &previous, Some(&start), &ActiveSetParams::default())
        .map_err(failed)?;
    let states = on.expand_states(&answer.states);
    for (&c, &s) in active.iter().zip(&answer.states) {
        last[c] = s;
    }
    let dv = system.final_body_friction_displacements(&states).map_err(failed)?;
    let velocities =
        v.iter().zip(dv).map(|(v, dv)| v.iter().zip(&dv).map(|(v, dv)| v + dv).collect()).collect();
    let (mut impulses, mut tangential) = (vec![0.0; m], vec![0.0; m]);
    for (k, &c) in active.iter().enumerate() {
        impulses[c] = answer.step.normal[k];
        tangential[c] = answer.step.tangential[k];
    }
    Ok((
        velocities,
        StepImpulses {
            impulses,
            tangential,
            active: active.len(),
            pivots: answer.step.iterations,
            residual: answer.step.residuals.max(),
        },
    ))
}

/// The candidates `set` of a system of `m` as a problem of their own, the others held open.
struct OnSet<'s, 'a> {
    inner: &'s mut Bodies<'a>,
    set: &'s [usize],
    m: usize,
}

impl OnSet<'_, '_> {
    /// `active` on the set as a status of all `m` candidates (open off the set).
    fn expand(&self, active: &[bool]) -> Vec<bool> {
        let mut all = vec![false; self.m];
        for (&c, &a) in self.set.iter().zip(active) {
            all[c] = a;
        }
        all
    }

    fn restrict(&self, x: &[f64]) -> Vec<f64> {
        self.set.iter().map(|&c| x[c]).collect()
    }

    /// `states` on the set as the states of all `m` candidates (open off the set).
    fn expand_states(&self, states: &[ContactState]) -> Vec<ContactState> {
        let mut all = vec![ContactState::Open; self.m];
        for (&c, &s) in self.set.iter().zip(states) {
            all[c] = s;
        }
        all
    }

    /// `x` on the set as values of all `m` candidates (0 off the set).
    fn expand_values(&self, x: &[f64]) -> Vec<f64> {
        let mut all = vec![0.0; self.m];
        for (&c, &v) in self.set.iter().zip(x) {
            all[c] = v;
        }
        all
    }
}

impl FrictionSystem for OnSet<'_, '_> {
    fn size(&self) -> usize {
        self.set.len()
    }
    fn friction(&self) -> Vec<f64> {
        self.restrict(&FrictionSystem::friction(&*self.inner))
    }
    /// `None`: the step starts from the last states (see [`ActiveSetSystem::free_gap`]).
    fn free_response(&mut self) -> Result<Option<FreeResponse>, ActiveSetError> {
        Ok(None)
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.restrict(&FrictionSystem::initial_gap(&*self.inner))
    }
    fn solve_states(
        &mut self,
        states: &[ContactState],
        previous: &[f64],
    ) -> Result<StateResponse, ActiveSetError> {
        let (all, previous) = (self.expand_states(states), self.expand_values(previous));
        let r = self.inner.solve_states(&all, &previous)?;
        Ok(StateResponse {
            normal: self.restrict(&r.normal),
            tangential: self.restrict(&r.tangential),
            gap: self.restrict(&r.gap),
            tangential_displacement: self.restrict(&r.tangential_displacement),
        })
    }
    fn reduced_problem(
        &mut self,
        states: &[ContactState],
        free: &[usize],
        previous: &[f64],
    ) -> Result<FrictionProblem, ActiveSetError> {
        let (all, previous) = (self.expand_states(states), self.expand_values(previous));
        let free: Vec<usize> = free.iter().map(|&k| self.set[k]).collect();
        self.inner.reduced_problem(&all, &free, &previous)
    }
}

impl ActiveSetSystem for OnSet<'_, '_> {
    fn size(&self) -> usize {
        self.set.len()
    }
    /// `None`: the method starts from the whole index set closed (every candidate of `A`
    /// has a predicted gap `≤ 0`, so most close; a step of a lasting contact then takes one
    /// solve) and measures its scales against `g0 = (1 + e) U` instead of the free gap, whose
    /// solve would double a step's cost.
    fn free_gap(&mut self) -> Result<Option<Vec<f64>>, ActiveSetError> {
        Ok(None)
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.restrict(&ActiveSetSystem::initial_gap(&*self.inner))
    }
    fn solve_active(&mut self, active: &[bool]) -> Result<(Vec<f64>, Vec<f64>), ActiveSetError> {
        let all = self.expand(active);
        let (p, g) = self.inner.solve_active(&all)?;
        Ok((self.restrict(&p), self.restrict(&g)))
    }
    fn reduced_lcp(&mut self, active: &[bool], free: &[usize]) -> Result<Lcp, ActiveSetError> {
        let all = self.expand(active);
        let free: Vec<usize> = free.iter().map(|&k| self.set[k]).collect();
        self.inner.reduced_lcp(&all, &free)
    }
}
