//! [`AngleCorrection`]: a sensor's angle-dependent error (harmonics of the electrical angle
//! that no offset, imbalance or quadrature correction removes), as a `Copy` table of
//! Fourier coefficients, removed inside the phase detector by a signal chain's stage
//! ([`Chain`](crate::Chain), `docs/theory.md §15`).
//!
//! The sensor gives `y = A (cos(theta + d(theta)), sin(theta + d(theta)))` with
//!
//! ```text
//! d(theta) = sum_{k=1..order} a_k cos(k theta) + b_k sin(k theta)
//! ```
//!
//! Rotating the sample by `-d(p)`, `p` the observer's predicted angle, makes the phase
//! detector's output `sin(theta + d(theta) - p - d(p))`: the detector evaluated at
//! `p + d(p)`, whose zero is at `p = theta` when `p` is close to `theta`. Inside the loop,
//! the observer then tracks `theta` itself: its speed and acceleration no longer ripple
//! with `d`'s harmonics, which a correction of the output angle would leave in them.
//!
//! `d(p)` costs one sin/cos of `p` and, per order, the Chebyshev recurrence
//! `sin((k+1)p) = 2 cos p sin(kp) - sin((k-1)p)` (and its cosine twin) and two
//! multiply-adds; the rotation, with `sin d = d - d^3/6` and `cos d = 1 - d^2/2`
//! (within `|d|^4/24` for `|d|` up to [`AngleCorrection::max_total_rad`]), a few more.

use crate::error::{ConfigError, Parameter};
use crate::real::Float;

/// [`AngleCorrection::max_total_rad`] (rad).
pub(crate) const MAX_TOTAL_RAD: f64 = 0.25;

/// The highest harmonic order an [`AngleCorrection`] holds.
pub const MAX_CORRECTION_ORDER: usize = 8;

/// An angle-dependent sensor error `d(theta) = sum_k a_k cos(k theta) + b_k sin(k theta)`,
/// `k = 1..=MAX_CORRECTION_ORDER` (rad), to be removed inside the phase detector by a chain's stage ([`Chain`](crate::Chain), see
/// the module's documentation). Learned from a capture by the `angletrack` crate's
/// `calibrate`; `Copy` and fixed-size, so firmware keeps it in flash and in the
/// configuration beside the [`Gains`](crate::Gains). The default corrects nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleCorrection<T> {
    /// `a_k` (index `k - 1`), rad.
    pub(crate) cos_coefficients: [T; MAX_CORRECTION_ORDER],
    /// `b_k` (index `k - 1`), rad.
    pub(crate) sin_coefficients: [T; MAX_CORRECTION_ORDER],
    /// The highest order with a non-zero coefficient (0: no correction).
    pub(crate) order: usize,
}

impl<T: Float> Default for AngleCorrection<T> {
    fn default() -> Self {
        Self::NONE
    }
}

impl<T: Float> AngleCorrection<T> {
    /// A correction from its coefficients `cos_coefficients[k - 1] = a_k` and
    /// `sin_coefficients[k - 1] = b_k` (rad), `d(theta) = sum_k a_k cos(k theta) +
    /// b_k sin(k theta)`.
    ///
    /// Refuses non-finite coefficients and a total `sum_k |a_k| + |b_k|` beyond
    /// [`AngleCorrection::max_total_rad`] ([`Parameter::AngleCorrection`](crate::Parameter::AngleCorrection)).
    ///
    /// ```
    /// use angletrack_core::{AngleCorrection, Parameter};
    /// // 5 mrad of 3rd harmonic (sine phase) and 5 mrad of 4th (cosine phase).
    /// let mut a = [0.0_f32; 8];
    /// let mut b = [0.0_f32; 8];
    /// b[2] = 5e-3;
    /// a[3] = 5e-3;
    /// let correction = AngleCorrection::new(a, b)?;
    /// assert_eq!(correction.order(), 4);
    /// let theta = 0.3_f32;
    /// let d = 5e-3 * (3.0 * theta).sin() + 5e-3 * (4.0 * theta).cos();
    /// assert!((correction.error_at(theta) - d).abs() < 1e-7);
    /// b[0] = f32::NAN;
    /// let err = AngleCorrection::new(a, b).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AngleCorrection);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(
        cos_coefficients: [T; MAX_CORRECTION_ORDER],
        sin_coefficients: [T; MAX_CORRECTION_ORDER],
    ) -> Result<Self, ConfigError> {
        let mut total = T::ZERO;
        let mut order = 0;
        for k in 0..MAX_CORRECTION_ORDER {
            let (a, b) = (cos_coefficients[k], sin_coefficients[k]);
            if !(a.is_finite() && b.is_finite()) {
                return Err(ConfigError::NotFinite(Parameter::AngleCorrection));
            }
            total += a.abs() + b.abs();
            if a != T::ZERO || b != T::ZERO {
                order = k + 1;
            }
        }
        if !(total <= Self::max_total_rad()) {
            return Err(ConfigError::OutOfRange(Parameter::AngleCorrection));
        }
        Ok(Self {
            cos_coefficients,
            sin_coefficients,
            order,
        })
    }
}

impl<T: Float> AngleCorrection<T> {
    /// No correction.
    pub const NONE: Self = Self {
        cos_coefficients: [T::ZERO; MAX_CORRECTION_ORDER],
        sin_coefficients: [T::ZERO; MAX_CORRECTION_ORDER],
        order: 0,
    };

    /// The largest `sum_k |a_k| + |b_k|` (rad), a bound of `|d|`: 0.25 rad, within which the
    /// rotation's polynomial sin/cos of `d` err by less than `|d|^4/24` (2e-4 at the bound,
    /// 1e-10 for a sensor's few mrad). Float sensors are within a few tens of mrad.
    pub fn max_total_rad() -> T {
        T::from_f32(MAX_TOTAL_RAD as f32)
    }

    /// The coefficients `(a, b)`: `a[k - 1] = a_k`, `b[k - 1] = b_k` (rad), as
    /// [`AngleCorrection::new`] takes them.
    pub fn coefficients(&self) -> ([T; MAX_CORRECTION_ORDER], [T; MAX_CORRECTION_ORDER]) {
        (self.cos_coefficients, self.sin_coefficients)
    }

    /// The highest order with a non-zero coefficient (0: no correction); the cost of
    /// [`AngleCorrection::error_from_sin_cos`] grows with it.
    pub fn order(&self) -> usize {
        self.order
    }

    /// `d(angle)` (rad) for `angle` in [-pi, pi], with the polynomial sin/cos
    /// (`docs/theory.md §11`).
    pub fn error_at(&self, angle: T) -> T {
        let (sin, cos) = angle.fast_sin_cos();
        self.error_from_sin_cos(sin, cos)
    }

    /// `d(p)` (rad) from `sin p` and `cos p`: the Chebyshev recurrence up to
    /// [`AngleCorrection::order`], four multiply-adds per order.
    #[inline(always)]
    pub fn error_from_sin_cos(&self, sin: T, cos: T) -> T {
        let two_cos = cos + cos;
        let (mut sin_prev, mut cos_prev) = (T::ZERO, T::ONE);
        let (mut sin_k, mut cos_k) = (sin, cos);
        let mut d = T::ZERO;
        for k in 0..self.order.min(MAX_CORRECTION_ORDER) {
            d += self.cos_coefficients[k] * cos_k + self.sin_coefficients[k] * sin_k;
            let sin_next = two_cos * sin_k - sin_prev;
            let cos_next = two_cos * cos_k - cos_prev;
            (sin_prev, cos_prev, sin_k, cos_k) = (sin_k, cos_k, sin_next, cos_next);
        }
        d
    }

    /// The sample `(y_c, y_s)` rotated by `-d(p)`, `(sin p, cos p)` given: the phase
    /// detector at `p` then gives what it would at `p + d(p)` (see the module's
    /// documentation). Keeps the sample's magnitude (to `|d|^4/24`).
    #[inline(always)]
    pub fn rotate(&self, sin_p: T, cos_p: T, y_c: T, y_s: T) -> (T, T) {
        rotate_by(self.error_from_sin_cos(sin_p, cos_p), y_c, y_s)
    }
}

/// The sample `(y_c, y_s)` rotated by `-d` (rad, within
/// [`AngleCorrection::max_total_rad`]), with `sin d = d - d^3/6` and `cos d = 1 - d^2/2`:
/// keeps the sample's magnitude to `|d|^4/24`.
#[inline(always)]
pub(crate) fn rotate_by<T: Float>(d: T, y_c: T, y_s: T) -> (T, T) {
    let d2 = d * d;
    let sin_d = d - d * d2 * T::from_f32(1.0 / 6.0);
    let cos_d = T::ONE - d2 * T::HALF;
    (y_c * cos_d + y_s * sin_d, y_s * cos_d - y_c * sin_d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recurrence_matches_direct_sum_to_the_highest_order() {
        let mut a = [0.0_f64; MAX_CORRECTION_ORDER];
        let mut b = [0.0_f64; MAX_CORRECTION_ORDER];
        for k in 0..MAX_CORRECTION_ORDER {
            a[k] = 1e-3 * (k as f64 + 1.0);
            b[k] = -7e-4 * (k as f64 * 0.7).cos();
        }
        let correction = AngleCorrection::new(a, b).unwrap();
        assert_eq!(correction.order(), MAX_CORRECTION_ORDER);
        for i in 0..100 {
            let theta = -3.1 + 0.062 * i as f64;
            let direct: f64 = (0..MAX_CORRECTION_ORDER)
                .map(|k| {
                    let kt = (k as f64 + 1.0) * theta;
                    a[k] * libm::cos(kt) + b[k] * libm::sin(kt)
                })
                .sum();
            assert!((correction.error_at(theta) - direct).abs() < 1e-12);
        }
    }

    #[test]
    fn too_large_a_correction_is_refused() {
        let mut a = [0.0_f32; MAX_CORRECTION_ORDER];
        a[0] = 0.2;
        a[1] = -0.06;
        assert_eq!(
            AngleCorrection::new(a, [0.0; MAX_CORRECTION_ORDER]),
            Err(ConfigError::OutOfRange(Parameter::AngleCorrection))
        );
    }

    #[test]
    fn rotation_moves_the_detector_by_the_error() {
        let mut b = [0.0_f32; MAX_CORRECTION_ORDER];
        b[3] = 0.02;
        let correction = AngleCorrection::new([0.0; MAX_CORRECTION_ORDER], b).unwrap();
        let p = 0.4_f32;
        let d = 0.02 * libm::sinf(4.0 * p);
        let (y_c, y_s) = (libm::cosf(p + d), libm::sinf(p + d));
        let (c, s) = correction.rotate(libm::sinf(p), libm::cosf(p), y_c, y_s);
        assert!((s * libm::cosf(p) - c * libm::sinf(p)).abs() < 1e-6);
        assert!((c * c + s * s - 1.0).abs() < 1e-6);
    }
}
