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
//! Its cost per sample is one comparison with the level in force and one with the flag's
//! state; the levels are switched out of line, when the flag changes.

use crate::faults::Faults;

/// The release level as a fraction of the trip level: the flag set by a residual above the
/// trip level clears at the first residual at or below half of it.
pub const TRACKING_RELEASE_FRACTION: f32 = 0.5;

/// The levels of the check, in the numbers of the residual (`|eps|`; Q15 in the fixed-point
/// observer).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TrackingLevels<R> {
    /// A residual above this sets the flag.
    pub(crate) trip: R,
    /// While the flag is set, a residual at or below this clears it.
    pub(crate) release: R,
}

/// The check's memory in an observer's state: the level in force (the trip level while the
/// flag is clear, the release level while it is set) and the flag.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TrackingCheck<R> {
    /// The level the next residual is compared with.
    pub(crate) level: R,
    /// [`Faults::LOSS_OF_TRACKING`] while the flag is held, else none.
    pub(crate) flag: Faults,
}

impl<R: Copy + PartialOrd> TrackingCheck<R> {
    /// A check that is not armed: `never` is a level no residual exceeds (the monitor
    /// arms it at its first decision, [`TrackingCheck::arm`]).
    pub(crate) const fn new(never: R) -> Self {
        Self {
            level: never,
            flag: Faults::NONE,
        }
    }

    /// Whether `residual` changes the flag: above the level with the flag clear, or at or
    /// below it with the flag set (NaN compares false: it sets nothing and clears a flag;
    /// the input check rejects such a sample before it gets here).
    #[inline(always)]
    pub(crate) fn changes(&self, residual: R) -> bool {
        (residual > self.level) != !self.flag.is_empty()
    }

    /// The level in force set from `levels` for the flag's state.
    pub(crate) fn arm(&mut self, levels: TrackingLevels<R>) {
        self.level = if self.flag.is_empty() {
            levels.trip
        } else {
            levels.release
        };
    }

    /// `residual` (one that [`TrackingCheck::changes`] the flag, or any) applied: the flag
    /// set or cleared, the level switched, and the flag latched in `latched` when set.
    #[cold]
    #[inline(never)]
    pub(crate) fn apply(&mut self, residual: R, levels: TrackingLevels<R>, latched: &mut Faults) {
        if self.changes(residual) {
            self.flag = if self.flag.is_empty() {
                Faults::LOSS_OF_TRACKING
            } else {
                Faults::NONE
            };
            *latched |= self.flag;
        }
        self.arm(levels);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LEVELS: TrackingLevels<f32> = TrackingLevels {
        trip: 0.05,
        release: 0.025,
    };

    /// The flag of each residual of `residuals`, the check applied as the monitor does.
    fn flags<const K: usize>(residuals: [f32; K]) -> ([bool; K], Faults) {
        let mut check = TrackingCheck::new(f32::INFINITY);
        check.arm(LEVELS);
        let mut latched = Faults::NONE;
        let flags = residuals.map(|r| {
            if check.changes(r) {
                check.apply(r, LEVELS, &mut latched);
            }
            !check.flag.is_empty()
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
        let check = TrackingCheck::new(f32::INFINITY);
        assert!(!check.changes(1e30));
    }
}
