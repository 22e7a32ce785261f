//! The clamped cantilever of `problems/cantilever.toml` (L = 48, D = 12, E = 3e7, ν = 0.3,
//! plane stress; the left edge fully clamped, `u = 0`; a uniform shear traction on `x = L` of
//! resultant `P = 1000`): the measures shared by `clamped_cantilever.rs` and
//! `examples/studies/adaptive_cantilever.rs`.
//!
//! The measure is the compliance `W = ∫_{x = L} t · u dy` (the load's work, twice the strain
//! energy); MFVM: the MLS field `u^h` at 4 Gauss points per interval between boundary nodes;
//! FE (Q2): Simpson's rule on each element side, exact for the quadratic trace. Also the tip
//! deflection `u_y(L, 0)` (a node in every set used).

use mlpg_contact::mls;
use mlpg_contact::problem::{Method, Problem};
use mlpg_contact::{Model, Silent, Solution};

/// Beam length (the clamped edge is `x = 0`, the loaded one `x = L`).
pub const LENGTH: f64 = 48.0;
/// The end shear traction `t_y` of the problem file (`P / D`).
pub const SHEAR: f64 = 1000.0 / 12.0;

/// `problems/cantilever.toml` at spacing (MFVM) or element size (FE) `h`, with the stabilised
/// blend `β = 0.5` (the pure mixed method is not robust on graded node sets,
/// docs/method.md §2.1; uniform and graded runs use the same blend).
pub fn cantilever(h: f64, method: Method) -> Problem {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/cantilever.toml");
    let mut p =
        Problem::from_toml(&std::fs::read_to_string(path).expect("problem file")).expect("valid");
    assert_eq!(p.domain.bounding_box(), ([0.0, -6.0], [LENGTH, 6.0]), "the shipped cantilever");
    p.node_spacing = h;
    p.discretisation.beta = 0.5;
    p.discretisation.method = method;
    p
}

/// The nodes on `x = L`, sorted by `y`.
fn right_edge(model: &Model) -> Vec<usize> {
    let p = &model.nodes.points;
    let mut ids: Vec<usize> =
        (0..p.len()).filter(|&i| (p[i][0] - LENGTH).abs() < 1e-9 * LENGTH).collect();
    ids.sort_by(|&a, &b| p[a][1].total_cmp(&p[b][1]));
    ids
}

/// The tip deflection `u_y(L, 0)` (at the node there).
pub fn tip(model: &Model, s: &Solution) -> f64 {
    let p = &model.nodes.points;
    let i = (0..p.len())
        .find(|&i| (p[i][0] - LENGTH).abs() < 1e-9 * LENGTH && p[i][1].abs() < 1e-9 * LENGTH)
        .expect("a node at (L, 0)");
    s.displacement[i][1]
}

/// `W = ∫ t_y u^h_y dy` on `x = L` for an MFVM solution (4 Gauss points per interval).
pub fn compliance_mfvm(p: &Problem, model: &Model, s: &Solution) -> f64 {
    const G: [(f64, f64); 4] = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    ];
    let ids = right_edge(model);
    let (mut points, mut weights) = (Vec::new(), Vec::new());
    for w in ids.windows(2) {
        let (a, b) = (model.nodes.points[w[0]][1], model.nodes.points[w[1]][1]);
        for (xi, wi) in G {
            points.push([LENGTH, 0.5 * (a + b) + 0.5 * (b - a) * xi]);
            weights.push(0.5 * (b - a) * wi);
        }
    }
    let mfvm = model.mfvm().expect("an MFVM model");
    let set =
        mls::shape_functions(&points, &model.nodes, &mfvm.supports, &p.discretisation.mls, false)
            .expect("shape functions on x = L");
    let w: f64 = weights
        .iter()
        .enumerate()
        .map(|(k, w)| w * set.interpolate(k, &s.nodal_parameters)[1])
        .sum();
    SHEAR * w
}

/// `W` for an FE (Q2) solution: Simpson's rule on each element side (nodes `h/2` apart).
pub fn compliance_fem(model: &Model, s: &Solution) -> f64 {
    let ids = right_edge(model);
    assert!(ids.len() % 2 == 1, "{} Q2 nodes on x = L", ids.len());
    let y = |j: usize| model.nodes.points[ids[j]][1];
    let u = |j: usize| s.displacement[ids[j]][1];
    let w: f64 = (2..ids.len())
        .step_by(2)
        .map(|k| (y(k) - y(k - 2)) / 6.0 * (u(k - 2) + 4.0 * u(k - 1) + u(k)))
        .sum();
    SHEAR * w
}

/// Discretises and solves `p` (one body, no contact); checks the residual and equilibrium.
pub fn solve(p: &Problem) -> (Model, Solution) {
    let mut silent = Silent;
    let model = mlpg_contact::discretise(p, &mut silent).expect("discretise");
    let (model, _, s) = mlpg_contact::solve_model(p, model, None, &mut silent).expect("solve");
    // The linear solve's relative residual (observed up to 1.5e-10 on the FE systems).
    assert!(s.relative_residual < 1e-9, "residual {}", s.relative_residual);
    assert!(s.equilibrium_error < 1e-9, "equilibrium {}", s.equilibrium_error);
    (model, s)
}

/// Richardson extrapolation of three values at halving sizes, with the observed rate
/// `log₂((a − b)/(b − c))`: `(c + (c − b)/(2^rate − 1), rate)`.
pub fn extrapolate(a: f64, b: f64, c: f64) -> (f64, f64) {
    let rate = ((a - b) / (b - c)).log2();
    (c + (c - b) / (2f64.powf(rate) - 1.0), rate)
}

/// The FE reference: `W` at the element sizes `sizes` (halving), extrapolated from the last
/// three; its error bar is the change of the extrapolation when the three sizes before are
/// used instead (needs four sizes or more). Returns `(W_ref, bar, rate, values)`.
pub fn fe_reference(sizes: &[f64]) -> (f64, f64, f64, Vec<f64>) {
    assert!(sizes.len() >= 4 && sizes.windows(2).all(|w| w[1] == 0.5 * w[0]), "{sizes:?}");
    let values: Vec<f64> = sizes
        .iter()
        .map(|&h| {
            let p = cantilever(h, Method::Fem);
            let (m, s) = solve(&p);
            compliance_fem(&m, &s)
        })
        .collect();
    let n = values.len();
    let (w, rate) = extrapolate(values[n - 3], values[n - 2], values[n - 1]);
    let (coarser, _) = extrapolate(values[n - 4], values[n - 3], values[n - 2]);
    (w, (w - coarser).abs(), rate, values)
}
