//! Coulomb friction with the Q2 finite elements (docs/method.md §8), the same checks as
//! `friction.rs` for the MFVM on the FE path:
//!
//! - a tiny `μ = 1e-12` on the FE beam gives the frictionless FE contact forces to 1e-9;
//! - full stick: `μ = 1e6` on a block pressed and sheared on a rigid flat equals the same
//!   block with its bottom clamped (the reactions there are the bonded contact forces, so this
//!   checks the FE tangential operator and the reaction recovery with `T`);
//! - gross sliding: `Σ T = −μ Σ P` to 1e-10, and the clamped top takes `Σ R_x = −Σ T`;
//! - load steps on the FE: with `μ = 0` they reproduce the one-step answer at the final load
//!   (path independence, so the FE step ends are right); with friction every increment meets
//!   the residual and equilibrium bounds;
//! - two FE bodies with friction (one step): the contact forces on the bodies cancel and
//!   both are in equilibrium;
//! - Cattaneo–Mindlin with the cylinder cap as a curved Gmsh mesh (isoparametric Q2): MFVM and
//!   FE agree within their discretisation errors.

use super::common::shipped_problem;
use super::friction::{block_text, bonded_difference, check_frictional, press_then_shear};
use mlpg_contact::lcp::ContactState;
use mlpg_contact::pipeline::compare::stick_extent;
use mlpg_contact::problem::{Method, Problem};
use mlpg_contact::solve;

/// A 2 × 1 Q2 block (E = 1000, ν = 0.3, plane stress, h = 0.1) whose top is moved by
/// `(shift, −0.01)`; its bottom touches the rigid line y = 0 with friction `mu`, or
/// (`mu = None`) is clamped. `steps`, if not empty, replaces the top's condition by zero
/// values reached along the `[[step]]` tables given.
fn fe_block(shift: f64, mu: Option<f64>, steps: &str) -> Problem {
    Problem::from_toml(&block_text("fem", shift, mu, steps)).unwrap()
}

#[test]
fn fe_tiny_friction_gives_the_frictionless_forces() {
    let frictionless = shipped_problem("beam_on_foundation_fem.toml", 0.5);
    let mut tiny = frictionless.clone();
    tiny.contact_mut().unwrap().friction = 1e-12;
    let (a, b) = (solve(&frictionless).unwrap(), solve(&tiny).unwrap());
    check_frictional(&b, "FE beam, μ = 1e-12");
    let (ca, cb) = (a.contact().unwrap(), b.contact().unwrap());
    let scale = ca.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let worst = ca.lcp.z.iter().zip(&cb.lcp.z).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let t_max =
        cb.friction.as_ref().unwrap().step.tangential.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    println!(
        "FE beam: max |P_μ − P_0| / max P = {:.2e}, max |T| / max P = {:.2e}",
        worst / scale,
        t_max / scale
    );
    assert!(worst <= 1e-9 * scale, "forces differ by {worst:.3e}");
    assert!(t_max <= 1e-11 * scale, "|T| = {t_max:.3e}");
}

#[test]
fn fe_huge_friction_gives_the_bonded_solution() {
    let shift = 0.002;
    let stuck = solve(&fe_block(shift, Some(1e6), "")).unwrap();
    check_frictional(&stuck, "FE stick");
    let bonded = solve(&fe_block(shift, None, "")).unwrap();
    let c = stuck.contact().unwrap();
    let f = c.friction.as_ref().unwrap();
    assert!(f.step.state.iter().all(|&s| s == ContactState::Stick), "{:?}", f.step.state);
    // ν = (0, 1), t = (1, 0): R_y = P, R_x = T at the same node (E = Gᵀ in the FE).
    let (worst, du) = bonded_difference(&stuck, &bonded);
    let scale = f.step.normal.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    println!(
        "FE stick: m = {}, max |force − bonded reaction| / max P = {:.2e}, max |u − u_bonded| = {du:.2e}",
        c.candidates.len(),
        worst / scale
    );
    // Every bottom node is a candidate (none is constrained), so the bonded reference has the
    // same unknowns: equal to the LCP's round-off.
    assert_eq!(c.candidates.len(), 41);
    assert!(worst <= 1e-8 * scale, "forces differ from the bonded reactions by {worst:.3e}");
    assert!(du <= 1e-8 * 0.01, "displacements differ by {du:.3e}");
}

#[test]
fn fe_gross_sliding_slips_everywhere_on_the_cone() {
    super::friction::gross_sliding_on("fem");
}

#[test]
fn fe_frictionless_steps_reproduce_the_one_step_answer() {
    let stepped = solve(&fe_block(0.0, Some(0.0), &press_then_shear(3, 4, 0.004))).unwrap();
    let reference = solve(&fe_block(0.004, Some(0.0), "")).unwrap();
    assert!(reference.contact().unwrap().friction.is_none());
    let (a, b) = (stepped.contact().unwrap(), reference.contact().unwrap());
    assert_eq!(a.friction.as_ref().unwrap().increments.len(), 7);
    let scale = b.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let dp = a.lcp.z.iter().zip(&b.lcp.z).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let du = stepped
        .displacement
        .iter()
        .zip(&reference.displacement)
        .map(|(x, y)| (x[0] - y[0]).hypot(x[1] - y[1]))
        .fold(0.0, f64::max);
    println!(
        "FE, μ = 0 steps vs one step: max |ΔP| / max P = {:.2e}, max |Δu| / 0.01 = {:.2e}",
        dp / scale,
        du / 0.01
    );
    assert!(dp <= 1e-12 * scale, "forces differ by {dp:.3e}");
    assert!(du <= 1e-12 * 0.01, "displacements differ by {du:.3e}");
}

#[test]
fn fe_press_then_shear_meets_every_condition_at_every_increment() {
    let s = solve(&fe_block(0.0, Some(0.3), &press_then_shear(4, 8, 0.004))).unwrap();
    check_frictional(&s, "FE press then shear");
    let f = s.contact().unwrap().friction.as_ref().unwrap();
    assert_eq!(f.increments.len(), 12);
    let t: Vec<f64> = f.increments.iter().map(|r| r.tangential_force).collect();
    println!("FE press then shear: ΣT per increment {t:?}");
    // The shear builds up monotonically (T opposes the shift, so ΣT decreases).
    assert!(t[4..].windows(2).all(|w| w[1] < w[0]), "{t:?}");
    assert!(f.stick_zones >= 1 && f.slip_zones >= 1, "{:?}", f.step.state);
}

#[test]
fn fe_beam_with_friction_in_load_steps() {
    // The shipped frictional beam (μ = 0.3, 10 increments) on the FE at h = 0.5: the clamp
    // takes the tangential force (no applied x-load), every increment solved to 1e-9.
    let mut p = shipped_problem("beam_on_foundation_friction.toml", 0.5);
    p.discretisation.method = Method::Fem;
    let s = solve(&p).unwrap();
    check_frictional(&s, "FE frictional beam, h = 0.5");
    let c = s.contact().unwrap();
    let f = c.friction.as_ref().unwrap();
    assert_eq!(f.increments.len(), 10);
    assert!(f.total_force < 0.0, "friction resists the stretching bottom fibre: {}", f.total_force);
    let rx = s.reaction_force[0];
    assert!((rx + f.total_force).abs() <= 1e-8 * c.total_force, "Σ R_x = {rx}");
}

#[test]
fn fe_two_blocks_pressed_and_sheared() {
    // Mirror images on matching meshes, but the coupling does not cancel exactly: the candidate
    // body takes its force at the node and the target spreads it over the tributary segment
    // (fem::target_operator), so the summed M_nt, M_tn are not zero. Observed (partial slip,
    // sliding, stick): 4.7e-4, 4.3e-5, 1.1e-4 of max P; a wrong sign of the target's
    // tangential operator would add the two bodies' coupling instead of cancelling it.
    super::friction::two_blocks_pressed_and_sheared_on("fem", 2e-3);
}

/// What is compared between the methods on the frictional beam.
const QUANTITIES: [&str; 5] = ["onset", "ΣP", "ΣT", "stick start", "stick end"];

/// The frictional beam (`problems/beam_on_foundation_friction.toml`: the paper's beam on a
/// foundation with friction `mu`, the load in 10 increments) by `method` at spacing `h`:
/// onset, ΣP, ΣT and the stick zone's extent, after checking every increment.
fn frictional_beam(method: Method, mu: f64, h: f64) -> [f64; 5] {
    let mut p = shipped_problem("beam_on_foundation_friction.toml", h);
    p.discretisation.method = method;
    p.contact_mut().unwrap().friction = mu;
    let s = solve(&p).unwrap();
    check_frictional(&s, &format!("{method:?} beam, μ = {mu}, h = {h}"));
    let c = s.contact().unwrap();
    let f = c.friction.as_ref().unwrap();
    assert_eq!(f.stick_zones, 1, "{:?}", f.step.state);
    let (start, end) = stick_extent(c).unwrap();
    let onset = c.onset.from_gap_raw.unwrap();
    [onset, c.total_force, f.total_force, start, end]
}

/// The paper's beam on a rough foundation, MFVM against FE (μ = 0.2 and 0.5, h = 0.5 and
/// 0.25). Neither has a closed form; each method's discretisation error is estimated by its
/// change from h = 0.5 to h = 0.25, `e = |X(0.25) − X(0.5)|`, and the two must agree at
/// h = 0.25 within `e_MFVM + e_FE + r`, where `r` is the read-off resolution of a position
/// (half a candidate spacing for each method: h/2 for the MFVM, h/4 for the FE, whose
/// candidates are the Q2 edge nodes; 0 for the forces), since a zone's end or the onset is
/// known only to that. Observed numbers: see the `println!` output and docs/dev/friction.md.
#[test]
fn frictional_beam_mfvm_and_fem_agree_within_their_discretisation_errors() {
    for mu in [0.2, 0.5] {
        compare_frictional_beam(mu, &[0.5, 0.25]);
    }
}

/// The same at h = 0.25 and 0.125 (μ = 0.2 and 0.5); slow (the FE at h = 0.125 has 768
/// candidates, a 2304-unknown step LCP per increment; 260 s on the shared 2-core machine).
/// Observed at h = 0.125 (MFVM / FE): μ = 0.2: ΣP 32.41971 / 32.41968, ΣT −2.56041 /
/// −2.56043, onset 20.032 / 20.039, stick zone 25.3125–47.6875 / 25.40625–47.59375;
/// μ = 0.5: ΣP 32.47585 / 32.47576, ΣT −3.37126 / −3.37066, onset 20.204 / 20.231, stick
/// zone 21.1875–48 / 21.21875–48. Every |MFVM − FE| within its bound (ΣT at μ = 0.5: 6.0e-4
/// against 2.1e-3). At h = 0.5 → 0.25 (the test above): μ = 0.2: ΣT −2.56145 → −2.56074 /
/// −2.56051 → −2.56027; μ = 0.5: ΣT −3.38016 → −3.37322 / −3.37052 → −3.37055.
#[test]
#[ignore]
fn frictional_beam_mfvm_and_fem_agree_within_their_discretisation_errors_fine() {
    for mu in [0.2, 0.5] {
        compare_frictional_beam(mu, &[0.25, 0.125]);
    }
}

fn compare_frictional_beam(mu: f64, spacings: &[f64; 2]) {
    let [coarse, fine] = *spacings;
    let run = |m, h| frictional_beam(m, mu, h);
    let (m0, m1) = (run(Method::Mfvm, coarse), run(Method::Mfvm, fine));
    let (f0, f1) = (run(Method::Fem, coarse), run(Method::Fem, fine));
    for (k, what) in QUANTITIES.iter().enumerate() {
        let (em, ef) = ((m1[k] - m0[k]).abs(), (f1[k] - f0[k]).abs());
        let r = if k >= 3 { 0.5 * fine + 0.25 * fine } else { 0.0 };
        let diff = (m1[k] - f1[k]).abs();
        println!(
            "beam μ = {mu}, {what}: MFVM {:.5} → {:.5} (e {em:.2e}), FE {:.5} → {:.5} (e {ef:.2e}), |MFVM − FE| at h = {fine}: {diff:.2e}, bound {:.2e}",
            m0[k],
            m1[k],
            f0[k],
            f1[k],
            em + ef + r
        );
        assert!(diff <= em + ef + r, "μ = {mu}, {what}: |{} − {}| = {diff:.3e}", m1[k], f1[k]);
    }
}

/// `--compare` on a frictional problem: both methods solve it with friction, and the table
/// gains the total tangential force, the stick / slip counts and the stick zone, each equal
/// to what the method's own solution says.
#[test]
fn compare_reports_the_frictional_quantities() {
    let p = shipped_problem("beam_on_foundation_friction.toml", 0.5);
    let out =
        std::env::temp_dir().join(format!("mlpg-fem-friction-compare-{}", std::process::id()));
    let cmp = mlpg_contact::pipeline::compare::compare(
        &p,
        &out,
        serde_json::Value::Null,
        &mut mlpg_contact::Silent,
    )
    .unwrap();
    let row = |name: &str| {
        cmp.rows
            .iter()
            .find(|r| r.quantity == name)
            .unwrap_or_else(|| panic!("no row {name}"))
            .clone()
    };
    type Pick = fn(&mlpg_contact::pipeline::compare::Row) -> Option<f64>;
    let picks: [(_, Pick); 2] = [(&cmp.mfvm, |r| r.mfvm), (&cmp.fem, |r| r.fem)];
    for (run, value) in picks {
        let c = run.summary.contact.as_ref().unwrap();
        assert_eq!(value(&row("total_tangential_force")), c.total_tangential_force);
        let [stick, slip] = c.stick_slip_counts.unwrap();
        assert_eq!(value(&row("stick_candidates")), Some(stick as f64));
        assert_eq!(value(&row("slip_candidates")), Some(slip as f64));
        let (start, end) = run.stick_extent.unwrap();
        assert_eq!(value(&row("stick_zone_start")), Some(start));
        assert_eq!(value(&row("stick_zone_end")), Some(end));
        assert!(start > 20.0 && end > start, "{start} .. {end}");
    }
    let text = std::fs::read_to_string(out.join("compare.csv")).unwrap();
    assert!(text.contains("\ntotal_tangential_force,") && text.contains("\nstick_zone_start,"));
    assert!(out.join("plots/compare_tangential_traction.svg").exists());
    let _ = std::fs::remove_dir_all(&out);
}

/// A 2 × 1 block (E = 1, ν = 0.3, plane strain: Dundurs β = (1 − 2ν)/(2(1 − ν)) = 0.29
/// against the rigid flat) touching the rigid line y = 0 with its whole bottom (zero initial
/// gap), friction `mu`, its top clamped laterally and pressed down along `steps`
/// (`(increments, press at the step's end)`).
fn pressed_block(method: Method, h: f64, mu: f64, steps: &[(usize, f64)]) -> Problem {
    let step = |k: usize, d: f64| {
        format!(
            "[[step]]\nincrements = {k}\nboundary = [{{ edge = \"top\", displacement = {{ y = {d:e} }} }}]\n"
        )
    };
    let method = match method {
        Method::Mfvm => "mfvm",
        Method::Fem => "fem",
    };
    Problem::from_toml(&format!(
        r#"
        name = "spence_block"
        [geometry]
        kind = "rectangle"
        x = [-1.0, 1.0]
        y = [0.0, 1.0]
        [nodes]
        spacing = {h:e}
        [discretisation]
        method = "{method}"
        [material]
        young = 1.0
        poisson = 0.3
        plane = "strain"
        [[boundary]]
        edge = "top"
        displacement = {{ x = 0.0, y = 0.0 }}
        [contact]
        edge = "bottom"
        obstacle_point = [0.0, 0.0]
        obstacle_normal = [0.0, 1.0]
        friction = {mu:e}
        {}
        "#,
        steps.iter().map(|&(k, d)| step(k, d)).collect::<String>()
    ))
    .unwrap()
}

/// Spence's self-similarity [Spence 1975, "The Hertz contact problem with finite friction",
/// J. Elasticity 5; for the flat punch, Spence 1973]: under a monotonically increasing normal
/// load, a contact with a fixed contact area and Dundurs β ≠ 0 (the Poisson expansion of the
/// block's bottom resisted by friction) develops a central stick zone and outward slip at
/// the ends whose stick fraction c/a does not change with the load.
///
/// It is exact for the discrete problem too, which makes this a test of the load path: with
/// zero initial gaps and proportional loading, the step data are `q_n = λ q̂_n`,
/// `q_t = λ q̂_t`, and the conditions of a step (docs/method.md §8) are positively homogeneous
/// in `(P, T, s, Δs)`. If `(P*, T*, s*)` solves the first step (from `s = 0`, λ = λ_1), then
/// `(λ/λ_1)(P*, T*, s*)` solves every later increment from the previous one's `s`: a sticking
/// candidate had `s* = Δs* = 0`, so it stays at `s = 0`; a slipping one keeps the direction
/// of `Δs` (the increments of λ are positive) and `T = ∓μP` scales with `P`. So every
/// increment must show the same stick set and `ΣP` in proportion to the load, and the last
/// increment must equal the one-step answer at the full load (P and T per candidate), to
/// round-off — for any increment sizes (here uneven: 1, 2, 1, 3 increments over four equal
/// steps). A wrong load factor or step end breaks it, and so does a step solver that leaves
/// the sets it found at the first increment. What it cannot see is the carry of `s_prev`:
/// sticking candidates have `s = 0` all along, so a zero `s_prev` gives the same answer (the
/// press-then-shear and path tests check the carry). (`ΣT` is zero by symmetry.)
///
/// The block is finite (height half its width, top clamped), not Spence's half-space, so
/// there is no closed form for c/a here; the MFVM and the FE must agree on it within their
/// discretisation errors (refinement h = 0.05 → 0.025, plus the read-off resolution of a
/// stick zone's ends: half a candidate spacing per end, h/2 for the MFVM and h/4 for the FE).
/// Observed (μ = 0.2): MFVM c/a = 0.4750 → 0.4375, FE 0.4375 → 0.43125.
#[test]
fn spence_stick_fraction_is_self_similar() {
    let mu = 0.2;
    let mut fraction = Vec::new();
    for method in [Method::Mfvm, Method::Fem] {
        for h in [0.05, 0.025] {
            let path = [(1, -0.0025), (2, -0.005), (1, -0.0075), (3, -0.01)];
            let s = solve(&pressed_block(method, h, mu, &path)).unwrap();
            let case = format!("Spence block, {method:?}, h = {h}");
            check_frictional(&s, &case);
            let c = s.contact().unwrap();
            let f = c.friction.as_ref().unwrap();
            assert_eq!(f.increments.len(), 7);
            // The load at each increment (fraction of the final press).
            let ends = [0.25, 0.5, 0.75, 1.0];
            let load: Vec<f64> = f
                .increments
                .iter()
                .map(|r| {
                    let before = if r.step == 1 { 0.0 } else { ends[r.step - 2] };
                    before + r.load_factor * (ends[r.step - 1] - before)
                })
                .collect();
            let last = f.increments.last().unwrap();
            for (r, l) in f.increments.iter().zip(&load) {
                // Same sets, forces in proportion to the load.
                assert_eq!((r.stick, r.slip, r.open), (last.stick, last.slip, 0), "{case}: {r:?}");
                let dp = (r.normal_force / l - last.normal_force).abs() / last.normal_force;
                assert!(dp <= 1e-10, "{case}: ΣP / λ off by {dp:.2e}: {r:?}");
            }
            // The path's end equals the one-step answer at the full press.
            let one = solve(&pressed_block(method, h, mu, &[(1, -0.01)])).unwrap();
            let f1 = one.contact().unwrap().friction.as_ref().unwrap();
            let scale = f.step.normal.iter().fold(0.0f64, |a, p| a.max(p.abs()));
            let worst = (0..f.step.normal.len())
                .map(|k| {
                    (f.step.normal[k] - f1.step.normal[k])
                        .abs()
                        .max((f.step.tangential[k] - f1.step.tangential[k]).abs())
                })
                .fold(0.0, f64::max);
            assert_eq!(f.step.state, f1.step.state, "{case}");
            assert!(worst <= 1e-10 * scale, "{case}: path end vs one step {worst:.2e}");
            // Stick in the middle, slip outward at both ends (ν = (0, 1), t = (1, 0)).
            let st = &f.step.state;
            assert_eq!(f.stick_zones, 1, "{case}: {st:?}");
            assert_eq!(st[0], ContactState::SlipNegative, "{case}");
            assert_eq!(st[st.len() - 1], ContactState::SlipPositive, "{case}");
            let (start, end) = stick_extent(c).unwrap();
            let ratio = 0.5 * (end - start) / 1.0;
            let by_count = last.stick as f64 / st.len() as f64;
            println!(
                "{case}: stick {} slip {} at every increment; c/a = {ratio:.4} (count fraction {by_count:.4}); ΣP = {:.6}; path end vs one step: {:.1e} of max P",
                last.stick,
                last.slip,
                last.normal_force,
                worst / scale
            );
            fraction.push(ratio);
        }
    }
    let (em, ef) = ((fraction[1] - fraction[0]).abs(), (fraction[3] - fraction[2]).abs());
    let (fine, diff) = (0.025, (fraction[1] - fraction[3]).abs());
    let bound = em + ef + (0.5 + 0.25) * fine;
    println!("Spence c/a: MFVM − FE at h = {fine}: {diff:.4}, bound {bound:.4}");
    assert!(diff <= bound, "c/a: MFVM {} vs FE {}", fraction[1], fraction[3]);
}

/// Two blocks (upper `[0, 2] × [1, 2]` on lower `[0, 2] × [0, 1]`, E = 1000, ν = 0.3, plane
/// stress, non-matching spacings `h` and `1.25 h`), the upper top pressed by 0.01 in 2
/// increments and then sheared to 0.012 in 4 with the press held, μ = 0.3, on method
/// `method`: `(ΣP, ΣT)` after checking every increment of both bodies.
fn two_blocks_in_steps(method: &str, h: f64) -> (f64, f64) {
    let text = format!(
        r#"
        name = "upper"
        [discretisation]
        method = "{method}"
        [[body]]
        name = "upper"
        geometry = {{ kind = "rectangle", x = [0.0, 2.0], y = [1.0, 2.0] }}
        nodes = {{ spacing = {h:e} }}
        material = {{ young = 1000.0, poisson = 0.3, plane = "stress" }}
        boundary = [{{ edge = "top", displacement = {{ x = 0.0, y = 0.0 }} }}]
        [[body]]
        name = "lower"
        geometry = {{ kind = "rectangle", x = [0.0, 2.0], y = [0.0, 1.0] }}
        nodes = {{ spacing = {:e} }}
        material = {{ young = 1000.0, poisson = 0.3, plane = "stress" }}
        boundary = [{{ edge = "bottom", displacement = {{ x = 0.0, y = 0.0 }} }}]
        [contact]
        edge = "bottom"
        target_edge = "top"
        friction = 0.3
        [[step]]
        increments = 2
        boundary = [{{ body = "upper", edge = "top", displacement = {{ x = 0.0, y = -0.01 }} }}]
        [[step]]
        increments = 4
        boundary = [{{ body = "upper", edge = "top", displacement = {{ x = 0.012, y = -0.01 }} }}]
        "#,
        1.25 * h
    );
    let s = solve(&Problem::from_toml(&text).unwrap()).unwrap();
    let case = format!("two blocks in steps, {method}, h = {h}");
    check_frictional(&s, &case);
    let second = s.body(1).unwrap();
    assert!(
        second.equilibrium_error <= 1e-8,
        "{case}: lower body {:.3e}",
        second.equilibrium_error
    );
    // Action and reaction: the contact forces on the two bodies cancel.
    let (f1, f2) = (s.contact_force, second.contact_force);
    let scale = f1[1].abs();
    assert!(
        (f1[0] + f2[0]).abs() <= 1e-10 * scale && (f1[1] + f2[1]).abs() <= 1e-10 * scale,
        "{case}"
    );
    let c = s.contact().unwrap();
    let f = c.friction.as_ref().unwrap();
    assert_eq!(f.increments.len(), 6, "{case}");
    assert!(f.step.state.contains(&ContactState::Stick), "{case}: partial slip");
    assert!(f.step.state.iter().any(|x| x.is_slip()), "{case}: partial slip");
    (c.total_force, f.total_force)
}

/// Two elastic bodies under load steps on both methods (the MFVM and the Q2 finite elements):
/// each method's error is estimated by its change from `h = 0.1` to `0.05`, and the two
/// finer answers agree within the sum (measured: ΣP 10.258875 → 10.257520 MFVM, 10.258408 →
/// 10.257384 FE; ΣT −2.820947 → −2.816796 MFVM, −2.816413 → −2.816641 FE).
#[test]
fn two_blocks_in_load_steps_mfvm_and_fem_agree() {
    let [m1, m2, f1, f2] = [("mfvm", 0.1), ("mfvm", 0.05), ("fem", 0.1), ("fem", 0.05)]
        .map(|(method, h)| two_blocks_in_steps(method, h));
    for (k, name) in [(0, "ΣP"), (1, "ΣT")] {
        let get = |r: (f64, f64)| if k == 0 { r.0 } else { r.1 };
        let bound = (get(m2) - get(m1)).abs() + (get(f2) - get(f1)).abs();
        let diff = (get(m2) - get(f2)).abs();
        println!(
            "{name}: MFVM {} → {}, FE {} → {}, |MFVM − FE| {diff:.2e} ≤ {bound:.2e}",
            get(m1),
            get(m2),
            get(f1),
            get(f2)
        );
        assert!(diff <= bound, "{name}: {diff:.3e} > {bound:.3e}");
    }
}

/// The Cattaneo–Mindlin case (`problems/cattaneo_mindlin.toml`, the press without friction,
/// then the shear to Q/μP ≈ 0.5 in 4 increments) on the FE: the cylinder cap from
/// `tests/data/fem_meshes/cattaneo_cap_<level>.msh` (9-node quadrilaterals with curved sides
/// along the arc, node spacing 0.02 or 0.01 there; `nodes.from = "mesh"`) and the block as the
/// Q2 grid at the same node spacing.
fn cattaneo_mindlin_fem(level: usize) -> Problem {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/cattaneo_mindlin.toml"),
    )
    .unwrap();
    let head = &text[..text.find("\n[[step]]").unwrap()];
    let start = head.find("geometry = { kind = \"curves\"").unwrap();
    let end = start + head[start..].find("] }\n").unwrap() + 4;
    let mesh = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("tests/data/fem_meshes/cattaneo_cap_{level}.msh"));
    let cap = format!(
        "geometry = {{ kind = \"gmsh\", file = \"{}\", surface = \"cylinder\" }}\n",
        mesh.display()
    );
    let head = format!("{}{cap}{}", &head[..start], &head[end..]);
    // The cap's nodes from the mesh, the block's Q2 grid of element size 2 × node spacing.
    let block = 2.0 * [0.02, 0.01][level];
    let head = head
        .replacen("nodes = { spacing = 0.01 }\n", "nodes = { from = \"mesh\" }\n", 1)
        .replacen("nodes = { spacing = 0.01 }\n", &format!("nodes = {{ spacing = {block} }}\n"), 1);
    let head = head.replacen("[[body]]", "[discretisation]\nmethod = \"fem\"\n\n[[body]]", 1);
    let steps = super::friction::cylinder_path(&[0.0023], 4);
    Problem::from_toml(&format!("{head}\n{steps}")).unwrap()
}

/// MFVM and FE on Cattaneo–Mindlin agree within their discretisation errors: at node spacing
/// 0.02 and 0.01 each (MFVM: the shipped problem at h; FE: [`cattaneo_mindlin_fem`]), the
/// total normal force `P`, the tangential force `Q`, the contact half-width `a` and the stick
/// zone `c/a` (read as in `friction.rs`) differ at the finer level by at most the sum of the
/// two methods' changes from the coarser to the finer level (each method's error estimate).
/// Every increment of both meets the complementarity and equilibrium bounds.
///
/// Observed (MFVM h = 0.02, 0.01; FE levels 0, 1): P 4.0391e-3, 4.0503e-3 and 4.0689e-3,
/// 4.0563e-3 (|diff| 6.0e-6 ≤ 2.4e-5); Q 6.018e-4, 5.987e-4 and 5.988e-4, 5.983e-4 (3.2e-7 ≤
/// 3.6e-6); a 0.09414, 0.09470 and 0.09499, 0.09508 (3.8e-4 ≤ 6.5e-4); c/a 0.742, 0.711 and
/// 0.713, 0.736 (2.5e-2 ≤ 5.4e-2; theory 0.712–0.714). The FE's c/a is the less regular of
/// the two: its tractions are nodal forces over consistent tributary lengths, alternating
/// between corner and middle nodes, which the stick zone's fit reads with a jitter of a node.
#[test]
fn cattaneo_mindlin_mfvm_and_fem_agree() {
    use super::friction::{cattaneo_mindlin, check_increments, read_contact, zone_from_fit};
    let mu = 0.3;
    let measure = |p: &Problem, case: &str| {
        let s = solve(p).unwrap();
        check_frictional(&s, case);
        check_increments(&s, case);
        let k = read_contact(&s);
        let slack: Vec<f64> = k.p.iter().zip(&k.q).map(|(p, q)| mu * p - q.abs()).collect();
        let stick: Vec<bool> = k.state.iter().map(|&st| st == ContactState::Stick).collect();
        let (_, c, _) = zone_from_fit(&k.x, &slack, &stick);
        let ratio = k.total_q / (mu * k.total_p);
        println!(
            "{case}: {} candidates, P = {:.6e}, Q = {:.6e} (Q/μP {ratio:.4}), a = {:.5}, c/a = {:.4}, theory {:.4}",
            k.x.len(),
            k.total_p,
            k.total_q,
            k.a,
            c / k.a,
            (1.0 - ratio).sqrt()
        );
        [k.total_p, k.total_q, k.a, c / k.a]
    };
    let steps = super::friction::cylinder_path(&[0.0023], 4);
    let mfvm: Vec<[f64; 4]> = [0.02, 0.01]
        .iter()
        .map(|&h| {
            measure(&cattaneo_mindlin(h, mu, &steps), &format!("Cattaneo–Mindlin MFVM h = {h}"))
        })
        .collect();
    let fem: Vec<[f64; 4]> = (0..2)
        .map(|level| {
            measure(&cattaneo_mindlin_fem(level), &format!("Cattaneo–Mindlin FE level {level}"))
        })
        .collect();
    for (i, name) in ["P", "Q", "a", "c/a"].iter().enumerate() {
        let diff = (mfvm[1][i] - fem[1][i]).abs();
        let (e_m, e_f) = ((mfvm[1][i] - mfvm[0][i]).abs(), (fem[1][i] - fem[0][i]).abs());
        println!(
            "Cattaneo–Mindlin {name}: MFVM {:.6e} FE {:.6e} |diff| {diff:.2e} ≤ e_MFVM {e_m:.2e} + e_FE {e_f:.2e}",
            mfvm[1][i], fem[1][i]
        );
        assert!(diff <= e_m + e_f, "{name}: {diff:e} > {e_m:e} + {e_f:e}");
    }
}
