//! `Estimate` and `Estimates`: what observers give back, and the numpy arrays a run writes
//! its estimates into.

use angletrack::{EstimateColumns, Output, OutputSet};
use angletrack_core::{Estimate as CoreEstimate, Real};
use numpy::{Element, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyString;

use crate::arrays::{as_slice_mut, writable};
use crate::errors::{Error, Result};
use crate::getters::class_methods;

/// The outputs of argument `outputs`: `None` for every output, else a name or an iterable
/// of names (`Output::name`: a tuple, a list, a set); an unknown name is refused, named.
pub(crate) fn output_set(outputs: Option<&Bound<'_, PyAny>>) -> Result<OutputSet> {
    let Some(outputs) = outputs.filter(|o| !o.is_none()) else {
        return Ok(OutputSet::ALL);
    };
    let names: Vec<String> = if let Ok(name) = outputs.cast::<PyString>() {
        vec![name.to_string()]
    } else {
        let refused = |_| {
            Error::value(
                "outputs",
                "expected output names (str), e.g. ('angle', 'speed')",
            )
        };
        outputs
            .try_iter()
            .map_err(refused)?
            .map(|name| name.and_then(|n| n.extract::<String>()))
            .collect::<PyResult<_>>()
            .map_err(refused)?
    };
    OutputSet::from_names(names.iter().map(String::as_str)).map_err(|e| Error::value("outputs", e))
}

/// The estimates of `n` samples (the arrays shaped `shape` if given) and what `fill`
/// returns: each output in `outputs` allocated by numpy (which asks for huge pages on large
/// arrays) and filled in place by `fill` with the GIL released, `None` for an output not
/// asked for. A `MemoryError` when they need more than the machine's physical memory (each
/// allocation alone may succeed, overcommitted, and the run be killed when it writes them),
/// or when numpy cannot allocate one.
pub(crate) fn run_estimates<T: Real + Element, R: Send>(
    py: Python<'_>,
    n: usize,
    (outputs, shape): (OutputSet, Option<(usize, usize)>),
    fill: impl FnOnce(EstimateColumns<'_, T>) -> R + Send,
) -> Result<(R, Estimates)> {
    let bytes = n as u128 * outputs.bytes_per_sample::<T>() as u128;
    if physical_memory_bytes(py).is_some_and(|memory| bytes > memory) {
        return Err(Error::Memory {
            parameter: "y_c",
            bytes,
        });
    }
    let shaped = |a: Option<Bound<'_, PyAny>>| -> Result<Py<PyAny>> {
        Ok(match (a, shape) {
            (None, _) => py.None(),
            (Some(a), Some(shape)) => a.call_method1("reshape", shape)?.unbind(),
            (Some(a), None) => a.unbind(),
        })
    };
    // Each column: allocated if asked for, borrowed for writing while `fill` runs, then
    // shaped into the result.
    macro_rules! columns {
        ($($field:ident: $t:ty = $output:ident,)*) => {{
            $(let $field = outputs.has(Output::$output).then(|| zeros::<$t>(py, n)).transpose()?;)*
            let filled = {
                $(let mut $field = $field.as_ref().map(writable).transpose()?;)*
                let columns = EstimateColumns {
                    $($field: $field.as_mut().map(as_slice_mut).transpose()?,)*
                };
                py.detach(|| fill(columns))
            };
            let estimates = Estimates {
                len: shape.map_or(n, |(_, samples)| samples),
                dtype: numpy::dtype::<T>(py).to_string(),
                $($field: shaped($field.map(Bound::into_any))?,)*
            };
            (filled, estimates)
        }};
    }
    Ok(columns! {
        angle: T = Angle,
        position: f64 = Position,
        speed: T = Speed,
        acceleration: T = Acceleration,
        phase_error: T = PhaseError,
        faults: u8 = Faults,
    })
}

/// The machine's physical memory (bytes), if the platform tells it (`os.sysconf`).
fn physical_memory_bytes(py: Python<'_>) -> Option<u128> {
    let sysconf = PyModule::import(py, "os").ok()?.getattr("sysconf").ok()?;
    let value = |name: &str| sysconf.call1((name,)).ok()?.extract::<u64>().ok();
    Some(u128::from(value("SC_PHYS_PAGES")?) * u128::from(value("SC_PAGE_SIZE")?))
}

/// A zeroed array of `n` elements allocated by `numpy.zeros`, which raises `MemoryError`
/// where the allocation fails (a failed allocation must not abort the interpreter).
pub(crate) fn zeros<'py, E: Element>(py: Python<'py>, n: usize) -> Result<Bound<'py, PyArray1<E>>> {
    let array = PyModule::import(py, "numpy")?
        .getattr("zeros")?
        .call1((n, numpy::dtype::<E>(py)))?;
    Ok(array.cast_into::<PyArray1<E>>().map_err(PyErr::from)?)
}

/// What an observer knows after its last sample (scalars, in `float`).
#[pyclass(module = "angletrack", frozen)]
#[derive(Debug, Clone)]
pub struct Estimate {
    /// The core's estimate.
    pub(crate) inner: CoreEstimate<f64>,
}

class_methods! {
    Estimate {
        /// Estimated angle (rad), wrapped to [-pi, pi).
        angle: f64 = |this, py| this.inner.angle;
        /// Whole turns counted since initialisation.
        turns: i64 = |this, py| this.inner.turns;
        /// Multi-turn position `turns * 2 pi + angle` (rad).
        position: f64 = |this, py| this.inner.position();
        /// Estimated speed (rad/s).
        speed: f64 = |this, py| this.inner.speed;
        /// Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
        acceleration: f64 = |this, py| this.inner.acceleration;
        /// Normalised phase-detector output of the last sample (about `sin(error)`).
        phase_error: f64 = |this, py| this.inner.phase_error;
        /// Fault flags of the last sample (bits, see `angletrack.Faults`).
        faults: u8 = |this, py| this.inner.faults.bits();
    }
    methods {
        fn __repr__(&self) -> String {
            let e = &self.inner;
            format!(
                "Estimate(angle={:.6} rad, turns={}, position={:.6} rad, speed={:.6} rad/s, \
                 acceleration={:.6} rad/s^2, phase_error={:.3e}, faults={})",
                e.angle,
                e.turns,
                e.position(),
                e.speed,
                e.acceleration,
                e.phase_error,
                e.faults
            )
        }
    }
}

/// The estimates of a run, one numpy array per quantity, one element per sample.
///
/// `angle`, `speed`, `acceleration` and `phase_error` have the dtype of the input
/// (float32 or float64); `position` is always float64. A quantity left out of a batch's
/// `outputs` is `None`.
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

    fn __repr__(&self, py: Python<'_>) -> String {
        let arrays = [
            (&self.angle, "angle"),
            (&self.position, "position (float64)"),
            (&self.speed, "speed"),
            (&self.acceleration, "acceleration"),
            (&self.phase_error, "phase_error"),
            (&self.faults, "faults (uint8)"),
        ];
        let present: Vec<&str> = arrays
            .iter()
            .filter(|(array, _)| !array.is_none(py))
            .map(|&(_, name)| name)
            .collect();
        format!(
            "Estimates({} samples, dtype={}: {})",
            self.len,
            self.dtype,
            present.join(", ")
        )
    }
}
