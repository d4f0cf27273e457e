//! The observer through a front-end fault (`docs/theory.md §15`): the coast on the
//! prediction, and after it the re-acquisition: the fit of the next samples after a long
//! coast (`crate::reacquisition`), and the check of a re-acquisition's jump.

use crate::faults::Faults;
use crate::gains::Gains;
use crate::reacquisition::{IMPLAUSIBLE_JUMP_MAX_COAST, Refit};
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::state::ObserverState;
use crate::wrap::{re_acquired, wrap_angle};

impl<T: Float, const N: usize, S: SinCos<T>> Gains<T, N, S> {
    /// A sample that is not a measurement (a chain's front end says so:
    /// [`Stage::coasts`](crate::Stage::coasts)): the angle advances by the speed, and the
    /// speed and the acceleration are held (not integrated: an acceleration estimate's noise
    /// would grow quadratically over a fault of many samples, and a shaft through a short
    /// fault turns at the speed it had); the next used sample sets the angle from its
    /// `atan2` (by the shortest way, turns counted), so that neither a drift of the coast
    /// nor a false lock outlasts the fault. A state that has no angle yet is left as it
    /// is. The front end's flag is the chain's to add.
    #[cold]
    #[inline(never)]
    pub(crate) fn coast_front_end(&self, state: &mut ObserverState<T, N>) {
        if !state.initialised {
            return;
        }
        if N > 1 {
            state.x[0] += state.x[1];
        }
        let whole = wrap_angle(&mut state.x[0]);
        state.advance(whole, T::ZERO);
        state.park(Faults::NONE);
        state.coasted = state.coasted.saturating_add(1);
        // A fit under way is cut short by the fault: it starts again after it.
        state.refit = Refit::new();
    }

    /// One sample of the fit after a long coast (`crate::reacquisition`): its angle is the
    /// estimate's (`atan2`, turns counted), flagged [`Faults::LOSS_OF_TRACKING`] and not
    /// used by the loop; at the fit's last sample the state takes the fitted angle, speed
    /// and acceleration and tracks from the next sample on. Returns `false`: the recursion
    /// does not run on the sample.
    #[cold]
    #[inline(never)]
    pub(super) fn refit(
        &self,
        state: &mut ObserverState<T, N>,
        y_c: T,
        y_s: T,
        amplitude2: T,
    ) -> bool {
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
        false
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
