//! The load path on the sparse system (docs/method.md §5.1, §8) for one contact pair: one
//! body against rigid obstacles or two bodies, by the active-set method increment by
//! increment, with the force-driven obstacle and the held translation of §4.6–4.7 as searches
//! over warm-started solves. Both walk the scene's sparse path
//! ([`super::super::multibody::pair`]); this module turns its answer into the pair's contact
//! solution. Frictionless contact in one shot is one step of one increment of it: the
//! frictionless active-set method on the system as built, no tangential operators, and
//! against rigid obstacles the system owns `K`'s factors, which it may release
//! (docs/method.md §5.1: one factorisation of the body alive at a time).

use super::*;

/// Whether the body's system on its rigid obstacles owns `K`'s factors (and may release
/// them): one-shot contact (no `[[step]]` tables, frictionless) of one body against rigid
/// obstacles with no translation held by the contact (a search comes back to `K`'s factors).
fn owns_factors(problem: &Problem, spec: &ContactSpec, model: &Model, rigid: bool) -> bool {
    rigid && problem.steps.is_empty() && spec.friction == 0.0 && model.system.pinned.is_none()
}

/// Frictional contact, load steps or a held translation against rigid obstacles or a second
/// body (`target`) by the active-set method on the sparse system (docs/method.md §5.1, §8),
/// and frictionless contact in one shot as one step of one increment of it: no blocks `M_**`,
/// no condensation. The pair walks the scene's sparse path
/// ([`multibody::pair::solve_sparse`]): each increment sets the bodies' loads, the
/// obstacles' displacement `d_λ` (through `g0 − d_λ·ν` and `o = d_λ·t`) and the step's `μ`
/// on one system, whose factorisations and update columns carry over, and starts from the
/// previous increment's states. An obstacle pressed by a force (§4.6) or a translation held
/// by the contact (§4.7) is found by the search of `lcp::load_driven` over warm-started
/// solves. The displacements are those of each increment's final states.
///
/// On a one-shot path against rigid obstacles the system takes `K`'s factorisation from
/// `model` and gives it back, its factors released if it factorised a row-replaced matrix
/// ([`contact::sparse::ModelFactors`]): the peak is then one factorisation of the body, not
/// two. Only statistics are left of `model.factorisation` then.
pub(in crate::pipeline) fn solve_frictional_active_set(
    problem: &Problem,
    spec: &ContactSpec,
    model: &mut Model,
    candidates: contact::Candidates,
    target: Option<Target<'_>>,
    steps: &[StepEnd],
    clock: &mut Clock<'_>,
) -> Result<ContactOutcome, Error> {
    let owns = owns_factors(problem, spec, model, target.is_none());
    let factors = owns.then(|| model.factorisation.take());
    let second = target.as_ref().map(|t| t.model);
    let pinned = model.system.pinned.or(second.and_then(|m| m.system.pinned));
    let models: Vec<&Model> = std::iter::once(&*model).chain(second).collect();
    let (operator, ends) = match target {
        Some(Target { operator, steps: steps2, .. }) => {
            (Some(operator), vec![steps.to_vec(), steps2])
        }
        None => (None, vec![steps.to_vec()]),
    };
    let on = (ends, factors);
    let solved =
        multibody::pair::solve_sparse(problem, spec, &models, (candidates, operator), on, clock);
    drop(models);
    let (answer, factors) = solved?;
    if let Some(f) = factors {
        model.factorisation = f;
    }
    let multibody::pair::SparsePair { mut candidates, load_driven, .. } = answer;
    move_to_final_obstacle(&mut candidates, steps, load_driven.as_ref());
    let gap = answer.result.w.clone();
    let mut contact = ContactSolution::new(
        spec,
        candidates,
        answer.target,
        Vec::new(),
        None,
        &answer.free_gap,
        answer.result,
        gap,
        None,
    );
    contact.active_set = answer.record;
    attach_records(&mut contact, problem, answer.friction, pinned, load_driven, answer.rigid_mode);
    let mut u = answer.displacements.into_iter();
    let u1 = u.next().expect("the sparse path gives the first body's displacements");
    Ok((u1, u.next(), contact))
}
