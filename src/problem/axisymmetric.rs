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

/// Refuses what an axisymmetric problem cannot do yet: several bodies (an elastic pair or
/// more), friction, load steps and adaptive refinement. One axisymmetric body against rigid
/// obstacles (a line: a flat or a cone; a circle: a sphere or a torus), frictionless and in
/// one step, is solved: its contact candidates are rings (`contact::rings`).
///
/// # Errors
/// [`ProblemError::Invalid`] naming the key of the first such feature.
pub fn refuse_unsupported(problem: &Problem) -> Result<(), ProblemError> {
    let axisymmetric = std::iter::once(problem)
        .chain(problem.second_body.as_deref())
        .chain(problem.multibody.iter().flat_map(|m| m.bodies.iter()))
        .any(|p| p.material.is_axisymmetric());
    if !axisymmetric {
        return Ok(());
    }
    let refused = if problem.second_body.is_some() || problem.multibody.is_some() {
        Some(("body", "contact between bodies (an elastic pair or more bodies)"))
    } else if problem.contact.as_ref().is_some_and(|c| c.friction > 0.0) {
        Some(("contact.friction", "friction"))
    } else if !problem.steps.is_empty() {
        Some(("step", "load steps"))
    } else if problem.adaptive.is_some() {
        Some(("refinement", "adaptive refinement"))
    } else {
        None
    };
    match refused {
        Some((key, what)) => Err(invalid(
            key,
            "(given)",
            format!(
                "{what} is not implemented for axisymmetric bodies yet (material.plane = \"axisymmetric\" solves one body under displacement conditions and loads, with frictionless contact against rigid obstacles in one step); remove it or use plane = \"strain\" or \"stress\""
            ),
        )),
        None => Ok(()),
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
        assert!(p.contact.is_some());
    }

    #[test]
    fn friction_and_steps_are_refused_with_a_remedy() {
        let contact = "[contact]\nedge = \"top\"\nobstacle_point = [0.0, 1.01]\nobstacle_normal = [0.0, -1.0]";
        let friction = format!("{contact}\nfriction = 0.3");
        let e = refusal(&file("[0.0, 1.0]", &friction));
        assert!(
            e.contains("contact.friction") && e.contains("not implemented for axisymmetric"),
            "{e}"
        );
        let steps = format!("{contact}\n[[step]]\nobstacle_displacement = [0.0, -0.001]");
        let e = refusal(&file("[0.0, 1.0]", &steps));
        assert!(e.contains("step") && e.contains("not implemented for axisymmetric"), "{e}");
    }
}
