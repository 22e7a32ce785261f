//! The cost of axisymmetry (docs/dev/axisymmetric.md, "Cost against plane strain"): the Hertz
//! sphere of `problems/sphere_on_flat_axisymmetric.toml` (at its spacing the fitted `a` and `p₀`
//! are within 1 % of Hertz) against the same section in plane strain (a cylinder on a flat, the
//! edge `x = 0` a symmetry roller), same nodes, same spacing. The two are run alternately,
//! `--rounds` times each, in this process (`discretise` then `solve_model`, no output files);
//! prints each stage's minimum and median over the rounds, the totals and their ratio.
//! Nothing is asserted (no timed tests).
//!
//! `cargo run --release --features studies --example axisymmetric_cost -- [--rounds 5]`

mod args;

use mlpg_contact::problem::Problem;
use mlpg_contact::{Progress, discretise, solve_model};
use std::collections::BTreeMap;
use std::time::Instant;

const SPHERE: &str = include_str!("../../problems/sphere_on_flat_axisymmetric.toml");

/// The axisymmetric sphere against its plane-strain twin, alternately.
#[derive(clap::Parser)]
struct Cli {
    /// Runs of each case
    #[arg(long, default_value_t = 5)]
    rounds: usize,
}

/// Keeps each stage's seconds (summed when a stage recurs).
#[derive(Default)]
struct Record {
    stages: Vec<(&'static str, f64)>,
}

impl Progress for Record {
    fn finish(&mut self, stage: &'static str, seconds: f64) {
        match self.stages.iter_mut().find(|(s, _)| *s == stage) {
            Some((_, t)) => *t += seconds,
            None => self.stages.push((stage, seconds)),
        }
    }
}

fn cases() -> [(&'static str, Problem); 2] {
    let axi = Problem::from_toml(SPHERE).unwrap();
    let from = "plane = \"axisymmetric\"";
    assert!(SPHERE.contains(from), "sphere_on_flat_axisymmetric.toml: `{from}` not found");
    let plane = SPHERE.replace(from, "plane = \"strain\"").replace(
        "[contact]",
        "[[boundary]]\nedge = \"axis\"\ndisplacement = { x = 0.0 }\n\n[contact]",
    );
    [("axisymmetric", axi), ("plane strain", Problem::from_toml(&plane).unwrap())]
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }
}

fn main() {
    let cli: Cli = args::parse(&[]);
    let cases = cases();
    // times[case][stage] = seconds per round; totals[case] = wall seconds per round
    let mut times: Vec<BTreeMap<&'static str, Vec<f64>>> = vec![BTreeMap::new(); 2];
    let mut order: Vec<&'static str> = Vec::new();
    let mut totals = vec![Vec::new(); 2];
    for round in 0..cli.rounds {
        for (k, (name, problem)) in cases.iter().enumerate() {
            let mut record = Record::default();
            let start = Instant::now();
            let model = discretise(problem, &mut record).unwrap();
            let (model, _, s) = solve_model(problem, model, None, &mut record).unwrap();
            let wall = start.elapsed().as_secs_f64();
            let c = s.contact().unwrap();
            if round == 0 {
                println!(
                    "{name:<13} nodes {}  candidates {}  closed {}  total_force {:.6e}",
                    model.nodes.len(),
                    c.closed.len(),
                    c.closed.iter().filter(|&&x| x).count(),
                    c.total_force
                );
            }
            for (stage, t) in record.stages {
                if !order.contains(&stage) {
                    order.push(stage);
                }
                times[k].entry(stage).or_default().push(t);
            }
            totals[k].push(wall);
        }
    }
    println!(
        "\n{:<22} {:>10} {:>10} {:>10} {:>10} {:>8}",
        "stage (s)", "axi min", "axi med", "plane min", "plane med", "med ×"
    );
    for stage in &order {
        let mut a = times[0].get(stage).cloned().unwrap_or_default();
        let mut p = times[1].get(stage).cloned().unwrap_or_default();
        let (amin, pmin) = (
            a.iter().cloned().fold(f64::NAN, f64::min),
            p.iter().cloned().fold(f64::NAN, f64::min),
        );
        let (amed, pmed) = (median(&mut a), median(&mut p));
        println!(
            "{stage:<22} {amin:>10.4} {amed:>10.4} {pmin:>10.4} {pmed:>10.4} {:>8.2}",
            amed / pmed
        );
    }
    let (mut a, mut p) = (totals[0].clone(), totals[1].clone());
    let (amin, pmin) =
        (a.iter().cloned().fold(f64::NAN, f64::min), p.iter().cloned().fold(f64::NAN, f64::min));
    let (amed, pmed) = (median(&mut a), median(&mut p));
    println!(
        "{:<22} {amin:>10.4} {amed:>10.4} {pmin:>10.4} {pmed:>10.4} {:>8.2}",
        "total (wall)",
        amed / pmed
    );
    println!("ratio axisymmetric / plane: min {:.3}, median {:.3}", amin / pmin, amed / pmed);
}
