//! The `const` constructors of the standard chain's stages and of its front end
//! ([`TrackerFrontEnd`]) on `f32` and `f64`, so that a firmware's whole tracker is a
//! `static` checked when it compiles. Constant evaluation cannot call the float trait's
//! methods, so each check is a `const fn` per float type (one macro); the run-time
//! constructors (`AdcScaling::new`, `SensorCalibration::new`, ...) stay generic in the
//! layers below, doing the same operations in the same order, and the tests hold both to
//! the same bits (`tests.rs`). Above them here, the module imports them without a cycle.

use crate::adc::AdcScaling;
use crate::angle_correction::{AngleCorrection, MAX_CORRECTION_ORDER};
use crate::angle_table::AngleCorrectionTable;
use crate::calibration::SensorCalibration;
use crate::calibration_settings::CalibrationSettings;
use crate::chain::{OnlineCalibration, WindingCheck};
use crate::error::{ConfigError, Parameter};
use crate::tracker::{Input, Rails, TrackerFrontEnd, TrackerSettings};

/// The `const` constructors for the float type `$t`, whose fast sin/cos polynomials are
/// `$sin` and `$cos` (`real::sincos`).
macro_rules! const_stages {
    ($t:ident, $m:ident, $sin:path, $cos:path) => {
        use super::*;
        use crate::error::$m::check_positive;
        use crate::error::const_try;

        /// `c[0] + c[1] t + ...` by Horner's rule.
        const fn polynomial(t: $t, c: &[$t]) -> $t {
            let mut i = c.len();
            let mut sum = 0.0;
            while i > 0 {
                i -= 1;
                sum = sum * t + c[i];
            }
            sum
        }

        /// `(sin x, cos x)` for `|x| <= pi/2` by the fast sin/cos polynomials
        /// (`docs/theory.md §11`), by Horner's rule: at construction only.
        pub(crate) const fn sin_cos(x: $t) -> ($t, $t) {
            let w = core::$t::consts::FRAC_PI_2 - x.abs();
            let w2 = w * w;
            let q = polynomial(w2, &$cos);
            (if x < 0.0 { -q } else { q }, w * polynomial(w2, &$sin))
        }

        /// `tan d` for `|d| <= 0.25` rad (a table's errors): its series to `d^11` (the next
        /// term is below 6e-11 rad there), by Horner's rule in `d^2`, in the table's own
        /// float (no `f64` routine in an `f32` firmware).
        pub(crate) const fn tangent(d: $t) -> $t {
            // The operations of `angle_table::tangent`, in its order.
            const SERIES: [f64; 5] = [
                1.0 / 3.0,
                2.0 / 15.0,
                17.0 / 315.0,
                62.0 / 2835.0,
                1382.0 / 155_925.0,
            ];
            let d2 = d * d;
            let mut sum: $t = 0.0;
            let mut k = SERIES.len();
            while k > 0 {
                k -= 1;
                sum = (sum + SERIES[k] as $t) * d2;
            }
            d * (1.0 + sum)
        }

        /// A table's entries `[error, _]` made `[tan error, step to the next]` (periodic).
        const fn table_of_errors<const L: usize>(segments: &mut [[$t; 2]; L]) {
            let mut k = 0;
            while k < L {
                segments[k][0] = tangent(segments[k][0]);
                k += 1;
            }
            let mut k = 0;
            while k < L {
                segments[k][1] = segments[(k + 1) % L][0] - segments[k][0];
                k += 1;
            }
        }

        /// The ADC code `code` in the observer's units, exactly as `AdcScaling::sample`
        /// scales it (the difference halved, so that it fits an `i32`).
        const fn code_in_units(adc: &AdcScaling<$t>, code: i32) -> $t {
            let d = code as i64 - adc.mid_scale_counts as i64;
            (((d >> 1) as i32) as $t * 2.0 + ((d & 1) as i32) as $t) * adc.units_per_count
        }

        impl AdcScaling<$t> {
            /// [`AdcScaling::new`] as a `const fn`.
            ///
            /// ```
            /// use angletrack_core::AdcScaling;
            #[doc = concat!("const ADC: AdcScaling<", stringify!($t), "> = match AdcScaling::<", stringify!($t), ">::new_const(2048, 2048.0) {")]
            ///     Ok(adc) => adc,
            ///     Err(_) => panic!("bad ADC"),
            /// };
            /// assert_eq!(Ok(ADC), AdcScaling::new(2048, 2048.0));
            /// ```
            pub const fn new_const(
                mid_scale_counts: i32,
                counts_per_unit: $t,
            ) -> Result<Self, ConfigError> {
                if mid_scale_counts.unsigned_abs() > crate::MAX_MID_SCALE_COUNTS as u32 {
                    return Err(ConfigError::OutOfRange(Parameter::MidScaleCounts));
                }
                let counts = const_try!(check_positive(counts_per_unit, Parameter::CountsPerUnit));
                let units_per_count = 1.0 / counts;
                if !(units_per_count.is_finite() && units_per_count > 0.0) {
                    return Err(ConfigError::OutOfRange(Parameter::CountsPerUnit));
                }
                Ok(Self {
                    mid_scale_counts,
                    units_per_count,
                })
            }

            /// [`AdcScaling::offset_binary`] as a `const fn`.
            pub const fn offset_binary_const(bits: u32) -> Result<Self, ConfigError> {
                let half = const_try!(crate::adc::half_range(bits, 31));
                Self::new_const(half, half as $t)
            }

            /// [`AdcScaling::twos_complement`] as a `const fn`.
            pub const fn twos_complement_const(bits: u32) -> Result<Self, ConfigError> {
                let half = const_try!(crate::adc::half_range(bits, 32));
                // 2^31 counts per unit for 32 bits (the half range is capped at 2^30).
                Self::new_const(0, if bits == 32 { 2_147_483_648.0 } else { half as $t })
            }
        }

        impl SensorCalibration<$t> {
            /// [`SensorCalibration::new`] as a `const fn`.
            ///
            /// ```
            /// use angletrack_core::SensorCalibration;
            #[doc = concat!("const STORED: SensorCalibration<", stringify!($t), "> =")]
            #[doc = concat!("    match SensorCalibration::<", stringify!($t), ">::new_const(0.02, -0.01, 1.0, 1.05, 0.01) {")]
            ///         Ok(calibration) => calibration,
            ///         Err(_) => panic!("bad calibration"),
            ///     };
            /// assert_eq!(Ok(STORED), SensorCalibration::new(0.02, -0.01, 1.0, 1.05, 0.01));
            /// ```
            pub const fn new_const(
                offset_c: $t,
                offset_s: $t,
                amplitude_c: $t,
                amplitude_s: $t,
                quadrature_rad: $t,
            ) -> Result<Self, ConfigError> {
                if !offset_c.is_finite() {
                    return Err(ConfigError::NotFinite(Parameter::OffsetCos));
                }
                if !offset_s.is_finite() {
                    return Err(ConfigError::NotFinite(Parameter::OffsetSin));
                }
                if !quadrature_rad.is_finite() {
                    return Err(ConfigError::NotFinite(Parameter::Quadrature));
                }
                let amplitude_c = const_try!(check_positive(amplitude_c, Parameter::AmplitudeCos));
                let amplitude_s = const_try!(check_positive(amplitude_s, Parameter::AmplitudeSin));
                // Beyond pi/4 the correction's division by cos(phi) would amplify the
                // noise by more than sqrt(2).
                if !(quadrature_rad.abs() < core::$t::consts::FRAC_PI_4) {
                    return Err(ConfigError::OutOfRange(Parameter::Quadrature));
                }
                let (sin, cos) = sin_cos(quadrature_rad);
                let sine_gain = amplitude_c / (amplitude_s * cos);
                if !(sine_gain.is_finite() && sine_gain > 0.0) {
                    return Err(ConfigError::OutOfRange(Parameter::AmplitudeSin));
                }
                Ok(Self {
                    offset_c,
                    offset_s,
                    amplitude_c,
                    amplitude_s,
                    quadrature_rad,
                    sine_gain,
                    cross_gain: sin / cos,
                })
            }
        }

        impl AngleCorrection<$t> {
            /// [`AngleCorrection::new`] as a `const fn`.
            ///
            /// ```
            /// use angletrack_core::AngleCorrection;
            #[doc = concat!("const HARMONICS: AngleCorrection<", stringify!($t), "> =")]
            #[doc = concat!("    match AngleCorrection::<", stringify!($t), ">::new_const([0.0; 8], [0.0, 0.004, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]) {")]
            ///         Ok(harmonics) => harmonics,
            ///         Err(_) => panic!("bad correction"),
            ///     };
            /// assert_eq!(HARMONICS.order(), 2);
            /// ```
            pub const fn new_const(
                cos_coefficients: [$t; MAX_CORRECTION_ORDER],
                sin_coefficients: [$t; MAX_CORRECTION_ORDER],
            ) -> Result<Self, ConfigError> {
                let mut total: $t = 0.0;
                let mut order = 0;
                let mut k = 0;
                while k < MAX_CORRECTION_ORDER {
                    let (a, b) = (cos_coefficients[k], sin_coefficients[k]);
                    if !(a.is_finite() && b.is_finite()) {
                        return Err(ConfigError::NotFinite(Parameter::AngleCorrection));
                    }
                    total += a.abs() + b.abs();
                    if a != 0.0 || b != 0.0 {
                        order = k + 1;
                    }
                    k += 1;
                }
                if !(total <= crate::angle_correction::MAX_TOTAL_RAD as $t) {
                    return Err(ConfigError::OutOfRange(Parameter::AngleCorrection));
                }
                Ok(Self {
                    cos_coefficients,
                    sin_coefficients,
                    order,
                })
            }
        }

        impl<const L: usize> AngleCorrectionTable<$t, L> {
            /// [`AngleCorrectionTable::new`] as a `const fn`.
            ///
            /// ```
            /// use angletrack_core::AngleCorrectionTable;
            #[doc = concat!("const TABLE: AngleCorrectionTable<", stringify!($t), ", 4> =")]
            #[doc = concat!("    match AngleCorrectionTable::<", stringify!($t), ", 4>::new_const([0.0, 0.01, 0.0, -0.01]) {")]
            ///         Ok(table) => table,
            ///         Err(_) => panic!("an entry beyond 0.25 rad"),
            ///     };
            /// assert_eq!(Ok(TABLE), AngleCorrectionTable::new([0.0, 0.01, 0.0, -0.01]));
            /// ```
            pub const fn new_const(errors: [$t; L]) -> Result<Self, ConfigError> {
                let () = Self::LENGTH_IS_A_POWER_OF_TWO;
                let mut segments = [[0.0; 2]; L];
                let mut k = 0;
                while k < L {
                    let d = errors[k];
                    if !d.is_finite() {
                        return Err(ConfigError::NotFinite(Parameter::AngleCorrection));
                    }
                    if !(d.abs() <= crate::angle_correction::MAX_TOTAL_RAD as $t) {
                        return Err(ConfigError::OutOfRange(Parameter::AngleCorrection));
                    }
                    segments[k][0] = d;
                    k += 1;
                }
                table_of_errors(&mut segments);
                Ok(Self { segments })
            }
        }

        impl WindingCheck<$t> {
            /// [`WindingCheck::new`] as a `const fn`.
            pub const fn new_const(amplitude: $t) -> Result<Self, ConfigError> {
                match check_positive(amplitude, Parameter::NominalAmplitude) {
                    Ok(amplitude) => Ok(Self { amplitude }),
                    Err(error) => Err(error),
                }
            }
        }

        impl OnlineCalibration<$t> {
            /// [`OnlineCalibration::new`] as a `const fn`.
            pub const fn new_const(
                settings: CalibrationSettings<$t>,
                sample_period_s: $t,
            ) -> Result<Self, ConfigError> {
                match crate::calibration_settings::$m::check(&settings, sample_period_s) {
                    Ok(checked) => Ok(Self { checked }),
                    Err(error) => Err(error),
                }
            }
        }

        impl TrackerFrontEnd<$t> {
            /// [`TrackerFrontEnd::new`] as a `const fn`: a firmware's standard chain in a
            /// `static`, checked when it compiles.
            ///
            /// ```
            /// use angletrack_core::{
            ///     AdcScaling, CalibrationStage, CorrectionStage, Gains, Input, Rails,
            ///     SensorCalibration, Tracker, TrackerFrontEnd, TrackerSettings,
            /// };
            #[doc = concat!("type T = ", stringify!($t), ";")]
            /// const fn ok<V: Copy>(r: Result<V, angletrack_core::ConfigError>) -> V {
            ///     match r {
            ///         Ok(v) => v,
            ///         Err(_) => panic!("refused"),
            ///     }
            /// }
            /// static TRACKER: Tracker<T, Gains<T, 3>> = Tracker::new(
            ///     ok(TrackerFrontEnd::<T>::new_const(TrackerSettings {
            ///         input: Input::Counts {
            ///             adc: ok(AdcScaling::<T>::offset_binary_const(12)),
            ///             rails: Rails::Stated { min: 0, max: 4095 },
            ///         },
            ///         winding: None,
            ///         calibration: CalibrationStage::Stored(ok(SensorCalibration::<T>::new_const(
            ///             0.02, -0.01, 1.0, 1.05, 0.01,
            ///         ))),
            ///         correction: CorrectionStage::None,
            ///     })),
            ///     ok(Gains::<T, 3>::new_const([0.1578, 0.0126, 0.000_34], 50e-6)),
            /// );
            /// assert!(TRACKER.front_end.adc_range().is_some());
            /// ```
            ///
            /// A range the ADC's scaling does not keep ordered does not compile:
            ///
            /// ```compile_fail,E0080
            /// use angletrack_core::{AdcScaling, Input, Rails, TrackerFrontEnd, TrackerSettings};
            #[doc = concat!("static FRONT_END: TrackerFrontEnd<", stringify!($t), "> = match TrackerFrontEnd::<", stringify!($t), ">::new_const(TrackerSettings {")]
            ///     input: Input::Counts {
            #[doc = concat!("        adc: match AdcScaling::<", stringify!($t), ">::offset_binary_const(12) { Ok(a) => a, Err(_) => panic!() },")]
            ///         rails: Rails::Stated { min: 4095, max: 0 },
            ///     },
            ///     winding: None,
            ///     calibration: angletrack_core::CalibrationStage::None,
            ///     correction: angletrack_core::CorrectionStage::None,
            /// }) {
            ///     Ok(front_end) => front_end,
            ///     Err(_) => panic!("refused"),
            /// };
            /// ```
            pub const fn new_const(settings: TrackerSettings<$t>) -> Result<Self, ConfigError> {
                let (adc, counts, rails) = match settings.input {
                    Input::Units { rails } => (AdcScaling::<$t>::UNSCALED, false, rails),
                    Input::Counts { adc, rails } => {
                        let rails = match rails {
                            Rails::Unchecked => Rails::Unchecked,
                            Rails::Measured => Rails::Measured,
                            Rails::Stated { min, max } => {
                                let (low, high) =
                                    (code_in_units(&adc, min), code_in_units(&adc, max));
                                if !(min < max && low < high) {
                                    return Err(ConfigError::OutOfRange(Parameter::AdcRange));
                                }
                                Rails::Stated {
                                    min: low,
                                    max: high,
                                }
                            }
                        };
                        (adc, true, rails)
                    }
                };
                // NaN compares false: refused.
                if let Rails::Stated { min, max } = rails
                    && !(min < max)
                {
                    return Err(ConfigError::OutOfRange(Parameter::AdcRange));
                }
                Ok(Self::of_checked(adc, counts, rails, settings))
            }
        }
    };
}

/// The `f32` stages.
pub(crate) mod for_f32 {
    const_stages!(
        f32,
        for_f32,
        crate::real::sincos::F32_SIN_POLY,
        crate::real::sincos::F32_COS_POLY
    );
}

/// The `f64` stages.
pub(crate) mod for_f64 {
    const_stages!(
        f64,
        for_f64,
        crate::real::sincos::F64_SIN_POLY,
        crate::real::sincos::F64_COS_POLY
    );
}

#[cfg(test)]
mod tests;
