//! Stage 13: orchestration — the pipeline as functions that read like the algorithm:
//! [`discretise`] (stages 2–8, MFVM or FE), [`solve_model`] (solve, or condense, run the LCP
//! and solve again; then recover), [`solve`] (both in one call) and [`run`] (solve and write
//! every output, the command-line program's job). [`compare`] runs both discretisations on
//! one problem.

pub mod adaptive;
pub mod compare;
pub mod dynamics;
mod friction;
mod load_path;
pub mod memory;
pub mod multibody;
mod plan;

use crate::assembly::{self, AssemblyInput};
use crate::contact::{self, ContactTarget};
use crate::error::Error;
use crate::fem;
use crate::geometry;
use crate::lcp;
use crate::linear_solve::{ColumnOrdering, FactorPrecision, Factorisation};
use crate::mls;
use crate::model::{self, Model, Scheme};
use crate::neighbours::Supports;
use crate::nodes;
use crate::post::{self, Summary};
use crate::problem::{ContactSpec, Method, Problem};
use crate::progress::{Clock, Progress, Silent};
use crate::solution::{self, ContactSolution, Solution};
use crate::system;
use crate::weak_form::{self, FaceQuadrature};
use friction::{StepEnd, Target, solve_frictional, solve_frictional_active_set, step_ends};
use std::path::{Path, PathBuf};

/// Builds the model of `problem`: nodes, supports, shape functions, cells, assembly and
/// factorisation for the MFVM; mesh, assembly and factorisation for the finite elements.
///
/// # Errors
/// Any stage's error, wrapped in [`Error`].
pub fn discretise(problem: &Problem, progress: &mut dyn Progress) -> Result<Model, Error> {
    discretise_held(problem, false, progress)
}

/// [`discretise`], with `held_by_contact` telling assembly that a contact pair touches the
/// body, so that it may hold one free translation (`assembly::Body::contact_may_hold`; the
/// second and later bodies of several, whose own `contact` is `None`; docs/method.md §4.7).
/// An axisymmetric body may hold its axial translation only (a uniform `u_r` is no rigid
/// motion; `assembly::with_pin`).
fn discretise_held(
    problem: &Problem,
    held_by_contact: bool,
    progress: &mut dyn Progress,
) -> Result<Model, Error> {
    match problem.discretisation.method {
        Method::Mfvm => discretise_mfvm(problem, held_by_contact, progress),
        Method::Fem => discretise_fem(problem, held_by_contact, progress),
    }
}

fn discretise_mfvm(
    problem: &Problem,
    held_by_contact: bool,
    progress: &mut dyn Progress,
) -> Result<Model, Error> {
    discretise_mfvm_nodes(problem, held_by_contact, None, progress)
}

/// [`discretise_mfvm`] on the node set `given` when there is one (it must be
/// `nodes::for_problem(problem)`'s: the adaptive loop has generated it already to count it).
fn discretise_mfvm_nodes(
    problem: &Problem,
    held_by_contact: bool,
    given: Option<nodes::Nodes>,
    progress: &mut dyn Progress,
) -> Result<Model, Error> {
    discretise_mfvm_with(problem, (held_by_contact, false), given, progress)
}

/// [`discretise_mfvm_nodes`]; with `may_skip`, `K` is left unfactorised
/// ([`Factorisation::unfactorised`]) when [`skips_model_factorisation`] (for
/// [`solve_model_with`] only, which factorises it if the candidates found need it).
fn discretise_mfvm_with(
    problem: &Problem,
    (held_by_contact, may_skip): (bool, bool),
    given: Option<nodes::Nodes>,
    progress: &mut dyn Progress,
) -> Result<Model, Error> {
    let mut clock = Clock::new(progress, Vec::new());
    let parts = mfvm_parts(problem, held_by_contact, given, &mut clock)?;
    let (nodes, system) = (parts.nodes, parts.system);
    check_factor_memory(problem, &system, &nodes.points)?;
    let pinned = system.pinned.is_some();
    let factorisation = if may_skip && skips_model_factorisation(problem, &nodes, pinned) {
        let options = plan::model_factor_options(problem, &nodes, pinned);
        Factorisation::unfactorised(system.matrix.n, options)
    } else {
        clock.run("factorisation", || {
            let ordering = ColumnOrdering::NestedDissection(&nodes.points);
            let options = plan::model_factor_options(problem, &nodes, pinned);
            Factorisation::with_options(&system.matrix, ordering, &options)
        })?
    };
    Ok(Model {
        nodes,
        node_shapes: parts.node_shapes,
        system,
        factorisation,
        scheme: Scheme::Mfvm(Box::new(parts.mfvm)),
        timings: clock.timings,
    })
}

/// Whether the body's `K` need not be factorised before its contact is solved: one MFVM body,
/// frictionless contact in one shot (no load steps, no translation held by the contact)
/// against rigid obstacles, on the sparse system (the active set, as the plan decides for the
/// nodes on the contact edge), with more nodes on that edge than
/// [`contact::sparse::RigidObstacle::MAX_UPDATE_RANK`]. Without `K`'s factors the active set
/// starts from every candidate closed, a row-replaced matrix it factorises at once; `K`'s
/// factors would have served the free solve of its first guess only (and at 10⁶ nodes that
/// solve failed its accuracy check, so the set started from every candidate closed anyway;
/// docs/dev/performance.md, "Contact at 10⁶ nodes: no factorisation of K").
/// [`solve_contact`] decides again on the candidates found and factorises `K` if they need
/// it.
fn skips_model_factorisation(problem: &Problem, nodes: &nodes::Nodes, pinned: bool) -> bool {
    let Some(spec) = problem.contact() else { return false };
    let rigid = matches!(spec.target, ContactTarget::Rigid(_) | ContactTarget::Obstacles);
    if !rigid
        || spec.friction > 0.0
        || !problem.steps.is_empty()
        || pinned
        || problem.second_body().is_some()
        || problem.is_scene_of_pairs()
    {
        return false;
    }
    let on_edge = nodes.edges.iter().filter(|e| e.contains(spec.edge)).count();
    on_edge > contact::sparse::RigidObstacle::MAX_UPDATE_RANK
        && plan::Plan::new(spec.solver, plan::Shape::OneShot, on_edge).is_sparse()
}

/// `K`'s factorisation, made now (stage `factorisation`) if [`discretise_all`] left it
/// unfactorised ([`skips_model_factorisation`]) and the route found needs it.
fn factorise_deferred(model: &mut Model, clock: &mut Clock<'_>) -> Result<(), Error> {
    if !model.factorisation.is_released() {
        return Ok(());
    }
    let options = model.factorisation.options().clone();
    let ordering = match model.scheme {
        Scheme::Mfvm(_) => ColumnOrdering::NestedDissection(&model.nodes.points),
        Scheme::Fem(_) => ColumnOrdering::Colamd,
    };
    model.factorisation = clock.run("factorisation", || {
        Factorisation::with_options(&model.system.matrix, ordering, &options)
    })?;
    Ok(())
}

/// An MFVM body assembled but not factorised: nodes, shape functions at the nodes, the system
/// and the MFVM's own data (a dynamic run factorises `M + h²θ² K` instead of `K`).
pub struct MfvmParts {
    /// Nodes.
    pub nodes: nodes::Nodes,
    /// Shape functions with gradients at the nodes.
    pub node_shapes: mls::ShapeSet,
    /// `K`, `f` and the collocation rows.
    pub system: assembly::GlobalSystem,
    /// Supports, cells, faces and face shapes.
    pub mfvm: model::Mfvm,
}

/// The stages of [`discretise_mfvm_nodes`] before the factorisation, timed on `clock`.
fn mfvm_parts(
    problem: &Problem,
    held_by_contact: bool,
    given: Option<nodes::Nodes>,
    clock: &mut Clock<'_>,
) -> Result<MfvmParts, Error> {
    let disc = &problem.discretisation;
    let nodes = match given {
        Some(nodes) => clock.run("nodes", || nodes),
        None => clock.run("nodes", || nodes::for_problem(problem))?,
    };
    let supports = clock.run("supports", || Supports::new(&nodes, disc.mls.support_factor));
    let cells = clock.run("cells", || weak_form::build_cells(&problem.domain, &nodes))?;
    let (faces, face_quadrature) = clock.run("faces", || {
        let faces = weak_form::collect_faces(&cells);
        let q = FaceQuadrature::new(&faces.interior, disc.quadrature_points);
        (faces, q)
    });
    let node_shapes = clock.run("mls_nodes", || {
        mls::shape_functions(&nodes.points, &nodes, &supports, &disc.mls, true)
    })?;
    let face_shapes = clock.run("mls_faces", || {
        mls::shape_functions(
            &face_quadrature.points,
            &nodes,
            &supports,
            &disc.mls,
            assembly::needs_face_gradients(disc.beta),
        )
    })?;
    let d = problem.material.constitutive();
    let cells_axi = match problem.material.hoop() {
        Some(hoop) => Some(clock.run("mls_cells", || {
            let q = weak_form::axisymmetric::CellQuadrature::new(&cells);
            let gradients = assembly::needs_face_gradients(disc.beta);
            mls::shape_functions(&q.points, &nodes, &supports, &disc.mls, gradients)
                .map(|shapes| (hoop, q, shapes))
        })?),
        None => None,
    };
    let system = clock.run("assembly", || {
        assembly::assemble(&AssemblyInput {
            body: assembly::Body {
                contact_may_hold: held_by_contact
                    || assembly::Body::new(problem, &nodes, &d).contact_may_hold,
                ..assembly::Body::new(problem, &nodes, &d)
            },
            cells: &cells,
            interior_faces: &faces.interior,
            boundary_faces: &faces.boundary,
            face_quadrature: &face_quadrature,
            face_shapes: &face_shapes,
            node_shapes: &node_shapes,
            beta: disc.beta,
            axisymmetric: cells_axi.as_ref().map(|(hoop, q, shapes)| assembly::Axisymmetric {
                hoop: *hoop,
                cell_quadrature: q,
                cell_shapes: shapes,
            }),
        })
    })?;
    Ok(MfvmParts {
        nodes,
        node_shapes,
        system,
        mfvm: model::Mfvm { supports, cells, faces, face_quadrature, face_shapes },
    })
}

fn discretise_fem(
    problem: &Problem,
    held_by_contact: bool,
    progress: &mut dyn Progress,
) -> Result<Model, Error> {
    let mut clock = Clock::new(progress, Vec::new());
    let (mesh, nodes) = clock.run("mesh", || fem::mesh(problem))?;
    let d = problem.material.constitutive();
    let system = clock.run("assembly", || {
        fem::system::assemble(&fem::system::FemInput {
            body: assembly::Body {
                contact_may_hold: held_by_contact
                    || assembly::Body::new(problem, &nodes, &d).contact_may_hold,
                ..assembly::Body::new(problem, &nodes, &d)
            },
            mesh: &mesh,
        })
    })?;
    let factorisation = clock.run("factorisation", || Factorisation::new(&system.matrix))?;
    let ids: Vec<u32> = (0..nodes.len() as u32).collect();
    Ok(Model {
        node_shapes: mls::ShapeSet::nodal(&ids),
        nodes,
        system,
        factorisation,
        scheme: Scheme::Fem(model::Fem { mesh }),
        timings: clock.timings,
    })
}

/// Refuses `problem` when its estimated memory ([`memory::estimate`]) exceeds what the
/// process may use ([`system::limit`]), unless it is a thin MFVM body whose factors are
/// counted after assembly instead ([`memory::defers_to_analysis`], [`check_factor_memory`]).
fn check_memory(problem: &Problem) -> Result<(), Error> {
    let (need, nodes) = memory::estimate(problem);
    match system::limit() {
        Some((available, _))
            if need > available && memory::defers_to_analysis(problem, available) =>
        {
            Ok(())
        }
        Some((available, what)) if need > available => {
            let precision_hint = match memory::precision(problem) {
                crate::linear_solve::FactorPrecision::Double => {
                    ", or set discretisation.precision = \"mixed\" (MFVM)"
                }
                crate::linear_solve::FactorPrecision::Mixed => "",
            };
            Err(Error::Memory { estimate: need, nodes, available, limit: what, precision_hint })
        }
        _ => Ok(()),
    }
}

/// After assembly, for a body that [`check_memory`] let through on
/// [`memory::defers_to_analysis`] (its estimate exceeds what the process may use): the
/// symbolic analysis of `K` (ordering and exact fill, as the factorisation will compute them
/// again) and [`memory::after_analysis`] against what is left now; refused with that count
/// when it does not fit. Nothing is done when the estimate fits.
fn check_factor_memory(
    problem: &Problem,
    system: &assembly::GlobalSystem,
    points: &[geometry::Point],
) -> Result<(), Error> {
    let Some((available_before, _)) = system::limit() else { return Ok(()) };
    let (estimate, nodes) = memory::estimate(problem);
    // `limit` now is what is left after assembly; the estimate was against the whole.
    if estimate <= available_before + system::resident_bytes() {
        return Ok(());
    }
    let options = plan::factor_options(problem);
    let ordering = ColumnOrdering::NestedDissection(points);
    let stats = Factorisation::analyse(&system.matrix, ordering, &options)?;
    // The frictionless active set against a rigid obstacle releases `K`'s factors before its
    // own factorisation (not with a pinned translation: that takes the incremental path).
    let releases = system.pinned.is_none();
    let need =
        memory::after_analysis(problem, &stats, system.matrix.n, options.precision, releases);
    match system::limit() {
        Some((available, what)) if need > available => {
            let precision_hint = match options.precision {
                FactorPrecision::Double => ", or set discretisation.precision = \"mixed\" (MFVM)",
                FactorPrecision::Mixed => "",
            };
            let used = system::resident_bytes();
            Err(Error::Memory {
                estimate: need + used,
                nodes,
                available: available + used,
                limit: what,
                precision_hint,
            })
        }
        _ => Ok(()),
    }
}

/// The models of `problem` and of its second body, if it has one.
fn discretise_all(
    problem: &Problem,
    progress: &mut dyn Progress,
) -> Result<(Model, Option<Model>), Error> {
    check_memory(problem)?;
    let method = match problem.discretisation.method {
        Method::Mfvm => "MFVM",
        Method::Fem => "FE",
    };
    let several = problem.second_body().is_some() || problem.is_scene_of_pairs();
    if several {
        progress.section(&format!("body `{}` ({method})", problem.name));
    }
    let paired = problem.second_body().is_some();
    let first = match problem.discretisation.method {
        // `K` left unfactorised when its factors would serve nothing (one body).
        Method::Mfvm if !paired => discretise_mfvm_with(problem, (false, true), None, progress),
        _ => discretise_held(problem, paired, progress),
    };
    let model = first.map_err(|e| match problem.multibody() {
        Some(m) => {
            let held = m.pairs.iter().any(|p| p.body == 0 || p.target_body == Some(0));
            multibody::named(problem, held, e)
        }
        None if paired => multibody::named(problem, true, e),
        None => e,
    })?;
    // Two bodies in one pair: the contact may hold one free translation of either body
    // (docs/method.md §4.7), as between several bodies.
    let second = match problem.second_body() {
        Some(p2) => {
            progress.section(&format!("body `{}` ({method})", p2.name));
            Some(discretise_held(p2, true, progress).map_err(|e| multibody::named(p2, true, e))?)
        }
        None => None,
    };
    if problem.second_body().is_some() {
        progress.section("contact and recovery");
    }
    Ok((model, second))
}

/// Solves `problem` end to end (stages 1–10; both bodies of a two-body contact; with
/// `[refinement]` the adaptive loop, [`adaptive::solve_adaptive`], and its last solution).
/// Once, at the `β` of `problem.discretisation`: the second attempt of `beta = "auto"` and
/// its warning belong to [`Outcome::solve`], which the command line and Python use.
///
/// # Errors
/// Any stage's error, wrapped in [`Error`].
pub fn solve(problem: &Problem) -> Result<Solution, Error> {
    solve_with_lemke(problem, &lcp::LemkeParams::default())
}

/// [`solve`] with Lemke's parameters given (the frictionless path's; for instance a low
/// pivot limit, to provoke Lemke's failure and the refusal or the `"auto"` fallback to the
/// active-set solver in tests). With the default parameters it is [`solve`].
///
/// # Errors
/// As [`solve`].
pub fn solve_with_lemke(problem: &Problem, lemke: &lcp::LemkeParams) -> Result<Solution, Error> {
    refuse_dynamics(problem)?;
    let mut silent = Silent;
    if let Some(a) = &problem.adaptive {
        let run = adaptive::solve_adaptive(problem, a, &mut silent, &mut |_, _, _, _| {})?;
        return Ok(run.solution);
    }
    let (model, second) = discretise_all(problem, &mut silent)?;
    if problem.is_scene_of_pairs() {
        let others = multibody::discretise_others(problem, &mut silent)?;
        return multibody::solve_bodies(problem, model, others, &mut silent, lemke)
            .map(|(_, _, s)| s);
    }
    solve_model_with(problem, model, second, &mut silent, lemke).map(|(_, _, s)| s)
}

/// Solves a discretised model (with contact when the problem has it; `second` is the model of
/// `problem.second_body()` for a two-body contact) and recovers displacements, stresses,
/// reactions and contact forces.
///
/// # Errors
/// [`Error::Solve`] when `K` is numerically singular; [`Error::Contact`] and [`Error::Lcp`]
/// when the contact problem cannot be solved or its compliance fails the run-time checks;
/// [`Error::Problem`] when `second` is given without `problem.second_body()`, or the other way
/// round; [`Error::LemkeRefused`] when Lemke fails numerically on a frictionless problem
/// (with `contact.solver = "auto"` only when the active-set solver then fails too).
pub fn solve_model(
    problem: &Problem,
    model: Model,
    second: Option<Model>,
    progress: &mut dyn Progress,
) -> Result<(Model, Option<Model>, Solution), Error> {
    solve_model_with(problem, model, second, progress, &lcp::LemkeParams::default())
}

/// [`solve_model`] with Lemke's parameters given (see [`solve_with_lemke`]).
///
/// # Errors
/// As [`solve_model`].
pub fn solve_model_with(
    problem: &Problem,
    mut model: Model,
    mut second: Option<Model>,
    progress: &mut dyn Progress,
    lemke: &lcp::LemkeParams,
) -> Result<(Model, Option<Model>, Solution), Error> {
    if second.is_some() != problem.second_body().is_some() || problem.is_scene_of_pairs() {
        return Err(crate::problem::ProblemError::Invalid {
            field: "body".into(),
            value: format!("{} models", 1 + usize::from(second.is_some())),
            reason: "solve_model needs the second body's model exactly when the problem has one (several bodies or contact pairs: multibody::solve_bodies)"
                .into(),
        }
        .into());
    }
    let mut clock = Clock::new(progress, std::mem::take(&mut model.timings));
    let Some(spec) = problem.contact() else {
        let u_hat = clock.run("solve", || model.factorisation.solve(&model.system.rhs))?;
        let mut solution = clock.run("recovery", || solution::recover(problem, &model, u_hat, &[]));
        solution.timings = clock.timings.clone();
        model.timings = clock.timings;
        return finite(solution).map(|s| (model, None, s));
    };
    // Load steps: the load and right-hand side at the end of each step, per body; the models'
    // own are those of the last (the solution is the last increment's; docs/method.md §8).
    let steps = if problem.steps.is_empty() {
        None
    } else {
        let mut ends = vec![clock.run("load_steps", || step_ends(problem, &model))?];
        if let (Some(p2), Some(m2)) = (problem.second_body(), second.as_mut()) {
            ends.push(clock.run("load_steps", || step_ends(p2, m2))?);
        }
        for (m, e) in std::iter::once(&mut model).chain(second.as_mut()).zip(&ends) {
            if let Some(last) = e.last() {
                m.system.load = last.load.clone();
                m.system.rhs = last.rhs.clone();
            }
        }
        Some(ends)
    };
    let pair = problem.second_body().zip(second.as_ref());
    let (u1, u2, contact) =
        solve_contact(problem, spec, &mut model, pair, steps.as_deref(), lemke, &mut clock)?;
    // A translation held by the contact: the pin's value is the translation found
    // (docs/method.md §4.7), so that the system the solution answers is the one reported.
    if let Some(r) = &contact.rigid_mode {
        let held = if model.system.pinned.is_some() { Some(&mut model) } else { second.as_mut() };
        if let Some(m) = held {
            set_pin(m, r);
        }
    }
    let pair = problem.second_body().zip(second.as_ref());
    let mut solution = clock.run("recovery", || {
        let forces = &contact.lcp.z;
        let mut ops = vec![(&contact.candidates.operator, forces.as_slice())];
        if let Some(f) = &contact.friction {
            ops.push((&f.operator, f.step.tangential.as_slice()));
        }
        let mut s = solution::recover(problem, &model, u1, &ops);
        if let (Some((p2, m2)), Some(u2), Some(target)) = (pair, u2, &contact.target) {
            let mut ops2 = vec![(target, forces.as_slice())];
            if let Some((f, op)) =
                contact.friction.as_ref().and_then(|f| f.target_operator.as_ref().map(|o| (f, o)))
            {
                ops2.push((op, f.step.tangential.as_slice()));
            }
            s.others.push(solution::recover(p2, m2, u2, &ops2));
        }
        s
    });
    solution.contact_pairs.push(contact);
    solution.timings = clock.timings.clone();
    model.timings = clock.timings;
    finite(solution).map(|s| (model, second, s))
}

/// The pin of `model`'s held translation set to the translation `r` found (docs/method.md
/// §4.7): its collocation row's value and its displacement condition.
fn set_pin(model: &mut Model, r: &solution::RigidMode) {
    let Some(pin) = model.system.pinned else { return };
    let value = r.translation[pin.axis as usize];
    let d = nodes::dof(pin.node as usize, pin.axis);
    model.system.rhs[d] = model.system.collocation_scale * value;
    if let Some(c) =
        model.system.constraints.iter_mut().find(|c| c.node == pin.node && c.axis == pin.axis)
    {
        c.value = value;
    }
}

/// `solution`, unless it holds a value that is not finite ([`Error::NonFinite`]).
fn finite(solution: Solution) -> Result<Solution, Error> {
    match solution.first_non_finite() {
        Some(what) => Err(Error::NonFinite { what }),
        None => Ok(solution),
    }
}

type ContactOutcome = (Vec<f64>, Option<Vec<f64>>, ContactSolution);

/// Candidates, the plan ([`plan::Plan`], decided once from them), condensation `M = G K⁻¹ E`,
/// the checks of `M`, Lemke, and the solves with the contact forces (docs/method.md §4–§5), or
/// the load path, or the active set. When Lemke fails numerically, `"auto"` hands the
/// problem to the active-set solver and records why; `"lemke"` refuses with the conditioning
/// of `M` ([`crate::error::LemkeRefusal`]).
fn solve_contact(
    problem: &Problem,
    spec: &ContactSpec,
    model: &mut Model,
    second: Option<(&Problem, &Model)>,
    steps: Option<&[Vec<StepEnd>]>,
    lemke: &lcp::LemkeParams,
    clock: &mut Clock<'_>,
) -> Result<ContactOutcome, Error> {
    let found =
        clock.run("contact_candidates", || find_candidates(problem, spec, model, second))?;
    // A rigid translation held by the contact alone takes the incremental path too: its
    // search (docs/method.md §4.7) lives there.
    let held =
        model.system.pinned.is_some() || second.is_some_and(|(_, m2)| m2.system.pinned.is_some());
    let on_path = spec.friction > 0.0 || steps.is_some() || held;
    let shape = plan::Shape::of(on_path, found.target.is_some());
    let plan = plan::Plan::new(spec.solver, shape, found.candidates.len());
    // `K`'s factors (unless the body has none yet, [`skips_model_factorisation`], and the
    // route is the one-shot active set against rigid obstacles starting from more candidates
    // closed than it would solve with them: then they would serve nothing).
    let closes_all = !on_path
        && found.target.is_none()
        && plan.is_sparse()
        && found.candidates.len() > contact::sparse::RigidObstacle::MAX_UPDATE_RANK;
    if !closes_all {
        factorise_deferred(model, clock)?;
    }
    // The sparse system in one shot is one step of one increment of its load path.
    if on_path || plan.is_sparse() {
        return on_load_path(problem, (spec, plan, lemke), model, second, steps, found, clock);
    }
    solve_condensed_once(problem, (spec, plan), model, second, found, lemke, clock)
}

/// [`solve_on_load_path`] with the pair's paired points, unpaired candidates and the MLS gaps
/// of the final displacements ([`final_gaps`]).
fn on_load_path(
    problem: &Problem,
    (spec, plan, lemke): (&ContactSpec, plan::Plan, &lcp::LemkeParams),
    model: &mut Model,
    second: Option<(&Problem, &Model)>,
    steps: Option<&[Vec<StepEnd>]>,
    found: Found,
    clock: &mut Clock<'_>,
) -> Result<ContactOutcome, Error> {
    let Found { candidates, target, paired_points, unpaired } = found;
    let on_path = (candidates, target, plan, lemke);
    let (u1, u2, mut contact) =
        solve_on_load_path(problem, spec, model, second, steps, on_path, clock)?;
    contact.paired_points = paired_points;
    contact.unpaired = unpaired;
    let second_gap = contact.target.as_ref().zip(u2.as_deref());
    contact.gap = final_gaps(model, &contact.candidates, &u1, second_gap);
    Ok((u1, u2, contact))
}

/// One pair's candidates before any solve: the target body's operator, the paired points
/// and the number of candidates without a partner (two bodies).
struct Found {
    candidates: contact::Candidates,
    target: Option<contact::BodyOperator>,
    paired_points: Vec<geometry::Point>,
    unpaired: usize,
}

/// The candidates of `spec`'s edge against its rigid obstacles or the second body's edge.
fn find_candidates(
    problem: &Problem,
    spec: &ContactSpec,
    model: &Model,
    second: Option<(&Problem, &Model)>,
) -> Result<Found, contact::ContactError> {
    match (&spec.target, second) {
        (ContactTarget::Obstacles, _) if problem.obstacles().is_empty() => {
            // A library-built problem may name obstacles it does not have.
            Err(contact::ContactError::MissingTarget)
        }
        (ContactTarget::Rigid(_) | ContactTarget::Obstacles, _) => {
            let target =
                |x| contact::rigid_target(problem, spec, x).expect("a rigid target has obstacles");
            let c = contact::candidates_on(problem, model, spec.edge, &target, spec.condensation)?;
            Ok(Found { candidates: c, target: None, paired_points: Vec::new(), unpaired: 0 })
        }
        (ContactTarget::Body { edge }, Some((p2, m2))) => {
            let (c, op, paired, unpaired) = multibody::body_pair(
                problem,
                contact::Discretised::of(model),
                spec,
                (p2, contact::Discretised::of(m2), *edge),
            )?;
            Ok(Found { candidates: c, target: Some(op), paired_points: paired, unpaired })
        }
        (ContactTarget::Body { .. }, None) => Err(contact::ContactError::MissingTarget),
    }
}

/// Friction, load steps or a held translation: the load path (docs/method.md §8), condensed
/// or sparse as `plan` says, MFVM or FE, a rigid obstacle or two bodies; and frictionless
/// contact in one shot on the sparse system (one step of one increment of its path). Without
/// steps, one step to the models' loads in one increment. On the condensed path Lemke's
/// frictionless steps take `lemke`'s parameters, and with the plan's fallback (`"auto"`) a
/// path on which Lemke fails numerically is done again on the sparse system
/// ([`with_fallback`]).
fn solve_on_load_path(
    problem: &Problem,
    spec: &ContactSpec,
    model: &mut Model,
    second: Option<(&Problem, &Model)>,
    steps: Option<&[Vec<StepEnd>]>,
    on_path: (contact::Candidates, Option<contact::BodyOperator>, plan::Plan, &lcp::LemkeParams),
    clock: &mut Clock<'_>,
) -> Result<ContactOutcome, Error> {
    let (candidates, target, plan, lemke) = on_path;
    let one = |m: &Model| vec![StepEnd::whole(m, spec.friction)];
    let steps1 = steps.map_or_else(|| one(model), |s| s[0].clone());
    let target_of = |target: Option<contact::BodyOperator>| match (target, second) {
        (Some(op), Some((_, m2))) => Some(Target {
            model: m2,
            operator: op,
            steps: steps.and_then(|s| s.get(1)).map_or_else(|| one(m2), Clone::clone),
        }),
        _ => None,
    };
    if plan.is_sparse() {
        let target = target_of(target);
        return solve_frictional_active_set(
            problem, spec, model, candidates, target, &steps1, clock,
        );
    }
    let kept = plan.fallback.then(|| (candidates.clone(), target.clone()));
    let on = (&steps1[..], lemke);
    let condensed =
        solve_frictional(problem, spec, &*model, candidates, target_of(target), on, clock);
    let sparse = |clock: &mut Clock<'_>| {
        let (candidates, target) = kept.expect("kept for the fallback");
        let target = target_of(target);
        solve_frictional_active_set(problem, spec, model, candidates, target, &steps1, clock)
    };
    let ((u1, u2, mut contact), fallback_from) =
        with_fallback(condensed, plan.fallback, clock, sparse)?;
    if fallback_from.is_some() {
        contact.fallback_from = fallback_from;
    }
    Ok((u1, u2, contact))
}

/// `condensed`'s answer; or, when it failed as Lemke's numerical failure ([`lemke_refusal`])
/// and the plan has the fallback (`"auto"`), the sparse system's (`sparse`, docs/method.md
/// §5.1) with the reason recorded ([`fallback_reason`]). When the sparse system fails too,
/// the refusal says so ([`crate::error::LemkeRefusal::active_set_failure`]).
fn with_fallback<T>(
    condensed: Result<T, Error>,
    fallback: bool,
    clock: &mut Clock<'_>,
    sparse: impl FnOnce(&mut Clock<'_>) -> Result<T, Error>,
) -> Result<(T, Option<String>), Error> {
    let mut e = match condensed {
        Ok(answer) => return Ok((answer, None)),
        Err(e) => e,
    };
    if !fallback || lemke_refusal(&mut e).is_none() {
        return Err(e);
    }
    match sparse(clock) {
        Ok(answer) => Ok((answer, fallback_reason(&e))),
        Err(failure) => {
            if let Some(refusal) = lemke_refusal(&mut e) {
                refusal.active_set_failure = Some(failure.to_string());
            }
            Err(e)
        }
    }
}

/// Lemke's refusal in `e`: `e` itself, or the cause of the increment that failed.
fn lemke_refusal(e: &mut Error) -> Option<&mut crate::error::LemkeRefusal> {
    match e {
        Error::LemkeRefused(refusal) => Some(refusal),
        Error::Increment { cause, .. } => lemke_refusal(cause),
        _ => None,
    }
}

/// What `fallback_from` records of Lemke's refusal `e`: its diagnosis, after the increment
/// that failed when the problem has `[[step]]` tables.
fn fallback_reason(e: &Error) -> Option<String> {
    match e {
        Error::LemkeRefused(refusal) => Some(refusal.diagnosis_text()),
        Error::Increment { step, increment, increments, cause } => fallback_reason(cause)
            .map(|why| format!("load step {step}, increment {increment} of {increments}: {why}")),
        _ => None,
    }
}

/// Frictionless contact in one step: μ = 0, one step of one increment on the condensed load
/// path ([`load_path::run_condensed`]: Lemke on `M`, polished; one solve per body), a
/// mixed-precision factorisation's gaps corrected, with the plan's fallback to the active set
/// (`"auto"`) when Lemke fails numerically.
fn solve_condensed_once(
    problem: &Problem,
    (spec, plan): (&ContactSpec, plan::Plan),
    model: &mut Model,
    second: Option<(&Problem, &Model)>,
    found: Found,
    lemke: &lcp::LemkeParams,
    clock: &mut Clock<'_>,
) -> Result<ContactOutcome, Error> {
    let Found { candidates, target, paired_points, unpaired } = found;
    let m = candidates.len();
    let steps: Vec<_> =
        std::iter::once(&*model).chain(second.map(|(_, m2)| m2)).map(one_shot_step).collect();
    let terms = one_shot_terms((model, &candidates.operator), target.as_ref().zip(second), &steps);
    let mut condensed = clock.run_counted("condensation", |progress| {
        load_path::condense_normal(&terms, &candidates.initial_gap, progress)
    })?;
    let warning = compliance_warning(problem, spec, &condensed, target.as_ref())?;
    let path = load_path::Path {
        initial_gap: &candidates.initial_gap,
        normals: &candidates.normals,
        steps: &steps[0],
        friction: vec![vec![0.0; m]],
        moved: None,
        held: Vec::new(),
        groups: Vec::new(),
        write_steps: false,
        named_steps: false,
    };
    let blocks = load_path::normal_blocks(&mut condensed);
    let answer = match load_path::run_condensed(&path, &terms, blocks, lemke, clock) {
        Ok(answer) => answer,
        Err(e) => {
            let mut refusal = match refused(e, &condensed, warning.is_some()) {
                Error::LemkeRefused(refusal) => refusal,
                other => return Err(other),
            };
            // Frictionless and one step here: the active-set solver takes the problem, one
            // step of one increment of the sparse path.
            if plan.fallback {
                drop((terms, condensed));
                let found = Found { candidates, target, paired_points, unpaired };
                let sparse = (spec, plan::Plan::SPARSE, lemke);
                match on_load_path(problem, sparse, model, second, None, found, clock) {
                    Ok((u1, u2, mut contact)) => {
                        contact.warning = warning;
                        contact.fallback_from = Some(refusal.diagnosis_text());
                        return Ok((u1, u2, contact));
                    }
                    Err(e) => refusal.active_set_failure = Some(e.to_string()),
                }
            }
            return Err(Error::LemkeRefused(refusal));
        }
    };
    drop(terms);
    let load_path::PathAnswer { mut u, problem: step_problem, normal, .. } = answer;
    condensed.compliance = step_problem.nn;
    let Some((mut result, polish)) = normal else {
        unreachable!("a frictionless one-shot path answers with Lemke's normal LCP")
    };
    let mut u2 = (u.len() == 2).then(|| u.pop()).flatten();
    let mut u1 = u.pop().expect("the first body's displacements");
    let mut gap = final_gaps(model, &candidates, &u1, target.as_ref().zip(u2.as_deref()));
    // Mixed precision: `M` and `q` carry the single-precision solves' error; one correction
    // against the displacements' own gaps closes them to double precision.
    let mut correction = None;
    if model.factorisation.stats().precision == FactorPrecision::Mixed {
        let lcp_problem =
            lcp::Lcp::new(m, condensed.compliance.clone(), condensed.free_gap.clone())?;
        // The displacements of the forces `z` added to `u1`, `u2`, and their gaps.
        let displaced = |z: &[f64], u1: &[f64], u2: Option<&[f64]>| -> Result<_, Error> {
            let mut rhs = vec![0.0; u1.len()];
            candidates.operator.add_forces(z, &mut rhs);
            let d1 = model.factorisation.solve(&rhs)?;
            let v1: Vec<f64> = u1.iter().zip(&d1).map(|(a, b)| a + b).collect();
            let v2 = match (&target, second, u2) {
                (Some(op), Some((_, m2)), Some(u2)) => {
                    let mut rhs2 = vec![0.0; u2.len()];
                    op.add_forces(z, &mut rhs2);
                    let d2 = m2.factorisation.solve(&rhs2)?;
                    Some(u2.iter().zip(&d2).map(|(a, b)| a + b).collect::<Vec<f64>>())
                }
                _ => None,
            };
            let gap = final_gaps(model, &candidates, &v1, target.as_ref().zip(v2.as_deref()));
            Ok((v1, v2, gap))
        };
        let mut moved = None;
        let record = clock.run("gap_correction", || {
            solution::correct_closed_gaps(&lcp_problem, &mut result, &mut gap, &mut |dz| {
                let (v1, v2, g) = displaced(dz, &u1, u2.as_deref())?;
                moved = Some((v1, v2));
                Ok(g)
            })
        })?;
        if let (true, Some((v1, v2))) = (record.accepted, moved) {
            (u1, u2) = (v1, v2);
        }
        correction = Some(record);
    }
    let free_gap = condensed.free_gap.clone();
    let mut contact = ContactSolution::new(
        spec,
        candidates,
        target,
        paired_points,
        Some(condensed),
        &free_gap,
        result,
        gap,
        warning,
    );
    contact.unpaired = unpaired;
    contact.lemke_polish = Some(polish);
    contact.gap_correction = correction;
    Ok((u1, u2, contact))
}

/// A load path's error `e` as [`refused`] makes it, inside the increment that failed
/// ([`Error::Increment`]).
fn refused_on_path(e: Error, condensed: &contact::CondensedContact, overridden: bool) -> Error {
    match e {
        Error::Increment { step, increment, increments, cause } => {
            let cause = Box::new(refused_on_path(*cause, condensed, overridden));
            Error::Increment { step, increment, increments, cause }
        }
        e => refused(e, condensed, overridden),
    }
}

/// A frictionless one-shot path's error `e` as Lemke's numerical failure
/// ([`Error::LemkeRefused`], with the conditioning of `condensed`), or `e` itself: any other
/// error, and a ray when `M` failed its checks (`overridden`: the ray may then prove that no
/// solution exists, and stays Lemke's own error). The active-set method applies to every
/// problem that reaches Lemke.
fn refused(e: Error, condensed: &contact::CondensedContact, overridden: bool) -> Error {
    let cause = match e {
        Error::Lcp(cause @ lcp::LcpError::RayTermination { .. }) if overridden => {
            return cause.into();
        }
        Error::Lcp(cause) => cause,
        other => return other,
    };
    let m = condensed.free_gap.len();
    let extremes = [condensed.min_symmetric_eigenvalue, condensed.max_symmetric_eigenvalue];
    match crate::error::LemkeRefusal::new(cause, m, extremes, true) {
        Ok(refusal) => Error::LemkeRefused(Box::new(refusal)),
        Err(cause) => cause.into(),
    }
}

/// A body's one step of a one-shot path: to its own load in one increment, frictionless.
fn one_shot_step(model: &Model) -> Vec<StepEnd> {
    vec![StepEnd::whole(model, 0.0)]
}

/// The terms of a one-shot path (no tangential operators): the body's on its candidates'
/// operator, and the target body's on its operator.
fn one_shot_terms<'a>(
    (model, operator): (&'a Model, &'a contact::BodyOperator),
    target: Option<(&'a contact::BodyOperator, (&Problem, &'a Model))>,
    steps: &'a [Vec<StepEnd>],
) -> Vec<load_path::Term<'a>> {
    let term = |model, normal, steps| load_path::Term {
        model,
        normal,
        tangential: None,
        index: None,
        steps,
    };
    let mut terms = vec![term(model, operator, &steps[0])];
    if let Some((op, (_, m2))) = target {
        terms.push(term(m2, op, &steps[1]));
    }
    terms
}

/// The node coordinates the active-set solver orders its factorisations by (MFVM; the FE
/// path's meshes use the default ordering).
fn node_points(m: &Model) -> Option<&[geometry::Point]> {
    match m.scheme {
        Scheme::Mfvm(_) => Some(m.nodes.points.as_slice()),
        Scheme::Fem(_) => None,
    }
}

/// The active-set system of one body against rigid obstacles, owning `K`'s factors when
/// given them (`factors`: it may then release them, [`contact::sparse::ModelFactors`]), else
/// borrowing the model's.
fn rigid_obstacle<'a>(
    model: &'a Model,
    candidates: &'a contact::Candidates,
    factors: Option<Factorisation>,
) -> Result<contact::sparse::RigidObstacle<'a>, lcp::active_set::ActiveSetError> {
    let factors: contact::sparse::ModelFactors<'a> = match factors {
        Some(f) => f.into(),
        None => (&model.factorisation).into(),
    };
    contact::sparse::RigidObstacle::new(
        &model.system.matrix,
        &model.system.rhs,
        factors,
        &candidates.operator,
        &candidates.initial_gap,
        model.system.collocation_scale,
        node_points(model),
    )
}

/// The run-time checks of `M` (docs/method.md §4.1, §4.3): an error, or the warning to report
/// (`M` indefinite only below the scale of `target`'s cells, or `contact.allow_indefinite`).
fn compliance_warning(
    problem: &Problem,
    spec: &ContactSpec,
    condensed: &contact::CondensedContact,
    target: Option<&contact::BodyOperator>,
) -> Result<Option<String>, Error> {
    let two_body = matches!(spec.target, contact::ContactTarget::Body { .. });
    let context = contact::ComplianceContext::of(problem, two_body);
    let m = condensed.free_gap.len();
    let pairs = [(0..m, target)];
    Ok(contact::check_pair_compliance(condensed, &context, &pairs, spec.allow_indefinite)?)
}

/// The MLS gaps from the final displacements, `g0 + ν·u^h(x_c)`, plus the second body's
/// contribution `−ν·u_2^h(y_c)` when `second` holds its operator and displacements (also for
/// the stiffness form, whose LCP reads nodal parameters instead; `max_gap_mismatch` in the
/// summary shows the difference).
fn final_gaps(
    model: &Model,
    candidates: &contact::Candidates,
    u1: &[f64],
    second: Option<(&contact::BodyOperator, &[f64])>,
) -> Vec<f64> {
    let mut gap: Vec<f64> = candidates
        .initial_gap
        .iter()
        .zip(&candidates.nodes)
        .zip(&candidates.normals)
        .map(|((g0, &i), nu)| {
            let u = model.node_shapes.interpolate(i as usize, u1);
            g0 + nu[0] * u[0] + nu[1] * u[1]
        })
        .collect();
    if let Some((op, u2)) = second {
        for (g, d) in gap.iter_mut().zip(op.gap_contribution(u2)) {
            *g += d;
        }
    }
    gap
}

/// What a run reports: the summary and the files written.
#[derive(Debug)]
pub struct RunReport {
    /// The contents of `summary.json`.
    pub summary: Summary,
    /// Files written (`summary.json` last).
    pub files: Vec<PathBuf>,
}

impl std::fmt::Display for RunReport {
    /// The result block the command line prints after the stage list.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", post::console::Console(&self.summary))?;
        let dir = self.files.last().and_then(|p| p.parent());
        write!(
            f,
            "wrote {} files into {}",
            self.files.len(),
            dir.map_or_else(|| "-".into(), |d| d.display().to_string())
        )
    }
}

/// Solves `problem` and writes every output into `out`, `summary.json` included (the CLI's
/// job; `input`, the problem file as read, is echoed into the summary). The files go into
/// `out` when the run succeeds, replacing those of the earlier run and keeping every other
/// file ([`post::StagedDir`]), and `out` is left as it was when the run fails; an existing
/// non-empty `out` that holds no earlier run is refused.
///
/// # Errors
/// Any stage's error.
pub fn run(
    problem: &Problem,
    out: &Path,
    input: serde_json::Value,
    progress: &mut dyn Progress,
) -> Result<RunReport, Error> {
    run_with_report(problem, out, input, progress, false)
}

/// [`run`], and with `report` also `report.html` ([`post::report`]: the problem in words, the
/// results, the warnings, the plots inline and the timings), written with the other files.
///
/// # Errors
/// Any stage's error.
pub fn run_with_report(
    problem: &Problem,
    out: &Path,
    input: serde_json::Value,
    progress: &mut dyn Progress,
    report: bool,
) -> Result<RunReport, Error> {
    let staged = post::StagedDir::new(out)?;
    let (_, _, mut run) = solve_and_write(problem, staged.path(), input, progress)?;
    if report {
        let page = post::report::write_report(staged.path(), problem, &run.summary, &run.files)?;
        run.files.insert(run.files.len() - 1, page);
    }
    let files = staged.commit(run.files)?;
    Ok(RunReport { summary: run.summary, files })
}

/// A solved problem held in memory: the models, the solution and the summary, ready to be
/// inspected (for instance from the Python package) and written with [`Outcome::write`].
pub struct Outcome {
    /// The problem solved.
    pub problem: Problem,
    /// The (first) body's model.
    pub model: Model,
    /// The second body's model of a two-body contact.
    pub second: Option<Model>,
    /// The other bodies' models of a problem with several bodies or contact pairs
    /// (`Problem::multibody`; empty otherwise).
    pub others: Vec<Model>,
    /// The solution (the second body's inside it).
    pub solution: Solution,
    /// The contents of `summary.json`.
    pub summary: Summary,
}

impl Outcome {
    /// Solves `problem` without writing anything; `input` (the problem file as read) is echoed
    /// into the summary, as by [`run`]. With `discretisation.beta = "auto"` a run whose
    /// condensed compliance at `β = 0` fails its run-time checks is repeated once, from the
    /// start, at [`crate::problem::AUTO_BETA`]; the warnings (`summary.json` and the terminal) say so,
    /// and the summary's discretisation records the `β` used.
    ///
    /// # Errors
    /// Any stage's error.
    pub fn solve(
        problem: Problem,
        input: serde_json::Value,
        progress: &mut dyn Progress,
    ) -> Result<Self, Error> {
        let d = problem.discretisation;
        if !d.beta_auto
            || d.beta >= crate::problem::MIN_STABILISING_BETA
            || d.method == crate::problem::Method::Fem
        {
            return Self::solve_once(problem, input, progress);
        }
        match Self::solve_once(problem.clone(), input.clone(), progress) {
            Err(Error::Contact(contact::ContactError::IndefiniteCompliance {
                what,
                value,
                ..
            })) => {
                let mut stabilised = problem;
                // Every body shares the problem's discretisation table.
                for k in 0..stabilised.body_count() {
                    if let Some(body) = stabilised.body_mut(k) {
                        body.discretisation.beta = crate::problem::AUTO_BETA;
                    }
                }
                let mut outcome = Self::solve_once(stabilised, input, progress)?;
                outcome.summary.warnings.insert(
                    0,
                    format!(
                        "discretisation.beta = \"auto\": at beta = {} the condensed contact compliance was not trustworthy ({what} = {value:.3e}); solved again with beta = {}",
                        d.beta,
                        crate::problem::AUTO_BETA
                    ),
                );
                Ok(outcome)
            }
            other => other,
        }
    }

    fn solve_once(
        problem: Problem,
        input: serde_json::Value,
        progress: &mut dyn Progress,
    ) -> Result<Self, Error> {
        refuse_dynamics(&problem)?;
        if let Some(a) = problem.adaptive {
            let run = adaptive::solve_adaptive(&problem, &a, progress, &mut |_, _, _, _| {})?;
            let mut summary = Summary::new(input, &run.problem, &run.model, &run.solution);
            summary.refinement = Some(run.summary);
            let adaptive::AdaptiveRun { mut problem, model, second, others, solution, .. } = run;
            problem.adaptive = Some(a);
            return Ok(Self { problem, model, second, others, solution, summary });
        }
        let (model, second) = discretise_all(&problem, progress)?;
        if problem.is_scene_of_pairs() {
            let others = multibody::discretise_others(&problem, progress)?;
            let lemke = lcp::LemkeParams::default();
            let (model, others, solution) =
                multibody::solve_bodies(&problem, model, others, progress, &lemke)?;
            let summary = Summary::new(input, &problem, &model, &solution);
            return Ok(Self { problem, model, second: None, others, solution, summary });
        }
        let (model, second, solution) = solve_model(&problem, model, second, progress)?;
        let summary = Summary::new(input, &problem, &model, &solution);
        Ok(Self { problem, model, second, others: Vec::new(), solution, summary })
    }

    /// Writes every output into `out`, as [`run`] does (same files, same bytes; the earlier
    /// run's files replaced, every other file kept).
    ///
    /// # Errors
    /// [`Error::Output`] when a file cannot be written or `out` holds something else.
    pub fn write(&self, out: &Path) -> Result<RunReport, Error> {
        self.write_with_report(out, false)
    }

    /// [`Outcome::write`], and with `report` also `report.html` ([`run_with_report`]).
    ///
    /// # Errors
    /// [`Error::Output`] when a file cannot be written or `out` holds something else.
    pub fn write_with_report(&self, out: &Path, report: bool) -> Result<RunReport, Error> {
        let staged = post::StagedDir::new(out)?;
        let mut files = write_outcome(staged.path(), self)?;
        if report {
            let page =
                post::report::write_report(staged.path(), &self.problem, &self.summary, &files)?;
            files.insert(files.len() - 1, page);
        }
        let files = staged.commit(files)?;
        Ok(RunReport { summary: self.summary.clone(), files })
    }
}

/// Writes the files of a solved problem into `out` (`summary.json` last).
fn write_outcome(out: &Path, o: &Outcome) -> Result<Vec<PathBuf>, Error> {
    let (problem, second, solution) = (&o.problem, o.second.as_ref(), &o.solution);
    let mut files = match problem.multibody() {
        Some(_) => post::write_multibody(out, problem, &o.model, &o.others, solution)?,
        None => post::write_solution(out, problem, &o.model, second, solution)?,
    };
    if o.summary.refinement.is_some() {
        files.extend(post::write_node_spacing(out, problem, &o.model.nodes)?);
        if let Some(several) = problem.multibody() {
            for (p, m) in several.bodies.iter().zip(&o.others) {
                files.extend(post::write_node_spacing(&out.join(&p.name), p, &m.nodes)?);
            }
        }
    }
    if let (Some(p2), Some(m2), Some(s2)) = (problem.second_body(), second, solution.second_body())
    {
        files.extend(post::write_solution(&out.join(&p2.name), p2, m2, None, s2)?);
        if o.summary.refinement.is_some() {
            files.extend(post::write_node_spacing(&out.join(&p2.name), p2, &m2.nodes)?);
        }
    }
    files.extend(post::write_paraview(out, problem, solution)?);
    let path = out.join("summary.json");
    post::write_text(&path, &o.summary.to_json())?;
    files.push(path);
    Ok(files)
}

/// [`run`], also returning the model and the solution (for [`compare`]).
/// The static solves refuse a `[dynamics]` problem: it runs through [`dynamics::run`] or
/// [`dynamics::solve`].
fn refuse_dynamics(problem: &Problem) -> Result<(), Error> {
    match problem.dynamics {
        Some(_) => Err(crate::problem::ProblemError::Invalid {
            field: "dynamics".into(),
            value: "(given)".into(),
            reason: "a [dynamics] problem is solved by pipeline::dynamics::run or ::solve (the command line does this), not by the static solve".into(),
        }
        .into()),
        None => Ok(()),
    }
}

fn solve_and_write(
    problem: &Problem,
    out: &Path,
    input: serde_json::Value,
    progress: &mut dyn Progress,
) -> Result<(Model, Solution, RunReport), Error> {
    let outcome = Outcome::solve(problem.clone(), input, progress)?;
    let files = write_outcome(out, &outcome)?;
    let Outcome { model, solution, summary, .. } = outcome;
    Ok((model, solution, RunReport { summary, files }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip `length × 1` at spacing 0.05 (`length / 0.05 + 1` nodes on its bottom, the
    /// contact edge) above a rigid floor, with `contact` appended to its `[contact]` table.
    fn strip(length: f64, contact: &str) -> Problem {
        Problem::from_toml(&format!(
            r#"
            [geometry]
            kind = "rectangle"
            x = [0.0, {length:?}]
            y = [-0.5, 0.5]
            [nodes]
            spacing = 0.05
            [material]
            young = 30000.0
            poisson = 0.3
            plane = "stress"
            [[boundary]]
            edge = "left"
            displacement = {{ x = 0.0, y = 0.0 }}
            [[boundary]]
            edge = "top"
            traction = {{ y = -1.0 }}
            [contact]
            edge = "bottom"
            obstacle_point = [0.0, -0.51]
            obstacle_normal = [0.0, 1.0]
            {contact}
            "#
        ))
        .unwrap()
    }

    #[test]
    fn the_static_lu_is_the_models_own_only_for_lemke_from_1000_candidates() {
        let sparse = |p: &Problem, pinned: bool| {
            plan::condensed_sparsely(p, &nodes::for_problem(p).unwrap(), pinned)
        };
        let lemke = "solver = \"lemke\"";
        // 1 001 nodes on the contact edge: the Lemke path condenses by reach-restricted solves.
        assert!(sparse(&strip(50.0, lemke), false));
        // 981: below the threshold.
        assert!(!sparse(&strip(49.0, lemke), false));
        // "auto" takes the active set from 1 000 candidates; friction and a held translation
        // take the incremental path.
        assert!(!sparse(&strip(50.0, ""), false));
        assert!(!sparse(&strip(50.0, &format!("{lemke}\nfriction = 0.3")), false));
        assert!(!sparse(&strip(50.0, lemke), true));
    }
}
