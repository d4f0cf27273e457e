//! `Observer` and `track`: the core's observer on 1-D numpy arrays.
//!
//! The per-sample work is the core's `Gains::update`; this module only moves samples in and
//! estimates out, with the GIL released, straight into preallocated arrays that numpy owns.

use angletrack::BatchColumns;
use angletrack_core::{Faults, Observer as CoreObserver, ObserverState, Real, SinCos};
use pyo3::prelude::*;

use crate::arrays::{Float, check_equal_lengths, samples};
use crate::diagnostics::PyFaultThresholds;
use crate::dispatch::{Arg, PhaseSinCos, Run, RunSettings, Sample};
use crate::errors::{Error, Result};
use crate::estimates::{Estimate, Estimates, OutputArrays};
use crate::gains::PyGains;

/// What `Observer` does with the core observer of whichever float type, order and sin/cos
/// its settings chose.
pub trait ObserverOps: Run {
    fn estimate(&self) -> Estimate;
    fn reset(&mut self);
    fn initialise(&mut self, y_c: f64, y_s: f64);
    fn set_state(&mut self, angle_rad: f64, speed_rad_s: f64, acceleration_rad_s2: f64);
    fn is_initialised(&self) -> bool;
    fn latched_faults(&self) -> Faults;
    fn clear_faults(&mut self) -> Faults;
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> Run for CoreObserver<T, N, S> {
    fn run(&mut self, py: Python<'_>, y_c: Arg<'_, '_>, y_s: Arg<'_, '_>) -> Result<Estimates> {
        let y_c = samples::<T>(y_c, "y_c")?;
        let y_s = samples::<T>(y_s, "y_s")?;
        let (y_c, y_s) = (y_c.as_slice(), y_s.as_slice());
        check_equal_lengths(("y_c", y_c.len()), ("y_s", y_s.len()))?;
        let out = OutputArrays::<T>::new(py, y_c.len())?;
        out.fill(py, |columns| run_columns(columns, self, y_c, y_s))?;
        out.into_estimates(y_c.len(), None)
    }
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> ObserverOps for CoreObserver<T, N, S> {
    fn estimate(&self) -> Estimate {
        Estimate::from_core(&self.gains.estimate(&self.state))
    }

    fn reset(&mut self) {
        self.state = ObserverState::new();
    }

    fn initialise(&mut self, y_c: f64, y_s: f64) {
        let (y_c, y_s) = (T::from_f64(y_c), T::from_f64(y_s));
        self.gains.initialise(&mut self.state, y_c, y_s);
    }

    fn set_state(&mut self, angle_rad: f64, speed_rad_s: f64, acceleration_rad_s2: f64) {
        self.state = ObserverState::at(
            T::from_f64(angle_rad),
            T::from_f64(speed_rad_s),
            T::from_f64(acceleration_rad_s2),
            self.gains.sample_period(),
        );
    }

    fn is_initialised(&self) -> bool {
        self.state.is_initialised()
    }

    fn latched_faults(&self) -> Faults {
        self.state.latched_faults()
    }

    fn clear_faults(&mut self) -> Faults {
        self.state.clear_faults()
    }
}

/// Runs `observer` over `y_c`, `y_s` into the columns (all of equal length, checked by the
/// caller). Called with the GIL released: no Python object is touched.
fn run_columns<T: Real, const N: usize, S: SinCos<T>>(
    columns: BatchColumns<'_, T>,
    observer: &mut CoreObserver<T, N, S>,
    y_c: &[T],
    y_s: &[T],
) {
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

/// Refuses the first value that is not finite, naming its parameter: a NaN state would be
/// silently replaced by the observer's own start.
fn finite(values: &[(&'static str, f64)]) -> Result<()> {
    match values.iter().find(|(_, v)| !v.is_finite()) {
        Some(&(parameter, v)) => Err(Error::value(parameter, format!("{v} is not finite"))),
        None => Ok(()),
    }
}

/// An angle tracking observer running on numpy arrays: checked gains plus a state that
/// persists between calls, so a capture fed in chunks gives exactly the result of one call.
#[pyclass(name = "Observer", module = "angletrack", extends = RunSettings)]
#[derive(Debug)]
pub struct PyObserver {
    thresholds: PyFaultThresholds,
    inner: Box<dyn ObserverOps>,
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
    ) -> Result<PyClassInitializer<Self>> {
        let thresholds = fault_thresholds.unwrap_or_default();
        RunSettings::from_arguments(gains, dtype, sin_cos)?.subclass(|gains| {
            let inner = gains.observer(&thresholds)?;
            Ok(Self { thresholds, inner })
        })
    }

    /// Runs the observer over the samples `y_c ~ cos(theta)`, `y_s ~ sin(theta)` (1-D,
    /// equal lengths, of the observer's dtype) and returns the estimates of every sample.
    /// The state carries over to the next call.
    #[pyo3(signature = (y_c, y_s))]
    fn update(&mut self, py: Python<'_>, y_c: Arg<'_, '_>, y_s: Arg<'_, '_>) -> Result<Estimates> {
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
    /// Refuses (`ConfigError`) a sample that is not finite.
    #[pyo3(signature = (y_c, y_s))]
    fn initialise(&mut self, y_c: f64, y_s: f64) -> Result<()> {
        finite(&[("y_c", y_c), ("y_s", y_s)])?;
        self.inner.initialise(y_c, y_s);
        Ok(())
    }

    /// Starts from a known angle (rad, any value: wrapped, whole turns counted), speed
    /// (rad/s) and acceleration (rad/s^2, ignored at order 2). Refuses (`ConfigError`) a
    /// value that is not finite.
    #[pyo3(signature = (angle_rad, speed_rad_s = 0.0, acceleration_rad_s2 = 0.0))]
    fn set_state(
        &mut self,
        angle_rad: f64,
        speed_rad_s: f64,
        acceleration_rad_s2: f64,
    ) -> Result<()> {
        finite(&[
            ("angle_rad", angle_rad),
            ("speed_rad_s", speed_rad_s),
            ("acceleration_rad_s2", acceleration_rad_s2),
        ])?;
        self.inner
            .set_state(angle_rad, speed_rad_s, acceleration_rad_s2);
        Ok(())
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

    fn __repr__(slf: PyRef<'_, Self>) -> String {
        let settings = slf.as_super();
        format!(
            "Observer({}, gains={:?}, initialised={})",
            settings.describe(),
            settings.gain_set().gains(),
            slf.inner.is_initialised()
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
    let settings = RunSettings::new(gains, Float::of_samples(y_c, "y_c")?, sin_cos)?;
    let thresholds = fault_thresholds.unwrap_or_default();
    settings
        .typed_gains()?
        .observer(&thresholds)?
        .run(py, y_c, y_s)
}
