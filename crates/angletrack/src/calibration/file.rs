//! The calibration files: JSON documents of a sensor's calibration, read back by
//! `angletrack track --calibration`.
//!
//! Two kinds, told apart by their `format` key:
//!
//! * `angletrack-sensor-calibration` ([`SensorCalibrationRecord`], written by `angletrack
//!   track --calibrate`): the offsets, amplitudes and quadrature of the core's
//!   [`SensorCalibration`] under `calibration`, beside `turns_learned` and `source` (where
//!   it came from). A bare object of the five fields is read too (a file written by hand).
//! * `angletrack-calibration` ([`CaptureCalibration`], written by `angletrack calibrate`):
//!   `sensor` (the five parameters in [`SensorCalibration::new`]'s order), `cos` and `sin`
//!   (the [`AngleCorrection`]'s coefficients, 8 each) and what the learning saw: `method`
//!   and `orders` (each order's `amplitude_rad`, `uncertainty_rad` and `status`), which a
//!   file written before them lacks (read as unknown).
//!
//! Numbers are written as the shortest decimal of their `f64` and read back exactly; a
//! value that is not finite is written `null` (and read back as NaN) where NaN is allowed.
//! Every value read is checked by the core, and every error names the file and the field.
//!
//! ```
//! use angletrack::{CalibrationFile, SensorCalibration, SensorCalibrationRecord};
//! let record = SensorCalibrationRecord {
//!     calibration: SensorCalibration::new(90.0, -90.0, 1800.0, 1980.0, 0.0524)?,
//!     turns_learned: Some(42),
//!     source: Some("capture.csv".into()),
//! };
//! let text = record.to_json();
//! assert!(text.starts_with("{\n  \"format\": \"angletrack-sensor-calibration\",\n"));
//! let read = CalibrationFile::from_json(&text, "cal.json")?;
//! assert_eq!(read, CalibrationFile::Sensor(record));
//! let bad = text.replace("1980.0", "-1.0");
//! let e = CalibrationFile::from_json(&bad, "cal.json").unwrap_err();
//! assert_eq!(e.to_string(), "cal.json: calibration.amplitude_s: amplitude_s must be positive");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::Path;

use angletrack_core::{AngleCorrection, MAX_CORRECTION_ORDER, SensorCalibration};
use serde_json::Value;

use super::{CalibrationMethod, CaptureCalibration, OrderQuality, OrderStatus, SPECTRUM_ORDERS};
use crate::json_file::{Document, JsonFileError, number};

/// The `format` of a file of [`SensorCalibrationRecord`].
pub const SENSOR_CALIBRATION_FORMAT: &str = "angletrack-sensor-calibration";
/// The `format` of a file of [`CaptureCalibration`].
pub const ANGLE_CALIBRATION_FORMAT: &str = "angletrack-calibration";
/// The `version` both formats are written with, and the only one read.
pub const CALIBRATION_FILE_VERSION: u64 = 1;

/// The fields of a sensor calibration, in [`SensorCalibration::new`]'s order.
pub(crate) const SENSOR_FIELDS: [&str; 5] = [
    "offset_c",
    "offset_s",
    "amplitude_c",
    "amplitude_s",
    "quadrature_rad",
];

/// A sensor calibration learned while tracking, with what learned it: the document of
/// [`SENSOR_CALIBRATION_FORMAT`].
#[derive(Debug, Clone, PartialEq)]
pub struct SensorCalibrationRecord {
    /// The offsets, amplitudes and quadrature (the capture's units, rad).
    pub calibration: SensorCalibration<f64>,
    /// The turns the online calibration learned from, if known.
    pub turns_learned: Option<u32>,
    /// The capture it was learned from, if known.
    pub source: Option<String>,
}

/// A calibration file of either kind, as [`CalibrationFile::from_json`] tells them apart.
#[derive(Debug, Clone, PartialEq)]
// A file is read once per run: its size does not matter, and its variants stay plain values.
#[allow(clippy::large_enum_variant)]
pub enum CalibrationFile {
    /// Offsets, imbalance and quadrature (`angletrack track --calibrate`).
    Sensor(SensorCalibrationRecord),
    /// Offsets, imbalance, quadrature and the angle error's harmonics (`angletrack
    /// calibrate`).
    Angle(CaptureCalibration),
}

impl CalibrationFile {
    /// The calibration of the JSON `text` of either format (or a bare object of the sensor
    /// calibration's five fields); `file` names it in errors.
    pub fn from_json(text: &str, file: &str) -> Result<Self, JsonFileError> {
        let doc = Document::parse(text, file)?;
        match doc.object.get("format").and_then(Value::as_str) {
            Some(ANGLE_CALIBRATION_FORMAT) => doc.angle().map(CalibrationFile::Angle),
            _ => doc.sensor().map(CalibrationFile::Sensor),
        }
    }

    /// The JSON text of the calibration, in its format.
    pub fn to_json(&self) -> String {
        match self {
            CalibrationFile::Sensor(record) => record.to_json(),
            CalibrationFile::Angle(calibration) => calibration.to_json(),
        }
    }

    /// Reads the calibration file at `path` (either format).
    pub fn read(path: &Path) -> Result<Self, JsonFileError> {
        let (text, name) = crate::json_file::read_text(path)?;
        Self::from_json(&text, &name)
    }

    /// Writes the calibration to `path` as [`CalibrationFile::to_json`].
    pub fn write(&self, path: &Path) -> Result<(), JsonFileError> {
        crate::json_file::write_text(path, &self.to_json())
    }
}

impl SensorCalibrationRecord {
    /// The calibration of JSON `text` of [`SENSOR_CALIBRATION_FORMAT`] (or a bare object of
    /// the five fields); `file` names it in errors.
    pub fn from_json(text: &str, file: &str) -> Result<Self, JsonFileError> {
        Document::parse(text, file)?.sensor()
    }

    /// The JSON text of [`SENSOR_CALIBRATION_FORMAT`].
    pub fn to_json(&self) -> String {
        let (o_c, o_s, a_c, a_s, q) = self.calibration.parameters();
        let fields: Vec<String> = SENSOR_FIELDS
            .iter()
            .zip([o_c, o_s, a_c, a_s, q])
            .map(|(name, value)| format!("    \"{name}\": {}", number(value)))
            .collect();
        let mut members = vec![
            format!("  \"format\": \"{SENSOR_CALIBRATION_FORMAT}\""),
            format!("  \"version\": {CALIBRATION_FILE_VERSION}"),
            format!("  \"calibration\": {{\n{}\n  }}", fields.join(",\n")),
        ];
        if let Some(turns) = self.turns_learned {
            members.push(format!("  \"turns_learned\": {turns}"));
        }
        if let Some(source) = &self.source {
            members.push(format!("  \"source\": {}", Value::from(source.as_str())));
        }
        format!("{{\n{}\n}}\n", members.join(",\n"))
    }
}

impl CaptureCalibration {
    /// The calibration of JSON `text` of [`ANGLE_CALIBRATION_FORMAT`] (another format is
    /// refused); `file` names it in errors.
    pub fn from_json(text: &str, file: &str) -> Result<Self, JsonFileError> {
        Document::parse(text, file)?.angle()
    }

    /// The JSON text of [`ANGLE_CALIBRATION_FORMAT`].
    pub fn to_json(&self) -> String {
        let (o_c, o_s, a_c, a_s, q) = self.sensor.parameters();
        let (cos, sin) = self.correction.coefficients();
        let list = |values: &[f64]| {
            let items: Vec<String> = values
                .iter()
                .map(|&v| format!("    {}", number(v)))
                .collect();
            format!("[\n{}\n  ]", items.join(",\n"))
        };
        let orders: Vec<String> = self
            .orders
            .iter()
            .enumerate()
            .map(|(i, q)| {
                format!(
                    "    {{\"order\": {}, \"amplitude_rad\": {}, \"uncertainty_rad\": {}, \"status\": {}}}",
                    i + 1,
                    number(q.amplitude_rad),
                    number(q.uncertainty_rad),
                    Value::from(q.status.name())
                )
            })
            .collect();
        let members = [
            format!("  \"format\": \"{ANGLE_CALIBRATION_FORMAT}\""),
            format!("  \"version\": {CALIBRATION_FILE_VERSION}"),
            format!("  \"sensor\": {}", list(&[o_c, o_s, a_c, a_s, q])),
            format!("  \"cos\": {}", list(&cos)),
            format!("  \"sin\": {}", list(&sin)),
            format!("  \"speed_rad_s\": {}", number(self.speed_rad_s)),
            format!("  \"turns\": {}", number(self.turns)),
            format!("  \"error_rms_rad\": {}", number(self.error_rms_rad)),
            format!("  \"residual_rms_rad\": {}", number(self.residual_rms_rad)),
            format!("  \"method\": {}", Value::from(self.method.name())),
            format!("  \"orders\": [\n{}\n  ]", orders.join(",\n")),
            format!("  \"warnings\": {}", Value::from(self.warnings())),
        ];
        format!("{{\n{}\n}}\n", members.join(",\n"))
    }
}

impl Document<'_> {
    fn sensor(&self) -> Result<SensorCalibrationRecord, JsonFileError> {
        match self.object.get("format") {
            None => {}
            Some(Value::String(f)) if f == SENSOR_CALIBRATION_FORMAT => {
                self.check_version(CALIBRATION_FILE_VERSION)?
            }
            Some(other) => {
                return Err(self.error(
                    "format",
                    format!("expected {SENSOR_CALIBRATION_FORMAT:?}, got {other}"),
                ));
            }
        }
        let (fields, prefix) = match self.object.get("calibration") {
            Some(Value::Object(fields)) => (fields, "calibration."),
            Some(_) => return Err(self.error("calibration", "must hold an object")),
            None => (&self.object, ""),
        };
        let mut values = [0.0; 5];
        for (value, name) in values.iter_mut().zip(SENSOR_FIELDS) {
            let field = format!("{prefix}{name}");
            *value = match fields.get(name) {
                Some(v) => v
                    .as_f64()
                    .ok_or_else(|| self.error(&field, format!("must be a number, got {v}")))?,
                None => return Err(self.error(&field, "missing")),
            };
        }
        let [o_c, o_s, a_c, a_s, q] = values;
        let calibration = SensorCalibration::new(o_c, o_s, a_c, a_s, q)
            .map_err(|e| self.error(&format!("{prefix}{}", e.parameter().name()), e.to_string()))?;
        let turns_learned =
            match self.object.get("turns_learned") {
                None | Some(Value::Null) => None,
                Some(v) => Some(v.as_u64().and_then(|t| u32::try_from(t).ok()).ok_or_else(
                    || {
                        self.error(
                            "turns_learned",
                            format!("must be a whole number of turns, got {v}"),
                        )
                    },
                )?),
            };
        let source = match self.object.get("source") {
            None | Some(Value::Null) => None,
            Some(Value::String(s)) => Some(s.clone()),
            Some(v) => return Err(self.error("source", format!("must be a string, got {v}"))),
        };
        Ok(SensorCalibrationRecord {
            calibration,
            turns_learned,
            source,
        })
    }

    fn angle(&self) -> Result<CaptureCalibration, JsonFileError> {
        self.check_format(ANGLE_CALIBRATION_FORMAT)?;
        self.check_version(CALIBRATION_FILE_VERSION)?;
        let [o_c, o_s, a_c, a_s, q] = self.numbers::<5>("sensor")?;
        let sensor = SensorCalibration::new(o_c, o_s, a_c, a_s, q)
            .map_err(|e| self.error("sensor", e.to_string()))?;
        let cos = self.numbers::<MAX_CORRECTION_ORDER>("cos")?;
        let sin = self.numbers::<MAX_CORRECTION_ORDER>("sin")?;
        let correction =
            AngleCorrection::new(cos, sin).map_err(|e| self.error("cos, sin", e.to_string()))?;
        Ok(CaptureCalibration {
            sensor,
            correction,
            speed_rad_s: self.optional_number("speed_rad_s")?,
            turns: self.optional_number("turns")?,
            error_rms_rad: self.optional_number("error_rms_rad")?,
            residual_rms_rad: self.optional_number("residual_rms_rad")?,
            method: match self.object.get("method") {
                None | Some(Value::Null) => CalibrationMethod::Unknown,
                Some(Value::String(name)) => CalibrationMethod::from_name(name),
                Some(v) => return Err(self.error("method", format!("must be a string, got {v}"))),
            },
            orders: self.orders()?,
        })
    }

    /// The `orders` list (every order unknown when it is missing, as in older files).
    fn orders(&self) -> Result<[OrderQuality; SPECTRUM_ORDERS], JsonFileError> {
        let mut orders = [OrderQuality::UNKNOWN; SPECTRUM_ORDERS];
        let list = match self.object.get("orders") {
            None | Some(Value::Null) => return Ok(orders),
            Some(Value::Array(list)) => list,
            Some(v) => return Err(self.error("orders", format!("must be a list, got {v}"))),
        };
        for item in list {
            let refused = || {
                self.error(
                    "orders",
                    format!("each must be {{\"order\": 1..={SPECTRUM_ORDERS}, \"amplitude_rad\", \"uncertainty_rad\", \"status\"}}, got {item}"),
                )
            };
            let order = item
                .get("order")
                .and_then(Value::as_u64)
                .ok_or_else(refused)? as usize;
            let slot = order
                .checked_sub(1)
                .and_then(|i| orders.get_mut(i))
                .ok_or_else(refused)?;
            let number = |key: &str| match item.get(key) {
                None | Some(Value::Null) => Ok(f64::NAN),
                Some(v) => v.as_f64().ok_or_else(refused),
            };
            *slot = OrderQuality {
                amplitude_rad: number("amplitude_rad")?,
                uncertainty_rad: number("uncertainty_rad")?,
                status: OrderStatus::from_name(
                    item.get("status").and_then(Value::as_str).unwrap_or(""),
                ),
            };
        }
        Ok(orders)
    }
}
