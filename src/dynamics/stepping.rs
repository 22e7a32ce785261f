//! The time-step loop shared by one body against rigid obstacles ([`super::simulate`]) and
//! bodies in contact ([`super::simulate_bodies`]): per step each body's free velocity, the
//! candidates' index set and LCP over all bodies ([`Impacts`]), each body's velocity and
//! position update, and one [`Record`] of the bodies summed. A run is its bodies and the
//! [`Term`]s through which the candidates act on them.

use super::impacts::StepImpulses;
use super::loads::{ObstacleMotion, ObstacleStep, StepSide};
use super::mass::Mass;
use super::sparse::SparseStep;
use super::{Body, DynamicsError, Frame, History, Impacts, Iteration, Record, Seconds, State};
use super::{Friction, StepLoad, Term, free_load, record, recorded_mass};
use crate::geometry::Point;
use crate::nodes::Axis;
use crate::problem::ContactSolver;
use crate::problem::dynamics::Dynamics;
use std::borrow::Cow;
use std::time::Instant;

/// The candidates of a run before condensation: every contact pair's, numbered pair after
/// pair.
pub struct Contacts<'a> {
    /// The normal terms (`G_b`, `E_b` of the candidates on each body; a pair of bodies has
    /// two, the candidates' and the target's, a pair against rigid obstacles one), each at
    /// its pair's first candidate.
    pub normal: Vec<Term<'a>>,
    /// `g0`, one per candidate.
    pub initial_gap: Vec<f64>,
    /// Coulomb friction at the velocity level (`None`: frictionless).
    pub friction: Option<Friction<'a>>,
    /// The first candidate of each contact pair, ascending from 0 (`[0]` for one pair): with
    /// several, each record carries each pair's force ([`Record::pair_forces`]).
    pub pair_starts: Vec<usize>,
    /// The rigid obstacles' motion in time (`None`: at rest; docs/method.md §10.6).
    pub obstacle: Option<ObstacleMotion>,
}

/// A finished run of the loop.
pub(super) struct Run {
    /// Records at time 0 and after every step (the bodies summed).
    pub history: History,
    /// Snapshots of every body.
    pub frames: Vec<Frame>,
    /// Each body's state at the end.
    pub states: Vec<State>,
    /// Each candidate's gap at the end (empty without contact).
    pub final_gap: Vec<f64>,
    /// Each candidate's impulse over the last step (empty without contact).
    pub final_impulses: Vec<f64>,
    /// Wall times.
    pub seconds: Seconds,
}

/// Runs the Moreau–Jean time stepping of `bodies`, each from its uniform initial velocity
/// (`velocities`, undeformed), in the contact `contacts`, to `params.end_time`, reporting
/// `(step, steps)` to `progress`.
///
/// # Errors
/// [`DynamicsError`] when a factorisation, a solve or a step's LCP fails.
pub(super) fn run(
    bodies: &[&Body<'_>],
    contacts: Option<Contacts<'_>>,
    params: &Dynamics,
    velocities: &[[f64; 2]],
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Run, DynamicsError> {
    let (h, theta) = (params.time_step, params.theta);
    let mut seconds = Seconds::default();
    let clock = Instant::now();
    let iterations = bodies
        .iter()
        .map(|b| Iteration::new(b.system, &b.mass, b.node_shapes, h, theta, b.points))
        .collect::<Result<Vec<_>, _>>()?;
    let pair_starts = contacts.as_ref().map_or_else(Vec::new, |c| c.pair_starts.clone());
    let active_set = params.solver == ContactSolver::ActiveSet;
    let points: Vec<&[Point]> = bodies.iter().map(|b| b.points).collect();
    let zeros: Vec<Vec<f64>> = match active_set {
        true => bodies.iter().map(|b| vec![0.0; b.system.matrix.n]).collect(),
        false => Vec::new(),
    };
    let mut sparse = None;
    let impacts = match contacts {
        Some(c) if active_set => {
            let m = c.initial_gap.len();
            let friction = c.friction.as_ref();
            sparse = Some(SparseStep::new(&iterations, &points, &zeros, &c.normal, m, friction)?);
            Some(
                Impacts::uncondensed(&c.normal, c.initial_gap, c.friction)
                    .with_obstacle(c.obstacle),
            )
        }
        Some(c) => Some(
            Impacts::new(&iterations, &c.normal, c.initial_gap, c.friction)?
                .with_obstacle(c.obstacle),
        ),
        None => None,
    };
    seconds.setup = clock.elapsed().as_secs_f64();
    let loads: Vec<Vec<f64>> = bodies.iter().map(|b| free_load(b.system)).collect();
    let mut states = initial_states(bodies, velocities);
    let masses: Vec<Cow<'_, Mass>> = bodies.iter().map(|b| recorded_mass(b)).collect();
    let mut start = summed(bodies, &masses, &states, 0.0);
    if pair_starts.len() > 1 {
        start.pair_forces = vec![0.0; pair_starts.len()];
    }
    let mut history = History { records: vec![start] };
    let steps = params.steps();
    let snapshot =
        |step: usize| params.snapshot_every.is_some_and(|k| step % k == 0 || step == steps);
    let mut frames = Vec::new();
    if snapshot(0) {
        frames.push(Frame::of(bodies, &states, 0, 0.0));
    }
    let mut final_impulses = Vec::new();
    for step in 1..=steps {
        let factor = params.load_factor((step as f64 - 1.0 + theta) * h);
        // Each body's loads and prescribed values of the step when they vary in time.
        let (t0, t1) = ((step - 1) as f64 * h, step as f64 * h);
        let sides: Vec<Option<StepSide>> = bodies
            .iter()
            .map(|b| b.history.as_ref().map(|l| l.step(b.system, t0, t1, theta)))
            .collect();
        let load = |b: usize| match &sides[b] {
            Some(side) => StepLoad::Given(&side.rhs),
            None => StepLoad::Scaled(factor),
        };
        // The moving obstacles' step (docs/method.md §10.6).
        let obstacle = impacts.as_ref().and_then(|i| i.obstacle_step(step - 1, h));
        let obstacle = obstacle.as_ref();
        // The sparse step: on a non-empty index set the step's velocities come from the
        // sparse system (its free solve included), timed as the LCP.
        let sparse_step = match (&impacts, sparse.as_mut()) {
            (Some(impacts), Some(sparse)) => {
                let clock = Instant::now();
                let (q, v) = (positions(&states), self::velocities(&states));
                let active = impacts.index_set(&q, &v, h, obstacle);
                let answer = if active.is_empty() {
                    None
                } else {
                    let rhs: Vec<Vec<f64>> = iterations
                        .iter()
                        .zip(&states)
                        .enumerate()
                        .map(|(b, (it, s))| it.free_rhs(&s.q, &s.v, load(b)))
                        .collect();
                    let e = params.restitution;
                    Some(sparse.step(impacts, &active, &rhs, &v, e, step, obstacle)?)
                };
                seconds.lcp += clock.elapsed().as_secs_f64();
                answer.map(|(v, a)| (v, (impacts, a)))
            }
            _ => None,
        };
        let (v_next, answer) = match sparse_step {
            Some((v_next, answer)) => (v_next, Some(answer)),
            None => {
                let clock = Instant::now();
                let v_free = iterations
                    .iter()
                    .zip(&states)
                    .enumerate()
                    .map(|(b, (it, s))| it.free_velocity(&s.q, &s.v, load(b)))
                    .collect::<Result<Vec<_>, _>>()?;
                seconds.free += clock.elapsed().as_secs_f64();
                match (&impacts, sparse.is_some()) {
                    (Some(impacts), false) => {
                        let clock = Instant::now();
                        let answer =
                            contact_step(impacts, &states, &v_free, params, step, obstacle)?;
                        seconds.lcp += clock.elapsed().as_secs_f64();
                        let v_next = v_free
                            .into_iter()
                            .enumerate()
                            .map(|(b, v)| impacts.apply(b, v, &answer.impulses, &answer.tangential))
                            .collect();
                        (v_next, Some((impacts, answer)))
                    }
                    (Some(impacts), true) => {
                        (v_free, Some((impacts, StepImpulses::none(impacts.len()))))
                    }
                    (None, _) => (v_free, None),
                }
            }
        };
        let previous = &history.records[history.records.len() - 1];
        let start = (previous.external_work, previous.contact_loss);
        let applied = Applied { bodies, loads: &loads, factor, sides: &sides };
        let (next, (external, loss)) =
            advance(&states, v_next, answer.as_ref(), obstacle, &applied, params, start);
        states = next;
        let clock = Instant::now();
        let mut rec = summed(bodies, &masses, &states, step as f64 * h);
        seconds.records += clock.elapsed().as_secs_f64();
        (rec.external_work, rec.contact_loss) = (external, loss);
        if let Some((_, answer)) = answer {
            with_contact(&mut rec, &answer, h, &pair_starts);
            final_impulses = answer.impulses;
        }
        history.records.push(rec);
        if snapshot(step) {
            frames.push(Frame::of(bodies, &states, step, step as f64 * h));
        }
        progress(step, steps);
    }
    let end = steps as f64 * h;
    let final_gap = impacts.as_ref().map_or_else(Vec::new, |c| c.gaps_at(&positions(&states), end));
    Ok(Run { history, frames, states, final_gap, final_impulses, seconds })
}

/// Each body undeformed at its uniform velocity.
fn initial_states(bodies: &[&Body<'_>], velocities: &[[f64; 2]]) -> Vec<State> {
    bodies
        .iter()
        .zip(velocities)
        .map(|(b, u)| State {
            q: vec![0.0; b.system.matrix.n],
            v: (0..b.system.matrix.n).map(|d| u[d % 2]).collect(),
        })
        .collect()
}

/// The step's index set and impulses over all bodies.
fn contact_step(
    impacts: &Impacts<'_>,
    states: &[State],
    v_free: &[Vec<f64>],
    params: &Dynamics,
    step: usize,
    obstacle: Option<&ObstacleStep<'_>>,
) -> Result<StepImpulses, DynamicsError> {
    let (q, v) = (positions(states), velocities(states));
    let active = impacts.index_set(&q, &v, params.time_step, obstacle);
    let v_free: Vec<&[f64]> = v_free.iter().map(Vec::as_slice).collect();
    impacts.impulses(&active, &v_free, &v, params.restitution, step, obstacle)
}

/// The applied side of a step, per body: the constant loads (`loads`, scaled by the ramp's
/// `factor`) or the step's side of a history (`sides`).
struct Applied<'s, 'b> {
    bodies: &'s [&'s Body<'b>],
    loads: &'s [Vec<f64>],
    factor: f64,
    sides: &'s [Option<StepSide>],
}

/// Each body's next state from its velocity at the step's end `v_next` (the step's
/// impulses applied), with the work done on the bodies since time 0 (`start.0` plus the
/// loads' `fᵀ Δq`, the prescribed displacements' work and a moving `obstacle`'s work,
/// body after body) and the energy taken by the contacts (`start.1` minus the impulses'
/// work `/ h` on the bodies' motion relative to the obstacle's, docs/method.md §10.6).
fn advance(
    states: &[State],
    v_next: Vec<Vec<f64>>,
    answer: Option<&(&Impacts<'_>, StepImpulses)>,
    obstacle: Option<&ObstacleStep<'_>>,
    applied: &Applied<'_, '_>,
    params: &Dynamics,
    start: (f64, f64),
) -> (Vec<State>, (f64, f64)) {
    let (h, theta) = (params.time_step, params.theta);
    let (mut external, mut loss) = start;
    let mut next = Vec::with_capacity(states.len());
    for (b, (s, v)) in states.iter().zip(v_next).enumerate() {
        let q: Vec<f64> =
            (0..v.len()).map(|d| s.q[d] + h * ((1.0 - theta) * s.v[d] + theta * v[d])).collect();
        let dq: Vec<f64> = q.iter().zip(&s.q).map(|(a, b)| a - b).collect();
        let next_state = State { q, v };
        match &applied.sides[b] {
            None => {
                let f = &applied.loads[b];
                external += applied.factor * f.iter().zip(&dq).map(|(f, d)| f * d).sum::<f64>();
            }
            Some(side) => {
                external += side.free_load.iter().zip(&dq).map(|(f, d)| f * d).sum::<f64>();
                let contact =
                    answer.map(|(i, a)| i.forces(b, &a.impulses, &a.tangential, dq.len()));
                let body = applied.bodies[b];
                external += support_work(body, s, &next_state, side, contact.as_deref(), params);
                let prescribed = |d: usize| body.system.is_constrained(d);
                external += body.mass.support_inertia_work(&s.v, &next_state.v, prescribed);
            }
        }
        match (answer, obstacle) {
            (Some((impacts, a)), Some(o)) => {
                let moved = impacts.obstacle_work(b, &a.impulses, &a.tangential, dq.len(), o);
                loss -= (impacts.work(b, &a.impulses, &a.tangential, &dq) - moved) / h;
                external += moved / h;
            }
            (Some((impacts, a)), None) => {
                loss -= impacts.work(b, &a.impulses, &a.tangential, &dq) / h;
            }
            (None, _) => {}
        }
        next.push(next_state);
    }
    (next, (external, loss))
}

/// The work done on `body` at its prescribed DOFs over the step from `s` to `next` (docs/method.md
/// §10.5): `Σ_d F_d Δū_d` over the DOFs whose prescribed value moves by `Δū_d`
/// (`side.moved`), with `F_d = (K q_{n+θ})_d − (E Π)_d / h` the force the support (and any
/// load on that row) exerts there: the balance of the massless row `d` that its
/// prescribed-value row replaced (`K` unconstrained: the interior faces' fluxes, or the FE
/// stiffness; the contact's share is in the contact's work).
fn support_work(
    body: &Body<'_>,
    s: &State,
    next: &State,
    side: &StepSide,
    contact: Option<&[f64]>,
    params: &Dynamics,
) -> f64 {
    if side.moved.is_empty() {
        return 0.0;
    }
    let (h, theta) = (params.time_step, params.theta);
    let q_theta: Vec<f64> =
        s.q.iter().zip(&next.q).map(|(a, b)| (1.0 - theta) * a + theta * b).collect();
    let k = &body.system.interior_stiffness;
    side.moved
        .iter()
        .map(|&(d, du)| {
            let (node, a) = (d / 2, d % 2);
            let axis = if a == 0 { Axis::X } else { Axis::Y };
            let contact = contact.map_or(0.0, |e| e[d] / h);
            (k.row_dot(node, axis, &q_theta) - contact) * du
        })
        .sum()
}

/// `rec` with the step's contact: the mean force `Σ Π / h` (and each pair's, with several
/// pairs starting at `pair_starts`), the index set's size, Lemke's pivots and the LCP's
/// residual.
fn with_contact(rec: &mut Record, answer: &StepImpulses, h: f64, pair_starts: &[usize]) {
    rec.contact_force = answer.impulses.iter().sum::<f64>() / h;
    if pair_starts.len() > 1 {
        let ends = pair_starts[1..].iter().copied().chain([answer.impulses.len()]);
        rec.pair_forces = pair_starts
            .iter()
            .zip(ends)
            .map(|(&a, b)| answer.impulses[a..b].iter().sum::<f64>() / h)
            .collect();
    }
    rec.active = answer.active;
    rec.pivots = answer.pivots;
    rec.residual = answer.residual;
}

/// The bodies' records at `time`, summed (without contact or work: the caller adds them).
fn summed(bodies: &[&Body<'_>], masses: &[Cow<'_, Mass>], states: &[State], time: f64) -> Record {
    let mut records =
        bodies.iter().zip(masses).zip(states).map(|((b, m), s)| record(b, m, s, time));
    let first = records.next().unwrap_or_else(|| unreachable!("a run has a body"));
    records.fold(first, |a, b| Record {
        kinetic_energy: a.kinetic_energy + b.kinetic_energy,
        strain_energy: a.strain_energy + b.strain_energy,
        momentum: [a.momentum[0] + b.momentum[0], a.momentum[1] + b.momentum[1]],
        ..a
    })
}

/// The bodies' positions `q_b`.
fn positions(states: &[State]) -> Vec<&[f64]> {
    states.iter().map(|s| s.q.as_slice()).collect()
}

/// The bodies' velocities `v_b`.
fn velocities(states: &[State]) -> Vec<&[f64]> {
    states.iter().map(|s| s.v.as_slice()).collect()
}
