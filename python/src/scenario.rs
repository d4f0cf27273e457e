//! `SensorModel` and `Scenario`: sampled test signals with their truth, deterministic from a
//! seed, from the `angletrack` crate.

use angletrack::SensorModel;
use pyo3::prelude::*;

use crate::arrays::{Column, Count, samples};
use crate::calibration::PySensorCalibration;
use crate::errors::{Error, Result};
use crate::getters::result_class;
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

result_class! {
    /// A sampled scenario: the truth (`angle_rad` unwrapped, `speed_rad_s`,
    /// `acceleration_rad_s2`) beside the sensor signals `y_c`, `y_s`, at times `time_s`; every
    /// array float64.
    PyScenario = "Scenario" of |py, s: angletrack::Scenario| {
        /// Number of samples.
        len: usize = s.len(),
        /// Sample period (s).
        sample_period_s: f64 = s.sample_period_s,
        /// Sample times (s).
        time_s: Column<f64> = s.time_s,
        /// True angle (rad, unwrapped).
        angle_rad: Column<f64> = s.angle_rad,
        /// True speed (rad/s); NaN where unknown (a capture without a speed reference).
        speed_rad_s: Column<f64> = s.speed_rad_s,
        /// True acceleration (rad/s^2); NaN where unknown.
        acceleration_rad_s2: Column<f64> = s.acceleration_rad_s2,
        /// Cosine signal.
        y_c: Column<f64> = s.y_c,
        /// Sine signal.
        y_s: Column<f64> = s.y_s,
        /// `False` when the speed truth is unknown (speed metrics are then not computed).
        has_speed: bool = true,
    }
    repr |s| format!("Scenario({} samples, sample_period_s={:e}, duration {:.6} s)", s.len, s.sample_period_s, s.len as f64 * s.sample_period_s);
    methods {
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
        Self::of(py, s)
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
            ..Self::of(py, scenario)?
        })
    }

    fn __len__(&self) -> usize {
        self.len
    }
    }
}
