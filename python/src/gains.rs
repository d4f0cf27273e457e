//! `Gains`: the discrete gains of one observer and its sample period, checked by the core.

use pyo3::prelude::*;
use pyo3::types::PyType;

use crate::errors::{Error, Result};
use crate::getters::class_methods;

pub use angletrack::AnyGains as GainSet;
pub(crate) use angletrack::with_any_gains as with_gains;

/// Discrete gains of an angle tracking observer, checked against the stability region of the
/// discrete loop.
///
/// `gains` are `(l1, l2)` (2nd order) or `(l1, l2, l3)` (3rd order), dimensionless, for the
/// scaled state `(theta, Ts*Omega, Ts^2*alpha)`; `sample_period_s` is `Ts` in seconds.
/// Raises `ConfigError` (parameter `gains`) naming the gain whose stability condition fails.
#[pyclass(name = "Gains", module = "angletrack", frozen, eq)]
#[derive(Debug, Clone, PartialEq)]
pub struct PyGains {
    /// The checked gains.
    pub set: GainSet,
}

/// Every function takes its gains as the argument `gains`: anything but a `Gains` is a
/// `TypeError` whose message starts with it (pyo3's own would not name it).
impl<'a, 'py> FromPyObject<'a, 'py> for PyGains {
    type Error = PyErr;

    fn extract(obj: pyo3::Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        match obj.cast::<PyGains>() {
            Ok(gains) => Ok(gains.get().clone()),
            Err(_) => Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "gains: expected an angletrack.Gains (e.g. Gains([0.06, 0.001], \
                 sample_period_s=1e-4), or a design's .gains), got {}",
                type_name(&obj)
            ))),
        }
    }
}

/// `str 'abc'`: the type and the value of an argument, for a message.
pub fn type_name(obj: &Bound<'_, PyAny>) -> String {
    let name = obj
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    match obj.repr() {
        Ok(r) => {
            let r = r.to_string();
            let short: String = r.chars().take(40).collect();
            format!(
                "{name} {short}{}",
                if r.len() > short.len() { "..." } else { "" }
            )
        }
        Err(_) => name,
    }
}

/// The floats of the sequence argument `parameter`, or a `ConfigError` naming it and the
/// element at fault.
pub fn reals(obj: &Bound<'_, PyAny>, parameter: &'static str) -> Result<Vec<f64>> {
    let not_a_sequence = || {
        Error::value(
            parameter,
            format!("expected a sequence of numbers, got {}", type_name(obj)),
        )
    };
    if obj.is_instance_of::<pyo3::types::PyString>() {
        return Err(not_a_sequence());
    }
    let items = obj.try_iter().map_err(|_| not_a_sequence())?;
    items
        .enumerate()
        .map(|(i, item)| {
            let item = item?;
            item.extract::<f64>().map_err(|_| {
                Error::value(
                    parameter,
                    format!("element {i} is not a number: {}", type_name(&item)),
                )
            })
        })
        .collect()
}

class_methods! {
    PyGains {
        /// The discrete gains `(l1, l2[, l3])` (dimensionless).
        gains: Vec<f64> = |this, py| this.set.gains();
        /// Coefficients (lowest first, leading 1 omitted) of the closed-loop characteristic
        /// polynomial in `s = z - 1`.
        loop_polynomial: Vec<f64> = |this, py| this.set.loop_polynomial();
        /// The sample period `Ts` (s).
        sample_period_s: f64 = |this, py| this.set.sample_period();
        /// The sample rate `1/Ts` (Hz).
        sample_rate_hz: f64 = |this, py| 1.0 / this.set.sample_period();
        /// The observer order: 2 (angle, speed) or 3 (angle, speed, acceleration).
        order: usize = |this, py| this.set.order();
    }
    methods {
        #[new]
        #[pyo3(signature = (gains, sample_period_s))]
        fn py_new(gains: &Bound<'_, PyAny>, sample_period_s: &Bound<'_, PyAny>) -> Result<Self> {
            let gains = reals(gains, "gains")?;
            // An int, a float or a numpy scalar.
            let sample_period_s = sample_period_s.extract::<f64>().map_err(|_| {
                let given = type_name(sample_period_s);
                Error::value("sample_period_s", format!("expected a number, got {given}"))
            })?;
            Ok(Self {
                set: GainSet::new(&gains, sample_period_s)?,
            })
        }

        /// Gains from the closed-loop characteristic polynomial written in `s = z - 1`
        /// (coefficients lowest first, monic, leading 1 omitted), as the core's pole-matching
        /// entry point.
        #[staticmethod]
        #[pyo3(signature = (coefficients, sample_period_s))]
        fn from_loop_polynomial(coefficients: Vec<f64>, sample_period_s: f64) -> Result<Self> {
            Ok(Self {
                set: GainSet::from_loop_polynomial(&coefficients, sample_period_s)?,
            })
        }

        /// Pickling: rebuilt (and checked again) from the gains and the sample period.
        fn __reduce__<'py>(slf: &Bound<'py, Self>) -> (Bound<'py, PyType>, (Vec<f64>, f64)) {
            let set = &slf.get().set;
            (slf.get_type(), (set.gains(), set.sample_period()))
        }

        fn __repr__(&self) -> String {
            let l: Vec<String> = self
                .set
                .gains()
                .iter()
                .map(|x| format!("{x:.9e}"))
                .collect();
            format!(
                "Gains(gains=[{}], sample_period_s={:e})  # order {}, {:.6} Hz",
                l.join(", "),
                self.set.sample_period(),
                self.set.order(),
                1.0 / self.set.sample_period()
            )
        }
    }
}
