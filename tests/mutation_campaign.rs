//! A seeded mutation campaign on the problem-file front door: every shipped problem file is
//! mutated (each number replaced by extreme and wrongly typed values, each line deleted and
//! duplicated, seeded random byte edits) and fed to `ProblemFile::from_toml` →
//! `Problem::try_from`. Every input must end in `Ok` or in a typed error with a message (an
//! `Invalid` error names a key path); none may panic. The count of inputs is printed
//! (`cargo test --release --test mutation_campaign -- --nocapture`).

use mlpg_contact::problem::{Problem, ProblemError, ProblemFile};
use mlpg_contact::random::SplitMix64;
use std::path::Path;

#[path = "support/mutations.rs"]
mod mutations;
use mutations::{REPLACEMENTS, numbers};

/// Validates `text`; panics are caught and returned as `Err` with the input.
fn check(text: &str) -> Result<(), String> {
    let outcome = std::panic::catch_unwind(|| {
        ProblemFile::from_toml(text).and_then(Problem::try_from).map(|_| ())
    });
    match outcome {
        Err(_) => Err(format!("panic on input:\n{text}")),
        Ok(Ok(())) => Ok(()),
        Ok(Err(ProblemError::Invalid { field, reason, .. })) => {
            if field.is_empty() || reason.is_empty() {
                Err(format!("an Invalid error without field or reason on input:\n{text}"))
            } else {
                Ok(())
            }
        }
        Ok(Err(e)) => {
            if e.to_string().is_empty() {
                Err(format!("an empty message on input:\n{text}"))
            } else {
                Ok(())
            }
        }
    }
}

/// Accepted inputs solved per file, spread evenly over its mutations (see [`Tally::solve`]).
const SOLVES_PER_FILE: usize = 4;

/// What the campaign saw of one file's mutations.
#[derive(Default)]
struct Tally {
    inputs: usize,
    /// The inputs validation accepted, in the order they were made.
    accepted: Vec<String>,
    solved: usize,
    failures: Vec<String>,
}

impl Tally {
    /// Validates `text` (a panic or an unnamed error fails) and keeps it if accepted.
    fn run(&mut self, text: &str) {
        self.inputs += 1;
        match check(text) {
            Err(e) => self.failures.push(e),
            Ok(()) => {
                if ProblemFile::from_toml(text).and_then(Problem::try_from).is_ok() {
                    self.accepted.push(text.to_string());
                }
            }
        }
    }

    /// Solves [`SOLVES_PER_FILE`] of the accepted inputs, one from the middle of each of as
    /// many equal runs of them (so every kind of mutation of the file, from its first keys to
    /// the random byte edits, has its turn): each must end in a finite solution or a typed
    /// error, never in a panic. Most of the campaign's time is these solves (a mutated input
    /// costs about as much as the shipped file): every 25th accepted input (259 solves) took
    /// two of the CI's minutes; four per file (128) reach every file and every kind of
    /// mutation at half the cost.
    fn solve(&mut self) {
        let n = self.accepted.len();
        let k = SOLVES_PER_FILE.min(n);
        for j in 0..k {
            let text = &self.accepted[(2 * j + 1) * n / (2 * k)];
            let problem = ProblemFile::from_toml(text).and_then(Problem::try_from).unwrap();
            self.solved += 1;
            match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                mlpg_contact::solve(&problem)
            })) {
                Err(_) => self.failures.push(format!("panic solving:\n{text}")),
                Ok(Ok(s)) if s.first_non_finite().is_some() => {
                    self.failures.push(format!("a non-finite solution of:\n{text}"))
                }
                Ok(_) => {}
            }
        }
    }
}

/// The mutations of one shipped file (`seed` seeds its random byte edits).
fn mutate(seed: u64, text: &str) -> Tally {
    let mut tally = Tally::default();
    for (start, end) in numbers(text) {
        for r in REPLACEMENTS {
            tally.run(&format!("{}{r}{}", &text[..start], &text[end..]));
        }
    }
    let lines: Vec<&str> = text.lines().collect();
    for k in 0..lines.len() {
        let mut deleted = lines.clone();
        deleted.remove(k);
        tally.run(&deleted.join("\n"));
        let mut duplicated = lines.clone();
        duplicated.insert(k, lines[k]);
        tally.run(&duplicated.join("\n"));
    }
    let mut rng = SplitMix64::new(seed);
    for _ in 0..300 {
        let mut bytes = text.to_string().into_bytes();
        for _ in 0..1 + rng.next_u64() % 4 {
            let at = (rng.next_u64() % bytes.len() as u64) as usize;
            match rng.next_u64() % 3 {
                0 => bytes[at] = (rng.next_u64() % 128) as u8,
                1 => {
                    bytes.remove(at);
                }
                _ => bytes.insert(at, b"0.-e[]{}=\",x9"[(rng.next_u64() % 13) as usize]),
            }
        }
        tally.run(&String::from_utf8_lossy(&bytes));
    }
    tally.solve();
    tally
}

/// The files are mutated in parallel (rayon), one [`Tally`] each: the campaign is the
/// longest single test, and its files are independent.
#[test]
fn no_mutated_problem_file_panics() {
    use rayon::prelude::*;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.path()).collect();
    files.sort();
    files.retain(|p| p.extension().is_some_and(|x| x == "toml"));
    // Quiet the default panic message of caught panics; failures are reported below.
    std::panic::set_hook(Box::new(|_| {}));
    let tallies: Vec<Tally> = files
        .par_iter()
        .enumerate()
        .map(|(seed, path)| mutate(seed as u64 + 1, &std::fs::read_to_string(path).unwrap()))
        .collect();
    let _ = std::panic::take_hook();
    let inputs: usize = tallies.iter().map(|t| t.inputs).sum();
    let accepted: usize = tallies.iter().map(|t| t.accepted.len()).sum();
    let solved: usize = tallies.iter().map(|t| t.solved).sum();
    let failures: Vec<&String> = tallies.iter().flat_map(|t| &t.failures).collect();
    println!(
        "mutation campaign: {inputs} inputs, {accepted} accepted, {solved} of those solved, {} failures",
        failures.len()
    );
    assert!(inputs > 2000, "the campaign ran only {inputs} inputs");
    assert!(
        solved >= SOLVES_PER_FILE * files.len() / 2,
        "only {solved} accepted inputs solved over {} files",
        files.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {inputs} inputs failed:\n{}",
        failures.len(),
        failures[..failures.len().min(3)]
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n---\n")
    );
}

/// The out-of-scale values of a number literal `lit`: scaled by 10^k (k = ±3, ±9, ±15), 2^63
/// as a float and as an integer literal, a subnormal, its negative.
fn out_of_scale(lit: &str) -> Vec<String> {
    let v: f64 = lit.replace('_', "").parse().unwrap_or(1.0);
    let mut out: Vec<String> =
        [-15, -9, -3, 3, 9, 15].into_iter().map(|k| format!("{:e}", v * 10f64.powi(k))).collect();
    out.push("9.223372036854775808e18".into());
    out.push("9223372036854775808".into());
    out.push("5e-324".into());
    out.push(lit.strip_prefix('-').map_or_else(|| format!("-{lit}"), String::from));
    out
}

/// The out-of-scale class of the opt-in campaign (`examples/studies/fault_campaign.rs`) on the
/// cheapest shipped problems, in a few seconds: every number out of scale, and seeded pairs of
/// such values at once. Each input is validated (a panic or an unnamed error fails); every
/// third accepted one of up to 2 000 nodes is solved and must end in a typed error or a finite
/// solution.
#[test]
fn no_out_of_scale_value_panics() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let files = ["two_blocks.toml", "three_block_stack.toml", "block_on_flat_held_by_contact.toml"];
    let mut rng = SplitMix64::new(7);
    let (mut inputs, mut accepted, mut solved, mut failures) = (0, 0, 0, Vec::new());
    let mut run = |text: &str| {
        inputs += 1;
        if let Err(e) = check(text) {
            failures.push(e);
            return;
        }
        let Ok(problem) = ProblemFile::from_toml(text).and_then(Problem::try_from) else {
            return;
        };
        // A spacing out of scale makes millions of nodes (the command line refuses what does
        // not fit in memory; the opt-in campaign solves those through it): solved here only
        // up to 2 000 nodes (the three files have 100 to 300); every third, to stay within
        // seconds.
        accepted += 1;
        if accepted % 3 == 0 && mlpg_contact::pipeline::memory::estimate(&problem).1 <= 2000.0 {
            solved += 1;
            match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                mlpg_contact::solve(&problem)
            })) {
                Err(_) => failures.push(format!("panic solving:\n{text}")),
                Ok(Ok(s)) if s.first_non_finite().is_some() => {
                    failures.push(format!("a non-finite solution of:\n{text}"))
                }
                Ok(_) => {}
            }
        }
    };
    std::panic::set_hook(Box::new(|_| {}));
    for file in files {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let nums = numbers(&text);
        for &(s, e) in &nums {
            for by in out_of_scale(&text[s..e]) {
                run(&format!("{}{by}{}", &text[..s], &text[e..]));
            }
        }
        for _ in 0..40 {
            // Two numbers at once, the later one replaced first so that the ranges hold.
            let mut pick = [0, 0].map(|_| nums[(rng.next_u64() % nums.len() as u64) as usize]);
            pick.sort();
            let mut mutated = text.clone();
            for (s, e) in pick.into_iter().rev() {
                let all = out_of_scale(&text[s..e]);
                let by = &all[(rng.next_u64() % all.len() as u64) as usize];
                mutated = format!("{}{by}{}", &mutated[..s], &mutated[e..]);
            }
            if pick[0] != pick[1] {
                run(&mutated);
            }
        }
    }
    let _ = std::panic::take_hook();
    println!("out-of-scale campaign: {inputs} inputs, {accepted} accepted, {solved} solved");
    assert!(solved > 50, "only {solved} solved");
    assert!(inputs > 300, "only {inputs} inputs");
    assert!(failures.is_empty(), "{} failures; the first:\n{}", failures.len(), failures[0]);
}
