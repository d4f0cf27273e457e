//! `measured_carrier_cycles_per_sample`: the carrier frequency of raw windings, measured in
//! the capture (`angletrack::measured_carrier_cycles_per_sample`), against which a declared
//! carrier is checked.

use pyo3::prelude::*;

use crate::arrays::samples;
use crate::errors::Result;

/// The carrier frequency of the raw windings `y_c`, `y_s` (1-D float64, any offset) in
/// cycles per sample, from the tone at twice the carrier in `y_c^2 + y_s^2` (the angle
/// modulation cancels there); `None` when it cannot be measured (too few samples, no
/// carrier, fewer than about 5 samples per carrier period).
///
/// >>> import numpy as np
/// >>> from angletrack._angletrack import measured_carrier_cycles_per_sample
/// >>> k = np.arange(4000)
/// >>> carrier = np.sin(2 * np.pi * k / 15.0)
/// >>> round(1 / measured_carrier_cycles_per_sample(np.cos(0.001 * k) * carrier, np.sin(0.001 * k) * carrier), 3)
/// 15.0
#[pyfunction]
pub fn measured_carrier_cycles_per_sample(
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
) -> Result<Option<f64>> {
    let (c, s) = (samples::<f64>(y_c, "y_c")?, samples::<f64>(y_s, "y_s")?);
    Ok(angletrack::measured_carrier_cycles_per_sample(
        c.as_slice(),
        s.as_slice(),
    ))
}
