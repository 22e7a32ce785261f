//! Stage 0: the domain — a closed loop of named boundary curves (straight segments, circular
//! arcs and polylines) with the body on its left (counter-clockwise outer boundary), and one
//! clockwise loop around each hole.
//!
//! The discretisation works on a polygonal approximation of the loop
//! ([`Domain::boundary_polygon`]): straight edges are kept, arcs are replaced by the chords
//! between their boundary nodes (which lie on the exact arc), polylines (a physical curve of a
//! Gmsh mesh: the chords through its nodes) are kept as they are. The area lost to the chords
//! is `O(h²)` per unit arc length; the Kirsch and Hertz validation cases
//! (`tests/validation/kirsch.rs`, `hertz.rs`, `gmsh.rs`) run on such boundaries and converge.

use std::f64::consts::PI;
use std::sync::Arc;

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
    /// A boundary loop of curves that is not closed, not counter-clockwise, or degenerate.
    #[error("boundary curve {curve}: {reason}")]
    Loop {
        /// Index of the offending curve.
        curve: usize,
        /// What is wrong.
        reason: String,
    },
    /// A hole (a boundary loop after the first) that is not inside the body, touches or
    /// crosses another loop, or runs the wrong way.
    #[error("hole {hole}: {reason}")]
    Hole {
        /// Index of the hole (0 for the first loop after the outer one).
        hole: usize,
        /// What is wrong.
        reason: String,
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

/// One piece of the boundary loop (one named edge).
#[derive(Clone, Debug, PartialEq)]
pub enum Curve {
    /// The straight segment from `a` to `b`.
    Segment {
        /// Start.
        a: Point,
        /// End.
        b: Point,
    },
    /// The circular arc of `radius` about `center` from polar angle `start` over `sweep`
    /// radians (positive: counter-clockwise, the body inside the circle; negative: clockwise,
    /// the body outside it, as around a hole). `|sweep| = 2π` is a full circle.
    Arc {
        /// Centre.
        center: Point,
        /// Radius (> 0).
        radius: f64,
        /// Polar angle of the start point.
        start: f64,
        /// Signed angle swept.
        sweep: f64,
    },
    /// The chain of straight pieces through `points` (at least two, consecutive points
    /// distinct), parametrised by arc length: a curve of a mesh, given by its boundary nodes.
    /// Its boundary nodes and the vertices of its polygonal approximation are its points,
    /// whatever the spacing.
    Polyline {
        /// The points, in order.
        points: Arc<[Point]>,
    },
}

/// The piece of a polyline nearest to `p`: `(index, u, q)` with `u ∈ [0, 1]` the position
/// along the piece and `q` the nearest point (an end point exactly when `u` is 0 or 1).
fn nearest_piece(points: &[Point], p: Point) -> (usize, f64, Point) {
    let mut best = (0, 0.0, points[0], f64::INFINITY);
    for (i, w) in points.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let u = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
        let q = if u == 0.0 {
            a
        } else if u == 1.0 {
            b
        } else {
            [a[0] + u * dx, a[1] + u * dy]
        };
        let d = (p[0] - q[0]).hypot(p[1] - q[1]);
        if d < best.3 {
            best = (i, u, q, d);
        }
    }
    (best.0, best.1, best.2)
}

/// Outward unit normal (body on the left) of the straight piece from `a` to `b`.
fn piece_normal(a: Point, b: Point) -> Point {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len = dx.hypot(dy);
    [dy / len, -dx / len]
}

/// Lengths of the pieces of a polyline.
fn piece_lengths(points: &[Point]) -> impl Iterator<Item = f64> + '_ {
    points.windows(2).map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
}

impl Curve {
    /// The arc from `from` to `to` about `center`, turning counter-clockwise (`ccw`) or
    /// clockwise; `from == to` gives the full circle.
    pub fn arc_between(from: Point, to: Point, center: Point, ccw: bool) -> Self {
        let radius = (from[0] - center[0]).hypot(from[1] - center[1]);
        let start = (from[1] - center[1]).atan2(from[0] - center[0]);
        let end = (to[1] - center[1]).atan2(to[0] - center[0]);
        let mut sweep = if ccw {
            (end - start).rem_euclid(2.0 * PI)
        } else {
            -(start - end).rem_euclid(2.0 * PI)
        };
        if sweep.abs() < 1e-12 {
            sweep = if ccw { 2.0 * PI } else { -2.0 * PI };
        }
        Curve::Arc { center, radius, start, sweep }
    }

    /// The same curve run the other way (start and end swapped; an arc's sweep negated).
    pub fn reversed(&self) -> Self {
        match *self {
            Curve::Segment { a, b } => Curve::Segment { a: b, b: a },
            Curve::Arc { center, radius, start, sweep } => {
                Curve::Arc { center, radius, start: start + sweep, sweep: -sweep }
            }
            Curve::Polyline { ref points } => {
                Curve::Polyline { points: points.iter().rev().copied().collect() }
            }
        }
    }

    /// Whether this is a straight segment.
    pub fn is_straight(&self) -> bool {
        matches!(self, Curve::Segment { .. })
    }

    /// The point at parameter `t ∈ [0, 1]` (proportional to arc length).
    pub fn point_at(&self, t: f64) -> Point {
        match *self {
            Curve::Segment { a, b } => [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
            Curve::Arc { center, radius, start, sweep } => {
                let (s, c) = (start + t * sweep).sin_cos();
                [center[0] + radius * c, center[1] + radius * s]
            }
            Curve::Polyline { ref points } => {
                // Beyond the ends along the end pieces.
                let m = points.len() - 1;
                let mut s = t * self.length();
                for (i, len) in piece_lengths(points).enumerate() {
                    if (s <= len || i == m - 1) && (s >= 0.0 || i == 0) {
                        let (a, b) = (points[i], points[i + 1]);
                        let u = s / len;
                        return [a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])];
                    }
                    s -= len;
                }
                points[m]
            }
        }
    }

    /// Start point.
    pub fn start(&self) -> Point {
        match *self {
            Curve::Segment { a, .. } => a,
            Curve::Arc { .. } => self.point_at(0.0),
            Curve::Polyline { ref points } => points[0],
        }
    }

    /// End point.
    pub fn end(&self) -> Point {
        match *self {
            Curve::Segment { b, .. } => b,
            Curve::Arc { .. } => self.point_at(1.0),
            Curve::Polyline { ref points } => points[points.len() - 1],
        }
    }

    /// Length.
    pub fn length(&self) -> f64 {
        match *self {
            Curve::Segment { a, b } => (b[0] - a[0]).hypot(b[1] - a[1]),
            Curve::Arc { radius, sweep, .. } => radius * sweep.abs(),
            Curve::Polyline { ref points } => piece_lengths(points).sum(),
        }
    }

    /// Parameter `t` of the point of the curve's line or circle closest to `p` (`0` at the
    /// start, `1` at the end; outside `[0, 1]` beyond the ends; for an arc the angular
    /// position measured in the sweep direction, beyond-the-end angles split at the middle of
    /// the missing part of the circle; for a polyline the arc length to the nearest point, on
    /// the end pieces' lines beyond the ends).
    pub fn parameter(&self, p: Point) -> f64 {
        match *self {
            Curve::Segment { a, b } => {
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)
            }
            Curve::Arc { center, start, sweep, .. } => {
                let angle = (p[1] - center[1]).atan2(p[0] - center[0]);
                let s = sweep.signum();
                let mut d = (s * (angle - start)).rem_euclid(2.0 * PI);
                let full = sweep.abs();
                if d > full + 0.5 * (2.0 * PI - full) {
                    d -= 2.0 * PI;
                }
                d / full
            }
            Curve::Polyline { ref points } => {
                let (i, u, _) = nearest_piece(points, p);
                let m = points.len() - 1;
                let lengths: Vec<f64> = piece_lengths(points).collect();
                let total: f64 = lengths.iter().sum();
                let before: f64 = lengths[..i].iter().sum();
                let (a, b) = (points[i], points[i + 1]);
                let along = |a: Point, b: Point| {
                    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                    ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)
                };
                // Unclamped on the end pieces, so that the parameter leaves [0, 1] there.
                let u =
                    if (i == 0 && u == 0.0) || (i == m - 1 && u == 1.0) { along(a, b) } else { u };
                (before + u * lengths[i]) / total
            }
        }
    }

    /// Outward unit normal (the body lies on the curve's left) at the curve point nearest `p`.
    pub fn outward_normal_at(&self, p: Point) -> Point {
        match *self {
            Curve::Segment { a, b } => {
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let len = dx.hypot(dy);
                [dy / len, -dx / len]
            }
            Curve::Arc { center, radius, sweep, .. } => {
                let q = self.point_at(self.parameter(p).clamp(0.0, 1.0));
                let s = sweep.signum();
                [s * (q[0] - center[0]) / radius, s * (q[1] - center[1]) / radius]
            }
            Curve::Polyline { ref points } => {
                // At an inner vertex the mean of the two pieces' normals (the radial direction
                // for a regular polygon inscribed in a circle).
                let (i, u, _) = nearest_piece(points, p);
                let n = piece_normal(points[i], points[i + 1]);
                // (Within round-off of the vertex: 1e-9 of the piece.)
                let other = if u <= 1e-9 && i > 0 {
                    Some(piece_normal(points[i - 1], points[i]))
                } else if u >= 1.0 - 1e-9 && i + 2 < points.len() {
                    Some(piece_normal(points[i + 1], points[i + 2]))
                } else {
                    None
                };
                match other {
                    Some(m) => {
                        let s = [n[0] + m[0], n[1] + m[1]];
                        let len = s[0].hypot(s[1]);
                        if len > 1e-12 { [s[0] / len, s[1] / len] } else { n }
                    }
                    None => n,
                }
            }
        }
    }

    /// Signed distance of `p` to the curve's supporting line or circle (negative on the
    /// body's side); for a polyline the distance to its nearest point (on the end pieces'
    /// lines beyond the ends), signed by the outward normal there.
    pub fn signed_distance(&self, p: Point) -> f64 {
        match *self {
            Curve::Segment { a, .. } => {
                let n = self.outward_normal_at(p);
                (p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1]
            }
            Curve::Arc { center, radius, sweep, .. } => {
                sweep.signum() * ((p[0] - center[0]).hypot(p[1] - center[1]) - radius)
            }
            Curve::Polyline { ref points } => {
                let (i, u, q) = nearest_piece(points, p);
                let m = points.len() - 1;
                if (i == 0 && u == 0.0) || (i == m - 1 && u == 1.0) {
                    let n = piece_normal(points[i], points[i + 1]);
                    let a = points[i];
                    return (p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1];
                }
                let n = self.outward_normal_at(p);
                let d = (p[0] - q[0]).hypot(p[1] - q[1]);
                if (p[0] - q[0]) * n[0] + (p[1] - q[1]) * n[1] < 0.0 { -d } else { d }
            }
        }
    }

    /// Distance of `p` to the curve piece itself (ends included).
    pub fn distance(&self, p: Point) -> f64 {
        let t = self.parameter(p);
        if (0.0..=1.0).contains(&t) {
            self.signed_distance(p).abs()
        } else {
            let (a, b) = (self.start(), self.end());
            (p[0] - a[0]).hypot(p[1] - a[1]).min((p[0] - b[0]).hypot(p[1] - b[1]))
        }
    }

    /// Number of intervals the curve is divided into at nominal spacing `h` (boundary nodes
    /// and the chords of the polygonal approximation): `round(length / h)`, at least 1 for a
    /// segment and at least one per 45° of an arc; a polyline's pieces, whatever `h`.
    pub fn divisions(&self, h: f64) -> usize {
        let n = (self.length() / h).round().max(1.0) as usize;
        match *self {
            Curve::Segment { .. } => n,
            Curve::Arc { sweep, .. } => n.max((sweep.abs() / (0.25 * PI)).ceil() as usize),
            Curve::Polyline { ref points } => points.len() - 1,
        }
    }

    /// The `divisions(h) + 1` points dividing the curve at nominal spacing `h`, start and end
    /// included: equally spaced along a segment or an arc (`point_at(i / n)`), a polyline's
    /// own points.
    pub fn division_points(&self, h: f64) -> Vec<Point> {
        match self {
            Curve::Polyline { points } => points.to_vec(),
            _ => {
                let n = self.divisions(h);
                (0..=n).map(|i| self.point_at(i as f64 / n as f64)).collect()
            }
        }
    }

    /// Crossings of the ray `{p + s e_x : s > 0}` with the curve, counted with the half-open
    /// rule (a piece counts when one end is above `p_y` and the other is not), for the
    /// even–odd inside test.
    fn ray_crossings(&self, p: Point) -> usize {
        let crosses = |a: Point, b: Point, x_at: &dyn Fn() -> f64| {
            usize::from((a[1] > p[1]) != (b[1] > p[1]) && x_at() > p[0])
        };
        match *self {
            Curve::Segment { a, b } => {
                crosses(a, b, &|| a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]))
            }
            Curve::Arc { center, radius, start, sweep } => {
                // Split at the circle's top and bottom so each piece is monotone in y.
                let mut cuts = vec![0.0];
                for k in -4..=4 {
                    let a = 0.5 * PI + k as f64 * PI;
                    let t = (a - start) / sweep;
                    if t > 0.0 && t < 1.0 {
                        cuts.push(t);
                    }
                }
                cuts.push(1.0);
                cuts.sort_by(f64::total_cmp);
                // A full circle ends exactly where it starts (`point_at(1)` differs from
                // `point_at(0)` by round-off, a gap a ray could pass through).
                let full = (sweep.abs() - 2.0 * PI).abs() <= 1e-12 * 2.0 * PI;
                let at = |t: f64| self.point_at(if full && t == 1.0 { 0.0 } else { t });
                cuts.windows(2)
                    .map(|w| {
                        let (a, b) = (at(w[0]), at(w[1]));
                        let mid = self.point_at(0.5 * (w[0] + w[1]));
                        let side = if mid[0] >= center[0] { 1.0 } else { -1.0 };
                        crosses(a, b, &|| {
                            let dy = p[1] - center[1];
                            center[0] + side * (radius * radius - dy * dy).max(0.0).sqrt()
                        })
                    })
                    .sum()
            }
            Curve::Polyline { ref points } => points
                .windows(2)
                .map(|w| {
                    let (a, b) = (w[0], w[1]);
                    crosses(a, b, &|| a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]))
                })
                .sum(),
        }
    }
}

/// Closed loops of named boundary curves (edges) with the body on the left: the outer loop
/// (counter-clockwise: a convex polygon, a rectangle, or any simple loop of segments and
/// circular arcs, e.g. a disk, a half-disk, a plate with a quarter hole), then one clockwise
/// loop around each hole ([`Self::from_loops`], [`Self::with_holes`]). Edge `k` is curve
/// `k`; the curves are numbered loop by loop.
#[derive(Clone, Debug, PartialEq)]
pub struct Domain {
    curves: Vec<Curve>,
    edge_names: Vec<String>,
    /// The end (exclusive) of each loop's curves in `curves`, outer loop first.
    loop_ends: Vec<usize>,
}

fn check_names(edge_names: &[String], n: usize) -> Result<(), GeometryError> {
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
    Ok(())
}

/// The curve after curve `k` along its loop, for loops ending at `loop_ends`.
fn next_in_loop(loop_ends: &[usize], k: usize) -> usize {
    let l = loop_ends.iter().position(|&e| k < e).unwrap_or(loop_ends.len() - 1);
    let start = if l == 0 { 0 } else { loop_ends[l - 1] };
    if k + 1 == loop_ends[l] { start } else { k + 1 }
}

/// The curve's part of a loop's signed area (shoelace over its chord plus an arc's circular
/// segment, or over a polyline's pieces).
fn curve_area(c: &Curve) -> f64 {
    let (a, b) = (c.start(), c.end());
    let chord = 0.5 * (a[0] * b[1] - b[0] * a[1]);
    match *c {
        Curve::Segment { .. } => chord,
        Curve::Arc { radius, sweep, .. } => {
            let th = sweep.abs();
            chord + sweep.signum() * 0.5 * radius * radius * (th - th.sin())
        }
        Curve::Polyline { ref points } => {
            points.windows(2).map(|w| 0.5 * (w[0][0] * w[1][1] - w[1][0] * w[0][1])).sum()
        }
    }
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
        check_names(&edge_names, n)?;
        for k in 0..n {
            let a = vertices[(k + n - 1) % n];
            let b = vertices[k];
            let c = vertices[(k + 1) % n];
            let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
            // The sine of the turn at b must be positive beyond round-off: relative to the
            // adjacent edges' lengths, not to the coordinates (a body far from the origin).
            let lengths = (b[0] - a[0]).hypot(b[1] - a[1]) * (c[0] - b[0]).hypot(c[1] - b[1]);
            if cross.is_nan() || cross <= 1e-12 * lengths {
                return Err(GeometryError::NotConvex { vertex: k, cross });
            }
        }
        let curves =
            (0..n).map(|k| Curve::Segment { a: vertices[k], b: vertices[(k + 1) % n] }).collect();
        Ok(Self { curves, edge_names, loop_ends: vec![n] })
    }

    /// A loop of curves, each starting where the previous one ends (the last closing on the
    /// first), enclosing the body on its left, with one name per curve. The loop may be
    /// non-convex (a hole cut into a plate's corner); it must not cross itself and its
    /// features must be several node spacings wide (not checked).
    ///
    /// # Errors
    /// [`GeometryError::Loop`] for a gap between curves, a degenerate curve or a clockwise
    /// loop; [`GeometryError::EdgeNames`] when the names do not match.
    pub fn from_curves(curves: Vec<Curve>, edge_names: Vec<String>) -> Result<Self, GeometryError> {
        Self::from_loops(vec![curves], edge_names)
    }

    /// Several loops of curves, as [`Self::from_curves`] each: the outer loop first
    /// (counter-clockwise), then one loop around each hole, clockwise (the body on the left
    /// of every curve), with one name per curve, loop by loop. Each hole must lie inside the
    /// outer loop, clear of it and of the other holes: checked on the curves' points and 64
    /// points along each segment or arc (a loop crossing another between two such points is
    /// not seen).
    ///
    /// # Errors
    /// As [`Self::from_curves`] (the loop of the offending curve); [`GeometryError::Hole`]
    /// for a hole running counter-clockwise, outside the body, touching or crossing another
    /// loop.
    pub fn from_loops(
        loops: Vec<Vec<Curve>>,
        edge_names: Vec<String>,
    ) -> Result<Self, GeometryError> {
        let mut loop_ends = Vec::with_capacity(loops.len());
        let mut curves = Vec::new();
        for l in loops {
            if l.is_empty() {
                return Err(GeometryError::Loop {
                    curve: curves.len(),
                    reason: "no curves".into(),
                });
            }
            curves.extend(l);
            loop_ends.push(curves.len());
        }
        let n = curves.len();
        if n == 0 {
            return Err(GeometryError::Loop { curve: 0, reason: "no curves".into() });
        }
        check_names(&edge_names, n)?;
        let scale = curves
            .iter()
            .flat_map(|c| [c.start(), c.end()])
            .flat_map(|p| p.into_iter())
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(curves.iter().map(Curve::length).fold(0.0, f64::max));
        for (k, c) in curves.iter().enumerate() {
            let finite = match *c {
                Curve::Segment { a, b } => a.iter().chain(&b).all(|v| v.is_finite()),
                Curve::Arc { center, radius, start, sweep } => {
                    center.iter().all(|v| v.is_finite())
                        && radius.is_finite()
                        && start.is_finite()
                        && sweep.is_finite()
                }
                Curve::Polyline { ref points } => {
                    points.len() >= 2 && points.iter().flatten().all(|v| v.is_finite())
                }
            };
            if !finite {
                return Err(GeometryError::Loop {
                    curve: k,
                    reason: "non-finite coordinates".into(),
                });
            }
            if c.length() <= 1e-12 * scale {
                return Err(GeometryError::Loop { curve: k, reason: "has zero length".into() });
            }
            if let Curve::Polyline { points } = c {
                if let Some(i) = piece_lengths(points).position(|l| l <= 1e-12 * scale) {
                    return Err(GeometryError::Loop {
                        curve: k,
                        reason: format!("piece {i} of the polyline has zero length"),
                    });
                }
            }
            if let Curve::Arc { sweep, .. } = *c {
                if sweep.abs() > 2.0 * PI * (1.0 + 1e-12) {
                    return Err(GeometryError::Loop {
                        curve: k,
                        reason: "an arc sweeps more than a full circle".into(),
                    });
                }
            }
            let next = curves[next_in_loop(&loop_ends, k)].start();
            let end = c.end();
            let gap = (end[0] - next[0]).hypot(end[1] - next[1]);
            if gap > 1e-9 * scale {
                return Err(GeometryError::Loop {
                    curve: k,
                    reason: format!(
                        "ends at ({:.6}, {:.6}) but the next curve starts at ({:.6}, {:.6})",
                        end[0], end[1], next[0], next[1]
                    ),
                });
            }
        }
        let outer = loop_ends[0];
        if outer < 3 && curves[..outer].iter().all(Curve::is_straight) {
            return Err(GeometryError::TooFewVertices { count: outer });
        }
        let domain = Self { curves, edge_names, loop_ends };
        let outer_area = domain.loop_area(0);
        if outer_area.is_nan() || outer_area <= 0.0 {
            return Err(GeometryError::Loop {
                curve: 0,
                reason: format!(
                    "the loop encloses a signed area of {outer_area:.3e}: it must run counter-clockwise around the body",
                ),
            });
        }
        domain.check_holes(scale)?;
        Ok(domain)
    }

    /// The checks of [`Self::from_loops`] on the holes (loops after the first).
    fn check_holes(&self, scale: f64) -> Result<(), GeometryError> {
        let samples = |l: usize| -> Vec<Point> {
            self.curves[self.loop_range(l)]
                .iter()
                .flat_map(|c| match c {
                    Curve::Polyline { points } => points.to_vec(),
                    _ => (0..64).map(|i| c.point_at(i as f64 / 64.0)).collect(),
                })
                .collect()
        };
        let tol = 1e-9 * scale;
        for l in 1..self.loop_count() {
            let hole = l - 1;
            let fail = |reason: String| Err(GeometryError::Hole { hole, reason });
            let first = self.loop_range(l).start;
            if self.loop_area(l).is_nan() || self.loop_area(l) >= 0.0 {
                return fail(format!(
                    "its loop (from curve {first}) runs counter-clockwise: a hole's loop runs clockwise, the body on its left"
                ));
            }
            let points = samples(l);
            let inside = |m: usize, p: Point| {
                self.curves[self.loop_range(m)].iter().map(|c| c.ray_crossings(p)).sum::<usize>()
                    % 2
                    == 1
            };
            let gap = |m: usize| {
                let curves = &self.curves[self.loop_range(m)];
                points
                    .iter()
                    .map(|&p| curves.iter().map(|c| c.distance(p)).fold(f64::INFINITY, f64::min))
                    .fold(f64::INFINITY, f64::min)
            };
            if gap(0) <= tol {
                return fail("touches or crosses the body's outer boundary".into());
            }
            if let Some(p) = points.iter().find(|&&p| !inside(0, p)) {
                let what = if points.iter().any(|&p| inside(0, p)) {
                    "crosses the body's outer boundary"
                } else {
                    "lies outside the body"
                };
                return fail(format!(
                    "{what}: its point ({:.6}, {:.6}) is not inside the outer boundary",
                    p[0], p[1]
                ));
            }
            // Against the earlier holes, both ways (one inside the other, or crossing).
            for m in 1..l {
                let contains_other = samples(m).iter().any(|&p| inside(l, p));
                if gap(m) <= tol || points.iter().any(|&p| inside(m, p)) || contains_other {
                    return fail(format!("overlaps or touches hole {}", m - 1));
                }
            }
        }
        Ok(())
    }

    /// The least distance from loop `l` to the other loops (the width of the narrowest
    /// ligament next to it), measured from its curves' points and 64 points along each
    /// segment or arc; infinite for a domain with one loop.
    pub fn loop_clearance(&self, l: usize) -> f64 {
        let points: Vec<Point> = self.curves[self.loop_range(l)]
            .iter()
            .flat_map(|c| match c {
                Curve::Polyline { points } => points.to_vec(),
                _ => (0..64).map(|i| c.point_at(i as f64 / 64.0)).collect(),
            })
            .collect();
        (0..self.loop_count())
            .filter(|&m| m != l)
            .flat_map(|m| self.curves[self.loop_range(m)].iter())
            .flat_map(|c| points.iter().map(move |&p| c.distance(p)))
            .fold(f64::INFINITY, f64::min)
    }

    /// This domain with `holes` cut out of it: each hole is given as the domain of the region
    /// removed (its outer loop, counter-clockwise, as a body's), which becomes a clockwise
    /// loop of this domain (curves reversed, names kept), after this domain's loops.
    ///
    /// # Errors
    /// As [`Self::from_loops`]: [`GeometryError::Hole`] (numbered from this domain's first
    /// hole) for a hole outside the body, touching or crossing another loop; a given hole
    /// with holes of its own; [`GeometryError::EdgeNames`] for a repeated name.
    pub fn with_holes(self, holes: Vec<Domain>) -> Result<Self, GeometryError> {
        let first = self.loop_count() - 1;
        let mut loops: Vec<Vec<Curve>> =
            (0..self.loop_count()).map(|l| self.curves[self.loop_range(l)].to_vec()).collect();
        let mut names = self.edge_names;
        for (i, hole) in holes.into_iter().enumerate() {
            if hole.has_holes() {
                return Err(GeometryError::Hole {
                    hole: first + i,
                    reason: "a hole cannot have holes of its own".into(),
                });
            }
            loops.push(hole.curves.iter().rev().map(Curve::reversed).collect());
            names.extend(hole.edge_names.into_iter().rev());
        }
        Self::from_loops(loops, names)
    }

    /// Number of boundary loops (1 + the number of holes).
    pub fn loop_count(&self) -> usize {
        self.loop_ends.len()
    }

    /// Whether the body has holes (more than one boundary loop).
    pub fn has_holes(&self) -> bool {
        self.loop_ends.len() > 1
    }

    /// The edges (curve indices) of loop `l` (0: the outer loop, then the holes).
    pub fn loop_range(&self, l: usize) -> std::ops::Range<usize> {
        let start = if l == 0 { 0 } else { self.loop_ends[l - 1] };
        start..self.loop_ends[l]
    }

    /// The loop edge `k` belongs to.
    pub fn loop_of(&self, k: usize) -> usize {
        self.loop_ends.iter().position(|&e| k < e).unwrap_or(self.loop_ends.len() - 1)
    }

    /// The edge after edge `k` along its loop (the loop's first after its last).
    pub fn next_in_loop(&self, k: usize) -> usize {
        next_in_loop(&self.loop_ends, k)
    }

    /// Signed area enclosed by loop `l` (positive counter-clockwise).
    fn loop_area(&self, l: usize) -> f64 {
        self.curves[self.loop_range(l)].iter().map(curve_area).sum()
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

    /// The curves, in edge order.
    pub fn curves(&self) -> &[Curve] {
        &self.curves
    }

    /// Curve of edge `k`.
    pub fn curve(&self, k: usize) -> &Curve {
        &self.curves[k]
    }

    /// Whether every edge is a straight segment.
    pub fn is_polygon(&self) -> bool {
        self.curves.iter().all(Curve::is_straight)
    }

    /// Number of edges (curves).
    pub fn edge_count(&self) -> usize {
        self.curves.len()
    }

    /// Edge names, in edge order.
    pub fn edge_names(&self) -> &[String] {
        &self.edge_names
    }

    /// Index of the edge with this name.
    pub fn edge_index(&self, name: &str) -> Option<usize> {
        self.edge_names.iter().position(|n| n == name)
    }

    /// End points `(start, end)` of edge `k`.
    pub fn edge(&self, k: usize) -> (Point, Point) {
        (self.curves[k].start(), self.curves[k].end())
    }

    /// Outward unit normal of a straight edge `k`; `None` for an arc (use
    /// [`Self::outward_normal_at`]).
    ///
    /// A component of at most 1e-12 is round-off of an axis-aligned edge (end points whose
    /// shared coordinate differs in its last bits, e.g. `1.0` and `1.0000000000000002`) and is
    /// snapped to zero, the other to ±1, as for a rigid obstacle's normal: which displacement
    /// conditions a contact candidate meets then does not depend on the last bit of an input.
    pub fn straight_normal(&self, k: usize) -> Option<Point> {
        let c = &self.curves[k];
        c.is_straight().then(|| {
            let n = c.outward_normal_at(c.start());
            match (n[0].abs() <= 1e-12, n[1].abs() <= 1e-12) {
                (true, false) => [0.0, n[1].signum()],
                (false, true) => [n[0].signum(), 0.0],
                _ => n,
            }
        })
    }

    /// Outward unit normal of edge `k` at its point nearest `p`.
    pub fn outward_normal_at(&self, k: usize, p: Point) -> Point {
        self.curves[k].outward_normal_at(p)
    }

    /// Axis-aligned bounding box `([xmin, ymin], [xmax, ymax])` (exact for arcs).
    pub fn bounding_box(&self) -> (Point, Point) {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        let mut add = |p: Point| {
            for d in 0..2 {
                lo[d] = lo[d].min(p[d]);
                hi[d] = hi[d].max(p[d]);
            }
        };
        for c in &self.curves {
            add(c.start());
            add(c.end());
            if let Curve::Polyline { points } = c {
                points.iter().for_each(|&p| add(p));
            }
            if let Curve::Arc { center, radius, start, sweep } = *c {
                for k in -8..=8 {
                    let t = (k as f64 * 0.5 * PI - start) / sweep;
                    if (0.0..=1.0).contains(&t) {
                        let (s, co) = (k as f64 * 0.5 * PI).sin_cos();
                        add([center[0] + radius * co, center[1] + radius * s]);
                    }
                }
            }
        }
        (lo, hi)
    }

    /// Area enclosed by the exact loops (shoelace over the chords plus the circular segments;
    /// the holes' clockwise loops subtract theirs).
    pub fn area(&self) -> f64 {
        self.curves.iter().map(curve_area).sum()
    }

    /// Centroid of the enclosed area (of a fine polygonal approximation of each loop).
    pub fn centroid(&self) -> Point {
        let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
        for l in 0..self.loop_count() {
            // Every loop has at least 3 vertices here: 3 segments, or an arc (256 points).
            let pts: Vec<Point> = self.curves[self.loop_range(l)]
                .iter()
                .flat_map(|c| match c {
                    Curve::Polyline { points } => points[..points.len() - 1].to_vec(),
                    _ => {
                        let n = if c.is_straight() { 1 } else { 256 };
                        (0..n).map(|i| c.point_at(i as f64 / n as f64)).collect()
                    }
                })
                .collect();
            for k in 0..pts.len() {
                let (p, q) = (pts[k], pts[(k + 1) % pts.len()]);
                let w = p[0] * q[1] - q[0] * p[1];
                a += w;
                cx += (p[0] + q[0]) * w;
                cy += (p[1] + q[1]) * w;
            }
        }
        [cx / (3.0 * a), cy / (3.0 * a)]
    }

    /// Whether `p` lies inside the exact loops (even–odd rule over every loop: inside the
    /// outer one and outside the holes; points on the boundary may go either way).
    pub fn contains(&self, p: Point) -> bool {
        self.curves.iter().map(|c| c.ray_crossings(p)).sum::<usize>() % 2 == 1
    }

    /// Distance of `p` to the boundary.
    pub fn boundary_distance(&self, p: Point) -> f64 {
        self.curves.iter().map(|c| c.distance(p)).fold(f64::INFINITY, f64::min)
    }

    /// Signed distance of `p` to the line or circle carrying edge `k` (negative on the
    /// body's side).
    pub fn edge_distance(&self, k: usize, p: Point) -> f64 {
        self.curves[k].signed_distance(p)
    }

    /// Parameter `t ∈ [0, 1]` of the projection of `p` on edge `k` (`0` at its start,
    /// proportional to arc length).
    pub fn edge_parameter(&self, k: usize, p: Point) -> f64 {
        self.curves[k].parameter(p)
    }

    /// The polygonal approximation of the outer loop used by the discretisation at nominal
    /// spacing `h`: vertices counter-clockwise, and for each polygon edge (from vertex `i` to
    /// `i + 1`) the domain edge it approximates. Straight edges are kept whole; an arc becomes
    /// the chords between its [`Curve::divisions`]`(h)` equally spaced points, which are
    /// exactly the arc's boundary nodes; a polyline is kept (its points are its boundary
    /// nodes). A domain with holes has one such ring per loop: [`Self::boundary_rings`].
    pub fn boundary_polygon(&self, h: f64) -> (Vec<Point>, Vec<u32>) {
        self.ring(0, h)
    }

    /// The polygonal approximation of every loop, as [`Self::boundary_polygon`]: the outer
    /// ring (counter-clockwise) first, then one clockwise ring per hole.
    pub fn boundary_rings(&self, h: f64) -> Vec<(Vec<Point>, Vec<u32>)> {
        (0..self.loop_count()).map(|l| self.ring(l, h)).collect()
    }

    /// The polygonal approximation of loop `l` ([`Self::boundary_polygon`]).
    fn ring(&self, l: usize, h: f64) -> (Vec<Point>, Vec<u32>) {
        let mut vertices = Vec::new();
        let mut labels = Vec::new();
        for k in self.loop_range(l) {
            let c = &self.curves[k];
            if c.is_straight() {
                vertices.push(c.start());
                labels.push(k as u32);
            } else {
                let points = c.division_points(h);
                labels.extend(std::iter::repeat_n(k as u32, points.len() - 1));
                vertices.extend_from_slice(&points[..points.len() - 1]);
            }
        }
        (vertices, labels)
    }

    /// The polygonal approximation of every loop through given points on the arcs (as
    /// [`Self::boundary_rings`], outer ring first): straight edges and polylines as there, and
    /// arc `k` as the chords through `arc_points(k)`, its points from its start (included) to
    /// its end (excluded) in order — a graded node set's boundary nodes on the arc
    /// (docs/method.md §2.1). An arc for which `arc_points` gives no point is divided at `h`
    /// ([`Curve::division_points`]).
    pub fn boundary_rings_through(
        &self,
        h: f64,
        arc_points: impl Fn(usize) -> Vec<Point>,
    ) -> Vec<(Vec<Point>, Vec<u32>)> {
        (0..self.loop_count())
            .map(|l| {
                let mut vertices = Vec::new();
                let mut labels = Vec::new();
                for k in self.loop_range(l) {
                    let c = &self.curves[k];
                    let given =
                        if matches!(c, Curve::Arc { .. }) { arc_points(k) } else { Vec::new() };
                    if c.is_straight() {
                        vertices.push(c.start());
                        labels.push(k as u32);
                    } else if given.is_empty() {
                        let points = c.division_points(h);
                        labels.extend(std::iter::repeat_n(k as u32, points.len() - 1));
                        vertices.extend_from_slice(&points[..points.len() - 1]);
                    } else {
                        labels.extend(std::iter::repeat_n(k as u32, given.len()));
                        vertices.extend_from_slice(&given);
                    }
                }
                (vertices, labels)
            })
            .collect()
    }

    /// Whether the domain is an axis-aligned rectangle built by [`Self::rectangle`] order.
    pub fn as_rectangle(&self) -> Option<([f64; 2], [f64; 2])> {
        if self.curves.len() != 4 || !self.is_polygon() {
            return None;
        }
        let v: Vec<Point> = self.curves.iter().map(Curve::start).collect();
        (v[0][1] == v[1][1]
            && v[1][0] == v[2][0]
            && v[2][1] == v[3][1]
            && v[3][0] == v[0][0]
            && v[0][0] < v[1][0])
            .then(|| ([v[0][0], v[1][0]], [v[0][1], v[2][1]]))
    }
}

/// Whether the orthogonal projection of `x` on the line through `a` and `b` falls on the
/// segment `[a, b]`, to `tol` in length (a point of one body has a partner on a target edge
/// only then).
pub fn projects_onto(x: Point, a: Point, b: Point, tol: f64) -> bool {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len = dx.hypot(dy);
    let s = ((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / len;
    (-tol..=len + tol).contains(&s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangle_normals_and_area() {
        let d = Domain::rectangle([0.0, 2.0], [0.0, 1.0]).unwrap();
        assert_eq!(d.straight_normal(0), Some([0.0, -1.0]));
        assert_eq!(d.straight_normal(1), Some([1.0, 0.0]));
        assert!((d.area() - 2.0).abs() < 1e-15);
        assert!(d.as_rectangle().is_some());
    }

    #[test]
    fn straight_normal_snaps_round_off() {
        let names = || ["a", "b", "c", "d"].map(String::from).to_vec();
        // The top edge rises by one ulp of 1 over a length of 2: axis-aligned up to round-off.
        let y = 1.0 + f64::EPSILON;
        let d =
            Domain::polygon(vec![[0.0, 0.0], [2.0, 0.0], [2.0, y], [0.0, 1.0]], names()).unwrap();
        assert_eq!(d.straight_normal(2), Some([0.0, 1.0]));
        // A real tilt is kept.
        let d =
            Domain::polygon(vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.1], [0.0, 1.0]], names()).unwrap();
        let n = d.straight_normal(2).unwrap();
        assert!(n[0] < -0.04 && (n[0].hypot(n[1]) - 1.0).abs() < 1e-15, "{n:?}");
    }

    /// The quarter plate `[0, 4]²` minus the disk of radius 1 at the origin.
    fn quarter_plate() -> Domain {
        let c = [0.0, 0.0];
        Domain::from_curves(
            vec![
                Curve::Segment { a: [1.0, 0.0], b: [4.0, 0.0] },
                Curve::Segment { a: [4.0, 0.0], b: [4.0, 4.0] },
                Curve::Segment { a: [4.0, 4.0], b: [0.0, 4.0] },
                Curve::Segment { a: [0.0, 4.0], b: [0.0, 1.0] },
                Curve::arc_between([0.0, 1.0], [1.0, 0.0], c, false),
            ],
            ["bottom", "right", "top", "left", "hole"].iter().map(|s| s.to_string()).collect(),
        )
        .unwrap()
    }

    #[test]
    fn arcs_have_exact_area_box_normals_and_inside_test() {
        let d = quarter_plate();
        assert!((d.area() - (16.0 - PI / 4.0)).abs() < 1e-13);
        assert_eq!(d.bounding_box(), ([0.0, 0.0], [4.0, 4.0]));
        // The hole's outward normal points towards its centre.
        let n = d.outward_normal_at(4, [0.7, 0.7]);
        assert!((n[0] + 0.5f64.sqrt()).abs() < 1e-15 && (n[1] + 0.5f64.sqrt()).abs() < 1e-15);
        assert!((d.edge_parameter(4, [0.0, 1.0])).abs() < 1e-15);
        assert!((d.edge_parameter(4, [1.0, 1.0]) - 0.5).abs() < 1e-15);
        assert!(d.contains([2.0, 2.0]) && d.contains([0.8, 0.8]) && d.contains([0.1, 1.0 + 1e-3]));
        assert!(!d.contains([0.5, 0.5]) && !d.contains([5.0, 1.0]) && !d.contains([-0.1, 2.0]));
        let disk = Domain::from_curves(
            vec![Curve::arc_between([1.0, 0.0], [1.0, 0.0], [0.0, 0.0], true)],
            vec!["rim".into()],
        )
        .unwrap();
        assert!((disk.area() - PI).abs() < 1e-13);
        assert!(
            disk.contains([0.0, 0.0]) && disk.contains([0.99, 0.0]) && !disk.contains([0.0, 1.01])
        );
        let (lo, hi) = disk.bounding_box();
        assert!((lo[0] + 1.0).abs() < 1e-15 && (hi[1] - 1.0).abs() < 1e-15);
        let c = disk.centroid();
        assert!(c[0].abs() < 1e-12 && c[1].abs() < 1e-12);
    }

    #[test]
    fn open_or_clockwise_loops_are_rejected() {
        let names = || vec!["a".to_string(), "b".to_string()];
        let open = Domain::from_curves(
            vec![
                Curve::Segment { a: [-1.0, 0.0], b: [1.0, 0.0] },
                Curve::arc_between([1.0, 0.0], [-1.0, 0.1], [0.0, 0.0], true),
            ],
            names(),
        );
        assert!(matches!(open, Err(GeometryError::Loop { curve: 1, .. })), "{open:?}");
        let clockwise = Domain::from_curves(
            vec![
                Curve::Segment { a: [-1.0, 0.0], b: [1.0, 0.0] },
                Curve::arc_between([1.0, 0.0], [-1.0, 0.0], [0.0, 0.0], false),
            ],
            names(),
        );
        assert!(matches!(clockwise, Err(GeometryError::Loop { .. })), "{clockwise:?}");
        let half_disk = Domain::from_curves(
            vec![
                Curve::Segment { a: [1.0, 0.0], b: [-1.0, 0.0] },
                Curve::arc_between([-1.0, 0.0], [1.0, 0.0], [0.0, 0.0], true),
            ],
            names(),
        )
        .unwrap();
        assert!((half_disk.area() - PI / 2.0).abs() < 1e-13);
    }

    /// The quarter plate with the hole's arc replaced by the polyline through `n + 1` points
    /// on it (a mesh's boundary nodes).
    fn polyline_plate(n: usize) -> Domain {
        let hole: Vec<Point> = (0..=n)
            .map(|i| {
                let th = 0.5 * PI * (1.0 - i as f64 / n as f64);
                [th.cos(), th.sin()]
            })
            .collect();
        Domain::from_curves(
            vec![
                Curve::Segment { a: [1.0, 0.0], b: [4.0, 0.0] },
                Curve::Segment { a: [4.0, 0.0], b: [4.0, 4.0] },
                Curve::Segment { a: [4.0, 4.0], b: [0.0, 4.0] },
                Curve::Segment { a: [0.0, 4.0], b: [0.0, 1.0] },
                Curve::Polyline { points: hole.into() },
            ],
            ["bottom", "right", "top", "left", "hole"].iter().map(|s| s.to_string()).collect(),
        )
        .unwrap()
    }

    #[test]
    fn polyline_edges_follow_their_points() {
        let n = 8;
        let d = polyline_plate(n);
        let c = d.curve(4);
        // The chords' area: the exact region plus the n circular segments.
        let th = 0.5 * PI / n as f64;
        let chords = 16.0 - PI / 4.0 + n as f64 * 0.5 * (th - th.sin());
        assert!((d.area() - chords).abs() < 1e-13, "{}", d.area());
        // Length, parameter and point: arc-length parametrised, vertices at i / n.
        let chord = 2.0 * (0.5 * th).sin();
        assert!((c.length() - n as f64 * chord).abs() < 1e-14);
        for i in 0..=n {
            let t = i as f64 / n as f64;
            let p = c.point_at(t);
            let th_i = 0.5 * PI * (1.0 - t);
            assert!((p[0] - th_i.cos()).abs() < 1e-14 && (p[1] - th_i.sin()).abs() < 1e-14);
            assert!((d.edge_parameter(4, p) - t).abs() < 1e-14);
            assert!(d.edge_distance(4, p).abs() < 1e-15);
            // Inner vertices: the mean of the pieces' normals, the radial direction inwards.
            if i > 0 && i < n {
                let nrm = d.outward_normal_at(4, p);
                assert!((nrm[0] + p[0]).abs() < 1e-14 && (nrm[1] + p[1]).abs() < 1e-14);
            }
        }
        // Beyond the ends, along the end pieces' lines.
        assert!(d.edge_parameter(4, [-0.1, 1.0]) < 0.0 && d.edge_parameter(4, [1.0, -0.1]) > 1.0);
        // The body side is negative; the division points are the polyline's points.
        assert!(d.edge_distance(4, [0.8, 0.8]) < 0.0 && d.edge_distance(4, [0.5, 0.5]) > 0.0);
        assert!(d.contains([0.75, 0.75]) && !d.contains([0.6, 0.6]) && d.contains([2.0, 2.0]));
        assert_eq!(c.division_points(0.01).len(), n + 1);
        assert_eq!(c.divisions(0.01), n);
        let (poly, labels) = d.boundary_polygon(1.0);
        assert_eq!(poly.len(), 4 + n);
        assert_eq!(labels.iter().filter(|&&l| l == 4).count(), n);
        assert_eq!(d.bounding_box(), ([0.0, 0.0], [4.0, 4.0]));
        // A repeated point is a zero-length piece.
        let bad = Curve::Polyline { points: vec![[0.0, 1.0], [0.0, 1.0], [1.0, 0.0]].into() };
        let mut curves = d.curves().to_vec();
        curves[4] = bad;
        let e = Domain::from_curves(curves, d.edge_names().to_vec()).unwrap_err();
        assert!(e.to_string().contains("piece 0"), "{e}");
    }

    #[test]
    fn holes_are_clockwise_loops_inside_the_body() {
        let outer = || Domain::rectangle([-3.0, 3.0], [-2.0, 2.0]).unwrap();
        let disk = |c: Point, r: f64, name: &str| {
            let p = [c[0] + r, c[1]];
            Domain::from_curves(vec![Curve::arc_between(p, p, c, true)], vec![name.into()]).unwrap()
        };
        let d = outer().with_holes(vec![disk([-1.0, 0.0], 0.5, "a"), disk([1.5, 0.5], 0.4, "b")]);
        let d = d.unwrap();
        assert_eq!((d.loop_count(), d.edge_count()), (3, 6));
        assert_eq!((d.loop_of(3), d.loop_of(4), d.loop_of(5)), (0, 1, 2));
        assert_eq!((d.next_in_loop(3), d.next_in_loop(4), d.next_in_loop(5)), (0, 4, 5));
        assert!((d.area() - (24.0 - PI * (0.25 + 0.16))).abs() < 1e-12);
        // Ligaments: hole a to the left side 1.5, hole b to the top 1.1 (sampled: within 1e-3).
        assert!((d.loop_clearance(1) - 1.5).abs() < 1e-3, "{}", d.loop_clearance(1));
        assert!((d.loop_clearance(2) - 1.1).abs() < 1e-3, "{}", d.loop_clearance(2));
        // Outward normals of a hole point into it; inside test excludes the holes.
        let n = d.outward_normal_at(4, [-0.5, 0.0]);
        assert!((n[0] + 1.0).abs() < 1e-12 && n[1].abs() < 1e-12, "{n:?}");
        assert!(!d.contains([-1.0, 0.0]) && !d.contains([1.5, 0.5]) && d.contains([0.3, 0.0]));
        // A ray at the centre's height (the full circle's seam) still counts both sides.
        assert!(d.contains([-2.0, -1e-16]) && d.contains([-2.0, 1e-16]));
        let rings = d.boundary_rings(0.1);
        assert_eq!(rings.len(), 3);
        assert_eq!(rings[0], d.boundary_polygon(0.1));
        let c = outer().with_holes(vec![disk([1.0, 0.0], 0.5, "a")]).unwrap().centroid();
        // Centroid of the plate minus the disk: −(π/4 · 1) / (24 − π/4).
        assert!((c[0] + PI / 4.0 / (24.0 - PI / 4.0)).abs() < 1e-4 && c[1].abs() < 1e-12);
        // Refusals: outside, touching, overlapping, nested, a clockwise hole, a repeated name.
        let bad = |holes: Vec<Domain>| outer().with_holes(holes).unwrap_err().to_string();
        assert!(bad(vec![disk([5.0, 0.0], 0.5, "a")]).contains("outside"));
        assert!(bad(vec![disk([2.5, 0.0], 0.5, "a")]).contains("touches or crosses"));
        assert!(bad(vec![disk([2.7, 0.0], 0.5, "a")]).contains("crosses the body's outer"));
        let e = bad(vec![disk([0.0, 0.0], 0.5, "a"), disk([0.6, 0.0], 0.5, "b")]);
        assert!(e.contains("hole 1: overlaps or touches hole 0"), "{e}");
        let e = bad(vec![disk([0.0, 0.0], 0.5, "a"), disk([0.0, 0.0], 1.0, "b")]);
        assert!(e.contains("hole 1: overlaps"), "{e}");
        assert!(bad(vec![disk([0.0, 0.0], 0.5, "left")]).contains("repeated name"));
        let ccw = Domain::from_loops(
            vec![outer().curves().to_vec(), disk([0.0, 0.0], 0.5, "a").curves().to_vec()],
            ["bottom", "right", "top", "left", "a"].map(String::from).to_vec(),
        );
        assert!(ccw.unwrap_err().to_string().contains("runs counter-clockwise"));
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
