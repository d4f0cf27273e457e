//! [`CalibrationSettings`]: the configuration of the online calibration
//! (`docs/theory.md §12`), part of the [`Gains`](crate::Gains) and checked there, and the faults a
//! calibration raises against its bounds.

use crate::calibration::SensorCalibration;
use crate::faults::Faults;
use crate::real::Float;

/// The configuration of the online calibration: when it learns and the bounds of its
/// estimates beyond which a fault is flagged. Part of the [`Gains`](crate::Gains)
/// ([`Gains::with_calibration_settings`](crate::Gains::with_calibration_settings)), checked there.
///
/// | field | default |
/// | --- | --- |
/// | `min_speed_rad_s` | `None`: one electrical turn in 4096 samples, `2 pi / (4096 Ts)` |
/// | `max_offset` | 0.1 (each offset over its channel's amplitude) |
/// | `max_amplitude_mismatch` | 0.2 (`|A_s / A_c - 1|`) |
/// | `max_quadrature_rad` | 0.1 rad (5.7 degrees) |
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct CalibrationSettings<T> {
    /// The estimator learns only above this electrical speed (rad/s): a rotor at rest carries
    /// no information. `None`: one turn in 4096 samples. At least one turn in `2^20`
    /// samples (so that a turn's sums keep their precision) and at most a quarter turn per
    /// sample.
    pub min_speed_rad_s: Option<T>,
    /// An offset above this fraction of its channel's amplitude flags
    /// [`Faults::OFFSET_OR_QUADRATURE`].
    pub max_offset: T,
    /// `|A_s / A_c - 1|` above this flags [`Faults::AMPLITUDE_MISMATCH`].
    pub max_amplitude_mismatch: T,
    /// `|phi|` (rad) above this flags [`Faults::OFFSET_OR_QUADRATURE`].
    pub max_quadrature_rad: T,
}

/// Defines, for the float type `$t` (its functions in module `$m`), the `const fn`s that
/// make and check the settings: one implementation for both types and for both the generic
/// and the `const` constructors (constant evaluation cannot call trait methods).
macro_rules! calibration_settings_fns {
    ($t:ident, $m:ident) => {
        use super::{CalibrationSettings, CheckedCalibration};
        use $crate::error::$m::check_positive;
        use $crate::error::{ConfigError, Parameter, const_try};

        /// See [`CalibrationSettings::default`] (the bounds are the `f32` values in both
        /// types, so that `f32` and `f64` settings agree exactly).
        pub(crate) const fn default_settings() -> CalibrationSettings<$t> {
            CalibrationSettings {
                min_speed_rad_s: None,
                max_offset: 0.1_f32 as $t,
                max_amplitude_mismatch: 0.2_f32 as $t,
                max_quadrature_rad: 0.1_f32 as $t,
            }
        }

        /// See [`CalibrationSettings::check`].
        pub(crate) const fn check(
            settings: &CalibrationSettings<$t>,
            sample_period_s: $t,
        ) -> Result<CheckedCalibration<$t>, ConfigError> {
            const TAU: $t = core::$t::consts::TAU;
            let min_scaled_speed = match settings.min_speed_rad_s {
                Some(speed) => {
                    const_try!(check_positive(speed, Parameter::MinSpeed)) * sample_period_s
                }
                None => TAU / 4096.0,
            };
            let slowest = TAU / 1_048_576.0;
            if !(min_scaled_speed >= slowest && min_scaled_speed <= core::$t::consts::FRAC_PI_2) {
                return Err(ConfigError::OutOfRange(Parameter::MinSpeed));
            }
            const_try!(check_positive(settings.max_offset, Parameter::MaxOffset));
            const_try!(check_positive(
                settings.max_amplitude_mismatch,
                Parameter::MaxAmplitudeMismatch
            ));
            const_try!(check_positive(
                settings.max_quadrature_rad,
                Parameter::MaxQuadrature
            ));
            Ok(CheckedCalibration {
                settings: *settings,
                min_scaled_speed,
            })
        }
    };
}

/// The `f32` functions.
pub(crate) mod for_f32 {
    calibration_settings_fns!(f32, for_f32);
}

/// The `f64` functions.
pub(crate) mod for_f64 {
    calibration_settings_fns!(f64, for_f64);
}

/// The settings with the minimum speed in rad per sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckedCalibration<T> {
    pub(crate) settings: CalibrationSettings<T>,
    pub(crate) min_scaled_speed: T,
}

impl<T: Float> CheckedCalibration<T> {
    /// The faults a calibration's parameters raise against the bounds (out of line: once per
    /// change of the calibration).
    #[cold]
    #[inline(never)]
    pub(crate) fn sensor_faults(&self, calibration: &SensorCalibration<T>) -> Faults {
        let s = &self.settings;
        let (o_c, o_s) = calibration.offsets();
        let (a_c, a_s) = calibration.amplitudes();
        let offset_or_quadrature = o_c.abs() > s.max_offset * a_c
            || o_s.abs() > s.max_offset * a_s
            || calibration.quadrature_rad().abs() > s.max_quadrature_rad;
        let mismatch = (calibration.amplitude_ratio() - T::ONE).abs() > s.max_amplitude_mismatch;
        Faults::when(offset_or_quadrature, Faults::OFFSET_OR_QUADRATURE)
            | Faults::when(mismatch, Faults::AMPLITUDE_MISMATCH)
    }
}
