//! The trials of the sparse path's searches (docs/method.md §4.6–4.7) over any
//! [`SceneSystem`]: the held bodies' translations and a force-driven obstacle's displacement
//! found by [`lcp::load_driven`] over warm-started active-set solves.

use crate::contact::sparse::SceneSystem;
use crate::lcp;

/// The trials of a search on the sparse path (docs/method.md §4.6–4.7: a held translation,
/// a force-driven obstacle): each is the system with the initial gaps moved to `g0 − a t`,
/// solved by [`lcp::active_set::solve_friction_step`] from the last trial's states; the
/// slope one solve with the closed set's matrix ([`SceneSystem::search_rate`]).
pub(super) struct SparseTrials<'s, S> {
    system: &'s mut S,
    initial_gap: &'s [f64],
    along: &'s [f64],
    /// The accumulated slips (zero: frictionless).
    previous: Vec<f64>,
    /// The states to start the next solve from.
    warm: Option<Vec<lcp::ContactState>>,
    params: lcp::active_set::ActiveSetParams,
    /// Linear solves and Lemke rescues over the trials.
    pub(super) iterations: usize,
    pub(super) rescues: Vec<usize>,
    /// The round-off of the last trial's forces ([`SceneSystem::force_round_off`]).
    round_off: Vec<f64>,
    /// Inside outer searches ([`lcp::load_driven::nested::HeldWithin`]; other held bodies,
    /// a force-driven obstacle), nearest first: each one's `a_c` and trial displacement `s`,
    /// which move the gaps by `−a s` as well (empty when the search is the only one).
    pub(super) outer: Vec<(&'s [f64], f64)>,
}

impl<'s, 'p, S: SceneSystem<'p>> SparseTrials<'s, S> {
    /// The trials of a search along `along` from the gaps `initial_gap`, starting from the
    /// accumulated slips `previous` and the states `warm`, each trial's residuals measured
    /// against `force_scale` (`ActiveSetParams::force_scale`); not inside another search.
    pub(super) fn new(
        system: &'s mut S,
        (initial_gap, along): (&'s [f64], &'s [f64]),
        (previous, warm): (Vec<f64>, Option<Vec<lcp::ContactState>>),
        (params, force_scale): (lcp::active_set::ActiveSetParams, f64),
    ) -> Self {
        Self {
            system,
            initial_gap,
            along,
            previous,
            warm,
            params: lcp::active_set::ActiveSetParams { force_scale, ..params },
            iterations: 0,
            rescues: Vec::new(),
            round_off: Vec::new(),
            outer: Vec::new(),
        }
    }

    /// `q_b`, the gaps without contact forces at `t = 0` (one solve per body; `g0` when a
    /// body's solve fails its accuracy check).
    pub(super) fn base_gap(&mut self) -> Result<Vec<f64>, lcp::LcpError> {
        self.system.set_initial_gap(self.initial_gap);
        Ok(match self.system.free_response()? {
            Some((q, _)) => q,
            None => self.initial_gap.to_vec(),
        })
    }
}

impl<'p, S: SceneSystem<'p>> lcp::load_driven::Trials for SparseTrials<'_, S> {
    type Answer = lcp::active_set::FrictionStepSolution;
    type Error = lcp::LcpError;
    fn solve(&mut self, t: f64, _q: &[f64]) -> Result<Self::Answer, lcp::LcpError> {
        if t == 0.0 && self.outer.iter().all(|&(_, s)| s == 0.0) {
            self.system.set_initial_gap(self.initial_gap);
        } else {
            let g0 = self.initial_gap.iter().zip(self.along);
            let mut shifted: Vec<f64> = g0.map(|(g, a)| g - a * t).collect();
            for &(along, s) in self.outer.iter().filter(|&&(_, s)| s != 0.0) {
                shifted.iter_mut().zip(along).for_each(|(g, a)| *g -= a * s);
            }
            self.system.set_initial_gap(&shifted);
        }
        let answer = lcp::active_set::solve_friction_step(
            self.system,
            &self.previous,
            self.warm.as_deref(),
            &self.params,
        )?;
        self.iterations += answer.step.iterations;
        self.rescues.extend_from_slice(&answer.rescues);
        self.warm = Some(answer.states.clone());
        self.round_off = self.system.force_round_off();
        Ok(answer)
    }
    fn forces<'b>(&self, answer: &'b Self::Answer) -> &'b [f64] {
        &answer.step.normal
    }
    fn gaps(&self, _q: &[f64], answer: &Self::Answer) -> Vec<f64> {
        answer.step.gap.clone()
    }
    /// `Σ_c |a_c| δP_c` over the last trial's round-off `δP`.
    fn force_round_off(&self, _answer: &Self::Answer, along: &[f64]) -> f64 {
        self.round_off.iter().zip(along).map(|(d, a)| d * a.abs()).sum()
    }
    /// The scale the trials' residuals are measured against
    /// ([`lcp::active_set::ActiveSetParams::force_scale`]).
    fn force_scale(&self) -> f64 {
        self.params.force_scale
    }
    fn set_outer(&mut self, level: usize, s: f64) {
        self.outer[level].1 = s;
    }
    fn slope(
        &mut self,
        answer: &Self::Answer,
        along: &[f64],
        active: &[usize],
    ) -> Result<f64, lcp::LcpError> {
        let rate = self.system.search_rate(&answer.states, active, along)?;
        Ok(active.iter().map(|&c| along[c] * rate[c]).sum())
    }
}
