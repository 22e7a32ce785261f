//! Adaptive refinement of an axisymmetric body (docs/method.md §2.2, §9.7): the Hertz sphere
//! of `axisymmetric_contact.rs` (the quarter-disk section `R = 1` about `(0, 1)`, revolved the
//! lower hemisphere, its top pushed down by `δ = 0.015` onto the rigid flat `z = 0`; `a/R ≈
//! 0.125`), refined by the loop from a uniform structured start with `β = 0.5`, the gradient
//! indicator weighted by the radius and carrying the hoop strain.
//!
//! `a` and `p₀` are fitted as in `axisymmetric_contact.rs` (`p²` linear in `r²` over the closed
//! candidates) and compared with Hertz for the computed axial force, whose idealisation (half
//! space, parabolic profile) is not the finite hemisphere's answer at this `a/R`: the FE on
//! its finest mesh and the uniform MFVM at `h = 0.005` agree on `p₀` −0.22 % against Hertz.
//! The errors are therefore also printed against the FE on mesh 2 (`sphere_fem(2)`, the same
//! fit): the refinement must approach that, not Hertz.

use super::axisymmetric_contact::{CONDITIONS, SPHERE_SECTION, Sphere, measure};
use super::common::assert_lcp_residuals;
use mlpg_contact::problem::Problem;

/// The Hertz sphere with uniform structured nodes of spacing `h` and the blend `beta`, no
/// refinement.
pub(super) fn sphere_uniform(h: f64, beta: f64) -> Problem {
    Problem::from_toml(&format!(
        r#"
        {SPHERE_SECTION}
        [nodes]
        spacing = {h:?}
        layout = "structured"
        [material]
        young = 1.0
        poisson = 0.3
        plane = "axisymmetric"
        [discretisation]
        beta = {beta:?}
        {CONDITIONS}
        "#
    ))
    .unwrap()
}

/// The Hertz sphere refined adaptively from the uniform spacing `h0` (`β = 0.5`, graded nodes
/// need it, §2.1): at most `steps` refinements and `max_nodes` nodes, Dörfler `fraction`, the
/// gradient indicator, the contact transition marks.
pub(super) fn sphere_adaptive(h0: f64, steps: usize, fraction: f64, max_nodes: usize) -> Problem {
    let mut p = sphere_uniform(h0, 0.5);
    p.adaptive = Some(mlpg_contact::problem::Adaptive {
        steps,
        max_nodes,
        fraction,
        indicator: mlpg_contact::problem::Indicator::Gradient,
        contact: true,
        ..mlpg_contact::problem::Adaptive::default()
    });
    p
}

/// One solve of a study or test: nodes, the Hertz fit (`None` with fewer than six closed
/// candidates, which the fit needs), the closed candidates.
#[derive(Clone, Copy, Debug)]
pub(super) struct Row {
    pub(super) nodes: usize,
    pub(super) sphere: Option<Sphere>,
    pub(super) closed: usize,
}

impl Row {
    /// The larger of the relative errors of `a` and `p₀` against Hertz.
    pub(super) fn max_error(&self) -> Option<f64> {
        self.sphere.map(|o| o.radius_error.abs().max(o.peak_error.abs()))
    }
}

/// Checks `s` (complementarity to 1e-9, the per-radian axial balance to 1e-8) and measures it
/// ([`measure`] checks the same again when it fits).
pub(super) fn row(label: &str, s: &mlpg_contact::Solution) -> Row {
    let c = s.contact().unwrap();
    assert_lcp_residuals(label, &c.lcp.residuals, 1e-9);
    assert!(s.equilibrium_error < 1e-8, "{label}: equilibrium {}", s.equilibrium_error);
    let balance = s.reaction_force[1] + c.total_force / std::f64::consts::TAU;
    assert!(balance.abs() < 1e-8 * c.total_force, "{label}: balance {balance}");
    let closed = c.closed.iter().filter(|&&k| k).count();
    let fits = c.closed.iter().zip(&c.pressure).filter(|(k, p)| **k && **p > 0.0).count() >= 6;
    Row { nodes: s.displacement.len(), sphere: fits.then(|| measure(label, s)), closed }
}

/// The requirement's bound on the relative errors of `a` and `p₀` against Hertz.
const BOUND: f64 = 0.005;
/// The requirement's node ratio: adaptive needs at most a third of the uniform nodes.
const RATIO: usize = 3;

/// Three refinements from the uniform spacing 0.05 (350 nodes; about 0.3 s): every solve
/// complementary and balanced ([`row`]); from the first solve that closes enough candidates
/// for the fit on, the errors of `a` and `p₀` against Hertz shrink at every step (observed
/// −0.95, −0.40, −0.12 % and −1.01, −0.48, −0.32 %; a further step would meet the floor of
/// Hertz's idealisation, `p₀` −0.22 % on FE mesh 2, see the module header); the last is
/// within 0.5 %. The node claim: the uniform structured sets (`β = 0` and the loop's
/// `β = 0.5`) with at most three times the nodes of the first adaptive set within 0.5 % —
/// the halvings of 0.05 and the uniform set with the most nodes up to that count — all miss
/// it. The study `examples/studies/axisymmetric_adaptive.rs` measures the whole uniform series
/// (docs/dev/axisymmetric.md, increment 7d): the first uniform set within 0.5 % has 5 160
/// nodes (`h = 0.0125`, `β = 0.5`; with `β = 0` 8 018, `h = 0.01`), the loop's 542 and 1 049.
#[test]
fn adaptive_hertz_sphere_meets_hertz_with_a_third_of_the_uniform_nodes() {
    let problem = sphere_adaptive(0.05, 3, 0.5, 20_000);
    let adaptive = problem.adaptive.unwrap();
    let mut rows: Vec<Row> = Vec::new();
    let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
        &problem,
        &adaptive,
        &mut mlpg_contact::Silent,
        &mut |_, _, s, _| rows.push(row(&format!("adaptive step {}", rows.len()), s)),
    )
    .unwrap();
    assert_eq!(run.summary.stopped_by, "steps");
    assert_eq!(rows.len(), 4);
    assert!(rows.windows(2).all(|w| w[1].nodes > w[0].nodes), "{rows:?}");
    let fitted: Vec<Sphere> = rows.iter().filter_map(|r| r.sphere).collect();
    assert!(fitted.len() >= 3, "{rows:?}");
    for w in fitted.windows(2) {
        assert!(w[1].radius_error.abs() < w[0].radius_error.abs(), "a: {w:?}");
        assert!(w[1].peak_error.abs() < w[0].peak_error.abs(), "p0: {w:?}");
    }
    let last = rows.last().unwrap();
    assert!(last.max_error().unwrap() <= BOUND, "{last:?}");
    // The contact marks resolve the zone: more closed rings at every step.
    assert!(rows.windows(2).all(|w| w[1].closed > w[0].closed), "{rows:?}");
    let nodes = rows.iter().find(|r| r.max_error().is_some_and(|e| e <= BOUND)).unwrap().nodes;

    let cap = RATIO * nodes;
    let count = |h: f64| {
        mlpg_contact::nodes::for_problem(&sphere_uniform(h, 0.0)).map_or(usize::MAX, |n| n.len())
    };
    let spacings = super::hertz::uniform_spacings_up_to(0.05, cap, count);
    for beta in [0.0, 0.5] {
        super::hertz::assert_uniform_sets_miss(&spacings, cap, BOUND, |h| {
            let s = mlpg_contact::solve(&sphere_uniform(h, beta)).unwrap();
            let r = row(&format!("uniform h = {h:.5} β = {beta}"), &s);
            (r.nodes, r.max_error())
        });
    }
}

/// Several axisymmetric bodies in the loop (`adaptive/scene.rs`): the two cylinders of
/// `axisymmetric_pairs.rs` end to end (`E` = 1 and 2, the upper top pushed 0.01), as a two-body
/// `[contact]` and as a `[[contact]]` scene, refined twice (`β = 0.5`). Each body is estimated, marked and
/// refined on its own; the uniaxial state is linear, so every graded node set must carry the
/// exact ring pressure `δ/(1/E₁ + 1/E₂)` (patch test, docs/method.md §9.4) and balance.
#[test]
fn an_axisymmetric_pair_is_refined_body_by_body_and_stays_exact() {
    let p = 0.01 / (1.0 / 1.0 + 1.0 / 2.0);
    for scene in [false, true] {
        let text = super::axisymmetric_pairs::cylinders_text("structured", "mfvm", "lemke", scene);
        // Graded sets take the stabilised blend (§2.1; with β = 0 the refined candidates'
        // side makes `M` indefinite, which the contact stage refuses).
        let text = text.replace("method = \"mfvm\"", "method = \"mfvm\"\nbeta = 0.5");
        let problem = Problem::from_toml(&format!("{text}\n[refinement]\nsteps = 2\n")).unwrap();
        let adaptive = problem.adaptive.unwrap();
        let mut counts: Vec<usize> = Vec::new();
        let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
            &problem,
            &adaptive,
            &mut mlpg_contact::Silent,
            &mut |_, _, s, _| {
                let label = format!("scene {scene}, solve {}", counts.len());
                let (pairs, lower) = (s.pairs(), s.body(1).expect("two bodies"));
                assert_eq!(pairs.len(), 1, "{label}: one pair");
                let c = pairs[0];
                let worst = c.pressure.iter().map(|q| (q - p).abs() / p).fold(0.0, f64::max);
                assert!(worst < 1e-9, "{label}: pressure off by {worst:.2e}");
                assert_lcp_residuals(&label, &c.lcp.residuals, 1e-9);
                for b in [s, lower] {
                    assert!(b.equilibrium_error < 1e-9, "{label}: {}", b.equilibrium_error);
                }
                counts.push(s.displacement.len() + lower.displacement.len());
            },
        )
        .unwrap();
        let bodies = run.summary.steps.last().unwrap().bodies.clone().unwrap();
        println!("axisymmetric pair, scene {scene}: nodes {counts:?}");
        assert_eq!(counts.len(), 3);
        assert!(counts.windows(2).all(|w| w[1] > w[0]), "{counts:?}");
        assert_eq!(bodies.len(), 2);
    }
}
