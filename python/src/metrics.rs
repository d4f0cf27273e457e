//! `metrics`: the quality of a run against a scenario's truth, from the `angletrack` crate.

use angletrack::{ErrorStatistics, Metrics, MetricsOptions};
use pyo3::prelude::*;

use crate::arrays::float64;
use crate::errors::Result;
use crate::estimates::Estimates;
use crate::getters::result_class;
use crate::scenario::PyScenario;

result_class! {
    /// Mean, RMS and largest magnitude of an error series.
    #[derive(Clone)]
    PyErrorStatistics = "ErrorStatistics" of |py, e: ErrorStatistics| {
        /// Root mean square.
        rms: f64 = e.rms,
        /// Largest magnitude.
        max: f64 = e.max,
        /// Mean (signed: a bias).
        mean: f64 = e.mean,
    }
    repr |e| format!("ErrorStatistics({})", e.fields());
}

impl PyErrorStatistics {
    /// `rms=..., max=..., mean=...`.
    fn fields(&self) -> String {
        format!(
            "rms={:.6e}, max={:.6e}, mean={:.6e}",
            self.rms, self.max, self.mean
        )
    }
}

fn optional(v: Option<f64>) -> String {
    v.map_or("None".into(), |x| format!("{x:.6e}"))
}

result_class! {
    /// The quality of a run against the truth (errors are truth - estimate).
    PyMetrics = "Metrics" of |py, (m, has_speed): (Metrics, bool)| {
        /// Wrapped angle error (rad) over the samples from `skip_s` on.
        angle_error_rad: PyErrorStatistics = PyErrorStatistics::of(py, m.angle_error_rad)?,
        /// Speed error (rad/s) over the same samples; `None` without a speed truth.
        speed_error_rad_s: Option<PyErrorStatistics> =
            has_speed.then(|| PyErrorStatistics::of(py, m.speed_error_rad_s)).transpose()?,
        /// Number of samples in the statistics.
        samples: usize = m.samples,
        /// Overshoot past the truth's final angle, as a fraction of the move; `None` when the
        /// truth ends where it started.
        overshoot: Option<f64> = m.overshoot,
        /// Time (s) after which the estimate stays within the settling band of the move.
        settling_time_s: Option<f64> = m.settling_time_s,
        /// Time (s) from which the wrapped angle error stays within the lock tolerance.
        time_to_lock_s: Option<f64> = m.time_to_lock_s,
    }
    repr |m| format!(
        "Metrics(angle_error_rad: {}; speed_error_rad_s: {}; samples={}, overshoot={}, \
         settling_time_s={}, time_to_lock_s={})",
        m.angle_error_rad.fields(),
        m.speed_error_rad_s.as_ref().map_or("None".into(), PyErrorStatistics::fields),
        m.samples,
        optional(m.overshoot),
        optional(m.settling_time_s),
        optional(m.time_to_lock_s),
    );
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
    PyMetrics::of(py, (m, scenario.has_speed))
}
