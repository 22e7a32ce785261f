//! # Build a problem in code
//!
//! A problem does not have to come from a TOML file. This example builds one from the raw
//! problem structs of [`mlpg_contact::problem`] (the TOML tables, one struct each, with public
//! fields), validates it exactly as a file is validated, and solves it. It also shows what
//! happens to a bad value: validation refuses it with an error that names the field.
//!
//! ```text
//! cargo run --release --example build_problem
//! ```
//!
//! It runs in well under a second. The problem: a cantilever strip 8 × 1, clamped at its left
//! end, under a uniform downward load on its top edge, above a rigid foundation 0.05 below its
//! bottom edge; plane stress. The tip would deflect about 0.6 without the foundation, so the
//! strip comes to rest on it.

use mlpg_contact::material::PlaneState;
use mlpg_contact::problem::{
    BoundaryFile, ComponentsFile, ContactFile, DiscretisationFile, GeometryFile, MaterialFile,
    NodesFile, OutputFile, Problem, ProblemError, ProblemFile,
};

/// The problem as the raw structs. Each struct is one table of a problem file; a field that
/// is an `Option` may be left out of a file, and `None` here means the same: its default. The
/// constructors (`NodesFile::structured`, `BoundaryFile::displacement`, …) fill in the rest.
fn strip_on_foundation() -> ProblemFile {
    ProblemFile {
        name: Some("strip_on_foundation".into()),
        // [geometry]: a rectangle, whose edges are named bottom, right, top and left.
        geometry: Some(GeometryFile::Rectangle { x: [0.0, 8.0], y: [0.0, 1.0], holes: vec![] }),
        // [nodes]: the nominal node spacing h, on a structured grid.
        nodes: Some(NodesFile::structured(0.125)),
        // [material]: Young's modulus, Poisson's ratio, plane stress.
        material: Some(MaterialFile::new(1000.0, 0.3, PlaneState::Stress)),
        // [discretisation]: everything at its default (the paper's mixed MFVM: linear basis,
        // support factor 2, β = 0). `DiscretisationFile { beta: Some(BetaChoice::Value(1.0)), ..Default::default() }`
        // would choose the stabilised variant.
        discretisation: DiscretisationFile::default(),
        // [[boundary]]: one entry per edge with a condition; the others are traction-free.
        boundary: vec![
            BoundaryFile::displacement("left", ComponentsFile::xy(0.0, 0.0)),
            BoundaryFile::traction("top", ComponentsFile::y(-0.1)),
        ],
        // [contact]: the bottom edge against a rigid straight line through a point, whose
        // normal points into the body.
        contact: Some(ContactFile::rigid_line("bottom", [0.0, -0.05], [0.0, 1.0]).into()),
        // [output]: which edge's displacement profile to plot (used by `mlpg_contact::run`).
        output: OutputFile { profile_edge: Some("bottom".into()), ..Default::default() },
        // Everything else at its default (two-body problems list two [[body]] tables instead
        // of geometry, nodes, …).
        ..ProblemFile::default()
    }
}

fn main() -> anyhow::Result<()> {
    let file = strip_on_foundation();

    // The same problem as TOML text: what a problem file for it would say.
    println!("The problem, as a problem file:\n\n{}", toml::to_string(&file)?);

    // Validation: `Problem::try_from` checks every value, resolves edge names and defaults,
    // and builds the `Problem` the solver takes. It takes the file by value, so keep a clone
    // to vary it.
    let problem = Problem::try_from(file.clone())?;
    let solution = mlpg_contact::solve(&problem)?;
    let contact = solution.contact().expect("the problem has a [contact] table");
    let lowest = solution.displacement.iter().map(|u| u[1]).fold(f64::INFINITY, f64::min);
    println!("{} nodes; largest downward displacement {:.4}", solution.displacement.len(), -lowest);
    println!(
        "total contact force {:.4} of the applied {:.4}; contact from x = {:.3} on",
        contact.total_force,
        -solution.applied_force[1],
        contact.onset.from_gap.unwrap_or(f64::NAN)
    );

    // A bad value: Poisson's ratio must be below 0.5. Validation refuses the whole problem with
    // a `ProblemError` whose message names the field, the value and what is allowed.
    let mut bad = file;
    if let Some(material) = bad.material.as_mut() {
        material.poisson = 0.5;
    }
    match Problem::try_from(bad) {
        Ok(_) => println!("\nunexpected: poisson = 0.5 was accepted"),
        Err(error) => {
            println!("\nWith poisson = 0.5:\n  error: {error}");
            // The parts are there for a program to use, too.
            if let ProblemError::Invalid { field, .. } = &error {
                println!("  (the field to fix: {field})");
            }
        }
    }
    Ok(())
}
