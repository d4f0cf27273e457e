//! Real sensor signals over arrays (`docs/theory.md §12`): a run with the core's online
//! calibration ([`run_calibrated`]), and the nominal amplitude of a capture estimated from
//! its own samples ([`nominal_amplitude`], [`capture_fault_thresholds`]), so that the
//! diagnostics fit a capture in any unit (volts, raw ADC counts) without the caller stating
//! it.

use angletrack_core::{
    Calibrator, Chain, ChainState, FaultThresholds, Gains, ObserverState, Real, SinCos,
};

use super::Scenario;
use super::metrics::{Run, run_with};

/// The number of samples at the start of a capture from which [`nominal_amplitude`]
/// estimates its amplitude: 4096, a few electrical turns at usual speeds and sample rates,
/// and enough for the median to ignore a few bad samples.
pub const NOMINAL_AMPLITUDE_SAMPLES: usize = 4096;

/// Runs `gains` over the scenario's signals through the online calibration `calibrator`
/// (`Calibrator::new()` then `enable()` to learn from nothing,
/// `Calibrator::from_calibration(stored)` to apply a stored calibration, frozen), from a
/// fresh state, as [`run`](crate::run) does; returns the estimates and the calibrator as
/// the run left it (its [`calibration`](Calibrator::calibration) is what it learned).
///
/// ```
/// use angletrack::{Gains, Motion, MotionProfile, Scenario, SensorModel, run_calibrated};
/// use angletrack::core::Calibrator;
/// let sensor = SensorModel { offset_cos: 0.05, amplitude_imbalance: 0.1, ..SensorModel::default() };
/// let profile = MotionProfile::new(0.0, 300.0)
///     .then(Motion::ConstantSpeed { speed_rad_s: 300.0, duration_s: 1.0 });
/// let scenario = Scenario::generate(&profile, &sensor, 1e-4, 1)?;
/// let gains = Gains::<f64, 3>::new([0.06, 0.0019, 3e-5], 1e-4)?;
/// let mut calibrator = Calibrator::new();
/// calibrator.enable();
/// let (estimates, calibrator) = run_calibrated(&gains, calibrator, &scenario);
/// assert_eq!(estimates.angle_rad.len(), scenario.len());
/// let (o_c, _) = calibrator.calibration().offsets();
/// assert!((o_c - 0.05).abs() < 2e-3 && (calibrator.calibration().amplitude_ratio() - 1.1).abs() < 2e-3);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn run_calibrated<T: Real, const N: usize, S: SinCos<T>>(
    gains: &Gains<T, N, S>,
    calibrator: Calibrator<T>,
    scenario: &Scenario,
) -> (Run, Calibrator<T>) {
    let chain = Chain::new(gains.online_calibration(), *gains);
    let mut state = ChainState {
        front_end: calibrator,
        observer: ObserverState::new(),
    };
    let run = run_with(scenario, |c, s| chain.update(&mut state, (c, s)));
    (run, state.front_end)
}

/// The nominal amplitude of a capture, estimated from its samples: the median of
/// `sqrt(y_c^2 + y_s^2)` over the first [`NOMINAL_AMPLITUDE_SAMPLES`] samples (non-finite
/// ones left out), in the samples' own units. The median rather than the mean, so that a
/// few bad samples do not move it; the first samples, so that a long capture costs no more.
/// Offsets, imbalance and quadrature error of a few percent move it by about as much, well
/// inside the diagnostics' bands (0.5 to 1.5 times the nominal amplitude). `None` when no
/// sample is finite or the median is not positive (a capture that starts without signal).
///
/// ```
/// let theta: Vec<f64> = (0..1000).map(|k| 0.01 * k as f64).collect();
/// let y_c: Vec<f64> = theta.iter().map(|t| 1800.0 * t.cos()).collect();
/// let y_s: Vec<f64> = theta.iter().map(|t| 1800.0 * t.sin()).collect();
/// let amplitude = angletrack::nominal_amplitude(&y_c, &y_s).unwrap();
/// assert!((amplitude - 1800.0).abs() < 1e-9);
/// assert_eq!(angletrack::nominal_amplitude(&[0.0_f32; 8], &[0.0; 8]), None);
/// ```
pub fn nominal_amplitude<T: Real>(y_c: &[T], y_s: &[T]) -> Option<f64> {
    let mut magnitudes: Vec<f64> = y_c
        .iter()
        .zip(y_s)
        .take(NOMINAL_AMPLITUDE_SAMPLES)
        .map(|(&c, &s)| c.to_f64().hypot(s.to_f64()))
        .filter(|m| m.is_finite())
        .collect();
    if magnitudes.is_empty() {
        return None;
    }
    magnitudes.sort_unstable_by(f64::total_cmp);
    let n = magnitudes.len();
    let median = if n % 2 == 1 {
        magnitudes[n / 2]
    } else {
        0.5 * (magnitudes[n / 2 - 1] + magnitudes[n / 2])
    };
    (median > 0.0).then_some(median)
}

/// The default [`FaultThresholds`] scaled to the capture's [`nominal_amplitude`]
/// ([`FaultThresholds::for_amplitude`]); the core's defaults (amplitude 1) when it has none.
/// What the Python API and the command line use when the caller gives no thresholds, so
/// that a capture in raw ADC counts or in volts is monitored without its units being
/// stated.
///
/// ```
/// let (y_c, y_s) = ([1800.0_f32, 0.0, -1800.0], [0.0_f32, 1800.0, 0.0]);
/// let t = angletrack::capture_fault_thresholds(&y_c, &y_s);
/// assert_eq!((t.nominal_amplitude, t.loss_of_signal), (1800.0, 450.0));
/// ```
pub fn capture_fault_thresholds<T: Real>(y_c: &[T], y_s: &[T]) -> FaultThresholds<T> {
    match nominal_amplitude(y_c, y_s) {
        Some(amplitude) => FaultThresholds::for_amplitude(T::from_f64(amplitude)),
        None => FaultThresholds::default(),
    }
}

#[cfg(test)]
mod tests;
