//! Stage 9: contact with a rigid obstacle or a second body — candidates, gap, force operators, and
//! the condensation onto the contact unknowns (docs/method.md §4; paper eqs. 16–27).
//!
//! Unknown per candidate `c`: the normal contact force `P_c ≥ 0` (the pressure integrated over
//! the boundary segment the candidate's cell owns on the contact edge). With `ν_c` the unit
//! normal of the obstacle at the candidate's closest point, pointing into the body (one
//! vector for a line or a second body's straight edge; per candidate for a curved obstacle,
//! frozen at the initial closest point, docs/method.md §4.4):
//!
//! - gap `g_c = g0_c + ν_cᵀ u^h(x_c) = g0_c + G_c û` with `G_c = ν_cᵀ[φ_1(x_c) … φ_N(x_c)]`
//!   (MLS-evaluated: MLS is not interpolating);
//! - force `+ν_c P_c` on the right-hand side of the owner's equilibrium rows: `K û = f + E P`.
//!
//! `E ≠ Gᵀ` for MLS, so the textbook symmetric forms do not apply.

mod condense;
pub mod fem;
mod resolved;
pub mod rings;
pub mod sparse;
pub mod spectrum;

pub use crate::problem::{
    Closest, Condensation, ContactSpec, ContactTarget, Obstacle, RigidLine, Shape, closest_obstacle,
};
pub use condense::{
    CondensedBlocks, CondensedContact, CondensedPart, condense, condense_blocked, condense_blocks,
    condense_model_observed, condense_observed, sparse_compliance,
};
pub use condense::{GRADED_SPARSE_CONDENSATION_MIN_CANDIDATES, SPARSE_CONDENSATION_MIN_CANDIDATES};
pub use resolved::{PairTarget, target_resolved_extremes};
pub use spectrum::EigenvalueMethod;

use crate::assembly::GlobalSystem;
use crate::geometry::{Domain, Point};
use crate::mls::{self, MlsError, MlsParams, ShapeSet};
use crate::model::{Mfvm, Model, Scheme};
use crate::neighbours::Supports;
use crate::nodes::{Axis, Nodes, dof};
use crate::problem::Problem;
use crate::weak_form::{EdgeLabel, Face};
use serde::Serialize;

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
    /// The condensed compliance fails the run-time checks (docs/method.md §4.1).
    #[error(
        "the condensed contact compliance M is not trustworthy: {what} = {value:.3e} (at support factor α_s = {support_factor}, beta = {beta}); {remedy}, or set contact.allow_indefinite = true to proceed anyway"
    )]
    IndefiniteCompliance {
        /// Which check failed.
        what: &'static str,
        /// The offending value.
        value: f64,
        /// The support factor in use.
        support_factor: f64,
        /// The blend `β` in use.
        beta: f64,
        /// The remedies not already in effect ([`ComplianceContext::remedy`]).
        remedy: String,
    },
    /// A target cell's normal rows are Dirichlet rows: the contact force would be lost.
    #[error(
        "the contact force on edge `{edge}` of the second body would go to node {node}, whose normal displacement is prescribed"
    )]
    TargetConstrained {
        /// Edge name.
        edge: String,
        /// Node.
        node: usize,
    },
    /// No candidate of the contact edge lies over the target edge of the second body.
    #[error(
        "no point of contact edge `{edge}` lies over edge `{target}` of the second body: the bodies cannot touch (check the geometry)"
    )]
    NoPartner {
        /// The contact edge.
        edge: String,
        /// The target edge.
        target: String,
    },
    /// A two-body contact was solved without the second body's model, or a contact with
    /// obstacles without any obstacle.
    #[error(
        "the contact's target is missing: a second body without its model, or obstacles without any [[obstacle]]"
    )]
    MissingTarget,
    /// The frictional condensation (docs/method.md §8) was handed a body without its
    /// tangential operator, or no body at all: an inconsistency of the caller (a frictionless
    /// one-shot path builds no tangential operators), not of the input.
    #[error("the frictional condensation needs every contact body's tangential operator: {what}")]
    MissingTangential {
        /// Which body lacks it, or that there is none.
        what: String,
    },
    /// MLS failed at a contact point.
    #[error(transparent)]
    Mls(#[from] MlsError),
    /// Factorisation solve failed during condensation.
    #[error(transparent)]
    Solve(#[from] crate::linear_solve::SolveError),
}

/// The candidates on `edge` of a discretised body, whichever discretisation built it: the
/// MFVM's owned boundary segments with MLS gap rows ([`candidates`]), or the FE edge nodes
/// ([`fem::candidates`]). `problem` is the problem `model` was built from; `target(x)` is
/// the initial gap and the contact normal at a point `x` of the edge. The candidates of an
/// axisymmetric body are rings ([`rings`]): their forces are the rings' totals.
///
/// # Errors
/// As [`candidates`] and [`fem::candidates`].
pub fn candidates_on(
    problem: &Problem,
    model: &Model,
    edge: usize,
    target: &dyn Fn(Point) -> (f64, Point),
    condensation: Condensation,
) -> Result<Candidates, ContactError> {
    candidates_in(problem, Discretised::of(model), edge, target, condensation)
}

/// A discretised body as the contact stage reads it, with or without a factorisation: the
/// nodes, the assembled system and the MFVM's cells and faces or the FE mesh (a static
/// [`Model`], or a dynamic body assembled without `K⁻¹`).
#[derive(Clone, Copy)]
pub enum Discretised<'a> {
    /// The MFVM: nodes, system, supports and cells.
    Mfvm {
        /// Nodes.
        nodes: &'a Nodes,
        /// `K` with its collocation rows.
        system: &'a GlobalSystem,
        /// Supports, cells and faces.
        mfvm: &'a Mfvm,
    },
    /// Finite elements: nodes, system and mesh.
    Fem {
        /// Nodes.
        nodes: &'a Nodes,
        /// `K` with its eliminated rows.
        system: &'a GlobalSystem,
        /// The mesh.
        mesh: &'a crate::fem::Mesh,
    },
}

impl<'a> Discretised<'a> {
    /// The view of a static model.
    pub fn of(model: &'a Model) -> Self {
        match &model.scheme {
            Scheme::Mfvm(m) => Self::Mfvm { nodes: &model.nodes, system: &model.system, mfvm: m },
            Scheme::Fem(f) => {
                Self::Fem { nodes: &model.nodes, system: &model.system, mesh: &f.mesh }
            }
        }
    }

    /// The assembled system.
    pub fn system(&self) -> &'a GlobalSystem {
        match self {
            Self::Mfvm { system, .. } | Self::Fem { system, .. } => system,
        }
    }

    fn view(
        problem: &'a Problem,
        nodes: &'a Nodes,
        system: &'a GlobalSystem,
        m: &'a Mfvm,
    ) -> BodyView<'a> {
        BodyView {
            domain: &problem.domain,
            nodes,
            supports: &m.supports,
            mls: &problem.discretisation.mls,
            boundary_faces: &m.faces.boundary,
            system,
        }
    }
}

/// [`candidates_on`] for a [`Discretised`] body.
///
/// # Errors
/// As [`candidates`] and [`fem::candidates`].
pub fn candidates_in(
    problem: &Problem,
    body: Discretised<'_>,
    edge: usize,
    target: &dyn Fn(Point) -> (f64, Point),
    condensation: Condensation,
) -> Result<Candidates, ContactError> {
    let mut found = match body {
        Discretised::Mfvm { nodes, system, mfvm } => {
            candidates(Discretised::view(problem, nodes, system, mfvm), edge, target, condensation)
        }
        Discretised::Fem { nodes, system, mesh } => {
            fem::candidates(mesh, &problem.domain, nodes, system, edge, target)
        }
    }?;
    if body.system().axisymmetric {
        let area = match body {
            Discretised::Mfvm { mfvm, .. } => {
                rings::mfvm_areas(&mfvm.faces.boundary, edge, &found.nodes)
            }
            Discretised::Fem { nodes, mesh, .. } => {
                rings::fem_areas(mesh, &problem.domain, nodes, edge, &found.nodes)
            }
        };
        rings::into_rings(&mut found, area);
    }
    Ok(found)
}

/// The initial gap and contact normal at `x` against the rigid target of `spec`
/// (docs/method.md §4.4): the line of [`ContactTarget::Rigid`], or the closest of
/// `problem.obstacles` for [`ContactTarget::Obstacles`]; `None` for a second body.
pub fn rigid_target(problem: &Problem, spec: &ContactSpec, x: Point) -> Option<(f64, Point)> {
    match spec.target {
        ContactTarget::Rigid(line) => Some((line.gap(x), line.normal)),
        ContactTarget::Obstacles => {
            closest_obstacle(problem.obstacles(), x).map(|(_, c)| (c.gap, c.normal))
        }
        ContactTarget::Body { .. } => None,
    }
}

/// The second body's operator, initial gaps and paired points for `candidates` against its
/// edge `edge`, whichever discretisation built it ([`target_operator`],
/// [`fem::target_operator`]).
///
/// # Errors
/// As [`target_operator`] and [`fem::target_operator`].
pub fn target_operator_on(
    problem: &Problem,
    model: &Model,
    edge: usize,
    candidates: &Candidates,
) -> Result<(BodyOperator, Vec<f64>, Vec<Point>), ContactError> {
    target_operator_in(problem, Discretised::of(model), edge, candidates)
}

/// [`target_operator_on`] for a [`Discretised`] body.
///
/// # Errors
/// As [`target_operator`] and [`fem::target_operator`].
pub fn target_operator_in(
    problem: &Problem,
    body: Discretised<'_>,
    edge: usize,
    candidates: &Candidates,
) -> Result<(BodyOperator, Vec<f64>, Vec<Point>), ContactError> {
    match body {
        Discretised::Mfvm { nodes, system, mfvm } => {
            target_operator(Discretised::view(problem, nodes, system, mfvm), edge, candidates)
        }
        Discretised::Fem { nodes, system, mesh } => {
            fem::target_operator(mesh, &problem.domain, nodes, system, edge, candidates)
        }
    }
}

/// What the refusal of an untrustworthy `M` needs to name a remedy not already in effect.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComplianceContext {
    /// The support factor `α_s` in use.
    pub support_factor: f64,
    /// The blend `β` in use.
    pub beta: f64,
    /// The largest support factor of the pure mixed method with this basis
    /// ([`crate::problem::MIXED_LINEAR_MAX_SUPPORT_FACTOR`] or its quadratic counterpart).
    pub support_limit: f64,
    /// Whether a contact pairs with a second elastic body (its target side's force and gap
    /// pairing is indefinite when the candidates are finer than a softer target).
    pub two_body: bool,
}

impl ComplianceContext {
    /// The context of `problem`'s discretisation; `two_body` as given.
    pub fn of(problem: &Problem, two_body: bool) -> Self {
        let d = &problem.discretisation;
        let support_limit = match d.mls.basis {
            mls::Basis::Linear => crate::problem::MIXED_LINEAR_MAX_SUPPORT_FACTOR,
            mls::Basis::Quadratic => crate::problem::MIXED_QUADRATIC_MAX_SUPPORT_FACTOR,
        };
        Self { support_factor: d.mls.support_factor, beta: d.beta, support_limit, two_body }
    }

    /// The remedies for an untrustworthy `M` that are not already in effect: a support factor
    /// at most the mixed method's limit and the stabilised `β = 0.5` only while `β` is below
    /// [`crate::problem::MIN_STABILISING_BETA`] (they remove the checkerboard modes of §3.8,
    /// nothing else); a finer or stiffer target for a two-body contact
    /// (docs/dev/beta_study.md: a target coarser than the candidate edge and softer than the
    /// candidate body is indefinite whatever `β`); otherwise a finer, more evenly graded node
    /// set along the contact edge.
    pub fn remedy(&self) -> String {
        let mut remedies = Vec::new();
        if self.beta < crate::problem::MIN_STABILISING_BETA {
            if self.support_factor > self.support_limit {
                remedies.push(format!(
                    "use support_factor <= {} (mixed MFVM supports above it admit near-free checkerboard modes)",
                    self.support_limit
                ));
            }
            remedies.push(
                "use the stabilised discretisation.beta = 0.5 (docs/method.md §3.9)".to_string(),
            );
        }
        if self.two_body {
            remedies.push(
                "refine the second body along contact.target_edge at least as finely as contact.edge, or make the second body the stiffer one (a target coarser than the candidates and softer than their body makes M's symmetric part indefinite whatever beta)".to_string(),
            );
        }
        if remedies.is_empty() {
            remedies
                .push("use a finer, more evenly graded node set along contact.edge".to_string());
        }
        remedies.join("; or ")
    }
}

/// The run-time checks of the condensed compliance before an LCP answer is trusted
/// (docs/method.md §4.1): a positive diagonal and a positive definite symmetric part
/// (`λ_min((M + Mᵀ)/2) > 10⁻¹² λ_max`). The error quotes `context`'s values and remedies.
///
/// # Errors
/// [`ContactError::IndefiniteCompliance`] naming the failed check and its value.
pub fn check_compliance(
    condensed: &CondensedContact,
    context: &ComplianceContext,
) -> Result<(), ContactError> {
    let scale = condensed.max_symmetric_eigenvalue.abs().max(f64::MIN_POSITIVE);
    let failed = if condensed.min_diagonal <= 0.0 {
        Some(("smallest diagonal entry of M", condensed.min_diagonal))
    } else if condensed.min_symmetric_eigenvalue <= 1e-12 * scale {
        Some(("smallest eigenvalue of (M + Mᵀ)/2", condensed.min_symmetric_eigenvalue))
    } else {
        None
    };
    match failed {
        Some((what, value)) => Err(ContactError::IndefiniteCompliance {
            what,
            value,
            support_factor: context.support_factor,
            beta: context.beta,
            remedy: context.remedy(),
        }),
        None => Ok(()),
    }
}

/// The checks of `M` for contact pairs whose targets may be elastic bodies (`pairs`: each
/// pair's candidates in `M`'s numbering and its elastic target, if any): [`check_compliance`],
/// and when only its eigenvalue check fails and some pair's target is elastic, the same check
/// restricted to the force patterns the targets resolve ([`target_resolved_extremes`], docs/method.md
/// §4.3). `Ok(None)`: `M` passed; `Ok(Some(note))`: `M`'s symmetric part is indefinite only in
/// patterns finer than the target's cells, the note says so and the run proceeds to the
/// answer's own checks; `allow_indefinite` turns any remaining failure into a note.
///
/// # Errors
/// [`ContactError::IndefiniteCompliance`] as [`check_compliance`] when neither applies.
pub fn check_pair_compliance(
    condensed: &CondensedContact,
    context: &ComplianceContext,
    pairs: &[PairTarget<'_>],
    allow_indefinite: bool,
) -> Result<Option<String>, ContactError> {
    let Err(err) = check_compliance(condensed, context) else { return Ok(None) };
    let eigenvalue_only = condensed.min_diagonal > 0.0;
    let elastic = pairs.iter().any(|(_, target)| target.is_some());
    let resolved = (eigenvalue_only && elastic)
        .then(|| target_resolved_extremes(&condensed.compliance, pairs).ok())
        .flatten()
        .filter(|&(min, max)| max > 0.0 && min > 1e-12 * max);
    match resolved {
        Some((min, _)) => Ok(Some(format!(
            "the smallest eigenvalue of (M + Mᵀ)/2 is {:.3e} (largest {:.3e}), negative only in contact-force patterns that vary within one cell of a target body (on the patterns the target cells resolve the smallest is {min:.3e}): the candidates are finer than the target's cells (docs/method.md §4.3); the answer was accepted on its own checks (complementarity, equilibrium); refining the target body along its target_edge as finely as the contact edge removes this",
            condensed.min_symmetric_eigenvalue, condensed.max_symmetric_eigenvalue
        ))),
        None if allow_indefinite => Ok(Some(err.to_string())),
        None => Err(err),
    }
}

/// How one body enters the contact constraint: its displacement at the contact points adds
/// `d·u^h(x_c)` to the gap (the `G` rows) and the contact force adds `d P_c` to the owner
/// cell's equilibrium rows (the `E` columns). `d = +ν` for the candidate body and `−ν` for
/// the target body of a two-body contact (docs/method.md §4.3); `d` is per contact point
/// (a curved obstacle's normal differs from point to point, docs/method.md §4.4).
#[derive(Clone, Debug)]
pub struct BodyOperator {
    /// MLS shape functions at the contact points on this body (one row per candidate).
    pub shapes: ShapeSet,
    /// Nodes whose cells receive each contact force, with weights summing to 1.
    pub owners: Vec<Vec<(u32, f64)>>,
    /// `d_c` per contact point: `+ν_c` or `−ν_c`.
    pub directions: Vec<Point>,
}

impl BodyOperator {
    /// `d_c` of contact point `c`.
    pub fn direction(&self, c: usize) -> Point {
        self.directions[c]
    }
    /// Number of contact points.
    pub fn len(&self) -> usize {
        self.owners.len()
    }
    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.owners.is_empty()
    }
    /// `G û`: `d·u^h(x_c)` at every contact point.
    pub fn gap_contribution(&self, u_hat: &[f64]) -> Vec<f64> {
        (0..self.len())
            .map(|c| {
                let u = self.shapes.interpolate(c, u_hat);
                let d = self.directions[c];
                d[0] * u[0] + d[1] * u[1]
            })
            .collect()
    }
    /// Adds `E P` (force `d P_c` on each owner's rows) to `rhs`.
    pub fn add_forces(&self, forces: &[f64], rhs: &mut [f64]) {
        for ((owners, &p), d) in self.owners.iter().zip(forces).zip(&self.directions) {
            for &(i, w) in owners {
                rhs[dof(i as usize, Axis::X)] += d[0] * w * p;
                rhs[dof(i as usize, Axis::Y)] += d[1] * w * p;
            }
        }
    }
    /// Resultant `Σ d_c P_c` of the contact forces on this body (with one direction `d`,
    /// `d Σ P_c`).
    pub fn resultant(&self, forces: &[f64]) -> [f64; 2] {
        match self.uniform_direction() {
            Some(d) => {
                let total: f64 = forces.iter().sum();
                [d[0] * total, d[1] * total]
            }
            None => forces
                .iter()
                .zip(&self.directions)
                .fold([0.0, 0.0], |r, (p, d)| [r[0] + d[0] * p, r[1] + d[1] * p]),
        }
    }
    /// The direction when every contact point has the same one.
    pub fn uniform_direction(&self) -> Option<Point> {
        let first = *self.directions.first()?;
        self.directions.iter().all(|d| *d == first).then_some(first)
    }
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
    /// End points of that segment (its extent along the edge).
    pub segment_ends: Vec<(Point, Point)>,
    /// Initial gaps `g0_c`.
    pub initial_gap: Vec<f64>,
    /// The contact normal `ν_c` of each candidate (pointing into the candidate body; the
    /// same for all against a line or a straight target edge).
    pub normals: Vec<Point>,
    /// The candidate body's operator (`d = +ν`, owners = the candidate nodes).
    pub operator: BodyOperator,
}

impl Candidates {
    /// Keeps the candidates `k` with `keep[k]` (in order) and returns how many were dropped.
    pub fn retain(&mut self, keep: &[bool]) -> usize {
        let rows: Vec<usize> = (0..self.len()).filter(|&k| keep[k]).collect();
        fn pick<T: Clone>(v: &[T], rows: &[usize]) -> Vec<T> {
            rows.iter().map(|&k| v[k].clone()).collect()
        }
        let dropped = self.len() - rows.len();
        self.nodes = pick(&self.nodes, &rows);
        self.points = pick(&self.points, &rows);
        self.arc_length = pick(&self.arc_length, &rows);
        self.segment_length = pick(&self.segment_length, &rows);
        self.segment_ends = pick(&self.segment_ends, &rows);
        self.initial_gap = pick(&self.initial_gap, &rows);
        self.normals = pick(&self.normals, &rows);
        self.operator.directions = pick(&self.operator.directions, &rows);
        self.operator.shapes = self.operator.shapes.select_rows(&rows);
        self.operator.owners = pick(&self.operator.owners, &rows);
        dropped
    }

    /// Number of candidates `m`.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }
    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }
    /// The contact tangent `t_c = (ν_y, −ν_x)` of candidate `c`: `ν_c` turned clockwise by a
    /// right angle (docs/method.md §8). A positive tangential force pushes the body along
    /// `+t_c`.
    pub fn tangent(&self, c: usize) -> Point {
        tangent(self.normals[c])
    }
    /// The contact normal `ν_c` of candidate `c`.
    pub fn normal(&self, c: usize) -> Point {
        self.normals[c]
    }
    /// The tangential operator of the candidate body (docs/method.md §8): the same contact
    /// points and owners as [`Candidates::operator`], direction `t` instead of `ν`. A
    /// candidate whose owner has a prescribed displacement along `t` (its tangential row is a
    /// displacement condition of `system`) gets no tangential force: its owner list is empty
    /// and its flag in the returned vector is `false` (such candidates are frictionless).
    pub fn tangential_operator(&self, system: &GlobalSystem) -> (BodyOperator, Vec<bool>) {
        let tangents: Vec<Point> = (0..self.len()).map(|c| self.tangent(c)).collect();
        let free: Vec<bool> = self
            .operator
            .owners
            .iter()
            .zip(&tangents)
            .map(|(owners, &t)| {
                owners.iter().all(|&(i, _)| {
                    Axis::BOTH.iter().all(|&a| {
                        t[a as usize] == 0.0 || !system.is_constrained(dof(i as usize, a))
                    })
                })
            })
            .collect();
        let owners = self
            .operator
            .owners
            .iter()
            .zip(&free)
            .map(|(o, &f)| if f { o.clone() } else { Vec::new() })
            .collect();
        (BodyOperator { shapes: self.operator.shapes.clone(), owners, directions: tangents }, free)
    }
}

/// `t = (ν_y, −ν_x)` for the unit normal `ν` (docs/method.md §8).
pub fn tangent(normal: Point) -> Point {
    [normal[1], -normal[0]]
}

/// The discretised body a contact operator is built on.
#[derive(Clone, Copy)]
pub struct BodyView<'a> {
    /// Domain.
    pub domain: &'a Domain,
    /// Nodes.
    pub nodes: &'a Nodes,
    /// MLS supports.
    pub supports: &'a Supports,
    /// MLS parameters.
    pub mls: &'a MlsParams,
    /// Boundary faces of the cells.
    pub boundary_faces: &'a [Face],
    /// Assembled system (for the constrained rows).
    pub system: &'a GlobalSystem,
}

impl<'a> BodyView<'a> {
    /// The view of an MFVM model whose MFVM data is `m` (`problem` is the one it was built
    /// from).
    pub fn new(problem: &'a Problem, model: &'a Model, m: &'a Mfvm) -> Self {
        Self {
            domain: &problem.domain,
            nodes: &model.nodes,
            supports: &m.supports,
            mls: &problem.discretisation.mls,
            boundary_faces: &m.faces.boundary,
            system: &model.system,
        }
    }
}

/// Collects the candidates of `edge`: the nodes on that edge whose cells own a boundary
/// segment on it and whose equilibrium rows carrying the normal force are not replaced by
/// displacement conditions, sorted along the edge. `target(x)` is the gap before deformation
/// and the contact normal `ν` (into the body) at a point `x` of the edge. With
/// [`Condensation::Stiffness`] the gap rows read the candidates' nodal parameters instead of
/// the MLS displacement.
///
/// # Errors
/// [`ContactError::NoCandidates`], or an MLS failure at a candidate.
pub fn candidates(
    body: BodyView<'_>,
    edge: usize,
    target: &dyn Fn(Point) -> (f64, Point),
    condensation: Condensation,
) -> Result<Candidates, ContactError> {
    let (domain, nodes) = (body.domain, body.nodes);
    let k = edge;
    let mut segment = vec![0.0; nodes.len()];
    // Extent of each node's owned segment, as edge parameters.
    let mut extent = vec![[f64::INFINITY, f64::NEG_INFINITY]; nodes.len()];
    for f in body.boundary_faces {
        if f.across == EdgeLabel::Boundary(k as u32) {
            let o = f.owner as usize;
            segment[o] += f.length();
            for p in [f.a, f.b] {
                let t = domain.edge_parameter(k, p);
                extent[o] = [extent[o][0].min(t), extent[o][1].max(t)];
            }
        }
    }
    let mut list: Vec<(f64, usize)> = (0..nodes.len())
        .filter(|&i| nodes.edges[i].contains(k) && segment[i] > 0.0)
        .filter(|&i| {
            let nu = target(nodes.points[i]).1;
            Axis::BOTH
                .iter()
                .all(|&a| nu[a as usize] == 0.0 || !body.system.is_constrained(dof(i, a)))
        })
        .map(|i| (domain.edge_parameter(k, nodes.points[i]), i))
        .collect();
    if list.is_empty() {
        return Err(ContactError::NoCandidates { edge: domain.edge_names()[k].clone() });
    }
    list.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let curve = domain.curve(k);
    let len = curve.length();
    let points: Vec<Point> = list.iter().map(|&(_, i)| nodes.points[i]).collect();
    let shapes = match condensation {
        Condensation::Compliance => {
            mls::shape_functions(&points, nodes, body.supports, body.mls, false)?
        }
        Condensation::Stiffness => {
            ShapeSet::nodal(&list.iter().map(|&(_, i)| i as u32).collect::<Vec<_>>())
        }
    };
    let owners: Vec<Vec<(u32, f64)>> = list.iter().map(|&(_, i)| vec![(i as u32, 1.0)]).collect();
    let at = |t: f64| curve.point_at(t);
    let (initial_gap, normals): (Vec<f64>, Vec<Point>) = points.iter().map(|&p| target(p)).unzip();
    Ok(Candidates {
        nodes: list.iter().map(|&(_, i)| i as u32).collect(),
        segment_ends: list.iter().map(|&(_, i)| (at(extent[i][0]), at(extent[i][1]))).collect(),
        arc_length: list.iter().map(|&(t, _)| t * len).collect(),
        segment_length: list.iter().map(|&(_, i)| segment[i]).collect(),
        initial_gap,
        operator: BodyOperator { shapes, owners, directions: normals.clone() },
        normals,
        points,
    })
}

/// The target body of a two-body contact: each candidate `x_c` of body 1 is paired with the
/// closest point `y_c` of body 2's straight edge `edge`; `ν` is that edge's outward normal
/// (from body 2 into body 1) and `g0_c = ν·(x_c − y_c)`. The reaction `−ν P_c` is spread over
/// the body-2 cells whose boundary faces overlap the candidate's segment projected onto the
/// edge, in proportion to the overlap (a uniform pressure over the segment), so that
/// non-matching layouts pass the uniform-pressure patch test; where nothing overlaps, it goes
/// to the cell holding `y_c` (docs/method.md §4.3 describes the closest-point pairing).
/// An axisymmetric target (docs/method.md §9.6) takes the candidate ring's total force per
/// radian: the shares are in proportion to the overlap's `∫ r ds` and sum to `1/2π`.
///
/// Returns the operator (`d = −ν`), the initial gaps and the paired points.
///
/// # Errors
/// [`ContactError::TargetConstrained`] when a receiving cell's normal rows are Dirichlet rows,
/// or an MLS failure at a paired point.
pub fn target_operator(
    body: BodyView<'_>,
    edge: usize,
    candidates: &Candidates,
) -> Result<(BodyOperator, Vec<f64>, Vec<Point>), ContactError> {
    let name = || body.domain.edge_names()[edge].clone();
    let pairing = TargetEdge::new(body.domain, edge);
    // Body-2 faces on the edge as parameter intervals.
    let faces: Vec<(f64, f64, u32, &Face)> = body
        .boundary_faces
        .iter()
        .filter(|f| f.across == EdgeLabel::Boundary(edge as u32))
        .map(|f| {
            let (s, t) =
                (body.domain.edge_parameter(edge, f.a), body.domain.edge_parameter(edge, f.b));
            (s.min(t), s.max(t), f.owner, f)
        })
        .collect();
    if faces.is_empty() {
        return Err(ContactError::NoCandidates { edge: name() });
    }
    // An axisymmetric target receives a ring's total force per radian (`rings`): `1/2π`.
    let per_radian = if body.system.axisymmetric { rings::REVOLUTION } else { 1.0 };
    let mut paired = Vec::with_capacity(candidates.len());
    let mut owners = Vec::with_capacity(candidates.len());
    let mut gaps = Vec::with_capacity(candidates.len());
    let mut directions = Vec::with_capacity(candidates.len());
    for (c, &x) in candidates.points.iter().enumerate() {
        // A curved target pairs along the candidate's normal (the bisector, `body_pair`).
        let (y, nu, gap) = pairing.pair_along(x, candidates.normals[c]);
        let (p, q) = candidates.segment_ends[c];
        let (s0, s1) = {
            let (u, v) = (body.domain.edge_parameter(edge, p), body.domain.edge_parameter(edge, q));
            (u.min(v), u.max(v))
        };
        let mut share: Vec<(u32, f64)> = Vec::new();
        for &(f0, f1, owner, _) in &faces {
            let (lo, hi) = (s0.max(f0), s1.min(f1));
            if hi > lo {
                // Axisymmetric: the overlap's `∫ r ds`.
                let overlap = match body.system.axisymmetric {
                    true => pairing.moment(lo, hi),
                    false => hi - lo,
                };
                match share.iter_mut().find(|(o, _)| *o == owner) {
                    Some(entry) => entry.1 += overlap,
                    None => share.push((owner, overlap)),
                }
            }
        }
        let total: f64 = share.iter().map(|s| s.1).sum();
        if total > 0.0 {
            for s in share.iter_mut() {
                s.1 /= total * per_radian;
            }
        } else {
            // No overlap (a candidate past the end of the edge): the cell holding y_c.
            let owner = faces
                .iter()
                .map(|&(_, _, o, f)| (segment_distance(y, f.a, f.b), o))
                .min_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)))
                .map(|(_, o)| o)
                .ok_or_else(|| ContactError::NoCandidates { edge: name() })?;
            share = vec![(owner, 1.0 / per_radian)];
        }
        let blocked = |nu: Point| {
            share.iter().map(|&(o, _)| o as usize).find(|&o| {
                Axis::BOTH
                    .iter()
                    .any(|&ax| nu[ax as usize] != 0.0 && body.system.is_constrained(dof(o, ax)))
            })
        };
        let (nu, gap) = match body.system.axisymmetric && blocked(nu).is_some() {
            true => pairing.axial(x, y, nu),
            false => (nu, gap),
        };
        if let Some(node) = blocked(nu) {
            return Err(ContactError::TargetConstrained { edge: name(), node });
        }
        gaps.push(gap);
        paired.push(y);
        owners.push(share);
        directions.push([-nu[0], -nu[1]]);
    }
    let shapes = mls::shape_functions(&paired, body.nodes, body.supports, body.mls, false)?;
    Ok((BodyOperator { shapes, owners, directions }, gaps, paired))
}

/// The target edge of a two-body contact as the pairing reads it (docs/method.md §4.3, §4.5):
/// a straight edge (one normal, `r` linear along it) or a curved one (an arc, or a polyline of
/// a mesh's boundary nodes), whose closest point, normal and `∫ r ds` come from the curve.
#[derive(Clone, Copy)]
pub struct TargetEdge<'a> {
    curve: &'a crate::geometry::Curve,
    /// The straight edge's normal (snapped to the axes within round-off), `None` if curved.
    straight: Option<Point>,
}

impl<'a> TargetEdge<'a> {
    /// Edge `edge` of `domain`.
    pub fn new(domain: &'a Domain, edge: usize) -> Self {
        Self { curve: domain.curve(edge), straight: domain.straight_normal(edge) }
    }

    /// The closest point `y` of the edge to `x` (clamped to the edge), the target's outward
    /// normal `ν` there (from body 2 into body 1) and the initial gap `ν·(x − y)`.
    pub fn pair(&self, x: Point) -> (Point, Point, f64) {
        let t = self.curve.parameter(x).clamp(0.0, 1.0);
        let y = self.curve.point_at(t);
        let nu = match self.straight {
            Some(nu) => nu,
            // Round-off components dropped, as `Domain::straight_normal` does (a point on the
            // axis has the axial normal exactly, so its radial row may be the axis condition).
            None => self.curve.outward_normal_at(y).map(|n| if n.abs() <= 1e-12 { 0.0 } else { n }),
        };
        (y, nu, (x[0] - y[0]) * nu[0] + (x[1] - y[1]) * nu[1])
    }

    /// The pairing of `x` along the candidate side's normal `nu` (docs/method.md §9.6): a
    /// straight edge as [`Self::pair`] (its own normal); a curved one's closest point `y`,
    /// `nu` itself and the gap `nu·(x − y)`, so that both operators act along `±nu`.
    pub fn pair_along(&self, x: Point, nu: Point) -> (Point, Point, f64) {
        match self.straight {
            Some(_) => self.pair(x),
            None => {
                let (y, _, _) = self.pair(x);
                (y, nu, (x[0] - y[0]) * nu[0] + (x[1] - y[1]) * nu[1])
            }
        }
    }

    /// The contact normal of a candidate at `x` on a curved target whose own edge's inward
    /// normal there is `inward` (docs/method.md §9.6): the bisector of the target's outward
    /// normal at the closest point and `inward`, round-off components dropped (so two
    /// identical spheres pair along the axis, whichever is the target). A straight target's
    /// normal is its own.
    pub fn bisector(&self, x: Point, inward: Point) -> Point {
        let nu = self.normal(x);
        if self.straight.is_some() {
            return nu;
        }
        let b = [nu[0] + inward[0], nu[1] + inward[1]];
        let len = b[0].hypot(b[1]);
        // Opposite normals (no facing): keep the target's.
        if len <= 1e-12 {
            return nu;
        }
        [b[0] / len, b[1] / len].map(|n| if n.abs() <= 1e-12 { 0.0 } else { n })
    }

    /// A curved axisymmetric target's normal where its force reaches a node on the axis
    /// (whose radial row is the symmetry condition `u_r = 0`): the axial direction
    /// `(0, ±1)` instead of `ν` (whose radial part is `O(r/R)` there, and would be lost on
    /// that row), with the gap `ν'·(x − y)` along it (docs/method.md §9.6). A straight edge's
    /// normal is returned as it is.
    pub fn axial(&self, x: Point, y: Point, nu: Point) -> (Point, f64) {
        match self.straight {
            Some(_) => (nu, (x[0] - y[0]) * nu[0] + (x[1] - y[1]) * nu[1]),
            None => {
                let axial = [0.0, nu[1].signum()];
                (axial, (x[1] - y[1]) * axial[1])
            }
        }
    }

    /// The contact normal at a candidate point `x` (the target's outward normal at its
    /// closest point), with a zero initial gap: the candidates' `target` closure.
    pub fn normal(&self, x: Point) -> Point {
        self.pair(x).1
    }

    /// Whether `x`'s closest point lies on the edge (its parameter within `[0, 1]` to `1e-9`):
    /// a candidate whose projection falls beside the edge has no partner.
    pub fn over(&self, x: Point) -> bool {
        (-1e-9..=1.0 + 1e-9).contains(&self.curve.parameter(x))
    }

    /// `r` at parameter `t` (the first coordinate of the edge's point).
    pub fn radius(&self, t: f64) -> f64 {
        self.curve.point_at(t)[0]
    }

    /// `∫ r ds` over the parameters `[lo, hi]`: exact on a straight edge (`r` linear, the
    /// trapezoid), 4-point Gauss along a curved one (its arc length proportional to `t`).
    pub fn moment(&self, lo: f64, hi: f64) -> f64 {
        match self.straight {
            Some(_) => (hi - lo) * 0.5 * (self.radius(lo) + self.radius(hi)),
            None => {
                let (xs, ws) = crate::weak_form::gauss_legendre(4);
                let sum: f64 = xs
                    .iter()
                    .zip(ws)
                    .map(|(&q, &w)| w * self.radius(0.5 * (lo + hi) + 0.5 * q * (hi - lo)))
                    .sum();
                0.5 * (hi - lo) * sum
            }
        }
    }

    /// Whether the edge is straight.
    pub fn is_straight(&self) -> bool {
        self.straight.is_some()
    }
}

fn segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

/// Where contact begins along the edge: the last open and first closed candidates of the first
/// closed run, and two interpolated estimates (docs/method.md §6).
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

#[cfg(test)]
mod tests {
    use super::ComplianceContext;

    fn context(support_factor: f64, beta: f64, two_body: bool) -> ComplianceContext {
        ComplianceContext { support_factor, beta, support_limit: 2.25, two_body }
    }

    /// The refusal names only remedies not already in effect (it read "use support_factor =
    /// 2 or beta = 0.5" whatever the current values were).
    #[test]
    fn remedies_are_not_already_in_effect() {
        let wide = context(3.0, 0.0, false).remedy();
        assert!(wide.contains("support_factor <= 2.25") && wide.contains("beta = 0.5"), "{wide}");
        let paper = context(2.0, 0.0, false).remedy();
        assert!(!paper.contains("support_factor") && paper.contains("beta = 0.5"), "{paper}");
        let soft_target = context(2.0, 0.5, true).remedy();
        assert!(!soft_target.contains("support_factor"), "{soft_target}");
        assert!(!soft_target.contains("beta = 0.5"), "{soft_target}");
        assert!(soft_target.contains("contact.target_edge"), "{soft_target}");
        let stabilised = context(3.0, 0.5, false).remedy();
        assert!(!stabilised.contains("support_factor") && !stabilised.contains("beta ="));
        assert!(stabilised.contains("node set"), "{stabilised}");
    }
}
