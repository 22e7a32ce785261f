//! What the LCP test crates (`tests/lcp_suite.rs`, `tests/active_set.rs`) share: the external
//! suite's cases (`tests/data/lcp-suite`) and the random matrix families of their property
//! tests.

// Each test crate uses only some of these.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use mlpg_contact::lcp::Lcp;
use serde_json::Value;

/// The suite's folder.
pub fn suite_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lcp-suite")
}

/// One case of the suite, as read from its JSON file.
pub struct Case {
    pub name: String,
    pub lcp: Lcp,
    pub expected: String,
    pub z: Option<Vec<f64>>,
    pub solution_exists: bool,
    pub lemke_pivots: Option<usize>,
    pub p_matrix: bool,
}

fn numbers(v: &Value, what: &str, file: &str) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("{file}: {what} is not an array"))
        .iter()
        .map(|x| x.as_f64().unwrap_or_else(|| panic!("{file}: {what} has a non-number")))
        .collect()
}

fn load_case(path: &Path) -> Case {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{file}: {e}"));
    let v: Value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{file}: {e}"));
    let n = v["n"].as_u64().unwrap_or_else(|| panic!("{file}: no n")) as usize;
    let rows: Vec<Vec<f64>> = v["M"]
        .as_array()
        .unwrap_or_else(|| panic!("{file}: M is not an array"))
        .iter()
        .map(|row| numbers(row, "a row of M", &file))
        .collect();
    let q = numbers(&v["q"], "q", &file);
    let lcp = Lcp::from_rows(&rows, q).unwrap_or_else(|e| panic!("{file}: {e}"));
    assert_eq!(lcp.size(), n, "{file}: n does not match M");
    Case {
        name: v["name"].as_str().unwrap_or_else(|| panic!("{file}: no name")).to_string(),
        lcp,
        expected: v["expected"].as_str().unwrap_or_else(|| panic!("{file}: no expected")).into(),
        z: v.get("z").map(|z| numbers(z, "z", &file)),
        solution_exists: v["solution_exists"].as_bool().unwrap_or(true),
        lemke_pivots: v["lemke_pivots"].as_u64().map(|p| p as usize),
        p_matrix: v["properties"]["P_matrix"].as_bool() == Some(true),
    }
}

pub fn load_suite() -> Vec<Case> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(suite_dir())
        .expect("tests/data/lcp-suite is missing")
        .map(|e| e.expect("unreadable directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    paths.iter().map(|p| load_case(p)).collect()
}

pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()))
}

/// `M = AᵀA + δI + skew (S − Sᵀ)` from `n × n` row-major `a` and `s`: a positive definite
/// symmetric part plus a skew part (the character of the contact compliance).
pub fn positive_definite_plus_skew(
    n: usize,
    a: &[f64],
    s: &[f64],
    delta: f64,
    skew: f64,
) -> Vec<f64> {
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let ata: f64 = (0..n).map(|k| a[k * n + i] * a[k * n + j]).sum();
            m[i * n + j] =
                ata + skew * (s[i * n + j] - s[j * n + i]) + if i == j { delta } else { 0.0 };
        }
    }
    m
}

/// `M = P L Pᵀ` with `L` lower triangular (diagonal `diag`, below it `l`, row-major) and `P`
/// the permutation `perm`: a P-matrix that can be far from positive definite.
pub fn permuted_triangular(n: usize, l: &[f64], diag: &[f64], perm: &[usize]) -> Vec<f64> {
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let v = if i == j { diag[i] } else { l[i * n + j] };
            m[perm[i] * n + perm[j]] = v;
        }
    }
    m
}
