//! Two elastic bodies for the active-set method (docs/method.md §5.1): the unknowns are both
//! bodies' nodal parameters `(û₁, û₂)`, the matrix of an active set is the block-diagonal
//! `diag(K₁, K₂)` with, for every active candidate `c` (owner node `i` on body 1, normal
//! component `a`, `P_c = (K₁_a û₁ − f₁_a)/(w ν_a)` recovered from the removed row):
//!
//! - body 1's row `a` replaced by the scaled gap condition `s (G₁_c û₁ + G₂_c û₂) = −s g0_c`;
//! - body 1's row `b` by `K₁_b − (ν_b/ν_a) K₁_a` (the tangential balance without `P_c`);
//! - each row `r` of body 2 that receives `d₂ w_j P_c` (the target's owner cells) gains
//!   `−(d₂ w_j)_r/(w ν_a) · K₁_a` in body 1's columns (and the same multiple of `f₁_a` on the
//!   right-hand side): `K₂ û₂ = f₂ + E₂ P` with `P_c` in terms of `û₁`.
//!
//! Per candidate the change is of rank two, `e_a (gap row − K₁_a)ᵀ + v_c K₁_aᵀ` (`v_c` holds
//! `−ν_b/ν_a` at row `b` and the target rows' coefficients; the changes of two candidates
//! add where their target cells overlap), so the problem of an active set is the last
//! factorised matrix plus a low-rank term, solved by the Woodbury formula as for
//! [`RigidObstacle`] with two columns per changed candidate. The first base is the two
//! bodies' own factorisations (no new factorisation until the update would cost more than
//! one), later bases a factorisation of the combined matrix. No dense `M = G K⁻¹ E` is formed.
//!
//! With friction ([`TwoBodies::set_friction`], [`FrictionSystem`]) a candidate is open, closed
//! (frictionless, the terms above), sticking or slipping along `±t`, as against a rigid
//! obstacle: both forces come from the residuals `r` of the owner node's two rows of body 1,
//! `P = ν·r/w`, `T = t·r/w`; body 2's owner rows gain `(w_j/w)(d₂ νᵀ + d₂ₜ tᵀ) r` (two terms
//! `u_a K₁_aᵀ`, `u_b K₁_bᵀ`), row `a` is the gap row and row `b` the relative tangential
//! displacement condition (stick) or `(t ± μν)·r = 0` (slip±). Each mode is a set of rank-one
//! terms; modes share terms and update columns (`K_B⁻¹ e_a`, `K_B⁻¹ e_b`, `K_B⁻¹ u_a`,
//! `K_B⁻¹ u_b`), so a change between stick and slip is of rank one and a closing candidate of
//! rank four (docs/method.md §5.1 "Friction").
//!
//! [`RigidObstacle`]: super::RigidObstacle

use super::friction::{FreeResponse, FrictionSystem, StateResponse, mode_of, reduced_blocks};
use super::{
    ActiveSetError, ActiveSetSystem, CLOSED, COLUMN_BYTES, Lcp, Mode, OPEN, RigidObstacleStats,
    Row, SparseSolves, closed_modes, dense_lu, dense_lu_solve, singular, solve_blocks,
    solve_refined, sum_rows,
};
use crate::assembly::SystemMatrix;
use crate::contact::BodyOperator;
use crate::geometry::Point;
use crate::lcp::friction::{ContactState, FrictionProblem};
use crate::linear_solve::{ColumnOrdering, Factorisation};
use crate::nodes::{Axis, dof};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Mat, MatMut};
use std::collections::{HashMap, HashSet};
use std::time::Instant;

/// One body's parts: matrix (rows replaced by displacement conditions as assembled),
/// right-hand side, factorisation, contact operator, and node positions for the
/// nested-dissection ordering (`None`: a finite element model, COLAMD).
#[derive(Clone, Copy)]
pub struct BodyParts<'a> {
    /// `K`.
    pub matrix: &'a SystemMatrix,
    /// `f`.
    pub rhs: &'a [f64],
    /// The factorisation of `matrix`.
    pub factorisation: &'a Factorisation,
    /// The body's contact operator (`G` rows, `E` columns).
    pub operator: &'a BodyOperator,
    /// Node positions (`matrix.n == 2 points.len()`), or `None`.
    pub points: Option<&'a [Point]>,
}

/// The right-hand side that goes with a rank-one term `u dᵀ`: `u` times this value.
#[derive(Clone, Copy, Debug)]
enum TermRhs {
    /// `−s g0_c − f₁_a` (the gap row replaces body 1's row `a`).
    Gap,
    /// `s s_prev,c − f₁_b` (the stick row replaces body 1's row `b`).
    Tangential,
    /// `k f₁_r` (the term's row is `k K₁_r`).
    Row(f64, usize),
}

/// A rank-one term `u dᵀ` of a candidate's change: `u` is one of the candidate's vectors
/// ([`Pair::us`]), `d` a sparse row.
struct Term {
    u: usize,
    d: Row,
    rhs: TermRhs,
}

/// What a candidate's modes change in `diag(K₁, K₂)`: the distinct vectors `u`, the terms, and
/// which terms each closed mode uses (modes that share a term share its update column).
struct Pair {
    /// Sparse vectors `(DOF, value)`.
    us: Vec<Vec<(usize, f64)>>,
    terms: Vec<Term>,
    /// For each closed mode `k ≥ 1` (at `k − 1`), the indices in `terms` it adds.
    modes: Vec<Vec<usize>>,
    /// The frictionless vectors and terms (the first entries of `us`, `terms`).
    frictionless: (usize, usize),
    /// Body 1's original rows `a`, `b` of the owner node.
    rows: [Row; 2],
    /// Their DOFs.
    dofs: [usize; 2],
    /// Their axes.
    axes: [Axis; 2],
    /// The owner weight `w`.
    weight: f64,
    /// `w ν_a`.
    wn: f64,
}

/// One column of the low-rank update: candidate `c`'s vector `us[u]` times `sign`, and the
/// terms `(index, ±1)` whose rows sum to the change of the rows it multiplies.
struct Group {
    c: usize,
    u: usize,
    sign: f64,
    terms: Vec<(usize, f64)>,
}

/// Two elastic bodies in contact, in the sparse form of the module documentation.
pub struct TwoBodies<'a> {
    bodies: [BodyParts<'a>; 2],
    /// `f₁`, `f₂` (the bodies' right-hand sides; [`TwoBodies::set_load`] changes them).
    rhs: [Vec<f64>; 2],
    /// Body 1's DOFs (body 2's follow them).
    n1: usize,
    initial_gap: &'a [f64],
    /// The collocation scale `s` of the gap and stick rows.
    scale: f64,
    /// Both bodies' node positions, when both have them.
    points: Option<Vec<Point>>,
    /// Per candidate: the changes of its modes.
    pairs: Vec<Pair>,
    /// `‖diag(K₁, K₂)‖∞`.
    norm: f64,
    /// `None`: the bodies' own factorisations (every candidate of `base_modes` is open).
    base: Option<Box<Factorisation>>,
    base_modes: Vec<Mode>,
    /// `K_B⁻¹ u` by candidate and vector.
    columns: HashMap<(usize, usize), Vec<f64>>,
    last: Option<(Vec<Mode>, Vec<f64>)>,
    /// The tangential operators of both bodies (direction `t`, resp. `−t`), with friction.
    tangential: Option<[&'a BodyOperator; 2]>,
    /// `μ_c` (empty: frictionless).
    friction: Vec<f64>,
    /// The right-hand sides `s_prev,c` of the stick rows (before the scale `s`).
    tangential_target: Vec<f64>,
    /// Work counters (the same as a rigid obstacle's).
    pub stats: RigidObstacleStats,
}

/// `s (d₁·u₁^h(x_c) + d₂·u₂^h(y_c))` as a row of the combined unknowns: the gap row (normal
/// operators) or the relative tangential displacement row (tangential operators) of `c`.
fn pair_row(scale: f64, ops: [&BodyOperator; 2], n1: usize, c: usize) -> Row {
    let mut row: Row = Vec::new();
    for (op, offset) in [(ops[0], 0), (ops[1], n1)] {
        for (&j, &phi) in op.shapes.support(c).iter().zip(op.shapes.phi(c)) {
            for ax in Axis::BOTH {
                let v = scale * op.direction(c)[ax as usize] * phi;
                if v != 0.0 {
                    row.push((offset + dof(j as usize, ax), v));
                }
            }
        }
    }
    row.sort_by_key(|e| e.0);
    row
}

impl<'a> TwoBodies<'a> {
    /// The system of `first` (the candidate body: each candidate's force on one node of its
    /// own) and `second` (the target), with the candidates' `initial_gap`; `scale` multiplies
    /// the gap rows (body 1's collocation scale).
    ///
    /// # Errors
    /// [`ActiveSetError::Unsupported`] when a candidate's force is not on one node of body 1
    /// of its own, or the operators disagree on the candidates.
    pub fn new(
        first: BodyParts<'a>,
        second: BodyParts<'a>,
        initial_gap: &'a [f64],
        scale: f64,
    ) -> Result<Self, ActiveSetError> {
        let (op1, op2) = (first.operator, second.operator);
        let m = op1.len();
        let n1 = first.matrix.n;
        // Each candidate's replaced row: its own larger normal component (the normals are the
        // target edge's, the same for all on a straight edge).
        let axes = |c: usize| {
            let d = op1.direction(c);
            if d[0].abs() >= d[1].abs() { (Axis::X, Axis::Y) } else { (Axis::Y, Axis::X) }
        };
        let mut owner_of = Vec::with_capacity(m);
        let mut used = HashSet::new();
        for (c, owners) in op1.owners.iter().enumerate() {
            match owners.as_slice() {
                [(i, w)] if *w != 0.0 && used.insert(*i) && c < op2.len() => {
                    owner_of.push((*i as usize, *w));
                }
                _ => return Err(ActiveSetError::Unsupported { candidate: c }),
            }
        }
        if op2.len() != m {
            return Err(ActiveSetError::Unsupported { candidate: m.min(op2.len()) });
        }
        let mut wanted: HashMap<usize, Row> = HashMap::new();
        for &(i, _) in &owner_of {
            wanted.insert(dof(i, Axis::X), Vec::new());
            wanted.insert(dof(i, Axis::Y), Vec::new());
        }
        let k1 = first.matrix;
        for col in 0..k1.n {
            for k in k1.col_ptr[col]..k1.col_ptr[col + 1] {
                if let Some(row) = wanted.get_mut(&k1.row_idx[k]) {
                    row.push((col, k1.values[k]));
                }
            }
        }
        let mut pairs = Vec::with_capacity(m);
        for (c, &(i, w)) in owner_of.iter().enumerate() {
            let ((a, b), d1, d2) = (axes(c), op1.direction(c), op2.direction(c));
            let (na, ratio) = (d1[a as usize], d1[b as usize] / d1[a as usize]);
            let (ra, rb) = (dof(i, a), dof(i, b));
            let old_a = wanted[&ra].clone();
            let old_b = wanted[&rb].clone();
            let gap_row = pair_row(scale, [op1, op2], n1, c);
            let minus_old: Row = old_a.iter().map(|&(j, v)| (j, -v)).collect();
            // Row a: the gap row instead of K₁_a. Row b and the target's force rows: multiples
            // of K₁_a, one rank-one term `u K₁_aᵀ` (and `u f₁_a` on the right-hand side).
            let wn = w * na;
            let mut u: Vec<(usize, f64)> = Vec::new();
            if ratio != 0.0 {
                u.push((rb, -ratio));
            }
            for &(j, w2) in &op2.owners[c] {
                for ax in Axis::BOTH {
                    let k = -d2[ax as usize] * w2 / wn;
                    if k != 0.0 {
                        u.push((n1 + dof(j as usize, ax), k));
                    }
                }
            }
            let mut us = vec![vec![(ra, 1.0)]];
            let mut terms =
                vec![Term { u: 0, d: sum_rows(&gap_row, &minus_old), rhs: TermRhs::Gap }];
            if !u.is_empty() {
                us.push(u);
                terms.push(Term { u: 1, d: old_a.clone(), rhs: TermRhs::Row(1.0, ra) });
            }
            let closed: Vec<usize> = (0..terms.len()).collect();
            pairs.push(Pair {
                frictionless: (us.len(), terms.len()),
                us,
                terms,
                modes: vec![closed],
                rows: [old_a, old_b],
                dofs: [ra, rb],
                axes: [a, b],
                weight: w,
                wn,
            });
        }
        let row_norm = |matrix: &SystemMatrix| {
            let mut rows = vec![0.0_f64; matrix.n];
            for (k, &r) in matrix.row_idx.iter().enumerate() {
                rows[r] += matrix.values[k].abs();
            }
            rows.into_iter().fold(0.0, f64::max)
        };
        let points = match (first.points, second.points) {
            (Some(p1), Some(p2)) => Some(p1.iter().chain(p2).copied().collect()),
            _ => None,
        };
        Ok(Self {
            bodies: [first, second],
            rhs: [first.rhs.to_vec(), second.rhs.to_vec()],
            n1,
            initial_gap,
            scale,
            points,
            pairs,
            norm: row_norm(first.matrix).max(row_norm(second.matrix)),
            base: None,
            base_modes: vec![OPEN; m],
            columns: HashMap::new(),
            last: None,
            tangential: None,
            friction: Vec::new(),
            tangential_target: vec![0.0; m],
            stats: RigidObstacleStats::default(),
        })
    }

    /// Sets the Coulomb coefficients `μ_c` (docs/method.md §8) and the tangential operators of
    /// both bodies (body 1's with direction `t`, body 2's with `−t` at the paired points, so
    /// that they read the relative tangential displacement `s`): builds each candidate's
    /// stick and slip terms (a candidate with `μ_c = 0` closes frictionless). A change of `μ`
    /// drops the update columns, and the combined factorisation when it holds frictional
    /// modes.
    ///
    /// A closed frictional candidate's force on body 1 is `w(ν P + t T)`, both recovered from
    /// the residuals `r` of its node's two rows: `P = ν·r/w`, `T = t·r/w`. Body 2 receives
    /// `w_j (d₂ P + d₂ₜ T)` on the rows of its owner cells, i.e. `(w_j/w)(d₂ νᵀ + d₂ₜ tᵀ) r`:
    /// two terms `u_a K₁_aᵀ`, `u_b K₁_bᵀ`. Row `a` is the gap row; row `b` is the scaled
    /// relative tangential displacement `s (t·u₁^h(x_c) − t·u₂^h(y_c)) = s s_prev` (stick) or
    /// `K₁_b + (c_a/c_b) K₁_a` with `c = t ± μν` (slip±, `(t ± μν)·r = 0`): the term
    /// `e_b (stick row − K₁_b)ᵀ`, resp. `e_b ((c_a/c_b) K₁_a)ᵀ`, so that a change between
    /// stick and slip is of rank one and a closing candidate of rank four.
    ///
    /// # Errors
    /// [`ActiveSetError::Unsupported`] when a slip combination has no weight on row `b`
    /// (`t_b ± μ ν_b = 0`).
    pub fn set_friction(
        &mut self,
        mu: &[f64],
        tangential: [&'a BodyOperator; 2],
    ) -> Result<(), ActiveSetError> {
        self.tangential = Some(tangential);
        if self.friction == mu {
            return Ok(());
        }
        let (op1, op2) = (self.bodies[0].operator, self.bodies[1].operator);
        let (n1, scale) = (self.n1, self.scale);
        for (c, pair) in self.pairs.iter_mut().enumerate() {
            let (n_us, n_terms) = pair.frictionless;
            pair.us.truncate(n_us);
            pair.terms.truncate(n_terms);
            pair.modes.truncate(1);
            if mu[c] == 0.0 {
                let closed = pair.modes[0].clone();
                pair.modes.extend([closed.clone(), closed.clone(), closed]);
                continue;
            }
            let (nu, t) = (op1.direction(c), tangential[0].direction(c));
            let (d2, d2t) = (op2.direction(c), tangential[1].direction(c));
            let [a, b] = pair.axes;
            let [ra, rb] = pair.dofs;
            // Body 2's rows per unit residual r_x of body 1's row x: −(w_j/w)(d₂ ν_x + d₂ₜ t_x).
            let target = |x: Axis| -> Vec<(usize, f64)> {
                let mut u: Row = Vec::new();
                for (owners, d, e) in [(&op2.owners[c], d2, nu), (&tangential[1].owners[c], d2t, t)]
                {
                    for &(j, w2) in owners {
                        for ax in Axis::BOTH {
                            let k = -w2 / pair.weight * d[ax as usize] * e[x as usize];
                            if k != 0.0 {
                                u.push((n1 + dof(j as usize, ax), k));
                            }
                        }
                    }
                }
                sum_rows(&u, &Vec::new()).into_iter().filter(|e| e.1 != 0.0).collect()
            };
            let minus_b: Row = pair.rows[1].iter().map(|&(j, v)| (j, -v)).collect();
            let stick_row = sum_rows(&pair_row(scale, tangential, n1, c), &minus_b);
            let eb = pair.us.len();
            pair.us.push(vec![(rb, 1.0)]);
            let stick = pair.terms.len();
            pair.terms.push(Term { u: eb, d: stick_row, rhs: TermRhs::Tangential });
            let mut shared = vec![0];
            for (x, r) in [(a, ra), (b, rb)] {
                let u = target(x);
                if !u.is_empty() {
                    pair.us.push(u);
                    shared.push(pair.terms.len());
                    let d = pair.rows[if x == a { 0 } else { 1 }].clone();
                    pair.terms.push(Term { u: pair.us.len() - 1, d, rhs: TermRhs::Row(1.0, r) });
                }
            }
            let mut modes = Vec::new();
            for sign in [1.0, -1.0] {
                let (ca, cb) = (
                    t[a as usize] + sign * mu[c] * nu[a as usize],
                    t[b as usize] + sign * mu[c] * nu[b as usize],
                );
                if cb.abs() <= 1e-8 * ca.abs() {
                    return Err(ActiveSetError::Unsupported { candidate: c });
                }
                let k = ca / cb;
                let d: Row = pair.rows[0].iter().map(|&(j, v)| (j, k * v)).collect();
                modes.push(pair.terms.len());
                pair.terms.push(Term { u: eb, d, rhs: TermRhs::Row(k, ra) });
            }
            let with = |own: usize| {
                let mut v = vec![shared[0], own];
                v.extend_from_slice(&shared[1..]);
                v
            };
            pair.modes.push(with(stick));
            pair.modes.push(with(modes[0]));
            pair.modes.push(with(modes[1]));
        }
        self.friction = mu.to_vec();
        self.columns.clear();
        if self.base_modes.iter().any(|&k| k != OPEN && k != CLOSED) {
            self.base = None;
            self.base_modes = vec![OPEN; self.pairs.len()];
        }
        self.last = None;
        Ok(())
    }

    /// Sets the load of an increment: the right-hand sides `f₁`, `f₂` of both bodies.
    pub fn set_load(&mut self, first: &[f64], second: &[f64]) {
        self.rhs[0].copy_from_slice(first);
        self.rhs[1].copy_from_slice(second);
        self.last = None;
    }

    fn n(&self) -> usize {
        self.n1 + self.bodies[1].matrix.n
    }

    /// The terms (indices in `terms`) of candidate `c` in `mode`.
    fn mode_terms(&self, c: usize, mode: Mode) -> &[usize] {
        if mode == OPEN { &[] } else { &self.pairs[c].modes[mode as usize - 1] }
    }

    /// The right-hand side value of a term of candidate `c`.
    fn term_rhs(&self, c: usize, rhs: TermRhs) -> f64 {
        let [ra, rb] = self.pairs[c].dofs;
        let f1 = &self.rhs[0];
        match rhs {
            TermRhs::Gap => -self.scale * self.initial_gap[c] - f1[ra],
            TermRhs::Tangential => self.scale * self.tangential_target[c] - f1[rb],
            TermRhs::Row(k, r) => k * f1[r],
        }
    }

    /// `[f₁; f₂]` plus the closed candidates' additions.
    fn rhs_of(&self, modes: &[Mode]) -> Vec<f64> {
        let mut b: Vec<f64> = self.rhs[0].iter().chain(&self.rhs[1]).copied().collect();
        for (c, pair) in self.pairs.iter().enumerate() {
            for &t in self.mode_terms(c, modes[c]) {
                let term = &pair.terms[t];
                let v = self.term_rhs(c, term.rhs);
                for &(r, k) in &pair.us[term.u] {
                    b[r] += k * v;
                }
            }
        }
        b
    }

    /// The matrix of `modes` times `u`.
    fn apply(&self, modes: &[Mode], u: &[f64]) -> Vec<f64> {
        let mut y = crate::linear_solve::mul(self.bodies[0].matrix, &u[..self.n1]);
        y.extend(crate::linear_solve::mul(self.bodies[1].matrix, &u[self.n1..]));
        for (c, pair) in self.pairs.iter().enumerate() {
            for &t in self.mode_terms(c, modes[c]) {
                let term = &pair.terms[t];
                let dot = term.d.iter().map(|&(j, v)| v * u[j]).sum::<f64>();
                for &(r, k) in &pair.us[term.u] {
                    y[r] += k * dot;
                }
            }
        }
        y
    }

    /// The combined matrix of `modes` (entries that cancel exactly are dropped).
    fn matrix_of(&self, modes: &[Mode]) -> SystemMatrix {
        let n = self.n();
        let mut extra: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for (c, pair) in self.pairs.iter().enumerate() {
            for &t in self.mode_terms(c, modes[c]) {
                let term = &pair.terms[t];
                for &(col, v) in &term.d {
                    extra[col].extend(pair.us[term.u].iter().map(|&(r, k)| (r, k * v)));
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let nnz = self.bodies[0].matrix.row_idx.len() + self.bodies[1].matrix.row_idx.len();
        let mut row_idx = Vec::with_capacity(nnz);
        let mut values = Vec::with_capacity(nnz);
        col_ptr.push(0);
        let mut column: Vec<(usize, f64)> = Vec::new();
        for (col, extra) in extra.iter().enumerate() {
            column.clear();
            let (k, offset, local) = if col < self.n1 {
                (self.bodies[0].matrix, 0, col)
            } else {
                (self.bodies[1].matrix, self.n1, col - self.n1)
            };
            for e in k.col_ptr[local]..k.col_ptr[local + 1] {
                column.push((offset + k.row_idx[e], k.values[e]));
            }
            column.extend_from_slice(extra);
            column.sort_by_key(|e| e.0);
            let start = row_idx.len();
            for &(r, v) in &column {
                if row_idx.len() > start && row_idx.last() == Some(&r) {
                    *values.last_mut().expect("an entry was pushed") += v;
                } else {
                    row_idx.push(r);
                    values.push(v);
                }
            }
            // Drop the entries that cancelled (a replaced row's old entries).
            let mut keep = start;
            for e in start..row_idx.len() {
                if values[e] != 0.0 {
                    row_idx[keep] = row_idx[e];
                    values[keep] = values[e];
                    keep += 1;
                }
            }
            row_idx.truncate(keep);
            values.truncate(keep);
            col_ptr.push(row_idx.len());
        }
        SystemMatrix { n, col_ptr, row_idx, values }
    }

    /// `K_B⁻¹ X` in place.
    fn base_solve(&self, x: MatMut<'_, f64>) {
        match &self.base {
            Some(f) => solve_blocks(f, x),
            None => {
                let (top, bottom) = x.split_at_row_mut(self.n1);
                solve_blocks(self.bodies[0].factorisation, top);
                solve_blocks(self.bodies[1].factorisation, bottom);
            }
        }
    }

    /// The update columns of candidate `c` going from mode `from` to mode `to`: the terms of
    /// `to` that `from` lacks (+1) and of `from` that `to` lacks (−1), one column per vector
    /// `u` they use.
    fn changes_of(&self, c: usize, from: Mode, to: Mode, out: &mut Vec<Group>) {
        let (old, new) = (self.mode_terms(c, from), self.mode_terms(c, to));
        let signed = new
            .iter()
            .filter(|t| !old.contains(t))
            .map(|&t| (t, 1.0))
            .chain(old.iter().filter(|t| !new.contains(t)).map(|&t| (t, -1.0)));
        let mut by_u: Vec<(usize, Vec<(usize, f64)>)> = Vec::new();
        for (t, s) in signed {
            let u = self.pairs[c].terms[t].u;
            match by_u.iter_mut().find(|g| g.0 == u) {
                Some(g) => g.1.push((t, s)),
                None => by_u.push((u, vec![(t, s)])),
            }
        }
        for (u, terms) in by_u {
            match terms[..] {
                [(t, s)] => out.push(Group { c, u, sign: s, terms: vec![(t, 1.0)] }),
                _ => out.push(Group { c, u, sign: 1.0, terms }),
            }
        }
    }

    /// Makes the base suitable for `modes` (refactorising when the update would cost more)
    /// and returns the update's columns.
    fn prepare(&mut self, modes: &[Mode]) -> Result<Vec<Group>, ActiveSetError> {
        let mut groups = Vec::new();
        for (c, &mode) in modes.iter().enumerate() {
            if mode != self.base_modes[c] {
                self.changes_of(c, self.base_modes[c], mode, &mut groups);
            }
        }
        let new: Vec<(usize, usize)> = groups
            .iter()
            .map(|g| (g.c, g.u))
            .filter(|key| !self.columns.contains_key(key))
            .collect();
        let n = self.n();
        // The deterministic cost model of the rigid obstacle: a factorisation costs about
        // `bound_flops`, an update column about `bound_nnz` (of the base's analysis).
        let (nnz, flops) = match &self.base {
            Some(f) => (f.stats().bound_nnz as f64, f.stats().bound_flops),
            None => {
                let (s1, s2) =
                    (self.bodies[0].factorisation.stats(), self.bodies[1].factorisation.stats());
                ((s1.bound_nnz + s2.bound_nnz) as f64, s1.bound_flops + s2.bound_flops)
            }
        };
        let too_costly = new.len() as f64 * nnz > flops;
        let too_big = (self.columns.len() + new.len()) * n * 8 > COLUMN_BYTES;
        if groups.len() > 1024 || too_costly || too_big {
            self.base = None;
            self.columns.clear();
            let t = Instant::now();
            let matrix = self.matrix_of(modes);
            // With the options of the first body's own factorisation (its precision).
            let f = match &self.points {
                Some(p) => Factorisation::with_options(
                    &matrix,
                    ColumnOrdering::NestedDissection(p),
                    self.bodies[0].factorisation.options(),
                )?,
                None => Factorisation::new(&matrix)?,
            };
            drop(matrix);
            self.stats.factorisations += 1;
            self.stats.factorisation_seconds += t.elapsed().as_secs_f64();
            self.base = Some(Box::new(f));
            self.base_modes = modes.to_vec();
            return Ok(Vec::new());
        }
        if !new.is_empty() {
            let t = Instant::now();
            let mut x = Mat::<f64>::zeros(n, new.len());
            for (j, &(c, u)) in new.iter().enumerate() {
                for &(r, v) in &self.pairs[c].us[u] {
                    x[(r, j)] = v;
                }
            }
            self.base_solve(x.as_mut());
            for (j, key) in new.into_iter().enumerate() {
                let z = x.col_as_slice(j);
                if z.iter().any(|v| !v.is_finite()) {
                    return Err(singular("the factorisation behind the low-rank update"));
                }
                self.columns.insert(key, z.to_vec());
            }
            self.stats.update_columns += x.ncols();
            self.stats.update_seconds += t.elapsed().as_secs_f64();
        }
        self.stats.max_update_rank = self.stats.max_update_rank.max(groups.len());
        Ok(groups)
    }

    /// `(Σ_t s_t d_t)·z` for the terms of a group.
    fn group_dot(&self, g: &Group, z: &[f64]) -> f64 {
        let terms = &self.pairs[g.c].terms;
        let mut dots = g
            .terms
            .iter()
            .map(|&(t, s)| s * terms[t].d.iter().map(|&(j, v)| v * z[j]).sum::<f64>());
        let first = dots.next().unwrap_or(0.0);
        dots.fold(first, |a, b| a + b)
    }

    /// Solves the problem of `modes` for the columns of `x` (`n × k`, overwritten):
    /// Woodbury, `K_A = K_B + Σ_j σ_j u_j D_jᵀ`, `K_A⁻¹ b = y − Σ_j σ_j z_j v_j` with
    /// `y = K_B⁻¹ b`, `z_j = K_B⁻¹ u_j`, `C v = (D_jᵀ y)_j`, `C_ij = δ_ij + σ_j D_iᵀ z_j`.
    fn solve_columns(
        &mut self,
        modes: &[Mode],
        mut x: MatMut<'_, f64>,
    ) -> Result<(), ActiveSetError> {
        let groups = self.prepare(modes)?;
        self.base_solve(x.rb_mut());
        if groups.is_empty() {
            return Ok(());
        }
        let k = groups.len();
        let mut cap = vec![0.0; k * k];
        for (j, gj) in groups.iter().enumerate() {
            let z = &self.columns[&(gj.c, gj.u)];
            for (i, gi) in groups.iter().enumerate() {
                cap[j * k + i] = gj.sign * self.group_dot(gi, z) + if i == j { 1.0 } else { 0.0 };
            }
        }
        let perm = dense_lu(&mut cap, k).ok_or_else(|| singular("the low-rank update"))?;
        for col in 0..x.ncols() {
            let y: Vec<f64> = x.rb().col(col).iter().copied().collect();
            let mut v: Vec<f64> = groups.iter().map(|g| self.group_dot(g, &y)).collect();
            dense_lu_solve(&cap, &perm, k, &mut v);
            let mut out = x.rb_mut().col_mut(col);
            for (g, v) in groups.iter().zip(&v) {
                let s = g.sign;
                for (i, zi) in self.columns[&(g.c, g.u)].iter().enumerate() {
                    out[i] -= s * zi * v;
                }
            }
        }
        Ok(())
    }

    /// Solves the problem of `active` for `(û₁, û₂)` (concatenated).
    ///
    /// # Errors
    /// A failed solve.
    pub fn displacements(&mut self, active: &[bool]) -> Result<Vec<f64>, ActiveSetError> {
        self.displacements_of(&closed_modes(active))
    }

    fn displacements_of(&mut self, modes: &[Mode]) -> Result<Vec<f64>, ActiveSetError> {
        let b = self.rhs_of(modes);
        solve_refined(self, modes, &b)
    }

    /// The displacements `(û₁, û₂)` of the problem of `active`: those of the last
    /// [`ActiveSetSystem::solve_active`] when it solved `active`, else a new solve (see
    /// [`super::RigidObstacle::final_displacements`] for why they are not `K⁻¹(f + E P)`).
    ///
    /// # Errors
    /// A failed solve.
    pub fn final_displacements(
        &mut self,
        active: &[bool],
    ) -> Result<(Vec<f64>, Vec<f64>), ActiveSetError> {
        self.final_displacements_of(&closed_modes(active))
    }

    /// The final displacements `(û₁, û₂)` of the frictional step that settled on `states`
    /// (those of its last solve; see [`TwoBodies::final_displacements`]).
    ///
    /// # Errors
    /// A failed solve.
    pub fn final_friction_displacements(
        &mut self,
        states: &[ContactState],
    ) -> Result<(Vec<f64>, Vec<f64>), ActiveSetError> {
        let modes = self.modes_of(states);
        self.final_displacements_of(&modes)
    }

    fn final_displacements_of(
        &mut self,
        modes: &[Mode],
    ) -> Result<(Vec<f64>, Vec<f64>), ActiveSetError> {
        let mut u = match self.last.take() {
            Some((a, u)) if a == modes => u,
            _ => self.displacements_of(modes)?,
        };
        let u2 = u.split_off(self.n1);
        Ok((u, u2))
    }

    /// The mode of each candidate in `states`.
    fn modes_of(&self, states: &[ContactState]) -> Vec<Mode> {
        let mu = |c: usize| self.friction.get(c).copied().unwrap_or(0.0);
        states.iter().enumerate().map(|(c, &s)| mode_of(mu(c), s)).collect()
    }

    /// `(P_c, T_c)` of `modes` from body 1's rows: open 0; frictionless closed
    /// `P = (K₁_a û₁ − f₁_a)/(w ν_a)`, `T = 0`; frictional `P = ν·r/w`, `T = t·r/w`.
    fn forces(&self, modes: &[Mode], u: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let f1 = &self.rhs[0];
        let dot = |row: &Row| row.iter().map(|&(j, v)| v * u[j]).sum::<f64>();
        let mut p = Vec::with_capacity(modes.len());
        let mut t = Vec::with_capacity(modes.len());
        for (c, pair) in self.pairs.iter().enumerate() {
            let [ra, rb] = pair.dofs;
            match modes[c] {
                OPEN => {
                    p.push(0.0);
                    t.push(0.0);
                }
                CLOSED => {
                    p.push((dot(&pair.rows[0]) - f1[ra]) / pair.wn);
                    t.push(0.0);
                }
                _ => {
                    let mut r = [0.0; 2];
                    r[pair.axes[0] as usize] = dot(&pair.rows[0]) - f1[ra];
                    r[pair.axes[1] as usize] = dot(&pair.rows[1]) - f1[rb];
                    let nu = self.bodies[0].operator.direction(c);
                    let tc = self.tangential.map_or([0.0, 0.0], |ops| ops[0].direction(c));
                    p.push((nu[0] * r[0] + nu[1] * r[1]) / pair.weight);
                    t.push((tc[0] * r[0] + tc[1] * r[1]) / pair.weight);
                }
            }
        }
        (p, t)
    }

    /// `G₁ û₁ + G₂ û₂`.
    fn gap_change(&self, u: &[f64]) -> Vec<f64> {
        let g1 = self.bodies[0].operator.gap_contribution(&u[..self.n1]);
        let g2 = self.bodies[1].operator.gap_contribution(&u[self.n1..]);
        g1.iter().zip(&g2).map(|(a, b)| a + b).collect()
    }

    /// `g0 + G₁ û₁ + G₂ û₂`.
    fn gaps(&self, u: &[f64]) -> Vec<f64> {
        self.gap_change(u).iter().zip(self.initial_gap).map(|(g, g0)| g0 + g).collect()
    }

    /// The relative tangential displacements `t·u₁^h(x_c) − t·u₂^h(y_c)` (zero without the
    /// tangential operators).
    fn slips(&self, u: &[f64]) -> Vec<f64> {
        match self.tangential {
            Some([t1, t2]) => {
                let mut s = t1.gap_contribution(&u[..self.n1]);
                for (s, v) in s.iter_mut().zip(t2.gap_contribution(&u[self.n1..])) {
                    *s += v;
                }
                s
            }
            None => vec![0.0; self.pairs.len()],
        }
    }
}

impl SparseSolves<Mode> for TwoBodies<'_> {
    fn solve_in_place(&mut self, modes: &[Mode], x: MatMut<'_, f64>) -> Result<(), ActiveSetError> {
        self.solve_columns(modes, x)
    }
    fn product(&self, modes: &[Mode], u: &[f64]) -> Vec<f64> {
        self.apply(modes, u)
    }
    fn row_norm(&self) -> f64 {
        self.norm
    }
    fn count_refinement(&mut self) {
        self.stats.refinements += 1;
    }
}

impl ActiveSetSystem for TwoBodies<'_> {
    fn size(&self) -> usize {
        self.pairs.len()
    }
    /// `None` when a body's solve alone does not pass its accuracy check.
    fn free_gap(&mut self) -> Result<Option<Vec<f64>>, ActiveSetError> {
        match self.displacements(&vec![false; self.pairs.len()]) {
            Ok(u) => Ok(Some(self.gaps(&u))),
            Err(ActiveSetError::Solve(_)) => Ok(None),
            Err(e) => Err(e),
        }
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.initial_gap.to_vec()
    }
    fn solve_active(&mut self, active: &[bool]) -> Result<(Vec<f64>, Vec<f64>), ActiveSetError> {
        let modes = closed_modes(active);
        let u = self.displacements_of(&modes)?;
        let (p, _) = self.forces(&modes, &u);
        let mut g = self.gaps(&u);
        for (g, &a) in g.iter_mut().zip(active) {
            if a {
                // Zero up to the solve's round-off; the condition is g_c = 0 exactly.
                *g = 0.0;
            }
        }
        self.last = Some((modes, u));
        Ok((p, g))
    }
    fn reduced_lcp(&mut self, active: &[bool], free: &[usize]) -> Result<Lcp, ActiveSetError> {
        let mut held = closed_modes(active);
        for &c in free {
            held[c] = OPEN;
        }
        let (n, k) = (self.n(), free.len());
        // Column 0: the held problem's own right-hand side; column 1 + j: a unit force pair
        // on free[j] (E₁ on body 1, E₂ on body 2).
        let mut x = Mat::<f64>::zeros(n, k + 1);
        for (i, v) in self.rhs_of(&held).into_iter().enumerate() {
            x[(i, 0)] = v;
        }
        for (j, &c) in free.iter().enumerate() {
            self.add_unit_force(
                [self.bodies[0].operator, self.bodies[1].operator],
                c,
                x.col_mut(j + 1),
            );
        }
        self.solve_columns(&held, x.as_mut())?;
        let q: Vec<f64> = {
            let g = self.gaps(x.col_as_slice(0));
            free.iter().map(|&c| g[c]).collect()
        };
        let mut m = vec![0.0; k * k];
        for j in 0..k {
            let g = self.gap_change(x.col_as_slice(j + 1));
            for (i, &c) in free.iter().enumerate() {
                m[i * k + j] = g[c];
            }
        }
        Lcp::new(k, m, q).map_err(|e| ActiveSetError::Rescue(Box::new(e)))
    }
}

impl TwoBodies<'_> {
    /// Adds the unit force of candidate `c` on both bodies (`ops`: the normal or the
    /// tangential operators) to the column `x`.
    fn add_unit_force(&self, ops: [&BodyOperator; 2], c: usize, mut x: faer::ColMut<'_, f64>) {
        for (op, offset) in [(ops[0], 0), (ops[1], self.n1)] {
            let d = op.direction(c);
            for &(i, w) in &op.owners[c] {
                x[offset + dof(i as usize, Axis::X)] += d[0] * w;
                x[offset + dof(i as usize, Axis::Y)] += d[1] * w;
            }
        }
    }
}

impl FrictionSystem for TwoBodies<'_> {
    fn size(&self) -> usize {
        self.pairs.len()
    }
    fn friction(&self) -> Vec<f64> {
        if self.friction.is_empty() { vec![0.0; self.pairs.len()] } else { self.friction.clone() }
    }
    /// One solve with each body's own factorisation; `None` when one fails its accuracy
    /// check.
    fn free_response(&mut self) -> Result<Option<FreeResponse>, ActiveSetError> {
        let u1 = self.bodies[0].factorisation.solve(&self.rhs[0]);
        let u2 = self.bodies[1].factorisation.solve(&self.rhs[1]);
        match (u1, u2) {
            (Ok(mut u), Ok(u2)) => {
                u.extend(u2);
                Ok(Some((self.gaps(&u), self.slips(&u))))
            }
            _ => Ok(None),
        }
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.initial_gap.to_vec()
    }
    fn solve_states(
        &mut self,
        states: &[ContactState],
        previous: &[f64],
    ) -> Result<StateResponse, ActiveSetError> {
        self.tangential_target.copy_from_slice(previous);
        let modes = self.modes_of(states);
        let u = self.displacements_of(&modes)?;
        let (normal, tangential) = self.forces(&modes, &u);
        let (gap, tangential_displacement) = (self.gaps(&u), self.slips(&u));
        self.last = Some((modes, u));
        Ok(StateResponse { normal, tangential, gap, tangential_displacement })
    }
    fn reduced_problem(
        &mut self,
        states: &[ContactState],
        free: &[usize],
        previous: &[f64],
    ) -> Result<FrictionProblem, ActiveSetError> {
        self.tangential_target.copy_from_slice(previous);
        let mut held = self.modes_of(states);
        for &c in free {
            held[c] = OPEN;
        }
        let (n, k) = (self.n(), free.len());
        let mu = FrictionSystem::friction(self);
        // Column 0: the held problem; 1 + j: unit P on free[j]; 1 + k + j: unit T on free[j]
        // (none where μ = 0: T stays 0 there), each on both bodies.
        let mut x = Mat::<f64>::zeros(n, 2 * k + 1);
        for (i, v) in self.rhs_of(&held).into_iter().enumerate() {
            x[(i, 0)] = v;
        }
        let normal = [self.bodies[0].operator, self.bodies[1].operator];
        for (j, &c) in free.iter().enumerate() {
            self.add_unit_force(normal, c, x.col_mut(j + 1));
            if let (true, Some(tangential)) = (mu[c] > 0.0, self.tangential) {
                self.add_unit_force(tangential, c, x.col_mut(k + j + 1));
            }
        }
        self.solve_columns(&held, x.as_mut())?;
        let base = StateResponse {
            normal: Vec::new(),
            tangential: Vec::new(),
            gap: self.gaps(x.col_as_slice(0)),
            tangential_displacement: self.slips(x.col_as_slice(0)),
        };
        // The responses to unit forces: no g0.
        let columns: Vec<StateResponse> = (1..=2 * k)
            .map(|col| StateResponse {
                normal: Vec::new(),
                tangential: Vec::new(),
                gap: self.gap_change(x.col_as_slice(col)),
                tangential_displacement: self.slips(x.col_as_slice(col)),
            })
            .collect();
        Ok(reduced_blocks(&base, &columns, free, previous, &mu))
    }
}
