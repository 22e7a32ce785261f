//! Stage 13: adaptive node refinement (docs/method.md §2.2) — solve, estimate, mark, refine.
//!
//! - **Estimate** ([`estimate`]): an error indicator `η_I` per node from one solution
//!   ([`Indicator`]), and the relative global estimate `(Σ η_I² / Σ h_I² ε̂_Iᵀ D ε̂_I)^(1/2)`.
//! - **Mark** ([`mark`]): Dörfler bulk marking — the fewest nodes whose `η_I²` sum to at least
//!   `θ Σ η_I²`; and [`contact_marks`]: the candidates next to an open/closed (or stick/slip)
//!   transition, which the bulk estimate does not see (the onset is where the contact
//!   solution is least smooth).
//! - **Refine** ([`refined`]): every marked node becomes a refinement region of the graded
//!   generator (`Refinement::around`: spacing `h_I/2` within `h_I` of the node), and the node
//!   set is regenerated from scratch (its layout quality is the generator's).
//! - **Several bodies** (one pair or several; `adaptive/scene.rs` sees each solve as a list
//!   of bodies and pairs): each body has its own estimate, Dörfler marks, regions and node
//!   set; the contact marks of each pair's transition candidates are carried to an elastic
//!   target's contact edge at their paired points ([`paired_marks`]), so that the target
//!   refines where the candidate edge opens and closes. `max_nodes` counts every body.
//! - **FE bodies** (`method = "fem"`, `adaptive/fem.rs`): the same loop on elements — a
//!   recovery estimate per element (whatever `indicator`), Dörfler marks on elements, the
//!   contact marks' nodes carried to the elements that hold them, and each marked element a
//!   refinement region that the graded tensor-product grid meets by halving its column and
//!   row (`fem::Mesh::graded`: no hanging nodes). A Gmsh mesh is refused (no remesher).

use crate::error::Error;
use crate::geometry::{Domain, Point};
use crate::lcp::ContactState;
use crate::material::Hoop;
use crate::model::Model;
use crate::nodes::{self, Nodes};
use crate::post::summary::{
    AdaptiveBodyStep, AdaptivePairStep, AdaptiveStep, AdaptiveSummary, OnsetEstimate,
};
use crate::problem::{Adaptive, ContactTarget, Indicator, Method, Problem, Refinement};
use crate::progress::Progress;
use crate::solution::{ContactSolution, Solution};

mod fem;
mod scene;
use scene::Solved;

/// An error estimate from one solution.
#[derive(Clone, Debug)]
pub struct Estimate {
    /// `η_I²` per node (MFVM), or `η_e²` per element (FE).
    pub node: Vec<f64>,
    /// The relative global estimate `(Σ η_I² / Σ h_I² ε̂_Iᵀ D ε̂_I)^(1/2)`.
    pub relative: f64,
    /// The denominator `Σ h_I² ε̂_Iᵀ D ε̂_I` (to combine the estimates of two bodies).
    pub energy: f64,
}

/// `aᵀ D a` for a strain-like triple `a`.
fn energy(d: &crate::material::Constitutive, a: [f64; 3]) -> f64 {
    (0..3).map(|i| a[i] * (0..3).map(|j| d[i][j] * a[j]).sum::<f64>()).sum()
}

/// The energy density of a strain-like `(a_xx, a_yy, a_xy, a_θθ)`: `aᵀ D a` of the in-plane
/// part, and in axisymmetry (`hoop`) the rest of `aᵀ D₄ a`,
/// `2 λ a_θθ (a_rr + a_zz) + (λ + 2μ) a_θθ²` (docs/method.md §9.1).
fn energy4(d: &crate::material::Constitutive, hoop: Option<Hoop>, a: [f64; 4]) -> f64 {
    let plane = energy(d, [a[0], a[1], a[2]]);
    match hoop {
        None => plane,
        Some(h) => plane + a[3] * (2.0 * h.coupling * (a[0] + a[1]) + h.diagonal * a[3]),
    }
}

/// The mean radius `∫ r dA / A` of a cell (its centroid's `x`; positive for a cell touching
/// the axis: a quarter of its width there).
fn mean_radius(cell: &crate::weak_form::Cell) -> f64 {
    let v = &cell.vertices;
    let n = v.len();
    let (mut moment, mut area) = (0.0, 0.0);
    for k in 0..n {
        let (a, b) = (v[k], v[(k + 1) % n]);
        let cross = a[0] * b[1] - b[0] * a[1];
        area += 0.5 * cross;
        moment += (a[0] + b[0]) * cross / 6.0;
    }
    if area > 0.0 { moment / area } else { v.iter().map(|p| p[0]).sum::<f64>() / n as f64 }
}

/// The weight `A_I` of node `i`'s energy: `h_I²`, the cell area's stand-in, and in axisymmetry
/// `h_I² r̄_I` with the cell's mean radius `r̄_I` (the energy per radian is `∫ σ:ε r dA`).
fn weights(problem: &Problem, model: &Model) -> Vec<f64> {
    let h = &model.nodes.spacing;
    let cells = model.mfvm().map(|m| &m.cells).filter(|_| problem.material.is_axisymmetric());
    match cells {
        None => h.iter().map(|h| h * h).collect(),
        Some(cells) => h.iter().zip(cells).map(|(h, c)| h * h * mean_radius(c)).collect(),
    }
}

/// The error indicator of `indicator` at every node of an MFVM solution (docs/method.md
/// §2.2; in axisymmetry §9.7: the hoop strain `ε̂_θθ` is a fourth component, `D₄` the law and
/// the cell weight carries the radius). Needs the node shape functions with gradients (as the
/// MFVM model has them).
pub fn estimate(
    problem: &Problem,
    model: &Model,
    solution: &Solution,
    indicator: Indicator,
) -> Estimate {
    let d = problem.material.constitutive();
    let hoop = problem.material.hoop();
    let (shapes, h) = (&model.node_shapes, &model.nodes.spacing);
    // The strains with the hoop component (zero in plane stress and strain).
    let eps: Vec<[f64; 4]> = solution
        .strain
        .iter()
        .enumerate()
        .map(|(i, e)| [e[0], e[1], e[2], solution.hoop.get(i).map_or(0.0, |t| t[0])])
        .collect();
    let weight = weights(problem, model);
    let mut node = Vec::with_capacity(eps.len());
    let mut norm = 0.0;
    for (i, e) in eps.iter().enumerate() {
        let area = weight[i];
        norm += area * energy4(&d, hoop, *e);
        let support = shapes.support(i);
        let eta2 = match indicator {
            Indicator::Recovery => {
                let mut s = [0.0; 4];
                for (&j, &phi) in support.iter().zip(shapes.phi(i)) {
                    for c in 0..4 {
                        s[c] += phi * eps[j as usize][c];
                    }
                }
                area * energy4(&d, hoop, [s[0] - e[0], s[1] - e[1], s[2] - e[2], s[3] - e[3]])
            }
            Indicator::Gradient => {
                let (dx, dy) = shapes.grad(i);
                let (mut gx, mut gy) = ([0.0; 4], [0.0; 4]);
                for ((&j, &a), &b) in support.iter().zip(dx).zip(dy) {
                    for c in 0..4 {
                        gx[c] += a * eps[j as usize][c];
                        gy[c] += b * eps[j as usize][c];
                    }
                }
                area * (h[i] * h[i]) * (energy4(&d, hoop, gx) + energy4(&d, hoop, gy))
            }
        };
        node.push(eta2);
    }
    let total: f64 = node.iter().sum();
    let relative = if norm > 0.0 { (total / norm).sqrt() } else { 0.0 };
    Estimate { node, relative, energy: norm }
}

/// Dörfler marking: the fewest nodes (largest `η_I²` first; ties by index) whose `η_I²` sum
/// to at least `fraction · Σ η_I²`. None when the estimate is zero.
pub fn mark(eta2: &[f64], fraction: f64) -> Vec<usize> {
    let total: f64 = eta2.iter().sum();
    if total <= 0.0 {
        return Vec::new();
    }
    let mut order: Vec<usize> = (0..eta2.len()).collect();
    order.sort_by(|&a, &b| eta2[b].total_cmp(&eta2[a]).then(a.cmp(&b)));
    let mut sum = 0.0;
    let mut marked = Vec::new();
    for i in order {
        if sum >= fraction * total {
            break;
        }
        sum += eta2[i];
        marked.push(i);
    }
    marked
}

/// The nodes of the contact candidates next to a change of state along the contact edge:
/// open/closed, and with friction stick/slip; the two candidates on either side of each
/// change (so that the onset's bracket is halved by each refinement).
pub fn contact_marks(solution: &Solution) -> Vec<usize> {
    let Some(c) = &solution.contact else { return Vec::new() };
    let mut marked: Vec<usize> =
        transition_candidates(solution).iter().map(|&k| c.candidates.nodes[k] as usize).collect();
    marked.sort_unstable();
    marked.dedup();
    marked
}

/// The candidates (indices into the contact table) of [`contact_marks`]: the two on either
/// side of every change of state along the contact edge, ascending.
pub fn transition_candidates(solution: &Solution) -> Vec<usize> {
    solution.contact.as_ref().map_or_else(Vec::new, transitions_of)
}

/// [`transition_candidates`] of one contact solution (one pair's).
fn transitions_of(c: &ContactSolution) -> Vec<usize> {
    let mut order: Vec<usize> = (0..c.candidates.len()).collect();
    order.sort_by(|&a, &b| c.candidates.arc_length[a].total_cmp(&c.candidates.arc_length[b]));
    let state = |k: usize| -> u8 {
        match c.friction.as_ref().map(|f| f.step.state[k]) {
            Some(ContactState::Open) => 0,
            Some(ContactState::Stick) => 1,
            Some(ContactState::SlipPositive | ContactState::SlipNegative) => 2,
            None => u8::from(c.closed[k]),
        }
    };
    let mut marked = Vec::new();
    for w in 1..order.len() {
        if state(order[w - 1]) != state(order[w]) {
            let lo = w.saturating_sub(2);
            let hi = (w + 2).min(order.len());
            marked.extend_from_slice(&order[lo..hi]);
        }
    }
    marked.sort_unstable();
    marked.dedup();
    marked
}

/// The second body's nodes to refine where the first body's contact marks lie: for each
/// `point` of the first body's contact edge, its closest point `y` on the target edge `edge`
/// of `domain` (the pairing of docs/method.md §4.3), and the target edge's nodes of `nodes`
/// next to `y` on either side along the edge (one node when `y` is a node, or lies beyond
/// the edge's last node). Ascending, without repeats.
pub fn paired_marks(domain: &Domain, edge: usize, nodes: &Nodes, points: &[Point]) -> Vec<usize> {
    let (a, b) = domain.edge(edge);
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let length2 = dx * dx + dy * dy;
    // The target edge's nodes by their parameter along the (straight) edge.
    let mut along: Vec<(f64, usize)> = (0..nodes.len())
        .filter(|&i| nodes.edges[i].contains(edge))
        .map(|i| {
            let p = nodes.points[i];
            (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2, i)
        })
        .collect();
    along.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    let mut marked = Vec::new();
    if along.is_empty() || length2 <= 0.0 || length2.is_nan() {
        return marked;
    }
    for x in points {
        let t = (((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / length2).clamp(0.0, 1.0);
        // The first node at or beyond `t`, and the one before it.
        let k = along.partition_point(|&(s, _)| s < t);
        if k < along.len() {
            marked.push(along[k].1);
        }
        if k > 0 && (k == along.len() || along[k].0 > t) {
            marked.push(along[k - 1].1);
        }
    }
    marked.sort_unstable();
    marked.dedup();
    marked
}

/// `problem` with the refinement regions around the `marked` nodes of `nodes` added
/// (`Refinement::around`; spacing at least the generator's finest, `h₀ / 4096`).
pub fn refined(problem: &Problem, nodes: &Nodes, marked: &[usize]) -> Problem {
    let floor = problem.node_spacing / f64::from(1u32 << nodes::MAX_LEVEL);
    let added =
        Refinement::around(marked.iter().map(|&i| (nodes.points[i], nodes.spacing[i])), floor);
    let mut next = problem.clone();
    next.refinement.boxes.extend(added.boxes);
    next
}

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
    let edge = problem.contact.as_ref().and_then(|c| match c.target {
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
    for k in 0..problem.body_count() {
        check_body(problem.body(k).unwrap_or(problem))?;
    }
    if let Some(p2) = problem.second_body.as_deref() {
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
                    None => estimate(p, m, s, adaptive.indicator),
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
        let onset = solved.solution.contact.as_ref().map(|c| &c.onset);
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
    let contact = solved.solution.contact.as_ref();
    let pairs = solved.solution.multibody.as_ref().map(|m| {
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
    let onset = solved.solution.contact.as_ref().map(|c| {
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

    #[test]
    fn dorfler_marks_the_fewest_nodes_carrying_the_fraction() {
        let eta2 = [1.0, 4.0, 0.5, 3.0, 1.5];
        // Σ = 10: 4 + 3 = 7 ≥ 6 (θ = 0.6); 4 + 3 + 1.5 = 8.5 ≥ 8 (θ = 0.8).
        assert_eq!(mark(&eta2, 0.6), vec![1, 3]);
        assert_eq!(mark(&eta2, 0.8), vec![1, 3, 4]);
        assert_eq!(mark(&eta2, 1.0).len(), 5);
        assert!(mark(&[0.0; 3], 0.5).is_empty());
    }

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
    fn paired_marks_are_the_target_nodes_on_either_side_of_the_closest_point() {
        // Target edge: the top of [0, 2] × [0, 1] (from (2, 1) to (0, 1)), nodes at x = 0,
        // 0.5, …, 2 on it, and interior nodes that must never be marked.
        let domain = Domain::rectangle([0.0, 2.0], [0.0, 1.0]).unwrap();
        let top = domain.edge_index("top").unwrap();
        let mut nodes = Nodes { points: Vec::new(), spacing: Vec::new(), edges: Vec::new() };
        for k in 0..5 {
            for (y, on_top) in [(1.0, true), (0.5, false)] {
                let mut tags = crate::nodes::EdgeSet::default();
                if on_top {
                    tags.insert(top);
                }
                nodes.points.push([0.5 * f64::from(k), y]);
                nodes.spacing.push(0.5);
                nodes.edges.push(tags);
            }
        }
        // Nodes on the top edge: x = 0 → 0, 0.5 → 2, 1 → 4, 1.5 → 6, 2 → 8.
        // A point above x = 0.7 pairs with (0.7, 1): the nodes at 0.5 and 1.
        assert_eq!(paired_marks(&domain, top, &nodes, &[[0.7, 1.01]]), vec![2, 4]);
        // Exactly above a node: that node only; beyond the edge: its end node.
        assert_eq!(paired_marks(&domain, top, &nodes, &[[1.5, 1.2]]), vec![6]);
        assert_eq!(paired_marks(&domain, top, &nodes, &[[2.3, 1.0]]), vec![8]);
        // Several points: the union, ascending.
        assert_eq!(paired_marks(&domain, top, &nodes, &[[0.2, 1.0], [1.9, 1.0]]), vec![0, 2, 6, 8]);
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
        cylinder.second_body = None;
        cylinder.contact = None;
        let arc = cylinder.domain.edge_index("arc").unwrap();
        p.second_body = Some(Box::new(cylinder));
        p.contact.as_mut().unwrap().target = ContactTarget::Body { edge: arc };
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
