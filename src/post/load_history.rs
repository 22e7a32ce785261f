//! The load history of a run along several load increments (`[[step]]` tables, friction):
//! `load_history.csv` and `plots/load_history.{svg,png}`, each contact pair's total normal
//! force `Σ P_c` (and tangential force `Σ T_c` where it has friction) at the end of every
//! increment, against the load path parameter `t = (step − 1) + λ` (`λ` the step's load
//! factor, so that step `k` runs from `t = k − 1` to `t = k`).

use super::{OutputError, num, plot, save};
use crate::solution::IncrementRecord;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One contact pair's record along the load path.
pub struct PairHistory<'a> {
    /// The pair's index (its `[[contact]]` table, from 0; 0 for a single `[contact]`).
    pub index: usize,
    /// The pair's name in the legend (e.g. `contact[0] middle.bottom`).
    pub label: String,
    /// One record per increment, in order.
    pub records: &'a [IncrementRecord],
}

/// The load path parameter `t = (step − 1) + λ` of an increment.
pub fn path_parameter(record: &IncrementRecord) -> f64 {
    (record.step - 1) as f64 + record.load_factor
}

/// Whether the pairs' path has more than one increment (a history worth drawing).
pub fn is_stepped(pairs: &[PairHistory<'_>]) -> bool {
    pairs.iter().any(|p| p.records.len() > 1)
}

/// The text of `load_history.csv`: one row per pair and increment, pair after pair.
pub fn table(pairs: &[PairHistory<'_>]) -> String {
    let mut text = String::from(
        "pair,step,increment,load_factor,path_parameter,normal_force,tangential_force\n",
    );
    for pair in pairs {
        for r in pair.records {
            let _ = writeln!(
                text,
                "{},{},{},{},{},{},{}",
                pair.index,
                r.step,
                r.increment,
                num(r.load_factor),
                num(path_parameter(r)),
                num(r.normal_force),
                num(r.tangential_force)
            );
        }
    }
    text
}

/// The chart: per pair a solid line with markers for `Σ P`, and a dashed one for `Σ T` when
/// any of its increments carries a tangential force.
pub fn chart(problem_name: &str, pairs: &[PairHistory<'_>]) -> plot::Chart {
    let mut series = Vec::new();
    for (k, pair) in pairs.iter().enumerate() {
        let along = |f: fn(&IncrementRecord) -> f64| -> Vec<(f64, f64)> {
            pair.records.iter().map(|r| (path_parameter(r), f(r))).collect()
        };
        let normal = along(|r| r.normal_force);
        series.push(plot::Series {
            label: format!("{}: normal ΣP", pair.label),
            points: normal.clone(),
            style: plot::Style::Line,
            colour: 2 * k,
        });
        series.push(plot::Series {
            label: String::new(),
            points: normal,
            style: plot::Style::Points,
            colour: 2 * k,
        });
        if pair.records.iter().any(|r| r.tangential_force != 0.0) {
            series.push(plot::Series {
                label: format!("{}: tangential ΣT", pair.label),
                points: along(|r| r.tangential_force),
                style: plot::Style::Dashed,
                colour: 2 * k + 1,
            });
        }
    }
    plot::Chart {
        title: format!("{problem_name}: total contact forces along the load path"),
        x_label: "load path t = (step − 1) + load factor λ".into(),
        y_label: "total contact force on the pair's candidate body".into(),
        series,
    }
}

/// Writes `load_history.csv` into `dir` and `plots/load_history.{svg,png}` when the path has
/// more than one increment ([`is_stepped`]); nothing otherwise.
///
/// # Errors
/// [`OutputError`] when a file cannot be written.
pub fn write(
    dir: &Path,
    problem_name: &str,
    pairs: &[PairHistory<'_>],
) -> Result<Vec<PathBuf>, OutputError> {
    if !is_stepped(pairs) {
        return Ok(Vec::new());
    }
    let mut written = vec![save(dir, "load_history.csv", &table(pairs))?];
    let plots = dir.join("plots");
    super::create_dir(&plots)?;
    let stem = plots.join("load_history");
    written.extend(plot::write_chart(&stem, &chart(problem_name, pairs))?);
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(step: usize, increment: usize, load_factor: f64, p: f64, t: f64) -> IncrementRecord {
        IncrementRecord {
            step,
            increment,
            load_factor,
            normal_force: p,
            tangential_force: t,
            solver: crate::lcp::FrictionMethod::Lemke,
            pivots: 0,
            iterations: 0,
            active_set_changes: Vec::new(),
            complementarity: 0.0,
            equilibrium_error: 0.0,
            stick: 0,
            slip: 0,
            open: 0,
            seconds: 0.0,
        }
    }

    #[test]
    fn path_parameter_runs_through_the_steps() {
        let records = [record(1, 1, 1.0, 2.0, 0.0), record(2, 1, 0.25, 2.0, 0.5)];
        assert_eq!(path_parameter(&records[0]), 1.0);
        assert_eq!(path_parameter(&records[1]), 1.25);
        let pairs = [PairHistory { index: 0, label: "contact".into(), records: &records }];
        assert!(is_stepped(&pairs));
        let text = table(&pairs);
        let rows: Vec<&str> = text.lines().collect();
        assert_eq!(rows.len(), 3);
        assert!(rows[2].starts_with("0,2,1,2.50000000000e-1,1.25000000000e0,"), "{}", rows[2]);
        // A tangential series only where there is a tangential force.
        let c = chart("p", &pairs);
        assert_eq!(c.series.len(), 3);
        let single = [PairHistory { index: 0, label: "c".into(), records: &records[..1] }];
        assert!(!is_stepped(&single));
        assert_eq!(chart("p", &single).series.len(), 2);
    }
}
