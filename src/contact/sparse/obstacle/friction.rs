//! A body against rigid obstacles with friction: [`RigidObstacle`]'s frictional rows and its
//! [`FrictionSystem`] (docs/method.md §5.1 "Friction", §8).

use super::RigidObstacle;
use crate::lcp::active_set::{
    ActiveSetError, CLOSED, FreeResponse, FrictionSystem, Mode, OPEN, StateResponse, mode_of,
    reduced_blocks,
};
use crate::lcp::friction::{ContactState, FrictionProblem};
use crate::nodes::{Axis, dof};
use faer::Mat;

impl RigidObstacle<'_> {
    fn modes_of(&self, states: &[ContactState]) -> Vec<Mode> {
        let mu = |c: usize| self.friction.get(c).copied().unwrap_or(0.0);
        states.iter().enumerate().map(|(c, &s)| mode_of(mu(c), s)).collect()
    }

    /// `(g, s)` of displacements `u`: `g0 + ν·u^h(x_c)`, `t·u^h(x_c) − o_c`.
    fn gaps_and_slips(&self, u: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let m = self.replacements.len();
        let mut g = Vec::with_capacity(m);
        let mut s = Vec::with_capacity(m);
        for c in 0..m {
            let v = self.operator.shapes.interpolate(c, u);
            let nu = self.operator.direction(c);
            let t = crate::contact::tangent(nu);
            g.push(self.initial_gap[c] + nu[0] * v[0] + nu[1] * v[1]);
            s.push(t[0] * v[0] + t[1] * v[1] - self.tangential_offset[c]);
        }
        (g, s)
    }

    /// `(P_c, T_c)` from the removed rows' residuals `r = K û − f` on the owner's rows:
    /// `P = ν·r/w`, `T = t·r/w` (frictionless closed candidates: `P` from row `a`, `T = 0`).
    fn friction_forces(&self, modes: &[Mode], u: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.friction_forces_with(modes, u, &self.rhs)
    }

    /// [`RigidObstacle::friction_forces`] with the right-hand side `rhs` of the removed rows.
    fn friction_forces_with(&self, modes: &[Mode], u: &[f64], rhs: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let normal = self.forces_with(modes, u, rhs);
        let mut p = Vec::with_capacity(modes.len());
        let mut t = Vec::with_capacity(modes.len());
        for (c, rep) in self.replacements.iter().enumerate() {
            if modes[c] == OPEN || modes[c] == CLOSED {
                p.push(normal[c]);
                t.push(0.0);
                continue;
            }
            let [ra, rb] = rep.dofs;
            let dot = |row: &[(usize, f64)]| row.iter().map(|&(j, v)| v * u[j]).sum::<f64>();
            let mut r = [0.0; 2];
            r[rep.axes[0] as usize] = dot(&rep.normal_row.0) - rhs[ra];
            r[rep.axes[1] as usize] = dot(&rep.other_row) - rhs[rb];
            let nu = self.operator.direction(c);
            let tc = crate::contact::tangent(nu);
            p.push((nu[0] * r[0] + nu[1] * r[1]) / rep.weight);
            t.push((tc[0] * r[0] + tc[1] * r[1]) / rep.weight);
        }
        (p, t)
    }

    /// The final displacements of the frictional step that settled on `states` (those of its
    /// last solve; see [`RigidObstacle::final_displacements`]).
    ///
    /// # Errors
    /// A failed solve.
    pub fn final_friction_displacements(
        &mut self,
        states: &[ContactState],
    ) -> Result<Vec<f64>, ActiveSetError> {
        let modes = self.modes_of(states);
        self.final_displacements_of(&modes)
    }

    /// The rates `dP/ds` of the normal forces of the problem of `states` (each candidate's
    /// rows as its state, `Open` ones free) when the gaps without displacement move as
    /// `g0 − a s` (an obstacle, or the body itself, translated by `s`; `along` = `a`): one
    /// solve with that problem's matrix, whose right-hand side is `s_g a_c` on the closed
    /// candidates' gap rows and zero elsewhere, the rates read from the removed rows as the
    /// forces are (docs/method.md §4.6, §5.1). With `μ = 0` this is `M_AA⁻¹ a_A` on the
    /// closed set `A`, the slope of the force search being `a_Aᵀ M_AA⁻¹ a_A`.
    ///
    /// # Errors
    /// A failed solve.
    pub fn force_rate(
        &mut self,
        states: &[ContactState],
        along: &[f64],
    ) -> Result<Vec<f64>, ActiveSetError> {
        let modes = self.modes_of(states);
        let n = self.matrix.n;
        let mut b = vec![0.0; n];
        for (c, rep) in self.replacements.iter().enumerate() {
            if modes[c] != OPEN {
                b[rep.rows[0].0] = self.scale * along[c];
            }
        }
        let du = super::solve_refined(self, &modes, &b)?;
        Ok(self.friction_forces_with(&modes, &du, &vec![0.0; n]).0)
    }

    fn set_targets(&mut self, previous: &[f64]) {
        for (c, target) in self.tangential_target.iter_mut().enumerate() {
            *target = previous[c] + self.tangential_offset[c];
        }
    }
}

impl FrictionSystem for RigidObstacle<'_> {
    fn size(&self) -> usize {
        self.replacements.len()
    }
    fn friction(&self) -> Vec<f64> {
        if self.friction.is_empty() { vec![0.0; self.size()] } else { self.friction.clone() }
    }
    /// One solve with `K`'s own factorisation; `None` when it fails its accuracy check.
    fn free_response(&mut self) -> Result<Option<FreeResponse>, ActiveSetError> {
        match self.model.get().solve(&self.rhs) {
            Ok(u) => Ok(Some(self.gaps_and_slips(&u))),
            Err(_) => Ok(None),
        }
    }
    fn initial_gap(&self) -> Vec<f64> {
        self.initial_gap.clone()
    }
    fn solve_states(
        &mut self,
        states: &[ContactState],
        previous: &[f64],
    ) -> Result<StateResponse, ActiveSetError> {
        self.set_targets(previous);
        let modes = self.modes_of(states);
        let u = self.displacements_of(&modes)?;
        let (normal, tangential) = self.friction_forces(&modes, &u);
        let (gap, tangential_displacement) = self.gaps_and_slips(&u);
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
        let (n, k) = (self.matrix.n, free.len());
        let mu = FrictionSystem::friction(self);
        // Column 0: the held problem; 1 + j: unit P on free[j]; 1 + k + j: unit T on free[j]
        // (none where μ = 0: T stays 0 there).
        let mut x = Mat::<f64>::zeros(n, 2 * k + 1);
        for (i, v) in self.rhs_of(&held).into_iter().enumerate() {
            x[(i, 0)] = v;
        }
        for (j, &c) in free.iter().enumerate() {
            let nu = self.operator.direction(c);
            let t = crate::contact::tangent(nu);
            for &(i, w) in &self.operator.owners[c] {
                for ax in Axis::BOTH {
                    x[(dof(i as usize, ax), j + 1)] += nu[ax as usize] * w;
                    if mu[c] > 0.0 {
                        x[(dof(i as usize, ax), k + j + 1)] += t[ax as usize] * w;
                    }
                }
            }
        }
        self.solve_columns(&held, x.as_mut())?;
        let response = |col: usize, with_offset: bool| {
            let (mut g, mut s) = self.gaps_and_slips(x.col_as_slice(col));
            if !with_offset {
                // The response to a unit force: no g0, no obstacle offset.
                for c in 0..g.len() {
                    g[c] -= self.initial_gap[c];
                    s[c] += self.tangential_offset[c];
                }
            }
            StateResponse {
                normal: Vec::new(),
                tangential: Vec::new(),
                gap: g,
                tangential_displacement: s,
            }
        };
        let base = response(0, true);
        let columns: Vec<StateResponse> = (1..=2 * k).map(|col| response(col, false)).collect();
        Ok(reduced_blocks(&base, &columns, free, previous, &mu))
    }
}
