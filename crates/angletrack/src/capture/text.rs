//! Rows of delimited text, line by line: fields split at a delimiter byte (outside double
//! quotes) or at runs of blanks; blank lines and `#` comment lines skipped; every row keeps
//! its line number, counted the same for `\n` and `\r\n` line ends. UTF-16 text is read
//! through a transcoder to UTF-8.

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use super::encoding::{Encoding, Utf16Reader};
use super::error::CaptureError;
use super::sniff::{DecimalMark, Delimiter, TextLayout};
use super::source::{Filled, RawRows, RowSource, field_error, parse_field};

/// The rows of a text capture.
pub struct TextSource {
    path: PathBuf,
    names: Vec<String>,
    delimiter: Delimiter,
    decimal_comma: bool,
    /// Bytes of the file per byte of text read (2 for UTF-16's ASCII), for progress.
    bytes_per_byte: u64,
    reader: BufReader<Box<dyn Read + Send>>,
    line: Vec<u8>,
    /// The fields of the current line, as byte ranges of `line`.
    fields: Vec<(usize, usize)>,
    number: u64,
    bytes_read: u64,
}

impl TextSource {
    /// Opens `path` laid out as `layout`, positioned at its first data row.
    pub fn open(path: &Path, layout: &TextLayout) -> Result<Self, CaptureError> {
        let io = |e: std::io::Error| CaptureError::io(path, &e);
        let mut file = File::open(path).map_err(io)?;
        file.seek(SeekFrom::Start(layout.bom_bytes)).map_err(io)?;
        let (file, bytes_per_byte): (Box<dyn Read + Send>, u64) = match layout.encoding {
            Encoding::Utf16Le | Encoding::Utf16Be => (
                Box::new(Utf16Reader::new(BufReader::new(file), layout.encoding)),
                2,
            ),
            Encoding::Utf8 | Encoding::Latin1 => (Box::new(file), 1),
        };
        let mut source = Self {
            path: path.to_path_buf(),
            names: layout.names.clone(),
            delimiter: layout.delimiter,
            decimal_comma: layout.decimal == DecimalMark::Comma,
            bytes_per_byte,
            reader: BufReader::with_capacity(1 << 20, file),
            line: Vec::new(),
            fields: Vec::new(),
            number: 0,
            bytes_read: 0,
        };
        while source.number < layout.lines_before_data && source.next_line()? {}
        Ok(source)
    }

    /// Reads the next line into `line`; `false` at the end of the file.
    fn next_line(&mut self) -> Result<bool, CaptureError> {
        self.line.clear();
        let n = self
            .reader
            .read_until(b'\n', &mut self.line)
            .map_err(|e| CaptureError::io(&self.path, &e).at(Some(self.number + 1), None))?;
        self.number += 1;
        self.bytes_read += n as u64;
        Ok(n > 0)
    }

    /// Splits `line` into `fields`; `false` for a blank or comment line.
    fn split(&mut self) -> Result<bool, CaptureError> {
        let text = self.line.trim_ascii();
        if text.is_empty() || text.starts_with(b"#") {
            return Ok(false);
        }
        if let Some(at) = self.line.iter().position(|&b| b == 0) {
            return Err(
                CaptureError::new(&self.path, "not a text capture: a NUL byte")
                    .at(Some(self.number), Some(at + 1)),
            );
        }
        self.fields.clear();
        let line = &self.line;
        match self.delimiter {
            Delimiter::Byte(d) => {
                let (mut start, mut quoted) = (0, false);
                for (i, &b) in line.iter().enumerate() {
                    if b == b'"' {
                        quoted = !quoted;
                    } else if b == d && !quoted {
                        self.fields.push((start, i));
                        start = i + 1;
                    }
                }
                self.fields.push((start, line.len()));
            }
            Delimiter::Whitespace => {
                let mut start = None;
                for (i, &b) in line.iter().enumerate() {
                    match (b.is_ascii_whitespace(), start) {
                        (true, Some(s)) => {
                            self.fields.push((s, i));
                            start = None;
                        }
                        (false, None) => start = Some(i),
                        _ => {}
                    }
                }
                if let Some(s) = start {
                    self.fields.push((s, line.len()));
                }
            }
        }
        Ok(true)
    }

    /// Parses the chosen `columns` of the current line into `rows`.
    fn push_row(&self, columns: &[usize], rows: &mut RawRows) -> Result<(), CaptureError> {
        let field = |c: usize| self.fields.get(c).map(|&(a, b)| &self.line[a..b]);
        for (k, &c) in columns.iter().enumerate() {
            let text = field(c);
            match text.and_then(|t| parse_field(t, self.decimal_comma)) {
                Some(Ok((value, integer))) => {
                    rows.columns[k].push(value);
                    rows.integers[k] &= integer;
                }
                Some(Err(())) | None => {
                    let name = self.names.get(c).map_or("", String::as_str);
                    let text = text.filter(|t| !t.trim_ascii().is_empty());
                    let count = self.fields.len();
                    return Err(field_error(
                        &self.path,
                        self.number,
                        c + 1,
                        name,
                        text,
                        count,
                    ));
                }
            }
        }
        rows.lines.push(self.number);
        Ok(())
    }
}

impl core::fmt::Debug for TextSource {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "TextSource({}, line {})",
            self.path.display(),
            self.number
        )
    }
}

impl RowSource for TextSource {
    fn read(&mut self, columns: &[usize], rows: &mut RawRows, max_rows: usize) -> Filled {
        while rows.lines.len() < max_rows && self.next_line()? {
            if self.split()? {
                self.push_row(columns, rows)?;
            }
        }
        Ok(())
    }

    fn bytes_read(&self) -> u64 {
        self.bytes_read * self.bytes_per_byte
    }
}
