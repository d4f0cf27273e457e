//! The tracker file: one JSON document of a whole sensor setup, what `angletrack track
//! --tracker` runs and `angletrack calibrate --tracker` completes. It holds what a gains
//! file, a calibration file and the command line's options held apart: the observer's
//! gains at their sample period (and the design they came from), the number type, the
//! input (units, or counts), the ADC range rule, the winding check, the fault thresholds,
//! the sensor calibration (none, stored, or learned online with its settings), the angle
//! correction (none, harmonics, or a table) and the motor's pole pairs.
//!
//! Every value read is checked by the core constructor that checks it everywhere else
//! ([`Gains::new`](crate::Gains::new), [`SensorCalibration::new`], [`AngleCorrection::new`],
//! [`AdcScaling`](crate::AdcScaling), [`AngleCorrectionTable::from_curve`](crate::core::AngleCorrectionTable::from_curve),
//! the fault thresholds and calibration settings as [`Gains`](crate::Gains) takes them),
//! and an error names the field as written in the file (`calibration.max_offset`). An
//! unknown field, another version and another of the crate's documents (a gains or
//! calibration file) are refused.
//!
//! ```
//! use angletrack::export::GainsFile;
//! use angletrack::tracker_file::{NumberType, TrackerFile};
//! let gains = GainsFile { gains: vec![0.06, 0.001], sample_period_s: 1e-4, design: None };
//! let mut tracker = TrackerFile::new(gains);
//! tracker.number_type = NumberType::F32;
//! let text = tracker.to_json();
//! assert!(text.starts_with("{\n  \"format\": \"angletrack-tracker\",\n  \"version\": 1,\n"));
//! assert_eq!(TrackerFile::from_json(&text, "t.json")?, tracker);
//! let e = TrackerFile::from_json(&text.replace("\"f32\"", "\"f16\""), "t.json").unwrap_err();
//! assert_eq!(e.to_string(), "t.json: number_type: expected \"f32\", \"f64\" or \"fixed\", got \"f16\"");
//! # Ok::<(), angletrack::JsonFileError>(())
//! ```

mod firmware;
mod firmware_c;
mod firmware_rust;
mod firmware_rust_fixed;
mod read;
mod rules;
mod runner;
mod write;

pub use firmware::{FirmwareError, Language};
pub use runner::{CaptureHead, TrackedRows, TrackedSample, TrackerRun};

#[cfg(test)]
mod tests;

use std::path::Path;

use angletrack_core::{AngleCorrection, CalibrationSettings, FaultThresholds, SensorCalibration};

use crate::calibration::CalibrationFile;
use crate::export::GainsFile;
use crate::json_file::JsonFileError;

/// The `format` of a tracker file.
pub const TRACKER_FILE_FORMAT: &str = "angletrack-tracker";
/// The `version` a tracker file is written with, and the only one read.
pub const TRACKER_FILE_VERSION: u64 = 1;

/// The number type the observer runs on (`number_type`: `"f32"`, `"f64"`, `"fixed"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumberType {
    /// `f32`, as on a Cortex-M4F.
    F32,
    /// `f64`, as on a host.
    F64,
    /// The fixed-point chain on integer counts, as on a Cortex-M0.
    Fixed,
}

/// The phase detector's sine and cosine (`sin_cos`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SinCosKind {
    /// The number type's default (fast for `f32`, exact for `f64`).
    Default,
    /// The fast polynomial.
    Fast,
    /// The correctly rounded functions.
    Exact,
}

/// What the samples are (`input`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Input {
    /// Numbers in physical units (volts, normalised): tracked as they are.
    Units,
    /// Integer counts whose mid-scale is measured on the capture's first samples (the
    /// command line's rule without a stated one; a firmware states it).
    Counts,
    /// Counts of an ADC of `bits` bits, two's complement (`signed`: mid-scale 0) or offset
    /// binary (mid-scale `2^(bits-1)`); its full scale is the rails of
    /// [`AdcRange::FullScale`].
    Bits {
        /// The resolution (2 to 31 offset binary, 2 to 32 signed).
        bits: u32,
        /// Two's complement counts.
        signed: bool,
    },
    /// Counts whose `mid_scale` (the reading of a zero signal) is removed and which are
    /// divided by `counts_per_unit`.
    Scaled {
        /// The reading of a zero signal (counts).
        mid_scale: i32,
        /// Counts per unit of the observer's input.
        counts_per_unit: f64,
    },
}

/// The ADC's range against which clipping is flagged (`adc_range`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AdcRange {
    /// Measured on the samples (extremes held flat).
    Measured,
    /// The full scale of [`Input::Bits`].
    FullScale,
    /// Stated, in the samples' units (counts for counts).
    Stated {
        /// The lowest value.
        min: f64,
        /// The highest value.
        max: f64,
    },
}

/// The sensor calibration (`calibration`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Calibration {
    /// None: the samples go to the phase detector as they are.
    None,
    /// Applied as stored (frozen).
    Stored(SensorCalibration<f64>),
    /// Learned while tracking, from `initial` if given, with `settings`.
    Online {
        /// Where learning starts (`None`: from the first turns).
        initial: Option<SensorCalibration<f64>>,
        /// When it learns and its faults' bounds.
        settings: CalibrationSettings<f64>,
    },
}

/// The angle correction (`correction`).
#[derive(Debug, Clone, PartialEq)]
pub enum Correction {
    /// None.
    None,
    /// The angle error's harmonics (`cos`, `sin`: [`AngleCorrection::new`]'s arguments).
    Harmonics(AngleCorrection<f64>),
    /// The angle error (rad) at the angles `-pi + 2 pi k / n`, `n` the list's length
    /// ([`AngleCorrectionTable::from_curve`](crate::core::AngleCorrectionTable::from_curve)).
    Table(Vec<f64>),
}

/// A whole sensor setup: the document of [`TRACKER_FILE_FORMAT`].
#[derive(Debug, Clone, PartialEq)]
pub struct TrackerFile {
    /// The gains at their sample period, and the design they came from.
    pub gains: GainsFile,
    /// The number type.
    pub number_type: NumberType,
    /// The phase detector's sine and cosine.
    pub sin_cos: SinCosKind,
    /// What the samples are.
    pub input: Input,
    /// The ADC range rule.
    pub adc_range: AdcRange,
    /// The windings' nominal envelope amplitude against which a winding open or shorted is
    /// flagged (`winding_check.amplitude`; `None`: no winding check).
    pub winding_amplitude: Option<f64>,
    /// The fault thresholds in the observer's input units (`None`: scaled to the signal's
    /// measured amplitude).
    pub fault_thresholds: Option<FaultThresholds<f64>>,
    /// The sensor calibration.
    pub calibration: Calibration,
    /// The angle correction.
    pub correction: Correction,
    /// The motor's pole pairs (`None`: 1, the electrical angle is the mechanical one).
    pub pole_pairs: Option<u32>,
    /// The RMS angle error (rad) predicted for these gains on the capture they were
    /// designed from ([`design_capture`](crate::design_capture)); a record, not a setting:
    /// written only when known.
    pub predicted_error_rms_rad: Option<f64>,
}

impl TrackerFile {
    /// The setup of `gains` and nothing else: `f64`, samples in units, the ADC range
    /// measured, no winding check, thresholds scaled to the signal, no calibration or
    /// correction.
    pub fn new(gains: GainsFile) -> Self {
        Self {
            gains,
            number_type: NumberType::F64,
            sin_cos: SinCosKind::Default,
            input: Input::Units,
            adc_range: AdcRange::Measured,
            winding_amplitude: None,
            fault_thresholds: None,
            calibration: Calibration::None,
            correction: Correction::None,
            pole_pairs: None,
            predicted_error_rms_rad: None,
        }
    }

    /// The same setup with the calibration of a calibration file: a sensor calibration
    /// (`angletrack track --calibrate`) stored, or an angle calibration (`angletrack
    /// calibrate`) stored with its harmonics as the correction.
    pub fn with_calibration_file(self, file: &CalibrationFile) -> Self {
        let (calibration, correction) = match file {
            CalibrationFile::Sensor(record) => (record.calibration, Correction::None),
            CalibrationFile::Angle(angle) => {
                (angle.sensor, Correction::Harmonics(angle.correction))
            }
        };
        Self {
            calibration: Calibration::Stored(calibration),
            correction,
            ..self
        }
    }

    /// Reads the tracker file at `path`.
    pub fn read(path: &Path) -> Result<Self, JsonFileError> {
        let (text, name) = crate::json_file::read_text(path)?;
        Self::from_json(&text, &name)
    }

    /// Writes the tracker file to `path` as [`TrackerFile::to_json`].
    pub fn write(&self, path: &Path) -> Result<(), JsonFileError> {
        crate::json_file::write_text(path, &self.to_json())
    }
}

impl NumberType {
    /// The name in the file.
    pub fn name(self) -> &'static str {
        match self {
            NumberType::F32 => "f32",
            NumberType::F64 => "f64",
            NumberType::Fixed => "fixed",
        }
    }
}

impl SinCosKind {
    /// Whether it is the exact sin/cos in a float type (`float64`: `f64`, else `f32`):
    /// the default is the fast one in `f32`, whose error of 2 ulp of 1 is `f32`'s own
    /// scale, and the exact one in `f64`.
    pub fn is_exact(self, float64: bool) -> bool {
        match self {
            SinCosKind::Default => float64,
            kind => kind == SinCosKind::Exact,
        }
    }

    /// The name in the file (`None`: `null`, the number type's default).
    pub fn name(self) -> Option<&'static str> {
        match self {
            SinCosKind::Default => None,
            SinCosKind::Fast => Some("fast"),
            SinCosKind::Exact => Some("exact"),
        }
    }

    /// The kind of a name as [`SinCosKind::name`] gives it (`None`: the default); `None` for
    /// any other name.
    pub fn from_name(name: Option<&str>) -> Option<Self> {
        [SinCosKind::Default, SinCosKind::Fast, SinCosKind::Exact]
            .into_iter()
            .find(|kind| kind.name() == name)
    }
}
