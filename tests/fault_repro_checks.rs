//! Regression tests for the reproducers in `tests/data/fault-repro-2/` (its README says what
//! each one showed): results whose own checks failed. Values legal in range but out of scale
//! for a small-strain linear model are refused up front (exit 2, naming the key); a result
//! whose residual, equilibrium or complementarity check fails is written but ends with exit
//! status 3 and `checks.passed = false`; the equilibrium of a body that nothing loads is not
//! round-off divided by round-off; mixed precision closes the contact gaps as double does.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn binary() -> &'static str {
    env!("CARGO_BIN_EXE_mlpg-contact")
}

fn repro(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fault-repro-2").join(name)
}

fn repro_text(name: &str) -> String {
    std::fs::read_to_string(repro(name)).unwrap()
}

/// A fresh, empty scratch directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fault-repro-checks").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run(problem: &Path, out: &Path) -> Output {
    Command::new(binary()).arg(problem).arg("--out").arg(out).arg("--quiet").output().unwrap()
}

/// Writes `text` as a problem file in a fresh scratch directory `name` and runs it into
/// `<scratch>/out`: the output and that directory.
fn run_text(name: &str, text: &str) -> (Output, PathBuf) {
    let dir = scratch(name);
    let file = dir.join(format!("{name}.toml"));
    std::fs::write(&file, text).unwrap();
    let out = dir.join("out");
    (run(&file, &out), out)
}

fn summary(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// Asserts a refusal: exit 2, no panic, every part of `expected` in stderr, nothing written.
fn assert_refused(label: &str, output: &Output, out: &Path, expected: &[&str]) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{label}: {stderr}");
    assert!(!stderr.contains("panicked"), "{label}: {stderr}");
    for part in expected {
        assert!(stderr.contains(part), "{label}: expected {part:?} in: {stderr}");
    }
    assert!(!out.exists(), "{label}: a refused run left an output directory");
}

/// Asserts exit 0 and `checks.passed`; the summary.
fn assert_passed(label: &str, output: &Output, out: &Path) -> serde_json::Value {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{label}: {stderr}");
    let s = summary(out);
    assert_eq!(s["checks"]["passed"], true, "{label}: {}", s["checks"]);
    s
}

#[test]
fn a_clamp_moved_far_beyond_the_body_is_refused() {
    let dir = scratch("d1");
    let out = dir.join("out");
    let output = run(&repro("D1_huge_rigid_displacement.toml"), &out);
    assert_refused(
        "D1",
        &output,
        &out,
        &["`boundary[0].displacement.x`", "1e12", "times the body's size", "check the units"],
    );
}

/// At the largest accepted motion (10³ times the body's size, the diagonal 48.37) the beam
/// still carries the contact force of the unmoved clamp, and its checks pass.
#[test]
fn a_clamp_moved_by_a_thousand_body_sizes_keeps_its_answer() {
    let text = repro_text("D1_huge_rigid_displacement.toml");
    let force = |name: &str, x: &str| {
        let (output, out) = run_text(name, &text.replace("x = 1e12", &format!("x = {x}")));
        let s = assert_passed(name, &output, &out);
        s["contact"]["total_force"].as_f64().unwrap()
    };
    let (still, moved) = (force("d1_still", "0.0"), force("d1_moved", "4.8e4"));
    assert!((still - 32.344).abs() < 1e-3, "{still}");
    assert!((moved - still).abs() <= 1e-6 * still, "{moved} against {still}");
}

#[test]
fn a_stiffness_ratio_beyond_double_precision_is_refused() {
    let dir = scratch("d1b");
    let out = dir.join("out");
    let output = run(&repro("D1b_stiff_middle_block.toml"), &out);
    assert_refused(
        "D1b",
        &output,
        &out,
        &["`body[1].material.young`", "times body[0].material.young", "ratio of 1e12"],
    );
}

/// The middle block 10¹⁰ times stiffer than the bottom one (accepted): its reactions carry
/// round-off of the contact forces and its equilibrium error (8.7e-6) fails its check; the
/// outputs are written, `summary.json` marks the run failed and the status is 3.
#[test]
fn a_failing_check_writes_the_outputs_and_ends_with_status_3() {
    let text = repro_text("D1b_stiff_middle_block.toml")
        .replace("young = 9223372036854775807", "young = 1e13");
    let (output, out) = run_text("d1b_1e13", &text);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(3), "{stderr}");
    for part in [
        "checks failed",
        "bodies[1].equilibrium_error",
        "above its tolerance 1e-6",
        "summary.json",
        "material.young",
    ] {
        assert!(stderr.contains(part), "expected {part:?} in: {stderr}");
    }
    for file in ["contact_0.csv", "displacement.csv", "middle/reactions.csv"] {
        assert!(out.join(file).is_file(), "{file} not written");
    }
    let s = summary(&out);
    assert_eq!(s["checks"]["passed"], false);
    let verdicts = s["checks"]["verdicts"].as_array().unwrap();
    let failed: Vec<&serde_json::Value> = verdicts.iter().filter(|v| v["pass"] == false).collect();
    assert_eq!(failed.len(), 1, "{verdicts:?}");
    assert_eq!(failed[0]["key"], "bodies[1].equilibrium_error");
    let value = failed[0]["value"].as_f64().unwrap();
    assert_eq!(value, s["bodies"][1]["equilibrium_error"].as_f64().unwrap());
    assert!(value > failed[0]["tolerance"].as_f64().unwrap());
}

/// Nothing loads the cylinder (its top edge moves it, the obstacle is far below): the
/// reactions are round-off, measured against the internal forces at the supports.
#[test]
fn a_body_that_nothing_loads_has_no_equilibrium_error() {
    let dir = scratch("d2");
    let out = dir.join("out");
    let output = run(&repro("D2_zero_load_equilibrium_error.toml"), &out);
    let s = assert_passed("D2", &output, &out);
    let error = s["checks"]["equilibrium_error"].as_f64().unwrap();
    assert!(error < 1e-12, "equilibrium error {error:e}");
    assert_eq!(s["checks"]["applied_force"], serde_json::json!([0.0, 0.0]));
    assert_eq!(s["contact"]["total_force"], 0.0);
}

/// The closed candidates' gaps from `contact.csv` (`in_contact = 1`).
fn closed_gaps(out: &Path) -> Vec<f64> {
    let csv = std::fs::read_to_string(out.join("contact.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (gap, closed) = (col("gap"), col("in_contact"));
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[closed] == "1")
        .map(|f| f[gap].parse().unwrap())
        .collect()
}

/// Mixed precision: the gaps of the displacements close as in double precision (they were
/// −3.5e-11 against a 0.01 initial gap), and the contact force agrees with double's.
#[test]
fn mixed_precision_closes_the_gaps_as_double_does() {
    let dir = scratch("d4");
    let out = dir.join("out");
    let output = run(&repro("D4_mixed_precision_penetration.toml"), &out);
    let mixed = assert_passed("D4", &output, &out);
    let gaps = closed_gaps(&out);
    assert_eq!(gaps.len(), 57);
    let worst = gaps.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(worst < 1e-14, "closed gaps up to {worst:e}");
    let correction = &mixed["lcp"]["gap_correction"];
    assert_eq!(correction["accepted"], true, "{correction}");
    assert!(correction["closed_gap_before"].as_f64().unwrap() > 1e-12, "{correction}");
    assert!(correction["closed_gap_after"].as_f64().unwrap() < 1e-14, "{correction}");

    let text =
        repro_text("D4_mixed_precision_penetration.toml").replace("precision = \"mixed\"", "");
    let (output, out) = run_text("d4_double", &text);
    let double = assert_passed("D4 in double precision", &output, &out);
    assert!(double["lcp"].get("gap_correction").is_none());
    let worst_double = closed_gaps(&out).iter().fold(0.0f64, |m, g| m.max(g.abs()));
    assert!(worst_double < 1e-14, "double: closed gaps up to {worst_double:e}");
    let force = |s: &serde_json::Value| s["contact"]["total_force"].as_f64().unwrap();
    let (f_mixed, f_double) = (force(&mixed), force(&double));
    assert!((f_mixed - f_double).abs() <= 1e-10 * f_double, "{f_mixed} against {f_double}");
}

/// The beam clamped at its left end, above a rigid floor, with `steps` appended.
fn stepped_beam(steps: &str) -> String {
    format!(
        r#"
[geometry]
kind = "rectangle"
x = [0.0, 48.0]
y = [-3.0, 3.0]
[nodes]
spacing = 1.0
[material]
young = 30000.0
poisson = 0.3
plane = "stress"
[[boundary]]
edge = "left"
displacement = {{ x = 0.0, y = 0.0 }}
[contact]
edge = "bottom"
obstacle_point = [0.0, -3.01]
obstacle_normal = [0.0, 1.0]
{steps}"#
    )
}

#[test]
fn step_motions_far_beyond_the_body_are_refused() {
    let cases = [
        (
            "obstacle",
            "[[step]]\nobstacle_displacement = [0.0, 1e6]\n",
            "`step[0].obstacle_displacement`",
        ),
        (
            "boundary",
            "[[step]]\nboundary = [{ edge = \"left\", displacement = { x = 1e9 } }]\n",
            "`step[0].boundary[0].displacement.x`",
        ),
    ];
    for (name, steps, key) in cases {
        let (output, out) = run_text(&format!("steps_{name}"), &stepped_beam(steps));
        assert_refused(name, &output, &out, &[key, "times the body's size"]);
    }
    // Within the limit the same steps are accepted.
    let (output, out) =
        run_text("steps_within", &stepped_beam("[[step]]\nobstacle_displacement = [0.0, 0.02]\n"));
    assert_passed("steps within the limit", &output, &out);
}

#[test]
fn help_lists_the_exit_statuses() {
    let output = Command::new(binary()).arg("--help").output().unwrap();
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success());
    for part in ["Exit status:", "0  solved", "2  refused or failed", "3  solved and written"] {
        assert!(text.contains(part), "expected {part:?} in: {text}");
    }
}
