//! Stage 5: the local weak form of the mixed MLPG finite volume method over subdomains `Ω_s`
//! (paper eqs. (8)–(12); \[AHR04\]).
//!
//! With a Heaviside test function on the cell `Ω_I` of node `I`, the local balance is
//! `∫_{∂Ω_I} t dΓ + ∫_{Ω_I} b dΩ = 0` (eq. 9). Its boundary splits into *faces*: interior faces
//! shared with a neighbouring cell (field traction `t = N(n) D ε^h`, eq. 10) and boundary faces
//! on a domain edge (prescribed traction, or the edge of a Dirichlet node whose rows are
//! replaced by collocation). This module builds the cells and faces and their quadrature.

pub mod axisymmetric;
mod quadrature;
mod subdomain;

pub use quadrature::{gauss_legendre, segment_rule};
pub use subdomain::{Cell, EdgeLabel, build_cells};

use crate::geometry::Point;
use crate::material::Constitutive;

/// Failures while building subdomain cells.
#[derive(Debug, thiserror::Error)]
pub enum CellError {
    /// Two nodes coincide.
    #[error("nodes {node} and {other} coincide at ({x}, {y})", x = point[0], y = point[1])]
    DuplicateNode {
        /// First node.
        node: usize,
        /// Second node.
        other: usize,
        /// Where.
        point: Point,
    },
    /// A cell vanished after clipping (node outside the domain?).
    #[error("the subdomain cell of node {node} at ({x}, {y}) is empty (is the node inside the domain?)", x = point[0], y = point[1])]
    EmptyCell {
        /// Node.
        node: usize,
        /// Where.
        point: Point,
    },
    /// Every cut joining the holes to the outer boundary passes through a node's cell (the
    /// holes are too small or too close together for the node spacing).
    #[error(
        "the subdomain cell of node {node} at ({x}, {y}) cannot be built: the holes are too small or too close to each other for the node spacing (make the spacing finer than the holes' size and the ligaments between them)",
        x = point[0],
        y = point[1]
    )]
    HoleCut {
        /// Node.
        node: usize,
        /// Where.
        point: Point,
    },
    /// A boundary face on a Dirichlet edge belongs to a node that is not on that edge.
    #[error(
        "the cell of node {node} reaches Dirichlet edge `{edge}` but the node is not on it; refine or regularise the node layout near that edge"
    )]
    DirichletOwnership {
        /// Node.
        node: usize,
        /// Edge name.
        edge: String,
    },
}

/// A straight piece of a cell boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// Node whose cell this face bounds (the normal points out of it).
    pub owner: u32,
    /// Across the face: another cell, or a domain edge.
    pub across: EdgeLabel,
    /// Start point.
    pub a: Point,
    /// End point.
    pub b: Point,
    /// Unit normal pointing out of the owner's cell.
    pub normal: Point,
}

impl Face {
    /// Length `|b − a|`.
    pub fn length(&self) -> f64 {
        (self.b[0] - self.a[0]).hypot(self.b[1] - self.a[1])
    }
}

/// The faces of all cells: each interior face once (owner = the lower node index, unless only
/// the higher one has it) and every boundary face.
#[derive(Clone, Debug)]
pub struct Faces {
    /// Interior faces.
    pub interior: Vec<Face>,
    /// Boundary faces.
    pub boundary: Vec<Face>,
}

/// Lists the faces of the cells.
pub fn collect_faces(cells: &[Cell]) -> Faces {
    let mut interior = Vec::new();
    let mut boundary = Vec::new();
    for (i, cell) in cells.iter().enumerate() {
        for (k, &label) in cell.labels.iter().enumerate() {
            let (a, b) = cell.edge(k);
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            let face = Face {
                owner: i as u32,
                across: label,
                a,
                b,
                normal: [(b[1] - a[1]) / len, -(b[0] - a[0]) / len],
            };
            match label {
                EdgeLabel::Boundary(_) => boundary.push(face),
                EdgeLabel::Neighbour(j) => {
                    let keep = (i as u32) < j
                        || !cells[j as usize].labels.contains(&EdgeLabel::Neighbour(i as u32));
                    if keep {
                        interior.push(face);
                    }
                }
            }
        }
    }
    Faces { interior, boundary }
}

/// Quadrature points on a list of faces: face `f` owns points `offsets[f]..offsets[f+1]`.
#[derive(Clone, Debug, Default)]
pub struct FaceQuadrature {
    /// Start of each face's points (length = faces + 1).
    pub offsets: Vec<usize>,
    /// Points.
    pub points: Vec<Point>,
    /// Weights including the segment Jacobian.
    pub weights: Vec<f64>,
}

impl FaceQuadrature {
    /// An `n`-point Gauss–Legendre rule on every face.
    pub fn new(faces: &[Face], n: usize) -> Self {
        let mut q = FaceQuadrature { offsets: vec![0], ..Default::default() };
        for f in faces {
            for (p, w) in segment_rule(f.a, f.b, n) {
                q.points.push(p);
                q.weights.push(w);
            }
            q.offsets.push(q.points.len());
        }
        q
    }
}

/// The traction operator `T = N(n) D` (2 × 3): `t = T ε` for a Voigt strain, with
/// `N = [[n_x, 0, n_y], [0, n_y, n_x]]` (paper eq. 10; docs/method.md §3.3).
pub fn traction_operator(n: Point, d: &Constitutive) -> [[f64; 3]; 2] {
    let nm = [[n[0], 0.0, n[1]], [0.0, n[1], n[0]]];
    let mut t = [[0.0; 3]; 2];
    for i in 0..2 {
        for j in 0..3 {
            t[i][j] = (0..3).map(|k| nm[i][k] * d[k][j]).sum();
        }
    }
    t
}
