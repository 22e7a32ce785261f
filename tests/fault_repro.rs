//! Regression tests for the fault reproducers in `tests/data/fault-repro/` and
//! `tests/data/fault-repro-2/` (their READMEs say what each one showed): every one now ends in a clear refusal naming the input (exit 2) or
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
    // A contact run, then a run without contact into the same directory: nothing the first
    // wrote (contact.csv, its plots) is left, and a file of the user's is kept.
    assert!(run_problem(&shipped("beam_on_foundation.toml"), &out, &[]).status.success());
    std::fs::write(out.join("notes.csv"), "mine").unwrap();
    assert!(run_problem(&shipped("cantilever.toml"), &out, &[]).status.success());
    let after = listing(&out);
    assert!(!after.contains(&"contact.csv".to_string()), "{after:?}");
    assert_eq!(std::fs::read_to_string(out.join("notes.csv")).unwrap(), "mine");
    assert!(!listing(&out.join("plots")).iter().any(|f| f.starts_with("contact_")));
    // The manifest lists what the run wrote, and only that.
    let manifest = std::fs::read_to_string(out.join(".mlpg-contact-manifest")).unwrap();
    assert!(manifest.lines().any(|l| l == "plots/deformed.svg"), "{manifest}");
    let listed: Vec<&str> = manifest.lines().filter(|l| !l.starts_with('#')).collect();
    assert!(!listed.iter().any(|l| l.contains("contact") || l.contains("notes")), "{listed:?}");
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

fn repro2(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fault-repro-2").join(name)
}

/// The beam of `D4` in double precision, written into `dir` as `problem.toml`.
fn d4_beam(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repro2("D4_mixed_precision_penetration.toml")).unwrap();
    let path = dir.join("problem.toml");
    std::fs::write(&path, text.replace("precision = \"mixed\"", "")).unwrap();
    path
}

#[test]
fn a_rerun_keeps_the_files_it_did_not_write() {
    // D5: the outputs of a first run moved beside the problem file (no manifest: as an older
    // version leaves them), a note of the user's, then a run into that directory.
    let dir = scratch("d5");
    let problem = d4_beam(&dir);
    let first = run_problem(&problem, &dir.join("run1"), &[]);
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    for entry in std::fs::read_dir(dir.join("run1")).unwrap().flatten() {
        if !entry.file_name().to_string_lossy().starts_with('.') {
            std::fs::rename(entry.path(), dir.join(entry.file_name())).unwrap();
        }
    }
    std::fs::write(dir.join("notes.txt"), "my notes").unwrap();
    let problem_text = std::fs::read_to_string(&problem).unwrap();
    for round in 0..2 {
        // The second round reruns into a directory that has this program's manifest.
        let out = run_problem(&problem, &dir, &[]);
        assert!(out.status.success(), "round {round}: {}", String::from_utf8_lossy(&out.stderr));
        assert_eq!(std::fs::read_to_string(&problem).unwrap(), problem_text, "round {round}");
        assert_eq!(std::fs::read_to_string(dir.join("notes.txt")).unwrap(), "my notes");
        assert!(dir.join("run1/.mlpg-contact-manifest").exists(), "round {round}");
        assert!(dir.join("summary.json").exists() && dir.join("plots/deformed.svg").exists());
    }
    let manifest = std::fs::read_to_string(dir.join(".mlpg-contact-manifest")).unwrap();
    assert!(manifest.lines().any(|l| l == "summary.json"), "{manifest}");
    assert!(!manifest.contains("problem.toml") && !manifest.contains("notes"), "{manifest}");
    assert!(!listing(&dir).iter().any(|f| f.contains("partial")), "{:?}", listing(&dir));
}

#[test]
fn a_file_of_the_users_in_the_way_of_an_output_is_refused() {
    // A run without contact, then the user's own contact.csv, then a contact run: contact.csv
    // is not the earlier run's, so it is neither overwritten nor removed, and nothing changes.
    let dir = scratch("in-the-way");
    let out = dir.join("out");
    assert!(run_problem(&shipped("cantilever.toml"), &out, &[]).status.success());
    std::fs::write(out.join("contact.csv"), "mine").unwrap();
    let before = listing(&out);
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let second = run_problem(&shipped("beam_on_foundation.toml"), &out, &[]);
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert_eq!(second.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("contact.csv is in the way of an output"), "{stderr}");
    assert_eq!(std::fs::read_to_string(out.join("contact.csv")).unwrap(), "mine");
    assert_eq!(std::fs::read_to_string(out.join("summary.json")).unwrap(), summary);
    assert_eq!(listing(&out), before);
    assert_eq!(listing(&dir), vec!["out".to_string()]);
}

#[cfg(unix)]
#[test]
fn a_symlinked_out_is_followed_and_kept() {
    // D10: --out a symbolic link to a directory: the outputs go into the directory it names,
    // the link stays a link (twice: a rerun goes through the link too).
    let dir = scratch("d10");
    std::fs::create_dir(dir.join("real")).unwrap();
    std::os::unix::fs::symlink("real", dir.join("link")).unwrap();
    for round in 0..2 {
        let out =
            run_problem(&repro2("D4_mixed_precision_penetration.toml"), &dir.join("link"), &[]);
        assert!(out.status.success(), "round {round}: {}", String::from_utf8_lossy(&out.stderr));
        let meta = std::fs::symlink_metadata(dir.join("link")).unwrap();
        assert!(meta.file_type().is_symlink(), "round {round}: the link was replaced");
        assert!(dir.join("real/summary.json").exists(), "round {round}");
        assert!(dir.join("real/.mlpg-contact-manifest").exists(), "round {round}");
        assert_eq!(listing(&dir), vec!["link".to_string(), "real".to_string()]);
    }
    // A link to nothing is refused with its path, before anything is solved.
    std::os::unix::fs::symlink("nowhere", dir.join("dangling")).unwrap();
    let out =
        run_problem(&repro2("D4_mixed_precision_penetration.toml"), &dir.join("dangling"), &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("dangling is not a directory"), "{stderr}");
    assert!(!dir.join("nowhere").exists());

    // Across file systems (a link into /dev/shm, when that is another file system): the
    // staging directory is beside the link's target, so the move cannot fail after the solve.
    use std::os::unix::fs::MetadataExt;
    let here = std::fs::metadata(&dir).unwrap().dev();
    if std::fs::metadata("/dev/shm").is_ok_and(|m| m.is_dir() && m.dev() != here) {
        let other = Path::new("/dev/shm").join(format!("mlpg-contact-d10-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&other);
        if std::fs::create_dir(&other).is_ok() {
            std::os::unix::fs::symlink(&other, dir.join("link2")).unwrap();
            let out = run_problem(
                &repro2("D4_mixed_precision_penetration.toml"),
                &dir.join("link2"),
                &[],
            );
            let written = other.join("summary.json").exists();
            let _ = std::fs::remove_dir_all(&other);
            assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            assert!(written);
            assert!(std::fs::symlink_metadata(dir.join("link2")).unwrap().file_type().is_symlink());
        }
    }
}

#[test]
fn a_staging_directory_left_by_a_dead_process_is_removed() {
    // D11: `.out.partial-<pid>` of a process that is gone (a child that has ended and been
    // waited for) is removed by the next run into `out`; that of a live process (this test)
    // is left alone.
    if !Path::new("/proc/self").exists() {
        return; // without /proc a process cannot be told gone: nothing is removed
    }
    let dir = scratch("d11");
    let mut child = Command::new(binary()).arg("--version").stdout(Stdio::null()).spawn().unwrap();
    let dead = child.id();
    child.wait().unwrap();
    let stale = dir.join(format!(".out.partial-{dead}"));
    let alive = dir.join(format!(".out.partial-{}", std::process::id()));
    for d in [&stale, &alive] {
        std::fs::create_dir_all(d.join("plots")).unwrap();
        std::fs::write(d.join("plots/deformed.svg"), "left behind").unwrap();
    }
    let out = run_problem(&repro("r_ok.toml"), &dir.join("out"), &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!stale.exists(), "the dead process's staging directory is still there");
    assert!(alive.exists(), "a live process's staging directory was removed");
    assert!(dir.join("out/summary.json").exists());
}

#[cfg(unix)]
#[test]
fn a_run_ended_by_sigterm_removes_its_staging_directory() {
    // D11's problem (100 000 increments: it runs far longer than this test waits) is ended by
    // SIGTERM once its staging directory exists: the directory goes, the process ends by the
    // signal, no --out is created.
    use std::os::unix::process::ExitStatusExt;
    let dir = scratch("d11-term");
    let script = std::fs::read_to_string(repro2("D11_killed_run_leaves_staging.sh")).unwrap();
    let start = script.find("name = \"d11\"").unwrap();
    let end = script[start..].find("TOML\n").unwrap() + start;
    std::fs::write(dir.join("p.toml"), &script[start..end]).unwrap();
    let mut child = Command::new(binary())
        .arg(dir.join("p.toml"))
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--quiet")
        .spawn()
        .unwrap();
    let staging = dir.join(format!(".out.partial-{}", child.id()));
    // Wait (without a deadline on the result) until the run has created its staging directory.
    while !staging.exists() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended before its staging directory appeared: {status}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let killed = Command::new("kill").arg("-TERM").arg(child.id().to_string()).status();
    if !killed.is_ok_and(|s| s.success()) {
        let _ = child.kill();
        let _ = child.wait();
        return; // no kill command on this system
    }
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(15), "{status}");
    assert!(!staging.exists(), "the staging directory is still there");
    assert!(!dir.join("out").exists());
}

#[test]
fn a_refinement_box_far_larger_than_the_body_is_clipped() {
    // D3: a box x = [0, 1e9] over a 2 x 2 body aborted on a 4 GB allocation. Clipped, it gives
    // the node set of the box x = [0, 2] (the same spacing over the body), under the same
    // address-space limit.
    let dir = scratch("d3");
    let command = format!(
        "ulimit -v 4000000 && exec '{}' '{}' --out '{}' --quiet",
        binary(),
        repro2("D3_refine_box_huge_abort.toml").display(),
        dir.join("huge").display()
    );
    let Ok(out) = Command::new("sh").arg("-c").arg(&command).output() else {
        return; // no POSIX shell on this system
    };
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(repro2("D3_refine_box_huge_abort.toml")).unwrap();
    let body = dir.join("body.toml");
    std::fs::write(&body, text.replace("x = [0.0, 1e9]", "x = [0.0, 2.0]")).unwrap();
    let out = run_problem(&body, &dir.join("body"), &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let nodes = |d: &str| std::fs::read_to_string(dir.join(d).join("nodes.csv")).unwrap();
    assert_eq!(nodes("huge"), nodes("body"));
}

#[cfg(unix)]
#[test]
fn out_layouts_that_are_no_directory_are_refused_and_missing_parents_made() {
    // The --out layouts of the opt-in campaign (examples/studies/fault_campaign.rs) that the
    // tests above do not cover: a symbolic link to a file and a file where the directory
    // should be are refused before anything is solved, the file intact and nothing beside it;
    // missing parents are created, and hold only the run.
    let dir = scratch("layouts");
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    std::os::unix::fs::symlink("notes.txt", dir.join("to-file")).unwrap();
    for out in ["to-file", "notes.txt"] {
        let ran = run_problem(&repro("r_ok.toml"), &dir.join(out), &[]);
        let stderr = String::from_utf8_lossy(&ran.stderr);
        assert_eq!(ran.status.code(), Some(2), "{out}: {stderr}");
        assert!(stderr.contains("is not a directory"), "{out}: {stderr}");
        assert_eq!(std::fs::read_to_string(dir.join("notes.txt")).unwrap(), "mine");
        assert_eq!(listing(&dir), vec!["notes.txt".to_string(), "to-file".to_string()]);
    }
    let ran = run_problem(&repro("r_ok.toml"), &dir.join("a/b/out"), &[]);
    assert!(ran.status.success(), "{}", String::from_utf8_lossy(&ran.stderr));
    assert_eq!(listing(&dir.join("a")), vec!["b".to_string()]);
    assert_eq!(listing(&dir.join("a/b")), vec!["out".to_string()]);
    assert!(dir.join("a/b/out/summary.json").exists());
}

#[test]
fn an_initial_velocity_out_of_scale_is_refused() {
    // F1 (tests/data/fault-repro-3): -1e300 ended in exit 0 with inf in history.csv.
    let dir = scratch("f1");
    let problem = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fault-repro-3/F1_huge_initial_velocity.toml");
    let out = run_problem(&problem, &dir.join("out"), &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("dynamics.initial_velocity"), "{stderr}");
    assert!(stderr.contains("rescale the units"), "{stderr}");
    assert!(!dir.join("out").exists());
}
