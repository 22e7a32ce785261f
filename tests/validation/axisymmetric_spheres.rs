//! Two elastic spheres of revolution pressed together (docs/method.md §9.6, "A curved
//! target"): the candidates are rings on the upper sphere's arc, the target the lower sphere's
//! arc, each candidate paired with its closest point on that circle, the normal the bisector
//! of the two arcs' normals there (`contact::TargetEdge::bisector`).
//!
//! **Hertz** (Hertz 1882; Johnson, *Contact Mechanics* (1985), §4.2, eqs. 4.22–4.24): with
//! `1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂` and `1/R = 1/R₁ + 1/R₂`, for the axial force `F`
//! `a = (3FR/(4E*))^(1/3)` and `p₀ = 3F/(2πa²)`; `a`, `p₀` fitted from `p²` linear in `r²` over
//! the closed rings (as `axisymmetric_contact.rs`). The upper sphere `R₁ = 1`, `E₁ = 1`,
//! `ν₁ = 0.3`, its equatorial plane pushed down by 0.008; the lower `R₂ = 2`, `E₂ = 2`,
//! `ν₂ = 0.25`, its equatorial plane on a roller. `R = 2/3`, `a/R ≈ 0.11` (`a/R₁ ≈ 0.074`).
//! The approach is not compared (it includes both hemispheres' bulk compression).
//!
//! Measured by the CLI on the same file (docs/dev/axisymmetric.md, increment 7e; far spacing
//! 0.05, box `[0, 0.15]` by 0.03 around the contact): box spacing 0.01, 0.005, 0.0025 gave
//! `a` +0.29 %, +0.42 %, +0.14 % and `p₀` −0.56 %, −0.44 %, −0.43 % against Hertz with the
//! target's normal; with the bisector the box at 0.01 gives +0.33 %, −0.72 %. The test
//! runs the box at 0.01 and asks for 2 % (the task's bound; Hertz's idealisation at
//! `a/R ≈ 0.11` and the far field's spacing leave about half a percent, which the refinement
//! above does not remove).
//!
//! **The FE twin** (`two_elastic_spheres_fe_against_hertz_and_mfvm`): both sections from one
//! Gmsh file (`tests/data/fem_meshes/two_spheres_<level>.msh`, written by
//! `make_two_spheres.py` from `two_spheres.geo`: 9-node quadrilaterals, element size `hc`
//! within 0.15 of the contact, growing to 0.2 at distance 1), the lower arc the target as the
//! mesh's polyline. Mesh 1 (`hc` = 0.01, 3 718 nodes): `a` +0.16 %, `p₀` −0.31 % against
//! Hertz. The series (`examples/studies/two_spheres.rs`; docs/dev/axisymmetric.md, 7e): FE
//! `hc` = 0.02 … 0.0025 and MFVM with a middle box refined to 0.003125 converge to the same
//! answer (with the bisector: FE mesh 2 and that MFVM within 0.001 % in `F`, 0.05 % in `a`
//! and `p₀`); the MFVM box 0.01 is 0.10 % low in `F` and 0.48 % low in `p₀` (its spacing
//! between the box and the far field), FE mesh 1 0.11 % high in `F`. The test asks FE and
//! MFVM to agree within 1.5 × the sum of those measured errors.

use super::common::*;
use mlpg_contact::Solution;
use mlpg_contact::problem::Problem;
use std::f64::consts::TAU;

const E1: f64 = 1.0;
const NU1: f64 = 0.3;
const R1: f64 = 1.0;
const E2: f64 = 2.0;
const NU2: f64 = 0.25;
const R2: f64 = 2.0;

/// The two hemispheres' sections with the box around the contact at spacing `h` (0.05
/// elsewhere), MFVM, `β = 0.5`.
pub(super) fn spheres(h: f64) -> Problem {
    spheres_mfvm(None, h)
}

/// [`spheres`] with, when `mid` is given, a middle box `[0, 0.5]` by 0.25 around the contact
/// at spacing `mid` (between the far spacing 0.05 and the contact box's `h`; the study's
/// MFVM refinement, `examples/studies/two_spheres.rs`).
pub(super) fn spheres_mfvm(mid: Option<f64>, h: f64) -> Problem {
    let middle = |y: &str| match mid {
        Some(m) => format!("[[body.nodes.refine]]\nx = [0.0, 0.5]\ny = {y}\nspacing = {m:?}"),
        None => String::new(),
    };
    let (upper_mid, lower_mid) = (middle("[0.0, 0.25]"), middle("[-0.25, 0.0]"));
    Problem::from_toml(&format!(
        r#"
        [discretisation]
        beta = 0.5
        [[body]]
        name = "upper"
        [body.geometry]
        kind = "curves"
        start = [0.0, 0.0]
        curves = [
            {{ name = "arc", to = [0.5, 0.1339745962155614], center = [0.0, {R1:?}] }},
            {{ name = "rim", to = [1.0, 1.0], center = [0.0, {R1:?}] }},
            {{ name = "top", to = [0.0, 1.0] }},
            {{ name = "axis", to = [0.0, 0.0] }},
        ]
        [body.nodes]
        spacing = 0.05
        {upper_mid}
        [[body.nodes.refine]]
        x = [0.0, 0.15]
        y = [0.0, 0.03]
        spacing = {h:?}
        [body.material]
        young = {E1:?}
        poisson = {NU1:?}
        plane = "axisymmetric"
        [[body.boundary]]
        edge = "top"
        displacement = {{ y = -0.008 }}
        [[body]]
        name = "lower"
        [body.geometry]
        kind = "curves"
        start = [0.0, -2.0]
        curves = [
            {{ name = "bottom", to = [2.0, -2.0] }},
            {{ name = "rim", to = [1.0, -0.2679491924311228], center = [0.0, -{R2:?}] }},
            {{ name = "arc", to = [0.0, 0.0], center = [0.0, -{R2:?}] }},
            {{ name = "axis", to = [0.0, -2.0] }},
        ]
        [body.nodes]
        spacing = 0.05
        {lower_mid}
        [[body.nodes.refine]]
        x = [0.0, 0.15]
        y = [-0.03, 0.0]
        spacing = {h:?}
        [body.material]
        young = {E2:?}
        poisson = {NU2:?}
        plane = "axisymmetric"
        [[body.boundary]]
        edge = "bottom"
        displacement = {{ y = 0.0 }}
        [contact]
        edge = "arc"
        target_edge = "arc"
        "#
    ))
    .unwrap()
}

/// The committed FE mesh `tests/data/fem_meshes/two_spheres_<level>.msh`.
pub(super) fn mesh_file(level: usize) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("tests/data/fem_meshes/two_spheres_{level}.msh"))
}

/// The same two spheres by FE on a Gmsh mesh of both sections (`two_spheres.geo`: surfaces
/// `upper` and `lower`, 9-node quadrilaterals with curved sides, element size `hc` within
/// 0.15 of the contact growing to 0.2; the lower arc is the target as the mesh's polyline of
/// its corner and middle nodes).
pub(super) fn spheres_fem(file: &std::path::Path) -> Problem {
    let body = |name: &str, young: f64, poisson: f64, edge: &str, uy: f64| {
        format!(
            r#"
            [[body]]
            name = "{name}"
            [body.geometry]
            kind = "gmsh"
            file = "{}"
            surface = "{name}"
            [body.nodes]
            from = "mesh"
            [body.material]
            young = {young:?}
            poisson = {poisson:?}
            plane = "axisymmetric"
            [[body.boundary]]
            edge = "{edge}"
            displacement = {{ y = {uy:?} }}
            "#,
            file.display()
        )
    };
    Problem::from_toml(&format!(
        "[discretisation]\nmethod = \"fem\"\n{}\n{}\n[contact]\nedge = \"upper_arc\"\ntarget_edge = \"lower_arc\"\n",
        body("upper", E1, NU1, "upper_top", -0.008),
        body("lower", E2, NU2, "lower_bottom", 0.0),
    ))
    .unwrap()
}

/// What a two-sphere run gives: the rings' axial force, the fitted contact radius and peak
/// pressure, their errors against Hertz for that force, the closed rings.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pair {
    pub(super) force: f64,
    pub(super) radius: f64,
    pub(super) peak: f64,
    pub(super) radius_error: f64,
    pub(super) peak_error: f64,
    pub(super) closed: usize,
}

/// Checks a two-sphere solution — complementarity (1e-9), both bodies' balance and the
/// pair's (the rings' axial force per radian leaves the upper body and enters the lower;
/// each ring's target weights sum to its own `1/2π`), Newton's third law ring by ring, one
/// closed interval of at least 6 rings — and fits Hertz (see the header).
pub(super) fn measure(label: &str, s: &Solution) -> Pair {
    let c = s.contact().unwrap();
    assert_lcp_residuals(label, &c.lcp.residuals, 1e-9);
    let lower = s.body(1).expect("the lower sphere");
    assert!(s.equilibrium_error < 1e-8, "{label}: upper equilibrium {}", s.equilibrium_error);
    assert!(
        lower.equilibrium_error < 1e-8,
        "{label}: lower equilibrium {}",
        lower.equilibrium_error
    );
    let axial: f64 = c.candidates.normals.iter().zip(&c.lcp.z).map(|(n, f)| n[1] * f).sum();
    assert!(axial > 0.0, "{label}: the rings push the upper sphere up: {axial}");
    let scale = axial / TAU;
    let upper_balance = s.reaction_force[1] + axial / TAU;
    let lower_balance = lower.reaction_force[1] - axial / TAU;
    assert!(upper_balance.abs() < 1e-8 * scale, "{label}: upper balance {upper_balance}");
    assert!(lower_balance.abs() < 1e-8 * scale, "{label}: lower balance {lower_balance}");
    // Newton's third law ring by ring: opposite directions, equal weights.
    let target = c.target.as_ref().expect("the target's operator");
    for k in 0..c.candidates.len() {
        let (d1, d2) = (c.candidates.operator.direction(k), target.direction(k));
        assert!(
            (d1[0] + d2[0]).abs() + (d1[1] + d2[1]).abs() == 0.0,
            "{label}: ring {k}: {d1:?} {d2:?}"
        );
        let w1: f64 = c.candidates.operator.owners[k].iter().map(|o| o.1).sum();
        let w2: f64 = target.owners[k].iter().map(|o| o.1).sum();
        assert!((w1 - w2).abs() < 1e-14, "{label}: ring {k}: weights {w1} {w2}");
    }
    let e_star = 1.0 / ((1.0 - NU1 * NU1) / E1 + (1.0 - NU2 * NU2) / E2);
    let radius = 1.0 / (1.0 / R1 + 1.0 / R2);
    let a = (3.0 * axial * radius / (4.0 * e_star)).cbrt();
    let p0 = 3.0 * axial / (TAU * a * a);
    let (peak, fitted, closed) = hertz_fit(c);
    assert_eq!(c.onset.closed_intervals, 1, "{label}");
    assert!(closed >= 6, "{label}: only {} closed rings", closed);
    let out = Pair {
        force: axial,
        radius: fitted,
        peak,
        radius_error: fitted / a - 1.0,
        peak_error: peak / p0 - 1.0,
        closed,
    };
    println!(
        "two spheres: {label:<12} F = {axial:.6e}  a/R = {:.4}  a {:+.3e}  p0 {:+.3e}  closed {}",
        a / radius,
        out.radius_error,
        out.peak_error,
        closed
    );
    out
}

/// MFVM with the box at 0.01: Hertz's `a` and `p₀` within 2 % (see the header).
#[test]
fn two_elastic_spheres_against_hertz() {
    let m = measure("MFVM", &mlpg_contact::solve(&spheres(0.01)).unwrap());
    assert!(
        m.radius_error.abs() < 0.02 && m.peak_error.abs() < 0.02,
        "a {:+.3e}, p0 {:+.3e}",
        m.radius_error,
        m.peak_error
    );
}

/// The FE twin (mesh `two_spheres_1.msh`, `hc` = 0.01) against Hertz (2 %) and against the
/// MFVM (box 0.01) within the two discretisations' measured errors (see the header).
#[test]
fn two_elastic_spheres_fe_against_hertz_and_mfvm() {
    let s = mlpg_contact::solve(&spheres_fem(&mesh_file(1))).unwrap();
    let fe = measure("FE mesh 1", &s);
    // The upper sphere's axis node is a candidate (its normal the axial one, not the lower
    // polyline's end piece's, which would leave it out, free to overlap) and closed.
    let c = s.contact().unwrap();
    let axis = c.candidates.points.iter().position(|p| p[0] == 0.0).expect("the axis ring");
    assert_eq!(c.candidates.normals[axis], [0.0, 1.0]);
    assert!(c.closed[axis], "the axis ring is open: gap {:e}", c.gap[axis]);
    assert!(
        fe.radius_error.abs() < 0.02 && fe.peak_error.abs() < 0.02,
        "FE: a {:+.3e}, p0 {:+.3e} ({} closed)",
        fe.radius_error,
        fe.peak_error,
        fe.closed
    );
    let mfvm = measure("MFVM", &mlpg_contact::solve(&spheres(0.01)).unwrap());
    let (df, da, dp) =
        (fe.force / mfvm.force - 1.0, fe.radius / mfvm.radius - 1.0, fe.peak / mfvm.peak - 1.0);
    println!("two spheres: FE / MFVM − 1: F {df:+.3e}  a {da:+.3e}  p0 {dp:+.3e}");
    assert!(df.abs() < F_AGREEMENT, "F: FE / MFVM − 1 = {df:+.3e}");
    assert!(da.abs() < A_AGREEMENT, "a: FE / MFVM − 1 = {da:+.3e}");
    assert!(dp.abs() < P_AGREEMENT, "p0: FE / MFVM − 1 = {dp:+.3e}");
}

/// FE / MFVM − 1 bounds: 1.5 × the sum of the two runs' measured errors against the finest
/// runs, remeasured with the bisector normal (the mean of FE mesh 2 and MFVM with the middle
/// box at 0.003125 and the contact box at 0.0015625, which agree to 0.001 %, 0.05 %, 0.04 %
/// in `F`, `a`, `p₀`): FE mesh 1 is at +0.11 %, +0.14 %, −0.01 %, the MFVM box 0.01 at
/// −0.10 %, +0.24 %, −0.48 % (docs/dev/axisymmetric.md, 7e), so 0.32 %, 0.58 %, 0.73 %,
/// rounded down (with the target's normal they were 0.3 %, 0.6 %, 0.75 %). The margin covers
/// the FE's mesh-to-mesh scatter (where the contact edge falls between nodes).
const F_AGREEMENT: f64 = 3e-3;
const A_AGREEMENT: f64 = 5.5e-3;
const P_AGREEMENT: f64 = 7e-3;

/// Two identical spheres (SSNV104, `problems/two_spheres_axisymmetric.toml`) pair along the
/// axis whichever body is the candidate side: the bisector of the two circles' normals is
/// axial within `(r/R)³` at every ring (the target's normal alone is tilted by `r/R`), and
/// the pairing is the same in either order, so swapping the
/// `[[body]]` tables gives the same axial force (observed to 5e-16; checked to 1e-10).
#[test]
fn identical_spheres_pair_along_the_axis_in_either_order() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems/two_spheres_axisymmetric.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let first = text.find("[[body]]").unwrap();
    let second = first + 1 + text[first + 1..].find("[[body]]").unwrap();
    let contact = text.find("[contact]").unwrap();
    let swapped = format!(
        "{}{}{}{}",
        &text[..first],
        &text[second..contact],
        &text[first..second],
        &text[contact..]
    );
    let axial = |text: &str| {
        let s = mlpg_contact::solve(&Problem::from_toml(text).unwrap()).unwrap();
        let c = s.contact().unwrap();
        for (p, n) in c.candidates.points.iter().zip(&c.candidates.normals) {
            // The closest point on the other circle lies on the line through its centre, not
            // at `x_c`'s mirror image: the bisector's radial part is `O((r/R)³)`, not zero.
            let tilt = (p[0] / 50.0).powi(3);
            assert!(n[0].abs() <= tilt && n[1].abs() > 0.0, "normal {n:?} at {p:?}");
        }
        let f: f64 = c.candidates.normals.iter().zip(&c.lcp.z).map(|(n, f)| n[1] * f).sum();
        assert!(c.closed.iter().filter(|&&k| k).count() >= 6);
        f.abs()
    };
    let (f, g) = (axial(&text), axial(&swapped));
    println!("identical spheres: axial force {f:.9e}, swapped {g:.9e}");
    assert!((f / g - 1.0).abs() < 1e-10, "{f} against {g}");
}
