//! Adaptive refinement of FE meshes (`method = "fem"`, docs/method.md §2.2): the loop of
//! `problems/cylinder_indenter_adaptive.toml` (a rigid circle `R = 1` moved down by
//! `δ = 0.0025` onto the half block `[0, 2] × [−2, 0]`, plane strain) on Q2 elements from the
//! uniform element size 0.1, each step a graded tensor-product grid (the columns and rows
//! through the marked elements halved). Reference: Hertz (Hertz 1882; Johnson, *Contact
//! Mechanics* (1985), §4.3, eqs. 4.43–4.45), `a = √(4PR/(πE*))`, `p₀ = 2P/(πa)` for the
//! computed resultant `P`, measured by the helpers of `hertz.rs` and `cylinder_indenter.rs`
//! (least-squares fit of `p²` against `x²`; the LCP's complementarity, `M` positive definite,
//! equilibrium, one closed zone and the force balance at every measured step).
//!
//! The bound, 0.5 %, is the MFVM loop's on the same problem (`adaptive_hertz.rs`): the
//! converged answer differs from Hertz by 0.35–0.4 % there (the terms Hertz's `a ≪ R` and
//! half-space drop; docs/dev/adaptive.md), a floor the FE approaches too; the uniform
//! starting mesh misses it by far (fewer than 4 closed candidates, no fit), so the bound
//! fails unless the loop refines toward the contact.

use super::cylinder_indenter::checked;
use super::hertz::adaptive_rows;

/// The bound on the relative errors of `a` and `p₀` (the MFVM loop's; module docs).
const BOUND: f64 = 0.005;

#[test]
fn adaptive_fem_indenter_converges_to_hertz() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems/cylinder_indenter_adaptive.toml");
    let text = std::fs::read_to_string(path).unwrap().replace("beta = 0.5", "method = \"fem\"");
    let problem = mlpg_contact::problem::Problem::from_toml(&text).unwrap();
    assert_eq!(problem.discretisation.method, mlpg_contact::problem::Method::Fem);
    let (rows, stopped_by) = adaptive_rows(&problem, BOUND, |s| {
        let c = s.contact().unwrap();
        let closed = c.closed.iter().filter(|&&b| b).count();
        let n = s.displacement.len();
        (n, (closed >= 4).then(|| checked(&format!("adaptive FE, {n} nodes"), s).max_error()))
    });
    assert_eq!(stopped_by, "steps");
    // The first step has no fit or misses the bound: the refinement is what meets it.
    assert!(rows[0].1.is_none_or(|e| e > BOUND), "{rows:?}");
}
