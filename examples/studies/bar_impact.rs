//! The bar impact of `problems/bar_impact.toml` (docs/method.md §10) refined: errors of the
//! contact duration, the mean force and the rebound velocity against the exact 1-D wave
//! solution, the energy lost at the impact, the force oscillation, and the long-time energy
//! of the free flight after the impact for several θ. Prints CSV blocks.
//!
//! `cargo run --release --features studies --example bar_impact`

use mlpg_contact::pipeline::dynamics::solve;
use mlpg_contact::problem::{Problem, ProblemFile};
use mlpg_contact::progress::Silent;
use std::time::Instant;

const L: f64 = 1.0;
const V0: f64 = 0.1;
const T_CONTACT: f64 = 2.0; // 2 L / c with E = ρ = 1
const FORCE: f64 = 0.01; // ρ c v0 H

fn bar(spacing: f64, step: f64, theta: f64, end_time: f64) -> Problem {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/bar_impact.toml");
    let text = std::fs::read_to_string(path).expect("read problems/bar_impact.toml");
    let mut file = ProblemFile::from_toml(&text).expect("parse");
    file.nodes.as_mut().expect("nodes").spacing = Some(spacing);
    let d = file.dynamics.as_mut().expect("dynamics");
    d.time_step = step;
    d.theta = Some(theta);
    d.end_time = end_time;
    Problem::try_from(file).expect("valid")
}

/// One run: prints `spacing, h, θ, nodes, steps, errors…, energy lost / E0, force spread,
/// seconds`.
fn row(spacing: f64, step: f64, theta: f64) {
    let t0 = Instant::now();
    let outcome = solve(&bar(spacing, step, theta, 2.6), &mut Silent).expect("run");
    let seconds = t0.elapsed().as_secs_f64();
    let f = outcome.simulation.figures(step);
    let duration = f.contact.contact_duration.unwrap_or(0.0);
    let force = f.contact.mean_contact_force.unwrap_or(0.0);
    // The force's spread over the middle of the contact (t in [0.5, 1.7]).
    let middle: Vec<f64> = outcome
        .simulation
        .history
        .records
        .iter()
        .filter(|r| (0.5..=1.7).contains(&r.time))
        .map(|r| r.contact_force)
        .collect();
    let mean = middle.iter().sum::<f64>() / middle.len() as f64;
    let spread =
        (middle.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / middle.len() as f64).sqrt();
    println!(
        "{spacing},{step},{theta},{},{},{:+.4e},{:+.4e},{:+.4e},{:.4e},{:.4e},{seconds:.2}",
        outcome.nodes(),
        f.steps,
        (duration - T_CONTACT) / T_CONTACT,
        (force - FORCE) / FORCE,
        (f.final_velocity[0] - V0) / V0,
        f.contact_loss / f.initial_energy,
        spread / FORCE,
    );
}

fn main() {
    let header = "spacing,h,theta,nodes,steps,duration_error,mean_force_error,rebound_error,energy_lost_over_E0,force_rms_spread_over_exact,seconds";
    println!("# spacing and step refined together (h = spacing / 2c)\n{header}");
    for k in [40.0, 80.0, 160.0, 320.0] {
        row(L / k, L / k / 2.0, 0.5);
    }
    println!("\n# step refined at spacing L/80\n{header}");
    for m in [1.0, 2.0, 4.0, 8.0] {
        row(L / 80.0, L / 80.0 / m, 0.5);
    }
    println!("\n# spacing refined at step 1/320\n{header}");
    for k in [40.0, 80.0, 160.0] {
        row(L / k, 1.0 / 320.0, 0.5);
    }
    println!("\n# theta at spacing L/80, h = spacing / 2\n{header}");
    for theta in [0.5, 0.51, 0.55, 0.6] {
        row(L / 80.0, L / 160.0, theta);
    }
    println!("\n# free flight after the impact: (E(t) - E(2.2)) / E(2.2), spacing L/40, h = L/80");
    println!("theta,t=5,t=10,t=20,t=40,t=60");
    for theta in [0.5, 0.51, 0.52, 0.55] {
        let outcome = solve(&bar(L / 40.0, L / 80.0, theta, 60.0), &mut Silent).expect("run");
        let records = &outcome.simulation.history.records;
        let at = |t: f64| {
            records
                .iter()
                .min_by(|a, b| (a.time - t).abs().total_cmp(&(b.time - t).abs()))
                .expect("records")
                .energy()
        };
        let e0 = at(2.2);
        let rel: Vec<String> = [5.0, 10.0, 20.0, 40.0, 60.0]
            .iter()
            .map(|&t| format!("{:+.3e}", (at(t) - e0) / e0))
            .collect();
        println!("{theta},{}", rel.join(","));
    }
}
