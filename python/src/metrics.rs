//! `metrics`: the quality of a run against a scenario's truth, from the `angletrack` crate.

use angletrack::{ErrorStatistics, Metrics, MetricsOptions};
use pyo3::prelude::*;

use crate::arrays::float64;
use crate::errors::Result;
use crate::estimates::Estimates;
use crate::getters::class_methods;
use crate::scenario::PyScenario;

/// Mean, RMS and largest magnitude of an error series.
#[pyclass(name = "ErrorStatistics", module = "angletrack", frozen)]
#[derive(Debug, Clone)]
pub struct PyErrorStatistics(ErrorStatistics);

class_methods! {
    PyErrorStatistics {
        /// Root mean square.
        rms: f64 = |this, py| this.0.rms;
        /// Largest magnitude.
        max: f64 = |this, py| this.0.max;
        /// Mean (signed: a bias).
        mean: f64 = |this, py| this.0.mean;
    }
    methods {
        fn __repr__(&self) -> String {
            format!("ErrorStatistics({})", self.fields())
        }
    }
}

impl PyErrorStatistics {
    /// `rms=..., max=..., mean=...`.
    fn fields(&self) -> String {
        let s = &self.0;
        format!("rms={:.6e}, max={:.6e}, mean={:.6e}", s.rms, s.max, s.mean)
    }
}

/// The quality of a run against the truth (errors are truth - estimate).
#[pyclass(name = "Metrics", module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct PyMetrics {
    /// Wrapped angle error (rad) over the samples from `skip_s` on.
    angle_error_rad: PyErrorStatistics,
    /// Speed error (rad/s) over the same samples; `None` without a speed truth.
    speed_error_rad_s: Option<PyErrorStatistics>,
    /// Number of samples in the statistics.
    samples: usize,
    /// Overshoot past the truth's final angle, as a fraction of the move; `None` when the
    /// truth ends where it started.
    overshoot: Option<f64>,
    /// Time (s) after which the estimate stays within the settling band of the move.
    settling_time_s: Option<f64>,
    /// Time (s) from which the wrapped angle error stays within the lock tolerance.
    time_to_lock_s: Option<f64>,
}

fn optional(v: Option<f64>) -> String {
    v.map_or("None".into(), |x| format!("{x:.6e}"))
}

#[pymethods]
impl PyMetrics {
    fn __repr__(&self) -> String {
        format!(
            "Metrics(angle_error_rad: {}; speed_error_rad_s: {}; samples={}, overshoot={}, \
             settling_time_s={}, time_to_lock_s={})",
            self.angle_error_rad.fields(),
            self.speed_error_rad_s
                .as_ref()
                .map_or("None".into(), PyErrorStatistics::fields),
            self.samples,
            optional(self.overshoot),
            optional(self.settling_time_s),
            optional(self.time_to_lock_s),
        )
    }
}

/// Measures the estimates of a run against the scenario's truth: wrapped angle error and
/// speed error statistics from `skip_s` (s) on, overshoot and settling time (band
/// `settling_band` of the move), and time to lock (error within `lock_tolerance_rad`).
#[pyfunction]
#[pyo3(signature = (scenario, estimates, *, skip_s = 0.0, lock_tolerance_rad = 0.01, settling_band = 0.02))]
pub fn metrics(
    py: Python<'_>,
    scenario: &PyScenario,
    estimates: &Estimates,
    skip_s: f64,
    lock_tolerance_rad: f64,
    settling_band: f64,
) -> Result<PyMetrics> {
    let truth = angletrack::Scenario {
        sample_period_s: scenario.sample_period_s,
        time_s: float64(scenario.time_s.bind(py).as_any(), "scenario.time_s")?,
        angle_rad: float64(scenario.angle_rad.bind(py).as_any(), "scenario.angle_rad")?,
        speed_rad_s: if scenario.has_speed {
            float64(
                scenario.speed_rad_s.bind(py).as_any(),
                "scenario.speed_rad_s",
            )?
        } else {
            // Unknown speed truth: any finite series; its statistics are not reported.
            vec![0.0; scenario.len]
        },
        ..Default::default()
    };
    let run = angletrack::Run {
        angle_rad: float64(estimates.position.bind(py), "estimates.position")?,
        speed_rad_s: float64(estimates.speed.bind(py), "estimates.speed")?,
        acceleration_rad_s2: float64(estimates.acceleration.bind(py), "estimates.acceleration")?,
    };
    let options = MetricsOptions {
        skip_s,
        lock_tolerance_rad,
        settling_band,
    };
    let m = py.detach(|| Metrics::new(&truth, &run, &options))?;
    Ok(PyMetrics {
        angle_error_rad: PyErrorStatistics(m.angle_error_rad),
        speed_error_rad_s: scenario
            .has_speed
            .then_some(PyErrorStatistics(m.speed_error_rad_s)),
        samples: m.samples,
        overshoot: m.overshoot,
        settling_time_s: m.settling_time_s,
        time_to_lock_s: m.time_to_lock_s,
    })
}
