//! The per-sample tracking-error check, as an RDC chip flags loss of tracking whenever its
//! tracking error exceeds a threshold (`docs/theory.md §10`): written once for the floats
//! and the fixed-point observer, run where each used sample adds to the monitor's window
//! ([`MonitorWindow::accumulate`](super::MonitorWindow::accumulate)).
//!
//! A sample whose phase-detector residual `|eps|` (the normalised phase error before the
//! update, about the sine of the angle between the prediction and the measurement) exceeds
//! the trip level ([`FaultThresholds::tracking_error`](super::FaultThresholds::tracking_error))
//! is flagged [`Faults::LOSS_OF_TRACKING`] and latched; the flag holds while the residual
//! stays above the release level ([`TRACKING_RELEASE_FRACTION`] of the trip level), so that
//! the samples of the loop's re-convergence stay flagged. The update moves the angle by
//! `l1 eps` toward the measurement, so an estimate after an unflagged sample is within about
//! `(1 - l1) asin(trip level)` of the measured angle.
//!
//! Its cost per sample is one comparison with the level in force: the trip level while the
//! flag is clear, a level below every residual while it is held (every held sample then
//! takes the out-of-line path, which compares it with the release level: a held flag is a
//! fault, rare).

use crate::faults::Faults;
use crate::real::Float;

/// The release level as a fraction of the trip level: the flag set by a residual above the
/// trip level clears at the first residual at or below half of it.
pub const TRACKING_RELEASE_FRACTION: f32 = 0.5;

/// The monitor windows in a row whose mean residual must be at or below the release level
/// before the check arms after its start-up (`docs/guide/diagnostics.md`).
pub const TRACKING_STARTUP_WINDOWS: u32 = 2;

/// A level of the check as an observer's state stores it: it tells whether the flag is
/// held (a negative level, below every residual), and the start-up's progress (levels
/// above every usual residual, so that the start-up's samples stay on the per-sample path).
/// The levels are functions, not constants: the floats' arithmetic is not `const` for a
/// generic type (each is a constant once inlined).
pub(crate) trait Level: Copy + PartialEq {
    /// The level of a check not armed yet: one no residual exceeds.
    const UNARMED: Self;
    /// The level of a held flag (-1): below every residual.
    fn held() -> Self;
    /// The level of the start-up before a window whose mean residual is at or below the
    /// release level (2 pi, or 32766 in Q15): above every usual residual (one above goes out
    /// of line and changes nothing), so that the start-up is neither flagged nor latched.
    fn startup() -> Self;
    /// The level of the start-up after one such window (pi, or 32765): the next one ends
    /// it.
    fn settling() -> Self;
    /// Whether the flag is held (a negative level).
    fn holds(self) -> bool;
    /// Whether the level is [`Level::held`]: the flag is set.
    fn is_held(self) -> bool;
}

impl<T: Float> Level for T {
    const UNARMED: T = T::INFINITY;
    #[inline(always)]
    fn held() -> T {
        -T::ONE
    }
    #[inline(always)]
    fn startup() -> T {
        T::TAU
    }
    #[inline(always)]
    fn settling() -> T {
        T::PI
    }
    #[inline(always)]
    fn holds(self) -> bool {
        self < T::ZERO
    }
    /// Compared by their bits, an integer comparison (no library call on a Cortex-M0).
    #[inline(always)]
    fn is_held(self) -> bool {
        self.ordered_bits() == Self::held().ordered_bits()
    }
}

impl Level for i16 {
    const UNARMED: i16 = i16::MAX;
    #[inline(always)]
    fn held() -> i16 {
        -1
    }
    #[inline(always)]
    fn startup() -> i16 {
        i16::MAX - 1
    }
    #[inline(always)]
    fn settling() -> i16 {
        i16::MAX - 2
    }
    #[inline(always)]
    fn holds(self) -> bool {
        self < 0
    }
    #[inline(always)]
    fn is_held(self) -> bool {
        self == -1
    }
}

/// A residual `|eps|` in an observer's numbers (a float, or Q15 in an `i32`): how the
/// check compares it per sample with the level it stores, and what it derives from its trip
/// level out of line, so that a configuration stores the trip level alone.
pub(crate) trait Residual: Copy + PartialOrd {
    /// The level as the state stores it.
    type Level: Level;
    /// Whether `self` is above `level`.
    fn exceeds(self, level: Self::Level) -> bool;
    /// `trip` as a level.
    fn level_of(trip: Self) -> Self::Level;
    /// The release level of `trip`: [`TRACKING_RELEASE_FRACTION`] of it.
    fn release(trip: Self) -> Self;
}

/// Compared by their bits as signed integers ([`Float::ordered_bits`]): ordered as the
/// residuals (non-negative), a negative level below them all, NaN above every trip level;
/// an integer comparison, which a Cortex-M0 makes without a call.
impl<T: Float> Residual for T {
    type Level = T;
    #[inline(always)]
    fn exceeds(self, level: T) -> bool {
        self.ordered_bits() > level.ordered_bits()
    }
    fn level_of(trip: T) -> T {
        trip
    }
    fn release(trip: T) -> T {
        trip * T::HALF
    }
}

/// Q15 `|eps|` from 0 to 32767, its level in 16 bits (the fixed-point state has no room for
/// more), read as an `i32`.
impl Residual for i32 {
    type Level = i16;
    #[inline(always)]
    fn exceeds(self, level: i16) -> bool {
        self > i32::from(level)
    }
    fn level_of(trip: i32) -> i16 {
        // A trip level beyond 16 bits is one no residual exceeds.
        i16::try_from(trip).unwrap_or(i16::MAX)
    }
    fn release(trip: i32) -> i32 {
        trip >> 1
    }
}

/// The check's memory in an observer's state: the level in force, which tells the flag
/// (one word: the states of the C API have no room for more).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TrackingCheck<L> {
    /// The level the next residual is compared with: the trip level while the flag is
    /// clear, one below every residual (negative) while it is held.
    pub(crate) level: L,
}

impl<L: Level> TrackingCheck<L> {
    /// A check that is not armed: no residual exceeds its level (the monitor arms it at its
    /// first decision, [`TrackingCheck::arm`]).
    pub(crate) const fn new() -> Self {
        Self { level: L::UNARMED }
    }

    /// [`Faults::LOSS_OF_TRACKING`] while the flag is held, else none (in the start-up:
    /// none, the acquisition being a status and not a fault).
    #[inline(always)]
    pub(crate) fn flag(&self) -> Faults {
        Faults::when(self.level.is_held(), Faults::LOSS_OF_TRACKING)
    }

    /// Whether the check is in its start-up (or not armed yet): nothing to apply.
    fn starting(&self) -> bool {
        self.level == L::startup() || self.level == L::settling() || self.level == L::UNARMED
    }

    /// Whether `residual` must go out of line ([`TrackingCheck::apply`]): above the trip
    /// level with the flag clear, or any residual while it is held.
    #[inline(always)]
    pub(crate) fn changes<R: Residual<Level = L>>(&self, residual: R) -> bool {
        residual.exceeds(self.level)
    }

    /// At a window's end, of mean residual `window_mean`: the level in force of trip level
    /// `trip`, the flag kept (following a changed threshold). The monitor's first decision,
    /// on the first sample, arms a new check in its start-up: nothing tripped, flagged or
    /// latched (the loop's acquisition is a status, not a fault) until
    /// [`TRACKING_STARTUP_WINDOWS`] windows in a row have a mean residual at or below the
    /// release level. One such window is not enough: while the loop's lag still grows, or
    /// between the lobes of a third-order loop's acquisition, a window's mean dips below it
    /// and the next samples, with the noise on them, would trip.
    pub(crate) fn arm<R: Residual<Level = L>>(&mut self, trip: R, window_mean: R) {
        if self.level.holds() {
            // The flag held: it clears on a residual, not at a window's end.
        } else if self.level == L::UNARMED {
            self.level = L::startup();
        } else if self.level == L::startup() || self.level == L::settling() {
            self.level = if window_mean > R::release(trip) {
                L::startup()
            } else if self.level == L::settling() {
                R::level_of(trip)
            } else {
                L::settling()
            };
        } else {
            self.level = R::level_of(trip);
        }
    }

    /// `residual` applied (out of line), of trip level `trip`: with the flag clear, a
    /// residual above `trip` sets it and latches it in `latched`; with the flag held, one at
    /// or below the release level clears it; the level in force follows.
    #[cold]
    #[inline(never)]
    pub(crate) fn apply<R: Residual<Level = L>>(
        &mut self,
        residual: R,
        trip: R,
        latched: &mut Faults,
    ) {
        // Not armed yet (the monitor's first window, whose end arms it) or in the start-up:
        // nothing to apply.
        if self.starting() {
            return;
        }
        if !self.level.holds() {
            if residual > trip {
                self.level = L::held();
                *latched |= Faults::LOSS_OF_TRACKING;
            } else {
                self.level = R::level_of(trip);
            }
        } else if !(residual > R::release(trip)) {
            self.level = R::level_of(trip);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRIP: f32 = 0.05;

    /// The flag of each residual of `residuals`, the check applied as the monitor does.
    fn flags<const K: usize>(residuals: [f32; K]) -> ([bool; K], Faults) {
        let mut check = TrackingCheck::new();
        check.arm(TRIP, 0.0);
        let mut latched = Faults::NONE;
        // Armed in its start-up (no trip, no flag, no latch), whatever the samples, until
        // two windows in a row have a mean residual at or below 0.025.
        check.apply(0.9, TRIP, &mut latched);
        check.arm(TRIP, 0.03);
        assert!(check.flag().is_empty() && check.level == f32::startup());
        check.arm(TRIP, 0.02);
        check.apply(0.9, TRIP, &mut latched);
        assert!(check.flag().is_empty() && check.level == f32::settling());
        check.arm(TRIP, 0.026);
        assert!(check.flag().is_empty() && check.level == f32::startup());
        check.arm(TRIP, 0.025);
        check.arm(TRIP, 0.01);
        assert!(check.flag().is_empty() && latched.is_empty() && check.level == TRIP);
        let flags = residuals.map(|r| {
            if check.changes(r) {
                check.apply(r, TRIP, &mut latched);
            }
            !check.flag().is_empty()
        });
        (flags, latched)
    }

    #[test]
    fn trips_above_the_trip_level_and_holds_down_to_the_release_level() {
        let (flags, latched) = flags([0.049, 0.051, 0.03, 0.026, 0.025, 0.04, 0.05, 0.0501]);
        assert_eq!(
            flags,
            [false, true, true, true, false, false, false, true],
            "trip above 0.05, hold above 0.025"
        );
        assert_eq!(latched, Faults::LOSS_OF_TRACKING);
    }

    #[test]
    fn an_unarmed_check_never_trips() {
        let check = TrackingCheck::<f32>::new();
        assert!(!check.changes(1e30));
        assert!(check.flag().is_empty());
    }
}
