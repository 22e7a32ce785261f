//! The quasi-static limit at long ramps (docs/dev/dynamics.md, "The quasi-static limit"): the
//! beam of `problems/beam_on_foundation.toml` at spacing 1, density 1, θ = 0.6, h = 0.7, its
//! load ramped over `T_r` (end time `T_r`), against the static solve of the same file. For the
//! obstacle's gap given (0.01 shipped, 1e-9 "in contact") and each `T_r` prints the total and
//! the largest candidate force errors (relative to the total force), the displacement error
//! (`max_I |Δu(x_I)| / max_I |u_static(x_I)|`), the least final gap, and the seconds.
//!
//! `cargo run --release --features studies --example quasi_static_limit -- GAP T_r...`

use mlpg_contact::pipeline::dynamics::{DynamicBody, solve};
use mlpg_contact::problem::{Problem, ProblemFile, file::DynamicsFile};
use mlpg_contact::progress::Silent;
use std::time::Instant;

fn beam(gap: f64) -> ProblemFile {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/beam_on_foundation.toml");
    let text = std::fs::read_to_string(path).expect("the shipped beam");
    let moved = format!("obstacle_point = [0.0, {}]", -3.0 - gap);
    let text = text.replace("obstacle_point = [0.0, -3.01]", &moved);
    assert!(text.contains(&moved), "the obstacle moved");
    let mut file = ProblemFile::from_toml(&text).expect("parse");
    file.nodes.as_mut().expect("nodes").spacing = Some(1.0);
    file
}

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().expect("a number")).collect();
    let gap = args.first().copied().unwrap_or(0.01);
    let ramps = if args.len() > 1 { args[1..].to_vec() } else { vec![280.0, 560.0, 1120.0] };
    let h = 0.7;
    let reference = mlpg_contact::solve(&Problem::try_from(beam(gap)).expect("valid"))
        .expect("the static solve");
    let contact = reference.contact().expect("contact");
    let total = contact.total_force;
    println!("gap,T_r,steps,force,candidate_force,displacement,least_gap,seconds");
    for ramp in ramps {
        let mut file = beam(gap);
        file.material.as_mut().expect("material").density = Some(1.0);
        file.dynamics = Some(DynamicsFile {
            end_time: ramp,
            time_step: h,
            theta: Some(0.6),
            load_ramp: Some(ramp),
            ..DynamicsFile::default()
        });
        let clock = Instant::now();
        let outcome = solve(&Problem::try_from(file).expect("valid"), &mut Silent).expect("run");
        let seconds = clock.elapsed().as_secs_f64();
        let sim = &outcome.simulation;
        let DynamicBody::Mfvm(parts) = &outcome.body else { panic!("an MFVM body") };
        let forces: Vec<f64> = sim.final_impulses.iter().map(|p| p / h).collect();
        let candidate = forces
            .iter()
            .zip(&contact.lcp.z)
            .map(|(f, p)| (f - p).abs() / total)
            .fold(0.0, f64::max);
        let mut worst: f64 = 0.0;
        for (i, s) in reference.displacement.iter().enumerate() {
            let u = parts.node_shapes.interpolate(i, &sim.displacement);
            worst = worst.max((u[0] - s[0]).hypot(u[1] - s[1]));
        }
        let largest = reference.displacement.iter().map(|s| s[0].hypot(s[1])).fold(0.0, f64::max);
        let least_gap = sim.final_gap.iter().copied().fold(f64::INFINITY, f64::min);
        println!(
            "{gap},{ramp},{},{:.3e},{:.3e},{:.3e},{least_gap:.3e},{seconds:.1}",
            sim.history.records.len() - 1,
            (forces.iter().sum::<f64>() - total).abs() / total,
            candidate,
            worst / largest,
        );
    }
}
