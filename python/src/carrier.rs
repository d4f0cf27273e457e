//! What a capture's samples tell of the front end, measured in the crate: the carrier
//! frequency of raw windings (`angletrack::measured_carrier_cycles_per_sample`), against
//! which a declared carrier is checked, and the ADC's rails (`angletrack::measured_adc_range`),
//! against which clipping is flagged when no range is stated.

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

/// The ADC range measured on the samples `y_c`, `y_s` (1-D float64; NaNs ignored): each
/// extreme of both channels that is a rail (held flat over 4 consecutive samples of a
/// channel, and reached by more than four times the samples of the half-percent band just
/// inside it); an extreme that is not is put one span beyond. ``None`` when neither is a
/// rail: clipping is then not checked.
///
/// >>> import numpy as np
/// >>> from angletrack._angletrack import measured_adc_range
/// >>> k = np.arange(2000)
/// >>> measured_adc_range(np.clip(np.cos(0.01 * k), -0.9, 0.9), np.clip(np.sin(0.01 * k), -0.9, 0.9))
/// (-0.9, 0.9)
#[pyfunction]
pub fn measured_adc_range(
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
) -> Result<Option<(f64, f64)>> {
    let (c, s) = (samples::<f64>(y_c, "y_c")?, samples::<f64>(y_s, "y_s")?);
    Ok(angletrack::measured_adc_range(c.as_slice(), s.as_slice()))
}
