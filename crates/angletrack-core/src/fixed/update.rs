//! The fixed-point update (`docs/theory.md §14`): the integer [`Arithmetic`] of the one
//! recursion ([`step`]) and the window that updates the amplitude's reciprocal and decides
//! the monitor's flags; the rare cases (first sample, coast, re-acquisition, a window with a
//! fault) are the driver's, in `rare_cases.rs`.

use super::binary_angle::detect;
use super::gains::{FixedGains, FixedThresholds};
use super::multiply::{add_round_q16, add_wide, mul_q16};
use super::state::{FixedEstimate, FixedState, FixedVector};
use crate::faults::Faults;
use crate::monitor::{Measures, MonitorLimits, MonitorWindow, TrackingCheck, WindowMeasures};
use crate::real::sincos::Detection;
use crate::recursion::Sample;
use crate::recursion::{Arithmetic, step};
use crate::wrap::{NoWrap, Wrap, crossed_turns, crosses_turn};

/// What the fixed-point monitor decides a window from ([`WindowMeasures`] in its integers).
type FixedMeasures = Measures<FixedThresholds>;

/// The smallest value of the reciprocal `2^27 / amplitude`: amplitudes up to 65536 counts,
/// above any `i16` signal's `32768 sqrt(2)`.
pub const MIN_RECIPROCAL: i32 = 2048;

/// The largest value of the reciprocal, `2^15 - 1`: amplitudes down to 4096 counts
/// ([`MIN_NORMALISED_AMPLITUDE_COUNTS`](crate::fixed::MIN_NORMALISED_AMPLITUDE_COUNTS)).
pub const MAX_RECIPROCAL: i32 = (1 << 15) - 1;

/// Samples per window: the amplitude's reciprocal is updated and the monitor's flags are
/// decided at each window's end (out of line, so that the per-sample path stays short): a
/// loss of signal or degradation is flagged at the end of the window it starts in, at most
/// `W` samples after, a loss of tracking present over a whole window at most `2 W - 1`
/// samples after it starts (`docs/theory.md §14`).
pub const MONITOR_WINDOW: u32 = 32;

/// The phase detector of the fixed-point path: the binary angle's sine table
/// ([`detect`]). Zero-sized.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SineTable;

/// One Newton step of the reciprocal square root: `r (3 - r^2 m) / 2` with
/// `m = amplitude2_half 2^-53`, so that `r` tends to `2^27 / sqrt(y_c^2 + y_s^2)`
/// (`docs/theory.md §14`). The factor is kept in [1/2, 3/2], so a far-off `r` (a step of the
/// amplitude) moves by at most half or half again per step and converges; the result is
/// kept at most [`MAX_RECIPROCAL`] and stays at least [`MIN_RECIPROCAL`] (from any `r` in
/// range) without a clamp: the result is non-decreasing in the factor, the factor
/// non-increasing in the amplitude, and at the largest (`amplitude2_half = 2^30`) every `r`
/// in range steps to at least `MIN_RECIPROCAL` (test
/// `reciprocal_stays_in_range_without_a_lower_clamp`). Every product is below 2^31:
/// `r^2 < 2^30`, `(r^2 >> 15)(m2 / 2^16) <= 2^15 2^15`, `r f <= 32767 49152`.
#[inline(always)]
pub(crate) fn track_reciprocal(reciprocal: i32, amplitude2_half: i32) -> i32 {
    let r2 = (reciprocal * reciprocal) >> 15;
    let x = r2 * (amplitude2_half >> 15);
    // (3 - x 2^-23) / 2 in Q15.
    let factor = ((3 << 23) - x) >> 9;
    let factor = factor.max(1 << 14);
    ((reciprocal * factor) >> 15).min(MAX_RECIPROCAL)
}

/// The speed change of one sample, `acceleration 2^-63` turn in 2^-32 turn per sample
/// (floored), modulo one turn per sample.
#[inline(always)]
pub(super) fn speed_change(acceleration: i64) -> i32 {
    (acceleration >> 31) as i32
}

impl<const N: usize> FixedGains<N> {
    /// The corrected speed of the last sample: the state keeps the next sample's predicted
    /// speed, this less the acceleration's change.
    #[inline(always)]
    pub(crate) fn corrected_speed(x: &FixedVector) -> i32 {
        match N {
            1 => 0,
            2 => x.speed,
            _ => x.speed.wrapping_sub(speed_change(x.acceleration)),
        }
    }

    /// The predicted angle of the next sample, `angle + speed + acceleration / 2` in 2^-32
    /// turn (`acceleration 2^-64` turn is the top word of the acceleration).
    #[inline(always)]
    pub(super) fn next_angle(x: &FixedVector) -> i32 {
        let angle = if N > 1 {
            x.angle.wrapping_add(x.speed)
        } else {
            x.angle
        };
        if N > 2 {
            angle.wrapping_add((x.acceleration >> 32) as i32)
        } else {
            angle
        }
    }
}

impl<const N: usize> Arithmetic<SineTable, N> for FixedGains<N> {
    type Value = i32;
    type Magnitude = i32;
    type Vector = FixedVector;

    /// The angle and the speed are the predictions the previous sample left (the state
    /// keeps the predicted speed, as it keeps the predicted angle: the acceleration that
    /// changes it is then not needed after its own correction); every component wraps
    /// (modulo one turn, one turn per sample, two turns per sample^2: the recursion maps
    /// that lattice onto itself, `docs/theory.md §14`).
    #[inline(always)]
    fn predict(&self, x: &FixedVector, angle: i32) -> FixedVector {
        FixedVector { angle, ..*x }
    }

    /// The binary angle wraps by itself: no turn is removed here (they are counted in
    /// [`Arithmetic::correct`]).
    #[inline(always)]
    fn wrap<W: Wrap>(_angle: &mut i32) -> i32 {
        0
    }

    #[inline(always)]
    fn detect(_unit: &mut SineTable, angle: i32, y_c: i32, y_s: i32) -> Detection<i32> {
        let (phase_error, in_phase, sin, cos) = detect(angle, y_c, y_s);
        Detection {
            phase_error,
            in_phase,
            sin,
            cos,
        }
    }

    /// `eps = phase_error / amplitude` in Q15 by the reciprocal (updated at each window's
    /// end, not here), rounded to nearest (a floor would bias the phase error, and a loop
    /// settles where the phase error is zero) and kept in [-2^15, 2^15 - 1] (one `SSAT` on a
    /// Cortex-M4; beyond +-1 only while the reciprocal catches up with an amplitude step).
    /// `(phase_error r / 2^16 + 2^10) / 2^11` with `|phase_error| < 1.54e9` and
    /// `r < 2^15`: below `7.7e8`, no overflow.
    #[inline(always)]
    fn normalise(reciprocal: &mut i32, _sample: &Sample<i32>, phase_error: i32) -> i32 {
        // The reciprocal is in [MIN_RECIPROCAL, MAX_RECIPROCAL]: 16 bits.
        let scaled = mul_q16(phase_error, *reciprocal as i16);
        ((scaled + (1 << 10)) >> 11).clamp(-(1 << 15), (1 << 15) - 1)
    }

    /// The angle and the speed by `round(multiplier eps / 2^16)`, the acceleration by
    /// `multiplier eps 2^k` in its 64 bits, each wrapping (`docs/theory.md §14`); the next
    /// predicted angle is the prediction of the corrected state. The turns the angle
    /// crossed are counted by [`FixedGains::track`] (none are returned here).
    #[inline(always)]
    fn correct(&self, _x: &FixedVector, p: &mut FixedVector, eps: i32) -> (i32, i32) {
        // eps is in [-2^15, 2^15 - 1] (`normalise`).
        let eps = eps as i16;
        p.angle = add_round_q16(p.angle, self.multiplier[0], eps);
        if N > 1 {
            p.speed = add_round_q16(p.speed, self.multiplier[1], eps);
        }
        if N > 2 {
            p.acceleration = add_wide(
                p.acceleration,
                self.multiplier[N - 1],
                eps,
                self.acceleration_scale,
                self.acceleration_shift,
            );
        }
        let next_angle = Self::next_angle(p);
        if N > 2 {
            // The next sample's predicted speed.
            p.speed = p.speed.wrapping_add(speed_change(p.acceleration));
        }
        (next_angle, 0)
    }
}

/// Counts the turn the predicted angle crossed from `from` to the state's (out of line:
/// rare).
#[cold]
#[inline(never)]
pub(super) fn count_turn<const N: usize>(state: &mut FixedState<N>, from: i32) {
    state.turns = state
        .turns
        .wrapping_add(i64::from(crossed_turns::<i16>(from, state.next_angle)));
}

/// The whole turns of the estimate's angle: those of the predicted angle (which the state
/// counts) and the turn between the two, if any.
pub(super) fn turns_of_estimate<const N: usize>(state: &FixedState<N>) -> i64 {
    state.turns.wrapping_add(i64::from(crossed_turns::<i16>(
        state.next_angle,
        state.x.angle,
    )))
}

/// The fixed-point window: the sum of `|eps|` (Q15), counted down from [`MONITOR_WINDOW`]
/// (or from 1 by `FixedState::new`: at least 1 before each sample).
impl<const N: usize> MonitorWindow for FixedState<N> {
    /// `eps` (Q15).
    type Term = i32;
    /// `|eps|` (Q15, [`residual`]).
    type Residual = i32;

    /// At most MONITOR_WINDOW 2^15 = 2^20, no overflow.
    #[inline(always)]
    fn add(&mut self, eps: i32) -> i32 {
        let residual = residual(eps);
        self.error_sum += residual as u32;
        residual
    }

    #[inline(always)]
    fn remaining(&mut self) -> &mut u32 {
        &mut self.window_left
    }

    #[inline(always)]
    fn tracking(&self) -> &TrackingCheck<i16> {
        &self.tracking
    }
}

/// `|eps|` of a Q15 phase error, less one for a negative `eps` (`eps ^ (eps >> 31)`, one
/// instruction): a window's sum is within MONITOR_WINDOW units of the sum of `|eps|`, 0.03 %
/// of the threshold, and a sample's within one unit (0.002 % of the default tracking-error
/// level).
#[inline(always)]
fn residual(eps: i32) -> i32 {
    eps ^ (eps >> 31)
}

impl<const N: usize> FixedGains<N> {
    /// One sample of the fixed-point observer on the integer samples `y_c`, `y_s` (counts,
    /// the ADC's mid-scale removed; amplitudes from 4096 to 46341 counts are normalised
    /// exactly, so a 12-bit reading is shifted left by 3 or 4): predict, detect, normalise,
    /// correct by the one recursion of every observer, then the monitor. Never fails, never
    /// panics, never overflows (`docs/theory.md §14`).
    ///
    #[cfg(test)]
    #[inline]
    pub(crate) fn update(&self, state: &mut FixedState<N>, y_c: i16, y_s: i16) -> FixedEstimate {
        self.track(state, y_c, y_s);
        Self::estimate(state)
    }

    /// [`FixedGains::update`] without the estimate (a chain's `track`): the state (and its
    /// faults) updated, the estimate read on demand by [`FixedGains::estimate`].
    // Always inlined, as the float path's: a call costs a Cortex-M a few instructions more.
    #[inline(always)]
    pub(crate) fn track(&self, state: &mut FixedState<N>, y_c: i16, y_s: i16) {
        // Stored first: the sample's registers are then free for the rest.
        state.sample = [y_c, y_s];
        let (y_c, y_s) = (i32::from(y_c), i32::from(y_s));
        let from = state.next_angle;
        let sample = Sample {
            y_c,
            y_s,
            // The fixed-point path reads the amplitude once per window, and every integer
            // sample is valid.
            amplitude2: 0,
            valid: true,
        };
        let step = step::<Self, SineTable, NoWrap, N>(
            self,
            &mut SineTable,
            &mut state.x,
            &mut state.next_angle,
            &mut state.reciprocal,
            sample,
        );
        // The turns the predicted angle crossed from one sample to the next: the carry of
        // its change (the shortest way: below half a turn per sample); rare, so the 64-bit
        // count is read and written only then. Counted on the predicted angle, already in a
        // register; the estimate's angle is within half a turn of it (`turns_of_estimate`).
        if crosses_turn::<i16>(from, state.next_angle) {
            count_turn(state, from);
        }
        state.phase_error = step.eps;
        if state.accumulate(step.eps) {
            self.end_sample(state);
        }
    }

    /// A sample that changed the tracking-error flag or ended the window (out of line): the
    /// per-sample check applied (`crate::monitor::TrackingCheck::apply`, the floats' own),
    /// then the window's end if it ended.
    #[inline(never)]
    fn end_sample(&self, state: &mut FixedState<N>) {
        state.tracking.apply(
            residual(state.phase_error),
            self.monitor.tracking_error,
            &mut state.latched,
        );
        if state.window_left == 0 {
            self.end_window(state);
        }
    }

    /// The last sample, in counts.
    fn last_sample(state: &FixedState<N>) -> (i32, i32) {
        (i32::from(state.sample[0]), i32::from(state.sample[1]))
    }

    /// Half the last sample's square amplitude, `(y_c^2 + y_s^2) / 2`: at most 2^30.
    pub(super) fn amplitude2_half(state: &FixedState<N>) -> i32 {
        let (y_c, y_s) = Self::last_sample(state);
        // The sum is at most 2^31: in 32 bits unsigned.
        (((y_c * y_c) as u32).wrapping_add((y_s * y_s) as u32) >> 1) as i32
    }

    /// A window's end (once per window): half a Newton step of the reciprocal
    /// toward the amplitude of the window's last sample (half: the sample's noise is
    /// averaged over a few windows), then the monitor's decision ([`MonitorLimits`], the
    /// floats' own) on that amplitude, the window's sum of `|eps|`, the speed and the last
    /// sample's in-phase component at its estimated angle; a healthy window clears the
    /// flags, any other ([`FixedGains::end_window_with_fault`]) is the first sample's, or
    /// one with a fault.
    ///
    /// [`MonitorLimits`]: crate::monitor::MonitorLimits
    #[inline(always)]
    fn end_window(&self, state: &mut FixedState<N>) {
        let amplitude2 = Self::amplitude2_half(state);
        // Between r and the Newton step's result, both in range: in range.
        let r = state.reciprocal;
        state.reciprocal = r + ((track_reciprocal(r, amplitude2) - r) >> 1);
        let measures = Self::measures(state, amplitude2 as u32);
        if self.monitor.healthy(&measures) && state.round_hold == 0 {
            state.faults = Faults::NONE;
        } else {
            self.end_window_with_fault(state, amplitude2 as u32);
        }
        if self.monitor.enabled {
            // The window's mean |eps| (Q15): the sum is at most 2^20 but the forced 2^31.
            let mean = (state.error_sum / MONITOR_WINDOW).min(1 << 16) as i32;
            state.tracking.arm(self.monitor.tracking_error, mean);
        }
        state.error_sum = 0;
        state.window_left = MONITOR_WINDOW;
        if state.coasted != 0 {
            // A fit under way: the next sample ends a window of its own too.
            state.error_sum = 1 << 31;
            state.window_left = 1;
        }
    }

    /// What the monitor decides the window from: half the last sample's square amplitude
    /// `amplitude2`, the window's sum of `|eps|`, the speed and the last sample's in-phase
    /// component at its estimated angle.
    #[inline(always)]
    pub(super) fn measures(state: &FixedState<N>, amplitude2: u32) -> FixedMeasures {
        let (y_c, y_s) = Self::last_sample(state);
        WindowMeasures {
            amplitude2,
            // The first window's error sum starts at 2^31 (`FixedState::new`), above every
            // threshold, so that it is not taken for healthy.
            error: state.error_sum,
            // The predicted speed: within one sample's change of the corrected one, far
            // below the quarter turn per sample the check is for.
            speed: state.x.speed.unsigned_abs(),
            // Its sign tells a false lock (the estimate more than a quarter turn off).
            in_phase: detect(state.x.angle, y_c, y_s).1,
            // The amplitude is the last sample's: it is the roundness check's too.
            sample2: amplitude2,
        }
    }

    /// The estimate held by `state`.
    #[inline(always)]
    pub fn estimate(state: &FixedState<N>) -> FixedEstimate {
        FixedEstimate {
            angle: state.x.angle,
            turns: turns_of_estimate(state),
            speed: Self::corrected_speed(&state.x),
            acceleration: if N > 2 { state.x.acceleration } else { 0 },
            phase_error: state.phase_error,
            faults: state.faults.union(state.tracking.flag()),
        }
    }

    /// The estimate's multi-turn position (rad): `2 pi (turns + angle / 2^32)`.
    pub fn position_rad(&self, estimate: &FixedEstimate) -> f64 {
        (estimate.turns as f64 + f64::from(estimate.angle) / 4_294_967_296.0)
            * core::f64::consts::TAU
    }

    /// The estimate's speed (rad/s).
    pub fn speed_rad_s(&self, estimate: &FixedEstimate) -> f64 {
        f64::from(estimate.speed) / 4_294_967_296.0 * core::f64::consts::TAU / self.sample_period_s
    }

    /// The estimate's acceleration (rad/s^2), from 2^-63 turn per sample^2.
    pub fn acceleration_rad_s2(&self, estimate: &FixedEstimate) -> f64 {
        libm::ldexp(estimate.acceleration as f64, -63) * core::f64::consts::TAU
            / (self.sample_period_s * self.sample_period_s)
    }
}
