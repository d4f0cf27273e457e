//! Diagnostics like an RDC chip's fault register (`docs/theory.md §10`): the input check
//! that rejects bad samples, and the monitor that flags loss of signal, degradation of
//! signal, loss of tracking and false lock from the means of the amplitude and of the
//! phase error over windows of samples, and from the speed and the in-phase component at
//! each window's end. Its thresholds are checked at construction.
//!
//! Each used sample only adds to two sums, compares its residual `|eps|` with the
//! tracking-error level (`tracking`: a sample beyond it is flagged on itself) and counts
//! down (a few instructions); the other flags are decided once per window of `W` used samples (`W` a power of two, 16 by
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
/// | `tracking_error` | 0.05 (one sample's `|eps|`: 2.9 degrees; held down to half of it) |
/// | `max_speed` | `None`: pi/2 rad per sample, i.e. `pi / (2 Ts)` rad/s |
/// | `filter_factor` | 1/16 (windows of 16 samples) |
/// | `false_lock` | 0 (filtered in-phase component; 0 means an error beyond 90 degrees) |
/// | `magnitude_tolerance` | 0.1 (a window's last sample's magnitude within 10 % of the stated nominal amplitude); `None` in [`Default`], whose amplitude is not stated |
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
    /// One sample's `|eps|` above this: [`Faults::LOSS_OF_TRACKING`] at once, on that sample,
    /// held while `|eps|` stays above [`TRACKING_RELEASE_FRACTION`] of it (the loop's
    /// re-convergence) and latched (`docs/theory.md §10`). Dimensionless like
    /// `loss_of_tracking` (the sine of the angle between a sample and its prediction, in
    /// electrical radians for a sensor of several pole pairs); any positive value (above 1
    /// it never trips but for an amplitude step). While the flag is clear, the estimate is
    /// within about `(1 - l1) asin(tracking_error)` of the measured angle. The default 0.05
    /// is half the default `loss_of_tracking`; it stays clear of noise whose standard
    /// deviation per channel is below about 0.6 % of the amplitude (`|eps|` then stays below
    /// 8 standard deviations); for noisier signals
    /// [`FaultThresholds::with_tracking_error_above_noise`] sets it to 8 times the noise's
    /// fraction of the amplitude (the `angletrack` crate does, on the thresholds it measures
    /// on a capture).
    pub tracking_error: T,
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
    /// The largest distance, as a fraction of `nominal_amplitude`, of the magnitude
    /// `sqrt(y_c^2 + y_s^2)` of a window's last sample from `nominal_amplitude`: further,
    /// [`Faults::DEGRADATION_OF_SIGNAL`], held until [`ROUNDNESS_HOLD_WINDOWS`] windows in a
    /// row end within it. `Some(0.1)` from [`FaultThresholds::for_amplitude`] (the caller
    /// states the amplitude); `None` (no check) in the [`Default`] thresholds, whose
    /// amplitude of 1 is a placeholder (a fraction of full scale, say, that a signal need
    /// not reach). A healthy pair is round (its magnitude the same at every angle);
    /// a dead, open, shorted or stuck channel, an imbalance, a quadrature error, clipping
    /// or a coupled carrier make it depart from the circle at most angles, while the loop
    /// follows the faulty pair and its residual stays small (`docs/guide/diagnostics.md`).
    pub magnitude_tolerance: Option<T>,
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
                tracking_error: super::DEFAULT_TRACKING_ERROR as $t,
                max_speed: None,
                filter_factor: 0.0625,
                false_lock: 0.0,
                magnitude_tolerance: Some(0.1_f32 as $t),
                monitor: true,
                re_acquire: true,
            }
        }

        /// The thresholds of an observer whose caller stated no amplitude: those of
        /// amplitude 1 without the roundness check (`magnitude_tolerance` `None`).
        pub(crate) const fn unstated() -> FaultThresholds<$t> {
            FaultThresholds {
                magnitude_tolerance: None,
                ..for_amplitude(1.0)
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
            const_try!(check_positive(
                t.tracking_error,
                Parameter::TrackingErrorThreshold
            ));
            let k = const_try!(check_positive(t.filter_factor, Parameter::FilterFactor));
            let max_speed = match t.max_speed {
                Some(s) => const_try!(check_positive(s, Parameter::MaxSpeed)),
                None => core::$t::consts::FRAC_PI_2 / sample_period_s,
            };
            let tolerance = match t.magnitude_tolerance {
                Some(r) => Some(const_try!(check_positive(r, Parameter::MagnitudeTolerance))),
                None => None,
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
            // The band of the square magnitude: [(1 - r)^2, (1 + r)^2] a^2, its lower edge 0
            // for a tolerance of 1 or more; without the check, a band no number leaves.
            let (round_middle2, round_half_width2) = match tolerance {
                Some(r) => {
                    let (below, above) = (1.0 - r, 1.0 + r);
                    let below = if below > 0.0 { below } else { 0.0 };
                    let (low2, high2) = (below * below * a * a, above * above * a * a);
                    ((low2 + high2) * 0.5, (high2 - low2) * 0.5)
                }
                None => (0.0, $t::INFINITY),
            };
            Ok(CheckedThresholds {
                thresholds: *t,
                round_middle2,
                round_half_width2,
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

/// The default [`FaultThresholds::tracking_error`]: half the default `loss_of_tracking`.
pub(crate) const DEFAULT_TRACKING_ERROR: f32 = 0.05;

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
    /// The band of a window's last sample's square magnitude (`magnitude_tolerance`), as
    /// its middle and half width.
    pub(crate) round_middle2: T,
    pub(crate) round_half_width2: T,
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
    /// Window ends left that flag [`Faults::LOSS_OF_TRACKING`] whatever their means, after
    /// an implausible re-acquisition (`crate::reacquisition`).
    pub(crate) held_windows: u8,
    /// Window ends left that flag [`Faults::DEGRADATION_OF_SIGNAL`] after one whose last
    /// sample was off the circle ([`FaultThresholds::magnitude_tolerance`]).
    pub(crate) round_hold: u8,
    /// The per-sample tracking-error check ([`FaultThresholds::tracking_error`]).
    pub(crate) tracking: TrackingCheck<T>,
}

/// The window ends in a row whose last sample must be within
/// [`FaultThresholds::magnitude_tolerance`] before the degradation flag it raised is
/// cleared: a faulty pair looks round at some angles (a dead channel's near its healthy
/// winding's peaks), and the flag holds through them.
pub const ROUNDNESS_HOLD_WINDOWS: u8 = 8;

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
            held_windows: 0,
            round_hold: 0,
            tracking: TrackingCheck::new(),
        }
    }

    /// The faults of the current sample: the last window's flags and the per-sample
    /// tracking-error check's.
    #[inline(always)]
    pub(crate) fn sample_faults(&self) -> Faults {
        self.flags | self.tracking.flag()
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
}

/// The floats' window: the sums of `y_c^2 + y_s^2` and of `|eps|`.
impl<T: Float> MonitorWindow for MonitorState<T> {
    /// `(y_c^2 + y_s^2, eps)`.
    type Term = (T, T);
    /// `|eps|`.
    type Residual = T;

    #[inline(always)]
    fn add(&mut self, (amplitude2, phase_error): (T, T)) -> T {
        let residual = phase_error.abs();
        self.amplitude2_sum += amplitude2;
        self.error_sum += residual;
        residual
    }

    #[inline(always)]
    fn remaining(&mut self) -> &mut u32 {
        &mut self.remaining
    }

    #[inline(always)]
    fn tracking(&self) -> &TrackingCheck<T> {
        &self.tracking
    }
}

/// A monitor's window as each used sample sees it, written once for the floats
/// ([`MonitorState`]) and the fixed-point observer (its state, `fixed/update.rs`): the
/// sample added to the window's sums, its residual checked against the per-sample
/// tracking-error level ([`TrackingCheck`]), and the count down to the window's end, where
/// the caller decides the flags ([`MonitorLimits::decide_window`]).
pub(crate) trait MonitorWindow {
    /// What one used sample adds to the window.
    type Term;
    /// The sample's residual `|eps|`, in the observer's numbers.
    type Residual: tracking::Residual;

    /// Adds `term` to the window's sums; returns the sample's residual.
    fn add(&mut self, term: Self::Term) -> Self::Residual;

    /// The used samples left in the window.
    fn remaining(&mut self) -> &mut u32;

    /// The per-sample tracking-error check.
    fn tracking(&self) -> &TrackingCheck<<Self::Residual as tracking::Residual>::Level>;

    /// Adds one used sample to the window and checks its residual; `true` when it ends the
    /// window or its residual must go out of line ([`TrackingCheck::changes`]): the caller
    /// then runs its out-of-line path, which applies the check ([`TrackingCheck::apply`]) and
    /// decides the window if it ended.
    #[inline(always)]
    fn accumulate(&mut self, term: Self::Term) -> bool {
        let residual = self.add(term);
        let changes = self.tracking().changes(residual);
        let remaining = self.remaining();
        *remaining = remaining.wrapping_sub(1);
        (*remaining == 0) | changes
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
    /// (rad per sample), the in-phase component `in_phase` (`y_c cos + y_s sin` of the
    /// corrected angle) and the square magnitude `sample2` of its last sample, held in
    /// `monitor.flags` and latched, and a new window started. Returns `true` when the angle
    /// must be re-acquired (false lock).
    pub(crate) fn decide(
        &self,
        monitor: &mut MonitorState<T>,
        scaled_speed: T,
        in_phase: T,
        sample2: T,
    ) -> bool {
        let mean = |sum: T| sum * monitor.length_inverse;
        let (a2, error) = (mean(monitor.amplitude2_sum), mean(monitor.error_sum));
        monitor.amplitude2 = a2;
        let measures = WindowMeasures {
            amplitude2: a2,
            error,
            speed: scaled_speed.abs(),
            in_phase,
            sample2,
        };
        let false_lock = self.decide_window(
            &measures,
            &mut monitor.flags,
            &mut monitor.latched,
            &mut monitor.round_hold,
        );
        if monitor.held_windows > 0 {
            monitor.hold_implausible_jump();
        }
        monitor.tracking.arm(self.thresholds.tracking_error, error);
        monitor.start_window(self.window, self.window_inverse);
        false_lock && self.thresholds.re_acquire
    }
}

mod decision;
pub(crate) mod tracking;

pub(crate) use decision::{AmplitudeMeasure, Limits, Measures, MonitorLimits, WindowMeasures};
pub(crate) use tracking::TrackingCheck;
pub use tracking::{TRACKING_RELEASE_FRACTION, TRACKING_STARTUP_WINDOWS};

#[cfg(test)]
mod latency_tests;
#[cfg(test)]
mod roundness_tests;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tracking_tests;
