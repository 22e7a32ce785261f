//! Two elastic bodies in contact (docs/method.md §10.3; increment 10 of
//! docs/dev/dynamics.md): each body has its own lumped mass and `M̂_b = M_b Φ_b + h²θ² K_b`,
//! factorised once; the pair's candidates (on body 1) and the target's operator (on body 2)
//! are condensed into one
//!
//! ```text
//! W = G₁ M̂₁⁻¹ E₁ + G₂ M̂₂⁻¹ E₂
//! ```
//!
//! (the load path's body terms with `M̂_b` for `K_b`). Per step the free velocities of both
//! bodies, the index set from the predicted gaps `g0 + G₁ (q₁ + h/2 v₁) + G₂ (q₂ + h/2 v₂)`,
//! Lemke on `0 ≤ Π ⊥ U_free + W Π + e U ≥ 0` with the pair's relative normal velocity
//! `U = G₁ v₁ + G₂ v₂` (Newton's law), then `v_b⁺ = v_b,free + M̂_b⁻¹ E_b Π`. The impulses act
//! on both bodies with opposite directions, so the total momentum changes only by the loads.
//! With Coulomb friction the tangential terms `G_t,1` (along `t`) and `G_t,2` (along `−t`)
//! enter the same way: the step is Moreau's frictional law on the relative tangential
//! velocity (the one-body friction of [`super::Impacts`] with the sums over both bodies).

use super::stepping::{self, Contacts};
use super::{Body, DynamicsError, Friction, Simulation, Term, energy, mass};
use crate::contact::BodyOperator;
use crate::problem::dynamics::Dynamics;

/// The contact of two bodies: the candidates' operator on body 1, the target's on body 2.
pub struct PairContact<'a> {
    /// `G₁`, `E₁` (the candidates, normal `ν` into body 1).
    pub operator: &'a BodyOperator,
    /// `G₂`, `E₂` (the target's shares, direction `−ν`).
    pub target: &'a BodyOperator,
    /// `g0` (one per candidate).
    pub initial_gap: &'a [f64],
    /// Coulomb friction at the velocity level (`None`: frictionless): the candidates'
    /// tangential term on body 1 (direction `t`) and the target's on body 2 (`−t`).
    pub friction: Option<Friction<'a>>,
}

/// One body at the end of a two-body run.
pub struct BodyEnd {
    /// Nodal parameters `û`.
    pub displacement: Vec<f64>,
    /// Their rates `v̂`.
    pub velocity: Vec<f64>,
    /// The body's mass (one direction's total).
    pub mass: f64,
    /// Its momentum `Σ_I m_I v^h(x_I)`.
    pub momentum: [f64; 2],
}

impl BodyEnd {
    /// The velocity of the body's centre of mass.
    pub fn mean_velocity(&self) -> [f64; 2] {
        [self.momentum[0] / self.mass, self.momentum[1] / self.mass]
    }
}

/// A finished two-body run: the pair's history (forces; the energies and momentum summed over
/// both bodies) and each body's end.
pub struct PairSimulation {
    /// The pair's run: `displacement`, `velocity` and `mass` are body 1's followed by body 2's;
    /// no frames.
    pub simulation: Simulation,
    /// Body 1, body 2.
    pub bodies: [BodyEnd; 2],
}

/// Runs the Moreau–Jean time stepping of two bodies in contact (with friction when
/// `contact.friction` is given), each from its
/// uniform initial velocity (`velocities`, undeformed) to `params.end_time`, reporting
/// `(step, steps)` to `progress`.
///
/// # Errors
/// [`DynamicsError`] when a factorisation, a solve or a step's LCP fails.
pub fn simulate_bodies(
    bodies: [&Body<'_>; 2],
    contact: &PairContact<'_>,
    params: &Dynamics,
    velocities: [[f64; 2]; 2],
    progress: &mut dyn FnMut(usize, usize),
) -> Result<PairSimulation, DynamicsError> {
    let contacts = Contacts {
        normal: vec![
            Term { body: 0, offset: 0, operator: contact.operator },
            Term { body: 1, offset: 0, operator: contact.target },
        ],
        initial_gap: contact.initial_gap.to_vec(),
        friction: contact.friction.clone(),
    };
    let run = stepping::run(&bodies, Some(contacts), params, &velocities, progress)?;
    let mut ends = run.states.into_iter().zip(bodies).map(|(s, body)| {
        let v = mass::nodal_values(body.node_shapes, &s.v);
        BodyEnd {
            momentum: energy::momentum(&body.mass, &v),
            mass: mass::total(&body.mass),
            displacement: s.q,
            velocity: s.v,
        }
    });
    let (Some(first), Some(second)) = (ends.next(), ends.next()) else {
        unreachable!("two states")
    };
    let concat = |a: &[f64], b: &[f64]| [a, b].concat();
    Ok(PairSimulation {
        simulation: Simulation {
            history: run.history,
            frames: run.frames,
            displacement: concat(&first.displacement, &second.displacement),
            velocity: concat(&first.velocity, &second.velocity),
            mass: concat(&bodies[0].mass, &bodies[1].mass),
            final_gap: run.final_gap,
            final_impulses: run.final_impulses,
            seconds: run.seconds,
        },
        bodies: [first, second],
    })
}
