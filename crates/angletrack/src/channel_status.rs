//! What a [`TrackerChannel`]'s state holds now, in float64: what the Python `Observer`'s
//! attributes read.

use angletrack_core::{
    CalibrationMode, CalibrationStatus, Estimate, FaultThresholds, Faults, FrontEndFaults, Real,
    SensorCalibration, SinCos,
};

use crate::{TrackerChannel, converted_calibration, converted_thresholds};

/// A [`TrackerChannel`]'s state now ([`TrackerChannel::status`]), in float64.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelStatus {
    /// The estimate after the last sample.
    pub estimate: Estimate<f64>,
    /// `false` until the first sample (or a state set) has set the angle.
    pub initialised: bool,
    /// The observer's faults latched.
    pub latched_faults: Faults,
    /// The front-end faults latched (the range check, the rails measured, the winding check).
    pub front_end_faults: FrontEndFaults,
    /// The diagnostics' thresholds, once decided.
    pub fault_thresholds: Option<FaultThresholds<f64>>,
    /// The signal's magnitude the loop normalises its phase error by (input units).
    pub amplitude: f64,
    /// The sensor calibration applied (or learned so far).
    pub calibration: SensorCalibration<f64>,
    /// The calibration's mode.
    pub calibration_mode: CalibrationMode,
    /// The electrical turns the calibration has learned from.
    pub calibration_turns_learned: u32,
    /// Where the online calibration stands.
    pub calibration_status: CalibrationStatus,
}

impl<T: Real, const N: usize, S: SinCos<T>> TrackerChannel<T, N, S> {
    /// The chain's state now, in float64.
    ///
    /// ```
    /// use angletrack::{ChannelOptions, TrackerChannel};
    /// use angletrack::core::Gains;
    /// let gains = Gains::<f32, 2, angletrack::Fast>::new([0.2, 0.02], 1e-4)?;
    /// let mut channel = TrackerChannel::new(gains, &ChannelOptions::default()).unwrap();
    /// assert!(!channel.status().initialised);
    /// channel.initialise(0.0, 1.0).unwrap();
    /// let status = channel.status();
    /// assert!(status.initialised && (status.estimate.angle - 1.5707963705062866).abs() < 1e-12);
    /// # Ok::<(), angletrack::core::ConfigError>(())
    /// ```
    pub fn status(&self) -> ChannelStatus {
        let (observer, calibrator) = (&self.state.observer, self.state.front_end.calibrator());
        let e = self.tracker.observer.estimate(observer);
        let f = T::to_f64;
        ChannelStatus {
            estimate: Estimate::new(
                f(e.angle),
                e.turns,
                f(e.speed),
                f(e.acceleration),
                f(e.phase_error),
                e.faults,
            ),
            initialised: observer.is_initialised(),
            latched_faults: observer.latched_faults(),
            front_end_faults: self.state.front_end.latched_faults(),
            fault_thresholds: self.fault_thresholds().as_ref().map(converted_thresholds),
            amplitude: f(observer.amplitude()),
            // Widened exactly to f64, the calibration the core checked passes its check again.
            calibration: converted_calibration(&calibrator.calibration()).unwrap_or_default(),
            calibration_mode: calibrator.mode(),
            calibration_turns_learned: calibrator.turns_learned(),
            calibration_status: calibrator.status(),
        }
    }
}
