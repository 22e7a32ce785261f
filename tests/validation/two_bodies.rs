//! Two elastic bodies in frictionless contact (docs/method.md §4.3; paper eqs. 28–34):
//! `M = M_1 + M_2`, `q = g0 + G_1 K_1⁻¹ f_1 + G_2 K_2⁻¹ f_2`, the candidate body's force `+ν P`
//! and the target body's `−ν P` at the closest point of its edge.
//!
//! 1. Two identical blocks pressed together (top displacement `−δ`, rollers): the exact
//!    solution is uniaxial stress, contact pressure `p = E δ / (H_1 + H_2)` uniform. It is a
//!    linear field, so matching and non-matching layouts (the reaction spread over the target
//!    cells by overlap) must reproduce it to round-off: a contact patch test.
//! 2. Mirror symmetry: a block and its mirror image about `y = 0`, loaded symmetrically, give
//!    the same contact forces as the block alone on a rigid line at `y = 0`.
//!
//! The uniform-pressure case also for the stabilised blend (docs/method.md §3.9), `β = 1`
//! at `α_s = 2` and `β = 0.5` at `α_s = 3`, on both bodies.

use super::common::*;
use mlpg_contact::contact::{ContactSpec, ContactTarget, RigidLine};
use mlpg_contact::geometry::Domain;
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{ComponentCondition, EdgeCondition, Field, Problem, Refinement};

const YOUNG: f64 = 1000.0;
const PRESS: f64 = 0.01;

fn roller_x() -> ComponentCondition {
    ComponentCondition::Displacement(Field::Constant(0.0))
}
fn free() -> ComponentCondition {
    ComponentCondition::Traction(Field::Constant(0.0))
}

/// Edges of a rectangle: 0 bottom, 1 right, 2 top, 3 left.
fn block(y: [f64; 2], h: f64, top_uy: Option<Field>, bottom_uy: Option<Field>) -> Problem {
    let domain = Domain::rectangle([0.0, 2.0], y).unwrap();
    let mut p = base_problem(domain, h, Layout::Structured, plane_stress(YOUNG, 0.3));
    p.boundary[3] = EdgeCondition::Components([roller_x(), free()]);
    if let Some(f) = top_uy {
        p.boundary[2] = EdgeCondition::Components([free(), ComponentCondition::Displacement(f)]);
    }
    if let Some(f) = bottom_uy {
        p.boundary[0] = EdgeCondition::Components([free(), ComponentCondition::Displacement(f)]);
    }
    p
}

/// The two blocks pressed together, spacing `h_upper` above and `h_lower` below (also solved
/// by the active-set method in `active_set.rs`).
pub fn two_blocks(h_upper: f64, h_lower: f64) -> Problem {
    let mut upper = block([1.0, 2.0], h_upper, Some(Field::Constant(-PRESS)), None);
    let lower = block([0.0, 1.0], h_lower, None, Some(Field::Constant(0.0)));
    upper.set_contact(ContactSpec {
        edge: 0,
        target: ContactTarget::Body { edge: 2 },
        gap_tolerance: None,
        allow_indefinite: false,
        condensation: Default::default(),
        friction: 0.0,
        solver: Default::default(),
        interference: 0.0,
    });
    let mut lower = lower;
    lower.name = "lower".into();
    upper.with_second_body(lower)
}

fn pressures(problem: &Problem) -> (Vec<f64>, f64, f64) {
    let s = mlpg_contact::solve(problem).unwrap();
    let c = s.contact().unwrap();
    let r = &c.lcp.residuals;
    assert!(r.max_violation() < 1e-9, "KKT residuals {r:?}");
    assert!(s.equilibrium_error < 1e-9, "body 1 equilibrium {}", s.equilibrium_error);
    let s2 = s.body(1).unwrap();
    assert!(s2.equilibrium_error < 1e-9, "body 2 equilibrium {}", s2.equilibrium_error);
    // Action and reaction: the forces on the two bodies cancel.
    assert!((s.contact_force[1] + s2.contact_force[1]).abs() < 1e-12 * c.total_force);
    (c.pressure.clone(), c.total_force, c.condensed.as_ref().unwrap().skew_ratio)
}

#[test]
fn identical_blocks_give_uniform_pressure() {
    let exact = YOUNG * PRESS / 2.0;
    let (p, total, _) = pressures(&two_blocks(0.1, 0.1));
    let worst = p.iter().map(|v| (v / exact - 1.0).abs()).fold(0.0, f64::max);
    println!(
        "matching: max |p/p_exact − 1| = {worst:.3e}, total {total:.6} (exact {})",
        2.0 * exact
    );
    assert!(worst < 1e-8, "pressure not uniform: {worst:.3e}");
    assert!((total / (2.0 * exact) - 1.0).abs() < 1e-8);
}

/// Sets `α_s` and `β` on both bodies of a two-body problem.
pub fn with_variant(mut problem: Problem, support_factor: f64, beta: f64) -> Problem {
    for k in 0..problem.body_count() {
        let d = &mut problem.body_mut(k).expect("a body").discretisation;
        d.mls.support_factor = support_factor;
        d.beta = beta;
    }
    problem
}

#[test]
fn stabilised_blocks_give_uniform_pressure() {
    let exact = YOUNG * PRESS / 2.0;
    for (alpha, beta) in [(2.0, 1.0), (3.0, 0.5)] {
        for (h1, h2) in [(0.1, 0.1), (0.1, 0.125)] {
            let (p, total, skew) = pressures(&with_variant(two_blocks(h1, h2), alpha, beta));
            let worst = p.iter().map(|v| (v / exact - 1.0).abs()).fold(0.0, f64::max);
            println!(
                "α_s = {alpha}, β = {beta}, h = {h1}/{h2}: max |p/p_exact − 1| = {worst:.3e}, total {total:.6}, skew {skew:.2e}"
            );
            assert!(worst < 1e-8, "α_s = {alpha} β = {beta} h = {h1}/{h2}: {worst:.3e}");
            assert!((total / (2.0 * exact) - 1.0).abs() < 1e-8, "total {total}");
        }
    }
}

#[test]
fn non_matching_layouts() {
    let exact = YOUNG * PRESS / 2.0;
    let (p, total, skew) = pressures(&two_blocks(0.1, 0.125));
    let worst = p.iter().map(|v| (v / exact - 1.0).abs()).fold(0.0, f64::max);
    let mean = p.iter().sum::<f64>() / p.len() as f64;
    println!(
        "non-matching: max |p/p_exact − 1| = {worst:.3e}, mean {mean:.6}, total {total:.6} (exact {}), skew {skew:.2e}",
        2.0 * exact
    );
    // Round-off bound, as for the matching case (observed 3.8e-15). With the reaction put at
    // the closest point only, this case deviated by 33 % pointwise (measured during development).
    assert!((total / (2.0 * exact) - 1.0).abs() < 1e-8, "total {total}");
    assert!(worst < 1e-8, "pressure deviates by {worst:.3e}");
}

/// The block on a rigid line at `y = 0` and the same block on its mirror image (partial
/// contact).
pub fn mirror_problems() -> (Problem, Problem) {
    let (gap, d) = (0.01, 0.015);
    // Body 1 above y = 0; its top edge runs from x = 2 (t = 0) to x = 0 (t = 1).
    let top = Field::Linear { start: -d, end: -0.5 * d };
    let bottom = Field::Linear { start: 0.5 * d, end: d }; // mirror: x = 0 → 2
    let upper = |tag: &str| {
        let mut b = block([gap, 1.0 + gap], 0.1, Some(top.clone()), None);
        b.name = tag.into();
        b
    };
    let mut rigid = upper("rigid");
    rigid.set_contact(ContactSpec {
        edge: 0,
        target: ContactTarget::Rigid(RigidLine { point: [0.0, 0.0], normal: [0.0, 1.0] }),
        gap_tolerance: None,
        allow_indefinite: false,
        condensation: Default::default(),
        friction: 0.0,
        solver: Default::default(),
        interference: 0.0,
    });
    let mut pair = upper("upper");
    let mut mirror = block([-1.0 - gap, -gap], 0.1, None, Some(bottom));
    mirror.name = "mirror".into();
    pair.set_contact(ContactSpec {
        edge: 0,
        target: ContactTarget::Body { edge: 2 },
        gap_tolerance: None,
        allow_indefinite: false,
        condensation: Default::default(),
        friction: 0.0,
        solver: Default::default(),
        interference: 0.0,
    });
    (rigid, pair.with_second_body(mirror))
}

#[test]
fn mirror_image_equals_rigid_line() {
    let (rigid, pair) = mirror_problems();
    let a = mlpg_contact::solve(&rigid).unwrap();
    let b = mlpg_contact::solve(&pair).unwrap();
    let (ca, cb) = (a.contact().unwrap(), b.contact().unwrap());
    assert_eq!(ca.lcp.z.len(), cb.lcp.z.len());
    let scale = ca.lcp.z.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = ca.lcp.z.iter().zip(&cb.lcp.z).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    println!(
        "mirror: total {:.6} vs rigid {:.6}, closed {}/{}, max |ΔP|/max P = {:.3e}",
        cb.total_force,
        ca.total_force,
        ca.closed.iter().filter(|&&c| c).count(),
        ca.closed.len(),
        worst / scale
    );
    assert!(ca.closed.iter().any(|&c| c) && ca.closed.iter().any(|&c| !c), "want partial contact");
    assert!(worst < 1e-9 * scale, "forces differ by {worst:.3e}");
}

/// Graded node sets (docs/method.md §2.1) on both blocks, refined along the contact edges
/// (upper: 0.05 within 0.2 of its bottom, h₀ = 0.1; lower: 0.0625 within 0.25 of its top,
/// h₀ = 0.125): the uniaxial solution is linear, so the pressure must stay uniform and exact
/// to round-off (the patch-test argument), for the paper's `β = 0` and the blend `β = 0.5`.
#[test]
fn graded_blocks_give_uniform_pressure() {
    use mlpg_contact::problem::RefineBox;
    let exact = YOUNG * PRESS / 2.0;
    for beta in [0.0, 0.5] {
        let mut problem = with_variant(two_blocks(0.1, 0.125), 2.0, beta);
        problem.refinement =
            Refinement { boxes: vec![RefineBox { x: [0.0, 2.0], y: [1.0, 1.2], spacing: 0.05 }] };
        if let Some(lower) = problem.body_mut(1) {
            lower.refinement = Refinement {
                boxes: vec![RefineBox { x: [0.0, 2.0], y: [0.75, 1.0], spacing: 0.0625 }],
            };
        }
        let (p, total, _) = pressures(&problem);
        let worst = p.iter().map(|v| (v / exact - 1.0).abs()).fold(0.0, f64::max);
        println!("graded, β = {beta}: {} candidates, max |p/p_exact − 1| = {worst:.3e}", p.len());
        assert_eq!(p.len(), 41, "candidates at the refined spacing 0.05");
        assert!(worst < 1e-8, "β = {beta}: pressure not uniform: {worst:.3e}");
        assert!((total / (2.0 * exact) - 1.0).abs() < 1e-8, "total {total}");
    }
}

/// The refinement regions the adaptive loop (docs/method.md §2.2) builds for the two blocks of
/// [`two_blocks`] (spacings 0.2 above, 0.25 below: non-matching) when the upper block's top is
/// tilted (moved by `−δ` at `x = 2` and `+δ` at `x = 0`): partial contact, so both the bulk
/// marks and the contact marks (the first block's transition candidates and the lower block's
/// nodes at their paired points) take part. Three steps, gradient indicator, `θ = 0.5`,
/// `β = 0.5`; each body refines on its own.
fn adaptive_gradings(layout: Layout) -> (Refinement, Refinement) {
    let mut problem = with_variant(two_blocks(0.2, 0.25), 2.0, 0.5);
    problem.layout = layout;
    let top = Field::Linear { start: -PRESS, end: PRESS };
    problem.boundary[2] =
        EdgeCondition::Components([free(), ComponentCondition::Displacement(top)]);
    if let Some(lower) = problem.body_mut(1) {
        lower.layout = layout;
    }
    let adaptive = mlpg_contact::problem::Adaptive {
        steps: 3,
        max_nodes: 100_000,
        fraction: 0.5,
        indicator: mlpg_contact::problem::Indicator::Gradient,
        contact: true,
        ..mlpg_contact::problem::Adaptive::default()
    };
    let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
        &problem,
        &adaptive,
        &mut mlpg_contact::Silent,
        &mut |_, _, s, _| {
            let c = s.contact().unwrap();
            assert!(c.closed.iter().any(|&b| b) && c.closed.iter().any(|&b| !b), "partial contact");
        },
    )
    .unwrap();
    let steps = &run.summary.steps;
    assert_eq!(steps.len(), 4);
    for row in steps {
        println!("{layout:?} step {}: {:?}", row.step, row.bodies);
    }
    for row in &steps[..3] {
        let bodies = row.bodies.as_ref().unwrap();
        assert!(bodies.iter().all(|b| b.marked > 0), "step {}: {bodies:?}", row.step);
    }
    // The paired marks add nodes beyond the lower block's bulk marks at least once.
    let paired: usize = steps.iter().map(|r| r.bodies.as_ref().unwrap()[1].marked_contact).sum();
    assert!(paired > 0, "no paired marks beyond the bulk marks");
    let last = steps[3].bodies.as_ref().unwrap();
    for (b, h0) in last.iter().zip([0.2, 0.25]) {
        assert!(h0 / b.min_spacing >= 4.0, "{}: finest spacing {}", b.name, b.min_spacing);
    }
    let lower = run.problem.body(1).unwrap().refinement.clone();
    (run.problem.refinement, lower)
}

/// The contact patch test on adaptively refined, non-matching node sets: the two blocks
/// pressed uniformly (exact: uniaxial stress, `p = E δ / 2`) on the gradings of
/// [`adaptive_gradings`], structured and jittered, for the blends `β = 0.5` and `1`
/// (`α_s = 2`) and `β = 0.5` at `α_s = 3`: the pressure must be uniform to round-off, both
/// bodies in equilibrium, complementarity satisfied (checked by [`pressures`]). The paper's
/// `β = 0` is left out: on these gradings (2:1 transitions next to the contact edges) its
/// `M` is indefinite (smallest eigenvalue of the symmetric part −8.8e-3 on the structured
/// grading) and the run stops at the check of docs/method.md §4.1, as on the one-body graded
/// beam (docs/method.md §2.1).
#[test]
fn adaptively_graded_blocks_give_uniform_pressure() {
    let exact = YOUNG * PRESS / 2.0;
    for layout in [Layout::Structured, Layout::Jittered { amplitude: 0.3, seed: 5 }] {
        let (upper, lower) = adaptive_gradings(layout);
        for (alpha, beta) in [(2.0, 0.5), (2.0, 1.0), (3.0, 0.5)] {
            let mut problem = with_variant(two_blocks(0.2, 0.25), alpha, beta);
            problem.layout = layout;
            problem.refinement = upper.clone();
            if let Some(p2) = problem.body_mut(1) {
                p2.layout = layout;
                p2.refinement = lower.clone();
            }
            let (p, total, _) = pressures(&problem);
            let worst = p.iter().map(|v| (v / exact - 1.0).abs()).fold(0.0, f64::max);
            println!(
                "adaptive grading {layout:?}, α_s = {alpha}, β = {beta}: {} candidates, max |p/p_exact − 1| = {worst:.3e}",
                p.len()
            );
            assert!(worst < 1e-8, "{layout:?} α_s = {alpha} β = {beta}: {worst:.3e}");
            assert!((total / (2.0 * exact) - 1.0).abs() < 1e-8, "total {total}");
        }
    }
}
