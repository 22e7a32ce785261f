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
    let spec = problem.contact().unwrap();
    let contact::ContactTarget::Rigid(line) = spec.target else { panic!("rigid obstacle") };
    let target = |x| (line.gap(x), line.normal);
    let cand =
        contact::candidates_on(&problem, &model, spec.edge, &target, spec.condensation).unwrap();
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
    let nu = line.normal;
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

/// The frictional blocks `M_ab = G_a K⁻¹ E_b` (`a, b ∈ {n, t}`) and `q_n`, `q_t` of one
/// multi-column condensation (docs/method.md §8) equal a dense computation with `G_t`, `E_t`
/// written out independently from `t = (ν_y, −ν_x)`, for the MFVM and the FE beam.
/// Tolerance as above (round-off amplified by cond(K)), 1e-9 for the FE beam, whose `K` has
/// four times the DOFs at the same `h` and a dense LU 20 times less accurate (4.6e-11 observed).
#[test]
fn frictional_blocks_equal_dense_computation() {
    for (file, tol) in [("beam_on_foundation.toml", 1e-10), ("beam_on_foundation_fem.toml", 1e-9)] {
        let problem = shipped_problem(file, 1.0);
        let mut silent = mlpg_contact::Silent;
        let model = mlpg_contact::discretise(&problem, &mut silent).unwrap();
        let spec = problem.contact().unwrap();
        let contact::ContactTarget::Rigid(line) = spec.target else { panic!("rigid obstacle") };
        let target = |x| (line.gap(x), line.normal);
        let cand = contact::candidates_on(&problem, &model, spec.edge, &target, spec.condensation)
            .unwrap();
        let (tangential, free) = cand.tangential_operator(&model.system);
        assert!(free.iter().all(|&f| f), "{file}: no beam candidate is tangentially clamped");
        let blocks = contact::condense_blocks(
            &model.factorisation,
            &model.system.rhs,
            &cand.operator,
            &tangential,
        )
        .unwrap()
        .with_initial_gap(&cand.initial_gap);
        let a = &model.system.matrix;
        let n = a.n;
        let mut k = faer::Mat::<f64>::zeros(n, n);
        for c in 0..n {
            for p in a.col_ptr[c]..a.col_ptr[c + 1] {
                k[(a.row_idx[p], c)] += a.values[p];
            }
        }
        let m = cand.len();
        let nu = line.normal;
        let t = [nu[1], -nu[0]];
        let mut e = faer::Mat::<f64>::zeros(n, 2 * m);
        let mut g = faer::Mat::<f64>::zeros(2 * m, n);
        for (c, &node) in cand.nodes.iter().enumerate() {
            let node = node as usize;
            for (b, d) in [nu, t].iter().enumerate() {
                e[(2 * node, b * m + c)] = d[0];
                e[(2 * node + 1, b * m + c)] = d[1];
                let ns = &model.node_shapes;
                for (&j, &phi) in ns.support(node).iter().zip(ns.phi(node)) {
                    g[(b * m + c, 2 * j as usize)] += d[0] * phi;
                    g[(b * m + c, 2 * j as usize + 1)] += d[1] * phi;
                }
            }
        }
        use faer::linalg::solvers::Solve;
        let lu = k.partial_piv_lu();
        let dense = &g * lu.solve(&e);
        let f = faer::Mat::<f64>::from_fn(n, 1, |i, _| model.system.rhs[i]);
        let gf = &g * lu.solve(&f);
        let scale = (0..2 * m).map(|i| dense[(i, i)].abs()).fold(0.0, f64::max);
        let q_scale = (0..2 * m).map(|i| gf[(i, 0)].abs()).fold(0.0, f64::max)
            + cand.initial_gap.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut worst = 0.0f64;
        for (a, b, block) in
            [(0, 0, &blocks.nn), (0, 1, &blocks.nt), (1, 0, &blocks.tn), (1, 1, &blocks.tt)]
        {
            for i in 0..m {
                for j in 0..m {
                    let d = dense[(a * m + i, b * m + j)] - block[i * m + j];
                    worst = worst.max(d.abs());
                }
            }
        }
        let mut worst_q = 0.0f64;
        for i in 0..m {
            worst_q = worst_q.max((cand.initial_gap[i] + gf[(i, 0)] - blocks.free_gap[i]).abs());
            worst_q = worst_q.max((gf[(m + i, 0)] - blocks.free_tangential[i]).abs());
        }
        let coupling = (0..m * m).map(|i| blocks.nt[i].abs()).fold(0.0, f64::max) / scale;
        println!(
            "{file}: m = {m}, max |M_ab − dense| / max diag = {:.3e}, max |q − dense| / max|q| = {:.3e}, max |M_nt| / max diag = {coupling:.3e}",
            worst / scale,
            worst_q / q_scale
        );
        assert!(worst < tol * scale, "{file}: blocks differ by {worst:.3e}, scale {scale:.3e}");
        assert!(worst_q < tol * q_scale, "{file}: q differs by {worst_q:.3e}");
        // The normal block is the frictionless M, bit for bit (same columns, same solves).
        let part =
            contact::condense(&model.factorisation, &model.system.rhs, &cand.operator).unwrap();
        assert_eq!(blocks.nn, part.compliance, "{file}: M_nn is the frictionless M");
        // The tangential rows are not decoupled from the normal ones on a finite body.
        assert!(coupling > 1e-6, "{file}: M_nt unexpectedly zero");
    }
}

/// A candidate whose tangential row is a displacement condition (the bottom-left corner of
/// `two_blocks.toml`'s upper block, on a roller `u_x = 0`) gets no tangential force.
#[test]
fn tangentially_clamped_candidate_is_frictionless() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/two_blocks.toml");
    let problem =
        mlpg_contact::problem::Problem::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap();
    let mut silent = mlpg_contact::Silent;
    let model = mlpg_contact::discretise(&problem, &mut silent).unwrap();
    let spec = problem.contact().unwrap();
    let cand = contact::candidates_on(
        &problem,
        &model,
        spec.edge,
        &|_| (0.0, [0.0, 1.0]),
        spec.condensation,
    )
    .unwrap();
    assert!((0..cand.len()).all(|c| cand.tangent(c) == [1.0, -0.0]));
    let (op, free) = cand.tangential_operator(&model.system);
    let clamped: Vec<usize> = (0..cand.len()).filter(|&c| !free[c]).collect();
    assert_eq!(clamped, vec![0], "only the corner on the roller x = 0");
    assert!(cand.points[0][0] == 0.0 && op.owners[0].is_empty());
    assert!(op.owners[1..].iter().all(|o| o.len() == 1));
}

/// `M` by reach-restricted solves in the static-pivoting LU's own supernodal factors
/// (`contact::sparse_compliance`, nested dissection) on the shipped contact problems with a
/// rigid line obstacle, against
/// 1. blocked full solves with the same factors (`condense_blocked`): the same arithmetic up
///    to the order of the sums, so round-off: 1e-12 of max |M| (observed ≤ 2e-12 on the
///    84k-unknown strip of `examples/studies/contact_timing.rs`, whose `K` is far worse
///    conditioned than these);
/// 2. the current `M` (faer's partial-pivoting LU, blocked solves): two different backward
///    stable LUs, so round-off amplified by cond(K), 1e-10 of max |M| as the dense check
///    above.
///
/// Lemke (same `q`) on the three `M`: the same pivots and the same active set, and contact
/// forces within 10 κ times the relative difference of the `M` compared (at least 1e-15),
/// κ = λ_max/λ_min of the symmetric part: Lemke's own round-off is amplified by about κ (on
/// the refined beam, κ = 2.9e5, `M` differing by 4e-15 gave forces differing by 4.7e-10; on
/// the beam, κ = 1.3e4, 1.1e-11). Every solution satisfies complementarity and
/// `w = M z + q` to 1e-12 (scaled residuals, `common::assert_lcp_residuals`). The spacing is
/// 1 for the beams, 0.05 for the Hertz cylinder (the refined beam is refined to 0.0625
/// along its contact edge: 768 candidates).
#[test]
fn sparse_condensation_equals_blocked_solves_on_shipped_problems() {
    use mlpg_contact::lcp::{Lcp, LemkeParams, lemke};
    use mlpg_contact::linear_solve::{ColumnOrdering, FactorOptions, Factorisation};
    let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let max_diff =
        |a: &[f64], b: &[f64]| a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    for file in [
        "beam_on_foundation.toml",
        "beam_on_foundation_stabilised.toml",
        "beam_on_foundation_refined.toml",
        "hertz_cylinder.toml",
    ] {
        let shipped = shipped_problem(file, 1.0);
        let h = if file.starts_with("hertz") { 0.05 } else { 1.0 };
        let problem = mlpg_contact::problem::Problem { node_spacing: h, ..shipped };
        let model = mlpg_contact::discretise(&problem, &mut mlpg_contact::Silent).unwrap();
        let spec = problem.contact().unwrap();
        let contact::ContactTarget::Rigid(line) = spec.target else { panic!("{file}: rigid line") };
        let target = |x| (line.gap(x), line.normal);
        let cand = contact::candidates_on(&problem, &model, spec.edge, &target, spec.condensation)
            .unwrap();
        let (rhs, op) = (&model.system.rhs, &cand.operator);
        let current = contact::condense(&model.factorisation, rhs, op).unwrap();
        let nd = Factorisation::with_options(
            &model.system.matrix,
            ColumnOrdering::NestedDissection(&model.nodes.points),
            &FactorOptions::nested_dissection_static(),
        )
        .unwrap();
        let sparse =
            contact::sparse_compliance(&nd, op).unwrap().expect("the sparse route applies");
        let full = contact::condense_blocked(&nd, rhs, op, 64).unwrap();
        let scale = max_abs(&current.compliance);
        let same_factors = max_diff(&sparse, &full.compliance) / scale;
        let other_lu = max_diff(&sparse, &current.compliance) / scale;
        println!(
            "{file}: m = {}, sparse vs full solves (same factors) {same_factors:.2e}, vs faer's \
             LU {other_lu:.2e} of max |M|",
            cand.len()
        );
        assert!(same_factors <= 1e-12, "{file}: {same_factors:e}");
        assert!(other_lu <= 1e-10, "{file}: {other_lu:e}");
        let q: Vec<f64> =
            cand.initial_gap.iter().zip(&current.free_gap).map(|(g, f)| g + f).collect();
        let m = cand.len();
        let solve = |compliance: Vec<f64>| {
            let lcp = Lcp::new(m, compliance, q.clone()).unwrap();
            let s = lemke(&lcp, &LemkeParams::default()).unwrap();
            super::common::assert_lcp_residuals(file, &s.residuals, 1e-12);
            s
        };
        let checks =
            contact::CondensedContact::combine(&cand.initial_gap, std::slice::from_ref(&full))
                .unwrap();
        let kappa = checks.max_symmetric_eigenvalue / checks.min_symmetric_eigenvalue;
        let (a, b, c) =
            (solve(sparse), solve(full.compliance.clone()), solve(current.compliance.clone()));
        assert_eq!(a.pivots, b.pivots, "{file}: pivots");
        let dz = max_diff(&a.z, &b.z) / max_abs(&a.z);
        let dz_faer = max_diff(&a.z, &c.z) / max_abs(&a.z);
        println!(
            "{file}: Lemke {} pivots; forces differ by {dz:.2e} (same factors), {dz_faer:.2e} \
             (faer's LU; κ = {kappa:.2e}) of the largest",
            a.pivots
        );
        let active = |z: &[f64]| z.iter().map(|&v| v > 0.0).collect::<Vec<_>>();
        assert_eq!(active(&a.z), active(&b.z), "{file}: active set");
        assert_eq!(active(&a.z), active(&c.z), "{file}: active set");
        assert!(dz <= 10.0 * kappa * same_factors.max(1e-15), "{file}: {dz:e}");
        assert!(dz_faer <= 10.0 * kappa * other_lu.max(1e-15), "{file}: {dz_faer:e}");
    }
}
