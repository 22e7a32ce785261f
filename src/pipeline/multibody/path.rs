//! Several bodies and contact pairs along the load path (docs/method.md §4.5, §8; plan in
//! docs/dev/contact_core.md): friction, `[[step]]` tables and a body held by the contact,
//! each body one [`load_path::Term`] over the candidates of the pairs that touch it.

use super::super::friction::{History, StepEnd, tangential_operators};
use super::super::load_path::{self, Held, Path, Term};
use super::{Held as HeldBody, PairCandidates, Solved};
use crate::contact::BodyOperator;
use crate::error::Error;
use crate::lcp::{self, load_driven::LoadDrivenError};
use crate::model::Model;
use crate::problem::{ContactPair, Problem};
use crate::progress::Clock;
use crate::solution::FrictionContact;

/// Each pair's tangential operators: the candidate body's, whether each candidate can take a
/// tangential force, and the target body's (direction `−t`) for a pair between bodies.
pub(super) type Tangential = (BodyOperator, Vec<bool>, Option<BodyOperator>);

/// Every pair's [`Tangential`] operators.
pub(super) fn pair_tangential(scene: &Scene<'_>, models: &[&Model]) -> Vec<Tangential> {
    scene
        .pairs
        .iter()
        .zip(scene.found)
        .map(|(pair, f)| {
            let target = pair.target_body.zip(f.target.as_ref()).map(|(t, op)| (models[t], op));
            tangential_operators(&f.candidates, models[pair.body], target)
        })
        .collect()
}

/// Each body's tangential operator over the candidates that touch it (with their global
/// indices), as [`super::body_operator`] gives the normal ones.
pub(super) fn tangential_by_body(
    scene: &Scene<'_>,
    tangential: &[Tangential],
    bodies: usize,
) -> Vec<Option<(BodyOperator, Vec<usize>)>> {
    let ops: Vec<_> = tangential.iter().map(|(t, _, t2)| (t, t2.as_ref())).collect();
    (0..bodies).map(|b| super::body_operator(b, scene.pairs, &ops, scene.offsets)).collect()
}

/// Every candidate's normal, pair after pair.
pub(super) fn normals(scene: &Scene<'_>) -> Vec<crate::geometry::Point> {
    scene.found.iter().flat_map(|f| f.candidates.normals.iter().copied()).collect()
}

/// One frictional record per pair from the path's last answer `step`, the coefficients of
/// the last step and the pairs' histories.
pub(super) fn pair_records(
    scene: &Scene<'_>,
    tangential: Vec<Tangential>,
    step: &lcp::FrictionSolution,
    last_friction: &[f64],
    histories: Vec<History>,
) -> Vec<FrictionContact> {
    tangential
        .into_iter()
        .zip(histories)
        .enumerate()
        .map(|(k, ((op, free, target_op), history))| {
            let range = scene.offsets[k]..scene.offsets[k + 1];
            let coefficient = last_friction[range.clone()].iter().copied().fold(0.0, f64::max);
            let step = load_path::select(step, range);
            let length = &scene.found[k].candidates.segment_length;
            let mut f = FrictionContact::new(coefficient, free, op, step, length);
            history.finish(&mut f);
            f.target_operator = target_op;
            f
        })
        .collect()
}

/// What the path needs of the scene besides the models.
#[derive(Clone, Copy)]
pub(super) struct Scene<'s> {
    pub(super) problem: &'s Problem,
    pub(super) pairs: &'s [ContactPair],
    pub(super) found: &'s [PairCandidates],
    pub(super) offsets: &'s [usize],
    pub(super) operators: &'s [Option<(BodyOperator, Vec<usize>)>],
    pub(super) initial_gap: &'s [f64],
    /// Whether each candidate's pair is against rigid obstacles: the candidates a step's
    /// obstacle motion or force moves (all rigid obstacles together; docs/method.md §4.6).
    pub(super) moved: &'s [bool],
    /// Each body's step ends (the same steps and increments for every body).
    pub(super) steps: &'s [Vec<StepEnd>],
}

/// `μ` per candidate in each step: a step's `friction` when it sets one, else each pair's
/// own; 0 where the candidate's tangential row is a displacement condition.
pub(super) fn friction_per_step(scene: &Scene<'_>, tangential: &[Tangential]) -> Vec<Vec<f64>> {
    let steps = &scene.problem.steps;
    let count = steps.len().max(1);
    (0..count)
        .map(|k| {
            scene
                .pairs
                .iter()
                .zip(tangential)
                .flat_map(|(pair, (_, free, _))| {
                    let mu = match steps.get(k) {
                        Some(step) if step.friction_set => step.friction,
                        _ => pair.spec.friction,
                    };
                    free.iter().map(move |&f| if f { mu } else { 0.0 })
                })
                .collect()
        })
        .collect()
}

/// Refuses friction with a held body where a frictional candidate's tangent is not
/// orthogonal to the held translation ([`super::super::friction::slanted`]).
pub(super) fn refuse_slanted(
    pin: &crate::assembly::PinnedMode,
    friction: &[Vec<f64>],
    normals: &[crate::geometry::Point],
) -> Result<(), Error> {
    let frictional = |c: usize| friction.iter().any(|mu| mu[c] > 0.0);
    use super::super::friction::{axis_direction, slanted};
    match slanted(normals, axis_direction(pin.axis as usize), frictional) {
        None => Ok(()),
        Some(c) => {
            let why = format!(
                "the contact has friction and candidate {c}'s tangent has a component along the held translation (its tangential force would enter the balance the search solves)"
            );
            Err(lcp::LcpError::from(LoadDrivenError::Unsupported { mode: pin.name(), why }).into())
        }
    }
}

/// Refuses a force-driven obstacle with friction on a moved candidate whose tangent has a
/// component along the force ([`super::super::friction::refuse_slanted_force_on`]).
pub(super) fn refuse_force(
    scene: &Scene<'_>,
    friction: &[Vec<f64>],
    normals: &[crate::geometry::Point],
) -> Result<(), Error> {
    let mu = |k: usize, c: usize| if scene.moved[c] { friction[k][c] } else { 0.0 };
    super::super::friction::refuse_slanted_force_on(&scene.steps[0], normals, mu)
}

/// The held bodies' searches on the path (docs/method.md §4.7), with friction only as
/// [`refuse_slanted`] allows.
pub(super) fn held_on_path(
    held: &[HeldBody],
    term_of: &[Option<usize>],
    friction: &[Vec<f64>],
    normals: &[crate::geometry::Point],
) -> Result<Vec<Held>, Error> {
    let mut on_path = Vec::with_capacity(held.len());
    for (b, pin, along, _) in held {
        refuse_slanted(pin, friction, normals)?;
        let term = term_of[*b].expect("a held body is touched by a pair");
        on_path.push(Held { term, pin: *pin, along: along.clone() });
    }
    Ok(on_path)
}

/// What the load path gives the scene: the answer, one frictional record per pair, and the
/// force-driven obstacle's record.
pub(super) type OnPath = (Solved, Vec<FrictionContact>, Option<crate::solution::LoadDriven>);

/// Friction and load steps for several bodies and pairs: the condensed blocks of every body
/// over all candidates, the load path (Lemke's frictionless steps with `lemke`'s parameters),
/// one frictional record per pair.
///
/// # Errors
/// The condensation's and the compliance checks' errors, the path's (Lemke's numerical
/// failure as its refusal, [`Error::LemkeRefused`], inside the increment that failed).
pub(super) fn solve(
    scene: &Scene<'_>,
    models: &[&Model],
    held_bodies: &[HeldBody],
    lemke: &lcp::LemkeParams,
    clock: &mut Clock<'_>,
) -> Result<OnPath, Error> {
    let pairs = scene.pairs;
    let tangential = pair_tangential(scene, models);
    let tangential_by_body = tangential_by_body(scene, &tangential, models.len());
    let mut term_of = vec![None; models.len()];
    let mut terms = Vec::new();
    for (b, (normal, tangential)) in scene.operators.iter().zip(&tangential_by_body).enumerate() {
        if let (Some((normal, index)), Some((tangential, _))) = (normal, tangential) {
            term_of[b] = Some(terms.len());
            terms.push(Term {
                model: models[b],
                normal,
                tangential: Some(tangential),
                index: Some(index),
                steps: &scene.steps[b],
            });
        }
    }
    let normals = normals(scene);
    let friction = friction_per_step(scene, &tangential);
    refuse_force(scene, &friction, &normals)?;
    let held = held_on_path(held_bodies, &term_of, &friction, &normals)?;
    let load_path::Condensed { blocks, compliance } =
        clock.run("condensation", || load_path::condense(&terms, scene.initial_gap))?;
    let targets = super::pair_targets(scene.found, scene.offsets);
    let warning = super::compliance_warning(scene.problem, pairs, &targets, &compliance)?;
    let path = Path {
        initial_gap: scene.initial_gap,
        normals: &normals,
        steps: &scene.steps[0],
        friction,
        moved: Some(scene.moved),
        held,
        groups: (0..pairs.len()).map(|k| scene.offsets[k]..scene.offsets[k + 1]).collect(),
        write_steps: scene.problem.write_steps,
        named_steps: !scene.problem.steps.is_empty(),
    };
    let overridden = warning.is_some();
    let answer = load_path::run_condensed(&path, &terms, blocks, lemke, clock)
        .map_err(|e| super::super::refused_on_path(e, &compliance, overridden))?;
    let last_friction = path.friction.last().cloned().unwrap_or_default();
    drop(terms);
    let result = load_path::normal_lcp(&answer.problem, &answer.step)?;
    // Each body's displacements: its term's, or (no pair touches it) its own solve.
    let mut solved = answer.u.into_iter();
    let mut u = Vec::with_capacity(models.len());
    for (b, m) in models.iter().enumerate() {
        match term_of[b] {
            Some(_) => u.push(solved.next().expect("one answer per term")),
            None => u.push(m.factorisation.solve(&m.system.rhs)?),
        }
    }
    let frictions = pair_records(scene, tangential, &answer.step, &last_friction, answer.histories);
    let search = (answer.rigid_modes.iter().zip(held_bodies))
        .map(|(r, (_, pin, _, _))| (r.translation[pin.axis as usize], r.evaluations))
        .collect();
    let solved = Solved {
        result,
        free_gap: compliance.free_gap.clone(),
        condensed: Some(compliance),
        warning,
        search,
        displacements: u,
        record: None,
    };
    Ok((solved, frictions, answer.load_driven))
}
