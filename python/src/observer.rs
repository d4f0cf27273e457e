//! `Observer` and `track`: the crate's chain of one observer (`angletrack::AnyChannel`) on
//! 1-D numpy arrays.
//!
//! The per-sample work is the core's `Tracker::update`; this module only moves samples in
//! and estimates out, with the GIL released, straight into preallocated arrays that numpy
//! owns.

use angletrack::{
    AnyChannel, ChannelOptions, OutputSet, TrackerChannel, mode_name, status_name, with_any_channel,
};
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;

use crate::arrays::{Count, Float};
use crate::calibration::{PySensorCalibration, calibration_choice};
use crate::counts::adc_settings;
use crate::diagnostics::PyFaultThresholds;
use crate::dispatch::{Arg, PhaseSinCos, RunSettings, Sample};
use crate::errors::{Error, Result};
use crate::estimates::{Estimate, Estimates, run_estimates};
use crate::gains::PyGains;
use crate::getters::class_methods;

/// Runs `channel` over `y_c`, `y_s` (floats of its type, or counts it scales) with the
/// front-end faults of each sample (`None`: none given) and returns the estimates of every
/// sample; `stated`: the first ADC argument the caller gave (refused with float samples).
pub fn run_channel<T: Sample, const N: usize, S: PhaseSinCos<T>>(
    py: Python<'_>,
    channel: &mut TrackerChannel<T, N, S>,
    stated: Option<&'static str>,
    (y_c, y_s): (Arg<'_, '_>, Arg<'_, '_>),
    front_end_faults: Option<&[u8]>,
) -> Result<Estimates> {
    let counts = crate::counts::is_counts(y_c);
    let (y_c, y_s) = crate::counts::signals(&mut channel.input, stated, y_c, y_s)?;
    let (y_c, y_s) = (y_c.as_slice(), y_s.as_slice());
    channel.prepare(counts, (y_c, y_s), front_end_faults)?;
    let ((), estimates) = run_estimates(py, y_c.len(), (OutputSet::ALL, None), |columns| {
        channel.run(columns, (y_c, y_s), front_end_faults)
    })?;
    Ok(estimates)
}

/// An angle tracking observer running on numpy arrays: checked gains plus a state that
/// persists between calls, so a capture fed in chunks gives exactly the result of one call.
///
/// Samples may be floats of the observer's dtype or raw ADC counts (int16, uint16, int32,
/// int64), converted exactly: minus `adc_mid_scale` and divided by `adc_counts_per_unit`
/// (default 1: the observer runs in counts). Nothing is read from the samples, so that
/// chunks of any size give the result of one call: without `adc_mid_scale`, int16 and int32
/// counts (or any with `adc_signed=True`) are signed, mid-scale 0; uint16 counts (or any with
/// `adc_signed=False`) are refused, naming `adc_mid_scale`; int64 counts without
/// `adc_signed` are refused, naming it. The loop is amplitude-invariant, so counts or volts
/// track alike. The ADC arguments apply to counts only: float samples with any given are
/// refused (`ConfigError` naming it), not tracked unscaled.
///
/// `fault_thresholds=None` (the default): the diagnostics' defaults, those of a signal of
/// amplitude 1 in the observer's units: floats of amplitude about 1, or counts with
/// `adc_counts_per_unit` their amplitude in counts. Raw counts in counts (no
/// `adc_counts_per_unit`) are refused without thresholds (`ConfigError` naming
/// `fault_thresholds`): give `FaultThresholds(nominal_amplitude=A)` with `A` in the samples'
/// units. Never measured on the first call, whose samples depend on the chunks.
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
/// `initial_calibration` with the calibration off is refused (`ConfigError` naming it).
#[pyclass(name = "Observer", module = "angletrack", extends = RunSettings)]
#[derive(Debug)]
pub struct PyObserver {
    /// The crate's chain of one observer.
    pub(crate) inner: AnyChannel,
    /// The first ADC argument the caller gave.
    pub(crate) stated: Option<&'static str>,
}

class_methods! {
    PyObserver {
        /// The front-end faults latched since they were last cleared (bits of
        /// `DemodulatedPairs.faults`, and 4 for a sample clipped against `adc_range` or the
        /// rails measured).
        latched_front_end_faults: u8 = |this, py| this.inner.status().front_end_faults.bits();
        /// The estimate after the last sample.
        estimate: Estimate = |this, py| Estimate { inner: this.inner.status().estimate };
        /// The faults latched since they were last cleared (bits, see `angletrack.Faults`), like
        /// reading an RDC chip's fault register.
        latched_faults: u8 = |this, py| this.inner.status().latched_faults.bits();
        /// The diagnostics thresholds the observer runs with (given, or the defaults).
        fault_thresholds: Option<PyFaultThresholds> = |this, py| this.inner.status().fault_thresholds.map(|t| PyFaultThresholds::from_typed(&t));
        /// The signal's magnitude `sqrt(y_c^2 + y_s^2)` the loop normalises its phase error by
        /// (input units, after the calibration's correction).
        amplitude: f64 = |this, py| this.inner.status().amplitude;
        /// The sensor calibration applied to each sample (unless the calibration is off): what
        /// it learned so far, or was given.
        calibration: PySensorCalibration = |this, py| PySensorCalibration::from_core(&this.inner.status().calibration);
        /// The calibration's mode: `"off"`, `"learn"` or `"frozen"`.
        calibration_mode: &'static str = |this, py| mode_name(this.inner.status().calibration_mode);
        /// The electrical turns the calibration has learned from since it started or was set.
        calibration_turns_learned: u32 = |this, py| this.inner.status().calibration_turns_learned;
        /// Where the online calibration stands: `"finding-centre"` (the channels' centres are
        /// not found yet: the rotor has not turned a whole turn, or is at rest; nothing is
        /// learned and the angle of biased signals is wrong), `"centred"` (learning, or ready
        /// to), or `"stalled"` (16 electrical turns at speed without a turn learned: the
        /// observer is not locked within 0.29 of phase error, or the speed is not steady).
        calibration_status: &'static str = |this, py| status_name(this.inner.status().calibration_status);
        /// `False` until the first sample (or `set_state`) has set the angle.
        is_initialised: bool = |this, py| this.inner.status().initialised;
    }
    methods {
        #[new]
        #[pyo3(signature = (gains, *, dtype = None, sin_cos = None, fault_thresholds = None,
            calibration = None, initial_calibration = None, adc_mid_scale = None,
            adc_counts_per_unit = None, adc_signed = None, adc_range = None,
            measure_adc_range = false, winding_amplitude = None))]
        #[allow(clippy::too_many_arguments)]
        fn py_new(
            gains: PyGains,
            dtype: Option<&Bound<'_, PyAny>>,
            sin_cos: Option<&str>,
            fault_thresholds: Option<PyFaultThresholds>,
            calibration: Option<&str>,
            initial_calibration: Option<PySensorCalibration>,
            adc_mid_scale: Option<Count>,
            adc_counts_per_unit: Option<f64>,
            adc_signed: Option<bool>,
            adc_range: Option<(f64, f64)>,
            measure_adc_range: bool,
            winding_amplitude: Option<f64>,
        ) -> Result<PyClassInitializer<Self>> {
            let adc = adc_settings(adc_mid_scale, adc_counts_per_unit, adc_signed)?;
            let options = ChannelOptions {
                thresholds: fault_thresholds.map(|t| t.typed()),
                counts: adc.counts,
                calibration: calibration_choice(calibration, initial_calibration)?,
                adc_range,
                measure_adc_range,
                winding_amplitude,
                ..ChannelOptions::default()
            };
            let settings = RunSettings::from_arguments(gains, dtype, sin_cos)?;
            let inner = settings.channel(&options)?;
            Ok(settings.subclass(Self { inner, stated: adc.stated }))
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
            let faults = front_end_faults.as_ref().map(|f| f.as_slice()).transpose();
            let faults = faults
                .map_err(|_| Error::value("front_end_faults", "expected a contiguous uint8 array"))?;
            let stated = self.stated;
            with_any_channel!(AnyChannel, &mut self.inner, c => {
                run_channel(py, c, stated, (y_c, y_s), faults)
            })
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
            Ok(self.inner.initialise(y_c, y_s)?)
        }

        /// Starts from a known angle (rad: wrapped, whole turns counted, within +-2^31 turns),
        /// speed (rad/s, within half a turn per sample, `pi / sample_period_s`) and acceleration
        /// (rad/s^2, within `pi / sample_period_s^2`; 0 at order 2, which has no acceleration
        /// state). Refuses (`ConfigError` naming it) a value that is not finite or beyond these.
        #[pyo3(signature = (angle_rad, speed_rad_s = 0.0, acceleration_rad_s2 = 0.0))]
        fn set_state(
            &mut self,
            angle_rad: f64,
            speed_rad_s: f64,
            acceleration_rad_s2: f64,
        ) -> Result<()> {
            Ok(self
                .inner
                .set_state(angle_rad, speed_rad_s, acceleration_rad_s2)?)
        }

        /// Returns the latched faults (bits) and clears them.
        fn clear_faults(&mut self) -> u8 {
            self.inner.clear_faults().bits()
        }

        /// Sets the calibration as the constructor's `calibration` and `initial_calibration`
        /// do (`ConfigError` naming them); the state is kept.
        #[pyo3(signature = (calibration, initial_calibration = None))]
        fn set_calibration(
            &mut self,
            calibration: Option<&str>,
            initial_calibration: Option<PySensorCalibration>,
        ) -> Result<()> {
            let choice = calibration_choice(calibration, initial_calibration)?;
            Ok(self.inner.set_calibration(&choice)?)
        }

        fn __repr__(slf: PyRef<'_, Self>) -> String {
            let settings = slf.as_super();
            format!(
                "Observer({}, gains={:?}, calibration={}, initialised={})",
                settings.describe(),
                settings.gain_set().gains(),
                mode_name(slf.inner.status().calibration_mode),
                slf.inner.status().initialised
            )
        }
    }
}

/// Runs a fresh observer with `gains` over the whole capture `y_c`, `y_s` in the samples'
/// own dtype (float32 or float64; float64 for raw ADC counts, int16, uint16, int32 or
/// int64) and returns the estimates. Counts are scaled as `Observer` scales them, except
/// that what is not stated is read from the whole capture (the crate's `capture_counts`):
/// uint16 counts, or counts with `adc_signed=False`, lose the offset-binary mid-scale of
/// the largest sample; int64 counts are signed with a negative sample, unsigned when both
/// channels swing about one offset-binary mid-scale, else refused (`ConfigError` naming
/// `adc_signed`). `fault_thresholds=None` scales the diagnostics to the capture's own
/// amplitude (the median magnitude of its first 4096 samples). `adc_mid_scale`,
/// `adc_counts_per_unit` or `adc_signed` with float samples is a `ConfigError` naming it;
/// `adc_range=(min, max)` flags samples clipped against it, as `Observer` does.
#[pyfunction]
#[pyo3(signature = (gains, y_c, y_s, *, sin_cos = None, fault_thresholds = None,
    adc_mid_scale = None, adc_counts_per_unit = None, adc_signed = None, adc_range = None))]
#[allow(clippy::too_many_arguments)]
pub fn track(
    py: Python<'_>,
    gains: PyGains,
    y_c: &Bound<'_, PyAny>,
    y_s: &Bound<'_, PyAny>,
    sin_cos: Option<&str>,
    fault_thresholds: Option<PyFaultThresholds>,
    adc_mid_scale: Option<Count>,
    adc_counts_per_unit: Option<f64>,
    adc_signed: Option<bool>,
    adc_range: Option<(f64, f64)>,
) -> Result<Estimates> {
    let settings = RunSettings::new(gains, Float::of_samples(y_c, "y_c")?, sin_cos)?;
    let adc = adc_settings(adc_mid_scale, adc_counts_per_unit, adc_signed)?;
    let options = ChannelOptions {
        thresholds: fault_thresholds.map(|t| t.typed()),
        whole: true,
        counts: adc.counts,
        adc_range,
        ..ChannelOptions::default()
    };
    let mut channel = settings.channel(&options)?;
    with_any_channel!(AnyChannel, &mut channel, c => {
        run_channel(py, c, adc.stated, (y_c, y_s), None)
    })
}
