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

/// What the contact edge touches.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactTarget {
    /// A rigid straight obstacle.
    Rigid(RigidLine),
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
}

/// `[contact] solver`: how the frictionless contact problem is solved (docs/method.md §5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactSolver {
    /// Lemke's method on the dense condensed compliance `M = G K⁻¹ E` (docs/method.md §5).
    Lemke,
    /// The primal–dual active-set method on the sparse system, without `M` (docs/method.md
    /// §5.1); a rigid obstacle or two bodies, frictionless, one load step.
    ActiveSet,
    /// Lemke below [`ContactSolver::AUTO_THRESHOLD`] candidates (and always with friction or
    /// load steps), the active-set method from there on.
    #[default]
    Auto,
}

impl ContactSolver {
    /// Candidates from which `Auto` takes the active-set method: on the strip `L × 1` at
    /// spacing 0.05 (docs/dev/active_set.md) Lemke's path took 0.6 s against 0.9 s at 1 000
    /// candidates and 3.1 s against 1.7 s at 2 000; on the beam the two are even at 768.
    /// Above every shipped problem (at most 384 candidates).
    pub const AUTO_THRESHOLD: usize = 1000;

    /// Whether a frictionless problem with `candidates` candidates is solved by the active-set
    /// method (a rigid obstacle or two bodies).
    pub fn is_active_set(self, candidates: usize) -> bool {
        match self {
            ContactSolver::Lemke => false,
            ContactSolver::ActiveSet => true,
            ContactSolver::Auto => candidates >= Self::AUTO_THRESHOLD,
        }
    }
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
