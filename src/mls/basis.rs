//! Polynomial bases in shifted, scaled local coordinates `ξ = (x − x_c)/s`.

use crate::problem::Basis;

/// Largest number of basis terms.
pub const MAX_TERMS: usize = 6;

impl Basis {
    /// `p(ξ, η)` into the first `m` entries.
    #[inline]
    pub fn eval(self, xi: f64, eta: f64) -> [f64; MAX_TERMS] {
        match self {
            Basis::Linear => [1.0, xi, eta, 0.0, 0.0, 0.0],
            Basis::Quadratic => [1.0, xi, eta, xi * xi, xi * eta, eta * eta],
        }
    }
}
