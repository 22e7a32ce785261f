//! Stage 4: moving least squares (MLS) shape functions and their gradients \[LS81\]; paper
//! eqs. (1)–(5).
//!
//! MLS is **not interpolating**: `u^h(x_I) ≠ û_I`. The nodal unknowns are fictitious values and
//! every displacement that is reported, constrained or compared is `u^h(x) = Σ_J φ_J(x) û_J`.

mod basis;
mod shape;
mod weight;

pub use crate::problem::{Basis, MlsParams};
pub use shape::{ShapeSet, shape_functions};
pub use weight::quartic_spline;

use crate::geometry::Point;

/// Failures of the MLS approximation at an evaluation point.
#[derive(Debug, thiserror::Error)]
pub enum MlsError {
    /// Fewer support nodes than the basis needs.
    #[error(
        "MLS support of point ({x:.6}, {y:.6}) holds {support_size} nodes; the {basis} basis needs at least {needed} (more nodes than its basis terms) — increase support_factor (2 for the linear basis, 2.5 for the quadratic one: at 2 a corner's support holds only 4 nodes; docs/method.md §2)",
        x = point[0], y = point[1]
    )]
    TooFewNodes {
        /// The evaluation point.
        point: Point,
        /// Nodes found in its support.
        support_size: usize,
        /// Nodes needed.
        needed: usize,
        /// Basis name.
        basis: &'static str,
    },
    /// The moment matrix `A(x)` is singular or ill-conditioned (e.g. collinear support nodes).
    #[error(
        "MLS moment matrix at point ({x:.6}, {y:.6}) is ill-conditioned: reciprocal condition {rcond:.3e} < {min_rcond:.1e} with {support_size} support nodes (collinear nodes? increase support_factor)",
        x = point[0], y = point[1]
    )]
    SingularMoment {
        /// The evaluation point.
        point: Point,
        /// Nodes found in its support.
        support_size: usize,
        /// Estimated reciprocal condition number.
        rcond: f64,
        /// The threshold.
        min_rcond: f64,
    },
}
