//! Stage 2: node layouts (structured, jittered) and boundary tags.
//!
//! Boundary nodes are placed on the domain's edges at the nominal spacing and are never
//! jittered, so every boundary segment of a subdomain cell belongs to a node on that edge
//! (stage 4 relies on this for Dirichlet edges).

pub use crate::problem::Layout;

use crate::geometry::{Domain, GeometryError, Point};
use crate::random::SplitMix64;

/// Coordinate axis of a displacement component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// `x`, component 0.
    X = 0,
    /// `y`, component 1.
    Y = 1,
}

impl Axis {
    /// Both axes in order.
    pub const BOTH: [Axis; 2] = [Axis::X, Axis::Y];
}

/// The global DOF index of a node's displacement component: interleaved, `2·node + axis`.
#[inline]
pub fn dof(node: usize, axis: Axis) -> usize {
    2 * node + axis as usize
}

/// The set of domain edges a node lies on (a bit per edge; corners lie on two).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeSet(u64);

impl EdgeSet {
    /// Whether edge `k` is in the set.
    pub fn contains(self, k: usize) -> bool {
        self.0 >> k & 1 == 1
    }
    /// Adds edge `k`.
    pub fn insert(&mut self, k: usize) {
        self.0 |= 1 << k;
    }
    /// Whether the node is on no edge (interior).
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// The edges, ascending.
    pub fn iter(self) -> impl Iterator<Item = usize> {
        (0..64).filter(move |&k| self.contains(k))
    }
}

/// The node cloud: positions, local spacing and boundary tags.
#[derive(Clone, Debug)]
pub struct Nodes {
    /// Node positions.
    pub points: Vec<Point>,
    /// Local node spacing `h_I` (the support radius is `α_s · h_I`).
    pub spacing: Vec<f64>,
    /// The domain edges each node lies on.
    pub edges: Vec<EdgeSet>,
}

impl Nodes {
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.points.len()
    }
    /// Whether there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
    /// Number of displacement unknowns, `2 N`.
    pub fn dof_count(&self) -> usize {
        2 * self.points.len()
    }
}

/// Generates nodes in `domain` with nominal spacing `h`.
///
/// Rectangles get a grid that fits the sides exactly (`round(L/h)` intervals per side);
/// other convex polygons get equally spaced nodes on each edge and the points of a grid of
/// spacing `h` that lie at least `h/2` inside every edge. Domains with arcs get
/// [`crate::geometry::Curve::divisions`] equally spaced nodes on every curve (the vertices of
/// [`Domain::boundary_polygon`]), one layer of nodes at distance `h` inside every arc along
/// its boundary nodes' normals (so the first interior row follows the curve; a clipped grid
/// alone left rows at 0.7–1.7 h and made the contact compliance far from symmetric there),
/// and the points of a grid of spacing `h` inside the loop, at least `0.7 h` from straight
/// edges and `1.6 h` from arcs (so that no interior node's cell reaches the boundary);
/// there, a jittered interior node that would come closer than `0.7 h` keeps its position.
///
/// # Errors
/// [`GeometryError::Spacing`] when `h` is not positive or leaves fewer than two intervals
/// across the domain, or would create more than 50 million nodes.
pub fn generate(domain: &Domain, h: f64, layout: Layout) -> Result<Nodes, GeometryError> {
    let (lo, hi) = domain.bounding_box();
    let size = (hi[0] - lo[0]).min(hi[1] - lo[1]);
    if !(h > 0.0 && h.is_finite()) {
        return Err(GeometryError::Spacing { spacing: h, size, reason: "must be positive" });
    }
    if size / h < 1.999 {
        return Err(GeometryError::Spacing {
            spacing: h,
            size,
            reason: "needs at least two intervals across the domain",
        });
    }
    if domain.area() / (h * h) > 5.0e7 {
        return Err(GeometryError::Spacing {
            spacing: h,
            size,
            reason: "would create more than 50 million nodes",
        });
    }
    let mut points = match domain.as_rectangle() {
        Some((x, y)) => rectangle_grid(x, y, h),
        None if domain.is_polygon() => polygon_grid(domain, h),
        None => curved_grid(domain, h),
    };
    let tol = 1e-9 * h;
    let edges: Vec<EdgeSet> = points
        .iter()
        .map(|p| {
            let mut set = EdgeSet::default();
            for k in 0..domain.edge_count() {
                let t = domain.edge_parameter(k, *p);
                if domain.edge_distance(k, *p).abs() <= tol && (-1e-12..=1.0 + 1e-12).contains(&t) {
                    set.insert(k);
                }
            }
            set
        })
        .collect();
    if let Layout::Jittered { amplitude, seed } = layout {
        let curved = !domain.is_polygon();
        let mut rng = SplitMix64::new(seed);
        for (p, on) in points.iter_mut().zip(&edges) {
            // Draw for every node so the sequence does not depend on the boundary test.
            let (dx, dy) = (rng.uniform_symmetric(), rng.uniform_symmetric());
            let q = [p[0] + amplitude * h * dx, p[1] + amplitude * h * dy];
            // Near arcs a moved node could come closer to the boundary than the chord
            // points are to the boundary nodes, and its cell would take a boundary face:
            // such a move is not made.
            let keeps_clear = !curved || domain.boundary_distance(q) >= CURVED_CLEARANCE * h;
            if on.is_empty() && keeps_clear {
                *p = q;
            }
        }
    }
    let spacing = vec![h; points.len()];
    Ok(Nodes { points, spacing, edges })
}
fn rectangle_grid(x: [f64; 2], y: [f64; 2], h: f64) -> Vec<Point> {
    let nx = ((x[1] - x[0]) / h).round().max(1.0) as usize;
    let ny = ((y[1] - y[0]) / h).round().max(1.0) as usize;
    let mut points = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        let yj = if j == ny { y[1] } else { y[0] + (y[1] - y[0]) * j as f64 / ny as f64 };
        for i in 0..=nx {
            let xi = if i == nx { x[1] } else { x[0] + (x[1] - x[0]) * i as f64 / nx as f64 };
            points.push([xi, yj]);
        }
    }
    points
}

fn polygon_grid(domain: &Domain, h: f64) -> Vec<Point> {
    let mut points = Vec::new();
    for k in 0..domain.edge_count() {
        let (a, b) = domain.edge(k);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let n = (len / h).round().max(1.0) as usize;
        for i in 0..n {
            let t = i as f64 / n as f64;
            points.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    let inside =
        |p: Point| (0..domain.edge_count()).all(|k| domain.edge_distance(k, p) <= -0.5 * h);
    points.extend(lattice(domain, h).filter(|&p| inside(p)));
    points
}

/// The points of the square lattice of spacing `h` anchored at the lower-left corner of the
/// domain's bounding box and covering it, row by row.
fn lattice(domain: &Domain, h: f64) -> impl Iterator<Item = Point> {
    let (lo, hi) = domain.bounding_box();
    let nx = ((hi[0] - lo[0]) / h).ceil() as usize;
    let ny = ((hi[1] - lo[1]) / h).ceil() as usize;
    (0..=ny).flat_map(move |j| (0..=nx).map(move |i| [lo[0] + i as f64 * h, lo[1] + j as f64 * h]))
}

/// Least distance of an interior node from a curved domain's boundary, in spacings.
const CURVED_CLEARANCE: f64 = 0.7;
/// Least distance of a grid node from an arc, in spacings (the layer at `h` comes first).
const ARC_GRID_CLEARANCE: f64 = 1.6;

fn curved_grid(domain: &Domain, h: f64) -> Vec<Point> {
    // The same points as the arcs' vertices in `Domain::boundary_polygon`.
    let mut points: Vec<Point> = domain
        .curves()
        .iter()
        .flat_map(|c| {
            let n = c.divisions(h);
            (0..n).map(move |i| c.point_at(i as f64 / n as f64))
        })
        .collect();
    // One layer of nodes a spacing inside each arc, along the normals of its boundary
    // nodes, so that the first interior row follows the curve instead of a clipped grid.
    let clear =
        |p: Point| domain.contains(p) && domain.boundary_distance(p) >= CURVED_CLEARANCE * h;
    let curves = domain.curves();
    for (k, c) in curves.iter().enumerate().filter(|(_, c)| !c.is_straight()) {
        let n = c.divisions(h);
        // The end's layer node belongs to the next curve when that is an arc too.
        let last = if curves[(k + 1) % curves.len()].is_straight() { n } else { n - 1 };
        for i in 0..=last {
            let b = c.point_at(i as f64 / n as f64);
            let nrm = c.outward_normal_at(b);
            let p = [b[0] - h * nrm[0], b[1] - h * nrm[1]];
            if clear(p) {
                points.push(p);
            }
        }
    }
    let near_arc = |p: Point| {
        domain.curves().iter().any(|c| !c.is_straight() && c.distance(p) < ARC_GRID_CLEARANCE * h)
    };
    points.extend(lattice(domain, h).filter(|&p| clear(p) && !near_arc(p)));
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structured_rectangle_counts_and_tags() {
        let d = Domain::rectangle([0.0, 4.0], [0.0, 2.0]).unwrap();
        let n = generate(&d, 0.5, Layout::Structured).unwrap();
        assert_eq!(n.len(), 9 * 5);
        // Corner (0,0) is on bottom (0) and left (3).
        assert!(n.edges[0].contains(0) && n.edges[0].contains(3));
        assert!(n.edges[10].is_empty());
    }

    #[test]
    fn jitter_is_deterministic_and_keeps_boundary() {
        let d = Domain::rectangle([0.0, 4.0], [0.0, 2.0]).unwrap();
        let layout = Layout::Jittered { amplitude: 0.3, seed: 7 };
        let a = generate(&d, 0.5, layout).unwrap();
        let b = generate(&d, 0.5, layout).unwrap();
        assert_eq!(a.points, b.points);
        let boundary = a.edges.iter().filter(|e| !e.is_empty()).count();
        assert_eq!(boundary, 2 * 9 + 2 * 3);
    }

    #[test]
    fn curved_domain_nodes_lie_on_arcs_or_well_inside() {
        use crate::geometry::Curve;
        let r = 2.0;
        let d = Domain::from_curves(
            vec![Curve::arc_between([r, 0.0], [r, 0.0], [0.0, 0.0], true)],
            vec!["rim".into()],
        )
        .unwrap();
        let h = 0.1;
        let n = generate(&d, h, Layout::Jittered { amplitude: 0.3, seed: 3 }).unwrap();
        let rim = n.edges.iter().filter(|e| e.contains(0)).count();
        assert_eq!(rim, (2.0 * std::f64::consts::PI * r / h).round() as usize);
        for (p, e) in n.points.iter().zip(&n.edges) {
            let dist = r - p[0].hypot(p[1]);
            if e.is_empty() {
                assert!(dist >= 0.7 * h - 0.3 * h * 2f64.sqrt() - 1e-12, "{p:?}");
            } else {
                assert!(dist.abs() < 1e-12);
            }
        }
        // Roughly one node per h² of area.
        let ratio = n.len() as f64 * h * h / d.area();
        assert!((0.9..1.1).contains(&ratio), "{ratio}");
    }

    #[test]
    fn polygon_nodes_are_inside() {
        let d = Domain::polygon(
            vec![[0.0, 0.0], [4.0, 0.0], [0.0, 3.0]],
            vec!["a".into(), "b".into(), "c".into()],
        )
        .unwrap();
        let n = generate(&d, 0.25, Layout::Structured).unwrap();
        for p in &n.points {
            assert!((0..3).all(|k| d.edge_distance(k, *p) <= 1e-12));
        }
    }
}
