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

/// A rigid obstacle moving in time (`[[step]] obstacle_displacement` with `time`,
/// docs/method.md §10.6): its displacement `d(t)` linear between the steps' times from
/// `d(0) = 0`, held after the last, moving the candidates of every pair against rigid
/// obstacles together (each along its normal `ν_c`; the candidates of pairs between bodies
/// are not moved).
#[derive(Clone, Debug)]
pub struct ObstacleMotion {
    /// `t_k`, strictly increasing from 0.
    times: Vec<f64>,
    /// `d(t_k)`.
    displacements: Vec<[f64; 2]>,
    /// `ν_c` of each candidate the obstacle moves, `None` for the others.
    normals: Vec<Option<[f64; 2]>>,
}

/// What the moving obstacle gives one time step `n → n + 1` (docs/method.md §10.6).
pub struct ObstacleStep<'a> {
    /// `d(t_n + h/2)`: the obstacle where the index set predicts the gaps (the bodies at
    /// `q_n + h/2 v_n`).
    pub ahead: [f64; 2],
    /// `d(t_{n+1})`.
    pub end: [f64; 2],
    /// `w_n`: the obstacle's velocity at the step's start, the previous step's `w_{n+1}`
    /// (the first step's own at `n = 0`).
    pub start_velocity: [f64; 2],
    /// `w_{n+1} = (d(t_{n+1}) − d(t_n)) / h`: its velocity at the step's end.
    pub end_velocity: [f64; 2],
    /// `d(t_{n+1}) − d(t_n)`.
    pub displacement: [f64; 2],
    /// `ν_c` of the moved candidates.
    normals: &'a [Option<[f64; 2]>],
}

impl ObstacleMotion {
    /// The motion through the states `(t_k, d(t_k))` (the first `(0, [0, 0])`) of the
    /// candidates with normals `normals` (`None`: not moved).
    ///
    /// # Panics
    /// When the times do not start at 0 and increase (caller bugs: the steps' times are
    /// validated in [`crate::problem::dynamics`]).
    pub fn new(states: Vec<(f64, [f64; 2])>, normals: Vec<Option<[f64; 2]>>) -> Self {
        assert!(states.first().is_some_and(|s| s.0 == 0.0), "a motion starts at time 0");
        assert!(states.windows(2).all(|w| w[1].0 > w[0].0), "the times increase");
        let (times, displacements) = states.into_iter().unzip();
        Self { times, displacements, normals }
    }

    /// `d(t)`: linear between the states, the last state's after it.
    pub fn at(&self, t: f64) -> [f64; 2] {
        let k = self.times.partition_point(|&s| s <= t);
        if k == self.times.len() {
            return self.displacements[k - 1];
        }
        let k = k.max(1);
        let (a, b) = (self.times[k - 1], self.times[k]);
        let lambda = ((t - a) / (b - a)).clamp(0.0, 1.0);
        let (p, q) = (self.displacements[k - 1], self.displacements[k]);
        [(1.0 - lambda) * p[0] + lambda * q[0], (1.0 - lambda) * p[1] + lambda * q[1]]
    }

    /// Number of candidates (moved or not).
    pub fn len(&self) -> usize {
        self.normals.len()
    }

    /// Whether there are no candidates.
    pub fn is_empty(&self) -> bool {
        self.normals.is_empty()
    }

    /// Time step `n → n + 1` (`n` from 0) of size `h`.
    pub(super) fn step(&self, n: usize, h: f64) -> ObstacleStep<'_> {
        let (t0, t1) = (n as f64 * h, (n + 1) as f64 * h);
        let (d0, d1) = (self.at(t0), self.at(t1));
        let velocity = |a: [f64; 2], b: [f64; 2]| [(b[0] - a[0]) / h, (b[1] - a[1]) / h];
        let start_velocity = match n {
            0 => velocity(d0, d1),
            _ => velocity(self.at((n - 1) as f64 * h), d0),
        };
        ObstacleStep {
            ahead: self.at(t0 + 0.5 * h),
            end: d1,
            start_velocity,
            end_velocity: velocity(d0, d1),
            displacement: [d1[0] - d0[0], d1[1] - d0[1]],
            normals: &self.normals,
        }
    }

    /// `ν_c·d(t)` per candidate (0 on those not moved): what the obstacle takes off the gaps
    /// at time `t`.
    pub fn closing(&self, t: f64) -> Vec<f64> {
        along(&self.normals, self.at(t), false)
    }
}

impl ObstacleStep<'_> {
    /// `ν_c·x` per candidate, 0 on those not moved.
    pub fn along(&self, x: [f64; 2]) -> Vec<f64> {
        along(self.normals, x, false)
    }

    /// `t_c·x` per candidate with `t_c = (ν_y, −ν_x)` (the tangent of the static friction,
    /// docs/method.md §8), 0 on those not moved.
    pub fn across(&self, x: [f64; 2]) -> Vec<f64> {
        along(self.normals, x, true)
    }

    /// Whether candidate `c` is moved.
    pub fn moves(&self, c: usize) -> bool {
        self.normals[c].is_some()
    }
}

/// `ν_c·x` (or `t_c·x` with `tangential`) per candidate, 0 where `normals[c]` is `None`.
fn along(normals: &[Option<[f64; 2]>], x: [f64; 2], tangential: bool) -> Vec<f64> {
    normals
        .iter()
        .map(|n| match n {
            Some(nu) => {
                let d = if tangential { crate::contact::tangent(*nu) } else { *nu };
                d[0] * x[0] + d[1] * x[1]
            }
            None => 0.0,
        })
        .collect()
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

    #[test]
    fn an_obstacle_moves_linearly_and_its_step_velocities_are_the_steps_means() {
        let m = ObstacleMotion::new(
            vec![(0.0, [0.0, 0.0]), (1.0, [2.0, 0.0]), (2.0, [2.0, -1.0])],
            vec![Some([1.0, 0.0]), None, Some([0.0, -1.0])],
        );
        assert_eq!(m.at(0.5), [1.0, 0.0]);
        assert_eq!(m.at(1.5), [2.0, -0.5]);
        assert_eq!(m.at(9.0), [2.0, -1.0]);
        let first = m.step(0, 0.5);
        assert_eq!((first.start_velocity, first.end_velocity), ([2.0, 0.0], [2.0, 0.0]));
        assert_eq!((first.ahead, first.end), ([0.5, 0.0], [1.0, 0.0]));
        let kink = m.step(2, 0.5);
        assert_eq!((kink.start_velocity, kink.end_velocity), ([2.0, 0.0], [0.0, -1.0]));
        assert_eq!(kink.along([3.0, 4.0]), vec![3.0, 0.0, -4.0]);
        assert_eq!(kink.across([3.0, 4.0]), vec![-4.0, 0.0, -3.0]);
        assert_eq!(m.closing(2.0), vec![2.0, 0.0, 1.0]);
    }
}
