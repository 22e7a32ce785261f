//! Timing of the contact stages on a long strip with ~2 000 contact candidates (the size for
//! which condensation, checks of `M` and Lemke together were to take under 10 s): a strip
//! `L × 1` (default `L = 100`), clamped on its left edge, under a uniform downward load `1` on
//! its top edge, above a rigid foundation `0.01` below its bottom edge (the beam on
//! foundation, stretched). Plane stress, `E = 30 000`, `ν = 0.3`, linear basis, `α_s = 2`.
//! Run with
//!
//! ```text
//! cargo run --release --features studies --example contact_timing -- [--spacing h] [--length L] [--repeats r] [--blocks 32,64,...] [--sparse n [--compare-static]]
//! ```
//!
//! (defaults `--spacing 0.05 --length 100`: 42 021 nodes and 2 000 candidates; `--repeats 3`;
//! without `--blocks`, the library's default block width). Prints the discretisation stages
//! once, then for each block width the condensation `M = G K⁻¹ E` `repeats` times (min and
//! max) with a hash of `M`, the checks of `M` (Cholesky and Lanczos, `contact::spectrum`), and
//! Lemke (pivots, seconds). With `--sparse n` it also factorises `K` with static pivoting and
//! nested dissection and condenses `n` times by reach-restricted solves
//! (`contact::sparse_compliance`), compares that `M` with the blocked one and uses it for the
//! checks and Lemke. Nothing is asserted.

mod args;
mod strip;

use strip::strip;

use clap::Parser;
use std::time::Instant;

use mlpg_contact::contact::{self, ContactTarget};
use mlpg_contact::lcp::{Lcp, LemkeParams, lemke};
use mlpg_contact::linear_solve::{ColumnOrdering, FactorOptions, Factorisation};
use mlpg_contact::{Silent, discretise};

/// Timing of the contact stages (candidates, condensation, checks of M, Lemke) on a long strip
/// above a rigid foundation.
#[derive(Parser)]
struct Cli {
    /// Node spacing h
    #[arg(long, value_name = "H", default_value_t = 0.05, value_parser = args::positive)]
    spacing: f64,
    /// Length L of the strip L × 1
    #[arg(long, value_name = "L", default_value_t = 100.0, value_parser = args::positive)]
    length: f64,
    /// Condensations timed per block width
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Block widths of the condensation, comma-separated (default: the library's width)
    #[arg(long, value_name = "WIDTH", value_delimiter = ',')]
    blocks: Vec<usize>,
    /// Also factorise with static pivoting and nested dissection and condense by
    /// reach-restricted solves (`contact::sparse_compliance`) `SPARSE` times; its `M` is
    /// compared with the blocked one and used for the checks and Lemke
    #[arg(long, value_name = "SPARSE", default_value_t = 0)]
    sparse: usize,
    /// With `--sparse`: also condense by blocked full solves with the same static-pivoting
    /// factors and compare (slow: refined full solves)
    #[arg(long)]
    compare_static: bool,
}

/// CPU seconds (user + system, all threads) of this process so far.
fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/self/stat")
        .ok()
        .and_then(|s| {
            let rest = s.rsplit_once(')')?.1.split_whitespace().collect::<Vec<_>>();
            let t: f64 = rest.get(11)?.parse::<f64>().ok()? + rest.get(12)?.parse::<f64>().ok()?;
            Some(t / 100.0)
        })
        .unwrap_or(f64::NAN)
}

fn hash(m: &[f64]) -> u64 {
    m.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, v| (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cli: Cli = args::parse(&[]);
    let (h, length, repeats) = (cli.spacing, cli.length, cli.repeats);
    let blocks: Vec<Option<usize>> =
        if cli.blocks.is_empty() { vec![None] } else { cli.blocks.into_iter().map(Some).collect() };
    let problem = strip(h, length);
    println!("strip {length} x 1, h = {h}; {} rayon threads", rayon::current_num_threads());
    let t0 = Instant::now();
    let model = discretise(&problem, &mut Silent)?;
    let stages: Vec<String> =
        model.timings.iter().map(|t| format!("{} {:.3}", t.stage, t.seconds)).collect();
    println!(
        "{} nodes, {} DOFs, nnz(K) {}; discretise {:.3} s ({})",
        model.nodes.len(),
        model.system.matrix.n,
        model.system.matrix.values.len(),
        t0.elapsed().as_secs_f64(),
        stages.join(", ")
    );
    println!("factorisation: {:?}", model.factorisation.stats());
    let spec = problem.contact().ok_or("the strip has contact")?;
    let ContactTarget::Rigid(line) = spec.target else { return Err("rigid obstacle".into()) };
    let t = Instant::now();
    let cand = contact::candidates_on(
        &problem,
        &model,
        spec.edge,
        &|x| (line.gap(x), line.normal),
        spec.condensation,
    )?;
    println!("{} candidates in {:.3} s", cand.len(), t.elapsed().as_secs_f64());
    let mut last = None;
    for block in blocks.into_iter().filter(|_| repeats > 0) {
        let mut times = Vec::new();
        let cpu = cpu_seconds();
        for _ in 0..repeats {
            let t = Instant::now();
            let (f, b, op) = (&model.factorisation, &model.system.rhs, &cand.operator);
            last = Some(match block {
                Some(w) => contact::condense_blocked(f, b, op, w)?,
                None => contact::condense(f, b, op)?,
            });
            times.push(t.elapsed().as_secs_f64());
        }
        let (min, max) =
            times.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &t| (a.min(t), b.max(t)));
        let hash = last.as_ref().map_or(0, |p: &contact::CondensedPart| hash(&p.compliance));
        let label = block.map_or("default".to_string(), |w| w.to_string());
        println!(
            "condense (G K^-1 E), block {label}: min {min:.3} s, max {max:.3} s over {} runs \
             (cpu {:.3} s per run); hash of M {hash:016x}",
            times.len(),
            (cpu_seconds() - cpu) / times.len() as f64
        );
    }
    if cli.sparse > 0 {
        let (t, cpu) = (Instant::now(), cpu_seconds());
        let f = Factorisation::with_options(
            &model.system.matrix,
            ColumnOrdering::NestedDissection(&model.nodes.points),
            &FactorOptions::nested_dissection_static(),
        )?;
        println!(
            "static ND factorisation: {:.3} s (cpu {:.3} s); {:?}",
            t.elapsed().as_secs_f64(),
            cpu_seconds() - cpu,
            f.stats()
        );
        let mut sparse = None;
        for _ in 0..cli.sparse {
            let (t, cpu) = (Instant::now(), cpu_seconds());
            let op = &cand.operator;
            sparse = Some(contact::sparse_compliance(&f, op)?.ok_or("sparse route refused")?);
            println!(
                "sparse condensation: {:.3} s (cpu {:.3} s)",
                t.elapsed().as_secs_f64(),
                cpu_seconds() - cpu
            );
        }
        let compliance = sparse.ok_or("no sparse condensation")?;
        if let Some(old) = &last {
            let scale = old.compliance.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let diff = old
                .compliance
                .iter()
                .zip(&compliance)
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            println!("sparse vs blocked M: max |diff| / max |M| = {:.3e}", diff / scale);
        }
        if cli.compare_static {
            let t = Instant::now();
            let full = contact::condense_blocked(&f, &model.system.rhs, &cand.operator, 64)?;
            let scale = full.compliance.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let diff = full
                .compliance
                .iter()
                .zip(&compliance)
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            println!(
                "blocked full solves with the static factors: {:.3} s; sparse vs those: max \
                 |diff| / max |M| = {:.3e}",
                t.elapsed().as_secs_f64(),
                diff / scale
            );
        }
        let free_gap = cand.operator.gap_contribution(&f.solve(&model.system.rhs)?);
        println!("hash of sparse M {:016x}", hash(&compliance));
        last = Some(contact::CondensedPart { compliance, free_gap });
    }
    let part = last.ok_or("no condensation")?;
    let t = Instant::now();
    let condensed = contact::CondensedContact::combine(&cand.initial_gap, &[part])?;
    println!(
        "combine + checks (extreme eigenvalues of the symmetric part, {:?}): {:.3} s; min eig \
         {:.6e}, max eig {:.6e}, skew {:.2e}",
        condensed.eigenvalue_method,
        t.elapsed().as_secs_f64(),
        condensed.min_symmetric_eigenvalue,
        condensed.max_symmetric_eigenvalue,
        condensed.skew_ratio
    );
    let lcp = Lcp::new(cand.len(), condensed.compliance.clone(), condensed.free_gap.clone())?;
    let t = Instant::now();
    let result = lemke(&lcp, &LemkeParams::default())?;
    let active = result.z.iter().filter(|&&z| z > 0.0).count();
    println!(
        "lemke: {:.3} s, {} pivots, {active} active, total force {:.6}",
        t.elapsed().as_secs_f64(),
        result.pivots,
        result.z.iter().sum::<f64>()
    );
    Ok(())
}
