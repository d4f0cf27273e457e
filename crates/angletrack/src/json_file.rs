//! What the crate's JSON files (the calibration files, the gains files) share: the error
//! that names the file and the field, and a parsed document with the checks of its
//! `format`, `version` and numbers. Numbers are written as the shortest decimal of their
//! `f64` and read back exactly (`serde_json`'s `float_roundtrip`).

use core::fmt;

use serde_json::{Map, Value};

/// Why a JSON file of the crate's (a calibration, gains) could not be read or written: the
/// file (or the name the caller gave its text), the field at fault (`None` for the whole
/// file: not JSON, not readable), and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JsonFileError {
    /// The file's path, or the name of its text.
    pub file: String,
    /// The field at fault, dotted for a nested one (`calibration.amplitude_s`).
    pub field: Option<String>,
    /// What is wrong with it.
    pub reason: String,
}

impl JsonFileError {
    pub(crate) fn new(file: &str, field: Option<&str>, reason: impl Into<String>) -> Self {
        Self {
            file: file.to_string(),
            field: field.map(str::to_string),
            reason: reason.into(),
        }
    }
}

impl fmt::Display for JsonFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.field {
            Some(field) => write!(f, "{}: {field}: {}", self.file, self.reason),
            None => write!(f, "{}: {}", self.file, self.reason),
        }
    }
}

impl std::error::Error for JsonFileError {}

/// The text of the file at `path` and the name its errors give it (its path).
pub(crate) fn read_text(path: &std::path::Path) -> Result<(String, String), JsonFileError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| JsonFileError::new(&name, None, e.to_string()))?;
    Ok((text, name))
}

/// Writes `text` to the file at `path`, an error naming it.
pub(crate) fn write_text(path: &std::path::Path, text: &str) -> Result<(), JsonFileError> {
    std::fs::write(path, text)
        .map_err(|e| JsonFileError::new(&path.display().to_string(), None, e.to_string()))
}

/// `value` as a JSON number: its shortest round-trip decimal, `null` if not finite.
pub(crate) fn number(value: f64) -> String {
    if value.is_finite() {
        format!("{value:?}")
    } else {
        "null".to_string()
    }
}

/// A parsed JSON object and the name of its file, for the errors; for a nested object (a
/// [`Document::section`]), the dotted path before its fields' names.
pub(crate) struct Document<'a> {
    pub(crate) object: Map<String, Value>,
    pub(crate) file: &'a str,
    pub(crate) prefix: String,
}

impl<'a> Document<'a> {
    /// The object of `text` (refused: not JSON, not an object).
    pub(crate) fn parse(text: &str, file: &'a str) -> Result<Self, JsonFileError> {
        let value: Value = serde_json::from_str(text)
            .map_err(|e| JsonFileError::new(file, None, format!("not JSON ({e})")))?;
        match value {
            Value::Object(object) => Ok(Self {
                object,
                file,
                prefix: String::new(),
            }),
            _ => Err(JsonFileError::new(file, None, "expected a JSON object")),
        }
    }

    /// The error of `field` (its dotted path in a section).
    pub(crate) fn error(&self, field: &str, reason: impl Into<String>) -> JsonFileError {
        JsonFileError::new(self.file, Some(&format!("{}{field}", self.prefix)), reason)
    }

    /// The object under `field` as a document whose errors name its fields `field.NAME`
    /// (`None`: missing or `null`; refused: not an object).
    pub(crate) fn section(&self, field: &str) -> Result<Option<Document<'a>>, JsonFileError> {
        match self.object.get(field) {
            None | Some(Value::Null) => Ok(None),
            Some(Value::Object(object)) => Ok(Some(Document {
                object: object.clone(),
                file: self.file,
                prefix: format!("{}{field}.", self.prefix),
            })),
            Some(v) => Err(self.error(field, format!("must be an object, got {v}"))),
        }
    }

    /// Refuses a field not in `known`: a misspelt one would otherwise be ignored, its value
    /// silently replaced by the default.
    pub(crate) fn refuse_unknown(&self, known: &[&str]) -> Result<(), JsonFileError> {
        match self.object.keys().find(|k| !known.contains(&k.as_str())) {
            None => Ok(()),
            Some(key) => Err(self.error(
                key,
                format!("unknown field (expected one of: {})", known.join(", ")),
            )),
        }
    }

    /// The string under `field` (refused: missing, not a string).
    pub(crate) fn string(&self, field: &str) -> Result<&str, JsonFileError> {
        match self.object.get(field) {
            None => Err(self.error(field, "missing")),
            Some(v) => v
                .as_str()
                .ok_or_else(|| self.error(field, format!("must be a string, got {v}"))),
        }
    }

    /// Refuses a `format` other than `format` (a missing one too).
    pub(crate) fn check_format(&self, format: &str) -> Result<(), JsonFileError> {
        match self.object.get("format") {
            Some(Value::String(f)) if f == format => Ok(()),
            // Another of the library's documents (the fixed-point constants where the gains
            // are read, a calibration): say which.
            Some(Value::String(f)) => Err(self.error(
                "format",
                format!("not an {format} document but an {f:?} one"),
            )),
            _ => Err(self.error("format", format!("not an {format} document"))),
        }
    }

    /// Refuses a `version` other than `version` (a missing one too).
    pub(crate) fn check_version(&self, version: u64) -> Result<(), JsonFileError> {
        match self.object.get("version") {
            Some(v) if v.as_u64() == Some(version) => Ok(()),
            other => Err(self.error(
                "version",
                format!(
                    "{} is not supported (expected {version})",
                    other.map_or("none".to_string(), Value::to_string)
                ),
            )),
        }
    }

    /// The list of `N` numbers under `field`.
    pub(crate) fn numbers<const N: usize>(&self, field: &str) -> Result<[f64; N], JsonFileError> {
        let refused = || self.error(field, format!("must be a list of {N} numbers"));
        let list = self
            .object
            .get(field)
            .and_then(Value::as_array)
            .filter(|list| list.len() == N)
            .ok_or_else(refused)?;
        let mut out = [0.0; N];
        for (slot, value) in out.iter_mut().zip(list) {
            *slot = value.as_f64().ok_or_else(refused)?;
        }
        Ok(out)
    }

    /// The number under `field` (refused: missing, not a number).
    pub(crate) fn number(&self, field: &str) -> Result<f64, JsonFileError> {
        match self.object.get(field) {
            None => Err(self.error(field, "missing")),
            Some(v) => v
                .as_f64()
                .ok_or_else(|| self.error(field, format!("must be a number, got {v}"))),
        }
    }

    /// The number under `field`; NaN when it is missing or `null`.
    pub(crate) fn optional_number(&self, field: &str) -> Result<f64, JsonFileError> {
        match self.object.get(field) {
            None | Some(Value::Null) => Ok(f64::NAN),
            Some(v) => v
                .as_f64()
                .ok_or_else(|| self.error(field, format!("must be a number, got {v}"))),
        }
    }
}
