//! Re-acquisition after a long coast (`docs/theory.md §15`): the speed and the acceleration
//! the state held through a front-end fault are stale once the fault has lasted a while
//! (a shaft that accelerated through a brown-out), and a loop started from them rings for
//! its settling time with errors of tens of milliradians. So after a coast of at least
//! [`REFIT_AFTER_COAST`] samples, the next [`REFIT_SAMPLES`] samples are not tracked but
//! fitted: their angles (`atan2`, unwrapped the shortest way) give the angle, the speed and
//! the acceleration at the last of them, from which the loop starts. Those samples carry
//! [`Faults::LOSS_OF_TRACKING`](crate::Faults::LOSS_OF_TRACKING): the loop is not tracking
//! them.
//!
//! The fit takes the sums `G_0..G_3` of four groups of four samples (centred on
//! `t_j = 1.5 + 4j`). For `theta = a + b t + c t^2 / 2` a group's mean is
//! `a + b t_j + c (t_j^2 + 5/4) / 2`, so with `D = G_3 - G_2 - G_1 + G_0` and
//! `E = G_3 + G_2 - G_1 - G_0`, exactly:
//!
//! ```text
//! acceleration c        = D / 128
//! speed at t = 15       = (4 E + 15 D) / 256
//! angle at t = 15       = (16 (G_0 + G_1 + G_2 + G_3) + 30 E + 35 D) / 256
//! ```
//!
//! Every denominator is a power of two: the fixed-point observer divides by shifts (a
//! Cortex-M0 has no divide instruction, and a library division would be kilobytes).

use crate::faults::Faults;
use crate::monitor::MonitorState;
use crate::real::Float;

/// The samples of a coast after which the next samples are fitted rather than tracked:
/// below it the coasted speed is trusted (a drift of a few samples, taken out by the
/// re-acquired angle).
pub(crate) const REFIT_AFTER_COAST: u32 = 16;

/// The longest coast after which a re-acquisition's jump of a quarter turn or more is
/// flagged (`check_jump` in `update`): 64 samples, over which only an acceleration change
/// beyond 7.7e-4 rad per sample^2 drifts that far (`2 (pi/2) / 64^2`).
pub(crate) const IMPLAUSIBLE_JUMP_MAX_COAST: u32 = 64;

/// The windows after the one under way for which an implausible re-acquisition
/// ([`MonitorState::flag_implausible_jump`]) holds [`Faults::LOSS_OF_TRACKING`].
pub(crate) const IMPLAUSIBLE_JUMP_HOLD: u8 = 16;

/// The samples fitted after a long coast: four groups of four.
pub(crate) const REFIT_SAMPLES: u32 = 16;

/// The signs of sample `taken`'s group in `D` and `E` (each sample adds its unwrapped
/// angle to `sum G_j`, and with these signs to `D` and `E`).
fn signs(taken: u32) -> (i32, i32) {
    // Groups 0 to 3: D's signs + - - +, E's - - + +.
    match taken / 4 {
        0 => (1, -1),
        1 => (-1, -1),
        2 => (-1, 1),
        _ => (1, 1),
    }
}

/// The numbers the fit sums in: a float (rad), or the fixed-point observer's `i64` (2^-32
/// turn), whose operations wrap (no input can panic; the fit's sums stay below 2^47).
pub(crate) trait FitNumber: Copy {
    /// The angle of a sample as the fit is given it: nothing for the floats, which give its
    /// step from the last; the fixed-point observer's binary angle, from which the fit
    /// unwraps the step itself.
    type Given: Copy;
    /// The given angle of no sample.
    const NO_ANGLE: Self::Given;
    /// Zero.
    const ZERO: Self;
    /// `self + other`.
    fn plus(self, other: Self) -> Self;
    /// `self - other`.
    fn minus(self, other: Self) -> Self;
    /// `k self`.
    fn times(self, k: i32) -> Self;
    /// `self / 2^shift`: exact in a float, rounded to the nearest in an integer.
    fn over_power_of_two(self, shift: u32) -> Self;
    /// The acceleration `D / 128` in the state's unit: rad per sample^2 for the floats,
    /// 2^-63 turn per sample^2 (`D / 128` 2^-32 turn, times 2^31) for the fixed point.
    fn acceleration(d: Self) -> Self;
}

impl<T: Float> FitNumber for T {
    type Given = ();
    const NO_ANGLE: () = ();
    const ZERO: T = T::ZERO;
    #[inline(always)]
    fn plus(self, other: T) -> T {
        self + other
    }
    #[inline(always)]
    fn minus(self, other: T) -> T {
        self - other
    }
    #[inline(always)]
    fn times(self, k: i32) -> T {
        T::from_i32(k) * self
    }
    #[inline(always)]
    fn over_power_of_two(self, shift: u32) -> T {
        self / T::from_i32(1 << shift)
    }
    #[inline(always)]
    fn acceleration(d: T) -> T {
        d.over_power_of_two(7)
    }
}

impl FitNumber for i64 {
    type Given = i32;
    const NO_ANGLE: i32 = 0;
    const ZERO: i64 = 0;
    #[inline(always)]
    fn plus(self, other: i64) -> i64 {
        self.wrapping_add(other)
    }
    #[inline(always)]
    fn minus(self, other: i64) -> i64 {
        self.wrapping_sub(other)
    }
    #[inline(always)]
    fn times(self, k: i32) -> i64 {
        self.wrapping_mul(i64::from(k))
    }
    #[inline(always)]
    fn over_power_of_two(self, shift: u32) -> i64 {
        self.wrapping_add(1 << (shift - 1)) >> shift
    }
    #[inline(always)]
    fn acceleration(d: i64) -> i64 {
        d.wrapping_shl(24)
    }
}

/// The fit under way after a long coast, in the numbers `S`: the samples taken, the last
/// sample's angle as given ([`FitNumber::Given`]) and unwrapped from the first's, and the
/// sums `sum G_j`, `D`, `E`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Refit<S, A = ()> {
    /// Samples taken (0: none yet).
    pub(crate) taken: u32,
    /// The last sample's angle as given (`A`, [`FitNumber::Given`]), and unwrapped
    /// relative to the first's.
    last: (A, S),
    /// `sum G_j`, `D`, `E`.
    sums: [S; 3],
}

/// What the fit gives at its last sample: the angle's change from that sample's own
/// (unwrapped), the speed (per sample) and the acceleration (in the state's unit, see
/// [`FitNumber::acceleration`]).
pub(crate) struct Fitted<S> {
    pub(crate) angle_change: S,
    pub(crate) speed: S,
    pub(crate) acceleration: S,
}

impl<S: FitNumber> Refit<S, S::Given> {
    /// No fit under way.
    pub(crate) const fn new() -> Self {
        Self {
            taken: 0,
            last: (S::NO_ANGLE, S::ZERO),
            sums: [S::ZERO; 3],
        }
    }

    /// Takes one sample whose angle moved by `step` (wrapped: the shortest way) from the
    /// last one's (anything for the first); returns the fit once it has [`REFIT_SAMPLES`],
    /// and is then ready for another.
    pub(crate) fn take(&mut self, step: S) -> Option<Fitted<S>> {
        self.last.1 = if self.taken == 0 {
            S::ZERO
        } else {
            self.last.1.plus(step)
        };
        let last = self.last.1;
        let (d, e) = signs(self.taken);
        self.sums[0] = self.sums[0].plus(last);
        self.sums[1] = self.sums[1].plus(last.times(d));
        self.sums[2] = self.sums[2].plus(last.times(e));
        self.taken += 1;
        if self.taken < REFIT_SAMPLES {
            return None;
        }
        let [g, d, e] = self.sums;
        let end = g.times(16).plus(e.times(30)).plus(d.times(35));
        let fitted = Fitted {
            angle_change: end.over_power_of_two(8).minus(last),
            speed: e.times(4).plus(d.times(15)).over_power_of_two(8),
            acceleration: S::acceleration(d),
        };
        *self = Self::new();
        Some(fitted)
    }
}

/// The monitor's side of the check of a re-acquisition's jump (the floats'
/// `Driver::re_acquire_after_coast`, `update/coasting.rs`).
impl<T: Float> MonitorState<T> {
    /// A re-acquisition after a short coast jumped a quarter turn or more: the angle before
    /// it was wrong, and the pair it re-acquired from may be as wrong (a faulty pair the
    /// loop follows without an error the window's means would show). Flagged
    /// [`Faults::LOSS_OF_TRACKING`] at once and latched, and held for the window under way
    /// and the next [`IMPLAUSIBLE_JUMP_HOLD`] windows (out of line: a fault is rare).
    #[cold]
    #[inline(never)]
    pub(crate) fn flag_implausible_jump(&mut self) {
        self.flags |= Faults::LOSS_OF_TRACKING;
        self.latched |= Faults::LOSS_OF_TRACKING;
        self.held_windows = IMPLAUSIBLE_JUMP_HOLD;
    }

    /// The end of a window while an implausible re-acquisition holds its flag: the flag
    /// held until the next window ends.
    #[cold]
    #[inline(never)]
    pub(crate) fn hold_implausible_jump(&mut self) {
        self.held_windows -= 1;
        self.flags |= Faults::LOSS_OF_TRACKING;
        self.latched |= Faults::LOSS_OF_TRACKING;
    }
}

/// The fit in the fixed-point observer's integers: binary angles (2^-32 turn), unwrapped
/// in `i64` (16 samples of at most half a turn: below 2^35), the sums below 2^39.
pub(crate) type FixedRefit = Refit<i64, i32>;

/// What the integer fit gives at its last sample: the angle (2^-32 turn), the speed
/// (2^-32 turn per sample) and the acceleration (2^-63 turn per sample^2, the state's unit).
pub(crate) struct FixedFitted {
    pub(crate) angle: i32,
    pub(crate) speed: i32,
    pub(crate) acceleration: i64,
}

impl FixedRefit {
    /// Takes one sample of binary angle `angle` (unwrapped the shortest way: the wrapping
    /// difference of binary angles); returns the fit once it has [`REFIT_SAMPLES`], and is
    /// then ready for another.
    pub(crate) fn take_angle(&mut self, angle: i32) -> Option<FixedFitted> {
        let step = i64::from(angle.wrapping_sub(self.last.0));
        self.last.0 = angle;
        let fitted = self.take(step)?;
        Some(FixedFitted {
            angle: angle.wrapping_add(fitted.angle_change as i32),
            speed: fitted.speed as i32,
            acceleration: fitted.acceleration,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A parabola is fitted exactly: its end angle, speed and acceleration.
    #[test]
    fn a_parabola_is_fitted_exactly() {
        let (a, b, c) = (0.3_f64, 0.05, 2e-4);
        let angle = |k: f64| a + b * k + c * k * k / 2.0;
        let mut refit = Refit::<f64>::new();
        let mut fitted = None;
        for k in 0..REFIT_SAMPLES {
            let step = angle(f64::from(k)) - angle(f64::from(k) - 1.0);
            fitted = refit.take(step);
        }
        let fitted = fitted.expect("fitted after K samples");
        let end = f64::from(REFIT_SAMPLES - 1);
        assert!(fitted.angle_change.abs() < 1e-12);
        assert!(
            (fitted.speed - (b + c * end)).abs() < 1e-12,
            "{}",
            fitted.speed
        );
        assert!((fitted.acceleration - c).abs() < 1e-12);
        assert_eq!(refit, Refit::new());
    }

    /// White noise of standard deviation `sigma` on the angles leaves the fitted speed an
    /// error of about 0.24 sigma per sample (`docs/theory.md §15`): measured over 4000
    /// fits of a deterministic noise.
    #[test]
    fn the_speed_error_of_noisy_angles() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let sigma = 1e-3;
        let (mut squares, fits) = (0.0, 4000);
        for _ in 0..fits {
            let mut refit = Refit::<f64>::new();
            let (mut previous, mut fitted) = (0.0, None);
            for k in 0..REFIT_SAMPLES {
                // Uniform noise of standard deviation sigma.
                let noise = sigma * 12f64.sqrt() * (uniform() - 0.5);
                let angle = 0.02 * f64::from(k) + noise;
                fitted = refit.take(angle - previous);
                previous = angle;
            }
            let error = fitted.unwrap().speed - 0.02;
            squares += error * error;
        }
        let rms = (squares / f64::from(fits)).sqrt() / sigma;
        assert!((0.2..0.29).contains(&rms), "{rms}");
    }

    /// The integer fit of a parabola in binary angles, across the turn's wrap: its end
    /// angle, speed and acceleration to within the rounding of the integers.
    #[test]
    fn the_integer_fit_of_a_parabola() {
        let (a, b, c) = (2.1e9_f64, 3.0e7, 4.0e5);
        let angle = |k: f64| a + b * k + c * k * k / 2.0;
        let mut refit = FixedRefit::new();
        let mut fitted = None;
        for k in 0..REFIT_SAMPLES {
            let binary = (angle(f64::from(k)) as i64) as i32; // wraps past 2^31
            fitted = refit.take_angle(binary);
        }
        let fitted = fitted.expect("fitted after K samples");
        let end = f64::from(REFIT_SAMPLES - 1);
        assert!((i64::from(fitted.angle) - ((angle(end) as i64) as i32) as i64).abs() <= 2);
        assert!(
            (f64::from(fitted.speed) - (b + c * end)).abs() <= 2.0,
            "{}",
            fitted.speed
        );
        let acceleration = fitted.acceleration as f64 / 2f64.powi(31);
        assert!((acceleration - c).abs() < 1e-3 * c, "{acceleration}");
        assert_eq!(refit, FixedRefit::new());
    }
}
