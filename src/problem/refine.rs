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

/// Which error indicator drives adaptive refinement (docs/method.md §2.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Indicator {
    /// Recovery (ZZ-type): the MLS smoothing of the collocated strains, `ε*_I = Σ_J φ_J(x_I)
    /// ε̂_J`, minus `ε̂_I`, in the energy norm and weighted by the node's area `h_I²`.
    Recovery,
    /// Strain gradient (default): `h_I |∇ε^h(x_I)|` (the leading truncation term of a linear
    /// basis) in the energy norm, weighted by `h_I²`.
    #[default]
    Gradient,
}

impl Indicator {
    /// The name used in problem files and `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Indicator::Recovery => "recovery",
            Indicator::Gradient => "gradient",
        }
    }
}

/// The adaptive loop of `[refinement]` (docs/method.md §2.2): solve, estimate, mark, refine,
/// until the estimated error is at most `tolerance`, the next node set would exceed
/// `max_nodes`, or after `steps` refinements.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Adaptive {
    /// Refinement steps at most (solves: `steps + 1`).
    pub steps: usize,
    /// Largest node count of a refined node set.
    pub max_nodes: usize,
    /// Relative estimated error at which to stop (`None`: run the steps).
    pub tolerance: Option<f64>,
    /// Dörfler bulk fraction `θ`: the marked nodes carry at least `θ` of `Σ η_I²`.
    pub fraction: f64,
    /// The indicator.
    pub indicator: Indicator,
    /// Also mark the contact candidates at open/closed (and stick/slip) transitions.
    pub contact: bool,
}

impl Adaptive {
    /// Default `steps`.
    pub const STEPS: usize = 4;
    /// Default `max_nodes`.
    pub const MAX_NODES: usize = 100_000;
    /// Default `fraction`.
    pub const FRACTION: f64 = 0.7;
}

impl Refinement {
    /// Regions that halve the spacing around the points `(x_I, h_I)`: per point, the square
    /// of half-width `h_I` centred on it, asking for `h_I / 2` (at least `floor`), merged
    /// into one region per point (docs/method.md §2.2).
    pub fn around(marked: impl IntoIterator<Item = (Point, f64)>, floor: f64) -> Self {
        let boxes = marked
            .into_iter()
            .map(|(p, h)| RefineBox {
                x: [p[0] - h, p[0] + h],
                y: [p[1] - h, p[1] + h],
                spacing: (0.5 * h).max(floor),
            })
            .collect();
        Self { boxes }
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

    #[test]
    fn regions_around_points_halve_their_spacing() {
        let r = Refinement::around([([1.0, 2.0], 0.5), ([0.0, 0.0], 0.01)], 0.02);
        assert_eq!(r.boxes[0], RefineBox { x: [0.5, 1.5], y: [1.5, 2.5], spacing: 0.25 });
        assert_eq!(r.boxes[1].spacing, 0.02);
        assert_eq!(r.spacing_at(1.0, [1.2, 2.3]), 0.25);
    }
}
