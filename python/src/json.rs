//! A JSON document of the crates (a report, a record) as the Python value `json.loads` reads.

use pyo3::prelude::*;

/// `value` as Python dicts, lists, strings, numbers, booleans and `None`.
pub fn to_python<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    let loads = PyModule::import(py, "json")?.getattr("loads")?;
    loads.call1((value.to_string(),))
}
