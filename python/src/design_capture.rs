//! `design_from_capture`: the observer chosen from a capture by
//! `angletrack::design_capture`, returned as a dict of the design, its tracker file, the
//! prediction and the estimates.

use angletrack::design_capture::{
    CaptureSignals, DesignCaptureError, DesignConstraints, design_from_capture as choose,
};
use angletrack::tracker_file::NumberType;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{paired_samples, samples};
use crate::design::PyDesign;
use crate::errors::{Error, Result};

/// The points of the returned spectra.
const SPECTRUM_POINTS: usize = 200;

/// The Python argument of a series the crate names.
fn python_series(series: &str) -> &'static str {
    match series {
        "cos" => "y_c",
        "sin" => "y_s",
        _ => "reference_angle_rad",
    }
}

impl From<DesignCaptureError> for Error {
    fn from(e: DesignCaptureError) -> Self {
        match e {
            DesignCaptureError::Argument { name, expected } => {
                Error::value(name, format!("must be {expected}"))
            }
            DesignCaptureError::NotFinite { series, index } => Error::value(
                python_series(series),
                format!("[{index}] is not a finite number"),
            ),
            DesignCaptureError::LengthMismatch {
                series,
                len,
                expected,
            } => Error::value(
                python_series(series),
                format!("has {len} samples, y_c has {expected}: they must be the same length"),
            ),
            other => Error::Python(PyValueError::new_err(other.to_string())),
        }
    }
}

/// Chooses the observer from a capture (`angletrack::design_capture::design_from_capture`).
#[pyfunction]
#[pyo3(signature = (y_c, y_s, sample_period_s, *, reference_angle_rad = None,
    quantisation_step = None, max_overshoot = None, min_bandwidth_hz = None,
    speed_step_rad_s = None, number_type = "f32", grid_points = 31))]
#[allow(clippy::too_many_arguments)]
pub fn design_from_capture<'py>(
    py: Python<'py>,
    y_c: &Bound<'py, PyAny>,
    y_s: &Bound<'py, PyAny>,
    sample_period_s: f64,
    reference_angle_rad: Option<&Bound<'py, PyAny>>,
    quantisation_step: Option<f64>,
    max_overshoot: Option<f64>,
    min_bandwidth_hz: Option<f64>,
    speed_step_rad_s: Option<f64>,
    number_type: &str,
    grid_points: i64,
) -> Result<Bound<'py, PyDict>> {
    let (cos, sin) = paired_samples::<f64>((y_c, "y_c"), (y_s, "y_s"))?;
    let reference = reference_angle_rad
        .map(|r| samples::<f64>(r, "reference_angle_rad"))
        .transpose()?;
    let number_type = match number_type {
        "f32" => NumberType::F32,
        "f64" => NumberType::F64,
        "fixed" => NumberType::Fixed,
        other => {
            return Err(Error::value(
                "number_type",
                format!("expected \"f32\", \"f64\" or \"fixed\", got {other:?}"),
            ));
        }
    };
    let signals = CaptureSignals {
        cos: cos.as_slice(),
        sin: sin.as_slice(),
        sample_period_s,
        reference_angle_rad: reference.as_ref().map(|r| r.as_slice()),
        quantisation_step,
    };
    let constraints = DesignConstraints {
        max_overshoot,
        min_bandwidth_hz,
        speed_step_rad_s,
        number_type,
        // A count out of usize is out of the crate's range too, which names it.
        grid_points: usize::try_from(grid_points).unwrap_or(0),
    };
    let design = py.detach(|| choose(&signals, &constraints))?;
    let out = crate::json::to_python(py, &design.report(SPECTRUM_POINTS))?;
    out.set_item("design", PyDesign::from(design.chosen.design))?;
    Ok(out.cast_into::<PyDict>().map_err(PyErr::from)?)
}
