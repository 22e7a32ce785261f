//! What the contact plots show: the x-range they zoom to, and whether they mark an onset.
//!
//! Zoom: a contact zone that covers a small part of its edge (a cylinder or a punch pressed
//! into a block) would be a spike a few pixels wide on a plot of the whole edge. When the zone
//! (first to last closed candidate) grown by its margin covers less than [`ZOOM_BELOW`] of
//! the edge, the plot shows the zone and its margin, with the whole edge in a panel under it;
//! otherwise (the beam on its foundation, two blocks in contact over their whole width) the
//! whole edge. The margin is half the zone's width, and at least [`MARGIN_SPACINGS`]
//! candidate spacings, so that the open candidates next to the zone and the gap opening
//! beyond it are seen.
//!
//! Onset: the contact onset `l_c` (`contact::onset`) extrapolates the gap of the last open
//! candidates to zero, which describes a body lifting off an obstacle parallel to it (the
//! paper's beam: a uniform initial gap along the edge). Where the initial gap varies along
//! the edge (a curved indenter, a punch), the zone's end is set by the obstacle's shape and is
//! no onset: the plots mark none.

use crate::solution::ContactSolution;

/// The share of the edge below which a contact plot zooms to the zone.
pub const ZOOM_BELOW: f64 = 0.5;

/// The least margin around the zone, in candidate spacings.
pub const MARGIN_SPACINGS: f64 = 4.0;

/// The x-range (distance along the edge) a contact plot zooms to, or none for the whole
/// edge: the closed zone grown by its margin, within the edge.
pub fn contact_window(arc: &[f64], closed: &[bool]) -> Option<(f64, f64)> {
    let first = closed.iter().position(|&c| c)?;
    let last = closed.iter().rposition(|&c| c)?;
    let (lo, hi) = (arc.first()?.min(*arc.last()?), arc.first()?.max(*arc.last()?));
    let spacing = |k: usize| {
        let before = if k > 0 { (arc[k] - arc[k - 1]).abs() } else { 0.0 };
        let after = arc.get(k + 1).map_or(0.0, |a| (a - arc[k]).abs());
        before.max(after)
    };
    let (a, b) = (arc[first].min(arc[last]), arc[first].max(arc[last]));
    let margin = (0.5 * (b - a)).max(MARGIN_SPACINGS * spacing(first).max(spacing(last)));
    let window = ((a - margin).max(lo), (b + margin).min(hi));
    let shown = window.1 - window.0;
    (shown.is_finite() && shown > 0.0 && shown < ZOOM_BELOW * (hi - lo)).then_some(window)
}

/// The onset to mark on the contact plots: `l_c` when there is one and the initial gap is
/// uniform along the edge (to `1e-9` of the edge's length).
pub fn marked_onset(c: &ContactSolution) -> Option<f64> {
    let arc = &c.candidates.arc_length;
    let length = arc.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
    let g = &c.candidates.initial_gap;
    let lo = g.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = g.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    c.onset.from_gap.filter(|_| hi - lo <= 1e-9 * length.max(f64::MIN_POSITIVE))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge(n: usize) -> Vec<f64> {
        (0..n).map(|k| k as f64 * 0.1).collect()
    }

    #[test]
    fn a_small_zone_is_zoomed_with_its_margin() {
        let arc = edge(101);
        let closed: Vec<bool> = (0..101).map(|k| (90..=95).contains(&k)).collect();
        let (a, b) = contact_window(&arc, &closed).unwrap();
        assert!((a - 8.6).abs() < 1e-9 && (b - 9.9).abs() < 1e-9, "{a} {b}");
    }

    #[test]
    fn a_zone_at_the_end_of_the_edge_is_cut_at_the_end() {
        let arc = edge(101);
        let closed: Vec<bool> = (0..101).map(|k| k >= 95).collect();
        let (_, b) = contact_window(&arc, &closed).unwrap();
        assert!((b - 10.0).abs() < 1e-9);
    }

    #[test]
    fn wide_empty_and_single_zones() {
        let arc = edge(101);
        let wide: Vec<bool> = (0..101).map(|k| k >= 40).collect();
        assert_eq!(contact_window(&arc, &wide), None);
        assert_eq!(contact_window(&arc, &[false; 101]), None);
        assert_eq!(contact_window(&[], &[]), None);
        let one: Vec<bool> = (0..101).map(|k| k == 50).collect();
        let (a, b) = contact_window(&arc, &one).unwrap();
        assert!((a - 4.6).abs() < 1e-9 && (b - 5.4).abs() < 1e-9);
        assert_eq!(contact_window(&[0.0], &[true]), None);
    }
}
