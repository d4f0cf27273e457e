//! Recorded captures: reading any delimited text (`,` `;` tab or blanks, decimal points or
//! commas, with or without a header, metadata lines before it, UTF-8, Latin-1 or UTF-16
//! with its byte-order mark, an oscilloscope's (x, y) column pairs), NumPy `.npy` and
//! `.npz` files, in chunks of constant memory ([`CaptureReader`]) or whole
//! ([`read_capture`]); and writing an observer's estimates the same way
//! ([`EstimatesWriter`]), never over an input ([`check_outputs`]) and never half
//! ([`OutputFile`]).
//!
//! Every fault of the input is a [`CaptureError`] naming the file, the line and the column:
//! an empty file, a header without rows, a single row, text or nothing where a number
//! belongs, a time column that is not finite, not increasing, not evenly spaced (unless the
//! sample rate is stated) or that disagrees with a channel's own time column, a reference
//! angle that is not finite, binary data in a text file. Samples that are not finite are
//! kept: the observer rejects them one by one (fault bit `BAD_SAMPLE`).

mod columns;
mod encoding;
mod error;
mod npy;
mod npy_out;
mod npy_record;
mod options;
mod output;
mod reader;
mod sniff;
mod source;
mod table;
mod text;
mod time;
mod write;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_real;

pub use columns::{ColumnMap, NO_COLUMN, ResolvedColumns, Role, is_time_name};
pub use encoding::Encoding;
pub use error::CaptureError;
pub use options::{CaptureOptionError, WrittenCaptureOptions};
pub use output::{NamedPath, OutputFile, check_outputs, write_output};
pub use reader::{CaptureChunk, CaptureOptions, CaptureReader};
pub use sniff::{DecimalMark, Delimiter};
pub use table::{Column, ColumnType, EstimatesFormat, TableWriter};
pub use time::{SPACING_TOLERANCE, TimeUnit};
pub use write::{ESTIMATE_COLUMNS, EstimateRows, EstimatesWriter, OutputFloat, estimate_columns};

/// A whole capture in memory, with what was learnt reading it.
#[derive(Debug, Clone, PartialEq)]
pub struct Capture {
    /// The samples (time in seconds).
    pub samples: CaptureChunk,
    /// The sample rate (Hz): the stated one, else the time column's mean; `None` without
    /// either.
    pub sample_rate_hz: Option<f64>,
    /// The samples' element type as stored (`int16`, `int64` for whole numbers in text,
    /// `float64`, ...).
    pub sample_dtype: String,
    /// The columns used, as `(role, column name)`.
    pub mapping: Vec<(Role, String)>,
    /// `npy`, `npz` or `text, delimiter X`.
    pub format: String,
}

/// Reads the whole capture `path` (see [`CaptureReader`] for the checks).
///
/// ```
/// use angletrack::capture::{CaptureOptions, read_capture};
/// let path = std::env::temp_dir().join("angletrack_doc_read.csv");
/// std::fs::write(&path, "\u{feff}time,y_c,y_s\n0,2048,3548\n1e-4,2049,3547\n").unwrap();
/// let capture = read_capture(&path, CaptureOptions::default()).map_err(|e| e.to_string())?;
/// assert_eq!(capture.samples.y_c, [2048.0, 2049.0]);
/// assert_eq!(capture.sample_dtype, "int64"); // raw ADC counts
/// # std::fs::remove_file(&path).unwrap();
/// # Ok::<(), String>(())
/// ```
pub fn read_capture(
    path: impl AsRef<std::path::Path>,
    options: CaptureOptions,
) -> Result<Capture, CaptureError> {
    let mut reader = CaptureReader::open(path, options)?;
    let mut all = CaptureChunk::default();
    // A capture larger than memory is an error, not an abort: each column grows fallibly.
    let append = |to: &mut Vec<f64>, from: &[f64], path: &std::path::Path| {
        to.try_reserve(from.len()).map_err(|_| {
            CaptureError::new(
                path,
                "the capture does not fit in memory: read it in chunks (CaptureReader)",
            )
        })?;
        to.extend_from_slice(from);
        Ok::<(), CaptureError>(())
    };
    let path = reader.path().to_path_buf();
    while let Some(chunk) = reader.next_chunk()? {
        append(&mut all.y_c, &chunk.y_c, &path)?;
        append(&mut all.y_s, &chunk.y_s, &path)?;
        if let Some(t) = &chunk.time_s {
            append(all.time_s.get_or_insert_with(Vec::new), t, &path)?;
        }
        if let Some(r) = &chunk.reference_rad {
            append(all.reference_rad.get_or_insert_with(Vec::new), r, &path)?;
        }
        if let Some(e) = &chunk.excitation {
            append(all.excitation.get_or_insert_with(Vec::new), e, &path)?;
        }
    }
    Ok(Capture {
        samples: all,
        sample_rate_hz: reader.sample_rate_hz(),
        sample_dtype: reader.sample_dtype(),
        mapping: reader.mapping(),
        format: reader.format().to_string(),
    })
}
