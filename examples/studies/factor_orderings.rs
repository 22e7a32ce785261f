//! Compares column orderings and knobs of the sparse LU (`linear_solve::FactorOptions`) on the
//! system of a problem file with its node spacing overridden. Run with
//!
//! ```text
//! cargo run --release --features studies --example factor_orderings -- <problem.toml> <spacing> [variant ...] [--beta 1]
//! ```
//!
//! A variant is `nd` or `colamd` followed by optional `:key=value` settings: `void=1e-14`
//! (drop tolerance, `0` keeps every entry), `tasks=2` (numeric split), `leaf=64` (nodes per
//! nested-dissection leaf), `width=1.0` (separator width scale), `thin=4` (boxes thinner than
//! this many separator widths are not cut; a comma list builds one ordering per value and
//! keeps the least fill), `method=static|partial|auto` (`static`: the static-pivoting LU with the structure of
//! `K + Kᵀ`; its bound is then that of the Cholesky factor of `P(K + Kᵀ)Pᵀ`), `pivot=1.5e-8`
//! (its pivot tolerance), `precision=double|mixed` (its factors' precision), `amd=1` (the approximate minimum degree order of the node graph as a further candidate), `analyse=1` (ordering and fill bound only, no factorisation). Default variants: `nd` and
//! `colamd`. Each variant prints its stage times, nonzeros, supernodes, the relative residual
//! of one solve against the full `K`, the solve time and a hash of the solution (equal hashes
//! = bit-identical solutions). The last line is the peak resident memory of the process
//! (`VmHWM`): run one variant per process to measure its memory. `--beta 1` and
//! `--support-factor 1.5` override the problem's `discretisation.beta` and
//! `discretisation.support_factor`; `--graded` keeps the file's refinement regions (its
//! graded node set, e.g. `problems/beam_on_foundation_refined.toml 0.25 --graded`); `--adaptive`
//! runs the file's adaptive loop first and takes its final node set (e.g.
//! `benches/peer/beam_goals.toml 0.5 --adaptive`).

mod args;

use clap::Parser;
use std::path::PathBuf;
use std::time::Instant;

use mlpg_contact::assembly::{self, AssemblyInput};
use mlpg_contact::linear_solve::{
    self, ColumnOrdering, FactorMethod, FactorOptions, FactorPrecision, Factorisation,
};
use mlpg_contact::neighbours::Supports;
use mlpg_contact::problem::Problem;
use mlpg_contact::{mls, nodes, weak_form};

fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    Some(line.split_whitespace().nth(1)?.parse::<f64>().ok()? / 1024.0)
}

/// Column orderings and options of the sparse LU on the system of a problem file.
#[derive(Parser)]
struct Cli {
    /// Problem file (TOML)
    problem: PathBuf,
    /// Node spacing h (overrides the file's; with `--graded` the file's spacing and
    /// refinement regions are kept and this must equal the file's spacing)
    #[arg(value_parser = args::positive)]
    spacing: f64,
    /// Use the file's graded node set (`nodes::for_problem`: its `[[nodes.refine]]` regions)
    #[arg(long)]
    graded: bool,
    /// Run the file's adaptive loop (`[refinement]`) and take its final node set (its
    /// refinement regions; implies `--graded`)
    #[arg(long)]
    adaptive: bool,
    /// `nd` or `colamd`, each followed by optional `:key=value` settings (see the file header)
    #[arg(default_values = ["nd", "colamd"])]
    variants: Vec<String>,
    #[command(flatten)]
    operator: args::Operator,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    args::refuse_retired_env(&[("MLPG_BETA", "--beta")]);
    let cli: Cli = args::parse(&[]);
    let (spacing, variants) = (cli.spacing, &cli.variants);
    let mut problem = Problem::from_toml(&std::fs::read_to_string(&cli.problem)?)?;
    problem.node_spacing = spacing;
    if let Some(beta) = cli.operator.beta {
        problem.discretisation.beta = beta;
    }
    if let Some(support_factor) = cli.operator.support_factor {
        problem.discretisation.mls.support_factor = support_factor;
    }
    let t = Instant::now();
    let disc = &problem.discretisation;
    if cli.adaptive {
        let a = problem.adaptive.ok_or("--adaptive needs a [refinement] table")?;
        let mut silent = mlpg_contact::Silent;
        let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
            &problem,
            &a,
            &mut silent,
            &mut |_, _, _, _| {},
        )?;
        problem.refinement = run.problem.refinement.clone();
    }
    let nodes = if cli.graded || cli.adaptive {
        nodes::for_problem(&problem)?
    } else {
        nodes::generate(&problem.domain, problem.node_spacing, problem.layout)?
    };
    let supports = Supports::new(&nodes, disc.mls.support_factor);
    let cells = weak_form::build_cells(&problem.domain, &nodes)?;
    let faces = weak_form::collect_faces(&cells);
    let fq = weak_form::FaceQuadrature::new(&faces.interior, disc.quadrature_points);
    let ns = mls::shape_functions(&nodes.points, &nodes, &supports, &disc.mls, true)?;
    let fs = mls::shape_functions(
        &fq.points,
        &nodes,
        &supports,
        &disc.mls,
        assembly::needs_face_gradients(disc.beta),
    )?;
    let d = problem.material.constitutive();
    let system = assembly::assemble(&AssemblyInput {
        body: assembly::Body::new(&problem, &nodes, &d),
        cells: &cells,
        interior_faces: &faces.interior,
        boundary_faces: &faces.boundary,
        face_quadrature: &fq,
        face_shapes: &fs,
        node_shapes: &ns,
        axisymmetric: None,
        beta: disc.beta,
    })?;
    let k = &system.matrix;
    println!(
        "{}: h = {spacing}, {} nodes, {} DOFs, nnz(K) {}, assembled in {:.2} s; separator width {:?}",
        problem.name,
        nodes.len(),
        k.n,
        k.values.len(),
        t.elapsed().as_secs_f64(),
        linear_solve::separator_width(k, &nodes.points)
    );
    let b = &system.rhs;
    for v in variants {
        let mut parts = v.split(':');
        let kind = parts.next().unwrap_or("nd");
        let mut opt = FactorOptions::default();
        let mut analyse_only = false;
        for kv in parts {
            let (key, value) = kv.split_once('=').ok_or("settings are key=value")?;
            match key {
                "void" => opt.void_tolerance = value.parse()?,
                "tasks" => opt.tasks = value.parse()?,
                "leaf" => opt.leaf_nodes = value.parse()?,
                "width" => opt.separator_scale = value.parse()?,
                "thin" => {
                    opt.thin_boxes = value.split(',').map(str::parse).collect::<Result<_, _>>()?;
                }
                "analyse" => analyse_only = value == "1",
                "amd" => opt.amd = value == "1",
                "method" => {
                    opt.method = match value {
                        "static" => FactorMethod::StaticPivoting,
                        "partial" => FactorMethod::PartialPivoting,
                        "auto" => FactorMethod::Auto,
                        _ => return Err(format!("unknown method {value}").into()),
                    }
                }
                "pivot" => opt.pivot_tolerance = value.parse()?,
                "precision" => {
                    opt.precision = match value {
                        "double" => FactorPrecision::Double,
                        "mixed" => FactorPrecision::Mixed,
                        _ => return Err(format!("unknown precision {value}").into()),
                    }
                }
                _ => return Err(format!("unknown setting {key}").into()),
            }
        }
        let ordering = match kind {
            "nd" => ColumnOrdering::NestedDissection(&nodes.points),
            "colamd" => ColumnOrdering::Colamd,
            _ => return Err(format!("unknown ordering {kind}").into()),
        };
        if analyse_only {
            let s = Factorisation::analyse(k, ordering, &opt)?;
            println!(
                "{v:<28} ordering + analysis {:.3} s; bound nnz {:.1} M, flops {:.2e}",
                s.ordering_seconds,
                s.bound_nnz as f64 * 1e-6,
                s.bound_flops
            );
            continue;
        }
        let t = Instant::now();
        let f = Factorisation::with_options(k, ordering, &opt)?;
        let total = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let x = f.solve(b)?;
        let solve = t.elapsed().as_secs_f64();
        let ax = linear_solve::mul(k, &x);
        let r = ax.iter().zip(b).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt()
            / b.iter().map(|v| v * v).sum::<f64>().sqrt();
        // Componentwise backward error max_i |r_i| / (|K||x| + |b|)_i.
        let mut den: Vec<f64> = b.iter().map(|v| v.abs()).collect();
        for (c, &xc) in x.iter().enumerate() {
            for q in k.col_ptr[c]..k.col_ptr[c + 1] {
                den[k.row_idx[q]] += k.values[q].abs() * xc.abs();
            }
        }
        let berr = ax
            .iter()
            .zip(b)
            .zip(&den)
            .map(|((a, b), d)| if a == b { 0.0 } else { (a - b).abs() / d })
            .fold(0.0f64, f64::max);
        let hash = x
            .iter()
            .fold(0xcbf2_9ce4_8422_2325u64, |h, v| (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3));
        let s = f.stats();
        println!(
            "{v:<28} total {total:7.3} s (order {:.3}, symbolic {:.3}, numeric {:.3}); nnz {} -> {}; \
             {} supernodes; bound nnz {:.1} M, flops {:.2e}; solve {solve:.3} s; residual {r:.1e}, backward error {berr:.1e}; \
             hash {hash:016x}; factor nnz {:.1} M ({:?}), {} perturbed pivots, {} refinement steps, \
             {} columns finished by GMRES-IR ({} iterations), worst refined backward error {:.1e}",
            s.ordering_seconds,
            s.symbolic_seconds,
            s.numeric_seconds,
            s.nnz,
            s.nnz_factorised,
            s.supernodes,
            s.bound_nnz as f64 * 1e-6,
            s.bound_flops,
            s.factor_nnz as f64 * 1e-6,
            s.precision,
            s.perturbed_pivots,
            s.refinement_steps,
            s.gmres_columns,
            s.gmres_iterations,
            s.worst_backward_error
        );
    }
    println!("peak resident memory (VmHWM) {:.0} MiB", peak_rss_mib().unwrap_or(f64::NAN));
    Ok(())
}
