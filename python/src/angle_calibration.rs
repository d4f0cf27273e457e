//! The angle-dependent error calibration (`angletrack::learn_angle_correction`) and the
//! observer that applies it, on numpy arrays; the Python package wraps them in
//! `angletrack.harmonics` (`calibrate`, `Calibration`, `CalibratedObserver`).

use angletrack::{
    AngleCorrection, CalibrationOptions, Calibrator, CaptureCalibration, EstimateColumns, Gains,
    ObserverState, SensorCalibration, ThresholdPolicy,
};
use angletrack_core::MAX_CORRECTION_ORDER;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{check_equal_lengths, samples};
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

/// One channel of either order with its state.
#[derive(Debug, Clone, Copy)]
enum Channel {
    Second(Gains<f64, 2>, ObserverState<f64, 2>),
    Third(Gains<f64, 3>, ObserverState<f64, 3>),
}

/// An observer (float64, exact sin/cos) whose samples are corrected by a sensor
/// calibration (offsets, amplitudes, quadrature) and an angle correction (harmonic
/// coefficients `cos`, `sin`, rad) before its phase detector; its state carries over from
/// one `update` to the next, so a capture can be tracked chunk by chunk.
#[pyclass(name = "_CorrectedObserver", module = "angletrack")]
#[derive(Debug)]
pub struct PyCorrectedObserver {
    channel: Channel,
    /// The monitor's thresholds: scaled to the first call's samples (`ThresholdPolicy`),
    /// so that counts or volts are monitored as normalised signals are.
    thresholds: ThresholdPolicy<f64>,
    calibrator: Calibrator<f64>,
    correction: AngleCorrection<f64>,
}

#[pymethods]
impl PyCorrectedObserver {
    #[new]
    fn py_new(
        gains: PyGains,
        sensor: SensorParameters,
        cos: Vec<f64>,
        sin: Vec<f64>,
    ) -> Result<Self> {
        let (sensor, correction) = checked(sensor, cos, sin)?;
        let channel = match gains.set {
            GainSet::Second(g) => Channel::Second(g, ObserverState::new()),
            GainSet::Third(g) => Channel::Third(g, ObserverState::new()),
        };
        Ok(Self {
            channel,
            thresholds: ThresholdPolicy::new(None),
            calibrator: Calibrator::from_calibration(sensor),
            correction,
        })
    }

    /// Tracks the samples `(y_c, y_s)` (float64) and returns their estimates.
    fn update(
        &mut self,
        py: Python<'_>,
        y_c: &Bound<'_, PyAny>,
        y_s: &Bound<'_, PyAny>,
    ) -> Result<Estimates> {
        let (c, s) = (samples::<f64>(y_c, "y_c")?, samples::<f64>(y_s, "y_s")?);
        let (c, s) = (c.as_slice(), s.as_slice());
        check_equal_lengths(("y_c", c.len()), ("y_s", s.len()))?;
        if let Some(thresholds) = self.thresholds.decide(c, s) {
            self.channel = match self.channel {
                Channel::Second(g, st) => Channel::Second(g.with_fault_thresholds(thresholds)?, st),
                Channel::Third(g, st) => Channel::Third(g.with_fault_thresholds(thresholds)?, st),
            };
        }
        let n = c.len();
        let out = OutputArrays::<f64>::new(py, n)?;
        let (calibrator, correction) = (&mut self.calibrator, &self.correction);
        let channel = &mut self.channel;
        out.fill(py, |columns| match channel {
            Channel::Second(g, state) => run(g, state, calibrator, correction, c, s, columns),
            Channel::Third(g, state) => run(g, state, calibrator, correction, c, s, columns),
        })?;
        out.into_estimates(py, n, None)
    }
}

/// Runs one channel over the samples into the columns.
fn run<const N: usize>(
    gains: &Gains<f64, N>,
    state: &mut ObserverState<f64, N>,
    calibrator: &mut Calibrator<f64>,
    correction: &AngleCorrection<f64>,
    y_c: &[f64],
    y_s: &[f64],
    columns: EstimateColumns<'_, f64>,
) {
    columns.write(
        y_c.iter()
            .zip(y_s)
            .map(|(&c, &s)| gains.update_calibrated_corrected(state, calibrator, correction, c, s)),
    );
}

/// Adds the functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(learn_calibration, m)?)?;
    m.add_class::<PyCorrectedObserver>()?;
    Ok(())
}
