//! The sensor calibration's plain C structs: `at_sensor_calibration_f32` (the sensor's
//! offsets, amplitudes and quadrature as plain floats, which firmware stores in flash and
//! loads at start-up) and `at_calibration_settings_f32` (the online calibration's
//! settings), and the online calibration's modes and status (the core's `Calibrator`, held
//! per channel in `at_chain_state_f32`).

use angletrack_core::{
    CalibrationMode, CalibrationSettings, CalibrationStatus, Calibrator, ConfigError, Float,
    SensorCalibration,
};

use crate::mirror::mirror;
use crate::status::{AT_ERR_MODE, AT_OK, at_status};

/// `at_chain_state_f32_calibration_mode`: neither corrects nor learns (a fresh calibrator's mode).
pub const AT_CALIBRATION_OFF: u32 = 0;
/// `at_chain_state_f32_calibration_mode`: corrects each sample and learns while the observer tracks.
pub const AT_CALIBRATION_LEARNING: u32 = 1;
/// `at_chain_state_f32_calibration_mode`: corrects each sample, learns nothing.
pub const AT_CALIBRATION_FROZEN: u32 = 2;

/// `at_chain_state_f32_calibration_status`: the channels' centres are not found yet (the rotor has not
/// turned a whole turn while learning, or is at rest); nothing is learned (a fresh
/// calibrator's status).
pub const AT_CALIBRATION_FINDING_CENTRE: u32 = 0;
/// `at_chain_state_f32_calibration_status`: the centre is known (found, or loaded); learning, or ready to.
pub const AT_CALIBRATION_CENTRED: u32 = 1;
/// `at_chain_state_f32_calibration_status`: 16 electrical turns at speed without a turn learned (the
/// observer not locked within 0.29 of phase error, or the speed not steady).
pub const AT_CALIBRATION_STALLED: u32 = 2;

/// A sensor's calibration, `y_c = offset_c + amplitude_c cos(theta)`,
/// `y_s = offset_s + amplitude_s sin(theta + quadrature_rad)` (input units, rad): plain
/// floats to store in flash. `at_chain_f32_new` and `at_chain_state_f32_load_calibration` check them.
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

impl at_sensor_calibration_f32 {
    /// The core's calibration in `f32` or `f64`, checked.
    pub(crate) fn checked<T: Float + From<f32>>(
        &self,
    ) -> Result<SensorCalibration<T>, ConfigError> {
        SensorCalibration::new(
            self.offset_c.into(),
            self.offset_s.into(),
            self.amplitude_c.into(),
            self.amplitude_s.into(),
            self.quadrature_rad.into(),
        )
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
pub(crate) fn calibration_status(calibrator: &Calibrator<f32>) -> u32 {
    match calibrator.status() {
        CalibrationStatus::FindingCentre => AT_CALIBRATION_FINDING_CENTRE,
        CalibrationStatus::Centred => AT_CALIBRATION_CENTRED,
        CalibrationStatus::Stalled => AT_CALIBRATION_STALLED,
    }
}

mirror! {
    /// The online calibration's settings (the core's `CalibrationSettings`): when it learns and
    /// the bounds beyond which its estimates raise a fault. Start from
    /// `at_calibration_settings_f32_default()`.
    at_calibration_settings_f32: CalibrationSettings<f32> =
        |_: &Self| CalibrationSettings::default();
    /// Learns only above this electrical speed (rad/s); 0 for the default, one turn in
    /// 4096 samples.
    min_speed_rad_s: f32 = min_speed_rad_s,
    /// An offset above this fraction of its channel's amplitude flags
    /// `AT_FAULT_OFFSET_OR_QUADRATURE` (default 0.1).
    max_offset: f32 = max_offset,
    /// `|A_s / A_c - 1|` above this flags `AT_FAULT_AMPLITUDE_MISMATCH` (default 0.2).
    max_amplitude_mismatch: f32 = max_amplitude_mismatch,
    /// `|quadrature|` (rad) above this flags `AT_FAULT_OFFSET_OR_QUADRATURE` (default 0.1).
    max_quadrature_rad: f32 = max_quadrature_rad,
}
