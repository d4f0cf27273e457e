//! What kind of file a capture is, from its first bytes: a NumPy array, a zip of arrays
//! (`.npz`), or text, whose encoding, delimiter, decimal mark, metadata lines and header
//! lines are found here.

use std::path::Path;

use super::encoding::{Encoding, by_bom, decode, is_latin1_text};
use super::error::CaptureError;

/// How the fields of a text capture are separated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delimiter {
    /// One byte: `,`, `;`, tab, `|`.
    Byte(u8),
    /// Runs of blanks (spaces and tabs), as in aligned columns.
    Whitespace,
}

impl Delimiter {
    /// A delimiter from its name: one character, `tab`, `\t`, `space` or `whitespace`.
    ///
    /// ```
    /// use angletrack::capture::Delimiter;
    /// assert_eq!(Delimiter::parse(";"), Ok(Delimiter::Byte(b';')));
    /// assert_eq!(Delimiter::parse("tab"), Ok(Delimiter::Byte(b'\t')));
    /// assert_eq!(Delimiter::parse("whitespace"), Ok(Delimiter::Whitespace));
    /// assert!(Delimiter::parse("::").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Self, String> {
        match text {
            "tab" | "\\t" | "\t" => Ok(Delimiter::Byte(b'\t')),
            "space" | "whitespace" | " " => Ok(Delimiter::Whitespace),
            t if t.len() == 1 && t.is_ascii() => Ok(Delimiter::Byte(t.as_bytes()[0])),
            t => Err(format!(
                "delimiter: expected one character, 'tab' or 'whitespace', got {t:?}"
            )),
        }
    }

    /// Its name in messages and metadata.
    pub fn name(self) -> String {
        match self {
            Delimiter::Byte(b'\t') => "tab".into(),
            Delimiter::Byte(b) => (b as char).to_string(),
            Delimiter::Whitespace => "whitespace".into(),
        }
    }

    /// The fields of one line (not trimmed).
    pub(crate) fn split(self, line: &str) -> Vec<&str> {
        match self {
            Delimiter::Byte(b) => line.split(b as char).collect(),
            Delimiter::Whitespace => line.split_ascii_whitespace().collect(),
        }
    }
}

/// The decimal mark of a text capture's numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DecimalMark {
    /// `1.5`.
    Point,
    /// `1,5` (with a delimiter other than `,`: `;`, tab or blanks).
    Comma,
}

impl DecimalMark {
    /// `.` or `,`.
    ///
    /// ```
    /// use angletrack::capture::DecimalMark;
    /// assert_eq!(DecimalMark::parse(","), Ok(DecimalMark::Comma));
    /// assert!(DecimalMark::parse(";").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Self, String> {
        match text.trim() {
            "." => Ok(DecimalMark::Point),
            "," => Ok(DecimalMark::Comma),
            t => Err(format!("decimal: expected '.' or ',', got {t:?}")),
        }
    }

    /// The mark.
    pub const fn mark(self) -> char {
        match self {
            DecimalMark::Point => '.',
            DecimalMark::Comma => ',',
        }
    }
}

/// What the user states of a text capture's layout (the rest is sniffed).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TextOptions {
    /// The field delimiter.
    pub delimiter: Option<Delimiter>,
    /// The decimal mark.
    pub decimal: Option<DecimalMark>,
    /// Lines at the start of the file skipped before the header (an instrument's
    /// metadata); more are skipped if sniffed.
    pub skip_rows: u64,
}

/// What kind of file a capture is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Kind {
    /// A NumPy `.npy` array.
    Npy,
    /// A NumPy `.npz` zip of named arrays.
    Npz,
    /// Delimited text.
    Text(TextLayout),
}

/// The layout of a text capture.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TextLayout {
    /// Bytes of a byte-order mark to skip (0, 2 or 3).
    pub bom_bytes: u64,
    /// The text's encoding.
    pub encoding: Encoding,
    /// The field delimiter.
    pub delimiter: Delimiter,
    /// The numbers' decimal mark.
    pub decimal: DecimalMark,
    /// The column names (the header's; the 0-based indices without a header).
    pub names: Vec<String>,
    /// Whether the capture has a header line.
    pub has_header: bool,
    /// Lines before the data (metadata, header, units lines, comments and blank lines).
    pub lines_before_data: u64,
    /// Lines of metadata skipped before the header (stated and sniffed).
    pub metadata_lines: u64,
}

/// Bytes read to tell the kind and the layout.
pub const SNIFF_BYTES: usize = 64 * 1024;
const NPY_MAGIC: &[u8] = b"\x93NUMPY";
const ZIP_MAGIC: &[u8] = b"PK\x03\x04";

/// `field` without blanks and quotes around it.
fn bare(field: &str) -> &str {
    field.trim().trim_matches('"').trim()
}

fn is_number(field: &str, decimal: DecimalMark) -> bool {
    let f = bare(field);
    match decimal {
        DecimalMark::Point => !f.is_empty() && f.parse::<f64>().is_ok(),
        DecimalMark::Comma => !f.is_empty() && f.replace(',', ".").parse::<f64>().is_ok(),
    }
}

fn skipped(line: &str) -> bool {
    let t = line.trim();
    t.is_empty() || t.starts_with('#')
}

/// The kind and layout of a capture whose first bytes are `head` (the whole file if shorter
/// than [`SNIFF_BYTES`]; `complete` says whether it is); `stated` is what the user gave.
pub fn sniff(
    path: &Path,
    head: &[u8],
    complete: bool,
    stated: TextOptions,
) -> Result<Kind, CaptureError> {
    if head.starts_with(NPY_MAGIC) {
        return Ok(Kind::Npy);
    }
    if head.starts_with(ZIP_MAGIC) {
        return Ok(Kind::Npz);
    }
    let (encoding, bom_bytes) = match by_bom(head) {
        Some(found) => found,
        None => (text_encoding(path, head, complete)?, 0),
    };
    let text = decode(&head[bom_bytes as usize..], encoding);
    let all_lines = text.lines().count();
    let complete_lines = if complete {
        all_lines
    } else {
        all_lines.saturating_sub(1)
    };
    let mut lines: Vec<(u64, &str)> = Vec::new();
    for (i, line) in text.lines().take(complete_lines).enumerate() {
        if i as u64 >= stated.skip_rows && !skipped(line) {
            lines.push((i as u64 + 1, line));
        }
    }
    if lines.is_empty() {
        let what = if stated.skip_rows > 0 {
            format!("no line after the {} skipped (skip_rows)", stated.skip_rows)
        } else {
            "empty file: no header and no data".to_string()
        };
        return Err(CaptureError::new(path, what).at(Some(1), None));
    }
    let comma_decimal = stated.decimal == Some(DecimalMark::Comma);
    let delimiter = stated
        .delimiter
        .unwrap_or_else(|| guess_delimiter(&lines, comma_decimal));
    let decimal = stated
        .decimal
        .unwrap_or_else(|| guess_decimal(&lines, delimiter));
    let metadata = metadata_lines(&lines, delimiter, decimal);
    let lines = &lines[metadata..];
    let (first_line, first) = lines[0];
    let numeric = |line: &str, all: bool| {
        let fields = delimiter.split(line);
        if all {
            fields.iter().all(|f| is_number(f, decimal))
        } else {
            fields.iter().any(|f| is_number(f, decimal))
        }
    };
    // The header is the first line if any field is not a number; units lines after it have
    // no number at all.
    let has_header = !numeric(first, true);
    let mut header_lines = usize::from(has_header);
    while has_header && header_lines < lines.len() && !numeric(lines[header_lines].1, false) {
        header_lines += 1;
    }
    if header_lines == lines.len() && complete {
        let last = lines[header_lines - 1].0;
        return Err(
            CaptureError::new(path, "header only: no data rows after it").at(Some(last), None),
        );
    }
    let names: Vec<String> = if has_header {
        delimiter
            .split(first)
            .iter()
            .map(|n| bare(n).to_string())
            .collect()
    } else {
        (0..delimiter.split(first).len())
            .map(|i| i.to_string())
            .collect()
    };
    let lines_before_data = lines.get(header_lines).map_or(first_line, |&(l, _)| l - 1);
    Ok(Kind::Text(TextLayout {
        bom_bytes,
        encoding,
        delimiter,
        decimal,
        names,
        has_header,
        lines_before_data,
        metadata_lines: first_line - 1,
    }))
}

/// How many of the first `lines` are an instrument's metadata (`Model,MSO44`,
/// `Record Length,10000`, `Label,,`): before the first row of numbers, the lines up to the
/// last one whose number of fields is not the data's (but for a wider header just before
/// the data), and after it lines of mostly empty fields; the header (and units lines)
/// follow. A line of numbers only is never metadata
/// (a malformed first row is reported, not skipped).
fn metadata_lines(lines: &[(u64, &str)], delimiter: Delimiter, decimal: DecimalMark) -> usize {
    let sample = &lines[..lines.len().min(50)];
    let fields = delimiter.split(sample[sample.len() - 1].1).len();
    let count = |line: &str| delimiter.split(line).len();
    let all_numbers = |line: &str| delimiter.split(line).iter().all(|f| is_number(f, decimal));
    let Some(data) = lines
        .iter()
        .position(|(_, l)| count(l) == fields && all_numbers(l))
    else {
        return 0;
    };
    // A header wider than the rows (a trailing delimiter, a name over an empty column) is
    // the header, not metadata.
    let end = match data.checked_sub(1) {
        Some(h) if count(lines[h].1) > fields => h,
        _ => data,
    };
    let Some(last_other) = lines[..end].iter().rposition(|(_, l)| count(l) != fields) else {
        return 0;
    };
    let mostly_empty = |line: &str| {
        let f = delimiter.split(line);
        2 * f.iter().filter(|x| bare(x).is_empty()).count() >= f.len()
    };
    let mut metadata = last_other + 1;
    while metadata + 1 < data && mostly_empty(lines[metadata].1) {
        metadata += 1;
    }
    if lines[..data].iter().any(|(_, l)| all_numbers(l)) {
        return 0;
    }
    metadata
}

/// The encoding of text without a byte-order mark: UTF-8 if it is valid UTF-8 (but for a
/// character cut by the end of an incomplete head), else Latin-1 if no byte is a control
/// character; else a binary file, named with its line and column.
fn text_encoding(path: &Path, bytes: &[u8], complete: bool) -> Result<Encoding, CaptureError> {
    let (valid_up_to, invalid) = match std::str::from_utf8(bytes) {
        Ok(_) => (bytes.len(), false),
        Err(e) => (e.valid_up_to(), e.error_len().is_some() || complete),
    };
    if let Some(at) = bytes[..valid_up_to].iter().position(|&b| b == 0) {
        return Err(binary(path, bytes, at));
    }
    if !invalid {
        return Ok(Encoding::Utf8);
    }
    if is_latin1_text(bytes) {
        return Ok(Encoding::Latin1);
    }
    let at = bytes
        .iter()
        .position(|&b| !is_latin1_text(&[b]))
        .unwrap_or(valid_up_to);
    Err(binary(path, bytes, at))
}

/// `,` when the numbers of the data are written with decimal commas (`0,5` with a
/// delimiter other than `,`, and no number written with a point), else `.`.
fn guess_decimal(lines: &[(u64, &str)], delimiter: Delimiter) -> DecimalMark {
    if delimiter == Delimiter::Byte(b',') {
        return DecimalMark::Point;
    }
    let tail = &lines[lines.len().saturating_sub(50)..];
    let fields = || tail.iter().flat_map(|(_, l)| delimiter.split(l));
    let comma = fields()
        .filter(|f| bare(f).contains(',') && is_number(f, DecimalMark::Comma))
        .count();
    let point = fields()
        .filter(|f| bare(f).contains('.') && is_number(f, DecimalMark::Point))
        .count();
    if comma > 0 && point == 0 {
        DecimalMark::Comma
    } else {
        DecimalMark::Point
    }
}

fn binary(path: &Path, bytes: &[u8], at: usize) -> CaptureError {
    let before = &bytes[..at];
    let line = before.iter().filter(|&&b| b == b'\n').count() as u64 + 1;
    let column = at
        - before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |p| p + 1)
        + 1;
    CaptureError::new(
        path,
        format!(
            "not a text capture: binary data (byte 0x{:02x}) where text was expected; \
             captures are delimited text (UTF-8, Latin-1, or UTF-16 with its byte-order mark), \
             .npy or .npz",
            bytes[at]
        ),
    )
    .at(Some(line), Some(column))
}

/// The delimiter that splits the most lines into the same number (at least 2) of fields
/// as the last line does; tab, `;`, `,`, `|` in that order on a tie (`;` before `,` for
/// files with decimal commas; never `,` with decimal commas stated); runs of blanks if none
/// splits.
fn guess_delimiter(lines: &[(u64, &str)], comma_decimal: bool) -> Delimiter {
    let sample = &lines[..lines.len().min(50)];
    let mut best = (0, Delimiter::Whitespace);
    for d in [b'\t', b';', b',', b'|'].map(Delimiter::Byte) {
        if comma_decimal && d == Delimiter::Byte(b',') {
            continue;
        }
        let last = d.split(sample[sample.len() - 1].1).len();
        if last < 2 {
            continue;
        }
        let agreeing = sample
            .iter()
            .filter(|(_, l)| d.split(l).len() == last)
            .count();
        if agreeing > best.0 {
            best = (agreeing, d);
        }
    }
    best.1
}
