//! The fixed-point update (`docs/theory.md §14`): the integer [`Arithmetic`] of the one
//! recursion ([`step`]), the amplitude's reciprocal tracker that normalises the phase error
//! without a division, the first sample, and the monitor in integers.

use super::binary_angle::{atan2, detect};
use super::gains::FixedGains;
use super::state::{FixedEstimate, FixedState};
use crate::faults::Faults;
use crate::recursion::{Arithmetic, step};
use crate::sincos::Detection;
use crate::update::Sample;
use crate::wrap::{NoWrap, Wrap};

/// The smallest value of the tracked reciprocal `2^27 / amplitude`: amplitudes up to 65536
/// counts, above any `i16` signal's `32768 sqrt(2)`.
pub const MIN_RECIPROCAL: i32 = 2048;

/// The largest value of the tracked reciprocal, `2^15 - 1`: amplitudes down to 4096 counts
/// ([`MIN_NORMALISED_AMPLITUDE_COUNTS`](crate::fixed::MIN_NORMALISED_AMPLITUDE_COUNTS)).
pub const MAX_RECIPROCAL: i32 = (1 << 15) - 1;

/// Samples per window of the fixed-point monitor: the flags are decided at each window's
/// end, so a fault present over a whole window is flagged at most `2 W - 1` samples after it
/// starts (`docs/theory.md §14`).
pub const MONITOR_WINDOW: u32 = 16;

/// The phase detector of the fixed-point path: the binary angle's sine table
/// ([`detect`]). Zero-sized.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SineTable;

/// One Newton step of the reciprocal square root: `r (3 - r^2 m) / 2` with
/// `m = amplitude2_half 2^-53`, so that `r` tends to `2^27 / sqrt(y_c^2 + y_s^2)`
/// (`docs/theory.md §14`). The factor is kept in [1/2, 3/2], so a far-off `r` (a step of the
/// amplitude) moves by at most half or half again per sample and converges; the result is
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

/// `(y_c^2 + y_s^2) / 2` of a sample in [-32768, 32767]: at most 2^30.
#[inline(always)]
fn amplitude2_half(y_c: i32, y_s: i32) -> i32 {
    ((y_c * y_c) >> 1) + ((y_s * y_s) >> 1)
}

/// A value normalised by the tracked reciprocal, in Q15: `(v / 2^15) r / 2^12`, each shift
/// rounded to nearest (a floor would bias the phase error, and a loop settles where the
/// phase error is zero). For `|v| < 1.54e9` (a phase-detector output): `|(v + 2^14) >> 15|
/// <= 46911`, times `r < 2^15`, plus `2^11`, stays below 1.54e9.
#[inline(always)]
fn normalised(value: i32, reciprocal: i32) -> i32 {
    ((((value + (1 << 14)) >> 15) * reciprocal) + (1 << 11)) >> 12
}

impl<const N: usize> Arithmetic<SineTable, N> for FixedGains<N> {
    type Value = i32;
    type Magnitude = i32;

    /// `p_i = x_i + sum_{j > i} x_j / (j - i)!` with each state's fraction bits; the angle
    /// and the speed wrap (they are modular: one turn, one turn per sample), the acceleration
    /// is carried without change.
    #[inline(always)]
    fn predict(&self, x: &[i32; N]) -> [i32; N] {
        let mut p = *x;
        let mut i = 0;
        while i < N {
            let mut j = i + 1;
            while j < N {
                // The angle and speed have no fraction bits: only the acceleration's shift
                // is a variable (the loops unroll, so the others are constants).
                let shift = if j < 2 {
                    (j - i - 1) as u32
                } else {
                    self.acceleration_shift[i].bits()
                };
                p[i] = p[i].wrapping_add(x[j] >> shift);
                j += 1;
            }
            i += 1;
        }
        p
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

    /// `eps = phase_error / amplitude` in Q15, by the reciprocal tracked with this sample,
    /// kept in [-2^15, 2^15 - 1] (the sine's range, less a unit at the top: one saturation
    /// instruction on a Cortex-M4; beyond it only while the tracker catches up with an
    /// amplitude step).
    #[inline(always)]
    fn normalise(reciprocal: &mut i32, sample: &Sample<i32>, phase_error: i32) -> i32 {
        if !sample.valid {
            return 0;
        }
        *reciprocal = track_reciprocal(*reciprocal, sample.amplitude2);
        normalised(phase_error, *reciprocal).clamp(-(1 << 15), (1 << 15) - 1)
    }

    /// `x_i += (mantissa_i eps + rounding_i) >> shift_i`, rounded to nearest (a floor would
    /// bias the speed by half a unit per sample, which a 2nd-order loop turns into an angle
    /// error; `|mantissa_i eps| <= (2^15 - 1) 2^15`, plus `rounding_i <= 2^30`, stays below
    /// 2^31), the angle and speed wrapping, the acceleration saturating; the next predicted angle is the
    /// prediction of the corrected state; the turns the angle crossed are the carry of its
    /// change (the shortest way: below half a turn per sample).
    #[inline(always)]
    fn correct(&self, x: &[i32; N], p: &mut [i32; N], eps: i32) -> (i32, i32) {
        let mut i = 0;
        while i < N {
            let delta = (self.mantissa[i] * eps + self.rounding[i]) >> self.shift[i].bits();
            p[i] = if i == 2 {
                p[i].saturating_add(delta)
            } else {
                p[i].wrapping_add(delta)
            };
            i += 1;
        }
        let next = Arithmetic::<SineTable, N>::predict(self, p)[0];
        (next, crossed_turns(x[0], p[0]))
    }
}

/// The whole turns (-1, 0 or 1) crossed from binary angle `from` to `to` by the shortest way.
#[inline(always)]
fn crossed_turns(from: i32, to: i32) -> i32 {
    let change = to.wrapping_sub(from);
    match from.checked_add(change) {
        Some(_) => 0,
        None if change > 0 => 1,
        None => -1,
    }
}

impl<const N: usize> FixedGains<N> {
    /// One sample of the fixed-point observer on the integer samples `y_c`, `y_s` (counts,
    /// the ADC's mid-scale removed; amplitudes from 4096 to 46341 counts are normalised
    /// exactly, so a 12-bit reading is shifted left by 3 or 4): predict, detect, normalise,
    /// correct by the one recursion of every observer, then the monitor. Never fails, never
    /// panics, never overflows (`docs/theory.md §14`).
    ///
    /// ```
    /// use angletrack_core::{Faults, FixedGains, FixedState};
    /// let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
    /// let mut state = FixedState::new();
    /// let mut e = Default::default();
    /// for k in 0..2000 {
    ///     // 2 rad/ms: 0.1 rad per sample.
    ///     let theta = 0.1 * k as f64;
    ///     let (c, s) = ((16384.0 * theta.cos()) as i16, (16384.0 * theta.sin()) as i16);
    ///     e = gains.update(&mut state, c, s);
    /// }
    /// let speed_rad_s = gains.speed_rad_s(&e);
    /// assert!((speed_rad_s - 2000.0).abs() < 0.1, "{speed_rad_s}");
    /// assert_eq!(e.faults, Faults::NONE);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    #[inline]
    pub fn update(&self, state: &mut FixedState<N>, y_c: i16, y_s: i16) -> FixedEstimate {
        self.track(state, y_c, y_s);
        Self::estimate(state)
    }

    /// [`FixedGains::update`] without the estimate: the state (and its faults) updated,
    /// the estimate read on demand by [`FixedGains::estimate`] (the cheaper per-sample
    /// entry point where the estimate is read less often than every sample).
    ///
    /// ```
    /// use angletrack_core::{Faults, FixedGains, FixedState};
    /// let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
    /// let mut state = FixedState::new();
    /// for k in 0..2000 {
    ///     let theta = 0.1 * k as f64;
    ///     let (c, s) = ((16384.0 * theta.cos()) as i16, (16384.0 * theta.sin()) as i16);
    ///     gains.track(&mut state, c, s);
    /// }
    /// let e = FixedGains::estimate(&state);
    /// assert!((gains.speed_rad_s(&e) - 2000.0).abs() < 0.1);
    /// assert_eq!(e.faults, Faults::NONE);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    #[inline]
    pub fn track(&self, state: &mut FixedState<N>, y_c: i16, y_s: i16) {
        let (y_c, y_s) = (i32::from(y_c), i32::from(y_s));
        if !state.initialised {
            self.initialise(state, y_c, y_s);
            return;
        }
        let sample = Sample {
            y_c,
            y_s,
            amplitude2: amplitude2_half(y_c, y_s),
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
        // A turn is crossed rarely: the 64-bit count is read and written only then.
        if step.whole != 0 {
            state.turns = state.turns.wrapping_add(i64::from(step.whole));
        }
        state.phase_error = step.eps;
        if self.monitor.enabled {
            self.observe(state, step.eps, step.in_phase, y_c, y_s);
        }
    }

    /// The monitor's per-sample part (`docs/theory.md §14`): `|eps|` summed over a window
    /// of [`MONITOR_WINDOW`] samples (at most 2^19: no overflow), and the flags decided at
    /// the window's end.
    #[inline(always)]
    fn observe(&self, state: &mut FixedState<N>, eps: i32, in_phase: i32, y_c: i32, y_s: i32) {
        state.error_sum += eps.abs();
        state.window_left -= 1;
        if state.window_left == 0 {
            self.decide(state, in_phase, y_c, y_s);
        }
    }

    /// The flags at a window's end (out of line: once per window), latched, and the
    /// re-acquisition after a false lock: loss of signal and degradation from the tracked
    /// reciprocal (an amplitude estimate), loss of tracking from the window's mean `|eps|`
    /// and the speed, false lock from the sign of the window's last in-phase component, with
    /// the float monitor's default thresholds.
    #[inline(never)]
    fn decide(&self, state: &mut FixedState<N>, in_phase: i32, y_c: i32, y_s: i32) {
        let t = &self.monitor;
        let r = state.reciprocal;
        let speed = if N > 1 { state.x[1] } else { 0 };
        let signal_lost = r >= t.loss_of_signal;
        let false_lock = !signal_lost && in_phase < 0;
        let faults = Faults::when(signal_lost, Faults::LOSS_OF_SIGNAL)
            | Faults::when(
                r > t.degradation_low || r < t.degradation_high,
                Faults::DEGRADATION_OF_SIGNAL,
            )
            | Faults::when(
                state.error_sum > t.loss_of_tracking * MONITOR_WINDOW as i32
                    || speed.unsigned_abs() > t.max_speed as u32,
                Faults::LOSS_OF_TRACKING,
            )
            | Faults::when(false_lock, Faults::FALSE_LOCK);
        state.faults = faults;
        state.latched |= faults;
        state.error_sum = 0;
        state.window_left = MONITOR_WINDOW;
        if false_lock {
            let angle = atan2(y_s, y_c);
            state.turns = state
                .turns
                .wrapping_add(i64::from(crossed_turns(state.x[0], angle)));
            state.x[0] = angle;
            state.next_angle = Arithmetic::<SineTable, N>::predict(self, &state.x)[0];
        }
    }

    /// The first sample: the angle from `atan2`, speed and acceleration 0, the reciprocal
    /// converged on the sample's amplitude.
    #[cold]
    #[inline(never)]
    fn initialise(&self, state: &mut FixedState<N>, y_c: i32, y_s: i32) {
        let latched = state.latched;
        *state = FixedState::new();
        state.latched = latched;
        state.x[0] = atan2(y_s, y_c);
        state.next_angle = state.x[0];
        let amplitude2 = amplitude2_half(y_c, y_s);
        // Until a fixed point (or 24 steps): the same result as 24 steps, and a loop that is
        // not unrolled into a kilobyte of code.
        for _ in 0..24 {
            let next = track_reciprocal(state.reciprocal, amplitude2);
            if next == state.reciprocal {
                break;
            }
            state.reciprocal = next;
        }
        state.initialised = true;
    }

    /// The estimate held by `state`.
    #[inline(always)]
    pub fn estimate(state: &FixedState<N>) -> FixedEstimate {
        FixedEstimate {
            angle: state.x[0],
            turns: state.turns,
            speed: if N > 1 { state.x[1] } else { 0 },
            acceleration: if N > 2 { state.x[N - 1] } else { 0 },
            phase_error: state.phase_error,
            faults: state.faults,
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

    /// The estimate's acceleration (rad/s^2).
    pub fn acceleration_rad_s2(&self, estimate: &FixedEstimate) -> f64 {
        let unit = libm::ldexp(1.0, -32 - self.acceleration_fraction_bits() as i32);
        f64::from(estimate.acceleration) * unit * core::f64::consts::TAU
            / (self.sample_period_s * self.sample_period_s)
    }
}
