//! The long strip of the contact studies (`contact_timing.rs`, `contact_scaling.rs`): a
//! `length × 1` block (E = 30 000, ν = 0.3, plane stress, the paper's discretisation), clamped
//! at its left end, loaded by `f = 1` on its top, above a rigid floor 0.01 below its bottom
//! edge. At spacing `h` it has `length / h + 1` contact candidates.

use mlpg_contact::problem::Problem;

/// The strip of length `length` at node spacing `h`.
pub fn strip(h: f64, length: f64) -> Problem {
    let text = format!(
        r#"
        name = "strip"
        [geometry]
        kind = "rectangle"
        x = [0.0, {length:?}]
        y = [-0.5, 0.5]
        [nodes]
        spacing = {h:?}
        [material]
        young = 30000.0
        poisson = 0.3
        plane = "stress"
        [discretisation]
        basis = "linear"
        support_factor = 2.0
        [[boundary]]
        edge = "left"
        displacement = {{ x = 0.0, y = 0.0 }}
        [[boundary]]
        edge = "top"
        traction = {{ y = -1.0 }}
        [contact]
        edge = "bottom"
        obstacle_point = [0.0, -0.51]
        obstacle_normal = [0.0, 1.0]
        "#
    );
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("strip problem is invalid: {e}"))
}
