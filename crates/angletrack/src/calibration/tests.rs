use std::f64::consts::{PI, TAU};

use angletrack_core::{Chain, ChainState, Gains};

use super::*;
use crate::{
    Discretisation, Motion, MotionProfile, Scenario, SensorModel, predicted_error,
    third_order_butterworth,
};

const SAMPLE_PERIOD_S: f64 = 5e-5;
/// Electrical speed of the captures: 200 Hz, orders 2 and up are above the loop.
const SPEED_RAD_S: f64 = TAU * 200.0;

/// The sensor: 5 mrad of 3rd and 4th harmonic angle error, 5 % offsets, imbalance
/// and quadrature, white noise 0.001 per channel.
pub(crate) fn harmonic_sensor() -> SensorModel {
    let mut sensor = SensorModel::with_noise(1e-3);
    sensor.offset_cos = 0.05;
    sensor.offset_sin = -0.05;
    sensor.amplitude_imbalance = 0.05;
    sensor.quadrature_error_rad = 0.02;
    sensor.angle_error_harmonics[0] = (3, 5e-3, 0.3);
    sensor.angle_error_harmonics[1] = (4, 5e-3, 1.1);
    sensor
}

/// A 3rd-order Butterworth loop whose predicted noise floor on that sensor is about 0.2 mrad.
fn loop_gains() -> Gains<f64, 3> {
    third_order_butterworth(2e-3, SAMPLE_PERIOD_S, Discretisation::PoleMatching)
        .unwrap()
        .gains
}

fn capture(motion: Motion, seed: u64) -> Scenario {
    let profile = MotionProfile::new(0.0, SPEED_RAD_S).then(motion);
    Scenario::generate(&profile, &harmonic_sensor(), SAMPLE_PERIOD_S, seed).unwrap()
}

/// The RMS of `angle - truth` (wrapped, mean removed) over the last half of the run.
fn rms_after_mean(errors: &[f64]) -> f64 {
    let tail = &errors[errors.len() / 2..];
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    (tail.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / tail.len() as f64).sqrt()
}

#[test]
fn loop_of_the_targets_has_the_stated_noise_floor() {
    let floor = predicted_error(&loop_gains(), 1e-3, 0.0)
        .unwrap()
        .angle_rms_rad;
    assert!((1.5e-4..2.5e-4).contains(&floor), "{floor}");
}

#[test]
fn error_transfer_is_zero_at_dc_and_one_far_above_the_loop() {
    let gains = loop_gains();
    assert!(error_transfer(&gains, 1e-6).norm() < 1e-6);
    let near_nyquist = error_transfer(&gains, 0.9 * PI);
    assert!((near_nyquist.norm() - 1.0).abs() < 0.1);
}

/// The target (docs/theory.md §12): learned from 50 turns at constant speed, the
/// correction leaves below 0.5 mrad RMS on another capture with a 5 % speed ripple.
#[test]
fn learned_correction_leaves_below_half_a_milliradian_on_a_rippling_capture() {
    let gains = loop_gains();
    let learning = capture(
        Motion::ConstantSpeed {
            speed_rad_s: SPEED_RAD_S,
            duration_s: 50.0 / 200.0,
        },
        1,
    );
    let learned =
        learn_angle_correction(&gains, &learning.y_c, &learning.y_s, &Default::default()).unwrap();
    let (a, b) = learned.correction.coefficients();
    for (k, amplitude, phase) in [(3, 5e-3, 0.3_f64), (4, 5e-3, 1.1_f64)] {
        // a_k cos + b_k sin = amplitude sin(k theta + phase).
        let (a_true, b_true) = (amplitude * phase.sin(), amplitude * phase.cos());
        assert!(
            (a[k - 1] - a_true).abs() < 2e-4,
            "a{k} {} {a_true}",
            a[k - 1]
        );
        assert!(
            (b[k - 1] - b_true).abs() < 2e-4,
            "b{k} {} {b_true}",
            b[k - 1]
        );
    }
    let (o_c, o_s) = learned.sensor.offsets();
    assert!((o_c - 0.05).abs() < 2e-3 && (o_s + 0.05).abs() < 2e-3);

    let test = capture(
        Motion::SpeedRipple {
            ripple_rad_s: 0.05 * SPEED_RAD_S,
            frequency_hz: 2.0,
            duration_s: 1.0,
        },
        2,
    );
    let run = |corrected: bool| {
        let correction = if corrected {
            learned.correction
        } else {
            AngleCorrection::NONE
        };
        // The stored calibration, then the angle correction, before the observer.
        let chain = Chain::new((learned.sensor, correction), gains);
        let mut state = ChainState::new();
        let errors: Vec<f64> = (0..test.len())
            .map(|k| {
                let e = chain.update(&mut state, (test.y_c[k], test.y_s[k]));
                let d = e.angle - test.angle_rad[k];
                d.sin().atan2(d.cos())
            })
            .collect();
        rms_after_mean(&errors)
    };
    let (before, after) = (run(false), run(true));
    println!(
        "learned a {a:?} b {b:?}; residual RMS {before:.3e} rad uncorrected, {after:.3e} rad corrected"
    );
    assert!(before > 1e-3, "{before}");
    assert!(after < 5e-4, "{after}");
}

#[test]
fn a_capture_too_slow_for_the_loop_is_refused() {
    let gains = loop_gains();
    let profile = MotionProfile::new(0.0, TAU * 10.0).then(Motion::ConstantSpeed {
        speed_rad_s: TAU * 10.0,
        duration_s: 1.0,
    });
    let slow = Scenario::generate(&profile, &harmonic_sensor(), SAMPLE_PERIOD_S, 3).unwrap();
    let err =
        learn_angle_correction(&gains, &slow.y_c, &slow.y_s, &Default::default()).unwrap_err();
    assert!(err.to_string().contains("bandwidth"), "{err}");
}

#[test]
fn orders_outside_the_table_are_refused() {
    let options = CalibrationOptions {
        highest_order: 9,
        ..Default::default()
    };
    let err = learn_angle_correction(&loop_gains(), &[1.0], &[0.0], &options).unwrap_err();
    assert!(err.to_string().contains("order"), "{err}");
}

#[test]
fn a_capture_too_short_for_the_sensor_calibration_is_refused() {
    // 30 turns: the settling fifth (6 turns) teaches the online calibration 1 turn, which
    // leaves a fifth of the sine offset unlearned (measured: -0.041 for -0.05).
    let short = capture(
        Motion::ConstantSpeed {
            speed_rad_s: SPEED_RAD_S,
            duration_s: 30.0 / 200.0,
        },
        3,
    );
    let refused =
        learn_angle_correction(&loop_gains(), &short.y_c, &short.y_s, &Default::default());
    match refused {
        Err(Error::OutOfRange { argument, expected }) => {
            assert_eq!(argument, Argument::CalibrationCapture);
            assert!(expected.contains("settle_fraction"), "{expected}");
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
    // The same capture with half of it to settle (15 turns: 10 learned) is accepted.
    let options = CalibrationOptions {
        settle_fraction: 0.5,
        ..Default::default()
    };
    let learned = learn_angle_correction(&loop_gains(), &short.y_c, &short.y_s, &options).unwrap();
    assert!(
        (learned.sensor.offsets().1 + 0.05).abs() < 2e-3,
        "{:?}",
        learned.sensor
    );
}

/// Issue 21: the loop is amplitude-invariant and the diagnostics' thresholds come from the
/// capture's measured amplitude, so the same capture in int16 counts of amplitude 1800 and
/// in volts of amplitude 0.455 teaches the same harmonics, its offsets in its own units.
#[test]
fn captures_in_counts_and_in_volts_are_learned_as_the_normalised_one() {
    let gains = loop_gains();
    let learning = capture(
        Motion::ConstantSpeed {
            speed_rad_s: SPEED_RAD_S,
            duration_s: 50.0 / 200.0,
        },
        1,
    );
    let normalised =
        learn_angle_correction(&gains, &learning.y_c, &learning.y_s, &Default::default()).unwrap();
    let (a, b) = normalised.correction.coefficients();
    for (scale, round) in [(1800.0, true), (0.455, false)] {
        let scaled = |y: &[f64]| -> Vec<f64> {
            y.iter()
                .map(|v| {
                    if round {
                        (v * scale).round()
                    } else {
                        v * scale
                    }
                })
                .collect()
        };
        let (y_c, y_s) = (scaled(&learning.y_c), scaled(&learning.y_s));
        let learned = learn_angle_correction(&gains, &y_c, &y_s, &Default::default())
            .unwrap_or_else(|e| panic!("amplitude {scale}: {e}"));
        let (a_scaled, b_scaled) = learned.correction.coefficients();
        let largest = (0..MAX_CORRECTION_ORDER)
            .map(|k| (a_scaled[k] - a[k]).abs().max((b_scaled[k] - b[k]).abs()))
            .fold(0.0, f64::max);
        println!(
            "amplitude {scale}: coefficients within {largest:.2e} rad of the normalised capture's"
        );
        // Measured: within 1.4e-5 rad at 1800 counts (the rounding to counts), 6e-17 in volts.
        assert!(
            largest < 5e-5,
            "{scale}: {a_scaled:?} {b_scaled:?} against {a:?} {b:?}"
        );
        let (o_c, o_s) = learned.sensor.offsets();
        assert!((o_c / scale - 0.05).abs() < 2e-3 && (o_s / scale + 0.05).abs() < 2e-3);
    }
}
