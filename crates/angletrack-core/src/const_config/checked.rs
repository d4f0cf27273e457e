//! The checked constructors of the configurations, generic over [`Real`]: each reaches the
//! `const fn` checks of its float type through [`ConstChecks`], so that the generic and the
//! `const` constructors (`const_config.rs`) share one implementation.

use crate::calibration_settings::{CalibrationSettings, CheckedCalibration};
use crate::const_config::Real;
use crate::error::ConfigError;
use crate::gains::{Gains, Order, SupportedOrder};
use crate::monitor::{CheckedThresholds, FaultThresholds};
use crate::real::sincos::SinCos;

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
        Self::new(T::gains_of_loop_polynomial(&coefficients), sample_period_s)
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

    /// The same gains with other online-calibration settings (checked: see
    /// [`CalibrationSettings`]).
    ///
    /// ```
    /// use angletrack_core::{CalibrationSettings, Gains, Parameter};
    /// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 1e-4)?
    ///     .with_calibration_settings({
    ///         let mut s = CalibrationSettings::default();
    ///         s.min_speed_rad_s = Some(50.0);
    ///         s
    ///     })?;
    /// assert_eq!(gains.calibration_settings().min_speed_rad_s, Some(50.0));
    /// let mut slow = CalibrationSettings::default();
    /// slow.min_speed_rad_s = Some(1e-3);
    /// let err = gains.with_calibration_settings(slow).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::MinSpeed);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn with_calibration_settings(
        self,
        settings: CalibrationSettings<T>,
    ) -> Result<Self, ConfigError> {
        Ok(Self {
            calibration: settings.check(self.sample_period)?,
            ..self
        })
    }
}

impl<T: Real> Default for FaultThresholds<T> {
    /// The thresholds of amplitude 1 without the roundness check (no amplitude stated:
    /// [`FaultThresholds::magnitude_tolerance`]).
    fn default() -> Self {
        Self {
            magnitude_tolerance: None,
            ..Self::for_amplitude(T::ONE)
        }
    }
}

impl<T: Real> FaultThresholds<T> {
    /// The default thresholds (see the table above) with the amplitude checks scaled to a
    /// nominal amplitude (in the units of `y_c`, `y_s`); the loss-of-tracking threshold is
    /// dimensionless and stays 0.1.
    ///
    /// ```
    /// use angletrack_core::FaultThresholds;
    /// // Raw 12-bit ADC counts with the mid-scale removed, amplitude about 1800 counts.
    /// let t = FaultThresholds::<f32>::for_amplitude(1800.0);
    /// assert_eq!(t.loss_of_signal, 450.0);
    /// assert_eq!(t.loss_of_tracking, 0.1);
    /// ```
    pub fn for_amplitude(nominal_amplitude: T) -> Self {
        T::thresholds_for_amplitude(nominal_amplitude)
    }

    /// No diagnostics and no re-acquisition, only the input check: the bare loop of the
    /// paper (use it to study the loop's own large-signal behaviour).
    ///
    /// ```
    /// use angletrack_core::FaultThresholds;
    /// let t = FaultThresholds::<f64>::disabled();
    /// assert!(!t.monitor && !t.re_acquire);
    /// ```
    pub fn disabled() -> Self {
        Self {
            monitor: false,
            re_acquire: false,
            ..Self::default()
        }
    }

    /// Checks the thresholds: all finite and positive (the false-lock threshold may be
    /// zero or negative, within the nominal amplitude), ordered
    /// `loss_of_signal < degradation_low < nominal < degradation_high <= max_input`,
    /// filter factor in (0, 1]. Returns the squared-amplitude form used per sample.
    pub(crate) fn check(&self, sample_period_s: T) -> Result<CheckedThresholds<T>, ConfigError> {
        T::check_thresholds(self, sample_period_s)
    }
}

impl<T: Real> Default for CalibrationSettings<T> {
    fn default() -> Self {
        T::default_calibration_settings()
    }
}

impl<T: Real> CalibrationSettings<T> {
    /// Checks the settings for the sample period `sample_period_s`: every bound finite and
    /// positive, the minimum speed within its range.
    pub(crate) fn check(&self, sample_period_s: T) -> Result<CheckedCalibration<T>, ConfigError> {
        T::check_calibration_settings(self, sample_period_s)
    }
}

impl<T: Real> crate::chain::OnlineCalibration<T> {
    /// The online calibration with `settings`, checked for the observer's sample period
    /// `sample_period_s` (s): see [`CalibrationSettings`].
    ///
    /// ```
    /// use angletrack_core::{CalibrationSettings, OnlineCalibration, Parameter};
    /// let online = OnlineCalibration::<f32>::new(CalibrationSettings::default(), 1e-4)?;
    /// assert_eq!(online.settings(), CalibrationSettings::default());
    /// let mut slow = CalibrationSettings::default();
    /// slow.min_speed_rad_s = Some(1e-3);
    /// let err = OnlineCalibration::<f32>::new(slow, 1e-4).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::MinSpeed);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new(settings: CalibrationSettings<T>, sample_period_s: T) -> Result<Self, ConfigError> {
        Ok(Self {
            checked: settings.check(sample_period_s)?,
        })
    }
}
