//! Error against nodes, uniform and adaptive refinement (docs/method.md §2.2), for the Kirsch
//! quarter plate and the clamped cantilever: the table printed, the data written as CSV under
//! `docs/data/` and the log–log plots as SVG under `docs/guide/src/img/` (the user guide shows them).
//! Results and reading: docs/dev/adaptive.md ("Kirsch: adaptive against uniform", "Plots").
//!
//! - **Kirsch** (`tests/validation/kirsch.rs`): the quarter `[0, 5]²` outside the hole of
//!   radius 1, rollers on the symmetry lines, the exact traction of the infinite plate on
//!   `x = 5` and `y = 5`, so Kirsch's solution is the exact one of this finite plate (no
//!   truncation). Error: the relative energy-norm error against it (nodal quadrature over the
//!   cells); the max-norm displacement error and `σ_xx(0, a)` are printed and written too.
//!   `β = 0.5`, `α_s = 2`, structured nodes. Uniform `h` and the loop from each start `h₀`,
//!   each indicator and Dörfler `θ`, `max_nodes` = the finest uniform count.
//! - **Cantilever** (`tests/validation/clamped_cantilever_measure.rs`): the compliance `W`
//!   against the Q2 FE path extrapolated from element sizes 0.5, 0.25, 0.125 (the reference of
//!   `clamped_cantilever.rs`), uniform `h` = 2 … 0.125 and four adaptive variants (the test's,
//!   from `h₀ = 0.25`, and three from coarse starts).
//!
//! `cargo run --release --features studies --example adaptive_convergence -- [--only kirsch|cantilever]
//! [--kirsch-uniform 0.4,0.2,0.1,0.05,0.025] [--kirsch-start 0.4,0.2] [--fraction 0.3,0.5,0.7]
//! [--no-write] [--plot-only]` (the defaults; about 4 minutes for Kirsch and 5.5 GB peak
//! memory, under 2 minutes and 3 GB for the cantilever, on the shared 2-core machine). Without
//! `--no-write` the CSV and SVG files of the case(s) run are overwritten; `--plot-only` redraws
//! the SVGs from the CSVs without solving.

mod args;
#[path = "../../tests/validation/common.rs"]
#[allow(dead_code)]
mod common;
#[path = "../../tests/validation/kirsch.rs"]
#[allow(dead_code)]
mod kirsch;
#[path = "../../tests/validation/clamped_cantilever_measure.rs"]
#[allow(dead_code)]
mod measure;

use mlpg_contact::nodes::Layout;
use mlpg_contact::pipeline::adaptive;
use mlpg_contact::problem::{Adaptive, Indicator, Method, Problem};
use mlpg_contact::{Model, Solution};
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;
use std::time::Instant;

/// The case a run is limited to (`--only`).
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Case {
    Kirsch,
    Cantilever,
}

/// Error against nodes, uniform and adaptive, for the Kirsch plate and the clamped cantilever.
#[derive(clap::Parser)]
struct Cli {
    /// Run one case only (default: both)
    #[arg(long, value_enum)]
    only: Option<Case>,
    /// Uniform node spacings of the Kirsch study
    #[arg(long, value_name = "H,…", value_delimiter = ',', value_parser = args::positive,
          default_values_t = [0.4, 0.2, 0.1, 0.05, 0.025])]
    kirsch_uniform: Vec<f64>,
    /// Initial spacings h₀ of the Kirsch study's adaptive loops
    #[arg(long, value_name = "H,…", value_delimiter = ',', value_parser = args::positive,
          default_values_t = [0.4, 0.2])]
    kirsch_start: Vec<f64>,
    /// Dörfler fractions θ of the Kirsch study's adaptive loops
    #[arg(long, value_name = "THETA,…", value_delimiter = ',', value_parser = args::positive,
          default_values_t = [0.3, 0.5, 0.7])]
    fraction: Vec<f64>,
    /// Write neither CSV nor SVG files (print the table only)
    #[arg(long)]
    no_write: bool,
    /// Redraw the SVGs from the CSVs without solving
    #[arg(long)]
    plot_only: bool,
}

/// One solve of a sequence: nodes, the primary error and the secondary measures.
#[derive(Clone, Debug)]
struct Row {
    nodes: usize,
    error: f64,
    extra: Vec<f64>,
}

/// A sequence of solves (uniform spacings, or the steps of one adaptive run).
struct Run {
    label: String,
    /// `uniform`, `gradient` or `recovery`.
    kind: String,
    fraction: f64,
    start: f64,
    rows: Vec<Row>,
}

/// The primary error of a solve and its secondary measures.
type Measure = dyn Fn(&Problem, &Model, &Solution) -> (f64, Vec<f64>);

/// An adaptive run of `problem` with `max_nodes`, each step measured by `error`.
fn adaptive_run(
    label: String,
    problem: &Problem,
    indicator: Indicator,
    fraction: f64,
    max_nodes: usize,
    error: &Measure,
) -> Run {
    let a = Adaptive {
        steps: 14,
        max_nodes,
        fraction,
        indicator,
        contact: false,
        ..Adaptive::default()
    };
    let mut rows = Vec::new();
    let t = Instant::now();
    let result =
        adaptive::solve_adaptive(problem, &a, &mut mlpg_contact::Silent, &mut |q, m, s, _| {
            assert!(s.relative_residual < 1e-10, "residual {}", s.relative_residual);
            assert!(s.equilibrium_error < 1e-9, "equilibrium {}", s.equilibrium_error);
            let (e, extra) = error(q, m, s);
            println!(
                "| {label} | {} | {} | {e:.3e} | {} | {:.1} |",
                rows.len(),
                m.nodes.len(),
                extra.iter().map(|v| format!("{v:.4e}")).collect::<Vec<_>>().join(" | "),
                t.elapsed().as_secs_f64()
            );
            rows.push(Row { nodes: m.nodes.len(), error: e, extra });
        });
    if let Err(e) = result {
        println!("| {label} | failed: {e} | | | | |");
    }
    Run { label, kind: indicator.name().into(), fraction, start: problem.node_spacing, rows }
}

/// The first set of `run` at or below `target` (nodes), if any.
fn reached(run: &Run, target: f64) -> Option<usize> {
    run.rows.iter().find(|r| r.error <= target).map(|r| r.nodes)
}

fn verdict(runs: &[Run], uniform: &Run) {
    let finest = uniform.rows.last().expect("a uniform set");
    println!(
        "\nfinest uniform: {} nodes, error {:.3e}; a third: {} nodes\n",
        finest.nodes,
        finest.error,
        finest.nodes / 3
    );
    for run in runs {
        match reached(run, finest.error) {
            Some(n) => println!(
                "{}: reached with {n} nodes ({:.3} of the finest uniform)",
                run.label,
                n as f64 / finest.nodes as f64
            ),
            None => println!(
                "{}: not reached within {} nodes (best {:.3e})",
                run.label,
                finest.nodes,
                run.rows.iter().map(|r| r.error).fold(f64::INFINITY, f64::min)
            ),
        }
    }
}

fn write_csv(path: &Path, extra: &str, runs: &[Run]) {
    let mut text = format!("run,kind,fraction,start_spacing,step,nodes,error,{extra}\n");
    for run in runs {
        for (k, r) in run.rows.iter().enumerate() {
            let extra: Vec<String> = r.extra.iter().map(|v| format!("{v:.6e}")).collect();
            text.push_str(&format!(
                "\"{}\",{},{},{},{k},{},{:.6e},{}\n",
                run.label,
                run.kind,
                run.fraction,
                run.start,
                r.nodes,
                r.error,
                extra.join(",")
            ));
        }
    }
    std::fs::write(path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    println!("wrote {}", path.display());
}

/// The runs of a CSV written by [`write_csv`] (for `--plot-only`).
fn read_csv(path: &Path) -> Vec<Run> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut runs: Vec<Run> = Vec::new();
    for line in text.lines().skip(1) {
        let (label, rest) = line[1..].split_once("\",").expect("a quoted run label");
        let f: Vec<&str> = rest.split(',').collect();
        let number = |k: usize| f[k].parse::<f64>().expect("a number");
        let row = Row {
            nodes: f[4].parse().expect("a node count"),
            error: number(5),
            extra: (6..f.len()).map(number).collect(),
        };
        match runs.last_mut() {
            Some(run) if run.label == label => run.rows.push(row),
            _ => runs.push(Run {
                label: label.to_string(),
                kind: f[0].to_string(),
                fraction: number(1),
                start: number(2),
                rows: vec![row],
            }),
        }
    }
    runs
}

fn kirsch_error(_: &Problem, m: &Model, s: &Solution) -> (f64, Vec<f64>) {
    let e = kirsch::measure(m, s);
    (e.energy, vec![e.displacement, e.concentration])
}

fn kirsch_study(cli: &Cli) -> Vec<Run> {
    let (uniform_h, starts, fractions) =
        (&cli.kirsch_uniform[..], &cli.kirsch_start[..], &cli.fraction[..]);
    let problem = |h: f64| {
        let mut p = kirsch::kirsch_problem(kirsch::quarter_plate(), h, Layout::Structured);
        p.discretisation.beta = 0.5;
        p
    };
    println!("## Kirsch quarter plate, β = 0.5: relative energy-norm error\n");
    println!("| run | step | nodes | energy error | displacement error | σ_xx(0, a) | seconds |");
    println!("|---|---|---|---|---|---|---|");
    let mut uniform = Run {
        label: "uniform".into(),
        kind: "uniform".into(),
        fraction: 0.0,
        start: uniform_h[0],
        rows: Vec::new(),
    };
    for &h in uniform_h {
        let t = Instant::now();
        let p = problem(h);
        let mut silent = mlpg_contact::Silent;
        let m = mlpg_contact::discretise(&p, &mut silent).expect("discretised");
        let (m, _, s) = mlpg_contact::solve_model(&p, m, None, &mut silent).expect("solved");
        let (e, extra) = kirsch_error(&p, &m, &s);
        println!(
            "| uniform h = {h} | – | {} | {e:.3e} | {:.4e} | {:.4e} | {:.1} |",
            m.nodes.len(),
            extra[0],
            extra[1],
            t.elapsed().as_secs_f64()
        );
        uniform.rows.push(Row { nodes: m.nodes.len(), error: e, extra });
    }
    let max_nodes = uniform.rows.last().expect("a uniform set").nodes;
    let mut runs = Vec::new();
    for &h0 in starts {
        for indicator in [Indicator::Gradient, Indicator::Recovery] {
            for &fraction in fractions {
                let label = format!("{} θ = {fraction} from h₀ = {h0}", indicator.name());
                runs.push(adaptive_run(
                    label,
                    &problem(h0),
                    indicator,
                    fraction,
                    max_nodes,
                    &kirsch_error,
                ));
            }
        }
    }
    verdict(&runs, &uniform);
    runs.insert(0, uniform);
    runs
}

fn cantilever_study() -> Vec<Run> {
    let (w_ref, bar, rate, fe) = measure::fe_reference(&[1.0, 0.5, 0.25, 0.125]);
    println!("## Clamped cantilever, β = 0.5: relative error of the compliance W\n");
    println!("FE W at h = 1, 0.5, 0.25, 0.125: {fe:.10?}");
    println!("W_ref = {w_ref:.10} (rate {rate:.2}, error bar {bar:.2e})\n");
    println!("| run | step | nodes | W error | W/W_ref − 1 | seconds |");
    println!("|---|---|---|---|---|---|");
    let error = move |p: &Problem, m: &Model, s: &Solution| {
        let e = measure::compliance_mfvm(p, m, s) / w_ref - 1.0;
        (e.abs(), vec![e])
    };
    let mut uniform = Run {
        label: "uniform".into(),
        kind: "uniform".into(),
        fraction: 0.0,
        start: 2.0,
        rows: Vec::new(),
    };
    for h in [2.0, 1.0, 0.5, 0.25, 0.125] {
        let t = Instant::now();
        let p = measure::cantilever(h, Method::Mfvm);
        let (m, s) = measure::solve(&p);
        let (e, extra) = error(&p, &m, &s);
        println!(
            "| uniform h = {h} | – | {} | {e:.3e} | {:+.3e} | {:.1} |",
            m.nodes.len(),
            extra[0],
            t.elapsed().as_secs_f64()
        );
        uniform.rows.push(Row { nodes: m.nodes.len(), error: e, extra });
    }
    let max_nodes = uniform.rows.last().expect("a uniform set").nodes;
    let variants = [
        (0.25, Indicator::Recovery, 0.5),
        (2.0, Indicator::Gradient, 0.5),
        (2.0, Indicator::Recovery, 0.5),
        (1.0, Indicator::Gradient, 0.3),
    ];
    let mut runs = Vec::new();
    for (h0, indicator, fraction) in variants {
        let label = format!("{} θ = {fraction} from h₀ = {h0}", indicator.name());
        let p = measure::cantilever(h0, Method::Mfvm);
        runs.push(adaptive_run(label, &p, indicator, fraction, max_nodes, &error));
    }
    verdict(&runs, &uniform);
    runs.insert(0, uniform);
    runs
}

// ---------------------------------------------------------------------------------------------
// The plot: error against nodes, log–log, one panel per group of runs.

const PALETTE: [RGBColor; 7] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0x8c, 0x56, 0x4b),
    RGBColor(0xe3, 0x77, 0xc2),
];

/// A panel: title, y label, the runs drawn (the first, uniform, black dashed) and the
/// horizontal line of the finest uniform error with the vertical one at a third of its nodes.
struct Panel<'a> {
    title: String,
    y_label: &'a str,
    runs: Vec<&'a Run>,
    /// The rows' first extra value is the signed error: mark the positive ones (ringed).
    signed: bool,
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    (lo / 1.4, hi * 1.4)
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let all = || panel.runs.iter().flat_map(|r| r.rows.iter());
    let (x0, x1) = bounds(all().map(|r| r.nodes as f64));
    let (y0, y1) = bounds(all().map(|r| r.error));
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 15))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(60)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("nodes")
        .y_desc(panel.y_label)
        .label_style(("sans-serif", 11))
        .axis_desc_style(("sans-serif", 12))
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(e)?;
    let uniform = panel.runs[0];
    let finest = uniform.rows.last().expect("a uniform set");
    let grey = RGBColor(140, 140, 140).stroke_width(1);
    chart
        .draw_series(DashedLineSeries::new([(x0, finest.error), (x1, finest.error)], 4, 4, grey))
        .map_err(e)?
        .label("finest uniform error")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], grey));
    let third = finest.nodes as f64 / 3.0;
    chart
        .draw_series(DashedLineSeries::new([(third, y0), (third, y1)], 2, 4, grey))
        .map_err(e)?
        .label("a third of its nodes")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], grey));
    for (k, run) in panel.runs.iter().enumerate() {
        let points: Vec<(f64, f64)> = run.rows.iter().map(|r| (r.nodes as f64, r.error)).collect();
        let colour = if k == 0 { BLACK } else { PALETTE[(k - 1) % PALETTE.len()] };
        let style = colour.stroke_width(2);
        let series = if k == 0 {
            chart.draw_series(DashedLineSeries::new(points.iter().copied(), 7, 4, style))
        } else {
            chart.draw_series(LineSeries::new(points.iter().copied(), style))
        };
        series.map_err(e)?.label(run.label.as_str()).legend(move |(x, y)| {
            PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
        });
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled()))).map_err(e)?;
        if panel.signed {
            let positive = run.rows.iter().filter(|r| r.extra.first().is_some_and(|&v| v > 0.0));
            chart
                .draw_series(
                    positive
                        .map(|r| Circle::new((r.nodes as f64, r.error), 7, colour.stroke_width(2))),
                )
                .map_err(e)?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 10))
        .draw()
        .map_err(e)?;
    Ok(())
}

fn draw_grid<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    panels: &[Panel],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let root = root.titled(title, ("sans-serif", 18)).map_err(|e| e.to_string())?;
    for (area, panel) in root.split_evenly((1, panels.len())).iter().zip(panels) {
        draw_panel(area, panel)?;
    }
    root.present().map_err(|e| e.to_string())
}

fn draw_figure(svg: &Path, title: &str, panels: &[Panel]) {
    static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
    static REGISTER: std::sync::Once = std::sync::Once::new();
    REGISTER.call_once(|| {
        if plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_err() {
            panic!("embedded DejaVuSans.ttf failed to parse");
        }
    });
    let size = (560 * panels.len() as u32 + if panels.len() == 1 { 200 } else { 0 }, 480);
    draw_grid(SVGBackend::new(svg, size).into_drawing_area(), title, panels)
        .unwrap_or_else(|e| panic!("{}: {e}", svg.display()));
    println!("wrote {}", svg.display());
    // A PNG under target/ (for viewing; docs/ takes the SVG).
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target");
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let png = dir.join(svg.file_name().expect("a file")).with_extension("png");
    draw_grid(BitMapBackend::new(&png, size).into_drawing_area(), title, panels)
        .unwrap_or_else(|e| panic!("{}: {e}", png.display()));
}

fn main() {
    let cli: Cli = args::parse(&[]);
    let (only, write, plot_only) = (cli.only, !cli.no_write, cli.plot_only);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs");
    if only != Some(Case::Cantilever) {
        let runs = if plot_only {
            read_csv(&root.join("data/adaptive_kirsch.csv"))
        } else {
            kirsch_study(&cli)
        };
        if write && !plot_only {
            write_csv(
                &root.join("data/adaptive_kirsch.csv"),
                "displacement_error,sigma_xx_at_hole",
                &runs,
            );
        }
        if write {
            let panels: Vec<Panel> = ["gradient", "recovery"]
                .iter()
                .map(|&kind| Panel {
                    title: format!("{kind} indicator"),
                    y_label: "relative energy-norm error",
                    runs: std::iter::once(&runs[0])
                        .chain(runs.iter().filter(|r| r.kind == kind))
                        .collect(),
                    signed: false,
                })
                .collect();
            draw_figure(
                &root.join("guide/src/img/adaptive_kirsch.svg"),
                "Kirsch quarter plate: energy-norm error against nodes, uniform and adaptive",
                &panels,
            );
        }
    }
    if only != Some(Case::Kirsch) {
        let runs = if plot_only {
            read_csv(&root.join("data/adaptive_cantilever.csv"))
        } else {
            cantilever_study()
        };
        if write && !plot_only {
            write_csv(&root.join("data/adaptive_cantilever.csv"), "signed_error", &runs);
        }
        if write {
            let panel = Panel {
                title: "ringed: W above W_ref (the error changes sign)".into(),
                y_label: "|W/W_ref − 1|",
                runs: runs.iter().collect(),
                signed: true,
            };
            draw_figure(
                &root.join("guide/src/img/adaptive_cantilever.svg"),
                "Clamped cantilever: compliance error against nodes, uniform and adaptive",
                &[panel],
            );
        }
    }
}
