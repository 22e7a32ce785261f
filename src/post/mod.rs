//! Stage 9: outputs — CSV tables, a VTU file for ParaView, plots and `summary.json`.
//!
//! Every file is deterministic (fixed float formatting, sorted keys) except the `timings`
//! field of `summary.json`.

pub mod plot;
pub mod progress;
mod vtk;

use crate::nodes::Axis;
use crate::problem::Problem;
use crate::{Model, Solution};
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Failures while writing outputs.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// File-system error.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// Plotting failed.
    #[error("cannot draw plot {path}: {reason}")]
    Plot {
        /// The path.
        path: String,
        /// The cause.
        reason: String,
    },
}

/// Writes `text` to `path`.
///
/// # Errors
/// [`OutputError::Io`].
pub fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    std::fs::write(path, text)
        .map_err(|source| OutputError::Io { path: path.display().to_string(), source })
}

/// Creates the output directory (and parents).
///
/// # Errors
/// [`OutputError::Io`].
pub fn create_dir(dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir)
        .map_err(|source| OutputError::Io { path: dir.display().to_string(), source })
}

/// Formats a float for CSV/JSON-like text: 12 significant digits, scientific.
pub fn num(v: f64) -> String {
    format!("{v:.11e}")
}

/// The files written for an elastostatic solution.
pub fn write_solution(
    dir: &Path,
    problem: &Problem,
    model: &Model,
    solution: &Solution,
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let mut written = Vec::new();
    let nodes = &model.nodes;
    let names = problem.domain.edge_names();

    let mut text = String::from("node,x,y,edges,spacing\n");
    for (i, p) in nodes.points.iter().enumerate() {
        let edges: Vec<&str> = nodes.edges[i].iter().map(|k| names[k].as_str()).collect();
        let _ = writeln!(
            text,
            "{i},{},{},{},{}",
            num(p[0]),
            num(p[1]),
            edges.join("|"),
            num(nodes.spacing[i])
        );
    }
    written.push(save(dir, "nodes.csv", &text)?);

    let mut text = String::from("node,x,y,ux,uy\n");
    for (i, p) in nodes.points.iter().enumerate() {
        let u = solution.displacement[i];
        let _ = writeln!(text, "{i},{},{},{},{}", num(p[0]), num(p[1]), num(u[0]), num(u[1]));
    }
    written.push(save(dir, "displacement.csv", &text)?);

    let mut text = String::from("node,x,y,sxx,syy,sxy,von_mises\n");
    for (i, p) in nodes.points.iter().enumerate() {
        let s = solution.stress[i];
        let vm = problem.material.von_mises(s);
        let _ = writeln!(
            text,
            "{i},{},{},{},{},{},{}",
            num(p[0]),
            num(p[1]),
            num(s[0]),
            num(s[1]),
            num(s[2]),
            num(vm)
        );
    }
    written.push(save(dir, "stress.csv", &text)?);

    let mut text = String::from("node,axis,x,y,reaction\n");
    for &(node, axis, r) in &solution.reactions {
        let p = nodes.points[node as usize];
        let a = if axis == Axis::X { "x" } else { "y" };
        let _ = writeln!(text, "{node},{a},{},{},{}", num(p[0]), num(p[1]), num(r));
    }
    written.push(save(dir, "reactions.csv", &text)?);

    let vtu = vtk::solution_vtu(problem, model, solution);
    written.push(save(dir, "solution.vtu", &vtu)?);

    written.extend(solution_plots(dir, problem, model, solution)?);
    Ok(written)
}

fn save(dir: &Path, name: &str, text: &str) -> Result<PathBuf, OutputError> {
    let path = dir.join(name);
    write_text(&path, text)?;
    Ok(path)
}

/// Deformed shape coloured by von Mises stress, and the displacement profile along an edge.
fn solution_plots(
    dir: &Path,
    problem: &Problem,
    model: &Model,
    solution: &Solution,
) -> Result<Vec<PathBuf>, OutputError> {
    let plots = dir.join("plots");
    create_dir(&plots)?;
    let nodes = &model.nodes;
    let (lo, hi) = problem.domain.bounding_box();
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let umax = solution.displacement.iter().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
    let magnification = if umax > 0.0 { 0.1 * size / umax } else { 1.0 };
    let map = plot::ColourMap {
        title: format!("{}: deformed shape (x{magnification:.3e}), von Mises stress", problem.name),
        value_label: "von Mises".into(),
        points: nodes
            .points
            .iter()
            .zip(&solution.displacement)
            .map(|(p, u)| (p[0] + magnification * u[0], p[1] + magnification * u[1]))
            .collect(),
        values: solution.stress.iter().map(|s| problem.material.von_mises(*s)).collect(),
    };
    let deformed = plots.join("deformed");
    plot::write_colour_map(&deformed, &map)?;

    let k = problem.profile_edge;
    let name = &problem.domain.edge_names()[k];
    let mut on_edge: Vec<(f64, usize)> = (0..nodes.len())
        .filter(|&i| nodes.edges[i].contains(k))
        .map(|i| (problem.domain.edge_parameter(k, nodes.points[i]), i))
        .collect();
    on_edge.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (a, b) = problem.domain.edge(k);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let series = |axis: usize, label: &str, colour: usize| plot::Series {
        label: label.into(),
        points: on_edge.iter().map(|&(t, i)| (t * len, solution.displacement[i][axis])).collect(),
        style: plot::Style::Line,
        colour,
    };
    let chart = plot::Chart {
        title: format!("{}: displacement u^h along edge `{name}`", problem.name),
        x_label: format!("distance along `{name}` from its first vertex"),
        y_label: "displacement".into(),
        series: vec![series(0, "u_x", 0), series(1, "u_y", 1)],
    };
    let profile = plots.join("profile");
    plot::write_chart(&profile, &chart)?;
    Ok(vec![
        deformed.with_extension("svg"),
        deformed.with_extension("png"),
        profile.with_extension("svg"),
        profile.with_extension("png"),
    ])
}

/// The summary of an elastostatic run as JSON (`input` is the echo of the problem file).
pub fn summary(input: Value, problem: &Problem, model: &Model, solution: &Solution) -> Value {
    let timings: serde_json::Map<String, Value> =
        solution.timings.iter().map(|t| (t.stage.to_string(), json!(t.seconds))).collect();
    json!({
        "program": { "name": env!("CARGO_PKG_NAME"), "version": env!("CARGO_PKG_VERSION") },
        "input": input,
        "problem": {
            "name": problem.name,
            "material": problem.material,
            "discretisation": problem.discretisation,
            "layout": problem.layout,
            "node_spacing": problem.node_spacing,
        },
        "counts": {
            "nodes": model.nodes.len(),
            "dofs": model.nodes.dof_count(),
            "constrained_dofs": model.system.constraints.len(),
            "interior_faces": model.faces.interior.len(),
            "boundary_faces": model.faces.boundary.len(),
            "matrix_nonzeros": model.system.matrix.values.len(),
        },
        "checks": {
            "relative_residual": solution.relative_residual,
            "equilibrium_error": solution.equilibrium_error,
            "applied_force": solution.applied_force,
            "reaction_force": solution.reaction_force,
        },
        "results": {
            "max_displacement": solution.displacement.iter().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max),
            "max_von_mises": solution.stress.iter().map(|s| problem.material.von_mises(*s)).fold(0.0, f64::max),
        },
        "timings": timings,
    })
}
