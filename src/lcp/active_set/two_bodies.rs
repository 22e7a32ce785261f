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
//! [`RigidObstacle`]: super::RigidObstacle

use super::{
    ActiveSetError, ActiveSetSystem, COLUMN_BYTES, Lcp, RigidObstacleStats, Row, SparseSolves,
    dense_lu, dense_lu_solve, singular, solve_blocks, solve_refined, sum_rows,
};
use crate::assembly::SystemMatrix;
use crate::contact::BodyOperator;
use crate::geometry::Point;
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

/// A rank-one change `u dᵀ` of the matrix: `u` sparse (`(DOF, value)`), `d` a sparse row.
struct Update {
    u: Vec<(usize, f64)>,
    d: Row,
}

/// Two elastic bodies in contact, in the sparse form of the module documentation.
pub struct TwoBodies<'a> {
    bodies: [BodyParts<'a>; 2],
    /// Body 1's DOFs (body 2's follow them).
    n1: usize,
    initial_gap: &'a [f64],
    /// Both bodies' node positions, when both have them.
    points: Option<Vec<Point>>,
    /// Per candidate: the rank-one terms `u dᵀ` its activation adds to the matrix.
    changes: Vec<Vec<Update>>,
    /// Per candidate: `(DOF, value)` its activation adds to the right-hand side.
    rhs_changes: Vec<Vec<(usize, f64)>>,
    /// Per candidate: body 1's original normal row, its right-hand side and `w ν_a`.
    force_rows: Vec<(Row, f64, f64)>,
    /// `‖diag(K₁, K₂)‖∞`.
    norm: f64,
    /// `None`: the bodies' own factorisations (the active set of `base_active` is empty).
    base: Option<Box<Factorisation>>,
    base_active: Vec<bool>,
    /// `K_B⁻¹ u` by candidate and term.
    columns: HashMap<(usize, usize), Vec<f64>>,
    last: Option<(Vec<bool>, Vec<f64>)>,
    /// Work counters (the same as a rigid obstacle's).
    pub stats: RigidObstacleStats,
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
        for (c, &(i, _)) in owner_of.iter().enumerate() {
            wanted.insert(dof(i, axes(c).0), Vec::new());
        }
        let k1 = first.matrix;
        for col in 0..k1.n {
            for k in k1.col_ptr[col]..k1.col_ptr[col + 1] {
                if let Some(row) = wanted.get_mut(&k1.row_idx[k]) {
                    row.push((col, k1.values[k]));
                }
            }
        }
        let f1 = first.rhs;
        let mut changes = Vec::with_capacity(m);
        let mut rhs_changes = Vec::with_capacity(m);
        let mut force_rows = Vec::with_capacity(m);
        for (c, &(i, w)) in owner_of.iter().enumerate() {
            let ((a, b), d1, d2) = (axes(c), op1.direction(c), op2.direction(c));
            let (na, ratio) = (d1[a as usize], d1[b as usize] / d1[a as usize]);
            let (ra, rb) = (dof(i, a), dof(i, b));
            let old_a = wanted[&ra].clone();
            let mut gap_row: Row = Vec::new();
            for (op, offset) in [(op1, 0), (op2, n1)] {
                for (&j, &phi) in op.shapes.support(c).iter().zip(op.shapes.phi(c)) {
                    for ax in Axis::BOTH {
                        let v = scale * op.direction(c)[ax as usize] * phi;
                        if v != 0.0 {
                            gap_row.push((offset + dof(j as usize, ax), v));
                        }
                    }
                }
            }
            gap_row.sort_by_key(|e| e.0);
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
            let mut rhs = vec![(ra, -scale * initial_gap[c] - f1[ra])];
            rhs.extend(u.iter().map(|&(r, k)| (r, k * f1[ra])));
            let mut terms = vec![Update { u: vec![(ra, 1.0)], d: sum_rows(&gap_row, &minus_old) }];
            if !u.is_empty() {
                terms.push(Update { u, d: old_a.clone() });
            }
            changes.push(terms);
            rhs_changes.push(rhs);
            force_rows.push((old_a, f1[ra], wn));
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
            n1,
            initial_gap,
            points,
            changes,
            rhs_changes,
            force_rows,
            norm: row_norm(first.matrix).max(row_norm(second.matrix)),
            base: None,
            base_active: vec![false; m],
            columns: HashMap::new(),
            last: None,
            stats: RigidObstacleStats::default(),
        })
    }

    fn n(&self) -> usize {
        self.n1 + self.bodies[1].matrix.n
    }

    /// `[f₁; f₂]` plus the active candidates' additions.
    fn rhs_of(&self, active: &[bool]) -> Vec<f64> {
        let mut b: Vec<f64> =
            self.bodies[0].rhs.iter().chain(self.bodies[1].rhs).copied().collect();
        for (c, rows) in self.rhs_changes.iter().enumerate() {
            if active[c] {
                for &(r, v) in rows {
                    b[r] += v;
                }
            }
        }
        b
    }

    /// The matrix of `active` times `u`.
    fn apply(&self, active: &[bool], u: &[f64]) -> Vec<f64> {
        let mut y = crate::linear_solve::mul(self.bodies[0].matrix, &u[..self.n1]);
        y.extend(crate::linear_solve::mul(self.bodies[1].matrix, &u[self.n1..]));
        for (c, terms) in self.changes.iter().enumerate() {
            if active[c] {
                for t in terms {
                    let dot = t.d.iter().map(|&(j, v)| v * u[j]).sum::<f64>();
                    for &(r, k) in &t.u {
                        y[r] += k * dot;
                    }
                }
            }
        }
        y
    }

    /// The combined matrix of `active` (entries that cancel exactly are dropped).
    fn matrix_of(&self, active: &[bool]) -> SystemMatrix {
        let n = self.n();
        let mut extra: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for (c, terms) in self.changes.iter().enumerate() {
            if active[c] {
                for t in terms {
                    for &(col, v) in &t.d {
                        extra[col].extend(t.u.iter().map(|&(r, k)| (r, k * v)));
                    }
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

    /// Makes the base suitable for `active` (refactorising when the update would cost more)
    /// and returns the update's terms `(candidate, term, sign)`.
    fn prepare(&mut self, active: &[bool]) -> Result<Vec<(usize, usize, f64)>, ActiveSetError> {
        let terms: Vec<(usize, usize, f64)> = (0..active.len())
            .filter(|&c| active[c] != self.base_active[c])
            .flat_map(|c| {
                let sign = if active[c] { 1.0 } else { -1.0 };
                (0..self.changes[c].len()).map(move |k| (c, k, sign))
            })
            .collect();
        let new: Vec<(usize, usize)> = terms
            .iter()
            .map(|&(c, k, _)| (c, k))
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
        if terms.len() > 1024 || too_costly || too_big {
            self.base = None;
            self.columns.clear();
            let t = Instant::now();
            let matrix = self.matrix_of(active);
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
            self.base_active = active.to_vec();
            return Ok(Vec::new());
        }
        if !new.is_empty() {
            let t = Instant::now();
            let mut x = Mat::<f64>::zeros(n, new.len());
            for (j, &(c, k)) in new.iter().enumerate() {
                for &(r, v) in &self.changes[c][k].u {
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
        self.stats.max_update_rank = self.stats.max_update_rank.max(terms.len());
        Ok(terms)
    }

    /// Solves the problem of `active` for the columns of `x` (`n × k`, overwritten):
    /// Woodbury, `K_A = K_B + Σ_j s_j u_j d_jᵀ`, `K_A⁻¹ b = y − Σ_j s_j z_j v_j` with
    /// `y = K_B⁻¹ b`, `z_j = K_B⁻¹ u_j`, `C v = (d_jᵀ y)_j`, `C_ij = δ_ij + s_j d_iᵀ z_j`.
    fn solve_columns(
        &mut self,
        active: &[bool],
        mut x: MatMut<'_, f64>,
    ) -> Result<(), ActiveSetError> {
        let terms = self.prepare(active)?;
        self.base_solve(x.rb_mut());
        if terms.is_empty() {
            return Ok(());
        }
        let k = terms.len();
        let dot = |row: &Row, z: &[f64]| row.iter().map(|&(j, v)| v * z[j]).sum::<f64>();
        let d = |(c, t, _): (usize, usize, f64)| &self.changes[c][t].d;
        let mut cap = vec![0.0; k * k];
        for (j, &(cj, tj, sj)) in terms.iter().enumerate() {
            let z = &self.columns[&(cj, tj)];
            for (i, &ti) in terms.iter().enumerate() {
                cap[j * k + i] = sj * dot(d(ti), z) + if i == j { 1.0 } else { 0.0 };
            }
        }
        let perm = dense_lu(&mut cap, k).ok_or_else(|| singular("the low-rank update"))?;
        for col in 0..x.ncols() {
            let y: Vec<f64> = x.rb().col(col).iter().copied().collect();
            let mut v: Vec<f64> = terms.iter().map(|&t| dot(d(t), &y)).collect();
            dense_lu_solve(&cap, &perm, k, &mut v);
            let mut out = x.rb_mut().col_mut(col);
            for (&(c, t, s), v) in terms.iter().zip(&v) {
                for (i, zi) in self.columns[&(c, t)].iter().enumerate() {
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
        let b = self.rhs_of(active);
        solve_refined(self, active, &b)
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
        let mut u = match self.last.take() {
            Some((a, u)) if a == active => u,
            _ => self.displacements(active)?,
        };
        let u2 = u.split_off(self.n1);
        Ok((u, u2))
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
}

impl SparseSolves for TwoBodies<'_> {
    fn solve_in_place(
        &mut self,
        active: &[bool],
        x: MatMut<'_, f64>,
    ) -> Result<(), ActiveSetError> {
        self.solve_columns(active, x)
    }
    fn product(&self, active: &[bool], u: &[f64]) -> Vec<f64> {
        self.apply(active, u)
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
        self.changes.len()
    }
    /// `None` when a body's solve alone does not pass its accuracy check.
    fn free_gap(&mut self) -> Result<Option<Vec<f64>>, ActiveSetError> {
        match self.displacements(&vec![false; self.size()]) {
            Ok(u) => Ok(Some(self.gaps(&u))),
            Err(ActiveSetError::Solve(_)) => Ok(None),
            Err(e) => Err(e),
        }
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.initial_gap.to_vec()
    }
    fn solve_active(&mut self, active: &[bool]) -> Result<(Vec<f64>, Vec<f64>), ActiveSetError> {
        let u = self.displacements(active)?;
        let p: Vec<f64> = self
            .force_rows
            .iter()
            .enumerate()
            .map(|(c, (row, f, wn))| {
                if active[c] {
                    (row.iter().map(|&(j, v)| v * u[j]).sum::<f64>() - f) / wn
                } else {
                    0.0
                }
            })
            .collect();
        let mut g = self.gaps(&u);
        for (g, &a) in g.iter_mut().zip(active) {
            if a {
                // Zero up to the solve's round-off; the condition is g_c = 0 exactly.
                *g = 0.0;
            }
        }
        self.last = Some((active.to_vec(), u));
        Ok((p, g))
    }
    fn reduced_lcp(&mut self, active: &[bool], free: &[usize]) -> Result<Lcp, ActiveSetError> {
        let mut held = active.to_vec();
        for &c in free {
            held[c] = false;
        }
        let (n, k) = (self.n(), free.len());
        // Column 0: the held problem's own right-hand side; column 1 + j: a unit force pair
        // on free[j] (E₁ on body 1, E₂ on body 2).
        let mut x = Mat::<f64>::zeros(n, k + 1);
        for (i, v) in self.rhs_of(&held).into_iter().enumerate() {
            x[(i, 0)] = v;
        }
        for (j, &c) in free.iter().enumerate() {
            for (body, offset) in [(&self.bodies[0], 0), (&self.bodies[1], self.n1)] {
                let d = body.operator.direction(c);
                for &(i, w) in &body.operator.owners[c] {
                    x[(offset + dof(i as usize, Axis::X), j + 1)] += d[0] * w;
                    x[(offset + dof(i as usize, Axis::Y), j + 1)] += d[1] * w;
                }
            }
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
