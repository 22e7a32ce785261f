//! VTK XML unstructured grid (`.vtu`, ASCII). MFVM: one polygon per subdomain cell, carrying
//! that node's displacement and stress as cell data. FE: the mesh nodes as points, each Q2
//! element drawn as four bilinear sub-quads through its nodes, displacement and (averaged)
//! nodal stress as point data. Opens in ParaView.

use super::num;
use crate::fem::Mesh;
use crate::problem::Problem;
use crate::{Model, Solution};
use std::fmt::Write as _;

/// The VTU text of a solution.
pub fn solution_vtu(problem: &Problem, model: &Model, solution: &Solution) -> String {
    if let Some(mesh) = &model.mesh {
        return fem_vtu(problem, model, mesh, solution);
    }
    let cells = &model.cells;
    let n_points: usize = cells.iter().map(|c| c.vertices.len()).sum();
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">"
    );
    let _ = writeln!(s, "<UnstructuredGrid>");
    let _ = writeln!(s, "<Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{}\">", cells.len());
    let _ = writeln!(
        s,
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for c in cells {
        for v in &c.vertices {
            let _ = writeln!(s, "{} {} 0", num(v[0]), num(v[1]));
        }
    }
    let _ = writeln!(s, "</DataArray>\n</Points>\n<Cells>");
    let _ = writeln!(s, "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">");
    let mut next = 0usize;
    for c in cells {
        let ids: Vec<String> = (next..next + c.vertices.len()).map(|k| k.to_string()).collect();
        next += c.vertices.len();
        let _ = writeln!(s, "{}", ids.join(" "));
    }
    let _ =
        writeln!(s, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">");
    let mut end = 0usize;
    for c in cells {
        end += c.vertices.len();
        let _ = writeln!(s, "{end}");
    }
    let _ = writeln!(s, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">");
    for _ in cells {
        let _ = writeln!(s, "7");
    }
    let _ = writeln!(s, "</DataArray>\n</Cells>\n<CellData Vectors=\"displacement\">");
    let _ = writeln!(s, "<DataArray type=\"Int64\" Name=\"node\" format=\"ascii\">");
    for i in 0..cells.len() {
        let _ = writeln!(s, "{i}");
    }
    let _ = writeln!(
        s,
        "</DataArray>\n<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">"
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
    let _ = writeln!(s, "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>");
    s
}

/// The FE solution: points = nodes, cells = four sub-quads per element (VTK_QUAD).
fn fem_vtu(problem: &Problem, model: &Model, mesh: &Mesh, solution: &Solution) -> String {
    // Local corner quadruples of the four sub-quads (counter-clockwise).
    const SUB: [[usize; 4]; 4] = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
    let points = &model.nodes.points;
    let n_cells = 4 * mesh.elements.len();
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">"
    );
    let _ = writeln!(s, "<UnstructuredGrid>");
    let _ = writeln!(s, "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{n_cells}\">", points.len());
    let _ = writeln!(
        s,
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for p in points {
        let _ = writeln!(s, "{} {} 0", num(p[0]), num(p[1]));
    }
    let _ = writeln!(s, "</DataArray>\n</Points>\n<Cells>");
    let _ = writeln!(s, "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">");
    for e in &mesh.elements {
        for q in SUB {
            let _ = writeln!(s, "{} {} {} {}", e[q[0]], e[q[1]], e[q[2]], e[q[3]]);
        }
    }
    let _ =
        writeln!(s, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">");
    for k in 1..=n_cells {
        let _ = writeln!(s, "{}", 4 * k);
    }
    let _ = writeln!(s, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">");
    for _ in 0..n_cells {
        let _ = writeln!(s, "9");
    }
    let _ = writeln!(s, "</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">");
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
    let _ = writeln!(s, "</DataArray>\n</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>");
    s
}
