//! The firmware source generators of `angletrack::export` (C headers and Rust `const`s of
//! gains, fixed-point constants and calibrations) on Python values; the Python package
//! wraps them in `angletrack.export` and `angletrack.harmonics`.

use angletrack::FixedDesignConstants;
use angletrack::export::{self, FloatType};
use pyo3::conversion::FromPyObjectOwned;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::angle_calibration::{SensorParameters, checked};
use crate::errors::{Error, Result};
use crate::gains::{GainSet, PyGains, with_gains};

/// The float type named `dtype` (`"float32"` or `"float64"`).
fn float_type(dtype: &str) -> Result<FloatType> {
    Ok(dtype.parse::<FloatType>()?)
}

/// The C header of `gains` (`angletrack::export::gains_c_header`).
#[pyfunction]
#[pyo3(signature = (gains, *, name = "angletrack", dtype = "float32", description = ""))]
pub fn gains_c_header(
    gains: PyGains,
    name: &str,
    dtype: &str,
    description: &str,
) -> Result<String> {
    let float_type = float_type(dtype)?;
    Ok(with_gains!(gains.set, g => export::gains_c_header(&g, float_type, name, description))?)
}

/// The Rust `const`s of `gains` (`angletrack::export::gains_rust`).
#[pyfunction]
#[pyo3(signature = (gains, *, name = "angletrack", dtype = "float32", description = ""))]
pub fn gains_rust(gains: PyGains, name: &str, dtype: &str, description: &str) -> Result<String> {
    let float_type = float_type(dtype)?;
    Ok(with_gains!(gains.set, g => export::gains_rust(&g, float_type, name, description))?)
}

/// The value of `key` in the dict of fixed-point constants.
fn item<'py, T: FromPyObjectOwned<'py>>(constants: &Bound<'py, PyDict>, key: &str) -> Result<T> {
    let value = constants
        .get_item(key)?
        .ok_or_else(|| Error::value("constants", format!("missing {key:?}")))?;
    value
        .extract::<T>()
        .map_err(|_| Error::value("constants", format!("{key:?} has the wrong type")))
}

/// The constants of a dict as `Design.fixed_constants()` gives it.
fn fixed_constants(constants: &Bound<'_, PyDict>) -> Result<FixedDesignConstants> {
    Ok(FixedDesignConstants {
        multiplier: item(constants, "multiplier")?,
        acceleration_shift: item(constants, "acceleration_shift")?,
        quantised_gains: item(constants, "quantised_gains")?,
        sample_period_s: item(constants, "sample_period_s")?,
    })
}

/// The C header of fixed-point constants (`angletrack::export::fixed_c_header`).
#[pyfunction]
#[pyo3(signature = (constants, *, name = "angletrack", description = ""))]
pub fn fixed_c_header(
    constants: &Bound<'_, PyDict>,
    name: &str,
    description: &str,
) -> Result<String> {
    Ok(export::fixed_c_header(
        &fixed_constants(constants)?,
        name,
        description,
    )?)
}

/// The Rust `const`s of fixed-point constants (`angletrack::export::fixed_rust`).
#[pyfunction]
#[pyo3(signature = (constants, *, name = "angletrack", description = ""))]
pub fn fixed_rust(constants: &Bound<'_, PyDict>, name: &str, description: &str) -> Result<String> {
    Ok(export::fixed_rust(
        &fixed_constants(constants)?,
        name,
        description,
    )?)
}

/// The C header of a calibration (`angletrack::export::calibration_c_header`).
#[pyfunction]
#[pyo3(signature = (sensor, cos, sin, *, name = "angletrack", dtype = "float32"))]
pub fn calibration_c_header(
    sensor: SensorParameters,
    cos: Vec<f64>,
    sin: Vec<f64>,
    name: &str,
    dtype: &str,
) -> Result<String> {
    let (sensor, correction) = checked(sensor, cos, sin)?;
    Ok(export::calibration_c_header(
        &sensor,
        &correction,
        float_type(dtype)?,
        name,
    )?)
}

/// The Rust `const`s of a calibration (`angletrack::export::calibration_rust`).
#[pyfunction]
#[pyo3(signature = (sensor, cos, sin, *, name = "angletrack", dtype = "float32"))]
pub fn calibration_rust(
    sensor: SensorParameters,
    cos: Vec<f64>,
    sin: Vec<f64>,
    name: &str,
    dtype: &str,
) -> Result<String> {
    let (sensor, correction) = checked(sensor, cos, sin)?;
    Ok(export::calibration_rust(
        &sensor,
        &correction,
        float_type(dtype)?,
        name,
    )?)
}

/// Adds the functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(gains_c_header, m)?)?;
    m.add_function(wrap_pyfunction!(gains_rust, m)?)?;
    m.add_function(wrap_pyfunction!(fixed_c_header, m)?)?;
    m.add_function(wrap_pyfunction!(fixed_rust, m)?)?;
    m.add_function(wrap_pyfunction!(calibration_c_header, m)?)?;
    m.add_function(wrap_pyfunction!(calibration_rust, m)?)?;
    Ok(())
}
