//! Several elastic bodies and contact pairs for the active-set method (docs/method.md §5.1,
//! §4.5): the unknowns are all bodies' nodal parameters `(û₁, …, û_N)` (concatenated, body
//! `b`'s from its offset), the matrix of an active set is the block-diagonal
//! `diag(K₁, …, K_N)` with, for every active candidate `c` of a pair (owner node `i` on the
//! pair's candidate body `b`, normal component `a`, `P_c = (K_b,a û_b − f_b,a)/(w ν_a)`
//! recovered from the removed row):
//!
//! - body `b`'s row `a` replaced by the scaled gap condition `s (G_b,c û_b + G_t,c û_t) =
//!   −s g0_c` (against a rigid obstacle `s G_b,c û_b = −s g0_c`);
//! - body `b`'s row `b` by `K_b,b − (ν_b/ν_a) K_b,a` (the tangential balance without `P_c`);
//! - each row `r` of the target body `t` that receives `d_t w_j P_c` (the target's owner
//!   cells) gains `−(d_t w_j)_r/(w ν_a) · K_b,a` in body `b`'s columns (and the same multiple
//!   of `f_b,a` on the right-hand side): `K_t û_t = f_t + E_t P` with `P_c` in terms of `û_b`.
//!
//! Per candidate the change is of rank two, `e_a (gap row − K_b,a)ᵀ + v_c K_b,aᵀ` (`v_c` holds
//! `−ν_b/ν_a` at row `b` and the target rows' coefficients; the changes of two candidates
//! add where their target cells overlap), so the problem of an active set is the last
//! factorised matrix plus a low-rank term, solved by the Woodbury formula as for
//! [`RigidObstacle`] with two columns per changed candidate. The first base is the bodies' own
//! factorisations (no new factorisation until the update would cost more than one), later
//! bases a factorisation of the combined matrix. No dense `M = G K⁻¹ E` is formed.
//!
//! A node may own one candidate (over all pairs of its body), and a node that owns one may
//! not receive another pair's target forces (a body one node thick, or a corner node shared
//! by two contact edges): its removed row would hold two unknown forces
//! ([`ActiveSetError::OwnerConflict`]). [`Bodies::sharing_corners`] (the time stepping's)
//! takes a node owning candidates of two pairs (a corner node of two contact edges) when both
//! are frictionless and their normals lie along different axes: each then replaces its own
//! row of the node, whose residual holds its force alone, and the two candidates' changes add
//! (`shared_owners`); normals off the axes, or friction on either (the frictional modes use
//! both rows), stay refused. [`TwoBodies`] is the case of two bodies and one pair.
//!
//! With friction (any number of pairs: [`Bodies::set_friction`], [`FrictionSystem`]) a
//! candidate is open, closed
//! (frictionless, the terms above), sticking or slipping along `±t`, as against a rigid
//! obstacle: both forces come from the residuals `r` of the owner node's two rows of its body,
//! `P = ν·r/w`, `T = t·r/w`; a target body's owner rows gain `(w_j/w)(d₂ νᵀ + d₂ₜ tᵀ) r` (two
//! terms `u_a K_aᵀ`, `u_b K_bᵀ`), row `a` is the gap row and row `b` the relative tangential
//! displacement condition (stick) or `(t ± μν)·r = 0` (slip±). Each mode is a set of rank-one
//! terms; modes share terms and update columns (`K_B⁻¹ e_a`, `K_B⁻¹ e_b`, `K_B⁻¹ u_a`,
//! `K_B⁻¹ u_b`), so a change between stick and slip is of rank one and a closing candidate of
//! rank four (docs/method.md §5.1 "Friction").
//!
//! [`RigidObstacle`]: super::RigidObstacle

use super::{
    COLUMN_BYTES, RigidObstacleStats, Row, SparseSolves, closed_modes, singular, solve_blocks,
    solve_refined, sum_rows,
};
use crate::assembly::SystemMatrix;
use crate::contact::BodyOperator;
use crate::geometry::Point;
use crate::lcp::Lcp;
use crate::lcp::active_set::{
    ActiveSetError, ActiveSetSystem, CLOSED, FreeResponse, FrictionSystem, Mode, OPEN,
    StateResponse, dense_lu, dense_lu_solve, mode_of, reduced_blocks,
};
use crate::lcp::friction::{ContactState, FrictionProblem};
use crate::linear_solve::{ColumnOrdering, Factorisation};
use crate::nodes::{Axis, dof};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Mat, MatMut};
use std::collections::HashMap;
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
    /// The body's contact operator (`G` rows, `E` columns) as [`TwoBodies::two`] reads it
    /// (the candidate body's, resp. the target's); [`Bodies::new`] takes the operators from
    /// its [`PairParts`] instead.
    pub operator: &'a BodyOperator,
    /// Node positions (`matrix.n == 2 points.len()`), or `None`.
    pub points: Option<&'a [Point]>,
}

/// One contact pair of [`Bodies`]: the body that carries its candidates and their operator,
/// the target body's operator at the paired points (`None`: rigid obstacles), and the
/// collocation scale of the candidate body (which multiplies the gap rows).
#[derive(Clone, Copy)]
pub struct PairParts<'a> {
    /// Index of the candidate body in [`Bodies::new`]'s `bodies`.
    pub body: usize,
    /// The candidates' operator on `body` (one owner node per candidate).
    pub operator: &'a BodyOperator,
    /// The target body's index and operator, or `None` against rigid obstacles.
    pub target: Option<(usize, &'a BodyOperator)>,
    /// The collocation scale `s` of `body`.
    pub scale: f64,
}

/// The right-hand side that goes with a rank-one term `u dᵀ`: `u` times this value.
#[derive(Clone, Copy, Debug)]
enum TermRhs {
    /// `−s g0_c − f_a` (the gap row replaces the candidate body's row `a`).
    Gap,
    /// `s s_prev,c − f_b` (the stick row replaces the candidate body's row `b`).
    Tangential,
    /// `k f_r` (the term's row is `k K_r`).
    Row(f64, usize),
}

/// A rank-one term `u dᵀ` of a candidate's change: `u` is one of the candidate's vectors
/// ([`Pair::us`]), `d` a sparse row.
struct Term {
    u: usize,
    d: Row,
    rhs: TermRhs,
}

/// What a candidate's modes change in `diag(K₁, …, K_N)`: the distinct vectors `u`, the
/// terms, and which terms each closed mode uses (modes that share a term share its update
/// column). DOFs are global (offset by the body's).
struct Pair {
    /// Sparse vectors `(DOF, value)`.
    us: Vec<Vec<(usize, f64)>>,
    terms: Vec<Term>,
    /// For each closed mode `k ≥ 1` (at `k − 1`), the indices in `terms` it adds.
    modes: Vec<Vec<usize>>,
    /// The frictionless vectors and terms (the first entries of `us`, `terms`).
    frictionless: (usize, usize),
    /// The candidate body's original rows `a`, `b` of the owner node.
    rows: [Row; 2],
    /// Their DOFs.
    dofs: [usize; 2],
    /// Their axes.
    axes: [Axis; 2],
    /// The owner weight `w`.
    weight: f64,
    /// `w ν_a`.
    wn: f64,
    /// The contact pair (index in `Bodies::contact`) and the candidate's index in it.
    contact: (usize, usize),
    /// The collocation scale `s` of its gap and stick rows.
    scale: f64,
}

/// One column of the low-rank update: candidate `c`'s vector `us[u]` times `sign`, and the
/// terms `(index, ±1)` whose rows sum to the change of the rows it multiplies.
struct Group {
    c: usize,
    u: usize,
    sign: f64,
    terms: Vec<(usize, f64)>,
}

/// Several elastic bodies and contact pairs, in the sparse form of the module documentation.
pub struct Bodies<'a> {
    bodies: Vec<BodyParts<'a>>,
    /// `[f₁; …; f_N]` (the bodies' right-hand sides; [`Bodies::set_body_load`] changes
    /// them).
    rhs: Vec<f64>,
    /// Body `b`'s DOFs are `offsets[b]..offsets[b + 1]`.
    offsets: Vec<usize>,
    /// The contact pairs; their candidates are numbered in turn.
    contact: Vec<PairParts<'a>>,
    initial_gap: Vec<f64>,
    /// All bodies' node positions, when every body has them.
    points: Option<Vec<Point>>,
    /// Per candidate: the changes of its modes.
    pairs: Vec<Pair>,
    /// `‖diag(K₁, …, K_N)‖∞`.
    norm: f64,
    /// `None`: the bodies' own factorisations (every candidate of `base_modes` is open).
    base: Option<Box<Factorisation>>,
    base_modes: Vec<Mode>,
    /// `K_B⁻¹ u` by candidate and vector.
    columns: HashMap<(usize, usize), Vec<f64>>,
    /// The LU of the Woodbury capacitance matrix and its row permutation, with the modes it
    /// was built for (valid while the base and the columns are: a time stepping solves the
    /// same modes step after step, and rebuilding it costs `k²` row products and `k³/3`).
    capacitance: Option<(Vec<Mode>, Vec<f64>, Vec<usize>)>,
    last: Option<(Vec<Mode>, Vec<f64>)>,
    /// Each pair's tangential operators ([`PairTangential`]), with friction.
    tangential: Option<Vec<PairTangential<'a>>>,
    /// `μ_c` (empty: frictionless).
    friction: Vec<f64>,
    /// The right-hand sides `s_prev,c + o_c` of the stick rows (before the scale `s`).
    tangential_target: Vec<f64>,
    /// `o_c = d·t_c`: a rigid obstacle's tangential displacement at candidate `c` (0 against a
    /// body, or an obstacle that has not moved): the slip is `t·u^h(x_c) − o_c`.
    tangential_offset: Vec<f64>,
    /// Per candidate, the candidate of another pair owned by the same node (a corner node of
    /// two contact edges; [`candidate_owners`]), or `None`.
    shared: Vec<Option<usize>>,
    /// Work counters (the same as a rigid obstacle's).
    pub stats: RigidObstacleStats,
}

/// A pair's tangential operators for [`Bodies::set_friction`]: the candidate body's
/// (direction `t`) and, against a second body, the target's (direction `−t` at the paired
/// points); `None` against rigid obstacles.
pub type PairTangential<'a> = (&'a BodyOperator, Option<&'a BodyOperator>);

/// Two elastic bodies and one contact pair: [`Bodies`] built by [`Bodies::two`].
pub type TwoBodies<'a> = Bodies<'a>;

/// `s Σ d·u^h(x_c)` over `sides` (operator, offset of its body's DOFs) as a row of the
/// combined unknowns, for candidate `c` of the operators: the gap row (normal operators) or
/// the relative tangential displacement row (tangential operators).
fn pair_row(scale: f64, sides: &[(&BodyOperator, usize)], c: usize) -> Row {
    let mut row: Row = Vec::new();
    for &(op, offset) in sides {
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

impl<'a> Bodies<'a> {
    /// The system of `first` (the candidate body: each candidate's force on one node of its
    /// own) and `second` (the target) with one pair between them, the candidates'
    /// `initial_gap`; `scale` multiplies the gap rows (body 1's collocation scale).
    ///
    /// # Errors
    /// As [`Bodies::new`].
    pub fn two(
        first: BodyParts<'a>,
        second: BodyParts<'a>,
        initial_gap: &[f64],
        scale: f64,
    ) -> Result<Self, ActiveSetError> {
        let pair = PairParts {
            body: 0,
            operator: first.operator,
            target: Some((1, second.operator)),
            scale,
        };
        Self::new(vec![first, second], vec![pair], initial_gap)
    }

    /// The system of `bodies` (their `operator` fields are not read) with the contact
    /// `pairs`, whose candidates are numbered pair after pair; `initial_gap` over all of them.
    ///
    /// # Errors
    /// [`ActiveSetError::Unsupported`] when a candidate's force is not on one node of its
    /// body, two candidates share an owner node, a pair's operators disagree on the
    /// candidates, or a body index is out of range; [`ActiveSetError::OwnerConflict`] when a
    /// node that owns a candidate receives target forces of another pair.
    pub fn new(
        bodies: Vec<BodyParts<'a>>,
        contact: Vec<PairParts<'a>>,
        initial_gap: &[f64],
    ) -> Result<Self, ActiveSetError> {
        Self::build(bodies, contact, initial_gap, false)
    }

    /// As [`Bodies::new`], also taking a node that owns candidates of two pairs when both are
    /// frictionless and their normals lie along different axes (`shared_owners`; the time
    /// stepping's per-step system, docs/dev/dynamics.md increment 11; the static paths keep
    /// refusing it, untested there).
    ///
    /// # Errors
    /// As [`Bodies::new`], the shared nodes it takes excepted.
    pub fn sharing_corners(
        bodies: Vec<BodyParts<'a>>,
        contact: Vec<PairParts<'a>>,
        initial_gap: &[f64],
    ) -> Result<Self, ActiveSetError> {
        Self::build(bodies, contact, initial_gap, true)
    }

    fn build(
        bodies: Vec<BodyParts<'a>>,
        contact: Vec<PairParts<'a>>,
        initial_gap: &[f64],
        corners_allowed: bool,
    ) -> Result<Self, ActiveSetError> {
        let (offsets, starts) = numbering(&bodies, &contact, initial_gap)?;
        let m = initial_gap.len();
        let (owner_of, corners) = candidate_owners(&contact, &starts)?;
        if let (Some(&(first, second)), false) = (corners.first(), corners_allowed) {
            let pair = |c: usize| starts.partition_point(|&s| s <= c) - 1;
            return Err(ActiveSetError::OwnerConflict {
                body: contact[pair(first)].body,
                node: owner_of[first].0,
                pair: pair(first),
                other: pair(second),
                what: "owns a candidate of each (a corner node shared by two contact edges)",
            });
        }
        let wanted = owner_rows(&bodies, &contact, &offsets, &starts, &owner_of);
        let mut pairs = Vec::with_capacity(m);
        for (k, pair) in contact.iter().enumerate() {
            for c in 0..pair.operator.len() {
                let owner = owner_of[starts[k] + c];
                pairs.push(replaced_rows(pair, (k, c), owner, &offsets, &wanted));
            }
        }
        let shared = shared_owners(&pairs, &contact, &corners, &offsets, m)?;
        check_target_rows(&pairs, &offsets)?;
        let points =
            bodies.iter().map(|b| b.points).collect::<Option<Vec<_>>>().map(|all| all.concat());
        let norm = bodies.iter().map(|b| max_row_norm(b.matrix)).fold(0.0, f64::max);
        Ok(Self {
            rhs: bodies.iter().flat_map(|b| b.rhs.iter().copied()).collect(),
            bodies,
            offsets,
            contact,
            initial_gap: initial_gap.to_vec(),
            points,
            pairs,
            norm,
            base: None,
            base_modes: vec![OPEN; m],
            columns: HashMap::new(),
            capacitance: None,
            last: None,
            tangential: None,
            friction: Vec::new(),
            tangential_target: vec![0.0; m],
            tangential_offset: vec![0.0; m],
            shared,
            stats: RigidObstacleStats::default(),
        })
    }

    /// Sets the Coulomb coefficients `μ_c` (docs/method.md §8, over all candidates) and each
    /// pair's tangential operators (`tangential[k]`: the candidate body's with direction `t`,
    /// and against a second body the target's with `−t` at the paired points, so that they
    /// read the relative tangential displacement `s`; `None` against rigid obstacles, which do
    /// not move): builds each candidate's stick and slip terms (a candidate with `μ_c = 0`
    /// closes frictionless). A change of `μ` drops the update columns, and the combined
    /// factorisation when it holds frictional modes.
    ///
    /// A closed frictional candidate's force on its body is `w(ν P + t T)`, both recovered from
    /// the residuals `r` of its node's two rows: `P = ν·r/w`, `T = t·r/w`. A target body
    /// receives `w_j (d₂ P + d₂ₜ T)` on the rows of its owner cells, i.e.
    /// `(w_j/w)(d₂ νᵀ + d₂ₜ tᵀ) r`: two terms `u_a K_aᵀ`, `u_b K_bᵀ`. Row `a` is the gap row;
    /// row `b` is the scaled relative tangential displacement `s (t·u^h(x_c) − t·u₂^h(y_c)) =
    /// s s_prev` (stick) or `K_b + (c_a/c_b) K_a` with `c = t ± μν` (slip±, `(t ± μν)·r = 0`):
    /// the term `e_b (stick row − K_b)ᵀ`, resp. `e_b ((c_a/c_b) K_a)ᵀ`, so that a change
    /// between stick and slip is of rank one and a closing candidate of rank four.
    ///
    /// # Errors
    /// [`ActiveSetError::Unsupported`] when a slip combination has no weight on row `b`
    /// (`t_b ± μ ν_b = 0`), `tangential` does not hold one entry per pair, or a pair's target
    /// side and tangential target disagree.
    pub fn set_friction(
        &mut self,
        mu: &[f64],
        tangential: Vec<PairTangential<'a>>,
    ) -> Result<(), ActiveSetError> {
        let agree =
            tangential.len() == self.contact.len()
                && self.contact.iter().zip(&tangential).all(|(p, t)| {
                    p.target.is_some() == t.1.is_some() && t.0.len() == p.operator.len()
                });
        if !agree || mu.len() != self.pairs.len() {
            return Err(ActiveSetError::Unsupported { candidate: 0 });
        }
        let same = self.friction == mu;
        self.tangential = Some(tangential);
        if same {
            return Ok(());
        }
        for (c, &mu_c) in mu.iter().enumerate() {
            self.set_candidate_friction(c, mu_c)?;
        }
        self.friction = mu.to_vec();
        self.columns.clear();
        self.capacitance = None;
        if self.base_modes.iter().any(|&k| k != OPEN && k != CLOSED) {
            self.base = None;
            self.base_modes = vec![OPEN; self.pairs.len()];
        }
        self.last = None;
        Ok(())
    }

    /// Candidate `c`'s stick and slip terms for the coefficient `mu` ([`Bodies::set_friction`]).
    fn set_candidate_friction(&mut self, c: usize, mu: f64) -> Result<(), ActiveSetError> {
        let (k, local) = self.pairs[c].contact;
        let parts = self.contact[k];
        let (t1, t2) = self.tangential.as_ref().expect("set by set_friction")[k];
        let ob = self.offsets[parts.body];
        if let (Some(other), true) = (self.shared[c], mu != 0.0) {
            return Err(ActiveSetError::OwnerConflict {
                body: parts.body,
                node: (self.pairs[c].dofs[0] - ob) / 2,
                pair: k,
                other: self.pairs[other].contact.0,
                what: "owns a candidate of each, the first with friction (a corner node shared by two contact edges, where the first's tangential force and the second's normal force act on one row)",
            });
        }
        // The target side: its DOF offset, normal and tangential operators.
        let target = parts.target.zip(t2).map(|((t, op2), t2)| (self.offsets[t], op2, t2));
        let pair = &mut self.pairs[c];
        let (n_us, n_terms) = pair.frictionless;
        pair.us.truncate(n_us);
        pair.terms.truncate(n_terms);
        pair.modes.truncate(1);
        if mu == 0.0 {
            let closed = pair.modes[0].clone();
            pair.modes.extend([closed.clone(), closed.clone(), closed]);
            return Ok(());
        }
        let (nu, t) = (parts.operator.direction(local), t1.direction(local));
        let [a, b] = pair.axes;
        let [ra, rb] = pair.dofs;
        // The target's rows per unit residual r_x of the candidate body's row x:
        // −(w_j/w)(d₂ ν_x + d₂ₜ t_x).
        let weight = pair.weight;
        let target_rows = |x: Axis| -> Vec<(usize, f64)> {
            let Some((ot, op2, t2)) = target else { return Vec::new() };
            let (d2, d2t) = (op2.direction(local), t2.direction(local));
            let mut u: Row = Vec::new();
            for (owners, d, e) in [(&op2.owners[local], d2, nu), (&t2.owners[local], d2t, t)] {
                for &(j, w2) in owners {
                    for ax in Axis::BOTH {
                        let k = -w2 / weight * d[ax as usize] * e[x as usize];
                        if k != 0.0 {
                            u.push((ot + dof(j as usize, ax), k));
                        }
                    }
                }
            }
            sum_rows(&u, &Vec::new()).into_iter().filter(|e| e.1 != 0.0).collect()
        };
        let minus_b: Row = pair.rows[1].iter().map(|&(j, v)| (j, -v)).collect();
        let mut sides = vec![(t1, ob)];
        if let Some((ot, _, t2)) = target {
            sides.push((t2, ot));
        }
        let stick_row = sum_rows(&pair_row(pair.scale, &sides, local), &minus_b);
        let eb = pair.us.len();
        pair.us.push(vec![(rb, 1.0)]);
        let stick = pair.terms.len();
        pair.terms.push(Term { u: eb, d: stick_row, rhs: TermRhs::Tangential });
        let mut shared = vec![0];
        for (x, r) in [(a, ra), (b, rb)] {
            let u = target_rows(x);
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
                t[a as usize] + sign * mu * nu[a as usize],
                t[b as usize] + sign * mu * nu[b as usize],
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
        Ok(())
    }

    /// Sets the right-hand side `f_b` of body `b`.
    pub fn set_body_load(&mut self, b: usize, rhs: &[f64]) {
        self.rhs[self.offsets[b]..self.offsets[b + 1]].copy_from_slice(rhs);
        self.last = None;
    }

    /// Sets the initial gaps `g0` of all candidates (a search's trial moves them,
    /// docs/method.md §4.7).
    pub fn set_initial_gap(&mut self, initial_gap: &[f64]) {
        self.initial_gap.copy_from_slice(initial_gap);
        self.last = None;
    }

    /// Sets the obstacles' tangential displacement `o_c = d·t_c` per candidate (0 on the
    /// candidates of pairs between bodies; docs/method.md §8).
    pub fn set_tangential_offset(&mut self, offset: &[f64]) {
        self.tangential_offset.copy_from_slice(offset);
        self.last = None;
    }

    /// The stick rows' targets `s_prev,c + o_c`.
    fn set_targets(&mut self, previous: &[f64]) {
        let targets = previous.iter().zip(&self.tangential_offset);
        self.tangential_target.iter_mut().zip(targets).for_each(|(t, (p, o))| *t = p + o);
    }

    /// The rows of body `b` in the combined unknowns.
    pub fn body_range(&self, b: usize) -> std::ops::Range<usize> {
        self.offsets[b]..self.offsets[b + 1]
    }

    fn n(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0)
    }

    /// The terms (indices in `terms`) of candidate `c` in `mode`.
    fn mode_terms(&self, c: usize, mode: Mode) -> &[usize] {
        if mode == OPEN { &[] } else { &self.pairs[c].modes[mode as usize - 1] }
    }

    /// The right-hand side value of a term of candidate `c`.
    fn term_rhs(&self, c: usize, rhs: TermRhs) -> f64 {
        let [ra, rb] = self.pairs[c].dofs;
        let (f1, scale) = (&self.rhs, self.pairs[c].scale);
        match rhs {
            TermRhs::Gap => -scale * self.initial_gap[c] - f1[ra],
            TermRhs::Tangential => scale * self.tangential_target[c] - f1[rb],
            TermRhs::Row(k, r) => k * f1[r],
        }
    }

    /// `[f₁; …; f_N]` plus the closed candidates' additions.
    fn rhs_of(&self, modes: &[Mode]) -> Vec<f64> {
        let mut b = self.rhs.clone();
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
        let mut y = Vec::with_capacity(u.len());
        for (b, body) in self.bodies.iter().enumerate() {
            y.extend(crate::linear_solve::mul(body.matrix, &u[self.body_range(b)]));
        }
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
        let nnz = self.bodies.iter().map(|b| b.matrix.row_idx.len()).sum();
        let mut row_idx = Vec::with_capacity(nnz);
        let mut values = Vec::with_capacity(nnz);
        col_ptr.push(0);
        let mut column: Vec<(usize, f64)> = Vec::new();
        let mut body = 0;
        for (col, extra) in extra.iter().enumerate() {
            column.clear();
            while col >= self.offsets[body + 1] {
                body += 1;
            }
            let (k, offset) = (self.bodies[body].matrix, self.offsets[body]);
            let local = col - offset;
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
                let mut rest = x;
                for (b, body) in self.bodies.iter().enumerate() {
                    let (top, bottom) =
                        rest.split_at_row_mut(self.offsets[b + 1] - self.offsets[b]);
                    solve_blocks(body.factorisation, top);
                    rest = bottom;
                }
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
                let stats: Vec<_> = self.bodies.iter().map(|b| b.factorisation.stats()).collect();
                let nnz: usize = stats.iter().map(|s| s.bound_nnz).sum();
                let flops =
                    stats.iter().skip(1).fold(stats[0].bound_flops, |f, s| f + s.bound_flops);
                (nnz as f64, flops)
            }
        };
        let too_costly = new.len() as f64 * nnz > flops;
        let too_big = (self.columns.len() + new.len()) * n * 8 > COLUMN_BYTES;
        if groups.len() > 1024 || too_costly || too_big {
            self.base = None;
            self.columns.clear();
            self.capacitance = None;
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
        let (cap, perm) = match self.capacitance.take() {
            Some((m, cap, perm)) if m == modes => (cap, perm),
            _ => {
                let mut cap = vec![0.0; k * k];
                for (j, gj) in groups.iter().enumerate() {
                    let z = &self.columns[&(gj.c, gj.u)];
                    for (i, gi) in groups.iter().enumerate() {
                        cap[j * k + i] =
                            gj.sign * self.group_dot(gi, z) + if i == j { 1.0 } else { 0.0 };
                    }
                }
                let perm = dense_lu(&mut cap, k).ok_or_else(|| singular("the low-rank update"))?;
                (cap, perm)
            }
        };
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
        self.capacitance = Some((modes.to_vec(), cap, perm));
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

    /// The displacements of every body (`û_b` at `b`) of the problem of `active`: those of
    /// the last [`ActiveSetSystem::solve_active`] when it solved `active`, else a new solve.
    ///
    /// # Errors
    /// A failed solve.
    pub fn final_body_displacements(
        &mut self,
        active: &[bool],
    ) -> Result<Vec<Vec<f64>>, ActiveSetError> {
        self.final_body_displacements_of(closed_modes(active))
    }

    /// The displacements of every body of the frictional step that settled on `states` (those
    /// of its last solve, else a new solve).
    ///
    /// # Errors
    /// A failed solve.
    pub fn final_body_friction_displacements(
        &mut self,
        states: &[ContactState],
    ) -> Result<Vec<Vec<f64>>, ActiveSetError> {
        let modes = self.modes_of(states);
        self.final_body_displacements_of(modes)
    }

    fn final_body_displacements_of(
        &mut self,
        modes: Vec<Mode>,
    ) -> Result<Vec<Vec<f64>>, ActiveSetError> {
        let u = match self.last.take() {
            Some((a, u)) if a == modes => u,
            _ => self.displacements_of(&modes)?,
        };
        Ok((0..self.bodies.len()).map(|b| u[self.body_range(b)].to_vec()).collect())
    }

    /// The round-off of the frictionless forces of the last solve, per candidate:
    /// `4 ε (Σ_j |K_a,j û_j| + |f_a|) / |w ν_a|` (the removed row's residual loses the digits
    /// `K_a û` and `f_a` share; 0 for an open candidate or before any solve).
    pub fn force_round_off(&self) -> Vec<f64> {
        let Some((modes, u)) = &self.last else { return vec![0.0; self.pairs.len()] };
        let sum = |row: &Row| row.iter().map(|&(j, v)| (v * u[j]).abs()).sum::<f64>();
        self.pairs
            .iter()
            .zip(modes)
            .map(|(pair, &mode)| match mode {
                OPEN => 0.0,
                _ => {
                    let f = self.rhs[pair.dofs[0]].abs();
                    4.0 * f64::EPSILON * (sum(&pair.rows[0]) + f) / pair.wn.abs()
                }
            })
            .collect()
    }

    /// The rates `dP_c/dt` of the frictionless closed set `active` when the initial gaps move
    /// by `−a t` (`along` = `a`): one solve with the closed set's matrix and the right-hand
    /// side `s a_c` on the gap rows, the rates read from the removed rows as the forces are
    /// (docs/method.md §4.7, the slope `a_Aᵀ M_AA⁻¹ a_A` of a held translation's search).
    ///
    /// # Errors
    /// A failed solve.
    pub fn force_rate(
        &mut self,
        active: &[bool],
        along: &[f64],
    ) -> Result<Vec<f64>, ActiveSetError> {
        let modes = closed_modes(active);
        let mut b = vec![0.0; self.n()];
        for (c, pair) in self.pairs.iter().enumerate() {
            if active[c] {
                b[pair.dofs[0]] = pair.scale * along[c];
            }
        }
        let du = solve_refined(self, &modes, &b)?;
        let dot = |row: &Row| row.iter().map(|&(j, v)| v * du[j]).sum::<f64>();
        Ok(self
            .pairs
            .iter()
            .zip(active)
            .map(|(pair, &a)| if a { dot(&pair.rows[0]) / pair.wn } else { 0.0 })
            .collect())
    }

    /// The mode of each candidate in `states`.
    fn modes_of(&self, states: &[ContactState]) -> Vec<Mode> {
        let mu = |c: usize| self.friction.get(c).copied().unwrap_or(0.0);
        states.iter().enumerate().map(|(c, &s)| mode_of(mu(c), s)).collect()
    }

    /// `(P_c, T_c)` of `modes` from body 1's rows: open 0; frictionless closed
    /// `P = (K₁_a û₁ − f₁_a)/(w ν_a)`, `T = 0`; frictional `P = ν·r/w`, `T = t·r/w`.
    fn forces(&self, modes: &[Mode], u: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let f1 = &self.rhs;
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
                    let (k, local) = pair.contact;
                    let nu = self.contact[k].operator.direction(local);
                    let tc = self
                        .tangential
                        .as_ref()
                        .map_or([0.0, 0.0], |ops| ops[k].0.direction(local));
                    p.push((nu[0] * r[0] + nu[1] * r[1]) / pair.weight);
                    t.push((tc[0] * r[0] + tc[1] * r[1]) / pair.weight);
                }
            }
        }
        (p, t)
    }

    /// `G_b û_b + G_t û_t` of every pair's candidates (`G_b û_b` against obstacles).
    fn gap_change(&self, u: &[f64]) -> Vec<f64> {
        let mut g = Vec::with_capacity(self.pairs.len());
        for pair in &self.contact {
            let g1 = pair.operator.gap_contribution(&u[self.body_range(pair.body)]);
            match pair.target {
                Some((t, op)) => {
                    let g2 = op.gap_contribution(&u[self.body_range(t)]);
                    g.extend(g1.iter().zip(&g2).map(|(a, b)| a + b));
                }
                None => g.extend(g1),
            }
        }
        g
    }

    /// `g0 + G_b û_b + G_t û_t`.
    fn gaps(&self, u: &[f64]) -> Vec<f64> {
        self.gap_change(u).iter().zip(&self.initial_gap).map(|(g, g0)| g0 + g).collect()
    }

    /// The slips of displacements `u` relative to the obstacles: `t·u^h(x_c) − o_c`.
    fn offset_slips(&self, u: &[f64]) -> Vec<f64> {
        let mut s = self.slips(u);
        s.iter_mut().zip(&self.tangential_offset).for_each(|(s, o)| *s -= o);
        s
    }

    /// The relative tangential displacements `t·u₁^h(x_c) − t·u₂^h(y_c)` (zero without the
    /// tangential operators).
    fn slips(&self, u: &[f64]) -> Vec<f64> {
        let Some(tangential) = &self.tangential else { return vec![0.0; self.pairs.len()] };
        let mut s = Vec::with_capacity(self.pairs.len());
        for (pair, &(t1, t2)) in self.contact.iter().zip(tangential) {
            let mut part = t1.gap_contribution(&u[self.body_range(pair.body)]);
            if let (Some((t, _)), Some(t2)) = (pair.target, t2) {
                let other = t2.gap_contribution(&u[self.body_range(t)]);
                part.iter_mut().zip(other).for_each(|(s, v)| *s += v);
            }
            s.extend(part);
        }
        s
    }
}

impl SparseSolves<Mode> for Bodies<'_> {
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

impl ActiveSetSystem for Bodies<'_> {
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
            self.add_unit_force(false, c, x.col_mut(j + 1));
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

impl Bodies<'_> {
    /// Adds the unit force of candidate `c` on its body and its target body to the column
    /// `x`: the normal force (the pair's operators) or, with `tangential`, the tangential one
    /// (the pair's tangential operators of [`Bodies::set_friction`]).
    fn add_unit_force(&self, tangential: bool, c: usize, mut x: faer::ColMut<'_, f64>) {
        let (k, local) = self.pairs[c].contact;
        let pair = &self.contact[k];
        let mut sides = vec![(pair.operator, self.offsets[pair.body])];
        if let Some((t, op)) = pair.target {
            sides.push((op, self.offsets[t]));
        }
        if let (true, Some(ops)) = (tangential, &self.tangential) {
            let (t1, t2) = ops[k];
            sides[0].0 = t1;
            if let (Some(side), Some(t2)) = (sides.get_mut(1), t2) {
                side.0 = t2;
            }
        }
        for (op, offset) in sides {
            let d = op.direction(local);
            for &(i, w) in &op.owners[local] {
                x[offset + dof(i as usize, Axis::X)] += d[0] * w;
                x[offset + dof(i as usize, Axis::Y)] += d[1] * w;
            }
        }
    }
}

impl FrictionSystem for Bodies<'_> {
    fn size(&self) -> usize {
        self.pairs.len()
    }
    fn friction(&self) -> Vec<f64> {
        if self.friction.is_empty() { vec![0.0; self.pairs.len()] } else { self.friction.clone() }
    }
    /// One solve with each body's own factorisation; `None` when one fails its accuracy
    /// check.
    fn free_response(&mut self) -> Result<Option<FreeResponse>, ActiveSetError> {
        let mut u = Vec::with_capacity(self.n());
        for (b, body) in self.bodies.iter().enumerate() {
            match body.factorisation.solve(&self.rhs[self.body_range(b)]) {
                Ok(ub) => u.extend(ub),
                Err(_) => return Ok(None),
            }
        }
        Ok(Some((self.gaps(&u), self.offset_slips(&u))))
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.initial_gap.to_vec()
    }
    fn solve_states(
        &mut self,
        states: &[ContactState],
        previous: &[f64],
    ) -> Result<StateResponse, ActiveSetError> {
        self.set_targets(previous);
        let modes = self.modes_of(states);
        let u = self.displacements_of(&modes)?;
        let (normal, tangential) = self.forces(&modes, &u);
        let (gap, tangential_displacement) = (self.gaps(&u), self.offset_slips(&u));
        self.last = Some((modes, u));
        Ok(StateResponse { normal, tangential, gap, tangential_displacement })
    }
    fn reduced_problem(
        &mut self,
        states: &[ContactState],
        free: &[usize],
        previous: &[f64],
    ) -> Result<FrictionProblem, ActiveSetError> {
        self.set_targets(previous);
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
        for (j, &c) in free.iter().enumerate() {
            self.add_unit_force(false, c, x.col_mut(j + 1));
            if mu[c] > 0.0 && self.tangential.is_some() {
                self.add_unit_force(true, c, x.col_mut(k + j + 1));
            }
        }
        self.solve_columns(&held, x.as_mut())?;
        let base = StateResponse {
            normal: Vec::new(),
            tangential: Vec::new(),
            gap: self.gaps(x.col_as_slice(0)),
            tangential_displacement: self.offset_slips(x.col_as_slice(0)),
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

/// Each body's first DOF in the stacked system, and each pair's first candidate (one past the
/// last at the end).
///
/// # Errors
/// [`ActiveSetError::Unsupported`] when a pair names a body out of range (or itself as its
/// target), its operators disagree on the candidates, or `initial_gap` does not cover them.
fn numbering(
    bodies: &[BodyParts<'_>],
    contact: &[PairParts<'_>],
    initial_gap: &[f64],
) -> Result<(Vec<usize>, Vec<usize>), ActiveSetError> {
    let mut offsets = vec![0];
    for b in bodies {
        offsets.push(offsets.last().copied().unwrap_or(0) + b.matrix.n);
    }
    let mut starts = vec![0];
    for pair in contact {
        let m = starts.last().copied().unwrap_or(0);
        let bad = pair.body >= bodies.len()
            || pair.target.is_some_and(|(t, op)| {
                t >= bodies.len() || t == pair.body || op.len() != pair.operator.len()
            });
        if bad {
            return Err(ActiveSetError::Unsupported { candidate: m });
        }
        starts.push(m + pair.operator.len());
    }
    let m = starts.last().copied().unwrap_or(0);
    if initial_gap.len() != m {
        return Err(ActiveSetError::Unsupported { candidate: m.min(initial_gap.len()) });
    }
    Ok((offsets, starts))
}

/// Candidates `(first, second)` of two pairs owned by one node ([`candidate_owners`]).
type Corners = Vec<(usize, usize)>;

/// Each candidate's owner: one node of its body with a non-zero weight, no node owning two
/// candidates of one pair; and the candidates `(first, second)` whose node also owns a
/// candidate of an earlier pair (a corner node of two contact edges, checked by
/// [`shared_owners`]).
///
/// # Errors
/// [`ActiveSetError::Unsupported`] for two candidates of one pair on a node or a force not on
/// one node.
fn candidate_owners(
    contact: &[PairParts<'_>],
    starts: &[usize],
) -> Result<(Vec<(usize, f64)>, Corners), ActiveSetError> {
    let mut owner_of = Vec::with_capacity(starts.last().copied().unwrap_or(0));
    let mut corners = Vec::new();
    let mut used: HashMap<(usize, u32), (usize, usize)> = HashMap::new();
    for (k, pair) in contact.iter().enumerate() {
        for (c, owners) in pair.operator.owners.iter().enumerate() {
            match owners.as_slice() {
                [(i, w)] if *w != 0.0 => {
                    match used.insert((pair.body, *i), (k, starts[k] + c)) {
                        None => {}
                        // A corner node of two contact edges.
                        Some((first, other)) if first != k => {
                            corners.push((other, starts[k] + c));
                        }
                        Some(_) => {
                            return Err(ActiveSetError::Unsupported { candidate: starts[k] + c });
                        }
                    }
                    owner_of.push((*i as usize, *w));
                }
                _ => return Err(ActiveSetError::Unsupported { candidate: starts[k] + c }),
            }
        }
    }
    Ok((owner_of, corners))
}

/// Each candidate's partner on a node that owns candidates of two pairs (`corners` from
/// [`candidate_owners`]). Such a node is taken when the two candidates' rows do not meet: each
/// normal lies along an axis (no tangential term `−(ν_b/ν_a) K_a`), the two along different
/// axes, so that each replaces its own row of the node, whose residual then holds its force
/// alone, and the two candidates' changes add up to the node with both closed; friction on
/// either is refused by [`Bodies::set_friction`] (the frictional modes use both rows).
///
/// # Errors
/// [`ActiveSetError::OwnerConflict`] for a node owning candidates of more than two pairs, or of
/// two whose normals are not along different axes.
fn shared_owners(
    pairs: &[Pair],
    contact: &[PairParts<'_>],
    corners: &[(usize, usize)],
    offsets: &[usize],
    m: usize,
) -> Result<Vec<Option<usize>>, ActiveSetError> {
    let mut shared = vec![None; m];
    let along_an_axis = |c: usize| {
        let (k, local) = pairs[c].contact;
        let d = contact[k].operator.direction(local);
        d[pairs[c].axes[1] as usize] == 0.0
    };
    for &(first, second) in corners {
        let apart = pairs[first].axes[0] != pairs[second].axes[0];
        let taken = shared[first].is_some() || shared[second].is_some();
        if !apart || taken || !along_an_axis(first) || !along_an_axis(second) {
            let k = pairs[first].contact.0;
            let body = contact[k].body;
            return Err(ActiveSetError::OwnerConflict {
                body,
                node: (pairs[first].dofs[0] - offsets[body]) / 2,
                pair: k,
                other: pairs[second].contact.0,
                what: "owns a candidate of each (a corner node shared by two contact edges) whose normals are not along the two axes",
            });
        }
        shared[first] = Some(second);
        shared[second] = Some(first);
    }
    Ok(shared)
}

/// The rows of `K` (stacked) at the owners' DOFs, which the contact rows replace.
fn owner_rows(
    bodies: &[BodyParts<'_>],
    contact: &[PairParts<'_>],
    offsets: &[usize],
    starts: &[usize],
    owner_of: &[(usize, f64)],
) -> HashMap<usize, Row> {
    let mut wanted: HashMap<usize, Row> = HashMap::new();
    for (k, pair) in contact.iter().enumerate() {
        for &(i, _) in &owner_of[starts[k]..starts[k + 1]] {
            let o = offsets[pair.body];
            wanted.insert(o + dof(i, Axis::X), Vec::new());
            wanted.insert(o + dof(i, Axis::Y), Vec::new());
        }
    }
    for (b, body) in bodies.iter().enumerate() {
        let (k, o) = (body.matrix, offsets[b]);
        for col in 0..k.n {
            for e in k.col_ptr[col]..k.col_ptr[col + 1] {
                if let Some(row) = wanted.get_mut(&(o + k.row_idx[e])) {
                    row.push((o + col, k.values[e]));
                }
            }
        }
    }
    wanted
}

/// Candidate `c` of pair `k`, owned by node `i` with weight `w`: its replaced row (the
/// candidate's own larger normal component) becomes the gap row, and the other row and the
/// target's force rows the rank-one terms that carry the removed row's force.
fn replaced_rows(
    pair: &PairParts<'_>,
    (k, c): (usize, usize),
    (i, w): (usize, f64),
    offsets: &[usize],
    wanted: &HashMap<usize, Row>,
) -> Pair {
    let (op1, ob) = (pair.operator, offsets[pair.body]);
    let mut sides = vec![(op1, ob)];
    if let Some((t, op2)) = pair.target {
        sides.push((op2, offsets[t]));
    }
    // The replaced row: the candidate's own larger normal component (the normals are the
    // target edge's, the same for all on a straight edge).
    let d1 = op1.direction(c);
    let (a, b) = if d1[0].abs() >= d1[1].abs() { (Axis::X, Axis::Y) } else { (Axis::Y, Axis::X) };
    let (na, ratio) = (d1[a as usize], d1[b as usize] / d1[a as usize]);
    let (ra, rb) = (ob + dof(i, a), ob + dof(i, b));
    let old_a = wanted[&ra].clone();
    let old_b = wanted[&rb].clone();
    let gap_row = pair_row(pair.scale, &sides, c);
    let minus_old: Row = old_a.iter().map(|&(j, v)| (j, -v)).collect();
    // Row a: the gap row instead of K_a. Row b and the target's force rows: multiples of
    // K_a, one rank-one term `u K_aᵀ` (and `u f_a` on the right).
    let wn = w * na;
    let mut u: Vec<(usize, f64)> = Vec::new();
    if ratio != 0.0 {
        u.push((rb, -ratio));
    }
    if let Some((t, op2)) = pair.target {
        let d2 = op2.direction(c);
        for &(j, w2) in &op2.owners[c] {
            for ax in Axis::BOTH {
                let v = -d2[ax as usize] * w2 / wn;
                if v != 0.0 {
                    u.push((offsets[t] + dof(j as usize, ax), v));
                }
            }
        }
    }
    let mut us = vec![vec![(ra, 1.0)]];
    let mut terms = vec![Term { u: 0, d: sum_rows(&gap_row, &minus_old), rhs: TermRhs::Gap }];
    if !u.is_empty() {
        us.push(u);
        terms.push(Term { u: 1, d: old_a.clone(), rhs: TermRhs::Row(1.0, ra) });
    }
    let closed: Vec<usize> = (0..terms.len()).collect();
    Pair {
        frictionless: (us.len(), terms.len()),
        us,
        terms,
        modes: vec![closed],
        rows: [old_a, old_b],
        dofs: [ra, rb],
        axes: [a, b],
        weight: w,
        wn,
        contact: (k, c),
        scale: pair.scale,
    }
}

/// A node that owns a candidate and receives another pair's target forces: its removed row
/// would hold two unknown forces.
///
/// # Errors
/// [`ActiveSetError::OwnerConflict`] naming the node and the two pairs.
fn check_target_rows(pairs: &[Pair], offsets: &[usize]) -> Result<(), ActiveSetError> {
    let owned: HashMap<usize, usize> =
        pairs.iter().enumerate().flat_map(|(c, p)| p.dofs.iter().map(move |&r| (r, c))).collect();
    for p in pairs {
        let Some(targets) = p.us.get(1) else { continue };
        for &(r, _) in targets.iter().filter(|&&(r, _)| r != p.dofs[1]) {
            if let Some(&c) = owned.get(&r) {
                let body = offsets.partition_point(|&o| o <= r) - 1;
                return Err(ActiveSetError::OwnerConflict {
                    body,
                    node: (r - offsets[body]) / 2,
                    pair: pairs[c].contact.0,
                    other: p.contact.0,
                    what: "owns a candidate of the first and receives the target forces of the second on the same rows (a body one node thick, or a corner node of the two edges)",
                });
            }
        }
    }
    Ok(())
}

/// The largest absolute row sum of `matrix`.
fn max_row_norm(matrix: &SystemMatrix) -> f64 {
    let mut rows = vec![0.0_f64; matrix.n];
    for (k, &r) in matrix.row_idx.iter().enumerate() {
        rows[r] += matrix.values[k].abs();
    }
    rows.into_iter().fold(0.0, f64::max)
}
