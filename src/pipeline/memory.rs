//! The memory a run will need, estimated from the problem before anything large is allocated,
//! against the memory the process may use (available memory, the cgroup limit, the
//! address-space limit): a run that cannot fit is refused with the estimate and the parameter
//! to change, instead of aborting half-way.
//!
//! The model is the measured peak resident memory of a 4 × 1 MFVM strip clamped at one end
//! (paper's operator, `β = 0`, `α_s = 2`; `/usr/bin/time -f %M`): with faer's LU (below 10⁵
//! unknowns) 44, 75, 88 and 78 kB per node at 10k, 21k, 30k and 41k nodes; with the
//! static-pivoting LU (from 10⁵ unknowns) 41 kB at 56k and 36 kB at 120k nodes (29 kB on the
//! 250k-node cantilever, docs/dev/performance.md). The per-node cost is taken at the top of
//! each range and scaled with the support area `α_s²` (`α_s = 1.5` and `β = 1` measured
//! 17–20 kB at 100k–250k nodes). Contact adds the dense `M` and Lemke's tableau, about
//! `4 · 8 m²` bytes for `m` candidates, or, with the active-set solver, 1 GB and, but for
//! one body against rigid obstacles without friction, half the body's estimate again.
//!
//! With `discretisation.precision = "mixed"` the MFVM body's share is multiplied by
//! [`MIXED_FRACTION`] (single-precision factors and fronts; the matrix, its copies, shape
//! functions and cells stay double); `"auto"` is resolved by [`precision`] against the
//! estimate in double precision.
//!
//! The per-node constants come from `4 × 1` domains; on thin ones (a strip `L × W` with few
//! nodes across) the nested-dissection factors are far smaller per node and the estimate is
//! 1.5–2× too high (docs/dev/performance.md, "Contact at 10⁶ nodes through the CLI"). So an
//! MFVM body whose bounding box
//! is at least [`THIN_ASPECT`] times longer than wide is not refused on that estimate when
//! everything but its factors fits ([`defers_to_analysis`]): after assembly, the symbolic
//! analysis of `K` counts the factors exactly ([`after_analysis`]), and the run is refused
//! then if they do not fit in what is left.

use super::plan::{Plan, Shape};
use crate::contact::ContactSpec;
use crate::linear_solve::{FactorPrecision, FactorStats, STATIC_PIVOTING_MIN_DOFS};
use crate::problem::{Method, Precision, Problem};
use crate::system;

/// The MFVM body's memory with single-precision factors, as a fraction of that with
/// double-precision ones (docs/dev/performance.md, "10⁶ nodes").
pub const MIXED_FRACTION: f64 = 0.6;

/// Bytes per node of the paper's operator at `α_s = 2` with faer's LU (measured up to 88 kB).
const BYTES_PER_NODE_FAER: f64 = 90e3;
/// The same with the static-pivoting LU, from 10⁵ unknowns (measured up to 41 kB).
const BYTES_PER_NODE_STATIC: f64 = 42e3;
/// A floor for the process itself (binary, thread stacks, allocator).
const BASE_BYTES: f64 = 64e6;

/// Long side over short side of the bounding box from which an MFVM body's factors are
/// counted after assembly instead of refused on the per-node estimate (the per-node constants
/// were measured on `4 × 1` domains).
pub const THIN_ASPECT: f64 = 8.0;
/// Bytes per node of everything but the factors (nodes, supports, cells, shape functions at
/// nodes and face points, `K` and its interior blocks) at `α_s = 2`, scaled with `α_s²` like
/// the rest: 1.12 GB measured after assembly on the 255k-node strip `250 × 2.5` at
/// `α_s = 1.5` (4.4 kB per node, 7.8 kB at `α_s = 2`), with a margin.
const ASSEMBLY_BYTES_PER_NODE: f64 = 10e3;
/// Bytes of resident memory per stored factor entry, measured as the growth of the resident
/// set over the factorisation stage divided by the factor entries, on the strip `250 × 2.5`
/// (255k nodes, 236 M entries): 9.9 B in double precision (2.33 GB), 6.0 B with
/// single-precision factors (1.42 GB) — values, indices, supernode structure, fronts; with a
/// margin.
const FACTOR_ENTRY_BYTES_DOUBLE: f64 = 11.0;
/// The same with single-precision factors.
const FACTOR_ENTRY_BYTES_MIXED: f64 = 7.0;
/// Stored factor entries (`L` and `U`) per nonzero of the Cholesky factor of the symmetric
/// structure the static-pivoting LU uses (`FactorStats::bound_nnz`): 2.21 measured on the
/// strip (236.4 M entries for a bound of 106.8 M).
const FACTOR_ENTRIES_PER_BOUND: f64 = 2.25;
/// The update columns the active-set solver keeps at most (`lcp::active_set`'s own limit).
const COLUMN_BYTES: f64 = 1_073_741_824.0;

/// The estimated peak memory of solving `problem` (and its second body), in bytes, with the
/// node count it assumes.
pub fn estimate(problem: &Problem) -> (f64, f64) {
    estimate_in(problem, precision(problem))
}

/// The precision the factors of `problem`'s MFVM bodies will have: `"auto"` is mixed when
/// the estimate in double precision exceeds what the process may use ([`system::limit`]).
pub fn precision(problem: &Problem) -> FactorPrecision {
    match problem.discretisation.precision {
        Precision::Double => FactorPrecision::Double,
        Precision::Mixed => FactorPrecision::Mixed,
        Precision::Auto => match system::limit() {
            Some((available, _)) if estimate_in(problem, FactorPrecision::Double).0 > available => {
                FactorPrecision::Mixed
            }
            _ => FactorPrecision::Double,
        },
    }
}

/// [`estimate`] with the factors' precision given.
fn estimate_in(problem: &Problem, precision: FactorPrecision) -> (f64, f64) {
    let mixed = precision == FactorPrecision::Mixed;
    let body = |p: &Problem| {
        let h = p.node_spacing;
        let perimeter: f64 = p.domain.curves().iter().map(|c| c.length()).sum();
        let (lo, hi) = p.domain.bounding_box();
        let mut nodes =
            p.domain.area() / (h * h) + perimeter / h + p.refinement.added_nodes(h, lo, hi);
        let disc = &p.discretisation;
        let per_node = match disc.method {
            // Q2 elements of size h: about four times the nodes, a symmetric pattern of at
            // most 25 nodes per row.
            Method::Fem => {
                // A Gmsh body's own elements: its nodes as they are.
                nodes = p.mesh_nodes.as_ref().map_or(4.0 * nodes, |m| m.points.len() as f64);
                0.5 * BYTES_PER_NODE_FAER
            }
            Method::Mfvm => {
                let reach = (disc.mls.support_factor / 2.0).powi(2);
                let blend = if disc.beta > 0.0 { 0.7 } else { 1.0 };
                // Mixed precision always uses the static-pivoting LU.
                let lu = if mixed {
                    BYTES_PER_NODE_STATIC * MIXED_FRACTION
                } else if 2.0 * nodes >= STATIC_PIVOTING_MIN_DOFS as f64 {
                    BYTES_PER_NODE_STATIC
                } else {
                    BYTES_PER_NODE_FAER
                };
                lu * reach * blend
            }
        };
        (nodes * per_node, nodes)
    };
    let (mut bytes, mut nodes) = (0.0, 0.0);
    for p in problem.bodies() {
        let (b, n) = body(p);
        bytes += b;
        nodes += n;
    }
    if problem.is_scene_of_pairs() {
        // One dense M over the candidates of every pair, as for one pair below.
        let m: f64 = problem
            .pairs()
            .iter()
            .filter_map(|pair| {
                let p = problem.body(pair.body)?;
                Some(
                    p.domain.curve(pair.spec.edge).length() / p.refinement.finest(p.node_spacing)
                        + 1.0,
                )
            })
            .sum();
        bytes += 4.0 * 8.0 * m * m;
    }
    if let Some(spec) = problem.contact() {
        let Route { m, active_set, frictionless } = route(problem, spec);
        if active_set {
            // At most 1 GB of stored update columns (docs/method.md §5.1), and a second
            // factorisation (of the row-replaced matrix) but on one body against rigid
            // obstacles without friction: that system releases `K`'s factors before it
            // factorises (or never makes them) and keeps no copy of the row-replaced matrix,
            // so one factorisation is alive at a time (`after_analysis` counts the same;
            // 3.6 GB measured on the 210k-node strip whose estimate without contact is
            // 8.8 GB). A translation held by the contact (which keeps `K`'s factors) is not
            // known before assembly, as in `route`.
            let one_body = problem.body_count() == 1 && !problem.is_scene_of_pairs();
            let second = if frictionless && one_body { 0.0 } else { 0.5 };
            bytes += second * bytes + f64::from(1u32 << 30);
        } else {
            bytes += 4.0 * 8.0 * m * m;
        }
    }
    (bytes + BASE_BYTES, nodes)
}

/// How the contact of `problem` (one pair, `spec`) will be solved, as far as memory is
/// concerned.
struct Route {
    /// The candidates: a refined contact edge has more, so its finest spacing is taken (an
    /// upper bound when the refinement lies elsewhere).
    m: f64,
    /// No friction and no load steps.
    frictionless: bool,
    /// The active-set solver (no dense `M`), as `contact.solver` resolves for `m` candidates.
    active_set: bool,
}

fn route(problem: &Problem, spec: &ContactSpec) -> Route {
    let m = problem.domain.curve(spec.edge).length()
        / problem.refinement.finest(problem.node_spacing)
        + 1.0;
    let frictionless = spec.friction == 0.0 && problem.steps.is_empty();
    // A translation held by the contact is not known before assembly: a held body is counted
    // on the route of its problem without the hold.
    let shape = Shape::of(!frictionless, problem.body_count() > 1);
    let active_set = Plan::new(spec.solver, shape, m as usize).is_sparse();
    Route { m, frictionless, active_set }
}

/// Whether `problem`, whose estimate ([`estimate`]) exceeds what the process may use, is left
/// to the exact count after assembly ([`after_analysis`]) instead of refused: one MFVM body
/// (no second body, no several bodies) whose bounding box is at least [`THIN_ASPECT`] times
/// longer than wide (where the per-node estimate is known to be high), factorised by the
/// static-pivoting LU, and whose assembled data and update columns fit in `available`.
pub fn defers_to_analysis(problem: &Problem, available: f64) -> bool {
    if problem.discretisation.method != Method::Mfvm
        || problem.body_count() > 1
        || problem.is_scene_of_pairs()
    {
        return false;
    }
    let (lo, hi) = problem.domain.bounding_box();
    let (dx, dy) = (hi[0] - lo[0], hi[1] - lo[1]);
    if dx.max(dy) < THIN_ASPECT * dx.min(dy) {
        return false;
    }
    let (_, nodes) = estimate(problem);
    let static_lu = precision(problem) == FactorPrecision::Mixed
        || 2.0 * nodes >= STATIC_PIVOTING_MIN_DOFS as f64;
    let reach = (problem.discretisation.mls.support_factor / 2.0).powi(2);
    static_lu && nodes * ASSEMBLY_BYTES_PER_NODE * reach + COLUMN_BYTES + BASE_BYTES <= available
}

/// The bytes an assembled MFVM body of `unknowns` unknowns still needs when the symbolic
/// analysis of its `K` gave `stats` (static-pivoting LU): its factors (from the exact fill,
/// [`FactorStats::bound_nnz`]), the solve's work vectors (GMRES-IR's 40 with single-precision
/// factors), and for contact: Lemke's dense `M` and tableau, or the active-set solver's update
/// columns, plus a second factorisation unless `releases` (the frictionless active set
/// against a rigid obstacle releases `K`'s factors before it factorises its row-replaced
/// matrix, `contact::sparse::ModelFactors`).
pub fn after_analysis(
    problem: &Problem,
    stats: &FactorStats,
    unknowns: usize,
    precision: FactorPrecision,
    releases: bool,
) -> f64 {
    let per_entry = match precision {
        FactorPrecision::Double => FACTOR_ENTRY_BYTES_DOUBLE,
        FactorPrecision::Mixed => FACTOR_ENTRY_BYTES_MIXED,
    };
    let factors = stats.bound_nnz as f64 * FACTOR_ENTRIES_PER_BOUND * per_entry;
    let vectors = match precision {
        FactorPrecision::Double => 4.0,
        FactorPrecision::Mixed => 44.0,
    } * 8.0
        * unknowns as f64;
    let contact = match problem.contact() {
        None => 0.0,
        Some(spec) => {
            let Route { m, frictionless, active_set } = route(problem, spec);
            match (active_set, frictionless && releases) {
                (false, _) => 4.0 * 8.0 * m * m,
                (true, true) => COLUMN_BYTES,
                (true, false) => factors + COLUMN_BYTES,
            }
        }
    };
    factors + vectors + contact
}

/// Address space a solving thread maps besides the problem's own estimate, other than the
/// dense product kernels' workspace ([`system::kernel_workspace`]): its malloc arena (64 MiB
/// reserved by glibc for each thread that allocates) and its stack (8 MiB). Measured from Python:
/// each further thread solving the two-block problem at once raised `VmPeak` by ~140 MB
/// (555, 696 and 978 MB with 1, 2 and 4 threads), of which 64 MiB is the kernels' workspace
/// on that machine.
const THREAD_BYTES: f64 = 76e6;

/// The solves running now in this process (several threads, e.g. from Python): their
/// reserved bytes, and what the process could use when none ran.
struct Ledger {
    running: usize,
    reserved: f64,
    base: Option<(f64, &'static str)>,
}

static LEDGER: std::sync::Mutex<Ledger> =
    std::sync::Mutex::new(Ledger { running: 0, reserved: 0.0, base: None });

/// A solve admitted by [`admit`]: its reservation is returned when it is dropped.
#[derive(Debug)]
pub struct Admission {
    bytes: f64,
}

impl Drop for Admission {
    fn drop(&mut self) {
        let mut ledger = LEDGER.lock().unwrap_or_else(|e| e.into_inner());
        ledger.running -= 1;
        ledger.reserved -= self.bytes;
        if ledger.running == 0 {
            ledger.reserved = 0.0;
        }
    }
}

/// Admits one of several solves running at once in this process (the Python front end: one
/// thread per solve, the GIL released): each reserves its estimate ([`estimate`]), the dense
/// kernels' workspace of its thread ([`system::kernel_workspace`]) and the thread's arena and
/// stack.
/// The first solve is refused only when it and the thread pool's workspace cannot fit
/// together (the run's own check then refuses what does not fit, as on the command line); a
/// solve that starts while others run is refused when the
/// reservations together exceed what the process could use when none ran ([`system::limit`], read
/// then, less the thread pool's workspace), with the limit named — where it used to run out
/// of address space in the middle and abort the interpreter.
pub fn admit(problem: &Problem) -> Result<Admission, crate::Error> {
    let (need, nodes) = estimate(problem);
    let bytes = need + system::kernel_workspace() + THREAD_BYTES;
    let mut ledger = LEDGER.lock().unwrap_or_else(|e| e.into_inner());
    if ledger.running == 0 {
        // The worker threads' workspace, once they have multiplied, is mapped already; before,
        // it is still to come: counted either way.
        let pool =
            rayon::current_num_threads() as f64 * (system::kernel_workspace() + THREAD_BYTES);
        ledger.base = system::limit().map(|(available, what)| (available - pool, what));
        // The first solve too, when its own thread and the pool's cannot map their kernels'
        // workspace: that allocation has no fallible path (600 MiB a thread on a machine with
        // a 300 MiB last-level cache, where a solve under `ulimit -v` aborted the process).
        if let Some((available, what)) = ledger.base
            && bytes > available
        {
            return Err(crate::Error::Memory {
                estimate: bytes,
                nodes,
                available: available.max(0.0),
                limit: what,
                precision_hint: "",
            });
        }
    } else if let Some((available, what)) = ledger.base {
        let left = available - ledger.reserved;
        if bytes > left {
            return Err(crate::Error::Memory {
                estimate: bytes,
                nodes,
                available: left.max(0.0),
                limit: concurrent(what),
                precision_hint: ", or solve fewer problems at once",
            });
        }
    }
    ledger.running += 1;
    ledger.reserved += bytes;
    Ok(Admission { bytes })
}

/// `what` ([`system::limit`]'s name of a limit) with the solves running beside.
fn concurrent(what: &'static str) -> &'static str {
    match what {
        "available memory" => "available memory, with the other solves running in this process,",
        "the cgroup's memory limit" => {
            "the cgroup's memory limit, with the other solves running in this process,"
        }
        _ => {
            "the address-space limit (ulimit -v), with the other solves running in this process \
             (each thread's dense-kernel workspace counted),"
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A clamped strip `length × width` at spacing `h` under its own load, on a rigid floor
    /// (frictionless, `"auto"` solver), `α_s = 1.5`, double precision.
    fn strip(length: f64, width: f64, h: f64) -> Problem {
        Problem::from_toml(&format!(
            r#"
            [geometry]
            kind = "rectangle"
            x = [0.0, {length:?}]
            y = [0.0, {width:?}]
            [nodes]
            spacing = {h:?}
            [material]
            young = 30000.0
            poisson = 0.3
            plane = "stress"
            [discretisation]
            support_factor = 1.5
            precision = "double"
            [[boundary]]
            edge = "left"
            displacement = {{ x = 0.0, y = 0.0 }}
            [[boundary]]
            edge = "top"
            traction = {{ y = -1.0 }}
            [contact]
            edge = "bottom"
            obstacle_point = [0.0, -0.01]
            obstacle_normal = [0.0, 1.0]
            "#
        ))
        .unwrap()
    }

    #[test]
    fn thin_bodies_defer_to_the_analysis_when_their_assembly_fits() {
        // The 10⁶-node strip 1000 × 2.5: the per-node estimate (double precision) is far
        // above 20 GB, everything but the factors (~5.7 GB at 10 kB × (1.5/2)² per node) and
        // the update columns fit in 20 GB, not in 5 GB.
        let thin = strip(1000.0, 2.5, 0.05);
        let (estimate, nodes) = estimate_in(&thin, FactorPrecision::Double);
        assert!((1.0e6..1.1e6).contains(&nodes), "{nodes}");
        assert!(estimate > 25e9, "{estimate:e}");
        assert!(defers_to_analysis(&thin, 20e9));
        assert!(!defers_to_analysis(&thin, 5e9));
        // A 4 × 1 body (the calibration's shape, aspect below THIN_ASPECT) is refused on the
        // estimate whatever is available.
        let square = strip(400.0, 100.0, 0.1);
        assert!(!defers_to_analysis(&square, 1e15));
    }

    #[test]
    fn released_factors_are_counted_once() {
        // 10⁸ bound entries: 2.25 · 10⁸ factor entries of 11 B in double precision.
        let stats = FactorStats { bound_nnz: 100_000_000, ..FactorStats::default() };
        let thin = strip(1000.0, 2.5, 0.05);
        let n = 2_000_000;
        let released = after_analysis(&thin, &stats, n, FactorPrecision::Double, true);
        let kept = after_analysis(&thin, &stats, n, FactorPrecision::Double, false);
        let factors = 2.25e8 * 11.0;
        assert!((kept - released - factors).abs() < 1.0, "{kept:e} {released:e}");
        assert!((released - factors - 4.0 * 8.0 * n as f64 - COLUMN_BYTES).abs() < 1.0);
        let mixed = after_analysis(&thin, &stats, n, FactorPrecision::Mixed, true);
        assert!(mixed < released, "single-precision factors need less: {mixed:e}");
    }
}
