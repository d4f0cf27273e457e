//! The chosen design as a tracker file, its prediction and estimates recorded.

use serde_json::{Value, json};

use super::CaptureDesign;
use crate::export::GainsFile;
use crate::tracker_file::{Input, NumberType, TrackerFile};

impl CaptureDesign {
    /// The tracker file of the chosen design in the constraints' number type (fixed point:
    /// on counts, their mid-scale measured), its other settings the defaults, with
    /// `predicted_error_rms_rad` and the estimates under `design`.
    pub fn tracker_file(&self) -> TrackerFile {
        let design = &self.chosen.design;
        let gains = GainsFile {
            gains: design.gains(),
            sample_period_s: design.sample_period(),
            design: Some(self.record()),
        };
        let number_type = self.constraints.number_type;
        TrackerFile {
            number_type,
            input: if number_type == NumberType::Fixed {
                Input::Counts
            } else {
                Input::Units
            },
            predicted_error_rms_rad: Some(self.chosen.predicted.total_rad),
            ..TrackerFile::new(gains)
        }
    }

    /// What the design came from, as the tracker file's `design` member.
    fn record(&self) -> Value {
        let e = &self.estimates;
        let p = &self.chosen.predicted;
        json!({
            "method": "design from a capture",
            "observer": self.chosen.family.name(),
            "bandwidth_hz": self.chosen.bandwidth_hz,
            "predicted_error_parts_rad": {
                "noise": p.noise_rad, "lag": p.lag_rad, "number_type": p.number_type_rad,
            },
            "noise_std": e.noise.std.value,
            "noise_std_uncertainty": e.noise.std.std,
            "jerk_std_rad_s3": e.motion.jerk_std_rad_s3.value,
            "jerk_std_uncertainty_rad_s3": e.motion.jerk_std_rad_s3.std,
            "jerk_by_als": e.motion.jerk_by_als,
            "jerk_by_differences_rad_s3": e.motion.jerk_by_differences_rad_s3.value,
            "als": e.als.map(|a| json!({
                "jerk_std_rad_s3": a.jerk_std_rad_s3.value,
                "jerk_std_uncertainty_rad_s3": a.jerk_std_rad_s3.std,
                "noise_std": a.noise_std.value,
                "noise_std_uncertainty": a.noise_std.std,
            })),
            "motion_from_reference": e.motion.from_reference,
        })
    }
}
