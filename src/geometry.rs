//! Stage 1a: the domain — a convex polygon whose edges carry names for boundary conditions.

/// A point or vector in the plane.
pub type Point = [f64; 2];

/// Errors in the description of the domain or its node layout.
#[derive(Debug, thiserror::Error)]
pub enum GeometryError {
    /// Fewer than three vertices.
    #[error("the domain polygon needs at least 3 vertices, got {count}")]
    TooFewVertices {
        /// Number of vertices given.
        count: usize,
    },
    /// The polygon is not convex and counter-clockwise (or has a zero-length edge).
    #[error(
        "the domain polygon must be convex with counter-clockwise vertices; vertex {vertex} turns the wrong way (cross product {cross:.3e})"
    )]
    NotConvex {
        /// Vertex index where the turn is wrong.
        vertex: usize,
        /// The cross product of the adjacent edges there.
        cross: f64,
    },
    /// Edge names are not one per edge, or not unique.
    #[error("edge names: {reason}")]
    EdgeNames {
        /// What is wrong.
        reason: String,
    },
    /// The node spacing does not fit the domain.
    #[error("node spacing {spacing} is not usable for a domain of size {size:.4e}: {reason}")]
    Spacing {
        /// The spacing requested.
        spacing: f64,
        /// The domain's smallest extent.
        size: f64,
        /// Why.
        reason: &'static str,
    },
}

/// A convex polygon with counter-clockwise vertices; edge `k` runs from vertex `k` to
/// vertex `k+1` (cyclically) and has a name used by boundary conditions.
#[derive(Clone, Debug, PartialEq)]
pub struct Domain {
    vertices: Vec<Point>,
    edge_names: Vec<String>,
}

impl Domain {
    /// A polygon from its vertices (counter-clockwise, convex) and one name per edge.
    ///
    /// # Errors
    /// [`GeometryError`] when the polygon is not convex and counter-clockwise or the names do
    /// not match the edges.
    pub fn polygon(vertices: Vec<Point>, edge_names: Vec<String>) -> Result<Self, GeometryError> {
        let n = vertices.len();
        if n < 3 {
            return Err(GeometryError::TooFewVertices { count: n });
        }
        if edge_names.len() != n {
            return Err(GeometryError::EdgeNames {
                reason: format!("{} names for {} edges", edge_names.len(), n),
            });
        }
        for (i, name) in edge_names.iter().enumerate() {
            if name.is_empty() || edge_names[..i].contains(name) {
                return Err(GeometryError::EdgeNames {
                    reason: format!("edge {i} has an empty or repeated name {name:?}"),
                });
            }
        }
        let scale = vertices.iter().flat_map(|p| p.iter()).fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 0..n {
            let a = vertices[(k + n - 1) % n];
            let b = vertices[k];
            let c = vertices[(k + 1) % n];
            let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
            if cross <= 1e-12 * scale * scale.max(1e-300) {
                return Err(GeometryError::NotConvex { vertex: k, cross });
            }
        }
        Ok(Self { vertices, edge_names })
    }

    /// The axis-aligned rectangle `[x0, x1] × [y0, y1]` with edges named
    /// `bottom`, `right`, `top`, `left`.
    ///
    /// # Errors
    /// [`GeometryError::NotConvex`] when `x1 ≤ x0` or `y1 ≤ y0`.
    pub fn rectangle(x: [f64; 2], y: [f64; 2]) -> Result<Self, GeometryError> {
        Self::polygon(
            vec![[x[0], y[0]], [x[1], y[0]], [x[1], y[1]], [x[0], y[1]]],
            ["bottom", "right", "top", "left"].iter().map(|s| s.to_string()).collect(),
        )
    }

    /// Vertices, counter-clockwise.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }

    /// Number of edges (= vertices).
    pub fn edge_count(&self) -> usize {
        self.vertices.len()
    }

    /// Edge names, in edge order.
    pub fn edge_names(&self) -> &[String] {
        &self.edge_names
    }

    /// Index of the edge with this name.
    pub fn edge_index(&self, name: &str) -> Option<usize> {
        self.edge_names.iter().position(|n| n == name)
    }

    /// End points `(a, b)` of edge `k`.
    pub fn edge(&self, k: usize) -> (Point, Point) {
        (self.vertices[k], self.vertices[(k + 1) % self.vertices.len()])
    }

    /// Outward unit normal of edge `k`.
    pub fn outward_normal(&self, k: usize) -> Point {
        let (a, b) = self.edge(k);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        [dy / len, -dx / len]
    }

    /// Axis-aligned bounding box `([xmin, ymin], [xmax, ymax])`.
    pub fn bounding_box(&self) -> (Point, Point) {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in &self.vertices {
            for d in 0..2 {
                lo[d] = lo[d].min(p[d]);
                hi[d] = hi[d].max(p[d]);
            }
        }
        (lo, hi)
    }

    /// Area (shoelace formula).
    pub fn area(&self) -> f64 {
        let n = self.vertices.len();
        0.5 * (0..n)
            .map(|k| {
                let (a, b) = self.edge(k);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
    }

    /// Signed distance of `p` to the line of edge `k` (negative inside).
    pub fn edge_distance(&self, k: usize, p: Point) -> f64 {
        let (a, _) = self.edge(k);
        let n = self.outward_normal(k);
        (p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1]
    }

    /// Parameter `t ∈ [0, 1]` of the projection of `p` on edge `k` (`0` at its first vertex).
    pub fn edge_parameter(&self, k: usize, p: Point) -> f64 {
        let (a, b) = self.edge(k);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)
    }

    /// Whether the domain is an axis-aligned rectangle built by [`Self::rectangle`] order.
    pub fn as_rectangle(&self) -> Option<([f64; 2], [f64; 2])> {
        let v = &self.vertices;
        (v.len() == 4
            && v[0][1] == v[1][1]
            && v[1][0] == v[2][0]
            && v[2][1] == v[3][1]
            && v[3][0] == v[0][0]
            && v[0][0] < v[1][0])
            .then(|| ([v[0][0], v[1][0]], [v[0][1], v[2][1]]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangle_normals_and_area() {
        let d = Domain::rectangle([0.0, 2.0], [0.0, 1.0]).unwrap();
        assert_eq!(d.outward_normal(0), [0.0, -1.0]);
        assert_eq!(d.outward_normal(1), [1.0, 0.0]);
        assert!((d.area() - 2.0).abs() < 1e-15);
        assert!(d.as_rectangle().is_some());
    }

    #[test]
    fn clockwise_polygon_is_rejected() {
        let e = Domain::polygon(
            vec![[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]],
            vec!["a".into(), "b".into(), "c".into()],
        );
        assert!(matches!(e, Err(GeometryError::NotConvex { .. })));
    }
}
