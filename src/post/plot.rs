//! Plots (SVG and PNG) with plotters and an embedded font, so no system library is needed.

use super::OutputError;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::{Path, PathBuf};
use std::sync::Once;

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

fn ensure_font() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        // The font is compiled in; failure would be a broken build, not bad input.
        if register_font("sans-serif", FontStyle::Normal, FONT).is_err() {
            panic!("embedded DejaVuSans.ttf failed to parse");
        }
    });
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A polyline.
    Line,
    /// Dashed polyline (reference curves).
    Dashed,
    /// Markers.
    Points,
    /// Shaded vertical bands: the points come in pairs `(x_start, _), (x_end, _)`, each pair a
    /// band over the whole height (e.g. a stick zone); their `y` is ignored.
    Bands,
}

/// One data series.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label (none when empty).
    pub label: String,
    /// `(x, y)` data.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
    /// Palette index.
    pub colour: usize,
}

/// A 2-D line/marker chart.
#[derive(Clone, Debug)]
pub struct Chart {
    /// Title.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Data.
    pub series: Vec<Series>,
}

/// The axis range of `values`: padded by 5 % of their spread, or, when the spread is below
/// `1e-9` of their magnitude (a constant up to round-off), ±10 % of the value around it, so
/// that round-off is not drawn as data.
pub(crate) fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let magnitude = lo.abs().max(hi.abs());
    if hi - lo <= 1e-9 * magnitude {
        let centre = 0.5 * (lo + hi);
        let half = if magnitude > 0.0 { 0.1 * magnitude } else { 1.0 };
        return (centre - half, centre + half);
    }
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// Tick labels for an axis over `lo..hi`, with as many digits as the tick spacing needs (the
/// spacing is at least a tenth of the range): fixed notation for magnitudes in `[0.01, 1e4)`,
/// scientific otherwise; a value below `1e-6` of the range is printed as 0.
pub(crate) fn tick_label(lo: f64, hi: f64) -> impl Fn(&f64) -> String {
    let span = (hi - lo).abs();
    let magnitude = lo.abs().max(hi.abs());
    let step = if span > 0.0 { span / 10.0 } else { magnitude.max(1.0) };
    let step_exponent = step.log10().floor() as i32;
    let fixed = (1e-2..1e4).contains(&magnitude);
    move |&v| {
        let v = if v.abs() <= 1e-6 * span { 0.0 } else { v };
        if fixed {
            let decimals = (-step_exponent).max(0) as usize;
            format!("{v:.decimals$}")
        } else if v == 0.0 {
            "0".into()
        } else {
            let exponent = v.abs().log10().floor() as i32;
            let digits = (exponent - step_exponent).clamp(0, 6) as usize;
            format!("{v:.digits$e}")
        }
    }
}

fn draw_chart<DB: DrawingBackend>(
    area: DrawingArea<DB, plotters::coord::Shift>,
    chart: &Chart,
) -> Result<(), String> {
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    let (x0, x1) = range(chart.series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
    let curves = chart.series.iter().filter(|s| !matches!(s.style, Style::Bands));
    let (y0, y1) = range(curves.flat_map(|s| s.points.iter().map(|p| p.1)));
    let mut ctx = ChartBuilder::on(&area)
        .caption(&chart.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| e.to_string())?;
    ctx.configure_mesh()
        .x_desc(&chart.x_label)
        .y_desc(&chart.y_label)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .x_label_formatter(&tick_label(x0, x1))
        .y_label_formatter(&tick_label(y0, y1))
        .draw()
        .map_err(|e| e.to_string())?;
    // Bands first, under the curves.
    let mut ordered: Vec<&Series> = chart.series.iter().collect();
    ordered.sort_by_key(|s| !matches!(s.style, Style::Bands));
    for s in ordered {
        let colour = Palette99::pick(s.colour).to_rgba();
        let legend_colour = colour;
        match s.style {
            Style::Bands => {
                let fill = colour.mix(0.18).filled();
                ctx.draw_series(
                    s.points
                        .chunks_exact(2)
                        .map(|p| Rectangle::new([(p[0].0, y0), (p[1].0, y1)], fill)),
                )
                .map_err(|e| e.to_string())?
                .label(&s.label)
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], fill));
            }
            Style::Line => {
                let drawn = ctx
                    .draw_series(LineSeries::new(s.points.iter().copied(), colour.stroke_width(2)))
                    .map_err(|e| e.to_string())?;
                if !s.label.is_empty() {
                    drawn.label(&s.label).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], legend_colour.stroke_width(2))
                    });
                }
            }
            Style::Dashed => {
                let drawn = ctx
                    .draw_series(DashedLineSeries::new(
                        s.points.iter().copied(),
                        8,
                        5,
                        colour.stroke_width(2),
                    ))
                    .map_err(|e| e.to_string())?;
                if !s.label.is_empty() {
                    drawn.label(&s.label).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], legend_colour.stroke_width(2))
                    });
                }
            }
            Style::Points => {
                ctx.draw_series(
                    s.points.iter().map(|&(x, y)| Circle::new((x, y), 3, colour.filled())),
                )
                .map_err(|e| e.to_string())?
                .label(&s.label)
                .legend(move |(x, y)| Circle::new((x + 10, y), 3, legend_colour.filled()));
            }
        }
    }
    ctx.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    area.present().map_err(|e| e.to_string())
}

/// Writes `<stem>.svg` and `<stem>.png` (1000 × 600) and returns their paths.
///
/// # Errors
/// [`OutputError::Plot`] when plotters fails (e.g. the directory is not writable).
pub fn write_chart(stem: &Path, chart: &Chart) -> Result<[PathBuf; 2], OutputError> {
    ensure_font();
    let size = (1000, 600);
    let svg = stem.with_extension("svg");
    draw_chart(SVGBackend::new(&svg, size).into_drawing_area(), chart)
        .map_err(|reason| OutputError::Plot { path: svg.display().to_string(), reason })?;
    let png = stem.with_extension("png");
    draw_chart(BitMapBackend::new(&png, size).into_drawing_area(), chart)
        .map_err(|reason| OutputError::Plot { path: png.display().to_string(), reason })?;
    Ok([svg, png])
}

/// A scatter of points coloured by a scalar (e.g. the deformed nodes by von Mises stress),
/// over reference lines (the undeformed outline, an obstacle) and with text labels.
#[derive(Clone, Debug)]
pub struct ColourMap {
    /// Title.
    pub title: String,
    /// Label of the scalar.
    pub value_label: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Scalar per point.
    pub values: Vec<f64>,
    /// Lines drawn under the points.
    pub lines: Vec<Overlay>,
    /// Text labels (e.g. a body's name) at positions of the plot.
    pub labels: Vec<(String, (f64, f64))>,
}

/// A reference line of a [`ColourMap`].
#[derive(Clone, Debug)]
pub struct Overlay {
    /// Legend label (none: not in the legend).
    pub label: Option<String>,
    /// The polyline.
    pub points: Vec<(f64, f64)>,
    /// How it is drawn.
    pub kind: OverlayKind,
}

/// How an [`Overlay`] is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OverlayKind {
    /// Thin grey line (an undeformed outline).
    Outline,
    /// Thick dashed black line (a rigid obstacle).
    Obstacle,
}

fn viridis(t: f64) -> RGBColor {
    // Five-stop piecewise-linear approximation of matplotlib's viridis.
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = t.clamp(0.0, 1.0) * 4.0;
    let k = (t.floor() as usize).min(3);
    let f = t - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |x: f64, y: f64| (x + f * (y - x)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn draw_colour_map<DB: DrawingBackend>(
    area: DrawingArea<DB, plotters::coord::Shift>,
    map: &ColourMap,
) -> Result<(), String> {
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    let (main, bar) = area.split_horizontally(880);
    let everything = || map.points.iter().chain(map.lines.iter().flat_map(|l| l.points.iter()));
    let (x0, x1) = range(everything().map(|p| p.0));
    let (y0, y1) = range(everything().map(|p| p.1));
    // Equal axis scales: widen the shorter range.
    let (w, h) = (x1 - x0, y1 - y0);
    let aspect = 800.0 / 490.0;
    let (x0, x1, y0, y1) = if w / h > aspect {
        let c = 0.5 * (y0 + y1);
        (x0, x1, c - 0.5 * w / aspect, c + 0.5 * w / aspect)
    } else {
        let c = 0.5 * (x0 + x1);
        (c - 0.5 * h * aspect, c + 0.5 * h * aspect, y0, y1)
    };
    let (v0, v1) = range(map.values.iter().copied());
    let mut ctx = ChartBuilder::on(&main)
        .caption(&map.title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| e.to_string())?;
    ctx.configure_mesh()
        .disable_mesh()
        .x_desc(&map.x_label)
        .y_desc(&map.y_label)
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .x_label_formatter(&tick_label(x0, x1))
        .y_label_formatter(&tick_label(y0, y1))
        .draw()
        .map_err(|e| e.to_string())?;
    for line in &map.lines {
        let (colour, width) = match line.kind {
            OverlayKind::Outline => (RGBColor(150, 150, 150).to_rgba(), 1),
            OverlayKind::Obstacle => (BLACK.to_rgba(), 2),
        };
        let points = line.points.iter().copied();
        let drawn = match line.kind {
            OverlayKind::Outline => {
                ctx.draw_series(LineSeries::new(points, colour.stroke_width(width)))
            }
            OverlayKind::Obstacle => {
                ctx.draw_series(DashedLineSeries::new(points, 10, 6, colour.stroke_width(width)))
            }
        }
        .map_err(|e| e.to_string())?;
        if let Some(label) = &line.label {
            drawn.label(label).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(width))
            });
        }
    }
    let radius = ((500.0 / (map.points.len() as f64).sqrt()).round() as i32).clamp(1, 6);
    ctx.draw_series(
        map.points.iter().zip(&map.values).map(|(&(x, y), &v)| {
            Circle::new((x, y), radius, viridis((v - v0) / (v1 - v0)).filled())
        }),
    )
    .map_err(|e| e.to_string())?;
    for (text, at) in &map.labels {
        ctx.draw_series(std::iter::once(Text::new(
            text.clone(),
            *at,
            ("sans-serif", 16).into_font().color(&BLACK),
        )))
        .map_err(|e| e.to_string())?;
    }
    if map.lines.iter().any(|l| l.label.is_some()) {
        ctx.configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| e.to_string())?;
    }
    let mut bar_ctx = ChartBuilder::on(&bar)
        .margin_top(40)
        .margin_bottom(40)
        .y_label_area_size(70)
        .caption(&map.value_label, ("sans-serif", 13))
        .build_cartesian_2d(0.0..1.0, v0..v1)
        .map_err(|e| e.to_string())?;
    bar_ctx
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_formatter(&tick_label(v0, v1))
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(|e| e.to_string())?;
    let steps = 100;
    bar_ctx
        .draw_series((0..steps).map(|k| {
            let a = v0 + (v1 - v0) * k as f64 / steps as f64;
            let b = v0 + (v1 - v0) * (k + 1) as f64 / steps as f64;
            Rectangle::new([(0.0, a), (1.0, b)], viridis((k as f64 + 0.5) / steps as f64).filled())
        }))
        .map_err(|e| e.to_string())?;
    area.present().map_err(|e| e.to_string())
}

/// Writes `<stem>.svg` and `<stem>.png` of a colour map (1000 × 600).
///
/// # Errors
/// [`OutputError::Plot`] when plotters fails.
pub fn write_colour_map(stem: &Path, map: &ColourMap) -> Result<(), OutputError> {
    ensure_font();
    let size = (1000, 600);
    let svg = stem.with_extension("svg");
    draw_colour_map(SVGBackend::new(&svg, size).into_drawing_area(), map)
        .map_err(|reason| OutputError::Plot { path: svg.display().to_string(), reason })?;
    let png = stem.with_extension("png");
    draw_colour_map(BitMapBackend::new(&png, size).into_drawing_area(), map)
        .map_err(|reason| OutputError::Plot { path: png.display().to_string(), reason })
}
