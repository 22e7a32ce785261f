//! Two elastic spheres of revolution, MFVM and FE (docs/dev/axisymmetric.md, increment 7e):
//! the upper `R₁ = 1`, `E₁ = 1`, `ν₁ = 0.3` pushed 0.008 onto the lower `R₂ = 2`, `E₂ = 2`,
//! `ν₂ = 0.25` (`tests/validation/axisymmetric_spheres.rs`). Prints, per run, the rings'
//! axial force `F`, the fitted contact radius `a` and peak `p₀`, their errors against Hertz
//! for that `F`, the closed rings, the nodes of both bodies and the wall time.
//!
//! FE on Gmsh meshes of both sections (`tests/data/fem_meshes/two_spheres.geo`; by default
//! the committed `two_spheres_{0,1,2}.msh`, element size `hc` = 0.02, 0.01, 0.005 near the
//! contact; `--meshes` takes other files, e.g. written by `make_two_spheres.py --hc … --out
//! DIR`), then MFVM with the contact box at `h` and, optionally, a middle box at `mid`
//! (`--mfvm MID:H,…`, `-` for no middle box). Every run passes the test's checks
//! (complementarity, both balances, Newton's third law ring by ring). Nothing else is
//! asserted (the test `validation two_elastic_spheres_fe` uses one FE mesh and one MFVM set).
//!
//! `cargo run --release --features studies --example two_spheres -- [--meshes A.msh,B.msh]
//! [--mfvm -:0.01,-:0.005,0.0125:0.0025,0.00625:0.0025]`

mod args;
#[path = "../../tests/validation/axisymmetric_spheres.rs"]
#[allow(dead_code)]
mod axisymmetric_spheres;
#[path = "../../tests/validation/common.rs"]
#[allow(dead_code)]
mod common;

use axisymmetric_spheres::{measure, mesh_file, spheres_fem, spheres_mfvm};
use std::path::PathBuf;
use std::time::Instant;

/// FE meshes and MFVM node sets of the two spheres.
#[derive(clap::Parser)]
struct Cli {
    /// FE mesh files (default: the committed two_spheres_{0,1,2}.msh)
    #[arg(long, value_name = "FILE,…", value_delimiter = ',')]
    meshes: Vec<PathBuf>,
    /// MFVM node sets MID:H (middle box [0, 0.5] × 0.25 at MID, `-` for none; contact box
    /// [0, 0.15] × 0.03 at H; far spacing 0.05; `--mfvm=` for none)
    #[arg(long, value_name = "MID:H,…", value_delimiter = ',',
          default_values_t = ["-:0.01".to_string(), "-:0.005".to_string(),
                              "-:0.0025".to_string(), "0.0125:0.0025".to_string(),
                              "0.00625:0.0025".to_string()])]
    mfvm: Vec<String>,
}

fn main() {
    let cli: Cli = args::parse(&[]);
    let meshes = match cli.meshes.is_empty() {
        true => (0..3).map(mesh_file).collect(),
        false => cli.meshes.clone(),
    };
    let mut runs: Vec<(String, mlpg_contact::problem::Problem)> = Vec::new();
    for m in &meshes {
        let name = m.file_stem().map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        runs.push((format!("FE {name}"), spheres_fem(m)));
    }
    for set in cli.mfvm.iter().filter(|s| !s.is_empty()) {
        let (mid, h) = set.split_once(':').expect("MID:H");
        let mid = (mid != "-").then(|| mid.parse::<f64>().expect("MID"));
        let h: f64 = h.parse().expect("H");
        runs.push((format!("MFVM {set}"), spheres_mfvm(mid, h)));
    }
    println!(
        "{:<28} {:>13} {:>10} {:>10} {:>9} {:>9} {:>6} {:>7} {:>7}",
        "run", "F", "a fit", "p0 fit", "a err", "p0 err", "closed", "nodes", "time"
    );
    for (label, problem) in &runs {
        let start = Instant::now();
        let s = mlpg_contact::solve(problem).expect("solve");
        let time = start.elapsed().as_secs_f64();
        let m = measure(label, &s);
        let nodes = s.displacement.len() + s.second_body().map_or(0, |b| b.displacement.len());
        println!(
            "{label:<28} {:>13.6e} {:>10.6} {:>10.6} {:>+8.3}% {:>+8.3}% {:>6} {:>7} {:>6.2}s",
            m.force,
            m.radius,
            m.peak,
            100.0 * m.radius_error,
            100.0 * m.peak_error,
            m.closed,
            nodes,
            time
        );
    }
}
