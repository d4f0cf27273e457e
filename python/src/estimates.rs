//! `Estimate` and `Estimates`: what observers give back, and the numpy arrays a run writes
//! its estimates into.

use angletrack::BatchColumns;
use angletrack_core::{Estimate as CoreEstimate, Faults, Real};
use numpy::{Element, PyArray1};
use pyo3::prelude::*;

use crate::arrays::{as_slice_mut, writable};
use crate::errors::{Error, Result};

/// The output arrays of a run, allocated by numpy (which asks for huge pages on large
/// arrays) and written in place.
pub(crate) struct OutputArrays<'py, T: Element> {
    angle: Bound<'py, PyArray1<T>>,
    position: Bound<'py, PyArray1<f64>>,
    speed: Bound<'py, PyArray1<T>>,
    acceleration: Bound<'py, PyArray1<T>>,
    phase_error: Bound<'py, PyArray1<T>>,
    faults: Bound<'py, PyArray1<u8>>,
}

impl<'py, T: Real + Element> OutputArrays<'py, T> {
    /// `n` elements per quantity; a `MemoryError` when they need more than the machine's
    /// physical memory (each allocation alone may succeed, overcommitted, and the run be
    /// killed when it writes them), or when numpy cannot allocate one.
    pub(crate) fn new(py: Python<'py>, n: usize) -> Result<Self> {
        let per_sample = 4 * core::mem::size_of::<T>() + core::mem::size_of::<f64>() + 1;
        let bytes = n as u128 * per_sample as u128;
        if physical_memory_bytes(py).is_some_and(|memory| bytes > memory) {
            return Err(Error::Memory {
                parameter: "y_c",
                bytes,
            });
        }
        Ok(Self {
            angle: zeros(py, n)?,
            position: zeros(py, n)?,
            speed: zeros(py, n)?,
            acceleration: zeros(py, n)?,
            phase_error: zeros(py, n)?,
            faults: zeros(py, n)?,
        })
    }

    /// Calls `fill` with the arrays' slices, the GIL released.
    pub(crate) fn fill<R: Send>(
        &self,
        py: Python<'_>,
        fill: impl FnOnce(BatchColumns<'_, T>) -> R + Send,
    ) -> Result<R> {
        let mut w = (
            writable(&self.angle)?,
            writable(&self.position)?,
            writable(&self.speed)?,
            writable(&self.acceleration)?,
            writable(&self.phase_error)?,
            writable(&self.faults)?,
        );
        let columns = BatchColumns {
            angle: as_slice_mut(&mut w.0)?,
            position: as_slice_mut(&mut w.1)?,
            speed: as_slice_mut(&mut w.2)?,
            acceleration: as_slice_mut(&mut w.3)?,
            phase_error: as_slice_mut(&mut w.4)?,
            faults: as_slice_mut(&mut w.5)?,
        };
        Ok(py.detach(|| fill(columns)))
    }

    /// The `Estimates` of `len` samples, each array reshaped to `shape` if given.
    pub(crate) fn into_estimates(
        self,
        len: usize,
        shape: Option<(usize, usize)>,
    ) -> Result<Estimates> {
        let py = self.angle.py();
        let shaped = |a: Bound<'py, PyAny>| -> Result<Py<PyAny>> {
            Ok(match shape {
                Some(shape) => a.call_method1("reshape", shape)?.unbind(),
                None => a.unbind(),
            })
        };
        Ok(Estimates {
            len,
            dtype: numpy::dtype::<T>(py).to_string(),
            angle: shaped(self.angle.into_any())?,
            position: shaped(self.position.into_any())?,
            speed: shaped(self.speed.into_any())?,
            acceleration: shaped(self.acceleration.into_any())?,
            phase_error: shaped(self.phase_error.into_any())?,
            faults: shaped(self.faults.into_any())?,
        })
    }
}

/// The machine's physical memory (bytes), if the platform tells it (`os.sysconf`).
fn physical_memory_bytes(py: Python<'_>) -> Option<u128> {
    let os = PyModule::import(py, "os").ok()?;
    let sysconf = |name: &str| -> Option<u128> {
        let value: i64 = os
            .getattr("sysconf")
            .ok()?
            .call1((name,))
            .ok()?
            .extract()
            .ok()?;
        u128::try_from(value).ok()
    };
    Some(sysconf("SC_PHYS_PAGES")? * sysconf("SC_PAGE_SIZE")?)
}

/// A zeroed array of `n` elements allocated by `numpy.zeros`, which raises `MemoryError`
/// where the allocation fails (a failed allocation must not abort the interpreter).
fn zeros<'py, E: Element>(py: Python<'py>, n: usize) -> Result<Bound<'py, PyArray1<E>>> {
    let array = PyModule::import(py, "numpy")?
        .getattr("zeros")?
        .call1((n, numpy::dtype::<E>(py)))?;
    Ok(array.cast_into::<PyArray1<E>>().map_err(PyErr::from)?)
}

/// What an observer knows after its last sample (scalars, in `float`).
#[pyclass(module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct Estimate {
    /// Estimated angle (rad), wrapped to [-pi, pi).
    angle: f64,
    /// Whole turns counted since initialisation.
    turns: i64,
    /// Multi-turn position `turns * 2 pi + angle` (rad).
    position: f64,
    /// Estimated speed (rad/s).
    speed: f64,
    /// Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
    acceleration: f64,
    /// Normalised phase-detector output of the last sample (about `sin(error)`).
    phase_error: f64,
    /// Fault flags of the last sample (bits, see `angletrack.Faults`).
    faults: u8,
}

impl Estimate {
    pub(crate) fn from_core<T: Real>(e: &CoreEstimate<T>) -> Self {
        Self {
            angle: e.angle.to_f64(),
            turns: e.turns,
            position: e.position(),
            speed: e.speed.to_f64(),
            acceleration: e.acceleration.to_f64(),
            phase_error: e.phase_error.to_f64(),
            faults: e.faults.bits(),
        }
    }
}

#[pymethods]
impl Estimate {
    fn __repr__(&self) -> String {
        format!(
            "Estimate(angle={:.6} rad, turns={}, position={:.6} rad, speed={:.6} rad/s, \
             acceleration={:.6} rad/s^2, phase_error={:.3e}, faults={})",
            self.angle,
            self.turns,
            self.position,
            self.speed,
            self.acceleration,
            self.phase_error,
            Faults::from_bits_truncate(self.faults)
        )
    }
}

/// The estimates of a run, one numpy array per quantity, one element per sample.
///
/// `angle`, `speed`, `acceleration` and `phase_error` have the dtype of the input
/// (float32 or float64); `position` is always float64.
#[pyclass(module = "angletrack", frozen, get_all)]
#[derive(Debug)]
pub struct Estimates {
    /// Estimated angle (rad), wrapped to [-pi, pi).
    pub(crate) angle: Py<PyAny>,
    /// Multi-turn position `turns * 2 pi + angle` (rad), float64.
    pub(crate) position: Py<PyAny>,
    /// Estimated speed (rad/s).
    pub(crate) speed: Py<PyAny>,
    /// Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
    pub(crate) acceleration: Py<PyAny>,
    /// Normalised phase-detector output `(y_s cos(angle_p) - y_c sin(angle_p)) / |y|` per
    /// sample (about the sine of the angle error, whatever the amplitude).
    pub(crate) phase_error: Py<PyAny>,
    /// Fault flags of each sample (uint8 bits, see `angletrack.Faults`).
    pub(crate) faults: Py<PyAny>,
    /// The dtype of the angle, speed, acceleration and phase-error arrays.
    pub(crate) dtype: String,
    /// The number of samples.
    pub(crate) len: usize,
}

#[pymethods]
impl Estimates {
    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        format!(
            "Estimates({} samples, dtype={}: angle, position (float64), speed, acceleration, \
             phase_error, faults (uint8))",
            self.len, self.dtype
        )
    }
}
