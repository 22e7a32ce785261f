//! Several bodies and contact pairs in one LCP (docs/method.md §4.5): every pair's
//! candidates, each body's `K` factorised once and condensed once for all the pairs that touch
//! it, `M = Σ_b G_b K_b⁻¹ E_b` and `q = g0 + Σ_b G_b K_b⁻¹ f_b` over all candidates, Lemke,
//! then one solve per body with the contact forces of its pairs; or, with
//! `contact[k].solver = "active_set"`, the active-set method on all bodies at once without
//! `M` (docs/method.md §5.1, [`contact::sparse::Bodies`]).

pub(super) mod pair;
mod path;
mod sparse_path;
mod trials;

use super::friction::{StepEnd, step_ends};
use super::load_path::{self, Term};
use super::plan::Plan;
use super::{final_gaps, finite};
use crate::assembly::PinnedMode;
use crate::contact::{self, BodyOperator, Candidates, ContactTarget};
use crate::error::Error;
use crate::geometry::{self, Point};
use crate::lcp;
use crate::lcp::load_driven::LoadDrivenError;
use crate::mls::ShapeSet;
use crate::model::Model;
use crate::problem::{ContactPair, ContactSolver, Multibody, Problem, ProblemError};
use crate::progress::{Clock, Progress};
use crate::solution::{self, ContactSolution, SceneContact, Solution};

/// The candidates of `edge` of `problem`'s body against the edge `target_edge` of `target`,
/// straight or curved (docs/method.md §4.3): the candidates whose projection falls on the target edge
/// (the others have no partner: their number is returned), the target's operator (`d = −ν`
/// at the paired points), the initial gaps (less the pair's `interference`, docs/method.md
/// §9.9) and the paired points.
///
/// # Errors
/// [`contact::ContactError::NoPartner`] when no candidate lies over it, and the errors of
/// [`contact::candidates_on`] and [`contact::target_operator_on`].
pub(super) fn body_pair(
    problem: &Problem,
    model: contact::Discretised<'_>,
    spec: &contact::ContactSpec,
    target: (&Problem, contact::Discretised<'_>, usize),
) -> Result<(Candidates, BodyOperator, Vec<Point>, usize), contact::ContactError> {
    let (p2, m2, edge) = target;
    let pairing = contact::TargetEdge::new(&p2.domain, edge);
    let mut c = match p2.domain.straight_normal(edge) {
        Some(normal) => contact::candidates_in(
            problem,
            model,
            spec.edge,
            &|_| (0.0, normal),
            spec.condensation,
        )?,
        // A curved target: each candidate's normal is the bisector of the target's outward
        // normal at its closest point and the candidate edge's inward normal at it
        // (`contact::TargetEdge::bisector`, docs/method.md §9.6), the target's side pairing
        // along it (`contact::TargetEdge::pair_along`); a
        // candidate on the axis of an axisymmetric body takes the axial one, as the target's
        // side turns it (`contact::TargetEdge::axial`): its radial row is the symmetry
        // condition, so a normal with a radial part (a mesh's polyline target at its end
        // vertex) would leave that node out of the candidates, free to overlap the target.
        None => {
            let (lo, hi) = problem.domain.bounding_box();
            let axis = AXIS_TOLERANCE * (hi[0] - lo[0]).max(hi[1] - lo[1]);
            let axisymmetric = model.system().axisymmetric;
            let normal = |x: Point| {
                let n = problem.domain.outward_normal_at(spec.edge, x);
                let nu = pairing.bisector(x, [-n[0], -n[1]]);
                match axisymmetric && x[0].abs() <= axis {
                    true => (0.0, [0.0, nu[1].signum()]),
                    false => (0.0, nu),
                }
            };
            contact::candidates_in(problem, model, spec.edge, &normal, spec.condensation)?
        }
    };
    // A candidate whose projection falls beside the target edge has no partner: it cannot
    // close, and is no candidate.
    let (a2, b2) = p2.domain.edge(edge);
    let tol = 1e-9 * (b2[0] - a2[0]).hypot(b2[1] - a2[1]);
    let over: Vec<bool> = match pairing.is_straight() {
        true => c.points.iter().map(|&x| geometry::projects_onto(x, a2, b2, tol)).collect(),
        false => c.points.iter().map(|&x| pairing.over(x)).collect(),
    };
    let unpaired = c.retain(&over);
    if c.is_empty() {
        return Err(contact::ContactError::NoPartner {
            edge: problem.domain.edge_names()[spec.edge].clone(),
            target: p2.domain.edge_names()[edge].clone(),
        });
    }
    let (op, gaps, paired) = contact::target_operator_in(p2, m2, edge, &c)?;
    // A designed interference (a press fit): the gaps of the bodies made `δ` larger.
    c.initial_gap = gaps.into_iter().map(|g| g - spec.interference).collect();
    if !pairing.is_straight() {
        // The target may have turned a normal to the axis (`contact::TargetEdge::axial`).
        for (k, d) in op.directions.iter().enumerate() {
            c.normals[k] = [-d[0], -d[1]];
        }
        c.operator.directions.clone_from(&c.normals);
    }
    Ok((c, op, paired, unpaired))
}

/// Relative tolerance (of the section's size) within which a candidate lies on the axis (as
/// `contact::rings` and `problem::axisymmetric` read it).
const AXIS_TOLERANCE: f64 = 1e-12;

/// The models of `problem`'s other bodies (`multibody`; empty without).
///
/// # Errors
/// Any stage's error while discretising a body.
pub fn discretise_others(
    problem: &Problem,
    progress: &mut dyn Progress,
) -> Result<Vec<Model>, Error> {
    let Some(several) = problem.multibody() else { return Ok(Vec::new()) };
    let mut models = Vec::with_capacity(several.bodies.len());
    for (k, p) in several.bodies.iter().enumerate() {
        progress.section(&format!("body `{}` ({})", p.name, crate::post::method_label(p)));
        let held = several.pairs.iter().any(|c| c.body == k + 1 || c.target_body == Some(k + 1));
        models.push(super::discretise_held(p, held, progress).map_err(|e| named(p, held, e))?);
    }
    progress.section("contact and recovery");
    Ok(models)
}

/// `err`, from discretising body `problem` of several: a body touched by a contact pair that
/// its displacement conditions leave free in more ways than the one translation contact may
/// hold is refused naming the body and a free mode ([`LoadDrivenError::FreeBody`],
/// docs/method.md §4.7); other errors unchanged.
pub(super) fn named(problem: &Problem, held: bool, err: Error) -> Error {
    use crate::assembly::AssemblyError as A;
    let (mode, detail) = match &err {
        Error::Assembly(A::NoDirichlet) if held => (
            "translation in x",
            "no displacement is prescribed on any of its edges, so both translations and the rotation are free".to_string(),
        ),
        Error::Assembly(A::RigidBodyMotion { mode }) if held => (
            *mode,
            format!("its displacement conditions leave rigid-body {mode} free, with more than one translation or with the rotation"),
        ),
        _ => return err,
    };
    lcp::LcpError::from(LoadDrivenError::FreeBody { body: problem.name.clone(), mode, detail })
        .into()
}

/// A body held by contact: its index, pin, `a` over all candidates and the load along `r`.
type Held = (usize, PinnedMode, Vec<f64>, f64);

/// The bodies of several whose free translation the contact holds (docs/method.md §4.7),
/// in body order: each one's index, pin, the `a_c = −s_c ν_c·r` over all candidates
/// (`s_c = +1` on the candidate's body, `−1` on its target body) and the applied load along
/// `r`. Empty when no body is pinned.
///
/// # Errors
/// [`LoadDrivenError::NotRestrained`] when every `ν_c·r` of a pinned body vanishes,
/// [`LoadDrivenError::Unsupported`] when a pinned node carries contact forces.
fn held_bodies(
    problems: &[&Problem],
    models: &[&Model],
    pairs: &[ContactPair],
    found: &[PairCandidates],
    operators: &[Option<(BodyOperator, Vec<usize>)>],
) -> Result<Vec<Held>, LoadDrivenError> {
    let pinned = models.iter().enumerate().filter_map(|(b, m)| m.system.pinned.map(|p| (b, p)));
    let mut held = Vec::new();
    for (b, pin) in pinned {
        if let Some((op, _)) = &operators[b]
            && op.owners.iter().flatten().any(|&(i, _)| i == pin.node)
        {
            return Err(LoadDrivenError::Unsupported {
                mode: pin.name(),
                why: format!(
                    "the pinned node {} of body `{}` carries contact forces",
                    pin.node, problems[b].name
                ),
            });
        }
        let axis = pin.axis as usize;
        let along: Vec<f64> = pairs
            .iter()
            .zip(found)
            .flat_map(|(pair, f)| {
                let side = if pair.body == b {
                    1.0
                } else if pair.target_body == Some(b) {
                    -1.0
                } else {
                    0.0
                };
                (0..f.candidates.len()).map(move |c| -side * f.candidates.normal(c)[axis])
            })
            .collect();
        if along.iter().all(|a| a.abs() <= 1e-12) {
            return Err(LoadDrivenError::NotRestrained { mode: pin.name() });
        }
        let load = super::load_path::load_along(models[b], pin, &models[b].system.load);
        held.push((b, pin, along, load));
    }
    Ok(held)
}

/// One pair's candidates and target operator.
struct PairCandidates {
    candidates: Candidates,
    target: Option<BodyOperator>,
    paired: Vec<Point>,
    unpaired: usize,
}

/// Solves a problem with several bodies or contact pairs (`problem.multibody()`): `model` is
/// the first body's, `others` the other bodies' (as [`discretise_others`] builds them).
/// Returns the models and the first body's solution, the others' and the pairs' inside its
/// `multibody`.
///
/// # Errors
/// [`Error::Problem`] without `multibody` or with the wrong number of models; the contact
/// stage's errors (no candidates, no partner, a compliance that fails its checks);
/// [`Error::LemkeRefused`] when Lemke fails; [`Error::Solve`] when a solve fails.
pub fn solve_bodies(
    problem: &Problem,
    mut model: Model,
    mut others: Vec<Model>,
    progress: &mut dyn Progress,
    lemke: &lcp::LemkeParams,
) -> Result<(Model, Vec<Model>, Solution), Error> {
    let several = multibody_of(problem, others.len())?;
    let mut clock = Clock::new(progress, std::mem::take(&mut model.timings));
    let problems: Vec<&Problem> = std::iter::once(problem).chain(several.bodies.iter()).collect();
    let pairs = &several.pairs;
    // Friction or load steps: the load path (docs/method.md §8) with each body's step ends,
    // the models' own load and right-hand side those of the last step.
    let on_path = !problem.steps.is_empty() || pairs.iter().any(|p| p.spec.friction > 0.0);
    let steps = if on_path {
        path_steps(&problems, &mut model, &mut others, &mut clock)?
    } else {
        Vec::new()
    };
    let models: Vec<&Model> = std::iter::once(&model).chain(others.iter()).collect();
    let found = clock.run("contact_candidates", || {
        pairs
            .iter()
            .map(|pair| pair_candidates(pair, &problems, &models))
            .collect::<Result<Vec<_>, contact::ContactError>>()
    })?;
    let numbering = Numbering::new(pairs, &found, problems.len());
    let held = held_bodies(&problems, &models, pairs, &found, &numbering.operators)
        .map_err(lcp::LcpError::from)?;
    let scene = numbering.scene(problem, pairs, &found, &steps);
    let ((solved, frictions, load_driven), fallback_from) =
        solve_scene(&scene, &models, &held, on_path, lemke, &mut clock)?;
    let Solved { result, free_gap, condensed, warning, search, displacements: u, record } = solved;
    let rigid = held_modes(&held, &search, (&problems, &models), &result, &free_gap)?;
    // The pin's value is the translation found, so that the system each solution answers
    // (its residual, its reactions) is the one solved.
    drop(models);
    for (b, r) in &rigid {
        super::set_pin(if *b == 0 { &mut model } else { &mut others[*b - 1] }, r);
    }
    let models: Vec<&Model> = std::iter::once(&model).chain(others.iter()).collect();
    let answer = PairAnswer { result: &result, free_gap: &free_gap, load_driven, frictions };
    let contacts = pair_solutions(problem, pairs, found, &numbering, (&models, &u), answer);
    let mut solutions =
        clock.run("recovery", || recover_bodies(&problems, &models, pairs, &contacts, u));
    let rest = solutions.split_off(1);
    let mut solution = solutions.pop().expect("the first body's solution");
    solution.others = rest;
    solution.contact_pairs = contacts;
    solution.scene = Some(Box::new(SceneContact {
        condensed,
        lcp: result,
        active_set: record,
        warning,
        held: rigid,
        fallback_from,
    }));
    solution.timings = clock.timings.clone();
    model.timings = clock.timings;
    finite(solution).map(|s| (model, others, s))
}

/// `problem`'s several bodies and pairs, when `others` holds one model per further body.
fn multibody_of(problem: &Problem, others: usize) -> Result<Multibody<'_>, Error> {
    match problem.multibody() {
        Some(m) if m.bodies.len() == others => Ok(m),
        _ => Err(ProblemError::Invalid {
            field: "body".into(),
            value: format!("{} models", 1 + others),
            reason: "solve_bodies needs a problem with several bodies or contact pairs and one model per body".into(),
        }
        .into()),
    }
}

/// Each body's step ends on the load path; each model's load and right-hand side become those
/// of its last step.
fn path_steps(
    problems: &[&Problem],
    model: &mut Model,
    others: &mut [Model],
    clock: &mut Clock<'_>,
) -> Result<Vec<Vec<StepEnd>>, Error> {
    let mut steps = Vec::with_capacity(problems.len());
    for (p, m) in problems.iter().zip(std::iter::once(model).chain(others.iter_mut())) {
        let ends = if p.steps.is_empty() {
            // μ per pair is read from the pairs (`path::friction_per_step`).
            vec![StepEnd::whole(m, 0.0)]
        } else {
            clock.run("load_steps", || step_ends(p, m))?
        };
        if let Some(last) = ends.last() {
            m.system.load.clone_from(&last.load);
            m.system.rhs.clone_from(&last.rhs);
        }
        steps.push(ends);
    }
    Ok(steps)
}

/// The candidates of all pairs in one numbering.
struct Numbering {
    /// Pair `k`'s candidates are `offsets[k]..offsets[k + 1]`.
    offsets: Vec<usize>,
    /// Each body's operator over the candidates that touch it, and their global indices.
    operators: Vec<Option<(BodyOperator, Vec<usize>)>>,
    initial_gap: Vec<f64>,
    /// The candidates a step's obstacle motion or force moves: those of the pairs against
    /// rigid obstacles, which move together (docs/method.md §4.6).
    moved: Vec<bool>,
}

impl Numbering {
    fn new(pairs: &[ContactPair], found: &[PairCandidates], bodies: usize) -> Self {
        // Global candidate numbering: pair k's candidates follow pair k − 1's.
        let mut offsets = vec![0];
        for f in found {
            offsets.push(offsets.last().copied().unwrap_or(0) + f.candidates.len());
        }
        let normal_ops: Vec<_> =
            found.iter().map(|f| (&f.candidates.operator, f.target.as_ref())).collect();
        let operators =
            (0..bodies).map(|b| body_operator(b, pairs, &normal_ops, &offsets)).collect();
        let initial_gap =
            found.iter().flat_map(|f| f.candidates.initial_gap.iter().copied()).collect();
        let moved = pairs
            .iter()
            .zip(found)
            .flat_map(|(p, f)| std::iter::repeat_n(p.target_body.is_none(), f.candidates.len()))
            .collect();
        Self { offsets, operators, initial_gap, moved }
    }

    /// The scene the paths walk: `problem`'s `pairs` with their candidates `found` in this
    /// numbering, each body along its step ends `steps`.
    fn scene<'s>(
        &'s self,
        problem: &'s Problem,
        pairs: &'s [ContactPair],
        found: &'s [PairCandidates],
        steps: &'s [Vec<StepEnd>],
    ) -> path::Scene<'s> {
        path::Scene {
            problem,
            pairs,
            found,
            offsets: &self.offsets,
            operators: &self.operators,
            initial_gap: &self.initial_gap,
            moved: &self.moved,
            steps,
        }
    }
}

/// The LCP over all pairs, by the route the scene takes: the load path (condensed or sparse)
/// with friction or steps, else one shot (Lemke, or the sparse path's one step of one
/// increment); on the condensed system `"auto"`'s fallback to the sparse one when Lemke fails
/// numerically ([`super::with_fallback`]). Also the frictional records, a force-driven
/// obstacle's record and the fallback's reason.
fn solve_scene(
    scene: &path::Scene<'_>,
    models: &[&Model],
    held: &[Held],
    on_path: bool,
    lemke: &lcp::LemkeParams,
    clock: &mut Clock<'_>,
) -> Result<(path::OnPath, Option<String>), Error> {
    let solvers: Vec<ContactSolver> = scene.pairs.iter().map(|p| p.spec.solver).collect();
    let plan = Plan::several(&solvers, on_path, scene.initial_gap.len());
    let sparse = |clock: &mut Clock<'_>| match on_path {
        true => sparse_path::solve(scene, models, held, clock),
        false => sparse_once(scene, models, held, clock).map(|s| (s, Vec::new(), None)),
    };
    if plan.is_sparse() {
        return Ok((sparse(clock)?, None));
    }
    let condensed = match on_path {
        true => path::solve(scene, models, held, lemke, clock),
        false => solve_lemke(scene, models, held, lemke, clock).map(|s| (s, Vec::new(), None)),
    };
    // Lemke failed numerically: the plan's fallback (`"auto"` on every pair) hands the
    // problem to the active-set method (docs/method.md §5.1) and records why, as for one pair.
    super::with_fallback(condensed, plan.fallback, clock, sparse)
}

/// Frictionless contact in one shot on the sparse system ([`contact::sparse::Bodies`],
/// docs/method.md §5.1): one step of one increment of the sparse load path
/// ([`sparse_path::solve`]), each body to its own load; no `M`, so none of its checks; a held
/// translation (§4.7) found by the nested search over warm-started solves; the displacements
/// those of the final closed set (with the pins at the translations found).
fn sparse_once(
    scene: &path::Scene<'_>,
    models: &[&Model],
    held: &[Held],
    clock: &mut Clock<'_>,
) -> Result<Solved, Error> {
    let steps: Vec<Vec<StepEnd>> = models.iter().map(|m| super::one_shot_step(m)).collect();
    let scene = path::Scene { steps: &steps, ..*scene };
    let (solved, _, _) = sparse_path::solve(&scene, models, held, clock)?;
    Ok(solved)
}

/// The bodies held by the contact alone (docs/method.md §4.7): each one's translation found,
/// after checking that the contact determines it.
fn held_modes(
    held: &[Held],
    search: &[(f64, usize)],
    (problems, models): (&[&Problem], &[&Model]),
    result: &lcp::LcpSolution,
    free_gap: &[f64],
) -> Result<Vec<(usize, solution::RigidMode)>, Error> {
    let mut rigid = Vec::with_capacity(held.len());
    for ((b, pin, along, load), &(displacement, evaluations)) in held.iter().zip(search) {
        super::load_path::check_determined(
            (&problems[*b].name, pin.name()),
            *load,
            along,
            result,
            free_gap,
        )?;
        let mut translation = [0.0; 2];
        translation[pin.axis as usize] = displacement;
        let mode = solution::RigidMode {
            mode: pin.name(),
            pin_point: models[*b].nodes.points[pin.node as usize],
            translation,
            load: *load,
            evaluations,
            total_evaluations: evaluations,
        };
        rigid.push((*b, mode));
    }
    Ok(rigid)
}

/// What the LCP gave that every pair's record shares.
struct PairAnswer<'a> {
    result: &'a lcp::LcpSolution,
    free_gap: &'a [f64],
    load_driven: Option<solution::LoadDriven>,
    /// One frictional record per pair (empty when frictionless).
    frictions: Vec<solution::FrictionContact>,
}

/// Each pair's contact solution: its share of the answer, its gaps from the final
/// displacements (the rigid obstacles where the last step or the force search left them).
fn pair_solutions(
    problem: &Problem,
    pairs: &[ContactPair],
    found: Vec<PairCandidates>,
    numbering: &Numbering,
    (models, u): (&[&Model], &[Vec<f64>]),
    answer: PairAnswer<'_>,
) -> Vec<ContactSolution> {
    let PairAnswer { result, free_gap, load_driven, frictions } = answer;
    // The default gap tolerance (docs/method.md §6) from all pairs' gaps: one pair's own
    // contact-free gaps may all vanish (an edge that a rigid motion keeps in place).
    let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    let tolerance =
        (1e-5 * max_abs(&numbering.initial_gap) + 1e-12 * max_abs(free_gap)).max(f64::MIN_POSITIVE);
    let mut frictions = frictions.into_iter();
    // Where the last step left the rigid obstacles (or the force search put them).
    let obstacle = load_driven
        .as_ref()
        .map_or(problem.steps.last().map_or([0.0, 0.0], |s| s.obstacle_displacement), |l| {
            l.displacement
        });
    let offsets = &numbering.offsets;
    found
        .into_iter()
        .zip(pairs)
        .enumerate()
        .map(|(k, (mut f, pair))| {
            let range = offsets[k]..offsets[k + 1];
            let rigid = pair.target_body.is_none();
            if rigid {
                super::friction::move_obstacle(&mut f.candidates, obstacle);
            }
            let target = pair.target_body.zip(f.target.as_ref());
            let gap = final_gaps(
                models[pair.body],
                &f.candidates,
                &u[pair.body],
                target.map(|(t, op)| (op, u[t].as_slice())),
            );
            let share = lcp::LcpSolution {
                z: result.z[range.clone()].to_vec(),
                w: result.w[range.clone()].to_vec(),
                pivots: result.pivots,
                residuals: result.residuals,
            };
            let spec = crate::problem::ContactSpec {
                gap_tolerance: pair.spec.gap_tolerance.or(Some(tolerance)),
                ..pair.spec
            };
            let mut c = ContactSolution::new(
                &spec,
                f.candidates,
                f.target,
                f.paired,
                None,
                &free_gap[range],
                share,
                gap,
                None,
            );
            c.unpaired = f.unpaired;
            c.friction = frictions.next();
            c.load_driven = load_driven.clone().filter(|_| rigid);
            c
        })
        .collect()
}

/// Every body's solution from its displacements and the normal and tangential forces of the
/// pairs that touch it (as candidate body or as target).
fn recover_bodies(
    problems: &[&Problem],
    models: &[&Model],
    pairs: &[ContactPair],
    contacts: &[ContactSolution],
    u: Vec<Vec<f64>>,
) -> Vec<Solution> {
    u.into_iter()
        .enumerate()
        .map(|(b, u_b)| {
            let ops: Vec<(&BodyOperator, &[f64])> = pairs
                .iter()
                .zip(contacts)
                .flat_map(|(pair, c)| {
                    let own = (pair.body == b).then_some(&c.candidates.operator);
                    let target = c.target.as_ref().filter(|_| pair.target_body == Some(b));
                    let normal = own.into_iter().chain(target).map(|op| (op, c.lcp.z.as_slice()));
                    // The tangential forces of a frictional pair on either body.
                    let tangential = c.friction.iter().flat_map(move |f| {
                        let own = (pair.body == b).then_some(&f.operator);
                        let target =
                            f.target_operator.as_ref().filter(|_| pair.target_body == Some(b));
                        own.into_iter().chain(target).map(|op| (op, f.step.tangential.as_slice()))
                    });
                    normal.chain(tangential)
                })
                .collect();
            solution::recover(problems[b], models[b], u_b, &ops)
        })
        .collect()
}

/// What the LCP over all pairs gave: the answer `z, w` over all candidates, the gaps without
/// contact forces `q` (at `t = 0` for a held body), Lemke's `M` and its overridden checks,
/// the held translation's search (`t`, LCP solves), and the active set's displacements per
/// body and record.
struct Solved {
    result: lcp::LcpSolution,
    free_gap: Vec<f64>,
    condensed: Option<contact::CondensedContact>,
    warning: Option<String>,
    /// Each held body's translation and the LCP solves of the search (empty: none held).
    search: Vec<(f64, usize)>,
    displacements: Vec<Vec<f64>>,
    record: Option<solution::ActiveSetRecord>,
}

/// The run-time checks of `M` over all pairs (docs/method.md §4.1, §4.3): an error, or the
/// warning to report (`M` indefinite only below the scale of the targets' cells, or
/// `allow_indefinite`, the same on every pair, validated).
fn compliance_warning(
    problem: &Problem,
    pairs: &[ContactPair],
    targets: &[contact::PairTarget<'_>],
    condensed: &contact::CondensedContact,
) -> Result<Option<String>, Error> {
    let allow = pairs.first().is_some_and(|p| p.spec.allow_indefinite);
    let two_body =
        pairs.iter().any(|p| matches!(p.spec.target, contact::ContactTarget::Body { .. }));
    let context = contact::ComplianceContext::of(problem, two_body);
    Ok(contact::check_pair_compliance(condensed, &context, targets, allow)?)
}

/// Each pair's candidates in the global numbering and its elastic target's operator, for
/// [`contact::check_pair_compliance`].
fn pair_targets<'a>(
    found: &'a [PairCandidates],
    offsets: &[usize],
) -> Vec<contact::PairTarget<'a>> {
    found.iter().enumerate().map(|(k, f)| (offsets[k]..offsets[k + 1], f.target.as_ref())).collect()
}

/// Lemke's method on `M = Σ_b G_b K_b⁻¹ E_b` over all candidates (docs/method.md §4.5), with
/// the search of a held translation (§4.7): μ = 0, one step of one increment on the
/// condensed load path ([`load_path::run_condensed`]), each body one term.
fn solve_lemke(
    scene: &path::Scene<'_>,
    models: &[&Model],
    held: &[Held],
    lemke: &lcp::LemkeParams,
    clock: &mut Clock<'_>,
) -> Result<Solved, Error> {
    let (problem, pairs, initial_gap) = (scene.problem, scene.pairs, scene.initial_gap);
    let m = initial_gap.len();
    let steps: Vec<Vec<StepEnd>> = models.iter().map(|m| super::one_shot_step(m)).collect();
    let mut term_of = vec![None; models.len()];
    let mut terms = Vec::new();
    for (b, op) in scene.operators.iter().enumerate() {
        if let Some((normal, index)) = op {
            term_of[b] = Some(terms.len());
            let (model, steps) = (models[b], &steps[b]);
            terms.push(Term { model, normal, tangential: None, index: Some(index), steps });
        }
    }
    let mut condensed = clock.run_counted("condensation", |progress| {
        load_path::condense_normal(&terms, initial_gap, progress)
    })?;
    let targets = pair_targets(scene.found, scene.offsets);
    let warning = compliance_warning(problem, pairs, &targets, &condensed)?;
    let (normals, friction) = (path::normals(scene), vec![vec![0.0; m]]);
    let path = load_path::Path {
        initial_gap,
        normals: &normals,
        steps: &steps[0],
        moved: Some(scene.moved),
        held: path::held_on_path(held, &term_of, &friction, &normals)?,
        friction,
        groups: Vec::new(),
        write_steps: false,
        named_steps: false,
    };
    let blocks = load_path::normal_blocks(&mut condensed);
    let answer = load_path::run_condensed(&path, &terms, blocks, lemke, clock)
        .map_err(|e| super::refused(e, &condensed, warning.is_some()))?;
    drop(terms);
    condensed.compliance = answer.problem.nn;
    let Some((result, _)) = answer.normal else {
        unreachable!("a frictionless path answers with Lemke's normal LCP")
    };
    // Each body's displacements: its term's, or (no pair touches it) its own solve.
    let mut solved = answer.u.into_iter();
    let mut u = Vec::with_capacity(models.len());
    for (b, model) in models.iter().enumerate() {
        match term_of[b] {
            Some(_) => u.push(solved.next().expect("one answer per term")),
            None => u.push(clock.run("solve", || model.factorisation.solve(&model.system.rhs))?),
        }
    }
    let search = (answer.rigid_modes.iter().zip(held))
        .map(|(r, (_, pin, _, _))| (r.translation[pin.axis as usize], r.evaluations))
        .collect();
    Ok(Solved {
        result,
        free_gap: condensed.free_gap.clone(),
        condensed: Some(condensed),
        warning,
        search,
        displacements: u,
        record: None,
    })
}

/// The sparse system of all bodies and pairs ([`contact::sparse::Bodies`]).
fn bodies_system<'a>(
    models: &[&'a Model],
    pairs: &'a [ContactPair],
    found: &'a [PairCandidates],
    initial_gap: &[f64],
) -> Result<contact::sparse::Bodies<'a>, Error> {
    let bodies = models
        .iter()
        .map(|m| contact::sparse::BodyParts {
            matrix: &m.system.matrix,
            rhs: &m.system.rhs,
            factorisation: &m.factorisation,
            operator: &EMPTY_OPERATOR,
            points: super::node_points(m),
        })
        .collect();
    let parts = pairs
        .iter()
        .zip(found)
        .map(|(pair, f)| contact::sparse::PairParts {
            body: pair.body,
            operator: &f.candidates.operator,
            target: pair.target_body.zip(f.target.as_ref()),
            scale: models[pair.body].system.collocation_scale,
        })
        .collect();
    Ok(contact::sparse::Bodies::new(bodies, parts, initial_gap).map_err(lcp::LcpError::from)?)
}

/// The operator [`contact::sparse::BodyParts::operator`] holds for [`contact::sparse::Bodies::new`],
/// which reads the pairs' operators instead.
static EMPTY_OPERATOR: std::sync::LazyLock<BodyOperator> = std::sync::LazyLock::new(|| {
    BodyOperator { shapes: ShapeSet::from_rows(&[]), owners: Vec::new(), directions: Vec::new() }
});

/// The candidates of `pair` (on its body) against its target body's edge or its obstacles.
fn pair_candidates(
    pair: &ContactPair,
    problems: &[&Problem],
    models: &[&Model],
) -> Result<PairCandidates, contact::ContactError> {
    let (problem, model) = (problems[pair.body], models[pair.body]);
    let spec = &pair.spec;
    match (spec.target, pair.target_body) {
        (ContactTarget::Body { edge }, Some(t)) => {
            let (candidates, op, paired, unpaired) = body_pair(
                problem,
                contact::Discretised::of(model),
                spec,
                (problems[t], contact::Discretised::of(models[t]), edge),
            )?;
            Ok(PairCandidates { candidates, target: Some(op), paired, unpaired })
        }
        (ContactTarget::Body { .. }, None) => Err(contact::ContactError::MissingTarget),
        (ContactTarget::Obstacles, _) if pair.obstacles.is_empty() => {
            Err(contact::ContactError::MissingTarget)
        }
        (ContactTarget::Obstacles, _) => {
            let target = |x| {
                contact::closest_obstacle(&pair.obstacles, x)
                    .map(|(_, c)| (c.gap, c.normal))
                    .expect("the pair has obstacles")
            };
            let candidates =
                contact::candidates_on(problem, model, spec.edge, &target, spec.condensation)?;
            Ok(PairCandidates { candidates, target: None, paired: Vec::new(), unpaired: 0 })
        }
        (ContactTarget::Rigid(line), _) => {
            let target = |x| (line.gap(x), line.normal);
            let candidates =
                contact::candidates_on(problem, model, spec.edge, &target, spec.condensation)?;
            Ok(PairCandidates { candidates, target: None, paired: Vec::new(), unpaired: 0 })
        }
    }
}

/// Body `b`'s operator over every candidate that touches it (of each pair `k`, `ops[k].0` on
/// the pairs on `b`, the target operator `ops[k].1` on the pairs against `b`), with the
/// candidates' global indices; `None` when no pair touches `b`. `ops` are the normal
/// operators, or the tangential ones (the same rows, so the same indices).
pub(super) fn body_operator(
    b: usize,
    pairs: &[ContactPair],
    ops: &[(&BodyOperator, Option<&BodyOperator>)],
    offsets: &[usize],
) -> Option<(BodyOperator, Vec<usize>)> {
    let mut rows: Vec<Vec<(u32, f64)>> = Vec::new();
    let mut owners = Vec::new();
    let mut directions = Vec::new();
    let mut index = Vec::new();
    for (k, (pair, &(own, target))) in pairs.iter().zip(ops).enumerate() {
        let own = (pair.body == b).then_some(own);
        let target = target.filter(|_| pair.target_body == Some(b));
        for op in own.into_iter().chain(target) {
            for c in 0..op.len() {
                let support = op.shapes.support(c);
                rows.push(support.iter().copied().zip(op.shapes.phi(c).iter().copied()).collect());
                owners.push(op.owners[c].clone());
                directions.push(op.directions[c]);
                index.push(offsets[k] + c);
            }
        }
    }
    (!index.is_empty())
        .then(|| (BodyOperator { shapes: ShapeSet::from_rows(&rows), owners, directions }, index))
}
