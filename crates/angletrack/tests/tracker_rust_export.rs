//! A tracker file as a Rust `static` (`angletrack export --format rust`): the text against
//! its reference files (`tests/fixtures/tracker/`, which this test rewrites with
//! `ANGLETRACK_WRITE_FIXTURES=1`), and those files compiled here (the compiler evaluates
//! their `const` constructors) and run on the sensor the file describes: 12-bit counts with
//! offsets, imbalance, quadrature and a 3rd-harmonic angle error, in `f32` and fixed point.

use angletrack::export::GainsFile;
use angletrack::tracker_file::{
    AdcRange, Calibration, Correction, Input, Language, NumberType, TrackerFile,
};
use angletrack_core::{AngleCorrection, FaultThresholds, SensorCalibration, TrackerState};

mod exported_f32 {
    include!("fixtures/tracker/motor_f32.rs.txt");
}
mod exported_fixed {
    include!("fixtures/tracker/motor_fixed.rs.txt");
}

/// The sensor: offsets and amplitudes in counts, quadrature (rad).
const SENSOR: (f64, f64, f64, f64, f64) = (36.0, -36.0, 1800.0, 1854.0, 0.01);
/// The 3rd harmonic of the angle error (rad): cosine and sine coefficients.
const HARMONIC_3: (f64, f64) = (1.2e-3, 3.8e-3);
const SAMPLE_PERIOD_S: f64 = 50e-6;

fn harmonics() -> AngleCorrection<f64> {
    let (mut a, mut b) = ([0.0; 8], [0.0; 8]);
    (a[2], b[2]) = HARMONIC_3;
    AngleCorrection::new(a, b).unwrap()
}

fn tracker_file(number_type: NumberType) -> TrackerFile {
    let gains = GainsFile {
        gains: vec![
            0.048770575499286,
            0.0012192008871052071,
            1.5239217375442759e-5,
        ],
        sample_period_s: SAMPLE_PERIOD_S,
        design: None,
    };
    let (o_c, o_s, a_c, a_s, phi) = SENSOR;
    TrackerFile {
        number_type,
        input: Input::Bits {
            bits: 12,
            signed: false,
        },
        adc_range: AdcRange::FullScale,
        fault_thresholds: Some(FaultThresholds::for_amplitude(1800.0)),
        calibration: Calibration::Stored(SensorCalibration::new(o_c, o_s, a_c, a_s, phi).unwrap()),
        correction: Correction::Harmonics(harmonics()),
        ..TrackerFile::new(gains)
    }
}

#[test]
fn the_rust_export_of_a_tracker_file_is_its_reference() {
    for (number_type, name) in [
        (NumberType::F32, "motor_f32.rs.txt"),
        (NumberType::Fixed, "motor_fixed.rs.txt"),
    ] {
        let text = tracker_file(number_type)
            .firmware_constants("motor.json", Language::Rust, "motor")
            .unwrap();
        let path = format!(
            "{}/tests/fixtures/tracker/{name}",
            env!("CARGO_MANIFEST_DIR")
        );
        if std::env::var_os("ANGLETRACK_WRITE_FIXTURES").is_some() {
            std::fs::write(&path, &text).unwrap();
        }
        assert_eq!(text, std::fs::read_to_string(&path).unwrap(), "{name}");
    }
}

/// The code of the sensor's channel at its reading `angle` (the truth plus its error).
fn counts(angle: f64) -> (i32, i32) {
    let (o_c, o_s, a_c, a_s, phi) = SENSOR;
    let code = |v: f64| 2048 + v.round() as i32;
    (
        code(o_c + a_c * angle.cos()),
        code(o_s + a_s * (angle + phi).sin()),
    )
}

fn wrap(angle: f64) -> f64 {
    (angle + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

#[test]
fn the_exported_statics_track_the_sensor_the_file_describes() {
    let speed_rad_s = std::f64::consts::TAU * 30.0;
    let mut state_f32 = TrackerState::new();
    let mut state_fixed = TrackerState::new();
    let (mut worst_f32, mut worst_fixed): (f64, f64) = (0.0, 0.0);
    for k in 0..8000 {
        let truth = wrap(speed_rad_s * k as f64 * SAMPLE_PERIOD_S);
        let sample = counts(truth + harmonics().error_at(truth));
        let f = exported_f32::MOTOR_TRACKER.update(&mut state_f32, sample);
        let x = exported_fixed::MOTOR_TRACKER.update(&mut state_fixed, sample);
        if k >= 4000 {
            assert!(
                f.faults.is_empty() && x.faults.is_empty(),
                "{k}: {:?} {:?}",
                f.faults,
                x.faults
            );
            worst_f32 = worst_f32.max(wrap(f64::from(f.angle) - truth).abs());
            let fixed_angle = f64::from(x.angle) * std::f64::consts::TAU / 4294967296.0;
            worst_fixed = worst_fixed.max(wrap(fixed_angle - truth).abs());
        }
    }
    // 12-bit counts of an 1800-count signal: about 0.3 mrad of quantisation.
    assert!(
        worst_f32 < 1.5e-3 && worst_fixed < 1.5e-3,
        "{worst_f32} {worst_fixed}"
    );
}
