//! The sparse contact systems of the active-set method (docs/method.md §5.1): the problem of a
//! guessed active set is the bodies' own matrices `K` with the rows of each active candidate
//! replaced by its gap condition (as a displacement condition is collocated), the force
//! recovered from the removed row like a reaction. No dense `M = G K⁻¹ E` is formed.
//!
//! [`RigidObstacle`] is one body against rigid obstacles, [`Bodies`] any number of elastic
//! bodies and pairs (rigid pairs among them); both implement the algorithms' traits of
//! [`crate::lcp::active_set`] (`ActiveSetSystem` for frictionless contact, `FrictionSystem`
//! for a frictional step), which know nothing of bodies or matrices, and [`SceneSystem`], the
//! interface the load path drives them by (bodies' loads, gaps, `μ` per step, displacements).

mod bodies;
mod obstacle;
mod scene;

pub use bodies::{Bodies, BodyParts, PairParts, PairTangential, TwoBodies};
pub use obstacle::{ModelFactors, RigidObstacle, RigidObstacleStats};
pub use scene::SceneSystem;

use crate::lcp::active_set::{ActiveSetError, CLOSED, Mode, OPEN};
use crate::linear_solve::{Factorisation, SolveError};
use faer::MatMut;
use faer::reborrow::ReborrowMut;
use rayon::prelude::*;

impl From<SolveError> for ActiveSetError {
    fn from(e: SolveError) -> Self {
        ActiveSetError::Solve(Box::new(e))
    }
}

/// The error of a singular problem of an active set (a linear solve's own error).
fn singular(what: &str) -> ActiveSetError {
    SolveError::Singular { detail: format!("{what} is singular") }.into()
}

/// Memory for the stored update columns `K_B⁻¹ e_r` of a [`RigidObstacle`] (1 GB).
const COLUMN_BYTES: usize = 1 << 30;

/// A sparse row `(column, value)`.
type Row = Vec<(usize, f64)>;

/// `CLOSED` where `active`, `OPEN` elsewhere.
fn closed_modes(active: &[bool]) -> Vec<Mode> {
    active.iter().map(|&a| if a { CLOSED } else { OPEN }).collect()
}

/// Solves `f X = B` in place, 64 columns per task.
fn solve_blocks(f: &Factorisation, x: MatMut<'_, f64>) {
    let n = x.nrows();
    let cols = x.ncols();
    if cols <= 64 {
        f.solve_in_place(x);
        return;
    }
    let mut x = x;
    let mut parts: Vec<MatMut<'_, f64>> = Vec::new();
    let mut rest = x.rb_mut();
    while rest.ncols() > 64 {
        let (a, b) = rest.split_at_col_mut(64);
        parts.push(a);
        rest = b;
    }
    parts.push(rest);
    debug_assert!(parts.iter().all(|p| p.nrows() == n));
    parts.into_par_iter().for_each(|p| f.solve_in_place(p));
}

fn sum_rows(a: &Row, b: &Row) -> Row {
    let mut out: Row = a.iter().chain(b).copied().collect();
    out.sort_by_key(|e| e.0);
    let mut merged: Row = Vec::with_capacity(out.len());
    for (j, v) in out {
        match merged.last_mut() {
            Some(last) if last.0 == j => last.1 += v,
            _ => merged.push((j, v)),
        }
    }
    merged
}

/// What [`solve_refined`] needs of a sparse active-set system ([`RigidObstacle`] and
/// `TwoBodies`).
trait SparseSolves<T = bool> {
    /// Solves the problem of `active` for the columns of `x`, in place.
    fn solve_in_place(&mut self, active: &[T], x: MatMut<'_, f64>) -> Result<(), ActiveSetError>;
    /// The matrix of `active` times `u`.
    fn product(&self, active: &[T], u: &[f64]) -> Vec<f64>;
    /// The largest absolute row sum of the unmodified matrix.
    fn row_norm(&self) -> f64;
    /// Counts one refinement step in the statistics.
    fn count_refinement(&mut self);
}

/// `K_A⁻¹ b` with one step of iterative refinement when the normwise backward error is
/// above 1e-14 (below it the step would change nothing that matters, and it costs one or two
/// solves).
fn solve_refined<T, S: SparseSolves<T>>(
    system: &mut S,
    active: &[T],
    b: &[f64],
) -> Result<Vec<f64>, ActiveSetError> {
    let n = b.len();
    let mut u = b.to_vec();
    system.solve_in_place(active, MatMut::from_column_major_slice_mut(&mut u, n, 1))?;
    if u.iter().any(|v| !v.is_finite()) {
        return Err(singular("the problem of the active set"));
    }
    let mut r = system.product(active, &u);
    for (r, b) in r.iter_mut().zip(b) {
        *r = b - *r;
    }
    let max_abs = |v: &[f64]| v.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let backward =
        max_abs(&r) / (system.row_norm() * max_abs(&u) + max_abs(b)).max(f64::MIN_POSITIVE);
    if backward <= 1e-14 {
        return Ok(u);
    }
    system.count_refinement();
    system.solve_in_place(active, MatMut::from_column_major_slice_mut(&mut r, n, 1))?;
    for (u, d) in u.iter_mut().zip(&r) {
        *u += d;
    }
    if u.iter().any(|v| !v.is_finite()) {
        return Err(singular("the problem of the active set"));
    }
    Ok(u)
}
