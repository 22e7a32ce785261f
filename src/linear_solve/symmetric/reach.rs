//! Products `G K⁻¹ E` with sparse `E` columns and sparse `G` rows through the static LU's own
//! supernodal factors, each triangular solve restricted to the reach of its right-hand sides
//! (docs/method.md §4.2 for the product; docs/dev/performance.md, "Sparse condensation for
//! the Lemke path").
//!
//! With `Π P D_r K D_c Pᵀ = L U` (`Π` the row swaps inside the supernodes' diagonal blocks),
//!
//! ```text
//! G K⁻¹ E = (U⁻ᵀ ĝ)ᵀ (L⁻¹ Π ê) = Yᵀ Z,   ê = P D_r E,   ĝ = P D_c Gᵀ.
//! ```
//!
//! A column of `Z` is nonzero only on the supernodes on the paths from its entries'
//! supernodes to the root of the assembly tree (its *reach*), and so is a column of `Y`
//! (`Uᵀ` has the structure of `L`). Both are computed like a multifrontal solve: each
//! supernode assembles the right-hand sides whose reach contains it (its own entries and its
//! children's contribution rows), solves with its diagonal block, and passes the rows of its
//! pattern to its parent. Then `M = Σ_s Y_sᵀ Z_s` over the supernodes `s`, each term only for
//! the rows and columns of `M` whose reach contains `s`.
//!
//! With nested dissection a reach is a leaf-to-root path of separators, so the work per
//! right-hand side grows like the separators on that path instead of the whole factor. No
//! iterative refinement is done (it would need full solutions): the caller uses this only
//! when no pivot was perturbed, where the unrefined solves are at a normwise backward error of
//! ~1e-17–4e-15 (docs/dev/performance.md, "symmetric-structure LU").
//!
//! The arithmetic of every supernode and of every fixed chunk of rows of `M` does not depend
//! on the thread count; the two solves run side by side and the product in parallel over
//! chunks of rows.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};
use rayon::prelude::*;

use super::{NodeFactor, StaticLu, Supernode, swap_rows};

/// Rows of `M` per parallel task of the product (fixed, so that the arithmetic does not
/// depend on the thread count).
const ROW_CHUNK: usize = 64;

/// Which triangular factor a reach solve applies.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    /// `Z = L⁻¹ Π ê` (row swaps, unit lower `L11`, update with `L21`).
    Lower,
    /// `Y = U⁻ᵀ ĝ` (lower `U11ᵀ`, update with `U12ᵀ`).
    UpperTransposed,
}

/// The result of a reach-restricted solve: per supernode `s`, the ascending ids of the
/// vectors whose reach contains `s` and their solution rows on `s` (`ns × sets[s].len()`,
/// column-major).
struct Reach {
    sets: Vec<Vec<u32>>,
    blocks: Vec<Vec<f64>>,
}

/// Flop estimate of [`StaticLu::sparse_products`] and of the same product by full solves.
#[derive(Clone, Copy, Debug)]
pub(in crate::linear_solve) struct ProductCost {
    /// Both reach solves and the supernode products.
    pub sparse: f64,
    /// `columns` full forward and backward substitutions.
    pub full: f64,
}

impl StaticLu {
    /// Per supernode, the ascending ids of the vectors with an entry in it (`entries[v]`:
    /// supernode-local positions are not needed here, only the supernodes).
    fn reach_sets(&self, touched: &[Vec<usize>]) -> Vec<Vec<u32>> {
        let ns = self.nodes.len();
        let mut own: Vec<Vec<u32>> = vec![Vec::new(); ns];
        for (v, nodes) in touched.iter().enumerate() {
            for &s in nodes {
                // Lossless: fewer than 2³² vectors (checked by the caller).
                own[s].push(v as u32);
            }
        }
        let mut sets: Vec<Vec<u32>> = Vec::with_capacity(ns);
        for (s, mut set) in own.into_iter().enumerate() {
            for &c in &self.nodes[s].children {
                set.extend_from_slice(&sets[c]);
            }
            set.sort_unstable();
            set.dedup();
            sets.push(set);
        }
        sets
    }

    /// The supernodes touched by each vector (ascending, deduplicated) and its entries in
    /// elimination order `(k, value · scale[dof])`.
    #[allow(clippy::type_complexity)]
    fn permuted_entries(
        &self,
        vectors: &[Vec<(usize, f64)>],
        perm_inv: &[usize],
        col_to_node: &[usize],
        scale: &[f64],
    ) -> (Vec<Vec<usize>>, Vec<Vec<(usize, f64)>>) {
        vectors
            .iter()
            .map(|v| {
                let entries: Vec<(usize, f64)> =
                    v.iter().map(|&(d, x)| (perm_inv[d], x * scale[d])).collect();
                let mut nodes: Vec<usize> = entries.iter().map(|&(k, _)| col_to_node[k]).collect();
                nodes.sort_unstable();
                nodes.dedup();
                (nodes, entries)
            })
            .unzip()
    }

    /// The reach-restricted solve of `side` for the (permuted, scaled) `entries`.
    fn reach_solve(
        &self,
        factors: &[NodeFactor<f64>],
        side: Side,
        sets: Vec<Vec<u32>>,
        entries: &[Vec<(usize, f64)>],
        col_to_node: &[usize],
    ) -> Reach {
        let nodes = &self.nodes;
        // Own entries per supernode: (vector, k, value).
        let mut own: Vec<Vec<(u32, usize, f64)>> = vec![Vec::new(); nodes.len()];
        for (v, list) in entries.iter().enumerate() {
            for &(k, x) in list {
                own[col_to_node[k]].push((v as u32, k, x));
            }
        }
        let mut blocks: Vec<Vec<f64>> = Vec::with_capacity(nodes.len());
        // Contribution blocks (`p × r`, column-major) of supernodes whose parent is pending.
        let mut stack: Vec<Vec<f64>> = Vec::new();
        for (s, node) in nodes.iter().enumerate() {
            let nc = node.children.len();
            let child_blocks = stack.split_off(stack.len().saturating_sub(nc));
            let (top, bottom) =
                front_solve(node, &factors[s], side, &sets, s, &own[s], nodes, &child_blocks);
            blocks.push(top);
            stack.push(bottom);
        }
        Reach { sets, blocks }
    }

    /// Flops of [`Self::sparse_products`] for these reach sets, and of full solves.
    fn product_cost(&self, zs: &[Vec<u32>], ys: &[Vec<u32>], columns: usize) -> ProductCost {
        let mut sparse = 0.0;
        let mut full = 0.0;
        for (s, node) in self.nodes.iter().enumerate() {
            let (w, p) = ((node.end - node.start) as f64, node.pattern.len() as f64);
            let solve = w * w + 2.0 * w * p;
            let (rz, ry) = (zs[s].len() as f64, ys[s].len() as f64);
            sparse += (rz + ry) * solve + 2.0 * w * ry * rz;
            full += 2.0 * solve;
        }
        ProductCost { sparse, full: full * columns as f64 }
    }

    /// `G K⁻¹ E` (row-major `rows.len() × columns.len()`) for the sparse columns of `E` and
    /// rows of `G` (`(DOF, value)` entries), with the double-precision factors and no
    /// refinement, and the flop estimates of both routes; `None` for single-precision
    /// factors or more than 2³² vectors. With `max_ratio`, `None` as well when the reach
    /// route would cost more than `max_ratio` times the full solves (the product is then
    /// not computed).
    pub(in crate::linear_solve) fn sparse_products(
        &self,
        columns: &[Vec<(usize, f64)>],
        rows: &[Vec<(usize, f64)>],
        max_ratio: Option<f64>,
    ) -> Option<(Vec<f64>, ProductCost)> {
        let super::Factors::Double(factors) = &self.factors else { return None };
        if u32::try_from(columns.len().max(rows.len())).is_err() {
            return None;
        }
        let perm_inv = super::super::inverse(&self.perm);
        let mut col_to_node = vec![0usize; self.n];
        for (s, node) in self.nodes.iter().enumerate() {
            col_to_node[node.start..node.end].fill(s);
        }
        let (z_nodes, z_entries) =
            self.permuted_entries(columns, &perm_inv, &col_to_node, &self.row_scale);
        let (y_nodes, y_entries) =
            self.permuted_entries(rows, &perm_inv, &col_to_node, &self.col_scale);
        let (z_sets, y_sets) = (self.reach_sets(&z_nodes), self.reach_sets(&y_nodes));
        let cost = self.product_cost(&z_sets, &y_sets, columns.len());
        if max_ratio.is_some_and(|r| cost.sparse > r * cost.full) {
            return None;
        }
        let (z, y) = rayon::join(
            || self.reach_solve(factors, Side::Lower, z_sets, &z_entries, &col_to_node),
            || self.reach_solve(factors, Side::UpperTransposed, y_sets, &y_entries, &col_to_node),
        );
        let (mr, mc) = (rows.len(), columns.len());
        let mut out = vec![0.0f64; mr * mc];
        out.par_chunks_mut(ROW_CHUNK * mc.max(1)).enumerate().for_each(|(chunk, part)| {
            let r0 = chunk * ROW_CHUNK;
            let r1 = r0 + part.len() / mc.max(1);
            let mut prod: Vec<f64> = Vec::new();
            for (s, node) in self.nodes.iter().enumerate() {
                let (ry, rz) = (&y.sets[s], &z.sets[s]);
                if rz.is_empty() {
                    continue;
                }
                let a = ry.partition_point(|&i| (i as usize) < r0);
                let b = ry.partition_point(|&i| (i as usize) < r1);
                if a == b {
                    continue;
                }
                let w = node.end - node.start;
                let ys = MatRef::from_column_major_slice(&y.blocks[s], w, ry.len());
                let zs = MatRef::from_column_major_slice(&z.blocks[s], w, rz.len());
                prod.clear();
                prod.resize((b - a) * rz.len(), 0.0);
                let p = MatMut::from_column_major_slice_mut(&mut prod, b - a, rz.len());
                matmul(p, Accum::Replace, ys.subcols(a, b - a).transpose(), zs, 1.0, Par::Seq);
                for (j, &c) in rz.iter().enumerate() {
                    let col = &prod[j * (b - a)..(j + 1) * (b - a)];
                    for (&i, &v) in ry[a..b].iter().zip(col) {
                        part[(i as usize - r0) * mc + c as usize] += v;
                    }
                }
            }
        });
        Some((out, cost))
    }
}

/// One supernode of a reach solve: assembles its right-hand sides (own entries and the
/// children's contribution rows), solves with the diagonal block and returns its solution
/// rows (`ns × r`) and its contribution block to the parent (`p × r`), column-major.
#[allow(clippy::too_many_arguments)]
fn front_solve(
    node: &Supernode,
    fac: &NodeFactor<f64>,
    side: Side,
    sets: &[Vec<u32>],
    s: usize,
    own: &[(u32, usize, f64)],
    nodes: &[Supernode],
    child_blocks: &[Vec<f64>],
) -> (Vec<f64>, Vec<f64>) {
    let set = &sets[s];
    let r = set.len();
    let (ns, p) = (node.end - node.start, node.pattern.len());
    let m = ns + p;
    if r == 0 {
        return (Vec::new(), Vec::new());
    }
    let mut f = vec![0.0f64; m * r];
    let position = |v: u32| set.binary_search(&v).unwrap_or(0);
    for &(v, k, x) in own {
        f[position(v) * m + (k - node.start)] += x;
    }
    for (&c, cb) in node.children.iter().zip(child_blocks) {
        let cset = &sets[c];
        if cset.is_empty() {
            continue;
        }
        let child = &nodes[c];
        let pc = child.pattern.len();
        // Child pattern rows → front rows (the child's pattern lies in this supernode's
        // columns and pattern: the supernodal structure, checked by the factorisation).
        let mut rows = Vec::with_capacity(pc);
        let mut q = 0;
        for &g in &child.pattern {
            if g < node.end {
                rows.push(g - node.start);
            } else {
                while q < p && node.pattern[q] < g {
                    q += 1;
                }
                rows.push(ns + q);
            }
        }
        // Child columns → front columns (the child's set is a subset, both ascending).
        let mut t = 0;
        for (j, &v) in cset.iter().enumerate() {
            while set[t] < v {
                t += 1;
            }
            let src = &cb[j * pc..(j + 1) * pc];
            let dst = &mut f[t * m..(t + 1) * m];
            for (&row, &x) in rows.iter().zip(src) {
                dst[row] += x;
            }
        }
    }
    let lu = MatRef::from_column_major_slice(&fac.lu, m, ns);
    {
        let mut fm = MatMut::from_column_major_slice_mut(&mut f, m, r);
        let (mut top, bottom) = fm.rb_mut().split_at_row_mut(ns);
        match side {
            Side::Lower => {
                swap_rows(&fac.swaps, top.rb_mut());
                solve_unit_lower_triangular_in_place(lu.subrows(0, ns), top.rb_mut(), Par::Seq);
                if p > 0 {
                    matmul(bottom, Accum::Add, lu.subrows(ns, p), top.rb(), -1.0, Par::Seq);
                }
            }
            Side::UpperTransposed => {
                solve_lower_triangular_in_place(
                    lu.subrows(0, ns).transpose(),
                    top.rb_mut(),
                    Par::Seq,
                );
                if p > 0 {
                    let u12 = MatRef::from_column_major_slice(&fac.u12, ns, p);
                    matmul(bottom, Accum::Add, u12.transpose(), top.rb(), -1.0, Par::Seq);
                }
            }
        }
    }
    let mut top = Vec::with_capacity(ns * r);
    let mut bottom = Vec::with_capacity(p * r);
    for c in 0..r {
        top.extend_from_slice(&f[c * m..c * m + ns]);
        bottom.extend_from_slice(&f[c * m + ns..(c + 1) * m]);
    }
    (top, bottom)
}
