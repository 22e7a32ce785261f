//! `mlpg-contact <problem.toml> --out <dir> [--compare]`: solve a problem file (or compare
//! both methods on it) and write the outputs; `mlpg-contact schema`: print the problem file's
//! JSON Schema.
use anyhow::Context;
use clap::Parser;
use mlpg_contact::problem;
use std::io::Write as _;
use std::{path::PathBuf, process::ExitCode};

/// Meshless mixed MLPG finite volume (or finite element) solver for 2-D elastostatics and
/// contact: rigid obstacles or several bodies, Coulomb friction, load steps; Lemke's method or
/// a sparse active-set contact solver.
#[derive(Parser)]
#[command(
    version,
    about,
    after_help = EXIT_STATUS,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
struct Args {
    /// Other commands than solving.
    #[command(subcommand)]
    command: Option<Command>,
    /// Problem file (TOML); see problems/ for annotated examples.
    #[arg(required = true)]
    problem: Option<PathBuf>,
    /// Output directory (created if missing).
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// No progress on stderr.
    #[arg(long)]
    quiet: bool,
    /// Solve with both methods (MFVM and FE) and write a side-by-side table and overlay plots.
    #[arg(long)]
    compare: bool,
    /// Also write report.html: one self-contained page with the problem, results and plots.
    #[arg(long, conflicts_with = "compare")]
    report: bool,
}

/// Commands other than solving a problem file.
#[derive(clap::Subcommand)]
enum Command {
    /// Print the JSON Schema of the problem file (for editors: a `#:schema <file>` comment).
    Schema,
}

/// The exit statuses, as `--help` lists them.
const EXIT_STATUS: &str = "Exit status:
  0  solved; every check passed (residual, equilibrium, complementarity)
  2  refused or failed (invalid input, a failed stage); nothing is written
  3  solved and written, but a check failed: the message names it, its value and tolerance,
     and summary.json says `checks.passed = false` (`checks.verdicts` lists every check)";

/// The status of a run that was solved and written but whose checks failed.
const CHECK_FAILED: u8 = 3;

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

/// Longest value printed under a run-time error, in characters.
const VALUE_WIDTH: usize = 100;

/// The values a problem file gives to `keys` (comma-separated paths such as
/// `boundary[*].displacement` or `material`, as [`mlpg_contact::Error::input_keys`] names them),
/// as `path = value` lines, looked up at the top level and else in every `[[body]]` table; keys
/// the file leaves at their defaults (or free text) give none.
fn key_values(echo: &serde_json::Value, keys: &str) -> Vec<String> {
    fn walk(v: &serde_json::Value, path: String, rest: &[&str], out: &mut Vec<String>) {
        let Some((first, rest)) = rest.split_first() else {
            if !v.is_null() {
                let mut text = v.to_string();
                if text.chars().count() > VALUE_WIDTH {
                    text = text.chars().take(VALUE_WIDTH).collect::<String>() + "…";
                }
                out.push(format!("{path} = {text}"));
            }
            return;
        };
        let join =
            |name: &str| if path.is_empty() { name.to_string() } else { format!("{path}.{name}") };
        match first.strip_suffix("[*]") {
            Some(name) => {
                if let Some(list) = v.get(name).and_then(|l| l.as_array()) {
                    for (k, item) in list.iter().enumerate() {
                        walk(item, format!("{}[{k}]", join(name)), rest, out);
                    }
                }
            }
            None => {
                if let Some(next) = v.get(*first) {
                    walk(next, join(first), rest, out);
                }
            }
        }
    }
    let mut out = Vec::new();
    for key in keys.split(',').map(str::trim) {
        let parts: Vec<&str> = key.split('.').collect();
        if parts.iter().all(|p| !p.is_empty() && !p.contains(' ')) {
            let found = out.len();
            walk(echo, String::new(), &parts, &mut out);
            if out.len() == found {
                // With `[[body]]` tables a body's keys live under `body[k]`.
                walk(echo, String::new(), &[&["body[*]"], &parts[..]].concat(), &mut out);
            }
        }
    }
    out
}

/// How a run that reached its outputs ended: every check passed, or these failed (each
/// `(where, verdict)`, `where` the summary that holds it).
enum Finished {
    Passed,
    ChecksFailed(Vec<(String, mlpg_contact::post::summary::Verdict)>),
}

/// The failed checks of the summaries `(file, failed checks)` of a run.
fn finished<'a>(
    summaries: impl IntoIterator<Item = (String, Vec<&'a mlpg_contact::post::summary::Verdict>)>,
) -> Finished {
    let failed: Vec<_> = summaries
        .into_iter()
        .flat_map(|(file, failed)| failed.into_iter().map(move |v| (file.clone(), v.clone())))
        .collect();
    if failed.is_empty() { Finished::Passed } else { Finished::ChecksFailed(failed) }
}

fn run(args: &Args, echo: &mut Option<serde_json::Value>) -> anyhow::Result<Finished> {
    if let Some(Command::Schema) = args.command {
        writeln!(std::io::stdout().lock(), "{:#}", problem::schema::problem_file())
            .context("cannot write the schema to stdout")?;
        return Ok(Finished::Passed);
    }
    let path = args.problem.as_deref().context("a problem file is required")?;
    thread_pool()?;
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let file =
        problem::ProblemFile::from_toml(&text).with_context(|| format!("in {}", path.display()))?;
    let echo = echo.insert(serde_json::to_value(&file)?).clone();
    let mut file = file;
    file.resolve_paths(path.parent().unwrap_or(std::path::Path::new("")));
    let problem =
        problem::Problem::try_from(file).with_context(|| format!("in {}", path.display()))?;
    let mut progress = mlpg_contact::progress::StageProgress::new(args.quiet);
    if problem.dynamics.is_some() {
        anyhow::ensure!(
            !args.compare && !args.report,
            "--compare and --report are not available for a [dynamics] problem yet"
        );
        let report =
            mlpg_contact::pipeline::dynamics::run(&problem, &args.out, echo, &mut progress)?;
        for w in &report.summary.warnings {
            say(format_args!("warning: {w}"));
        }
        if !args.quiet {
            say(format_args!("{report}"));
        }
        let file = args.out.join("summary.json").display().to_string();
        return Ok(finished([(file, report.summary.failed_checks())]));
    }
    if args.compare {
        let comparison = mlpg_contact::compare::compare(&problem, &args.out, echo, &mut progress)?;
        if !args.quiet {
            say(format_args!("{comparison}"));
        }
        let out = &args.out;
        return Ok(finished([
            (
                out.join("mfvm/summary.json").display().to_string(),
                comparison.mfvm.summary.failed_checks(),
            ),
            (
                out.join("fem/summary.json").display().to_string(),
                comparison.fem.summary.failed_checks(),
            ),
        ]));
    }
    let report = mlpg_contact::pipeline::run_with_report(
        &problem,
        &args.out,
        echo,
        &mut progress,
        args.report,
    )?;
    for w in &report.summary.warnings {
        say(format_args!("warning: {w}"));
    }
    if !args.quiet {
        say(format_args!("{report}"));
    }
    let file = args.out.join("summary.json").display().to_string();
    Ok(finished([(file, report.summary.failed_checks())]))
}

/// On SIGINT, SIGTERM or SIGHUP: removes the staging directory of the run under way (the
/// output directory keeps the earlier run), then ends by the same signal. A thread waits for
/// the signals (signal-hook's self-pipe), so the removal runs outside the signal handler.
/// A signal the process was started ignoring (SIGHUP under `nohup`, SIGINT in a shell's
/// background job) stays ignored: the ignored set is read from `/proc/self/status`, and where
/// that cannot be read only SIGTERM is taken.
fn end_cleanly_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let ignored = std::fs::read_to_string("/proc/self/status").ok().and_then(|status| {
        let mask = status.lines().find_map(|l| l.strip_prefix("SigIgn:"))?;
        u64::from_str_radix(mask.trim(), 16).ok()
    });
    let wanted: Vec<i32> = match ignored {
        Some(mask) => {
            [SIGINT, SIGTERM, SIGHUP].into_iter().filter(|&s| mask & (1 << (s - 1)) == 0).collect()
        }
        None => vec![SIGTERM],
    };
    let Ok(mut signals) = signal_hook::iterator::Signals::new(wanted) else {
        return; // the run goes on; a staging directory left by a signal is removed next time
    };
    let spawned = std::thread::Builder::new().name("signals".into()).spawn(move || {
        if let Some(signal) = signals.forever().next() {
            mlpg_contact::post::abandon_staging();
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            std::process::exit(128 + signal);
        }
    });
    drop(spawned);
}

fn main() -> ExitCode {
    let args = Args::parse();
    end_cleanly_on_signals();
    let mut echo = None;
    match run(&args, &mut echo) {
        Ok(Finished::Passed) => ExitCode::SUCCESS,
        Ok(Finished::ChecksFailed(failed)) => {
            say(format_args!(
                "error: the problem was solved and its outputs written, but {} of its checks failed; the result is not reliable:",
                failed.len()
            ));
            for (file, v) in &failed {
                say(format_args!("  {v} (in {file}): {}", v.remedy()));
            }
            ExitCode::from(CHECK_FAILED)
        }
        Err(e) => {
            say(format_args!("error: {e:#}"));
            if let Some(keys) = e.downcast_ref::<mlpg_contact::Error>().and_then(|e| e.input_keys())
            {
                say(format_args!("  (decided by: {keys})"));
                for line in echo.as_ref().map(|v| key_values(v, keys)).unwrap_or_default() {
                    say(format_args!("    {line}"));
                }
            }
            ExitCode::from(2)
        }
    }
}
