//! Contact at the velocity level (docs/method.md §10.3): the condensed operator
//! `W = Σ_b G_b M̂_b⁻¹ E_b` formed once per run, the index set from the predicted gaps, and
//! each step's LCP in the impulses, solved by Lemke's method.
//!
//! The candidates act on the bodies through [`Term`]s: one against rigid obstacles (the body's
//! `G`, `E`), two for a pair of bodies (the candidates' `G₁`, `E₁` and the target's `G₂`, `E₂`
//! with the opposite direction). The gaps' rates `U = Σ_b G_b v_b` and the impulses' velocity
//! changes `M̂_b⁻¹ E_b Π` are sums over the terms.

use super::loads::{ObstacleMotion, ObstacleStep};
use super::{DynamicsError, Iteration};
use crate::contact::BodyOperator;
use crate::lcp::{FrictionProblem, Lcp, LemkeParams, lemke, solve_step};

/// The index set's activation threshold relative to the size of a predicted gap's terms
/// ([`Impacts::index_set`]): far above their round-off (1e-16), far below any gap a step
/// resolves.
pub const ACTIVATION: f64 = 1e-9;

/// The candidates `offset .. offset + operator.len()` acting on body `body` through
/// `operator` (`G` rows, `E` columns).
#[derive(Clone, Copy)]
pub struct Term<'a> {
    /// The body's index.
    pub body: usize,
    /// The first candidate's index among all.
    pub offset: usize,
    /// `G_b`, `E_b` of these candidates.
    pub operator: &'a BodyOperator,
}

/// A term condensed with its body's iteration matrix: `Y = M̂_b⁻¹ E_b`.
struct Condensed<'a> {
    term: Term<'a>,
    /// One column per candidate of the term.
    columns: Vec<Vec<f64>>,
}

/// The candidates against rigid obstacles or between bodies, condensed with each body's `M̂`.
pub struct Impacts<'a> {
    initial_gap: Vec<f64>,
    normal: Vec<Condensed<'a>>,
    /// `W = G Y`, row-major `m × m`.
    compliance: Vec<f64>,
    /// Coulomb friction at the velocity level (`None`: frictionless).
    friction: Option<Tangential<'a>>,
    /// The rigid obstacles' motion in time (`None`: at rest; docs/method.md §10.6).
    obstacle: Option<ObstacleMotion>,
}

/// The tangential side of the candidates, condensed with `M̂`.
struct Tangential<'a> {
    /// `G_t`, `E_t` (direction `t` per candidate, `−t` on a pair's target) with `Y_t`.
    terms: Vec<Condensed<'a>>,
    /// `μ_c` per candidate.
    coefficients: Vec<f64>,
    /// The coefficients in time ([`Friction::schedule`]).
    schedule: Vec<(usize, Vec<f64>)>,
    /// `W_nt = G Y_t`, `W_tn = G_t Y`, `W_tt = G_t Y_t`, row-major `m × m`.
    nt: Vec<f64>,
    tn: Vec<f64>,
    tt: Vec<f64>,
}

/// Coulomb friction for [`Impacts::new`]: the tangential terms and `μ` per candidate.
#[derive(Clone)]
pub struct Friction<'a> {
    /// `G_t`, `E_t` of each term of the normal side, in the same order.
    pub terms: Vec<Term<'a>>,
    /// `μ_c ≥ 0` (0: frictionless candidate).
    pub coefficients: Vec<f64>,
    /// The coefficients in time (`[[step]] friction` with `time`, docs/method.md §10.6):
    /// `(n_k, μ_c)`, the coefficients of the time steps up to `n_k` (from 1; after the
    /// previous entry's), the last entry's after it; empty: `coefficients` throughout.
    pub schedule: Vec<(usize, Vec<f64>)>,
}

impl Friction<'_> {
    /// The coefficients of time step `step` (from 1).
    pub fn at_step(&self, step: usize) -> &[f64] {
        coefficients_at(&self.coefficients, &self.schedule, step)
    }
}

/// `base`, or the coefficients `schedule` gives time step `step` ([`Friction::schedule`]).
pub(super) fn coefficients_at<'s>(
    base: &'s [f64],
    schedule: &'s [(usize, Vec<f64>)],
    step: usize,
) -> &'s [f64] {
    match schedule.iter().find(|(n, _)| step <= *n).or(schedule.last()) {
        Some((_, mu)) => mu,
        None => base,
    }
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

impl StepImpulses {
    /// No candidate in the index set, among `m`.
    pub(super) fn none(m: usize) -> Self {
        Self { impulses: vec![0.0; m], tangential: Vec::new(), active: 0, pivots: 0, residual: 0.0 }
    }
}

impl<'a> Impacts<'a> {
    /// Condenses the `normal` terms (the candidates' `G` and `E` on each body), and the
    /// tangential terms of `friction`, with the bodies' iteration matrices `iterations`;
    /// `initial_gap` has one gap per candidate.
    ///
    /// # Errors
    /// [`DynamicsError::Solve`] when a solve fails.
    pub fn new(
        iterations: &[Iteration<'_>],
        normal: &[Term<'a>],
        initial_gap: Vec<f64>,
        friction: Option<Friction<'a>>,
    ) -> Result<Self, DynamicsError> {
        let m = initial_gap.len();
        let normal = condense(iterations, normal)?;
        let compliance = block(&normal, &normal, m);
        let friction = match friction {
            Some(f) => {
                let t = condense(iterations, &f.terms)?;
                Some(Tangential {
                    nt: block(&normal, &t, m),
                    tn: block(&t, &normal, m),
                    tt: block(&t, &t, m),
                    terms: t,
                    coefficients: f.coefficients,
                    schedule: f.schedule,
                })
            }
            None => None,
        };
        Ok(Self { initial_gap, normal, compliance, friction, obstacle: None })
    }

    /// These candidates with the rigid obstacles moving by `motion` (one entry per
    /// candidate).
    ///
    /// # Panics
    /// When `motion` does not have one entry per candidate (a caller bug).
    pub fn with_obstacle(mut self, motion: Option<ObstacleMotion>) -> Self {
        assert!(motion.as_ref().is_none_or(|m| m.len() == self.len()), "one per candidate");
        self.obstacle = motion;
        self
    }

    /// The obstacle's motion over time step `n → n + 1` of size `h` (`None`: at rest).
    pub fn obstacle_step(&self, n: usize, h: f64) -> Option<ObstacleStep<'_>> {
        self.obstacle.as_ref().map(|m| m.step(n, h))
    }

    /// The candidates of the `normal` terms without `W` (no solve with `M̂`): the index set,
    /// the gaps, their rates and the impulses' work, for a step solved on the sparse system
    /// (`super::sparse`); [`Self::impulses`] and [`Self::apply`] are not available.
    pub(super) fn uncondensed(
        normal: &[Term<'a>],
        initial_gap: Vec<f64>,
        friction: Option<Friction<'a>>,
    ) -> Self {
        let bare = |terms: &[Term<'a>]| -> Vec<Condensed<'a>> {
            terms.iter().map(|&term| Condensed { term, columns: Vec::new() }).collect()
        };
        let friction = friction.map(|f| Tangential {
            terms: bare(&f.terms),
            coefficients: f.coefficients,
            schedule: f.schedule,
            nt: Vec::new(),
            tn: Vec::new(),
            tt: Vec::new(),
        });
        Self { initial_gap, normal: bare(normal), compliance: Vec::new(), friction, obstacle: None }
    }

    /// Number of candidates.
    pub fn len(&self) -> usize {
        self.initial_gap.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.initial_gap.is_empty()
    }

    /// The gaps `g0 + Σ_b G_b q_b` of the bodies' states `q` (the obstacles at rest).
    pub fn gaps(&self, q: &[&[f64]]) -> Vec<f64> {
        let gq = rates(&self.normal, q, self.len());
        self.initial_gap.iter().zip(gq).map(|(g0, g)| g0 + g).collect()
    }

    /// The gaps `g0 + Σ_b G_b q_b − ν_c·d(t)` of the bodies' states `q` at time `t` (the
    /// moving obstacles at `d(t)`).
    pub fn gaps_at(&self, q: &[&[f64]], t: f64) -> Vec<f64> {
        let mut g = self.gaps(q);
        if let Some(m) = &self.obstacle {
            g.iter_mut().zip(m.closing(t)).for_each(|(g, d)| *g -= d);
        }
        g
    }

    /// The relative normal velocities `Σ_b G_b v_b − ν_c·w` with the moving obstacles at
    /// the velocity `w` (`obstacle` and `velocity` of its step; `None`: at rest).
    pub fn relative_velocities(
        &self,
        v: &[&[f64]],
        w: Option<(&ObstacleStep<'_>, [f64; 2])>,
    ) -> Vec<f64> {
        let mut u = self.normal_velocities(v);
        if let Some((o, w)) = w {
            u.iter_mut().zip(o.along(w)).for_each(|(u, w)| *u -= w);
        }
        u
    }

    /// The normal velocities `Σ_b G_b v_b` (the gaps' rates).
    pub fn normal_velocities(&self, v: &[&[f64]]) -> Vec<f64> {
        rates(&self.normal, v, self.len())
    }

    /// The index set of Moreau–Jean: the candidates whose gap predicted half a step ahead,
    /// `g0 + Σ_b G_b (q_b + h/2 v_b)`, is at most [`ACTIVATION`] times the size of the motion
    /// it is computed from (`|g0|` plus, for each body it acts on, `max |q_b| + h max |v_b|`).
    /// A contact resting at a zero gap then stays in the set instead of leaving it on the sign
    /// of the last step's round-off (`U⁺ = 0` to the LCP solver's accuracy: Lemke's polished
    /// answer leaves gaps of 1e-20, the frictional step's 1e-15, enough to flip a `≤ 0` test);
    /// Siconos' "constraint activation threshold", here relative. With moving obstacles
    /// (`obstacle`) the gaps are predicted at the same time, with the obstacle at
    /// `d(t_n + h/2)` (its motion `|d| + h |w|` added to the scale of the moved candidates).
    pub fn index_set(
        &self,
        q: &[&[f64]],
        v: &[&[f64]],
        h: f64,
        obstacle: Option<&ObstacleStep<'_>>,
    ) -> Vec<usize> {
        let ahead: Vec<Vec<f64>> = q
            .iter()
            .zip(v)
            .map(|(q, v)| q.iter().zip(*v).map(|(q, v)| q + 0.5 * h * v).collect())
            .collect();
        let mut g = self.gaps(&ahead.iter().map(Vec::as_slice).collect::<Vec<_>>());
        let largest = |x: &[f64]| x.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        let motion: Vec<f64> = q.iter().zip(v).map(|(q, v)| largest(q) + h * largest(v)).collect();
        let mut scale: Vec<f64> = self.initial_gap.iter().map(|g| g.abs()).collect();
        for t in &self.normal {
            let range = t.term.offset..t.term.offset + t.term.operator.len();
            scale[range].iter_mut().for_each(|s| *s += motion[t.term.body]);
        }
        if let Some(o) = obstacle {
            let own = largest(&o.ahead) + h * largest(&o.end_velocity);
            for (c, d) in o.along(o.ahead).into_iter().enumerate().filter(|&(c, _)| o.moves(c)) {
                g[c] -= d;
                scale[c] += own;
            }
        }
        (0..g.len()).filter(|&c| g[c] <= ACTIVATION * scale[c]).collect()
    }

    /// The impulses on the index set `active`: `0 ≤ Π ⊥ U⁺ + e U ≥ 0` with
    /// `U⁺ = Σ_b G_b v_b,free + W Π` (Newton's impact law at the velocity level),
    /// `U = Σ_b G_b v_b` at the step's start; with moving obstacles (`obstacle`) the
    /// velocities relative to theirs, `U⁺ − ν_c·w_{n+1}` and `U − ν_c·w_n` (docs/method.md
    /// §10.6).
    ///
    /// # Errors
    /// [`DynamicsError::Lcp`] when Lemke's method fails.
    pub fn impulses(
        &self,
        active: &[usize],
        v_free: &[&[f64]],
        v: &[&[f64]],
        restitution: f64,
        step: usize,
        obstacle: Option<&ObstacleStep<'_>>,
    ) -> Result<StepImpulses, DynamicsError> {
        let m = self.len();
        if active.is_empty() {
            return Ok(StepImpulses::none(m));
        }
        let mut impulses = vec![0.0; m];
        let u_free = self.relative_velocities(v_free, obstacle.map(|o| (o, o.end_velocity)));
        let u = self.relative_velocities(v, obstacle.map(|o| (o, o.start_velocity)));
        let q: Vec<f64> = active.iter().map(|&c| u_free[c] + restitution * u[c]).collect();
        let sliding = |f: &&Tangential<'_>| {
            let mu = coefficients_at(&f.coefficients, &f.schedule, step);
            active.iter().any(|&c| mu[c] > 0.0)
        };
        if let Some(f) = self.friction.as_ref().filter(sliding) {
            return self.frictional(f, active, q, v_free, step, obstacle);
        }
        let (z, pivots, residual) = solve_on(&self.compliance, m, active, q, step)?;
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
    /// `U_t = Σ_b G_t,b v_b,free + W_tn Π + W_tt Π_t`: stick (`U_t = 0`, `|Π_t| ≤ μ Π`) or
    /// slide (`Π_t = −μ Π sign U_t`) — the step LCP of the static friction ([`solve_step`])
    /// with the velocities in place of the displacement increments (`s_prev = 0`); relative
    /// to a moving obstacle's `t_c·w_{n+1}` (`obstacle`).
    fn frictional(
        &self,
        f: &Tangential<'_>,
        active: &[usize],
        q_n: Vec<f64>,
        v_free: &[&[f64]],
        step: usize,
        obstacle: Option<&ObstacleStep<'_>>,
    ) -> Result<StepImpulses, DynamicsError> {
        let m = self.len();
        let mut u_t = rates(&f.terms, v_free, m);
        if let Some(o) = obstacle {
            u_t.iter_mut().zip(o.across(o.end_velocity)).for_each(|(u, w)| *u -= w);
        }
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
            friction: {
                let mu = coefficients_at(&f.coefficients, &f.schedule, step);
                active.iter().map(|&c| mu[c]).collect()
            },
        };
        let answer = solve_step(&problem).map_err(|e| DynamicsError::Lcp { step, cause: e })?;
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

    /// The terms on body `b`, normal then tangential, with their impulses (`tangential` empty:
    /// no friction).
    fn on_body<'s>(
        &'s self,
        b: usize,
        impulses: &'s [f64],
        tangential: &'s [f64],
    ) -> impl Iterator<Item = (&'s Condensed<'a>, &'s [f64])> {
        let t_terms = self.friction.as_ref().filter(|_| !tangential.is_empty());
        let normal = self.normal.iter().map(move |t| (t, impulses));
        let t = t_terms.into_iter().flat_map(|f| f.terms.iter()).map(move |t| (t, tangential));
        normal.chain(t).filter(move |(t, _)| t.term.body == b).map(|(t, p)| {
            let o = t.term.offset;
            (t, &p[o..o + t.term.operator.len()])
        })
    }

    /// Body `b`'s velocity `v_free + M̂_b⁻¹ (E_b Π + E_t,b Π_t)`.
    pub fn apply(
        &self,
        b: usize,
        v_free: Vec<f64>,
        impulses: &[f64],
        tangential: &[f64],
    ) -> Vec<f64> {
        let mut v = v_free;
        for (t, p) in self.on_body(b, impulses, tangential) {
            for (y, &p) in t.columns.iter().zip(p) {
                if p != 0.0 {
                    for (v, y) in v.iter_mut().zip(y) {
                        *v += p * y;
                    }
                }
            }
        }
        v
    }

    /// The work of the impulses on body `b`'s velocity `v`: `(E_b Π + E_t,b Π_t)ᵀ v`.
    pub fn work(&self, b: usize, impulses: &[f64], tangential: &[f64], v: &[f64]) -> f64 {
        let e = self.forces(b, impulses, tangential, v.len());
        e.iter().zip(v).map(|(e, v)| e * v).sum()
    }

    /// The work of the impulses of the moved candidates on body `b` along the obstacle's
    /// displacement over the step `Δd` (`obstacle.displacement`): `(E_b Π + E_t,b Π_t)ᵀ D`
    /// with `D` the uniform `Δd` at every node and `Π` zero off the moved candidates — the
    /// obstacle's work on the body times `h` (docs/method.md §10.6).
    pub fn obstacle_work(
        &self,
        b: usize,
        impulses: &[f64],
        tangential: &[f64],
        n: usize,
        obstacle: &ObstacleStep<'_>,
    ) -> f64 {
        let moved = |p: &[f64]| -> Vec<f64> {
            p.iter().enumerate().map(|(c, &p)| if obstacle.moves(c) { p } else { 0.0 }).collect()
        };
        let uniform: Vec<f64> = (0..n).map(|d| obstacle.displacement[d % 2]).collect();
        self.work(b, &moved(impulses), &moved(tangential), &uniform)
    }

    /// `E Π` on body `b` (`n` DOFs): the impulses' contributions to its rows.
    pub fn forces(&self, b: usize, impulses: &[f64], tangential: &[f64], n: usize) -> Vec<f64> {
        let mut e = vec![0.0; n];
        for (t, p) in self.on_body(b, impulses, tangential) {
            t.term.operator.add_forces(p, &mut e);
        }
        e
    }
}

/// `Σ_terms G_t x_body` placed at each term's candidates (`m` in all).
fn rates(terms: &[Condensed<'_>], x: &[&[f64]], m: usize) -> Vec<f64> {
    let mut r = vec![0.0; m];
    for t in terms {
        let g = t.term.operator.gap_contribution(x[t.term.body]);
        for (r, g) in r[t.term.offset..].iter_mut().zip(g) {
            *r += g;
        }
    }
    r
}

/// Lemke's answer to `0 ≤ z ⊥ W_SS z + q ≥ 0` on the candidates `set` of the `m × m`
/// row-major `compliance`, with its pivots and its largest scaled residual
/// ([`crate::lcp::LcpResiduals::max_violation`]).
fn solve_on(
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
    let lcp = Lcp::new(set.len(), w, q).map_err(|e| DynamicsError::Lcp { step, cause: e })?;
    let answer =
        lemke(&lcp, &LemkeParams::default()).map_err(|e| DynamicsError::Lcp { step, cause: e })?;
    Ok((answer.z, answer.pivots, answer.residuals.max_violation()))
}

/// Each term with `M̂_b⁻¹ E_c` for every candidate `c` of it.
fn condense<'a>(
    iterations: &[Iteration<'_>],
    terms: &[Term<'a>],
) -> Result<Vec<Condensed<'a>>, DynamicsError> {
    terms
        .iter()
        .map(|&term| {
            let (operator, m) = (term.operator, term.operator.len());
            let iteration = &iterations[term.body];
            let columns = (0..m)
                .map(|c| {
                    let mut unit = vec![0.0; m];
                    unit[c] = 1.0;
                    let mut e = vec![0.0; iteration.dofs()];
                    operator.add_forces(&unit, &mut e);
                    iteration.solve(&e)
                })
                .collect::<Result<_, _>>()?;
            Ok(Condensed { term, columns })
        })
        .collect()
}

/// `Σ G_r Y_c` over the pairs of a row term `r` and a column term `c` on the same body, placed
/// at their candidates: row-major `m × m`.
fn block(rows: &[Condensed<'_>], columns: &[Condensed<'_>], m: usize) -> Vec<f64> {
    let mut w = vec![0.0; m * m];
    for r in rows {
        for c in columns.iter().filter(|c| c.term.body == r.term.body) {
            for (j, y) in c.columns.iter().enumerate() {
                let col = c.term.offset + j;
                for (i, g) in r.term.operator.gap_contribution(y).into_iter().enumerate() {
                    w[(r.term.offset + i) * m + col] += g;
                }
            }
        }
    }
    w
}
