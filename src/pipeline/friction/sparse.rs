//! The load path on the sparse system (docs/method.md §5.1, §8): one body against a rigid
//! obstacle by the active-set method, increment by increment, with the force-driven obstacle
//! and the held translation of §4.6–4.7 as searches over warm-started solves; two bodies in
//! one pair take the several-pairs scene's walk ([`super::super::multibody::pair`]).
//! Frictionless contact in one shot is one step of one increment of it ([`one_shot`]): the
//! frictionless active-set method on the system as built, no tangential operators, and the
//! system owns `K`'s factors, which it may release (docs/method.md §5.1: one factorisation of
//! the body alive at a time).

use super::*;

/// Whether the path is one-shot contact: no `[[step]]` tables, frictionless, no translation
/// held by the contact (one step to the models' loads in one increment, no search).
pub(in crate::pipeline) fn one_shot(problem: &Problem, steps: &[StepEnd], model: &Model) -> bool {
    let pinned = model.system.pinned.is_some();
    let plain = |e: &StepEnd| e.increments == 1 && e.friction == 0.0 && e.force.is_none();
    problem.steps.is_empty() && !pinned && steps.len() == 1 && plain(&steps[0])
}

/// What stays fixed along the path.
struct Path<'p> {
    problem: &'p Problem,
    model: &'p Model,
    candidates: &'p contact::Candidates,
    steps: &'p [StepEnd],
    /// The tangential operator (`None` on a one-shot path: frictionless, none built).
    tangential: Option<&'p contact::BodyOperator>,
    /// A held translation's projection of the candidates' normals on its axis.
    mode_projection: Option<&'p [f64]>,
    params: lcp::active_set::ActiveSetParams,
    /// One-shot contact ([`one_shot`]): the frictionless active-set method.
    once: bool,
}

/// One increment's answer: the step's solution, the body's displacements, the linear solves
/// and Lemke rescues it took.
type Increment = (lcp::active_set::FrictionStepSolution, Vec<f64>, usize, Vec<usize>);

/// What the walk carries from increment to increment: the start of the current step (the
/// previous step's end), the tangential displacements and states to start from, and the
/// records.
struct Walk {
    load0: Vec<f64>,
    rhs0: Vec<f64>,
    d0: geometry::Point,
    force0: f64,
    previous: Vec<f64>,
    warm: Option<Vec<lcp::ContactState>>,
    history: History,
    iterations: usize,
    rescues: Vec<usize>,
    end_all: lcp::active_set::ActiveSetEnd,
    last: Option<(lcp::active_set::FrictionStepSolution, Vec<f64>)>,
    load_driven: Option<solution::LoadDriven>,
    rigid_mode: Option<solution::RigidMode>,
    total_evaluations: usize,
}

/// Frictional contact, load steps or a held translation against a rigid obstacle or a second
/// body (`target`) by the active-set method on the sparse system (docs/method.md §5.1, §8),
/// and frictionless contact in one shot as one step of one increment of it ([`one_shot`]): no
/// blocks `M_**`, no condensation. Two bodies take the walk of a scene of pairs
/// ([`multibody::pair::solve_sparse`]). Against a rigid obstacle each increment sets the load
/// `f_λ`, the obstacle's displacement `d_λ` (through `g0 − d_λ·ν` and `o = d_λ·t`) and the
/// step's `μ` on one [`contact::sparse::RigidObstacle`], whose factorisations and update
/// columns carry over, and starts from the previous increment's states. An obstacle pressed
/// by a force (§4.6) or a translation held by the contact (§4.7) is found by the search of
/// `lcp::load_driven` over warm-started solves. The displacements are those of each
/// increment's final states.
///
/// On a one-shot path against a rigid obstacle the system takes `K`'s factorisation from
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
    if let Some(target) = target {
        return pair_path(problem, spec, model, candidates, target, steps, clock);
    }
    let once = one_shot(problem, steps, model);
    let factors = once.then(|| model.factorisation.take());
    let on = (problem, spec, &*model);
    let (outcome, factors) = walk_path(on, candidates, (steps, once, factors), clock)?;
    if let Some(f) = factors {
        model.factorisation = f;
    }
    Ok(outcome)
}

/// Two bodies in one pair on the sparse path: the walk of a scene of that one pair
/// ([`multibody::pair::solve_sparse`]; a translation of either body held by the contact is
/// its held body), its answer as the pair's contact solution.
fn pair_path(
    problem: &Problem,
    spec: &ContactSpec,
    model: &Model,
    candidates: contact::Candidates,
    target: Target<'_>,
    steps: &[StepEnd],
    clock: &mut Clock<'_>,
) -> Result<ContactOutcome, Error> {
    let Target { model: second, operator, steps: steps2 } = target;
    let pinned = model.system.pinned.or(second.system.pinned);
    let ends = [steps.to_vec(), steps2];
    let answer = multibody::pair::solve_sparse(
        problem,
        spec,
        [model, second],
        (candidates, operator),
        ends,
        clock,
    )?;
    let gap = answer.result.w.clone();
    let mut contact = ContactSolution::new(
        spec,
        answer.candidates,
        Some(answer.target),
        Vec::new(),
        None,
        &answer.free_gap,
        answer.result,
        gap,
        None,
    );
    contact.active_set = answer.record;
    attach_records(&mut contact, problem, answer.friction, pinned, None, answer.rigid_mode);
    let (u1, u2) = answer.displacements;
    Ok((u1, Some(u2), contact))
}

/// [`solve_frictional_active_set`] against a rigid obstacle on the model without the factors
/// the system owns (`factors`, one-shot), which come back with the outcome.
fn walk_path(
    (problem, spec, model): (&Problem, &ContactSpec, &Model),
    mut candidates: contact::Candidates,
    (steps, once, factors): (&[StepEnd], bool, Option<crate::linear_solve::Factorisation>),
    clock: &mut Clock<'_>,
) -> Result<(ContactOutcome, Option<crate::linear_solve::Factorisation>), Error> {
    let tangents = (!once).then(|| tangential_operators(&candidates, model, None));
    let pinned = model.system.pinned;
    refuse_slanted_force(steps, &candidates)?;
    let mode_projection = held_projection(pinned, steps, &candidates)?;
    let free = tangents.as_ref().map_or_else(|| vec![false; candidates.len()], |t| t.1.clone());
    let path = Path {
        problem,
        model,
        candidates: &candidates,
        steps,
        tangential: tangents.as_ref().map(|t| &t.0),
        mode_projection: mode_projection.as_deref(),
        params: lcp::active_set::ActiveSetParams::default(),
        once,
    };
    let mut walk = Walk::new(&path);
    let stage = if once { "active_set" } else { "friction" };
    let (work, factors) = clock.run(stage, || -> Result<_, Error> {
        let mut system = path.system(factors)?;
        for (k, end) in steps.iter().enumerate() {
            path.set_friction(&mut system, &free, k)?;
            for i in 1..=end.increments {
                walk.increment(&path, &mut system, (k, i))?;
            }
            walk.end_step(&path, k);
        }
        Ok((system.stats, system.into_factorisation()))
    })?;
    let Walk { iterations, rescues, end_all, last, history, load_driven, rigid_mode, .. } = walk;
    let Some((answer, u)) = last else {
        unreachable!("validated: at least one step with at least one increment")
    };
    let step = answer.step;
    let result = lcp::LcpSolution {
        residuals: lcp::active_set::residuals(&answer.free_gap, &step.normal, &step.gap),
        w: step.gap.clone(),
        z: step.normal.clone(),
        pivots: iterations,
    };
    move_to_final_obstacle(&mut candidates, steps, load_driven.as_ref());
    let gap = step.gap.clone();
    let segment_length = candidates.segment_length.clone();
    let mut contact = ContactSolution::new(
        spec,
        candidates,
        None,
        Vec::new(),
        None,
        &answer.free_gap,
        result,
        gap,
        None,
    );
    contact.active_set = Some(solution::ActiveSetRecord {
        iterations,
        changes: answer.changes,
        rescues,
        end: end_all,
        work,
    });
    // The frictional record (none on a one-shot path, as on the condensed one-shot route).
    let coefficient = steps.last().map_or(spec.friction, |end| end.friction);
    let friction = tangents.map(|(tangential, free, _)| {
        let mut f =
            solution::FrictionContact::new(coefficient, free, tangential, step, &segment_length);
        history.finish(&mut f);
        f
    });
    attach_records(&mut contact, problem, friction, pinned, load_driven, rigid_mode);
    Ok(((u, None, contact), factors))
}

impl<'p> Path<'p> {
    /// The body's sparse system on its rigid obstacle, which owns `K`'s factors when given
    /// them (`factors`), else borrows the model's.
    fn system(
        &self,
        factors: Option<crate::linear_solve::Factorisation>,
    ) -> Result<contact::sparse::RigidObstacle<'p>, Error> {
        Ok(rigid_obstacle(self.model, self.candidates, factors).map_err(lcp::LcpError::from)?)
    }

    /// Step `k`'s coefficient on every candidate whose tangential row is free (0 where it is
    /// a displacement condition); nothing on a one-shot path (no tangential operators: the
    /// system stays frictionless).
    fn set_friction(
        &self,
        system: &mut contact::sparse::RigidObstacle<'p>,
        free: &[bool],
        k: usize,
    ) -> Result<(), Error> {
        if self.tangential.is_none() {
            return Ok(());
        }
        let mu: Vec<f64> =
            free.iter().map(|&f| if f { self.steps[k].friction } else { 0.0 }).collect();
        system.set_friction(&mu).map_err(lcp::LcpError::from)?;
        Ok(())
    }
}

impl Walk {
    fn new(path: &Path<'_>) -> Self {
        let n = path.model.system.rhs.len();
        let m = path.candidates.len();
        Self {
            load0: vec![0.0; n],
            rhs0: vec![0.0; n],
            d0: [0.0, 0.0],
            force0: 0.0,
            previous: vec![0.0; m],
            warm: None,
            history: History::new(m, path.problem.write_steps),
            iterations: 0,
            rescues: Vec::new(),
            end_all: lcp::active_set::ActiveSetEnd::Converged,
            last: None,
            load_driven: None,
            rigid_mode: None,
            total_evaluations: 0,
        }
    }

    /// Increment `i` of step `k` (0-based): solved, checked for equilibrium, recorded.
    fn increment(
        &mut self,
        path: &Path<'_>,
        system: &mut contact::sparse::RigidObstacle<'_>,
        (k, i): (usize, usize),
    ) -> Result<(), Error> {
        let end = &path.steps[k];
        let started = std::time::Instant::now();
        let lambda = i as f64 / end.increments as f64;
        let named = !path.problem.steps.is_empty();
        let at_step = |e| at_increment(named, (k, i, end.increments), e);
        let (answer, u, step_iterations, step_rescues) = if path.once {
            once_increment(system, &path.params).map_err(at_step)?
        } else {
            let rhs = lerp(&self.rhs0, &end.rhs, lambda);
            self.rigid_increment(path, system, (k, lambda), &rhs, &at_step)?
        };
        let equilibrium = self.equilibrium(path, (k, lambda), &answer.step, &u);
        self.history.record(
            &answer.step,
            (k, i, lambda),
            equilibrium,
            answer.changes.clone(),
            started.elapsed().as_secs_f64(),
        );
        self.previous.clone_from(&answer.step.tangential_displacement);
        self.iterations += step_iterations;
        self.rescues.extend_from_slice(&step_rescues);
        if answer.end != lcp::active_set::ActiveSetEnd::Converged {
            self.end_all = answer.end;
        }
        self.warm = Some(answer.states.clone());
        self.last = Some((answer, u));
        Ok(())
    }

    /// The relative equilibrium error of the body at load factor `lambda` of step `k`.
    fn equilibrium(
        &self,
        path: &Path<'_>,
        (k, lambda): (usize, f64),
        step: &lcp::FrictionSolution,
        u: &[f64],
    ) -> f64 {
        let load = lerp(&self.load0, &path.steps[k].load, lambda);
        let normal = (&path.candidates.operator, step.normal.as_slice());
        let tangential = path.tangential.map(|op_t| (op_t, step.tangential.as_slice()));
        let ops: Vec<_> = std::iter::once(normal).chain(tangential).collect();
        solution::equilibrium_error(&path.model.system, &load, u, &ops)
    }

    /// One increment on a rigid obstacle: the obstacle moved to `d_λ`, and the search of
    /// docs/method.md §4.6–4.7 when a force presses it or the contact holds the body.
    fn rigid_increment(
        &mut self,
        path: &Path<'_>,
        system: &mut contact::sparse::RigidObstacle<'_>,
        (k, lambda): (usize, f64),
        rhs: &[f64],
        at_step: &dyn Fn(lcp::LcpError) -> Error,
    ) -> Result<Increment, Error> {
        let (end, candidates) = (&path.steps[k], path.candidates);
        let d = [
            (1.0 - lambda) * self.d0[0] + lambda * end.obstacle[0],
            (1.0 - lambda) * self.d0[1] + lambda * end.obstacle[1],
        ];
        let (g0, offset): (Vec<f64>, Vec<f64>) = (0..candidates.len())
            .map(|c| {
                let (nu, t) = (candidates.normal(c), candidates.tangent(c));
                let g0 = candidates.initial_gap[c];
                if d == [0.0, 0.0] {
                    (g0, 0.0)
                } else {
                    (g0 - (d[0] * nu[0] + d[1] * nu[1]), d[0] * t[0] + d[1] * t[1])
                }
            })
            .unzip();
        system.set_load(rhs, &g0, &offset);
        let mut trials = ActiveSetTrials {
            system: &mut *system,
            rhs,
            initial_gap: &g0,
            offset: &offset,
            previous: &self.previous,
            along: Vec::new(),
            warm: self.warm.clone(),
            params: path.params,
            iterations: 0,
            rescues: Vec::new(),
        };
        let solved = match (end.force, path.mode_projection) {
            (Some(f), _) => {
                let (e, size, along) = force_along(f, &candidates.normals);
                let target = (1.0 - lambda) * self.force0 + lambda * size;
                trials.along.clone_from(&along);
                trials.params.force_scale = target.abs();
                trials.base_gap().and_then(|base| {
                    lcp::load_driven::find_displacement_with(&mut trials, &base, &along, e, target)
                        .map(|search| {
                            self.total_evaluations += search.evaluations;
                            let s = search.displacement;
                            self.load_driven = Some(solution::LoadDriven::found(
                                (e, target),
                                s,
                                search.force,
                                (search.evaluations, self.total_evaluations),
                            ));
                            (search.answer, None)
                        })
                })
            }
            (None, Some(projection)) => {
                let load = lerp(&self.load0, &end.load, lambda);
                let model = path.model;
                held_search(&mut trials, model, projection, &load, &mut self.total_evaluations).map(
                    |(answer, held, mode)| {
                        self.rigid_mode = Some(mode);
                        (answer, Some(held))
                    },
                )
            }
            (None, None) => {
                use lcp::load_driven::Trials;
                trials.solve(0.0, &g0).map(|answer| (answer, None))
            }
        };
        let (trial_iterations, trial_rescues) = (trials.iterations, trials.rescues);
        let (answer, held) = solved.map_err(at_step)?;
        // The body's translation found: the pin's value, the gaps without the shift (the
        // system the displacements answer is the one reported, as on Lemke's path).
        if let Some((pin, t)) = held {
            let mut rhs = rhs.to_vec();
            load_path::set_pin_value(&mut rhs, path.model, pin, t);
            system.set_load(&rhs, &g0, &offset);
        }
        let u = system.final_friction_displacements(&answer.states).map_err(lcp::LcpError::from)?;
        Ok((answer, u, trial_iterations, trial_rescues))
    }

    /// The previous step's end becomes the next step's start.
    fn end_step(&mut self, path: &Path<'_>, k: usize) {
        let end = &path.steps[k];
        (self.load0, self.rhs0) = (end.load.clone(), end.rhs.clone());
        self.d0 = end.obstacle;
        self.force0 = end.force.map_or(0.0, |f| f[0].hypot(f[1]));
    }
}

/// The increment of a one-shot path: the frictionless active-set method
/// ([`lcp::active_set::solve`], from the free gaps: there is no earlier increment to start
/// from) on the system as built (the models' loads, the obstacle where it was given), the
/// displacements those of its final active set.
fn once_increment(
    system: &mut contact::sparse::RigidObstacle<'_>,
    params: &lcp::active_set::ActiveSetParams,
) -> Result<Increment, lcp::LcpError> {
    let answer = lcp::active_set::solve(system, params)?;
    let u = system.final_displacements(&answer.active)?;
    let (iterations, rescues) = (answer.iterations, answer.rescues.clone());
    let step = lcp::active_set::FrictionStepSolution::frictionless(answer);
    Ok((step, u, iterations, rescues))
}

/// The search for the body's translation held by the contact (docs/method.md §4.7) under
/// `load`: the trials' answer, the pin with the translation found, and its record.
fn held_search(
    trials: &mut ActiveSetTrials<'_, '_>,
    model: &Model,
    projection: &[f64],
    load: &[f64],
    total_evaluations: &mut usize,
) -> Result<
    (lcp::active_set::FrictionStepSolution, (assembly::PinnedMode, f64), solution::RigidMode),
    lcp::LcpError,
> {
    let pin = model.system.pinned.expect("a projection comes with a pin");
    let a = pin.axis as usize;
    let (along_load, sign, along) = pin_along(pin, projection, load)?;
    let mut r = [0.0; 2];
    r[a] = sign;
    trials.along.clone_from(&along);
    trials.params.force_scale = along_load.abs();
    let base = trials.base_gap()?;
    let search =
        lcp::load_driven::find_displacement_with(trials, &base, &along, r, along_load.abs())?;
    *total_evaluations += search.evaluations;
    let t = sign * search.displacement;
    let mut translation = [0.0; 2];
    translation[a] = t;
    let mode = solution::RigidMode {
        mode: pin.name(),
        pin_point: model.nodes.points[pin.node as usize],
        translation,
        load: along_load,
        evaluations: search.evaluations,
        total_evaluations: *total_evaluations,
    };
    Ok((search.answer, (pin, t), mode))
}

/// The trials of a force search (docs/method.md §4.6–4.7) on the active-set path: each is
/// the increment's problem with the gaps without displacement moved to `g0 − a s`, solved
/// by [`lcp::active_set::solve_friction_step`] from the last trial's states; the slope is
/// one solve with the closed set's matrix ([`contact::sparse::RigidObstacle::force_rate`]).
struct ActiveSetTrials<'s, 'a> {
    system: &'s mut contact::sparse::RigidObstacle<'a>,
    rhs: &'s [f64],
    initial_gap: &'s [f64],
    offset: &'s [f64],
    previous: &'s [f64],
    /// `a_c` of the search (empty without one).
    along: Vec<f64>,
    /// The states to start the next solve from.
    warm: Option<Vec<lcp::ContactState>>,
    params: lcp::active_set::ActiveSetParams,
    /// Linear solves and Lemke rescues over the trials.
    iterations: usize,
    rescues: Vec<usize>,
}

impl ActiveSetTrials<'_, '_> {
    /// `q_b`, the gaps without contact forces at `s = 0` (one solve with `K`; `g0` when `K`
    /// alone fails its accuracy check: then only the first trial is a worse guess).
    fn base_gap(&mut self) -> Result<Vec<f64>, lcp::LcpError> {
        use lcp::active_set::FrictionSystem;
        self.system.set_load(self.rhs, self.initial_gap, self.offset);
        Ok(match self.system.free_response().map_err(lcp::LcpError::from)? {
            Some((q, _)) => q,
            None => self.initial_gap.to_vec(),
        })
    }
}

impl lcp::load_driven::Trials for ActiveSetTrials<'_, '_> {
    type Answer = lcp::active_set::FrictionStepSolution;
    type Error = lcp::LcpError;
    fn solve(&mut self, s: f64, _q: &[f64]) -> Result<Self::Answer, lcp::LcpError> {
        if s == 0.0 {
            self.system.set_load(self.rhs, self.initial_gap, self.offset);
        } else {
            let g0 = self.initial_gap.iter().zip(&self.along);
            let shifted: Vec<f64> = g0.map(|(g, a)| g - a * s).collect();
            self.system.set_load(self.rhs, &shifted, self.offset);
        }
        let answer = lcp::active_set::solve_friction_step(
            self.system,
            self.previous,
            self.warm.as_deref(),
            &self.params,
        )?;
        self.iterations += answer.step.iterations;
        self.rescues.extend_from_slice(&answer.rescues);
        self.warm = Some(answer.states.clone());
        Ok(answer)
    }
    fn forces<'b>(&self, answer: &'b Self::Answer) -> &'b [f64] {
        &answer.step.normal
    }
    fn gaps(&self, _q: &[f64], answer: &Self::Answer) -> Vec<f64> {
        answer.step.gap.clone()
    }
    fn slope(
        &mut self,
        answer: &Self::Answer,
        along: &[f64],
        active: &[usize],
    ) -> Result<f64, lcp::LcpError> {
        let mut states = vec![lcp::ContactState::Open; answer.states.len()];
        for &c in active {
            states[c] = match answer.states[c] {
                lcp::ContactState::Open => lcp::ContactState::Stick,
                s => s,
            };
        }
        let rate = self.system.force_rate(&states, along)?;
        Ok(active.iter().map(|&c| along[c] * rate[c]).sum())
    }
}
