//! Benchmark: the adaptive beam on the rigid foundation (`problems/beam_on_foundation_adaptive.toml`)
//! to `|l_c − l_c,ref| ≤ 0.01`, end to end (reading the problem file, every refinement step,
//! the node set that `max_nodes` refuses), against the uniform spacing of the same accuracy,
//! in one run (docs/dev/adaptive.md, "The adaptive beam benchmark").
//!
//! Reference: the independent Q2 FE solution `l_c = 19.810 ± 0.005`, `ΣP = 32.3476 ± 0.0001`
//! (`tests/validation/beam_on_foundation.rs`). The uniform runs use the file's discretisation
//! (β = 0.5) without `[refinement]`, halving the spacing from the file's `h₀` until `l_c` is
//! within 0.01 (at most to `h₀/8`). The adaptive run is repeated `--repeat N` times (default
//! 3; the shared machine's load varies): its fastest and slowest wall-clock times are
//! printed with the least CPU time (user + system, all threads), and the step table of the
//! last repetition (cumulative seconds).
//!
//! `cargo run --release --features studies --example adaptive_beam_benchmark [-- --repeat 5]`

use mlpg_contact::pipeline::adaptive;
use mlpg_contact::problem::Problem;
use mlpg_contact::{Silent, Solution};
use std::time::Instant;

/// The independent Q2 FE reference of the beam: `ΣP`, `l_c`.
const BEAM_FORCE: f64 = 32.3476;
const BEAM_ONSET: f64 = 19.810;
/// The accuracy asked for: `|l_c − l_c,ref|`.
const ONSET_TOLERANCE: f64 = 0.01;

/// CPU seconds of this process so far (user + system, all threads; Linux `/proc/self/stat`,
/// NaN elsewhere): on the shared machine the wall-clock time depends on the other jobs' load,
/// the CPU time much less.
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else { return f64::NAN };
    // Fields after the parenthesised command name: state is field 3, utime 14, stime 15.
    let Some(rest) = stat.rsplit_once(')').map(|(_, r)| r) else { return f64::NAN };
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |k: usize| f.get(k - 3).and_then(|v| v.parse::<f64>().ok()).unwrap_or(f64::NAN);
    // The kernel's USER_HZ is 100 on every Linux architecture in use.
    (ticks(14) + ticks(15)) / 100.0
}

fn read() -> Problem {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems/beam_on_foundation_adaptive.toml");
    Problem::from_toml(&std::fs::read_to_string(path).expect("problem file")).expect("valid")
}

fn onset(s: &Solution) -> f64 {
    s.contact().and_then(|c| c.onset.from_gap).unwrap_or(f64::NAN)
}

/// What a table row shows of one solution.
struct Row {
    nodes: usize,
    force: f64,
    onset: f64,
    bracket: [f64; 2],
    complementarity: f64,
    equilibrium: f64,
}

impl Row {
    fn of(s: &Solution, nodes: usize) -> Self {
        let c = s.contact().expect("contact");
        Row {
            nodes,
            force: c.total_force,
            onset: onset(s),
            bracket: [
                c.onset.last_open.unwrap_or(f64::NAN),
                c.onset.first_closed.unwrap_or(f64::NAN),
            ],
            complementarity: c.lcp.residuals.max_complementarity,
            equilibrium: s.equilibrium_error,
        }
    }

    fn print(&self, name: &str, seconds: f64) {
        println!(
            "| {name} | {} | {:+.1e} | {:+.4} | [{}, {}] | {:.1e} | {:.1e} | {seconds:.2} |",
            self.nodes,
            self.force / BEAM_FORCE - 1.0,
            self.onset - BEAM_ONSET,
            self.bracket[0],
            self.bracket[1],
            self.complementarity,
            self.equilibrium
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let repeat = args
        .iter()
        .position(|a| a == "--repeat")
        .and_then(|k| args.get(k + 1))
        .map_or(3, |v| v.parse::<usize>().expect("--repeat N"));
    println!("## Adaptive beam: l_c within {ONSET_TOLERANCE} of {BEAM_ONSET}\n");
    println!("| run | nodes | ΣP/ref − 1 | l_c − ref | bracket | KKT | equilibrium | seconds |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut times = Vec::new();
    let mut cpu = Vec::new();
    let mut last = None;
    for r in 0..repeat.max(1) {
        let (t, c) = (Instant::now(), cpu_seconds());
        let p = read();
        let a = p.adaptive.expect("[refinement]");
        let mut steps = Vec::new();
        let run = adaptive::solve_adaptive(&p, &a, &mut Silent, &mut |_, m, s, _| {
            steps.push((Row::of(s, m.nodes.len()), t.elapsed().as_secs_f64()));
        })
        .expect("adaptive beam");
        let total = t.elapsed().as_secs_f64();
        times.push(total);
        cpu.push(cpu_seconds() - c);
        if r + 1 == repeat.max(1) {
            last = Some((steps, run, total));
        }
    }
    let (steps, run, total) = last.expect("one repetition");
    for (k, (r, seconds)) in steps.iter().enumerate() {
        r.print(&format!("adaptive step {k}"), *seconds);
    }
    Row::of(&run.solution, run.model.nodes.len())
        .print(&format!("adaptive, all steps (stopped by {})", run.summary.stopped_by), total);
    let adaptive_error = (onset(&run.solution) - BEAM_ONSET).abs();
    let (fastest, slowest) =
        times.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &t| (a.min(t), b.max(t)));

    let base = read();
    let mut uniform = None;
    let mut h = base.node_spacing;
    for _ in 0..4 {
        let mut u = base.clone();
        u.adaptive = None;
        u.node_spacing = h;
        let (t, c) = (Instant::now(), cpu_seconds());
        let s = mlpg_contact::solve(&u).expect("uniform beam");
        let seconds = t.elapsed().as_secs_f64();
        let cpu_used = cpu_seconds() - c;
        Row::of(&s, s.displacement.len()).print(&format!("uniform h = {h}"), seconds);
        if (onset(&s) - BEAM_ONSET).abs() <= ONSET_TOLERANCE {
            uniform = Some((h, s.displacement.len(), seconds, cpu_used));
            break;
        }
        h /= 2.0;
    }
    println!();
    let cpu_least = cpu.iter().copied().fold(f64::INFINITY, f64::min);
    println!(
        "adaptive: |l_c − ref| = {adaptive_error:.4} with {} nodes; end to end {fastest:.2} s fastest, {slowest:.2} s slowest of {} runs; CPU {cpu_least:.2} s least",
        run.model.nodes.len(),
        times.len()
    );
    match uniform {
        Some((h, n, s, c)) => println!(
            "uniform: the first halving within {ONSET_TOLERANCE} is h = {h} ({n} nodes), {s:.2} s, CPU {c:.2} s: {:.1} times the adaptive run's fastest wall-clock time",
            s / fastest
        ),
        None => println!("uniform: no spacing down to h₀/8 within {ONSET_TOLERANCE}"),
    }
}
