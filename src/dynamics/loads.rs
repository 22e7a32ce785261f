//! Loads and prescribed displacements that vary in time (`[[step]]` tables with `time`,
//! docs/method.md §10.5): the assembled load `f` and right-hand side `r` (a collocation or
//! eliminated row's value `D₀₀ ū`, the FE lift `− K_fc ū` on the free rows) at the steps'
//! times, linear between them and held after the last. A step `n → n + 1` takes the θ-weighted
//! right-hand side `(1 − θ) r(t_n) + θ r(t_{n+1})`: on a free row the load at `t_{n+θ}` when the
//! history has no kink inside the step, on a prescribed row the value that places the
//! displacement at the step's end on `ū(t_{n+1})` (`super::iteration`).

use crate::assembly::GlobalSystem;

/// A body's load and right-hand side at the times `0 = t_0 < t_1 < …` (the state at time 0:
/// the unloaded `[[boundary]]` values; each `[[step]]`'s end state at its time).
#[derive(Clone, Debug)]
pub struct LoadHistory {
    /// `t_k`, strictly increasing from 0.
    times: Vec<f64>,
    /// `f(t_k)`, interleaved (a prescribed row's load included).
    loads: Vec<Vec<f64>>,
    /// `r(t_k)`: the solved right-hand side for the conditions at `t_k`.
    rhs: Vec<Vec<f64>>,
}

/// What a history gives one time step `n → n + 1`.
pub(super) struct StepSide {
    /// `(1 − θ) r(t_n) + θ r(t_{n+1})`.
    pub rhs: Vec<f64>,
    /// `(1 − θ) f(t_n) + θ f(t_{n+1})` on the free rows, 0 on the prescribed ones (the loads
    /// whose work is `fᵀ Δq`).
    pub free_load: Vec<f64>,
    /// Each prescribed DOF whose value moves in the step, with `ū(t_{n+1}) − ū(t_n)`.
    pub moved: Vec<(usize, f64)>,
}

impl LoadHistory {
    /// The history of the states `(t_k, f(t_k), r(t_k))`, the first at time 0.
    ///
    /// # Panics
    /// When the times do not start at 0 and increase, or a vector's length differs (caller
    /// bugs: the steps' times are validated in [`crate::problem::dynamics`]).
    pub fn new(states: Vec<(f64, Vec<f64>, Vec<f64>)>) -> Self {
        assert!(states.first().is_some_and(|s| s.0 == 0.0), "a history starts at time 0");
        assert!(states.windows(2).all(|w| w[1].0 > w[0].0), "the times increase");
        let n = states[0].1.len();
        assert!(states.iter().all(|s| s.1.len() == n && s.2.len() == n), "one length");
        let mut history = Self { times: Vec::new(), loads: Vec::new(), rhs: Vec::new() };
        for (t, f, r) in states {
            history.times.push(t);
            history.loads.push(f);
            history.rhs.push(r);
        }
        history
    }

    /// `(f(t), r(t))`: linear between the states (exactly a state's vectors at its time), the
    /// last state's after it.
    pub fn at(&self, t: f64) -> (Vec<f64>, Vec<f64>) {
        let k = self.times.partition_point(|&s| s <= t);
        if k == self.times.len() {
            return (self.loads[k - 1].clone(), self.rhs[k - 1].clone());
        }
        let k = k.max(1);
        let (a, b) = (self.times[k - 1], self.times[k]);
        let lambda = ((t - a) / (b - a)).clamp(0.0, 1.0);
        (
            lerp(&self.loads[k - 1], &self.loads[k], lambda),
            lerp(&self.rhs[k - 1], &self.rhs[k], lambda),
        )
    }

    /// The step from `t0` to `t1` of `system` (its prescribed rows and their scale) with `θ`.
    pub(super) fn step(&self, system: &GlobalSystem, t0: f64, t1: f64, theta: f64) -> StepSide {
        let ((f0, r0), (f1, r1)) = (self.at(t0), self.at(t1));
        let rhs = lerp(&r0, &r1, theta);
        let mut free_load = lerp(&f0, &f1, theta);
        let mut moved = Vec::new();
        for c in &system.constraints {
            let d = crate::nodes::dof(c.node as usize, c.axis);
            free_load[d] = 0.0;
            let du = (r1[d] - r0[d]) / system.collocation_scale;
            if du != 0.0 {
                moved.push((d, du));
            }
        }
        StepSide { rhs, free_load, moved }
    }
}

/// `(1 − λ) a + λ b`, exactly `b` at `λ = 1` and `a` at `λ = 0`.
fn lerp(a: &[f64], b: &[f64], lambda: f64) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| (1.0 - lambda) * x + lambda * y).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_history_is_linear_between_its_states_and_held_after_the_last() {
        let h = LoadHistory::new(vec![
            (0.0, vec![0.0, 0.0], vec![0.0, 0.0]),
            (2.0, vec![4.0, 2.0], vec![1.0, -2.0]),
            (3.0, vec![4.0, 0.0], vec![3.0, -2.0]),
        ]);
        assert_eq!(h.at(0.0), (vec![0.0, 0.0], vec![0.0, 0.0]));
        assert_eq!(h.at(1.0), (vec![2.0, 1.0], vec![0.5, -1.0]));
        assert_eq!(h.at(2.0), (vec![4.0, 2.0], vec![1.0, -2.0]));
        assert_eq!(h.at(2.5), (vec![4.0, 1.0], vec![2.0, -2.0]));
        assert_eq!(h.at(7.0), (vec![4.0, 0.0], vec![3.0, -2.0]));
    }
}
