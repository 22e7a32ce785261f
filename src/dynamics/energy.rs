//! Energies of a state (docs/method.md §10.4): kinetic `½ Σ_I ρ |Ω_I| |v^h(x_I)|²` with the
//! lumped mass on the nodal values, and
//! strain `½ Σ_I |Ω_I| ε̂_Iᵀ D ε̂_I` from the collocated strains over the cells (per unit
//! thickness).

use crate::material::Constitutive;
use crate::mls::ShapeSet;
use crate::model::collocated_strains;
use crate::weak_form::Cell;

/// `½ Σ_d m_d v_d²` (`v`: the nodal values).
pub fn kinetic(mass: &[f64], v: &[f64]) -> f64 {
    0.5 * mass.iter().zip(v).map(|(m, v)| m * v * v).sum::<f64>()
}

/// `½ Σ_I |Ω_I| ε̂_Iᵀ D ε̂_I`, with `ε̂ = S û` collocated at the nodes.
pub fn strain(node_shapes: &ShapeSet, cells: &[Cell], d: &Constitutive, u_hat: &[f64]) -> f64 {
    let strains = collocated_strains(node_shapes, u_hat);
    0.5 * strains
        .iter()
        .zip(cells)
        .map(|(e, cell)| {
            let s: f64 = (0..3).map(|i| e[i] * (0..3).map(|j| d[i][j] * e[j]).sum::<f64>()).sum();
            cell.area() * s
        })
        .sum::<f64>()
}

/// The momentum `Σ_I m_I v_I` (x and y; `v`: the nodal values).
pub fn momentum(mass: &[f64], v: &[f64]) -> [f64; 2] {
    let mut p = [0.0; 2];
    for (d, (m, v)) in mass.iter().zip(v).enumerate() {
        p[d % 2] += m * v;
    }
    p
}
