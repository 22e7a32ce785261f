//! Stage 7: sparse LU factorisation of `K` (faer's supernodal LU), kept for many solves.
//!
//! # How
//!
//! `P K Q = L U` with partial pivoting (rows, `P`) and a fill-reducing column ordering `Q`
//! chosen here, through faer's low-level supernodal API (`qr::col_etree`, `qr::postorder`,
//! `qr::column_counts_ata`, `lu::supernodal::factorize_supernodal_*`).
//!
//! - **Ordering.** With node coordinates ([`Factorisation::with_node_coordinates`], what
//!   [`crate::discretise`] uses) the columns are ordered geometrically, a node's two DOFs
//!   together, and two candidates are compared by the fill bound below:
//!   1. *nested dissection*: recursive median bisection of the nodes across the longer side
//!      of their bounding box, the separator being a strip of width [`separator_width`]
//!      around the median, ordered after both halves. A partial-pivoting LU takes its fill
//!      bound from the structure of `KᵀK` (any row may become a pivot row), so the separator
//!      must split the graph of `KᵀK`, whose reach is twice `K`'s: the strip width is twice
//!      the largest coordinate distance between coupled nodes, measured on `K` itself (3 h at
//!      α_s = 2, so 6 h; a sparser operator gets a thinner strip). Boxes thinner than two
//!      strip widths are ordered along their long side.
//!   2. a *banded* order of all nodes along the domain's long side.
//!
//!   The bound is the flop count of the Cholesky factor of `QᵀKᵀKQ` (faer's column counts,
//!   ~0.3 s at 100k nodes); the banded order is kept only if its bound is below 0.8 × that
//!   of nested dissection, which needs less memory at equal flops. With this operator the
//!   banded order wins on beams, strips and the 48 × 12 cantilever up to ~50k nodes, nested
//!   dissection beyond (peak 6.5 GB instead of 11.8 GB at 100k). Either costs milliseconds
//!   where COLAMD on `K` took 36 s at 100k nodes (docs/dev/performance.md).
//!   Without coordinates ([`Factorisation::new`]) COLAMD orders the columns.
//! - **Void entries.** Entries with `|K_ij| ≤ 1e-14 max|K|` (round-off left by cancellation in
//!   `−Q D S`, ~14 % of them at α_s = 2) are dropped from the matrix that is factorised: they
//!   change `K` by less than the LU's own backward error but cost work. The diagonal is
//!   always kept. Residuals are computed against the full `K` ([`mul`]).
//! - **Parallelism and determinism.** The numeric factorisation runs with `Par::rayon(2)`,
//!   a *fixed* split into two tasks whatever the size of the rayon pool: the arithmetic (and
//!   so every output bit) does not depend on `RAYON_NUM_THREADS`, while two cores are used
//!   when available. Following the pool size (`Par::rayon(0)`) would make the last bits
//!   depend on the thread count. Solves run sequentially (the contact condensation runs
//!   many of them in parallel).
//!
//! A structurally singular `K` gives [`SolveError::Singular`] at factorisation; a numerically
//! singular one gives a non-finite solution, reported as [`SolveError::Singular`] by
//! [`Factorisation::solve`]. Nothing here panics on a singular matrix.

mod replaced;
mod rows;
mod symmetric;

pub use replaced::ReplacedRows;
pub use rows::RowProduct;
pub use symmetric::{ACCEPTED_BACKWARD_ERROR, MAX_REFINEMENT_STEPS};

use crate::assembly::SystemMatrix;
use crate::geometry::Point;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::lu::supernodal::{
    self, SupernodalLu, SymbolicSupernodalLu, factorize_supernodal_numeric_lu,
    factorize_supernodal_symbolic_lu,
};
use faer::sparse::linalg::{LuError, SymbolicSupernodalParams, colamd, qr};
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};

/// Failures of the linear solve.
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    /// The matrix is structurally or numerically singular.
    #[error(
        "the system matrix is singular ({detail}); is the body held by enough displacement conditions?"
    )]
    Singular {
        /// What was detected.
        detail: String,
    },
    /// The single-precision factors with refinement and GMRES-IR did not reach the accepted
    /// backward error ([`FactorPrecision::Mixed`]).
    #[error(
        "the mixed-precision solve did not converge ({detail}); use solver.precision = \"double\""
    )]
    NotConverged {
        /// What was reached.
        detail: String,
    },
    /// faer failed for another reason (e.g. memory).
    #[error("sparse LU failed: {0}")]
    Backend(String),
    /// The factors were released ([`Factorisation::release`]) to make room for another
    /// factorisation; only the statistics remain.
    #[error(
        "the factors of this matrix were released after use (the active-set solver keeps only its own row-replaced factors)"
    )]
    Released,
}

/// Which LU [`Factorisation`] computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum FactorMethod {
    /// [`Self::StaticPivoting`] for systems of at least [`STATIC_PIVOTING_MIN_DOFS`] unknowns
    /// with a geometric ordering, [`Self::PartialPivoting`] otherwise. Measured (docs/dev/performance.md,
    /// docs/dev/performance.md): the static-pivoting LU factorises 1.5–2× faster in half the
    /// memory, but its solves (with the residual check) are slower, which costs more than
    /// it saves in the contact condensation of the beam and the 84k-DOF strip.
    #[default]
    Auto,
    /// faer's supernodal LU with partial pivoting (static structure of `KᵀK`).
    PartialPivoting,
    /// Multifrontal LU with the static structure of `K + Kᵀ`, pivoting only inside each
    /// supernode's diagonal block (tiny pivots perturbed), and iterative refinement against
    /// `K` in every solve (`symmetric.rs`). Needs a nested-dissection ordering or a
    /// permutation; with [`ColumnOrdering::Colamd`] the partial-pivoting LU is used.
    StaticPivoting,
}

/// Precision of the stored factors of [`FactorMethod::StaticPivoting`] (the partial-pivoting
/// LU is always double precision).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum FactorPrecision {
    /// Factors in `f64` (the default).
    #[default]
    Double,
    /// Factors in `f32` (half the memory, ~1.5× faster numeric factorisation measured) and iterative
    /// refinement with `f64` residuals against `K` to the same backward error as
    /// [`Self::Double`]; a column whose refinement stalls (at 250k nodes on the cantilever,
    /// κ · ε_f32 ≳ 1) is finished by GMRES-IR (`f64` GMRES preconditioned by the `f32`
    /// factors), and rejected ([`SolveError::NotConverged`]) if even that does not reach
    /// [`ACCEPTED_BACKWARD_ERROR`]. Not the default: it factorises 1.4× faster at 100k nodes
    /// but needs ~8 refinement steps per solve (docs/dev/performance.md); it is the way to
    /// fit a problem whose double-precision factors do not fit in memory.
    Mixed,
}

/// Tuning knobs of [`Factorisation::with_options`]; [`Default`] is what the solver uses.
#[derive(Clone, Debug)]
pub struct FactorOptions {
    /// The factorisation. Default [`FactorMethod::Auto`].
    pub method: FactorMethod,
    /// [`FactorMethod::StaticPivoting`]: pivots of magnitude below this (in the equilibrated
    /// matrix, whose largest entry per row and column is ~1) are replaced by ±this value.
    /// Default `√ε ≈ 1.5e-8` (at least `√ε_f32 ≈ 3.5e-4` for single-precision factors).
    pub pivot_tolerance: f64,
    /// Precision of the static-pivoting factors. Default [`FactorPrecision::Double`].
    pub precision: FactorPrecision,
    /// [`FactorPrecision::Mixed`]: GMRES iterations per column at most in GMRES-IR (each one
    /// substitution with the factors and one product with `K`). Default 200.
    pub gmres_max_iterations: usize,
    /// Entries with `|K_ij| ≤ void_tolerance · max|K|` are left out of the factorised matrix
    /// (`0` keeps every entry). Default `1e-14`.
    pub void_tolerance: f64,
    /// Tasks of the numeric factorisation (`Par::rayon(tasks)`, `1` = sequential). Fixed,
    /// not the pool size, so that results do not depend on the machine. Default 2.
    pub tasks: usize,
    /// Nested dissection stops splitting boxes of at most this many nodes. Default 64.
    pub leaf_nodes: usize,
    /// Multiplies [`separator_width`]. Default 1.
    pub separator_scale: f64,
    /// Nested dissection does not cut a box whose short side is below `thin` separator
    /// widths; its nodes are ordered along the long side instead (a banded order, cheaper
    /// for thin boxes, where wide separators cost more than they save). One ordering is
    /// built per value; a later one replaces an earlier one only when its fill bound
    /// (`bound_flops`) is below 0.8 times the earlier one's. Default `[2, ∞]`: nested
    /// dissection, or a banded order of the whole domain (thin beams and strips).
    pub thin_boxes: Vec<f64>,
    /// [`FactorMethod::StaticPivoting`] with node coordinates: also build the approximate
    /// minimum degree order of the node graph (faer's AMD) as the last candidate, kept under
    /// the same rule (its fill bound below 0.8 times the kept one's). Default `false`; the
    /// graded node sets of the adaptive loop take it (docs/dev/time_to_accuracy.md).
    pub amd: bool,
    /// [`FactorMethod::StaticPivoting`] with node coordinates: also build the
    /// [`split_band`] order and take it when its fill bound stays within
    /// [`SPLIT_BAND_ALLOWANCE`] of the kept order's (its two independent halves go on two
    /// tasks in the factorisation and in every substitution). Default `false`: it pays where
    /// one column after another is solved with the same factors (the time steps' `M̂`,
    /// 1.7× faster per run), not in the contact paths, whose blocks of columns already
    /// occupy both cores (the adaptive beam and the 10⁶-node strip measured no gain;
    /// docs/dev/performance.md, "Two-core substitution").
    pub split_band: bool,
}

impl FactorOptions {
    /// Static pivoting with nested dissection only (no banded candidate): the elimination
    /// tree then has short leaf-to-root paths, which [`Factorisation::sparse_products`]
    /// needs to pay (a banded order's tree is one path).
    pub fn nested_dissection_static() -> Self {
        Self { method: FactorMethod::StaticPivoting, thin_boxes: vec![2.0], ..Self::default() }
    }
}

/// [`FactorMethod::Auto`] uses static pivoting from this many unknowns on.
pub const STATIC_PIVOTING_MIN_DOFS: usize = 100_000;

/// A later ordering candidate must bound the flops below this fraction of the kept one's.
const PREFER_FIRST: f64 = 0.8;

/// The [`split_band`] order replaces the kept one when its fill bound (entries and flops)
/// is at most this multiple of the kept one's: its two halves halve the substitution's
/// time on two cores (docs/dev/performance.md, "Two-core substitution").
pub const SPLIT_BAND_ALLOWANCE: f64 = 1.1;

impl Default for FactorOptions {
    fn default() -> Self {
        Self {
            method: FactorMethod::Auto,
            pivot_tolerance: f64::EPSILON.sqrt(),
            precision: FactorPrecision::Double,
            gmres_max_iterations: 200,
            void_tolerance: 1e-14,
            tasks: 2,
            leaf_nodes: 64,
            separator_scale: 1.0,
            thin_boxes: vec![2.0, f64::INFINITY],
            amd: false,
            split_band: false,
        }
    }
}

/// How the columns of `K` are ordered before the LU.
#[derive(Clone, Copy, Debug)]
pub enum ColumnOrdering<'a> {
    /// Geometric nested dissection; `points[i]` is the node of DOFs `2i` and `2i + 1`.
    NestedDissection(&'a [Point]),
    /// COLAMD on the pattern of `K` (no geometry needed).
    Colamd,
    /// A precomputed column order (`perm[k]` = the column eliminated `k`-th).
    Permutation(&'a [usize]),
}

/// Statistics of a factorisation (for benchmarks and reports).
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct FactorStats {
    /// Nonzeros of `K` as assembled.
    pub nnz: usize,
    /// Nonzeros factorised (after dropping void entries).
    pub nnz_factorised: usize,
    /// Number of supernodes.
    pub supernodes: usize,
    /// Nonzeros of the Cholesky factor of `QᵀKᵀKQ`: the bound on the nonzeros of each of
    /// `L` and `U` that partial pivoting respects (a timing-free measure of an ordering).
    pub bound_nnz: usize,
    /// `Σ_j c_j²` over the column counts `c_j` of that factor: proportional to the flops of
    /// the bounding factorisation.
    pub bound_flops: f64,
    /// Seconds spent ordering the columns.
    pub ordering_seconds: f64,
    /// Seconds of the symbolic analysis.
    pub symbolic_seconds: f64,
    /// Seconds of the numeric factorisation.
    pub numeric_seconds: f64,
    /// The factorisation used.
    pub method: FactorMethod,
    /// Nonzeros stored in `L` and `U` ([`FactorMethod::StaticPivoting`] only; 0 otherwise).
    pub factor_nnz: usize,
    /// Pivots replaced by `±pivot_tolerance` ([`FactorMethod::StaticPivoting`]).
    pub perturbed_pivots: usize,
    /// Right-hand-side columns solved so far ([`FactorMethod::StaticPivoting`]).
    pub columns_solved: usize,
    /// Refinement corrections applied so far, summed over columns.
    pub refinement_steps: usize,
    /// Largest normwise backward error `‖K x − b‖∞ / (‖K‖∞ ‖x‖∞ + ‖b‖∞)` of a returned
    /// solution so far (columns above [`ACCEPTED_BACKWARD_ERROR`] are returned as
    /// NaN and count as infinity here).
    pub worst_backward_error: f64,
    /// Precision of the stored factors ([`FactorPrecision::Double`] or
    /// [`FactorPrecision::Mixed`]).
    pub precision: FactorPrecision,
    /// Columns that single-precision refinement could not finish and that GMRES-IR finished
    /// or rejected ([`FactorPrecision::Mixed`]).
    pub gmres_columns: usize,
    /// GMRES iterations over those columns (each one substitution with the factors and one
    /// product with `K`).
    pub gmres_iterations: usize,
}

/// The result of [`Factorisation::sparse_products`].
#[derive(Clone, Debug)]
pub struct SparseProducts {
    /// `G K⁻¹ E`, row-major.
    pub values: Vec<f64>,
    /// Estimated flops of the reach-restricted route that computed it.
    pub sparse_flops: f64,
    /// Estimated flops of the same product by full forward and backward substitutions.
    pub full_flops: f64,
}

/// A sparse LU factorisation `P K Q = L U` of the system matrix.
pub struct Factorisation {
    inner: Inner,
    n: usize,
    stats: FactorStats,
    /// The options it was made with (a related matrix is factorised alike).
    options: FactorOptions,
}

/// The factors of either method.
enum Inner {
    Partial {
        lu: SupernodalLu<usize, f64>,
        row_perm: Vec<usize>,
        row_perm_inv: Vec<usize>,
        col_perm: Vec<usize>,
        col_perm_inv: Vec<usize>,
    },
    Static(symmetric::StaticLu),
    /// Released ([`Factorisation::release`]): no factors, the statistics as they were.
    Released,
}

impl std::fmt::Debug for Factorisation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Factorisation {{ n: {}, {:?} }}", self.n, self.stats)
    }
}

fn backend(e: impl std::fmt::Debug) -> SolveError {
    SolveError::Backend(format!("{e:?}"))
}

fn buffer(req: StackReq) -> Result<MemBuffer, SolveError> {
    MemBuffer::try_new(req).map_err(backend)
}

/// `matrix` without its void entries (`|v| ≤ tolerance · max|v|`, diagonal kept).
fn without_void_entries(matrix: &SystemMatrix, tolerance: f64) -> SystemMatrix {
    let max = matrix.values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let tol = tolerance * max;
    let mut out = SystemMatrix {
        n: matrix.n,
        col_ptr: Vec::with_capacity(matrix.n + 1),
        row_idx: Vec::with_capacity(matrix.row_idx.len()),
        values: Vec::with_capacity(matrix.values.len()),
    };
    out.col_ptr.push(0);
    for c in 0..matrix.n {
        for k in matrix.col_ptr[c]..matrix.col_ptr[c + 1] {
            let (r, v) = (matrix.row_idx[k], matrix.values[k]);
            if v.abs() > tol || r == c {
                out.row_idx.push(r);
                out.values.push(v);
            }
        }
        out.col_ptr.push(out.row_idx.len());
    }
    out
}

/// Width of the nested-dissection separator strip across each axis: twice the largest
/// distance along that axis between the nodes of a nonzero of `matrix` (the reach of
/// `KᵀK`), so that no column left of the strip shares a row with a column right of it.
pub fn separator_width(matrix: &SystemMatrix, points: &[Point]) -> [f64; 2] {
    let mut reach = [0.0f64; 2];
    for c in 0..matrix.n {
        let pc = points[c / 2];
        for &r in &matrix.row_idx[matrix.col_ptr[c]..matrix.col_ptr[c + 1]] {
            let pr = points[r / 2];
            reach[0] = reach[0].max((pr[0] - pc[0]).abs());
            reach[1] = reach[1].max((pr[1] - pc[1]).abs());
        }
    }
    [2.0 * reach[0], 2.0 * reach[1]]
}

/// Geometric nested dissection of `points`: returns the DOF order (node `i` gives DOFs `2i`,
/// `2i + 1`, kept adjacent). Each box of nodes is cut across its longer side at the median;
/// nodes within `width[axis] / 2` of the median form the separator, ordered after both
/// halves. Boxes of at most `leaf` nodes, or whose separator would swallow a half, are not
/// cut further.
pub fn nested_dissection(
    points: &[Point],
    width: [f64; 2],
    leaf: usize,
    thin_box: f64,
) -> Vec<usize> {
    let mut ids: Vec<u32> = (0..points.len() as u32).collect();
    let mut order = Vec::with_capacity(points.len());
    // Recursion depth is about log2(N / leaf).
    /// Sorts `ids` along `axis`, then the other axis (a banded order within a box).
    fn sort_along(ids: &mut [u32], pts: &[Point], axis: usize) {
        ids.sort_unstable_by(|a, b| {
            let (p, q) = (pts[*a as usize], pts[*b as usize]);
            p[axis].total_cmp(&q[axis]).then(p[1 - axis].total_cmp(&q[1 - axis])).then(a.cmp(b))
        });
    }
    fn dissect(ids: &mut [u32], pts: &[Point], w: [f64; 2], cut: (usize, f64), out: &mut Vec<u32>) {
        let (leaf, thin_box) = cut;
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &i in ids.iter() {
            let p = pts[i as usize];
            for d in 0..2 {
                lo[d] = lo[d].min(p[d]);
                hi[d] = hi[d].max(p[d]);
            }
        }
        let ax = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
        if ids.len() <= leaf || hi[1 - ax] - lo[1 - ax] < thin_box * w[ax] {
            sort_along(ids, pts, ax);
            out.extend_from_slice(ids);
            return;
        }
        let mid = ids.len() / 2;
        ids.select_nth_unstable_by(mid, |a, b| {
            pts[*a as usize][ax].total_cmp(&pts[*b as usize][ax]).then(a.cmp(b))
        });
        let median = pts[ids[mid] as usize][ax];
        let half = 0.5 * w[ax];
        let (mut left, mut right, mut sep) = (Vec::new(), Vec::new(), Vec::new());
        for &i in ids.iter() {
            let x = pts[i as usize][ax];
            if x < median - half {
                left.push(i);
            } else if x > median + half {
                right.push(i);
            } else {
                sep.push(i);
            }
        }
        if left.is_empty() || right.is_empty() {
            sort_along(ids, pts, ax);
            out.extend_from_slice(ids);
            return;
        }
        dissect(&mut left, pts, w, cut, out);
        dissect(&mut right, pts, w, cut, out);
        sort_along(&mut sep, pts, 1 - ax);
        out.extend_from_slice(&sep);
    }
    dissect(&mut ids, points, width, (leaf, thin_box), &mut order);
    order.iter().flat_map(|&i| [2 * i as usize, 2 * i as usize + 1]).collect()
}

/// The nodes cut once across the longer side at the median, each half in a banded order
/// running towards the cut (the lower half ascending, the upper half descending, along the
/// longer side then the shorter), the separator (the nodes within `width[axis] / 2` of the
/// median) last, along the shorter side; the DOF order as [`nested_dissection`]'s. The fill
/// is about the banded order's, and the assembly tree has two independent halves, which the
/// static LU factorises and substitutes on two tasks (docs/dev/performance.md, "Two-core
/// substitution"). `None` when the cut leaves a half empty.
pub fn split_band(points: &[Point], width: [f64; 2]) -> Option<Vec<usize>> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for d in 0..2 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let ax = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
    let mut along: Vec<f64> = points.iter().map(|p| p[ax]).collect();
    let mid = along.len() / 2;
    let median = *along.select_nth_unstable_by(mid, f64::total_cmp).1;
    let half = 0.5 * width[ax];
    let key = |i: &u32, sign: f64| {
        let p = points[*i as usize];
        (sign * p[ax], sign * p[1 - ax])
    };
    let (mut left, mut right, mut sep): (Vec<u32>, Vec<u32>, Vec<u32>) = Default::default();
    for (i, p) in (0u32..).zip(points) {
        match p[ax] {
            x if x < median - half => left.push(i),
            x if x > median + half => right.push(i),
            _ => sep.push(i),
        }
    }
    if left.is_empty() || right.is_empty() {
        return None;
    }
    let sort = |ids: &mut Vec<u32>, sign: f64| {
        ids.sort_unstable_by(|a, b| {
            let (ka, kb) = (key(a, sign), key(b, sign));
            ka.0.total_cmp(&kb.0).then(ka.1.total_cmp(&kb.1)).then(a.cmp(b))
        });
    };
    sort(&mut left, 1.0);
    sort(&mut right, -1.0);
    sep.sort_unstable_by(|a, b| {
        let (p, q) = (points[*a as usize], points[*b as usize]);
        p[1 - ax].total_cmp(&q[1 - ax]).then(p[ax].total_cmp(&q[ax])).then(a.cmp(b))
    });
    let nodes = left.into_iter().chain(right).chain(sep);
    Some(nodes.flat_map(|i| [2 * i as usize, 2 * i as usize + 1]).collect())
}

/// COLAMD column order of `matrix`.
fn colamd_order(a: SymbolicSparseColMatRef<'_, usize>) -> Result<Vec<usize>, SolveError> {
    let n = a.ncols();
    let (mut perm, mut inv) = (vec![0usize; n], vec![0usize; n]);
    let mut buf = buffer(colamd::order_scratch::<usize>(n, n, a.compute_nnz()))?;
    colamd::order(&mut perm, &mut inv, a, Default::default(), MemStack::new(&mut buf))
        .map_err(backend)?;
    Ok(perm)
}

fn is_permutation(perm: &[usize], n: usize) -> bool {
    let mut seen = vec![false; n];
    perm.len() == n && perm.iter().all(|&p| p < n && !std::mem::replace(&mut seen[p], true))
}

fn inverse(perm: &[usize]) -> Vec<usize> {
    let mut inv = vec![0usize; perm.len()];
    for (k, &p) in perm.iter().enumerate() {
        inv[p] = k;
    }
    inv
}

/// Column elimination tree and its postorder for the column order `perm`.
fn etree_and_postorder(
    a: SymbolicSparseColMatRef<'_, usize>,
    perm: &[usize],
    inv: &[usize],
) -> Result<(Vec<usize>, Vec<usize>), SolveError> {
    let n = a.ncols();
    let mut etree = vec![0usize; n];
    let mut post = vec![0usize; n];
    let mut buf = buffer(StackReq::any_of(&[
        qr::col_etree_scratch::<usize>(n, n),
        qr::postorder_scratch::<usize>(n),
    ]))?;
    let tree = qr::col_etree(
        a,
        Some(PermRef::new_checked(perm, inv, n)),
        &mut etree,
        MemStack::new(&mut buf),
    );
    qr::postorder(&mut post, tree, MemStack::new(&mut buf));
    Ok((etree, post))
}

/// Numeric factors with the row permutation and its inverse.
type Numeric = (SupernodalLu<usize, f64>, Vec<usize>, Vec<usize>);

/// A fill-reducing column order with its bounding column counts.
struct Analysis {
    col_perm: Vec<usize>,
    col_perm_inv: Vec<usize>,
    col_counts: Vec<usize>,
    min_col: Vec<usize>,
    /// `Σ c_j²` of the column counts.
    flops: f64,
}

impl Analysis {
    /// Postorders the column elimination tree of `perm` (so that supernodes are contiguous)
    /// and counts the columns of the Cholesky factor of `KᵀK` in that order.
    fn new(
        a: SymbolicSparseColMatRef<'_, usize>,
        at: SymbolicSparseColMatRef<'_, usize>,
        perm: Vec<usize>,
    ) -> Result<Self, SolveError> {
        let n = a.ncols();
        let inv = inverse(&perm);
        let (_, post) = etree_and_postorder(a, &perm, &inv)?;
        let col_perm: Vec<usize> = post.iter().map(|&k| perm[k]).collect();
        let col_perm_inv = inverse(&col_perm);
        let perm_ref = PermRef::new_checked(&col_perm, &col_perm_inv, n);
        let (mut etree, mut post) = (vec![0usize; n], vec![0usize; n]);
        let (mut col_counts, mut min_col) = (vec![0usize; n], vec![0usize; n]);
        let mut buf = buffer(StackReq::any_of(&[
            qr::col_etree_scratch::<usize>(n, n),
            qr::postorder_scratch::<usize>(n),
            StackReq::new::<usize>(n).array(6),
        ]))?;
        let tree = qr::col_etree(a, Some(perm_ref), &mut etree, MemStack::new(&mut buf));
        qr::postorder(&mut post, tree, MemStack::new(&mut buf));
        qr::column_counts_ata(
            &mut col_counts,
            &mut min_col,
            at,
            Some(perm_ref),
            tree,
            &post,
            MemStack::new(&mut buf),
        );
        let flops = col_counts.iter().map(|&c| (c as f64) * (c as f64)).sum();
        Ok(Self { col_perm, col_perm_inv, col_counts, min_col, flops })
    }
}

/// The chosen ordering of either method.
enum Ordered {
    /// Column order and bounding counts for the partial-pivoting LU.
    Columns(Analysis),
    /// Symmetric order for the static-pivoting LU, and the node graph its analysis uses.
    Symmetric(Vec<usize>, Option<symmetric::NodeGraph>),
}

/// Everything before the symbolic factorisation: the pruned matrix, its transpose and the
/// chosen ordering.
struct Plan {
    pruned: SystemMatrix,
    /// `Kᵀ` (partial pivoting only).
    at: Option<SparseColMat<usize, f64>>,
    ordered: Ordered,
    stats: FactorStats,
}

impl Plan {
    fn new(
        matrix: &SystemMatrix,
        ordering: ColumnOrdering<'_>,
        options: &FactorOptions,
    ) -> Result<Self, SolveError> {
        let n = matrix.n;
        let mut stats = FactorStats { nnz: matrix.values.len(), ..Default::default() };
        let pruned = without_void_entries(matrix, options.void_tolerance);
        stats.nnz_factorised = pruned.values.len();
        let sym =
            SymbolicSparseColMatRef::new_checked(n, n, &pruned.col_ptr, None, &pruned.row_idx);
        let a = SparseColMatRef::new(sym, &pruned.values);
        let t = std::time::Instant::now();
        let use_static = !matches!(ordering, ColumnOrdering::Colamd)
            && match options.method {
                FactorMethod::StaticPivoting => true,
                FactorMethod::PartialPivoting => false,
                FactorMethod::Auto => n >= STATIC_PIVOTING_MIN_DOFS,
            };
        // The candidates, and the split band order to weigh against the kept one.
        let (candidates, split): (Vec<Vec<usize>>, _) = match ordering {
            ColumnOrdering::NestedDissection(points) if 2 * points.len() == n => {
                // The static structure of the static-pivoting LU is that of `K + Kᵀ`, whose
                // reach is half that of `KᵀK`.
                let own = if use_static { 0.5 } else { 1.0 };
                let w = separator_width(&pruned, points).map(|w| w * own * options.separator_scale);
                let split = (use_static && options.split_band).then(|| split_band(points, w));
                let candidates = options
                    .thin_boxes
                    .iter()
                    .map(|&thin| nested_dissection(points, w, options.leaf_nodes.max(1), thin))
                    .collect();
                (candidates, split.flatten())
            }
            ColumnOrdering::Permutation(p) if is_permutation(p, n) => (vec![p.to_vec()], None),
            _ => (vec![colamd_order(sym)?], None),
        };
        // The first candidate, unless a later one bounds the flops clearly lower (the first,
        // nested dissection proper, needs less memory at equal flops: 6.5 vs 11.8 GB at 100k
        // nodes, docs/dev/performance.md).
        let is_static = use_static;
        stats.method =
            if is_static { FactorMethod::StaticPivoting } else { FactorMethod::PartialPivoting };
        if is_static {
            // Fill of the Cholesky factor of `P(K + Kᵀ)Pᵀ`.
            let graph = symmetric::NodeGraph::new(&pruned);
            let mut best: Option<(Vec<usize>, usize, f64)> = None;
            let mut candidates = candidates;
            if options.amd && matches!(ordering, ColumnOrdering::NestedDissection(_)) {
                if let Some(g) = &graph {
                    candidates.push(g.amd_order()?);
                }
            }
            for perm in candidates {
                let (nnz, flops) = symmetric::symmetric_fill(&pruned, graph.as_ref(), &perm)?;
                if best.as_ref().is_none_or(|b| flops < PREFER_FIRST * b.2) {
                    best = Some((perm, nnz, flops));
                }
            }
            let Some((mut perm, mut nnz, mut flops)) = best else {
                return Err(backend("no column ordering"));
            };
            if let Some(split) = split {
                let (s_nnz, s_flops) = symmetric::symmetric_fill(&pruned, graph.as_ref(), &split)?;
                let within = |a: f64, b: f64| a <= SPLIT_BAND_ALLOWANCE * b;
                if within(s_nnz as f64, nnz as f64) && within(s_flops, flops) {
                    (perm, nnz, flops) = (split, s_nnz, s_flops);
                }
            }
            stats.ordering_seconds = t.elapsed().as_secs_f64();
            stats.bound_nnz = nnz;
            stats.bound_flops = flops;
            return Ok(Self { pruned, at: None, ordered: Ordered::Symmetric(perm, graph), stats });
        }
        let at = a.transpose().to_col_major().map_err(backend)?;
        let mut best: Option<Analysis> = None;
        for perm in candidates {
            let analysis = Analysis::new(sym, at.symbolic(), perm)?;
            if best.as_ref().is_none_or(|b| analysis.flops < PREFER_FIRST * b.flops) {
                best = Some(analysis);
            }
        }
        let Some(analysis) = best else { return Err(backend("no column ordering")) };
        stats.ordering_seconds = t.elapsed().as_secs_f64();
        stats.bound_nnz = analysis.col_counts.iter().sum();
        stats.bound_flops = analysis.flops;
        Ok(Self { pruned, at: Some(at), ordered: Ordered::Columns(analysis), stats })
    }
}

impl Factorisation {
    /// Factorises `matrix` with a COLAMD column ordering (no geometry needed).
    ///
    /// # Errors
    /// [`SolveError::Singular`] for a structurally singular matrix, [`SolveError::Backend`]
    /// otherwise. Numerical singularity shows up in [`Self::solve`].
    pub fn new(matrix: &SystemMatrix) -> Result<Self, SolveError> {
        Self::with_ordering(matrix, ColumnOrdering::Colamd)
    }

    /// Factorises `matrix` with the nested-dissection ordering of the nodes `points`
    /// (`matrix.n == 2 points.len()`, DOFs interleaved); falls back to COLAMD when the sizes
    /// do not match.
    ///
    /// # Errors
    /// As [`Self::new`].
    pub fn with_node_coordinates(
        matrix: &SystemMatrix,
        points: &[Point],
    ) -> Result<Self, SolveError> {
        Self::with_ordering(matrix, ColumnOrdering::NestedDissection(points))
    }

    /// Factorises `matrix` with the given column ordering.
    ///
    /// # Errors
    /// As [`Self::new`].
    pub fn with_ordering(
        matrix: &SystemMatrix,
        ordering: ColumnOrdering<'_>,
    ) -> Result<Self, SolveError> {
        Self::with_options(matrix, ordering, &FactorOptions::default())
    }

    /// Factorises `matrix` with the given column ordering and tuning knobs (for experiments;
    /// the solver uses the defaults).
    ///
    /// # Errors
    /// As [`Self::new`].
    pub fn with_options(
        matrix: &SystemMatrix,
        ordering: ColumnOrdering<'_>,
        options: &FactorOptions,
    ) -> Result<Self, SolveError> {
        let plan = Plan::new(matrix, ordering, options)?;
        Self::from_plan(plan, symmetric::Full::Matrix(matrix), options)
    }

    /// Factorises `base` with the rows `rows` replaced ([`ReplacedRows::matrix`]), as
    /// [`Self::with_options`] would that matrix, with the same factors and solutions, but
    /// without holding a copy of it through the numeric factorisation, nor (static
    /// pivoting) keeping one for refinement: only `rows` are kept, and every solve needs
    /// `base` again ([`Self::solve_in_place_against`]; [`Self::solve_in_place`] gives NaN
    /// columns). The active set's row-replaced `K` at 10⁶ nodes: 1.6 GB less at the peak
    /// and 1.6 GB less through the iterations (docs/dev/performance.md).
    ///
    /// # Errors
    /// As [`Self::new`].
    pub fn with_replaced_rows(
        base: &SystemMatrix,
        rows: ReplacedRows,
        ordering: ColumnOrdering<'_>,
        options: &FactorOptions,
    ) -> Result<Self, SolveError> {
        let plan = {
            let matrix = rows.matrix(base);
            Plan::new(&matrix, ordering, options)?
        };
        Self::from_plan(plan, symmetric::Full::Replaced { base, rows }, options)
    }

    /// The factorisation of a planned matrix; `full` is what the static-pivoting LU refines
    /// against.
    fn from_plan(
        plan: Plan,
        full: symmetric::Full<'_>,
        options: &FactorOptions,
    ) -> Result<Self, SolveError> {
        let Plan { pruned, at, ordered, mut stats } = plan;
        let n = pruned.n;
        let analysis = match ordered {
            Ordered::Columns(analysis) => analysis,
            Ordered::Symmetric(perm, graph) => {
                let settings = symmetric::Settings {
                    pivot_tolerance: options.pivot_tolerance,
                    parallel: options.tasks > 1,
                    precision: options.precision,
                    gmres_max_iterations: options.gmres_max_iterations,
                };
                let (lu, symbolic_seconds, numeric_seconds) =
                    symmetric::StaticLu::new(full, pruned, graph, &perm, settings)?;
                stats.symbolic_seconds = symbolic_seconds;
                stats.numeric_seconds = numeric_seconds;
                stats.supernodes = lu.supernodes();
                stats.factor_nnz = lu.factor_nnz;
                stats.perturbed_pivots = lu.perturbed;
                stats.precision = lu.precision();
                let options = options.clone();
                return Ok(Self { inner: Inner::Static(lu), n, stats, options });
            }
        };
        let sym =
            SymbolicSparseColMatRef::new_checked(n, n, &pruned.col_ptr, None, &pruned.row_idx);
        let a = SparseColMatRef::new(sym, &pruned.values);

        let t = std::time::Instant::now();
        let Analysis { col_perm, col_perm_inv, col_counts, min_col, .. } = analysis;
        let perm_ref = PermRef::new_checked(&col_perm, &col_perm_inv, n);
        let symbolic = {
            let mut etree = vec![0usize; n];
            let mut buf = buffer(StackReq::any_of(&[
                qr::col_etree_scratch::<usize>(n, n),
                supernodal::factorize_supernodal_symbolic_lu_scratch::<usize>(n, n),
            ]))?;
            let tree = qr::col_etree(sym, Some(perm_ref), &mut etree, MemStack::new(&mut buf));
            factorize_supernodal_symbolic_lu::<usize>(
                sym,
                Some(perm_ref),
                &min_col,
                tree,
                &col_counts,
                MemStack::new(&mut buf),
                SymbolicSupernodalParams::default(),
            )
            .map_err(backend)?
        };
        stats.symbolic_seconds = t.elapsed().as_secs_f64();

        let t = std::time::Instant::now();
        let par = if options.tasks > 1 { Par::rayon(options.tasks) } else { Par::Seq };
        let at = at.ok_or_else(|| backend("no transpose for the partial-pivoting LU"))?;
        let (lu, row_perm, row_perm_inv) = Self::numeric(a, at.as_ref(), perm_ref, &symbolic, par)?;
        stats.numeric_seconds = t.elapsed().as_secs_f64();
        stats.supernodes = lu.n_supernodes();
        stats.precision = FactorPrecision::Double;
        let inner = Inner::Partial { lu, row_perm, row_perm_inv, col_perm, col_perm_inv };
        Ok(Self { inner, n, stats, options: options.clone() })
    }

    /// The ordering and the fill bound a factorisation with these settings would use, without
    /// factorising (milliseconds to a second; for tuning).
    ///
    /// # Errors
    /// [`SolveError::Backend`] when out of memory.
    pub fn analyse(
        matrix: &SystemMatrix,
        ordering: ColumnOrdering<'_>,
        options: &FactorOptions,
    ) -> Result<FactorStats, SolveError> {
        Plan::new(matrix, ordering, options).map(|p| p.stats)
    }

    fn numeric(
        a: SparseColMatRef<'_, usize, f64>,
        at: SparseColMatRef<'_, usize, f64>,
        col_perm: PermRef<'_, usize>,
        symbolic: &SymbolicSupernodalLu<usize>,
        par: Par,
    ) -> Result<Numeric, SolveError> {
        let n = a.ncols();
        let mut lu = SupernodalLu::<usize, f64>::new();
        let (mut row_perm, mut row_perm_inv) = (vec![0usize; n], vec![0usize; n]);
        let mut buf = buffer(supernodal::factorize_supernodal_numeric_lu_scratch::<usize, f64>(
            symbolic,
            Default::default(),
        ))?;
        factorize_supernodal_numeric_lu(
            &mut row_perm,
            &mut row_perm_inv,
            &mut lu,
            a,
            at,
            col_perm,
            symbolic,
            par,
            MemStack::new(&mut buf),
            Default::default(),
        )
        .map_err(|e| match e {
            LuError::SymbolicSingular { index } => {
                SolveError::Singular { detail: format!("no pivot at step {index} of {n}") }
            }
            LuError::Generic(g) => backend(g),
        })?;
        Ok((lu, row_perm, row_perm_inv))
    }

    /// The options this factorisation was made with (to factorise a related matrix, such as a
    /// row-replaced `K`, alike).
    pub fn options(&self) -> &FactorOptions {
        &self.options
    }

    /// Order of the matrix.
    pub fn size(&self) -> usize {
        self.n
    }

    /// Drops the factors (and frees their memory), keeping [`Self::stats`] as they are now
    /// and [`Self::options`]; later solves give NaN columns and [`SolveError::Released`].
    /// The active-set solver releases `K`'s factors before it factorises its first
    /// row-replaced matrix, when nothing will solve with `K` again (docs/method.md §5.1), so
    /// that two factorisations of the body are never alive at once.
    pub fn release(&mut self) {
        self.stats = self.stats();
        self.inner = Inner::Released;
    }

    /// Moves the factors out into the factorisation returned, leaving `self` released (its
    /// statistics and options as they are now), so that a solver can own them and release
    /// them when done.
    pub fn take(&mut self) -> Factorisation {
        let released = Factorisation {
            inner: Inner::Released,
            n: self.n,
            stats: self.stats(),
            options: self.options.clone(),
        };
        std::mem::replace(self, released)
    }

    /// A factorisation of an `n × n` matrix that is not made: no factors and empty
    /// statistics, as if released from the start ([`Self::is_released`]), with the `options`
    /// that a factorisation of that matrix, or of a related one, is to be made with. The
    /// pipeline leaves `K` so when the one solver that would use its factors needs none
    /// (the frictionless active set against rigid obstacles that starts from every candidate
    /// closed, docs/method.md §5.1), or factorises it later when it turns out to need them.
    /// Solves give NaN columns and [`SolveError::Released`].
    pub fn unfactorised(n: usize, options: FactorOptions) -> Self {
        let stats = FactorStats { precision: options.precision, ..FactorStats::default() };
        Factorisation { inner: Inner::Released, n, stats, options }
    }

    /// Whether [`Self::release`] has dropped the factors (or [`Self::unfactorised`] made
    /// none).
    pub fn is_released(&self) -> bool {
        matches!(self.inner, Inner::Released)
    }

    /// Sizes and stage times of this factorisation, and (static pivoting) the refinement
    /// record of the solves so far.
    pub fn stats(&self) -> FactorStats {
        let mut stats = self.stats;
        if let Inner::Static(lu) = &self.inner {
            let r = lu.refinement();
            stats.refinement_steps = r.steps;
            stats.columns_solved = r.columns;
            stats.gmres_columns = r.gmres_columns;
            stats.gmres_iterations = r.gmres_iterations;
            stats.worst_backward_error = r.worst_backward_error;
        }
        stats
    }

    /// Solves `K X = B` in place for the columns of `rhs` (`n × k`), sequentially.
    ///
    /// With [`FactorMethod::StaticPivoting`] every column is refined against `K`; a column
    /// whose backward error stays above [`ACCEPTED_BACKWARD_ERROR`] is returned as NaN
    /// (reported by [`Self::solve`] and by the contact condensation as an error).
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        self.solve_with(rhs, None);
    }

    /// Solves `K X = B` in place with the factors alone: with
    /// [`FactorMethod::StaticPivoting`] the substitutions without refinement against `K`
    /// (no residual, no backward error recorded), otherwise [`Self::solve_in_place`]. For
    /// callers that check the accuracy themselves, or whose factorisation perturbed no pivot
    /// and whose matrix the substitution is known to solve to round-off.
    pub fn solve_unrefined_in_place(&self, rhs: MatMut<'_, f64>) {
        match &self.inner {
            Inner::Static(lu) => lu.substitute_in_place(rhs),
            _ => self.solve_in_place(rhs),
        }
    }

    /// [`Self::solve_in_place`] for a factorisation of replaced rows
    /// ([`Self::with_replaced_rows`]) of `base`, which its refinement needs; any other
    /// factorisation ignores `base`.
    pub fn solve_in_place_against(&self, base: &SystemMatrix, rhs: MatMut<'_, f64>) {
        self.solve_with(rhs, Some(base));
    }

    fn solve_with(&self, rhs: MatMut<'_, f64>, base: Option<&SystemMatrix>) {
        match &self.inner {
            Inner::Partial { lu, row_perm, row_perm_inv, col_perm, col_perm_inv } => {
                let par = Par::Seq;
                let req =
                    supernodal::solve_in_place_scratch::<usize, f64>(self.n, rhs.ncols(), par);
                let mut buf = MemBuffer::new(req);
                lu.solve_in_place_with_conj(
                    PermRef::new_checked(row_perm, row_perm_inv, self.n),
                    PermRef::new_checked(col_perm, col_perm_inv, self.n),
                    Conj::No,
                    rhs,
                    par,
                    MemStack::new(&mut buf),
                );
            }
            Inner::Static(lu) => lu.solve_in_place(rhs, base),
            Inner::Released => {
                let mut rhs = rhs;
                rhs.fill(f64::NAN);
            }
        }
    }

    /// `G K⁻¹ E` (row-major `rows.len() × columns.len()`) for sparse columns of `E` and rows
    /// of `G` (`(DOF, value)` entries), by triangular solves restricted to the reach of each
    /// vector in the static-pivoting LU's own supernodal factors (`symmetric/reach.rs`),
    /// without forming `K⁻¹ E`. `None` when that route does not apply or would not pay:
    /// faer's LU, single-precision factors, perturbed pivots (the unrefined solves could
    /// have lost accuracy), or an estimate of its flops above that of `columns.len()` full
    /// solves (as with a banded order, whose elimination tree is a path).
    pub fn sparse_products(
        &self,
        columns: &[Vec<(usize, f64)>],
        rows: &[Vec<(usize, f64)>],
    ) -> Option<SparseProducts> {
        let Inner::Static(lu) = &self.inner else { return None };
        if lu.perturbed > 0 {
            return None;
        }
        let (values, cost) = lu.sparse_products(columns, rows, Some(1.0))?;
        Some(SparseProducts { values, sparse_flops: cost.sparse, full_flops: cost.full })
    }

    /// Solves `K x = b`.
    ///
    /// # Errors
    /// [`SolveError::Singular`] when the result is not finite (numerically singular `K`).
    pub fn solve(&self, b: &[f64]) -> Result<Vec<f64>, SolveError> {
        let mut x = b.to_vec();
        self.solve_in_place(MatMut::from_column_major_slice_mut(&mut x, self.n, 1));
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            if self.is_released() {
                return Err(SolveError::Released);
            }
            if self.stats.precision == FactorPrecision::Mixed {
                return Err(SolveError::NotConverged {
                    detail: format!(
                        "iterative refinement and GMRES-IR with the single-precision factors \
                         did not reach a backward error of {ACCEPTED_BACKWARD_ERROR:e}"
                    ),
                });
            }
            let detail = match self.inner {
                Inner::Static(_) => format!(
                    "iterative refinement did not reach a backward error of \
                     {ACCEPTED_BACKWARD_ERROR:e} (static pivoting)"
                ),
                Inner::Partial { .. } | Inner::Released => {
                    format!("non-finite solution at DOF {i}")
                }
            };
            return Err(SolveError::Singular { detail });
        }
        Ok(x)
    }
}

/// `y = A x` for a compressed-column matrix.
pub fn mul(matrix: &SystemMatrix, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; matrix.n];
    for (c, &xc) in x.iter().enumerate() {
        for k in matrix.col_ptr[c]..matrix.col_ptr[c + 1] {
            y[matrix.row_idx[k]] += matrix.values[k] * xc;
        }
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    /// A 2-D Laplacian-like matrix on a `k × k` grid with two DOFs per node (non-symmetric
    /// off-diagonal scaling, a few void entries).
    fn grid(k: usize) -> (SystemMatrix, Vec<Point>) {
        let nn = k * k;
        let n = 2 * nn;
        let points: Vec<Point> = (0..nn).map(|i| [(i % k) as f64, (i / k) as f64]).collect();
        let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for i in 0..nn {
            let (x, y) = (i % k, i / k);
            for d in 0..2 {
                let c = 2 * i + d;
                cols[c].push((c, 4.5));
                cols[c].push((2 * i + 1 - d, 1e-17));
                let mut push = |j: usize, v: f64| cols[c].push((2 * j + d, v));
                if x > 0 {
                    push(i - 1, -1.0);
                }
                if x + 1 < k {
                    push(i + 1, -1.2);
                }
                if y > 0 {
                    push(i - k, -0.9);
                }
                if y + 1 < k {
                    push(i + k, -1.1);
                }
            }
        }
        let mut m = SystemMatrix { n, col_ptr: vec![0], row_idx: Vec::new(), values: Vec::new() };
        for mut col in cols {
            col.sort_by_key(|e| e.0);
            for (r, v) in col {
                m.row_idx.push(r);
                m.values.push(v);
            }
            m.col_ptr.push(m.row_idx.len());
        }
        (m, points)
    }

    fn residual(m: &SystemMatrix, x: &[f64], b: &[f64]) -> f64 {
        let ax = mul(m, x);
        let r = ax.iter().zip(b).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
        r / b.iter().map(|v| v * v).sum::<f64>().sqrt()
    }

    #[test]
    fn nested_dissection_is_a_permutation_keeping_node_dofs_together() {
        let (m, points) = grid(30);
        let w = separator_width(&m, &points);
        assert_eq!(w, [2.0, 2.0]);
        let p = nested_dissection(&points, w, 16, 4.0);
        assert_eq!(p.len(), m.n);
        let mut seen = vec![false; m.n];
        for pair in p.chunks(2) {
            assert_eq!(pair[0] % 2, 0);
            assert_eq!(pair[1], pair[0] + 1);
        }
        for &i in &p {
            assert!(!seen[i]);
            seen[i] = true;
        }
    }

    #[test]
    fn both_orderings_solve_to_round_off() {
        let (m, points) = grid(40);
        let b: Vec<f64> = (0..m.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        for ordering in [ColumnOrdering::NestedDissection(&points), ColumnOrdering::Colamd] {
            let f = Factorisation::with_ordering(&m, ordering).unwrap();
            assert!(f.stats().nnz_factorised < f.stats().nnz, "void entries dropped");
            let x = f.solve(&b).unwrap();
            let r = residual(&m, &x, &b);
            assert!(r < 1e-14, "{ordering:?}: residual {r:e}");
        }
    }

    fn static_options() -> FactorOptions {
        FactorOptions { method: FactorMethod::StaticPivoting, ..Default::default() }
    }

    fn hash(x: &[f64]) -> u64 {
        x.iter()
            .fold(0xcbf2_9ce4_8422_2325u64, |h, v| (h ^ v.to_bits()).wrapping_mul(0x100_0000_01b3))
    }

    #[test]
    fn replaced_rows_factorise_and_solve_as_their_assembled_matrix_bit_for_bit() {
        let (m, points) = grid(30);
        // Rows of a few node pairs replaced by rows reaching other nodes (as the active set's
        // gap rows do), one a sum with a repeated column.
        let rows: Vec<(usize, Vec<(usize, f64)>)> = (0..m.n)
            .step_by(97)
            .map(|d| {
                let j = (d + 61) % m.n;
                (d, vec![(j, 0.7), (d, 3.9), (j, 0.25), ((d + 2) % m.n, -1.3)])
            })
            .collect();
        let replaced = ReplacedRows::new(m.n, rows);
        let assembled = replaced.matrix(&m);
        let mixed = FactorOptions { precision: FactorPrecision::Mixed, ..static_options() };
        // 17 columns: the residuals against the replaced rows are computed in two halves
        // (`symmetric::SPLIT_RESIDUAL_COLUMNS`), those of the copy in one pass.
        for ((ordering, options), cols) in [
            (ColumnOrdering::NestedDissection(&points), static_options()),
            (ColumnOrdering::NestedDissection(&points), mixed),
            (ColumnOrdering::Colamd, FactorOptions::default()),
        ]
        .into_iter()
        .flat_map(|o| [(o.clone(), 3), (o, 17)])
        {
            let b = Mat::<f64>::from_fn(m.n, cols, |i, j| ((i * 7919 + j * 31) % 13) as f64 - 6.0);
            let copy = Factorisation::with_options(&assembled, ordering, &options).unwrap();
            let rows = Factorisation::with_replaced_rows(&m, replaced.clone(), ordering, &options)
                .unwrap();
            let (mut x, mut y) = (b.clone(), b.clone());
            copy.solve_in_place(x.as_mut());
            rows.solve_in_place_against(&m, y.as_mut());
            for j in 0..cols {
                assert_eq!(hash(x.col_as_slice(j)), hash(y.col_as_slice(j)), "{ordering:?}");
            }
            assert!(residual(&assembled, y.col_as_slice(0), b.col_as_slice(0)) < 1e-13);
            let (a, c) = (copy.stats(), rows.stats());
            assert_eq!(a.refinement_steps, c.refinement_steps);
            assert_eq!(a.worst_backward_error.to_bits(), c.worst_backward_error.to_bits());
            if c.method == FactorMethod::StaticPivoting {
                // Without `K` the refinement cannot run: the columns are refused.
                let mut z = b.clone();
                rows.solve_in_place(z.as_mut());
                assert!(z.col_as_slice(0).iter().all(|v| v.is_nan()));
            }
        }
        // GMRES-IR (single-precision factors of an ill-conditioned matrix: its products with
        // the replaced matrix) alike: the 1-D Laplacian with its first row replaced.
        let n = 20_000;
        let lap = laplacian(n);
        let replaced = ReplacedRows::new(n, [(0, vec![(1, -1.0), (0, 2.5)])]);
        let assembled = replaced.matrix(&lap);
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let order: Vec<usize> = (0..n).collect();
        let mixed = FactorOptions { precision: FactorPrecision::Mixed, ..static_options() };
        let ordering = ColumnOrdering::Permutation(&order);
        let copy = Factorisation::with_options(&assembled, ordering, &mixed).unwrap();
        let rows = Factorisation::with_replaced_rows(&lap, replaced, ordering, &mixed).unwrap();
        let (mut x, mut y) = (b.clone(), b.clone());
        copy.solve_in_place(MatMut::from_column_major_slice_mut(&mut x, n, 1));
        rows.solve_in_place_against(&lap, MatMut::from_column_major_slice_mut(&mut y, n, 1));
        assert_eq!(hash(&x), hash(&y));
        let (a, c) = (copy.stats(), rows.stats());
        assert_eq!(c.gmres_columns, 1, "plain refinement must have stalled");
        assert_eq!((a.gmres_columns, a.gmres_iterations), (c.gmres_columns, c.gmres_iterations));
    }

    #[test]
    fn static_pivoting_solves_to_round_off_independently_of_tasks() {
        let (m, points) = grid(40);
        let b: Vec<f64> = (0..m.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let mut hashes = Vec::new();
        for tasks in [1, 2] {
            let options = FactorOptions { tasks, ..static_options() };
            let f = Factorisation::with_options(
                &m,
                ColumnOrdering::NestedDissection(&points),
                &options,
            )
            .unwrap();
            assert_eq!(f.stats().method, FactorMethod::StaticPivoting);
            assert!(f.stats().factor_nnz > 0);
            let x = f.solve(&b).unwrap();
            let r = residual(&m, &x, &b);
            assert!(r < 1e-14, "tasks {tasks}: residual {r:e}");
            assert!(f.stats().worst_backward_error <= 1e-14);
            hashes.push(hash(&x));
            // Several right-hand sides at once.
            let mut block =
                Mat::<f64>::from_fn(
                    m.n,
                    3,
                    |i, j| if j == 1 { b[i] } else { (i % (j + 2)) as f64 },
                );
            f.solve_in_place(block.as_mut());
            let r = residual(&m, block.col_as_slice(1), &b);
            assert!(r < 1e-14, "tasks {tasks}, block: residual {r:e}");
        }
        assert_eq!(hashes[0], hashes[1]);
    }

    #[test]
    fn the_minimum_degree_candidate_keeps_node_dofs_together_and_solves() {
        // Alone (no geometric candidate) and as a third candidate: a permutation that keeps
        // each node's DOFs adjacent (so the analysis runs on the node graph), kept only when
        // its bound is lower, solving to round-off.
        let (m, points) = grid(30);
        let b: Vec<f64> = (0..m.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let graph = symmetric::NodeGraph::new(&m).unwrap();
        let order = graph.amd_order().unwrap();
        assert!(is_permutation(&order, m.n));
        assert!(order.chunks(2).all(|p| p[0] % 2 == 0 && p[1] == p[0] + 1));
        let nd = FactorOptions::nested_dissection_static();
        let alone = FactorOptions { thin_boxes: Vec::new(), amd: true, ..static_options() };
        let third = FactorOptions { amd: true, ..nd.clone() };
        let mut flops = Vec::new();
        for options in [&nd, &alone, &third] {
            let ordering = ColumnOrdering::NestedDissection(&points);
            let f = Factorisation::with_options(&m, ordering, options).unwrap();
            let x = f.solve(&b).unwrap();
            let r = residual(&m, &x, &b);
            assert!(r < 1e-14, "amd {}: residual {r:e}", options.amd);
            flops.push(f.stats().bound_flops);
        }
        let (nd, alone, third) = (flops[0], flops[1], flops[2]);
        assert!(alone > 0.0);
        assert!(third == nd || (third == alone && alone < PREFER_FIRST * nd), "{flops:?}");
    }

    #[test]
    fn static_pivoting_analyses_node_and_dof_graphs_alike() {
        // Nested dissection keeps node DOFs together (analysis on the node graph); swapping
        // each pair's DOFs forces the analysis of the DOF graph. Both must solve.
        let (m, points) = grid(20);
        let b: Vec<f64> = (0..m.n).map(|i| (i % 5) as f64 - 2.0).collect();
        let nd = nested_dissection(&points, separator_width(&m, &points), 16, 4.0);
        let swapped: Vec<usize> = nd.chunks(2).flat_map(|p| [p[1], p[0]]).collect();
        for order in [&nd, &swapped] {
            let f = Factorisation::with_options(
                &m,
                ColumnOrdering::Permutation(order),
                &static_options(),
            )
            .unwrap();
            let x = f.solve(&b).unwrap();
            let r = residual(&m, &x, &b);
            assert!(r < 1e-14, "residual {r:e}");
        }
    }

    /// The 1-D Laplacian `tridiag(−1, 2, −1)` of order `n`.
    fn laplacian(n: usize) -> SystemMatrix {
        let mut lap = SystemMatrix { n, col_ptr: vec![0], row_idx: Vec::new(), values: Vec::new() };
        for c in 0..n {
            for (r, v) in [(c.wrapping_sub(1), -1.0), (c, 2.0), (c + 1, -1.0)] {
                if r < n {
                    lap.row_idx.push(r);
                    lap.values.push(v);
                }
            }
            lap.col_ptr.push(lap.row_idx.len());
        }
        lap
    }

    #[test]
    fn mixed_precision_refines_to_double_accuracy_and_finishes_with_gmres_when_refinement_stalls() {
        let mixed = FactorOptions { precision: FactorPrecision::Mixed, ..static_options() };
        // Well conditioned: single-precision factors (solution errors ~1e-7 unrefined) are
        // refined to the double-precision target by plain refinement alone.
        let (m, points) = grid(40);
        let b: Vec<f64> = (0..m.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let f = Factorisation::with_options(&m, ColumnOrdering::NestedDissection(&points), &mixed)
            .unwrap();
        let x = f.solve(&b).unwrap();
        let r = residual(&m, &x, &b);
        let s = f.stats();
        assert_eq!(s.precision, FactorPrecision::Mixed);
        assert!(r < 1e-14, "residual {r:e}");
        assert!(s.refinement_steps > 0, "single-precision factors need refinement");
        assert_eq!(s.gmres_columns, 0);
        assert!(s.worst_backward_error <= 1e-14);
        // Ill conditioned: the 1-D Laplacian of order 20 000 has κ ≈ 4n²/π² ≈ 1.6e8 >
        // 1/ε_f32, so plain refinement with single-precision factors stalls; GMRES-IR, with
        // the same factors as preconditioner, reaches the double-precision target.
        let n = 20_000;
        let lap = laplacian(n);
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let order: Vec<usize> = (0..n).collect();
        let f =
            Factorisation::with_options(&lap, ColumnOrdering::Permutation(&order), &mixed).unwrap();
        let x = f.solve(&b).unwrap();
        let s = f.stats();
        println!("Laplacian n = {n}: {s:?}");
        assert_eq!(s.gmres_columns, 1, "plain refinement must have stalled");
        assert!(s.gmres_iterations > 0);
        assert!(s.worst_backward_error <= 1e-14, "{:e}", s.worst_backward_error);
        let r = residual(&lap, &x, &b);
        assert!(r < 1e-12, "residual {r:e}");
    }

    #[test]
    fn taken_factors_solve_and_the_released_ones_keep_their_statistics() {
        // The active-set solver takes `K`'s factors out of the model and releases them
        // (contact::sparse::ModelFactors): the taken ones solve as before, the model's keep
        // the statistics (summary.json reports them) and refuse to solve with a typed error;
        // releasing keeps the refinement record of the solves made before.
        let (m, points) = grid(20);
        let b: Vec<f64> = (0..m.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let mut f = Factorisation::with_options(
            &m,
            ColumnOrdering::NestedDissection(&points),
            &static_options(),
        )
        .unwrap();
        let expected = f.solve(&b).unwrap();
        let before = f.stats();
        let mut taken = f.take();
        assert!(f.is_released() && !taken.is_released());
        assert_eq!(format!("{:?}", f.stats()), format!("{before:?}"));
        assert!(matches!(f.solve(&b), Err(SolveError::Released)), "{:?}", f.solve(&b));
        assert_eq!(taken.solve(&b).unwrap(), expected, "the taken factors are the same");
        let used = taken.stats();
        assert_eq!(used.columns_solved, before.columns_solved + 1);
        taken.release();
        assert!(taken.is_released());
        assert_eq!(format!("{:?}", taken.stats()), format!("{used:?}"));
        assert_eq!(taken.size(), m.n);
        assert!(matches!(taken.solve(&b), Err(SolveError::Released)));
    }

    #[test]
    fn mixed_precision_refuses_a_column_gmres_ir_cannot_finish() {
        // The Laplacian above needs ~100 GMRES iterations; with at most 5 the column cannot
        // reach the accepted backward error, and the solve must say so (a typed error, not a
        // wrong answer), while the double-precision factors solve it.
        let n = 20_000;
        let lap = laplacian(n);
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let order: Vec<usize> = (0..n).collect();
        let double = Factorisation::with_options(
            &lap,
            ColumnOrdering::Permutation(&order),
            &static_options(),
        )
        .unwrap();
        assert!(residual(&lap, &double.solve(&b).unwrap(), &b) < 1e-12);
        let mixed = FactorOptions {
            precision: FactorPrecision::Mixed,
            gmres_max_iterations: 5,
            ..static_options()
        };
        let f =
            Factorisation::with_options(&lap, ColumnOrdering::Permutation(&order), &mixed).unwrap();
        let out = f.solve(&b);
        let s = f.stats();
        assert!(matches!(out, Err(SolveError::NotConverged { .. })), "{:?}", out.err());
        assert_eq!((s.gmres_columns, s.gmres_iterations), (1, 5));
        assert!(s.worst_backward_error.is_infinite());
    }

    #[test]
    fn static_pivoting_pivots_inside_node_blocks() {
        // Swap the roles of a node's two DOFs: each diagonal entry becomes tiny while the
        // node's off-diagonal couplings are strong, so the diagonal block must pivot.
        let (mut m, points) = grid(20);
        for c in 0..m.n {
            for k in m.col_ptr[c]..m.col_ptr[c + 1] {
                let r = m.row_idx[k];
                if r == c {
                    m.values[k] = 1e-3;
                } else if r / 2 == c / 2 {
                    m.values[k] = 4.5;
                }
            }
        }
        let b: Vec<f64> = (0..m.n).map(|i| (i % 7) as f64 - 3.0).collect();
        let f = Factorisation::with_options(
            &m,
            ColumnOrdering::NestedDissection(&points),
            &static_options(),
        )
        .unwrap();
        let x = f.solve(&b).unwrap();
        let r = residual(&m, &x, &b);
        assert!(r < 1e-13, "residual {r:e}");
    }

    #[test]
    fn reach_restricted_products_equal_full_solves_with_row_swaps() {
        // The matrix of `static_pivoting_pivots_inside_node_blocks` (every diagonal block
        // pivots), sparse columns of E and rows of G of a few entries each, G K⁻¹ E by
        // reach-restricted solves against G times full solves with the same factors.
        let (mut m, points) = grid(20);
        for c in 0..m.n {
            for k in m.col_ptr[c]..m.col_ptr[c + 1] {
                let r = m.row_idx[k];
                if r == c {
                    m.values[k] = 1e-3;
                } else if r / 2 == c / 2 {
                    m.values[k] = 4.5;
                }
            }
        }
        let f = Factorisation::with_options(
            &m,
            ColumnOrdering::NestedDissection(&points),
            &FactorOptions::nested_dissection_static(),
        )
        .unwrap();
        let Inner::Static(lu) = &f.inner else { panic!("static pivoting") };
        assert_eq!(lu.perturbed, 0);
        let n = m.n;
        let columns: Vec<Vec<(usize, f64)>> = (0..30)
            .map(|c| vec![((c * 97) % n, 1.0 + c as f64), ((c * 31 + 5) % n, -0.5)])
            .collect();
        let rows: Vec<Vec<(usize, f64)>> = (0..25)
            .map(|r| (0..6).map(|t| ((r * 53 + t * 11) % n, 0.3 * t as f64 - 0.7)).collect())
            .collect();
        let (sparse, _) = lu.sparse_products(&columns, &rows, None).unwrap();
        let mut e = Mat::<f64>::zeros(n, columns.len());
        for (c, col) in columns.iter().enumerate() {
            for &(i, v) in col {
                e[(i, c)] += v;
            }
        }
        f.solve_in_place(e.as_mut());
        let mut worst = 0.0f64;
        let mut scale = 0.0f64;
        for (r, row) in rows.iter().enumerate() {
            for c in 0..columns.len() {
                let full: f64 = row.iter().map(|&(i, v)| v * e[(i, c)]).sum();
                worst = worst.max((full - sparse[r * columns.len() + c]).abs());
                scale = scale.max(full.abs());
            }
        }
        assert!(scale > 0.0);
        assert!(worst <= 1e-12 * scale, "max difference {worst:e} of {scale:e}");
        // The same bits with the public entry point when it accepts the route.
        if let Some(p) = f.sparse_products(&columns, &rows) {
            assert_eq!(p.values, sparse);
        }
    }

    #[test]
    fn singular_matrices_give_errors_not_panics() {
        // Structurally singular: an empty column and row.
        let (mut m, points) = grid(6);
        let c = 10;
        let kept: Vec<(usize, usize, f64)> = (0..m.n)
            .flat_map(|col| {
                let m = &m;
                (m.col_ptr[col]..m.col_ptr[col + 1]).map(move |k| (m.row_idx[k], col, m.values[k]))
            })
            .filter(|&(r, col, _)| r != c && col != c)
            .collect();
        m.col_ptr = vec![0];
        m.row_idx.clear();
        m.values.clear();
        for col in 0..m.n {
            for &(r, cc, v) in kept.iter().filter(|e| e.1 == col) {
                debug_assert_eq!(cc, col);
                m.row_idx.push(r);
                m.values.push(v);
            }
            m.col_ptr.push(m.row_idx.len());
        }
        for ordering in [ColumnOrdering::NestedDissection(&points), ColumnOrdering::Colamd] {
            let out =
                Factorisation::with_ordering(&m, ordering).and_then(|f| f.solve(&vec![1.0; m.n]));
            assert!(matches!(out, Err(SolveError::Singular { .. })), "{ordering:?}: {out:?}");
        }
        let out = Factorisation::with_options(
            &m,
            ColumnOrdering::NestedDissection(&points),
            &static_options(),
        )
        .and_then(|f| f.solve(&vec![1.0; m.n]));
        assert!(matches!(out, Err(SolveError::Singular { .. })), "static pivoting: {out:?}");
    }
}
