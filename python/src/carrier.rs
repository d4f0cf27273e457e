//! What a capture's samples tell of the front end, measured in the crate: the ADC's rails
//! (`angletrack::measured_adc_range`), against which clipping is flagged when no range is
//! stated, and the plan of a capture of raw windings (`angletrack::WindingsPlan`).

use pyo3::prelude::*;

use angletrack::{WindingsPlan, WindingsSettings};

use crate::arrays::paired_samples;
use crate::errors::{Error, Result};
use crate::getters::result_class;

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
    let (c, s) = paired_samples::<f64>((y_c, "y_c"), (y_s, "y_s"))?;
    Ok(angletrack::measured_adc_range(c.as_slice(), s.as_slice()))
}

result_class! {
    /// How a capture of raw windings is demodulated (`angletrack::WindingsPlan`): the ADC rate
    /// and samples per declared carrier period, a winding's carrier amplitude, the ADC's codes
    /// and where they come from (`"stated"`, `"measured: extremes held flat"` or `"guessed"`).
    PyWindingsPlan = "WindingsPlan" of |py, p: WindingsPlan| {
        /// The ADC rate (Hz).
        adc_rate_hz: f64 = p.adc_rate_hz,
        /// ADC samples per declared carrier period.
        samples_per_period: f64 = p.samples_per_period,
        /// A winding's carrier amplitude at envelope 1 (counts).
        carrier_amplitude_counts: f64 = p.carrier_amplitude_counts,
        /// The lowest ADC code clipping is checked against.
        adc_min_code: f64 = p.adc_range.0,
        /// The highest ADC code clipping is checked against.
        adc_max_code: f64 = p.adc_range.1,
        /// Where the ADC's codes come from.
        adc_range_source: String = p.adc_range_source.to_string(),
    }
}

/// The plan of a capture of raw windings whose first samples are `first_c`, `first_s`
/// (1-D float64): the ADC rate from `samples_per_period` times `carrier_hz`, else the
/// capture's rate `capture_hz`; a ratio the time column contradicts by more than 1 %, or a
/// carrier more than 2 % from the one measured in the samples, is refused naming both
/// values; the amplitude and ADC range as stated, else measured (the range guessed when no
/// rail shows). `ConfigError` for unequal lengths (naming `first_s`), an amplitude that is
/// not a positive number of counts up to 2^31, or a range that is not two finite numbers,
/// the first below the second.
///
/// >>> import numpy as np
/// >>> from angletrack._angletrack import plan_windings
/// >>> k = np.arange(4000)
/// >>> carrier = np.sin(2 * np.pi * k / 15.0)
/// >>> c, s = 2048 + 1800 * np.cos(0.002 * k) * carrier, 2048 + 1800 * np.sin(0.002 * k) * carrier
/// >>> plan = plan_windings(c, s, carrier_hz=10e3, capture_hz=150e3)
/// >>> plan.samples_per_period, plan.adc_min_code, plan.adc_max_code, plan.adc_range_source
/// (15.0, 0.0, 4095.0, 'guessed')
#[pyfunction]
#[pyo3(signature = (first_c, first_s, *, carrier_hz, capture_hz = None, samples_per_period = None,
    carrier_amplitude_counts = None, adc_range = None))]
pub fn plan_windings(
    first_c: &Bound<'_, PyAny>,
    first_s: &Bound<'_, PyAny>,
    carrier_hz: f64,
    capture_hz: Option<f64>,
    samples_per_period: Option<f64>,
    carrier_amplitude_counts: Option<f64>,
    adc_range: Option<(f64, f64)>,
) -> Result<PyWindingsPlan> {
    let (c, s) = paired_samples::<f64>((first_c, "first_c"), (first_s, "first_s"))?;
    let adc_range = angletrack::checked_adc_range(adc_range)?;
    let mut settings = WindingsSettings::new(carrier_hz);
    settings.capture_hz = capture_hz;
    settings.samples_per_period = samples_per_period;
    settings.carrier_amplitude_counts = carrier_amplitude_counts;
    settings.adc_range = adc_range;
    let plan = WindingsPlan::new(c.as_slice(), s.as_slice(), &settings)
        .map_err(|e| Error::value(e.argument(), e.to_string()))?;
    PyWindingsPlan::of(first_c.py(), plan)
}
