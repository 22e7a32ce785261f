//! Two bodies in one contact pair on the sparse load path: the scene's walk
//! ([`sparse_path::solve`]) over the scene of that one pair, so that one pair and several
//! pairs between bodies take one sparse walk (docs/dev/contact_core.md, piece 5).

use super::super::friction::StepEnd;
use super::{Numbering, PairCandidates, Solved, held_bodies, held_modes, sparse_path};
use crate::contact::{BodyOperator, Candidates};
use crate::error::Error;
use crate::lcp::{self, load_driven::LoadDrivenError};
use crate::model::Model;
use crate::problem::{ContactPair, ContactSpec, Problem};
use crate::progress::Clock;
use crate::solution;

/// What the sparse path gives a pair of two bodies: the normal LCP's view of the last
/// increment, its gaps without contact forces (at no translation for a held body), both
/// bodies' displacements, the active set's record, the frictional record (none on a one-shot
/// path), a held body's translation, and the candidates and the target's operator handed
/// back.
pub(in crate::pipeline) struct SparsePair {
    pub(in crate::pipeline) result: lcp::LcpSolution,
    pub(in crate::pipeline) free_gap: Vec<f64>,
    pub(in crate::pipeline) displacements: (Vec<f64>, Vec<f64>),
    pub(in crate::pipeline) record: Option<solution::ActiveSetRecord>,
    pub(in crate::pipeline) friction: Option<solution::FrictionContact>,
    pub(in crate::pipeline) rigid_mode: Option<solution::RigidMode>,
    pub(in crate::pipeline) candidates: Candidates,
    pub(in crate::pipeline) target: BodyOperator,
}

/// The pair `spec` of `problem`'s first body (`models[0]`, its `candidates`) against the
/// second (`models[1]`, the `target` operator at the paired points), each body along its
/// step ends `steps`, on the sparse load path of the several-pairs scene (friction, load
/// steps, or frictionless contact in one shot as one step of one increment). A translation of
/// either body held by the contact alone (docs/method.md §4.7) is the scene's held body,
/// found by its search over warm-started solves.
///
/// # Errors
/// The sparse path's ([`sparse_path::solve`]); both bodies held
/// ([`LoadDrivenError::SeveralHeld`]: one pair cannot fix both translations), and the
/// checks of a held body ([`super::held_bodies`], [`super::held_modes`]).
pub(in crate::pipeline) fn solve_sparse(
    problem: &Problem,
    spec: &ContactSpec,
    models: [&Model; 2],
    (candidates, target): (Candidates, BodyOperator),
    steps: [Vec<StepEnd>; 2],
    clock: &mut Clock<'_>,
) -> Result<SparsePair, Error> {
    let pairs = [ContactPair { body: 0, spec: *spec, target_body: Some(1), obstacles: Vec::new() }];
    let found =
        [PairCandidates { candidates, target: Some(target), paired: Vec::new(), unpaired: 0 }];
    let numbering = Numbering::new(&pairs, &found, 2);
    let problems = [problem, problem.second_body().unwrap_or(problem)];
    let held = held_bodies(&problems, &models, &pairs, &found, &numbering.operators)
        .map_err(lcp::LcpError::from)?;
    if held.len() > 1 {
        let name = |b: usize| format!("`{}` ({})", problems[b].name, held[b].1.name());
        let bodies = format!("{}, {}", name(0), name(1));
        return Err(lcp::LcpError::from(LoadDrivenError::SeveralHeld { bodies }).into());
    }
    let steps = Vec::from(steps);
    let scene = numbering.scene(problem, &pairs, &found, &steps);
    let (solved, mut frictions, _) = sparse_path::solve(&scene, &models, &held, clock)?;
    let Solved { result, free_gap, displacements, record, search, .. } = solved;
    let rigid = held_modes(&held, &search, (&problems, &models), &result, &free_gap)?;
    let [u1, u2]: [Vec<f64>; 2] =
        displacements.try_into().expect("the sparse path gives one displacement per body");
    let [PairCandidates { candidates, target, .. }] = found;
    Ok(SparsePair {
        result,
        free_gap,
        displacements: (u1, u2),
        record,
        friction: frictions.pop(),
        rigid_mode: rigid.into_iter().next().map(|(_, mode)| mode),
        candidates,
        target: target.expect("a pair of two bodies has a target operator"),
    })
}
