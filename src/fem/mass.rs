//! The lumped mass of the finite elements (docs/method.md §10.1, for the FE path of
//! elastodynamics): per node, from the element shape functions over each element.
//!
//! The row sums of the consistent mass `ρ ∫ N_a N_b dA` are `ρ ∫ N_a dA`, which vanish at the
//! corners of the 6-node triangle (and are negative for 8-node serendipity elements, not used
//! here); the 9-node quadrilateral's are positive (1/36, 1/9, 4/9 of the element's mass). The
//! HRZ lumping (Hinton, Rock & Zienkiewicz, Earthq. Eng. Struct. Dyn. 4:245–249, 1976) scales
//! the consistent diagonal `ρ ∫ N_a² dA` to the element's mass: positive for every node of
//! both elements, exact in total.
//!
//! The consistent mass `M_ab = ρ ∫ N_a N_b dA` (per radian `ρ ∫ N_a N_b r dA`) on the same
//! quadrature ([`consistent_mass`]): a sparse matrix with the stiffness's pattern, one block
//! per direction; its entries sum to the element's mass (`Σ_a N_a = 1`), so the total is
//! exact as the lumped one's.

use super::Mesh;
use crate::assembly::SystemMatrix;

/// How the consistent element mass is lumped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lumping {
    /// Row sums `ρ ∫ N_a dA`.
    RowSum,
    /// The diagonal `ρ ∫ N_a² dA`, scaled to the element's mass (HRZ).
    Hrz,
}

/// The lumped mass of every node of `mesh` (per unit thickness).
pub fn lumped_mass(mesh: &Mesh, density: f64, lumping: Lumping) -> Vec<f64> {
    assembled(mesh, |k| element_mass(mesh, k, density, lumping, false))
}

/// The lumped mass per radian of every node of an axisymmetric `mesh` (`x = r`): the element
/// integrals weighted by `r` (`ρ ∫ N_a² r dA` scaled to `ρ ∫ r dA` for HRZ).
pub fn lumped_mass_per_radian(mesh: &Mesh, density: f64, lumping: Lumping) -> Vec<f64> {
    assembled(mesh, |k| element_mass(mesh, k, density, lumping, true))
}

fn assembled(mesh: &Mesh, element: impl Fn(usize) -> Vec<f64>) -> Vec<f64> {
    let mut mass = vec![0.0; mesh.node_count()];
    for k in 0..mesh.element_count() {
        for (a, m) in element(k).into_iter().enumerate() {
            mass[mesh.cell(k).nodes[a] as usize] += m;
        }
    }
    mass
}

/// The consistent mass `ρ ∫ N_a N_b dA` of `mesh` on the interleaved DOFs (`2 a + d`, no
/// coupling between the directions; `per_radian`: `ρ ∫ N_a N_b r dA`, `x = r`), on the
/// element quadrature of [`element_mass`] and the stiffness (3 × 3 Gauss on Q9: exact for
/// `N_a N_b` on affine elements, with the factor `r` too).
pub fn consistent_mass(mesh: &Mesh, density: f64, per_radian: bool) -> SystemMatrix {
    let mut entries: Vec<(usize, usize, f64)> = Vec::new();
    for k in 0..mesh.element_count() {
        let (shape, nodes) = (mesh.cell(k).shape, mesh.cell(k).nodes);
        let n = shape.node_count();
        let mut me = vec![0.0; n * n];
        for ([xi, eta], w) in shape.quadrature() {
            let r = if per_radian { mesh.point(k, xi, eta)[0] } else { 1.0 };
            let weight = density * w * r * mesh.area_factor(k, xi, eta);
            let values = shape.functions(xi, eta)[0];
            for a in 0..n {
                for b in 0..n {
                    me[a * n + b] += weight * values[a] * values[b];
                }
            }
        }
        for a in 0..n {
            for b in 0..n {
                let (i, j) = (nodes[a] as usize, nodes[b] as usize);
                for d in 0..2 {
                    entries.push((2 * i + d, 2 * j + d, me[a * n + b]));
                }
            }
        }
    }
    SystemMatrix::from_entries(2 * mesh.node_count(), entries)
}

/// The lumped masses of the nodes of element `k`, in local order (`per_radian`: the
/// integrals weighted by `r = x`).
pub fn element_mass(
    mesh: &Mesh,
    k: usize,
    density: f64,
    lumping: Lumping,
    per_radian: bool,
) -> Vec<f64> {
    let shape = mesh.cell(k).shape;
    let n = shape.node_count();
    let (mut total, mut rows, mut diagonal) = (0.0, vec![0.0; n], vec![0.0; n]);
    for ([xi, eta], w) in shape.quadrature() {
        let r = if per_radian { mesh.point(k, xi, eta)[0] } else { 1.0 };
        let weight = w * r * mesh.area_factor(k, xi, eta);
        let values = shape.functions(xi, eta)[0];
        total += weight;
        for a in 0..n {
            rows[a] += weight * values[a];
            diagonal[a] += weight * values[a] * values[a];
        }
    }
    match lumping {
        Lumping::RowSum => rows.iter().map(|r| density * r).collect(),
        Lumping::Hrz => {
            let sum: f64 = diagonal.iter().sum();
            diagonal.iter().map(|d| density * total * d / sum).collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> Mesh {
        let points = vec![[0.0, 0.0], [2.0, 0.0], [0.0, 1.0], [1.0, 0.0], [1.0, 0.5], [0.0, 0.5]];
        Mesh { grid: None, points, elements: Vec::new(), triangles: vec![[0, 1, 2, 3, 4, 5]] }
    }

    #[test]
    fn hrz_masses_are_positive_and_sum_to_the_mass() {
        let grid = Mesh::rectangle([0.0, 3.0], [0.0, 1.0], 0.5);
        for (mesh, area) in [(grid, 3.0), (triangle(), 1.0)] {
            let m = lumped_mass(&mesh, 2.0, Lumping::Hrz);
            let total: f64 = m.iter().sum();
            assert!((total - 2.0 * area).abs() < 1e-12 * area, "{total}");
            assert!(m.iter().all(|&x| x > 0.0), "{m:?}");
        }
    }

    /// Per radian (`x = r`) the masses sum to `ρ ∫ r dA` (3 × 3 Gauss is exact for `r` on
    /// the grid's elements and the triangle's six points for `r` on the triangle) and are
    /// positive, on the axis `r = 0` too (`ρ ∫ N_a² r dA` is positive inside the element).
    #[test]
    fn masses_per_radian_are_positive_and_sum_to_the_mass_per_radian() {
        for (x, lumping) in [([0.0, 2.0], Lumping::Hrz), ([0.5, 2.0], Lumping::RowSum)] {
            let grid = Mesh::rectangle(x, [0.0, 1.0], 0.25);
            let m = lumped_mass_per_radian(&grid, 3.0, lumping);
            let total: f64 = m.iter().sum();
            let exact = 3.0 * (x[1] * x[1] - x[0] * x[0]) / 2.0;
            assert!((total - exact).abs() < 1e-12 * exact, "{lumping:?}: {total} against {exact}");
            assert!(m.iter().all(|&x| x > 0.0), "{lumping:?}: {m:?}");
        }
        // The triangle (0, 0), (2, 0), (0, 1): ∫ r dA = 2/3; its corner at r = 0 too.
        let m = lumped_mass_per_radian(&triangle(), 3.0, Lumping::Hrz);
        let total: f64 = m.iter().sum();
        assert!((total - 2.0).abs() < 1e-12, "{total}");
        assert!(m.iter().all(|&x| x > 0.0), "{m:?}");
    }

    /// The consistent mass is symmetric, has no coupling between the directions, and its
    /// entries of one direction sum to the mass (plane, and per radian from the axis); its row
    /// sums are the row-sum lumping's.
    #[test]
    fn consistent_mass_is_symmetric_and_sums_to_the_mass() {
        for (x, per_radian, mesh) in [
            ([0.0, 3.0], false, Mesh::rectangle([0.0, 3.0], [0.0, 1.0], 0.5)),
            ([0.0, 2.0], true, Mesh::rectangle([0.0, 2.0], [0.0, 1.0], 0.25)),
            ([0.0, 1.0], false, triangle()),
        ] {
            let m = consistent_mass(&mesh, 3.0, per_radian);
            let exact = match (per_radian, mesh.grid.is_some()) {
                (true, _) => 3.0 * (x[1] * x[1] - x[0] * x[0]) / 2.0,
                (false, true) => 3.0 * (x[1] - x[0]),
                (false, false) => 3.0,
            };
            let mut sums = [0.0; 2];
            let mut rows = vec![0.0; m.n];
            let dense = |r: usize, c: usize| {
                (m.col_ptr[c]..m.col_ptr[c + 1])
                    .find(|&e| m.row_idx[e] == r)
                    .map_or(0.0, |e| m.values[e])
            };
            for c in 0..m.n {
                for e in m.col_ptr[c]..m.col_ptr[c + 1] {
                    let r = m.row_idx[e];
                    assert_eq!(r % 2, c % 2, "no coupling between the directions");
                    sums[c % 2] += m.values[e];
                    rows[r] += m.values[e];
                    assert!((m.values[e] - dense(c, r)).abs() < 1e-14, "symmetric at ({r}, {c})");
                }
            }
            for s in sums {
                assert!((s - exact).abs() < 1e-12 * exact, "{s} against {exact}");
            }
            let lumped = match per_radian {
                true => lumped_mass_per_radian(&mesh, 3.0, Lumping::RowSum),
                false => lumped_mass(&mesh, 3.0, Lumping::RowSum),
            };
            for (i, l) in lumped.iter().enumerate() {
                assert!((rows[2 * i] - l).abs() < 1e-13, "row sum of node {i}");
            }
        }
    }

    #[test]
    fn row_sums_vanish_at_the_triangle_corners_and_not_on_the_quadrilateral() {
        let t = element_mass(&triangle(), 0, 1.0, Lumping::RowSum, false);
        for (a, corner) in t[..3].iter().enumerate() {
            assert!(corner.abs() < 1e-14, "corner {a}: {corner}");
        }
        assert!(t[3..].iter().all(|&x| (x - 1.0 / 3.0).abs() < 1e-14), "{t:?}");
        let grid = Mesh::rectangle([0.0, 1.0], [0.0, 1.0], 1.0);
        let q = element_mass(&grid, 0, 1.0, Lumping::RowSum, false);
        let expected = [1.0 / 36.0, 1.0 / 9.0, 1.0 / 36.0, 1.0 / 9.0, 4.0 / 9.0];
        for (a, e) in [0, 1, 2, 3, 4].into_iter().zip(expected) {
            assert!((q[a] - e).abs() < 1e-14, "node {a}: {} against {e}", q[a]);
        }
        let h = element_mass(&grid, 0, 1.0, Lumping::Hrz, false);
        println!("Q9 HRZ corner, mid-side, centre: {:.6} {:.6} {:.6}", h[0], h[1], h[4]);
    }
}
