//! One contact pair on the sparse load path: the first body against rigid obstacles, or
//! against a second body, walks the scene's path ([`sparse_path::walk`]) over the scene of
//! that one pair, so that every sparse problem takes one walk (docs/dev/contact_core.md,
//! piece 5). Against rigid obstacles the system is the body's own
//! ([`crate::contact::sparse::RigidObstacle`]), which may own `K`'s factors and release them (one
//! factorisation of the body alive at a time at 10⁶ nodes); between two bodies it is
//! [`crate::contact::sparse::Bodies`].

use super::super::friction::StepEnd;
use super::{Numbering, PairCandidates, Solved, held_bodies, held_modes, sparse_path};
use crate::contact::{BodyOperator, Candidates};
use crate::error::Error;
use crate::lcp::{self, load_driven::LoadDrivenError};
use crate::linear_solve::Factorisation;
use crate::model::Model;
use crate::problem::{ContactPair, ContactSpec, Problem};
use crate::progress::Clock;
use crate::solution;

/// What the sparse path gives one pair: the normal LCP's view of the last increment, its gaps
/// without contact forces (at no translation for a held body), each body's displacements,
/// the active set's record, the frictional record (none on a one-shot path), a held body's
/// translation, a force-driven obstacle's record, and the candidates and the target body's
/// operator (none against rigid obstacles) handed back.
pub(in crate::pipeline) struct SparsePair {
    pub(in crate::pipeline) result: lcp::LcpSolution,
    pub(in crate::pipeline) free_gap: Vec<f64>,
    pub(in crate::pipeline) displacements: Vec<Vec<f64>>,
    pub(in crate::pipeline) record: Option<solution::ActiveSetRecord>,
    pub(in crate::pipeline) friction: Option<solution::FrictionContact>,
    pub(in crate::pipeline) rigid_mode: Option<solution::RigidMode>,
    pub(in crate::pipeline) load_driven: Option<solution::LoadDriven>,
    pub(in crate::pipeline) candidates: Candidates,
    pub(in crate::pipeline) target: Option<BodyOperator>,
}

/// The pair `spec` of `problem`'s first body (`models[0]`, its `candidates`) against rigid
/// obstacles (`target` `None`, one model) or the second body (`models[1]`, the `target`
/// operator at the paired points), each body along its step ends `steps`, on the sparse load
/// path (friction, load steps, or frictionless contact in one shot as one step of one
/// increment). A translation of either body held by the contact alone (docs/method.md §4.7)
/// is the scene's held body, found by its search over warm-started solves. Against rigid
/// obstacles the system owns `factors` when given them (`K`'s, taken from the model on a
/// one-shot path), which come back beside the answer, released if it factorised a
/// row-replaced matrix ([`crate::contact::sparse::ModelFactors`]).
///
/// # Errors
/// The sparse path's ([`sparse_path::walk`]); both bodies held
/// ([`LoadDrivenError::SeveralHeld`]: one pair cannot fix both translations), and the
/// checks of a held body ([`super::held_bodies`], [`super::held_modes`]).
pub(in crate::pipeline) fn solve_sparse(
    problem: &Problem,
    spec: &ContactSpec,
    models: &[&Model],
    (candidates, target): (Candidates, Option<BodyOperator>),
    (steps, factors): (Vec<Vec<StepEnd>>, Option<Factorisation>),
    clock: &mut Clock<'_>,
) -> Result<(SparsePair, Option<Factorisation>), Error> {
    let target_body = target.is_some().then_some(1);
    let pairs = [ContactPair { body: 0, spec: *spec, target_body, obstacles: Vec::new() }];
    let found = [PairCandidates { candidates, target, paired: Vec::new(), unpaired: 0 }];
    let numbering = Numbering::new(&pairs, &found, models.len());
    let second = problem.second_body().unwrap_or(problem);
    let problems = &[problem, second][..models.len()];
    let held = held_bodies(problems, models, &pairs, &found, &numbering.operators)
        .map_err(lcp::LcpError::from)?;
    if held.len() > 1 {
        let name = |b: usize| format!("`{}` ({})", problems[b].name, held[b].1.name());
        let bodies = format!("{}, {}", name(0), name(1));
        return Err(lcp::LcpError::from(LoadDrivenError::SeveralHeld { bodies }).into());
    }
    let scene = numbering.scene(problem, &pairs, &found, &steps);
    let prepared = sparse_path::prepare(&scene, models, &held)?;
    let on = (models, &held[..]);
    let (walk, work, factors) = match &found[0].target {
        None => {
            let system = super::super::rigid_obstacle(models[0], &found[0].candidates, factors);
            let mut system = system.map_err(lcp::LcpError::from)?;
            let walk = sparse_path::walk(&scene, on, &prepared, &mut system, clock)?;
            (walk, system.stats, system.into_factorisation())
        }
        Some(_) => {
            let gap = &numbering.initial_gap;
            let mut system = super::bodies_system(models, &pairs, &found, gap)?;
            let walk = sparse_path::walk(&scene, on, &prepared, &mut system, clock)?;
            (walk, system.stats, None)
        }
    };
    let (solved, mut frictions, load_driven) = walk.finish(&scene, prepared, work);
    let Solved { result, free_gap, displacements, record, search, .. } = solved;
    let rigid = held_modes(&held, &search, (problems, models), &result, &free_gap)?;
    let [PairCandidates { candidates, target, .. }] = found;
    let answer = SparsePair {
        result,
        free_gap,
        displacements,
        record,
        friction: frictions.pop(),
        rigid_mode: rigid.into_iter().next().map(|(_, mode)| mode),
        load_driven,
        candidates,
        target,
    };
    Ok((answer, factors))
}
