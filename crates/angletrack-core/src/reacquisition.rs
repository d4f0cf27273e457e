//! Re-acquisition after a long coast (`docs/theory.md §15`): the speed and the acceleration
//! the state held through a front-end fault are stale once the fault has lasted a while
//! (a shaft that accelerated through a brown-out), and a loop started from them rings for
//! its settling time with errors of tenths of a radian. So after a coast of at least
//! [`REFIT_AFTER_COAST`] samples, the next [`REFIT_SAMPLES`] samples are not tracked but
//! fitted: their angles (`atan2`, unwrapped) by least squares to a parabola in the sample
//! index, whose end gives the angle, the speed and the acceleration the loop starts from.
//! Those samples carry [`Faults::LOSS_OF_TRACKING`](crate::Faults::LOSS_OF_TRACKING): the
//! loop is not tracking them.
//!
//! The fit uses the discrete orthogonal (Gram) polynomials of the centred index
//! `u = k - (K - 1)/2`, `p0 = 1`, `p1 = u`, `p2 = u^2 - (K^2 - 1)/12`: each coefficient is
//! one running sum divided by a constant, `c_j = sum p_j(u) theta_k / sum p_j(u)^2`, with
//! `sum p1^2 = K (K^2 - 1)/12` and `sum p2^2 = K (K^2 - 1)(K^2 - 4)/180`, and no system
//! to solve.

use crate::real::Float;

/// The samples of a coast after which the next samples are fitted rather than tracked:
/// below it the coasted speed is trusted (a drift of a few samples, taken out by the
/// re-acquired angle).
pub(crate) const REFIT_AFTER_COAST: u32 = 16;

/// The samples fitted after a long coast, `K`.
pub(crate) const REFIT_SAMPLES: u32 = 16;

/// The fit under way after a long coast: the samples taken, the unwrapped angle of the
/// last (rad, from the first's) and the three sums.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Refit<T> {
    /// Samples taken (0: none yet).
    pub(crate) taken: u32,
    /// The last sample's angle, unwrapped, relative to the first's (rad).
    last: T,
    /// `sum p_j(u_k) theta_k` for `j = 0, 1, 2`.
    sums: [T; 3],
}

/// What the fit gives at its last sample: the angle's change from the last sample's
/// `atan2` (rad), the speed (rad per sample) and the acceleration (rad per sample^2).
pub(crate) struct Fitted<T> {
    pub(crate) angle_change: T,
    pub(crate) speed: T,
    pub(crate) acceleration: T,
}

impl<T: Float> Refit<T> {
    /// No fit under way.
    pub(crate) const fn new() -> Self {
        Self {
            taken: 0,
            last: T::ZERO,
            sums: [T::ZERO; 3],
        }
    }

    /// The centred index of sample `k` and its second Gram polynomial.
    fn basis(k: u32) -> (T, T) {
        let n = T::from_i32(REFIT_SAMPLES as i32);
        let u = T::from_i32(k as i32) - (n - T::ONE) * T::HALF;
        (u, u * u - (n * n - T::ONE) / T::from_i32(12))
    }

    /// Takes one sample whose angle moved by `step` (rad, wrapped: the shortest way) from
    /// the last one's (anything for the first); returns the fit once it has
    /// [`REFIT_SAMPLES`], and is then ready for another.
    pub(crate) fn take(&mut self, step: T) -> Option<Fitted<T>> {
        self.last = if self.taken == 0 {
            T::ZERO
        } else {
            self.last + step
        };
        let (u, p2) = Self::basis(self.taken);
        self.sums[0] += self.last;
        self.sums[1] += u * self.last;
        self.sums[2] += p2 * self.last;
        self.taken += 1;
        if self.taken < REFIT_SAMPLES {
            return None;
        }
        let n = T::from_i32(REFIT_SAMPLES as i32);
        let c0 = self.sums[0] / n;
        let c1 = self.sums[1] * T::from_i32(12) / (n * (n * n - T::ONE));
        let c2 =
            self.sums[2] * T::from_i32(180) / (n * (n * n - T::ONE) * (n * n - T::from_i32(4)));
        let (u, p2) = Self::basis(REFIT_SAMPLES - 1);
        let fitted = Fitted {
            angle_change: c0 + c1 * u + c2 * p2 - self.last,
            speed: c1 + T::TWO * c2 * u,
            acceleration: T::TWO * c2,
        };
        *self = Self::new();
        Some(fitted)
    }
}

/// The fit in the fixed-point observer's integers: binary angles (2^-32 turn), the sums in
/// `i64` of the doubled centred index `v = 2u` (odd, -15 to 15) and of `q = 4 p2 = v^2 - 85`
/// (the constants below are those of `K = 16`: `sum u^2 = 340`, `sum p2^2 = 5712`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct FixedRefit {
    /// Samples taken (0: none yet).
    pub(crate) taken: u32,
    /// The last sample's binary angle, and its angle unwrapped from the first's.
    last: (i32, i64),
    /// `sum theta`, `sum v theta`, `sum q theta`.
    sums: [i64; 3],
}

/// What the integer fit gives at its last sample: the angle (2^-32 turn), the speed
/// (2^-32 turn per sample) and the acceleration (2^-63 turn per sample^2, the state's unit).
pub(crate) struct FixedFitted {
    pub(crate) angle: i32,
    pub(crate) speed: i32,
    pub(crate) acceleration: i64,
}

const _: () = assert!(
    REFIT_SAMPLES == 16,
    "FixedRefit's constants are those of K = 16"
);

/// `numerator / denominator` rounded to the nearest, `denominator > 0` (in `i64`: an
/// `i128` division would bring a Cortex-M0 kilobytes of library code).
fn rounded(numerator: i64, denominator: i64) -> i64 {
    let half = numerator.signum().wrapping_mul(denominator / 2);
    numerator.wrapping_add(half) / denominator
}

impl FixedRefit {
    /// No fit under way.
    pub(crate) const fn new() -> Self {
        Self {
            taken: 0,
            last: (0, 0),
            sums: [0; 3],
        }
    }

    /// Takes one sample of binary angle `angle`; returns the fit once it has
    /// [`REFIT_SAMPLES`], and is then ready for another.
    pub(crate) fn take(&mut self, angle: i32) -> Option<FixedFitted> {
        let unwrapped = if self.taken == 0 {
            0
        } else {
            // The shortest way: the wrapping difference of binary angles.
            self.last.1 + i64::from(angle.wrapping_sub(self.last.0))
        };
        self.last = (angle, unwrapped);
        let v = 2 * i64::from(self.taken) - 15;
        self.sums[0] += unwrapped;
        self.sums[1] += v * unwrapped;
        self.sums[2] += (v * v - 85) * unwrapped;
        self.taken += 1;
        if self.taken < REFIT_SAMPLES {
            return None;
        }
        let [s0, s1, s2] = self.sums;
        // At u = 7.5 (v = 15, q = 140): c0 + 7.5 c1 + 35 c2, c1 + 15 c2 and 2 c2, with
        // c0 = s0 / 16, c1 = s1 / 680, c2 = s2 / 22848, over their common denominator.
        // Below half a turn a sample, |theta| < 2^35, |s0| < 2^39, |s1| < 2^42 and
        // |s2| < 2^46: the products below stay under 2^56 (wrapping beyond: no panic).
        let end = rounded(
            7140_i64
                .wrapping_mul(s0)
                .wrapping_add(1260_i64.wrapping_mul(s1))
                .wrapping_add(175_i64.wrapping_mul(s2)),
            114_240,
        );
        let speed = rounded(
            168_i64
                .wrapping_mul(s1)
                .wrapping_add(75_i64.wrapping_mul(s2)),
            114_240,
        );
        // 2^31 s2 / 11424 without 2^77: the quotient's part shifted, the remainder's scaled.
        let (whole, part) = (s2 / 11_424, s2 % 11_424);
        let acceleration = whole
            .wrapping_shl(31)
            .wrapping_add(rounded(part.wrapping_shl(31), 11_424));
        let fitted = FixedFitted {
            angle: angle.wrapping_add(end.wrapping_sub(unwrapped) as i32),
            speed: speed as i32,
            acceleration,
        };
        *self = Self::new();
        Some(fitted)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The integer fit of a parabola in binary angles, across the turn's wrap: its end
    /// angle, speed and acceleration to within a unit of rounding.
    #[test]
    fn the_integer_fit_of_a_parabola() {
        let (a, b, c) = (2.1e9_f64, 3.0e7, 4.0e5);
        let angle = |k: f64| a + b * k + c * k * k / 2.0;
        let mut refit = FixedRefit::new();
        let mut fitted = None;
        for k in 0..REFIT_SAMPLES {
            let binary = (angle(f64::from(k)) as i64) as i32; // wraps past 2^31
            fitted = refit.take(binary);
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

    /// Noise on the angles: the fitted speed's error is the fit's, far below the samples'.
    #[test]
    fn noise_is_averaged() {
        let mut refit = Refit::<f32>::new();
        let mut previous = 0.0_f32;
        let mut fitted = None;
        for k in 0..REFIT_SAMPLES {
            // +-1 mrad alternating: the worst white-ish pattern for a difference.
            let angle = 0.02 * k as f32 + if k % 2 == 0 { 1e-3 } else { -1e-3 };
            fitted = refit.take(angle - previous);
            previous = angle;
        }
        let fitted = fitted.unwrap();
        assert!((fitted.speed - 0.02).abs() < 2e-4, "{}", fitted.speed);
    }
}
