//! The FE path on Gmsh meshes with curved sides: isoparametric 6-node triangles and 9-node
//! quadrilaterals read from `tests/data/fem_meshes/` (second-order meshes of the quarter plate
//! `[0, 10]²` outside the unit hole, written by Gmsh from `plate_with_hole.geo`; see
//! `make_meshes.py` there), the body's edges those of the exact geometry (the hole an arc).
//!
//! 1. Patch test: a constant stress state (the linear displacement prescribed on the two
//!    straight sides, the traction `σ·n` on the others, the hole's included) is reproduced to
//!    round-off on curved, mixed meshes — the isoparametric map reproduces linear fields and
//!    the curved sides' loads are integrated exactly (their integrands are polynomials).
//! 2. Kirsch (the closed form of `kirsch.rs`; rollers on the symmetry lines, the exact traction
//!    on `x = 10` and `y = 10`, the hole free): displacement and energy errors and the stress
//!    concentration `σ_xx(0, 1)/σ₀` (exact 3) on three meshes each of triangles and of
//!    quadrilaterals, with their rates. Quadratic elements on a smooth solution converge
//!    like `h³` (displacement) and `h²` (energy) in theory; the geometry error of the
//!    quadratic hole is of the same or higher order.
//! 3. Hertz (the quarter cylinder of `hertz.rs` on a rigid flat, meshed by Gmsh from
//!    `hertz_cylinder.geo`): the FE and the MFVM agree within their discretisation errors,
//!    both within 1 % of Hertz.

use super::common::*;
use super::kirsch::{POISSON, YOUNG, exact_displacement, exact_stress};
use mlpg_contact::assembly::Body;
use mlpg_contact::fem::{self, Mesh, system::FemInput};
use mlpg_contact::geometry::{Curve, Domain, Point};
use mlpg_contact::linear_solve::Factorisation;
use mlpg_contact::nodes::{Layout, Nodes};
use mlpg_contact::problem::{ComponentCondition, EdgeCondition, Field, Problem, gmsh};
use std::sync::Arc;

const SIDE: f64 = 10.0;

/// The quarter plate `[0, 10]²` outside the unit hole, with the edge names of the meshes'
/// physical curves.
fn plate() -> Domain {
    Domain::from_curves(
        vec![
            Curve::Segment { a: [1.0, 0.0], b: [SIDE, 0.0] },
            Curve::Segment { a: [SIDE, 0.0], b: [SIDE, SIDE] },
            Curve::Segment { a: [SIDE, SIDE], b: [0.0, SIDE] },
            Curve::Segment { a: [0.0, SIDE], b: [0.0, 1.0] },
            Curve::arc_between([0.0, 1.0], [1.0, 0.0], [0.0, 0.0], false),
        ],
        ["bottom", "right", "top", "left", "hole"].iter().map(|s| s.to_string()).collect(),
    )
    .unwrap()
}

/// The mesh of `tests/data/fem_meshes/<file>` (surface `plate`).
fn mesh(file: &str) -> Mesh {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fem_meshes").join(file);
    let body = gmsh::Mesh::read(&path).unwrap().body("plate").unwrap();
    Mesh::from_elements(body.points, &body.elements).unwrap()
}

/// Solves `problem` on `mesh`: its nodes (tagged by the problem's edges) and the nodal
/// displacements (interleaved).
fn solve_on(problem: &Problem, mesh: &Mesh) -> (Nodes, Vec<f64>) {
    let nodes = mesh.nodes(&problem.domain);
    let d = problem.material.constitutive();
    let system =
        fem::system::assemble(&FemInput { body: Body::new(problem, &nodes, &d), mesh }).unwrap();
    let u = Factorisation::new(&system.matrix).unwrap().solve(&system.rhs).unwrap();
    (nodes, u)
}

/// The traction `σ·n` of a stress field on edge `k` of the plate (outward normal).
fn stress_traction(domain: &Domain, k: usize, stress: fn(Point) -> [f64; 3]) -> EdgeCondition {
    let curve = domain.curve(k).clone();
    traction(Arc::new(move |p| {
        let (s, n) = (stress(p), curve.outward_normal_at(p));
        [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]]
    }))
}

/// Two constant stress states: (a) a general one, the linear displacement prescribed on the
/// hole and the symmetry lines and `σ·n` on the straight outer sides; (b) a hydrostatic one,
/// `σ = s I`, with the pressure `−s` on the curved hole (integrated with the side's own
/// normal), `σ·n` outside. A traction given as `σ·n` with the exact circle's normal would not
/// be a patch test: the quadratic side is not the circle (the difference is the geometry
/// error, 1.5e-7 relative here).
#[test]
fn curved_meshes_pass_the_patch_test() {
    for (case, stress) in [("general", [1.0, -0.4, 0.3]), ("hydrostatic", [0.7, 0.7, 0.0])] {
        let linear = move |p: Point| {
            let (e, nu) = (YOUNG, POISSON);
            let strain = [
                (stress[0] - nu * stress[1]) / e,
                (stress[1] - nu * stress[0]) / e,
                2.0 * (1.0 + nu) * stress[2] / e,
            ];
            [
                1e-3 + strain[0] * p[0] + 0.5 * strain[2] * p[1],
                -2e-3 + strain[1] * p[1] + 0.5 * strain[2] * p[0],
            ]
        };
        let domain = plate();
        let mut problem =
            base_problem(domain.clone(), 1.0, Layout::Structured, plane_stress(YOUNG, POISSON));
        let outer = move |n: Point| {
            [stress[0] * n[0] + stress[2] * n[1], stress[2] * n[0] + stress[1] * n[1]]
        };
        for k in [1, 2] {
            let normal = domain.straight_normal(k).unwrap();
            problem.boundary[k] = traction(Arc::new(move |_| outer(normal)));
        }
        if case == "general" {
            for k in [0, 3, 4] {
                problem.boundary[k] = displacement(Arc::new(linear));
            }
        } else {
            for k in [0, 3] {
                problem.boundary[k] = displacement(Arc::new(linear));
            }
            problem.boundary[4] = EdgeCondition::Pressure(Field::Constant(-stress[0]));
        }
        for file in ["plate_with_hole_tri_0.msh", "plate_with_hole_quad_0.msh"] {
            let mesh = mesh(file);
            let (nodes, u) = solve_on(&problem, &mesh);
            let scale =
                nodes.points.iter().map(|&p| linear(p)[0].hypot(linear(p)[1])).fold(0.0, f64::max);
            let err = nodes
                .points
                .iter()
                .enumerate()
                .map(|(i, &p)| (u[2 * i] - linear(p)[0]).hypot(u[2 * i + 1] - linear(p)[1]))
                .fold(0.0, f64::max);
            println!(
                "FE patch test ({case}) on {file}: {} quadrilaterals, {} triangles, {} nodes: max |u − u_exact| / max |u| = {:.2e}",
                mesh.elements.len(),
                mesh.triangles.len(),
                nodes.len(),
                err / scale
            );
            assert!(err <= 1e-10 * scale, "{case}, {file}: {err:e}");
        }
    }
}

/// Errors of the FE solution on `file` against Kirsch: max-norm displacement (relative),
/// energy norm (relative, element quadrature), `σ_xx(0, 1)` (nodal average).
fn kirsch_errors(file: &str) -> (usize, [f64; 3]) {
    let domain = plate();
    let mut problem =
        base_problem(domain.clone(), 1.0, Layout::Structured, plane_stress(YOUNG, POISSON));
    let roller = |axis: usize| {
        let mut c = EdgeCondition::free();
        if let EdgeCondition::Components(c) = &mut c {
            c[axis] = ComponentCondition::Displacement(Field::Constant(0.0));
        }
        c
    };
    problem.boundary[0] = roller(1);
    problem.boundary[3] = roller(0);
    for k in [1, 2] {
        problem.boundary[k] = stress_traction(&domain, k, exact_stress);
    }
    let mesh = mesh(file);
    let (nodes, u) = solve_on(&problem, &mesh);
    let (mut err_u, mut max_u) = (0.0f64, 0.0f64);
    for (i, &p) in nodes.points.iter().enumerate() {
        let e = exact_displacement(p);
        err_u = err_u.max((u[2 * i] - e[0]).hypot(u[2 * i + 1] - e[1]));
        max_u = max_u.max(e[0].hypot(e[1]));
    }
    let d = problem.material.constitutive();
    let compliance = |s: [f64; 3]| {
        [
            (s[0] - POISSON * s[1]) / YOUNG,
            (s[1] - POISSON * s[0]) / YOUNG,
            2.0 * (1.0 + POISSON) * s[2] / YOUNG,
        ]
    };
    let (mut num, mut den) = (0.0, 0.0);
    for k in 0..mesh.element_count() {
        for ([xi, eta], w) in mesh.cell(k).shape.quadrature() {
            let p = mesh.point(k, xi, eta);
            let sh = mlpg_contact::material::apply(&d, mesh.strain(k, xi, eta, &u));
            let se = exact_stress(p);
            let ds = [sh[0] - se[0], sh[1] - se[1], sh[2] - se[2]];
            let (de, ee) = (compliance(ds), compliance(se));
            let w = w * mesh.area_factor(k, xi, eta);
            num += w * (ds[0] * de[0] + ds[1] * de[1] + ds[2] * de[2]);
            den += w * (se[0] * ee[0] + se[1] * ee[1] + se[2] * ee[2]);
        }
    }
    let top =
        nodes.points.iter().position(|p| p[0].abs() < 1e-12 && (p[1] - 1.0).abs() < 1e-12).unwrap();
    let sigma = mlpg_contact::material::apply(&d, mesh.nodal_strains(&u)[top]);
    (nodes.len(), [err_u / max_u, (num / den).sqrt(), (sigma[0] - 3.0).abs() / 3.0])
}

// Observed (size factors 2, 1, 1/2 of the .geo's: h = 2, 1, 0.5 far from the hole and a
// quarter of that on it; 341–4188 nodes):
// triangles: displacement 1.93e-3, 2.43e-4, 4.76e-5 (rate 2.67); energy 9.02e-3, 3.11e-3,
//   9.99e-4 (1.59); σ_xx(0, 1) error 8.4e-2, 3.1e-2, 9.3e-3 (1.58);
// quadrilaterals: 1.14e-3, 1.46e-4, 1.75e-5 (3.01); 7.16e-3, 1.87e-3, 5.73e-4 (1.82);
//   2.2e-2, 2.1e-4, 2.4e-3 (1.59; not monotone: the nodal average changes sign).
// Theory for quadratic elements: 3 and 2 asymptotically; these graded meshes are short of it.
// The bounds: rates above 2.3 (displacement) and 1.4 (energy), finest errors with ~25 %
// headroom; the concentration within 1.2 %.
#[test]
fn kirsch_on_curved_meshes_converges() {
    for kind in ["tri", "quad"] {
        let h = [2.0, 1.0, 0.5];
        let mut errors = Vec::new();
        for (level, hl) in h.iter().enumerate() {
            let file = format!("plate_with_hole_{kind}_{level}.msh");
            let (n, e) = kirsch_errors(&file);
            println!(
                "FE Kirsch {kind}, h = {hl}: {n} nodes, displacement {:.3e}, energy {:.3e}, σ_xx(0, 1) {:.3e}",
                e[0], e[1], e[2]
            );
            errors.push(e);
        }
        let rate =
            |c: usize| convergence_rate(&h, &errors.iter().map(|e| e[c]).collect::<Vec<_>>());
        println!(
            "FE Kirsch {kind} rates: displacement {:.2}, energy {:.2}, concentration {:.2}",
            rate(0),
            rate(1),
            rate(2)
        );
        let finest = errors[2];
        assert!(rate(0) > 2.3 && rate(1) > 1.4, "{kind}: rates {} {}", rate(0), rate(1));
        assert!(finest[0] < 6e-5 && finest[1] < 1.25e-3, "{kind}: {finest:?}");
        assert!(finest[2] < 1.2e-2, "{kind}: σ_xx(0, 1) off by {}", finest[2]);
    }
}

/// The FE path on a Gmsh body: without `nodes.from = "mesh"` it is refused naming the key;
/// a first-order mesh is refused at the discretisation naming the element's line; the
/// second-order mesh solves.
#[test]
fn gmsh_bodies_on_the_fe_path() {
    let text = |file: &str, nodes: &str| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
        format!(
            "[geometry]\nkind = \"gmsh\"\nfile = \"{}\"\nsurface = \"plate\"\n[nodes]\n{nodes}\n[discretisation]\nmethod = \"fem\"\n[material]\nyoung = 1000.0\npoisson = 0.3\nplane = \"stress\"\n[[boundary]]\nedge = \"bottom\"\ndisplacement = {{ y = 0.0 }}\n[[boundary]]\nedge = \"left\"\ndisplacement = {{ x = 0.0 }}\n[[boundary]]\nedge = \"right\"\ntraction = {{ x = 1.0 }}\n",
            path.display()
        )
    };
    let e = Problem::from_toml(&text("tests/data/gmsh/plate_with_hole_o2_v4.msh", "spacing = 0.5"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("nodes.from"), "{e}");
    let first =
        Problem::from_toml(&text("tests/data/gmsh/plate_with_hole_o1_v4.msh", "from = \"mesh\""))
            .unwrap();
    let e = mlpg_contact::solve(&first).unwrap_err().to_string();
    assert!(e.contains("line ") && e.contains("Tri3"), "{e}");
    let second =
        Problem::from_toml(&text("tests/data/gmsh/plate_with_hole_o2_v4.msh", "from = \"mesh\""))
            .unwrap();
    let s = mlpg_contact::solve(&second).unwrap();
    assert!(s.equilibrium_error < 1e-9, "{}", s.equilibrium_error);
}

/// The Hertz quarter cylinder of `hertz.rs` on the FE path: the body from
/// `tests/data/fem_meshes/hertz_cylinder_<level>.msh` (9-node quadrilaterals, a few 6-node
/// triangles, curved sides along the arcs; element size 0.04, 0.02, 0.01 along the arc, so node
/// spacing 0.02, 0.01, 0.005 there; `nodes.from = "mesh"`), against the MFVM on the TOML twin
/// (`hertz_problem`) at the same arc node spacings.
fn hertz_fem(level: usize) -> Problem {
    let file = format!("hertz_cylinder_{level}.msh");
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fem_meshes").join(&file);
    let body = gmsh::Mesh::read(&path).unwrap().body("cylinder").unwrap();
    let mean = body.spacing.iter().sum::<f64>() / body.points.len() as f64;
    let mut problem = super::hertz::hertz_problem_on(body.domain, mean, Layout::Structured);
    problem.mesh_nodes = Some(Arc::new(mlpg_contact::problem::MeshNodes {
        points: body.points,
        spacing: body.spacing,
        elements: body.elements,
    }));
    problem.discretisation.method = mlpg_contact::problem::Method::Fem;
    problem
}

/// FE and MFVM agree on Hertz within their discretisation errors: on the meshes of
/// `hertz_fem` (levels 0, 1, 2) and the MFVM twin at `h = 0.02, 0.01, 0.005`, the resultant
/// `P`, the fitted half-width `a` and the fitted peak `p₀` (`hertz.rs`'s least-squares fit,
/// which also checks each run's LCP residuals and equilibrium) differ at the finest level by at
/// most the sum of the two methods' changes over the last refinement (each method's error
/// estimate); both fits are within 1 % of Hertz at the finest level (half-space theory: the
/// finite cylinder's `a/R ≈ 0.1` leaves a few tenths of a percent).
///
/// Observed (levels 0, 1, 2): FE P 8.0310e-3, 8.0214e-3, 8.0206e-3, MFVM 7.9930e-3, 8.0105e-3,
/// 8.0183e-3 (|diff| 2.3e-6 ≤ 8.6e-6); a against Hertz FE −0.28 %, −0.62 %, −0.27 %, MFVM
/// +2.1 %, +1.3 %, −0.46 %; p₀ FE +0.54 %, +0.32 %, +0.20 %, MFVM −0.93 %, −0.33 %, +0.18 %.
#[test]
fn hertz_fem_on_a_curved_mesh_agrees_with_the_mfvm() {
    use super::hertz::{hertz_problem, run_problem};
    let fem: Vec<_> = (0..3).map(|l| run_problem(hertz_fem(l), &format!("FE level {l}"))).collect();
    let mfvm: Vec<_> = [0.02, 0.01, 0.005]
        .iter()
        .map(|&h| run_problem(hertz_problem(h, Layout::Structured), &format!("MFVM h = {h}")))
        .collect();
    // P, fitted a, fitted p₀ = (1 + peak error) · 2P/(π a_Hertz), a_Hertz = a_fit/(1 + a error).
    let values = |m: &super::hertz::Outcome| {
        let a_hertz = m.half_width_fit / (1.0 + m.half_width);
        [m.load, m.half_width_fit, (1.0 + m.peak) * 2.0 * m.load / (std::f64::consts::PI * a_hertz)]
    };
    let (f, m) =
        (fem.iter().map(values).collect::<Vec<_>>(), mfvm.iter().map(values).collect::<Vec<_>>());
    for (i, name) in ["P", "a", "p0"].iter().enumerate() {
        let diff = (f[2][i] - m[2][i]).abs();
        let (e_f, e_m) = ((f[2][i] - f[1][i]).abs(), (m[2][i] - m[1][i]).abs());
        println!(
            "Hertz {name}: FE {:.6e} MFVM {:.6e} |diff| {diff:.2e} ≤ e_FE {e_f:.2e} + e_MFVM {e_m:.2e}",
            f[2][i], m[2][i]
        );
        assert!(diff <= e_f + e_m, "{name}: {diff:.3e} > {:.3e}", e_f + e_m);
    }
    for (name, o) in [("FE", &fem[2]), ("MFVM", &mfvm[2])] {
        assert!(o.half_width.abs() < 0.01, "{name}: a error {}", o.half_width);
        assert!(o.peak.abs() < 0.01, "{name}: p0 error {}", o.peak);
    }
}
