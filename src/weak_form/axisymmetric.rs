//! The pieces of the axisymmetric cell balance (docs/method.md §9): the cell quadrature of the
//! hoop-stress integral, the traction operator of the four-component strain, and the hoop
//! row of the collocated strain with its limit on the axis.
//!
//! Per radian, with `x = r` and `y = z`, the Heaviside test of the cell `Ω_I` gives
//! `∮ r t_r dΓ − ∫ σ_θθ dA + ∫ r b_r dA = 0` and `∮ r t_z dΓ + ∫ r b_z dA = 0`.

use super::Cell;
use crate::geometry::Point;
use crate::material::{Constitutive, Hoop};

/// A node within this fraction of the nodal spacing of `r = 0` lies on the axis.
pub const AXIS_TOLERANCE: f64 = 1e-9;

/// Whether radius `r` is on the axis, for a node of spacing `h`.
pub fn on_axis(r: f64, h: f64) -> bool {
    r.abs() <= AXIS_TOLERANCE * h
}

/// Quadrature points inside the cells: cell `i` owns points `offsets[i]..offsets[i+1]`.
#[derive(Clone, Debug, Default)]
pub struct CellQuadrature {
    /// Start of each cell's points (length = cells + 1).
    pub offsets: Vec<usize>,
    /// Points.
    pub points: Vec<Point>,
    /// Weights (areas).
    pub weights: Vec<f64>,
}

impl CellQuadrature {
    /// The fan of triangles from the mean of each cell's vertices, each with the one-point,
    /// degree-1 rule at its centroid `(c + a + b)/3`: exact for integrands linear in `r` and
    /// `z` (the patch test's constant `σ_θθ`, the area and `∫ r dA`), and every point lies
    /// strictly inside the cell, so `r > 0` at every point of a cell that touches the axis.
    /// The degree-2 rule (three points a triangle) cost three times the shape functions for
    /// no gain in the measured convergence (docs/dev/axisymmetric.md, "Cost against plane
    /// strain").
    pub fn new(cells: &[Cell]) -> Self {
        let mut q = CellQuadrature { offsets: vec![0], ..Default::default() };
        for cell in cells {
            let m = cell.vertices.len();
            let c = cell.vertices.iter().fold([0.0; 2], |s, v| [s[0] + v[0], s[1] + v[1]]);
            let c = [c[0] / m as f64, c[1] / m as f64];
            for k in 0..m {
                let (a, b) = cell.edge(k);
                let area = 0.5 * ((a[0] - c[0]) * (b[1] - c[1]) - (b[0] - c[0]) * (a[1] - c[1]));
                q.points.push([(c[0] + a[0] + b[0]) / 3.0, (c[1] + a[1] + b[1]) / 3.0]);
                q.weights.push(area);
            }
            q.offsets.push(q.points.len());
        }
        q
    }
}

/// The 2 × 4 traction operator `T₄(n) = N(n) D₄[0..3]` of the strain
/// `(ε_rr, ε_zz, γ_rz, ε_θθ)`: `t = T₄ ε` (the in-plane block of §3.3 and the hoop coupling
/// `λ ε_θθ` of `σ_rr` and `σ_zz`).
pub fn traction_operator(n: Point, d: &Constitutive, hoop: &Hoop) -> [[f64; 4]; 2] {
    let d4 = hoop.full(d);
    let nm = [[n[0], 0.0, n[1]], [0.0, n[1], n[0]]];
    let mut t = [[0.0; 4]; 2];
    for i in 0..2 {
        for j in 0..4 {
            t[i][j] = (0..3).map(|k| nm[i][k] * d4[k][j]).sum();
        }
    }
    t
}

/// The hoop-strain coefficient of `u_r` of a support node at a point of radius `r`:
/// `ε_θθ = Σ_K c_K û_K,r` with `c_K = φ_K / r` off the axis and, on it (where `u_r = 0` is
/// imposed), the limit `ε_θθ = ε_rr`, `c_K = ∂φ_K/∂r`.
pub fn hoop_coefficient(phi: f64, dphi_dr: f64, r: f64, h: f64) -> f64 {
    if on_axis(r, h) { dphi_dr } else { phi / r }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Domain;
    use crate::nodes;

    /// The cell rule integrates `1` and `r` exactly over every cell (so `∫ r dA` sums to the
    /// section's first moment), with all points at `r > 0` on a section touching the axis.
    #[test]
    fn cell_rule_is_exact_for_linear_integrands() {
        let domain = Domain::rectangle([0.0, 2.0], [0.0, 1.0]).expect("rectangle");
        let nodes = nodes::generate(
            &domain,
            0.25,
            crate::problem::Layout::Jittered { amplitude: 0.2, seed: 1 },
        )
        .expect("nodes");
        let cells = super::super::build_cells(&domain, &nodes).expect("cells");
        let q = CellQuadrature::new(&cells);
        let area: f64 = q.weights.iter().sum();
        let moment: f64 = q.weights.iter().zip(&q.points).map(|(w, p)| w * p[0]).sum();
        assert!((area - 2.0).abs() < 1e-13, "area {area}");
        assert!((moment - 2.0).abs() < 1e-13, "∫ r dA = {moment}");
        assert!(q.points.iter().all(|p| p[0] > 0.0));
    }
}
