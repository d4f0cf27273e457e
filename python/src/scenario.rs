//! `SensorModel` and `Scenario`: sampled test signals with their truth, deterministic from a
//! seed, from the `angletrack` crate.

use angletrack::SensorModel;
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::arrays::{Count, array, samples};
use crate::calibration::PySensorCalibration;
use crate::errors::{Error, Result};
use crate::model_class::{ModelField, model_class};
use crate::motion::PyMotionProfile;

model_class! {
    /// The sensor that turns the shaft angle into `y_c` and `y_s`: amplitude, DC offsets,
    /// amplitude imbalance, quadrature error (rad), relative 3rd harmonic, harmonics of the angle
    /// error (`angle_error_harmonics`: up to 8 `(order, amplitude rad, phase rad)`, the reading
    /// being `theta + sum a sin(k theta + p)`), white noise
    /// (standard deviation per channel) and ADC quantisation (`adc_bits`, 0 for none, over
    /// `[-adc_full_scale, adc_full_scale)`). Checked when a scenario is generated.
    PySensorModel = "SensorModel" of SensorModel {
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
        /// Harmonics `(order, amplitude rad, phase rad)` of the angle error.
        angle_error_harmonics: Vec<(u32, f64, f64)>,
        /// Standard deviation of the white noise on each signal.
        noise_std: f64,
        /// ADC resolution (bits); 0 for no quantisation.
        adc_bits: u32,
        /// ADC full scale.
        adc_full_scale: f64,
    }
    methods {
        /// The `SensorCalibration` of this sensor (the core's model: `offset_c = offset_cos`,
        /// `offset_s = offset_sin`, `amplitude_c = amplitude`, `amplitude_s = amplitude (1 +
        /// amplitude_imbalance)`, `quadrature_rad = quadrature_error_rad`): what an online
        /// calibration should learn. `ConfigError` for an invalid model or a quadrature error
        /// beyond pi/4.
        fn calibration(&self) -> Result<PySensorCalibration> {
            Ok(PySensorCalibration::from_core(&self.model().calibration()?))
        }
    }
}

/// A sampled scenario: the truth (`angle_rad` unwrapped, `speed_rad_s`,
/// `acceleration_rad_s2`) beside the sensor signals `y_c`, `y_s`, at times `time_s`; every
/// array float64.
#[pyclass(name = "Scenario", module = "angletrack", frozen, get_all)]
#[derive(Debug)]
pub struct PyScenario {
    /// Sample period (s).
    pub(crate) sample_period_s: f64,
    /// Sample times (s).
    pub(crate) time_s: Py<PyArray1<f64>>,
    /// True angle (rad, unwrapped).
    pub(crate) angle_rad: Py<PyArray1<f64>>,
    /// True speed (rad/s); NaN where unknown (a capture without a speed reference).
    pub(crate) speed_rad_s: Py<PyArray1<f64>>,
    /// True acceleration (rad/s^2); NaN where unknown.
    pub(crate) acceleration_rad_s2: Py<PyArray1<f64>>,
    /// Cosine signal.
    pub(crate) y_c: Py<PyArray1<f64>>,
    /// Sine signal.
    pub(crate) y_s: Py<PyArray1<f64>>,
    /// `False` when the speed truth is unknown (speed metrics are then not computed).
    pub(crate) has_speed: bool,
    /// Number of samples.
    pub(crate) len: usize,
}

impl PyScenario {
    /// The Python scenario of a generated one (its truth known, speed included).
    pub(crate) fn from_scenario(py: Python<'_>, s: angletrack::Scenario) -> Self {
        Self {
            len: s.len(),
            sample_period_s: s.sample_period_s,
            time_s: array(py, s.time_s),
            angle_rad: array(py, s.angle_rad),
            speed_rad_s: array(py, s.speed_rad_s),
            acceleration_rad_s2: array(py, s.acceleration_rad_s2),
            y_c: array(py, s.y_c),
            y_s: array(py, s.y_s),
            has_speed: true,
        }
    }
}

#[pymethods]
impl PyScenario {
    /// Samples `profile` every `sample_period_s` through `sensor` (an ideal sensor if
    /// `None`); the noise comes from a ChaCha8 generator seeded with `seed`, so the same
    /// arguments give the same scenario on every machine.
    #[staticmethod]
    #[pyo3(signature = (profile, sensor = None, *, sample_period_s, seed = Count::Whole(0)),
        text_signature = "(profile, sensor=None, *, sample_period_s, seed=0)")]
    fn generate(
        py: Python<'_>,
        profile: &PyMotionProfile,
        sensor: Option<&PySensorModel>,
        sample_period_s: f64,
        seed: Count,
    ) -> Result<Self> {
        let seed: u64 = seed.get("seed")?;
        let sensor = sensor.map_or_else(SensorModel::default, PySensorModel::model);
        let profile = profile.inner.clone();
        let s = py.detach(move || {
            angletrack::Scenario::generate(&profile, &sensor, sample_period_s, seed)
        })?;
        Ok(Self::from_scenario(py, s))
    }

    /// A scenario from recorded arrays (a capture with a reference angle): the truth
    /// `angle_rad` (finite at every sample: `ConfigError` otherwise) beside `y_c`, `y_s`;
    /// `speed_rad_s` NaN when not given.
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
        let read = |obj, name| Ok::<_, Error>(samples::<f64>(obj, name)?.as_slice().to_vec());
        let speed = speed_rad_s.map(|v| read(v, "speed_rad_s")).transpose()?;
        let has_speed = speed.is_some();
        let (angle, c, s) = (
            read(angle_rad, "angle_rad")?,
            read(y_c, "y_c")?,
            read(y_s, "y_s")?,
        );
        let scenario = angletrack::Scenario::from_arrays(sample_period_s, angle, c, s, speed)?;
        Ok(Self {
            has_speed,
            ..Self::from_scenario(py, scenario)
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
