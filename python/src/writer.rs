//! `TableWriter`: any table of named numeric columns (an observer's estimates among them:
//! `estimate_columns`), written chunk by chunk by the std crate's writer (CSV with the
//! shortest round-trip decimals, a `.npy` structured array or an `.npz`).

use std::path::PathBuf;

use angletrack::capture::{
    self, Column, ColumnType, OutputFile as CoreOutputFile, TableWriter as CoreTableWriter,
};
use numpy::{Element, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::arrays::Float;
use crate::errors::{Error, Result};
use crate::getters::class_methods;

/// The columns `(name, dtype)` of estimates in the float type `dtype` (float32 or float64,
/// default float64; `angletrack::capture::estimate_columns`): the table `EstimatesWriter`
/// writes.
#[pyfunction]
#[pyo3(signature = (dtype = None))]
pub fn estimate_columns(
    dtype: Option<&Bound<'_, PyAny>>,
) -> Result<Vec<(&'static str, &'static str)>> {
    let float = match Float::from_dtype_like(dtype, "dtype")? {
        Float::F32 => ColumnType::F32,
        Float::F64 => ColumnType::F64,
    };
    Ok(capture::estimate_columns(float)
        .map(|(name, kind)| (name, kind.name()))
        .to_vec())
}

/// Writes a table of named numeric columns chunk by chunk in constant memory, in the format
/// of `path`'s extension (`.csv`, `.npy` structured array, `.npz`
/// of one array per column; another extension is refused). `columns` lists `(name, dtype)`
/// in file order: names of letters, digits and underscores, each once; dtypes float64,
/// float32, uint8 or int32 (anything `numpy.dtype` reads as one of them). `write(arrays)`
/// appends one 1-D array per column, of the column's dtype, all of one length. All or
/// nothing: the target is replaced by `close()` or at the end of a
/// `with` block, and left as it was after an exception in the block.
#[pyclass(name = "TableWriter", module = "angletrack")]
#[derive(Debug)]
pub struct PyTableWriter {
    writer: Option<CoreTableWriter>,
}

/// The column type of the dtype-like `dtype` of column `name` (as `numpy.dtype` reads it).
fn column_type(py: Python<'_>, name: &str, dtype: &Bound<'_, PyAny>) -> Result<ColumnType> {
    let resolved: Option<String> = py
        .import("numpy")
        .and_then(|numpy| numpy.call_method1("dtype", (dtype,)))
        .and_then(|d| d.getattr("name"))
        .and_then(|n| n.extract())
        .ok();
    resolved
        .as_deref()
        .and_then(ColumnType::of_name)
        .ok_or_else(|| {
            let given = resolved.unwrap_or_else(|| dtype.to_string());
            Error::value(
                "columns",
                format!("{name}: dtype {given}: expected float64, float32, uint8 or int32"),
            )
        })
}

/// `ColumnArray` (one column's array, read-only, of the column's type) and `column_values`
/// of the column types `Variant: element type`.
macro_rules! column_arrays {
    ($($variant:ident: $t:ty),*) => {
        enum ColumnArray<'py> {
            $($variant(PyReadonlyArray1<'py, $t>),)*
        }

        impl ColumnArray<'_> {
            /// The values as the writer's column (contiguous: checked when read).
            fn column(&self) -> Column<'_> {
                match self {
                    $(ColumnArray::$variant(a) => Column::$variant(a.as_slice().unwrap_or(&[])),)*
                }
            }
        }

        /// The values of column `name` of type `kind` in `array`: a 1-D contiguous array of
        /// that type.
        fn column_values<'py>(
            array: &Bound<'py, PyAny>,
            name: &str,
            kind: ColumnType,
        ) -> Result<ColumnArray<'py>> {
            let values = match kind {
                $(ColumnType::$variant => typed(array).map(ColumnArray::$variant),)*
            };
            values.ok_or_else(|| {
                Error::value(
                    "arrays",
                    format!("{name}: expected a contiguous 1-D {} array", kind.name()),
                )
            })
        }
    };
}

column_arrays!(F64: f64, F32: f32, U8: u8, I32: i32);

/// `array` as a read-only contiguous 1-D array of `T`, if it is one.
fn typed<'py, T: Element>(array: &Bound<'py, PyAny>) -> Option<PyReadonlyArray1<'py, T>> {
    array
        .cast::<numpy::PyArray1<T>>()
        .ok()
        .and_then(|a| a.try_readonly().ok())
        .filter(|a| a.is_contiguous())
}

#[pymethods]
impl PyTableWriter {
    #[new]
    #[pyo3(signature = (path, columns))]
    fn py_new(
        py: Python<'_>,
        path: PathBuf,
        columns: Vec<(String, Bound<'_, PyAny>)>,
    ) -> Result<Self> {
        let typed = columns
            .iter()
            .map(|(name, dtype)| Ok((name.as_str(), column_type(py, name, dtype)?)))
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            writer: Some(CoreTableWriter::create(&path, &typed)?),
        })
    }

    /// Appends a chunk: one array per column, in the columns' order.
    #[pyo3(signature = (arrays))]
    fn write(&mut self, py: Python<'_>, arrays: Vec<Bound<'_, PyAny>>) -> Result<()> {
        let writer = self
            .writer
            .as_mut()
            .ok_or_else(|| Error::value("writer", "is closed"))?;
        if arrays.len() != writer.columns().len() {
            return Err(Error::value(
                "arrays",
                format!(
                    "{} given for a table of {} columns",
                    arrays.len(),
                    writer.columns().len()
                ),
            ));
        }
        let held = writer
            .columns()
            .iter()
            .zip(&arrays)
            .map(|((name, kind), array)| column_values(array, name, *kind))
            .collect::<Result<Vec<_>>>()?;
        let columns: Vec<Column<'_>> = held.iter().map(ColumnArray::column).collect();
        py.detach(|| writer.write(&columns))?;
        Ok(())
    }

    /// Finishes the file; returns the number of rows written (0 if already closed).
    fn close(&mut self) -> Result<u64> {
        Ok(self
            .writer
            .take()
            .map(CoreTableWriter::finish)
            .transpose()?
            .unwrap_or(0))
    }

    fn __enter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    /// Closes the file; after an exception in the block, discards it instead.
    #[pyo3(signature = (exc_type, _exc_value, _traceback))]
    fn __exit__(
        &mut self,
        exc_type: &Bound<'_, PyAny>,
        _exc_value: &Bound<'_, PyAny>,
        _traceback: &Bound<'_, PyAny>,
    ) -> Result<bool> {
        if exc_type.is_none() {
            self.close()?;
        } else {
            self.writer = None;
        }
        Ok(false)
    }
}

/// An output written all or nothing: open `temporary_path` (beside `path`) and write it;
/// leaving the `with` block renames it over `path`, or after an exception removes it and
/// leaves `path` as it was (`angletrack::capture::OutputFile`). For files written by Python
/// code (figures, text); `EstimatesWriter` does the same itself.
#[pyclass(name = "OutputFile", module = "angletrack")]
#[derive(Debug)]
pub struct PyOutputFile {
    output: Option<CoreOutputFile>,
    temporary: PathBuf,
}

class_methods! {
    PyOutputFile {
        /// The temporary file to write, beside the target.
        temporary_path: PathBuf = |this, py| this.temporary.clone();
    }
    methods {
        #[new]
        #[pyo3(signature = (path))]
        fn py_new(path: PathBuf) -> Result<Self> {
            let output = CoreOutputFile::create(&path)?;
            let temporary = output.temporary().to_path_buf();
            Ok(Self {
                output: Some(output),
                temporary,
            })
        }

        /// Renames the temporary file over the target.
        fn commit(&mut self) -> Result<()> {
            match self.output.take() {
                Some(o) => Ok(o.commit()?),
                None => Err(Error::value(
                    "OutputFile",
                    "is committed or discarded already",
                )),
            }
        }

        /// Removes the temporary file; the target stays as it was.
        fn discard(&mut self) {
            self.output = None;
        }

        fn __enter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
            slf
        }

        #[pyo3(signature = (exc_type, _exc_value, _traceback))]
        fn __exit__(
            &mut self,
            exc_type: &Bound<'_, PyAny>,
            _exc_value: &Bound<'_, PyAny>,
            _traceback: &Bound<'_, PyAny>,
        ) -> Result<bool> {
            if exc_type.is_none() && self.output.is_some() {
                self.commit()?;
            } else {
                self.discard();
            }
            Ok(false)
        }
    }
}
