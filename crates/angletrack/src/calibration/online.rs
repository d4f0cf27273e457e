//! The online calibration a user chooses (the Python API's `calibration` and
//! `initial_calibration`): off, learning (from a calibration given, or from none) or frozen
//! at a calibration given; and the names of the core's modes and statuses.

use core::fmt;

use angletrack_core::{
    CalibrationMode, CalibrationStatus, Calibrator, ConfigError, Real, SensorCalibration,
};

/// The online calibration chosen: its mode and the calibration it starts from.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OnlineCalibrationChoice {
    mode: CalibrationMode,
    initial: Option<SensorCalibration<f64>>,
}

/// A refused choice: the argument at fault (`calibration` or `initial_calibration`) and why.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationChoiceError {
    /// The argument.
    pub argument: &'static str,
    /// What is wrong (without the argument's name).
    pub reason: String,
}

impl fmt::Display for CalibrationChoiceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.argument, self.reason)
    }
}

impl std::error::Error for CalibrationChoiceError {}

impl OnlineCalibrationChoice {
    /// The choice of the mode named `mode` ([`mode_name`]'s names, `None` for off) from
    /// `initial`: refused for an unknown name, a calibration given with the calibration
    /// off (it would be reported but not applied), or frozen without one.
    ///
    /// ```
    /// use angletrack::{OnlineCalibrationChoice, SensorCalibration};
    /// let given = SensorCalibration::new(0.01, 0.0, 1.0, 1.02, 0.0).unwrap();
    /// assert!(OnlineCalibrationChoice::new(Some("frozen"), Some(given)).is_ok());
    /// let refused = OnlineCalibrationChoice::new(None, Some(given)).unwrap_err();
    /// assert_eq!(refused.argument, "initial_calibration");
    /// ```
    pub fn new(
        mode: Option<&str>,
        initial: Option<SensorCalibration<f64>>,
    ) -> Result<Self, CalibrationChoiceError> {
        let refused = |argument, reason: &str| {
            let reason = reason.to_string();
            Err(CalibrationChoiceError { argument, reason })
        };
        let mode = match mode {
            None | Some("off") => CalibrationMode::Off,
            Some("learn") => CalibrationMode::Learning,
            Some("frozen") => CalibrationMode::Frozen,
            Some(other) => {
                let expected = format!("expected None, 'learn' or 'frozen', got {other:?}");
                return refused("calibration", &expected);
            }
        };
        match (mode, initial) {
            (CalibrationMode::Off, Some(_)) => refused(
                "initial_calibration",
                "is applied only with calibration='learn' or 'frozen' (the calibration is off)",
            ),
            (CalibrationMode::Frozen, None) => refused(
                "initial_calibration",
                "is needed with calibration='frozen' (the calibration to apply)",
            ),
            _ => Ok(Self { mode, initial }),
        }
    }

    /// The core's calibrator of the choice in `T` (the calibration given converted, checked
    /// again there).
    pub fn calibrator<T: Real>(&self) -> Result<Calibrator<T>, ConfigError> {
        let mut calibrator = match &self.initial {
            Some(c) => Calibrator::from_calibration(converted_calibration(c)?),
            None => Calibrator::new(),
        };
        match self.mode {
            CalibrationMode::Off => calibrator.disable(),
            CalibrationMode::Learning => calibrator.enable(),
            CalibrationMode::Frozen => calibrator.freeze(),
        }
        Ok(calibrator)
    }
}

/// `calibration` in the float type `U`, checked again there (rounding to `f32` may
/// refuse it; widening to `f64` keeps it).
pub fn converted_calibration<T: Real, U: Real>(
    calibration: &SensorCalibration<T>,
) -> Result<SensorCalibration<U>, ConfigError> {
    let f = |x: T| U::from_f64(x.to_f64());
    let (o_c, o_s, a_c, a_s, phi) = calibration.parameters();
    SensorCalibration::new(f(o_c), f(o_s), f(a_c), f(a_s), f(phi))
}

/// The name of a calibration mode: `"off"`, `"learn"` or `"frozen"`.
pub fn mode_name(mode: CalibrationMode) -> &'static str {
    match mode {
        CalibrationMode::Off => "off",
        CalibrationMode::Learning => "learn",
        CalibrationMode::Frozen => "frozen",
    }
}

/// The name of a calibrator's status: `"finding-centre"`, `"centred"` or `"stalled"`.
pub fn status_name(status: CalibrationStatus) -> &'static str {
    match status {
        CalibrationStatus::FindingCentre => "finding-centre",
        CalibrationStatus::Centred => "centred",
        CalibrationStatus::Stalled => "stalled",
    }
}
