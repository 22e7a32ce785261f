//! The primal–dual active-set contact solver (docs/method.md §5.1, `contact.solver =
//! "active_set"`) against Lemke's method on the condensed LCP (§5), on every shipped problem
//! with a rigid obstacle (MFVM, stabilised MFVM, FE, the Hertz cylinder) and on a block
//! against an inclined obstacle (the normal not along an axis: two rows change per active
//! candidate). Both answer the same LCP exactly, so forces and gaps must agree to round-off:
//! the tolerance 1e-10 (relative to the largest force, resp. the largest gap magnitude) leaves
//! room for the condition of the two routes (`M`'s eigenvalue ratio is ≈ 2e-5 on the beam)
//! times the double-precision ε. Each answer is also checked on its own: scaled
//! complementarity residuals, and global equilibrium of the recovered solution.

use mlpg_contact::Error;
use mlpg_contact::lcp::LcpError;
use mlpg_contact::lcp::active_set::ActiveSetError;
use mlpg_contact::problem::{ContactSolver, Problem};
use mlpg_contact::solution::Solution;

/// Agreement of the two solvers (see the module documentation).
const AGREEMENT: f64 = 1e-10;
/// Scaled complementarity residuals of each answer.
const KKT_TOLERANCE: f64 = 1e-9;
/// Global equilibrium of each recovered solution, relative to the applied load.
const EQUILIBRIUM_TOLERANCE: f64 = 1e-8;

fn shipped(file: &str) -> Problem {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems").join(file);
    Problem::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn solve_with(problem: &Problem, solver: ContactSolver) -> Solution {
    let mut p = problem.clone();
    p.contact.as_mut().unwrap().solver = solver;
    mlpg_contact::solve(&p).unwrap()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

fn check_own(name: &str, s: &Solution) {
    let c = s.contact.as_ref().unwrap();
    let r = &c.lcp.residuals;
    assert!(r.min_z >= -KKT_TOLERANCE && r.min_w >= -KKT_TOLERANCE, "{name}: {r:?}");
    assert!(r.max_complementarity <= KKT_TOLERANCE, "{name}: {r:?}");
    assert!(s.equilibrium_error < EQUILIBRIUM_TOLERANCE, "{name}: {}", s.equilibrium_error);
}

/// Returns (largest force difference, largest gap difference), both relative.
pub(super) fn compare(name: &str, problem: &Problem) -> (f64, f64) {
    let lemke = solve_with(problem, ContactSolver::Lemke);
    let active = solve_with(problem, ContactSolver::ActiveSet);
    check_own(name, &lemke);
    check_own(name, &active);
    let (a, b) = (active.contact.as_ref().unwrap(), lemke.contact.as_ref().unwrap());
    assert!(a.condensed.is_none() && a.active_set.is_some(), "{name}: not the active-set path");
    assert!(b.condensed.is_some() && b.active_set.is_none(), "{name}: not the Lemke path");
    let diff =
        |x: &[f64], y: &[f64]| x.iter().zip(y).fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()));
    // The largest gap of a closed candidate (0 in exact arithmetic) measures how well each
    // answer solves its own problem; the other's forces may differ by that gap over the
    // smallest eigenvalue of M's symmetric part (from the Lemke run's checks of M).
    let closed_gap = |c: &mlpg_contact::ContactSolution| {
        c.gap.iter().zip(&c.closed).filter(|p| *p.1).fold(0.0_f64, |m, (g, _)| m.max(g.abs()))
    };
    let (ga, gb) = (closed_gap(a), closed_gap(b));
    let lambda_min = b.condensed.as_ref().unwrap().min_symmetric_eigenvalue;
    let p_max = max_abs(&b.lcp.z);
    let conditioned = 4.0 * ga.max(gb) / lambda_min / p_max;
    println!("{name}: closed gaps: active set {ga:.1e}, Lemke {gb:.1e}; bound {conditioned:.1e}");
    let force = diff(&a.lcp.z, &b.lcp.z) / p_max;
    let gap_scale = max_abs(&b.gap).max(max_abs(&b.candidates.initial_gap));
    let gap = diff(&a.gap, &b.gap) / gap_scale;
    // Likewise the gaps: each answer's gaps are off by at least its closed gaps' round-off.
    let gap_bound = 4.0 * ga.max(gb) / gap_scale;
    assert!(
        force < AGREEMENT.max(conditioned),
        "{name}: forces differ by {force:e} (bound {conditioned:e})"
    );
    assert!(gap < AGREEMENT.max(gap_bound), "{name}: gaps differ by {gap:e} (bound {gap_bound:e})");
    assert_eq!(a.closed, b.closed, "{name}: closed sets differ");
    (force, gap)
}

#[test]
fn shipped_rigid_obstacle_problems_equal_lemke() {
    for file in [
        "beam_on_foundation.toml",
        "beam_on_foundation_stabilised.toml",
        "beam_on_foundation_fem.toml",
        "hertz_cylinder.toml",
    ] {
        let (force, gap) = compare(file, &shipped(file));
        println!("{file}: forces {force:.1e}, gaps {gap:.1e}");
    }
}

/// A 2 × 1 block, its top pushed down by 0.02 and held in x on the left, pressed onto a rigid
/// line inclined at atan(0.1) that touches first at the left end: the normal has both
/// components, so the gap row and the tangential combination both replace rows.
#[test]
fn inclined_obstacle_equals_lemke() {
    let problem = Problem::from_toml(
        r#"
        name = "inclined"
        [geometry]
        kind = "rectangle"
        x = [0.0, 2.0]
        y = [0.0, 1.0]
        [nodes]
        spacing = 0.1
        [material]
        young = 1000.0
        poisson = 0.3
        plane = "strain"
        [[boundary]]
        edge = "top"
        displacement = { y = -0.02 }
        [[boundary]]
        edge = "left"
        displacement = { x = 0.0 }
        [contact]
        edge = "bottom"
        obstacle_point = [0.0, -0.005]
        obstacle_normal = [0.1, 1.0]
        "#,
    )
    .unwrap();
    let (force, gap) = compare("inclined", &problem);
    println!("inclined: forces {force:.1e}, gaps {gap:.1e}");
    let s = solve_with(&problem, ContactSolver::ActiveSet);
    let c = s.contact.as_ref().unwrap();
    let closed = c.closed.iter().filter(|&&v| v).count();
    assert!(closed > 0 && closed < c.closed.len(), "a partial contact zone: {closed}");
}

/// Two bodies: the problem file is refused with the key named; a problem built in code
/// reaches the solver and is refused there.
#[test]
fn two_bodies_are_refused() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/two_blocks.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let with = text.replace("[contact]\n", "[contact]\nsolver = \"active_set\"\n");
    assert_ne!(with, text);
    let err = Problem::from_toml(&with).unwrap_err().to_string();
    assert!(err.contains("contact.solver") && err.contains("rigid obstacle"), "{err}");
    let mut p = Problem::from_toml(&text).unwrap();
    p.contact.as_mut().unwrap().solver = ContactSolver::ActiveSet;
    match mlpg_contact::solve(&p) {
        Err(Error::Lcp(LcpError::ActiveSet(ActiveSetError::TwoBodies))) => {}
        other => panic!("expected the two-body refusal, got {:?}", other.err()),
    }
}

/// `"auto"` (the default) takes the active-set solver from `ContactSolver::AUTO_THRESHOLD`
/// candidates on: a strip 100 × 1 at spacing 0.1, clamped on the left (its corner is no
/// candidate), has exactly 1 000; one candidate fewer (the strip 99.9 long) stays with Lemke.
/// The active-set answer equals Lemke's as above.
#[test]
fn auto_switches_at_the_threshold() {
    let strip = |length: f64| {
        Problem::from_toml(&format!(
            r#"
            name = "strip"
            [geometry]
            kind = "rectangle"
            x = [0.0, {length:?}]
            y = [-0.5, 0.5]
            [nodes]
            spacing = 0.1
            [material]
            young = 30000.0
            poisson = 0.3
            plane = "stress"
            [[boundary]]
            edge = "left"
            displacement = {{ x = 0.0, y = 0.0 }}
            [[boundary]]
            edge = "top"
            traction = {{ y = -1.0 }}
            [contact]
            edge = "bottom"
            obstacle_point = [0.0, -0.51]
            obstacle_normal = [0.0, 1.0]
            "#
        ))
        .unwrap()
    };
    let at = strip(100.0);
    assert_eq!(at.contact.unwrap().solver, ContactSolver::Auto);
    let s = mlpg_contact::solve(&at).unwrap();
    let c = s.contact.as_ref().unwrap();
    assert_eq!(c.candidates.len(), ContactSolver::AUTO_THRESHOLD);
    assert!(c.active_set.is_some(), "auto did not take the active-set solver");
    check_own("strip at the threshold", &s);
    let (force, gap) = compare("strip at the threshold", &at);
    println!("strip 100 × 1: forces {force:.1e}, gaps {gap:.1e}");
    let below = strip(99.9);
    let s = mlpg_contact::solve(&below).unwrap();
    let c = s.contact.as_ref().unwrap();
    assert_eq!(c.candidates.len(), ContactSolver::AUTO_THRESHOLD - 1);
    assert!(c.active_set.is_none(), "auto left Lemke below the threshold");
}

/// `summary.json` of an active-set run records the solver, the iterations, the changes after
/// each iteration (ending with 0) and the scaled residuals; the compliance checks of `M` are
/// absent (no `M` was formed), and a Lemke run says `"lemke"`.
#[test]
fn summary_records_the_solver() {
    let mut problem = shipped("beam_on_foundation.toml");
    for solver in [ContactSolver::ActiveSet, ContactSolver::Lemke] {
        problem.contact.as_mut().unwrap().solver = solver;
        let out = std::env::temp_dir().join(format!("mlpg-as-{solver:?}-{}", std::process::id()));
        let input = serde_json::Value::Null;
        let report = mlpg_contact::run(&problem, &out, input, &mut mlpg_contact::Silent).unwrap();
        let v: serde_json::Value = serde_json::from_str(&report.summary.to_json()).unwrap();
        let lcp = &v["lcp"];
        match solver {
            ContactSolver::ActiveSet => {
                assert_eq!(lcp["solver"], "active_set");
                let a = &lcp["active_set"];
                let changes = a["changes_per_iteration"].as_array().unwrap();
                assert_eq!(changes.len() as u64, a["iterations"].as_u64().unwrap());
                assert_eq!(changes.last().unwrap(), 0);
                assert_eq!(lcp["pivots"], a["iterations"]);
                assert_eq!(a["end"], "converged");
                assert!(lcp.get("compliance_min_diagonal").is_none());
                assert!(lcp["max_complementarity"].as_f64().unwrap() <= KKT_TOLERANCE);
                assert!(lcp["min_z"].as_f64().unwrap() >= -KKT_TOLERANCE);
            }
            _ => {
                assert_eq!(lcp["solver"], "lemke");
                assert!(lcp.get("active_set").is_none());
                assert!(lcp["compliance_min_diagonal"].as_f64().unwrap() > 0.0);
            }
        }
        std::fs::remove_dir_all(&out).unwrap();
    }
}
