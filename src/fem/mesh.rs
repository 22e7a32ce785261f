//! The structured Q2 mesh of a rectangle: node grid, element connectivity, nodal strains.

use super::element::{self, NODES, REFERENCE_NODES};
use crate::geometry::{Domain, Point};
use crate::nodes::{EdgeSet, Nodes};

/// A structured mesh of `nx × ny` biquadratic elements on an axis-aligned rectangle. Its
/// `(2 nx + 1) × (2 ny + 1)` nodes are numbered row by row from the lower-left corner.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Elements along x.
    pub nx: usize,
    /// Elements along y.
    pub ny: usize,
    /// Lower-left corner.
    pub origin: Point,
    /// Element size `(h_x, h_y)`.
    pub element_size: [f64; 2],
    /// Node indices of each element in local order `a = 3 j + i` (see [`element`]).
    pub elements: Vec<[u32; NODES]>,
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
        Self {
            nx,
            ny,
            origin: [x[0], y[0]],
            element_size: [(x[1] - x[0]) / nx as f64, (y[1] - y[0]) / ny as f64],
            elements,
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        (2 * self.nx + 1) * (2 * self.ny + 1)
    }

    /// The nodes with boundary tags of `domain` (the rectangle this mesh covers). The local
    /// spacing recorded is the node spacing, half the element size.
    pub fn nodes(&self, domain: &Domain) -> Nodes {
        let (cols, rows) = (2 * self.nx + 1, 2 * self.ny + 1);
        let (lo, hi) = domain.bounding_box();
        let coord = |k: usize, n: usize, a: f64, b: f64| {
            if k == n { b } else { a + (b - a) * k as f64 / n as f64 }
        };
        let points: Vec<Point> = (0..rows)
            .flat_map(|j| (0..cols).map(move |i| (i, j)))
            .map(|(i, j)| [coord(i, cols - 1, lo[0], hi[0]), coord(j, rows - 1, lo[1], hi[1])])
            .collect();
        let tol = 1e-9 * self.element_size[0].min(self.element_size[1]);
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
        let h = 0.5 * self.element_size[0].max(self.element_size[1]);
        Nodes { spacing: vec![h; points.len()], points, edges }
    }

    /// The element's interleaved nodal values taken from a global vector `u` (2 per node).
    pub fn gather(&self, element: usize, u: &[f64]) -> [f64; 2 * NODES] {
        let e = &self.elements[element];
        std::array::from_fn(|k| u[2 * e[k / 2] as usize + k % 2])
    }

    /// Position of reference point `(ξ, η)` of `element`.
    pub fn point(&self, element: usize, xi: f64, eta: f64) -> Point {
        let (ex, ey) = (element % self.nx, element / self.nx);
        let [hx, hy] = self.element_size;
        [
            self.origin[0] + hx * (ex as f64 + 0.5 * (1.0 + xi)),
            self.origin[1] + hy * (ey as f64 + 0.5 * (1.0 + eta)),
        ]
    }

    /// Strain `(ε_xx, ε_yy, γ_xy)` of the displacement `u` at `(ξ, η)` of `element`.
    pub fn strain(&self, element: usize, xi: f64, eta: f64, u: &[f64]) -> [f64; 3] {
        element::strain(self.element_size, xi, eta, &self.gather(element, u))
    }

    /// Nodal strains: at each node, the average of the strains of the elements that share it
    /// evaluated at that node (the element strains jump across element edges; the average is
    /// what `stress.csv` reports).
    pub fn nodal_strains(&self, u: &[f64]) -> Vec<[f64; 3]> {
        let n = self.node_count();
        let mut sum = vec![[0.0; 3]; n];
        let mut count = vec![0u32; n];
        for (k, e) in self.elements.iter().enumerate() {
            let u_e = self.gather(k, u);
            for (a, &node) in e.iter().enumerate() {
                let (xi, eta) = (REFERENCE_NODES[a % 3], REFERENCE_NODES[a / 3]);
                let s = element::strain(self.element_size, xi, eta, &u_e);
                let i = node as usize;
                for c in 0..3 {
                    sum[i][c] += s[c];
                }
                count[i] += 1;
            }
        }
        sum.iter().zip(&count).map(|(s, &c)| s.map(|v| v / f64::from(c.max(1)))).collect()
    }

    /// The element edges on the domain edge `k` of `domain`, each as its three node indices in
    /// order along the edge (end, middle, end) with its length.
    pub fn boundary_segments(
        &self,
        domain: &Domain,
        nodes: &Nodes,
        k: usize,
    ) -> Vec<([u32; 3], f64)> {
        // Local node triples of the four element sides (bottom, right, top, left).
        const SIDES: [[usize; 3]; 4] = [[0, 1, 2], [2, 5, 8], [8, 7, 6], [6, 3, 0]];
        let mut out = Vec::new();
        for e in &self.elements {
            for side in SIDES {
                let ids = side.map(|a| e[a]);
                if ids.iter().all(|&i| nodes.edges[i as usize].contains(k)) {
                    let (p, q) = (nodes.points[ids[0] as usize], nodes.points[ids[2] as usize]);
                    let (tp, tq) = (domain.edge_parameter(k, p), domain.edge_parameter(k, q));
                    let ids = if tp <= tq { ids } else { [ids[2], ids[1], ids[0]] };
                    out.push((ids, (q[0] - p[0]).hypot(q[1] - p[1])));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn connectivity_matches_node_positions() {
        let domain = Domain::rectangle([1.0, 4.0], [0.0, 1.0]).unwrap();
        let mesh = Mesh::rectangle([1.0, 4.0], [0.0, 1.0], 0.5);
        assert_eq!((mesh.nx, mesh.ny), (6, 2));
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
}
