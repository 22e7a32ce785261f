//! The outputs of a dynamic run (docs/method.md §10): `history.csv` (one row per written
//! step), the force and energy plots against time, and `summary.json` with the run's figures.

use super::summary::Verdict;
use super::{OutputError, num, plot, write_text};
use crate::dynamics::{Figures, History, Record};
use crate::problem::dynamics::{Dynamics, MassKind};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The contents of a dynamic run's `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct DynamicSummary {
    /// The layout's version ([`super::summary::SCHEMA_VERSION`]).
    pub schema_version: u32,
    /// The problem's name.
    pub name: String,
    /// Nodes of the body.
    pub nodes: usize,
    /// Contact candidates.
    pub candidates: usize,
    /// The time stepping's parameters.
    pub dynamics: DynamicsEcho,
    /// The run's figures.
    pub figures: Figures,
    /// Every check of the run against its tolerance ([`DynamicChecks::of`]); a run
    /// with a failing check still writes its outputs, and the command line ends it with exit
    /// status 3.
    pub checks: DynamicChecks,
    /// What the reader should know about the result ([`warnings`]).
    pub warnings: Vec<String>,
    /// The problem file as read.
    pub input: serde_json::Value,
    /// Wall time of each stage, seconds (the only non-deterministic entry, as in the static
    /// `summary.json`).
    pub timings: BTreeMap<&'static str, f64>,
    /// The bodies of a run of several (absent for one body; `figures` are the scene's: the
    /// total contact force, the energies and momentum summed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bodies: Option<Vec<BodyFigures>>,
    /// Each contact pair's figures with several pairs (`[[contact]]` order; absent with
    /// one pair, whose figures are `figures`' contact entries); `history.csv` has each
    /// pair's force as `contact_force_<k>`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pairs: Option<Vec<PairHistory>>,
}

/// One contact pair of a run with several.
#[derive(Clone, Debug, Serialize)]
pub struct PairHistory {
    /// The body carrying the candidates.
    pub body: String,
    /// Its contact edge.
    pub edge: String,
    /// The target body (`null` for rigid obstacles).
    pub target_body: Option<String>,
    /// The pair's candidates.
    pub candidates: usize,
    /// Its contact figures.
    #[serde(flatten)]
    pub figures: crate::dynamics::PairFigures,
}

/// One body of a two-body run.
#[derive(Clone, Debug, Serialize)]
pub struct BodyFigures {
    /// Its name.
    pub name: String,
    /// Its nodes.
    pub nodes: usize,
    /// Its density.
    pub density: f64,
    /// Its mass (per unit thickness).
    pub mass: f64,
    /// Its uniform velocity at time 0.
    pub initial_velocity: [f64; 2],
    /// The velocity of its centre of mass at the end.
    pub final_velocity: [f64; 2],
}

/// The checks of a dynamic run (`checks` in its `summary.json`).
#[derive(Clone, Debug, Serialize)]
pub struct DynamicChecks {
    /// Whether every check in `verdicts` passed.
    pub passed: bool,
    /// The worst step's LCP residual against
    /// [`crate::solution::COMPLEMENTARITY_TOLERANCE`], and the count of non-finite history
    /// entries against 0.
    pub verdicts: Vec<Verdict>,
}

impl DynamicChecks {
    /// The checks of a run with these figures.
    pub fn of(figures: &Figures) -> Self {
        let verdicts = vec![
            Verdict::new(
                "step_complementarity",
                "figures.max_step_residual".into(),
                figures.max_step_residual,
                crate::solution::COMPLEMENTARITY_TOLERANCE,
            ),
            Verdict::new(
                "finite_values",
                "figures.non_finite_values".into(),
                figures.non_finite_values as f64,
                0.0,
            ),
        ];
        Self { passed: verdicts.iter().all(|v| v.pass), verdicts }
    }
}

impl DynamicSummary {
    /// The checks that failed.
    pub fn failed_checks(&self) -> Vec<&Verdict> {
        self.checks.verdicts.iter().filter(|v| !v.pass).collect()
    }
}

/// The checked `[dynamics]` parameters, as used.
#[derive(Clone, Debug, Serialize)]
pub struct DynamicsEcho {
    /// Density.
    pub density: f64,
    /// Time step.
    pub time_step: f64,
    /// θ.
    pub theta: f64,
    /// Restitution.
    pub restitution: f64,
    /// Initial velocity.
    pub initial_velocity: [f64; 2],
    /// The loads' ramp time (absent without).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_ramp: Option<f64>,
    /// `"consistent"` with the FE's consistent mass (absent with the lumped one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mass: Option<&'static str>,
}

impl From<&Dynamics> for DynamicsEcho {
    fn from(d: &Dynamics) -> Self {
        Self {
            density: d.density,
            time_step: d.time_step,
            theta: d.theta,
            restitution: d.restitution,
            initial_velocity: d.initial_velocity,
            load_ramp: d.load_ramp,
            mass: (d.mass == MassKind::Consistent).then_some("consistent"),
        }
    }
}

/// An energy growth ([`Figures::energy_growth`]) above this is reported as a warning: the
/// energy grew beyond what the loads brought — a complex mode of the Petrov–Galerkin `K`
/// growing at θ = ½ (docs/method.md §10.2). Numerical damping (θ > ½) is not warned about.
pub const ENERGY_GROWTH_WARNING: f64 = 0.05;

/// The warnings of a run with these figures at the θ it used.
pub fn warnings(figures: &Figures, theta: f64) -> Vec<String> {
    let mut out = Vec::new();
    if figures.energy_growth > ENERGY_GROWTH_WARNING {
        let remedy = if theta < 0.51 {
            "set theta = 0.51 or more"
        } else {
            "raise theta further, or refine the time step"
        };
        out.push(format!(
            "the energy grew by {:.3e} of its largest value beyond the work of the loads at dynamics.theta = {theta}: a mode of the non-symmetric stiffness grows near theta = 0.5 over long runs; {remedy} (docs/method.md §10.2)",
            figures.energy_growth
        ));
    }
    out
}

/// Writes `history.csv`, `plots/history_force.{svg,png}`, `plots/history_energy.{svg,png}`
/// and `summary.json` (last) under `dir`; returns the files.
///
/// # Errors
/// [`OutputError`] when a file cannot be written.
pub fn write_dynamic(
    dir: &Path,
    history: &History,
    summary: &DynamicSummary,
) -> Result<Vec<PathBuf>, OutputError> {
    let csv = dir.join("history.csv");
    write_text(&csv, &history_csv(history))?;
    let plots = dir.join("plots");
    super::create_dir(&plots)?;
    let force = plots.join("history_force");
    plot::write_chart(&force, &force_chart(history, summary.pairs.as_deref()))?;
    let energy = plots.join("history_energy");
    plot::write_chart(&energy, &energy_chart(history))?;
    let json = dir.join("summary.json");
    let text = serde_json::to_string_pretty(summary).map_err(|e| OutputError::Io {
        path: json.display().to_string(),
        source: std::io::Error::other(e),
    })?;
    write_text(&json, &(text + "\n"))?;
    let mut files = vec![csv];
    for stem in [force, energy] {
        files.push(stem.with_extension("svg"));
        files.push(stem.with_extension("png"));
    }
    files.push(json);
    Ok(files)
}

/// One row per record; with several contact pairs each pair's force follows as
/// `contact_force_<k>` (`[[contact]]` order).
fn history_csv(history: &History) -> String {
    let mut s = String::from(
        "time,contact_force,kinetic_energy,strain_energy,external_work,contact_loss,momentum_x,momentum_y,active",
    );
    let pairs = history.records.first().map_or(0, |r| r.pair_forces.len());
    for k in 0..pairs {
        let _ = write!(s, ",contact_force_{k}");
    }
    s.push('\n');
    for r in &history.records {
        let _ = write!(
            s,
            "{},{},{},{},{},{},{},{},{}",
            num(r.time),
            num(r.contact_force),
            num(r.kinetic_energy),
            num(r.strain_energy),
            num(r.external_work),
            num(r.contact_loss),
            num(r.momentum[0]),
            num(r.momentum[1]),
            r.active
        );
        for f in &r.pair_forces {
            let _ = write!(s, ",{}", num(*f));
        }
        s.push('\n');
    }
    s
}

fn series(
    history: &History,
    label: &str,
    colour: usize,
    f: impl Fn(&Record) -> f64,
) -> plot::Series {
    plot::Series {
        label: label.into(),
        points: history.records.iter().map(|r| (r.time, f(r))).collect(),
        style: plot::Style::Line,
        colour,
    }
}

fn force_chart(history: &History, pairs: Option<&[PairHistory]>) -> plot::Chart {
    let mut series_ = vec![series(history, "total contact force", 0, |r| r.contact_force)];
    for (k, p) in pairs.unwrap_or_default().iter().enumerate() {
        let target = p.target_body.as_deref().unwrap_or("obstacles");
        let label = format!("pair {k}: {}.{} on {target}", p.body, p.edge);
        series_
            .push(series(history, &label, k + 1, |r| r.pair_forces.get(k).copied().unwrap_or(0.0)));
    }
    let title = match pairs {
        Some(_) => "Contact forces, total and per pair (mean over each step)",
        None => "Total contact force (mean over each step)",
    };
    plot::Chart {
        title: title.into(),
        x_label: "time".into(),
        y_label: "contact force".into(),
        series: series_,
    }
}

fn energy_chart(history: &History) -> plot::Chart {
    plot::Chart {
        title: "Energies".into(),
        x_label: "time".into(),
        y_label: "energy".into(),
        series: vec![
            series(history, "kinetic", 0, |r| r.kinetic_energy),
            series(history, "strain", 1, |r| r.strain_energy),
            series(history, "kinetic + strain", 2, Record::energy),
            series(history, "lost at contacts", 3, |r| r.contact_loss),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::History;

    fn figures(residual: f64, kinetic: f64) -> Figures {
        let record =
            |time: f64| Record { kinetic_energy: kinetic, ..Record::sample(time, residual) };
        History { records: vec![record(0.0), record(0.1)] }.figures(0.1, 1.0)
    }

    #[test]
    fn a_dynamic_run_fails_its_checks_on_an_inaccurate_step_or_a_non_finite_value() {
        assert!(DynamicChecks::of(&figures(1e-12, 1.0)).passed);
        let inaccurate = DynamicChecks::of(&figures(1e-6, 1.0));
        assert!(!inaccurate.passed);
        assert_eq!(inaccurate.verdicts[0].check, "step_complementarity");
        assert!(!inaccurate.verdicts[0].pass && inaccurate.verdicts[1].pass);
        let nan = DynamicChecks::of(&figures(f64::NAN, 1.0));
        assert!(!nan.verdicts[0].pass, "a NaN residual fails");
        let infinite = DynamicChecks::of(&figures(0.0, f64::INFINITY));
        assert!(!infinite.passed && !infinite.verdicts[1].pass);
        assert!(infinite.verdicts[1].to_string().contains("figures.non_finite_values"));
    }
}
