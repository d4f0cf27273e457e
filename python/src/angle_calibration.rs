//! The angle-dependent error calibration (`angletrack::CaptureCalibrator`) and the observer
//! that applies it (the `Observer`'s chain with the stored stages), on numpy arrays; the
//! Python package wraps them in `angletrack.harmonics` (`calibrate`, `calibrate_chunks`,
//! `Calibration`, `CalibratedObserver`).

use angletrack::{
    CalibrationError, CalibrationOptions, CaptureCalibration, CaptureCalibrator, ChannelOptions,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::arrays::{Count, paired_samples, samples};
use crate::diagnostics::PyFaultThresholds;
use crate::dispatch::RunSettings;
use crate::errors::{Error, Result};
use crate::gains::{GainSet, PyGains, with_gains};
use crate::observer::PyObserver;

/// The sensor calibration `(offset_c, offset_s, amplitude_c, amplitude_s, quadrature_rad)`.
pub type SensorParameters = (f64, f64, f64, f64, f64);

/// A refused calibration as a `ConfigError` naming the option.
fn refused(e: CalibrationError) -> Error {
    Error::value(e.option, e.reason)
}

/// A calibration learned from a capture read twice, chunk by chunk
/// (`angletrack::CaptureCalibrator`): `add_geometry` on every chunk, `start_fit`,
/// `add_fit` on every chunk again, `finish`.
#[pyclass(name = "_CaptureCalibrator", module = "angletrack")]
#[derive(Debug)]
pub struct PyCaptureCalibrator {
    inner: Option<CaptureCalibrator>,
    gains: GainSet,
}

impl PyCaptureCalibrator {
    fn inner(&mut self) -> Result<&mut CaptureCalibrator> {
        self.inner
            .as_mut()
            .ok_or_else(|| Error::value("calibrator", "finished already"))
    }
}

#[pymethods]
impl PyCaptureCalibrator {
    #[new]
    #[pyo3(signature = (gains, *, lowest_order = None, highest_order = Count::Whole(8), settle_fraction = 0.2,
        self_calibration = false, own_loop = true, min_significance = 3.0))]
    fn py_new(
        gains: PyGains,
        lowest_order: Option<Count>,
        highest_order: Count,
        settle_fraction: f64,
        self_calibration: bool,
        own_loop: bool,
        min_significance: f64,
    ) -> Result<Self> {
        let options = CalibrationOptions {
            lowest_order: lowest_order.map(|o| o.get("lowest_order")).transpose()?,
            highest_order: highest_order.get("highest_order")?,
            settle_fraction,
            self_calibration,
            own_loop,
            min_significance,
        };
        let period = with_gains!(&gains.set, g => g.sample_period());
        Ok(Self {
            inner: Some(CaptureCalibrator::new(period, &options).map_err(refused)?),
            gains: gains.set,
        })
    }

    /// The first pass: a chunk of raw samples (float64).
    fn add_geometry(&mut self, y_c: &Bound<'_, PyAny>, y_s: &Bound<'_, PyAny>) -> Result<()> {
        let (c, s) = paired_samples::<f64>((y_c, "y_c"), (y_s, "y_s"))?;
        let (c, s) = (c.as_slice(), s.as_slice());
        let inner = self.inner()?;
        y_c.py().detach(|| inner.add_geometry(c, s));
        Ok(())
    }

    /// Ends the first pass; returns the method (`"reference"` when `has_reference` and
    /// self-calibration is not forced).
    fn start_fit(&mut self, has_reference: bool) -> Result<&'static str> {
        let gains = self.gains;
        let inner = self.inner()?;
        let method =
            with_gains!(&gains, g => inner.start_fit(g, has_reference)).map_err(refused)?;
        Ok(method.name())
    }

    /// The second pass: a chunk of raw samples and, against a reference, its angles.
    #[pyo3(signature = (y_c, y_s, reference = None))]
    fn add_fit(
        &mut self,
        y_c: &Bound<'_, PyAny>,
        y_s: &Bound<'_, PyAny>,
        reference: Option<&Bound<'_, PyAny>>,
    ) -> Result<()> {
        let (c, s) = paired_samples::<f64>((y_c, "y_c"), (y_s, "y_s"))?;
        let reference = reference
            .map(|r| samples::<f64>(r, "reference"))
            .transpose()?;
        let reference = reference.as_ref().map(|r| r.as_slice());
        if let Some(r) = reference {
            angletrack::ArgumentError::check_equal_lengths(
                ("y_c", c.as_slice().len()),
                ("reference", r.len()),
            )?;
        }
        let (c, s) = (c.as_slice(), s.as_slice());
        let inner = self.inner()?;
        y_c.py().detach(|| inner.add_fit(c, s, reference));
        Ok(())
    }

    /// The calibration learned (a dict: see [`learned_dict`]).
    fn finish<'py>(&mut self, py: Python<'py>) -> Result<Bound<'py, PyDict>> {
        let inner = self
            .inner
            .take()
            .ok_or_else(|| Error::value("calibrator", "finished already"))?;
        learned_dict(py, &inner.finish().map_err(refused)?)
    }
}

/// The dict of a learned calibration: `sensor`, `cos`, `sin`, `speed_rad_s`, `turns`,
/// `error_rms_rad`, `residual_rms_rad`, `method`, `orders` (per order 1..12: `order`,
/// `amplitude_rad`, `uncertainty_rad`, `status`) and `warnings`.
pub fn learned_dict<'py>(
    py: Python<'py>,
    learned: &CaptureCalibration,
) -> Result<Bound<'py, PyDict>> {
    let (a, b) = learned.correction.coefficients();
    let out = PyDict::new(py);
    out.set_item("sensor", learned.sensor.parameters())?;
    out.set_item("cos", a.to_vec())?;
    out.set_item("sin", b.to_vec())?;
    out.set_item("speed_rad_s", learned.speed_rad_s)?;
    out.set_item("turns", learned.turns)?;
    out.set_item("error_rms_rad", learned.error_rms_rad)?;
    out.set_item("residual_rms_rad", learned.residual_rms_rad)?;
    out.set_item("method", learned.method.name())?;
    let orders = PyList::empty(py);
    for (i, q) in learned.orders.iter().enumerate() {
        let order = PyDict::new(py);
        order.set_item("order", i + 1)?;
        order.set_item("amplitude_rad", q.amplitude_rad)?;
        order.set_item("uncertainty_rad", q.uncertainty_rad)?;
        order.set_item("status", q.status.name())?;
        orders.append(order)?;
    }
    out.set_item("orders", orders)?;
    out.set_item("warnings", learned.warnings())?;
    Ok(out)
}

/// An `Observer` whose samples are corrected by a sensor calibration (offsets, amplitudes,
/// quadrature) and an angle correction (harmonic coefficients `cos`, `sin`, rad) before its
/// phase detector (the core's chain of both stages), in `dtype` (float32 or float64, default
/// float64) with `sin_cos` (the default of the dtype); its state carries over from one
/// `update` to the next, so a capture can be tracked chunk by chunk. The raw samples are
/// checked for clipping against `adc_range`, or with `measure_adc_range` against the rails
/// measured, as `Observer` checks them; the diagnostics' thresholds are `fault_thresholds`,
/// else those of amplitude 1, as `Observer`'s for floats.
#[pyfunction(name = "_corrected_observer")]
#[pyo3(signature = (gains, sensor, cos, sin, *, dtype = None, sin_cos = None,
    adc_range = None, measure_adc_range = false, fault_thresholds = None))]
#[allow(clippy::too_many_arguments)]
fn corrected_observer<'py>(
    py: Python<'py>,
    gains: PyGains,
    sensor: SensorParameters,
    cos: Vec<f64>,
    sin: Vec<f64>,
    dtype: Option<&Bound<'_, PyAny>>,
    sin_cos: Option<&str>,
    adc_range: Option<(f64, f64)>,
    measure_adc_range: bool,
    fault_thresholds: Option<PyFaultThresholds>,
) -> Result<Bound<'py, PyObserver>> {
    let options = ChannelOptions {
        stored: Some(angletrack::stored_stages(sensor, &cos, &sin)?),
        thresholds: fault_thresholds.map(|t| t.typed()),
        adc_range,
        measure_adc_range,
        ..ChannelOptions::default()
    };
    let settings = RunSettings::from_arguments(gains, dtype, sin_cos)?;
    let inner = settings.channel(&options)?;
    Ok(Bound::new(
        py,
        settings.subclass(PyObserver {
            inner,
            stated: None,
        }),
    )?)
}

/// Adds the functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCaptureCalibrator>()?;
    m.add_function(wrap_pyfunction!(corrected_observer, m)?)?;
    Ok(())
}
