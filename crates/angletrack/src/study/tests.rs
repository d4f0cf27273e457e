use std::path::Path;

use super::Study;

/// A study of one sensor of `sensor` turning at 300 rad/s for 1 s at 10 kHz through the
/// tracker `tracker` (fields beside the gains).
fn spec(sensor: &str, tracker: &str) -> String {
    format!(
        r#"{{"format": "angletrack-study", "version": 1, "seed": 3, "sensors": 1,
        "sample_period_s": 1e-4, "skip_s": 0.5, "sensor": {{{sensor}}},
        "profiles": {{"cruise": {{"initial_speed_rad_s": 300.0,
            "segments": [{{"constant_speed": {{"speed_rad_s": 300.0, "duration_s": 1.0}}}}]}}}},
        "setups": {{"online": {{"tracker": {{"format": "angletrack-tracker", "version": 1,
            "sample_period_s": 1e-4, "gains": [0.06, 0.0019, 3e-5]{tracker}}}}}}}}}"#
    )
}

fn error(text: &str) -> String {
    Study::from_json(text, "s.json", Path::new("."))
        .unwrap_err()
        .to_string()
}

#[test]
fn an_online_calibration_learns_the_drawn_sensor_and_removes_its_error() {
    let sensor = r#""offset_cos": 0.05, "amplitude_imbalance": 0.1, "noise_std": 0.001"#;
    let online = r#", "calibration": {"kind": "online"}"#;
    let learned = Study::from_json(&spec(sensor, online), "s.json", Path::new("."))
        .unwrap()
        .run(0);
    assert_eq!(learned.error, None);
    let [o_c, _, a_c, a_s, _] = learned.learned;
    assert!((o_c - 0.05).abs() < 2e-3, "{o_c}");
    assert!((a_s / a_c - 1.1).abs() < 2e-3, "{a_c} {a_s}");
    let plain = Study::from_json(&spec(sensor, ""), "s.json", Path::new("."))
        .unwrap()
        .run(0);
    assert!(plain.learned[0].is_nan());
    // The offset's error (about 0.05 rad peak) is gone once learned.
    assert!(plain.max_error_rad > 0.03 && learned.rms_error_rad < 0.005);
}

#[test]
fn the_fixed_point_chain_tracks_the_sensors_adc_codes_as_the_float_one_does() {
    let sensor = r#""offset_cos": 0.01, "noise_std": 0.001, "adc_bits": 12"#;
    let fixed = r#", "number_type": "fixed", "input": {"kind": "counts", "bits": 12, "signed": false},
        "adc_range": {"rule": "full_scale"}"#;
    let run = |tracker: &str| {
        Study::from_json(&spec(sensor, tracker), "s.json", Path::new("."))
            .unwrap()
            .run(0)
    };
    let (fixed, float) = (run(fixed), run(""));
    assert_eq!((&fixed.error, fixed.number_type), (&None, "fixed"));
    // The offset's error, about 10 mrad peak, in both; the integers add little.
    assert!(
        (fixed.max_error_rad - float.max_error_rad).abs() < 1e-3,
        "{} {}",
        fixed.max_error_rad,
        float.max_error_rad
    );
    assert!(
        fixed.max_error_rad > 5e-3 && fixed.fault_samples == 0,
        "{fixed:?}"
    );
}

#[test]
fn the_angle_error_harmonics_drawn_are_in_the_signals_and_the_row() {
    let sensor = r#""angle_error_harmonics": [{"order": 3, "amplitude_rad": {"uniform": {"low": 0.004, "high": 0.005}}, "phase_rad": 0.3}]"#;
    let row = Study::from_json(&spec(sensor, ""), "s.json", Path::new("."))
        .unwrap()
        .run(0);
    let amplitude = row.angle_error_harmonics[0].1;
    assert!((0.004..0.005).contains(&amplitude) && row.angle_error_harmonics[0].2 == 0.3);
    let names: Vec<String> = row.columns().into_iter().map(|(name, _)| name).collect();
    assert!(
        names.contains(&"angle_error_h3_rad".to_string())
            && names.contains(&"angle_error_h3_phase_rad".to_string())
    );
    // The loop follows the sensor's reading: its error against the truth is the harmonic's,
    // within the loop's filtering of 143 Hz.
    assert!(
        row.max_error_rad > 0.5 * amplitude && row.max_error_rad < 2.0 * amplitude,
        "{} {amplitude}",
        row.max_error_rad
    );
    let repeated = r#""angle_error_harmonics": [{"order": 3}, {"order": 3}]"#;
    assert_eq!(
        error(&spec(repeated, "")),
        "s.json: sensor.angle_error_harmonics[1].order: must be a whole number from 1 to 32, each order once"
    );
}

#[test]
fn a_bad_spec_is_refused_naming_the_field() {
    assert_eq!(
        error(&spec(r#""offset_cos": {"normal": {"mean": 0.0}}"#, "")),
        "s.json: sensor.offset_cos.normal.std: missing"
    );
    assert_eq!(
        error(&spec(r#""offset": 0.1"#, "")),
        "s.json: sensor.offset: unknown field (expected one of: amplitude, offset_cos, offset_sin, \
         amplitude_imbalance, quadrature_error_rad, third_harmonic, noise_std, angle_error_harmonics, adc_bits, \
         adc_full_scale)"
    );
    let fixed = error(&spec(
        "",
        r#", "number_type": "fixed", "input": {"kind": "counts", "bits": 12, "signed": true}"#,
    ));
    assert!(
        fixed.starts_with(
            "s.json: setups.online.tracker.input: number_type \"fixed\" tracks the sensor's ADC codes"
        ),
        "{fixed}"
    );
    let other_rate = spec("", "").replace(
        "\"sample_period_s\": 1e-4, \"skip",
        "\"sample_period_s\": 5e-5, \"skip",
    );
    assert_eq!(
        error(&other_rate),
        "s.json: setups.online.tracker.sample_period_s: 0.0001 s, but the study samples every 0.00005 s \
         (sample_period_s): design the gains for the study's rate"
    );
}

#[test]
fn a_setups_tracker_refused_by_its_reader_is_named_as_the_specs_field() {
    assert_eq!(
        error(&spec("", r#", "number_type": "f16""#)),
        "s.json: setups.online.tracker.number_type: expected \"f32\", \"f64\" or \"fixed\", got \"f16\""
    );
}

#[test]
fn a_drawn_sensor_out_of_the_models_range_is_a_row_with_its_error() {
    let study = Study::from_json(
        &spec(r#""amplitude_imbalance": -2.0"#, ""),
        "s.json",
        Path::new("."),
    )
    .unwrap();
    let row = study.run(0);
    assert!(
        row.error.unwrap().starts_with("sensor: "),
        "{:?}",
        study.run(0).error
    );
    assert!(row.rms_error_rad.is_nan());
    assert!(
        study
            .run(1)
            .error
            .unwrap()
            .contains("beyond the study's 1 runs")
    );
}
