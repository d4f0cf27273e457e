//! [`CaptureReader`]: a capture of any size read in chunks of rows, each row checked (time
//! finite, increasing and evenly spaced; reference finite) and the time column converted to
//! seconds.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

use super::columns::{ColumnMap, ResolvedColumns, Role, resolve};
use super::encoding::Encoding;
use super::error::CaptureError;
use super::npy::{NpySource, NpzSource};
use super::sniff::{DecimalMark, Delimiter, Kind, SNIFF_BYTES, TextLayout, TextOptions, sniff};
use super::source::{RawRows, RowSource};
use super::text::TextSource;
use super::time::{SpacingCheck, TimeUnit};

/// How to read a capture; the defaults sniff everything.
#[derive(Debug, Clone, PartialEq)]
pub struct CaptureOptions {
    /// Which columns hold what (roles it leaves out get their usual header names).
    pub columns: ColumnMap,
    /// The field delimiter of a text capture (`None`: sniffed).
    pub delimiter: Option<Delimiter>,
    /// The decimal mark of a text capture (`None`: sniffed, `,` for numbers such as `0,5`
    /// with another delimiter).
    pub decimal: Option<DecimalMark>,
    /// Lines skipped at the start of a text capture, before its header (an instrument's
    /// metadata; metadata lines of fewer or more fields than the data are skipped anyway).
    pub skip_rows: u64,
    /// The unit of the time column.
    pub time_unit: TimeUnit,
    /// The true sample rate (Hz), if the user states it: the time column's spacing is then
    /// not checked (rounded or jittered time stamps), only its order.
    pub sample_rate_hz: Option<f64>,
    /// Rows per chunk (at least 2).
    pub chunk_rows: usize,
}

impl Default for CaptureOptions {
    fn default() -> Self {
        Self {
            columns: ColumnMap::default(),
            delimiter: None,
            decimal: None,
            skip_rows: 0,
            time_unit: TimeUnit::Seconds,
            sample_rate_hz: None,
            chunk_rows: 1 << 16,
        }
    }
}

/// `text, delimiter ;` and what else was not the default: `decimal comma`, the encoding,
/// the metadata lines skipped.
fn text_format(layout: &TextLayout) -> String {
    let mut format = format!("text, delimiter {}", layout.delimiter.name());
    if layout.decimal == DecimalMark::Comma {
        format.push_str(", decimal comma");
    }
    if layout.encoding != Encoding::Utf8 {
        format.push_str(", ");
        format.push_str(layout.encoding.name());
    }
    if layout.metadata_lines > 0 {
        format.push_str(&format!(
            ", {} metadata lines skipped",
            layout.metadata_lines
        ));
    }
    format
}

/// A chunk of samples, each column converted to `f64` (integers exactly) and the time to
/// seconds.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct CaptureChunk {
    /// 0-based index of the chunk's first sample in the capture.
    pub first_sample: u64,
    /// Time stamps (s), if the capture has a time column.
    pub time_s: Option<Vec<f64>>,
    /// The cosine signal.
    pub y_c: Vec<f64>,
    /// The sine signal.
    pub y_s: Vec<f64>,
    /// The reference angle (rad), if the capture has one.
    pub reference_rad: Option<Vec<f64>>,
    /// The resolver's excitation, if the capture has a column for it.
    pub excitation: Option<Vec<f64>>,
}

impl CaptureChunk {
    /// The number of samples.
    pub fn len(&self) -> usize {
        self.y_c.len()
    }

    /// Whether the chunk has no sample.
    pub fn is_empty(&self) -> bool {
        self.y_c.is_empty()
    }
}

/// A capture read chunk by chunk in constant memory.
///
/// ```
/// use angletrack::capture::{CaptureOptions, CaptureReader};
/// let path = std::env::temp_dir().join("angletrack_doc_capture.csv");
/// std::fs::write(&path, "t;sin;cos\n0;0;1\n0.0001;0.01;0.99995\n0.0002;0.02;0.9998\n").unwrap();
/// let options = CaptureOptions { columns: "time=t,y_s=sin,y_c=cos".parse()?, ..Default::default() };
/// let mut reader = CaptureReader::open(&path, options).map_err(|e| e.to_string())?;
/// let chunk = reader.next_chunk().map_err(|e| e.to_string())?.expect("a chunk");
/// assert_eq!(chunk.y_s, [0.0, 0.01, 0.02]);
/// assert!((reader.sample_rate_hz().unwrap() - 1e4).abs() < 1e-6);
/// # std::fs::remove_file(&path).unwrap();
/// # Ok::<(), String>(())
/// ```
pub struct CaptureReader {
    path: PathBuf,
    source: Box<dyn RowSource + Send>,
    layout: ResolvedColumns,
    /// The columns read, in the order of `roles`.
    wanted: Vec<usize>,
    roles: Vec<Role>,
    options: CaptureOptions,
    format: String,
    raw: RawRows,
    chunk: CaptureChunk,
    rows: u64,
    spacing: SpacingCheck,
    total_bytes: u64,
    done: bool,
}

impl core::fmt::Debug for CaptureReader {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "CaptureReader({}, {}, {} rows read)",
            self.path.display(),
            self.format,
            self.rows
        )
    }
}

impl CaptureReader {
    /// Opens `path` (delimited text, `.npy` or `.npz`, told by its content), finds its
    /// layout and columns; nothing is read past the header yet.
    pub fn open(path: impl AsRef<Path>, options: CaptureOptions) -> Result<Self, CaptureError> {
        let path = path.as_ref();
        let fail = |m: String| CaptureError::new(path, m);
        options.check().map_err(|e| fail(e.to_string()))?;
        let mut file = File::open(path).map_err(|e| CaptureError::io(path, &e))?;
        let total_bytes = file.metadata().map_or(0, |m| m.len());
        let mut head = Vec::with_capacity(SNIFF_BYTES);
        (&mut file)
            .take(SNIFF_BYTES as u64)
            .read_to_end(&mut head)
            .map_err(|e| CaptureError::io(path, &e))?;
        let complete = (head.len() as u64) >= total_bytes;
        let stated = TextOptions {
            delimiter: options.delimiter,
            decimal: options.decimal,
            skip_rows: options.skip_rows,
        };
        let kind = sniff(path, &head, complete, stated)?;
        let (source, names, has_header, format): (Box<dyn RowSource + Send>, _, _, _) = match &kind
        {
            Kind::Npy => {
                let (s, names) = NpySource::open(path)?;
                let named = s.has_field_names();
                (Box::new(s), names, named, "npy".to_string())
            }
            Kind::Npz => {
                let (s, names) = NpzSource::open(path)?;
                (Box::new(s), names, true, "npz".to_string())
            }
            Kind::Text(layout) => (
                Box::new(TextSource::open(path, layout)?),
                layout.names.clone(),
                layout.has_header,
                text_format(layout),
            ),
        };
        let layout = resolve(&options.columns, &names, has_header).map_err(fail)?;
        let mut roles: Vec<Role> = vec![Role::Cosine, Role::Sine];
        roles.extend(
            [Role::Time, Role::Reference, Role::Excitation]
                .into_iter()
                .filter(|&r| layout.index(r).is_some()),
        );
        let mut wanted: Vec<usize> = roles.iter().filter_map(|&r| layout.index(r)).collect();
        wanted.extend(&layout.other_times);
        let spacing = SpacingCheck::new(options.sample_rate_hz);
        Ok(Self {
            path: path.to_path_buf(),
            source,
            layout,
            wanted,
            roles,
            options,
            format,
            raw: RawRows::default(),
            chunk: CaptureChunk::default(),
            rows: 0,
            spacing,
            total_bytes,
            done: false,
        })
    }

    /// The next chunk of at most `chunk_rows` samples, checked; `None` after the last.
    /// A capture of fewer than 2 samples is refused at its first chunk.
    pub fn next_chunk(&mut self) -> Result<Option<&CaptureChunk>, CaptureError> {
        if self.done {
            return Ok(None);
        }
        self.raw.clear(self.wanted.len());
        self.source
            .read(&self.wanted, &mut self.raw, self.options.chunk_rows)?;
        let n = self.raw.lines.len();
        if n < self.options.chunk_rows {
            self.done = true;
        }
        if self.rows == 0 && n < 2 {
            return Err(self.too_short(n));
        }
        if n == 0 {
            self.chunk = CaptureChunk::default();
            return Ok(None);
        }
        self.check_and_convert()?;
        self.chunk.first_sample = self.rows;
        self.rows += n as u64;
        Ok(Some(&self.chunk))
    }

    fn too_short(&self, n: usize) -> CaptureError {
        let what = if n == 0 {
            "no data rows"
        } else {
            "only one data row"
        };
        CaptureError::new(
            &self.path,
            format!("{what}: a capture needs at least 2 samples (one row per sample)"),
        )
        .at(self.raw.lines.first().copied(), None)
    }

    /// The raw column of `role` in this chunk (if the capture has one).
    fn raw_column(&self, role: Role) -> Option<usize> {
        self.roles.iter().position(|&r| r == role)
    }

    fn check_and_convert(&mut self) -> Result<(), CaptureError> {
        let raw = &self.raw;
        let (c, s) = (self.raw_column(Role::Cosine), self.raw_column(Role::Sine));
        let copy = |i: Option<usize>, out: &mut Vec<f64>| {
            out.clear();
            out.extend_from_slice(&raw.columns[i.unwrap_or(0)]);
        };
        copy(c, &mut self.chunk.y_c);
        copy(s, &mut self.chunk.y_s);
        for (role, what) in [
            (Role::Reference, "reference angle"),
            (Role::Excitation, "excitation"),
        ] {
            let slot = match role {
                Role::Reference => self.chunk.reference_rad.take(),
                _ => self.chunk.excitation.take(),
            };
            let value = match self.raw_column(role) {
                Some(r) => {
                    let index = self.layout.index(role).unwrap_or(0);
                    let column = &raw.columns[r];
                    if let Some(k) = column.iter().position(|v| !v.is_finite()) {
                        return Err(self.value_error(k, index, what, column[k]));
                    }
                    let mut out = slot.unwrap_or_default();
                    copy(Some(r), &mut out);
                    Some(out)
                }
                None => None,
            };
            match role {
                Role::Reference => self.chunk.reference_rad = value,
                _ => self.chunk.excitation = value,
            }
        }
        self.chunk.time_s = match self.raw_column(Role::Time) {
            Some(t) => Some(self.checked_time(t)?),
            None => None,
        };
        Ok(())
    }

    fn value_error(&self, k: usize, index: usize, what: &str, value: f64) -> CaptureError {
        CaptureError::new(
            &self.path,
            format!(
                "column {:?}: the {what} is {value}: it must be finite",
                self.layout.name(index)
            ),
        )
        .at(Some(self.raw.lines[k]), Some(index + 1))
    }

    /// The time column of raw column `t` in seconds, checked: finite, increasing, agreeing
    /// with the other time columns, evenly spaced (unless the rate was stated).
    fn checked_time(&mut self, t: usize) -> Result<Vec<f64>, CaptureError> {
        let index = self.layout.index(Role::Time).unwrap_or(0);
        let raw = &self.raw.columns[t];
        if let Some(k) = raw.iter().position(|v| !v.is_finite()) {
            return Err(self.value_error(k, index, "time", raw[k]));
        }
        for (o, &other) in self.layout.other_times.iter().enumerate() {
            let column = &self.raw.columns[self.roles.len() + o];
            let disagree = |(a, b): (&f64, &f64)| (a - b).abs() > 1e-9 * a.abs().max(b.abs());
            if let Some(k) = raw.iter().zip(column).position(disagree) {
                return Err(CaptureError::new(
                    &self.path,
                    format!(
                        "time column {:?} (column {}) says {} but the time column {:?} says {}: \
                         the channels were not sampled together; map the columns of one \
                         channel pair",
                        self.layout.name(other),
                        other + 1,
                        column[k],
                        self.layout.name(index),
                        raw[k]
                    ),
                )
                .at(Some(self.raw.lines[k]), Some(other + 1)));
            }
        }
        let unit = self.options.time_unit;
        let mut time_s = self.chunk.time_s.take().unwrap_or_default();
        time_s.clear();
        time_s.extend(raw.iter().map(|&v| unit.to_seconds(v)));
        let name = self.layout.name(index).to_string();
        self.spacing.check(&time_s, unit).map_err(|(k, m)| {
            CaptureError::new(&self.path, format!("column {name:?}: {m}"))
                .at(Some(self.raw.lines[k]), Some(index + 1))
        })?;
        Ok(time_s)
    }

    /// The chunk the last [`next_chunk`](Self::next_chunk) returned (`None` before the
    /// first and after the last).
    pub fn last_chunk(&self) -> Option<&CaptureChunk> {
        Some(&self.chunk).filter(|c| !c.is_empty())
    }

    /// The sample rate (Hz): the stated one, else the time column's (its mean spacing over
    /// the rows read so far), else `None`.
    pub fn sample_rate_hz(&self) -> Option<f64> {
        self.options
            .sample_rate_hz
            .or_else(|| self.spacing.mean_step_s().map(|s| 1.0 / s))
    }

    /// The number of samples read so far (all of them once [`next_chunk`](Self::next_chunk)
    /// has returned `None`).
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// `npy`, `npz` or `text, delimiter ;` (with `, decimal comma`, the encoding if not
    /// UTF-8, `, N metadata lines skipped`).
    pub fn format(&self) -> &str {
        &self.format
    }

    /// The columns used, as `(role, column name)`.
    pub fn mapping(&self) -> Vec<(Role, String)> {
        self.layout.mapping()
    }

    /// The element type of the samples: the array's dtype for `.npy`/`.npz`; for text,
    /// `int64` while every `y_c` and `y_s` value read was written as a whole number (raw ADC
    /// counts), else `float64`. The chunks hold them as `f64`, exactly.
    pub fn sample_dtype(&self) -> String {
        self.source.stored_dtype().unwrap_or_else(|| {
            let integers = self.raw.integers.iter().take(2).all(|&i| i);
            if integers { "int64" } else { "float64" }.to_string()
        })
    }

    /// Bytes of the file read so far, and its size (for progress).
    pub fn progress_bytes(&self) -> (u64, u64) {
        (self.source.bytes_read(), self.total_bytes)
    }
}
