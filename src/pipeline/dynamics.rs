//! Elastodynamic runs (`[dynamics]`, docs/method.md §10): the body assembled without a
//! static factorisation (MFVM or finite elements), its contact candidates against the rigid
//! obstacles, the time stepping ([`crate::dynamics::simulate`]) and the outputs; or several
//! bodies in contact pairs with each other or with rigid obstacles (`solve_bodies`,
//! [`crate::dynamics::simulate_bodies`]).

use super::{MfvmParts, mfvm_parts};
use crate::assembly::{self, GlobalSystem};
use crate::contact::{self, BodyOperator, BodyView, Candidates, ContactTarget, rings};
use crate::dynamics::mass::Mass;
use crate::dynamics::{
    self, Body, BodyEnd, Contact, LoadHistory, ObstacleMotion, Simulation, StrainEnergy,
};
use crate::error::Error;
use crate::fem::{self, Mesh};
use crate::geometry::Point;
use crate::mls::ShapeSet;
use crate::nodes::Nodes;
use crate::post::{self, history::DynamicSummary};
use crate::problem::dynamics::{Dynamics, MassKind};
use crate::problem::{ContactPair as ScenePair, Method, Problem};
use crate::progress::{Clock, Progress, StageTiming};
use std::path::{Path, PathBuf};

/// The body of a dynamic run, assembled.
pub enum DynamicBody {
    /// MFVM: nodes, shapes, system and the cells.
    Mfvm(Box<MfvmParts>),
    /// Finite elements: the mesh, its nodes, the system and the identity `Φ`.
    Fem(Box<FemParts>),
}

/// The finite element body of a dynamic run, assembled, not factorised.
pub struct FemParts {
    /// The mesh.
    pub mesh: Mesh,
    /// Its nodes.
    pub nodes: Nodes,
    /// `K` (eliminated rows) and `f`.
    pub system: GlobalSystem,
    /// The identity as shape functions (`u^h(x_I) = u_I`).
    pub node_shapes: ShapeSet,
}

impl DynamicBody {
    /// The body as the contact stage reads it.
    pub fn discretised(&self) -> contact::Discretised<'_> {
        match self {
            Self::Mfvm(p) => {
                contact::Discretised::Mfvm { nodes: &p.nodes, system: &p.system, mfvm: &p.mfvm }
            }
            Self::Fem(p) => {
                contact::Discretised::Fem { nodes: &p.nodes, system: &p.system, mesh: &p.mesh }
            }
        }
    }

    /// The nodes.
    pub fn nodes(&self) -> &Nodes {
        match self {
            Self::Mfvm(p) => &p.nodes,
            Self::Fem(p) => &p.nodes,
        }
    }
}

/// A dynamic run, solved: the body, its candidates and the time history.
pub struct DynamicOutcome {
    /// The body (the first of several).
    pub body: DynamicBody,
    /// The candidates of one body against rigid obstacles (`None` without contact; with
    /// several bodies each pair's are in `bodies`).
    pub candidates: Option<Candidates>,
    /// The time stepping's result.
    pub simulation: Simulation,
    /// The checked parameters.
    pub dynamics: Dynamics,
    /// Stage timings.
    pub timings: Vec<crate::progress::StageTiming>,
    /// The other bodies, the contact pairs and each body's end (`None` for one body).
    pub bodies: Option<Box<BodiesOutcome>>,
}

/// The other bodies of a run of several (the first is [`DynamicOutcome::body`]), every contact
/// pair and each body's end.
pub struct BodiesOutcome {
    /// Bodies 1, 2, … ([`Problem::body`]'s numbering).
    pub others: Vec<DynamicBody>,
    /// Each contact pair (`[contact]`, or the `[[contact]]` tables in order).
    pub pairs: Vec<PairOutcome>,
    /// Each body's end, in body order.
    pub ends: Vec<BodyEnd>,
}

/// One contact pair of a run of several bodies.
pub struct PairOutcome {
    /// The body carrying the candidates.
    pub body: usize,
    /// The target body (`None`: rigid obstacles).
    pub target_body: Option<usize>,
    /// The candidates (on `body`).
    pub candidates: Candidates,
    /// The target's operator on the target body (`G₂`, `E₂`; `None` against obstacles).
    pub target: Option<BodyOperator>,
    /// The pair's first candidate among all pairs'.
    pub offset: usize,
}

impl DynamicOutcome {
    /// Number of nodes (of every body).
    pub fn nodes(&self) -> usize {
        self.body.nodes().len()
            + self.bodies.as_ref().map_or(0, |b| b.others.iter().map(|o| o.nodes().len()).sum())
    }
    /// Number of contact candidates (of every pair).
    pub fn candidates(&self) -> usize {
        match &self.bodies {
            Some(b) => b.pairs.iter().map(|p| p.candidates.len()).sum(),
            None => self.candidates.as_ref().map_or(0, Candidates::len),
        }
    }
    /// The nodes' positions (of the first body).
    pub fn points(&self) -> &[crate::geometry::Point] {
        &self.body.nodes().points
    }
    /// Every body, in body order.
    pub fn all_bodies(&self) -> impl Iterator<Item = &DynamicBody> {
        std::iter::once(&self.body).chain(self.bodies.iter().flat_map(|b| &b.others))
    }
}

/// What [`run`] wrote.
pub struct DynamicReport {
    /// The contents of `summary.json`.
    pub summary: DynamicSummary,
    /// Files written (`summary.json` last).
    pub files: Vec<PathBuf>,
}

impl std::fmt::Display for DynamicReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (s, g) = (&self.summary, &self.summary.figures);
        writeln!(f, "{}: {} nodes, {} time steps to t = {}", s.name, s.nodes, g.steps, g.end_time)?;
        writeln!(f, "  {}", g.contact.describe())?;
        writeln!(
            f,
            "  final velocity [{:.6}, {:.6}]; energy {:.6e} → {:.6e}, lost at contacts {:.6e}",
            g.final_velocity[0],
            g.final_velocity[1],
            g.initial_energy,
            g.final_energy,
            g.contact_loss
        )?;
        // Several pairs: each pair's contact and each body's final velocity.
        for (k, p) in s.pairs.iter().flatten().enumerate() {
            let target = p.target_body.as_deref().unwrap_or("obstacles");
            let (body, edge, figures) = (&p.body, &p.edge, p.figures.describe());
            writeln!(f, "  pair {k} ({body}.{edge} on {target}): {figures}")?;
        }
        for b in s.bodies.iter().flatten().filter(|_| s.pairs.is_some()) {
            let v = b.final_velocity;
            writeln!(f, "  body {}: final velocity [{:.6}, {:.6}]", b.name, v[0], v[1])?;
        }
        Ok(())
    }
}

/// The body of the dynamic `problem` assembled, not factorised (its rigid-body motions need
/// no displacement condition: inertia holds them).
///
/// # Errors
/// A stage's error.
pub fn discretise(problem: &Problem, clock: &mut Clock<'_>) -> Result<MfvmParts, Error> {
    mfvm_parts(problem, false, None, clock)
}

/// The finite element body of the dynamic `problem`, assembled, not factorised (inertia
/// holds its rigid-body motions).
///
/// # Errors
/// A stage's error.
pub fn discretise_fem(problem: &Problem, clock: &mut Clock<'_>) -> Result<FemParts, Error> {
    let (mesh, nodes) = clock.run("mesh", || fem::mesh(problem))?;
    let d = problem.material.constitutive();
    let system = clock.run("assembly", || {
        fem::system::assemble(&fem::system::FemInput {
            body: assembly::Body::new(problem, &nodes, &d),
            mesh: &mesh,
        })
    })?;
    let ids: Vec<u32> = (0..nodes.len() as u32).collect();
    Ok(FemParts { node_shapes: ShapeSet::nodal(&ids), mesh, nodes, system })
}

/// Solves the dynamic `problem` (its `dynamics` must be `Some`).
///
/// # Errors
/// Any stage's error.
pub fn solve(problem: &Problem, progress: &mut dyn Progress) -> Result<DynamicOutcome, Error> {
    let dynamics =
        problem.dynamics.clone().ok_or_else(|| crate::problem::ProblemError::Invalid {
            field: "dynamics".into(),
            value: "(missing)".into(),
            reason: "a dynamic run needs a [dynamics] table".into(),
        })?;
    let mut clock = Clock::new(progress, Vec::new());
    let body = discretise_any(problem, &mut clock)?;
    if problem.body_count() > 1 || problem.is_scene_of_pairs() {
        return solve_bodies(problem, body, dynamics, clock);
    }
    let candidates = match problem.contact() {
        Some(spec) => Some(clock.run("candidates", || {
            let target =
                |x| contact::rigid_target(problem, spec, x).unwrap_or((f64::INFINITY, [0.0, 1.0]));
            let mut found = match &body {
                DynamicBody::Mfvm(parts) => {
                    let view = BodyView {
                        domain: &problem.domain,
                        nodes: &parts.nodes,
                        supports: &parts.mfvm.supports,
                        mls: &problem.discretisation.mls,
                        boundary_faces: &parts.mfvm.faces.boundary,
                        system: &parts.system,
                    };
                    contact::candidates(view, spec.edge, &target, spec.condensation)
                }
                DynamicBody::Fem(p) => contact::fem::candidates(
                    &p.mesh,
                    &problem.domain,
                    &p.nodes,
                    &p.system,
                    spec.edge,
                    &target,
                ),
            }?;
            if problem.material.is_axisymmetric() {
                let area = ring_areas(problem, &body, spec.edge, &found);
                rings::into_rings(&mut found, area);
            }
            Ok::<_, contact::ContactError>(found)
        })?),
        None => None,
    };
    let history = load_history(problem, &body)?;
    let stepped = stepped_body(problem, &body, dynamics.density, history);
    // Coulomb friction: the tangential operator (a candidate whose owner is held along `t`
    // is frictionless, as in the static solve).
    let mu = problem.contact().map_or(0.0, |c| c.friction);
    let system = stepped.system;
    let in_time = friction_steps(problem, dynamics.time_step);
    let frictional = mu > 0.0 || in_time.iter().any(|s| s.1.is_some_and(|m| m > 0.0));
    let tangential =
        candidates.as_ref().filter(|_| frictional).map(|c| c.tangential_operator(system));
    let contact = candidates.as_ref().map(|c| Contact {
        operator: &c.operator,
        initial_gap: &c.initial_gap,
        friction: tangential.as_ref().map(|(operator, free)| dynamics::Friction {
            terms: vec![dynamics::Term { body: 0, offset: 0, operator }],
            coefficients: free.iter().map(|&f| if f { mu } else { 0.0 }).collect(),
            schedule: in_time
                .iter()
                .map(|&(n, m)| {
                    let mu = m.unwrap_or(mu);
                    (n, free.iter().map(|&f| if f { mu } else { 0.0 }).collect())
                })
                .collect(),
        }),
        obstacle: obstacle_motion(problem, c.normals.iter().map(|&n| Some(n)).collect()),
    });
    let simulation = clock.run_counted("time steps", |advance| {
        dynamics::simulate(&stepped, contact, &dynamics, advance)
    })?;
    // The shares of the stage: the set-up (M̂'s LU and W) and the steps' LCPs.
    let s = simulation.seconds;
    clock.timings.push(StageTiming { stage: "time steps: M̂ and W set-up", seconds: s.setup });
    clock.timings.push(StageTiming { stage: "time steps: LCPs", seconds: s.lcp });
    Ok(DynamicOutcome {
        candidates,
        simulation,
        dynamics,
        timings: clock.timings,
        body,
        bodies: None,
    })
}

/// `problem`'s body assembled by its method, not factorised.
fn discretise_any(problem: &Problem, clock: &mut Clock<'_>) -> Result<DynamicBody, Error> {
    Ok(match problem.discretisation.method {
        Method::Fem => DynamicBody::Fem(Box::new(discretise_fem(problem, clock)?)),
        Method::Mfvm => DynamicBody::Mfvm(Box::new(discretise(problem, clock)?)),
    })
}

/// The contact pairs of `problem`'s bodies (its `[contact]` table, or every `[[contact]]`
/// table in order).
///
/// # Errors
/// [`contact::ContactError::MissingTarget`] when the bodies have no contact pair.
fn scene_pairs(problem: &Problem) -> Result<&[ScenePair], contact::ContactError> {
    let pairs = problem.pairs();
    if pairs.is_empty() {
        return Err(contact::ContactError::MissingTarget);
    }
    Ok(pairs)
}

/// `pair`'s candidates and, against a body, the target's operator: between bodies the static
/// pair's candidates, normals, gaps and target operator ([`super::multibody::body_pair`]:
/// straight or curved targets), against rigid obstacles the one body's candidates.
fn pair_candidates(
    pair: &ScenePair,
    problems: &[&Problem],
    bodies: &[&DynamicBody],
) -> Result<(Candidates, Option<BodyOperator>), contact::ContactError> {
    let (problem, view, spec) = (problems[pair.body], bodies[pair.body].discretised(), &pair.spec);
    let rigid = |target: &dyn Fn(Point) -> (f64, Point)| {
        contact::candidates_in(problem, view, spec.edge, target, spec.condensation)
    };
    match (spec.target, pair.target_body) {
        (ContactTarget::Body { edge }, Some(t)) => {
            let target = (problems[t], bodies[t].discretised(), edge);
            let (candidates, op, _, _) = super::multibody::body_pair(problem, view, spec, target)?;
            Ok((candidates, Some(op)))
        }
        (ContactTarget::Body { .. }, None) => Err(contact::ContactError::MissingTarget),
        (ContactTarget::Obstacles, _) if pair.obstacles.is_empty() => {
            Err(contact::ContactError::MissingTarget)
        }
        (ContactTarget::Obstacles, _) => Ok((
            rigid(&|x| {
                contact::closest_obstacle(&pair.obstacles, x)
                    .map_or((f64::INFINITY, [0.0, 1.0]), |(_, c)| (c.gap, c.normal))
            })?,
            None,
        )),
        (ContactTarget::Rigid(line), _) => Ok((rigid(&|x| (line.gap(x), line.normal))?, None)),
    }
}

/// Several bodies in contact (increment 10 of docs/dev/dynamics.md): every body assembled,
/// each pair's candidates ([`pair_candidates`]) numbered pair after pair, the pairs' terms on
/// their bodies at their offsets, with Coulomb friction the tangential operators of the
/// static friction (a target's along `−t`), and the time stepping of all bodies at once
/// ([`dynamics::simulate_bodies`]).
fn solve_bodies(
    problem: &Problem,
    body: DynamicBody,
    dynamics: Dynamics,
    mut clock: Clock<'_>,
) -> Result<DynamicOutcome, Error> {
    let problems: Vec<&Problem> =
        (0..problem.body_count()).filter_map(|k| problem.body(k)).collect();
    let mut others = Vec::with_capacity(problems.len() - 1);
    for p in &problems[1..] {
        others.push(discretise_any(p, &mut clock)?);
    }
    let all: Vec<&DynamicBody> = std::iter::once(&body).chain(&others).collect();
    let scene = scene_pairs(problem)?;
    let found = clock.run("candidates", || {
        scene
            .iter()
            .map(|pair| pair_candidates(pair, &problems, &all))
            .collect::<Result<Vec<_>, _>>()
    })?;
    let mut offsets = Vec::with_capacity(found.len());
    let mut next = 0;
    for (c, _) in &found {
        offsets.push(next);
        next += c.len();
    }
    let motions: Vec<(f64, [f64; 2])> =
        std::iter::once((dynamics.density, dynamics.initial_velocity))
            .chain(dynamics.others.iter().map(|m| (m.density, m.initial_velocity)))
            .collect();
    if motions.len() != problems.len() {
        return Err(crate::problem::ProblemError::Invalid {
            field: "dynamics".into(),
            value: format!("{} motions for {} bodies", motions.len(), problems.len()),
            reason:
                "each body needs its density and initial velocity (problem::dynamics builds them)"
                    .into(),
        }
        .into());
    }
    let histories = problems
        .iter()
        .zip(&all)
        .map(|(p, b)| load_history(p, b))
        .collect::<Result<Vec<_>, _>>()?;
    let stepped: Vec<Body<'_>> = problems
        .iter()
        .zip(&all)
        .zip(&motions)
        .zip(histories)
        .map(|(((p, b), &(density, _)), history)| stepped_body(p, b, density, history))
        .collect();
    let mut normal = Vec::new();
    for ((pair, (c, target)), &offset) in scene.iter().zip(&found).zip(&offsets) {
        normal.push(dynamics::Term { body: pair.body, offset, operator: &c.operator });
        if let (Some(t), Some(op)) = (pair.target_body, target) {
            normal.push(dynamics::Term { body: t, offset, operator: op });
        }
    }
    // Coulomb friction: every pair's tangential operators when any pair has friction (a
    // frictionless pair's candidates get μ = 0).
    let in_time = friction_steps(problem, dynamics.time_step);
    let frictional = scene.iter().any(|p| p.spec.friction > 0.0)
        || in_time.iter().any(|s| s.1.is_some_and(|m| m > 0.0));
    let tangential: Option<Vec<_>> = frictional.then(|| {
        scene
            .iter()
            .zip(&found)
            .map(|(pair, (c, target))| {
                let on_target =
                    pair.target_body.zip(target.as_ref()).map(|(t, op)| (stepped[t].system, op));
                super::friction::tangential_operators_of(c, stepped[pair.body].system, on_target)
            })
            .collect()
    });
    let friction = tangential.as_ref().map(|tangential| {
        let mut terms = Vec::new();
        let mut coefficients = Vec::new();
        let mut schedule: Vec<(usize, Vec<f64>)> =
            in_time.iter().map(|&(n, _)| (n, Vec::new())).collect();
        for ((pair, (t1, free, t2)), &offset) in scene.iter().zip(tangential).zip(&offsets) {
            terms.push(dynamics::Term { body: pair.body, offset, operator: t1 });
            if let (Some(t), Some(op)) = (pair.target_body, t2) {
                terms.push(dynamics::Term { body: t, offset, operator: op });
            }
            let mu = pair.spec.friction;
            coefficients.extend(free.iter().map(|&f| if f { mu } else { 0.0 }));
            for ((_, own), (_, step)) in in_time.iter().zip(&mut schedule) {
                let mu = own.unwrap_or(mu);
                step.extend(free.iter().map(|&f| if f { mu } else { 0.0 }));
            }
        }
        dynamics::Friction { terms, coefficients, schedule }
    });
    // A step's obstacle motion moves the pairs against rigid obstacles together.
    let moved = scene.iter().zip(&found).flat_map(|(pair, (c, _))| {
        c.normals.iter().map(move |&n| pair.target_body.is_none().then_some(n))
    });
    let contacts = dynamics::Contacts {
        normal,
        initial_gap: found.iter().flat_map(|(c, _)| c.initial_gap.iter().copied()).collect(),
        friction,
        pair_starts: offsets.clone(),
        obstacle: obstacle_motion(problem, moved.collect()),
    };
    let velocities: Vec<[f64; 2]> = motions.iter().map(|m| m.1).collect();
    let refs: Vec<&Body<'_>> = stepped.iter().collect();
    let run = clock.run_counted("time steps", |advance| {
        dynamics::simulate_bodies(&refs, contacts, &dynamics, &velocities, advance)
    })?;
    let s = run.simulation.seconds;
    clock.timings.push(StageTiming { stage: "time steps: M̂ and W set-up", seconds: s.setup });
    clock.timings.push(StageTiming { stage: "time steps: LCPs", seconds: s.lcp });
    drop(refs);
    drop(stepped);
    drop(tangential);
    drop(all);
    let pairs = scene
        .iter()
        .zip(found)
        .zip(offsets)
        .map(|((pair, (candidates, target)), offset)| PairOutcome {
            body: pair.body,
            target_body: pair.target_body,
            candidates,
            target,
            offset,
        })
        .collect();
    Ok(DynamicOutcome {
        candidates: None,
        simulation: run.simulation,
        dynamics,
        timings: clock.timings,
        body,
        bodies: Some(Box::new(BodiesOutcome { others, pairs, ends: run.bodies })),
    })
}

/// The ring areas of the axisymmetric `body`'s candidates `found` on `edge`.
fn ring_areas(problem: &Problem, body: &DynamicBody, edge: usize, found: &Candidates) -> Vec<f64> {
    match body {
        DynamicBody::Mfvm(p) => rings::mfvm_areas(&p.mfvm.faces.boundary, edge, &found.nodes),
        DynamicBody::Fem(p) => {
            rings::fem_areas(&p.mesh, &problem.domain, &p.nodes, edge, &found.nodes)
        }
    }
}

/// The loads and prescribed displacements of `problem`'s `[[step]]` tables in time (`None`
/// without steps): the unloaded conditions at time 0 and each step's at its time, assembled
/// on `body` (the same prescribed DOFs, so the same `K`; only `f` and the prescribed values
/// change, as in the static load steps).
///
/// # Errors
/// The assembly's error.
fn load_history(problem: &Problem, body: &DynamicBody) -> Result<Option<LoadHistory>, Error> {
    if problem.steps.is_empty() {
        return Ok(None);
    }
    let d = problem.material.constitutive();
    let system = match body {
        DynamicBody::Mfvm(p) => &p.system,
        DynamicBody::Fem(p) => &p.system,
    };
    let mut states = vec![(0.0, system.load.clone(), system.rhs.clone())];
    for step in &problem.steps {
        let time = step.time.ok_or_else(|| crate::problem::ProblemError::Invalid {
            field: "step.time".into(),
            value: "(missing)".into(),
            reason: "with [dynamics] each step needs its time".into(),
        })?;
        let (load, rhs) = match body {
            DynamicBody::Mfvm(p) => {
                let mut input = assembly::Body::new(problem, &p.nodes, &d);
                input.boundary = &step.boundary;
                assembly::load_and_rhs(&assembly::AssemblyInput {
                    body: input,
                    cells: &p.mfvm.cells,
                    interior_faces: &p.mfvm.faces.interior,
                    boundary_faces: &p.mfvm.faces.boundary,
                    face_quadrature: &p.mfvm.face_quadrature,
                    face_shapes: &p.mfvm.face_shapes,
                    node_shapes: &p.node_shapes,
                    beta: problem.discretisation.beta,
                    // Loads only: the hoop terms are in the matrix; the loads weigh by r
                    // through `Body::hoop` in axisymmetry.
                    axisymmetric: None,
                })?
            }
            DynamicBody::Fem(p) => {
                let mut input = assembly::Body::new(problem, &p.nodes, &d);
                input.boundary = &step.boundary;
                fem::system::load_and_rhs(
                    &fem::system::FemInput { body: input, mesh: &p.mesh },
                    &p.system.interior_stiffness,
                )
            }
        };
        states.push((time, load, rhs));
    }
    Ok(Some(LoadHistory::new(states)))
}

/// Each `[[step]]`'s friction in time (docs/method.md §10.6; empty when no step sets one): the
/// last time step it holds in, `n_k` (a step's coefficient holds during it, `(t_{k−1}, t_k]`:
/// time step `n`, whose middle is `(n − ½) h`, is step `k`'s when `(n − ½) h ≤ t_k`, so
/// `n_k = ⌊t_k / h + ½⌋`), and its own coefficient (`None`: each pair's own).
fn friction_steps(problem: &Problem, h: f64) -> Vec<(usize, Option<f64>)> {
    if !problem.steps.iter().any(|s| s.friction_set) {
        return Vec::new();
    }
    let last = |t: f64| (t / h + 0.5).floor() as usize;
    problem
        .steps
        .iter()
        .map(|s| (last(s.time.unwrap_or(0.0)), s.friction_set.then_some(s.friction)))
        .collect()
}

/// The rigid obstacles' motion in `problem`'s `[[step]]` tables (`obstacle_displacement`
/// at each step's `time`, docs/method.md §10.6) for the candidates with normals `normals`
/// (`None`: a candidate it does not move); `None` when no step moves the obstacles.
fn obstacle_motion(problem: &Problem, normals: Vec<Option<Point>>) -> Option<ObstacleMotion> {
    let steps = &problem.steps;
    if steps.iter().all(|s| s.obstacle_displacement == [0.0, 0.0]) {
        return None;
    }
    let states: Option<Vec<(f64, [f64; 2])>> = std::iter::once(Some((0.0, [0.0, 0.0])))
        .chain(steps.iter().map(|s| s.time.map(|t| (t, s.obstacle_displacement))))
        .collect();
    states.map(|states| ObstacleMotion::new(states, normals))
}

/// What the time stepping needs of `body`: its system, `Φ`, the mass (MFVM: `ρ |Ω_I|`
/// on the nodal values; FE: HRZ, or the consistent mass with `[dynamics] mass =
/// "consistent"`; axisymmetric: per radian, `ρ r dA`), its strain energy
/// (the MFVM's collocated strains have no hoop term, so an axisymmetric MFVM body measures
/// `½ uᵀ K u` as the FE does) and its loads' `history` in time.
fn stepped_body<'a>(
    problem: &Problem,
    body: &'a DynamicBody,
    density: f64,
    history: Option<LoadHistory>,
) -> Body<'a> {
    let axisymmetric = problem.material.is_axisymmetric();
    match body {
        DynamicBody::Mfvm(parts) => {
            let cells = &parts.mfvm.cells;
            Body {
                system: &parts.system,
                node_shapes: &parts.node_shapes,
                points: &parts.nodes.points,
                mass: Mass::Lumped(match axisymmetric {
                    true => dynamics::mass::lumped_mass_per_radian(cells, density),
                    false => dynamics::mass::lumped_mass(cells, density),
                }),
                strain: match axisymmetric {
                    true => StrainEnergy::Quadratic(&parts.system.interior_stiffness),
                    false => StrainEnergy::Collocated {
                        cells,
                        constitutive: problem.material.constitutive(),
                    },
                },
                history,
            }
        }
        DynamicBody::Fem(p) => {
            let hrz = fem::mass::Lumping::Hrz;
            let consistent =
                problem.dynamics.as_ref().is_some_and(|d| d.mass == MassKind::Consistent);
            let mass = match (consistent, axisymmetric) {
                (true, per_radian) => {
                    Mass::Consistent(fem::mass::consistent_mass(&p.mesh, density, per_radian))
                }
                (false, true) => {
                    Mass::Lumped(lumped(fem::mass::lumped_mass_per_radian(&p.mesh, density, hrz)))
                }
                (false, false) => {
                    Mass::Lumped(lumped(fem::mass::lumped_mass(&p.mesh, density, hrz)))
                }
            };
            Body {
                system: &p.system,
                node_shapes: &p.node_shapes,
                points: &p.nodes.points,
                mass,
                strain: StrainEnergy::Quadratic(&p.system.interior_stiffness),
                history,
            }
        }
    }
}

/// The nodal masses on both DOFs of each node (interleaved).
fn lumped(nodal: Vec<f64>) -> Vec<f64> {
    nodal.into_iter().flat_map(|m| [m, m]).collect()
}

/// Solves the dynamic `problem` and writes its outputs to `out` (`input`: the problem file
/// as read, echoed into `summary.json`).
///
/// # Errors
/// Any stage's error.
pub fn run(
    problem: &Problem,
    out: &Path,
    input: serde_json::Value,
    progress: &mut dyn Progress,
) -> Result<DynamicReport, Error> {
    let staged = post::StagedDir::new(out)?;
    let outcome = solve(problem, progress)?;
    let h = outcome.dynamics.time_step;
    let figures = outcome.simulation.figures(h);
    let summary = DynamicSummary {
        schema_version: post::summary::SCHEMA_VERSION,
        checks: post::history::DynamicChecks::of(&figures),
        warnings: post::history::warnings(&figures, outcome.dynamics.theta),
        name: problem.name.clone(),
        nodes: outcome.nodes(),
        candidates: outcome.candidates(),
        dynamics: (&outcome.dynamics).into(),
        figures,
        input,
        timings: outcome.timings.iter().map(|t| (t.stage, t.seconds)).collect(),
        bodies: outcome.bodies.as_ref().map(|b| body_summaries(problem, &outcome, b)),
        pairs: outcome
            .bodies
            .as_ref()
            .filter(|b| b.pairs.len() > 1)
            .map(|b| pair_summaries(problem, &outcome, b)),
    };
    let names: Vec<String> =
        (0..problem.body_count()).filter_map(|k| problem.body(k)).map(|p| p.name.clone()).collect();
    let bodies: Vec<(&str, &[Point])> = names
        .iter()
        .zip(outcome.all_bodies())
        .map(|(name, body)| (name.as_str(), body.nodes().points.as_slice()))
        .collect();
    let mut files = post::frames::write_frames(staged.path(), &bodies, &outcome.simulation.frames)?;
    files.extend(post::history::write_dynamic(
        staged.path(),
        &outcome.simulation.history,
        &summary,
    )?);
    let files = staged.commit(files)?;
    Ok(DynamicReport { summary, files })
}

/// Each body of a run of several for `summary.json`.
fn body_summaries(
    problem: &Problem,
    outcome: &DynamicOutcome,
    several: &BodiesOutcome,
) -> Vec<post::history::BodyFigures> {
    let d = &outcome.dynamics;
    let motions = std::iter::once((d.density, d.initial_velocity))
        .chain(d.others.iter().map(|m| (m.density, m.initial_velocity)));
    let bodies = std::iter::once(&outcome.body).chain(&several.others);
    (0..problem.body_count())
        .filter_map(|k| problem.body(k))
        .zip(bodies)
        .zip(motions)
        .zip(&several.ends)
        .map(|(((p, body), (density, initial_velocity)), end)| post::history::BodyFigures {
            name: p.name.clone(),
            nodes: body.nodes().len(),
            density,
            mass: end.mass,
            initial_velocity,
            final_velocity: end.mean_velocity(),
        })
        .collect()
}

/// Each contact pair of a run with several for `summary.json`.
fn pair_summaries(
    problem: &Problem,
    outcome: &DynamicOutcome,
    several: &BodiesOutcome,
) -> Vec<post::history::PairHistory> {
    let name = |k: usize| problem.body(k).map_or_else(String::new, |p| p.name.clone());
    let edge = |pair: &ScenePair| {
        let body = problem.body(pair.body).unwrap_or(problem);
        body.domain.edge_names().get(pair.spec.edge).map_or_else(String::new, |e| e.to_string())
    };
    let figures = outcome.simulation.history.pair_figures(outcome.dynamics.time_step);
    several
        .pairs
        .iter()
        .zip(problem.pairs())
        .zip(figures)
        .map(|((pair, stated), figures)| post::history::PairHistory {
            body: name(pair.body),
            edge: edge(stated),
            target_body: pair.target_body.map(name),
            candidates: pair.candidates.len(),
            figures,
        })
        .collect()
}
