//! The colour range of a filled-cell plot, robust to a single peak: a stress concentration
//! (a clamped corner, the edge of a punch) covers a few small cells, and a range up to its
//! peak would leave the rest of the body one colour. The range ends at the value below which
//! [`QUANTILE`] of the drawn area lies; larger values take the top colour, and the colour
//! bar says so.

/// The share of the drawn area whose values the colour range spans.
pub const QUANTILE: f64 = 0.99;

/// A colour range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColourRange {
    /// Bottom of the colour bar (the smallest value).
    pub lo: f64,
    /// Top of the colour bar.
    pub hi: f64,
    /// The largest value; above `hi` when the range is clipped.
    pub max: f64,
    /// Whether values above `hi` exist (drawn in the top colour).
    pub clipped: bool,
}

/// The colour range of `values` weighted by `weights` (cell areas; non-finite values and
/// negative or non-finite weights are left out, all-zero weights count equally): from the
/// smallest value to the [`QUANTILE`] by weight, or to the largest value when that quantile
/// equals the smallest value (most of the area at one value). A constant field (spread below `1e-9` of its
/// magnitude) gets ±10 % around its value, as the plots' axes do.
pub fn robust_range(values: &[f64], weights: &[f64]) -> ColourRange {
    let mut pairs: Vec<(f64, f64)> = values
        .iter()
        .zip(weights)
        .filter(|(v, _)| v.is_finite())
        .map(|(&v, &w)| (v, if w.is_finite() && w > 0.0 { w } else { 0.0 }))
        .collect();
    if pairs.is_empty() {
        return ColourRange { lo: 0.0, hi: 1.0, max: 1.0, clipped: false };
    }
    if pairs.iter().all(|p| p.1 == 0.0) {
        pairs.iter_mut().for_each(|p| p.1 = 1.0);
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (lo, max) = (pairs[0].0, pairs[pairs.len() - 1].0);
    let total: f64 = pairs.iter().map(|p| p.1).sum();
    let mut sum = 0.0;
    let quantile = pairs
        .iter()
        .find(|p| {
            sum += p.1;
            sum >= QUANTILE * total
        })
        .map_or(max, |p| p.0);
    let magnitude = lo.abs().max(max.abs());
    if max - lo <= 1e-9 * magnitude || magnitude == 0.0 {
        let half = if magnitude > 0.0 { 0.1 * magnitude } else { 1.0 };
        let centre = 0.5 * (lo + max);
        return ColourRange { lo: centre - half, hi: centre + half, max, clipped: false };
    }
    let clipped = quantile < max && quantile - lo > 1e-9 * magnitude;
    ColourRange { lo, hi: if clipped { quantile } else { max }, max, clipped }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_single_peak_on_a_small_area_is_clipped() {
        let mut values: Vec<f64> = (0..1000).map(|k| k as f64 / 1000.0).collect();
        values.push(100.0);
        let mut weights = vec![1.0; 1000];
        weights.push(0.5);
        let r = robust_range(&values, &weights);
        assert!(r.clipped && r.max == 100.0 && r.lo == 0.0);
        assert!((r.hi - 0.99).abs() < 0.01, "{r:?}");
    }

    #[test]
    fn an_even_field_is_not_clipped() {
        let values: Vec<f64> = (0..=10).map(f64::from).collect();
        let r = robust_range(&values, &[1.0; 11]);
        assert_eq!(r, ColourRange { lo: 0.0, hi: 10.0, max: 10.0, clipped: false });
    }

    #[test]
    fn constant_empty_and_non_finite_fields_give_a_usable_range() {
        let r = robust_range(&[2.0, 2.0], &[0.0, 0.0]);
        assert!(r.lo < 2.0 && r.hi > 2.0 && !r.clipped);
        let r = robust_range(&[], &[]);
        assert!(r.lo < r.hi);
        let r = robust_range(&[f64::NAN, 0.0], &[1.0, 1.0]);
        assert!(r.lo < r.hi && r.lo.is_finite());
    }
}
