//! The calibration files: files in the Python `json` module's layout (`tests/fixtures/
//! calibration/`, as users hold them) read back exactly, round trips, and refusals that name
//! the file and the field.

use std::path::PathBuf;

use angletrack::{
    AngleCorrection, CalibrationFile, CalibrationMethod, CaptureCalibration, OrderQuality,
    OrderStatus, SPECTRUM_ORDERS, SensorCalibration, SensorCalibrationRecord,
};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/calibration")
        .join(name)
}

fn angle_calibration() -> CaptureCalibration {
    CaptureCalibration {
        sensor: SensorCalibration::new(0.0512, -0.0498, 1.0, 1.1, 0.0123).unwrap(),
        correction: AngleCorrection::new(
            [1e-4, -2e-4, 5.001e-3, 0.0, 0.0, 0.0, 0.0, 1.5e-6],
            [0.0, 3e-5, -1.23456789e-3, 4.9e-3, 0.0, 0.0, 0.0, 0.0],
        )
        .unwrap(),
        speed_rad_s: 1256.6370614359173,
        turns: 160.0,
        error_rms_rad: 0.0071234,
        residual_rms_rad: 1.2e-05,
        method: CalibrationMethod::Reference,
        orders: core::array::from_fn(|i| OrderQuality {
            amplitude_rad: 1e-3 / (i + 1) as f64,
            uncertainty_rad: 2e-5,
            status: if i < 8 {
                OrderStatus::Learned
            } else {
                OrderStatus::NotRequested
            },
        }),
    }
}

fn sensor_record() -> SensorCalibrationRecord {
    SensorCalibrationRecord {
        calibration: SensorCalibration::new(
            90.00000000000001,
            -89.5,
            1800.0,
            1980.0000000000002,
            0.05235987755982988,
        )
        .unwrap(),
        turns_learned: Some(42),
        source: Some("capture.csv".to_string()),
    }
}

#[test]
fn files_in_the_python_json_layout_read_back_exactly() {
    // Written before the method and the orders' quality were: read as unknown.
    let CalibrationFile::Angle(angle) = CalibrationFile::read(&fixture("angle.json")).unwrap()
    else {
        panic!("an angle calibration")
    };
    assert_eq!(angle.method, CalibrationMethod::Unknown);
    assert!(
        angle
            .orders
            .iter()
            .all(|q| q.status == OrderStatus::Unknown)
    );
    assert_eq!(
        CaptureCalibration {
            method: CalibrationMethod::Reference,
            orders: angle_calibration().orders,
            ..angle
        },
        angle_calibration()
    );
    assert!(angle.warnings().is_empty());
    let sensor = CalibrationFile::read(&fixture("sensor.json")).unwrap();
    assert_eq!(sensor, CalibrationFile::Sensor(sensor_record()));
}

#[test]
fn both_kinds_round_trip_through_a_file() {
    let dir = std::env::temp_dir().join(format!("angletrack-calibration-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut nan = angle_calibration();
    nan.speed_rad_s = f64::NAN; // not learned: written null
    for (name, file) in [
        ("angle.json", CalibrationFile::Angle(angle_calibration())),
        ("sensor.json", CalibrationFile::Sensor(sensor_record())),
    ] {
        let path = dir.join(name);
        file.write(&path).unwrap();
        assert_eq!(CalibrationFile::read(&path).unwrap(), file);
    }
    let text = nan.to_json();
    assert!(text.contains("\"speed_rad_s\": null,"), "{text}");
    assert!(
        CaptureCalibration::from_json(&text, "x")
            .unwrap()
            .speed_rad_s
            .is_nan()
    );
    assert!(text.contains("\"method\": \"reference\""), "{text}");
    assert!(
        text.contains("{\"order\": 12, \"amplitude_rad\": "),
        "{text}"
    );
    assert_eq!(SPECTRUM_ORDERS, 12);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_sensor_format_is_the_python_packages_layout() {
    let written = sensor_record().to_json();
    let python = std::fs::read_to_string(fixture("sensor.json")).unwrap();
    assert_eq!(written, python);
    let bare = SensorCalibrationRecord {
        turns_learned: None,
        source: None,
        ..sensor_record()
    };
    assert!(!bare.to_json().contains("turns_learned"));
}

#[test]
fn a_bare_object_of_the_five_fields_is_a_sensor_calibration() {
    let text = r#"{"offset_c": 0, "offset_s": 0.5, "amplitude_c": 1, "amplitude_s": 2, "quadrature_rad": 0}"#;
    let CalibrationFile::Sensor(record) = CalibrationFile::from_json(text, "hand.json").unwrap()
    else {
        panic!("a sensor calibration")
    };
    assert_eq!(record.calibration.parameters(), (0.0, 0.5, 1.0, 2.0, 0.0));
    assert_eq!((record.turns_learned, record.source), (None, None));
}

fn refusal(text: &str) -> (Option<String>, String) {
    let e = CalibrationFile::from_json(text, "cal.json").unwrap_err();
    assert_eq!(e.file, "cal.json");
    assert!(e.to_string().starts_with("cal.json: "), "{e}");
    let message = e.to_string();
    (e.field, message)
}

#[test]
fn refusals_name_the_file_and_the_field() {
    let (field, message) = refusal("{nope");
    assert_eq!(field, None);
    assert!(message.starts_with("cal.json: not JSON ("), "{message}");
    assert_eq!(refusal("[1, 2]").1, "cal.json: expected a JSON object");
    let angle = angle_calibration().to_json();
    let cases = [
        (angle.replace("\"version\": 1", "\"version\": 2"), "version"),
        (angle.replace("    1.1,\n", ""), "sensor"),
        (angle.replace("1.5e-6", "\"x\""), "cos"),
        (
            angle.replace("\"turns\": 160.0", "\"turns\": \"many\""),
            "turns",
        ),
        (angle.replace("    1.0,\n", "    -1.0,\n"), "sensor"),
        (angle.replace("-0.0002", "7.0"), "cos, sin"),
        (angle.replace("\"order\": 3,", "\"order\": 13,"), "orders"),
        (
            angle.replace("\"method\": \"reference\"", "\"method\": 3"),
            "method",
        ),
    ];
    for (text, expected) in cases {
        assert_eq!(refusal(&text).0.as_deref(), Some(expected), "{text}");
    }
    let sensor = sensor_record().to_json();
    let cases = [
        (
            sensor.replace("\"amplitude_s\"", "\"amplitude\""),
            "calibration.amplitude_s",
        ),
        (sensor.replace("-89.5", "\"-89.5\""), "calibration.offset_s"),
        (
            sensor.replace("0.05235987755982988", "1.0"),
            "calibration.quadrature_rad",
        ),
        (sensor.replace("42", "-1"), "turns_learned"),
        (sensor.replace("\"capture.csv\"", "3"), "source"),
        (sensor.replace("sensor-calibration", "gains"), "format"),
        (r#"{"calibration": 3}"#.to_string(), "calibration"),
    ];
    for (text, expected) in cases {
        assert_eq!(refusal(&text).0.as_deref(), Some(expected), "{text}");
    }
    // An angle calibration's reader refuses the other format.
    let e = CaptureCalibration::from_json(&sensor, "calibration file").unwrap_err();
    assert_eq!(
        e.to_string(),
        "calibration file: format: not an angletrack-calibration document but an \
         \"angletrack-sensor-calibration\" one"
    );
}

#[test]
fn a_missing_file_is_named() {
    let e = CalibrationFile::read(&fixture("missing.json")).unwrap_err();
    assert!(e.file.ends_with("missing.json") && e.field.is_none(), "{e}");
}
