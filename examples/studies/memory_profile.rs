//! Where the memory of one run goes: solves a problem file as the CLI does (discretise, then
//! solve with its contact) while a thread samples the resident set size (`VmRSS` of
//! `/proc/self/status`) every 20 ms, and prints per stage the RSS at its start and end and the
//! largest sample inside it, then the sizes of the model's parts computed from their lengths
//! (the system matrix, the interior stiffness blocks, the shape functions at nodes and face
//! points, the factors of `K`). Nothing is asserted; one problem per process, so that the
//! peak is this run's.
//!
//! ```text
//! cargo run --release --features studies --example memory_profile -- problems/large/strip_million.toml
//! ```

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use mlpg_contact::pipeline::memory;
use mlpg_contact::problem::Problem;
use mlpg_contact::{Progress, discretise, solve_model};

/// `VmRSS` (or another `/proc/self/status` field) in bytes.
fn status_bytes(field: &str) -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with(field))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        })
        .map_or(0, |kb| kb * 1024)
}

fn gb(bytes: f64) -> String {
    format!("{:.2}", bytes / 1e9)
}

/// The sampler's running maximum since the last reset.
struct Sampler {
    max: Arc<AtomicU64>,
}

impl Sampler {
    /// The maximum since the last call, and a reset to the current RSS.
    fn take(&self) -> u64 {
        self.max.swap(status_bytes("VmRSS:"), Ordering::Relaxed).max(status_bytes("VmRSS:"))
    }
}

/// A [`Progress`] that prints each stage's RSS at its start and end and its sampled peak.
struct Recorder {
    sampler: Sampler,
    rows: Arc<Mutex<Vec<String>>>,
    at_start: u64,
}

impl Progress for Recorder {
    fn section(&mut self, label: &str) {
        self.rows.lock().expect("rows").push(format!("| {label} | | | | |"));
    }
    fn start(&mut self, _stage: &'static str) {
        self.sampler.take();
        self.at_start = status_bytes("VmRSS:");
    }
    fn finish(&mut self, stage: &'static str, seconds: f64) {
        let peak = self.sampler.take();
        let end = status_bytes("VmRSS:");
        self.rows.lock().expect("rows").push(format!(
            "| {stage} | {seconds:.2} | {} | {} | {} |",
            gb(self.at_start as f64),
            gb(peak as f64),
            gb(end as f64)
        ));
    }
}

fn main() {
    let path = std::env::args().nth(1).expect("usage: memory_profile <problem.toml>");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let problem = Problem::from_toml(&text).unwrap_or_else(|e| panic!("{e}"));

    let max = Arc::new(AtomicU64::new(0));
    let stop = Arc::new(AtomicBool::new(false));
    let sampler_thread = {
        let (max, stop) = (Arc::clone(&max), Arc::clone(&stop));
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                max.fetch_max(status_bytes("VmRSS:"), Ordering::Relaxed);
                std::thread::sleep(Duration::from_millis(20));
            }
        })
    };
    let rows = Arc::new(Mutex::new(Vec::new()));
    let mut recorder = Recorder {
        sampler: Sampler { max: Arc::clone(&max) },
        rows: Arc::clone(&rows),
        at_start: 0,
    };
    let model = discretise(&problem, &mut recorder).unwrap_or_else(|e| panic!("{e}"));

    // The parts of the model, from their lengths.
    let sys = &model.system;
    let matrix = sys.matrix.values.len() as f64 * 16.0 + sys.matrix.col_ptr.len() as f64 * 8.0;
    let blocks = sys.interior_stiffness.cols.len() as f64 * (4.0 + 32.0);
    // Per entry: a node index (4 B), `φ` (8 B) and, when kept, two gradients (16 B).
    let shapes = |s: &mlpg_contact::mls::ShapeSet| {
        s.nnz() as f64 * if s.has_gradients() { 28.0 } else { 12.0 }
    };
    let node_shapes = shapes(&model.node_shapes);
    let (face_shapes, cells) = model.mfvm().map_or((0.0, 0.0), |m| {
        let cells: usize = m.cells.iter().map(|c| c.vertices.len() * 24 + 48).sum();
        (shapes(&m.face_shapes), cells as f64)
    });
    let st = model.factorisation.stats();
    let factor_bytes = match st.precision {
        mlpg_contact::linear_solve::FactorPrecision::Mixed => 4.0,
        mlpg_contact::linear_solve::FactorPrecision::Double => 8.0,
    };
    let k_nnz = sys.matrix.values.len();
    let n = sys.matrix.n;
    let predicted = (
        memory::after_analysis(&problem, &st, n, st.precision, true),
        memory::after_analysis(&problem, &st, n, st.precision, false),
    );
    let after_discretise = status_bytes("VmRSS:");
    let (_, _, solution) =
        solve_model(&problem, model, None, &mut recorder).unwrap_or_else(|e| panic!("{e}"));
    stop.store(true, Ordering::Relaxed);
    sampler_thread.join().expect("sampler");

    println!("{path}: {} nodes", solution.displacement.len());
    println!("| stage | s | RSS at start GB | peak GB | RSS at end GB |");
    println!("|---|---|---|---|---|");
    for row in rows.lock().expect("rows").iter() {
        println!("{row}");
    }
    println!();
    println!("| part | GB |");
    println!("|---|---|");
    println!("| system matrix K (CSC, {} entries) | {} |", k_nnz, gb(matrix));
    println!("| interior stiffness blocks | {} |", gb(blocks));
    println!("| shape functions at nodes | {} |", gb(node_shapes));
    println!("| shape functions at face points | {} |", gb(face_shapes));
    println!("| cells (vertices) | {} |", gb(cells));
    println!(
        "| factors of K ({} entries × {} B, values only) | {} |",
        st.factor_nnz,
        factor_bytes,
        gb(st.factor_nnz as f64 * factor_bytes)
    );
    println!("| RSS after discretise | {} |", gb(after_discretise as f64));
    println!(
        "| bound_nnz {} (factor entries / bound {:.3}); after_analysis predicts {} beyond the RSS after assembly (with release), {} (without) |",
        st.bound_nnz,
        st.factor_nnz as f64 / st.bound_nnz as f64,
        gb(predicted.0),
        gb(predicted.1)
    );
    println!("| peak (VmHWM) | {} |", gb(status_bytes("VmHWM:") as f64));
    if let Some(a) = solution.contact().and_then(|c| c.active_set.as_ref()) {
        println!(
            "active set: {} iterations, {} factorisations ({:.1} s), {} update columns ({:.1} s)",
            a.iterations,
            a.work.factorisations,
            a.work.factorisation_seconds,
            a.work.update_columns,
            a.work.update_seconds
        );
    }
}
