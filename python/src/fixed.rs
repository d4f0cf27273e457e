//! `FixedObserver`: the core's fixed-point observer (`FixedGains::update`, `docs/theory.md
//! §14`) on int16 numpy arrays, bit for bit what a Cortex-M0/M4 firmware computes.
//!
//! The per-sample work is the core's; this module checks the samples (int16 counts, no
//! silent conversion), converts the constants dict and runs `angletrack::FixedColumns` with
//! the GIL released.

use angletrack::{FixedConstantsError, FixedTracker, clipping_rails, fixed_front_end};
use angletrack_core::{AngleCorrection, SensorCalibration, TrackerFrontEnd};
use numpy::PyUntypedArray;
use numpy::prelude::*;
use pyo3::basic::CompareOp;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::angle_calibration::SensorParameters;
use crate::arrays::{Count, Samples, samples};
use crate::calibration::PySensorCalibration;
use crate::design::{PyDesign, constants_dict};
use crate::errors::{Error, Result};
use crate::export::constant;
use crate::fixed_estimates::{FixedEstimate, FixedEstimates, run_fixed};
use crate::gains::{GainSet, PyGains};
use crate::getters::class_methods;

impl From<FixedConstantsError> for Error {
    fn from(e: FixedConstantsError) -> Self {
        match e {
            FixedConstantsError::Config(e) => Error::Config(e),
            FixedConstantsError::Constants(reason) => Error::value("constants", reason),
        }
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

/// The samples of argument `parameter` as int16 counts: an int16 numpy array as it is, an
/// array of another integer dtype (numpy's default int64 among them) or anything else (a
/// list) read by numpy and refused unless its values are integers within int16, and an
/// array of floats refused (`TypeError`: no silent conversion).
fn counts<'py>(obj: &Bound<'py, PyAny>, parameter: &'static str) -> Result<Samples<'py, i16>> {
    if let Ok(array) = obj.cast::<PyUntypedArray>() {
        let dtype = array.dtype();
        let other_integers =
            matches!(dtype.kind(), b'i' | b'u') && !(dtype.kind() == b'i' && dtype.itemsize() == 2);
        if !other_integers {
            return samples::<i16>(obj, parameter);
        }
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
    let outside = read
        .rich_compare(i16::MIN, CompareOp::Lt)?
        .bitor(read.rich_compare(i16::MAX, CompareOp::Gt)?)?;
    let outside = numpy.getattr("flatnonzero")?.call1((outside,))?;
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
/// the monitor off. The stages before the observer, the core's standard chain (`Tracker`,
/// its front end by `angletrack::fixed_front_end`), in integers: `mid_scale_counts` removed and the counts shifted left by `input_shift`
/// bits (`AdcCounts`), then `calibration` (learned in float on the counts before the shift)
/// applied: a `SensorCalibration` as a `FixedCalibration`, a `harmonics.Calibration` also
/// with its harmonics as the core's 256-entry `FixedAngleCorrectionTable`. `adc_range=(min, max)`
/// (integer codes, as the samples come): a sample at or beyond it in either channel is
/// flagged `Faults.FRONT_END` and one clipped in both channels is coasted through; or
/// `measure_adc_range=True`: the same against the rails measured on the samples as they
/// come (the core's `HeldRailCheck`), as the C chain does.
#[pyclass(name = "FixedObserver", module = "angletrack")]
#[derive(Debug)]
pub struct PyFixedObserver {
    tracker: FixedTracker,
}

/// The stored sensor calibration and angle correction of a chain, either absent.
type Stages = (Option<SensorCalibration<f64>>, Option<AngleCorrection<f64>>);

/// The sensor calibration and angle correction of argument `calibration`: a
/// `SensorCalibration` (no angle correction), or an object with the attributes `sensor`
/// (the 5 parameters), `cos` and `sin` (the harmonics: `harmonics.Calibration`).
fn stages(calibration: Option<&Bound<'_, PyAny>>) -> Result<Stages> {
    let Some(calibration) = calibration.filter(|c| !c.is_none()) else {
        return Ok((None, None));
    };
    if let Ok(sensor) = calibration.extract::<PySensorCalibration>() {
        return Ok((Some(sensor.inner), None));
    }
    let attribute = |name: &str| {
        calibration.getattr(name).map_err(|_| {
            Error::value(
                "calibration",
                format!(
                    "expected a SensorCalibration or a harmonics.Calibration, got an object of \
                     type {} without '{name}'",
                    calibration.get_type()
                ),
            )
        })
    };
    let sensor: SensorParameters = attribute("sensor")?.extract()?;
    let (cos, sin): (Vec<f64>, Vec<f64>) =
        (attribute("cos")?.extract()?, attribute("sin")?.extract()?);
    let (sensor, correction) = angletrack::stored_stages(sensor, &cos, &sin)?;
    Ok((Some(sensor), Some(correction)))
}

/// The core's front end of the arguments (`angletrack::fixed_front_end`), clipped against
/// `adc_range` or the rails measured (`angletrack::clipping_rails`).
fn front_end(
    calibration: Option<&Bound<'_, PyAny>>,
    mid_scale_counts: Count,
    input_shift: Count,
    (adc_range, measure_adc_range): (Option<(i32, i32)>, bool),
) -> Result<TrackerFrontEnd<i16>> {
    let rails = clipping_rails(adc_range, measure_adc_range)?;
    let (sensor, correction) = stages(calibration)?;
    Ok(fixed_front_end(
        mid_scale_counts.get("mid_scale_counts")?,
        input_shift.get("input_shift")?,
        sensor.as_ref(),
        correction.as_ref(),
        rails,
    )?)
}

class_methods! {
    PyFixedObserver {
        /// The front-end faults latched (4: a sample clipped against `adc_range` or the rails
        /// measured).
        latched_front_end_faults: u8 = |this, py| this.tracker.latched_faults().1;
        /// The estimate after the last sample.
        estimate: FixedEstimate = |this, py| FixedEstimate { inner: this.tracker.estimate() };
        /// The integer constants (the dict `Design.fixed_constants()` returns): what
        /// `FixedObserver.from_constants` takes back.
        constants: Result<Bound<'py, PyDict>> = |this, py| constants_dict(py, this.tracker.constants());
        /// The gains the integers represent, `(l1, l2[, l3])` (float): the loop that runs.
        gains: Vec<f64> = |this, py| this.tracker.gains();
        /// The sample period `Ts` (s).
        sample_period_s: f64 = |this, py| this.tracker.sample_period();
        /// The observer order: 2 or 3.
        order: usize = |this, py| this.tracker.gains().len();
        /// The faults latched since they were last cleared (bits, see `angletrack.Faults`).
        latched_faults: u8 = |this, py| this.tracker.latched_faults().0;
    }
    methods {
        #[new]
        #[pyo3(signature = (design, *, nominal_amplitude = Some(16384.0), calibration = None,
            mid_scale_counts = Count::Whole(0), input_shift = Count::Whole(0), adc_range = None,
            measure_adc_range = false),
            text_signature = "(design, *, nominal_amplitude=16384.0, calibration=None, mid_scale_counts=0, input_shift=0, adc_range=None, measure_adc_range=False)")]
        fn py_new(
            design: &Bound<'_, PyAny>,
            nominal_amplitude: Option<f64>,
            calibration: Option<&Bound<'_, PyAny>>,
            mid_scale_counts: Count,
            input_shift: Count,
            adc_range: Option<(i32, i32)>,
            measure_adc_range: bool,
        ) -> Result<Self> {
            let gains = designed_gains(design)?;
            let range = (adc_range, measure_adc_range);
            let front_end = front_end(calibration, mid_scale_counts, input_shift, range)?;
            let period = gains.sample_period();
            let tracker = FixedTracker::of_gains(&gains.gains(), period, front_end, nominal_amplitude)?;
            Ok(Self { tracker })
        }

        /// The observer of the integer constants a firmware embeds: the dict
        /// `Design.fixed_constants()` returns (`multiplier`, `acceleration_shift`; other keys
        /// are ignored), at `sample_period_s` (s). Checked again by the core: `ConfigError`
        /// (parameter `constants`) naming the gain whose multiplier or shift is out of range or
        /// leaves the loop unstable.
        #[staticmethod]
        #[pyo3(signature = (constants, sample_period_s, *, nominal_amplitude = Some(16384.0),
            calibration = None, mid_scale_counts = Count::Whole(0), input_shift = Count::Whole(0),
            adc_range = None, measure_adc_range = false),
            text_signature = "(constants, sample_period_s, *, nominal_amplitude=16384.0, calibration=None, mid_scale_counts=0, input_shift=0, adc_range=None, measure_adc_range=False)")]
        #[allow(clippy::too_many_arguments)]
        fn from_constants(
            constants: &Bound<'_, PyAny>,
            sample_period_s: f64,
            nominal_amplitude: Option<f64>,
            calibration: Option<&Bound<'_, PyAny>>,
            mid_scale_counts: Count,
            input_shift: Count,
            adc_range: Option<(i32, i32)>,
            measure_adc_range: bool,
        ) -> Result<Self> {
            let multiplier: Vec<i32> =
                constant(constants, "multiplier", "a list of integers (int32)")?;
            let shift: u32 = constant(constants, "acceleration_shift", "an integer from 0 to 15")?;
            let range = (adc_range, measure_adc_range);
            let front_end = front_end(calibration, mid_scale_counts, input_shift, range)?;
            let tracker = FixedTracker::of_constants(
                &multiplier,
                shift,
                sample_period_s,
                front_end,
                nominal_amplitude,
            )?;
            Ok(Self { tracker })
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
            angletrack::ArgumentError::check_equal_lengths(("y_c", y_c.len()), ("y_s", y_s.len()))?;
            let tracker = &mut self.tracker;
            run_fixed(py, y_c.len(), |columns| {
                tracker.run(columns, y_c, y_s);
            })
        }

        /// Forgets the state: the next sample sets the angle from its `atan2`.
        fn reset(&mut self) {
            self.tracker.reset();
        }

        /// Returns the latched faults (bits) and clears them.
        fn clear_faults(&mut self) -> u8 {
            self.tracker.clear_faults()
        }

        fn __repr__(&self) -> String {
            let c = self.tracker.constants();
            format!(
                "FixedObserver(order={}, multiplier={:?}, acceleration_shift={}, sample_period_s={:e})",
                c.multiplier.len(),
                c.multiplier,
                c.acceleration_shift,
                self.tracker.sample_period()
            )
        }
    }
}
