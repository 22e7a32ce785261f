//! The checks and conditions of an axisymmetric body (`material.plane = "axisymmetric"`;
//! docs/method.md §9): the section lies in `r = x ≥ 0`; an edge on `r = 0` is the axis, where
//! `u_r = 0` is imposed (its `x` displacement is set to 0 unless the file gives it so) and no
//! radial traction may act; and what is not implemented in axisymmetry yet is refused.

use super::{ComponentCondition, EdgeCondition, Field, Problem, ProblemError, invalid};
use crate::geometry::Domain;

/// Relative tolerance (of the section's size) within which `x` counts as 0.
const AXIS_TOLERANCE: f64 = 1e-12;

/// The section's size, for tolerances.
fn size(domain: &Domain) -> f64 {
    let (lo, hi) = domain.bounding_box();
    (hi[0] - lo[0]).max(hi[1] - lo[1])
}

/// Whether edge `k` of `domain` is straight and lies on the axis `r = 0`.
pub fn on_axis(domain: &Domain, k: usize) -> bool {
    let tol = AXIS_TOLERANCE * size(domain);
    let (a, b) = domain.edge(k);
    domain.curve(k).is_straight() && a[0].abs() <= tol && b[0].abs() <= tol
}

/// Refuses a section reaching `r < 0` and makes every edge on the axis a roller in `r`
/// (`u_r = 0`; the `z` component keeps its condition). Keys are those of a one-body file
/// (the caller prefixes `body[k].`).
///
/// # Errors
/// [`ProblemError::Invalid`] naming `geometry` when the section reaches `r < 0`, or
/// `boundary` when an axis edge carries a radial traction, a pressure or a non-zero radial
/// displacement.
pub fn axis_conditions(
    domain: &Domain,
    boundary: &mut [EdgeCondition],
) -> Result<(), ProblemError> {
    let (lo, _) = domain.bounding_box();
    if lo[0] < -AXIS_TOLERANCE * size(domain) {
        return Err(invalid(
            "geometry",
            format!("x from {}", lo[0]),
            "with material.plane = \"axisymmetric\" x is the radius r and the section must lie in r ≥ 0 (the axis is x = 0): move or cut the section to x ≥ 0",
        ));
    }
    for (k, condition) in boundary.iter_mut().enumerate() {
        if !on_axis(domain, k) {
            continue;
        }
        let name = &domain.edge_names()[k];
        let refuse = |what: &str| {
            invalid(
                "boundary",
                format!("edge `{name}`: {what}"),
                "this edge lies on the axis r = 0, where u_r = 0 by symmetry and no radial load can act: give at most displacement.x = 0 and a condition on y there",
            )
        };
        let z = match condition {
            EdgeCondition::Pressure(p) if p.is_zero() => {
                ComponentCondition::Traction(Field::Constant(0.0))
            }
            EdgeCondition::Pressure(_) => return Err(refuse("a pressure")),
            EdgeCondition::Components([ComponentCondition::Traction(t), _]) if !t.is_zero() => {
                return Err(refuse("a radial traction"));
            }
            EdgeCondition::Components([ComponentCondition::Displacement(u), _]) if !u.is_zero() => {
                return Err(refuse("a non-zero radial displacement"));
            }
            EdgeCondition::Components([_, z]) => z.clone(),
        };
        *condition =
            EdgeCondition::Components([ComponentCondition::Displacement(Field::Constant(0.0)), z]);
    }
    Ok(())
}

/// Refuses what an axisymmetric problem cannot do yet. Axisymmetric bodies against rigid
/// obstacles (a line: a flat or a cone; a circle: a sphere or a torus) and against each other
/// (a two-body `[contact]`, `[[body]]`/`[[contact]]` scenes), with friction and load steps,
/// are solved: their contact candidates are rings (`contact::rings`); a body of several may be
/// held along the axis by contact alone; `[refinement]` refines them adaptively (the estimate
/// weighted by the radius, with the hoop strain). Refused: a scene mixing axisymmetric and
/// plane bodies; the obstacles are surfaces of revolution and move (or are pressed) along the axis only, and each step's conditions on
/// the axis obey [`axis_conditions`].
///
/// # Errors
/// [`ProblemError::Invalid`] naming the key of the first such feature.
pub fn refuse_unsupported(problem: &Problem) -> Result<(), ProblemError> {
    let bodies: Vec<&Problem> = (0..problem.body_count()).filter_map(|k| problem.body(k)).collect();
    if !bodies.iter().any(|p| p.material.is_axisymmetric()) {
        return Ok(());
    }
    let several = bodies.len() > 1;
    // The key prefix of body k: `body[k].` when there are several.
    let prefix = |k: usize| if several { format!("body[{k}].") } else { String::new() };
    if let Some(k) = bodies.iter().position(|p| !p.material.is_axisymmetric()) {
        return Err(invalid(
            &format!("{}material.plane", prefix(k)),
            format!("body `{}` is not axisymmetric", bodies[k].name),
            "bodies in contact with an axisymmetric body must be axisymmetric too (a body of revolution cannot touch a prism): give every body plane = \"axisymmetric\", or none",
        ));
    }
    for (b, body) in bodies.iter().enumerate() {
        for (k, step) in body.steps.iter().enumerate() {
            axial_motion(&format!("step[{k}].obstacle_displacement"), step.obstacle_displacement)?;
            if let Some(f) = step.obstacle_force {
                axial_motion(&format!("step[{k}].obstacle_force"), f)?;
            }
            axis_conditions(&body.domain, &mut step.boundary.clone()).map_err(|e| match e {
                ProblemError::Invalid { field, value, reason } => {
                    ProblemError::Invalid { field: format!("{}{field}", prefix(b)), value, reason }
                }
                other => other,
            })?;
        }
    }
    Ok(())
}

/// Refuses a radial component of an obstacle's motion or force: a rigid surface of revolution
/// moved across the axis is no longer axisymmetric.
fn axial_motion(key: &str, v: [f64; 2]) -> Result<(), ProblemError> {
    match v[0] == 0.0 {
        true => Ok(()),
        false => Err(invalid(
            key,
            format!("[{}, {}]", v[0], v[1]),
            "with material.plane = \"axisymmetric\" an obstacle is a surface of revolution and moves along the axis only: give x = 0",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(x: &str, extra: &str) -> String {
        format!(
            r#"
            [geometry]
            kind = "rectangle"
            x = {x}
            y = [0.0, 1.0]
            [nodes]
            spacing = 0.25
            [material]
            young = 100.0
            poisson = 0.3
            plane = "axisymmetric"
            [[boundary]]
            edge = "bottom"
            displacement = {{ y = 0.0 }}
            {extra}
            "#
        )
    }

    fn refusal(text: &str) -> String {
        match Problem::from_toml(text) {
            Ok(_) => panic!("accepted:\n{text}"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn a_section_reaching_negative_radii_is_refused() {
        let e = refusal(&file("[-0.5, 1.0]", ""));
        assert!(e.contains("geometry") && e.contains("r ≥ 0"), "{e}");
    }

    #[test]
    fn an_edge_on_the_axis_becomes_a_radial_roller() {
        let p = Problem::from_toml(&file("[0.0, 1.0]", "")).expect("valid");
        let left = p.domain.edge_index("left").expect("left");
        let EdgeCondition::Components([ComponentCondition::Displacement(u), z]) = &p.boundary[left]
        else {
            panic!("axis edge not held radially: {:?}", p.boundary[left]);
        };
        assert!(u.is_zero() && matches!(z, ComponentCondition::Traction(t) if t.is_zero()));
        let right = p.domain.edge_index("right").expect("right");
        assert!(p.boundary[right].displacement(0).is_none());
    }

    #[test]
    fn loads_on_the_axis_are_refused() {
        let pressure = "[[boundary]]\nedge = \"left\"\npressure = 1.0";
        let e = refusal(&file("[0.0, 1.0]", pressure));
        assert!(e.contains("boundary") && e.contains("axis"), "{e}");
        let radial = "[[boundary]]\nedge = \"left\"\ndisplacement = { x = 0.1 }";
        assert!(refusal(&file("[0.0, 1.0]", radial)).contains("non-zero radial displacement"));
    }

    #[test]
    fn contact_with_a_rigid_obstacle_is_accepted() {
        let contact = "[contact]\nedge = \"top\"\nobstacle_point = [0.0, 1.01]\nobstacle_normal = [0.0, -1.0]";
        let p = Problem::from_toml(&file("[0.0, 1.0]", contact)).expect("valid");
        assert!(p.contact().is_some());
    }

    #[test]
    fn friction_and_axial_steps_are_accepted_radial_motion_refused() {
        let contact = "[contact]\nedge = \"top\"\nobstacle_point = [0.0, 1.01]\nobstacle_normal = [0.0, -1.0]";
        let friction = format!("{contact}\nfriction = 0.3");
        assert!(Problem::from_toml(&file("[0.0, 1.0]", &friction)).is_ok());
        let steps = format!("{friction}\n[[step]]\nobstacle_displacement = [0.0, -0.02]");
        assert_eq!(Problem::from_toml(&file("[0.0, 1.0]", &steps)).expect("valid").steps.len(), 1);
        let radial = format!("{contact}\n[[step]]\nobstacle_displacement = [0.01, -0.02]");
        let e = refusal(&file("[0.0, 1.0]", &radial));
        assert!(e.contains("step[0].obstacle_displacement") && e.contains("along the axis"), "{e}");
        let force = format!("{contact}\n[[step]]\nobstacle_force = [0.5, -1.0]");
        let e = refusal(&file("[0.0, 1.0]", &force));
        assert!(e.contains("step[0].obstacle_force"), "{e}");
    }

    /// Two cylinders, the upper's plane `plane`, the lower's bottom `lower` (a `boundary`
    /// entry).
    fn pair(plane: &str, lower: &str) -> String {
        format!(
            r#"
            [[body]]
            name = "upper"
            geometry = {{ kind = "rectangle", x = [0.0, 1.0], y = [1.0, 2.0] }}
            nodes = {{ spacing = 0.25 }}
            material = {{ young = 1.0, poisson = 0.3, plane = "{plane}" }}
            boundary = [ {{ edge = "top", displacement = {{ y = -0.01 }} }} ]
            [[body]]
            name = "lower"
            geometry = {{ kind = "rectangle", x = [0.0, 1.0], y = [0.0, 1.0] }}
            nodes = {{ spacing = 0.25 }}
            material = {{ young = 1.0, poisson = 0.3, plane = "axisymmetric" }}
            boundary = [ {lower} ]
            [contact]
            edge = "bottom"
            target_edge = "top"
            "#
        )
    }

    #[test]
    fn elastic_pairs_are_accepted_mixed_bodies_refused() {
        let held = "{ edge = \"bottom\", displacement = { y = 0.0 } }";
        let p = Problem::from_toml(&pair("axisymmetric", held)).expect("valid");
        assert!(p.second_body().is_some());
        let e = refusal(&pair("strain", held));
        assert!(e.contains("body[0].material.plane") && e.contains("axisymmetric too"), "{e}");
        let free = "{ edge = \"bottom\", traction = { y = 0.0 } }";
        assert!(Problem::from_toml(&pair("axisymmetric", free)).is_ok());
    }

    #[test]
    fn refinement_is_accepted_for_one_body_and_a_pair() {
        let contact = "[contact]\nedge = \"top\"\nobstacle_point = [0.0, 1.01]\nobstacle_normal = [0.0, -1.0]";
        let adaptive = format!("{contact}\n[refinement]\nsteps = 2");
        let p = Problem::from_toml(&file("[0.0, 1.0]", &adaptive)).expect("valid");
        assert_eq!(p.adaptive.map(|a| a.steps), Some(2));
        let held = "{ edge = \"bottom\", displacement = { y = 0.0 } }";
        let p = Problem::from_toml(&format!("{}\n[refinement]\n", pair("axisymmetric", held)))
            .expect("valid");
        assert!(p.adaptive.is_some() && p.second_body().is_some());
    }
}
