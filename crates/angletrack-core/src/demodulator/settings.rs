//! The settings of the demodulator (`docs/theory.md §13`), as the caller writes them, with
//! their defaults; [`Demodulator::new`](crate::Demodulator::new) checks them.

use crate::real::Float;

// The defaults of `DemodulatorSettings::new` and `new_const`, in `f32` for both types.
/// The clipping margin's share of the ADC's range.
const CLIP_MARGIN_OF_RANGE: f32 = 1.0 / 256.0;
const LOSS_OF_EXCITATION: f32 = 0.25;
const WEAK_EXCITATION: f32 = 0.7;
/// 44 degrees: the AD2S1210's lock range.
const PHASE_DRIFT_BOUND_RAD: f32 = 44.0 * core::f32::consts::PI / 180.0;
const CARRIER_LOOP_BANDWIDTH: f32 = 0.3;
const MAX_CARRIER_ERROR: f32 = 0.03;
const STARTUP_PERIODS: u32 = 24;

/// The settings of a [`Demodulator`](crate::Demodulator), checked by
/// [`Demodulator::new`](crate::Demodulator::new). `T` is the float type of the
/// demodulator's [`Real`](crate::DemodulatorNumber::Real) (`f32` for `f32` and `i16`
/// samples, `f64` for `f64`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemodulatorSettings<T> {
    /// The declared excitation carrier frequency (Hz): the carrier loop starts there and
    /// tracks the carrier within [`DemodulatorSettings::max_carrier_error`] of it.
    pub carrier_hz: T,
    /// The ADC's sample rate (Hz), at least 4 times the carrier, any ratio (at most
    /// [`DemodulatorNumber::MAX_SAMPLES_PER_PERIOD`](crate::DemodulatorNumber::MAX_SAMPLES_PER_PERIOD)).
    pub adc_rate_hz: T,
    /// The nominal carrier amplitude of a winding at the ADC (counts, peak) when its
    /// envelope is 1: the pairs are divided by it, so their nominal amplitude is 1.
    pub carrier_amplitude_counts: T,
    /// The lowest ADC code.
    pub adc_min_code: T,
    /// The highest ADC code.
    pub adc_max_code: T,
    /// A raw sample within this many counts of a rail counts as clipped.
    pub clip_margin_counts: T,
    /// Loss of excitation is flagged below this carrier amplitude (relative to nominal, the
    /// windings' envelopes summed in power).
    pub loss_of_excitation: T,
    /// Weak excitation is flagged below this carrier amplitude (relative to nominal), from
    /// [`DemodulatorSettings::loss_of_excitation`] to 1.
    pub weak_excitation: T,
    /// The carrier loop is out of lock (phase drift flagged) when its phase error exceeds
    /// this (rad, at most pi/2; 44 degrees by default, the AD2S1210's lock range).
    pub phase_drift_bound_rad: T,
    /// The carrier delay (rad, positive when the windings' carrier lags) the sign of the
    /// windings' carrier is resolved around: with a recorded excitation, the windings' delay
    /// after it (a scope's reading: 20 degrees for windings 20 degrees behind the
    /// excitation); without, their delay after a carrier of phase 0 at the first sample.
    /// The delay is measured modulo pi and taken within 90 degrees of this.
    pub expected_delay_rad: T,
    /// The carrier loop's natural frequency times the carrier period (rad, in (0, 0.5]):
    /// its bandwidth is about `0.2 carrier_hz` at the default 0.3.
    pub carrier_loop_bandwidth: T,
    /// The largest relative carrier frequency error tracked (0.03: 3 %, in (0, 0.2]).
    pub max_carrier_error: T,
    /// The carrier periods the loop acquires over before the first pair.
    pub startup_periods: u32,
}

impl<T: Float> DemodulatorSettings<T> {
    /// Settings for a carrier of `carrier_hz` (Hz) sampled at `adc_rate_hz` (Hz) with
    /// amplitude `carrier_amplitude_counts` at an ADC whose codes run from `adc_min_code`
    /// to `adc_max_code`, with the defaults: clip margin 1/256 of the range, loss of
    /// excitation below 0.25, weak excitation below 0.7, phase drift bound 44 degrees,
    /// expected delay 0, carrier loop bandwidth 0.3, carrier error up to 3 %, start-up over
    /// 24 periods.
    ///
    /// ```
    /// use angletrack_core::DemodulatorSettings;
    /// let settings = DemodulatorSettings::<f32>::new(10e3, 150e3, 1800.0, 0.0, 4095.0);
    /// assert_eq!(settings.startup_periods, 24);
    /// ```
    pub fn new(
        carrier_hz: T,
        adc_rate_hz: T,
        carrier_amplitude_counts: T,
        adc_min_code: T,
        adc_max_code: T,
    ) -> Self {
        Self {
            carrier_hz,
            adc_rate_hz,
            carrier_amplitude_counts,
            adc_min_code,
            adc_max_code,
            clip_margin_counts: (adc_max_code - adc_min_code) * T::from_f32(CLIP_MARGIN_OF_RANGE),
            loss_of_excitation: T::from_f32(LOSS_OF_EXCITATION),
            weak_excitation: T::from_f32(WEAK_EXCITATION),
            phase_drift_bound_rad: T::from_f32(PHASE_DRIFT_BOUND_RAD),
            expected_delay_rad: T::ZERO,
            carrier_loop_bandwidth: T::from_f32(CARRIER_LOOP_BANDWIDTH),
            max_carrier_error: T::from_f32(MAX_CARRIER_ERROR),
            startup_periods: STARTUP_PERIODS,
        }
    }
}

/// Defines [`DemodulatorSettings::new_const`] for the float type `$t`.
macro_rules! const_settings {
    ($t:ident) => {
        impl DemodulatorSettings<$t> {
            /// [`DemodulatorSettings::new`] as a `const fn` (the same defaults, the `f32`
            /// values in both types), for a
            /// `static` demodulator ([`Demodulator::new_const`](crate::Demodulator)).
            ///
            /// ```
            /// use angletrack_core::DemodulatorSettings;
            #[doc = concat!("const SETTINGS: DemodulatorSettings<", stringify!($t), "> = DemodulatorSettings::<", stringify!($t), ">::new_const(10e3, 150e3, 1800.0, 0.0, 4095.0);")]
            /// assert_eq!(SETTINGS, DemodulatorSettings::new(10e3, 150e3, 1800.0, 0.0, 4095.0));
            /// ```
            pub const fn new_const(
                carrier_hz: $t,
                adc_rate_hz: $t,
                carrier_amplitude_counts: $t,
                adc_min_code: $t,
                adc_max_code: $t,
            ) -> Self {
                Self {
                    carrier_hz,
                    adc_rate_hz,
                    carrier_amplitude_counts,
                    adc_min_code,
                    adc_max_code,
                    clip_margin_counts: (adc_max_code - adc_min_code)
                        * (CLIP_MARGIN_OF_RANGE as $t),
                    loss_of_excitation: LOSS_OF_EXCITATION as $t,
                    weak_excitation: WEAK_EXCITATION as $t,
                    phase_drift_bound_rad: PHASE_DRIFT_BOUND_RAD as $t,
                    expected_delay_rad: 0.0,
                    carrier_loop_bandwidth: CARRIER_LOOP_BANDWIDTH as $t,
                    max_carrier_error: MAX_CARRIER_ERROR as $t,
                    startup_periods: STARTUP_PERIODS,
                }
            }
        }
    };
}

const_settings!(f32);
const_settings!(f64);
