//! `Design`, the designed gain set of the `angletrack` crate with what it was designed from,
//! and `KalmanSolution`, the Riccati solution of a Kalman design.

use angletrack::{AnyDesign, Complex, Design, FixedDesignConstants, KalmanSolution};
use pyo3::prelude::*;
use pyo3::types::{PyComplex, PyDict, PyList};

use crate::analysis::DesignReport;
use crate::errors::Result;
use crate::gains::{GainSet, PyGains, with_gains};
use crate::getters::{class_methods, result_class};

/// Runs `$body` with `$d` bound to the concrete `Design<N>` inside `$any`.
macro_rules! with_design {
    ($any:expr, $d:ident => $body:expr) => {
        match $any {
            AnyDesign::Second($d) => $body,
            AnyDesign::Third($d) => $body,
        }
    };
}

/// The Python list of complex `values`.
pub(crate) fn complex_list(py: Python<'_>, values: &[Complex<f64>]) -> PyResult<Py<PyList>> {
    let values = values
        .iter()
        .map(|z| PyComplex::from_doubles(py, z.re, z.im));
    Ok(PyList::new(py, values)?.unbind())
}

result_class! {
    /// The steady-state solution of a Kalman design on the scaled state
    /// `(theta, Ts*Omega, Ts^2*alpha)`.
    PyKalmanSolution = "KalmanSolution" of |py, (k, ts): (KalmanSolution, f64)| {
        /// Process noise variance `q` of the scaled jerk `Ts^3 beta` (rad^2).
        process_noise_q: f64 = k.process_noise_q,
        /// Measurement noise variance `r` of each channel (amplitude 1).
        measurement_noise_r: f64 = k.measurement_noise_r,
        /// Predicted (a priori) error covariance, the solution of the Riccati equation (3x3).
        predicted_covariance: [[f64; 3]; 3] = k.predicted_covariance,
        /// Filtered (a posteriori) error covariance (3x3).
        covariance: [[f64; 3]; 3] = k.covariance,
        /// `sqrt(P11)` (rad): the smallest RMS angle error of any linear estimator of the model.
        angle_floor_rad: f64 = k.angle_floor_rad(),
        /// `sqrt(P22) / Ts` (rad/s).
        speed_floor_rad_s: f64 = k.speed_floor_rad_s(ts),
    }
    repr |k| format!(
        "KalmanSolution(process_noise_q={:e}, measurement_noise_r={:e}, angle_floor_rad={:.6e}, \
         speed_floor_rad_s={:.6e})",
        k.process_noise_q, k.measurement_noise_r, k.angle_floor_rad, k.speed_floor_rad_s
    );
}

/// The dict of fixed-point constants `Design.fixed_constants()` and
/// `FixedObserver.constants` give.
pub(crate) fn constants_dict(py: Python<'_>, c: FixedDesignConstants) -> Result<Bound<'_, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("multiplier", c.multiplier)?;
    dict.set_item("acceleration_shift", c.acceleration_shift)?;
    dict.set_item("quantised_gains", c.quantised_gains)?;
    dict.set_item("sample_period_s", c.sample_period_s)?;
    Ok(dict)
}

/// A designed gain set (float64) with what it was designed from. Analyse it with
/// `report()`; run it with `Observer(design.gains, dtype=...)`.
#[pyclass(name = "Design", module = "angletrack", frozen)]
#[derive(Debug, Clone)]
pub struct PyDesign {
    inner: AnyDesign,
}

impl PyDesign {
    /// The designed gains.
    pub(crate) fn gain_set(&self) -> GainSet {
        match &self.inner {
            AnyDesign::Second(d) => GainSet::Second(d.gains),
            AnyDesign::Third(d) => GainSet::Third(d.gains),
        }
    }
}

impl<D: Into<AnyDesign>> From<D> for PyDesign {
    fn from(d: D) -> Self {
        Self { inner: d.into() }
    }
}

class_methods! {
    PyDesign {
        /// The designed discrete gains (float64, checked).
        gains: PyGains = |this, py| {
            PyGains {
                set: this.gain_set(),
            }
        };
        /// The design rule, in words.
        method: &'static str = |this, py| with_design!(&this.inner, d => d.method.name());
        /// The mapping of a continuous design ('pole_matching', 'forward_euler', 'tustin');
        /// `None` for Kalman and given gains.
        discretisation: Option<&'static str> =
            |this, py| with_design!(&this.inner, d => d.discretisation.map(|x| x.id()));
        /// The continuous closed-loop poles (rad/s) of a continuous design; empty otherwise.
        continuous_poles: PyResult<Py<PyList>> =
            |this, py| with_design!(&this.inner, d => complex_list(py, &d.continuous_poles));
        /// The continuous gains `(k_a, k_b[, k_c])` (1/s, 1/s^2, 1/s^3) of a continuous design,
        /// in the order of `gains` (the state each corrects, angle first: `l_i ~ k_i Ts^i`).
        continuous_gains: Option<Vec<f64>> =
            |this, py| with_design!(&this.inner, d => d.continuous_gains.map(|k| k.to_vec()));
        /// Coefficients (lowest power first, leading 1 omitted) of the continuous closed-loop
        /// polynomial `s^N + ... + c0` of a continuous design, the order of
        /// `Gains.loop_polynomial`: `continuous_gains` reversed.
        continuous_loop_polynomial: Option<Vec<f64>> =
            |this, py| with_design!(&this.inner, d => d.continuous_loop_polynomial());
        /// The Riccati solution of a Kalman design; `None` otherwise.
        kalman: Result<Option<PyKalmanSolution>> = |this, py| {
            let ts = this.inner.sample_period();
            with_design!(&this.inner, d => d.kalman.map(|k| PyKalmanSolution::of(py, (k, ts))).transpose())
        };
        /// The sample period (s).
        sample_period_s: f64 = |this, py| this.inner.sample_period();
        /// The observer order (2 or 3).
        order: usize = |this, py| this.inner.order();
    }
    methods {
        /// Wraps gains designed elsewhere, to analyse them.
        #[staticmethod]
        #[pyo3(signature = (gains))]
        fn from_gains(gains: PyGains) -> Self {
            with_gains!(gains.set, g => Design::from_gains(g).into())
        }

        /// The design's datasheet for white sensor noise of standard deviation
        /// `sensor_noise_std` per channel (amplitude 1; 0 for a noise-free analysis).
        #[pyo3(signature = (sensor_noise_std = 0.0))]
        fn report(&self, py: Python<'_>, sensor_noise_std: f64) -> Result<DesignReport> {
            let inner = self.inner.clone();
            let report = py.detach(move || inner.report(sensor_noise_std))?;
            DesignReport::of(py, report)
        }

        /// The design's constants for the core's fixed-point observer (`docs/theory.md §14`): a
        /// dict with `multiplier` (one per gain), `acceleration_shift`, the `quantised_gains`
        /// they represent and `sample_period_s`. Raises `ConfigError` naming the gain if one
        /// rounds to zero, does not fit, or the quantised loop is unstable.
        fn fixed_constants<'py>(&self, py: Python<'py>) -> Result<Bound<'py, PyDict>> {
            constants_dict(py, self.inner.fixed_constants()?)
        }

        fn __repr__(&self) -> String {
            with_design!(&self.inner, d => format!(
                "Design(method={:?}, discretisation={}, order={}, sample_period_s={:e}, gains={:?})",
                d.method.name(),
                d.discretisation.map_or("None".to_string(), |x| format!("{:?}", x.id())),
                d.gains.order(),
                d.sample_period(),
                d.gains.gains()
            ))
        }
    }
}
