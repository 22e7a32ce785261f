//! Timing of the contact stages on a long strip with ~2 000 contact candidates (the size for
//! which condensation, checks of `M` and Lemke together were to take under 10 s): a strip
//! `L × 1` (default `L = 100`), clamped on its left edge, under a uniform downward load `1` on
//! its top edge, above a rigid foundation `0.01` below its bottom edge (the beam on
//! foundation, stretched). Plane stress, `E = 30 000`, `ν = 0.3`, linear basis, `α_s = 2`.
//! Run with
//!
//! ```text
//! cargo run --release --example contact_timing -- [--spacing h] [--length L] [--repeats r] [--blocks 32,64,...]
//! ```
//!
//! (defaults `--spacing 0.05 --length 100`: 42 021 nodes and 2 000 candidates; `--repeats 3`;
//! without `--blocks`, the library's default block width). Prints the discretisation stages
//! once, then for each block width the condensation `M = G K⁻¹ E` `repeats` times (min and
//! max) with a hash of `M`, the checks of `M` (Cholesky and Lanczos, `contact::spectrum`), and
//! Lemke (pivots, seconds). Nothing is asserted.

mod args;
mod strip;

use strip::strip;

use clap::Parser;
use std::time::Instant;

use mlpg_contact::contact::{self, ContactTarget};
use mlpg_contact::lcp::{Lcp, LemkeParams, lemke};
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
    let spec = problem.contact.ok_or("the strip has contact")?;
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
    for block in blocks {
        let mut times = Vec::new();
        for _ in 0..repeats.max(1) {
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
        let hash = last.as_ref().map_or(0, |p: &contact::CondensedPart| {
            p.compliance.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, v| {
                (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3)
            })
        });
        let label = block.map_or("default".to_string(), |w| w.to_string());
        println!(
            "condense (G K^-1 E), block {label}: min {min:.3} s, max {max:.3} s over {} runs; \
             hash of M {hash:016x}",
            times.len()
        );
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
