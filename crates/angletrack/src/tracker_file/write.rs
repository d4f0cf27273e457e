//! The text of a tracker file: the gains file's layout (one member a line, the lists one
//! number a line, the design last), each setting one object of a `kind` or `rule`.

use angletrack_core::{FaultThresholds, SensorCalibration};
use serde_json::Value;

use super::{
    AdcRange, Calibration, Correction, Input, TRACKER_FILE_FORMAT, TRACKER_FILE_VERSION,
    TrackerFile,
};
use crate::calibration::file::SENSOR_FIELDS;
use crate::export::gains_file::{document, list};
use crate::json_file::number;

/// The members as one JSON object on a line.
fn inline(members: &[(&str, String)]) -> String {
    let items: Vec<String> = members
        .iter()
        .map(|(name, value)| format!("\"{name}\": {value}"))
        .collect();
    format!("{{{}}}", items.join(", "))
}

/// The members as a nested object, one a line.
fn nested(members: &[(&str, String)]) -> String {
    let items: Vec<String> = members
        .iter()
        .map(|(name, value)| format!("    \"{name}\": {value}"))
        .collect();
    format!("{{\n{}\n  }}", items.join(",\n"))
}

fn optional(value: Option<f64>) -> String {
    value.map_or("null".to_string(), number)
}

fn kind(name: &str) -> (&'static str, String) {
    ("kind", Value::from(name).to_string())
}

fn sensor(calibration: &SensorCalibration<f64>) -> String {
    let (o_c, o_s, a_c, a_s, q) = calibration.parameters();
    let members: Vec<(&str, String)> = SENSOR_FIELDS
        .iter()
        .zip([o_c, o_s, a_c, a_s, q])
        .map(|(&name, value)| (name, number(value)))
        .collect();
    inline(&members)
}

fn numbers(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|&v| number(v)).collect();
    format!("[{}]", items.join(", "))
}

fn input(input: &Input) -> String {
    match *input {
        Input::Units => nested(&[kind("units")]),
        Input::Counts => nested(&[kind("counts")]),
        Input::Bits { bits, signed } => nested(&[
            kind("counts"),
            ("bits", bits.to_string()),
            ("signed", signed.to_string()),
        ]),
        Input::Scaled {
            mid_scale,
            counts_per_unit,
        } => nested(&[
            kind("counts"),
            ("mid_scale", mid_scale.to_string()),
            ("counts_per_unit", number(counts_per_unit)),
        ]),
    }
}

fn adc_range(range: &AdcRange) -> String {
    let rule = |name: &str| ("rule", Value::from(name).to_string());
    match *range {
        AdcRange::Measured => nested(&[rule("measured")]),
        AdcRange::FullScale => nested(&[rule("full_scale")]),
        AdcRange::Stated { min, max } => {
            nested(&[rule("stated"), ("min", number(min)), ("max", number(max))])
        }
    }
}

fn thresholds(t: &FaultThresholds<f64>) -> String {
    nested(&[
        ("nominal_amplitude", number(t.nominal_amplitude)),
        ("max_input_amplitude", number(t.max_input_amplitude)),
        ("loss_of_signal", number(t.loss_of_signal)),
        ("degradation_low", number(t.degradation_low)),
        ("degradation_high", number(t.degradation_high)),
        ("loss_of_tracking", number(t.loss_of_tracking)),
        ("tracking_error", number(t.tracking_error)),
        ("max_speed_rad_s", optional(t.max_speed)),
        ("filter_factor", number(t.filter_factor)),
        ("false_lock", number(t.false_lock)),
        ("magnitude_tolerance", optional(t.magnitude_tolerance)),
        ("monitor", t.monitor.to_string()),
        ("re_acquire", t.re_acquire.to_string()),
    ])
}

fn calibration(calibration: &Calibration) -> String {
    match calibration {
        Calibration::None => nested(&[kind("none")]),
        Calibration::Stored(stored) => nested(&[kind("stored"), ("sensor", sensor(stored))]),
        Calibration::Online { initial, settings } => nested(&[
            kind("online"),
            (
                "initial",
                initial.as_ref().map_or("null".to_string(), sensor),
            ),
            ("min_speed_rad_s", optional(settings.min_speed_rad_s)),
            ("max_offset", number(settings.max_offset)),
            (
                "max_amplitude_mismatch",
                number(settings.max_amplitude_mismatch),
            ),
            ("max_quadrature_rad", number(settings.max_quadrature_rad)),
        ]),
    }
}

fn correction(correction: &Correction) -> String {
    match correction {
        Correction::None => nested(&[kind("none")]),
        Correction::Harmonics(harmonics) => {
            let (cos, sin) = harmonics.coefficients();
            nested(&[
                kind("harmonics"),
                ("cos", numbers(&cos)),
                ("sin", numbers(&sin)),
            ])
        }
        Correction::Table(errors) => nested(&[kind("table"), ("errors_rad", numbers(errors))]),
    }
}

impl TrackerFile {
    /// The JSON text of [`TRACKER_FILE_FORMAT`]: every setting written (none left to a
    /// default the reader might not share), the numbers as the shortest decimals that read
    /// back to the same `f64`.
    pub fn to_json(&self) -> String {
        let g = &self.gains;
        // A record, not a setting: written only when known.
        let predicted = self
            .predicted_error_rms_rad
            .map(|e| format!("  \"predicted_error_rms_rad\": {}", number(e)));
        document(
            vec![
                format!("  \"format\": \"{TRACKER_FILE_FORMAT}\""),
                format!("  \"version\": {TRACKER_FILE_VERSION}"),
                format!("  \"sample_period_s\": {}", number(g.sample_period_s)),
                format!("  \"gains\": {}", list(&g.gains, |&v| number(v))),
                format!("  \"number_type\": \"{}\"", self.number_type.name()),
                format!(
                    "  \"sin_cos\": {}",
                    self.sin_cos
                        .name()
                        .map_or("null".to_string(), |n| format!("\"{n}\""))
                ),
                format!("  \"input\": {}", input(&self.input)),
                format!("  \"adc_range\": {}", adc_range(&self.adc_range)),
                format!(
                    "  \"winding_check\": {}",
                    self.winding_amplitude
                        .map_or("null".to_string(), |a| nested(&[("amplitude", number(a))]))
                ),
                format!(
                    "  \"fault_thresholds\": {}",
                    self.fault_thresholds
                        .as_ref()
                        .map_or("null".to_string(), thresholds)
                ),
                format!("  \"calibration\": {}", calibration(&self.calibration)),
                format!("  \"correction\": {}", correction(&self.correction)),
                format!(
                    "  \"pole_pairs\": {}",
                    self.pole_pairs
                        .map_or("null".to_string(), |p| p.to_string())
                ),
            ]
            .into_iter()
            .chain(predicted)
            .collect(),
            g.design.as_ref(),
        )
    }
}
