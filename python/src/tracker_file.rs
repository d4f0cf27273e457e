//! The tracker files of `angletrack::tracker_file` on JSON text: the crate reads, checks
//! and writes them; the Python package edits the document as a dict and hands it back.

use angletrack::CalibrationFile;
use angletrack::export::GainsFile;
use angletrack::tracker_file::{FirmwareError, TrackerFile};
use pyo3::prelude::*;

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
    Ok(())
}
