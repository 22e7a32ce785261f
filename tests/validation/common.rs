//! Shared helpers for the validation cases.

use mlpg_contact::geometry::{Domain, Point};
use mlpg_contact::material::{Material, PlaneState};
use mlpg_contact::nodes::Layout;
use mlpg_contact::problem::{ComponentCondition, Discretisation, EdgeCondition, Field, Problem};
use std::sync::Arc;

/// A vector field given as a function of position.
pub type VectorField = Arc<dyn Fn(Point) -> [f64; 2] + Send + Sync>;

/// `problems/<file>` (a shipped problem file) with the node spacing `h` substituted.
pub fn shipped_problem(file: &str, h: f64) -> Problem {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("problems").join(file);
    let mut p = Problem::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap();
    p.node_spacing = h;
    p
}

/// A problem on `domain` with default discretisation and no boundary conditions (free).
pub fn base_problem(domain: Domain, h: f64, layout: Layout, material: Material) -> Problem {
    let edges = domain.edge_count();
    Problem {
        name: "validation".into(),
        domain,
        node_spacing: h,
        layout,
        refinement: Default::default(),
        adaptive: None,
        material,
        discretisation: Discretisation::default(),
        boundary: vec![EdgeCondition::free(); edges],
        body_force: None,
        profile_edge: 0,
        write_steps: false,
        revolve: None,
        units: None,
        others: Vec::new(),
        contact_pairs: Vec::new(),
        mesh_nodes: None,
        dynamics: None,
        steps: Vec::new(),
    }
}

/// Plane-stress material.
pub fn plane_stress(young: f64, poisson: f64) -> Material {
    Material { young, poisson, plane: PlaneState::Stress }
}

/// Both components of `u` prescribed from a field.
pub fn displacement(u: VectorField) -> EdgeCondition {
    let (ux, uy) = (u.clone(), u);
    EdgeCondition::Components([
        ComponentCondition::Displacement(Field::Function(Arc::new(move |p| ux(p)[0]))),
        ComponentCondition::Displacement(Field::Function(Arc::new(move |p| uy(p)[1]))),
    ])
}

/// Both traction components from a field.
pub fn traction(t: VectorField) -> EdgeCondition {
    let (tx, ty) = (t.clone(), t);
    EdgeCondition::Components([
        ComponentCondition::Traction(Field::Function(Arc::new(move |p| tx(p)[0]))),
        ComponentCondition::Traction(Field::Function(Arc::new(move |p| ty(p)[1]))),
    ])
}

/// Least-squares slope of `log e` against `log h`.
pub fn convergence_rate(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = h.iter().zip(e).map(|(h, e)| (h.ln(), e.ln())).unzip();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Writes a small CSV of a convergence table to `target/validation/<case>/<file>`.
pub fn write_table(case: &str, file: &str, header: &str, rows: &[Vec<f64>]) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/validation").join(case);
    if std::fs::create_dir_all(&dir).is_ok() {
        let mut text = format!("{header}\n");
        for r in rows {
            let line: Vec<String> = r.iter().map(|v| format!("{v:.6e}")).collect();
            text.push_str(&line.join(","));
            text.push('\n');
        }
        let _ = std::fs::write(dir.join(file), text);
    }
}

/// Asserts that an LCP answer's residuals (`min z`, `min w`, `z·w`, `w − (Mz + q)`, each
/// signed so that a violation is positive) are at most `tolerance`, naming `label`.
pub fn assert_lcp_residuals(label: &str, r: &mlpg_contact::lcp::LcpResiduals, tolerance: f64) {
    for (what, v) in [
        ("min z", -r.min_z),
        ("min w", -r.min_w),
        ("z·w", r.max_complementarity),
        ("w − (Mz + q)", r.equation_residual),
    ] {
        assert!(v <= tolerance, "{label}: {what} {v}");
    }
}

/// The Hertz pressure fit of every Hertz case: `p² = p₀²(1 − x²/a²)` is linear in `x²`, so a
/// least-squares line through `(x_c², p_c²)` over the closed candidates with a positive
/// pressure gives the peak `p₀` and the half-width (contact radius) `a`. Returns `(p₀, a,
/// number of points)`; `NaN`s when fewer than two points (the callers assert the count).
pub fn hertz_fit(c: &mlpg_contact::ContactSolution) -> (f64, f64, usize) {
    let pts: Vec<(f64, f64)> = (0..c.closed.len())
        .filter(|&i| c.closed[i] && c.pressure[i] > 0.0)
        .map(|i| (c.candidates.points[i][0].powi(2), c.pressure[i].powi(2)))
        .collect();
    let n = pts.len() as f64;
    let (mx, my) = pts.iter().fold((0.0, 0.0), |s, p| (s.0 + p.0 / n, s.1 + p.1 / n));
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let slope = sxy / sxx;
    let alpha = my - slope * mx;
    (alpha.sqrt(), (-alpha / slope).sqrt(), pts.len())
}
