//! `Observer` and `track`: the core's observer on 1-D numpy arrays.
//!
//! The per-sample work is the core's `Gains::update`; this module only moves samples in and
//! estimates out, with the GIL released, straight into preallocated arrays that numpy owns.

use angletrack::{CountsSettings, EstimateColumns, ThresholdPolicy, online_calibration};
use angletrack_core::{
    CalibrationMode, CalibrationStatus, Calibrator, Chain, ChainState, Faults, FrontEndCheck,
    FrontEndCheckState, FrontEndFaults, Gains as CoreGains, HeldRailCheck, HeldRails,
    Observer as CoreObserver, ObserverState, Real, SinCos, WindingCheck,
};
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;

use crate::arrays::{Float, check_equal_lengths};
use crate::calibration::{CalibrationChoice, PySensorCalibration, mode_name, status_name};
use crate::counts::{AdcInput, adc_settings};
use crate::diagnostics::PyFaultThresholds;
use crate::dispatch::{Arg, PhaseSinCos, Run, RunSettings, Sample};
use crate::errors::{Error, Result};
use crate::estimates::{Estimate, Estimates, OutputArrays};
use crate::gains::PyGains;

/// What `Observer` and `track` are asked for besides the gains, float type and sin/cos.
#[derive(Debug, Clone, Copy, Default)]
pub struct ObserverOptions {
    /// The diagnostics' thresholds; `None`: scaled to the first call's samples.
    pub thresholds: Option<PyFaultThresholds>,
    /// How integer counts are scaled.
    pub adc: CountsSettings,
    /// The online calibration.
    pub calibration: CalibrationChoice,
    /// The ADC's range `(min, max)` in the input's units (counts for integer samples):
    /// a sample at or beyond it is clipped (`crate::front_end`).
    pub adc_range: Option<(f64, f64)>,
    /// Without `adc_range`: clipping flagged against the rails measured as the samples come
    /// (the core's `HeldRailCheck`).
    pub measure_adc_range: bool,
    /// The windings' nominal envelope amplitude for the winding check (`None`: no check).
    pub winding_amplitude: Option<f64>,
}

impl ObserverOptions {
    /// Refuses a stated range with the measured one.
    pub fn checked(self) -> Result<Self> {
        if self.measure_adc_range && self.adc_range.is_some() {
            return Err(Error::value(
                "measure_adc_range",
                "give adc_range or measure_adc_range, not both",
            ));
        }
        Ok(self)
    }
}

/// What `Observer` does with the core observer of whichever float type, order and sin/cos
/// its settings chose.
pub trait ObserverOps: Run {
    /// [`Run::run`] with the front-end faults of each sample (`None`: none given).
    fn run_with_faults(
        &mut self,
        py: Python<'_>,
        y_c: Arg<'_, '_>,
        y_s: Arg<'_, '_>,
        front_end_faults: Option<&[u8]>,
    ) -> Result<Estimates>;
    /// The front-end faults latched (of the check and the winding check).
    fn front_end_faults(&self) -> FrontEndFaults;
    fn estimate(&self) -> Estimate;
    fn reset(&mut self);
    fn initialise(&mut self, y_c: f64, y_s: f64);
    fn set_state(&mut self, angle_rad: f64, speed_rad_s: f64, acceleration_rad_s2: f64);
    fn is_initialised(&self) -> bool;
    fn latched_faults(&self) -> Faults;
    fn clear_faults(&mut self) -> Faults;
    fn fault_thresholds(&self) -> Option<PyFaultThresholds>;
    fn amplitude(&self) -> f64;
    fn calibration(&self) -> PySensorCalibration;
    fn calibration_mode(&self) -> CalibrationMode;
    fn calibration_turns_learned(&self) -> u32;
    fn calibration_status(&self) -> CalibrationStatus;
    fn set_calibration(&mut self, choice: &CalibrationChoice) -> Result<()>;
}

/// The core observer behind the binding's front end: integer counts scaled
/// (`crate::counts`), the online calibration, and the diagnostics' thresholds by the crate's
/// `ThresholdPolicy` (scaled to the first call's samples when the caller gave none).
#[derive(Debug)]
pub struct Channel<T: Real, const N: usize, S> {
    observer: CoreObserver<T, N, S>,
    calibrator: Calibrator<T>,
    adc: AdcInput<T>,
    thresholds: ThresholdPolicy<T>,
    adc_range: Option<(f64, f64)>,
    held_rails: Option<HeldRailCheck>,
    rails: HeldRails<T>,
    winding: Option<WindingCheck<T>>,
    front_end: (FrontEndCheckState, FrontEndCheckState),
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> Channel<T, N, S> {
    /// The observer of `gains` with `options`.
    pub fn new(gains: CoreGains<T, N, S>, options: &ObserverOptions) -> Result<Self> {
        let thresholds = ThresholdPolicy::new(options.thresholds.map(|t| t.typed()));
        let gains = match thresholds.thresholds() {
            Some(t) => gains.with_fault_thresholds(t)?,
            None => gains,
        };
        Ok(Self {
            observer: CoreObserver::new(gains),
            calibrator: options.calibration.calibrator()?,
            adc: AdcInput::new(options.adc),
            thresholds,
            adc_range: options.adc_range,
            held_rails: options.measure_adc_range.then_some(HeldRailCheck::new()),
            rails: HeldRails::default(),
            winding: options
                .winding_amplitude
                .map(|a| WindingCheck::new(T::from_f64(a)))
                .transpose()
                .map_err(|e| Error::value("winding_amplitude", e.to_string()))?,
            front_end: Default::default(),
        })
    }
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> Run for Channel<T, N, S> {
    fn run(&mut self, py: Python<'_>, y_c: Arg<'_, '_>, y_s: Arg<'_, '_>) -> Result<Estimates> {
        self.run_with_faults(py, y_c, y_s, None)
    }
}

impl<T: Sample, const N: usize, S: PhaseSinCos<T>> Channel<T, N, S> {
    /// The ADC range in the observer's units: counts through the decided scaling when
    /// `counts` (the samples were counts), else as given.
    fn range_in_units(&self, counts: bool) -> Option<(T, T)> {
        let (min, max) = self.adc_range?;
        match self.adc.decided().filter(|_| counts) {
            Some(adc) => {
                let mid = f64::from(adc.mid_scale_counts());
                let per_unit = adc.counts_per_unit().to_f64();
                Some((
                    T::from_f64((min - mid) / per_unit),
                    T::from_f64((max - mid) / per_unit),
                ))
            }
            None => Some((T::from_f64(min), T::from_f64(max))),
        }
    }
}
impl<T: Sample, const N: usize, S: PhaseSinCos<T>> ObserverOps for Channel<T, N, S> {
    fn run_with_faults(
        &mut self,
        py: Python<'_>,
        y_c: Arg<'_, '_>,
        y_s: Arg<'_, '_>,
        front_end_faults: Option<&[u8]>,
    ) -> Result<Estimates> {
        let counts = crate::counts::is_counts(y_c);
        let (y_c, y_s) = self.adc.signals(y_c, y_s)?;
        let (y_c, y_s) = (y_c.as_slice(), y_s.as_slice());
        check_equal_lengths(("y_c", y_c.len()), ("y_s", y_s.len()))?;
        if let Some(faults) = front_end_faults {
            check_equal_lengths(("y_c", y_c.len()), ("front_end_faults", faults.len()))?;
        }
        if let Some(thresholds) = self.thresholds.decide(y_c, y_s) {
            self.observer.gains = self.observer.gains.with_fault_thresholds(thresholds)?;
        }
        let check = FrontEndCheck::around((), self.range_in_units(counts))
            .map_err(|e| Error::value("adc_range", e.to_string()))?;
        let out = OutputArrays::<T>::new(py, y_c.len())?;
        out.fill(py, |columns| {
            run_columns(columns, self, check, (y_c, y_s), front_end_faults)
        })?;
        out.into_estimates(py, y_c.len(), None)
    }

    fn front_end_faults(&self) -> FrontEndFaults {
        self.front_end.0.latched_faults()
            | self.front_end.1.latched_faults()
            | self.rails.check().latched_faults()
    }

    fn estimate(&self) -> Estimate {
        Estimate::from_core(&self.observer.gains.estimate(&self.observer.state))
    }

    fn reset(&mut self) {
        self.observer.state = ObserverState::new();
    }

    fn initialise(&mut self, y_c: f64, y_s: f64) {
        let (y_c, y_s) = (T::from_f64(y_c), T::from_f64(y_s));
        let o = &mut self.observer;
        o.gains.initialise(&mut o.state, y_c, y_s);
    }

    fn set_state(&mut self, angle_rad: f64, speed_rad_s: f64, acceleration_rad_s2: f64) {
        self.observer.state = ObserverState::at(
            T::from_f64(angle_rad),
            T::from_f64(speed_rad_s),
            T::from_f64(acceleration_rad_s2),
            self.observer.gains.sample_period(),
        );
    }

    fn is_initialised(&self) -> bool {
        self.observer.state.is_initialised()
    }

    fn latched_faults(&self) -> Faults {
        self.observer.state.latched_faults()
    }

    fn clear_faults(&mut self) -> Faults {
        self.observer.state.clear_faults()
    }

    fn fault_thresholds(&self) -> Option<PyFaultThresholds> {
        // The gains' own (checked) thresholds, once the policy has decided them.
        let thresholds = self.observer.gains.fault_thresholds();
        self.thresholds
            .thresholds()
            .map(|_| PyFaultThresholds::from_typed(&thresholds))
    }

    fn amplitude(&self) -> f64 {
        self.observer.state.amplitude().to_f64()
    }

    fn calibration(&self) -> PySensorCalibration {
        PySensorCalibration::from_core(&self.calibrator.calibration())
    }

    fn calibration_mode(&self) -> CalibrationMode {
        self.calibrator.mode()
    }

    fn calibration_turns_learned(&self) -> u32 {
        self.calibrator.turns_learned()
    }

    fn calibration_status(&self) -> CalibrationStatus {
        self.calibrator.status()
    }

    fn set_calibration(&mut self, choice: &CalibrationChoice) -> Result<()> {
        self.calibrator = choice.calibrator()?;
        Ok(())
    }
}

/// Runs `channel` over `y_c`, `y_s` into the columns (all of equal length, checked by the
/// caller), through the front-end `check` with the samples' `front_end_faults` if given.
/// Called with the GIL released: no Python object is touched.
fn run_columns<T: Real, const N: usize, S: SinCos<T>>(
    columns: EstimateColumns<'_, T>,
    channel: &mut Channel<T, N, S>,
    check: FrontEndCheck<T>,
    (y_c, y_s): (&[T], &[T]),
    front_end_faults: Option<&[u8]>,
) {
    let gains = channel.observer.gains;
    // The front-end check (quiet on a sample without a fault), the rails measured and the
    // winding check if asked for, then the online calibration (with the calibration off,
    // the chain's quiet path: one branch on the mode).
    let chain = Chain::new(
        (
            check,
            (
                channel.held_rails,
                (channel.winding, online_calibration(&gains)),
            ),
        ),
        gains,
    );
    let mut state = ChainState {
        front_end: (
            (channel.front_end.0, ()),
            (channel.rails, (channel.front_end.1, channel.calibrator)),
        ),
        observer: channel.observer.state,
    };
    let faults = |k: usize| {
        front_end_faults
            .and_then(|f| f.get(k))
            .map_or(FrontEndFaults::NONE, |&bits| {
                FrontEndFaults::from_bits(bits)
            })
    };
    columns.write(
        y_c.iter()
            .zip(y_s)
            .enumerate()
            .map(|(k, (&c, &s))| chain.update(&mut state, ((c, s), faults(k)))),
    );
    let ((check, ()), (rails, (winding, calibrator))) = state.front_end;
    (
        channel.front_end,
        channel.rails,
        channel.calibrator,
        channel.observer.state,
    ) = ((check, winding), rails, calibrator, state.observer);
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
///
/// Samples may be floats of the observer's dtype or raw ADC counts (int16, uint16, int32),
/// converted exactly: minus `adc_mid_scale` (default 0 for signed counts; for uint16 the
/// mid-scale of the smallest offset-binary ADC that holds the first call's samples, 2048
/// for counts up to 4095) and divided by `adc_counts_per_unit` (default 1: the observer
/// runs in counts). The loop is amplitude-invariant, so counts or volts track alike.
///
/// `fault_thresholds=None` (the default) scales the diagnostics to the signal: at the
/// first `update`, `FaultThresholds(nominal_amplitude=A)` with `A` the median magnitude
/// `sqrt(y_c^2 + y_s^2)` of its first 4096 samples (amplitude 1 if that is not positive);
/// give thresholds to state the amplitude yourself.
///
/// `adc_range=(min, max)`: the ADC's range in the samples' units (counts for integer
/// samples): a sample at or beyond it in either channel is flagged `Faults.FRONT_END`, and
/// one clipped in both channels is not used (the observer coasts on its prediction).
/// `measure_adc_range=True` (without `adc_range`): the same against the rails measured as
/// the samples come: an extreme a channel holds for `HELD_RAIL_SAMPLES` samples while the
/// other moves, the samples piled up there (the core's `HeldRailCheck`; a clean signal and
/// a still shaft have none).
///
/// `winding_amplitude`: the windings' nominal envelope amplitude in the samples' units (1
/// for a `Demodulator`'s pairs): a winding open or shorted (reading below a quarter of it
/// where the prediction puts half of it there, the other winding agreeing with the
/// prediction) is flagged `Faults.FRONT_END` (front-end bit 16) and coasted through;
/// `None` (the default): no winding check.
///
/// `calibration`: `None` (off), `"learn"` (correct offsets, gain imbalance and quadrature
/// error and learn them while tracking, from `initial_calibration` if given) or `"frozen"`
/// (apply `initial_calibration`, learn nothing). The calibration is in the input's units.
#[pyclass(name = "Observer", module = "angletrack", extends = RunSettings)]
#[derive(Debug)]
pub struct PyObserver {
    inner: Box<dyn ObserverOps>,
}

#[pymethods]
impl PyObserver {
    #[new]
    #[pyo3(signature = (gains, *, dtype = None, sin_cos = None, fault_thresholds = None,
        calibration = None, initial_calibration = None, adc_mid_scale = None,
        adc_counts_per_unit = None, adc_range = None, measure_adc_range = false,
        winding_amplitude = None))]
    #[allow(clippy::too_many_arguments)]
    fn py_new(
        gains: PyGains,
        dtype: Option<&Bound<'_, PyAny>>,
        sin_cos: Option<&str>,
        fault_thresholds: Option<PyFaultThresholds>,
        calibration: Option<&str>,
        initial_calibration: Option<PySensorCalibration>,
        adc_mid_scale: Option<i64>,
        adc_counts_per_unit: Option<f64>,
        adc_range: Option<(f64, f64)>,
        measure_adc_range: bool,
        winding_amplitude: Option<f64>,
    ) -> Result<PyClassInitializer<Self>> {
        let options = ObserverOptions {
            thresholds: fault_thresholds,
            adc: adc_settings(adc_mid_scale, adc_counts_per_unit)?,
            calibration: CalibrationChoice::new(calibration, initial_calibration)?,
            adc_range: crate::counts::adc_range(adc_range)?,
            measure_adc_range,
            winding_amplitude,
        }
        .checked()?;
        RunSettings::from_arguments(gains, dtype, sin_cos)?.subclass(|gains| {
            let inner = gains.observer(&options)?;
            Ok(Self { inner })
        })
    }

    /// Runs the observer over the samples `y_c ~ cos(theta)`, `y_s ~ sin(theta)` (1-D,
    /// equal lengths, of the observer's dtype, or both raw counts of one integer dtype) and
    /// returns the estimates of every sample. The state carries over to the next call.
    ///
    /// `front_end_faults` (uint8, one per sample, the bits of `DemodulatedPairs.faults`):
    /// while a sample's faults invalidate it (loss of excitation, a winding open or
    /// shorted) the observer coasts on its prediction, and every flagged sample's estimate
    /// carries `Faults.FRONT_END`; so do samples clipped against `adc_range`.
    #[pyo3(signature = (y_c, y_s, front_end_faults = None))]
    fn update(
        &mut self,
        py: Python<'_>,
        y_c: Arg<'_, '_>,
        y_s: Arg<'_, '_>,
        front_end_faults: Option<PyReadonlyArray1<'_, u8>>,
    ) -> Result<Estimates> {
        let faults = front_end_faults
            .as_ref()
            .map(|f| f.as_slice())
            .transpose()
            .map_err(|_| {
                Error::value(
                    "front_end_faults",
                    "expected a contiguous uint8 array".to_string(),
                )
            })?;
        self.inner.run_with_faults(py, y_c, y_s, faults)
    }

    /// The front-end faults latched since they were last cleared (bits of
    /// `DemodulatedPairs.faults`, and 4 for a sample clipped against `adc_range` or the
    /// rails measured).
    #[getter]
    fn latched_front_end_faults(&self) -> u8 {
        self.inner.front_end_faults().bits()
    }

    /// The estimate after the last sample.
    #[getter]
    fn estimate(&self) -> Estimate {
        self.inner.estimate()
    }

    /// Forgets the state: the next sample initialises the observer from its `atan2`. Keeps
    /// the calibration.
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

    /// The diagnostics thresholds the observer runs with; `None` until the first `update`
    /// when they are scaled to its samples.
    #[getter]
    fn fault_thresholds(&self) -> Option<PyFaultThresholds> {
        self.inner.fault_thresholds()
    }

    /// The signal's magnitude `sqrt(y_c^2 + y_s^2)` the loop normalises its phase error by
    /// (input units, after the calibration's correction).
    #[getter]
    fn amplitude(&self) -> f64 {
        self.inner.amplitude()
    }

    /// The sensor calibration applied to each sample (unless the calibration is off): what
    /// it learned so far, or was given.
    #[getter]
    fn calibration(&self) -> PySensorCalibration {
        self.inner.calibration()
    }

    /// The calibration's mode: `"off"`, `"learn"` or `"frozen"`.
    #[getter]
    fn calibration_mode(&self) -> &'static str {
        mode_name(self.inner.calibration_mode())
    }

    /// The electrical turns the calibration has learned from since it started or was set.
    #[getter]
    fn calibration_turns_learned(&self) -> u32 {
        self.inner.calibration_turns_learned()
    }

    /// Where the online calibration stands: `"finding-centre"` (the channels' centres are
    /// not found yet: the rotor has not turned a whole turn, or is at rest; nothing is
    /// learned and the angle of biased signals is wrong), `"centred"` (learning, or ready
    /// to), or `"stalled"` (16 electrical turns at speed without a turn learned: the
    /// observer is not locked within 0.29 of phase error, or the speed is not steady).
    #[getter]
    fn calibration_status(&self) -> &'static str {
        status_name(self.inner.calibration_status())
    }

    /// Sets the calibration as the constructor's `calibration` and `initial_calibration`
    /// do (`ConfigError` naming them); the state is kept.
    #[pyo3(signature = (calibration, initial_calibration = None))]
    fn set_calibration(
        &mut self,
        calibration: Option<&str>,
        initial_calibration: Option<PySensorCalibration>,
    ) -> Result<()> {
        let choice = CalibrationChoice::new(calibration, initial_calibration)?;
        self.inner.set_calibration(&choice)
    }

    /// `False` until the first sample (or `set_state`) has set the angle.
    #[getter]
    fn is_initialised(&self) -> bool {
        self.inner.is_initialised()
    }

    fn __repr__(slf: PyRef<'_, Self>) -> String {
        let settings = slf.as_super();
        format!(
            "Observer({}, gains={:?}, calibration={}, initialised={})",
            settings.describe(),
            settings.gain_set().gains(),
            mode_name(slf.inner.calibration_mode()),
            slf.inner.is_initialised()
        )
    }
}

/// Runs a fresh observer with `gains` over `y_c`, `y_s` in the samples' own dtype (float32
/// or float64; float64 for raw ADC counts, int16, uint16 or int32, scaled as `Observer`
/// does) and returns the estimates. `fault_thresholds=None` scales the diagnostics to the
/// samples' own amplitude, as `Observer` does; `adc_range=(min, max)` flags samples clipped
/// against it, as `Observer` does.
#[pyfunction]
#[pyo3(signature = (gains, y_c, y_s, *, sin_cos = None, fault_thresholds = None,
    adc_mid_scale = None, adc_counts_per_unit = None, adc_range = None))]
#[allow(clippy::too_many_arguments)]
pub fn track(
    py: Python<'_>,
    gains: PyGains,
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
    sin_cos: Option<&str>,
    fault_thresholds: Option<PyFaultThresholds>,
    adc_mid_scale: Option<i64>,
    adc_counts_per_unit: Option<f64>,
    adc_range: Option<(f64, f64)>,
) -> Result<Estimates> {
    let settings = RunSettings::new(gains, Float::of_samples(y_c, "y_c")?, sin_cos)?;
    let options = ObserverOptions {
        thresholds: fault_thresholds,
        adc: adc_settings(adc_mid_scale, adc_counts_per_unit)?,
        calibration: CalibrationChoice::default(),
        adc_range: crate::counts::adc_range(adc_range)?,
        measure_adc_range: false,
        winding_amplitude: None,
    };
    settings
        .typed_gains()?
        .observer(&options)?
        .run(py, y_c, y_s)
}
