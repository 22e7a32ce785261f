//! The free-velocity solve of the elastodynamic benchmark (docs/dev/dynamics.md, increment 13,
//! "Free-velocity solve: alternatives to the LU"): the bar of `problems/bar_impact.toml` at
//! spacing L/divisor, h = spacing/2, θ = 0.51, stepped without contact (free vibration from
//! a velocity jump across x = L/2, like the impact's front) with `M̂ = MΦ + h²θ²K` solved by
//!
//! - `lu`: the run's LU (faer, partial pivoting; what `dynamics::Iteration` uses),
//! - `mixed`: the static-pivoting LU with `f32` factors and refinement against `M̂`
//!   (`precision = "mixed"` of the static path),
//! - `envelope LU`: an LU without pivoting in envelope (skyline) storage in the banded
//!   order (the true fill of `M̂`'s band, half of faer's bound), factors in `f64` or `f32`
//!   (arithmetic in `f64`, no refinement),
//! - `own f64 LU` / `f32 LU`: faer's supernodal partial-pivoting LU built here in the banded
//!   order, in `f64` or `f32`, the latter with 0, 1 or 2 refinement steps (`f64` residuals),
//! - `bicgstab <tol>`: BiCGStab preconditioned by the diagonal of `M̂` (a collocation row's
//!   own diagonal for the massless rows), started from the last step's velocity change, to a
//!   relative residual `tol`.
//!
//! Prints per variant the ms per solve (wall and this thread's CPU time), per step, the
//! iterations, and the velocity's difference to the LU run after the steps (max-norm,
//! relative to the LU's max |v|), and the largest |eigenvalue| of `D⁻¹M̂` (power iteration).
//! Before the steps it times two envelope substitutions at once on two threads against one alone (does
//! the second core add memory bandwidth?).
//!
//! `cargo run --release --features studies --example dynamics_free_solve [divisor steps]`
//! (default 320 and 200).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::SymbolicSupernodalParams;
use faer::sparse::linalg::lu::supernodal::{
    self, SupernodalLu, factorize_supernodal_numeric_lu, factorize_supernodal_symbolic_lu,
};
use faer::sparse::linalg::qr;
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::ComplexField;
use faer::{Conj, MatMut, Par};
use mlpg_contact::assembly::SystemMatrix;
use mlpg_contact::dynamics::{Iteration, StepLoad};
use mlpg_contact::linear_solve::{
    ColumnOrdering, FactorMethod, FactorOptions, FactorPrecision, Factorisation,
};
use mlpg_contact::problem::{Problem, ProblemFile};
use mlpg_contact::progress::{Clock, Silent};
use std::time::Instant;

fn inverse(p: &[usize]) -> Vec<usize> {
    let mut inv = vec![0; p.len()];
    for (k, &i) in p.iter().enumerate() {
        inv[i] = k;
    }
    inv
}

/// faer's supernodal partial-pivoting LU in precision `T`, with the column order `order`
/// (postordered), as `linear_solve::Factorisation` builds it for `f64`.
struct OwnLu<T: ComplexField> {
    lu: SupernodalLu<usize, T>,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    col_perm: Vec<usize>,
    col_perm_inv: Vec<usize>,
    /// Σ of the bounding column counts (the structure of the factors of `AᵀA`).
    bound: usize,
}

impl<T: ComplexField + Copy> OwnLu<T> {
    fn new(a: &SystemMatrix, order: &[usize], cast: impl Fn(f64) -> T) -> Self {
        let n = a.n;
        let values: Vec<T> = a.values.iter().map(|&v| cast(v)).collect();
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &a.col_ptr, None, &a.row_idx);
        let am = SparseColMatRef::new(sym, &values);
        let at: SparseColMat<usize, T> = am.transpose().to_col_major().expect("transpose");
        let stack_req = StackReq::any_of(&[
            qr::col_etree_scratch::<usize>(n, n),
            qr::postorder_scratch::<usize>(n),
            StackReq::new::<usize>(n).array(6),
            supernodal::factorize_supernodal_symbolic_lu_scratch::<usize>(n, n),
        ]);
        let mut buf = MemBuffer::new(stack_req);
        let inv = inverse(order);
        let (mut etree, mut post) = (vec![0usize; n], vec![0usize; n]);
        let tree = qr::col_etree(
            sym,
            Some(PermRef::new_checked(order, &inv, n)),
            &mut etree,
            MemStack::new(&mut buf),
        );
        qr::postorder(&mut post, tree, MemStack::new(&mut buf));
        let col_perm: Vec<usize> = post.iter().map(|&k| order[k]).collect();
        let col_perm_inv = inverse(&col_perm);
        let perm_ref = PermRef::new_checked(&col_perm, &col_perm_inv, n);
        let (mut col_counts, mut min_col) = (vec![0usize; n], vec![0usize; n]);
        let tree = qr::col_etree(sym, Some(perm_ref), &mut etree, MemStack::new(&mut buf));
        qr::postorder(&mut post, tree, MemStack::new(&mut buf));
        qr::column_counts_ata(
            &mut col_counts,
            &mut min_col,
            at.symbolic(),
            Some(perm_ref),
            tree,
            &post,
            MemStack::new(&mut buf),
        );
        let symbolic = factorize_supernodal_symbolic_lu::<usize>(
            sym,
            Some(perm_ref),
            &min_col,
            tree,
            &col_counts,
            MemStack::new(&mut buf),
            SymbolicSupernodalParams::default(),
        )
        .expect("symbolic LU");
        let mut lu = SupernodalLu::<usize, T>::new();
        let (mut row_perm, mut row_perm_inv) = (vec![0usize; n], vec![0usize; n]);
        let mut nbuf = MemBuffer::new(supernodal::factorize_supernodal_numeric_lu_scratch::<
            usize,
            T,
        >(&symbolic, Default::default()));
        factorize_supernodal_numeric_lu(
            &mut row_perm,
            &mut row_perm_inv,
            &mut lu,
            am,
            at.as_ref(),
            perm_ref,
            &symbolic,
            Par::rayon(2),
            MemStack::new(&mut nbuf),
            Default::default(),
        )
        .expect("numeric LU");
        let bound = col_counts.iter().sum();
        Self { lu, row_perm, row_perm_inv, col_perm, col_perm_inv, bound }
    }

    fn solve_in_place(&self, x: &mut [T]) {
        let n = x.len();
        let par = Par::Seq;
        let mut buf = MemBuffer::new(supernodal::solve_in_place_scratch::<usize, T>(n, 1, par));
        self.lu.solve_in_place_with_conj(
            PermRef::new_checked(&self.row_perm, &self.row_perm_inv, n),
            PermRef::new_checked(&self.col_perm, &self.col_perm_inv, n),
            Conj::No,
            MatMut::from_column_major_slice_mut(x, n, 1),
            par,
            MemStack::new(&mut buf),
        );
    }
}

/// An LU without pivoting in envelope (skyline) storage, in the symmetric order `order`:
/// row `i` of `L` from column `first[i]`, column `j` of `U` from row `first[j]`, `first` the
/// envelope of the pattern of `A + Aᵀ` (no fill outside it without pivoting). Every product
/// of the factorisation and the substitutions is a dot product or an axpy over contiguous
/// memory. Factors stored in `T` (`f64` or `f32`), arithmetic in `f64`.
struct Skyline<T> {
    order: Vec<usize>,
    first: Vec<usize>,
    ptr: Vec<usize>,
    l: Vec<T>,
    u: Vec<T>,
    diag: Vec<f64>,
    /// `U` by rows for the backward substitution: row `i` holds columns `i + 1 ..= last[i]`.
    last: Vec<usize>,
    row_ptr: Vec<usize>,
    u_rows: Vec<T>,
}

fn dot_mixed<T: Copy + Into<f64>>(a: &[T], b: &[f64]) -> f64 {
    let mut s = [0.0f64; 8];
    let (ca, cb) = (a.chunks_exact(8), b.chunks_exact(8));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..8 {
            s[k] += x[k].into() * y[k];
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| (*x).into() * y).sum();
    s.iter().sum::<f64>() + tail
}

impl Skyline<f64> {
    fn new(a: &SystemMatrix, order: &[usize]) -> Self {
        let n = a.n;
        let pos = inverse(order);
        let mut first: Vec<usize> = (0..n).collect();
        for c in 0..n {
            for e in a.col_ptr[c]..a.col_ptr[c + 1] {
                let (i, j) = (pos[a.row_idx[e]], pos[c]);
                let (lo, hi) = (i.min(j), i.max(j));
                first[hi] = first[hi].min(lo);
            }
        }
        let mut ptr = vec![0usize; n + 1];
        for i in 0..n {
            ptr[i + 1] = ptr[i] + (i - first[i]);
        }
        let (mut l, mut u, mut diag) = (vec![0.0; ptr[n]], vec![0.0; ptr[n]], vec![0.0; n]);
        for c in 0..n {
            for e in a.col_ptr[c]..a.col_ptr[c + 1] {
                let (i, j, v) = (pos[a.row_idx[e]], pos[c], a.values[e]);
                if i == j {
                    diag[i] += v;
                } else if i > j {
                    l[ptr[i] + j - first[i]] += v; // row i, column j < i
                } else {
                    u[ptr[j] + i - first[j]] += v; // column j, row i < j
                }
            }
        }
        for j in 0..n {
            let fj = first[j];
            for i in fj..j {
                let k0 = first[i].max(fj);
                // U(i, j) = A(i, j) − Σ_k L(i, k) U(k, j)
                let li = &l[ptr[i] + k0 - first[i]..ptr[i] + i - first[i]];
                let uj = &u[ptr[j] + k0 - fj..ptr[j] + i - fj];
                let s = dot_mixed(li, uj);
                u[ptr[j] + i - fj] -= s;
                // L(j, i) = (A(j, i) − Σ_k L(j, k) U(k, i)) / U(i, i)
                let lj = &l[ptr[j] + k0 - fj..ptr[j] + i - fj];
                let ui = &u[ptr[i] + k0 - first[i]..ptr[i] + i - first[i]];
                let s = dot_mixed(ui, lj);
                l[ptr[j] + i - fj] = (l[ptr[j] + i - fj] - s) / diag[i];
            }
            let lj = &l[ptr[j]..ptr[j + 1]];
            let uj = &u[ptr[j]..ptr[j + 1]];
            diag[j] -= dot_mixed(lj, uj);
        }
        let mut last: Vec<usize> = (0..n).collect();
        for (j, &f) in first.iter().enumerate() {
            for l in &mut last[f..j] {
                *l = (*l).max(j);
            }
        }
        let mut row_ptr = vec![0usize; n + 1];
        for i in 0..n {
            row_ptr[i + 1] = row_ptr[i] + (last[i] - i);
        }
        let mut u_rows = vec![0.0; row_ptr[n]];
        for j in 0..n {
            for i in first[j]..j {
                u_rows[row_ptr[i] + j - i - 1] = u[ptr[j] + i - first[j]];
            }
        }
        Self { order: order.to_vec(), first, ptr, l, u, diag, last, row_ptr, u_rows }
    }

    fn to_f32(&self) -> Skyline<f32> {
        Skyline {
            order: self.order.clone(),
            first: self.first.clone(),
            ptr: self.ptr.clone(),
            l: self.l.iter().map(|&v| v as f32).collect(),
            u: self.u.iter().map(|&v| v as f32).collect(),
            diag: self.diag.clone(),
            last: self.last.clone(),
            row_ptr: self.row_ptr.clone(),
            u_rows: self.u_rows.iter().map(|&v| v as f32).collect(),
        }
    }
}

impl<T: Copy + Into<f64>> Skyline<T> {
    fn entries(&self) -> usize {
        self.l.len() + self.u_rows.len() + self.diag.len()
    }

    fn solve(&self, b: &[f64]) -> Vec<f64> {
        let n = b.len();
        let mut y: Vec<f64> = self.order.iter().map(|&d| b[d]).collect();
        for i in 0..n {
            let (f, p) = (self.first[i], self.ptr[i]);
            y[i] -= dot_mixed(&self.l[p..p + i - f], &y[f..i]);
        }
        for i in (0..n).rev() {
            let (e, p) = (self.last[i], self.row_ptr[i]);
            let s = dot_mixed(&self.u_rows[p..p + e - i], &y[i + 1..=e]);
            y[i] = (y[i] - s) / self.diag[i];
        }
        let mut x = vec![0.0; n];
        for (k, &d) in self.order.iter().enumerate() {
            x[d] = y[k];
        }
        x
    }
}

/// `x = LU₃₂⁻¹ b`, then `refinements` steps `x += LU₃₂⁻¹ (b − M̂ x)` with `f64` residuals.
fn solve_f32(lu: &OwnLu<f32>, a: &Rows, b: &[f64], refinements: usize) -> Vec<f64> {
    let mut w: Vec<f32> = b.iter().map(|&v| v as f32).collect();
    lu.solve_in_place(&mut w);
    let mut x: Vec<f64> = w.iter().map(|&v| f64::from(v)).collect();
    let mut r = vec![0.0; b.len()];
    for _ in 0..refinements {
        a.mul_into(&x, &mut r);
        for (wi, (bi, ri)) in w.iter_mut().zip(b.iter().zip(&r)) {
            *wi = (bi - ri) as f32;
        }
        lu.solve_in_place(&mut w);
        for (xi, wi) in x.iter_mut().zip(&w) {
            *xi += f64::from(*wi);
        }
    }
    x
}

/// `M̂` by rows (the product streams each row once, no scattered writes).
struct Rows {
    ptr: Vec<usize>,
    col: Vec<u32>,
    val: Vec<f64>,
}

impl Rows {
    fn of(a: &SystemMatrix) -> Self {
        let n = a.n;
        let mut count = vec![0usize; n + 1];
        for &r in &a.row_idx {
            count[r + 1] += 1;
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let ptr = count.clone();
        let mut next = count;
        let mut col = vec![0u32; a.row_idx.len()];
        let mut val = vec![0.0; a.row_idx.len()];
        for c in 0..n {
            for e in a.col_ptr[c]..a.col_ptr[c + 1] {
                let r = a.row_idx[e];
                col[next[r]] = c as u32;
                val[next[r]] = a.values[e];
                next[r] += 1;
            }
        }
        Self { ptr, col, val }
    }

    fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate() {
            let (a, b) = (self.ptr[i], self.ptr[i + 1]);
            *yi = self.col[a..b].iter().zip(&self.val[a..b]).map(|(&c, v)| v * x[c as usize]).sum();
        }
    }

    fn diagonal(&self) -> Vec<f64> {
        (0..self.ptr.len() - 1)
            .map(|i| {
                (self.ptr[i]..self.ptr[i + 1])
                    .find(|&e| self.col[e] as usize == i)
                    .map_or(0.0, |e| self.val[e])
            })
            .collect()
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// Right-preconditioned BiCGStab on `A x = b` with `P = diag(d)`, from `x`; returns the
/// iterations (matrix products: two each).
fn bicgstab(a: &Rows, d_inv: &[f64], b: &[f64], x: &mut [f64], tol: f64) -> usize {
    let n = b.len();
    let mut r = vec![0.0; n];
    a.mul_into(x, &mut r);
    for i in 0..n {
        r[i] = b[i] - r[i];
    }
    let bnorm = dot(b, b).sqrt().max(f64::MIN_POSITIVE);
    if dot(&r, &r).sqrt() <= tol * bnorm {
        return 0;
    }
    let r0 = r.clone();
    let (mut rho, mut alpha, mut omega) = (1.0, 1.0, 1.0);
    let (mut v, mut p) = (vec![0.0; n], vec![0.0; n]);
    let (mut ph, mut sh, mut t) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for it in 1..=500 {
        let rho_new = dot(&r0, &r);
        let beta = (rho_new / rho) * (alpha / omega);
        rho = rho_new;
        for i in 0..n {
            p[i] = r[i] + beta * (p[i] - omega * v[i]);
            ph[i] = d_inv[i] * p[i];
        }
        a.mul_into(&ph, &mut v);
        alpha = rho / dot(&r0, &v);
        for i in 0..n {
            r[i] -= alpha * v[i]; // s
            x[i] += alpha * ph[i];
        }
        if dot(&r, &r).sqrt() <= tol * bnorm {
            return it;
        }
        for i in 0..n {
            sh[i] = d_inv[i] * r[i];
        }
        a.mul_into(&sh, &mut t);
        omega = dot(&t, &r) / dot(&t, &t);
        for i in 0..n {
            x[i] += omega * sh[i];
            r[i] -= omega * t[i];
        }
        if dot(&r, &r).sqrt() <= tol * bnorm {
            return it;
        }
    }
    500
}

fn bar(divisor: f64) -> (Problem, f64) {
    let h = 1.0 / (2.0 * divisor);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/bar_impact.toml");
    let text = std::fs::read_to_string(path).expect("read problems/bar_impact.toml");
    let mut file = ProblemFile::from_toml(&text).expect("parse");
    file.nodes.as_mut().expect("nodes").spacing = Some(1.0 / divisor);
    let d = file.dynamics.as_mut().expect("dynamics");
    d.time_step = h;
    d.theta = Some(0.51);
    d.end_time = 100.0 * h;
    (Problem::try_from(file).expect("valid"), h)
}

enum Variant<'a> {
    Lu,
    Mixed(&'a Factorisation),
    Own64(&'a OwnLu<f64>),
    Own32(&'a OwnLu<f32>, usize),
    Sky64(&'a Skyline<f64>),
    Sky32(&'a Skyline<f32>),
    BiCgStab(f64),
}

/// This thread's time on a CPU (ns, `/proc/thread-self/schedstat`): less dependent on the
/// shared machine's load than the wall clock.
fn cpu_seconds() -> f64 {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").unwrap_or_default();
    s.split_whitespace().next().and_then(|w| w.parse::<f64>().ok()).unwrap_or(0.0) * 1e-9
}

fn load() -> String {
    let l = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    l.split_whitespace().take(3).collect::<Vec<_>>().join(" ")
}

fn main() {
    let args: Vec<f64> =
        std::env::args().skip(1).take(2).map(|a| a.parse().expect("a number")).collect();
    let divisor = args.first().copied().unwrap_or(320.0);
    let steps = args.get(1).copied().unwrap_or(200.0) as usize;
    let (problem, h) = bar(divisor);
    let theta = 0.51;
    let mut silent = Silent;
    let mut clock = Clock::new(&mut silent, Vec::new());
    let parts = mlpg_contact::pipeline::dynamics::discretise(&problem, &mut clock).expect("body");
    let density = problem.dynamics.as_ref().expect("dynamics").density;
    let mass = mlpg_contact::dynamics::mass::Mass::Lumped(
        mlpg_contact::dynamics::mass::lumped_mass(&parts.mfvm.cells, density),
    );
    let clock = Instant::now();
    let it =
        Iteration::new(&parts.system, &mass, &parts.node_shapes, h, theta, &parts.nodes.points)
            .expect("LU of M̂");
    let n = it.dofs();
    let constrained = (0..n).filter(|&d| parts.system.is_constrained(d)).count();
    println!(
        "nodes {}, dofs {n} ({constrained} collocation rows), h {h}, θ {theta}, M̂ entries {}, \
         LU {:.2} s",
        parts.nodes.points.len(),
        it.matrix().values.len(),
        clock.elapsed().as_secs_f64()
    );
    let rows = Rows::of(it.matrix());
    let diag = rows.diagonal();
    let d_inv: Vec<f64> = diag.iter().map(|d| 1.0 / d).collect();
    // Largest |eigenvalue| of D⁻¹M̂ by power iteration.
    let mut x: Vec<f64> = (0..n).map(|i| ((i * 7919) % 101) as f64 / 101.0 - 0.5).collect();
    let mut y = vec![0.0; n];
    let mut lambda = 0.0;
    for _ in 0..200 {
        rows.mul_into(&x, &mut y);
        for i in 0..n {
            y[i] *= d_inv[i];
        }
        let ny = dot(&y, &y).sqrt();
        lambda = ny / dot(&x, &x).sqrt();
        for i in 0..n {
            x[i] = y[i] / ny;
        }
    }
    println!("power iteration: |λ|_max(D⁻¹M̂) ≈ {lambda:.3}");
    let clock = Instant::now();
    let mixed_options = FactorOptions {
        method: FactorMethod::StaticPivoting,
        precision: FactorPrecision::Mixed,
        ..FactorOptions::default()
    };
    let mixed = Factorisation::with_options(
        it.matrix(),
        ColumnOrdering::NestedDissection(&parts.nodes.points),
        &mixed_options,
    )
    .expect("mixed LU of M̂");
    println!("mixed-precision static LU of M̂: {:.2} s", clock.elapsed().as_secs_f64());

    // The static LU in double precision (split band when its fill allows), one and two
    // tasks: the refined solve and the substitution alone, 100 solves each.
    for (tasks, split) in [(2, true), (1, true), (2, false)] {
        let options = FactorOptions {
            method: FactorMethod::StaticPivoting,
            tasks,
            split_band: split,
            ..FactorOptions::default()
        };
        let clock = Instant::now();
        let lu = Factorisation::with_options(
            it.matrix(),
            ColumnOrdering::NestedDissection(&parts.nodes.points),
            &options,
        )
        .expect("static LU of M̂");
        let factor_s = clock.elapsed().as_secs_f64();
        let st = lu.stats();
        let b: Vec<f64> = (0..n).map(|i| ((i * 31) % 23) as f64 - 11.0).collect();
        let time = |refined: bool| {
            let clock = Instant::now();
            let mut x = b.clone();
            for _ in 0..100 {
                x.copy_from_slice(&b);
                let m = faer::MatMut::from_column_major_slice_mut(&mut x, n, 1);
                if refined { lu.solve_in_place(m) } else { lu.solve_unrefined_in_place(m) }
            }
            (clock.elapsed().as_secs_f64() * 10.0, x)
        };
        let (refined, xr) = time(true);
        let (unrefined, xu) = time(false);
        let diff = xr.iter().zip(&xu).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        println!(
            "static LU (tasks {tasks}, split_band {split}): factorised {factor_s:.2} s, {} \
             supernodes, {} factor entries, {} perturbed; ms per solve: refined {refined:.2}, \
             substitution alone {unrefined:.2} (difference {diff:.1e})",
            st.supernodes, st.factor_nnz, st.perturbed_pivots
        );
    }

    // The banded order along the bar (x, then y), as main's ordering picks for this bar.
    let mut order: Vec<usize> = (0..n).collect();
    let pts = &parts.nodes.points;
    order.sort_by(|&a, &b| {
        let (p, q) = (pts[a / 2], pts[b / 2]);
        p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])).then((a % 2).cmp(&(b % 2)))
    });
    let clock = Instant::now();
    let own64 = OwnLu::<f64>::new(it.matrix(), &order, |v| v);
    println!(
        "own f64 LU (banded x-y order): {:.2} s, bound {} entries per factor",
        clock.elapsed().as_secs_f64(),
        own64.bound
    );
    let clock = Instant::now();
    let own32 = OwnLu::<f32>::new(it.matrix(), &order, |v| v as f32);
    println!("own f32 LU: {:.2} s", clock.elapsed().as_secs_f64());
    let clock = Instant::now();
    let sky64 = Skyline::new(it.matrix(), &order);
    let sky32 = sky64.to_f32();
    println!(
        "envelope LU without pivoting (banded x-y order): {:.2} s, {} entries in L, U and the \
         diagonal together; smallest |pivot| / largest {:.1e}",
        clock.elapsed().as_secs_f64(),
        sky64.entries(),
        sky64.diag.iter().fold(f64::INFINITY, |m, d| m.min(d.abs()))
            / sky64.diag.iter().fold(0.0f64, |m, d| m.max(d.abs()))
    );
    // Can the second core add memory bandwidth? Two independent substitutions at once (one
    // per thread, the same factors): if each takes as long as one alone, a substitution
    // split in two independent halves would run ≈ 2× faster.
    let b: Vec<f64> = (0..n).map(|i| ((i * 31) % 17) as f64 - 8.0).collect();
    let repeats = 50;
    let clock = Instant::now();
    for _ in 0..repeats {
        std::hint::black_box(sky64.solve(&b));
    }
    let one = clock.elapsed().as_secs_f64() / repeats as f64;
    let clock = Instant::now();
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                for _ in 0..repeats {
                    std::hint::black_box(sky64.solve(&b));
                }
            });
        }
    });
    let two = clock.elapsed().as_secs_f64() / repeats as f64;
    println!(
        "envelope f64 substitution: one alone {:.2} ms; two at once (2 threads) {:.2} ms per \
         pair (load {})",
        1e3 * one,
        1e3 * two,
        load()
    );
    let x_mid = 0.5;
    let initial: Vec<f64> = (0..n)
        .map(|d| {
            let p = parts.nodes.points[d / 2];
            if d % 2 == 0 && p[0] > x_mid { -0.1 } else { 0.0 }
        })
        .collect();
    let variants: Vec<(String, Variant)> = vec![
        ("lu".into(), Variant::Lu),
        ("mixed (f32 static LU + refinement)".into(), Variant::Mixed(&mixed)),
        ("envelope LU, no pivoting, f64".into(), Variant::Sky64(&sky64)),
        ("envelope LU, no pivoting, f32 factors".into(), Variant::Sky32(&sky32)),
        ("own f64 LU, banded".into(), Variant::Own64(&own64)),
        ("f32 LU, no refinement".into(), Variant::Own32(&own32, 0)),
        ("f32 LU, 1 refinement".into(), Variant::Own32(&own32, 1)),
        ("f32 LU, 2 refinements".into(), Variant::Own32(&own32, 2)),
        ("bicgstab 1e-8".into(), Variant::BiCgStab(1e-8)),
        ("bicgstab 1e-10".into(), Variant::BiCgStab(1e-10)),
        ("bicgstab 1e-12".into(), Variant::BiCgStab(1e-12)),
        ("lu (again)".into(), Variant::Lu),
    ];
    let mut reference: Option<Vec<f64>> = None;
    println!(
        "variant | ms per solve (CPU) | ms per step | iterations (mean, max) | max|v − v_lu| / max|v_lu| \
         after {steps} steps | load before"
    );
    for (name, variant) in &variants {
        let before = load();
        let mut q = vec![0.0; n];
        let mut v = initial.clone();
        let mut dv = vec![0.0; n];
        let (mut solve_s, mut iterations, mut most) = (0.0, 0usize, 0usize);
        let mut solve_cpu = 0.0;
        let step_clock = Instant::now();
        for _ in 0..steps {
            let rhs = it.free_rhs(&q, &v, StepLoad::Scaled(1.0));
            let c = Instant::now();
            let cpu = cpu_seconds();
            match variant {
                Variant::Lu => dv = it.solve(&rhs).expect("solve"),
                Variant::Mixed(f) => dv = f.solve(&rhs).expect("solve"),
                Variant::Own64(f) => {
                    dv.copy_from_slice(&rhs);
                    f.solve_in_place(&mut dv);
                }
                Variant::Own32(f, k) => dv = solve_f32(f, &rows, &rhs, *k),
                Variant::Sky64(f) => dv = f.solve(&rhs),
                Variant::Sky32(f) => dv = f.solve(&rhs),
                Variant::BiCgStab(tol) => {
                    let k = bicgstab(&rows, &d_inv, &rhs, &mut dv, *tol);
                    iterations += k;
                    most = most.max(k);
                }
            }
            solve_s += c.elapsed().as_secs_f64();
            solve_cpu += cpu_seconds() - cpu;
            for i in 0..n {
                let v_new = v[i] + dv[i];
                q[i] += h * ((1.0 - theta) * v[i] + theta * v_new);
                v[i] = v_new;
            }
        }
        let step_s = step_clock.elapsed().as_secs_f64();
        let difference = match &reference {
            None => {
                reference = Some(v.clone());
                0.0
            }
            Some(r) => {
                let top = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                r.iter().zip(&v).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / top
            }
        };
        println!(
            "{name} | {:.2} ({:.2} CPU) | {:.2} | {:.1}, {most} | {difference:.1e} | {before}",
            1e3 * solve_s / steps as f64,
            1e3 * solve_cpu / steps as f64,
            1e3 * step_s / steps as f64,
            iterations as f64 / steps as f64,
        );
    }
}
