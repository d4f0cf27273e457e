//! Design from a capture (`docs/theory.md §16`): the observer chosen from the user's own
//! recording, with its RMS angle error predicted.
//!
//! [`estimate_from_capture`] measures what every design function otherwise asks for: the
//! sensor noise per channel (white and coloured, quantisation included) from the radial
//! residual around the fitted Lissajous ellipse, and the motion (the jerk's standard
//! deviation, and the angle the loops' lag is predicted on) from the reference angle when
//! the capture has one, else from the signals' own angle smoothed by a first-pass loop
//! whose noise is accounted for. [`choose_design`] then tries the 2nd-order, 3rd-order and
//! Kalman observers over a grid of bandwidths and keeps the one of least predicted RMS
//! angle error under the [`DesignConstraints`]; [`design_from_capture`] does both.
//!
//! ```
//! use angletrack::design_capture::{CaptureSignals, DesignConstraints, design_from_capture};
//! let ts = 1e-4;
//! let angle: Vec<f64> = (0..20_000).map(|k| 200.0 * k as f64 * ts).collect();
//! let dither = |k: usize| 0.005 * (k as f64 * 2.399).sin();
//! let cos: Vec<f64> = angle.iter().enumerate().map(|(k, a)| a.cos() + dither(k)).collect();
//! let sin: Vec<f64> = angle.iter().enumerate().map(|(k, a)| a.sin() - dither(k + 7)).collect();
//! let signals = CaptureSignals { cos: &cos, sin: &sin, sample_period_s: ts,
//!     reference_angle_rad: None, quantisation_step: None };
//! let constraints = DesignConstraints { grid_points: 6, ..DesignConstraints::default() };
//! let design = design_from_capture(&signals, &constraints)?;
//! let tracker = design.tracker_file();
//! assert_eq!(tracker.predicted_error_rms_rad, Some(design.chosen.predicted.total_rad));
//! let report = design.report(10);
//! assert_eq!(report["chosen"]["observer"], design.chosen.family.name());
//! assert_eq!(report["spectra"]["noise_rad2_per_hz"].as_array().map(Vec::len), Some(10));
//! # Ok::<(), angletrack::design_capture::DesignCaptureError>(())
//! ```

mod als;
mod choice;
mod ellipse;
mod error;
mod estimate;
mod jerk;
mod linear_loop;
mod noise;
mod report;
mod tracker;

pub use als::AlsEstimate;
pub use choice::{
    CaptureCandidate, CaptureDesign, DesignConstraints, GRID_SPAN, ObserverFamily,
    PredictedErrorParts, choose_design,
};
pub use error::DesignCaptureError;
pub use estimate::{
    CaptureEstimates, CaptureSignals, MAX_NOISE_STD, MIN_SAMPLES, MIN_TURNS, MotionEstimate,
    NoiseEstimate, SKIP_FRACTION, Uncertain, estimate_from_capture,
};

/// [`estimate_from_capture`] then [`choose_design`].
///
/// ```
/// use angletrack::design_capture::{CaptureSignals, DesignConstraints, design_from_capture};
/// let cos = vec![1.0; 10];
/// let signals = CaptureSignals { cos: &cos, sin: &cos, sample_period_s: 1e-4,
///     reference_angle_rad: None, quantisation_step: None };
/// let e = design_from_capture(&signals, &DesignConstraints::default()).unwrap_err();
/// assert_eq!(e.to_string(), "capture too short: 10 samples, at least 2000 needed");
/// ```
pub fn design_from_capture(
    signals: &CaptureSignals<'_>,
    constraints: &DesignConstraints,
) -> Result<CaptureDesign, DesignCaptureError> {
    choose_design(estimate_from_capture(signals)?, constraints)
}

#[cfg(test)]
mod tests;
