//! Stage 13: adaptive node refinement (docs/method.md §2.2) — solve, estimate, mark, refine,
//! until the tolerance, an accuracy goal, `max_nodes` or `steps` stops it. The estimate, the
//! marks and the refined problem are [`crate::refine`]'s; this is the loop.
//!
//! - **Several bodies** (one pair or several; `adaptive/scene.rs` sees each solve as a list
//!   of bodies and pairs): each body has its own estimate, Dörfler marks, regions and node
//!   set; the contact marks of each pair's transition candidates are carried to an elastic
//!   target's contact edge at their paired points ([`refine::paired_marks`]), so that the
//!   target refines where the candidate edge opens and closes. `max_nodes` counts every body.
//! - **FE bodies** (`method = "fem"`, [`refine::fem`]): the same loop on elements — a
//!   recovery estimate per element (whatever `indicator`), Dörfler marks on elements, the
//!   contact marks' nodes carried to the elements that hold them, and each marked element a
//!   refinement region that the graded tensor-product grid meets by halving its column and
//!   row (`fem::Mesh::graded`: no hanging nodes). A Gmsh mesh is refused (no remesher).

use crate::error::Error;
use crate::geometry::Point;
use crate::model::Model;
use crate::nodes::{self, Nodes};
use crate::post::summary::{
    AdaptiveBodyStep, AdaptivePairStep, AdaptiveStep, AdaptiveSummary, OnsetEstimate,
};
use crate::problem::{Adaptive, ContactTarget, Method, Problem};
use crate::progress::Progress;
use crate::refine::{self, Estimate, fem, mark, paired_marks, refined, transitions_of};
use crate::solution::Solution;

mod scene;
use scene::Solved;

/// The adaptive loop's result: the last solved problem (its refinement regions included),
/// its model and solution, and the record of the loop.
pub struct AdaptiveRun {
    /// The problem of the final node set (with two bodies, the second body's inside it).
    pub problem: Problem,
    /// The final model.
    pub model: Model,
    /// The second body's final model (two-body contact only).
    pub second: Option<Model>,
    /// The other bodies' final models (several bodies or pairs; empty otherwise).
    pub others: Vec<Model>,
    /// The final solution.
    pub solution: Solution,
    /// The loop's record (`summary.json`'s `refinement`).
    pub summary: AdaptiveSummary,
}

/// `Err` with `reason`, naming the `refinement` key.
fn refuse(problem: &Problem, reason: &str) -> Result<(), Error> {
    Err(crate::problem::ProblemError::Invalid {
        field: "refinement".into(),
        value: problem.name.clone(),
        reason: reason.into(),
    }
    .into())
}

/// What the loop needs of a body: a domain without holes; with the FE, not a Gmsh mesh
/// (the loop regenerates the graded grid of a rectangle and has no remesher).
fn check_body(problem: &Problem) -> Result<(), Error> {
    if problem.discretisation.method == Method::Fem && problem.mesh_nodes.is_some() {
        return refuse(
            problem,
            "adaptive refinement of a Gmsh mesh needs a remesher, which the FE path does not have; refine the mesh in Gmsh, or use method = \"mfvm\"",
        );
    }
    if problem.domain.has_holes() {
        return refuse(problem, "adaptive refinement is not implemented for domains with holes");
    }
    Ok(())
}

/// With two bodies, the second body's target edge must be straight (docs/method.md §4.3):
/// [`paired_marks`] projects onto it as a segment. The first body (the candidates') may be
/// curved.
fn check_target(problem: &Problem, second: &Problem) -> Result<(), Error> {
    let edge = problem.contact().and_then(|c| match c.target {
        ContactTarget::Body { edge } => Some(edge),
        _ => None,
    });
    let Some(edge) = edge else {
        return refuse(problem, "two bodies need a contact pair whose target is the second body");
    };
    if second.domain.straight_normal(edge).is_none() {
        return Err(crate::problem::ProblemError::Invalid {
            field: "contact.target_edge".into(),
            value: second.domain.edge_names().get(edge).cloned().unwrap_or_default(),
            reason: "the adaptive loop pairs the contact marks with a straight target edge; this edge of the second body is curved".into(),
        }
        .into());
    }
    Ok(())
}

/// One body's part of a step: its estimate, marks and row.
struct BodyPart {
    estimate: Estimate,
    marked: Vec<usize>,
    marked_contact: usize,
}

impl BodyPart {
    /// The row of `summary.json`'s `refinement.steps[].bodies`.
    fn row(&self, name: &str, nodes: &Nodes) -> AdaptiveBodyStep {
        AdaptiveBodyStep {
            name: name.to_string(),
            nodes: nodes.len(),
            min_spacing: nodes.spacing.iter().copied().fold(f64::INFINITY, f64::min),
            estimated_error: self.estimate.relative,
            marked: self.marked.len(),
            marked_contact: self.marked_contact,
        }
    }
}

/// The marks of one body: Dörfler on its estimate, plus `contact` (deduplicated); the count
/// of marks the contact added.
fn marks(estimate: &Estimate, fraction: f64, contact: Vec<usize>) -> (Vec<usize>, usize) {
    let mut marked = mark(&estimate.node, fraction);
    let bulk = marked.len();
    marked.extend(contact);
    marked.sort_unstable();
    marked.dedup();
    let added = marked.len() - bulk;
    (marked, added)
}

/// Solves `problem` adaptively with the parameters `adaptive` (docs/method.md §2.2): solve,
/// estimate, stop (tolerance, steps), mark, refine, stop when the refined node set would
/// exceed `max_nodes`, repeat. `observe` sees every solve (for studies; the first body's
/// problem, model and estimate, the other bodies' solutions inside the solution). One
/// progress line per solve.
///
/// Any number of bodies (one body; two bodies in one pair; several bodies or pairs): each
/// body is estimated, marked and refined on its own; the contact marks of every pair are its
/// candidates' transition candidates and, on an elastic target, the target-edge nodes at
/// their paired points ([`paired_marks`]); the estimate the tolerance tests is the bodies'
/// combined `(Σ η_I² / Σ h_I² ε̂_Iᵀ D ε̂_I)^(1/2)`, and `max_nodes` counts every node set.
///
/// # Errors
/// [`Error::Problem`] for a Gmsh FE body, a domain with holes (what `[refinement]`'s
/// validation refuses) or a curved target edge of an elastic pair (what the contact's
/// validation refuses); any stage's error of any solve.
pub fn solve_adaptive(
    problem: &Problem,
    adaptive: &Adaptive,
    progress: &mut dyn Progress,
    observe: &mut dyn FnMut(&Problem, &Model, &Solution, &Estimate),
) -> Result<AdaptiveRun, Error> {
    for body in problem.bodies() {
        check_body(body)?;
    }
    if let Some(p2) = problem.second_body() {
        check_target(problem, p2)?;
    }
    let mut current = problem.clone();
    current.adaptive = None;
    let mut rows: Vec<AdaptiveStep> = Vec::new();
    let mut step = 0;
    // The refined node set of one body, generated to count it (reused, it is
    // `nodes::for_problem`'s).
    let mut counted: Option<Nodes> = None;
    loop {
        let regions: usize = (0..current.body_count())
            .filter_map(|k| current.body(k))
            .map(|p| p.refinement.boxes.len())
            .sum();
        progress.section(&format!(
            "refinement step {step} of at most {}: {regions} refinement regions",
            adaptive.steps,
        ));
        let solved = Solved::solve(current, counted.take(), progress)?;
        let estimates: Vec<Estimate> = (0..solved.len())
            .map(|k| {
                let (p, m, s) = solved.body(k);
                match fem::mesh_of(m) {
                    Some(mesh) => fem::estimate(p, mesh, s),
                    None => refine::estimate(p, m, s, adaptive.indicator),
                }
            })
            .collect();
        observe(&solved.problem, &solved.models[0], &solved.solution, &estimates[0]);
        let mut row = step_row(step, &solved, &estimates);
        progress.section(&progress_line(&row, &solved));
        let parts = body_marks(&solved, estimates, adaptive);
        if solved.len() > 1 {
            row.bodies = Some(
                parts
                    .iter()
                    .enumerate()
                    .map(|(k, b)| {
                        let (p, m, _) = solved.body(k);
                        b.row(&p.name, &m.nodes)
                    })
                    .collect(),
            );
        }
        if adaptive.tolerance.is_some_and(|t| row.estimated_error <= t) {
            rows.push(unmarked(row));
            return Ok(finish(solved, adaptive, "tolerance", rows));
        }
        let onset = solved.solution.contact().map(|c| &c.onset);
        if goals_met(adaptive, &row, onset, rows.last()) {
            rows.push(unmarked(row));
            return Ok(finish(solved, adaptive, "accuracy", rows));
        }
        if step == adaptive.steps {
            rows.push(unmarked(row));
            return Ok(finish(solved, adaptive, "steps", rows));
        }
        row.marked = parts.iter().map(|b| b.marked.len()).sum();
        row.marked_contact = parts.iter().map(|b| b.marked_contact).sum();
        if row.marked == 0 {
            rows.push(row);
            return Ok(finish(solved, adaptive, "no_marks", rows));
        }
        let mut next = solved.problem.clone();
        for (k, part) in parts.iter().enumerate() {
            if let Some(body) = next.body_mut(k) {
                let model = &solved.models[k];
                *body = match fem::mesh_of(model) {
                    Some(_) => fem::refined(body, model, &part.marked),
                    None => refined(body, &model.nodes, &part.marked),
                };
            }
        }
        // The generator refuses only sets beyond its own size limits: too many as well. One
        // body's set known to exceed `max_nodes` from its quadtree's leaves is not generated,
        // and the set generated to count it is the next step's.
        let fits = if next.body_count() == 1 && next.discretisation.method == Method::Mfvm {
            counted = nodes::for_problem_at_most(&next, adaptive.max_nodes)
                .ok()
                .flatten()
                .filter(|n| n.len() <= adaptive.max_nodes);
            counted.is_some()
        } else {
            let count = |p: &Problem| match p.discretisation.method {
                Method::Mfvm => nodes::for_problem(p).map_or(usize::MAX, |n| n.len()),
                Method::Fem => crate::fem::mesh(p).map_or(usize::MAX, |(m, _)| m.node_count()),
            };
            let total = (0..next.body_count())
                .filter_map(|k| next.body(k))
                .fold(0usize, |sum, p| sum.saturating_add(count(p)));
            total <= adaptive.max_nodes
        };
        if !fits {
            row.marked = 0;
            row.marked_contact = 0;
            rows.push(unmarked(row));
            return Ok(finish(solved, adaptive, "max_nodes", rows));
        }
        rows.push(row);
        current = next;
        step += 1;
    }
}

/// The row of `summary.json`'s `refinement.steps` for one solve, nothing marked yet: the
/// bodies' totals (least spacing), their combined estimate, and the contact's figures (one
/// pair: its force and onset; several pairs: one row per pair).
fn step_row(step: usize, solved: &Solved, estimates: &[Estimate]) -> AdaptiveStep {
    let norm: f64 = estimates.iter().map(|e| e.energy).sum();
    let total: f64 = estimates.iter().flat_map(|e| &e.node).sum();
    let relative = if norm > 0.0 { (total / norm).sqrt() } else { 0.0 };
    let contact = solved.solution.contact();
    let pairs = solved.solution.multibody().map(|m| {
        m.pairs
            .iter()
            .enumerate()
            .map(|(k, c)| AdaptivePairStep {
                pair: k,
                total_contact_force: c.total_force,
                onset_x: c.onset.from_gap,
                last_open_x: c.onset.last_open,
                first_closed_x: c.onset.first_closed,
            })
            .collect()
    });
    AdaptiveStep {
        step,
        nodes: solved.models.iter().map(|m| m.nodes.len()).sum(),
        min_spacing: solved
            .models
            .iter()
            .flat_map(|m| m.nodes.spacing.iter().copied())
            .fold(f64::INFINITY, f64::min),
        estimated_error: relative,
        marked: 0,
        marked_contact: 0,
        total_contact_force: contact.map(|c| c.total_force),
        onset_x: contact.and_then(|c| c.onset.from_gap),
        last_open_x: contact.and_then(|c| c.onset.last_open),
        first_closed_x: contact.and_then(|c| c.onset.first_closed),
        bodies: None,
        pairs,
    }
}

/// The terminal line of one solve.
fn progress_line(row: &AdaptiveStep, solved: &Solved) -> String {
    let opt = |v: Option<f64>| v.map_or_else(|| "–".to_string(), |v| format!("{v:.6}"));
    let per_body = if solved.len() > 1 {
        let counts: Vec<String> = solved.models.iter().map(|m| m.nodes.len().to_string()).collect();
        format!(" ({})", counts.join(" + "))
    } else {
        String::new()
    };
    let contact = match &row.pairs {
        Some(pairs) => {
            let forces: Vec<String> =
                pairs.iter().map(|p| format!("{:.6}", p.total_contact_force)).collect();
            format!("pair contact forces [{}]", forces.join(", "))
        }
        None => format!(
            "contact force {}, onset {} in [{}, {}]",
            opt(row.total_contact_force),
            opt(row.onset_x),
            opt(row.last_open_x),
            opt(row.first_closed_x)
        ),
    };
    format!(
        "refinement step {}: {} nodes{per_body}, estimated error {:.3e}, {contact}",
        row.step, row.nodes, row.estimated_error
    )
}

/// Every body's marks: Dörfler on its own estimate, and the contact marks of every pair —
/// the candidates' transition candidates on the candidates' body and, on an elastic target,
/// the target-edge nodes at their paired points.
fn body_marks(solved: &Solved, estimates: Vec<Estimate>, adaptive: &Adaptive) -> Vec<BodyPart> {
    let mut contact: Vec<Vec<usize>> = vec![Vec::new(); solved.len()];
    if adaptive.contact {
        for pair in solved.pairs() {
            let c = pair.contact;
            let transitions = transitions_of(c);
            contact[pair.body].extend(transitions.iter().map(|&k| c.candidates.nodes[k] as usize));
            if let Some((target, edge)) = pair.target {
                let (p2, m2, _) = solved.body(target);
                let points: Vec<Point> =
                    transitions.iter().map(|&k| c.candidates.points[k]).collect();
                contact[target].extend(paired_marks(&p2.domain, edge, &m2.nodes, &points));
            }
        }
    }
    estimates
        .into_iter()
        .zip(contact)
        .zip(&solved.models)
        .map(|((estimate, contact), model)| {
            let contact = match fem::mesh_of(model) {
                Some(mesh) => fem::elements_at(mesh, &contact),
                None => contact,
            };
            let (marked, marked_contact) = marks(&estimate, adaptive.fraction, contact);
            BodyPart { estimate, marked, marked_contact }
        })
        .collect()
}

/// Whether the accuracy goals of `adaptive` (at least one stated) are met by the solve of
/// `row` (its contact onset `onset`) after the solve of `previous`, from computed quantities
/// only. `onset_tolerance`: the onset's two one-sided estimates — `gap^(2/3)` extrapolated
/// from the open side and `p²` from the closed side — both strictly inside the bracket (not
/// clipped to it) and at most `onset_tolerance` apart. `force_tolerance`: the total contact
/// force changed by at most that, relative, from the solve before. Never on the first solve.
fn goals_met(
    adaptive: &Adaptive,
    row: &AdaptiveStep,
    onset: Option<&crate::contact::ContactOnset>,
    previous: Option<&AdaptiveStep>,
) -> bool {
    let Some(prev) = previous else { return false };
    if adaptive.onset_tolerance.is_none() && adaptive.force_tolerance.is_none() {
        return false;
    }
    let onset_met = adaptive.onset_tolerance.is_none_or(|t| {
        let Some(o) = onset else { return false };
        let (Some(a), Some(b)) = (o.last_open, o.first_closed) else { return false };
        let (lo, hi) = (a.min(b), a.max(b));
        let inside = |x: f64| lo < x && x < hi;
        match (o.from_gap_raw, o.from_pressure) {
            (Some(g), Some(p)) => inside(g) && inside(p) && (g - p).abs() <= t,
            _ => false,
        }
    });
    let force_met = adaptive.force_tolerance.is_none_or(|t| {
        match (row.total_contact_force, prev.total_contact_force) {
            (Some(f), Some(g)) => (f - g).abs() <= t * f.abs(),
            _ => false,
        }
    });
    onset_met && force_met
}

/// `row` with nothing marked (a step that stops).
fn unmarked(mut row: AdaptiveStep) -> AdaptiveStep {
    for b in row.bodies.iter_mut().flatten() {
        b.marked = 0;
        b.marked_contact = 0;
    }
    row
}

/// The loop's result, stopped by `why` after `solved`.
fn finish(
    solved: Solved,
    adaptive: &Adaptive,
    why: &'static str,
    rows: Vec<AdaptiveStep>,
) -> AdaptiveRun {
    let onset = solved.solution.contact().map(|c| {
        let o = &c.onset;
        OnsetEstimate {
            estimate: o.from_gap,
            estimator: if o.from_gap == o.from_gap_raw { "gap_extrapolation" } else { "clipped" },
            last_open_x: o.last_open,
            first_closed_x: o.first_closed,
            bracket_width: o.last_open.zip(o.first_closed).map(|(a, b)| b - a),
        }
    });
    let summary = AdaptiveSummary { parameters: *adaptive, stopped_by: why, steps: rows, onset };
    let (problem, model, second, others, solution) = solved.into_parts();
    AdaptiveRun { problem, model, second, others, solution, summary }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Indicator;

    /// The accuracy goals from computed quantities: the onset's two one-sided estimates inside
    /// the bracket and close, the force's change from the solve before; never on the first
    /// solve, never without a goal stated.
    #[test]
    fn accuracy_goals_need_every_stated_goal() {
        let row = |force: f64| AdaptiveStep {
            step: 1,
            nodes: 10,
            min_spacing: 0.1,
            estimated_error: 0.1,
            marked: 0,
            marked_contact: 0,
            total_contact_force: Some(force),
            onset_x: None,
            last_open_x: None,
            first_closed_x: None,
            bodies: None,
            pairs: None,
        };
        let onset = |gap: f64, pressure: f64| crate::contact::ContactOnset {
            last_open: Some(1.0),
            first_closed: Some(1.5),
            from_gap_raw: Some(gap),
            from_gap: Some(gap.clamp(1.0, 1.5)),
            from_pressure: Some(pressure),
            closed_intervals: 1,
        };
        let goals = |o: Option<f64>, f: Option<f64>| Adaptive {
            steps: 4,
            max_nodes: 1000,
            tolerance: None,
            fraction: 0.5,
            indicator: Indicator::Gradient,
            contact: true,
            onset_tolerance: o,
            force_tolerance: f,
        };
        let (close, apart, clipped) = (onset(1.20, 1.205), onset(1.20, 1.25), onset(1.6, 1.5));
        let (prev, near, far) = (row(10.0), row(10.0005), row(10.01));
        let met = |a: &Adaptive, r: &AdaptiveStep, o, p| goals_met(a, r, Some(o), p);
        // Onset: both estimates inside the bracket and at most the tolerance apart.
        let a = goals(Some(0.01), None);
        assert!(met(&a, &far, &close, Some(&prev)));
        assert!(!met(&a, &far, &apart, Some(&prev)));
        assert!(!met(&a, &far, &clipped, Some(&prev)));
        assert!(!met(&a, &far, &close, None));
        assert!(!goals_met(&a, &far, None, Some(&prev)));
        // Force: relative change from the solve before.
        let f = goals(None, Some(1e-4));
        assert!(met(&f, &near, &apart, Some(&prev)));
        assert!(!met(&f, &far, &close, Some(&prev)));
        // Both: each must hold; none stated: never.
        let both = goals(Some(0.01), Some(1e-4));
        assert!(met(&both, &near, &close, Some(&prev)));
        assert!(!met(&both, &near, &apart, Some(&prev)));
        assert!(!met(&both, &far, &close, Some(&prev)));
        assert!(!met(&goals(None, None), &near, &close, Some(&prev)));
    }

    #[test]
    fn a_curved_target_edge_is_refused_naming_its_key() {
        // The Cattaneo–Mindlin pair (a curved first body, accepted by validation), its second
        // body replaced in code by a copy of the cylinder and the target by its arc.
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/cattaneo_mindlin.toml");
        let text = std::fs::read_to_string(path).unwrap();
        let mut p = Problem::from_toml(&format!("{text}\n[refinement]\n")).unwrap();
        let a = p.adaptive.unwrap();
        let mut cylinder = p.clone();
        cylinder.others.clear();
        cylinder.contact_pairs.clear();
        let arc = cylinder.domain.edge_index("arc").unwrap();
        p.others = vec![cylinder];
        p.contact_mut().unwrap().target = ContactTarget::Body { edge: arc };
        let mut silent = crate::Silent;
        let Err(e) = solve_adaptive(&p, &a, &mut silent, &mut |_, _, _, _| {}) else {
            panic!("a curved target edge must be refused");
        };
        assert!(e.to_string().contains("`contact.target_edge`"), "{e}");
        assert!(e.to_string().contains("curved"), "{e}");
    }

    #[test]
    fn the_loop_refines_both_methods_and_refuses_a_gmsh_fe_body() {
        let text = |method: &str| {
            format!(
                "[geometry]\nkind = \"rectangle\"\nx = [0.0, 4.0]\ny = [0.0, 1.0]\n[nodes]\nspacing = 0.25\n[material]\nyoung = 1000.0\npoisson = 0.3\nplane = \"stress\"\n[discretisation]\nmethod = \"{method}\"\n[[boundary]]\nedge = \"left\"\ndisplacement = {{ x = 0.0, y = 0.0 }}\n[[boundary]]\nedge = \"right\"\ntraction = {{ y = 1.0 }}"
            )
        };
        let a = Adaptive {
            steps: 1,
            max_nodes: 1000,
            fraction: 0.5,
            indicator: Indicator::Gradient,
            contact: true,
            ..Adaptive::default()
        };
        let mut silent = crate::Silent;
        for method in ["mfvm", "fem"] {
            let p = Problem::from_toml(&text(method)).unwrap();
            let run = solve_adaptive(&p, &a, &mut silent, &mut |_, _, _, _| {}).unwrap();
            assert_eq!(run.summary.steps.len(), 2, "{method}");
            assert!(run.summary.steps[1].nodes > run.summary.steps[0].nodes, "{method}");
            assert!(run.summary.onset.is_none());
            assert_eq!(run.summary.stopped_by, "steps");
        }
        // A Gmsh FE body: the loop has no remesher.
        let mut gmsh = Problem::from_toml(&text("fem")).unwrap();
        gmsh.mesh_nodes = Some(std::sync::Arc::new(crate::problem::MeshNodes {
            points: Vec::new(),
            spacing: Vec::new(),
            elements: Vec::new(),
        }));
        let Err(e) = solve_adaptive(&gmsh, &a, &mut silent, &mut |_, _, _, _| {}) else {
            panic!("a Gmsh FE body must be refused");
        };
        assert!(e.to_string().contains("`refinement`") && e.to_string().contains("remesher"));
    }
}
