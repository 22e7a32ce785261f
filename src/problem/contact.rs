//! What a contact edge touches: the contact specification of a problem (validated in
//! `Problem::try_from`, used by the contact stage [`crate::contact`]).

use crate::geometry::Point;
use serde::{Deserialize, Serialize};

/// A rigid straight obstacle: the line through `point` with unit normal `normal` pointing into
/// the body. The initial gap of a point `x` is `(x − point)·normal` (negative = penetration, i.e.
/// a prescribed indentation).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RigidLine {
    /// A point of the line.
    pub point: Point,
    /// Unit normal, pointing into the body.
    pub normal: Point,
}

impl RigidLine {
    /// Signed distance of `x` from the line along the normal.
    pub fn gap(&self, x: Point) -> f64 {
        (x[0] - self.point[0]) * self.normal[0] + (x[1] - self.point[1]) * self.normal[1]
    }
}

/// One piece of a [`Polyline`] obstacle: a straight segment or a rounded corner.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Piece {
    /// The segment from `a` to `b`; the body lies on its right (normal `(d_y, −d_x)` for the
    /// direction `d` from `a` to `b`).
    Segment {
        /// Start.
        a: Point,
        /// End.
        b: Point,
    },
    /// A circular arc of radius `radius` about `centre` from `a` to `b` (the shorter way),
    /// tangent to the segments it joins.
    Arc {
        /// Centre.
        centre: Point,
        /// Radius.
        radius: f64,
        /// Start (the tangent point on the incoming segment).
        a: Point,
        /// End (the tangent point on the outgoing segment).
        b: Point,
        /// Whether the arc bulges towards the body (a left turn of the polyline): the normal
        /// into the body is then `(x − centre)/radius`, else `(centre − x)/radius`.
        convex: bool,
    },
}

/// A rigid obstacle bounded by a polyline whose interior corners may be rounded: the obstacle
/// lies on the left of the polyline walked from its first point to its last (its outline
/// counter-clockwise), the body on the right.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Polyline {
    /// The pieces in order along the polyline.
    pub pieces: Vec<Piece>,
}

/// The shape of a rigid obstacle (docs/method.md §4.4).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// A straight line; the body on the side its normal points to.
    Line(RigidLine),
    /// A rigid disk; the body outside it.
    Circle {
        /// Centre.
        centre: Point,
        /// Radius.
        radius: f64,
    },
    /// A polyline with rounded corners.
    Polyline(Polyline),
}

/// A named rigid obstacle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Obstacle {
    /// Name (`[[obstacle]] name`).
    pub name: String,
    /// Its shape in the initial position.
    pub shape: Shape,
}

/// The initial gap of a point against an obstacle and the contact normal there
/// (docs/method.md §4.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closest {
    /// Signed distance from the obstacle (negative inside it).
    pub gap: f64,
    /// Unit normal of the obstacle at the closest point, pointing into the body.
    pub normal: Point,
    /// The closest point of the obstacle.
    pub point: Point,
}

fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}
fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn cross(a: Point, b: Point) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

impl Piece {
    /// The closest point of the piece to `x`, the distance, the normal into the body there
    /// (for a closest point at an end of the piece, the normal of the piece at that end) and
    /// whether the closest point is an end of the piece (`x` beyond it).
    fn closest(&self, x: Point) -> (Point, f64, Point, bool) {
        match *self {
            Piece::Segment { a, b } => {
                let d = sub(b, a);
                let len2 = dot(d, d);
                let raw = dot(sub(x, a), d) / len2;
                let t = raw.clamp(0.0, 1.0);
                let y = [a[0] + t * d[0], a[1] + t * d[1]];
                let len = len2.sqrt();
                let n = [d[1] / len, -d[0] / len];
                let r = sub(x, y);
                (y, r[0].hypot(r[1]), n, raw != t)
            }
            Piece::Arc { centre, radius, a, b, convex } => {
                let (ua, ub, u) = (sub(a, centre), sub(b, centre), sub(x, centre));
                let sweep = cross(ua, ub);
                let inside = cross(ua, u) * sweep >= 0.0 && cross(u, ub) * sweep >= 0.0;
                let len = u[0].hypot(u[1]);
                let y = if inside && len > 0.0 {
                    [centre[0] + radius * u[0] / len, centre[1] + radius * u[1] / len]
                } else if dot(sub(x, a), sub(x, a)) <= dot(sub(x, b), sub(x, b)) {
                    a
                } else {
                    b
                };
                let s = if convex { 1.0 } else { -1.0 };
                let n = [s * (y[0] - centre[0]) / radius, s * (y[1] - centre[1]) / radius];
                let r = sub(x, y);
                (y, r[0].hypot(r[1]), n, !(inside && len > 0.0))
            }
        }
    }
}

impl Polyline {
    /// The polyline through `points` with every interior corner rounded by an arc of radius
    /// `corner_radius` (0: sharp corners), or why not: fewer than two points, a zero-length
    /// segment, a reversal, or rounded corners that do not fit on their segments.
    pub fn new(points: &[Point], corner_radius: f64) -> Result<Self, String> {
        if points.len() < 2 {
            return Err(format!("{} points; a polyline needs at least 2", points.len()));
        }
        let n = points.len();
        let dirs: Vec<Point> = (0..n - 1)
            .map(|k| {
                let d = sub(points[k + 1], points[k]);
                let l = d[0].hypot(d[1]);
                [d[0] / l, d[1] / l]
            })
            .collect();
        for k in 0..n - 1 {
            let d = sub(points[k + 1], points[k]);
            if d[0].hypot(d[1]) == 0.0 {
                return Err(format!("points {k} and {} coincide", k + 1));
            }
        }
        // Setback of each interior corner: the distance from the vertex to the tangent points.
        let mut setback = vec![0.0; n];
        let mut turn = vec![0.0; n];
        for k in 1..n - 1 {
            let (d1, d2) = (dirs[k - 1], dirs[k]);
            let angle = cross(d1, d2).atan2(dot(d1, d2));
            if angle.abs() > std::f64::consts::PI * (1.0 - 1e-9) {
                return Err(format!("the polyline reverses at point {k}"));
            }
            turn[k] = angle;
            setback[k] = corner_radius * (0.5 * angle.abs()).tan();
        }
        for k in 0..n - 1 {
            let d = sub(points[k + 1], points[k]);
            if setback[k] + setback[k + 1] > d[0].hypot(d[1]) * (1.0 + 1e-12) {
                return Err(format!(
                    "corner_radius {corner_radius} is too large: the rounded corners at points {k} and {} do not fit on the segment between them",
                    k + 1
                ));
            }
        }
        let mut pieces = Vec::new();
        let mut start = points[0];
        for k in 1..n {
            let d = dirs[k - 1];
            let s = setback[k];
            let end = [points[k][0] - s * d[0], points[k][1] - s * d[1]];
            if sub(end, start) != [0.0, 0.0] {
                pieces.push(Piece::Segment { a: start, b: end });
            }
            start = end;
            if k < n - 1 && s > 0.0 {
                let d2 = dirs[k];
                let b = [points[k][0] + s * d2[0], points[k][1] + s * d2[1]];
                let convex = turn[k] > 0.0;
                // The centre lies on the left of d for a left turn, on the right otherwise.
                let side = if convex { [-d[1], d[0]] } else { [d[1], -d[0]] };
                let centre = [end[0] + corner_radius * side[0], end[1] + corner_radius * side[1]];
                pieces.push(Piece::Arc { centre, radius: corner_radius, a: end, b, convex });
                start = b;
            }
        }
        Ok(Self { pieces })
    }

    /// The closest point of the polyline to `x`, its signed distance (positive on the body's
    /// side) and the normal into the body there. Where `x` projects inside a piece, that
    /// piece's normal and `gap = (x − y)·ν`; where the closest point is a sharp corner or an
    /// end point (the projection falls beyond every piece there), the direction from it to
    /// `x` (the piece's normal when `x` is on the polyline).
    pub fn closest(&self, x: Point) -> Closest {
        let mut best: Option<(Point, f64, Point, bool)> = None;
        for piece in &self.pieces {
            let c = piece.closest(x);
            // On a tie (a point over the joint of two pieces), the piece it projects inside.
            let better = best.is_none_or(|b| c.1 < b.1 || (c.1 == b.1 && b.3 && !c.3));
            if better {
                best = Some(c);
            }
        }
        let (y, dist, n, at_end) = best.expect("a polyline has at least one piece");
        let r = sub(x, y);
        let along = dot(r, n);
        if !at_end {
            return Closest { gap: along, normal: n, point: y };
        }
        // Off the piece's normal line: x lies in the wedge of a sharp corner or beyond an end.
        let scale = x[0].abs().max(x[1].abs()).max(1.0);
        if dist <= 1e-12 * scale {
            return Closest { gap: 0.0, normal: n, point: y };
        }
        let sign = if along >= 0.0 { 1.0 } else { -1.0 };
        Closest { gap: sign * dist, normal: [sign * r[0] / dist, sign * r[1] / dist], point: y }
    }

    /// Points along the polyline, arcs divided into pieces of at most `step` radians.
    pub fn outline(&self, step: f64) -> Vec<Point> {
        let mut out = Vec::new();
        for piece in &self.pieces {
            match *piece {
                Piece::Segment { a, b } => {
                    if out.last() != Some(&a) {
                        out.push(a);
                    }
                    out.push(b);
                }
                Piece::Arc { centre, radius, a, b, .. } => {
                    let (ua, ub) = (sub(a, centre), sub(b, centre));
                    let t0 = ua[1].atan2(ua[0]);
                    let sweep = cross(ua, ub).atan2(dot(ua, ub));
                    let k = ((sweep.abs() / step).ceil() as usize).max(1);
                    for i in 0..=k {
                        let t = t0 + sweep * i as f64 / k as f64;
                        out.push([centre[0] + radius * t.cos(), centre[1] + radius * t.sin()]);
                    }
                }
            }
        }
        out
    }
}

impl Shape {
    /// The closest point of the obstacle to `x`, the signed gap and the normal into the body
    /// there (docs/method.md §4.4). For a line: the same numbers as [`RigidLine::gap`] and
    /// its normal.
    pub fn closest(&self, x: Point) -> Closest {
        match self {
            Shape::Line(line) => {
                let gap = line.gap(x);
                let n = line.normal;
                Closest { gap, normal: n, point: [x[0] - gap * n[0], x[1] - gap * n[1]] }
            }
            Shape::Circle { centre, radius } => {
                let r = sub(x, *centre);
                let len = r[0].hypot(r[1]);
                // The centre itself: any direction; take +y.
                let n = if len > 0.0 { [r[0] / len, r[1] / len] } else { [0.0, 1.0] };
                Closest {
                    gap: len - radius,
                    normal: n,
                    point: [centre[0] + radius * n[0], centre[1] + radius * n[1]],
                }
            }
            Shape::Polyline(p) => p.closest(x),
        }
    }

    /// The shape moved rigidly by `d`.
    pub fn translated(&self, d: Point) -> Shape {
        let m = |p: Point| [p[0] + d[0], p[1] + d[1]];
        match self {
            Shape::Line(l) => Shape::Line(RigidLine { point: m(l.point), normal: l.normal }),
            Shape::Circle { centre, radius } => {
                Shape::Circle { centre: m(*centre), radius: *radius }
            }
            Shape::Polyline(p) => Shape::Polyline(Polyline {
                pieces: p
                    .pieces
                    .iter()
                    .map(|piece| match *piece {
                        Piece::Segment { a, b } => Piece::Segment { a: m(a), b: m(b) },
                        Piece::Arc { centre, radius, a, b, convex } => {
                            Piece::Arc { centre: m(centre), radius, a: m(a), b: m(b), convex }
                        }
                    })
                    .collect(),
            }),
        }
    }

    /// The kind as written in `[[obstacle]] kind`.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Line(_) => "line",
            Shape::Circle { .. } => "circle",
            Shape::Polyline(_) => "polyline",
        }
    }
}

/// The obstacle closest to `x` among `obstacles` (the smallest gap; the first on a tie) with
/// its index, gap and normal. `None` without obstacles.
pub fn closest_obstacle(obstacles: &[Obstacle], x: Point) -> Option<(usize, Closest)> {
    let mut best: Option<(usize, Closest)> = None;
    for (k, o) in obstacles.iter().enumerate() {
        let c = o.shape.closest(x);
        if best.is_none_or(|b| c.gap < b.1.gap) {
            best = Some((k, c));
        }
    }
    best
}

/// What the contact edge touches.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactTarget {
    /// A rigid straight obstacle (`[contact] obstacle_point`, `obstacle_normal`).
    Rigid(RigidLine),
    /// The rigid obstacles of `Problem::obstacles` (`[[obstacle]]` tables named by
    /// `[contact] target`): each candidate pairs with the closest of them (docs/method.md §4.4).
    Obstacles,
    /// A straight edge of the second elastic body (`Problem::second_body`).
    Body {
        /// The second body's edge.
        edge: usize,
    },
}

/// Contact of one edge of the body with a rigid line or with a second elastic body.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactSpec {
    /// Domain edge of the (first) body that may touch the target; it carries the candidates.
    pub edge: usize,
    /// The obstacle or the second body's edge.
    pub target: ContactTarget,
    /// A candidate is reported closed when its gap is at most this (absolute; default
    /// `1e-5 · max |g0| + 1e-12 · max |q|`, see docs/method.md §6).
    pub gap_tolerance: Option<f64>,
    /// Accept a condensed compliance `M` that fails the run-time checks (with a warning).
    pub allow_indefinite: bool,
    /// Which condensation (default: the compliance form, exact for MLS).
    pub condensation: Condensation,
    /// Coulomb friction coefficient `μ ≥ 0`; 0 (the default) is frictionless contact and takes
    /// the frictionless path unchanged (docs/method.md §8).
    pub friction: f64,
    /// Which solver takes the frictionless contact problem (docs/method.md §5).
    #[serde(skip)]
    pub solver: ContactSolver,
    /// A designed interference `δ ≥ 0` of a two-body pair (a press or shrink fit): every
    /// candidate's initial gap is `g0 − δ` along the pair's normal, as if the contact body
    /// were `δ` larger towards the target (docs/method.md §9.9). 0 for rigid obstacles.
    pub interference: f64,
}

/// `[contact] solver`: how the frictionless contact problem is solved (docs/method.md §5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactSolver {
    /// Lemke's method on the dense condensed compliance `M = G K⁻¹ E` (docs/method.md §5).
    Lemke,
    /// The primal–dual active-set method on the sparse system, without `M` (docs/method.md
    /// §5.1); a rigid obstacle or two bodies, with friction and load steps too.
    ActiveSet,
    /// Lemke below [`ContactSolver::AUTO_THRESHOLD`] candidates (frictional problems against
    /// a rigid obstacle: [`ContactSolver::FRICTION_AUTO_THRESHOLD`]; two bodies with friction
    /// or load steps: [`ContactSolver::FRICTION_PAIR_AUTO_THRESHOLD`]), the active-set method
    /// from there on (the rule: `pipeline::plan`).
    #[default]
    Auto,
}

impl ContactSolver {
    /// Candidates from which `Auto` takes the active-set method: on the strip `L × 1` at
    /// spacing 0.05 (docs/dev/active_set.md) Lemke's path took 0.6 s against 0.9 s at 1 000
    /// candidates and 3.1 s against 1.7 s at 2 000; on the beam the two are even at 768.
    /// Above every shipped problem (at most 384 candidates).
    pub const AUTO_THRESHOLD: usize = 1000;

    /// Candidates from which `Auto` takes the active-set method for a frictional problem
    /// (or one with load steps) against a rigid obstacle (docs/dev/active_set.md, "Friction"):
    /// with μ = 0.3, one step, on the strip `L × 1` at spacing 0.05 Lemke's path (condensation
    /// of four blocks, Lemke on the 3m step LCP) took 0.5 s against 0.6 s at 250 candidates,
    /// 2.5 s against 1.4 s at 500 and 9.2 s against 3.8 s at 1 000; on the beam 3.3 s
    /// against 4.6 s at 384. Above every shipped frictional problem (at most 192 candidates).
    pub const FRICTION_AUTO_THRESHOLD: usize = 500;

    /// Candidates from which `Auto` takes the active-set method for two bodies with friction
    /// (or load steps) (docs/dev/active_set.md, "Friction between two bodies"): with μ = 0.3,
    /// one step, on the strip `L × 1` at spacing 0.05 pressed onto an elastic block, Lemke's
    /// path (both bodies' four blocks, Lemke on the 3m step LCP) took 5.0 s wall against
    /// 7.1 s at 500 candidates, 11.3 s against 12.2 s at 750 and 19.3 s against 13.5 s at
    /// 1 000 (under load). Above every shipped two-body problem (at most 52 candidates).
    pub const FRICTION_PAIR_AUTO_THRESHOLD: usize = 800;
}

/// How the problem is condensed onto the contact unknowns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Condensation {
    /// `M = G K⁻¹ E` with MLS-evaluated gaps (docs/method.md §4.2; default).
    #[default]
    Compliance,
    /// The paper's literal stiffness form (eqs. 22–27): the Schur complement on the nodal
    /// parameters of the candidates, `K_p = K_cc − K_ci K_ii⁻¹ K_ic`, i.e. `M = K_p⁻¹`, which
    /// reads fictitious nodal values as displacements. Offered for comparison only: its gaps
    /// are not the MLS gaps (the summary reports the mismatch).
    Stiffness,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Point, b: Point) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    #[test]
    fn circle_gap_and_normal_are_radial() {
        let s = Shape::Circle { centre: [0.0, 2.0], radius: 1.0 };
        let c = s.closest([0.0, 0.0]);
        assert!((c.gap - 1.0).abs() < 1e-15 && close(c.normal, [0.0, -1.0]));
        let c = s.closest([1.0, 2.0 - 1.0]);
        let r = 2f64.sqrt();
        assert!((c.gap - (r - 1.0)).abs() < 1e-15, "{c:?}");
        assert!(close(c.normal, [1.0 / r, -1.0 / r]));
        // Inside the disk: negative gap, normal still outward.
        let c = s.closest([0.0, 1.5]);
        assert!((c.gap + 0.5).abs() < 1e-15 && close(c.normal, [0.0, -1.0]));
    }

    #[test]
    fn line_shape_matches_rigid_line() {
        let line = RigidLine { point: [0.0, -1.0], normal: [0.6, 0.8] };
        let x = [0.3, 0.7];
        let c = Shape::Line(line).closest(x);
        assert_eq!((c.gap, c.normal), (line.gap(x), line.normal));
    }

    /// A flat punch of half-width 1 with corners rounded to 0.1: the obstacle above, walked
    /// down its left side, along its face, up its right side.
    fn punch(r: f64) -> Polyline {
        Polyline::new(&[[-1.0, 1.0], [-1.0, 0.0], [1.0, 0.0], [1.0, 1.0]], r).unwrap()
    }

    #[test]
    fn rounded_punch_pieces_and_closest_points() {
        let p = punch(0.1);
        // Three segments and two arcs.
        assert_eq!(p.pieces.len(), 5);
        // Under the face: the face's normal, pointing down into the body.
        let c = p.closest([0.3, -0.2]);
        assert!((c.gap - 0.2).abs() < 1e-15 && close(c.normal, [0.0, -1.0]), "{c:?}");
        // Below-left of the rounded corner: radial from the arc's centre (-0.9, 0.1).
        let x = [-1.2, -0.2];
        let c = p.closest(x);
        let d = (x[0] + 0.9f64).hypot(x[1] - 0.1);
        assert!((c.gap - (d - 0.1)).abs() < 1e-14, "{c:?}");
        assert!(close(c.normal, [(x[0] + 0.9) / d, (x[1] - 0.1) / d]), "{c:?}");
        // Left of the punch: the side's normal (−1, 0).
        let c = p.closest([-1.5, 0.5]);
        assert!((c.gap - 0.5).abs() < 1e-15 && close(c.normal, [-1.0, 0.0]));
        // Inside the punch: negative.
        let c = p.closest([0.0, 0.05]);
        assert!((c.gap + 0.05).abs() < 1e-15 && close(c.normal, [0.0, -1.0]));
    }

    #[test]
    fn sharp_corner_normal_points_to_the_point() {
        let p = punch(0.0);
        assert_eq!(p.pieces.len(), 3);
        let c = p.closest([-2.0, -1.0]);
        let r = 2f64.sqrt();
        assert!((c.gap - r).abs() < 1e-15 && close(c.normal, [-1.0 / r, -1.0 / r]), "{c:?}");
    }

    #[test]
    fn concave_corner_and_bad_polylines() {
        // A right turn (the body inside the corner): normal towards the arc's centre.
        let p = Polyline::new(&[[0.0, 0.0], [1.0, 0.0], [1.0, -1.0]], 0.2).unwrap();
        let c = p.closest([0.5, -0.5]);
        assert!(c.gap > 0.0, "{c:?}");
        assert!(Polyline::new(&[[0.0, 0.0]], 0.0).is_err());
        assert!(Polyline::new(&[[0.0, 0.0], [0.0, 0.0]], 0.0).is_err());
        assert!(Polyline::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]], 0.0).is_err());
        assert!(Polyline::new(&[[-1.0, 1.0], [-1.0, 0.0], [1.0, 0.0], [1.0, 1.0]], 1.5).is_err());
    }

    #[test]
    fn translated_moves_every_piece() {
        let p = Shape::Polyline(punch(0.1)).translated([0.5, -0.25]);
        let c = p.closest([0.8, -0.5]);
        assert!((c.gap - 0.25).abs() < 1e-15 && close(c.normal, [0.0, -1.0]), "{c:?}");
        let s = Shape::Circle { centre: [0.0, 2.0], radius: 1.0 }.translated([0.0, -1.0]);
        assert!((s.closest([0.0, 0.0]).gap).abs() < 1e-15);
    }
}
