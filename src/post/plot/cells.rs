//! Filled cells coloured by a scalar (a body's deformed shape by von Mises stress): each cell
//! a polygon in one colour, so that the body is drawn as the area it covers, over which the
//! reference lines (undeformed outline, obstacles) are drawn. The colour range is robust to a
//! single peak ([`super::scale`]); the colour bar says where it is clipped.

use super::scale::{self, QUANTILE};
use super::{
    OutputError, Overlay, PlotResult, draw_colour_bar, draw_labels, draw_overlays, ensure_font,
    equal_aspect, map_axes, viridis,
};
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;

/// One filled cell.
#[derive(Clone, Debug)]
pub struct Cell {
    /// Its vertices, in order around it.
    pub polygon: Vec<(f64, f64)>,
    /// Its value.
    pub value: f64,
}

impl Cell {
    /// The area of the cell (shoelace formula; zero for fewer than three vertices).
    pub fn area(&self) -> f64 {
        let p = &self.polygon;
        let twice: f64 = (0..p.len())
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % p.len()]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum();
        0.5 * twice.abs()
    }
}

/// A map of filled cells coloured by a scalar, over reference lines and with text labels.
#[derive(Clone, Debug)]
pub struct CellMap {
    /// Title.
    pub title: String,
    /// The quantity of the colour bar (with its units).
    pub value_label: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// The cells.
    pub cells: Vec<Cell>,
    /// Lines drawn over the cells.
    pub lines: Vec<Overlay>,
    /// Text labels (e.g. a body's name) at positions of the plot.
    pub labels: Vec<(String, (f64, f64))>,
}

/// The lines under the colour bar: where the range is clipped, and the largest value.
fn clipping_notes(range: &scale::ColourRange) -> Vec<String> {
    if !range.clipped {
        return Vec::new();
    }
    let max = format!("{:.4}", range.max);
    let max =
        if (1e-2..1e5).contains(&range.max.abs()) { max } else { format!("{:.3e}", range.max) };
    vec![
        format!("top: {:.0}th percentile", 100.0 * QUANTILE),
        "by area; larger values".into(),
        format!("in top colour (max {max})"),
    ]
}

/// Fills `cells` in the colours of `range`, each also outlined in its colour so that no
/// seam of background shows between neighbours.
fn draw_cells<'a, DB: DrawingBackend + 'a>(
    ctx: &mut super::Ctx<'a, DB>,
    cells: &[Cell],
    range: &scale::ColourRange,
) -> PlotResult<()> {
    let colour = |c: &Cell| viridis((c.value - range.lo) / (range.hi - range.lo));
    let drawn = || cells.iter().filter(|c| c.polygon.len() >= 3);
    ctx.draw_series(drawn().map(|c| Polygon::new(c.polygon.clone(), colour(c).filled())))
        .map_err(|e| e.to_string())?;
    ctx.draw_series(drawn().map(|c| {
        let mut ring = c.polygon.clone();
        ring.push(c.polygon[0]);
        PathElement::new(ring, colour(c).stroke_width(1))
    }))
    .map_err(|e| e.to_string())?;
    Ok(())
}

/// The edges of `cells` that belong to one cell only: the bodies' deformed boundaries (and the
/// contact interfaces between bodies). Shared vertices are moved alike, so an interior edge
/// has the same end points in both its cells; a sorted map keeps the drawing deterministic.
fn boundary_edges(cells: &[Cell]) -> Vec<[(f64, f64); 2]> {
    type Key = (u64, u64);
    type Edge = [(f64, f64); 2];
    let key = |p: (f64, f64)| (p.0.to_bits(), p.1.to_bits());
    let mut edges: BTreeMap<(Key, Key), (usize, Edge)> = BTreeMap::new();
    for c in cells.iter().filter(|c| c.polygon.len() >= 3) {
        let p = &c.polygon;
        for i in 0..p.len() {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            let (ka, kb) = (key(a), key(b));
            let k = if ka <= kb { (ka, kb) } else { (kb, ka) };
            edges.entry(k).or_insert((0, [a, b])).0 += 1;
        }
    }
    edges.into_values().filter(|(n, _)| *n == 1).map(|(_, e)| e).collect()
}

fn draw_cell_map<DB: DrawingBackend>(
    area: DrawingArea<DB, plotters::coord::Shift>,
    map: &CellMap,
) -> PlotResult<()> {
    area.fill(&WHITE).map_err(|e| e.to_string())?;
    let (main, bar) = area.split_horizontally(850);
    let vertices = map.cells.iter().flat_map(|c| c.polygon.iter());
    let everything = vertices.chain(map.lines.iter().flat_map(|l| l.points.iter()));
    let window = equal_aspect(everything, 770.0 / 490.0);
    let values: Vec<f64> = map.cells.iter().map(|c| c.value).collect();
    let areas: Vec<f64> = map.cells.iter().map(Cell::area).collect();
    let range = scale::robust_range(&values, &areas);
    let mut ctx = map_axes(&main, &map.title, (&map.x_label, &map.y_label), window)?;
    draw_cells(&mut ctx, &map.cells, &range)?;
    let dark = BLACK.stroke_width(1);
    ctx.draw_series(boundary_edges(&map.cells).into_iter().map(|e| PathElement::new(e, dark)))
        .map_err(|e| e.to_string())?;
    draw_overlays(&mut ctx, &map.lines)?;
    draw_labels(&mut ctx, &map.labels, &map.lines)?;
    draw_colour_bar(&bar, &map.value_label, (range.lo, range.hi), &clipping_notes(&range))?;
    area.present().map_err(|e| e.to_string())
}

/// Writes `<stem>.svg` and `<stem>.png` of a cell map (1000 × 600).
///
/// # Errors
/// [`OutputError::Plot`] when plotters fails.
pub fn write_cell_map(stem: &Path, map: &CellMap) -> Result<(), OutputError> {
    ensure_font();
    let size = (1000, 600);
    let svg = stem.with_extension("svg");
    draw_cell_map(SVGBackend::new(&svg, size).into_drawing_area(), map)
        .map_err(|reason| OutputError::Plot { path: svg.display().to_string(), reason })?;
    let png = stem.with_extension("png");
    draw_cell_map(BitMapBackend::new(&png, size).into_drawing_area(), map)
        .map_err(|reason| OutputError::Plot { path: png.display().to_string(), reason })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_of_a_unit_square_either_way_round_and_of_a_degenerate_cell() {
        let square = vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let mut reversed = square.clone();
        reversed.reverse();
        assert_eq!(Cell { polygon: square, value: 0.0 }.area(), 1.0);
        assert_eq!(Cell { polygon: reversed, value: 0.0 }.area(), 1.0);
        assert_eq!(Cell { polygon: vec![(0.0, 0.0)], value: 0.0 }.area(), 0.0);
    }

    #[test]
    fn the_boundary_of_two_squares_is_their_six_outer_edges() {
        let square = |x: f64| Cell {
            polygon: vec![(x, 0.0), (x + 1.0, 0.0), (x + 1.0, 1.0), (x, 1.0)],
            value: 0.0,
        };
        assert_eq!(boundary_edges(&[square(0.0), square(1.0)]).len(), 6);
    }

    #[test]
    fn an_empty_map_and_a_map_with_a_peak_are_drawn() {
        let dir = std::env::temp_dir().join(format!("mlpg-cells-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut map = CellMap {
            title: "t".into(),
            value_label: "v".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            cells: Vec::new(),
            lines: Vec::new(),
            labels: Vec::new(),
        };
        write_cell_map(&dir.join("empty"), &map).unwrap();
        map.cells = (0..400)
            .map(|k| {
                let (x, y) = ((k % 20) as f64, (k / 20) as f64);
                let polygon = vec![(x, y), (x + 1.0, y), (x + 1.0, y + 1.0), (x, y + 1.0)];
                Cell { polygon, value: if k == 0 { 1e3 } else { y } }
            })
            .collect();
        write_cell_map(&dir.join("peak"), &map).unwrap();
        assert!(dir.join("peak.png").exists() && dir.join("peak.svg").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
