//! The design chosen from a capture as one JSON document: what the Python binding returns
//! as a dict and the CLI plots, written once here.

use serde_json::{Value, json};

use super::{CaptureCandidate, CaptureDesign, Uncertain};

fn uncertain(u: Uncertain) -> Value {
    json!({"value": u.value, "std": u.std})
}

impl CaptureCandidate {
    /// The candidate: `observer`, `bandwidth_hz`, `gains`, `predicted_error_rms_rad` and its
    /// parts `noise_rad`, `lag_rad`, `number_type_rad`, and `refused_by`.
    pub fn report(&self) -> Value {
        let p = &self.predicted;
        json!({
            "observer": self.family.name(), "bandwidth_hz": self.bandwidth_hz,
            "gains": self.design.gains(), "predicted_error_rms_rad": p.total_rad,
            "noise_rad": p.noise_rad, "lag_rad": p.lag_rad,
            "number_type_rad": p.number_type_rad, "refused_by": self.refused_by,
        })
    }
}

impl CaptureDesign {
    /// The design with what it was chosen from: `tracker_json` (the tracker file),
    /// `chosen`, `predicted_error_rms_rad`, `runners_up` and `candidates` (each a
    /// [`CaptureCandidate::report`]), the estimates `noise`, `motion` and `als` (`null`
    /// without), and `spectra` (`frequency_hz`, `noise_rad2_per_hz`, `motion_rad2_per_hz`
    /// at `spectrum_points` frequencies).
    pub fn report(&self, spectrum_points: usize) -> Value {
        let (e, n, m) = (
            &self.estimates,
            &self.estimates.noise,
            &self.estimates.motion,
        );
        let points = e.spectra(spectrum_points);
        let column =
            |pick: fn(&(f64, f64, f64)) -> f64| points.iter().map(pick).collect::<Vec<_>>();
        let reports =
            |c: &[CaptureCandidate]| c.iter().map(CaptureCandidate::report).collect::<Vec<_>>();
        json!({
            "tracker_json": self.tracker_file().to_json(),
            "chosen": self.chosen.report(),
            "predicted_error_rms_rad": self.chosen.predicted.total_rad,
            "runners_up": reports(&self.runners_up),
            "candidates": reports(&self.candidates),
            "noise": {
                "amplitude": n.amplitude, "std": uncertain(n.std), "cos_std": uncertain(n.cos_std),
                "sin_std": uncertain(n.sin_std), "white_std": n.white_std,
                "coloured_std": n.coloured_std, "coloured_pole": n.coloured_pole,
                "quantisation_std": n.quantisation_std,
            },
            "motion": {
                "jerk_std_rad_s3": uncertain(m.jerk_std_rad_s3),
                "jerk_by_differences_rad_s3": uncertain(m.jerk_by_differences_rad_s3),
                "jerk_by_als": m.jerk_by_als, "from_reference": m.from_reference,
                "turns": m.turns, "initial_speed_rad_s": m.initial_speed_rad_s,
                "first_pass_bandwidth_hz": e.first_pass_bandwidth_hz,
            },
            "als": e.als.map(|a| json!({
                "jerk_std_rad_s3": uncertain(a.jerk_std_rad_s3), "noise_std": uncertain(a.noise_std),
                "first_pass_bandwidth_hz": a.first_pass_bandwidth_hz, "lags": a.lags,
            })),
            "spectra": {
                "frequency_hz": column(|p| p.0), "noise_rad2_per_hz": column(|p| p.1),
                "motion_rad2_per_hz": column(|p| p.2),
            },
        })
    }
}
