//! Stage 6: assembly of `K û = f` (paper eqs. (12)–(15); docs/method.md §3.4–3.6).
//!
//! `K_int = −Q · blockdiag(D) · S`: `S` collocates the strains at the nodes
//! (`ε̂_J = Σ_K B_K(x_J) û_K`, eq. 15), `φ_J(x_q)` interpolates them to the quadrature points of
//! the interior faces (eq. 11), and `Q` integrates the traction `N(n) D ε^h` over each face
//! (eq. 12), with opposite signs for its two cells. Rows of Dirichlet DOFs are then replaced
//! by collocation of `u^h` (docs/method.md §3.6). `K` is sparse and non-symmetric.
//!
//! Stabilised variant (docs/method.md §3.9, beyond the paper): with a blend `β ∈ [0, 1]` the strain
//! at a face point is `(1 − β) Σ_J φ_J(x_q) ε̂_J + β Σ_K B_K(x_q) û_K`, so
//! `K_int = −Q D [(1 − β) Φ S + β B_q]` with `B_q` the MLS strain–displacement matrix at the
//! face points. `β = 0` is the paper's method; `β = 1` never touches `S` (the stencil of a row
//! shrinks from the supports of the supports of the face points to the face points' supports).

mod axisymmetric;

pub use axisymmetric::Axisymmetric;

use crate::geometry::{Domain, Point};
use crate::material::{Constitutive, Hoop};
use crate::mls::ShapeSet;
use crate::nodes::{Axis, Nodes, dof};
use crate::problem::{BodyForce, ComponentCondition, ContactTarget, EdgeCondition, Field, Problem};
use crate::weak_form::{
    Cell, CellError, EdgeLabel, Face, FaceQuadrature, segment_rule, traction_operator,
};
use rayon::prelude::*;

/// Failures of assembly.
#[derive(Debug, thiserror::Error)]
pub enum AssemblyError {
    /// Cell/face bookkeeping is inconsistent with the boundary conditions.
    #[error(transparent)]
    Cells(#[from] CellError),
    /// No displacement condition anywhere: `K` is singular (rigid-body motion).
    #[error(
        "no displacement is prescribed on any edge: the body can move rigidly and K is singular (add a displacement condition)"
    )]
    NoDirichlet,
    /// The displacement conditions leave a rigid-body motion free: `K` is singular.
    #[error(
        "the displacement conditions do not prevent rigid-body {mode}: K is singular (contact with a rigid obstacle may hold one free translation, not a rotation or both translations: docs/method.md §4.7; add a displacement condition)"
    )]
    RigidBodyMotion {
        /// Which motion is free.
        mode: &'static str,
    },
    /// The body's material is axisymmetric but the hoop terms were not given, or the other
    /// way round ([`AssemblyInput::axisymmetric`] against [`Body::hoop`]).
    #[error(
        "the body is {body} but the assembly input {input} (build AssemblyInput::axisymmetric from the cells exactly when the material is axisymmetric)"
    )]
    AxisymmetricMismatch {
        /// "axisymmetric" or "plane".
        body: &'static str,
        /// What the input has.
        input: &'static str,
    },
    /// `β > 0` blends in direct MLS strains at the face points, whose gradients were not
    /// computed (build the face shapes with [`needs_face_gradients`]).
    #[error("the blend beta = {beta} needs MLS gradients at the face quadrature points")]
    MissingFaceGradients {
        /// The blend.
        beta: f64,
    },
}

/// Whether the interior-face quadrature points need MLS gradients: for the direct-strain part
/// of the blend, `β > 0` (docs/method.md §3.9).
pub fn needs_face_gradients(beta: f64) -> bool {
    beta > 0.0
}

/// A sparse matrix in block-row form: row `I` (a node) holds 2 × 2 blocks `(I, J)` for the
/// column nodes `cols[offsets[I]..offsets[I+1]]`, ascending.
#[derive(Clone, Debug, Default)]
pub struct BlockRows {
    /// Row starts (length = nodes + 1).
    pub offsets: Vec<usize>,
    /// Column node indices.
    pub cols: Vec<u32>,
    /// 2 × 2 blocks `[[K_xx, K_xy], [K_yx, K_yy]]`.
    pub blocks: Vec<[[f64; 2]; 2]>,
}

impl BlockRows {
    /// Number of block rows (nodes).
    pub fn rows(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }
    /// Number of stored scalar entries.
    pub fn nnz(&self) -> usize {
        4 * self.blocks.len()
    }
    /// `(K v)` for DOF row `(node, axis)`.
    pub fn row_dot(&self, node: usize, axis: Axis, v: &[f64]) -> f64 {
        let a = axis as usize;
        (self.offsets[node]..self.offsets[node + 1])
            .map(|k| {
                let j = self.cols[k] as usize;
                self.blocks[k][a][0] * v[2 * j] + self.blocks[k][a][1] * v[2 * j + 1]
            })
            .sum()
    }
    /// `K v` for all rows.
    pub fn mul(&self, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; 2 * self.rows()];
        out.par_chunks_mut(2).enumerate().for_each(|(i, o)| {
            o[0] = self.row_dot(i, Axis::X, v);
            o[1] = self.row_dot(i, Axis::Y, v);
        });
        out
    }
    /// Dense copy (small problems and tests only).
    pub fn to_dense(&self) -> Vec<Vec<f64>> {
        let n = 2 * self.rows();
        let mut d = vec![vec![0.0; n]; n];
        for i in 0..self.rows() {
            for k in self.offsets[i]..self.offsets[i + 1] {
                let j = self.cols[k] as usize;
                for a in 0..2 {
                    for b in 0..2 {
                        d[2 * i + a][2 * j + b] += self.blocks[k][a][b];
                    }
                }
            }
        }
        d
    }
}

/// A Dirichlet condition on one DOF, imposed by collocation `u^h_axis(x_node) = value`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Constraint {
    /// Node.
    pub node: u32,
    /// Component.
    pub axis: Axis,
    /// Prescribed displacement `ū`.
    pub value: f64,
}

/// The scalar sparse system `K û = f` in compressed-column form, with Dirichlet rows replaced.
#[derive(Clone, Debug)]
pub struct SystemMatrix {
    /// Size (= 2 N).
    pub n: usize,
    /// Column starts.
    pub col_ptr: Vec<usize>,
    /// Row indices.
    pub row_idx: Vec<usize>,
    /// Values.
    pub values: Vec<f64>,
}

impl SystemMatrix {
    /// The `n × n` compressed-column matrix of the entries `(row, column, value)`, duplicates
    /// summed in the order given (the entries sorted by column, then row).
    pub fn from_entries(n: usize, mut entries: Vec<(usize, usize, f64)>) -> Self {
        entries.sort_by_key(|&(r, c, _)| (c, r));
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::<f64>::new());
        let mut last = None;
        for (r, c, v) in entries {
            if last == Some((r, c)) {
                if let Some(x) = values.last_mut() {
                    *x += v;
                }
                continue;
            }
            while col_ptr.len() <= c {
                col_ptr.push(row_idx.len());
            }
            row_idx.push(r);
            values.push(v);
            last = Some((r, c));
        }
        while col_ptr.len() <= n {
            col_ptr.push(row_idx.len());
        }
        Self { n, col_ptr, row_idx, values }
    }
}

/// The assembled global system.
#[derive(Clone, Debug)]
pub struct GlobalSystem {
    /// `K_int = −Q D S` from interior faces only, before any row is replaced.
    pub interior_stiffness: BlockRows,
    /// Applied load `f` (tractions and body force), interleaved, length 2 N.
    pub load: Vec<f64>,
    /// Dirichlet constraints, sorted by DOF.
    pub constraints: Vec<Constraint>,
    /// Factor applied to collocation rows so they scale like equilibrium rows (`D_00`).
    pub collocation_scale: f64,
    /// The solved matrix: `K_int` with constrained rows replaced by scaled collocation rows.
    pub matrix: SystemMatrix,
    /// The solved right-hand side: `f`, with constrained rows replaced by scaled `ū`.
    pub rhs: Vec<f64>,
    /// The rigid-body translation the displacement conditions leave free and the contact is
    /// to hold, pinned at one node (its row among `constraints`; docs/method.md §4.7).
    pub pinned: Option<PinnedMode>,
    /// Whether the body is axisymmetric (`x = r`): then only the axial (`y`) components of the
    /// loads and reactions balance globally; the radial ones balance the hoop stresses
    /// (docs/method.md §9.3).
    pub axisymmetric: bool,
}

/// A rigid-body translation that no displacement condition restrains, left to a contact with
/// a rigid obstacle (docs/method.md §4.7): `K` is made regular by an artificial condition
/// `u^h_axis(x_node) = 0`, whose reaction the contact must bring to zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PinnedMode {
    /// The free translation's axis.
    pub axis: Axis,
    /// The pinned node.
    pub node: u32,
}

impl PinnedMode {
    /// `"translation in x"` or `"translation in y"`.
    pub fn name(&self) -> &'static str {
        match self.axis {
            Axis::X => "translation in x",
            Axis::Y => "translation in y",
        }
    }
}

impl GlobalSystem {
    /// Whether DOF `d` is constrained.
    pub fn is_constrained(&self, d: usize) -> bool {
        self.constraints.binary_search_by_key(&d, |c| dof(c.node as usize, c.axis)).is_ok()
    }
}

/// What assembly needs from the earlier stages.
pub struct AssemblyInput<'a> {
    /// The body: domain, nodes, material, conditions and loads.
    pub body: Body<'a>,
    /// Cells.
    pub cells: &'a [Cell],
    /// Interior faces.
    pub interior_faces: &'a [Face],
    /// Boundary faces.
    pub boundary_faces: &'a [Face],
    /// Quadrature of the interior faces.
    pub face_quadrature: &'a FaceQuadrature,
    /// Shape functions at the interior-face quadrature points (with gradients when `β > 0`).
    pub face_shapes: &'a ShapeSet,
    /// Shape functions with gradients at the nodes (`S` and collocation).
    pub node_shapes: &'a ShapeSet,
    /// Stabilisation blend `β ∈ [0, 1]` (docs/method.md §3.9; 0 = the paper's mixed method).
    pub beta: f64,
    /// The hoop terms of an axisymmetric body (docs/method.md §9; `None` in plane stress and
    /// strain). Its hoop must be the body's [`Body::hoop`].
    pub axisymmetric: Option<Axisymmetric<'a>>,
}

/// What either discretisation ([`assemble`], [`crate::fem::system::assemble`]) needs of the
/// body: its domain and nodes, the constitutive matrix, the edge conditions and the loads.
#[derive(Clone, Copy, Debug)]
pub struct Body<'a> {
    /// Domain (edge normals and parameters).
    pub domain: &'a Domain,
    /// Nodes (with boundary tags).
    pub nodes: &'a Nodes,
    /// Constitutive matrix.
    pub d: &'a Constitutive,
    /// Edge conditions (one per domain edge).
    pub boundary: &'a [EdgeCondition],
    /// Body force.
    pub body_force: Option<&'a BodyForce>,
    /// Gauss points per segment (FE: per element side, and per direction for the body force)
    /// for applied tractions.
    pub load_quadrature_points: usize,
    /// Whether a contact (with a rigid obstacle, or any pair of several bodies) may hold one
    /// rigid-body translation that the displacement conditions leave free (MFVM: pinned,
    /// [`PinnedMode`], instead of refused).
    pub contact_may_hold: bool,
    /// Whether inertia holds the rigid-body motions (elastodynamics, docs/method.md §10): the
    /// displacement conditions need not restrain them, and there may be none.
    pub inertia: bool,
    /// The hoop terms of an axisymmetric body (`x = r`, `y = z`; docs/method.md §9): loads are
    /// weighted by `r` (per radian) and only the translation along the axis is a rigid-body
    /// motion. `None` in plane stress and strain.
    pub hoop: Option<Hoop>,
}

impl<'a> Body<'a> {
    /// The body of `problem` with its nodes `nodes` and constitutive matrix `d`.
    pub fn new(problem: &'a Problem, nodes: &'a Nodes, d: &'a Constitutive) -> Self {
        Self {
            domain: &problem.domain,
            nodes,
            d,
            boundary: &problem.boundary,
            body_force: problem.body_force.as_ref(),
            load_quadrature_points: problem.discretisation.load_quadrature_points,
            // One body against rigid obstacles; or the first of several bodies, touched by a
            // contact pair (docs/method.md §4.7; the others: `pipeline::multibody`). An
            // axisymmetric body's axial translation too: the searches balance its per-radian
            // loads times 2π against the rings' total forces (`load_path::load_along`). Not in
            // dynamics, where inertia holds the free motions.
            contact_may_hold: problem.dynamics.is_none()
                && (problem
                    .contact()
                    .is_some_and(|c| !matches!(c.target, ContactTarget::Body { .. }))
                    || problem.multibody().is_some_and(|m| {
                        m.pairs.iter().any(|p| p.body == 0 || p.target_body == Some(0))
                    })),
            hoop: problem.material.hoop(),
            inertia: problem.dynamics.is_some(),
        }
    }
}

/// Assembles `K_int`, `f`, the constraints and the solved matrix.
///
/// # Panics
/// When `β` is outside `[0, 1]`, or `β > 0` and `face_shapes` has no gradients (caller bugs:
/// `β` is validated in [`crate::problem::Discretisation`]).
///
/// # Errors
/// [`AssemblyError`] when a Dirichlet edge's face belongs to a node off that edge, or when
/// nothing is constrained.
pub fn assemble(input: &AssemblyInput<'_>) -> Result<GlobalSystem, AssemblyError> {
    let beta = input.beta;
    if needs_face_gradients(beta) && !input.face_shapes.has_gradients() {
        return Err(AssemblyError::MissingFaceGradients { beta });
    }
    match (input.body.hoop.is_some(), input.axisymmetric.is_some()) {
        (true, false) => {
            return Err(AssemblyError::AxisymmetricMismatch {
                body: "axisymmetric",
                input: "lacks the hoop terms",
            });
        }
        (false, true) => {
            return Err(AssemblyError::AxisymmetricMismatch {
                body: "plane",
                input: "has axisymmetric hoop terms",
            });
        }
        _ => {}
    }
    let interior_stiffness = match &input.axisymmetric {
        Some(axi) => {
            if needs_face_gradients(beta) && !axi.cell_shapes.has_gradients() {
                return Err(AssemblyError::MissingFaceGradients { beta });
            }
            axisymmetric::interior_stiffness(input, axi)
        }
        None => interior_stiffness(input),
    };
    let load = applied_load(input)?;
    let (constraints, pinned) = constraints_and_pin(input);
    if input.body.inertia {
        // Inertia holds the rigid-body motions: nothing to check.
    } else if constraints.is_empty() {
        return Err(AssemblyError::NoDirichlet);
    } else if input.body.hoop.is_some() {
        check_axial_restraint(&constraints)?;
    } else {
        check_rigid_body_restraint(&constraints, input.body.nodes)?;
    }
    let collocation_scale = input.body.d[0][0];
    let (matrix, rhs) = system_matrix(
        &interior_stiffness,
        &load,
        &constraints,
        input.node_shapes,
        collocation_scale,
    );
    Ok(GlobalSystem {
        interior_stiffness,
        load,
        constraints,
        collocation_scale,
        matrix,
        rhs,
        pinned,
        axisymmetric: input.body.hoop.is_some(),
    })
}

/// The applied load `f` and the solved right-hand side of `input`'s conditions without
/// assembling the matrix: for load steps, whose conditions differ from the assembled ones in
/// their values only (the same constrained DOFs, so the same matrix; docs/method.md §8).
///
/// # Errors
/// As [`assemble`]'s load.
pub fn load_and_rhs(input: &AssemblyInput<'_>) -> Result<(Vec<f64>, Vec<f64>), AssemblyError> {
    let load = applied_load(input)?;
    let mut rhs = load.clone();
    let scale = input.body.d[0][0];
    for c in constraints_and_pin(input).0 {
        rhs[dof(c.node as usize, c.axis)] = scale * c.value;
    }
    Ok((load, rhs))
}

/// One block row: column nodes and their 2 × 2 blocks.
type BlockRow = (Vec<u32>, Vec<[[f64; 2]; 2]>);

/// `K_int = −Q D [(1 − β) Φ S + β B_q]`, row by row in parallel (deterministic: each row is
/// summed in face order). With `β = 0` this is the paper's `−Q D S` (eqs. 12–15).
#[allow(non_snake_case)]
fn interior_stiffness(input: &AssemblyInput<'_>) -> BlockRows {
    let beta = input.beta;
    let mixed = 1.0 - beta;
    let n = input.body.nodes.len();
    let FaceAdjacency { count, adj } = face_adjacency(input.interior_faces, n);
    let d = input.body.d;
    let q = input.face_quadrature;
    let S = input.node_shapes;
    // Workspaces are dense over the nodes; `with_min_len` bounds how many get allocated.
    let rows: Vec<BlockRow> = (0..n)
        .into_par_iter()
        .with_min_len(1024)
        .map_init(
            || (vec![[[0.0; 3]; 2]; n], vec![false; n], vec![[[0.0; 2]; 2]; n], vec![false; n]),
            |(qd, qd_used, krow, k_used), i| {
                // Row i of (1 − β) Q·blockdiag(D)·Φ: a 2x3 block per strain node J; and the
                // direct part −β Σ_q w_q T(n_q) B_K(x_q) straight into the row (docs/method.md §3.9).
                let mut js: Vec<u32> = Vec::new();
                let mut ks: Vec<u32> = Vec::new();
                for &(f, sign) in &adj[count[i]..count[i + 1]] {
                    let face = &input.interior_faces[f as usize];
                    let t = traction_operator(face.normal, d);
                    for p in q.offsets[f as usize]..q.offsets[f as usize + 1] {
                        let wq = sign * q.weights[p];
                        let support = input.face_shapes.support(p);
                        if mixed > 0.0 {
                            for (&j, &phi) in support.iter().zip(input.face_shapes.phi(p)) {
                                let ju = j as usize;
                                if !qd_used[ju] {
                                    qd_used[ju] = true;
                                    js.push(j);
                                }
                                let c = mixed * wq * phi;
                                for a in 0..2 {
                                    for b in 0..3 {
                                        qd[ju][a][b] += c * t[a][b];
                                    }
                                }
                            }
                        }
                        if beta > 0.0 {
                            let (dx, dy) = input.face_shapes.grad(p);
                            let c = beta * wq;
                            for ((&k, &gx), &gy) in support.iter().zip(dx).zip(dy) {
                                let ku = k as usize;
                                if !k_used[ku] {
                                    k_used[ku] = true;
                                    ks.push(k);
                                }
                                for a in 0..2 {
                                    krow[ku][a][0] -= c * (t[a][0] * gx + t[a][2] * gy);
                                    krow[ku][a][1] -= c * (t[a][1] * gy + t[a][2] * gx);
                                }
                            }
                        }
                    }
                }
                js.sort_unstable();
                // Times S: ε̂_J = Σ_K B_K(x_J) û_K, B_K = [[φ,x, 0], [0, φ,y], [φ,y, φ,x]].
                for &j in &js {
                    let ju = j as usize;
                    let blk = qd[ju];
                    let (dx, dy) = S.grad(ju);
                    for ((&k, &gx), &gy) in S.support(ju).iter().zip(dx).zip(dy) {
                        let ku = k as usize;
                        if !k_used[ku] {
                            k_used[ku] = true;
                            ks.push(k);
                        }
                        for a in 0..2 {
                            // −(blk · B_K): columns x and y of the 2x2 block.
                            krow[ku][a][0] -= blk[a][0] * gx + blk[a][2] * gy;
                            krow[ku][a][1] -= blk[a][1] * gy + blk[a][2] * gx;
                        }
                    }
                    qd[ju] = [[0.0; 3]; 2];
                    qd_used[ju] = false;
                }
                ks.sort_unstable();
                let blocks: Vec<[[f64; 2]; 2]> = ks
                    .iter()
                    .map(|&k| {
                        let ku = k as usize;
                        let b = krow[ku];
                        krow[ku] = [[0.0; 2]; 2];
                        k_used[ku] = false;
                        b
                    })
                    .collect();
                (ks, blocks)
            },
        )
        .collect();
    block_rows(rows)
}

/// The interior faces of each node's cell with the sign of their normal (`+1` out of the
/// owner, `−1` for the cell across): node `i` holds `adj[count[i]..count[i + 1]]`.
struct FaceAdjacency {
    count: Vec<usize>,
    adj: Vec<(u32, f64)>,
}

impl FaceAdjacency {
    /// The faces of node `i`'s cell and their signs.
    fn of(&self, i: usize) -> &[(u32, f64)] {
        &self.adj[self.count[i]..self.count[i + 1]]
    }
}

/// [`FaceAdjacency`] of `faces` over `n` nodes.
fn face_adjacency(faces: &[Face], n: usize) -> FaceAdjacency {
    // Node -> (face, sign): the face normal points out of the owner.
    let mut count = vec![0usize; n + 1];
    for f in faces {
        count[f.owner as usize + 1] += 1;
        if let EdgeLabel::Neighbour(j) = f.across {
            count[j as usize + 1] += 1;
        }
    }
    for i in 1..=n {
        count[i] += count[i - 1];
    }
    let mut fill = count.clone();
    let mut adj = vec![(0u32, 0.0f64); count[n]];
    for (k, f) in faces.iter().enumerate() {
        adj[fill[f.owner as usize]] = (k as u32, 1.0);
        fill[f.owner as usize] += 1;
        if let EdgeLabel::Neighbour(j) = f.across {
            adj[fill[j as usize]] = (k as u32, -1.0);
            fill[j as usize] += 1;
        }
    }
    FaceAdjacency { count, adj }
}

/// The rows, one per node in order, as [`BlockRows`].
fn block_rows(rows: Vec<BlockRow>) -> BlockRows {
    let n = rows.len();
    let mut out = BlockRows { offsets: Vec::with_capacity(n + 1), ..Default::default() };
    out.offsets.push(0);
    let total: usize = rows.iter().map(|r| r.0.len()).sum();
    out.cols.reserve(total);
    out.blocks.reserve(total);
    for (cols, blocks) in rows {
        out.cols.extend_from_slice(&cols);
        out.blocks.extend_from_slice(&blocks);
        out.offsets.push(out.cols.len());
    }
    out
}

/// `f_I = ∫_{Γt ∩ ∂Ω_I} t̄ dΓ + ∫_{Ω_I} b dΩ` (paper eq. 12, right-hand side).
fn applied_load(input: &AssemblyInput<'_>) -> Result<Vec<f64>, AssemblyError> {
    let n = input.body.nodes.len();
    let mut f = vec![0.0; 2 * n];
    for face in input.boundary_faces {
        let EdgeLabel::Boundary(k) = face.across else { continue };
        let k = k as usize;
        let owner = face.owner as usize;
        let condition = &input.body.boundary[k];
        for axis in Axis::BOTH {
            if condition.displacement(axis as usize).is_some()
                && !input.body.nodes.edges[owner].contains(k)
            {
                return Err(CellError::DirichletOwnership {
                    node: owner,
                    edge: input.body.domain.edge_names()[k].clone(),
                }
                .into());
            }
        }
        // Straight edges: the edge's normal. Arcs: the normal of the chord this face lies on,
        // so that a pressure on the polygonal approximation is in equilibrium by itself.
        let normal = input.body.domain.straight_normal(k).unwrap_or(face.normal);
        let traction = |p: Point| -> [f64; 2] {
            let t = input.body.domain.edge_parameter(k, p);
            match condition {
                EdgeCondition::Pressure(pr) => {
                    let v = pr.value(p, t);
                    [-v * normal[0], -v * normal[1]]
                }
                EdgeCondition::Components(c) => {
                    let comp = |c: &ComponentCondition| match c {
                        ComponentCondition::Traction(field) => field.value(p, t),
                        ComponentCondition::Displacement(_) => 0.0,
                    };
                    [comp(&c[0]), comp(&c[1])]
                }
            }
        };
        let zero = match condition {
            EdgeCondition::Pressure(p) => p.is_zero(),
            EdgeCondition::Components(c) => c.iter().all(|c| match c {
                ComponentCondition::Traction(f) => f.is_zero(),
                ComponentCondition::Displacement(_) => true,
            }),
        };
        if zero {
            continue;
        }
        for (p, w) in segment_rule(face.a, face.b, input.body.load_quadrature_points) {
            let t = traction(p);
            let w = w * radial_weight(&input.body, p);
            f[2 * owner] += w * t[0];
            f[2 * owner + 1] += w * t[1];
        }
    }
    if let Some(b) = input.body.body_force {
        for (i, cell) in input.cells.iter().enumerate() {
            let v = integrate_over_cell(cell, |p| {
                let (b, r) = (b.at(p), radial_weight(&input.body, p));
                [r * b[0], r * b[1]]
            });
            f[2 * i] += v[0];
            f[2 * i + 1] += v[1];
        }
    }
    Ok(f)
}

/// The weight of a load integral at `p`: `r = x` in axisymmetry (per radian; docs/method.md
/// §9.3), 1 otherwise.
fn radial_weight(body: &Body<'_>, p: Point) -> f64 {
    if body.hoop.is_some() { p[0] } else { 1.0 }
}

/// `∫_cell g dΩ` by a fan of triangles from the centroid with the 3-point (degree-2) rule.
pub fn integrate_over_cell(cell: &Cell, g: impl Fn(Point) -> [f64; 2]) -> [f64; 2] {
    let m = cell.vertices.len();
    let c = cell.vertices.iter().fold([0.0; 2], |s, v| [s[0] + v[0], s[1] + v[1]]);
    let c = [c[0] / m as f64, c[1] / m as f64];
    let mut out = [0.0; 2];
    for k in 0..m {
        let (a, b) = cell.edge(k);
        let area = 0.5 * ((a[0] - c[0]) * (b[1] - c[1]) - (b[0] - c[0]) * (a[1] - c[1]));
        for (l1, l2, l3) in [(4.0, 1.0, 1.0), (1.0, 4.0, 1.0), (1.0, 1.0, 4.0)] {
            let p = [
                (l1 * c[0] + l2 * a[0] + l3 * b[0]) / 6.0,
                (l1 * c[1] + l2 * a[1] + l3 * b[1]) / 6.0,
            ];
            let v = g(p);
            out[0] += area / 3.0 * v[0];
            out[1] += area / 3.0 * v[1];
        }
    }
    out
}

/// One constraint per (node, axis) on an edge that prescribes that component's displacement
/// (the lowest-numbered such edge wins at corners).
fn constraints(input: &AssemblyInput<'_>) -> Vec<Constraint> {
    let mut out = Vec::new();
    for (i, edges) in input.body.nodes.edges.iter().enumerate() {
        for axis in Axis::BOTH {
            let hit = edges.iter().find_map(|k| {
                input.body.boundary[k].displacement(axis as usize).map(|f: &Field| (k, f))
            });
            if let Some((k, field)) = hit {
                let p = input.body.nodes.points[i];
                let t = input.body.domain.edge_parameter(k, p);
                out.push(Constraint { node: i as u32, axis, value: field.value(p, t) });
            }
        }
    }
    out
}

/// The constraints of `input`'s conditions and, when the contact may hold a rigid-body
/// translation they leave free ([`Body::contact_may_hold`]), the pin of that translation
/// among them (docs/method.md §4.7).
fn constraints_and_pin(input: &AssemblyInput<'_>) -> (Vec<Constraint>, Option<PinnedMode>) {
    with_pin(constraints(input), &input.body)
}

/// `constraints` with, when the contact may hold a rigid-body translation they leave free
/// ([`Body::contact_may_hold`]), the pin of that translation inserted in DOF order, and the
/// pin (docs/method.md §4.7). The MFVM's and the FE's assembly share it.
pub(crate) fn with_pin(
    constraints: Vec<Constraint>,
    body: &Body<'_>,
) -> (Vec<Constraint>, Option<PinnedMode>) {
    let mut out = constraints;
    let pinned = match (body.contact_may_hold, body.hoop.is_some()) {
        (false, _) => None,
        (true, false) => free_translation(&out, body.nodes),
        // In axisymmetry the axial translation is the only rigid motion (docs/method.md §9.3).
        (true, true) => free_axial_translation(&out, body.nodes),
    };
    if let Some(p) = pinned {
        let pin = Constraint { node: p.node, axis: p.axis, value: 0.0 };
        let at =
            out.partition_point(|c| dof(c.node as usize, c.axis) < dof(p.node as usize, p.axis));
        out.insert(at, pin);
    }
    (out, pinned)
}

/// An axisymmetric body's axial translation when `constraints` leave it free (no `y`
/// condition), pinned as [`free_translation`] pins; `None` otherwise.
fn free_axial_translation(constraints: &[Constraint], nodes: &Nodes) -> Option<PinnedMode> {
    if constraints.iter().any(|c| c.axis == Axis::Y) {
        return None;
    }
    let node = central_node(nodes)?;
    Some(PinnedMode { axis: Axis::Y, node })
}

/// The node nearest the centre of `nodes`' bounding box among those on no edge (any node when
/// every node is on one).
fn central_node(nodes: &Nodes) -> Option<u32> {
    // The centre of the nodes' bounding box (not their centroid, which graded node sets
    // pull towards their refined regions: the pinned point stays put under refinement).
    let (lo, hi) =
        nodes.points.iter().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), p| {
            ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
        });
    let centroid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let distance = |i: usize| {
        let p = nodes.points[i];
        (p[0] - centroid[0]).hypot(p[1] - centroid[1])
    };
    let nearest = |interior: bool| {
        (0..nodes.len())
            .filter(|&i| !interior || nodes.edges[i].is_empty())
            .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
    };
    nearest(true).or_else(|| nearest(false)).map(|i| i as u32)
}

/// The one rigid-body translation `constraints` leave free, pinned at the node nearest the
/// centre of the nodes' bounding box among those on no edge (any node when every node is on one), provided
/// that the other translation and the rotation are restrained once it is pinned; `None`
/// otherwise (no translation free, or more than one mode free: refused by
/// [`check_rigid_body_restraint`]).
fn free_translation(constraints: &[Constraint], nodes: &Nodes) -> Option<PinnedMode> {
    let has = |a: Axis| constraints.iter().any(|c| c.axis == a);
    let axis = match (has(Axis::X), has(Axis::Y)) {
        (false, true) => Axis::X,
        (true, false) => Axis::Y,
        _ => return None,
    };
    let node = central_node(nodes)?;
    let mut with = constraints.to_vec();
    with.push(Constraint { node, axis, value: 0.0 });
    check_rigid_body_restraint(&with, nodes).ok()?;
    Some(PinnedMode { axis, node })
}

/// Checks that the collocation rows restrain the three rigid-body modes. MLS reproduces linear
/// fields, so a constraint row applied to the modes `(1, 0)`, `(0, 1)`, `(−y, x)` gives
/// `(1, 0, −y_I)` for an x-constraint and `(0, 1, x_I)` for a y-constraint; the modes are
/// restrained exactly when these rows have rank 3.
fn check_rigid_body_restraint(
    constraints: &[Constraint],
    nodes: &Nodes,
) -> Result<(), AssemblyError> {
    let has = |a: Axis| constraints.iter().any(|c| c.axis == a);
    if !has(Axis::X) {
        return Err(AssemblyError::RigidBodyMotion { mode: "translation in x" });
    }
    if !has(Axis::Y) {
        return Err(AssemblyError::RigidBodyMotion { mode: "translation in y" });
    }
    // Rotation is free iff every row's third entry is an affine function a·(first) + b·(second)
    // of the others, i.e. all x-constraints share one y and all y-constraints share one x
    // while the pair (a, b) fits both: −y_I = a for x-rows and x_I = b for y-rows. It is
    // restrained as soon as two x-constraints differ in y or two y-constraints differ in x.
    let (lo, hi) =
        nodes.points.iter().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), p| {
            ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
        });
    let tol = 1e-9 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let spread = |a: Axis, coord: usize| {
        let values = constraints
            .iter()
            .filter(|c| c.axis == a)
            .map(|c| nodes.points[c.node as usize][coord]);
        let (mn, mx) =
            values.fold((f64::INFINITY, f64::NEG_INFINITY), |(mn, mx), v| (mn.min(v), mx.max(v)));
        mx - mn
    };
    if spread(Axis::X, 1) <= tol && spread(Axis::Y, 0) <= tol {
        return Err(AssemblyError::RigidBodyMotion { mode: "rotation" });
    }
    Ok(())
}

/// In axisymmetry the only rigid-body motion is the translation along the axis (`y`): a
/// uniform `u_r` or a rotation in the `r–z` plane strains the hoop (docs/method.md §9.3).
fn check_axial_restraint(constraints: &[Constraint]) -> Result<(), AssemblyError> {
    if constraints.iter().any(|c| c.axis == Axis::Y) {
        Ok(())
    } else {
        Err(AssemblyError::RigidBodyMotion { mode: "translation along the axis (y)" })
    }
}

/// The solved system: `K_int` with constrained rows replaced by `c·Σ_J φ_J(x_I) û_J,i = c·ū_i`.
fn system_matrix(
    k_int: &BlockRows,
    load: &[f64],
    constraints: &[Constraint],
    node_shapes: &ShapeSet,
    scale: f64,
) -> (SystemMatrix, Vec<f64>) {
    let n = 2 * k_int.rows();
    let mut rhs = load.to_vec();
    let mut constrained = vec![false; n];
    for c in constraints {
        let r = dof(c.node as usize, c.axis);
        constrained[r] = true;
        rhs[r] = scale * c.value;
    }
    // Count entries per column.
    let mut col_count = vec![0usize; n + 1];
    for i in 0..k_int.rows() {
        for axis in Axis::BOTH {
            let r = dof(i, axis);
            if constrained[r] {
                for &j in node_shapes.support(i) {
                    col_count[dof(j as usize, axis) + 1] += 1;
                }
            } else {
                for &j in &k_int.cols[k_int.offsets[i]..k_int.offsets[i + 1]] {
                    col_count[2 * j as usize + 1] += 1;
                    col_count[2 * j as usize + 2] += 1;
                }
            }
        }
    }
    for c in 1..=n {
        col_count[c] += col_count[c - 1];
    }
    let col_ptr = col_count.clone();
    let mut fill = col_count;
    let mut row_idx = vec![0usize; col_ptr[n]];
    let mut values = vec![0.0; col_ptr[n]];
    // Rows are visited in increasing order, so each column's row indices come out sorted.
    for i in 0..k_int.rows() {
        for axis in Axis::BOTH {
            let r = dof(i, axis);
            if constrained[r] {
                for (&j, &phi) in node_shapes.support(i).iter().zip(node_shapes.phi(i)) {
                    let c = dof(j as usize, axis);
                    row_idx[fill[c]] = r;
                    values[fill[c]] = scale * phi;
                    fill[c] += 1;
                }
            } else {
                for k in k_int.offsets[i]..k_int.offsets[i + 1] {
                    let j = k_int.cols[k] as usize;
                    for b in 0..2 {
                        let c = 2 * j + b;
                        row_idx[fill[c]] = r;
                        values[fill[c]] = k_int.blocks[k][axis as usize][b];
                        fill[c] += 1;
                    }
                }
            }
        }
    }
    (SystemMatrix { n, col_ptr, row_idx, values }, rhs)
}

#[cfg(test)]
mod tests {
    use crate::problem::Problem;

    fn interior_stiffness(beta: f64) -> Vec<Vec<f64>> {
        let mut problem = Problem::from_toml(
            r#"
            [geometry]
            kind = "rectangle"
            x = [0.0, 2.0]
            y = [0.0, 1.0]
            [nodes]
            spacing = 0.25
            layout = "jittered"
            [material]
            young = 100.0
            poisson = 0.3
            plane = "stress"
            [[boundary]]
            edge = "left"
            displacement = { x = 0.0, y = 0.0 }
            "#,
        )
        .expect("valid problem");
        problem.discretisation.beta = beta;
        let model = crate::discretise(&problem, &mut crate::Silent).expect("discretise");
        model.system.interior_stiffness.to_dense()
    }

    /// `K_int(β) = (1 − β) K_int(0) + β K_int(1)` (docs/method.md §3.9: the face stress is a blend),
    /// and `β = 1` couples fewer nodes than the collocated-strain operator.
    #[test]
    fn interior_stiffness_is_linear_in_beta_and_sparser_at_one() {
        let (k0, k1, kb) =
            (interior_stiffness(0.0), interior_stiffness(1.0), interior_stiffness(0.3));
        let scale = k0.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut worst = 0.0f64;
        for ((r0, r1), rb) in k0.iter().zip(&k1).zip(&kb) {
            for ((a, b), c) in r0.iter().zip(r1).zip(rb) {
                worst = worst.max((0.7 * a + 0.3 * b - c).abs());
            }
        }
        assert!(worst < 1e-12 * scale, "blend off by {worst:.3e} (scale {scale:.3e})");
        let nnz = |k: &[Vec<f64>]| k.iter().flatten().filter(|v| **v != 0.0).count();
        // Observed 2652 vs 4836 on this small block (boundary rows have smaller stencils; the
        // beam at h = 0.125 has 41 vs 87 per row).
        assert!(10 * nnz(&k1) < 6 * nnz(&k0), "nnz β=1 {} vs β=0 {}", nnz(&k1), nnz(&k0));
    }
}
