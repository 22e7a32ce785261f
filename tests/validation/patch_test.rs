//! Patch test (docs/method.md §3.7): a linear displacement field imposed on the whole boundary of
//! a square must be reproduced to round-off inside, with a linear MLS basis, on structured and
//! jittered nodes. Exact: `u = (a0 + a1 x + a2 y, b0 + b1 x + b2 y)`; constant strain, so
//! every cell's `∮ t dΓ = 0` and the collocated strains are exact. The stabilised blend of
//! docs/method.md §3.9 mixes two exact strains (collocated and direct MLS), so it must pass for
//! every `β`: checked for `β ∈ {0, 0.1, 0.5, 1}` at `α_s = 2`, and for `β ∈ {0.5, 1}` at
//! `α_s = 3` (a support the pure mixed method refuses).
//!
//! Graded node sets (docs/method.md §2.1) must pass too: the MLS consistency and the cell
//! tiling do not depend on the node spacing being uniform, so the same bound holds on three
//! gradings (a band along an edge, a box two levels finer, both), structured and jittered;
//! and on a node set refined by the adaptive loop (docs/method.md §2.2). Curved domains too
//! (the Hertz quarter cylinder: two arcs and two segments), graded along the contact arc and
//! in a box across the second arc, where the boundary nodes, the inner layer and the lattice
//! all change spacing (`nodes::generate_graded_curved`).

use super::common::*;
use mlpg_contact::geometry::Domain;
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{RefineBox, Refinement};
use std::sync::Arc;

/// Relative max-norm error bound: round-off with a margin (condition of K ~ 1e4–1e6).
const TOLERANCE: f64 = 1e-10;

/// Blends checked at `α_s = 2`.
const BETAS: [f64; 4] = [0.0, 0.1, 0.5, 1.0];

fn exact(p: [f64; 2]) -> [f64; 2] {
    [1e-3 * (1.0 + 2.0 * p[0] - 3.0 * p[1]), 1e-3 * (-0.5 + 1.5 * p[0] + 0.7 * p[1])]
}

fn run_graded(layout: Layout, refinement: Refinement, beta: f64, support_factor: f64) -> f64 {
    let domain = Domain::rectangle([0.0, 2.0], [0.0, 2.0]).unwrap();
    run_graded_on(domain, 0.2, layout, refinement, beta, support_factor)
}

/// The patch test on `domain` at the nominal spacing `h0` (every edge held by the exact field).
pub(super) fn run_graded_on(
    domain: Domain,
    h0: f64,
    layout: Layout,
    refinement: Refinement,
    beta: f64,
    support_factor: f64,
) -> f64 {
    let edges = domain.edge_count();
    let mut problem = base_problem(domain, h0, layout, plane_stress(1000.0, 0.3));
    problem.refinement = refinement;
    problem.discretisation.beta = beta;
    problem.discretisation.mls.support_factor = support_factor;
    let u: VectorField = Arc::new(exact);
    problem.boundary = vec![displacement(u); edges];
    let s = mlpg_contact::solve(&problem).unwrap();
    let scale = 1e-3 * 6.0;
    let nodes = mlpg_contact::nodes::for_problem(&problem).unwrap();
    nodes
        .points
        .iter()
        .zip(&s.displacement)
        .map(|(p, u)| {
            let e = exact(*p);
            (u[0] - e[0]).abs().max((u[1] - e[1]).abs()) / scale
        })
        .fold(0.0, f64::max)
}

fn check(name: &str, layout: Layout) {
    check_graded(name, layout, Refinement::default());
}

fn check_graded(name: &str, layout: Layout, refinement: Refinement) {
    let cases = BETAS.iter().map(|&b| (b, 2.0)).chain([(0.5, 3.0), (1.0, 3.0)]);
    for (beta, alpha) in cases {
        let err = run_graded(layout, refinement.clone(), beta, alpha);
        println!("{name}, α_s = {alpha}, β = {beta}: {err:.3e}");
        assert!(err < TOLERANCE, "{name} patch test error {err:.3e} at α_s = {alpha}, β = {beta}");
    }
}

/// The gradings of the graded patch tests on the square `[0, 2]²` at `h₀ = 0.2`: a band of
/// `h₀/2` along the bottom edge, a box of `h₀/4` off-centre (two transition levels), and both.
fn gradings() -> [(&'static str, Refinement); 3] {
    let band = RefineBox { x: [0.0, 2.0], y: [0.0, 0.3], spacing: 0.1 };
    let inner = RefineBox { x: [0.7, 1.1], y: [1.2, 1.5], spacing: 0.05 };
    [
        ("band", Refinement { boxes: vec![band] }),
        ("box", Refinement { boxes: vec![inner] }),
        ("band+box", Refinement { boxes: vec![band, inner] }),
    ]
}

#[test]
fn patch_test_structured() {
    check("structured", Layout::Structured);
}

#[test]
fn patch_test_jittered() {
    check("jittered", Layout::Jittered { amplitude: 0.3, seed: 5 });
}

#[test]
fn patch_test_graded_structured() {
    for (name, refinement) in gradings() {
        check_graded(&format!("graded {name}, structured"), Layout::Structured, refinement);
    }
}

#[test]
fn patch_test_graded_jittered() {
    for (name, refinement) in gradings() {
        let layout = Layout::Jittered { amplitude: 0.3, seed: 5 };
        check_graded(&format!("graded {name}, jittered"), layout, refinement);
    }
}

/// The refinement regions the adaptive loop (docs/method.md §2.2) builds on the square
/// clamped on the left and sheared on the right (corner singularities at the clamp): three
/// steps, gradient indicator, `θ = 0.5`, `β = 0.5`. The patch test then runs on that grading.
fn adaptive_grading(layout: Layout) -> Refinement {
    let domain = Domain::rectangle([0.0, 2.0], [0.0, 2.0]).unwrap();
    let mut problem = base_problem(domain, 0.2, layout, plane_stress(1000.0, 0.3));
    problem.discretisation.beta = 0.5;
    problem.boundary[3] = displacement(Arc::new(|_| [0.0, 0.0]));
    problem.boundary[1] = traction(Arc::new(|_| [0.0, 1.0]));
    let adaptive = mlpg_contact::problem::Adaptive {
        steps: 3,
        max_nodes: 100_000,
        fraction: 0.5,
        indicator: mlpg_contact::problem::Indicator::Gradient,
        contact: false,
        ..mlpg_contact::problem::Adaptive::default()
    };
    let mut silent = mlpg_contact::Silent;
    let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
        &problem,
        &adaptive,
        &mut silent,
        &mut |_, _, _, _| {},
    )
    .unwrap();
    assert_eq!(run.summary.steps.len(), 4);
    let levels = run.summary.steps[0].min_spacing / run.summary.steps[3].min_spacing;
    assert!(levels >= 4.0, "finest spacing only {levels} times finer");
    run.problem.refinement
}

#[test]
fn patch_test_adaptively_refined() {
    for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 5 }] {
        let refinement = adaptive_grading(layout);
        check_graded(&format!("adaptive, {layout:?}"), layout, refinement);
    }
}

/// The Hertz quarter cylinder (radius 1 about `(0, 1)`, the arc split at 30° from the bottom),
/// as `problems/hertz_cylinder.toml`.
fn quarter_cylinder() -> Domain {
    use mlpg_contact::geometry::Curve;
    let c = [0.0, 1.0];
    let split = [0.5, 1.0 - 0.75f64.sqrt()];
    Domain::from_curves(
        vec![
            Curve::arc_between([0.0, 0.0], split, c, true),
            Curve::arc_between(split, [1.0, 1.0], c, true),
            Curve::Segment { a: [1.0, 1.0], b: [0.0, 1.0] },
            Curve::Segment { a: [0.0, 1.0], b: [0.0, 0.0] },
        ],
        ["arc", "rim", "top", "axis"].iter().map(|s| s.to_string()).collect(),
    )
    .unwrap()
}

/// Gradings of the quarter cylinder at `h₀ = 0.1`: a box of `h₀/8` around the contact (three
/// transition levels along the arc, the layer and the lattice), and that with a box of `h₀/2`
/// across the rim, the `arc`–`rim` corner and the diameter.
fn curved_gradings() -> [(&'static str, Refinement); 2] {
    let contact = RefineBox { x: [0.0, 0.15], y: [0.0, 0.03], spacing: 0.0125 };
    let rim = RefineBox { x: [0.45, 0.9], y: [0.1, 0.95], spacing: 0.05 };
    [
        ("contact", Refinement { boxes: vec![contact] }),
        ("contact+rim", Refinement { boxes: vec![contact, rim] }),
    ]
}

fn check_graded_curved(layout: Layout) {
    for (name, refinement) in curved_gradings() {
        let cases = BETAS.iter().map(|&b| (b, 2.0)).chain([(0.5, 3.0), (1.0, 3.0)]);
        for (beta, alpha) in cases {
            let err =
                run_graded_on(quarter_cylinder(), 0.1, layout, refinement.clone(), beta, alpha);
            println!("quarter cylinder {name}, {layout:?}, α_s = {alpha}, β = {beta}: {err:.3e}");
            assert!(
                err < TOLERANCE,
                "quarter cylinder {name}, {layout:?}: patch test error {err:.3e} at α_s = {alpha}, β = {beta}"
            );
        }
    }
}

#[test]
fn patch_test_graded_curved_structured() {
    check_graded_curved(Layout::Structured);
}

#[test]
fn patch_test_graded_curved_jittered() {
    check_graded_curved(Layout::Jittered { amplitude: 0.3, seed: 5 });
}
