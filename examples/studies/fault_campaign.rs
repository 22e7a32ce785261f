//! The opt-in fault campaign: at least 10⁵ seeded inputs against the problem-file front door,
//! the command line's `--out` handling and its signal handling, in parallel (rayon).
//!
//! ```text
//! cargo build --release
//! nice -n 19 cargo run --release --features studies --example fault_campaign -- [--seed 1]
//! ```
//!
//! Classes of input:
//! - `structural`: every number of every shipped problem file replaced by extreme and wrongly
//!   typed values, every line deleted and duplicated, seeded random byte edits;
//! - `scale`: every number scaled by 10^k (k = ±3 … ±15), replaced by 2^63 (as a float and as
//!   an integer literal), by subnormals, by its negative;
//! - `combined`: two or three of the above at once;
//! - `out-layout`: the command line run on a cheap problem into `--out` layouts (an earlier run
//!   with user files, a symlink to a directory or to a file, a file in the way, missing parents,
//!   read-only directories, a dangling link, the problem's own directory, stale staging
//!   directories); every file that is not the earlier run's must be intact (content hash) and
//!   nothing may appear outside `--out` (snapshot of the case's directory before and after);
//! - `killed`: a ~1 s run ended by SIGTERM or SIGKILL at a random time, then a rerun into the
//!   same `--out`: no staging directory may remain and the user's files must be intact;
//! - `python`: bad values through the Python package, when it is importable (skipped with a
//!   message otherwise).
//!
//! Every input of the first three classes is validated in-process (`ProblemFile::from_toml` →
//! `Problem::try_from`, panics caught). A sample of the accepted ones is solved through the
//! command line as a child process (so that an abort is seen), under an 8 GB address-space
//! limit and a time limit: per shipped file, `--solve-seconds` divided by the file's own run
//! time, evenly spaced over its accepted inputs. A solved input is classified by its exit
//! status, its `summary.json` (exit 0 must have `checks.passed`), its CSV outputs (finite) and
//! the files around `--out`. Failures are written, minimised by line deletion, to
//! `<scratch>/failures/`. Results: docs/dev/fault_campaign.md.

mod args;

#[path = "../../tests/support/mutations.rs"]
mod mutations;
use clap::Parser;
use mlpg_contact::problem::{Problem, ProblemError, ProblemFile};
use mlpg_contact::random::SplitMix64;
use mutations::{REPLACEMENTS, numbers};
use rayon::prelude::*;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(about = "Seeded fault campaign (≥ 10⁵ inputs) against the front door and --out")]
struct Cli {
    /// Seed of every random choice.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Random byte edits per shipped file (structural class).
    #[arg(long, default_value_t = 800)]
    byte_edits: usize,
    /// Combined mutations per shipped file.
    #[arg(long, default_value_t = 2000)]
    combined: usize,
    /// Seconds of solving per shipped file (divided by the file's own run time: the sample).
    #[arg(long, default_value_t = 5.0)]
    solve_seconds: f64,
    /// `--out` layout cases.
    #[arg(long, default_value_t = 240)]
    layouts: usize,
    /// Killed runs.
    #[arg(long, default_value_t = 30)]
    kills: usize,
    /// Only the classes out-layout, killed and python (no problem-file mutations).
    #[arg(long)]
    skip_files: bool,
    /// The command-line binary (default: target/release/mlpg-contact).
    #[arg(long)]
    bin: Option<PathBuf>,
    /// Scratch directory (default: target/fault-campaign); emptied first.
    #[arg(long)]
    scratch: Option<PathBuf>,
}

/// The class of an input.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Class {
    Structural,
    Scale,
    Combined,
    OutLayout,
    Killed,
    Python,
}

impl Class {
    const ALL: [Class; 6] = [
        Class::Structural,
        Class::Scale,
        Class::Combined,
        Class::OutLayout,
        Class::Killed,
        Class::Python,
    ];
    fn name(self) -> &'static str {
        match self {
            Class::Structural => "structural",
            Class::Scale => "scale",
            Class::Combined => "combined",
            Class::OutLayout => "out-layout",
            Class::Killed => "killed",
            Class::Python => "python",
        }
    }
}

/// What became of an input (or of its solved run).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Outcome {
    /// Validation accepted it.
    Accepted,
    /// Validation refused it with a typed error.
    Refused,
    /// The command line: exit 0, every check passed.
    RunOk,
    /// The command line: exit 2 (a typed refusal or failed stage).
    RunRefused,
    /// The command line: exit 3 (solved, a check failed and is flagged).
    RunFlagged,
    /// Killed at the time limit (not a failure: a mutated spacing can make a large problem).
    Timeout,
    /// A killed run ended before its signal (it finished).
    Finished,
    /// A killed run: the user's files intact, nothing left after the rerun.
    KilledClean,
    Panic,
    Abort,
    NonFinite,
    Exit0FailedCheck,
    FilesLost,
    FilesOutside,
    StagingLeft,
    /// A typed error without a message or an `Invalid` error without a key path.
    Unnamed,
    /// Any other exit status.
    OtherExit,
}

impl Outcome {
    const ALL: [Outcome; 17] = [
        Outcome::Accepted,
        Outcome::Refused,
        Outcome::RunOk,
        Outcome::RunRefused,
        Outcome::RunFlagged,
        Outcome::Timeout,
        Outcome::Finished,
        Outcome::KilledClean,
        Outcome::Panic,
        Outcome::Abort,
        Outcome::NonFinite,
        Outcome::Exit0FailedCheck,
        Outcome::FilesLost,
        Outcome::FilesOutside,
        Outcome::StagingLeft,
        Outcome::Unnamed,
        Outcome::OtherExit,
    ];
    fn is_failure(self) -> bool {
        self >= Outcome::Panic
    }
    fn name(self) -> &'static str {
        match self {
            Outcome::Accepted => "accepted",
            Outcome::Refused => "refused",
            Outcome::RunOk => "exit 0",
            Outcome::RunRefused => "exit 2",
            Outcome::RunFlagged => "exit 3",
            Outcome::Timeout => "timeout",
            Outcome::Finished => "done before signal",
            Outcome::KilledClean => "killed, clean",
            Outcome::Panic => "panic",
            Outcome::Abort => "abort",
            Outcome::NonFinite => "non-finite",
            Outcome::Exit0FailedCheck => "exit 0, check failed",
            Outcome::FilesLost => "files lost",
            Outcome::FilesOutside => "outside --out",
            Outcome::StagingLeft => "staging left",
            Outcome::Unnamed => "unnamed error",
            Outcome::OtherExit => "other exit",
        }
    }
}

/// Counts per class and outcome, and the failures' descriptions.
#[derive(Default)]
struct Tally {
    counts: BTreeMap<(Class, Outcome), usize>,
    inputs: BTreeMap<Class, usize>,
    failures: Vec<String>,
}

impl Tally {
    fn input(&mut self, class: Class) {
        *self.inputs.entry(class).or_default() += 1;
    }
    fn add(&mut self, class: Class, outcome: Outcome) {
        *self.counts.entry((class, outcome)).or_default() += 1;
    }
    fn merge(mut self, other: Tally) -> Tally {
        for (k, v) in other.counts {
            *self.counts.entry(k).or_default() += v;
        }
        for (k, v) in other.inputs {
            *self.inputs.entry(k).or_default() += v;
        }
        self.failures.extend(other.failures);
        self
    }
    fn print(&self) {
        let used: Vec<Outcome> = Outcome::ALL
            .into_iter()
            .filter(|&o| o.is_failure() || self.counts.keys().any(|&(_, k)| k == o))
            .collect();
        let mut header = format!("| {:<10} | {:>7} |", "class", "inputs");
        let mut rule = "|---|---:|".to_string();
        for o in &used {
            header += &format!(" {} |", o.name());
            rule += "---:|";
        }
        println!("{header}\n{rule}");
        for class in Class::ALL {
            let mut row = format!(
                "| {:<10} | {:>7} |",
                class.name(),
                self.inputs.get(&class).copied().unwrap_or(0)
            );
            for &o in &used {
                row += &format!(" {} |", self.counts.get(&(class, o)).copied().unwrap_or(0));
            }
            println!("{row}");
        }
    }
}

/// The out-of-scale values of the literal `lit`: ×10^k for k = ±3 … ±15 (an integer literal
/// stays an integer while it fits), 2^63 as a float and as an integer, two subnormals, −lit.
fn scaled(lit: &str) -> Vec<String> {
    let v: f64 = lit.replace('_', "").parse().unwrap_or(1.0);
    let integer = !lit.contains(['.', 'e', 'E']);
    let mut out = Vec::new();
    for k in (-15..=-3).chain(3..=15) {
        let s = v * 10f64.powi(k);
        if integer && k > 0 && s.abs() < 9.2e18 {
            out.push(format!("{}", s as i64));
        } else {
            out.push(format!("{s:e}"));
        }
    }
    out.push("9.223372036854775808e18".into());
    out.push("9223372036854775808".into());
    out.push("5e-324".into());
    out.push("2.5e-310".into());
    out.push(if let Some(rest) = lit.strip_prefix('-') { rest.into() } else { format!("-{lit}") });
    out
}

/// `text` with the number at `range` replaced by `by`.
fn replace(text: &str, (start, end): (usize, usize), by: &str) -> String {
    format!("{}{by}{}", &text[..start], &text[end..])
}

/// Seeded random byte edits (1 to 4: set, remove, insert).
fn byte_edit(rng: &mut SplitMix64, text: &str) -> String {
    let mut bytes = text.to_string().into_bytes();
    for _ in 0..1 + rng.next_u64() % 4 {
        if bytes.is_empty() {
            break;
        }
        let at = (rng.next_u64() % bytes.len() as u64) as usize;
        match rng.next_u64() % 3 {
            0 => bytes[at] = (rng.next_u64() % 128) as u8,
            1 => {
                bytes.remove(at);
            }
            _ => bytes.insert(at, b"0.-e[]{}=\",x9"[(rng.next_u64() % 13) as usize]),
        }
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// A line of `text` deleted or duplicated.
fn line_edit(text: &str, k: usize, duplicate: bool) -> String {
    let mut lines: Vec<&str> = text.lines().collect();
    if lines.is_empty() {
        return String::new();
    }
    let k = k % lines.len();
    if duplicate {
        lines.insert(k, lines[k]);
    } else {
        lines.remove(k);
    }
    lines.join("\n")
}

/// Two or three mutations at once: numbers replaced or scaled (from the last to the first, so
/// that the ranges stay valid), then possibly a line or byte edit.
fn combined(rng: &mut SplitMix64, text: &str, nums: &[(usize, usize)]) -> String {
    let count = 2 + (rng.next_u64() % 2) as usize;
    let mut picked: BTreeSet<usize> = BTreeSet::new();
    let edits = if nums.is_empty() { 0 } else { count - (rng.next_u64() % 2) as usize };
    while picked.len() < edits.min(nums.len()) {
        picked.insert((rng.next_u64() % nums.len() as u64) as usize);
    }
    let mut out = text.to_string();
    for &i in picked.iter().rev() {
        let (s, e) = nums[i];
        let by = if rng.next_u64() % 2 == 0 {
            REPLACEMENTS[(rng.next_u64() % REPLACEMENTS.len() as u64) as usize].to_string()
        } else {
            let all = scaled(&text[s..e]);
            all[(rng.next_u64() % all.len() as u64) as usize].clone()
        };
        out = replace(&out, (s, e), &by);
    }
    for _ in picked.len()..count {
        out = match rng.next_u64() % 3 {
            0 => byte_edit(rng, &out),
            r => line_edit(&out, rng.next_u64() as usize, r == 1),
        };
    }
    out
}

/// Every mutation of one shipped file, by class, in a fixed order.
fn mutants(cli: &Cli, file: usize, text: &str) -> Vec<(Class, String)> {
    let nums = numbers(text);
    let mut out = Vec::new();
    for &r in &nums {
        for by in REPLACEMENTS {
            out.push((Class::Structural, replace(text, r, by)));
        }
    }
    for k in 0..text.lines().count() {
        out.push((Class::Structural, line_edit(text, k, false)));
        out.push((Class::Structural, line_edit(text, k, true)));
    }
    let mut rng = SplitMix64::new(cli.seed ^ (0x9e37 * (file as u64 + 1)));
    for _ in 0..cli.byte_edits {
        out.push((Class::Structural, byte_edit(&mut rng, text)));
    }
    for &r in &nums {
        for by in scaled(&text[r.0..r.1]) {
            out.push((Class::Scale, replace(text, r, &by)));
        }
    }
    for _ in 0..cli.combined {
        out.push((Class::Combined, combined(&mut rng, text, &nums)));
    }
    out
}

/// Validates `text` in-process: accepted, refused with a named error, unnamed, or a panic.
fn validate(text: &str) -> Outcome {
    let result = std::panic::catch_unwind(|| {
        ProblemFile::from_toml(text).and_then(Problem::try_from).map(|_| ())
    });
    match result {
        Err(_) => Outcome::Panic,
        Ok(Ok(())) => Outcome::Accepted,
        Ok(Err(ProblemError::Invalid { field, reason, .. }))
            if field.is_empty() || reason.is_empty() =>
        {
            Outcome::Unnamed
        }
        Ok(Err(e)) if e.to_string().is_empty() => Outcome::Unnamed,
        Ok(Err(_)) => Outcome::Refused,
    }
}

/// Every file and link under `root` (not following links): relative path → content hash (a
/// link: its target), directories included as `dir`.
fn snapshot(root: &Path) -> BTreeMap<PathBuf, String> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, String>) {
        let Ok(entries) = std::fs::read_dir(dir) else { return };
        for e in entries.flatten() {
            let path = e.path();
            let rel = path.strip_prefix(root).unwrap().to_path_buf();
            let Ok(meta) = std::fs::symlink_metadata(&path) else { continue };
            if meta.file_type().is_symlink() {
                let target = std::fs::read_link(&path).unwrap_or_default();
                out.insert(rel, format!("link:{}", target.display()));
            } else if meta.is_dir() {
                out.insert(rel, "dir".into());
                walk(root, &path, out);
            } else {
                let bytes = std::fs::read(&path).unwrap_or_default();
                out.insert(rel, format!("{:016x}:{}", fnv(&bytes), bytes.len()));
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(root, root, &mut out);
    out
}

/// FNV-1a, 64 bits.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3))
}

/// The files a manifest in `dir` lists (relative to `dir`).
fn manifest(dir: &Path) -> BTreeSet<PathBuf> {
    std::fs::read_to_string(dir.join(".mlpg-contact-manifest"))
        .unwrap_or_default()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(PathBuf::from)
        .collect()
}

/// Compares snapshots of a case directory taken before and after a run whose outputs belong
/// in `out` (relative to the case directory, links resolved): files of an earlier run that
/// its manifest lists may change; every other entry must be intact, every new one must be
/// inside `out`, and no staging directory may remain.
fn compare(
    before: &BTreeMap<PathBuf, String>,
    after: &BTreeMap<PathBuf, String>,
    out: &Path,
    replaceable: &BTreeSet<PathBuf>,
) -> Vec<(Outcome, String)> {
    let mut found = Vec::new();
    for (path, was) in before {
        let owned = path.strip_prefix(out).is_ok_and(|rel| replaceable.contains(rel));
        let output_dir = path.starts_with(out) && was == "dir";
        if owned || output_dir || path.to_string_lossy().contains(".partial-") {
            continue;
        }
        if after.get(path) != Some(was) {
            found.push((Outcome::FilesLost, format!("{} changed or lost", path.display())));
        }
    }
    for path in after.keys() {
        if path.to_string_lossy().contains(".partial-") {
            found.push((Outcome::StagingLeft, format!("{} remains", path.display())));
        } else if !before.contains_key(path) && !path.starts_with(out) && !out.starts_with(path) {
            found.push((Outcome::FilesOutside, format!("{} written outside", path.display())));
        }
    }
    found
}

/// A finished child process: its status (None: killed at the time limit), stderr, seconds.
struct Ran {
    code: Option<i32>,
    signal: Option<i32>,
    timed_out: bool,
    stderr: String,
}

/// Runs the command line on `problem` into `out` (in `cwd`), with one thread, an 8 GB
/// address-space limit and a time limit.
fn run_cli(bin: &Path, cwd: &Path, problem: &Path, out: &str, limit: Duration) -> Ran {
    let child = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 8000000; exec \"$0\" \"$@\"")
        .arg(bin)
        .arg(problem)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .current_dir(cwd)
        .env("RAYON_NUM_THREADS", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sh");
    wait(child, limit)
}

/// Waits for `child` up to `limit`, then kills it (SIGKILL).
fn wait(mut child: std::process::Child, limit: Duration) -> Ran {
    use std::io::Read;
    use std::os::unix::process::ExitStatusExt;
    let mut stderr = child.stderr.take();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        if let Some(e) = stderr.as_mut() {
            let _ = e.read_to_string(&mut s);
        }
        s
    });
    let start = Instant::now();
    let mut timed_out = false;
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > limit {
            timed_out = true;
            let _ = child.kill();
            break child.wait().expect("wait");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let stderr = reader.join().unwrap_or_default();
    Ran { code: status.code(), signal: status.signal(), timed_out, stderr }
}

/// The outcome of a finished run from its status, `summary.json` and CSV outputs.
fn classify_run(ran: &Ran, out: &Path) -> (Outcome, String) {
    if ran.timed_out {
        return (Outcome::Timeout, String::new());
    }
    if ran.stderr.contains("panicked") || ran.code == Some(101) {
        return (Outcome::Panic, tail(&ran.stderr));
    }
    if let Some(s) = ran.signal {
        return (Outcome::Abort, format!("signal {s}: {}", tail(&ran.stderr)));
    }
    match ran.code {
        Some(2) => (Outcome::RunRefused, String::new()),
        Some(3) => (Outcome::RunFlagged, String::new()),
        Some(0) => {
            let summary: Option<serde_json::Value> =
                std::fs::read_to_string(out.join("summary.json"))
                    .ok()
                    .and_then(|s| serde_json::from_str(&s).ok());
            // A dynamics run's summary has no checks (nothing to fail); any other must pass.
            let passed = summary.as_ref().is_some_and(|s| {
                s.get("checks").is_none()
                    || s["checks"]["passed"] == serde_json::Value::Bool(true)
                        && s["checks"]["verdicts"]
                            .as_array()
                            .is_some_and(|v| v.iter().all(|x| x["pass"] == true))
            });
            if !passed {
                return (Outcome::Exit0FailedCheck, "summary.json: checks not all passed".into());
            }
            match non_finite(out) {
                Some(at) => (Outcome::NonFinite, at),
                None => (Outcome::RunOk, String::new()),
            }
        }
        c => (Outcome::OtherExit, format!("exit {c:?}: {}", tail(&ran.stderr))),
    }
}

/// The first CSV field under `dir` that parses as a non-finite number, or a `null` in
/// summary.json (how serde writes NaN).
fn non_finite(dir: &Path) -> Option<String> {
    for (rel, _) in snapshot(dir) {
        let path = dir.join(&rel);
        if rel.extension().is_some_and(|e| e == "csv") {
            let text = std::fs::read_to_string(&path).unwrap_or_default();
            for line in text.lines().skip(1) {
                if line.split(',').any(|f| f.trim().parse::<f64>().is_ok_and(|v| !v.is_finite())) {
                    return Some(format!("{}: {line}", rel.display()));
                }
            }
        }
    }
    None
}

fn tail(s: &str) -> String {
    let lines: Vec<&str> = s.lines().collect();
    lines[lines.len().saturating_sub(4)..].join(" / ")
}

/// Where things are.
struct Env {
    bin: PathBuf,
    scratch: PathBuf,
    problems: PathBuf,
    cheap: String,
}

/// A problem text solved through the command line in a fresh job directory (with the Gmsh
/// files it may name), checked for its outcome and the files around `--out`.
fn solve_job(env: &Env, name: &str, text: &str, limit: Duration) -> (Outcome, String) {
    let job = env.scratch.join("solve").join(name);
    let _ = std::fs::remove_dir_all(&job);
    std::fs::create_dir_all(&job).unwrap();
    std::fs::write(job.join("problem.toml"), text).unwrap();
    for msh in ["plate_with_hole_gmsh.msh"] {
        if text.contains(msh) {
            std::fs::copy(env.problems.join(msh), job.join(msh)).unwrap();
        }
    }
    let before = snapshot(&job);
    let ran = run_cli(&env.bin, &job, &job.join("problem.toml"), "out", limit);
    let mut result = classify_run(&ran, &job.join("out"));
    let mut problems = compare(&before, &snapshot(&job), Path::new("out"), &BTreeSet::new());
    if result.0 == Outcome::Timeout {
        // Killed by SIGKILL at the time limit: its staging directory is the next run's to
        // remove (class killed checks that).
        problems.retain(|(o, _)| *o != Outcome::StagingLeft);
    }
    if let Some((o, what)) = problems.into_iter().next() {
        if !result.0.is_failure() {
            result = (o, what);
        }
    }
    let _ = std::fs::remove_dir_all(&job);
    result
}

/// Minimises a failing `text` by deleting lines while `fails` holds (greedy, bounded).
fn minimise(text: &str, budget: usize, fails: impl Fn(&str) -> bool) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut tries = 0;
    let mut k = 0;
    while k < lines.len() && tries < budget {
        let mut shorter = lines.clone();
        shorter.remove(k);
        tries += 1;
        if fails(&shorter.join("\n")) {
            lines = shorter;
        } else {
            k += 1;
        }
    }
    lines.join("\n")
}

/// Records a failure of `text` (minimised) in `<scratch>/failures/` and in the tally.
fn record(env: &Env, tally: &mut Tally, label: &str, outcome: Outcome, what: &str, text: &str) {
    let dir = env.scratch.join("failures");
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join(format!("{label}.toml"));
    let header = format!("# {}: {}\n", outcome.name(), what.replace('\n', " "));
    let _ = std::fs::write(&path, format!("{header}{text}\n"));
    tally.failures.push(format!("{label}: {} ({what}) -> {}", outcome.name(), path.display()));
}

/// Classes structural, scale, combined of one shipped file: every mutant validated, the
/// sample solved.
fn mutate_file(cli: &Cli, env: &Env, file: usize, path: &Path, run_time: f64) -> Tally {
    let text = std::fs::read_to_string(path).unwrap();
    let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
    let mut tally = Tally::default();
    let mut accepted = Vec::new();
    let all = mutants(cli, file, &text);
    for (i, (class, m)) in all.iter().enumerate() {
        tally.input(*class);
        let outcome = validate(m);
        tally.add(*class, outcome);
        if outcome == Outcome::Accepted {
            accepted.push(i);
        } else if outcome.is_failure() {
            let min = minimise(m, 400, |t| validate(t) == outcome);
            record(env, &mut tally, &format!("{stem}-{i}"), outcome, "validation", &min);
        }
    }
    let wanted = ((cli.solve_seconds / run_time.max(0.02)) as usize).max(2).min(accepted.len());
    let limit = Duration::from_secs_f64((5.0 * run_time).max(5.0));
    for j in 0..wanted {
        let i = accepted[j * accepted.len() / wanted.max(1)];
        let (class, m) = &all[i];
        let (outcome, what) = solve_job(env, &format!("{stem}-{i}"), m, limit);
        tally.add(*class, outcome);
        if outcome.is_failure() {
            record(env, &mut tally, &format!("{stem}-{i}-full"), outcome, &what, m);
            tally.failures.pop();
            let min = minimise(m, 12, |t| {
                solve_job(env, &format!("{stem}-{i}-min"), t, limit).0 == outcome
            });
            record(env, &mut tally, &format!("{stem}-{i}"), outcome, &what, &min);
        }
    }
    eprintln!("{stem}: {} inputs, {} accepted, {wanted} solved", all.len(), accepted.len());
    tally
}

/// The `--out` layouts of class out-layout.
const LAYOUTS: [&str; 12] = [
    "earlier run with user files",
    "symlink to a directory",
    "symlink to a file",
    "a file where the directory should be",
    "nested missing parents",
    "read-only directory with an earlier run",
    "read-only parent",
    "dangling symlink",
    "the problem's own directory (.)",
    "a stale staging directory",
    "a user file named like an output",
    "symlink to a symlink to a directory with a user's directory",
];

/// Sets up layout `kind` in `case/` (the problem in `case/root/`): the `--out` argument
/// (relative to `case/root`) and where its outputs belong (relative to `case`).
fn set_up_layout(env: &Env, case: &Path, kind: usize, rng: &mut SplitMix64) -> (String, PathBuf) {
    let root = case.join("root");
    std::fs::create_dir_all(root.join("user/deep")).unwrap();
    std::fs::write(root.join("problem.toml"), &env.cheap).unwrap();
    std::fs::write(root.join("user/notes.txt"), format!("notes {}", rng.next_u64())).unwrap();
    std::fs::write(root.join("user/deep/data.bin"), rng.next_u64().to_le_bytes()).unwrap();
    let earlier = |dir: &Path| {
        let ran = run_cli(
            &env.bin,
            &root,
            &root.join("problem.toml"),
            dir.to_str().unwrap(),
            Duration::from_secs(60),
        );
        assert_eq!(ran.code, Some(0), "an earlier run failed: {}", ran.stderr);
    };
    let user_files = |dir: &Path, rng: &mut SplitMix64| {
        std::fs::create_dir_all(dir.join("mine")).unwrap();
        std::fs::write(dir.join("mine/keep.txt"), format!("{}", rng.next_u64())).unwrap();
        std::fs::write(dir.join("thesis.tex"), "mine").unwrap();
    };
    match kind {
        0 => {
            earlier(&root.join("out"));
            user_files(&root.join("out"), rng);
            ("out".into(), "root/out".into())
        }
        1 | 11 => {
            std::fs::create_dir(root.join("real")).unwrap();
            if rng.next_u64() % 2 == 0 {
                earlier(&root.join("real"));
            }
            if kind == 11 {
                std::fs::create_dir_all(root.join("real/mine")).unwrap();
                std::fs::write(root.join("real/mine/keep.txt"), "mine").unwrap();
                std::os::unix::fs::symlink("real", root.join("hop")).unwrap();
                std::os::unix::fs::symlink("hop", root.join("out")).unwrap();
            } else {
                std::os::unix::fs::symlink("real", root.join("out")).unwrap();
            }
            ("out".into(), "root/real".into())
        }
        2 => {
            std::os::unix::fs::symlink("user/notes.txt", root.join("out")).unwrap();
            ("out".into(), "root/out".into())
        }
        3 => {
            std::fs::write(root.join("out"), "a file").unwrap();
            ("out".into(), "root/out".into())
        }
        4 => ("a/b/c/out".into(), "root/a/b/c/out".into()),
        5 | 6 => {
            use std::os::unix::fs::PermissionsExt;
            let dir = if kind == 5 { root.join("out") } else { root.join("ro") };
            std::fs::create_dir(&dir).unwrap();
            if kind == 5 {
                earlier(&dir);
            }
            std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o555)).unwrap();
            if kind == 5 {
                ("out".into(), "root/out".into())
            } else {
                ("ro/out".into(), "root/ro/out".into())
            }
        }
        7 => {
            std::os::unix::fs::symlink("nowhere", root.join("out")).unwrap();
            ("out".into(), "root/out".into())
        }
        8 => (".".into(), "root".into()),
        9 => {
            earlier(&root.join("out"));
            let stale = root.join(".out.partial-999999");
            std::fs::create_dir_all(stale.join("plots")).unwrap();
            std::fs::write(stale.join("plots/deformed.svg"), "stale").unwrap();
            ("out".into(), "root/out".into())
        }
        _ => {
            std::fs::create_dir(root.join("out")).unwrap();
            std::fs::write(root.join("out/summary.json"), "{\"mine\": true}").unwrap();
            ("out".into(), "root/out".into())
        }
    }
}

/// One `--out` layout case through the command line.
fn layout_case(env: &Env, seed: u64, i: usize) -> Tally {
    let mut tally = Tally::default();
    let mut rng = SplitMix64::new(seed ^ (0x51ed * (i as u64 + 1)));
    let kind = i % LAYOUTS.len();
    let case = env.scratch.join("layouts").join(i.to_string());
    let (out, belongs) = set_up_layout(env, &case, kind, &mut rng);
    let mut replaceable = manifest(&case.join(&belongs));
    if !replaceable.is_empty() {
        replaceable.insert(PathBuf::from(".mlpg-contact-manifest"));
    }
    let before = snapshot(&case);
    let root = case.join("root");
    let ran = run_cli(&env.bin, &root, &root.join("problem.toml"), &out, Duration::from_secs(60));
    let after = snapshot(&case);
    tally.input(Class::OutLayout);
    let (mut outcome, mut what) = classify_run(&ran, &case.join(&belongs));
    // The stale staging directory (a dead pid) is the one entry a run may remove.
    let found = compare(&before, &after, &belongs, &replaceable);
    if let Some((o, w)) = found.into_iter().next() {
        if !outcome.is_failure() {
            (outcome, what) = (o, w);
        }
    }
    tally.add(Class::OutLayout, outcome);
    if outcome.is_failure() {
        tally.failures.push(format!("layout {i} ({}): {} {what}", LAYOUTS[kind], outcome.name()));
    }
    restore_permissions(&case);
    let _ = std::fs::remove_dir_all(&case);
    tally
}

fn restore_permissions(dir: &Path) {
    use std::os::unix::fs::PermissionsExt;
    for (rel, kind) in snapshot(dir) {
        if kind == "dir" {
            let _ = std::fs::set_permissions(dir.join(rel), std::fs::Permissions::from_mode(0o755));
        }
    }
}

/// One killed run: `problem` (about a second) into an `--out` holding an earlier run and user
/// files, SIGTERM or SIGKILL at a random time, then a rerun of the cheap problem.
fn kill_case(env: &Env, seed: u64, i: usize, problem: &Path, run_time: f64) -> Tally {
    let mut tally = Tally::default();
    let mut rng = SplitMix64::new(seed ^ (0x4b1 * (i as u64 + 1)));
    let case = env.scratch.join("kills").join(i.to_string());
    let _ = std::fs::remove_dir_all(&case);
    std::fs::create_dir_all(&case).unwrap();
    std::fs::write(case.join("cheap.toml"), &env.cheap).unwrap();
    std::fs::write(case.join("notes.txt"), format!("{}", rng.next_u64())).unwrap();
    let cheap = case.join("cheap.toml");
    let first = run_cli(&env.bin, &case, &cheap, "out", Duration::from_secs(60));
    assert_eq!(first.code, Some(0), "{}", first.stderr);
    std::fs::write(case.join("out/mine.txt"), "mine").unwrap();
    let mut replaceable = manifest(&case.join("out"));
    replaceable.insert(PathBuf::from(".mlpg-contact-manifest"));
    let before = snapshot(&case);
    let child = Command::new(&env.bin)
        .arg(problem)
        .args(["--out", "out", "--quiet"])
        .current_dir(&case)
        .env("RAYON_NUM_THREADS", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid = child.id();
    let delay = rng.uniform() * 1.1 * run_time;
    let signal = if rng.next_u64() % 2 == 0 { "-TERM" } else { "-KILL" };
    std::thread::sleep(Duration::from_secs_f64(delay));
    let _ = Command::new("kill").arg(signal).arg(pid.to_string()).status();
    let ran = wait(child, Duration::from_secs(120));
    tally.input(Class::Killed);
    let mut outcome = if ran.code == Some(0) { Outcome::Finished } else { Outcome::KilledClean };
    let mut what = format!("{signal} after {delay:.2} s");
    // After the kill: the user's files intact (staging directories are the rerun's to remove).
    let mut found = compare(&before, &snapshot(&case), Path::new("out"), &replaceable);
    found.retain(|(o, _)| *o != Outcome::StagingLeft);
    let rerun = run_cli(&env.bin, &case, &cheap, "out", Duration::from_secs(60));
    if rerun.code != Some(0) {
        found.push((
            Outcome::OtherExit,
            format!("rerun exit {:?}: {}", rerun.code, tail(&rerun.stderr)),
        ));
    }
    found.extend(compare(&before, &snapshot(&case), Path::new("out"), &replaceable));
    if let Some((o, w)) = found.into_iter().next() {
        outcome = o;
        what = format!("{what}: {w}");
    }
    tally.add(Class::Killed, outcome);
    if outcome.is_failure() {
        tally.failures.push(format!("kill {i}: {} ({what})", outcome.name()));
    }
    let _ = std::fs::remove_dir_all(&case);
    tally
}

/// Class python: `scripts/python-fault-campaign.py` (malformed `mc.solve` dicts, numpy values,
/// keys and sweep grids, in worker processes that count an abort), with the interpreter
/// `MLPG_PYTHON` names (default `python3`); skipped with a message when `import mlpg_contact`
/// fails there. Its table is printed as it comes; its last line gives the counts: inputs,
/// results, `ProblemError`, `SolveError`, failures (any other exception, an unnamed key, a
/// numpy value not solving like its number, an abort).
fn python_class(seed: u64) -> Tally {
    let mut tally = Tally::default();
    let python = std::env::var("MLPG_PYTHON").unwrap_or_else(|_| "python3".into());
    let importable = Command::new(&python)
        .args(["-c", "import mlpg_contact, numpy"])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !importable {
        println!(
            "python: skipped (`import mlpg_contact` fails with {python}: build the wheel with maturin, set MLPG_PYTHON)"
        );
        return tally;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/python-fault-campaign.py");
    let output = Command::new(&python)
        .arg(script)
        .args(["--seed", &seed.to_string()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    println!("{text}");
    let n: Vec<usize> = text
        .lines()
        .rev()
        .find_map(|l| l.strip_prefix("SUMMARY "))
        .map(|l| l.split_whitespace().filter_map(|w| w.parse().ok()).collect())
        .unwrap_or_default();
    use std::os::unix::process::ExitStatusExt;
    if output.status.signal().is_some() || n.len() != 5 {
        tally.input(Class::Python);
        tally.add(Class::Python, Outcome::Abort);
        tally.failures.push(format!("python: {}", tail(&String::from_utf8_lossy(&output.stderr))));
        return tally;
    }
    // SolveError (a valid input the run could not solve) counts as a refusal with a message.
    let counts =
        [(n[1], Outcome::RunOk), (n[2] + n[3], Outcome::Refused), (n[4], Outcome::OtherExit)];
    for (count, outcome) in counts {
        for _ in 0..count {
            tally.input(Class::Python);
            tally.add(Class::Python, outcome);
        }
    }
    if n[4] > 0 {
        tally.failures.push(format!("python: {} failures (its table above)", n[4]));
    }
    tally
}

/// The seconds one run of `problem` takes through the command line (it must pass).
fn run_time(env: &Env, problem: &Path) -> f64 {
    let job = env.scratch.join("baseline").join(problem.file_stem().unwrap());
    std::fs::create_dir_all(&job).unwrap();
    let start = Instant::now();
    let ran = run_cli(&env.bin, &job, problem, "out", Duration::from_secs(300));
    assert_eq!(ran.code, Some(0), "{}: {}", problem.display(), ran.stderr);
    start.elapsed().as_secs_f64()
}

fn main() {
    let cli = args::parse::<Cli>(&[]);
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scratch = cli.scratch.clone().unwrap_or_else(|| root.join("target/fault-campaign"));
    let _ = std::fs::remove_dir_all(&scratch);
    std::fs::create_dir_all(&scratch).unwrap();
    let env = Env {
        bin: cli.bin.clone().unwrap_or_else(|| root.join("target/release/mlpg-contact")),
        scratch: scratch.canonicalize().unwrap(),
        problems: root.join("problems"),
        cheap: std::fs::read_to_string(root.join("tests/data/fault-repro/r_ok.toml")).unwrap(),
    };
    assert!(env.bin.exists(), "{} is missing: cargo build --release", env.bin.display());
    let start = Instant::now();
    let mut files: Vec<PathBuf> =
        std::fs::read_dir(&env.problems).unwrap().flatten().map(|e| e.path()).collect();
    files.retain(|p| p.extension().is_some_and(|x| x == "toml"));
    files.sort();
    if cli.skip_files {
        files.clear();
    }
    let times: Vec<f64> = files.par_iter().map(|p| run_time(&env, p)).collect();
    eprintln!("baseline runs: {:.1} s", start.elapsed().as_secs_f64());
    // Quiet the default message of caught panics; they are counted and written out.
    std::panic::set_hook(Box::new(|_| {}));
    let mut order: Vec<usize> = (0..files.len()).collect();
    order.sort_by(|&a, &b| times[b].total_cmp(&times[a]));
    let mutated = order
        .par_iter()
        .map(|&k| mutate_file(&cli, &env, k, &files[k], times[k]))
        .reduce(Tally::default, Tally::merge);
    let _ = std::panic::take_hook();
    let t_mutated = start.elapsed().as_secs_f64();
    let layouts = (0..cli.layouts)
        .into_par_iter()
        .map(|i| layout_case(&env, cli.seed, i))
        .reduce(Tally::default, Tally::merge);
    let kill_problem = env.problems.join("beam_on_foundation.toml");
    // Its run time two at a time, as the kills run (their signals fall in 0 … 1.1 times it).
    let kill_time =
        [0, 1].into_par_iter().map(|_| run_time(&env, &kill_problem)).sum::<f64>() / 2.0;
    let kills = (0..cli.kills)
        .into_par_iter()
        .map(|i| kill_case(&env, cli.seed, i, &kill_problem, kill_time))
        .reduce(Tally::default, Tally::merge);
    let tally = mutated.merge(layouts).merge(kills).merge(python_class(cli.seed));
    let total: usize = tally.inputs.values().sum();
    println!(
        "\nfault campaign, seed {}: {total} inputs in {:.0} s ({:.0} s for the problem-file classes)\n",
        cli.seed,
        start.elapsed().as_secs_f64(),
        t_mutated
    );
    tally.print();
    println!("\nlayouts: {}", LAYOUTS.join("; "));
    println!("\n{} failures", tally.failures.len());
    for f in &tally.failures {
        println!("- {f}");
    }
    if !tally.failures.is_empty() {
        std::process::exit(1);
    }
}
