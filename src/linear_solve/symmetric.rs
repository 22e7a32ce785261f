//! Multifrontal LU with the symmetric static structure of `K + Kᵀ` and static pivoting
//! ([`super::FactorMethod::StaticPivoting`]).
//!
//! # How
//!
//! - **Scaling.** `Â = D_r K D_c` with power-of-two row then column equilibration (every row
//!   and column of `Â` has its largest entry in `[0.5, 2)`), so that one pivot tolerance fits
//!   all rows (displacement rows and traction rows differ by ~10⁷ in `K`).
//! - **Ordering.** Nested dissection of the nodes with separators as wide as `K`'s own reach
//!   (half of [`super::separator_width`], which is sized for `KᵀK`), or a banded order when
//!   its fill is clearly lower, and on request ([`super::FactorOptions::amd`], the adaptive
//!   loop's graded sets) the approximate minimum degree order of the node graph; the orders
//!   are compared by the flops of the Cholesky factor of `P(K + Kᵀ)Pᵀ` (faer's column
//!   counts), the static structure used here.
//! - **Symbolic.** faer's supernodal Cholesky analysis of `P(Â + Âᵀ)Pᵀ` (postordered
//!   elimination tree, relaxed supernodes). `L` and `Uᵀ` have this structure. When the order
//!   keeps each node's two DOFs together (nested dissection does), the analysis runs on the
//!   node graph ([`NodeGraph`], a quarter of the entries) and is expanded to DOFs, each node
//!   a dense 2 × 2 block: 0.75 s instead of 3.7 s for ordering and analysis at 100k nodes.
//! - **Numeric.** Multifrontal: each supernode assembles its front (its entries of `Â` and
//!   its children's contribution blocks), factors its diagonal block with partial pivoting
//!   *restricted to that block* (a pivot below `pivot_tolerance` is replaced by
//!   `±pivot_tolerance` and counted), computes its rows of `U` and columns of `L`, and passes
//!   the Schur complement to its parent. The front's columns are factorised recursively
//!   (halves, narrow unblocked panels at the leaves), so nearly all dense work goes through
//!   faer's triangular solves and large matrix products. Independent subtrees of the
//!   assembly tree run in parallel (rayon); the arithmetic of every front is the same
//!   whatever the pool size, so results are bit-identical across thread counts.
//! - **Precision.** The factors are `f64` by default; [`super::FactorPrecision::Mixed`]
//!   stores them in `f32` (half the memory, ~1.5× faster numeric factorisation) and relies
//!   on the refinement below, with `f64` residuals, to reach the same backward error;
//!   columns whose refinement stalls (`κ ε_f32 ≳ 1`, the cantilever from ~250k nodes) are
//!   finished by GMRES-IR: GMRES in `f64` on the correction equation, right-preconditioned
//!   by the `f32` factors, restarted from the true residual (Carson & Higham, SIAM J. Sci.
//!   Comput. 40(2):A817–A847, 2018). A column that does not reach the accepted backward
//!   error even so is rejected (NaN, reported as an error); no `f64` factors are computed.
//! - **Solve.** Forward and backward supernodal substitution for a block of right-hand
//!   sides, then iterative refinement against the *full* `K` (not the pruned, scaled copy):
//!   per column, until the normwise backward error (relative residual)
//!   `‖K x − b‖∞ / (‖K‖∞ ‖x‖∞ + ‖b‖∞)` is below `1e-14`, stops halving, or
//!   [`MAX_REFINEMENT_STEPS`] steps were taken. A column whose backward error is still above
//!   [`ACCEPTED_BACKWARD_ERROR`] is overwritten with NaN, which
//!   [`super::Factorisation::solve`] and the contact condensation report as an error.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use faer::dyn_stack::MemStack;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_unit_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::{simplicial, supernodal};
use faer::sparse::linalg::{SymbolicSupernodalParams, amd};
use faer::{Accum, Mat, MatMut, MatRef, Par};
use rayon::prelude::*;

use super::replaced::ReplacedRows;
use super::{FactorPrecision, SolveError, backend, buffer};

mod reach;
mod substitute;
use crate::assembly::SystemMatrix;
use substitute::{Substitution, Tree};

/// Refinement stops after this many corrections.
pub const MAX_REFINEMENT_STEPS: usize = 10;
/// A solution column whose normwise backward error stays above this is rejected.
pub const ACCEPTED_BACKWARD_ERROR: f64 = 1e-12;
/// Refinement stops once the normwise backward error is at most this (~50 ε). On the
/// cantilever, beam and strip the unrefined solutions are at ~1e-17 already: refinement
/// only acts when static pivoting lost accuracy (perturbed pivots, growth).
const TARGET_BACKWARD_ERROR: f64 = 1e-14;
/// Width of the unblocked panels at the leaves of the recursive front LU. A dense
/// 2512 × 2512 front with 1506 pivots (the largest at 250k nodes, β = 1) factorises at
/// 27–28 GFlop/s with 16, 22–25 with 32 or 64, 22 with 4 or 8 (two cores; the previous
/// right-looking LU with panels of 32: 17).
const PANEL: usize = 16;
/// Subtrees with fewer estimated flops than this are factorised by one task.
const PARALLEL_SUBTREE_FLOPS: f64 = 2e7;
/// GMRES-IR: iterations per GMRES cycle (one cycle per refinement step).
const GMRES_RESTART: usize = 20;
/// GMRES-IR: a cycle stops once its residual estimate fell by this factor.
const GMRES_INNER_TOLERANCE: f64 = 1e-6;
/// Dense products with more flops than this use `Par::rayon(2)` (fixed, not the pool size).
const PARALLEL_DENSE_FLOPS: f64 = 2e7;

/// Scalar type of the stored factors: `f64`, or `f32` for mixed-precision refinement
/// (the residuals and the solution stay in `f64`).
pub(super) trait Scalar: faer::traits::RealField + Copy + Send + Sync + 'static {
    fn of(v: f64) -> Self;
    fn get(self) -> f64;
    /// Runs `f` on this thread's reusable front buffer of this type.
    fn with_front<R>(f: impl FnOnce(&std::cell::RefCell<Vec<Self>>) -> R) -> R;
}

thread_local! {
    /// Reused front storage (fresh `m × m` allocations cost a page fault per page).
    static FRONT64: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
    static FRONT32: std::cell::RefCell<Vec<f32>> = const { std::cell::RefCell::new(Vec::new()) };
    /// Reused global-to-front index map `(supernode, local position)` of the front assembly.
    static LOCAL: std::cell::RefCell<Vec<(usize, usize)>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

impl Scalar for f64 {
    fn of(v: f64) -> Self {
        v
    }
    fn get(self) -> f64 {
        self
    }
    fn with_front<R>(f: impl FnOnce(&std::cell::RefCell<Vec<Self>>) -> R) -> R {
        FRONT64.with(f)
    }
}

impl Scalar for f32 {
    #[allow(clippy::cast_possible_truncation)]
    fn of(v: f64) -> Self {
        v as f32
    }
    fn get(self) -> f64 {
        f64::from(self)
    }
    fn with_front<R>(f: impl FnOnce(&std::cell::RefCell<Vec<Self>>) -> R) -> R {
        FRONT32.with(f)
    }
}

/// Supernode relaxation (faer's default): merge two supernodes of at most `.0` columns
/// together when their fraction of explicit zeros stays below `.1`.
const DOF_RELAX: &[(usize, f64)] = &[(4, 1.0), (16, 0.8), (48, 0.1), (usize::MAX, 0.05)];
/// The same thresholds counted in nodes of two DOFs, for the analysis of the node graph.
const NODE_RELAX: &[(usize, f64)] = &[(2, 1.0), (8, 0.8), (24, 0.1), (usize::MAX, 0.05)];

/// Upper-triangular pattern of `P(A + Aᵀ)Pᵀ` (diagonal included), columns sorted.
fn symmetric_pattern(a: &SystemMatrix, perm_inv: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let n = a.n;
    let mut count = vec![0usize; n + 1];
    for c in 0..n {
        for &r in &a.row_idx[a.col_ptr[c]..a.col_ptr[c + 1]] {
            let (i, j) = (perm_inv[r], perm_inv[c]);
            count[i.max(j) + 1] += 1;
        }
    }
    for j in 0..n {
        count[j + 1] += count[j] + 1;
    }
    // count[j] = start of column j with room for the diagonal.
    let mut fill = count.clone();
    let mut rows = vec![0usize; count[n]];
    for j in 0..n {
        rows[fill[j]] = j;
        fill[j] += 1;
    }
    for c in 0..n {
        for &r in &a.row_idx[a.col_ptr[c]..a.col_ptr[c + 1]] {
            let (i, j) = (perm_inv[r], perm_inv[c]);
            let col = i.max(j);
            rows[fill[col]] = i.min(j);
            fill[col] += 1;
        }
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(rows.len());
    col_ptr.push(0);
    for j in 0..n {
        let col = &mut rows[count[j]..count[j + 1]];
        col.sort_unstable();
        let mut last = usize::MAX;
        for &r in col.iter() {
            if r != last {
                row_idx.push(r);
                last = r;
            }
        }
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx)
}

/// The node order of a DOF order that keeps each node's DOFs `2i`, `2i + 1` adjacent and
/// in that order (as nested dissection does); `None` otherwise.
fn node_order(perm: &[usize]) -> Option<Vec<usize>> {
    if perm.len() % 2 != 0 {
        return None;
    }
    perm.chunks(2).map(|p| (p[0] % 2 == 0 && p[1] == p[0] + 1).then_some(p[0] / 2)).collect()
}

/// The node graph of `A + Aᵀ` for a matrix with two DOFs per node (`2i`, `2i + 1`): nodes
/// `i`, `j` are adjacent when any DOF of `i` couples with any DOF of `j`. Its expansion to
/// DOFs (each node a dense 2 × 2 block) contains the DOF pattern of `A + Aᵀ`, with about a
/// quarter of the entries to analyse; built once and reused for every candidate order.
pub(super) struct NodeGraph {
    /// Adjacency of node `i` (itself included): `adj[ptr[i]..ptr[i + 1]]`.
    ptr: Vec<usize>,
    adj: Vec<usize>,
}

impl NodeGraph {
    /// `None` when `a.n` is odd.
    pub(super) fn new(a: &SystemMatrix) -> Option<Self> {
        if a.n % 2 != 0 {
            return None;
        }
        let nn = a.n / 2;
        // Node graph of A, deduplicated per node column with a marker.
        let mut mark = vec![usize::MAX; nn];
        let mut g_ptr = Vec::with_capacity(nn + 1);
        let mut g_adj = Vec::with_capacity(a.row_idx.len() / 3);
        g_ptr.push(0);
        for j in 0..nn {
            mark[j] = j;
            g_adj.push(j);
            for c in [2 * j, 2 * j + 1] {
                for &r in &a.row_idx[a.col_ptr[c]..a.col_ptr[c + 1]] {
                    let i = r / 2;
                    if mark[i] != j {
                        mark[i] = j;
                        g_adj.push(i);
                    }
                }
            }
            g_ptr.push(g_adj.len());
        }
        // Transpose it (structure only), then merge both per node.
        let (t_ptr, t_adj, _) = transpose(nn, &g_ptr, &g_adj, &vec![(); g_adj.len()]);
        mark.fill(usize::MAX);
        let mut ptr = Vec::with_capacity(nn + 1);
        let mut adj = Vec::with_capacity(g_adj.len() + g_adj.len() / 4);
        ptr.push(0);
        for i in 0..nn {
            for &k in g_adj[g_ptr[i]..g_ptr[i + 1]].iter().chain(&t_adj[t_ptr[i]..t_ptr[i + 1]]) {
                if mark[k] != i {
                    mark[k] = i;
                    adj.push(k);
                }
            }
            ptr.push(adj.len());
        }
        Some(Self { ptr, adj })
    }

    /// The approximate-minimum-degree order of the node graph (faer's AMD on the pattern of
    /// `A + Aᵀ` at node level), expanded to DOFs (node `i` gives `2i`, `2i + 1`, adjacent).
    pub(super) fn amd_order(&self) -> Result<Vec<usize>, SolveError> {
        let nn = self.ptr.len() - 1;
        let a = SymbolicSparseColMatRef::new_unsorted_checked(nn, nn, &self.ptr, None, &self.adj);
        let (mut perm, mut inv) = (vec![0usize; nn], vec![0usize; nn]);
        let mut buf = buffer(amd::order_maybe_unsorted_scratch::<usize>(nn, self.adj.len()))?;
        amd::order_maybe_unsorted(
            &mut perm,
            &mut inv,
            a,
            amd::Control::default(),
            MemStack::new(&mut buf),
        )
        .map_err(backend)?;
        Ok(perm.iter().flat_map(|&i| [2 * i, 2 * i + 1]).collect())
    }

    /// Upper-triangular pattern (diagonal included, columns sorted) of the graph permuted
    /// by `node_inv` (`node_inv[i]` = position of node `i`).
    fn pattern(&self, node_inv: &[usize]) -> (Vec<usize>, Vec<usize>) {
        let nn = self.ptr.len() - 1;
        let mut col_ptr = vec![0usize; nn + 1];
        for i in 0..nn {
            let p = node_inv[i];
            for &k in &self.adj[self.ptr[i]..self.ptr[i + 1]] {
                if node_inv[k] <= p {
                    col_ptr[p + 1] += 1;
                }
            }
        }
        for j in 0..nn {
            col_ptr[j + 1] += col_ptr[j];
        }
        let mut fill = col_ptr.clone();
        let mut row_idx = vec![0usize; col_ptr[nn]];
        for i in 0..nn {
            let p = node_inv[i];
            for &k in &self.adj[self.ptr[i]..self.ptr[i + 1]] {
                let q = node_inv[k];
                if q <= p {
                    row_idx[fill[p]] = q;
                    fill[p] += 1;
                }
            }
        }
        for j in 0..nn {
            row_idx[col_ptr[j]..col_ptr[j + 1]].sort_unstable();
        }
        (col_ptr, row_idx)
    }
}

/// Elimination tree (`None` for roots) and column counts of the Cholesky factor of the
/// symmetric pattern.
fn etree_and_counts(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Result<(Vec<isize>, Vec<usize>), SolveError> {
    let a = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let mut etree = vec![0isize; n];
    let mut counts = vec![0usize; n];
    let mut buf = buffer(simplicial::prefactorize_symbolic_cholesky_scratch::<usize>(n, 0))?;
    simplicial::prefactorize_symbolic_cholesky(&mut etree, &mut counts, a, MemStack::new(&mut buf));
    Ok((etree, counts))
}

/// Postorder of a forest given by parents (`< 0` for roots); children in ascending order.
fn postorder(parent: &[isize]) -> Vec<usize> {
    let n = parent.len();
    let mut head = vec![usize::MAX; n];
    let mut next = vec![usize::MAX; n];
    // Insert in descending order so that the lists are ascending.
    for j in (0..n).rev() {
        if let Ok(p) = usize::try_from(parent[j]) {
            next[j] = head[p];
            head[p] = j;
        }
    }
    let mut post = Vec::with_capacity(n);
    let mut stack = Vec::new();
    for root in (0..n).filter(|&j| parent[j] < 0) {
        stack.push(root);
        while let Some(&top) = stack.last() {
            let child = head[top];
            if child == usize::MAX {
                post.push(top);
                stack.pop();
            } else {
                head[top] = next[child];
                stack.push(child);
            }
        }
    }
    post
}

/// `(nnz, Σ c_j²)` of the Cholesky factor of `P(A + Aᵀ)Pᵀ` for the order `perm`.
///
/// With an order that keeps node DOFs together the count is that of the node graph expanded
/// to DOFs (a node column of `c` nodes gives DOF columns of `2c` and `2c − 1` entries), a
/// bound on the DOF-level count that is cheaper to compute.
pub(super) fn symmetric_fill(
    a: &SystemMatrix,
    graph: Option<&NodeGraph>,
    perm: &[usize],
) -> Result<(usize, f64), SolveError> {
    if let (Some(graph), Some(node_perm)) = (graph, node_order(perm)) {
        let inv = super::inverse(&node_perm);
        let (col_ptr, row_idx) = graph.pattern(&inv);
        let (_, counts) = etree_and_counts(node_perm.len(), &col_ptr, &row_idx)?;
        let nnz = counts.iter().map(|&c| 4 * c - 1).sum();
        let flops = counts
            .iter()
            .map(|&c| {
                let c = c as f64;
                4.0 * c * c + (2.0 * c - 1.0) * (2.0 * c - 1.0)
            })
            .sum();
        return Ok((nnz, flops));
    }
    let inv = super::inverse(perm);
    let (col_ptr, row_idx) = symmetric_pattern(a, &inv);
    let (_, counts) = etree_and_counts(a.n, &col_ptr, &row_idx)?;
    Ok((counts.iter().sum(), counts.iter().map(|&c| (c as f64) * (c as f64)).sum()))
}

/// Symbolic analysis of a graph of order `n` given by `pattern(perm_inv)` (upper triangle
/// of the permuted symmetric pattern) in the order `perm`: the postordered order and its
/// relaxed supernodes `(start, end, sorted pattern)`.
#[allow(clippy::type_complexity)]
fn supernodes(
    n: usize,
    perm: &[usize],
    relax: &[(usize, f64)],
    pattern: impl Fn(&[usize]) -> (Vec<usize>, Vec<usize>),
) -> Result<(Vec<usize>, Vec<(usize, usize, Vec<usize>)>), SolveError> {
    // Postorder the elimination tree so that supernodes are contiguous.
    let inv = super::inverse(perm);
    let (col_ptr, row_idx) = pattern(&inv);
    let (etree, _) = etree_and_counts(n, &col_ptr, &row_idx)?;
    let post = postorder(&etree);
    let perm: Vec<usize> = post.iter().map(|&k| perm[k]).collect();
    let perm_inv = super::inverse(&perm);
    let (col_ptr, row_idx) = pattern(&perm_inv);
    let (mut etree, mut counts) = (vec![0isize; n], vec![0usize; n]);
    let a = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
    let mut buf = buffer(
        simplicial::prefactorize_symbolic_cholesky_scratch::<usize>(n, 0)
            .or(supernodal::factorize_supernodal_symbolic_cholesky_scratch::<usize>(n)),
    )?;
    let tree = simplicial::prefactorize_symbolic_cholesky(
        &mut etree,
        &mut counts,
        a,
        MemStack::new(&mut buf),
    );
    let symbolic = supernodal::factorize_supernodal_symbolic_cholesky(
        a,
        tree,
        &counts,
        MemStack::new(&mut buf),
        SymbolicSupernodalParams { relax: Some(relax) },
    )
    .map_err(backend)?;
    let nodes = (0..symbolic.n_supernodes())
        .map(|s| {
            let mut pattern = symbolic.supernode(s).pattern().to_vec();
            pattern.sort_unstable();
            (symbolic.supernode(s).start(), symbolic.supernode_end()[s], pattern)
        })
        .collect();
    Ok((perm, nodes))
}

/// One supernode's structure: columns `start..end` and the rows below them.
#[derive(Debug)]
struct Supernode {
    start: usize,
    end: usize,
    /// Rows of `L` (columns of `U`) beyond the diagonal block, ascending, all `≥ end`.
    pattern: Vec<usize>,
    /// Supernodes whose parent this is, ascending.
    children: Vec<usize>,
    /// Estimated flops of the subtree rooted here.
    subtree_flops: f64,
}

/// The numeric factor of one supernode (`ns` columns, `p` pattern rows, `m = ns + p`).
#[derive(Debug)]
struct NodeFactor<T> {
    /// `m × ns` column-major: `L11` (unit, strictly lower) and `U11` (upper) in the top
    /// `ns` rows, `L21` below.
    lu: Vec<T>,
    /// `ns × p` column-major: `U12`.
    u12: Vec<T>,
    /// Row `j` of the diagonal block was swapped with row `swaps[j] ≥ j` at step `j`.
    swaps: Vec<usize>,
}

/// `K` by rows (compressed sparse rows).
struct RowMatrix {
    row_ptr: Vec<usize>,
    col_idx: Vec<usize>,
    values: Vec<f64>,
}

/// The other orientation of compressed storage with `n` lines (`ptr`, `idx`, `values`):
/// columns from rows or rows from columns, indices ascending within each line (`V = ()`
/// for a structure alone).
pub(super) fn transpose<V: Copy + Default>(
    n: usize,
    ptr: &[usize],
    idx: &[usize],
    values: &[V],
) -> (Vec<usize>, Vec<usize>, Vec<V>) {
    let mut t_ptr = vec![0usize; n + 1];
    for &i in idx {
        t_ptr[i + 1] += 1;
    }
    for i in 0..n {
        t_ptr[i + 1] += t_ptr[i];
    }
    let mut fill = t_ptr.clone();
    let mut t_idx = vec![0usize; idx.len()];
    let mut t_values = vec![V::default(); idx.len()];
    for line in 0..n {
        for k in ptr[line]..ptr[line + 1] {
            let i = idx[k];
            t_idx[fill[i]] = line;
            t_values[fill[i]] = values[k];
            fill[i] += 1;
        }
    }
    (t_ptr, t_idx, t_values)
}

impl RowMatrix {
    fn new(a: &SystemMatrix) -> Self {
        let (row_ptr, col_idx, values) = transpose(a.n, &a.col_ptr, &a.row_idx, &a.values);
        Self { row_ptr, col_idx, values }
    }

    /// `‖K‖∞`, the largest absolute row sum.
    fn norm(&self) -> f64 {
        self.row_ptr
            .windows(2)
            .map(|w| self.values[w[0]..w[1]].iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0f64, f64::max)
    }
}

/// The matrix a [`StaticLu`] refines against: its own copy by rows, or rows replacing some
/// of a base matrix the caller keeps and passes to each solve.
enum Refine {
    Rows(RowMatrix),
    Replaced(ReplacedRows),
}

/// What [`StaticLu::new`] refines against: the matrix `full` (copied by rows after the
/// numeric factorisation), or `base` with the rows `rows` replaced (only the rows are kept;
/// each solve is given `base` again).
pub(super) enum Full<'a> {
    Matrix(&'a SystemMatrix),
    Replaced { base: &'a SystemMatrix, rows: ReplacedRows },
}

/// The matrix of one solve's refinement.
#[derive(Clone, Copy)]
enum Operator<'a> {
    Rows(&'a RowMatrix),
    Replaced(&'a SystemMatrix, &'a ReplacedRows),
}

/// Columns per half above which [`StaticLu`] computes the residuals of a block of columns
/// against replaced rows in two halves on two cores (the active set's update columns come in
/// one block per iteration, 39 columns of 420 042 unknowns on the 10⁴-candidate strip; a
/// block of 8 at 2·10⁶ unknowns stays whole: there its pass through `K` is memory-bound).
const SPLIT_RESIDUAL_COLUMNS: usize = 8;

/// Residuals of some columns, row-major in parts of consecutive columns: `(first column,
/// width, entries)` with entry `(i, first + t)` at `i * width + t`.
struct Residual(Vec<(usize, usize, Vec<f64>)>);

impl Residual {
    /// Copies column `j` into `out`.
    fn copy_column(&self, j: usize, out: &mut [f64]) {
        let (first, w, r) =
            self.0.iter().find(|p| p.0 <= j && j < p.0 + p.1).expect("a column of the residuals");
        for (i, o) in out.iter_mut().enumerate() {
            *o = r[i * w + (j - first)];
        }
    }
}

/// The stored factors, in the precision they were computed in.
enum Factors {
    Double(Vec<NodeFactor<f64>>),
    Single(Vec<NodeFactor<f32>>),
}

/// A multifrontal LU with symmetric structure and static pivoting.
pub(super) struct StaticLu {
    n: usize,
    /// `perm[k]` = original DOF eliminated `k`-th.
    perm: Vec<usize>,
    row_scale: Vec<f64>,
    col_scale: Vec<f64>,
    nodes: Vec<Supernode>,
    /// The assembly tree as the substitutions walk it.
    tree: Tree,
    factors: Factors,
    /// The full, unscaled `K` for refinement (by rows, or rows replacing a base's).
    refine: Refine,
    /// `‖K‖∞`.
    norm: f64,
    /// GMRES iterations per column at most in GMRES-IR.
    gmres_max_iterations: usize,
    /// Pivots replaced by `±tolerance`.
    pub perturbed: usize,
    /// Nonzeros stored in `L` and `U` (diagonal once).
    pub factor_nnz: usize,
    /// Refinement corrections applied so far, over all columns.
    refinement_steps: AtomicUsize,
    /// Columns solved so far.
    columns_solved: AtomicUsize,
    /// Columns finished by GMRES-IR (single-precision factors).
    gmres_columns: AtomicUsize,
    /// GMRES iterations over those columns.
    gmres_iterations: AtomicUsize,
    /// Largest final backward error so far (`f64` bits; non-negative floats order as bits).
    worst_backward_error: AtomicU64,
}

/// Power-of-two row-then-column equilibration of `a` (`D_r`, `D_c`).
fn equilibrate(a: &SystemMatrix) -> (Vec<f64>, Vec<f64>) {
    let n = a.n;
    let pow2 =
        |max: f64| if max > 0.0 && max.is_finite() { (-max.log2().round()).exp2() } else { 1.0 };
    let mut row_max = vec![0.0f64; n];
    for c in 0..n {
        for k in a.col_ptr[c]..a.col_ptr[c + 1] {
            let r = a.row_idx[k];
            row_max[r] = row_max[r].max(a.values[k].abs());
        }
    }
    let row_scale: Vec<f64> = row_max.into_iter().map(pow2).collect();
    let col_scale = (0..n)
        .map(|c| {
            let max = (a.col_ptr[c]..a.col_ptr[c + 1])
                .map(|k| (a.values[k] * row_scale[a.row_idx[k]]).abs())
                .fold(0.0f64, f64::max);
            pow2(max)
        })
        .collect();
    (row_scale, col_scale)
}

/// The scaled, permuted matrix `Â = P D_r K D_c Pᵀ`, each entry stored once, with the
/// elimination step whose front assembles it: `(i, j)` belongs to column `j` when `i` lies
/// in or below `j`'s supernode, otherwise (`i` in an earlier supernode) to row `i`. So line
/// `j` holds `j`'s column part (`rows`, below and inside its diagonal block) followed by its
/// row part (columns beyond its supernode). Indices are `u32` (12 bytes an entry, against 32
/// for both orientations of `(usize, f64)`: at 250k nodes with β = 0, 0.5 GB instead of
/// 1.2 GB).
struct Permuted {
    /// Line starts; line `j` is `start[j]..start[j + 1]`.
    start: Vec<usize>,
    /// End of line `j`'s column part (its row part follows).
    split: Vec<usize>,
    /// Row (column part) or column (row part) of each entry, in elimination order.
    index: Vec<u32>,
    values: Vec<f64>,
}

impl Permuted {
    /// `first_of[j]` is the first column of `j`'s supernode.
    fn new(
        a: &SystemMatrix,
        perm_inv: &[usize],
        first_of: &[usize],
        rs: &[f64],
        cs: &[f64],
    ) -> Result<Self, SolveError> {
        let n = a.n;
        if u32::try_from(n).is_err() {
            return Err(backend(format!("{n} unknowns exceed the static LU's 32-bit indices")));
        }
        // Owner line of entry (i, j) and whether it is in its column part.
        let owner = |i: usize, j: usize| if i >= first_of[j] { (j, true) } else { (i, false) };
        let mut count = vec![[0usize; 2]; n];
        for c in 0..n {
            let j = perm_inv[c];
            for &r in &a.row_idx[a.col_ptr[c]..a.col_ptr[c + 1]] {
                let (line, column_part) = owner(perm_inv[r], j);
                count[line][usize::from(!column_part)] += 1;
            }
        }
        let mut start = vec![0usize; n + 1];
        let mut split = vec![0usize; n];
        for j in 0..n {
            split[j] = start[j] + count[j][0];
            start[j + 1] = split[j] + count[j][1];
        }
        // Fill positions: column parts from `start`, row parts from `split`.
        let mut fill: Vec<[usize; 2]> = (0..n).map(|j| [start[j], split[j]]).collect();
        drop(count);
        let nnz = start[n];
        let (mut index, mut values) = (vec![0u32; nnz], vec![0.0f64; nnz]);
        for c in 0..n {
            let j = perm_inv[c];
            for k in a.col_ptr[c]..a.col_ptr[c + 1] {
                let r = a.row_idx[k];
                let i = perm_inv[r];
                let (line, column_part) = owner(i, j);
                let slot = &mut fill[line][usize::from(!column_part)];
                // Lossless: n fits in u32 (checked above).
                index[*slot] = if column_part { i } else { j } as u32;
                values[*slot] = a.values[k] * rs[r] * cs[c];
                *slot += 1;
            }
        }
        Ok(Self { start, split, index, values })
    }

    /// Line `j`'s column part `(row, value)` and row part `(column, value)`.
    fn line(&self, j: usize) -> [impl Iterator<Item = (usize, f64)> + '_; 2] {
        let part = |range: std::ops::Range<usize>| {
            self.index[range.clone()]
                .iter()
                .map(|&i| i as usize)
                .zip(self.values[range].iter().copied())
        };
        [part(self.start[j]..self.split[j]), part(self.split[j]..self.start[j + 1])]
    }
}

/// The first column of each column's supernode.
fn first_columns(nodes: &[Supernode], n: usize) -> Vec<usize> {
    let mut first = vec![0usize; n];
    for node in nodes {
        first[node.start..node.end].fill(node.start);
    }
    first
}

/// Applies a supernode's row swaps (`swaps[j]`: row `j` swapped with row `swaps[j] ≥ j` at
/// step `j`) to every column of `x`, the rows of its diagonal block.
fn swap_rows<T: Copy>(swaps: &[usize], mut x: MatMut<'_, T>) {
    for (j, &sj) in swaps.iter().enumerate() {
        if sj != j {
            for c in 0..x.ncols() {
                let (a, b) = (x[(j, c)], x[(sj, c)]);
                x[(j, c)] = b;
                x[(sj, c)] = a;
            }
        }
    }
}

fn par_for(flops: f64) -> Par {
    if flops > PARALLEL_DENSE_FLOPS { Par::rayon(2) } else { Par::Seq }
}

/// Factors the first `ns` columns of the `m × m` front `f` in place: `S F11 = L11 U11` with
/// row swaps `S` inside the diagonal block, `L21`, `U12`, and the Schur complement
/// `F22 − L21 U12` in the trailing block. Returns the number of perturbed pivots.
///
/// The tall `m × ns` block is factorised recursively (halves of its columns, unblocked
/// panels of at most [`PANEL`] columns at the leaves), so most of its flops are large
/// matrix products; then `U12 = L11⁻¹ S F12` is one triangular solve and the Schur
/// complement one product.
fn factor_front<T: Scalar>(
    f: &mut [T],
    m: usize,
    ns: usize,
    tol: f64,
    swaps: &mut [usize],
) -> usize {
    let perturbed = factor_columns(f, m, ns, 0..ns, tol, swaps);
    if ns < m {
        let (left, right) = f.split_at_mut(ns * m);
        let l = MatRef::from_column_major_slice(left, m, ns);
        let mut r = MatMut::from_column_major_slice_mut(right, m, m - ns);
        let (mut u12, f22) = r.rb_mut().split_at_row_mut(ns);
        let flops = (ns * ns * (m - ns)) as f64;
        solve_unit_lower_triangular_in_place(l.subrows(0, ns), u12.rb_mut(), par_for(flops));
        let flops = ((m - ns) * (m - ns) * ns) as f64;
        matmul(f22, Accum::Add, l.subrows(ns, m - ns), u12.rb(), T::of(-1.0), par_for(flops));
    }
    perturbed
}

/// LU with row pivoting restricted to rows `< ns` of the columns `cols` of the front (rows
/// above `cols.start` are already final: `U`), recursively; row swaps are applied to whole
/// rows of the front and recorded in `swaps`. Returns the number of perturbed pivots.
fn factor_columns<T: Scalar>(
    f: &mut [T],
    m: usize,
    ns: usize,
    cols: std::ops::Range<usize>,
    tol: f64,
    swaps: &mut [usize],
) -> usize {
    let (j0, j1) = (cols.start, cols.end);
    if j1 - j0 <= PANEL {
        return factor_panel(f, m, ns, j0, j1, tol, swaps);
    }
    // Split at a multiple of the panel width.
    let mid = j0 + ((j1 - j0) / 2).div_ceil(PANEL) * PANEL;
    let mut perturbed = factor_columns(f, m, ns, j0..mid, tol, swaps);
    {
        // Right half: its rows j0..mid of U, then the update of the rows below.
        let (left, right) = f.split_at_mut(mid * m);
        let l = MatRef::from_column_major_slice(&left[j0 * m..], m, mid - j0);
        let mut r = MatMut::from_column_major_slice_mut(&mut right[..(j1 - mid) * m], m, j1 - mid);
        let (top, mut below) = r.rb_mut().split_at_row_mut(mid);
        let mut u = top.subrows_mut(j0, mid - j0);
        let w = mid - j0;
        let flops = (w * w * (j1 - mid)) as f64;
        solve_unit_lower_triangular_in_place(l.subrows(j0, w), u.rb_mut(), par_for(flops));
        let flops = ((m - mid) * w * (j1 - mid)) as f64;
        matmul(
            below.rb_mut(),
            Accum::Add,
            l.subrows(mid, m - mid),
            u.rb(),
            T::of(-1.0),
            par_for(flops),
        );
    }
    perturbed += factor_columns(f, m, ns, mid..j1, tol, swaps);
    perturbed
}

/// Unblocked LU of the columns `j0..j1` (rank-1 updates inside the panel only).
fn factor_panel<T: Scalar>(
    f: &mut [T],
    m: usize,
    ns: usize,
    j0: usize,
    j1: usize,
    tol: f64,
    swaps: &mut [usize],
) -> usize {
    let mut perturbed = 0;
    for j in j0..j1 {
        // Pivot search restricted to the diagonal block's rows.
        let col = &f[j * m..j * m + ns];
        let mut imax = j;
        let mut max = col[j].get().abs();
        for (i, v) in col.iter().enumerate().skip(j + 1) {
            if v.get().abs() > max {
                max = v.get().abs();
                imax = i;
            }
        }
        swaps[j] = imax;
        if imax != j {
            for c in 0..m {
                f.swap(c * m + j, c * m + imax);
            }
        }
        let mut pivot = f[j * m + j].get();
        if pivot.abs() < tol || !pivot.is_finite() {
            pivot = if pivot < 0.0 { -tol } else { tol };
            f[j * m + j] = T::of(pivot);
            perturbed += 1;
        }
        let inv = T::of(pivot.recip());
        for v in &mut f[j * m + j + 1..j * m + m] {
            *v *= inv;
        }
        let (left, right) = f.split_at_mut((j + 1) * m);
        let lj = &left[j * m + j + 1..j * m + m];
        for c in j + 1..j1 {
            let colc = &mut right[(c - j - 1) * m..(c - j) * m];
            let u = colc[j];
            if u.get() != 0.0 {
                for (x, l) in colc[j + 1..].iter_mut().zip(lj) {
                    *x -= u * l;
                }
            }
        }
    }
    perturbed
}

/// Context shared by the front computations.
struct Numeric<'a, T> {
    nodes: &'a [Supernode],
    a: &'a Permuted,
    tol: f64,
    factors: Vec<OnceLock<NodeFactor<T>>>,
    perturbed: AtomicUsize,
}

impl<T: Scalar> Numeric<'_, T> {
    /// Assembles, factors and stores supernode `s` from its children's contribution blocks
    /// (in the order of `nodes[s].children`); returns its own contribution block.
    fn front(&self, s: usize, child_blocks: Vec<Vec<T>>) -> Result<Vec<T>, SolveError> {
        let node = &self.nodes[s];
        let ns = node.end - node.start;
        let p = node.pattern.len();
        let m = ns + p;
        let zero = T::of(0.0);
        // A per-thread front buffer, taken out of its slot for the duration (a nested
        // rayon task on this thread then finds the slot empty and allocates its own).
        let mut buf = T::with_front(|slot| std::mem::take(&mut *slot.borrow_mut()));
        if buf.len() < m * m {
            buf = vec![zero; m * m];
        } else {
            buf[..m * m].fill(zero);
        }
        let f = &mut buf[..m * m];
        let missing = || backend(format!("entry outside the symbolic structure of supernode {s}"));
        // Global index → position in this front, stamped with the supernode (stale entries
        // of other fronts are recognised, so an entry outside the structure is an error).
        let mut map = LOCAL.with(|slot| std::mem::take(&mut *slot.borrow_mut()));
        map.resize(self.a.split.len(), (usize::MAX, 0));
        for (l, g) in (node.start..node.end).chain(node.pattern.iter().copied()).enumerate() {
            map[g] = (s, l);
        }
        let at = |g: usize| match map[g] {
            (t, l) if t == s => Some(l),
            _ => None,
        };
        for j in node.start..node.end {
            let lj = j - node.start;
            let [column, row] = self.a.line(j);
            for (i, v) in column {
                let li = at(i).ok_or_else(missing)?;
                f[lj * m + li] += T::of(v);
            }
            for (c, v) in row {
                let lc = at(c).ok_or_else(missing)?;
                f[lc * m + lj] += T::of(v);
            }
        }
        LOCAL.with(|slot| *slot.borrow_mut() = map);
        for (&c, cb) in node.children.iter().zip(&child_blocks) {
            let child = &self.nodes[c];
            let pc = child.pattern.len();
            let mut map = Vec::with_capacity(pc);
            let mut q = 0;
            for &g in &child.pattern {
                if g < node.end {
                    map.push(g.checked_sub(node.start).ok_or_else(missing)?);
                } else {
                    while q < p && node.pattern[q] < g {
                        q += 1;
                    }
                    if q == p || node.pattern[q] != g {
                        return Err(missing());
                    }
                    map.push(ns + q);
                }
            }
            for (b, &lb) in map.iter().enumerate() {
                let src = &cb[b * pc..(b + 1) * pc];
                let dst = &mut f[lb * m..(lb + 1) * m];
                for (&la, &v) in map.iter().zip(src) {
                    dst[la] += v;
                }
            }
        }
        let mut swaps = vec![0usize; ns];
        let perturbed = factor_front(f, m, ns, self.tol, &mut swaps);
        if perturbed > 0 {
            self.perturbed.fetch_add(perturbed, Ordering::Relaxed);
        }
        let lu = f[..m * ns].to_vec();
        let mut u12 = Vec::with_capacity(ns * p);
        drop(child_blocks);
        let mut cb = Vec::with_capacity(p * p);
        for c in ns..m {
            u12.extend_from_slice(&f[c * m..c * m + ns]);
            cb.extend_from_slice(&f[c * m + ns..(c + 1) * m]);
        }
        T::with_front(|slot| {
            let mut slot = slot.borrow_mut();
            if slot.len() < buf.len() {
                *slot = buf;
            }
        });
        if self.factors[s].set(NodeFactor { lu, u12, swaps }).is_err() {
            return Err(backend(format!("supernode {s} factorised twice")));
        }
        Ok(cb)
    }

    /// Factorises the subtree rooted at `s` with one task (postorder, explicit stack).
    fn subtree_sequential(&self, s: usize, first: usize) -> Result<Vec<T>, SolveError> {
        let mut stack: Vec<Vec<T>> = Vec::new();
        for t in first..=s {
            let nc = self.nodes[t].children.len();
            if stack.len() < nc {
                return Err(backend("assembly tree is not postordered"));
            }
            let blocks = stack.split_off(stack.len() - nc);
            stack.push(self.front(t, blocks)?);
        }
        match (stack.pop(), stack.is_empty()) {
            (Some(cb), true) => Ok(cb),
            _ => Err(backend("assembly tree is not postordered")),
        }
    }

    /// Factorises the subtree rooted at `s`, independent subtrees in parallel.
    fn subtree(&self, s: usize, first: &[usize], parallel: bool) -> Result<Vec<T>, SolveError> {
        let big = |t: usize| parallel && self.nodes[t].subtree_flops > PARALLEL_SUBTREE_FLOPS;
        if !big(s) {
            return self.subtree_sequential(s, first[s]);
        }
        // Walk down the chain of single children, then fan out at its bottom.
        let mut chain = vec![s];
        let mut t = s;
        while self.nodes[t].children.len() == 1 && big(self.nodes[t].children[0]) {
            t = self.nodes[t].children[0];
            chain.push(t);
        }
        let bottom = chain.pop().unwrap_or(s);
        let blocks: Vec<Vec<T>> = self.nodes[bottom]
            .children
            .par_iter()
            .map(|&c| self.subtree(c, first, parallel))
            .collect::<Result<_, _>>()?;
        let mut cb = self.front(bottom, blocks)?;
        while let Some(t) = chain.pop() {
            cb = self.front(t, vec![cb])?;
        }
        Ok(cb)
    }
}

/// The numeric factorisation of `a` (scaled and permuted) over the supernodes `nodes` in
/// precision `T`: the factors and the number of perturbed pivots.
fn factorise<T: Scalar>(
    nodes: &[Supernode],
    first: &[usize],
    a: &Permuted,
    tol: f64,
    parallel: bool,
) -> Result<(Vec<NodeFactor<T>>, usize), SolveError> {
    let ns = nodes.len();
    let numeric = Numeric::<T> {
        nodes,
        a,
        tol,
        factors: (0..ns).map(|_| OnceLock::new()).collect(),
        perturbed: AtomicUsize::new(0),
    };
    let roots: Vec<usize> = (0..ns).filter(|&s| nodes[s].pattern.is_empty()).collect();
    let blocks: Vec<Vec<T>> =
        roots.par_iter().map(|&r| numeric.subtree(r, first, parallel)).collect::<Result<_, _>>()?;
    if blocks.iter().any(|b| !b.is_empty()) {
        return Err(backend("a root supernode has a contribution block"));
    }
    let perturbed = numeric.perturbed.load(Ordering::Relaxed);
    let factors = numeric
        .factors
        .into_iter()
        .map(|f| f.into_inner().ok_or_else(|| backend("a supernode was not factorised")))
        .collect::<Result<_, _>>()?;
    Ok((factors, perturbed))
}

/// The refinement record of a [`StaticLu`] ([`StaticLu::refinement`]).
pub(super) struct Refinement {
    /// Refinement corrections over all columns.
    pub steps: usize,
    /// Columns solved.
    pub columns: usize,
    /// Columns finished by GMRES-IR.
    pub gmres_columns: usize,
    /// GMRES iterations over them.
    pub gmres_iterations: usize,
    /// Largest final backward error.
    pub worst_backward_error: f64,
}

/// Settings of [`StaticLu::new`].
pub(super) struct Settings {
    /// Pivot tolerance of the double-precision factors; single precision uses at least
    /// `√ε_f32`.
    pub pivot_tolerance: f64,
    pub parallel: bool,
    pub precision: FactorPrecision,
    /// GMRES iterations per column at most in GMRES-IR.
    pub gmres_max_iterations: usize,
}

impl StaticLu {
    /// Analyses and factorises `pruned` (the matrix to factorise) in the order `perm`
    /// (`perm[k]` = DOF eliminated `k`-th); `full` is kept for refinement, copied by rows
    /// after the numeric factorisation (or its replaced rows only). With `graph`
    /// (the node graph of `pruned`) and an order that keeps node DOFs together, the
    /// analysis runs on the node graph.
    pub(super) fn new(
        full: Full<'_>,
        pruned: SystemMatrix,
        graph: Option<NodeGraph>,
        perm: &[usize],
        settings: Settings,
    ) -> Result<(Self, f64, f64), SolveError> {
        let n = pruned.n;
        let t = std::time::Instant::now();
        // The node graph when the order keeps node DOFs together (a quarter of the entries),
        // expanded to DOFs; the DOF graph otherwise.
        let (perm, raw) = match (graph.as_ref(), node_order(perm)) {
            (Some(graph), Some(node_perm)) => {
                let (node_perm, raw) =
                    supernodes(n / 2, &node_perm, NODE_RELAX, |inv| graph.pattern(inv))?;
                let perm = node_perm.iter().flat_map(|&i| [2 * i, 2 * i + 1]).collect();
                let raw = raw
                    .into_iter()
                    .map(|(start, end, pattern)| {
                        let pattern = pattern.iter().flat_map(|&g| [2 * g, 2 * g + 1]).collect();
                        (2 * start, 2 * end, pattern)
                    })
                    .collect();
                (perm, raw)
            }
            _ => supernodes(n, perm, DOF_RELAX, |inv| symmetric_pattern(&pruned, inv))?,
        };
        drop(graph);
        let perm_inv = super::inverse(&perm);
        let ns = raw.len();
        let mut col_to_node = vec![0usize; n];
        let mut nodes: Vec<Supernode> = raw
            .into_iter()
            .enumerate()
            .map(|(s, (start, end, pattern))| {
                col_to_node[start..end].fill(s);
                Supernode { start, end, pattern, children: Vec::new(), subtree_flops: 0.0 }
            })
            .collect();
        let mut first = (0..ns).collect::<Vec<usize>>();
        for s in 0..ns {
            let (w, p) = ((nodes[s].end - nodes[s].start) as f64, nodes[s].pattern.len() as f64);
            // Dense LU of the diagonal block, L21/U12 and the Schur update.
            nodes[s].subtree_flops += 2.0 / 3.0 * w * w * w + 2.0 * w * w * p + 2.0 * w * p * p;
            if let Some(&g) = nodes[s].pattern.first() {
                let parent = col_to_node[g];
                if parent <= s {
                    return Err(backend("supernodal tree is not postordered"));
                }
                nodes[parent].children.push(s);
                let f = nodes[s].subtree_flops;
                nodes[parent].subtree_flops += f;
                first[parent] = first[parent].min(first[s]);
            }
        }
        let symbolic_seconds = t.elapsed().as_secs_f64();

        let t = std::time::Instant::now();
        let (row_scale, col_scale) = equilibrate(&pruned);
        let permuted =
            Permuted::new(&pruned, &perm_inv, &first_columns(&nodes, n), &row_scale, &col_scale)?;
        // Peak memory is reached at the top of the assembly tree: keep only what is needed.
        drop(pruned);
        let (tol, parallel) = (settings.pivot_tolerance, settings.parallel);
        let (factors, perturbed) = match settings.precision {
            FactorPrecision::Double => {
                let (f, p) = factorise::<f64>(&nodes, &first, &permuted, tol, parallel)?;
                (Factors::Double(f), p)
            }
            FactorPrecision::Mixed => {
                let tol = tol.max(f64::from(f32::EPSILON).sqrt());
                let (f, p) = factorise::<f32>(&nodes, &first, &permuted, tol, parallel)?;
                (Factors::Single(f), p)
            }
        };
        drop(permuted);
        let (refine, norm) = match full {
            Full::Matrix(a) => {
                let rows = RowMatrix::new(a);
                let norm = rows.norm();
                (Refine::Rows(rows), norm)
            }
            Full::Replaced { base, rows } => {
                let norm = rows.norm(base);
                (Refine::Replaced(rows), norm)
            }
        };
        let factor_nnz = nodes
            .iter()
            .map(|s| {
                let (w, p) = (s.end - s.start, s.pattern.len());
                w * w + 2 * w * p
            })
            .sum();
        let numeric_seconds = t.elapsed().as_secs_f64();
        let lu = Self {
            n,
            perm,
            row_scale,
            col_scale,
            tree: Tree::new(&nodes, first, parallel),
            nodes,
            factors,
            norm,
            refine,
            gmres_max_iterations: settings.gmres_max_iterations,
            perturbed,
            factor_nnz,
            refinement_steps: AtomicUsize::new(0),
            columns_solved: AtomicUsize::new(0),
            gmres_columns: AtomicUsize::new(0),
            gmres_iterations: AtomicUsize::new(0),
            worst_backward_error: AtomicU64::new(0),
        };
        Ok((lu, symbolic_seconds, numeric_seconds))
    }

    /// Number of supernodes.
    pub(super) fn supernodes(&self) -> usize {
        self.nodes.len()
    }

    /// Precision of the stored factors.
    pub(super) fn precision(&self) -> FactorPrecision {
        match self.factors {
            Factors::Double(_) => FactorPrecision::Double,
            Factors::Single(_) => FactorPrecision::Mixed,
        }
    }

    /// The refinement record so far.
    pub(super) fn refinement(&self) -> Refinement {
        Refinement {
            steps: self.refinement_steps.load(Ordering::Relaxed),
            columns: self.columns_solved.load(Ordering::Relaxed),
            gmres_columns: self.gmres_columns.load(Ordering::Relaxed),
            gmres_iterations: self.gmres_iterations.load(Ordering::Relaxed),
            worst_backward_error: f64::from_bits(self.worst_backward_error.load(Ordering::Relaxed)),
        }
    }

    /// Solves `K X = B` with the stored factors only (no refinement); `x` holds `B` on entry.
    pub(super) fn substitute_in_place(&self, x: MatMut<'_, f64>) {
        match &self.factors {
            Factors::Double(f) => self.substitute(f, x),
            Factors::Single(f) => self.substitute(f, x),
        }
    }

    /// Solves `K X = B` with the factors `factors` only (no refinement); `x` holds `B` on
    /// entry.
    fn substitute<T: Scalar>(&self, factors: &[NodeFactor<T>], mut x: MatMut<'_, f64>) {
        let (n, k) = (self.n, x.ncols());
        // w = P D_r b
        let mut w = Mat::<T>::zeros(n, k);
        for j in 0..k {
            let (wj, xj) = (w.col_as_slice_mut(j), x.rb().col(j));
            for (i, &p) in self.perm.iter().enumerate() {
                wj[i] = T::of(xj[p] * self.row_scale[p]);
            }
        }
        Substitution { nodes: &self.nodes, factors, tree: &self.tree }.run(w.as_mut());
        // x = D_c Pᵀ w
        for j in 0..k {
            let wj = w.col_as_slice(j);
            let mut xj = x.rb_mut().col_mut(j);
            for (i, &p) in self.perm.iter().enumerate() {
                xj[p] = wj[i].get() * self.col_scale[p];
            }
        }
    }

    /// Residuals `b − K x` of the given columns ([`Residual`]) and their normwise backward
    /// errors `‖b − K x‖∞ / (‖K‖∞ ‖x‖∞ + ‖b‖∞)` (NaN when not finite).
    fn residuals(
        &self,
        op: Operator<'_>,
        b: MatRef<'_, f64>,
        x: MatRef<'_, f64>,
        cols: &[usize],
    ) -> (Residual, Vec<f64>) {
        let (n, ka) = (self.n, cols.len());
        // ∞-norms, NaN-propagating.
        let max = |m: f64, v: f64| if m.is_nan() || v.is_nan() { f64::NAN } else { m.max(v.abs()) };
        let a = match op {
            Operator::Rows(a) => a,
            Operator::Replaced(base, rows) => {
                return self.replaced_residuals(base, rows, b, x, cols);
            }
        };
        // Row-major copies of x and b; their ∞-norms.
        let mut xt = vec![0.0f64; n * ka];
        let mut res = vec![0.0f64; n * ka];
        let (mut xn, mut bn) = (vec![0.0f64; ka], vec![0.0f64; ka]);
        for (j, &c) in cols.iter().enumerate() {
            for (i, (&xv, &bv)) in x.col(c).iter().zip(b.col(c).iter()).enumerate() {
                xt[i * ka + j] = xv;
                res[i * ka + j] = bv;
                xn[j] = max(xn[j], xv);
                bn[j] = max(bn[j], bv);
            }
        }
        let mut rn = vec![0.0f64; ka];
        if ka == 1 {
            // One column (every solve of the active set's iterations): the same operations in
            // the same order as below, without a slice per entry.
            for (r, s) in res.iter_mut().enumerate() {
                let mut v = *s;
                for k in a.row_ptr[r]..a.row_ptr[r + 1] {
                    v -= a.values[k] * xt[a.col_idx[k]];
                }
                *s = v;
                rn[0] = max(rn[0], v);
            }
        } else {
            for r in 0..n {
                let row = &mut res[r * ka..(r + 1) * ka];
                for k in a.row_ptr[r]..a.row_ptr[r + 1] {
                    let (c, v) = (a.col_idx[k], a.values[k]);
                    for (s, &xc) in row.iter_mut().zip(&xt[c * ka..(c + 1) * ka]) {
                        *s -= v * xc;
                    }
                }
                for (m, &v) in rn.iter_mut().zip(row.iter()) {
                    *m = max(*m, v);
                }
            }
        }
        let berr = self.backward_errors(&rn, &xn, &bn);
        (Residual(vec![(0, ka, res)]), berr)
    }

    /// [`Self::residuals`] against `base` with `rows` replaced ([`Operator::Replaced`]).
    fn replaced_residuals(
        &self,
        base: &SystemMatrix,
        rows: &ReplacedRows,
        b: MatRef<'_, f64>,
        x: MatRef<'_, f64>,
        cols: &[usize],
    ) -> (Residual, Vec<f64>) {
        let (n, ka) = (self.n, cols.len());
        let max = |m: f64, v: f64| if m.is_nan() || v.is_nan() { f64::NAN } else { m.max(v.abs()) };
        // Row-major copies of x and b for the columns `js` of `cols`, their residuals
        // (column by column through `base`: each row's terms in the same order as the
        // row-wise products of [`Self::residuals`]) and the three norms of each column.
        let part = |js: std::ops::Range<usize>| {
            let w = js.len();
            let mut xt = vec![0.0f64; n * w];
            let mut res = vec![0.0f64; n * w];
            let (mut xn, mut bn, mut rn) = (vec![0.0f64; w], vec![0.0f64; w], vec![0.0f64; w]);
            for (t, &c) in cols[js].iter().enumerate() {
                for (i, (&xv, &bv)) in x.col(c).iter().zip(b.col(c).iter()).enumerate() {
                    xt[i * w + t] = xv;
                    res[i * w + t] = bv;
                    xn[t] = max(xn[t], xv);
                    bn[t] = max(bn[t], bv);
                }
            }
            rows.subtract_product(base, &xt, &mut res, w);
            drop(xt);
            for row in res.chunks_exact(w.max(1)) {
                for (m, &v) in rn.iter_mut().zip(row) {
                    *m = max(*m, v);
                }
            }
            (res, xn, bn, rn)
        };
        // A block of many columns (the update columns of the active set, one block per
        // iteration) in two halves on two cores: the same operations on every entry.
        let parts = if ka >= 2 * SPLIT_RESIDUAL_COLUMNS {
            let h = ka.div_ceil(2);
            let (a, b) = rayon::join(|| part(0..h), || part(h..ka));
            vec![(0, h, a), (h, ka - h, b)]
        } else {
            vec![(0, ka, part(0..ka))]
        };
        let (mut xn, mut bn, mut rn) = (Vec::new(), Vec::new(), Vec::new());
        let mut out = Vec::with_capacity(parts.len());
        for (first, w, (res, x_norm, b_norm, r_norm)) in parts {
            xn.extend(x_norm);
            bn.extend(b_norm);
            rn.extend(r_norm);
            out.push((first, w, res));
        }
        (Residual(out), self.backward_errors(&rn, &xn, &bn))
    }

    /// `‖r‖∞ / (‖K‖∞ ‖x‖∞ + ‖b‖∞)` per column from the three norms (NaN when not finite).
    fn backward_errors(&self, rn: &[f64], xn: &[f64], bn: &[f64]) -> Vec<f64> {
        (0..rn.len())
            .map(|j| {
                let den = self.norm * xn[j] + bn[j];
                if rn[j] == 0.0 {
                    0.0
                } else if den > 0.0 {
                    rn[j] / den
                } else {
                    f64::NAN
                }
            })
            .collect()
    }

    /// Solves `K X = B` with the factors `factors` followed by iterative refinement of every
    /// column (`x` holds `B` on entry, `b` is a copy of it). Returns the columns whose
    /// backward error stayed above [`ACCEPTED_BACKWARD_ERROR`] and the largest backward
    /// error of the others.
    fn solve_refined<T: Scalar>(
        &self,
        op: Operator<'_>,
        factors: &[NodeFactor<T>],
        b: MatRef<'_, f64>,
        mut x: MatMut<'_, f64>,
    ) -> (Vec<usize>, f64) {
        self.substitute(factors, x.rb_mut());
        let k = x.ncols();
        let mut active: Vec<usize> = (0..k).collect();
        let mut last = vec![f64::INFINITY; k];
        let mut steps = 0;
        let mut worst = 0.0f64;
        let mut rejected = Vec::new();
        for step in 0..=MAX_REFINEMENT_STEPS {
            if active.is_empty() {
                break;
            }
            let (r, berr) = self.residuals(op, b, x.rb(), &active);
            let mut keep = Vec::with_capacity(active.len());
            let mut keep_cols = Vec::with_capacity(active.len());
            for (j, (&c, &e)) in active.iter().zip(&berr).enumerate() {
                let go =
                    e > TARGET_BACKWARD_ERROR && 2.0 * e <= last[c] && step < MAX_REFINEMENT_STEPS;
                last[c] = e;
                if go {
                    keep.push(c);
                    keep_cols.push(j);
                } else if e.is_nan() || e > ACCEPTED_BACKWARD_ERROR {
                    rejected.push(c);
                } else {
                    worst = worst.max(e);
                }
            }
            if keep.is_empty() {
                break;
            }
            // Corrections for the columns that go on.
            let mut d = Mat::<f64>::zeros(self.n, keep.len());
            for (t, &j) in keep_cols.iter().enumerate() {
                r.copy_column(j, d.col_as_slice_mut(t));
            }
            drop(r);
            self.substitute(factors, d.as_mut());
            for (t, &c) in keep.iter().enumerate() {
                let mut xc = x.rb_mut().col_mut(c);
                for (i, &v) in d.col_as_slice(t).iter().enumerate() {
                    xc[i] += v;
                }
            }
            steps += keep.len();
            active = keep;
        }
        self.refinement_steps.fetch_add(steps, Ordering::Relaxed);
        rejected.sort_unstable();
        (rejected, worst)
    }

    /// `y = K x` with the kept, unscaled `K`.
    fn mul(op: Operator<'_>, x: &[f64], y: &mut [f64]) {
        let a = match op {
            Operator::Rows(a) => a,
            Operator::Replaced(base, rows) => return rows.product(base, x, y),
        };
        for (r, yr) in y.iter_mut().enumerate() {
            let mut s = 0.0;
            for k in a.row_ptr[r]..a.row_ptr[r + 1] {
                s += a.values[k] * x[a.col_idx[k]];
            }
            *yr = s;
        }
    }

    /// One application of the preconditioner: `z = (L U)⁻¹ v` with the stored factors.
    fn precondition<T: Scalar>(&self, factors: &[NodeFactor<T>], z: &mut [f64]) {
        let n = self.n;
        self.substitute(factors, MatMut::from_column_major_slice_mut(z, n, 1));
    }

    /// GMRES-IR for one column (docs/dev/performance.md, "Mixed precision"): iterative
    /// refinement whose correction equation `K d = r` (true residual `r = b − K x` in `f64`)
    /// is solved by flexible GMRES in `f64`, right-preconditioned by the stored factors
    /// (`2 · GMRES_RESTART` vectors of `n` doubles at most), to a relative
    /// residual of [`GMRES_INNER_TOLERANCE`] or [`GMRES_RESTART`] iterations. Stops when the
    /// normwise backward error of `x` is at most `TARGET_BACKWARD_ERROR`, when it stops
    /// falling, or after `gmres_max_iterations` (`super::FactorOptions`) GMRES iterations. Returns the backward error
    /// reached and the GMRES iterations taken; `x` holds the starting guess on entry (a NaN
    /// guess starts from zero).
    fn gmres_ir<T: Scalar>(
        &self,
        op: Operator<'_>,
        factors: &[NodeFactor<T>],
        b: &[f64],
        x: &mut [f64],
    ) -> (f64, usize) {
        let n = self.n;
        if x.iter().any(|v| !v.is_finite()) {
            x.fill(0.0);
        }
        let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        let bn = inf(b);
        let mut r = vec![0.0; n];
        let residual = |x: &[f64], r: &mut Vec<f64>| {
            Self::mul(op, x, r);
            for (ri, bi) in r.iter_mut().zip(b) {
                *ri = bi - *ri;
            }
            let den = self.norm * inf(x) + bn;
            let rn = inf(r);
            if rn == 0.0 {
                0.0
            } else if den > 0.0 && rn.is_finite() {
                rn / den
            } else {
                f64::NAN
            }
        };
        let mut berr = residual(x, &mut r);
        let mut iterations = 0;
        let mut best = (if berr.is_nan() { f64::INFINITY } else { berr }, x.to_vec());
        while berr > TARGET_BACKWARD_ERROR
            && iterations < self.gmres_max_iterations
            && berr.is_finite()
        {
            // Arnoldi with modified Gram–Schmidt on K M⁻¹, Givens rotations for the
            // least-squares problem (Saad, Iterative Methods for Sparse Linear Systems, §6.5).
            let beta = r.iter().map(|v| v * v).sum::<f64>().sqrt();
            let m = GMRES_RESTART;
            let mut v: Vec<Vec<f64>> = Vec::with_capacity(m + 1);
            v.push(r.iter().map(|ri| ri / beta).collect());
            let mut h = vec![vec![0.0; m]; m + 1];
            let (mut cs, mut sn) = (vec![0.0; m], vec![0.0; m]);
            let mut g = vec![0.0; m + 1];
            g[0] = beta;
            let mut k = 0;
            // Flexible GMRES: the preconditioned vectors are kept (the single-precision
            // substitution is not exactly linear, so `M⁻¹ (V y)` ≠ `Σ y_j M⁻¹ v_j` to
            // `κ ε_f32`, which is what makes plain refinement stall).
            let mut zs: Vec<Vec<f64>> = Vec::with_capacity(m);
            let mut w = vec![0.0; n];
            while k < m && iterations < self.gmres_max_iterations {
                let mut z = v[k].clone();
                self.precondition(factors, &mut z);
                Self::mul(op, &z, &mut w);
                zs.push(z);
                iterations += 1;
                for (i, vi) in v.iter().enumerate() {
                    let hik = w.iter().zip(vi).map(|(a, b)| a * b).sum::<f64>();
                    h[i][k] = hik;
                    for (wj, vj) in w.iter_mut().zip(vi) {
                        *wj -= hik * vj;
                    }
                }
                let hn = w.iter().map(|a| a * a).sum::<f64>().sqrt();
                h[k + 1][k] = hn;
                for i in 0..k {
                    let t = cs[i] * h[i][k] + sn[i] * h[i + 1][k];
                    h[i + 1][k] = -sn[i] * h[i][k] + cs[i] * h[i + 1][k];
                    h[i][k] = t;
                }
                let d = h[k][k].hypot(h[k + 1][k]);
                if d == 0.0 || !d.is_finite() {
                    break;
                }
                (cs[k], sn[k]) = (h[k][k] / d, h[k + 1][k] / d);
                h[k][k] = d;
                h[k + 1][k] = 0.0;
                g[k + 1] = -sn[k] * g[k];
                g[k] *= cs[k];
                k += 1;
                if g[k].abs() <= GMRES_INNER_TOLERANCE * beta || hn == 0.0 {
                    break;
                }
                v.push(w.iter().map(|a| a / hn).collect());
            }
            if k == 0 {
                break;
            }
            // y = H⁻¹ g (upper triangular k × k), x += Z y.
            let mut y = vec![0.0; k];
            for i in (0..k).rev() {
                let s = (i + 1..k).fold(g[i], |s, j| s - h[i][j] * y[j]);
                y[i] = s / h[i][i];
            }
            drop(v);
            for (zi, yi) in zs.iter().zip(&y) {
                for (xj, zj) in x.iter_mut().zip(zi) {
                    *xj += yi * zj;
                }
            }
            drop(zs);
            let previous = berr;
            berr = residual(x, &mut r);
            if berr.is_finite() && berr < best.0 {
                best = (berr, x.to_vec());
            }
            // Stop when a whole cycle no longer gains a factor of two.
            if berr.is_nan() || berr > 0.5 * previous {
                break;
            }
        }
        if berr.is_nan() || berr > best.0 {
            x.copy_from_slice(&best.1);
            berr = best.0;
        }
        (berr, iterations)
    }

    /// Solves `K X = B` in place with iterative refinement (see the module documentation);
    /// with single-precision factors, columns that refinement does not bring to the accepted
    /// backward error are finished by GMRES-IR ([`Self::gmres_ir`]); rejected columns are set
    /// to NaN. `base` is the base matrix of a factorisation of replaced rows
    /// ([`Full::Replaced`]; without it every column is rejected), ignored otherwise.
    pub(super) fn solve_in_place(&self, mut rhs: MatMut<'_, f64>, base: Option<&SystemMatrix>) {
        let k = rhs.ncols();
        if k == 0 {
            return;
        }
        let op = match (&self.refine, base) {
            (Refine::Rows(a), _) => Operator::Rows(a),
            (Refine::Replaced(rows), Some(base)) if base.n == self.n => {
                Operator::Replaced(base, rows)
            }
            (Refine::Replaced(_), _) => {
                rhs.fill(f64::NAN);
                self.columns_solved.fetch_add(k, Ordering::Relaxed);
                self.worst_backward_error.fetch_max(f64::INFINITY.to_bits(), Ordering::Relaxed);
                return;
            }
        };
        let b = rhs.rb().to_owned();
        let (mut rejected, mut worst) = match &self.factors {
            Factors::Double(f) => self.solve_refined(op, f, b.as_ref(), rhs.rb_mut()),
            Factors::Single(f) => self.solve_refined(op, f, b.as_ref(), rhs.rb_mut()),
        };
        if let Factors::Single(f) = &self.factors
            && !rejected.is_empty()
        {
            let mut again = Vec::new();
            let mut iterations = 0;
            for &c in &rejected {
                let mut x: Vec<f64> = rhs.rb().col(c).iter().copied().collect();
                let bc: Vec<f64> = b.col(c).iter().copied().collect();
                let (e, it) = self.gmres_ir(op, f, &bc, &mut x);
                iterations += it;
                if e.is_nan() || e > ACCEPTED_BACKWARD_ERROR {
                    again.push(c);
                } else {
                    worst = worst.max(e);
                    for (i, v) in x.into_iter().enumerate() {
                        rhs[(i, c)] = v;
                    }
                }
            }
            self.gmres_columns.fetch_add(rejected.len(), Ordering::Relaxed);
            self.gmres_iterations.fetch_add(iterations, Ordering::Relaxed);
            rejected = again;
        }
        for &c in &rejected {
            rhs.rb_mut().col_mut(c).fill(f64::NAN);
        }
        if !rejected.is_empty() {
            worst = f64::INFINITY;
        }
        self.columns_solved.fetch_add(k, Ordering::Relaxed);
        self.worst_backward_error.fetch_max(worst.to_bits(), Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn postorder_lists_children_before_parents() {
        // 0 -> 2, 1 -> 2, 3 -> 4, 2 -> 4
        let parent = [2isize, 2, 4, 4, -1];
        let post = postorder(&parent);
        assert_eq!(post, vec![0, 1, 2, 3, 4]);
        let parent = [-1isize, 0, 0];
        assert_eq!(postorder(&parent), vec![1, 2, 0]);
    }

    #[test]
    fn front_factorisation_matches_a_dense_solve() {
        // Check S F11 = L11 U11, L21, U12 and the Schur complement against the input: a 5 × 5
        // front with 3 supernode columns (one unblocked panel), and fronts wide enough for
        // the recursive column split (several panels, with and without pattern rows).
        for (m, ns) in [(5, 3), (150, 100), (97, 97), (70, 40)] {
            let a: Vec<f64> = (0..m * m)
                .map(|k| ((k * 37 % 11) as f64 - 5.0) + if k % (m + 1) == 0 { 9.0 } else { 0.0 })
                .collect();
            let mut f = a.clone();
            let mut swaps = vec![0; ns];
            let perturbed = factor_front(&mut f, m, ns, 1e-12, &mut swaps);
            assert_eq!(perturbed, 0);
            // Rebuild S A from the factors: rows 0..ns of columns 0..m, and rows ns..m.
            let at = |f: &[f64], i: usize, j: usize| f[j * m + i];
            let mut sa = a.clone();
            for (j, &s) in swaps.iter().enumerate() {
                for c in 0..m {
                    sa.swap(c * m + j, c * m + s);
                }
            }
            for i in 0..m {
                for j in 0..m {
                    let (mut v, mut size) = (0.0, 0.0);
                    for q in 0..ns.min(i + 1).min(if j < ns { j + 1 } else { ns }) {
                        let l = if i == q { 1.0 } else { at(&f, i, q) };
                        v += l * at(&f, q, j);
                        size += (l * at(&f, q, j)).abs();
                    }
                    if i >= ns && j >= ns {
                        v += at(&f, i, j); // Schur complement
                        size += at(&f, i, j).abs();
                    }
                    // Rounding of a sum of `size` magnitude.
                    let err = (v - at(&sa, i, j)).abs();
                    assert!(
                        err <= 1e-14 * (size + 1.0) * m as f64,
                        "m = {m}, ({i}, {j}): {v} vs {}",
                        at(&sa, i, j)
                    );
                }
            }
        }
    }
}
