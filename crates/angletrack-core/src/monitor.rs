//! Diagnostics like an RDC chip's fault register (`docs/theory.md §10`): the input check
//! that rejects bad samples, and the monitor that flags loss of signal, degradation of
//! signal, loss of tracking and false lock from the means of the amplitude and of the
//! phase error over windows of samples, and from the speed and the in-phase component at
//! each window's end. Its thresholds are checked at construction.
//!
//! Each used sample only adds to two sums and counts down (a few instructions); the
//! flags are decided once per window of `W` used samples (`W` a power of two, 16 by
//! default: [`FaultThresholds::filter_factor`]), out of line. A fault present over a whole
//! window is flagged at that window's end: at most `2 W - 1` used samples after it starts
//! (31 by default). A rejected sample is flagged at once. The first window after the angle
//! is set is its first used sample alone (a start 180 degrees off is caught at once).

use crate::faults::Faults;
use crate::real::Float;

/// Thresholds of the diagnostics and of the input check, in the units of `y_c`, `y_s`
/// (amplitudes) unless stated. Part of the observer's configuration
/// ([`Gains::with_fault_thresholds`](crate::Gains::with_fault_thresholds)).
///
/// The loop itself is unit-free (its phase error is normalised by the signal's magnitude,
/// `docs/theory.md §12`), but these amplitude checks compare the signal with a healthy one,
/// so they need its nominal amplitude in the caller's units: build them with
/// [`FaultThresholds::for_amplitude`] (for raw ADC counts with the mid-scale removed, the
/// amplitude in counts), or feed samples through an [`AdcScaling`](crate::AdcScaling),
/// which makes the defaults fractions of full scale.
///
/// | field | default (nominal amplitude 1) |
/// | --- | --- |
/// | `nominal_amplitude` | 1 |
/// | `max_input_amplitude` | 4 (a sample above is rejected) |
/// | `loss_of_signal` | 0.25 |
/// | `degradation_low`, `degradation_high` | 0.5, 1.5 |
/// | `loss_of_tracking` | 0.1 (filtered `|eps|`, the sine of the phase error: 5.7 degrees) |
/// | `max_speed` | `None`: pi/2 rad per sample, i.e. `pi / (2 Ts)` rad/s |
/// | `filter_factor` | 1/16 (windows of 16 samples) |
/// | `false_lock` | 0 (filtered in-phase component; 0 means an error beyond 90 degrees) |
/// | `monitor` | `true` |
/// | `re_acquire` | `true` |
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct FaultThresholds<T> {
    /// The amplitude of a healthy signal.
    pub nominal_amplitude: T,
    /// A sample with `sqrt(y_c^2 + y_s^2)` above this (or NaN, or infinite) is rejected and
    /// flagged [`Faults::BAD_SAMPLE`]; the observer coasts on its prediction. Always checked.
    pub max_input_amplitude: T,
    /// Amplitude `sqrt(mean of y_c^2 + y_s^2)` over a window below this:
    /// [`Faults::LOSS_OF_SIGNAL`].
    pub loss_of_signal: T,
    /// Window amplitude below this: [`Faults::DEGRADATION_OF_SIGNAL`].
    pub degradation_low: T,
    /// Window amplitude above this: [`Faults::DEGRADATION_OF_SIGNAL`].
    pub degradation_high: T,
    /// Mean `|eps|` over a window above this: [`Faults::LOSS_OF_TRACKING`]. `eps` is the normalised
    /// phase error (about the sine of the angle error), so this is dimensionless, the same
    /// for every amplitude.
    pub loss_of_tracking: T,
    /// Estimated `|speed|` (rad/s) at the end of a window above this:
    /// [`Faults::LOSS_OF_TRACKING`]. `None`: a
    /// quarter turn per sample, `pi / (2 Ts)` (`docs/theory.md §9`). Named
    /// `max_speed_rad_s` in errors and in the Python API.
    pub max_speed: Option<T>,
    /// `1 / W`, in (0, 1], for the monitor's window of `W` used samples: `W` is `1 /
    /// filter_factor` rounded down to a power of two, at most 4096 (the default 1/16
    /// gives 16). The flags are decided once per window, from its means: a fault
    /// present over a whole window is flagged within `2 W - 1` used samples.
    pub filter_factor: T,
    /// In-phase component `y_c cos + y_s sin` (about `A cos(error)`) of the last sample of a
    /// window, at its corrected angle, below this, with the signal present: a lock about
    /// 180 degrees off.
    pub false_lock: T,
    /// Compute the flags (loss of signal, degradation, loss of tracking, false lock). When
    /// `false`, only the input check runs (cheapest update).
    pub monitor: bool,
    /// On a false lock, re-acquire the angle from `atan2(y_s, y_c)`, keeping speed and
    /// acceleration.
    pub re_acquire: bool,
}

/// Defines, for the float type `$t` (its functions in module `$m`), the `const fn`s that
/// make and check thresholds: one implementation for both types and for both the generic
/// and the `const` constructors (constant evaluation cannot call trait methods).
macro_rules! threshold_fns {
    ($t:ident, $m:ident, sqrt_min_positive $sqrt_min_positive:expr) => {
        use super::{CheckedThresholds, FaultThresholds};
        use $crate::error::$m::check_positive;
        use $crate::error::{ConfigError, Parameter, const_try};

        /// `sqrt(MIN_POSITIVE)` (exact: a power of two).
        const SQRT_MIN_POSITIVE: $t = $sqrt_min_positive;

        /// See [`FaultThresholds::for_amplitude`]; the fractions are the `f32` values in
        /// both types, so that `f32` and `f64` thresholds agree exactly.
        pub(crate) const fn for_amplitude(a: $t) -> FaultThresholds<$t> {
            FaultThresholds {
                nominal_amplitude: a,
                max_input_amplitude: 4.0 * a,
                loss_of_signal: 0.25 * a,
                degradation_low: 0.5 * a,
                degradation_high: 1.5 * a,
                loss_of_tracking: 0.1_f32 as $t,
                max_speed: None,
                filter_factor: 0.0625,
                false_lock: 0.0,
                monitor: true,
                re_acquire: true,
            }
        }

        /// See [`FaultThresholds::check`].
        pub(crate) const fn check(
            t: &FaultThresholds<$t>,
            sample_period_s: $t,
        ) -> Result<CheckedThresholds<$t>, ConfigError> {
            let a = const_try!(check_positive(
                t.nominal_amplitude,
                Parameter::NominalAmplitude
            ));
            let max_in = const_try!(check_positive(
                t.max_input_amplitude,
                Parameter::MaxInputAmplitude
            ));
            let los = const_try!(check_positive(
                t.loss_of_signal,
                Parameter::LossOfSignalThreshold
            ));
            let low = const_try!(check_positive(
                t.degradation_low,
                Parameter::DegradationLowThreshold
            ));
            let high = const_try!(check_positive(
                t.degradation_high,
                Parameter::DegradationHighThreshold
            ));
            const_try!(check_positive(
                t.loss_of_tracking,
                Parameter::LossOfTrackingThreshold
            ));
            let k = const_try!(check_positive(t.filter_factor, Parameter::FilterFactor));
            let max_speed = match t.max_speed {
                Some(s) => const_try!(check_positive(s, Parameter::MaxSpeed)),
                None => core::$t::consts::FRAC_PI_2 / sample_period_s,
            };
            if !t.false_lock.is_finite() {
                return Err(ConfigError::NotFinite(Parameter::FalseLockThreshold));
            }
            let ordered = [
                (los < low, Parameter::LossOfSignalThreshold),
                (low < a, Parameter::DegradationLowThreshold),
                (high > a, Parameter::DegradationHighThreshold),
                (max_in >= high, Parameter::MaxInputAmplitude),
                (k <= 1.0, Parameter::FilterFactor),
                (t.false_lock.abs() < a, Parameter::FalseLockThreshold),
            ];
            let mut i = 0;
            while i < ordered.len() {
                if !ordered[i].0 {
                    return Err(ConfigError::OutOfRange(ordered[i].1));
                }
                i += 1;
            }
            // The window: the largest power of two W <= 1/k (k <= 1, checked above), at
            // most MAX_WINDOW.
            let mut window = 1u32;
            while window < super::MAX_WINDOW && (2 * window) as $t * k <= 1.0 {
                window *= 2;
            }
            let max_input2 = max_in * max_in;
            // The amplitude tracker divides `y_c^2 + y_s^2` by a magnitude that is at least
            // `sqrt(MIN_POSITIVE)` (`docs/theory.md §12`): the quotient must stay finite.
            if !(max_input2 / SQRT_MIN_POSITIVE).is_finite() {
                return Err(ConfigError::OutOfRange(Parameter::MaxInputAmplitude));
            }
            Ok(CheckedThresholds {
                thresholds: *t,
                max_input2,
                loss_of_signal2: los * los,
                degradation_low2: low * low,
                degradation_high2: high * high,
                degradation_middle2: (low * low + high * high) * 0.5,
                degradation_half_width2: (high * high - low * low) * 0.5,
                max_scaled_speed: max_speed * sample_period_s,
                window,
                window_inverse: 1.0 / window as $t,
            })
        }
    };
}

/// The `f32` functions.
pub(crate) mod for_f32 {
    threshold_fns!(f32, for_f32, sqrt_min_positive f32::from_bits(0x2000_0000)); // 2^-63
}

/// The `f64` functions.
pub(crate) mod for_f64 {
    threshold_fns!(f64, for_f64, sqrt_min_positive f64::from_bits(0x2000_0000_0000_0000)); // 2^-511
}

/// The largest window of the monitor (used samples): `2^12`, so that its sums stay accurate
/// in `f32` and a fault is flagged within `2^13` samples whatever the filter factor.
pub(crate) const MAX_WINDOW: u32 = 1 << 12;

/// The thresholds with the per-sample comparisons precomputed (squared amplitudes, speed
/// in rad per sample), so the update needs no square root.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckedThresholds<T> {
    pub(crate) thresholds: FaultThresholds<T>,
    pub(crate) max_input2: T,
    pub(crate) loss_of_signal2: T,
    pub(crate) degradation_low2: T,
    pub(crate) degradation_high2: T,
    /// The middle of [`degradation_low2`, `degradation_high2`] and its half width: the
    /// usual case tests the band with one comparison.
    pub(crate) degradation_middle2: T,
    pub(crate) degradation_half_width2: T,
    pub(crate) max_scaled_speed: T,
    /// The monitor's window `W` (used samples, a power of two) and `1 / W` (exact).
    pub(crate) window: u32,
    pub(crate) window_inverse: T,
}

/// The monitor's memory in each channel's state: the sums over the current window, the
/// used samples left in it, the flags of the last window and the latched fault register.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MonitorState<T> {
    /// Sum of `y_c^2 + y_s^2` over the current window.
    pub(crate) amplitude2_sum: T,
    /// Sum of `|eps|` over the current window.
    pub(crate) error_sum: T,
    /// Used samples left in the current window (0: no window started yet).
    pub(crate) remaining: u32,
    /// `1 / length` of the current window (exact: a power of two).
    pub(crate) length_inverse: T,
    /// Mean `y_c^2 + y_s^2` of the last window (of the first sample before one ends).
    pub(crate) amplitude2: T,
    /// The flags of the last window, held until the next one ends.
    pub(crate) flags: Faults,
    /// Flags latched until cleared.
    pub(crate) latched: Faults,
}

impl<T: Float> MonitorState<T> {
    /// A monitor whose first window starts at the next used sample.
    pub(crate) const fn new() -> Self {
        Self {
            amplitude2_sum: T::ZERO,
            error_sum: T::ZERO,
            remaining: 0,
            length_inverse: T::ONE,
            amplitude2: T::ZERO,
            flags: Faults::NONE,
            latched: Faults::NONE,
        }
    }

    /// Starts a new window of `window` used samples, whose `1 / window` is
    /// `window_inverse`. Done where the angle is set (first used sample, re-acquisition),
    /// so that no window mixes two angles.
    pub(crate) fn start_window(&mut self, window: u32, window_inverse: T) {
        self.amplitude2_sum = T::ZERO;
        self.error_sum = T::ZERO;
        self.remaining = window;
        self.length_inverse = window_inverse;
    }

    /// Adds one used sample to the window; `true` when it ends the window (the caller then
    /// decides the flags, [`CheckedThresholds::decide`]).
    #[inline(always)]
    pub(crate) fn accumulate(&mut self, amplitude2: T, phase_error: T) -> bool {
        self.amplitude2_sum += amplitude2;
        self.error_sum += phase_error.abs();
        self.remaining = self.remaining.wrapping_sub(1);
        self.remaining == 0
    }
}

impl<T: Float> CheckedThresholds<T> {
    /// `y_c^2 + y_s^2 + m` of a sample and whether it is accepted: finite and within the
    /// input bound (NaN compares false, so it is refused). `m` is [`Float::MIN_POSITIVE`],
    /// which keeps the amplitude tracker's magnitude positive (`docs/theory.md §12`) and is
    /// negligible anywhere else; added first, it costs no instruction of its own.
    #[inline(always)]
    pub(crate) fn accept(&self, y_c: T, y_s: T) -> (T, bool) {
        let amplitude2 = self.amplitude2(y_c, y_s);
        (amplitude2, amplitude2 <= self.max_input2)
    }

    /// `y_c^2 + y_s^2 + m` (see [`CheckedThresholds::accept`]).
    #[inline(always)]
    pub(crate) fn amplitude2(&self, y_c: T, y_s: T) -> T {
        (T::MIN_POSITIVE + y_c * y_c) + y_s * y_s
    }

    /// The end of a window: its flags from its means, and from the speed `scaled_speed`
    /// (rad per sample) and the in-phase component `in_phase` (`y_c cos + y_s sin` of the
    /// corrected angle) of its last sample, held in `monitor.flags` and latched, and a new
    /// window started. Returns `true` when the angle must be re-acquired (false lock).
    pub(crate) fn decide(
        &self,
        monitor: &mut MonitorState<T>,
        scaled_speed: T,
        in_phase: T,
    ) -> bool {
        let mean = |sum: T| sum * monitor.length_inverse;
        let (a2, error) = (mean(monitor.amplitude2_sum), mean(monitor.error_sum));
        monitor.amplitude2 = a2;
        let t = &self.thresholds;
        // The usual case in one chain of tests: no flag at all. Loss of signal lies below the
        // degradation band (checked at construction), so an amplitude inside the band rules
        // out both; one comparison for the band (one rounding of its edges, which `flags`
        // then sorts out exactly; NaN fails it).
        let (faults, false_lock) = if (a2 - self.degradation_middle2).abs()
            <= self.degradation_half_width2
            && error <= t.loss_of_tracking
            && scaled_speed.abs() <= self.max_scaled_speed
            && in_phase >= t.false_lock
        {
            (Faults::NONE, false)
        } else {
            self.flags(a2, error, in_phase, scaled_speed)
        };
        monitor.flags = faults;
        monitor.latched |= faults;
        monitor.start_window(self.window, self.window_inverse);
        false_lock && self.thresholds.re_acquire
    }

    /// The flags of a window outside the usual case of [`CheckedThresholds::decide`] (out
    /// of line: a fault is rare), and whether they declare a false lock.
    #[cold]
    #[inline(never)]
    fn flags(&self, a2: T, error: T, in_phase: T, scaled_speed: T) -> (Faults, bool) {
        let t = &self.thresholds;
        let signal_lost = a2 < self.loss_of_signal2;
        let faults = Faults::when(signal_lost, Faults::LOSS_OF_SIGNAL)
            | Faults::when(
                a2 < self.degradation_low2 || a2 > self.degradation_high2,
                Faults::DEGRADATION_OF_SIGNAL,
            )
            | Faults::when(
                error > t.loss_of_tracking || scaled_speed.abs() > self.max_scaled_speed,
                Faults::LOSS_OF_TRACKING,
            );
        let false_lock = !signal_lost && in_phase < t.false_lock;
        (
            faults | Faults::when(false_lock, Faults::FALSE_LOCK),
            false_lock,
        )
    }
}

#[cfg(test)]
mod latency_tests;
#[cfg(test)]
mod tests;
