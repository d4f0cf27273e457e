//! What the reader asks of each file format: rows of the chosen columns as `f64`, with the
//! line (or row) each came from, chunk by chunk.

use super::error::CaptureError;

/// The chosen columns of up to a chunk of rows, as read (before any check or unit).
#[derive(Debug, Default)]
pub struct RawRows {
    /// One vector per chosen column, in the order the columns were asked for.
    pub columns: Vec<Vec<f64>>,
    /// The 1-based line (text) or row (arrays) of each row, for messages.
    pub lines: Vec<u64>,
    /// Whether every value read so far of each chosen column was a whole number as written
    /// (an integer literal, or an integer array).
    pub integers: Vec<bool>,
}

impl RawRows {
    /// Empties the rows, keeping `n` columns (and the integer flags of earlier chunks).
    pub fn clear(&mut self, n: usize) {
        self.columns.resize_with(n, Vec::new);
        self.columns.iter_mut().for_each(Vec::clear);
        self.integers.resize(n, true);
        self.lines.clear();
    }
}

/// What [`RowSource::read`] gives: the rows were appended, or the first fault.
pub type Filled = Result<(), CaptureError>;

/// A file format's rows.
pub trait RowSource {
    /// Appends up to `max_rows` rows of the 0-based `columns` to `rows` (cleared by the
    /// caller); fewer only at the end of the data.
    fn read(&mut self, columns: &[usize], rows: &mut RawRows, max_rows: usize) -> Filled;

    /// Bytes of the file consumed so far (for progress).
    fn bytes_read(&self) -> u64;

    /// The element type of the stored samples (`int16`, `float64`, ...; `None` for text,
    /// whose type the values themselves tell).
    fn stored_dtype(&self) -> Option<String> {
        None
    }
}

/// The value of one text field (blanks around it ignored), with `,` as its decimal mark
/// when `decimal_comma`, and whether it is written as a whole number; `None` for an empty
/// field.
pub fn parse_field(field: &[u8], decimal_comma: bool) -> Option<Result<(f64, bool), ()>> {
    let f = field.trim_ascii();
    let f = f
        .strip_prefix(b"\"")
        .and_then(|f| f.strip_suffix(b"\""))
        .unwrap_or(f)
        .trim_ascii();
    if f.is_empty() {
        return None;
    }
    let integer = f
        .iter()
        .enumerate()
        .all(|(i, &b)| b.is_ascii_digit() || (i == 0 && (b == b'-' || b == b'+')));
    // A number is short: a longer field is not one, and is refused below.
    let mut pointed = [0u8; 64];
    let f = match (decimal_comma, pointed.get_mut(..f.len())) {
        (true, Some(copy)) => {
            for (to, &from) in copy.iter_mut().zip(f) {
                *to = if from == b',' { b'.' } else { from };
            }
            &*copy
        }
        _ => f,
    };
    let value = std::str::from_utf8(f)
        .ok()
        .and_then(|t| t.parse::<f64>().ok());
    Some(value.map(|v| (v, integer)).ok_or(()))
}

/// The error of a field that is not a number (`text`) or is missing, at `line`, 1-based
/// `column` named `name`.
pub fn field_error(
    path: &std::path::Path,
    line: u64,
    column: usize,
    name: &str,
    text: Option<&[u8]>,
    fields: usize,
) -> CaptureError {
    let message = match text {
        Some(t) => format!(
            "column {name:?}: {:?} is not a number",
            String::from_utf8_lossy(t.trim_ascii())
        ),
        None if column > fields => format!(
            "column {name:?}: missing value (the row has {fields} field(s), the column is number \
             {column})"
        ),
        None => format!("column {name:?}: missing value (empty field)"),
    };
    CaptureError::new(path, message).at(Some(line), Some(column))
}
