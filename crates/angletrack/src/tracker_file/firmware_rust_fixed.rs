//! A fixed-point tracker file as one Rust `static` (`TrackerFile::rust_tracker` for
//! `number_type` `"fixed"`): the core's [`Tracker`](angletrack_core::Tracker) of
//! [`FixedGains`] on 16-bit samples, built by its `const` constructors.

use angletrack_core::{
    FixedGains, Input as CoreInput, Order, Rails, SupportedOrder, TrackerFrontEnd, TrackerSettings,
};

use super::firmware_rust::{input_text, sensor_text};
use super::rules::refuse;
use super::{FirmwareError, TrackerFile};
use crate::export::{FloatType, literal};

impl TrackerFile {
    /// The fixed-point chain's type and initialiser.
    pub(super) fn fixed_tracker(&self, file: &str) -> Result<(String, String), FirmwareError> {
        let n = self.gains.gains.len();
        let period = literal(
            self.gains.sample_period_s,
            FloatType::F64,
            "sample_period_s",
        )?;
        let constants = match *self.gains.gains.as_slice() {
            [a, b] => fixed_constants::<2>([a, b], self.gains.sample_period_s),
            [a, b, c] => fixed_constants::<3>([a, b, c], self.gains.sample_period_s),
            _ => return Err(refuse(file, "gains", "2 or 3 gains (the observer's order)")),
        }
        .map_err(|e| refuse(file, "gains", e))?;
        if self.winding_amplitude.is_some() {
            return Err(refuse(
                file,
                "winding_check",
                "the fixed-point chain has none: leave it null",
            ));
        }
        // The std's rule for counts (`fixed_input`): shifted to 16 bits, the calibration
        // (learned on the counts before the shift) scaled with them.
        let counts = self.fixed_counts(file)?;
        let (input, adc, shift) = match counts {
            None => (None, None, 0),
            Some(c) => {
                let kind = if c.signed {
                    "twos_complement"
                } else {
                    "offset_binary"
                };
                let bits = 16 - c.shift;
                (
                    Some(format!("AdcCounts::{kind}({bits})")),
                    Some(c.adc),
                    c.shift,
                )
            }
        };
        let rails = self.rails(file, adc.is_some())?;
        let units_rails = match rails.1 {
            Rails::Stated { min, max } => {
                let fits = |v: f64| v.fract() == 0.0 && (-32768.0..=32767.0).contains(&v);
                if !(fits(min) && fits(max)) {
                    return Err(refuse(
                        file,
                        "adc_range",
                        "the fixed-point samples' range is in 16-bit integers",
                    ));
                }
                Rails::Stated {
                    min: min as i16,
                    max: max as i16,
                }
            }
            Rails::Measured => Rails::Measured,
            Rails::Unchecked => Rails::Unchecked,
        };
        let core_input = match adc {
            Some(adc) => CoreInput::Counts {
                adc,
                rails: rails.0,
            },
            None => CoreInput::Units { rails: units_rails },
        };
        TrackerFrontEnd::<i16>::new(TrackerSettings {
            input: core_input,
            ..TrackerSettings::default()
        })
        .map_err(|e| refuse(file, "adc_range", e.to_string()))?;
        let input_text = input_text(input, rails.0, units_rails, |v| {
            Ok::<_, FirmwareError>(v.to_string())
        })?;
        let calibration = match self
            .fixed_calibration(file, shift)
            .map_err(FirmwareError::File)?
        {
            None => "None".to_string(),
            Some((shifted, _)) => format!(
                "Some(ok(FixedCalibration::new_const(&{})))",
                sensor_text("f64", &shifted, FloatType::F64)?
            ),
        };
        let table = self.fixed_correction(file).map_err(FirmwareError::File)?;
        let correction = match table {
            None => "None".to_string(),
            Some(table) => {
                let entries: Vec<String> = table.errors_q15().iter().map(i16::to_string).collect();
                format!(
                    "Some(ok(FixedAngleCorrectionTable::new([{}])))",
                    entries.join(", ")
                )
            }
        };
        let multipliers: Vec<String> = constants.0.iter().map(i32::to_string).collect();
        let mut observer = format!(
            "ok(FixedGains::from_constants(\n            fixed::FixedConstants {{ multiplier: \
             [{}], acceleration_shift: {} }},\n            {period},\n        ))",
            multipliers.join(", "),
            constants.1
        );
        match (self.fixed_monitor(file, shift)?, adc.is_some()) {
            (Some(monitor), _) => {
                let samples = literal(
                    monitor.amplitude,
                    FloatType::F64,
                    "fault_thresholds.nominal_amplitude",
                )?;
                observer = match monitor.tolerance {
                    // `with_monitor`'s tolerance.
                    Some(0.1) => format!("ok({observer}.with_monitor(Some({samples})))"),
                    Some(r) => format!(
                        "ok({observer}.with_monitor_tolerance(Some({samples}), Some({})))",
                        literal(r, FloatType::F64, "fault_thresholds.magnitude_tolerance")?
                    ),
                    None => format!("ok({observer}.with_monitor_tolerance(Some({samples}), None))"),
                };
                // After the monitor, which sets the default level.
                if let Some(level) = monitor.tracking_error {
                    let level = literal(level, FloatType::F64, "fault_thresholds.tracking_error")?;
                    observer = format!("ok({observer}.with_tracking_error({level}))");
                }
            }
            (None, true) => return Err(Self::amplitude_not_stated(file)),
            (None, false) => {}
        }
        let ty = format!("angletrack_core::Tracker<i16, angletrack_core::FixedGains<{n}>>");
        let body = format!(
            "    Tracker::new(\n        ok(TrackerFrontEnd::<i16>::new_const(TrackerSettings {{\n            \
             input: {input_text},\n            winding: (),\n            calibration: {calibration},\n            \
             correction: {correction},\n        }})),\n        {observer},\n    )\n"
        );
        Ok((ty, body))
    }
}

/// The fixed-point gains' constants, checked by [`FixedGains::new`].
fn fixed_constants<const N: usize>(gains: [f64; N], period: f64) -> Result<(Vec<i32>, u32), String>
where
    Order<N>: SupportedOrder,
{
    let constants = FixedGains::<N>::new(gains, period)
        .map_err(|e| e.to_string())?
        .constants();
    Ok((constants.multiplier.to_vec(), constants.acceleration_shift))
}
