//! Python bindings of mlpg-contact: the extension module `mlpg_contact._native`, wrapped by the
//! pure-Python package `mlpg_contact` beside it (`python/mlpg_contact/`), which is what users
//! import. Built by maturin (`pip install .`); the Rust crate and its command line never
//! need it.
//!
//! The module has one function, [`solve`], which takes the problem as TOML or JSON text, solves
//! it with the GIL released and returns a [`Solved`]: numpy arrays of the nodes, the
//! displacements, stresses, reactions and contact columns, the summary as JSON text, and
//! `write(dir)` for the usual output files. Validation errors raise `ProblemError` (a
//! `ValueError`) with the attributes `field`, `value` and `reason`; every other failure raises
//! `SolveError` (a `RuntimeError`) with `keys`, the problem-file keys that decide it.

use mlpg_contact::pipeline::Outcome;
use mlpg_contact::problem::{Problem, ProblemError as RawProblemError, ProblemFile};
use mlpg_contact::solution::Solution;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

create_exception!(
    _native,
    ProblemError,
    PyValueError,
    "A problem that fails validation; `field` names the key path, `value` the value as written, `reason` what is accepted."
);
create_exception!(
    _native,
    SolveError,
    PyRuntimeError,
    "A run that fails after validation; `keys` names the problem-file keys that decide it."
);

/// A Python exception for a validation error, its parts as attributes.
fn problem_error(py: Python<'_>, e: &RawProblemError) -> PyErr {
    let err = ProblemError::new_err(e.to_string());
    let (field, value, reason) = match e {
        RawProblemError::Invalid { field, value, reason } => {
            (Some(field.clone()), Some(value.clone()), Some(reason.clone()))
        }
        RawProblemError::Parse(text) => {
            // "at `path`: ..." carries the key path of a parse error.
            let field = text
                .strip_prefix("at `")
                .and_then(|rest| rest.split_once('`'))
                .map(|(path, _)| path.to_string());
            (field, None, Some(text.clone()))
        }
    };
    let value_obj = err.value(py);
    for (name, v) in [("field", field), ("value", value), ("reason", reason)] {
        // Setting an attribute on a fresh exception instance cannot fail in practice; if it
        // did, the message still carries everything.
        let _ = value_obj.setattr(name, v);
    }
    err
}

/// A Python exception for a run-time error.
fn solve_error(py: Python<'_>, e: &mlpg_contact::Error) -> PyErr {
    if let mlpg_contact::Error::Problem(p) = e {
        return problem_error(py, p);
    }
    let err = SolveError::new_err(e.to_string());
    let _ = err.value(py).setattr("keys", e.input_keys());
    err
}

/// A solved problem.
#[pyclass(module = "mlpg_contact._native", frozen)]
struct Solved {
    outcome: Outcome,
}

/// `rows × 2` (or `× 3`) numpy array from fixed-size rows.
fn matrix<'py, const N: usize>(
    py: Python<'py>,
    rows: &[[f64; N]],
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    PyArray1::from_vec(py, flat).reshape([rows.len(), N])
}

impl Solved {
    fn body(&self, second: bool) -> PyResult<(&mlpg_contact::Model, &Solution)> {
        let o = &self.outcome;
        match (second, o.second.as_ref(), o.solution.second_body()) {
            (false, _, _) => Ok((&o.model, &o.solution)),
            (true, Some(m), Some(s)) => Ok((m, s)),
            (true, _, _) => Err(PyValueError::new_err("the problem has no second body")),
        }
    }
}

#[pymethods]
impl Solved {
    /// Node coordinates, `n × 2` (`second=True`: the second body's).
    #[pyo3(signature = (second = false))]
    fn nodes<'py>(&self, py: Python<'py>, second: bool) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, &self.body(second)?.0.nodes.points)
    }

    /// Displacement `u^h` at the nodes, `n × 2`.
    #[pyo3(signature = (second = false))]
    fn displacement<'py>(
        &self,
        py: Python<'py>,
        second: bool,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, &self.body(second)?.1.displacement)
    }

    /// Stress `(σ_xx, σ_yy, σ_xy)` at the nodes, `n × 3`.
    #[pyo3(signature = (second = false))]
    fn stress<'py>(&self, py: Python<'py>, second: bool) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, &self.body(second)?.1.stress)
    }

    /// Reactions as `(node, axis, force)` arrays in a dict (`axis`: 0 for x, 1 for y).
    #[pyo3(signature = (second = false))]
    fn reactions<'py>(&self, py: Python<'py>, second: bool) -> PyResult<Bound<'py, PyDict>> {
        let r = &self.body(second)?.1.reactions;
        let d = PyDict::new(py);
        d.set_item("node", PyArray1::from_vec(py, r.iter().map(|x| u64::from(x.0)).collect()))?;
        d.set_item("axis", PyArray1::from_vec(py, r.iter().map(|x| x.1 as u8).collect()))?;
        d.set_item("force", PyArray1::from_vec(py, r.iter().map(|x| x.2).collect()))?;
        Ok(d)
    }

    /// The columns of `contact.csv` as numpy arrays in a dict, or `None` without contact.
    fn contact<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(c) = self.outcome.solution.contact() else { return Ok(None) };
        let cand = &c.candidates;
        let d = PyDict::new(py);
        let column = |v: Vec<f64>| PyArray1::from_vec(py, v);
        d.set_item("candidate", PyArray1::from_vec(py, (0..cand.len() as u64).collect()))?;
        d.set_item(
            "node",
            PyArray1::from_vec(py, cand.nodes.iter().map(|&n| u64::from(n)).collect()),
        )?;
        d.set_item("x", column(cand.points.iter().map(|p| p[0]).collect()))?;
        d.set_item("y", column(cand.points.iter().map(|p| p[1]).collect()))?;
        d.set_item("arc_length", column(cand.arc_length.clone()))?;
        d.set_item("initial_gap", column(cand.initial_gap.clone()))?;
        d.set_item("gap", column(c.gap.clone()))?;
        d.set_item("force", column(c.lcp.z[..cand.len()].to_vec()))?;
        d.set_item("pressure", column(c.pressure.clone()))?;
        d.set_item("in_contact", PyArray1::from_vec(py, c.closed.clone()))?;
        if let Some(f) = &c.friction {
            d.set_item("tangential_force", column(f.step.tangential.clone()))?;
            d.set_item("tangential_traction", column(f.traction.clone()))?;
            d.set_item("slip", column(f.slip.clone()))?;
            let states: Vec<&str> = f.step.state.iter().map(|s| s.label()).collect();
            d.set_item("state", states)?;
        }
        Ok(Some(d))
    }

    /// The contents of `summary.json`, as JSON text (the Python wrapper parses it).
    fn summary_json(&self) -> String {
        self.outcome.summary.to_json()
    }

    /// Writes the usual output files into `out` (the earlier run's files replaced, any other
    /// file kept, as by the command line),
    /// with `report=True` also `report.html`; returns the paths written.
    #[pyo3(signature = (out, report = false))]
    fn write(&self, py: Python<'_>, out: PathBuf, report: bool) -> PyResult<Vec<PathBuf>> {
        let written = py.detach(|| self.outcome.write_with_report(&out, report));
        written.map(|report| report.files).map_err(|e| solve_error(py, &e))
    }
}

/// Solves a problem given as text: `format` is `"toml"` (a problem file's contents) or
/// `"json"` (the same keys as JSON); relative mesh paths (`geometry.file`) are taken relative
/// to `folder` when given (the problem file's folder, as the binary does), else to the working
/// directory. The GIL is released while solving.
#[pyfunction]
#[pyo3(signature = (text, format = "toml", folder = None))]
fn solve(py: Python<'_>, text: &str, format: &str, folder: Option<&str>) -> PyResult<Solved> {
    let file = match format {
        "toml" => ProblemFile::from_toml(text),
        "json" => ProblemFile::from_json(text),
        other => {
            return Err(PyValueError::new_err(format!(
                "format must be \"toml\" or \"json\", not {other:?}"
            )));
        }
    }
    .map_err(|e| problem_error(py, &e))?;
    let echo = serde_json::to_value(&file).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let mut file = file;
    if let Some(folder) = folder {
        file.resolve_paths(std::path::Path::new(folder));
    }
    let problem = Problem::try_from(file).map_err(|e| problem_error(py, &e))?;
    // Threads solving at once reserve their memory, dense kernels' workspace included, against
    // what the process may use: a solve that would not fit is refused with the limit named
    // (pipeline::memory::admit) instead of aborting the interpreter half-way.
    let admission =
        mlpg_contact::pipeline::memory::admit(&problem).map_err(|e| solve_error(py, &e))?;
    let outcome = py.detach(|| Outcome::solve(problem, echo, &mut mlpg_contact::Silent));
    drop(admission);
    outcome.map(|outcome| Solved { outcome }).map_err(|e| solve_error(py, &e))
}

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    m.add_class::<Solved>()?;
    m.add("ProblemError", m.py().get_type::<ProblemError>())?;
    m.add("SolveError", m.py().get_type::<SolveError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
