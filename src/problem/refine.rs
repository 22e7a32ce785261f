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

    /// The bin index of the regions for the nominal spacing `h0` ([`SpacingIndex`]).
    pub fn index(&self, h0: f64) -> SpacingIndex<'_> {
        let reach =
            |b: &RefineBox| (h0 - b.spacing).max(0.0) / Self::GROWTH * (1.0 + 1e-9) + 1e-12 * h0;
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for b in &self.boxes {
            let r = reach(b);
            lo = [lo[0].min(b.x[0] - r), lo[1].min(b.y[0] - r)];
            hi = [hi[0].max(b.x[1] + r), hi[1].max(b.y[1] + r)];
        }
        if self.boxes.is_empty() {
            (lo, hi) = ([0.0; 2], [0.0; 2]);
        }
        let extent = [(hi[0] - lo[0]).max(h0), (hi[1] - lo[1]).max(h0)];
        // At least the longer side over MAX_BINS as well: a long thin extent keeps the bin
        // count below 3 MAX_BINS + 4 (the area bound alone lets one side reach any count).
        let bin = h0
            .max((extent[0] * extent[1] / SpacingIndex::MAX_BINS).sqrt())
            .max(extent[0].max(extent[1]) / SpacingIndex::MAX_BINS);
        let dims = [(extent[0] / bin).ceil() as usize + 1, (extent[1] / bin).ceil() as usize + 1];
        let mut index = SpacingIndex {
            refinement: self,
            h0,
            origin: lo,
            bin,
            dims,
            bins: vec![Vec::new(); dims[0] * dims[1]],
        };
        for (k, b) in self.boxes.iter().enumerate() {
            let r = reach(b);
            if let Some([rx, ry]) = index.range([b.x[0] - r, b.y[0] - r], [b.x[1] + r, b.y[1] + r])
            {
                for j in ry[0]..=ry[1] {
                    for i in rx[0]..=rx[1] {
                        index.bins[j * dims[0] + i].push(k as u32);
                    }
                }
            }
        }
        index
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

/// [`Refinement::min_spacing_in`] through a bin grid: each region is listed in the bins its
/// reach (the distance `(h₀ − s_r)/g` beyond which it asks for no less than `h₀`) overlaps, and
/// a query looks only at the regions listed in the bins its box overlaps. Returns exactly the
/// value of the plain loop (a region left out cannot lower the minimum below `h₀`); it makes
/// the graded generator linear in the number of regions instead of cells × regions.
#[derive(Clone, Debug)]
pub struct SpacingIndex<'a> {
    refinement: &'a Refinement,
    h0: f64,
    origin: Point,
    bin: f64,
    dims: [usize; 2],
    bins: Vec<Vec<u32>>,
}

impl SpacingIndex<'_> {
    /// Largest number of bins (the bin size grows to stay below it).
    const MAX_BINS: f64 = 4.0e6;

    fn range(&self, lo: Point, hi: Point) -> Option<[[usize; 2]; 2]> {
        let mut r = [[0; 2]; 2];
        for a in 0..2 {
            let (l, h) = ((lo[a] - self.origin[a]) / self.bin, (hi[a] - self.origin[a]) / self.bin);
            let n = self.dims[a] as f64;
            if h < 0.0 || l >= n {
                return None;
            }
            r[a] =
                [l.max(0.0).floor() as usize, (h.floor().max(0.0) as usize).min(self.dims[a] - 1)];
        }
        Some(r)
    }

    /// The least `h` over the box `[lo, hi]`, as [`Refinement::min_spacing_in`].
    pub fn min_spacing_in(&self, lo: Point, hi: Point) -> f64 {
        let Some([rx, ry]) = self.range(lo, hi) else { return self.h0 };
        let boxes = &self.refinement.boxes;
        let mut h = self.h0;
        for j in ry[0]..=ry[1] {
            for i in rx[0]..=rx[1] {
                for &k in &self.bins[j * self.dims[0] + i] {
                    let b = &boxes[k as usize];
                    h = h.min(b.spacing + Refinement::GROWTH * b.box_distance(lo, hi));
                }
            }
        }
        h
    }
}

impl<'r> SpacingIndex<'r> {
    /// [`Self::min_spacing_in`] for queries that descend nested boxes, as the graded
    /// generator's quadtree split asks them (each cell after its parent): see [`NestedQuery`].
    pub fn nested(&self) -> NestedQuery<'_, 'r> {
        NestedQuery { index: self, stack: Default::default() }
    }
}

/// [`SpacingIndex::min_spacing_in`] with the regions inherited from the enclosing box of the
/// previous queries. A query keeps, for the boxes inside it, the regions whose value over it
/// is at most `(m + g·diam)(1 + 10⁻⁹)`, `m` its least spacing: over a box inside it every
/// region's value is at least its value over the query box (the distance only grows) and the
/// least one at most `m + g·diam` (the region giving `m` is at most `diam` farther), so a region
/// left out is never the least. A query inside the last kept box (or one of its enclosing
/// boxes) scans only those regions; any other query starts from the bins. The returned value
/// is exactly [`SpacingIndex::min_spacing_in`]'s for every query, in any order; in the
/// quadtree's depth-first order a fine cell scans a handful of regions instead of every region
/// within reach.
#[derive(Debug)]
pub struct NestedQuery<'i, 'r> {
    index: &'i SpacingIndex<'r>,
    /// The enclosing boxes of the last query, outermost first, with their kept regions.
    stack: std::cell::RefCell<Vec<(Point, Point, Vec<u32>)>>,
}

impl NestedQuery<'_, '_> {
    /// The least `h` over the box `[lo, hi]`, as [`SpacingIndex::min_spacing_in`].
    pub fn min_spacing_in(&self, lo: Point, hi: Point) -> f64 {
        let index = self.index;
        let boxes = &index.refinement.boxes;
        let value = |k: u32| {
            let b = &boxes[k as usize];
            b.spacing + Refinement::GROWTH * b.box_distance(lo, hi)
        };
        let mut stack = self.stack.borrow_mut();
        let inside =
            |a: &Point, b: &Point| a[0] <= lo[0] && a[1] <= lo[1] && hi[0] <= b[0] && hi[1] <= b[1];
        while stack.last().is_some_and(|(a, b, _)| !inside(a, b)) {
            stack.pop();
        }
        let values: Vec<(u32, f64)> = match stack.last() {
            Some((_, _, kept)) => kept.iter().map(|&k| (k, value(k))).collect(),
            None => {
                let mut listed = Vec::new();
                if let Some([rx, ry]) = index.range(lo, hi) {
                    for j in ry[0]..=ry[1] {
                        for i in rx[0]..=rx[1] {
                            listed.extend_from_slice(&index.bins[j * index.dims[0] + i]);
                        }
                    }
                }
                listed.sort_unstable();
                listed.dedup();
                listed.into_iter().map(|k| (k, value(k))).collect()
            }
        };
        let least = values.iter().fold(index.h0, |h, &(_, v)| h.min(v));
        let diam = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
        let bound = (least + Refinement::GROWTH * diam) * (1.0 + 1e-9);
        let kept = values.into_iter().filter(|&(_, v)| v <= bound).map(|(k, _)| k).collect();
        stack.push((lo, hi, kept));
        least
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
/// until the estimated error is at most `tolerance`, the stated accuracy goals
/// (`onset_tolerance`, `force_tolerance`) are met, the next node set would exceed
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
    /// Accuracy goal for the contact onset, a length: met when its two one-sided estimates
    /// (the gap's from the open side, the pressure's from the closed side), both inside the
    /// bracket, are at most this apart (`None`: no goal).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub onset_tolerance: Option<f64>,
    /// Accuracy goal for the total contact force: met when it changed by at most this,
    /// relative, between this solve and the one before (`None`: no goal).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub force_tolerance: Option<f64>,
}

/// The defaults of `[refinement]`: `STEPS` steps, at most `MAX_NODES` nodes, Dörfler's
/// `FRACTION`, the gradient indicator, the contact transitions marked, no tolerance or goal.
impl Default for Adaptive {
    fn default() -> Self {
        Self {
            steps: Self::STEPS,
            max_nodes: Self::MAX_NODES,
            tolerance: None,
            onset_tolerance: None,
            force_tolerance: None,
            fraction: Self::FRACTION,
            indicator: Indicator::default(),
            contact: true,
        }
    }
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
    fn the_index_gives_the_plain_minimum() {
        let mut boxes = Vec::new();
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..300 {
            let (x, y, w) = (10.0 * next(), 3.0 * next(), 0.3 * next());
            boxes.push(RefineBox { x: [x, x + w], y: [y, y + w], spacing: 0.01 + 0.4 * next() });
        }
        let r = Refinement { boxes };
        let index = r.index(0.5);
        for _ in 0..2000 {
            let (x, y, w) = (12.0 * next() - 1.0, 5.0 * next() - 1.0, 0.5 * next());
            let (lo, hi) = ([x, y], [x + w, y + w]);
            assert_eq!(index.min_spacing_in(lo, hi), r.min_spacing_in(0.5, lo, hi), "{lo:?}");
        }
        assert_eq!(Refinement::default().index(0.5).min_spacing_in([0.0; 2], [1.0; 2]), 0.5);
    }

    /// The nested query gives the plain minimum on quadtree cells visited depth first (and
    /// on boxes in any order: a box outside the kept ones starts from the bins).
    #[test]
    fn the_nested_query_gives_the_plain_minimum() {
        let mut seed = 11u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut boxes = Vec::new();
        for _ in 0..400 {
            let (x, y, w) = (8.0 * next(), 2.0 * next(), 0.2 * next());
            boxes.push(RefineBox { x: [x, x + w], y: [y, y + w], spacing: 0.005 + 0.3 * next() });
        }
        let r = Refinement { boxes };
        let (h0, index) = (0.5, r.index(0.5));
        let nested = index.nested();
        // Depth first over a quadtree on [0, 8] × [0, 2] with cells of h0, split while the
        // spacing asks for it (as nodes::generate_graded does), to depth 6.
        let mut stack: Vec<(u32, f64, f64)> = (0..4)
            .flat_map(|j| (0..16).map(move |i| (0, 0.5 * i as f64, 0.5 * j as f64)))
            .collect();
        let mut queries = 0;
        while let Some((level, x, y)) = stack.pop() {
            let a = h0 / f64::from(1u32 << level);
            let (lo, hi) = ([x, y], [x + a, y + a]);
            let m = nested.min_spacing_in(lo, hi);
            assert_eq!(m, r.min_spacing_in(h0, lo, hi), "{lo:?} {hi:?}");
            queries += 1;
            if level < 6 && a > m {
                let b = 0.5 * a;
                stack.extend(
                    [(x, y), (x + b, y), (x, y + b), (x + b, y + b)]
                        .map(|(u, v)| (level + 1, u, v)),
                );
            }
        }
        assert!(queries > 1000, "{queries} queries");
        for _ in 0..2000 {
            let (x, y, w) = (10.0 * next() - 1.0, 4.0 * next() - 1.0, 0.5 * next());
            let (lo, hi) = ([x, y], [x + w, y + w]);
            assert_eq!(nested.min_spacing_in(lo, hi), r.min_spacing_in(h0, lo, hi), "{lo:?}");
        }
    }

    /// A long thin region (10⁹ × 0.25) sizes the bins by its longer side too: a few million
    /// bins, not one per nominal spacing along it, and the minimum is still the plain one.
    #[test]
    fn a_long_thin_region_keeps_the_bin_count_bounded() {
        let r = Refinement {
            boxes: vec![RefineBox { x: [0.0, 1.0e9], y: [-0.25, 0.0], spacing: 0.025 }],
        };
        let index = r.index(0.1);
        assert!(index.bins.len() as f64 <= 3.0 * SpacingIndex::MAX_BINS + 4.0, "{:?}", index.dims);
        for (lo, hi) in [([0.0, -2.0], [0.1, -1.9]), ([5.0e8, -0.3], [5.0e8 + 1.0, -0.2])] {
            assert_eq!(index.min_spacing_in(lo, hi), r.min_spacing_in(0.1, lo, hi), "{lo:?}");
        }
    }

    #[test]
    fn regions_around_points_halve_their_spacing() {
        let r = Refinement::around([([1.0, 2.0], 0.5), ([0.0, 0.0], 0.01)], 0.02);
        assert_eq!(r.boxes[0], RefineBox { x: [0.5, 1.5], y: [1.5, 2.5], spacing: 0.25 });
        assert_eq!(r.boxes[1].spacing, 0.02);
        assert_eq!(r.spacing_at(1.0, [1.2, 2.3]), 0.25);
    }
}
