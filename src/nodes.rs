//! Stage 2: node layouts (structured, jittered, uniform or graded) and boundary tags.
//!
//! Boundary nodes are placed on the domain's edges at the nominal spacing (graded sets: at the
//! local spacing, docs/method.md §2.1) and are never jittered, so every boundary segment of a
//! subdomain cell belongs to a node on that edge (stage 4 relies on this for Dirichlet edges).

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
/// Domains with holes are laid out the same way, whatever their curves: nodes on every
/// loop, the layer inside each hole's arcs too, the grid outside the holes.
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
        None if domain.is_polygon() && !domain.has_holes() => polygon_grid(domain, h),
        None => curved_grid(domain, h),
    };
    let edges = tag_edges(domain, &points, 1e-9 * h);
    if let Layout::Jittered { amplitude, seed } = layout {
        let curved = !domain.is_polygon() || domain.has_holes();
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
/// The domain edges each point lies on (within `tol` of the edge, inside its end points).
fn tag_edges(domain: &Domain, points: &[Point], tol: f64) -> Vec<EdgeSet> {
    points
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
        .collect()
}

/// Generates the nodes of `problem`'s (first) body: the mesh's nodes when it has them
/// (`nodes.from = "mesh"`; tagged with the edges they lie on, to `1e-9` of the smallest
/// spacing), else [`generate`] at the nominal spacing, or when the problem has refinement
/// regions [`generate_graded`] (rectangles) or [`generate_graded_curved`] (other domains).
///
/// # Errors
/// As [`generate`] and [`generate_graded`].
pub fn for_problem(problem: &crate::problem::Problem) -> Result<Nodes, GeometryError> {
    let (h, refinement) = (problem.node_spacing, &problem.refinement);
    if let Some(mesh) = &problem.mesh_nodes {
        let finest = mesh.spacing.iter().fold(f64::INFINITY, |m, &v| m.min(v));
        let edges = tag_edges(&problem.domain, &mesh.points, 1e-9 * finest);
        return Ok(Nodes { points: mesh.points.clone(), spacing: mesh.spacing.clone(), edges });
    }
    if refinement.is_empty() {
        generate(&problem.domain, h, problem.layout)
    } else {
        let index = refinement.index(h);
        let query = index.nested();
        let min_spacing = |lo, hi| query.min_spacing_in(lo, hi);
        if problem.domain.as_rectangle().is_some() {
            generate_graded(&problem.domain, h, problem.layout, min_spacing)
        } else {
            generate_graded_curved(&problem.domain, h, problem.layout, min_spacing)
        }
    }
}

/// [`for_problem`], or `None` when the node set would have more than `max_nodes` nodes. A
/// graded set is abandoned as soon as its quadtree has more leaves than that bound allows
/// (see [`generate_graded_at_most`]), without generating it; `Some` sets are exactly those of
/// [`for_problem`] (their size may still exceed `max_nodes`: the caller compares).
///
/// # Errors
/// As [`for_problem`].
pub fn for_problem_at_most(
    problem: &crate::problem::Problem,
    max_nodes: usize,
) -> Result<Option<Nodes>, GeometryError> {
    let geometry = problem.domain.as_rectangle();
    if problem.mesh_nodes.is_some() || problem.refinement.is_empty() || geometry.is_none() {
        return for_problem(problem).map(Some);
    }
    let (h, index) = (problem.node_spacing, problem.refinement.index(problem.node_spacing));
    let query = index.nested();
    generate_graded_at_most(&problem.domain, h, problem.layout, max_nodes, |lo, hi| {
        query.min_spacing_in(lo, hi)
    })
}

/// Deepest quadtree level of [`generate_graded`]: cells of `h₀ / 4096`.
pub const MAX_LEVEL: u32 = 12;

/// Generates a graded node set in a rectangle from a spacing function (docs/method.md §2.1).
///
/// `min_spacing(lo, hi)` is the least wanted spacing `h(x)` over the box `[lo, hi]` (at most
/// `h0`). The rectangle is first cut into the cells of the uniform grid of [`generate`]
/// (`round(L/h0)` per side); a cell of level `L` (nominal size `h0 / 2^L`) is split into four
/// while its nominal size exceeds `min_spacing` over it (so the spacing is never coarser than
/// asked for: in a region asking for `s`, the cells have the largest `h0 / 2^L ≤ s`), down to
/// [`MAX_LEVEL`]. Then the tree is balanced (a cell is split while a cell sharing an edge or a
/// corner with it is more than one level finer), so that neighbouring cells differ by at most
/// a factor 2; a leaf at a corner of the rectangle whose diagonal neighbour is split while its
/// two side neighbours are not is split as well and the tree balanced again (else the corner
/// has 3 support nodes at `α_s = 2`, docs/method.md §2.1). The nodes are the cell corners,
/// row by row (the mid-side nodes where a coarse cell meets two finer ones included); boundary
/// nodes lie on the edges at the local spacing and the corners of the rectangle are nodes.
///
/// Each node's spacing `h_I` is the geometric mean of the nominal sizes `h0 / 2^L` of the
/// largest and the smallest cell it touches (the uniform generator gives every node `h0`): at
/// most `√2` times finer than any cell it touches, so at `α_s = 2` the four corners of every
/// cell have the whole open cell in their supports, and at most `√2` times coarser than its
/// nearest neighbour distance, which keeps the mixed method's supports near `α_s` local
/// spacings (the largest cell made the graded patch test's round-off 500 times larger at
/// `β = 0`; the smallest left a top-edge point with 3 support nodes; docs/method.md §2.1). A jittered layout moves interior nodes by at most `amplitude ·` the size of the
/// smallest cell they touch in each coordinate; the generator draws two numbers per node in
/// node order, so the layout is deterministic for a seed. Without any split the result is the
/// node set of [`generate`].
///
/// # Errors
/// [`GeometryError::Spacing`] when the domain is not a rectangle, when `h0` is not usable (as
/// for [`generate`]) or the graded set would have more than 50 million nodes.
pub fn generate_graded(
    domain: &Domain,
    h0: f64,
    layout: Layout,
    min_spacing: impl Fn(Point, Point) -> f64,
) -> Result<Nodes, GeometryError> {
    generate_graded_at_most(domain, h0, layout, usize::MAX, min_spacing)
        .map(|n| n.expect("no node bound"))
}

/// [`generate_graded`], abandoned (`None`) as soon as the set is known to have more than
/// `max_nodes` nodes: while the quadtree is split, a tree with `F` leaves on an `nx × ny` root
/// grid has at least `F + nx + ny + 1` cell corners (each leaf's lower-left corner is a node,
/// no two leaves share it, and the top row and right column of the root grid's corners are
/// no leaf's lower-left corner), and balancing only adds leaves. `Some` holds exactly the set
/// of [`generate_graded`].
///
/// # Errors
/// As [`generate_graded`].
pub fn generate_graded_at_most(
    domain: &Domain,
    h0: f64,
    layout: Layout,
    max_nodes: usize,
    min_spacing: impl Fn(Point, Point) -> f64,
) -> Result<Option<Nodes>, GeometryError> {
    let (lo, hi) = domain.bounding_box();
    let size = (hi[0] - lo[0]).min(hi[1] - lo[1]);
    let Some((x, y)) = domain.as_rectangle() else {
        return Err(GeometryError::Spacing {
            spacing: h0,
            size,
            reason: "graded node sets are implemented for rectangles only",
        });
    };
    // The checks of the uniform generator, on its grid.
    generate(domain, h0, Layout::Structured).map(|_| ())?;
    let nx = ((x[1] - x[0]) / h0).round().max(1.0) as u64;
    let ny = ((y[1] - y[0]) / h0).round().max(1.0) as u64;
    let cell_box = |level: u32, i: u64, j: u64| {
        let (cx, cy) = ((nx << level) as f64, (ny << level) as f64);
        let at = |v: [f64; 2], k: u64, n: f64| v[0] + (v[1] - v[0]) * k as f64 / n;
        ([at(x, i, cx), at(y, j, cy)], [at(x, i + 1, cx), at(y, j + 1, cy)])
    };
    let Some(mut split) =
        split_cells([nx, ny], h0, size, cell_box, &min_spacing, |_, _| true, Some(max_nodes))?
    else {
        return Ok(None);
    };
    balance(&mut split, nx, ny);
    // Corner cells: a leaf at a corner of the rectangle whose cell across its inner vertex is
    // split while its two side neighbours are not gives that vertex `h_I = size/√2`, a support
    // radius equal to the corner cell's diagonal, which leaves the domain corner with 3 support
    // nodes at `α_s = 2` (itself and its two edge neighbours; no mid-side node on the corner
    // cell's inner sides). Such a corner cell is split (and the tree balanced again); its inner
    // vertex then touches only cells of its own size.
    while split_corner_cells(&mut split, nx, ny, [true; 4]) {
        balance(&mut split, nx, ny);
    }
    let depth = split.iter().rposition(|s| !s.is_empty()).map_or(0, |l| l as u32 + 1);
    // Leaves: cells whose parent is split (or roots) and which are not split themselves.
    let mut leaves: Vec<(u32, u64, u64)> = Vec::new();
    let mut stack: Vec<(u32, u64, u64)> =
        (0..ny).flat_map(|j| (0..nx).map(move |i| (0, i, j))).collect();
    while let Some((level, i, j)) = stack.pop() {
        if split.get(level as usize).is_some_and(|s| s.contains(&(i, j))) {
            for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                stack.push((level + 1, 2 * i + di, 2 * j + dj));
            }
        } else {
            leaves.push((level, i, j));
        }
    }
    // Corners on the lattice of the deepest level; (row, column) keys give row-by-row order.
    let (nx_f, ny_f) = (nx << depth, ny << depth);
    let mut sizes: std::collections::BTreeMap<(u64, u64), (f64, f64)> = Default::default();
    // Nominal sizes, as the uniform generator's `h` (the grid fits the sides within rounding).
    let leaf_size = |level: u32| h0 / (1u64 << level) as f64;
    for &(level, i, j) in &leaves {
        let k = 1u64 << (depth - level);
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            sizes.insert(((j + dj) * k, (i + di) * k), (0.0, f64::INFINITY));
        }
    }
    for &(level, i, j) in &leaves {
        let k = 1u64 << (depth - level);
        let s = leaf_size(level);
        // Corners and (when a finer neighbour put a node there) mid-sides.
        for (di, dj) in [(0, 0), (2, 0), (0, 2), (2, 2), (1, 0), (0, 1), (2, 1), (1, 2)] {
            if k == 1 && (di == 1 || dj == 1) {
                continue;
            }
            let key = ((2 * j + dj) * k / 2, (2 * i + di) * k / 2);
            if let Some(e) = sizes.get_mut(&key) {
                e.0 = e.0.max(s);
                e.1 = e.1.min(s);
            }
        }
    }
    let coord = |v: [f64; 2], k: u64, n: u64| {
        if k == n { v[1] } else { v[0] + (v[1] - v[0]) * k as f64 / n as f64 }
    };
    let mut points = Vec::with_capacity(sizes.len());
    let mut spacing = Vec::with_capacity(sizes.len());
    let mut smallest = Vec::with_capacity(sizes.len());
    for (&(row, col), &(largest, least)) in &sizes {
        points.push([coord(x, col, nx_f), coord(y, row, ny_f)]);
        spacing.push(if largest == least { largest } else { (least * largest).sqrt() });
        smallest.push(least);
    }
    let finest = smallest.iter().fold(f64::INFINITY, |m, &v| m.min(v));
    let edges = tag_edges(domain, &points, 1e-9 * finest);
    if let Layout::Jittered { amplitude, seed } = layout {
        let mut rng = SplitMix64::new(seed);
        for ((p, on), s) in points.iter_mut().zip(&edges).zip(&smallest) {
            let (dx, dy) = (rng.uniform_symmetric(), rng.uniform_symmetric());
            if on.is_empty() {
                *p = [p[0] + amplitude * s * dx, p[1] + amplitude * s * dy];
            }
        }
    }
    Ok(Some(Nodes { points, spacing, edges }))
}

/// A quadtree's split cells per level: `[L]` holds `(i, j)` of the level-`L` cells with children.
type SplitCells = Vec<std::collections::BTreeSet<(u64, u64)>>;

/// The split cells of a quadtree over `nx × ny` root cells of nominal size `h0`, per level:
/// `split[L]` holds `(i, j)` of the level-`L` cells that have children. A cell
/// (`cell_box(level, i, j)`) is split while its nominal size `h0 / 2^L` exceeds `min_spacing`
/// over it and `meets` it (the domain), down to [`MAX_LEVEL`]; not balanced. `None` as soon as
/// the leaves' corners would exceed `max_nodes`.
///
/// # Errors
/// [`GeometryError::Spacing`] beyond 50 million nodes (`size`: the domain's, for the message).
fn split_cells(
    [nx, ny]: [u64; 2],
    h0: f64,
    size: f64,
    cell_box: impl Fn(u32, u64, u64) -> (Point, Point),
    min_spacing: &impl Fn(Point, Point) -> f64,
    meets: impl Fn(Point, Point) -> bool,
    max_nodes: Option<usize>,
) -> Result<Option<SplitCells>, GeometryError> {
    let mut split: SplitCells = vec![Default::default()];
    let mut stack: Vec<(u32, u64, u64)> =
        (0..ny).flat_map(|j| (0..nx).map(move |i| (0, i, j))).collect();
    let mut cells = 0u64;
    while let Some((level, i, j)) = stack.pop() {
        let (a, b) = cell_box(level, i, j);
        let nominal = h0 / (1u64 << level) as f64;
        if level < MAX_LEVEL && nominal > min_spacing(a, b) * (1.0 + 1e-9) && meets(a, b) {
            cells += 3;
            if max_nodes.is_some_and(|m| (nx * ny + cells + nx + ny + 1) as f64 > m as f64) {
                return Ok(None);
            }
            if cells as f64 > 5.0e7 {
                return Err(GeometryError::Spacing {
                    spacing: h0,
                    size,
                    reason: "the refinement would create more than 50 million nodes",
                });
            }
            if split.len() <= level as usize {
                split.resize_with(level as usize + 1, Default::default);
            }
            split[level as usize].insert((i, j));
            for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                stack.push((level + 1, 2 * i + di, 2 * j + dj));
            }
        }
    }
    Ok(Some(split))
}

/// Generates a graded node set in a domain that is not a rectangle (a convex polygon, or a
/// loop of segments and arcs) from a spacing function (docs/method.md §2.1): the curved
/// counterpart of [`generate_graded`], laid out like [`generate`]'s curved sets.
///
/// `min_spacing(lo, hi)` is the least wanted spacing over the box `[lo, hi]` (at most `h0`).
/// A quadtree covers the domain's bounding box with cells of `h0` anchored at its lower-left
/// corner (the lattice of [`generate`]); a cell that meets the domain is split while its
/// nominal size exceeds `min_spacing` over it, down to [`MAX_LEVEL`], and the tree is balanced
/// (neighbouring cells within a factor 2). The local boundary spacing `σ(x)` is the size of
/// the leaf holding `x`. Then, in this order:
///
/// - **boundary nodes** on every curve, from its start (its end is the next curve's start):
///   `N = round(∫ ds/σ)` intervals (at least one, and one per 45° of an arc), placed where
///   `∫ ds/σ` reaches `i/N` of its total, so that the chords follow `σ` and neighbouring
///   chords differ by about the factor 2 of neighbouring leaves at most; with `σ` constant
///   along the curve they are [`crate::geometry::Curve::division_points`]`(σ)`. A polyline
///   keeps its points. A boundary node's `h_I` is the geometric mean of `σ` at the midpoints
///   of its two chords;
/// - **the inner layer** of every arc: a node at distance `h_I` inside each boundary node
///   along the arc's normal, kept at least `0.7 h_I` from the boundary (as [`generate`]);
/// - **lattice nodes**: the corners of the leaves (mid-side nodes of coarse leaves next to
///   finer ones included), row by row, kept inside the domain at least `0.7 s` from the
///   boundary, `1.6 S` from every arc and `0.6 h_L` from every layer node (its `h_L`: so that
///   the lattice stays clear of a coarser layer; on uniform sets this follows from the arc
///   clearance), with `s` and `S` the smallest and the largest leaf the corner touches; `h_I`
///   as in [`generate_graded`], `√(s S)`.
///
/// A jittered layout moves interior nodes by at most `amplitude · s` (lattice) or
/// `amplitude · h_I` (layer) in each coordinate, and keeps a node where a move would bring it
/// closer than `0.7` of that to the boundary; two numbers are drawn per node in node order.
/// Without any split the result is the node set of [`generate`] for a loop of curves.
///
/// # Errors
/// [`GeometryError::Spacing`] for a domain with holes (not implemented), when `h0` is not
/// usable (as for [`generate`]) or the graded set would have more than 50 million nodes.
pub fn generate_graded_curved(
    domain: &Domain,
    h0: f64,
    layout: Layout,
    min_spacing: impl Fn(Point, Point) -> f64,
) -> Result<Nodes, GeometryError> {
    let (lo, hi) = domain.bounding_box();
    let size = (hi[0] - lo[0]).min(hi[1] - lo[1]);
    if domain.has_holes() {
        return Err(GeometryError::Spacing {
            spacing: h0,
            size,
            reason: "graded node sets are not implemented for domains with holes",
        });
    }
    // The checks of the uniform generator.
    generate(domain, h0, Layout::Structured).map(|_| ())?;
    let nx = (((hi[0] - lo[0]) / h0).ceil() as u64).max(1);
    let ny = (((hi[1] - lo[1]) / h0).ceil() as u64).max(1);
    let cell_box = |level: u32, i: u64, j: u64| {
        let s = h0 / (1u64 << level) as f64;
        (
            [lo[0] + i as f64 * s, lo[1] + j as f64 * s],
            [lo[0] + (i + 1) as f64 * s, lo[1] + (j + 1) as f64 * s],
        )
    };
    let meets = |a: Point, b: Point| {
        let c = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let r = 0.5 * (b[0] - a[0]).hypot(b[1] - a[1]);
        domain.contains(c) || domain.boundary_distance(c) <= r * (1.0 + 1e-9)
    };
    let Some(mut split) = split_cells([nx, ny], h0, size, cell_box, &min_spacing, meets, None)?
    else {
        unreachable!("no node bound given");
    };
    balance(&mut split, nx, ny);
    // The corner-cell rule of `generate_graded` at the corners of the root grid that are
    // corners of the domain (the box's corner on the boundary and on the root grid).
    let corners = [(false, false), (true, false), (false, true), (true, true)].map(|(r, t)| {
        let q = [if r { hi[0] } else { lo[0] }, if t { hi[1] } else { lo[1] }];
        let on_grid = |v: f64, from: f64, n: u64| (from + n as f64 * h0 - v).abs() <= 1e-9 * h0;
        (!r || on_grid(hi[0], lo[0], nx))
            && (!t || on_grid(hi[1], lo[1], ny))
            && domain.boundary_distance(q) <= 1e-9 * h0
    });
    if nx >= 2 && ny >= 2 {
        while split_corner_cells(&mut split, nx, ny, corners) {
            balance(&mut split, nx, ny);
        }
    }
    let depth = split.iter().rposition(|s| !s.is_empty()).map_or(0, |l| l as u32 + 1);
    let is_split =
        |level: u32, c: (u64, u64)| split.get(level as usize).is_some_and(|s| s.contains(&c));
    // σ(x): the size of the leaf holding x (points beyond the box: the nearest root cell).
    let sigma = |p: Point| {
        let clamp = |v: f64, n: u64| (v.max(0.0).floor() as u64).min(n - 1);
        let (mut i, mut j) = (clamp((p[0] - lo[0]) / h0, nx), clamp((p[1] - lo[1]) / h0, ny));
        let mut level = 0u32;
        while is_split(level, (i, j)) {
            let (a, b) = cell_box(level, i, j);
            let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            i = 2 * i + u64::from(p[0] >= mid[0]);
            j = 2 * j + u64::from(p[1] >= mid[1]);
            level += 1;
        }
        h0 / (1u64 << level) as f64
    };
    let finest = h0 / (1u64 << depth) as f64;
    // Boundary nodes, curve by curve (each from its start; its end is the next one's start).
    let curves = domain.curves();
    let mut boundary: Vec<Vec<Point>> = Vec::with_capacity(curves.len());
    for c in curves {
        let mut p = graded_division_points(c, &sigma, finest);
        p.pop();
        boundary.push(p);
    }
    let ring: Vec<Point> = boundary.iter().flatten().copied().collect();
    let mid_sigma = |a: Point, b: Point| sigma([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
    let geometric = |a: f64, b: f64| if a == b { a } else { (a * b).sqrt() };
    let m = ring.len();
    let ring_h: Vec<f64> = (0..m)
        .map(|i| {
            let (prev, next) = (ring[(i + m - 1) % m], ring[(i + 1) % m]);
            geometric(mid_sigma(prev, ring[i]), mid_sigma(ring[i], next))
        })
        .collect();
    let mut points = ring.clone();
    let mut spacing = ring_h.clone();
    let mut smallest = ring_h.clone();
    // The inner layer along each arc's normals (the end's node belongs to the next curve when
    // that is an arc too; else the arc's end gets one).
    let clear = |p: Point, s: f64| {
        domain.contains(p) && domain.boundary_distance(p) >= CURVED_CLEARANCE * s
    };
    let mut first = 0;
    for (k, c) in curves.iter().enumerate() {
        let count = boundary[k].len();
        if !c.is_straight() {
            let end_too = curves[domain.next_in_loop(k)].is_straight();
            let at: Vec<(Point, f64)> = (first..first + count)
                .map(|i| (ring[i], ring_h[i]))
                .chain(end_too.then(|| (c.end(), ring_h[(first + count) % m])))
                .collect();
            for (b, s) in at {
                let nrm = c.outward_normal_at(b);
                let p = [b[0] - s * nrm[0], b[1] - s * nrm[1]];
                if clear(p, s) {
                    points.push(p);
                    spacing.push(s);
                    smallest.push(s);
                }
            }
        }
        first += count;
    }
    // Lattice nodes: leaf corners on the deepest level's lattice, row by row.
    let mut leaves: Vec<(u32, u64, u64)> = Vec::new();
    let mut stack: Vec<(u32, u64, u64)> =
        (0..ny).flat_map(|j| (0..nx).map(move |i| (0, i, j))).collect();
    while let Some((level, i, j)) = stack.pop() {
        if is_split(level, (i, j)) {
            for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                stack.push((level + 1, 2 * i + di, 2 * j + dj));
            }
        } else {
            leaves.push((level, i, j));
        }
    }
    let mut sizes: std::collections::BTreeMap<(u64, u64), (f64, f64)> = Default::default();
    for &(level, i, j) in &leaves {
        let k = 1u64 << (depth - level);
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            sizes.insert(((j + dj) * k, (i + di) * k), (0.0, f64::INFINITY));
        }
    }
    for &(level, i, j) in &leaves {
        let k = 1u64 << (depth - level);
        let s = h0 / (1u64 << level) as f64;
        for (di, dj) in [(0, 0), (2, 0), (0, 2), (2, 2), (1, 0), (0, 1), (2, 1), (1, 2)] {
            if k == 1 && (di == 1 || dj == 1) {
                continue;
            }
            let key = ((2 * j + dj) * k / 2, (2 * i + di) * k / 2);
            if let Some(e) = sizes.get_mut(&key) {
                e.0 = e.0.max(s);
                e.1 = e.1.min(s);
            }
        }
    }
    let arcs: Vec<&crate::geometry::Curve> = curves.iter().filter(|c| !c.is_straight()).collect();
    // The layer nodes by bins of h0 (each with its distance from the arc).
    let bin =
        |p: Point| (((p[0] - lo[0]) / h0).floor() as i64, ((p[1] - lo[1]) / h0).floor() as i64);
    let mut layer: std::collections::HashMap<(i64, i64), Vec<(Point, f64)>> = Default::default();
    for i in ring.len()..points.len() {
        layer.entry(bin(points[i])).or_default().push((points[i], spacing[i]));
    }
    let near_arc = |p: Point, largest: f64| {
        if arcs.iter().any(|c| c.distance(p) < ARC_GRID_CLEARANCE * largest) {
            return true;
        }
        // A layer node coarser than the lattice here is farther from the arc than `largest`:
        // keep the lattice `(ARC_GRID_CLEARANCE − 1)` of its distance away from it, as on
        // uniform sets (where this follows from the arc clearance).
        let (bi, bj) = bin(p);
        (bi - 1..=bi + 1).any(|i| {
            (bj - 1..=bj + 1).any(|j| {
                layer.get(&(i, j)).is_some_and(|list| {
                    list.iter().any(|&(q, s)| {
                        (p[0] - q[0]).hypot(p[1] - q[1])
                            < (ARC_GRID_CLEARANCE - 1.0) * s * (1.0 - 1e-9)
                    })
                })
            })
        })
    };
    let step = h0 / (1u64 << depth) as f64;
    let at = |(row, col): (u64, u64)| [lo[0] + col as f64 * step, lo[1] + row as f64 * step];
    // Corners strictly inside, away from arcs, dropped only by the clearance from a straight
    // edge (the root column or row that straddles an edge when `h0` does not divide the box).
    let dropped = |key: (u64, u64), largest: f64, least: f64| {
        let p = at(key);
        domain.contains(p)
            && domain.boundary_distance(p) > 1e-9 * finest
            && !clear(p, least)
            && !near_arc(p, largest)
    };
    let kept_at = points.len();
    let mut kept: Vec<(u64, u64)> = Vec::new();
    for (&key, &(largest, least)) in &sizes {
        let p = at(key);
        if clear(p, least) && !near_arc(p, largest) {
            points.push(p);
            spacing.push(geometric(least, largest));
            smallest.push(least);
            kept.push(key);
        }
    }
    // A lattice node whose neighbour along a leaf side was dropped that way takes the largest
    // touched leaf as `h_I` (not the geometric mean): the gap to the edge is then up to 1.5 of
    // that leaf, as on the uniform set, where `h_I` is the leaf. With the mean, boundary points
    // of the straddled edge could be covered by boundary nodes only (collinear supports).
    for (k, &(row, col)) in kept.iter().enumerate() {
        let (largest, _) = sizes[&(row, col)];
        let leaf = ((largest / step).round() as u64).max(1);
        let beside = [
            (Some(row), col.checked_add(leaf)),
            (Some(row), col.checked_sub(leaf)),
            (row.checked_add(leaf), Some(col)),
            (row.checked_sub(leaf), Some(col)),
        ];
        let gap = beside.into_iter().any(|(r, c)| {
            let (Some(r), Some(c)) = (r, c) else { return false };
            sizes.get(&(r, c)).is_some_and(|&(g, l)| dropped((r, c), g, l))
        });
        if gap {
            spacing[kept_at + k] = largest;
        }
    }
    let edges = tag_edges(domain, &points, 1e-9 * finest);
    if let Layout::Jittered { amplitude, seed } = layout {
        let mut rng = SplitMix64::new(seed);
        for ((p, on), &s) in points.iter_mut().zip(&edges).zip(&smallest) {
            let (dx, dy) = (rng.uniform_symmetric(), rng.uniform_symmetric());
            let q = [p[0] + amplitude * s * dx, p[1] + amplitude * s * dy];
            if on.is_empty() && domain.boundary_distance(q) >= CURVED_CLEARANCE * s {
                *p = q;
            }
        }
    }
    Ok(Nodes { points, spacing, edges })
}

/// The points dividing `curve` at the local spacing `sigma(x)` ([`generate_graded_curved`]),
/// start and end included: `N = round(∫ ds/σ)` intervals (at least one; for an arc at least
/// one per 45°) where `∫ ds/σ` reaches `i/N` of its total, `σ` sampled at the midpoints of
/// pieces of at most `finest / 8`; [`crate::geometry::Curve::division_points`] when `σ` is
/// constant along the curve (a polyline always keeps its points).
fn graded_division_points(
    curve: &crate::geometry::Curve,
    sigma: &impl Fn(Point) -> f64,
    finest: f64,
) -> Vec<Point> {
    use crate::geometry::Curve;
    if matches!(curve, Curve::Polyline { .. }) {
        return curve.division_points(finest);
    }
    let length = curve.length();
    let pieces = ((8.0 * length / finest).ceil() as usize).clamp(1, 10_000_000);
    let local: Vec<f64> =
        (0..pieces).map(|j| sigma(curve.point_at((j as f64 + 0.5) / pieces as f64))).collect();
    if local.iter().all(|&s| s == local[0]) {
        return curve.division_points(local[0]);
    }
    // Cumulative ∫ ds/σ at the piece ends.
    let ds = length / pieces as f64;
    let mut cumulative = Vec::with_capacity(pieces + 1);
    cumulative.push(0.0);
    for s in &local {
        cumulative.push(cumulative.last().copied().unwrap_or(0.0) + ds / s);
    }
    let total = cumulative[pieces];
    let mut n = total.round().max(1.0) as usize;
    if let Curve::Arc { sweep, .. } = curve {
        n = n.max((sweep.abs() / (0.25 * std::f64::consts::PI)).ceil() as usize);
    }
    let mut points = vec![curve.start()];
    let mut j = 0;
    for i in 1..n {
        let target = total * i as f64 / n as f64;
        while j + 1 < pieces && cumulative[j + 1] <= target {
            j += 1;
        }
        let u = (target - cumulative[j]) / (cumulative[j + 1] - cumulative[j]);
        points.push(curve.point_at((j as f64 + u) / pieces as f64));
    }
    points.push(curve.end());
    points
}

/// Balances the quadtree of [`generate_graded`], finest level first: a split cell at level
/// `L ≥ 1` needs the level-`(L − 1)` cells around it (edge and corner neighbours) split, and
/// their ancestors. `split[L]` holds the split cells of level `L` of an `nx × ny` root grid.
fn balance(split: &mut [std::collections::BTreeSet<(u64, u64)>], nx: u64, ny: u64) {
    for level in (1..split.len()).rev() {
        let (cx, cy) = (nx << level, ny << level);
        let list: Vec<(u64, u64)> = split[level].iter().copied().collect();
        for (i, j) in list {
            for dj in -1i64..=1 {
                for di in -1i64..=1 {
                    let (ni, nj) = (i as i64 + di, j as i64 + dj);
                    if ni < 0 || nj < 0 || ni >= cx as i64 || nj >= cy as i64 {
                        continue;
                    }
                    let (mut l, mut a, mut b) = (level - 1, ni as u64 / 2, nj as u64 / 2);
                    while split[l].insert((a, b)) && l > 0 {
                        (l, a, b) = (l - 1, a / 2, b / 2);
                    }
                }
            }
        }
    }
}

/// Splits each leaf at a corner of the root grid whose diagonal neighbour (the cell across its
/// inner vertex) is split and whose two side neighbours are not (see [`generate_graded`]);
/// whether any was split. `corners` selects the corners (lower left, lower right, upper left,
/// upper right). The tree must be balanced before and after.
fn split_corner_cells(
    split: &mut [std::collections::BTreeSet<(u64, u64)>],
    nx: u64,
    ny: u64,
    corners: [bool; 4],
) -> bool {
    let mut changed = false;
    let all = [(false, false), (true, false), (false, true), (true, true)];
    for (right, top) in all.into_iter().zip(corners).filter(|c| c.1).map(|c| c.0) {
        // The leaf holding the corner.
        let (mut l, mut i, mut j) =
            (0usize, if right { nx - 1 } else { 0 }, if top { ny - 1 } else { 0 });
        while split.get(l).is_some_and(|s| s.contains(&(i, j))) {
            (l, i, j) = (l + 1, 2 * i + u64::from(right), 2 * j + u64::from(top));
        }
        // Inner neighbours (the root grid has at least two cells per side).
        let (ii, jj) = (if right { i - 1 } else { i + 1 }, if top { j - 1 } else { j + 1 });
        let is_split = |c: (u64, u64)| split.get(l).is_some_and(|s| s.contains(&c));
        if l < MAX_LEVEL as usize && is_split((ii, jj)) && !is_split((ii, j)) && !is_split((i, jj))
        {
            split[l].insert((i, j));
            changed = true;
        }
    }
    changed
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
            let mut p = c.division_points(h);
            p.pop();
            p
        })
        .collect();
    // One layer of nodes a spacing inside each arc, along the normals of its boundary
    // nodes, so that the first interior row follows the curve instead of a clipped grid.
    let clear =
        |p: Point| domain.contains(p) && domain.boundary_distance(p) >= CURVED_CLEARANCE * h;
    let curves = domain.curves();
    for (k, c) in curves.iter().enumerate().filter(|(_, c)| !c.is_straight()) {
        let division = c.division_points(h);
        let n = division.len() - 1;
        // The end's layer node belongs to the next curve (of the same loop) when that is an
        // arc too.
        let last = if curves[domain.next_in_loop(k)].is_straight() { n } else { n - 1 };
        for &b in &division[..=last] {
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

    /// A rectangle refined along its bottom edge and in a box (docs/method.md §2.1).
    fn graded(layout: Layout) -> (Domain, Nodes) {
        use crate::problem::{RefineBox, Refinement};
        let d = Domain::rectangle([0.0, 8.0], [-1.0, 1.0]).unwrap();
        let r = Refinement {
            boxes: vec![
                RefineBox { x: [0.0, 8.0], y: [-1.0, -0.8], spacing: 0.0625 },
                RefineBox { x: [5.0, 5.5], y: [0.2, 0.4], spacing: 0.03 },
            ],
        };
        let n = generate_graded(&d, 0.25, layout, |lo, hi| r.min_spacing_in(0.25, lo, hi)).unwrap();
        (d, n)
    }

    /// The bounded generator abandons exactly the sets larger than the bound, and returns the
    /// unbounded generator's set otherwise (its leaf bound never exceeds the node count).
    #[test]
    fn bounded_graded_generation_refuses_exactly_the_sets_beyond_the_bound() {
        use crate::problem::{RefineBox, Refinement};
        let r = Refinement {
            boxes: vec![
                RefineBox { x: [0.0, 8.0], y: [-1.0, -0.8], spacing: 0.0625 },
                RefineBox { x: [5.0, 5.5], y: [0.2, 0.4], spacing: 0.03 },
            ],
        };
        let spacing = |lo, hi| r.min_spacing_in(0.25, lo, hi);
        for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 7 }] {
            let (d, full) = graded(layout);
            let n = full.len();
            for bound in [n / 2, n - 1, n, n + 1] {
                let got = generate_graded_at_most(&d, 0.25, layout, bound, spacing).unwrap();
                if bound < n {
                    // Abandoned, or (when the leaf bound stayed below) the whole set, refused
                    // by its size.
                    assert!(got.as_ref().is_none_or(|g| g.len() == n), "bound {bound}");
                } else {
                    let got = got.expect("within the bound");
                    assert_eq!(
                        (got.points, got.spacing),
                        (full.points.clone(), full.spacing.clone())
                    );
                }
            }
            assert!(generate_graded_at_most(&d, 0.25, layout, n / 2, spacing).unwrap().is_none());
        }
    }

    #[test]
    fn graded_without_refinement_is_the_uniform_set() {
        let d = Domain::rectangle([0.0, 4.0], [0.0, 2.0]).unwrap();
        for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 7 }] {
            let a = generate(&d, 0.3, layout).unwrap();
            let b = generate_graded(&d, 0.3, layout, |_, _| 0.3).unwrap();
            assert_eq!(a.points, b.points);
            assert_eq!(a.spacing, b.spacing);
            assert_eq!(a.edges, b.edges);
        }
    }

    #[test]
    fn graded_set_has_boundary_nodes_at_the_local_spacing_and_bounded_ratios() {
        let (d, n) = graded(Layout::Structured);
        // Bottom edge: 8 / 0.0625 intervals; the corners are nodes.
        let bottom = n.edges.iter().filter(|e| e.contains(0)).count();
        assert_eq!(bottom, 129);
        for c in [[0.0, -1.0], [8.0, -1.0], [8.0, 1.0], [0.0, 1.0]] {
            assert!(n.points.contains(&c), "corner {c:?}");
        }
        // The box asks for 0.03: cells of 0.25 / 16 = 0.015625 there.
        let finest = n.spacing.iter().fold(f64::INFINITY, |m, &v| m.min(v));
        assert!((finest - 0.015625).abs() < 1e-15, "{finest}");
        assert_eq!(n.spacing.iter().fold(0.0f64, |m, &v| m.max(v)), 0.25);
        // h_I is the geometric mean of the largest and smallest cells touched: the nearest
        // neighbour is at least h_I / √2 away (cells differ by at most 2) and at most h_I (a
        // corner of the smallest cell).
        for (i, p) in n.points.iter().enumerate() {
            let nn = n
                .points
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(nn >= n.spacing[i] / 2f64.sqrt() * (1.0 - 1e-12), "node {i} at {p:?}: {nn}");
            assert!(nn <= n.spacing[i] * (1.0 + 1e-12), "node {i} at {p:?}: {nn}");
        }
        // Every node inside the rectangle; tags only on the edges.
        for (p, e) in n.points.iter().zip(&n.edges) {
            let on = p[1] == -1.0 || p[1] == 1.0 || p[0] == 0.0 || p[0] == 8.0;
            assert_eq!(on, !e.is_empty(), "{p:?}");
            assert!((0..4).all(|k| d.edge_distance(k, *p) <= 0.0));
        }
        // Fewer nodes than the uniform set at the finest spacing in the band.
        assert!(n.len() < 129 * 33, "{}", n.len());
    }

    #[test]
    fn graded_jitter_is_deterministic_local_and_keeps_boundary() {
        let layout = Layout::Jittered { amplitude: 0.4, seed: 9 };
        let (_, a) = graded(layout);
        let (_, b) = graded(layout);
        let (_, s) = graded(Layout::Structured);
        assert_eq!(a.points, b.points);
        assert_eq!(a.spacing, s.spacing);
        for i in 0..a.len() {
            let (p, q) = (a.points[i], s.points[i]);
            if a.edges[i].is_empty() {
                // At most 0.4 of the smallest touched cell, itself at most h_I.
                let moved = (p[0] - q[0]).abs().max((p[1] - q[1]).abs());
                assert!(moved <= 0.4 * s.spacing[i] + 1e-15, "{i}: {moved}");
            } else {
                assert_eq!(p, q);
            }
        }
    }

    /// Nodes whose support `|x − x_J|² < (α_s h_J)² (1 − 10⁻¹⁰)` at `α_s = 2` holds `x`
    /// (docs/method.md §2).
    fn support_size(n: &Nodes, x: Point) -> usize {
        (0..n.len())
            .filter(|&j| {
                let (p, r) = (n.points[j], 2.0 * n.spacing[j]);
                (p[0] - x[0]).powi(2) + (p[1] - x[1]).powi(2) < r * r * (1.0 - 1e-10)
            })
            .count()
    }

    /// The cantilever's rectangle at `h₀ = 2` with a point region of spacing 1 diagonally off
    /// each corner cell: the cell across each corner cell's inner vertex is split, the corner
    /// cell and its two side neighbours are not. That inner vertex then touches a cell of size
    /// 1 and takes `h_I = √2`: its support radius `2√2` is the corner cell's diagonal, so the
    /// domain corner had only 3 support nodes (itself and its two edge neighbours), on
    /// structured and jittered layouts alike (the adaptive loop's jittered cantilever stopped
    /// there). The generator splits such a corner cell.
    #[test]
    fn graded_corner_cell_next_to_a_finer_diagonal_cell_keeps_four_support_nodes() {
        use crate::problem::{RefineBox, Refinement};
        let d = Domain::rectangle([0.0, 48.0], [-6.0, 6.0]).unwrap();
        let point = |x: f64, y: f64| RefineBox { x: [x, x], y: [y, y], spacing: 1.0 };
        let r = Refinement {
            boxes: vec![point(4.0, -1.0), point(44.0, -1.0), point(4.0, 1.0), point(44.0, 1.0)],
        };
        for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.4, seed: 1 }] {
            let n =
                generate_graded(&d, 2.0, layout, |lo, hi| r.min_spacing_in(2.0, lo, hi)).unwrap();
            // The regions did refine next to the corners (the cells across their inner vertices).
            assert!(n.spacing.iter().any(|&h| h < 2.0));
            for c in [[0.0, -6.0], [48.0, -6.0], [48.0, 6.0], [0.0, 6.0]] {
                let k = support_size(&n, c);
                assert!(k >= 4, "{layout:?}: corner {c:?} has {k} support nodes");
            }
        }
    }

    /// The Hertz quarter cylinder (two arcs, two segments).
    fn quarter_cylinder() -> Domain {
        use crate::geometry::Curve;
        let c = [0.0, 1.0];
        let split = [0.5, 1.0 - 0.75f64.sqrt()];
        Domain::from_curves(
            vec![
                Curve::arc_between([0.0, 0.0], split, c, true),
                Curve::arc_between(split, [1.0, 1.0], c, true),
                Curve::Segment { a: [1.0, 1.0], b: [0.0, 1.0] },
                Curve::Segment { a: [0.0, 1.0], b: [0.0, 0.0] },
            ],
            ["arc", "rim", "top", "axis"].iter().map(|s| s.to_string()).collect(),
        )
        .unwrap()
    }

    #[test]
    fn graded_curved_without_refinement_is_the_uniform_set() {
        let d = quarter_cylinder();
        for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 7 }] {
            let a = generate(&d, 0.05, layout).unwrap();
            let b = generate_graded_curved(&d, 0.05, layout, |_, _| 0.05).unwrap();
            assert_eq!(a.points, b.points);
            assert_eq!(a.spacing, b.spacing);
            assert_eq!(a.edges, b.edges);
        }
    }

    #[test]
    fn graded_curved_set_follows_the_spacing_on_the_arcs_and_inside() {
        use crate::problem::{RefineBox, Refinement};
        let d = quarter_cylinder();
        let r = Refinement {
            boxes: vec![RefineBox { x: [0.0, 0.15], y: [0.0, 0.03], spacing: 0.0125 }],
        };
        for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 3 }] {
            let n = generate_graded_curved(&d, 0.1, layout, |lo, hi| r.min_spacing_in(0.1, lo, hi))
                .unwrap();
            // Boundary nodes lie on their edges; interior nodes at least 0.7 of their (smallest
            // touched) spacing inside, less the jitter.
            for (i, (p, e)) in n.points.iter().zip(&n.edges).enumerate() {
                if e.is_empty() {
                    assert!(d.contains(*p), "{p:?}");
                    let least = n.spacing[i] / 2f64.sqrt();
                    assert!(d.boundary_distance(*p) >= 0.7 * least * (1.0 - 1e-12), "{p:?}");
                } else {
                    assert!(e.iter().all(|k| d.edge_distance(k, *p).abs() < 1e-12), "{p:?}");
                }
            }
            // Along the contact arc, neighbouring chords differ by at most 2:1 (plus the
            // sampling's margin) and reach the finest spacing, 0.1 / 8, near x = 0.
            let mut arc: Vec<(f64, Point)> = (0..n.len())
                .filter(|&i| n.edges[i].contains(0))
                .map(|i| (d.edge_parameter(0, n.points[i]), n.points[i]))
                .collect();
            arc.sort_by(|a, b| a.0.total_cmp(&b.0));
            let chords: Vec<f64> = arc
                .windows(2)
                .map(|w| (w[1].1[0] - w[0].1[0]).hypot(w[1].1[1] - w[0].1[1]))
                .collect();
            assert!(chords[0] < 0.0125 * 1.1 && chords[0] > 0.0125 / 1.1, "{}", chords[0]);
            assert!(chords.iter().fold(0.0f64, |m, &c| m.max(c)) > 0.04);
            for w in chords.windows(2) {
                let ratio = w[0].max(w[1]) / w[0].min(w[1]);
                assert!(ratio <= 2.1, "{chords:?}");
            }
            // No two nodes closer than half the finer one's spacing (structured).
            let structured = layout == Layout::Structured;
            for i in (0..n.len()).filter(|_| structured) {
                for j in 0..i {
                    let (p, q) = (n.points[i], n.points[j]);
                    let dist = (p[0] - q[0]).hypot(p[1] - q[1]);
                    assert!(dist > n.spacing[i].min(n.spacing[j]) / 2.0, "{p:?} {q:?}");
                }
            }
            // Far fewer nodes than the uniform set at the finest spacing.
            let fine = generate(&d, 0.0125, Layout::Structured).unwrap();
            assert!(n.len() * 5 < fine.len(), "{} vs {}", n.len(), fine.len());
        }
    }

    #[test]
    fn graded_curved_refuses_holes() {
        use crate::geometry::Curve;
        let hole = Domain::from_curves(
            vec![Curve::arc_between([1.5, 1.0], [1.5, 1.0], [1.0, 1.0], true)],
            vec!["hole".into()],
        )
        .unwrap();
        let d = Domain::rectangle([0.0, 2.0], [0.0, 2.0]).unwrap().with_holes(vec![hole]).unwrap();
        let e = generate_graded_curved(&d, 0.25, Layout::Structured, |_, _| 0.1).unwrap_err();
        assert!(e.to_string().contains("holes"), "{e}");
    }

    #[test]
    fn graded_refuses_non_rectangles() {
        let d = Domain::polygon(
            vec![[0.0, 0.0], [4.0, 0.0], [0.0, 3.0]],
            vec!["a".into(), "b".into(), "c".into()],
        )
        .unwrap();
        let e = generate_graded(&d, 0.25, Layout::Structured, |_, _| 0.1).unwrap_err();
        assert!(e.to_string().contains("rectangles only"), "{e}");
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
