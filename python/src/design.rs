//! The design functions of the `angletrack` crate, its `Design` value and its analysis
//! (`DesignReport`, `predicted_error`), with SI units in every argument name.

use angletrack::core::{Order, SupportedOrder};
use angletrack::{Complex, Design, Discretisation, KalmanSolution};
use pyo3::prelude::*;
use pyo3::types::PyComplex;

use crate::errors::{Error, Result};
use crate::observer::{GainSet, PyGains};

/// A design of either order.
#[derive(Debug, Clone)]
enum AnyDesign {
    Second(Design<2>),
    Third(Design<3>),
}

/// Runs `$body` with `$d` bound to the concrete `Design<N>` inside `$any`.
macro_rules! with_design {
    ($any:expr, $d:ident => $body:expr) => {
        match $any {
            AnyDesign::Second($d) => $body,
            AnyDesign::Third($d) => $body,
        }
    };
}

fn discretisation(name: &str) -> Result<Discretisation> {
    match name {
        "pole_matching" => Ok(Discretisation::PoleMatching),
        "forward_euler" => Ok(Discretisation::ForwardEuler),
        "tustin" => Ok(Discretisation::Tustin),
        other => Err(Error::value(
            "discretisation",
            format!("expected 'pole_matching', 'forward_euler' or 'tustin', got {other:?}"),
        )),
    }
}

fn discretisation_name(d: Discretisation) -> &'static str {
    match d {
        Discretisation::PoleMatching => "pole_matching",
        Discretisation::ForwardEuler => "forward_euler",
        Discretisation::Tustin => "tustin",
    }
}

fn complex_list<'py>(py: Python<'py>, values: &[Complex<f64>]) -> Vec<Bound<'py, PyComplex>> {
    values
        .iter()
        .map(|z| PyComplex::from_doubles(py, z.re, z.im))
        .collect()
}

/// The steady-state solution of a Kalman design on the scaled state
/// `(theta, Ts*Omega, Ts^2*alpha)`.
#[pyclass(name = "KalmanSolution", module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct PyKalmanSolution {
    /// Process noise variance `q` of the scaled jerk `Ts^3 beta` (rad^2).
    process_noise_q: f64,
    /// Measurement noise variance `r` of each channel (amplitude 1).
    measurement_noise_r: f64,
    /// Predicted (a priori) error covariance, the solution of the Riccati equation (3x3).
    predicted_covariance: [[f64; 3]; 3],
    /// Filtered (a posteriori) error covariance (3x3).
    covariance: [[f64; 3]; 3],
    /// `sqrt(P11)` (rad): the smallest RMS angle error of any linear estimator of the model.
    angle_floor_rad: f64,
    /// `sqrt(P22) / Ts` (rad/s).
    speed_floor_rad_s: f64,
}

impl PyKalmanSolution {
    fn new(k: &KalmanSolution, sample_period_s: f64) -> Self {
        Self {
            process_noise_q: k.process_noise_q,
            measurement_noise_r: k.measurement_noise_r,
            predicted_covariance: k.predicted_covariance,
            covariance: k.covariance,
            angle_floor_rad: k.angle_floor_rad(),
            speed_floor_rad_s: k.speed_floor_rad_s(sample_period_s),
        }
    }
}

#[pymethods]
impl PyKalmanSolution {
    fn __repr__(&self) -> String {
        format!(
            "KalmanSolution(process_noise_q={:e}, measurement_noise_r={:e}, angle_floor_rad={:.6e}, \
             speed_floor_rad_s={:.6e})",
            self.process_noise_q,
            self.measurement_noise_r,
            self.angle_floor_rad,
            self.speed_floor_rad_s
        )
    }
}

/// A designed gain set (float64) with what it was designed from. Analyse it with
/// `report()`; run it with `Observer(design.gains, dtype=...)`.
#[pyclass(name = "Design", module = "angletrack", frozen)]
#[derive(Debug, Clone)]
pub struct PyDesign {
    inner: AnyDesign,
}

impl PyDesign {
    fn gain_set(&self) -> GainSet {
        match &self.inner {
            AnyDesign::Second(d) => GainSet::Second(d.gains),
            AnyDesign::Third(d) => GainSet::Third(d.gains),
        }
    }
}

impl From<Design<2>> for PyDesign {
    fn from(d: Design<2>) -> Self {
        Self {
            inner: AnyDesign::Second(d),
        }
    }
}

impl From<Design<3>> for PyDesign {
    fn from(d: Design<3>) -> Self {
        Self {
            inner: AnyDesign::Third(d),
        }
    }
}

#[pymethods]
impl PyDesign {
    /// Wraps gains designed elsewhere, to analyse them.
    #[staticmethod]
    #[pyo3(signature = (gains))]
    fn from_gains(gains: PyGains) -> Self {
        match gains.set {
            GainSet::Second(g) => Design::from_gains(g).into(),
            GainSet::Third(g) => Design::from_gains(g).into(),
        }
    }

    /// The designed discrete gains (float64, checked).
    #[getter]
    fn gains(&self) -> PyGains {
        PyGains {
            set: self.gain_set(),
        }
    }

    /// The design rule, in words.
    #[getter]
    fn method(&self) -> &'static str {
        with_design!(&self.inner, d => d.method.name())
    }

    /// The mapping of a continuous design ('pole_matching', 'forward_euler', 'tustin');
    /// `None` for Kalman and given gains.
    #[getter]
    fn discretisation(&self) -> Option<&'static str> {
        with_design!(&self.inner, d => d.discretisation.map(discretisation_name))
    }

    /// The continuous closed-loop poles (rad/s) of a continuous design; empty otherwise.
    #[getter]
    fn continuous_poles<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyComplex>> {
        with_design!(&self.inner, d => complex_list(py, &d.continuous_poles))
    }

    /// The continuous gains `(k_a, k_b[, k_c])` (1/s, 1/s^2, 1/s^3) of a continuous design.
    #[getter]
    fn continuous_gains(&self) -> Option<Vec<f64>> {
        with_design!(&self.inner, d => d.continuous_gains.map(|k| k.to_vec()))
    }

    /// The Riccati solution of a Kalman design; `None` otherwise.
    #[getter]
    fn kalman(&self) -> Option<PyKalmanSolution> {
        with_design!(&self.inner, d => d.kalman.as_ref().map(|k| PyKalmanSolution::new(k, d.sample_period())))
    }

    /// The sample period (s).
    #[getter]
    fn sample_period_s(&self) -> f64 {
        with_design!(&self.inner, d => d.sample_period())
    }

    /// The observer order (2 or 3).
    #[getter]
    fn order(&self) -> usize {
        self.gain_set().order()
    }

    /// The design's datasheet for white sensor noise of standard deviation
    /// `sensor_noise_std` per channel (amplitude 1; 0 for a noise-free analysis).
    #[pyo3(signature = (sensor_noise_std = 0.0))]
    fn report(&self, py: Python<'_>, sensor_noise_std: f64) -> Result<DesignReport> {
        let inner = self.inner.clone();
        let report = py.detach(
            move || with_design!(&inner, d => angletrack::DesignReport::new(d, sensor_noise_std)),
        )?;
        Ok(DesignReport { inner: report })
    }

    fn __repr__(&self) -> String {
        with_design!(&self.inner, d => format!(
            "Design(method={:?}, discretisation={}, order={}, sample_period_s={:e}, gains={:?})",
            d.method.name(),
            d.discretisation.map_or("None".to_string(), |x| format!("{:?}", discretisation_name(x))),
            d.gains.order(),
            d.sample_period(),
            d.gains.gains()
        ))
    }
}

/// Overshoot and 2 % settling time of a step response.
#[pyclass(name = "StepResponse", module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct PyStepResponse {
    /// Overshoot, as a fraction of the step (0.1 for 10 %).
    overshoot: f64,
    /// 2 % settling time (s).
    settling_time_s: f64,
}

impl From<angletrack::StepResponse> for PyStepResponse {
    fn from(s: angletrack::StepResponse) -> Self {
        Self {
            overshoot: s.overshoot,
            settling_time_s: s.settling_time_s,
        }
    }
}

#[pymethods]
impl PyStepResponse {
    fn __repr__(&self) -> String {
        format!(
            "StepResponse(overshoot={:.4} ({:.2} %), settling_time_s={:.6e})",
            self.overshoot,
            100.0 * self.overshoot,
            self.settling_time_s
        )
    }
}

/// Everything the analysis predicts about a gain set, in physical units (the design's
/// datasheet). `repr()` and `str()` render it as a table.
#[pyclass(module = "angletrack", frozen)]
#[derive(Debug, Clone)]
pub struct DesignReport {
    inner: angletrack::DesignReport,
}

#[pymethods]
impl DesignReport {
    /// The design rule, in words.
    #[getter]
    fn method(&self) -> &'static str {
        self.inner.method.name()
    }
    /// The mapping of a continuous design, or `None`.
    #[getter]
    fn discretisation(&self) -> Option<&'static str> {
        self.inner.discretisation.map(discretisation_name)
    }
    /// Loop order (2 or 3).
    #[getter]
    fn order(&self) -> usize {
        self.inner.order
    }
    /// Sample period (s).
    #[getter]
    fn sample_period_s(&self) -> f64 {
        self.inner.sample_period_s
    }
    /// The discrete gains.
    #[getter]
    fn gains(&self) -> Vec<f64> {
        self.inner.gains.clone()
    }
    /// Poles `z_i` of the discrete loop.
    #[getter]
    fn discrete_poles<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyComplex>> {
        complex_list(py, &self.inner.discrete_poles)
    }
    /// Their continuous equivalents `ln(z_i) / Ts` (rad/s).
    #[getter]
    fn continuous_equivalent_poles<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyComplex>> {
        complex_list(py, &self.inner.continuous_equivalent_poles)
    }
    /// The continuous design's poles (rad/s); empty for Kalman and given gains.
    #[getter]
    fn design_poles<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyComplex>> {
        complex_list(py, &self.inner.design_poles)
    }
    /// Largest relative pole shift of the discretisation, or `None`.
    #[getter]
    fn pole_shift(&self) -> Option<f64> {
        self.inner.pole_shift
    }
    /// -3 dB bandwidth (Hz) of the closed-loop angle transfer function, or `None`.
    #[getter]
    fn bandwidth_hz(&self) -> Option<f64> {
        self.inner.bandwidth_hz
    }
    /// Order 2: discrete acceleration constant Ka (1/s^2).
    #[getter]
    fn acceleration_constant_per_s2(&self) -> Option<f64> {
        self.inner.acceleration_constant_per_s2
    }
    /// Order 2: continuous acceleration constant `k_b1` (1/s^2).
    #[getter]
    fn continuous_acceleration_constant_per_s2(&self) -> Option<f64> {
        self.inner.continuous_acceleration_constant_per_s2
    }
    /// Order 3: steady-state angle error per unit jerk (s^3).
    #[getter]
    fn error_per_unit_jerk_s3(&self) -> Option<f64> {
        self.inner.error_per_unit_jerk_s3
    }
    /// Order 3: `1 / k_c2` of the continuous design (s^3).
    #[getter]
    fn continuous_error_per_unit_jerk_s3(&self) -> Option<f64> {
        self.inner.continuous_error_per_unit_jerk_s3
    }
    /// The sensor noise standard deviation the noise figures are for.
    #[getter]
    fn sensor_noise_std(&self) -> f64 {
        self.inner.sensor_noise_std
    }
    /// Predicted steady-state RMS angle error (rad) from sensor noise.
    #[getter]
    fn angle_error_rms_rad(&self) -> f64 {
        self.inner.angle_error_rms_rad
    }
    /// Predicted steady-state RMS speed error (rad/s) from sensor noise.
    #[getter]
    fn speed_error_rms_rad_s(&self) -> f64 {
        self.inner.speed_error_rms_rad_s
    }
    /// Kalman design: `sqrt(P11)` (rad).
    #[getter]
    fn kalman_angle_floor_rad(&self) -> Option<f64> {
        self.inner.kalman_angle_floor_rad
    }
    /// Kalman design: `sqrt(P22) / Ts` (rad/s).
    #[getter]
    fn kalman_speed_floor_rad_s(&self) -> Option<f64> {
        self.inner.kalman_speed_floor_rad_s
    }
    /// Small-signal (linear) step response of the discrete loop.
    #[getter]
    fn linear_step(&self) -> PyStepResponse {
        self.inner.linear_step.into()
    }
    /// Step response of the continuous design, or `None`.
    #[getter]
    fn continuous_step(&self) -> Option<PyStepResponse> {
        self.inner.continuous_step.map(Into::into)
    }
    /// Response of the bare nonlinear loop (no diagnostics) to a 179 degree step from rest.
    #[getter]
    fn large_step(&self) -> PyStepResponse {
        self.inner.large_step.into()
    }
    /// The 179 degree step with the core's default diagnostics (false-lock detection
    /// re-acquires the angle).
    #[getter]
    fn large_step_with_diagnostics(&self) -> PyStepResponse {
        self.inner.large_step_with_diagnostics.into()
    }
    /// Where the nonlinear loop ends after the 179 degree step (rad).
    #[getter]
    fn large_step_final_rad(&self) -> f64 {
        self.inner.large_step_final_rad
    }
    /// The largest speed the phase detector can follow, `pi / Ts` (rad/s).
    #[getter]
    fn max_speed_rad_s(&self) -> f64 {
        self.inner.max_speed_rad_s
    }
    /// The largest speed step (rad/s) the loop acquires from rest without slipping a cycle.
    #[getter]
    fn acquisition_speed_rad_s(&self) -> f64 {
        self.inner.acquisition_speed_rad_s
    }

    fn __str__(&self) -> String {
        self.inner.to_string()
    }

    fn __repr__(&self) -> String {
        format!("DesignReport:\n{}", self.inner)
    }
}

/// Predicted RMS errors of the linearised loop.
#[pyclass(name = "PredictedError", module = "angletrack", frozen, get_all)]
#[derive(Debug, Clone)]
pub struct PyPredictedError {
    /// RMS angle error (rad).
    angle_rms_rad: f64,
    /// RMS speed error (rad/s).
    speed_rms_rad_s: f64,
}

#[pymethods]
impl PyPredictedError {
    fn __repr__(&self) -> String {
        format!(
            "PredictedError(angle_rms_rad={:.6e}, speed_rms_rad_s={:.6e})",
            self.angle_rms_rad, self.speed_rms_rad_s
        )
    }
}

fn predicted<const N: usize>(
    gains: &angletrack::Gains<f64, N>,
    sensor_noise_std: f64,
    process_noise_q: f64,
) -> Result<PyPredictedError>
where
    Order<N>: SupportedOrder,
{
    let p = angletrack::predicted_error(gains, sensor_noise_std, process_noise_q)?;
    Ok(PyPredictedError {
        angle_rms_rad: p.angle_rms_rad,
        speed_rms_rad_s: p.speed_rms_rad_s,
    })
}

/// Steady-state RMS angle and speed errors of the linearised loop with `gains`, driven by
/// white sensor noise of standard deviation `sensor_noise_std` per channel and a white
/// N-th derivative of the angle of scaled variance `process_noise_q` (discrete Lyapunov
/// equation).
#[pyfunction]
#[pyo3(signature = (gains, sensor_noise_std, process_noise_q = 0.0))]
pub fn predicted_error(
    gains: PyGains,
    sensor_noise_std: f64,
    process_noise_q: f64,
) -> Result<PyPredictedError> {
    match &gains.set {
        GainSet::Second(g) => predicted(g, sensor_noise_std, process_noise_q),
        GainSet::Third(g) => predicted(g, sensor_noise_std, process_noise_q),
    }
}

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
    let d = self::discretisation(discretisation)?;
    Ok(angletrack::second_order_from_tracking_error(
        max_error_rad,
        acceleration_rad_s2,
        damping,
        sample_period_s,
        d,
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
    let d = self::discretisation(discretisation)?;
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
    let d = self::discretisation(discretisation)?;
    Ok(angletrack::second_order_butterworth(time_constant_s, sample_period_s, d)?.into())
}

/// `omega_3dB / omega_n` of the continuous 2nd-order loop with damping `m`.
#[pyfunction]
#[pyo3(signature = (damping))]
pub fn second_order_bandwidth_ratio(damping: f64) -> f64 {
    angletrack::second_order_bandwidth_ratio(damping)
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
    let d = self::discretisation(discretisation)?;
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
    let d = self::discretisation(discretisation)?;
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
    let d = self::discretisation(discretisation)?;
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
