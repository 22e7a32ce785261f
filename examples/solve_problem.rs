//! # Solve a problem file
//!
//! The first thing to do with `mlpg_contact` as a library: read a problem file, solve it, read
//! the answer off the [`Solution`](mlpg_contact::Solution), and write the same outputs as the
//! `mlpg-contact` command line.
//!
//! ```text
//! cargo run --release --example solve_problem       # problems/beam_on_foundation.toml
//! cargo run --release --example solve_problem -- problems/hertz_cylinder.toml
//! ```
//!
//! Paths are relative to the directory you run `cargo` in (the crate's root in the commands
//! above). The outputs go to `out/solve_problem/<problem name>/`. The paper's beam (4 825
//! nodes) takes under a second in release mode, although it is solved twice, once by `solve`
//! and once by `run`.
//!
//! The steps:
//! 1. read the file into the raw [`ProblemFile`] (the TOML as written) and validate it into a
//!    [`Problem`] (every value checked; an error names the field);
//! 2. [`mlpg_contact::solve`]: the whole pipeline (nodes, MLS shape functions, assembly, sparse
//!    LU, contact condensation and Lemke, recovery);
//! 3. the headline numbers, from the fields of the solution;
//! 4. [`mlpg_contact::run`]: solve and write every output file.

use anyhow::Context;
use mlpg_contact::problem::{Problem, ProblemFile};
use std::path::{Path, PathBuf};

fn main() -> anyhow::Result<()> {
    // The problem file: the first argument, or the paper's beam on a rigid foundation.
    let path = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("problems/beam_on_foundation.toml"), PathBuf::from);

    // Step 1. `Problem::from_toml(&text)` does both halves at once. Parsing into the raw
    // `ProblemFile` first keeps a copy of the input, which `run` echoes into summary.json.
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let file = ProblemFile::from_toml(&text).with_context(|| format!("in {}", path.display()))?;
    let input = serde_json::to_value(&file)?;
    let problem = Problem::try_from(file).with_context(|| format!("in {}", path.display()))?;

    // Step 2. One call from the validated problem to the solution.
    let started = std::time::Instant::now();
    let solution = mlpg_contact::solve(&problem)?;
    println!("{}: solved in {:.2} s", problem.name, started.elapsed().as_secs_f64());

    // Step 3. The solution holds per-node fields (`displacement` is u^h at the nodes, `stress`
    // the nodal stresses) and global checks. The equilibrium error is
    // |Σ f + Σ R + Σ P| / max(|Σ f|, Σ |R|, Σ P): the applied loads, the reactions and the
    // contact forces must balance.
    println!("  nodes:               {}", solution.displacement.len());
    println!("  equilibrium error:   {:.2e}", solution.equilibrium_error);
    println!("  relative residual:   {:.2e}", solution.relative_residual);

    // `solution.contact` is `Some` when the problem has a [contact] table. Its `onset` holds
    // the estimates of where the closed zone begins, as arc length along the contact edge
    // from the edge's first vertex: `from_gap` (the one summary.json reports as onset_x)
    // extrapolates from the open side, and is `None` when no open candidate precedes the
    // first closed one.
    match solution.contact() {
        Some(contact) => {
            let closed = contact.closed.iter().filter(|&&c| c).count();
            println!("  contact candidates:  {} ({closed} closed)", contact.closed.len());
            println!("  total contact force: {:.6}", contact.total_force);
            match (contact.onset.from_gap, contact.onset.first_closed) {
                (Some(onset), _) => println!("  contact onset l_c:   {onset:.4}"),
                (None, Some(first)) => {
                    println!(
                        "  contact onset l_c:   none: closed from the first candidate ({first:.4})"
                    )
                }
                (None, None) => println!("  contact onset l_c:   none: no candidate is closed"),
            }
        }
        None => println!("  (no contact in this problem)"),
    }

    // Step 4. `run` is what the command line does: it solves again and writes the CSV
    // tables, the VTU file, the plots and summary.json into `out`, and returns the summary as
    // a typed struct (`report.summary.contact`, `.checks`, …).
    let out = Path::new("out").join("solve_problem").join(&problem.name);
    let report = mlpg_contact::run(&problem, &out, input, &mut mlpg_contact::Silent)?;
    println!("{report} into {}", out.display());
    Ok(())
}
