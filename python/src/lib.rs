//! The `angletrack._angletrack` Python extension: the angle tracking observers of
//! `angletrack-core` on numpy arrays, and the design tools of `angletrack`.
//!
//! This crate only converts: arguments in (checked by `arrays`), results out, errors in
//! one place (`errors`). Every computation is a call into the Rust crates.

use pyo3::prelude::*;

mod analysis;
mod angle_calibration;
mod arrays;
mod batch;
mod calibration;
mod calibration_file;
mod capture;
mod carrier;
mod counts;
mod design;
mod design_capture;
mod design_functions;
mod diagnostics;
mod dispatch;
mod drive;
mod errors;
mod estimates;
mod export;
mod fixed;
mod fixed_estimates;
mod gains;
mod getters;
mod json;
mod metrics;
mod model_class;
mod motion;
mod observer;
mod paper;
mod resolver;
mod scenario;
mod study;
mod tracker_file;
mod writer;

/// The compiled part of the `angletrack` Python package.
#[pymodule]
fn _angletrack(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("ConfigError", m.py().get_type::<errors::ConfigError>())?;
    m.add_class::<gains::PyGains>()?;
    m.add_class::<observer::PyObserver>()?;
    m.add_class::<diagnostics::PyFaultThresholds>()?;
    m.add_class::<calibration::PySensorCalibration>()?;
    m.add("FAULT_BITS", diagnostics::fault_bits())?;
    m.add("FRONT_END_FAULT_BITS", diagnostics::front_end_fault_bits())?;
    m.add_class::<estimates::Estimate>()?;
    m.add_class::<estimates::Estimates>()?;
    m.add_function(wrap_pyfunction!(observer::track, m)?)?;
    m.add_class::<fixed::PyFixedObserver>()?;
    m.add_class::<fixed_estimates::FixedEstimate>()?;
    m.add_class::<fixed_estimates::FixedEstimates>()?;
    m.add_class::<batch::PyObserverBatch>()?;
    m.add_function(wrap_pyfunction!(batch::track_batch, m)?)?;
    m.add_function(wrap_pyfunction!(carrier::measured_adc_range, m)?)?;
    m.add_function(wrap_pyfunction!(carrier::plan_windings, m)?)?;
    m.add_class::<carrier::PyWindingsPlan>()?;
    m.add("HELD_RAIL_SAMPLES", angletrack::core::HELD_RAIL_SAMPLES)?;
    m.add_function(wrap_pyfunction!(counts::capture_counts, m)?)?;
    m.add_function(wrap_pyfunction!(counts::capture_fault_thresholds, m)?)?;
    m.add_class::<counts::PyCountsExtremes>()?;
    design_functions::register(m)?;
    scenario::register(m)?;
    metrics::register(m)?;
    paper::register(m)?;
    capture::register(m)?;
    resolver::register(m)?;
    angle_calibration::register(m)?;
    export::register(m)?;
    calibration_file::register(m)?;
    tracker_file::register(m)?;
    design_capture::register(m)?;
    study::register(m)?;
    Ok(())
}
