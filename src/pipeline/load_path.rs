//! The load path (docs/method.md §8; plan in docs/dev/contact_core.md): steps × increments
//! over any number of bodies, walked once ([`drive`]) over either contact system
//! ([`PathSystem`]): the condensed blocks `M = G K⁻¹ E` of [`condensed`] (Lemke, the
//! frictional step LCP) or the sparse system of `multibody::sparse_path` (row replacement,
//! the active set).
//!
//! Per step its coefficients `μ_c`; per increment each body's load and right-hand side at the
//! load factor `λ`, the rigid obstacles where the increment puts them, the held bodies' loads
//! along their translations and a force pressing the obstacles; the system's answer (the step
//! problem, or one of the two searches of docs/method.md §4.6–4.7 around it), each body's
//! displacements, and the pairs' histories.

use super::friction::{History, StepEnd, StepStart, at_increment, force_along, lerp};
use super::*;
use std::ops::Range;

pub(super) mod condensed;

pub(super) use condensed::{
    Condensed, PathAnswer, Term, condense, condense_normal, normal_blocks, normal_lcp,
    run_condensed,
};

/// A body's rigid translation held by the contact alone (docs/method.md §4.7): the pin of
/// the walk's body `term` (a condensed term, or a body of the sparse scene) and
/// `a_c = −s_c ν_c·r` over all candidates (`s_c = +1` on the candidate's body, `−1` on its
/// target), found by the nested search ([`lcp::load_driven::nested`]) from the body's load
/// along `r`.
pub(super) struct Held {
    pub(super) term: usize,
    pub(super) pin: assembly::PinnedMode,
    pub(super) along: Vec<f64>,
}

/// The factor from a body's loads to the contact forces' units: `2π` for an axisymmetric body
/// (its loads are per radian, the rings' forces totals over the circumference, so a held
/// body's search balances `2π` times its load along the translation; `contact::rings`), 1
/// otherwise.
pub(super) fn ring_units(model: &crate::model::Model) -> f64 {
    match model.system.axisymmetric {
        true => crate::contact::rings::REVOLUTION,
        false => 1.0,
    }
}

/// A held body's load `load` along its pinned translation, in the contact forces' units
/// ([`ring_units`]): the target of its search (docs/method.md §4.7).
pub(super) fn load_along(
    model: &crate::model::Model,
    pin: assembly::PinnedMode,
    load: &[f64],
) -> f64 {
    load.iter().skip(pin.axis as usize).step_by(2).sum::<f64>() * ring_units(model)
}

/// Sets the pin's collocation row of `rhs` (body `model`) to the translation `t` found
/// (docs/method.md §4.7): the solve then adds the rigid translation, which `K_int` does not
/// see, to the pinned answer.
pub(super) fn set_pin_value(
    rhs: &mut [f64],
    model: &crate::model::Model,
    pin: assembly::PinnedMode,
    t: f64,
) {
    rhs[crate::nodes::dof(pin.node as usize, pin.axis)] = model.system.collocation_scale * t;
}

/// Refuses the answer of a held body's search when nothing determines the body's position
/// (docs/method.md §4.7): no load along the translation, no force carried along it, and the
/// touching gaps do not block it both ways (every translation of an interval answers).
pub(super) fn check_determined(
    (body, mode): (&str, &'static str),
    load: f64,
    along: &[f64],
    result: &lcp::LcpSolution,
    free_gap: &[f64],
) -> Result<(), lcp::load_driven::LoadDrivenError> {
    let (z, w) = (&result.z, &result.w);
    let carries = z.iter().zip(along).any(|(z, a)| *z * a != 0.0);
    let touching = 1e-12 * free_gap.iter().fold(0.0f64, |g, q| g.max(q.abs()));
    let blocked = |sign: f64| along.iter().zip(w).any(|(a, w)| sign * a > 0.0 && *w <= touching);
    if load == 0.0 && !carries && !(blocked(1.0) && blocked(-1.0)) {
        return Err(lcp::load_driven::LoadDrivenError::Undetermined { body: body.into(), mode });
    }
    Ok(())
}

/// What the load path walks besides the contact system: the candidates' initial gaps and
/// normals, the step ends that carry the obstacle's motion, force and increments (the first
/// body's), `μ`
/// per step and candidate, the candidates the obstacle moves, the held translation, and the
/// candidate ranges whose histories are recorded apart (the pairs).
pub(super) struct Path<'a> {
    pub(super) initial_gap: &'a [f64],
    pub(super) normals: &'a [geometry::Point],
    pub(super) steps: &'a [StepEnd],
    pub(super) friction: Vec<Vec<f64>>,
    /// The candidates the obstacle's motion or force moves (`None`: all): with several pairs,
    /// those of the pairs against rigid obstacles, which move together (docs/method.md §4.6).
    pub(super) moved: Option<&'a [bool]>,
    /// The bodies held by contact alone.
    pub(super) held: Vec<Held>,
    pub(super) groups: Vec<Range<usize>>,
    pub(super) write_steps: bool,
    /// Whether the problem has `[[step]]` tables (a failure then names the step).
    pub(super) named_steps: bool,
}

impl Path<'_> {
    /// Whether the obstacle's motion moves candidate `c`'s target.
    pub(super) fn moves(&self, c: usize) -> bool {
        self.moved.is_none_or(|moved| moved[c])
    }

    /// Frictionless contact in one step of one increment without a search: the one-shot
    /// problem (docs/method.md §4–§5), whose stages are timed one by one (`lemke`,
    /// `lemke_polish`, `solve`) instead of as one `friction` stage.
    pub(super) fn is_one_shot(&self) -> bool {
        let plain = self.held.is_empty() && self.steps.iter().all(|s| s.force.is_none());
        let frictionless = self.friction.iter().flatten().all(|&mu| mu == 0.0);
        plain && frictionless && self.steps.len() == 1 && self.steps[0].increments == 1
    }
}

/// Times the path's stages: inside the path's one stage (no clock), or each as its own
/// stage (the condensed one-shot path, [`Path::is_one_shot`]).
pub(super) struct Timer<'c, 'p>(Option<&'c mut Clock<'p>>);

impl Timer<'_, '_> {
    pub(super) fn run<T>(
        &mut self,
        stage: &'static str,
        f: impl FnOnce(&mut dyn FnMut(usize, usize)) -> T,
    ) -> T {
        match &mut self.0 {
            Some(clock) => clock.run_counted(stage, f),
            None => f(&mut |_, _| {}),
        }
    }
}

/// One increment as the walk hands it to the system: step `k` at load factor `lambda`, each
/// body's load and right-hand side there, the rigid obstacles' displacement `d_λ`, and the
/// searches' unknowns (the held bodies' `a_c` with their loads along their translations in
/// the contact forces' units, a force pressing the obstacles).
pub(super) struct At<'a> {
    pub(super) k: usize,
    pub(super) lambda: f64,
    pub(super) loads: &'a [Vec<f64>],
    pub(super) rhss: &'a [Vec<f64>],
    pub(super) obstacle: [f64; 2],
    pub(super) unknowns: lcp::load_driven::nested::Unknowns<'a>,
}

/// A contact system the load path walks ([`drive`]): the condensed blocks
/// ([`condensed::System`]) or the sparse system (`multibody::sparse_path`).
pub(super) trait PathSystem {
    /// One increment's answer.
    type Answer;

    /// Step `k` begins: its coefficients `μ_c` (`path.friction[k]`).
    ///
    /// # Errors
    /// The system's refusal of the coefficients.
    fn begin_step(&mut self, path: &Path<'_>, k: usize) -> Result<(), Error>;

    /// The increment's answer: its step problem solved, or the searches for the held
    /// translations and a force-driven obstacle's displacement (`at.unknowns`) around it.
    ///
    /// # Errors
    /// The step solver's and the searches' errors.
    fn solve(
        &mut self,
        path: &Path<'_>,
        at: &At<'_>,
        timer: &mut Timer<'_, '_>,
    ) -> Result<Self::Answer, lcp::LcpError>;

    /// Each body's displacements of the answer and, when `record`, the largest relative
    /// equilibrium error of the bodies under their loads and contact forces (else 0).
    ///
    /// # Errors
    /// A failed solve.
    fn displacements(
        &mut self,
        path: &Path<'_>,
        answer: &mut Self::Answer,
        at: (&At<'_>, bool),
        timer: &mut Timer<'_, '_>,
    ) -> Result<(Vec<Vec<f64>>, f64), Error>;

    /// The answer's contact forces, gaps, tangential displacements and states.
    fn step(answer: &Self::Answer) -> &lcp::FrictionSolution;

    /// The active set's changes per iteration, for the histories (none on the condensed
    /// system).
    fn changes(answer: &Self::Answer) -> &[usize];

    /// The answer is taken: what the next increment starts from (the tangential
    /// displacements; the sparse system's states and counts).
    fn end_increment(&mut self, answer: &Self::Answer);
}

/// What the walk ends with: the last increment's answer with each body's displacements, and
/// one history per group of [`Path::groups`].
pub(super) struct Walked<A> {
    pub(super) last: A,
    pub(super) u: Vec<Vec<f64>>,
    pub(super) histories: Vec<History>,
}

/// Walks the load path (docs/method.md §8) over `system`, whose bodies are `bodies` (each
/// one's model and step ends, in the system's order): every step's increments from the
/// unloaded start (no load, the obstacles where they were given). Timed as one `stage`, or
/// (`None`) each of the system's stages on its own.
///
/// # Errors
/// The system's errors (naming the step and the increment when the problem has `[[step]]`
/// tables); a held body whose load pulls it off what holds it ([`refuse_not_pressed`]).
pub(super) fn drive<S: PathSystem>(
    path: &Path<'_>,
    bodies: &[(&Model, &[StepEnd])],
    system: &mut S,
    (stage, clock): (Option<&'static str>, &mut Clock<'_>),
) -> Result<Walked<S::Answer>, Error> {
    let histories = path.groups.iter().map(|g| History::new(g.len(), path.write_steps)).collect();
    let mut walk = Walk { path, bodies, histories, last: None };
    match stage {
        Some(stage) => clock.run(stage, || walk.steps(system, &mut Timer(None)))?,
        None => walk.steps(system, &mut Timer(Some(clock)))?,
    }
    let Some((last, u)) = walk.last else {
        unreachable!("validated: at least one step with at least one increment")
    };
    Ok(Walked { last, u, histories: walk.histories })
}

/// The walk's running state: the histories and the last increment's answer with each body's
/// displacements.
struct Walk<'w, 'a, A> {
    path: &'w Path<'a>,
    bodies: &'w [(&'w Model, &'w [StepEnd])],
    histories: Vec<History>,
    last: Option<(A, Vec<Vec<f64>>)>,
}

impl<A> Walk<'_, '_, A> {
    /// Every step's increments; the step's ends become the next step's start.
    fn steps<S: PathSystem<Answer = A>>(
        &mut self,
        system: &mut S,
        timer: &mut Timer<'_, '_>,
    ) -> Result<(), Error> {
        let path = self.path;
        let mut start = StepStart::new(self.bodies.iter().map(|(m, _)| m.system.rhs.len()));
        for (k, end) in path.steps.iter().enumerate() {
            system.begin_step(path, k)?;
            for i in 1..=end.increments {
                self.increment(system, &start, (k, i), timer)?;
            }
            start.advance(self.bodies.iter().map(|(_, steps)| &steps[k]), end);
        }
        Ok(())
    }

    /// Increment `i` of step `k` (0-based) from the step's `start`: the bodies' loads, the
    /// obstacles and the searches' unknowns at `λ = i / n`, the system's answer and
    /// displacements, the histories.
    fn increment<S: PathSystem<Answer = A>>(
        &mut self,
        system: &mut S,
        start: &StepStart,
        (k, i): (usize, usize),
        timer: &mut Timer<'_, '_>,
    ) -> Result<(), Error> {
        let (path, bodies) = (self.path, self.bodies);
        let started = std::time::Instant::now();
        let end = &path.steps[k];
        let lambda = i as f64 / end.increments as f64;
        // With [[step]] tables, a failure names the step and the increment.
        let at_step = |e| at_increment(path.named_steps, (k, i, end.increments), e);
        let at_lambda = |v0: &[Vec<f64>], which: fn(&StepEnd) -> &Vec<f64>| -> Vec<Vec<f64>> {
            bodies.iter().zip(v0).map(|((_, s), v0)| lerp(v0, which(&s[k]), lambda)).collect()
        };
        let loads = at_lambda(&start.loads, |e| &e.load);
        let rhss = at_lambda(&start.rhss, |e| &e.rhs);
        // The held bodies (their loads along r in the contact's units) and a force-driven
        // obstacle, searched at once (docs/method.md §4.6–4.7).
        let mut held = Vec::with_capacity(path.held.len());
        for Held { term, pin, along } in &path.held {
            let load = load_along(bodies[*term].0, *pin, &loads[*term]);
            refuse_not_pressed(*pin, along, load).map_err(at_step)?;
            held.push((along.as_slice(), load));
        }
        let force = end.force.map(|f| {
            let (e, size, mut along) = force_along(f, path.normals);
            for (c, a) in along.iter_mut().enumerate() {
                if !path.moves(c) {
                    *a = 0.0;
                }
            }
            (along, e, start.force_at(size, lambda))
        });
        let force = force.as_ref().map(|(along, e, target)| (along.as_slice(), *e, *target));
        if let Some((force, e, _)) = force {
            for Held { pin, along, .. } in &path.held {
                refuse_moving_together(*pin, along, (force, e)).map_err(at_step)?;
            }
        }
        let unknowns = lcp::load_driven::nested::Unknowns { held: &held, force };
        let obstacle = start.obstacle_at(end, lambda);
        let at = At { k, lambda, loads: &loads, rhss: &rhss, obstacle, unknowns };
        let mut answer = system.solve(path, &at, timer).map_err(at_step)?;
        let record = !self.histories.is_empty();
        let (u, equilibrium) = system.displacements(path, &mut answer, (&at, record), timer)?;
        let seconds = started.elapsed().as_secs_f64();
        let groups = path.groups.iter().cloned();
        let record = (equilibrium, S::changes(&answer), seconds);
        History::record_pairs(
            &mut self.histories,
            groups,
            S::step(&answer),
            (k, i, lambda),
            record,
        );
        system.end_increment(&answer);
        self.last = Some((answer, u));
        Ok(())
    }
}

/// Refuses a held body whose load along its translation `r` (`load`, non-zero) no contact
/// force can balance: every `a_c` has the opposite sign (the load pulls the body off what
/// holds it, docs/method.md §4.7).
pub(super) fn refuse_not_pressed(
    pin: assembly::PinnedMode,
    along: &[f64],
    load: f64,
) -> Result<(), lcp::LcpError> {
    if load != 0.0 && along.iter().all(|a| load.signum() * a <= 0.0) {
        return Err(lcp::load_driven::LoadDrivenError::NotPressed { mode: pin.name(), load }.into());
    }
    Ok(())
}

/// Refuses a held body that moves with a force-driven obstacle without changing any gap
/// (docs/method.md §4.6–4.7): its `a_c` (`along`) and the force's `a_c` (`force`, along
/// `e`) proportional over the candidates to round-off (Cauchy–Schwarz with equality), as for
/// a body resting on one rigid flat alone: neither position is determined.
pub(super) fn refuse_moving_together(
    pin: assembly::PinnedMode,
    along: &[f64],
    (force, e): (&[f64], [f64; 2]),
) -> Result<(), lcp::LcpError> {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let (ab, aa, bb) = (dot(along, force), dot(along, along), dot(force, force));
    if aa > 0.0 && bb > 0.0 && ab * ab >= (1.0 - 1e-12) * aa * bb {
        let error =
            lcp::load_driven::LoadDrivenError::MovesWithObstacle { mode: pin.name(), direction: e };
        return Err(error.into());
    }
    Ok(())
}

/// The step answer's rows `range` (the residuals, method and counts are the whole step's).
pub(super) fn select(step: &lcp::FrictionSolution, range: Range<usize>) -> lcp::FrictionSolution {
    lcp::FrictionSolution {
        normal: step.normal[range.clone()].to_vec(),
        tangential: step.tangential[range.clone()].to_vec(),
        gap: step.gap[range.clone()].to_vec(),
        tangential_displacement: step.tangential_displacement[range.clone()].to_vec(),
        slip_increment: step.slip_increment[range.clone()].to_vec(),
        state: step.state[range].to_vec(),
        residuals: step.residuals,
        method: step.method,
        pivots: step.pivots,
        iterations: step.iterations,
        lemke_failure: step.lemke_failure.clone(),
    }
}
