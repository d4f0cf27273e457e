//! `at_calibrator_f32` (the online calibration of one channel, the core's `Calibrator<f32>`)
//! and `at_sensor_calibration_f32` (the sensor's offsets, amplitudes and quadrature as
//! plain floats, which firmware stores in flash and loads at start-up).

use core::mem::MaybeUninit;

use angletrack_core::{
    CalibrationMode, CalibrationStatus, Calibrator, ConfigError, SensorCalibration,
};

use crate::slot::{self, Refused};
use crate::status::{AT_ERR_MODE, AT_OK, at_status, status_of_result};

/// The 8-byte words of an `at_calibrator_f32`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CALIBRATOR_F32_WORDS: usize = 14;

/// `at_calibrator_f32_mode`: neither corrects nor learns (a fresh calibrator's mode).
pub const AT_CALIBRATION_OFF: u32 = 0;
/// `at_calibrator_f32_mode`: corrects each sample and learns while the observer tracks.
pub const AT_CALIBRATION_LEARNING: u32 = 1;
/// `at_calibrator_f32_mode`: corrects each sample, learns nothing.
pub const AT_CALIBRATION_FROZEN: u32 = 2;

/// `at_calibrator_f32_status`: the channels' centres are not found yet (the rotor has not
/// turned a whole turn while learning, or is at rest); nothing is learned (a fresh
/// calibrator's status).
pub const AT_CALIBRATION_FINDING_CENTRE: u32 = 0;
/// `at_calibrator_f32_status`: the centre is known (found, or loaded); learning, or ready to.
pub const AT_CALIBRATION_CENTRED: u32 = 1;
/// `at_calibrator_f32_status`: 16 electrical turns at speed without a turn learned (the
/// observer not locked within 0.29 of phase error, or the speed not steady).
pub const AT_CALIBRATION_STALLED: u32 = 2;

/// One channel's online calibration: the correction applied to each sample and its
/// estimator. A zeroed one (C static memory) is a fresh calibrator: off, no correction,
/// nothing learned. Place it anywhere; copy it by assignment; never write its fields.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_calibrator_f32 {
    /// Private: whether `storage` holds it (0: a fresh calibrator).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_CALIBRATOR_F32_WORDS],
}

slot::slot_struct!(at_calibrator_f32, AT_CALIBRATOR_F32_WORDS);

/// A sensor's calibration, `y_c = offset_c + amplitude_c cos(theta)`,
/// `y_s = offset_s + amplitude_s sin(theta + quadrature_rad)` (input units, rad): plain
/// floats to store in flash. `at_calibrator_f32_load` checks them.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct at_sensor_calibration_f32 {
    /// Offset of the cosine channel.
    pub offset_c: f32,
    /// Offset of the sine channel.
    pub offset_s: f32,
    /// Amplitude of the cosine channel (positive).
    pub amplitude_c: f32,
    /// Amplitude of the sine channel (positive).
    pub amplitude_s: f32,
    /// Quadrature (non-orthogonality) angle (rad), below pi/4 in magnitude.
    pub quadrature_rad: f32,
}

impl From<SensorCalibration<f32>> for at_sensor_calibration_f32 {
    fn from(c: SensorCalibration<f32>) -> Self {
        let (offset_c, offset_s, amplitude_c, amplitude_s, quadrature_rad) = c.parameters();
        Self {
            offset_c,
            offset_s,
            amplitude_c,
            amplitude_s,
            quadrature_rad,
        }
    }
}

impl at_calibrator_f32 {
    /// A fresh calibrator (all zero, as C static memory holds).
    pub(crate) const FRESH: Self = Self::ZEROED;

    /// The calibrator held, or a fresh one; refused if another build's.
    pub(crate) fn get_mut(&mut self) -> Result<&mut Calibrator<f32>, Refused> {
        self.slot_get_or_put(Calibrator::new)
    }

    /// A copy of the calibrator held, or a fresh one; refused if another build's.
    pub(crate) fn value(&self) -> Result<Calibrator<f32>, Refused> {
        match self.slot_get() {
            Ok(c) => Ok(*c),
            Err(Refused::NotInitialised) => Ok(Calibrator::new()),
            Err(refused) => Err(refused),
        }
    }

    /// Loads a stored calibration (checked), frozen; on error `self` is left as it was.
    pub(crate) fn load(&mut self, stored: &at_sensor_calibration_f32) -> at_status {
        let calibration = stored.checked();
        if let Ok(calibration) = calibration {
            self.slot_put(Calibrator::from_calibration(calibration));
        }
        status_of_result(calibration)
    }

    /// Sets the mode from an `AT_CALIBRATION_*` value.
    pub(crate) fn set_mode(&mut self, mode: u32) -> at_status {
        match self.get_mut() {
            Ok(calibrator) => set_mode_of(calibrator, mode),
            Err(refused) => refused.status(),
        }
    }

    /// The mode, as an `AT_CALIBRATION_*` value (off for another build's calibrator).
    pub(crate) fn mode(&self) -> u32 {
        self.value().map_or(AT_CALIBRATION_OFF, |c| mode_of(&c))
    }
}

impl at_sensor_calibration_f32 {
    /// The core's calibration, checked.
    pub(crate) fn checked(&self) -> Result<SensorCalibration<f32>, ConfigError> {
        SensorCalibration::new(
            self.offset_c,
            self.offset_s,
            self.amplitude_c,
            self.amplitude_s,
            self.quadrature_rad,
        )
    }
}

#[cfg(test)]
impl at_sensor_calibration_f32 {
    /// The calibration that corrects nothing.
    pub(crate) fn from_core_identity() -> Self {
        SensorCalibration::IDENTITY.into()
    }
}

/// Sets the mode of `calibrator` from an `AT_CALIBRATION_*` value.
pub(crate) fn set_mode_of(calibrator: &mut Calibrator<f32>, mode: u32) -> at_status {
    match mode {
        AT_CALIBRATION_OFF => calibrator.disable(),
        AT_CALIBRATION_LEARNING => calibrator.enable(),
        AT_CALIBRATION_FROZEN => calibrator.freeze(),
        _ => return AT_ERR_MODE,
    }
    AT_OK
}

/// The mode of `calibrator`, as an `AT_CALIBRATION_*` value.
pub(crate) fn mode_of(calibrator: &Calibrator<f32>) -> u32 {
    match calibrator.mode() {
        CalibrationMode::Learning => AT_CALIBRATION_LEARNING,
        CalibrationMode::Frozen => AT_CALIBRATION_FROZEN,
        _ => AT_CALIBRATION_OFF,
    }
}

/// The status of `calibrator`, as an `AT_CALIBRATION_*` status value.
pub(crate) fn status_of(calibrator: &Calibrator<f32>) -> u32 {
    match calibrator.status() {
        CalibrationStatus::FindingCentre => AT_CALIBRATION_FINDING_CENTRE,
        CalibrationStatus::Centred => AT_CALIBRATION_CENTRED,
        CalibrationStatus::Stalled => AT_CALIBRATION_STALLED,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::status::AT_ERR_AMPLITUDE_S;

    #[test]
    fn loads_checks_and_reads_back() {
        let mut calibrator = at_calibrator_f32::FRESH;
        assert_eq!(calibrator.mode(), AT_CALIBRATION_OFF);
        let stored = at_sensor_calibration_f32 {
            offset_c: 90.0,
            offset_s: -90.0,
            amplitude_c: 1800.0,
            amplitude_s: 1980.0,
            quadrature_rad: 0.052,
        };
        assert_eq!(calibrator.load(&stored), AT_OK);
        assert_eq!(calibrator.mode(), AT_CALIBRATION_FROZEN);
        assert_eq!(
            at_sensor_calibration_f32::from(calibrator.value().unwrap().calibration()),
            stored
        );
        assert_eq!(calibrator.set_mode(AT_CALIBRATION_LEARNING), AT_OK);
        assert_eq!(calibrator.mode(), AT_CALIBRATION_LEARNING);
        assert_eq!(calibrator.set_mode(7), AT_ERR_MODE);
        let bad = at_sensor_calibration_f32 {
            amplitude_s: -1.0,
            ..stored
        };
        assert_eq!(calibrator.load(&bad), AT_ERR_AMPLITUDE_S);
        assert_eq!(
            calibrator.mode(),
            AT_CALIBRATION_LEARNING,
            "a refused load changes nothing"
        );
    }
}
