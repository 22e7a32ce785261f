//! Stage 14: adaptive node refinement (docs/method.md §2.2) — solve, estimate, mark, refine.
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

use crate::error::Error;
use crate::lcp::ContactState;
use crate::model::Model;
use crate::nodes::{self, Nodes};
use crate::post::summary::{AdaptiveStep, AdaptiveSummary, OnsetEstimate};
use crate::problem::{Adaptive, Indicator, Problem, Refinement};
use crate::progress::Progress;
use crate::solution::Solution;

/// An error estimate from one solution.
#[derive(Clone, Debug)]
pub struct Estimate {
    /// `η_I²` per node.
    pub node: Vec<f64>,
    /// The relative global estimate `(Σ η_I² / Σ h_I² ε̂_Iᵀ D ε̂_I)^(1/2)`.
    pub relative: f64,
}

/// `aᵀ D a` for a strain-like triple `a`.
fn energy(d: &crate::material::Constitutive, a: [f64; 3]) -> f64 {
    (0..3).map(|i| a[i] * (0..3).map(|j| d[i][j] * a[j]).sum::<f64>()).sum()
}

/// The error indicator of `indicator` at every node of an MFVM solution (docs/method.md
/// §2.2). Needs the node shape functions with gradients (as the MFVM model has them).
pub fn estimate(
    problem: &Problem,
    model: &Model,
    solution: &Solution,
    indicator: Indicator,
) -> Estimate {
    let d = problem.material.constitutive();
    let (shapes, eps, h) = (&model.node_shapes, &solution.strain, &model.nodes.spacing);
    let mut node = Vec::with_capacity(eps.len());
    let mut norm = 0.0;
    for (i, e) in eps.iter().enumerate() {
        let area = h[i] * h[i];
        norm += area * energy(&d, *e);
        let support = shapes.support(i);
        let eta2 = match indicator {
            Indicator::Recovery => {
                let mut s = [0.0; 3];
                for (&j, &phi) in support.iter().zip(shapes.phi(i)) {
                    for c in 0..3 {
                        s[c] += phi * eps[j as usize][c];
                    }
                }
                area * energy(&d, [s[0] - e[0], s[1] - e[1], s[2] - e[2]])
            }
            Indicator::Gradient => {
                let (dx, dy) = shapes.grad(i);
                let (mut gx, mut gy) = ([0.0; 3], [0.0; 3]);
                for ((&j, &a), &b) in support.iter().zip(dx).zip(dy) {
                    for c in 0..3 {
                        gx[c] += a * eps[j as usize][c];
                        gy[c] += b * eps[j as usize][c];
                    }
                }
                area * area * (energy(&d, gx) + energy(&d, gy))
            }
        };
        node.push(eta2);
    }
    let total: f64 = node.iter().sum();
    let relative = if norm > 0.0 { (total / norm).sqrt() } else { 0.0 };
    Estimate { node, relative }
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
            marked.extend(order[lo..hi].iter().map(|&k| c.candidates.nodes[k] as usize));
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
    /// The problem of the final node set.
    pub problem: Problem,
    /// The final model.
    pub model: Model,
    /// The final solution.
    pub solution: Solution,
    /// The loop's record (`summary.json`'s `refinement`).
    pub summary: AdaptiveSummary,
}

/// Solves `problem` adaptively with the parameters `adaptive` (docs/method.md §2.2): solve,
/// estimate, stop (tolerance, steps), mark, refine, stop when the refined node set would
/// exceed `max_nodes`, repeat. `observe` sees every solve (for studies). One progress line
/// per solve.
///
/// # Errors
/// [`Error::Problem`] for two bodies, the FE method or a domain with holes (what
/// `[refinement]`'s validation refuses); any stage's error of any solve.
pub fn solve_adaptive(
    problem: &Problem,
    adaptive: &Adaptive,
    progress: &mut dyn Progress,
    observe: &mut dyn FnMut(&Problem, &Model, &Solution, &Estimate),
) -> Result<AdaptiveRun, Error> {
    let refuse = |reason: &str| -> Result<AdaptiveRun, Error> {
        Err(crate::problem::ProblemError::Invalid {
            field: "refinement".into(),
            value: problem.name.clone(),
            reason: reason.into(),
        }
        .into())
    };
    if problem.second_body.is_some() {
        return refuse("adaptive refinement is implemented for one body");
    }
    if problem.discretisation.method != crate::problem::Method::Mfvm {
        return refuse("adaptive refinement needs method = \"mfvm\"");
    }
    if problem.domain.has_holes() {
        return refuse("adaptive refinement is not implemented for domains with holes");
    }
    let mut current = problem.clone();
    current.adaptive = None;
    let mut rows: Vec<AdaptiveStep> = Vec::new();
    let mut step = 0;
    loop {
        progress.section(&format!(
            "refinement step {step} of at most {}: {} refinement regions",
            adaptive.steps,
            current.refinement.boxes.len()
        ));
        let (model, second) = super::discretise_all(&current, progress)?;
        let (model, _, solution) = super::solve_model(&current, model, second, progress)?;
        let est = estimate(&current, &model, &solution, adaptive.indicator);
        observe(&current, &model, &solution, &est);
        let contact = solution.contact.as_ref();
        let mut row = AdaptiveStep {
            step,
            nodes: model.nodes.len(),
            min_spacing: model.nodes.spacing.iter().copied().fold(f64::INFINITY, f64::min),
            estimated_error: est.relative,
            marked: 0,
            marked_contact: 0,
            total_contact_force: contact.map(|c| c.total_force),
            onset_x: contact.and_then(|c| c.onset.from_gap),
            last_open_x: contact.and_then(|c| c.onset.last_open),
            first_closed_x: contact.and_then(|c| c.onset.first_closed),
        };
        let opt = |v: Option<f64>| v.map_or_else(|| "–".to_string(), |v| format!("{v:.6}"));
        progress.section(&format!(
            "refinement step {step}: {} nodes, estimated error {:.3e}, contact force {}, onset {} in [{}, {}]",
            row.nodes,
            row.estimated_error,
            opt(row.total_contact_force),
            opt(row.onset_x),
            opt(row.last_open_x),
            opt(row.first_closed_x)
        ));
        let stop =
            |why: &'static str, rows: Vec<AdaptiveStep>, p: Problem, m: Model, s: Solution| {
                let onset = s.contact.as_ref().map(|c| {
                    let o = &c.onset;
                    OnsetEstimate {
                        estimate: o.from_gap,
                        estimator: if o.from_gap == o.from_gap_raw {
                            "gap_extrapolation"
                        } else {
                            "clipped"
                        },
                        last_open_x: o.last_open,
                        first_closed_x: o.first_closed,
                        bracket_width: o.last_open.zip(o.first_closed).map(|(a, b)| b - a),
                    }
                });
                let summary =
                    AdaptiveSummary { parameters: *adaptive, stopped_by: why, steps: rows, onset };
                Ok(AdaptiveRun { problem: p, model: m, solution: s, summary })
            };
        if adaptive.tolerance.is_some_and(|t| est.relative <= t) {
            rows.push(row);
            return stop("tolerance", rows, current, model, solution);
        }
        if step == adaptive.steps {
            rows.push(row);
            return stop("steps", rows, current, model, solution);
        }
        let mut marked = mark(&est.node, adaptive.fraction);
        let bulk = marked.len();
        if adaptive.contact {
            marked.extend(contact_marks(&solution));
            marked.sort_unstable();
            marked.dedup();
        }
        row.marked = marked.len();
        row.marked_contact = marked.len() - bulk;
        if marked.is_empty() {
            rows.push(row);
            return stop("no_marks", rows, current, model, solution);
        }
        let next = refined(&current, &model.nodes, &marked);
        // The generator refuses only sets beyond its own size limits: too many as well.
        let too_many = nodes::for_problem(&next).map_or(true, |n| n.len() > adaptive.max_nodes);
        if too_many {
            row.marked = 0;
            row.marked_contact = 0;
            rows.push(row);
            return stop("max_nodes", rows, current, model, solution);
        }
        rows.push(row);
        current = next;
        step += 1;
    }
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

    #[test]
    fn the_loop_refuses_what_validation_refuses() {
        let text = |method: &str| {
            format!(
                "[geometry]\nkind = \"rectangle\"\nx = [0.0, 4.0]\ny = [0.0, 1.0]\n[nodes]\nspacing = 0.25\n[material]\nyoung = 1000.0\npoisson = 0.3\nplane = \"stress\"\n[discretisation]\nmethod = \"{method}\"\n[[boundary]]\nedge = \"left\"\ndisplacement = {{ x = 0.0, y = 0.0 }}\n[[boundary]]\nedge = \"right\"\ntraction = {{ y = 1.0 }}"
            )
        };
        let a = Adaptive {
            steps: 1,
            max_nodes: 1000,
            tolerance: None,
            fraction: 0.5,
            indicator: Indicator::Gradient,
            contact: true,
        };
        let fem = Problem::from_toml(&text("fem")).unwrap();
        let mut silent = crate::Silent;
        let Err(e) = solve_adaptive(&fem, &a, &mut silent, &mut |_, _, _, _| {}) else {
            panic!("the FE path must be refused");
        };
        assert!(e.to_string().contains("`refinement`"), "{e}");
        let mfvm = Problem::from_toml(&text("mfvm")).unwrap();
        let run = solve_adaptive(&mfvm, &a, &mut silent, &mut |_, _, _, _| {}).unwrap();
        assert_eq!(run.summary.steps.len(), 2);
        assert!(run.summary.steps[1].nodes > run.summary.steps[0].nodes);
        assert!(run.summary.onset.is_none());
        assert_eq!(run.summary.stopped_by, "steps");
    }
}
