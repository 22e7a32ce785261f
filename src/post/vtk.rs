//! VTK XML unstructured grid (`.vtu`, ASCII). MFVM: one polygon per subdomain cell, carrying
//! that node's displacement and stress as cell data. FE: the mesh nodes as points, each Q2
//! element drawn as four bilinear sub-quads through its nodes, displacement and (averaged)
//! nodal stress as point data. Opens in ParaView.

use super::num;
use crate::fem::Mesh;
use crate::model::{Model, Scheme};
use crate::problem::Problem;
use crate::solution::Solution;
use std::fmt::Write as _;

/// The VTU text of a solution.
pub fn solution_vtu(problem: &Problem, model: &Model, solution: &Solution) -> String {
    let cells = match &model.scheme {
        Scheme::Fem(fem) => return fem_vtu(problem, model, &fem.mesh, solution),
        Scheme::Mfvm(mfvm) => &mfvm.cells,
    };
    // One polygon (VTK_POLYGON) per subdomain cell, its own copy of the vertices; the node's
    // values as cell data.
    let points: Vec<[f64; 2]> = cells.iter().flat_map(|c| c.vertices.iter().copied()).collect();
    let mut next = 0usize;
    let connectivity: Vec<Vec<usize>> = cells
        .iter()
        .map(|c| {
            next += c.vertices.len();
            (next - c.vertices.len()..next).collect()
        })
        .collect();
    unstructured_grid(problem, solution, &points, &connectivity, 7, Location::Cell)
}

/// The FE solution: points = nodes, cells = four sub-quads per element (VTK_QUAD).
fn fem_vtu(problem: &Problem, model: &Model, mesh: &Mesh, solution: &Solution) -> String {
    // Local corner quadruples of the four sub-quads (counter-clockwise).
    const SUB: [[usize; 4]; 4] = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
    let connectivity: Vec<Vec<usize>> = mesh
        .elements
        .iter()
        .flat_map(|e| SUB.iter().map(move |q| q.iter().map(|&k| e[k] as usize).collect()))
        .collect();
    unstructured_grid(problem, solution, &model.nodes.points, &connectivity, 9, Location::Point)
}

/// Where the solution's values sit: on the cells (MFVM: one cell per node, with the node's
/// index as an extra array) or on the points (FE).
#[derive(Clone, Copy, PartialEq)]
enum Location {
    Cell,
    Point,
}

/// The VTU text of an unstructured grid of `points` and `cells` (all of VTK type `vtk_type`)
/// carrying the displacement, stress and von Mises stress of `solution` at `location`.
fn unstructured_grid(
    problem: &Problem,
    solution: &Solution,
    points: &[[f64; 2]],
    cells: &[Vec<usize>],
    vtk_type: u8,
    location: Location,
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">"
    );
    let _ = writeln!(s, "<UnstructuredGrid>");
    let _ = writeln!(
        s,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        points.len(),
        cells.len()
    );
    let _ = writeln!(
        s,
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for p in points {
        let _ = writeln!(s, "{} {} 0", num(p[0]), num(p[1]));
    }
    let _ = writeln!(s, "</DataArray>\n</Points>\n<Cells>");
    let _ = writeln!(s, "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">");
    for c in cells {
        let ids: Vec<String> = c.iter().map(|k| k.to_string()).collect();
        let _ = writeln!(s, "{}", ids.join(" "));
    }
    let _ =
        writeln!(s, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">");
    let mut end = 0usize;
    for c in cells {
        end += c.len();
        let _ = writeln!(s, "{end}");
    }
    let _ = writeln!(s, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">");
    for _ in cells {
        let _ = writeln!(s, "{vtk_type}");
    }
    let tag = match location {
        Location::Cell => "CellData",
        Location::Point => "PointData",
    };
    let _ = writeln!(s, "</DataArray>\n</Cells>\n<{tag} Vectors=\"displacement\">");
    if location == Location::Cell {
        let _ = writeln!(s, "<DataArray type=\"Int64\" Name=\"node\" format=\"ascii\">");
        for i in 0..cells.len() {
            let _ = writeln!(s, "{i}");
        }
        let _ = writeln!(s, "</DataArray>");
    }
    let _ = writeln!(
        s,
        "<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for u in &solution.displacement {
        let _ = writeln!(s, "{} {} 0", num(u[0]), num(u[1]));
    }
    let _ = writeln!(
        s,
        "</DataArray>\n<DataArray type=\"Float64\" Name=\"stress_xx_yy_xy\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for t in &solution.stress {
        let _ = writeln!(s, "{} {} {}", num(t[0]), num(t[1]), num(t[2]));
    }
    let _ = writeln!(
        s,
        "</DataArray>\n<DataArray type=\"Float64\" Name=\"von_mises\" format=\"ascii\">"
    );
    for t in &solution.stress {
        let _ = writeln!(s, "{}", num(problem.material.von_mises(*t)));
    }
    let _ = writeln!(s, "</DataArray>\n</{tag}>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>");
    s
}
