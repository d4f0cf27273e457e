//! `DriveOutputs`: the core's drive outputs over an observer's estimates on numpy arrays
//! (`docs/theory.md §13`): the electrical angle for the pole pairs at the PWM update instant,
//! and the filtered speed.

use angletrack::DriveColumns;
use angletrack_core::{DriveOutputs as CoreDriveOutputs, DriveOutputsState};
use pyo3::prelude::*;

use crate::arrays::{Column, Count, float64};
use crate::errors::Result;
use crate::estimates::Estimates;
use crate::getters::result_class;

result_class! {
    /// The drive's outputs of one `DriveOutputs.update`, float64 arrays (turns int64), one
    /// element per estimate.
    PyDriveAngles = "DriveAngles" of |py, d: DriveColumns| {
        /// The motor's electrical angle at the latency (rad, in [-pi, pi)).
        electrical_angle_rad: Column<f64> = d.electrical_angle_rad,
        /// The motor's electrical speed (rad/s), filtered.
        electrical_speed_rad_s: Column<f64> = d.electrical_speed_rad_s,
        /// The shaft's mechanical angle at the latency (rad, in [-pi, pi)).
        mechanical_angle_rad: Column<f64> = d.mechanical_angle_rad,
        /// Whole mechanical turns.
        mechanical_turns: Column<i64> = d.mechanical_turns,
        /// The shaft's mechanical speed (rad/s), filtered.
        mechanical_speed_rad_s: Column<f64> = d.mechanical_speed_rad_s,
    }
}

/// What a drive takes from an observer's estimates: the angle extrapolated by `latency_s`
/// (s, the PWM update instant) from the estimated speed and acceleration, as the electrical
/// angle of a motor of `pole_pairs` read by a resolver of `speed_ratio`, and the speed with
/// an optional first-order low-pass of `speed_cutoff_hz`; for estimates every
/// `sample_period_s`. The speed filter's state carries over between `update` calls.
#[pyclass(name = "DriveOutputs", module = "angletrack")]
#[derive(Debug)]
pub struct PyDriveOutputs {
    outputs: CoreDriveOutputs<f64>,
    state: DriveOutputsState<f64>,
}

#[pymethods]
impl PyDriveOutputs {
    #[new]
    #[pyo3(signature = (*, sample_period_s, pole_pairs = Count::Whole(1), speed_ratio = Count::Whole(1),
        latency_s = 0.0, speed_cutoff_hz = None),
        text_signature = "(*, sample_period_s, pole_pairs=1, speed_ratio=1, latency_s=0.0, speed_cutoff_hz=None)")]
    fn py_new(
        sample_period_s: f64,
        pole_pairs: Count,
        speed_ratio: Count,
        latency_s: f64,
        speed_cutoff_hz: Option<f64>,
    ) -> Result<Self> {
        let (pole_pairs, speed_ratio) = (
            pole_pairs.get("pole_pairs")?,
            speed_ratio.get("speed_ratio")?,
        );
        let mut outputs =
            CoreDriveOutputs::new(pole_pairs, speed_ratio, latency_s, sample_period_s)?;
        if let Some(cutoff) = speed_cutoff_hz {
            outputs = outputs.with_speed_cutoff_hz(cutoff)?;
        }
        Ok(Self {
            outputs,
            state: DriveOutputsState::default(),
        })
    }

    /// The drive's angles of each of `estimates` (an observer's, either dtype).
    #[pyo3(signature = (estimates))]
    fn update(&mut self, py: Python<'_>, estimates: PyRef<'_, Estimates>) -> Result<PyDriveAngles> {
        let column = |a: &Py<PyAny>| float64(a.bind(py), "estimates");
        let columns = [
            column(&estimates.angle)?,
            column(&estimates.position)?,
            column(&estimates.speed)?,
            column(&estimates.acceleration)?,
        ];
        let columns = columns.each_ref().map(Vec::as_slice);
        let d = DriveColumns::of_estimates(&self.outputs, &mut self.state, columns);
        PyDriveAngles::of(py, d)
    }

    #[getter]
    fn latency_s(&self) -> f64 {
        self.outputs.latency_s()
    }
}
