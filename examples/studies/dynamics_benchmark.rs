//! The elastodynamic benchmark (docs/dev/dynamics.md, increment 13): the bar impact of
//! `problems/bar_impact.toml` at spacing L/320 (10 593 nodes) and h = 1/640 for 10 000 steps
//! (end time 15.625: the impact, the rebound and free flight), θ = 0.51 (θ = ½ grows over so
//! many wave transits). Prints the stage timings of the run (the set-up of `M̂` and `W`, the
//! steps' LCPs, the whole stage), the time per step and the LCPs' share, and the load average
//! (the machine may be shared).
//!
//! `cargo run --release --features studies --example dynamics_benchmark [spacing_divisor steps
//! height solver]`: `height` replaces the bar's `H = 0.1` (a taller bar has more candidates on
//! its left edge, `H × divisor + 1`), `solver` is the contact's `solver` (`lemke`,
//! `active_set`; default the file's, Lemke: docs/dev/dynamics.md increment 11).

use mlpg_contact::pipeline::dynamics::solve;
use mlpg_contact::problem::{Problem, ProblemFile};
use mlpg_contact::progress::Silent;
use std::time::Instant;

fn main() {
    let words: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<f64> = words.iter().take(3).map(|a| a.parse().expect("a number")).collect();
    let divisor = args.first().copied().unwrap_or(320.0);
    let steps = args.get(1).copied().unwrap_or(10_000.0);
    let h = 1.0 / (2.0 * divisor);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/bar_impact.toml");
    let mut text = std::fs::read_to_string(path).expect("read problems/bar_impact.toml");
    if let Some(height) = args.get(2) {
        text = text.replace("y = [0.0, 0.1]", &format!("y = [0.0, {height}]"));
    }
    if let Some(solver) = words.get(3) {
        text = text.replace("[contact]\n", &format!("[contact]\nsolver = \"{solver}\"\n"));
    }
    let mut file = ProblemFile::from_toml(&text).expect("parse");
    file.nodes.as_mut().expect("nodes").spacing = Some(1.0 / divisor);
    let d = file.dynamics.as_mut().expect("dynamics");
    d.time_step = h;
    d.theta = Some(0.51);
    d.end_time = steps * h;
    let problem = Problem::try_from(file).expect("valid");
    let load = |when: &str| {
        let l = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
        println!(
            "load average {when}: {}",
            l.split_whitespace().take(3).collect::<Vec<_>>().join(" ")
        );
    };
    load("before");
    let clock = Instant::now();
    let outcome = solve(&problem, &mut Silent).expect("run");
    let total = clock.elapsed().as_secs_f64();
    load("after");
    let f = outcome.simulation.figures(h);
    let contact_steps = outcome.simulation.history.records.iter().filter(|r| r.active > 0).count();
    println!(
        "nodes {}, candidates {}, steps {} ({contact_steps} with contact), h {h}, solver {:?}",
        outcome.nodes(),
        outcome.candidates(),
        f.steps,
        outcome.dynamics.solver
    );
    for t in &outcome.timings {
        println!("  {:<32} {:>9.3} s", t.stage, t.seconds);
    }
    let s = outcome.simulation.seconds;
    let stepping: f64 =
        outcome.timings.iter().filter(|t| t.stage == "time steps").map(|t| t.seconds).sum();
    let per_step = (stepping - s.setup) / f.steps as f64;
    println!("whole run {total:.2} s; time stepping {stepping:.2} s");
    println!(
        "per step {:.3} ms (set-up excluded); LCPs {:.3} s = {:.1} % of the stepping",
        1e3 * per_step,
        s.lcp,
        100.0 * s.lcp / stepping
    );
    let ms = |seconds: f64| 1e3 * seconds / f.steps as f64;
    println!(
        "per step: free velocities (K product, M̂ solve) {:.3} ms, records (energies) {:.3} ms, \
         LCPs {:.3} ms, the rest {:.3} ms",
        ms(s.free),
        ms(s.records),
        ms(s.lcp),
        1e3 * per_step - ms(s.free + s.records + s.lcp)
    );
    println!(
        "contact duration {:?}, mean force {:?}, final velocity {:?}",
        f.contact.contact_duration, f.contact.mean_contact_force, f.final_velocity
    );
}
