//! VTK XML unstructured grid (`.vtu`, ASCII). MFVM: one polygon per subdomain cell over shared
//! points (the cells' coinciding vertices merged), the MLS field at each point as point data —
//! `u^h(x) = Σ φ_J(x) û_J` and `σ = D Σ φ_J(x) ε̂_J` (docs/method.md §3.2) — so that ParaView's
//! "Warp By Vector" keeps the body whole; the node's own values (and its index) as cell data.
//! FE: the mesh nodes as points, each Q2 element drawn as four bilinear sub-quads through its
//! nodes, displacement and (averaged) nodal stress as point data. Opens in ParaView.

use super::{OutputError, num};
use crate::fem::Mesh;
use crate::geometry::Point;
use crate::material;
use crate::mls;
use crate::model::{Model, Scheme};
use crate::problem::Problem;
use crate::solution::Solution;
use std::collections::HashMap;
use std::fmt::Write as _;

/// Merge tolerance of cell vertices, relative to the smallest node spacing.
pub(crate) const MERGE_TOLERANCE: f64 = 1e-9;

/// The VTU text of a solution.
///
/// # Errors
/// [`OutputError::Field`] when the MLS shape functions cannot be evaluated at a cell vertex.
pub fn solution_vtu(
    problem: &Problem,
    model: &Model,
    solution: &Solution,
) -> Result<String, OutputError> {
    let mfvm = match &model.scheme {
        Scheme::Fem(fem) => return Ok(fem_vtu(problem, model, &fem.mesh, solution)),
        Scheme::Mfvm(mfvm) => mfvm,
    };
    let h = model.nodes.spacing.iter().copied().filter(|h| *h > 0.0).fold(f64::INFINITY, f64::min);
    let h = if h.is_finite() { h } else { 1.0 };
    let (points, polygons) =
        merge_vertices(mfvm.cells.iter().map(|c| c.vertices.as_slice()), MERGE_TOLERANCE * h);
    let shapes = mls::shape_functions(
        &points,
        &model.nodes,
        &mfvm.supports,
        &problem.discretisation.mls,
        false,
    )
    .map_err(|e| OutputError::Field { reason: e.to_string() })?;
    let d = problem.material.constitutive();
    let displacement: Vec<[f64; 2]> =
        (0..points.len()).map(|k| shapes.interpolate(k, &solution.nodal_parameters)).collect();
    let stress: Vec<[f64; 3]> = (0..points.len())
        .map(|k| {
            let mut e = [0.0; 3];
            for (&j, &phi) in shapes.support(k).iter().zip(shapes.phi(k)) {
                let ej = solution.strain[j as usize];
                for c in 0..3 {
                    e[c] += phi * ej[c];
                }
            }
            material::apply(&d, e)
        })
        .collect();
    let point_data = field_arrays(problem, "", &displacement, &stress);
    let mut cell_data = vec![Array::Index("node", (0..polygons.len()).collect())];
    cell_data.extend(field_arrays(problem, "node_", &solution.displacement, &solution.stress));
    Ok(unstructured_grid(&points, &polygons, 7, &point_data, &cell_data))
}

/// Merges the vertices of `cells` that coincide within `tol` (max-norm): each vertex is
/// snapped to a grid of spacing `tol` and looked up in its own and the eight neighbouring grid
/// cells, so two vertices closer than `tol` always merge and the merged points are pairwise at
/// least `tol` apart. Deterministic: the first occurrence (in cell order) is kept. Returns the
/// points and each cell's polygon as point indices (repeated consecutive points dropped).
pub(crate) fn merge_vertices<'a>(
    cells: impl Iterator<Item = &'a [Point]>,
    tol: f64,
) -> (Vec<Point>, Vec<Vec<usize>>) {
    let mut points: Vec<Point> = Vec::new();
    let mut grid: HashMap<(i64, i64), usize> = HashMap::new();
    let mut polygons = Vec::new();
    for vertices in cells {
        let mut polygon: Vec<usize> = Vec::with_capacity(vertices.len());
        for &v in vertices {
            let key = ((v[0] / tol).round() as i64, (v[1] / tol).round() as i64);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    if let Some(&k) = grid.get(&(key.0 + dx, key.1 + dy)) {
                        let p = points[k];
                        if (p[0] - v[0]).abs() <= tol && (p[1] - v[1]).abs() <= tol {
                            found = Some(k);
                            break 'search;
                        }
                    }
                }
            }
            let k = found.unwrap_or_else(|| {
                points.push(v);
                grid.insert(key, points.len() - 1);
                points.len() - 1
            });
            if polygon.last() != Some(&k) {
                polygon.push(k);
            }
        }
        while polygon.len() > 1 && polygon.first() == polygon.last() {
            polygon.pop();
        }
        polygons.push(polygon);
    }
    (points, polygons)
}

/// VTK's cell types used here.
const VTK_TRIANGLE: u8 = 5;
const VTK_QUAD: u8 = 9;

/// The FE solution: points = nodes, cells = four sub-quads per Q2 element (VTK_QUAD) and four
/// sub-triangles per T6 element (VTK_TRIANGLE).
fn fem_vtu(problem: &Problem, model: &Model, mesh: &Mesh, solution: &Solution) -> String {
    // Local corner quadruples of the four sub-quads of a Q2 element and corner triples of the
    // four sub-triangles of a T6 element (counter-clockwise on the reference element).
    const SUB: [[usize; 4]; 4] = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
    const SUB_T: [[usize; 3]; 4] = [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]];
    let quads = mesh
        .elements
        .iter()
        .flat_map(|e| SUB.iter().map(move |q| q.iter().map(|&k| e[k] as usize).collect()));
    let triangles = mesh
        .triangles
        .iter()
        .flat_map(|e| SUB_T.iter().map(move |q| q.iter().map(|&k| e[k] as usize).collect()));
    let connectivity: Vec<Vec<usize>> = quads.chain(triangles).collect();
    let point_data = field_arrays(problem, "", &solution.displacement, &solution.stress);
    unstructured_grid(&model.nodes.points, &connectivity, VTK_QUAD, &point_data, &[])
}

/// One data array of a VTU piece.
enum Array {
    /// Integers, one per tuple.
    Index(&'static str, Vec<usize>),
    /// 2-D vectors, written with a zero third component.
    Vector(String, Vec<[f64; 2]>),
    /// Three components (the stress `σxx σyy σxy`).
    Triple(String, Vec<[f64; 3]>),
    /// Scalars.
    Scalar(String, Vec<f64>),
}

/// Displacement, stress and von Mises stress, named with `prefix`.
fn field_arrays(
    problem: &Problem,
    prefix: &str,
    displacement: &[[f64; 2]],
    stress: &[[f64; 3]],
) -> Vec<Array> {
    vec![
        Array::Vector(format!("{prefix}displacement"), displacement.to_vec()),
        Array::Triple(format!("{prefix}stress_xx_yy_xy"), stress.to_vec()),
        Array::Scalar(
            format!("{prefix}von_mises"),
            stress.iter().map(|t| problem.material.von_mises(*t)).collect(),
        ),
    ]
}

fn write_arrays(s: &mut String, tag: &str, arrays: &[Array]) {
    if arrays.is_empty() {
        return;
    }
    let vectors = arrays.iter().find_map(|a| match a {
        Array::Vector(name, _) => Some(name.as_str()),
        _ => None,
    });
    match vectors {
        Some(name) => {
            let _ = writeln!(s, "<{tag} Vectors=\"{name}\">");
        }
        None => {
            let _ = writeln!(s, "<{tag}>");
        }
    }
    for a in arrays {
        match a {
            Array::Index(name, v) => {
                let _ = writeln!(s, "<DataArray type=\"Int64\" Name=\"{name}\" format=\"ascii\">");
                for i in v {
                    let _ = writeln!(s, "{i}");
                }
            }
            Array::Vector(name, v) => {
                let _ = writeln!(
                    s,
                    "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" format=\"ascii\">"
                );
                for u in v {
                    let _ = writeln!(s, "{} {} 0", num(u[0]), num(u[1]));
                }
            }
            Array::Triple(name, v) => {
                let _ = writeln!(
                    s,
                    "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" format=\"ascii\">"
                );
                for t in v {
                    let _ = writeln!(s, "{} {} {}", num(t[0]), num(t[1]), num(t[2]));
                }
            }
            Array::Scalar(name, v) => {
                let _ =
                    writeln!(s, "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">");
                for x in v {
                    let _ = writeln!(s, "{}", num(*x));
                }
            }
        }
        let _ = writeln!(s, "</DataArray>");
    }
    let _ = writeln!(s, "</{tag}>");
}

/// The VTU text of an unstructured grid of `points` and `cells` (all of VTK type `vtk_type`)
/// with the given point and cell data.
fn unstructured_grid(
    points: &[Point],
    cells: &[Vec<usize>],
    vtk_type: u8,
    point_data: &[Array],
    cell_data: &[Array],
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
    for c in cells {
        // A 3-vertex cell of a quadrilateral grid (the FE's sub-triangles) is a triangle.
        let t = if vtk_type == VTK_QUAD && c.len() == 3 { VTK_TRIANGLE } else { vtk_type };
        let _ = writeln!(s, "{t}");
    }
    let _ = writeln!(s, "</DataArray>\n</Cells>");
    write_arrays(&mut s, "PointData", point_data);
    write_arrays(&mut s, "CellData", cell_data);
    let _ = writeln!(s, "</Piece>\n</UnstructuredGrid>\n</VTKFile>");
    s
}

#[cfg(test)]
mod tests {
    use super::merge_vertices;

    #[test]
    fn coinciding_vertices_merge_and_distinct_ones_do_not() {
        let a = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        // The neighbour computes the shared edge with round-off, one vertex twice.
        let b = [[1.0 + 1e-15, -1e-16], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0 - 2e-15], [1.0, 1.0]];
        let (points, polygons) = merge_vertices([&a[..], &b[..]].into_iter(), 1e-9);
        assert_eq!(points.len(), 6);
        assert_eq!(polygons, vec![vec![0, 1, 2, 3], vec![1, 4, 5, 2]]);
        // Across a grid line: 0.4e-9 and 1.3e-9 snap to different cells but are within tol.
        let c = [[0.4e-9, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let d = [[1.3e-9, 0.0], [1.0, 5.0], [0.0, 7.0]];
        let (points, _) = merge_vertices([&c[..], &d[..]].into_iter(), 1e-9);
        assert_eq!(points.len(), 5);
    }
}
