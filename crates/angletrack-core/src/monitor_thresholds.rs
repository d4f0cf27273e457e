//! The builder of [`FaultThresholds`]: code outside this crate cannot write the
//! `#[non_exhaustive]` struct as a literal, so it starts from
//! [`FaultThresholds::for_amplitude`] and sets each other field by name with these
//! `const fn`s (usable for a `static` in firmware). Nothing is checked here: the thresholds
//! are checked where an observer's configuration takes them
//! ([`Gains::with_fault_thresholds`](crate::Gains::with_fault_thresholds)), with the
//! [`ConfigError`](crate::ConfigError) naming the parameter.

use crate::monitor::{DEFAULT_TRACKING_ERROR, FaultThresholds};
use crate::real::Float;

/// The loss-of-tracking level in standard deviations of the input's angle noise (the rule
/// of [`FaultThresholds::with_tracking_error_above_noise`]): a residual of healthy Gaussian
/// noise exceeds 8 of its standard deviations about once in 10^15 samples, so a healthy
/// sensor is not flagged.
pub const TRACKING_ERROR_NOISE_FACTOR: f32 = 8.0;

impl<T: Copy> FaultThresholds<T> {
    /// The same thresholds with [`FaultThresholds::max_input_amplitude`] set (units of
    /// `y_c`, `y_s`). Every setter works alike; a value out of range is refused by
    /// [`Gains::with_fault_thresholds`](crate::Gains::with_fault_thresholds), naming it:
    ///
    /// ```
    /// use angletrack_core::{FaultThresholds, Gains, Parameter};
    /// // Raw ADC counts with the mid-scale removed, amplitude about 1800 counts.
    /// let thresholds = FaultThresholds::<f32>::for_amplitude(1800.0)
    ///     .with_max_input_amplitude(2047.0)
    ///     .with_loss_of_signal(300.0)
    ///     .with_degradation_low(1000.0)
    ///     .with_degradation_high(2000.0)
    ///     .with_loss_of_tracking(0.05)
    ///     .with_max_speed(Some(3000.0))
    ///     .with_filter_factor(1.0 / 32.0)
    ///     .with_false_lock(0.0)
    ///     .with_monitor(true)
    ///     .with_re_acquire(false);
    /// assert_eq!((thresholds.loss_of_signal, thresholds.max_speed), (300.0, Some(3000.0)));
    /// let gains = Gains::<f32, 3>::new([0.3, 0.04, 0.002], 1e-4)?
    ///     .with_fault_thresholds(thresholds)?;
    /// assert_eq!(gains.fault_thresholds(), thresholds);
    /// let below_nominal = thresholds.with_degradation_high(1700.0);
    /// let err = gains.with_fault_thresholds(below_nominal).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::DegradationHighThreshold);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn with_max_input_amplitude(mut self, max_input_amplitude: T) -> Self {
        self.max_input_amplitude = max_input_amplitude;
        self
    }

    /// The same thresholds with [`FaultThresholds::loss_of_signal`] set (units of `y_c`,
    /// `y_s`); see [`FaultThresholds::with_max_input_amplitude`] for an example.
    pub const fn with_loss_of_signal(mut self, loss_of_signal: T) -> Self {
        self.loss_of_signal = loss_of_signal;
        self
    }

    /// The same thresholds with [`FaultThresholds::degradation_low`] set (units of `y_c`,
    /// `y_s`); see [`FaultThresholds::with_max_input_amplitude`] for an example.
    pub const fn with_degradation_low(mut self, degradation_low: T) -> Self {
        self.degradation_low = degradation_low;
        self
    }

    /// The same thresholds with [`FaultThresholds::degradation_high`] set (units of `y_c`,
    /// `y_s`); see [`FaultThresholds::with_max_input_amplitude`] for an example.
    pub const fn with_degradation_high(mut self, degradation_high: T) -> Self {
        self.degradation_high = degradation_high;
        self
    }

    /// The same thresholds with [`FaultThresholds::loss_of_tracking`] set (dimensionless);
    /// see [`FaultThresholds::with_max_input_amplitude`] for an example.
    pub const fn with_loss_of_tracking(mut self, loss_of_tracking: T) -> Self {
        self.loss_of_tracking = loss_of_tracking;
        self
    }

    /// The same thresholds with [`FaultThresholds::tracking_error`] set (dimensionless: one
    /// sample's `|eps|`, about the sine of its angle error, electrical); a value that is not
    /// positive and finite is refused naming `tracking_error`:
    ///
    /// ```
    /// use angletrack_core::{FaultThresholds, Gains, Parameter};
    /// let gains = Gains::<f32, 2>::new([0.05, 0.0012], 1e-4)?;
    /// let tight = FaultThresholds::<f32>::for_amplitude(1.0).with_tracking_error(0.02);
    /// assert_eq!(gains.with_fault_thresholds(tight)?.fault_thresholds().tracking_error, 0.02);
    /// let err = gains.with_fault_thresholds(tight.with_tracking_error(0.0)).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::TrackingErrorThreshold);
    /// assert_eq!(err.parameter().name(), "tracking_error");
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn with_tracking_error(mut self, tracking_error: T) -> Self {
        self.tracking_error = tracking_error;
        self
    }

    /// The same thresholds with [`FaultThresholds::max_speed`] set (rad/s; `None`: a
    /// quarter turn per sample); see [`FaultThresholds::with_max_input_amplitude`] for an
    /// example.
    pub const fn with_max_speed(mut self, max_speed_rad_s: Option<T>) -> Self {
        self.max_speed = max_speed_rad_s;
        self
    }

    /// The same thresholds with [`FaultThresholds::filter_factor`] set (`1 / W` for a
    /// window of `W` used samples); see [`FaultThresholds::with_max_input_amplitude`] for an
    /// example.
    pub const fn with_filter_factor(mut self, filter_factor: T) -> Self {
        self.filter_factor = filter_factor;
        self
    }

    /// The same thresholds with [`FaultThresholds::false_lock`] set (units of `y_c`,
    /// `y_s`); see [`FaultThresholds::with_max_input_amplitude`] for an example.
    pub const fn with_false_lock(mut self, false_lock: T) -> Self {
        self.false_lock = false_lock;
        self
    }

    /// The same thresholds with [`FaultThresholds::magnitude_tolerance`] set (a fraction of
    /// the nominal amplitude; `None`: no roundness check); see
    /// [`FaultThresholds::with_max_input_amplitude`] for an example.
    pub const fn with_magnitude_tolerance(mut self, magnitude_tolerance: Option<T>) -> Self {
        self.magnitude_tolerance = magnitude_tolerance;
        self
    }

    /// The same thresholds with [`FaultThresholds::monitor`] set (whether the flags are
    /// computed); see [`FaultThresholds::with_max_input_amplitude`] for an example.
    pub const fn with_monitor(mut self, monitor: bool) -> Self {
        self.monitor = monitor;
        self
    }

    /// The same thresholds with [`FaultThresholds::re_acquire`] set (whether a false lock
    /// re-acquires the angle); see [`FaultThresholds::with_max_input_amplitude`] for an
    /// example.
    pub const fn with_re_acquire(mut self, re_acquire: bool) -> Self {
        self.re_acquire = re_acquire;
        self
    }
}

impl<T: Float> FaultThresholds<T> {
    /// The same thresholds with [`FaultThresholds::tracking_error`] set above the noise of
    /// the input's angle, as a mature RDC sets its loss-of-tracking level above its noise
    /// floor: [`TRACKING_ERROR_NOISE_FACTOR`] (8) times `angle_noise_rad`, the standard
    /// deviation of one sample's angle about the smooth motion (rad electrical; for Gaussian
    /// noise of standard deviation `s` per channel on a signal of amplitude `a`, about
    /// `s / a`), and never below the default 0.05. A noise that is not finite or not
    /// positive leaves the thresholds as they are. The residual `|eps|` a healthy sample
    /// shows is about its angle noise, so a sensor of any noise keeps the check clear; up
    /// to 0.6 % noise the level stays the default.
    ///
    /// What the `angletrack` crate applies to the thresholds it measures on a capture
    /// (`capture_fault_thresholds`) when the caller states none:
    ///
    /// ```
    /// use angletrack_core::FaultThresholds;
    /// let t = FaultThresholds::<f32>::for_amplitude(1800.0);
    /// // 1 % noise: 8 times 0.01.
    /// assert_eq!(t.with_tracking_error_above_noise(0.01).tracking_error, 0.08);
    /// // 0.25 % noise: the default.
    /// assert_eq!(t.with_tracking_error_above_noise(0.0025).tracking_error, 0.05);
    /// assert_eq!(t.with_tracking_error_above_noise(f32::NAN), t);
    /// ```
    pub fn with_tracking_error_above_noise(self, angle_noise_rad: T) -> Self {
        if !(angle_noise_rad > T::ZERO && angle_noise_rad < T::INFINITY) {
            return self;
        }
        let level = T::from_f32(TRACKING_ERROR_NOISE_FACTOR) * angle_noise_rad;
        self.with_tracking_error(level.max(T::from_f32(DEFAULT_TRACKING_ERROR)))
    }
}
