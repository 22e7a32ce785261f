//! Bodies and contact pairs along the load path on the sparse system (docs/method.md §5.1,
//! §8; plan in docs/dev/contact_core.md): friction, `[[step]]` tables and a body held by the
//! contact with `contact[k].solver = "active_set"`, for every sparse problem (one body on
//! rigid obstacles and two bodies in one pair through [`super::pair`]). No condensed blocks:
//! one system ([`SceneSystem`]: [`contact::sparse::Bodies`] over all bodies and pairs, or
//! [`contact::sparse::RigidObstacle`] for one body), whose factorisations and update columns
//! carry over the increments; per increment each body's right-hand side, per step
//! the coefficients `μ_c`, and the increment's frictional step solved from the previous
//! increment's states (the held body's translation by the search of
//! [`lcp::load_driven::find_translation_with`], a force-driven obstacle's displacement by
//! [`lcp::load_driven::find_displacement_with`], over warm-started solves). A step's
//! obstacle motion moves the gaps and the stick targets of the pairs against rigid
//! obstacles (docs/method.md §4.6, §8).

use super::super::friction::{History, StepEnd, StepStart, at_increment, force_along, lerp};
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

/// The rigid obstacles at load factor `lambda` of step `k`, from where the previous step left
/// them (`start`): the moved gaps and stick offsets ([`obstacle_at`]), and
/// a force's direction `e`, the increment's force and `a_c = ν_c·e` on the moved candidates.
fn obstacle_increment(
    scene: &Scene<'_>,
    normals: &[crate::geometry::Point],
    (k, lambda): (usize, f64),
    start: &StepStart,
) -> (Option<Gaps>, Option<Force>) {
    let end = &scene.steps[0][k];
    let d = start.obstacle_at(end, lambda);
    let force = end.force.map(|f| {
        let (e, size, mut along) = force_along(f, normals);
        along.iter_mut().zip(scene.moved).filter(|(_, m)| !**m).for_each(|(a, _)| *a = 0.0);
        (e, start.force_at(size, lambda), along)
    });
    (obstacle_at(scene, normals, d), force)
}

/// A force pressing the obstacles: its direction `e`, the increment's magnitude and `a_c`.
type Force = ([f64; 2], f64, Vec<f64>);

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

/// What the increments read: the scene, the models, the held bodies and the path's fixed
/// data.
struct Context<'c, 's> {
    scene: &'c Scene<'s>,
    models: &'c [&'c Model],
    held_bodies: &'c [HeldBody],
    prepared: &'c Prepared,
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

/// The walk of the sparse path over the steps and their increments on `system` (timed as one
/// stage, `friction`, or `active_set` on a one-shot path): per step the coefficients, per
/// increment the bodies' loads and the obstacles set and the step solved; the walk's state
/// at its end, which [`Walk::finish`] turns into the path's answer.
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
    let pair_tangential: Vec<contact::sparse::PairTangential<'p>> =
        prepared.tangential.iter().map(|(t1, _, t2)| (t1, t2.as_ref())).collect();
    let cx = Context { scene, models, held_bodies, prepared };
    let mut walk = Walk::new(scene, models);
    let stage = if once { "active_set" } else { "friction" };
    clock.run(stage, || -> Result<_, Error> {
        for (k, end) in scene.steps[0].iter().enumerate() {
            if !once {
                let tangential = pair_tangential.clone();
                let mu = &prepared.friction[k];
                system.set_pair_friction(mu, tangential).map_err(lcp::LcpError::from)?;
            }
            for i in 1..=end.increments {
                walk.increment(&cx, system, (k, i))?;
            }
            walk.end_step(scene, k);
        }
        Ok(())
    })?;
    Ok(walk)
}

/// The path's running state: the previous step's end (each body's load and right-hand side,
/// the obstacles' position and force), the accumulated tangential displacements and states
/// to start from, the records, and the last increment's answer.
pub(super) struct Walk {
    start: StepStart,
    /// The force search's solves so far.
    evaluations: usize,
    previous: Vec<f64>,
    warm: Option<Vec<lcp::ContactState>>,
    histories: Vec<History>,
    iterations: usize,
    rescues: Vec<usize>,
    end_all: lcp::active_set::ActiveSetEnd,
    last: Option<Increment>,
}

impl Walk {
    fn new(scene: &Scene<'_>, models: &[&Model]) -> Self {
        let histories = (0..scene.pairs.len())
            .map(|k| {
                History::new(scene.offsets[k + 1] - scene.offsets[k], scene.problem.write_steps)
            })
            .collect();
        Self {
            start: StepStart::new(models.iter().map(|m| m.system.rhs.len())),
            evaluations: 0,
            previous: vec![0.0; scene.initial_gap.len()],
            warm: None,
            histories,
            iterations: 0,
            rescues: Vec::new(),
            end_all: lcp::active_set::ActiveSetEnd::Converged,
            last: None,
        }
    }

    /// Each body's load and right-hand side at load factor `lambda` of step `k` (on a
    /// one-shot path the step's end itself, bit for bit: the models' own).
    fn loads(&self, cx: &Context<'_, '_>, (k, lambda): (usize, f64)) -> [Vec<Vec<f64>>; 2] {
        let at = |ends: &[Vec<f64>], which: fn(&StepEnd) -> &Vec<f64>| -> Vec<Vec<f64>> {
            let steps = cx.scene.steps.iter().zip(ends);
            match cx.prepared.once {
                true => steps.map(|(e, _)| which(&e[k]).clone()).collect(),
                false => steps.map(|(e, v0)| lerp(v0, which(&e[k]), lambda)).collect(),
            }
        };
        [at(&self.start.loads, |e| &e.load), at(&self.start.rhss, |e| &e.rhs)]
    }

    /// Increment `i` of step `k` (0-based): the bodies' loads and the obstacles set, solved,
    /// recorded (but on a one-shot path, which has no frictional record).
    fn increment<'p, S: SceneSystem<'p>>(
        &mut self,
        cx: &Context<'_, '_>,
        system: &mut S,
        (k, i): (usize, usize),
    ) -> Result<(), Error> {
        let scene = cx.scene;
        let end = &scene.steps[0][k];
        let started = std::time::Instant::now();
        let lambda = i as f64 / end.increments as f64;
        let named = !scene.problem.steps.is_empty();
        let at_step = |e| at_increment(named, (k, i, end.increments), e);
        let [loads, rhss] = self.loads(cx, (k, lambda));
        for (b, rhs) in rhss.iter().enumerate() {
            system.set_body_load(b, rhs);
        }
        let (moved, force) =
            obstacle_increment(scene, &cx.prepared.normals, (k, lambda), &self.start);
        if let Some((g, o)) = &moved {
            system.set_initial_gap(g);
            system.set_tangential_offset(o);
        }
        let state = Warm {
            previous: &self.previous,
            warm: self.warm.as_deref(),
            params: lcp::active_set::ActiveSetParams::default(),
            initial_gap: moved.as_ref().map_or(scene.initial_gap, |(g, _)| g),
            force,
        };
        let bodies = (cx.models, cx.held_bodies);
        let mut solved = solve_increment(system, bodies, (&loads, &rhss), state, cx.prepared.once)
            .map_err(at_step)?;
        if let Some(l) = &mut solved.load_driven {
            self.evaluations += l.evaluations;
            l.total_evaluations = self.evaluations;
        }
        if !cx.prepared.once {
            self.record(cx, &solved, &loads, (k, i, lambda), started);
        }
        let answer = &solved.answer;
        self.previous.clone_from(&answer.step.tangential_displacement);
        self.iterations += answer.step.iterations;
        self.rescues.extend_from_slice(&answer.rescues);
        if answer.end != lcp::active_set::ActiveSetEnd::Converged {
            self.end_all = answer.end;
        }
        self.warm = Some(answer.states.clone());
        self.last = Some(solved);
        Ok(())
    }

    /// Records the increment in every pair's history, with the largest relative equilibrium
    /// error of the bodies under `loads`.
    fn record(
        &mut self,
        cx: &Context<'_, '_>,
        solved: &Increment,
        loads: &[Vec<f64>],
        (k, i, lambda): (usize, usize, f64),
        started: std::time::Instant,
    ) {
        let (scene, step) = (cx.scene, &solved.answer.step);
        let equilibrium = cx
            .models
            .iter()
            .enumerate()
            .map(|(b, model)| {
                let ops = (&scene.operators[b], &cx.prepared.by_body[b]);
                body_equilibrium(model, &loads[b], &solved.u[b], ops, step)
            })
            .fold(0.0, f64::max);
        let seconds = started.elapsed().as_secs_f64();
        let groups = scene.offsets.windows(2).map(|w| w[0]..w[1]);
        let record = (equilibrium, &solved.answer.changes[..], seconds);
        History::record_pairs(&mut self.histories, groups, step, (k, i, lambda), record);
    }

    /// The previous step's end becomes the next step's start.
    fn end_step(&mut self, scene: &Scene<'_>, k: usize) {
        self.start.advance(scene.steps.iter().map(|ends| &ends[k]), &scene.steps[0][k]);
    }

    /// The path's answer from its last increment: the normal LCP's view, the held bodies'
    /// translations, one frictional record per pair (none without tangential operators) and
    /// the active set's record.
    pub(super) fn finish(
        self,
        scene: &Scene<'_>,
        prepared: Prepared,
        work: contact::sparse::RigidObstacleStats,
    ) -> path::OnPath {
        let Walk { iterations, rescues, end_all, last, histories, .. } = self;
        let Prepared { tangential, friction, .. } = prepared;
        let Some(Increment { answer, u, held, load_driven }) = last else {
            unreachable!("validated: at least one step with at least one increment")
        };
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
/// the previous increment, the initial gaps with the obstacles where the increment puts them,
/// and a force pressing them (`e`, the increment's force, `a_c = ν_c·e` on the moved
/// candidates).
struct Warm<'w> {
    previous: &'w [f64],
    warm: Option<&'w [lcp::ContactState]>,
    params: lcp::active_set::ActiveSetParams,
    initial_gap: &'w [f64],
    force: Option<Force>,
}

/// One increment on the system whose bodies' right-hand sides and gaps are set: the
/// active-set step (on a one-shot path, `once`, the frictionless active-set method), or the
/// search for a force-driven obstacle's displacement ([`force_search`]) or the held bodies'
/// translations ([`held_search`]).
fn solve_increment<'p, S: SceneSystem<'p>>(
    system: &mut S,
    (models, held_bodies): (&[&Model], &[HeldBody]),
    (loads, rhss): (&[Vec<f64>], &[Vec<f64>]),
    start: Warm<'_>,
    once: bool,
) -> Result<Increment, lcp::LcpError> {
    if held_bodies.is_empty() {
        if start.force.is_some() {
            return force_search(system, start);
        }
        if once {
            // One-shot: the frictionless active-set method from the free gaps.
            let answer = lcp::active_set::solve(system, &start.params)?;
            let u = system.final_body_displacements(&answer.active)?;
            let answer = lcp::active_set::FrictionStepSolution::frictionless(answer);
            return Ok(Increment { answer, u, held: None, load_driven: None });
        }
        let answer = lcp::active_set::solve_friction_step(
            system,
            start.previous,
            start.warm,
            &start.params,
        )?;
        let u = system.final_body_friction_displacements(&answer.states)?;
        return Ok(Increment { answer, u, held: None, load_driven: None });
    }
    let held: Vec<(&[f64], f64)> = held_bodies
        .iter()
        .map(|(b, pin, along, _)| {
            (along.as_slice(), super::super::load_path::load_along(models[*b], *pin, &loads[*b]))
        })
        .collect();
    held_search(system, models, (held_bodies, &held), rhss, start)
}

/// An increment with bodies held by the contact (docs/method.md §4.6–4.7): their
/// translations (`held`: each one's `b_c` and load along its translation, in the order of
/// `held_bodies`), and a force-driven obstacle's displacement, by nested searches
/// ([`lcp::load_driven::nested::search`]); then each pin set to the translation found and the
/// gaps to the obstacle's displacement alone, so that the displacements answer the system
/// reported.
fn held_search<'p, S: SceneSystem<'p>>(
    system: &mut S,
    models: &[&Model],
    (held_bodies, held): (&[HeldBody], &[(&[f64], f64)]),
    rhss: &[Vec<f64>],
    start: Warm<'_>,
) -> Result<Increment, lcp::LcpError> {
    let force = start.force.clone();
    let scale =
        held.iter().fold(force.as_ref().map_or(0.0, |f| f.1.abs()), |s, h| s.max(h.1.abs()));
    let mut trials = SparseTrials::new(
        &mut *system,
        (start.initial_gap, held[0].0),
        (start.previous.to_vec(), start.warm.map(<[_]>::to_vec)),
        (start.params, scale),
    );
    let force_along = force.as_ref().map(|(_, _, along)| (along.as_slice(), 0.0));
    trials.outer = held[1..].iter().map(|&(along, _)| (along, 0.0)).chain(force_along).collect();
    let base = trials.base_gap()?;
    let unknowns = lcp::load_driven::nested::Unknowns {
        held,
        force: force.as_ref().map(|(e, target, along)| (along.as_slice(), *e, *target)),
    };
    let found = lcp::load_driven::nested::search(&mut trials, &base, unknowns)?;
    let (iterations, rescues) = (trials.iterations, trials.rescues);
    let mut answer = found.outer.answer;
    answer.step.iterations = iterations;
    answer.rescues = rescues;
    for ((b, pin, _, _), t) in held_bodies.iter().zip(&found.translations) {
        let mut rhs = rhss[*b].clone();
        super::super::load_path::set_pin_value(&mut rhs, models[*b], *pin, *t);
        system.set_body_load(*b, &rhs);
    }
    let s = found.outer.displacement;
    let load_driven = match &force {
        Some((e, target, along)) => {
            let g0 = start.initial_gap.iter().zip(along);
            let moved: Vec<f64> = g0.map(|(g, a)| g - a * s).collect();
            system.set_initial_gap(&moved);
            let solves = (found.evaluations, found.evaluations);
            Some(solution::LoadDriven::found((*e, *target), s, found.outer.force, solves))
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
/// whose answer carries the increment's force, over warm-started solves with the moved
/// candidates' gaps at `g0 − a s` (the system is left at the last trial, the answer's).
fn force_search<'p, S: SceneSystem<'p>>(
    system: &mut S,
    start: Warm<'_>,
) -> Result<Increment, lcp::LcpError> {
    let (e, target, along) = start.force.expect("a force");
    let mut trials = SparseTrials::new(
        &mut *system,
        (start.initial_gap, &along),
        (start.previous.to_vec(), start.warm.map(<[_]>::to_vec)),
        (start.params, target.abs()),
    );
    let base = trials.base_gap()?;
    let search = lcp::load_driven::find_displacement_with(&mut trials, &base, &along, e, target)?;
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
