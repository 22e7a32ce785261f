//! Stage 11: outputs — CSV tables, VTK files for ParaView (each body's `solution.vtu`, the
//! contact edges and obstacles, `solution.vtm` opening them all), plots and `summary.json`.
//!
//! Every file is deterministic (fixed float formatting, sorted keys) except the `timings`
//! field of `summary.json`.

pub mod console;
mod deformed;
pub mod frames;
pub mod history;
pub mod load_history;
mod outdir;
pub mod paraview;
pub mod plot;
pub mod report;
pub mod resolution;
mod revolve;
pub mod summary;
mod vtk;
pub mod zoom;

pub use outdir::{MANIFEST, StagedDir, abandon_staging};
pub use paraview::write_paraview;
pub use summary::Summary;

use crate::geometry::Domain;
use crate::model::Model;
use crate::nodes::Axis;
use crate::problem::{ContactTarget, Problem, RigidLine};
use crate::solution::{ContactSolution, Solution};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Failures while writing outputs.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// File-system error.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// The output directory exists, is not empty and holds no earlier run of this program: it
    /// is not replaced.
    #[error(
        "the output directory {path} exists and holds something other than an mlpg-contact run; choose another --out or empty it"
    )]
    NotAnOutputDirectory {
        /// The directory.
        path: String,
    },
    /// The output path is a file, or a symbolic link to nothing.
    #[error(
        "the output path {path} is not a directory (a file, or a symbolic link to nothing); choose another --out or create the directory the link names"
    )]
    NotADirectory {
        /// The path.
        path: String,
    },
    /// A file the earlier run did not write (or a directory, or a link) has the path of an
    /// output of this run: nothing is moved, the directory stays as it was.
    #[error(
        "{path} is in the way of an output of this run and was not written by an earlier run; move it away or choose another --out (nothing was changed)"
    )]
    InTheWay {
        /// The path.
        path: String,
    },
    /// The MLS field could not be evaluated at a point of the VTU file.
    #[error("cannot evaluate the MLS field for solution.vtu: {reason}")]
    Field {
        /// The cause.
        reason: String,
    },
    /// Plotting failed.
    #[error("cannot draw plot {path}: {reason}")]
    Plot {
        /// The path.
        path: String,
        /// The cause.
        reason: String,
    },
}

/// Maps an I/O failure on `path` to [`OutputError::Io`].
fn io(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError {
    let path = path.display().to_string();
    move |source| OutputError::Io { path, source }
}

/// Writes `text` to `path`.
///
/// # Errors
/// [`OutputError::Io`].
pub fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    std::fs::write(path, text).map_err(io(path))
}

/// Creates the output directory (and parents).
///
/// # Errors
/// [`OutputError::Io`].
pub fn create_dir(dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(io(dir))
}

/// Formats a float for CSV/JSON-like text: 12 significant digits, scientific (`{:.11e}`).
/// Written straight into the text it is formatted into, without a `String` of its own
/// (millions of numbers in a large body's outputs; `num(v).to_string()` gives the text).
pub fn num(v: f64) -> Num {
    Num(v)
}

/// A float displayed as [`num`] formats it.
#[derive(Clone, Copy, Debug)]
pub struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:.11e}", self.0)
    }
}

/// The files written for an elastostatic solution (`second`: the second body's model of a
/// two-body contact, drawn with the first in the deformed plot).
pub fn write_solution(
    dir: &Path,
    problem: &Problem,
    model: &Model,
    second: Option<&Model>,
    solution: &Solution,
) -> Result<Vec<PathBuf>, OutputError> {
    write_body(dir, problem, model, second, solution, &[])
}

/// Another body drawn in the deformed plot: its problem, model and solution.
type Drawn<'a> = (&'a Problem, &'a Model, &'a Solution);

/// [`write_solution`], with `others` drawn in the deformed plot too.
fn write_body(
    dir: &Path,
    problem: &Problem,
    model: &Model,
    second: Option<&Model>,
    solution: &Solution,
    others: &[Drawn<'_>],
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    // Three independent groups of files, written side by side (a large body's text
    // formatting is seconds of one core); listed in the same order as written one after the
    // other: the tables, the VTU grid, the plots and contact files.
    let tables = || -> Result<Vec<PathBuf>, OutputError> {
        let mut written = Vec::new();
        let nodes = &model.nodes;
        let names = problem.domain.edge_names();
        let [x, y] = coordinate_names(problem);

        let mut text = format!("node,{x},{y},edges,spacing\n");
        for (i, p) in nodes.points.iter().enumerate() {
            let edges: Vec<&str> = nodes.edges[i].iter().map(|k| names[k].as_str()).collect();
            let _ = writeln!(
                text,
                "{i},{},{},{},{}",
                num(p[0]),
                num(p[1]),
                edges.join("|"),
                num(nodes.spacing[i])
            );
        }
        written.push(save(dir, "nodes.csv", &text)?);

        let mut text = format!("node,{x},{y},u{x},u{y}\n");
        for (i, p) in nodes.points.iter().enumerate() {
            let u = solution.displacement[i];
            let _ = writeln!(text, "{i},{},{},{},{}", num(p[0]), num(p[1]), num(u[0]), num(u[1]));
        }
        written.push(save(dir, "displacement.csv", &text)?);

        let mut text = format!("node,{x},{y},s{x}{x},s{y}{y},s{x}{y},von_mises\n");
        let von_mises = solution.von_mises(&problem.material);
        for (i, p) in nodes.points.iter().enumerate() {
            let s = solution.stress[i];
            let vm = von_mises[i];
            let _ = writeln!(
                text,
                "{i},{},{},{},{},{},{}",
                num(p[0]),
                num(p[1]),
                num(s[0]),
                num(s[1]),
                num(s[2]),
                num(vm)
            );
        }
        written.push(save(dir, "stress.csv", &text)?);

        if !solution.hoop.is_empty() {
            // Axisymmetric bodies only (x = r, y = z; docs/method.md §9.2).
            let mut text = String::from("node,r,z,e_thth,s_thth\n");
            for (i, (p, h)) in nodes.points.iter().zip(&solution.hoop).enumerate() {
                let _ =
                    writeln!(text, "{i},{},{},{},{}", num(p[0]), num(p[1]), num(h[0]), num(h[1]));
            }
            written.push(save(dir, "hoop.csv", &text)?);
        }

        let mut text = format!("node,axis,{x},{y},reaction\n");
        for &(node, axis, r) in &solution.reactions {
            let p = nodes.points[node as usize];
            let a = if axis == Axis::X { x } else { y };
            let _ = writeln!(text, "{node},{a},{},{},{}", num(p[0]), num(p[1]), num(r));
        }
        written.push(save(dir, "reactions.csv", &text)?);
        Ok(written)
    };
    let grid = || -> Result<Vec<PathBuf>, OutputError> {
        let grid = vtk::solution_grid(problem, model, solution)?;
        let mut written = vec![save(dir, "solution.vtu", &grid.to_vtu())?];
        if let Some(r) = &problem.revolve {
            written.push(save(dir, "solution_revolved.vtu", &revolve::revolved_vtu(&grid, r))?);
        }
        Ok(written)
    };
    let plots = || -> Result<Vec<PathBuf>, OutputError> {
        let mut written = solution_plots(dir, problem, model, second, solution, others)?;
        if let Some(c) = solution.contact() {
            written.extend(contact_outputs(dir, problem, solution, c)?);
        }
        Ok(written)
    };
    let (tables, (grid, plots)) = rayon::join(tables, || rayon::join(grid, plots));
    let mut written = tables?;
    written.extend(grid?);
    written.extend(plots?);
    Ok(written)
}

/// The text of `contact.csv`: one row per candidate (with the friction columns when the
/// contact has friction); `x, y` the names of the coordinates ([`coordinate_names`]).
fn contact_table(c: &ContactSolution, [x, y]: [&str; 2]) -> String {
    let cand = &c.candidates;
    let mut text =
        format!("candidate,node,{x},{y},arc_length,initial_gap,gap,force,pressure,in_contact");
    // Friction columns only with friction, so that frictionless files are unchanged.
    if c.friction.is_some() {
        text.push_str(",tangential_force,tangential_traction,slip,state");
    }
    text.push('\n');
    for k in 0..cand.len() {
        let p = cand.points[k];
        let _ = write!(
            text,
            "{k},{},{},{},{},{},{},{},{},{}",
            cand.nodes[k],
            num(p[0]),
            num(p[1]),
            num(cand.arc_length[k]),
            num(cand.initial_gap[k]),
            num(c.gap[k]),
            num(c.lcp.z[k]),
            num(c.pressure[k]),
            u8::from(c.closed[k])
        );
        if let Some(f) = &c.friction {
            let _ = write!(
                text,
                ",{},{},{},{}",
                num(f.step.tangential[k]),
                num(f.traction[k]),
                num(f.slip[k]),
                f.step.state[k].label()
            );
        }
        text.push('\n');
    }
    text
}

/// The files of a problem with several bodies or contact pairs (`Problem::multibody`): the
/// first body's files in `dir` (its deformed plot draws every body), each other body's in
/// `dir/<name>/` (as the second body's of a two-body contact), and per pair `k` (the `k`-th
/// `[[contact]]` table, from 0) `contact_<k>.csv` (the columns of `contact.csv`) and
/// `plots/contact_pressure_<k>.{svg,png}`. Without `multibody`, [`write_solution`].
///
/// # Errors
/// [`OutputError`] when a file cannot be written.
pub fn write_multibody(
    dir: &Path,
    problem: &Problem,
    model: &Model,
    others: &[Model],
    solution: &Solution,
) -> Result<Vec<PathBuf>, OutputError> {
    let (Some(several), Some(ms)) = (problem.multibody(), solution.multibody()) else {
        return write_solution(dir, problem, model, None, solution);
    };
    let drawn: Vec<Drawn<'_>> =
        several.bodies.iter().zip(others).zip(ms.bodies).map(|((p, m), s)| (p, m, s)).collect();
    let mut written = write_body(dir, problem, model, None, solution, &drawn)?;
    for &(p, m, s) in &drawn {
        written.extend(write_solution(&dir.join(&p.name), p, m, None, s)?);
    }
    let plots = dir.join("plots");
    create_dir(&plots)?;
    for (k, (pair, c)) in several.pairs.iter().zip(ms.pairs).enumerate() {
        let body = problem.body(pair.body).unwrap_or(problem);
        let table = contact_table(c, coordinate_names(body));
        written.push(save(dir, &format!("contact_{k}.csv"), &table)?);
        let edge = &body.domain.edge_names()[pair.spec.edge];
        let target = match (pair.target_body.and_then(|t| problem.body(t)), pair.spec.target) {
            (Some(t), ContactTarget::Body { edge: e2 }) => {
                format!("edge {} of {}", t.domain.edge_names()[e2], t.name)
            }
            _ => "the obstacle".to_string(),
        };
        let cand = &c.candidates;
        let chart = plot::Chart {
            title: format!(
                "{}: contact pressure along edge {edge} of {} against {target}",
                problem.name, body.name
            ),
            x_label: along_label(problem, edge),
            y_label: pressure_label(problem),
            series: vec![plot::Series {
                label: "p = P_c/|segment|".into(),
                points: (0..cand.len()).map(|i| (cand.arc_length[i], c.pressure[i])).collect(),
                style: plot::Style::Line,
                colour: 4,
            }],
        };
        let stem = plots.join(format!("contact_pressure_{k}"));
        let window = zoom::contact_window(&cand.arc_length, &c.closed);
        written.extend(plot::write_zoomed_chart(&stem, &chart, window)?);
    }
    let histories: Vec<load_history::PairHistory<'_>> = several
        .pairs
        .iter()
        .zip(ms.pairs)
        .enumerate()
        .filter_map(|(k, (pair, c))| {
            let body = problem.body(pair.body).unwrap_or(problem);
            let edge = &body.domain.edge_names()[pair.spec.edge];
            c.friction.as_ref().map(|f| load_history::PairHistory {
                index: k,
                label: format!("contact[{k}] {}.{edge}", body.name),
                records: &f.increments,
            })
        })
        .collect();
    written.extend(load_history::write(dir, &problem.name, &histories)?);
    Ok(written)
}

/// `contact.csv` and the two contact plots (the paper's Figs. 2 and 3).
fn contact_outputs(
    dir: &Path,
    problem: &Problem,
    solution: &Solution,
    c: &ContactSolution,
) -> Result<Vec<PathBuf>, OutputError> {
    let cand = &c.candidates;
    let text = contact_table(c, coordinate_names(problem));
    let mut written = vec![save(dir, "contact.csv", &text)?];
    if let Some(f) = c.friction.as_ref().filter(|f| !f.snapshots.is_empty()) {
        written.extend(increment_tables(dir, c, f, coordinate_names(problem))?);
    }
    if let Some(f) = &c.friction {
        let pairs = [load_history::PairHistory {
            index: 0,
            label: "contact".into(),
            records: &f.increments,
        }];
        written.extend(load_history::write(dir, &problem.name, &pairs)?);
    }
    let plots = dir.join("plots");
    create_dir(&plots)?;
    let edge = &problem.domain.edge_names()[problem.contact().map_or(0, |s| s.edge)];
    let window = zoom::contact_window(&cand.arc_length, &c.closed);
    // Deflection of the contact edge along each candidate's normal, and the obstacle at −g0.
    let deflection: Vec<(f64, f64)> = (0..cand.len())
        .map(|k| {
            let nu = cand.normal(k);
            let u = solution.displacement[cand.nodes[k] as usize];
            (cand.arc_length[k], nu[0] * u[0] + nu[1] * u[1])
        })
        .collect();
    // The target in the same coordinate: contact where ν·u_1 = −g0 (a rigid obstacle) or
    // −g0 + ν·u_2^h(y_c) (a second body, whose displacement at the paired points moves it).
    let second = problem.second_body().zip(solution.second_body());
    let target_motion = match (second, &c.target) {
        (Some((_, s2)), Some(op)) if op.len() == cand.len() => {
            op.gap_contribution(&s2.nodal_parameters)
        }
        _ => vec![0.0; cand.len()],
    };
    let obstacle: Vec<(f64, f64)> = (0..cand.len())
        .map(|k| (cand.arc_length[k], -cand.initial_gap[k] - target_motion[k]))
        .collect();
    let (target_label, target_title) = match (problem.contact().map(|s| s.target), second) {
        (Some(ContactTarget::Body { edge: e2 }), Some((p2, _))) => {
            let edge2 = &p2.domain.edge_names()[e2];
            (format!("body {}, edge {edge2}: ν·u^h − g0", p2.name), format!("body {}", p2.name))
        }
        _ => ("rigid obstacle: −g0".to_string(), "the obstacle".to_string()),
    };
    let chart = plot::Chart {
        title: format!("{}: displacement of edge {edge} towards {target_title}", problem.name),
        x_label: along_label(problem, edge),
        y_label: format!("normal displacement ν·u^h ({})", length_unit(problem)),
        series: vec![
            plot::Series {
                label: format!("edge {edge}: ν·u^h ({})", method_label(problem)),
                points: deflection,
                style: plot::Style::Line,
                colour: 1,
            },
            plot::Series {
                label: target_label,
                points: obstacle,
                style: plot::Style::Reference,
                colour: 0,
            },
        ],
    };
    let stem = plots.join("contact_deflection");
    written.extend(plot::write_zoomed_chart(&stem, &chart, window)?);
    let pressure: Vec<(f64, f64)> =
        (0..cand.len()).map(|k| (cand.arc_length[k], c.pressure[k])).collect();
    // An axisymmetric body's candidates are rings (`contact::rings`).
    let label = match problem.material.is_axisymmetric() {
        true => "p = F_c/(ring area), F_c the ring's total force",
        false => "p = P_c/|segment|",
    };
    let mut series = vec![plot::Series {
        label: label.into(),
        points: pressure,
        style: plot::Style::Line,
        colour: 4,
    }];
    if let Some(lc) = zoom::marked_onset(c) {
        let top = c.pressure.iter().copied().fold(0.0, f64::max);
        series.push(plot::Series {
            label: format!("onset l_c = {lc:.4}"),
            points: vec![(lc, 0.0), (lc, top)],
            style: plot::Style::Dashed,
            colour: 0,
        });
    }
    let chart = plot::Chart {
        title: format!("{}: contact pressure along edge {edge}", problem.name),
        x_label: along_label(problem, edge),
        y_label: pressure_label(problem),
        series,
    };
    let stem = plots.join("contact_pressure");
    written.extend(plot::write_zoomed_chart(&stem, &chart, window)?);
    if let Some(f) = &c.friction {
        let stem = plots.join("contact_traction");
        let chart = traction_chart(problem, c, f, edge);
        written.extend(plot::write_zoomed_chart(&stem, &chart, window)?);
    }
    Ok(written)
}

/// `steps/contact_s<step>_i<increment>.csv`, one per load increment (`[output] steps`): the
/// columns of `contact.csv` at the end of that increment but `initial_gap` (`gap` is the step
/// problem's gap; `in_contact`: not open), and `steps/index.csv` (step, increment, load
/// factor, total normal and tangential force, file).
fn increment_tables(
    dir: &Path,
    c: &ContactSolution,
    f: &crate::solution::FrictionContact,
    [x, y]: [&str; 2],
) -> Result<Vec<PathBuf>, OutputError> {
    let steps = dir.join("steps");
    create_dir(&steps)?;
    let cand = &c.candidates;
    let mut written = Vec::new();
    let mut index = String::from("step,increment,load_factor,normal_force,tangential_force,file\n");
    for snap in &f.snapshots {
        let name = format!("contact_s{:03}_i{:04}.csv", snap.step, snap.increment);
        let mut text = format!(
            "candidate,node,{x},{y},arc_length,gap,force,pressure,in_contact,tangential_force,tangential_traction,slip,state\n",
        );
        for k in 0..cand.len() {
            let p = cand.points[k];
            let l = cand.segment_length[k];
            let _ = writeln!(
                text,
                "{k},{},{},{},{},{},{},{},{},{},{},{},{}",
                cand.nodes[k],
                num(p[0]),
                num(p[1]),
                num(cand.arc_length[k]),
                num(snap.gap[k]),
                num(snap.normal[k]),
                num(snap.normal[k] / l),
                u8::from(snap.state[k] != crate::lcp::ContactState::Open),
                num(snap.tangential[k]),
                num(snap.tangential[k] / l),
                num(snap.slip[k]),
                snap.state[k].label()
            );
        }
        written.push(save(&steps, &name, &text)?);
        let _ = writeln!(
            index,
            "{},{},{},{},{},{name}",
            snap.step,
            snap.increment,
            num(snap.load_factor),
            num(snap.normal.iter().sum()),
            num(snap.tangential.iter().sum())
        );
    }
    written.push(save(&steps, "index.csv", &index)?);
    Ok(written)
}

/// With friction: the pressure `p` and the tangential traction `q` along the contact edge,
/// the Coulomb limits `±μp`, and the stick zones shaded (after Johnson, *Contact Mechanics*,
/// Fig. 7.7). A stick zone spans its sticking candidates and half the way to each neighbour.
fn traction_chart(
    problem: &Problem,
    c: &ContactSolution,
    f: &crate::solution::FrictionContact,
    edge: &str,
) -> plot::Chart {
    let s = &c.candidates.arc_length;
    let mu = f.coefficient;
    let along =
        |v: &[f64]| -> Vec<(f64, f64)> { s.iter().copied().zip(v.iter().copied()).collect() };
    let limit = |sign: f64| c.pressure.iter().map(|p| sign * mu * p).collect::<Vec<f64>>();
    let mut bands = Vec::new();
    let stick = |k: usize| f.step.state[k] == crate::lcp::ContactState::Stick && c.closed[k];
    let m = s.len();
    let mut k = 0;
    while k < m {
        if !stick(k) {
            k += 1;
            continue;
        }
        let first = k;
        while k + 1 < m && stick(k + 1) {
            k += 1;
        }
        let start = if first > 0 { 0.5 * (s[first - 1] + s[first]) } else { s[first] };
        let end = if k + 1 < m { 0.5 * (s[k] + s[k + 1]) } else { s[k] };
        bands.extend([(start, 0.0), (end, 0.0)]);
        k += 1;
    }
    let mut series = vec![
        plot::Series {
            label: "stick zone".into(),
            points: bands,
            style: plot::Style::Bands,
            colour: 2,
        },
        plot::Series {
            label: "pressure p".into(),
            points: along(&c.pressure),
            style: plot::Style::Line,
            colour: 4,
        },
        plot::Series {
            label: "tangential traction q".into(),
            points: along(&f.traction),
            style: plot::Style::Line,
            colour: 1,
        },
        plot::Series {
            label: format!("±μp (μ = {mu})"),
            points: along(&limit(1.0)),
            style: plot::Style::Dashed,
            colour: 0,
        },
    ];
    series.push(plot::Series {
        label: String::new(),
        points: along(&limit(-1.0)),
        style: plot::Style::Dashed,
        colour: 0,
    });
    plot::Chart {
        title: format!("{}: contact tractions along edge {edge}, friction μ = {mu}", problem.name),
        x_label: along_label(problem, edge),
        y_label: format!("traction: p normal, q along t ({})", stress_unit(problem)),
        series,
    }
}

/// The y-axis label of the contact pressure plots.
fn pressure_label(problem: &Problem) -> String {
    format!("contact pressure p ({})", stress_unit(problem))
}

/// The unit of lengths in labels: `[output] units`' length, or the word "length".
fn length_unit(problem: &Problem) -> &str {
    problem.units.as_ref().map_or("length", |u| u.length.as_str())
}

/// The unit of stresses in labels: `[output] units`' stress, or "units of E".
fn stress_unit(problem: &Problem) -> &str {
    problem.units.as_ref().map_or("units of E", |u| u.stress.as_str())
}

/// The x-axis label of a plot along `edge`.
fn along_label(problem: &Problem, edge: &str) -> String {
    format!("s: distance along edge {edge} from its first vertex ({})", length_unit(problem))
}

/// The names of the two coordinates of `problem`'s body, for headers and labels: `x, y`, or
/// `r, z` for an axisymmetric body (x is the radius r, y the axis z; docs/method.md §9).
pub fn coordinate_names(problem: &Problem) -> [&'static str; 2] {
    if problem.material.is_axisymmetric() { ["r", "z"] } else { ["x", "y"] }
}

/// `"MFVM"` or `"FE"`, for labels.
pub fn method_label(problem: &Problem) -> &'static str {
    match problem.discretisation.method {
        crate::problem::Method::Mfvm => "MFVM",
        crate::problem::Method::Fem => "FE",
    }
}

fn save(dir: &Path, name: &str, text: &str) -> Result<PathBuf, OutputError> {
    let path = dir.join(name);
    write_text(&path, text)?;
    Ok(path)
}

/// Deformed shape coloured by von Mises stress, and the displacement profile along an edge.
fn solution_plots(
    dir: &Path,
    problem: &Problem,
    model: &Model,
    second: Option<&Model>,
    solution: &Solution,
    others: &[Drawn<'_>],
) -> Result<Vec<PathBuf>, OutputError> {
    let plots = dir.join("plots");
    create_dir(&plots)?;
    let deformed = plots.join("deformed");
    plot::write_cell_map(&deformed, &deformed_map(problem, model, second, solution, others))?;
    let profile = plots.join("profile");
    plot::write_chart(&profile, &profile_chart(problem, model, solution))?;
    Ok(vec![
        deformed.with_extension("svg"),
        deformed.with_extension("png"),
        profile.with_extension("svg"),
        profile.with_extension("png"),
    ])
}

/// The magnification of the deformed plot: the largest displacement of any body drawn at a
/// tenth of the size of the bodies' bounding box (1 without displacement).
fn magnification(problem: &Problem, solution: &Solution, others: &[Drawn<'_>]) -> f64 {
    let (lo, hi) = others.iter().fold(problem.domain.bounding_box(), |(lo, hi), (p, _, _)| {
        let (a, b) = p.domain.bounding_box();
        ([lo[0].min(a[0]), lo[1].min(a[1])], [hi[0].max(b[0]), hi[1].max(b[1])])
    });
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let umax = std::iter::once(solution)
        .chain(others.iter().map(|o| o.2))
        .flat_map(|s| s.displacement.iter())
        .map(|u| u[0].hypot(u[1]))
        .fold(0.0, f64::max);
    if umax > 0.0 { 0.1 * size / umax } else { 1.0 }
}

/// The nodes of a body at their deformed positions, magnified `m` times.
fn deformed_nodes(model: &Model, solution: &Solution, m: f64) -> Vec<(f64, f64)> {
    let points = model.nodes.points.iter().zip(&solution.displacement);
    points.map(|(p, u)| (p[0] + m * u[0], p[1] + m * u[1])).collect()
}

/// Another body of the deformed plot: its cells, its name at its centre and its undeformed
/// outline (unlabelled).
fn add_body(map: &mut plot::CellMap, (p, model, s): Drawn<'_>, m: f64) {
    map.cells.extend(deformed::body_cells(p, model, s, m));
    map.labels.push(body_label(&p.name, &deformed_nodes(model, s, m)));
    let h = model.nodes.spacing.iter().copied().fold(f64::INFINITY, f64::min);
    let mut o = outline(&p.domain, h, "");
    o.label = None;
    map.lines.push(o);
}

/// The deformed plot: every body's cells on one scale and magnification, the undeformed
/// outlines, and the rigid obstacle(s) with their gaps magnified like the displacement.
fn deformed_map(
    problem: &Problem,
    model: &Model,
    second: Option<&Model>,
    solution: &Solution,
    others: &[Drawn<'_>],
) -> plot::CellMap {
    let m = magnification(problem, solution, others);
    let points = deformed_nodes(model, solution, m);
    let [x, y] = coordinate_names(problem);
    let min_spacing = model.nodes.spacing.iter().copied().fold(f64::INFINITY, f64::min);
    let mut map = plot::CellMap {
        title: format!(
            "{}: deformed shape (displacement ×{}), von Mises stress",
            problem.name,
            significant(m)
        ),
        value_label: format!("σ_vM ({})", stress_unit(problem)),
        x_label: format!("{x} + m·u_{x}"),
        y_label: format!("{y} + m·u_{y}"),
        cells: deformed::body_cells(problem, model, solution, m),
        lines: vec![outline(&problem.domain, min_spacing, "undeformed outline")],
        labels: Vec::new(),
    };
    map.lines.extend(hole_outlines(&problem.domain, min_spacing));
    match (problem.contact().map(|s| s.target), solution.contact()) {
        (Some(ContactTarget::Rigid(line)), Some(c)) => {
            map.lines.push(obstacle_line(&line, c, m, &points));
        }
        (Some(ContactTarget::Obstacles), Some(c)) => {
            map.lines.extend(obstacle_shapes(problem, c, m, &points));
        }
        (Some(ContactTarget::Body { .. }), _) => {
            let p2 = problem.second_body();
            if let (Some(p2), Some(s2), Some(m2)) = (p2, solution.second_body(), second) {
                map.labels.push(body_label(&problem.name, &points));
                add_body(&mut map, (p2, m2, s2), m);
            }
        }
        _ => {}
    }
    if !others.is_empty() {
        map.labels.push(body_label(&problem.name, &points));
    }
    for &other in others {
        add_body(&mut map, other, m);
    }
    map
}

/// `u_x` and `u_y` along the edge `[output] profile_edge`.
fn profile_chart(problem: &Problem, model: &Model, solution: &Solution) -> plot::Chart {
    let nodes = &model.nodes;
    let k = problem.profile_edge;
    let name = &problem.domain.edge_names()[k];
    let mut on_edge: Vec<(f64, usize)> = (0..nodes.len())
        .filter(|&i| nodes.edges[i].contains(k))
        .map(|i| (problem.domain.edge_parameter(k, nodes.points[i]), i))
        .collect();
    on_edge.sort_by(|a, b| a.0.total_cmp(&b.0));
    let len = problem.domain.curve(k).length();
    let [x, y] = coordinate_names(problem);
    let series = |axis: usize, label: &str, colour: usize| plot::Series {
        label: label.into(),
        points: on_edge.iter().map(|&(t, i)| (t * len, solution.displacement[i][axis])).collect(),
        style: plot::Style::Line,
        colour,
    };
    plot::Chart {
        title: format!("{}: displacement u^h along edge {name}", problem.name),
        x_label: along_label(problem, name),
        y_label: format!("displacement u^h ({})", length_unit(problem)),
        series: vec![series(0, &format!("u_{x}"), 0), series(1, &format!("u_{y}"), 1)],
    }
}

/// `plots/node_spacing.{svg,png}`: the nodes of an adaptively refined set coloured by
/// `log₂(h₀ / h_I)`, the number of halvings of the nominal spacing (docs/method.md §2.2).
///
/// # Errors
/// [`OutputError`] when the directory or a plot cannot be written.
pub fn write_node_spacing(
    dir: &Path,
    problem: &Problem,
    nodes: &crate::nodes::Nodes,
) -> Result<Vec<PathBuf>, OutputError> {
    let plots = dir.join("plots");
    create_dir(&plots)?;
    let min_spacing = nodes.spacing.iter().copied().fold(f64::INFINITY, f64::min);
    let h0 = problem.node_spacing;
    let mut map = plot::ColourMap {
        title: format!(
            "{}: {} nodes, spacing h₀ = {} to {}",
            problem.name,
            nodes.len(),
            significant(h0),
            significant(min_spacing)
        ),
        value_label: "log₂(h₀ / h_I)".into(),
        x_label: coordinate_names(problem)[0].into(),
        y_label: coordinate_names(problem)[1].into(),
        points: nodes.points.iter().map(|p| (p[0], p[1])).collect(),
        values: nodes.spacing.iter().map(|h| (h0 / h).log2()).collect(),
        lines: Vec::new(),
        labels: Vec::new(),
    };
    let mut edge = outline(&problem.domain, min_spacing, "");
    edge.label = None;
    map.lines.push(edge);
    map.lines.extend(hole_outlines(&problem.domain, min_spacing));
    let stem = plots.join("node_spacing");
    plot::write_colour_map(&stem, &map)?;
    Ok(vec![stem.with_extension("svg"), stem.with_extension("png")])
}

/// `v` with four significant digits, without an exponent when it is between 0.01 and 1e5.
fn significant(v: f64) -> String {
    if (1e-2..1e5).contains(&v.abs()) {
        let decimals = (3 - v.abs().log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// The undeformed boundary of `domain` as a closed thin grey polyline (arcs as chords of
/// length about `h / 2`).
fn outline(domain: &Domain, h: f64, label: &str) -> plot::Overlay {
    let (mut vertices, _) = domain.boundary_polygon(0.5 * h);
    if let Some(&first) = vertices.first() {
        vertices.push(first);
    }
    plot::Overlay {
        label: Some(label.to_string()),
        points: vertices.into_iter().map(|p| (p[0], p[1])).collect(),
        kind: plot::OverlayKind::Outline,
    }
}

/// The undeformed boundaries of `domain`'s holes, as [`outline`] draws the outer one
/// (unlabelled; none without holes).
fn hole_outlines(domain: &Domain, h: f64) -> Vec<plot::Overlay> {
    domain
        .boundary_rings(0.5 * h)
        .into_iter()
        .skip(1)
        .map(|(mut vertices, _)| {
            vertices.push(vertices[0]);
            plot::Overlay {
                label: None,
                points: vertices.into_iter().map(|p| (p[0], p[1])).collect(),
                kind: plot::OverlayKind::Outline,
            }
        })
        .collect()
}

/// The rigid obstacle line in a deformed plot magnified `m` times: its distance to the
/// undeformed body is magnified too (it is drawn `(m − 1) g_min` farther along `−n`, with
/// `g_min` the smallest initial gap), so that a candidate of gap `g_min` that closes touches
/// it; it spans the plot's extent along the line. On a curved edge the other closed candidates
/// appear `(m − 1) g₀` beyond the line, and the legend says so.
fn obstacle_line(
    line: &RigidLine,
    c: &ContactSolution,
    m: f64,
    points: &[(f64, f64)],
) -> plot::Overlay {
    let g_min = c.candidates.initial_gap.iter().copied().fold(f64::INFINITY, f64::min);
    let g_min = if g_min.is_finite() { g_min } else { 0.0 };
    let n = line.normal;
    let shift = (1.0 - m) * g_min;
    let origin = [line.point[0] + shift * n[0], line.point[1] + shift * n[1]];
    let t = [-n[1], n[0]];
    let along = |p: &(f64, f64)| (p.0 - origin[0]) * t[0] + (p.1 - origin[1]) * t[1];
    let (lo, hi) = plot::range(points.iter().map(along));
    let pad = 0.05 * (hi - lo);
    let at = |s: f64| (origin[0] + s * t[0], origin[1] + s * t[1]);
    // Where the closed candidates' initial gaps differ (a curved edge), no straight line can
    // be touched by all their magnified positions: they sit `(m − 1) g₀` beyond it. Say so
    // rather than draw a bent "rigid" line.
    let closed_gaps = || c.candidates.initial_gap.iter().zip(&c.closed).filter(|(_, k)| **k);
    let g_lo = closed_gaps().map(|(g, _)| *g).fold(f64::INFINITY, f64::min);
    let g_hi = closed_gaps().map(|(g, _)| *g).fold(f64::NEG_INFINITY, f64::max);
    // Gaps equal to round-off (a flat edge) do not count.
    let crossing = m > 1.0 && g_hi - g_lo > 1e-9 * g_hi.abs().max(g_lo.abs());
    let label = match (shift.abs() > 0.0, crossing) {
        (_, true) => format!(
            "rigid obstacle (u drawn ×{}: closed points cross the line by (m−1)·g₀)",
            significant(m)
        ),
        (true, false) => format!("rigid obstacle (gap drawn ×{} like u)", significant(m)),
        (false, false) => "rigid obstacle".to_string(),
    };
    plot::Overlay {
        label: Some(label),
        points: vec![at(lo - pad), at(hi + pad)],
        kind: plot::OverlayKind::Obstacle,
    }
}

/// The rigid obstacles of `problem` (`[[obstacle]]`) in a deformed plot magnified `m` times,
/// drawn as what they are (a circle, a polyline with its rounded corners, a line): each at its
/// final position (moved by the last step's obstacle displacement `d`, or by the one a force
/// found) and shifted by
/// `(1 − m) g′ ν` with `g′` and `ν` the final initial gap and normal of the candidate closest
/// to it, so that this candidate, once closed, touches it (as for the line). The drawing is
/// clipped to the body's plot window grown by half its size on each side.
fn obstacle_shapes(
    problem: &Problem,
    c: &ContactSolution,
    m: f64,
    points: &[(f64, f64)],
) -> Vec<plot::Overlay> {
    use crate::problem::Shape;
    let d = match &c.load_driven {
        Some(l) => l.displacement,
        None => problem.steps.last().map_or([0.0, 0.0], |s| s.obstacle_displacement),
    };
    let (xlo, xhi) = plot::range(points.iter().map(|p| p.0));
    let (ylo, yhi) = plot::range(points.iter().map(|p| p.1));
    let pad = 0.5 * (xhi - xlo).max(yhi - ylo);
    let inside = |p: &(f64, f64)| {
        p.0 >= xlo - pad && p.0 <= xhi + pad && p.1 >= ylo - pad && p.1 <= yhi + pad
    };
    let cand = &c.candidates;
    let mut out = Vec::new();
    for (k, o) in problem.obstacles().iter().enumerate() {
        // The candidate of this obstacle with the smallest gap.
        let closest = (0..cand.len())
            .filter(|&i| {
                crate::problem::closest_obstacle(problem.obstacles(), cand.points[i])
                    .is_some_and(|(j, _)| j == k)
            })
            .min_by(|&a, &b| cand.initial_gap[a].total_cmp(&cand.initial_gap[b]));
        let shift = closest.map_or([0.0, 0.0], |i| {
            let (g, nu) = (cand.initial_gap[i], cand.normal(i));
            [(1.0 - m) * g * nu[0], (1.0 - m) * g * nu[1]]
        });
        let shape = o.shape.translated([d[0] + shift[0], d[1] + shift[1]]);
        let outline: Vec<(f64, f64)> = match &shape {
            Shape::Line(l) => {
                let t = [-l.normal[1], l.normal[0]];
                let r = 2.0 * (xhi - xlo).hypot(yhi - ylo) + 2.0 * pad;
                let (cx, cy) = (0.5 * (xlo + xhi), 0.5 * (ylo + yhi));
                let s0 = (cx - l.point[0]) * t[0] + (cy - l.point[1]) * t[1];
                (0..=200)
                    .map(|i| {
                        let s = s0 - r + 2.0 * r * i as f64 / 200.0;
                        (l.point[0] + s * t[0], l.point[1] + s * t[1])
                    })
                    .collect()
            }
            Shape::Circle { centre, radius } => (0..=720)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / 720.0;
                    (centre[0] + radius * a.cos(), centre[1] + radius * a.sin())
                })
                .collect(),
            Shape::Polyline(p) => {
                // Long segments split so that clipping keeps their visible part.
                let raw = p.outline(std::f64::consts::PI / 90.0);
                let mut fine = Vec::new();
                for w in raw.windows(2) {
                    let n = 50;
                    for i in 0..n {
                        let s = i as f64 / n as f64;
                        fine.push((
                            w[0][0] + s * (w[1][0] - w[0][0]),
                            w[0][1] + s * (w[1][1] - w[0][1]),
                        ));
                    }
                }
                if let Some(last) = raw.last() {
                    fine.push((last[0], last[1]));
                }
                fine
            }
        };
        let label =
            format!("rigid {} {} (gap drawn ×{} like u)", shape.kind(), o.name, significant(m));
        let mut first = true;
        let mut run: Vec<(f64, f64)> = Vec::new();
        for p in outline.iter().chain(std::iter::once(&(f64::NAN, f64::NAN))) {
            if p.0.is_finite() && inside(p) {
                run.push(*p);
            } else if run.len() >= 2 {
                out.push(plot::Overlay {
                    label: first.then(|| label.clone()),
                    points: std::mem::take(&mut run),
                    kind: plot::OverlayKind::Obstacle,
                });
                first = false;
            } else {
                run.clear();
            }
        }
    }
    out
}

/// A body's name at the centre of its (deformed) points.
fn body_label(name: &str, points: &[(f64, f64)]) -> (String, (f64, f64)) {
    let n = points.len().max(1) as f64;
    let x = points.iter().map(|p| p.0).sum::<f64>() / n;
    let y = points.iter().map(|p| p.1).sum::<f64>() / n;
    (format!("body {name}"), (x, y))
}
