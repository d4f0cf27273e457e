//! Tolerance studies (`angletrack::study`): a specification checked and resolved, and its
//! runs computed with the GIL released, each row a dict of named columns.

use std::path::PathBuf;

use angletrack::study::{Study, StudyCell};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::Result;

/// The study of the JSON `text` (`file` names it in errors), its tracker files read
/// relative to `base_dir`: `(resolved, runs)`, the specification as one JSON text with the
/// tracker files inline (what `study_runs` takes) and its number of runs.
#[pyfunction]
pub fn study_resolve(text: &str, file: &str, base_dir: PathBuf) -> Result<(String, u64)> {
    let study = Study::from_json(text, file, &base_dir)?;
    Ok((study.resolved_json().to_string(), study.runs()))
}

/// The rows of the runs `runs` of the resolved specification `resolved`, one dict each
/// (the crate's `StudyRow::columns`), computed with the GIL released.
#[pyfunction]
pub fn study_runs<'py>(
    py: Python<'py>,
    resolved: &str,
    runs: Vec<u64>,
) -> Result<Vec<Bound<'py, PyDict>>> {
    let rows = py.detach(|| -> Result<_> {
        let study = Study::from_json(resolved, "study", std::path::Path::new("."))?;
        Ok(runs.iter().map(|&r| study.run(r)).collect::<Vec<_>>())
    })?;
    rows.iter()
        .map(|row| {
            let dict = PyDict::new(py);
            for (name, cell) in row.columns() {
                match cell {
                    StudyCell::Integer(v) => dict.set_item(name, v)?,
                    StudyCell::Number(v) => dict.set_item(name, v)?,
                    StudyCell::Text(v) => dict.set_item(name, v)?,
                }
            }
            Ok(dict)
        })
        .collect()
}

/// The outliers of a lot's `values` (`angletrack::lot::outliers`): `(median, scaled MAD,
/// flags)`, flagged beyond `low`/`high` or `spread_factor` scaled MADs from the median.
#[pyfunction]
#[pyo3(signature = (values, spread_factor, low = None, high = None))]
pub fn lot_outliers(
    values: Vec<f64>,
    spread_factor: f64,
    low: Option<f64>,
    high: Option<f64>,
) -> (f64, f64, Vec<bool>) {
    angletrack::lot::outliers(&values, spread_factor, low, high)
}
