//! The demodulator's checked construction (`docs/theory.md §13`), a `const fn` per number
//! type so that a firmware can hold its configuration in a `static` checked at compile time:
//! constant evaluation cannot call trait methods, so the checks and the derived constants
//! are written once in a macro over the concrete types (as `const_config.rs` does for the
//! observer's configuration), and [`Demodulator::new`] reaches the same code through
//! [`DemodulatorNumber`].

use super::{
    Demodulator, DemodulatorNumber, DemodulatorSettings, EXCITATION_REFERENCE_FRACTION,
    FIXED_PAIR_UNIT,
};
use crate::error::{ConfigError, Parameter, const_try};

/// Defines, for the sample type `$v` whose settings are in the float type `$r` (its checks
/// in `crate::error::$m`), with the number-type constants of module `$n`, the `const`
/// constructor `Demodulator::<$v>::new_const`.
macro_rules! checked_demodulator {
    ($v:ident, $r:ident, $m:ident, $n:ident) => {
        /// `v` if it is finite and within `[low, high]`, else the error naming `parameter`.
        const fn in_range(
            v: $r,
            low: $r,
            high: $r,
            parameter: Parameter,
        ) -> Result<$r, ConfigError> {
            if !v.is_finite() {
                Err(ConfigError::NotFinite(parameter))
            } else if !(v >= low && v <= high) {
                Err(ConfigError::OutOfRange(parameter))
            } else {
                Ok(v)
            }
        }

        /// `v` if it is positive, finite and at most `max`, else the error naming
        /// `parameter`: one check for the settings with an upper bound.
        const fn positive_at_most(
            v: $r,
            max: $r,
            parameter: Parameter,
        ) -> Result<$r, ConfigError> {
            let v = const_try!(crate::error::$m::check_positive(v, parameter));
            if v <= max {
                Ok(v)
            } else {
                Err(ConfigError::OutOfRange(parameter))
            }
        }

        /// `floor(x)` for `|x| < 2^31` (`as` truncates toward zero and saturates).
        const fn floor_to_i32(x: $r) -> i32 {
            let t = x as i32;
            if (t as $r) > x { t - 1 } else { t }
        }

        /// A turn fraction in [-1/2, 1/2) as phase units (2^32 per turn).
        const fn turn_fraction_to_phase(fraction: $r) -> u32 {
            // 2^31 times a fraction below 1/2 in magnitude fits an i32.
            (floor_to_i32(fraction * 2_147_483_648.0) as u32).wrapping_mul(2)
        }

        /// `(sin x, cos x)` for `|x| <= pi` by their series (24 terms: below the type's
        /// resolution).
        const fn sin_cos(x: $r) -> ($r, $r) {
            let (mut sin_term, mut cos_term) = (x, 1.0 as $r);
            let (mut sin, mut cos) = (x, 1.0 as $r);
            let mut n = 1;
            while n < 12 {
                sin_term = -sin_term * x * x / (((2 * n) * (2 * n + 1)) as $r);
                cos_term = -cos_term * x * x / (((2 * n - 1) * (2 * n)) as $r);
                sin += sin_term;
                cos += cos_term;
                n += 1;
            }
            (sin, cos)
        }

        impl Demodulator<$v> {
            #[doc = concat!("[`Demodulator::new`] for `", stringify!($v), "` samples as a `const fn`")]
            /// (the same checks, the same configuration), so that a firmware's demodulator
            /// can be a `static` checked at compile time: invalid settings are a compile
            /// error.
            ///
            /// ```
            #[doc = concat!("use angletrack_core::{Demodulator, DemodulatorSettings, DemodulatorState};")]
            #[doc = concat!("static DEMODULATOR: Demodulator<", stringify!($v), "> = match Demodulator::<", stringify!($v), ">::new_const(")]
            #[doc = concat!("    DemodulatorSettings::<", stringify!($r), ">::new_const(10e3, 160e3, 1800.0, 0.0, 4095.0),")]
            /// ) {
            ///     Ok(demodulator) => demodulator,
            ///     Err(_) => panic!("bad demodulator settings"),
            /// };
            /// assert_eq!(DEMODULATOR.samples_per_period(), 16.0);
            #[doc = concat!("let settings = DemodulatorSettings::<", stringify!($r), ">::new(10e3, 160e3, 1800.0, 0.0, 4095.0);")]
            /// assert_eq!(Ok(DEMODULATOR), Demodulator::new(settings));
            /// let mut state = DemodulatorState::new();
            #[doc = concat!("assert!(DEMODULATOR.push(&mut state, 2048 as ", stringify!($v), ", 2048 as ", stringify!($v), ").is_none());")]
            /// ```
            ///
            /// Settings [`Demodulator::new`] refuses (here an ADC rate of 3 samples per
            /// period) do not compile:
            ///
            /// ```compile_fail,E0080
            #[doc = concat!("use angletrack_core::{Demodulator, DemodulatorSettings};")]
            #[doc = concat!("static DEMODULATOR: Demodulator<", stringify!($v), "> = match Demodulator::<", stringify!($v), ">::new_const(")]
            #[doc = concat!("    DemodulatorSettings::<", stringify!($r), ">::new_const(10e3, 30e3, 1800.0, 0.0, 4095.0),")]
            /// ) {
            ///     Ok(demodulator) => demodulator,
            ///     Err(_) => panic!("bad demodulator settings"),
            /// };
            /// ```
            pub const fn new_const(
                settings: DemodulatorSettings<$r>,
            ) -> Result<Self, ConfigError> {
                use crate::error::$m::check_positive;
                let carrier = const_try!(check_positive(
                    settings.carrier_hz,
                    Parameter::CarrierFrequency
                ));
                let adc_rate = const_try!(check_positive(settings.adc_rate_hz, Parameter::AdcRate));
                let ratio = const_try!(in_range(
                    adc_rate / carrier,
                    4.0,
                    <$v as DemodulatorNumber>::MAX_SAMPLES_PER_PERIOD as $r,
                    Parameter::AdcRate,
                ));
                let amplitude = const_try!(check_positive(
                    settings.carrier_amplitude_counts,
                    Parameter::CarrierAmplitude,
                ));
                let Some(pair_gain) = $n::pair_gain(amplitude) else {
                    return Err(ConfigError::OutOfRange(Parameter::CarrierAmplitude));
                };
                let (low, high, margin) = (
                    settings.adc_min_code,
                    settings.adc_max_code,
                    settings.clip_margin_counts,
                );
                if !(low.is_finite() && high.is_finite() && margin.is_finite()) {
                    return Err(ConfigError::NotFinite(Parameter::AdcRange));
                }
                if !(margin >= 0.0 && high - low > margin + margin) {
                    return Err(ConfigError::OutOfRange(Parameter::AdcRange));
                }
                let (Some(clip_centre), Some(clip_half_span)) = (
                    $n::from_counts((low + high) * 0.5),
                    $n::from_counts((high - low) * 0.5 - margin),
                ) else {
                    return Err(ConfigError::NotFinite(Parameter::AdcRange));
                };
                let loss = const_try!(in_range(
                    settings.loss_of_excitation,
                    0.0,
                    1.0,
                    Parameter::LossOfExcitationThreshold,
                ));
                if loss == 1.0 {
                    return Err(ConfigError::OutOfRange(
                        Parameter::LossOfExcitationThreshold,
                    ));
                }
                let weak = const_try!(in_range(
                    settings.weak_excitation,
                    loss,
                    1.0,
                    Parameter::WeakExcitationThreshold,
                ));
                let drift = const_try!(positive_at_most(
                    settings.phase_drift_bound_rad,
                    core::$r::consts::FRAC_PI_2,
                    Parameter::PhaseDriftBound,
                ));
                let expected = const_try!(in_range(
                    settings.expected_delay_rad,
                    -1e3,
                    1e3,
                    Parameter::ExpectedDelay,
                ));
                let bandwidth = const_try!(positive_at_most(
                    settings.carrier_loop_bandwidth,
                    0.5,
                    Parameter::CarrierLoopBandwidth,
                ));
                let error = const_try!(positive_at_most(
                    settings.max_carrier_error,
                    0.2,
                    Parameter::MaxCarrierError,
                ));
                if settings.startup_periods == 0 {
                    return Err(ConfigError::NotPositive(Parameter::StartupPeriods));
                }
                let fraction = 1.0 / ratio;
                const fn step_at(f: $r) -> u32 {
                    turn_fraction_to_phase(if f < 0.499_999 { f } else { 0.499_999 })
                }
                use core::$r::consts::{PI, TAU};
                // The loop holds the windings' carrier phase, a delay's negative; within
                // [-pi, pi).
                let expected = -expected;
                let expected = expected - TAU * floor_to_i32(expected / TAU + 0.5) as $r;
                let (sin_expected, cos_expected) = sin_cos(expected);
                let (_, cos2) = sin_cos(drift + drift);
                // The phase detector's Q31 unit is 2^-31 rad of carrier phase, 2^32 / (2 pi)
                // phase units per rad: a gain k per rad is k / pi phase units per detector
                // unit.
                let per_unit = 1.0 / PI;
                let phase_gain =
                    floor_to_i32(core::$r::consts::SQRT_2 * bandwidth * per_unit * 65_536.0);
                // The integral gain acts on the step, per sample: divided by the samples per
                // period.
                let step_gain =
                    floor_to_i32(bandwidth * bandwidth * per_unit * fraction * 16_777_216.0);
                Ok(Self {
                    step: step_at(fraction),
                    step_min: step_at(fraction * (1.0 - error)),
                    step_max: step_at(fraction * (1.0 + error)),
                    phase_gain,
                    step_gain,
                    clip_centre,
                    clip_half_span,
                    pair_gain,
                    loss_power: $n::unit_power(loss),
                    weak_power: $n::unit_power(weak),
                    reference_power: $n::unit_power(EXCITATION_REFERENCE_FRACTION as $r),
                    drift_cos2: $n::fraction(cos2),
                    expected: turn_fraction_to_phase(expected / TAU),
                    expected_cos: $n::fraction(cos_expected),
                    expected_sin: $n::fraction(sin_expected),
                    startup_periods: settings.startup_periods,
                    carrier_hz: carrier,
                    adc_rate_hz: adc_rate,
                })
            }
        }
    };
}

/// The constants of a float type's demodulator: the settings' values themselves.
macro_rules! float_constants {
    ($t:ident) => {
        /// The gain that makes a winding of amplitude `amplitude_counts` an envelope of 1.
        pub(super) const fn pair_gain(amplitude_counts: $t) -> Option<$t> {
            Some(2.0 / amplitude_counts)
        }
        /// A setting in counts in the type of the samples; `None` if not finite.
        pub(super) const fn from_counts(x: $t) -> Option<$t> {
            if x.is_finite() { Some(x) } else { None }
        }
        /// The square of a fraction of the pair's unit: a power threshold.
        pub(super) const fn unit_power(fraction: $t) -> $t {
            fraction * fraction
        }
        /// A fraction in [-1, 1] as the window's products take it.
        pub(super) const fn fraction(x: $t) -> $t {
            x
        }
    };
}

/// `f32` samples.
mod for_f32 {
    use super::*;
    mod number {
        float_constants!(f32);
    }
    checked_demodulator!(f32, f32, for_f32, number);
}

/// `f64` samples.
mod for_f64 {
    use super::*;
    mod number {
        float_constants!(f64);
    }
    checked_demodulator!(f64, f64, for_f64, number);
}

/// `i16` samples (fixed point), their settings in `f32`.
mod for_i16 {
    use super::*;
    mod number {
        use super::FIXED_PAIR_UNIT;
        /// 2^14 / (512 amplitude) in Q24: 2^29 / amplitude, within [1, 2^24).
        pub(super) const fn pair_gain(amplitude_counts: f32) -> Option<i32> {
            let gain = 536_870_912.0_f32 / amplitude_counts;
            if gain >= 1.0 && gain < 16_777_216.0 {
                Some(gain as i32)
            } else {
                None
            }
        }
        /// A setting in counts as a sample, saturated (`as` saturates); `None` if not finite.
        pub(super) const fn from_counts(x: f32) -> Option<i16> {
            if x.is_finite() { Some(x as i16) } else { None }
        }
        /// The square of a fraction of [`FIXED_PAIR_UNIT`], as a product of pair components
        /// (over 2^4).
        pub(super) const fn unit_power(fraction: f32) -> i32 {
            let v = fraction * FIXED_PAIR_UNIT as f32;
            (v * v / 16.0) as i32
        }
        /// A fraction in [-1, 1] in Q16.
        pub(super) const fn fraction(x: f32) -> i32 {
            (x * 65_536.0) as i32
        }
    }
    checked_demodulator!(i16, f32, for_f32, number);
}
