//! Adaptive refinement of two elastic bodies (docs/method.md §2.2, §4.3) against uniform node
//! sets and an FE reference: `problems/beam_on_block_adaptive.toml`, a cantilever `[0, 16] ×
//! [−1, 1]` (clamped at `x = 0`, `f = 1` down on its top) 0.01 above an elastic block `[0, 16] ×
//! [−3.01, −1.01]` (clamped on its bottom), both `E = 30 000`, `ν = 0.3`, plane stress, `β =
//! 0.5`, `α_s = 2`. Partial contact: the beam's bottom is open from the clamp to the onset
//! `l_c ≈ 9.04` and closed from there to the tip.
//!
//! **Reference** (an independent discretisation of the same problem: the built-in Q2 finite
//! elements, `method = "fem"`, both bodies, uniform meshes; [`fe_reference_ladder`] recomputes
//! it): `ΣP` = 8.9535227, 8.9540719, 8.9542311, 8.9543394 at FE spacings 0.25, 0.125, 0.0625,
//! 0.03125 (132 225 nodes per body, 148 s and 7.4 GB on the 2-core machine), increasing; the
//! differences 5.5e-4, 1.6e-4, 1.1e-4 shrink by `ρ ≈ 0.68` at the last halving, so the limit
//! lies within `d ρ/(1 − ρ) ≈ 2.3e-4` above the finest value if they keep shrinking so: the
//! reference is `ΣP = 8.9543394 ± 2.3e-4` (the bar taken on both sides). The onset (gap
//! extrapolation, `contact.onset_x`): 9.0588, 9.0505, 9.0374, 9.0436; the finest FE bracket
//! `[9.03125, 9.046875]` (last open, first closed candidate) holds the two finest estimates
//! (and the pressure extrapolation 9.0435); the reference is `l_c = 9.0436 ± 0.008`, the
//! bracket's half-width, which also covers the change 0.006 of the last halving.
//!
//! **Bounds**: the reference's own error bars, `|ΣP − 8.9543394| ≤ 2.3e-4` and `|l_c − 9.0436|
//! ≤ 0.008` — a tighter bound could not be checked against this reference.
//!
//! **The claim**: the loop's final node set (21 746 nodes of both bodies, stopped before a set
//! above 30 000) meets both bounds, with the contact checked at every step (complementarity,
//! equilibrium of both bodies, action and reaction, gaps from the displacements, one closed zone
//! reaching the tip, `M`'s checks); every uniform set of at most four times its nodes — the
//! halvings of `h₀ = 0.25` on both bodies — misses at least one, so the uniform layout needs
//! more than three times the adaptive nodes for this accuracy. Measured
//! (`cargo test --release --test validation adaptive_beam_on_block -- --nocapture`):
//! adaptive 21 746 nodes `ΣP` 8.954193 (−1.5e-4), `l_c` 9.0390 (−0.0046); uniform h = 0.03125
//! (66 690 nodes) `ΣP` 8.954052 (−2.9e-4), `l_c` 9.03125 (−0.0123, the bracket `[9.0,
//! 9.03125]` excludes the reference's).

use super::common::shipped_problem;
use mlpg_contact::Solution;
use mlpg_contact::problem::{Method, Problem, Refinement};

/// Reference `ΣP` (FE, spacing 0.03125) and its error bar from the FE refinement.
const FE_FORCE: f64 = 8.9543394;
const FE_FORCE_BAR: f64 = 2.3e-4;
/// Reference onset (FE, spacing 0.03125) and its error bar (the FE bracket's half-width).
const FE_ONSET: f64 = 9.0436;
const FE_ONSET_BAR: f64 = 0.008;
/// Complementarity and equilibrium: round-off.
const TOL: f64 = 1e-9;

/// The contact checks of every contact case on a two-body solution; `(ΣP, l_c)`.
fn checked(label: &str, s: &Solution) -> (f64, f64) {
    let c = s.contact().unwrap();
    let r = &c.lcp.residuals;
    assert!(r.max_violation() < TOL, "{label}: KKT residuals {r:?}");
    let mismatch = c.gap.iter().zip(&c.lcp.w).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(mismatch < 1e-12, "{label}: gap mismatch {mismatch}");
    let s2 = s.body(1).unwrap();
    assert!(s.equilibrium_error < TOL, "{label}: beam equilibrium {}", s.equilibrium_error);
    assert!(s2.equilibrium_error < TOL, "{label}: block equilibrium {}", s2.equilibrium_error);
    // The beam: load 16 down = clamp reaction + contact force up; the block: the contact force
    // down is the beam's, reversed.
    let balance = s.reaction_force[1] + c.total_force - 16.0;
    assert!(balance.abs() < TOL * 16.0, "{label}: beam balance {balance}");
    let action = s.contact_force[1] + s2.contact_force[1];
    assert!(action.abs() < 1e-12 * c.total_force, "{label}: action and reaction {action}");
    assert_eq!(c.onset.closed_intervals, 1, "{label}");
    let tip = (0..c.closed.len())
        .max_by(|&a, &b| c.candidates.arc_length[a].total_cmp(&c.candidates.arc_length[b]))
        .unwrap();
    assert!(c.closed[tip], "{label}: the tip candidate is open");
    let m = c.condensed.as_ref().unwrap();
    assert!(m.min_diagonal > 0.0 && m.min_symmetric_eigenvalue > 0.0, "{label}: M checks");
    (c.total_force, c.onset.from_gap.unwrap())
}

/// One adaptive solve: total nodes, nodes per body, combined estimate, `(ΣP, l_c)`.
type Row = (usize, [usize; 2], f64, (f64, f64));

/// Whether `(ΣP, l_c)` lies within the reference's error bars.
fn meets((force, onset): (f64, f64)) -> bool {
    (force - FE_FORCE).abs() <= FE_FORCE_BAR && (onset - FE_ONSET).abs() <= FE_ONSET_BAR
}

/// `problem` on uniform node sets of spacing `h` on both bodies (no refinement).
fn uniform(problem: &Problem, h: f64) -> Problem {
    let mut p = problem.clone();
    p.adaptive = None;
    p.node_spacing = h;
    p.refinement = Refinement::default();
    if let Some(p2) = p.body_mut(1) {
        p2.node_spacing = h;
        p2.refinement = Refinement::default();
    }
    p
}

/// The loop on the shipped problem meets the reference's bounds with fewer nodes than any
/// uniform set of at most four times as many, which all miss them.
#[test]
fn adaptive_beam_on_block_meets_the_fe_reference_with_a_third_of_the_uniform_nodes() {
    let problem = shipped_problem("beam_on_block_adaptive.toml", 0.25);
    let adaptive = problem.adaptive.unwrap();
    let mut rows: Vec<Row> = Vec::new();
    let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
        &problem,
        &adaptive,
        &mut mlpg_contact::Silent,
        &mut |_, m, s, _| {
            let n2 = s.body(1).unwrap().displacement.len();
            let label = format!("adaptive, {} + {n2} nodes", m.nodes.len());
            rows.push((m.nodes.len() + n2, [m.nodes.len(), n2], 0.0, checked(&label, s)));
        },
    )
    .unwrap();
    let steps = &run.summary.steps;
    assert_eq!(steps.len(), rows.len());
    for (row, step) in rows.iter_mut().zip(steps) {
        row.2 = step.estimated_error;
        let bodies = step.bodies.as_ref().unwrap();
        assert_eq!(row.0, step.nodes);
        assert_eq!(row.1, [bodies[0].nodes, bodies[1].nodes]);
    }
    for (n, [n1, n2], e, (f, l)) in &rows {
        println!(
            "adaptive {n:>6} nodes ({n1} + {n2}): estimate {e:.3e}, ΣP {f:.6} ({:+.1e}), l_c {l:.4} ({:+.4})",
            f - FE_FORCE,
            l - FE_ONSET
        );
    }
    assert_eq!(run.summary.stopped_by, "max_nodes");
    assert!(rows.len() >= 3, "{} solves", rows.len());
    // Both bodies refine at every step, and the combined estimate falls.
    assert!(
        rows.windows(2).all(|w| w[1].1[0] > w[0].1[0] && w[1].1[1] > w[0].1[1] && w[1].2 < w[0].2),
        "{rows:?}"
    );
    let &(nodes, _, _, last) = rows.last().unwrap();
    assert!(nodes <= adaptive.max_nodes);
    assert!(meets(last), "final set ({nodes} nodes): ΣP {:.6}, l_c {:.4}", last.0, last.1);
    let c = run.solution.contact().unwrap();
    let (lo, hi) = (c.onset.last_open.unwrap(), c.onset.first_closed.unwrap());
    assert!(lo <= last.1 && last.1 <= hi, "onset {} outside its bracket [{lo}, {hi}]", last.1);

    // Uniform sets: halvings of h₀ on both bodies while they have at most 4 × nodes.
    let cap = 4 * nodes;
    let mut h = problem.node_spacing;
    let mut largest = 0;
    loop {
        let p = uniform(&problem, h);
        let n = mlpg_contact::nodes::for_problem(&p).unwrap().len()
            + mlpg_contact::nodes::for_problem(p.body(1).unwrap()).unwrap().len();
        if n > cap {
            break;
        }
        let s = mlpg_contact::solve(&p).unwrap();
        let (f, l) = checked(&format!("uniform h = {h}"), &s);
        println!(
            "uniform h = {h:<8} {n:>6} nodes: ΣP {f:.6} ({:+.1e}), l_c {l:.4} ({:+.4})",
            f - FE_FORCE,
            l - FE_ONSET
        );
        assert!(!meets((f, l)), "uniform h = {h} ({n} nodes) meets the bounds");
        largest = n;
        h /= 2.0;
    }
    assert!(largest > 3 * nodes, "the largest uniform set tested has {largest} nodes");
}

/// Recomputes the FE reference of this file (uniform Q2 meshes on both bodies; the finest
/// needs about 150 s and 7.4 GB): `cargo test --release --test validation fe_reference_ladder
/// -- --ignored --nocapture`.
#[test]
#[ignore = "the FE reference: 150 s and 7.4 GB at its finest spacing"]
fn fe_reference_ladder() {
    let problem = shipped_problem("beam_on_block_adaptive.toml", 0.25);
    let mut last = (0.0, 0.0);
    for h in [0.25, 0.125, 0.0625, 0.03125] {
        let mut p = uniform(&problem, h);
        p.discretisation.method = Method::Fem;
        if let Some(p2) = p.body_mut(1) {
            p2.discretisation.method = Method::Fem;
        }
        let s = mlpg_contact::solve(&p).unwrap();
        last = checked(&format!("FE h = {h}"), &s);
        let c = s.contact().unwrap();
        println!(
            "FE h = {h:<8} {} nodes per body: ΣP {:.7}, l_c {:.4} in [{}, {}], from the pressures {:?}",
            s.displacement.len(),
            last.0,
            last.1,
            c.onset.last_open.unwrap(),
            c.onset.first_closed.unwrap(),
            c.onset.from_pressure
        );
    }
    assert!((last.0 - FE_FORCE).abs() < 1e-7, "ΣP {}", last.0);
    assert!((last.1 - FE_ONSET).abs() < 1e-4, "l_c {}", last.1);
}

/// Friction and load steps in the two-body loop: the shipped problem with `μ = 0.3` and the
/// beam's load applied in a `[[step]]` of four increments, two refinement steps. At every solve
/// the frictional step's residuals (normal and Coulomb complementarity, cone) and every
/// increment's complementarity and equilibrium ([`super::friction::check_frictional`]), the
/// second body's equilibrium and action and reaction in both directions; the contact marks
/// follow the open/stick/slip transitions onto both bodies.
#[test]
fn adaptive_beam_on_block_with_friction_and_steps() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems/beam_on_block_adaptive.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let loaded = r#"{ edge = "top", traction = { y = -1.0 } }"#;
    assert!(text.contains(loaded) && text.contains("steps = 10"));
    let text = text
        .replace(loaded, r#"{ edge = "top", traction = { y = 0.0 } }"#)
        .replace("steps = 10", "steps = 2")
        .replace("target_edge = \"top\"", "target_edge = \"top\"\nfriction = 0.3")
        + "\n[[step]]\nincrements = 4\nboundary = [{ body = \"beam\", edge = \"top\", traction = { y = -1.0 } }]\n";
    let problem = Problem::from_toml(&text).unwrap();
    let adaptive = problem.adaptive.unwrap();
    let mut solves = 0;
    let run = mlpg_contact::pipeline::adaptive::solve_adaptive(
        &problem,
        &adaptive,
        &mut mlpg_contact::Silent,
        &mut |_, m, s, _| {
            solves += 1;
            let label = format!("friction, {} nodes in the beam", m.nodes.len());
            super::friction::check_frictional(s, &label);
            let c = s.contact().unwrap();
            let s2 = s.body(1).unwrap();
            assert!(s2.equilibrium_error <= 1e-8, "{label}: block equilibrium");
            for axis in 0..2 {
                let action = s.contact_force[axis] + s2.contact_force[axis];
                assert!(action.abs() <= 1e-12 * c.total_force, "{label}: axis {axis}: {action}");
            }
            let f = c.friction.as_ref().unwrap();
            assert!(f.stick_zones >= 1 && f.slip_zones >= 1, "{label}: stick and slip");
        },
    )
    .unwrap();
    assert_eq!(solves, 3);
    assert_eq!(run.summary.stopped_by, "steps");
    for row in &run.summary.steps[..2] {
        let bodies = row.bodies.as_ref().unwrap();
        println!("step {}: {bodies:?}", row.step);
        assert!(bodies.iter().all(|b| b.marked > 0), "step {}", row.step);
    }
    let paired: usize =
        run.summary.steps.iter().map(|r| r.bodies.as_ref().unwrap()[1].marked_contact).sum();
    let first: usize =
        run.summary.steps.iter().map(|r| r.bodies.as_ref().unwrap()[0].marked_contact).sum();
    assert!(first > 0 && paired > 0, "contact marks beyond the bulk: beam {first}, block {paired}");
}
