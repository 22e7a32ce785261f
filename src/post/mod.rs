//! Stage 12: outputs — CSV tables, a VTU file for ParaView, plots and `summary.json`.
//!
//! Every file is deterministic (fixed float formatting, sorted keys) except the `timings`
//! field of `summary.json`.

pub mod plot;
pub mod summary;
mod vtk;

pub use summary::Summary;

use crate::model::Model;
use crate::nodes::Axis;
use crate::problem::Problem;
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

/// An output directory written as a whole: the files go into a staging directory beside the
/// target, which replaces the target only when [`StagedDir::commit`] is called, so that the
/// target holds either one complete run (the previous one, or this one) and never a partial
/// or a mixed one. Dropped without a commit (a failed run), the staging directory is removed.
#[derive(Debug)]
pub struct StagedDir {
    staging: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl StagedDir {
    /// Prepares a staging directory for `target`.
    ///
    /// # Errors
    /// [`OutputError::NotAnOutputDirectory`] when `target` exists, is not empty and holds no
    /// earlier run (it is never replaced); [`OutputError::Io`] when the staging directory
    /// cannot be created.
    pub fn new(target: &Path) -> Result<Self, OutputError> {
        let io = |path: &Path| {
            let path = path.display().to_string();
            move |source| OutputError::Io { path, source }
        };
        let absolute = match target.canonicalize() {
            Ok(p) => p,
            Err(_) => std::env::current_dir().map_err(io(target))?.join(target),
        };
        if absolute.exists() && !is_empty_dir(&absolute) && !holds_a_run(&absolute) {
            return Err(OutputError::NotAnOutputDirectory { path: target.display().to_string() });
        }
        let (Some(parent), Some(name)) = (absolute.parent(), absolute.file_name()) else {
            return Err(OutputError::NotAnOutputDirectory { path: target.display().to_string() });
        };
        create_dir(parent)?;
        let staging =
            parent.join(format!(".{}.partial-{}", name.to_string_lossy(), std::process::id()));
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(io(&staging))?;
        }
        create_dir(&staging)?;
        Ok(Self { staging, target: target.to_path_buf(), committed: false })
    }

    /// Where to write.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Replaces the target with the staged directory; returns `files` (paths under
    /// [`Self::path`]) as paths under the target.
    ///
    /// # Errors
    /// [`OutputError::Io`] when the earlier run cannot be removed or the rename fails.
    pub fn commit(mut self, files: Vec<PathBuf>) -> Result<Vec<PathBuf>, OutputError> {
        let io = |path: &Path| {
            let path = path.display().to_string();
            move |source| OutputError::Io { path, source }
        };
        if self.target.exists() {
            std::fs::remove_dir_all(&self.target).map_err(io(&self.target))?;
        }
        std::fs::rename(&self.staging, &self.target).map_err(io(&self.target))?;
        self.committed = true;
        Ok(files
            .into_iter()
            .map(|f| match f.strip_prefix(&self.staging) {
                Ok(rel) => self.target.join(rel),
                Err(_) => f,
            })
            .collect())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}

fn is_empty_dir(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|mut entries| entries.next().is_none())
}

/// Whether `dir` holds an earlier run of this program (its `summary.json`, or those of a
/// comparison's `mfvm/`, name the program).
fn holds_a_run(dir: &Path) -> bool {
    let ours = |summary: PathBuf| {
        std::fs::read_to_string(summary)
            .is_ok_and(|text| text.contains(&format!("\"name\": \"{}\"", env!("CARGO_PKG_NAME"))))
    };
    ours(dir.join("summary.json")) || ours(dir.join("mfvm").join("summary.json"))
}

/// Writes `text` to `path`.
///
/// # Errors
/// [`OutputError::Io`].
pub fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    std::fs::write(path, text)
        .map_err(|source| OutputError::Io { path: path.display().to_string(), source })
}

/// Creates the output directory (and parents).
///
/// # Errors
/// [`OutputError::Io`].
pub fn create_dir(dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir)
        .map_err(|source| OutputError::Io { path: dir.display().to_string(), source })
}

/// Formats a float for CSV/JSON-like text: 12 significant digits, scientific.
pub fn num(v: f64) -> String {
    format!("{v:.11e}")
}

/// The files written for an elastostatic solution.
pub fn write_solution(
    dir: &Path,
    problem: &Problem,
    model: &Model,
    solution: &Solution,
) -> Result<Vec<PathBuf>, OutputError> {
    create_dir(dir)?;
    let mut written = Vec::new();
    let nodes = &model.nodes;
    let names = problem.domain.edge_names();

    let mut text = String::from("node,x,y,edges,spacing\n");
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

    let mut text = String::from("node,x,y,ux,uy\n");
    for (i, p) in nodes.points.iter().enumerate() {
        let u = solution.displacement[i];
        let _ = writeln!(text, "{i},{},{},{},{}", num(p[0]), num(p[1]), num(u[0]), num(u[1]));
    }
    written.push(save(dir, "displacement.csv", &text)?);

    let mut text = String::from("node,x,y,sxx,syy,sxy,von_mises\n");
    for (i, p) in nodes.points.iter().enumerate() {
        let s = solution.stress[i];
        let vm = problem.material.von_mises(s);
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

    let mut text = String::from("node,axis,x,y,reaction\n");
    for &(node, axis, r) in &solution.reactions {
        let p = nodes.points[node as usize];
        let a = if axis == Axis::X { "x" } else { "y" };
        let _ = writeln!(text, "{node},{a},{},{},{}", num(p[0]), num(p[1]), num(r));
    }
    written.push(save(dir, "reactions.csv", &text)?);

    let vtu = vtk::solution_vtu(problem, model, solution)?;
    written.push(save(dir, "solution.vtu", &vtu)?);

    written.extend(solution_plots(dir, problem, model, solution)?);
    if let Some(c) = &solution.contact {
        written.extend(contact_outputs(dir, problem, solution, c)?);
    }
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
    let mut text =
        String::from("candidate,node,x,y,arc_length,initial_gap,gap,force,pressure,in_contact");
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
    let mut written = vec![save(dir, "contact.csv", &text)?];
    let plots = dir.join("plots");
    create_dir(&plots)?;
    let edge = &problem.domain.edge_names()[problem.contact.as_ref().map_or(0, |s| s.edge)];
    let nu = cand.normal;
    // Deflection of the contact edge along the normal, and the obstacle at −g0.
    let deflection: Vec<(f64, f64)> = (0..cand.len())
        .map(|k| {
            let u = solution.displacement[cand.nodes[k] as usize];
            (cand.arc_length[k], nu[0] * u[0] + nu[1] * u[1])
        })
        .collect();
    let obstacle: Vec<(f64, f64)> =
        (0..cand.len()).map(|k| (cand.arc_length[k], -cand.initial_gap[k])).collect();
    let chart = plot::Chart {
        title: format!("{}: displacement of edge `{edge}` towards the obstacle", problem.name),
        x_label: format!("distance along `{edge}`"),
        y_label: "normal displacement ν·u^h".into(),
        series: vec![
            plot::Series {
                label: format!("ν·u^h ({})", method_label(problem)),
                points: deflection,
                style: plot::Style::Line,
                colour: 1,
            },
            plot::Series {
                label: "rigid obstacle".into(),
                points: obstacle,
                style: plot::Style::Dashed,
                colour: 0,
            },
        ],
    };
    let stem = plots.join("contact_deflection");
    plot::write_chart(&stem, &chart)?;
    written.push(stem.with_extension("svg"));
    written.push(stem.with_extension("png"));
    let pressure: Vec<(f64, f64)> =
        (0..cand.len()).map(|k| (cand.arc_length[k], c.pressure[k])).collect();
    let mut series = vec![plot::Series {
        label: "contact pressure P_c/|segment|".into(),
        points: pressure,
        style: plot::Style::Line,
        colour: 4,
    }];
    if let Some(lc) = c.onset.from_gap {
        let top = c.pressure.iter().copied().fold(0.0, f64::max);
        series.push(plot::Series {
            label: format!("onset l_c = {lc:.4}"),
            points: vec![(lc, 0.0), (lc, top)],
            style: plot::Style::Dashed,
            colour: 0,
        });
    }
    let chart = plot::Chart {
        title: format!("{}: contact pressure along `{edge}`", problem.name),
        x_label: format!("distance along `{edge}`"),
        y_label: "pressure".into(),
        series,
    };
    let stem = plots.join("contact_pressure");
    plot::write_chart(&stem, &chart)?;
    written.push(stem.with_extension("svg"));
    written.push(stem.with_extension("png"));
    Ok(written)
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
    solution: &Solution,
) -> Result<Vec<PathBuf>, OutputError> {
    let plots = dir.join("plots");
    create_dir(&plots)?;
    let nodes = &model.nodes;
    let (lo, hi) = problem.domain.bounding_box();
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let umax = solution.displacement.iter().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
    let magnification = if umax > 0.0 { 0.1 * size / umax } else { 1.0 };
    let map = plot::ColourMap {
        title: format!("{}: deformed shape (x{magnification:.3e}), von Mises stress", problem.name),
        value_label: "von Mises".into(),
        points: nodes
            .points
            .iter()
            .zip(&solution.displacement)
            .map(|(p, u)| (p[0] + magnification * u[0], p[1] + magnification * u[1]))
            .collect(),
        values: solution.stress.iter().map(|s| problem.material.von_mises(*s)).collect(),
    };
    let deformed = plots.join("deformed");
    plot::write_colour_map(&deformed, &map)?;

    let k = problem.profile_edge;
    let name = &problem.domain.edge_names()[k];
    let mut on_edge: Vec<(f64, usize)> = (0..nodes.len())
        .filter(|&i| nodes.edges[i].contains(k))
        .map(|i| (problem.domain.edge_parameter(k, nodes.points[i]), i))
        .collect();
    on_edge.sort_by(|a, b| a.0.total_cmp(&b.0));
    let len = problem.domain.curve(k).length();
    let series = |axis: usize, label: &str, colour: usize| plot::Series {
        label: label.into(),
        points: on_edge.iter().map(|&(t, i)| (t * len, solution.displacement[i][axis])).collect(),
        style: plot::Style::Line,
        colour,
    };
    let chart = plot::Chart {
        title: format!("{}: displacement u^h along edge `{name}`", problem.name),
        x_label: format!("distance along `{name}` from its first vertex"),
        y_label: "displacement".into(),
        series: vec![series(0, "u_x", 0), series(1, "u_y", 1)],
    };
    let profile = plots.join("profile");
    plot::write_chart(&profile, &chart)?;
    Ok(vec![
        deformed.with_extension("svg"),
        deformed.with_extension("png"),
        profile.with_extension("svg"),
        profile.with_extension("png"),
    ])
}
