//! Elastodynamic runs (`[dynamics]`, docs/method.md §10): the body assembled without a
//! static factorisation (MFVM or finite elements), its contact candidates against the rigid
//! obstacles, the time stepping ([`crate::dynamics::simulate`]) and the outputs.

use super::{MfvmParts, mfvm_parts};
use crate::assembly::{self, GlobalSystem};
use crate::contact::{self, BodyView, Candidates, rings};
use crate::dynamics::{self, Body, Contact, Simulation, StrainEnergy};
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
}

impl DynamicOutcome {
    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.body.nodes().len()
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
    let body = match problem.discretisation.method {
        Method::Fem => DynamicBody::Fem(Box::new(discretise_fem(problem, &mut clock)?)),
        Method::Mfvm => DynamicBody::Mfvm(Box::new(discretise(problem, &mut clock)?)),
    };
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
            operator,
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
    Ok(DynamicOutcome { candidates, simulation, dynamics, timings: clock.timings, body })
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
        warnings: post::history::warnings(&figures, outcome.dynamics.theta),
        name: problem.name.clone(),
        nodes: outcome.nodes(),
        candidates: outcome.candidates.as_ref().map_or(0, Candidates::len),
        dynamics: (&outcome.dynamics).into(),
        figures,
        input,
        timings: outcome.timings.iter().map(|t| (t.stage, t.seconds)).collect(),
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
