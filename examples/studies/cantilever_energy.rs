//! The time stepping's energy without contact (docs/dev/dynamics.md, "Energy"): the
//! cantilever of `problems/cantilever.toml` (density 1) with its end load applied in full at
//! time 0, so that it vibrates about the static deflection; the conserved energy is
//! `E = E_kin + E_strain − W` (`W` the constant load's work). Prints, for θ = 0.5 and 0.51,
//! `(E(t) − E(0)) / max_t E_strain` at 1, 10, 50 and 100 periods of the first bending mode
//! (the analytic Euler–Bernoulli period 0.217 is used for the step, `T / 40`, and the end;
//! the measured period from the kinetic energy's peaks is printed too).
//!
//! `cargo run --release --features studies --example cantilever_energy [spacing]`

use mlpg_contact::pipeline::dynamics::solve;
use mlpg_contact::problem::{Problem, ProblemFile, file::DynamicsFile};
use mlpg_contact::progress::Silent;
use std::time::Instant;

fn main() {
    let spacing: f64 = std::env::args().nth(1).map_or(2.0, |a| a.parse().expect("a number"));
    // ω₁ = 1.875² √(EI / (ρ A L⁴)) with E = 3e7, I = 12³/12, A = 12, L = 48, ρ = 1.
    let omega = 1.875_f64.powi(2) * (3e7 * 144.0 / 12.0_f64).sqrt() / 48.0_f64.powi(2);
    let period = std::f64::consts::TAU / omega;
    let h = period / 40.0;
    println!("spacing {spacing}, Euler–Bernoulli period {period:.4}, h {h:.4e}");
    println!("theta,steps,period_measured,drift_1,drift_10,drift_50,drift_100,seconds");
    for theta in [0.5, 0.51] {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/cantilever.toml");
        let text = std::fs::read_to_string(path).expect("read problems/cantilever.toml");
        let mut file = ProblemFile::from_toml(&text).expect("parse");
        file.nodes.as_mut().expect("nodes").spacing = Some(spacing);
        file.material.as_mut().expect("material").density = Some(1.0);
        file.dynamics = Some(DynamicsFile {
            end_time: 100.0 * period,
            time_step: h,
            theta: Some(theta),
            ..DynamicsFile::default()
        });
        let clock = Instant::now();
        let outcome = solve(&Problem::try_from(file).expect("valid"), &mut Silent).expect("run");
        let seconds = clock.elapsed().as_secs_f64();
        let records = &outcome.simulation.history.records;
        let conserved = |k: usize| records[k].energy() - records[k].external_work;
        let scale = records.iter().map(|r| r.strain_energy).fold(0.0, f64::max);
        let at = |periods: f64| {
            let k = ((periods * period / h).round() as usize).min(records.len() - 1);
            (conserved(k) - conserved(0)) / scale
        };
        // The kinetic energy peaks twice a period: the mean spacing of its local maxima.
        let peaks: Vec<f64> = (1..records.len() - 1)
            .filter(|&k| {
                records[k].kinetic_energy > records[k - 1].kinetic_energy
                    && records[k].kinetic_energy >= records[k + 1].kinetic_energy
                    && records[k].kinetic_energy > 0.1 * scale
            })
            .map(|k| records[k].time)
            .collect();
        let measured = match (peaks.first(), peaks.last()) {
            (Some(a), Some(b)) if peaks.len() > 1 => 2.0 * (b - a) / (peaks.len() - 1) as f64,
            _ => f64::NAN,
        };
        println!(
            "{theta},{},{measured:.4},{:+.3e},{:+.3e},{:+.3e},{:+.3e},{seconds:.1}",
            records.len() - 1,
            at(1.0),
            at(10.0),
            at(50.0),
            at(100.0)
        );
    }
}
