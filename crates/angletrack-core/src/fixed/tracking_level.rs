//! The fixed-point monitor's per-sample tracking-error level set away from its default
//! (`FaultThresholds::tracking_error`, raised above a noisy sensor's residual), in the Q15
//! the update compares.

use super::gains::FixedGains;
use crate::error::{ConfigError, Parameter};

/// The largest per-sample tracking-error level in Q15 ([`FixedGains::with_tracking_error`],
/// the 9th monitor word): the check's state stores its level in 16 bits, and the three
/// levels above (32765 to 32767) mark its start-up and a check not armed yet.
pub const MAX_TRACKING_ERROR_Q15: i32 = i16::MAX as i32 - 3;

impl<const N: usize> FixedGains<N> {
    /// The same gains with the monitor's per-sample tracking-error level set to `level`
    /// (a fraction, one sample's `|eps|`, as
    /// [`FaultThresholds::tracking_error`](crate::FaultThresholds::tracking_error): 0.05 by
    /// default), in Q15 rounded to nearest and released at half of it. Refused naming
    /// [`Parameter::TrackingErrorThreshold`]: a level that is not finite, not positive, or
    /// not held by the Q15 check (`ConfigError::OutOfRange`: rounding to 0, or above
    /// [`MAX_TRACKING_ERROR_Q15`] / 32768, about 0.9999, where the check's state marks its
    /// start-up). With the monitor off it has no effect (the level is still checked);
    /// [`FixedGains::with_monitor`] sets the default level with the others, so set this one
    /// after it.
    ///
    /// ```
    /// use angletrack_core::{FixedGains, Parameter};
    /// let gains = FixedGains::<2>::new([0.05, 0.0012], 1e-4)?.with_monitor(Some(28_000.0))?;
    /// // 8 times an angle noise of 0.01 (`FaultThresholds::with_tracking_error_above_noise`).
    /// let noisy = gains.with_tracking_error(0.08)?;
    /// assert_eq!(noisy.monitor_words()[8], 2621);
    /// assert_eq!(gains.monitor_words()[8], 1638);
    /// let err = gains.with_tracking_error(0.0).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::TrackingErrorThreshold);
    /// assert!(gains.with_tracking_error(1.0).is_err());
    ///
    /// // A firmware's static, checked when it compiles.
    /// static NOISY: FixedGains<2> = match FixedGains::<2>::from_constants(
    ///     angletrack_core::fixed::FixedConstants {
    ///         multiplier: [68_356_528, 1_640_557],
    ///         acceleration_shift: 0,
    ///     },
    ///     1e-4,
    /// ) {
    ///     Ok(gains) => match gains.with_tracking_error(0.08) {
    ///         Ok(gains) => gains,
    ///         Err(_) => panic!("the level is refused"),
    ///     },
    ///     Err(_) => panic!("unstable gains"),
    /// };
    /// assert_eq!(NOISY.monitor_words()[8], 2621);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn with_tracking_error(self, level: f64) -> Result<Self, ConfigError> {
        if !level.is_finite() {
            return Err(ConfigError::NotFinite(Parameter::TrackingErrorThreshold));
        }
        if level <= 0.0 {
            return Err(ConfigError::NotPositive(Parameter::TrackingErrorThreshold));
        }
        // Rounded to nearest (`as` saturates a level far beyond the range).
        let q15 = (level * 32768.0 + 0.5) as i32;
        if q15 < 1 || q15 > MAX_TRACKING_ERROR_Q15 {
            return Err(ConfigError::OutOfRange(Parameter::TrackingErrorThreshold));
        }
        let mut monitor = self.monitor;
        if monitor.enabled {
            monitor.tracking_error = q15;
        }
        Ok(Self { monitor, ..self })
    }
}
