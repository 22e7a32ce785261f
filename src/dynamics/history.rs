//! The time history of a dynamic run, one [`Record`] per step, and the run's figures read
//! from it ([`Figures`]).

use serde::Serialize;

/// The state after one time step (or at time 0).
#[derive(Clone, Debug, Serialize)]
pub struct Record {
    /// Time at the end of the step.
    pub time: f64,
    /// Mean total contact force over the step, `Σ_c Π_c / h`.
    pub contact_force: f64,
    /// Kinetic energy.
    pub kinetic_energy: f64,
    /// Strain energy.
    pub strain_energy: f64,
    /// Work of the applied loads since time 0.
    pub external_work: f64,
    /// Energy taken by the contact impulses since time 0 (minus their work).
    pub contact_loss: f64,
    /// Momentum `Σ_I m_I v^h(x_I)` (x, y).
    pub momentum: [f64; 2],
    /// Candidates in the step's index set.
    pub active: usize,
    /// Lemke's pivots in the step.
    pub pivots: usize,
}

impl Record {
    /// Kinetic plus strain energy.
    pub fn energy(&self) -> f64 {
        self.kinetic_energy + self.strain_energy
    }
}

/// The run's figures for `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Figures {
    /// Steps taken.
    pub steps: usize,
    /// Time of the last step.
    pub end_time: f64,
    /// Total mass (per unit thickness).
    pub mass: f64,
    /// Start of the first step with a contact impulse (`None`: no contact).
    pub contact_start: Option<f64>,
    /// End of the last step with a contact impulse.
    pub contact_end: Option<f64>,
    /// `contact_end − contact_start`.
    pub contact_duration: Option<f64>,
    /// Total contact impulse over the run.
    pub total_impulse: f64,
    /// `total_impulse / contact_duration`.
    pub mean_contact_force: Option<f64>,
    /// Largest mean force of one step.
    pub peak_contact_force: f64,
    /// Velocity of the centre of mass at the end (`momentum / mass`).
    pub final_velocity: [f64; 2],
    /// Kinetic plus strain energy at time 0.
    pub initial_energy: f64,
    /// Kinetic plus strain energy at the end.
    pub final_energy: f64,
    /// Energy taken by the contact impulses over the run.
    pub contact_loss: f64,
    /// Work of the applied loads over the run.
    pub external_work: f64,
    /// Largest `|E(t) − E(0) − W_ext(t) + loss(t)| / max(E(0), max_t E(t))` over the run: what the
    /// time stepping and the energy measure add or lose besides the contacts.
    pub energy_balance_error: f64,
    /// The positive part of the same: the largest energy the run gained beyond what the loads
    /// brought, relative (a growing mode; numerical damping does not count).
    pub energy_growth: f64,
    /// Steps with a non-empty index set.
    pub contact_steps: usize,
    /// Lemke's pivots over the run.
    pub pivots: usize,
}

/// The records of a run: time 0 first, then one per step.
#[derive(Clone, Debug, Default)]
pub struct History {
    /// The records.
    pub records: Vec<Record>,
}

impl History {
    /// The run's figures; `h` is the step, `mass` the total mass.
    pub fn figures(&self, h: f64, mass: f64) -> Figures {
        let r = &self.records;
        let (first, last) = (&r[0], &r[r.len() - 1]);
        let touching: Vec<&Record> = r[1..].iter().filter(|x| x.contact_force > 0.0).collect();
        let contact_start = touching.first().map(|x| x.time - h);
        let contact_end = touching.last().map(|x| x.time);
        let contact_duration = contact_start.zip(contact_end).map(|(a, b)| b - a);
        let total_impulse: f64 = r[1..].iter().map(|x| x.contact_force * h).sum();
        let top = r.iter().map(Record::energy).fold(first.energy(), f64::max);
        let scale = if top > 0.0 { top } else { 1.0 };
        let excess: Vec<f64> = r
            .iter()
            .map(|x| (x.energy() - first.energy() - x.external_work + x.contact_loss) / scale)
            .collect();
        let energy_balance_error = excess.iter().map(|e| e.abs()).fold(0.0, f64::max);
        let energy_growth = excess.iter().copied().fold(0.0, f64::max);
        Figures {
            steps: r.len() - 1,
            end_time: last.time,
            mass,
            contact_start,
            contact_end,
            contact_duration,
            total_impulse,
            mean_contact_force: contact_duration.map(|d| total_impulse / d),
            peak_contact_force: r.iter().map(|x| x.contact_force).fold(0.0, f64::max),
            final_velocity: [last.momentum[0] / mass, last.momentum[1] / mass],
            initial_energy: first.energy(),
            final_energy: last.energy(),
            contact_loss: last.contact_loss,
            external_work: last.external_work,
            energy_balance_error,
            energy_growth,
            contact_steps: r.iter().filter(|x| x.active > 0).count(),
            pivots: r.iter().map(|x| x.pivots).sum(),
        }
    }
}
