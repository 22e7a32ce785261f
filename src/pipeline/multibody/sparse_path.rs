//! Bodies and contact pairs along the load path on the sparse system (docs/method.md §5.1,
//! §8; plan in docs/dev/contact_core.md): friction, `[[step]]` tables and a body held by the
//! contact with `contact[k].solver = "active_set"`, for every sparse problem (one body on
//! rigid obstacles and two bodies in one pair through [`super::pair`]). No condensed blocks:
//! one system ([`SceneSystem`]: [`contact::sparse::Bodies`] over all bodies and pairs, or
//! [`contact::sparse::RigidObstacle`] for one body), whose factorisations and update columns
//! carry over the increments, walked by the load path's one driver ([`load_path::drive`])
//! as a [`PathSystem`]: per step the coefficients `μ_c` on the system, per increment each
//! body's right-hand side and the moved candidates' gaps and stick offsets set on it, and
//! the increment's frictional step solved from the previous increment's states (the held
//! bodies' translations and a force-driven obstacle's displacement by the searches of
//! [`lcp::load_driven`] over warm-started solves, [`SparseTrials`]).

use super::super::friction::StepEnd;
use super::super::load_path::{self, At, Held, PathSystem, Timer, Walked};
use super::path::{self, Scene};
use super::trials::SparseTrials;
use super::{Held as HeldBody, Solved};
use crate::contact::{self, BodyOperator, sparse::SceneSystem};
use crate::error::Error;
use crate::lcp;
use crate::model::Model;
use crate::progress::Clock;
use crate::solution;

/// One increment's answer: the step, every body's displacements and, with held bodies, their
/// translations, the search's LCP solves and the gaps without contact forces at `t = 0`.
struct Increment {
    answer: lcp::active_set::FrictionStepSolution,
    u: Vec<Vec<f64>>,
    held: Option<(Vec<f64>, usize, Vec<f64>)>,
    /// A force-driven obstacle's record (its `total_evaluations` this increment's).
    load_driven: Option<solution::LoadDriven>,
}

/// The gaps `g0 − d·ν_c` and the stick offsets `d·t_c` of the moved candidates
/// (`scene.moved`) with the obstacles at `d`; `None` when no step moves them.
fn obstacle_at(scene: &Scene<'_>, normals: &[crate::geometry::Point], d: [f64; 2]) -> Option<Gaps> {
    if scene.steps[0].iter().all(|e| e.obstacle == [0.0, 0.0]) {
        return None;
    }
    let moved = |c: usize| scene.moved[c] && d != [0.0, 0.0];
    Some(
        (0..normals.len())
            .map(|c| {
                let (nu, t) = (normals[c], crate::contact::tangent(normals[c]));
                let g0 = scene.initial_gap[c];
                if moved(c) {
                    (g0 - (d[0] * nu[0] + d[1] * nu[1]), d[0] * t[0] + d[1] * t[1])
                } else {
                    (g0, 0.0)
                }
            })
            .unzip(),
    )
}

/// Initial gaps and stick offsets per candidate.
type Gaps = (Vec<f64>, Vec<f64>);

/// Whether the scene is one-shot contact: no `[[step]]` tables and frictionless on every
/// pair (one step to the models' loads in one increment; bodies held by the contact are
/// searched inside it, as on the condensed one-shot path).
fn one_shot(scene: &Scene<'_>) -> bool {
    scene.problem.steps.is_empty() && scene.pairs.iter().all(|p| p.spec.friction == 0.0)
}

/// What stays fixed along the sparse path besides the scene: each pair's tangential
/// operators and each body's (none on a one-shot path), `μ` per step and candidate, every
/// candidate's normal, and whether the path is one-shot ([`one_shot`]).
pub(super) struct Prepared {
    tangential: Vec<path::Tangential>,
    by_body: Vec<Indexed>,
    friction: Vec<Vec<f64>>,
    normals: Vec<crate::geometry::Point>,
    once: bool,
}

/// The sparse path's fixed data for `scene` with its `held_bodies`, after the refusals of
/// friction the searches cannot take ([`path::refuse_slanted`], [`path::refuse_force`]).
///
/// # Errors
/// Those refusals.
pub(super) fn prepare(
    scene: &Scene<'_>,
    models: &[&Model],
    held_bodies: &[HeldBody],
) -> Result<Prepared, Error> {
    let once = one_shot(scene);
    let m = scene.initial_gap.len();
    // A one-shot path builds no tangential operators: the system stays frictionless.
    let tangential = if once { Vec::new() } else { path::pair_tangential(scene, models) };
    let by_body = match once {
        true => (0..models.len()).map(|_| None).collect(),
        false => path::tangential_by_body(scene, &tangential, models.len()),
    };
    let friction = match once {
        true => vec![vec![0.0; m]],
        false => path::friction_per_step(scene, &tangential),
    };
    let normals = path::normals(scene);
    for (_, pin, _, _) in held_bodies {
        path::refuse_slanted(pin, &friction, &normals)?;
    }
    path::refuse_force(scene, &friction, &normals)?;
    Ok(Prepared { tangential, by_body, friction, normals, once })
}

/// Friction and load steps for several bodies and pairs on the sparse system: the path of
/// [`path::solve`] with each increment an active-set step instead of the step LCP on
/// condensed blocks; and frictionless contact in one shot as one step of one increment of it
/// ([`one_shot`]: no tangential operators, the frictionless active-set method, or the held
/// bodies' search over warm-started solves), timed as one `active_set` stage. The system is
/// [`contact::sparse::Bodies`] over all bodies and pairs ([`walk`] takes any
/// [`SceneSystem`]).
///
/// # Errors
/// The active-set solver's and the search's errors (naming the step and the increment when
/// the problem has `[[step]]` tables), a failed solve.
pub(super) fn solve(
    scene: &Scene<'_>,
    models: &[&Model],
    held_bodies: &[HeldBody],
    clock: &mut Clock<'_>,
) -> Result<path::OnPath, Error> {
    let prepared = prepare(scene, models, held_bodies)?;
    let mut system = super::bodies_system(models, scene.pairs, scene.found, scene.initial_gap)?;
    let walk = self::walk(scene, (models, held_bodies), &prepared, &mut system, clock)?;
    let work = system.stats;
    drop(system);
    Ok(walk.finish(scene, prepared, work))
}

/// The load path ([`load_path::drive`]) over the scene's sparse `system` (timed as one
/// stage, `friction`, or `active_set` on a one-shot path): per step the coefficients, per
/// increment the bodies' loads and the obstacles set and the step solved; what the walk
/// ends with, which [`Walk::finish`] turns into the path's answer.
///
/// # Errors
/// As [`solve`].
pub(super) fn walk<'p, S: SceneSystem<'p>>(
    scene: &Scene<'_>,
    (models, held_bodies): (&[&Model], &[HeldBody]),
    prepared: &'p Prepared,
    system: &mut S,
    clock: &mut Clock<'_>,
) -> Result<Walk, Error> {
    let once = prepared.once;
    let held = held_bodies.iter().map(|(b, pin, along, _)| Held {
        term: *b,
        pin: *pin,
        along: along.clone(),
    });
    let groups = match once {
        // A one-shot path keeps no frictional record.
        true => Vec::new(),
        false => scene.offsets.windows(2).map(|w| w[0]..w[1]).collect(),
    };
    let path = load_path::Path {
        initial_gap: scene.initial_gap,
        normals: &prepared.normals,
        steps: &scene.steps[0],
        friction: prepared.friction.clone(),
        moved: Some(scene.moved),
        held: held.collect(),
        groups,
        write_steps: scene.problem.write_steps,
        named_steps: !scene.problem.steps.is_empty(),
    };
    let mut sparse = Sparse {
        scene,
        models,
        prepared,
        tangential: prepared.tangential.iter().map(|(t1, _, t2)| (t1, t2.as_ref())).collect(),
        system,
        previous: vec![0.0; scene.initial_gap.len()],
        warm: None,
        evaluations: 0,
        iterations: 0,
        rescues: Vec::new(),
        end_all: lcp::active_set::ActiveSetEnd::Converged,
    };
    let bodies: Vec<(&Model, &[StepEnd])> =
        models.iter().zip(scene.steps).map(|(m, s)| (*m, s.as_slice())).collect();
    let stage = if once { "active_set" } else { "friction" };
    let walked = load_path::drive(&path, &bodies, &mut sparse, (Some(stage), clock))?;
    let Sparse { iterations, rescues, end_all, .. } = sparse;
    Ok(Walk { walked, iterations, rescues, end_all })
}

/// The sparse system along the path: the scene's system, its pairs' tangential operators,
/// and what carries over the increments (the accumulated tangential displacements and the
/// states to start from) with the counts of the active set's record.
struct Sparse<'c, 's, 'p, S> {
    scene: &'c Scene<'s>,
    models: &'c [&'c Model],
    prepared: &'p Prepared,
    tangential: Vec<contact::sparse::PairTangential<'p>>,
    system: &'c mut S,
    previous: Vec<f64>,
    warm: Option<Vec<lcp::ContactState>>,
    /// The force search's solves so far.
    evaluations: usize,
    iterations: usize,
    rescues: Vec<usize>,
    end_all: lcp::active_set::ActiveSetEnd,
}

impl<'p, S: SceneSystem<'p>> PathSystem for Sparse<'_, '_, 'p, S> {
    type Answer = Increment;

    /// The pairs' coefficients on the system (none on a one-shot path: it stays
    /// frictionless).
    fn begin_step(&mut self, path: &load_path::Path<'_>, k: usize) -> Result<(), Error> {
        if !self.prepared.once {
            let tangential = self.tangential.clone();
            self.system
                .set_pair_friction(&path.friction[k], tangential)
                .map_err(lcp::LcpError::from)?;
        }
        Ok(())
    }

    /// The bodies' right-hand sides and the obstacles set on the system, then the step
    /// solved ([`solve_increment`]).
    fn solve(
        &mut self,
        path: &load_path::Path<'_>,
        at: &At<'_>,
        _: &mut Timer<'_, '_>,
    ) -> Result<Increment, lcp::LcpError> {
        for (b, rhs) in at.rhss.iter().enumerate() {
            self.system.set_body_load(b, rhs);
        }
        let moved = obstacle_at(self.scene, &self.prepared.normals, at.obstacle);
        if let Some((g, o)) = &moved {
            self.system.set_initial_gap(g);
            self.system.set_tangential_offset(o);
        }
        let start = Warm {
            previous: &self.previous,
            warm: self.warm.as_deref(),
            params: lcp::active_set::ActiveSetParams::default(),
            initial_gap: moved.as_ref().map_or(self.scene.initial_gap, |(g, _)| g),
        };
        let models = self.models;
        let mut solved =
            solve_increment(&mut *self.system, (path, models), at, start, self.prepared.once)?;
        if let Some(l) = &mut solved.load_driven {
            self.evaluations += l.evaluations;
            l.total_evaluations = self.evaluations;
        }
        Ok(solved)
    }

    /// The final states' displacements (the system's), and the bodies' equilibrium under
    /// the increment's loads.
    fn displacements(
        &mut self,
        _: &load_path::Path<'_>,
        answer: &mut Increment,
        (at, record): (&At<'_>, bool),
        _: &mut Timer<'_, '_>,
    ) -> Result<(Vec<Vec<f64>>, f64), Error> {
        let u = std::mem::take(&mut answer.u);
        let step = &answer.answer.step;
        let equilibrium = match record {
            false => 0.0,
            true => (self.models.iter().enumerate())
                .map(|(b, model)| {
                    let ops = (&self.scene.operators[b], &self.prepared.by_body[b]);
                    body_equilibrium(model, &at.loads[b], &u[b], ops, step)
                })
                .fold(0.0, f64::max),
        };
        Ok((u, equilibrium))
    }

    fn step(answer: &Increment) -> &lcp::FrictionSolution {
        &answer.answer.step
    }

    fn changes(answer: &Increment) -> &[usize] {
        &answer.answer.changes
    }

    fn end_increment(&mut self, solved: &Increment) {
        let answer = &solved.answer;
        self.previous.clone_from(&answer.step.tangential_displacement);
        self.iterations += answer.step.iterations;
        self.rescues.extend_from_slice(&answer.rescues);
        if answer.end != lcp::active_set::ActiveSetEnd::Converged {
            self.end_all = answer.end;
        }
        self.warm = Some(answer.states.clone());
    }
}

/// What the sparse path's walk ends with: the last increment's answer with the bodies'
/// displacements and the pairs' histories, and the active set's counts over all increments.
pub(super) struct Walk {
    walked: Walked<Increment>,
    iterations: usize,
    rescues: Vec<usize>,
    end_all: lcp::active_set::ActiveSetEnd,
}

impl Walk {
    /// The path's answer from its last increment: the normal LCP's view, the held bodies'
    /// translations, one frictional record per pair (none without tangential operators) and
    /// the active set's record.
    pub(super) fn finish(
        self,
        scene: &Scene<'_>,
        prepared: Prepared,
        work: contact::sparse::RigidObstacleStats,
    ) -> path::OnPath {
        let Walk { iterations, rescues, end_all, walked } = self;
        let Walked { last: Increment { answer, held, load_driven, .. }, u, histories } = walked;
        let Prepared { tangential, friction, .. } = prepared;
        let last_friction = friction.last().cloned().unwrap_or_default();
        let step = answer.step;
        let (search, free_gap) = match held {
            Some((t, evaluations, base)) => (t.iter().map(|&t| (t, evaluations)).collect(), base),
            None => (Vec::new(), answer.free_gap),
        };
        let result = lcp::LcpSolution {
            residuals: lcp::active_set::residuals(&free_gap, &step.normal, &step.gap),
            w: step.gap.clone(),
            z: step.normal.clone(),
            pivots: iterations,
        };
        let frictions = path::pair_records(scene, tangential, &step, &last_friction, histories);
        let record = solution::ActiveSetRecord {
            iterations,
            changes: answer.changes,
            rescues,
            end: end_all,
            work,
        };
        let solved = Solved {
            result,
            free_gap,
            condensed: None,
            warning: None,
            search,
            displacements: u,
            record: Some(record),
        };
        (solved, frictions, load_driven)
    }
}

/// Where an increment starts: the accumulated tangential displacements and the states of
/// the previous increment, and the initial gaps with the obstacles where the increment puts
/// them.
struct Warm<'w> {
    previous: &'w [f64],
    warm: Option<&'w [lcp::ContactState]>,
    params: lcp::active_set::ActiveSetParams,
    initial_gap: &'w [f64],
}

/// One increment on the system whose bodies' right-hand sides and gaps are set: the
/// active-set step (on a one-shot path, `once`, the frictionless active-set method), or the
/// search for a force-driven obstacle's displacement ([`force_search`]) or the held bodies'
/// translations ([`held_search`]).
fn solve_increment<'p, S: SceneSystem<'p>>(
    system: &mut S,
    (path, models): (&load_path::Path<'_>, &[&Model]),
    at: &At<'_>,
    start: Warm<'_>,
    once: bool,
) -> Result<Increment, lcp::LcpError> {
    if !path.held.is_empty() {
        return held_search(system, (path, models), at, start);
    }
    if let Some(force) = at.unknowns.force {
        return force_search(system, force, start);
    }
    if once {
        // One-shot: the frictionless active-set method from the free gaps.
        let answer = lcp::active_set::solve(system, &start.params)?;
        let u = system.final_body_displacements(&answer.active)?;
        let answer = lcp::active_set::FrictionStepSolution::frictionless(answer);
        return Ok(Increment { answer, u, held: None, load_driven: None });
    }
    let answer =
        lcp::active_set::solve_friction_step(system, start.previous, start.warm, &start.params)?;
    let u = system.final_body_friction_displacements(&answer.states)?;
    Ok(Increment { answer, u, held: None, load_driven: None })
}

/// An increment with bodies held by the contact (docs/method.md §4.6–4.7): their
/// translations (`at.unknowns.held`: each one's `b_c` and load along its translation, in
/// the order of `path.held`), and a force-driven obstacle's displacement, by nested searches
/// ([`lcp::load_driven::nested::search`]); then each pin set to the translation found and the
/// gaps to the obstacle's displacement alone, so that the displacements answer the system
/// reported.
fn held_search<'p, S: SceneSystem<'p>>(
    system: &mut S,
    (path, models): (&load_path::Path<'_>, &[&Model]),
    at: &At<'_>,
    start: Warm<'_>,
) -> Result<Increment, lcp::LcpError> {
    let (held, force) = (at.unknowns.held, at.unknowns.force);
    let scale = held.iter().fold(force.map_or(0.0, |f| f.2.abs()), |s, h| s.max(h.1.abs()));
    let mut trials = SparseTrials::new(
        &mut *system,
        (start.initial_gap, held[0].0),
        (start.previous.to_vec(), start.warm.map(<[_]>::to_vec)),
        (start.params, scale),
    );
    let force_along = force.map(|(along, _, _)| (along, 0.0));
    trials.outer = held[1..].iter().map(|&(along, _)| (along, 0.0)).chain(force_along).collect();
    let base = trials.base_gap()?;
    let found = lcp::load_driven::nested::search(&mut trials, &base, at.unknowns)?;
    let (iterations, rescues) = (trials.iterations, trials.rescues);
    let mut answer = found.outer.answer;
    answer.step.iterations = iterations;
    answer.rescues = rescues;
    for (Held { term: b, pin, .. }, t) in path.held.iter().zip(&found.translations) {
        let mut rhs = at.rhss[*b].clone();
        load_path::set_pin_value(&mut rhs, models[*b], *pin, *t);
        system.set_body_load(*b, &rhs);
    }
    let s = found.outer.displacement;
    let load_driven = match force {
        Some((along, e, target)) => {
            let g0 = start.initial_gap.iter().zip(along);
            let moved: Vec<f64> = g0.map(|(g, a)| g - a * s).collect();
            system.set_initial_gap(&moved);
            let solves = (found.evaluations, found.evaluations);
            Some(solution::LoadDriven::found((e, target), s, found.outer.force, solves))
        }
        None => {
            system.set_initial_gap(start.initial_gap);
            None
        }
    };
    let u = system.final_body_friction_displacements(&answer.states)?;
    let held = Some((found.translations, found.evaluations, base));
    Ok(Increment { answer, u, held, load_driven })
}

/// A force-driven obstacle's increment (docs/method.md §4.6): the displacement `s` along `e`
/// whose answer carries the increment's force (`a_c`, `e`, the force), over warm-started
/// solves with the moved candidates' gaps at `g0 − a s` (the system is left at the last
/// trial, the answer's).
fn force_search<'p, S: SceneSystem<'p>>(
    system: &mut S,
    (along, e, target): (&[f64], [f64; 2], f64),
    start: Warm<'_>,
) -> Result<Increment, lcp::LcpError> {
    let mut trials = SparseTrials::new(
        &mut *system,
        (start.initial_gap, along),
        (start.previous.to_vec(), start.warm.map(<[_]>::to_vec)),
        (start.params, target.abs()),
    );
    let base = trials.base_gap()?;
    let search = lcp::load_driven::find_displacement_with(&mut trials, &base, along, e, target)?;
    let (iterations, rescues) = (trials.iterations, trials.rescues);
    let mut answer = search.answer;
    answer.step.iterations = iterations;
    answer.rescues = rescues;
    let u = system.final_body_friction_displacements(&answer.states)?;
    let s = search.displacement;
    let found = (search.evaluations, search.evaluations);
    let load_driven = Some(solution::LoadDriven::found((e, target), s, search.force, found));
    Ok(Increment { answer, u, held: None, load_driven })
}

/// A body's operator over the candidates that touch it, with their global indices.
type Indexed = Option<(BodyOperator, Vec<usize>)>;

/// The relative equilibrium error of one body under its load and the normal and tangential
/// forces of the candidates that touch it (`ops`: its normal and tangential operators with
/// the candidates' global indices; `None` when no pair touches it).
fn body_equilibrium(
    model: &Model,
    load: &[f64],
    u: &[f64],
    ops: (&Indexed, &Indexed),
    step: &lcp::FrictionSolution,
) -> f64 {
    let gather = |v: &[f64], index: &[usize]| index.iter().map(|&g| v[g]).collect::<Vec<f64>>();
    match ops {
        (Some((normal, index)), Some((tangential, _))) => {
            let (p, t) = (gather(&step.normal, index), gather(&step.tangential, index));
            let forces = [(normal, p.as_slice()), (tangential, t.as_slice())];
            solution::equilibrium_error(&model.system, load, u, &forces)
        }
        _ => solution::equilibrium_error(&model.system, load, u, &[]),
    }
}
