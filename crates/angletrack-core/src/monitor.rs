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
    /// Window ends left that flag [`Faults::LOSS_OF_TRACKING`] whatever their means, after
    /// an implausible re-acquisition (`crate::reacquisition`).
    pub(crate) held_windows: u32,
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
            held_windows: 0,
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
}

/// The floats' window: the sums of `y_c^2 + y_s^2` and of `|eps|`.
impl<T: Float> MonitorWindow for MonitorState<T> {
    /// `(y_c^2 + y_s^2, eps)`.
    type Term = (T, T);

    #[inline(always)]
    fn add(&mut self, (amplitude2, phase_error): (T, T)) {
        self.amplitude2_sum += amplitude2;
        self.error_sum += phase_error.abs();
    }

    #[inline(always)]
    fn remaining(&mut self) -> &mut u32 {
        &mut self.remaining
    }
}

/// A monitor's window as each used sample sees it, written once for the floats
/// ([`MonitorState`]) and the fixed-point observer (its state, `fixed/update.rs`): the
/// sample added to the window's sums, and the count down to the window's end, where the
/// caller decides the flags ([`MonitorLimits::decide_window`]).
pub(crate) trait MonitorWindow {
    /// What one used sample adds to the window.
    type Term;

    /// Adds `term` to the window's sums.
    fn add(&mut self, term: Self::Term);

    /// The used samples left in the window.
    fn remaining(&mut self) -> &mut u32;

    /// Adds one used sample to the window; `true` when it ends the window.
    #[inline(always)]
    fn accumulate(&mut self, term: Self::Term) -> bool {
        self.add(term);
        let remaining = self.remaining();
        *remaining = remaining.wrapping_sub(1);
        *remaining == 0
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
        let measures = WindowMeasures {
            amplitude2: a2,
            error,
            speed: scaled_speed.abs(),
            in_phase,
        };
        let false_lock = self.decide_window(&measures, &mut monitor.flags, &mut monitor.latched);
        if monitor.held_windows > 0 {
            monitor.hold_implausible_jump();
        }
        monitor.start_window(self.window, self.window_inverse);
        false_lock && self.thresholds.re_acquire
    }
}

/// What the monitor decides a window's flags from, in the numbers of its observer: its
/// amplitude `A` (the floats: the mean `y_c^2 + y_s^2`; the fixed-point observer: half the
/// square amplitude of its last sample), its phase error `E` (the mean `|eps|`; the sum of
/// `|eps|` in Q15), the magnitude of the speed `S` at its end (rad per sample; 2^-32 turn per
/// sample) and the in-phase component `P` of its last sample.
#[derive(Debug, Clone, Copy)]
pub(crate) struct WindowMeasures<A, E, S, P> {
    pub(crate) amplitude2: A,
    pub(crate) error: E,
    pub(crate) speed: S,
    pub(crate) in_phase: P,
}

/// The monitor's decision on a window, written once over the [`Limits`] its
/// [`WindowMeasures`] are compared with, in the same numbers: the floats'
/// [`CheckedThresholds`] and the fixed-point observer's integer thresholds
/// (`fixed/gains.rs`).
pub(crate) trait MonitorLimits {
    /// The amplitude measure.
    type Amplitude2: AmplitudeMeasure;
    /// The phase error measure.
    type Error: Copy + PartialOrd;
    /// The magnitude of the speed.
    type Speed: Copy + PartialOrd;
    /// The in-phase component.
    type InPhase: Copy + PartialOrd;

    /// The limits, as values (each read only where a test needs it, once inlined).
    fn limits(&self) -> Limits<Self::Amplitude2, Self::Error, Self::Speed, Self::InPhase>;

    /// Whether a window is healthy, in one chain of tests: no flag at all. Loss of signal
    /// lies below the degradation band, so an amplitude inside the band rules out both.
    #[inline(always)]
    fn healthy(&self, m: &Measures<Self>) -> bool {
        let l = self.limits();
        m.amplitude2.in_band(l.band)
            && m.error <= l.loss_of_tracking
            && m.speed <= l.max_speed
            && m.in_phase >= l.false_lock
    }

    /// A window's flags, held in `flags` and latched in `latched`; returns whether they
    /// declare a false lock. A healthy window clears the flags and nothing more (the usual
    /// case, inline); any other is [`MonitorLimits::latch_flags`] (out of line).
    #[inline(always)]
    fn decide_window(&self, m: &Measures<Self>, flags: &mut Faults, latched: &mut Faults) -> bool {
        if self.healthy(m) {
            *flags = Faults::NONE;
            return false;
        }
        // The measures by value: in registers, not stored for the call.
        self.latch_flags(m.amplitude2, m.error, m.speed, m.in_phase, flags, latched)
    }

    /// The flags of a window that is not [`MonitorLimits::healthy`], held in `flags` and
    /// latched in `latched` (out of line: a fault is rare); returns whether they declare a
    /// false lock.
    #[cold]
    #[inline(never)]
    fn latch_flags(
        &self,
        a2: Self::Amplitude2,
        error: Self::Error,
        speed: Self::Speed,
        in_phase: Self::InPhase,
        flags: &mut Faults,
        latched: &mut Faults,
    ) -> bool {
        let (faults, false_lock) = self.flags(a2, error, speed, in_phase);
        *flags = faults;
        *latched |= faults;
        false_lock
    }

    /// The flags of a window that is not [`MonitorLimits::healthy`], from its
    /// [`WindowMeasures`], and whether they declare a false lock.
    #[inline(always)]
    fn flags(
        &self,
        a2: Self::Amplitude2,
        error: Self::Error,
        speed: Self::Speed,
        in_phase: Self::InPhase,
    ) -> (Faults, bool) {
        let l = self.limits();
        let signal_lost = a2 < l.loss_of_signal;
        let faults = Faults::when(signal_lost, Faults::LOSS_OF_SIGNAL)
            | Faults::when(
                a2 < l.degradation_low || a2 > l.degradation_high,
                Faults::DEGRADATION_OF_SIGNAL,
            )
            | Faults::when(
                error > l.loss_of_tracking || speed > l.max_speed,
                Faults::LOSS_OF_TRACKING,
            );
        let false_lock = !signal_lost && in_phase < l.false_lock;
        (
            faults | Faults::when(false_lock, Faults::FALSE_LOCK),
            false_lock,
        )
    }
}

/// What a window's [`WindowMeasures`] are compared with, in the same numbers: loss of signal
/// below `loss_of_signal`, degradation outside [`degradation_low`, `degradation_high`] (loss
/// of signal lies below that band, checked at construction), loss of tracking above
/// `loss_of_tracking` or `max_speed`, false lock below `false_lock` with the signal present.
pub(crate) struct Limits<A, E, S, P> {
    pub(crate) loss_of_signal: A,
    pub(crate) degradation_low: A,
    pub(crate) degradation_high: A,
    /// The degradation band in the form of its one comparison
    /// ([`AmplitudeMeasure::in_band`]).
    pub(crate) band: (A, A),
    pub(crate) loss_of_tracking: E,
    pub(crate) max_speed: S,
    pub(crate) false_lock: P,
}

/// The [`WindowMeasures`] in the numbers of limits `L`.
pub(crate) type Measures<L> = WindowMeasures<
    <L as MonitorLimits>::Amplitude2,
    <L as MonitorLimits>::Error,
    <L as MonitorLimits>::Speed,
    <L as MonitorLimits>::InPhase,
>;

/// A monitor's amplitude measure: a float, or the fixed-point observer's `u32`
/// (`fixed/gains.rs`).
pub(crate) trait AmplitudeMeasure: Copy + PartialOrd {
    /// Whether `self` lies in the degradation band, by one comparison with the band's
    /// precomputed form `band` (NaN is outside).
    fn in_band(self, band: (Self, Self)) -> bool;
}

/// The band as its middle and half width: `|a - middle| <= half_width` (one rounding of its
/// edges, which [`MonitorLimits::flags`] then sorts out exactly).
impl<T: Float> AmplitudeMeasure for T {
    #[inline(always)]
    fn in_band(self, (middle, half_width): (T, T)) -> bool {
        (self - middle).abs() <= half_width
    }
}

/// The floats' limits: the squared amplitudes, the mean `|eps|`, the speed in rad per
/// sample and the in-phase component, from the checked thresholds.
impl<T: Float> MonitorLimits for CheckedThresholds<T> {
    type Amplitude2 = T;
    type Error = T;
    type Speed = T;
    type InPhase = T;

    #[inline(always)]
    fn limits(&self) -> Limits<T, T, T, T> {
        Limits {
            loss_of_signal: self.loss_of_signal2,
            degradation_low: self.degradation_low2,
            degradation_high: self.degradation_high2,
            band: (self.degradation_middle2, self.degradation_half_width2),
            loss_of_tracking: self.thresholds.loss_of_tracking,
            max_speed: self.max_scaled_speed,
            false_lock: self.thresholds.false_lock,
        }
    }
}

#[cfg(test)]
mod latency_tests;
#[cfg(test)]
mod tests;
