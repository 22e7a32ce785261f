//! Elastic bodies in contact (docs/method.md §10.3; increment 10 of docs/dev/dynamics.md):
//! each body has its own lumped mass and `M̂_b = M_b Φ_b + h²θ² K_b`, factorised once; every
//! contact pair's candidates (on its body) and, between two bodies, the target's operator
//! (on the target body) are condensed into one
//!
//! ```text
//! W = Σ_terms G_b M̂_b⁻¹ E_b         (two bodies, one pair: G₁ M̂₁⁻¹ E₁ + G₂ M̂₂⁻¹ E₂)
//! ```
//!
//! (the load path's body terms with `M̂_b` for `K_b`; pairs that share a body couple). Per
//! step the free velocities of all bodies, the index set from the predicted gaps
//! `g0 + Σ G_b (q_b + h/2 v_b)`, Lemke on `0 ≤ Π ⊥ U_free + W Π + e U ≥ 0` with each
//! candidate's relative normal velocity `U = Σ G_b v_b` (Newton's law), then
//! `v_b⁺ = v_b,free + M̂_b⁻¹ Σ E_b Π`. Between bodies the impulses act on both with opposite
//! directions, so the total momentum changes only by the loads and the rigid obstacles.
//! With Coulomb friction the tangential terms `G_t,1` (along `t`) and `G_t,2` (along `−t`)
//! enter the same way: the step is Moreau's frictional law on the relative tangential
//! velocity (the one-body friction of [`super::Impacts`] with the sums over the bodies).

use super::stepping::{self, Contacts};
use super::{Body, DynamicsError, Simulation, mass};
use crate::problem::dynamics::Dynamics;

/// One body at the end of a run of several bodies.
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

/// A finished run of several bodies: the scene's history (the total contact force and each
/// pair's; the energies and momentum summed over the bodies) and each body's end.
pub struct BodiesSimulation {
    /// The scene's run: `displacement`, `velocity` and `mass` are the bodies' one after the
    /// other; each frame holds every body.
    pub simulation: Simulation,
    /// Each body's end, in body order.
    pub bodies: Vec<BodyEnd>,
}

/// Runs the Moreau–Jean time stepping of `bodies` in the contact pairs `contacts` (with
/// friction when `contacts.friction` is given), each body from its uniform initial velocity
/// (`velocities`, undeformed) to `params.end_time`, reporting `(step, steps)` to `progress`.
///
/// # Errors
/// [`DynamicsError`] when a factorisation, a solve or a step's LCP fails.
pub fn simulate_bodies(
    bodies: &[&Body<'_>],
    contacts: Contacts<'_>,
    params: &Dynamics,
    velocities: &[[f64; 2]],
    progress: &mut dyn FnMut(usize, usize),
) -> Result<BodiesSimulation, DynamicsError> {
    let run = stepping::run(bodies, Some(contacts), params, velocities, progress)?;
    let ends: Vec<BodyEnd> = run
        .states
        .into_iter()
        .zip(bodies)
        .map(|(s, body)| {
            let v = mass::nodal_values(body.node_shapes, &s.v);
            BodyEnd {
                momentum: body.mass.momentum(&v),
                mass: body.mass.total(),
                displacement: s.q,
                velocity: s.v,
            }
        })
        .collect();
    let concat = |f: &dyn Fn(&BodyEnd) -> &[f64]| ends.iter().flat_map(f).copied().collect();
    Ok(BodiesSimulation {
        simulation: Simulation {
            history: run.history,
            frames: run.frames,
            displacement: concat(&|e| &e.displacement),
            velocity: concat(&|e| &e.velocity),
            mass: bodies.iter().flat_map(|b| b.mass.row_sums()).collect(),
            final_gap: run.final_gap,
            final_impulses: run.final_impulses,
            seconds: run.seconds,
        },
        bodies: ends,
    })
}
