//! Patch test (docs/method.md §3.7): a linear displacement field imposed on the whole boundary of
//! a square must be reproduced to round-off inside, with a linear MLS basis, on structured and
//! jittered nodes. Exact: `u = (a0 + a1 x + a2 y, b0 + b1 x + b2 y)`; constant strain, so
//! every cell's `∮ t dΓ = 0` and the collocated strains are exact. The stabilised blend of
//! docs/method.md §3.9 mixes two exact strains (collocated and direct MLS), so it must pass for
//! every `β`: checked for `β ∈ {0, 0.1, 0.5, 1}` at `α_s = 2`, and for `β ∈ {0.5, 1}` at
//! `α_s = 3` (a support the pure mixed method refuses).

use super::common::*;
use mlpg_contact::geometry::Domain;
use mlpg_contact::nodes::Layout;
use std::sync::Arc;

/// Relative max-norm error bound: round-off with a margin (condition of K ~ 1e4–1e6).
const TOLERANCE: f64 = 1e-10;

/// Blends checked at `α_s = 2`.
const BETAS: [f64; 4] = [0.0, 0.1, 0.5, 1.0];

fn exact(p: [f64; 2]) -> [f64; 2] {
    [1e-3 * (1.0 + 2.0 * p[0] - 3.0 * p[1]), 1e-3 * (-0.5 + 1.5 * p[0] + 0.7 * p[1])]
}

fn run(layout: Layout, beta: f64, support_factor: f64) -> f64 {
    let domain = Domain::rectangle([0.0, 2.0], [0.0, 2.0]).unwrap();
    let mut problem = base_problem(domain, 0.2, layout, plane_stress(1000.0, 0.3));
    problem.discretisation.beta = beta;
    problem.discretisation.mls.support_factor = support_factor;
    let u: VectorField = Arc::new(exact);
    problem.boundary = vec![displacement(u); 4];
    let s = mlpg_contact::solve(&problem).unwrap();
    let scale = 1e-3 * 6.0;
    let nodes =
        mlpg_contact::nodes::generate(&problem.domain, problem.node_spacing, problem.layout)
            .unwrap();
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
    let cases = BETAS.iter().map(|&b| (b, 2.0)).chain([(0.5, 3.0), (1.0, 3.0)]);
    for (beta, alpha) in cases {
        let err = run(layout, beta, alpha);
        println!("{name}, α_s = {alpha}, β = {beta}: {err:.3e}");
        assert!(err < TOLERANCE, "{name} patch test error {err:.3e} at α_s = {alpha}, β = {beta}");
    }
}

#[test]
fn patch_test_structured() {
    check("structured", Layout::Structured);
}

#[test]
fn patch_test_jittered() {
    check("jittered", Layout::Jittered { amplitude: 0.3, seed: 5 });
}
