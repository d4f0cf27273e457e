//! Rows of delimited text: a one-byte delimiter through the `csv` crate (quotes, comment
//! lines), runs of blanks line by line.

use std::fs::File;
use std::io::{BufRead, BufReader, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use super::error::CaptureError;
use super::sniff::{Delimiter, TextLayout};
use super::source::{Filled, RawRows, RowSource, field_error, parse_field};

/// The rows of a text capture.
#[derive(Debug)]
pub struct TextSource {
    fields: Fields,
    rows: Rows,
}

/// How the fields of a row become values: the file and its column names, for messages.
#[derive(Debug)]
struct Fields {
    path: PathBuf,
    names: Vec<String>,
}

#[derive(Debug)]
enum Rows {
    Delimited {
        reader: csv::Reader<BufReader<File>>,
        record: csv::ByteRecord,
        bom_bytes: u64,
    },
    Blanks {
        reader: BufReader<File>,
        line: Vec<u8>,
        number: u64,
        bytes_read: u64,
    },
}

impl TextSource {
    /// Opens `path` laid out as `layout`, positioned at its first data row.
    pub fn open(path: &Path, layout: &TextLayout) -> Result<Self, CaptureError> {
        let io = |e: std::io::Error| CaptureError::io(path, &e);
        let mut file = File::open(path).map_err(io)?;
        file.seek(SeekFrom::Start(layout.bom_bytes)).map_err(io)?;
        let mut reader = BufReader::with_capacity(1 << 20, file);
        let rows = match layout.delimiter {
            Delimiter::Byte(b) => {
                let mut reader = csv::ReaderBuilder::new()
                    .delimiter(b)
                    .has_headers(false)
                    .flexible(true)
                    .comment(Some(b'#'))
                    .from_reader(reader);
                let mut record = csv::ByteRecord::new();
                // Header and units lines: the records that start before the data.
                loop {
                    let position = reader.position().clone();
                    let more = reader
                        .read_byte_record(&mut record)
                        .map_err(|e| csv_error(path, &e))?;
                    if !more || record.position().map_or(0, |p| p.line()) > layout.lines_before_data
                    {
                        reader
                            .seek_raw(
                                SeekFrom::Start(position.byte() + layout.bom_bytes),
                                position,
                            )
                            .map_err(|e| csv_error(path, &e))?;
                        break;
                    }
                }
                Rows::Delimited {
                    reader,
                    record,
                    bom_bytes: layout.bom_bytes,
                }
            }
            Delimiter::Whitespace => {
                let mut line = Vec::new();
                let mut bytes_read = layout.bom_bytes;
                for _ in 0..layout.lines_before_data {
                    line.clear();
                    bytes_read += reader.read_until(b'\n', &mut line).map_err(io)? as u64;
                }
                Rows::Blanks {
                    reader,
                    line,
                    number: layout.lines_before_data,
                    bytes_read,
                }
            }
        };
        Ok(Self {
            fields: Fields {
                path: path.to_path_buf(),
                names: layout.names.clone(),
            },
            rows,
        })
    }
}

impl Fields {
    /// Parses the chosen `columns` of the row at `line` (`count` fields, `field(i)` the
    /// i-th) into `rows`.
    fn push_row<'f>(
        &self,
        line: u64,
        count: usize,
        field: impl Fn(usize) -> Option<&'f [u8]>,
        columns: &[usize],
        rows: &mut RawRows,
    ) -> Result<(), CaptureError> {
        for (k, &c) in columns.iter().enumerate() {
            let text = field(c);
            match text.and_then(parse_field) {
                Some(Ok((value, integer))) => {
                    rows.columns[k].push(value);
                    rows.integers[k] &= integer;
                }
                Some(Err(())) | None => {
                    let name = self.names.get(c).map_or("", String::as_str);
                    let text = text.filter(|t| !t.trim_ascii().is_empty());
                    return Err(field_error(&self.path, line, c + 1, name, text, count));
                }
            }
        }
        rows.lines.push(line);
        Ok(())
    }
}

fn csv_error(path: &Path, e: &csv::Error) -> CaptureError {
    let line = e.position().map(|p| p.line());
    let message = match e.kind() {
        csv::ErrorKind::Utf8 { .. } => "not a text capture: invalid UTF-8".to_string(),
        _ => e.to_string(),
    };
    CaptureError::new(path, message).at(line, None)
}

impl RowSource for TextSource {
    fn read(&mut self, columns: &[usize], rows: &mut RawRows, max_rows: usize) -> Filled {
        let fields = &self.fields;
        let path = fields.path.as_path();
        match &mut self.rows {
            Rows::Delimited { reader, record, .. } => {
                while rows.lines.len() < max_rows {
                    if !reader
                        .read_byte_record(record)
                        .map_err(|e| csv_error(path, &e))?
                    {
                        break;
                    }
                    let line = record.position().map_or(0, |p| p.line());
                    let record = &*record;
                    fields.push_row(line, record.len(), |i| record.get(i), columns, rows)?;
                }
            }
            Rows::Blanks {
                reader,
                line,
                number,
                bytes_read,
            } => {
                while rows.lines.len() < max_rows {
                    line.clear();
                    let n = reader
                        .read_until(b'\n', line)
                        .map_err(|e| CaptureError::io(path, &e).at(Some(*number + 1), None))?;
                    if n == 0 {
                        break;
                    }
                    *number += 1;
                    *bytes_read += n as u64;
                    if std::str::from_utf8(line).is_err() || line.contains(&0) {
                        return Err(CaptureError::new(path, "not a text capture: invalid UTF-8")
                            .at(Some(*number), None));
                    }
                    let text = line.trim_ascii();
                    if text.is_empty() || text.starts_with(b"#") {
                        continue;
                    }
                    let split: Vec<&[u8]> = text
                        .split(|b| b.is_ascii_whitespace())
                        .filter(|f| !f.is_empty())
                        .collect();
                    fields.push_row(
                        *number,
                        split.len(),
                        |i| split.get(i).copied(),
                        columns,
                        rows,
                    )?;
                }
            }
        }
        Ok(())
    }

    fn bytes_read(&self) -> u64 {
        match &self.rows {
            Rows::Delimited {
                reader, bom_bytes, ..
            } => reader.position().byte() + bom_bytes,
            Rows::Blanks { bytes_read, .. } => *bytes_read,
        }
    }
}
