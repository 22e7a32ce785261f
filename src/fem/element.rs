//! The biquadratic (Q2, 9-node Lagrange) reference element on `[-1, 1]²` and its stiffness on
//! an axis-aligned rectangle.
//!
//! Local node `a = 3 j + i` sits at `(ξ_i, η_j)` with `ξ, η ∈ {−1, 0, 1}` (tensor-product
//! order), and `N_a(ξ, η) = L_i(ξ) L_j(η)` with the quadratic Lagrange polynomials
//! `L_0 = ξ(ξ−1)/2`, `L_1 = 1 − ξ²`, `L_2 = ξ(ξ+1)/2`.

use crate::material::Constitutive;
use crate::weak_form::gauss_legendre;

/// Nodes per element.
pub const NODES: usize = 9;

/// Reference coordinates of the three nodes along one direction.
pub const REFERENCE_NODES: [f64; 3] = [-1.0, 0.0, 1.0];

/// The quadratic Lagrange polynomials `L_0, L_1, L_2` at `s`.
pub fn lagrange(s: f64) -> [f64; 3] {
    [0.5 * s * (s - 1.0), 1.0 - s * s, 0.5 * s * (s + 1.0)]
}

/// Their derivatives at `s`.
pub fn lagrange_derivative(s: f64) -> [f64; 3] {
    [s - 0.5, -2.0 * s, s + 0.5]
}

/// `N_a(ξ, η)` for the nine local nodes.
pub fn shape(xi: f64, eta: f64) -> [f64; NODES] {
    let (lx, ly) = (lagrange(xi), lagrange(eta));
    std::array::from_fn(|a| lx[a % 3] * ly[a / 3])
}

/// `(∂N_a/∂ξ, ∂N_a/∂η)` for the nine local nodes.
pub fn shape_derivatives(xi: f64, eta: f64) -> ([f64; NODES], [f64; NODES]) {
    let (lx, ly) = (lagrange(xi), lagrange(eta));
    let (dx, dy) = (lagrange_derivative(xi), lagrange_derivative(eta));
    (std::array::from_fn(|a| dx[a % 3] * ly[a / 3]), std::array::from_fn(|a| lx[a % 3] * dy[a / 3]))
}

/// Strain `(ε_xx, ε_yy, γ_xy)` at `(ξ, η)` of a `size[0] × size[1]` rectangle from the
/// element's interleaved nodal displacements `u_e` (18 values).
pub fn strain(size: [f64; 2], xi: f64, eta: f64, u_e: &[f64; 2 * NODES]) -> [f64; 3] {
    let (dxi, deta) = shape_derivatives(xi, eta);
    let (jx, jy) = (2.0 / size[0], 2.0 / size[1]);
    let mut e = [0.0; 3];
    for a in 0..NODES {
        let (dx, dy) = (dxi[a] * jx, deta[a] * jy);
        let (ux, uy) = (u_e[2 * a], u_e[2 * a + 1]);
        e[0] += dx * ux;
        e[1] += dy * uy;
        e[2] += dy * ux + dx * uy;
    }
    e
}

/// The `n`-point Gauss–Legendre rule on `[-1, 1]` (abscissae, weights), `n = 1..=8`.
pub fn gauss_points(n: usize) -> (&'static [f64], &'static [f64]) {
    gauss_legendre(n)
}

/// Element stiffness `K_e = ∫ Bᵀ D B dA` (18 × 18, interleaved local DOFs `2a + axis`) of an
/// axis-aligned `size[0] × size[1]` rectangle by 3 × 3 Gauss–Legendre quadrature (exact for
/// the rectangle: the integrand is a polynomial of degree ≤ 4 per direction).
pub fn stiffness(size: [f64; 2], d: &Constitutive) -> [[f64; 2 * NODES]; 2 * NODES] {
    let (xs, ws) = gauss_legendre(3);
    let (jx, jy) = (2.0 / size[0], 2.0 / size[1]);
    let det = 0.25 * size[0] * size[1];
    let mut k = [[0.0; 2 * NODES]; 2 * NODES];
    for (&eta, &wy) in xs.iter().zip(ws) {
        for (&xi, &wx) in xs.iter().zip(ws) {
            let (dxi, deta) = shape_derivatives(xi, eta);
            // B (3 × 18): rows ε_xx, ε_yy, γ_xy.
            let mut b = [[0.0; 2 * NODES]; 3];
            for a in 0..NODES {
                let (dx, dy) = (dxi[a] * jx, deta[a] * jy);
                b[0][2 * a] = dx;
                b[1][2 * a + 1] = dy;
                b[2][2 * a] = dy;
                b[2][2 * a + 1] = dx;
            }
            let w = wx * wy * det;
            // DB (3 × 18).
            let mut db = [[0.0; 2 * NODES]; 3];
            for (r, row) in db.iter_mut().enumerate() {
                for (c, v) in row.iter_mut().enumerate() {
                    *v = (0..3).map(|s| d[r][s] * b[s][c]).sum();
                }
            }
            for (p, kp) in k.iter_mut().enumerate() {
                for (q, kpq) in kp.iter_mut().enumerate() {
                    *kpq += w * (0..3).map(|s| b[s][p] * db[s][q]).sum::<f64>();
                }
            }
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, PlaneState};

    #[test]
    fn shape_functions_are_a_partition_of_unity_and_interpolate() {
        for (a, &(xi, eta)) in (0..NODES)
            .map(|a| (REFERENCE_NODES[a % 3], REFERENCE_NODES[a / 3]))
            .collect::<Vec<_>>()
            .iter()
            .enumerate()
        {
            let n = shape(xi, eta);
            for (b, v) in n.iter().enumerate() {
                assert_eq!(*v, if a == b { 1.0 } else { 0.0 });
            }
        }
        let (xi, eta) = (0.3, -0.7);
        let n = shape(xi, eta);
        let (dx, dy) = shape_derivatives(xi, eta);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert!(dx.iter().sum::<f64>().abs() < 1e-14 && dy.iter().sum::<f64>().abs() < 1e-14);
    }

    #[test]
    fn stiffness_is_symmetric_with_three_rigid_modes() {
        let m = Material { young: 2.0e5, poisson: 0.3, plane: PlaneState::Strain };
        let size = [2.0, 0.5];
        let k = stiffness(size, &m.constitutive());
        let scale = k.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
        for (p, row) in k.iter().enumerate() {
            for (q, v) in row.iter().enumerate() {
                assert!((v - k[q][p]).abs() < 1e-12 * scale);
            }
        }
        let coords = |a: usize| {
            [0.5 * size[0] * REFERENCE_NODES[a % 3], 0.5 * size[1] * REFERENCE_NODES[a / 3]]
        };
        let modes: [fn([f64; 2]) -> [f64; 2]; 3] =
            [|_| [1.0, 0.0], |_| [0.0, 1.0], |x| [-x[1], x[0]]];
        for mode in modes {
            let r: Vec<f64> = (0..NODES).flat_map(|a| mode(coords(a))).collect();
            for row in &k {
                let v: f64 = row.iter().zip(&r).map(|(a, b)| a * b).sum();
                assert!(v.abs() < 1e-11 * scale, "K r = {v}");
            }
        }
    }
}
