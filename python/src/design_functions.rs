//! The design functions of the `angletrack` crate, with SI units in every argument name.

use pyo3::prelude::*;

use crate::design::PyDesign;
use crate::errors::Result;

/// A design function of the crate as a Python function of the same name and arguments (each
/// a float, in the unit its name says), the discretisation given by name where it takes one.
macro_rules! designs {
    ($($(#[$doc:meta])* $name:ident($($arg:ident),* $(; $discretisation:ident)?);)*) => {
    $(
        $(#[$doc])*
        #[pyfunction]
        #[pyo3(signature = ($($arg,)* $($discretisation = "pole_matching")?))]
        pub fn $name($($arg: f64,)* $($discretisation: &str)?) -> Result<PyDesign> {
            Ok(angletrack::$name($($arg,)* $($discretisation.parse()?)?)?.into())
        }
    )*
    };
}

designs! {
    /// 2nd-order ATO from the tolerated angle error `max_error_rad` at the acceleration
    /// `acceleration_rad_s2` and the damping `m` (the paper's time-domain design:
    /// `k_b1 = alpha / e_max`, `k_a1 = 2 m sqrt(k_b1)`).
    second_order_from_tracking_error(
        max_error_rad, acceleration_rad_s2, damping, sample_period_s; discretisation);
    /// 2nd-order ATO whose sampled loop has exactly the angle error `max_error_rad` at the
    /// acceleration `acceleration_rad_s2` and exactly the step-response `overshoot` (fraction,
    /// 0.05 for 5 %): the discrete loop is designed directly, so no discretisation shifts it.
    second_order_from_tracking_error_sampled(
        max_error_rad, acceleration_rad_s2, overshoot, sample_period_s);
    /// 2nd-order ATO with the -3 dB bandwidth `bandwidth_hz` of the continuous loop and the
    /// damping `m`.
    second_order_from_bandwidth(bandwidth_hz, damping, sample_period_s; discretisation);
    /// 2nd-order Butterworth setting (damping `sqrt(2)/2`) with time constant
    /// `time_constant_s`: `k_a1 = sqrt(2)/Tc`, `k_b1 = 1/Tc^2`.
    second_order_butterworth(time_constant_s, sample_period_s; discretisation);
    /// 3rd-order ATO by pole placement: a real pole at `-K/T` and a pair at `(-1 +- j psi)/T`
    /// (`pole_ratio` K, `pole_time_constant_s` T, `pole_frequency_ratio` psi).
    third_order_from_poles(
        pole_ratio, pole_time_constant_s, pole_frequency_ratio, sample_period_s; discretisation);
    /// 3rd-order Butterworth setting with time constant `time_constant_s`:
    /// `k_a2 = 2/Tc`, `k_b2 = 2/Tc^2`, `k_c2 = 1/Tc^3`.
    third_order_butterworth(time_constant_s, sample_period_s; discretisation);
    /// 3rd-order ATO from a target `overshoot` (fraction, 0.1 for 10 %) and 2 % settling time
    /// `settling_time_s`, for the pole family with frequency ratio `pole_frequency_ratio` (psi).
    third_order_from_overshoot(
        overshoot, settling_time_s, pole_frequency_ratio, sample_period_s; discretisation);
    /// The time-invariant Kalman ATO (3rd order): steady-state Kalman gain for the process
    /// noise variance `process_noise_q` of the scaled jerk `Ts^3 beta` and the measurement
    /// noise variance `measurement_noise_r` per channel (discrete algebraic Riccati equation).
    kalman(process_noise_q, measurement_noise_r, sample_period_s);
    /// The Kalman ATO from the jerk's standard deviation `jerk_std_rad_s3` (rad/s^3) and the
    /// sensor noise standard deviation `sensor_noise_std` per channel (amplitude 1).
    kalman_from_jerk_std(jerk_std_rad_s3, sensor_noise_std, sample_period_s);
    /// The Kalman ATO from the power spectral density `jerk_density_rad2_s5` (rad^2/s^5) of a
    /// white jerk and the sensor noise standard deviation `sensor_noise_std` per channel.
    kalman_from_jerk_density(jerk_density_rad2_s5, sensor_noise_std, sample_period_s);
}

/// `omega_3dB / omega_n` of the continuous 2nd-order loop with damping `m`, refused outside
/// the designs' range `0 < m <= 1000`.
#[pyfunction]
#[pyo3(signature = (damping))]
pub fn second_order_bandwidth_ratio(damping: f64) -> Result<f64> {
    Ok(angletrack::second_order_bandwidth_ratio(damping)?)
}
