//! Stage 10: elastodynamics with contact — Moreau–Jean time stepping of one body against
//! rigid obstacles (docs/method.md §10; the plan in docs/dev/dynamics.md).
//!
//! Per step `n → n + 1` (step `h`, `θ ∈ [½, 1]`, restitution `e`):
//!
//! ```text
//! v_free = v + M̂⁻¹ h (s f − K (q + hθ v))          M̂ = M Φ + h²θ² K, factorised once;
//!                                                    s = min(t_{n+θ} / T_r, 1) (load ramp)
//! A      = { c : g_c(q + h/2 v) ≤ τ_c }               index set from the predicted gap
//! Π_A    : 0 ≤ Π ⊥ G v_free + W Π + e G v ≥ 0         W = G M̂⁻¹ E, condensed once
//! v⁺     = v_free + M̂⁻¹ E Π
//! q⁺     = q + h ((1 − θ) v + θ v⁺)
//! ```
//!
//! With `contact.solver = "active_set"` no `W` is formed: a step with a non-empty index set
//! solves `M̂` with the active candidates' rows replaced by their gap rows (`sparse`).
//!
//! - [`mass`]: the lumped mass `ρ |Ω_I|` on the nodal values `Φ û`;
//! - `iteration` (private): `M̂` and the free velocity;
//! - [`LoadHistory`]: loads and prescribed displacements in time (`[[step]]` with `time`);
//! - [`ObstacleMotion`]: the rigid obstacles' displacement in time (`[[step]]`
//!   `obstacle_displacement` with `time`): the contact law on the velocities relative to
//!   theirs (docs/method.md §10.6);
//! - [`Impacts`]: `W`, the index set and each step's LCP, over the bodies' [`Term`]s;
//! - `sparse` (private): the step's contact on the sparse system without `W`
//!   (`contact.solver = "active_set"`);
//! - `stepping` (private): the step loop of one body and of bodies in contact;
//! - [`energy`]: kinetic and strain energies, momentum;
//! - [`history`]: one record per step and the run's figures.

pub mod energy;
pub mod history;
mod impacts;
mod iteration;
mod loads;
pub mod mass;
mod pair;
mod sparse;
mod stepping;

pub use history::{Figures, History, PairFigures, Record};

pub use impacts::{ACTIVATION, Friction, Impacts, Term};
pub use iteration::{Iteration, StepLoad};
pub use loads::{LoadHistory, ObstacleMotion, ObstacleStep};
pub use pair::{BodiesSimulation, BodyEnd, simulate_bodies};
pub use stepping::Contacts;

use crate::assembly::{BlockRows, GlobalSystem};
use crate::contact::BodyOperator;
use crate::geometry::Point;
use crate::lcp::LcpError;
use crate::lcp::active_set::ActiveSetError;
use crate::linear_solve::SolveError;
use crate::material::Constitutive;
use crate::mls::ShapeSet;
use crate::problem::dynamics::Dynamics;
use crate::weak_form::Cell;

/// Failures of the time stepping.
#[derive(Debug, thiserror::Error)]
pub enum DynamicsError {
    /// The iteration matrix could not be factorised or a solve was not finite.
    #[error("time stepping: {0}")]
    Solve(#[from] SolveError),
    /// A step's contact LCP failed.
    #[error(
        "time step {step}: the contact LCP failed ({cause}); a smaller dynamics.time_step may help"
    )]
    Lcp {
        /// The step.
        step: usize,
        /// Lemke's error (named in the message: not a `source`, which would repeat it).
        cause: LcpError,
    },
    /// A step's contact on the sparse system failed (`contact.solver = "active_set"`; step 0:
    /// the system could not be built).
    #[error("time step {step}: the active-set contact step failed ({cause})")]
    ActiveSet {
        /// The step.
        step: usize,
        /// The active-set method's error (named in the message: not a `source`, which would
        /// repeat it).
        cause: ActiveSetError,
    },
}

/// What the time stepping needs of a discretised body (MFVM or finite elements).
pub struct Body<'a> {
    /// `K` with its collocation rows (MFVM) or eliminated rows (FE), and `f`.
    pub system: &'a GlobalSystem,
    /// The nodal values `Φ` of the parameters: the MLS shape functions at the nodes (with
    /// gradients: collocated strains), or the identity of the finite elements.
    pub node_shapes: &'a ShapeSet,
    /// Node positions (the ordering of the factorisation).
    pub points: &'a [Point],
    /// The mass on the DOFs (interleaved): lumped, acting on the nodal values `Φ v̂`, or the
    /// FE's consistent one.
    pub mass: mass::Mass,
    /// How the strain energy is measured.
    pub strain: StrainEnergy<'a>,
    /// The loads and prescribed displacements in time (`[[step]]` tables with `time`;
    /// `None`: `system`'s, constant or scaled by the load ramp).
    pub history: Option<LoadHistory>,
}

/// The strain energy of a state (docs/method.md §10.4).
pub enum StrainEnergy<'a> {
    /// MFVM: `½ Σ_I |Ω_I| ε̂_Iᵀ D ε̂_I` from the collocated strains over the cells.
    Collocated {
        /// The subdomain cells.
        cells: &'a [Cell],
        /// Constitutive matrix `D`.
        constitutive: Constitutive,
    },
    /// Finite elements: `½ uᵀ K u` with the symmetric unconstrained stiffness.
    Quadratic(&'a BlockRows),
}

impl StrainEnergy<'_> {
    fn of(&self, node_shapes: &ShapeSet, q: &[f64]) -> f64 {
        match self {
            Self::Collocated { cells, constitutive } => {
                energy::strain(node_shapes, cells, constitutive, q)
            }
            Self::Quadratic(k) => 0.5 * k.mul(q).iter().zip(q).map(|(a, b)| a * b).sum::<f64>(),
        }
    }
}

/// The contact candidates against rigid obstacles: their operators and initial gaps.
pub struct Contact<'a> {
    /// `G` and `E`.
    pub operator: &'a BodyOperator,
    /// `g0`.
    pub initial_gap: &'a [f64],
    /// Coulomb friction at the velocity level (`None`: frictionless): the one body's
    /// tangential term.
    pub friction: Option<Friction<'a>>,
    /// The obstacles' motion in time (`None`: at rest).
    pub obstacle: Option<ObstacleMotion>,
}

/// A finished run.
pub struct Simulation {
    /// Records at time 0 and after every step.
    pub history: History,
    /// Snapshots at time 0, every `snapshot_every` steps and at the end (empty without).
    pub frames: Vec<Frame>,
    /// Nodal parameters `û` at the end.
    pub displacement: Vec<f64>,
    /// Their rates `v̂` at the end.
    pub velocity: Vec<f64>,
    /// The mass per DOF: the lumped mass, or the consistent mass's row sums (the same total
    /// and momentum).
    pub mass: Vec<f64>,
    /// Each candidate's gap at the end.
    pub final_gap: Vec<f64>,
    /// Each candidate's impulse `Π_c` over the last step (`Π_c / h` is its force; empty
    /// without contact).
    pub final_impulses: Vec<f64>,
    /// Wall time of the set-up (`M̂`'s factorisation and `W`) and of the steps' LCPs.
    pub seconds: Seconds,
}

/// Wall times inside [`simulate`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Seconds {
    /// Factorising `M̂` and condensing `W`.
    pub setup: f64,
    /// Forming and solving the steps' LCPs (index sets included); with the active-set
    /// solver the whole step on a non-empty index set (its `M̂` solves included).
    pub lcp: f64,
    /// The steps' free velocities (each the product with `K` and one `M̂` solve).
    pub free: f64,
    /// The steps' records (energies, momenta).
    pub records: f64,
}

impl Simulation {
    /// The run's figures.
    pub fn figures(&self, h: f64) -> Figures {
        self.history.figures(h, mass::total(&self.mass))
    }
}

/// A snapshot of the bodies: each body's displacement and velocity at its nodes.
pub struct Frame {
    /// Time.
    pub time: f64,
    /// The step.
    pub step: usize,
    /// Each body's fields, in body order (one for one body).
    pub bodies: Vec<BodyFrame>,
}

/// One body's fields in a [`Frame`].
pub struct BodyFrame {
    /// `u^h(x_I)` (`Φ q`).
    pub displacement: Vec<[f64; 2]>,
    /// `v^h(x_I)` (`Φ v`).
    pub velocity: Vec<[f64; 2]>,
}

impl Frame {
    fn of(bodies: &[&Body<'_>], states: &[State], step: usize, time: f64) -> Self {
        let of = |body: &Body<'_>, state: &State| {
            let shapes = body.node_shapes;
            BodyFrame {
                displacement: (0..shapes.len()).map(|i| shapes.interpolate(i, &state.q)).collect(),
                velocity: (0..shapes.len()).map(|i| shapes.interpolate(i, &state.v)).collect(),
            }
        };
        Self { time, step, bodies: bodies.iter().zip(states).map(|(b, s)| of(b, s)).collect() }
    }
}

/// The state of the body: `q = û` and `v = v̂`.
struct State {
    q: Vec<f64>,
    v: Vec<f64>,
}

/// Runs the Moreau–Jean time stepping of `body` from `params.initial_velocity` (undeformed)
/// to `params.end_time`, reporting `(step, steps)` to `progress`.
///
/// # Errors
/// [`DynamicsError`] when the factorisation, a solve or a step's LCP fails.
pub fn simulate(
    body: &Body<'_>,
    contact: Option<Contact<'_>>,
    params: &Dynamics,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Simulation, DynamicsError> {
    let contacts = contact.map(|c| stepping::Contacts {
        normal: vec![Term { body: 0, offset: 0, operator: c.operator }],
        initial_gap: c.initial_gap.to_vec(),
        friction: c.friction,
        pair_starts: vec![0],
        obstacle: c.obstacle,
    });
    let mut run = stepping::run(&[body], contacts, params, &[params.initial_velocity], progress)?;
    let state = run.states.pop().unwrap_or_else(|| unreachable!("one body"));
    Ok(Simulation {
        history: run.history,
        frames: run.frames,
        displacement: state.q,
        velocity: state.v,
        mass: body.mass.row_sums(),
        final_gap: run.final_gap,
        final_impulses: run.final_impulses,
        seconds: run.seconds,
    })
}

/// The mass the records of `body` count: its mass, without the prescribed DOFs when
/// their values vary in time (a prescribed row is massless in `M̂`; its nodal velocity is the
/// θ-method's `v_{n+1}`, which only the average `(1 − θ) v_n + θ v_{n+1}` constrains, so at
/// θ = ½ it alternates about the prescribed rate: its kinetic energy and momentum are the
/// support's, docs/method.md §10.5).
fn recorded_mass<'a>(body: &'a Body<'_>) -> std::borrow::Cow<'a, mass::Mass> {
    match body.history {
        None => std::borrow::Cow::Borrowed(&body.mass),
        Some(_) => std::borrow::Cow::Owned(body.mass.without(|d| body.system.is_constrained(d))),
    }
}

/// The applied load `f` on the free rows (a constrained row's load goes to the support).
fn free_load(system: &GlobalSystem) -> Vec<f64> {
    (0..system.load.len())
        .map(|d| if system.is_constrained(d) { 0.0 } else { system.load[d] })
        .collect()
}

/// The record of `state` at `time`, without contact or work (the caller adds them); the
/// kinetic energy and momentum with `mass` (the body's, or with a history in time the body's
/// without its prescribed DOFs: [`recorded_mass`]).
fn record(body: &Body<'_>, mass: &mass::Mass, state: &State, time: f64) -> Record {
    let v = mass::nodal_values(body.node_shapes, &state.v);
    Record {
        time,
        contact_force: 0.0,
        kinetic_energy: mass.kinetic(&v),
        strain_energy: body.strain.of(body.node_shapes, &state.q),
        external_work: 0.0,
        contact_loss: 0.0,
        momentum: mass.momentum(&v),
        pair_forces: Vec::new(),
        active: 0,
        pivots: 0,
        residual: 0.0,
    }
}
