//! The tracker files of `angletrack::tracker_file` on JSON text: the crate reads, checks
//! and writes them; the Python package edits the document as a dict and hands it back.

use angletrack::CalibrationFile;
use angletrack::CaptureCounts;
use angletrack::export::GainsFile;
use angletrack::tracker_file::{CaptureHead, FirmwareError, TrackerFile, TrackerRun};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::angle_calibration::SensorParameters;
use crate::errors::{Error, Result};

/// The tracker file's JSON `text` checked (`file` names it in errors), written again as
/// the crate writes it: every setting present, the numbers exact.
#[pyfunction]
pub fn checked_tracker_file(text: &str, file: &str) -> Result<String> {
    Ok(TrackerFile::from_json(text, file)?.to_json())
}

/// The tracker file's JSON text of a gains file (`gains_text`, named `gains_file` in
/// errors), the other settings at their defaults (`TrackerFile::new`).
#[pyfunction]
pub fn tracker_file_from_gains(gains_text: &str, gains_file: &str) -> Result<String> {
    Ok(TrackerFile::new(GainsFile::from_json(gains_text, gains_file)?).to_json())
}

/// The tracker file of `tracker_text` with the calibration of a calibration file of either
/// kind in place of its own (`TrackerFile::with_calibration_file`); the names are the
/// files' in errors.
#[pyfunction]
pub fn tracker_file_with_calibration(
    tracker_text: &str,
    tracker_file: &str,
    calibration_text: &str,
    calibration_file: &str,
) -> Result<String> {
    let tracker = TrackerFile::from_json(tracker_text, tracker_file)?;
    let calibration = CalibrationFile::from_json(calibration_text, calibration_file)?;
    Ok(tracker.with_calibration_file(&calibration).to_json())
}

/// The firmware constants of the tracker file's JSON `text` (`file` names it in errors):
/// `language` `"c"` (a header) or `"rust"` (`const`s), every identifier prefixed by `name`
/// (`TrackerFile::firmware_constants`).
#[pyfunction]
pub fn tracker_firmware_constants(
    text: &str,
    file: &str,
    language: &str,
    name: &str,
) -> Result<String> {
    let language = crate::export::language(language)?;
    TrackerFile::from_json(text, file)?
        .firmware_constants(file, language, name)
        .map_err(|e| match e {
            FirmwareError::File(e) => Error::JsonFile(e),
            FirmwareError::Export(e) => Error::Export(e),
        })
}

fn contiguous<'a>(y: &'a PyReadonlyArray1<'_, f64>, name: &'static str) -> Result<&'a [f64]> {
    y.as_slice()
        .map_err(|_| Error::value(name, "a contiguous float64 array"))
}

/// A tracker file's chain (`angletrack::tracker_file::TrackerRun`), fed a capture chunk
/// by chunk: what `Tracker.track` and `angletrack track --tracker` hold.
#[derive(Debug)]
#[pyclass(name = "TrackerRun", module = "angletrack._angletrack")]
pub struct PyTrackerRun {
    run: TrackerRun,
}

#[pymethods]
impl PyTrackerRun {
    /// The chain of the tracker file's JSON `text` (`file` names it in errors), its open
    /// settings measured on the capture's first samples `y_c`, `y_s`; `mid_scale`: the
    /// counts' mid-scale decided on the whole capture, for counts the file leaves it open.
    #[new]
    #[pyo3(signature = (text, file, y_c, y_s, mid_scale=None))]
    fn new(
        text: &str,
        file: &str,
        y_c: PyReadonlyArray1<'_, f64>,
        y_s: PyReadonlyArray1<'_, f64>,
        mid_scale: Option<u64>,
    ) -> Result<Self> {
        let tracker = TrackerFile::from_json(text, file)?;
        let counts = mid_scale.map(CaptureCounts::of_mid_scale);
        let head = CaptureHead {
            y_c: contiguous(&y_c, "y_c")?,
            y_s: contiguous(&y_s, "y_s")?,
            counts,
        };
        Ok(Self {
            run: TrackerRun::new(&tracker, file, &head)?,
        })
    }

    /// The estimates of the next samples `y_c`, `y_s` (float64, equal lengths): a dict of
    /// the arrays `angle_rad`, `position_rad`, `speed_rad_s`, `acceleration_rad_s2`,
    /// `phase_error` (float64), `faults`, `front_end_faults` (uint8) and, for fixed point,
    /// `angle_binary` (int32).
    fn track<'py>(
        &mut self,
        py: Python<'py>,
        y_c: PyReadonlyArray1<'py, f64>,
        y_s: PyReadonlyArray1<'py, f64>,
    ) -> Result<Bound<'py, PyDict>> {
        let (y_c, y_s) = (contiguous(&y_c, "y_c")?, contiguous(&y_s, "y_s")?);
        angletrack::ArgumentError::check_equal_lengths(("y_c", y_c.len()), ("y_s", y_s.len()))?;
        let fixed = self.run.is_fixed();
        let run = &mut self.run;
        let rows = py.detach(|| run.track(y_c, y_s));
        let out = PyDict::new(py);
        for (name, column) in [
            ("angle_rad", rows.angle_rad),
            ("position_rad", rows.position_rad),
            ("speed_rad_s", rows.speed_rad_s),
            ("acceleration_rad_s2", rows.acceleration_rad_s2),
            ("phase_error", rows.phase_error),
        ] {
            out.set_item(name, PyArray1::from_vec(py, column))?;
        }
        for (name, column) in [
            ("faults", rows.faults),
            ("front_end_faults", rows.front_end_faults),
        ] {
            out.set_item(name, PyArray1::from_vec(py, column))?;
        }
        if fixed {
            out.set_item("angle_binary", PyArray1::from_vec(py, rows.angle_binary))?;
        }
        Ok(out)
    }

    /// The observer's and the front end's faults latched since the start, as bits.
    #[getter]
    fn latched_faults(&self) -> (u8, u8) {
        let (faults, front_end) = self.run.latched_faults();
        (faults.bits(), front_end.bits())
    }

    /// What the online calibration learned: `(calibration, turns_learned, status)`, the
    /// calibration as `(offset_c, offset_s, amplitude_c, amplitude_s, quadrature_rad)`;
    /// `None` without an online calibration.
    #[getter]
    fn learning(&self) -> Option<(SensorParameters, u32, &'static str)> {
        self.run
            .learning()
            .map(|l| (l.calibration.parameters(), l.turns_learned, l.status))
    }

    fn __repr__(&self) -> String {
        self.run.describe()
    }
}

/// Adds the functions and the format's name and version to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add(
        "TRACKER_FILE_FORMAT",
        angletrack::tracker_file::TRACKER_FILE_FORMAT,
    )?;
    m.add(
        "TRACKER_FILE_VERSION",
        angletrack::tracker_file::TRACKER_FILE_VERSION,
    )?;
    m.add_function(wrap_pyfunction!(checked_tracker_file, m)?)?;
    m.add_function(wrap_pyfunction!(tracker_file_from_gains, m)?)?;
    m.add_function(wrap_pyfunction!(tracker_file_with_calibration, m)?)?;
    m.add_function(wrap_pyfunction!(tracker_firmware_constants, m)?)?;
    m.add_class::<PyTrackerRun>()?;
    Ok(())
}
