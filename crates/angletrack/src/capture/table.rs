//! [`TableWriter`]: a table of named numeric columns written chunk by chunk in constant
//! memory, as CSV text (each float the shortest decimal that reads back to it, by `ryu`), a
//! NumPy `.npy` structured array or an `.npz` of one array per column; written beside the
//! target and renamed over it when complete. The estimates' writer and every other table the
//! tools write (a resolver's pairs, the fixed-point chain's integers) go through it.

use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use super::error::CaptureError;
use super::npy_out::{NpzColumn, npy_header, write_npz};
use super::output::OutputFile;

/// How a table is stored, from the output file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EstimatesFormat {
    /// Comma-separated text with a header line of the column names (`.csv`).
    Csv,
    /// A NumPy structured array, one record per row, one field per column (`.npy`).
    Npy,
    /// A NumPy `.npz` archive of one 1-D array per column, named as the columns.
    Npz,
}

impl EstimatesFormat {
    /// The format of `path` from its extension (any case): `.csv`, `.npy` or `.npz`;
    /// `None` for any other, which would hide what the file holds.
    ///
    /// ```
    /// use angletrack::capture::EstimatesFormat;
    /// use std::path::Path;
    /// assert_eq!(EstimatesFormat::of_path(Path::new("est.NPZ")), Some(EstimatesFormat::Npz));
    /// assert_eq!(EstimatesFormat::of_path(Path::new("est.dat")), None);
    /// ```
    pub fn of_path(path: &Path) -> Option<Self> {
        let extension = path.extension().and_then(|e| e.to_str())?;
        [
            ("csv", EstimatesFormat::Csv),
            ("npy", EstimatesFormat::Npy),
            ("npz", EstimatesFormat::Npz),
        ]
        .into_iter()
        .find(|(e, _)| extension.eq_ignore_ascii_case(e))
        .map(|(_, f)| f)
    }
}

/// The numeric type of a table's column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColumnType {
    /// 64-bit float (`<f8`).
    F64,
    /// 32-bit float (`<f4`).
    F32,
    /// 8-bit unsigned integer (`|u1`): fault bits.
    U8,
    /// 32-bit signed integer (`<i4`): binary angles, counts.
    I32,
}

impl ColumnType {
    /// The little-endian numpy type string.
    pub fn npy_type(self) -> &'static str {
        match self {
            ColumnType::F64 => "<f8",
            ColumnType::F32 => "<f4",
            ColumnType::U8 => "|u1",
            ColumnType::I32 => "<i4",
        }
    }

    /// Every column type.
    pub const ALL: [ColumnType; 4] = [
        ColumnType::F64,
        ColumnType::F32,
        ColumnType::U8,
        ColumnType::I32,
    ];

    /// The numpy type name (`numpy.dtype(...).name`): `float64`, `float32`, `uint8`, `int32`.
    pub fn name(self) -> &'static str {
        match self {
            ColumnType::F64 => "float64",
            ColumnType::F32 => "float32",
            ColumnType::U8 => "uint8",
            ColumnType::I32 => "int32",
        }
    }

    /// The type of a numpy type name ([`ColumnType::name`]); `None` for another.
    ///
    /// ```
    /// use angletrack::capture::ColumnType;
    /// assert_eq!(ColumnType::of_name("int32"), Some(ColumnType::I32));
    /// assert_eq!(ColumnType::of_name("int64"), None);
    /// ```
    pub fn of_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }
}

/// One chunk of one column's values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Column<'a> {
    /// Values of a [`ColumnType::F64`] column.
    F64(&'a [f64]),
    /// Values of a [`ColumnType::F32`] column.
    F32(&'a [f32]),
    /// Values of a [`ColumnType::U8`] column.
    U8(&'a [u8]),
    /// Values of a [`ColumnType::I32`] column.
    I32(&'a [i32]),
}

impl Column<'_> {
    /// The values' type.
    pub fn column_type(&self) -> ColumnType {
        match self {
            Column::F64(_) => ColumnType::F64,
            Column::F32(_) => ColumnType::F32,
            Column::U8(_) => ColumnType::U8,
            Column::I32(_) => ColumnType::I32,
        }
    }

    /// The number of values.
    pub fn len(&self) -> usize {
        match self {
            Column::F64(v) => v.len(),
            Column::F32(v) => v.len(),
            Column::U8(v) => v.len(),
            Column::I32(v) => v.len(),
        }
    }

    /// Whether there is no value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Appends value `k`, little-endian, to `out`.
    fn write_le(&self, k: usize, out: &mut impl Write) -> std::io::Result<()> {
        match self {
            Column::F64(v) => out.write_all(&v[k].to_le_bytes()),
            Column::F32(v) => out.write_all(&v[k].to_le_bytes()),
            Column::U8(v) => out.write_all(&[v[k]]),
            Column::I32(v) => out.write_all(&v[k].to_le_bytes()),
        }
    }

    /// Appends all values, little-endian, to `out`.
    fn write_all_le(&self, out: &mut impl Write) -> std::io::Result<()> {
        (0..self.len()).try_for_each(|k| self.write_le(k, out))
    }

    /// Appends value `k` as CSV text to `line`: a float the shortest decimal that reads
    /// back to it, an integer its digits.
    fn push_text(&self, k: usize, line: &mut Vec<u8>, floats: &mut ryu::Buffer) {
        match self {
            Column::F64(v) => line.extend_from_slice(floats.format(v[k]).as_bytes()),
            Column::F32(v) => line.extend_from_slice(floats.format(v[k]).as_bytes()),
            Column::U8(v) => line.extend_from_slice(itoa::Buffer::new().format(v[k]).as_bytes()),
            Column::I32(v) => line.extend_from_slice(itoa::Buffer::new().format(v[k]).as_bytes()),
        }
    }
}

/// Where the rows go while they are written.
#[derive(Debug)]
enum Sink {
    /// CSV text or `.npy` records, into the output's temporary file.
    Records(BufWriter<File>),
    /// One temporary file per column, assembled into the `.npz` at the end.
    Columns(Vec<NpzColumn>),
}

/// Writes a table of named numeric columns chunk by chunk in constant memory.
///
/// ```
/// use angletrack::capture::{Column, ColumnType, TableWriter};
/// let path = std::env::temp_dir().join("angletrack_doc_table.csv");
/// let mut w = TableWriter::create(&path, &[("time_s", ColumnType::F64), ("angle", ColumnType::I32)])
///     .map_err(|e| e.to_string())?;
/// w.write(&[Column::F64(&[0.0, 1e-4]), Column::I32(&[-5, 7])]).map_err(|e| e.to_string())?;
/// assert_eq!(w.finish().map_err(|e| e.to_string())?, 2);
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "time_s,angle\n0.0,-5\n0.0001,7\n");
/// # std::fs::remove_file(&path).unwrap();
/// # Ok::<(), String>(())
/// ```
#[derive(Debug)]
pub struct TableWriter {
    path: PathBuf,
    output: OutputFile,
    sink: Sink,
    format: EstimatesFormat,
    columns: Vec<(String, ColumnType)>,
    /// The `.npy` header's length: room for any record count, written when it is known.
    npy_header_bytes: usize,
    rows: u64,
}

impl TableWriter {
    /// Starts `path` (format from its extension, [`EstimatesFormat::of_path`]; another
    /// extension is refused) for a table of `columns` (names and types, in file order; at
    /// least one, each name a distinct identifier as numpy's fields need). The rows go to a
    /// temporary file beside `path`, renamed to it by [`finish`](Self::finish): a writer
    /// dropped before leaves `path` as it was.
    pub fn create(
        path: impl AsRef<Path>,
        columns: &[(&str, ColumnType)],
    ) -> Result<Self, CaptureError> {
        let path = path.as_ref();
        let format = EstimatesFormat::of_path(path).ok_or_else(|| {
            CaptureError::new(
                path,
                "output: the estimates' format follows the file's extension: .csv (text), .npy \
                 (a structured array) or .npz (one array per column)",
            )
        })?;
        check_names(path, columns)?;
        let mut output = OutputFile::create(path)?;
        let io = |e: std::io::Error| CaptureError::io(path, &e);
        let sink = match format {
            EstimatesFormat::Npz => Sink::Columns(
                columns
                    .iter()
                    .map(|&(name, kind)| NpzColumn::create(path, name, kind.npy_type()))
                    .collect::<Result<_, _>>()?,
            ),
            _ => Sink::Records(BufWriter::with_capacity(
                1 << 20,
                output.file().try_clone().map_err(io)?,
            )),
        };
        let mut writer = Self {
            path: path.to_path_buf(),
            output,
            sink,
            format,
            columns: columns.iter().map(|&(n, t)| (n.to_owned(), t)).collect(),
            npy_header_bytes: 0,
            rows: 0,
        };
        writer.npy_header_bytes =
            npy_header(&writer.npy_descr(), &format!("({},)", u64::MAX), 0).len();
        if writer.npy_header_bytes > usize::from(u16::MAX) {
            return Err(CaptureError::new(
                path,
                "columns: too many for the header of a .npy (64 kB)",
            ));
        }
        let header = match writer.format {
            EstimatesFormat::Csv => {
                let names: Vec<&str> = columns.iter().map(|&(n, _)| n).collect();
                format!("{}\n", names.join(",")).into_bytes()
            }
            EstimatesFormat::Npy => writer.npy_header(),
            EstimatesFormat::Npz => Vec::new(),
        };
        if let Sink::Records(out) = &mut writer.sink {
            out.write_all(&header).map_err(io)?;
        }
        Ok(writer)
    }

    /// The target path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The columns' names and types, in file order.
    pub fn columns(&self) -> &[(String, ColumnType)] {
        &self.columns
    }

    /// The `.npy` structured type of the columns.
    fn npy_descr(&self) -> String {
        let fields: Vec<String> = self
            .columns
            .iter()
            .map(|(name, kind)| format!("('{name}', '{}')", kind.npy_type()))
            .collect();
        format!("[{}]", fields.join(", "))
    }

    /// The `.npy` (version 1.0) header for the records written so far, padded to the room
    /// kept for any count: the header written last is as long as the first.
    fn npy_header(&self) -> Vec<u8> {
        npy_header(
            &self.npy_descr(),
            &format!("({},)", self.rows),
            self.npy_header_bytes,
        )
    }

    /// Appends a chunk: one [`Column`] per column, in file order, of the column's type, all
    /// of one length. Refused (naming the column) otherwise, with nothing written.
    pub fn write(&mut self, values: &[Column<'_>]) -> Result<(), CaptureError> {
        if values.len() != self.columns.len() {
            return Err(CaptureError::new(
                &self.path,
                format!(
                    "columns: {} given for a table of {}",
                    values.len(),
                    self.columns.len()
                ),
            ));
        }
        let n = values.first().map_or(0, Column::len);
        for ((name, kind), value) in self.columns.iter().zip(values) {
            if value.column_type() != *kind {
                return Err(CaptureError::new(
                    &self.path,
                    format!(
                        "{name}: values of numpy type {} for a column of {}",
                        value.column_type().npy_type(),
                        kind.npy_type()
                    ),
                ));
            }
            if value.len() != n {
                return Err(CaptureError::new(
                    &self.path,
                    format!(
                        "{name}: {} values where the first column has {n}",
                        value.len()
                    ),
                ));
            }
        }
        let result = match (&mut self.sink, self.format) {
            (Sink::Records(out), EstimatesFormat::Csv) => write_csv(out, values, n),
            (Sink::Records(out), _) => {
                (0..n).try_for_each(|k| values.iter().try_for_each(|v| v.write_le(k, out)))
            }
            (Sink::Columns(columns), _) => columns
                .iter_mut()
                .zip(values)
                .try_for_each(|(column, v)| v.write_all_le(&mut column.out)),
        };
        result.map_err(|e| CaptureError::io(&self.path, &e))?;
        self.rows += n as u64;
        Ok(())
    }

    /// Completes the file (a `.npy` gets its final record count, an `.npz` its arrays),
    /// renames it to the target and returns the rows written.
    pub fn finish(mut self) -> Result<u64, CaptureError> {
        let path = self.path.clone();
        let io = |e: std::io::Error| CaptureError::io(&path, &e);
        match std::mem::replace(&mut self.sink, Sink::Columns(Vec::new())) {
            Sink::Records(mut out) => {
                if self.format == EstimatesFormat::Npy {
                    let header = self.npy_header();
                    out.flush()
                        .and_then(|()| out.seek(SeekFrom::Start(0)))
                        .and_then(|_| out.write_all(&header))
                        .map_err(io)?;
                }
                out.flush().map_err(io)?;
            }
            Sink::Columns(columns) => {
                let file = self.output.file().try_clone().map_err(io)?;
                let mut out = BufWriter::with_capacity(1 << 20, file);
                write_npz(&mut out, columns, self.rows, &path)?;
                out.flush().map_err(io)?;
            }
        }
        self.output.commit()?;
        Ok(self.rows)
    }
}

/// Refuses no column, a name that is not an identifier (a CSV header, a numpy field and an
/// `.npz` member all take it), and a name given twice.
fn check_names(path: &Path, columns: &[(&str, ColumnType)]) -> Result<(), CaptureError> {
    if columns.is_empty() {
        return Err(CaptureError::new(
            path,
            "columns: a table needs one at least",
        ));
    }
    for (k, &(name, _)) in columns.iter().enumerate() {
        let identifier = name
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        if !identifier {
            return Err(CaptureError::new(
                path,
                format!("columns: {name:?} is not a name of letters, digits and underscores"),
            ));
        }
        if columns[..k].iter().any(|&(other, _)| other == name) {
            return Err(CaptureError::new(
                path,
                format!("columns: {name} given twice"),
            ));
        }
    }
    Ok(())
}

/// The rows `0..n` of `values` as CSV lines.
fn write_csv(out: &mut impl Write, values: &[Column<'_>], n: usize) -> std::io::Result<()> {
    let mut floats = ryu::Buffer::new();
    let mut line = Vec::with_capacity(32 * values.len());
    for k in 0..n {
        line.clear();
        for (j, value) in values.iter().enumerate() {
            if j > 0 {
                line.push(b',');
            }
            value.push_text(k, &mut line, &mut floats);
        }
        line.push(b'\n');
        out.write_all(&line)?;
    }
    Ok(())
}
