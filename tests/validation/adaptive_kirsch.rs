//! Adaptive refinement (docs/method.md §2.2) against uniform node sets on the Kirsch quarter
//! plate of `kirsch.rs`: the quarter `[0, 5]²` outside the hole of radius `a = 1` (a concave
//! arc in the outer boundary), rollers on the symmetry lines, the exact traction of the
//! infinite plate under remote tension `σ₀ = 1` on `x = 5` and `y = 5`. With those tractions
//! Kirsch's closed form is the exact solution of this finite plate, so there is no truncation
//! error and no reference uncertainty. `β = 0.5` (graded sets need it, docs/method.md §2.1; the
//! uniform sets use it too), `α_s = 2`, structured nodes.
//!
//! Measure: the relative energy-norm error `‖σ^h − σ‖_{D⁻¹} / ‖σ‖_{D⁻¹}` by nodal quadrature
//! over the cells (`kirsch::measure`), the same on uniform and graded sets. The max-norm
//! displacement error is printed as well.
//!
//! The claim tested (the requirement: adaptive reaches the finest uniform error with at most a
//! third of its nodes): the loop with its defaults (gradient indicator, Dörfler `θ = 0.7`,
//! `Adaptive::FRACTION`) from the uniform `h₀ = 0.2`, with `max_nodes` = a third of the finest
//! uniform count, produces a node set whose energy error is below that of the finest uniform
//! set (h = 0.025). Observed: uniform h = 0.4, 0.2, 0.1, 0.05, 0.025 → 166, 653, 2 518, 9 875,
//! 39 129 nodes, energy error 6.07e-2, 2.36e-2, 8.22e-3, 3.31e-3, 1.19e-3 (rate ≈ 1.4 in h);
//! adaptive 653, 767, 1 325, 3 675, 11 552 nodes → 2.36e-2, 9.25e-3, 4.20e-3, 2.01e-3,
//! 1.10e-3: reached with 0.295 of the nodes, 7.5 % below the uniform error (displacement error
//! 1.15e-4 against 1.44e-4). The indicator and θ are the loop's defaults, not chosen here. Of
//! the twelve variants measured (starts 0.4 and 0.2 × both indicators × θ = 0.3, 0.5, 0.7;
//! docs/dev/adaptive.md, "Kirsch: adaptive against uniform") seven reach the error within a
//! third (gradient 0.3 and 0.7 and recovery 0.3 from 0.2; gradient 0.3, 0.5, 0.7 and recovery
//! 0.3 from 0.4; 0.185–0.315), gradient 0.5 from 0.2 just misses (0.334), the recovery θ = 0.5
//! and 0.7 runs need 0.47–0.57. Against
//! the h = 0.05 error (9 875 nodes) the defaults need 0.372 of the nodes (their steps triple
//! the node count: 3 675 → 11 552), so one comparison's ratio is a coarse number.

use super::kirsch::{kirsch_problem, measure, quarter_plate};
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{Adaptive, Indicator, Problem};

/// The requirement's node ratio.
const RATIO: usize = 3;

fn plate(h: f64) -> Problem {
    let mut p = kirsch_problem(quarter_plate(), h, Layout::Structured);
    p.discretisation.beta = 0.5;
    p
}

fn checked(s: &mlpg_contact::Solution) {
    assert!(s.relative_residual < 1e-10, "residual {}", s.relative_residual);
    assert!(s.equilibrium_error < 1e-9, "equilibrium {}", s.equilibrium_error);
}

#[test]
fn kirsch_adaptive_reaches_the_finest_uniform_error_with_a_third_of_the_nodes() {
    let mut uniform = Vec::new();
    for h in [0.4, 0.2, 0.1, 0.05, 0.025] {
        let p = plate(h);
        let mut silent = mlpg_contact::Silent;
        let m = mlpg_contact::discretise(&p, &mut silent).unwrap();
        let (m, _, s) = mlpg_contact::solve_model(&p, m, None, &mut silent).unwrap();
        checked(&s);
        let e = measure(&m, &s);
        println!(
            "MEASURED uniform h = {h}: {} nodes, energy error {:.3e}, displacement error {:.3e}, sigma_xx(0, a) {:.4}",
            m.nodes.len(),
            e.energy,
            e.displacement,
            e.concentration
        );
        uniform.push((m.nodes.len(), e.energy));
    }
    // The uniform sets converge (the comparison is against a converging sequence).
    assert!(uniform.windows(2).all(|w| w[1].1 < 0.7 * w[0].1), "uniform errors {uniform:?}");
    let (n_finest, e_finest) = uniform[uniform.len() - 1];

    let adaptive = Adaptive {
        steps: 12,
        max_nodes: n_finest / RATIO,
        fraction: Adaptive::FRACTION,
        indicator: Indicator::default(),
        contact: false,
        ..Adaptive::default()
    };
    let mut rows = Vec::new();
    mlpg_contact::pipeline::adaptive::solve_adaptive(
        &plate(0.2),
        &adaptive,
        &mut mlpg_contact::Silent,
        &mut |_, m, s, _| {
            checked(s);
            let e = measure(m, s);
            println!(
                "MEASURED adaptive: {} nodes, energy error {:.3e}, displacement error {:.3e}, sigma_xx(0, a) {:.4}",
                m.nodes.len(),
                e.energy,
                e.displacement,
                e.concentration
            );
            rows.push((m.nodes.len(), e.energy));
        },
    )
    .unwrap();
    // Each step refines: the node count grows and (on this smooth problem) the error falls.
    assert!(rows.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 < w[0].1), "adaptive {rows:?}");
    let reached = rows.iter().find(|&&(n, e)| n * RATIO <= n_finest && e < e_finest);
    println!(
        "MEASURED finest uniform: {n_finest} nodes, energy error {e_finest:.3e}; adaptive reached it: {reached:?}"
    );
    assert!(
        reached.is_some(),
        "no adaptive set of at most {} nodes below {e_finest:.3e}: {rows:?}",
        n_finest / RATIO
    );
}

/// The graded curved generator on node sets of the loop that used to break the MLS (each
/// stopped the loop before `generate_graded_curved` had its two boundary rules; messages as
/// observed): from `h₀ = 0.4` (`5/0.4 = 12.5`: the last root column and row straddle `x = 5`
/// and `y = 5`) "moment matrix at (5, 3.0588) / (5, 3.4444) / (3.0526, 5) ill-conditioned …
/// collinear", with the lattice nodes beside the dropped straddled corners at the geometric
/// mean `h_I` not reaching the edge; from `h₀ = 0.5` "support of (0, 5) / (5, 5) holds 3
/// nodes", the corner-cell defect. Every step of each run must now solve (residual and
/// equilibrium), and the final grading must pass the patch test (a linear displacement
/// imposed on every edge, reproduced to 1e-10 of its scale) at `β = 0.5`, `α_s = 2` and at
/// `β = 0`, `α_s = 2`.
#[test]
fn graded_kirsch_sets_with_straddled_edges_and_corners_solve_and_pass_the_patch_test() {
    let runs = [
        (0.4, Indicator::Gradient, 0.3),
        (0.4, Indicator::Gradient, 0.5),
        (0.4, Indicator::Recovery, 0.3),
        (0.5, Indicator::Gradient, 0.3),
        (0.5, Indicator::Recovery, 0.3),
    ];
    for (h0, indicator, fraction) in runs {
        let adaptive = Adaptive {
            steps: 8,
            max_nodes: 2500,
            fraction,
            indicator,
            contact: false,
            ..Adaptive::default()
        };
        let mut nodes = Vec::new();
        let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
            &plate(h0),
            &adaptive,
            &mut mlpg_contact::Silent,
            &mut |_, m, s, _| {
                checked(s);
                nodes.push(m.nodes.len());
            },
        )
        .unwrap_or_else(|e| panic!("h0 = {h0}, {indicator:?} θ = {fraction}: {e}"));
        let refinement = run.problem.refinement.clone();
        println!("MEASURED h0 = {h0}, {indicator:?} θ = {fraction}: nodes {nodes:?}");
        assert!(nodes.len() >= 5, "too few steps to reach the old failures: {nodes:?}");
        for beta in [0.5, 0.0] {
            let err = super::patch_test::run_graded_on(
                quarter_plate(),
                h0,
                Layout::Structured,
                refinement.clone(),
                beta,
                2.0,
            );
            println!("MEASURED   patch test at β = {beta}: {err:.3e}");
            assert!(err < 1e-10, "patch test {err:.3e} at β = {beta}");
        }
    }
}
