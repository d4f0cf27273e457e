//! The settings of the synchronous demodulator (`docs/theory.md §13`), as the caller writes
//! them, with their defaults; [`Demodulator::new`](crate::Demodulator::new) checks them.

use crate::real::Float;

/// The settings of a [`Demodulator`](crate::Demodulator), checked by [`Demodulator::new`](crate::Demodulator::new).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemodulatorSettings<T> {
    /// The excitation carrier frequency (Hz); the ADC samples `N` times per period.
    pub carrier_hz: T,
    /// The nominal carrier amplitude of a winding at the ADC (counts, peak) when its
    /// envelope is 1: the pairs are divided by it, so their nominal amplitude is 1.
    pub carrier_amplitude_counts: T,
    /// The lowest ADC code.
    pub adc_min_code: T,
    /// The highest ADC code.
    pub adc_max_code: T,
    /// A raw sample within this many counts of a rail counts as clipped.
    pub clip_margin_counts: T,
    /// Loss of excitation is flagged below this carrier amplitude (relative to nominal).
    pub loss_of_excitation: T,
    /// Phase drift is flagged when the tracked delay moves this far (rad) from its start-up
    /// value (44 degrees by default, the AD2S1210's lock range).
    pub phase_drift_bound_rad: T,
    /// The delay (rad) the start-up estimate is resolved around: it is measured modulo pi
    /// and taken within 90 degrees of this (see [`Demodulator`](crate::Demodulator)).
    pub expected_delay_rad: T,
    /// How fast the delay is tracked after start-up: the fraction of each period's phase
    /// error applied (0 holds the start-up value).
    pub delay_tracking_factor: T,
    /// The carrier periods averaged by the start-up delay estimate.
    pub startup_periods: u32,
}

impl<T: Float> DemodulatorSettings<T> {
    /// Settings for a carrier of `carrier_hz` (Hz) and amplitude `carrier_amplitude_counts`
    /// at an ADC whose codes run from `adc_min_code` to `adc_max_code`, with the defaults:
    /// clip margin 1/256 of the range, loss of excitation below 0.25, phase drift bound
    /// 44 degrees, expected delay 0, delay tracking factor 0.01 (a time constant of 100
    /// periods), start-up over 16 periods.
    ///
    /// ```
    /// use angletrack_core::DemodulatorSettings;
    /// let settings = DemodulatorSettings::<f32>::new(10e3, 1800.0, 0.0, 4095.0);
    /// assert_eq!(settings.startup_periods, 16);
    /// ```
    pub fn new(
        carrier_hz: T,
        carrier_amplitude_counts: T,
        adc_min_code: T,
        adc_max_code: T,
    ) -> Self {
        Self {
            carrier_hz,
            carrier_amplitude_counts,
            adc_min_code,
            adc_max_code,
            clip_margin_counts: (adc_max_code - adc_min_code) * T::from_f32(1.0 / 256.0),
            loss_of_excitation: T::from_f32(0.25),
            phase_drift_bound_rad: T::from_f32(44.0 * core::f32::consts::PI / 180.0),
            expected_delay_rad: T::ZERO,
            delay_tracking_factor: T::from_f32(0.01),
            startup_periods: 16,
        }
    }
}
