//! `Gains`, `Observer`, `Estimate`, `Estimates` and `track`: the core's observers on numpy
//! arrays.
//!
//! The per-sample work is the core's `Gains::update`; this module only moves samples in and
//! estimates out, with the GIL released, straight into preallocated vectors that numpy then
//! owns without a copy.

use angletrack_core::{
    Estimate as CoreEstimate, Exact, Fast, Gains as CoreGains, Observer as CoreObserver,
    ObserverState, Order, Real, SinCos, SupportedOrder,
};
use numpy::{Element, PyArray1};
use pyo3::prelude::*;

use crate::arrays::{Float, as_slice_mut, check_equal_lengths, samples, writable};
use crate::errors::{Error, Result};

/// Checked discrete gains of order 2 or 3, in `f64` (the Python-side configuration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GainSet {
    /// Order 2: `(l1, l2)`.
    Second(CoreGains<f64, 2>),
    /// Order 3: `(l1, l2, l3)`.
    Third(CoreGains<f64, 3>),
}

impl GainSet {
    /// Checks gains `l` (length 2 or 3) and the sample period (s) with the core.
    pub fn new(l: &[f64], sample_period: f64) -> Result<Self> {
        match *l {
            [l1, l2] => Ok(GainSet::Second(CoreGains::new([l1, l2], sample_period)?)),
            [l1, l2, l3] => Ok(GainSet::Third(CoreGains::new([l1, l2, l3], sample_period)?)),
            _ => Err(order_error("gains", l.len())),
        }
    }

    /// Gains from the closed-loop characteristic polynomial in `s = z - 1` (coefficients,
    /// lowest first, leading 1 omitted).
    pub fn from_loop_polynomial(c: &[f64], sample_period: f64) -> Result<Self> {
        match *c {
            [c0, c1] => Ok(GainSet::Second(CoreGains::from_loop_polynomial(
                [c0, c1],
                sample_period,
            )?)),
            [c0, c1, c2] => Ok(GainSet::Third(CoreGains::from_loop_polynomial(
                [c0, c1, c2],
                sample_period,
            )?)),
            _ => Err(order_error("coefficients", c.len())),
        }
    }

    fn gains(&self) -> Vec<f64> {
        match self {
            GainSet::Second(g) => g.gains().to_vec(),
            GainSet::Third(g) => g.gains().to_vec(),
        }
    }

    fn loop_polynomial(&self) -> Vec<f64> {
        match self {
            GainSet::Second(g) => g.loop_polynomial().to_vec(),
            GainSet::Third(g) => g.loop_polynomial().to_vec(),
        }
    }

    fn sample_period(&self) -> f64 {
        match self {
            GainSet::Second(g) => g.sample_period(),
            GainSet::Third(g) => g.sample_period(),
        }
    }

    fn order(&self) -> usize {
        match self {
            GainSet::Second(_) => 2,
            GainSet::Third(_) => 3,
        }
    }
}

fn order_error(parameter: &'static str, len: usize) -> Error {
    Error::value(
        parameter,
        format!("expected 2 values (2nd-order observer) or 3 (3rd-order), got {len}"),
    )
}

/// Discrete gains of an angle tracking observer, checked against the stability region of the
/// discrete loop.
///
/// `gains` are `(l1, l2)` (2nd order) or `(l1, l2, l3)` (3rd order), dimensionless, for the
/// scaled state `(theta, Ts*Omega, Ts^2*alpha)`; `sample_period` is `Ts` in seconds.
/// Raises `ValueError` naming the gain whose stability condition fails.
#[pyclass(name = "Gains", module = "angletrack", frozen, eq, from_py_object)]
#[derive(Debug, Clone, PartialEq)]
pub struct PyGains {
    /// The checked gains.
    pub set: GainSet,
}

#[pymethods]
impl PyGains {
    #[new]
    #[pyo3(signature = (gains, sample_period))]
    fn py_new(gains: Vec<f64>, sample_period: f64) -> Result<Self> {
        Ok(Self {
            set: GainSet::new(&gains, sample_period)?,
        })
    }

    /// Gains from the closed-loop characteristic polynomial written in `s = z - 1`
    /// (coefficients lowest first, monic, leading 1 omitted), as the core's pole-matching
    /// entry point.
    #[staticmethod]
    #[pyo3(signature = (coefficients, sample_period))]
    fn from_loop_polynomial(coefficients: Vec<f64>, sample_period: f64) -> Result<Self> {
        Ok(Self {
            set: GainSet::from_loop_polynomial(&coefficients, sample_period)?,
        })
    }

    /// The discrete gains `(l1, l2[, l3])` (dimensionless).
    #[getter]
    fn gains(&self) -> Vec<f64> {
        self.set.gains()
    }

    /// Coefficients (lowest first, leading 1 omitted) of the closed-loop characteristic
    /// polynomial in `s = z - 1`.
    #[getter]
    fn loop_polynomial(&self) -> Vec<f64> {
        self.set.loop_polynomial()
    }

    /// The sample period `Ts` (s).
    #[getter]
    fn sample_period(&self) -> f64 {
        self.set.sample_period()
    }

    /// The sample rate `1/Ts` (Hz).
    #[getter]
    fn sample_rate_hz(&self) -> f64 {
        1.0 / self.set.sample_period()
    }

    /// The observer order: 2 (angle, speed) or 3 (angle, speed, acceleration).
    #[getter]
    fn order(&self) -> usize {
        self.set.order()
    }

    fn __repr__(&self) -> String {
        let l: Vec<String> = self
            .set
            .gains()
            .iter()
            .map(|x| format!("{x:.9e}"))
            .collect();
        format!(
            "Gains(gains=[{}], sample_period={:e})  # order {}, {:.6} Hz",
            l.join(", "),
            self.set.sample_period(),
            self.set.order(),
            1.0 / self.set.sample_period()
        )
    }
}

/// Which sin/cos the phase detector uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SinCosKind {
    /// The core's branch-free polynomial (`Fast`).
    Fast,
    /// `libm` (`Exact`).
    Exact,
}

impl SinCosKind {
    fn parse(name: Option<&str>, float: Float) -> Result<Self> {
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

    fn name(self) -> &'static str {
        match self {
            SinCosKind::Fast => "fast",
            SinCosKind::Exact => "exact",
        }
    }
}

/// One observer of any float type, order and sin/cos: the core's generic `Observer`.
#[derive(Debug, Clone)]
enum AnyObserver {
    F32x2Fast(CoreObserver<f32, 2, Fast>),
    F32x2Exact(CoreObserver<f32, 2, Exact>),
    F32x3Fast(CoreObserver<f32, 3, Fast>),
    F32x3Exact(CoreObserver<f32, 3, Exact>),
    F64x2Fast(CoreObserver<f64, 2, Fast>),
    F64x2Exact(CoreObserver<f64, 2, Exact>),
    F64x3Fast(CoreObserver<f64, 3, Fast>),
    F64x3Exact(CoreObserver<f64, 3, Exact>),
}

/// Runs `$body` with `$o` bound to the concrete core observer inside `$any`.
macro_rules! dispatch {
    ($any:expr, $o:ident => $body:expr) => {
        match $any {
            AnyObserver::F32x2Fast($o) => $body,
            AnyObserver::F32x2Exact($o) => $body,
            AnyObserver::F32x3Fast($o) => $body,
            AnyObserver::F32x3Exact($o) => $body,
            AnyObserver::F64x2Fast($o) => $body,
            AnyObserver::F64x2Exact($o) => $body,
            AnyObserver::F64x3Fast($o) => $body,
            AnyObserver::F64x3Exact($o) => $body,
        }
    };
}

/// The `f64` gains converted to float type `T` and checked again there (rounding to `f32`
/// can, at the edge of the stability region, leave it).
fn typed<T: Real, const N: usize, S: SinCos<T>>(
    g: &CoreGains<f64, N>,
) -> Result<CoreObserver<T, N, S>>
where
    Order<N>: SupportedOrder,
{
    let gains = CoreGains::new(g.gains().map(T::from_f64), T::from_f64(g.sample_period()))?;
    Ok(CoreObserver::new(gains))
}

impl AnyObserver {
    fn new(set: &GainSet, float: Float, sin_cos: SinCosKind) -> Result<Self> {
        use {Float::*, SinCosKind::*};
        Ok(match (set, float, sin_cos) {
            (GainSet::Second(g), F32, Fast) => AnyObserver::F32x2Fast(typed(g)?),
            (GainSet::Second(g), F32, Exact) => AnyObserver::F32x2Exact(typed(g)?),
            (GainSet::Third(g), F32, Fast) => AnyObserver::F32x3Fast(typed(g)?),
            (GainSet::Third(g), F32, Exact) => AnyObserver::F32x3Exact(typed(g)?),
            (GainSet::Second(g), F64, Fast) => AnyObserver::F64x2Fast(typed(g)?),
            (GainSet::Second(g), F64, Exact) => AnyObserver::F64x2Exact(typed(g)?),
            (GainSet::Third(g), F64, Fast) => AnyObserver::F64x3Fast(typed(g)?),
            (GainSet::Third(g), F64, Exact) => AnyObserver::F64x3Exact(typed(g)?),
        })
    }

    fn run(
        &mut self,
        py: Python<'_>,
        y_c: &Bound<'_, PyAny>,
        y_s: &Bound<'_, PyAny>,
    ) -> Result<Estimates> {
        dispatch!(self, o => run_arrays(py, o, y_c, y_s))
    }

    fn estimate(&self) -> Estimate {
        dispatch!(self, o => Estimate::from_core(&o.gains.estimate(&o.state)))
    }

    fn reset(&mut self) {
        dispatch!(self, o => o.state = ObserverState::new())
    }

    fn initialise(&mut self, y_c: f64, y_s: f64) {
        dispatch!(self, o => o.gains.initialise(&mut o.state, Real::from_f64(y_c), Real::from_f64(y_s)))
    }

    fn set_state(&mut self, angle: f64, speed: f64, acceleration: f64) {
        dispatch!(self, o => {
            o.state = ObserverState::at(
                Real::from_f64(angle),
                Real::from_f64(speed),
                Real::from_f64(acceleration),
                o.gains.sample_period(),
            )
        })
    }

    fn is_initialised(&self) -> bool {
        dispatch!(self, o => o.state.is_initialised())
    }
}

/// The per-sample outputs of a run: one preallocated slice per quantity, filled in place.
struct Columns<'a, T> {
    angle: &'a mut [T],
    position: &'a mut [f64],
    speed: &'a mut [T],
    acceleration: &'a mut [T],
    phase_error: &'a mut [T],
}

impl<T: Real> Columns<'_, T> {
    /// Runs `observer` over `y_c`, `y_s` into the columns (all of equal length, checked by
    /// the caller). Called with the GIL released: no Python object is touched.
    fn run<const N: usize, S: SinCos<T>>(
        self,
        observer: &mut CoreObserver<T, N, S>,
        y_c: &[T],
        y_s: &[T],
    ) where
        Order<N>: SupportedOrder,
    {
        let n = y_c.len().min(y_s.len()).min(self.angle.len());
        // Slices of one length: the bounds checks of the loop below are removed.
        let (y_c, y_s) = (&y_c[..n], &y_s[..n]);
        let (angle, position) = (&mut self.angle[..n], &mut self.position[..n]);
        let (speed, acceleration) = (&mut self.speed[..n], &mut self.acceleration[..n]);
        let phase_error = &mut self.phase_error[..n];
        let (gains, state) = (&observer.gains, &mut observer.state);
        for k in 0..n {
            let e = gains.update(state, y_c[k], y_s[k]);
            angle[k] = e.angle;
            position[k] = e.position();
            speed[k] = e.speed;
            acceleration[k] = e.acceleration;
            phase_error[k] = e.phase_error;
        }
    }
}

fn run_arrays<T: Real + Element, const N: usize, S: SinCos<T>>(
    py: Python<'_>,
    observer: &mut CoreObserver<T, N, S>,
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
) -> Result<Estimates>
where
    Order<N>: SupportedOrder,
{
    let y_c = samples::<T>(y_c, "y_c")?;
    let y_s = samples::<T>(y_s, "y_s")?;
    let (y_c, y_s) = (y_c.as_slice(), y_s.as_slice());
    check_equal_lengths(("y_c", y_c.len()), ("y_s", y_s.len()))?;
    let n = y_c.len();
    // Allocated by numpy (which asks for huge pages on large arrays), written in place.
    let angle = PyArray1::<T>::zeros(py, n, false);
    let position = PyArray1::<f64>::zeros(py, n, false);
    let speed = PyArray1::<T>::zeros(py, n, false);
    let acceleration = PyArray1::<T>::zeros(py, n, false);
    let phase_error = PyArray1::<T>::zeros(py, n, false);
    {
        let mut w = (
            writable(&angle)?,
            writable(&position)?,
            writable(&speed)?,
            writable(&acceleration)?,
            writable(&phase_error)?,
        );
        let columns = Columns {
            angle: as_slice_mut(&mut w.0)?,
            position: as_slice_mut(&mut w.1)?,
            speed: as_slice_mut(&mut w.2)?,
            acceleration: as_slice_mut(&mut w.3)?,
            phase_error: as_slice_mut(&mut w.4)?,
        };
        py.detach(|| columns.run(observer, y_c, y_s));
    }
    Ok(Estimates {
        len: n,
        dtype: numpy::dtype::<T>(py).to_string(),
        angle: angle.into_any().unbind(),
        position: position.into_any().unbind(),
        speed: speed.into_any().unbind(),
        acceleration: acceleration.into_any().unbind(),
        phase_error: phase_error.into_any().unbind(),
    })
}

/// What an observer knows after its last sample (scalars, in `float`).
#[pyclass(module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct Estimate {
    /// Estimated angle (rad), wrapped to [-pi, pi).
    angle: f64,
    /// Whole turns counted since initialisation.
    turns: i64,
    /// Multi-turn position `turns * 2 pi + angle` (rad).
    position: f64,
    /// Estimated speed (rad/s).
    speed: f64,
    /// Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
    acceleration: f64,
    /// Phase-detector output of the last sample (input units, about `A sin(error)`).
    phase_error: f64,
}

impl Estimate {
    fn from_core<T: Real>(e: &CoreEstimate<T>) -> Self {
        Self {
            angle: e.angle.to_f64(),
            turns: e.turns,
            position: e.position(),
            speed: e.speed.to_f64(),
            acceleration: e.acceleration.to_f64(),
            phase_error: e.phase_error.to_f64(),
        }
    }
}

#[pymethods]
impl Estimate {
    fn __repr__(&self) -> String {
        format!(
            "Estimate(angle={:.6} rad, turns={}, position={:.6} rad, speed={:.6} rad/s, \
             acceleration={:.6} rad/s^2, phase_error={:.3e})",
            self.angle, self.turns, self.position, self.speed, self.acceleration, self.phase_error
        )
    }
}

/// The estimates of a run, one numpy array per quantity, one element per sample.
///
/// `angle`, `speed`, `acceleration` and `phase_error` have the dtype of the input
/// (float32 or float64); `position` is always float64.
#[pyclass(module = "angletrack", frozen, get_all)]
#[derive(Debug)]
pub struct Estimates {
    /// Estimated angle (rad), wrapped to [-pi, pi).
    angle: Py<PyAny>,
    /// Multi-turn position `turns * 2 pi + angle` (rad), float64.
    position: Py<PyAny>,
    /// Estimated speed (rad/s).
    speed: Py<PyAny>,
    /// Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
    acceleration: Py<PyAny>,
    /// Phase-detector output `y_s cos(angle_p) - y_c sin(angle_p)` per sample.
    phase_error: Py<PyAny>,
    /// The dtype of the angle, speed, acceleration and phase-error arrays.
    dtype: String,
    /// The number of samples.
    len: usize,
}

#[pymethods]
impl Estimates {
    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        format!(
            "Estimates({} samples, dtype={}: angle, position (float64), speed, acceleration, \
             phase_error)",
            self.len, self.dtype
        )
    }
}

/// An angle tracking observer running on numpy arrays: checked gains plus a state that
/// persists between calls, so a capture fed in chunks gives exactly the result of one call.
#[pyclass(name = "Observer", module = "angletrack")]
#[derive(Debug)]
pub struct PyObserver {
    gains: PyGains,
    float: Float,
    sin_cos: SinCosKind,
    inner: AnyObserver,
}

#[pymethods]
impl PyObserver {
    #[new]
    #[pyo3(signature = (gains, *, dtype = None, sin_cos = None))]
    fn py_new(
        gains: PyGains,
        dtype: Option<&Bound<'_, PyAny>>,
        sin_cos: Option<&str>,
    ) -> Result<Self> {
        let float = Float::from_dtype_like(dtype, "dtype")?;
        let sin_cos = SinCosKind::parse(sin_cos, float)?;
        let inner = AnyObserver::new(&gains.set, float, sin_cos)?;
        Ok(Self {
            gains,
            float,
            sin_cos,
            inner,
        })
    }

    /// Runs the observer over the samples `y_c ~ cos(theta)`, `y_s ~ sin(theta)` (1-D,
    /// equal lengths, of the observer's dtype) and returns the estimates of every sample.
    /// The state carries over to the next call.
    #[pyo3(signature = (y_c, y_s))]
    fn update(
        &mut self,
        py: Python<'_>,
        y_c: &Bound<'_, PyAny>,
        y_s: &Bound<'_, PyAny>,
    ) -> Result<Estimates> {
        self.inner.run(py, y_c, y_s)
    }

    /// The estimate after the last sample.
    #[getter]
    fn estimate(&self) -> Estimate {
        self.inner.estimate()
    }

    /// Forgets the state: the next sample initialises the observer from its `atan2`.
    fn reset(&mut self) {
        self.inner.reset();
    }

    /// Sets the angle from one sample, `atan2(y_s, y_c)`; speed and acceleration 0.
    #[pyo3(signature = (y_c, y_s))]
    fn initialise(&mut self, y_c: f64, y_s: f64) {
        self.inner.initialise(y_c, y_s);
    }

    /// Starts from a known angle (rad, any value: wrapped, whole turns counted), speed
    /// (rad/s) and acceleration (rad/s^2, ignored at order 2).
    #[pyo3(signature = (angle, speed = 0.0, acceleration = 0.0))]
    fn set_state(&mut self, angle: f64, speed: f64, acceleration: f64) {
        self.inner.set_state(angle, speed, acceleration);
    }

    /// `False` until the first sample (or `set_state`) has set the angle.
    #[getter]
    fn is_initialised(&self) -> bool {
        self.inner.is_initialised()
    }

    /// The gains the observer runs with.
    #[getter]
    fn gains(&self) -> PyGains {
        self.gains.clone()
    }

    /// The float type the observer runs on: 'float32' or 'float64'.
    #[getter]
    fn dtype(&self) -> &'static str {
        self.float.name()
    }

    /// The phase detector's sin/cos: 'fast' (polynomial) or 'exact' (libm).
    #[getter]
    fn sin_cos(&self) -> &'static str {
        self.sin_cos.name()
    }

    /// The observer order (2 or 3).
    #[getter]
    fn order(&self) -> usize {
        self.gains.set.order()
    }

    /// The sample period (s).
    #[getter]
    fn sample_period(&self) -> f64 {
        self.gains.set.sample_period()
    }

    fn __repr__(&self) -> String {
        format!(
            "Observer(order={}, dtype={}, sin_cos={}, sample_period={:e} s, gains={:?}, \
             initialised={})",
            self.gains.set.order(),
            self.float.name(),
            self.sin_cos.name(),
            self.gains.set.sample_period(),
            self.gains.set.gains(),
            self.inner.is_initialised()
        )
    }
}

/// Runs a fresh observer with `gains` over `y_c`, `y_s` in the samples' own dtype (float32
/// or float64) and returns the estimates.
#[pyfunction]
#[pyo3(signature = (gains, y_c, y_s, *, sin_cos = None))]
pub fn track(
    py: Python<'_>,
    gains: PyGains,
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
    sin_cos: Option<&str>,
) -> Result<Estimates> {
    let float = Float::of_samples(y_c, "y_c")?;
    let sin_cos = SinCosKind::parse(sin_cos, float)?;
    AnyObserver::new(&gains.set, float, sin_cos)?.run(py, y_c, y_s)
}
