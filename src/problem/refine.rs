//! Static refinement: the graded node spacing `h(x)` of `[[nodes.refine]]` (docs/method.md
//! §2.1).
//!
//! Each refinement region asks for a spacing `s_r` inside an axis-aligned box `B_r` (a band
//! along a named edge of a rectangle is such a box too); away from it the spacing grows
//! linearly with the distance at the rate [`Refinement::GROWTH`], and the nominal spacing `h₀`
//! caps it:
//!
//! `h(x) = min(h₀, min_r (s_r + g · dist(x, B_r)))`, `g = GROWTH`.
//!
//! `h` is Lipschitz with constant `g`, which is what keeps neighbouring quadtree cells of the
//! graded node set within a factor 2 of each other (see `crate::nodes::generate_graded`).

use crate::geometry::Point;
use serde::Serialize;

/// One refinement region: spacing `spacing` inside the box `[x0, x1] × [y0, y1]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RefineBox {
    /// `[x0, x1]`.
    pub x: [f64; 2],
    /// `[y0, y1]`.
    pub y: [f64; 2],
    /// Spacing asked for inside the box (`> 0`).
    pub spacing: f64,
}

impl RefineBox {
    /// Distance from the point `p` to the box (0 inside).
    pub fn distance(&self, p: Point) -> f64 {
        let dx = (self.x[0] - p[0]).max(p[0] - self.x[1]).max(0.0);
        let dy = (self.y[0] - p[1]).max(p[1] - self.y[1]).max(0.0);
        dx.hypot(dy)
    }

    /// Least distance between the box `[lo, hi]` and this box (0 when they overlap).
    pub fn box_distance(&self, lo: Point, hi: Point) -> f64 {
        let dx = (self.x[0] - hi[0]).max(lo[0] - self.x[1]).max(0.0);
        let dy = (self.y[0] - hi[1]).max(lo[1] - self.y[1]).max(0.0);
        dx.hypot(dy)
    }
}

/// The refinement regions of one body (empty: the uniform layout at the nominal spacing).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Refinement {
    /// The regions, in the order of the `[[nodes.refine]]` tables.
    pub boxes: Vec<RefineBox>,
}

impl Refinement {
    /// Rate `g` at which the spacing grows with the distance from a region (`h` grows by
    /// `g · d` at distance `d`). At most 1/2 keeps neighbouring quadtree cells within a factor
    /// 2 of each other (docs/method.md §2.1).
    pub const GROWTH: f64 = 0.5;

    /// Whether no region is given.
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// `h(p)` for the nominal spacing `h0`.
    pub fn spacing_at(&self, h0: f64, p: Point) -> f64 {
        self.boxes.iter().fold(h0, |h, b| h.min(b.spacing + Self::GROWTH * b.distance(p)))
    }

    /// The least `h` over the box `[lo, hi]` (exact: the distance between boxes is).
    pub fn min_spacing_in(&self, h0: f64, lo: Point, hi: Point) -> f64 {
        self.boxes.iter().fold(h0, |h, b| h.min(b.spacing + Self::GROWTH * b.box_distance(lo, hi)))
    }

    /// Estimated number of nodes the regions add to the uniform set of spacing `h0` in the
    /// box `[lo, hi]`: per region, its area inside the box times `1/s² − 1/h0²` (the
    /// transitions add a little more; the quadtree's spacing can be up to 2 times finer
    /// than `s`, 4 times the nodes, when `s` is not `h0 / 2^k`).
    pub fn added_nodes(&self, h0: f64, lo: Point, hi: Point) -> f64 {
        self.boxes
            .iter()
            .map(|b| {
                let w = (b.x[1].min(hi[0]) - b.x[0].max(lo[0])).max(0.0);
                let d = (b.y[1].min(hi[1]) - b.y[0].max(lo[1])).max(0.0);
                w * d * (1.0 / (b.spacing * b.spacing) - 1.0 / (h0 * h0)).max(0.0)
            })
            .sum()
    }

    /// The smallest spacing asked for (`h0` when there is no region).
    pub fn finest(&self, h0: f64) -> f64 {
        self.boxes.iter().fold(h0, |h, b| h.min(b.spacing))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spacing_grows_at_the_rate_and_is_capped() {
        let r =
            Refinement { boxes: vec![RefineBox { x: [0.0, 1.0], y: [0.0, 0.5], spacing: 0.1 }] };
        assert_eq!(r.spacing_at(1.0, [0.5, 0.2]), 0.1);
        assert!((r.spacing_at(1.0, [0.5, 1.5]) - (0.1 + 0.5)).abs() < 1e-15);
        assert_eq!(r.spacing_at(1.0, [0.5, 10.0]), 1.0);
        // The box minimum is attained at the nearest point.
        assert!((r.min_spacing_in(1.0, [2.0, 0.0], [3.0, 1.0]) - 0.6).abs() < 1e-15);
        assert_eq!(r.finest(1.0), 0.1);
        assert!((r.added_nodes(1.0, [0.0, 0.0], [2.0, 2.0]) - 0.5 * 99.0).abs() < 1e-9);
    }
}
