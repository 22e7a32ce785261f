//! The clamped cantilever (`problems/cantilever.toml`: left edge fully clamped, `u = 0`;
//! uniform end shear, `P = 1000`; L = 48, D = 12, E = 3e7, ν = 0.3, plane stress): the
//! compliance `W` (the load's work) against nodes, uniform and adaptive, against the Q2 FE
//! path extrapolated (docs/dev/adaptive.md, "The clamped cantilever";
//! `tests/validation/clamped_cantilever.rs` asserts the row it relies on).
//!
//! Printed: the FE values at element sizes 2 … 0.125 (`--quick`: … 0.25) with their
//! extrapolation (rate, error bar), the tip deflection's too; then MFVM (`β = 0.5`,
//! structured) uniform `h` and adaptive runs (gradient and recovery indicators, each θ, from
//! each `h₀`) with the relative errors of `W` and of the tip deflection, and whether and with
//! how many nodes each adaptive run reaches the finest uniform error (`max_nodes` = the
//! finest uniform count).
//!
//! `cargo run --release --features studies --example adaptive_cantilever -- [--quick] [--uniform 2,1,0.5,0.25]
//! [--start 2] [--fraction 0.5,0.7]` (the defaults; the validation test's row is
//! `--uniform 1,0.5,0.25,0.125 --start 0.25 --fraction 0.5`).

mod args;
#[path = "../../tests/validation/clamped_cantilever_measure.rs"]
#[allow(dead_code)]
mod measure;

use measure::{cantilever, compliance_fem, compliance_mfvm, extrapolate, solve, tip};
use mlpg_contact::pipeline::adaptive;
use mlpg_contact::problem::{Adaptive, Indicator, Method};
use std::time::Instant;

/// The clamped cantilever's compliance against nodes, uniform and adaptive.
#[derive(clap::Parser)]
struct Cli {
    /// FE reference from element sizes 2 … 0.25 only (default: … 0.125)
    #[arg(long)]
    quick: bool,
    /// Uniform node spacings
    #[arg(long, value_name = "H,…", value_delimiter = ',', value_parser = args::positive,
          default_values_t = [2.0, 1.0, 0.5, 0.25])]
    uniform: Vec<f64>,
    /// Initial spacings h₀ of the adaptive loops
    #[arg(long, value_name = "H,…", value_delimiter = ',', value_parser = args::positive,
          default_values_t = [2.0])]
    start: Vec<f64>,
    /// Dörfler fractions θ of the adaptive loops
    #[arg(long, value_name = "THETA,…", value_delimiter = ',', value_parser = args::positive,
          default_values_t = [0.5, 0.7])]
    fraction: Vec<f64>,
}

fn main() {
    let cli: Cli = args::parse(&[]);
    let (quick, uniform, starts, fractions) = (cli.quick, cli.uniform, cli.start, cli.fraction);

    println!("## FE (Q2) reference\n");
    println!("| h | nodes | W | tip u_y | seconds |");
    println!("|---|---|---|---|---|");
    let fe_h: &[f64] = if quick { &[2.0, 1.0, 0.5, 0.25] } else { &[2.0, 1.0, 0.5, 0.25, 0.125] };
    let (mut fw, mut ft) = (Vec::new(), Vec::new());
    for &h in fe_h {
        let p = cantilever(h, Method::Fem);
        let t = Instant::now();
        let (m, s) = solve(&p);
        let (w, u) = (compliance_fem(&m, &s), tip(&m, &s));
        let seconds = t.elapsed().as_secs_f64();
        println!("| {h} | {} | {w:.10e} | {u:.10e} | {seconds:.1} |", m.nodes.len());
        fw.push(w);
        ft.push(u);
    }
    let n = fw.len();
    let (w_ref, w_rate) = extrapolate(fw[n - 3], fw[n - 2], fw[n - 1]);
    let (w_coarser, _) = extrapolate(fw[n - 4], fw[n - 3], fw[n - 2]);
    let (t_ref, t_rate) = extrapolate(ft[n - 3], ft[n - 2], ft[n - 1]);
    let (t_coarser, _) = extrapolate(ft[n - 4], ft[n - 3], ft[n - 2]);
    println!(
        "\nW: extrapolated {w_ref:.10e} (rate {w_rate:.2}; error bar {:.2e}, relative {:.1e}; finest − extrapolated {:.2e})",
        (w_ref - w_coarser).abs(),
        (w_ref - w_coarser).abs() / w_ref,
        fw[n - 1] - w_ref
    );
    println!(
        "tip: extrapolated {t_ref:.10e} (rate {t_rate:.2}; error bar {:.2e}, relative {:.1e})\n",
        (t_ref - t_coarser).abs(),
        (t_ref - t_coarser).abs() / t_ref.abs()
    );

    println!("## MFVM, β = 0.5: relative errors against the FE extrapolation\n");
    println!("| run | step | nodes | min h_I | W/W_ref − 1 | tip/tip_ref − 1 | seconds |");
    println!("|---|---|---|---|---|---|---|");
    let mut finest = (0usize, 0.0f64, 0.0f64);
    for &h in &uniform {
        let p = cantilever(h, Method::Mfvm);
        let t = Instant::now();
        let (m, s) = solve(&p);
        let e = compliance_mfvm(&p, &m, &s) / w_ref - 1.0;
        println!(
            "| uniform h = {h} | – | {} | {h} | {e:+.3e} | {:+.3e} | {:.2} |",
            m.nodes.len(),
            tip(&m, &s) / t_ref - 1.0,
            t.elapsed().as_secs_f64()
        );
        finest = (m.nodes.len(), e.abs(), h);
    }
    for &h0 in &starts {
        for &fraction in &fractions {
            for indicator in [Indicator::Gradient, Indicator::Recovery] {
                let name = format!("adaptive {} θ = {fraction} from h₀ = {h0}", indicator.name());
                let a = Adaptive {
                    steps: 14,
                    max_nodes: finest.0,
                    fraction,
                    indicator,
                    contact: false,
                    ..Adaptive::default()
                };
                let (mut step, mut reached) = (0, None);
                let t = Instant::now();
                let run = adaptive::solve_adaptive(
                    &cantilever(h0, Method::Mfvm),
                    &a,
                    &mut mlpg_contact::Silent,
                    &mut |q, m, s, _| {
                        let e = compliance_mfvm(q, m, s) / w_ref - 1.0;
                        let hmin = m.nodes.spacing.iter().copied().fold(f64::INFINITY, f64::min);
                        println!(
                            "| {name} | {step} | {} | {hmin:.4} | {e:+.3e} | {:+.3e} | {:.2} |",
                            m.nodes.len(),
                            tip(m, s) / t_ref - 1.0,
                            t.elapsed().as_secs_f64()
                        );
                        if reached.is_none() && e.abs() <= finest.1 {
                            reached = Some(m.nodes.len());
                        }
                        step += 1;
                    },
                );
                if let Err(e) = run {
                    println!("| {name} | failed: {e} | | | | | |");
                }
                let verdict = match reached {
                    Some(n) => format!(
                        "reached the uniform h = {} error {:.3e} with {n} nodes ({:.3} of {})",
                        finest.2,
                        finest.1,
                        n as f64 / finest.0 as f64,
                        finest.0
                    ),
                    None => format!(
                        "did not reach the uniform h = {} error {:.3e} within {} nodes",
                        finest.2, finest.1, finest.0
                    ),
                };
                println!("| {name} | {verdict} | | | | | |");
            }
        }
    }
}
