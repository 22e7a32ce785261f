//! Bodies with holes (several boundary loops): from curves (`Domain::with_holes`, as
//! `geometry.holes` builds them), from a Gmsh surface whose hole is a second curve loop, and
//! the FE path on that mesh's elements.
//!
//! - Patch test (docs/method.md §3.7) on the square `[-2, 2]²` with holes: a linear
//!   displacement field prescribed on the outer boundary and the traction of its constant
//!   stress on the holes must be reproduced to round-off (1e-10 relative, as
//!   `patch_test.rs`), structured and jittered. A general field with a square hole (the
//!   traction `σ·n` per straight edge), and an isotropic field with a disk hole and the square
//!   hole (the pressure `−σ₀` on both: on the disk's chords the discretisation takes the
//!   chord's normal, so the polygonal hole carries the exact traction).
//! - Kirsch (`kirsch.rs`, whose closed form is used): the full plate `[-5, 5]²` outside the
//!   unit hole at the origin, Kirsch's infinite-plate displacement prescribed on the whole
//!   outer square and the hole traction-free, so the exact solution is Kirsch's field. The
//!   relative max-norm displacement error and the relative energy-norm error at `h = 0.2,
//!   0.1, 0.05`, with their observed rates, compared with the quarter plate of `kirsch.rs`
//!   (rates 1.69 and 1.56 there, with tractions on two sides and rollers on the others).
//! - The same from `tests/data/gmsh/kirsch_full_h{h}_v4.msh` (`kirsch_full.geo`: the hole a
//!   second curve loop, meshed at `h`), nodes laid out inside at `h`: errors and rates within
//!   10 % of the twin's (as `gmsh.rs` asks of the quarter plate's mesh).
//! - The FE path on the second-order meshes `kirsch_full_o2_h{0.2,0.1}_v4.msh` (`method =
//!   "fem"`, `nodes.from = "mesh"`; hole at `h`, corners at `5h`): the displacement error
//!   halves at least from one to the other and stays below the MFVM's at the same `h`
//!   (quadratic isoparametric elements against the linear MLS), so the two methods agree
//!   with each other within the MFVM's own error.
//!
//! MLS supports are discs: one that spans a hole holds nodes on its far side (there is no
//! visibility criterion). Here the support radius `2h` is at most 0.4 against the hole's
//! diameter 2, so a support reaches across only near the hole's rim, where the far-side nodes
//! lie on the same body a chord away; the patch test holds whatever the supports hold (MLS
//! reproduces linear fields), and the Kirsch rates match the quarter plate's (which has no
//! support spanning a hole).

use super::common::*;
use super::kirsch::{POISSON, YOUNG, errors, exact_displacement};
use mlpg_contact::geometry::{Curve, Domain, Point};
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::gmsh::Mesh;
use mlpg_contact::problem::{EdgeCondition, Field, Problem};
use std::path::PathBuf;
use std::sync::Arc;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/gmsh").join(name)
}

fn disk(center: Point, radius: f64, name: &str) -> Domain {
    let p = [center[0] + radius, center[1]];
    Domain::from_curves(vec![Curve::arc_between(p, p, center, true)], vec![name.into()]).unwrap()
}

/// The square hole `[0.4, 1.2] × [-1.2, -0.4]`, edges `s0`–`s3`.
fn square_hole() -> Domain {
    Domain::polygon(
        vec![[0.4, -1.2], [1.2, -1.2], [1.2, -0.4], [0.4, -0.4]],
        ["s0", "s1", "s2", "s3"].map(String::from).to_vec(),
    )
    .unwrap()
}

/// Relative max-norm error of the linear field `exact` on `domain` (outer edges `bottom`,
/// `right`, `top`, `left` prescribed; the holes' edges loaded by `hole_load(k)`).
fn patch_error(
    domain: Domain,
    layout: Layout,
    exact: fn(Point) -> [f64; 2],
    hole_load: &dyn Fn(&Domain, usize) -> EdgeCondition,
) -> f64 {
    let h = 0.1;
    let mut problem = base_problem(domain.clone(), h, layout, plane_stress(YOUNG, POISSON));
    for k in 0..domain.edge_count() {
        problem.boundary[k] = if domain.loop_of(k) == 0 {
            displacement(Arc::new(exact))
        } else {
            hole_load(&domain, k)
        };
    }
    let s = mlpg_contact::solve(&problem).unwrap();
    assert!(s.equilibrium_error < 1e-9, "equilibrium {}", s.equilibrium_error);
    let nodes = mlpg_contact::nodes::for_problem(&problem).unwrap();
    let scale = nodes.points.iter().map(|&p| exact(p)[0].hypot(exact(p)[1])).fold(0.0, f64::max);
    nodes
        .points
        .iter()
        .zip(&s.displacement)
        .map(|(&p, u)| {
            let e = exact(p);
            (u[0] - e[0]).hypot(u[1] - e[1]) / scale
        })
        .fold(0.0, f64::max)
}

fn general(p: Point) -> [f64; 2] {
    [1e-3 * (1.0 + 2.0 * p[0] - 3.0 * p[1]), 1e-3 * (-0.5 + 1.5 * p[0] + 0.7 * p[1])]
}

fn isotropic(p: Point) -> [f64; 2] {
    // Strain 1e-3 in every direction, a rotation and a translation.
    [1e-3 * (0.3 + p[0] - 0.5 * p[1]), 1e-3 * (-0.2 + 0.5 * p[0] + p[1])]
}

#[test]
fn patch_test_with_holes() {
    let outer = || Domain::rectangle([-2.0, 2.0], [-2.0, 2.0]).unwrap();
    // σ of the general field (plane stress): ε = (2, 0.7, 2·γ/2 = −3 + 1.5) × 1e-3.
    let (e, nu) = (YOUNG, POISSON);
    let c = e / (1.0 - nu * nu);
    let (exx, eyy, gxy) = (2e-3, 0.7e-3, -1.5e-3);
    let sigma = [c * (exx + nu * eyy), c * (eyy + nu * exx), e / (2.0 * (1.0 + nu)) * gxy];
    let traction_of = move |d: &Domain, k: usize| {
        let n = d.straight_normal(k).unwrap();
        let t = [sigma[0] * n[0] + sigma[2] * n[1], sigma[2] * n[0] + sigma[1] * n[1]];
        traction(Arc::new(move |_| t))
    };
    // Isotropic: σ₀ = E ε / (1 − ν); the traction σ₀ n is the pressure −σ₀.
    let s0 = YOUNG * 1e-3 / (1.0 - POISSON);
    let pressure = move |_: &Domain, _: usize| EdgeCondition::Pressure(Field::Constant(-s0));
    for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 7 }] {
        let square = outer().with_holes(vec![square_hole()]).unwrap();
        let err = patch_error(square, layout, general, &traction_of);
        println!("patch test, square hole, general field, {layout:?}: {err:.3e}");
        assert!(err < 1e-10, "square hole, {layout:?}: {err:.3e}");
        let two = outer().with_holes(vec![disk([-0.6, 0.5], 0.8, "hole"), square_hole()]).unwrap();
        let err = patch_error(two, layout, isotropic, &pressure);
        println!("patch test, disk and square holes, isotropic field, {layout:?}: {err:.3e}");
        assert!(err < 1e-10, "two holes, {layout:?}: {err:.3e}");
    }
}

/// The full Kirsch plate `[-5, 5]²` minus the unit disk, from curves.
fn full_plate() -> Domain {
    Domain::rectangle([-5.0, 5.0], [-5.0, 5.0])
        .unwrap()
        .with_holes(vec![disk([0.0, 0.0], 1.0, "hole")])
        .unwrap()
}

/// The Kirsch problem on a full plate `domain` (outer edges `bottom`, `right`, `top`,
/// `left` take Kirsch's displacement; the hole is free).
fn full_kirsch(domain: Domain, h: f64) -> Problem {
    let mut problem =
        base_problem(domain.clone(), h, Layout::Structured, plane_stress(YOUNG, POISSON));
    for name in ["bottom", "right", "top", "left"] {
        problem.boundary[domain.edge_index(name).unwrap()] =
            displacement(Arc::new(exact_displacement));
    }
    problem
}

const SPACINGS: [f64; 3] = [0.2, 0.1, 0.05];

/// Displacement and energy errors at [`SPACINGS`] on `domain(h)`, and their rates.
fn study(name: &str, domain: &dyn Fn(f64) -> Domain) -> ([f64; 3], [f64; 3], [f64; 2]) {
    let (mut du, mut de) = ([0.0; 3], [0.0; 3]);
    let mut rows = Vec::new();
    for (i, &h) in SPACINGS.iter().enumerate() {
        let e = errors(full_kirsch(domain(h), h));
        println!(
            "kirsch full plate {name}: h = {h:<5} displacement {:.3e}  energy {:.3e}",
            e.displacement, e.energy
        );
        (du[i], de[i]) = (e.displacement, e.energy);
        rows.push(vec![h, e.displacement, e.energy]);
    }
    write_table(
        "holes",
        &format!("kirsch_full_{name}.csv"),
        "h,displacement_error,energy_error",
        &rows,
    );
    let rates = [convergence_rate(&SPACINGS, &du), convergence_rate(&SPACINGS, &de)];
    println!(
        "kirsch full plate {name} rates: displacement {:.2}, energy {:.2}",
        rates[0], rates[1]
    );
    (du, de, rates)
}

#[test]
fn kirsch_full_plate_converges() {
    let (du, de, rates) = study("curves", &|_| full_plate());
    // The quarter plate's floors (kirsch.rs: 1.4 and 1.3 for observed 1.69 and 1.56) and its
    // finest bounds with the same headroom.
    assert!(rates[0] > 1.4 && rates[1] > 1.3, "rates {rates:?}");
    assert!(du[2] < 1.25e-3 && de[2] < 2.6e-3, "finest errors {} {}", du[2], de[2]);
}

fn mesh_body(name: &str) -> mlpg_contact::problem::gmsh::MeshBody {
    let mesh = Mesh::read(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    mesh.body("plate").unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn kirsch_full_plate_from_msh_matches_its_twin() {
    let d = mesh_body("kirsch_full_h0.1_v4.msh").domain;
    assert_eq!(d.loop_count(), 2);
    let hole = d.curve(d.edge_index("hole").unwrap());
    let Curve::Polyline { points } = hole else { panic!("{hole:?}") };
    assert!(points.iter().all(|p| (p[0].hypot(p[1]) - 1.0).abs() < 1e-12));
    assert_eq!(points.first(), points.last(), "the hole is one closed curve");
    assert!((d.area() - (100.0 - std::f64::consts::PI)).abs() < 0.01);
    let (tu, te, trates) = study("twin", &|_| full_plate());
    let (mu, me, mrates) = study("msh", &|h| mesh_body(&format!("kirsch_full_h{h}_v4.msh")).domain);
    for (what, m, t) in [
        ("displacement rate", mrates[0], trates[0]),
        ("energy rate", mrates[1], trates[1]),
        ("finest displacement", mu[2], tu[2]),
        ("finest energy", me[2], te[2]),
    ] {
        println!("kirsch full plate {what}: msh {m:.4} twin {t:.4}");
        assert!((m - t).abs() <= 0.1 * t.abs(), "{what}: msh {m} vs twin {t}");
    }
}

/// Max-norm displacement error of the FE path on `file`'s second-order elements, relative to
/// the largest exact displacement, and the node count.
fn fe_error(file: &str) -> (f64, usize) {
    let path = data(file);
    let text = format!(
        "[geometry]\nkind = \"gmsh\"\nfile = \"{}\"\n[nodes]\nfrom = \"mesh\"\n[discretisation]\nmethod = \"fem\"\n[material]\nyoung = {YOUNG}\npoisson = {POISSON}\nplane = \"stress\"\n",
        path.display()
    );
    let mut problem = Problem::from_toml(&text).unwrap();
    for name in ["bottom", "right", "top", "left"] {
        let k = problem.domain.edge_index(name).unwrap();
        problem.boundary[k] = displacement(Arc::new(exact_displacement));
    }
    let s = mlpg_contact::solve(&problem).unwrap();
    assert!(s.equilibrium_error < 1e-9, "equilibrium {}", s.equilibrium_error);
    let points = &problem.mesh_nodes.as_ref().unwrap().points;
    let max_u = points
        .iter()
        .map(|&p| exact_displacement(p)[0].hypot(exact_displacement(p)[1]))
        .fold(0.0, f64::max);
    let err = points
        .iter()
        .zip(&s.displacement)
        .map(|(&p, u)| {
            let e = exact_displacement(p);
            (u[0] - e[0]).hypot(u[1] - e[1])
        })
        .fold(0.0, f64::max);
    (err / max_u, points.len())
}

#[test]
fn kirsch_full_plate_on_the_fe_path() {
    let mut fe = Vec::new();
    for h in [0.2, 0.1] {
        let (e, n) = fe_error(&format!("kirsch_full_o2_h{h}_v4.msh"));
        let mfvm = errors(full_kirsch(full_plate(), h)).displacement;
        println!(
            "kirsch full plate FE (Q9/T6 from Gmsh, {n} nodes) h = {h}: displacement {e:.3e}; MFVM at h: {mfvm:.3e}"
        );
        // Quadratic isoparametric elements: more accurate than the linear MLS at equal h.
        assert!(e < mfvm, "FE {e} vs MFVM {mfvm} at h = {h}");
        fe.push(e);
    }
    assert!(fe[1] < 0.5 * fe[0], "FE errors {fe:?}");
}
