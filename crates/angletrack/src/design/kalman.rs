//! The time-invariant Kalman ATO (`docs/theory.md §4`): the steady-state gain of the
//! Kalman filter of the triple integrator, from the scaled process noise `q` and the
//! measurement noise `r`, or from physical units of the jerk.

use angletrack_core::{Gains, Parameter};
use nalgebra::Matrix3;

use super::{Design, DesignMethod};
use crate::error::{Argument, Error, positive};

/// The steady-state solution of the Kalman design, on the scaled state
/// `(theta, Ts Omega, Ts^2 alpha)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KalmanSolution {
    /// Process noise variance `q` of the scaled jerk `v = Ts^3 beta` (rad^2).
    pub process_noise_q: f64,
    /// Measurement noise variance `r` of each channel (amplitude 1).
    pub measurement_noise_r: f64,
    /// The predicted (a priori) error covariance, solution of the DARE.
    pub predicted_covariance: [[f64; 3]; 3],
    /// The filtered (a posteriori) error covariance `P - P e1 e1^T P / (r + P11)`.
    pub covariance: [[f64; 3]; 3],
}

impl KalmanSolution {
    /// `sqrt(P11)` of the filtered covariance (rad): the smallest RMS angle error any linear
    /// estimator of the model reaches (for the design's own `q` and `r`).
    pub fn angle_floor_rad(&self) -> f64 {
        self.covariance[0][0].sqrt()
    }

    /// `sqrt(P22) / Ts` of the filtered covariance (rad/s): the matching speed floor.
    pub fn speed_floor_rad_s(&self, sample_period_s: f64) -> f64 {
        self.covariance[1][1].sqrt() / sample_period_s
    }
}

/// The time-invariant Kalman ATO (3rd order): the steady-state gain of the Kalman filter of
/// the triple integrator `X[k+1] = A3 X[k] + G v[k]` on the scaled state
/// `(theta, Ts Omega, Ts^2 alpha)`, `G = (1/6, 1/2, 1)`, `var(v) = q` (`v = Ts^3 beta`, the
/// scaled jerk), measured through the phase detector with noise variance `r` per channel.
///
/// The gains and the predicted covariance `P` are the core's
/// [`Gains::kalman_with_covariance`] (the discrete algebraic Riccati equation, doubling
/// algorithm) in `f64`: `K_lin = P e1 / (r + P11)`, depending on `q / r` only. The ratio
/// must lie in `[1e-30, 1e6]`.
///
/// ```
/// use angletrack::kalman;
/// let design = kalman(1e-9, 1.0, 1e-4)?;
/// let [l1, l2, l3] = design.gains.gains();
/// assert!((l1 - 0.0613).abs() < 1e-3 && (l2 - 0.00194).abs() < 1e-5 && (l3 - 3.06e-5).abs() < 1e-7);
/// let floor = design.kalman.unwrap().angle_floor_rad();
/// assert!(floor > 0.0 && floor < 1.0);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn kalman(
    process_noise_q: f64,
    measurement_noise_r: f64,
    sample_period_s: f64,
) -> Result<Design<3>, Error> {
    let q = positive(process_noise_q, Argument::ProcessNoise)?;
    let r = positive(measurement_noise_r, Argument::MeasurementNoise)?;
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    let ratio = q / r;
    if !(1e-30..=1e6).contains(&ratio) {
        return Err(Error::OutOfRange {
            argument: Argument::ProcessNoise,
            expected: "1e-30 <= q / r <= 1e6",
        });
    }
    // The core's solver (one DARE solver for the firmware and the host), in f64; the
    // arguments were checked above, so a refusal naming `q` is the solver's.
    let (gains, predicted) =
        Gains::<f64, 3>::kalman_with_covariance(q, r, ts).map_err(|e| match e.parameter() {
            Parameter::ProcessNoise => Error::NoSolution(Argument::ProcessNoise),
            _ => Error::Gains(e),
        })?;
    let p = Matrix3::from_fn(|i, j| predicted[i][j]);
    let filtered = p - p.column(0) * p.row(0) / (r + p[(0, 0)]);
    Ok(Design {
        method: DesignMethod::Kalman,
        kalman: Some(KalmanSolution {
            process_noise_q: q,
            measurement_noise_r: r,
            predicted_covariance: predicted,
            covariance: core::array::from_fn(|i| core::array::from_fn(|j| filtered[(i, j)])),
        }),
        ..Design::from_gains(gains)
    })
}

/// The Kalman ATO from physical units: the jerk as a white sequence of standard deviation
/// `jerk_std_rad_s3` (rad/s^3, constant over each sample), the sensor noise standard
/// deviation `sensor_noise_std` per channel (amplitude 1), sample period `Ts`:
/// `q = (Ts^3 jerk_std)^2`, `r = sensor_noise_std^2`.
///
/// ```
/// use angletrack::kalman_from_jerk_std;
/// let design = kalman_from_jerk_std(1e5, 0.01, 1e-4)?;
/// let solution = design.kalman.unwrap();
/// assert!((solution.process_noise_q / 1e-14 - 1.0).abs() < 1e-12); // (Ts^3 jerk_std)^2
/// assert!((solution.measurement_noise_r / 1e-4 - 1.0).abs() < 1e-12);
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn kalman_from_jerk_std(
    jerk_std_rad_s3: f64,
    sensor_noise_std: f64,
    sample_period_s: f64,
) -> Result<Design<3>, Error> {
    let jerk = positive(jerk_std_rad_s3, Argument::JerkStd)?;
    let noise = positive(sensor_noise_std, Argument::SensorNoiseStd)?;
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    let scaled = jerk * ts * ts * ts;
    kalman(scaled * scaled, noise * noise, ts).map_err(|e| rename(e, Argument::JerkStd))
}

/// The Kalman ATO from the power spectral density `jerk_density_rad2_s5` (rad^2/s^5) of a
/// continuous white jerk: over one sample it integrates to a jerk of variance `S / Ts`, so
/// `q = S Ts^5`; `r = sensor_noise_std^2` per channel (amplitude 1).
///
/// ```
/// use angletrack::kalman_from_jerk_density;
/// let design = kalman_from_jerk_density(1e6, 0.01, 1e-4)?;
/// assert!((design.kalman.unwrap().process_noise_q / 1e-14 - 1.0).abs() < 1e-12); // S Ts^5
/// # Ok::<(), angletrack::Error>(())
/// ```
pub fn kalman_from_jerk_density(
    jerk_density_rad2_s5: f64,
    sensor_noise_std: f64,
    sample_period_s: f64,
) -> Result<Design<3>, Error> {
    let density = positive(jerk_density_rad2_s5, Argument::JerkDensity)?;
    let noise = positive(sensor_noise_std, Argument::SensorNoiseStd)?;
    let ts = positive(sample_period_s, Argument::SamplePeriod)?;
    kalman(density * ts.powi(5), noise * noise, ts).map_err(|e| rename(e, Argument::JerkDensity))
}

/// Names the caller's arguments instead of `q` and `r` in an error of [`kalman`].
fn rename(e: Error, argument: Argument) -> Error {
    e.renamed(Argument::ProcessNoise, argument)
        .renamed(Argument::MeasurementNoise, Argument::SensorNoiseStd)
}
