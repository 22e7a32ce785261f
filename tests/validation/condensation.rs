//! The condensed compliance `M = G K⁻¹ E` and `q = g0 + G K⁻¹ f` (docs/method.md §4.2), formed by
//! blocked sparse solves, equal a dense computation (dense LU of `K`, explicit `G` and `E`)
//! on a small beam-on-foundation problem. Tolerance: round-off amplified by cond(K) ~ 1e6.

use super::common::shipped_problem;
use mlpg_contact::contact::{self};

#[test]
fn condensed_compliance_equals_dense_computation() {
    let problem = shipped_problem("beam_on_foundation.toml", 1.0);
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&problem, &mut silent).unwrap();
    let spec = problem.contact.unwrap();
    let contact::ContactTarget::Rigid(line) = spec.target else { panic!("rigid obstacle") };
    let gap = |x| line.gap(x);
    let cand =
        contact::candidates_on(&problem, &model, spec.edge, line.normal, &gap, spec.condensation)
            .unwrap();
    let part = contact::condense(&model.factorisation, &model.system.rhs, &cand.operator).unwrap();
    let condensed = contact::CondensedContact::combine(&cand.initial_gap, &[part]).unwrap();
    // Dense K.
    let a = &model.system.matrix;
    let n = a.n;
    let mut k = faer::Mat::<f64>::zeros(n, n);
    for c in 0..n {
        for p in a.col_ptr[c]..a.col_ptr[c + 1] {
            k[(a.row_idx[p], c)] += a.values[p];
        }
    }
    let m = cand.len();
    // Dense E (n × m) and G (m × n), written out independently of the library's helpers.
    let nu = cand.normal;
    let mut e = faer::Mat::<f64>::zeros(n, m);
    let mut g = faer::Mat::<f64>::zeros(m, n);
    for (c, &node) in cand.nodes.iter().enumerate() {
        e[(2 * node as usize, c)] = nu[0];
        e[(2 * node as usize + 1, c)] = nu[1];
        let ns = &model.node_shapes;
        for (&j, &phi) in ns.support(node as usize).iter().zip(ns.phi(node as usize)) {
            g[(c, 2 * j as usize)] += nu[0] * phi;
            g[(c, 2 * j as usize + 1)] += nu[1] * phi;
        }
    }
    let lu = k.partial_piv_lu();
    use faer::linalg::solvers::Solve;
    let x = lu.solve(&e);
    let dense = &g * &x;
    let f = faer::Mat::<f64>::from_fn(n, 1, |i, _| model.system.rhs[i]);
    let gf = &g * lu.solve(&f);
    let scale = (0..m).map(|i| dense[(i, i)].abs()).fold(0.0, f64::max);
    let q_scale = condensed.free_gap.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut worst = 0.0f64;
    for i in 0..m {
        for j in 0..m {
            worst = worst.max((dense[(i, j)] - condensed.compliance[i * m + j]).abs());
        }
        let q = cand.initial_gap[i] + gf[(i, 0)];
        let dq = (q - condensed.free_gap[i]).abs();
        assert!(dq < 1e-10 * q_scale, "q[{i}]: {q} vs {}", condensed.free_gap[i]);
    }
    println!("max |M − M_dense| / max M_ii = {:.3e} (m = {m})", worst / scale);
    assert!(worst < 1e-10 * scale, "max |M − M_dense| = {worst:.3e}, scale {scale:.3e}");
}
