use angletrack_core::{
    AngleCorrection, CalibrationSettings, FaultThresholds, FixedGains, SensorCalibration,
};

use super::*;
use crate::calibration::SensorCalibrationRecord;
use crate::calibration::{CalibrationMethod, CaptureCalibration, OrderQuality, SPECTRUM_ORDERS};

fn gains() -> GainsFile {
    GainsFile {
        gains: vec![0.095_16, 0.004_757, 1.189e-4],
        sample_period_s: 50e-6,
        design: Some(serde_json::json!({"method": "kalman", "jerk_std": 1e5})),
    }
}

fn sensor() -> SensorCalibration<f64> {
    SensorCalibration::new(90.0, -90.0, 1800.0, 1980.0, 0.0524).unwrap()
}

/// A setup with every setting away from its default.
fn full() -> TrackerFile {
    let mut settings = CalibrationSettings::default();
    settings.min_speed_rad_s = Some(50.0);
    settings.max_offset = 0.05;
    TrackerFile {
        gains: gains(),
        number_type: NumberType::F32,
        sin_cos: SinCosKind::Exact,
        input: Input::Scaled {
            mid_scale: 2048,
            counts_per_unit: 1800.0,
        },
        adc_range: AdcRange::Stated {
            min: -1.1377,
            max: 1.1372,
        },
        winding_amplitude: Some(1.0),
        fault_thresholds: Some(
            FaultThresholds::for_amplitude(0.88)
                .with_max_speed(Some(3000.0))
                .with_tracking_error(0.04)
                .with_magnitude_tolerance(Some(0.2))
                .with_re_acquire(false),
        ),
        calibration: Calibration::Online {
            initial: Some(sensor()),
            settings,
        },
        correction: Correction::Table(vec![0.0, 0.002, 0.0, -0.002]),
        pole_pairs: Some(4),
        predicted_error_rms_rad: Some(2.5e-4),
    }
}

fn read(text: &str) -> Result<TrackerFile, JsonFileError> {
    TrackerFile::from_json(text, "t.json")
}

#[test]
fn every_setting_reads_back_identical() {
    let mut harmonics = full();
    harmonics.calibration = Calibration::Stored(sensor());
    harmonics.input = Input::Bits {
        bits: 12,
        signed: false,
    };
    harmonics.adc_range = AdcRange::FullScale;
    let mut cos = [0.0; 8];
    cos[2] = 1.5e-3;
    let mut sin = [0.0; 8];
    sin[3] = -2.5e-4;
    harmonics.correction = Correction::Harmonics(AngleCorrection::new(cos, sin).unwrap());
    // No roundness check: `null`, which reads back as `None` (not the default 0.1).
    harmonics.fault_thresholds = harmonics
        .fault_thresholds
        .map(|t| t.with_magnitude_tolerance(None));
    let mut counts = TrackerFile::new(gains());
    counts.input = Input::Counts;
    for tracker in [TrackerFile::new(gains()), full(), harmonics, counts] {
        let text = tracker.to_json();
        assert_eq!(read(&text).unwrap(), tracker, "{text}");
        assert_eq!(read(&text).unwrap().to_json(), text);
    }
}

#[test]
fn settings_left_out_are_the_defaults() {
    let text = r#"{"format": "angletrack-tracker", "version": 1, "sample_period_s": 1e-4,
        "gains": [0.06, 0.001]}"#;
    let tracker = read(text).unwrap();
    let mut expected = TrackerFile::new(gains());
    expected.gains = GainsFile {
        gains: vec![0.06, 0.001],
        sample_period_s: 1e-4,
        design: None,
    };
    assert_eq!(tracker, expected);
}

/// A file written before `tracking_error` and `magnitude_tolerance` existed reads with
/// their defaults (0.05, and 0.1 for the stated amplitude), and a value out of range is
/// refused naming the field.
#[test]
fn thresholds_left_out_read_with_their_defaults_and_are_refused_by_name() {
    let text = r#"{"format": "angletrack-tracker", "version": 1, "sample_period_s": 1e-4,
        "gains": [0.06, 0.001], "fault_thresholds": {"nominal_amplitude": 0.9}}"#;
    let thresholds = read(text).unwrap().fault_thresholds.unwrap();
    // The f32 value in both types, as every fraction of the defaults.
    assert_eq!(thresholds.tracking_error, f64::from(0.05_f32));
    assert_eq!(thresholds.magnitude_tolerance, Some(f64::from(0.1_f32)));
    for (field, value) in [
        ("tracking_error", "-1"),
        ("magnitude_tolerance", "0"),
        ("magnitude_tolerance", "\"wide\""),
    ] {
        let refused = text.replace("0.9}", &format!("0.9, \"{field}\": {value}}}"));
        let err = read(&refused).unwrap_err().to_string();
        assert!(
            err.starts_with(&format!("t.json: fault_thresholds.{field}: ")),
            "{err}"
        );
    }
}

#[test]
fn the_older_files_build_one() {
    let record = CalibrationFile::Sensor(SensorCalibrationRecord {
        calibration: sensor(),
        turns_learned: Some(3),
        source: None,
    });
    let tracker = TrackerFile::new(gains()).with_calibration_file(&record);
    assert_eq!(tracker.calibration, Calibration::Stored(sensor()));
    assert_eq!(tracker.correction, Correction::None);
    let mut cos = [0.0; 8];
    cos[1] = 1e-3;
    let correction = AngleCorrection::new(cos, [0.0; 8]).unwrap();
    let angle = CalibrationFile::Angle(CaptureCalibration {
        sensor: sensor(),
        correction,
        speed_rad_s: f64::NAN,
        turns: f64::NAN,
        error_rms_rad: f64::NAN,
        residual_rms_rad: f64::NAN,
        method: CalibrationMethod::Unknown,
        orders: [OrderQuality::UNKNOWN; SPECTRUM_ORDERS],
    });
    let tracker = tracker.with_calibration_file(&angle);
    assert_eq!(tracker.correction, Correction::Harmonics(correction));
}

#[test]
fn other_documents_and_versions_are_refused_by_name() {
    let gains_text = gains().to_json();
    let e = read(&gains_text).unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.json: format: not an angletrack-tracker document but an \"angletrack-gains\" one"
    );
    let calibration = SensorCalibrationRecord {
        calibration: sensor(),
        turns_learned: None,
        source: None,
    };
    let e = read(&calibration.to_json()).unwrap_err();
    assert!(
        e.to_string().contains("\"angletrack-sensor-calibration\""),
        "{e}"
    );
    let text = full().to_json().replace("\"version\": 1", "\"version\": 2");
    assert_eq!(
        read(&text).unwrap_err().to_string(),
        "t.json: version: 2 is not supported (expected 1)"
    );
}

#[test]
fn each_refusal_names_the_field_as_written() {
    let text = full().to_json();
    let cases = [
        ("\"pole_pairs\": 4", "\"pole_poles\": 4", "pole_poles"),
        (
            "\"max_offset\": 0.05",
            "\"max_ofset\": 0.05",
            "calibration.max_ofset",
        ),
        (
            "\"max_offset\": 0.05",
            "\"max_offset\": -0.05",
            "calibration.max_offset",
        ),
        (
            "\"min_speed_rad_s\": 50.0",
            "\"min_speed_rad_s\": 1e-9",
            "calibration.min_speed_rad_s",
        ),
        (
            "\"amplitude_s\": 1980.0",
            "\"amplitude_s\": -1.0",
            "calibration.initial.amplitude_s",
        ),
        (
            "\"filter_factor\": ",
            "\"filter_factor\": 1.5, \"x\": ",
            "fault_thresholds.x",
        ),
        (
            "\"counts_per_unit\": 1800.0",
            "\"counts_per_unit\": 0.0",
            "input.counts_per_unit",
        ),
        (
            "\"mid_scale\": 2048",
            "\"mid_scale\": 2048.5",
            "input.mid_scale",
        ),
        ("\"min\": -1.1377", "\"min\": 2.0", "adc_range.max"),
        (
            "\"rule\": \"stated\"",
            "\"rule\": \"guessed\"",
            "adc_range.rule",
        ),
        (
            "\"amplitude\": 1.0",
            "\"amplitude\": 0.0",
            "winding_check.amplitude",
        ),
        (
            "\"errors_rad\": [",
            "\"errors_rad\": [1e9, ",
            "correction.errors_rad",
        ),
        ("\"pole_pairs\": 4", "\"pole_pairs\": 0", "pole_pairs"),
        (
            "\"sample_period_s\": 5e-5",
            "\"sample_period_s\": -1.0",
            "sample_period_s",
        ),
        (
            "\"number_type\": \"f32\"",
            "\"number_type\": \"f16\"",
            "number_type",
        ),
        ("\"sin_cos\": \"exact\"", "\"sin_cos\": \"slow\"", "sin_cos"),
        (
            "\"kind\": \"online\"",
            "\"kind\": \"offline\"",
            "calibration.kind",
        ),
    ];
    for (from, to, field) in cases {
        assert!(text.contains(from), "{from} not in {text}");
        let e = read(&text.replacen(from, to, 1)).unwrap_err();
        assert_eq!(e.field.as_deref(), Some(field), "{to}: {e}");
        assert!(!e.to_string().contains('\n'), "{e}");
    }
    // The thresholds are checked as the gains take them (the degradation's high threshold
    // above the nominal amplitude).
    let mut tracker = full();
    tracker.fault_thresholds = tracker
        .fault_thresholds
        .map(|t| t.with_degradation_high(0.1));
    let e = read(&tracker.to_json()).unwrap_err();
    assert_eq!(
        e.field.as_deref(),
        Some("fault_thresholds.degradation_high"),
        "{e}"
    );
}

#[test]
fn the_gains_are_checked_by_the_core() {
    let unstable = full().to_json().replacen("0.09516", "3.5", 1);
    let e = read(&unstable).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("gains"), "{e}");
    let four = full().to_json().replacen("0.09516,", "0.09516, 0.1,", 1);
    assert_eq!(read(&four).unwrap_err().field.as_deref(), Some("gains"));
}

#[test]
fn settings_that_contradict_each_other_are_refused() {
    let mut tracker = full();
    tracker.adc_range = AdcRange::FullScale;
    let e = read(&tracker.to_json()).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("adc_range.rule"), "{e}");
    let mut tracker = TrackerFile::new(gains());
    tracker.number_type = NumberType::Fixed;
    let e = read(&tracker.to_json()).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("number_type"), "{e}");
    tracker.input = Input::Bits {
        bits: 12,
        signed: true,
    };
    tracker.calibration = Calibration::Online {
        initial: None,
        settings: CalibrationSettings::default(),
    };
    let e = read(&tracker.to_json()).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("calibration.kind"), "{e}");
}

#[test]
fn firmware_constants_are_the_generators_gains_and_calibration() {
    use crate::export::{FloatType, calibration_c_header, gains_c_header};
    let mut tracker = TrackerFile::new(gains()).with_calibration_file(&CalibrationFile::Sensor(
        SensorCalibrationRecord {
            calibration: sensor(),
            turns_learned: None,
            source: None,
        },
    ));
    tracker.number_type = NumberType::F32;
    let text = tracker
        .firmware_constants("t.json", Language::C, "motor")
        .unwrap();
    let g = &tracker.gains.gains;
    let core = angletrack_core::Gains::<f64, 3>::new([g[0], g[1], g[2]], 50e-6).unwrap();
    let header = gains_c_header(&core, FloatType::F32, "motor", "x").unwrap();
    let zero = AngleCorrection::new([0.0; 8], [0.0; 8]).unwrap();
    let calibration = calibration_c_header(&sensor(), &zero, FloatType::F32, "motor").unwrap();
    // The gains' lines (after the comment, which describes the setup) and the calibration.
    let from_guard = |t: &str| t[t.find("#ifndef").unwrap()..].to_string();
    assert!(text.contains(&from_guard(&header)), "{text}");
    assert!(text.ends_with(&calibration), "{text}");
    assert!(
        text.contains(" * From a tracker file: number type f32.\n"),
        "{text}"
    );

    // Rust: one `static` (tests/tracker_rust_export.rs compiles and runs it); counts whose
    // mid-scale is measured are a run-time measurement, refused naming the field.
    tracker.number_type = NumberType::Fixed;
    tracker.input = Input::Counts;
    tracker.calibration = Calibration::None;
    let e = tracker
        .firmware_constants("t.json", Language::Rust, "motor")
        .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("t.json: input: counts with the mid-scale measured"),
        "{e}"
    );

    let e = full()
        .firmware_constants("t.json", Language::C, "motor")
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.json: fault_thresholds: fault thresholds: no firmware constants are generated for it yet; leave it out"
    );

    // C in fixed point: the chain's integers carry the monitor, so counts need their
    // amplitude stated, as in Rust.
    tracker.input = Input::Bits {
        bits: 12,
        signed: false,
    };
    let e = tracker
        .firmware_constants("t.json", Language::C, "motor")
        .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("t.json: fault_thresholds: counts tracked as counts"),
        "{e}"
    );
    tracker.fault_thresholds = Some(FaultThresholds::for_amplitude(1800.0));
    let text = tracker
        .firmware_constants("t.json", Language::C, "motor")
        .unwrap();
    assert!(
        text.contains("static const at_adc_counts motor_adc = {2048, 4};\n"),
        "{text}"
    );
    assert!(
        text.contains("    &motor_adc,\n    NULL,\n    NULL,\n};\n"),
        "{text}"
    );
}

#[test]
fn sin_cos_names_read_back() {
    for kind in [SinCosKind::Default, SinCosKind::Fast, SinCosKind::Exact] {
        assert_eq!(SinCosKind::from_name(kind.name()), Some(kind));
    }
    assert_eq!(SinCosKind::from_name(Some("slow")), None);
}

/// Every threshold reaches the firmware: the float chain's `static` sets each field (the
/// roundness check's tolerance too, `None` as `None`); the fixed-point monitor takes the
/// nominal amplitude, the tolerance and the tracking-error level (the C words' 9th), and
/// refuses another field naming it.
#[test]
fn the_exports_write_every_threshold_and_refuse_what_fixed_point_cannot_hold() {
    let mut tracker = TrackerFile::new(gains());
    tracker.number_type = NumberType::F32;
    let stated = FaultThresholds::for_amplitude(0.9).with_magnitude_tolerance(None);
    tracker.fault_thresholds = Some(stated);
    let rust = |t: &TrackerFile| t.firmware_constants("t.json", Language::Rust, "motor");
    let text = rust(&tracker).unwrap();
    assert!(text.contains(" t.magnitude_tolerance = None;"), "{text}");

    tracker.number_type = NumberType::Fixed;
    tracker.input = Input::Bits {
        bits: 12,
        signed: true,
    };
    let fixed = |r| Some(FaultThresholds::for_amplitude(1800.0).with_magnitude_tolerance(r));
    tracker.fault_thresholds = fixed(Some(0.25));
    let text = rust(&tracker).unwrap();
    assert!(
        text.contains(".with_monitor_tolerance(Some(2.88e+04), Some(2.5e-01))"),
        "{text}"
    );
    let c = tracker
        .firmware_constants("t.json", Language::C, "motor")
        .unwrap();
    // The C constants carry the same monitor as the fixed-point run of the file.
    let monitor = FixedGains::<3>::new([0.095_16, 0.004_757, 1.189e-4], 50e-6)
        .and_then(|g| g.with_monitor_tolerance(Some(28_800.0), Some(0.25)))
        .unwrap()
        .monitor_words();
    let words: Vec<String> = monitor.iter().map(|w| w.to_string()).collect();
    assert!(c.contains(&words.join(", ")), "{c}");
    tracker.fault_thresholds = fixed(None);
    assert!(rust(&tracker).unwrap().contains(", None))"));
    // A noisy sensor's level (8 times 1 % noise): 2621 in Q15, in both exports.
    tracker.fault_thresholds = fixed(Some(0.1)).map(|t| t.with_tracking_error(0.08));
    let text = rust(&tracker).unwrap();
    assert!(text.contains(".with_tracking_error(8e-02))"), "{text}");
    let c = tracker
        .firmware_constants("t.json", Language::C, "motor")
        .unwrap();
    assert!(c.contains(", 1073741824, 2621}"), "{c}");
    tracker.fault_thresholds = fixed(Some(0.1)).map(|t| t.with_tracking_error(1.5));
    for language in [Language::C, Language::Rust] {
        let e = tracker
            .firmware_constants("t.json", language, "motor")
            .unwrap_err();
        assert!(
            e.to_string().starts_with(
                "t.json: fault_thresholds.tracking_error: the fixed-point monitor holds"
            ),
            "{e}"
        );
    }
    tracker.fault_thresholds = fixed(Some(0.1)).map(|t| t.with_filter_factor(0.5));
    for language in [Language::C, Language::Rust] {
        let e = tracker
            .firmware_constants("t.json", language, "motor")
            .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("t.json: fault_thresholds.filter_factor: the fixed-point monitor"),
            "{e}"
        );
    }
}
