//! VTK XML files (ASCII) for ParaView. `solution.vtu`, an unstructured grid of one body:
//! MFVM: one polygon per subdomain cell over shared points (the cells' coinciding vertices
//! merged), the MLS field at each point as point data — `u^h(x) = Σ φ_J(x) û_J`, the strain
//! `Σ φ_J(x) ε̂_J` and `σ = D Σ φ_J(x) ε̂_J` (docs/method.md §3.2) — so that ParaView's
//! "Warp By Vector" keeps the body whole; the node's own values (its index, its reaction) as
//! cell data. FE: the mesh nodes as points, each Q2 element drawn as four bilinear sub-quads
//! through its nodes, displacement, (averaged) nodal strain and stress and the reactions as
//! point data. Stress and strain are symmetric tensors of six components ([`stress_tensor`]).
//! The polygonal data (`.vtp`) of the contact edges and obstacles and the multiblock file that
//! opens everything at once are written by the sibling module `paraview`.

use super::{OutputError, num};
use crate::fem::Mesh;
use crate::geometry::Point;
use crate::material::{self, Material, PlaneState};
use crate::mls;
use crate::model::{Model, Scheme};
use crate::problem::Problem;
use crate::solution::Solution;
use std::collections::HashMap;
use std::fmt::Write as _;

/// Merge tolerance of cell vertices, relative to the smallest node spacing.
pub(crate) const MERGE_TOLERANCE: f64 = 1e-9;

/// A grid of `solution.vtu` before it is written: points, cells (all of VTK type `vtk_type`;
/// a 3-vertex cell of a quadrilateral grid is a triangle), point and cell data.
pub(crate) struct Grid {
    /// Points (z = 0).
    pub points: Vec<Point>,
    /// Cells as point indices.
    pub cells: Vec<Vec<usize>>,
    /// The cells' VTK type.
    pub vtk_type: u8,
    /// Point data.
    pub point_data: Vec<Array>,
    /// Cell data.
    pub cell_data: Vec<Array>,
}

impl Grid {
    /// The VTU text.
    pub fn to_vtu(&self) -> String {
        let Self { points, cells, vtk_type, point_data, cell_data } = self;
        unstructured_grid(points, cells, *vtk_type, point_data, cell_data)
    }
}

/// The grid of a solution's `solution.vtu` ([`Grid::to_vtu`] writes it).
///
/// Point data: `displacement` (a vector), `stress` and `strain` (symmetric tensors, see
/// [`tensor`]), `von_mises`; MFVM cell data (one cell per node): `node`, and the node's own
/// values `node_displacement`, `node_stress`, `node_strain`, `node_von_mises` and
/// `node_reaction` (the support reaction `R = K_int û − f − E P` on the node, zero in a
/// component without a displacement condition). FE: the points are the nodes, so `reaction`
/// is point data.
///
/// # Errors
/// [`OutputError::Field`] when the MLS shape functions cannot be evaluated at a cell vertex.
pub(crate) fn solution_grid(
    problem: &Problem,
    model: &Model,
    solution: &Solution,
) -> Result<Grid, OutputError> {
    let reaction = nodal_reactions(model.nodes.len(), solution);
    let mfvm = match &model.scheme {
        Scheme::Fem(fem) => return Ok(fem_grid(problem, model, &fem.mesh, solution, reaction)),
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
    let strain: Vec<[f64; 3]> = (0..points.len())
        .map(|k| {
            let mut e = [0.0; 3];
            for (&j, &phi) in shapes.support(k).iter().zip(shapes.phi(k)) {
                let ej = solution.strain[j as usize];
                for c in 0..3 {
                    e[c] += phi * ej[c];
                }
            }
            e
        })
        .collect();
    // Axisymmetric: the hoop strain interpolated like the others, the stresses with it.
    let hoop_strain: Vec<f64> = match solution.hoop.is_empty() {
        true => Vec::new(),
        false => (0..points.len())
            .map(|k| {
                let (support, phi) = (shapes.support(k), shapes.phi(k));
                support.iter().zip(phi).map(|(&j, &phi)| phi * solution.hoop[j as usize][0]).sum()
            })
            .collect(),
    };
    let (stress, hoop): (Vec<[f64; 3]>, Vec<[f64; 2]>) = match problem.material.hoop() {
        Some(law) => strain
            .iter()
            .zip(&hoop_strain)
            .map(|(e, &t)| (law.in_plane(&d, *e, t), [t, law.stress(*e, t)]))
            .unzip(),
        None => (strain.iter().map(|e| material::apply(&d, *e)).collect(), Vec::new()),
    };
    let point_data = field_arrays(&problem.material, "", &displacement, &stress, &strain, &hoop);
    let mut cell_data = vec![Array::Int("node".into(), (0..polygons.len() as i64).collect())];
    cell_data.extend(field_arrays(
        &problem.material,
        "node_",
        &solution.displacement,
        &solution.stress,
        &solution.strain,
        &solution.hoop,
    ));
    cell_data.push(Array::Vector("node_reaction".into(), reaction));
    Ok(Grid { points, cells: polygons, vtk_type: 7, point_data, cell_data })
}

/// The reaction `(R_x, R_y)` at each of `n` nodes (zero in a component without a
/// displacement condition).
fn nodal_reactions(n: usize, solution: &Solution) -> Vec<[f64; 2]> {
    let mut r = vec![[0.0; 2]; n];
    for &(node, axis, value) in &solution.reactions {
        if let Some(v) = r.get_mut(node as usize) {
            v[axis as usize] += value;
        }
    }
    r
}

/// The symmetric 3-D tensor of a plane stress `(σxx, σyy, σxy)` in VTK's six-component order
/// `xx, yy, zz, xy, yz, xz` (ParaView reads a six-component array as a symmetric tensor):
/// `σzz = 0` in plane stress and `ν (σxx + σyy)` in plane strain, `σyz = σxz = 0`; in
/// axisymmetry `zz` is the hoop `σ_θθ` of `hoop = (ε_θθ, σ_θθ)`.
pub(crate) fn stress_tensor(material: &Material, s: [f64; 3], hoop: Option<[f64; 2]>) -> [f64; 6] {
    [s[0], s[1], material.out_of_plane(s, hoop.map(|h| h[1])), s[2], 0.0, 0.0]
}

/// The symmetric strain tensor of the Voigt strain `(εxx, εyy, γxy)` in the order of
/// [`stress_tensor`]: the tensor shear `εxy = γxy / 2`; `εzz = −ν (εxx + εyy) / (1 − ν)` in
/// plane stress and 0 in plane strain; the hoop strain `ε_θθ` of `hoop` in axisymmetry.
pub(crate) fn strain_tensor(material: &Material, e: [f64; 3], hoop: Option<[f64; 2]>) -> [f64; 6] {
    let zz = match material.plane {
        PlaneState::Stress => -material.poisson / (1.0 - material.poisson) * (e[0] + e[1]),
        PlaneState::Strain => 0.0,
        PlaneState::Axisymmetric => hoop.map_or(f64::NAN, |h| h[0]),
    };
    [e[0], e[1], zz, 0.5 * e[2], 0.0, 0.0]
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

/// Local corner quadruples of the four sub-quads of a Q2 element (counter-clockwise on the
/// reference element).
const Q2_SUB_QUADS: [[usize; 4]; 4] = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]];
/// Local corner triples of the four sub-triangles of a T6 element (counter-clockwise).
const T6_SUB_TRIANGLES: [[usize; 3]; 4] = [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]];

/// The sub-cells of `mesh` as node lists: four sub-quads per Q2 element ([`Q2_SUB_QUADS`]),
/// then four sub-triangles per T6 element ([`T6_SUB_TRIANGLES`]).
pub(crate) fn fem_sub_cells(mesh: &Mesh) -> impl Iterator<Item = Vec<usize>> + '_ {
    let quads = mesh
        .elements
        .iter()
        .flat_map(|e| Q2_SUB_QUADS.iter().map(move |q| q.iter().map(|&k| e[k] as usize).collect()));
    let triangles = mesh.triangles.iter().flat_map(|e| {
        T6_SUB_TRIANGLES.iter().map(move |q| q.iter().map(|&k| e[k] as usize).collect())
    });
    quads.chain(triangles)
}

/// The FE solution: points = nodes, cells = four sub-quads per Q2 element (VTK_QUAD) and four
/// sub-triangles per T6 element (VTK_TRIANGLE).
fn fem_grid(
    problem: &Problem,
    model: &Model,
    mesh: &Mesh,
    solution: &Solution,
    reaction: Vec<[f64; 2]>,
) -> Grid {
    let connectivity: Vec<Vec<usize>> = fem_sub_cells(mesh).collect();
    let mut point_data = field_arrays(
        &problem.material,
        "",
        &solution.displacement,
        &solution.stress,
        &solution.strain,
        &solution.hoop,
    );
    point_data.push(Array::Vector("reaction".into(), reaction));
    let points = model.nodes.points.clone();
    Grid { points, cells: connectivity, vtk_type: VTK_QUAD, point_data, cell_data: Vec::new() }
}

/// One data array of a VTK XML piece.
pub(crate) enum Array {
    /// Integers, one per tuple.
    Int(String, Vec<i64>),
    /// 2-D vectors, written with a zero third component.
    Vector(String, Vec<[f64; 2]>),
    /// 3-D vectors.
    Vector3(String, Vec<[f64; 3]>),
    /// Symmetric tensors in VTK's order `xx, yy, zz, xy, yz, xz` ([`stress_tensor`]).
    Tensor(String, Vec<[f64; 6]>),
    /// Scalars.
    Scalar(String, Vec<f64>),
    /// Strings (field data: a legend).
    Strings(String, Vec<String>),
}

/// Displacement, stress and strain tensors and von Mises stress, named with `prefix`;
/// `hoop` holds `(ε_θθ, σ_θθ)` per point in axisymmetry (empty otherwise).
fn field_arrays(
    material: &Material,
    prefix: &str,
    displacement: &[[f64; 2]],
    stress: &[[f64; 3]],
    strain: &[[f64; 3]],
    hoop: &[[f64; 2]],
) -> Vec<Array> {
    let h = |i: usize| hoop.get(i).copied();
    vec![
        Array::Vector(format!("{prefix}displacement"), displacement.to_vec()),
        Array::Tensor(
            format!("{prefix}stress"),
            stress.iter().enumerate().map(|(i, s)| stress_tensor(material, *s, h(i))).collect(),
        ),
        Array::Tensor(
            format!("{prefix}strain"),
            strain.iter().enumerate().map(|(i, e)| strain_tensor(material, *e, h(i))).collect(),
        ),
        Array::Scalar(
            format!("{prefix}von_mises"),
            stress
                .iter()
                .enumerate()
                .map(|(i, t)| material.von_mises_with(*t, h(i).map(|h| h[1])))
                .collect(),
        ),
    ]
}

/// `text` with the five XML special characters escaped (for attribute values).
pub(crate) fn xml_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// Writes `arrays` as the section `tag` (`PointData`, `CellData`, `FieldData`); the first
/// vector and the first tensor are the section's active ones (`Vectors=`, `Tensors=`).
pub(crate) fn write_arrays(s: &mut String, tag: &str, arrays: &[Array]) {
    if arrays.is_empty() {
        return;
    }
    let _ = write!(s, "<{tag}");
    if tag != "FieldData" {
        let vectors = arrays.iter().find_map(|a| match a {
            Array::Vector(name, _) | Array::Vector3(name, _) => Some(name.as_str()),
            _ => None,
        });
        let tensors = arrays.iter().find_map(|a| match a {
            Array::Tensor(name, _) => Some(name.as_str()),
            _ => None,
        });
        if let Some(name) = vectors {
            let _ = write!(s, " Vectors=\"{}\"", xml_escape(name));
        }
        if let Some(name) = tensors {
            let _ = write!(s, " Tensors=\"{}\"", xml_escape(name));
        }
    }
    let _ = writeln!(s, ">");
    for a in arrays {
        match a {
            Array::Int(name, v) => {
                let _ = writeln!(
                    s,
                    "<DataArray type=\"Int64\" Name=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">",
                    xml_escape(name),
                    v.len()
                );
                for i in v {
                    let _ = writeln!(s, "{i}");
                }
            }
            Array::Vector(name, v) => {
                let _ = writeln!(
                    s,
                    "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"3\" NumberOfTuples=\"{}\" format=\"ascii\">",
                    xml_escape(name),
                    v.len()
                );
                for u in v {
                    let _ = writeln!(s, "{} {} 0", num(u[0]), num(u[1]));
                }
            }
            Array::Vector3(name, v) => {
                let _ = writeln!(
                    s,
                    "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"3\" NumberOfTuples=\"{}\" format=\"ascii\">",
                    xml_escape(name),
                    v.len()
                );
                for u in v {
                    let _ = writeln!(s, "{} {} {}", num(u[0]), num(u[1]), num(u[2]));
                }
            }
            Array::Tensor(name, v) => {
                let _ = writeln!(
                    s,
                    "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"6\" ComponentName0=\"XX\" ComponentName1=\"YY\" ComponentName2=\"ZZ\" ComponentName3=\"XY\" ComponentName4=\"YZ\" ComponentName5=\"XZ\" NumberOfTuples=\"{}\" format=\"ascii\">",
                    xml_escape(name),
                    v.len()
                );
                // A plane problem's out-of-plane shears are zero.
                for t in v {
                    for (k, &x) in t.iter().enumerate() {
                        let sep = if k == 0 { "" } else { " " };
                        if x == 0.0 {
                            let _ = write!(s, "{sep}0");
                        } else {
                            let _ = write!(s, "{sep}{}", num(x));
                        }
                    }
                    s.push('\n');
                }
            }
            Array::Scalar(name, v) => {
                let _ = writeln!(
                    s,
                    "<DataArray type=\"Float64\" Name=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">",
                    xml_escape(name),
                    v.len()
                );
                for x in v {
                    let _ = writeln!(s, "{}", num(*x));
                }
            }
            Array::Strings(name, v) => {
                // VTK's ASCII string arrays: each string as its bytes, ended by a 0.
                let _ = writeln!(
                    s,
                    "<DataArray type=\"String\" Name=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">",
                    xml_escape(name),
                    v.len()
                );
                for text in v {
                    let bytes: Vec<String> = text.bytes().map(|b| b.to_string()).collect();
                    let _ = writeln!(s, "{} 0", bytes.join(" "));
                }
            }
        }
        let _ = writeln!(s, "</DataArray>");
    }
    let _ = writeln!(s, "</{tag}>");
}

/// The `<Points>` section of `points` (z = 0).
pub(crate) fn write_points(s: &mut String, points: &[Point]) {
    let _ = writeln!(
        s,
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for p in points {
        let _ = writeln!(s, "{} {} 0", num(p[0]), num(p[1]));
    }
    let _ = writeln!(s, "</DataArray>\n</Points>");
}

/// The `connectivity` and `offsets` arrays of `cells` (point indices).
pub(crate) fn write_connectivity(s: &mut String, cells: &[Vec<usize>]) {
    let _ = writeln!(s, "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">");
    for c in cells {
        for (k, id) in c.iter().enumerate() {
            let _ = write!(s, "{}{id}", if k == 0 { "" } else { " " });
        }
        s.push('\n');
    }
    let _ =
        writeln!(s, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">");
    let mut end = 0usize;
    for c in cells {
        end += c.len();
        let _ = writeln!(s, "{end}");
    }
    let _ = writeln!(s, "</DataArray>");
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
    write_points(&mut s, points);
    let _ = writeln!(s, "<Cells>");
    write_connectivity(&mut s, cells);
    let _ = writeln!(s, "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">");
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

/// The VTP text of a polygonal data set: `points`, vertex cells `verts` and polyline cells
/// `lines` (point indices), point data and field data (the data set's own, e.g. a legend).
pub(crate) fn poly_data(
    points: &[Point],
    verts: &[Vec<usize>],
    lines: &[Vec<usize>],
    point_data: &[Array],
    cell_data: &[Array],
    field_data: &[Array],
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(s, "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">");
    let _ = writeln!(s, "<PolyData>");
    write_arrays(&mut s, "FieldData", field_data);
    let _ = writeln!(
        s,
        "<Piece NumberOfPoints=\"{}\" NumberOfVerts=\"{}\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">",
        points.len(),
        verts.len(),
        lines.len()
    );
    write_points(&mut s, points);
    for (tag, cells) in [("Verts", verts), ("Lines", lines)] {
        if !cells.is_empty() {
            let _ = writeln!(s, "<{tag}>");
            write_connectivity(&mut s, cells);
            let _ = writeln!(s, "</{tag}>");
        }
    }
    write_arrays(&mut s, "PointData", point_data);
    write_arrays(&mut s, "CellData", cell_data);
    let _ = writeln!(s, "</Piece>\n</PolyData>\n</VTKFile>");
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
