//! `ObserverBatch` and `track_batch`: many channels on one gain set (the design crate's
//! `ChannelBatch`, run by the core's vectorisable `ChannelBank`s) on 2-D numpy arrays.

use angletrack::{AnyBatch, ChannelBatch, OutputSet, with_any_channel};
use pyo3::prelude::*;

use crate::arrays::{Float, channel_samples};
use crate::dispatch::{Arg, PhaseSinCos, RunSettings, Sample};
use crate::errors::{Error, Result};
use crate::estimates::{Estimates, output_set, run_estimates};
use crate::gains::PyGains;
use crate::getters::class_methods;

/// Runs `batch` over 2-D `y_c`, `y_s` (channels x samples) and returns the estimates in
/// `outputs`, shaped like the inputs; the state carries over to the next call.
fn run_batch<T: Sample, const N: usize, S: PhaseSinCos<T>>(
    py: Python<'_>,
    batch: &mut ChannelBatch<T, N, S>,
    (y_c, y_s): (Arg<'_, '_>, Arg<'_, '_>),
    outputs: OutputSet,
) -> Result<Estimates> {
    let (y_c, channels_c, samples) = channel_samples::<T>(y_c, "y_c")?;
    let (y_s, channels_s, samples_s) = channel_samples::<T>(y_s, "y_s")?;
    if (channels_c, samples) != (channels_s, samples_s) {
        return Err(Error::value(
            "y_s",
            format!(
                "has shape ({channels_s}, {samples_s}) but y_c has ({channels_c}, {samples}): \
                 they must be equal"
            ),
        ));
    }
    if channels_c != batch.channels() {
        return Err(Error::value(
            "y_c",
            format!(
                "has {channels_c} channels (rows) but the batch has {}",
                batch.channels()
            ),
        ));
    }
    let (y_c, y_s) = (
        crate::arrays::samples::<T>(&y_c, "y_c")?,
        crate::arrays::samples::<T>(&y_s, "y_s")?,
    );
    let (y_c, y_s) = (y_c.as_slice(), y_s.as_slice());
    let shape = Some((channels_c, samples));
    let (run, estimates) = run_estimates(py, channels_c * samples, (outputs, shape), |c| {
        batch.run(y_c, y_s, samples, c)
    })?;
    run?;
    Ok(estimates)
}

/// Many independent observers on one gain set: `channels` channels (several axes, a Monte
/// Carlo batch), run 8 at a time side by side (the core's struct-of-arrays `ChannelBank`).
/// The state persists between calls, so chunks along the sample axis give exactly the result
/// of one call. Each channel gives exactly what an `Observer` with the same gains and
/// `FaultThresholds.disabled()` gives: a batch rejects bad samples (fault bit BAD_SAMPLE)
/// but runs no fault monitor. The samples are floats of amplitude about 1: a sample whose
/// magnitude `sqrt(y_c^2 + y_s^2)` is above 4 (the thresholds' `max_input_amplitude`) is
/// rejected as BAD_SAMPLE. Raw ADC counts (an integer dtype) are refused (`TypeError` naming
/// the argument): scale them to that amplitude first, `(counts - mid_scale) / amplitude`.
/// `update(..., outputs=("angle", "speed"))`
/// computes and returns only those estimates (the others are `None`).
#[pyclass(name = "ObserverBatch", module = "angletrack", extends = RunSettings)]
#[derive(Debug)]
pub struct PyObserverBatch {
    inner: AnyBatch,
}

class_methods! {
    PyObserverBatch {
        /// The number of channels.
        channels: usize = |this, py| this.inner.channels();
    }
    methods {
        #[new]
        #[pyo3(signature = (gains, channels, *, dtype = None, sin_cos = None))]
        fn py_new(
            gains: PyGains,
            channels: crate::arrays::Count,
            dtype: Option<&Bound<'_, PyAny>>,
            sin_cos: Option<&str>,
        ) -> Result<PyClassInitializer<Self>> {
            let channels = channels.at_least("channels", 1)?;
            let settings = RunSettings::from_arguments(gains, dtype, sin_cos)?;
            let inner = settings.batch(channels)?;
            Ok(settings.subclass(Self { inner }))
        }

        /// Runs every channel over its samples: `y_c`, `y_s` are 2-D arrays (channels x
        /// samples) of the batch's dtype; returns `Estimates` whose arrays have that shape.
        /// `outputs` names the estimates to compute (`angle`, `position`, `speed`,
        /// `acceleration`, `phase_error`, `faults`; `None`: all), the others are `None`.
        #[pyo3(signature = (y_c, y_s, *, outputs = None))]
        fn update(
            &mut self,
            py: Python<'_>,
            y_c: Arg<'_, '_>,
            y_s: Arg<'_, '_>,
            outputs: Option<Arg<'_, '_>>,
        ) -> Result<Estimates> {
            let outputs = output_set(outputs)?;
            with_any_channel!(AnyBatch, &mut self.inner, b => run_batch(py, b, (y_c, y_s), outputs))
        }

        fn __repr__(slf: PyRef<'_, Self>) -> String {
            format!(
                "ObserverBatch(channels={}, {})",
                slf.inner.channels(),
                slf.as_super().describe()
            )
        }
    }
}

/// Runs a fresh batch of observers with `gains` over 2-D arrays `y_c`, `y_s` (channels x
/// samples) in their own dtype (float32 or float64, amplitude about 1: see `ObserverBatch`)
/// and returns the estimates, shaped like the inputs: those
/// named in `outputs` (`None`: all; e.g. `("angle", "speed")`), the others `None`.
#[pyfunction]
#[pyo3(signature = (gains, y_c, y_s, *, sin_cos = None, outputs = None))]
pub fn track_batch(
    py: Python<'_>,
    gains: PyGains,
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
    sin_cos: Option<&str>,
    outputs: Option<&Bound<'_, PyAny>>,
) -> Result<Estimates> {
    let outputs = output_set(outputs)?;
    let settings = RunSettings::new(gains, Float::of_samples(y_c, "y_c")?, sin_cos)?;
    // `numpy.shape` reads nested sequences too (the run refuses any shape but 2-D).
    let channels = PyModule::import(py, "numpy")?
        .getattr("shape")?
        .call1((y_c,))
        .and_then(|s| s.get_item(0))
        .and_then(|c| c.extract::<usize>())
        .map_err(|_| Error::value("y_c", "expected a 2-D array (channels x samples)"))?;
    let mut batch = settings.batch(channels)?;
    with_any_channel!(AnyBatch, &mut batch, b => run_batch(py, b, (y_c, y_s), outputs))
}
