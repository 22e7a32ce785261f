//! MLS shape functions `φ(x) = pᵀ(x) A⁻¹(x) B(x)` and gradients, paper eqs. (3)–(4).

use super::basis::MAX_TERMS;
use super::{MlsError, MlsParams, quartic_spline};
use crate::geometry::Point;
use crate::neighbours::Supports;
use rayon::prelude::*;

/// Shape functions (and optionally gradients) at a list of evaluation points, stored row-wise:
/// point `k` has support nodes `support(k)` with values `phi(k)` and gradients `grad(k)`.
#[derive(Clone, Debug, Default)]
pub struct ShapeSet {
    offsets: Vec<usize>,
    nodes: Vec<u32>,
    phi: Vec<f64>,
    dphi_dx: Vec<f64>,
    dphi_dy: Vec<f64>,
}

impl ShapeSet {
    /// Kronecker-delta rows: point `k` has the single entry `φ = 1` at `nodes[k]` (nodal
    /// parameters read as if they were displacements; used by the paper's stiffness-form
    /// condensation).
    pub fn nodal(nodes: &[u32]) -> Self {
        Self {
            offsets: (0..=nodes.len()).collect(),
            nodes: nodes.to_vec(),
            phi: vec![1.0; nodes.len()],
            dphi_dx: Vec::new(),
            dphi_dy: Vec::new(),
        }
    }
    /// The rows `rows` of this set, in that order (gradients kept when present).
    pub fn select_rows(&self, rows: &[usize]) -> Self {
        let grads = self.has_gradients();
        let mut out = Self { offsets: vec![0], ..Self::default() };
        for &k in rows {
            let range = self.offsets[k]..self.offsets[k + 1];
            out.nodes.extend_from_slice(&self.nodes[range.clone()]);
            out.phi.extend_from_slice(&self.phi[range.clone()]);
            if grads {
                out.dphi_dx.extend_from_slice(&self.dphi_dx[range.clone()]);
                out.dphi_dy.extend_from_slice(&self.dphi_dy[range]);
            }
            out.offsets.push(out.nodes.len());
        }
        out
    }
    /// Rows given explicitly: point `k` has the `(node, φ)` pairs `rows[k]` (nodes ascending;
    /// no gradients). Used for interpolating finite element shape functions.
    pub fn from_rows(rows: &[Vec<(u32, f64)>]) -> Self {
        let mut set = Self { offsets: vec![0], ..Self::default() };
        for row in rows {
            debug_assert!(row.windows(2).all(|w| w[0].0 < w[1].0), "nodes must ascend");
            for &(node, phi) in row {
                set.nodes.push(node);
                set.phi.push(phi);
            }
            set.offsets.push(set.nodes.len());
        }
        set
    }
    /// Number of evaluation points.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }
    /// Whether there are no evaluation points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Whether gradients were computed.
    pub fn has_gradients(&self) -> bool {
        self.dphi_dx.len() == self.phi.len()
    }
    /// Total number of stored (point, node) pairs.
    pub fn nnz(&self) -> usize {
        self.phi.len()
    }
    fn range(&self, k: usize) -> std::ops::Range<usize> {
        self.offsets[k]..self.offsets[k + 1]
    }
    /// Support nodes of point `k`, ascending.
    pub fn support(&self, k: usize) -> &[u32] {
        &self.nodes[self.range(k)]
    }
    /// `φ_J(x_k)` for `J` in `support(k)`.
    pub fn phi(&self, k: usize) -> &[f64] {
        &self.phi[self.range(k)]
    }
    /// `(∂φ_J/∂x, ∂φ_J/∂y)` at `x_k` for `J` in `support(k)`.
    ///
    /// # Panics
    /// If the set was computed without gradients.
    pub fn grad(&self, k: usize) -> (&[f64], &[f64]) {
        assert!(self.has_gradients(), "ShapeSet was computed without gradients");
        let r = self.range(k);
        (&self.dphi_dx[r.clone()], &self.dphi_dy[r])
    }
    /// `u^h(x_k) = Σ_J φ_J(x_k) û_J` for interleaved nodal values `û` (2 per node).
    pub fn interpolate(&self, k: usize, u_hat: &[f64]) -> [f64; 2] {
        let mut u = [0.0; 2];
        for (&j, &p) in self.support(k).iter().zip(self.phi(k)) {
            u[0] += p * u_hat[2 * j as usize];
            u[1] += p * u_hat[2 * j as usize + 1];
        }
        u
    }
}

/// MLS shape functions at `points` from the node cloud `nodes` with supports `supports`.
///
/// `φ(x) = pᵀ(x) A⁻¹(x) B(x)`, `A = Σ_I w_I p_I p_Iᵀ`, `B = [w_I p_I]` \[LS81\]; paper
/// eqs. (3)–(4). The basis is evaluated in coordinates shifted to the evaluation point and
/// scaled by the largest support radius there, so cond(`A`) does not grow as the spacing
/// shrinks. Gradients use `γ = A⁻¹p`, `γ_,k = A⁻¹(p_,k − A_,k γ)`,
/// `φ_I,k = w_I γ_,k·p_I + w_I,k γ·p_I` (docs/method.md §2); `A` is never inverted explicitly
/// except to estimate its condition.
///
/// Runs in parallel over points; the result does not depend on the number of threads.
///
/// # Errors
/// [`MlsError::TooFewNodes`] when a support holds no more nodes than basis terms,
/// [`MlsError::SingularMoment`] when `A` is ill-conditioned; the first failing point (in
/// order) is reported.
///
/// # Examples
/// ```
/// use mlpg_contact::{geometry::Domain, mls, neighbours::Supports, nodes};
/// let domain = Domain::rectangle([0.0, 1.0], [0.0, 1.0]).unwrap();
/// let cloud = nodes::generate(&domain, 0.25, nodes::Layout::Structured).unwrap();
/// let params = mls::MlsParams::default();
/// let supports = Supports::new(&cloud, params.support_factor);
/// let set = mls::shape_functions(&[[0.3, 0.6]], &cloud, &supports, &params, true).unwrap();
/// let sum: f64 = set.phi(0).iter().sum();
/// assert!((sum - 1.0).abs() < 1e-12);
/// ```
pub fn shape_functions(
    points: &[Point],
    nodes: &crate::nodes::Nodes,
    supports: &Supports,
    params: &MlsParams,
    gradients: bool,
) -> Result<ShapeSet, MlsError> {
    const CHUNK: usize = 1024;
    let chunks: Vec<Result<ShapeSet, MlsError>> = points
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut out = ShapeSet { offsets: vec![0], ..Default::default() };
            let mut support = Vec::new();
            for &x in chunk {
                supports.support_of(&nodes.points, x, &mut support);
                evaluate_point(x, &support, nodes, supports, params, gradients, &mut out)?;
            }
            Ok(out)
        })
        .collect();
    let mut set = ShapeSet { offsets: vec![0], ..Default::default() };
    for chunk in chunks {
        let chunk = chunk?;
        let base = set.nodes.len();
        set.offsets.extend(chunk.offsets[1..].iter().map(|o| o + base));
        set.nodes.extend_from_slice(&chunk.nodes);
        set.phi.extend_from_slice(&chunk.phi);
        set.dphi_dx.extend_from_slice(&chunk.dphi_dx);
        set.dphi_dy.extend_from_slice(&chunk.dphi_dy);
    }
    Ok(set)
}

type Small = [[f64; MAX_TERMS]; MAX_TERMS];

#[allow(clippy::too_many_arguments)]
fn evaluate_point(
    x: Point,
    support: &[usize],
    nodes: &crate::nodes::Nodes,
    supports: &Supports,
    params: &MlsParams,
    gradients: bool,
    out: &mut ShapeSet,
) -> Result<(), MlsError> {
    let basis = params.basis;
    let m = basis.terms();
    if support.len() <= m {
        return Err(MlsError::TooFewNodes {
            point: x,
            support_size: support.len(),
            needed: m + 1,
            basis: basis.name(),
        });
    }
    let s = support.iter().fold(0.0f64, |acc, &i| acc.max(supports.radius(i)));
    let n = support.len();
    let mut p = Vec::with_capacity(n);
    let mut w = Vec::with_capacity(n);
    let mut a: Small = [[0.0; MAX_TERMS]; MAX_TERMS];
    let mut ax: Small = [[0.0; MAX_TERMS]; MAX_TERMS];
    let mut ay: Small = [[0.0; MAX_TERMS]; MAX_TERMS];
    for &i in support {
        let xi = nodes.points[i];
        let r = supports.radius(i);
        let (dx, dy) = (x[0] - xi[0], x[1] - xi[1]);
        let (wi, dw_over_r) = quartic_spline(dx.hypot(dy) / r);
        let (wx, wy) = (dw_over_r * dx / (r * r), dw_over_r * dy / (r * r));
        let pi = basis.eval(-dx / s, -dy / s);
        for row in 0..m {
            for col in 0..=row {
                let pp = pi[row] * pi[col];
                a[row][col] += wi * pp;
                if gradients {
                    ax[row][col] += wx * pp;
                    ay[row][col] += wy * pp;
                }
            }
        }
        p.push(pi);
        w.push((wi, wx, wy));
    }
    for row in 0..m {
        for col in row + 1..m {
            a[row][col] = a[col][row];
            ax[row][col] = ax[col][row];
            ay[row][col] = ay[col][row];
        }
    }
    let chol = Cholesky::new(&a, m);
    let rcond = chol.as_ref().map_or(0.0, |c| c.rcond(&a));
    let chol = match chol {
        Some(c) if rcond >= params.min_rcond => c,
        _ => {
            return Err(MlsError::SingularMoment {
                point: x,
                support_size: n,
                rcond,
                min_rcond: params.min_rcond,
            });
        }
    };
    // p(x) at the shifted origin is e_0; its derivatives are e_1/s and e_2/s.
    let mut gamma = [0.0; MAX_TERMS];
    gamma[0] = 1.0;
    chol.solve(&mut gamma);
    let (mut gx, mut gy) = ([0.0; MAX_TERMS], [0.0; MAX_TERMS]);
    if gradients {
        gx[1] = 1.0 / s;
        gy[2] = 1.0 / s;
        for row in 0..m {
            for col in 0..m {
                gx[row] -= ax[row][col] * gamma[col];
                gy[row] -= ay[row][col] * gamma[col];
            }
        }
        chol.solve(&mut gx);
        chol.solve(&mut gy);
    }
    for (k, &i) in support.iter().enumerate() {
        let (wi, wx, wy) = w[k];
        let pi = &p[k];
        let dot = |v: &[f64; MAX_TERMS]| (0..m).map(|t| v[t] * pi[t]).sum::<f64>();
        let gp = dot(&gamma);
        out.nodes.push(i as u32);
        out.phi.push(wi * gp);
        if gradients {
            out.dphi_dx.push(wi * dot(&gx) + wx * gp);
            out.dphi_dy.push(wi * dot(&gy) + wy * gp);
        }
    }
    out.offsets.push(out.nodes.len());
    Ok(())
}

/// Cholesky factor of a small symmetric positive definite matrix (leading `m × m` block).
struct Cholesky {
    l: Small,
    m: usize,
}

// Index loops transcribe the textbook recurrences of dense Cholesky most plainly.
#[allow(clippy::needless_range_loop)]
impl Cholesky {
    fn new(a: &Small, m: usize) -> Option<Self> {
        let mut l: Small = [[0.0; MAX_TERMS]; MAX_TERMS];
        for j in 0..m {
            let mut d = a[j][j];
            for k in 0..j {
                d -= l[j][k] * l[j][k];
            }
            if d.is_nan() || d <= 0.0 {
                return None;
            }
            let djj = d.sqrt();
            l[j][j] = djj;
            for i in j + 1..m {
                let mut v = a[i][j];
                for k in 0..j {
                    v -= l[i][k] * l[j][k];
                }
                l[i][j] = v / djj;
            }
        }
        Some(Self { l, m })
    }

    fn solve(&self, b: &mut [f64; MAX_TERMS]) {
        let (l, m) = (&self.l, self.m);
        for i in 0..m {
            let mut v = b[i];
            for k in 0..i {
                v -= l[i][k] * b[k];
            }
            b[i] = v / l[i][i];
        }
        for i in (0..m).rev() {
            let mut v = b[i];
            for k in i + 1..m {
                v -= l[k][i] * b[k];
            }
            b[i] = v / l[i][i];
        }
    }

    /// `1 / (‖A‖₁ ‖A⁻¹‖₁)`, with `A⁻¹` formed column by column (m ≤ 6).
    fn rcond(&self, a: &Small) -> f64 {
        let m = self.m;
        let norm = |cols: &dyn Fn(usize) -> [f64; MAX_TERMS]| {
            (0..m).map(|j| cols(j)[..m].iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max)
        };
        let a_norm = norm(&|j| {
            let mut c = [0.0; MAX_TERMS];
            for i in 0..m {
                c[i] = a[i][j];
            }
            c
        });
        let inv_norm = norm(&|j| {
            let mut e = [0.0; MAX_TERMS];
            e[j] = 1.0;
            self.solve(&mut e);
            e
        });
        1.0 / (a_norm * inv_norm)
    }
}
