//! The floats' rare cases as the driver's ([`Driver`], `update/driver.rs`, `docs/theory.md
//! §15`): the first sample, a rejected sample, the coast through a front-end fault, and after
//! it the re-acquisition: the fit of the next samples after a long coast
//! (`crate::reacquisition`), else the angle re-acquired and its jump checked.

use super::driver::Driver;
use crate::faults::Faults;
use crate::gains::Gains;
use crate::reacquisition::{IMPLAUSIBLE_JUMP_MAX_COAST, Refit};
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::recursion::Sample;
use crate::state::{ObserverState, predict};
use crate::wrap::{re_acquired, sample_angle, wrap_angle};

impl<T: Float, const N: usize, S: SinCos<T>> Driver for Gains<T, N, S> {
    type State = ObserverState<T, N>;
    type Sample = Sample<T>;

    #[inline(always)]
    fn initialised(state: &ObserverState<T, N>) -> bool {
        state.initialised
    }

    #[inline(always)]
    fn coasted(state: &ObserverState<T, N>) -> u32 {
        state.coasted
    }

    #[inline(always)]
    fn valid(sample: &Sample<T>) -> bool {
        sample.valid
    }

    /// The angle from `atan2(y_s, y_c)` ([`ObserverState::restart`]), the magnitude the
    /// sample's; a sample that is not valid is flagged and sets nothing.
    #[inline(always)]
    fn first_sample(&self, state: &mut ObserverState<T, N>, sample: Sample<T>) {
        match if sample.valid {
            sample_angle(sample.y_c, sample.y_s)
        } else {
            None
        } {
            Some((angle, whole)) => {
                let latched = state.monitor.latched;
                state.restart(angle, whole, sample.amplitude2, latched);
            }
            None => state.reject_sample(),
        }
    }

    /// The state coasts on the recursion's prediction (speed and acceleration), flagged
    /// [`Faults::BAD_SAMPLE`].
    #[inline(always)]
    fn reject(&self, state: &mut ObserverState<T, N>) {
        // The predicted angle, parked by `reject_sample`, is that of the coasted state,
        // `predict(x)[0]` (`coasted_state` computes it so, to the bit).
        let (x, _, whole) = self.coasted_state(state.x, state.predicted_angle());
        state.x = x;
        state.advance(whole, T::ZERO);
        state.reject_sample();
        // A fit under way lost a sample: it starts again.
        state.refit = Refit::new();
    }

    /// One sample of the fit after a long coast (`crate::reacquisition`): its angle is the
    /// estimate's (`atan2`, turns counted), flagged [`Faults::LOSS_OF_TRACKING`] and not
    /// used by the loop; at the fit's last sample the state takes the fitted angle, speed
    /// and acceleration and tracks from the next sample on.
    #[cold]
    #[inline(never)]
    fn refit(&self, state: &mut ObserverState<T, N>, sample: Sample<T>) {
        let Sample {
            y_c,
            y_s,
            amplitude2,
            ..
        } = sample;
        let before = state.x[0];
        let (angle, whole) = re_acquired(before, y_c, y_s);
        state.x[0] = angle;
        state.turns = state.turns.wrapping_add(whole as i64);
        let mut step = angle - before;
        wrap_angle(&mut step);
        if state.refit.taken == 0 {
            // The first sample after the coast: its jump from the coast's prediction.
            let mut jump = step - if N > 1 { state.x[1] } else { T::ZERO };
            wrap_angle(&mut jump);
            check_jump(state, jump, self.thresholds.thresholds.monitor);
        }
        match state.refit.take(step) {
            None => {
                state.park(Faults::LOSS_OF_TRACKING);
                state.advance(0, T::ZERO);
            }
            Some(fitted) => {
                state.x[0] += fitted.angle_change;
                let whole = wrap_angle(&mut state.x[0]);
                state.turns = state.turns.wrapping_add(whole as i64);
                if N > 1 {
                    state.x[1] = fitted.speed;
                }
                if N > 2 {
                    state.x[2] = fitted.acceleration;
                }
                state.coasted = 0;
                state.start_tracking(amplitude2);
            }
        }
    }

    /// The angle re-acquired from the sample (however far the coast drifted: no false
    /// lock, and no transient of the loop correcting the drift), speed and acceleration
    /// kept; a jump no coast could drift is flagged ([`check_jump`]). The loop then runs on
    /// the sample.
    #[inline(always)]
    fn re_acquire_after_coast(&self, state: &mut ObserverState<T, N>, sample: Sample<T>) -> bool {
        // The state holds the previous sample's estimate: it moves by the jump from this
        // sample's prediction to its atan2.
        let mut jump = sample.y_s.atan2(sample.y_c) - predict(&state.x)[0];
        wrap_angle(&mut jump);
        check_jump(state, jump, self.thresholds.thresholds.monitor);
        state.x[0] += jump;
        let whole = wrap_angle(&mut state.x[0]);
        state.turns = state.turns.wrapping_add(whole as i64);
        state.coasted = 0;
        true
    }

    /// The angle advances by the speed, and the speed and the acceleration are held (not
    /// integrated: an acceleration estimate's noise would grow quadratically over a fault
    /// of many samples, and a shaft through a short fault turns at the speed it had); the
    /// predicted angle is parked, so the next sample takes the rare path. The front end's
    /// flag is the chain's to add.
    #[inline(always)]
    fn coast_prediction(&self, state: &mut ObserverState<T, N>) {
        if N > 1 {
            state.x[0] += state.x[1];
        }
        let whole = wrap_angle(&mut state.x[0]);
        state.advance(whole, T::ZERO);
        state.park(Faults::NONE);
    }

    #[inline(always)]
    fn count_coast(state: &mut ObserverState<T, N>) {
        state.coasted = state.coasted.saturating_add(1);
        state.refit = Refit::new();
    }
}

impl<T: Float, const N: usize, S: SinCos<T>> Gains<T, N, S> {
    /// A sample that is not a measurement ([`Driver::coast`]), out of line: rare.
    #[cold]
    #[inline(never)]
    pub(crate) fn coast_front_end(&self, state: &mut ObserverState<T, N>) {
        Driver::coast(self, state);
    }
}

/// The re-acquisition after a coast through a front-end fault of at most
/// [`IMPLAUSIBLE_JUMP_MAX_COAST`] samples, whose first sample's angle is `jump` (rad,
/// wrapped) from the coast's prediction: a quarter turn or more is implausible (the coast
/// held the speed, and a shaft whose acceleration changed by less than 7.7e-4 rad per
/// sample^2, 3e5 rad/s^2 at 20 kHz, drifts less in 64 samples). Such a jump says the angle
/// before the fault was wrong, and the pair after it may be as wrong: the loop had followed
/// a faulty pair (a dead or open channel from the start stands the estimate at +-pi/2), and
/// the winding check took the healthy winding's zero crossing for an open winding. The
/// re-acquired angle does not cure that: the monitor, if `monitored`, flags it
/// ([`MonitorState::flag_implausible_jump`]).
#[inline(always)]
pub(super) fn check_jump<T: Float, const N: usize>(
    state: &mut ObserverState<T, N>,
    jump: T,
    monitored: bool,
) {
    if monitored && state.coasted <= IMPLAUSIBLE_JUMP_MAX_COAST && !(jump.abs() < T::FRAC_PI_2) {
        state.monitor.flag_implausible_jump();
    }
}
