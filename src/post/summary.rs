//! `summary.json` as types: [`Summary`] and its sections, each field documented, serialised
//! with sorted keys (through [`serde_json::Value`]) so that the file is byte-for-byte
//! deterministic apart from `timings`.

use crate::contact::EigenvalueMethod;
use crate::lcp::{ContactState, FrictionMethod};
use crate::linear_solve::{FactorMethod, FactorPrecision};
use crate::material::Material;
use crate::model::Model;
use crate::problem::{Discretisation, Layout, Method, Problem};
use crate::solution::{IncrementRecord, Solution};
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;

/// The units of an axisymmetric body's contact (`contact::rings`).
pub const RING_NOTE: &str = "axisymmetric: each candidate is a ring; force (contact.csv) and total_force are the rings' total forces over the whole circumference (2π × the force per radian), pressure = force / ring area (2π ∫ r ds over the candidate's segment), axial_force = Σ ν_z × force; applied_force, reaction_force, contact_force and reactions.csv stay per radian";

/// How `summary.json` explains the onset fields.
pub const ONSET_NOTE: &str = "distances along the contact edge from its first vertex; onset_x: gap^(2/3) extrapolated from the last two open candidates, clipped to [last_open_x, first_closed_x]; onset_x_from_pressure: p^2 extrapolated from the first two closed candidates";

/// The version of `summary.json`'s layout (static and dynamic runs): raised when a key is
/// removed, renamed or changes meaning; keys added keep it (docs/guide: outputs).
/// `tests/summary_layout.rs` holds the layout it names.
pub const SCHEMA_VERSION: u32 = 1;

/// The summary of a run (`summary.json`).
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// The layout's version ([`SCHEMA_VERSION`]).
    pub schema_version: u32,
    /// The program's name and version.
    pub program: Program,
    /// The problem file as read (raw form, before validation).
    pub input: Value,
    /// The validated problem's main parameters.
    pub problem: ProblemEcho,
    /// Sizes of the discretisation.
    pub counts: Counts,
    /// The factorisation of `K`.
    pub linear_solve: LinearSolve,
    /// Residual and global equilibrium of the first body.
    pub checks: Checks,
    /// Headline results.
    pub results: Results,
    /// The LCP and the checks of `M` (contact problems).
    pub lcp: Option<LcpSummary>,
    /// The contact result (contact problems).
    pub contact: Option<ContactSummary>,
    /// The second body's checks (two-body contact; `bodies[1]` holds the same, this key is
    /// kept for the readers of the earlier layout).
    pub second_body: Option<BodySummary>,
    /// Every body's checks, the first included (one entry for a one-body problem).
    pub bodies: Vec<BodySummary>,
    /// Each contact pair's result (empty without contact): the `[contact]` pair, or the
    /// `[[contact]]` tables in their order (`lcp` describes the one LCP over all of them).
    pub pairs: Vec<PairSummary>,
    /// One record per load increment (friction or `[[step]]` only; absent otherwise, so that
    /// frictionless summaries are unchanged; docs/method.md §8).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps: Option<Vec<IncrementRecord>>,
    /// The adaptive loop (`[refinement]` only; absent otherwise, so that other summaries are
    /// unchanged; docs/method.md §2.2). The other sections describe the final node set.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refinement: Option<AdaptiveSummary>,
    /// What the run proceeded past (an unstable discretisation or an indefinite `M` accepted on
    /// request, a contact zone closed by too few candidates), each with its remedy where one
    /// applies.
    pub warnings: Vec<String>,
    /// Seconds per stage (a stage run twice, such as `solve` for two bodies, keeps the last).
    pub timings: BTreeMap<&'static str, f64>,
}

/// The adaptive loop of `[refinement]` (docs/method.md §2.2).
#[derive(Clone, Debug, Serialize)]
pub struct AdaptiveSummary {
    /// The parameters of the loop.
    pub parameters: crate::problem::Adaptive,
    /// Why the loop stopped: `"tolerance"`, `"steps"`, `"max_nodes"` (the next node set would
    /// have exceeded it; the last solved set is reported), `"accuracy"` (the stated
    /// `onset_tolerance` / `force_tolerance` goals are met) or `"no_marks"`.
    pub stopped_by: &'static str,
    /// One row per solve, the first on the initial node set.
    pub steps: Vec<AdaptiveStep>,
    /// How the final onset estimate (`contact.onset_x`) is made, with its bracket.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub onset: Option<OnsetEstimate>,
}

/// One solve of the adaptive loop.
#[derive(Clone, Debug, Serialize)]
pub struct AdaptiveStep {
    /// Solve number, from 0 (the initial node set).
    pub step: usize,
    /// Nodes.
    pub nodes: usize,
    /// Smallest node spacing `h_I`.
    pub min_spacing: f64,
    /// The relative estimated error `(Σ η_I² / Σ h_I² ε̂_Iᵀ D ε̂_I)^(1/2)`.
    pub estimated_error: f64,
    /// Nodes marked for refinement after this solve (bulk and contact; 0 after the last).
    pub marked: usize,
    /// Of those, marked at contact transitions.
    pub marked_contact: usize,
    /// `Σ P_c` (contact problems).
    pub total_contact_force: Option<f64>,
    /// The onset estimate and its bracket (contact problems).
    pub onset_x: Option<f64>,
    /// Last open candidate before the first closed one.
    pub last_open_x: Option<f64>,
    /// First closed candidate.
    pub first_closed_x: Option<f64>,
    /// Two bodies: each body's part of the step, the first body first (absent for one body,
    /// so that one-body summaries are unchanged). `nodes`, `min_spacing`, `marked` and
    /// `marked_contact` above are then the two bodies' totals (least spacing) and
    /// `estimated_error` their combined estimate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bodies: Option<Vec<AdaptiveBodyStep>>,
    /// Several contact pairs: each pair's force and onset (the figures above are then
    /// absent; absent with one pair).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pairs: Option<Vec<AdaptivePairStep>>,
}

/// One contact pair's figures at a step of the adaptive loop with several pairs.
#[derive(Clone, Debug, Serialize)]
pub struct AdaptivePairStep {
    /// The pair's index (`[[contact]]` order, as `pairs` in the summary).
    pub pair: usize,
    /// The pair's `Σ P_c`.
    pub total_contact_force: f64,
    /// The pair's onset estimate and its bracket.
    pub onset_x: Option<f64>,
    /// Last open candidate before the first closed one.
    pub last_open_x: Option<f64>,
    /// First closed candidate.
    pub first_closed_x: Option<f64>,
}

/// One body's part of a step of the adaptive loop with two bodies.
#[derive(Clone, Debug, Serialize)]
pub struct AdaptiveBodyStep {
    /// The body's name.
    pub name: String,
    /// Its nodes.
    pub nodes: usize,
    /// Its smallest node spacing `h_I`.
    pub min_spacing: f64,
    /// Its relative estimated error.
    pub estimated_error: f64,
    /// Its nodes marked after this solve (0 after the last).
    pub marked: usize,
    /// Of those, marked at the contact transitions (the second body: at the paired points of
    /// the first body's transition candidates).
    pub marked_contact: usize,
}

/// The final onset estimate, its bracket and its estimator.
#[derive(Clone, Debug, Serialize)]
pub struct OnsetEstimate {
    /// The estimate (`contact.onset_x`).
    pub estimate: Option<f64>,
    /// Which estimator gave it: `"gap_extrapolation"` (inside the bracket) or `"clipped"`
    /// (the extrapolation left the bracket and was clipped to its end).
    pub estimator: &'static str,
    /// Last open candidate.
    pub last_open_x: Option<f64>,
    /// First closed candidate.
    pub first_closed_x: Option<f64>,
    /// `first_closed_x − last_open_x`: the bracket the onset lies in.
    pub bracket_width: Option<f64>,
}

/// The program that wrote the summary.
#[derive(Clone, Debug, Serialize)]
pub struct Program {
    /// Crate name.
    pub name: &'static str,
    /// Crate version.
    pub version: &'static str,
}

/// The validated problem's parameters.
#[derive(Clone, Debug, Serialize)]
pub struct ProblemEcho {
    /// Problem name.
    pub name: String,
    /// MFVM or FE.
    pub method: Method,
    /// Material.
    pub material: Material,
    /// Discretisation parameters.
    pub discretisation: Discretisation,
    /// Node layout.
    pub layout: Layout,
    /// Nominal node spacing `h`.
    pub node_spacing: f64,
}

/// Sizes of the discretisation.
#[derive(Clone, Debug, Serialize)]
pub struct Counts {
    /// Nodes.
    pub nodes: usize,
    /// Unknowns (two per node).
    pub dofs: usize,
    /// Prescribed displacement components.
    pub constrained_dofs: usize,
    /// Interior cell faces (0 for FE).
    pub interior_faces: usize,
    /// Boundary cell faces (0 for FE).
    pub boundary_faces: usize,
    /// Stored entries of `K`.
    pub matrix_nonzeros: usize,
    /// `matrix_nonzeros / dofs`.
    pub matrix_nonzeros_per_row: f64,
    /// Finite elements (FE only).
    pub elements: Option<usize>,
}

/// The factorisation of `K`; the fields after `supernodes` exist for the static-pivoting LU
/// only (null for faer's LU).
#[derive(Clone, Debug, Serialize)]
pub struct LinearSolve {
    /// Which LU.
    pub method: FactorMethod,
    /// Factor precision.
    pub precision: FactorPrecision,
    /// Supernodes of the factorisation.
    pub supernodes: usize,
    /// Stored entries of the factors.
    pub factor_nonzeros: Option<usize>,
    /// Tiny pivots replaced by a perturbation.
    pub perturbed_pivots: Option<usize>,
    /// Right-hand sides solved.
    pub columns_solved: Option<usize>,
    /// Iterative refinement steps.
    pub refinement_steps: Option<usize>,
    /// Columns solved again with double-precision factors: 0 (mixed precision finishes
    /// stalled columns with GMRES-IR instead, below); kept so that summaries keep their keys.
    pub columns_in_double: Option<usize>,
    /// Mixed precision only: columns that plain refinement could not finish and that
    /// GMRES-IR did (absent in double precision).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gmres_columns: Option<usize>,
    /// Mixed precision only: GMRES iterations over those columns.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gmres_iterations: Option<usize>,
    /// Largest normwise backward error after refinement.
    pub worst_backward_error: Option<f64>,
}

/// Residual and global force balance of one body.
#[derive(Clone, Debug, Serialize)]
pub struct Checks {
    /// `‖K û − f‖ / ‖f‖`.
    pub relative_residual: f64,
    /// Global force balance, relative.
    pub equilibrium_error: f64,
    /// `Σ f`.
    pub applied_force: [f64; 2],
    /// `Σ R`.
    pub reaction_force: [f64; 2],
    /// `Σ ν P`.
    pub contact_force: [f64; 2],
    /// Whether every check in `verdicts` passed. A run with a failing check still writes its
    /// outputs, and the command line ends it with exit status 3.
    pub passed: bool,
    /// Every check of the run against its tolerance: each body's residual and equilibrium,
    /// the contact answer's complementarity, and the worst load increment's.
    pub verdicts: Vec<Verdict>,
}

/// One check of a run against its tolerance (`checks.verdicts`).
#[derive(Clone, Debug, Serialize)]
pub struct Verdict {
    /// `"relative_residual"`, `"equilibrium_error"` or `"complementarity"`.
    pub check: &'static str,
    /// Where `summary.json` reports the value (`checks.equilibrium_error`,
    /// `bodies[1].equilibrium_error`, `lcp`, `steps[3].complementarity`, …).
    pub key: String,
    /// The measured value.
    pub value: f64,
    /// The largest value accepted ([`crate::solution::RESIDUAL_TOLERANCE`],
    /// [`crate::solution::EQUILIBRIUM_TOLERANCE`],
    /// [`crate::solution::COMPLEMENTARITY_TOLERANCE`]).
    pub tolerance: f64,
    /// `value ≤ tolerance` (false for a value that is not a number).
    pub pass: bool,
}

impl Verdict {
    pub(crate) fn new(check: &'static str, key: String, value: f64, tolerance: f64) -> Self {
        Self { check, key, value, tolerance, pass: value <= tolerance }
    }

    /// What to do about a failure of this check.
    pub fn remedy(&self) -> &'static str {
        match self.check {
            "complementarity" => {
                "the contact solver's answer is inaccurate: try `[contact] solver = \"active_set\"` or a coarser contact edge (a larger nodes.spacing)"
            }
            "step_complementarity" => {
                "a time step's contact impulses are inaccurate: try a smaller dynamics.time_step or a coarser contact edge (a larger nodes.spacing)"
            }
            _ => {
                "the magnitudes are out of scale for double precision: compare material.young between the bodies, the boundary[*] values with the body's size and the loads with the stiffness, and rescale the units"
            }
        }
    }
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} = {:.3e} ({}) {} its tolerance {:.0e}",
            self.key,
            self.value,
            self.check.replace('_', " "),
            if self.pass { "within" } else { "above" },
            self.tolerance
        )
    }
}

/// Every check of a solution against its tolerance, keyed as `summary.json` reports the
/// values (the first body's as `checks.*`, the others' as `second_body.*` or `bodies[k].*`).
fn verdicts(solution: &Solution) -> Vec<Verdict> {
    use crate::solution::{COMPLEMENTARITY_TOLERANCE, EQUILIBRIUM_TOLERANCE, RESIDUAL_TOLERANCE};
    let mut out = Vec::new();
    let mut body = |prefix: &str, s: &Solution| {
        out.push(Verdict::new(
            "relative_residual",
            format!("{prefix}.relative_residual"),
            s.relative_residual,
            RESIDUAL_TOLERANCE,
        ));
        out.push(Verdict::new(
            "equilibrium_error",
            format!("{prefix}.equilibrium_error"),
            s.equilibrium_error,
            EQUILIBRIUM_TOLERANCE,
        ));
    };
    for (k, s) in solution.bodies().enumerate() {
        // The second body of one pair keeps its `second_body` key (an alias of `bodies[1]`).
        let prefix = match k {
            0 => "checks".to_string(),
            1 if solution.second_body().is_some() => "second_body".to_string(),
            k => format!("bodies[{k}]"),
        };
        body(&prefix, s);
    }
    let lcp =
        solution.contact().map(|c| &c.lcp).or_else(|| solution.multibody().map(|m| &m.contact.lcp));
    if let Some(l) = lcp {
        let value = l.residuals.max_violation();
        out.push(Verdict::new("complementarity", "lcp".into(), value, COMPLEMENTARITY_TOLERANCE));
    }
    if let Some(f) = solution.contact().and_then(|c| c.friction.as_ref()) {
        out.push(Verdict::new(
            "complementarity",
            "contact.friction_residual".into(),
            f.step.residuals.max(),
            COMPLEMENTARITY_TOLERANCE,
        ));
        // The worst increment of each measure (NaN first: it fails).
        let worst =
            |v: &dyn Fn(&IncrementRecord) -> f64| {
                f.increments.iter().enumerate().map(|(k, r)| (k, v(r))).reduce(|a, b| {
                    if a.1.is_nan() || (!b.1.is_nan() && a.1 >= b.1) { a } else { b }
                })
            };
        if let Some((k, value)) = worst(&|r| r.complementarity) {
            let key = format!("steps[{k}].complementarity");
            out.push(Verdict::new("complementarity", key, value, COMPLEMENTARITY_TOLERANCE));
        }
        if let Some((k, value)) = worst(&|r| r.equilibrium_error) {
            let key = format!("steps[{k}].equilibrium_error");
            out.push(Verdict::new("equilibrium_error", key, value, EQUILIBRIUM_TOLERANCE));
        }
    }
    out
}

/// Headline results.
#[derive(Clone, Debug, Serialize)]
pub struct Results {
    /// Largest `|u^h|` at a node.
    pub max_displacement: f64,
    /// Largest von Mises stress at a node.
    pub max_von_mises: f64,
}

/// The LCP and the run-time checks of `M`.
#[derive(Clone, Debug, Serialize)]
pub struct LcpSummary {
    /// Candidates.
    pub size: usize,
    /// Lemke pivots.
    pub pivots: usize,
    /// `min z`.
    pub min_z: f64,
    /// `min w`.
    pub min_w: f64,
    /// `max |z_i w_i|`.
    pub max_complementarity: f64,
    /// `‖w − M z − q‖_∞`.
    pub equation_residual: f64,
    /// The scale the residuals are relative to.
    pub residual_scale: f64,
    /// Smallest diagonal entry of `M` (absent when `M` was not formed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compliance_min_diagonal: Option<f64>,
    /// Smallest eigenvalue of `(M + Mᵀ)/2`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compliance_min_symmetric_eigenvalue: Option<f64>,
    /// Largest eigenvalue of `(M + Mᵀ)/2`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compliance_max_symmetric_eigenvalue: Option<f64>,
    /// How the two eigenvalues were computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compliance_eigenvalue_method: Option<EigenvalueMethod>,
    /// `‖M − Mᵀ‖ / ‖M + Mᵀ‖`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compliance_skew_ratio: Option<f64>,
    /// `"lemke"` or `"active_set"` (`contact.solver`, with `"auto"` resolved): the solver
    /// that produced the answer.
    pub solver: &'static str,
    /// With `contact.solver = "auto"`, why Lemke failed before the active-set solver answered
    /// (its pivots, residual and the conditioning of `M`); absent when the first solver
    /// tried answered.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fallback_from: Option<String>,
    /// The active-set solver's record (docs/method.md §5.1); `pivots` then counts its linear
    /// solves.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub active_set: Option<ActiveSetSummary>,
    /// The polish of Lemke's answer on its closed set (`crate::lcp::polish`): whether it
    /// was accepted and the closed-set residual before and after (absent on the other paths).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lemke_polish: Option<crate::lcp::Polish>,
    /// `precision = "mixed"` on the Lemke path only: the correction of the answer against the
    /// displacements' own gaps, with the closed candidates' largest `|gap|` before and after
    /// (`crate::solution::correct_closed_gaps`; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gap_correction: Option<crate::solution::GapCorrection>,
}

/// What the active-set solver did (docs/method.md §5.1).
#[derive(Clone, Debug, Serialize)]
pub struct ActiveSetSummary {
    /// Linear solves.
    pub iterations: usize,
    /// Candidates whose status changed after each iteration (the last is 0).
    pub changes_per_iteration: Vec<usize>,
    /// Lemke rescues of the changing candidates, with the candidates each handled.
    pub rescues: Vec<usize>,
    /// `"converged"` or `"converged_after_rescue"`.
    pub end: crate::lcp::active_set::ActiveSetEnd,
    /// Factorisations of row-replaced matrices, low-rank update columns and their times.
    pub work: crate::contact::sparse::RigidObstacleStats,
}

/// The contact result.
#[derive(Clone, Debug, Serialize)]
pub struct ContactSummary {
    /// Candidates.
    pub candidates: usize,
    /// Closed candidates.
    pub closed: usize,
    /// Maximal runs of closed candidates.
    pub closed_intervals: usize,
    /// `Σ P_c` (an axisymmetric body: the rings' total forces, [`RING_NOTE`]).
    pub total_force: f64,
    /// An axisymmetric body: `Σ ν_c,z P_c`, the axial resultant of the rings' forces on the
    /// body over the whole circumference (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axial_force: Option<f64>,
    /// An axisymmetric body: what the contact forces mean ([`RING_NOTE`]; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub units_note: Option<&'static str>,
    /// Onset from the gaps, clipped to the bracket.
    pub onset_x: Option<f64>,
    /// Onset from the gaps, unclipped.
    pub onset_x_unclipped: Option<f64>,
    /// Onset from the pressures.
    pub onset_x_from_pressure: Option<f64>,
    /// The last open candidate before the first closed one.
    pub last_open_x: Option<f64>,
    /// The first closed candidate.
    pub first_closed_x: Option<f64>,
    /// The gap below which a candidate counts as closed.
    pub gap_tolerance: f64,
    /// Largest difference between the MLS gap and the LCP's `w`.
    pub max_gap_mismatch: f64,
    /// The checks of `M` that failed but were overridden.
    pub warning: Option<String>,
    /// What the onset fields mean ([`ONSET_NOTE`]).
    pub onset_note: &'static str,
    /// The friction coefficient `μ` (friction only; the friction keys are absent otherwise, so
    /// that frictionless summaries are unchanged).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_coefficient: Option<f64>,
    /// `Σ T_c`, the tangential contact force on the body along `t` (friction only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub total_tangential_force: Option<f64>,
    /// The stick zones of the final increment as `[start, end]` intervals of the coordinate
    /// `x·t` along the tangent, from outer candidate to outer candidate of each maximal run
    /// of sticking candidates (friction only; [`crate::solution::ContactSolution::friction_zones`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stick_zones: Option<Vec<[f64; 2]>>,
    /// The slip zones (either sign), as `stick_zones` (friction only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slip_zones: Option<Vec<[f64; 2]>>,
    /// The numbers of stick and of slip zones (friction only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stick_slip_zone_counts: Option<[usize; 2]>,
    /// Candidates that stick, that slip (friction only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stick_slip_counts: Option<[usize; 2]>,
    /// Which method solved the frictional step (friction only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_solver: Option<FrictionMethod>,
    /// Fixed-point and active-set rounds of the frictional step (friction only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_iterations: Option<usize>,
    /// Largest scaled residual of the frictional step (friction only; docs/method.md §8).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_residual: Option<f64>,
    /// Why Lemke on the step LCP was not accepted, when the fallback answered (friction only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_lemke_failure: Option<String>,
    /// The rigid obstacle pressed by a force (`[[step]] obstacle_force` only;
    /// docs/method.md §4.6).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_driven: Option<LoadDrivenSummary>,
    /// The body's rigid-body translation held by the contact alone (docs/method.md §4.7).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rigid_mode: Option<RigidModeSummary>,
}

/// A rigid-body translation of the body resolved by the contact (docs/method.md §4.7).
#[derive(Clone, Debug, Serialize)]
pub struct RigidModeSummary {
    /// `"translation in x"` or `"translation in y"`.
    pub mode: &'static str,
    /// The pinned node's position (the translation is its displacement).
    pub pin_point: [f64; 2],
    /// The body's translation.
    pub translation: [f64; 2],
    /// The applied load's component along the mode.
    pub load_along_mode: f64,
    /// LCP solves of the last increment's search.
    pub lcp_solves: usize,
    /// LCP solves of all increments' searches.
    pub lcp_solves_all_increments: usize,
}

impl RigidModeSummary {
    /// The summary of `r`.
    fn new(r: &crate::solution::RigidMode) -> Self {
        Self {
            mode: r.mode,
            pin_point: r.pin_point,
            translation: r.translation,
            load_along_mode: r.load,
            lcp_solves: r.evaluations,
            lcp_solves_all_increments: r.total_evaluations,
        }
    }
}

/// A rigid obstacle pressed by a prescribed force: the force and the displacement it found
/// (docs/method.md §4.6).
#[derive(Clone, Debug, Serialize)]
pub struct LoadDrivenSummary {
    /// The prescribed force `F` on the obstacle at the end of the last step.
    pub obstacle_force: [f64; 2],
    /// The obstacle's displacement `s e` that balances it.
    pub obstacle_displacement: [f64; 2],
    /// `s`, the displacement along `e = F/|F|`.
    pub displacement_along_force: f64,
    /// `Σ_c (ν_c·e) P_c`, the force the contact carries along `e`.
    pub carried_force: f64,
    /// LCP solves of the last increment's search.
    pub lcp_solves: usize,
    /// LCP solves of all increments' searches.
    pub lcp_solves_all_increments: usize,
}

impl LoadDrivenSummary {
    /// The summary of `l`.
    fn new(l: &crate::solution::LoadDriven) -> Self {
        Self {
            obstacle_force: l.force,
            obstacle_displacement: l.displacement,
            displacement_along_force: l.displacement_along,
            carried_force: l.carried,
            lcp_solves: l.evaluations,
            lcp_solves_all_increments: l.total_evaluations,
        }
    }
}

/// One contact pair.
#[derive(Clone, Debug, Serialize)]
pub struct PairSummary {
    /// The body carrying the candidates.
    pub body: String,
    /// Its contact edge.
    pub edge: String,
    /// The target body (`null` for obstacles).
    pub target_body: Option<String>,
    /// The target body's edge (`null` for obstacles).
    pub target_edge: Option<String>,
    /// Candidates.
    pub candidates: usize,
    /// Closed candidates.
    pub closed: usize,
    /// Maximal runs of closed candidates.
    pub closed_intervals: usize,
    /// `Σ P_c`.
    pub total_force: f64,
    /// `Σ ν_c P_c`: the resultant of the pair's forces on the candidate body.
    pub resultant: [f64; 2],
    /// Points of the contact edge beside the target edge (no partner, no candidate).
    pub unpaired: usize,
    /// The gap below which a candidate counts as closed.
    pub gap_tolerance: f64,
    /// Smallest contact force `min P_c` (≥ 0 up to round-off).
    pub min_force: f64,
    /// Smallest LCP gap `min w_c` (≥ 0 up to round-off).
    pub min_gap: f64,
    /// `max |P_c w_c|`: complementarity, unscaled.
    pub max_force_times_gap: f64,
    /// Largest difference between the MLS gap and the LCP's `w`.
    pub max_gap_mismatch: f64,
    /// The pair's frictional answer (friction or `[[step]]` only; absent otherwise, so that
    /// frictionless summaries are unchanged).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<PairFriction>,
    /// The rigid obstacles pressed by a force (`[[step]] obstacle_force`, pairs against rigid
    /// obstacles only; the same record on each: the obstacles move together).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_driven: Option<LoadDrivenSummary>,
}

/// One pair's frictional answer at the end of the load path (docs/method.md §8).
#[derive(Clone, Debug, Serialize)]
pub struct PairFriction {
    /// The pair's `μ` in the last step.
    pub coefficient: f64,
    /// `Σ T_c` on the candidate body along `t`.
    pub total_tangential_force: f64,
    /// Candidates that stick, that slip.
    pub stick_slip_counts: [usize; 2],
    /// Largest scaled residual of the last step (the whole LCP's).
    pub residual: f64,
    /// Load increments of the path.
    pub increments: usize,
}

/// One body's size and checks.
#[derive(Clone, Debug, Serialize)]
pub struct BodySummary {
    /// Its name.
    pub name: Option<String>,
    /// Nodes.
    pub nodes: usize,
    /// Unknowns.
    pub dofs: usize,
    /// `‖K û − f‖ / ‖f‖`.
    pub relative_residual: f64,
    /// Global force balance, relative.
    pub equilibrium_error: f64,
    /// `Σ f`.
    pub applied_force: [f64; 2],
    /// `Σ R`.
    pub reaction_force: [f64; 2],
    /// `Σ ν P`.
    pub contact_force: [f64; 2],
    /// Several bodies or pairs (`[[contact]]` tables): this body's rigid translation held by
    /// contact alone (docs/method.md §4.7; one pair: `contact.rigid_mode`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rigid_mode: Option<RigidModeSummary>,
}

impl Summary {
    /// The summary of a solved problem (`input` is the echo of the problem file).
    pub fn new(input: Value, problem: &Problem, model: &Model, solution: &Solution) -> Self {
        let f = model.factorisation.stats();
        // The factor size and the refinement record exist for the static-pivoting LU only.
        let is_static = f.method == FactorMethod::StaticPivoting;
        let only_static = |v| is_static.then_some(v);
        let mixed = is_static && f.precision == FactorPrecision::Mixed;
        let matrix = &model.system.matrix;
        Self {
            schema_version: SCHEMA_VERSION,
            program: Program { name: env!("CARGO_PKG_NAME"), version: env!("CARGO_PKG_VERSION") },
            input,
            problem: ProblemEcho {
                name: problem.name.clone(),
                method: problem.discretisation.method,
                material: problem.material,
                discretisation: problem.discretisation,
                layout: problem.layout,
                node_spacing: problem.node_spacing,
            },
            counts: Counts {
                nodes: model.nodes.len(),
                dofs: model.nodes.dof_count(),
                constrained_dofs: model.system.constraints.len(),
                interior_faces: model.mfvm().map_or(0, |m| m.faces.interior.len()),
                boundary_faces: model.mfvm().map_or(0, |m| m.faces.boundary.len()),
                matrix_nonzeros: matrix.values.len(),
                matrix_nonzeros_per_row: matrix.values.len() as f64 / matrix.n.max(1) as f64,
                elements: model.mesh().map(|m| m.element_count()),
            },
            linear_solve: LinearSolve {
                method: f.method,
                precision: f.precision,
                supernodes: f.supernodes,
                factor_nonzeros: only_static(f.factor_nnz),
                perturbed_pivots: only_static(f.perturbed_pivots),
                columns_solved: only_static(f.columns_solved),
                refinement_steps: only_static(f.refinement_steps),
                columns_in_double: only_static(0),
                gmres_columns: mixed.then_some(f.gmres_columns),
                gmres_iterations: mixed.then_some(f.gmres_iterations),
                worst_backward_error: is_static.then_some(f.worst_backward_error),
            },
            checks: {
                let verdicts = verdicts(solution);
                Checks {
                    relative_residual: solution.relative_residual,
                    equilibrium_error: solution.equilibrium_error,
                    applied_force: solution.applied_force,
                    reaction_force: solution.reaction_force,
                    contact_force: solution.contact_force,
                    passed: verdicts.iter().all(|v| v.pass),
                    verdicts,
                }
            },
            results: Results {
                max_displacement: solution
                    .displacement
                    .iter()
                    .map(|u| u[0].hypot(u[1]))
                    .fold(0.0, f64::max),
                max_von_mises: solution
                    .von_mises(&problem.material)
                    .into_iter()
                    .fold(0.0, f64::max),
            },
            lcp: solution
                .contact()
                .map(|c| LcpSummary {
                    size: c.candidates.len(),
                    pivots: c.lcp.pivots,
                    min_z: c.lcp.residuals.min_z,
                    min_w: c.lcp.residuals.min_w,
                    max_complementarity: c.lcp.residuals.max_complementarity,
                    equation_residual: c.lcp.residuals.equation_residual,
                    residual_scale: c.lcp.residuals.scale,
                    compliance_min_diagonal: c.condensed.as_ref().map(|m| m.min_diagonal),
                    compliance_min_symmetric_eigenvalue: c
                        .condensed
                        .as_ref()
                        .map(|m| m.min_symmetric_eigenvalue),
                    compliance_max_symmetric_eigenvalue: c
                        .condensed
                        .as_ref()
                        .map(|m| m.max_symmetric_eigenvalue),
                    compliance_eigenvalue_method: c.condensed.as_ref().map(|m| m.eigenvalue_method),
                    compliance_skew_ratio: c.condensed.as_ref().map(|m| m.skew_ratio),
                    solver: if c.active_set.is_some() { "active_set" } else { "lemke" },
                    fallback_from: c.fallback_from.clone(),
                    active_set: c.active_set.as_ref().map(|a| ActiveSetSummary {
                        iterations: a.iterations,
                        changes_per_iteration: a.changes.clone(),
                        rescues: a.rescues.clone(),
                        end: a.end,
                        work: a.work,
                    }),
                    lemke_polish: c.lemke_polish,
                    gap_correction: c.gap_correction,
                })
                .or_else(|| multibody_lcp(solution)),
            contact: solution.contact().map(|c| ContactSummary {
                candidates: c.candidates.len(),
                closed: c.closed.iter().filter(|&&v| v).count(),
                closed_intervals: c.onset.closed_intervals,
                total_force: c.total_force,
                axial_force: model.system.axisymmetric.then(|| {
                    c.candidates.normals.iter().zip(&c.lcp.z).map(|(n, p)| n[1] * p).sum()
                }),
                units_note: model.system.axisymmetric.then_some(RING_NOTE),
                onset_x: c.onset.from_gap,
                onset_x_unclipped: c.onset.from_gap_raw,
                onset_x_from_pressure: c.onset.from_pressure,
                last_open_x: c.onset.last_open,
                first_closed_x: c.onset.first_closed,
                gap_tolerance: c.gap_tolerance,
                max_gap_mismatch: c.max_gap_mismatch(),
                warning: c.warning.clone(),
                onset_note: ONSET_NOTE,
                friction_coefficient: c.friction.as_ref().map(|f| f.coefficient),
                total_tangential_force: c.friction.as_ref().map(|f| f.total_force),
                stick_zones: c.friction_zones().map(|z| z.stick),
                slip_zones: c.friction_zones().map(|z| z.slip),
                stick_slip_zone_counts: c.friction.as_ref().map(|f| [f.stick_zones, f.slip_zones]),
                stick_slip_counts: c.friction.as_ref().map(|f| {
                    let st = &f.step.state;
                    [
                        st.iter().filter(|s| **s == ContactState::Stick).count(),
                        st.iter().filter(|s| s.is_slip()).count(),
                    ]
                }),
                friction_solver: c.friction.as_ref().map(|f| f.step.method),
                friction_iterations: c.friction.as_ref().map(|f| f.step.iterations),
                friction_residual: c.friction.as_ref().map(|f| f.step.residuals.max()),
                friction_lemke_failure: c
                    .friction
                    .as_ref()
                    .and_then(|f| f.step.lemke_failure.clone()),
                load_driven: c.load_driven.as_ref().map(LoadDrivenSummary::new),
                rigid_mode: c.rigid_mode.as_ref().map(RigidModeSummary::new),
            }),
            second_body: solution
                .second_body()
                .map(|s2| BodySummary::new(problem.second_body().map(|p| &p.name), s2)),
            bodies: every_body(problem, solution),
            pairs: every_pair(problem, solution),
            steps: solution
                .contact()
                .and_then(|c| c.friction.as_ref())
                .map(|f| f.increments.clone()),
            refinement: None,
            warnings: warnings(problem, solution),
            timings: solution.timings.iter().map(|t| (t.stage, t.seconds)).collect(),
        }
    }

    /// Whether the contact result is given pair by pair (a scene of `[[contact]]` tables,
    /// without the one `contact` block of a single pair): the console and the report list
    /// `bodies` and `pairs` then.
    pub fn by_pair(&self) -> bool {
        self.contact.is_none() && !self.pairs.is_empty()
    }

    /// The checks that failed (`checks.verdicts` whose `pass` is false).
    pub fn failed_checks(&self) -> Vec<&Verdict> {
        self.checks.verdicts.iter().filter(|v| !v.pass).collect()
    }

    /// Total seconds over the recorded stages.
    pub fn total_seconds(&self) -> f64 {
        self.timings.values().sum()
    }

    /// The summary as pretty-printed JSON with sorted keys (the text of `summary.json`).
    pub fn to_json(&self) -> String {
        // Through `Value` (a sorted map) so that the keys are sorted at every level.
        serde_json::to_value(self)
            .and_then(|v| serde_json::to_string_pretty(&v))
            .unwrap_or_default()
    }
}

impl BodySummary {
    /// The size and checks of the body named `name` solved as `s`.
    fn new(name: Option<&String>, s: &Solution) -> Self {
        Self {
            name: name.cloned(),
            nodes: s.displacement.len(),
            dofs: 2 * s.displacement.len(),
            relative_residual: s.relative_residual,
            equilibrium_error: s.equilibrium_error,
            applied_force: s.applied_force,
            reaction_force: s.reaction_force,
            contact_force: s.contact_force,
            rigid_mode: None,
        }
    }
}

/// Every body's checks, the first body first (as [`Problem::bodies`]), with the rigid
/// translation the contact holds for the bodies that have one.
fn every_body(problem: &Problem, solution: &Solution) -> Vec<BodySummary> {
    let held = solution.multibody().map_or(&[][..], |m| &m.contact.held);
    problem
        .bodies()
        .zip(solution.bodies())
        .enumerate()
        .map(|(k, (p, s))| BodySummary {
            rigid_mode: held.iter().find(|(b, _)| *b == k).map(|(_, r)| RigidModeSummary::new(r)),
            ..BodySummary::new(Some(&p.name), s)
        })
        .collect()
}

/// Each contact pair's result, in the order of [`Problem::pairs`] (empty without contact).
fn every_pair(problem: &Problem, solution: &Solution) -> Vec<PairSummary> {
    let edge_name = |b: usize, e: usize| {
        problem.body(b).map(|p| p.domain.edge_names()[e].clone()).unwrap_or_default()
    };
    let target_edge = |target_body: Option<usize>, target| match (target_body, target) {
        (Some(t), crate::problem::ContactTarget::Body { edge }) => Some(edge_name(t, edge)),
        _ => None,
    };
    let body_name = |b: Option<usize>| b.and_then(|b| problem.body(b)).map(|p| p.name.clone());
    problem
        .pairs()
        .iter()
        .zip(solution.pairs())
        .map(|(pair, c)| PairSummary {
            target_body: body_name(pair.target_body),
            target_edge: target_edge(pair.target_body, pair.spec.target),
            ..PairSummary::new(
                body_name(Some(pair.body)).unwrap_or_default(),
                edge_name(pair.body, pair.spec.edge),
                c,
            )
        })
        .collect()
}

impl PairSummary {
    /// The result `c` of the pair whose candidates lie on `edge` of `body`, against rigid
    /// obstacles (the caller names a target body).
    fn new(body: String, edge: String, c: &crate::solution::ContactSolution) -> Self {
        let fold =
            |v: &mut dyn Iterator<Item = f64>, f: fn(f64, f64) -> f64, start| v.fold(start, f);
        Self {
            body,
            edge,
            target_body: None,
            target_edge: None,
            candidates: c.candidates.len(),
            closed: c.closed.iter().filter(|&&v| v).count(),
            closed_intervals: c.onset.closed_intervals,
            total_force: c.total_force,
            resultant: c.candidates.operator.resultant(&c.lcp.z),
            unpaired: c.unpaired,
            gap_tolerance: c.gap_tolerance,
            min_force: fold(&mut c.lcp.z.iter().copied(), f64::min, f64::INFINITY),
            min_gap: fold(&mut c.lcp.w.iter().copied(), f64::min, f64::INFINITY),
            max_force_times_gap: fold(
                &mut c.lcp.z.iter().zip(&c.lcp.w).map(|(z, w)| (z * w).abs()),
                f64::max,
                0.0,
            ),
            max_gap_mismatch: c.max_gap_mismatch(),
            friction: c.friction.as_ref().map(|f| PairFriction {
                coefficient: f.coefficient,
                total_tangential_force: f.total_force,
                stick_slip_counts: [
                    f.step.state.iter().filter(|s| **s == ContactState::Stick).count(),
                    f.step.state.iter().filter(|s| s.is_slip()).count(),
                ],
                residual: f.step.residuals.max(),
                increments: f.increments.len(),
            }),
            load_driven: c.load_driven.as_ref().map(LoadDrivenSummary::new),
        }
    }
}

/// The LCP of a problem with several bodies or pairs (`None` otherwise).
fn multibody_lcp(solution: &Solution) -> Option<LcpSummary> {
    let ms = solution.multibody()?;
    let (r, m) = (&ms.contact.lcp.residuals, ms.contact.condensed.as_ref());
    Some(LcpSummary {
        size: ms.contact.lcp.z.len(),
        pivots: ms.contact.lcp.pivots,
        min_z: r.min_z,
        min_w: r.min_w,
        max_complementarity: r.max_complementarity,
        equation_residual: r.equation_residual,
        residual_scale: r.scale,
        compliance_min_diagonal: m.map(|m| m.min_diagonal),
        compliance_min_symmetric_eigenvalue: m.map(|m| m.min_symmetric_eigenvalue),
        compliance_max_symmetric_eigenvalue: m.map(|m| m.max_symmetric_eigenvalue),
        compliance_eigenvalue_method: m.map(|m| m.eigenvalue_method),
        compliance_skew_ratio: m.map(|m| m.skew_ratio),
        solver: if ms.contact.active_set.is_some() { "active_set" } else { "lemke" },
        fallback_from: ms.contact.fallback_from.clone(),
        active_set: ms.contact.active_set.as_ref().map(|a| ActiveSetSummary {
            iterations: a.iterations,
            changes_per_iteration: a.changes.clone(),
            rescues: a.rescues.clone(),
            end: a.end,
            work: a.work,
        }),
        lemke_polish: None,
        gap_correction: None,
    })
}

/// Everything the run proceeded past: an unstable discretisation accepted with
/// `allow_unstable`, a contact compliance accepted with `allow_indefinite`, Lemke's failure
/// that `contact.solver = "auto"` answered with the active-set solver, a contact zone closed
/// by fewer candidates than [`super::resolution::MIN_CLOSED`].
fn warnings(problem: &Problem, solution: &Solution) -> Vec<String> {
    let disc = problem.discretisation.stability_warning().map(|w| format!("discretisation: {w}"));
    let contact = solution.contact().and_then(|c| c.warning.clone());
    let unpaired = solution.contact().filter(|c| c.unpaired > 0).map(|c| {
        format!(
            "contact: {} nodes of the contact edge lie beside the target edge; they have no partner and cannot close",
            c.unpaired
        )
    });
    let fallback = solution.contact().and_then(|c| c.fallback_from.as_ref()).map(|w| {
        format!("contact: {w}; the active-set solver answered instead (contact.solver = \"auto\")")
    });
    let several = solution.multibody();
    let several_warning = several.and_then(|m| m.contact.warning.clone());
    let several_fallback = several.and_then(|m| m.contact.fallback_from.as_ref()).map(|w| {
        format!(
            "contact: {w}; the active-set solver answered instead (contact[k].solver = \"auto\")"
        )
    });
    let several_unpaired = several.into_iter().flat_map(|m| m.pairs.iter().enumerate()).filter(|(_, c)| c.unpaired > 0).map(|(k, c)| {
        format!(
            "contact[{k}]: {} nodes of the contact edge lie beside the target edge; they have no partner and cannot close",
            c.unpaired
        )
    });
    let resolution =
        solution.contact().into_iter().filter_map(|c| super::resolution::warning("contact", c));
    let several_resolution = several
        .into_iter()
        .flat_map(|m| m.pairs.iter().enumerate())
        .filter_map(|(k, c)| super::resolution::warning(&format!("contact[{k}]"), c));
    disc.into_iter()
        .chain(contact.map(|w| format!("contact: {w}")))
        .chain(resolution)
        .chain(several_resolution)
        .chain(unpaired)
        .chain(fallback)
        .chain(several_warning.map(|w| format!("contact: {w}")))
        .chain(several_fallback)
        .chain(several_unpaired)
        .collect()
}
