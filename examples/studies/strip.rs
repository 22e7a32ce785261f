//! The long strip of the contact studies (`contact_timing.rs`, `contact_scaling.rs`): a
//! `length × 1` block (E = 30 000, ν = 0.3, plane stress, the paper's discretisation), clamped
//! at its left end, loaded by `f = 1` on its top, above a rigid floor 0.01 below its bottom
//! edge. At spacing `h` it has `length / h + 1` contact candidates.

use mlpg_contact::problem::Problem;

/// The strip of length `length` at node spacing `h`.
#[allow(dead_code)]
pub fn strip(h: f64, length: f64) -> Problem {
    Problem::from_toml(&strip_text(h, length))
        .unwrap_or_else(|e| panic!("strip problem is invalid: {e}"))
}

/// The problem file of [`strip`] (its `[contact]` table last, so that keys such as
/// `solver = "lemke"` can be appended to it).
#[allow(dead_code)]
pub fn strip_text(h: f64, length: f64) -> String {
    format!(
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
    )
}

/// The strip of [`strip`] (spacing `h`) 0.01 above an elastic block `length × 1` (the same
/// material, spacing `1.25 h`, fixed on its bottom edge) instead of the rigid floor: two
/// elastic bodies with `length / h + 1` candidates and a partial contact zone.
#[allow(dead_code)]
pub fn strip_on_block(h: f64, length: f64) -> Problem {
    let lower_h = 1.25 * h;
    let text = format!(
        r#"
        name = "strip"
        [discretisation]
        basis = "linear"
        support_factor = 2.0
        [[body]]
        name = "strip"
        geometry = {{ kind = "rectangle", x = [0.0, {length:?}], y = [-0.5, 0.5] }}
        nodes = {{ spacing = {h:?} }}
        material = {{ young = 30000.0, poisson = 0.3, plane = "stress" }}
        boundary = [
          {{ edge = "left", displacement = {{ x = 0.0, y = 0.0 }} }},
          {{ edge = "top", traction = {{ y = -1.0 }} }},
        ]
        [[body]]
        name = "block"
        geometry = {{ kind = "rectangle", x = [0.0, {length:?}], y = [-1.51, -0.51] }}
        nodes = {{ spacing = {lower_h:?} }}
        material = {{ young = 30000.0, poisson = 0.3, plane = "stress" }}
        boundary = [{{ edge = "bottom", displacement = {{ x = 0.0, y = 0.0 }} }}]
        [contact]
        edge = "bottom"
        target_edge = "top"
        "#
    );
    Problem::from_toml(&text).unwrap_or_else(|e| panic!("strip-on-block problem is invalid: {e}"))
}
