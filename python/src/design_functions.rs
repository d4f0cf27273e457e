//! The design functions of the `angletrack` crate, with SI units in every argument name.

use pyo3::prelude::*;

use crate::analysis::{
    DesignReport, PyPredictedError, PyStepResponse, closed_loop_response,
    max_trackable_speed_rad_s, predicted_error, predicted_error_on_kalman_model,
};
use crate::design::{PyDesign, PyKalmanSolution};
use crate::errors::Result;

/// 2nd-order ATO from the tolerated angle error `max_error_rad` at the acceleration
/// `acceleration_rad_s2` and the damping `m` (the paper's time-domain design:
/// `k_b1 = alpha / e_max`, `k_a1 = 2 m sqrt(k_b1)`).
#[pyfunction]
#[pyo3(signature = (max_error_rad, acceleration_rad_s2, damping, sample_period_s, discretisation = "pole_matching"))]
pub fn second_order_from_tracking_error(
    max_error_rad: f64,
    acceleration_rad_s2: f64,
    damping: f64,
    sample_period_s: f64,
    discretisation: &str,
) -> Result<PyDesign> {
    let d = discretisation.parse()?;
    Ok(angletrack::second_order_from_tracking_error(
        max_error_rad,
        acceleration_rad_s2,
        damping,
        sample_period_s,
        d,
    )?
    .into())
}

/// 2nd-order ATO whose sampled loop has exactly the angle error `max_error_rad` at the
/// acceleration `acceleration_rad_s2` and exactly the step-response `overshoot` (fraction,
/// 0.05 for 5 %): the discrete loop is designed directly, so no discretisation shifts it.
#[pyfunction]
#[pyo3(signature = (max_error_rad, acceleration_rad_s2, overshoot, sample_period_s))]
pub fn second_order_from_tracking_error_sampled(
    max_error_rad: f64,
    acceleration_rad_s2: f64,
    overshoot: f64,
    sample_period_s: f64,
) -> Result<PyDesign> {
    Ok(angletrack::second_order_from_tracking_error_sampled(
        max_error_rad,
        acceleration_rad_s2,
        overshoot,
        sample_period_s,
    )?
    .into())
}

/// 2nd-order ATO with the -3 dB bandwidth `bandwidth_hz` of the continuous loop and the
/// damping `m`.
#[pyfunction]
#[pyo3(signature = (bandwidth_hz, damping, sample_period_s, discretisation = "pole_matching"))]
pub fn second_order_from_bandwidth(
    bandwidth_hz: f64,
    damping: f64,
    sample_period_s: f64,
    discretisation: &str,
) -> Result<PyDesign> {
    let d = discretisation.parse()?;
    Ok(angletrack::second_order_from_bandwidth(bandwidth_hz, damping, sample_period_s, d)?.into())
}

/// 2nd-order Butterworth setting (damping `sqrt(2)/2`) with time constant
/// `time_constant_s`: `k_a1 = sqrt(2)/Tc`, `k_b1 = 1/Tc^2`.
#[pyfunction]
#[pyo3(signature = (time_constant_s, sample_period_s, discretisation = "pole_matching"))]
pub fn second_order_butterworth(
    time_constant_s: f64,
    sample_period_s: f64,
    discretisation: &str,
) -> Result<PyDesign> {
    let d = discretisation.parse()?;
    Ok(angletrack::second_order_butterworth(time_constant_s, sample_period_s, d)?.into())
}

/// `omega_3dB / omega_n` of the continuous 2nd-order loop with damping `m`, refused outside
/// the designs' range `0 < m <= 1000`.
#[pyfunction]
#[pyo3(signature = (damping))]
pub fn second_order_bandwidth_ratio(damping: f64) -> Result<f64> {
    if !(damping > 0.0 && damping <= 1000.0) {
        return Err(crate::errors::Error::value(
            "damping",
            format!("expected 0 < damping <= 1000, got {damping}"),
        ));
    }
    Ok(angletrack::second_order_bandwidth_ratio(damping))
}

/// 3rd-order ATO by pole placement: a real pole at `-K/T` and a pair at `(-1 +- j psi)/T`
/// (`pole_ratio` K, `pole_time_constant_s` T, `pole_frequency_ratio` psi).
#[pyfunction]
#[pyo3(signature = (pole_ratio, pole_time_constant_s, pole_frequency_ratio, sample_period_s, discretisation = "pole_matching"))]
pub fn third_order_from_poles(
    pole_ratio: f64,
    pole_time_constant_s: f64,
    pole_frequency_ratio: f64,
    sample_period_s: f64,
    discretisation: &str,
) -> Result<PyDesign> {
    let d = discretisation.parse()?;
    Ok(angletrack::third_order_from_poles(
        pole_ratio,
        pole_time_constant_s,
        pole_frequency_ratio,
        sample_period_s,
        d,
    )?
    .into())
}

/// 3rd-order Butterworth setting with time constant `time_constant_s`:
/// `k_a2 = 2/Tc`, `k_b2 = 2/Tc^2`, `k_c2 = 1/Tc^3`.
#[pyfunction]
#[pyo3(signature = (time_constant_s, sample_period_s, discretisation = "pole_matching"))]
pub fn third_order_butterworth(
    time_constant_s: f64,
    sample_period_s: f64,
    discretisation: &str,
) -> Result<PyDesign> {
    let d = discretisation.parse()?;
    Ok(angletrack::third_order_butterworth(time_constant_s, sample_period_s, d)?.into())
}

/// 3rd-order ATO from a target `overshoot` (fraction, 0.1 for 10 %) and 2 % settling time
/// `settling_time_s`, for the pole family with frequency ratio `pole_frequency_ratio` (psi).
#[pyfunction]
#[pyo3(signature = (overshoot, settling_time_s, pole_frequency_ratio, sample_period_s, discretisation = "pole_matching"))]
pub fn third_order_from_overshoot(
    overshoot: f64,
    settling_time_s: f64,
    pole_frequency_ratio: f64,
    sample_period_s: f64,
    discretisation: &str,
) -> Result<PyDesign> {
    let d = discretisation.parse()?;
    Ok(angletrack::third_order_from_overshoot(
        overshoot,
        settling_time_s,
        pole_frequency_ratio,
        sample_period_s,
        d,
    )?
    .into())
}

/// The time-invariant Kalman ATO (3rd order): steady-state Kalman gain for the process
/// noise variance `process_noise_q` of the scaled jerk `Ts^3 beta` and the measurement
/// noise variance `measurement_noise_r` per channel (discrete algebraic Riccati equation).
#[pyfunction]
#[pyo3(signature = (process_noise_q, measurement_noise_r, sample_period_s))]
pub fn kalman(
    process_noise_q: f64,
    measurement_noise_r: f64,
    sample_period_s: f64,
) -> Result<PyDesign> {
    Ok(angletrack::kalman(process_noise_q, measurement_noise_r, sample_period_s)?.into())
}

/// The Kalman ATO from the jerk's standard deviation `jerk_std_rad_s3` (rad/s^3) and the
/// sensor noise standard deviation `sensor_noise_std` per channel (amplitude 1).
#[pyfunction]
#[pyo3(signature = (jerk_std_rad_s3, sensor_noise_std, sample_period_s))]
pub fn kalman_from_jerk_std(
    jerk_std_rad_s3: f64,
    sensor_noise_std: f64,
    sample_period_s: f64,
) -> Result<PyDesign> {
    Ok(
        angletrack::kalman_from_jerk_std(jerk_std_rad_s3, sensor_noise_std, sample_period_s)?
            .into(),
    )
}

/// The Kalman ATO from the power spectral density `jerk_density_rad2_s5` (rad^2/s^5) of a
/// white jerk and the sensor noise standard deviation `sensor_noise_std` per channel.
#[pyfunction]
#[pyo3(signature = (jerk_density_rad2_s5, sensor_noise_std, sample_period_s))]
pub fn kalman_from_jerk_density(
    jerk_density_rad2_s5: f64,
    sensor_noise_std: f64,
    sample_period_s: f64,
) -> Result<PyDesign> {
    Ok(angletrack::kalman_from_jerk_density(
        jerk_density_rad2_s5,
        sensor_noise_std,
        sample_period_s,
    )?
    .into())
}

/// Adds this module's classes and functions to the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyDesign>()?;
    m.add_class::<DesignReport>()?;
    m.add_class::<PyStepResponse>()?;
    m.add_class::<PyKalmanSolution>()?;
    m.add_class::<PyPredictedError>()?;
    m.add_function(wrap_pyfunction!(predicted_error, m)?)?;
    m.add_function(wrap_pyfunction!(closed_loop_response, m)?)?;
    m.add_function(wrap_pyfunction!(predicted_error_on_kalman_model, m)?)?;
    m.add_function(wrap_pyfunction!(max_trackable_speed_rad_s, m)?)?;
    m.add_function(wrap_pyfunction!(
        second_order_from_tracking_error_sampled,
        m
    )?)?;
    m.add_function(wrap_pyfunction!(second_order_from_tracking_error, m)?)?;
    m.add_function(wrap_pyfunction!(second_order_from_bandwidth, m)?)?;
    m.add_function(wrap_pyfunction!(second_order_butterworth, m)?)?;
    m.add_function(wrap_pyfunction!(second_order_bandwidth_ratio, m)?)?;
    m.add_function(wrap_pyfunction!(third_order_from_poles, m)?)?;
    m.add_function(wrap_pyfunction!(third_order_butterworth, m)?)?;
    m.add_function(wrap_pyfunction!(third_order_from_overshoot, m)?)?;
    m.add_function(wrap_pyfunction!(kalman, m)?)?;
    m.add_function(wrap_pyfunction!(kalman_from_jerk_std, m)?)?;
    m.add_function(wrap_pyfunction!(kalman_from_jerk_density, m)?)?;
    m.add("LARGE_STEP_RAD", angletrack::LARGE_STEP_RAD)?;
    m.add("SETTLING_BAND", angletrack::SETTLING_BAND)?;
    m.add("MAX_POLE_TIMES_PERIOD", angletrack::MAX_POLE_TIMES_PERIOD)?;
    Ok(())
}
