//! Plots (SVG and PNG) with plotters and an embedded font, so no system library is needed.

use super::OutputError;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::Path;
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
}

/// One data series.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
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

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo { 0.05 * (hi - lo) } else { lo.abs().max(1e-12) * 0.1 };
    (lo - pad, hi + pad)
}

fn draw_chart<DB: DrawingBackend>(
    area: DrawingArea<DB, plotters::coord::Shift>,
    chart: &Chart,
) -> Result<(), String> {
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    let (x0, x1) = range(chart.series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
    let (y0, y1) = range(chart.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)));
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
        .y_label_formatter(&|v| format!("{v:.3e}"))
        .draw()
        .map_err(|e| e.to_string())?;
    for s in &chart.series {
        let colour = Palette99::pick(s.colour).to_rgba();
        let legend_colour = colour;
        match s.style {
            Style::Line => {
                ctx.draw_series(LineSeries::new(s.points.iter().copied(), colour.stroke_width(2)))
                    .map_err(|e| e.to_string())?
                    .label(&s.label)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], legend_colour.stroke_width(2))
                    });
            }
            Style::Dashed => {
                ctx.draw_series(DashedLineSeries::new(
                    s.points.iter().copied(),
                    8,
                    5,
                    colour.stroke_width(2),
                ))
                .map_err(|e| e.to_string())?
                .label(&s.label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], legend_colour.stroke_width(2))
                });
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

/// Writes `<stem>.svg` and `<stem>.png` (1000 × 600).
///
/// # Errors
/// [`OutputError::Plot`] when plotters fails (e.g. the directory is not writable).
pub fn write_chart(stem: &Path, chart: &Chart) -> Result<(), OutputError> {
    ensure_font();
    let size = (1000, 600);
    let svg = stem.with_extension("svg");
    draw_chart(SVGBackend::new(&svg, size).into_drawing_area(), chart)
        .map_err(|reason| OutputError::Plot { path: svg.display().to_string(), reason })?;
    let png = stem.with_extension("png");
    draw_chart(BitMapBackend::new(&png, size).into_drawing_area(), chart)
        .map_err(|reason| OutputError::Plot { path: png.display().to_string(), reason })
}

/// A scatter of points coloured by a scalar (e.g. the deformed nodes by von Mises stress).
#[derive(Clone, Debug)]
pub struct ColourMap {
    /// Title.
    pub title: String,
    /// Label of the scalar.
    pub value_label: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Scalar per point.
    pub values: Vec<f64>,
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
    let (x0, x1) = range(map.points.iter().map(|p| p.0));
    let (y0, y1) = range(map.points.iter().map(|p| p.1));
    // Equal axis scales: widen the shorter range.
    let (w, h) = (x1 - x0, y1 - y0);
    let aspect = 820.0 / 520.0;
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
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| e.to_string())?;
    ctx.configure_mesh()
        .disable_mesh()
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(|e| e.to_string())?;
    let radius = ((500.0 / (map.points.len() as f64).sqrt()).round() as i32).clamp(1, 6);
    ctx.draw_series(
        map.points.iter().zip(&map.values).map(|(&(x, y), &v)| {
            Circle::new((x, y), radius, viridis((v - v0) / (v1 - v0)).filled())
        }),
    )
    .map_err(|e| e.to_string())?;
    let mut bar_ctx = ChartBuilder::on(&bar)
        .margin_top(40)
        .margin_bottom(40)
        .y_label_area_size(70)
        .caption(&map.value_label, ("sans-serif", 14))
        .build_cartesian_2d(0.0..1.0, v0..v1)
        .map_err(|e| e.to_string())?;
    bar_ctx
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_formatter(&|v| format!("{v:.2e}"))
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
