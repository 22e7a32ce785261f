//! The mass of the MFVM (docs/method.md §10.1): `ρ |Ω_I|` per node, acting on the nodal
//! values `u^h(x_I) = Σ_J φ_J(x_I) û_J` — the mass operator is `M Φ`.
//!
//! The Heaviside test of cell `Ω_I` turns the inertia term into `∫_{Ω_I} ρ ü dΩ`; one
//! quadrature point at the node gives `ρ |Ω_I| ü^h(x_I) = ρ |Ω_I| Σ_J φ_J(x_I) ü̂_J`. The
//! Voronoi cells tile the body, so the total is the body's mass exactly, whatever the node
//! layout, and a uniform motion (`û = const`, reproduced by MLS) carries the exact momentum.
//! Acting on the nodal values rather than on the parameters `û` (the row-sum lumping) was
//! chosen by the spectrum of `K x = λ M x`: fewer complex eigenvalues, at higher frequencies
//! (docs/method.md §10.2, `examples/studies/dynamics_spectrum.rs`).

use crate::mls::ShapeSet;
use crate::weak_form::Cell;

/// `ρ |Ω_I|` for both DOFs of every node (interleaved, length `2 N`; per unit thickness).
pub fn lumped_mass(cells: &[Cell], density: f64) -> Vec<f64> {
    cells
        .iter()
        .flat_map(|c| {
            let m = density * c.area();
            [m, m]
        })
        .collect()
}

/// The axisymmetric body's mass per radian on the nodal values: `ρ ∫_{Ω_I} r dA` for both
/// DOFs of every node (`x = r`; docs/method.md §10.1), exact over the cells' polygons (the
/// first moment `∫ r dA = ⅙ Σ_k (r_k + r_{k+1})(r_k z_{k+1} − r_{k+1} z_k)`).
pub fn lumped_mass_per_radian(cells: &[Cell], density: f64) -> Vec<f64> {
    cells
        .iter()
        .flat_map(|c| {
            let n = c.vertices.len();
            let moment: f64 = (0..n)
                .map(|k| {
                    let (a, b) = (c.vertices[k], c.vertices[(k + 1) % n]);
                    (a[0] + b[0]) * (a[0] * b[1] - b[0] * a[1])
                })
                .sum::<f64>()
                / 6.0;
            let m = density * moment;
            [m, m]
        })
        .collect()
}

/// Total mass of one direction: `Σ_I ρ |Ω_I|` (the x DOFs' masses).
pub fn total(mass: &[f64]) -> f64 {
    mass.iter().step_by(2).sum()
}

/// The nodal values `Φ v̂` (interleaved) of the parameters `v̂`.
pub fn nodal_values(node_shapes: &ShapeSet, v_hat: &[f64]) -> Vec<f64> {
    (0..node_shapes.len()).flat_map(|i| node_shapes.interpolate(i, v_hat)).collect()
}
