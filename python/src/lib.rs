//! The `angletrack._angletrack` Python extension: the angle tracking observers of
//! `angletrack-core` on numpy arrays, and the design tools of `angletrack`.
//!
//! This crate only converts: arguments in (checked by [`arrays`]), results out, errors in
//! one place ([`errors`]). Every computation is a call into the Rust crates.

use pyo3::prelude::*;

mod arrays;
mod batch;
mod design;
mod errors;
mod observer;
mod scenario;

/// The compiled part of the `angletrack` Python package.
#[pymodule]
fn _angletrack(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<observer::PyGains>()?;
    m.add_class::<observer::PyObserver>()?;
    m.add_class::<observer::PyFaultThresholds>()?;
    m.add("FAULT_BITS", observer::fault_bits().to_vec())?;
    m.add_class::<observer::Estimate>()?;
    m.add_class::<observer::Estimates>()?;
    m.add_function(wrap_pyfunction!(observer::track, m)?)?;
    m.add_class::<batch::PyObserverBatch>()?;
    m.add_function(wrap_pyfunction!(batch::track_batch, m)?)?;
    design::register(m)?;
    scenario::register(m)?;
    Ok(())
}
