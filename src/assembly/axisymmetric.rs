//! `K_int` of an axisymmetric body (docs/method.md §9.3): the cell balance per radian,
//! `∮ r t dΓ − e_r ∫ σ_θθ dA` (the field part; loads go to `f` with the weight `r`), with the
//! four-component strain `(ε_rr, ε_zz, γ_rz, ε_θθ)` collocated at the nodes,
//! `ε̂_J = Σ_K B₄,K(x_J) û_K`, and the blend `β` of §3.9 at the face and cell points:
//!
//! `K_int = −Q_r D₄ [(1 − β) Φ S₄ + β B₄,q] + e_r Q_A D₄,θ [(1 − β) Φ_A S₄ + β B₄,A]`
//!
//! with `Q_r` the face integral weighted by `r`, `Q_A` the cell integral, `Φ`/`Φ_A` the MLS
//! interpolation to face/cell points and `D₄,θ` the hoop row of `D₄`.

use super::{AssemblyInput, BlockRows};
use crate::material::Hoop;
use crate::mls::ShapeSet;
use crate::weak_form::EdgeLabel;
use crate::weak_form::axisymmetric::{CellQuadrature, hoop_coefficient, traction_operator};
use rayon::prelude::*;

/// What the axisymmetric balance needs besides the plane one: the hoop row and column of
/// `D₄`, and the cell quadrature of `∫ σ_θθ dA` with the shape functions at its points
/// (with gradients when `β > 0`).
#[derive(Clone, Copy, Debug)]
pub struct Axisymmetric<'a> {
    /// The hoop part of `D₄`.
    pub hoop: Hoop,
    /// Points inside each cell.
    pub cell_quadrature: &'a CellQuadrature,
    /// Shape functions at those points.
    pub cell_shapes: &'a ShapeSet,
}

/// One block row: column nodes and their 2 × 2 blocks.
type BlockRow = (Vec<u32>, Vec<[[f64; 2]; 2]>);

/// Dense per-row workspaces over the nodes: the 2 × 4 blocks per strain node `J` before `S₄`,
/// the 2 × 2 blocks per displacement node `K`, and their lists.
struct Row {
    qd: Vec<[[f64; 4]; 2]>,
    js: Vec<u32>,
    j_used: Vec<bool>,
    krow: Vec<[[f64; 2]; 2]>,
    ks: Vec<u32>,
    k_used: Vec<bool>,
}

impl Row {
    fn new(n: usize) -> Self {
        Self {
            qd: vec![[[0.0; 4]; 2]; n],
            js: Vec::new(),
            j_used: vec![false; n],
            krow: vec![[[0.0; 2]; 2]; n],
            ks: Vec::new(),
            k_used: vec![false; n],
        }
    }

    /// `qd[J] += c · t` (the interpolated strain of node `J` in the field force).
    fn add_strain(&mut self, j: u32, c: f64, t: &[[f64; 4]; 2]) {
        let ju = j as usize;
        if !self.j_used[ju] {
            self.j_used[ju] = true;
            self.js.push(j);
        }
        for (out, row) in self.qd[ju].iter_mut().zip(t) {
            for (o, v) in out.iter_mut().zip(row) {
                *o += c * v;
            }
        }
    }

    /// `krow[K] −= block` (a direct displacement term of the field force).
    fn sub_block(&mut self, k: u32, block: [[f64; 2]; 2]) {
        let ku = k as usize;
        if !self.k_used[ku] {
            self.k_used[ku] = true;
            self.ks.push(k);
        }
        for (out, row) in self.krow[ku].iter_mut().zip(block) {
            for (o, v) in out.iter_mut().zip(row) {
                *o -= v;
            }
        }
    }
}

/// `c · t B₄,K(x)` with `B₄,K` the columns `(φ,r, 0, φ,z, h)` for `u_r` and `(0, φ,z, φ,r, 0)`
/// for `u_z`, `h` the hoop coefficient ([`hoop_coefficient`]).
fn times_b(t: &[[f64; 4]; 2], c: f64, gx: f64, gy: f64, h: f64) -> [[f64; 2]; 2] {
    std::array::from_fn(|a| {
        [c * (t[a][0] * gx + t[a][2] * gy + t[a][3] * h), c * (t[a][1] * gy + t[a][2] * gx)]
    })
}

/// `K_int` of the axisymmetric balance, row by row in parallel (each row summed in face
/// order, then cell-point order).
pub(super) fn interior_stiffness(input: &AssemblyInput<'_>, axi: &Axisymmetric<'_>) -> BlockRows {
    let n = input.body.nodes.len();
    let adjacency = super::face_adjacency(input.interior_faces, n);
    let rows: Vec<BlockRow> = (0..n)
        .into_par_iter()
        .with_min_len(1024)
        .map_init(|| Row::new(n), |row, i| stiffness_row(input, axi, &adjacency, row, i))
        .collect();
    super::block_rows(rows)
}

/// Row `i` of [`interior_stiffness`].
fn stiffness_row(
    input: &AssemblyInput<'_>,
    axi: &Axisymmetric<'_>,
    adjacency: &super::FaceAdjacency,
    row: &mut Row,
    i: usize,
) -> BlockRow {
    let (beta, mixed) = (input.beta, 1.0 - input.beta);
    let d = input.body.d;
    let h = input.body.nodes.spacing[i];
    let (q, fs) = (input.face_quadrature, input.face_shapes);
    // Faces: ∮ r T₄(n) ε dΓ.
    for &(f, sign) in adjacency.of(i) {
        let face = &input.interior_faces[f as usize];
        debug_assert!(matches!(face.across, EdgeLabel::Neighbour(_)));
        let t = traction_operator(face.normal, d, &axi.hoop);
        for p in q.offsets[f as usize]..q.offsets[f as usize + 1] {
            let r = q.points[p][0];
            let w = sign * q.weights[p] * r;
            if mixed > 0.0 {
                for (&j, &phi) in fs.support(p).iter().zip(fs.phi(p)) {
                    row.add_strain(j, mixed * w * phi, &t);
                }
            }
            if beta > 0.0 {
                let (dx, dy) = fs.grad(p);
                for (((&k, &phi), &gx), &gy) in fs.support(p).iter().zip(fs.phi(p)).zip(dx).zip(dy)
                {
                    // r_q > 0 inside a face; the hoop column times r is φ itself.
                    row.sub_block(k, times_b(&t, beta * w, gx, gy, phi / r));
                }
            }
        }
    }
    // The cell: −e_r ∫ σ_θθ dA.
    let hoop_row = [axi.hoop.row(), [0.0; 4]];
    let (cq, cs) = (axi.cell_quadrature, axi.cell_shapes);
    for p in cq.offsets[i]..cq.offsets[i + 1] {
        let w = -cq.weights[p];
        if mixed > 0.0 {
            for (&j, &phi) in cs.support(p).iter().zip(cs.phi(p)) {
                row.add_strain(j, mixed * w * phi, &hoop_row);
            }
        }
        if beta > 0.0 {
            let r = cq.points[p][0];
            let (dx, dy) = cs.grad(p);
            for (((&k, &phi), &gx), &gy) in cs.support(p).iter().zip(cs.phi(p)).zip(dx).zip(dy) {
                row.sub_block(
                    k,
                    times_b(&hoop_row, beta * w, gx, gy, hoop_coefficient(phi, gx, r, h)),
                );
            }
        }
    }
    // Times S₄: ε̂_J = Σ_K B₄,K(x_J) û_K.
    row.js.sort_unstable();
    let ns = input.node_shapes;
    let js = std::mem::take(&mut row.js);
    for &j in &js {
        let ju = j as usize;
        let blk = row.qd[ju];
        let (rj, hj) = (input.body.nodes.points[ju][0], input.body.nodes.spacing[ju]);
        let (dx, dy) = ns.grad(ju);
        for (((&k, &phi), &gx), &gy) in ns.support(ju).iter().zip(ns.phi(ju)).zip(dx).zip(dy) {
            row.sub_block(k, times_b(&blk, 1.0, gx, gy, hoop_coefficient(phi, gx, rj, hj)));
        }
        row.qd[ju] = [[0.0; 4]; 2];
        row.j_used[ju] = false;
    }
    row.js = js;
    row.js.clear();
    row.ks.sort_unstable();
    let ks = std::mem::take(&mut row.ks);
    let blocks = ks
        .iter()
        .map(|&k| {
            let ku = k as usize;
            row.k_used[ku] = false;
            std::mem::replace(&mut row.krow[ku], [[0.0; 2]; 2])
        })
        .collect();
    (ks, blocks)
}
