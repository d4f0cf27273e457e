//! The firmware source generators of `angletrack::export` (C headers and Rust `const`s of
//! gains, fixed-point constants and calibrations) on Python values; the Python package
//! wraps them in `angletrack.export` and `angletrack.harmonics`.

use angletrack::FixedDesignConstants;
use angletrack::export::{FixedGainsFile, FloatType, GainsFile};
use angletrack::tracker_file::Language;
use pyo3::conversion::FromPyObjectOwned;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::angle_calibration::SensorParameters;
use crate::errors::{Error, Result};
use crate::gains::{PyGains, with_gains};

/// The language named `language` (`"c"` or `"rust"`), refused naming it.
pub fn language(language: &str) -> Result<Language> {
    Language::from_name(language).ok_or_else(|| {
        Error::value(
            "language",
            format!("expected \"c\" or \"rust\", got {language:?}"),
        )
    })
}

/// The C header or Rust `const`s of `gains` (`angletrack::export::gains_c_header`,
/// `gains_rust`).
#[pyfunction]
#[pyo3(signature = (gains, language, *, name = "angletrack", dtype = "float32", description = ""))]
pub fn gains_source(
    gains: PyGains,
    language: &str,
    name: &str,
    dtype: &str,
    description: &str,
) -> Result<String> {
    let (language, float) = (self::language(language)?, dtype.parse::<FloatType>()?);
    Ok(with_gains!(gains.set, g => language.gains(&g, float, name, description))?)
}

/// The value of `key` in the constants dict as `Design.fixed_constants()` gives it,
/// refused (naming `constants`, and `expected`) when missing or of another type.
pub fn constant<'py, T: FromPyObjectOwned<'py>>(
    constants: &Bound<'py, PyAny>,
    key: &str,
    expected: &str,
) -> Result<T> {
    let value = constants.get_item(key).map_err(|_| {
        Error::value(
            "constants",
            format!("has no key '{key}' (expected the dict Design.fixed_constants() returns)"),
        )
    })?;
    value.extract::<T>().map_err(|_| {
        Error::value(
            "constants",
            format!(
                "'{key}' is {value:?}: expected {expected} (as Design.fixed_constants() gives)"
            ),
        )
    })
}

/// The constants of a dict as `Design.fixed_constants()` gives it.
fn fixed_constants(constants: &Bound<'_, PyAny>) -> Result<FixedDesignConstants> {
    Ok(FixedDesignConstants {
        multiplier: constant(constants, "multiplier", "a list of integers (int32)")?,
        acceleration_shift: constant(constants, "acceleration_shift", "an integer from 0 to 15")?,
        quantised_gains: constant(constants, "quantised_gains", "a list of floats")?,
        sample_period_s: constant(constants, "sample_period_s", "a period (s)")?,
    })
}

/// The C header or Rust `const`s of fixed-point constants (`angletrack::export::fixed_c_header`,
/// `fixed_rust`).
#[pyfunction]
#[pyo3(signature = (constants, language, *, name = "angletrack", description = ""))]
pub fn fixed_source(
    constants: &Bound<'_, PyDict>,
    language: &str,
    name: &str,
    description: &str,
) -> Result<String> {
    let constants = fixed_constants(constants.as_any())?;
    Ok(self::language(language)?.fixed(&constants, name, description)?)
}

/// The C header or Rust `const`s of a calibration (`angletrack::export::calibration_c_header`,
/// `calibration_rust`).
#[pyfunction]
#[pyo3(signature = (sensor, cos, sin, language, *, name = "angletrack", dtype = "float32"))]
pub fn calibration_source(
    sensor: SensorParameters,
    cos: Vec<f64>,
    sin: Vec<f64>,
    language: &str,
    name: &str,
    dtype: &str,
) -> Result<String> {
    let (sensor, correction) = angletrack::stored_stages(sensor, &cos, &sin)?;
    let (language, float) = (self::language(language)?, dtype.parse::<FloatType>()?);
    Ok(language.calibration(&sensor, &correction, float, name)?)
}

/// The design's JSON text as a value (`None` for none).
fn design(design_json: Option<&str>) -> Result<Option<serde_json::Value>> {
    design_json
        .map(|text| {
            serde_json::from_str(text)
                .map_err(|e| Error::value("metadata", format!("is not JSON ({e})")))
        })
        .transpose()
}

/// The gains file's text of `gains` and their design (JSON text)
/// (`angletrack::export::GainsFile::to_json`).
#[pyfunction]
#[pyo3(signature = (gains, design_json = None))]
pub fn gains_file_json(gains: PyGains, design_json: Option<&str>) -> Result<String> {
    Ok(GainsFile {
        gains: gains.set.gains(),
        sample_period_s: gains.set.sample_period(),
        design: design(design_json)?,
    }
    .to_json())
}

/// The gains and the sample period of a gains file's `text` (`file` names it in errors),
/// checked by the core (`angletrack::export::GainsFile::from_json`).
#[pyfunction]
#[pyo3(signature = (text, file = "gains file"))]
pub fn read_gains_file(text: &str, file: &str) -> Result<(Vec<f64>, f64)> {
    let read = GainsFile::from_json(text, file)?;
    Ok((read.gains, read.sample_period_s))
}

/// The fixed-point gains file's text of `constants` and their design (JSON text)
/// (`angletrack::export::FixedGainsFile::to_json`).
#[pyfunction]
#[pyo3(signature = (constants, design_json = None))]
pub fn fixed_gains_file_json(
    constants: &Bound<'_, PyDict>,
    design_json: Option<&str>,
) -> Result<String> {
    Ok(FixedGainsFile {
        constants: fixed_constants(constants.as_any())?,
        design: design(design_json)?,
    }
    .to_json())
}

/// The constants of a fixed-point gains file's `text`, as `Design.fixed_constants()` gives
/// them, checked by the core (`angletrack::export::FixedGainsFile::from_json`).
#[pyfunction]
#[pyo3(signature = (text, file = "gains file"))]
pub fn read_fixed_gains_file<'py>(
    py: Python<'py>,
    text: &str,
    file: &str,
) -> Result<Bound<'py, PyDict>> {
    crate::design::constants_dict(py, FixedGainsFile::from_json(text, file)?.constants)
}
