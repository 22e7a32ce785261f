//! The iteration matrix of the θ-method, `M̂ = M Φ + h²θ² K`, factorised once per run
//! (docs/method.md §10.2), and the free velocity of a step.
//!
//! A row of `K` that is a collocated displacement condition (docs/method.md §3.6) has no mass
//! and its collocation row enters `M̂` scaled by `h²θ²` like the other rows of `K` (so the
//! LU's pivoting sees rows of one magnitude: unscaled, the rows of a steel body's axis
//! rollers were 10¹⁶ times the others and the steps diverged): the step then places the field at
//! `q_{n+θ}` on the prescribed value, exactly. With a history in time ([`StepLoad::Given`])
//! that value is `(1 − θ) ū(t_n) + θ ū(t_{n+1})`, so that with `q_n` on `ū(t_n)` the step's end
//! `q_{n+1} = q_n + h ((1 − θ) v_n + θ v_{n+1})` is on `ū(t_{n+1})`: the velocity row asks
//! `(1 − θ) v_n + θ v_{n+1} = (ū(t_{n+1}) − ū(t_n)) / h` (docs/method.md §10.5).

use super::DynamicsError;
use super::mass::Mass;
use crate::assembly::{GlobalSystem, SystemMatrix};
use crate::geometry::Point;
use crate::linear_solve::{ColumnOrdering, FactorMethod, FactorOptions, Factorisation, RowProduct};
use crate::mls::ShapeSet;
use faer::MatMut;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The applied side of a step's free velocity.
#[derive(Clone, Copy, Debug)]
pub enum StepLoad<'a> {
    /// The assembled right-hand side with the applied loads scaled by this factor (the load
    /// ramp's at `t_{n+θ}`; 1 without); a prescribed row's value unscaled.
    Scaled(f64),
    /// The step's right-hand side itself, every row (a history in time:
    /// `(1 − θ) r(t_n) + θ r(t_{n+1})`, [`super::LoadHistory`]).
    Given(&'a [f64]),
}

/// `M̂` factorised, with what the free step needs.
pub struct Iteration<'a> {
    system: &'a GlobalSystem,
    /// The LU of `M̂`.
    pub factorisation: Factorisation,
    /// `M̂` itself (the active-set step replaces its rows, `contact::sparse::Bodies`).
    matrix: SystemMatrix,
    h: f64,
    theta: f64,
    /// `K` by rows, for the step's product on two tasks.
    stiffness: RowProduct,
    /// Free-velocity solves so far.
    solves: AtomicUsize,
    /// Every free-velocity solve refined against `M̂` from now on: pivots were perturbed, or a
    /// checked solve needed a refinement step.
    refine_all: AtomicBool,
}

/// The free velocity solves with the factors alone (the substitutions), but the first and
/// every `CHECK_EVERY`-th after it are refined against `M̂`, which checks their backward
/// error; once one of them needs a refinement step, every later solve is refined.
const CHECK_EVERY: usize = 64;

impl<'a> Iteration<'a> {
    /// Builds and factorises `M̂` from `system` (K with its collocation rows), the `mass`
    /// (lumped, or the FE's consistent one: a constrained row has none, its columns stay) and the shape functions at the nodes (`Φ`), for step `h` and `θ`; `points`
    /// order the columns (nested dissection).
    ///
    /// # Errors
    /// [`DynamicsError::Solve`] when the factorisation fails.
    pub fn new(
        system: &'a GlobalSystem,
        mass: &Mass,
        node_shapes: &ShapeSet,
        h: f64,
        theta: f64,
        points: &[Point],
    ) -> Result<Self, DynamicsError> {
        let n = system.matrix.n;
        let constrained: Vec<bool> = (0..n).map(|d| system.is_constrained(d)).collect();
        let mut entries = mass.entries(node_shapes, |r| constrained[r]);
        let s = h * h * theta * theta;
        let k = &system.matrix;
        for c in 0..n {
            for e in k.col_ptr[c]..k.col_ptr[c + 1] {
                let r = k.row_idx[e];
                entries.push((r, c, s * k.values[e]));
            }
        }
        let matrix = compressed_columns(n, entries);
        // The static-pivoting LU: its substitutions run the two halves of a split band order
        // on two cores, 1.5–3× faster per solve than the partial-pivoting LU on the bar
        // (docs/dev/dynamics.md, "Two-core substitution").
        let options = FactorOptions {
            method: FactorMethod::StaticPivoting,
            split_band: true,
            ..Default::default()
        };
        let factorisation = Factorisation::with_options(
            &matrix,
            ColumnOrdering::NestedDissection(points),
            &options,
        )?;
        let refine_all = AtomicBool::new(factorisation.stats().perturbed_pivots > 0);
        let stiffness = RowProduct::new(&system.matrix);
        let solves = AtomicUsize::new(0);
        Ok(Self { system, factorisation, matrix, h, theta, stiffness, solves, refine_all })
    }

    /// The velocity at the end of the step without contact impulses:
    /// `v_free = v + M̂⁻¹ h (r − K (q + hθ v))`, `r` from `load` ([`StepLoad::Scaled`]: `s f`
    /// with the applied loads' factor `s` at `t_{n+θ}`, a collocation row's `f` its prescribed
    /// value, not scaled; [`StepLoad::Given`]: the history's).
    ///
    /// # Errors
    /// [`DynamicsError::Solve`] when the solve is not finite.
    pub fn free_velocity(
        &self,
        q: &[f64],
        v: &[f64],
        load: StepLoad<'_>,
    ) -> Result<Vec<f64>, DynamicsError> {
        let rhs = self.free_rhs(q, v, load);
        let dv = self.free_solve(rhs)?;
        Ok(v.iter().zip(&dv).map(|(v, dv)| v + dv).collect())
    }

    /// `M̂⁻¹ b` for the free velocity: the substitutions alone, the checked solves refined
    /// ([`CHECK_EVERY`]).
    fn free_solve(&self, b: Vec<f64>) -> Result<Vec<f64>, DynamicsError> {
        let count = self.solves.fetch_add(1, Ordering::Relaxed);
        if self.refine_all.load(Ordering::Relaxed) || count % CHECK_EVERY == 0 {
            let before = self.factorisation.stats().refinement_steps;
            let x = self.factorisation.solve(&b)?;
            if self.factorisation.stats().refinement_steps > before {
                self.refine_all.store(true, Ordering::Relaxed);
            }
            return Ok(x);
        }
        let (n, mut x) = (b.len(), b.clone());
        self.factorisation
            .solve_unrefined_in_place(MatMut::from_column_major_slice_mut(&mut x, n, 1));
        match x.iter().all(|v| v.is_finite()) {
            true => Ok(x),
            // The refined solve reports what went wrong.
            false => Ok(self.factorisation.solve(&b)?),
        }
    }

    /// The right-hand side of the step's velocity change without contact,
    /// `h (r − K (q + hθ v))` (`M̂ (v_free − v)`; see [`Self::free_velocity`]).
    pub fn free_rhs(&self, q: &[f64], v: &[f64], load: StepLoad<'_>) -> Vec<f64> {
        let (h, theta, system) = (self.h, self.theta, self.system);
        let ahead: Vec<f64> = q.iter().zip(v).map(|(q, v)| q + h * theta * v).collect();
        let k_ahead = self.stiffness.mul(&ahead);
        (0..q.len())
            .map(|d| match load {
                StepLoad::Scaled(load_factor) => {
                    let s = if system.is_constrained(d) { 1.0 } else { load_factor };
                    h * (s * system.rhs[d] - k_ahead[d])
                }
                StepLoad::Given(r) => h * (r[d] - k_ahead[d]),
            })
            .collect()
    }

    /// `M̂`.
    pub fn matrix(&self) -> &SystemMatrix {
        &self.matrix
    }

    /// The scale of a gap row replacing a row of `M̂`: the body's collocation scale times
    /// `h²θ²`, as its collocation rows enter `M̂`.
    pub fn gap_row_scale(&self) -> f64 {
        self.system.collocation_scale * self.h * self.h * self.theta * self.theta
    }

    /// Number of degrees of freedom.
    pub fn dofs(&self) -> usize {
        self.system.matrix.n
    }

    /// `M̂⁻¹ b`.
    ///
    /// # Errors
    /// [`DynamicsError::Solve`] when the solve is not finite.
    pub fn solve(&self, b: &[f64]) -> Result<Vec<f64>, DynamicsError> {
        Ok(self.factorisation.solve(b)?)
    }
}

/// The compressed-column matrix of the entries `(row, column, value)` (duplicates summed,
/// every diagonal entry present).
fn compressed_columns(n: usize, mut entries: Vec<(usize, usize, f64)>) -> SystemMatrix {
    entries.extend((0..n).map(|d| (d, d, 0.0)));
    SystemMatrix::from_entries(n, entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compressed_columns_sum_duplicates_and_store_every_diagonal() {
        let m = compressed_columns(3, vec![(1, 0, 3.0), (0, 0, 1.0), (0, 1, 2.0), (1, 0, 0.5)]);
        assert_eq!(m.col_ptr, vec![0, 2, 4, 5]);
        assert_eq!(m.row_idx, vec![0, 1, 0, 1, 2]);
        assert_eq!(m.values, vec![1.0, 3.5, 2.0, 0.0, 0.0]);
    }
}
