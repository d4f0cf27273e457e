//! Many independent channels sharing one gain set: several axes, or a Monte Carlo batch.
//! [`ChannelBank`] keeps their states side by side so that [`Gains::update_bank`] runs the
//! one recursion (`docs/theory.md §5`) on every lane at once, vectorised.

use crate::faults::Faults;
use crate::gains::Gains;
use crate::reacquisition::Refit;
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::recursion::Sample;
use crate::state::{Estimate, ObserverState};
use crate::wrap::{FullWrap, NoWrap, Wrap, wrapped};

/// The states of `L` independent channels of order `N`, laid out as a struct of arrays
/// (`x[i][lane]`) so that [`Chain::track_bank`](crate::Chain::track_bank) runs the lanes side by side and the
/// compiler can vectorise the loop over them. No allocation: the bank is a plain value
/// (`(N + 3) * L` floats, for the states, the next predicted angles, the magnitudes the
/// phase errors are normalised by and the phase errors, and `L` turn counts and flags), kept
/// wherever the caller likes.
///
/// A bank runs the same recursion as a single observer, with the same rejection of bad
/// samples (a lane coasts on its prediction and is marked in [`ChannelBank::rejected`]);
/// it does not run the fault monitor (use single observers where each channel needs
/// diagnostics). Its lanes are exactly single observers whose monitor is off
/// ([`FaultThresholds::disabled`](crate::FaultThresholds::disabled)): the rare cases (a
/// lane's first sample, the re-acquisition after a front-end fault of a
/// [`Chain`](crate::Chain)'s bank form) run the single observer's code on the lane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelBank<T, const N: usize, const L: usize> {
    x: [[T; L]; N],
    next_angle: [T; L],
    /// Each lane's tracked magnitude `sqrt(y_c^2 + y_s^2)` (`docs/theory.md §12`).
    amplitude: [T; L],
    turns: [i32; L],
    phase_error: [T; L],
    /// 1 for a lane whose last sample was rejected, else 0: lane-wide integers, which a
    /// vectorised loop stores as they are (bytes would have to be packed first).
    rejected: [u32; L],
    /// The lanes that have no angle yet.
    pending: [bool; L],
    /// The samples each lane coasted through front-end faults (a chain's) since its last
    /// used one: the next used sample sets its angle from its `atan2`, or after a long
    /// coast the next samples are fitted first (as a single observer's).
    coasted: [u32; L],
    /// Each lane's fit under way after a long coast.
    refit: [Refit<T>; L],
    /// The faults each lane's chain front end flagged, latched.
    latched: [Faults; L],
    /// Some lane is pending or coasted: the next sample runs the lanes one by one.
    rare: bool,
}

impl<T: Float, const N: usize, const L: usize> Default for ChannelBank<T, N, L> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Float, const N: usize, const L: usize> ChannelBank<T, N, L> {
    /// A bank whose lanes initialise themselves from their first valid sample's `atan2`,
    /// exactly as single observers do.
    ///
    /// ```
    /// use angletrack_core::{Chain, ChainState, ChannelBank, Gains};
    /// let chain = Chain::new((), Gains::<f32, 3>::new([0.06, 0.0019, 3e-5], 1e-4)?);
    /// let mut state = ChainState { front_end: [(); 8], observer: ChannelBank::<f32, 3, 8>::new() };
    /// chain.track_bank(&mut state, &[(0.0, 1.0); 8]);
    /// let bank = &state.observer;
    /// assert!(bank.angles().iter().all(|a| (a - core::f32::consts::FRAC_PI_2).abs() < 1e-6));
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn new() -> Self {
        Self {
            x: [[T::ZERO; L]; N],
            next_angle: [T::ZERO; L],
            amplitude: [T::ZERO; L],
            turns: [0; L],
            phase_error: [T::ZERO; L],
            rejected: [0; L],
            pending: [true; L],
            coasted: [0; L],
            refit: [Refit::new(); L],
            latched: [Faults::NONE; L],
            rare: true,
        }
    }

    /// The estimated angles (rad), each in [-pi, pi).
    pub fn angles(&self) -> [T; L] {
        core::array::from_fn(|lane| self.wrapped(lane).0)
    }

    /// The whole turns counted by each lane (an `i32` that wraps around after 2^31 turns,
    /// to keep the lanes narrow for SIMD; a single observer counts in `i64`).
    pub fn turns(&self) -> [i32; L] {
        core::array::from_fn(|lane| self.wrapped(lane).1 as i32)
    }

    /// A lane's corrected angle as read (wrapped into [-pi, pi)) and its turn count: the
    /// lanes keep the angle as the recursion leaves it (see
    /// [`ObserverState`](crate::ObserverState)).
    fn wrapped(&self, lane: usize) -> (T, i64) {
        wrapped(self.x[0][lane], i64::from(self.turns[lane]))
    }

    /// The phase-detector outputs of the last sample (0 for a rejected sample).
    pub fn phase_errors(&self) -> [T; L] {
        self.phase_error
    }

    /// Which lanes rejected their last sample (NaN, infinite or above the input bound).
    pub fn rejected(&self) -> [bool; L] {
        self.rejected.map(|r| r != 0)
    }

    /// `false` until every lane has had a valid sample.
    pub fn is_initialised(&self) -> bool {
        !self.pending.contains(&true)
    }

    /// The faults each lane's front end flagged since they were last cleared, in a
    /// [`Chain`](crate::Chain)'s bank form (a rejected sample shows in
    /// [`ChannelBank::rejected`], for its sample).
    pub fn latched_faults(&self) -> [Faults; L] {
        self.latched
    }

    /// Returns the latched faults and clears them.
    pub fn clear_faults(&mut self) -> [Faults; L] {
        core::mem::replace(&mut self.latched, [Faults::NONE; L])
    }

    /// Latches `faults` in lane `lane` (nothing for a lane outside the bank).
    pub(crate) fn latch(&mut self, lane: usize, faults: Faults) {
        if let Some(latched) = self.latched.get_mut(lane) {
            *latched |= faults;
        }
    }

    /// Lane `lane` as the state of a single observer whose monitor is off: the same
    /// results, sample by sample, to the bit (the lane's predicted angle is live: for a lane
    /// that is not tracking, it is the prediction the single state computes on demand).
    #[inline(always)]
    pub(crate) fn lane_state(&self, lane: usize) -> ObserverState<T, N> {
        let mut state = ObserverState::new();
        if self.pending[lane] {
            return state;
        }
        for (i, xi) in state.x.iter_mut().enumerate() {
            *xi = self.x[i][lane];
        }
        state.turns = i64::from(self.turns[lane]);
        state.phase_error = self.phase_error[lane];
        state.amplitude = self.amplitude[lane];
        state.initialised = true;
        state.coasted = self.coasted[lane];
        state.refit = self.refit[lane];
        state.tracking = state.coasted == 0;
        if state.tracking {
            state.next_angle = self.next_angle[lane];
        }
        state.faults = self.lane_faults(lane);
        state
    }

    /// Lane `lane`'s sample faults as the single observer's (its monitor off): a rejected
    /// sample, or one of the fit after a long coast.
    #[inline(always)]
    fn lane_faults(&self, lane: usize) -> Faults {
        if self.rejected[lane] != 0 {
            Faults::BAD_SAMPLE
        } else if self.refit[lane].taken > 0 {
            Faults::LOSS_OF_TRACKING
        } else {
            Faults::NONE
        }
    }

    /// Lane `lane` set from the single observer's `state` (see [`ChannelBank::lane_state`]);
    /// the bank's turn count is the low 32 bits of the state's.
    #[inline(always)]
    pub(crate) fn set_lane(&mut self, lane: usize, state: &ObserverState<T, N>) {
        for (i, xi) in state.x.iter().enumerate() {
            self.x[i][lane] = *xi;
        }
        self.next_angle[lane] = state.predicted_angle();
        self.amplitude[lane] = state.amplitude;
        self.turns[lane] = state.turns as i32;
        self.phase_error[lane] = state.phase_error;
        self.rejected[lane] = u32::from(state.faults.contains(Faults::BAD_SAMPLE));
        self.pending[lane] = !state.initialised;
        self.coasted[lane] = state.coasted;
        self.refit[lane] = state.refit;
    }

    /// Lane `lane`'s predicted angle for its next sample (rad, not wrapped), as the single
    /// observer's.
    #[inline(always)]
    pub(crate) fn predicted_angle(&self, lane: usize) -> T {
        self.next_angle[lane]
    }

    /// Marks the bank for the lane-by-lane path if a lane is pending or coasted.
    pub(crate) fn update_rare(&mut self) {
        self.rare = self.pending.contains(&true) || self.coasted.iter().any(|&c| c > 0);
    }
}

impl<T: Float, const N: usize, S: SinCos<T>> Gains<T, N, S> {
    /// One sample for each of the `L` lanes of a bank. A lane's first valid sample
    /// initialises it from `atan2(y_s, y_c)`; until every lane is initialised the lanes run
    /// one by one, then side by side.
    ///
    #[inline]
    pub(crate) fn update_bank<const L: usize>(
        &self,
        bank: &mut ChannelBank<T, N, L>,
        y_c: &[T; L],
        y_s: &[T; L],
    ) {
        if bank.rare {
            self.update_lanes_as_single_observers(bank, y_c, y_s);
            return;
        }
        // Side by side: the same operations on every lane and no branch in the loop, so the
        // compiler vectorises it, on predicted angles every one of which is in [-pi, pi):
        // in the usual sample they are already (a lane crosses the edge once a turn); where
        // one is not, it is wrapped first, out of line, by the single observer's wrap and
        // its turns counted, which is what the single observer's step does first.
        if !Self::lanes_inside(bank) {
            Self::wrap_lanes(bank);
        }
        for lane in 0..L {
            self.update_lane::<NoWrap, L>(bank, lane, y_c[lane], y_s[lane]);
        }
    }

    /// Whether every lane's predicted angle is in [-pi, pi) (false for NaN).
    #[inline(always)]
    fn lanes_inside<const L: usize>(bank: &ChannelBank<T, N, L>) -> bool {
        let mut inside = true;
        for &angle in &bank.next_angle {
            inside &= angle >= -T::PI && angle < T::PI;
        }
        inside
    }

    /// Wraps the predicted angles outside [-pi, pi) as the single observer's step does
    /// ([`FullWrap`]), their turns counted.
    #[cold]
    #[inline(never)]
    fn wrap_lanes<const L: usize>(bank: &mut ChannelBank<T, N, L>) {
        for lane in 0..L {
            let angle = &mut bank.next_angle[lane];
            if !(*angle >= -T::PI && *angle < T::PI) {
                let whole = FullWrap::wrap(angle);
                bank.turns[lane] = bank.turns[lane].wrapping_add(whole);
            }
        }
    }

    /// One lane of a bank: the recursion with the wrap `W`.
    #[inline(always)]
    fn update_lane<W: Wrap, const L: usize>(
        &self,
        bank: &mut ChannelBank<T, N, L>,
        lane: usize,
        c: T,
        s: T,
    ) {
        let mut x = [T::ZERO; N];
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = bank.x[i][lane];
        }
        let mut next_angle = bank.next_angle[lane];
        let mut amplitude = bank.amplitude[lane];
        let (amplitude2, valid) = self.thresholds.accept(c, s);
        let sample = Sample {
            y_c: c,
            y_s: s,
            amplitude2,
            valid,
        };
        let step = self.step::<W, S>(
            &mut S::default(),
            &mut x,
            &mut next_angle,
            &mut amplitude,
            sample,
        );
        bank.amplitude[lane] = amplitude;
        bank.turns[lane] = bank.turns[lane].wrapping_add(step.whole);
        for (i, xi) in x.iter().enumerate() {
            bank.x[i][lane] = *xi;
        }
        bank.next_angle[lane] = next_angle;
        bank.phase_error[lane] = step.eps;
        bank.rejected[lane] = u32::from(!valid);
    }

    /// The estimate of one lane of a bank, in physical units; `None` for a lane index
    /// outside the bank.
    pub fn bank_estimate<const L: usize>(
        &self,
        bank: &ChannelBank<T, N, L>,
        lane: usize,
    ) -> Option<Estimate<T>> {
        if lane >= L {
            return None;
        }
        Some(self.lane_estimate(bank, lane))
    }

    /// The estimate of lane `lane` (< `L`) of a bank.
    #[inline(always)]
    pub(crate) fn lane_estimate<const L: usize>(
        &self,
        bank: &ChannelBank<T, N, L>,
        lane: usize,
    ) -> Estimate<T> {
        let mut x = [T::ZERO; N];
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = bank.x[i][lane];
        }
        self.estimate_of(
            &x,
            bank.turns[lane] as i64,
            bank.phase_error[lane],
            bank.lane_faults(lane),
        )
    }

    /// The gains of a bank's lane as a single observer: these, the monitor off.
    pub(crate) fn unmonitored(&self) -> Self {
        let mut gains = *self;
        gains.thresholds.thresholds.monitor = false;
        gains
    }

    /// The update while some lane waits for its first valid sample or coasted through a
    /// front-end fault: each lane as a single observer whose monitor is off.
    #[cold]
    #[inline(never)]
    fn update_lanes_as_single_observers<const L: usize>(
        &self,
        bank: &mut ChannelBank<T, N, L>,
        y_c: &[T; L],
        y_s: &[T; L],
    ) {
        let gains = self.unmonitored();
        for lane in 0..L {
            let mut state = bank.lane_state(lane);
            gains.track(&mut state, y_c[lane], y_s[lane]);
            bank.set_lane(lane, &state);
        }
        bank.update_rare();
    }
}

#[cfg(test)]
mod tests;
