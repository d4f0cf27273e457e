//! The tracker file's rules that its firmware exports (`firmware_rust`, `firmware_c`) and
//! its run ([`TrackerRun`](super::TrackerRun)) share: the fixed-point monitor's thresholds,
//! the rails of the ADC range rule, and the refusals of what a firmware cannot hold.

use angletrack_core::fixed::MAX_TRACKING_ERROR_Q15;
use angletrack_core::{ConfigError, FaultThresholds, FixedGains, Rails};

use super::{AdcRange, FirmwareError, Input, TrackerFile};
use crate::json_file::JsonFileError;

/// The fixed-point monitor's settings of a tracker file ([`TrackerFile::fixed_monitor`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct FixedMonitor {
    /// The nominal amplitude in the 16-bit samples.
    pub(super) amplitude: f64,
    /// The roundness tolerance (`None`: no roundness check).
    pub(super) tolerance: Option<f64>,
    /// The per-sample tracking-error level (`None`: the default, 0.05), the float
    /// monitor's `tracking_error`.
    pub(super) tracking_error: Option<f64>,
}

impl FixedMonitor {
    /// The monitor of `thresholds` measured on the capture, for counts shifted left by
    /// `shift`: the std's amplitude for its amplitude ([`fixed_monitor_amplitude`]), the
    /// floats' roundness check (none on a measured amplitude: the pair before any
    /// calibration need not be round; [`capture_fault_thresholds`]) where the fixed-point
    /// monitor can hold one ([`fixed_magnitude_tolerance`]), and the floats' tracking-error
    /// level.
    ///
    /// [`capture_fault_thresholds`]: crate::capture_fault_thresholds
    ///
    /// [`fixed_monitor_amplitude`]: crate::fixed_monitor_amplitude
    /// [`fixed_magnitude_tolerance`]: crate::fixed_magnitude_tolerance
    pub(super) fn measured(thresholds: &FaultThresholds<f64>, shift: u32) -> Self {
        let nominal = thresholds.nominal_amplitude;
        Self {
            amplitude: crate::fixed_monitor_amplitude(nominal, shift),
            tolerance: thresholds
                .magnitude_tolerance
                .filter(|_| crate::fixed_magnitude_tolerance(nominal, shift).is_some()),
            tracking_error: Self::level(thresholds),
        }
    }

    /// The tracking-error level of `thresholds` where it departs from the default.
    fn level(thresholds: &FaultThresholds<f64>) -> Option<f64> {
        let default = FaultThresholds::for_amplitude(thresholds.nominal_amplitude);
        (thresholds.tracking_error != default.tracking_error).then_some(thresholds.tracking_error)
    }

    /// `gains` with this monitor: its amplitude and tolerance, then its tracking-error
    /// level (after: `with_monitor_tolerance` sets the default one).
    pub(super) fn apply<const N: usize>(
        &self,
        gains: FixedGains<N>,
    ) -> Result<FixedGains<N>, ConfigError> {
        let gains = gains.with_monitor_tolerance(Some(self.amplitude), self.tolerance)?;
        match self.tracking_error {
            Some(level) => gains.with_tracking_error(level),
            None => Ok(gains),
        }
    }
}

/// A refusal naming the file's `field`.
pub(super) fn refuse(file: &str, field: &str, why: impl Into<String>) -> FirmwareError {
    FirmwareError::File(JsonFileError::new(file, Some(field), why.into()))
}

impl TrackerFile {
    /// The fixed-point monitor of the file's stated thresholds for counts shifted left by
    /// `shift` (`None` without thresholds). The fixed-point monitor takes the nominal
    /// amplitude, the roundness tolerance ([`FixedGains::with_monitor_tolerance`]) and the
    /// per-sample tracking-error level ([`FixedGains::with_tracking_error`]) only:
    /// another field away from the stated amplitude's default is refused, naming it. The
    /// amplitude in the 16-bit samples is the std's rule ([`fixed_monitor_amplitude`]);
    /// where it moved the amplitude into the monitor's range, the signal's magnitude is not
    /// the nominal one and no roundness check runs ([`fixed_magnitude_tolerance`]);
    /// elsewhere the file's `magnitude_tolerance`.
    ///
    /// [`fixed_monitor_amplitude`]: crate::fixed_monitor_amplitude
    /// [`fixed_magnitude_tolerance`]: crate::fixed_magnitude_tolerance
    pub(super) fn fixed_monitor(
        &self,
        file: &str,
        shift: u32,
    ) -> Result<Option<FixedMonitor>, FirmwareError> {
        let Some(th) = &self.fault_thresholds else {
            return Ok(None);
        };
        let d = FaultThresholds::for_amplitude(th.nominal_amplitude);
        let departs = [
            (
                "max_input_amplitude",
                th.max_input_amplitude != d.max_input_amplitude,
            ),
            ("loss_of_signal", th.loss_of_signal != d.loss_of_signal),
            ("degradation_low", th.degradation_low != d.degradation_low),
            (
                "degradation_high",
                th.degradation_high != d.degradation_high,
            ),
            (
                "loss_of_tracking",
                th.loss_of_tracking != d.loss_of_tracking,
            ),
            ("max_speed_rad_s", th.max_speed != d.max_speed),
            ("filter_factor", th.filter_factor != d.filter_factor),
            ("false_lock", th.false_lock != d.false_lock),
            ("monitor", th.monitor != d.monitor),
            ("re_acquire", th.re_acquire != d.re_acquire),
        ];
        if let Some((field, _)) = departs.iter().find(|(_, departs)| *departs) {
            return Err(refuse(
                file,
                &format!("fault_thresholds.{field}"),
                "the fixed-point monitor takes nominal_amplitude, magnitude_tolerance and \
                 tracking_error only: leave it out (its default for the nominal amplitude)",
            ));
        }
        let tracking_error = FixedMonitor::level(th);
        if let Some(level) = tracking_error {
            let q15 = (level * 32768.0).round();
            if !(1.0..=f64::from(MAX_TRACKING_ERROR_Q15)).contains(&q15) {
                return Err(refuse(
                    file,
                    "fault_thresholds.tracking_error",
                    format!(
                        "the fixed-point monitor holds the level in Q15: from 2^-16 to {}/32768",
                        MAX_TRACKING_ERROR_Q15
                    ),
                ));
            }
        }
        // The default tolerance is the rule's (0.1 in `f64`, where the file's default is the
        // `f32` value the floats share).
        let rule = crate::fixed_magnitude_tolerance(th.nominal_amplitude, shift);
        Ok(Some(FixedMonitor {
            amplitude: crate::fixed_monitor_amplitude(th.nominal_amplitude, shift),
            tolerance: if th.magnitude_tolerance == d.magnitude_tolerance {
                rule
            } else {
                rule.and(th.magnitude_tolerance)
            },
            tracking_error,
        }))
    }

    /// The refusal of counts tracked as counts without their amplitude (the std's rule for
    /// a stream, `ThresholdPolicy`).
    pub(super) fn amplitude_not_stated(file: &str) -> FirmwareError {
        refuse(
            file,
            "fault_thresholds",
            "counts tracked as counts need the signal's amplitude stated for the diagnostics: \
             give fault_thresholds (a firmware sees no whole capture)",
        )
    }

    /// The refusal of counts whose mid-scale is measured (a run-time measurement).
    pub(super) fn measured_mid_scale(&self, file: &str) -> FirmwareError {
        refuse(
            file,
            "input",
            "counts with the mid-scale measured on the capture: state the ADC's bits (and signedness) or its mid_scale",
        )
    }

    /// The rails in codes (counts) and in units, from the file's ADC range rule.
    pub(super) fn rails(
        &self,
        file: &str,
        counts: bool,
    ) -> Result<(Rails<i32>, Rails<f64>), FirmwareError> {
        Ok(match (self.adc_range, self.input) {
            (AdcRange::Measured, _) => (Rails::Measured, Rails::Measured),
            (AdcRange::FullScale, Input::Bits { bits, signed }) => (
                Rails::of_adc_bits(bits, signed)
                    .map_err(|e| refuse(file, "input.bits", e.to_string()))?,
                Rails::Unchecked,
            ),
            (AdcRange::FullScale, _) => {
                return Err(refuse(
                    file,
                    "adc_range.rule",
                    "\"full_scale\" needs the ADC's bits (input.bits)",
                ));
            }
            (AdcRange::Stated { min, max }, _) if counts => {
                let code = |v: f64| {
                    (v.fract() == 0.0 && v.abs() <= f64::from(i32::MAX)).then_some(v as i32)
                };
                match (code(min), code(max)) {
                    (Some(min), Some(max)) => (Rails::Stated { min, max }, Rails::Unchecked),
                    _ => {
                        return Err(refuse(
                            file,
                            "adc_range",
                            "an ADC's range is in whole codes",
                        ));
                    }
                }
            }
            (AdcRange::Stated { min, max }, _) => (Rails::Unchecked, Rails::Stated { min, max }),
        })
    }
}
