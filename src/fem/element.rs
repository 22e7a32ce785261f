//! The biquadratic (Q2, 9-node Lagrange) reference element on `[-1, 1]²` and its stiffness on
//! an axis-aligned rectangle; and the isoparametric elements of general meshes ([`Shape`]:
//! the same Q2 element and the 6-node quadratic triangle, on curved sides too).
//!
//! Local node `a = 3 j + i` sits at `(ξ_i, η_j)` with `ξ, η ∈ {−1, 0, 1}` (tensor-product
//! order), and `N_a(ξ, η) = L_i(ξ) L_j(η)` with the quadratic Lagrange polynomials
//! `L_0 = ξ(ξ−1)/2`, `L_1 = 1 − ξ²`, `L_2 = ξ(ξ+1)/2`.
//!
//! The triangle (T6) on `{ξ, η ≥ 0, ξ + η ≤ 1}` numbers its corners `(0, 0)`, `(1, 0)`,
//! `(0, 1)` first, then the mid-side nodes of sides 0–1, 1–2, 2–0 (Gmsh's order), with
//! `N = L_i (2 L_i − 1)` at the corners and `4 L_i L_j` at the mid-sides, `L_0 = 1 − ξ − η`,
//! `L_1 = ξ`, `L_2 = η`.

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

/// The element shapes of a general (isoparametric) mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// The 9-node biquadratic quadrilateral (local order `a = 3 j + i`, as above).
    Quad9,
    /// The 6-node quadratic triangle (corners, then mid-sides; module docs).
    Tri6,
}

/// Dunavant's 6-point rule on the reference triangle (degree 4; Dunavant 1985, Int. J. Numer.
/// Meth. Eng. 21): points `(a, a), (1 − 2a, a), (a, 1 − 2a)` with weight `w_a`, the same for
/// `b`; weights here include the reference area 1/2.
const TRIANGLE_RULE: [(f64, f64); 2] = [
    (0.445_948_490_915_964_9, 0.223_381_589_678_011_47),
    (0.091_576_213_509_770_74, 0.109_951_743_655_321_87),
];

impl Shape {
    /// Nodes of the element.
    pub fn node_count(self) -> usize {
        match self {
            Shape::Quad9 => NODES,
            Shape::Tri6 => 6,
        }
    }

    /// Reference coordinates of local node `a`.
    pub fn reference_node(self, a: usize) -> [f64; 2] {
        match self {
            Shape::Quad9 => [REFERENCE_NODES[a % 3], REFERENCE_NODES[a / 3]],
            Shape::Tri6 => {
                [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]][a]
            }
        }
    }

    /// Local nodes of each side (end, middle, end), counter-clockwise on the reference
    /// element.
    pub fn sides(self) -> &'static [[usize; 3]] {
        match self {
            Shape::Quad9 => &[[0, 1, 2], [2, 5, 8], [8, 7, 6], [6, 3, 0]],
            Shape::Tri6 => &[[0, 3, 1], [1, 4, 2], [2, 5, 0]],
        }
    }

    /// `N`, `∂N/∂ξ`, `∂N/∂η` at `(ξ, η)` (entries past [`Shape::node_count`] are zero).
    pub fn functions(self, xi: f64, eta: f64) -> [[f64; NODES]; 3] {
        match self {
            Shape::Quad9 => {
                let (dx, dy) = shape_derivatives(xi, eta);
                [shape(xi, eta), dx, dy]
            }
            Shape::Tri6 => {
                let l = [1.0 - xi - eta, xi, eta];
                // dL/dξ and dL/dη of L_0, L_1, L_2.
                let (lx, ly) = ([-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]);
                let mut out = [[0.0; NODES]; 3];
                for i in 0..3 {
                    out[0][i] = l[i] * (2.0 * l[i] - 1.0);
                    out[1][i] = (4.0 * l[i] - 1.0) * lx[i];
                    out[2][i] = (4.0 * l[i] - 1.0) * ly[i];
                }
                for (m, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                    out[0][3 + m] = 4.0 * l[i] * l[j];
                    out[1][3 + m] = 4.0 * (lx[i] * l[j] + l[i] * lx[j]);
                    out[2][3 + m] = 4.0 * (ly[i] * l[j] + l[i] * ly[j]);
                }
                out
            }
        }
    }

    /// The element's quadrature: points `(ξ, η)` and weights (3 × 3 Gauss on the square,
    /// Dunavant's 6 points on the triangle; both exact for the stiffness of an affine element
    /// and accurate to O(h⁴) relative on gently curved ones).
    pub fn quadrature(self) -> Vec<([f64; 2], f64)> {
        match self {
            Shape::Quad9 => {
                let (xs, ws) = gauss_legendre(3);
                xs.iter()
                    .zip(ws)
                    .flat_map(|(&eta, &wy)| {
                        xs.iter().zip(ws).map(move |(&xi, &wx)| ([xi, eta], wx * wy))
                    })
                    .collect()
            }
            Shape::Tri6 => TRIANGLE_RULE
                .iter()
                .flat_map(|&(a, w)| {
                    [
                        ([a, a], 0.5 * w),
                        ([1.0 - 2.0 * a, a], 0.5 * w),
                        ([a, 1.0 - 2.0 * a], 0.5 * w),
                    ]
                })
                .collect(),
        }
    }
}

/// The physical derivatives `∂N/∂x`, `∂N/∂y` and the Jacobian determinant of the
/// isoparametric map `x(ξ, η) = Σ N_a(ξ, η) x_a` of an element with node coordinates
/// `coords` at `(ξ, η)`.
pub fn iso_derivatives(
    shape: Shape,
    coords: &[[f64; 2]],
    xi: f64,
    eta: f64,
) -> ([f64; NODES], [f64; NODES], f64) {
    let [_, dxi, deta] = shape.functions(xi, eta);
    let mut j = [[0.0; 2]; 2];
    for (a, x) in coords.iter().enumerate() {
        for d in 0..2 {
            j[0][d] += dxi[a] * x[d];
            j[1][d] += deta[a] * x[d];
        }
    }
    // j = [[∂x/∂ξ, ∂y/∂ξ], [∂x/∂η, ∂y/∂η]]; (∂N/∂x, ∂N/∂y) = j⁻¹ (∂N/∂ξ, ∂N/∂η).
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    let (mut dx, mut dy) = ([0.0; NODES], [0.0; NODES]);
    for a in 0..coords.len() {
        dx[a] = (j[1][1] * dxi[a] - j[0][1] * deta[a]) / det;
        dy[a] = (-j[1][0] * dxi[a] + j[0][0] * deta[a]) / det;
    }
    (dx, dy, det)
}

/// The smallest and largest Jacobian determinant of an element over its quadrature points and
/// nodes: an element is valid when both have the same sign (a clockwise element has both
/// negative; the integrals use `|det J|`).
pub fn jacobian_range(shape: Shape, coords: &[[f64; 2]]) -> (f64, f64) {
    let at = shape
        .quadrature()
        .into_iter()
        .map(|(p, _)| p)
        .chain((0..shape.node_count()).map(|a| shape.reference_node(a)));
    at.map(|[xi, eta]| iso_derivatives(shape, coords, xi, eta).2)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| (lo.min(d), hi.max(d)))
}

/// Strain `(ε_xx, ε_yy, γ_xy)` at `(ξ, η)` of an isoparametric element with node coordinates
/// `coords` and interleaved nodal displacements `u_e`.
pub fn iso_strain(
    shape: Shape,
    coords: &[[f64; 2]],
    xi: f64,
    eta: f64,
    u_e: &[f64; 2 * NODES],
) -> [f64; 3] {
    let (dx, dy, _) = iso_derivatives(shape, coords, xi, eta);
    let mut e = [0.0; 3];
    for a in 0..coords.len() {
        let (ux, uy) = (u_e[2 * a], u_e[2 * a + 1]);
        e[0] += dx[a] * ux;
        e[1] += dy[a] * uy;
        e[2] += dy[a] * ux + dx[a] * uy;
    }
    e
}

/// `K_e = ∫ Bᵀ D B |det J| dξ dη` of an isoparametric element (rows and columns past
/// `2 ×` [`Shape::node_count`] are zero).
pub fn iso_stiffness(
    shape: Shape,
    coords: &[[f64; 2]],
    d: &Constitutive,
) -> [[f64; 2 * NODES]; 2 * NODES] {
    let n = coords.len();
    let mut k = [[0.0; 2 * NODES]; 2 * NODES];
    for ([xi, eta], w) in shape.quadrature() {
        let (dx, dy, det) = iso_derivatives(shape, coords, xi, eta);
        let mut b = [[0.0; 2 * NODES]; 3];
        for a in 0..n {
            b[0][2 * a] = dx[a];
            b[1][2 * a + 1] = dy[a];
            b[2][2 * a] = dy[a];
            b[2][2 * a + 1] = dx[a];
        }
        let w = w * det.abs();
        let mut db = [[0.0; 2 * NODES]; 3];
        for (r, row) in db.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate().take(2 * n) {
                *v = (0..3).map(|s| d[r][s] * b[s][c]).sum();
            }
        }
        for p in 0..2 * n {
            for q in 0..2 * n {
                k[p][q] += w * (0..3).map(|s| b[s][p] * db[s][q]).sum::<f64>();
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

    /// The isoparametric element on a curved, distorted quad and on a curved triangle:
    /// a linear displacement field gives its exact constant strain everywhere, the stiffness
    /// is symmetric with three rigid modes, and on an axis-aligned rectangle the isoparametric
    /// stiffness equals the rectangle's.
    #[test]
    fn isoparametric_elements_pass_the_patch_test() {
        let m = Material { young: 3.0, poisson: 0.25, plane: PlaneState::Strain };
        let d = m.constitutive();
        // A quad with a bulged bottom side and a moved centre node; a triangle with a curved side.
        let quad: Vec<[f64; 2]> = (0..NODES)
            .map(|a| {
                let [xi, eta] = Shape::Quad9.reference_node(a);
                let (x, y) = (1.0 + 0.8 * xi + 0.1 * eta, 2.0 + 0.6 * eta + 0.05 * xi);
                let bulge = if a == 1 {
                    -0.08
                } else if a == 4 {
                    0.03
                } else {
                    0.0
                };
                [x, y + bulge]
            })
            .collect();
        let mut tri: Vec<[f64; 2]> = (0..6)
            .map(|a| Shape::Tri6.reference_node(a))
            .map(|[x, y]| [2.0 * x + 0.3 * y, 1.5 * y])
            .collect();
        tri[4] = [tri[4][0] + 0.1, tri[4][1] + 0.07];
        let linear =
            |p: [f64; 2]| [0.3 + 0.02 * p[0] - 0.01 * p[1], -0.1 + 0.015 * p[0] + 0.03 * p[1]];
        let exact = [0.02, 0.03, -0.01 + 0.015];
        for (shape, coords) in [(Shape::Quad9, &quad), (Shape::Tri6, &tri)] {
            let (lo, hi) = jacobian_range(shape, coords);
            assert!(lo > 0.0 && hi > 0.0, "{shape:?}: det J in [{lo}, {hi}]");
            let mut u = [0.0; 2 * NODES];
            for (a, &x) in coords.iter().enumerate() {
                let v = linear(x);
                u[2 * a] = v[0];
                u[2 * a + 1] = v[1];
            }
            for ([xi, eta], _) in shape.quadrature() {
                let e = iso_strain(shape, coords, xi, eta, &u);
                for c in 0..3 {
                    assert!((e[c] - exact[c]).abs() < 1e-13, "{shape:?}: {e:?}");
                }
            }
            let k = iso_stiffness(shape, coords, &d);
            let n = 2 * shape.node_count();
            let scale = k.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
            for (p, row) in k.iter().enumerate().take(n) {
                for (q, v) in row.iter().enumerate().take(n) {
                    assert!((v - k[q][p]).abs() < 1e-12 * scale);
                }
            }
            let modes: [fn([f64; 2]) -> [f64; 2]; 3] =
                [|_| [1.0, 0.0], |_| [0.0, 1.0], |x| [-x[1], x[0]]];
            for mode in modes {
                let r: Vec<f64> = coords.iter().flat_map(|&x| mode(x)).collect();
                for row in &k[..n] {
                    let v: f64 = row.iter().zip(&r).map(|(a, b)| a * b).sum();
                    assert!(v.abs() < 1e-12 * scale, "{shape:?}: K r = {v}");
                }
            }
        }
        let size = [0.7, 0.4];
        let rect: Vec<[f64; 2]> = (0..NODES)
            .map(|a| {
                let [xi, eta] = Shape::Quad9.reference_node(a);
                [2.0 + 0.5 * size[0] * xi, -1.0 + 0.5 * size[1] * eta]
            })
            .collect();
        let (k_iso, k_rect) = (iso_stiffness(Shape::Quad9, &rect, &d), stiffness(size, &d));
        let scale = k_rect.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
        for p in 0..2 * NODES {
            for q in 0..2 * NODES {
                assert!((k_iso[p][q] - k_rect[p][q]).abs() < 1e-13 * scale);
            }
        }
    }
}
