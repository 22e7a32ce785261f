//! Stage 7: frictionless contact with a rigid obstacle — candidates, gap, force operators, and
//! the condensation onto the contact unknowns (method.md §4; paper eqs. 16–27).
//!
//! Unknown per candidate `c`: the normal contact force `P_c ≥ 0` (the pressure integrated over
//! the boundary segment the candidate's cell owns on the contact edge). With `ν_c` the unit
//! normal of the obstacle pointing into the body:
//!
//! - gap `g_c = g0_c + ν_cᵀ u^h(x_c) = g0_c + G_c û` with `G_c = ν_cᵀ[φ_1(x_c) … φ_N(x_c)]`
//!   (MLS-evaluated: MLS is not interpolating);
//! - force `+ν_c P_c` on the right-hand side of the owner's equilibrium rows: `K û = f + E P`.
//!
//! `E ≠ Gᵀ` for MLS, so the textbook symmetric forms do not apply.

mod condense;

pub use condense::{CondensedContact, condense};

use crate::assembly::GlobalSystem;
use crate::geometry::{Domain, Point};
use crate::mls::ShapeSet;
use crate::nodes::{Axis, Nodes, dof};
use crate::weak_form::{EdgeLabel, Face};
use serde::Serialize;

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

/// Contact of one edge of the body with a rigid line.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactSpec {
    /// Domain edge that may touch the obstacle.
    pub edge: usize,
    /// The obstacle.
    pub obstacle: RigidLine,
    /// A candidate is reported closed when its gap is at most this (absolute; default
    /// `1e-5 · max |g0|`, see method.md §6).
    pub gap_tolerance: Option<f64>,
    /// Accept a condensed compliance `M` that fails the run-time checks (with a warning).
    pub allow_indefinite: bool,
}

/// Failures of the contact stage.
#[derive(Debug, thiserror::Error)]
pub enum ContactError {
    /// The contact edge yields no usable candidate.
    #[error(
        "contact edge `{edge}` has no contact candidates (its nodes are all constrained, or it has none)"
    )]
    NoCandidates {
        /// Edge name.
        edge: String,
    },
    /// The condensed compliance fails the run-time checks (method.md §4.1).
    #[error(
        "the condensed contact compliance M is not trustworthy: {what} = {value:.3e} (at support factor α_s = {support_factor}); mixed MFVM supports above α_s ≈ 2.25 admit near-free checkerboard modes — use support_factor = 2, or set contact.allow_indefinite = true to proceed anyway"
    )]
    IndefiniteCompliance {
        /// Which check failed.
        what: &'static str,
        /// The offending value.
        value: f64,
        /// The support factor in use.
        support_factor: f64,
    },
    /// Factorisation solve failed during condensation.
    #[error(transparent)]
    Solve(#[from] crate::linear_solve::SolveError),
}

/// The contact candidates of one edge and their operators.
#[derive(Clone, Debug)]
pub struct Candidates {
    /// Node of each candidate (the candidate point is the node).
    pub nodes: Vec<u32>,
    /// Candidate positions.
    pub points: Vec<Point>,
    /// Distance along the contact edge from its first vertex.
    pub arc_length: Vec<f64>,
    /// Length of the boundary segment each candidate owns (for the pressure).
    pub segment_length: Vec<f64>,
    /// Initial gaps `g0_c`.
    pub initial_gap: Vec<f64>,
    /// The obstacle normal `ν` (into the body).
    pub normal: Point,
}

impl Candidates {
    /// Number of candidates `m`.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }
    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// `G û`: the normal displacement `ν·u^h(x_c)` at every candidate.
    pub fn normal_displacement(&self, node_shapes: &ShapeSet, u_hat: &[f64]) -> Vec<f64> {
        self.nodes
            .iter()
            .map(|&i| {
                let u = node_shapes.interpolate(i as usize, u_hat);
                self.normal[0] * u[0] + self.normal[1] * u[1]
            })
            .collect()
    }

    /// Adds `E P` (force `ν P_c` on each owner's rows) to `rhs`.
    pub fn add_forces(&self, forces: &[f64], rhs: &mut [f64]) {
        for (&i, &p) in self.nodes.iter().zip(forces) {
            rhs[dof(i as usize, Axis::X)] += self.normal[0] * p;
            rhs[dof(i as usize, Axis::Y)] += self.normal[1] * p;
        }
    }
}

/// Collects the candidates of `spec.edge`: the nodes on that edge whose cells own a boundary
/// segment on it and whose equilibrium rows carrying the normal force are not replaced by
/// displacement conditions, sorted along the edge.
///
/// # Errors
/// [`ContactError::NoCandidates`].
pub fn candidates(
    domain: &Domain,
    nodes: &Nodes,
    boundary_faces: &[Face],
    system: &GlobalSystem,
    spec: &ContactSpec,
) -> Result<Candidates, ContactError> {
    let k = spec.edge;
    let mut segment = vec![0.0; nodes.len()];
    for f in boundary_faces {
        if f.across == EdgeLabel::Boundary(k as u32) {
            segment[f.owner as usize] += f.length();
        }
    }
    let nu = spec.obstacle.normal;
    let mut list: Vec<(f64, usize)> = (0..nodes.len())
        .filter(|&i| nodes.edges[i].contains(k) && segment[i] > 0.0)
        .filter(|&i| {
            Axis::BOTH.iter().all(|&a| nu[a as usize] == 0.0 || !system.is_constrained(dof(i, a)))
        })
        .map(|i| (domain.edge_parameter(k, nodes.points[i]), i))
        .collect();
    if list.is_empty() {
        return Err(ContactError::NoCandidates { edge: domain.edge_names()[k].clone() });
    }
    list.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let (a, b) = domain.edge(k);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    Ok(Candidates {
        nodes: list.iter().map(|&(_, i)| i as u32).collect(),
        points: list.iter().map(|&(_, i)| nodes.points[i]).collect(),
        arc_length: list.iter().map(|&(t, _)| t * len).collect(),
        segment_length: list.iter().map(|&(_, i)| segment[i]).collect(),
        initial_gap: list.iter().map(|&(_, i)| spec.obstacle.gap(nodes.points[i])).collect(),
        normal: nu,
    })
}

/// Where contact begins along the edge: the last open and first closed candidates of the first
/// closed run, and two interpolated estimates (method.md §6).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactOnset {
    /// Arc length of the last open candidate before the first closed one.
    pub last_open: Option<f64>,
    /// Arc length of the first closed candidate.
    pub first_closed: Option<f64>,
    /// From the open side: `gap^(2/3)` extrapolated linearly from the last two open candidates
    /// to zero (a smooth contact edge has `gap ∝ d^(3/2)`), unclipped.
    pub from_gap_raw: Option<f64>,
    /// `from_gap_raw` clipped to `[last_open, first_closed]` (the reported `l_c`).
    pub from_gap: Option<f64>,
    /// From the closed side: `p²` extrapolated linearly from the first two closed candidates
    /// (pressure `∝ d^(1/2)`), clipped likewise.
    pub from_pressure: Option<f64>,
    /// Number of separate closed intervals along the edge.
    pub closed_intervals: usize,
}

/// Estimates the contact onset from gaps `w`, pressures `p` and the closed flags.
pub fn onset(arc: &[f64], gap: &[f64], pressure: &[f64], closed: &[bool]) -> ContactOnset {
    let m = arc.len();
    let closed_intervals = (0..m).filter(|&c| closed[c] && (c == 0 || !closed[c - 1])).count();
    let first = closed.iter().position(|&c| c);
    let mut out = ContactOnset {
        last_open: None,
        first_closed: first.map(|c| arc[c]),
        from_gap_raw: None,
        from_gap: None,
        from_pressure: None,
        closed_intervals,
    };
    let Some(c) = first else { return out };
    if c == 0 {
        return out;
    }
    out.last_open = Some(arc[c - 1]);
    let clip = |v: f64| v.clamp(arc[c - 1], arc[c]);
    if c >= 2 {
        let (x1, x2) = (arc[c - 2], arc[c - 1]);
        let (y1, y2) = (gap[c - 2].max(0.0).powf(2.0 / 3.0), gap[c - 1].max(0.0).powf(2.0 / 3.0));
        if y1 != y2 {
            let raw = x2 - y2 * (x2 - x1) / (y2 - y1);
            out.from_gap_raw = Some(raw);
            out.from_gap = Some(clip(raw));
        }
    }
    if c + 1 < m && closed[c + 1] {
        let (x1, x2) = (arc[c], arc[c + 1]);
        let (y1, y2) = (pressure[c].powi(2), pressure[c + 1].powi(2));
        if y1 != y2 {
            out.from_pressure = Some(clip(x1 - y1 * (x2 - x1) / (y2 - y1)));
        }
    }
    out
}
