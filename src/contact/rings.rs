//! Contact candidates of an axisymmetric body are rings (docs/method.md §9.6). The section's
//! candidate `c` at radius `r_c` stands for the ring of revolution of its segment, and its
//! unknown is the ring's total normal force `F_c` over the whole circumference.
//!
//! The body's balance is written per radian (§9.3): the contact traction `p ν` on the
//! candidate's segment enters its cell's (MFVM) or its nodes' (FE) equations as
//! `∫_seg p ν r ds`, a force per radian. A pressure `p` uniform over the segment makes
//! `F_c = 2π ∫_seg p r ds = p A_c` with the ring's area `A_c = 2π ∫_seg r ds`, so the
//! per-radian force is `F_c / 2π`: the force operator `E` holds `ν_c / 2π` (owner weight
//! `1/2π`), the gap operator `G` is unchanged (displacements are per point), and the pressure
//! reported is `F_c / A_c` (the candidate's `segment_length` holds `A_c`). The gaps and the
//! complementarity `gᵀF = 0` are those of the per-radian problem times `2π` in the forces only:
//! `M = G K⁻¹ E` is the per-radian compliance divided by `2π`, its checks are relative.

use super::Candidates;
use crate::fem::{Mesh, side_map};
use crate::geometry::Domain;
use crate::nodes::Nodes;
use crate::weak_form::{EdgeLabel, Face};

/// Radians in a full revolution: the ring's force is `2π` times the force per radian.
pub const REVOLUTION: f64 = std::f64::consts::TAU;

/// Turns `candidates` of an axisymmetric body into rings: owner weights divided by `2π` (the
/// unknown becomes the ring's total force) and `segment_length` replaced by the ring areas
/// `area` (one per candidate, `2π ∫_seg r ds`).
pub fn into_rings(candidates: &mut Candidates, area: Vec<f64>) {
    for owners in &mut candidates.operator.owners {
        for (_, w) in owners.iter_mut() {
            *w /= REVOLUTION;
        }
    }
    candidates.segment_length = area;
}

/// The ring areas `2π ∫ r ds` of the MFVM candidates `nodes` on `edge`: over the boundary
/// faces (straight chords) each candidate's cell owns on the edge, `∫ r ds = |b − a| (r_a +
/// r_b)/2` exactly.
pub fn mfvm_areas(faces: &[Face], edge: usize, nodes: &[u32]) -> Vec<f64> {
    nodes
        .iter()
        .map(|&i| {
            let moment: f64 = faces
                .iter()
                .filter(|f| f.owner == i && f.across == EdgeLabel::Boundary(edge as u32))
                .map(|f| f.length() * 0.5 * (f.a[0] + f.b[0]))
                .sum();
            REVOLUTION * moment
        })
        .collect()
}

/// The ring areas `2π ∫ N_a r ds` of the FE candidates `ids` on `edge`: the consistent
/// (r-weighted) tributary of each node over the quadratic sides on the edge, 5-point Gauss
/// (exact on a straight side with a centred middle node, where the integrand is cubic). A
/// node on the axis gets 0: its weight `∫ N_a r ds` vanishes on a straight side (round-off
/// otherwise), so a pressure carries no force to it ([`pressures`]).
pub fn fem_areas(
    mesh: &Mesh,
    domain: &Domain,
    nodes: &Nodes,
    edge: usize,
    ids: &[u32],
) -> Vec<f64> {
    let mut moment = vec![0.0; nodes.len()];
    let (xs, ws) = crate::weak_form::gauss_legendre(5);
    for (side, _) in mesh.boundary_segments(domain, nodes, edge) {
        let x = side.map(|i| nodes.points[i as usize]);
        for (&s, &w) in xs.iter().zip(ws) {
            let (p, t, n) = side_map(x, s);
            let ds = t[0].hypot(t[1]);
            for (&i, na) in side.iter().zip(n) {
                moment[i as usize] += w * ds * na * p[0];
            }
        }
    }
    let (lo, hi) = domain.bounding_box();
    let axis = AXIS_TOLERANCE * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    ids.iter()
        .map(|&i| match nodes.points[i as usize][0] <= axis {
            true => 0.0,
            false => REVOLUTION * moment[i as usize],
        })
        .collect()
}

/// Relative tolerance (of the section's size) within which a node lies on the axis.
const AXIS_TOLERANCE: f64 = 1e-12;

/// The pressures `F_c / A_c` of the forces `forces` on the areas `area` (lengths in plane
/// stress and strain). A candidate without area (an FE node on the axis of an axisymmetric
/// body, [`fem_areas`]) reports its neighbour's along the edge: its force is not a measure of
/// the pressure there, and `∂p/∂r = 0` on the axis by symmetry, so the neighbour's value is
/// second-order accurate.
pub fn pressures(forces: &[f64], area: &[f64]) -> Vec<f64> {
    let own = |c: usize| forces[c] / area[c];
    (0..forces.len())
        .map(|c| match area[c] > 0.0 {
            true => own(c),
            false => [c + 1, c.wrapping_sub(1)]
                .into_iter()
                .find(|&k| k < forces.len() && area[k] > 0.0)
                .map_or(0.0, own),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mls::ShapeSet;

    #[test]
    fn the_areas_of_a_disk_tiled_by_chords_sum_to_its_area() {
        // Faces of the segment [0, 1] on the line z = 0, owned by nodes 0 (at r = 0), 1
        // (r = 0.5) and 2 (r = 1): the ring areas are π r² differences.
        let face = |owner, a: f64, b: f64| Face {
            owner,
            across: EdgeLabel::Boundary(0),
            a: [a, 0.0],
            b: [b, 0.0],
            normal: [0.0, -1.0],
        };
        let faces =
            [face(0, 0.0, 0.25), face(1, 0.25, 0.5), face(1, 0.5, 0.75), face(2, 0.75, 1.0)];
        let area = mfvm_areas(&faces, 0, &[0, 1, 2]);
        let pi = std::f64::consts::PI;
        let exact = [pi * 0.0625, pi * (0.5625 - 0.0625), pi * (1.0 - 0.5625)];
        for (a, e) in area.iter().zip(exact) {
            assert!((a - e).abs() < 1e-15, "{a} against {e}");
        }
    }

    #[test]
    fn a_candidate_without_area_takes_its_neighbours_pressure() {
        let p = pressures(&[1e-9, 2.0, 3.0], &[0.0, 4.0, 2.0]);
        assert_eq!(p, vec![0.5, 0.5, 1.5]);
        assert_eq!(pressures(&[2.0, 1e-9], &[4.0, 0.0]), vec![0.5, 0.5]);
    }

    #[test]
    fn rings_divide_the_owner_weights_by_two_pi() {
        let mut c = Candidates {
            nodes: vec![3],
            points: vec![[1.0, 0.0]],
            arc_length: vec![0.0],
            segment_length: vec![0.1],
            segment_ends: vec![([0.95, 0.0], [1.05, 0.0])],
            initial_gap: vec![0.0],
            normals: vec![[0.0, 1.0]],
            operator: super::super::BodyOperator {
                shapes: ShapeSet::nodal(&[3]),
                owners: vec![vec![(3, 1.0)]],
                directions: vec![[0.0, 1.0]],
            },
        };
        into_rings(&mut c, vec![0.2 * std::f64::consts::PI]);
        let mut rhs = vec![0.0; 8];
        c.operator.add_forces(&[REVOLUTION], &mut rhs);
        assert!((rhs[7] - 1.0).abs() < 1e-15, "{}", rhs[7]);
        assert!((c.segment_length[0] - 0.2 * std::f64::consts::PI).abs() < 1e-15);
    }
}
