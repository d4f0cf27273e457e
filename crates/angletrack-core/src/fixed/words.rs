//! The fixed-point observer built from its words alone: the integers [`FixedGains::new`]
//! and [`FixedGains::with_monitor`] compute, checked by integer comparisons only, so that a
//! core without an FPU (or a C firmware's start-up) builds it without any floating-point
//! arithmetic.

use super::gains::{FixedConstants, FixedGains, FixedThresholds};
use crate::error::{ConfigError, Parameter};
use crate::gains::{Order, SupportedOrder};

/// The words of the fixed-point monitor's thresholds, in the order of
/// [`FixedGains::monitor_words`]: enabled (0 or 1), loss of signal, degradation low and
/// high, roundness low and high (half square amplitudes, counts^2), loss of tracking (the
/// window's sum of `|eps|` in Q15), the largest speed (2^-32 turn per sample), the
/// per-sample tracking-error level (one sample's `|eps|` in Q15, 1 to
/// [`MAX_TRACKING_ERROR_Q15`]: 1638, 0.05, by default; [`FixedGains::with_tracking_error`]).
///
/// [`MAX_TRACKING_ERROR_Q15`]: super::MAX_TRACKING_ERROR_Q15
pub type FixedMonitorWords = [u32; 9];

/// The sign bit of an `f64`.
const SIGN: u64 = 1 << 63;
/// The bits of `f64::INFINITY`: at or above them (without the sign), not finite.
const INFINITY_BITS: u64 = 0x7ff0_0000_0000_0000;

/// `sample_period_s` checked by its bits: finite (not NaN or infinite), then positive (not
/// zero, not negative).
pub(super) const fn check_sample_period(sample_period_s: f64) -> Result<(), ConfigError> {
    let bits = sample_period_s.to_bits();
    if bits & !SIGN >= INFINITY_BITS {
        return Err(ConfigError::NotFinite(Parameter::SamplePeriod));
    }
    if bits & SIGN != 0 || bits == 0 {
        return Err(ConfigError::NotPositive(Parameter::SamplePeriod));
    }
    Ok(())
}

impl<const N: usize> FixedGains<N>
where
    Order<N>: SupportedOrder,
{
    /// The observer of the integer `constants` at `sample_period_s` (s) with the monitor's
    /// threshold words `monitor` ([`FixedMonitorWords`]), as [`FixedGains::constants`] and
    /// [`FixedGains::monitor_words`] give them: what `angletrack export --format c` writes
    /// for a firmware. Checked by integer comparisons only (the sample period by its
    /// bits): the ranges of [`FixedGains::from_constants`] and thresholds in order, each
    /// refusal naming the parameter (with the monitor on, a tracking-error level from 1 to
    /// [`MAX_TRACKING_ERROR_Q15`]; with it off, that word is not read). The loop's
    /// stability is a float computation, so it is not checked again here: take words a
    /// checked [`FixedGains`] gave.
    ///
    /// [`MAX_TRACKING_ERROR_Q15`]: crate::fixed::MAX_TRACKING_ERROR_Q15
    ///
    /// ```
    /// use angletrack_core::{FixedGains, Parameter};
    /// let designed = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?
    ///     .with_monitor(Some(28_800.0))?;
    /// static GAINS: FixedGains<3> = match FixedGains::from_words(
    ///     angletrack_core::fixed::FixedConstants {
    ///         multiplier: [215_733_201, 17_225_845, 1_903_920_691],
    ///         acceleration_shift: 3,
    ///     },
    ///     50e-6,
    ///     [
    ///         1, 25_920_000, 103_680_000, 933_120_000, 335_923_200, 501_811_200, 104_864,
    ///         1 << 30, 1638,
    ///     ],
    /// ) {
    ///     Ok(gains) => gains,
    ///     Err(_) => panic!("the fixed-point words are refused"),
    /// };
    /// assert_eq!(GAINS, designed);
    /// let mut low_above_high = designed.monitor_words();
    /// low_above_high[2] = low_above_high[3] + 1;
    /// let err = FixedGains::from_words(designed.constants(), 50e-6, low_above_high).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::DegradationLowThreshold);
    /// let mut beyond_q15 = designed.monitor_words();
    /// beyond_q15[8] = 40_000;
    /// let err = FixedGains::from_words(designed.constants(), 50e-6, beyond_q15).unwrap_err();
    /// assert_eq!(err.parameter(), Parameter::TrackingErrorThreshold);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn from_words(
        constants: FixedConstants<N>,
        sample_period_s: f64,
        monitor: FixedMonitorWords,
    ) -> Result<Self, ConfigError> {
        let gains = match Self::checked_constants(constants, sample_period_s) {
            Ok(gains) => gains,
            Err(e) => return Err(e),
        };
        let [
            enabled,
            loss_of_signal,
            low,
            high,
            round_low,
            round_high,
            loss_of_tracking,
            max_speed,
            tracking_error,
        ] = monitor;
        let refused = if enabled > 1 {
            Some(Parameter::NominalAmplitude)
        } else if loss_of_signal > low {
            Some(Parameter::LossOfSignalThreshold)
        } else if low > high {
            Some(Parameter::DegradationLowThreshold)
        } else if round_low > round_high {
            Some(Parameter::MagnitudeTolerance)
        } else if loss_of_tracking > i32::MAX as u32 {
            Some(Parameter::LossOfTrackingThreshold)
        } else if enabled == 1
            && (tracking_error < 1 || tracking_error > super::MAX_TRACKING_ERROR_Q15 as u32)
        {
            Some(Parameter::TrackingErrorThreshold)
        } else {
            None
        };
        if let Some(parameter) = refused {
            return Err(ConfigError::OutOfRange(parameter));
        }
        let monitor = FixedThresholds {
            enabled: enabled == 1,
            loss_of_signal,
            degradation_low: low,
            degradation_high: high,
            round_low,
            round_high,
            loss_of_tracking,
            max_speed,
            // With the monitor off, no level (the word is not read).
            tracking_error: if enabled == 1 {
                tracking_error as i32
            } else {
                FixedThresholds::OFF.tracking_error
            },
        };
        Ok(Self { monitor, ..gains })
    }

    /// The monitor's threshold words ([`FixedMonitorWords`]), for
    /// [`FixedGains::from_words`].
    pub const fn monitor_words(&self) -> FixedMonitorWords {
        let m = &self.monitor;
        [
            m.enabled as u32,
            m.loss_of_signal,
            m.degradation_low,
            m.degradation_high,
            m.round_low,
            m.round_high,
            m.loss_of_tracking,
            m.max_speed,
            m.tracking_error as u32,
        ]
    }
}
