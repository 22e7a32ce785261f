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
//! `4 · 8 m²` bytes for `m` candidates, or, with the active-set solver, half the body's
//! estimate again and 1 GB.
//!
//! With `discretisation.precision = "mixed"` the MFVM body's share is multiplied by
//! [`MIXED_FRACTION`] (single-precision factors and fronts; the matrix, its copies, shape
//! functions and cells stay double); `"auto"` is resolved by [`precision`] against the
//! estimate in double precision.

use crate::linear_solve::{FactorPrecision, STATIC_PIVOTING_MIN_DOFS};
use crate::problem::{Method, Precision, Problem};

/// The MFVM body's memory with single-precision factors, as a fraction of that with
/// double-precision ones (docs/dev/performance.md, "10⁶ nodes").
pub const MIXED_FRACTION: f64 = 0.6;

/// Bytes per node of the paper's operator at `α_s = 2` with faer's LU (measured up to 88 kB).
const BYTES_PER_NODE_FAER: f64 = 90e3;
/// The same with the static-pivoting LU, from 10⁵ unknowns (measured up to 41 kB).
const BYTES_PER_NODE_STATIC: f64 = 42e3;
/// A floor for the process itself (binary, thread stacks, allocator).
const BASE_BYTES: f64 = 64e6;

/// The estimated peak memory of solving `problem` (and its second body), in bytes, with the
/// node count it assumes.
pub fn estimate(problem: &Problem) -> (f64, f64) {
    estimate_in(problem, precision(problem))
}

/// The precision the factors of `problem`'s MFVM bodies will have: `"auto"` is mixed when
/// the estimate in double precision exceeds what the process may use ([`limit`]).
pub fn precision(problem: &Problem) -> FactorPrecision {
    match problem.discretisation.precision {
        Precision::Double => FactorPrecision::Double,
        Precision::Mixed => FactorPrecision::Mixed,
        Precision::Auto => match limit() {
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
    let (mut bytes, mut nodes) = body(problem);
    if let Some(second) = &problem.second_body {
        let (b, n) = body(second);
        bytes += b;
        nodes += n;
    }
    if let Some(several) = &problem.multibody {
        for p in &several.bodies {
            let (b, n) = body(p);
            bytes += b;
            nodes += n;
        }
        // One dense M over the candidates of every pair, as for one pair below.
        let m: f64 = several
            .pairs
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
    if let Some(spec) = &problem.contact {
        // A refined contact edge has more candidates: its finest spacing is taken (an upper
        // bound when the refinement lies elsewhere).
        let m = problem.domain.curve(spec.edge).length()
            / problem.refinement.finest(problem.node_spacing)
            + 1.0;
        let frictionless = spec.friction == 0.0 && problem.steps.is_empty();
        let active_set = if frictionless {
            spec.solver.is_active_set(m as usize)
        } else {
            match problem.second_body {
                None => spec.solver.is_active_set_frictional(m as usize),
                Some(_) => spec.solver.is_active_set_frictional_pair(m as usize),
            }
        };
        if active_set {
            // A second factorisation (of the row-replaced matrix) and at most 1 GB of stored
            // update columns (docs/method.md §5.1): 6.9 GB measured on the 210k-node strip
            // whose estimate without contact is 8.8 GB.
            bytes += 0.5 * bytes + f64::from(1u32 << 30);
        } else {
            bytes += 4.0 * 8.0 * m * m;
        }
    }
    (bytes + BASE_BYTES, nodes)
}

/// What this process may use, in bytes, and what limits it; `None` where nothing can be read
/// (not Linux). The address-space limit counts virtual memory (thread stacks, allocator
/// arenas) too, so 0.5 GB of it is kept for those.
pub fn limit() -> Option<(f64, &'static str)> {
    let mut limits: Vec<(f64, &'static str)> = Vec::new();
    if let Some(kb) = read_field("/proc/meminfo", "MemAvailable:") {
        limits.push((kb * 1024.0, "available memory"));
    }
    if let Ok(text) = std::fs::read_to_string("/sys/fs/cgroup/memory.max") {
        if let Ok(max) = text.trim().parse::<f64>() {
            let used = std::fs::read_to_string("/sys/fs/cgroup/memory.current")
                .ok()
                .and_then(|t| t.trim().parse::<f64>().ok())
                .unwrap_or(0.0);
            limits.push((max - used, "the cgroup's memory limit"));
        }
    }
    if let Ok(text) = std::fs::read_to_string("/proc/self/limits") {
        let soft = text
            .lines()
            .find(|l| l.starts_with("Max address space"))
            .and_then(|l| l.split_whitespace().nth(3))
            .and_then(|v| v.parse::<f64>().ok());
        if let Some(bytes) = soft {
            limits.push((bytes - 0.5e9, "the address-space limit (ulimit -v)"));
        }
    }
    limits.into_iter().min_by(|a, b| a.0.total_cmp(&b.0))
}

/// The number after `key` in a `key value unit` file such as /proc/meminfo.
fn read_field(path: &str, key: &str) -> Option<f64> {
    let text = std::fs::read_to_string(path).ok()?;
    text.lines().find(|l| l.starts_with(key))?.split_whitespace().nth(1)?.parse().ok()
}
