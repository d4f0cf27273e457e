//! Rows of NumPy files (through the `npyz` crate): a 2-D `.npy` array (rows x columns,
//! C order), a 1-D structured `.npy` (one record per row, its numeric fields the columns:
//! `npy_record.rs`), or the named 1-D arrays of an `.npz` (a zip of `.npy` files, stored or
//! deflated, as `numpy.savez` and `numpy.savez_compressed` write), each read as it streams.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use flate2::read::DeflateDecoder;
use npyz::{NpyFile, TypeChar};

use super::error::CaptureError;
use super::npy_record::RecordLayout;
use super::source::{Filled, RawRows, RowSource};

/// The values of an array as `f64` (exactly for integers up to 2^53), in storage order.
type Values = Box<dyn Iterator<Item = std::io::Result<f64>> + Send>;

/// The numpy name of a scalar type of the samples (`None` for a type a capture cannot hold).
pub(super) fn numpy_name(kind: TypeChar, size: u64) -> Option<&'static str> {
    Some(match (kind, size) {
        (TypeChar::Float, 8) => "float64",
        (TypeChar::Float, 4) => "float32",
        (TypeChar::Int, 8) => "int64",
        (TypeChar::Int, 4) => "int32",
        (TypeChar::Int, 2) => "int16",
        (TypeChar::Int, 1) => "int8",
        (TypeChar::Uint, 8) => "uint64",
        (TypeChar::Uint, 4) => "uint32",
        (TypeChar::Uint, 2) => "uint16",
        (TypeChar::Uint, 1) => "uint8",
        _ => return None,
    })
}

/// The values of `file`, its numpy dtype name and whether the dtype is an integer one.
fn values<R: Read + Send + 'static>(file: NpyFile<R>) -> Result<(Values, String, bool), String> {
    let Some(npyz::DType::Plain(ts)) = Some(file.dtype()) else {
        return Err(format!(
            "a nested array (dtype {}) is not supported: save a 2-D array of numbers, a 1-D \
             record array of numeric fields, or one array per column in an .npz",
            file.dtype().descr()
        ));
    };
    let size = ts.size_field();
    macro_rules! as_f64 {
        ($t:ty) => {
            Box::new(
                file.data::<$t>()
                    .map_err(|e| e.to_string())?
                    .map(|v| v.map(|v| v as f64)),
            ) as Values
        };
    }
    let Some(name) = numpy_name(ts.type_char(), size) else {
        return Err(format!(
            "dtype {ts} is not supported: expected integers or float32/float64"
        ));
    };
    let values = match (ts.type_char(), size) {
        (TypeChar::Float, 8) => as_f64!(f64),
        (TypeChar::Float, _) => as_f64!(f32),
        (TypeChar::Int, 8) => as_f64!(i64),
        (TypeChar::Int, 4) => as_f64!(i32),
        (TypeChar::Int, 2) => as_f64!(i16),
        (TypeChar::Int, _) => as_f64!(i8),
        (_, 8) => as_f64!(u64),
        (_, 4) => as_f64!(u32),
        (_, 2) => as_f64!(u16),
        _ => as_f64!(u8),
    };
    Ok((values, name.to_string(), ts.type_char() != TypeChar::Float))
}

/// The most columns of a `.npy` capture: a header claiming more is not a capture (and its
/// row buffer must not be allocated).
pub const MAX_COLUMNS: usize = 1 << 16;

/// The rows of a 2-D `.npy` array (rows x columns), or of a 1-D record array (its numeric
/// fields the columns), streamed.
pub struct NpySource {
    path: PathBuf,
    values: Values,
    dtype: String,
    /// Per column: whether its values are integers, and its numpy type (a record's fields
    /// may differ: the first column read, the cosine signal's, is the samples').
    integer: Vec<bool>,
    column_dtypes: Vec<String>,
    first_column: Option<usize>,
    /// A record array: its columns named by its fields.
    field_names: bool,
    rows_total: u64,
    row: u64,
    buffer: Vec<f64>,
    row_bytes: u64,
}

impl core::fmt::Debug for NpySource {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "NpySource({}, {} x {} {})",
            self.path.display(),
            self.rows_total,
            self.integer.len(),
            self.dtype
        )
    }
}

impl NpySource {
    /// Opens the `.npy` file `path`; the columns are named by their 0-based index, or for a
    /// record array by its fields' names.
    pub fn open(path: &Path) -> Result<(Self, Vec<String>), CaptureError> {
        let fail = |m: String| CaptureError::new(path, m);
        let file = File::open(path).map_err(|e| CaptureError::io(path, &e))?;
        let npy = NpyFile::new(BufReader::with_capacity(1 << 20, file))
            .map_err(|e| fail(format!("not a readable .npy file: {e}")))?;
        let shape = npy.shape().to_vec();
        if npy.order() == npyz::Order::Fortran {
            return Err(fail(
                "a Fortran-ordered array: save numpy.ascontiguousarray(a) (rows x columns)".into(),
            ));
        }
        let source = |values, dtype, integer: Vec<bool>, column_dtypes, rows_total, row_bytes| {
            let columns = integer.len();
            Self {
                path: path.to_path_buf(),
                values,
                dtype,
                integer,
                column_dtypes,
                first_column: None,
                field_names: false,
                rows_total,
                row: 0,
                buffer: vec![0.0; columns],
                row_bytes,
            }
        };
        if let (npyz::DType::Record(_), [rows]) = (npy.dtype(), &shape[..]) {
            let layout = RecordLayout::new(&npy.dtype()).map_err(fail)?;
            let descr = npy.dtype().descr();
            let values = layout.values(npy.into_inner());
            let (names, width) = (layout.names.clone(), layout.width as u64);
            let dtype = format!("record {descr}");
            let mut source = source(values, dtype, layout.integer, layout.dtypes, *rows, width);
            source.field_names = true;
            return Ok((source, names));
        }
        let (rows_total, columns) = match shape[..] {
            [rows, columns] => (rows, columns as usize),
            _ => {
                return Err(fail(format!(
                    "an array of shape {shape:?}: expected 2-D (rows x columns; one row per \
                     sample), a 1-D record array, or an .npz with one array per column"
                )));
            }
        };
        if columns == 0 || columns > MAX_COLUMNS {
            return Err(fail(format!(
                "an array of {columns} columns: expected 2 to {MAX_COLUMNS} (rows x columns)"
            )));
        }
        let item_bytes = npy.header().dtype().num_bytes().unwrap_or(8) as u64;
        let (values, dtype, integer) = values(npy).map_err(fail)?;
        let names = (0..columns).map(|i| i.to_string()).collect();
        let row_bytes = columns as u64 * item_bytes;
        let column_dtypes = vec![dtype.clone(); columns];
        Ok((
            source(
                values,
                dtype,
                vec![integer; columns],
                column_dtypes,
                rows_total,
                row_bytes,
            ),
            names,
        ))
    }
}

impl NpySource {
    /// Whether the columns are named (a record array's fields), not numbered.
    pub fn has_field_names(&self) -> bool {
        self.field_names
    }
}

impl RowSource for NpySource {
    fn read(&mut self, columns: &[usize], rows: &mut RawRows, max_rows: usize) -> Filled {
        if self.first_column.is_none() {
            self.first_column = columns.first().copied();
        }
        while rows.lines.len() < max_rows && self.row < self.rows_total {
            for slot in self.buffer.iter_mut() {
                *slot = match self.values.next() {
                    Some(Ok(v)) => v,
                    Some(Err(e)) => {
                        return Err(CaptureError::io(&self.path, &e).at(Some(self.row + 1), None));
                    }
                    None => {
                        return Err(CaptureError::new(
                            &self.path,
                            "the file ends before its last row",
                        )
                        .at(Some(self.row + 1), None));
                    }
                };
            }
            self.row += 1;
            for (k, &c) in columns.iter().enumerate() {
                rows.columns[k].push(self.buffer[c]);
                rows.integers[k] &= self.integer.get(c).copied().unwrap_or(false);
            }
            rows.lines.push(self.row);
        }
        Ok(())
    }

    fn bytes_read(&self) -> u64 {
        self.row * self.row_bytes
    }

    fn stored_dtype(&self) -> Option<String> {
        let first = self.first_column.and_then(|c| self.column_dtypes.get(c));
        Some(first.unwrap_or(&self.dtype).clone())
    }
}

/// The named 1-D arrays of an `.npz` file, each a column, streamed from the zip (stored or
/// deflated) through a file handle of its own.
pub struct NpzSource {
    path: PathBuf,
    names: Vec<String>,
    columns: Vec<(Values, bool)>,
    dtype: Option<String>,
    rows_total: u64,
    row: u64,
    item_bytes: u64,
}

impl core::fmt::Debug for NpzSource {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "NpzSource({}, row {})", self.path.display(), self.row)
    }
}

impl NpzSource {
    /// Opens the `.npz` file `path`; the columns are its arrays, by name.
    pub fn open(path: &Path) -> Result<(Self, Vec<String>), CaptureError> {
        let archive = archive(path)?;
        let names: Vec<String> = archive
            .file_names()
            .filter_map(|n| n.ok())
            .map(|n| n.strip_suffix(".npy").unwrap_or(&n).to_string())
            .collect();
        let source = Self {
            path: path.to_path_buf(),
            names: names.clone(),
            columns: Vec::new(),
            dtype: None,
            rows_total: 0,
            row: 0,
            item_bytes: 0,
        };
        Ok((source, names))
    }

    /// Opens the arrays of `columns` as streams; they must be 1-D and of one length.
    fn open_columns(&mut self, columns: &[usize]) -> Result<(), CaptureError> {
        let mut archive = archive(&self.path)?;
        for &c in columns {
            let name = &self.names[c];
            let fail = |m: String| CaptureError::new(&self.path, format!("array {name:?}: {m}"));
            let member = format!("{name}.npy");
            let (method, start, size) = {
                let entry = archive.by_name(&member).map_err(|e| fail(e.to_string()))?;
                let start = entry
                    .data_start()
                    .ok_or_else(|| fail("its data cannot be found in the zip".into()))?;
                (entry.compression(), start, entry.compressed_size())
            };
            let mut file = File::open(&self.path).map_err(|e| CaptureError::io(&self.path, &e))?;
            file.seek(SeekFrom::Start(start))
                .map_err(|e| CaptureError::io(&self.path, &e))?;
            let stored = BufReader::with_capacity(1 << 18, file).take(size);
            let stream: Box<dyn Read + Send> = match method {
                zip::CompressionMethod::Stored => Box::new(stored),
                zip::CompressionMethod::Deflated => Box::new(BufReader::with_capacity(
                    1 << 18,
                    DeflateDecoder::new(stored),
                )),
                other => {
                    return Err(fail(format!(
                        "compressed with {other}: save it with numpy.savez or numpy.savez_compressed"
                    )));
                }
            };
            let npy = NpyFile::new(stream).map_err(|e| fail(format!("not a .npy array: {e}")))?;
            let shape = npy.shape().to_vec();
            if shape.iter().filter(|&&d| d != 1).count() > 1 {
                return Err(fail(format!(
                    "shape {shape:?}: expected 1-D (one value per sample)"
                )));
            }
            let len = shape.iter().product::<u64>();
            let first = self.rows_total;
            if !self.columns.is_empty() && first != len {
                return Err(fail(format!(
                    "has {len} values but {:?} has {first}: the columns must be of one length",
                    self.names[columns[0]]
                )));
            }
            let item_bytes = npy.header().dtype().num_bytes().unwrap_or(8) as u64;
            let (values, dtype, integer) = values(npy).map_err(fail)?;
            // The first column asked for is the cosine signal: its dtype is the samples'.
            if self.dtype.is_none() {
                self.dtype = Some(dtype);
            }
            self.rows_total = len;
            self.item_bytes += item_bytes;
            self.columns.push((values, integer));
        }
        Ok(())
    }
}

fn archive(path: &Path) -> Result<zip::ZipArchive<BufReader<File>>, CaptureError> {
    let file = File::open(path).map_err(|e| CaptureError::io(path, &e))?;
    zip::ZipArchive::new(BufReader::new(file))
        .map_err(|e| CaptureError::new(path, format!("not a readable .npz (zip) file: {e}")))
}

impl RowSource for NpzSource {
    fn read(&mut self, columns: &[usize], rows: &mut RawRows, max_rows: usize) -> Filled {
        if self.columns.is_empty() {
            self.open_columns(columns)?;
        }
        let n = (max_rows as u64).min(self.rows_total - self.row);
        for (k, (values, integer)) in self.columns.iter_mut().enumerate() {
            let out = &mut rows.columns[k];
            for i in 0..n {
                match values.next() {
                    Some(Ok(v)) => out.push(v),
                    Some(Err(e)) => {
                        let at = Some(self.row + i + 1);
                        let name = &self.names[columns[k]];
                        return Err(
                            CaptureError::new(&self.path, format!("array {name:?}: {e}"))
                                .at(at, None),
                        );
                    }
                    None => {
                        let name = &self.names[columns[k]];
                        return Err(CaptureError::new(
                            &self.path,
                            format!("array {name:?}: the array ends before its last value"),
                        )
                        .at(Some(self.row + i + 1), None));
                    }
                }
            }
            rows.integers[k] &= *integer;
        }
        rows.lines.extend((self.row + 1)..=(self.row + n));
        self.row += n;
        Ok(())
    }

    fn bytes_read(&self) -> u64 {
        self.row * self.item_bytes
    }

    fn stored_dtype(&self) -> Option<String> {
        self.dtype.clone()
    }
}
