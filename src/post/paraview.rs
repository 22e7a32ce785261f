//! The run's ParaView files beside the bodies' `solution.vtu` (module `vtk`): the contact
//! candidates of every contact edge and the rigid obstacles as polygonal data (`.vtp`), one
//! multiblock file `solution.vtm` that opens every body, contact edge and obstacle at once,
//! and with load steps a time series `solution.pvd` (and with `[output] steps` the contact
//! edge's series over the increments, `steps/contact.pvd`).
//!
//! Every data set carries a point vector `displacement`, so that one "Warp By Vector" on the
//! multiblock moves the bodies, their contact edges (each candidate by its node's `u^h`) and
//! the obstacles (by their rigid displacement) together: at scale 1 a closed candidate lies on
//! its obstacle.

use super::vtk::{Array, poly_data, xml_escape};
use super::{OutputError, save};
use crate::geometry::Point;
use crate::lcp::ContactState;
use crate::problem::{ContactTarget, Problem, Shape};
use crate::solution::{ContactSolution, Solution};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The codes of the contact datasets' `state` array without friction (the field-data array
/// `state_legend` of each file lists them too): the index is the code.
pub const FRICTIONLESS_STATES: [&str; 2] = ["open", "closed"];

/// The codes of the `state` array with friction: open, stick, slip along `+t`, slip along
/// `−t` (`contact.csv`'s `state` column).
pub const FRICTION_STATES: [&str; 4] = ["open", "stick", "slip+", "slip-"];

/// Writes the contact datasets (`contact.vtp`, or `contact_<k>.vtp` per pair of a problem
/// with several bodies or contact pairs, as `contact_<k>.csv`), the obstacles
/// (`obstacles.vtp`, when the contact has rigid obstacles), `solution.vtm` and, when the
/// problem has load steps, `solution.pvd` into `dir`, the output directory of a run whose
/// bodies' `solution.vtu` files are `dir/solution.vtu` (the first body) and
/// `dir/<name>/solution.vtu` (the others). Returns the files written.
///
/// The solution holds the final state only (the displacements of the earlier load increments
/// are not kept), so `solution.pvd` is a series of one time: the end of the last step, time
/// = the number of steps (step `k` ends at time `k`). The contact state of every increment is
/// kept when the problem asks for it (`[output] steps`): then `steps/contact.pvd` is the
/// contact edge's time series over the increments.
///
/// # Errors
/// [`OutputError::Io`] when a file cannot be written.
pub fn write_paraview(
    dir: &Path,
    problem: &Problem,
    solution: &Solution,
) -> Result<Vec<PathBuf>, OutputError> {
    let mut written = Vec::new();
    // (name, file) of each block's data sets.
    let mut bodies = vec![(problem.name.clone(), "solution.vtu".to_string())];
    let mut contacts = Vec::new();
    // (name, initial shape, rigid displacement) of each obstacle.
    let mut obstacles: Vec<(String, Shape, Point)> = Vec::new();
    let last_step = problem.steps.last().map_or([0.0, 0.0], |s| s.obstacle_displacement);
    let moved = |c: &ContactSolution| c.load_driven.as_ref().map_or(last_step, |l| l.displacement);
    let mut add_obstacles =
        |target: ContactTarget, list: &[crate::problem::Obstacle], c: &ContactSolution| {
            let d = moved(c);
            let found: Vec<(String, Shape)> = match target {
                ContactTarget::Rigid(line) => vec![("obstacle".to_string(), Shape::Line(line))],
                ContactTarget::Obstacles => {
                    list.iter().map(|o| (o.name.clone(), o.shape.clone())).collect()
                }
                ContactTarget::Body { .. } => Vec::new(),
            };
            for (name, shape) in found {
                if !obstacles.iter().any(|(n, s, _)| *n == name && *s == shape) {
                    obstacles.push((name, shape, d));
                }
            }
        };
    for (p, _) in problem.bodies().zip(solution.bodies()).skip(1) {
        bodies.push((p.name.clone(), format!("{}/solution.vtu", p.name)));
    }
    // One pair keeps the names it had before scenes of pairs (`contact.vtp`, with the
    // increments' series); a scene numbers its pairs.
    let one_pair = !problem.is_scene_of_pairs();
    for (k, (pair, c)) in problem.pairs().iter().zip(solution.pairs()).enumerate() {
        let displacement = solution.body(pair.body).map_or(&[][..], |s| s.displacement.as_slice());
        let name = problem.body(pair.body).map_or("", |p| p.name.as_str());
        let (file, title) = if one_pair {
            ("contact.vtp".to_string(), format!("contact of `{name}`"))
        } else {
            (format!("contact_{k}.vtp"), format!("contact {k} of `{name}`"))
        };
        written.push(save(dir, &file, &contact_vtp(c, displacement))?);
        if let Some(f) = c.friction.as_ref().filter(|f| one_pair && !f.snapshots.is_empty()) {
            written.extend(increment_series(dir, c, f)?);
        }
        contacts.push((title, file));
        add_obstacles(pair.spec.target, &pair.obstacles, c);
    }
    let mut blocks = vec![("bodies", bodies)];
    if !contacts.is_empty() {
        blocks.push(("contact", contacts));
    }
    if !obstacles.is_empty() {
        written.push(save(dir, "obstacles.vtp", &obstacles_vtp(problem, &obstacles))?);
        blocks.push(("obstacles", vec![("obstacles".to_string(), "obstacles.vtp".to_string())]));
    }
    written.push(save(dir, "solution.vtm", &multiblock(&blocks))?);
    if !problem.steps.is_empty() {
        let time = problem.steps.len() as f64;
        written.push(save(dir, "solution.pvd", &collection(&[(time, "solution.vtm")]))?);
    }
    Ok(written)
}

/// `[output] steps`: the contact edge at the end of every load increment,
/// `steps/contact_s<step>_i<increment>.vtp` (beside the increment's `.csv`), and the time series
/// `steps/contact.pvd` over them, at time `step − 1 + load factor` (step `k` ends at time `k`,
/// as in `solution.pvd`). The arrays are those of `contact.vtp` that an increment records:
/// `normal_force`, `pressure`, `tangential_force`, `tangential_traction`, `gap`, `slip`,
/// `in_contact` and `state` ([`FRICTION_STATES`]); the candidates stay at their undeformed
/// positions, since the increments' displacements are not kept (no `displacement` array).
fn increment_series(
    dir: &Path,
    c: &ContactSolution,
    f: &crate::solution::FrictionContact,
) -> Result<Vec<PathBuf>, OutputError> {
    let steps = dir.join("steps");
    super::create_dir(&steps)?;
    let cand = &c.candidates;
    let per_length = |v: &[f64]| v.iter().zip(&cand.segment_length).map(|(x, l)| x / l).collect();
    let mut written = Vec::new();
    let mut entries = Vec::new();
    for snap in &f.snapshots {
        let name = format!("contact_s{:03}_i{:04}.vtp", snap.step, snap.increment);
        let point_data = vec![
            Array::Int("node".into(), cand.nodes.iter().map(|&i| i64::from(i)).collect()),
            Array::Scalar("arc_length".into(), cand.arc_length.clone()),
            Array::Scalar("gap".into(), snap.gap.clone()),
            Array::Scalar("normal_force".into(), snap.normal.clone()),
            Array::Scalar("pressure".into(), per_length(&snap.normal)),
            Array::Int(
                "in_contact".into(),
                snap.state.iter().map(|&s| i64::from(s != ContactState::Open)).collect(),
            ),
            Array::Int("state".into(), snap.state.iter().map(|&s| state_code(s)).collect()),
            Array::Scalar("tangential_force".into(), snap.tangential.clone()),
            Array::Scalar("tangential_traction".into(), per_length(&snap.tangential)),
            Array::Scalar("slip".into(), snap.slip.clone()),
        ];
        let field_data = vec![
            Array::Strings("state_legend".into(), FRICTION_STATES.map(String::from).to_vec()),
            Array::Scalar("friction_coefficient".into(), vec![f.coefficient]),
        ];
        written.push(save(&steps, &name, &edge_vtp(&cand.points, &point_data, &field_data))?);
        entries.push((snap.step as f64 - 1.0 + snap.load_factor, name));
    }
    let list: Vec<(f64, &str)> = entries.iter().map(|(t, n)| (*t, n.as_str())).collect();
    written.push(save(&steps, "contact.pvd", &collection(&list))?);
    Ok(written)
}

/// The code of a frictional contact state in the `state` arrays ([`FRICTION_STATES`]).
fn state_code(s: ContactState) -> i64 {
    match s {
        ContactState::Open => 0,
        ContactState::Stick => 1,
        ContactState::SlipPositive => 2,
        ContactState::SlipNegative => 3,
    }
}

/// The polygonal data of the candidates `points`: each a vertex, and the edge through them in
/// order as one polyline.
fn edge_vtp(points: &[Point], point_data: &[Array], field_data: &[Array]) -> String {
    let n = points.len();
    let verts: Vec<Vec<usize>> = (0..n).map(|k| vec![k]).collect();
    let lines = if n >= 2 { vec![(0..n).collect()] } else { Vec::new() };
    poly_data(points, &verts, &lines, point_data, &[], field_data)
}

/// The polygonal data of one contact edge: each candidate as a vertex at its undeformed
/// position, and the edge through the candidates in order as one polyline; point data
/// `displacement` (`u^h` at the candidate's node), `normal` (`ν`, into the candidate body),
/// `node`, `arc_length`, `initial_gap`, `gap` (final), `normal_force` (`P`), `pressure`,
/// `in_contact` (0 or 1) and `state` ([`FRICTIONLESS_STATES`] or [`FRICTION_STATES`]), with
/// friction also `tangential_force` (`T`), `tangential_traction` and `slip`; field data
/// `state_legend` (the state names by code), `gap_tolerance` and with friction
/// `friction_coefficient`.
fn contact_vtp(c: &ContactSolution, displacement: &[[f64; 2]]) -> String {
    let cand = &c.candidates;
    let n = cand.len();
    let nodal = |k: usize| displacement.get(cand.nodes[k] as usize).copied().unwrap_or([0.0; 2]);
    let state: Vec<i64> = match &c.friction {
        Some(f) => f.step.state.iter().map(|&s| state_code(s)).collect(),
        None => c.closed.iter().map(|&k| i64::from(k)).collect(),
    };
    let mut point_data = vec![
        Array::Vector("displacement".into(), (0..n).map(nodal).collect()),
        Array::Vector("normal".into(), cand.normals.clone()),
        Array::Int("node".into(), cand.nodes.iter().map(|&i| i64::from(i)).collect()),
        Array::Scalar("arc_length".into(), cand.arc_length.clone()),
        Array::Scalar("initial_gap".into(), cand.initial_gap.clone()),
        Array::Scalar("gap".into(), c.gap.clone()),
        Array::Scalar("normal_force".into(), c.lcp.z.clone()),
        Array::Scalar("pressure".into(), c.pressure.clone()),
        Array::Int("in_contact".into(), c.closed.iter().map(|&k| i64::from(k)).collect()),
        Array::Int("state".into(), state),
    ];
    let legend: &[&str] =
        if c.friction.is_some() { &FRICTION_STATES } else { &FRICTIONLESS_STATES };
    let mut field_data = vec![
        Array::Strings("state_legend".into(), legend.iter().map(|s| s.to_string()).collect()),
        Array::Scalar("gap_tolerance".into(), vec![c.gap_tolerance]),
    ];
    if let Some(f) = &c.friction {
        point_data.push(Array::Scalar("tangential_force".into(), f.step.tangential.clone()));
        point_data.push(Array::Scalar("tangential_traction".into(), f.traction.clone()));
        point_data.push(Array::Scalar("slip".into(), f.slip.clone()));
        field_data.push(Array::Scalar("friction_coefficient".into(), vec![f.coefficient]));
    }
    edge_vtp(&cand.points, &point_data, &field_data)
}

/// The rigid obstacles as polylines at their initial positions, one line cell each (cell data
/// `obstacle`, the index into the field-data array `obstacle_names`), with their rigid
/// displacement `d` (the last step's, or the one a prescribed force found) as the point vector
/// `displacement`. A circle is drawn with 360 chords, a polyline's rounded corners in pieces
/// of 2°, and a straight line as the segment beside the bodies (their bounding box's extent
/// along it, and a quarter of that beyond each end).
fn obstacles_vtp(problem: &Problem, obstacles: &[(String, Shape, Point)]) -> String {
    let (mut lo, mut hi) = problem.domain.bounding_box();
    for k in 1..problem.body_count() {
        if let Some(p) = problem.body(k) {
            let (a, b) = p.domain.bounding_box();
            lo = [lo[0].min(a[0]), lo[1].min(a[1])];
            hi = [hi[0].max(b[0]), hi[1].max(b[1])];
        }
    }
    let corners = [lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]];
    let mut points: Vec<Point> = Vec::new();
    let mut displacement = Vec::new();
    let mut lines = Vec::new();
    for (_, shape, d) in obstacles {
        let outline: Vec<Point> = match shape {
            Shape::Line(l) => {
                let t = [-l.normal[1], l.normal[0]];
                let along = |p: &Point| (p[0] - l.point[0]) * t[0] + (p[1] - l.point[1]) * t[1];
                let s_lo = corners.iter().map(along).fold(f64::INFINITY, f64::min);
                let s_hi = corners.iter().map(along).fold(f64::NEG_INFINITY, f64::max);
                let pad = 0.25 * (s_hi - s_lo);
                [s_lo - pad, s_hi + pad]
                    .iter()
                    .map(|s| [l.point[0] + s * t[0], l.point[1] + s * t[1]])
                    .collect()
            }
            Shape::Circle { centre, radius } => (0..=360)
                .map(|i| {
                    let a = std::f64::consts::TAU * f64::from(i % 360) / 360.0;
                    [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]
                })
                .collect(),
            Shape::Polyline(p) => p.outline(std::f64::consts::PI / 90.0),
        };
        let first = points.len();
        let mut line: Vec<usize> = (first..first + outline.len()).collect();
        if let Shape::Circle { .. } = shape {
            // The closing point is the first one again.
            line.pop();
            line.push(first);
            points.extend(&outline[..outline.len() - 1]);
        } else {
            points.extend(&outline);
        }
        displacement.resize(points.len(), *d);
        lines.push(line);
    }
    let names = obstacles.iter().map(|(n, _, _)| n.clone()).collect();
    poly_data(
        &points,
        &[],
        &lines,
        &[Array::Vector("displacement".into(), displacement)],
        &[Array::Int("obstacle".into(), (0..obstacles.len() as i64).collect())],
        &[Array::Strings("obstacle_names".into(), names)],
    )
}

/// The text of a `.vtm` multiblock file: one block per `(name, data sets)`, each data set a
/// `(name, file)` with the file relative to the `.vtm`.
pub(crate) fn multiblock(blocks: &[(&str, Vec<(String, String)>)]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\">"
    );
    let _ = writeln!(s, "<vtkMultiBlockDataSet>");
    for (b, (name, sets)) in blocks.iter().enumerate() {
        let _ = writeln!(s, "<Block index=\"{b}\" name=\"{}\">", xml_escape(name));
        for (k, (set, file)) in sets.iter().enumerate() {
            let _ = writeln!(
                s,
                "<DataSet index=\"{k}\" name=\"{}\" file=\"{}\"/>",
                xml_escape(set),
                xml_escape(file)
            );
        }
        let _ = writeln!(s, "</Block>");
    }
    let _ = writeln!(s, "</vtkMultiBlockDataSet>\n</VTKFile>");
    s
}

/// The text of a `.pvd` time series: one `(time, file)` per entry.
pub(crate) fn collection(entries: &[(f64, &str)]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ =
        writeln!(s, "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">");
    let _ = writeln!(s, "<Collection>");
    for (time, file) in entries {
        let _ = writeln!(
            s,
            "<DataSet timestep=\"{time}\" group=\"\" part=\"0\" file=\"{}\"/>",
            xml_escape(file)
        );
    }
    let _ = writeln!(s, "</Collection>\n</VTKFile>");
    s
}

#[cfg(test)]
mod tests {
    use super::{collection, multiblock};

    #[test]
    fn multiblock_and_collection_escape_names_and_list_every_file() {
        let vtm = multiblock(&[
            ("bodies", vec![("a&b".into(), "solution.vtu".into()), ("c".into(), "c/x.vtu".into())]),
            ("contact", vec![("contact".into(), "contact.vtp".into())]),
        ]);
        assert!(vtm.contains("<Block index=\"1\" name=\"contact\">"), "{vtm}");
        assert!(vtm.contains("name=\"a&amp;b\" file=\"solution.vtu\""), "{vtm}");
        assert!(vtm.contains("<DataSet index=\"1\" name=\"c\" file=\"c/x.vtu\"/>"), "{vtm}");
        let pvd = collection(&[(2.0, "solution.vtm")]);
        assert!(
            pvd.contains("timestep=\"2\" group=\"\" part=\"0\" file=\"solution.vtm\""),
            "{pvd}"
        );
    }
}
