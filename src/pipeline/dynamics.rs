//! Elastodynamic runs (`[dynamics]`, docs/method.md §10): the body assembled without a
//! static factorisation (MFVM or finite elements), its contact candidates against the rigid
//! obstacles, the time stepping ([`crate::dynamics::simulate`]) and the outputs.

use super::{MfvmParts, mfvm_parts};
use crate::assembly::{self, GlobalSystem};
use crate::contact::{self, BodyOperator, BodyView, Candidates, rings};
use crate::dynamics::{self, Body, BodyEnd, Contact, Simulation, StrainEnergy};
use crate::error::Error;
use crate::fem::{self, Mesh};
use crate::mls::ShapeSet;
use crate::nodes::Nodes;
use crate::post::{self, history::DynamicSummary};
use crate::problem::Method;
use crate::problem::{Problem, dynamics::Dynamics};
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
    /// The body.
    pub body: DynamicBody,
    /// The candidates (`None` without contact).
    pub candidates: Option<Candidates>,
    /// The time stepping's result.
    pub simulation: Simulation,
    /// The checked parameters.
    pub dynamics: Dynamics,
    /// Stage timings.
    pub timings: Vec<crate::progress::StageTiming>,
    /// The second body of a two-body contact and each body's end (`None` for one body).
    pub pair: Option<Box<PairOutcome>>,
}

/// The second body of a two-body run (the candidates are on the first) and both bodies' ends.
pub struct PairOutcome {
    /// The second body.
    pub body: DynamicBody,
    /// The target's operator on it (`G₂`, `E₂`).
    pub target: BodyOperator,
    /// Body 1 and body 2 at the end.
    pub ends: [BodyEnd; 2],
}

impl DynamicOutcome {
    /// Number of nodes (of both bodies of a pair).
    pub fn nodes(&self) -> usize {
        self.body.nodes().len() + self.pair.as_ref().map_or(0, |p| p.body.nodes().len())
    }
    /// The nodes' positions.
    pub fn points(&self) -> &[crate::geometry::Point] {
        &self.body.nodes().points
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
        let opt = |v: Option<f64>| v.map_or_else(|| "–".to_string(), |v| format!("{v:.6}"));
        writeln!(f, "{}: {} nodes, {} time steps to t = {}", s.name, s.nodes, g.steps, g.end_time)?;
        writeln!(
            f,
            "  contact from {} to {} (duration {}), mean force {}, peak {:.6}",
            opt(g.contact_start),
            opt(g.contact_end),
            opt(g.contact_duration),
            opt(g.mean_contact_force),
            g.peak_contact_force
        )?;
        writeln!(
            f,
            "  final velocity [{:.6}, {:.6}]; energy {:.6e} → {:.6e}, lost at contacts {:.6e}",
            g.final_velocity[0],
            g.final_velocity[1],
            g.initial_energy,
            g.final_energy,
            g.contact_loss
        )
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
    if let Some(p2) = &problem.second_body {
        return solve_pair(problem, p2, body, dynamics, clock);
    }
    let candidates = match &problem.contact {
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
    let stepped = stepped_body(problem, &body, dynamics.density);
    // Coulomb friction: the tangential operator (a candidate whose owner is held along `t`
    // is frictionless, as in the static solve).
    let mu = problem.contact.as_ref().map_or(0.0, |c| c.friction);
    let system = stepped.system;
    let tangential =
        candidates.as_ref().filter(|_| mu > 0.0).map(|c| c.tangential_operator(system));
    let contact = candidates.as_ref().map(|c| Contact {
        operator: &c.operator,
        initial_gap: &c.initial_gap,
        friction: tangential.as_ref().map(|(operator, free)| dynamics::Friction {
            terms: vec![dynamics::Term { body: 0, offset: 0, operator }],
            coefficients: free.iter().map(|&f| if f { mu } else { 0.0 }).collect(),
        }),
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
        pair: None,
    })
}

/// `problem`'s body assembled by its method, not factorised.
fn discretise_any(problem: &Problem, clock: &mut Clock<'_>) -> Result<DynamicBody, Error> {
    Ok(match problem.discretisation.method {
        Method::Fem => DynamicBody::Fem(Box::new(discretise_fem(problem, clock)?)),
        Method::Mfvm => DynamicBody::Mfvm(Box::new(discretise(problem, clock)?)),
    })
}

/// Two bodies in contact (increment 10 of docs/dev/dynamics.md): the second body assembled,
/// the pair's candidates, normals, gaps and target operator of the static pair
/// ([`super::multibody::body_pair`]: straight or curved targets), with Coulomb friction the
/// tangential operators of the static friction (the target's along `−t`), and the two-body
/// time stepping ([`dynamics::simulate_bodies`]).
fn solve_pair(
    problem: &Problem,
    p2: &Problem,
    body: DynamicBody,
    dynamics: Dynamics,
    mut clock: Clock<'_>,
) -> Result<DynamicOutcome, Error> {
    let second = discretise_any(p2, &mut clock)?;
    let spec = problem.contact.as_ref().ok_or(contact::ContactError::MissingTarget)?;
    let contact::ContactTarget::Body { edge } = spec.target else {
        return Err(contact::ContactError::MissingTarget.into());
    };
    let (candidates, target, _, _) = clock.run("candidates", || {
        super::multibody::body_pair(
            problem,
            body.discretised(),
            spec,
            (p2, second.discretised(), edge),
        )
    })?;
    let motion = dynamics.second_body.ok_or(contact::ContactError::MissingTarget)?;
    let stepped =
        [stepped_body(problem, &body, dynamics.density), stepped_body(p2, &second, motion.density)];
    let mu = spec.friction;
    let tangential = (mu > 0.0).then(|| {
        let systems = (stepped[0].system, stepped[1].system);
        super::friction::tangential_operators_of(&candidates, systems.0, Some((systems.1, &target)))
    });
    let pair = dynamics::PairContact {
        operator: &candidates.operator,
        target: &target,
        initial_gap: &candidates.initial_gap,
        friction: tangential.as_ref().map(|(t1, free, t2)| {
            // Given a target, the tangential operators include the target's (along −t).
            let t2 = t2.as_ref().unwrap_or_else(|| unreachable!("the target's tangential term"));
            let terms = vec![
                dynamics::Term { body: 0, offset: 0, operator: t1 },
                dynamics::Term { body: 1, offset: 0, operator: t2 },
            ];
            let coefficients = free.iter().map(|&f| if f { mu } else { 0.0 }).collect();
            dynamics::Friction { terms, coefficients }
        }),
    };
    let velocities = [dynamics.initial_velocity, motion.initial_velocity];
    let run = clock.run_counted("time steps", |advance| {
        dynamics::simulate_bodies([&stepped[0], &stepped[1]], &pair, &dynamics, velocities, advance)
    })?;
    let s = run.simulation.seconds;
    clock.timings.push(StageTiming { stage: "time steps: M̂ and W set-up", seconds: s.setup });
    clock.timings.push(StageTiming { stage: "time steps: LCPs", seconds: s.lcp });
    drop(stepped);
    Ok(DynamicOutcome {
        candidates: Some(candidates),
        simulation: run.simulation,
        dynamics,
        timings: clock.timings,
        body,
        pair: Some(Box::new(PairOutcome { body: second, target, ends: run.bodies })),
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

/// What the time stepping needs of `body`: its system, `Φ`, the lumped mass (MFVM: `ρ |Ω_I|`
/// on the nodal values; FE: HRZ; axisymmetric: per radian, `ρ r dA`) and its strain energy
/// (the MFVM's collocated strains have no hoop term, so an axisymmetric MFVM body measures
/// `½ uᵀ K u` as the FE does).
fn stepped_body<'a>(problem: &Problem, body: &'a DynamicBody, density: f64) -> Body<'a> {
    let axisymmetric = problem.material.is_axisymmetric();
    match body {
        DynamicBody::Mfvm(parts) => {
            let cells = &parts.mfvm.cells;
            Body {
                system: &parts.system,
                node_shapes: &parts.node_shapes,
                points: &parts.nodes.points,
                mass: match axisymmetric {
                    true => dynamics::mass::lumped_mass_per_radian(cells, density),
                    false => dynamics::mass::lumped_mass(cells, density),
                },
                strain: match axisymmetric {
                    true => StrainEnergy::Quadratic(&parts.system.interior_stiffness),
                    false => StrainEnergy::Collocated {
                        cells,
                        constitutive: problem.material.constitutive(),
                    },
                },
            }
        }
        DynamicBody::Fem(p) => {
            let hrz = fem::mass::Lumping::Hrz;
            let nodal = match axisymmetric {
                true => fem::mass::lumped_mass_per_radian(&p.mesh, density, hrz),
                false => fem::mass::lumped_mass(&p.mesh, density, hrz),
            };
            Body {
                system: &p.system,
                node_shapes: &p.node_shapes,
                points: &p.nodes.points,
                mass: nodal.into_iter().flat_map(|m| [m, m]).collect(),
                strain: StrainEnergy::Quadratic(&p.system.interior_stiffness),
            }
        }
    }
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
        candidates: outcome.candidates.as_ref().map_or(0, Candidates::len),
        dynamics: (&outcome.dynamics).into(),
        figures,
        input,
        timings: outcome.timings.iter().map(|t| (t.stage, t.seconds)).collect(),
        bodies: outcome.pair.as_ref().map(|pair| body_summaries(problem, &outcome, pair)),
    };
    let mut files =
        post::frames::write_frames(staged.path(), outcome.points(), &outcome.simulation.frames)?;
    files.extend(post::history::write_dynamic(
        staged.path(),
        &outcome.simulation.history,
        &summary,
    )?);
    let files = staged.commit(files)?;
    Ok(DynamicReport { summary, files })
}

/// Each body of a two-body run for `summary.json`.
fn body_summaries(
    problem: &Problem,
    outcome: &DynamicOutcome,
    pair: &PairOutcome,
) -> Vec<post::history::BodyFigures> {
    let d = &outcome.dynamics;
    let motion = d.second_body.map_or((d.density, [0.0; 2]), |m| (m.density, m.initial_velocity));
    let bodies = [
        (problem, &outcome.body, (d.density, d.initial_velocity)),
        (problem.second_body.as_deref().unwrap_or(problem), &pair.body, motion),
    ];
    bodies
        .into_iter()
        .zip(&pair.ends)
        .map(|((p, body, (density, initial_velocity)), end)| post::history::BodyFigures {
            name: p.name.clone(),
            nodes: body.nodes().len(),
            density,
            mass: end.mass,
            initial_velocity,
            final_velocity: end.mean_velocity(),
        })
        .collect()
}
