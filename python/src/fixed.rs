//! `FixedObserver`: the core's fixed-point observer (`FixedGains::update`, `docs/theory.md
//! §14`) on int16 numpy arrays, bit for bit what a Cortex-M0/M4 firmware computes.
//!
//! The per-sample work is the core's; this module checks the samples (int16 counts, no
//! silent conversion), converts the constants dict and runs `angletrack::FixedColumns` with
//! the GIL released.

use angletrack::FixedDesignConstants;
use angletrack_core::fixed::FixedConstants;
use angletrack_core::{
    ConfigError as CoreConfigError, FixedGains, FixedState, Order, SupportedOrder,
};
use numpy::PyUntypedArray;
use numpy::prelude::*;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyMapping};

use crate::arrays::{Samples, check_equal_lengths, samples};
use crate::design::{PyDesign, constants_dict};
use crate::errors::{Error, Result};
use crate::fixed_estimates::{FixedArrays, FixedEstimate, FixedEstimates};
use crate::gains::{GainSet, PyGains};

/// The gains and state of a fixed-point observer of order 2 or 3.
#[derive(Debug, Clone, Copy)]
enum FixedChannel {
    Second(FixedGains<2>, FixedState<2>),
    Third(FixedGains<3>, FixedState<3>),
}

/// Runs `$body` with `$g` and `$s` bound to the gains and state inside a [`FixedChannel`].
macro_rules! with_channel {
    ($channel:expr, $g:ident, $s:ident => $body:expr) => {
        match $channel {
            FixedChannel::Second($g, $s) => $body,
            FixedChannel::Third($g, $s) => $body,
        }
    };
}

/// The core's fixed-point gains of order `N` from their integer constants, checked again.
fn gains_of_constants<const N: usize>(
    multiplier: [i32; N],
    acceleration_shift: u32,
    sample_period_s: f64,
) -> core::result::Result<FixedGains<N>, CoreConfigError>
where
    Order<N>: SupportedOrder,
{
    let constants = FixedConstants {
        multiplier,
        acceleration_shift,
    };
    FixedGains::from_constants(constants, sample_period_s)
}

impl FixedChannel {
    /// The fixed-point observer of checked float gains, quantised by the core.
    fn of_gains(set: &GainSet) -> core::result::Result<Self, CoreConfigError> {
        Ok(match set {
            GainSet::Second(g) => Self::Second(
                FixedGains::new(g.gains(), g.sample_period())?,
                FixedState::new(),
            ),
            GainSet::Third(g) => Self::Third(
                FixedGains::new(g.gains(), g.sample_period())?,
                FixedState::new(),
            ),
        })
    }

    /// The fixed-point observer of the integer constants (2 or 3 multipliers), checked by
    /// the core; a refusal names `constants` and the gain.
    fn of_constants(multiplier: &[i32], shift: u32, sample_period_s: f64) -> Result<Self> {
        let named = |e: CoreConfigError| match e {
            CoreConfigError::NotFinite(_) | CoreConfigError::NotPositive(_) => Error::Config(e),
            _ => Error::value(
                "constants",
                format!("{e} (multiplier {multiplier:?}, acceleration_shift {shift})"),
            ),
        };
        Ok(match *multiplier {
            [a, b] => Self::Second(
                gains_of_constants([a, b], shift, sample_period_s).map_err(named)?,
                FixedState::new(),
            ),
            [a, b, c] => Self::Third(
                gains_of_constants([a, b, c], shift, sample_period_s).map_err(named)?,
                FixedState::new(),
            ),
            _ => {
                return Err(Error::value(
                    "constants",
                    format!(
                        "'multiplier' has {} values: expected 2 (2nd-order observer) or 3 \
                         (3rd-order)",
                        multiplier.len()
                    ),
                ));
            }
        })
    }

    /// The same observer with the monitor for `nominal_amplitude` counts (`None`: off).
    fn with_monitor(self, nominal_amplitude: Option<f64>) -> Result<Self> {
        Ok(match self {
            Self::Second(g, s) => Self::Second(g.with_monitor(nominal_amplitude)?, s),
            Self::Third(g, s) => Self::Third(g.with_monitor(nominal_amplitude)?, s),
        })
    }
}

/// The float gains of argument `design`: a `Design` or `Gains`.
fn designed_gains(design: &Bound<'_, PyAny>) -> Result<GainSet> {
    if let Ok(d) = design.cast::<PyDesign>() {
        return Ok(d.get().gain_set());
    }
    match design.extract::<PyGains>() {
        Ok(g) => Ok(g.set),
        Err(_) => Err(Error::value(
            "design",
            format!(
                "expected a Design or Gains (FixedObserver.from_constants takes constants), got \
                 an object of type {}",
                design.get_type()
            ),
        )),
    }
}

/// The value of `key` in the constants dict.
fn constant<'py>(constants: &Bound<'py, PyMapping>, key: &str) -> Result<Bound<'py, PyAny>> {
    constants.get_item(key).map_err(|_| {
        Error::value(
            "constants",
            format!("has no key '{key}' (expected the dict Design.fixed_constants() returns)"),
        )
    })
}

/// The refusal of a constant `value` of `key` that is not what `Design.fixed_constants()`
/// gives.
fn not_integers(key: &str, value: &Bound<'_, PyAny>, expected: &str) -> Error {
    Error::value(
        "constants",
        format!("'{key}' is {value:?}: expected {expected} (as Design.fixed_constants() gives)"),
    )
}

/// The samples of argument `parameter` as int16 counts: an int16 numpy array as it is, any
/// other array refused (`TypeError`: no silent conversion), anything else (a list) read by
/// numpy and refused unless its values are integers within int16.
fn counts<'py>(obj: &Bound<'py, PyAny>, parameter: &'static str) -> Result<Samples<'py, i16>> {
    if obj.cast::<PyUntypedArray>().is_ok() {
        return samples::<i16>(obj, parameter);
    }
    let numpy = PyModule::import(obj.py(), "numpy")?;
    let read = numpy
        .getattr("asarray")?
        .call1((obj,))
        .map_err(|e| Error::value(parameter, format!("cannot be read as int16 samples ({e})")))?;
    let array = read.cast::<PyUntypedArray>().map_err(PyErr::from)?;
    let kind = array.dtype().kind();
    if array.len() > 0 && kind != b'i' && kind != b'u' {
        return Err(Error::Dtype {
            parameter,
            given: format!("values of dtype {}", array.dtype()),
            expected: "int16 samples (an int16 array, or integers from -32768 to 32767)".into(),
        });
    }
    let below = numpy.getattr("less")?.call1((&read, i16::MIN))?;
    let above = numpy.getattr("greater")?.call1((&read, i16::MAX))?;
    let outside = numpy
        .getattr("flatnonzero")?
        .call1((numpy.getattr("logical_or")?.call1((below, above))?,))?;
    if outside.len()? > 0 {
        let index = outside.get_item(0)?;
        return Err(Error::value(
            parameter,
            format!(
                "sample {} (index {index}) is outside the int16 range [-32768, 32767]",
                read.get_item(&index)?
            ),
        ));
    }
    samples::<i16>(
        &read.call_method1("astype", (numpy.getattr("int16")?,))?,
        parameter,
    )
}

/// The core's fixed-point angle tracking observer (`docs/theory.md §14`): the integers a
/// Cortex-M0/M4 firmware running `FixedGains::update` (or `track`) computes, bit for bit, on
/// int16 samples (counts, mid-scale removed), with a state that persists between calls so
/// that a recording fed in chunks gives exactly the result of one call.
///
/// `design` is a `Design` or `Gains`, quantised by the core (`ConfigError` naming the gain
/// that rounds to zero, does not fit, or leaves the quantised loop unstable);
/// `FixedObserver.from_constants` takes the integers a firmware embeds.
/// `nominal_amplitude` (counts, 16384 to 46341) sets the monitor's thresholds; `None` turns
/// the monitor off.
#[pyclass(name = "FixedObserver", module = "angletrack")]
#[derive(Debug)]
pub struct PyFixedObserver {
    channel: FixedChannel,
}

#[pymethods]
impl PyFixedObserver {
    #[new]
    #[pyo3(signature = (design, *, nominal_amplitude = Some(16384.0)))]
    fn py_new(design: &Bound<'_, PyAny>, nominal_amplitude: Option<f64>) -> Result<Self> {
        let channel =
            FixedChannel::of_gains(&designed_gains(design)?)?.with_monitor(nominal_amplitude)?;
        Ok(Self { channel })
    }

    /// The observer of the integer constants a firmware embeds: the dict
    /// `Design.fixed_constants()` returns (`multiplier`, `acceleration_shift`; other keys
    /// are ignored), at `sample_period_s` (s). Checked again by the core: `ConfigError`
    /// (parameter `constants`) naming the gain whose multiplier or shift is out of range or
    /// leaves the loop unstable.
    #[staticmethod]
    #[pyo3(signature = (constants, sample_period_s, *, nominal_amplitude = Some(16384.0)))]
    fn from_constants(
        constants: &Bound<'_, PyAny>,
        sample_period_s: f64,
        nominal_amplitude: Option<f64>,
    ) -> Result<Self> {
        let constants = constants.cast::<PyMapping>().map_err(|_| {
            Error::value(
                "constants",
                format!(
                    "expected the dict Design.fixed_constants() returns, got an object of type {}",
                    constants.get_type()
                ),
            )
        })?;
        let multiplier = constant(constants, "multiplier")?;
        let multiplier: Vec<i32> = multiplier
            .extract()
            .map_err(|_| not_integers("multiplier", &multiplier, "a list of integers (int32)"))?;
        let shift = constant(constants, "acceleration_shift")?;
        let shift: u32 = shift
            .extract()
            .map_err(|_| not_integers("acceleration_shift", &shift, "an integer from 0 to 15"))?;
        let channel = FixedChannel::of_constants(&multiplier, shift, sample_period_s)?
            .with_monitor(nominal_amplitude)?;
        Ok(Self { channel })
    }

    /// Runs the observer over the int16 samples `y_c ~ cos(theta)`, `y_s ~ sin(theta)`
    /// (1-D, equal lengths; a list of integers within int16 is read too) and returns the
    /// estimates of every sample. The state carries over to the next call.
    #[pyo3(signature = (y_c, y_s))]
    fn update(
        &mut self,
        py: Python<'_>,
        y_c: &Bound<'_, PyAny>,
        y_s: &Bound<'_, PyAny>,
    ) -> Result<FixedEstimates> {
        let (y_c, y_s) = (counts(y_c, "y_c")?, counts(y_s, "y_s")?);
        let (y_c, y_s) = (y_c.as_slice(), y_s.as_slice());
        check_equal_lengths(("y_c", y_c.len()), ("y_s", y_s.len()))?;
        let out = FixedArrays::new(py, y_c.len())?;
        let channel = &mut self.channel;
        out.fill(
            py,
            |columns| with_channel!(channel, g, s => columns.run(g, s, y_c, y_s)),
        )?;
        Ok(out.into_estimates(y_c.len()))
    }

    /// The estimate after the last sample.
    #[getter]
    fn estimate(&self) -> FixedEstimate {
        with_channel!(&self.channel, g, s => FixedEstimate::new(g, &FixedGains::estimate(s)))
    }

    /// Forgets the state: the next sample sets the angle from its `atan2`.
    fn reset(&mut self) {
        with_channel!(&mut self.channel, _g, s => *s = FixedState::new());
    }

    /// The integer constants (the dict `Design.fixed_constants()` returns): what
    /// `FixedObserver.from_constants` takes back.
    #[getter]
    fn constants<'py>(&self, py: Python<'py>) -> Result<Bound<'py, PyDict>> {
        constants_dict(
            py,
            with_channel!(&self.channel, g, _s => FixedDesignConstants::of(g)),
        )
    }

    /// The gains the integers represent, `(l1, l2[, l3])` (float): the loop that runs.
    #[getter]
    fn gains(&self) -> Vec<f64> {
        with_channel!(&self.channel, g, _s => g.gains().to_vec())
    }

    /// The sample period `Ts` (s).
    #[getter]
    fn sample_period_s(&self) -> f64 {
        with_channel!(&self.channel, g, _s => g.sample_period())
    }

    /// The observer order: 2 or 3.
    #[getter]
    fn order(&self) -> usize {
        with_channel!(&self.channel, g, _s => g.gains().len())
    }

    /// The faults latched since they were last cleared (bits, see `angletrack.Faults`).
    #[getter]
    fn latched_faults(&self) -> u8 {
        with_channel!(&self.channel, _g, s => s.latched_faults().bits())
    }

    /// Returns the latched faults (bits) and clears them.
    fn clear_faults(&mut self) -> u8 {
        with_channel!(&mut self.channel, _g, s => {
            let latched = s.latched_faults().bits();
            s.clear_faults();
            latched
        })
    }

    fn __repr__(&self) -> String {
        with_channel!(&self.channel, g, _s => format!(
            "FixedObserver(order={}, multiplier={:?}, acceleration_shift={}, sample_period_s={:e})",
            g.gains().len(),
            g.constants().multiplier,
            g.constants().acceleration_shift,
            g.sample_period()
        ))
    }
}
