//! Subdomains `Ω_s`: the Voronoi cells of the nodes clipped to the domain, which tile it.
//!
//! Tiling gives two exact properties (method.md §3.5): interior-face contributions cancel
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

/// A convex cell polygon: vertex `k` starts edge `k`, whose far side is `labels[k]`.
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
/// Each cell starts as the domain polygon and is clipped by the bisector half-planes of the
/// nearby nodes, nearest first, until every node closer than twice the cell's radius has been
/// used (the security-radius criterion), so the result is exact.
///
/// # Errors
/// [`CellError::EmptyCell`] when a node's cell vanishes (duplicate or outside nodes).
pub fn build_cells(domain: &Domain, nodes: &Nodes) -> Result<Vec<Cell>, CellError> {
    let h = nodes.spacing.iter().fold(0.0f64, |m, &v| m.max(v));
    let grid = NeighbourGrid::new(&nodes.points, 2.0 * h);
    let start = Cell {
        vertices: domain.vertices().to_vec(),
        labels: (0..domain.edge_count()).map(|k| EdgeLabel::Boundary(k as u32)).collect(),
    };
    (0..nodes.len())
        .into_par_iter()
        .map_init(Vec::new, |scratch, i| voronoi_cell(i, nodes, &grid, &start, scratch))
        .collect()
}

fn voronoi_cell(
    i: usize,
    nodes: &Nodes,
    grid: &NeighbourGrid,
    start: &Cell,
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
        let reach = cell.vertices.iter().map(|v| dist2(*v, x)).fold(0.0f64, f64::max).sqrt();
        if 2.0 * reach <= radius {
            return Ok(cell);
        }
        radius = 2.0 * reach * (1.0 + 1e-9);
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
