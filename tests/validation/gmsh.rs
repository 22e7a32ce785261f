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
