//! The FE mesh: the structured Q2 grid of a rectangle, or a general mesh of isoparametric
//! Q2 quadrilaterals and quadratic triangles (from a Gmsh file); node grid or coordinates,
//! element connectivity, boundary sides, nodal strains.

use super::FemError;
use super::element::{self, NODES, Shape};
use crate::geometry::{Domain, Point};
use crate::nodes::{EdgeSet, Nodes};
use crate::problem::RefineBox;
use crate::problem::gmsh;
use crate::weak_form::gauss_legendre;

/// The structured grid of `nx × ny` equal rectangles.
#[derive(Clone, Debug)]
pub struct Grid {
    /// Elements along x.
    pub nx: usize,
    /// Elements along y.
    pub ny: usize,
    /// Lower-left corner.
    pub origin: Point,
    /// Element size `(h_x, h_y)`.
    pub element_size: [f64; 2],
}

/// A mesh of quadratic elements. The structured mesh of a rectangle ([`Mesh::rectangle`]:
/// `nx × ny` biquadratic elements, `(2 nx + 1) × (2 ny + 1)` nodes numbered row by row from
/// the lower-left corner) or a general one ([`Mesh::general`]: isoparametric Q2
/// quadrilaterals and T6 triangles with given node coordinates, possibly on curved sides).
/// Elements are numbered quadrilaterals first, then triangles.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// The structured grid, if this is one.
    pub grid: Option<Grid>,
    /// Node coordinates (general meshes; empty for the grid, whose nodes
    /// [`Mesh::nodes`] places from the domain's corners).
    pub points: Vec<Point>,
    /// Node indices of each quadrilateral in local order `a = 3 j + i` (see [`element`]).
    pub elements: Vec<[u32; NODES]>,
    /// Node indices of each triangle (corners, then mid-sides; see [`element`]).
    pub triangles: Vec<[u32; 6]>,
}

/// One element of a mesh: its shape and node indices.
#[derive(Clone, Copy, Debug)]
pub struct Cell<'a> {
    /// The element shape.
    pub shape: Shape,
    /// Its node indices in local order.
    pub nodes: &'a [u32],
}

impl Mesh {
    /// Meshes the rectangle `x × y` with `round(L/h)` elements per side (at least 1), like the
    /// MFVM's structured node grid at spacing `h`: the element corners are its nodes.
    pub fn rectangle(x: [f64; 2], y: [f64; 2], h: f64) -> Self {
        let nx = ((x[1] - x[0]) / h).round().max(1.0) as usize;
        let ny = ((y[1] - y[0]) / h).round().max(1.0) as usize;
        let row = 2 * nx + 1;
        let elements = (0..ny)
            .flat_map(|ey| (0..nx).map(move |ex| (ex, ey)))
            .map(|(ex, ey)| {
                std::array::from_fn(|a| ((2 * ey + a / 3) * row + 2 * ex + a % 3) as u32)
            })
            .collect();
        let grid = Grid {
            nx,
            ny,
            origin: [x[0], y[0]],
            element_size: [(x[1] - x[0]) / nx as f64, (y[1] - y[0]) / ny as f64],
        };
        Self { grid: Some(grid), points: Vec::new(), elements, triangles: Vec::new() }
    }

    /// The graded tensor-product mesh of the rectangle `x × y` for the refinement regions
    /// `boxes`: the uniform grid of [`Mesh::rectangle`] at element size `h`, then every column
    /// (row) whose interior overlaps a box's x-range (y-range) halved until it is at most the
    /// box's spacing wide (tall). Columns and rows run across the whole rectangle, so the mesh
    /// has no hanging nodes; its straight-sided Q2 elements are a general mesh
    /// ([`Mesh::general`]), numbered row by row from the lower-left corner like the grid.
    pub fn graded(x: [f64; 2], y: [f64; 2], h: f64, boxes: &[RefineBox]) -> Self {
        let cols = breaks(x, h, boxes.iter().map(|b| (b.x, b.spacing)));
        let rows = breaks(y, h, boxes.iter().map(|b| (b.y, b.spacing)));
        // The node lines: breaks and the midpoints between them.
        let lines = |b: &[f64]| -> Vec<f64> {
            let mut out = vec![b[0]];
            for w in b.windows(2) {
                out.extend([0.5 * (w[0] + w[1]), w[1]]);
            }
            out
        };
        let (xs, ys) = (lines(&cols), lines(&rows));
        let points = ys.iter().flat_map(|&y| xs.iter().map(move |&x| [x, y])).collect();
        let (nx, ny, row) = (cols.len() - 1, rows.len() - 1, xs.len());
        let elements = (0..ny)
            .flat_map(|ey| (0..nx).map(move |ex| (ex, ey)))
            .map(|(ex, ey)| {
                std::array::from_fn(|a| ((2 * ey + a / 3) * row + 2 * ex + a % 3) as u32)
            })
            .collect();
        Self { grid: None, points, elements, triangles: Vec::new() }
    }

    /// A general mesh from node coordinates and the quadrilaterals' and triangles' node
    /// indices (local orders of [`element`]; either orientation).
    ///
    /// # Errors
    /// The index of the first element whose isoparametric map is degenerate or folds (its
    /// Jacobian determinant changes sign or vanishes) or that names a node out of range.
    pub fn general(
        points: Vec<Point>,
        elements: Vec<[u32; NODES]>,
        triangles: Vec<[u32; 6]>,
    ) -> Result<Self, usize> {
        let mesh = Self { grid: None, points, elements, triangles };
        for k in 0..mesh.element_count() {
            let cell = mesh.cell(k);
            if cell.nodes.iter().any(|&i| i as usize >= mesh.points.len()) {
                return Err(k);
            }
            let (lo, hi) = element::jacobian_range(cell.shape, &mesh.coordinates(k));
            if !(lo > 0.0 || hi < 0.0) || !(lo.is_finite() && hi.is_finite()) {
                return Err(k);
            }
        }
        Ok(mesh)
    }

    /// A general mesh from a Gmsh surface's elements on `points` (their `nodes` index
    /// `points`): 9-node quadrilaterals (Gmsh's order — corners, mid-sides, centre — permuted
    /// to the local order `a = 3 j + i`) and 6-node triangles (Gmsh's order is the local one).
    ///
    /// # Errors
    /// [`FemError::ElementKind`] for an element of another kind (first order or 8-node),
    /// [`FemError::DegenerateElement`] for a folded one; both name the element's line.
    pub fn from_elements(points: Vec<Point>, elements: &[gmsh::Element]) -> Result<Self, FemError> {
        /// Local node `a = 3 j + i` ← Gmsh node (corners 0–3 counter-clockwise from (−1, −1),
        /// mid-sides 4–7 from side 0–1, centre 8).
        const FROM_GMSH: [usize; NODES] = [0, 4, 1, 7, 8, 5, 3, 6, 2];
        let (mut quads, mut triangles) = (Vec::new(), Vec::new());
        let (mut quad_lines, mut triangle_lines) = (Vec::new(), Vec::new());
        for e in elements {
            let n = |a: usize| u32::try_from(e.nodes[a]).unwrap_or(u32::MAX);
            match e.kind {
                gmsh::ElementKind::Quad9 => {
                    quads.push(FROM_GMSH.map(n));
                    quad_lines.push(e.line);
                }
                gmsh::ElementKind::Tri6 => {
                    triangles.push(std::array::from_fn(n));
                    triangle_lines.push(e.line);
                }
                kind => return Err(FemError::ElementKind { kind, line: e.line }),
            }
        }
        quad_lines.extend(triangle_lines);
        Self::general(points, quads, triangles)
            .map_err(|k| FemError::DegenerateElement { line: quad_lines[k] })
    }

    /// Number of elements.
    pub fn element_count(&self) -> usize {
        self.elements.len() + self.triangles.len()
    }

    /// Element `k`.
    pub fn cell(&self, k: usize) -> Cell<'_> {
        match k.checked_sub(self.elements.len()) {
            None => Cell { shape: Shape::Quad9, nodes: &self.elements[k] },
            Some(t) => Cell { shape: Shape::Tri6, nodes: &self.triangles[t] },
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        match &self.grid {
            Some(g) => (2 * g.nx + 1) * (2 * g.ny + 1),
            None => self.points.len(),
        }
    }

    /// The node coordinates of element `k` (general meshes).
    fn coordinates(&self, k: usize) -> Vec<Point> {
        self.cell(k).nodes.iter().map(|&i| self.points[i as usize]).collect()
    }

    /// The nodes with boundary tags of `domain` (the region this mesh covers). The local
    /// spacing recorded is the node spacing, half the element size (for a general mesh, half
    /// the longest side of the elements around the node).
    pub fn nodes(&self, domain: &Domain) -> Nodes {
        let (points, tol, spacing) = match &self.grid {
            Some(g) => {
                let (cols, rows) = (2 * g.nx + 1, 2 * g.ny + 1);
                let (lo, hi) = domain.bounding_box();
                let coord = |k: usize, n: usize, a: f64, b: f64| {
                    if k == n { b } else { a + (b - a) * k as f64 / n as f64 }
                };
                let points: Vec<Point> = (0..rows)
                    .flat_map(|j| (0..cols).map(move |i| (i, j)))
                    .map(|(i, j)| {
                        [coord(i, cols - 1, lo[0], hi[0]), coord(j, rows - 1, lo[1], hi[1])]
                    })
                    .collect();
                let tol = 1e-9 * g.element_size[0].min(g.element_size[1]);
                let h = 0.5 * g.element_size[0].max(g.element_size[1]);
                let n = points.len();
                (points, tol, vec![h; n])
            }
            None => {
                let mut spacing = vec![0.0f64; self.points.len()];
                for k in 0..self.element_count() {
                    let cell = self.cell(k);
                    let longest = cell
                        .shape
                        .sides()
                        .iter()
                        .map(|s| {
                            let (p, q) = (
                                self.points[cell.nodes[s[0]] as usize],
                                self.points[cell.nodes[s[2]] as usize],
                            );
                            (q[0] - p[0]).hypot(q[1] - p[1])
                        })
                        .fold(0.0, f64::max);
                    for &i in cell.nodes {
                        spacing[i as usize] = spacing[i as usize].max(0.5 * longest);
                    }
                }
                let smallest =
                    spacing.iter().copied().filter(|&h| h > 0.0).fold(f64::INFINITY, f64::min);
                (self.points.clone(), 1e-9 * smallest, spacing)
            }
        };
        let edges = points
            .iter()
            .map(|p| {
                let mut set = EdgeSet::default();
                for k in 0..domain.edge_count() {
                    let t = domain.edge_parameter(k, *p);
                    if domain.edge_distance(k, *p).abs() <= tol
                        && (-1e-12..=1.0 + 1e-12).contains(&t)
                    {
                        set.insert(k);
                    }
                }
                set
            })
            .collect();
        Nodes { spacing, points, edges }
    }

    /// The element's interleaved nodal values taken from a global vector `u` (2 per node;
    /// zero past its node count).
    pub fn gather(&self, element: usize, u: &[f64]) -> [f64; 2 * NODES] {
        let e = self.cell(element).nodes;
        std::array::from_fn(
            |k| if k / 2 < e.len() { u[2 * e[k / 2] as usize + k % 2] } else { 0.0 },
        )
    }

    /// Position of reference point `(ξ, η)` of `element`.
    pub fn point(&self, element: usize, xi: f64, eta: f64) -> Point {
        match &self.grid {
            Some(g) => {
                let (ex, ey) = (element % g.nx, element / g.nx);
                let [hx, hy] = g.element_size;
                [
                    g.origin[0] + hx * (ex as f64 + 0.5 * (1.0 + xi)),
                    g.origin[1] + hy * (ey as f64 + 0.5 * (1.0 + eta)),
                ]
            }
            None => {
                let cell = self.cell(element);
                let [n, _, _] = cell.shape.functions(xi, eta);
                cell.nodes.iter().zip(n).fold([0.0, 0.0], |acc, (&i, n)| {
                    let x = self.points[i as usize];
                    [acc[0] + n * x[0], acc[1] + n * x[1]]
                })
            }
        }
    }

    /// `|det J|` of `element`'s map at `(ξ, η)` (the area factor of its quadrature).
    pub fn area_factor(&self, element: usize, xi: f64, eta: f64) -> f64 {
        match &self.grid {
            Some(g) => 0.25 * g.element_size[0] * g.element_size[1],
            None => {
                let shape = self.cell(element).shape;
                element::iso_derivatives(shape, &self.coordinates(element), xi, eta).2.abs()
            }
        }
    }

    /// Strain `(ε_xx, ε_yy, γ_xy)` of the displacement `u` at `(ξ, η)` of `element`.
    pub fn strain(&self, element: usize, xi: f64, eta: f64, u: &[f64]) -> [f64; 3] {
        let u_e = self.gather(element, u);
        match &self.grid {
            Some(g) => element::strain(g.element_size, xi, eta, &u_e),
            None => {
                let shape = self.cell(element).shape;
                element::iso_strain(shape, &self.coordinates(element), xi, eta, &u_e)
            }
        }
    }

    /// The element stiffness `K_e` of `element` (one matrix serves every element of the grid).
    pub fn stiffness(
        &self,
        element: usize,
        d: &crate::material::Constitutive,
    ) -> [[f64; 2 * NODES]; 2 * NODES] {
        match &self.grid {
            Some(g) => element::stiffness(g.element_size, d),
            None => {
                let shape = self.cell(element).shape;
                element::iso_stiffness(shape, &self.coordinates(element), d)
            }
        }
    }

    /// Nodal strains: at each node, the average of the strains of the elements that share it
    /// evaluated at that node (the element strains jump across element edges; the average is
    /// what `stress.csv` reports).
    pub fn nodal_strains(&self, u: &[f64]) -> Vec<[f64; 3]> {
        let n = self.node_count();
        let mut sum = vec![[0.0; 3]; n];
        let mut count = vec![0u32; n];
        for k in 0..self.element_count() {
            let cell = self.cell(k);
            for (a, &node) in cell.nodes.iter().enumerate() {
                let [xi, eta] = cell.shape.reference_node(a);
                let s = self.strain(k, xi, eta, u);
                let i = node as usize;
                for c in 0..3 {
                    sum[i][c] += s[c];
                }
                count[i] += 1;
            }
        }
        sum.iter().zip(&count).map(|(s, &c)| s.map(|v| v / f64::from(c.max(1)))).collect()
    }

    /// The element sides on the domain edge `k` of `domain`, each as its three node indices in
    /// order along the edge (end, middle, end) with its length (for a curved side, the length
    /// of its isoparametric arc).
    pub fn boundary_segments(
        &self,
        domain: &Domain,
        nodes: &Nodes,
        k: usize,
    ) -> Vec<([u32; 3], f64)> {
        let mut out = Vec::new();
        for e in 0..self.element_count() {
            let cell = self.cell(e);
            for side in cell.shape.sides() {
                let ids = side.map(|a| cell.nodes[a]);
                if ids.iter().all(|&i| nodes.edges[i as usize].contains(k)) {
                    let (p, q) = (nodes.points[ids[0] as usize], nodes.points[ids[2] as usize]);
                    let (tp, tq) = (domain.edge_parameter(k, p), domain.edge_parameter(k, q));
                    let ids = if tp <= tq { ids } else { [ids[2], ids[1], ids[0]] };
                    let length = match self.grid {
                        Some(_) => (q[0] - p[0]).hypot(q[1] - p[1]),
                        None => side_length(ids.map(|i| nodes.points[i as usize])),
                    };
                    out.push((ids, length));
                }
            }
        }
        out
    }
}

/// The element breaks of the interval `[a, b]`: `round((b − a)/h)` equal intervals (at least
/// one), then every interval whose interior overlaps a region `(range, spacing)` halved until
/// it is at most `spacing` long. The ends are `a` and `b` exactly.
fn breaks(
    [a, b]: [f64; 2],
    h: f64,
    regions: impl Iterator<Item = ([f64; 2], f64)> + Clone,
) -> Vec<f64> {
    let n = ((b - a) / h).round().max(1.0) as usize;
    let mut out: Vec<f64> =
        (0..=n).map(|k| if k == n { b } else { a + (b - a) * k as f64 / n as f64 }).collect();
    let tol = 1e-9 * (b - a);
    loop {
        let mut next = vec![out[0]];
        for w in out.windows(2) {
            let (lo, hi) = (w[0], w[1]);
            let split = regions
                .clone()
                .any(|(r, s)| r[0] < hi - tol && r[1] > lo + tol && hi - lo > s * (1.0 + 1e-9));
            if split {
                next.push(0.5 * (lo + hi));
            }
            next.push(hi);
        }
        if next.len() == out.len() {
            return out;
        }
        out = next;
    }
}

/// The position, the tangent `dx/ds` and the Lagrange values at `s ∈ [−1, 1]` of the quadratic
/// side through `x` (end, middle, end).
pub fn side_map(x: [Point; 3], s: f64) -> (Point, Point, [f64; 3]) {
    let (n, dn) = (element::lagrange(s), element::lagrange_derivative(s));
    let mut p = [0.0; 2];
    let mut t = [0.0; 2];
    for a in 0..3 {
        for d in 0..2 {
            p[d] += n[a] * x[a][d];
            t[d] += dn[a] * x[a][d];
        }
    }
    (p, t, n)
}

/// Length of the quadratic side through `x` (5-point Gauss; exact for a straight side).
fn side_length(x: [Point; 3]) -> f64 {
    let (xs, ws) = gauss_legendre(5);
    xs.iter().zip(ws).map(|(&s, &w)| w * side_map(x, s).1[0].hypot(side_map(x, s).1[1])).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::REFERENCE_NODES;

    #[test]
    fn connectivity_matches_node_positions() {
        let domain = Domain::rectangle([1.0, 4.0], [0.0, 1.0]).unwrap();
        let mesh = Mesh::rectangle([1.0, 4.0], [0.0, 1.0], 0.5);
        let g = mesh.grid.as_ref().unwrap();
        assert_eq!((g.nx, g.ny), (6, 2));
        let nodes = mesh.nodes(&domain);
        assert_eq!(nodes.len(), mesh.node_count());
        for (k, e) in mesh.elements.iter().enumerate() {
            for (a, &i) in e.iter().enumerate() {
                let p = mesh.point(k, REFERENCE_NODES[a % 3], REFERENCE_NODES[a / 3]);
                let q = nodes.points[i as usize];
                assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
            }
        }
        // Bottom edge: 6 element sides, 13 nodes.
        assert_eq!(mesh.boundary_segments(&domain, &nodes, 0).len(), 6);
        assert_eq!((0..nodes.len()).filter(|&i| nodes.edges[i].contains(0)).count(), 13);
    }
    #[test]
    fn a_graded_grid_halves_the_columns_and_rows_through_a_box() {
        // 4 × 2 elements of size 1; a box over element (1, 0) asking for 0.5: column 1 and
        // row 0 are halved (5 × 3 elements), then a box inside the new column (x ∈ [1, 1.5])
        // asking for 0.25 halves it again (6 × 4: row 0's lower half too, y ∈ [0, 0.5]).
        let domain = Domain::rectangle([0.0, 4.0], [0.0, 2.0]).unwrap();
        let one = RefineBox { x: [1.0, 2.0], y: [0.0, 1.0], spacing: 0.5 };
        let mesh = Mesh::graded([0.0, 4.0], [0.0, 2.0], 1.0, &[one]);
        assert_eq!(mesh.element_count(), 5 * 3);
        assert_eq!(mesh.node_count(), 11 * 7);
        let two = RefineBox { x: [1.0, 1.5], y: [0.0, 0.5], spacing: 0.25 };
        let mesh = Mesh::graded([0.0, 4.0], [0.0, 2.0], 1.0, &[one, two]);
        assert_eq!(mesh.element_count(), 6 * 4);
        let nodes = mesh.nodes(&domain);
        // Every element is the rectangle of its corners, its middle nodes centred (no
        // hanging nodes: each node is shared as the straight-sided Q9's own).
        let mut area = 0.0;
        for k in 0..mesh.element_count() {
            let p: Vec<Point> =
                mesh.cell(k).nodes.iter().map(|&i| nodes.points[i as usize]).collect();
            let (w, h) = (p[2][0] - p[0][0], p[6][1] - p[0][1]);
            assert!(w > 0.0 && h > 0.0);
            assert!((p[4][0] - p[0][0] - 0.5 * w).abs() < 1e-15);
            assert!((p[4][1] - p[0][1] - 0.5 * h).abs() < 1e-15);
            area += w * h;
        }
        assert!((area - 8.0).abs() < 1e-12);
        // Bottom edge: 6 element sides, 13 nodes tagged.
        assert_eq!(mesh.boundary_segments(&domain, &nodes, 0).len(), 6);
        assert_eq!((0..nodes.len()).filter(|&i| nodes.edges[i].contains(0)).count(), 13);
    }
}
