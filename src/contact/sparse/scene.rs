//! What the sparse load path asks of a sparse contact system ([`SceneSystem`]): one interface
//! over [`RigidObstacle`] (one body against rigid obstacles, which may own and release `K`'s
//! factors at 10⁶ nodes) and [`Bodies`] (any number of bodies and pairs), so that one walk
//! over steps and increments drives both (docs/method.md §5.1, §8).

use super::{Bodies, PairTangential, RigidObstacle, RigidObstacleStats};
use crate::lcp::active_set::{ActiveSetError, ActiveSetSystem, FrictionSystem};
use crate::lcp::friction::ContactState;

/// A sparse contact system of bodies (numbered from 0) and pairs (their candidates numbered
/// pair after pair) as the load path drives it: per increment the bodies' right-hand sides
/// and the obstacles' gaps and tangential offsets, per step the coefficients `μ_c`; the
/// frictionless ([`ActiveSetSystem`]) or frictional ([`FrictionSystem`]) step solved on it;
/// the bodies' displacements of the final states; the rates a force search's slope needs.
pub trait SceneSystem<'a>: ActiveSetSystem + FrictionSystem {
    /// Sets the right-hand side `f_b` of body `b`.
    fn set_body_load(&mut self, b: usize, rhs: &[f64]);
    /// Sets the gaps without displacement `g0_c` of all candidates.
    fn set_initial_gap(&mut self, initial_gap: &[f64]);
    /// Sets the obstacles' tangential displacement `o_c = d·t_c` per candidate.
    fn set_tangential_offset(&mut self, offset: &[f64]);
    /// Sets `μ_c` over all candidates with each pair's tangential operators (a system that
    /// derives them from its own operators ignores `tangential`).
    ///
    /// # Errors
    /// The system's own ([`Bodies::set_friction`], [`RigidObstacle::set_friction`]).
    fn set_pair_friction(
        &mut self,
        mu: &[f64],
        tangential: Vec<PairTangential<'a>>,
    ) -> Result<(), ActiveSetError>;
    /// Every body's displacements of the frictionless closed set `active` (those of the last
    /// solve when it solved that set).
    ///
    /// # Errors
    /// A failed solve.
    fn final_body_displacements(
        &mut self,
        active: &[bool],
    ) -> Result<Vec<Vec<f64>>, ActiveSetError>;
    /// Every body's displacements of the frictional step that settled on `states`.
    ///
    /// # Errors
    /// A failed solve.
    fn final_body_friction_displacements(
        &mut self,
        states: &[ContactState],
    ) -> Result<Vec<Vec<f64>>, ActiveSetError>;
    /// The round-off of the last solve's normal forces per candidate (empty when the system
    /// does not estimate it: the force search then sees none).
    fn force_round_off(&self) -> Vec<f64>;
    /// The rates `dP/ds` of the normal forces when the gaps without displacement move as
    /// `g0 − a s` (`along` = `a`), on the problem whose candidates `active` are closed
    /// (`states`: the last answer's, for a system whose closed candidates keep their
    /// frictional state).
    ///
    /// # Errors
    /// A failed solve.
    fn search_rate(
        &mut self,
        states: &[ContactState],
        active: &[usize],
        along: &[f64],
    ) -> Result<Vec<f64>, ActiveSetError>;
    /// The work counters.
    fn stats(&self) -> RigidObstacleStats;
}

impl<'a> SceneSystem<'a> for Bodies<'a> {
    fn set_body_load(&mut self, b: usize, rhs: &[f64]) {
        Bodies::set_body_load(self, b, rhs);
    }
    fn set_initial_gap(&mut self, initial_gap: &[f64]) {
        Bodies::set_initial_gap(self, initial_gap);
    }
    fn set_tangential_offset(&mut self, offset: &[f64]) {
        Bodies::set_tangential_offset(self, offset);
    }
    fn set_pair_friction(
        &mut self,
        mu: &[f64],
        tangential: Vec<PairTangential<'a>>,
    ) -> Result<(), ActiveSetError> {
        self.set_friction(mu, tangential)
    }
    fn final_body_displacements(
        &mut self,
        active: &[bool],
    ) -> Result<Vec<Vec<f64>>, ActiveSetError> {
        Bodies::final_body_displacements(self, active)
    }
    fn final_body_friction_displacements(
        &mut self,
        states: &[ContactState],
    ) -> Result<Vec<Vec<f64>>, ActiveSetError> {
        Bodies::final_body_friction_displacements(self, states)
    }
    fn force_round_off(&self) -> Vec<f64> {
        Bodies::force_round_off(self)
    }
    /// The frictionless closed set `active`'s rates ([`Bodies::force_rate`]; `states` unread).
    fn search_rate(
        &mut self,
        _states: &[ContactState],
        active: &[usize],
        along: &[f64],
    ) -> Result<Vec<f64>, ActiveSetError> {
        let mut closed = vec![false; along.len()];
        for &c in active {
            closed[c] = true;
        }
        self.force_rate(&closed, along)
    }
    fn stats(&self) -> RigidObstacleStats {
        self.stats
    }
}

/// One body (body 0) against rigid obstacles: the load is the body's right-hand side, the
/// tangential operators its own (derived from the candidates' operator).
impl<'a> SceneSystem<'a> for RigidObstacle<'a> {
    fn set_body_load(&mut self, b: usize, rhs: &[f64]) {
        debug_assert_eq!(b, 0, "a rigid obstacle's system has one body");
        self.set_rhs(rhs);
    }
    fn set_initial_gap(&mut self, initial_gap: &[f64]) {
        RigidObstacle::set_initial_gap(self, initial_gap);
    }
    fn set_tangential_offset(&mut self, offset: &[f64]) {
        RigidObstacle::set_tangential_offset(self, offset);
    }
    fn set_pair_friction(
        &mut self,
        mu: &[f64],
        _tangential: Vec<PairTangential<'a>>,
    ) -> Result<(), ActiveSetError> {
        self.set_friction(mu)
    }
    fn final_body_displacements(
        &mut self,
        active: &[bool],
    ) -> Result<Vec<Vec<f64>>, ActiveSetError> {
        self.final_displacements(active).map(|u| vec![u])
    }
    fn final_body_friction_displacements(
        &mut self,
        states: &[ContactState],
    ) -> Result<Vec<Vec<f64>>, ActiveSetError> {
        self.final_friction_displacements(states).map(|u| vec![u])
    }
    /// None estimated (the search's default).
    fn force_round_off(&self) -> Vec<f64> {
        Vec::new()
    }
    /// The rates of the answer's `states` with the `active` candidates that it leaves open
    /// closed as sticking ([`RigidObstacle::force_rate`]).
    fn search_rate(
        &mut self,
        states: &[ContactState],
        active: &[usize],
        along: &[f64],
    ) -> Result<Vec<f64>, ActiveSetError> {
        let mut closed = vec![ContactState::Open; states.len()];
        for &c in active {
            closed[c] = match states[c] {
                ContactState::Open => ContactState::Stick,
                s => s,
            };
        }
        self.force_rate(&closed, along)
    }
    fn stats(&self) -> RigidObstacleStats {
        self.stats
    }
}
