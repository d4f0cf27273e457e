//! `SensorCalibration` and the `calibration` argument of `Observer` and `track`: the core's
//! online correction of offsets, gain imbalance and quadrature error (`docs/theory.md §12`),
//! configured, read and written from Python.

use angletrack::OnlineCalibrationChoice;
use angletrack_core::SensorCalibration as CoreCalibration;
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyDict};

use crate::errors::{Error, Result};
use crate::getters::class_methods;

/// A sensor's calibration, the model `y_c = offset_c + amplitude_c cos(theta)`,
/// `y_s = offset_s + amplitude_s sin(theta + quadrature_rad)` in the observer's input units
/// (raw counts for integer input, unless `adc_counts_per_unit` is given) and radians. The
/// correction keeps the cosine channel's amplitude. Checked by the core (`ConfigError`
/// naming the field: amplitudes positive, `|quadrature_rad| < pi/4`, all finite).
/// `to_dict()` and `SensorCalibration.from_dict()` carry it to and from JSON.
#[pyclass(
    name = "SensorCalibration",
    module = "angletrack",
    frozen,
    eq,
    from_py_object
)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PySensorCalibration {
    /// The core's calibration, checked.
    pub inner: CoreCalibration<f64>,
}

/// The fields, in the order of the constructor and of `to_dict`.
const FIELDS: [&str; 5] = [
    "offset_c",
    "offset_s",
    "amplitude_c",
    "amplitude_s",
    "quadrature_rad",
];

impl PySensorCalibration {
    /// The Python value of a core calibration.
    pub fn from_core(c: &CoreCalibration<f64>) -> Self {
        Self { inner: *c }
    }

    /// The fields in the order of [`FIELDS`].
    fn values(&self) -> [f64; 5] {
        let (o_c, o_s, a_c, a_s, q) = self.inner.parameters();
        [o_c, o_s, a_c, a_s, q]
    }
}

class_methods! {
    PySensorCalibration {
        /// Offset of the cosine channel.
        offset_c: f64 = |this, py| this.values()[0];
        /// Offset of the sine channel.
        offset_s: f64 = |this, py| this.values()[1];
        /// Amplitude of the cosine channel.
        amplitude_c: f64 = |this, py| this.values()[2];
        /// Amplitude of the sine channel.
        amplitude_s: f64 = |this, py| this.values()[3];
        /// Quadrature (non-orthogonality) angle of the sine channel (rad).
        quadrature_rad: f64 = |this, py| this.values()[4];
        /// The gain imbalance `amplitude_s / amplitude_c`.
        amplitude_ratio: f64 = |this, py| this.values()[3] / this.values()[2];
    }
    methods {
        #[new]
        #[pyo3(signature = (*, offset_c = 0.0, offset_s = 0.0, amplitude_c = 1.0, amplitude_s = 1.0,
            quadrature_rad = 0.0))]
        fn py_new(
            offset_c: f64,
            offset_s: f64,
            amplitude_c: f64,
            amplitude_s: f64,
            quadrature_rad: f64,
        ) -> Result<Self> {
            let c = CoreCalibration::new(offset_c, offset_s, amplitude_c, amplitude_s, quadrature_rad)?;
            Ok(Self::from_core(&c))
        }

        /// The fields as a dict of floats (for `json.dumps`).
        // A Python method takes `&self` (pyo3 passes no Rust value), though the type is `Copy`.
        #[allow(clippy::wrong_self_convention)]
        fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
            FIELDS.into_iter().zip(self.values()).into_py_dict(py)
        }

        /// The calibration of a dict holding the five fields (as `to_dict` writes them; other
        /// keys are ignored), checked as the constructor does.
        #[staticmethod]
        fn from_dict(d: &Bound<'_, PyDict>) -> Result<Self> {
            let mut values = [0.0; 5];
            for (value, name) in values.iter_mut().zip(FIELDS) {
                let item = d
                    .get_item(name)?
                    .ok_or_else(|| Error::value(name, "missing from the dict"))?;
                *value = item
                    .extract::<f64>()
                    .map_err(|_| Error::value(name, "must be a number"))?;
            }
            let [o_c, o_s, a_c, a_s, q] = values;
            Self::py_new(o_c, o_s, a_c, a_s, q)
        }

        fn __repr__(&self) -> String {
            let [o_c, o_s, a_c, a_s, q] = self.values();
            format!(
                "SensorCalibration(offset_c={o_c:?}, offset_s={o_s:?}, amplitude_c={a_c:?}, \
                 amplitude_s={a_s:?}, quadrature_rad={q:?})"
            )
        }
    }
}

/// The online calibration of the arguments `calibration` (`None`, `"learn"` or `"frozen"`)
/// and `initial_calibration`, checked by the crate's `OnlineCalibrationChoice`.
pub fn calibration_choice(
    mode: Option<&str>,
    initial: Option<PySensorCalibration>,
) -> Result<OnlineCalibrationChoice> {
    OnlineCalibrationChoice::new(mode, initial.map(|c| c.inner))
        .map_err(|e| Error::value(e.argument, e.reason))
}
