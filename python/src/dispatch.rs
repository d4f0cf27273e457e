//! The settings `Observer` and `ObserverBatch` share (their common base class, with its
//! getters): what a Python caller chooses at run time (gains, float type, sin/cos), handed
//! to the crate, which chooses the concrete generic types once (`angletrack::AnyChannel`,
//! `angletrack::AnyBatch`).

use angletrack::export::FloatType;
use angletrack::tracker_file::SinCosKind;
use angletrack::{AnyBatch, AnyChannel, ChannelOptions};
use angletrack_core::{Real, SinCos};
use numpy::Element;
use pyo3::prelude::*;

use crate::arrays::Float;
use crate::errors::{Error, Result};
use crate::gains::{GainSet, PyGains};
use crate::getters::class_methods;

/// A float type the binding runs observers on: one of the core's, that numpy stores.
pub trait Sample: Real + Element {}
impl<T: Real + Element> Sample for T {}

/// A sin/cos of the phase detector, as the observers the binding keeps in Python objects
/// (shared between threads) hold it.
pub trait PhaseSinCos<T: Real>: SinCos<T> + Send + Sync {}
impl<T: Real, S: SinCos<T> + Send + Sync> PhaseSinCos<T> for S {}

/// A Python argument as the binding receives it, converted where it is used.
pub type Arg<'a, 'py> = &'a Bound<'py, PyAny>;

/// What an `Observer` or an `ObserverBatch` runs with: the gains (float64, checked), the
/// float type and the phase detector's sin/cos. Shared getters of both classes.
#[pyclass(name = "_RunSettings", module = "angletrack", subclass)]
#[derive(Debug, Clone)]
pub struct RunSettings {
    gains: PyGains,
    float: Float,
    sin_cos: SinCosKind,
}

impl RunSettings {
    /// The settings of a constructor's arguments: `dtype` a numpy dtype (or `None`, float64),
    /// `sin_cos` a name (or `None`, the default of the float type).
    pub fn from_arguments(
        gains: PyGains,
        dtype: Option<&Bound<'_, PyAny>>,
        sin_cos: Option<&str>,
    ) -> Result<Self> {
        Self::new(gains, Float::from_dtype_like(dtype, "dtype")?, sin_cos)
    }

    /// The settings for `gains` in the float type `float` with the sin/cos named `sin_cos`
    /// (`'fast'` or `'exact'`; `None`: the float type's default).
    pub fn new(gains: PyGains, float: Float, sin_cos: Option<&str>) -> Result<Self> {
        let sin_cos = SinCosKind::from_name(sin_cos).ok_or_else(|| {
            let other = sin_cos.unwrap_or_default();
            Error::value(
                "sin_cos",
                format!("expected 'fast' or 'exact', got {other:?}"),
            )
        })?;
        Ok(Self {
            gains,
            float,
            sin_cos,
        })
    }

    /// The gains' float64 set.
    pub fn gain_set(&self) -> &GainSet {
        &self.gains.set
    }

    fn float_type(&self) -> FloatType {
        match self.float {
            Float::F32 => FloatType::F32,
            Float::F64 => FloatType::F64,
        }
    }

    /// The crate's chain of one observer with these settings and `options`.
    pub fn channel(&self, options: &ChannelOptions) -> Result<AnyChannel> {
        Ok(AnyChannel::new(
            &self.gains.set,
            self.float_type(),
            self.sin_cos,
            options,
        )??)
    }

    /// The crate's batch of `channels` observers with these settings.
    pub fn batch(&self, channels: usize) -> Result<AnyBatch> {
        Ok(AnyBatch::new(
            &self.gains.set,
            self.float_type(),
            self.sin_cos,
            channels,
        )?)
    }

    /// The sin/cos's name in the Python API: `'fast'` or `'exact'`.
    fn sin_cos_name(&self) -> &'static str {
        ["fast", "exact"][usize::from(self.sin_cos.is_exact(self.float == Float::F64))]
    }

    /// The initialiser of a subclass whose value is `value`.
    pub fn subclass<C: pyo3::PyClass<BaseType = Self>>(self, value: C) -> PyClassInitializer<C> {
        PyClassInitializer::from(self).add_subclass(value)
    }

    /// `order=..., dtype=..., sin_cos=..., sample_period_s=...` for the subclasses' `repr`.
    pub fn describe(&self) -> String {
        format!(
            "order={}, dtype={}, sin_cos={}, sample_period_s={:e}",
            self.gains.set.order(),
            self.float.name(),
            self.sin_cos_name(),
            self.gains.set.sample_period()
        )
    }
}

class_methods! {
    RunSettings {
        /// The gains it runs with.
        gains: PyGains = |this, py| this.gains.clone();
        /// The float type it runs on: 'float32' or 'float64'.
        dtype: &'static str = |this, py| this.float.name();
        /// The phase detector's sin/cos: 'fast' (polynomial) or 'exact' (libm).
        sin_cos: &'static str = |this, py| this.sin_cos_name();
        /// The observer order (2 or 3).
        order: usize = |this, py| this.gains.set.order();
        /// The sample period (s).
        sample_period_s: f64 = |this, py| this.gains.set.sample_period();
    }
    methods {}
}
