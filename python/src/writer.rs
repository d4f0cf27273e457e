//! `EstimatesWriter`: an observer's estimates written chunk by chunk by the std crate's
//! writer (CSV with the shortest round-trip decimals, or a `.npy` structured array).

use std::path::PathBuf;

use angletrack::capture::{EstimateRows, EstimatesWriter as CoreWriter, OutputFloat};
use numpy::{Element, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::arrays::Float;
use crate::errors::{Error, Result};
use crate::estimates::Estimates;

/// Writes estimates chunk by chunk in constant memory: `.npy` (a structured array with
/// fields `time_s`, `angle_rad`, `position_rad`, `speed_rad_s`, `acceleration_rad_s2`,
/// `phase_error`, `faults`) for a path ending in `.npy`, else CSV with a header line of
/// those names, each number the shortest decimal that reads back to the same float of its
/// type. `dtype` is the observer's (float32 or float64). Use as a context manager, or call
/// `close()` (a `.npy` gets its record count then).
#[pyclass(name = "EstimatesWriter", module = "angletrack")]
#[derive(Debug)]
pub struct PyEstimatesWriter {
    writer: Option<CoreWriter>,
    float: Float,
}

fn column<'py, T: Element>(
    py: Python<'py>,
    array: &Py<PyAny>,
    parameter: &'static str,
) -> Result<PyReadonlyArray1<'py, T>> {
    let bound = array.bind(py);
    let typed = bound
        .cast::<numpy::PyArray1<T>>()
        .map_err(|_| Error::value(parameter, "expected 1-D estimates of the writer's dtype"))?;
    typed
        .try_readonly()
        .map_err(|e| Error::value(parameter, format!("cannot be read ({e})")))
}

fn slice<'a, T: Element>(
    a: &'a PyReadonlyArray1<'_, T>,
    parameter: &'static str,
) -> Result<&'a [T]> {
    a.as_slice()
        .map_err(|_| Error::value(parameter, "is not contiguous"))
}

impl PyEstimatesWriter {
    fn write_typed<T: OutputFloat + Element>(
        &mut self,
        py: Python<'_>,
        time_s: &[f64],
        e: &Estimates,
    ) -> Result<()> {
        let angle = column::<T>(py, &e.angle, "angle")?;
        let position = column::<f64>(py, &e.position, "position")?;
        let speed = column::<T>(py, &e.speed, "speed")?;
        let acceleration = column::<T>(py, &e.acceleration, "acceleration")?;
        let phase_error = column::<T>(py, &e.phase_error, "phase_error")?;
        let faults = column::<u8>(py, &e.faults, "faults")?;
        let rows = EstimateRows {
            time_s,
            angle: slice(&angle, "angle")?,
            position: slice(&position, "position")?,
            speed: slice(&speed, "speed")?,
            acceleration: slice(&acceleration, "acceleration")?,
            phase_error: slice(&phase_error, "phase_error")?,
            faults: slice(&faults, "faults")?,
        };
        let writer = self
            .writer
            .as_mut()
            .ok_or_else(|| Error::value("writer", "is closed"))?;
        py.detach(|| writer.write(rows))?;
        Ok(())
    }
}

#[pymethods]
impl PyEstimatesWriter {
    #[new]
    #[pyo3(signature = (path, *, dtype = None))]
    fn py_new(path: PathBuf, dtype: Option<&Bound<'_, PyAny>>) -> Result<Self> {
        let float = Float::from_dtype_like(dtype, "dtype")?;
        let writer = match float {
            Float::F32 => CoreWriter::create::<f32>(&path)?,
            Float::F64 => CoreWriter::create::<f64>(&path)?,
        };
        Ok(Self {
            writer: Some(writer),
            float,
        })
    }

    /// Appends the estimates of a chunk, with their time stamps `time_s` (float64 array of
    /// the same length).
    #[pyo3(signature = (time_s, estimates))]
    fn write(
        &mut self,
        py: Python<'_>,
        time_s: PyReadonlyArray1<'_, f64>,
        estimates: PyRef<'_, Estimates>,
    ) -> Result<()> {
        let time_s = slice(&time_s, "time_s")?;
        match self.float {
            Float::F32 => self.write_typed::<f32>(py, time_s, &estimates),
            Float::F64 => self.write_typed::<f64>(py, time_s, &estimates),
        }
    }

    /// Finishes the file; returns the number of rows written (0 if already closed).
    fn close(&mut self) -> Result<u64> {
        match self.writer.take() {
            Some(w) => Ok(w.finish()?),
            None => Ok(0),
        }
    }

    fn __enter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    #[pyo3(signature = (*_exc))]
    fn __exit__(&mut self, _exc: &Bound<'_, pyo3::types::PyTuple>) -> Result<bool> {
        self.close()?;
        Ok(false)
    }
}
