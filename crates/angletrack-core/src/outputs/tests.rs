use super::*;
use core::f64::consts::{PI, TAU};

fn estimate(angle: f64, turns: i64, speed: f64, acceleration: f64) -> Estimate<f64> {
    Estimate {
        angle,
        turns,
        speed,
        acceleration,
        ..Estimate::default()
    }
}

#[test]
fn extrapolates_by_the_latency_across_a_turn() {
    let outputs = DriveOutputs::<f64>::new(1, 1, 1e-3, 1e-4).unwrap();
    let mut state = DriveOutputsState::default();
    let drive = outputs.outputs(&mut state, &estimate(3.0, 5, 500.0, 2e4));
    let expected = 3.0 + 0.5 + 0.5 * 2e4 * 1e-6 - TAU;
    assert!((drive.mechanical_angle - expected).abs() < 1e-12);
    assert_eq!(drive.mechanical_turns, 6);
    assert!((drive.mechanical_speed - 520.0).abs() < 1e-9);
}

#[test]
fn electrical_angle_is_exact_over_many_turns() {
    // 3 pole pairs, a 2X resolver: electrical = 1.5 x resolver angle.
    let outputs = DriveOutputs::<f64>::new(3, 2, 0.0, 1e-4).unwrap();
    let mut state = DriveOutputsState::default();
    for turns in [-7i64, -1, 0, 1, 2, 3, 1_000_000_001] {
        let angle = 0.4;
        let drive = outputs.outputs(&mut state, &estimate(angle, turns, 0.0, 0.0));
        let total = turns as f64 * TAU + angle;
        let expected = (1.5 * total + PI).rem_euclid(TAU) - PI;
        let error = (drive.electrical_angle - expected + PI).rem_euclid(TAU) - PI;
        assert!(error.abs() < 1e-6, "turns {turns}: {error}");
        let mechanical = drive.mechanical_turns as f64 * TAU + drive.mechanical_angle;
        assert!((mechanical - total / 2.0).abs() < 1e-6 * (1.0 + total.abs() * 1e-9));
    }
}

#[test]
fn speed_low_pass_settles_with_its_time_constant() {
    let outputs = DriveOutputs::<f64>::new(4, 1, 0.0, 1e-4)
        .unwrap()
        .with_speed_time_constant_s(1e-2)
        .unwrap();
    let mut state = DriveOutputsState::default();
    outputs.outputs(&mut state, &estimate(0.0, 0, 0.0, 0.0));
    let mut last = DriveAngle::default();
    for _ in 0..100 {
        last = outputs.outputs(&mut state, &estimate(0.0, 0, 100.0, 0.0));
    }
    // After one time constant: 1 - 1/e of the step, to the first order of Ts / tau.
    assert!((last.mechanical_speed / 100.0 - (1.0 - (-1.0f64).exp())).abs() < 0.01);
    assert!((last.electrical_speed - 4.0 * last.mechanical_speed).abs() < 1e-9);
}

#[test]
fn refuses_bad_settings_by_name() {
    let p = |r: Result<DriveOutputs<f32>, ConfigError>| r.unwrap_err().parameter();
    assert_eq!(p(DriveOutputs::new(1, 0, 0.0, 1e-4)), Parameter::SpeedRatio);
    assert_eq!(p(DriveOutputs::new(1, 1, -1e-3, 1e-4)), Parameter::Latency);
    assert_eq!(
        p(DriveOutputs::new(1, 1, f32::NAN, 1e-4)),
        Parameter::Latency
    );
    assert_eq!(
        p(DriveOutputs::new(1, 1, 0.0, 0.0)),
        Parameter::SamplePeriod
    );
    let ok = DriveOutputs::<f32>::new(1, 1, 0.0, 1e-4).unwrap();
    assert_eq!(
        p(ok.with_speed_time_constant_s(0.0)),
        Parameter::SpeedFilter
    );
}
