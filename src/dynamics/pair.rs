//! Two elastic bodies in frictionless contact (docs/method.md §10.3; increment 10 of
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

use super::impacts::{block, condensed_columns, solve_on};
use super::{Body, DynamicsError, History, Iteration, Record, Seconds, Simulation, State};
use super::{energy, free_load, mass, record};
use crate::contact::BodyOperator;
use crate::problem::dynamics::Dynamics;
use std::time::Instant;

/// The contact of two bodies: the candidates' operator on body 1, the target's on body 2.
pub struct PairContact<'a> {
    /// `G₁`, `E₁` (the candidates, normal `ν` into body 1).
    pub operator: &'a BodyOperator,
    /// `G₂`, `E₂` (the target's shares, direction `−ν`).
    pub target: &'a BodyOperator,
    /// `g0` (one per candidate).
    pub initial_gap: &'a [f64],
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

/// Runs the Moreau–Jean time stepping of two bodies in frictionless contact, each from its
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
    let (h, theta) = (params.time_step, params.theta);
    let mut seconds = Seconds::default();
    let clock = Instant::now();
    let operators = [contact.operator, contact.target];
    let dofs = bodies.map(|b| b.system.matrix.n);
    let mut iterations = Vec::with_capacity(2);
    let mut columns = Vec::with_capacity(2);
    for (b, body) in bodies.iter().enumerate() {
        let iteration =
            Iteration::new(body.system, &body.mass, body.node_shapes, h, theta, body.points)?;
        columns.push(condensed_columns(&iteration, operators[b], dofs[b])?);
        iterations.push(iteration);
    }
    let m = contact.initial_gap.len();
    let mut compliance = block(operators[0], &columns[0]);
    for (w, w2) in compliance.iter_mut().zip(block(operators[1], &columns[1])) {
        *w += w2;
    }
    seconds.setup = clock.elapsed().as_secs_f64();
    let loads = bodies.map(|b| free_load(b.system));
    let mut states: Vec<State> = (0..2)
        .map(|b| State {
            q: vec![0.0; dofs[b]],
            v: (0..dofs[b]).map(|d| velocities[b][d % 2]).collect(),
        })
        .collect();
    let both = |states: &[State], time: f64| {
        sum(record(bodies[0], &states[0], time), &record(bodies[1], &states[1], time))
    };
    // `Σ_b G_b x_b` (the pair's relative normal velocity for velocities) and `g0 + Σ_b G_b x_b`.
    let rates = |x: [&[f64]; 2]| -> Vec<f64> {
        let mut g = operators[0].gap_contribution(x[0]);
        for (g, d) in g.iter_mut().zip(operators[1].gap_contribution(x[1])) {
            *g += d;
        }
        g
    };
    let gaps = |x: [&[f64]; 2]| -> Vec<f64> {
        rates(x).into_iter().zip(contact.initial_gap).map(|(r, g0)| g0 + r).collect()
    };
    let mut history = History { records: vec![both(&states, 0.0)] };
    let steps = params.steps();
    let mut final_impulses = Vec::new();
    for step in 1..=steps {
        let factor = params.load_factor((step as f64 - 1.0 + theta) * h);
        let v_free = [
            iterations[0].free_velocity(&states[0].q, &states[0].v, factor)?,
            iterations[1].free_velocity(&states[1].q, &states[1].v, factor)?,
        ];
        let lcp_clock = Instant::now();
        let ahead: Vec<Vec<f64>> = states
            .iter()
            .map(|s| s.q.iter().zip(&s.v).map(|(q, v)| q + 0.5 * h * v).collect())
            .collect();
        let predicted = gaps([&ahead[0], &ahead[1]]);
        let active: Vec<usize> = (0..m).filter(|&c| predicted[c] <= 0.0).collect();
        let mut impulses = vec![0.0; m];
        let (mut pivots, mut residual) = (0, 0.0);
        if !active.is_empty() {
            let u_free = rates([&v_free[0], &v_free[1]]);
            let u = rates([&states[0].v, &states[1].v]);
            let q: Vec<f64> =
                active.iter().map(|&c| u_free[c] + params.restitution * u[c]).collect();
            let (z, p, r) = solve_on(&compliance, m, &active, q, step)?;
            for (&c, z) in active.iter().zip(&z) {
                impulses[c] = *z;
            }
            (pivots, residual) = (p, r);
        }
        seconds.lcp += lcp_clock.elapsed().as_secs_f64();
        let previous = &history.records[history.records.len() - 1];
        let (mut external, mut loss) = (previous.external_work, previous.contact_loss);
        let mut next = Vec::with_capacity(2);
        for (b, v_free) in v_free.into_iter().enumerate() {
            let mut v = v_free;
            for (y, &p) in columns[b].iter().zip(&impulses) {
                if p != 0.0 {
                    for (v, y) in v.iter_mut().zip(y) {
                        *v += p * y;
                    }
                }
            }
            let s = &states[b];
            let q: Vec<f64> = (0..dofs[b])
                .map(|d| s.q[d] + h * ((1.0 - theta) * s.v[d] + theta * v[d]))
                .collect();
            let dq: Vec<f64> = q.iter().zip(&s.q).map(|(a, b)| a - b).collect();
            external += factor * loads[b].iter().zip(&dq).map(|(f, d)| f * d).sum::<f64>();
            let mut e = vec![0.0; dofs[b]];
            operators[b].add_forces(&impulses, &mut e);
            loss -= e.iter().zip(&dq).map(|(e, d)| e * d).sum::<f64>() / h;
            next.push(State { q, v });
        }
        states = next;
        let mut rec = both(&states, step as f64 * h);
        rec.external_work = external;
        rec.contact_loss = loss;
        rec.contact_force = impulses.iter().sum::<f64>() / h;
        rec.active = active.len();
        rec.pivots = pivots;
        rec.residual = residual;
        if !active.is_empty() {
            final_impulses.clone_from(&impulses);
        }
        history.records.push(rec);
        progress(step, steps);
    }
    let final_gap = gaps([&states[0].q, &states[1].q]);
    let end = |s: State, body: &Body<'_>| {
        let v = mass::nodal_values(body.node_shapes, &s.v);
        BodyEnd {
            momentum: energy::momentum(&body.mass, &v),
            mass: mass::total(&body.mass),
            displacement: s.q,
            velocity: s.v,
        }
    };
    let second_state = states.pop();
    let (first, second) = match (states.pop(), second_state) {
        (Some(a), Some(b)) => (end(a, bodies[0]), end(b, bodies[1])),
        _ => unreachable!("two states"),
    };
    let concat = |a: &[f64], b: &[f64]| [a, b].concat();
    Ok(PairSimulation {
        simulation: Simulation {
            history,
            frames: Vec::new(),
            displacement: concat(&first.displacement, &second.displacement),
            velocity: concat(&first.velocity, &second.velocity),
            mass: concat(&bodies[0].mass, &bodies[1].mass),
            final_gap,
            final_impulses,
            seconds,
        },
        bodies: [first, second],
    })
}

/// The records of two bodies at one time, summed (time and contact from `a`).
fn sum(a: Record, b: &Record) -> Record {
    Record {
        kinetic_energy: a.kinetic_energy + b.kinetic_energy,
        strain_energy: a.strain_energy + b.strain_energy,
        momentum: [a.momentum[0] + b.momentum[0], a.momentum[1] + b.momentum[1]],
        ..a
    }
}
