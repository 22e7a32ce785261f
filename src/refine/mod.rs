//! Stage 10: the a posteriori error estimate, the marks and the refined problem that the
//! adaptive loop ([`crate::pipeline::adaptive`]) takes between two solves (docs/method.md §2.2).
//!
//! - **Estimate** ([`estimate`]): an error indicator `η_I` per node from one MFVM solution
//!   ([`Indicator`]), and the relative global estimate `(Σ η_I² / Σ h_I² ε̂_Iᵀ D ε̂_I)^(1/2)`;
//!   for an FE body the recovery estimate per element ([`fem::estimate`]).
//! - **Mark** ([`mark`]): Dörfler bulk marking — the fewest nodes whose `η_I²` sum to at least
//!   `θ Σ η_I²`; and [`contact_marks`]: the candidates next to an open/closed (or stick/slip)
//!   transition, which the bulk estimate does not see (the onset is where the contact
//!   solution is least smooth); [`paired_marks`] carries them to an elastic target's edge.
//! - **Refine** ([`refined`]): every marked node becomes a refinement region of the graded
//!   generator (`Refinement::around`: spacing `h_I/2` within `h_I` of the node), and the node
//!   set is regenerated from scratch (its layout quality is the generator's); an FE body's
//!   marked elements become regions of its graded grid ([`fem::refined`]).

use crate::geometry::{Domain, Point};
use crate::lcp::ContactState;
use crate::material::Hoop;
use crate::model::Model;
use crate::nodes::{self, Nodes};
use crate::problem::{Indicator, Problem, Refinement};
use crate::solution::{ContactSolution, Solution};

pub mod fem;

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
    let Some(c) = solution.contact() else { return Vec::new() };
    let mut marked: Vec<usize> =
        transition_candidates(solution).iter().map(|&k| c.candidates.nodes[k] as usize).collect();
    marked.sort_unstable();
    marked.dedup();
    marked
}

/// The candidates (indices into the contact table) of [`contact_marks`]: the two on either
/// side of every change of state along the contact edge, ascending.
pub fn transition_candidates(solution: &Solution) -> Vec<usize> {
    solution.contact().map_or_else(Vec::new, transitions_of)
}

/// [`transition_candidates`] of one contact solution (one pair's).
pub fn transitions_of(c: &ContactSolution) -> Vec<usize> {
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
}
