//! The driver's control flow around the one recursion (`recursion.rs`), written once for
//! every observer: which rare case a sample is (the first sample, a rejected sample, the
//! first sample after a coast through a front-end fault: a fit after a long coast, else a
//! re-acquisition, `docs/theory.md §15`) and the coast itself. [`Driver`] is what each
//! arithmetic supplies for each case: the floats' [`Gains`](crate::Gains) (single
//! channels, and a [`ChannelBank`](crate::ChannelBank)'s lanes, which run the single
//! channel's rare path) and the fixed-point [`FixedGains`](crate::FixedGains).
//!
//! Where the rare path runs is the arithmetic's: the floats test every sample before the
//! recursion (their samples may be invalid, and a rejected or re-acquired sample changes
//! what the recursion runs on); the fixed-point observer runs the recursion on every sample
//! and its rare cases at the end of a window of one sample (its usual path then has no test
//! of its own).

use crate::reacquisition::REFIT_AFTER_COAST;

/// What an observer's arithmetic does in each rare case of [`Driver::rare_sample`] and in
/// [`Driver::coast`]; their order is the driver's.
pub(crate) trait Driver {
    /// The state of one channel.
    type State;
    /// A sample as the rare path sees it.
    type Sample: Copy;

    /// Whether the state has an angle (from a first sample, or set by the caller).
    fn initialised(state: &Self::State) -> bool;

    /// The samples coasted through front-end faults since the last used one.
    fn coasted(state: &Self::State) -> u32;

    /// Whether `sample` can be used (finite, within the input bound).
    fn valid(sample: &Self::Sample) -> bool;

    /// The first sample of a state that has no angle: the angle set from its `atan2`, or
    /// nothing but its flag for a sample that is not valid.
    fn first_sample(&self, state: &mut Self::State, sample: Self::Sample);

    /// A sample that is not valid: the state coasts on its prediction, the sample flagged.
    fn reject(&self, state: &mut Self::State);

    /// One sample of the fit after a long coast (`crate::reacquisition`), not tracked.
    fn refit(&self, state: &mut Self::State, sample: Self::Sample);

    /// The first sample after a short coast: the angle re-acquired from its `atan2`, the
    /// speed and the acceleration kept. Returns whether the rest of the usual path runs on
    /// the sample.
    fn re_acquire_after_coast(&self, state: &mut Self::State, sample: Self::Sample) -> bool;

    /// The coast of one sample that is not a measurement: the angle advanced by the held
    /// speed, the next sample marked for the rare path.
    fn coast_prediction(&self, state: &mut Self::State);

    /// Counts one more sample coasted (saturated); a fit under way starts again.
    fn count_coast(state: &mut Self::State);

    /// The rare cases of a sample, in the driver's order: a state without an angle takes
    /// its first sample, an invalid sample is rejected, and the first valid sample after a
    /// coast is fitted (long coast) or re-acquires the angle (short coast). Returns whether
    /// the rest of the usual path runs on the sample (no rare case, or a re-acquisition that
    /// says so).
    #[inline(always)]
    fn rare_sample(&self, state: &mut Self::State, sample: Self::Sample) -> bool {
        if !Self::initialised(state) {
            self.first_sample(state, sample);
            return false;
        }
        if !Self::valid(&sample) {
            self.reject(state);
            return false;
        }
        let coasted = Self::coasted(state);
        if coasted >= REFIT_AFTER_COAST {
            // After a long coast the speed and the acceleration are stale: the next samples
            // are fitted, not tracked, and the loop starts from the fit.
            self.refit(state, sample);
            return false;
        }
        if coasted > 0 {
            return self.re_acquire_after_coast(state, sample);
        }
        true
    }

    /// A sample that is not a measurement (a chain's front end says so:
    /// [`Stage::coasts`](crate::Stage::coasts)): the state coasts on its prediction and the
    /// next valid sample re-acquires or starts a fit. A state that has no angle yet is left
    /// as it is.
    #[inline(always)]
    fn coast(&self, state: &mut Self::State) {
        if !Self::initialised(state) {
            return;
        }
        self.coast_prediction(state);
        Self::count_coast(state);
    }
}
