//! `design_from_capture`: the observer chosen from a capture by
//! `angletrack::design_capture`, returned as a dict of the design, its tracker file, the
//! prediction and the estimates.

use angletrack::design_capture::{
    CaptureCandidate, CaptureSignals, DesignCaptureError, DesignConstraints, Uncertain,
    design_from_capture as choose,
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

fn uncertain<'py>(py: Python<'py>, u: Uncertain) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("value", u.value)?;
    d.set_item("std", u.std)?;
    Ok(d)
}

fn candidate<'py>(py: Python<'py>, c: &CaptureCandidate) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("observer", c.family.name())?;
    d.set_item("bandwidth_hz", c.bandwidth_hz)?;
    d.set_item("gains", c.design.gains())?;
    d.set_item("predicted_error_rms_rad", c.predicted.total_rad)?;
    d.set_item("noise_rad", c.predicted.noise_rad)?;
    d.set_item("lag_rad", c.predicted.lag_rad)?;
    d.set_item("number_type_rad", c.predicted.number_type_rad)?;
    d.set_item("refused_by", c.refused_by)?;
    Ok(d)
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
    let out = PyDict::new(py);
    let e = &design.estimates;
    let noise = PyDict::new(py);
    noise.set_item("amplitude", e.noise.amplitude)?;
    noise.set_item("std", uncertain(py, e.noise.std)?)?;
    noise.set_item("cos_std", uncertain(py, e.noise.cos_std)?)?;
    noise.set_item("sin_std", uncertain(py, e.noise.sin_std)?)?;
    noise.set_item("white_std", e.noise.white_std)?;
    noise.set_item("coloured_std", e.noise.coloured_std)?;
    noise.set_item("coloured_pole", e.noise.coloured_pole)?;
    noise.set_item("quantisation_std", e.noise.quantisation_std)?;
    let motion = PyDict::new(py);
    motion.set_item("jerk_std_rad_s3", uncertain(py, e.motion.jerk_std_rad_s3)?)?;
    motion.set_item(
        "jerk_by_differences_rad_s3",
        uncertain(py, e.motion.jerk_by_differences_rad_s3)?,
    )?;
    motion.set_item("jerk_by_als", e.motion.jerk_by_als)?;
    if let Some(als) = &e.als {
        let d = PyDict::new(py);
        d.set_item("jerk_std_rad_s3", uncertain(py, als.jerk_std_rad_s3)?)?;
        d.set_item("noise_std", uncertain(py, als.noise_std)?)?;
        d.set_item("first_pass_bandwidth_hz", als.first_pass_bandwidth_hz)?;
        d.set_item("lags", als.lags)?;
        out.set_item("als", d)?;
    } else {
        out.set_item("als", py.None())?;
    }
    motion.set_item("from_reference", e.motion.from_reference)?;
    motion.set_item("turns", e.motion.turns)?;
    motion.set_item("initial_speed_rad_s", e.motion.initial_speed_rad_s)?;
    motion.set_item("first_pass_bandwidth_hz", e.first_pass_bandwidth_hz)?;
    out.set_item("design", PyDesign::from(design.chosen.design.clone()))?;
    out.set_item("tracker_json", design.tracker_file().to_json())?;
    out.set_item("chosen", candidate(py, &design.chosen)?)?;
    out.set_item("predicted_error_rms_rad", design.chosen.predicted.total_rad)?;
    let runners_up: PyResult<Vec<_>> = design.runners_up.iter().map(|c| candidate(py, c)).collect();
    out.set_item("runners_up", runners_up?)?;
    let candidates: PyResult<Vec<_>> = design.candidates.iter().map(|c| candidate(py, c)).collect();
    out.set_item("candidates", candidates?)?;
    let points = e.spectra(SPECTRUM_POINTS);
    let column = |pick: fn(&(f64, f64, f64)) -> f64| points.iter().map(pick).collect::<Vec<f64>>();
    let (frequencies, noise_psd, motion_psd) = (column(|p| p.0), column(|p| p.1), column(|p| p.2));
    let spectra = PyDict::new(py);
    spectra.set_item("frequency_hz", frequencies)?;
    spectra.set_item("noise_rad2_per_hz", noise_psd)?;
    spectra.set_item("motion_rad2_per_hz", motion_psd)?;
    out.set_item("spectra", spectra)?;
    out.set_item("noise", noise)?;
    out.set_item("motion", motion)?;
    Ok(out)
}

/// Adds `design_from_capture` to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(design_from_capture, m)?)
}
