//! The refusals of a design from a capture: each names what the capture lacks or the
//! argument at fault, on one line.

use core::fmt;

/// Why a capture cannot support a design, or an argument of
/// [`design_from_capture`](super::design_from_capture) is refused.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum DesignCaptureError {
    /// Fewer samples than the estimates need.
    TooShort {
        /// The capture's samples.
        samples: usize,
        /// The fewest accepted ([`MIN_SAMPLES`](super::MIN_SAMPLES)).
        needed: usize,
    },
    /// The shaft hardly moves: the signals trace no arc of the Lissajous ellipse to fit.
    Standstill {
        /// The angle travelled (rad).
        travelled_rad: f64,
    },
    /// The shaft turns too little for the ellipse fit and the motion's statistics.
    TooFewTurns {
        /// The turns travelled (forward and back both count).
        turns: f64,
        /// The fewest accepted ([`MIN_TURNS`](super::MIN_TURNS)).
        needed: f64,
    },
    /// Two series of different lengths.
    LengthMismatch {
        /// The series whose length differs from the cosine's (`sin`, `reference_angle_rad`).
        series: &'static str,
        /// Its length.
        len: usize,
        /// The cosine's length.
        expected: usize,
    },
    /// A sample is NaN or infinite.
    NotFinite {
        /// The series (`cos`, `sin`, `reference_angle_rad`).
        series: &'static str,
        /// The sample's index.
        index: usize,
    },
    /// The signals do not lie on an ellipse: a conic fit that is no ellipse, or a residual
    /// around it above [`MAX_NOISE_STD`](super::MAX_NOISE_STD) of its amplitude (a shaft at
    /// standstill, whose noise the fit takes for an ellipse).
    NoEllipse,
    /// An argument out of its range.
    Argument {
        /// The argument as the Rust caller writes it (`sample_period_s`, `max_overshoot`, ..).
        name: &'static str,
        /// What it must be.
        expected: &'static str,
    },
    /// Every candidate design breaks a constraint.
    NoDesign {
        /// The constraint the last candidate broke, as it is named in
        /// [`DesignConstraints`](super::DesignConstraints).
        constraint: &'static str,
    },
}

impl fmt::Display for DesignCaptureError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooShort { samples, needed } => write!(
                f,
                "capture too short: {samples} samples, at least {needed} needed"
            ),
            Self::Standstill { travelled_rad } => write!(
                f,
                "capture at standstill: the shaft travels {travelled_rad:.2} rad, \
                 the estimates need it turning"
            ),
            Self::TooFewTurns { turns, needed } => write!(
                f,
                "capture with too few turns: {turns:.2} turns travelled, at least {needed} needed"
            ),
            Self::LengthMismatch {
                series,
                len,
                expected,
            } => write!(
                f,
                "{series} has {len} samples, cos has {expected}: they must be the same length"
            ),
            Self::NotFinite { series, index } => {
                write!(f, "{series}[{index}] is not a finite number")
            }
            Self::NoEllipse => write!(
                f,
                "cos and sin do not trace the Lissajous ellipse: a shaft at standstill, or not \
                 the sensor's two channels?"
            ),
            Self::Argument { name, expected } => write!(f, "{name} must be {expected}"),
            Self::NoDesign { constraint } => write!(
                f,
                "no candidate design meets {constraint} (with the other constraints)"
            ),
        }
    }
}

impl std::error::Error for DesignCaptureError {}
