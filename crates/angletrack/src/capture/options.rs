//! [`CaptureOptions`] as a caller writes them (the command line's options, the Python API's
//! arguments): each parsed and checked here, a refusal naming the option.

use core::fmt;

use super::columns::ColumnMap;
use super::reader::CaptureOptions;
use super::sniff::{DecimalMark, Delimiter};
use super::time::TimeUnit;

/// The options of a capture as written: text where the caller writes text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WrittenCaptureOptions<'a> {
    /// `role=column` pairs separated by commas (empty: the usual header names).
    pub columns: &'a str,
    /// The field delimiter (`None`: sniffed): one character, `tab` or `whitespace`.
    pub delimiter: Option<&'a str>,
    /// The decimal mark (`None`: sniffed): `.` or `,`.
    pub decimal: Option<&'a str>,
    /// Lines skipped before the header.
    pub skip_rows: u64,
    /// The time column's unit: `s`, `ms`, `us` or `ns`.
    pub time_unit: &'a str,
    /// The true sample rate (Hz), if stated.
    pub sample_rate_hz: Option<f64>,
    /// Rows per chunk.
    pub chunk_rows: usize,
}

/// An option refused: its name as the caller wrote it and why.
#[derive(Debug, Clone, PartialEq)]
pub struct CaptureOptionError {
    /// The option (`"delimiter"`, `"sample_rate_hz"`, ...).
    pub option: &'static str,
    /// What is wrong with it (without the option's name).
    pub reason: String,
}

impl CaptureOptionError {
    /// The refusal of `option`: `message`, less the `option: ` the parsers lead with.
    fn new(option: &'static str, message: &str) -> Self {
        let reason = message
            .strip_prefix(option)
            .and_then(|m| m.strip_prefix(": "));
        Self {
            option,
            reason: reason.unwrap_or(message).to_string(),
        }
    }
}

impl fmt::Display for CaptureOptionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.option, self.reason)
    }
}

impl std::error::Error for CaptureOptionError {}

impl CaptureOptions {
    /// The options of `written`, each parsed, then [`check`](Self::check)ed.
    ///
    /// ```
    /// use angletrack::capture::{CaptureOptions, WrittenCaptureOptions};
    /// let mut written = WrittenCaptureOptions {
    ///     columns: "y_c=cos,y_s=sin",
    ///     delimiter: Some(";"),
    ///     decimal: Some(","),
    ///     skip_rows: 0,
    ///     time_unit: "ms",
    ///     sample_rate_hz: None,
    ///     chunk_rows: 1 << 16,
    /// };
    /// assert!(CaptureOptions::parse(&written).is_ok());
    /// written.delimiter = Some(",");
    /// assert_eq!(CaptureOptions::parse(&written).unwrap_err().option, "decimal");
    /// ```
    pub fn parse(written: &WrittenCaptureOptions<'_>) -> Result<Self, CaptureOptionError> {
        let named = |option| move |m: String| CaptureOptionError::new(option, &m);
        let options = Self {
            columns: written
                .columns
                .parse::<ColumnMap>()
                .map_err(named("columns"))?,
            delimiter: written
                .delimiter
                .map(Delimiter::parse)
                .transpose()
                .map_err(named("delimiter"))?,
            decimal: written
                .decimal
                .map(DecimalMark::parse)
                .transpose()
                .map_err(named("decimal"))?,
            skip_rows: written.skip_rows,
            time_unit: written
                .time_unit
                .parse::<TimeUnit>()
                .map_err(named("time_unit"))?,
            sample_rate_hz: written.sample_rate_hz,
            chunk_rows: written.chunk_rows,
        };
        options.check()?;
        Ok(options)
    }

    /// Refuses options that contradict each other or cannot be read with: a decimal comma
    /// with the delimiter `,`, a sample rate not positive and finite, fewer than 2 rows per
    /// chunk.
    pub fn check(&self) -> Result<(), CaptureOptionError> {
        let refused = |option, reason: String| Err(CaptureOptionError { option, reason });
        if self.decimal == Some(DecimalMark::Comma) && self.delimiter == Some(Delimiter::Byte(b','))
        {
            return refused(
                "decimal",
                "',' with the delimiter ',': the fields could not be told apart".into(),
            );
        }
        if let Some(rate) = self.sample_rate_hz
            && !(rate.is_finite() && rate > 0.0)
        {
            return refused(
                "sample_rate_hz",
                format!("{rate} Hz: the sample rate must be positive and finite"),
            );
        }
        if self.chunk_rows < 2 {
            return refused("chunk_rows", "at least 2 rows per chunk".into());
        }
        Ok(())
    }
}
