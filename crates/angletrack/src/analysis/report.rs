//! The design's "datasheet": everything the analysis predicts about a gain set.

use angletrack_core::{FaultThresholds, Gains};
use nalgebra::Complex;

use super::discrete_loop::{DiscreteLoop, loop_poles};
use super::noise::predicted_error;
use super::speed::{acquisition_speed, max_trackable_speed_rad_s, simulate_nonlinear};
use super::step::{LARGE_STEP_RAD, SETTLING_BAND, StepResponse, continuous_step};
use crate::design::{Design, DesignMethod, Discretisation};
use crate::error::{Argument, Error, non_negative};
use crate::linalg;

/// Everything the analysis predicts about a gain set, in physical units.
///
/// Built by [`DesignReport::new`]; `Display` renders it as a table. All fields are public and
/// plain (`f64`, `Vec`, `Option`) for the Python bindings.
///
/// The linearised loop: for small errors the phase detector gives `eps = theta - x1_p + w`
/// (input amplitude 1), where `w = w_s cos x1_p - w_c sin x1_p` has variance
/// `r = sensor_noise_std^2` whatever the angle. The filtered estimate then follows
/// `x_e[k] = F x_e[k-1] + L theta[k]` with `F = (I - L e1^T) A`.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignReport {
    /// The design rule.
    pub method: DesignMethod,
    /// The mapping of a continuous design.
    pub discretisation: Option<Discretisation>,
    /// Loop order (2 or 3).
    pub order: usize,
    /// Sample period (s).
    pub sample_period_s: f64,
    /// The discrete gains `(l1, l2[, l3])`.
    pub gains: Vec<f64>,
    /// Poles `z_i` of the discrete loop `(I - L e1^T) A`.
    pub discrete_poles: Vec<Complex<f64>>,
    /// Their continuous equivalents `ln(z_i) / Ts` (rad/s).
    pub continuous_equivalent_poles: Vec<Complex<f64>>,
    /// The continuous design's poles (rad/s); empty for Kalman and given gains.
    pub design_poles: Vec<Complex<f64>>,
    /// Largest relative distance `|ln(z_i)/Ts - s_i| / |s_i|` between the continuous
    /// equivalent and the design's poles: 0 for pole matching, the mapping's error otherwise.
    pub pole_shift: Option<f64>,
    /// -3 dB bandwidth (Hz) of the closed-loop angle transfer function
    /// `X1_e(z) / Theta(z)`: the lowest frequency where its gain falls below `1/sqrt(2)`;
    /// `None` if it stays above up to the Nyquist frequency.
    pub bandwidth_hz: Option<f64>,
    /// Order 2: the discrete acceleration constant `Ka = l2 / ((1 - l1) Ts^2)` (1/s^2); the
    /// steady-state angle error under constant acceleration `alpha` is `alpha / Ka`.
    pub acceleration_constant_per_s2: Option<f64>,
    /// Order 2: the continuous `k_b1` of a continuous design; for a design without a
    /// continuous loop (given, sampled or Kalman gains), the product of the
    /// continuous-equivalent poles (1/s^2).
    pub continuous_acceleration_constant_per_s2: Option<f64>,
    /// Order 3: steady-state angle error (rad) per unit constant jerk (rad/s^3) of the
    /// discrete loop (s^3).
    pub error_per_unit_jerk_s3: Option<f64>,
    /// Order 3: `1 / k_c2` of the continuous design (or the continuous equivalent) (s^3).
    pub continuous_error_per_unit_jerk_s3: Option<f64>,
    /// The sensor noise standard deviation per channel the noise figures are for
    /// (amplitude 1).
    pub sensor_noise_std: f64,
    /// Predicted steady-state RMS angle error (rad) from the sensor noise `sensor_noise_std`
    /// alone, no process noise: a shaft whose motion the loop follows without steady error
    /// (constant speed; constant acceleration too at order 3). Discrete Lyapunov equation of
    /// the linearised loop (`docs/theory.md §8`). The figure to compare observers on for
    /// sensor noise.
    pub angle_error_rms_rad: f64,
    /// Predicted steady-state RMS speed error (rad/s), on the assumptions of
    /// `angle_error_rms_rad`.
    pub speed_error_rms_rad_s: f64,
    /// Kalman design: `sqrt(P11)` of the filtered covariance (rad,
    /// [`KalmanSolution::angle_floor_rad`](crate::KalmanSolution::angle_floor_rad)), the RMS
    /// angle error on the design's own model: its own measurement noise `r` AND a random jerk
    /// of its own variance `q`, whatever `sensor_noise_std` the report is for. It includes
    /// the random jerk, so it exceeds `angle_error_rms_rad` (sensor noise alone) for the same
    /// `r`. It is the smallest RMS angle error any linear observer reaches on that model;
    /// other observers compare with it through
    /// [`predicted_error_on_kalman_model`](crate::predicted_error_on_kalman_model).
    pub kalman_angle_floor_rad: Option<f64>,
    /// Kalman design: `sqrt(P22) / Ts` of the filtered covariance (rad/s), on the
    /// assumptions of `kalman_angle_floor_rad`.
    pub kalman_speed_floor_rad_s: Option<f64>,
    /// Small-signal (linear) step response of the discrete loop.
    pub linear_step: StepResponse,
    /// Step response of the continuous design, for comparison with `linear_step`.
    pub continuous_step: Option<StepResponse>,
    /// Response of the bare nonlinear loop of the paper (the core's observer, `f64`, exact
    /// sin/cos, diagnostics and re-acquisition disabled) to a [`LARGE_STEP_RAD`]
    /// (179 degree) step from rest.
    pub large_step: StepResponse,
    /// The angle (rad, unwrapped) the bare nonlinear loop ends at after the 179 degree step.
    pub large_step_final_rad: f64,
    /// The same step with the gains' own diagnostics (by default the core's false-lock
    /// detection, which re-acquires the angle from `atan2` once the filtered in-phase
    /// component turns negative): what the firmware does.
    pub large_step_with_diagnostics: StepResponse,
    /// The largest speed (rad/s) the observer tracks: the Nyquist speed `pi / Ts`, half a
    /// turn per sample ([`max_trackable_speed_rad_s`](crate::max_trackable_speed_rad_s),
    /// `docs/theory.md §9`).
    pub max_speed_rad_s: f64,
    /// The largest speed step (rad/s) the bare nonlinear loop acquires from rest (estimate
    /// at the right angle, speed 0) without slipping a cycle: found by bisection on a
    /// logarithmic scale between `1e-6` and 1 times `max_speed_rad_s`, assuming acquisition
    /// fails above a single threshold.
    pub acquisition_speed_rad_s: f64,
}

/// Pairs each design pole with the nearest continuous-equivalent pole and returns the
/// largest relative distance.
fn pole_shift(design: &[Complex<f64>], equivalent: &[Complex<f64>]) -> Option<f64> {
    if design.is_empty() {
        return None;
    }
    let shift = design
        .iter()
        .map(|s| {
            equivalent
                .iter()
                .map(|e| (e - s).norm() / s.norm())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    Some(shift)
}

impl DesignReport {
    /// Analyses a design for white sensor noise of standard deviation `sensor_noise_std` per
    /// channel (amplitude 1; 0 for a noise-free analysis).
    ///
    /// The step responses and the acquisition search simulate the loop (up to a few million
    /// samples for loops much slower than their sample rate).
    ///
    /// ```
    /// use angletrack::{DesignReport, Discretisation, second_order_from_tracking_error};
    /// let design = second_order_from_tracking_error(
    ///     1e-3, 1e3, 2f64.sqrt() / 2.0, 1e-5, Discretisation::PoleMatching)?;
    /// let report = DesignReport::new(&design, 0.01)?;
    /// assert!((report.linear_step.overshoot - 0.208).abs() < 0.003);
    /// assert!((report.acceleration_constant_per_s2.unwrap() / 1e6 - 1.0).abs() < 0.01);
    /// println!("{report}");
    /// # Ok::<(), angletrack::Error>(())
    /// ```
    pub fn new<const N: usize>(design: &Design<N>, sensor_noise_std: f64) -> Result<Self, Error> {
        let sigma = non_negative(sensor_noise_std, Argument::SensorNoiseStd)?;
        let gains = design.gains;
        let ts = gains.sample_period();
        let max_speed_rad_s = max_trackable_speed_rad_s(ts)?;
        let l = gains.gains();
        let discrete = DiscreteLoop::new(&l, ts);
        let bare = gains.with_fault_thresholds(FaultThresholds::disabled())?;
        let (shifted, equivalent) = loop_poles(&gains);
        let discrete_poles: Vec<Complex<f64>> = shifted.iter().map(|u| u + 1.0).collect();
        let continuous_c = design
            .continuous_loop_polynomial()
            .unwrap_or_else(|| linalg::monic_from_roots(&equivalent));
        let per_unit = discrete
            .error_per_unit_derivative()
            .ok_or(Error::NoSolution(Argument::SamplePeriod))?;
        let noise = predicted_error(&gains, sigma, 0.0)?;
        let samples = discrete.horizon(&equivalent);
        let large_step = |gains: &Gains<f64, N>| {
            let mut last = 0.0;
            let step = StepResponse::from_samples(
                simulate_nonlinear(gains, samples, |_| LARGE_STEP_RAD).inspect(|&y| last = y),
                0.0,
                LARGE_STEP_RAD,
                SETTLING_BAND,
                ts,
            );
            (step, last)
        };
        let (bare_step, large_step_final_rad) = large_step(&bare);
        Ok(DesignReport {
            method: design.method,
            discretisation: design.discretisation,
            order: N,
            sample_period_s: ts,
            gains: l.to_vec(),
            discrete_poles,
            pole_shift: pole_shift(&design.continuous_poles, &equivalent),
            continuous_equivalent_poles: equivalent,
            design_poles: design.continuous_poles.clone(),
            bandwidth_hz: discrete.bandwidth_hz(),
            acceleration_constant_per_s2: (N == 2).then(|| 1.0 / per_unit),
            continuous_acceleration_constant_per_s2: (N == 2).then(|| continuous_c[0]),
            error_per_unit_jerk_s3: (N == 3).then_some(per_unit),
            continuous_error_per_unit_jerk_s3: (N == 3).then(|| 1.0 / continuous_c[0]),
            sensor_noise_std: sigma,
            angle_error_rms_rad: noise.angle_rms_rad,
            speed_error_rms_rad_s: noise.speed_rms_rad_s,
            kalman_angle_floor_rad: design.kalman.map(|k| k.angle_floor_rad()),
            kalman_speed_floor_rad_s: design.kalman.map(|k| k.speed_floor_rad_s(ts)),
            linear_step: discrete.linear_step(samples),
            continuous_step: design
                .continuous_loop_polynomial()
                .map(|c| continuous_step(&c)),
            large_step: bare_step,
            large_step_final_rad,
            large_step_with_diagnostics: large_step(&gains).0,
            max_speed_rad_s,
            acquisition_speed_rad_s: acquisition_speed(&bare, samples, max_speed_rad_s),
        })
    }
}
