//! The gains files, `angletrack design --format json`: JSON documents of a design's gains
//! in `f64`, exactly (read back into the same gains: `angletrack track --gains-file`, a
//! firmware's build script), or of its fixed-point constants, each with the design it came
//! from (free-form: the method and the specification).
//!
//! ```
//! use angletrack::export::GainsFile;
//! let file = GainsFile { gains: vec![0.06, 0.001], sample_period_s: 1e-4, design: None };
//! let text = file.to_json();
//! assert!(text.starts_with("{\n  \"format\": \"angletrack-gains\",\n  \"version\": 1,\n"));
//! assert_eq!(GainsFile::from_json(&text, "gains.json")?, file);
//! let bad = text.replace("\"order\": 2", "\"order\": 3");
//! let e = GainsFile::from_json(&bad, "gains.json").unwrap_err();
//! assert_eq!(e.to_string(), "gains.json: order: 3, but the file holds 2 gains");
//! # Ok::<(), angletrack::JsonFileError>(())
//! ```

use angletrack_core::fixed::FixedConstants;
use angletrack_core::{ConfigError, FixedGains, Gains, Order, SupportedOrder};
use serde_json::Value;

use crate::FixedDesignConstants;
use crate::json_file::{Document, JsonFileError, number};

/// The `format` of a file of [`GainsFile`].
pub const GAINS_FILE_FORMAT: &str = "angletrack-gains";
/// The `format` of a file of [`FixedGainsFile`].
pub const FIXED_GAINS_FILE_FORMAT: &str = "angletrack-fixed-gains";
/// The `version` both formats are written with, and the only one read.
pub const GAINS_FILE_VERSION: u64 = 1;

/// A design's gains (`f64`, `l1` first: 2 or 3 of them) at its sample period, and the design
/// they came from: the document of [`GAINS_FILE_FORMAT`].
#[derive(Debug, Clone, PartialEq)]
pub struct GainsFile {
    /// The gains, `l1` first.
    pub gains: Vec<f64>,
    /// The sample period (s).
    pub sample_period_s: f64,
    /// What designed them (any JSON: the method, the specification), if known.
    pub design: Option<Value>,
}

/// A design's fixed-point constants and the design they came from: the document of
/// [`FIXED_GAINS_FILE_FORMAT`].
#[derive(Debug, Clone, PartialEq)]
pub struct FixedGainsFile {
    /// The constants (multipliers, shift, the gains they represent, the sample period).
    pub constants: FixedDesignConstants,
    /// What designed them, if known.
    pub design: Option<Value>,
}

/// `values` as a JSON list, one number a line (a member of the document's top level).
pub(crate) fn list<T>(values: &[T], item: impl Fn(&T) -> String) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("    {}", item(v))).collect();
    format!("[\n{}\n  ]", items.join(",\n"))
}

/// The members of a document, the design last, as one JSON object's text.
pub(crate) fn document(mut members: Vec<String>, design: Option<&Value>) -> String {
    if let Some(design) = design {
        // Nested one level: its lines indented by two more blanks.
        let pretty = serde_json::to_string_pretty(design).unwrap_or_else(|_| "null".into());
        members.push(format!("  \"design\": {}", pretty.replace('\n', "\n  ")));
    }
    format!("{{\n{}\n}}\n", members.join(",\n"))
}

/// `two` or `three` on the `values` of `field` by their count, the observer's order: another
/// count, or a value the core refuses (its message), is an error naming `field`.
fn by_order<T: Copy, R>(
    doc: &Document<'_>,
    field: &str,
    values: &[T],
    two: impl FnOnce([T; 2]) -> Result<R, ConfigError>,
    three: impl FnOnce([T; 3]) -> Result<R, ConfigError>,
) -> Result<R, JsonFileError> {
    match *values {
        [a, b] => two([a, b]),
        [a, b, c] => three([a, b, c]),
        _ => {
            return Err(doc.error(
                field,
                format!("2 or 3 (the observer's order), got {}", values.len()),
            ));
        }
    }
    .map_err(|e| doc.error(field, e.to_string()))
}

/// The core's check of a fixed-point file's constants, and the constants it checked.
fn fixed_constants<const N: usize>(
    multiplier: [i32; N],
    acceleration_shift: u32,
    sample_period_s: f64,
) -> Result<FixedDesignConstants, ConfigError>
where
    Order<N>: SupportedOrder,
{
    let constants = FixedConstants {
        multiplier,
        acceleration_shift,
    };
    FixedGains::<N>::from_constants(constants, sample_period_s)
        .map(|g| FixedDesignConstants::of(&g))
}

impl GainsFile {
    /// The JSON text of [`GAINS_FILE_FORMAT`]: the gains and the period as the shortest
    /// decimals that read back to the same `f64`.
    pub fn to_json(&self) -> String {
        document(
            vec![
                format!("  \"format\": \"{GAINS_FILE_FORMAT}\""),
                format!("  \"version\": {GAINS_FILE_VERSION}"),
                format!("  \"order\": {}", self.gains.len()),
                format!("  \"sample_period_s\": {}", number(self.sample_period_s)),
                format!("  \"gains\": {}", list(&self.gains, |&g| number(g))),
            ],
            self.design.as_ref(),
        )
    }

    /// The gains of JSON `text` of [`GAINS_FILE_FORMAT`]; `file` names it in errors. Refuses
    /// another format or version, an `order` other than the gains' count, and gains the core
    /// refuses ([`Gains::new`]: not 2 or 3, not finite, outside the sampled loop's stability
    /// region), naming the field.
    pub fn from_json(text: &str, file: &str) -> Result<Self, JsonFileError> {
        let doc = Document::parse(text, file)?;
        doc.check_format(GAINS_FILE_FORMAT)?;
        doc.check_version(GAINS_FILE_VERSION)?;
        let gains: Vec<f64> = match doc.object.get("gains") {
            Some(Value::Array(items)) => items
                .iter()
                .map(|v| {
                    v.as_f64()
                        .ok_or_else(|| doc.error("gains", format!("must be numbers, got {v}")))
                })
                .collect::<Result<_, _>>()?,
            Some(v) => return Err(doc.error("gains", format!("must be a list, got {v}"))),
            None => return Err(doc.error("gains", "missing")),
        };
        if let Some(order) = doc.object.get("order")
            && order.as_u64() != Some(gains.len() as u64)
        {
            // An order that contradicts the gains is a file edited by hand: neither is
            // trusted.
            return Err(doc.error(
                "order",
                format!("{order}, but the file holds {} gains", gains.len()),
            ));
        }
        let sample_period_s = doc.number("sample_period_s")?;
        by_order(
            &doc,
            "gains",
            &gains,
            |g| Gains::<f64, 2>::new(g, sample_period_s).map(|_| ()),
            |g| Gains::<f64, 3>::new(g, sample_period_s).map(|_| ()),
        )?;
        Ok(Self {
            gains,
            sample_period_s,
            design: doc.object.get("design").cloned(),
        })
    }
}

impl FixedGainsFile {
    /// The JSON text of [`FIXED_GAINS_FILE_FORMAT`].
    pub fn to_json(&self) -> String {
        let c = &self.constants;
        document(
            vec![
                format!("  \"format\": \"{FIXED_GAINS_FILE_FORMAT}\""),
                format!("  \"version\": {GAINS_FILE_VERSION}"),
                format!("  \"order\": {}", c.multiplier.len()),
                format!("  \"multiplier\": {}", list(&c.multiplier, i32::to_string)),
                format!("  \"acceleration_shift\": {}", c.acceleration_shift),
                format!(
                    "  \"quantised_gains\": {}",
                    list(&c.quantised_gains, |&g| number(g))
                ),
                format!("  \"sample_period_s\": {}", number(c.sample_period_s)),
            ],
            self.design.as_ref(),
        )
    }

    /// The constants of JSON `text` of [`FIXED_GAINS_FILE_FORMAT`], checked by the core
    /// ([`FixedGains::from_constants`]: the gains they represent are read from the
    /// multipliers, not the file); `file` names it in errors.
    pub fn from_json(text: &str, file: &str) -> Result<Self, JsonFileError> {
        let doc = Document::parse(text, file)?;
        doc.check_format(FIXED_GAINS_FILE_FORMAT)?;
        doc.check_version(GAINS_FILE_VERSION)?;
        let integer = |v: &Value| v.as_i64().and_then(|i| i32::try_from(i).ok());
        let multiplier: Vec<i32> = match doc.object.get("multiplier") {
            Some(Value::Array(items)) => items
                .iter()
                .map(|v| {
                    integer(v).ok_or_else(|| {
                        doc.error("multiplier", format!("must be 32-bit integers, got {v}"))
                    })
                })
                .collect::<Result<_, _>>()?,
            _ => return Err(doc.error("multiplier", "must be a list of integers")),
        };
        let acceleration_shift = doc
            .object
            .get("acceleration_shift")
            .and_then(Value::as_u64)
            .and_then(|s| u32::try_from(s).ok())
            .ok_or_else(|| doc.error("acceleration_shift", "must be an integer from 0 to 15"))?;
        let sample_period_s = doc.number("sample_period_s")?;
        let constants = by_order(
            &doc,
            "multiplier",
            &multiplier,
            |m| fixed_constants(m, acceleration_shift, sample_period_s),
            |m| fixed_constants(m, acceleration_shift, sample_period_s),
        )?;
        Ok(Self {
            constants,
            design: doc.object.get("design").cloned(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gains_and_their_design_read_back_exactly() {
        let design = serde_json::json!({"method": "kalman", "specification": {"jerk_std": 1e5}});
        let file = GainsFile {
            gains: vec![0.123_456_789_012_345_67, 7.1e-3, 1.234_5e-5],
            sample_period_s: 1.0 / 16_000.0,
            design: Some(design),
        };
        let text = file.to_json();
        assert!(
            text.contains("  \"design\": {\n    \"method\": \"kalman\",\n"),
            "{text}"
        );
        assert_eq!(GainsFile::from_json(&text, "g.json").unwrap(), file);
    }

    #[test]
    fn each_bad_field_is_named() {
        let good = GainsFile {
            gains: vec![0.06, 0.001],
            sample_period_s: 1e-4,
            design: None,
        }
        .to_json();
        for (from, to, message) in [
            (
                "angletrack-gains",
                "angletrack-fixed-gains",
                "g.json: format: not an angletrack-gains document but an \"angletrack-fixed-gains\" one",
            ),
            (
                "\"format\": \"angletrack-gains\"",
                "\"format\": 3",
                "g.json: format: not an angletrack-gains document",
            ),
            (
                "\"version\": 1",
                "\"version\": 2",
                "g.json: version: 2 is not supported (expected 1)",
            ),
            (
                "0.0001",
                "\"fast\"",
                "g.json: sample_period_s: must be a number, got \"fast\"",
            ),
            ("0.06", "\"a\"", "g.json: gains: must be numbers, got \"a\""),
            ("0.06", "6.0", "g.json: gains: "),
            ("{", "[", "g.json: not JSON"),
        ] {
            let e = GainsFile::from_json(&good.replacen(from, to, 1), "g.json").unwrap_err();
            assert!(e.to_string().starts_with(message), "{e}");
        }
    }

    #[test]
    fn fixed_constants_read_back_checked_by_the_core() {
        let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6).unwrap();
        let file = FixedGainsFile {
            constants: FixedDesignConstants::of(&gains),
            design: None,
        };
        let text = file.to_json();
        assert!(text.contains("  \"acceleration_shift\": "), "{text}");
        assert_eq!(FixedGainsFile::from_json(&text, "f.json").unwrap(), file);
        let multiplier = file.constants.multiplier[0].to_string();
        let zero = text.replacen(&format!("    {multiplier}"), "    0", 1);
        let e = FixedGainsFile::from_json(&zero, "f.json").unwrap_err();
        assert_eq!(e.field.as_deref(), Some("multiplier"), "{e}");
    }
}
