//! The adaptive loop's view of one solve: every body's problem, model and solution, and the
//! contact pairs between them — one body, two bodies in one pair and several pairs alike, so
//! that the loop estimates, marks and refines a list of bodies.

use crate::error::Error;
use crate::lcp::LemkeParams;
use crate::model::Model;
use crate::nodes::Nodes;
use crate::pipeline::{
    check_memory, discretise_all, discretise_mfvm_nodes, multibody, solve_model,
};
use crate::problem::{ContactTarget, Problem};
use crate::progress::Progress;
use crate::solution::{ContactSolution, Solution};

/// One solve of the loop.
pub(super) struct Solved {
    /// The problem solved (every body's refinement regions inside it).
    pub problem: Problem,
    /// Body `k`'s model, numbered as [`Problem::body`].
    pub models: Vec<Model>,
    /// The solution (the other bodies' inside it, [`Solution::body`]).
    pub solution: Solution,
}

/// A contact pair seen from the loop: the body carrying the candidates, the target body and
/// its edge (an elastic pair), and the pair's contact solution.
pub(super) struct PairView<'a> {
    /// The candidates' body.
    pub body: usize,
    /// The target body and its contact edge; `None` against rigid obstacles.
    pub target: Option<(usize, usize)>,
    /// The pair's contact solution.
    pub contact: &'a ContactSolution,
}

impl Solved {
    /// Discretises and solves every body of `problem`. `counted`: the node set of a one-body
    /// problem already generated (to count it), reused.
    pub fn solve(
        problem: Problem,
        counted: Option<Nodes>,
        progress: &mut dyn Progress,
    ) -> Result<Self, Error> {
        let (model, second) = match counted {
            Some(nodes) if problem.body_count() == 1 => {
                check_memory(&problem)?;
                (discretise_mfvm_nodes(&problem, false, Some(nodes), progress)?, None)
            }
            _ => discretise_all(&problem, progress)?,
        };
        let (models, solution) = if problem.is_scene_of_pairs() {
            let others = multibody::discretise_others(&problem, progress)?;
            let lemke = LemkeParams::default();
            let (model, others, solution) =
                multibody::solve_bodies(&problem, model, others, progress, &lemke)?;
            (std::iter::once(model).chain(others).collect(), solution)
        } else {
            let (model, second, solution) = solve_model(&problem, model, second, progress)?;
            (std::iter::once(model).chain(second).collect(), solution)
        };
        Ok(Self { problem, models, solution })
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.models.len()
    }

    /// Body `k`'s problem, model and solution.
    pub fn body(&self, k: usize) -> (&Problem, &Model, &Solution) {
        let missing = "every body of a solved problem has a problem and a solution";
        (
            self.problem.body(k).expect(missing),
            &self.models[k],
            self.solution.body(k).expect(missing),
        )
    }

    /// The contact pairs, in file order (none without contact).
    pub fn pairs(&self) -> Vec<PairView<'_>> {
        let body_edge = |target: ContactTarget| match target {
            ContactTarget::Body { edge } => Some(edge),
            _ => None,
        };
        if let (Some(several), Some(solved)) = (self.problem.multibody(), self.solution.multibody())
        {
            return several
                .pairs
                .iter()
                .zip(solved.pairs)
                .map(|(pair, contact)| PairView {
                    body: pair.body,
                    target: pair.target_body.zip(body_edge(pair.spec.target)),
                    contact,
                })
                .collect();
        }
        let (Some(spec), Some(contact)) = (self.problem.contact(), self.solution.contact()) else {
            return Vec::new();
        };
        let target = body_edge(spec.target).filter(|_| self.problem.second_body().is_some());
        vec![PairView { body: 0, target: target.map(|edge| (1, edge)), contact }]
    }

    /// The loop's result parts: the problem, the first body's model, the second body's (one
    /// pair), the other bodies' (several pairs) and the solution.
    pub fn into_parts(self) -> (Problem, Model, Option<Model>, Vec<Model>, Solution) {
        let mut models = self.models.into_iter();
        let first = models.next().expect("a solved problem has a first body");
        let rest: Vec<Model> = models.collect();
        if self.problem.is_scene_of_pairs() {
            (self.problem, first, None, rest, self.solution)
        } else {
            (self.problem, first, rest.into_iter().next(), Vec::new(), self.solution)
        }
    }
}
