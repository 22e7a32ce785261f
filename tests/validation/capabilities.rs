//! The capability matrix of the contact core (docs/dev/contact_core.md): every combination of
//! friction, load steps, adaptive refinement and the two contact solvers, for one body on a
//! rigid flat (top-level tables, or one `[[body]]` table), two bodies in one pair (a
//! `[contact]` table, or a `[[contact]]` table with the upper body's candidates) and three
//! bodies in two pairs. Each combination either
//! solves, with every check of the run passing (`summary.json`'s `checks.verdicts`: each
//! body's residual and equilibrium, the contact answer's complementarity, each increment's),
//! or is refused with a message naming the key that decides it. None is refused: the
//! several-pairs path (pairs written as `[[contact]]` tables) takes friction and load steps
//! on Lemke's path and on the active set's sparse path, as the two-body path does.
//!
//! **Problems.** Elastic blocks of width 2 stacked on a rigid flat or on one another, each
//! with a roller on its left edge, the top block's top edge pushed down by 0.01 (uniaxial
//! stress without friction), non-matching node spacings; `friction = 0.3` on every pair;
//! the push in one `[[step]]` of 2 increments; `[refinement]` of one step. Every pair sets
//! `allow_indefinite = true`: on the graded, non-matching node sets of a refinement step the
//! condensed compliance's symmetric part has a small negative eigenvalue, which the run-time
//! check refuses by default (a property of the discretisation, not of the combination;
//! docs/dev/contact_core.md); the answers' own checks are asserted instead.
//!
//! **Reference.** Without friction, every combination gives the uniaxial answer: the force on
//! every interface `2 δ / Σ L_i/E_i` (1e-8 relative: the MFVM reproduces linear fields on
//! any node set). With friction, one or two bodies written either way are the same LCP (on the
//! two-body and on the several-pairs path for two bodies): equal forces to 1e-9; and the two
//! solvers answer the same LCP: equal forces to 1e-9 on every path.

use mlpg_contact::Silent;
use mlpg_contact::pipeline::Outcome;
use mlpg_contact::problem::Problem;

/// One combination of the matrix.
#[derive(Clone, Copy, Debug)]
struct Features {
    friction: bool,
    steps: bool,
    refinement: bool,
    active_set: bool,
}

/// A block `[0, 2] × [y0, y0 + 1]` as a `[[body]]` table.
fn block(name: &str, y0: f64, spacing: f64, young: f64, boundary: &str) -> String {
    format!(
        "[[body]]\nname = \"{name}\"\ngeometry = {{ kind = \"rectangle\", x = [0.0, 2.0], y = [{y0:?}, {:?}] }}\nnodes = {{ spacing = {spacing:?} }}\nmaterial = {{ young = {young:?}, poisson = 0.3, plane = \"stress\" }}\nboundary = [{{ edge = \"left\", displacement = {{ x = 0.0 }} }}{boundary}]\n",
        y0 + 1.0
    )
}

/// The scene with `bodies` blocks (1: on a rigid flat; 2 and 3: on a restrained bottom
/// block) and the combination `f`; the exact frictionless interface force. `listed`: the
/// pairs as `[[contact]]` tables (always with three bodies); otherwise two bodies' one pair
/// is a `[contact]` table, the upper block's bottom against the lower's top.
fn scene(bodies: usize, listed: bool, f: Features) -> (String, f64) {
    let youngs = [1000.0, 300.0, 3000.0];
    let spacings = [0.1, 0.125, 0.0833];
    if bodies == 1 && !listed {
        return (one_body(f), 2.0 * 0.01 * youngs[0]);
    }
    let top_push = if f.steps { "y = 0.0" } else { "y = -0.01" };
    let mut tables: Vec<String> = (0..bodies)
        .map(|k| {
            let mut boundary = String::new();
            if k == 0 && bodies > 1 {
                boundary.push_str(", { edge = \"bottom\", displacement = { y = 0.0 } }");
            }
            if k + 1 == bodies {
                boundary
                    .push_str(&format!(", {{ edge = \"top\", displacement = {{ {top_push} }} }}"));
            }
            block(&format!("b{k}"), k as f64, spacings[k], youngs[k], &boundary)
        })
        .collect();
    let mut pair = String::from("allow_indefinite = true\n");
    if f.friction {
        pair.push_str("friction = 0.3\n");
    }
    if f.active_set {
        pair.push_str("solver = \"active_set\"\n");
    }
    let pairs: String = if listed && bodies == 1 {
        format!(
            "[[contact]]\nbody = \"b0\"\nedge = \"bottom\"\nobstacle_point = [0.0, 0.0]\nobstacle_normal = [0.0, 1.0]\n{pair}"
        )
    } else if listed {
        (1..bodies)
            .map(|k| {
                format!(
                    "[[contact]]\nbody = \"b{k}\"\nedge = \"bottom\"\ntarget_body = \"b{}\"\ntarget_edge = \"top\"\n{pair}",
                    k - 1
                )
            })
            .collect()
    } else {
        // One `[contact]` table: the candidates' body is the first `[[body]]`, the upper one.
        tables.reverse();
        format!("[contact]\nedge = \"bottom\"\ntarget_edge = \"top\"\n{pair}")
    };
    let mut text = String::from("[discretisation]\nsupport_factor = 2.0\n");
    text.extend(tables);
    text.push_str(&pairs);
    if f.steps {
        text.push_str(&format!(
            "[[step]]\nincrements = 2\nboundary = [{{ body = \"b{}\", edge = \"top\", displacement = {{ y = -0.01 }} }}]\n",
            bodies - 1
        ));
    }
    if f.refinement {
        text.push_str("[refinement]\nsteps = 1\n");
    }
    let compliance: f64 = youngs[..bodies].iter().map(|e| 1.0 / e).sum();
    (text, 2.0 * 0.01 / compliance)
}

/// The [`scene`] of one block on a rigid flat, written with top-level tables.
fn one_body(f: Features) -> String {
    let push = if f.steps { "0.0" } else { "-0.01" };
    let mut text = format!(
        "[discretisation]\nsupport_factor = 2.0\n[geometry]\nkind = \"rectangle\"\nx = [0.0, 2.0]\ny = [0.0, 1.0]\n[nodes]\nspacing = 0.1\n[material]\nyoung = 1000.0\npoisson = 0.3\nplane = \"stress\"\n[[boundary]]\nedge = \"left\"\ndisplacement = {{ x = 0.0 }}\n[[boundary]]\nedge = \"top\"\ndisplacement = {{ y = {push} }}\n[contact]\nedge = \"bottom\"\nobstacle_point = [0.0, 0.0]\nobstacle_normal = [0.0, 1.0]\nallow_indefinite = true\n"
    );
    if f.friction {
        text.push_str("friction = 0.3\n");
    }
    if f.active_set {
        text.push_str("solver = \"active_set\"\n");
    }
    if f.steps {
        text.push_str("[[step]]\nincrements = 2\nboundary = [{ edge = \"top\", displacement = { y = -0.01 } }]\n");
    }
    if f.refinement {
        text.push_str("[refinement]\nsteps = 1\n");
    }
    text
}

/// What a combination gives: `Ok(interface forces)` or `Err(message)`.
fn outcome(text: &str) -> Result<(Vec<f64>, bool), String> {
    let problem = Problem::from_toml(text).map_err(|e| e.to_string())?;
    let o =
        Outcome::solve(problem, serde_json::Value::Null, &mut Silent).map_err(|e| e.to_string())?;
    let forces = match (&o.solution.multibody, &o.solution.contact) {
        (Some(m), _) => m.pairs.iter().map(|c| c.total_force).collect(),
        (None, Some(c)) => vec![c.total_force],
        (None, None) => Vec::new(),
    };
    for v in o.summary.checks.verdicts.iter().filter(|v| !v.pass) {
        println!("    failed check {} at {}: {:e} > {:e}", v.check, v.key, v.value, v.tolerance);
    }
    Ok((forces, o.summary.checks.passed))
}

#[test]
fn every_combination_solves_with_its_checks() {
    let mut rows = Vec::new();
    // The two-body answers of the `[contact]` form, per combination, for the `[[contact]]` form;
    // Lemke's answers per scene and combination, for the active set's.
    let mut pair_form = std::collections::HashMap::new();
    let mut lemke = std::collections::HashMap::new();
    for (bodies, listed) in [(1, false), (1, true), (2, false), (2, true), (3, true)] {
        for bits in 0..16u32 {
            let f = Features {
                friction: bits & 1 != 0,
                steps: bits & 2 != 0,
                refinement: bits & 4 != 0,
                active_set: bits & 8 != 0,
            };
            let (text, exact) = scene(bodies, listed, f);
            let form = if listed { "[[contact]]" } else { "[contact]" };
            let label =
                format!("{bodies} bod{}, {form}, {f:?}", if bodies == 1 { "y" } else { "ies" });
            let (forces, passed) = outcome(&text).unwrap_or_else(|e| panic!("{label}: {e}"));
            assert!(passed, "{label}: a check failed");
            assert_eq!(forces.len(), bodies.max(2) - 1, "{label}");
            if !f.friction {
                for p in &forces {
                    let error = (p - exact).abs() / exact;
                    assert!(error <= 1e-8, "{label}: force {p} against {exact}");
                }
            }
            if !listed {
                pair_form.insert((bodies, bits), forces[0]);
            } else if let Some(p) = pair_form.get(&(bodies, bits)) {
                // Same LCP on the two-body and the several-pairs path.
                let difference = (forces[0] - p).abs() / p;
                assert!(difference <= 1e-9, "{label}: {} against [contact] {p}", forces[0]);
            }
            if !f.active_set {
                lemke.insert((bodies, listed, bits), forces.clone());
            } else {
                // Same LCP by either solver.
                let by_lemke = &lemke[&(bodies, listed, bits & 7)];
                for (p, q) in forces.iter().zip(by_lemke) {
                    let difference = (p - q).abs() / q;
                    assert!(difference <= 1e-9, "{label}: {p} against Lemke's {q}");
                }
            }
            rows.push(format!("{label}: solves, forces {forces:.6?}"));
        }
    }
    for row in &rows {
        println!("{row}");
    }
}
