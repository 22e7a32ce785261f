//! The spectrum behind the θ-method's stability on the MFVM (docs/method.md §10.2): the
//! generalised eigenvalues `K x = λ M x` of the free bar of `problems/bar_impact.toml`
//! (Petrov–Galerkin `K`, not symmetric) for several β and two lumpings of the mass — on the
//! nodal parameters (`M = diag(ρ|Ω_I|)`, the code's choice) and on the nodal values
//! (`M Φ`). A complex `λ` gives `ω = √λ` with `Im ω ≠ 0`: the θ = ½ scheme then grows at
//! about `|Im ω|` per unit time.
//!
//! `cargo run --release --features studies --example dynamics_spectrum`

use faer::Mat;
use faer::prelude::Solve;
use mlpg_contact::problem::{Problem, ProblemFile};
use mlpg_contact::progress::{Clock, Silent};

fn bar(spacing: f64, beta: f64) -> Problem {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/bar_impact.toml");
    let mut file =
        ProblemFile::from_toml(&std::fs::read_to_string(path).expect("read")).expect("parse");
    file.contact = None;
    file.nodes.as_mut().expect("nodes").spacing = Some(spacing);
    file.discretisation.beta = Some(mlpg_contact::problem::BetaChoice::Value(beta));
    Problem::try_from(file).expect("valid")
}

/// `(max |Im ω|, |ω| of that mode, max |ω|, count of λ with |Im λ| > 1e-9 max|λ|, the
/// smallest θ whose damping `(θ − ½) h² |ω|²` per step outweighs the growth `h |Im ω|` of
/// every mode at step `h`)`.
fn spectrum(k: &Mat<f64>, h: f64) -> (f64, f64, f64, usize, f64) {
    let eig = k.eigenvalues().expect("eigenvalues");
    let top = eig.iter().map(|l| l.norm()).fold(0.0, f64::max);
    let complex = eig.iter().filter(|l| l.im.abs() > 1e-9 * top).count();
    let omega: Vec<_> = eig.iter().map(|l| l.sqrt()).collect();
    let worst = omega.iter().max_by(|a, b| a.im.abs().total_cmp(&b.im.abs())).expect("modes");
    let abs = omega.iter().map(|w| w.norm()).fold(0.0, f64::max);
    let theta = omega
        .iter()
        .filter(|w| w.norm() > 1e-6 * abs)
        .map(|w| 0.5 + w.im.abs() / (h * w.norm() * w.norm()))
        .fold(0.5, f64::max);
    (worst.im.abs(), worst.norm(), abs, complex, theta)
}

fn main() {
    println!(
        "spacing,beta,mass,n,max_abs_omega,max_im_omega,abs_omega_of_that_mode,complex_eigenvalues,min_real_lambda,theta_needed_at_h=spacing/2"
    );
    for spacing in [0.05, 0.025] {
        for beta in [0.0, 0.5, 1.0] {
            let problem = bar(spacing, beta);
            let mut silent = Silent;
            let mut clock = Clock::new(&mut silent, Vec::new());
            let parts =
                mlpg_contact::pipeline::dynamics::discretise(&problem, &mut clock).expect("body");
            let a = &parts.system.matrix;
            let n = a.n;
            let density = problem.dynamics.as_ref().expect("dynamics").density;
            let mass = mlpg_contact::dynamics::mass::lumped_mass(&parts.mfvm.cells, density);
            let mut k = Mat::<f64>::zeros(n, n);
            for c in 0..n {
                for e in a.col_ptr[c]..a.col_ptr[c + 1] {
                    k[(a.row_idx[e], c)] += a.values[e];
                }
            }
            // On the parameters: M⁻¹ K.
            let mut on_params = k.clone();
            for r in 0..n {
                for c in 0..n {
                    on_params[(r, c)] /= mass[r];
                }
            }
            // On the nodal values: (M Φ)⁻¹ K.
            let shapes = &parts.node_shapes;
            let mut phi = Mat::<f64>::zeros(n, n);
            for i in 0..shapes.len() {
                for (&j, &p) in shapes.support(i).iter().zip(shapes.phi(i)) {
                    for axis in 0..2 {
                        phi[(2 * i + axis, 2 * j as usize + axis)] = mass[2 * i + axis] * p;
                    }
                }
            }
            let on_values = phi.partial_piv_lu().solve(&k);
            for (label, m) in [("parameters", &on_params), ("values", &on_values)] {
                let (im, at, abs, complex, theta) = spectrum(m, spacing / 2.0);
                let eig = m.eigenvalues().expect("eigenvalues");
                let min_re = eig.iter().map(|l| l.re).fold(f64::INFINITY, f64::min);
                println!(
                    "{spacing},{beta},{label},{n},{abs:.4e},{im:.4e},{at:.4e},{complex},{min_re:.3e},{theta:.4}"
                );
            }
        }
    }
}
