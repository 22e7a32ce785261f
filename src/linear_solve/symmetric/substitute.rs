//! The triangular substitutions with the supernodal factors of
//! [`StaticLu`](super::StaticLu), independent subtrees of the assembly tree on separate tasks.
//!
//! The forward substitution visits the supernodes in postorder: each solves its diagonal
//! block and subtracts `L21 x_s` from its pattern rows, which belong to its ancestors. Two
//! sibling subtrees touch disjoint rows of their own and meet only in their common
//! ancestors' rows, so each runs on its own task over its own rows and keeps its
//! subtractions from the rows above in a log, which is applied after both have finished,
//! first sibling first: every entry receives the same subtractions in the same order as in
//! one postorder sweep, so the result is bit-for-bit that of one task. The backward
//! substitution visits the supernodes in reverse postorder and only reads its ancestors'
//! rows, which are final before its siblings start.
//!
//! The substitution is memory-bound (each factor entry is read once per column); two
//! subtrees on two cores read the factors with both cores' bandwidth (docs/dev/performance.md,
//! "Two-core substitution").

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_unit_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, MatRef, Par};
use rayon::prelude::*;

use super::{NodeFactor, Scalar, Supernode, swap_rows};

/// A subtree with at most this many factor entries is substituted by one task (2 MB of
/// `f64`: below that a task costs more than the half of the reads it takes over).
const PARALLEL_SUBTREE_ENTRIES: usize = 1 << 18;

/// What the substitutions need of the assembly tree beyond the supernodes.
pub(super) struct Tree {
    /// The first supernode (in postorder) of each supernode's subtree.
    first: Vec<usize>,
    /// Factor entries (`L` and `U`) of each supernode's subtree.
    entries: Vec<usize>,
    /// Independent subtrees with more factor entries than this run on separate tasks
    /// (`usize::MAX`: one task).
    min_entries: usize,
}

impl Tree {
    /// The tree of the postordered `nodes`, `first` their subtrees' first supernodes.
    pub(super) fn new(nodes: &[Supernode], first: Vec<usize>, parallel: bool) -> Self {
        let mut entries = vec![0usize; nodes.len()];
        for (s, node) in nodes.iter().enumerate() {
            let (w, p) = (node.end - node.start, node.pattern.len());
            let below: usize = node.children.iter().map(|&c| entries[c]).sum();
            entries[s] = below + w * w + 2 * w * p;
        }
        let min_entries = if parallel { PARALLEL_SUBTREE_ENTRIES } else { usize::MAX };
        Self { first, entries, min_entries }
    }

    /// The same tree with tasks from `min_entries` factor entries on (tests).
    #[cfg(test)]
    pub(super) fn with_min_entries(mut self, min_entries: usize) -> Self {
        self.min_entries = min_entries;
        self
    }
}

/// Subtractions of a task's supernodes from rows above its own, in the order one postorder
/// sweep applies them: `rows[i]` receives `values[i k .. (i + 1) k]` (one per column).
struct Log<T> {
    rows: Vec<usize>,
    values: Vec<T>,
}

/// The rows above a task's own in the backward substitution (read only): `rows` holds rows
/// `lo ..`, the rest is `outer`'s.
struct Above<'a, T> {
    rows: MatRef<'a, T>,
    lo: usize,
    outer: Option<&'a Above<'a, T>>,
}

impl<T: Copy> Above<'_, T> {
    fn get(&self, g: usize, c: usize) -> T {
        match (g.checked_sub(self.lo), self.outer) {
            (Some(i), _) if i < self.rows.nrows() => self.rows[(i, c)],
            (_, Some(outer)) => outer.get(g, c),
            _ => unreachable!("a pattern row lies in an ancestor's rows"),
        }
    }
}

/// A child's subtree on a task: the child, its rows of `w`, and the first of them.
type Part<'w, T> = (usize, MatMut<'w, T>, usize);

/// The substitutions with the factors `factors` of the supernodes `nodes`.
pub(super) struct Substitution<'a, T> {
    pub nodes: &'a [Supernode],
    pub factors: &'a [NodeFactor<T>],
    pub tree: &'a Tree,
}

impl<T: Scalar> Substitution<'_, T> {
    /// `w ← U⁻¹ L⁻¹ S w` in place (`S` the row swaps), `w` permuted and scaled, `n × k`.
    pub(super) fn run(&self, mut w: MatMut<'_, T>) {
        let roots: Vec<usize> =
            (0..self.nodes.len()).filter(|&s| self.nodes[s].pattern.is_empty()).collect();
        let range = |r: usize| {
            let lo = self.nodes[self.tree.first[r]].start;
            (lo, self.nodes[r].end - lo)
        };
        let mut log = Log { rows: Vec::new(), values: Vec::new() };
        for &r in &roots {
            let (lo, len) = range(r);
            self.forward(r, w.rb_mut().subrows_mut(lo, len), lo, &mut log);
        }
        debug_assert!(log.rows.is_empty(), "a root's pattern is empty");
        for &r in roots.iter().rev() {
            let (lo, len) = range(r);
            self.backward(r, w.rb_mut().subrows_mut(lo, len), lo, None);
        }
    }

    /// The supernode at which the subtree of `s` splits into at least two subtrees worth a
    /// task each (walking down a chain of single children), if any.
    fn fan_out(&self, s: usize) -> Option<usize> {
        let big = |t: usize| self.tree.entries[t] > self.tree.min_entries;
        if !big(s) {
            return None;
        }
        let mut t = s;
        while self.nodes[t].children.len() == 1 && big(self.nodes[t].children[0]) {
            t = self.nodes[t].children[0];
        }
        (self.nodes[t].children.iter().filter(|&&c| big(c)).count() >= 2).then_some(t)
    }

    /// `own` (rows `lo ..` of `w`, the rows of the subtrees of `children`, in order, followed
    /// by the rest) split into each child's rows, with the first row of each.
    fn split<'w>(
        &self,
        children: &[usize],
        own: MatMut<'w, T>,
        lo: usize,
    ) -> (Vec<Part<'w, T>>, MatMut<'w, T>) {
        let mut parts = Vec::with_capacity(children.len());
        let (mut rest, mut start) = (own, lo);
        for &c in children {
            let end = self.nodes[c].end;
            let (part, tail) = rest.split_at_row_mut(end - start);
            parts.push((c, part, start));
            (rest, start) = (tail, end);
        }
        (parts, rest)
    }

    /// The forward substitution of the subtree of `s` on its rows `own` (from row `lo`);
    /// subtractions from rows above go to `log`.
    fn forward(&self, s: usize, mut own: MatMut<'_, T>, lo: usize, log: &mut Log<T>) {
        let mut tmp = Mat::<T>::zeros(0, 0);
        let Some(bottom) = self.fan_out(s) else {
            for t in self.tree.first[s]..=s {
                self.forward_node(t, own.rb_mut(), lo, log, &mut tmp);
            }
            return;
        };
        let logs: Vec<Log<T>> = {
            let (parts, _) = self.split(&self.nodes[bottom].children, own.rb_mut(), lo);
            parts
                .into_par_iter()
                .map(|(c, part, start)| {
                    let mut log = Log { rows: Vec::new(), values: Vec::new() };
                    self.forward(c, part, start, &mut log);
                    log
                })
                .collect()
        };
        let (hi, k) = (lo + own.nrows(), own.ncols());
        for child in &logs {
            for (i, &g) in child.rows.iter().enumerate() {
                let values = &child.values[i * k..(i + 1) * k];
                if g < hi {
                    for (c, &v) in values.iter().enumerate() {
                        own[(g - lo, c)] -= v;
                    }
                } else {
                    log.rows.push(g);
                    log.values.extend_from_slice(values);
                }
            }
        }
        // The chain from the fan-out up to `s`: single children, so consecutive supernodes.
        for t in bottom..=s {
            self.forward_node(t, own.rb_mut(), lo, log, &mut tmp);
        }
    }

    /// The forward step of supernode `t`.
    fn forward_node(
        &self,
        t: usize,
        mut own: MatMut<'_, T>,
        lo: usize,
        log: &mut Log<T>,
        tmp: &mut Mat<T>,
    ) {
        let (node, fac) = (&self.nodes[t], &self.factors[t]);
        let (ns, p) = (node.end - node.start, node.pattern.len());
        let (hi, k) = (lo + own.nrows(), own.ncols());
        let lu = MatRef::from_column_major_slice(&fac.lu, ns + p, ns);
        let mut xs = own.rb_mut().subrows_mut(node.start - lo, ns);
        swap_rows(&fac.swaps, xs.rb_mut());
        solve_unit_lower_triangular_in_place(lu.subrows(0, ns), xs.rb_mut(), Par::Seq);
        if p == 0 {
            return;
        }
        tmp.resize_with(p, k, |_, _| T::of(0.0));
        matmul(tmp.as_mut(), Accum::Replace, lu.subrows(ns, p), xs.rb(), T::of(1.0), Par::Seq);
        let inside = node.pattern.partition_point(|&g| g < hi);
        for c in 0..k {
            for (q, &g) in node.pattern[..inside].iter().enumerate() {
                own[(g - lo, c)] -= tmp[(q, c)];
            }
        }
        for (q, &g) in node.pattern.iter().enumerate().skip(inside) {
            log.rows.push(g);
            log.values.extend((0..k).map(|c| tmp[(q, c)]));
        }
    }

    /// The backward substitution of the subtree of `s` on its rows `own` (from row `lo`),
    /// the rows above read from `above`.
    fn backward(&self, s: usize, mut own: MatMut<'_, T>, lo: usize, above: Option<&Above<'_, T>>) {
        let mut tmp = Mat::<T>::zeros(0, 0);
        let Some(bottom) = self.fan_out(s) else {
            for t in (self.tree.first[s]..=s).rev() {
                self.backward_node(t, own.rb_mut(), lo, above, &mut tmp);
            }
            return;
        };
        for t in (bottom..=s).rev() {
            self.backward_node(t, own.rb_mut(), lo, above, &mut tmp);
        }
        let (parts, rest) = self.split(&self.nodes[bottom].children, own, lo);
        let rest = Above { rows: rest.rb(), lo: self.nodes[bottom].start, outer: above };
        parts
            .into_par_iter()
            .for_each(|(c, part, start)| self.backward(c, part, start, Some(&rest)));
    }

    /// The backward step of supernode `t`.
    fn backward_node(
        &self,
        t: usize,
        own: MatMut<'_, T>,
        lo: usize,
        above: Option<&Above<'_, T>>,
        tmp: &mut Mat<T>,
    ) {
        let (node, fac) = (&self.nodes[t], &self.factors[t]);
        let (ns, p) = (node.end - node.start, node.pattern.len());
        let (hi, k) = (lo + own.nrows(), own.ncols());
        if p > 0 {
            tmp.resize_with(p, k, |_, _| T::of(0.0));
            for c in 0..k {
                for (q, &g) in node.pattern.iter().enumerate() {
                    tmp[(q, c)] = match above {
                        Some(above) if g >= hi => above.get(g, c),
                        _ => own[(g - lo, c)],
                    };
                }
            }
        }
        let mut xs = own.subrows_mut(node.start - lo, ns);
        if p > 0 {
            let u12 = MatRef::from_column_major_slice(&fac.u12, ns, p);
            matmul(xs.rb_mut(), Accum::Add, u12, tmp.as_ref(), T::of(-1.0), Par::Seq);
        }
        let lu = MatRef::from_column_major_slice(&fac.lu, ns + p, ns);
        solve_upper_triangular_in_place(lu.subrows(0, ns), xs, Par::Seq);
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Factors, Full, NodeGraph, Settings, StaticLu};
    use super::*;
    use crate::assembly::SystemMatrix;
    use crate::linear_solve::{FactorPrecision, nested_dissection};

    /// A non-symmetric five-point matrix on an `nx × ny` grid, two DOFs per node, with its
    /// node positions.
    fn five_point(nx: usize, ny: usize) -> (SystemMatrix, Vec<[f64; 2]>) {
        let n = 2 * nx * ny;
        let mut m = SystemMatrix { n, col_ptr: vec![0], row_idx: Vec::new(), values: Vec::new() };
        for c in 0..n {
            let (i, d) = (c / 2, c % 2);
            let (x, y) = (i % nx, i / nx);
            let mut col = vec![(c, 4.6), (2 * i + 1 - d, 0.3)];
            let near = [(x > 0, i.wrapping_sub(1), -1.0), (x + 1 < nx, i + 1, -1.3)];
            let far = [(y > 0, i.wrapping_sub(nx), -0.8), (y + 1 < ny, i + nx, -1.2)];
            col.extend(near.into_iter().chain(far).filter(|e| e.0).map(|e| (2 * e.1 + d, e.2)));
            col.sort_by_key(|e| e.0);
            m.row_idx.extend(col.iter().map(|e| e.0));
            m.values.extend(col.iter().map(|e| e.1));
            m.col_ptr.push(m.row_idx.len());
        }
        let points = (0..nx * ny).map(|i| [(i % nx) as f64, (i / nx) as f64]).collect();
        (m, points)
    }

    /// Subtrees on separate tasks give the one-task substitution bit for bit, and the
    /// tree did fan out.
    #[test]
    fn subtrees_on_tasks_substitute_as_one_task_bit_for_bit() {
        let (m, points) = five_point(48, 40);
        let perm = nested_dissection(&points, [2.0, 2.0], 16, 2.0);
        let settings = Settings {
            pivot_tolerance: f64::EPSILON.sqrt(),
            parallel: true,
            precision: FactorPrecision::Double,
            gmres_max_iterations: 10,
        };
        let (lu, _, _) =
            StaticLu::new(Full::Matrix(&m), m.clone(), NodeGraph::new(&m), &perm, settings)
                .expect("factorise");
        let Factors::Double(factors) = &lu.factors else { panic!("double factors") };
        let k = 3;
        let b = Mat::<f64>::from_fn(m.n, k, |i, c| ((i * 7 + c * 13) % 17) as f64 - 8.0);
        let run = |min_entries: usize| {
            let tree =
                Tree::new(&lu.nodes, lu.tree.first.clone(), true).with_min_entries(min_entries);
            let sub = Substitution { nodes: &lu.nodes, factors, tree: &tree };
            let root = lu.nodes.len() - 1;
            let fans_out = sub.fan_out(root).is_some();
            let mut w = b.clone();
            sub.run(w.as_mut());
            (w, fans_out)
        };
        let (one, one_fans) = run(usize::MAX);
        let (tasks, tasks_fan) = run(0);
        assert!(!one_fans && tasks_fan, "the tree fans out only with tasks");
        for c in 0..k {
            for i in 0..m.n {
                assert_eq!(one[(i, c)].to_bits(), tasks[(i, c)].to_bits(), "entry ({i}, {c})");
            }
        }
        // And it is a solve: L U w = S b in the scaled, permuted system, checked through
        // the public solve of the same factors.
        let mut x = b.clone();
        lu.solve_in_place(x.as_mut(), None);
        for c in 0..k {
            let xc: Vec<f64> = (0..m.n).map(|i| x[(i, c)]).collect();
            let ax = crate::linear_solve::mul(&m, &xc);
            assert!((0..m.n).all(|i| (b[(i, c)] - ax[i]).abs() < 1e-12), "residual");
        }
    }
}
