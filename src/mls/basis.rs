//! Polynomial bases in shifted, scaled local coordinates `ξ = (x − x_c)/s`.

use serde::Serialize;

/// Polynomial basis `p` of the MLS approximation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Basis {
    /// `p = (1, ξ, η)` (default; \[AHR04\] shows a low order suffices for the mixed method).
    Linear,
    /// `p = (1, ξ, η, ξ², ξη, η²)`.
    Quadratic,
}

/// Largest number of basis terms.
pub const MAX_TERMS: usize = 6;

impl Basis {
    /// Number of terms `m`.
    pub fn terms(self) -> usize {
        match self {
            Basis::Linear => 3,
            Basis::Quadratic => 6,
        }
    }

    /// Name for messages.
    pub fn name(self) -> &'static str {
        match self {
            Basis::Linear => "linear",
            Basis::Quadratic => "quadratic",
        }
    }

    /// `p(ξ, η)` into the first `m` entries.
    #[inline]
    pub fn eval(self, xi: f64, eta: f64) -> [f64; MAX_TERMS] {
        match self {
            Basis::Linear => [1.0, xi, eta, 0.0, 0.0, 0.0],
            Basis::Quadratic => [1.0, xi, eta, xi * xi, xi * eta, eta * eta],
        }
    }
}
