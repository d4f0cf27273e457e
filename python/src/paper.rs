//! The paper's settings and reference observers (`angletrack::paper`): what `angletrack
//! report` reproduces, and the gains the tests and benchmarks run.

use angletrack::paper::{self, ComparedObserver, PaperSetting};
use pyo3::prelude::*;

use crate::design::PyDesign;
use crate::errors::Result;
use crate::gains::{GainSet, PyGains};
use crate::getters::result_class;

result_class! {
    /// One of the four settings whose step-response overshoot the paper quotes.
    PyPaperSetting = "PaperSetting" of |py, (s, design): (PaperSetting, PyDesign)| {
        /// The setting, in words (`"2nd order, m = 1.945"`).
        name: &'static str = s.name(),
        /// The overshoot the paper quotes (percent).
        paper_overshoot_percent: f64 = s.overshoot_percent(),
        /// The setting designed at the requested sample period.
        design: PyDesign = design,
    }
    repr |s| format!(
        "PaperSetting(name={:?}, paper_overshoot_percent={}, design=...)",
        s.name, s.paper_overshoot_percent
    );
}

/// The paper's four settings, in its order, designed at `sample_period_s` (by default
/// 100 kHz, at least 200 times each loop's bandwidth) with `discretisation`.
#[pyfunction]
#[pyo3(signature = (sample_period_s = paper::OVERSHOOT_SAMPLE_PERIOD_S, discretisation = "pole_matching"))]
pub fn paper_settings(
    py: Python<'_>,
    sample_period_s: f64,
    discretisation: &str,
) -> Result<Vec<PyPaperSetting>> {
    let discretisation = discretisation.parse()?;
    PaperSetting::ALL
        .into_iter()
        .map(|s| PyPaperSetting::of(py, (s, s.design(sample_period_s, discretisation)?.into())))
        .collect()
}

/// The three observers the report compares, `(name, design)`: the 2nd-order, 3rd-order and
/// Kalman ATOs, each about `PAPER_COMPARISON_BANDWIDTH_HZ` wide at
/// `PAPER_COMPARISON_SAMPLE_PERIOD_S`.
#[pyfunction]
pub fn paper_compared_observers() -> Result<Vec<(&'static str, PyDesign)>> {
    ComparedObserver::ALL
        .into_iter()
        .map(|o| Ok((o.name(), o.design()?.into())))
        .collect()
}

/// The fixed discrete gains of the benchmarks (10 kHz): the 2nd-order, 3rd-order and Kalman
/// ATOs, as the firmware embeds them.
#[pyfunction]
pub fn paper_benchmark_gains() -> Result<Vec<PyGains>> {
    let ts = paper::BENCHMARK_SAMPLE_PERIOD_S;
    [
        &paper::BENCHMARK_SECOND_ORDER_GAINS[..],
        &paper::BENCHMARK_THIRD_ORDER_GAINS[..],
        &paper::BENCHMARK_KALMAN_GAINS[..],
    ]
    .into_iter()
    .map(|l| {
        Ok(PyGains {
            set: GainSet::new(l, ts)?,
        })
    })
    .collect()
}
