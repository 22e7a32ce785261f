//! Contact at the velocity level (docs/method.md §10.3): the condensed operator
//! `W = G M̂⁻¹ E` formed once per run, the index set from the predicted gaps, and each step's
//! LCP in the impulses, solved by Lemke's method.

use super::{DynamicsError, Iteration};
use crate::contact::BodyOperator;
use crate::lcp::{FrictionProblem, Lcp, LemkeParams, lemke, solve_step};

/// The candidates of one body against rigid obstacles, condensed with `M̂`.
pub struct Impacts<'a> {
    operator: &'a BodyOperator,
    initial_gap: &'a [f64],
    /// `Y = M̂⁻¹ E`, one column per candidate.
    columns: Vec<Vec<f64>>,
    /// `W = G Y`, row-major `m × m`.
    compliance: Vec<f64>,
    /// Coulomb friction at the velocity level (`None`: frictionless).
    friction: Option<Tangential<'a>>,
}

/// The tangential side of the candidates, condensed with `M̂`.
struct Tangential<'a> {
    /// `G_t`, `E_t` (direction `t` per candidate).
    operator: &'a BodyOperator,
    /// `μ_c` per candidate.
    coefficients: Vec<f64>,
    /// `Y_t = M̂⁻¹ E_t`, one column per candidate.
    columns: Vec<Vec<f64>>,
    /// `W_nt = G Y_t`, `W_tn = G_t Y`, `W_tt = G_t Y_t`, row-major `m × m`.
    nt: Vec<f64>,
    tn: Vec<f64>,
    tt: Vec<f64>,
}

/// Coulomb friction for [`Impacts::new`]: the tangential operator and `μ` per candidate.
pub struct Friction<'a> {
    /// `G_t`, `E_t`.
    pub operator: &'a BodyOperator,
    /// `μ_c ≥ 0` (0: frictionless candidate).
    pub coefficients: Vec<f64>,
}

/// One step's contact answer.
pub struct StepImpulses {
    /// The impulse `Π_c ≥ 0` of every candidate over the step (0 off the index set).
    pub impulses: Vec<f64>,
    /// The tangential impulse `Π_t,c` (along `t`; empty when frictionless).
    pub tangential: Vec<f64>,
    /// Candidates in the index set.
    pub active: usize,
    /// Lemke's pivots.
    pub pivots: usize,
    /// The step LCP's largest scaled residual (complementarity, signs; 0 without contact).
    pub residual: f64,
}

impl<'a> Impacts<'a> {
    /// Condenses `operator` (the candidates' `G` and `E`), and the tangential operator of
    /// `friction`, with the iteration matrix.
    ///
    /// # Errors
    /// [`DynamicsError::Solve`] when a solve fails.
    pub fn new(
        iteration: &Iteration<'_>,
        operator: &'a BodyOperator,
        initial_gap: &'a [f64],
        friction: Option<Friction<'a>>,
        dofs: usize,
    ) -> Result<Self, DynamicsError> {
        let columns = condensed_columns(iteration, operator, dofs)?;
        let compliance = block(operator, &columns);
        let friction = match friction {
            Some(f) => {
                let t = condensed_columns(iteration, f.operator, dofs)?;
                Some(Tangential {
                    nt: block(operator, &t),
                    tn: block(f.operator, &columns),
                    tt: block(f.operator, &t),
                    operator: f.operator,
                    coefficients: f.coefficients,
                    columns: t,
                })
            }
            None => None,
        };
        Ok(Self { operator, initial_gap, columns, compliance, friction })
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
            return Ok(StepImpulses {
                impulses,
                tangential: Vec::new(),
                active: 0,
                pivots: 0,
                residual: 0.0,
            });
        }
        let (u_free, u) = (self.normal_velocities(v_free), self.normal_velocities(v));
        let q: Vec<f64> = active.iter().map(|&c| u_free[c] + restitution * u[c]).collect();
        if let Some(f) =
            self.friction.as_ref().filter(|f| active.iter().any(|&c| f.coefficients[c] > 0.0))
        {
            return self.frictional(f, active, q, v_free, step);
        }
        let (z, pivots, residual) = self.solve_on(active, q, step)?;
        for (&c, z) in active.iter().zip(&z) {
            impulses[c] = *z;
        }
        Ok(StepImpulses {
            impulses,
            tangential: Vec::new(),
            active: active.len(),
            pivots,
            residual,
        })
    }

    /// Moreau's frictional law on the index set: the normal law of [`Self::impulses`]
    /// (`q_n = U_free + e U`) and Coulomb's on the tangential velocities
    /// `U_t = G_t v_free + W_tn Π + W_tt Π_t`: stick (`U_t = 0`, `|Π_t| ≤ μ Π`) or slide
    /// (`Π_t = −μ Π sign U_t`) — the step LCP of the static friction ([`solve_step`]) with the
    /// velocities in place of the displacement increments (`s_prev = 0`).
    fn frictional(
        &self,
        f: &Tangential<'_>,
        active: &[usize],
        q_n: Vec<f64>,
        v_free: &[f64],
        step: usize,
    ) -> Result<StepImpulses, DynamicsError> {
        let m = self.len();
        let u_t = f.operator.gap_contribution(v_free);
        let sub = |b: &[f64]| -> Vec<f64> {
            active.iter().flat_map(|&r| active.iter().map(move |&c| b[r * m + c])).collect()
        };
        let problem = FrictionProblem {
            nn: sub(&self.compliance),
            nt: sub(&f.nt),
            tn: sub(&f.tn),
            tt: sub(&f.tt),
            free_gap: q_n,
            free_tangential: active.iter().map(|&c| u_t[c]).collect(),
            previous_tangential: vec![0.0; active.len()],
            friction: active.iter().map(|&c| f.coefficients[c]).collect(),
        };
        let answer = solve_step(&problem).map_err(|e| DynamicsError::Lcp { step, source: e })?;
        let (mut impulses, mut tangential) = (vec![0.0; m], vec![0.0; m]);
        for (k, &c) in active.iter().enumerate() {
            impulses[c] = answer.normal[k];
            tangential[c] = answer.tangential[k];
        }
        Ok(StepImpulses {
            impulses,
            tangential,
            active: active.len(),
            pivots: answer.pivots,
            residual: answer.residuals.max(),
        })
    }

    /// Lemke's answer to `0 ≤ z ⊥ W_SS z + q ≥ 0` on the candidates `set`, with its pivots and
    /// its largest scaled residual.
    fn solve_on(
        &self,
        set: &[usize],
        q: Vec<f64>,
        step: usize,
    ) -> Result<(Vec<f64>, usize, f64), DynamicsError> {
        solve_on(&self.compliance, self.len(), set, q, step)
    }

    /// `v_free + M̂⁻¹ (E Π + E_t Π_t)` (`tangential` empty: no friction).
    pub fn apply(&self, v_free: &[f64], impulses: &[f64], tangential: &[f64]) -> Vec<f64> {
        let mut v = v_free.to_vec();
        let t_columns = self.friction.as_ref().map_or(&[][..], |f| &f.columns[..]);
        let pairs = self.columns.iter().zip(impulses).chain(t_columns.iter().zip(tangential));
        for (y, &p) in pairs {
            if p != 0.0 {
                for (v, y) in v.iter_mut().zip(y) {
                    *v += p * y;
                }
            }
        }
        v
    }

    /// The work of the impulses on the velocity `v`: `(E Π + E_t Π_t)ᵀ v`.
    pub fn work(&self, impulses: &[f64], tangential: &[f64], v: &[f64]) -> f64 {
        let mut e = vec![0.0; v.len()];
        self.operator.add_forces(impulses, &mut e);
        if let (Some(f), false) = (&self.friction, tangential.is_empty()) {
            f.operator.add_forces(tangential, &mut e);
        }
        e.iter().zip(v).map(|(e, v)| e * v).sum()
    }
}

/// Lemke's answer to `0 ≤ z ⊥ W_SS z + q ≥ 0` on the candidates `set` of the `m × m`
/// row-major `compliance`, with its pivots and its largest scaled residual
/// ([`crate::lcp::LcpResiduals::max_violation`]).
pub(super) fn solve_on(
    compliance: &[f64],
    m: usize,
    set: &[usize],
    q: Vec<f64>,
    step: usize,
) -> Result<(Vec<f64>, usize, f64), DynamicsError> {
    let w: Vec<f64> = set
        .iter()
        .flat_map(|&r| set.iter().map(move |&c| (r, c)))
        .map(|(r, c)| compliance[r * m + c])
        .collect();
    let lcp = Lcp::new(set.len(), w, q).map_err(|e| DynamicsError::Lcp { step, source: e })?;
    let answer =
        lemke(&lcp, &LemkeParams::default()).map_err(|e| DynamicsError::Lcp { step, source: e })?;
    Ok((answer.z, answer.pivots, answer.residuals.max_violation()))
}

/// `M̂⁻¹ E_c` for every candidate `c` of `operator`.
pub(super) fn condensed_columns(
    iteration: &Iteration<'_>,
    operator: &BodyOperator,
    dofs: usize,
) -> Result<Vec<Vec<f64>>, DynamicsError> {
    let m = operator.len();
    (0..m)
        .map(|c| {
            let mut unit = vec![0.0; m];
            unit[c] = 1.0;
            let mut e = vec![0.0; dofs];
            operator.add_forces(&unit, &mut e);
            iteration.solve(&e)
        })
        .collect()
}

/// `G Y` for the rows of `operator` and the columns `Y`, row-major `m × m`.
pub(super) fn block(operator: &BodyOperator, columns: &[Vec<f64>]) -> Vec<f64> {
    let m = columns.len();
    let mut w = vec![0.0; m * m];
    for (c, y) in columns.iter().enumerate() {
        for (r, g) in operator.gap_contribution(y).into_iter().enumerate() {
            w[r * m + c] = g;
        }
    }
    w
}
