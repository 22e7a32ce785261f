//! Clipping of polylines to a plot window, so that a curve leaving the window ends at its
//! border instead of being squashed onto it (plotters clamps every point into the plotting
//! area, which draws the outside part of a curve along the frame).

/// A point of a plot.
type P = (f64, f64);

/// The parameter interval `[t0, t1]` of the segment `a → b` inside the window
/// `[x0, x1] × [y0, y1]` (Liang–Barsky), or none when the segment misses it or has a
/// non-finite end.
fn clip_segment(a: P, b: P, [x0, x1, y0, y1]: [f64; 4]) -> Option<(f64, f64)> {
    if ![a.0, a.1, b.0, b.1].iter().all(|v| v.is_finite()) {
        return None;
    }
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [(-dx, a.0 - x0), (dx, x1 - a.0), (-dy, a.1 - y0), (dy, y1 - a.1)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// The parts of the polyline `points` inside the window `[x0, x1] × [y0, y1]`, each a run of
/// at least two points; a run ends where the polyline leaves the window.
pub(crate) fn clip_polyline(points: &[P], window: [f64; 4]) -> Vec<Vec<P>> {
    let mut runs = Vec::new();
    let mut run: Vec<P> = Vec::new();
    let mut flush = |run: &mut Vec<P>| {
        if run.len() >= 2 {
            runs.push(std::mem::take(run));
        }
        run.clear();
    };
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let Some((t0, t1)) = clip_segment(a, b, window) else {
            flush(&mut run);
            continue;
        };
        let at = |t: f64| (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
        if t0 > 0.0 || run.is_empty() {
            flush(&mut run);
            run.push(at(t0));
        }
        run.push(at(t1));
        if t1 < 1.0 {
            flush(&mut run);
        }
    }
    flush(&mut run);
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    const UNIT: [f64; 4] = [0.0, 1.0, 0.0, 1.0];

    #[test]
    fn a_polyline_inside_is_one_run() {
        let p = [(0.1, 0.1), (0.5, 0.5), (0.9, 0.2)];
        assert_eq!(clip_polyline(&p, UNIT), vec![p.to_vec()]);
    }

    #[test]
    fn a_polyline_leaving_and_coming_back_is_two_runs_ending_on_the_border() {
        let p = [(0.0, 0.5), (0.5, 2.5), (1.0, 0.5)];
        let runs = clip_polyline(&p, UNIT);
        assert_eq!(runs.len(), 2);
        assert!((runs[0][1].1 - 1.0).abs() < 1e-12 && (runs[1][0].1 - 1.0).abs() < 1e-12);
        assert!((runs[0][1].0 - 0.125).abs() < 1e-12);
    }

    #[test]
    fn outside_degenerate_and_non_finite_input_gives_nothing() {
        assert!(clip_polyline(&[(2.0, 2.0), (3.0, 3.0)], UNIT).is_empty());
        assert!(clip_polyline(&[(0.5, 0.5)], UNIT).is_empty());
        assert!(clip_polyline(&[], UNIT).is_empty());
        assert!(clip_polyline(&[(0.5, 0.5), (f64::NAN, 0.5)], UNIT).is_empty());
    }
}
