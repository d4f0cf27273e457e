//! A tracker file's firmware constants: the gains (float or fixed-point) and the stored
//! calibration with its harmonics, by the generators of [`crate::export`] (one C header, or
//! one block of Rust `const`s). The rest of the setup goes into the first comment, for
//! the firmware's own constructors. Settings no generator writes yet are refused rather
//! than left out.

use core::fmt;

use angletrack_core::{
    AngleCorrection, ConfigError, FixedGains, Gains, Order, SensorCalibration, SupportedOrder,
};

use super::{AdcRange, Calibration, Correction, Input, NumberType, TrackerFile};
use crate::FixedDesignConstants;
use crate::export::{
    ExportError, FloatType, calibration_c_header, calibration_rust, fixed_c_header, fixed_rust,
    gains_c_header, gains_rust,
};
use crate::json_file::JsonFileError;

/// The language of firmware constants.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Language {
    /// A C header.
    C,
    /// A block of Rust `const`s.
    Rust,
}

impl Language {
    /// The language named `name`: `"c"` or `"rust"` (`None` for another name).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "c" => Some(Language::C),
            "rust" => Some(Language::Rust),
            _ => None,
        }
    }

    /// The float gains in this language (`gains_c_header` or `gains_rust`).
    pub fn gains<const N: usize>(
        self,
        gains: &Gains<f64, N>,
        float: FloatType,
        name: &str,
        description: &str,
    ) -> Result<String, ExportError> {
        match self {
            Language::C => gains_c_header(gains, float, name, description),
            Language::Rust => gains_rust(gains, float, name, description),
        }
    }

    /// The fixed-point constants in this language (`fixed_c_header` or `fixed_rust`).
    pub fn fixed(
        self,
        constants: &FixedDesignConstants,
        name: &str,
        description: &str,
    ) -> Result<String, ExportError> {
        match self {
            Language::C => fixed_c_header(constants, name, description),
            Language::Rust => fixed_rust(constants, name, description),
        }
    }

    /// A stored calibration and its harmonics in this language (`calibration_c_header` or
    /// `calibration_rust`).
    pub fn calibration(
        self,
        sensor: &SensorCalibration<f64>,
        correction: &AngleCorrection<f64>,
        float: FloatType,
        name: &str,
    ) -> Result<String, ExportError> {
        match self {
            Language::C => calibration_c_header(sensor, correction, float, name),
            Language::Rust => calibration_rust(sensor, correction, float, name),
        }
    }
}

/// Why a tracker file's firmware constants could not be written: a setting of the file no
/// generator writes (naming its field), or the generator's refusal (the name, a value
/// beyond the float type).
#[derive(Debug, Clone, PartialEq)]
pub enum FirmwareError {
    /// A setting of the file.
    File(JsonFileError),
    /// The generator's refusal.
    Export(ExportError),
}

impl fmt::Display for FirmwareError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FirmwareError::File(e) => e.fmt(f),
            FirmwareError::Export(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for FirmwareError {}

impl From<ExportError> for FirmwareError {
    fn from(e: ExportError) -> Self {
        FirmwareError::Export(e)
    }
}

/// The file's gains as the generators take them (checked again: they were when read).
fn gains_text<const N: usize>(
    gains: [f64; N],
    t: &TrackerFile,
    language: Language,
    name: &str,
    description: &str,
) -> Result<Result<String, ExportError>, ConfigError>
where
    Order<N>: SupportedOrder,
{
    let period = t.gains.sample_period_s;
    Ok(match (t.number_type, language) {
        (NumberType::Fixed, language) => {
            let constants = FixedDesignConstants::of(&FixedGains::<N>::new(gains, period)?);
            language.fixed(&constants, name, description)
        }
        (number_type, language) => {
            let gains = Gains::<f64, N>::new(gains, period)?;
            language.gains(&gains, float_type(number_type), name, description)
        }
    })
}

/// The firmware's float type: the number type's, `f64` for the fixed-point chain's
/// calibration (`FixedCalibration::new` takes the `f64` values).
fn float_type(number_type: NumberType) -> FloatType {
    match number_type {
        NumberType::F32 => FloatType::F32,
        NumberType::F64 | NumberType::Fixed => FloatType::F64,
    }
}

impl TrackerFile {
    /// The lines of the first comment: the settings the firmware states itself.
    pub(super) fn setup_comment(&self) -> String {
        let input = match self.input {
            Input::Units => "samples in units".to_string(),
            Input::Counts => "counts, the mid-scale measured".to_string(),
            Input::Bits { bits, signed } => format!(
                "{bits}-bit counts: AdcScaling::{}({bits})",
                if signed {
                    "twos_complement"
                } else {
                    "offset_binary"
                }
            ),
            Input::Scaled {
                mid_scale,
                counts_per_unit,
            } => format!("counts: AdcScaling::new({mid_scale}, {counts_per_unit:?})"),
        };
        let range = match self.adc_range {
            AdcRange::Measured => "ADC range measured".to_string(),
            AdcRange::FullScale => "ADC range: the full scale".to_string(),
            AdcRange::Stated { min, max } => format!("ADC range {min:?} to {max:?}"),
        };
        let mut lines = vec![
            format!(
                "From a tracker file: number type {}.",
                self.number_type.name()
            ),
            format!("Input: {input}; {range}."),
        ];
        if let Some(p) = self.pole_pairs {
            lines.push(format!("Pole pairs: {p}."));
        }
        lines.join("\n")
    }

    /// The file's setting no generator writes yet, if any: (its field, what it is).
    fn unwritten(&self) -> Option<(&'static str, &'static str)> {
        // The fixed-point chain's constants carry the monitor's thresholds.
        if self.fault_thresholds.is_some() && self.number_type != NumberType::Fixed {
            return Some(("fault_thresholds", "fault thresholds"));
        }
        if self.winding_amplitude.is_some() {
            return Some(("winding_check", "a winding check"));
        }
        if matches!(self.calibration, Calibration::Online { .. }) {
            return Some(("calibration.kind", "an online calibration"));
        }
        if matches!(self.correction, Correction::Table(_)) {
            return Some(("correction.kind", "a correction table"));
        }
        if self.correction != Correction::None && self.calibration == Calibration::None {
            return Some(("correction.kind", "harmonics without a stored calibration"));
        }
        None
    }

    /// The setup's firmware constants in `language`, every identifier prefixed by `name`.
    /// Rust: the whole tracker as one `static` ([`TrackerFile::rust_tracker`]). C: the gains
    /// (`gains_c_header` in the number type, or the fixed-point constants), then a stored
    /// calibration with its harmonics (`calibration_c_header`), then for fixed point the
    /// whole chain in integers (`at_chain_fixed_constants`, for
    /// `at_chain_fixed_from_constants`). `file` names the tracker
    /// file in the refusal of a setting no generator writes (in C: fault thresholds but in fixed point, a
    /// winding check, an online calibration, a correction table).
    pub fn firmware_constants(
        &self,
        file: &str,
        language: Language,
        name: &str,
    ) -> Result<String, FirmwareError> {
        if language == Language::Rust {
            return self.rust_tracker(file, name);
        }
        if let Some((field, what)) = self.unwritten() {
            return Err(FirmwareError::File(JsonFileError::new(
                file,
                Some(field),
                format!("{what}: no firmware constants are generated for it yet; leave it out"),
            )));
        }
        let description = self.setup_comment();
        let gains =
            match *self.gains.gains.as_slice() {
                [a, b] => gains_text([a, b], self, language, name, &description)
                    .map_err(|e| e.to_string()),
                [a, b, c] => gains_text([a, b, c], self, language, name, &description)
                    .map_err(|e| e.to_string()),
                ref other => Err(format!(
                    "2 or 3 (the observer's order), got {}",
                    other.len()
                )),
            }
            .map_err(|e| FirmwareError::File(JsonFileError::new(file, Some("gains"), e)))?;
        let mut text = gains?;
        if let Calibration::Stored(sensor) = &self.calibration {
            let correction = match &self.correction {
                Correction::Harmonics(harmonics) => *harmonics,
                _ => AngleCorrection::new([0.0; 8], [0.0; 8]).map_err(|e| {
                    FirmwareError::File(JsonFileError::new(file, Some("correction"), e.to_string()))
                })?,
            };
            let float = float_type(self.number_type);
            text.push('\n');
            text.push_str(&language.calibration(sensor, &correction, float, name)?);
        }
        if self.number_type == NumberType::Fixed {
            text.push('\n');
            text.push_str(&match *self.gains.gains.as_slice() {
                [a, b] => self.fixed_chain_c([a, b], file, name)?,
                [a, b, c] => self.fixed_chain_c([a, b, c], file, name)?,
                // Refused above.
                _ => String::new(),
            });
        }
        Ok(text)
    }
}
