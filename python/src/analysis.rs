//! The analysis of a gain set: `DesignReport` (the design's datasheet), `StepResponse`,
//! `predicted_error` (the noise prediction of the linearised loop) and
//! `closed_loop_response` (its frequency response).

use numpy::{Complex64, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyList;

use crate::design::complex_list;
use crate::errors::Result;
use crate::gains::{PyGains, with_gains};
use crate::getters::result_class;

result_class! {
    /// Overshoot and 2 % settling time of a step response.
    #[derive(Clone)]
    PyStepResponse = "StepResponse" of |py, s: angletrack::StepResponse| {
        /// Overshoot, as a fraction of the step (0.1 for 10 %).
        overshoot: f64 = s.overshoot,
        /// 2 % settling time (s).
        settling_time_s: f64 = s.settling_time_s,
    }
    repr |s| format!(
        "StepResponse(overshoot={:.4} ({:.2} %), settling_time_s={:.6e})",
        s.overshoot,
        100.0 * s.overshoot,
        s.settling_time_s
    );
}

result_class! {
    /// Everything the analysis predicts about a gain set, in physical units (the design's
    /// datasheet). `repr()` and `str()` render it as a table.
    DesignReport = "DesignReport" of |py, r: angletrack::DesignReport| {
        /// The design rule, in words.
        method: &'static str = r.method.name(),
        /// The mapping of a continuous design, or `None`.
        discretisation: Option<&'static str> = r.discretisation.map(|d| d.id()),
        /// Loop order (2 or 3).
        order: usize = r.order,
        /// Sample period (s).
        sample_period_s: f64 = r.sample_period_s,
        /// The discrete gains.
        gains: Vec<f64> = r.gains,
        /// Poles `z_i` of the discrete loop.
        discrete_poles: Py<PyList> = complex_list(py, &r.discrete_poles)?,
        /// Their continuous equivalents `ln(z_i) / Ts` (rad/s).
        continuous_equivalent_poles: Py<PyList> = complex_list(py, &r.continuous_equivalent_poles)?,
        /// The continuous design's poles (rad/s); empty for Kalman and given gains.
        design_poles: Py<PyList> = complex_list(py, &r.design_poles)?,
        /// Largest relative pole shift of the discretisation, or `None`.
        pole_shift: Option<f64> = r.pole_shift,
        /// -3 dB bandwidth (Hz) of the closed-loop angle transfer function, or `None`.
        bandwidth_hz: Option<f64> = r.bandwidth_hz,
        /// Order 2: discrete acceleration constant Ka (1/s^2).
        acceleration_constant_per_s2: Option<f64> = r.acceleration_constant_per_s2,
        /// Order 2: continuous acceleration constant `k_b1` (1/s^2).
        continuous_acceleration_constant_per_s2: Option<f64> = r.continuous_acceleration_constant_per_s2,
        /// Order 3: steady-state angle error per unit jerk (s^3).
        error_per_unit_jerk_s3: Option<f64> = r.error_per_unit_jerk_s3,
        /// Order 3: `1 / k_c2` of the continuous design (s^3).
        continuous_error_per_unit_jerk_s3: Option<f64> = r.continuous_error_per_unit_jerk_s3,
        /// The sensor noise standard deviation the noise figures are for.
        sensor_noise_std: f64 = r.sensor_noise_std,
        /// Predicted steady-state RMS angle error (rad) from the sensor noise alone (the shaft
        /// at constant speed), the same assumption for every design.
        angle_error_rms_rad: f64 = r.angle_error_rms_rad,
        /// Predicted steady-state RMS speed error (rad/s) from the sensor noise alone.
        speed_error_rms_rad_s: f64 = r.speed_error_rms_rad_s,
        /// Kalman design: `sqrt(P11)` (rad), the RMS angle error on the design's own model
        /// (its `q` and `r`, random jerk included): the smallest any linear observer reaches
        /// there, so larger than `angle_error_rms_rad` (sensor noise alone).
        kalman_angle_floor_rad: Option<f64> = r.kalman_angle_floor_rad,
        /// Kalman design: `sqrt(P22) / Ts` (rad/s), on the model of `kalman_angle_floor_rad`.
        kalman_speed_floor_rad_s: Option<f64> = r.kalman_speed_floor_rad_s,
        /// Small-signal (linear) step response of the discrete loop.
        linear_step: PyStepResponse = PyStepResponse::of(py, r.linear_step)?,
        /// Step response of the continuous design, or `None`.
        continuous_step: Option<PyStepResponse> =
            r.continuous_step.map(|s| PyStepResponse::of(py, s)).transpose()?,
        /// Response of the bare nonlinear loop (no diagnostics) to a 179 degree step from rest.
        large_step: PyStepResponse = PyStepResponse::of(py, r.large_step)?,
        /// The 179 degree step with the core's default diagnostics (false-lock detection
        /// re-acquires the angle).
        large_step_with_diagnostics: PyStepResponse =
            PyStepResponse::of(py, r.large_step_with_diagnostics)?,
        /// Where the nonlinear loop ends after the 179 degree step (rad).
        large_step_final_rad: f64 = r.large_step_final_rad,
        /// The largest trackable speed, `pi / Ts` (rad/s, `docs/theory.md §9`).
        max_speed_rad_s: f64 = r.max_speed_rad_s,
        /// The largest speed step (rad/s) the loop acquires from rest without slipping a cycle.
        acquisition_speed_rad_s: f64 = r.acquisition_speed_rad_s,
    }
    private {
        /// The table `str()` shows.
        table: String = r.to_string(),
    }
    repr |r| format!("DesignReport:\n{}", r.table);
    methods {
        fn __str__(&self) -> String {
            self.table.clone()
        }
    }
}

result_class! {
    /// Predicted RMS errors of the linearised loop.
    PyPredictedError = "PredictedError" of |py, p: angletrack::PredictedError| {
        /// RMS angle error (rad).
        angle_rms_rad: f64 = p.angle_rms_rad,
        /// RMS speed error (rad/s).
        speed_rms_rad_s: f64 = p.speed_rms_rad_s,
    }
    repr |p| format!(
        "PredictedError(angle_rms_rad={:.6e}, speed_rms_rad_s={:.6e})",
        p.angle_rms_rad, p.speed_rms_rad_s
    );
}

/// Steady-state RMS angle and speed errors of the linearised loop with `gains`, driven by
/// white sensor noise of standard deviation `sensor_noise_std` per channel and a white
/// N-th derivative of the angle of scaled variance `process_noise_q` (discrete Lyapunov
/// equation).
#[pyfunction]
#[pyo3(signature = (gains, sensor_noise_std, process_noise_q = 0.0))]
pub fn predicted_error(
    py: Python<'_>,
    gains: PyGains,
    sensor_noise_std: f64,
    process_noise_q: f64,
) -> Result<PyPredictedError> {
    let p = with_gains!(&gains.set, g => angletrack::predicted_error(g, sensor_noise_std, process_noise_q))?;
    PyPredictedError::of(py, p)
}

/// Steady-state RMS angle and speed errors of the loop with `gains` on the Kalman ATO's
/// model: white sensor noise `sensor_noise_std` per channel and a random jerk of scaled
/// variance `process_noise_q` (a Kalman design's own `q`). `None` for a 2nd-order loop with
/// `process_noise_q > 0`: a random jerk makes the acceleration a random walk, which a type-2
/// loop does not follow to a steady state.
#[pyfunction]
#[pyo3(signature = (gains, sensor_noise_std, process_noise_q))]
pub fn predicted_error_on_kalman_model(
    py: Python<'_>,
    gains: PyGains,
    sensor_noise_std: f64,
    process_noise_q: f64,
) -> Result<Option<PyPredictedError>> {
    let p = with_gains!(&gains.set, g => angletrack::predicted_error_on_kalman_model(
        g,
        sensor_noise_std,
        process_noise_q
    ))?;
    p.map(|p| PyPredictedError::of(py, p)).transpose()
}

/// The largest speed (rad/s) an observer sampled every `sample_period_s` tracks: `pi / Ts`,
/// half a turn per sample (`docs/theory.md §9`); a period that is not finite and positive
/// is refused.
#[pyfunction]
#[pyo3(signature = (sample_period_s))]
pub fn max_trackable_speed_rad_s(sample_period_s: f64) -> Result<f64> {
    Ok(angletrack::max_trackable_speed_rad_s(sample_period_s)?)
}

/// The closed-loop angle transfer `H(z) = X1_e / Theta` of the linearised discrete loop of
/// `gains` at `z = exp(j 2 pi f Ts)` for each frequency `f` of `frequencies_hz` (Hz, finite,
/// at least 0), as a complex128 array (`docs/theory.md §5`): `H = 1` at 0 Hz, `|H|` falls
/// through `1/sqrt(2)` at the design report's `bandwidth_hz`.
#[pyfunction]
#[pyo3(signature = (gains, frequencies_hz))]
pub fn closed_loop_response<'py>(
    py: Python<'py>,
    gains: PyGains,
    frequencies_hz: Vec<f64>,
) -> Result<Bound<'py, PyArray1<Complex64>>> {
    let h = with_gains!(&gains.set, g => angletrack::closed_loop_response(g, &frequencies_hz))?;
    let h: Vec<Complex64> = h.into_iter().map(|c| Complex64::new(c.re, c.im)).collect();
    Ok(PyArray1::from_vec(py, h))
}
