//! Bodies read from Gmsh meshes (`tests/data/gmsh/`, written by its `make_meshes.py` from the
//! `.geo` files beside them) against their twins built from curves.
//!
//! - Kirsch (`kirsch.rs`): the quarter plate `[0, 5]²` outside the unit hole, meshed with the
//!   hole at the twin's spacings `h = 0.2, 0.1, 0.05`; the hole becomes the polygon through the
//!   mesh's hole nodes (which lie on the circle), the straight edges stay segments. With nodes
//!   laid out inside the boundary at `h`, the displacement and energy errors and their
//!   observed rates must be within 10 % of the twin's (the twin's polygon is the chords through
//!   its own equally spaced arc nodes; the two differ only where Gmsh puts another number of
//!   nodes on the arc than `round(L/h)`: 32 against 31 at `h = 0.05`), `σ_xx(0, a)` within the
//!   twin's own change between the last two spacings. Versions 4.1 and 2.2 of each mesh give
//!   the same domain.
//! - Hertz (`hertz.rs`): the quarter cylinder with its contact arc and rim meshed at the twin's
//!   spacings `h = 0.02, 0.01, 0.005`: the errors of the fitted half-width and peak pressure
//!   against Hertz within the twin's own errors, the resultant within the twin's distance from
//!   its finest value, and the Hertz bounds of `hertz.rs`; the LCP residuals and equilibrium are
//!   checked by `hertz.rs`'s measurement.
//! - Nodes from the mesh (`nodes.from = "mesh"`): the Kirsch plate and the Hertz cylinder on
//!   the meshes' own nodes.
//! - Two bodies from one file (two `[[body]]` tables selecting their surfaces): the two blocks
//!   pressed together, exact to round-off.

use super::hertz::{Outcome, hertz_problem, hertz_problem_on, run_problem};
use super::kirsch::{errors, kirsch_problem, quarter_plate, run_on, study_on};
use mlpg_contact::geometry::{Curve, Domain};
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::MeshNodes;
use mlpg_contact::problem::gmsh::Mesh;
use std::path::PathBuf;
use std::sync::Arc;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/gmsh").join(name)
}

fn body(name: &str, surface: &str) -> Domain {
    let mesh = Mesh::read(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    mesh.body(surface).unwrap_or_else(|e| panic!("{name}: {e}")).domain
}

fn kirsch_mesh(h: f64) -> Domain {
    let v4 = body(&format!("kirsch_h{h}_v4.msh"), "plate");
    assert_eq!(v4, body(&format!("kirsch_h{h}_v2.msh"), "plate"), "h = {h}: 4.1 and 2.2 differ");
    v4
}

#[test]
fn kirsch_from_msh_matches_its_twin() {
    let h = [0.2, 0.1, 0.05];
    // The mesh's edges: four segments and the hole's polyline, on the circle.
    let d = kirsch_mesh(0.1);
    let hole = d.curve(d.edge_index("hole").unwrap());
    let Curve::Polyline { points } = hole else { panic!("{hole:?}") };
    assert!(points.iter().all(|p| (p[0].hypot(p[1]) - 1.0).abs() < 1e-12));
    assert_eq!(d.curves().iter().filter(|c| c.is_straight()).count(), 4);
    let (twin_rates, twin_finest) = study_on("twin", &|_| quarter_plate(), Layout::Structured, &h);
    let (rates, finest) = study_on("msh", &kirsch_mesh, Layout::Structured, &h);
    let what = ["displacement", "energy", "concentration"];
    for k in 0..3 {
        println!(
            "kirsch {}: rate {:.3} (twin {:.3}), finest {:.3e} (twin {:.3e})",
            what[k], rates[k], twin_rates[k], finest[k], twin_finest[k]
        );
    }
    for k in 0..2 {
        assert!((rates[k] / twin_rates[k] - 1.0).abs() < 0.1, "{} rate", what[k]);
        assert!((finest[k] / twin_finest[k] - 1.0).abs() < 0.1, "{} error", what[k]);
    }
    // The concentration's error changes sign between the spacings (kirsch.rs: the twin's finest
    // value is partly luck), so neither its rate nor its finest error compares to 10 %: the
    // finest σ_xx(0, a) must be as close to the twin's as the twin's own change from the
    // spacing before, |σ(0.1) − σ(0.05)|.
    let sigma = |d: Domain, hi: f64| run_on(d, hi, Layout::Structured).concentration;
    let (s_twin, s_twin_coarse) = (sigma(quarter_plate(), 0.05), sigma(quarter_plate(), 0.1));
    let s_msh = sigma(kirsch_mesh(0.05), 0.05);
    let tol = (s_twin - s_twin_coarse).abs();
    println!("kirsch sigma_xx(0, a): msh {s_msh:.5}, twin {s_twin:.5} (tolerance {tol:.2e})");
    assert!((s_msh - s_twin).abs() < tol, "sigma_xx(0, a) {s_msh} vs twin {s_twin}");
}

#[test]
fn hertz_from_msh_matches_its_twin() {
    let h = [0.02, 0.01, 0.005];
    let run = |hi: f64, msh: bool| -> Outcome {
        let problem = if msh {
            let domain = body(&format!("hertz_cylinder_h{hi}_v4.msh"), "cylinder");
            hertz_problem_on(domain, hi, Layout::Structured)
        } else {
            hertz_problem(hi, Layout::Structured)
        };
        run_problem(problem, &format!("{} h = {hi}", if msh { "msh" } else { "twin" }))
    };
    let twin: Vec<Outcome> = h.iter().map(|&hi| run(hi, false)).collect();
    let msh: Vec<Outcome> = h.iter().map(|&hi| run(hi, true)).collect();
    let last = h.len() - 1;
    for i in 0..h.len() {
        // The twin's discretisation error at h: for a and p₀ its error against Hertz (relative
        // errors, compared as such); for the resultant (no closed form under a prescribed
        // indentation) its distance from the finest value, or at the finest its change from
        // the spacing before.
        let p_tol = (twin[i].load - twin[if i == last { i - 1 } else { last }].load).abs();
        for (what, m, t, tol) in [
            ("P", msh[i].load, twin[i].load, p_tol),
            ("a error", msh[i].half_width, twin[i].half_width, twin[i].half_width.abs()),
            ("p0 error", msh[i].peak, twin[i].peak, twin[i].peak.abs()),
        ] {
            println!("hertz h = {}: {what} msh {m:.6e}, twin {t:.6e} (tolerance {tol:.2e})", h[i]);
            assert!((m - t).abs() < tol, "h = {}: {what} {m} vs twin {t} (tolerance {tol})", h[i]);
        }
        assert!(msh[i].half_width.abs() < 0.03, "half-width error {}", msh[i].half_width);
        assert!(msh[i].peak.abs() < 0.01, "peak error {}", msh[i].peak);
    }
}

// Observed: first order (301 nodes, mean spacing 0.61, graded from 0.25 at the hole to 1):
// displacement 1.53e-2, energy 8.20e-2, σ_xx(0, a) = 2.807; second order (1140 nodes, mean
// spacing 0.31): 6.74e-3, 1.87e-2, 2.914 (rates 1.2 and 2.1 per halving).
#[test]
fn kirsch_on_the_mesh_nodes() {
    // The quarter plate [0, 10]² of problems/plate_with_hole.toml, first and second order.
    let mut out = Vec::new();
    for order in [1, 2] {
        let mesh = Mesh::read(&data(&format!("plate_with_hole_o{order}_v4.msh"))).unwrap();
        let body = mesh.body("plate").unwrap();
        let n = body.points.len();
        let mean = body.spacing.iter().sum::<f64>() / n as f64;
        let mut problem = kirsch_problem(body.domain.clone(), mean, Layout::Structured);
        problem.mesh_nodes = Some(Arc::new(MeshNodes {
            points: body.points.clone(),
            spacing: body.spacing,
            elements: body.elements,
        }));
        let e = errors(problem);
        println!(
            "kirsch mesh nodes o{order} ({n} nodes, mean spacing {mean:.3}): displacement {:.3e} energy {:.3e} sigma_xx(0,a) = {:.4}",
            e.displacement, e.energy, e.concentration
        );
        out.push(e);
    }
    // Halving the spacing (second order: the same elements with their edge nodes) must at
    // least halve the displacement and energy errors and bring σ_xx(0, a) closer to 3.
    assert!(out[1].displacement < 0.5 * out[0].displacement);
    assert!(out[1].energy < 0.5 * out[0].energy);
    assert!((out[1].concentration - 3.0).abs() < (out[0].concentration - 3.0).abs());
    assert!(out[1].displacement < 0.01 && out[1].energy < 0.025, "finest errors");
}

/// The Hertz cylinder on the nodes of its h = 0.01 mesh (0.01 along the arcs, graded to 0.1
/// at the centre: 2068 nodes, about a quarter of the twin's): the Hertz bounds of `hertz.rs`
/// (3 % on `a`, 1 % on `p₀`, both against Hertz for the computed resultant), with the LCP
/// residuals and equilibrium checked by the measurement.
// Observed: a error +6.3e-3, p₀ error −5.8e-3 (twin at h = 0.01: +1.25e-2, −3.3e-3); the
// resultant P = 7.9933e-3 is 0.21 % below the twin's 8.0105e-3 (the coarse interior: the
// twin at h = 0.02 gives 7.9930e-3), not asserted.
#[test]
fn hertz_on_the_mesh_nodes() {
    let mesh = Mesh::read(&data("hertz_cylinder_h0.01_v4.msh")).unwrap();
    let body = mesh.body("cylinder").unwrap();
    let n = body.points.len();
    let mean = body.spacing.iter().sum::<f64>() / n as f64;
    let mut problem = hertz_problem_on(body.domain, mean, Layout::Structured);
    problem.mesh_nodes = Some(Arc::new(MeshNodes {
        points: body.points,
        spacing: body.spacing,
        elements: body.elements,
    }));
    let m = run_problem(problem, &format!("mesh nodes ({n})"));
    assert!(m.half_width.abs() < 0.03, "half-width error {}", m.half_width);
    assert!(m.peak.abs() < 0.01, "peak error {}", m.peak);
}

/// The flat punch of `problems/flat_punch.toml` with sharp corners, once as a `polyline`
/// obstacle through its four corners written in TOML and once as `kind = "gmsh"`: the
/// physical curve "punch" of `punch_o1_v4.msh` (the same corners, its sides and face divided
/// into pieces of 0.05, in the order of the TOML's points). The extra nodes lie on the TOML
/// polyline's segments (Gmsh interpolates them along straight lines), so both obstacles are
/// the same set and give every candidate the same gap and normal; the solutions must agree to
/// round-off (1e-9 relative: the two LCPs are the same up to the last bits of the gaps). Both
/// runs check their LCP residuals and equilibrium. The coarse box spacing 0.0125 of
/// `flat_punch.rs` (8 candidates under the half face).
#[test]
fn gmsh_obstacle_equals_its_polyline_twin() {
    let toml = include_str!("../../problems/flat_punch.toml")
        .replace("spacing = 0.003125", "spacing = 0.0125")
        .replace("corner_radius = 0.005", "corner_radius = 0.0");
    let file = data("punch_o1_v4.msh");
    let gmsh = toml
        .replace("kind = \"polyline\"", "kind = \"gmsh\"")
        .replace(
            "points = [[-0.1, 1.0], [-0.1, 0.0], [0.1, 0.0], [0.1, 1.0]]",
            &format!("file = {:?}\ncurve = \"punch\"", file.to_str().unwrap()),
        )
        .replace("corner_radius = 0.0\n", "");
    assert_ne!(gmsh, toml);
    let solve = |label: &str, text: &str| {
        let s = mlpg_contact::solve(&mlpg_contact::problem::Problem::from_toml(text).unwrap())
            .unwrap_or_else(|e| panic!("{label}: {e}"));
        let c = s.contact().unwrap();
        super::common::assert_lcp_residuals(label, &c.lcp.residuals, 1e-9);
        assert!(s.equilibrium_error < 1e-8, "{label}: equilibrium {}", s.equilibrium_error);
        s
    };
    let twin = solve("polyline", &toml);
    let mesh = solve("gmsh", &gmsh);
    let (ct, cm) = (twin.contact().unwrap(), mesh.contact().unwrap());
    assert_eq!(ct.closed, cm.closed, "the same candidates close");
    let closed = ct.closed.iter().filter(|&&c| c).count();
    assert!(closed >= 5, "{closed} closed candidates");
    let scale = ct.lcp.z.iter().fold(0.0_f64, |m, z| m.max(z.abs()));
    let force = ct.lcp.z.iter().zip(&cm.lcp.z).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    let u_scale = twin.displacement.iter().fold(0.0_f64, |m, u| m.max(u[0].hypot(u[1])));
    let u = twin
        .displacement
        .iter()
        .zip(&mesh.displacement)
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .fold(0.0, f64::max);
    println!(
        "punch twin: {closed} closed, total force {:.6e} vs {:.6e}; max force difference {:.2e} relative, displacement {:.2e} relative",
        ct.total_force,
        cm.total_force,
        force / scale,
        u / u_scale
    );
    assert!(force <= 1e-9 * scale, "contact forces differ by {force:e} (scale {scale:e})");
    assert!(u <= 1e-9 * u_scale, "displacements differ by {u:e} (scale {u_scale:e})");
}

/// Two bodies from one file: `two_bodies_o1_v4.msh` holds the surfaces `upper` (`[0, 2] ×
/// [1, 2]`, quadrilaterals of 0.2) and `lower` (`[0, 2] × [0, 1]`, 0.25), every side a named
/// physical curve; two `[[body]]` tables read the same file, each selecting its surface, with
/// the mesh's nodes (non-matching at `y = 1`). The problem is `problems/two_blocks.toml`'s:
/// the upper top pushed down by `δ = 0.01`, the lower bottom on rollers, rollers on both left
/// sides, frictionless contact of `upper_bottom` on `lower_top`. Exact (uniaxial stress, plane
/// stress): `p = Eδ/2 = 5` uniform, `u_y = −p y/E` in the lower block and `−p/E − p(y − 1)/E`
/// in the upper, `u_x = ν p x/E` in both — linear fields, which MLS reproduces and the
/// condensation carries exactly, so pressures and displacements must match to 1e-8 (round-off
/// with margin) at every candidate and node, with the LCP residuals and each body's equilibrium.
#[test]
fn two_bodies_from_one_file() {
    let file = data("two_bodies_o1_v4.msh");
    let body = |name: &str, boundary: &str| {
        format!(
            "[[body]]\nname = \"{name}\"\ngeometry = {{ kind = \"gmsh\", file = {:?}, surface = \"{name}\" }}\nnodes = {{ from = \"mesh\" }}\nmaterial = {{ young = 1000.0, poisson = 0.3, plane = \"stress\" }}\nboundary = [{boundary}]\n",
            file.to_str().unwrap()
        )
    };
    let text = format!(
        "name = \"upper\"\n[discretisation]\nsupport_factor = 2.0\n{}{}[contact]\nedge = \"upper_bottom\"\ntarget_edge = \"lower_top\"\n",
        body(
            "upper",
            "{ edge = \"upper_left\", displacement = { x = 0.0 } }, { edge = \"upper_top\", displacement = { y = -0.01 } }"
        ),
        body(
            "lower",
            "{ edge = \"lower_left\", displacement = { x = 0.0 } }, { edge = \"lower_bottom\", displacement = { y = 0.0 } }"
        ),
    );
    let problem = mlpg_contact::problem::Problem::from_toml(&text).unwrap();
    let s = mlpg_contact::solve(&problem).unwrap();
    let c = s.contact().unwrap();
    super::common::assert_lcp_residuals("two bodies from one file", &c.lcp.residuals, 1e-9);
    let (young, nu, delta) = (1000.0, 0.3, 0.01);
    let p = young * delta / 2.0;
    let worst = c.pressure.iter().map(|v| (v / p - 1.0).abs()).fold(0.0, f64::max);
    println!(
        "two bodies from one file: {} candidates, max |p/p_exact − 1| = {worst:.2e}, total {:.12} (exact {})",
        c.pressure.len(),
        c.total_force,
        2.0 * p
    );
    assert!(worst < 1e-8, "pressure {worst:e}");
    assert!((c.total_force / (2.0 * p) - 1.0).abs() < 1e-8, "total {}", c.total_force);
    let lower = s.body(1).unwrap();
    let lower_problem = problem.body(1).unwrap();
    for (label, sol, prob, shift) in
        [("upper", &s, &problem, -p / young), ("lower", lower, lower_problem, 0.0)]
    {
        let points = &prob.mesh_nodes.as_ref().unwrap().points;
        assert_eq!(points.len(), sol.displacement.len(), "{label}");
        let base = if shift == 0.0 { 0.0 } else { 1.0 };
        let err = points
            .iter()
            .zip(&sol.displacement)
            .map(|(x, u)| {
                let exact = [nu * p * x[0] / young, shift - p * (x[1] - base) / young];
                (u[0] - exact[0]).abs().max((u[1] - exact[1]).abs())
            })
            .fold(0.0, f64::max);
        println!("{label}: {} nodes, max |u − u_exact| = {:.2e} δ", points.len(), err / delta);
        assert!(err < 1e-8 * delta, "{label}: {err:e}");
        assert!(sol.equilibrium_error < 1e-8, "{label}: equilibrium {}", sol.equilibrium_error);
    }
}
