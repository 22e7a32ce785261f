//! The checked `[dynamics]` table (docs/method.md §10): the time stepping's parameters, the
//! density, the initial velocity, and the refusals of what the first dynamic increment does
//! not support (docs/dev/dynamics.md).

use super::file::StepFile;
use super::{ContactSolver, Precision, Problem, ProblemError, ProblemFile, invalid};

/// Most time steps a run may take.
pub const MAX_STEPS: usize = 10_000_000;

/// Elastodynamics of one body by Moreau–Jean time stepping (docs/method.md §10).
#[derive(Clone, Debug, PartialEq)]
pub struct Dynamics {
    /// Mass density `ρ` (`[material] density`).
    pub density: f64,
    /// End time `T` (the run starts at 0).
    pub end_time: f64,
    /// Fixed time step `h`.
    pub time_step: f64,
    /// θ of the θ-method, in `[0.5, 1]`.
    pub theta: f64,
    /// Newton's coefficient of restitution `e ∈ [0, 1]`.
    pub restitution: f64,
    /// Uniform velocity at time 0.
    pub initial_velocity: [f64; 2],
    /// The applied loads rise linearly from 0 to their value over this time, then hold
    /// (`None`: applied in full from time 0).
    pub load_ramp: Option<f64>,
    /// A VTP snapshot of the body every this many steps (the first and last always;
    /// `None`: no snapshots).
    pub snapshot_every: Option<usize>,
    /// The other bodies' density and initial velocity, bodies 1, 2, … of
    /// [`Problem::body`] in order (empty for one body; `density` and `initial_velocity`
    /// above are body 0's).
    pub others: Vec<Motion>,
    /// How each step's contact is solved: [`ContactSolver::ActiveSet`] on the sparse system
    /// of the bodies' `M̂` (plane MFVM bodies), otherwise Lemke's method on the
    /// condensed `W` (`Auto` takes Lemke).
    pub solver: ContactSolver,
    /// The mass of every body (`[dynamics] mass`).
    pub mass: MassKind,
}

/// `[dynamics] mass`: how the bodies' mass is formed (docs/method.md §10.1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MassKind {
    /// Diagonal: the MFVM's `ρ |Ω_I|` on the nodal values (lumped by construction), the
    /// finite elements' HRZ lumping.
    #[default]
    Lumped,
    /// The finite elements' consistent mass `ρ ∫ N_a N_b dA` (refused for the MFVM).
    Consistent,
}

/// A body's mass density and uniform velocity at time 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// `ρ`.
    pub density: f64,
    /// `[vx, vy]` at time 0.
    pub initial_velocity: [f64; 2],
}

impl Dynamics {
    /// Number of time steps: `T / h` rounded up (a last step never overshoots by more than
    /// `h`; `T / h` within 10⁻⁹ of an integer counts as that integer).
    pub fn steps(&self) -> usize {
        let ratio = self.end_time / self.time_step;
        let near = ratio.round();
        if (ratio - near).abs() <= 1e-9 * near.max(1.0) {
            near as usize
        } else {
            ratio.ceil() as usize
        }
    }

    /// The factor on the applied loads at time `t`: `min(t / T_r, 1)` with a ramp `T_r`, else 1.
    pub fn load_factor(&self, t: f64) -> f64 {
        self.load_ramp.map_or(1.0, |ramp| (t / ramp).clamp(0.0, 1.0))
    }
}

/// `[dynamics]` of `file` checked against the validated `problem` (`None` without the table).
///
/// # Errors
/// [`ProblemError::Invalid`] naming the key path and a remedy.
pub fn dynamics(file: &ProblemFile, problem: &Problem) -> Result<Option<Dynamics>, ProblemError> {
    let Some(d) = &file.dynamics else {
        return Ok(None);
    };
    let positive = |key: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(invalid(key, v, "must be a positive number"))
        }
    };
    let end_time = positive("dynamics.end_time", d.end_time)?;
    let time_step = positive("dynamics.time_step", d.time_step)?;
    if time_step > end_time {
        return Err(invalid(
            "dynamics.time_step",
            time_step,
            format!("must be at most dynamics.end_time = {end_time}"),
        ));
    }
    let theta = d.theta.unwrap_or(0.5);
    if !(0.5..=1.0).contains(&theta) {
        return Err(invalid(
            "dynamics.theta",
            theta,
            "must be in [0.5, 1] (0.5 keeps the energy, larger values damp high frequencies; below 0.5 the scheme is unstable)",
        ));
    }
    let restitution = d.restitution.unwrap_or(0.0);
    if !(0.0..=1.0).contains(&restitution) {
        return Err(invalid("dynamics.restitution", restitution, "must be in [0, 1]"));
    }
    let initial_velocity = velocity_of(file, 0)?;
    let load_ramp = match d.load_ramp {
        Some(r) if !(r.is_finite() && r > 0.0 && r <= end_time) => {
            return Err(invalid(
                "dynamics.load_ramp",
                r,
                format!("must be a positive time at most dynamics.end_time = {end_time}"),
            ));
        }
        Some(r) if !file.step.is_empty() => {
            return Err(invalid(
                "dynamics.load_ramp",
                r,
                "the [[step]] tables give the loads' history in time; remove load_ramp (a ramp is one step: `time = T_r` with the full values)",
            ));
        }
        r => r,
    };
    let snapshot_every = d.output.as_ref().and_then(|o| o.every);
    if snapshot_every == Some(0) {
        return Err(invalid("dynamics.output.every", 0, "must be at least 1"));
    }
    let density = density(file)?;
    let others = (1..problem.body_count())
        .map(|k| {
            let density = file.body.get(k).and_then(|b| b.material.density).ok_or_else(|| {
                invalid(
                    &format!("body[{k}].material.density"),
                    "(missing)",
                    "[dynamics] needs each body's mass density; add `density = …` to its material",
                )
            })?;
            Ok(Motion { density, initial_velocity: velocity_of(file, k)? })
        })
        .collect::<Result<Vec<_>, ProblemError>>()?;
    let dynamics = Dynamics {
        density,
        end_time,
        time_step,
        theta,
        restitution,
        initial_velocity,
        load_ramp,
        snapshot_every,
        others,
        solver: solver_of(problem),
        mass: mass_of(file, problem)?,
    };
    if dynamics.steps() > MAX_STEPS {
        return Err(invalid(
            "dynamics.time_step",
            time_step,
            format!(
                "end_time / time_step = {:.3e} steps, more than {MAX_STEPS}; take a larger step",
                end_time / time_step
            ),
        ));
    }
    refuse_unsupported(problem)?;
    refuse_inconsistent_start(problem, initial_velocity, "")?;
    for (k, m) in dynamics.others.iter().enumerate() {
        if let Some(p) = problem.body(k + 1) {
            refuse_inconsistent_start(p, m.initial_velocity, &format!("body[{}].", k + 1))?;
        }
    }
    Ok(Some(dynamics))
}

/// `[dynamics] mass`: `"consistent"` needs every body to be finite elements.
fn mass_of(file: &ProblemFile, problem: &Problem) -> Result<MassKind, ProblemError> {
    let kind = file.dynamics.as_ref().and_then(|d| d.mass).unwrap_or_default();
    let mfvm = (0..problem.body_count())
        .filter_map(|k| problem.body(k))
        .any(|p| p.discretisation.method != super::Method::Fem);
    if kind == MassKind::Consistent && mfvm {
        return Err(invalid(
            "dynamics.mass",
            "consistent",
            "a consistent mass is formed for finite elements only (the MFVM's Voronoi-cell mass is lumped by construction); remove it, set mass = \"lumped\", or set [discretisation] method = \"fem\"",
        ));
    }
    Ok(kind)
}

/// The initial velocity of body `k`: `[dynamics] initial_velocity` for a body
/// without `[[body]]` tables, else `[[body]] initial_velocity` (`[dynamics]`'s is refused
/// with several bodies, a body's and `[dynamics]`'s together with one), `[0, 0]` when absent;
/// each finite and bounded.
fn velocity_of(file: &ProblemFile, k: usize) -> Result<[f64; 2], ProblemError> {
    let own = file.body.get(k).and_then(|b| b.initial_velocity);
    let (key, given) = match (own, file.dynamics.as_ref().and_then(|d| d.initial_velocity)) {
        (Some(v), None) => (format!("body[{k}].initial_velocity"), Some(v)),
        (None, Some(v)) if file.body.len() <= 1 => ("dynamics.initial_velocity".into(), Some(v)),
        (None, Some(v)) => {
            return Err(invalid(
                "dynamics.initial_velocity",
                format!("{v:?}"),
                "with several bodies each body's initial velocity goes in its [[body]] table (`initial_velocity = [vx, vy]`)",
            ));
        }
        (Some(v), Some(_)) => {
            return Err(invalid(
                &format!("body[{k}].initial_velocity"),
                format!("{v:?}"),
                "give the initial velocity once: in [[body]] or in [dynamics], not both",
            ));
        }
        (None, None) => (String::new(), None),
    };
    let velocity = given.unwrap_or([0.0; 2]);
    for v in velocity {
        if !v.is_finite() {
            return Err(invalid(&key, v, "must be finite numbers"));
        }
        // Its square (the kinetic energy) must not overflow: the bound of every magnitude.
        let max = super::validate::MAX_MAGNITUDE;
        if v.abs() > max {
            return Err(invalid(
                &key,
                format!("{v:e}"),
                format!("magnitudes above {max:e} make the arithmetic overflow; rescale the units"),
            ));
        }
    }
    Ok(velocity)
}

/// `[material] density` (or the one `[[body]]` table's), required with `[dynamics]`.
fn density(file: &ProblemFile) -> Result<f64, ProblemError> {
    let (key, given) = match (&file.material, file.body.as_slice()) {
        (Some(m), _) => ("material.density", m.density),
        (None, [b, ..]) => ("body[0].material.density", b.material.density),
        _ => ("material.density", None),
    };
    given.ok_or_else(|| {
        invalid(
            key,
            "(missing)",
            "[dynamics] needs the mass density; add `density = …` to [material]",
        )
    })
}

/// What the time stepping refuses: it steps one body (MFVM or finite elements, plane or
/// axisymmetric, with or without friction) against rigid obstacles, or any number of
/// bodies (plane, or all axisymmetric) in contact pairs with each other or with rigid
/// obstacles (with or without friction), undeformed at time 0.
fn refuse_unsupported(problem: &Problem) -> Result<(), ProblemError> {
    let several = problem.body_count() > 1 || problem.is_scene_of_pairs();
    let specs: Vec<&super::ContactSpec> = problem.pairs().iter().map(|p| &p.spec).collect();
    let refused = if several && specs.iter().any(|c| c.interference != 0.0) {
        Some(("contact.interference", "an interference fit (the bodies start overlapping)"))
    } else if problem.adaptive.is_some() {
        Some(("refinement", "adaptive refinement"))
    } else if problem.discretisation.precision != Precision::Double {
        Some(("discretisation.precision", "mixed precision"))
    } else if problem.write_steps {
        Some(("output.steps", "per-increment contact tables"))
    } else {
        None
    };
    match refused {
        Some((key, what)) => Err(invalid(
            key,
            "(given)",
            format!(
                "{what} is not implemented with [dynamics] yet (it steps one body, MFVM or FE, plane or axisymmetric, with Coulomb friction or without, against rigid obstacles, or bodies (plane, or all axisymmetric) in contact pairs with each other or with rigid obstacles, with Coulomb friction or without; docs/dev/dynamics.md); remove it or remove [dynamics]"
            ),
        )),
        None => Ok(()),
    }
}

/// The time of `[[step]]` number `k` (`step`), after the previous step's `previous` (0
/// before the first): required and increasing with `[dynamics]` (`dynamic`), where a step is
/// a state of the conditions (and of the rigid obstacles' displacement, and the friction
/// coefficient during it) in time and `increments` and the obstacle's force are refused;
/// refused in a static solve. `None` there.
///
/// # Errors
/// [`ProblemError::Invalid`] naming the step's key and a remedy.
pub(super) fn step_time(
    k: usize,
    step: &StepFile,
    previous: f64,
    dynamic: bool,
) -> Result<Option<f64>, ProblemError> {
    let key = |f: &str| format!("step[{k}].{f}");
    if !dynamic {
        return match step.time {
            Some(t) => Err(invalid(
                &key("time"),
                t,
                "a step's time needs [dynamics] (a static step is reached in `increments`); remove it or add [dynamics]",
            )),
            None => Ok(None),
        };
    }
    let refused = if step.increments.is_some() {
        Some(("increments", "with [dynamics] a step is reached at its `time`, not in increments"))
    } else if step.obstacle_force.is_some() {
        Some((
            "obstacle_force",
            "a force-driven obstacle in time needs the obstacle's mass (its motion follows from the force and its inertia), which a rigid obstacle does not have; prescribe its motion in time with `obstacle_displacement`, or model the obstacle as a body with a density ([[body]] tables and a [[contact]] pair between the bodies)",
        ))
    } else {
        None
    };
    if let Some((name, why)) = refused {
        return Err(invalid(&key(name), "(given)", format!("{why}; remove it")));
    }
    let Some(t) = step.time else {
        return Err(invalid(
            &key("time"),
            "(missing)",
            "with [dynamics] each step gives the time at which its values are reached (`time = …`, increasing from step to step)",
        ));
    };
    if !(t.is_finite() && t > previous) {
        let after = match k {
            0 => "a positive time (the conditions' values at time 0 are the [[boundary]] ones, 0)"
                .to_string(),
            _ => format!("greater than step[{}].time = {previous}", k - 1),
        };
        return Err(invalid(&key("time"), t, format!("must be {after}")));
    }
    Ok(Some(t))
}

/// The contact solver of every step: the active-set method when a pair asks for it.
fn solver_of(problem: &Problem) -> ContactSolver {
    if problem.pairs().iter().any(|p| p.spec.solver == ContactSolver::ActiveSet) {
        ContactSolver::ActiveSet
    } else {
        ContactSolver::Lemke
    }
}

/// The start must satisfy the displacement conditions: every prescribed displacement is zero
/// (the body starts undeformed at rest on its supports), and the initial velocity has no
/// component that a displacement condition holds.
fn refuse_inconsistent_start(
    problem: &Problem,
    velocity: [f64; 2],
    prefix: &str,
) -> Result<(), ProblemError> {
    let names = problem.domain.edge_names();
    for (k, condition) in problem.boundary.iter().enumerate() {
        for axis in 0..2 {
            let Some(field) = condition.displacement(axis) else { continue };
            if !field.is_zero() {
                return Err(invalid(
                    &format!("{prefix}boundary ({}).displacement", names[k]),
                    "(non-zero)",
                    "with [dynamics] the body starts undeformed, so a prescribed displacement is 0 at time 0; declare it 0 here and give its history in [[step]] tables with `time` (docs/guide: [[step]])",
                ));
            }
            if velocity[axis] != 0.0 {
                let key = match prefix {
                    "" => "dynamics.initial_velocity".to_string(),
                    _ => format!("{prefix}initial_velocity"),
                };
                return Err(invalid(
                    &key,
                    format!("{velocity:?}"),
                    format!(
                        "edge `{}` holds the {} displacement at 0, so the initial velocity's {} component must be 0",
                        names[k],
                        ["x", "y"][axis],
                        ["x", "y"][axis]
                    ),
                ));
            }
        }
    }
    Ok(())
}
