//! Stage 10: recovery — from the nodal parameters `û` (and the contact forces) to what is
//! reported: the displacement `u^h` and the stresses at the nodes, the reactions, the contact
//! table (gaps, pressures, closed set, onset) and the global checks (residual, equilibrium).

use crate::assembly::GlobalSystem;
use crate::contact::{self, BodyOperator};
use crate::geometry;
use crate::lcp;
use crate::linear_solve;
use crate::material;
use crate::model::Model;
use crate::nodes::{Axis, dof};
use crate::problem::{ContactSpec, Problem};
use crate::progress::StageTiming;

/// Largest accepted `relative_residual` `‖K û − f‖ / ‖f‖` of a body (`f` with the contact
/// forces and the prescribed values; `f = 0` gives `û = 0` and a residual of 0). The shipped
/// problems reach at most 6.7e-12 (the FE beam); the 10⁶-node cantilever and strip of
/// docs/dev/performance.md 6.7e-10 and 2.4e-10. A run beyond it is written but fails
/// (exit status 3, `summary.json` `checks.passed = false`).
pub const RESIDUAL_TOLERANCE: f64 = 1e-6;

/// Largest accepted `equilibrium_error` of a body and of every load increment. The shipped
/// problems reach at most 1.5e-11 (the FE beam), the 10⁶-node strip 5.0e-10; a clamp moved
/// rigidly by 10¹² (0.65) or a block 10¹⁵ times stiffer than its neighbours (7e-4) fail.
pub const EQUILIBRIUM_TOLERANCE: f64 = 1e-6;

/// Largest accepted complementarity violation of the contact answer: the LCP's
/// [`lcp::LcpResiduals::max_violation`] and the frictional step's residual (scaled as
/// docs/method.md §5 and §8 say), for the final answer and every load increment. The
/// frictional step solvers accept the same ([`lcp::friction::FRICTION_TOLERANCE`]); Lemke refuses only
/// above 1e-6, so a Lemke answer between the two is written but fails. The shipped problems
/// reach at most 1.4e-15.
pub const COMPLEMENTARITY_TOLERANCE: f64 = 1e-9;

/// The solution and its checks.
#[derive(Debug)]
pub struct Solution {
    /// Fictitious nodal parameters `û` (interleaved; the nodal displacements for FE).
    pub nodal_parameters: Vec<f64>,
    /// `u^h(x_I)` at every node (MLS-evaluated).
    pub displacement: Vec<[f64; 2]>,
    /// Collocated strains `ε̂_I = (ε_xx, ε_yy, γ_xy)`.
    pub strain: Vec<[f64; 3]>,
    /// Stresses `σ_I = D ε̂_I = (σ_xx, σ_yy, σ_xy)`. `ε̂_I = Σ_K B_K(x_I) û_K` is both the
    /// collocated strain and the direct MLS strain at the node, so the nodal stress output is
    /// the same formula for every `β` (the blend only concerns the cell-boundary points).
    /// In axisymmetry `(σ_rr, σ_zz, σ_rz)`, including the hoop coupling `λ ε_θθ`.
    pub stress: Vec<[f64; 3]>,
    /// Axisymmetric bodies: the hoop strain and stress `(ε_θθ, σ_θθ)` at every node
    /// (docs/method.md §9.2); empty in plane stress and strain.
    pub hoop: Vec<[f64; 2]>,
    /// Reactions at constrained DOFs: `(node, axis, R)` with `R = K_int û − f − E P`.
    pub reactions: Vec<(u32, Axis, f64)>,
    /// Total applied load `Σ f` (tractions and body force).
    pub applied_force: [f64; 2],
    /// Total reaction `Σ R`.
    pub reaction_force: [f64; 2],
    /// Total contact force on the body `Σ ν P_c` (zero without contact; per radian for an
    /// axisymmetric body, as the applied and reaction totals, `contact::rings`).
    pub contact_force: [f64; 2],
    /// The other bodies' solutions, as [`crate::problem::Problem::others`] (empty for one
    /// body; each holds no bodies and no pairs of its own).
    pub others: Vec<Solution>,
    /// Every contact pair's solution, as [`crate::problem::Problem::contact_pairs`] (empty
    /// without contact). In a scene of pairs each holds its share of the one LCP (`lcp.z`,
    /// `lcp.w`; pivots and residuals are the whole LCP's).
    pub contact_pairs: Vec<ContactSolution>,
    /// The one LCP of a scene of pairs over every pair's candidates
    /// ([`crate::problem::Problem::is_scene_of_pairs`]); `None` for one pair of the first
    /// body, whose record is its [`ContactSolution`].
    pub scene: Option<Box<SceneContact>>,
    /// `‖K û − f‖ / ‖f‖` of the solved system (checked against [`RESIDUAL_TOLERANCE`]).
    pub relative_residual: f64,
    /// `|Σ f + Σ R + Σ ν P| / max(|Σ f|, Σ |R|, Σ P)`: global force balance (checked against
    /// [`EQUILIBRIUM_TOLERANCE`]). `|Σ f|` is taken per component over `|f|`, so that a
    /// self-equilibrated load keeps its scale; when nothing loads the body (no load and no
    /// contact force) the scale is the internal force at the supports instead
    /// ([`equilibrium_error`]).
    pub equilibrium_error: f64,
    /// Stage timings.
    pub timings: Vec<StageTiming>,
}

impl Solution {
    /// The von Mises stress at every node, with the out-of-plane stress of `material`'s
    /// plane state: `σ_θθ` from [`Self::hoop`] in axisymmetry.
    pub fn von_mises(&self, material: &crate::material::Material) -> Vec<f64> {
        self.stress
            .iter()
            .enumerate()
            .map(|(i, s)| material.von_mises_with(*s, self.hoop.get(i).map(|h| h[1])))
            .collect()
    }
}

/// The contact solution of a scene of several bodies or contact pairs: one LCP over the
/// candidates of every pair, in pair order (docs/method.md §4.5). Each pair's own share is
/// its [`ContactSolution`] in [`Solution::contact_pairs`].
#[derive(Debug)]
pub struct SceneContact {
    /// The condensed problem over all candidates and its run-time checks (`None`: solved by
    /// the active-set method, which forms no `M`).
    pub condensed: Option<contact::CondensedContact>,
    /// The LCP's answer over all candidates (Lemke's, or the active set's as
    /// [`ContactSolution::lcp`] describes).
    pub lcp: lcp::LcpSolution,
    /// The active-set solver's record (`contact[k].solver = "active_set"`), `None` for Lemke.
    pub active_set: Option<ActiveSetRecord>,
    /// The compliance checks that failed but were overridden (`allow_indefinite`).
    pub warning: Option<String>,
    /// The bodies (0 the first) whose rigid translation the contact holds, each with that
    /// translation (docs/method.md §4.7), in body order; empty when every body is restrained.
    pub held: Vec<(usize, RigidMode)>,
    /// Why Lemke failed before the active-set method answered instead (`"auto"` on every
    /// pair; `None` when the answering solver was the first one tried).
    pub fallback_from: Option<String>,
}

/// The solution of a scene of pairs ([`Solution::multibody`]), borrowed: the other bodies,
/// every pair's share and the scene's one LCP.
#[derive(Clone, Copy, Debug)]
pub struct MultibodySolution<'a> {
    /// Bodies 2, 3, … (as [`crate::problem::Multibody::bodies`]).
    pub bodies: &'a [Solution],
    /// One contact solution per pair: its candidates, the target body's operator, its share
    /// of `z` and `w`, gaps, pressures, closed set.
    pub pairs: &'a [ContactSolution],
    /// The one LCP over every pair's candidates and its record.
    pub contact: &'a SceneContact,
}

/// The solution of the contact problem on the candidates.
#[derive(Debug)]
pub struct ContactSolution {
    /// Candidates (positions, arc length, owned segment, initial gap).
    pub candidates: contact::Candidates,
    /// Two bodies: the second body's operator (`d = −ν`, paired points' shapes and owners).
    pub target: Option<contact::BodyOperator>,
    /// Two bodies: the closest point of the second body paired with each candidate.
    pub paired_points: Vec<geometry::Point>,
    /// The condensed problem (`M`, `q`) and its run-time checks (`None` when the active-set
    /// solver answered without forming `M`, docs/method.md §5.1).
    pub condensed: Option<contact::CondensedContact>,
    /// The active-set solver's record (`None` for Lemke).
    pub active_set: Option<ActiveSetRecord>,
    /// Lemke's result: `z` = contact forces `P`, `w` = gaps.
    pub lcp: lcp::LcpSolution,
    /// MLS gaps from the final displacements: `g0 + ν·u_1^h(x_c) (− ν·u_2^h(y_c))`.
    pub gap: Vec<f64>,
    /// Contact pressure `P_c / |segment_c|`.
    pub pressure: Vec<f64>,
    /// Whether each candidate is closed (gap at most the tolerance).
    pub closed: Vec<bool>,
    /// The gap tolerance used.
    pub gap_tolerance: f64,
    /// Contact onset estimates.
    pub onset: contact::ContactOnset,
    /// `Σ P_c`.
    pub total_force: f64,
    /// A warning when the compliance checks failed but were overridden.
    pub warning: Option<String>,
    /// Two bodies: points of the contact edge beside the target edge, which have no partner
    /// and are no candidates.
    pub unpaired: usize,
    /// The frictional part of the answer (`μ > 0` or load steps only; docs/method.md §8).
    pub friction: Option<FrictionContact>,
    /// Why Lemke failed before the active-set solver answered instead (`contact.solver =
    /// "auto"` only; `None` when the answering solver was the first one tried).
    pub fallback_from: Option<String>,
    /// The rigid obstacle pressed by a force (`[[step]] obstacle_force` only): the
    /// displacement the force found (docs/method.md §4.6).
    pub load_driven: Option<LoadDriven>,
    /// The body's rigid-body translation held by the contact alone (docs/method.md §4.7).
    pub rigid_mode: Option<RigidMode>,
    /// The polish of Lemke's answer on its closed set ([`lcp::polish`]; the frictionless
    /// one-step Lemke path only).
    pub lemke_polish: Option<lcp::Polish>,
    /// Mixed precision only: the correction of Lemke's answer against the gaps of the
    /// displacements themselves ([`correct_closed_gaps`]).
    pub gap_correction: Option<GapCorrection>,
}

/// The correction of a Lemke answer whose `M` and `q` came from single-precision factors
/// (`precision = "mixed"`, [`correct_closed_gaps`]): the closed candidates' largest `|gap|`
/// from the displacements before and after it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GapCorrection {
    /// Closed candidates (`z > 0`).
    pub closed: usize,
    /// Largest `|g_c|` over them before the correction (the MLS gaps of the displacements).
    pub closed_gap_before: f64,
    /// Largest `|g_c|` over them after it (the same as before when not accepted).
    pub closed_gap_after: f64,
    /// Whether the corrected answer replaced Lemke's (it closes the gaps better).
    pub accepted: bool,
}

/// Gaps of moved displacements, or why they could not be computed.
pub type GapsOrError = Result<Vec<f64>, crate::Error>;

/// Corrects Lemke's answer `result` (of `lcp`, whose `M` and `q` are those of the mixed
/// precision solves, accurate to about 1e-9 of the gaps) against the gaps `gap` of the
/// displacements recovered from it: the free gaps are corrected by the mismatch,
/// `q' = q + (gap − w)`, the answer is polished on its closed set for `q'` ([`lcp::polish`],
/// in double precision), and `displaced(Δz)` returns the gaps of the displacements moved by
/// the forces `Δz` (one more solve of each body). The corrected answer (its `w` and residuals
/// those of `q'`) replaces `result`, and its gaps `gap`, when it lowers the closed
/// candidates' largest `|gap|`; the caller keeps the moved displacements then.
///
/// # Errors
/// `displaced`'s.
pub fn correct_closed_gaps(
    lcp: &lcp::Lcp,
    result: &mut lcp::LcpSolution,
    gap: &mut Vec<f64>,
    displaced: &mut dyn FnMut(&[f64]) -> GapsOrError,
) -> Result<GapCorrection, crate::Error> {
    let closed_gap = |g: &[f64], z: &[f64]| {
        z.iter().zip(g).filter(|(z, _)| **z > 0.0).fold(0.0f64, |m, (_, g)| m.max(g.abs()))
    };
    let before = closed_gap(gap, &result.z);
    let mut record = GapCorrection {
        closed: result.z.iter().filter(|&&z| z > 0.0).count(),
        closed_gap_before: before,
        closed_gap_after: before,
        accepted: false,
    };
    if record.closed == 0 || before == 0.0 || gap.len() != result.w.len() {
        return Ok(record);
    }
    let q = lcp.q().iter().zip(gap.iter().zip(&result.w)).map(|(q, (g, w))| q + (g - w));
    let corrected = lcp::Lcp::new(lcp.size(), lcp.m_row_major().to_vec(), q.collect())?;
    let mut trial = result.clone();
    if !lcp::polish(&corrected, &mut trial).accepted {
        return Ok(record);
    }
    let dz: Vec<f64> = trial.z.iter().zip(&result.z).map(|(a, b)| a - b).collect();
    let moved = displaced(&dz)?;
    let after = closed_gap(&moved, &trial.z);
    if after < before {
        *result = trial;
        *gap = moved;
        record.closed = result.z.iter().filter(|&&z| z > 0.0).count();
        record.closed_gap_after = after;
        record.accepted = true;
    }
    Ok(record)
}

/// A rigid-body translation of the body that no displacement condition restrains, resolved
/// by the contact (docs/method.md §4.7): the body's translation `t r` that brings the pin's
/// reaction to zero.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidMode {
    /// `"translation in x"` or `"translation in y"`.
    pub mode: &'static str,
    /// The pinned node's position: the translation is its displacement along the mode.
    pub pin_point: geometry::Point,
    /// The translation `t r` (the pinned node's displacement).
    pub translation: geometry::Point,
    /// The applied load's component along the mode (the contact carries its opposite).
    pub load: f64,
    /// LCP solves of the last increment's search.
    pub evaluations: usize,
    /// LCP solves of all increments' searches.
    pub total_evaluations: usize,
}

/// A rigid obstacle pressed by a prescribed force (docs/method.md §4.6): the force at the end
/// of the last step and the obstacle's displacement that balances it.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadDriven {
    /// The prescribed force `F` on the obstacle.
    pub force: geometry::Point,
    /// The obstacle's displacement `s` along `e = F/|F|`.
    pub displacement_along: f64,
    /// The obstacle's displacement `s e`.
    pub displacement: geometry::Point,
    /// `Σ_c (ν_c·e) P_c`: the force the contact carries along `e` (equals `|F|` to
    /// [`lcp::load_driven::FORCE_TOLERANCE`]).
    pub carried: f64,
    /// LCP solves of the last increment's search.
    pub evaluations: usize,
    /// LCP solves of all increments' searches.
    pub total_evaluations: usize,
}

impl LoadDriven {
    /// The record of a search that found the displacement `s` along `e` carrying `carried` of
    /// the force `target` (its magnitude) in `evaluations` LCP solves (`total`: over all
    /// increments).
    pub fn found(
        (e, target): (geometry::Point, f64),
        s: f64,
        carried: f64,
        (evaluations, total): (usize, usize),
    ) -> Self {
        Self {
            force: [target * e[0], target * e[1]],
            displacement_along: s,
            displacement: [s * e[0], s * e[1]],
            carried,
            evaluations,
            total_evaluations: total,
        }
    }
}

/// What the active-set solver did (docs/method.md §5.1).
#[derive(Clone, Debug)]
pub struct ActiveSetRecord {
    /// Linear solves (iterations).
    pub iterations: usize,
    /// Candidates whose status changed after each iteration (the last is 0).
    pub changes: Vec<usize>,
    /// Lemke rescues, with the candidates each handled.
    pub rescues: Vec<usize>,
    /// How it ended.
    pub end: lcp::active_set::ActiveSetEnd,
    /// Factorisations and low-rank update work.
    pub work: contact::sparse::RigidObstacleStats,
}

/// The frictional part of a contact solution (the last load increment, and a record of every
/// increment; docs/method.md §8).
#[derive(Debug)]
pub struct FrictionContact {
    /// The coefficient `μ` of the problem.
    pub coefficient: f64,
    /// Whether each candidate can take a tangential force (`false`: its tangential row is a
    /// displacement condition; it is frictionless).
    pub tangentially_free: Vec<bool>,
    /// The tangential operator (`d = t`).
    pub operator: BodyOperator,
    /// The step solver's answer: `P`, `T`, `g`, `s`, `Δs`, states, residuals, method.
    pub step: lcp::FrictionSolution,
    /// Tangential traction `T_c / |segment_c|`.
    pub traction: Vec<f64>,
    /// Slip accumulated over the increments: `Σ Δs_c` over the increments in which the
    /// candidate slipped (one increment: `Δs_c` where it slips, 0 where it sticks or is open).
    pub slip: Vec<f64>,
    /// `Σ T_c`.
    pub total_force: f64,
    /// Maximal runs of sticking candidates along the edge.
    pub stick_zones: usize,
    /// Maximal runs of slipping candidates along the edge.
    pub slip_zones: usize,
    /// One record per load increment, in order (the last is `step`).
    pub increments: Vec<IncrementRecord>,
    /// Two bodies: the second body's tangential operator (direction `−t` at the paired
    /// points); its forces are `step.tangential`.
    pub target_operator: Option<BodyOperator>,
    /// Every increment's contact state, when the problem asks for them (`[output] steps`);
    /// empty otherwise.
    pub snapshots: Vec<IncrementSnapshot>,
}

/// The contact state at the end of one load increment (`[output] steps`).
#[derive(Clone, Debug)]
pub struct IncrementSnapshot {
    /// Load step, from 1.
    pub step: usize,
    /// Increment within the step, from 1.
    pub increment: usize,
    /// Fraction of the way from the previous step end (`i / increments`).
    pub load_factor: f64,
    /// Normal forces `P`.
    pub normal: Vec<f64>,
    /// Tangential forces `T`.
    pub tangential: Vec<f64>,
    /// Gaps of the step problem.
    pub gap: Vec<f64>,
    /// Slip accumulated up to this increment.
    pub slip: Vec<f64>,
    /// Open, stick or slip±.
    pub state: Vec<lcp::ContactState>,
}

/// The stick and slip zones along a contact edge ([`ContactSolution::friction_zones`]).
#[derive(Clone, Debug, PartialEq)]
pub struct FrictionZones {
    /// `[start, end]` of each stick zone, in the coordinate `x·t` along the tangent.
    pub stick: Vec<[f64; 2]>,
    /// `[start, end]` of each slip zone (either sign).
    pub slip: Vec<[f64; 2]>,
}

/// What one load increment did (`summary.json`'s `steps`; docs/method.md §8).
#[derive(Clone, Debug, serde::Serialize)]
pub struct IncrementRecord {
    /// The `[[step]]` (1-based; 1 without steps).
    pub step: usize,
    /// The increment within the step (1-based).
    pub increment: usize,
    /// The step's load factor at the end of the increment, `increment / increments`.
    pub load_factor: f64,
    /// `Σ P_c`.
    pub normal_force: f64,
    /// `Σ T_c`.
    pub tangential_force: f64,
    /// Which method solved the increment.
    pub solver: lcp::FrictionMethod,
    /// Lemke pivots.
    pub pivots: usize,
    /// Fixed-point and active-set rounds (the active-set solver: its linear solves).
    pub iterations: usize,
    /// The active-set solver (docs/method.md §5.1): candidates whose state changed after each
    /// of its iterations (the last is 0); empty, and not written, for the other solvers.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub active_set_changes: Vec<usize>,
    /// Largest scaled complementarity residual (docs/method.md §8).
    pub complementarity: f64,
    /// Relative global equilibrium error of the increment's displacements.
    pub equilibrium_error: f64,
    /// Candidates that stick, slip and are open (`P = 0`).
    pub stick: usize,
    /// Candidates that slip.
    pub slip: usize,
    /// Candidates that are open.
    pub open: usize,
    /// Wall-clock seconds of the increment (step solver, solve, equilibrium); not written
    /// to `summary.json`, whose contents are reproducible (for benchmarks).
    #[serde(skip)]
    pub seconds: f64,
}

impl FrictionContact {
    /// The frictional part from the step answer.
    pub fn new(
        coefficient: f64,
        tangentially_free: Vec<bool>,
        operator: BodyOperator,
        step: lcp::FrictionSolution,
        segment_length: &[f64],
    ) -> Self {
        let traction = step.tangential.iter().zip(segment_length).map(|(t, l)| t / l).collect();
        let slip = step
            .state
            .iter()
            .zip(&step.slip_increment)
            .map(|(s, &ds)| if s.is_slip() { ds } else { 0.0 })
            .collect();
        let runs = |pred: &dyn Fn(lcp::ContactState) -> bool| {
            let st = &step.state;
            (0..st.len()).filter(|&c| pred(st[c]) && (c == 0 || !pred(st[c - 1]))).count()
        };
        let stick_zones = runs(&|s| s == lcp::ContactState::Stick);
        let slip_zones = runs(&|s| s.is_slip());
        Self {
            coefficient,
            tangentially_free,
            operator,
            total_force: step.tangential.iter().sum(),
            traction,
            slip,
            step,
            stick_zones,
            slip_zones,
            increments: Vec::new(),
            target_operator: None,
            snapshots: Vec::new(),
        }
    }
}

impl ContactSolution {
    /// The largest difference between a candidate's gap from the displacements and the LCP's
    /// `w` (how far the condensed problem and the recovered field disagree).
    pub fn max_gap_mismatch(&self) -> f64 {
        self.gap.iter().zip(&self.lcp.w).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
    }

    /// The stick and the slip zones of the final increment (friction only): each maximal run
    /// of sticking (of slipping, either sign) candidates along the edge as the interval
    /// `[min, max]` of the candidates' coordinate `x·t` along the tangent `t`, from one outer
    /// candidate of the run to the other (a run of one candidate is `[s, s]`), in the
    /// candidates' order. Against a curved obstacle (normals differing between candidates)
    /// the coordinate is the arc length along the edge instead.
    pub fn friction_zones(&self) -> Option<FrictionZones> {
        let f = self.friction.as_ref()?;
        let along: Vec<f64> = match self.candidates.operator.uniform_direction() {
            Some(nu) => {
                let t = contact::tangent(nu);
                self.candidates.points.iter().map(|x| x[0] * t[0] + x[1] * t[1]).collect()
            }
            None => self.candidates.arc_length.clone(),
        };
        let runs = |pred: &dyn Fn(lcp::ContactState) -> bool| {
            let st = &f.step.state;
            let mut zones = Vec::new();
            let mut start = None;
            for c in 0..=st.len() {
                match (start, c < st.len() && pred(st[c])) {
                    (None, true) => start = Some(c),
                    (Some(first), false) => {
                        let (a, b) = (along[first], along[c - 1]);
                        zones.push([a.min(b), a.max(b)]);
                        start = None;
                    }
                    _ => {}
                }
            }
            zones
        };
        Some(FrictionZones {
            stick: runs(&|s| s == lcp::ContactState::Stick),
            slip: runs(&|s| s.is_slip()),
        })
    }
    /// Assembles the contact solution from the LCP result: `gap` holds the MLS gaps from the
    /// final displacements; the closed set, the pressures, the onset estimates and the total
    /// force follow (the gap tolerance from `spec`, or its default, docs/method.md §6).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        spec: &ContactSpec,
        candidates: contact::Candidates,
        target: Option<BodyOperator>,
        paired_points: Vec<geometry::Point>,
        condensed: Option<contact::CondensedContact>,
        free_gap: &[f64],
        lcp: lcp::LcpSolution,
        gap: Vec<f64>,
        warning: Option<String>,
    ) -> Self {
        // Default: 1e-5 of the largest initial gap (docs/method.md §6), plus 1e-12 of the
        // largest contact-free gap so that bodies touching at the start (g0 = 0) still have a
        // scale.
        let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        let gap_tolerance = spec.gap_tolerance.unwrap_or_else(|| {
            (1e-5 * max_abs(&candidates.initial_gap) + 1e-12 * max_abs(free_gap))
                .max(f64::MIN_POSITIVE)
        });
        let closed: Vec<bool> = lcp.w.iter().map(|&w| w <= gap_tolerance).collect();
        let pressure = contact::rings::pressures(&lcp.z, &candidates.segment_length);
        let onset = contact::onset(&candidates.arc_length, &lcp.w, &pressure, &closed);
        let total_force = lcp.z.iter().sum();
        Self {
            candidates,
            target,
            paired_points,
            condensed,
            active_set: None,
            lcp,
            gap,
            pressure,
            closed,
            gap_tolerance,
            onset,
            total_force,
            warning,
            unpaired: 0,
            friction: None,
            fallback_from: None,
            load_driven: None,
            rigid_mode: None,
            lemke_polish: None,
            gap_correction: None,
        }
    }
}

impl Solution {
    /// Body `k`'s solution, numbered as [`crate::problem::Problem::body`]: 0 is this one,
    /// then the other bodies'.
    pub fn body(&self, k: usize) -> Option<&Solution> {
        match k {
            0 => Some(self),
            k => self.others.get(k - 1),
        }
    }

    /// Every body's solution, this one first, numbered as [`Solution::body`].
    pub fn bodies(&self) -> impl Iterator<Item = &Solution> {
        std::iter::once(self).chain(&self.others)
    }

    /// Every contact pair's solution in the order of [`crate::problem::Problem::pairs`];
    /// empty without contact.
    pub fn pairs(&self) -> Vec<&ContactSolution> {
        self.contact_pairs.iter().collect()
    }

    /// The contact solution of the first body's one pair (`None` without contact and for a
    /// scene of pairs, whose pairs share one LCP: [`Solution::multibody`]).
    pub fn contact(&self) -> Option<&ContactSolution> {
        if self.scene.is_some() {
            return None;
        }
        self.contact_pairs.first()
    }

    /// The second body's solution of a two-body scene of one pair (`None` for one body and
    /// for a scene of pairs).
    pub fn second_body(&self) -> Option<&Solution> {
        if self.scene.is_some() {
            return None;
        }
        self.others.first()
    }

    /// The other bodies, the pairs and the one LCP of a scene of pairs (`None` otherwise).
    pub fn multibody(&self) -> Option<MultibodySolution<'_>> {
        self.scene.as_deref().map(|contact| MultibodySolution {
            bodies: &self.others,
            pairs: &self.contact_pairs,
            contact,
        })
    }

    /// The first reported quantity holding a value that is not finite (NaN or infinite), if
    /// any: a singular system that the factorisation did not catch, or magnitudes that overflow.
    pub fn first_non_finite(&self) -> Option<&'static str> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let checks: [(&'static str, bool); 8] = [
            ("displacement", self.displacement.iter().all(|u| finite(u))),
            ("stress", self.stress.iter().all(|s| finite(s))),
            ("reactions", self.reactions.iter().all(|r| r.2.is_finite())),
            ("relative residual", self.relative_residual.is_finite()),
            ("equilibrium error", self.equilibrium_error.is_finite()),
            ("contact force", self.contact().is_none_or(|c| finite(&c.lcp.z))),
            (
                "tangential contact force",
                self.contact()
                    .and_then(|c| c.friction.as_ref())
                    .is_none_or(|f| finite(&f.step.tangential)),
            ),
            ("contact gap", self.contact().is_none_or(|c| finite(&c.gap))),
        ];
        let own = checks.into_iter().find(|(_, ok)| !ok).map(|(what, _)| what);
        let several = self.multibody().and_then(|m| {
            let gaps = m.pairs.iter().all(|c| finite(&c.gap));
            let forces = finite(&m.contact.lcp.z);
            let bodies = m.bodies.iter().find_map(|s| s.first_non_finite());
            bodies.or((!forces).then_some("contact force")).or((!gaps).then_some("contact gap"))
        });
        own.or(several).or_else(|| self.second_body().and_then(|s| s.first_non_finite()))
    }
}

/// Recovers the solution of one body from its nodal parameters `u_hat`; `contact` holds the
/// body's contact operators and their forces (none without contact; the normal operator
/// first, then the tangential one with friction).
pub fn recover(
    problem: &Problem,
    model: &Model,
    u_hat: Vec<f64>,
    contact: &[(&BodyOperator, &[f64])],
) -> Solution {
    let system = &model.system;
    let ns = &model.node_shapes;
    let n = model.nodes.len();
    let displacement: Vec<[f64; 2]> = (0..n).map(|i| ns.interpolate(i, &u_hat)).collect();
    let d = problem.material.constitutive();
    let strain = model.nodal_strains(&u_hat);
    let (stress, hoop) = match problem.material.hoop() {
        None => (strain.iter().map(|e| material::apply(&d, *e)).collect(), Vec::new()),
        Some(law) => {
            let eps = model.nodal_hoop_strains(&u_hat, &strain);
            let stress = strain.iter().zip(&eps).map(|(e, &t)| law.in_plane(&d, *e, t)).collect();
            let hoop = strain.iter().zip(&eps).map(|(e, &t)| [t, law.stress(*e, t)]).collect();
            (stress, hoop)
        }
    };
    let Balance { contact_rhs, reactions, applied, reaction, contact_force, imbalance, scale } =
        balance(system, &system.load, &u_hat, contact);
    let ku = linear_solve::mul(&system.matrix, &u_hat);
    let rhs: Vec<f64> = system.rhs.iter().zip(&contact_rhs).map(|(a, b)| a + b).collect();
    let res: f64 = ku.iter().zip(&rhs).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
    let rhs_norm = rhs.iter().map(|v| v * v).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
    Solution {
        nodal_parameters: u_hat,
        displacement,
        strain,
        stress,
        hoop,
        reactions,
        applied_force: applied,
        reaction_force: reaction,
        contact_force,
        others: Vec::new(),
        contact_pairs: Vec::new(),
        scene: None,
        relative_residual: res / rhs_norm,
        equilibrium_error: imbalance / scale,
        timings: Vec::new(),
    }
}

/// The global balance of one body: applied loads, reactions and contact forces.
struct Balance {
    contact_rhs: Vec<f64>,
    reactions: Vec<(u32, Axis, f64)>,
    applied: [f64; 2],
    reaction: [f64; 2],
    contact_force: [f64; 2],
    imbalance: f64,
    scale: f64,
}

/// The balance of `u_hat` under the load `load` (the system's own, or a load step's) and the
/// contact forces `contact` (the normal operator first).
fn balance(
    system: &GlobalSystem,
    load: &[f64],
    u_hat: &[f64],
    contact: &[(&BodyOperator, &[f64])],
) -> Balance {
    let n = load.len() / 2;
    // E P: contact forces on the right-hand side (zero without contact).
    let mut contact_rhs = vec![0.0; 2 * n];
    let mut contact_force = [0.0; 2];
    let mut contact_abs = 0.0;
    if let Some(&(op, forces)) = contact.first() {
        op.add_forces(forces, &mut contact_rhs);
        contact_force = op.resultant(forces);
        contact_abs = forces.iter().map(|p| p.abs()).sum();
    }
    for &(op, forces) in contact.iter().skip(1) {
        op.add_forces(forces, &mut contact_rhs);
        let r = op.resultant(forces);
        contact_force = [contact_force[0] + r[0], contact_force[1] + r[1]];
        contact_abs += forces.iter().map(|p| p.abs()).sum::<f64>();
    }
    // An axisymmetric body's contact forces are rings' totals, its balance per radian
    // (`contact::rings`).
    if system.axisymmetric {
        contact_force = contact_force.map(|f| f / contact::rings::REVOLUTION);
        contact_abs /= contact::rings::REVOLUTION;
    }
    let reactions: Vec<(u32, Axis, f64)> = system
        .constraints
        .iter()
        .map(|c| {
            let i = c.node as usize;
            let r = system.interior_stiffness.row_dot(i, c.axis, u_hat)
                - load[dof(i, c.axis)]
                - contact_rhs[dof(i, c.axis)];
            (c.node, c.axis, r)
        })
        .collect();
    let mut applied = [0.0; 2];
    let mut load_abs = [0.0; 2];
    for i in 0..n {
        applied[0] += load[2 * i];
        applied[1] += load[2 * i + 1];
        load_abs[0] += load[2 * i].abs();
        load_abs[1] += load[2 * i + 1].abs();
    }
    let mut reaction = [0.0; 2];
    let mut reaction_abs = 0.0;
    for &(_, axis, r) in &reactions {
        reaction[axis as usize] += r;
        reaction_abs += r.abs();
    }
    // In axisymmetry the radial sums are balanced by the hoop stresses, not by each other
    // (docs/method.md §9.3): only the axial balance is a global law.
    let radial = if system.axisymmetric { 0.0 } else { 1.0 };
    let imbalance = (radial * (applied[0] + reaction[0] + contact_force[0]))
        .hypot(applied[1] + reaction[1] + contact_force[1]);
    // Nothing loads the body (a prescribed motion only): the reactions are the only forces
    // and are round-off when the motion is rigid, so they are measured against the internal
    // forces they are summed from, `Σ |K_int| |û|` over the constrained rows.
    let unloaded = load_abs == [0.0, 0.0] && contact_abs == 0.0;
    let internal = if unloaded { supported_internal_force(system, u_hat) } else { 0.0 };
    let scale = load_abs[0]
        .hypot(load_abs[1])
        .max(reaction_abs)
        .max(contact_abs)
        .max(internal)
        .max(f64::MIN_POSITIVE);
    Balance { contact_rhs, reactions, applied, reaction, contact_force, imbalance, scale }
}

/// `Σ_j |K_int,ij û_j|` summed over the constrained rows `i`: the size of the internal forces
/// the reactions are computed from (their round-off is a few ε of it).
fn supported_internal_force(system: &GlobalSystem, u_hat: &[f64]) -> f64 {
    let k = &system.interior_stiffness;
    system
        .constraints
        .iter()
        .map(|c| {
            let (i, a) = (c.node as usize, c.axis as usize);
            (k.offsets[i]..k.offsets[i + 1])
                .map(|q| {
                    let j = k.cols[q] as usize;
                    (k.blocks[q][a][0] * u_hat[2 * j]).abs()
                        + (k.blocks[q][a][1] * u_hat[2 * j + 1]).abs()
                })
                .sum::<f64>()
        })
        .sum()
}

/// The relative global equilibrium error of `u_hat` under `load` and the contact forces
/// `contact` (as [`Solution::equilibrium_error`]; for the increments of a load step): the
/// imbalance `|Σ f + Σ R + Σ ν P|` over the largest of `|Σ |f||` (per component), `Σ |R|`
/// and `Σ P`; when the body has neither load nor contact force, over the larger of `Σ |R|`
/// and the internal forces at the supports, `Σ |K_int| |û|` over the constrained rows, so
/// that round-off is never divided by round-off (a body moved rigidly by its supports).
pub fn equilibrium_error(
    system: &GlobalSystem,
    load: &[f64],
    u_hat: &[f64],
    contact: &[(&BodyOperator, &[f64])],
) -> f64 {
    let b = balance(system, load, u_hat, contact);
    b.imbalance / b.scale
}
