//! Regression tests for the fault reproducers in `tests/data/fault-repro/` (its README says
//! what each one showed): every one now ends in a clear refusal naming the input (exit 2) or
//! in the right answer, never in a panic, an abort, output outside `--out` or a silent wrong
//! result; and a failing stderr or an absurd thread count does not decide the run.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn binary() -> &'static str {
    env!("CARGO_BIN_EXE_mlpg-contact")
}

fn repro(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fault-repro").join(name)
}

/// A fresh, empty scratch directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fault-repro").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run(file: &str, out: &Path) -> Output {
    Command::new(binary()).arg(repro(file)).arg("--out").arg(out).arg("--quiet").output().unwrap()
}

/// Runs `file` and asserts exit code 2, no panic and every part of `expected` in stderr.
fn refused(file: &str, expected: &[&str]) {
    let dir = scratch(file);
    let out = run(file, &dir.join("out"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{file}: {stderr}");
    assert!(!stderr.contains("panicked"), "{file}: {stderr}");
    for part in expected {
        assert!(stderr.contains(part), "{file}: expected {part:?} in: {stderr}");
    }
    // A refused run writes nothing.
    assert!(!dir.join("out").exists(), "{file}: a refused run left an output directory");
}

#[test]
fn unsafe_body_names_are_refused() {
    refused("r1_empty.toml", &["body[1].name", "letters, digits"]);
    refused("r1_dotdot.toml", &["body[1].name", "../escaped_r1"]);
    assert!(!scratch("r1_dotdot.toml").join("escaped_r1").exists());
}

#[test]
fn a_candidate_beside_the_target_edge_cannot_close() {
    refused(
        "r2_beside.toml",
        &[
            "no point of contact edge `bottom` lies over edge `top`",
            // The run-time refusal prints the values of the keys that decide it.
            "(decided by: contact.edge, contact.target_edge, geometry)",
            "contact.edge = \"bottom\"",
            "body[0].geometry = {\"kind\":\"rectangle\",\"x\":[3.0,5.0],\"y\":[1.0,2.0]}",
        ],
    );
}

#[test]
fn overlapping_bodies_are_refused() {
    refused("r3_overlap.toml", &["contact.target_edge", "the bodies overlap", "5.000e-1"]);
}

#[test]
fn magnitudes_that_overflow_are_refused() {
    refused("r4_huge.toml", &["boundary[1].traction.y", "-1e300", "rescale the units"]);
    refused("r6_guard.toml", &["geometry.x", "1e160"]);
}

#[test]
fn fixed_length_arrays_have_exactly_their_length() {
    refused("r5_trunc.toml", &["invalid length", "expected exactly 2 numbers"]);
}

#[test]
fn messages_name_the_key_path() {
    refused("r10.toml", &["at `geometry.x`"]);
    refused("r10c.toml", &["contact.obstacle_point", "NaN"]);
}

#[test]
fn convexity_is_judged_relative_to_the_edges_not_the_coordinates() {
    // The rectangle far from the origin is convex; the file has no displacement condition,
    // which is what is refused now.
    let dir = scratch("r10b.toml");
    let out = run("r10b.toml", &dir.join("out"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("convex"), "{stderr}");
    assert!(stderr.contains("no displacement is prescribed"), "{stderr}");
    // A run-time refusal names the input that decides it.
    assert!(stderr.contains("(decided by: boundary[*].displacement)"), "{stderr}");
}

#[test]
fn a_round_off_normal_component_changes_nothing() {
    let csv = |file: &str| {
        let dir = scratch(file);
        let out = run(file, &dir.join("out"));
        assert!(out.status.success(), "{file}: {}", String::from_utf8_lossy(&out.stderr));
        std::fs::read_to_string(dir.join("out/contact.csv")).unwrap()
    };
    let (exact, tiny) = (csv("hz_0.0.toml"), csv("hz_1e-300.toml"));
    assert_eq!(exact.lines().count(), 54, "53 candidates and the header");
    assert_eq!(exact, tiny);
}

#[test]
fn a_failing_stderr_does_not_decide_the_run() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        return; // no /dev/full on this system
    };
    let dir = scratch("stderr-full");
    let status = Command::new(binary())
        .arg(repro("r_ok.toml"))
        .arg("--out")
        .arg(dir.join("out"))
        .stderr(Stdio::from(full))
        .status()
        .unwrap();
    assert!(status.success(), "exit {status}");
    assert!(dir.join("out/summary.json").exists());
    assert!(dir.join("out/b/nodes.csv").exists());
}

#[test]
fn an_absurd_thread_count_is_capped() {
    let dir = scratch("threads");
    let out = Command::new(binary())
        .arg(repro("r_ok.toml"))
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--quiet")
        .env("RAYON_NUM_THREADS", "100000")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("RAYON_NUM_THREADS = 100000 capped"), "{stderr}");
}

#[test]
fn an_overhang_keeps_only_the_candidates_over_the_target_edge() {
    // r2 with the upper block moved to x = [1, 3]: half of it overhangs the lower block's end
    // at x = 2. The nodes past x = 2 are no candidates; equilibrium holds.
    let text = std::fs::read_to_string(repro("r2_beside.toml"))
        .unwrap()
        .replace("x = [3.0, 5.0]", "x = [1.0, 3.0]");
    let dir = scratch("overhang");
    std::fs::write(dir.join("overhang.toml"), text).unwrap();
    let out = Command::new(binary())
        .arg(dir.join("overhang.toml"))
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--quiet")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("4 nodes of the contact edge lie beside the target edge"), "{stderr}");
    let csv = std::fs::read_to_string(dir.join("out/contact.csv")).unwrap();
    let xs: Vec<f64> =
        csv.lines().skip(1).map(|l| l.split(',').nth(2).unwrap().parse().unwrap()).collect();
    assert_eq!(xs.len(), 5, "candidates at x = 1, 1.25, …, 2");
    assert!(xs.iter().all(|&x| x <= 2.0 + 1e-12), "{xs:?}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/summary.json")).unwrap())
            .unwrap();
    let equilibrium = summary["checks"]["equilibrium_error"].as_f64().unwrap();
    assert!(equilibrium < 1e-10, "equilibrium error {equilibrium:e}");
}

fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("problems").join(name)
}

fn run_problem(problem: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(binary())
        .arg(problem)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(extra)
        .output()
        .unwrap()
}

/// The names in a directory, sorted, hidden ones included.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| d.flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect())
        .unwrap_or_default();
    names.sort();
    names
}

#[test]
fn an_output_directory_holds_one_complete_run() {
    let dir = scratch("one-run");
    let out = dir.join("out");
    // A contact run, then a run without contact into the same directory: nothing of the first
    // (contact.csv, its plots, a stray file) is left.
    assert!(run_problem(&shipped("beam_on_foundation.toml"), &out, &[]).status.success());
    std::fs::write(out.join("stale.csv"), "x").unwrap();
    assert!(run_problem(&shipped("cantilever.toml"), &out, &[]).status.success());
    let after = listing(&out);
    assert!(!after.contains(&"contact.csv".to_string()), "{after:?}");
    assert!(!after.contains(&"stale.csv".to_string()), "{after:?}");
    assert!(!listing(&out.join("plots")).iter().any(|f| f.starts_with("contact_")));
    // A comparison the finite elements cannot do (a curved body) is refused before anything
    // is solved or written: the previous run stays as it was, no staging directory remains.
    let failed = run_problem(&shipped("hertz_cylinder.toml"), &out, &["--compare"]);
    assert_eq!(failed.status.code(), Some(2));
    assert_eq!(listing(&out), after);
    assert_eq!(listing(&dir), vec!["out".to_string()]);
}

#[test]
fn a_directory_that_holds_no_run_is_not_replaced() {
    let dir = scratch("user-dir");
    std::fs::write(dir.join("thesis.tex"), "mine").unwrap();
    let out = run_problem(&shipped("cantilever.toml"), &dir, &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("holds something other than an mlpg-contact run"), "{stderr}");
    assert_eq!(listing(&dir), vec!["thesis.tex".to_string()]);
}

#[test]
fn a_problem_that_cannot_fit_in_memory_is_refused_up_front() {
    // ~120k nodes need about 4.3 GB: under a 4 GB address-space limit the run must refuse
    // with the estimate and the parameter to change, not abort half-way.
    let dir = scratch("r7_mem.toml");
    let command = format!(
        "ulimit -v 4000000 && exec '{}' '{}' --out '{}' --quiet",
        binary(),
        repro("r7_mem.toml").display(),
        dir.join("out").display()
    );
    let Ok(out) = Command::new("sh").arg("-c").arg(&command).output() else {
        return; // no POSIX shell on this system
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("the address-space limit"), "{stderr}");
    assert!(stderr.contains("increase nodes.spacing"), "{stderr}");
    assert!(stderr.contains("set discretisation.precision = \"mixed\""), "{stderr}");
    assert!(!dir.join("out").exists());

    // The same body in mixed precision (estimated at 0.6 of the double-precision bytes,
    // ~2.6 GB) under a 2 GB limit: refused too, and the advice no longer names the precision
    // the file already sets.
    let text = std::fs::read_to_string(repro("r7_mem.toml")).unwrap();
    let mixed = dir.join("r7_mem_mixed.toml");
    std::fs::write(&mixed, format!("{text}\n[discretisation]\nprecision = \"mixed\"\n")).unwrap();
    let command = format!(
        "ulimit -v 2000000 && exec '{}' '{}' --out '{}' --quiet",
        binary(),
        mixed.display(),
        dir.join("out").display()
    );
    let Ok(out) = Command::new("sh").arg("-c").arg(&command).output() else {
        return;
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("increase nodes.spacing"), "{stderr}");
    assert!(!stderr.contains("set discretisation.precision"), "{stderr}");
    assert!(!dir.join("out").exists());
}
