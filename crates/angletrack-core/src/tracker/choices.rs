//! The standard chain's choices of calibration and angle correction as stages, one type
//! each, so that a configuration chosen at start-up (from a tracker file, a C call or a
//! Python argument) is one `Copy` value of one type: [`CalibrationStage`] (none, a stored
//! calibration or the online one) and [`CorrectionStage`] (none, the harmonics or their
//! table) for the float observers, [`FixedCalibrationStage`] and [`FixedCorrectionStage`]
//! for the fixed-point one. Each delegates every [`Stage`] method to the stage it holds.

use crate::angle_correction::AngleCorrection;
use crate::angle_table::{AngleCorrectionTable, FixedAngleCorrectionTable};
use crate::calibration::{FixedCalibration, SensorCalibration};
use crate::chain::{Feedback, OnlineCalibration, Prediction, Stage};
use crate::faults::Faults;
use crate::learning::Calibrator;
use crate::real::Float;

/// The entries of the standard chain's angle-correction table over one electrical turn
/// (the error at `-pi + 2 pi k / 256`, interpolated linearly): 256 entries hold a
/// correction of the 8th harmonic within 0.4 % of its amplitude.
pub const TRACKER_TABLE_LENGTH: usize = 256;

/// The float chain's sensor calibration: none, a stored one applied to every sample, or
/// the online one (its estimate in the channel's [`Calibrator`], learned while tracking).
///
/// ```
/// use angletrack_core::{CalibrationStage, SensorCalibration};
/// let stored = SensorCalibration::<f32>::new(0.02, -0.01, 1.0, 1.05, 0.01)?;
/// let stage = CalibrationStage::Stored(stored);
/// assert_ne!(stage, CalibrationStage::None);
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum CalibrationStage<T> {
    /// No calibration: the samples as they come.
    #[default]
    None,
    /// A stored calibration (offsets, amplitudes, quadrature), applied to every sample.
    Stored(SensorCalibration<T>),
    /// The online calibration: its settings; its estimate is the channel's
    /// [`Calibrator`], off until enabled.
    Online(OnlineCalibration<T>),
}

impl<T: Float> Stage<T, (T, T)> for CalibrationStage<T> {
    type State = Calibrator<T>;
    type Memo = (T, T);

    #[inline(always)]
    fn forward(
        &self,
        calibrator: &mut Calibrator<T>,
        prediction: &impl Prediction<T>,
        input: (T, T),
    ) -> ((T, T), (T, T)) {
        match self {
            CalibrationStage::None => (input, input),
            CalibrationStage::Stored(stored) => {
                (stored.forward(&mut (), prediction, input).0, input)
            }
            CalibrationStage::Online(online) => online.forward(calibrator, prediction, input),
        }
    }

    #[inline(always)]
    fn feedback(&self, calibrator: &mut Calibrator<T>, raw: (T, T), used: Option<Feedback<T>>) {
        if let CalibrationStage::Online(online) = self {
            online.feedback(calibrator, raw, used);
        }
    }

    #[inline(always)]
    fn faults(&self, calibrator: &mut Calibrator<T>) -> Faults {
        match self {
            CalibrationStage::Online(online) => online.faults(calibrator),
            _ => Faults::NONE,
        }
    }

    #[inline(always)]
    fn quiet(&self, calibrator: &Calibrator<T>) -> bool {
        match self {
            CalibrationStage::Online(online) => online.quiet(calibrator),
            _ => true,
        }
    }
}

/// The float chain's angle correction: none, the harmonic one, or its table of
/// [`TRACKER_TABLE_LENGTH`] entries. As large as the table whatever it holds (`Copy`, no
/// heap: firmware keeps it in flash).
///
/// ```
/// use angletrack_core::{AngleCorrection, CorrectionStage};
/// let harmonics = AngleCorrection::<f32>::new([0.0; 8], [0.0, 0.004, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])?;
/// let stage = CorrectionStage::Harmonics(harmonics);
/// assert_ne!(stage, CorrectionStage::None);
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum CorrectionStage<T> {
    /// No correction.
    #[default]
    None,
    /// The harmonic angle correction.
    Harmonics(AngleCorrection<T>),
    /// The angle error's table.
    Table(AngleCorrectionTable<T, TRACKER_TABLE_LENGTH>),
}

impl<T: Float> Stage<T, (T, T)> for CorrectionStage<T> {
    type State = ();
    type Memo = ();

    #[inline(always)]
    fn forward(
        &self,
        state: &mut (),
        prediction: &impl Prediction<T>,
        input: (T, T),
    ) -> ((T, T), ()) {
        match self {
            CorrectionStage::None => (input, ()),
            CorrectionStage::Harmonics(h) => h.forward(state, prediction, input),
            CorrectionStage::Table(t) => t.forward(state, prediction, input),
        }
    }

    #[inline(always)]
    fn quiet(&self, _: &()) -> bool {
        true
    }
}

/// The fixed-point chain's sensor calibration: none or a stored one, in integers (the
/// fixed-point observer has no online calibration).
pub type FixedCalibrationStage = Option<FixedCalibration>;

/// The fixed-point chain's angle correction: none or the table in integers.
pub type FixedCorrectionStage = Option<FixedAngleCorrectionTable<TRACKER_TABLE_LENGTH>>;
