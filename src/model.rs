//! Stage 8: the discretised body — nodes, the assembled system and its factorisation, and what
//! the discretisation that built them keeps for the contact stage and the recovery: the MFVM's
//! supports, cells and shape functions ([`Mfvm`]) or the finite element mesh ([`Fem`]). The two
//! discretisations are peers ([`Scheme`]); [`crate::pipeline::discretise`] builds either.

use crate::assembly::GlobalSystem;
use crate::fem::Mesh;
use crate::linear_solve::Factorisation;
use crate::mls::ShapeSet;
use crate::neighbours::Supports;
use crate::nodes::Nodes;
use crate::progress::StageTiming;
use crate::weak_form::axisymmetric::on_axis;
use crate::weak_form::{Cell, FaceQuadrature, Faces};

/// A discretised body: everything needed to solve for any load and to condense onto contact
/// unknowns.
#[derive(Debug)]
pub struct Model {
    /// Nodes (the MFVM's nodes, or the FE mesh's nodes).
    pub nodes: Nodes,
    /// Shape functions at the nodes: `u^h(x_I) = Σ_J φ_J(x_I) û_J` (MLS values and gradients
    /// for the MFVM; the identity for the interpolating finite elements).
    pub node_shapes: ShapeSet,
    /// The assembled system `K û = f`.
    pub system: GlobalSystem,
    /// LU of the system matrix.
    pub factorisation: Factorisation,
    /// What the discretisation keeps besides.
    pub scheme: Scheme,
    /// Stage timings so far.
    pub timings: Vec<StageTiming>,
}

/// The discretisation that built a [`Model`], with its own data.
#[derive(Debug)]
pub enum Scheme {
    /// The meshless mixed MLPG finite volume method.
    Mfvm(Box<Mfvm>),
    /// Biquadratic finite elements ([`crate::fem`]).
    Fem(Fem),
}

/// The MFVM's data: supports, subdomain cells and the interior-face quadrature.
#[derive(Debug)]
pub struct Mfvm {
    /// MLS supports.
    pub supports: Supports,
    /// Subdomain cells, one per node.
    pub cells: Vec<Cell>,
    /// Faces of the cells.
    pub faces: Faces,
    /// Quadrature on the interior faces.
    pub face_quadrature: FaceQuadrature,
    /// Shape functions at the interior-face quadrature points (gradients when `β > 0`).
    pub face_shapes: ShapeSet,
}

/// The finite element discretisation's data.
#[derive(Debug)]
pub struct Fem {
    /// The Q2 mesh.
    pub mesh: Mesh,
}

impl Model {
    /// The MFVM's data, when this model is an MFVM model.
    pub fn mfvm(&self) -> Option<&Mfvm> {
        match &self.scheme {
            Scheme::Mfvm(m) => Some(m.as_ref()),
            Scheme::Fem(_) => None,
        }
    }

    /// The finite element mesh, when this model is an FE model.
    pub fn mesh(&self) -> Option<&Mesh> {
        match &self.scheme {
            Scheme::Mfvm(_) => None,
            Scheme::Fem(f) => Some(&f.mesh),
        }
    }

    /// Strains `(ε_xx, ε_yy, γ_xy)` at every node: the collocated strains
    /// `ε̂_I = Σ_J B_J(x_I) û_J` of the MFVM, or the FE element strains averaged at the node.
    pub fn nodal_strains(&self, u_hat: &[f64]) -> Vec<[f64; 3]> {
        match &self.scheme {
            Scheme::Fem(f) => f.mesh.nodal_strains(u_hat),
            Scheme::Mfvm(_) => collocated_strains(&self.node_shapes, u_hat),
        }
    }
}

impl Model {
    /// Axisymmetric bodies: the hoop strain `ε_θθ = u_r / r` at every node
    /// (docs/method.md §9.2), with its limit `ε_θθ = ε_rr` on the axis (`strains` are
    /// [`Self::nodal_strains`]): the MFVM's collocated `Σ_K φ_K(x_I) û_K,r / r_I`, the finite
    /// elements' nodal `u_r,I / r_I`.
    pub fn nodal_hoop_strains(&self, u_hat: &[f64], strains: &[[f64; 3]]) -> Vec<f64> {
        let (points, spacing) = (&self.nodes.points, &self.nodes.spacing);
        (0..self.nodes.len())
            .map(|i| {
                let (r, h) = (points[i][0], spacing[i]);
                if on_axis(r, h) {
                    return strains[i][0];
                }
                match &self.scheme {
                    Scheme::Fem(_) => u_hat[2 * i] / r,
                    Scheme::Mfvm(_) => {
                        let ns = &self.node_shapes;
                        let u_r: f64 = ns
                            .support(i)
                            .iter()
                            .zip(ns.phi(i))
                            .map(|(&k, &phi)| phi * u_hat[2 * k as usize])
                            .sum();
                        u_r / r
                    }
                }
            })
            .collect()
    }
}

/// Collocated strains `ε̂_I = Σ_J B_J(x_I) û_J` at every node from MLS gradients.
pub fn collocated_strains(ns: &ShapeSet, u_hat: &[f64]) -> Vec<[f64; 3]> {
    (0..ns.len())
        .map(|i| {
            let (gx, gy) = ns.grad(i);
            let mut e = [0.0; 3];
            for ((&j, &dx), &dy) in ns.support(i).iter().zip(gx).zip(gy) {
                let (ux, uy) = (u_hat[2 * j as usize], u_hat[2 * j as usize + 1]);
                e[0] += dx * ux;
                e[1] += dy * uy;
                e[2] += dy * ux + dx * uy;
            }
            e
        })
        .collect()
}
