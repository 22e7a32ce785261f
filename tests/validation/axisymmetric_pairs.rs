//! Axisymmetric elastic pairs (docs/method.md §9.6): two bodies of revolution in contact. The
//! candidates (body 1) are rings whose unknown is the ring's total force `F_c`; the target
//! (body 2) receives `F_c / 2π` per radian at the same radius, spread over its cells (MFVM) or
//! nodes (FE) in proportion to `∫ r ds` (`∫ N_a r ds`) over the candidate's segment projected
//! onto the target edge; the gap is read at the paired point, as in plane.
//!
//! 1. **Two solid cylinders pressed end to end** (radius `R = 1`, heights 1, the upper one
//!    `E₁ = 1`, the lower `E₂ = 2`, `ν = 0.3` for both, non-matching layouts, the upper top
//!    pushed down by `δ = 0.01`, the lower bottom on a roller, a frictionless interface): the
//!    uniaxial state, each body `σ_zz = −p`, `u_r = ν p r / E_i`, with `p = δ / (1/E₁ + 1/E₂)`
//!    reproduced by both methods. Every ring's pressure is `p` (the axis ring included), the
//!    total force `πR² p`, each body's axial reaction per radian `∓(R²/2) p`, to round-off: the
//!    `2π` and the `r` weighting of the target's share (an unweighted share moves the load
//!    inwards and breaks the uniform state on non-matching layouts). A two-body `[contact]`
//!    (MFVM structured and jittered, FE) and the same pair as a `[[contact]]` scene (the
//!    lower body's top against the upper body's bottom); Lemke and the active set. Along a
//!    load path (`[[step]]`, `μ = 1e-12`) the same pair equals its one-step answer.
//! 2. **Hertz: an elastic sphere on an elastic block** (Hertz 1882; Johnson, *Contact
//!    Mechanics* (1985), §4.2, eqs. 4.22–4.24, with the combined modulus
//!    `1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂` and `1/R = 1/R₁ + 1/R₂`, here `R₂ = ∞`): the
//!    hemisphere of `axisymmetric_contact.rs` (`R = 1`, `E₁ = 1`, `ν₁ = 0.3`, its equatorial
//!    plane pushed down by 0.015) on the cylinder block `[0, 1] × [−1, 0]` (`E₂ = 2`,
//!    `ν₂ = 0.25`, its bottom on a roller). For the computed axial force `F`,
//!    `a = (3FR/(4E*))^(1/3)`, `p₀ = 3F/(2πa²)`; `a`, `p₀` fitted from `p²` linear in `r²`.
//!    The approach `δ = a²/R` is not compared: the displacements prescribed are the equatorial
//!    plane's and the block's bottom, so the approach measured includes both bodies' bulk
//!    compression, which Hertz's half-spaces leave out. `a/R ≈ 0.125`, an eighth of the
//!    block's radius and depth: the finite block and Hertz's parabolic profile leave a few
//!    tenths of a percent, the limit the refinement below approaches.

use super::axisymmetric_contact::{SPHERE_SECTION, Sphere, measure_with};
use super::common::*;
use mlpg_contact::Solution;
use mlpg_contact::problem::Problem;
use std::f64::consts::{PI, TAU};

/// The upper body's (the sphere's, the upper cylinder's) modulus and Poisson's ratio.
const E1: f64 = 1.0;
const NU1: f64 = 0.3;
/// The lower body's (the block's, the lower cylinder's).
const E2: f64 = 2.0;

/// The two cylinders of case 1: `layout` of both node sets, `method`, `solver`; `scene`
/// gives the contact as a `[[contact]]` table on the lower body (the multibody path).
fn cylinders(layout: &str, method: &str, solver: &str, scene: bool) -> Problem {
    Problem::from_toml(&cylinders_text(layout, method, solver, scene)).unwrap()
}

/// The TOML of [`cylinders`] (the contact table last).
pub(super) fn cylinders_text(layout: &str, method: &str, solver: &str, scene: bool) -> String {
    let contact = match scene {
        false => {
            format!("[contact]\nedge = \"bottom\"\ntarget_edge = \"top\"\nsolver = \"{solver}\"")
        }
        true => format!(
            "[[contact]]\nbody = \"lower\"\nedge = \"top\"\ntarget_body = \"upper\"\ntarget_edge = \"bottom\"\nsolver = \"{solver}\""
        ),
    };
    format!(
        r#"
        [discretisation]
        method = "{method}"
        [[body]]
        name = "upper"
        geometry = {{ kind = "rectangle", x = [0.0, 1.0], y = [1.0, 2.0] }}
        nodes = {{ spacing = 0.125, layout = "{layout}" }}
        material = {{ young = {E1:?}, poisson = {NU1:?}, plane = "axisymmetric" }}
        boundary = [ {{ edge = "top", displacement = {{ y = -0.01 }} }} ]
        [[body]]
        name = "lower"
        geometry = {{ kind = "rectangle", x = [0.0, 1.0], y = [0.0, 1.0] }}
        nodes = {{ spacing = 0.1, layout = "{layout}" }}
        material = {{ young = {E2:?}, poisson = {NU1:?}, plane = "axisymmetric" }}
        boundary = [ {{ edge = "bottom", displacement = {{ y = 0.0 }} }} ]
        {contact}
        "#
    )
}

/// The contact solution of a pair, whether a two-body `[contact]` or a scene's only pair, and
/// the solutions of the upper and lower bodies.
fn pair(s: &Solution) -> (&mlpg_contact::solution::ContactSolution, &Solution, &Solution) {
    let (pairs, lower) = (s.pairs(), s.body(1).expect("two bodies"));
    assert_eq!(pairs.len(), 1, "one pair");
    (pairs[0], s, lower)
}

#[test]
fn two_cylinders_end_to_end_carry_the_uniaxial_pressure_over_rings() {
    let delta = 0.01;
    let p = delta / (1.0 / E1 + 1.0 / E2);
    let cases = [
        ("structured", "mfvm", false),
        ("jittered", "mfvm", false),
        ("structured", "fem", false),
        ("structured", "mfvm", true),
        ("structured", "fem", true),
    ];
    for (layout, method, scene) in cases {
        let mut forces: Vec<Vec<f64>> = Vec::new();
        for solver in ["lemke", "active_set"] {
            let label = format!("{layout} {method} {solver}{}", if scene { " scene" } else { "" });
            let s = mlpg_contact::solve(&cylinders(layout, method, solver, scene)).unwrap();
            let (c, upper, lower) = pair(&s);
            let worst = c.pressure.iter().map(|q| (q - p).abs() / p).fold(0.0, f64::max);
            println!("cylinder pair {label}: pressure off by {worst:.2e}");
            assert!(worst < 1e-9, "{label}: pressure off by {worst:.2e}");
            assert!(c.closed.iter().all(|&k| k), "{label}: an open candidate");
            let total: f64 = c.lcp.z.iter().sum();
            let exact = PI * p;
            assert!((total - exact).abs() < 1e-9 * exact, "{label}: F {total}");
            // Each body's axial balance per radian: its reaction −(+)∫ σ_zz r dr = ∓ p/2.
            for (body, sign) in [(upper, -1.0), (lower, 1.0)] {
                let r = body.reaction_force[1];
                assert!((r - sign * 0.5 * p).abs() < 1e-9 * p, "{label}: reaction {r}");
                assert!((body.contact_force[1] + r).abs() < 1e-9 * p, "{label}: contact");
                assert!(body.equilibrium_error < 1e-9, "{label}: {}", body.equilibrium_error);
            }
            assert_lcp_residuals(&label, &c.lcp.residuals, 1e-9);
            forces.push(c.lcp.z.clone());
        }
        let d = forces[0].iter().zip(&forces[1]).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(d < 1e-8 * PI * p, "{layout} {method}: active set against Lemke {d:.2e}");
    }
}

/// The cylinder pair along a load path (docs/method.md §8): the upper top pushed down in one
/// `[[step]]` of 3 increments with `μ = 1e-12` equals the frictionless one-step answer (the
/// frictionless problem has no path; `μ → 0` is frictionless), to 1e-9 of the ring force, on
/// the two-body `[contact]` and the `[[contact]]` scene, each body's per-radian balance
/// checked at the end (observed 3.8e-13 and 4.1e-13). The path's condensed blocks take the
/// rings' weights on both bodies; `μ = 1e-12` checks the frictional path's machinery, not the
/// size of the tangential forces.
#[test]
fn the_cylinder_pair_along_a_path_with_vanishing_friction_is_frictionless() {
    for scene in [false, true] {
        let one = mlpg_contact::solve(&cylinders("structured", "mfvm", "lemke", scene)).unwrap();
        let text = cylinders_text("structured", "mfvm", "lemke", scene)
            .replace("y = -0.01", "y = 0.0")
            + "friction = 1e-12\n[[step]]\nincrements = 3\nboundary = [{ body = \"upper\", edge = \"top\", displacement = { y = -0.01 } }]\n";
        let path = mlpg_contact::solve(&Problem::from_toml(&text).unwrap()).unwrap();
        let (a, b) = (&pair(&one).0.lcp.z, &pair(&path).0.lcp.z);
        let scale = a.iter().copied().fold(0.0, f64::max);
        let d = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale;
        println!("cylinder pair path (scene {scene}): against one step {d:.2e}");
        assert!(d < 1e-9, "scene {scene}: {d:.3e}");
        let (c, upper, lower) = pair(&path);
        assert!(c.friction.is_some(), "scene {scene}: not on the frictional path");
        for body in [upper, lower] {
            assert!(body.equilibrium_error < 1e-9, "scene {scene}: {}", body.equilibrium_error);
        }
    }
}

/// Three solid cylinders stacked (`R = 1`, heights 1, `E` = 1, 2, 1 from the bottom, `ν = 0.3`),
/// the top one's top pushed down by `δ = 0.01`, the bottom one's bottom on a roller, the middle
/// one held along the axis by its two contacts alone (docs/method.md §4.7, §9.6: its search
/// balances `2π` times its per-radian load against the rings' forces; here the load is 0).
/// Exactly, each interface carries `p = δ / (1/E₁ + 1/E₂ + 1/E₃)` at every ring, and the middle
/// body's axial translation puts its bottom at `−p/E₁` (the bottom cylinder's shortening).
/// MFVM and FE, Lemke and the active set.
#[test]
fn a_middle_cylinder_held_by_contact_alone_carries_the_uniaxial_pressure() {
    let delta = 0.01;
    let p = delta / (1.0 + 0.5 + 1.0);
    for method in ["mfvm", "fem"] {
        for solver in ["lemke", "active_set"] {
            let label = format!("stack {method} {solver}");
            let text = format!(
                r#"
                [discretisation]
                method = "{method}"
                [[body]]
                name = "bottom"
                geometry = {{ kind = "rectangle", x = [0.0, 1.0], y = [0.0, 1.0] }}
                nodes = {{ spacing = 0.125 }}
                material = {{ young = 1.0, poisson = 0.3, plane = "axisymmetric" }}
                boundary = [ {{ edge = "bottom", displacement = {{ y = 0.0 }} }} ]
                [[body]]
                name = "middle"
                geometry = {{ kind = "rectangle", x = [0.0, 1.0], y = [1.0, 2.0] }}
                nodes = {{ spacing = 0.1 }}
                material = {{ young = 2.0, poisson = 0.3, plane = "axisymmetric" }}
                [[body]]
                name = "top"
                geometry = {{ kind = "rectangle", x = [0.0, 1.0], y = [2.0, 3.0] }}
                nodes = {{ spacing = 0.125 }}
                material = {{ young = 1.0, poisson = 0.3, plane = "axisymmetric" }}
                boundary = [ {{ edge = "top", displacement = {{ y = -0.01 }} }} ]
                [[contact]]
                body = "middle"
                edge = "bottom"
                target_body = "bottom"
                target_edge = "top"
                solver = "{solver}"
                [[contact]]
                body = "top"
                edge = "bottom"
                target_body = "middle"
                target_edge = "top"
                solver = "{solver}"
                "#
            );
            let s = mlpg_contact::solve(&Problem::from_toml(&text).unwrap()).unwrap();
            let m = s.multibody().unwrap();
            for c in m.pairs {
                let worst = c.pressure.iter().map(|q| (q - p).abs() / p).fold(0.0, f64::max);
                println!("{label}: pressure off by {worst:.2e}");
                assert!(worst < 1e-8, "{label}: pressure off by {worst:.2e}");
            }
            for body in std::iter::once(&s).chain(m.bodies) {
                assert!(body.equilibrium_error < 1e-8, "{label}: {}", body.equilibrium_error);
            }
            let (held, rigid) = m.contact.held.first().expect("the middle body is held");
            assert_eq!(*held, 1, "{label}: the held body");
            // The pin's displacement: the bottom's shortening plus the middle's own strain.
            let z = rigid.pin_point[1];
            let exact = -p / 1.0 - p / 2.0 * (z - 1.0);
            let found = rigid.translation[1];
            println!("{label}: pin at z = {z}: {found:.6e} against {exact:.6e}");
            assert!((found - exact).abs() < 1e-8 * delta, "{label}: {found} against {exact}");
        }
    }
}

/// The Hertz pair's lower body, the block `[0, 1] × [−1, 0]` (a `[[body]]` table): MFVM with
/// spacing 0.05 and a box `[0, 0.2] × [−0.05, 0]` at `h`; FE on a uniform grid of spacing `h`.
fn block(method: &str, h: f64) -> String {
    let nodes = match method {
        "mfvm" => format!(
            "[body.nodes]\nspacing = 0.05\n[[body.nodes.refine]]\nx = [0.0, 0.2]\ny = [-0.05, 0.0]\nspacing = {h:?}"
        ),
        _ => format!("[body.nodes]\nspacing = {h:?}"),
    };
    format!(
        r#"
        [[body]]
        name = "block"
        [body.geometry]
        kind = "rectangle"
        x = [0.0, 1.0]
        y = [-1.0, 0.0]
        {nodes}
        [body.material]
        young = {E2:?}
        poisson = {NU2:?}
        plane = "axisymmetric"
        [[body.boundary]]
        edge = "bottom"
        displacement = {{ y = 0.0 }}
        "#
    )
}

const NU2: f64 = 0.25;

/// The sphere (a `[[body]]` table): MFVM with the box refined to `h` around the contact
/// (`axisymmetric_contact.rs`), FE on the Gmsh mesh `hertz_cylinder_<level>.msh`.
fn sphere(method: &str, h: f64, level: usize) -> String {
    let (geometry, nodes) = match method {
        "mfvm" => (
            SPHERE_SECTION.replace("[geometry]", "[body.geometry]"),
            format!(
                "[body.nodes]\nspacing = 0.05\n[[body.nodes.refine]]\nx = [0.0, 0.2]\ny = [0.0, 0.05]\nspacing = {h:?}"
            ),
        ),
        _ => {
            let dir =
                std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fem_meshes");
            let file = dir.join(format!("hertz_cylinder_{level}.msh"));
            (
                format!(
                    "[body.geometry]\nkind = \"gmsh\"\nfile = \"{}\"\nsurface = \"cylinder\"",
                    file.display()
                ),
                "[body.nodes]\nfrom = \"mesh\"".to_string(),
            )
        }
    };
    format!(
        r#"
        [[body]]
        name = "sphere"
        {geometry}
        {nodes}
        [body.material]
        young = {E1:?}
        poisson = {NU1:?}
        plane = "axisymmetric"
        [[body.boundary]]
        edge = "top"
        displacement = {{ y = -0.015 }}
        "#
    )
}

/// The Hertz pair: the sphere (MFVM box `h`, FE mesh `level`) on the block (MFVM box `h`, FE
/// grid `block_h`).
fn hertz_pair(method: &str, h: f64, level: usize, block_h: f64, solver: &str) -> Problem {
    let beta = if method == "mfvm" { "beta = 0.5" } else { "" };
    let b = if method == "mfvm" { h } else { block_h };
    Problem::from_toml(&format!(
        "[discretisation]\nmethod = \"{method}\"\n{beta}\n{}\n{}\n[contact]\nedge = \"arc\"\ntarget_edge = \"top\"\nsolver = \"{solver}\"\n",
        sphere(method, h, level),
        block(method, b)
    ))
    .unwrap()
}

/// `1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂`.
fn e_star() -> f64 {
    1.0 / ((1.0 - NU1 * NU1) / E1 + (1.0 - NU2 * NU2) / E2)
}

/// Checks the block's side of a Hertz pair run (its axial balance per radian against the
/// rings' force) and fits Hertz on the sphere's side ([`measure_with`]).
fn measure_pair(label: &str, s: &Solution) -> Sphere {
    let out = measure_with(label, s, e_star());
    let block = s.body(1).expect("the block");
    assert!(
        block.equilibrium_error < 1e-8,
        "{label}: block equilibrium {}",
        block.equilibrium_error
    );
    let balance = block.reaction_force[1] - out.force / TAU;
    assert!(balance.abs() < 1e-8 * out.force / TAU, "{label}: block balance {balance}");
    out
}

/// MFVM (boxes 0.02 and 0.01 on both bodies) and FE (sphere meshes 1 and 2, block grids 0.04
/// and 0.02): at the finer level each is within 1 % of Hertz with the combined modulus in `a`
/// and `p₀` (observed MFVM −0.16 %, −0.34 %; FE −0.001 %, −0.10 %: the finite block and
/// Hertz's idealisation at `a/R ≈ 0.125` — the `#[ignore]`d study's finer levels stay there),
/// each of `F`, `a`, `p₀` changes by less than 0.5 % over the refinement (observed ≤ 0.2 %),
/// and MFVM and FE agree within 0.5 % (observed 0.27 % in `F` and `p₀`: the MFVM's box leaves
/// its far field at 0.05, as for the sphere on a rigid flat in `axisymmetric_contact.rs`).
#[test]
fn hertz_sphere_on_an_elastic_block_mfvm_and_fe() {
    let mfvm: Vec<Sphere> = [0.02, 0.01]
        .iter()
        .map(|&h| {
            measure_pair(
                &format!("pair MFVM h = {h}"),
                &solve(hertz_pair("mfvm", h, 0, h, "lemke")),
            )
        })
        .collect();
    let fem: Vec<Sphere> = [(1, 0.04), (2, 0.02)]
        .iter()
        .map(|&(l, b)| {
            measure_pair(
                &format!("pair FE level {l}"),
                &solve(hertz_pair("fem", 0.0, l, b, "lemke")),
            )
        })
        .collect();
    for (name, runs) in [("MFVM", &mfvm), ("FE", &fem)] {
        let fine = &runs[1];
        assert!(fine.radius_error.abs() < 0.01, "{name}: a error {}", fine.radius_error);
        assert!(fine.peak_error.abs() < 0.01, "{name}: p0 error {}", fine.peak_error);
        let (v0, v1) = (runs[0].values(), runs[1].values());
        for (i, what) in ["F", "a", "p0"].iter().enumerate() {
            let change = (v1[i] - v0[i]).abs() / v1[i];
            println!("pair {name} {what}: change over the refinement {change:.2e}");
            assert!(change < 0.005, "{name} {what}: changes by {change:.3e}");
        }
    }
    let (f, m) = (fem[1].values(), mfvm[1].values());
    for (i, name) in ["F", "a", "p0"].iter().enumerate() {
        let diff = (f[i] - m[i]).abs() / f[i];
        println!("pair {name}: FE {:.6e} MFVM {:.6e} relative difference {diff:.2e}", f[i], m[i]);
        assert!(diff < 0.005, "{name}: FE and MFVM differ by {diff:.3e}");
    }
}

/// The active set gives Lemke's ring forces on the Hertz pair, MFVM and FE, to 1e-8 of the
/// largest.
#[test]
fn hertz_pair_active_set_equals_lemke() {
    for (label, lemke, active) in [
        (
            "MFVM",
            hertz_pair("mfvm", 0.02, 0, 0.0, "lemke"),
            hertz_pair("mfvm", 0.02, 0, 0.0, "active_set"),
        ),
        (
            "FE",
            hertz_pair("fem", 0.0, 0, 0.04, "lemke"),
            hertz_pair("fem", 0.0, 0, 0.04, "active_set"),
        ),
    ] {
        let (a, b) = (solve(lemke), solve(active));
        let (za, zb) = (&a.contact().unwrap().lcp.z, &b.contact().unwrap().lcp.z);
        let scale = za.iter().copied().fold(0.0, f64::max);
        let worst = za.iter().zip(zb).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale;
        println!("hertz pair {label}: active set against Lemke {worst:.2e}");
        assert!(worst < 1e-8, "{label}: {worst:.3e}");
        assert!(b.contact().unwrap().active_set.is_some(), "{label}: not the active set");
    }
}

/// The refinement study (`cargo test --release --test validation axisymmetric_pairs --
/// --ignored --nocapture`): finer MFVM boxes and FE meshes.
#[test]
#[ignore = "a refinement study of several seconds; the numbers are in docs/dev/axisymmetric.md"]
fn hertz_pair_study() {
    for h in [0.02, 0.01, 0.005] {
        measure_pair(&format!("pair MFVM h = {h}"), &solve(hertz_pair("mfvm", h, 0, h, "lemke")));
    }
    for (l, b) in [(0, 0.04), (1, 0.04), (1, 0.02), (2, 0.02), (2, 0.01)] {
        measure_pair(&format!("pair FE level {l}"), &solve(hertz_pair("fem", 0.0, l, b, "lemke")));
    }
}

fn solve(p: Problem) -> Solution {
    mlpg_contact::solve(&p).unwrap()
}
