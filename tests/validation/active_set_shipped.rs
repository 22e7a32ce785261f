//! The active-set solver (docs/method.md §5.1, `contact.solver = "active_set"`) against
//! Lemke's method on every shipped problem with contact: the files of `problems/` are listed
//! at run time, so a new problem file is covered without touching this test. Each file is
//! read twice, with `solver = "lemke"` and with `solver = "active_set"` set in its contact
//! table(s); both answers are checked on their own (scaled complementarity, equilibrium) and
//! against each other as `active_set::compare_solutions` does, the same closed set, and here
//! strictly: forces and gaps within 5e-10 of the largest force resp. gap, without the looser
//! bound `compare_solutions` allows for ill-conditioned `M` (the same LCP solved two ways;
//! Lemke's answer is polished on its closed set, `lcp::polish`, so what is left is the
//! round-off of the two routes to `M`: at most 1.8e-10, on the refined beam, κ(M) = 2.9e5,
//! whose graded node set `K` is factorised by the static-pivoting LU in the banded order
//! since that became the cheaper choice there; 6.7e-11 with the earlier ordering).
//! With friction the tangential forces are compared too, and for a load-driven obstacle or a
//! translation held by the contact (docs/method.md §4.6–4.7) the displacement found.
//!
//! Adaptive files (`[refinement]`) are compared over their first [`REFINEMENT_STEPS`]
//! refinement steps, graded node sets included: the rest of a loop only repeats the same
//! solve on larger sets (it was 60 % of this test's time; the shipped loops run whole in
//! tests/cli.rs and in their own validation suites).
//!
//! Files the active set cannot take yet are listed in [`REFUSED`] with the reason; each must
//! be refused with a message naming `contact.solver` (or `contact[k].solver`) and the value,
//! and an entry whose file is solved, or no longer exists, fails the test: the list can only
//! shrink.

use super::active_set::{compare_multibody, compare_solutions, max_abs};
use mlpg_contact::problem::Problem;
use mlpg_contact::solution::Solution;

/// Agreement of forces, gaps, displacements found by the searches and tangential forces
/// (relative to the largest).
const AGREEMENT: f64 = 5e-10;

/// Shipped files the active-set solver refuses, with the reason.
const REFUSED: &[(&str, &str)] = &[];

/// The refinement steps an adaptive file is compared over (its `[refinement] steps`, capped).
const REFINEMENT_STEPS: usize = 2;

/// `text` with its `[refinement] steps` capped at `most` (unchanged without the table).
fn with_refinement_steps(text: &str, most: usize) -> String {
    let mut out = String::new();
    let mut in_refinement = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with('[') {
            in_refinement = t == "[refinement]";
        }
        let value =
            t.strip_prefix("steps").map(|r| r.trim_start()).and_then(|r| r.strip_prefix('='));
        let steps = value.and_then(|v| v.split('#').next()?.trim().parse::<usize>().ok());
        match steps {
            Some(n) if in_refinement && n > most => out.push_str(&format!("steps = {most}")),
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    out
}

/// Whether the problem text has a contact table.
fn has_contact(text: &str) -> bool {
    text.lines().any(|l| matches!(l.trim(), "[contact]" | "[[contact]]"))
}

/// `text` with `solver = "<solver>"` in every contact table (any `solver` key there
/// replaced).
fn with_solver(text: &str, solver: &str) -> String {
    let mut out = String::new();
    let mut in_contact = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with('[') {
            in_contact = matches!(t, "[contact]" | "[[contact]]");
            out.push_str(line);
            out.push('\n');
            if in_contact {
                out.push_str(&format!("solver = \"{solver}\"\n"));
            }
            continue;
        }
        if in_contact && t.split('=').next().is_some_and(|k| k.trim() == "solver") {
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// The shipped problem files with contact, sorted, with their text.
fn contact_files() -> Vec<(String, String)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let mut files: Vec<(String, String)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(&p).unwrap();
            (name, with_refinement_steps(&text, REFINEMENT_STEPS))
        })
        // Dynamics (each time step's contact; the active set per step against Lemke's:
        // tests/validation/dynamics_active_set.rs) has its own suite.
        .filter(|(_, text)| has_contact(text) && !text.contains("\n[dynamics]\n"))
        .collect();
    files.sort();
    files
}

fn solve(file: &str, text: &str, solver: &str) -> Result<Solution, String> {
    let problem = Problem::from_toml(&with_solver(text, solver)).map_err(|e| e.to_string())?;
    mlpg_contact::solve(&problem).map_err(|e| format!("{file}: {e}"))
}

/// Relative difference of two values of a search (displacement, translation).
fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

#[test]
fn every_shipped_contact_problem_equals_lemke_or_is_refused() {
    let files = contact_files();
    assert!(files.len() >= 10, "{} contact problem files", files.len());
    for (file, _) in REFUSED {
        assert!(files.iter().any(|(f, _)| f == file), "{file} is listed but not shipped");
    }
    for (file, text) in &files {
        if let Some((_, why)) = REFUSED.iter().find(|(f, _)| f == file) {
            let message = match solve(file, text, "active_set") {
                Err(e) => e,
                Ok(_) => panic!("{file} is listed as refused ({why}) but the active set solved it"),
            };
            assert!(
                message.contains("solver`") && message.contains("active_set"),
                "{file}: the refusal does not name the key and the value: {message}"
            );
            println!("{file}: refused ({why}): {message}");
            continue;
        }
        let lemke = solve(file, text, "lemke").unwrap();
        let active = solve(file, text, "active_set").unwrap();
        if lemke.multibody().is_some() {
            let (force, gap, t) = compare_multibody(file, &lemke, &active);
            let ms = active.multibody().unwrap();
            let solves = ms.contact.active_set.as_ref().map_or(0, |r| r.iterations);
            let held = ms.contact.held.first().map_or(String::new(), |(_, r)| {
                format!(
                    ", translation {t:.1e} ({} LCP solves, {solves} linear solves)",
                    r.evaluations
                )
            });
            println!("{file}: forces {force:.1e}, gaps {gap:.1e}{held}");
            continue;
        }
        let (force, gap) = compare_solutions(file, &lemke, &active);
        assert!(force < AGREEMENT, "{file}: forces differ by {force:e} of the largest");
        assert!(gap < AGREEMENT, "{file}: gaps differ by {gap:e} of the largest");
        let (a, b) = (active.contact().unwrap(), lemke.contact().unwrap());
        let mut extra = String::new();
        match (&a.friction, &b.friction) {
            (Some(fa), Some(fb)) => {
                let p_max = max_abs(&b.lcp.z).max(f64::MIN_POSITIVE);
                let t = fa
                    .step
                    .tangential
                    .iter()
                    .zip(&fb.step.tangential)
                    .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
                    / p_max;
                assert!(t < AGREEMENT, "{file}: tangential forces differ by {t:e}");
                assert_eq!(fa.step.state, fb.step.state, "{file}: stick/slip states differ");
                extra += &format!(", tangential {t:.1e}");
            }
            (None, None) => {}
            _ => panic!("{file}: one answer has a frictional record, the other not"),
        }
        match (&a.load_driven, &b.load_driven) {
            (Some(la), Some(lb)) => {
                let d = relative(la.displacement_along, lb.displacement_along);
                assert!(d < AGREEMENT, "{file}: obstacle displacements differ by {d:e}");
                extra += &format!(
                    ", obstacle s {d:.1e} ({} against {} LCP solves)",
                    la.evaluations, lb.evaluations
                );
            }
            (None, None) => {}
            _ => panic!("{file}: one answer is load-driven, the other not"),
        }
        match (&a.rigid_mode, &b.rigid_mode) {
            (Some(ra), Some(rb)) => {
                let t = ra.translation.iter().zip(&rb.translation);
                let d = t.fold(0.0_f64, |m, (x, y)| m.max(relative(*x, *y)));
                assert!(d < AGREEMENT, "{file}: held translations differ by {d:e}");
                extra += &format!(
                    ", translation {d:.1e} ({} against {} LCP solves)",
                    ra.evaluations, rb.evaluations
                );
            }
            (None, None) => {}
            _ => panic!("{file}: one answer has a held translation, the other not"),
        }
        println!("{file}: forces {force:.1e}, gaps {gap:.1e}{extra}");
    }
}

/// [`with_refinement_steps`] caps the loop's steps and leaves every other `steps` alone.
#[test]
fn with_refinement_steps_caps_the_loop_only() {
    let text = "[[step]]\nsteps = 9\n[refinement]\nsteps = 8   # at most\nmax_nodes = 2\n";
    assert_eq!(
        with_refinement_steps(text, 2),
        "[[step]]\nsteps = 9\n[refinement]\nsteps = 2\nmax_nodes = 2\n"
    );
    let few = "[refinement]\nsteps = 1\n";
    assert_eq!(with_refinement_steps(few, 2), few);
}

/// [`with_solver`] sets the key in single and repeated contact tables and replaces one given.
#[test]
fn with_solver_sets_every_contact_table() {
    let text = "[contact]\nedge = \"a\"\nsolver = \"auto\"\n[[step]]\nsolver_x = 1\n";
    assert_eq!(
        with_solver(text, "lemke"),
        "[contact]\nsolver = \"lemke\"\nedge = \"a\"\n[[step]]\nsolver_x = 1\n"
    );
    let pairs = "[[contact]]\nbody = \"a\"\n[[contact]]\nbody = \"b\"\n";
    assert_eq!(with_solver(pairs, "active_set").matches("solver = \"active_set\"").count(), 2);
}
