//! The axisymmetric element stiffness (docs/method.md §9.5): with `x = r`, `y = z`, the
//! four-component strain `(ε_rr, ε_zz, γ_rz, ε_θθ)`, `ε_θθ = Σ_a N_a u_r,a / r`, and the volume
//! per radian `r dr dz`,
//!
//! `K_e = ∫ B₄ᵀ D₄ B₄ r |det J| dξ dη`
//!
//! on the isoparametric Q9 and T6 elements (the grid's rectangles are Q9 elements with straight
//! sides), by the element's own rule (3 × 3 Gauss, Dunavant's 6 points): every point lies
//! inside the element, so `r > 0` there even on elements touching the axis.

use super::element::{NODES, Shape, iso_derivatives};
use super::mesh::Mesh;
use crate::geometry::Point;
use crate::material::{Constitutive, Hoop};

/// The node coordinates of element `k` of `mesh` (grid or general).
pub fn coordinates(mesh: &Mesh, k: usize) -> Vec<Point> {
    let shape = mesh.cell(k).shape;
    (0..shape.node_count())
        .map(|a| {
            let [xi, eta] = shape.reference_node(a);
            mesh.point(k, xi, eta)
        })
        .collect()
}

/// `K_e` of element `k` of `mesh` (rows and columns past `2 ×` its node count are zero).
pub fn stiffness(
    mesh: &Mesh,
    k: usize,
    d: &Constitutive,
    hoop: &Hoop,
) -> [[f64; 2 * NODES]; 2 * NODES] {
    let shape: Shape = mesh.cell(k).shape;
    let coords = coordinates(mesh, k);
    let n = coords.len();
    let d4 = hoop.full(d);
    let mut ke = [[0.0; 2 * NODES]; 2 * NODES];
    for ([xi, eta], w) in shape.quadrature() {
        let (dx, dy, det) = iso_derivatives(shape, &coords, xi, eta);
        let [phi, _, _] = shape.functions(xi, eta);
        let r: f64 = coords.iter().zip(phi).map(|(x, p)| p * x[0]).sum();
        // B₄ (4 × 2n): rows ε_rr, ε_zz, γ_rz, ε_θθ.
        let mut b = [[0.0; 2 * NODES]; 4];
        for a in 0..n {
            b[0][2 * a] = dx[a];
            b[1][2 * a + 1] = dy[a];
            b[2][2 * a] = dy[a];
            b[2][2 * a + 1] = dx[a];
            b[3][2 * a] = phi[a] / r;
        }
        let w = w * det.abs() * r;
        let mut db = [[0.0; 2 * NODES]; 4];
        for (row, out) in d4.iter().zip(db.iter_mut()) {
            for (c, v) in out.iter_mut().enumerate().take(2 * n) {
                *v = (0..4).map(|s| row[s] * b[s][c]).sum();
            }
        }
        for p in 0..2 * n {
            for q in 0..2 * n {
                ke[p][q] += w * (0..4).map(|s| b[s][p] * db[s][q]).sum::<f64>();
            }
        }
    }
    ke
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, PlaneState};

    /// A uniform axial translation is the only rigid motion: `K_e` annihilates `u = (0, 1)` and
    /// not a uniform `u_r` (which strains the hoop); `K_e` is symmetric.
    #[test]
    fn rigid_axial_translation_only() {
        let mesh = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], 1.0);
        let m = Material { young: 1.0, poisson: 0.3, plane: PlaneState::Axisymmetric };
        let ke = stiffness(&mesh, 0, &m.constitutive(), &m.hoop().expect("axisymmetric"));
        let apply = |u: [f64; 2]| -> f64 {
            (0..2 * NODES)
                .map(|p| {
                    (0..NODES)
                        .map(|a| ke[p][2 * a] * u[0] + ke[p][2 * a + 1] * u[1])
                        .sum::<f64>()
                        .abs()
                })
                .fold(0.0, f64::max)
        };
        assert!(apply([0.0, 1.0]) < 1e-12);
        assert!(apply([1.0, 0.0]) > 1e-2);
        for (p, row) in ke.iter().enumerate() {
            for (q, v) in row.iter().enumerate() {
                assert!((v - ke[q][p]).abs() < 1e-12);
            }
        }
    }
}
