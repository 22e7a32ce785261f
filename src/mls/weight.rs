//! The quartic spline weight, paper eq. (5).

/// Quartic spline `w(r̄) = 1 − 6r̄² + 8r̄³ − 3r̄⁴` for `r̄ = d/r ≤ 1`, else 0, and
/// `w'(r̄)/r̄ = −12(1 − r̄)²` (finite at `r̄ = 0`), returned as `(w, w'/r̄)`.
///
/// With `d = |x − x_I|` the gradient is `∇w = (w'/r̄) (x − x_I) / r²`.
#[inline]
pub fn quartic_spline(rbar: f64) -> (f64, f64) {
    if rbar >= 1.0 {
        return (0.0, 0.0);
    }
    let r2 = rbar * rbar;
    let w = 1.0 - 6.0 * r2 + 8.0 * r2 * rbar - 3.0 * r2 * r2;
    let one_minus = 1.0 - rbar;
    (w, -12.0 * one_minus * one_minus)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spline_values_and_derivative() {
        assert_eq!(quartic_spline(0.0).0, 1.0);
        assert!(quartic_spline(1.0).0.abs() < 1e-15);
        let r = 0.37;
        let h = 1e-6;
        let fd = (quartic_spline(r + h).0 - quartic_spline(r - h).0) / (2.0 * h);
        assert!((fd - quartic_spline(r).1 * r).abs() < 1e-8);
    }
}
