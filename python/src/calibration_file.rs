//! The calibration files of `angletrack::CalibrationFile` on Python values: JSON text in
//! and out (the Python package reads and writes the files themselves).

use angletrack::{
    CalibrationFile, CalibrationMethod, CaptureCalibration, OrderQuality, SensorCalibrationRecord,
};
use pyo3::IntoPyObjectExt;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::angle_calibration::{SensorParameters, learned_dict};
use crate::calibration::PySensorCalibration;
use crate::errors::Result;

/// The JSON text of a sensor calibration learned while tracking.
#[pyfunction]
#[pyo3(signature = (calibration, *, turns_learned = None, source = None))]
pub fn sensor_calibration_to_json(
    calibration: PySensorCalibration,
    turns_learned: Option<crate::arrays::Count>,
    source: Option<String>,
) -> Result<String> {
    let record = SensorCalibrationRecord {
        calibration: calibration.inner,
        turns_learned: turns_learned.map(|n| n.get("turns_learned")).transpose()?,
        source,
    };
    Ok(record.to_json())
}

/// The JSON text of an angle calibration learned by `angletrack calibrate`, with its
/// `method` and its `orders` (`(order, amplitude_rad, uncertainty_rad, status)` each) when
/// known.
#[pyfunction]
#[pyo3(signature = (sensor, cos, sin, speed_rad_s, turns, error_rms_rad, residual_rms_rad, *,
    method = None, orders = None))]
#[allow(clippy::too_many_arguments)]
pub fn angle_calibration_to_json(
    sensor: SensorParameters,
    cos: Vec<f64>,
    sin: Vec<f64>,
    speed_rad_s: f64,
    turns: f64,
    error_rms_rad: f64,
    residual_rms_rad: f64,
    method: Option<String>,
    orders: Option<Vec<(usize, f64, f64, String)>>,
) -> Result<String> {
    let (sensor, correction) = angletrack::stored_stages(sensor, &cos, &sin)?;
    let calibration = CaptureCalibration {
        sensor,
        correction,
        speed_rad_s,
        turns,
        error_rms_rad,
        residual_rms_rad,
        method: CalibrationMethod::from_name(method.as_deref().unwrap_or("")),
        orders: OrderQuality::table(&orders.unwrap_or_default())?,
    };
    Ok(calibration.to_json())
}

/// The calibration of JSON `text` of either format (`file` names it in errors): a
/// `SensorCalibration`, or the dict of an angle calibration (as `_CaptureCalibrator.finish` gives).
#[pyfunction]
pub fn calibration_from_json<'py>(
    py: Python<'py>,
    text: &str,
    file: &str,
) -> Result<Bound<'py, PyAny>> {
    Ok(match CalibrationFile::from_json(text, file)? {
        CalibrationFile::Sensor(record) => {
            PySensorCalibration::from_core(&record.calibration).into_bound_py_any(py)?
        }
        CalibrationFile::Angle(calibration) => learned_dict(py, &calibration)?.into_any(),
    })
}

/// The sensor calibration of JSON `text` (`file` names it in errors).
#[pyfunction]
pub fn sensor_calibration_from_json(text: &str, file: &str) -> Result<PySensorCalibration> {
    let record = SensorCalibrationRecord::from_json(text, file)?;
    Ok(PySensorCalibration::from_core(&record.calibration))
}

/// The dict of the angle calibration of JSON `text` (`file` names it in errors).
#[pyfunction]
pub fn angle_calibration_from_json<'py>(
    py: Python<'py>,
    text: &str,
    file: &str,
) -> Result<Bound<'py, PyDict>> {
    learned_dict(py, &CaptureCalibration::from_json(text, file)?)
}
