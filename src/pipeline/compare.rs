//! Both discretisations on one problem: `mlpg-contact <problem.toml> --compare`.
//!
//! Solves the problem with the MFVM and with the Q2 finite elements ([`crate::fem`]), writes
//! each method's full outputs to `<out>/mfvm/` and `<out>/fem/`, a side-by-side table
//! (`compare.csv`, `compare.md`: counts, contact force, onset, deflections, times; with
//! friction also the total tangential force, the stick and slip counts and the stick zone's
//! extent) and overlay plots of the contact pressure and of the displacement along the
//! profile edge (`plots/compare_pressure`, `plots/compare_deflection`, SVG and PNG; with
//! friction also `plots/compare_tangential_traction`).

use crate::error::Error;
use crate::post::summary::{ContactSummary, Summary};
use crate::post::{self, OutputError, plot};
use crate::problem::{Method, Problem};
use crate::progress::Progress;
use crate::solution::{ContactSolution, Solution};
use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One method's run.
#[derive(Debug)]
pub struct MethodRun {
    /// The method.
    pub method: Method,
    /// Its `summary.json`.
    pub summary: Summary,
    /// `(arc length, pressure)` along the contact edge (empty without contact).
    pub pressure: Vec<(f64, f64)>,
    /// `(arc length, displacement component)` along the profile edge.
    pub deflection: Vec<(f64, f64)>,
    /// Which displacement component `deflection` holds (`"u_x"` or `"u_y"`).
    pub component: &'static str,
    /// With friction: `(arc length, tangential traction)` along the contact edge.
    pub tangential: Vec<(f64, f64)>,
    /// With friction: the extent of the stick zone along the contact edge ([`stick_extent`]).
    pub stick_extent: Option<(f64, f64)>,
    /// The arc-length window the contact plots zoom to ([`post::zoom::contact_window`]; `None`:
    /// the whole edge, or no contact).
    pub contact_window: Option<(f64, f64)>,
}

/// The extent `(start, end)` along the contact edge (arc length) of the sticking candidates:
/// from the first to the last sticking candidate, each widened to mid-way to its neighbour
/// (so a zone is read to about ± half a candidate spacing per end; at an end of the edge the
/// candidate itself). `None` without friction or when nothing sticks. Several stick zones
/// give the span from the first zone's start to the last zone's end.
pub fn stick_extent(contact: &ContactSolution) -> Option<(f64, f64)> {
    let f = contact.friction.as_ref()?;
    let s = &contact.candidates.arc_length;
    let stick = |c: &usize| f.step.state[*c] == crate::lcp::ContactState::Stick;
    let first = (0..s.len()).find(stick)?;
    let last = (0..s.len()).rev().find(stick)?;
    let start = if first == 0 { s[0] } else { 0.5 * (s[first - 1] + s[first]) };
    let end = if last + 1 == s.len() { s[last] } else { 0.5 * (s[last] + s[last + 1]) };
    Some((start, end))
}

/// One row of the comparison table.
#[derive(Clone, Debug)]
pub struct Row {
    /// What is compared.
    pub quantity: String,
    /// MFVM value.
    pub mfvm: Option<f64>,
    /// FE value.
    pub fem: Option<f64>,
}

/// The comparison: both runs, the table and the files written.
#[derive(Debug)]
pub struct Comparison {
    /// MFVM run.
    pub mfvm: MethodRun,
    /// FE run.
    pub fem: MethodRun,
    /// The table.
    pub rows: Vec<Row>,
    /// Files written (both methods' outputs, the tables and the overlay plots).
    pub files: Vec<PathBuf>,
}

impl std::fmt::Display for Comparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", markdown(&self.rows))?;
        write!(f, "wrote {} files", self.files.len())
    }
}

/// A copy of `problem` (and its second body) discretised by `method` (the finite elements on
/// their uniform mesh: without `[refinement]`'s loop, as without `[[nodes.refine]]`).
fn with_method(problem: &Problem, method: Method) -> Problem {
    let mut p = problem.clone();
    let fem = method == Method::Fem;
    if fem {
        p.adaptive = None;
    }
    // The MFVM's `[[nodes.refine]]` regions would grade the FE's grid (`fem::Mesh::graded`).
    for k in 0..p.body_count() {
        if let Some(body) = p.body_mut(k) {
            body.discretisation.method = method;
            if fem {
                body.refinement = Default::default();
            }
        }
    }
    p
}

fn run_one(
    problem: &Problem,
    dir: &Path,
    input: &Value,
    progress: &mut dyn Progress,
) -> Result<(MethodRun, Vec<PathBuf>), Error> {
    let (model, solution, report) = super::solve_and_write(problem, dir, input.clone(), progress)?;
    let (deflection, component) = profile(problem, &model.nodes, &solution);
    let pressure = solution
        .contact()
        .map(|c| c.candidates.arc_length.iter().copied().zip(c.pressure.iter().copied()).collect())
        .unwrap_or_default();
    let tangential = solution
        .contact()
        .and_then(|c| {
            let f = c.friction.as_ref()?;
            Some(c.candidates.arc_length.iter().copied().zip(f.traction.iter().copied()).collect())
        })
        .unwrap_or_default();
    let run = MethodRun {
        method: problem.discretisation.method,
        summary: report.summary,
        pressure,
        deflection,
        component,
        tangential,
        stick_extent: solution.contact().and_then(stick_extent),
        contact_window: solution
            .contact()
            .and_then(|c| post::zoom::contact_window(&c.candidates.arc_length, &c.closed)),
    };
    Ok((run, report.files))
}

/// The displacement component with the larger range along the profile edge, sorted by arc
/// length.
fn profile(
    problem: &Problem,
    nodes: &crate::nodes::Nodes,
    solution: &Solution,
) -> (Vec<(f64, f64)>, &'static str) {
    let k = problem.profile_edge;
    let (a, b) = problem.domain.edge(k);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let mut on_edge: Vec<(f64, usize)> = (0..nodes.len())
        .filter(|&i| nodes.edges[i].contains(k))
        .map(|i| (problem.domain.edge_parameter(k, nodes.points[i]) * len, i))
        .collect();
    on_edge.sort_by(|p, q| p.0.total_cmp(&q.0));
    let size = |axis: usize| {
        on_edge.iter().map(|&(_, i)| solution.displacement[i][axis].abs()).fold(0.0, f64::max)
    };
    let axis = if size(1) >= size(0) { 1 } else { 0 };
    (
        on_edge.iter().map(|&(s, i)| (s, solution.displacement[i][axis])).collect(),
        if axis == 1 { "u_y" } else { "u_x" },
    )
}

/// Runs both methods on `problem` and writes everything into `out` (`input` is echoed into
/// each `summary.json`).
///
/// # Errors
/// Any stage's error of either method (e.g. a problem the FE cannot mesh), or an output error.
pub fn compare(
    problem: &Problem,
    out: &Path,
    input: Value,
    progress: &mut dyn Progress,
) -> Result<Comparison, Error> {
    // Both methods must accept the problem before either is solved.
    let fem_problem = with_method(problem, Method::Fem);
    for body in fem_problem.bodies() {
        crate::fem::mesh(body)?;
    }
    let staged = post::StagedDir::new(out)?;
    let out = staged.path();
    progress.section("MFVM");
    let (mfvm, mut files) =
        run_one(&with_method(problem, Method::Mfvm), &out.join("mfvm"), &input, progress)?;
    progress.section("finite elements (Q2)");
    let (fem, more) =
        run_one(&with_method(problem, Method::Fem), &out.join("fem"), &input, progress)?;
    files.extend(more);
    let rows = table(&mfvm, &fem);
    let mut csv = String::from("quantity,mfvm,fem,difference\n");
    for r in &rows {
        let cell = |v: Option<f64>| v.map(format_value).unwrap_or_default();
        let diff = r.mfvm.zip(r.fem).map(|(a, b)| b - a);
        let _ = writeln!(csv, "{},{},{},{}", r.quantity, cell(r.mfvm), cell(r.fem), cell(diff));
    }
    for (name, text) in [("compare.csv", csv), ("compare.md", markdown(&rows))] {
        let path = out.join(name);
        post::write_text(&path, &text)?;
        files.push(path);
    }
    files.extend(overlay_plots(problem, out, &mfvm, &fem)?);
    let files = staged.commit(files)?;
    Ok(Comparison { mfvm, fem, rows, files })
}

fn table(mfvm: &MethodRun, fem: &MethodRun) -> Vec<Row> {
    let extreme = |run: &MethodRun| {
        run.deflection.iter().map(|p| p.1).fold(None, |m: Option<f64>, v| {
            Some(m.map_or(v, |m| if v.abs() > m.abs() { v } else { m }))
        })
    };
    let contact = |run: &MethodRun, f: &dyn Fn(&ContactSummary) -> Option<f64>| {
        run.summary.contact.as_ref().and_then(f)
    };
    let mut rows = Vec::new();
    let mut push = |quantity: &str, f: &dyn Fn(&MethodRun) -> Option<f64>| {
        rows.push(Row { quantity: quantity.into(), mfvm: f(mfvm), fem: f(fem) });
    };
    push("nodes", &|r| Some(r.summary.counts.nodes as f64));
    push("dofs", &|r| Some(r.summary.counts.dofs as f64));
    push("matrix_nonzeros", &|r| Some(r.summary.counts.matrix_nonzeros as f64));
    push("max_displacement", &|r| Some(r.summary.results.max_displacement));
    push(&format!("largest_{}_on_profile_edge", mfvm.component), &extreme);
    if mfvm.summary.contact.is_some() {
        push("contact_candidates", &|r| contact(r, &|c| Some(c.candidates as f64)));
        push("closed_candidates", &|r| contact(r, &|c| Some(c.closed as f64)));
        push("total_contact_force", &|r| contact(r, &|c| Some(c.total_force)));
        push("onset_l_c", &|r| contact(r, &|c| c.onset_x));
        push("onset_l_c_unclipped", &|r| contact(r, &|c| c.onset_x_unclipped));
        push("max_contact_pressure", &|r| r.pressure.iter().map(|p| p.1).reduce(f64::max));
        push("lemke_pivots", &|r| r.summary.lcp.as_ref().map(|l| l.pivots as f64));
    }
    if mfvm.summary.contact.as_ref().is_some_and(|c| c.friction_coefficient.is_some()) {
        let counts =
            |r: &MethodRun, k: usize| contact(r, &|c| c.stick_slip_counts.map(|n| n[k] as f64));
        push("total_tangential_force", &|r| contact(r, &|c| c.total_tangential_force));
        push("stick_candidates", &|r| counts(r, 0));
        push("slip_candidates", &|r| counts(r, 1));
        push("stick_zones", &|r| contact(r, &|c| c.stick_slip_zone_counts.map(|n| n[0] as f64)));
        push("stick_zone_start", &|r| r.stick_extent.map(|e| e.0));
        push("stick_zone_end", &|r| r.stick_extent.map(|e| e.1));
        push("max_tangential_traction", &|r| {
            r.tangential.iter().map(|p| p.1.abs()).reduce(f64::max)
        });
    }
    push("equilibrium_error", &|r| Some(r.summary.checks.equilibrium_error));
    push("total_seconds", &|r| Some(r.summary.total_seconds()));
    rows
}

/// Counts as integers, everything else with 9 significant digits.
fn format_value(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 { format!("{v:.0}") } else { format!("{v:.8e}") }
}

fn markdown(rows: &[Row]) -> String {
    let cell = |v: Option<f64>| v.map(format_value).unwrap_or_else(|| "–".into());
    let mut s = String::from("| quantity | MFVM | FE | FE − MFVM |\n|---|---|---|---|\n");
    for r in rows {
        let diff = r.mfvm.zip(r.fem).map(|(a, b)| b - a);
        let _ =
            writeln!(s, "| {} | {} | {} | {} |", r.quantity, cell(r.mfvm), cell(r.fem), cell(diff));
    }
    s
}

fn overlay_plots(
    problem: &Problem,
    out: &Path,
    mfvm: &MethodRun,
    fem: &MethodRun,
) -> Result<Vec<PathBuf>, OutputError> {
    let plots = out.join("plots");
    post::create_dir(&plots)?;
    let names = problem.domain.edge_names();
    let series = |label: &str, points: &[(f64, f64)], style, colour| plot::Series {
        label: label.into(),
        points: points.to_vec(),
        style,
        colour,
    };
    let mut charts = Vec::new();
    // The contact plots zoom to the window covering both methods' zones; the whole edge
    // when either shows it whole.
    let window = match (mfvm.contact_window, fem.contact_window) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        _ => None,
    };
    let profile = &names[problem.profile_edge];
    charts.push((
        "compare_deflection",
        None,
        plot::Chart {
            title: format!(
                "{}: {} along edge {profile}, MFVM and FE",
                problem.name, mfvm.component
            ),
            x_label: format!("distance along edge {profile}"),
            y_label: mfvm.component.into(),
            series: vec![
                series("MFVM", &mfvm.deflection, plot::Style::Line, 1),
                series("FE (Q2)", &fem.deflection, plot::Style::Dashed, 4),
            ],
        },
    ));
    if let Some(spec) = problem.contact() {
        let edge = &names[spec.edge];
        charts.push((
            "compare_pressure",
            window,
            plot::Chart {
                title: format!("{}: contact pressure along edge {edge}, MFVM and FE", problem.name),
                x_label: format!("distance along edge {edge}"),
                y_label: "pressure".into(),
                series: vec![
                    series("MFVM: P_c / |segment|", &mfvm.pressure, plot::Style::Line, 1),
                    series("FE: P_c / tributary length", &fem.pressure, plot::Style::Dashed, 4),
                ],
            },
        ));
        if !mfvm.tangential.is_empty() {
            charts.push((
                "compare_tangential_traction",
                window,
                plot::Chart {
                    title: format!(
                        "{}: tangential traction along edge {edge}, MFVM and FE",
                        problem.name
                    ),
                    x_label: format!("distance along edge {edge}"),
                    y_label: "tangential traction".into(),
                    series: vec![
                        series("MFVM: T_c / |segment|", &mfvm.tangential, plot::Style::Line, 1),
                        series(
                            "FE: T_c / tributary length",
                            &fem.tangential,
                            plot::Style::Dashed,
                            4,
                        ),
                    ],
                },
            ));
        }
    }
    let mut files = Vec::new();
    for (name, zoom, chart) in charts {
        let stem = plots.join(name);
        plot::write_zoomed_chart(&stem, &chart, zoom)?;
        files.push(stem.with_extension("svg"));
        files.push(stem.with_extension("png"));
    }
    Ok(files)
}
