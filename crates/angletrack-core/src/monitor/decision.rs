//! The monitor's decision on a window, written once for the floats and the fixed-point
//! observer: what it decides from ([`WindowMeasures`]), what it compares them with
//! ([`Limits`]), and the decision itself ([`MonitorLimits`]), with the roundness check's
//! hold.

use super::{CheckedThresholds, ROUNDNESS_HOLD_WINDOWS};
use crate::faults::Faults;
use crate::real::Float;

/// What the monitor decides a window's flags from, in the numbers of its observer: its
/// amplitude `A` (the floats: the mean `y_c^2 + y_s^2`; the fixed-point observer: half the
/// square amplitude of its last sample), its phase error `E` (the mean `|eps|`; the sum of
/// `|eps|` in Q15), the magnitude of the speed `S` at its end (rad per sample; 2^-32 turn per
/// sample), the in-phase component `P` of its last sample and that sample's square
/// magnitude (the floats: `y_c^2 + y_s^2`; the fixed-point observer: half of it, its `A`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct WindowMeasures<A, E, S, P> {
    pub(crate) amplitude2: A,
    pub(crate) error: E,
    pub(crate) speed: S,
    pub(crate) in_phase: P,
    pub(crate) sample2: A,
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
            && m.sample2.in_band(l.round)
            && m.error <= l.loss_of_tracking
            && m.speed <= l.max_speed
            && m.in_phase >= l.false_lock
    }

    /// A window's flags, held in `flags` and latched in `latched`, the roundness flag's
    /// hold counted down in `round_hold`; returns whether they declare a false lock. A
    /// healthy window with no hold clears the flags and nothing more (the usual case,
    /// inline); any other is [`MonitorLimits::latch_flags`] (out of line).
    #[inline(always)]
    fn decide_window(
        &self,
        m: &Measures<Self>,
        flags: &mut Faults,
        latched: &mut Faults,
        round_hold: &mut u8,
    ) -> bool {
        if self.healthy(m) && *round_hold == 0 {
            *flags = Faults::NONE;
            return false;
        }
        // The measures by value: in registers, not stored for the call.
        self.latch_flags(
            m.amplitude2,
            m.error,
            m.speed,
            m.in_phase,
            m.sample2,
            flags,
            (latched, round_hold),
        )
    }

    /// The flags of a window that is not [`MonitorLimits::healthy`], held in `flags` and
    /// latched in `latched` (out of line: a fault is rare); returns whether they declare a
    /// false lock.
    /// A last sample off the circle sets the hold; one on it counts the hold down,
    /// flagging degradation while it lasts.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn latch_flags(
        &self,
        a2: Self::Amplitude2,
        error: Self::Error,
        speed: Self::Speed,
        in_phase: Self::InPhase,
        sample2: Self::Amplitude2,
        flags: &mut Faults,
        (latched, round_hold): (&mut Faults, &mut u8),
    ) -> bool {
        let (mut faults, false_lock) = self.flags(a2, error, speed, in_phase);
        if !sample2.in_band(self.limits().round) {
            *round_hold = ROUNDNESS_HOLD_WINDOWS;
            faults |= Faults::DEGRADATION_OF_SIGNAL;
        } else if *round_hold > 0 {
            *round_hold -= 1;
            faults |= Faults::DEGRADATION_OF_SIGNAL;
        }
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
    /// The band of a window's last sample's square magnitude, in the same form.
    pub(crate) round: (A, A),
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
            round: (self.round_middle2, self.round_half_width2),
            loss_of_tracking: self.thresholds.loss_of_tracking,
            max_speed: self.max_scaled_speed,
            false_lock: self.thresholds.false_lock,
        }
    }
}
