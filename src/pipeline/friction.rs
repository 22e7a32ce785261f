//! Frictional contact in the pipeline: the ends of the load steps and the frictional
//! solve over their increments (docs/method.md §8; plan in docs/dev/friction.md).

use super::*;

mod sparse;
pub(super) use sparse::solve_frictional_active_set;

/// The end of one load step: the load `f` and the solved right-hand side there, the rigid
/// obstacle's total displacement, and the increments that reach it.
#[derive(Clone, Debug)]
pub(super) struct StepEnd {
    pub(super) increments: usize,
    pub(super) load: Vec<f64>,
    pub(super) rhs: Vec<f64>,
    pub(super) obstacle: geometry::Point,
    /// The force pressing the rigid obstacle (`[[step]] obstacle_force`; then `obstacle` is
    /// zero and the displacement along the force is found per increment, docs/method.md §4.6).
    pub(super) force: Option<geometry::Point>,
    /// The Coulomb coefficient during the step.
    pub(super) friction: f64,
}

impl StepEnd {
    /// One step to `model`'s own load in one increment, the obstacle where it was given (a
    /// problem without `[[step]]` tables on the load path), with the coefficient `friction`.
    pub(super) fn whole(model: &Model, friction: f64) -> Self {
        Self {
            increments: 1,
            load: model.system.load.clone(),
            rhs: model.system.rhs.clone(),
            obstacle: [0.0, 0.0],
            force: None,
            friction,
        }
    }
}

/// The ends of `problem.steps`: each step's conditions on the assembled body (the same
/// constrained DOFs, so the same `K`; only `f` and the prescribed values change), MFVM or FE.
/// `problem` is the problem `model` was built from (for two bodies: each body's own).
pub(super) fn step_ends(problem: &Problem, model: &Model) -> Result<Vec<StepEnd>, Error> {
    let d = problem.material.constitutive();
    problem
        .steps
        .iter()
        .map(|step| {
            let mut body = assembly::Body::new(problem, &model.nodes, &d);
            body.boundary = &step.boundary;
            // The pin of a translation held by the contact, as assembled (a second or later
            // body's `problem` does not know that a pair touches it).
            body.contact_may_hold = model.system.pinned.is_some();
            let (load, rhs) = match &model.scheme {
                Scheme::Mfvm(m) => assembly::load_and_rhs(&AssemblyInput {
                    body,
                    cells: &m.cells,
                    interior_faces: &m.faces.interior,
                    boundary_faces: &m.faces.boundary,
                    face_quadrature: &m.face_quadrature,
                    face_shapes: &m.face_shapes,
                    node_shapes: &model.node_shapes,
                    beta: problem.discretisation.beta,
                    // Loads only: the hoop terms are in the matrix; the loads weigh by r
                    // through `Body::hoop` in axisymmetry.
                    axisymmetric: None,
                })?,
                Scheme::Fem(f) => fem::system::load_and_rhs(
                    &fem::system::FemInput { body, mesh: &f.mesh },
                    &model.system.interior_stiffness,
                ),
            };
            Ok(StepEnd {
                increments: step.increments,
                load,
                rhs,
                obstacle: step.obstacle_displacement,
                force: step.obstacle_force,
                friction: step.friction,
            })
        })
        .collect()
}

/// `e` as the failure of increment `i` of step `k` (0-based) of `increments` when the problem
/// has `[[step]]` tables (`named`; the message then names them), else `e` itself.
pub(super) fn at_increment(
    named: bool,
    (k, i, increments): (usize, usize, usize),
    e: lcp::LcpError,
) -> Error {
    if named {
        Error::Increment { step: k + 1, increment: i, increments, cause: Box::new(e.into()) }
    } else {
        Error::from(e)
    }
}

/// `(1 − λ) a + λ b`, exactly `b` at `λ = 1` (its signed zeros too: the step's end itself).
pub(super) fn lerp(a: &[f64], b: &[f64], lambda: f64) -> Vec<f64> {
    if lambda == 1.0 {
        return b.to_vec();
    }
    a.iter().zip(b).map(|(x, y)| (1.0 - lambda) * x + lambda * y).collect()
}

/// Where the current load step starts, on both load paths (docs/method.md §8): each body's
/// load and right-hand side at the previous step's end (zero before the first step), and the
/// rigid obstacles' displacement and the force pressing them there.
pub(super) struct StepStart {
    /// Each body's load `f` (the order of the path's bodies).
    pub(super) loads: Vec<Vec<f64>>,
    /// Each body's solved right-hand side.
    pub(super) rhss: Vec<Vec<f64>>,
    /// The obstacles' displacement `d`.
    pub(super) obstacle: [f64; 2],
    /// The magnitude of the force pressing them.
    pub(super) force: f64,
}

impl StepStart {
    /// The unloaded start of bodies of `sizes` unknowns each.
    pub(super) fn new(sizes: impl IntoIterator<Item = usize>) -> Self {
        let (loads, rhss) = sizes.into_iter().map(|n| (vec![0.0; n], vec![0.0; n])).unzip();
        Self { loads, rhss, obstacle: [0.0, 0.0], force: 0.0 }
    }

    /// The obstacles' displacement at load factor `lambda` of the step ending at `end`.
    pub(super) fn obstacle_at(&self, end: &StepEnd, lambda: f64) -> [f64; 2] {
        std::array::from_fn(|a| (1.0 - lambda) * self.obstacle[a] + lambda * end.obstacle[a])
    }

    /// The force pressing the obstacles at load factor `lambda` of a step whose end's force
    /// has magnitude `size`.
    pub(super) fn force_at(&self, size: f64, lambda: f64) -> f64 {
        (1.0 - lambda) * self.force + lambda * size
    }

    /// Step `k`'s ends become the next step's start: each body's (`bodies`, in order) and the
    /// path's, whose obstacle and force are the obstacles'.
    pub(super) fn advance<'e>(
        &mut self,
        bodies: impl Iterator<Item = &'e StepEnd>,
        path_end: &StepEnd,
    ) {
        for (b, end) in bodies.enumerate() {
            self.loads[b].clone_from(&end.load);
            self.rhss[b].clone_from(&end.rhs);
        }
        self.obstacle = path_end.obstacle;
        self.force = path_end.force.map_or(0.0, |f| f[0].hypot(f[1]));
    }
}

/// The record of a load path (docs/method.md §8): the slip accumulated over the slipping
/// increments, one [`solution::IncrementRecord`] per increment and, with `write_steps`, one
/// [`solution::IncrementSnapshot`] per increment.
pub(super) struct History {
    accumulated: Vec<f64>,
    records: Vec<solution::IncrementRecord>,
    snapshots: Vec<solution::IncrementSnapshot>,
    write_steps: bool,
}

impl History {
    pub(super) fn new(candidates: usize, write_steps: bool) -> Self {
        let accumulated = vec![0.0; candidates];
        Self { accumulated, records: Vec::new(), snapshots: Vec::new(), write_steps }
    }

    /// Records increment `i` of step `k` at load factor `lambda` in each pair's history
    /// (`histories[p]` over the candidates `groups[p]` of `step`), as [`History::record`];
    /// both load paths record this way.
    pub(super) fn record_pairs(
        histories: &mut [History],
        groups: impl Iterator<Item = std::ops::Range<usize>>,
        step: &lcp::FrictionSolution,
        at: (usize, usize, f64),
        (equilibrium_error, active_set_changes, seconds): (f64, &[usize], f64),
    ) {
        for (h, g) in histories.iter_mut().zip(groups) {
            let share = (g.len() != step.normal.len()).then(|| super::load_path::select(step, g));
            let changes = active_set_changes.to_vec();
            h.record(share.as_ref().unwrap_or(step), at, equilibrium_error, changes, seconds);
        }
    }

    /// Records increment `i` of step `k` (0-based) at load factor `lambda`.
    pub(super) fn record(
        &mut self,
        step: &lcp::FrictionSolution,
        (k, i, lambda): (usize, usize, f64),
        equilibrium_error: f64,
        active_set_changes: Vec<usize>,
        seconds: f64,
    ) {
        let count =
            |f: &dyn Fn(&lcp::ContactState) -> bool| step.state.iter().filter(|s| f(s)).count();
        self.records.push(solution::IncrementRecord {
            step: k + 1,
            increment: i,
            load_factor: lambda,
            normal_force: step.normal.iter().sum(),
            tangential_force: step.tangential.iter().sum(),
            solver: step.method,
            pivots: step.pivots,
            iterations: step.iterations,
            active_set_changes,
            complementarity: step.residuals.max(),
            equilibrium_error,
            stick: count(&|s| *s == lcp::ContactState::Stick),
            slip: count(&|s| s.is_slip()),
            open: count(&|s| *s == lcp::ContactState::Open),
            seconds,
        });
        for ((a, s), ds) in self.accumulated.iter_mut().zip(&step.state).zip(&step.slip_increment) {
            if s.is_slip() {
                *a += ds;
            }
        }
        if self.write_steps {
            self.snapshots.push(solution::IncrementSnapshot {
                step: k + 1,
                increment: i,
                load_factor: lambda,
                normal: step.normal.clone(),
                tangential: step.tangential.clone(),
                gap: step.gap.clone(),
                slip: self.accumulated.clone(),
                state: step.state.clone(),
            });
        }
    }

    /// Hands the path's record to the final frictional contact.
    pub(super) fn finish(self, friction: &mut solution::FrictionContact) {
        friction.slip = self.accumulated;
        friction.increments = self.records;
        friction.snapshots = self.snapshots;
    }
}

/// The second body of a two-body frictional contact: its model, normal operator and the
/// ends of its load steps (the same steps and increments as the first body's).
pub(super) struct Target<'a> {
    pub(super) model: &'a Model,
    pub(super) operator: contact::BodyOperator,
    pub(super) steps: Vec<StepEnd>,
}

/// The tangential operators of a frictional contact (docs/method.md §8): the candidate body's
/// (direction `t`), and with a second body (`target`: its model and normal operator) the
/// target's, direction `−t` at the paired points, so that `s` is the relative tangential
/// displacement; a candidate whose tangential row on either body is a displacement condition
/// is frictionless (`free[c] = false`, its tangential owners cleared on both bodies when there
/// is a second body).
pub(super) fn tangential_operators(
    candidates: &contact::Candidates,
    model: &Model,
    target: Option<(&Model, &contact::BodyOperator)>,
) -> (contact::BodyOperator, Vec<bool>, Option<contact::BodyOperator>) {
    let target = target.map(|(m, op)| (&m.system, op));
    tangential_operators_of(candidates, &model.system, target)
}

/// [`tangential_operators`] on the bodies' systems (`K` with its displacement conditions)
/// alone: a body assembled without a model (the time stepping's).
pub(super) fn tangential_operators_of(
    candidates: &contact::Candidates,
    system: &crate::assembly::GlobalSystem,
    target: Option<(&crate::assembly::GlobalSystem, &contact::BodyOperator)>,
) -> (contact::BodyOperator, Vec<bool>, Option<contact::BodyOperator>) {
    let (mut tangential, mut free) = candidates.tangential_operator(system);
    // The second body: direction −t at the paired points; a candidate whose partner's
    // tangential row is a displacement condition is frictionless too.
    let target_tangential = target.map(|(sys, target_operator)| {
        let mut op = target_operator.clone();
        op.directions = (0..candidates.len())
            .map(|c| {
                let t = candidates.tangent(c);
                [-t[0], -t[1]]
            })
            .collect();
        for (c, owners) in op.owners.iter().enumerate() {
            let t = candidates.tangent(c);
            let fixed = owners.iter().any(|&(i, _)| {
                crate::nodes::Axis::BOTH.iter().any(|&a| {
                    t[a as usize] != 0.0 && sys.is_constrained(crate::nodes::dof(i as usize, a))
                })
            });
            if fixed {
                free[c] = false;
            }
        }
        op
    });
    let target_tangential = target_tangential.map(|mut op| {
        for (c, &f) in free.iter().enumerate() {
            if !f {
                op.owners[c].clear();
                tangential.owners[c].clear();
            }
        }
        op
    });
    (tangential, free, target_tangential)
}

/// Frictional contact against a rigid obstacle or a second body (`target`; one step) along
/// the load path `steps` (docs/method.md §8): the tangential operators (the second body's
/// with direction `−t` at the paired points, so that `s` is the relative tangential
/// displacement, as §4.3 does for the gap), the four condensed blocks of each body from its
/// one factorisation (with the model's right-hand side, the last step's), summed over the
/// bodies, the checks of `M_nn`, the free gaps and
/// tangential displacements of each step's end (one solve per step; linear in between), and
/// the step solver per increment, carrying the tangential displacements `s` and the
/// accumulated slip. Returns the last increment's solution (whose `gap` the caller replaces
/// by the MLS gaps) with the nodal parameters of both bodies. Lemke's frictionless steps take
/// `lemke`'s parameters; its numerical failure is refused with the conditioning of `M_nn`
/// ([`Error::LemkeRefused`], inside the increment's [`Error::Increment`]).
pub(super) fn solve_frictional(
    problem: &Problem,
    spec: &ContactSpec,
    model: &Model,
    mut candidates: contact::Candidates,
    target: Option<Target<'_>>,
    (steps, lemke): (&[StepEnd], &lcp::LemkeParams),
    clock: &mut Clock<'_>,
) -> Result<ContactOutcome, Error> {
    let (tangential, free, target_tangential) = tangential_operators(
        &candidates,
        model,
        target.as_ref().map(|tg| (tg.model, &tg.operator)),
    );
    let mut terms = vec![load_path::Term {
        model,
        normal: &candidates.operator,
        tangential: Some(&tangential),
        index: None,
        steps,
    }];
    if let (Some(tg), Some(op_t)) = (&target, &target_tangential) {
        terms.push(load_path::Term {
            model: tg.model,
            normal: &tg.operator,
            tangential: Some(op_t),
            index: None,
            steps: &tg.steps,
        });
    }
    let load_path::Condensed { blocks, compliance: condensed } =
        clock.run("condensation", || load_path::condense(&terms, &candidates.initial_gap))?;
    let warning =
        compliance_warning(problem, spec, &condensed, target.as_ref().map(|t| &t.operator))?;
    let m = candidates.len();
    // A rigid translation of the body held by the contact alone (docs/method.md §4.7):
    // `a_c = −ν_c·r` per candidate for its unit vector r, as for a body among several; only
    // with friction whose tangents are orthogonal to r and with a pinned node that carries
    // no contact force.
    let pinned = model.system.pinned;
    let held = match &target {
        None => refuse_slanted_force(steps, &candidates)
            .and_then(|()| held_projection(pinned, steps, &candidates))?
            .zip(pinned)
            .map(|(projection, pin)| {
                let along = projection.iter().map(|p| -p).collect();
                load_path::Held { term: 0, pin, along }
            }),
        Some(tg) => held_between(problem, model, tg, &candidates, steps)?,
    };
    // μ per candidate in step k: 0 where the tangential row is a displacement condition.
    let friction = (0..steps.len())
        .map(|k| free.iter().map(|&f| if f { steps[k].friction } else { 0.0 }).collect())
        .collect();
    let path = load_path::Path {
        initial_gap: &candidates.initial_gap,
        normals: &candidates.normals,
        steps,
        friction,
        moved: None,
        held: held.into_iter().collect(),
        groups: std::iter::once(0..m).collect(),
        write_steps: problem.write_steps,
        named_steps: !problem.steps.is_empty(),
    };
    // Lemke's numerical failure as its refusal, with the conditioning of `M_nn`.
    let answer = load_path::run_condensed(&path, &terms, blocks, lemke, clock)
        .map_err(|e| refused_on_path(e, &condensed, warning.is_some()))?;
    drop(terms);
    let load_path::PathAnswer {
        step,
        mut u,
        problem: step_problem,
        histories,
        load_driven,
        rigid_modes,
        ..
    } = answer;
    let rigid_mode = rigid_modes.into_iter().next();
    let u2 = (u.len() == 2).then(|| u.pop()).flatten();
    let u = u.pop().expect("the first body's displacements");
    let result = load_path::normal_lcp(&step_problem, &step)?;
    // A held body (the one against rigid obstacles, or either body of a pair) with no load
    // along its translation: determined only where the contact carries a force along it or
    // blocks it both ways (docs/method.md §4.7).
    if let (Some(load_path::Held { term, pin, along }), Some(r)) = (path.held.first(), &rigid_mode)
    {
        let name = match term {
            0 => problem.name.as_str(),
            _ => problem.second_body().map_or("second body", |p| p.name.as_str()),
        };
        load_path::check_determined(
            (name, pin.name()),
            r.load,
            along,
            &result,
            &condensed.free_gap,
        )
        .map_err(lcp::LcpError::from)?;
    }
    move_to_final_obstacle(&mut candidates, steps, load_driven.as_ref());
    let gap = step.gap.clone();
    let segment_length = candidates.segment_length.clone();
    let target_operator = target.map(|tg| tg.operator);
    let mut contact = ContactSolution::new(
        spec,
        candidates,
        target_operator,
        Vec::new(),
        Some(condensed.clone()),
        &condensed.free_gap,
        result,
        gap,
        warning,
    );
    // The final step's coefficient: the one the final state's stick/slip refer to.
    let coefficient = steps.last().map_or(spec.friction, |end| end.friction);
    let mut friction =
        solution::FrictionContact::new(coefficient, free, tangential, step, &segment_length);
    if let Some(history) = histories.into_iter().next() {
        history.finish(&mut friction);
    }
    friction.target_operator = target_tangential;
    attach_records(&mut contact, problem, Some(friction), pinned, load_driven, rigid_mode);
    Ok((u, u2, contact))
}

/// The initial gaps measured from the obstacle's final position: the last step's, or where
/// the force search put it (docs/method.md §4.6).
fn move_to_final_obstacle(
    candidates: &mut contact::Candidates,
    steps: &[StepEnd],
    load_driven: Option<&solution::LoadDriven>,
) {
    if let Some(end) = steps.last() {
        move_obstacle(candidates, load_driven.map_or(end.obstacle, |l| l.displacement));
    }
}

/// The initial gaps measured from the obstacle moved by `d`: `g0 − d·ν_c`.
pub(super) fn move_obstacle(candidates: &mut contact::Candidates, d: geometry::Point) {
    for (g, nu) in candidates.initial_gap.iter_mut().zip(&candidates.normals) {
        let dn = d[0] * nu[0] + d[1] * nu[1];
        if dn != 0.0 {
            *g -= dn;
        }
    }
}

/// The records both load paths end with. A translation held by the contact without load
/// steps is a frictionless one-step problem (it only took a frictional path for the search):
/// no frictional record, as on the direct path; nor has a one-shot sparse path (`friction`
/// `None`: no tangential operators).
fn attach_records(
    contact: &mut ContactSolution,
    problem: &Problem,
    friction: Option<solution::FrictionContact>,
    pinned: Option<assembly::PinnedMode>,
    load_driven: Option<solution::LoadDriven>,
    rigid_mode: Option<solution::RigidMode>,
) {
    // A frictionless held body without steps reports as one-shot contact does.
    let reported = |f: &solution::FrictionContact| {
        pinned.is_none() || !problem.steps.is_empty() || f.coefficient > 0.0
    };
    contact.friction = friction.filter(reported);
    contact.load_driven = load_driven;
    contact.rigid_mode = rigid_mode;
}

/// A force-driven obstacle (docs/method.md §4.6) takes friction where every step with a force
/// and friction presses along a direction orthogonal to every candidate's tangent (a flat
/// contact pressed along its normal): the obstacle's motion then leaves the tangential
/// displacements alone and the tangential forces carry nothing along the force, so the
/// search's balance is the normal forces' as without friction. Otherwise refused.
fn refuse_slanted_force(steps: &[StepEnd], candidates: &contact::Candidates) -> Result<(), Error> {
    refuse_slanted_force_on(steps, &candidates.normals, |k, _| steps[k].friction)
}

/// [`refuse_slanted_force`] with `μ` per step and candidate (`mu(k, c)`): with several
/// pairs, each pair's own coefficient, 0 on the candidates whose obstacle the force does not
/// move.
pub(super) fn refuse_slanted_force_on(
    steps: &[StepEnd],
    normals: &[geometry::Point],
    mu: impl Fn(usize, usize) -> f64,
) -> Result<(), Error> {
    for (k, step) in steps.iter().enumerate() {
        let Some(f) = step.force else { continue };
        let (e, _, _) = force_along(f, normals);
        if let Some(candidate) = slanted(normals, e, |c| mu(k, c) > 0.0) {
            let error = lcp::load_driven::LoadDrivenError::SlantedFriction {
                step: k + 1,
                direction: e,
                mu: mu(k, candidate),
                candidate,
            };
            return Err(lcp::LcpError::from(error).into());
        }
    }
    Ok(())
}

/// The checks of a rigid translation of the body held by the contact alone (docs/method.md
/// §4.7) and `ν_c·r` per candidate for its unit vector `r` (`None` without a pin): friction
/// only where every tangent is orthogonal to `r`, and a pinned node that carries no contact
/// force (a force-driven obstacle that moves with the body is the walk's refusal,
/// [`load_path::refuse_moving_together`]); on the condensed path (a pair of two bodies has
/// its own checks, [`held_between`]; the sparse path takes the scene's held body and its
/// checks).
fn held_projection(
    pinned: Option<assembly::PinnedMode>,
    steps: &[StepEnd],
    candidates: &contact::Candidates,
) -> Result<Option<Vec<f64>>, Error> {
    let m = candidates.len();
    match pinned {
        None => Ok(None),
        Some(pin) => {
            let unsupported = |why: String| {
                Error::from(lcp::LcpError::from(lcp::load_driven::LoadDrivenError::Unsupported {
                    mode: pin.name(),
                    why,
                }))
            };
            // Friction where every candidate's tangent is orthogonal to the translation.
            let a = pin.axis as usize;
            let slanted = slanted(&candidates.normals, axis_direction(a), |_| true);
            if let (Some(k), Some(c)) = (steps.iter().position(|s| s.friction > 0.0), slanted) {
                return Err(unsupported(format!(
                    "the contact has friction μ = {} (in step {}) and candidate {c}'s tangent has a component along the held translation (its tangential force would enter the balance the search solves)",
                    steps[k].friction,
                    k + 1
                )));
            }
            if candidates.operator.owners.iter().flatten().any(|&(i, _)| i == pin.node) {
                return Err(unsupported(format!(
                    "the pinned node {} carries contact forces",
                    pin.node
                )));
            }
            let projection: Vec<f64> = (0..m).map(|c| candidates.normal(c)[a]).collect();
            if projection.iter().all(|p| p.abs() <= 1e-12) {
                return Err(lcp::LcpError::from(
                    lcp::load_driven::LoadDrivenError::NotRestrained { mode: pin.name() },
                )
                .into());
            }
            Ok(Some(projection))
        }
    }
}

/// The first candidate among those `frictional` selects whose tangent has a component along
/// the unit `direction` (a held axis, a force's direction): with friction its tangential force
/// would enter the balance along it that the searches of docs/method.md §4.6–4.7 solve,
/// which is refused; friction with tangents orthogonal to it is accepted.
pub(super) fn slanted(
    normals: &[geometry::Point],
    direction: geometry::Point,
    frictional: impl Fn(usize) -> bool,
) -> Option<usize> {
    let along = |c: usize| {
        let t = contact::tangent(normals[c]);
        (t[0] * direction[0] + t[1] * direction[1]).abs() > 1e-12
    };
    (0..normals.len()).find(|&c| frictional(c) && along(c))
}

/// The unit vector of a held axis (0: x, 1: y).
pub(super) fn axis_direction(axis: usize) -> geometry::Point {
    let mut r = [0.0; 2];
    r[axis] = 1.0;
    r
}

/// The held translation of either body of a two-body pair (docs/method.md §4.7): the pinned
/// body's term, its pin and `a_c = −s_c ν_c·r` (`s_c = +1` on the candidate body, `−1` on the
/// target body). Refused for both bodies pinned, a pinned node that carries contact forces, no
/// candidate that restrains the translation, and friction on candidates whose tangent has a
/// component along it.
fn held_between(
    problem: &Problem,
    model: &Model,
    target: &Target<'_>,
    candidates: &contact::Candidates,
    steps: &[StepEnd],
) -> Result<Option<load_path::Held>, Error> {
    use lcp::load_driven::LoadDrivenError as L;
    let second = problem.second_body().map_or("second body", |p| p.name.as_str());
    let (term, pin, op, sign) = match (model.system.pinned, target.model.system.pinned) {
        (None, None) => return Ok(None),
        (Some(a), Some(b)) => {
            let bodies = format!("`{}` ({}), `{second}` ({})", problem.name, a.name(), b.name());
            return Err(lcp::LcpError::from(L::SeveralHeld { bodies }).into());
        }
        (Some(pin), None) => (0, pin, &candidates.operator, 1.0),
        (None, Some(pin)) => (1, pin, &target.operator, -1.0),
    };
    let unsupported =
        |why: String| Error::from(lcp::LcpError::from(L::Unsupported { mode: pin.name(), why }));
    if op.owners.iter().flatten().any(|&(i, _)| i == pin.node) {
        return Err(unsupported(format!("the pinned node {} carries contact forces", pin.node)));
    }
    let a = pin.axis as usize;
    let frictional = steps.iter().any(|s| s.friction > 0.0);
    if frictional && slanted(&candidates.normals, axis_direction(a), |_| true).is_some() {
        return Err(unsupported(
            "the contact has friction and a candidate's tangent has a component along the held translation".into(),
        ));
    }
    let along: Vec<f64> = candidates.normals.iter().map(|nu| -sign * nu[a]).collect();
    if along.iter().all(|x| x.abs() <= 1e-12) {
        return Err(lcp::LcpError::from(L::NotRestrained { mode: pin.name() }).into());
    }
    Ok(Some(load_path::Held { term, pin, along }))
}

/// The direction `e = F/|F|` of the force pressing the obstacle, `|F|`, and `a_c = ν_c·e` per
/// candidate (docs/method.md §4.6).
pub(super) fn force_along(
    f: geometry::Point,
    normals: &[geometry::Point],
) -> ([f64; 2], f64, Vec<f64>) {
    let size = f[0].hypot(f[1]);
    let e = [f[0] / size, f[1] / size];
    let along: Vec<f64> = normals.iter().map(|nu| nu[0] * e[0] + nu[1] * e[1]).collect();
    (e, size, along)
}
