//! Scenarios (motion profile + sensor model, deterministic from a seed) and the metrics of a
//! run against the truth, from the `angletrack` crate.

use angletrack::{ErrorStatistics, Metrics, MetricsOptions, Motion, MotionProfile, SensorModel};
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;

use crate::arrays::{Float, check_equal_lengths, samples};
use crate::errors::{Error, Result};
use crate::observer::Estimates;

/// A motion profile of the shaft: an initial angle (rad) and speed (rad/s), then segments
/// run one after the other. Each method returns a new profile with one more segment.
#[pyclass(name = "MotionProfile", module = "angletrack", frozen)]
#[derive(Debug, Clone)]
pub struct PyMotionProfile {
    inner: MotionProfile,
}

impl PyMotionProfile {
    fn then(&self, motion: Motion) -> Self {
        Self {
            inner: self.inner.clone().then(motion),
        }
    }
}

#[pymethods]
impl PyMotionProfile {
    #[new]
    #[pyo3(signature = (initial_angle_rad = 0.0, initial_speed_rad_s = 0.0))]
    fn py_new(initial_angle_rad: f64, initial_speed_rad_s: f64) -> Self {
        Self {
            inner: MotionProfile::new(initial_angle_rad, initial_speed_rad_s),
        }
    }

    /// Constant speed `speed_rad_s` for `duration_s` (a speed step if it differs).
    #[pyo3(signature = (speed_rad_s, duration_s))]
    fn constant_speed(&self, speed_rad_s: f64, duration_s: f64) -> Self {
        self.then(Motion::ConstantSpeed {
            speed_rad_s,
            duration_s,
        })
    }

    /// Constant acceleration `acceleration_rad_s2` from the current speed for `duration_s`.
    #[pyo3(signature = (acceleration_rad_s2, duration_s))]
    fn constant_acceleration(&self, acceleration_rad_s2: f64, duration_s: f64) -> Self {
        self.then(Motion::ConstantAcceleration {
            acceleration_rad_s2,
            duration_s,
        })
    }

    /// A position step of `step_rad` at the segment's start, then the current speed held
    /// for `duration_s`.
    #[pyo3(signature = (step_rad, duration_s))]
    fn step(&self, step_rad: f64, duration_s: f64) -> Self {
        self.then(Motion::Step {
            step_rad,
            duration_s,
        })
    }

    /// A point-to-point move of `distance_rad` with a trapezoidal speed profile.
    #[pyo3(signature = (distance_rad, max_speed_rad_s, max_acceleration_rad_s2))]
    fn trapezoidal(
        &self,
        distance_rad: f64,
        max_speed_rad_s: f64,
        max_acceleration_rad_s2: f64,
    ) -> Self {
        self.then(Motion::Trapezoidal {
            distance_rad,
            max_speed_rad_s,
            max_acceleration_rad_s2,
        })
    }

    /// A point-to-point move of `distance_rad` with a jerk-limited S-curve speed profile.
    #[pyo3(signature = (distance_rad, max_speed_rad_s, max_acceleration_rad_s2, max_jerk_rad_s3))]
    fn s_curve(
        &self,
        distance_rad: f64,
        max_speed_rad_s: f64,
        max_acceleration_rad_s2: f64,
        max_jerk_rad_s3: f64,
    ) -> Self {
        self.then(Motion::SCurve {
            distance_rad,
            max_speed_rad_s,
            max_acceleration_rad_s2,
            max_jerk_rad_s3,
        })
    }

    /// A sinusoidal speed ripple of amplitude `ripple_rad_s` at `frequency_hz` around the
    /// current speed, for `duration_s`.
    #[pyo3(signature = (ripple_rad_s, frequency_hz, duration_s))]
    fn speed_ripple(&self, ripple_rad_s: f64, frequency_hz: f64, duration_s: f64) -> Self {
        self.then(Motion::SpeedRipple {
            ripple_rad_s,
            frequency_hz,
            duration_s,
        })
    }

    /// A reversal of the current speed at constant deceleration `acceleration_rad_s2`.
    #[pyo3(signature = (acceleration_rad_s2))]
    fn reversal(&self, acceleration_rad_s2: f64) -> Self {
        self.then(Motion::Reversal {
            acceleration_rad_s2,
        })
    }

    /// This profile followed by the segments of `other` (its initial values are ignored).
    #[pyo3(signature = (other))]
    fn concat(&self, other: &PyMotionProfile) -> Self {
        let mut inner = self.inner.clone();
        inner.segments.extend(other.inner.segments.iter().copied());
        Self { inner }
    }

    /// Initial angle (rad).
    #[getter]
    fn initial_angle_rad(&self) -> f64 {
        self.inner.initial_angle_rad
    }

    /// Initial speed (rad/s).
    #[getter]
    fn initial_speed_rad_s(&self) -> f64 {
        self.inner.initial_speed_rad_s
    }

    /// Number of segments.
    fn __len__(&self) -> usize {
        self.inner.segments.len()
    }

    fn __repr__(&self) -> String {
        let segments: Vec<String> = self
            .inner
            .segments
            .iter()
            .map(|m| format!(".{}", segment_text(m)))
            .collect();
        format!(
            "MotionProfile(initial_angle_rad={:?}, initial_speed_rad_s={:?}){}",
            self.inner.initial_angle_rad,
            self.inner.initial_speed_rad_s,
            segments.join("")
        )
    }
}

fn segment_text(m: &Motion) -> String {
    match *m {
        Motion::ConstantSpeed {
            speed_rad_s,
            duration_s,
        } => format!("constant_speed(speed_rad_s={speed_rad_s:?}, duration_s={duration_s:?})"),
        Motion::ConstantAcceleration {
            acceleration_rad_s2,
            duration_s,
        } => format!(
            "constant_acceleration(acceleration_rad_s2={acceleration_rad_s2:?}, duration_s={duration_s:?})"
        ),
        Motion::Step {
            step_rad,
            duration_s,
        } => format!("step(step_rad={step_rad:?}, duration_s={duration_s:?})"),
        Motion::Trapezoidal {
            distance_rad,
            max_speed_rad_s,
            max_acceleration_rad_s2,
        } => format!(
            "trapezoidal(distance_rad={distance_rad:?}, max_speed_rad_s={max_speed_rad_s:?}, \
             max_acceleration_rad_s2={max_acceleration_rad_s2:?})"
        ),
        Motion::SCurve {
            distance_rad,
            max_speed_rad_s,
            max_acceleration_rad_s2,
            max_jerk_rad_s3,
        } => format!(
            "s_curve(distance_rad={distance_rad:?}, max_speed_rad_s={max_speed_rad_s:?}, \
             max_acceleration_rad_s2={max_acceleration_rad_s2:?}, max_jerk_rad_s3={max_jerk_rad_s3:?})"
        ),
        Motion::SpeedRipple {
            ripple_rad_s,
            frequency_hz,
            duration_s,
        } => format!(
            "speed_ripple(ripple_rad_s={ripple_rad_s:?}, frequency_hz={frequency_hz:?}, \
             duration_s={duration_s:?})"
        ),
        Motion::Reversal {
            acceleration_rad_s2,
        } => format!("reversal(acceleration_rad_s2={acceleration_rad_s2:?})"),
        // A segment added to the crate later: its Debug form.
        #[allow(unreachable_patterns)]
        ref other => format!("{other:?}"),
    }
}

/// The sensor that turns the shaft angle into `y_c` and `y_s`: amplitude, DC offsets,
/// amplitude imbalance, quadrature error (rad), relative 3rd harmonic, white noise
/// (standard deviation per channel) and ADC quantisation (`adc_bits`, 0 for none, over
/// `[-adc_full_scale, adc_full_scale)`). Checked when a scenario is generated.
#[pyclass(name = "SensorModel", module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct PySensorModel {
    /// Amplitude of both signals.
    amplitude: f64,
    /// DC offset of `y_c`.
    offset_cos: f64,
    /// DC offset of `y_s`.
    offset_sin: f64,
    /// Relative amplitude imbalance of `y_s` against `y_c`.
    amplitude_imbalance: f64,
    /// Quadrature error (rad).
    quadrature_error_rad: f64,
    /// Relative amplitude of the 3rd harmonic.
    third_harmonic: f64,
    /// Standard deviation of the white noise on each signal.
    noise_std: f64,
    /// ADC resolution (bits); 0 for no quantisation.
    adc_bits: u32,
    /// ADC full scale.
    adc_full_scale: f64,
}

impl PySensorModel {
    fn model(&self) -> SensorModel {
        SensorModel {
            amplitude: self.amplitude,
            offset_cos: self.offset_cos,
            offset_sin: self.offset_sin,
            amplitude_imbalance: self.amplitude_imbalance,
            quadrature_error_rad: self.quadrature_error_rad,
            third_harmonic: self.third_harmonic,
            noise_std: self.noise_std,
            adc_bits: self.adc_bits,
            adc_full_scale: self.adc_full_scale,
        }
    }
}

#[pymethods]
impl PySensorModel {
    #[new]
    #[pyo3(signature = (*, amplitude = None, offset_cos = None, offset_sin = None,
        amplitude_imbalance = None, quadrature_error_rad = None, third_harmonic = None,
        noise_std = None, adc_bits = None, adc_full_scale = None))]
    #[allow(clippy::too_many_arguments)]
    fn py_new(
        amplitude: Option<f64>,
        offset_cos: Option<f64>,
        offset_sin: Option<f64>,
        amplitude_imbalance: Option<f64>,
        quadrature_error_rad: Option<f64>,
        third_harmonic: Option<f64>,
        noise_std: Option<f64>,
        adc_bits: Option<u32>,
        adc_full_scale: Option<f64>,
    ) -> Self {
        // Defaults are the crate's ideal sensor.
        let d = SensorModel::default();
        Self {
            amplitude: amplitude.unwrap_or(d.amplitude),
            offset_cos: offset_cos.unwrap_or(d.offset_cos),
            offset_sin: offset_sin.unwrap_or(d.offset_sin),
            amplitude_imbalance: amplitude_imbalance.unwrap_or(d.amplitude_imbalance),
            quadrature_error_rad: quadrature_error_rad.unwrap_or(d.quadrature_error_rad),
            third_harmonic: third_harmonic.unwrap_or(d.third_harmonic),
            noise_std: noise_std.unwrap_or(d.noise_std),
            adc_bits: adc_bits.unwrap_or(d.adc_bits),
            adc_full_scale: adc_full_scale.unwrap_or(d.adc_full_scale),
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "SensorModel(amplitude={:?}, offset_cos={:?}, offset_sin={:?}, amplitude_imbalance={:?}, \
             quadrature_error_rad={:?}, third_harmonic={:?}, noise_std={:?}, adc_bits={}, \
             adc_full_scale={:?})",
            self.amplitude,
            self.offset_cos,
            self.offset_sin,
            self.amplitude_imbalance,
            self.quadrature_error_rad,
            self.third_harmonic,
            self.noise_std,
            self.adc_bits,
            self.adc_full_scale
        )
    }
}

/// A sampled scenario: the truth (`angle_rad` unwrapped, `speed_rad_s`,
/// `acceleration_rad_s2`) beside the sensor signals `y_c`, `y_s`, at times `time_s`; every
/// array float64.
#[pyclass(name = "Scenario", module = "angletrack", frozen, get_all)]
#[derive(Debug)]
pub struct PyScenario {
    /// Sample period (s).
    sample_period_s: f64,
    /// Sample times (s).
    time_s: Py<PyArray1<f64>>,
    /// True angle (rad, unwrapped).
    angle_rad: Py<PyArray1<f64>>,
    /// True speed (rad/s); NaN where unknown (a capture without a speed reference).
    speed_rad_s: Py<PyArray1<f64>>,
    /// True acceleration (rad/s^2); NaN where unknown.
    acceleration_rad_s2: Py<PyArray1<f64>>,
    /// Cosine signal.
    y_c: Py<PyArray1<f64>>,
    /// Sine signal.
    y_s: Py<PyArray1<f64>>,
    /// `False` when the speed truth is unknown (speed metrics are then not computed).
    has_speed: bool,
    /// Number of samples.
    len: usize,
}

fn array(py: Python<'_>, v: Vec<f64>) -> Py<PyArray1<f64>> {
    v.into_pyarray(py).unbind()
}

#[pymethods]
impl PyScenario {
    /// Samples `profile` every `sample_period_s` through `sensor` (an ideal sensor if
    /// `None`); the noise comes from a ChaCha8 generator seeded with `seed`, so the same
    /// arguments give the same scenario on every machine.
    #[staticmethod]
    #[pyo3(signature = (profile, sensor = None, *, sample_period_s, seed = 0))]
    fn generate(
        py: Python<'_>,
        profile: &PyMotionProfile,
        sensor: Option<&PySensorModel>,
        sample_period_s: f64,
        seed: u64,
    ) -> Result<Self> {
        let sensor = sensor.map_or_else(SensorModel::default, PySensorModel::model);
        let profile = profile.inner.clone();
        let s = py.detach(move || {
            angletrack::Scenario::generate(&profile, &sensor, sample_period_s, seed)
        })?;
        Ok(Self {
            len: s.len(),
            sample_period_s: s.sample_period_s,
            time_s: array(py, s.time_s),
            angle_rad: array(py, s.angle_rad),
            speed_rad_s: array(py, s.speed_rad_s),
            acceleration_rad_s2: array(py, s.acceleration_rad_s2),
            y_c: array(py, s.y_c),
            y_s: array(py, s.y_s),
            has_speed: true,
        })
    }

    /// A scenario from recorded arrays (a capture with a reference angle): the truth
    /// `angle_rad` beside `y_c`, `y_s`; `speed_rad_s` NaN when not given.
    #[staticmethod]
    #[pyo3(signature = (*, sample_period_s, angle_rad, y_c, y_s, speed_rad_s = None))]
    fn from_arrays(
        py: Python<'_>,
        sample_period_s: f64,
        angle_rad: &Bound<'_, PyAny>,
        y_c: &Bound<'_, PyAny>,
        y_s: &Bound<'_, PyAny>,
        speed_rad_s: Option<&Bound<'_, PyAny>>,
    ) -> Result<Self> {
        if !(sample_period_s.is_finite() && sample_period_s > 0.0) {
            return Err(Error::value(
                "sample_period_s",
                "must be finite and positive",
            ));
        }
        let angle = samples::<f64>(angle_rad, "angle_rad")?.as_slice().to_vec();
        let c = samples::<f64>(y_c, "y_c")?.as_slice().to_vec();
        let s = samples::<f64>(y_s, "y_s")?.as_slice().to_vec();
        check_equal_lengths(("angle_rad", angle.len()), ("y_c", c.len()))?;
        check_equal_lengths(("angle_rad", angle.len()), ("y_s", s.len()))?;
        let n = angle.len();
        let (speed, has_speed) = match speed_rad_s {
            Some(v) => {
                let v = samples::<f64>(v, "speed_rad_s")?.as_slice().to_vec();
                check_equal_lengths(("angle_rad", n), ("speed_rad_s", v.len()))?;
                (v, true)
            }
            None => (vec![f64::NAN; n], false),
        };
        Ok(Self {
            sample_period_s,
            time_s: array(py, (0..n).map(|k| k as f64 * sample_period_s).collect()),
            angle_rad: array(py, angle),
            speed_rad_s: array(py, speed),
            acceleration_rad_s2: array(py, vec![f64::NAN; n]),
            y_c: array(py, c),
            y_s: array(py, s),
            has_speed,
            len: n,
        })
    }

    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        format!(
            "Scenario({} samples, sample_period_s={:e}, duration {:.6} s)",
            self.len,
            self.sample_period_s,
            self.len as f64 * self.sample_period_s
        )
    }
}

/// Mean, RMS and largest magnitude of an error series.
#[pyclass(name = "ErrorStatistics", module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct PyErrorStatistics {
    /// Root mean square.
    rms: f64,
    /// Largest magnitude.
    max: f64,
    /// Mean (signed: a bias).
    mean: f64,
}

impl From<ErrorStatistics> for PyErrorStatistics {
    fn from(s: ErrorStatistics) -> Self {
        Self {
            rms: s.rms,
            max: s.max,
            mean: s.mean,
        }
    }
}

#[pymethods]
impl PyErrorStatistics {
    fn __repr__(&self) -> String {
        format!(
            "ErrorStatistics(rms={:.6e}, max={:.6e}, mean={:.6e})",
            self.rms, self.max, self.mean
        )
    }
}

/// The quality of a run against the truth (errors are truth - estimate).
#[pyclass(name = "Metrics", module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct PyMetrics {
    /// Wrapped angle error (rad) over the samples from `skip_s` on.
    angle_error_rad: PyErrorStatistics,
    /// Speed error (rad/s) over the same samples; `None` without a speed truth.
    speed_error_rad_s: Option<PyErrorStatistics>,
    /// Number of samples in the statistics.
    samples: usize,
    /// Overshoot past the truth's final angle, as a fraction of the move; `None` when the
    /// truth ends where it started.
    overshoot: Option<f64>,
    /// Time (s) after which the estimate stays within the settling band of the move.
    settling_time_s: Option<f64>,
    /// Time (s) from which the wrapped angle error stays within the lock tolerance.
    time_to_lock_s: Option<f64>,
}

fn optional(v: Option<f64>, scale: f64, unit: &str) -> String {
    v.map_or("None".into(), |x| format!("{:.6e}{unit}", x * scale))
}

#[pymethods]
impl PyMetrics {
    fn __repr__(&self) -> String {
        format!(
            "Metrics(angle_error_rad: rms={:.6e} max={:.6e} mean={:.6e}; speed_error_rad_s: {}; \
             samples={}, overshoot={}, settling_time_s={}, time_to_lock_s={})",
            self.angle_error_rad.rms,
            self.angle_error_rad.max,
            self.angle_error_rad.mean,
            self.speed_error_rad_s
                .as_ref()
                .map_or("None".into(), |s| format!(
                    "rms={:.6e} max={:.6e} mean={:.6e}",
                    s.rms, s.max, s.mean
                )),
            self.samples,
            optional(self.overshoot, 1.0, ""),
            optional(self.settling_time_s, 1.0, ""),
            optional(self.time_to_lock_s, 1.0, ""),
        )
    }
}

/// An estimates array as float64 (position is float64 already; float32 quantities are
/// widened, exactly).
fn as_f64(array: &Bound<'_, PyAny>, parameter: &'static str) -> Result<Vec<f64>> {
    Ok(match Float::of_samples(array, parameter)? {
        Float::F64 => samples::<f64>(array, parameter)?.as_slice().to_vec(),
        Float::F32 => samples::<f32>(array, parameter)?
            .as_slice()
            .iter()
            .map(|&x| f64::from(x))
            .collect(),
    })
}

/// Measures the estimates of a run against the scenario's truth: wrapped angle error and
/// speed error statistics from `skip_s` (s) on, overshoot and settling time (band
/// `settling_band` of the move), and time to lock (error within `lock_tolerance_rad`).
#[pyfunction]
#[pyo3(signature = (scenario, estimates, *, skip_s = 0.0, lock_tolerance_rad = 0.01, settling_band = 0.02))]
pub fn metrics(
    py: Python<'_>,
    scenario: &PyScenario,
    estimates: &Estimates,
    skip_s: f64,
    lock_tolerance_rad: f64,
    settling_band: f64,
) -> Result<PyMetrics> {
    let truth = angletrack::Scenario {
        sample_period_s: scenario.sample_period_s,
        time_s: samples::<f64>(scenario.time_s.bind(py).as_any(), "scenario.time_s")?
            .as_slice()
            .to_vec(),
        angle_rad: samples::<f64>(scenario.angle_rad.bind(py).as_any(), "scenario.angle_rad")?
            .as_slice()
            .to_vec(),
        speed_rad_s: if scenario.has_speed {
            samples::<f64>(
                scenario.speed_rad_s.bind(py).as_any(),
                "scenario.speed_rad_s",
            )?
            .as_slice()
            .to_vec()
        } else {
            // Unknown speed truth: any finite series; its statistics are not reported.
            vec![0.0; scenario.len]
        },
        ..Default::default()
    };
    let run = angletrack::Run {
        angle_rad: as_f64(estimates.position.bind(py), "estimates.position")?,
        speed_rad_s: as_f64(estimates.speed.bind(py), "estimates.speed")?,
        acceleration_rad_s2: as_f64(estimates.acceleration.bind(py), "estimates.acceleration")?,
    };
    let options = MetricsOptions {
        skip_s,
        lock_tolerance_rad,
        settling_band,
    };
    let m = py.detach(|| Metrics::new(&truth, &run, &options))?;
    Ok(PyMetrics {
        angle_error_rad: m.angle_error_rad.into(),
        speed_error_rad_s: scenario.has_speed.then(|| m.speed_error_rad_s.into()),
        samples: m.samples,
        overshoot: m.overshoot,
        settling_time_s: m.settling_time_s,
        time_to_lock_s: m.time_to_lock_s,
    })
}

/// Adds this module's classes and functions to the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyMotionProfile>()?;
    m.add_class::<PySensorModel>()?;
    m.add_class::<PyScenario>()?;
    m.add_class::<PyErrorStatistics>()?;
    m.add_class::<PyMetrics>()?;
    m.add_function(wrap_pyfunction!(metrics, m)?)?;
    Ok(())
}
