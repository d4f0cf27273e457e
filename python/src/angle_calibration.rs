//! The angle-dependent error calibration (`angletrack::learn_angle_correction`) and the
//! observer that applies it, on numpy arrays; the Python package wraps them in
//! `angletrack.harmonics` (`calibrate`, `Calibration`, `CalibratedObserver`).

use angletrack::{
    AngleCorrection, CalibrationOptions, CaptureCalibration, EstimateColumns, Gains, ObserverState,
    SensorCalibration, ThresholdPolicy,
};
use angletrack_core::MAX_CORRECTION_ORDER;
use angletrack_core::{Chain, ChainState};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{check_equal_lengths, samples};
use crate::dispatch::{Arg, PhaseSinCos, Run, RunSettings, Sample};
use crate::errors::{Error, Result};
use crate::estimates::{Estimates, OutputArrays};
use crate::gains::{GainSet, PyGains, with_gains};

/// The sensor calibration `(offset_c, offset_s, amplitude_c, amplitude_s, quadrature_rad)`.
pub type SensorParameters = (f64, f64, f64, f64, f64);

/// Learns the calibration of a capture `(y_c, y_s)` at roughly constant speed tracked with
/// `gains` (float64): a dict with `sensor` (the offsets, amplitudes and quadrature), `cos`
/// and `sin` (the correction's coefficients `a_k`, `b_k`, k = 1..8, rad), `speed_rad_s`,
/// `turns`, `error_rms_rad` and `residual_rms_rad`.
#[pyfunction]
#[pyo3(signature = (gains, y_c, y_s, *, lowest_order = 1, highest_order = 8, settle_fraction = 0.2))]
pub fn learn_calibration<'py>(
    py: Python<'py>,
    gains: PyGains,
    y_c: &Bound<'py, PyAny>,
    y_s: &Bound<'py, PyAny>,
    lowest_order: usize,
    highest_order: usize,
    settle_fraction: f64,
) -> Result<Bound<'py, PyDict>> {
    let (c, s) = (samples::<f64>(y_c, "y_c")?, samples::<f64>(y_s, "y_s")?);
    let (c, s) = (c.as_slice(), s.as_slice());
    check_equal_lengths(("y_c", c.len()), ("y_s", s.len()))?;
    let options = CalibrationOptions {
        lowest_order,
        highest_order,
        settle_fraction,
    };
    let learned = with_gains!(gains.set, g => py.detach(|| {
        angletrack::learn_angle_correction(&g, c, s, &options)
    }))?;
    learned_dict(py, &learned)
}

/// The dict of a learned calibration: `sensor`, `cos`, `sin`, `speed_rad_s`, `turns`,
/// `error_rms_rad` and `residual_rms_rad`.
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
    Ok(out)
}

/// The core's sensor calibration and angle correction from their parameters, checked.
pub fn checked(
    sensor: SensorParameters,
    cos: Vec<f64>,
    sin: Vec<f64>,
) -> Result<(SensorCalibration<f64>, AngleCorrection<f64>)> {
    let (o_c, o_s, a_c, a_s, phi) = sensor;
    let sensor = SensorCalibration::new(o_c, o_s, a_c, a_s, phi)?;
    let table = |values: Vec<f64>, name: &'static str| -> Result<[f64; MAX_CORRECTION_ORDER]> {
        let mut out = [0.0; MAX_CORRECTION_ORDER];
        if values.len() > MAX_CORRECTION_ORDER {
            return Err(Error::value(name, "holds more than 8 coefficients"));
        }
        out[..values.len()].copy_from_slice(&values);
        Ok(out)
    };
    let correction = AngleCorrection::new(table(cos, "cos")?, table(sin, "sin")?)?;
    Ok((sensor, correction))
}

/// The corrected observer of concrete types: the core's chain of the stored sensor
/// calibration and the angle correction before the observer.
#[derive(Debug)]
struct Corrected<T: Sample, const N: usize, S: PhaseSinCos<T>> {
    chain: Chain<(SensorCalibration<T>, AngleCorrection<T>), Gains<T, N, S>>,
    state: ChainState<((), ()), ObserverState<T, N>>,
    /// The monitor's thresholds: scaled to the first call's samples (`ThresholdPolicy`),
    /// so that counts or volts are monitored as normalised signals are.
    thresholds: ThresholdPolicy<T>,
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> Run for Corrected<T, N, S> {
    fn run(&mut self, py: Python<'_>, y_c: Arg<'_, '_>, y_s: Arg<'_, '_>) -> Result<Estimates> {
        let (c, s) = (samples::<T>(y_c, "y_c")?, samples::<T>(y_s, "y_s")?);
        let (c, s) = (c.as_slice(), s.as_slice());
        check_equal_lengths(("y_c", c.len()), ("y_s", s.len()))?;
        if let Some(thresholds) = self.thresholds.decide(c, s) {
            self.chain.observer = self.chain.observer.with_fault_thresholds(thresholds)?;
        }
        let n = c.len();
        let out = OutputArrays::<T>::new(py, n)?;
        let (chain, state) = (&self.chain, &mut self.state);
        out.fill(py, |columns: EstimateColumns<'_, T>| {
            columns.write(c.iter().zip(s).map(|(&c, &s)| chain.update(state, (c, s))));
        })?;
        out.into_estimates(py, n, None)
    }
}

/// The corrected observer for gains of concrete types, its stages converted to `T`
/// (checked again there).
pub fn corrected<T: Sample, const N: usize, S: PhaseSinCos<T>>(
    gains: Gains<T, N, S>,
    sensor: &SensorCalibration<f64>,
    correction: &AngleCorrection<f64>,
) -> Result<Box<dyn Run>> {
    let f = T::from_f64;
    let (o_c, o_s, a_c, a_s, phi) = sensor.parameters();
    let sensor = SensorCalibration::new(f(o_c), f(o_s), f(a_c), f(a_s), f(phi))?;
    let (a, b) = correction.coefficients();
    let correction = AngleCorrection::new(a.map(f), b.map(f))?;
    Ok(Box::new(Corrected {
        chain: Chain::new((sensor, correction), gains),
        state: ChainState::new(),
        thresholds: ThresholdPolicy::new(None),
    }))
}

/// An observer whose samples are corrected by a sensor calibration (offsets, amplitudes,
/// quadrature) and an angle correction (harmonic coefficients `cos`, `sin`, rad) before its
/// phase detector (the core's chain of both stages), in `dtype` (float32 or float64, default
/// float64) with `sin_cos` (the default of the dtype); its state carries over from one
/// `update` to the next, so a capture can be tracked chunk by chunk.
#[pyclass(name = "_CorrectedObserver", module = "angletrack")]
#[derive(Debug)]
pub struct PyCorrectedObserver {
    inner: Box<dyn Run>,
}

#[pymethods]
impl PyCorrectedObserver {
    #[new]
    #[pyo3(signature = (gains, sensor, cos, sin, *, dtype = None, sin_cos = None))]
    fn py_new(
        gains: PyGains,
        sensor: SensorParameters,
        cos: Vec<f64>,
        sin: Vec<f64>,
        dtype: Option<&Bound<'_, PyAny>>,
        sin_cos: Option<&str>,
    ) -> Result<Self> {
        let (sensor, correction) = checked(sensor, cos, sin)?;
        let settings = RunSettings::from_arguments(gains, dtype, sin_cos)?;
        Ok(Self {
            inner: settings.typed_gains()?.corrected(&sensor, &correction)?,
        })
    }

    /// Tracks the samples `(y_c, y_s)` (of the observer's dtype) and returns their
    /// estimates.
    fn update(
        &mut self,
        py: Python<'_>,
        y_c: &Bound<'_, PyAny>,
        y_s: &Bound<'_, PyAny>,
    ) -> Result<Estimates> {
        self.inner.run(py, y_c, y_s)
    }
}

/// Adds the functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(learn_calibration, m)?)?;
    m.add_class::<PyCorrectedObserver>()?;
    Ok(())
}
