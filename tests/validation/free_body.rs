//! Free body (method.md §3.8): with no displacement conditions, `K_int` must have exactly three
//! near-zero singular values (two translations, one rotation) and a clear gap to the fourth.
//! Nodal collocation of strains resembles nodal integration, which can admit spurious
//! zero-energy modes; the prototype measured on a 9 × 9 free body s₄/s_max ≈ 4e-3 at
//! `α_s = 2` and 7e-7 at `α_s = 3` (checkerboard modes). Those are the two cases checked here:
//! the positive one at `α_s = 2` and the documented negative one at `α_s = 3`.

use super::common::*;
use mlpg_contact::geometry::Domain;
use mlpg_contact::nodes::Layout;

/// Singular values of the unconstrained `K_int` of a 9 × 9 node square, descending.
fn singular_values(layout: Layout, support_factor: f64) -> Vec<f64> {
    let domain = Domain::rectangle([0.0, 1.0], [0.0, 1.0]).unwrap();
    let mut problem = base_problem(domain, 0.125, layout, plane_stress(1.0, 0.3));
    problem.discretisation.mls.support_factor = support_factor;
    // Assembly refuses a free body, so build K_int through a single pinned node's problem
    // and use the interior stiffness, which does not depend on the boundary conditions.
    problem.boundary[3] = displacement(std::sync::Arc::new(|_| [0.0, 0.0]));
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&problem, &mut silent).unwrap();
    let dense = model.system.interior_stiffness.to_dense();
    let n = dense.len();
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| dense[i][j]);
    let mut s = m.singular_values().unwrap();
    s.sort_by(|a, b| b.total_cmp(a));
    s
}

fn check_rigid_modes(s: &[f64], layout: &str) -> f64 {
    let n = s.len();
    let smax = s[0];
    for k in 1..=3 {
        assert!(s[n - k] < 1e-12 * smax, "{layout}: s[{}]/s_max = {:.3e}", n - k, s[n - k] / smax);
    }
    s[n - 4] / smax
}

#[test]
fn three_rigid_modes_and_a_gap_at_support_factor_2() {
    for (name, layout) in [
        ("structured", Layout::Structured),
        ("jittered", Layout::Jittered { amplitude: 0.25, seed: 2 }),
    ] {
        let s = singular_values(layout, 2.0);
        let gap = check_rigid_modes(&s, name);
        println!("{name}, α_s = 2: s4/s_max = {gap:.3e}");
        assert!(gap > 1e-3, "{name}: s4/s_max = {gap:.3e} (spurious near-zero-energy mode)");
    }
}

/// The documented negative case: at `α_s = 3` checkerboard modes are nearly free.
#[test]
fn near_zero_energy_modes_at_support_factor_3() {
    let s = singular_values(Layout::Structured, 3.0);
    let gap = check_rigid_modes(&s, "structured");
    println!("structured, α_s = 3: s4/s_max = {gap:.3e}");
    assert!(gap < 1e-5, "expected a near-free checkerboard mode, s4/s_max = {gap:.3e}");
}
