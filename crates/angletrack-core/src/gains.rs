//! [`Gains`]: the immutable, checked configuration of an observer, and the orders it may
//! have. Everything is checked here, once, so that the per-sample update never fails:
//! finite values, a physical sample period, gains inside the stability region of the
//! discrete loop (`docs/theory.md §6`) and consistent fault thresholds.

use core::marker::PhantomData;

use crate::calibration_settings::{CalibrationSettings, CheckedCalibration};
use crate::monitor::{CheckedThresholds, FaultThresholds};
use crate::real::Float;
use crate::real::sincos::SinCos;
pub use crate::stability::{Order, SupportedOrder};

/// The immutable, checked configuration of an angle tracking observer of order `N`:
/// the discrete gains `L = (l1, l2[, l3])` of the recursion on the scaled state
/// `(theta, Ts Omega[, Ts^2 alpha])` (`docs/theory.md §5`), the sample period, and the
/// sin/cos implementation `S` of the phase detector.
///
/// The gains act on the normalised phase error (about the sine of the angle error, whatever
/// the amplitude, `docs/theory.md §12`): a Kalman design's measurement noise `r` is
/// `(noise / amplitude)^2`.
///
/// Only [`Gains::new`] and [`Gains::from_loop_polynomial`] make one, for `N` = 2 or 3
/// ([`SupportedOrder`]), or their `const` forms [`Gains::new_const`] and
/// [`Gains::from_loop_polynomial_const`] for a `static` checked at compile time. `Copy`: one configuration can drive any number of
/// [`ObserverState`](crate::ObserverState)s (channels).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains<T: Float, const N: usize, S = <T as Float>::DefaultSinCos> {
    pub(crate) l: [T; N],
    pub(crate) sample_period: T,
    pub(crate) sample_rate: T,
    pub(crate) sample_rate_squared: T,
    /// `(A L)[0] = l1 + l2 + l3/2`: how much one sample's phase error moves the next
    /// sample's predicted angle.
    pub(crate) next_angle_gain: T,
    pub(crate) thresholds: CheckedThresholds<T>,
    /// The online calibration's settings (the stage of
    /// [`Gains::online_calibration`](crate::Gains::online_calibration)).
    pub(crate) calibration: CheckedCalibration<T>,
    pub(crate) sin_cos: PhantomData<S>,
}

impl<T: Float, const N: usize, S: SinCos<T>> Gains<T, N, S> {
    /// The online-calibration settings.
    pub fn calibration_settings(&self) -> CalibrationSettings<T> {
        self.calibration.settings
    }

    /// The diagnostics thresholds.
    pub fn fault_thresholds(&self) -> FaultThresholds<T> {
        self.thresholds.thresholds
    }

    /// The coefficients `c` of the loop's characteristic polynomial in `s = z - 1`
    /// (`s^N + c[N-1] s^(N-1) + ... + c[0]`, lowest first): the inverse of
    /// [`Gains::from_loop_polynomial`].
    pub fn loop_polynomial(&self) -> [T; N] {
        T::characteristic_polynomial_in_s(&self.l)
    }

    /// The same gains with another sin/cos implementation in the phase detector.
    ///
    /// ```
    /// use angletrack_core::{Gains, Exact};
    /// let fast = Gains::<f32, 2>::new([0.05, 0.0012], 1e-4)?;
    /// let exact: Gains<f32, 2, Exact> = fast.with_sin_cos();
    /// assert_eq!(exact.gains(), fast.gains());
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn with_sin_cos<S2: SinCos<T>>(self) -> Gains<T, N, S2> {
        Gains {
            l: self.l,
            sample_period: self.sample_period,
            sample_rate: self.sample_rate,
            sample_rate_squared: self.sample_rate_squared,
            next_angle_gain: self.next_angle_gain,
            thresholds: self.thresholds,
            calibration: self.calibration,
            sin_cos: PhantomData,
        }
    }

    /// The discrete gains `(l1, l2[, l3])`.
    pub fn gains(&self) -> [T; N] {
        self.l
    }

    /// The sample period `Ts` (s).
    pub fn sample_period(&self) -> T {
        self.sample_period
    }

    /// The observer order `N` (2 or 3).
    pub const fn order(&self) -> usize {
        N
    }
}

#[cfg(test)]
mod tests;
