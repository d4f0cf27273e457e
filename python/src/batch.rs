//! `ObserverBatch` and `track_batch`: many channels on one gain set (the design crate's
//! `ChannelBatch`, run by the core's vectorisable `ChannelBank`s) on 2-D numpy arrays.

use angletrack::ChannelBatch;
use angletrack_core::{Exact, Fast, Gains as CoreGains, Order, Real, SinCos, SupportedOrder};
use numpy::Element;
use pyo3::prelude::*;

use crate::arrays::{Float, channel_samples};
use crate::errors::{Error, Result};
use crate::observer::{Estimates, GainSet, OutputArrays, PyGains, SinCosKind};

/// A batch of any float type, order and sin/cos.
#[derive(Debug, Clone)]
enum AnyBatch {
    F32x2Fast(ChannelBatch<f32, 2, Fast>),
    F32x2Exact(ChannelBatch<f32, 2, Exact>),
    F32x3Fast(ChannelBatch<f32, 3, Fast>),
    F32x3Exact(ChannelBatch<f32, 3, Exact>),
    F64x2Fast(ChannelBatch<f64, 2, Fast>),
    F64x2Exact(ChannelBatch<f64, 2, Exact>),
    F64x3Fast(ChannelBatch<f64, 3, Fast>),
    F64x3Exact(ChannelBatch<f64, 3, Exact>),
}

/// The `f64` gains in float type `T`, checked again there, for `channels` channels.
fn typed<T: Real, const N: usize, S: SinCos<T>>(
    g: &CoreGains<f64, N>,
    channels: usize,
) -> Result<ChannelBatch<T, N, S>>
where
    Order<N>: SupportedOrder,
{
    let gains = CoreGains::new(g.gains().map(T::from_f64), T::from_f64(g.sample_period()))?;
    Ok(ChannelBatch::new(gains, channels)?)
}

impl AnyBatch {
    fn new(set: &GainSet, float: Float, sin_cos: SinCosKind, channels: usize) -> Result<Self> {
        use {Float::*, SinCosKind::*};
        let c = channels;
        Ok(match (set, float, sin_cos) {
            (GainSet::Second(g), F32, Fast) => AnyBatch::F32x2Fast(typed(g, c)?),
            (GainSet::Second(g), F32, Exact) => AnyBatch::F32x2Exact(typed(g, c)?),
            (GainSet::Third(g), F32, Fast) => AnyBatch::F32x3Fast(typed(g, c)?),
            (GainSet::Third(g), F32, Exact) => AnyBatch::F32x3Exact(typed(g, c)?),
            (GainSet::Second(g), F64, Fast) => AnyBatch::F64x2Fast(typed(g, c)?),
            (GainSet::Second(g), F64, Exact) => AnyBatch::F64x2Exact(typed(g, c)?),
            (GainSet::Third(g), F64, Fast) => AnyBatch::F64x3Fast(typed(g, c)?),
            (GainSet::Third(g), F64, Exact) => AnyBatch::F64x3Exact(typed(g, c)?),
        })
    }

    fn run(
        &mut self,
        py: Python<'_>,
        y_c: &Bound<'_, PyAny>,
        y_s: &Bound<'_, PyAny>,
    ) -> Result<Estimates> {
        match self {
            AnyBatch::F32x2Fast(b) => run_arrays(py, b, y_c, y_s),
            AnyBatch::F32x2Exact(b) => run_arrays(py, b, y_c, y_s),
            AnyBatch::F32x3Fast(b) => run_arrays(py, b, y_c, y_s),
            AnyBatch::F32x3Exact(b) => run_arrays(py, b, y_c, y_s),
            AnyBatch::F64x2Fast(b) => run_arrays(py, b, y_c, y_s),
            AnyBatch::F64x2Exact(b) => run_arrays(py, b, y_c, y_s),
            AnyBatch::F64x3Fast(b) => run_arrays(py, b, y_c, y_s),
            AnyBatch::F64x3Exact(b) => run_arrays(py, b, y_c, y_s),
        }
    }
}

fn run_arrays<T: Real + Element, const N: usize, S: SinCos<T>>(
    py: Python<'_>,
    batch: &mut ChannelBatch<T, N, S>,
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
) -> Result<Estimates>
where
    Order<N>: SupportedOrder,
{
    let (y_c, channels_c, samples) = channel_samples::<T>(y_c, "y_c")?;
    let (y_s, channels_s, samples_s) = channel_samples::<T>(y_s, "y_s")?;
    if (channels_c, samples) != (channels_s, samples_s) {
        return Err(Error::value(
            "y_s",
            format!(
                "has shape ({channels_s}, {samples_s}) but y_c has ({channels_c}, {samples}): they must be equal"
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
    let out = OutputArrays::<T>::new(py, channels_c * samples);
    let (y_c, y_s) = (y_c.as_slice(), y_s.as_slice());
    out.fill(py, |columns| batch.run(y_c, y_s, samples, columns))??;
    out.into_estimates(samples, Some((channels_c, samples)))
}

/// Many independent observers on one gain set: `channels` channels (several axes, a Monte
/// Carlo batch), run 8 at a time side by side (the core's struct-of-arrays `ChannelBank`).
/// The state persists between calls, so chunks along the sample axis give exactly the result
/// of one call. Each channel gives exactly what an `Observer` with the same gains and
/// `FaultThresholds.disabled()` gives: a batch rejects bad samples (fault bit BAD_SAMPLE)
/// but runs no fault monitor.
#[pyclass(name = "ObserverBatch", module = "angletrack")]
#[derive(Debug)]
pub struct PyObserverBatch {
    gains: PyGains,
    float: Float,
    sin_cos: SinCosKind,
    channels: usize,
    inner: AnyBatch,
}

#[pymethods]
impl PyObserverBatch {
    #[new]
    #[pyo3(signature = (gains, channels, *, dtype = None, sin_cos = None))]
    fn py_new(
        gains: PyGains,
        channels: usize,
        dtype: Option<&Bound<'_, PyAny>>,
        sin_cos: Option<&str>,
    ) -> Result<Self> {
        let float = Float::from_dtype_like(dtype, "dtype")?;
        let sin_cos = SinCosKind::parse(sin_cos, float)?;
        let inner = AnyBatch::new(&gains.set, float, sin_cos, channels)?;
        Ok(Self {
            gains,
            float,
            sin_cos,
            channels,
            inner,
        })
    }

    /// Runs every channel over its samples: `y_c`, `y_s` are 2-D arrays (channels x
    /// samples) of the batch's dtype; returns `Estimates` whose arrays have that shape.
    #[pyo3(signature = (y_c, y_s))]
    fn update(
        &mut self,
        py: Python<'_>,
        y_c: &Bound<'_, PyAny>,
        y_s: &Bound<'_, PyAny>,
    ) -> Result<Estimates> {
        self.inner.run(py, y_c, y_s)
    }

    /// The number of channels.
    #[getter]
    fn channels(&self) -> usize {
        self.channels
    }

    /// The gains every channel runs with.
    #[getter]
    fn gains(&self) -> PyGains {
        self.gains.clone()
    }

    /// The float type: 'float32' or 'float64'.
    #[getter]
    fn dtype(&self) -> &'static str {
        self.float.name()
    }

    /// The phase detector's sin/cos: 'fast' or 'exact'.
    #[getter]
    fn sin_cos(&self) -> &'static str {
        self.sin_cos.name()
    }

    fn __repr__(&self) -> String {
        format!(
            "ObserverBatch(channels={}, order={}, dtype={}, sin_cos={}, sample_period_s={:e})",
            self.channels,
            self.gains.set.order(),
            self.float.name(),
            self.sin_cos.name(),
            self.gains.set.sample_period()
        )
    }
}

/// Runs a fresh batch of observers with `gains` over 2-D arrays `y_c`, `y_s` (channels x
/// samples) in their own dtype and returns the estimates, shaped like the inputs.
#[pyfunction]
#[pyo3(signature = (gains, y_c, y_s, *, sin_cos = None))]
pub fn track_batch(
    py: Python<'_>,
    gains: PyGains,
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
    sin_cos: Option<&str>,
) -> Result<Estimates> {
    let float = Float::of_samples(y_c, "y_c")?;
    let sin_cos = SinCosKind::parse(sin_cos, float)?;
    let channels = y_c
        .getattr("shape")
        .and_then(|s| s.get_item(0))
        .and_then(|c| c.extract::<usize>())
        .map_err(|_| Error::value("y_c", "expected a 2-D array (channels x samples)"))?;
    AnyBatch::new(&gains.set, float, sin_cos, channels)?.run(py, y_c, y_s)
}
