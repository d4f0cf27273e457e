//! The generated C headers and Rust `const` blocks, byte for byte against reference files
//! (`tests/fixtures/export/`, written by the NumPy-formatting generator the command line
//! used), so that a header or `const` block checked into a firmware project regenerates
//! unchanged.

use angletrack::export::{
    FloatType, calibration_c_header, calibration_rust, fixed_c_header, fixed_rust, gains_c_header,
    gains_rust,
};
use angletrack::{AngleCorrection, FixedDesignConstants, Gains, SensorCalibration};

const DESCRIPTION: &str = "Kalman (kalman_from_jerk_std: jerk_std_rad_s3=100000.0)  \n-3 dB \
                           bandwidth 123.456 Hz, linear step overshoot 5.2 %";

fn fixture(name: &str) -> String {
    let path = format!(
        "{}/tests/fixtures/export/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn third_order() -> Gains<f64, 3> {
    Gains::new([0.1234567891234, 0.00512345678, 1.2345678e-4], 5e-5).unwrap()
}

fn second_order() -> Gains<f64, 2> {
    Gains::new([0.06123456789, 0.00101], 1e-4).unwrap()
}

#[test]
fn float_gains_as_c_headers() {
    let text = gains_c_header(&third_order(), FloatType::F32, "rdc", DESCRIPTION).unwrap();
    assert_eq!(text, fixture("gains3_float32.h"));
    let text = gains_c_header(&second_order(), FloatType::F64, "angletrack", "").unwrap();
    assert_eq!(text, fixture("gains2_float64.h"));
}

#[test]
fn float_gains_as_rust_consts() {
    let text = gains_rust(&third_order(), FloatType::F64, "rdc", DESCRIPTION).unwrap();
    assert_eq!(text, fixture("gains3_float64.rs.txt"));
    let text = gains_rust(&second_order(), FloatType::F32, "angletrack", "").unwrap();
    assert_eq!(text, fixture("gains2_float32.rs.txt"));
}

#[test]
fn fixed_point_constants_as_c_and_rust() {
    let constants = FixedDesignConstants {
        multiplier: vec![1234567891, 23456789, 345678],
        acceleration_shift: 7,
        quantised_gains: vec![0.1, 0.01, 0.001],
        sample_period_s: 1e-4,
    };
    let text = fixed_c_header(&constants, "rdc", DESCRIPTION).unwrap();
    assert_eq!(text, fixture("fixed3.h"));
    let text = fixed_rust(&constants, "angletrack", DESCRIPTION).unwrap();
    assert_eq!(text, fixture("fixed3.rs.txt"));
}

#[test]
fn a_calibration_as_c_and_rust() {
    let sensor = SensorCalibration::new(0.0512, -0.0498, 1.0, 1.1, 0.0123).unwrap();
    let correction = AngleCorrection::new(
        [1e-4, -2e-4, 5.001e-3, 0.0, 0.0, 0.0, 0.0, 1.5e-6],
        [0.0, 3e-5, -1.23456789e-3, 4.9e-3, 0.0, 0.0, 0.0, 0.0],
    )
    .unwrap();
    let text = calibration_c_header(&sensor, &correction, FloatType::F32, "rdc").unwrap();
    assert_eq!(text, fixture("calibration_float32.h"));
    let text = calibration_rust(&sensor, &correction, FloatType::F64, "rdc").unwrap();
    assert_eq!(text, fixture("calibration_float64.rs.txt"));
    let text = calibration_rust(&sensor, &correction, FloatType::F32, "angletrack").unwrap();
    assert_eq!(text, fixture("calibration_float32.rs.txt"));
}
