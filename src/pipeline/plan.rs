//! The plan of a contact problem (docs/dev/contact_core.md, "The plan"): which contact system
//! takes it — the condensed compliance `M = G K⁻¹ E` (Lemke, or the condensed load path) or
//! the sparse system without `M` (the active-set method) —, whether `"auto"` may hand a
//! numerical failure of Lemke to the active set, and the factorisation of the body's `K`
//! that the condensation foresees. The rule is decided here only; the memory estimate asks it
//! with the candidates it expects from the geometry, the factorisation with the nodes on the
//! contact edge, the solve with the candidates found.

use crate::contact;
use crate::linear_solve::{FactorMethod, FactorOptions, FactorPrecision};
use crate::nodes;
use crate::problem::{ContactSolver, Problem};

/// The contact system a problem is solved on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum System {
    /// The dense condensed compliance `M` (docs/method.md §4–§5): Lemke in one shot, or the
    /// condensed load path.
    Condensed,
    /// The sparse system without `M` (docs/method.md §5.1): the active-set method in one
    /// shot, or the sparse load path.
    Sparse,
}

/// What a problem is, as far as its route is concerned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// Frictionless, one step, no translation held by the contact: one LCP.
    OneShot,
    /// Friction, load steps or a held translation, against rigid obstacles.
    RigidPath,
    /// Friction, load steps or a held translation, between two bodies (or over several pairs).
    PairPath,
}

impl Shape {
    /// The shape of one pair: on the load path (`on_path`: friction, load steps or a held
    /// translation) between two bodies (`pair`) or against rigid obstacles, else one shot.
    pub fn of(on_path: bool, pair: bool) -> Shape {
        match (on_path, pair) {
            (false, _) => Shape::OneShot,
            (true, false) => Shape::RigidPath,
            (true, true) => Shape::PairPath,
        }
    }
}

/// The route of a contact problem: its system, and whether Lemke's numerical failure is
/// handed to the active set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plan {
    /// The contact system.
    pub system: System,
    /// `"auto"` on a condensed problem (in one shot or on the load path): a numerical failure
    /// of Lemke is handed to the active-set method, which answers instead (the reason
    /// recorded).
    pub fallback: bool,
}

impl Plan {
    /// The plan of one pair solved by `solver` on `candidates` candidates: `"lemke"` is
    /// condensed, `"active_set"` sparse, `"auto"` sparse from its shape's threshold on
    /// ([`ContactSolver::AUTO_THRESHOLD`], [`ContactSolver::FRICTION_AUTO_THRESHOLD`],
    /// [`ContactSolver::FRICTION_PAIR_AUTO_THRESHOLD`]).
    pub fn new(solver: ContactSolver, shape: Shape, candidates: usize) -> Plan {
        let threshold = match shape {
            Shape::OneShot => ContactSolver::AUTO_THRESHOLD,
            Shape::RigidPath => ContactSolver::FRICTION_AUTO_THRESHOLD,
            Shape::PairPath => ContactSolver::FRICTION_PAIR_AUTO_THRESHOLD,
        };
        let sparse = match solver {
            ContactSolver::Lemke => false,
            ContactSolver::ActiveSet => true,
            ContactSolver::Auto => candidates >= threshold,
        };
        if sparse { Plan::SPARSE } else { Plan::condensed(solver == ContactSolver::Auto) }
    }

    /// The plan of several pairs, `solvers` one per pair (validated: none says `"lemke"` when
    /// another says `"active_set"`), over `candidates` candidates of all pairs, on the load
    /// path or in one shot: sparse when a pair asks for the active set, or on the path when
    /// every pair is `"auto"` from the two-body threshold on; Lemke's fallback when every pair
    /// is `"auto"`.
    pub fn several(solvers: &[ContactSolver], on_path: bool, candidates: usize) -> Plan {
        let asks = solvers.contains(&ContactSolver::ActiveSet);
        let auto = solvers.iter().all(|&s| s == ContactSolver::Auto);
        let by_count = candidates >= ContactSolver::FRICTION_PAIR_AUTO_THRESHOLD;
        if asks || (on_path && auto && by_count) { Plan::SPARSE } else { Plan::condensed(auto) }
    }

    /// The sparse system (without a fallback: nothing comes after it).
    pub const SPARSE: Plan = Plan { system: System::Sparse, fallback: false };

    fn condensed(fallback: bool) -> Plan {
        Plan { system: System::Condensed, fallback }
    }

    /// Whether the plan is the sparse system (the active-set method).
    pub fn is_sparse(self) -> bool {
        self.system == System::Sparse
    }
}

/// The options of the factorisation of `problem`'s MFVM matrix on `nodes` (`pinned`: a
/// translation held by the contact): the static-pivoting LU the reach-restricted condensation
/// needs when [`condensed_sparsely`], else [`factor_options`].
pub(super) fn model_factor_options(
    problem: &Problem,
    nodes: &nodes::Nodes,
    pinned: bool,
) -> FactorOptions {
    if condensed_sparsely(problem, nodes, pinned) {
        graded_static(problem)
    } else {
        factor_options(problem)
    }
}

/// The options of the factorisation of `problem`'s MFVM matrix but for the sparse
/// condensation: the defaults, or with mixed precision (`discretisation.precision`,
/// [`super::memory::precision`]) the static-pivoting LU with single-precision factors
/// whatever the size.
pub(super) fn factor_options(problem: &Problem) -> FactorOptions {
    match super::memory::precision(problem) {
        FactorPrecision::Double => FactorOptions::default(),
        FactorPrecision::Mixed => FactorOptions {
            method: FactorMethod::StaticPivoting,
            precision: FactorPrecision::Mixed,
            ..FactorOptions::default()
        },
    }
}

/// Whether the Lemke path will condense by reach-restricted solves: from
/// [`contact::SPARSE_CONDENSATION_MIN_CANDIDATES`] candidates on this body (on a graded node
/// set, one with refinement regions: [`contact::GRADED_SPARSE_CONDENSATION_MIN_CANDIDATES`])
/// (one body or the first of two; frictionless, one step, no translation held by the contact,
/// double precision, the plan condensed), counted as the nodes on the contact edge (the
/// candidates are these, less constrained ones). Then the body's own factorisation is the
/// static-pivoting LU with nested dissection ([`FactorOptions::nested_dissection_static`])
/// that the condensation's reach-restricted solves need ([`contact::condense_model_observed`]),
/// instead of a second factorisation for `M`: on the 2 000-candidate strip one factorisation
/// of 84k unknowns less (docs/dev/performance.md, "Lemke's final accuracy and one
/// factorisation at 2 000 candidates").
pub(super) fn condensed_sparsely(problem: &Problem, nodes: &nodes::Nodes, pinned: bool) -> bool {
    let Some(spec) = problem.contact() else { return false };
    if spec.friction > 0.0
        || !problem.steps.is_empty()
        || pinned
        || problem.is_scene_of_pairs()
        || super::memory::precision(problem) != FactorPrecision::Double
    {
        return false;
    }
    let on_edge = nodes.edges.iter().filter(|e| e.contains(spec.edge)).count();
    let least = if problem.refinement.boxes.is_empty() {
        contact::SPARSE_CONDENSATION_MIN_CANDIDATES
    } else {
        contact::GRADED_SPARSE_CONDENSATION_MIN_CANDIDATES
    };
    on_edge >= least && !Plan::new(spec.solver, Shape::OneShot, on_edge).is_sparse()
}

/// The static-pivoting LU for the sparse condensation: nested dissection only on uniform sets
/// ([`FactorOptions::nested_dissection_static`], what the reach-restricted solves need on the
/// 2 000-candidate strip); on graded sets the lesser-fill of nested dissection, the banded
/// order (as [`FactorOptions::default`] compares them: on the refined beam's 13 474 graded
/// nodes nested dissection alone bounds 12× the flops of the banded order) and the
/// approximate minimum degree order of the node graph ([`FactorOptions::amd`]: on the
/// adaptive beam's last set 27 % fewer flops than the banded order, and a bushier
/// elimination tree for the reach-restricted solves; docs/dev/time_to_accuracy.md).
fn graded_static(problem: &Problem) -> FactorOptions {
    if problem.refinement.boxes.is_empty() {
        FactorOptions::nested_dissection_static()
    } else {
        FactorOptions {
            method: FactorMethod::StaticPivoting,
            amd: true,
            ..FactorOptions::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_takes_the_sparse_system_from_each_shapes_threshold() {
        let cases = [
            (Shape::OneShot, ContactSolver::AUTO_THRESHOLD),
            (Shape::RigidPath, ContactSolver::FRICTION_AUTO_THRESHOLD),
            (Shape::PairPath, ContactSolver::FRICTION_PAIR_AUTO_THRESHOLD),
        ];
        for (shape, threshold) in cases {
            let below = Plan::new(ContactSolver::Auto, shape, threshold - 1);
            assert_eq!(below.system, System::Condensed, "{shape:?}");
            assert!(below.fallback, "{shape:?}");
            assert!(Plan::new(ContactSolver::Auto, shape, threshold).is_sparse(), "{shape:?}");
            assert!(Plan::new(ContactSolver::ActiveSet, shape, 1).is_sparse(), "{shape:?}");
            assert!(!Plan::new(ContactSolver::Lemke, shape, usize::MAX).is_sparse(), "{shape:?}");
            assert!(!Plan::new(ContactSolver::Lemke, shape, 1).fallback, "{shape:?}");
        }
    }

    #[test]
    fn several_pairs_are_sparse_when_one_asks_or_all_are_auto_on_the_path_from_800() {
        use ContactSolver::{ActiveSet, Auto};
        let from = ContactSolver::FRICTION_PAIR_AUTO_THRESHOLD;
        assert!(Plan::several(&[Auto, ActiveSet], false, 1).is_sparse());
        assert!(Plan::several(&[Auto, Auto], true, from).is_sparse());
        assert!(!Plan::several(&[Auto, Auto], true, from - 1).is_sparse());
        let once = Plan::several(&[Auto, Auto], false, usize::MAX);
        assert_eq!(once, Plan { system: System::Condensed, fallback: true });
        assert!(Plan::several(&[Auto, Auto], true, 1).fallback);
        assert!(!Plan::several(&[Auto, ContactSolver::Lemke], true, 1).fallback);
    }
}
