//! `solution_revolved.vtu` (`[output] revolve`): an axisymmetric body's section swept about
//! the axis into a 3-D body for ParaView. The section `(r, z)` of `solution.vtu` is copied
//! at the angles `θ_j = j Θ / n` (`Θ` the swept angle, `n` the segments; a full turn reuses
//! the first copy as the last), the point `(r, z)` at `θ` placed at `(r cos θ, r sin θ, z)`;
//! each section cell, fanned into triangles, gives one wedge (VTK_WEDGE) per segment. The
//! wedges' volume is `n sin(Θ/n) ∫ r dA`, which tends to the revolved volume `Θ ∫ r dA`.
//!
//! Point data: `displacement` `(u_r cos θ, u_r sin θ, u_z)`, and `stress` and `strain` as
//! symmetric Cartesian tensors from their cylindrical components (`rr, zz, θθ, rz`; docs/
//! method.md §9.2), in VTK's order `xx, yy, zz, xy, yz, xz`:
//! `σ_xx = σ_rr c² + σ_θθ s²`, `σ_yy = σ_rr s² + σ_θθ c²`, `σ_zz`, `σ_xy = (σ_rr − σ_θθ) s c`,
//! `σ_yz = σ_rz s`, `σ_xz = σ_rz c` (`c = cos θ`, `s = sin θ`); `von_mises` as in the section.

use super::vtk::{self, Array, Grid};
use crate::problem::Revolve;
use std::fmt::Write as _;

/// VTK's wedge (triangular prism): the triangle `0, 1, 2` at one angle, `3, 4, 5` at the next,
/// the first triangle's right-hand normal pointing towards the second (VTK's cell volume is
/// negative otherwise).
const VTK_WEDGE: u8 = 13;

/// A cylindrical symmetric tensor `(rr, zz, θθ, rz)` (the section's order `xx, yy, zz, xy`
/// with x = r, y = z and z = θ) at angle `θ`, in Cartesian components `xx, yy, zz, xy, yz, xz`.
pub(crate) fn cartesian_tensor(t: [f64; 6], theta: f64) -> [f64; 6] {
    let (s, c) = theta.sin_cos();
    let [rr, zz, tt, rz, _, _] = t;
    [rr * c * c + tt * s * s, rr * s * s + tt * c * c, zz, (rr - tt) * s * c, rz * s, rz * c]
}

/// The angles of the copies of the section: `n + 1`, or `n` for a full turn (the body closes).
fn angles(revolve: &Revolve) -> Vec<f64> {
    let n = revolve.segments;
    let full = revolve.full_turn();
    let step = revolve.angle_degrees.to_radians() / n as f64;
    (0..n + usize::from(!full)).map(|j| j as f64 * step).collect()
}

/// The section's cells fanned into triangles, each clockwise in `(r, z)`: at `θ = 0` the
/// section lies in the plane `(x, z)` and a clockwise triangle's normal is `+y`, towards the
/// next copy, as VTK orders a wedge.
fn triangles(grid: &Grid) -> Vec<[usize; 3]> {
    let area = |t: [usize; 3]| {
        let [a, b, c] = t.map(|k| grid.points[k]);
        (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
    };
    let mut out = Vec::new();
    for cell in &grid.cells {
        for k in 1..cell.len().saturating_sub(1) {
            let t = [cell[0], cell[k], cell[k + 1]];
            match area(t) {
                a if a < 0.0 => out.push(t),
                a if a > 0.0 => out.push([t[0], t[2], t[1]]),
                _ => {}
            }
        }
    }
    out
}

/// The VTU text of the section `grid` (an axisymmetric body's `solution.vtu` grid) swept as
/// `revolve` says.
pub(crate) fn revolved_vtu(grid: &Grid, revolve: &Revolve) -> String {
    let thetas = angles(revolve);
    let rings = thetas.len();
    let m = grid.points.len();
    let id = |j: usize, k: usize| (j % rings) * m + k;
    let triangles = triangles(grid);
    let mut cells = Vec::with_capacity(triangles.len() * revolve.segments);
    for j in 0..revolve.segments {
        for t in &triangles {
            cells.push(
                [t[0], t[1], t[2]]
                    .map(|k| id(j, k))
                    .into_iter()
                    .chain(t.map(|k| id(j + 1, k)))
                    .collect::<Vec<usize>>(),
            );
        }
    }
    let mut point_data = Vec::new();
    for array in &grid.point_data {
        match array {
            Array::Vector(name, v) => point_data.push(Array::Vector3(
                name.clone(),
                thetas
                    .iter()
                    .flat_map(|&th| v.iter().map(move |u| [u[0] * th.cos(), u[0] * th.sin(), u[1]]))
                    .collect(),
            )),
            Array::Tensor(name, v) => point_data.push(Array::Tensor(
                name.clone(),
                thetas
                    .iter()
                    .flat_map(|&th| v.iter().map(move |t| cartesian_tensor(*t, th)))
                    .collect(),
            )),
            Array::Scalar(name, v) => point_data.push(Array::Scalar(
                name.clone(),
                thetas.iter().flat_map(|_| v.iter().copied()).collect(),
            )),
            _ => {}
        }
    }
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>"
    );
    let _ =
        writeln!(s, "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">", rings * m, cells.len());
    let _ = writeln!(
        s,
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    );
    for &th in &thetas {
        let (sin, cos) = th.sin_cos();
        for p in &grid.points {
            let _ = writeln!(
                s,
                "{} {} {}",
                super::num(p[0] * cos),
                super::num(p[0] * sin),
                super::num(p[1])
            );
        }
    }
    let _ = writeln!(s, "</DataArray>\n</Points>\n<Cells>");
    vtk::write_connectivity(&mut s, &cells);
    let _ = writeln!(s, "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">");
    for _ in &cells {
        let _ = writeln!(s, "{VTK_WEDGE}");
    }
    let _ = writeln!(s, "</DataArray>\n</Cells>");
    vtk::write_arrays(&mut s, "PointData", &point_data);
    let _ = writeln!(s, "</Piece>\n</UnstructuredGrid>\n</VTKFile>");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tensor_rotation_keeps_invariants_and_axes() {
        let t = [3.0, -1.0, 2.0, 0.5, 0.0, 0.0];
        // At θ = 0 the Cartesian frame is (r, θ, z): xx = rr, yy = θθ, xz = rz.
        assert_eq!(cartesian_tensor(t, 0.0), [3.0, 2.0, -1.0, 0.0, 0.0, 0.5]);
        let c = cartesian_tensor(t, 0.7);
        let trace = c[0] + c[1] + c[2];
        assert!((trace - 4.0).abs() < 1e-14, "{trace}");
        let norm = |v: [f64; 6]| {
            v[..3].iter().map(|x| x * x).sum::<f64>()
                + 2.0 * v[3..].iter().map(|x| x * x).sum::<f64>()
        };
        let cyl = t[0] * t[0] + t[1] * t[1] + t[2] * t[2] + 2.0 * t[3] * t[3];
        assert!((norm(c) - cyl).abs() < 1e-13, "{} {cyl}", norm(c));
    }
}
