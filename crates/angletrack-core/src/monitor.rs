//! Diagnostics like an RDC chip's fault register (`docs/theory.md §10`): the input check
//! that rejects bad samples, and the monitor that flags loss of signal, degradation of
//! signal, loss of tracking and false lock from first-order filters of the amplitude, the
//! phase error and the in-phase component. Its thresholds are checked at construction.

use crate::error::ConfigError;
use crate::faults::Faults;
use crate::real::Real;

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
/// | `filter_factor` | 1/16 (first-order filters, time constant 16 samples) |
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
    /// Filtered amplitude below this: [`Faults::LOSS_OF_SIGNAL`].
    pub loss_of_signal: T,
    /// Filtered amplitude below this: [`Faults::DEGRADATION_OF_SIGNAL`].
    pub degradation_low: T,
    /// Filtered amplitude above this: [`Faults::DEGRADATION_OF_SIGNAL`].
    pub degradation_high: T,
    /// Filtered `|eps|` above this: [`Faults::LOSS_OF_TRACKING`]. `eps` is the normalised
    /// phase error (about the sine of the angle error), so this is dimensionless, the same
    /// for every amplitude.
    pub loss_of_tracking: T,
    /// Estimated `|speed|` (rad/s) above this: [`Faults::LOSS_OF_TRACKING`]. `None`: a
    /// quarter turn per sample, `pi / (2 Ts)` (`docs/theory.md §9`). Named
    /// `max_speed_rad_s` in errors and in the Python API.
    pub max_speed: Option<T>,
    /// Smoothing factor `k` of the first-order filters `f += k (value - f)`, in (0, 1].
    pub filter_factor: T,
    /// Filtered in-phase component `y_c cos + y_s sin` (about `A cos(error)`) below this,
    /// with the signal present: a lock about 180 degrees off.
    pub false_lock: T,
    /// Compute the flags (loss of signal, degradation, loss of tracking, false lock). When
    /// `false`, only the input check runs (cheapest update).
    pub monitor: bool,
    /// On a false lock, re-acquire the angle from `atan2(y_s, y_c)`, keeping speed and
    /// acceleration.
    pub re_acquire: bool,
}

impl<T: Real> Default for FaultThresholds<T> {
    fn default() -> Self {
        Self::for_amplitude(T::ONE)
    }
}

impl<T: Real> FaultThresholds<T> {
    /// The default thresholds (see the table above) with the amplitude checks scaled to a
    /// nominal amplitude (in the units of `y_c`, `y_s`); the loss-of-tracking threshold is
    /// dimensionless and stays 0.1.
    ///
    /// ```
    /// use angletrack_core::FaultThresholds;
    /// // Raw 12-bit ADC counts with the mid-scale removed, amplitude about 1800 counts.
    /// let t = FaultThresholds::<f32>::for_amplitude(1800.0);
    /// assert_eq!(t.loss_of_signal, 450.0);
    /// assert_eq!(t.loss_of_tracking, 0.1);
    /// ```
    pub fn for_amplitude(nominal_amplitude: T) -> Self {
        T::thresholds_for_amplitude(nominal_amplitude)
    }

    /// No diagnostics and no re-acquisition, only the input check: the bare loop of the
    /// paper (use it to study the loop's own large-signal behaviour).
    ///
    /// ```
    /// use angletrack_core::FaultThresholds;
    /// let t = FaultThresholds::<f64>::disabled();
    /// assert!(!t.monitor && !t.re_acquire);
    /// ```
    pub fn disabled() -> Self {
        Self {
            monitor: false,
            re_acquire: false,
            ..Self::default()
        }
    }

    /// Checks the thresholds: all finite and positive (the false-lock threshold may be
    /// zero or negative, within the nominal amplitude), ordered
    /// `loss_of_signal < degradation_low < nominal < degradation_high <= max_input`,
    /// filter factor in (0, 1]. Returns the squared-amplitude form used per sample.
    pub(crate) fn check(&self, sample_period_s: T) -> Result<CheckedThresholds<T>, ConfigError> {
        T::check_thresholds(self, sample_period_s)
    }
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
}

/// The monitor's memory in each channel's state: three first-order filters and the latched
/// fault register.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MonitorState<T> {
    /// Filtered `y_c^2 + y_s^2`.
    pub(crate) amplitude2: T,
    /// Filtered `|eps|`.
    pub(crate) error: T,
    /// Filtered `y_c cos + y_s sin`.
    pub(crate) in_phase: T,
    /// Flags latched until cleared.
    pub(crate) latched: Faults,
}

impl<T: Real> MonitorState<T> {
    /// A monitor whose filters start from the next sample.
    pub(crate) const fn new() -> Self {
        Self {
            amplitude2: T::ZERO,
            error: T::ZERO,
            in_phase: T::ZERO,
            latched: Faults::NONE,
        }
    }

    /// Starts the phase-error and in-phase filters from an angle that agrees with the
    /// sample of magnitude `magnitude`: no error, the in-phase component the magnitude.
    /// Done where the angle is set (first sample, re-acquisition), so that the per-sample
    /// update has no first-sample test.
    pub(crate) fn prime_phase(&mut self, magnitude: T) {
        self.error = T::ZERO;
        self.in_phase = magnitude;
    }

    /// Starts the phase-error and in-phase filters from one sample's normalised phase error
    /// and in-phase component: for an angle that was set without looking at the sample
    /// (`ObserverState::at`), which may disagree with it by any amount.
    pub(crate) fn prime_from_sample(&mut self, phase_error: T, in_phase: T) {
        self.error = phase_error.abs();
        self.in_phase = in_phase;
    }
}

impl<T: Real> CheckedThresholds<T> {
    /// `y_c^2 + y_s^2 + m` of a sample and whether it is accepted: finite and within the
    /// input bound (NaN compares false, so it is refused). `m` is [`Real::MIN_POSITIVE`],
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

    /// Updates the filters with one accepted sample and returns its flags; the second value
    /// is `true` when the angle must be re-acquired (false lock).
    #[inline(always)]
    pub(crate) fn observe(
        &self,
        monitor: &mut MonitorState<T>,
        amplitude2: T,
        phase_error: T,
        in_phase: T,
        scaled_speed: T,
    ) -> (Faults, bool) {
        let t = &self.thresholds;
        let k = t.filter_factor;
        monitor.amplitude2 += k * (amplitude2 - monitor.amplitude2);
        monitor.error += k * (phase_error.abs() - monitor.error);
        monitor.in_phase += k * (in_phase - monitor.in_phase);
        let a2 = monitor.amplitude2;
        // The usual case in one chain of tests: no flag at all. Loss of signal lies below the
        // degradation band (checked at construction), so an amplitude inside the band rules
        // out both; then tracking and the in-phase component. Anything else is sorted out of
        // line, flag by flag.
        // One comparison for the band (one rounding of its edges, which `flags` then
        // sorts out exactly; NaN fails it).
        if (a2 - self.degradation_middle2).abs() <= self.degradation_half_width2
            && monitor.error <= t.loss_of_tracking
            && scaled_speed.abs() <= self.max_scaled_speed
            && monitor.in_phase >= t.false_lock
        {
            return (Faults::NONE, false);
        }
        let (faults, false_lock) = self.flags(a2, monitor.error, monitor.in_phase, scaled_speed);
        monitor.latched |= faults;
        (faults, false_lock && t.re_acquire)
    }

    /// The flags of filtered values outside the usual case of [`CheckedThresholds::observe`]
    /// (out of line: a fault is rare), and whether they declare a false lock.
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
mod tests;
