//! End-to-end scaling of the solver on the cantilever of `problems/cantilever.toml`
//! (48 × 12, plane stress, clamped left edge, shear traction on the right edge), refined to a
//! list of node counts. Run with
//!
//! ```text
//! cargo run --release --features studies --example scaling -- [N1 N2 ...] [--beta 1] [--support-factor 1.5]
//! ```
//!
//! `--beta 1` runs the sparser stabilised operator (`discretisation.beta`, default 0: the
//! paper's mixed method); `--support-factor 1.5` sets `discretisation.support_factor`
//! (default 2).
//!
//! Node counts may be written `25000`, `25k` or `1.5M` (default: 10k 25k 50k 100k 250k). The
//! grid has `ny` intervals across the height and `4 ny` along the length, with `ny` chosen so
//! that `(4 ny + 1)(ny + 1)` is nearest to `N`.
//!
//! Each size runs in a fresh child process (the example re-invokes itself with `--one N`), so
//! the peak resident memory (`VmHWM` from `/proc/self/status`) of a row is that size's own.
//! Prints one row per size: nodes, DOFs, nonzeros of `K`, seconds per stage (`discretise` and
//! `solve_model`), their total (wall), the child's CPU time (user + system, all threads), and
//! the peak memory; then the least-squares growth exponent
//! `p` of `t ∝ N^p` of each stage over the sizes run. Nothing is asserted about timings.

mod args;

use clap::Parser;
use std::process::Command;
use std::time::Instant;

use mlpg_contact::problem::Problem;
use mlpg_contact::{Silent, discretise, solve_model};

/// Short column headers for the stages of `Model::timings` (other stages use their name).
const HEADERS: [(&str, &str); 10] = [
    ("nodes", "nodes_s"),
    ("supports", "supp"),
    ("cells", "cells"),
    ("faces", "faces"),
    ("mls_nodes", "mls_n"),
    ("mls_faces", "mls_f"),
    ("assembly", "assem"),
    ("factorisation", "factor"),
    ("solve", "solve"),
    ("recovery", "recov"),
];

const DEFAULT_SIZES: [usize; 5] = [10_000, 25_000, 50_000, 100_000, 250_000];

/// Intervals across the height for about `n` nodes on the 48 × 12 rectangle.
fn intervals_for(n: usize) -> usize {
    let count = |ny: usize| (4 * ny + 1) * (ny + 1);
    let mut ny = ((n as f64 / 4.0).sqrt().round() as usize).max(2);
    // Step to the nearest count (the estimate is off by at most one or two).
    while ny > 2 && count(ny - 1).abs_diff(n) <= count(ny).abs_diff(n) {
        ny -= 1;
    }
    while count(ny + 1).abs_diff(n) < count(ny).abs_diff(n) {
        ny += 1;
    }
    ny
}

/// The cantilever of `problems/cantilever.toml` with `ny` intervals across its height, with
/// `discretisation.beta` and `discretisation.support_factor` set to `beta` and `support`.
fn cantilever(ny: usize, beta: f64, support: f64) -> Problem {
    let spacing = 12.0 / ny as f64;
    let text = format!(
        r#"
        name = "cantilever"
        [geometry]
        kind = "rectangle"
        x = [0.0, 48.0]
        y = [-6.0, 6.0]
        [nodes]
        spacing = {spacing:?}
        layout = "structured"
        [material]
        young = 3.0e7
        poisson = 0.3
        plane = "stress"
        [discretisation]
        basis = "linear"
        support_factor = {support:?}
        quadrature_points = 2
        beta = {beta:?}
        [[boundary]]
        edge = "left"
        displacement = {{ x = 0.0, y = 0.0 }}
        [[boundary]]
        edge = "right"
        traction = {{ y = 83.333333333333 }}
        "#
    );
    match Problem::from_toml(&text) {
        Ok(p) => p,
        Err(e) => panic!("cantilever with ny = {ny} is invalid: {e}"),
    }
}

/// Peak resident set size (`VmHWM`) of this process in MiB, if the kernel reports it.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// User + system CPU seconds of this process (all threads) from `/proc/self/stat`, assuming
/// the usual 100 clock ticks per second.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// End-to-end scaling of the solver on the cantilever 48 × 12: one row per node count, each
/// solved in a fresh child process.
#[derive(Parser)]
struct Cli {
    /// Node counts, written 25000, 25k or 1.5M
    #[arg(value_name = "N", value_parser = args::count, default_values_t = DEFAULT_SIZES)]
    sizes: Vec<usize>,
    #[command(flatten)]
    operator: args::Operator,
    /// Child mode: solve this one size and print one JSON line
    #[arg(long, value_name = "N", value_parser = args::count, hide = true)]
    one: Option<usize>,
}

/// Child mode: solves one size and prints one JSON line on stdout.
fn run_one(n: usize, beta: f64, support: f64) -> Result<(), Box<dyn std::error::Error>> {
    let ny = intervals_for(n);
    let problem = cantilever(ny, beta, support);
    let t0 = Instant::now();
    let model = discretise(&problem, &mut Silent)?;
    let (model, _, solution) = solve_model(&problem, model, None, &mut Silent)?;
    let total = t0.elapsed().as_secs_f64();
    let stages: Vec<(&str, f64)> = model.timings.iter().map(|t| (t.stage, t.seconds)).collect();
    let row = serde_json::json!({
        "nodes": model.nodes.len(),
        "dofs": model.system.matrix.n,
        "nnz": model.system.matrix.values.len(),
        "stages": stages,
        "total": total,
        "cpu": cpu_seconds(),
        "peak_mib": peak_rss_mib(),
        "relative_residual": solution.relative_residual,
    });
    println!("{row}");
    Ok(())
}

/// One finished row, as read back from a child.
struct Row {
    nodes: f64,
    dofs: f64,
    nnz: f64,
    /// `(stage, seconds)` in pipeline order.
    stages: Vec<(String, f64)>,
    total: f64,
    cpu: f64,
    peak_mib: f64,
    residual: f64,
}

/// Runs one size in a fresh child process.
fn run_child(exe: &std::path::Path, n: usize, beta: f64, support: f64) -> Result<Row, String> {
    let out = Command::new(exe)
        .args(["--one", &n.to_string()])
        .args(["--beta", &beta.to_string(), "--support-factor", &support.to_string()])
        .output()
        .map_err(|e| format!("cannot start {}: {e}", exe.display()))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let line = stdout.lines().find(|l| l.starts_with('{'));
    let parsed: Option<serde_json::Value> = line.and_then(|l| serde_json::from_str(l).ok());
    let Some(v) = parsed.filter(|_| out.status.success()) else {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!("{}: {}", out.status, err.trim()));
    };
    let num = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
    let stages = v["stages"]
        .as_array()
        .map(|a| {
            a.iter().filter_map(|p| Some((p[0].as_str()?.to_string(), p[1].as_f64()?))).collect()
        })
        .unwrap_or_default();
    Ok(Row {
        nodes: num("nodes"),
        dofs: num("dofs"),
        nnz: num("nnz"),
        stages,
        total: num("total"),
        cpu: num("cpu"),
        peak_mib: num("peak_mib"),
        residual: num("relative_residual"),
    })
}

/// Column header of a stage.
fn header(stage: &str) -> &str {
    HEADERS.iter().find(|(s, _)| *s == stage).map_or(stage, |(_, h)| h)
}

/// Seconds of `stage` in `row` (NaN when the row does not have it).
fn seconds(row: &Row, stage: &str) -> f64 {
    row.stages.iter().find(|(s, _)| s == stage).map_or(f64::NAN, |(_, t)| *t)
}

/// Least-squares slope of `log y` against `log x` (NaN with fewer than two usable points).
fn exponent(xs: &[f64], ys: &[f64]) -> f64 {
    let pts: Vec<(f64, f64)> = xs
        .iter()
        .zip(ys)
        .filter(|(x, y)| **x > 0.0 && **y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = pts.len() as f64;
    if pts.len() < 2 {
        return f64::NAN;
    }
    let (mx, my) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let sxy: f64 = pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = pts.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    args::refuse_retired_env(&[
        ("MLPG_SCALING_BETA", "--beta"),
        ("MLPG_SCALING_SUPPORT", "--support-factor"),
    ]);
    let cli: Cli = args::parse(&[("beta", "0"), ("support_factor", "2")]);
    let (beta, support) =
        (cli.operator.beta.unwrap_or(0.0), cli.operator.support_factor.unwrap_or(2.0));
    if let Some(n) = cli.one {
        return run_one(n, beta, support);
    }
    let sizes = cli.sizes;
    let exe = std::env::current_exe()?;
    println!(
        "cantilever 48 x 12, linear basis, alpha_s = {support}, 2-point face quadrature, beta = {beta}; {} rayon threads",
        rayon::current_num_threads()
    );
    println!(
        "wall seconds per stage; total = discretise + solve_model (wall), cpu = user + sys of \
         the child; peak = VmHWM of a fresh process per size"
    );
    // Stage columns: the pipeline's stages, in order (taken from the first finished row).
    let mut stages: Vec<String> = Vec::new();
    let mut rows = Vec::new();
    for n in sizes {
        let row = match run_child(&exe, n, beta, support) {
            Ok(row) => row,
            Err(e) => {
                println!("{n:>8} nodes requested: failed ({e})");
                continue;
            }
        };
        if stages.is_empty() {
            stages = row.stages.iter().map(|(s, _)| s.clone()).collect();
            let mut line = format!("{:>8} {:>8} {:>10}", "nodes", "dofs", "nnz(K)");
            for s in &stages {
                line += &format!(" {:>7}", header(s));
            }
            line += &format!(" {:>8} {:>8} {:>9} {:>9}", "total", "cpu", "peak MiB", "residual");
            println!("{line}");
        }
        let mut line = format!("{:>8} {:>8} {:>10}", row.nodes, row.dofs, row.nnz);
        for s in &stages {
            line += &format!(" {:>7.3}", seconds(&row, s));
        }
        line += &format!(
            " {:>8.3} {:>8.2} {:>9.0} {:>9.1e}",
            row.total, row.cpu, row.peak_mib, row.residual
        );
        println!("{line}");
        rows.push(row);
    }
    if rows.len() >= 2 {
        let xs: Vec<f64> = rows.iter().map(|r| r.nodes).collect();
        let mut line = format!("{:>28}", "exponent p (t ~ N^p)");
        for s in &stages {
            let ys: Vec<f64> = rows.iter().map(|r| seconds(r, s)).collect();
            line += &format!(" {:>7.2}", exponent(&xs, &ys));
        }
        let ys: Vec<f64> = rows.iter().map(|r| r.total).collect();
        line += &format!(" {:>8.2}", exponent(&xs, &ys));
        let ys: Vec<f64> = rows.iter().map(|r| r.cpu).collect();
        line += &format!(" {:>8.2}", exponent(&xs, &ys));
        let ys: Vec<f64> = rows.iter().map(|r| r.peak_mib).collect();
        line += &format!(" {:>9.2}", exponent(&xs, &ys));
        println!("{line}");
    }
    Ok(())
}
