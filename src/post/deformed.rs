//! The cells of a body in the deformed plot: MFVM, each node's subdomain cell (the Voronoi
//! cell the method integrates over); FE, each element as the sub-quadrilaterals (Q2) or
//! sub-triangles (T6) through its nodes, as in `solution.vtu`. Each cell vertex is moved by
//! the magnified displacement: FE, the node's own; MFVM, the mean of the displacements of the
//! nodes whose cells meet at the vertex, so that neighbouring cells stay joined. The colour is
//! the von Mises stress: of the cell's node (MFVM), the mean of its corners' (FE).

use super::plot::Cell;
use super::vtk::{MERGE_TOLERANCE, fem_sub_cells, merge_vertices};
use crate::fem::Mesh;
use crate::model::{Mfvm, Model, Scheme};
use crate::problem::Problem;
use crate::solution::Solution;

/// The deformed cells of one body, its displacement magnified `m` times.
pub(super) fn body_cells(
    problem: &Problem,
    model: &Model,
    solution: &Solution,
    m: f64,
) -> Vec<Cell> {
    let von_mises = solution.von_mises(&problem.material);
    match &model.scheme {
        Scheme::Mfvm(mfvm) => mfvm_cells(mfvm, model, &solution.displacement, &von_mises, m),
        Scheme::Fem(fem) => fem_cells(&fem.mesh, model, &solution.displacement, &von_mises, m),
    }
}

/// The MFVM's cells, their shared vertices moved by the mean displacement of the nodes that
/// share them.
fn mfvm_cells(mfvm: &Mfvm, model: &Model, u: &[[f64; 2]], von_mises: &[f64], m: f64) -> Vec<Cell> {
    let h = model.nodes.spacing.iter().copied().filter(|h| *h > 0.0).fold(f64::INFINITY, f64::min);
    let h = if h.is_finite() { h } else { 1.0 };
    let n = mfvm.cells.len().min(u.len()).min(von_mises.len());
    let cells = mfvm.cells[..n].iter().map(|c| c.vertices.as_slice());
    let (points, polygons) = merge_vertices(cells, MERGE_TOLERANCE * h);
    let mut sum = vec![([0.0_f64, 0.0], 0.0_f64); points.len()];
    for (node, polygon) in polygons.iter().enumerate() {
        for &v in polygon {
            sum[v].0[0] += u[node][0];
            sum[v].0[1] += u[node][1];
            sum[v].1 += 1.0;
        }
    }
    let moved: Vec<(f64, f64)> = points
        .iter()
        .zip(&sum)
        .map(|(p, &(s, k))| (p[0] + m * s[0] / k.max(1.0), p[1] + m * s[1] / k.max(1.0)))
        .collect();
    polygons
        .iter()
        .zip(von_mises)
        .map(|(polygon, &value)| Cell {
            polygon: polygon.iter().map(|&v| moved[v]).collect(),
            value,
        })
        .collect()
}

/// The FE elements as sub-cells through their nodes, at the nodes' deformed positions.
fn fem_cells(mesh: &Mesh, model: &Model, u: &[[f64; 2]], von_mises: &[f64], m: f64) -> Vec<Cell> {
    let points = &model.nodes.points;
    let ok = |k: usize| k < points.len() && k < u.len() && k < von_mises.len();
    let cell = |corners: Vec<usize>| {
        if !corners.iter().all(|&k| ok(k)) {
            return None;
        }
        let polygon = corners
            .iter()
            .map(|&k| (points[k][0] + m * u[k][0], points[k][1] + m * u[k][1]))
            .collect();
        let value = corners.iter().map(|&k| von_mises[k]).sum::<f64>() / corners.len() as f64;
        Some(Cell { polygon, value })
    };
    fem_sub_cells(mesh).filter_map(cell).collect()
}
