//! One body against rigid obstacles in the sparse form of the active-set method
//! ([`RigidObstacle`], docs/method.md §5.1), frictionless and, in [`friction`], with friction
//! (docs/method.md §8).

mod friction;

use super::{
    COLUMN_BYTES, Row, SparseSolves, closed_modes, singular, solve_blocks, solve_refined, sum_rows,
};
use crate::assembly::SystemMatrix;
use crate::contact::BodyOperator;
use crate::geometry::Point;
use crate::lcp::Lcp;
use crate::lcp::active_set::{
    ActiveSetError, ActiveSetSystem, CLOSED, Mode, OPEN, dense_lu, dense_lu_solve,
};
use crate::linear_solve::{ColumnOrdering, Factorisation};
use crate::nodes::{Axis, dof};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Mat, MatMut};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::{HashMap, HashSet};
use std::time::Instant;

/// Memory for one block of update columns solved together (at most 64 columns; fewer on
/// bodies of more than 250k unknowns). A block's solve holds about three copies of it
/// (right-hand sides, solutions, residuals) and both cores solve one each: with 64 columns
/// of 2·10⁶ unknowns that was 1–2 GB above the factors on the 10⁶-node strip
/// (docs/dev/performance.md, "Contact at 10⁶ nodes through the CLI").
const BLOCK_BYTES: usize = 1 << 27;

/// Columns per block of update columns for a body of `n` unknowns ([`BLOCK_BYTES`]).
fn block_columns(n: usize) -> usize {
    (BLOCK_BYTES / (8 * n.max(1))).clamp(1, 64)
}

/// The rank of a low-rank (Woodbury) update above which [`RigidObstacle`] factorises the
/// row-replaced matrix afresh whatever the cost model says: a start from every candidate
/// closed ([`ActiveSetSystem::free_gap`] without `K`'s factors) with more candidates than
/// this factorises at once, so `K`'s factors would serve it nothing
/// ([`RigidObstacle::MAX_UPDATE_RANK`]).
const MAX_UPDATE_RANK: usize = 1024;

/// One update column: its dots with every candidate's row changes, and the column itself
/// when it is stored.
type UpdateColumn = (Vec<f64>, Option<Vec<f64>>);

/// Offsets of each candidate's rows in a `dots` vector (and the total at the end).
fn slots(replacements: &[Replacement]) -> Vec<usize> {
    let mut slot = Vec::with_capacity(replacements.len() + 1);
    let mut next = 0;
    for r in replacements {
        slot.push(next);
        next += r.rows.len();
    }
    slot.push(next);
    slot
}

fn difference(new: &Row, old: &Row) -> Row {
    let neg: Row = old.iter().map(|&(j, v)| (j, -v)).collect();
    sum_rows(new, &neg).into_iter().filter(|e| e.1 != 0.0).collect()
}

/// The right-hand side of a replaced row.
#[derive(Clone, Copy, Debug)]
enum RowRhs {
    /// `−s g0_c` (the gap condition).
    Gap,
    /// `s (s_prev,c + o_c)` (the tangential displacement condition of a sticking candidate).
    Tangential,
    /// `f_b − ratio f_a` (a combination of the node's two balance rows).
    Balance(f64),
}

/// What replacing an active candidate's rows changes: the distinct new rows, and which of
/// them each closed mode uses.
#[derive(Clone, Debug)]
struct Replacement {
    /// `(dof, new row, its right-hand side, new − old row)`; the first is the gap row (on the
    /// normal DOF `a`), the second the frictionless tangential balance when `ν_b ≠ 0`, then the
    /// frictional rows of [`RigidObstacle::set_friction`].
    rows: Vec<(usize, Row, RowRhs, Row)>,
    /// For each closed mode `k ≥ 1` (at `k − 1`), the indices in `rows` that replace the
    /// candidate's rows.
    modes: Vec<Vec<usize>>,
    /// The original row of the normal DOF `a` and `w ν_a` (force recovery).
    normal_row: (Row, f64),
    /// The original row of the other DOF `b` (force recovery with friction).
    other_row: Row,
    /// The DOFs `a` and `b` of the owner node.
    dofs: [usize; 2],
    /// The axes `a`, `b`.
    axes: [Axis; 2],
    /// The owner weight `w`.
    weight: f64,
    /// The frictionless rows (the first `frictionless` entries of `rows`).
    frictionless: usize,
}

/// One row change of a low-rank update: the candidate, the DOF and the terms
/// `(index in the candidate's rows, ±1)` whose difference rows sum to the change.
#[derive(Clone, Debug)]
struct Change {
    candidate: usize,
    dof: usize,
    terms: Vec<(usize, f64)>,
}

/// Work counters of a [`RigidObstacle`].
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct RigidObstacleStats {
    /// Factorisations of row-replaced matrices.
    pub factorisations: usize,
    /// Seconds in them (assembly of the replaced matrix included); not in `summary.json`
    /// (its timings are the stage timings), so that the summary is reproducible.
    #[serde(skip)]
    pub factorisation_seconds: f64,
    /// Single-column solves for the low-rank (Woodbury) updates.
    pub update_columns: usize,
    /// Seconds in them (not in `summary.json`).
    #[serde(skip)]
    pub update_seconds: f64,
    /// Largest rank of a low-rank update used.
    pub max_update_rank: usize,
    /// Solves that needed a step of iterative refinement.
    pub refinements: usize,
}

/// `K`'s own factorisation as a [`RigidObstacle`] holds it: borrowed (the model keeps it), or
/// owned, when the system may release its factors ([`Factorisation::release`]) before it
/// factorises its first row-replaced matrix, so that two factorisations of the body are never
/// alive at once (frictionless only: the frictional path comes back to `K`'s factors), or
/// never made ([`Factorisation::unfactorised`]: the system then starts from every candidate
/// closed). [`RigidObstacle::into_factorisation`] gives an owned one back.
#[derive(Debug)]
pub enum ModelFactors<'a> {
    /// Borrowed from the model, never released.
    Borrowed(&'a Factorisation),
    /// Owned by the system.
    Owned(Box<Factorisation>),
}

impl ModelFactors<'_> {
    fn get(&self) -> &Factorisation {
        match self {
            ModelFactors::Borrowed(f) => f,
            ModelFactors::Owned(f) => f,
        }
    }
}

impl<'a> From<&'a Factorisation> for ModelFactors<'a> {
    fn from(f: &'a Factorisation) -> Self {
        ModelFactors::Borrowed(f)
    }
}

impl From<Factorisation> for ModelFactors<'_> {
    fn from(f: Factorisation) -> Self {
        ModelFactors::Owned(Box::new(f))
    }
}

/// One body against a rigid obstacle, in the sparse form (docs/method.md §5.1): the problem of
/// an active set `A` is `K` with, for every `c ∈ A`, the row of the normal component `a` of its
/// node (the larger `|ν_a|`) replaced by the scaled gap condition `s G_c û = −s g0_c` and the
/// other component's row `b` by `K_b − (ν_b/ν_a) K_a` (the tangential balance, which does not
/// hold `P_c`); the force is recovered from the removed row, `P_c = (K_a û − f_a)/(w ν_a)`,
/// like a reaction. Its matrix is factorised afresh, or, when few candidates changed since
/// the last factorisation, solved by the Woodbury formula on that factorisation (one solve
/// per changed row), whichever the measured costs predict to be cheaper.
///
/// With friction ([`RigidObstacle::set_friction`], [`FrictionSystem`](crate::lcp::active_set::FrictionSystem)) a closed candidate's
/// row `b` is instead the tangential displacement condition (stick) or the combination
/// `(t ± μν)·(K û − f) = 0` of its node's two rows (slip±), and both forces are recovered
/// from the two removed rows, `P = ν·r/w`, `T = t·r/w` (docs/method.md §8).
pub struct RigidObstacle<'a> {
    matrix: &'a SystemMatrix,
    rhs: Vec<f64>,
    operator: &'a BodyOperator,
    initial_gap: Vec<f64>,
    points: Option<&'a [Point]>,
    /// The modes last solved and their displacements.
    last: Option<(Vec<Mode>, Vec<f64>)>,
    /// The factorisation of `K` itself.
    model: ModelFactors<'a>,
    /// `K` was never factorised (given [`Factorisation::unfactorised`]): no free gap (the
    /// active set starts from every candidate closed), and the first solve factorises.
    without_model: bool,
    /// `‖K‖∞`, largest row sum (the gap rows are scaled to the same size).
    norm: f64,
    /// The collocation scale `s` of the gap (and tangential) rows.
    scale: f64,
    replacements: Vec<Replacement>,
    /// The factorisation of the row-replaced matrix of `base_modes` (`None`: `K`'s own).
    base: Option<Box<Factorisation>>,
    base_modes: Vec<Mode>,
    /// `z_r = K_B⁻¹ e_r` reduced to the dot products with every candidate's row changes:
    /// `dots[r][(c, k)] = (new − old row k of c)·z_r`, keyed by the DOF `r`.
    dots: HashMap<usize, Vec<f64>>,
    /// The columns `z_r` themselves while they fit in [`COLUMN_BYTES`] (then a solve with the
    /// update costs one solve with `K_B` instead of two).
    columns: HashMap<usize, Vec<f64>>,
    /// Offsets of each candidate's rows in a `dots` vector.
    slot: Vec<usize>,
    /// `μ_c` (empty: frictionless).
    friction: Vec<f64>,
    /// The right-hand sides `s_prev,c + o_c` of the stick rows.
    tangential_target: Vec<f64>,
    /// `o_c = d·t_c`, the obstacle's tangential displacement.
    tangential_offset: Vec<f64>,
    /// Work counters.
    pub stats: RigidObstacleStats,
}

impl<'a> RigidObstacle<'a> {
    /// The rank of a low-rank update above which the row-replaced matrix is factorised
    /// afresh: a start from more candidates closed than this never solves with `K`'s
    /// factors.
    pub const MAX_UPDATE_RANK: usize = MAX_UPDATE_RANK;

    /// The system of the body with matrix `matrix` (rows replaced by displacement conditions
    /// as assembled), right-hand side `rhs`, its factorisation `factorisation` (borrowed, or
    /// owned to be released when no longer needed: [`ModelFactors`]), the candidates'
    /// `operator` and `initial_gap`; `scale` multiplies the gap rows (the assembly's
    /// collocation scale); `points` are the node positions for the nested-dissection ordering
    /// (`None`: COLAMD, as the finite element model is factorised).
    ///
    /// # Errors
    /// [`ActiveSetError::Unsupported`] when a candidate's force is not on its own node's rows
    /// alone (one owner per candidate, no node shared).
    pub fn new(
        matrix: &'a SystemMatrix,
        rhs: &'a [f64],
        factorisation: impl Into<ModelFactors<'a>>,
        operator: &'a BodyOperator,
        initial_gap: &'a [f64],
        scale: f64,
        points: Option<&'a [Point]>,
    ) -> Result<Self, ActiveSetError> {
        let m = operator.len();
        // Per candidate: its normal ν_c and the axis `a` of its larger component (the row
        // the gap condition replaces) and the other axis `b`.
        let axes = |c: usize| {
            let nu = operator.direction(c);
            if nu[0].abs() >= nu[1].abs() { (Axis::X, Axis::Y) } else { (Axis::Y, Axis::X) }
        };
        let mut owner_of = Vec::with_capacity(m);
        let mut used = HashSet::new();
        for (c, owners) in operator.owners.iter().enumerate() {
            match owners.as_slice() {
                [(i, w)] if *w != 0.0 && used.insert(*i) => owner_of.push((*i as usize, *w)),
                _ => return Err(ActiveSetError::Unsupported { candidate: c }),
            }
        }
        // The candidates' original rows, from the compressed columns.
        let mut wanted: HashMap<usize, Row> = HashMap::new();
        for &(i, _) in &owner_of {
            wanted.insert(dof(i, Axis::X), Vec::new());
            wanted.insert(dof(i, Axis::Y), Vec::new());
        }
        for col in 0..matrix.n {
            for k in matrix.col_ptr[col]..matrix.col_ptr[col + 1] {
                if let Some(row) = wanted.get_mut(&matrix.row_idx[k]) {
                    row.push((col, matrix.values[k]));
                }
            }
        }
        let mut replacements = Vec::with_capacity(m);
        for (c, &(i, w)) in owner_of.iter().enumerate() {
            let nu = operator.direction(c);
            let (a, b) = axes(c);
            let (na, nb) = (nu[a as usize], nu[b as usize]);
            let ratio = nb / na;
            let (ra, rb) = (dof(i, a), dof(i, b));
            let old_a = wanted[&ra].clone();
            let old_b = wanted[&rb].clone();
            let mut gap_row: Row = Vec::new();
            for (&j, &phi) in operator.shapes.support(c).iter().zip(operator.shapes.phi(c)) {
                for ax in Axis::BOTH {
                    let v = scale * nu[ax as usize] * phi;
                    if v != 0.0 {
                        gap_row.push((dof(j as usize, ax), v));
                    }
                }
            }
            let mut rows = vec![(ra, gap_row.clone(), RowRhs::Gap, difference(&gap_row, &old_a))];
            if ratio != 0.0 {
                let scaled: Row = old_a.iter().map(|&(j, v)| (j, -ratio * v)).collect();
                let new_b = sum_rows(&old_b, &scaled);
                let diff = difference(&new_b, &old_b);
                rows.push((rb, new_b, RowRhs::Balance(ratio), diff));
            }
            let frictionless = rows.len();
            replacements.push(Replacement {
                rows,
                modes: vec![(0..frictionless).collect()],
                normal_row: (old_a, w * na),
                other_row: old_b,
                dofs: [ra, rb],
                axes: [a, b],
                weight: w,
                frictionless,
            });
        }
        let slot = slots(&replacements);
        let model: ModelFactors<'a> = factorisation.into();
        Ok(Self {
            without_model: model.get().is_released(),
            matrix,
            rhs: rhs.to_vec(),
            operator,
            initial_gap: initial_gap.to_vec(),
            points,
            last: None,
            model,
            norm: {
                let mut rows = vec![0.0_f64; matrix.n];
                for (k, &r) in matrix.row_idx.iter().enumerate() {
                    rows[r] += matrix.values[k].abs();
                }
                rows.into_iter().fold(0.0, f64::max)
            },
            scale,
            replacements,
            base: None,
            base_modes: vec![OPEN; m],
            dots: HashMap::new(),
            columns: HashMap::new(),
            slot,
            friction: Vec::new(),
            tangential_target: vec![0.0; m],
            tangential_offset: vec![0.0; m],
            stats: RigidObstacleStats::default(),
        })
    }

    /// Sets the Coulomb coefficients `μ_c` (docs/method.md §8): builds each candidate's stick
    /// and slip rows (a candidate with `μ_c = 0` closes frictionless). A change of `μ` drops
    /// the cached update columns, and the row-replaced factorisation when it holds slip rows.
    ///
    /// # Errors
    /// [`ActiveSetError::Unsupported`] when a slip combination `(t ± μν)·r` has no weight on
    /// the row it replaces (`t_b ± μ ν_b = 0`: a normal at 45° with `μ = 1`).
    pub fn set_friction(&mut self, mu: &[f64]) -> Result<(), ActiveSetError> {
        if self.friction == mu {
            return Ok(());
        }
        let scale = self.scale;
        for (c, rep) in self.replacements.iter_mut().enumerate() {
            rep.rows.truncate(rep.frictionless);
            rep.modes.truncate(1);
            if mu[c] == 0.0 {
                let closed = rep.modes[0].clone();
                rep.modes.extend([closed.clone(), closed.clone(), closed]);
                continue;
            }
            let nu = self.operator.direction(c);
            let t = crate::contact::tangent(nu);
            let [ra, rb] = rep.dofs;
            let [a, b] = rep.axes;
            let old_b = &rep.other_row;
            let mut t_row: Row = Vec::new();
            for (&j, &phi) in
                self.operator.shapes.support(c).iter().zip(self.operator.shapes.phi(c))
            {
                for ax in Axis::BOTH {
                    let v = scale * t[ax as usize] * phi;
                    if v != 0.0 {
                        t_row.push((dof(j as usize, ax), v));
                    }
                }
            }
            let stick = rep.rows.len();
            let diff = difference(&t_row, old_b);
            rep.rows.push((rb, t_row, RowRhs::Tangential, diff));
            // Slip±: (t ± μν)·r = 0 with r = (K û − f) on the node's rows, divided by its
            // coefficient on row b: row b + ((t_a ± μν_a)/(t_b ± μν_b)) row a.
            for sign in [1.0, -1.0] {
                let (ca, cb) = (
                    t[a as usize] + sign * mu[c] * nu[a as usize],
                    t[b as usize] + sign * mu[c] * nu[b as usize],
                );
                if cb.abs() <= 1e-8 * ca.abs() {
                    return Err(ActiveSetError::Unsupported { candidate: c });
                }
                let ratio = -ca / cb;
                let scaled: Row = rep.normal_row.0.iter().map(|&(j, v)| (j, -ratio * v)).collect();
                let new_b = sum_rows(old_b, &scaled);
                let diff = difference(&new_b, old_b);
                rep.rows.push((rb, new_b, RowRhs::Balance(ratio), diff));
            }
            rep.modes.push(vec![0, stick]);
            rep.modes.push(vec![0, stick + 1]);
            rep.modes.push(vec![0, stick + 2]);
            debug_assert_eq!(ra, rep.rows[0].0);
        }
        self.friction = mu.to_vec();
        self.slot = slots(&self.replacements);
        self.dots.clear();
        self.columns.clear();
        if self.base_modes.iter().any(|&k| k != OPEN && k != CLOSED) {
            self.base = None;
            self.base_modes = vec![OPEN; self.replacements.len()];
        }
        self.last = None;
        Ok(())
    }

    /// Sets the right-hand side `rhs` of `K û = f` (a step's load, docs/method.md §8).
    pub fn set_rhs(&mut self, rhs: &[f64]) {
        self.rhs.copy_from_slice(rhs);
        self.last = None;
    }

    /// Sets the gaps without displacement `g0_c` (the obstacle's normal displacement
    /// included).
    pub fn set_initial_gap(&mut self, initial_gap: &[f64]) {
        self.initial_gap.copy_from_slice(initial_gap);
        self.last = None;
    }

    /// Sets the obstacle's tangential displacement `o_c = d·t_c`.
    pub fn set_tangential_offset(&mut self, tangential_offset: &[f64]) {
        self.tangential_offset.copy_from_slice(tangential_offset);
        self.last = None;
    }

    /// The right-hand side of a replaced row of candidate `c`.
    fn row_rhs(&self, c: usize, rhs: RowRhs) -> f64 {
        let [ra, rb] = self.replacements[c].dofs;
        match rhs {
            RowRhs::Gap => -self.scale * self.initial_gap[c],
            RowRhs::Tangential => self.scale * self.tangential_target[c],
            RowRhs::Balance(ratio) => self.rhs[rb] - ratio * self.rhs[ra],
        }
    }

    /// The rows (indices in `rows`) of candidate `c` in `mode`.
    fn mode_rows(&self, c: usize, mode: Mode) -> &[usize] {
        if mode == OPEN { &[] } else { &self.replacements[c].modes[mode as usize - 1] }
    }

    /// The right-hand side of the problem of `modes`.
    fn rhs_of(&self, modes: &[Mode]) -> Vec<f64> {
        let mut b = self.rhs.clone();
        for (c, r) in self.replacements.iter().enumerate() {
            for &k in self.mode_rows(c, modes[c]) {
                b[r.rows[k].0] = self.row_rhs(c, r.rows[k].2);
            }
        }
        b
    }

    /// The matrix of `modes`: `K` with the closed candidates' rows replaced.
    fn matrix_of(&self, modes: &[Mode]) -> SystemMatrix {
        let n = self.matrix.n;
        let mut replaced = vec![false; n];
        let mut extra: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for (c, r) in self.replacements.iter().enumerate() {
            for &k in self.mode_rows(c, modes[c]) {
                let (d, row, _, _) = &r.rows[k];
                replaced[*d] = true;
                for &(col, v) in row {
                    extra[col].push((*d, v));
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(self.matrix.row_idx.len());
        let mut values = Vec::with_capacity(self.matrix.values.len());
        col_ptr.push(0);
        let mut column: Vec<(usize, f64)> = Vec::new();
        for col in 0..n {
            column.clear();
            for k in self.matrix.col_ptr[col]..self.matrix.col_ptr[col + 1] {
                if !replaced[self.matrix.row_idx[k]] {
                    column.push((self.matrix.row_idx[k], self.matrix.values[k]));
                }
            }
            column.extend_from_slice(&extra[col]);
            column.sort_by_key(|e| e.0);
            for &(r, v) in &column {
                if row_idx.last() == Some(&r) && row_idx.len() > col_ptr[col] {
                    *values.last_mut().expect("an entry was pushed") += v;
                } else {
                    row_idx.push(r);
                    values.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        SystemMatrix { n, col_ptr, row_idx, values }
    }

    /// The row changes of candidate `c` from mode `from` to mode `to`: the rows of `to`
    /// (less those `from` has too), then the rows of `from` whose DOF `to` leaves original.
    fn row_changes(&self, c: usize, from: Mode, to: Mode, out: &mut Vec<Change>) {
        let rows = &self.replacements[c].rows;
        let (old, new) = (self.mode_rows(c, from), self.mode_rows(c, to));
        for &k in new {
            let dof = rows[k].0;
            match old.iter().find(|&&j| rows[j].0 == dof) {
                Some(&j) if j == k => {}
                Some(&j) => {
                    out.push(Change { candidate: c, dof, terms: vec![(k, 1.0), (j, -1.0)] });
                }
                None => out.push(Change { candidate: c, dof, terms: vec![(k, 1.0)] }),
            }
        }
        for &j in old {
            let dof = rows[j].0;
            if !new.iter().any(|&k| rows[k].0 == dof) {
                out.push(Change { candidate: c, dof, terms: vec![(j, -1.0)] });
            }
        }
    }

    /// Makes the base factorisation suitable for `modes` (refactorising at `modes` when the
    /// low-rank update would cost more) and returns the rows the update must change.
    fn prepare(&mut self, modes: &[Mode]) -> Result<Vec<Change>, ActiveSetError> {
        let mut changed = Vec::new();
        for (c, &mode) in modes.iter().enumerate() {
            if mode != self.base_modes[c] {
                self.row_changes(c, self.base_modes[c], mode, &mut changed);
            }
        }
        let missing = changed.iter().filter(|ch| !self.dots.contains_key(&ch.dof)).count();
        // A deterministic cost model (so that the answer's last bits do not depend on the
        // machine's load): a factorisation costs about `bound_flops`, an update column (a
        // solve in a block of 64) about `bound_nnz` of the current base's analysis. Measured
        // break-even (factorisation time over time per column): 270 columns on the 42k-node
        // strip (the model says 260), 230 on the 19k-node beam (model 595).
        let base = self.base().stats();
        let too_costly = missing as f64 * base.bound_nnz as f64 > base.bound_flops;
        let no_base = self.base.is_none() && self.without_model;
        if changed.len() > MAX_UPDATE_RANK || too_costly || no_base {
            // Drop the previous row-replaced factors (and their columns) first: at most two
            // factorisations are alive at a time; and `K`'s own when this system owns them and
            // nothing will solve with them again (frictionless: only the free gap did): then
            // one is.
            self.base = None;
            self.dots.clear();
            self.columns.clear();
            if let ModelFactors::Owned(f) = &mut self.model {
                if self.friction.is_empty() {
                    f.release();
                }
            }
            let t = Instant::now();
            let matrix = self.matrix_of(modes);
            // With the options of `K`'s own factorisation (its precision).
            let f = match self.points {
                Some(p) => Factorisation::with_options(
                    &matrix,
                    ColumnOrdering::NestedDissection(p),
                    self.model.get().options(),
                )?,
                None => Factorisation::new(&matrix)?,
            };
            drop(matrix);
            self.stats.factorisations += 1;
            self.stats.factorisation_seconds += t.elapsed().as_secs_f64();
            self.base = Some(Box::new(f));
            self.base_modes = modes.to_vec();
            self.dots.clear();
            self.columns.clear();
            return Ok(Vec::new());
        }
        // New columns z_r = K_B⁻¹ e_r, reduced to their dots with every candidate's changes.
        let new: Vec<usize> =
            changed.iter().map(|ch| ch.dof).filter(|r| !self.dots.contains_key(r)).collect();
        if !new.is_empty() {
            let t = Instant::now();
            let n = self.matrix.n;
            // Stored columns serve a solve only when every changed row has one: once a batch
            // is not stored, none of the base's will serve again (but when every changed row
            // came back to an earlier batch's), so they are freed and no later one is kept
            // (0.95 GB of 58 columns on the 10⁶-node strip, docs/dev/performance.md).
            let keep = self.columns.len() == self.dots.len()
                && (self.columns.len() + new.len()) * n * 8 <= COLUMN_BYTES;
            if !keep {
                self.columns.clear();
            }
            let f = self.base();
            let (reps, slot) = (&self.replacements, &self.slot);
            let blocks: Vec<Vec<UpdateColumn>> = new
                .par_chunks(block_columns(n))
                .map(|chunk| {
                    let mut x = Mat::<f64>::zeros(n, chunk.len());
                    for (j, &r) in chunk.iter().enumerate() {
                        x[(r, j)] = 1.0;
                    }
                    f.solve_in_place(x.as_mut());
                    (0..chunk.len())
                        .map(|j| {
                            let z = x.col_as_slice(j);
                            let mut out = vec![0.0; slot[reps.len()]];
                            for (c, rep) in reps.iter().enumerate() {
                                for (k, (_, _, _, diff)) in rep.rows.iter().enumerate() {
                                    out[slot[c] + k] = diff.iter().map(|&(i, v)| v * z[i]).sum();
                                }
                            }
                            (out, keep.then(|| z.to_vec()))
                        })
                        .collect()
                })
                .collect();
            for (r, (d, z)) in new.iter().zip(blocks.into_iter().flatten()) {
                if d.iter().any(|v| !v.is_finite()) {
                    return Err(singular("the factorisation behind the low-rank update"));
                }
                self.dots.insert(*r, d);
                if let Some(z) = z {
                    self.columns.insert(*r, z);
                }
            }
            self.stats.update_columns += new.len();
            self.stats.update_seconds += t.elapsed().as_secs_f64();
        }
        self.stats.max_update_rank = self.stats.max_update_rank.max(changed.len());
        Ok(changed)
    }

    /// The factorisation the low-rank updates start from: the last row-replaced one, or
    /// `K`'s own.
    fn base(&self) -> &Factorisation {
        self.base.as_deref().unwrap_or_else(|| self.model.get())
    }

    /// `K`'s factorisation, owned (released when the active set factorised a row-replaced
    /// matrix: only its statistics are left), or `None` when it was borrowed. When `K` was
    /// never factorised ([`Factorisation::unfactorised`]), the last row-replaced
    /// factorisation instead, released (its statistics and refinement record: the
    /// factorisation the answer was solved with).
    pub fn into_factorisation(self) -> Option<Factorisation> {
        let RigidObstacle { model, base, without_model, .. } = self;
        match (model, base) {
            (ModelFactors::Owned(_), Some(mut last)) if without_model => {
                last.release();
                Some(*last)
            }
            (ModelFactors::Owned(f), _) => Some(*f),
            (ModelFactors::Borrowed(_), _) => None,
        }
    }

    /// `change · x` for a row change (the sum of its terms' difference rows).
    fn change_dot(&self, ch: &Change, x: &[f64]) -> f64 {
        let rows = &self.replacements[ch.candidate].rows;
        let mut terms = ch
            .terms
            .iter()
            .map(|&(k, s)| s * rows[k].3.iter().map(|&(i, v)| v * x[i]).sum::<f64>());
        let first = terms.next().unwrap_or(0.0);
        terms.fold(first, |a, b| a + b)
    }

    /// Solves the problem of `modes` for the columns of `x` (`n × k`, overwritten).
    fn solve_columns(
        &mut self,
        modes: &[Mode],
        mut x: MatMut<'_, f64>,
    ) -> Result<(), ActiveSetError> {
        let changed = self.prepare(modes)?;
        let f = self.base();
        let cols = x.ncols();
        // y = K_B⁻¹ b, in parallel over blocks of 64 columns.
        solve_blocks(f, x.rb_mut());
        if changed.is_empty() {
            return Ok(());
        }
        // Woodbury: K_A = K_B + U Dᵀ with U = [e_r], rows d_r = (new − old):
        // K_A⁻¹ b = K_B⁻¹ (b − U C⁻¹ Dᵀ y), C = I + Dᵀ K_B⁻¹ U.
        let k = changed.len();
        let mut cap = vec![0.0; k * k];
        for (j, cj) in changed.iter().enumerate() {
            let dots = &self.dots[&cj.dof];
            for (i, ci) in changed.iter().enumerate() {
                let s = self.slot[ci.candidate];
                let mut terms = ci.terms.iter().map(|&(ki, si)| si * dots[s + ki]);
                let first = terms.next().unwrap_or(0.0);
                let v = terms.fold(first, |a, b| a + b);
                cap[j * k + i] = v + if i == j { 1.0 } else { 0.0 };
            }
        }
        let perm = dense_lu(&mut cap, k).ok_or_else(|| singular("the low-rank update"))?;
        let stored = changed.iter().all(|ch| self.columns.contains_key(&ch.dof));
        let mut corrections = Mat::<f64>::zeros(self.matrix.n, cols);
        for col in 0..cols {
            let y = x.rb().col(col);
            let y: Vec<f64> = (0..y.nrows()).map(|i| y[i]).collect();
            let mut t: Vec<f64> = changed.iter().map(|ch| self.change_dot(ch, &y)).collect();
            dense_lu_solve(&cap, &perm, k, &mut t);
            for (ch, v) in changed.iter().zip(&t) {
                if stored {
                    // K_B⁻¹ U v from the stored columns.
                    let z = &self.columns[&ch.dof];
                    let mut out = corrections.col_mut(col);
                    for (i, zi) in z.iter().enumerate() {
                        out[i] += zi * v;
                    }
                } else {
                    corrections[(ch.dof, col)] = *v;
                }
            }
        }
        // x = y − K_B⁻¹ (U v).
        if !stored {
            solve_blocks(f, corrections.as_mut());
        }
        for col in 0..cols {
            for i in 0..self.matrix.n {
                x[(i, col)] -= corrections[(i, col)];
            }
        }
        Ok(())
    }

    /// `P_c` for the active candidates from their removed rows, given `û`.
    fn forces(&self, modes: &[Mode], u: &[f64]) -> Vec<f64> {
        self.forces_with(modes, u, &self.rhs)
    }

    /// [`RigidObstacle::forces`] with the right-hand side `rhs` of the removed rows (zero for
    /// the forces' rates, [`RigidObstacle::force_rate`]).
    fn forces_with(&self, modes: &[Mode], u: &[f64], rhs: &[f64]) -> Vec<f64> {
        self.replacements
            .iter()
            .enumerate()
            .map(|(c, r)| {
                if modes[c] == OPEN {
                    return 0.0;
                }
                let (row, wn) = &r.normal_row;
                (row.iter().map(|&(j, v)| v * u[j]).sum::<f64>() - rhs[r.dofs[0]]) / wn
            })
            .collect()
    }

    /// The displacements `û` of the problem of `active`: those of the last
    /// [`ActiveSetSystem::solve_active`] when it solved `active` (the final answer's, after
    /// [`solve`](crate::lcp::active_set::solve)), else a new solve. They satisfy `K û = f + E P` with the forces of that
    /// solve, so they are the displacements of the contact solution; recomputing them as
    /// `K⁻¹(f + E P)` would carry the round-off of `P` (recovered from a row residual) into
    /// the closed gaps, and fails where `K` alone is too ill-conditioned.
    ///
    /// # Errors
    /// A failed solve.
    pub fn final_displacements(&mut self, active: &[bool]) -> Result<Vec<f64>, ActiveSetError> {
        let modes = closed_modes(active);
        self.final_displacements_of(&modes)
    }

    /// [`RigidObstacle::final_displacements`] for candidate modes.
    fn final_displacements_of(&mut self, modes: &[Mode]) -> Result<Vec<f64>, ActiveSetError> {
        match self.last.take() {
            Some((a, u)) if a == modes => Ok(u),
            _ => self.displacements_of(modes),
        }
    }

    /// Solves the problem of `active` for `û`.
    ///
    /// # Errors
    /// A failed solve.
    ///
    /// One step of iterative refinement against the row-replaced matrix follows the solve
    /// when its normwise backward error is above 1e-14 (the low-rank update loses digits).
    pub fn displacements(&mut self, active: &[bool]) -> Result<Vec<f64>, ActiveSetError> {
        self.displacements_of(&closed_modes(active))
    }

    fn displacements_of(&mut self, modes: &[Mode]) -> Result<Vec<f64>, ActiveSetError> {
        let b = self.rhs_of(modes);
        solve_refined(self, modes, &b)
    }

    /// The matrix of `modes` times `u`.
    fn apply(&self, modes: &[Mode], u: &[f64]) -> Vec<f64> {
        let mut y = crate::linear_solve::mul(self.matrix, u);
        for (c, r) in self.replacements.iter().enumerate() {
            for &k in self.mode_rows(c, modes[c]) {
                let (d, row, _, _) = &r.rows[k];
                y[*d] = row.iter().map(|&(j, v)| v * u[j]).sum();
            }
        }
        y
    }
}

impl SparseSolves<Mode> for RigidObstacle<'_> {
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

impl ActiveSetSystem for RigidObstacle<'_> {
    fn size(&self) -> usize {
        self.replacements.len()
    }
    /// `None` when the solve with `K` does not pass its accuracy check (the static-pivoting
    /// LU returns NaN then: a strip 500 × 1 clamped at one end is such a case), and when `K`
    /// was never factorised (the pipeline does not when this start from every candidate
    /// closed would factorise the row-replaced matrix at once, more than
    /// [`RigidObstacle::MAX_UPDATE_RANK`] candidates).
    fn free_gap(&mut self) -> Result<Option<Vec<f64>>, ActiveSetError> {
        if self.without_model && self.base.is_none() {
            return Ok(None);
        }
        let u = match self.displacements(&vec![false; self.replacements.len()]) {
            Ok(u) => u,
            Err(ActiveSetError::Solve(_)) => return Ok(None),
            Err(e) => return Err(e),
        };
        let mut q = self.operator.gap_contribution(&u);
        for (g, g0) in q.iter_mut().zip(&self.initial_gap) {
            *g += g0;
        }
        Ok(Some(q))
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.initial_gap.to_vec()
    }
    fn solve_active(&mut self, active: &[bool]) -> Result<(Vec<f64>, Vec<f64>), ActiveSetError> {
        let modes = closed_modes(active);
        let u = self.displacements_of(&modes)?;
        let p = self.forces(&modes, &u);
        self.last = Some((modes, u.clone()));
        let mut g = self.operator.gap_contribution(&u);
        for (c, (g, g0)) in g.iter_mut().zip(&self.initial_gap).enumerate() {
            *g += g0;
            if active[c] {
                // Zero up to the solve's round-off; the condition is g_c = 0 exactly.
                *g = 0.0;
            }
        }
        Ok((p, g))
    }
    fn reduced_lcp(&mut self, active: &[bool], free: &[usize]) -> Result<Lcp, ActiveSetError> {
        let mut held = closed_modes(active);
        for &c in free {
            held[c] = OPEN;
        }
        let (n, k) = (self.matrix.n, free.len());
        // Column 0: the held problem's own right-hand side; column 1 + j: unit force on free[j].
        let mut x = Mat::<f64>::zeros(n, k + 1);
        for (i, v) in self.rhs_of(&held).into_iter().enumerate() {
            x[(i, 0)] = v;
        }
        for (j, &c) in free.iter().enumerate() {
            let d = self.operator.direction(c);
            for &(i, w) in &self.operator.owners[c] {
                x[(dof(i as usize, Axis::X), j + 1)] += d[0] * w;
                x[(dof(i as usize, Axis::Y), j + 1)] += d[1] * w;
            }
        }
        self.solve_columns(&held, x.as_mut())?;
        let shapes = &self.operator.shapes;
        let gap_of = |col: &[f64], c: usize| {
            let u = shapes.interpolate(c, col);
            let d = self.operator.direction(c);
            d[0] * u[0] + d[1] * u[1]
        };
        let q: Vec<f64> =
            free.iter().map(|&c| self.initial_gap[c] + gap_of(x.col_as_slice(0), c)).collect();
        let mut m = vec![0.0; k * k];
        for (j, _) in free.iter().enumerate() {
            let col = x.col_as_slice(j + 1);
            for (i, &c) in free.iter().enumerate() {
                m[i * k + j] = gap_of(col, c);
            }
        }
        Lcp::new(k, m, q).map_err(|e| ActiveSetError::Rescue(Box::new(e)))
    }
}
