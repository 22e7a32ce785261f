//! A force-driven obstacle pressing a body that only the contact holds (docs/method.md
//! §4.6–4.7): two unknowns, the obstacle's displacement `s` along `e` and the body's
//! translation `t`, with two balances, `aᵀz = F` (the obstacle) and `bᵀz = L` (the body).
//! The outer search over `s` ([`super::find_displacement_with`]) takes as its trial at `s`
//! the inner search over `t` ([`super::find_translation_with`]) at the gaps `q_b − a s`: each
//! outer trial answers with the body in balance, and `F(s)` is the force the balanced system
//! carries. On a piece with closed set `A` the outer slope is the Schur complement
//! `dF/ds = aᵀXa − (aᵀXb)(bᵀXa) / bᵀXb` with `X = M_AA⁻¹` (`t` follows `s` so that `bᵀz`
//! stays `L`), from the inner trials' slopes along `a`, `b` and `a + b`.

use super::{ForceSearch, Trials, find_translation_with};

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
    /// The inner search at `q = q_b − a s`: the body's translation `t` that balances it.
    fn solve(&mut self, s: f64, q: &[f64]) -> Result<T::Answer, T::Error> {
        self.inner.set_outer(s, q);
        let ForceSearch { displacement, answer, evaluations, .. } =
            find_translation_with(&mut *self.inner, q, self.held_along, self.held_load)?;
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
}
