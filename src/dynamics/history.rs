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
    /// With several contact pairs, each pair's mean force over the step (`[[contact]]`
    /// order; they sum to `contact_force`); empty with one pair (`contact_force` is its
    /// force) or none.
    pub pair_forces: Vec<f64>,
    /// Candidates in the step's index set.
    pub active: usize,
    /// Lemke's pivots in the step.
    pub pivots: usize,
    /// The step LCP's largest scaled residual (0 without contact in the step).
    pub residual: f64,
}

impl Record {
    /// Kinetic plus strain energy.
    pub fn energy(&self) -> f64 {
        self.kinetic_energy + self.strain_energy
    }

    /// A record of one contact step with unit kinetic energy and momentum, for tests.
    #[cfg(test)]
    pub(crate) fn sample(time: f64, residual: f64) -> Self {
        Record {
            time,
            contact_force: 1.0,
            kinetic_energy: 1.0,
            strain_energy: 0.0,
            external_work: 0.0,
            contact_loss: 0.0,
            momentum: [1.0, 0.0],
            pair_forces: Vec::new(),
            active: 1,
            pivots: 1,
            residual,
        }
    }

    /// How many of the record's numbers are not finite.
    fn non_finite(&self) -> usize {
        [
            self.time,
            self.contact_force,
            self.kinetic_energy,
            self.strain_energy,
            self.external_work,
            self.contact_loss,
            self.momentum[0],
            self.momentum[1],
            self.residual,
        ]
        .iter()
        .chain(&self.pair_forces)
        .filter(|v| !v.is_finite())
        .count()
    }
}

/// The larger of `a` and `b`, NaN if either is (so that a NaN residual fails its check).
fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) }
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
    /// The contact figures of the total contact force (every pair's together), written in
    /// line with the others in `summary.json`.
    #[serde(flatten)]
    pub contact: PairFigures,
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
    /// The largest scaled residual of a step's LCP over the run (complementarity and signs of
    /// the impulses and velocities; checked against
    /// [`crate::solution::COMPLEMENTARITY_TOLERANCE`]).
    pub max_step_residual: f64,
    /// Entries of the history that are not finite numbers (time, forces, energies, momentum):
    /// 0 in a sound run.
    pub non_finite_values: usize,
}

/// The records of a run: time 0 first, then one per step.
#[derive(Clone, Debug, Default)]
pub struct History {
    /// The records.
    pub records: Vec<Record>,
}

/// The contact figures of one contact force over a run: a pair's in a run with several
/// ([`History::pair_figures`]), or the total ([`Figures::contact`]).
#[derive(Clone, Debug, Serialize)]
pub struct PairFigures {
    /// Start of the first step with an impulse (`None`: it never touched).
    pub contact_start: Option<f64>,
    /// End of the last step with an impulse.
    pub contact_end: Option<f64>,
    /// `contact_end − contact_start`.
    pub contact_duration: Option<f64>,
    /// The total impulse over the run.
    pub total_impulse: f64,
    /// `total_impulse / contact_duration`.
    pub mean_contact_force: Option<f64>,
    /// The largest mean force of one step.
    pub peak_contact_force: f64,
}

impl PairFigures {
    /// "contact from … to … (duration …), mean force …, peak …" for the console ("–" where
    /// there was no contact).
    pub fn describe(&self) -> String {
        let opt = |v: Option<f64>| v.map_or_else(|| "–".to_string(), |v| format!("{v:.6}"));
        format!(
            "contact from {} to {} (duration {}), mean force {}, peak {:.6}",
            opt(self.contact_start),
            opt(self.contact_end),
            opt(self.contact_duration),
            opt(self.mean_contact_force),
            self.peak_contact_force
        )
    }

    /// The figures of the force `force(record)` over `records` (time 0 first), step `h`.
    fn of(records: &[Record], h: f64, force: impl Fn(&Record) -> f64) -> Self {
        let touching: Vec<&Record> = records[1..].iter().filter(|x| force(x) > 0.0).collect();
        let contact_start = touching.first().map(|x| x.time - h);
        let contact_end = touching.last().map(|x| x.time);
        let contact_duration = contact_start.zip(contact_end).map(|(a, b)| b - a);
        let total_impulse: f64 = records[1..].iter().map(|x| force(x) * h).sum();
        Self {
            contact_start,
            contact_end,
            contact_duration,
            total_impulse,
            mean_contact_force: contact_duration.map(|d| total_impulse / d),
            peak_contact_force: records.iter().map(&force).fold(0.0, f64::max),
        }
    }
}

impl History {
    /// Each contact pair's figures, from the records' pair forces (empty with one pair).
    pub fn pair_figures(&self, h: f64) -> Vec<PairFigures> {
        let pairs = self.records.first().map_or(0, |r| r.pair_forces.len());
        (0..pairs)
            .map(|k| {
                PairFigures::of(&self.records, h, |r| r.pair_forces.get(k).copied().unwrap_or(0.0))
            })
            .collect()
    }

    /// The run's figures; `h` is the step, `mass` the total mass.
    pub fn figures(&self, h: f64, mass: f64) -> Figures {
        let r = &self.records;
        let (first, last) = (&r[0], &r[r.len() - 1]);
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
            contact: PairFigures::of(r, h, |x| x.contact_force),
            final_velocity: [last.momentum[0] / mass, last.momentum[1] / mass],
            initial_energy: first.energy(),
            final_energy: last.energy(),
            contact_loss: last.contact_loss,
            external_work: last.external_work,
            energy_balance_error,
            energy_growth,
            contact_steps: r.iter().filter(|x| x.active > 0).count(),
            pivots: r.iter().map(|x| x.pivots).sum(),
            max_step_residual: r.iter().map(|x| x.residual).fold(0.0, nan_max),
            non_finite_values: r.iter().map(Record::non_finite).sum(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(time: f64, residual: f64) -> Record {
        Record::sample(time, residual)
    }

    /// Each pair's figures read its own force; they add up to the run's.
    #[test]
    fn pair_figures_follow_each_pair_force() {
        let with = |time: f64, forces: [f64; 2]| Record {
            contact_force: forces[0] + forces[1],
            pair_forces: forces.to_vec(),
            ..record(time, 0.0)
        };
        let h = History {
            records: vec![
                with(0.0, [0.0, 0.0]),
                with(0.1, [2.0, 0.0]),
                with(0.2, [1.0, 3.0]),
                with(0.3, [0.0, 1.0]),
            ],
        };
        let pairs = h.pair_figures(0.1);
        assert_eq!(pairs.len(), 2);
        assert_eq!((pairs[0].contact_start, pairs[0].contact_end), (Some(0.0), Some(0.2)));
        assert_eq!((pairs[1].contact_start, pairs[1].contact_end), (Some(0.1), Some(0.3)));
        assert_eq!((pairs[0].peak_contact_force, pairs[1].peak_contact_force), (2.0, 3.0));
        let total = h.figures(0.1, 1.0).contact.total_impulse;
        assert!((pairs[0].total_impulse + pairs[1].total_impulse - total).abs() < 1e-15);
        assert!(History { records: vec![record(0.0, 0.0)] }.pair_figures(0.1).is_empty());
    }

    #[test]
    fn the_figures_carry_the_worst_step_residual_and_the_non_finite_entries() {
        let h = History { records: vec![record(0.0, 0.0), record(0.1, 2e-12), record(0.2, 0.0)] };
        let f = h.figures(0.1, 1.0);
        assert_eq!(f.max_step_residual, 2e-12);
        assert_eq!(f.non_finite_values, 0);
        let mut bad = h.clone();
        bad.records[1].residual = f64::NAN;
        bad.records[2].kinetic_energy = f64::INFINITY;
        let f = bad.figures(0.1, 1.0);
        assert!(f.max_step_residual.is_nan(), "a NaN residual must not be folded away");
        assert_eq!(f.non_finite_values, 2);
    }
}
