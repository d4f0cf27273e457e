//! Noise prediction (`docs/theory.md §8`): the steady-state error covariance of the
//! linearised loop, from the discrete Lyapunov equation.

use angletrack_core::Gains;

use super::discrete_loop::DiscreteLoop;
use crate::error::{Argument, Error, non_negative};

/// The RMS angle (rad) and speed (rad/s) error of a gain set, predicted by the discrete
/// Lyapunov equation of the linearised loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictedError {
    /// RMS angle error (rad).
    pub angle_rms_rad: f64,
    /// RMS speed error (rad/s).
    pub speed_rms_rad_s: f64,
}

/// The steady-state RMS errors of the linearised loop driven by white sensor noise of
/// standard deviation `sensor_noise_std` per channel (amplitude 1: the phase detector's
/// noise has variance `r = sensor_noise_std^2`) and, through `process_noise_q`, by a white
/// `N`-th derivative of the angle (acceleration at order 2, jerk at order 3) whose value
/// times `Ts^N` has variance `q` per sample (the Kalman model; 0 for a shaft at constant
/// speed).
///
/// Solves `S = F S F^T + r L L^T + q (I - L e1^T) G G^T (I - L e1^T)^T` with
/// `F = (I - L e1^T) A`. For a Kalman design and its own `q` and `r` this is the filtered
/// covariance of the Riccati solution.
///
/// ```
/// use angletrack::{kalman, predicted_error};
/// let design = kalman(1e-12, 1e-4, 1e-4)?;
/// let predicted = predicted_error(&design.gains, 1e-2, 1e-12)?;
/// let floor = design.kalman.unwrap().angle_floor_rad();
/// assert!((predicted.angle_rms_rad / floor - 1.0).abs() < 1e-6);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn predicted_error<const N: usize>(
    gains: &Gains<f64, N>,
    sensor_noise_std: f64,
    process_noise_q: f64,
) -> Result<PredictedError, Error> {
    let sigma = non_negative(sensor_noise_std, Argument::SensorNoiseStd)?;
    let q = non_negative(process_noise_q, Argument::ProcessNoise)?;
    let ts = gains.sample_period();
    let s = DiscreteLoop::new(&gains.gains(), ts)
        .error_covariance(sigma * sigma, q)
        .ok_or(Error::NoSolution(Argument::SensorNoiseStd))?;
    Ok(PredictedError {
        angle_rms_rad: s[(0, 0)].max(0.0).sqrt(),
        speed_rms_rad_s: s[(1, 1)].max(0.0).sqrt() / ts,
    })
}

/// The steady-state RMS errors of an observer of either order on the Kalman ATO's model
/// (`docs/theory.md §4`): white sensor noise of standard deviation `sensor_noise_std` per
/// channel and a white jerk whose value times `Ts^3` has variance `jerk_process_noise_q`
/// per sample ([`KalmanSolution::process_noise_q`](crate::KalmanSolution::process_noise_q)).
/// The figure on which observers compare with the Kalman ATO's own
/// [`KalmanSolution::angle_floor_rad`](crate::KalmanSolution::angle_floor_rad), which no
/// linear observer beats on that model.
///
/// `None` for a 2nd-order observer with `jerk_process_noise_q > 0`: the random jerk makes
/// the acceleration a random walk, and a loop with a steady error under constant
/// acceleration has no steady state under it (its error grows without bound). With
/// `jerk_process_noise_q = 0` this is [`predicted_error`] without process noise.
///
/// ```
/// use angletrack::{kalman, predicted_error_on_kalman_model, second_order_butterworth, Discretisation};
/// let optimal = kalman(1e-12, 1e-4, 1e-4)?;
/// let q = optimal.kalman.unwrap().process_noise_q;
/// let floor = optimal.kalman.unwrap().angle_floor_rad();
/// let own = predicted_error_on_kalman_model(&optimal.gains, 1e-2, q)?.unwrap();
/// assert!((own.angle_rms_rad / floor - 1.0).abs() < 1e-6);
/// let second = second_order_butterworth(1e-2, 1e-4, Discretisation::PoleMatching)?;
/// assert_eq!(predicted_error_on_kalman_model(&second.gains, 1e-2, q)?, None);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn predicted_error_on_kalman_model<const N: usize>(
    gains: &Gains<f64, N>,
    sensor_noise_std: f64,
    jerk_process_noise_q: f64,
) -> Result<Option<PredictedError>, Error> {
    let q = non_negative(jerk_process_noise_q, Argument::ProcessNoise)?;
    if N == 2 && q > 0.0 {
        non_negative(sensor_noise_std, Argument::SensorNoiseStd)?;
        return Ok(None);
    }
    predicted_error(gains, sensor_noise_std, q).map(Some)
}
