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

use crate::assembly::SystemMatrix;
use crate::mls::ShapeSet;
use crate::weak_form::Cell;

/// The mass of a body on its DOFs (interleaved): what the stepping needs of it, one path
/// for both kinds (docs/method.md §10.1).
#[derive(Clone, Debug)]
pub enum Mass {
    /// Diagonal, per DOF, acting on the nodal values `Φ v̂`: the MFVM's `ρ |Ω_I|`, the FE's
    /// HRZ lumping.
    Lumped(Vec<f64>),
    /// The finite elements' consistent mass `ρ ∫ N_a N_b dA` (identity `Φ`; symmetric, no
    /// coupling between the directions; `fem::mass::consistent_mass`).
    Consistent(SystemMatrix),
}

impl Mass {
    /// `M v` (`v`: the nodal values).
    pub fn apply(&self, v: &[f64]) -> Vec<f64> {
        match self {
            Self::Lumped(m) => m.iter().zip(v).map(|(m, v)| m * v).collect(),
            Self::Consistent(m) => crate::linear_solve::mul(m, v),
        }
    }

    /// The kinetic energy `½ vᵀ M v`.
    pub fn kinetic(&self, v: &[f64]) -> f64 {
        match self {
            Self::Lumped(m) => super::energy::kinetic(m, v),
            Self::Consistent(_) => {
                0.5 * self.apply(v).iter().zip(v).map(|(a, b)| a * b).sum::<f64>()
            }
        }
    }

    /// The momentum `1ᵀ M v` per direction (x, y): with `M` symmetric, the row sums against
    /// `v`.
    pub fn momentum(&self, v: &[f64]) -> [f64; 2] {
        match self {
            Self::Lumped(m) => super::energy::momentum(m, v),
            Self::Consistent(_) => super::energy::momentum(&self.row_sums(), v),
        }
    }

    /// The row sums `M 1` per DOF: the lumped mass itself, or the consistent mass's row sums
    /// (the same total and momentum as the matrix).
    pub fn row_sums(&self) -> Vec<f64> {
        match self {
            Self::Lumped(m) => m.clone(),
            Self::Consistent(m) => {
                let mut rows = vec![0.0; m.n];
                for c in 0..m.n {
                    for e in m.col_ptr[c]..m.col_ptr[c + 1] {
                        rows[m.row_idx[e]] += m.values[e];
                    }
                }
                rows
            }
        }
    }

    /// The mass of one direction (the sum of the x DOFs' entries).
    pub fn total(&self) -> f64 {
        total(&self.row_sums())
    }

    /// The mass without the DOFs flagged in `massless` (their rows and columns removed: the
    /// records of a body whose prescribed values vary in time, `dynamics::recorded_mass`).
    pub fn without(&self, massless: impl Fn(usize) -> bool) -> Self {
        match self {
            Self::Lumped(m) => {
                Self::Lumped((0..m.len()).map(|d| if massless(d) { 0.0 } else { m[d] }).collect())
            }
            Self::Consistent(m) => {
                let mut kept = m.clone();
                for c in 0..m.n {
                    for e in m.col_ptr[c]..m.col_ptr[c + 1] {
                        if massless(c) || massless(m.row_idx[e]) {
                            kept.values[e] = 0.0;
                        }
                    }
                }
                Self::Consistent(kept)
            }
        }
    }

    /// The work over a step (velocities `v` to `next`) of the prescribed DOFs' inertia on the
    /// free ones: `−v̄_fᵀ M_fc Δv_c` (`v̄` the step's mean velocity, `f` the free DOFs, `c` the
    /// `prescribed` ones). The consistent mass couples them (`M̂` keeps a prescribed row's
    /// columns); the lumped mass does not (its records drop the prescribed rows), 0.
    pub fn support_inertia_work(
        &self,
        v: &[f64],
        next: &[f64],
        prescribed: impl Fn(usize) -> bool,
    ) -> f64 {
        let Self::Consistent(m) = self else { return 0.0 };
        let mut work = 0.0;
        for c in (0..m.n).filter(|&c| prescribed(c)) {
            for e in m.col_ptr[c]..m.col_ptr[c + 1] {
                let r = m.row_idx[e];
                if !prescribed(r) {
                    work -= 0.5 * (v[r] + next[r]) * m.values[e] * (next[c] - v[c]);
                }
            }
        }
        work
    }

    /// The entries `(row, column, value)` of `M Φ` on the rows not flagged `skip` (the mass's
    /// share of `M̂`; a skipped row is massless, a constraint's).
    pub fn entries(
        &self,
        node_shapes: &ShapeSet,
        skip: impl Fn(usize) -> bool,
    ) -> Vec<(usize, usize, f64)> {
        let mut entries = Vec::new();
        match self {
            Self::Lumped(mass) => {
                for i in 0..node_shapes.len() {
                    for (&j, &phi) in node_shapes.support(i).iter().zip(node_shapes.phi(i)) {
                        for a in 0..2 {
                            let (r, c) = (2 * i + a, 2 * j as usize + a);
                            if !skip(r) {
                                entries.push((r, c, mass[r] * phi));
                            }
                        }
                    }
                }
            }
            // `Φ` is the identity of the finite elements.
            Self::Consistent(m) => {
                for c in 0..m.n {
                    for e in m.col_ptr[c]..m.col_ptr[c + 1] {
                        if !skip(m.row_idx[e]) {
                            entries.push((m.row_idx[e], c, m.values[e]));
                        }
                    }
                }
            }
        }
        entries
    }
}

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
