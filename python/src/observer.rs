//! `Gains`, `Observer`, `Estimate`, `Estimates` and `track`: the core's observers on numpy
//! arrays.
//!
//! The per-sample work is the core's `Gains::update`; this module only moves samples in and
//! estimates out, with the GIL released, straight into preallocated vectors that numpy then
//! owns without a copy.

use angletrack_core::{
    Estimate as CoreEstimate, Exact, Fast, FaultThresholds as CoreThresholds, Faults,
    Gains as CoreGains, Observer as CoreObserver, ObserverState, Order, Real, SinCos,
    SupportedOrder,
};
use numpy::{Element, PyArray1};
use pyo3::prelude::*;

use angletrack::BatchColumns;

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

    pub(crate) fn sample_period(&self) -> f64 {
        match self {
            GainSet::Second(g) => g.sample_period(),
            GainSet::Third(g) => g.sample_period(),
        }
    }

    /// The observer order (2 or 3).
    pub fn order(&self) -> usize {
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
    #[pyo3(signature = (gains, sample_period_s))]
    fn py_new(gains: Vec<f64>, sample_period_s: f64) -> Result<Self> {
        Ok(Self {
            set: GainSet::new(&gains, sample_period_s)?,
        })
    }

    /// Gains from the closed-loop characteristic polynomial written in `s = z - 1`
    /// (coefficients lowest first, monic, leading 1 omitted), as the core's pole-matching
    /// entry point.
    #[staticmethod]
    #[pyo3(signature = (coefficients, sample_period_s))]
    fn from_loop_polynomial(coefficients: Vec<f64>, sample_period_s: f64) -> Result<Self> {
        Ok(Self {
            set: GainSet::from_loop_polynomial(&coefficients, sample_period_s)?,
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
    fn sample_period_s(&self) -> f64 {
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

    /// Pickling: rebuilt (and checked again) from the gains and the sample period.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> (Bound<'py, pyo3::types::PyType>, (Vec<f64>, f64)) {
        let set = &slf.get().set;
        (slf.get_type(), (set.gains(), set.sample_period()))
    }

    fn __repr__(&self) -> String {
        let l: Vec<String> = self
            .set
            .gains()
            .iter()
            .map(|x| format!("{x:.9e}"))
            .collect();
        format!(
            "Gains(gains=[{}], sample_period_s={:e})  # order {}, {:.6} Hz",
            l.join(", "),
            self.set.sample_period(),
            self.set.order(),
            1.0 / self.set.sample_period()
        )
    }
}

/// Thresholds of the observer's diagnostics (like an RDC chip's fault register) and of its
/// input check, in the units of `y_c`, `y_s` unless stated. Keyword arguments override the
/// defaults for `nominal_amplitude` (the core's `FaultThresholds::for_amplitude`): input
/// bound 4 A, loss of signal 0.25 A, degradation below 0.5 A or above 1.5 A, loss of
/// tracking at a filtered |phase error| of 0.1 A, maximum speed pi / (2 Ts) rad/s, filter
/// factor 1/16, false lock at a filtered in-phase component below 0, monitoring and
/// re-acquisition on. Checked when an observer is built (`ValueError` naming the field).
#[pyclass(
    name = "FaultThresholds",
    module = "angletrack",
    frozen,
    from_py_object
)]
#[derive(Debug, Clone, Copy)]
pub struct PyFaultThresholds {
    inner: CoreThresholds<f64>,
}

impl PyFaultThresholds {
    /// The thresholds in float type `T`.
    fn typed<T: Real>(&self) -> CoreThresholds<T> {
        let t = &self.inner;
        CoreThresholds {
            nominal_amplitude: T::from_f64(t.nominal_amplitude),
            max_input_amplitude: T::from_f64(t.max_input_amplitude),
            loss_of_signal: T::from_f64(t.loss_of_signal),
            degradation_low: T::from_f64(t.degradation_low),
            degradation_high: T::from_f64(t.degradation_high),
            loss_of_tracking: T::from_f64(t.loss_of_tracking),
            max_speed: t.max_speed.map(T::from_f64),
            filter_factor: T::from_f64(t.filter_factor),
            false_lock: T::from_f64(t.false_lock),
            monitor: t.monitor,
            re_acquire: t.re_acquire,
        }
    }
}

#[pymethods]
impl PyFaultThresholds {
    #[new]
    #[pyo3(signature = (*, nominal_amplitude = 1.0, max_input_amplitude = None,
        loss_of_signal = None, degradation_low = None, degradation_high = None,
        loss_of_tracking = None, max_speed_rad_s = None, filter_factor = None,
        false_lock = None, monitor = true, re_acquire = true))]
    #[allow(clippy::too_many_arguments)]
    fn py_new(
        nominal_amplitude: f64,
        max_input_amplitude: Option<f64>,
        loss_of_signal: Option<f64>,
        degradation_low: Option<f64>,
        degradation_high: Option<f64>,
        loss_of_tracking: Option<f64>,
        max_speed_rad_s: Option<f64>,
        filter_factor: Option<f64>,
        false_lock: Option<f64>,
        monitor: bool,
        re_acquire: bool,
    ) -> Self {
        let d = CoreThresholds::for_amplitude(nominal_amplitude);
        Self {
            inner: CoreThresholds {
                nominal_amplitude,
                max_input_amplitude: max_input_amplitude.unwrap_or(d.max_input_amplitude),
                loss_of_signal: loss_of_signal.unwrap_or(d.loss_of_signal),
                degradation_low: degradation_low.unwrap_or(d.degradation_low),
                degradation_high: degradation_high.unwrap_or(d.degradation_high),
                loss_of_tracking: loss_of_tracking.unwrap_or(d.loss_of_tracking),
                max_speed: max_speed_rad_s.or(d.max_speed),
                filter_factor: filter_factor.unwrap_or(d.filter_factor),
                false_lock: false_lock.unwrap_or(d.false_lock),
                monitor,
                re_acquire,
            },
        }
    }

    /// No diagnostics and no re-acquisition, only the input check: the bare loop of the
    /// paper (to study the loop's own large-signal behaviour).
    #[staticmethod]
    fn disabled() -> Self {
        Self {
            inner: CoreThresholds::disabled(),
        }
    }

    /// The amplitude of a healthy signal.
    #[getter]
    fn nominal_amplitude(&self) -> f64 {
        self.inner.nominal_amplitude
    }
    /// Samples with an amplitude above this (or non-finite) are rejected.
    #[getter]
    fn max_input_amplitude(&self) -> f64 {
        self.inner.max_input_amplitude
    }
    /// Filtered amplitude below this: loss of signal.
    #[getter]
    fn loss_of_signal(&self) -> f64 {
        self.inner.loss_of_signal
    }
    /// Filtered amplitude below this: degradation of signal.
    #[getter]
    fn degradation_low(&self) -> f64 {
        self.inner.degradation_low
    }
    /// Filtered amplitude above this: degradation of signal.
    #[getter]
    fn degradation_high(&self) -> f64 {
        self.inner.degradation_high
    }
    /// Filtered |phase error| above this: loss of tracking.
    #[getter]
    fn loss_of_tracking(&self) -> f64 {
        self.inner.loss_of_tracking
    }
    /// Estimated |speed| (rad/s) above this: loss of tracking; `None`: pi / (2 Ts).
    #[getter]
    fn max_speed_rad_s(&self) -> Option<f64> {
        self.inner.max_speed
    }
    /// Smoothing factor of the first-order filters, in (0, 1].
    #[getter]
    fn filter_factor(&self) -> f64 {
        self.inner.filter_factor
    }
    /// Filtered in-phase component below this: false lock.
    #[getter]
    fn false_lock(&self) -> f64 {
        self.inner.false_lock
    }
    /// Whether the fault flags are computed.
    #[getter]
    fn monitor(&self) -> bool {
        self.inner.monitor
    }
    /// Whether a false lock re-acquires the angle from atan2.
    #[getter]
    fn re_acquire(&self) -> bool {
        self.inner.re_acquire
    }

    fn __repr__(&self) -> String {
        let t = &self.inner;
        format!(
            "FaultThresholds(nominal_amplitude={}, max_input_amplitude={}, loss_of_signal={}, \
             degradation_low={}, degradation_high={}, loss_of_tracking={}, max_speed_rad_s={}, \
             filter_factor={}, false_lock={}, monitor={}, re_acquire={})",
            t.nominal_amplitude,
            t.max_input_amplitude,
            t.loss_of_signal,
            t.degradation_low,
            t.degradation_high,
            t.loss_of_tracking,
            t.max_speed.map_or("None".to_string(), |v| v.to_string()),
            t.filter_factor,
            t.false_lock,
            if t.monitor { "True" } else { "False" },
            if t.re_acquire { "True" } else { "False" },
        )
    }
}

/// Which sin/cos the phase detector uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SinCosKind {
    /// The core's branch-free polynomial (`Fast`).
    Fast,
    /// `libm` (`Exact`).
    Exact,
}

impl SinCosKind {
    pub(crate) fn parse(name: Option<&str>, float: Float) -> Result<Self> {
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

    pub(crate) fn name(self) -> &'static str {
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
    thresholds: &PyFaultThresholds,
) -> Result<CoreObserver<T, N, S>>
where
    Order<N>: SupportedOrder,
{
    let gains = CoreGains::new(g.gains().map(T::from_f64), T::from_f64(g.sample_period()))?
        .with_fault_thresholds(thresholds.typed())?;
    Ok(CoreObserver::new(gains))
}

impl AnyObserver {
    fn new(
        set: &GainSet,
        float: Float,
        sin_cos: SinCosKind,
        t: &PyFaultThresholds,
    ) -> Result<Self> {
        use {Float::*, SinCosKind::*};
        Ok(match (set, float, sin_cos) {
            (GainSet::Second(g), F32, Fast) => AnyObserver::F32x2Fast(typed(g, t)?),
            (GainSet::Second(g), F32, Exact) => AnyObserver::F32x2Exact(typed(g, t)?),
            (GainSet::Third(g), F32, Fast) => AnyObserver::F32x3Fast(typed(g, t)?),
            (GainSet::Third(g), F32, Exact) => AnyObserver::F32x3Exact(typed(g, t)?),
            (GainSet::Second(g), F64, Fast) => AnyObserver::F64x2Fast(typed(g, t)?),
            (GainSet::Second(g), F64, Exact) => AnyObserver::F64x2Exact(typed(g, t)?),
            (GainSet::Third(g), F64, Fast) => AnyObserver::F64x3Fast(typed(g, t)?),
            (GainSet::Third(g), F64, Exact) => AnyObserver::F64x3Exact(typed(g, t)?),
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

    fn latched_faults(&self) -> Faults {
        dispatch!(self, o => o.state.latched_faults())
    }

    fn clear_faults(&mut self) -> Faults {
        dispatch!(self, o => o.state.clear_faults())
    }
}

/// Runs `observer` over `y_c`, `y_s` into the columns (all of equal length, checked by the
/// caller). Called with the GIL released: no Python object is touched.
fn run_columns<T: Real, const N: usize, S: SinCos<T>>(
    columns: BatchColumns<'_, T>,
    observer: &mut CoreObserver<T, N, S>,
    y_c: &[T],
    y_s: &[T],
) where
    Order<N>: SupportedOrder,
{
    let n = y_c.len().min(y_s.len()).min(columns.angle.len());
    // Slices of one length: the bounds checks of the loop below are removed.
    let (y_c, y_s) = (&y_c[..n], &y_s[..n]);
    let (angle, position) = (&mut columns.angle[..n], &mut columns.position[..n]);
    let (speed, acceleration) = (&mut columns.speed[..n], &mut columns.acceleration[..n]);
    let (phase_error, faults) = (&mut columns.phase_error[..n], &mut columns.faults[..n]);
    let (gains, state) = (&observer.gains, &mut observer.state);
    for k in 0..n {
        let e = gains.update(state, y_c[k], y_s[k]);
        angle[k] = e.angle;
        position[k] = e.position();
        speed[k] = e.speed;
        acceleration[k] = e.acceleration;
        phase_error[k] = e.phase_error;
        faults[k] = e.faults.bits();
    }
}

/// The output arrays of a run, allocated by numpy (which asks for huge pages on large
/// arrays) and written in place.
pub(crate) struct OutputArrays<'py, T: Element> {
    angle: Bound<'py, PyArray1<T>>,
    position: Bound<'py, PyArray1<f64>>,
    speed: Bound<'py, PyArray1<T>>,
    acceleration: Bound<'py, PyArray1<T>>,
    phase_error: Bound<'py, PyArray1<T>>,
    faults: Bound<'py, PyArray1<u8>>,
}

impl<'py, T: Real + Element> OutputArrays<'py, T> {
    /// `n` elements per quantity.
    pub(crate) fn new(py: Python<'py>, n: usize) -> Self {
        Self {
            angle: PyArray1::zeros(py, n, false),
            position: PyArray1::zeros(py, n, false),
            speed: PyArray1::zeros(py, n, false),
            acceleration: PyArray1::zeros(py, n, false),
            phase_error: PyArray1::zeros(py, n, false),
            faults: PyArray1::zeros(py, n, false),
        }
    }

    /// Calls `fill` with the arrays' slices, the GIL released.
    pub(crate) fn fill<R: Send>(
        &self,
        py: Python<'_>,
        fill: impl FnOnce(BatchColumns<'_, T>) -> R + Send,
    ) -> Result<R> {
        let mut w = (
            writable(&self.angle)?,
            writable(&self.position)?,
            writable(&self.speed)?,
            writable(&self.acceleration)?,
            writable(&self.phase_error)?,
            writable(&self.faults)?,
        );
        let columns = BatchColumns {
            angle: as_slice_mut(&mut w.0)?,
            position: as_slice_mut(&mut w.1)?,
            speed: as_slice_mut(&mut w.2)?,
            acceleration: as_slice_mut(&mut w.3)?,
            phase_error: as_slice_mut(&mut w.4)?,
            faults: as_slice_mut(&mut w.5)?,
        };
        Ok(py.detach(|| fill(columns)))
    }

    /// The `Estimates` of `len` samples, each array reshaped to `shape` if given.
    pub(crate) fn into_estimates(
        self,
        len: usize,
        shape: Option<(usize, usize)>,
    ) -> Result<Estimates> {
        let py = self.angle.py();
        let shaped = |a: Bound<'py, PyAny>| -> Result<Py<PyAny>> {
            Ok(match shape {
                Some(shape) => a.call_method1("reshape", shape)?.unbind(),
                None => a.unbind(),
            })
        };
        Ok(Estimates {
            len,
            dtype: numpy::dtype::<T>(py).to_string(),
            angle: shaped(self.angle.into_any())?,
            position: shaped(self.position.into_any())?,
            speed: shaped(self.speed.into_any())?,
            acceleration: shaped(self.acceleration.into_any())?,
            phase_error: shaped(self.phase_error.into_any())?,
            faults: shaped(self.faults.into_any())?,
        })
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
    let out = OutputArrays::<T>::new(py, y_c.len());
    out.fill(py, |columns| run_columns(columns, observer, y_c, y_s))?;
    out.into_estimates(y_c.len(), None)
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
    /// Fault flags of the last sample (bits, see `angletrack.Faults`).
    faults: u8,
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
            faults: e.faults.bits(),
        }
    }
}

#[pymethods]
impl Estimate {
    fn __repr__(&self) -> String {
        format!(
            "Estimate(angle={:.6} rad, turns={}, position={:.6} rad, speed={:.6} rad/s, \
             acceleration={:.6} rad/s^2, phase_error={:.3e}, faults={})",
            self.angle,
            self.turns,
            self.position,
            self.speed,
            self.acceleration,
            self.phase_error,
            Faults::from_bits_truncate(self.faults)
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
    pub(crate) angle: Py<PyAny>,
    /// Multi-turn position `turns * 2 pi + angle` (rad), float64.
    pub(crate) position: Py<PyAny>,
    /// Estimated speed (rad/s).
    pub(crate) speed: Py<PyAny>,
    /// Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
    pub(crate) acceleration: Py<PyAny>,
    /// Phase-detector output `y_s cos(angle_p) - y_c sin(angle_p)` per sample.
    pub(crate) phase_error: Py<PyAny>,
    /// Fault flags of each sample (uint8 bits, see `angletrack.Faults`).
    pub(crate) faults: Py<PyAny>,
    /// The dtype of the angle, speed, acceleration and phase-error arrays.
    pub(crate) dtype: String,
    /// The number of samples.
    pub(crate) len: usize,
}

#[pymethods]
impl Estimates {
    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        format!(
            "Estimates({} samples, dtype={}: angle, position (float64), speed, acceleration, \
             phase_error, faults (uint8))",
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
    thresholds: PyFaultThresholds,
    float: Float,
    sin_cos: SinCosKind,
    inner: AnyObserver,
}

#[pymethods]
impl PyObserver {
    #[new]
    #[pyo3(signature = (gains, *, dtype = None, sin_cos = None, fault_thresholds = None))]
    fn py_new(
        gains: PyGains,
        dtype: Option<&Bound<'_, PyAny>>,
        sin_cos: Option<&str>,
        fault_thresholds: Option<PyFaultThresholds>,
    ) -> Result<Self> {
        let float = Float::from_dtype_like(dtype, "dtype")?;
        let sin_cos = SinCosKind::parse(sin_cos, float)?;
        let thresholds = fault_thresholds.unwrap_or_else(default_thresholds);
        let inner = AnyObserver::new(&gains.set, float, sin_cos, &thresholds)?;
        Ok(Self {
            gains,
            thresholds,
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
    #[pyo3(signature = (angle_rad, speed_rad_s = 0.0, acceleration_rad_s2 = 0.0))]
    fn set_state(&mut self, angle_rad: f64, speed_rad_s: f64, acceleration_rad_s2: f64) {
        self.inner
            .set_state(angle_rad, speed_rad_s, acceleration_rad_s2);
    }

    /// The faults latched since they were last cleared (bits, see `angletrack.Faults`), like
    /// reading an RDC chip's fault register.
    #[getter]
    fn latched_faults(&self) -> u8 {
        self.inner.latched_faults().bits()
    }

    /// Returns the latched faults (bits) and clears them.
    fn clear_faults(&mut self) -> u8 {
        self.inner.clear_faults().bits()
    }

    /// The diagnostics thresholds the observer runs with.
    #[getter]
    fn fault_thresholds(&self) -> PyFaultThresholds {
        self.thresholds
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
    fn sample_period_s(&self) -> f64 {
        self.gains.set.sample_period()
    }

    fn __repr__(&self) -> String {
        format!(
            "Observer(order={}, dtype={}, sin_cos={}, sample_period_s={:e}, gains={:?}, \
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
#[pyo3(signature = (gains, y_c, y_s, *, sin_cos = None, fault_thresholds = None))]
pub fn track(
    py: Python<'_>,
    gains: PyGains,
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
    sin_cos: Option<&str>,
    fault_thresholds: Option<PyFaultThresholds>,
) -> Result<Estimates> {
    let float = Float::of_samples(y_c, "y_c")?;
    let sin_cos = SinCosKind::parse(sin_cos, float)?;
    let thresholds = fault_thresholds.unwrap_or_else(default_thresholds);
    AnyObserver::new(&gains.set, float, sin_cos, &thresholds)?.run(py, y_c, y_s)
}

fn default_thresholds() -> PyFaultThresholds {
    PyFaultThresholds {
        inner: CoreThresholds::default(),
    }
}

/// The fault flag bits of `Estimates.faults`, `Estimate.faults` and
/// `Observer.latched_faults`, by name (the core's `Faults` constants).
pub fn fault_bits() -> [(&'static str, u8); 5] {
    [
        ("LOSS_OF_SIGNAL", Faults::LOSS_OF_SIGNAL.bits()),
        (
            "DEGRADATION_OF_SIGNAL",
            Faults::DEGRADATION_OF_SIGNAL.bits(),
        ),
        ("LOSS_OF_TRACKING", Faults::LOSS_OF_TRACKING.bits()),
        ("BAD_SAMPLE", Faults::BAD_SAMPLE.bits()),
        ("FALSE_LOCK", Faults::FALSE_LOCK.bits()),
    ]
}
