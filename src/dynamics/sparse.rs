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
//! The method starts from every candidate of `A` closed (the index set as the first guess;
//! the system's free solve is skipped, see [`OnSet`]'s `free_gap`): on the bar of
//! docs/dev/dynamics.md every contact step then settles in one solve.

use super::impacts::StepImpulses;
use super::{DynamicsError, Impacts, Iteration, Term};
use crate::contact::BodyOperator;
use crate::contact::sparse::{Bodies, BodyParts, PairParts};
use crate::geometry::Point;
use crate::lcp::Lcp;
use crate::lcp::active_set::{ActiveSetError, ActiveSetParams, ActiveSetSystem, solve};

/// The sparse system of the bodies' `M̂` and the contact pairs.
pub(super) struct SparseStep<'a> {
    system: Bodies<'a>,
    /// Every candidate's `g0` held for [`Bodies::set_initial_gap`].
    gaps: Vec<f64>,
}

impl<'a> SparseStep<'a> {
    /// The system of the bodies' iteration matrices `iterations` (with their node
    /// `points`, the columns' ordering) and the `normal` terms (each pair's candidate body's
    /// term, then its target's at the same offset; pairs in candidate order); `zeros[b]` is a
    /// zero right-hand side of body `b`'s size.
    ///
    /// # Errors
    /// [`DynamicsError::ActiveSet`] (step 0) when the terms do not form pairs in order, or a
    /// candidate's force is not on one node of its body ([`Bodies::new`]).
    pub fn new(
        iterations: &'a [Iteration<'_>],
        points: &[&'a [Point]],
        zeros: &'a [Vec<f64>],
        normal: &[Term<'a>],
        candidates: usize,
    ) -> Result<Self, DynamicsError> {
        let refused = |e| DynamicsError::ActiveSet { step: 0, source: e };
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
        let mut pairs: Vec<PairParts<'a>> = Vec::new();
        let mut next = 0;
        let mut k = 0;
        while k < normal.len() {
            let term = normal[k];
            if term.offset != next {
                return Err(unsupported());
            }
            let target = match normal.get(k + 1) {
                Some(t) if t.offset == term.offset => {
                    k += 1;
                    Some((t.body, t.operator))
                }
                _ => None,
            };
            pairs.push(PairParts {
                body: term.body,
                operator: term.operator,
                target,
                scale: iterations[term.body].gap_row_scale(),
            });
            next += term.operator.len();
            k += 1;
        }
        if next != candidates {
            return Err(unsupported());
        }
        let gaps = vec![0.0; candidates];
        let system = Bodies::new(bodies, pairs, &gaps).map_err(refused)?;
        Ok(Self { system, gaps })
    }

    /// The step on the index set `active` (not empty): each body's velocity `v_b⁺` and the
    /// impulses, from the free step's right-hand sides `rhs` and the velocities `v` at the
    /// step's start.
    ///
    /// # Errors
    /// [`DynamicsError::ActiveSet`] when the active-set method fails.
    pub fn step(
        &mut self,
        impacts: &Impacts<'_>,
        active: &[usize],
        rhs: &[Vec<f64>],
        v: &[&[f64]],
        restitution: f64,
        step: usize,
    ) -> Result<(Vec<Vec<f64>>, StepImpulses), DynamicsError> {
        let failed = |e| DynamicsError::ActiveSet { step, source: e };
        for (b, r) in rhs.iter().enumerate() {
            self.system.set_body_load(b, r);
        }
        let u = impacts.normal_velocities(v);
        self.gaps.iter_mut().for_each(|g| *g = 0.0);
        for &c in active {
            self.gaps[c] = (1.0 + restitution) * u[c];
        }
        self.system.set_initial_gap(&self.gaps);
        let m = self.gaps.len();
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
        self.restrict(&self.inner.initial_gap())
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
