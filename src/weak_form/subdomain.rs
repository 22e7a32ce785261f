//! Subdomains `Ω_s`: the Voronoi cells of the nodes clipped to the domain, which tile it.
//!
//! Tiling gives two exact properties (docs/method.md §3.5): interior-face contributions cancel
//! pairwise, so global equilibrium holds to round-off, and every boundary segment has exactly
//! one owner. On a structured grid the cells are the usual rectangles around the nodes (halved
//! on edges, quartered at corners).

use super::CellError;
use crate::geometry::{Domain, Point};
use crate::neighbours::{NeighbourGrid, dist2};
use crate::nodes::Nodes;
use rayon::prelude::*;

/// What lies across a cell edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeLabel {
    /// The cell of another node.
    Neighbour(u32),
    /// Domain edge `k` (the boundary).
    Boundary(u32),
}

/// A cell polygon (convex unless the domain boundary makes it otherwise): vertex `k` starts
/// edge `k`, whose far side is `labels[k]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    /// Vertices, counter-clockwise.
    pub vertices: Vec<Point>,
    /// What lies across each edge.
    pub labels: Vec<EdgeLabel>,
}

impl Cell {
    /// Area (shoelace).
    pub fn area(&self) -> f64 {
        let n = self.vertices.len();
        0.5 * (0..n)
            .map(|k| {
                let (a, b) = (self.vertices[k], self.vertices[(k + 1) % n]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
    }

    /// Edge `k` as `(a, b)`.
    pub fn edge(&self, k: usize) -> (Point, Point) {
        (self.vertices[k], self.vertices[(k + 1) % self.vertices.len()])
    }
}

/// Builds the clipped Voronoi cell of every node.
///
/// Each cell starts as the domain's polygonal approximation, its arcs as the chords between
/// their boundary nodes ([`Domain::boundary_rings_through`]; for polygons with many vertices,
/// its part inside a box around the node) and is clipped by
/// the bisector half-planes of the nearby nodes, nearest first, until every node closer than
/// twice the cell's radius has been used (the security-radius criterion), so the result is
/// exact. Clipping a non-convex start polygon by half-planes is exact as long as each clipped
/// piece stays connected, which holds when the domain's features are several spacings wide.
///
/// A domain with holes starts from one polygon too: its rings ([`Domain::boundary_rings`])
/// joined by cuts, a pair of opposite edges from each hole to the ring beyond it
/// (see `keyhole`). The cuts are drawn in one of four directions (`+x`, `+y`, `−x`, `−y`);
/// a node whose finished cell still has a cut edge (the cut passes through its cell) is
/// built again from the next direction's polygon.
///
/// # Errors
/// [`CellError::EmptyCell`] when a node's cell vanishes (duplicate or outside nodes);
/// [`CellError::HoleCut`] when every direction's cut passes through a node's cell.
pub fn build_cells(domain: &Domain, nodes: &Nodes) -> Result<Vec<Cell>, CellError> {
    let h = nodes.spacing.iter().fold(0.0f64, |m, &v| m.max(v));
    let grid = NeighbourGrid::new(&nodes.points, 2.0 * h);
    let on_arcs = arc_boundary_nodes(domain, nodes);
    let rings = domain.boundary_rings_through(h, |k| on_arcs[k].clone());
    let starts: Vec<Cell> = if domain.has_holes() {
        CUT_DIRECTIONS.iter().filter_map(|&e| keyhole(&rings, e)).collect()
    } else {
        let (vertices, labels) = rings.into_iter().next().unwrap_or_default();
        vec![Cell { vertices, labels: labels.into_iter().map(EdgeLabel::Boundary).collect() }]
    };
    (0..nodes.len())
        .into_par_iter()
        .map_init(Vec::new, |scratch, i| {
            for start in &starts {
                let cell = voronoi_cell(i, nodes, &grid, start, domain.has_holes(), scratch)?;
                if !cell.labels.contains(&EdgeLabel::Neighbour(CUT)) {
                    return Ok(cell);
                }
            }
            Err(CellError::HoleCut { node: i, point: nodes.points[i] })
        })
        .collect()
}

/// Per domain edge, the positions of the nodes on it when it is an arc (empty otherwise): the
/// nodes tagged with the edge, from its start (included) to its end (excluded, unless it is
/// also the start: a full circle), by their parameter along it. These are the vertices of the
/// arc's chords in the cells' start polygon ([`Domain::boundary_rings_through`]), so that every
/// boundary face lies between two boundary nodes of the arc at any grading (on a uniform set
/// they are the arc's [`crate::geometry::Curve::division_points`]).
fn arc_boundary_nodes(domain: &Domain, nodes: &Nodes) -> Vec<Vec<Point>> {
    let mut on: Vec<Vec<(f64, usize)>> = vec![Vec::new(); domain.edge_count()];
    for (i, set) in nodes.edges.iter().enumerate() {
        for k in set.iter() {
            let c = domain.curve(k);
            if !matches!(c, crate::geometry::Curve::Arc { .. }) {
                continue;
            }
            let p = nodes.points[i];
            let tol2 = (1e-9 * nodes.spacing[i]).powi(2);
            if dist2(p, c.end()) <= tol2 && dist2(p, c.start()) > tol2 {
                continue;
            }
            on[k].push((domain.edge_parameter(k, p), i));
        }
    }
    on.into_iter()
        .map(|mut list| {
            list.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            list.into_iter().map(|(_, i)| nodes.points[i]).collect()
        })
        .collect()
}

/// Start polygons with more vertices than this are first cut to a box around the node.
const BOX_CLIP_VERTICES: usize = 32;
/// Label of the box edges (never a node index; none survives in a finished cell).
const BOX: u32 = u32::MAX;
/// Label of the cuts joining a hole's ring to the ring beyond it (never a node index).
const CUT: u32 = u32::MAX - 1;
/// The directions of the cuts of [`keyhole`], tried in this order.
const CUT_DIRECTIONS: [Point; 4] = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];

/// One polygon from the rings of a domain with holes (outer ring counter-clockwise, holes
/// clockwise): holes in order of their farthest vertex along `e` (farthest first), each
/// joined to the polygon built so far by a cut from that vertex along `e` to the nearest
/// crossing with the polygon, walked there and back (two opposite edges labelled
/// `Neighbour(CUT)`; the crossing is a new vertex splitting the edge it lies on). The
/// polygon bounds the domain with the cuts removed, a region of the same area. `None` when
/// a cut finds no crossing (a hole outside the outer ring).
fn keyhole(rings: &[(Vec<Point>, Vec<u32>)], e: Point) -> Option<Cell> {
    let along = |p: Point| p[0] * e[0] + p[1] * e[1];
    let across = |p: Point| -p[0] * e[1] + p[1] * e[0];
    let (outer, outer_labels) = &rings[0];
    let mut vertices = outer.clone();
    let mut labels: Vec<EdgeLabel> = outer_labels.iter().map(|&k| EdgeLabel::Boundary(k)).collect();
    let mut holes: Vec<(usize, f64)> = rings[1..]
        .iter()
        .enumerate()
        .map(|(i, (v, _))| (i + 1, v.iter().map(|&p| along(p)).fold(f64::NEG_INFINITY, f64::max)))
        .collect();
    holes.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    for (r, _) in holes {
        let (ring, ring_labels) = &rings[r];
        let m = (0..ring.len()).fold(0, |m, i| if along(ring[i]) > along(ring[m]) { i } else { m });
        let p = ring[m];
        let (pa, pc) = (along(p), across(p));
        // The nearest crossing of the ray from p along e (half-open rule on the edges).
        let mut best: Option<(usize, Point, f64)> = None;
        for k in 0..vertices.len() {
            let (a, b) = (vertices[k], vertices[(k + 1) % vertices.len()]);
            let (sa, sb) = (across(a) - pc, across(b) - pc);
            if (sa > 0.0) == (sb > 0.0) {
                continue;
            }
            let t = sa / (sa - sb);
            let q = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            let d = along(q) - pa;
            if d > 0.0 && best.is_none_or(|(_, _, bd)| d < bd) {
                best = Some((k, q, d));
            }
        }
        let (k, q, _) = best?;
        let n = ring.len();
        let mut v = Vec::with_capacity(vertices.len() + n + 3);
        let mut l = Vec::with_capacity(vertices.len() + n + 3);
        v.extend_from_slice(&vertices[..=k]);
        l.extend_from_slice(&labels[..=k]);
        // q splits edge k; then the cut, the hole from p round to p, the cut back.
        v.push(q);
        l.push(EdgeLabel::Neighbour(CUT));
        for i in 0..n {
            v.push(ring[(m + i) % n]);
            l.push(EdgeLabel::Boundary(ring_labels[(m + i) % n]));
        }
        v.push(p);
        l.push(EdgeLabel::Neighbour(CUT));
        v.push(q);
        l.push(labels[k]);
        v.extend_from_slice(&vertices[k + 1..]);
        l.extend_from_slice(&labels[k + 1..]);
        // A crossing at a vertex repeats it: drop the zero-length edge.
        let mut i = 0;
        while i < v.len() {
            if v[i] == v[(i + 1) % v.len()] {
                v.remove(i);
                l.remove(i);
            } else {
                i += 1;
            }
        }
        (vertices, labels) = (v, l);
    }
    Some(Cell { vertices, labels })
}

fn voronoi_cell(
    i: usize,
    nodes: &Nodes,
    grid: &NeighbourGrid,
    start: &Cell,
    slits: bool,
    near: &mut Vec<usize>,
) -> Result<Cell, CellError> {
    let x = nodes.points[i];
    let h = nodes.spacing[i];
    let tol = 1e-10 * h;
    let mut radius = 2.5 * h;
    loop {
        grid.within(&nodes.points, x, radius, near);
        near.retain(|&j| j != i);
        near.sort_by(|&a, &b| {
            dist2(nodes.points[a], x).total_cmp(&dist2(nodes.points[b], x)).then(a.cmp(&b))
        });
        let mut cell = start.clone();
        if cell.vertices.len() > BOX_CLIP_VERTICES {
            // Keep only the part of the boundary polygon inside the square of half-width
            // `radius` about the node (the security criterion below keeps the final cell
            // well inside it), so each clip below costs O(local vertices).
            for e in [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]] {
                let y = [x[0] + 2.0 * radius * e[0], x[1] + 2.0 * radius * e[1]];
                clip(&mut cell, x, y, BOX, tol);
            }
        }
        for &j in near.iter() {
            let y = nodes.points[j];
            let d2 = dist2(x, y);
            if d2 <= tol * tol {
                return Err(CellError::DuplicateNode { node: i, other: j, point: x });
            }
            clip(&mut cell, x, y, j as u32, tol);
            if cell.vertices.len() < 3 {
                return Err(CellError::EmptyCell { node: i, point: x });
            }
        }
        if slits {
            remove_slits(&mut cell, 1e-9 * h);
        }
        let reach = cell.vertices.iter().map(|v| dist2(*v, x)).fold(0.0f64, f64::max).sqrt();
        if 2.0 * reach <= radius && !cell.labels.contains(&EdgeLabel::Neighbour(BOX)) {
            return Ok(cell);
        }
        radius = 2.0 * reach * (1.0 + 1e-9);
    }
}

/// Removes the slits of a clipped cell: pairs of consecutive edges with the same label that
/// run back along the same line (to within `tol`), which clipping a polygon with holes
/// leaves where a hole's boundary, outside a bisector's half-plane, was replaced by the
/// bisector (it then runs into the hole and back), and where a cut was clipped on both
/// sides. They enclose no area; the tip vertex is dropped, and the edge shortened. Two
/// consecutive edges with the same label running on along one line (an edge split where a
/// cut met it) become one, so that the face is the same piece as its twin's.
fn remove_slits(cell: &mut Cell, tol: f64) {
    let mut changed = true;
    while changed && cell.vertices.len() > 2 {
        changed = false;
        let n = cell.vertices.len();
        for k in 0..n {
            let prev = (k + n - 1) % n;
            let (a, t, b) = (cell.vertices[prev], cell.vertices[k], cell.vertices[(k + 1) % n]);
            let (u, v) = ([t[0] - a[0], t[1] - a[1]], [b[0] - t[0], b[1] - t[1]]);
            let longest = u[0].hypot(u[1]).max(v[0].hypot(v[1]));
            let cross = (u[0] * v[1] - u[1] * v[0]).abs();
            if cell.labels[prev] == cell.labels[k] && cross <= tol * longest {
                // The edge from `a` now ends at `b`; drop it if `a` and `b` coincide.
                cell.vertices.remove(k);
                cell.labels.remove(k);
                let m = cell.vertices.len();
                let j = if k == 0 { m - 1 } else { k - 1 };
                if m > 1 && dist2(cell.vertices[j], cell.vertices[(j + 1) % m]) <= tol * tol {
                    cell.vertices.remove(j);
                    cell.labels.remove(j);
                }
                changed = true;
                break;
            }
        }
    }
}

/// Clips `cell` by the half-plane of points closer to `x` than to `y`; the new edge is
/// labelled `Neighbour(j)`. Points within `tol` of the bisector count as inside, and edges
/// shorter than `tol` are dropped, so degenerate (4-cell) vertices of grids stay clean.
fn clip(cell: &mut Cell, x: Point, y: Point, j: u32, tol: f64) {
    let len = dist2(x, y).sqrt();
    let n = [(y[0] - x[0]) / len, (y[1] - x[1]) / len];
    let m = [0.5 * (x[0] + y[0]), 0.5 * (x[1] + y[1])];
    let side = |p: Point| (p[0] - m[0]) * n[0] + (p[1] - m[1]) * n[1];
    let count = cell.vertices.len();
    let s: Vec<f64> = cell.vertices.iter().map(|&p| side(p)).collect();
    if s.iter().all(|&v| v <= tol) {
        return;
    }
    let mut vertices = Vec::with_capacity(count + 1);
    let mut labels = Vec::with_capacity(count + 1);
    for k in 0..count {
        let (a, b) = cell.edge(k);
        let (sa, sb) = (s[k], s[(k + 1) % count]);
        let label = cell.labels[k];
        let cross = |sa: f64, sb: f64| {
            let t = sa / (sa - sb);
            [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
        };
        match (sa <= tol, sb <= tol) {
            (true, true) => {
                vertices.push(a);
                labels.push(label);
            }
            (true, false) => {
                vertices.push(a);
                labels.push(label);
                if sa < 0.0 {
                    vertices.push(cross(sa, sb));
                    labels.push(EdgeLabel::Neighbour(j));
                } else {
                    // `a` lies on the bisector: the clip edge starts at `a` itself.
                    if let Some(l) = labels.last_mut() {
                        *l = EdgeLabel::Neighbour(j);
                    }
                }
            }
            (false, true) => {
                if sb < 0.0 {
                    vertices.push(cross(sa, sb));
                    labels.push(label);
                }
            }
            (false, false) => {}
        }
    }
    // Drop zero-length edges.
    let mut k = 0;
    while vertices.len() > 2 && k < vertices.len() {
        let next = (k + 1) % vertices.len();
        if dist2(vertices[k], vertices[next]) <= tol * tol {
            vertices.remove(k);
            labels.remove(k);
        } else {
            k += 1;
        }
    }
    cell.vertices = vertices;
    cell.labels = labels;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nodes::{Layout, generate};

    fn total_area(cells: &[Cell]) -> f64 {
        cells.iter().map(Cell::area).sum()
    }

    #[test]
    fn structured_cells_are_rectangles_and_tile() {
        let d = Domain::rectangle([0.0, 2.0], [0.0, 1.0]).unwrap();
        let nodes = generate(&d, 0.25, Layout::Structured).unwrap();
        let cells = build_cells(&d, &nodes).unwrap();
        assert!((total_area(&cells) - 2.0).abs() < 1e-12);
        // Interior node: a 0.25 x 0.25 square with four neighbours.
        let interior = 9 + 1;
        assert_eq!(cells[interior].vertices.len(), 4);
        assert!((cells[interior].area() - 0.0625).abs() < 1e-14);
        // Corner: a quarter cell with two boundary edges.
        let corner = &cells[0];
        assert!((corner.area() - 0.0625 / 4.0).abs() < 1e-14);
        let boundary = corner.labels.iter().filter(|l| matches!(l, EdgeLabel::Boundary(_))).count();
        assert_eq!(boundary, 2);
    }

    #[test]
    fn cells_tile_curved_and_non_convex_domains() {
        use crate::geometry::Curve;
        let plate = Domain::from_curves(
            vec![
                Curve::Segment { a: [1.0, 0.0], b: [4.0, 0.0] },
                Curve::Segment { a: [4.0, 0.0], b: [4.0, 4.0] },
                Curve::Segment { a: [4.0, 4.0], b: [0.0, 4.0] },
                Curve::Segment { a: [0.0, 4.0], b: [0.0, 1.0] },
                Curve::arc_between([0.0, 1.0], [1.0, 0.0], [0.0, 0.0], false),
            ],
            ["bottom", "right", "top", "left", "hole"].iter().map(|s| s.to_string()).collect(),
        )
        .unwrap();
        let disk = Domain::from_curves(
            vec![Curve::arc_between([2.0, 0.0], [2.0, 0.0], [0.0, 0.0], true)],
            vec!["rim".into()],
        )
        .unwrap();
        for (d, h) in [(&plate, 0.1), (&plate, 0.05), (&disk, 0.1)] {
            for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 5 }] {
                let nodes = generate(d, h, layout).unwrap();
                let cells = build_cells(d, &nodes).unwrap();
                let (poly, _) = d.boundary_polygon(h);
                let poly_area = 0.5
                    * (0..poly.len())
                        .map(|k| {
                            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
                            a[0] * b[1] - b[0] * a[1]
                        })
                        .sum::<f64>();
                assert!((total_area(&cells) - poly_area).abs() < 1e-10 * poly_area);
                // The chords cut O(h²) off a convex arc and add as much inside a hole.
                let lost = (d.area() - poly_area) / d.area();
                assert!(lost != 0.0 && lost.abs() < 0.1 * h * h, "{lost}");
                for (i, c) in cells.iter().enumerate() {
                    assert!(c.area() > 0.0);
                    assert!(!c.labels.contains(&EdgeLabel::Neighbour(BOX)));
                    // Only boundary nodes own boundary faces.
                    if c.labels.iter().any(|l| matches!(l, EdgeLabel::Boundary(_))) {
                        assert!(
                            !nodes.edges[i].is_empty(),
                            "interior node {i} at {:?} reaches the boundary ({h}, {layout:?}, {} edges)",
                            nodes.points[i],
                            d.edge_count()
                        );
                    }
                }
            }
        }
    }

    /// A graded set on a quarter disk (`nodes::generate_graded_curved`, refined in a box at the
    /// arc): the cells start from the chords between the arc's own boundary nodes, so they
    /// tile that polygon and only boundary nodes own boundary faces (with the arc divided at
    /// the largest spacing instead, fine-spaced arc nodes would lose their boundary faces).
    #[test]
    fn graded_curved_cells_tile_the_polygon_through_the_boundary_nodes() {
        use crate::geometry::Curve;
        use crate::problem::{RefineBox, Refinement};
        let d = Domain::from_curves(
            vec![
                Curve::Segment { a: [0.0, 0.0], b: [1.0, 0.0] },
                Curve::arc_between([1.0, 0.0], [0.0, 1.0], [0.0, 0.0], true),
                Curve::Segment { a: [0.0, 1.0], b: [0.0, 0.0] },
            ],
            ["bottom", "arc", "left"].iter().map(|s| s.to_string()).collect(),
        )
        .unwrap();
        let r =
            Refinement { boxes: vec![RefineBox { x: [0.6, 0.8], y: [0.6, 0.8], spacing: 0.0125 }] };
        for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 5 }] {
            let nodes = crate::nodes::generate_graded_curved(&d, 0.1, layout, |lo, hi| {
                r.min_spacing_in(0.1, lo, hi)
            })
            .unwrap();
            let cells = build_cells(&d, &nodes).unwrap();
            let mut arc: Vec<(f64, Point)> = (0..nodes.len())
                .filter(|&i| nodes.edges[i].contains(1))
                .map(|i| (d.edge_parameter(1, nodes.points[i]), nodes.points[i]))
                .collect();
            arc.sort_by(|a, b| a.0.total_cmp(&b.0));
            // The polygon (0, 0) → the arc's nodes → back: its area.
            let mut poly = vec![[0.0, 0.0]];
            poly.extend(arc.iter().map(|a| a.1));
            let poly_area = 0.5
                * (0..poly.len())
                    .map(|k| {
                        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
                        a[0] * b[1] - b[0] * a[1]
                    })
                    .sum::<f64>();
            let total = total_area(&cells);
            assert!((total - poly_area).abs() < 1e-12, "{layout:?}: {total} vs {poly_area}");
            for (i, c) in cells.iter().enumerate() {
                assert!(c.area() > 0.0);
                let owns = c.labels.iter().any(|l| matches!(l, EdgeLabel::Boundary(_)));
                assert_eq!(owns, !nodes.edges[i].is_empty(), "{layout:?}: node {i}");
            }
        }
    }

    /// The square `[-3, 3]²` with holes (a disk, and a square hole for straight ones).
    fn holed_domains() -> Vec<Domain> {
        use crate::geometry::Curve;
        let outer = || Domain::rectangle([-3.0, 3.0], [-3.0, 3.0]).unwrap();
        let disk = |c: [f64; 2], r: f64, name: &str| {
            let p = [c[0] + r, c[1]];
            Domain::from_curves(vec![Curve::arc_between(p, p, c, true)], vec![name.into()]).unwrap()
        };
        let square = Domain::polygon(
            vec![[0.8, -0.6], [1.9, -0.6], [1.9, 0.5], [0.8, 0.5]],
            ["s0", "s1", "s2", "s3"].map(String::from).to_vec(),
        )
        .unwrap();
        vec![
            outer().with_holes(vec![disk([0.0, 0.0], 1.0, "hole")]).unwrap(),
            outer()
                .with_holes(vec![disk([-1.2, 0.3], 0.7, "a"), square, disk([0.5, 1.9], 0.5, "b")])
                .unwrap(),
        ]
    }

    #[test]
    fn cells_tile_domains_with_holes() {
        for (n, d) in holed_domains().iter().enumerate() {
            for h in [0.2, 0.1] {
                for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 5 }] {
                    let nodes = generate(d, h, layout).unwrap();
                    assert!(
                        nodes
                            .points
                            .iter()
                            .all(|&p| d.contains(p) || d.boundary_distance(p) < 1e-12)
                    );
                    let cells = build_cells(d, &nodes).unwrap();
                    let rings = d.boundary_rings(h);
                    let ring_area = |v: &Vec<Point>| {
                        0.5 * (0..v.len())
                            .map(|k| {
                                let (a, b) = (v[k], v[(k + 1) % v.len()]);
                                a[0] * b[1] - b[0] * a[1]
                            })
                            .sum::<f64>()
                    };
                    let poly_area: f64 = rings.iter().map(|(v, _)| ring_area(v)).sum();
                    let total = total_area(&cells);
                    assert!(
                        (total - poly_area).abs() < 1e-10 * poly_area,
                        "domain {n}, h = {h}, {layout:?}: cells {total} vs polygon {poly_area}"
                    );
                    for (i, c) in cells.iter().enumerate() {
                        assert!(c.area() > 0.0);
                        assert!(!c.labels.contains(&EdgeLabel::Neighbour(CUT)));
                        assert!(
                            c.vertices
                                .iter()
                                .all(|&p| d.contains(p) || d.boundary_distance(p) < 0.1 * h),
                            "domain {n}, h = {h}, {layout:?}: cell {i} at {:?}: {:?} {:?} {:?}",
                            nodes.points[i],
                            c.vertices
                                .iter()
                                .map(|&p| (d.contains(p), d.boundary_distance(p)))
                                .collect::<Vec<_>>(),
                            c.vertices,
                            c.labels
                        );
                        if c.labels.iter().any(|l| matches!(l, EdgeLabel::Boundary(_))) {
                            assert!(
                                !nodes.edges[i].is_empty(),
                                "interior node {i} reaches the boundary"
                            );
                        }
                        // Every neighbour edge has a twin of the same length (no slit left).
                        for (k, l) in c.labels.iter().enumerate() {
                            if let EdgeLabel::Neighbour(j) = *l {
                                let (a, b) = c.edge(k);
                                let other = &cells[j as usize];
                                let twin = (0..other.vertices.len()).any(|m| {
                                    let (p, q) = other.edge(m);
                                    other.labels[m] == EdgeLabel::Neighbour(i as u32)
                                        && dist2(p, b).sqrt() < 1e-9
                                        && dist2(q, a).sqrt() < 1e-9
                                });
                                assert!(
                                    twin,
                                    "domain {n}, h = {h}: edge {k} of cell {i} has no twin: {:?} {:?} / cell {j}: {:?} {:?}",
                                    c.vertices, c.labels, other.vertices, other.labels
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn graded_cells_tile_and_only_boundary_nodes_reach_the_boundary() {
        use crate::nodes::generate_graded;
        use crate::problem::{RefineBox, Refinement};
        let d = Domain::rectangle([0.0, 6.0], [-1.0, 1.0]).unwrap();
        let r = Refinement {
            boxes: vec![
                RefineBox { x: [0.0, 6.0], y: [-1.0, -0.9], spacing: 0.05 },
                RefineBox { x: [2.0, 2.5], y: [0.0, 0.5], spacing: 0.02 },
            ],
        };
        for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.4, seed: 3 }] {
            let nodes =
                generate_graded(&d, 0.2, layout, |lo, hi| r.min_spacing_in(0.2, lo, hi)).unwrap();
            let cells = build_cells(&d, &nodes).unwrap();
            assert!((total_area(&cells) - 12.0).abs() < 1e-11, "{layout:?}");
            for (i, c) in cells.iter().enumerate() {
                assert!(c.area() > 0.0);
                if c.labels.iter().any(|l| matches!(l, EdgeLabel::Boundary(_))) {
                    assert!(!nodes.edges[i].is_empty(), "interior node {i} reaches the boundary");
                }
            }
        }
    }

    #[test]
    fn jittered_cells_tile_and_pair_up() {
        let d = Domain::rectangle([0.0, 3.0], [-1.0, 1.0]).unwrap();
        let nodes = generate(&d, 0.2, Layout::Jittered { amplitude: 0.4, seed: 11 }).unwrap();
        let cells = build_cells(&d, &nodes).unwrap();
        assert!((total_area(&cells) - 6.0).abs() < 1e-11);
        // Every neighbour edge has a twin of the same length.
        for (i, c) in cells.iter().enumerate() {
            for (k, l) in c.labels.iter().enumerate() {
                if let EdgeLabel::Neighbour(j) = *l {
                    let (a, b) = c.edge(k);
                    let len = dist2(a, b).sqrt();
                    let other = &cells[j as usize];
                    let twin = other
                        .labels
                        .iter()
                        .position(|&m| m == EdgeLabel::Neighbour(i as u32))
                        .expect("twin edge");
                    let (p, q) = other.edge(twin);
                    assert!((dist2(p, q).sqrt() - len).abs() < 1e-9);
                }
            }
        }
    }
}
