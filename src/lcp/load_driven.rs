//! A rigid obstacle pressed by a prescribed force instead of a prescribed displacement
//! (docs/method.md §4.6): the obstacle translates by an unknown `s` along the force's
//! direction `e`, which moves every gap by `−a_c s` with `a_c = ν_c·e`, and `s` is fixed by the
//! obstacle's equilibrium along `e`:
//!
//! ```text
//! w = M z + q_b − a s,   0 ≤ z ⊥ w ≥ 0,   F(s) = aᵀ z(s) = |F|.
//! ```
//!
//! `M` does not change with `s`; where the LCP has one solution (`M` a P-matrix) `z(s)` is
//! continuous and piecewise linear, and for a positive definite `M` the force `F(s)` is
//! non-decreasing (the monotonicity of the LCP's solution in `q`). [`find_displacement`]
//! solves `F(s) = |F|` by Newton's method on that piecewise linear function, the slope of a
//! piece being `a_Aᵀ M_AA⁻¹ a_A` on the closed set `A` of the last evaluation, safeguarded by
//! a bracket (a step leaving the bracket is replaced by the bracket's midpoint, or by a
//! doubled step while one side is missing). Once an iterate's piece holds the root, the next
//! iterate is the root to round-off: every evaluation is one LCP on the same `M`.

pub mod nested;

use faer::Mat;
use faer::linalg::solvers::Solve;

/// Evaluations of `F(s)` at most.
pub const MAX_EVALUATIONS: usize = 100;
/// Relative tolerance on `F(s) = |F|` (Newton on the right piece reaches round-off).
pub const FORCE_TOLERANCE: f64 = 1e-12;

/// Why the obstacle's displacement under a prescribed force was not found.
#[derive(Debug, thiserror::Error)]
pub enum LoadDrivenError {
    /// No candidate's normal has a positive component along the force's direction: pressing
    /// the obstacle along `e` never closes a gap, so the contact cannot carry the force (the
    /// force pulls the obstacle away from the body, or runs along the contact edge).
    #[error(
        "the contact cannot carry a force along e = ({:.6}, {:.6}): no contact candidate's normal has a positive component along it (the largest ν·e is {largest:.3e}), so pressing the obstacle that way never closes a gap; the force must push the obstacle towards the body",
        direction[0],
        direction[1]
    )]
    NotCarried {
        /// The force's direction `e`.
        direction: [f64; 2],
        /// The largest `ν_c·e` over the candidates (≤ 0).
        largest: f64,
    },
    /// The prescribed force is not a positive finite number.
    #[error("the prescribed force's magnitude {force:e} must be finite and positive")]
    BadForce {
        /// The magnitude given.
        force: f64,
    },
    /// A rigid-body translation of the body that no displacement condition restrains is
    /// perpendicular to every contact normal: frictionless contact cannot hold it
    /// (docs/method.md §4.7).
    #[error(
        "{mode} is restrained neither by a displacement condition nor by the contact normals: every contact normal is perpendicular to it, so frictionless contact cannot hold it (add a displacement condition that prevents it)"
    )]
    NotRestrained {
        /// The free mode, e.g. `"translation in x"`.
        mode: &'static str,
    },
    /// A rigid-body translation left to the contact, but the applied load along it does not
    /// press the body onto the obstacle: the body's position is not determined.
    #[error(
        "{mode} is held only by the contact, but the applied load along it ({load:.6e}) does not press the body onto the obstacle (it is zero or pulls the body away), so the body's position is not determined (load it towards the obstacle, or add a displacement condition that prevents the {mode})"
    )]
    NotPressed {
        /// The free mode.
        mode: &'static str,
        /// The applied load's component along the mode.
        load: f64,
    },
    /// An obstacle pressed by a force with friction where a candidate's tangent has a
    /// component along the force: its tangential force would enter the balance along the
    /// force that the search solves (docs/method.md §4.6), which it does not.
    #[error(
        "step {step} presses the obstacle by a force along ({:.3}, {:.3}) with friction μ = {mu}, and candidate {candidate}'s tangent has a component along the force (its tangential force would enter the balance the search solves); a force-driven obstacle takes friction where the force is normal to every tangent (a flat contact pressed along its normal): press along the normal, prescribe the obstacle's displacement instead, or set the step's `friction = 0`",
        direction[0],
        direction[1]
    )]
    SlantedFriction {
        /// The step (1-based).
        step: usize,
        /// The force's direction.
        direction: [f64; 2],
        /// The step's friction coefficient.
        mu: f64,
        /// The first candidate whose tangent has a component along the force.
        candidate: usize,
    },
    /// A rigid-body translation left to the contact with something this method does not
    /// combine it with (friction with a tangent along the translation, a pin on the contact).
    #[error(
        "{mode} is held only by the contact, which is solved with friction only where the tangents are orthogonal to the translation, and for a body whose pinned node carries no contact force; here {why} (add a displacement condition that prevents the {mode})"
    )]
    Unsupported {
        /// The free mode.
        mode: &'static str,
        /// What is not supported.
        why: String,
    },
    /// A rigid-body translation left to the contact while the obstacle is pressed by a force,
    /// where the two move together without changing any gap: the translation's `a_c` and the
    /// force's are proportional over the candidates (the body touches only the obstacles the
    /// force moves, their normals in one direction), so the contact fixes neither position
    /// and balances both loads only if they happen to agree (docs/method.md §4.6–4.7).
    #[error(
        "{mode} is held only by the contact, and the obstacle it rests on is pressed by a force along e = ({:.6}, {:.6}): the body and the obstacle can move together without opening or closing any gap, so the contact determines neither position (and balances the body's load and the force only if they happen to agree); add a displacement condition that prevents the {mode}, or prescribe the obstacle's displacement instead of its force",
        direction[0],
        direction[1]
    )]
    MovesWithObstacle {
        /// The free mode.
        mode: &'static str,
        /// The force's direction `e`.
        direction: [f64; 2],
    },
    /// Both bodies of a two-body pair leave a rigid translation to the contact: nothing
    /// holds the pair as a whole (docs/method.md §4.7).
    #[error(
        "bodies {bodies} each have a rigid-body translation that no displacement condition restrains, and they touch only each other: no contact holds the pair as a whole (add a displacement condition to one of them, or the obstacle or body they rest on)"
    )]
    SeveralHeld {
        /// The bodies' names with their free modes, e.g. "`a` (translation in y), `b` (…)".
        bodies: String,
    },
    /// A body of several whose displacement conditions leave it free to move in more ways
    /// than one translation, which is all the contact may hold (docs/method.md §4.7).
    #[error(
        "body `{body}`: {detail}; contact between bodies may hold one free rigid-body translation of each body (the other translation and the rotation restrained by displacement conditions), so add a displacement condition to body `{body}` that prevents the {mode}"
    )]
    FreeBody {
        /// The body's name.
        body: String,
        /// A mode left free (`"translation in x"`, …).
        mode: &'static str,
        /// What assembly found.
        detail: String,
    },
    /// A body held by contact between bodies with no load along its free translation, whose
    /// contacts carry no force and do not block the translation both ways: every position of
    /// an interval answers, so none is reported (docs/method.md §4.7).
    #[error(
        "body `{body}`: its {mode} is left to the contact, but no load acts along it and its contacts carry no force, so its position is not determined (press the bodies together, load the body along the {mode}, or add a displacement condition that prevents it)"
    )]
    Undetermined {
        /// The body's name.
        body: String,
        /// The free mode.
        mode: &'static str,
    },
    /// No displacement meeting the force equation was found.
    #[error(
        "the obstacle's displacement under the force {target:.6e} was not found after {evaluations} LCP solves: the last, at s = {displacement:.6e}, carried {force:.6e} (bracket {low:?} to {high:?}); the contact's force–displacement relation may have a jump (M is not a P-matrix) — try a displacement step instead"
    )]
    NotConverged {
        /// LCP solves made.
        evaluations: usize,
        /// The last displacement tried.
        displacement: f64,
        /// The force carried there.
        force: f64,
        /// The force prescribed.
        target: f64,
        /// The largest displacement known to carry less than the force.
        low: Option<f64>,
        /// The smallest displacement known to carry more.
        high: Option<f64>,
    },
    /// No translation of a body held by contact balancing its load was found: the
    /// translation's search ([`find_translation`]) ran out of solves.
    #[error(
        "the translation of a body held by contact alone that balances its load {target:.6e} was not found after {evaluations} LCP solves: the last, at t = {translation:.6e}, carried {force:.6e} (bracket {low:?} to {high:?}); a translation that grows without bound means nothing holds the body on the side its load pushes it to (add the body or obstacle it rests on, or a displacement condition that prevents the translation)"
    )]
    HeldNotConverged {
        /// LCP solves made.
        evaluations: usize,
        /// The last translation tried.
        translation: f64,
        /// The force carried there along the translation.
        force: f64,
        /// The load along the translation.
        target: f64,
        /// The largest translation known to carry less than the load.
        low: Option<f64>,
        /// The smallest translation known to carry more.
        high: Option<f64>,
    },
}

/// What [`find_displacement`] found: the displacement `s` along `e`, the LCP's answer there
/// (the last evaluation), the force `aᵀz` it carries and the LCP solves made.
#[derive(Clone, Debug)]
pub struct ForceSearch<S> {
    /// The obstacle's displacement `s` along `e`.
    pub displacement: f64,
    /// The force carried, `aᵀ z(s)`.
    pub force: f64,
    /// The answer of the LCP at `s` (the last one solved).
    pub answer: S,
    /// LCP solves made (at least 1).
    pub evaluations: usize,
}

/// The LCP of a search at its trial displacements (docs/method.md §4.6): what
/// [`find_displacement_with`] needs of a solver. Lemke's method on the dense `M` is one
/// ([`find_displacement`]); the active-set method on the sparse system, whose answer at a
/// trial is a warm-started solve with the obstacle's offset in the gap rows, is another
/// (`pipeline`). Both answer `w = M z + q_b − a s`, `0 ≤ z ⊥ w ≥ 0`.
pub trait Trials {
    /// The answer at one trial.
    type Answer;
    /// The solver's error.
    type Error: From<LoadDrivenError>;
    /// Solves the LCP at the displacement `s`, where `q = q_b − a s`.
    ///
    /// # Errors
    /// The solver's.
    fn solve(&mut self, s: f64, q: &[f64]) -> Result<Self::Answer, Self::Error>;
    /// The forces `z` of an answer.
    fn forces<'b>(&self, answer: &'b Self::Answer) -> &'b [f64];
    /// The gaps `w = q + M z` of an answer at `q`.
    fn gaps(&self, q: &[f64], answer: &Self::Answer) -> Vec<f64>;
    /// `dF/ds = a_Aᵀ M_AA⁻¹ a_A` on the piece where the closed set is `active` (`answer` is
    /// the last trial's; `active` may hold the next candidate to close, open in it).
    ///
    /// # Errors
    /// The solver's.
    fn slope(
        &mut self,
        answer: &Self::Answer,
        along: &[f64],
        active: &[usize],
    ) -> Result<f64, Self::Error>;
    /// A bound on the round-off of `F = aᵀz` at `answer` (`along` = `a`), which
    /// [`find_translation_with`] accepts as met when it exceeds its relative tolerance: forces
    /// recovered from row residuals carry more than Lemke's (default 0: the relative
    /// tolerance alone).
    fn force_round_off(&self, _answer: &Self::Answer, _along: &[f64]) -> f64 {
        0.0
    }
    /// A force scale of the whole problem (the largest load or force a search of it aims
    /// at): a search whose own target is smaller, inside a search for a larger force
    /// ([`nested::HeldWithin`]), accepts a residual at [`FORCE_TOLERANCE`] of it as met
    /// (default 0: the search's own target and forces set the tolerance).
    fn force_scale(&self) -> f64 {
        0.0
    }
    /// Places the trials inside outer searches ([`nested::HeldWithin`]): the search `level`
    /// levels out (0 the nearest) is at its displacement `s`. Trials that answer from the
    /// gaps `q` they are given need nothing (the default); trials that move their own gaps
    /// add each outer level's shift.
    fn set_outer(&mut self, _level: usize, _s: f64) {}
}

/// Lemke's trials: `solve(q)` answers the LCP, `forces` reads `z`, and the gaps and slopes
/// come from the dense `M` (`compliance`, row-major `m × m`).
struct Condensed<'c, F, G, S, E> {
    compliance: &'c [f64],
    solve: F,
    forces: G,
    answer: std::marker::PhantomData<fn() -> (S, E)>,
}

impl<F, G, S, E> Trials for Condensed<'_, F, G, S, E>
where
    F: FnMut(&[f64]) -> Result<S, E>,
    G: Fn(&S) -> &[f64],
    E: From<LoadDrivenError>,
{
    type Answer = S;
    type Error = E;
    fn solve(&mut self, _s: f64, q: &[f64]) -> Result<S, E> {
        (self.solve)(q)
    }
    fn forces<'b>(&self, answer: &'b S) -> &'b [f64] {
        (self.forces)(answer)
    }
    fn gaps(&self, q: &[f64], answer: &S) -> Vec<f64> {
        gaps(self.compliance, q, (self.forces)(answer))
    }
    fn slope(&mut self, _answer: &S, along: &[f64], active: &[usize]) -> Result<f64, E> {
        Ok(slope(self.compliance, along.len(), along, active))
    }
}

/// Solves `F(s) = aᵀ z(s) = target` (docs/method.md §4.6) for the displacement `s` of the
/// obstacle along `e` by Lemke's method: [`find_displacement_with`] on the dense `M`.
/// `compliance` is `M` (row-major `m × m`, for the slopes and gaps), `base_gap` the gaps
/// `q_b` with the obstacle at `s = 0`, `along` the components `a_c = ν_c·e`; `solve(q)`
/// answers the LCP with `q = q_b − a s`, and `forces` reads `z` from its answer.
///
/// # Errors
/// As [`find_displacement_with`].
pub fn find_displacement<S, E: From<LoadDrivenError>>(
    compliance: &[f64],
    base_gap: &[f64],
    along: &[f64],
    direction: [f64; 2],
    target: f64,
    solve: impl FnMut(&[f64]) -> Result<S, E>,
    forces: impl Fn(&S) -> &[f64],
) -> Result<ForceSearch<S>, E> {
    debug_assert_eq!(compliance.len(), base_gap.len() * base_gap.len());
    let mut trials = Condensed { compliance, solve, forces, answer: std::marker::PhantomData };
    find_displacement_with(&mut trials, base_gap, along, direction, target)
}

/// Solves `F(s) = aᵀ z(s) = target` (docs/method.md §4.6) for the displacement `s` of the
/// obstacle along `e`, whatever answers the LCP at each trial (`trials`). `base_gap` are the
/// gaps `q_b` with the obstacle at `s = 0` (they fix the first trial: the displacement where
/// the first gap with `a_c > 0` closes), `along` the components `a_c = ν_c·e`.
///
/// # Errors
/// [`LoadDrivenError::NotCarried`] when no `a_c` is positive,
/// [`LoadDrivenError::BadForce`] for a target that is not positive and finite,
/// [`LoadDrivenError::NotConverged`] after [`MAX_EVALUATIONS`] solves; the solver's own errors.
pub fn find_displacement_with<T: Trials + ?Sized>(
    trials: &mut T,
    base_gap: &[f64],
    along: &[f64],
    direction: [f64; 2],
    target: f64,
) -> Result<ForceSearch<T::Answer>, T::Error> {
    let m = base_gap.len();
    debug_assert_eq!(along.len(), m);
    if !(target.is_finite() && target > 0.0) {
        return Err(LoadDrivenError::BadForce { force: target }.into());
    }
    let largest = along.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if largest.is_nan() || largest <= 0.0 {
        return Err(LoadDrivenError::NotCarried { direction, largest }.into());
    }
    // The first closure: the smallest q_c / a_c over a_c > 0.
    let first = |q: &[f64]| {
        (0..m)
            .filter(|&c| along[c] > 0.0)
            .min_by(|&i, &j| (q[i] / along[i]).total_cmp(&(q[j] / along[j])))
            .expect("some a_c > 0")
    };
    let c0 = first(base_gap);
    let mut s = base_gap[c0] / along[c0];
    let mut bracket = Bracket::default();
    let mut last_step: f64 = 0.0;
    let mut tried = (s, 0.0);
    let scale = 1.0 + s.abs();
    for evaluation in 1..=MAX_EVALUATIONS {
        let q: Vec<f64> = base_gap.iter().zip(along).map(|(g, a)| g - a * s).collect();
        let answer = trials.solve(s, &q)?;
        let z = trials.forces(&answer);
        let force: f64 = z.iter().zip(along).map(|(z, a)| z * a).sum();
        let residual = force - target;
        tried = (s, force);
        if residual.abs() <= FORCE_TOLERANCE * target {
            return Ok(ForceSearch { displacement: s, force, answer, evaluations: evaluation });
        }
        bracket.record(s, residual);
        if bracket.collapsed(scale) {
            return Err(bracket.not_converged(evaluation, (s, force), target).into());
        }
        // The closed set of this answer; none closed: the next to close.
        let w = trials.gaps(&q, &answer);
        let mut active: Vec<usize> = (0..m).filter(|&c| z[c] > 0.0).collect();
        if active.is_empty() {
            active.push(first(&w));
        }
        let slope = trials.slope(&answer, along, &active)?;
        let newton = s - residual / slope;
        let inside = |x: f64| bracket.contains(x);
        let next = if slope.is_finite() && slope > 0.0 && inside(newton) {
            newton
        } else {
            match bracket.midpoint() {
                Some(mid) => mid,
                // One side only: double the last step towards the other.
                None => {
                    let size = (2.0 * last_step.abs()).max(1e-6 * scale);
                    if residual < 0.0 { s + size } else { s - size }
                }
            }
        };
        last_step = next - s;
        s = next;
    }
    Err(bracket.not_converged(MAX_EVALUATIONS, tried, target).into())
}

/// Solves `F(t) = aᵀ z(t) = target` for a free rigid translation `t` of a body held by
/// contact between bodies (docs/method.md §4.7): `a_c` of either sign (`a_c = −s_c ν_c·r`,
/// `s_c = +1` when the body carries candidate `c`, `−1` when it is `c`'s target) and a
/// target of any sign, zero included (the applied load along the translation). `compliance`
/// is `M`, `base_gap` the gaps `q_b` at `t = 0`; `solve(q)` answers the LCP with
/// `q = q_b − a t`, `forces` reads `z` from its answer. `F` is non-decreasing in `t` (§4.6).
/// The search starts at `t = 0` and moves in the direction of the residual's sign: Newton on
/// the current piece (slope `a_Aᵀ M_AA⁻¹ a_A`), on a flat piece (no closed candidate with
/// `a_c ≠ 0`) a jump to the next candidate that closes in that direction, safeguarded by a
/// bracket as [`find_displacement`]; it stops at `|F − target| ≤ 10⁻¹² max(|target|,
/// max_c |a_c z_c|)`.
///
/// # Errors
/// [`LoadDrivenError::BadForce`] for a target that is not finite,
/// [`LoadDrivenError::HeldNotConverged`] after [`MAX_EVALUATIONS`] solves; `solve`'s own
/// errors.
pub fn find_translation<S, E: From<LoadDrivenError>>(
    compliance: &[f64],
    base_gap: &[f64],
    along: &[f64],
    target: f64,
    solve: impl FnMut(&[f64]) -> Result<S, E>,
    forces: impl Fn(&S) -> &[f64],
) -> Result<ForceSearch<S>, E> {
    debug_assert_eq!(compliance.len(), base_gap.len() * base_gap.len());
    let mut trials = Condensed { compliance, solve, forces, answer: std::marker::PhantomData };
    find_translation_with(&mut trials, base_gap, along, target)
}

/// The nested searches of [`nested::search`] on the dense `M` by Lemke's method: the
/// translations of the bodies held by contact and a force-driven obstacle's displacement
/// (docs/method.md §4.6–4.7). `compliance`, `base_gap`, `solve` and `forces` as
/// [`find_displacement`].
///
/// # Errors
/// As [`find_displacement`] and [`find_translation`].
pub fn search_condensed<S, E: From<LoadDrivenError>>(
    compliance: &[f64],
    base_gap: &[f64],
    unknowns: nested::Unknowns<'_>,
    solve: impl FnMut(&[f64]) -> Result<S, E>,
    forces: impl Fn(&S) -> &[f64],
) -> Result<nested::Found<S>, E> {
    debug_assert_eq!(compliance.len(), base_gap.len() * base_gap.len());
    let mut trials = Condensed { compliance, solve, forces, answer: std::marker::PhantomData };
    nested::search(&mut trials, base_gap, unknowns)
}

/// [`find_translation`] whatever answers the LCP at each trial (`trials`, as
/// [`find_displacement_with`]): `base_gap` are the gaps `q_b` at `t = 0`, `along` the `a_c`.
///
/// # Errors
/// As [`find_translation`].
pub fn find_translation_with<T: Trials + ?Sized>(
    trials: &mut T,
    base_gap: &[f64],
    along: &[f64],
    target: f64,
) -> Result<ForceSearch<T::Answer>, T::Error> {
    find_translation_from(trials, base_gap, along, target, 0.0)
}

/// [`find_translation_with`] from the trial translation `start` instead of 0: a search
/// inside another ([`nested::HeldWithin`]) starts where the last one ended, usually on the
/// piece of the answer, so that Newton's first step lands on it.
///
/// # Errors
/// As [`find_translation`].
pub fn find_translation_from<T: Trials + ?Sized>(
    trials: &mut T,
    base_gap: &[f64],
    along: &[f64],
    target: f64,
    start: f64,
) -> Result<ForceSearch<T::Answer>, T::Error> {
    let m = base_gap.len();
    debug_assert_eq!(along.len(), m);
    if !target.is_finite() {
        return Err(LoadDrivenError::BadForce { force: target }.into());
    }
    let mut t = if start.is_finite() { start } else { 0.0 };
    let mut bracket = Bracket::default();
    let mut last_step: f64 = 0.0;
    let mut tried = (t, 0.0);
    let gap_scale = base_gap.iter().fold(0.0f64, |g, q| g.max(q.abs()));
    for evaluation in 1..=MAX_EVALUATIONS {
        let q: Vec<f64> = base_gap.iter().zip(along).map(|(g, a)| g - a * t).collect();
        let answer = trials.solve(t, &q)?;
        let z = trials.forces(&answer);
        let force: f64 = z.iter().zip(along).map(|(z, a)| z * a).sum();
        let residual = force - target;
        tried = (t, force);
        let carried = z.iter().zip(along).fold(0.0f64, |s, (z, a)| s.max((z * a).abs()));
        let mut tolerance = FORCE_TOLERANCE * target.abs().max(carried).max(trials.force_scale());
        let round_off = trials.force_round_off(&answer, along);
        if round_off > tolerance {
            tolerance = round_off;
        }
        if residual.abs() <= tolerance {
            return Ok(ForceSearch { displacement: t, force, answer, evaluations: evaluation });
        }
        bracket.record(t, residual);
        let scale = gap_scale.max(t.abs()).max(f64::MIN_POSITIVE);
        if bracket.collapsed(scale) {
            return Err(bracket.held_not_converged(evaluation, (t, force), target).into());
        }
        let w = trials.gaps(&q, &answer);
        let active: Vec<usize> = (0..m).filter(|&c| z[c] > 0.0).collect();
        let slope = if active.is_empty() { 0.0 } else { trials.slope(&answer, along, &active)? };
        // Towards larger F: t grows when the residual is negative.
        let direction = if residual < 0.0 { 1.0 } else { -1.0 };
        let inside = |x: f64| bracket.contains(x);
        let newton = t - residual / slope;
        // A flat piece: the next candidate to close in that direction (a_c has its sign).
        let next_closure = (0..m)
            .filter(|&c| direction * along[c] > 0.0 && z[c] == 0.0)
            .map(|c| w[c] / along[c].abs())
            .filter(|d| d.is_finite() && *d >= 0.0)
            .min_by(f64::total_cmp)
            .map(|d| t + direction * d);
        let next = if slope.is_finite() && slope > 0.0 && inside(newton) {
            newton
        } else if let Some(x) = next_closure.filter(|&x| x != t && inside(x)) {
            x
        } else {
            match bracket.midpoint() {
                Some(mid) => mid,
                None => {
                    let size = (2.0 * last_step.abs()).max(1e-6 * scale.max(1e-300));
                    t + direction * size
                }
            }
        };
        last_step = next - t;
        t = next;
    }
    Err(bracket.held_not_converged(MAX_EVALUATIONS, tried, target).into())
}

/// The trial displacements of a search known to carry less (`low`) and more (`high`) than
/// the target: a Newton step leaving it is replaced (docs/method.md §4.6).
#[derive(Clone, Copy, Debug, Default)]
struct Bracket {
    low: Option<f64>,
    high: Option<f64>,
}

impl Bracket {
    /// Records the trial `x`, whose force missed the target by `residual`.
    fn record(&mut self, x: f64, residual: f64) {
        if residual < 0.0 {
            self.low = Some(self.low.map_or(x, |l| l.max(x)));
        } else {
            self.high = Some(self.high.map_or(x, |h| h.min(x)));
        }
    }

    /// Whether both sides are known and lie within round-off of each other at `scale`.
    fn collapsed(&self, scale: f64) -> bool {
        matches!((self.low, self.high),
            (Some(lo), Some(hi)) if hi - lo <= 4.0 * f64::EPSILON * scale.max(hi.abs()))
    }

    /// Whether `x` lies strictly inside the known sides.
    fn contains(&self, x: f64) -> bool {
        self.low.is_none_or(|l| x > l) && self.high.is_none_or(|h| x < h)
    }

    /// The midpoint, once both sides are known.
    fn midpoint(&self) -> Option<f64> {
        Some(0.5 * (self.low? + self.high?))
    }

    /// A held body's search's failure after `evaluations` solves, the last trial
    /// `(t, force)`.
    fn held_not_converged(
        &self,
        evaluations: usize,
        tried: (f64, f64),
        target: f64,
    ) -> LoadDrivenError {
        let (low, high) = (self.low, self.high);
        LoadDrivenError::HeldNotConverged {
            evaluations,
            translation: tried.0,
            force: tried.1,
            target,
            low,
            high,
        }
    }

    /// The search's failure after `evaluations` solves, the last trial `(x, force)`.
    fn not_converged(&self, evaluations: usize, tried: (f64, f64), target: f64) -> LoadDrivenError {
        let (low, high) = (self.low, self.high);
        LoadDrivenError::NotConverged {
            evaluations,
            displacement: tried.0,
            force: tried.1,
            target,
            low,
            high,
        }
    }
}

/// The gaps `w = q + M z` of an LCP answer (`compliance` row-major `m × m`).
fn gaps(compliance: &[f64], q: &[f64], z: &[f64]) -> Vec<f64> {
    let m = q.len();
    (0..m).map(|i| q[i] + (0..m).map(|j| compliance[i * m + j] * z[j]).sum::<f64>()).collect()
}

/// `a_Aᵀ M_AA⁻¹ a_A`: `dF/ds` on the piece where the closed set is `A` (`dz_A/ds =
/// M_AA⁻¹ a_A`, the open candidates' forces stay zero).
fn slope(compliance: &[f64], m: usize, along: &[f64], active: &[usize]) -> f64 {
    let k = active.len();
    let a = Mat::from_fn(k, k, |i, j| compliance[active[i] * m + active[j]]);
    let b = Mat::from_fn(k, 1, |i, _| along[active[i]]);
    let x = a.partial_piv_lu().solve(&b);
    (0..k).map(|i| along[active[i]] * x[(i, 0)]).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lcp::{Lcp, LcpError, LemkeParams, lemke};

    fn run(
        m: &[f64],
        q: &[f64],
        a: &[f64],
        target: f64,
    ) -> Result<ForceSearch<Vec<f64>>, LcpError> {
        let n = q.len();
        find_displacement(
            m,
            q,
            a,
            [0.0, -1.0],
            target,
            |q| {
                Ok::<_, LcpError>(
                    lemke(&Lcp::new(n, m.to_vec(), q.to_vec())?, &LemkeParams::default())?.z,
                )
            },
            |z| z.as_slice(),
        )
    }

    /// Two springs of compliance 1 and 2 at gaps 0 and 1 (diagonal `M`): `F(s) = s` for
    /// `s ≤ 1`, `s + (s − 1)/2` beyond; `F = 2.5` at `s = 2`, found exactly.
    #[test]
    fn two_springs_close_in_turn() {
        let m = [1.0, 0.0, 0.0, 2.0];
        let out = run(&m, &[0.0, 1.0], &[1.0, 1.0], 2.5).unwrap();
        assert!((out.displacement - 2.0).abs() < 1e-14, "{}", out.displacement);
        assert!((out.answer[0] - 2.0).abs() < 1e-14 && (out.answer[1] - 0.5).abs() < 1e-14);
        assert!(out.evaluations <= 4, "{} evaluations", out.evaluations);
        // Below the second closure: only the first spring.
        let out = run(&m, &[0.0, 1.0], &[1.0, 1.0], 0.5).unwrap();
        assert!((out.displacement - 0.5).abs() < 1e-14 && out.answer[1] == 0.0);
    }

    /// A coupled positive definite `M` with inclined normals (`a_c < 1`) and one candidate
    /// that the motion opens (`a_c < 0`): the answer satisfies the LCP and the force equation.
    #[test]
    fn coupled_and_inclined() {
        let m = [2.0, 0.5, 0.1, 0.5, 2.0, 0.5, 0.1, 0.5, 2.0];
        let q = [0.3, 0.0, 0.2];
        let a = [0.8, 1.0, -0.2];
        let out = run(&m, &q, &a, 1.7).unwrap();
        let s = out.displacement;
        let z = &out.answer;
        let f: f64 = z.iter().zip(&a).map(|(z, a)| z * a).sum();
        assert!((f - 1.7).abs() < 1e-12 * 1.7, "{f}");
        for i in 0..3 {
            let w = q[i] - a[i] * s + (0..3).map(|j| m[i * 3 + j] * z[j]).sum::<f64>();
            assert!(z[i] >= 0.0 && w >= -1e-12 && (z[i] * w).abs() < 1e-12, "{i}: {z:?} {w}");
        }
        assert_eq!(z[2], 0.0, "the candidate the motion opens");
    }

    /// A body between two springs (`a = (−1, +1)`: moving it by `t` opens the first gap and
    /// closes the second), no load along the translation (target 0). With `M = diag(1, 3)`,
    /// `q = (0, −4)` and both closed, `w = M z + q − a t = 0` gives `z_0 = −t`,
    /// `z_1 = (4 + t)/3`, and `aᵀz = 0` gives `t = −1`, `z = (1, 1)`.
    #[test]
    fn body_between_two_springs() {
        let m = [1.0, 0.0, 0.0, 3.0];
        let out = find_translation(
            &m,
            &[0.0, -4.0],
            &[-1.0, 1.0],
            0.0,
            |q| {
                Ok::<_, LcpError>(
                    lemke(&Lcp::new(2, m.to_vec(), q.to_vec())?, &LemkeParams::default())?.z,
                )
            },
            |z| z.as_slice(),
        )
        .unwrap();
        let t = out.displacement;
        assert!((t + 1.0).abs() < 1e-14, "{t}");
        assert!((out.answer[0] - 1.0).abs() < 1e-14 && (out.answer[1] - 1.0).abs() < 1e-14);
        assert!(out.evaluations <= 4, "{} evaluations", out.evaluations);
    }

    /// Lemke's answer to `M z + q` as a search's trial.
    fn lemke_z(m: &[f64], q: &[f64]) -> Result<Vec<f64>, LcpError> {
        Ok(lemke(&Lcp::new(q.len(), m.to_vec(), q.to_vec())?, &LemkeParams::default())?.z)
    }

    /// Two bodies stacked on a wall, each held by contact alone (`b₁ = (1, −1)`: body 1
    /// moving down closes the wall's gap and opens the gap to body 2; `b₂ = (0, 1)`), loads
    /// `L₁ = 1`, `L₂ = 2`: the balances give `z = (3, 2)` whatever `M`, and `w = 0` the
    /// translations `t₁ = (Mz)₀ + q₀ = 4`, `t₂ = (Mz)₁ + q₁ + t₁ = 9.75`.
    #[test]
    fn two_held_bodies_stacked_on_a_wall() {
        let m = [1.0, 0.25, 0.25, 2.0];
        let q = [0.5, 1.0];
        let (b1, b2) = ([1.0, -1.0], [0.0, 1.0]);
        let held = [(&b1[..], 1.0), (&b2[..], 2.0)];
        let unknowns = nested::Unknowns { held: &held, force: None };
        let found =
            search_condensed(&m, &q, unknowns, |q| lemke_z(&m, q), |z| z.as_slice()).unwrap();
        let z = &found.outer.answer;
        assert!((z[0] - 3.0).abs() < 1e-12 && (z[1] - 2.0).abs() < 1e-12, "{z:?}");
        let t = &found.translations;
        assert!((t[0] - 4.0).abs() < 1e-12 && (t[1] - 9.75).abs() < 1e-12, "{t:?}");
        assert_eq!(found.outer.displacement, t[1]);
        assert!(found.evaluations >= found.outer.evaluations, "{found:?}");
    }

    /// A force-driven obstacle under the same stack of two held bodies against a fixed top
    /// wall (`a = (1, 0, 0)`, `b₁ = (−1, 1, 0)`, `b₂ = (0, −1, 1)`, no loads on the bodies,
    /// `M = I`, `q = (0.1, 0.2, 0.3)`, `|F| = 2`): every contact carries 2 and `w = 0` gives
    /// `t₂ = F + 0.3`, `t₁ = F + 0.2 + t₂`, `s = F + 0.1 + t₁`.
    #[test]
    fn force_through_two_held_bodies() {
        let m = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let q = [0.1, 0.2, 0.3];
        let (a, b1, b2) = ([1.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [0.0, -1.0, 1.0]);
        let held = [(&b1[..], 0.0), (&b2[..], 0.0)];
        let unknowns = nested::Unknowns { held: &held, force: Some((&a, [0.0, 1.0], 2.0)) };
        let found =
            search_condensed(&m, &q, unknowns, |q| lemke_z(&m, q), |z| z.as_slice()).unwrap();
        let z = &found.outer.answer;
        assert!(z.iter().all(|z| (z - 2.0).abs() < 1e-12), "{z:?}");
        let (t, s) = (&found.translations, found.outer.displacement);
        assert!((t[1] - 2.3).abs() < 1e-12 && (t[0] - 4.5).abs() < 1e-12, "{t:?}");
        assert!((s - 6.6).abs() < 1e-12, "{s}");
    }

    /// A force the contact cannot carry (every `a_c ≤ 0`) and a force that is not positive
    /// are refused.
    #[test]
    fn refusals() {
        let m = [1.0];
        match run(&m, &[0.0], &[-1.0], 1.0) {
            Err(LcpError::LoadDriven(LoadDrivenError::NotCarried { largest, .. })) => {
                assert_eq!(largest, -1.0);
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            run(&m, &[0.0], &[1.0], 0.0),
            Err(LcpError::LoadDriven(LoadDrivenError::BadForce { .. }))
        ));
    }
}
