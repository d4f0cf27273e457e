//! `FaultThresholds` and the fault flags: the core's diagnostics, configured from Python.

use angletrack::converted_thresholds;
use angletrack_core::{FaultThresholds as CoreThresholds, Faults, FrontEndFaults, Real};
use pyo3::prelude::*;

use crate::getters::class_methods;

/// Thresholds of the observer's diagnostics (like an RDC chip's fault register) and of its
/// input check, in the units of `y_c`, `y_s` unless stated (the loop itself needs none: its
/// phase error is normalised). Keyword arguments override the defaults for
/// `nominal_amplitude` (the core's `FaultThresholds::for_amplitude`): input bound 4 A, loss
/// of signal 0.25 A, degradation below 0.5 A or above 1.5 A, loss of tracking at a mean
/// |normalised phase error| of 0.1 (about 5.7 degrees, at any amplitude), maximum speed
/// pi / (2 Ts) rad/s, filter factor 1/16 (the monitor decides once per window of 16 used
/// samples, from its means: a fault is flagged within 31 samples, a bad sample at once),
/// false lock at an in-phase component below 0, monitoring and re-acquisition on. Checked
/// when an observer is built (`ConfigError` naming the field).
#[pyclass(
    name = "FaultThresholds",
    module = "angletrack",
    frozen,
    from_py_object
)]
#[derive(Debug, Clone, Copy, Default)]
pub struct PyFaultThresholds {
    inner: CoreThresholds<f64>,
}

impl PyFaultThresholds {
    /// The Python value of thresholds in float type `T`.
    pub fn from_typed<T: Real>(t: &CoreThresholds<T>) -> Self {
        Self {
            inner: converted_thresholds(t),
        }
    }

    /// The thresholds in float type `T` (checked where an observer takes them).
    pub fn typed<T: Real>(&self) -> CoreThresholds<T> {
        converted_thresholds(&self.inner)
    }
}

class_methods! {
    PyFaultThresholds {
        /// The amplitude of a healthy signal.
        nominal_amplitude: f64 = |this, py| this.inner.nominal_amplitude;
        /// Samples with an amplitude above this (or non-finite) are rejected.
        max_input_amplitude: f64 = |this, py| this.inner.max_input_amplitude;
        /// A window's RMS amplitude below this: loss of signal.
        loss_of_signal: f64 = |this, py| this.inner.loss_of_signal;
        /// A window's RMS amplitude below this: degradation of signal.
        degradation_low: f64 = |this, py| this.inner.degradation_low;
        /// A window's RMS amplitude above this: degradation of signal.
        degradation_high: f64 = |this, py| this.inner.degradation_high;
        /// A window's mean |phase error| above this: loss of tracking.
        loss_of_tracking: f64 = |this, py| this.inner.loss_of_tracking;
        /// A sample's |phase error| (about the sine of its electrical angle error) above
        /// this: loss of tracking on that sample, held until it falls to half.
        tracking_error: f64 = |this, py| this.inner.tracking_error;
        /// Estimated |speed| (rad/s) above this: loss of tracking; `None`: pi / (2 Ts).
        max_speed_rad_s: Option<f64> = |this, py| this.inner.max_speed;
        /// 1 / W for the monitor's window of W used samples (1 / filter_factor rounded down
        /// to a power of two, at most 4096), in (0, 1]: a fault is flagged within 2 W - 1
        /// samples.
        filter_factor: f64 = |this, py| this.inner.filter_factor;
        /// In-phase component at a window's end below this: false lock.
        false_lock: f64 = |this, py| this.inner.false_lock;
        /// Whether the fault flags are computed (the input check always runs).
        monitor: bool = |this, py| this.inner.monitor;
        /// Whether a false lock re-acquires the angle from atan2.
        re_acquire: bool = |this, py| this.inner.re_acquire;
        /// The roundness check's tolerance (a fraction of `nominal_amplitude`; `None`: no
        /// check): a pair whose magnitude leaves the band is flagged `DEGRADATION_OF_SIGNAL`.
        magnitude_tolerance: Option<f64> = |this, py| this.inner.magnitude_tolerance;
    }
    methods {
        #[new]
        #[pyo3(signature = (*, nominal_amplitude = 1.0, max_input_amplitude = None,
            loss_of_signal = None, degradation_low = None, degradation_high = None,
            loss_of_tracking = None, tracking_error = None, max_speed_rad_s = None, filter_factor = None,
            false_lock = None, monitor = true, re_acquire = true, magnitude_tolerance = None))]
        #[allow(clippy::too_many_arguments)]
        fn py_new(
            nominal_amplitude: f64,
            max_input_amplitude: Option<f64>,
            loss_of_signal: Option<f64>,
            degradation_low: Option<f64>,
            degradation_high: Option<f64>,
            loss_of_tracking: Option<f64>,
            tracking_error: Option<f64>,
            max_speed_rad_s: Option<f64>,
            filter_factor: Option<f64>,
            false_lock: Option<f64>,
            monitor: bool,
            re_acquire: bool,
            magnitude_tolerance: Option<f64>,
        ) -> Self {
            let d = CoreThresholds::for_amplitude(nominal_amplitude);
            let inner = d
                .with_max_input_amplitude(max_input_amplitude.unwrap_or(d.max_input_amplitude))
                .with_loss_of_signal(loss_of_signal.unwrap_or(d.loss_of_signal))
                .with_degradation_low(degradation_low.unwrap_or(d.degradation_low))
                .with_degradation_high(degradation_high.unwrap_or(d.degradation_high))
                .with_loss_of_tracking(loss_of_tracking.unwrap_or(d.loss_of_tracking))
                .with_tracking_error(tracking_error.unwrap_or(d.tracking_error))
                .with_max_speed(max_speed_rad_s.or(d.max_speed))
                .with_filter_factor(filter_factor.unwrap_or(d.filter_factor))
                .with_false_lock(false_lock.unwrap_or(d.false_lock))
                .with_monitor(monitor)
                .with_re_acquire(re_acquire)
                .with_magnitude_tolerance(magnitude_tolerance);
            Self { inner }
        }

        /// No diagnostics and no re-acquisition, only the input check: the bare loop of the
        /// paper (to study the loop's own large-signal behaviour).
        #[staticmethod]
        fn disabled() -> Self {
            Self { inner: CoreThresholds::disabled() }
        }

        fn __repr__(&self) -> String {
            let t = &self.inner;
            let python_bool = |b: bool| if b { "True" } else { "False" };
            format!(
                "FaultThresholds(nominal_amplitude={}, max_input_amplitude={}, loss_of_signal={}, \
                 degradation_low={}, degradation_high={}, loss_of_tracking={}, tracking_error={}, \
                 max_speed_rad_s={}, \
                 filter_factor={}, false_lock={}, monitor={}, re_acquire={}, magnitude_tolerance={})",
                t.nominal_amplitude,
                t.max_input_amplitude,
                t.loss_of_signal,
                t.degradation_low,
                t.degradation_high,
                t.loss_of_tracking,
                t.tracking_error,
                t.max_speed.map_or("None".to_string(), |v| v.to_string()),
                t.filter_factor,
                t.false_lock,
                python_bool(t.monitor),
                python_bool(t.re_acquire),
                t.magnitude_tolerance.map_or("None".to_string(), |v| v.to_string()),
            )
        }
    }
}

/// The fault flag bits of `Estimates.faults`, `Estimate.faults` and
/// `Observer.latched_faults`, by the names of the core's `Faults` constants
/// (`LOSS_OF_SIGNAL`: the core's "loss of signal" in upper case, words joined by `_`).
pub fn fault_bits() -> Vec<(String, u8)> {
    constant_names(Faults::NAMES.map(|(flag, name)| (name, flag.bits())))
}

/// The front-end fault flag bits of `DemodulatedPairs.faults`, the resolver path's
/// `front_end_faults` column and `Demodulator.latched_faults`, named as [`fault_bits`].
pub fn front_end_fault_bits() -> Vec<(String, u8)> {
    constant_names(FrontEndFaults::NAMES.map(|(flag, name)| (name, flag.bits())))
}

/// The core's flag names as its constants spell them.
fn constant_names<const N: usize>(flags: [(&str, u8); N]) -> Vec<(String, u8)> {
    flags
        .into_iter()
        .map(|(name, bits)| (name.to_uppercase().replace(' ', "_"), bits))
        .collect()
}
