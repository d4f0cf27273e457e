//! The fixed-point observer's rare cases as the driver's ([`Driver`], `update/driver.rs`,
//! `docs/theory.md §14, §15`): the first sample, the coast through a front-end fault and the
//! re-acquisition after it (the fit of the next samples after a long coast), and the end of
//! a window that is not healthy (a false lock re-acquires). Each runs at the end of a window
//! (of one sample, after the first sample and a coast), after the recursion, so that the
//! usual path has no test of its own.

use super::gains::FixedGains;
use super::state::{FixedState, FixedVector};
use super::update::{
    MONITOR_WINDOW, count_turn, speed_change, track_reciprocal, turns_of_estimate,
};
use crate::faults::Faults;
use crate::monitor::MonitorLimits;
use crate::reacquisition::FixedRefit;
use crate::update::driver::Driver;
use crate::wrap::{crossed_turns, re_acquired, sample_angle};

/// The sample is the state's (`FixedState::sample`, stored by the usual path), and every
/// integer sample is valid.
impl<const N: usize> Driver for FixedGains<N> {
    type State = FixedState<N>;
    type Sample = ();

    #[inline(always)]
    fn initialised(state: &FixedState<N>) -> bool {
        state.initialised
    }

    #[inline(always)]
    fn coasted(state: &FixedState<N>) -> u32 {
        u32::from(state.coasted)
    }

    #[inline(always)]
    fn valid(_sample: &()) -> bool {
        true
    }

    /// The first sample: the angle from `atan2` ([`sample_angle`], the floats' own), speed
    /// and acceleration 0, the reciprocal converged on the sample's amplitude, the first
    /// full window started.
    #[cold]
    #[inline(never)]
    fn first_sample(&self, state: &mut FixedState<N>, _sample: ()) {
        let [y_c, y_s] = state.sample;
        // Every integer sample has an angle (that of (0, 0) is 0), within one turn.
        let angle = sample_angle(y_c, y_s).map_or(0, |(angle, _)| angle);
        let amplitude2 = Self::amplitude2_half(state);
        let latched = state.latched;
        *state = FixedState::new();
        state.latched = latched;
        state.x.angle = angle;
        state.next_angle = angle;
        // Until a fixed point (or 24 steps): the same result as 24 steps, and a loop that is
        // not unrolled into a kilobyte of code.
        for _ in 0..24 {
            let next = track_reciprocal(state.reciprocal, amplitude2);
            if next == state.reciprocal {
                break;
            }
            state.reciprocal = next;
        }
        state.window_left = MONITOR_WINDOW;
        if self.monitor.enabled {
            state.tracking.arm(self.monitor.tracking_error, 0);
        }
        state.initialised = true;
    }

    /// Never called: every integer sample is valid.
    #[inline(always)]
    fn reject(&self, _state: &mut FixedState<N>) {}

    /// One sample of the fit after a long coast (`crate::reacquisition`), at its window's
    /// end: the angle is the sample's `atan2` (turns counted), flagged
    /// [`Faults::LOSS_OF_TRACKING`]; at the fit's last sample the state takes the fitted
    /// angle, speed and acceleration, and the loop tracks from the next sample on.
    fn refit(&self, state: &mut FixedState<N>, _sample: ()) {
        Self::re_acquire(state);
        match state.refit.take_angle(state.x.angle) {
            None => {
                state.faults = Faults::LOSS_OF_TRACKING;
                state.latched |= Faults::LOSS_OF_TRACKING;
            }
            Some(fitted) => {
                let turns = turns_of_estimate(state)
                    .wrapping_add(i64::from(crossed_turns::<i16>(state.x.angle, fitted.angle)));
                state.x.angle = fitted.angle;
                state.x.acceleration = if N > 2 { fitted.acceleration } else { 0 };
                state.x.speed = if N > 2 {
                    fitted.speed.wrapping_add(speed_change(fitted.acceleration))
                } else {
                    fitted.speed
                };
                state.next_angle = Self::next_angle(&state.x);
                state.turns = turns.wrapping_add(i64::from(crossed_turns::<i16>(
                    state.x.angle,
                    state.next_angle,
                )));
                state.faults = Faults::NONE;
                state.coasted = 0;
            }
        }
    }

    /// The angle re-acquired from the sample at its window's end, after the recursion ran
    /// on it: nothing more of the window's end runs.
    #[inline(always)]
    fn re_acquire_after_coast(&self, state: &mut FixedState<N>, _sample: ()) -> bool {
        state.coasted = 0;
        Self::re_acquire(state);
        false
    }

    /// The angle takes its prediction and then advances by the speed, the speed and the
    /// acceleration held (as the float observers coast); the next sample ends a window of
    /// its own, whose end sets the angle from that sample's `atan2` (so that neither a drift
    /// of the coast nor a false lock outlasts the fault). The front end's flag is the
    /// chain's to add.
    #[inline(always)]
    fn coast_prediction(&self, state: &mut FixedState<N>) {
        let from = state.next_angle;
        state.x.angle = from;
        if N > 1 {
            state.next_angle = from.wrapping_add(state.x.speed);
        }
        if from
            .checked_add(state.next_angle.wrapping_sub(from))
            .is_none()
        {
            count_turn(state, from);
        }
        state.phase_error = 0;
        // The next sample ends a window that is not taken for healthy: its end re-acquires.
        state.error_sum = 1 << 31;
        state.window_left = 1;
    }

    #[inline(always)]
    fn count_coast(state: &mut FixedState<N>) {
        state.coasted = state.coasted.saturating_add(1);
        state.refit = FixedRefit::new();
    }
}

impl<const N: usize> FixedGains<N> {
    /// A sample that is not a measurement ([`Driver::coast`]), out of line: rare.
    #[cold]
    #[inline(never)]
    pub(crate) fn coast_front_end(&self, state: &mut FixedState<N>) {
        Driver::coast(self, state);
    }

    /// The window's end that [`FixedGains::end_window`] did not find healthy, of half a
    /// square amplitude `amplitude2`: the first sample's, or one with a fault, whose flags
    /// are held and latched, and after a false lock the angle re-acquired from the last
    /// sample, keeping the speed (out of line: rare).
    #[cold]
    #[inline(never)]
    pub(super) fn end_window_with_fault(&self, state: &mut FixedState<N>, amplitude2: u32) {
        // The first sample, and the first after a coast (the driver's rare cases), end
        // windows of their own.
        if !self.rare_sample(state, ()) || !self.monitor.enabled {
            return;
        }
        let measures = Self::measures(state, amplitude2);
        if self.monitor.decide_window(
            &measures,
            &mut state.faults,
            &mut state.latched,
            &mut state.round_hold,
        ) {
            Self::re_acquire(state);
        }
    }

    /// The angle set from the last sample's `atan2` by the shortest way (the floats'
    /// [`re_acquired`]), the speed and the acceleration kept (after a false lock or a
    /// coast).
    fn re_acquire(state: &mut FixedState<N>) {
        let [y_c, y_s] = state.sample;
        let (angle, whole) = re_acquired::<i16>(state.x.angle, y_c, y_s);
        let turns = turns_of_estimate(state).wrapping_add(i64::from(whole));
        let speed = Self::corrected_speed(&state.x);
        let next_angle = Self::next_angle(&FixedVector {
            angle,
            speed,
            ..state.x
        });
        state.x.angle = angle;
        state.next_angle = next_angle;
        // The state counts the turns of the predicted angle.
        state.turns = turns.wrapping_add(i64::from(crossed_turns::<i16>(angle, next_angle)));
    }
}
