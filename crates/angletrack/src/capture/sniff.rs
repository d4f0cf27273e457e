//! What kind of file a capture is, from its first bytes: a NumPy array, a zip of arrays
//! (`.npz`), or text, whose byte-order mark, delimiter and header lines are found here.

use std::path::Path;

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
    /// Bytes of a UTF-8 byte-order mark to skip (0 or 3).
    pub bom_bytes: u64,
    /// The field delimiter.
    pub delimiter: Delimiter,
    /// The column names (the header's; the 0-based indices without a header).
    pub names: Vec<String>,
    /// Whether the first line is a header.
    pub has_header: bool,
    /// Lines before the data (header, units lines, comments and blank lines).
    pub lines_before_data: u64,
}

/// Bytes read to tell the kind and the layout.
pub const SNIFF_BYTES: usize = 64 * 1024;
const NPY_MAGIC: &[u8] = b"\x93NUMPY";
const ZIP_MAGIC: &[u8] = b"PK\x03\x04";
const BOM: &[u8] = b"\xEF\xBB\xBF";

fn is_number(field: &str) -> bool {
    let f = field.trim().trim_matches('"');
    !f.is_empty() && f.parse::<f64>().is_ok()
}

fn skipped(line: &str) -> bool {
    let t = line.trim();
    t.is_empty() || t.starts_with('#')
}

/// The kind and layout of a capture whose first bytes are `head` (the whole file if shorter
/// than [`SNIFF_BYTES`]; `complete` says whether it is); `delimiter` is the user's choice.
pub fn sniff(
    path: &Path,
    head: &[u8],
    complete: bool,
    delimiter: Option<Delimiter>,
) -> Result<Kind, CaptureError> {
    if head.starts_with(NPY_MAGIC) {
        return Ok(Kind::Npy);
    }
    if head.starts_with(ZIP_MAGIC) {
        return Ok(Kind::Npz);
    }
    let bom_bytes = if head.starts_with(BOM) { 3 } else { 0 };
    let text = text_of(path, &head[bom_bytes as usize..], complete)?;
    let mut lines: Vec<(u64, &str)> = Vec::new();
    let complete_lines = if complete {
        text.lines().count()
    } else {
        text.lines().count().saturating_sub(1)
    };
    for (i, line) in text.lines().take(complete_lines).enumerate() {
        if !skipped(line) {
            lines.push((i as u64 + 1, line));
        }
    }
    let Some(&(first_line, first)) = lines.first() else {
        return Err(CaptureError::new(path, "empty file: no header and no data").at(Some(1), None));
    };
    let delimiter = delimiter.unwrap_or_else(|| guess_delimiter(&lines));
    // The header is the first line if any field is not a number; units lines after it have
    // no number at all.
    let has_header = !delimiter.split(first).iter().all(|f| is_number(f));
    let mut header_lines = usize::from(has_header);
    while has_header
        && header_lines < lines.len()
        && !delimiter
            .split(lines[header_lines].1)
            .iter()
            .any(|f| is_number(f))
    {
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
            .map(|n| n.trim().trim_matches('"').to_string())
            .collect()
    } else {
        (0..delimiter.split(first).len())
            .map(|i| i.to_string())
            .collect()
    };
    let lines_before_data = lines.get(header_lines).map_or(first_line, |&(l, _)| l - 1);
    Ok(Kind::Text(TextLayout {
        bom_bytes,
        delimiter,
        names,
        has_header,
        lines_before_data,
    }))
}

/// `bytes` as UTF-8 text; a NUL byte or invalid UTF-8 (other than a sequence cut by the
/// end of an incomplete head) is a binary file, named with its line and column.
fn text_of<'a>(path: &Path, bytes: &'a [u8], complete: bool) -> Result<&'a str, CaptureError> {
    let (valid_up_to, invalid) = match std::str::from_utf8(bytes) {
        Ok(_) => (bytes.len(), false),
        Err(e) => (e.valid_up_to(), e.error_len().is_some() || complete),
    };
    let valid = &bytes[..valid_up_to];
    if let Some(at) = valid.iter().position(|&b| b == 0) {
        return Err(binary(path, bytes, at));
    }
    if invalid {
        return Err(binary(path, bytes, valid_up_to));
    }
    Ok(std::str::from_utf8(valid).unwrap_or_default())
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
            "not a text capture: binary data (byte 0x{:02x}) where UTF-8 text was expected; \
             captures are delimited text, .npy or .npz",
            bytes[at]
        ),
    )
    .at(Some(line), Some(column))
}

/// The delimiter that splits the most lines into the same number (at least 2) of fields
/// as the last line does; tab, `;`, `,`, `|` in that order on a tie (`;` before `,` for
/// files with decimal commas); runs of blanks if none splits.
fn guess_delimiter(lines: &[(u64, &str)]) -> Delimiter {
    let sample = &lines[..lines.len().min(50)];
    let mut best = (0, Delimiter::Whitespace);
    for d in [b'\t', b';', b',', b'|'].map(Delimiter::Byte) {
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
