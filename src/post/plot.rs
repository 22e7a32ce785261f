//! Plots (SVG and PNG) with plotters and an embedded font, so no system library is needed:
//! line charts ([`Chart`], zoomable to a part of their x-range), scatters coloured by a scalar
//! ([`ColourMap`]) and filled cells coloured by a scalar ([`CellMap`]).

mod cells;
mod clip;
pub mod scale;

pub use cells::{Cell, CellMap, write_cell_map};

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
    /// A dashed polyline that does not set the y-range (a target drawn for comparison, e.g. an
    /// obstacle whose distance grows far from the contact zone); clipped to the plot.
    Reference,
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

/// The height of the zoomed panel of a chart with a whole-edge panel under it.
const ZOOMED_HEIGHT: u32 = 580;

/// The drawing of one series in one panel.
type PlotResult<T> = Result<T, String>;

/// The y-range of the series that set it (not [`Style::Bands`] nor [`Style::Reference`]) over
/// their points with `x` in `x0..=x1`.
fn y_range(chart: &Chart, (x0, x1): (f64, f64)) -> (f64, f64) {
    let curves =
        chart.series.iter().filter(|s| !matches!(s.style, Style::Bands | Style::Reference));
    range(curves.flat_map(|s| s.points.iter().filter(|p| p.0 >= x0 && p.0 <= x1).map(|p| p.1)))
}

/// One panel of a chart over `x0..x1`: its series clipped to the panel, the legend and the
/// axis titles when `main` (not on the whole-edge panel under a zoomed one), and `shade` (the
/// zoomed window, shown on the whole-edge panel) as a grey band.
struct Panel<'a> {
    caption: &'a str,
    caption_size: u32,
    x: (f64, f64),
    main: bool,
    shade: Option<(f64, f64)>,
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    chart: &Chart,
    panel: &Panel<'_>,
) -> PlotResult<()> {
    let (x0, x1) = panel.x;
    let (y0, y1) = y_range(chart, panel.x);
    let none = String::new();
    let mut ctx = ChartBuilder::on(area)
        .caption(panel.caption, ("sans-serif", panel.caption_size))
        .margin(12)
        .x_label_area_size(if panel.main { 45 } else { 25 })
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| e.to_string())?;
    let (x_desc, y_desc) =
        if panel.main { (&chart.x_label, &chart.y_label) } else { (&none, &none) };
    ctx.configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .y_labels(if panel.main { 10 } else { 4 })
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .x_label_formatter(&tick_label(x0, x1))
        .y_label_formatter(&tick_label(y0, y1))
        .draw()
        .map_err(|e| e.to_string())?;
    if let Some((a, b)) = panel.shade {
        let grey = RGBColor(120, 120, 120).mix(0.2).filled();
        ctx.draw_series(std::iter::once(Rectangle::new([(a, y0), (b, y1)], grey)))
            .map_err(|e| e.to_string())?;
    }
    // Bands first, under the curves.
    let mut ordered: Vec<&Series> = chart.series.iter().collect();
    ordered.sort_by_key(|s| !matches!(s.style, Style::Bands));
    for s in ordered {
        draw_series(&mut ctx, s, [x0, x1, y0, y1], panel.main)?;
    }
    if panel.main {
        ctx.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

type Ctx<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Draws `s` inside `window` (`[x0, x1, y0, y1]`), with its legend entry when `legend`.
fn draw_series<'a, DB: DrawingBackend + 'a>(
    ctx: &mut Ctx<'a, DB>,
    s: &Series,
    window: [f64; 4],
    legend: bool,
) -> PlotResult<()> {
    let [x0, x1, y0, y1] = window;
    let colour = Palette99::pick(s.colour).to_rgba();
    let label = if legend && !s.label.is_empty() { Some(s.label.as_str()) } else { None };
    let line =
        move |x: i32, y: i32| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2));
    match s.style {
        Style::Bands => {
            let fill = colour.mix(0.18).filled();
            let bands = s.points.chunks_exact(2).filter(|p| p[1].0 >= x0 && p[0].0 <= x1);
            let drawn = ctx
                .draw_series(
                    bands.map(|p| {
                        Rectangle::new([(p[0].0.max(x0), y0), (p[1].0.min(x1), y1)], fill)
                    }),
                )
                .map_err(|e| e.to_string())?;
            if let Some(l) = label {
                drawn
                    .label(l)
                    .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], fill));
            }
        }
        Style::Line | Style::Dashed | Style::Reference => {
            // An empty series carries the legend entry, so that it is there even when the
            // curve lies outside the panel.
            let empty = ctx
                .draw_series(LineSeries::new(std::iter::empty(), colour.stroke_width(2)))
                .map_err(|e| e.to_string())?;
            if let Some(l) = label {
                empty.label(l).legend(move |(x, y)| line(x, y));
            }
            for run in clip::clip_polyline(&s.points, window) {
                if s.style == Style::Line {
                    ctx.draw_series(LineSeries::new(run, colour.stroke_width(2)))
                } else {
                    ctx.draw_series(DashedLineSeries::new(run, 8, 5, colour.stroke_width(2)))
                }
                .map_err(|e| e.to_string())?;
            }
        }
        Style::Points => {
            let inside =
                s.points.iter().filter(|p| p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1);
            let drawn = ctx
                .draw_series(inside.map(|&(x, y)| Circle::new((x, y), 3, colour.filled())))
                .map_err(|e| e.to_string())?;
            if let Some(l) = label {
                drawn.label(l).legend(move |(x, y)| Circle::new((x + 10, y), 3, colour.filled()));
            }
        }
    }
    Ok(())
}

/// The chart on `area`: one panel over every point's x-range, or with `zoom` the zoomed
/// panel over `zoom` and, under it, the whole x-range with the zoomed part shaded.
fn draw_chart<DB: DrawingBackend>(
    area: DrawingArea<DB, plotters::coord::Shift>,
    chart: &Chart,
    zoom: Option<(f64, f64)>,
) -> PlotResult<()> {
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    let whole = range(chart.series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
    let main = |x| Panel { caption: &chart.title, caption_size: 22, x, main: true, shade: None };
    match zoom.filter(|(a, b)| a < b) {
        None => draw_panel(&area, chart, &main(whole))?,
        Some(window) => {
            let (top, bottom) = area.split_vertically(ZOOMED_HEIGHT);
            draw_panel(&top, chart, &main(window))?;
            let overview = Panel {
                caption: "the whole edge (the part shown above shaded)",
                caption_size: 15,
                x: whole,
                main: false,
                shade: Some(window),
            };
            draw_panel(&bottom, chart, &overview)?;
        }
    }
    area.present().map_err(|e| e.to_string())
}

/// Writes `<stem>.svg` and `<stem>.png` (1000 × 600) and returns their paths.
///
/// # Errors
/// [`OutputError::Plot`] when plotters fails (e.g. the directory is not writable).
pub fn write_chart(stem: &Path, chart: &Chart) -> Result<[PathBuf; 2], OutputError> {
    write_zoomed_chart(stem, chart, None)
}

/// [`write_chart`], zoomed to the x-range `zoom` when given: then the image is 1000 × 820,
/// the zoomed chart over a panel of the whole x-range with the zoomed part shaded.
///
/// # Errors
/// [`OutputError::Plot`] when plotters fails (e.g. the directory is not writable).
pub fn write_zoomed_chart(
    stem: &Path,
    chart: &Chart,
    zoom: Option<(f64, f64)>,
) -> Result<[PathBuf; 2], OutputError> {
    ensure_font();
    let size = if zoom.is_some() { (1000, ZOOMED_HEIGHT + 240) } else { (1000, 600) };
    let svg = stem.with_extension("svg");
    draw_chart(SVGBackend::new(&svg, size).into_drawing_area(), chart, zoom)
        .map_err(|reason| OutputError::Plot { path: svg.display().to_string(), reason })?;
    let png = stem.with_extension("png");
    draw_chart(BitMapBackend::new(&png, size).into_drawing_area(), chart, zoom)
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

pub(crate) fn viridis(t: f64) -> RGBColor {
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

/// The plot window `(x0, x1, y0, y1)` of `points` with equal scales on both axes in a
/// plotting area of aspect ratio `aspect` (width / height): the shorter range is widened.
fn equal_aspect<'a>(points: impl Iterator<Item = &'a (f64, f64)> + Clone, aspect: f64) -> [f64; 4] {
    let (x0, x1) = range(points.clone().map(|p| p.0));
    let (y0, y1) = range(points.map(|p| p.1));
    let (w, h) = (x1 - x0, y1 - y0);
    if w / h > aspect {
        let c = 0.5 * (y0 + y1);
        [x0, x1, c - 0.5 * w / aspect, c + 0.5 * w / aspect]
    } else {
        let c = 0.5 * (x0 + x1);
        [c - 0.5 * h * aspect, c + 0.5 * h * aspect, y0, y1]
    }
}

/// The axes of a map over `window`, with its title.
fn map_axes<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    labels: (&str, &str),
    [x0, x1, y0, y1]: [f64; 4],
) -> PlotResult<Ctx<'a, DB>> {
    let mut ctx = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| e.to_string())?;
    ctx.configure_mesh()
        .disable_mesh()
        .x_desc(labels.0)
        .y_desc(labels.1)
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .x_label_formatter(&tick_label(x0, x1))
        .y_label_formatter(&tick_label(y0, y1))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(ctx)
}

/// The reference lines of a map (outlines, obstacles), with their legend entries.
fn draw_overlays<'a, DB: DrawingBackend + 'a>(
    ctx: &mut Ctx<'a, DB>,
    lines: &[Overlay],
) -> PlotResult<()> {
    for line in lines {
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
    Ok(())
}

/// The text labels of a map, and the legend of its lines (if any has a label).
fn draw_labels<'a, DB: DrawingBackend + 'a>(
    ctx: &mut Ctx<'a, DB>,
    labels: &[(String, (f64, f64))],
    lines: &[Overlay],
) -> PlotResult<()> {
    for (text, at) in labels {
        ctx.draw_series(std::iter::once(Text::new(
            text.clone(),
            *at,
            ("sans-serif", 16).into_font().color(&BLACK),
        )))
        .map_err(|e| e.to_string())?;
    }
    if lines.iter().any(|l| l.label.is_some()) {
        ctx.configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// The colour bar from `v0` (bottom) to `v1` (top) captioned `label`, with `notes` (one line
/// each) under it.
fn draw_colour_bar<DB: DrawingBackend>(
    bar: &DrawingArea<DB, plotters::coord::Shift>,
    label: &str,
    (v0, v1): (f64, f64),
    notes: &[String],
) -> PlotResult<()> {
    let mut bar_ctx = ChartBuilder::on(bar)
        .margin_top(40)
        .margin_bottom(if notes.is_empty() { 40 } else { 30 + 16 * notes.len() as u32 })
        .y_label_area_size(70)
        .caption(label, ("sans-serif", 13))
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
    let height = bar.dim_in_pixel().1 as i32;
    let font = ("sans-serif", 12).into_font().color(&BLACK);
    for (k, note) in notes.iter().enumerate() {
        let y = height - 16 * (notes.len() - k) as i32 - 4;
        bar.draw(&Text::new(note.clone(), (4, y), font.clone())).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn draw_colour_map<DB: DrawingBackend>(
    area: DrawingArea<DB, plotters::coord::Shift>,
    map: &ColourMap,
) -> PlotResult<()> {
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    let (main, bar) = area.split_horizontally(880);
    let everything = map.points.iter().chain(map.lines.iter().flat_map(|l| l.points.iter()));
    let window = equal_aspect(everything, 800.0 / 490.0);
    let (v0, v1) = range(map.values.iter().copied());
    let mut ctx = map_axes(&main, &map.title, (&map.x_label, &map.y_label), window)?;
    draw_overlays(&mut ctx, &map.lines)?;
    let radius = ((500.0 / (map.points.len() as f64).sqrt()).round() as i32).clamp(1, 6);
    ctx.draw_series(
        map.points.iter().zip(&map.values).map(|(&(x, y), &v)| {
            Circle::new((x, y), radius, viridis((v - v0) / (v1 - v0)).filled())
        }),
    )
    .map_err(|e| e.to_string())?;
    draw_labels(&mut ctx, &map.labels, &map.lines)?;
    draw_colour_bar(&bar, &map.value_label, (v0, v1), &[])?;
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
