//! # A parameter sweep: the initial gap of the beam on a rigid foundation
//!
//! How do the total contact force and the contact onset of the paper's beam change with the
//! initial gap between the beam and the rigid foundation (0.01 in the paper)? This example
//! reads `problems/beam_on_foundation.toml` once, changes the gap in the raw [`ProblemFile`]
//! for each of six values, validates and solves each variant, prints a table and plots both
//! quantities against the gap.
//!
//! ```text
//! cargo run --release --example gap_sweep
//! ```
//!
//! Run it from the crate's root (it reads `problems/` and writes `out/gap_sweep/`); it takes
//! about a second in release mode. The figure is `out/gap_sweep/gap_sweep.png` (and `.svg`).
//!
//! The same pattern serves any sweep: change a field of the raw file (never the TOML text),
//! validate with `Problem::try_from`, solve, keep what you need from the solution.

use anyhow::Context;
use mlpg_contact::problem::{GeometryFile, Problem, ProblemFile};
use plotters::prelude::*;
use std::path::Path;

/// The initial gaps, from a tenth of the file's 0.01 to ten times it.
const GAPS: [f64; 6] = [0.001, 0.0025, 0.005, 0.01, 0.025, 0.05];

/// What we keep of each solve.
struct Row {
    gap: f64,
    force: f64,
    onset: f64,
}

fn main() -> anyhow::Result<()> {
    // Read the file once into the raw `ProblemFile`; every variant starts from a clone.
    let path = "problems/beam_on_foundation.toml";
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {path}"))?;
    let base = ProblemFile::from_toml(&text)?;

    // The foundation is the straight line through `contact.obstacle_point` with normal
    // `obstacle_normal` (here (0, 1), pointing up into the beam). The gap is the distance from
    // the beam's bottom edge down to that line, so read the bottom edge from the geometry.
    let Some(GeometryFile::Rectangle { x, y, .. }) = &base.geometry else {
        anyhow::bail!("{path}: expected a rectangle");
    };
    let (x0, bottom) = (x[0], y[0]);

    let mut rows = Vec::new();
    for gap in GAPS {
        let mut file = base.clone();
        let tables = file.contact.as_mut().context("the beam has a [contact] table")?;
        let contact = &mut tables.tables_mut()[0];
        contact.obstacle_point = Some([x0, bottom - gap]);

        let problem = Problem::try_from(file)?;
        let solution = mlpg_contact::solve(&problem)?;
        let contact = solution.contact().context("no contact solution")?;
        rows.push(Row {
            gap,
            force: contact.total_force,
            // Where the closed zone begins, along the bottom edge from the clamp (x = 0).
            onset: contact.onset.from_gap.unwrap_or(f64::NAN),
        });
    }

    println!("{:>8} {:>14} {:>10}", "gap", "contact force", "onset l_c");
    for r in &rows {
        println!("{:>8} {:>14.4} {:>10.3}", r.gap, r.force, r.onset);
    }

    let out = Path::new("out").join("gap_sweep");
    std::fs::create_dir_all(&out)?;
    let svg = out.join("gap_sweep.svg");
    let png = out.join("gap_sweep.png");
    draw(SVGBackend::new(&svg, (1000, 500)).into_drawing_area(), &rows)?;
    draw(BitMapBackend::new(&png, (1000, 500)).into_drawing_area(), &rows)?;
    println!("plots: {} and {}", png.display(), svg.display());
    Ok(())
}

/// Two panels side by side, force and onset against the gap (logarithmic, as the gaps are),
/// drawn on any plotters backend: the same code writes the SVG and the PNG.
fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    rows: &[Row],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    // Plotters draws text with a font registered under a family name; the crate ships one.
    static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
    static REGISTER: std::sync::Once = std::sync::Once::new();
    REGISTER.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
            .unwrap_or_else(|_| panic!("the embedded font does not parse"));
    });

    root.fill(&WHITE)?;
    let title = "The paper's beam on a rigid foundation: contact against the initial gap";
    let root = root.titled(title, ("sans-serif", 22))?;
    let panels = root.split_evenly((1, 2));
    let gaps = (GAPS[0] / 1.5)..(GAPS[GAPS.len() - 1] * 1.5);
    let quantities = [
        (
            "total contact force F_c (per unit thickness)",
            rows.iter().map(|r| r.force).collect::<Vec<_>>(),
            BLUE,
        ),
        (
            "contact onset l_c (distance from the clamp)",
            rows.iter().map(|r| r.onset).collect(),
            RED,
        ),
    ];
    for (area, (label, values, colour)) in panels.iter().zip(quantities) {
        let points: Vec<(f64, f64)> = rows.iter().map(|r| r.gap).zip(values).collect();
        let (lo, hi) =
            points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
        let pad = 0.1 * (hi - lo).max(1e-9);
        let mut chart = ChartBuilder::on(area)
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(
                // A logarithmic gap axis with a tick at each gap of the sweep.
                gaps.clone().log_scale().with_key_points(GAPS.to_vec()),
                (lo - pad)..(hi + pad),
            )?;
        chart
            .configure_mesh()
            .x_desc("initial gap δ₀")
            .y_desc(label)
            .x_label_formatter(&|g| format!("{g}"))
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .draw()?;
        chart.draw_series(LineSeries::new(points.iter().copied(), colour.stroke_width(2)))?;
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, colour.filled())))?;
    }
    root.present()?;
    Ok(())
}
