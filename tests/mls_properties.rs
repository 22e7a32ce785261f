//! Property tests of the defining identities of MLS shape functions [LS81] on random node
//! clouds (jittered grids with random amplitude, seed and support factor): partition of unity,
//! linear (and, for the quadratic basis, quadratic) reproduction, the gradient identities
//! `Σ∇φ_I = 0`, `Σ ∇φ_I x_Iᵀ = I`, and gradients against central finite differences.

use mlpg_contact::geometry::Domain;
use mlpg_contact::mls::{Basis, MlsParams, shape_functions};
use mlpg_contact::neighbours::Supports;
use mlpg_contact::nodes::{Layout, Nodes, generate};
use proptest::prelude::*;

fn cloud(seed: u64, amplitude: f64) -> Nodes {
    let domain = Domain::rectangle([0.0, 1.0], [0.0, 0.7]).unwrap();
    generate(&domain, 0.1, Layout::Jittered { amplitude, seed }).unwrap()
}

fn params(basis: Basis, support_factor: f64) -> MlsParams {
    MlsParams { basis, support_factor, ..MlsParams::default() }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn reproduction_and_gradient_identities(
        seed in 0u64..10_000,
        amplitude in 0.01f64..0.4,
        support_factor in 2.0f64..3.5,
        quadratic in proptest::bool::ANY,
        x in 0.0f64..1.0,
        y in 0.0f64..0.7,
    ) {
        let basis = if quadratic { Basis::Quadratic } else { Basis::Linear };
        // The quadratic basis needs 7 support nodes; corners of small supports lack them.
        let support_factor = if quadratic { support_factor.max(2.6) } else { support_factor };
        let nodes = cloud(seed, amplitude);
        let p = params(basis, support_factor);
        let supports = Supports::new(&nodes, p.support_factor);
        let set = shape_functions(&[[x, y]], &nodes, &supports, &p, true).unwrap();
        let (gx, gy) = set.grad(0);
        let mut sums = [0.0f64; 9];
        for (k, &i) in set.support(0).iter().enumerate() {
            let [xi, yi] = nodes.points[i as usize];
            let phi = set.phi(0)[k];
            sums[0] += phi;
            sums[1] += phi * xi;
            sums[2] += phi * yi;
            sums[3] += gx[k];
            sums[4] += gy[k];
            sums[5] += gx[k] * xi; // = 1
            sums[6] += gx[k] * yi; // = 0
            sums[7] += gy[k] * xi; // = 0
            sums[8] += gy[k] * yi; // = 1
        }
        let tol = 1e-11;
        prop_assert!((sums[0] - 1.0).abs() < tol, "partition of unity {}", sums[0]);
        prop_assert!((sums[1] - x).abs() < tol && (sums[2] - y).abs() < tol);
        // Gradients scale like 1/h = 10.
        prop_assert!(sums[3].abs() < 10.0 * tol && sums[4].abs() < 10.0 * tol);
        prop_assert!((sums[5] - 1.0).abs() < 10.0 * tol && sums[6].abs() < 10.0 * tol);
        prop_assert!(sums[7].abs() < 10.0 * tol && (sums[8] - 1.0).abs() < 10.0 * tol);
        if quadratic {
            let q: f64 = set.support(0).iter().zip(set.phi(0)).map(|(&i, &phi)| {
                let [xi, yi] = nodes.points[i as usize];
                phi * (xi * xi - 2.0 * xi * yi + 3.0 * yi * yi)
            }).sum();
            prop_assert!((q - (x * x - 2.0 * x * y + 3.0 * y * y)).abs() < tol);
        }
    }

    #[test]
    fn gradients_match_finite_differences(
        seed in 0u64..10_000,
        amplitude in 0.01f64..0.4,
        support_factor in 2.0f64..3.0,
        x in 0.05f64..0.95,
        y in 0.05f64..0.65,
    ) {
        let nodes = cloud(seed, amplitude);
        let p = params(Basis::Linear, support_factor);
        let supports = Supports::new(&nodes, p.support_factor);
        let d = 1e-6;
        let pts = [[x, y], [x + d, y], [x - d, y], [x, y + d], [x, y - d]];
        let set = shape_functions(&pts, &nodes, &supports, &p, true).unwrap();
        // Compare node by node over the union of supports (a node may enter or leave).
        let value = |k: usize, node: u32| {
            set.support(k).iter().position(|&j| j == node).map_or(0.0, |m| set.phi(k)[m])
        };
        let (gx, gy) = set.grad(0);
        for (m, &node) in set.support(0).iter().enumerate() {
            let fx = (value(1, node) - value(2, node)) / (2.0 * d);
            let fy = (value(3, node) - value(4, node)) / (2.0 * d);
            // Shape functions are C1 with gradients O(1/h) = O(10); FD error ~ d² φ''' + ε/d.
            prop_assert!((fx - gx[m]).abs() < 1e-5 * 10.0, "node {node}: fd {fx} vs {}", gx[m]);
            prop_assert!((fy - gy[m]).abs() < 1e-5 * 10.0, "node {node}: fd {fy} vs {}", gy[m]);
        }
    }
}

#[test]
fn too_few_nodes_is_an_error_naming_the_point() {
    let nodes = cloud(1, 0.2);
    let p = params(Basis::Quadratic, 1.2);
    let supports = Supports::new(&nodes, p.support_factor);
    let err = shape_functions(&[[0.0, 0.0]], &nodes, &supports, &p, false).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("(0.000000, 0.000000)") && msg.contains("needs at least 7"), "{msg}");
}
