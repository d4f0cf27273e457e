//! The fixed-point chains of a [`TrackerRun`](super::TrackerRun): order 2 or 3, on counts
//! shifted to 16 bits.

use angletrack_core::{
    AdcCounts, AngleCorrectionTable, Faults, FixedAngleCorrectionTable, FixedCalibration,
    FixedGains, FrontEndFaults, Input as CoreInput, Order, SensorCalibration, SupportedOrder,
    TRACKER_TABLE_LENGTH, Tracker, TrackerFrontEnd, TrackerSettings, TrackerState,
};

use super::super::rules::FixedMonitor;
use super::super::{Calibration, Correction, Input, TrackerFile};
use super::{
    CaptureHead, Fixed, Learning, Run, TrackedSample, field, file_error, mid_scale, refuse,
    thresholds,
};
use crate::json_file::JsonFileError;

impl TrackerFile {
    /// The stored calibration in the fixed-point chain's counts shifted by `shift` (the
    /// calibration is learned on the counts before the shift), and the chain's integer
    /// stage of it; `None` without one. An online calibration is refused, naming the
    /// field (`name` names the file). The export writes what this builds.
    pub(in crate::tracker_file) fn fixed_calibration(
        &self,
        name: &str,
        shift: u32,
    ) -> Result<Option<(SensorCalibration<f64>, FixedCalibration)>, JsonFileError> {
        match &self.calibration {
            Calibration::None => Ok(None),
            Calibration::Stored(s) => {
                let shifted = crate::shifted_calibration(s, shift)
                    .map_err(field(name, "calibration.sensor"))?;
                let fixed =
                    FixedCalibration::new(&shifted).map_err(field(name, "calibration.sensor"))?;
                Ok(Some((shifted, fixed)))
            }
            Calibration::Online { .. } => Err(refuse(
                name,
                "calibration.kind",
                "the fixed-point chain has no online calibration: give \"stored\" or \"none\"",
            )),
        }
    }

    /// The fixed-point chain's table of the file's angle correction (`None` without one).
    pub(in crate::tracker_file) fn fixed_correction(
        &self,
        name: &str,
    ) -> Result<Option<FixedAngleCorrectionTable<TRACKER_TABLE_LENGTH>>, JsonFileError> {
        Ok(match &self.correction {
            Correction::None => None,
            Correction::Harmonics(h) => Some(FixedAngleCorrectionTable::from_harmonics(h)),
            Correction::Table(curve) => Some(FixedAngleCorrectionTable::from_table(
                &AngleCorrectionTable::<f64, TRACKER_TABLE_LENGTH>::from_curve(curve)
                    .map_err(field(name, "correction.table"))?,
            )),
        })
    }
}

impl<const N: usize> Run for Fixed<N>
where
    Order<N>: SupportedOrder,
{
    fn new(file: &TrackerFile, name: &str, head: &CaptureHead<'_>) -> Result<Self, JsonFileError> {
        let field = |f: &'static str| field(name, f);
        if file.winding_amplitude.is_some() {
            return Err(refuse(
                name,
                "winding_check",
                "the fixed-point chain has none: leave it null",
            ));
        }
        let mid = mid_scale(file, name, head)?;
        let Some(mid) = mid else {
            return Err(refuse(
                name,
                "input",
                "the fixed-point chain takes counts: give input.bits",
            ));
        };
        // The firmware's rule for a stated width (`AdcCounts::offset_binary`): shifted to 16
        // bits; for counts of another width, the shift that keeps the samples in 16 bits.
        let shift = match file.input {
            Input::Bits { bits, .. } if bits <= 16 => 16 - bits,
            Input::Scaled { .. } => {
                return Err(refuse(
                    name,
                    "input",
                    "the fixed-point chain takes counts of a stated width: give input.bits",
                ));
            }
            _ => {
                let n = head.y_c.len().min(head.y_s.len());
                crate::fixed_input(&head.y_c[..n], &head.y_s[..n], mid as u64)
                    .map_err(field("input"))?
                    .shift
            }
        };
        // Stated thresholds: the export's monitor; measured: the capture's amplitude and
        // tracking-error level (above its noise, as the floats'), by the same rule.
        let measured = thresholds(file, head, Some(mid));
        let nominal = measured.nominal_amplitude;
        let monitor = file
            .fixed_monitor(name, shift)
            .map_err(|e| file_error(name, e))?
            .unwrap_or_else(|| FixedMonitor::measured(&measured, shift));
        // The monitor judges a window's amplitude against half its own at the least: a
        // signal below it in 16 bits (a small amplitude in counts of a stated width, whose
        // shift is fixed) would be flagged on every row. Refused, rather than every row
        // flagged, where the thresholds are measured.
        let (in_16_bits, least) = (nominal * f64::from(1u32 << shift), 0.6 * monitor.amplitude);
        if file.fault_thresholds.is_none() && in_16_bits < least {
            return Err(refuse(
                name,
                "input.bits",
                format!(
                    "the signal's amplitude, {} counts, is {} in 16 bits after the {shift}-bit \
                     shift of its stated width, below what the fixed-point monitor judges ({}: \
                     half its smallest amplitude, 16384, and a margin): every row would be \
                     flagged; leave the width out (--adc-bits: the shift is then measured, {} \
                     bits), state the fault thresholds, or track in float",
                    super::significant(nominal),
                    super::significant(in_16_bits),
                    super::significant(least),
                    crate::fixed_input_shift(nominal)
                ),
            ));
        }
        let (rails, _) = file.rails(name, true).map_err(|e| file_error(name, e))?;
        let calibration = file.fixed_calibration(name, shift)?.map(|(_, c)| c);
        let correction = file.fixed_correction(name)?;
        let adc = AdcCounts::new(mid, shift).map_err(field("input"))?;
        let front_end = TrackerFrontEnd::<i16>::new(TrackerSettings {
            input: CoreInput::Counts { adc, rails },
            winding: (),
            calibration,
            correction,
        })
        .map_err(field("adc_range"))?;
        let mut values = [0.0; N];
        if file.gains.gains.len() != N {
            return Err(refuse(name, "gains", "2 or 3 gains (the observer's order)"));
        }
        values.copy_from_slice(&file.gains.gains);
        let gains = FixedGains::<N>::new(values, file.gains.sample_period_s)
            .and_then(|g| monitor.apply(g))
            .map_err(field("gains"))?;
        Ok(Self {
            tracker: Tracker::new(front_end, gains),
            state: TrackerState::new(),
            description: format!(
                "the core's Tracker (fixed point, {}): counts of amplitude {}, mid-scale \
                 {mid} removed, shifted left by {shift} bits (AdcCounts), monitor amplitude {}; {}",
                super::order_name(N),
                super::significant(nominal),
                super::significant(monitor.amplitude),
                super::stages(file, true),
            ),
        })
    }

    fn track_each(&mut self, y_c: &[f64], y_s: &[f64], mut each: impl FnMut(TrackedSample)) {
        for (&c, &s) in y_c.iter().zip(y_s) {
            let e = self.tracker.update(&mut self.state, (c as i32, s as i32));
            let observer = &self.tracker.observer;
            each(TrackedSample {
                // The binary angle's 2^32 a turn in radians: exact in f64.
                angle_rad: f64::from(e.angle) * (core::f64::consts::PI / 2_147_483_648.0),
                position_rad: observer.position_rad(&e),
                speed_rad_s: observer.speed_rad_s(&e),
                acceleration_rad_s2: observer.acceleration_rad_s2(&e),
                phase_error: f64::from(e.phase_error) / 32768.0,
                faults: e.faults.bits(),
                front_end_faults: self.state.front_end.faults().bits(),
                angle_binary: Some(e.angle),
            });
        }
    }

    fn latched_faults(&self) -> (Faults, FrontEndFaults) {
        (
            self.state.observer.latched_faults(),
            self.state.front_end.latched_faults(),
        )
    }

    fn learning(&self) -> Option<Learning> {
        None
    }

    fn describe(&self) -> String {
        self.description.clone()
    }
}
