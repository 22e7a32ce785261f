//! Assembly of the Q2 system: `K = Σ_e K_e` (symmetric), consistent loads, and strong
//! Dirichlet conditions by symmetric elimination.

use super::FemError;
use super::element;
use super::mesh::Mesh;
use crate::assembly::{self, BlockRows, Body, Constraint, GlobalSystem, SystemMatrix};
use crate::material::{Constitutive, Hoop};
use crate::nodes::{Axis, Nodes, dof};
use crate::problem::{ComponentCondition, EdgeCondition};
use crate::weak_form::gauss_legendre;
use rayon::prelude::*;

/// What the FE assembly needs.
pub struct FemInput<'a> {
    /// The body: the rectangle, the mesh's nodes, material, conditions and loads.
    pub body: Body<'a>,
    /// The mesh.
    pub mesh: &'a Mesh,
}

/// Assembles the global system in the form the rest of the pipeline expects:
/// `interior_stiffness` holds the unconstrained `K` (for reactions `K u − f − E P`), `matrix`
/// the solved one. Each prescribed DOF `c` is eliminated symmetrically: its row and column
/// are zeroed, the diagonal set to `D_00`, `rhs_c = D_00 ū_c`, and `K_{rc} ū_c` moved to the
/// right-hand side of every other row `r`, so `matrix` stays symmetric. A body whose one free
/// translation the contact holds (docs/method.md §4.7) is pinned at one node as the MFVM's is
/// (`assembly::with_pin`): the pin's row is replaced, its column kept, so that setting the
/// pin's right-hand side to `D_00 t` translates the whole body by `t` (the matrix is then
/// unsymmetric in that column; the LU does not mind).
///
/// # Errors
/// [`FemError::NoDirichlet`] / [`FemError::RigidBodyMotion`] when the prescribed
/// displacements leave a rigid-body motion free.
pub fn assemble(input: &FemInput<'_>) -> Result<GlobalSystem, FemError> {
    let stiffness =
        stiffness(input.mesh, input.body.nodes.len(), input.body.d, input.body.hoop.as_ref());
    let load = load(input);
    let (constraints, pinned) = constraints_and_pin(input);
    if !input.body.inertia {
        check_restraint(&constraints, input.body.nodes, input.body.hoop.is_some())?;
    }
    let scale = input.body.d[0][0];
    let (rhs, constrained) = eliminated_rhs(&stiffness, &load, &constraints, scale);
    let pin = pinned.map(|p| dof(p.node as usize, p.axis));
    let matrix = eliminated_matrix(&stiffness, &constrained, pin, scale);
    Ok(GlobalSystem {
        interior_stiffness: stiffness,
        load,
        constraints,
        collocation_scale: scale,
        matrix,
        rhs,
        pinned,
        axisymmetric: input.body.hoop.is_some(),
    })
}

/// The load `f` and the right-hand side of `input`'s conditions for the unconstrained
/// stiffness `stiffness` (the `interior_stiffness` of an assembled system with the same
/// constrained DOFs), without assembling anything else: for load steps, whose conditions
/// differ from the assembled ones in their values only (docs/method.md §8).
pub fn load_and_rhs(input: &FemInput<'_>, stiffness: &BlockRows) -> (Vec<f64>, Vec<f64>) {
    let load = load(input);
    let (constraints, _) = constraints_and_pin(input);
    let (rhs, _) = eliminated_rhs(stiffness, &load, &constraints, input.body.d[0][0]);
    (load, rhs)
}

/// The constraints of `input`'s conditions and, when the contact may hold a free rigid-body
/// translation (in axisymmetry the axial one only), its pin among them (docs/method.md §4.7).
fn constraints_and_pin(input: &FemInput<'_>) -> (Vec<Constraint>, Option<assembly::PinnedMode>) {
    assembly::with_pin(constraints(input), &input.body)
}

/// The right-hand side after symmetric elimination of `constraints` (`scale · ū_c` on a
/// prescribed row, `f_r − Σ_c K_rc ū_c` elsewhere) and the constrained-DOF flags.
fn eliminated_rhs(
    stiffness: &BlockRows,
    load: &[f64],
    constraints: &[Constraint],
    scale: f64,
) -> (Vec<f64>, Vec<bool>) {
    let n = load.len();
    let mut prescribed = vec![0.0; n];
    let mut constrained = vec![false; n];
    for c in constraints {
        let r = dof(c.node as usize, c.axis);
        prescribed[r] = c.value;
        constrained[r] = true;
    }
    let lift = stiffness.mul(&prescribed);
    let rhs: Vec<f64> = (0..n)
        .map(|r| if constrained[r] { scale * prescribed[r] } else { load[r] - lift[r] })
        .collect();
    (rhs, constrained)
}

/// One block row: column nodes and their 2 × 2 blocks.
type BlockRow = (Vec<u32>, Vec<[[f64; 2]; 2]>);

/// `K = Σ_e K_e` in block-row form, row-parallel. On the grid every element is a
/// `h_x × h_y` rectangle, so one `K_e` serves all (not in axisymmetry, where `K_e` depends on
/// the radius: [`super::axisymmetric::stiffness`]); a general mesh computes each element's.
fn stiffness(mesh: &Mesh, node_count: usize, d: &Constitutive, hoop: Option<&Hoop>) -> BlockRows {
    let shared = mesh.grid.is_some() && hoop.is_none();
    let ke: Vec<_> = match (shared, hoop) {
        (true, _) => vec![mesh.stiffness(0, d)],
        (false, Some(hoop)) => (0..mesh.element_count())
            .into_par_iter()
            .map(|k| super::axisymmetric::stiffness(mesh, k, d, hoop))
            .collect(),
        (false, None) => {
            (0..mesh.element_count()).into_par_iter().map(|k| mesh.stiffness(k, d)).collect()
        }
    };
    let ke = |k: usize| &ke[if shared { 0 } else { k }];
    // Elements containing each node, with the node's local index.
    let mut touching: Vec<Vec<(u32, u8)>> = vec![Vec::new(); node_count];
    for k in 0..mesh.element_count() {
        for (a, &i) in mesh.cell(k).nodes.iter().enumerate() {
            touching[i as usize].push((k as u32, a as u8));
        }
    }
    let rows: Vec<BlockRow> = touching
        .par_iter()
        .map(|list| {
            let mut cols: Vec<u32> =
                list.iter().flat_map(|&(k, _)| mesh.cell(k as usize).nodes).copied().collect();
            cols.sort_unstable();
            cols.dedup();
            let mut blocks = vec![[[0.0; 2]; 2]; cols.len()];
            for &(k, a) in list {
                let (a, ke) = (a as usize, ke(k as usize));
                for (b, &j) in mesh.cell(k as usize).nodes.iter().enumerate() {
                    let pos = cols.binary_search(&j).unwrap_or_else(|_| {
                        unreachable!("column {j} was collected from the same elements")
                    });
                    for (r, row) in blocks[pos].iter_mut().enumerate() {
                        for (c, v) in row.iter_mut().enumerate() {
                            *v += ke[2 * a + r][2 * b + c];
                        }
                    }
                }
            }
            (cols, blocks)
        })
        .collect();
    let mut out = BlockRows { offsets: vec![0], cols: Vec::new(), blocks: Vec::new() };
    for (cols, blocks) in rows {
        out.cols.extend(cols);
        out.blocks.extend(blocks);
        out.offsets.push(out.cols.len());
    }
    out
}

/// The compressed-column matrix of `K` with constrained rows and columns replaced by
/// `scale` on the diagonal, except the `pin`'s column, which keeps its entries (its row is
/// replaced). `K` is symmetric, so column `(j, b)` is read from block row `j`.
fn eliminated_matrix(
    k: &BlockRows,
    constrained: &[bool],
    pin: Option<usize>,
    scale: f64,
) -> SystemMatrix {
    let n = 2 * k.rows();
    let mut col_ptr = vec![0usize];
    let mut row_idx = Vec::with_capacity(k.nnz());
    let mut values = Vec::with_capacity(k.nnz());
    for j in 0..k.rows() {
        for b in Axis::BOTH {
            let c = dof(j, b);
            if constrained[c] && pin != Some(c) {
                row_idx.push(c);
                values.push(scale);
            } else {
                for p in k.offsets[j]..k.offsets[j + 1] {
                    let i = k.cols[p] as usize;
                    for a in Axis::BOTH {
                        let r = dof(i, a);
                        if r == c {
                            // The pin's column keeps its entries (the pinned value moves the
                            // body rigidly when the pipeline sets it), its row is replaced.
                            row_idx.push(r);
                            values.push(if pin == Some(c) {
                                scale
                            } else {
                                k.blocks[p][b as usize][a as usize]
                            });
                        } else if !constrained[r] {
                            row_idx.push(r);
                            // K[r][c] = K[c][r] = block (j, i)[b][a].
                            values.push(k.blocks[p][b as usize][a as usize]);
                        }
                    }
                }
            }
            col_ptr.push(row_idx.len());
        }
    }
    SystemMatrix { n, col_ptr, row_idx, values }
}

/// Consistent nodal loads: `∫ N_a t̄ ds` over the element sides on traction and pressure
/// edges, `∫ N_a b dA` over the elements.
fn load(input: &FemInput<'_>) -> Vec<f64> {
    let (domain, nodes, mesh) = (input.body.domain, input.body.nodes, input.mesh);
    let mut f = vec![0.0; 2 * nodes.len()];
    let (xs, ws) = gauss_legendre(input.body.load_quadrature_points);
    for (k, condition) in input.body.boundary.iter().enumerate() {
        let straight = domain.straight_normal(k);
        for (ids, length) in mesh.boundary_segments(domain, nodes, k) {
            let (p, q) = (nodes.points[ids[0] as usize], nodes.points[ids[2] as usize]);
            let side = ids.map(|i| nodes.points[i as usize]);
            for (&s, &w) in xs.iter().zip(ws) {
                // The grid's straight sides by their chord (as always); a general mesh's by
                // the isoparametric side map, whose outward normal is the tangent turned
                // clockwise (the sides run along the edge, the body on their left).
                let (x, ds, normal) = match (mesh.grid.is_some(), straight) {
                    (true, Some(normal)) => (
                        [
                            0.5 * (p[0] + q[0]) + 0.5 * s * (q[0] - p[0]),
                            0.5 * (p[1] + q[1]) + 0.5 * s * (q[1] - p[1]),
                        ],
                        0.5 * length,
                        normal,
                    ),
                    _ => {
                        let (x, t, _) = super::mesh::side_map(side, s);
                        let norm = t[0].hypot(t[1]);
                        (x, norm, [t[1] / norm, -t[0] / norm])
                    }
                };
                let t_edge = domain.edge_parameter(k, x);
                let t = match condition {
                    EdgeCondition::Pressure(field) => {
                        let v = field.value(x, t_edge);
                        [-v * normal[0], -v * normal[1]]
                    }
                    EdgeCondition::Components(c) => std::array::from_fn(|axis| match &c[axis] {
                        ComponentCondition::Traction(field) => field.value(x, t_edge),
                        ComponentCondition::Displacement(_) => 0.0,
                    }),
                };
                let n = element::lagrange(s);
                // Per radian in axisymmetry: ∫ N t̄ r ds (docs/method.md §9.5).
                let ds = ds * radial_weight(input, x);
                for (a, &i) in ids.iter().enumerate() {
                    for axis in Axis::BOTH {
                        f[dof(i as usize, axis)] += ds * w * n[a] * t[axis as usize];
                    }
                }
            }
        }
    }
    if let Some(b) = input.body.body_force {
        // Quadrilaterals: the tensor Gauss rule of `load_quadrature_points`; triangles: their
        // element rule.
        let square: Vec<([f64; 2], f64)> = xs
            .iter()
            .zip(ws)
            .flat_map(|(&eta, &wy)| xs.iter().zip(ws).map(move |(&xi, &wx)| ([xi, eta], wx * wy)))
            .collect();
        for k in 0..mesh.element_count() {
            let cell = mesh.cell(k);
            let rule = match cell.shape {
                element::Shape::Quad9 => square.clone(),
                element::Shape::Tri6 => cell.shape.quadrature(),
            };
            for ([xi, eta], w) in rule {
                let x = mesh.point(k, xi, eta);
                let force = b.at(x);
                let det = mesh.area_factor(k, xi, eta) * radial_weight(input, x);
                let [n, _, _] = cell.shape.functions(xi, eta);
                for (a, &i) in cell.nodes.iter().enumerate() {
                    for axis in Axis::BOTH {
                        f[dof(i as usize, axis)] += w * det * n[a] * force[axis as usize];
                    }
                }
            }
        }
    }
    f
}

/// The weight of a load integral at `x`: the radius `x[0]` in axisymmetry, 1 otherwise.
fn radial_weight(input: &FemInput<'_>, x: [f64; 2]) -> f64 {
    if input.body.hoop.is_some() { x[0] } else { 1.0 }
}

/// One constraint per (node, axis) on an edge that prescribes that component (the
/// lowest-numbered such edge wins at corners), sorted by DOF; the nodal value `ū(x_I)`.
fn constraints(input: &FemInput<'_>) -> Vec<Constraint> {
    let mut out = Vec::new();
    for (i, edges) in input.body.nodes.edges.iter().enumerate() {
        for axis in Axis::BOTH {
            let hit = edges
                .iter()
                .find_map(|k| input.body.boundary[k].displacement(axis as usize).map(|f| (k, f)));
            if let Some((k, field)) = hit {
                let p = input.body.nodes.points[i];
                let t = input.body.domain.edge_parameter(k, p);
                out.push(Constraint { node: i as u32, axis, value: field.value(p, t) });
            }
        }
    }
    out
}

/// The prescribed DOFs must fix both translations and the rotation: the rows
/// `(1, 0, −y_I)` (x-constraints) and `(0, 1, x_I)` (y-constraints) must have rank 3. In
/// axisymmetry only the axial translation is a rigid motion (docs/method.md §9.3).
fn check_restraint(
    constraints: &[Constraint],
    nodes: &Nodes,
    axisymmetric: bool,
) -> Result<(), FemError> {
    if constraints.is_empty() {
        return Err(FemError::NoDirichlet);
    }
    if axisymmetric {
        return match constraints.iter().any(|c| c.axis == Axis::Y) {
            true => Ok(()),
            false => Err(FemError::RigidBodyMotion { mode: "translation along the axis (y)" }),
        };
    }
    for (axis, mode) in [(Axis::X, "translation in x"), (Axis::Y, "translation in y")] {
        if !constraints.iter().any(|c| c.axis == axis) {
            return Err(FemError::RigidBodyMotion { mode });
        }
    }
    let spread = |axis: Axis, coord: usize| {
        let (lo, hi) = constraints
            .iter()
            .filter(|c| c.axis == axis)
            .map(|c| nodes.points[c.node as usize][coord])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
        hi - lo
    };
    let size = nodes.spacing.first().copied().unwrap_or(1.0);
    if spread(Axis::X, 1) <= 1e-9 * size && spread(Axis::Y, 0) <= 1e-9 * size {
        return Err(FemError::RigidBodyMotion { mode: "rotation" });
    }
    Ok(())
}
