//! Coulomb friction against a rigid obstacle and between two bodies (docs/method.md §8):
//!
//! - (a) a tiny `μ = 1e-12` on every shipped MFVM rigid-obstacle problem gives the frictionless
//!   contact forces to 1e-9 (`μ = 0` itself takes the frictionless path unchanged; the
//!   outputs are checked byte for byte by `scripts/output-digest.sh`);
//! - (b) full stick: `μ = 1e6` on a block pressed and sheared on a rigid flat gives the bonded
//!   solution, computed independently as the same block with its bottom edge clamped by
//!   displacement conditions (the reactions there are the bonded contact forces), to 1e-8;
//! - (c) gross sliding: the block sheared beyond `μ P` slips at every closed candidate, with
//!   `Σ T = −μ Σ P` to 1e-10;
//! - (d) in every frictional case the scaled step residual is ≤ 1e-9 and the global
//!   equilibrium (applied + reactions + normal and tangential contact forces) ≤ 1e-8;
//! - the `[contact] friction` key is validated and refused where it is not wired yet;
//! - load steps (`[[step]]`): with `μ = 0` they give the one-step answer at the final load;
//!   with friction every increment meets the residual and equilibrium bounds; the same final
//!   load along different paths gives different `Σ T` when candidates slip and the same when
//!   all stick; the `[[step]]` tables are validated with their key paths;
//! - two identical blocks pressed and sheared: the contact forces on the bodies cancel, both
//!   bodies are in equilibrium, and the normal forces do not depend on friction (mirrored,
//!   elastically similar bodies uncouple);
//! - Cattaneo–Mindlin: the stick zone of a cylinder pressed, then sheared, on a rigid flat
//!   (ν = 0.45, weakly coupled) against `c/a = (1 − Q/μP)^{1/2}` [J85 §7.1].

use super::common::shipped_problem;
use mlpg_contact::lcp::{ContactState, FrictionMethod};
use mlpg_contact::problem::Problem;
use mlpg_contact::{Solution, solve};

/// A 2 × 1 block (E = 1000, ν = 0.3, plane stress, h = 0.1) whose top is moved by
/// `(shift, −0.01)`; its bottom either touches the rigid line y = 0 with friction `mu`, or
/// (`mu = None`) is clamped (`u = 0`, the bonded reference).
fn block(shift: f64, mu: Option<f64>) -> Problem {
    let bottom = match mu {
        Some(mu) => format!(
            "[contact]\nedge = \"bottom\"\nobstacle_point = [0.0, 0.0]\nobstacle_normal = [0.0, 1.0]\nfriction = {mu:e}\n"
        ),
        None => "[[boundary]]\nedge = \"bottom\"\ndisplacement = { x = 0.0, y = 0.0 }\n".into(),
    };
    Problem::from_toml(&format!(
        r#"
        name = "block"
        [geometry]
        kind = "rectangle"
        x = [0.0, 2.0]
        y = [0.0, 1.0]
        [nodes]
        spacing = 0.1
        [material]
        young = 1000.0
        poisson = 0.3
        plane = "stress"
        [[boundary]]
        edge = "top"
        displacement = {{ x = {shift:e}, y = -0.01 }}
        {bottom}
        "#
    ))
    .unwrap()
}

/// (d): the step residual and the global equilibrium of a frictional solution.
fn check_frictional(s: &Solution, case: &str) {
    let c = s.contact.as_ref().unwrap();
    let f = c.friction.as_ref().expect("a frictional solution");
    let r = f.step.residuals.max();
    println!(
        "{case}: solver {:?}, pivots {}, iterations {}, residual {r:.2e}, equilibrium {:.2e}, stick {} slip {} zones",
        f.step.method,
        f.step.pivots,
        f.step.iterations,
        s.equilibrium_error,
        f.stick_zones,
        f.slip_zones
    );
    assert!(r <= 1e-9, "{case}: step residual {r:.3e}");
    assert!(s.equilibrium_error <= 1e-8, "{case}: equilibrium {:.3e}", s.equilibrium_error);
    // The MLS gaps after the final solve agree with the step's gaps.
    let scale = c.candidates.initial_gap.iter().fold(0.01f64, |a, g| a.max(g.abs()));
    for (a, b) in c.gap.iter().zip(&f.step.gap) {
        assert!((a - b).abs() <= 1e-9 * scale, "{case}: gap {a} vs {b}");
    }
}

#[test]
fn tiny_friction_gives_the_frictionless_forces() {
    for (file, h) in [
        ("beam_on_foundation.toml", 0.5),
        ("beam_on_foundation_stabilised.toml", 0.5),
        ("hertz_cylinder.toml", 0.02),
    ] {
        let frictionless = shipped_problem(file, h);
        let mut tiny = frictionless.clone();
        tiny.contact.as_mut().unwrap().friction = 1e-12;
        let (a, b) = (solve(&frictionless).unwrap(), solve(&tiny).unwrap());
        check_frictional(&b, file);
        let (ca, cb) = (a.contact.as_ref().unwrap(), b.contact.as_ref().unwrap());
        let scale = ca.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
        let worst = ca.lcp.z.iter().zip(&cb.lcp.z).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        let f = cb.friction.as_ref().unwrap();
        let t_max = f.step.tangential.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        println!(
            "{file}: max |P_μ − P_0| / max P = {:.2e}, max |T| / max P = {:.2e}, {} tangentially clamped",
            worst / scale,
            t_max / scale,
            f.tangentially_free.iter().filter(|&&x| !x).count()
        );
        assert!(worst <= 1e-9 * scale, "{file}: forces differ by {worst:.3e}");
        assert!(t_max <= 1e-11 * scale, "{file}: |T| = {t_max:.3e}");
        assert!(
            f.step.residuals.cone <= 1e-12,
            "{file}: cone residual {:.3e}",
            f.step.residuals.cone
        );
    }
}

#[test]
fn huge_friction_gives_the_bonded_solution() {
    let shift = 0.002;
    let stuck = solve(&block(shift, Some(1e6))).unwrap();
    check_frictional(&stuck, "stick");
    let bonded = solve(&block(shift, None)).unwrap();
    let c = stuck.contact.as_ref().unwrap();
    let f = c.friction.as_ref().unwrap();
    assert!(f.step.state.iter().all(|&s| s == ContactState::Stick), "{:?}", f.step.state);
    assert_eq!((f.stick_zones, f.slip_zones), (1, 0));
    // Bonded reference: the reactions of the clamped bottom nodes.
    let reaction = |node: u32, axis: usize| {
        bonded
            .reactions
            .iter()
            .find(|&&(n, a, _)| n == node && a as usize == axis)
            .map(|r| r.2)
            .unwrap_or_else(|| panic!("node {node} is not clamped in the reference"))
    };
    let scale = f.step.normal.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let mut worst = 0.0f64;
    for (k, &node) in c.candidates.nodes.iter().enumerate() {
        // ν = (0, 1), t = (1, 0): R_y = P, R_x = T.
        worst = worst.max((reaction(node, 1) - f.step.normal[k]).abs());
        worst = worst.max((reaction(node, 0) - f.step.tangential[k]).abs());
    }
    let du = stuck
        .displacement
        .iter()
        .zip(&bonded.displacement)
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .fold(0.0, f64::max);
    println!(
        "stick: m = {}, max |force − bonded reaction| / max P = {:.2e}, max |u − u_bonded| = {du:.2e}, ΣT / ΣP = {:.4}",
        c.candidates.len(),
        worst / scale,
        f.total_force / c.total_force
    );
    assert!(worst <= 1e-8 * scale, "forces differ from the bonded reactions by {worst:.3e}");
    assert!(du <= 1e-8 * 0.01, "displacements differ by {du:.3e}");
}

#[test]
fn gross_sliding_slips_everywhere_on_the_cone() {
    let mu = 0.2;
    let s = solve(&block(0.05, Some(mu))).unwrap();
    check_frictional(&s, "gross sliding");
    let c = s.contact.as_ref().unwrap();
    let f = c.friction.as_ref().unwrap();
    let closed = f.step.normal.iter().filter(|&&p| p > 0.0).count();
    assert!(closed > c.candidates.len() / 2, "only {closed} candidates closed");
    for (k, &state) in f.step.state.iter().enumerate() {
        if f.step.normal[k] > 0.0 {
            assert_eq!(state, ContactState::SlipPositive, "candidate {k}");
        }
    }
    let ratio = f.total_force / c.total_force;
    println!(
        "gross sliding: {closed} of {} closed, ΣT = {:.6}, ΣP = {:.6}, ΣT/ΣP = {ratio:.12}",
        c.candidates.len(),
        f.total_force,
        c.total_force
    );
    assert!((ratio + mu).abs() <= 1e-10, "ΣT / ΣP = {ratio}");
    // The top's reaction carries the friction force: Σ R_x = −Σ T.
    let rx = s.reaction_force[0];
    assert!((rx + f.total_force).abs() <= 1e-8 * c.total_force, "Σ R_x = {rx}");
    assert_ne!(f.step.method, FrictionMethod::Frictionless);
}

#[test]
fn partial_slip_meets_every_condition() {
    // Between the two: a stick zone inside, slip towards the ends.
    let s = solve(&block(0.004, Some(0.3))).unwrap();
    check_frictional(&s, "partial slip");
    let f = s.contact.as_ref().unwrap().friction.as_ref().unwrap();
    assert!(f.stick_zones >= 1 && f.slip_zones >= 1, "{:?}", f.step.state);
}

#[test]
fn friction_key_is_validated() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/beam_on_foundation.toml"),
    )
    .unwrap();
    let with = |line: &str| text.replace("[contact]\n", &format!("[contact]\n{line}\n"));
    for bad in ["friction = -0.1", "friction = nan", "friction = inf"] {
        let e = Problem::from_toml(&with(bad)).unwrap_err().to_string();
        assert!(e.contains("contact.friction"), "{bad}: {e}");
    }
    let p = Problem::from_toml(&with("friction = 0.3")).unwrap();
    assert_eq!(p.contact.unwrap().friction, 0.3);
    assert_eq!(Problem::from_toml(&text).unwrap().contact.unwrap().friction, 0.0);
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let with_friction = |file: &str| {
        let t = std::fs::read_to_string(root.join(file)).unwrap();
        t.replace("[contact]\n", "[contact]\nfriction = 0.3\n")
    };
    // The finite elements take friction too (validation/fem_friction.rs).
    let fe = Problem::from_toml(&with_friction("beam_on_foundation_fem.toml")).unwrap();
    assert_eq!(fe.contact.unwrap().friction, 0.3);
    // Two bodies take friction, but not load steps yet.
    let two = with_friction("two_blocks.toml");
    assert_eq!(Problem::from_toml(&two).unwrap().contact.unwrap().friction, 0.3);
    let e = Problem::from_toml(&format!(
        "{two}\n[[step]]\nboundary = [{{ edge = \"top\", displacement = {{ y = -0.01 }} }}]\n"
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("`step`") && e.contains("two elastic bodies"), "{e}");
}

/// The 2 × 1 block of [`block`] on the rigid line y = 0 with friction `mu`, loaded along the
/// path `steps` (`[[step]]` tables): its top is declared `displacement = { x = 0, y = 0 }`
/// and each step sets its end values.
fn stepped_block(mu: f64, steps: &str) -> Problem {
    Problem::from_toml(&stepped_block_text(mu, steps)).unwrap()
}

/// Press by 0.01 in `k` increments, shear by `shift` in `m` increments with the press held.
fn press_then_shear(k: usize, m: usize, shift: f64) -> String {
    format!(
        "[[step]]\nincrements = {k}\nboundary = [{{ edge = \"top\", displacement = {{ y = -0.01 }} }}]\n\
         [[step]]\nincrements = {m}\nboundary = [{{ edge = \"top\", displacement = {{ x = {shift:e} }} }}]\n"
    )
}

/// Every increment of a stepped solution: complementarity ≤ 1e-9, equilibrium ≤ 1e-8.
fn check_increments(s: &Solution, case: &str) -> Vec<f64> {
    let f = s.contact.as_ref().unwrap().friction.as_ref().unwrap();
    let mut worst = (0.0f64, 0.0f64);
    for r in &f.increments {
        assert!(r.complementarity <= 1e-9, "{case}: {r:?}");
        assert!(r.equilibrium_error <= 1e-8, "{case}: {r:?}");
        worst = (worst.0.max(r.complementarity), worst.1.max(r.equilibrium_error));
    }
    println!(
        "{case}: {} increments, worst complementarity {:.2e}, equilibrium {:.2e}; ΣT per increment {:?}",
        f.increments.len(),
        worst.0,
        worst.1,
        f.increments.iter().map(|r| format!("{:.4}", r.tangential_force)).collect::<Vec<_>>()
    );
    f.increments.iter().map(|r| r.tangential_force).collect()
}

#[test]
fn frictionless_steps_reproduce_the_one_step_answer() {
    // μ = 0: contact without friction is path independent, so the last increment equals the
    // one-step solve at the final load (the frictionless path, no steps).
    let stepped = solve(&stepped_block(0.0, &press_then_shear(3, 4, 0.004))).unwrap();
    let mut reference = block(0.004, Some(0.0));
    reference.contact.as_mut().unwrap().friction = 0.0;
    let reference = solve(&reference).unwrap();
    assert!(reference.contact.as_ref().unwrap().friction.is_none());
    check_increments(&stepped, "μ = 0 steps");
    let (a, b) = (stepped.contact.as_ref().unwrap(), reference.contact.as_ref().unwrap());
    let scale = b.lcp.z.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    let dp = a.lcp.z.iter().zip(&b.lcp.z).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let du = stepped
        .displacement
        .iter()
        .zip(&reference.displacement)
        .map(|(x, y)| (x[0] - y[0]).hypot(x[1] - y[1]))
        .fold(0.0, f64::max);
    let t = a.friction.as_ref().unwrap().step.tangential.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    println!(
        "μ = 0 steps vs one step: max |ΔP| / max P = {:.2e}, max |Δu| / 0.01 = {:.2e}, max |T| = {t:.1e}",
        dp / scale,
        du / 0.01
    );
    assert!(dp <= 1e-12 * scale, "forces differ by {dp:.3e}");
    assert!(du <= 1e-12 * 0.01, "displacements differ by {du:.3e}");
    assert_eq!(t, 0.0);
}

#[test]
fn press_then_shear_meets_every_condition_at_every_increment() {
    let s = solve(&stepped_block(0.3, &press_then_shear(4, 8, 0.004))).unwrap();
    check_frictional(&s, "press then shear");
    let t = check_increments(&s, "press then shear");
    let f = s.contact.as_ref().unwrap().friction.as_ref().unwrap();
    assert_eq!(f.increments.len(), 12);
    // The shear builds up monotonically (T opposes the shift, so ΣT decreases).
    assert!(t[4..].windows(2).all(|w| w[1] < w[0]), "{t:?}");
    // The last increment is the reported answer.
    assert_eq!(f.increments.last().unwrap().tangential_force, f.total_force);
    // Unloading the shear afterwards leaves a residual tangential force where candidates slipped.
    let unload = format!(
        "{}[[step]]\nincrements = 4\nboundary = [{{ edge = \"top\", displacement = {{ x = 0.0 }} }}]\n",
        press_then_shear(4, 8, 0.004)
    );
    let u = solve(&stepped_block(0.3, &unload)).unwrap();
    let tu = check_increments(&u, "press, shear, unload");
    println!("after unloading: ΣT = {:.3e} (ΣT loaded {:.4})", tu[15], tu[11]);
}

#[test]
fn the_path_matters_only_when_something_slips() {
    // The same final load (top moved by (0.004, −0.01)) along three paths: A press, then
    // shear; B press and shear together (proportional); C press, shear to 0.008, back to 0.004.
    let paths = [
        ("press then shear", press_then_shear(4, 8, 0.004)),
        (
            "proportional",
            "[[step]]\nincrements = 8\nboundary = [{ edge = \"top\", displacement = { x = 0.004, y = -0.01 } }]\n"
                .to_string(),
        ),
        (
            "overshoot and back",
            format!(
                "{}[[step]]\nincrements = 8\nboundary = [{{ edge = \"top\", displacement = {{ x = 0.004 }} }}]\n",
                press_then_shear(4, 8, 0.008)
            ),
        ),
    ];
    let totals = |mu: f64| -> Vec<(f64, usize)> {
        paths
            .iter()
            .map(|(case, steps)| {
                let s = solve(&stepped_block(mu, steps)).unwrap();
                check_increments(&s, &format!("μ = {mu}, {case}"));
                let f = s.contact.as_ref().unwrap().friction.as_ref().unwrap();
                (f.total_force, f.increments.iter().map(|r| r.slip).sum())
            })
            .collect()
    };
    let slip = totals(0.3);
    println!("μ = 0.3: (ΣT, slipping candidate-increments) per path {slip:?}");
    assert!(slip.iter().all(|&(_, n)| n > 0));
    let (a, b, c) = (slip[0].0, slip[1].0, slip[2].0);
    assert!((a - b).abs() > 1e-5 * a.abs(), "A {a} vs B {b}");
    assert!((a - c).abs() > 1e-2 * a.abs(), "A {a} vs C {c}");
    let stick = totals(1e3);
    println!("μ = 1e3: (ΣT, slipping candidate-increments) per path {stick:?}");
    for &(t, n) in &stick {
        assert_eq!(n, 0);
        assert!((t - stick[0].0).abs() <= 1e-10 * t.abs(), "{t} vs {}", stick[0].0);
    }
}

#[test]
fn steps_are_validated() {
    let ok = press_then_shear(2, 2, 0.004);
    assert_eq!(stepped_block(0.3, &ok).steps.len(), 2);
    let parse = |mu: f64, steps: &str| {
        let text = stepped_block_text(mu, steps);
        Problem::from_toml(&text).unwrap_err().to_string()
    };
    for (steps, key) in [
        (ok.replace("increments = 2\nboundary", "increments = 0\nboundary"), "step[0].increments"),
        (ok.replace("increments = 2\nboundary", "incremnts = 2\nboundary"), "step[0].incremnts"),
        (ok.replacen("edge = \"top\"", "edge = \"left\"", 1), "step[0].boundary[0].edge"),
        (ok.replacen("edge = \"top\"", "edge = \"nowhere\"", 1), "step[0].boundary[0].edge"),
        (ok.replacen("displacement = {", "traction = {", 1), "step[0].boundary[0].traction.y"),
        (ok.replacen("displacement = {", "pressure = 1.0, x = {", 1), "step[0].boundary[0]"),
        ("[[step]]\nincrements = 2\n".into(), "step[0].boundary"),
        (format!("{ok}[[step]]\nobstacle_displacement = [1.0]\n"), "step[2].obstacle_displacement"),
        (
            format!("{ok}[[step]]\nobstacle_displacement = [nan, 0.0]\n"),
            "step[2].obstacle_displacement",
        ),
    ] {
        let e = parse(0.3, &steps);
        assert!(e.contains(key), "{key}: {e}");
    }
    // The loading starts from the unloaded body: a non-zero [[boundary]] value is refused.
    let text = stepped_block_text(0.3, &ok).replace("x = 0.0, y = 0.0 }", "x = 0.0, y = -0.01 }");
    let e = Problem::from_toml(&text).unwrap_err().to_string();
    assert!(e.contains("boundary[0].displacement.y"), "{e}");
    // Steps need a contact problem (here: the block clamped at the bottom, no contact).
    let text = stepped_block_text(0.3, &ok).replace(
        "[contact]\n        edge = \"bottom\"\n        obstacle_point = [0.0, 0.0]\n        obstacle_normal = [0.0, 1.0]\n        friction = 3e-1\n",
        "[[boundary]]\nedge = \"bottom\"\ndisplacement = { x = 0.0, y = 0.0 }\n",
    );
    let e = Problem::from_toml(&text).unwrap_err().to_string();
    assert!(e.contains("`step`") && e.contains("need contact"), "{e}");
}

/// The text of [`stepped_block`].
fn stepped_block_text(mu: f64, steps: &str) -> String {
    format!(
        r#"
        name = "block_steps"
        [geometry]
        kind = "rectangle"
        x = [0.0, 2.0]
        y = [0.0, 1.0]
        [nodes]
        spacing = 0.1
        [material]
        young = 1000.0
        poisson = 0.3
        plane = "stress"
        [[boundary]]
        edge = "top"
        displacement = {{ x = 0.0, y = 0.0 }}
        [contact]
        edge = "bottom"
        obstacle_point = [0.0, 0.0]
        obstacle_normal = [0.0, 1.0]
        friction = {mu:e}
        {steps}
        "#
    )
}

/// Two identical 2 × 1 blocks (E = 1000, ν = 0.3, plane stress, h = 0.1), the upper one's top
/// moved by `(shift, −0.01)`, the lower one's bottom clamped; friction `mu` between them.
fn two_blocks(shift: f64, mu: f64) -> Problem {
    Problem::from_toml(&format!(
        r#"
        [[body]]
        name = "upper"
        geometry = {{ kind = "rectangle", x = [0.0, 2.0], y = [1.0, 2.0] }}
        nodes = {{ spacing = 0.1 }}
        material = {{ young = 1000.0, poisson = 0.3, plane = "stress" }}
        boundary = [{{ edge = "top", displacement = {{ x = {shift:e}, y = -0.01 }} }}]
        [[body]]
        name = "lower"
        geometry = {{ kind = "rectangle", x = [0.0, 2.0], y = [0.0, 1.0] }}
        nodes = {{ spacing = 0.1 }}
        material = {{ young = 1000.0, poisson = 0.3, plane = "stress" }}
        boundary = [{{ edge = "bottom", displacement = {{ x = 0.0, y = 0.0 }} }}]
        [contact]
        edge = "bottom"
        target_edge = "top"
        friction = {mu:e}
        "#
    ))
    .unwrap()
}

#[test]
fn two_blocks_pressed_and_sheared() {
    // Frictionless reference: the blocks are mirror images about the interface (elastically
    // similar bodies), so M_nt = M_tn = 0 and the normal forces do not depend on friction.
    let p0 = solve(&two_blocks(0.0, 0.0)).unwrap().contact.unwrap().lcp.z;
    let p_max = p0.iter().fold(0.0f64, |m, p| m.max(p.abs()));
    for (shift, mu, case) in [
        (0.009, 0.3, "two blocks, partial slip"),
        (0.05, 0.2, "two blocks, gross sliding"),
        (0.002, 1e3, "two blocks, stick"),
    ] {
        let s = solve(&two_blocks(shift, mu)).unwrap();
        check_frictional(&s, case);
        let s2 = s.second_body.as_deref().unwrap();
        let c = s.contact.as_ref().unwrap();
        let f = c.friction.as_ref().unwrap();
        // The contact forces on the two bodies balance: body 1 gets +ν P + t T, body 2 the
        // opposite (ν = (0, 1), t = (1, 0)).
        let (f1, f2) = (s.contact_force, s2.contact_force);
        let total = c.total_force.abs().max(f.total_force.abs());
        let imbalance = (f1[0] + f2[0]).hypot(f1[1] + f2[1]);
        println!(
            "{case}: ΣP = {:.6}, ΣT = {:.6}, body forces ({:.6}, {:.6}) and ({:.6}, {:.6}), imbalance {:.1e}, equilibrium {:.1e} / {:.1e}, residual {:.1e} / {:.1e}, stick {} slip {} of {}",
            c.total_force,
            f.total_force,
            f1[0],
            f1[1],
            f2[0],
            f2[1],
            imbalance / total,
            s.equilibrium_error,
            s2.equilibrium_error,
            s.relative_residual,
            s2.relative_residual,
            f.step.state.iter().filter(|&&x| x == ContactState::Stick).count(),
            f.step.state.iter().filter(|x| x.is_slip()).count(),
            f.step.state.len()
        );
        assert!((f1[0] - f.total_force).abs() <= 1e-12 * total, "{case}: {f1:?}");
        assert!(imbalance <= 1e-12 * total, "{case}: {f1:?} vs {f2:?}");
        assert!(
            s2.equilibrium_error <= 1e-8,
            "{case}: body 2 equilibrium {}",
            s2.equilibrium_error
        );
        assert!(f.total_force.abs() > 1e-3 * c.total_force, "{case}: no shear");
        let inc = f.increments.last().unwrap();
        assert!(inc.equilibrium_error <= 1e-8 && inc.complementarity <= 1e-9, "{case}: {inc:?}");
        let dp = c.lcp.z.iter().zip(&p0).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        println!("{case}: max |P − P_frictionless| / max P = {:.1e}", dp / p_max);
        assert!(dp <= 1e-9 * p_max, "{case}: normal forces depend on friction by {dp:.3e}");
        let (stick, slip) = (
            f.step.state.iter().filter(|&&x| x == ContactState::Stick).count(),
            f.step.state.iter().filter(|x| x.is_slip()).count(),
        );
        match case {
            "two blocks, partial slip" => {
                assert!(stick > 0 && slip > 0, "{case}: {:?}", f.step.state)
            }
            "two blocks, stick" => assert_eq!(slip, 0, "{case}"),
            _ => assert_eq!(stick, 0, "{case}"),
        }
        if mu < 1.0 && shift > 0.01 {
            let ratio = f.total_force / c.total_force;
            assert!((ratio + mu).abs() <= 1e-10, "{case}: ΣT/ΣP = {ratio}");
        }
    }
}

/// A half-disk of radius 1 (centre (0, 1); E = 1, ν = `nu`, plane strain, spacing `h`) on the
/// rigid line y = 0 with `μ = 0.3`: its top is pressed down by 0.015 in one step, then moved
/// sideways by `shift` in 8 increments with the press held.
fn cylinder_pressed_then_sheared(h: f64, nu: f64, shift: f64) -> Problem {
    Problem::from_toml(&format!(
        r#"
        name = "cattaneo_mindlin"
        [geometry]
        kind = "curves"
        start = [1.0, 1.0]
        curves = [
            {{ name = "top", to = [-1.0, 1.0] }},
            {{ name = "arc", to = [1.0, 1.0], center = [0.0, 1.0] }},
        ]
        [nodes]
        spacing = {h:e}
        [material]
        young = 1.0
        poisson = {nu:e}
        plane = "strain"
        [[boundary]]
        edge = "top"
        displacement = {{ x = 0.0, y = 0.0 }}
        [contact]
        edge = "arc"
        obstacle_point = [0.0, 0.0]
        obstacle_normal = [0.0, 1.0]
        friction = 0.3
        [[step]]
        boundary = [{{ edge = "top", displacement = {{ y = -0.015 }} }}]
        [[step]]
        increments = 8
        boundary = [{{ edge = "top", displacement = {{ x = {shift:e} }} }}]
        "#
    ))
    .unwrap()
}

/// Cattaneo–Mindlin [J85 §7.1]: a cylinder pressed by `P`, then sheared by `Q < μP` with the
/// press held, sticks on `|x| < c` with `c/a = (1 − Q/μP)^{1/2}`. The theory assumes the
/// normal and tangential problems uncouple (elastically similar bodies, Dundurs' β = 0);
/// two bodies do not take load steps yet, so this is the cylinder on a rigid flat with
/// ν = 0.45 (β = (1 − 2ν)/(2(1 − ν)) = 0.09, a weak coupling that shifts the stick zone a
/// little). `a` and `c` are read at mid-segment between the outermost closed (sticking)
/// candidate and its open (slipping) neighbour, so each is known to about ±h/2 per side.
/// Observed (c/a against the theory at Q/μP ≈ 0.26, 0.51, 0.76): h = 0.02: 0.834 / 0.859,
/// 0.668 / 0.695, 0.417 / 0.490 (errors up to 0.073); h = 0.01: 0.858 / 0.860, 0.715 /
/// 0.697, 0.501 / 0.495 (errors ≤ 0.018); h = 0.005: 0.834 / 0.860, 0.691 / 0.698, 0.501 /
/// 0.496 (errors ≤ 0.026, i.e. at that spacing's read-off resolution h/(2a) = 0.024). The
/// error does not fall steadily with h: below h = 0.01 it is set by the read-off and by the
/// coupling, not by the discretisation. The tolerance 0.04 at h = 0.01 lies inside that
/// spacing's read-off resolution (0.048) and above every error seen at h ≤ 0.01; the h = 0.02
/// errors (0.073) exceed it.
#[test]
fn cattaneo_mindlin_stick_zone() {
    let h = 0.01;
    for shift in [0.0024, 0.0048, 0.0072] {
        let s = solve(&cylinder_pressed_then_sheared(h, 0.45, shift)).unwrap();
        let t = check_increments(&s, &format!("Cattaneo–Mindlin, shift {shift}"));
        let c = s.contact.as_ref().unwrap();
        let f = c.friction.as_ref().unwrap();
        let (p, q) = (c.total_force, -t[t.len() - 1]);
        let ratio = q / (0.3 * p);
        let x: Vec<f64> = c.candidates.points.iter().map(|p| p[0]).collect();
        let closed: Vec<bool> = f.step.normal.iter().map(|&p| p > 0.0).collect();
        let stick: Vec<bool> = f.step.state.iter().map(|&s| s == ContactState::Stick).collect();
        // Half the extent of the run where `inside` holds, read at mid-segment to the
        // neighbours (the candidates are ordered along the arc).
        let half_width = |inside: &[bool]| {
            let first = inside.iter().position(|&v| v).unwrap();
            let last = inside.iter().rposition(|&v| v).unwrap();
            assert!(inside[first..=last].iter().all(|&v| v), "not one zone: {inside:?}");
            let lo = 0.5 * (x[first] + x[first - 1]);
            let hi = 0.5 * (x[last] + x[last + 1]);
            0.5 * (hi - lo).abs()
        };
        let (a, cz) = (half_width(&closed), half_width(&stick));
        let theory = (1.0 - ratio).sqrt();
        println!(
            "Cattaneo–Mindlin h = {h}: P = {p:.5}, Q/μP = {ratio:.3}, a = {a:.4}, c/a = {:.3}, theory {theory:.3}, error {:+.3}",
            cz / a,
            cz / a - theory
        );
        assert!(ratio > 0.2 && ratio < 0.8, "Q/μP = {ratio}");
        assert!((cz / a - theory).abs() <= 0.04, "c/a = {} vs {theory}", cz / a);
    }
}
