//! An independent finite element discretisation of the same problems, selected by
//! `[discretisation] method = "fem"`: an oracle for the MFVM and a feature (solve one problem
//! file both ways, `mlpg-contact --compare`).
//!
//! - Mesh: `round(L_x/h) × round(L_y/h)` biquadratic (Q2, 9-node Lagrange) elements on the
//!   rectangle, `h` = `[nodes] spacing`, so the element corners are the MFVM's structured nodes
//!   and the FE has about four times as many nodes. Rectangles with structured layout only
//!   (the problem file is refused otherwise, naming the field). A general mesh
//!   ([`Mesh::general`], [`Mesh::from_elements`]: a Gmsh file's 9-node quadrilaterals and 6-node
//!   triangles) takes isoparametric elements with curved sides ([`element::Shape`]); its
//!   loads integrate along the sides' own map and normal (docs/method.md §7).
//! - Stiffness `K = Σ_e ∫ Bᵀ D B dA` by 3 × 3 Gauss (exact on rectangles), symmetric;
//!   consistent loads `∫ N t̄ ds`, `∫ N b dA` (`load_quadrature_points` per side/direction).
//! - Displacement conditions are imposed strongly at the nodes by symmetric elimination
//!   ([`system::assemble`]); reactions are `K u − f − E P` at the prescribed DOFs.
//! - Contact: the candidates are the nodes of the contact edge, `G` picks their normal
//!   displacement and `E = Gᵀ` ([`crate::contact::fem`]), then the same condensation and
//!   Lemke as the MFVM. Contact pressure = nodal force / consistent
//!   tributary length (`l/6, 4l/6, l/6` of each element side).
//! - Stresses at the nodes are the average over the elements sharing the node of the element
//!   stress evaluated there.
//!
//! The resulting [`crate::model::Model`] carries the [`Mesh`] ([`crate::model::Scheme::Fem`])
//! and the identity as its `node_shapes` (`u^h(x_I) = u_I`).
//!
//! # Examples
//!
//! ```
//! let problem = mlpg_contact::problem::Problem::from_toml(r#"
//!     [geometry]
//!     kind = "rectangle"
//!     x = [0.0, 4.0]
//!     y = [0.0, 1.0]
//!     [nodes]
//!     spacing = 0.5
//!     [discretisation]
//!     method = "fem"
//!     [material]
//!     young = 1000.0
//!     poisson = 0.0
//!     plane = "stress"
//!     [[boundary]]
//!     edge = "left"
//!     displacement = { x = 0.0 }
//!     [[boundary]]
//!     edge = "bottom"
//!     displacement = { y = 0.0 }
//!     [[boundary]]
//!     edge = "right"
//!     traction = { x = 1.0 }
//! "#).unwrap();
//! let solution = mlpg_contact::solve(&problem).unwrap();
//! // Uniaxial tension with rollers (ν = 0): u_x(4, y) = σ L / E = 0.004 exactly.
//! let tip = solution.displacement.iter().map(|u| u[0]).fold(0.0, f64::max);
//! assert!((tip - 0.004).abs() < 1e-12, "tip = {tip}");
//! assert_eq!(solution.displacement.len(), 17 * 5); // (2·8 + 1) × (2·2 + 1) Q2 nodes
//! ```

pub mod axisymmetric;
pub mod element;
pub mod mass;
mod mesh;
pub mod system;

pub use mesh::{Cell, Grid, Mesh, side_map};

use crate::nodes::{Layout, Nodes};
use crate::problem::Problem;

/// Failures of the finite element discretisation.
#[derive(Debug, thiserror::Error)]
pub enum FemError {
    /// The domain is not an axis-aligned rectangle.
    #[error(
        "the finite element method meshes axis-aligned rectangles only; this domain has {edges} edges, or is rotated or curved"
    )]
    NotRectangle {
        /// Number of domain edges.
        edges: usize,
    },
    /// The node layout is not structured.
    #[error("the finite element method needs the structured layout (element grid), not {layout}")]
    NotStructured {
        /// The layout given.
        layout: String,
    },
    /// No displacement is prescribed.
    #[error(
        "no displacement is prescribed on any edge: the body can move rigidly and K is singular (add a displacement condition)"
    )]
    NoDirichlet,
    /// An element the FE path does not take (it needs quadratic elements).
    #[error(
        "line {line}: a {kind:?} element; the finite element path takes 6-node triangles and 9-node quadrilaterals (mesh with Mesh.ElementOrder = 2 and Mesh.SecondOrderIncomplete = 0)"
    )]
    ElementKind {
        /// The element's kind.
        kind: crate::problem::gmsh::ElementKind,
        /// Its line in the mesh file.
        line: usize,
    },
    /// An element whose isoparametric map folds or is degenerate.
    #[error(
        "line {line}: the element's Jacobian determinant vanishes or changes sign (a folded or degenerate element)"
    )]
    DegenerateElement {
        /// Its line in the mesh file.
        line: usize,
    },
    /// A rigid-body motion is left free.
    #[error("the displacement conditions do not prevent rigid-body {mode}: K is singular")]
    RigidBodyMotion {
        /// Which motion is free.
        mode: &'static str,
    },
}

/// The mesh of `problem`'s rectangle at element size `nodes.spacing` (graded by its
/// refinement regions, [`Mesh::graded`], when it has any: the adaptive loop's), or of its
/// Gmsh body's elements (`nodes.from = "mesh"`), and its nodes.
///
/// # Errors
/// [`FemError::NotRectangle`] or [`FemError::NotStructured`] for a problem the FE cannot mesh.
pub fn mesh(problem: &Problem) -> Result<(Mesh, Nodes), FemError> {
    if let Some(given) = &problem.mesh_nodes {
        let mesh = Mesh::from_elements(given.points.clone(), &given.elements)?;
        let nodes = mesh.nodes(&problem.domain);
        return Ok((mesh, nodes));
    }
    let Some((x, y)) = problem.domain.as_rectangle() else {
        return Err(FemError::NotRectangle { edges: problem.domain.edge_count() });
    };
    if problem.layout != Layout::Structured {
        return Err(FemError::NotStructured { layout: format!("{:?}", problem.layout) });
    }
    let mesh = match problem.refinement.is_empty() {
        true => Mesh::rectangle(x, y, problem.node_spacing),
        false => Mesh::graded(x, y, problem.node_spacing, &problem.refinement.boxes),
    };
    let nodes = mesh.nodes(&problem.domain);
    Ok((mesh, nodes))
}
