//! `mlpg-contact <problem.toml> --out <dir> [--compare]`: solve a problem file (or compare
//! both methods on it) and write the outputs.
use anyhow::Context;
use clap::Parser;
use mlpg_contact::problem;
use std::io::Write as _;
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

/// Writes a line to stderr; a failing stderr (closed pipe, full disk) never decides the run.
fn say(line: std::fmt::Arguments<'_>) {
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// Most worker threads accepted from `RAYON_NUM_THREADS`, per core.
const THREADS_PER_CORE: usize = 4;

/// Builds the global thread pool: `RAYON_NUM_THREADS` as given, capped at
/// [`THREADS_PER_CORE`] per core (a warning says so), and a failure to start the threads is an
/// error instead of a panic later.
fn thread_pool() -> anyhow::Result<()> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let cap = THREADS_PER_CORE * cores;
    let requested = std::env::var("RAYON_NUM_THREADS").ok().and_then(|v| v.trim().parse().ok());
    let threads = match requested {
        Some(n) if n > cap => {
            say(format_args!(
                "warning: RAYON_NUM_THREADS = {n} capped at {cap} ({THREADS_PER_CORE} per core)"
            ));
            cap
        }
        Some(n) => n,
        None => 0, // rayon's default: one per core
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .with_context(|| format!("cannot start {threads} worker threads (RAYON_NUM_THREADS)"))
}

fn run(args: &Args) -> anyhow::Result<()> {
    thread_pool()?;
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
            say(format_args!("{comparison}"));
        }
        return Ok(());
    }
    let report = mlpg_contact::run(&problem, &args.out, echo, &mut progress)?;
    for w in &report.summary.warnings {
        say(format_args!("warning: {w}"));
    }
    if !args.quiet {
        say(format_args!("{report}"));
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            say(format_args!("error: {e:#}"));
            if let Some(keys) = e.downcast_ref::<mlpg_contact::Error>().and_then(|e| e.input_keys())
            {
                say(format_args!("  (decided by: {keys})"));
            }
            ExitCode::from(2)
        }
    }
}
