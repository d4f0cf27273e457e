//! `FixedEstimate` and `FixedEstimates`: what `FixedObserver` gives back, in the integers
//! the firmware holds (`docs/theory.md §14`) and in physical units.

use angletrack::FixedColumns;
use angletrack_core::{FixedEstimate as CoreFixedEstimate, FixedGains};
use numpy::{Element, PyArray1};
use pyo3::prelude::*;

use crate::arrays::{as_slice_mut, writable};
use crate::errors::{Error, Result};
use crate::estimates::zeros;

/// What a fixed-point observer knows after its last sample: its integers and the same in
/// physical units.
#[pyclass(module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct FixedEstimate {
    /// Binary angle (2^32 per turn, -2^31 is -pi).
    angle: i32,
    /// Whole turns since initialisation: the position is `turns + angle / 2^32` turns.
    turns: i64,
    /// Speed (2^-32 turn per sample).
    speed: i32,
    /// Acceleration (2^-63 turn per sample^2); 0 for a 2nd-order observer.
    acceleration: i64,
    /// Normalised phase error (Q15: 2^15 is 1).
    phase_error: i32,
    /// Fault flags of the monitor's last window (bits, see `angletrack.Faults`).
    faults: u8,
    /// Multi-turn position (rad).
    position_rad: f64,
    /// Speed (rad/s).
    speed_rad_s: f64,
    /// Acceleration (rad/s^2).
    acceleration_rad_s2: f64,
}

impl FixedEstimate {
    /// The estimate `e` of the observer of `gains`.
    pub(crate) fn new<const N: usize>(gains: &FixedGains<N>, e: &CoreFixedEstimate) -> Self {
        Self {
            angle: e.angle,
            turns: e.turns,
            speed: e.speed,
            acceleration: e.acceleration,
            phase_error: e.phase_error,
            faults: e.faults.bits(),
            position_rad: gains.position_rad(e),
            speed_rad_s: gains.speed_rad_s(e),
            acceleration_rad_s2: gains.acceleration_rad_s2(e),
        }
    }
}

#[pymethods]
impl FixedEstimate {
    fn __repr__(&self) -> String {
        format!(
            "FixedEstimate(angle={}, turns={}, speed={}, acceleration={}, phase_error={}, \
             faults={}, position_rad={:.9}, speed_rad_s={:.6}, acceleration_rad_s2={:.6})",
            self.angle,
            self.turns,
            self.speed,
            self.acceleration,
            self.phase_error,
            self.faults,
            self.position_rad,
            self.speed_rad_s,
            self.acceleration_rad_s2
        )
    }
}

/// The estimates of a `FixedObserver.update`, one numpy array per quantity, one element per
/// sample: the firmware's integers (`angle` int32, `turns` int64, `speed` int32,
/// `acceleration` int64, `phase_error` int32, `faults` uint8) and the same in physical
/// units (float64).
#[pyclass(module = "angletrack", frozen, get_all)]
#[derive(Debug)]
pub struct FixedEstimates {
    /// Binary angle (int32, 2^32 per turn, -2^31 is -pi).
    angle: Py<PyAny>,
    /// Whole turns since initialisation (int64).
    turns: Py<PyAny>,
    /// Speed (int32, 2^-32 turn per sample).
    speed: Py<PyAny>,
    /// Acceleration (int64, 2^-63 turn per sample^2); 0 for a 2nd-order observer.
    acceleration: Py<PyAny>,
    /// Normalised phase error (int32, Q15: 2^15 is 1).
    phase_error: Py<PyAny>,
    /// Fault flags of the monitor's window each sample ends in (uint8 bits, see
    /// `angletrack.Faults`).
    faults: Py<PyAny>,
    /// Multi-turn position `2 pi (turns + angle / 2^32)` (rad, float64).
    position_rad: Py<PyAny>,
    /// Speed (rad/s, float64).
    speed_rad_s: Py<PyAny>,
    /// Acceleration (rad/s^2, float64).
    acceleration_rad_s2: Py<PyAny>,
    /// The number of samples.
    len: usize,
}

#[pymethods]
impl FixedEstimates {
    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        format!(
            "FixedEstimates({} samples: angle, turns, speed, acceleration, phase_error, faults, \
             position_rad, speed_rad_s, acceleration_rad_s2)",
            self.len
        )
    }
}

/// The output arrays of a fixed-point run, allocated by numpy and written in place.
pub(crate) struct FixedArrays<'py> {
    angle: Bound<'py, PyArray1<i32>>,
    turns: Bound<'py, PyArray1<i64>>,
    speed: Bound<'py, PyArray1<i32>>,
    acceleration: Bound<'py, PyArray1<i64>>,
    phase_error: Bound<'py, PyArray1<i32>>,
    faults: Bound<'py, PyArray1<u8>>,
    position_rad: Bound<'py, PyArray1<f64>>,
    speed_rad_s: Bound<'py, PyArray1<f64>>,
    acceleration_rad_s2: Bound<'py, PyArray1<f64>>,
}

/// A zeroed array of `n` elements.
fn array<'py, E: Element>(py: Python<'py>, n: usize) -> Result<Bound<'py, PyArray1<E>>> {
    zeros(py, Some(n))?.ok_or_else(|| Error::value("output", "was not allocated"))
}

impl<'py> FixedArrays<'py> {
    /// `n` elements of every quantity.
    pub(crate) fn new(py: Python<'py>, n: usize) -> Result<Self> {
        Ok(Self {
            angle: array(py, n)?,
            turns: array(py, n)?,
            speed: array(py, n)?,
            acceleration: array(py, n)?,
            phase_error: array(py, n)?,
            faults: array(py, n)?,
            position_rad: array(py, n)?,
            speed_rad_s: array(py, n)?,
            acceleration_rad_s2: array(py, n)?,
        })
    }

    /// Calls `fill` with the arrays' slices, the GIL released.
    pub(crate) fn fill<R: Send>(
        &self,
        py: Python<'_>,
        fill: impl FnOnce(FixedColumns<'_>) -> R + Send,
    ) -> Result<R> {
        let mut integers = (
            writable(&self.angle)?,
            writable(&self.turns)?,
            writable(&self.speed)?,
            writable(&self.acceleration)?,
            writable(&self.phase_error)?,
            writable(&self.faults)?,
        );
        let mut physical = (
            writable(&self.position_rad)?,
            writable(&self.speed_rad_s)?,
            writable(&self.acceleration_rad_s2)?,
        );
        let columns = FixedColumns {
            angle: as_slice_mut(&mut integers.0)?,
            turns: as_slice_mut(&mut integers.1)?,
            speed: as_slice_mut(&mut integers.2)?,
            acceleration: as_slice_mut(&mut integers.3)?,
            phase_error: as_slice_mut(&mut integers.4)?,
            faults: as_slice_mut(&mut integers.5)?,
            position_rad: as_slice_mut(&mut physical.0)?,
            speed_rad_s: as_slice_mut(&mut physical.1)?,
            acceleration_rad_s2: as_slice_mut(&mut physical.2)?,
        };
        Ok(py.detach(|| fill(columns)))
    }

    /// The `FixedEstimates` of `len` samples.
    pub(crate) fn into_estimates(self, len: usize) -> FixedEstimates {
        FixedEstimates {
            angle: self.angle.into_any().unbind(),
            turns: self.turns.into_any().unbind(),
            speed: self.speed.into_any().unbind(),
            acceleration: self.acceleration.into_any().unbind(),
            phase_error: self.phase_error.into_any().unbind(),
            faults: self.faults.into_any().unbind(),
            position_rad: self.position_rad.into_any().unbind(),
            speed_rad_s: self.speed_rad_s.into_any().unbind(),
            acceleration_rad_s2: self.acceleration_rad_s2.into_any().unbind(),
            len,
        }
    }
}
