//! The estimate and refinement of a body of Q2 elements (`discretisation.method = "fem"`): a
//! recovery estimate per element, marks on elements, and the marked elements' refinement regions,
//! which [`crate::fem::mesh`] meshes as a graded tensor-product grid ([`Mesh::graded`]:
//! the columns and rows through a marked element halved, no hanging nodes).

use super::{Estimate, energy};
use crate::fem::Mesh;
use crate::model::{Model, Scheme};
use crate::nodes;
use crate::problem::{Problem, RefineBox};
use crate::solution::Solution;

/// The Q2 mesh of `model`, when it is an FE model.
pub fn mesh_of(model: &Model) -> Option<&Mesh> {
    match &model.scheme {
        Scheme::Fem(fem) => Some(&fem.mesh),
        Scheme::Mfvm(_) => None,
    }
}

/// The recovery (Zienkiewicz–Zhu) estimate of an FE solution, per element: `η_e² = ∫_e
/// (ε* − ε^h)ᵀ D (ε* − ε^h) dA` with `ε*` the nodal averages of the element strains
/// ([`Mesh::nodal_strains`], what `stress.csv` reports) interpolated by the element's shape
/// functions; the relative estimate `(Σ η_e² / ∫ ε^hᵀ D ε^h dA)^(1/2)` (the element's own
/// quadrature). `Estimate::node` holds the elements' `η_e²`, numbered as the mesh's.
pub fn estimate(problem: &Problem, mesh: &Mesh, solution: &Solution) -> Estimate {
    let d = problem.material.constitutive();
    let u: Vec<f64> = solution.displacement.iter().flatten().copied().collect();
    let recovered = mesh.nodal_strains(&u);
    let mut eta2 = Vec::with_capacity(mesh.element_count());
    let mut norm = 0.0;
    for k in 0..mesh.element_count() {
        let cell = mesh.cell(k);
        let mut sum = 0.0;
        for ([xi, eta], w) in cell.shape.quadrature() {
            let da = w * mesh.area_factor(k, xi, eta);
            let e = mesh.strain(k, xi, eta, &u);
            let [n, _, _] = cell.shape.functions(xi, eta);
            let mut s = [0.0; 3];
            for (&i, n) in cell.nodes.iter().zip(n) {
                for c in 0..3 {
                    s[c] += n * recovered[i as usize][c];
                }
            }
            sum += da * energy(&d, [s[0] - e[0], s[1] - e[1], s[2] - e[2]]);
            norm += da * energy(&d, e);
        }
        eta2.push(sum);
    }
    let total: f64 = eta2.iter().sum();
    let relative = if norm > 0.0 { (total / norm).sqrt() } else { 0.0 };
    Estimate { node: eta2, relative, energy: norm }
}

/// The elements of `mesh` that hold any of the nodes `marked` (the contact marks, found as
/// nodes, carried to the elements the FE loop refines). Ascending.
pub fn elements_at(mesh: &Mesh, marked: &[usize]) -> Vec<usize> {
    let mut wanted = vec![false; mesh.node_count()];
    for &i in marked {
        wanted[i] = true;
    }
    (0..mesh.element_count())
        .filter(|&k| mesh.cell(k).nodes.iter().any(|&i| wanted[i as usize]))
        .collect()
}

/// `problem` with a refinement region per `marked` element of `model`'s mesh (positions
/// from its nodes, which a uniform grid does not store): the element's box with
/// the spacing half its longer side (at least the generator's finest, `h₀ / 4096`), so that
/// the graded grid halves the element's column, and its row unless the row is already at
/// most that tall.
pub fn refined(problem: &Problem, model: &Model, marked: &[usize]) -> Problem {
    let Some(mesh) = mesh_of(model) else { return problem.clone() };
    let floor = problem.node_spacing / f64::from(1u32 << nodes::MAX_LEVEL);
    let mut next = problem.clone();
    for &k in marked {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &i in mesh.cell(k).nodes {
            let p = model.nodes.points[i as usize];
            lo = [lo[0].min(p[0]), lo[1].min(p[1])];
            hi = [hi[0].max(p[0]), hi[1].max(p[1])];
        }
        let longer = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        next.refinement.boxes.push(RefineBox {
            x: [lo[0], hi[0]],
            y: [lo[1], hi[1]],
            spacing: (0.5 * longer).max(floor),
        });
    }
    next
}
