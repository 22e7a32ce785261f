//! A force-driven obstacle pressing a body that only the contact holds (docs/method.md
//! §4.6–4.7): two unknowns, the obstacle's displacement `s` along `e` and the body's
//! translation `t`, with two balances, `aᵀz = F` (the obstacle) and `bᵀz = L` (the body).
//! The outer search over `s` ([`super::find_displacement_with`]) takes as its trial at `s`
//! the inner search over `t` ([`super::find_translation_with`]) at the gaps `q_b − a s`: each
//! outer trial answers with the body in balance, and `F(s)` is the force the balanced system
//! carries. On a piece with closed set `A` the outer slope is the Schur complement
//! `dF/ds = aᵀXa − (aᵀXb)(bᵀXa) / bᵀXb` with `X = M_AA⁻¹` (`t` follows `s` so that `bᵀz`
//! stays `L`), from the inner trials' slopes along `a`, `b` and `a + b`.
//!
//! Several bodies held by contact nest the same way ([`search`]): the search over the last
//! body's translation (or the obstacle's displacement) takes as its trial the search over
//! the one before, and so on down to the LCP; each level's slope is the Schur complement of
//! the levels inside it (the quotient property of Schur complements makes the nested
//! complements the complement of the whole block).

use super::{
    ForceSearch, LoadDrivenError, Trials, find_displacement_with, find_translation_from,
    find_translation_with,
};

/// The outer trials of the two searches: each [`Trials::solve`] is an inner search.
pub struct HeldWithin<'t, T: Trials + ?Sized> {
    /// The trials at fixed `s` (the held body's).
    pub inner: &'t mut T,
    /// `b_c`, the held translation's components per candidate.
    pub held_along: &'t [f64],
    /// `L`, the load on the held body along its translation.
    pub held_load: f64,
    /// The translation `t` of the last outer trial.
    pub translation: f64,
    /// LCP solves over all inner searches.
    pub evaluations: usize,
}

impl<T: Trials + ?Sized> Trials for HeldWithin<'_, T> {
    type Answer = T::Answer;
    type Error = T::Error;
    /// The inner search at `q = q_b − a s`: the body's translation `t` that balances it,
    /// from the last trial's.
    fn solve(&mut self, s: f64, q: &[f64]) -> Result<T::Answer, T::Error> {
        self.inner.set_outer(0, s);
        // From the last trial's translation: the next is usually on the same piece.
        let start = self.translation;
        let ForceSearch { displacement, answer, evaluations, .. } =
            find_translation_from(&mut *self.inner, q, self.held_along, self.held_load, start)?;
        self.translation = displacement;
        self.evaluations += evaluations;
        Ok(answer)
    }
    fn forces<'b>(&self, answer: &'b T::Answer) -> &'b [f64] {
        self.inner.forces(answer)
    }
    /// The gaps at `q − b t`, the translation the inner search found.
    fn gaps(&self, q: &[f64], answer: &T::Answer) -> Vec<f64> {
        let t = self.translation;
        let q: Vec<f64> = q.iter().zip(self.held_along).map(|(q, b)| q - b * t).collect();
        self.inner.gaps(&q, answer)
    }
    /// `aᵀXa − (aᵀXb)(bᵀXa)/bᵀXb`, the cross terms' product taken as the square of their
    /// mean (exact for a symmetric `M`; a Newton slope, which the bracket safeguards).
    fn slope(
        &mut self,
        answer: &T::Answer,
        along: &[f64],
        active: &[usize],
    ) -> Result<f64, T::Error> {
        let b = self.held_along;
        let sum: Vec<f64> = along.iter().zip(b).map(|(a, b)| a + b).collect();
        let aa = self.inner.slope(answer, along, active)?;
        let bb = self.inner.slope(answer, b, active)?;
        let cross = 0.5 * (self.inner.slope(answer, &sum, active)? - aa - bb);
        Ok(if bb > 0.0 { aa - cross * cross / bb } else { aa })
    }
    fn force_round_off(&self, answer: &T::Answer, along: &[f64]) -> f64 {
        self.inner.force_round_off(answer, along)
    }
    fn force_scale(&self) -> f64 {
        self.inner.force_scale()
    }
    /// A search further out: one level further from the inner trials.
    fn set_outer(&mut self, level: usize, s: f64) {
        self.inner.set_outer(level + 1, s);
    }
}

/// What [`search`] solves for besides the LCP: the bodies held by contact, innermost first
/// (each `b_c` and the load `L` along its translation), and a force-driven obstacle (`a_c`,
/// the force's direction `e` and magnitude), the outermost search when present.
#[derive(Clone, Copy, Debug)]
pub struct Unknowns<'u> {
    /// `(b_c, L)` per held body, innermost first.
    pub held: &'u [(&'u [f64], f64)],
    /// `(a_c, e, |F|)` of a force-driven obstacle.
    pub force: Option<(&'u [f64], [f64; 2], f64)>,
}

/// What [`search`] found: the outermost search (an obstacle's displacement, or the last held
/// body's translation), every held body's translation in the order given, and the LCP
/// solves over all levels.
#[derive(Clone, Debug)]
pub struct Found<A> {
    /// The outermost search, its answer the LCP's at the unknowns found.
    pub outer: ForceSearch<A>,
    /// The held bodies' translations, in the order of [`Unknowns::held`].
    pub translations: Vec<f64>,
    /// LCP solves over all levels.
    pub evaluations: usize,
}

/// Solves for every unknown of `unknowns` at once by nested searches (docs/method.md
/// §4.6–4.7): the held bodies' translations and a force-driven obstacle's displacement, with
/// `trials` answering the LCP at each; `base_gap` are the gaps `q_b` with every unknown 0.
/// One held body and no force is [`find_translation_with`]; a force alone
/// [`super::find_displacement_with`].
///
/// # Errors
/// [`LoadDrivenError::BadForce`] when there is nothing to search; the searches' errors.
pub fn search<A, E: From<LoadDrivenError>>(
    trials: &mut dyn Trials<Answer = A, Error = E>,
    base_gap: &[f64],
    unknowns: Unknowns<'_>,
) -> Result<Found<A>, E> {
    let mut translations = Vec::with_capacity(unknowns.held.len());
    let (outer, evaluations) = nest(trials, base_gap, unknowns, &mut translations)?;
    Ok(Found { outer, translations, evaluations })
}

/// [`search`]'s levels: the innermost held body wraps `trials` ([`HeldWithin`]) and the rest
/// are searched over the wrapper; returns the outermost search and the LCP solves.
fn nest<A, E: From<LoadDrivenError>>(
    trials: &mut dyn Trials<Answer = A, Error = E>,
    base_gap: &[f64],
    unknowns: Unknowns<'_>,
    translations: &mut Vec<f64>,
) -> Result<(ForceSearch<A>, usize), E> {
    match (unknowns.held, unknowns.force) {
        ([], None) => Err(LoadDrivenError::BadForce { force: f64::NAN }.into()),
        ([], Some((along, direction, target))) => {
            let found = find_displacement_with(trials, base_gap, along, direction, target)?;
            let evaluations = found.evaluations;
            Ok((found, evaluations))
        }
        ([(along, load)], None) => {
            let found = find_translation_with(trials, base_gap, along, *load)?;
            translations.push(found.displacement);
            let evaluations = found.evaluations;
            Ok((found, evaluations))
        }
        ([(held_along, held_load), rest @ ..], force) => {
            let mut within = HeldWithin {
                inner: trials,
                held_along,
                held_load: *held_load,
                translation: 0.0,
                evaluations: 0,
            };
            let (found, _) =
                nest(&mut within, base_gap, Unknowns { held: rest, force }, translations)?;
            translations.insert(0, within.translation);
            Ok((found, within.evaluations))
        }
    }
}
