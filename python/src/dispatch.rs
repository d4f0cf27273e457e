//! The one dispatch from what a Python caller chooses at run time (float type, order,
//! sin/cos) to the concrete generic types of the Rust crates, and the settings `Observer` and
//! `ObserverBatch` share (their common base class, with its getters).

use core::fmt::Debug;

use angletrack::{ChannelBatch, ChannelOptions, TrackerChannel, convert_gains};
use angletrack_core::{Exact, Fast, Gains as CoreGains, Real, SinCos};
use numpy::Element;
use pyo3::prelude::*;

use crate::arrays::Float;
use crate::batch::RunBatch;
use crate::errors::{Error, Result};
use crate::gains::{GainSet, PyGains};
use crate::getters::class_methods;
use crate::observer::ObserverOps;
use crate::observer_channel::Channel;

/// Which sin/cos the phase detector uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SinCosKind {
    /// The core's branch-free polynomial (`Fast`).
    Fast,
    /// `libm` (`Exact`).
    Exact,
}

impl SinCosKind {
    /// The sin/cos named `name`; `None` gives the core's default for the float type (the
    /// fast one in float32, whose error of 2 ulp of 1 is float32's own scale; the exact one
    /// in float64).
    pub fn parse(name: Option<&str>, float: Float) -> Result<Self> {
        match name {
            None => Ok(match float {
                Float::F32 => SinCosKind::Fast,
                Float::F64 => SinCosKind::Exact,
            }),
            Some("fast") => Ok(SinCosKind::Fast),
            Some("exact") => Ok(SinCosKind::Exact),
            Some(other) => Err(Error::value(
                "sin_cos",
                format!("expected 'fast' or 'exact', got {other:?}"),
            )),
        }
    }

    /// Its name in the Python API.
    pub fn name(self) -> &'static str {
        match self {
            SinCosKind::Fast => "fast",
            SinCosKind::Exact => "exact",
        }
    }
}

/// A float type the binding runs observers on: one of the core's, that numpy stores.
pub trait Sample: Real + Element {}
impl<T: Real + Element> Sample for T {}

/// A sin/cos of the phase detector, as the observers the binding keeps in Python objects
/// (shared between threads) hold it.
pub trait PhaseSinCos<T: Real>: SinCos<T> + Debug + Send + Sync {}
impl<T: Real, S: SinCos<T> + Debug + Send + Sync> PhaseSinCos<T> for S {}

/// Gains of the float type, order and sin/cos a caller chose, behind one object: what an
/// `Observer` or an `ObserverBatch` is built from.
pub trait TypedGains {
    /// A core observer with `options` (diagnostics, ADC counts, calibration); `stated`: the
    /// first ADC argument the caller gave (refused with float samples).
    fn observer(
        &self,
        options: &ChannelOptions,
        stated: Option<&'static str>,
    ) -> Result<Box<dyn ObserverOps>>;
    /// A batch of `channels` observers (the input check only, no diagnostics).
    fn batch(&self, channels: usize) -> Result<Box<dyn RunBatch>>;
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> TypedGains for CoreGains<T, N, S> {
    fn observer(
        &self,
        options: &ChannelOptions,
        stated: Option<&'static str>,
    ) -> Result<Box<dyn ObserverOps>> {
        Ok(Box::new(Channel {
            inner: TrackerChannel::new(*self, options)?,
            stated,
        }))
    }

    fn batch(&self, channels: usize) -> Result<Box<dyn RunBatch>> {
        Ok(Box::new(ChannelBatch::new(*self, channels)?))
    }
}

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

    /// The settings for `gains` in the float type `float` with the sin/cos named `sin_cos`.
    pub fn new(gains: PyGains, float: Float, sin_cos: Option<&str>) -> Result<Self> {
        let sin_cos = SinCosKind::parse(sin_cos, float)?;
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

    /// The gains in the chosen float type (checked again there: rounding to float32 can
    /// leave the stability region at its edge) with the chosen sin/cos.
    pub fn typed_gains(&self) -> Result<Box<dyn TypedGains>> {
        match self.float {
            Float::F32 => self.with_float::<f32>(),
            Float::F64 => self.with_float::<f64>(),
        }
    }

    fn with_float<T: Sample>(&self) -> Result<Box<dyn TypedGains>> {
        match self.sin_cos {
            SinCosKind::Fast => self.with_types::<T, Fast>(),
            SinCosKind::Exact => self.with_types::<T, Exact>(),
        }
    }

    fn with_types<T: Sample, S: PhaseSinCos<T>>(&self) -> Result<Box<dyn TypedGains>> {
        Ok(match &self.gains.set {
            GainSet::Second(g) => Box::new(convert_gains::<T, 2>(g)?.with_sin_cos::<S>()),
            GainSet::Third(g) => Box::new(convert_gains::<T, 3>(g)?.with_sin_cos::<S>()),
        })
    }

    /// The initialiser of a subclass whose value `class` makes from the typed gains.
    pub fn subclass<C: pyo3::PyClass<BaseType = Self>>(
        self,
        class: impl FnOnce(&dyn TypedGains) -> Result<C>,
    ) -> Result<PyClassInitializer<C>> {
        let value = class(self.typed_gains()?.as_ref())?;
        Ok(PyClassInitializer::from(self).add_subclass(value))
    }

    /// `order=..., dtype=..., sin_cos=..., sample_period_s=...` for the subclasses' `repr`.
    pub fn describe(&self) -> String {
        format!(
            "order={}, dtype={}, sin_cos={}, sample_period_s={:e}",
            self.gains.set.order(),
            self.float.name(),
            self.sin_cos.name(),
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
        sin_cos: &'static str = |this, py| this.sin_cos.name();
        /// The observer order (2 or 3).
        order: usize = |this, py| this.gains.set.order();
        /// The sample period (s).
        sample_period_s: f64 = |this, py| this.gains.set.sample_period();
    }
    methods {

    }
}
