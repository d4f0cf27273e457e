//! `read_capture` and `CaptureReader`: the std crate's capture reader on numpy arrays, the
//! parsing in Rust with the GIL released; `check_outputs` and `write_output`, its rules for
//! what a run writes.

use std::path::PathBuf;
use std::sync::Mutex;

use angletrack::capture::{
    Capture as CoreCapture, CaptureChunk, CaptureOptions, CaptureReader as CoreReader, Role,
    WrittenCaptureOptions, read_capture as core_read_capture,
};
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyDict, PyString};

use crate::arrays::{Column, Count};
use crate::errors::{Error, Result};
use crate::getters::{class_methods, result_class};

/// The text of a `columns` argument: `"y_c=cos,y_s=sin"` or a dict `{"y_c": "cos", "y_s": 1}`
/// (names or 0-based indices); empty for `None` (the usual header names).
fn columns_text(columns: Option<&Bound<'_, PyAny>>) -> Result<String> {
    let Some(columns) = columns.filter(|c| !c.is_none()) else {
        return Ok(String::new());
    };
    if let Ok(text) = columns.cast::<PyString>() {
        return Ok(text.to_cow()?.into_owned());
    }
    let dict = columns
        .cast::<PyDict>()
        .map_err(|_| Error::value("columns", "expected 'y_c=NAME,y_s=NAME,...' or a dict"))?;
    let pairs = dict
        .iter()
        .map(|(role, column)| Ok(format!("{}={}", role.str()?, column.str()?)))
        .collect::<PyResult<Vec<_>>>()?;
    Ok(pairs.join(","))
}

/// The reader's options of the Python arguments, parsed and checked by the crate.
fn options(written: &WrittenCaptureOptions<'_>) -> Result<CaptureOptions> {
    CaptureOptions::parse(written).map_err(|e| Error::value(e.option, e.reason))
}

/// `{role: column name}` of the columns used.
fn mapping_dict<'py>(py: Python<'py>, mapping: &[(Role, String)]) -> Result<Bound<'py, PyDict>> {
    Ok(mapping
        .iter()
        .map(|(role, name)| (role.key(), name))
        .into_py_dict(py)?)
}

result_class! {
    /// A chunk of a capture: float64 arrays of one length (time in seconds).
    PyCaptureChunk = "CaptureChunk" of |py, c: &CaptureChunk| {
        /// 0-based index of the chunk's first sample in the capture.
        first_sample: u64 = c.first_sample,
        /// Time stamps (s), or `None` without a time column.
        time_s: Option<Column<f64>> = c.time_s.clone(),
        /// The cosine signal.
        y_c: Column<f64> = c.y_c.clone(),
        /// The sine signal.
        y_s: Column<f64> = c.y_s.clone(),
        /// The reference angle (rad), or `None`.
        reference_rad: Option<Column<f64>> = c.reference_rad.clone(),
        /// The resolver's excitation (counts), or `None`.
        excitation: Option<Column<f64>> = c.excitation.clone(),
    }
    len y_c;
}

/// A capture read chunk by chunk in constant memory (iterate over it for `CaptureChunk`s).
///
/// `columns`: `"y_c=cos,y_s=sin,time=t,reference=ref"` or a dict; each value a header name,
/// else a 0-based index; roles left out get their usual names (`time`/`t`, `y_c`/`cos`,
/// `y_s`/`sin`, `reference`/`theta`); `time="-"` ignores a time column. `delimiter`: one
/// character, `"tab"` or `"whitespace"` (default: sniffed). `decimal`: `"."` or `","`
/// (default: sniffed, `,` for numbers such as `0,5` beside another delimiter).
/// `skip_rows`: lines before the header (an instrument's metadata; lines of another width
/// than the data are skipped anyway). UTF-8, Latin-1 and UTF-16 (with its byte-order mark)
/// text is decoded. `time_unit`: `s`, `ms`, `us` or `ns`. `sample_rate_hz`: the true rate,
/// which skips the time column's spacing check (rounded, repeated stamps pass). Raises
/// `CaptureError` (file, line, column) on malformed input.
#[pyclass(name = "CaptureReader", module = "angletrack")]
#[derive(Debug)]
pub struct PyCaptureReader {
    // Python objects are shared between threads; the file readers need not be `Sync`.
    reader: Mutex<CoreReader>,
}

impl PyCaptureReader {
    fn reader(&self) -> std::sync::MutexGuard<'_, CoreReader> {
        self.reader
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

class_methods! {
    PyCaptureReader {
        /// The sample rate (Hz): the stated one, else the time column's (mean spacing of the
        /// rows read so far); `None` without either.
        sample_rate_hz: Option<f64> = |this, py| this.reader().sample_rate_hz();
        /// Samples read so far.
        rows: u64 = |this, py| this.reader().rows();
        /// The samples' element type as stored (`int16`; `int64` for whole numbers in text).
        sample_dtype: String = |this, py| this.reader().sample_dtype();
        /// `{role: column name}` of the columns used.
        columns: Result<Bound<'py, PyDict>> = |this, py| mapping_dict(py, &this.reader().mapping());
        /// `npy`, `npz` or `text, delimiter X`.
        format: String = |this, py| this.reader().format().to_string();
        /// The file.
        path: PathBuf = |this, py| this.reader().path().to_path_buf();
        /// `(bytes read, file size)`, for progress.
        progress_bytes: (u64, u64) = |this, py| this.reader().progress_bytes();
    }
    methods {
        #[new]
        #[pyo3(signature = (path, *, columns = None, delimiter = None, decimal = None, skip_rows = Count::Whole(0), time_unit = "s", sample_rate_hz = None, chunk_rows = Count::Whole(65536)), text_signature = "(path, *, columns=None, delimiter=None, decimal=None, skip_rows=0, time_unit='s', sample_rate_hz=None, chunk_rows=65536)")]
        #[allow(clippy::too_many_arguments)]
        fn py_new(
            path: PathBuf,
            columns: Option<&Bound<'_, PyAny>>,
            delimiter: Option<&str>,
            decimal: Option<&str>,
            skip_rows: Count,
            time_unit: &str,
            sample_rate_hz: Option<f64>,
            chunk_rows: Count,
        ) -> Result<Self> {
            let options = options(&WrittenCaptureOptions {
                columns: &columns_text(columns)?,
                delimiter,
                decimal,
                skip_rows: skip_rows.get("skip_rows")?,
                time_unit,
                sample_rate_hz,
                // The crate's rule (at least 2) names it.
                chunk_rows: chunk_rows.get("chunk_rows")?,
            })?;
            Ok(Self {
                reader: Mutex::new(CoreReader::open(path, options)?),
            })
        }

        fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
            slf
        }

        fn __next__(&mut self, py: Python<'_>) -> Result<Option<PyCaptureChunk>> {
            let reader = self
                .reader
                .get_mut()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            let done = py.detach(|| reader.next_chunk().map(|c| c.is_none()))?;
            if done {
                return Ok(None);
            }
            // The chunk was read above; it is borrowed again under the GIL to be copied out (the
            // reader reuses its buffers).
            reader.last_chunk().map(|c| PyCaptureChunk::of(py, c)).transpose()
        }
    }
}

result_class! {
    /// A whole capture: float64 arrays and what was learnt reading it.
    PyCapture = "Capture" of |py, (path, c): (PathBuf, CoreCapture)| {
        /// The number of samples.
        rows: usize = c.samples.len(),
        /// The file.
        path: PathBuf = path,
        /// Time stamps (s), or `None`.
        time_s: Option<Column<f64>> = c.samples.time_s,
        /// The cosine signal (float64; integers exactly).
        y_c: Column<f64> = c.samples.y_c,
        /// The sine signal.
        y_s: Column<f64> = c.samples.y_s,
        /// The reference angle (rad), or `None`.
        reference_rad: Option<Column<f64>> = c.samples.reference_rad,
        /// The stated sample rate, else the time column's mean (Hz); `None` without either.
        sample_rate_hz: Option<f64> = c.sample_rate_hz,
        /// The samples' element type as stored (`int16`; `int64` for whole numbers in text).
        sample_dtype: String = c.sample_dtype,
        /// `{role: column name}` of the columns used.
        columns: Py<PyDict> = mapping_dict(py, &c.mapping)?.unbind(),
        /// `npy`, `npz` or `text, delimiter X`.
        format: String = c.format,
    }
    repr |c| format!("Capture({:?}, {} samples of {}, sample_rate_hz={:?}, {})", c.path, c.rows, c.sample_dtype, c.sample_rate_hz, c.format);
    methods {
        fn __len__(&self) -> usize {
            self.rows
        }
    }
}

/// Reads a whole capture (see `CaptureReader` for the arguments and the checks).
#[pyfunction]
#[pyo3(signature = (path, *, columns = None, delimiter = None, decimal = None, skip_rows = Count::Whole(0), time_unit = "s", sample_rate_hz = None), text_signature = "(path, *, columns=None, delimiter=None, decimal=None, skip_rows=0, time_unit='s', sample_rate_hz=None)")]
#[allow(clippy::too_many_arguments)]
pub fn read_capture(
    py: Python<'_>,
    path: PathBuf,
    columns: Option<&Bound<'_, PyAny>>,
    delimiter: Option<&str>,
    decimal: Option<&str>,
    skip_rows: Count,
    time_unit: &str,
    sample_rate_hz: Option<f64>,
) -> Result<PyCapture> {
    let options = options(&WrittenCaptureOptions {
        columns: &columns_text(columns)?,
        delimiter,
        decimal,
        skip_rows: skip_rows.get("skip_rows")?,
        time_unit,
        sample_rate_hz,
        chunk_rows: CaptureOptions::default().chunk_rows,
    })?;
    let read_path = path.clone();
    let c: CoreCapture = py.detach(|| core_read_capture(read_path, options))?;
    PyCapture::of(py, (path, c))
}

/// The `(name, path)` pairs of a dict `{name: path}` (names `str`, paths `str` or
/// `os.PathLike`), refused naming `parameter`.
fn named_paths(obj: &Bound<'_, PyAny>, parameter: &'static str) -> Result<Vec<(String, PathBuf)>> {
    let pairs = obj
        .cast::<PyDict>()
        .ok()
        .and_then(|d| d.items().extract().ok());
    pairs.ok_or_else(|| {
        let given = crate::gains::type_name(obj);
        Error::value(
            parameter,
            format!("expected a dict {{name: path}}, got {given}"),
        )
    })
}

/// Refuses an output that is (through symbolic links, `..` or hard links) one of the
/// inputs or another output, before anything is written (`angletrack::capture::check_outputs`).
/// `outputs` and `inputs` are dicts `{name: path}`, the names as the user knows the files
/// (`"--output"`, `"capture"`); `None` paths are left out. Raises `CaptureError` naming both.
#[pyfunction]
#[pyo3(signature = (outputs, inputs))]
pub fn check_outputs(outputs: &Bound<'_, PyAny>, inputs: &Bound<'_, PyAny>) -> Result<()> {
    let (outputs, inputs) = (
        named_paths(outputs, "outputs")?,
        named_paths(inputs, "inputs")?,
    );
    fn borrowed(pairs: &[(String, PathBuf)]) -> Vec<(&str, &std::path::Path)> {
        pairs
            .iter()
            .map(|(n, p)| (n.as_str(), p.as_path()))
            .collect()
    }
    let (o, i) = (borrowed(&outputs), borrowed(&inputs));
    Ok(angletrack::capture::check_outputs(&o, &i)?)
}

/// Writes `data` (`bytes`, or `str` as UTF-8) to `path` all or nothing: to a temporary
/// file beside it, renamed over it when complete (`angletrack::capture::write_output`).
#[pyfunction]
#[pyo3(signature = (path, data))]
pub fn write_output(py: Python<'_>, path: PathBuf, data: &Bound<'_, PyAny>) -> Result<()> {
    let bytes: Vec<u8> = if let Ok(text) = data.cast::<PyString>() {
        text.to_cow()?.into_owned().into_bytes()
    } else {
        data.extract::<Vec<u8>>().map_err(|_| {
            Error::value(
                "data",
                format!(
                    "expected bytes or str, got {}",
                    crate::gains::type_name(data)
                ),
            )
        })?
    };
    py.detach(|| angletrack::capture::write_output(&path, &bytes))?;
    Ok(())
}
