//! `read_capture`, `CaptureReader` and `EstimatesWriter`: the std crate's capture reader and
//! estimates writer on numpy arrays, the parsing and formatting in Rust with the GIL
//! released.

use std::path::PathBuf;
use std::sync::Mutex;

use angletrack::capture::{
    Capture as CoreCapture, CaptureChunk, CaptureOptions, CaptureReader as CoreReader, ColumnMap,
    Delimiter, Role, TimeUnit, read_capture as core_read_capture,
};
use numpy::{PyArray1, ToPyArray};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use crate::errors::{Error, Result};

/// The column mapping of a `columns` argument: `"y_c=cos,y_s=sin"` or a dict
/// `{"y_c": "cos", "y_s": 1}` (names or 0-based indices).
fn column_map(columns: Option<&Bound<'_, PyAny>>) -> Result<ColumnMap> {
    let Some(columns) = columns.filter(|c| !c.is_none()) else {
        return Ok(ColumnMap::default());
    };
    if let Ok(text) = columns.cast::<PyString>() {
        return text
            .to_cow()?
            .parse()
            .map_err(|m: String| Error::value("columns", strip(&m)));
    }
    let dict = columns
        .cast::<PyDict>()
        .map_err(|_| Error::value("columns", "expected 'y_c=NAME,y_s=NAME,...' or a dict"))?;
    let mut text = Vec::new();
    for (role, column) in dict.iter() {
        text.push(format!("{}={}", role.str()?, column.str()?));
    }
    text.join(",")
        .parse()
        .map_err(|m: String| Error::value("columns", strip(&m)))
}

/// A message without the parameter name the binding's error adds again.
fn strip(message: &str) -> String {
    message
        .strip_prefix("columns: ")
        .unwrap_or(message)
        .to_string()
}

/// The reader's options from the Python arguments.
fn options(
    columns: Option<&Bound<'_, PyAny>>,
    delimiter: Option<&str>,
    time_unit: &str,
    sample_rate_hz: Option<f64>,
    chunk_rows: usize,
) -> Result<CaptureOptions> {
    let delimiter = delimiter
        .map(Delimiter::parse)
        .transpose()
        .map_err(|m| Error::value("delimiter", m.trim_start_matches("delimiter: ")))?;
    let time_unit: TimeUnit = time_unit
        .parse()
        .map_err(|m: String| Error::value("time_unit", m.trim_start_matches("time_unit: ")))?;
    if let Some(rate) = sample_rate_hz
        && !(rate.is_finite() && rate > 0.0)
    {
        return Err(Error::value(
            "sample_rate_hz",
            format!("{rate} Hz: the sample rate must be positive and finite"),
        ));
    }
    if chunk_rows < 2 {
        return Err(Error::value("chunk_rows", "at least 2 rows per chunk"));
    }
    Ok(CaptureOptions {
        columns: column_map(columns)?,
        delimiter,
        time_unit,
        sample_rate_hz,
        chunk_rows,
    })
}

/// `{role: column name}` of the columns used.
fn mapping_dict<'py>(py: Python<'py>, mapping: &[(Role, String)]) -> Result<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (role, name) in mapping {
        dict.set_item(role.key(), name)?;
    }
    Ok(dict)
}

fn optional_array(py: Python<'_>, values: Option<&Vec<f64>>) -> Option<Py<PyArray1<f64>>> {
    values.map(|v| v.to_pyarray(py).unbind())
}

/// The array that takes over `values` (no copy: a whole capture is not held twice).
fn owned_array(py: Python<'_>, values: Vec<f64>) -> Py<PyArray1<f64>> {
    PyArray1::from_vec(py, values).unbind()
}

/// A chunk of a capture: float64 arrays of one length (time in seconds).
#[pyclass(name = "CaptureChunk", module = "angletrack", frozen, get_all)]
#[derive(Debug)]
pub struct PyCaptureChunk {
    /// 0-based index of the chunk's first sample in the capture.
    first_sample: u64,
    /// Time stamps (s), or `None` without a time column.
    time_s: Option<Py<PyArray1<f64>>>,
    /// The cosine signal.
    y_c: Py<PyArray1<f64>>,
    /// The sine signal.
    y_s: Py<PyArray1<f64>>,
    /// The reference angle (rad), or `None`.
    reference_rad: Option<Py<PyArray1<f64>>>,
    /// The resolver's excitation (counts), or `None`.
    excitation: Option<Py<PyArray1<f64>>>,
}

impl PyCaptureChunk {
    fn new(py: Python<'_>, c: &CaptureChunk) -> Self {
        Self {
            first_sample: c.first_sample,
            time_s: optional_array(py, c.time_s.as_ref()),
            y_c: c.y_c.to_pyarray(py).unbind(),
            y_s: c.y_s.to_pyarray(py).unbind(),
            reference_rad: optional_array(py, c.reference_rad.as_ref()),
            excitation: optional_array(py, c.excitation.as_ref()),
        }
    }
}

#[pymethods]
impl PyCaptureChunk {
    fn __len__(&self, py: Python<'_>) -> usize {
        numpy::PyUntypedArrayMethods::len(self.y_c.bind(py))
    }
}

/// A capture read chunk by chunk in constant memory (iterate over it for `CaptureChunk`s).
///
/// `columns`: `"y_c=cos,y_s=sin,time=t,reference=ref"` or a dict; each value a header name,
/// else a 0-based index; roles left out get their usual names (`time`/`t`, `y_c`/`cos`,
/// `y_s`/`sin`, `reference`/`theta`). `delimiter`: one character, `"tab"` or
/// `"whitespace"` (default: sniffed). `time_unit`: `s`, `ms`, `us` or `ns`.
/// `sample_rate_hz`: the true rate, which skips the time column's spacing check. Raises
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

#[pymethods]
impl PyCaptureReader {
    #[new]
    #[pyo3(signature = (path, *, columns = None, delimiter = None, time_unit = "s", sample_rate_hz = None, chunk_rows = 65536))]
    fn py_new(
        path: PathBuf,
        columns: Option<&Bound<'_, PyAny>>,
        delimiter: Option<&str>,
        time_unit: &str,
        sample_rate_hz: Option<f64>,
        chunk_rows: usize,
    ) -> Result<Self> {
        let options = options(columns, delimiter, time_unit, sample_rate_hz, chunk_rows)?;
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
        // The chunk was read above; it is borrowed again under the GIL to be copied out.
        Ok(reader.last_chunk().map(|c| PyCaptureChunk::new(py, c)))
    }

    /// The sample rate (Hz): the stated one, else the time column's (mean spacing of the
    /// rows read so far); `None` without either.
    #[getter]
    fn sample_rate_hz(&self) -> Option<f64> {
        self.reader().sample_rate_hz()
    }

    /// Samples read so far.
    #[getter]
    fn rows(&self) -> u64 {
        self.reader().rows()
    }

    /// The samples' element type as stored (`int16`; `int64` for whole numbers in text).
    #[getter]
    fn sample_dtype(&self) -> String {
        self.reader().sample_dtype()
    }

    /// `{role: column name}` of the columns used.
    #[getter]
    fn columns<'py>(&self, py: Python<'py>) -> Result<Bound<'py, PyDict>> {
        mapping_dict(py, &self.reader().mapping())
    }

    /// `npy`, `npz` or `text, delimiter X`.
    #[getter]
    fn format(&self) -> String {
        self.reader().format().to_string()
    }

    /// The file.
    #[getter]
    fn path(&self) -> PathBuf {
        self.reader().path().to_path_buf()
    }

    /// `(bytes read, file size)`, for progress.
    #[getter]
    fn progress_bytes(&self) -> (u64, u64) {
        self.reader().progress_bytes()
    }
}

/// A whole capture: float64 arrays and what was learnt reading it.
#[pyclass(name = "Capture", module = "angletrack", frozen, get_all)]
#[derive(Debug)]
pub struct PyCapture {
    /// The file.
    path: PathBuf,
    /// The number of samples.
    rows: usize,
    /// Time stamps (s), or `None`.
    time_s: Option<Py<PyArray1<f64>>>,
    /// The cosine signal (float64; integers exactly).
    y_c: Py<PyArray1<f64>>,
    /// The sine signal.
    y_s: Py<PyArray1<f64>>,
    /// The reference angle (rad), or `None`.
    reference_rad: Option<Py<PyArray1<f64>>>,
    /// The stated sample rate, else the time column's mean (Hz); `None` without either.
    sample_rate_hz: Option<f64>,
    /// The samples' element type as stored (`int16`; `int64` for whole numbers in text).
    sample_dtype: String,
    /// `{role: column name}` of the columns used.
    columns: Py<PyDict>,
    /// `npy`, `npz` or `text, delimiter X`.
    format: String,
}

#[pymethods]
impl PyCapture {
    fn __len__(&self) -> usize {
        self.rows
    }

    fn __repr__(&self) -> String {
        format!(
            "Capture({:?}, {} samples of {}, sample_rate_hz={:?}, {})",
            self.path, self.rows, self.sample_dtype, self.sample_rate_hz, self.format
        )
    }
}

/// Reads a whole capture (see `CaptureReader` for the arguments and the checks).
#[pyfunction]
#[pyo3(signature = (path, *, columns = None, delimiter = None, time_unit = "s", sample_rate_hz = None))]
pub fn read_capture(
    py: Python<'_>,
    path: PathBuf,
    columns: Option<&Bound<'_, PyAny>>,
    delimiter: Option<&str>,
    time_unit: &str,
    sample_rate_hz: Option<f64>,
) -> Result<PyCapture> {
    let options = options(columns, delimiter, time_unit, sample_rate_hz, 1 << 16)?;
    let read_path = path.clone();
    let c: CoreCapture = py.detach(|| core_read_capture(read_path, options))?;
    let samples = c.samples;
    Ok(PyCapture {
        path,
        rows: samples.len(),
        time_s: samples.time_s.map(|v| owned_array(py, v)),
        y_c: owned_array(py, samples.y_c),
        y_s: owned_array(py, samples.y_s),
        reference_rad: samples.reference_rad.map(|v| owned_array(py, v)),
        sample_rate_hz: c.sample_rate_hz,
        sample_dtype: c.sample_dtype,
        columns: mapping_dict(py, &c.mapping)?.unbind(),
        format: c.format,
    })
}

/// Registers the capture functions and classes in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add(
        "CaptureError",
        m.py().get_type::<crate::errors::CaptureError>(),
    )?;
    m.add_class::<PyCaptureReader>()?;
    m.add_class::<PyCaptureChunk>()?;
    m.add_class::<PyCapture>()?;
    m.add_function(wrap_pyfunction!(read_capture, m)?)?;
    m.add_class::<crate::writer::PyEstimatesWriter>()?;
    Ok(())
}
