//! The closed form of the cantilever under a parabolic end shear, plane stress [TG70, §21], as
//! written by Augarde & Deeks (2008) for a beam clamped at `x = 0` and loaded at `x = L`:
//!
//! `u_x = −P y / (6EI) [(6L − 3x) x + (2 + ν)(y² − D²/4)]`,
//! `u_y =  P / (6EI) [3ν y² (L − x) + (4 + 5ν) D² x / 4 + (3L − x) x²]`,
//! `σ_xx = −P (L − x) y / I`, `σ_yy = 0`, `τ_xy = P (D²/4 − y²) / (2I)`, `I = D³/12`.
//! (Checked symbolically: equilibrium, traction-free top and bottom, resultant shear `P`.)
//!
//! Used by `cantilever_end_shear.rs`, `fem_cantilever.rs` and (through `#[path]`)
//! `examples/studies/param_study.rs` and `examples/studies/adaptive_refinement.rs`; depends on
//! nothing but `std`.

/// Length `L` (the beam spans `x ∈ [0, L]`).
pub const LENGTH: f64 = 48.0;
/// Depth `D` (the beam spans `y ∈ [−D/2, D/2]`).
pub const DEPTH: f64 = 12.0;
/// Young's modulus.
pub const YOUNG: f64 = 3.0e7;
/// Poisson's ratio.
pub const POISSON: f64 = 0.3;
/// Resultant end shear `P`.
pub const LOAD: f64 = 1000.0;

fn inertia() -> f64 {
    DEPTH.powi(3) / 12.0
}

/// `(u_x, u_y)` at `p = [x, y]`.
pub fn exact_displacement(p: [f64; 2]) -> [f64; 2] {
    let [x, y] = p;
    let (l, d, nu) = (LENGTH, DEPTH, POISSON);
    let c = LOAD / (6.0 * YOUNG * inertia());
    [
        -c * y * ((6.0 * l - 3.0 * x) * x + (2.0 + nu) * (y * y - d * d / 4.0)),
        c * (3.0 * nu * y * y * (l - x)
            + (4.0 + 5.0 * nu) * d * d * x / 4.0
            + (3.0 * l - x) * x * x),
    ]
}

/// `(σ_xx, σ_yy, τ_xy)` at `p = [x, y]`.
pub fn exact_stress(p: [f64; 2]) -> [f64; 3] {
    let [x, y] = p;
    let i = inertia();
    [-LOAD * (LENGTH - x) * y / i, 0.0, LOAD * (DEPTH * DEPTH / 4.0 - y * y) / (2.0 * i)]
}

/// The complementary energy density `σ · C σ` (twice the energy per unit volume) of a
/// plane-stress stress `(σ_xx, σ_yy, τ_xy)` for this material: the integrand of the energy
/// norm of the error.
pub fn energy_density(s: [f64; 3]) -> f64 {
    (s[0] * s[0] + s[1] * s[1] - 2.0 * POISSON * s[0] * s[1]) / YOUNG
        + 2.0 * (1.0 + POISSON) * s[2] * s[2] / YOUNG
}
