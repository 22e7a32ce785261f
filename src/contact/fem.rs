//! Contact operators of the Q2 discretisation. The shape functions interpolate, so the gap
//! row of a candidate node picks its nodal displacement (`G_c = ν_cᵀ e_c`) and the contact
//! force acts on the same DOFs (`E = Gᵀ`): the condensed compliance `M = G K⁻¹ Gᵀ` is
//! symmetric positive definite.

use super::{BodyOperator, Candidates, ContactError};
use crate::assembly::GlobalSystem;
use crate::fem::Mesh;
use crate::fem::element;
use crate::geometry::{Domain, Point};
use crate::mls::ShapeSet;
use crate::nodes::{Axis, Nodes, dof};

/// The candidates of domain edge `edge`: its nodes whose DOFs along the contact normal (into
/// the body) are free, sorted along the edge; `target(x)` gives the initial gap and that
/// normal at a point `x`.
///
/// `segment_length` is the node's consistent tributary length: of each element side of length
/// `l` on the edge, `l/6` goes to each end node and `4l/6` to the middle node (the nodal forces
/// of a uniform pressure are `p` times these), so `P_c / segment_length_c` is a pressure
/// comparable with the MFVM's. `segment_ends` are the matching sub-intervals (`l/6` on each
/// side of an end node, `l/3` on each side of a middle node); they tile the edge. An
/// axisymmetric body's sub-intervals have the nodes' consistent ring moments `∫ N_a r ds`
/// instead (`ring_cuts`; its areas are `super::rings::fem_areas`).
///
/// # Errors
/// [`ContactError::NoCandidates`] when no node of the edge is free along the normal.
pub fn candidates(
    mesh: &Mesh,
    domain: &Domain,
    nodes: &Nodes,
    system: &GlobalSystem,
    edge: usize,
    target: &dyn Fn(Point) -> (f64, Point),
) -> Result<Candidates, ContactError> {
    let curve = domain.curve(edge);
    let len = curve.length();
    let mut tributary = vec![0.0; nodes.len()];
    let mut extent = vec![[f64::INFINITY, f64::NEG_INFINITY]; nodes.len()];
    for (ids, l) in mesh.boundary_segments(domain, nodes, edge) {
        let t: Vec<f64> =
            ids.iter().map(|&i| domain.edge_parameter(edge, nodes.points[i as usize])).collect();
        let dt = (t[2] - t[0]) / 6.0;
        // The grid's straight sides: l/6, 4l/6, l/6; a general mesh's (possibly curved) side:
        // ∫ N_a ds by 5-point Gauss (the same on a straight side with a centred middle node).
        let w = match mesh.grid {
            Some(_) => [l / 6.0, 4.0 * l / 6.0, l / 6.0],
            None => side_weights(ids.map(|i| nodes.points[i as usize])),
        };
        let (ta, tb) = match system.axisymmetric {
            false => (t[0] + dt, t[2] - dt),
            true => {
                let f = ring_cuts(ids.map(|i| nodes.points[i as usize]));
                (t[0] + f[0] * (t[2] - t[0]), t[0] + f[1] * (t[2] - t[0]))
            }
        };
        let pieces = [(w[0], t[0], ta), (w[1], ta, tb), (w[2], tb, t[2])];
        for (&i, (w, lo, hi)) in ids.iter().zip(pieces) {
            let i = i as usize;
            tributary[i] += w;
            extent[i] = [extent[i][0].min(lo), extent[i][1].max(hi)];
        }
    }
    let mut list: Vec<(f64, usize)> = (0..nodes.len())
        .filter(|&i| tributary[i] > 0.0)
        .filter(|&i| {
            let normal = target(nodes.points[i]).1;
            Axis::BOTH
                .iter()
                .all(|&ax| normal[ax as usize] == 0.0 || !system.is_constrained(dof(i, ax)))
        })
        .map(|i| (domain.edge_parameter(edge, nodes.points[i]), i))
        .collect();
    if list.is_empty() {
        return Err(ContactError::NoCandidates { edge: domain.edge_names()[edge].clone() });
    }
    list.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
    let ids: Vec<u32> = list.iter().map(|&(_, i)| i as u32).collect();
    let points: Vec<Point> = list.iter().map(|&(_, i)| nodes.points[i]).collect();
    let at = |t: f64| curve.point_at(t);
    let (initial_gap, normals): (Vec<f64>, Vec<Point>) = points.iter().map(|&p| target(p)).unzip();
    Ok(Candidates {
        segment_ends: list.iter().map(|&(_, i)| (at(extent[i][0]), at(extent[i][1]))).collect(),
        arc_length: list.iter().map(|&(t, _)| t * len).collect(),
        segment_length: list.iter().map(|&(_, i)| tributary[i]).collect(),
        initial_gap,
        operator: BodyOperator {
            shapes: ShapeSet::nodal(&ids),
            owners: ids.iter().map(|&i| vec![(i, 1.0)]).collect(),
            directions: normals.clone(),
        },
        normals,
        nodes: ids,
        points,
    })
}

/// The target body of a two-body contact discretised by Q2 elements: each candidate `x_c` of
/// body 1 is paired with the closest point `y_c` of body 2's straight edge `edge` (outward
/// normal `ν`, `g0_c = ν·(x_c − y_c)`). The gap row reads `u_2^h(y_c)` through the quadratic
/// shape functions of the element side holding `y_c`. The reaction `−ν P_c` is spread as a
/// uniform pressure over the candidate's tributary segment projected onto the edge:
/// `E_2[a, c] = ∫_{seg_c} N_a ds / |seg_c|` (exact 3-point Gauss on each overlapping side).
/// Since `P_c / |seg_c|` is the pressure and the segments tile the edge, a uniform pressure
/// on body 1 gives body 2 its consistent load, so non-matching meshes pass the contact patch
/// test (`E_2 ≠ G_2ᵀ`: `M` is slightly non-symmetric there, as for the MFVM). Where no side
/// overlaps, the reaction acts at `y_c` through the point values. An axisymmetric target
/// (docs/method.md §9.6) takes the ring's total force per radian:
/// `E_2[a, c] = ∫_{seg_c} N_a r ds / (2π ∫_{seg_c} r ds)`.
///
/// Returns the operator (`d = −ν`), the initial gaps and the paired points.
///
/// # Errors
/// [`ContactError::NoCandidates`] when the edge has no element side,
/// [`ContactError::TargetConstrained`] when a receiving node's normal DOF is prescribed.
pub fn target_operator(
    mesh: &Mesh,
    domain: &Domain,
    nodes: &Nodes,
    system: &GlobalSystem,
    edge: usize,
    candidates: &Candidates,
) -> Result<(BodyOperator, Vec<f64>, Vec<Point>), ContactError> {
    let name = || domain.edge_names()[edge].clone();
    let pairing = super::TargetEdge::new(domain, edge);
    let sides: Vec<([u32; 3], f64, f64)> = mesh
        .boundary_segments(domain, nodes, edge)
        .into_iter()
        .map(|(ids, _)| {
            let t0 = domain.edge_parameter(edge, nodes.points[ids[0] as usize]);
            let t1 = domain.edge_parameter(edge, nodes.points[ids[2] as usize]);
            (ids, t0, t1)
        })
        .collect();
    if sides.is_empty() {
        return Err(ContactError::NoCandidates { edge: name() });
    }
    let (xs, ws) = crate::weak_form::gauss_legendre(3);
    // An axisymmetric target: `N_a r` over the overlap (cubic: 3-point Gauss is exact), the
    // row summing to `1/2π` (the ring's total force per radian, `super::rings`).
    let radius = |t: f64| match system.axisymmetric {
        true => pairing.radius(t),
        false => 1.0,
    };
    let per_radian = if system.axisymmetric { super::rings::REVOLUTION } else { 1.0 };
    let mut rows = Vec::with_capacity(candidates.len());
    let mut owners = Vec::with_capacity(candidates.len());
    let mut gaps = Vec::with_capacity(candidates.len());
    let mut paired = Vec::with_capacity(candidates.len());
    let mut directions = Vec::with_capacity(candidates.len());
    for (c, &x) in candidates.points.iter().enumerate() {
        let t = domain.edge_parameter(edge, x).clamp(0.0, 1.0);
        // A curved target pairs along the candidate's normal (the bisector, `body_pair`).
        let (y, nu, gap) = pairing.pair_along(x, candidates.normals[c]);
        let (ids, t0, t1) = sides
            .iter()
            .min_by(|p, q| side_distance(t, p.1, p.2).total_cmp(&side_distance(t, q.1, q.2)))
            .copied()
            .ok_or_else(|| ContactError::NoCandidates { edge: name() })?;
        let s = (2.0 * (t - t0) / (t1 - t0) - 1.0).clamp(-1.0, 1.0);
        let point_row = sorted_row(ids.iter().copied().zip(element::lagrange(s)));
        let (p, q) = candidates.segment_ends[c];
        let (u, v) = (domain.edge_parameter(edge, p), domain.edge_parameter(edge, q));
        let (s0, s1) = (u.min(v), u.max(v));
        let mut spread: Vec<(u32, f64)> = Vec::new();
        let mut total = 0.0;
        for &(ids, t0, t1) in &sides {
            let (lo, hi) = (s0.max(t0), s1.min(t1));
            if hi <= lo {
                continue;
            }
            // A straight edge: the exact trapezoid (`r` linear); a curved one: the same rule
            // as the spread, so that the row sums to `1/2π` exactly (`r` along a mesh's
            // polyline has kinks that the Gauss rules integrate differently).
            let mut quadrature = 0.0;
            for (&r, &w) in xs.iter().zip(ws) {
                let tq = 0.5 * (lo + hi) + 0.5 * r * (hi - lo);
                let n = element::lagrange(2.0 * (tq - t0) / (t1 - t0) - 1.0);
                let weight = 0.5 * w * (hi - lo) * radius(tq);
                quadrature += weight;
                spread.extend(ids.iter().zip(n).map(|(&i, n)| (i, weight * n)));
            }
            total += match pairing.is_straight() {
                true => (hi - lo) * 0.5 * (radius(lo) + radius(hi)),
                false => quadrature,
            };
        }
        let owner_row = if total > 0.0 {
            sorted_row(spread.into_iter().map(|(i, w)| (i, w / (total * per_radian))))
        } else {
            sorted_row(point_row.iter().map(|&(i, w)| (i, w / per_radian)))
        };
        let blocked = |nu: Point| {
            owner_row.iter().map(|&(i, _)| i as usize).find(|&i| {
                Axis::BOTH
                    .iter()
                    .any(|&ax| nu[ax as usize] != 0.0 && system.is_constrained(dof(i, ax)))
            })
        };
        // A curved axisymmetric target's force reaching an axis node: along the axis
        // (`super::TargetEdge::axial`).
        let (nu, gap) = match system.axisymmetric && blocked(nu).is_some() {
            true => pairing.axial(x, y, nu),
            false => (nu, gap),
        };
        if let Some(node) = blocked(nu) {
            return Err(ContactError::TargetConstrained { edge: name(), node });
        }
        gaps.push(gap);
        paired.push(y);
        rows.push(point_row);
        owners.push(owner_row);
        directions.push([-nu[0], -nu[1]]);
    }
    let operator = BodyOperator { shapes: ShapeSet::from_rows(&rows), directions, owners };
    Ok((operator, gaps, paired))
}

/// Where an axisymmetric side's sub-intervals end (fractions of the side's parameter): the
/// cuts `s_A`, `s_B` with `∫_{−1}^{s_A} r ds = ∫ N_0 r ds` and `∫_{s_B}^{1} r ds = ∫ N_2 r ds`,
/// so that each node's sub-interval has its consistent ring moment and a uniform pressure
/// spread over the sub-intervals is the consistent load (docs/method.md §9.6; an elastic
/// target reads them, [`target_operator`]). `∫ r ds` of a piece by 5-point Gauss, the cuts by
/// bisection. A node on the axis gets an empty sub-interval (its moment is 0).
fn ring_cuts(x: [Point; 3]) -> [f64; 2] {
    let (xs, ws) = crate::weak_form::gauss_legendre(5);
    // ∫ r ds from −1 to s, and ∫ N_a r ds over the side.
    let moment = |s: f64| -> f64 {
        let half = 0.5 * (s + 1.0);
        xs.iter()
            .zip(ws)
            .map(|(&q, &w)| {
                let (p, t, _) = crate::fem::side_map(x, -1.0 + half * (q + 1.0));
                w * half * p[0] * t[0].hypot(t[1])
            })
            .sum()
    };
    let mut nodal = [0.0; 3];
    for (&q, &w) in xs.iter().zip(ws) {
        let (p, t, n) = crate::fem::side_map(x, q);
        for a in 0..3 {
            nodal[a] += w * p[0] * t[0].hypot(t[1]) * n[a];
        }
    }
    let total = moment(1.0);
    let cut = |target: f64| {
        let (mut lo, mut hi) = (-1.0_f64, 1.0_f64);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if moment(mid) < target { lo = mid } else { hi = mid }
        }
        0.25 * (lo + hi) + 0.5
    };
    [cut(nodal[0]), cut(total - nodal[2])]
}

/// `∫ N_a ds` over the quadratic side through `x` (end, middle, end), 5-point Gauss.
fn side_weights(x: [Point; 3]) -> [f64; 3] {
    let (xs, ws) = crate::weak_form::gauss_legendre(5);
    let mut out = [0.0; 3];
    for (&s, &w) in xs.iter().zip(ws) {
        let (_, t, n) = crate::fem::side_map(x, s);
        let ds = t[0].hypot(t[1]);
        for a in 0..3 {
            out[a] += w * ds * n[a];
        }
    }
    out
}

/// `(node, weight)` pairs merged by node, ascending, zero weights dropped.
fn sorted_row(pairs: impl Iterator<Item = (u32, f64)>) -> Vec<(u32, f64)> {
    let mut row: Vec<(u32, f64)> = pairs.collect();
    row.sort_by_key(|&(i, _)| i);
    let mut merged: Vec<(u32, f64)> = Vec::with_capacity(row.len());
    for (i, w) in row {
        match merged.last_mut() {
            Some(last) if last.0 == i => last.1 += w,
            _ => merged.push((i, w)),
        }
    }
    merged.retain(|&(_, w)| w != 0.0);
    merged
}

/// Distance of edge parameter `t` from the interval between `t0` and `t1`.
fn side_distance(t: f64, t0: f64, t1: f64) -> f64 {
    let (lo, hi) = (t0.min(t1), t0.max(t1));
    (lo - t).max(t - hi).max(0.0)
}
