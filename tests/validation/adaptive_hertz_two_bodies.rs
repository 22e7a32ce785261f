//! Adaptive refinement (docs/method.md §2.2) of two bodies, the first curved, against uniform
//! node sets: `problems/hertz_two_bodies_adaptive.toml`, the elastic quarter cylinder
//! (`R = 1`, plane strain) of `hertz.rs` pressed by `δ = 0.0017` on its top onto an elastic
//! block `[0, 1.5] × [−1, 0]` of the same material (docs/method.md §4.3), the loop from the
//! uniform spacing 0.05 on both bodies (the cylinder's sets by `nodes::generate_graded_curved`,
//! the block's by `nodes::generate_graded`). Reference: Hertz (Hertz 1882; Johnson, *Contact
//! Mechanics* (1985), §4.3, eqs. 4.43–4.45), `a = √(4PR/(πE*))`, `p₀ = 2P/(πa)` with
//! `1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂` for the computed resultant `P = 2 Σ P_c` per unit
//! length, measured by `hertz::measure` (least-squares fit of `p²` against `x²` over the
//! closed candidates; complementarity, `M` positive definite, the cylinder's equilibrium and
//! one closed zone checked at every measured step), with the block's equilibrium, the balance
//! of the contact force against the reaction on the pushed top, and the two bodies' contact
//! forces equal and opposite.
//!
//! The finite block: as in `hertz::hertz_two_elastic_bodies`, the Hertz a–P relation is that
//! of two half-planes and does not feel the block's size to first order; here the block is
//! about 33 contact half-widths deep (`a ≈ 0.03`), three times the depth ratio of that test.
//! The indentation is the rigid-flat study's (`adaptive_hertz_cylinder.rs`), chosen before
//! any run for `a/R ≈ 0.03`, where the rigid studies found the converged answer within 0.4 %
//! of Hertz.
//!
//! The requirement: `a` and `p₀` within 0.5 % of Hertz with at most a fifth of the nodes the
//! uniform layout (both bodies at one spacing) needs for the same error.

use super::common::shipped_problem;
use super::hertz::{
    Outcome, adaptive_rows, assert_uniform_sets_miss, measure, uniform_spacings_up_to,
};
use mlpg_contact::lcp::ContactState;

/// The requirement's bound on the relative errors of `a` and `p₀`.
const BOUND: f64 = 0.005;
/// The requirement's node ratio: adaptive needs at most a fifth of the uniform nodes.
const RATIO: usize = 5;

/// Both bodies' node count of a solution.
fn nodes(s: &mlpg_contact::Solution) -> usize {
    s.displacement.len() + s.body(1).unwrap().displacement.len()
}

/// Checks both bodies' equilibrium and the force balances and measures the Hertz quantities
/// (`None` with fewer than four closed candidates, which the fit needs).
fn checked(label: &str, s: &mlpg_contact::Solution) -> Option<Outcome> {
    let c = s.contact().unwrap();
    let s2 = s.body(1).unwrap();
    assert!(s2.equilibrium_error < 1e-8, "{label}: block equilibrium {}", s2.equilibrium_error);
    let balance = s.reaction_force[1] + c.total_force;
    assert!(balance.abs() < 1e-8 * c.total_force, "{label}: cylinder balance {balance}");
    let pair = s.contact_force[1] + s2.contact_force[1];
    assert!(pair.abs() < 1e-12 * c.total_force, "{label}: contact forces differ by {pair}");
    let block = s2.reaction_force[1] + s2.contact_force[1];
    assert!(block.abs() < 1e-8 * c.total_force, "{label}: block balance {block}");
    let closed = c.closed.iter().filter(|&&b| b).count();
    // Equal materials: 1/E* = 2 (1 − ν²)/E.
    let e_star = 1.0 / (2.0 * (1.0 - 0.3 * 0.3));
    (closed >= 4).then(|| measure(label, s, e_star, 1.0, 2.0 * c.total_force))
}

/// The loop reaches the bound on its final node set, with every step's contact checked; the
/// uniform node sets (both bodies at one spacing) of at most `RATIO` times as many nodes as
/// its first set within the bound — the halvings of the initial spacing up to that count and
/// the uniform spacing with the most nodes up to it — all miss it, so the uniform layout needs
/// more than `RATIO` times the adaptive nodes.
#[test]
fn adaptive_cylinder_on_block_meets_hertz_with_a_fifth_of_the_uniform_nodes() {
    let problem = shipped_problem("hertz_two_bodies_adaptive.toml", 0.05);
    let (rows, stopped_by) = adaptive_rows(&problem, BOUND, |s| {
        let n = nodes(s);
        (n, checked(&format!("adaptive, {n} nodes"), s).as_ref().map(Outcome::max_error))
    });
    println!("stopped by {stopped_by}");
    // The comparison starts from the first node set within the bound.
    let first = rows.iter().find(|r| r.1.is_some_and(|e| e <= BOUND)).unwrap().0;

    // Uniform sets, both bodies at spacing h: halvings of the initial spacing while they have
    // at most RATIO × first nodes, and (bisection on h) the set with the most nodes up to it.
    let cap = RATIO * first;
    let block = problem.body(1).unwrap();
    let count = |h: f64| {
        let generate = |p: &mlpg_contact::problem::Problem| {
            mlpg_contact::nodes::generate(&p.domain, h, p.layout).unwrap().len()
        };
        generate(&problem) + generate(block)
    };
    let spacings = uniform_spacings_up_to(problem.node_spacing, cap, count);
    assert_uniform_sets_miss(&spacings, cap, BOUND, |h| {
        let mut uniform = problem.clone();
        uniform.adaptive = None;
        uniform.node_spacing = h;
        uniform.body_mut(1).unwrap().node_spacing = h;
        let s = mlpg_contact::solve(&uniform).unwrap();
        let e = checked(&format!("uniform h = {h:.5}"), &s).as_ref().map(Outcome::max_error);
        (nodes(&s), e)
    });
}

/// Cattaneo–Mindlin [Johnson 1985, §7.1] in the two-body loop: `problems/cattaneo_mindlin.toml`
/// (a cylinder cap of radius 1 pressed onto a block of the same material, plane strain,
/// μ = 0.3; pressed without friction, then sheared by 0.0023 in 4 increments with the press
/// held, `Q/μP ≈ 0.5`), with `β = 0.5` (graded sets need it, docs/method.md §2.1) and
/// `[refinement]` from the uniform spacing 0.02 on both bodies (10 closed candidates at the
/// start): gradient indicator, θ = 0.7, contact marks (at the final increment's open/stick/slip
/// transitions, so the stick zone's ends refine), 4 steps, at most 40 000 nodes. Parameters
/// chosen before any run; the start is the coarser spacing of `friction.rs`'s uniform study.
///
/// Measured as `friction::cattaneo_mindlin_two_similar_bodies` does: `a` from the pressure
/// profile, `c` from the stick zone's slack `μp − |q|`, both by the quadratic fit of
/// `friction::zone_from_fit`; the reference is `c/a = (1 − Q/μP)^{1/2}` for the computed `Q`
/// and `P`. Asserted on the final set: `c/a` within 1 % of it (the requirement), and at every
/// solve complementarity ≤ 1e-9 and equilibrium ≤ 1e-8 on both bodies at every increment,
/// the bodies' contact forces equal and opposite.
///
/// Observed: c/a error +9.7e-2, −5.8e-3, +7.6e-3, +7.6e-3 at 2 238, 2 912, 6 876, 20 668
/// nodes (stopped by `max_nodes`). The converged offset is the finite problem's, not the
/// discretisation's: the uniform h = 0.0025 (134 972 nodes) gives +5.9e-3 with β = 0.5 and
/// with β = 0 alike, and doubling the block (2.4 × 0.8) moves the loop's answer to +5.1e-3;
/// `friction.rs` estimates the finite bodies' effect on `c/a` below 0.005 absolute (0.7 %).
#[test]
fn adaptive_cattaneo_mindlin_stick_zone() {
    let mu = 0.3;
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/cattaneo_mindlin.toml"),
    )
    .unwrap();
    assert_eq!(text.matches("nodes = { spacing = 0.01 }").count(), 2);
    assert!(text.contains("displacement = { x = 0.0023 }"));
    let text = text.replace("nodes = { spacing = 0.01 }", "nodes = { spacing = 0.02 }");
    let head = &text[..text.find("\n[[step]]").unwrap()];
    let steps = &text[text.find("\n[[step]]").unwrap()..];
    let adaptive = "[discretisation]\nbeta = 0.5\n\n[refinement]\nsteps = 4\nmax_nodes = 40000\nfraction = 0.7\nindicator = \"gradient\"\ncontact = true\n";
    let problem =
        mlpg_contact::problem::Problem::from_toml(&format!("{head}\n{adaptive}{steps}")).unwrap();
    let settings = problem.adaptive.unwrap();
    let mut rows: Vec<(usize, f64, f64, f64)> = Vec::new();
    let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
        &problem,
        &settings,
        &mut mlpg_contact::Silent,
        &mut |_, _, s, _| {
            let n = nodes(s);
            let label = format!("adaptive Cattaneo–Mindlin, {n} nodes");
            super::friction::check_frictional(s, &label);
            super::friction::check_increments(s, &label);
            let s2 = s.body(1).unwrap();
            let total = s.contact().unwrap().total_force;
            for k in 0..2 {
                let pair = s.contact_force[k] + s2.contact_force[k];
                assert!(pair.abs() <= 1e-12 * total, "{label}: contact forces differ by {pair}");
            }
            let k = super::friction::read_contact(s);
            let ratio = k.total_q / (mu * k.total_p);
            let slack: Vec<f64> = k.p.iter().zip(&k.q).map(|(p, q)| mu * p - q.abs()).collect();
            let stick: Vec<bool> = k.state.iter().map(|&st| st == ContactState::Stick).collect();
            let (_, c, _) = super::friction::zone_from_fit(&k.x, &slack, &stick);
            let theory = (1.0 - ratio).sqrt();
            let error = (c / k.a - theory) / theory;
            let closed = k.p.iter().filter(|&&p| p > 0.0).count();
            println!(
                "{label}: P = {:.6}, Q/μP = {ratio:.4}, a = {:.5} (centre {:+.1e}), c/a = {:.4}, theory {theory:.4}, relative error {error:+.4}; {closed} closed, {} stick",
                k.total_p,
                k.a,
                k.centre,
                c / k.a,
                stick.iter().filter(|&&b| b).count()
            );
            rows.push((n, ratio, c / k.a, error));
        },
    )
    .unwrap();
    println!("stopped by {}: {rows:?}", run.summary.stopped_by);
    assert!(rows.windows(2).all(|w| w[1].0 > w[0].0), "{rows:?}");
    let &(n, ratio, _, error) = rows.last().unwrap();
    assert!((ratio - 0.5).abs() <= 0.03, "Q/μP = {ratio}, meant 0.5");
    assert!(error.abs() <= 0.01, "final c/a off by {error:+.4} with {n} nodes");
}
