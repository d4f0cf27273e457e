//! [`Gains`]: the immutable, checked configuration of an observer, and the orders it may
//! have. Everything is checked here, once, so that the per-sample update never fails:
//! finite values, a physical sample period, gains inside the stability region of the
//! discrete loop (`docs/theory.md §6`) and consistent fault thresholds.

use core::marker::PhantomData;

use crate::calibration_settings::CheckedCalibration;
use crate::error::ConfigError;
use crate::monitor::{CheckedThresholds, FaultThresholds};
use crate::real::Real;
use crate::sincos::SinCos;
use crate::stability::{characteristic_polynomial_in_s, gains_of_loop_polynomial};

/// The orders the recursion supports: 2 (type II loop) and 3 (type III loop).
///
/// Implemented for [`Order<2>`] and [`Order<3>`] only. It bounds the constructors of
/// [`Gains`], the only place where the order's mathematics (the stability conditions) is
/// specific to 2 and 3: an observer of any other order cannot be made, and the update,
/// written for any `N`, needs no bound.
pub trait SupportedOrder: sealed::Sealed {}

/// Marker for the observer order `N` (the number of states: angle, speed, acceleration).
#[derive(Debug, Clone, Copy)]
pub struct Order<const N: usize>;

impl SupportedOrder for Order<2> {}
impl SupportedOrder for Order<3> {}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Order<2> {}
    impl Sealed for super::Order<3> {}
}

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
pub struct Gains<T: Real, const N: usize, S = <T as Real>::DefaultSinCos> {
    pub(crate) l: [T; N],
    pub(crate) sample_period: T,
    pub(crate) sample_rate: T,
    pub(crate) sample_rate_squared: T,
    /// `(A L)[0] = l1 + l2 + l3/2`: how much one sample's phase error moves the next
    /// sample's predicted angle.
    pub(crate) next_angle_gain: T,
    pub(crate) thresholds: CheckedThresholds<T>,
    /// The online calibration's settings (used by
    /// [`Gains::update_calibrated`](crate::Gains::update_calibrated) only).
    pub(crate) calibration: CheckedCalibration<T>,
    pub(crate) sin_cos: PhantomData<S>,
}

impl<T: Real, const N: usize, S: SinCos<T>> Gains<T, N, S>
where
    Order<N>: SupportedOrder,
{
    /// Checks and wraps discrete gains `gains` (dimensionless, for the scaled state) and the
    /// sample period `sample_period_s` (s).
    ///
    /// Refuses non-finite values, a non-positive sample period or one outside
    /// [1 ps, 1000 s], and gains outside the stability region of the discrete loop (see
    /// [`ConfigError`]).
    ///
    /// ```
    /// use angletrack_core::{Gains, ConfigError, Parameter};
    /// // A 3rd-order loop at 20 kHz (gains from `angletrack design`).
    /// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 50e-6)?;
    /// assert_eq!(gains.sample_period(), 50e-6);
    /// // l3 <= 0 is outside the stability region:
    /// let err = Gains::<f32, 3>::new([0.3, 0.04, -0.002], 50e-6).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::AccelerationGain);
    /// # Ok::<(), ConfigError>(())
    /// ```
    pub fn new(gains: [T; N], sample_period_s: T) -> Result<Self, ConfigError> {
        // The checks are `const fn`s, shared with `Gains::new_const` (`const_config.rs`).
        T::new_gains(gains, sample_period_s)
    }

    /// Gains that give the discrete loop `(I - L e1^T) A` a chosen characteristic polynomial,
    /// written in `s = z - 1` as `s^N + c[N-1] s^(N-1) + ... + c[0]` (for poles `z_i`,
    /// the coefficients of `prod (s - (z_i - 1))`), lowest coefficient first. This is how
    /// pole matching (`z_i = exp(s_i Ts)`, `docs/theory.md §7`) reaches the recursion;
    /// writing the polynomial in `z - 1` keeps it accurate at high sample rates, where every
    /// `z_i` is close to 1.
    ///
    /// The map from gains to coefficients is linear and triangular; this solves it and then
    /// checks the result as [`Gains::new`] does.
    ///
    /// ```
    /// use angletrack_core::Gains;
    /// // Triple pole at z = 0.9: (s + 0.1)^3 = s^3 + 0.3 s^2 + 0.03 s + 0.001.
    /// let gains = Gains::<f64, 3>::from_loop_polynomial([0.001, 0.03, 0.3], 1e-4)?;
    /// let [l1, l2, l3] = gains.gains();
    /// assert!((l3 - 0.001).abs() < 1e-15 && (l2 - 0.0285).abs() < 1e-15);
    /// assert!((l1 - 0.271).abs() < 1e-15);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn from_loop_polynomial(
        coefficients: [T; N],
        sample_period_s: T,
    ) -> Result<Self, ConfigError> {
        Self::new(gains_of_loop_polynomial(&coefficients), sample_period_s)
    }
}

impl<T: Real, const N: usize, S: SinCos<T>> Gains<T, N, S> {
    /// The same gains with other diagnostics thresholds (checked: see
    /// [`FaultThresholds`]); the defaults assume a nominal amplitude of 1.
    ///
    /// ```
    /// use angletrack_core::{FaultThresholds, Gains, Parameter};
    /// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 1e-4)?
    ///     .with_fault_thresholds(FaultThresholds::for_amplitude(2048.0))?;
    /// assert_eq!(gains.fault_thresholds().nominal_amplitude, 2048.0);
    /// let mut bad = FaultThresholds::default();
    /// bad.filter_factor = 1.5;
    /// let err = gains.with_fault_thresholds(bad).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::FilterFactor);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn with_fault_thresholds(
        self,
        thresholds: FaultThresholds<T>,
    ) -> Result<Self, ConfigError> {
        Ok(Self {
            thresholds: thresholds.check(self.sample_period)?,
            ..self
        })
    }

    /// The diagnostics thresholds.
    pub fn fault_thresholds(&self) -> FaultThresholds<T> {
        self.thresholds.thresholds
    }

    /// The coefficients `c` of the loop's characteristic polynomial in `s = z - 1`
    /// (`s^N + c[N-1] s^(N-1) + ... + c[0]`, lowest first): the inverse of
    /// [`Gains::from_loop_polynomial`].
    pub fn loop_polynomial(&self) -> [T; N] {
        characteristic_polynomial_in_s(&self.l)
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
