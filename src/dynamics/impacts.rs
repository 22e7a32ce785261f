//! Contact at the velocity level (docs/method.md §10.3): the condensed operator
//! `W = G M̂⁻¹ E` formed once per run, the index set from the predicted gaps, and each step's
//! LCP in the impulses, solved by Lemke's method.

use super::{DynamicsError, Iteration};
use crate::contact::BodyOperator;
use crate::lcp::{Lcp, LemkeParams, lemke};

/// The candidates of one body against rigid obstacles, condensed with `M̂`.
pub struct Impacts<'a> {
    operator: &'a BodyOperator,
    initial_gap: &'a [f64],
    /// `Y = M̂⁻¹ E`, one column per candidate.
    columns: Vec<Vec<f64>>,
    /// `W = G Y`, row-major `m × m`.
    compliance: Vec<f64>,
}

/// One step's contact answer.
pub struct StepImpulses {
    /// The impulse `Π_c ≥ 0` of every candidate over the step (0 off the index set).
    pub impulses: Vec<f64>,
    /// Candidates in the index set.
    pub active: usize,
    /// Lemke's pivots.
    pub pivots: usize,
}

impl<'a> Impacts<'a> {
    /// Condenses `operator` (the candidates' `G` and `E`) with the iteration matrix.
    ///
    /// # Errors
    /// [`DynamicsError::Solve`] when a solve fails.
    pub fn new(
        iteration: &Iteration<'_>,
        operator: &'a BodyOperator,
        initial_gap: &'a [f64],
        dofs: usize,
    ) -> Result<Self, DynamicsError> {
        let m = operator.len();
        let mut columns = Vec::with_capacity(m);
        for c in 0..m {
            let mut unit = vec![0.0; m];
            unit[c] = 1.0;
            let mut e = vec![0.0; dofs];
            operator.add_forces(&unit, &mut e);
            columns.push(iteration.solve(&e)?);
        }
        let mut compliance = vec![0.0; m * m];
        for (c, y) in columns.iter().enumerate() {
            for (r, g) in operator.gap_contribution(y).into_iter().enumerate() {
                compliance[r * m + c] = g;
            }
        }
        Ok(Self { operator, initial_gap, columns, compliance })
    }

    /// Number of candidates.
    pub fn len(&self) -> usize {
        self.initial_gap.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.initial_gap.is_empty()
    }

    /// The gaps `g0 + G q`.
    pub fn gaps(&self, q: &[f64]) -> Vec<f64> {
        let gq = self.operator.gap_contribution(q);
        self.initial_gap.iter().zip(gq).map(|(g0, g)| g0 + g).collect()
    }

    /// The normal velocities `G v` (the gaps' rates).
    pub fn normal_velocities(&self, v: &[f64]) -> Vec<f64> {
        self.operator.gap_contribution(v)
    }

    /// The index set of Moreau–Jean: the candidates whose gap predicted half a step ahead,
    /// `g0 + G (q + h/2 v)`, is not positive.
    pub fn index_set(&self, q: &[f64], v: &[f64], h: f64) -> Vec<usize> {
        let ahead: Vec<f64> = q.iter().zip(v).map(|(q, v)| q + 0.5 * h * v).collect();
        let g = self.gaps(&ahead);
        (0..g.len()).filter(|&c| g[c] <= 0.0).collect()
    }

    /// The impulses on the index set `active`: `0 ≤ Π ⊥ U⁺ + e U ≥ 0` with
    /// `U⁺ = G v_free + W Π` (Newton's impact law at the velocity level), `U = G v` at the
    /// step's start.
    ///
    /// # Errors
    /// [`DynamicsError::Lcp`] when Lemke's method fails.
    pub fn impulses(
        &self,
        active: &[usize],
        v_free: &[f64],
        v: &[f64],
        restitution: f64,
        step: usize,
    ) -> Result<StepImpulses, DynamicsError> {
        let m = self.len();
        let mut impulses = vec![0.0; m];
        if active.is_empty() {
            return Ok(StepImpulses { impulses, active: 0, pivots: 0 });
        }
        let (u_free, u) = (self.normal_velocities(v_free), self.normal_velocities(v));
        let q: Vec<f64> = active.iter().map(|&c| u_free[c] + restitution * u[c]).collect();
        let (z, pivots) = self.solve_on(active, q, step)?;
        for (&c, z) in active.iter().zip(&z) {
            impulses[c] = *z;
        }
        Ok(StepImpulses { impulses, active: active.len(), pivots })
    }

    /// Lemke's answer to `0 ≤ z ⊥ W_SS z + q ≥ 0` on the candidates `set`, with its pivots.
    fn solve_on(
        &self,
        set: &[usize],
        q: Vec<f64>,
        step: usize,
    ) -> Result<(Vec<f64>, usize), DynamicsError> {
        let m = self.len();
        let w: Vec<f64> = set
            .iter()
            .flat_map(|&r| set.iter().map(move |&c| (r, c)))
            .map(|(r, c)| self.compliance[r * m + c])
            .collect();
        let lcp = Lcp::new(set.len(), w, q).map_err(|e| DynamicsError::Lcp { step, source: e })?;
        let answer = lemke(&lcp, &LemkeParams::default())
            .map_err(|e| DynamicsError::Lcp { step, source: e })?;
        Ok((answer.z, answer.pivots))
    }

    /// `v_free + M̂⁻¹ E Π`.
    pub fn apply(&self, v_free: &[f64], impulses: &[f64]) -> Vec<f64> {
        let mut v = v_free.to_vec();
        for (y, &p) in self.columns.iter().zip(impulses) {
            if p != 0.0 {
                for (v, y) in v.iter_mut().zip(y) {
                    *v += p * y;
                }
            }
        }
        v
    }

    /// The work of the impulses on the velocity `v`: `Πᵀ Eᵀ v`.
    pub fn work(&self, impulses: &[f64], v: &[f64]) -> f64 {
        let mut e = vec![0.0; v.len()];
        self.operator.add_forces(impulses, &mut e);
        e.iter().zip(v).map(|(e, v)| e * v).sum()
    }
}
