//! `mlpg-contact <problem.toml> --out <dir> [--compare]`: solve a problem file (or compare
//! both methods on it) and write the outputs.
use anyhow::Context;
use clap::Parser;
use mlpg_contact::problem;
use std::{path::PathBuf, process::ExitCode};

/// Meshless mixed MLPG finite volume solver for 2-D elastostatics and frictionless contact.
#[derive(Parser)]
#[command(version, about)]
struct Args {
    /// Problem file (TOML); see problems/ for annotated examples.
    problem: PathBuf,
    /// Output directory (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// No progress on stderr.
    #[arg(long)]
    quiet: bool,
    /// Solve with both methods (MFVM and FE) and write a side-by-side table and overlay plots.
    #[arg(long)]
    compare: bool,
}

fn run(args: &Args) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(&args.problem)
        .with_context(|| format!("cannot read {}", args.problem.display()))?;
    let file = problem::ProblemFile::from_toml(&text)
        .with_context(|| format!("in {}", args.problem.display()))?;
    let echo = serde_json::to_value(&file)?;
    let problem = problem::Problem::try_from(file)
        .with_context(|| format!("in {}", args.problem.display()))?;
    let mut progress = mlpg_contact::progress::StageProgress::new(args.quiet);
    if args.compare {
        let comparison = mlpg_contact::compare::compare(&problem, &args.out, echo, &mut progress)?;
        if !args.quiet {
            eprintln!("{comparison}");
        }
        return Ok(());
    }
    let report = mlpg_contact::run(&problem, &args.out, echo, &mut progress)?;
    for w in &report.summary.warnings {
        eprintln!("warning: {w}");
    }
    if !args.quiet {
        eprintln!("{report}");
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
