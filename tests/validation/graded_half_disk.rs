//! A graded Gmsh mesh solved with the default discretisation (`beta = "auto"`): the elastic
//! half-disk of radius 1 (plane strain, `E = 1`, `ν = 0.3`) pressed by its flat top (`u_y =
//! −0.01`, `u_x = 0`) onto the rigid line `y = 0`, on the nodes of
//! `tests/data/gmsh/hertz_half_disk_hc0.006_v4.msh` (`hertz_half_disk.geo`: size 0.006 within
//! 0.15 of the lowest point, growing to 0.08 at 0.6 from it; 2 157 nodes, `nodes.from =
//! "mesh"`).
//!
//! **Reference**: Hertz for a cylinder on a rigid flat (Johnson, *Contact Mechanics*, §4.3):
//! `a = √(4PR/(πE*))`, `p₀ = 2P/(πa)`, `E* = E/(1 − ν²)`, for the computed resultant `P` (the
//! whole contact here), measured by `hertz::measure` (a least-squares fit of `p²` against `x²`).
//!
//! **Bounds**: 3 % on `a` and 1 % on `p₀`, the bounds of `hertz.rs` (the Hertz relations
//! assume `a ≪ R`, here `a/R ≈ 0.08`), with complementarity, equilibrium and the checks of `M`.
//!
//! **The claim**: at `β = 0` this node set's compliance is refused (a negative diagonal entry:
//! the mixed method's checkerboard modes on graded nodes, docs/method.md §3.8); the default
//! `"auto"` repeats the solve at `β = 0.5`, says so, and meets the Hertz bounds. A user's first
//! graded mesh no longer meets a refusal.

use super::hertz::measure;
use mlpg_contact::Silent;
use mlpg_contact::pipeline::Outcome;
use mlpg_contact::problem::Problem;

const YOUNG: f64 = 1.0;
const POISSON: f64 = 0.3;

/// The problem file of the half-disk on the mesh `file` (under tests/data/gmsh), with the
/// default discretisation.
fn half_disk(file: &str) -> String {
    let mesh = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gmsh").join(file);
    format!(
        r#"name = "graded_half_disk"
[geometry]
kind = "gmsh"
file = {:?}
surface = "half_disk"
[nodes]
from = "mesh"
[material]
young = {YOUNG}
poisson = {POISSON}
plane = "strain"
[[boundary]]
edge = "top"
displacement = {{ x = 0.0, y = -0.01 }}
[contact]
edge = "arc"
obstacle_point = [0.0, 0.0]
obstacle_normal = [0.0, 1.0]
"#,
        mesh.to_str().unwrap()
    )
}

#[test]
fn a_graded_gmsh_half_disk_solves_with_the_default_discretisation() {
    let problem = Problem::from_toml(&half_disk("hertz_half_disk_hc0.006_v4.msh")).unwrap();
    assert!(problem.discretisation.beta_auto);
    let outcome = Outcome::solve(problem, serde_json::Value::Null, &mut Silent).unwrap();
    let warnings = outcome.summary.warnings.join("\n");
    assert!(warnings.contains("beta = \"auto\": at beta = 0"), "{warnings}");
    assert!(outcome.summary.checks.passed, "{:?}", outcome.summary.checks);
    let s = &outcome.solution;
    let c = s.contact().unwrap();
    let balance = s.reaction_force[1] + c.total_force;
    assert!(balance.abs() < 1e-8 * c.total_force, "balance {balance}");
    let e_star = YOUNG / (1.0 - POISSON * POISSON);
    let m = measure("graded half-disk", s, e_star, 1.0, c.total_force);
    assert!(m.a_over_r < 0.15, "a/R = {}", m.a_over_r);
    assert!(m.half_width.abs() < 0.03, "half-width error {}", m.half_width);
    assert!(m.peak.abs() < 0.01, "peak error {}", m.peak);
}
