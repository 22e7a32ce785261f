//! A two-body contact whose target is 100 × softer than the candidate body, refined adaptively,
//! solved with the default discretisation (`beta = "auto"`, no `allow_indefinite`): the case
//! where the candidates end up finer than the target and `M`'s symmetric part is indefinite
//! whatever `β` (docs/method.md §4.3, "A target coarser than the candidates";
//! docs/dev/beta_study.md).
//!
//! **Problem**: `problems/beam_on_block_adaptive.toml` with the block's `young = 300` (the beam
//! keeps 30 000) and its `beta = 0.5` line removed, so `"auto"` applies; the loop capped at
//! 10 000 nodes (three refinement steps, 6 824 nodes).
//!
//! **Reference** (an independent discretisation: the built-in Q2 finite elements, `method =
//! "fem"`, both bodies, uniform meshes, no refinement; [`soft_target_fe_reference_ladder`]
//! recomputes it): `ΣP` = 8.8105868, 8.8112951, 8.8115409, 8.8116267 at spacings 0.25, 0.125,
//! 0.0625, 0.03125; the differences 7.1e-4, 2.5e-4, 8.6e-5 shrink by `ρ ≈ 0.35`, so the limit
//! is about `8.81163 + 8.6e-5 · ρ/(1 − ρ) = 8.81167`. The onset (gap extrapolation): 6.2491,
//! 6.2473, 6.2467, 6.2464, the finest bracket `[6.234375, 6.25]`.
//!
//! **Bounds**: the accuracy level the project's time-to-accuracy measurements use (contact
//! force within `10⁻⁴` relative, onset within 0.01; docs/dev/time_to_accuracy.md), against the
//! finest FE values; the FE error bars (4.6e-5 and the bracket) are inside them.
//!
//! **The claim**: at `β = 0` the first solve is refused (an indefinite `M` whose negative
//! direction the target does resolve), `"auto"` repeats at `β = 0.5`, and from the first
//! refinement step on `M`'s symmetric part is indefinite only in force patterns finer than the
//! block's cells: the run proceeds with a warning saying so, and its answer passes its own
//! checks (complementarity, both bodies' equilibrium, action and reaction) and the reference's
//! bounds. Before, the default refused this problem at the first refinement step.

use mlpg_contact::Silent;
use mlpg_contact::pipeline::Outcome;
use mlpg_contact::problem::{Method, Problem};

/// Reference `ΣP` and onset (FE, spacing 0.03125).
const FE_FORCE: f64 = 8.8116267;
const FE_ONSET: f64 = 6.2464;
/// Complementarity and equilibrium: round-off.
const TOL: f64 = 1e-9;

/// The shipped adaptive two-body problem with a block of `young = 300` and the default `β`.
fn soft_target_text() -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems/beam_on_block_adaptive.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let block = "name = \"block\"";
    let (head, tail) = text.split_at(text.find(block).unwrap());
    let stiff = "young = 30000.0";
    assert!(tail.contains(stiff) && head.contains("beta = 0.5"));
    let head: String =
        head.lines().filter(|l| !l.starts_with("beta = 0.5")).map(|l| format!("{l}\n")).collect();
    format!("{head}{}", tail.replacen(stiff, "young = 300.0", 1))
}

#[test]
fn a_soft_target_solves_with_the_default_discretisation() {
    let mut problem = Problem::from_toml(&soft_target_text()).unwrap();
    assert!(problem.discretisation.beta_auto);
    problem.adaptive.as_mut().unwrap().max_nodes = 10_000;
    let outcome = Outcome::solve(problem, serde_json::Value::Null, &mut Silent).unwrap();
    let (s, summary) = (&outcome.solution, &outcome.summary);
    let warnings = summary.warnings.join("\n");
    assert!(warnings.contains("beta = \"auto\": at beta = 0"), "{warnings}");
    assert!(warnings.contains("negative only in contact-force patterns"), "{warnings}");
    let c = s.contact().unwrap();
    let m = c.condensed.as_ref().unwrap();
    // The case this test is about: M indefinite, yet accepted.
    assert!(m.min_diagonal > 0.0 && m.min_symmetric_eigenvalue < 0.0, "{m:?}");
    assert!(c.lcp.residuals.max_violation() < TOL, "KKT residuals {:?}", c.lcp.residuals);
    let s2 = s.body(1).unwrap();
    assert!(s.equilibrium_error < TOL && s2.equilibrium_error < TOL);
    let action = s.contact_force[1] + s2.contact_force[1];
    assert!(action.abs() < 1e-12 * c.total_force, "action and reaction {action}");
    assert!(summary.checks.passed, "{:?}", summary.checks);
    let steps = &summary.refinement.as_ref().unwrap().steps;
    assert_eq!(steps.len(), 4, "three refinement steps");
    let onset = c.onset.from_gap.unwrap();
    println!(
        "soft target, {} nodes: ΣP {:.7} ({:+.1e} relative to FE), l_c {onset:.4} ({:+.4})",
        steps.last().unwrap().nodes,
        c.total_force,
        c.total_force / FE_FORCE - 1.0,
        onset - FE_ONSET
    );
    assert!((c.total_force / FE_FORCE - 1.0).abs() < 1e-4, "ΣP {}", c.total_force);
    assert!((onset - FE_ONSET).abs() < 0.01, "l_c {onset}");
}

/// Recomputes the FE reference of this file (uniform Q2 meshes on both bodies; the finest
/// takes about a minute): `cargo test --release --test validation
/// soft_target_fe_reference_ladder -- --ignored --nocapture`.
#[test]
#[ignore = "the FE reference: about a minute and 7 GB at its finest spacing"]
fn soft_target_fe_reference_ladder() {
    let base = Problem::from_toml(&soft_target_text()).unwrap();
    let mut last = (0.0, 0.0);
    for h in [0.25, 0.125, 0.0625, 0.03125] {
        let mut p = base.clone();
        p.adaptive = None;
        p.node_spacing = h;
        p.discretisation.method = Method::Fem;
        let p2 = p.body_mut(1).unwrap();
        p2.node_spacing = h;
        p2.discretisation.method = Method::Fem;
        let s = mlpg_contact::solve(&p).unwrap();
        let c = s.contact().unwrap();
        assert!(c.lcp.residuals.max_violation() < TOL);
        last = (c.total_force, c.onset.from_gap.unwrap());
        println!(
            "FE h = {h:<8}: ΣP {:.7}, l_c {:.4} in [{}, {}]",
            last.0,
            last.1,
            c.onset.last_open.unwrap(),
            c.onset.first_closed.unwrap()
        );
    }
    assert!((last.0 - FE_FORCE).abs() < 1e-7, "ΣP {}", last.0);
    assert!((last.1 - FE_ONSET).abs() < 1e-4, "l_c {}", last.1);
}
