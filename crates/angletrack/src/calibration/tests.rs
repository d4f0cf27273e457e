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

/// The RMS (rad, mean removed, last half) of the angle tracked by `gains` with `learned`
/// applied (or nothing) against the truth of `test`.
fn tracked_rms(
    gains: &Gains<f64, 3>,
    learned: Option<&CaptureCalibration>,
    test: &Scenario,
) -> f64 {
    let (sensor, correction) = learned
        .map_or((SensorCalibration::IDENTITY, AngleCorrection::NONE), |l| {
            (l.sensor, l.correction)
        });
    let chain = Chain::new((sensor, correction), *gains);
    let mut state = ChainState::new();
    let errors: Vec<f64> = (0..test.len())
        .map(|k| {
            let e = chain.update(&mut state, (test.y_c[k], test.y_s[k]));
            let d = e.angle - test.angle_rad[k];
            d.sin().atan2(d.cos())
        })
        .collect();
    rms_after_mean(&errors)
}

fn steady(turns: f64) -> Motion {
    Motion::ConstantSpeed {
        speed_rad_s: SPEED_RAD_S,
        duration_s: turns / 200.0,
    }
}

/// `a_k`, `b_k` of `amplitude sin(k theta + phase)`.
fn coefficients_of(amplitude: f64, phase: f64) -> (f64, f64) {
    (amplitude * phase.sin(), amplitude * phase.cos())
}

/// The target (docs/theory.md §12): self-calibrated with the calibration's own loop
/// on 50 turns at constant speed, the correction leaves below 0.5 mrad RMS on another
/// capture with a 5 % speed ripple.
#[test]
fn self_calibration_leaves_below_half_a_milliradian_on_a_rippling_capture() {
    let gains = loop_gains();
    let learning = capture(steady(50.0), 1);
    let learned = learn_angle_correction(
        &gains,
        &learning.y_c,
        &learning.y_s,
        None,
        &Default::default(),
    )
    .unwrap();
    assert_eq!(learned.method, CalibrationMethod::OwnLoop);
    let (a, b) = learned.correction.coefficients();
    for (k, amplitude, phase) in [(3, 5e-3, 0.3), (4, 5e-3, 1.1)] {
        let (a_true, b_true) = coefficients_of(amplitude, phase);
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
    // Orders 1 and 2 are the ellipse's: the angle error's are reported, not learned.
    assert_eq!(learned.orders[0].status, OrderStatus::NotRequested);
    assert_eq!((a[0], b[0], a[1], b[1]), (0.0, 0.0, 0.0, 0.0));
    let (o_c, o_s) = learned.sensor.offsets();
    assert!(
        (o_c - 0.05).abs() < 1e-3 && (o_s + 0.05).abs() < 1e-3,
        "{o_c} {o_s}"
    );
    assert!((learned.sensor.quadrature_rad() - 0.02).abs() < 1e-3);

    let test = capture(
        Motion::SpeedRipple {
            ripple_rad_s: 0.05 * SPEED_RAD_S,
            frequency_hz: 2.0,
            duration_s: 1.0,
        },
        2,
    );
    let (before, after) = (
        tracked_rms(&gains, None, &test),
        tracked_rms(&gains, Some(&learned), &test),
    );
    println!("self-calibrated: {before:.3e} rad uncorrected, {after:.3e} rad corrected");
    assert!(before > 1e-3, "{before}");
    assert!(after < 5e-4, "{after}");
}

/// The harmonic sensor at 25 electrical turns per second with a once-per-turn speed ripple
/// of 4.6 mrad of angle (a load, a coupling), for `turns` turns.
fn rippling_slowly(turns: f64, seed: u64) -> Scenario {
    let speed = TAU * 25.0;
    let profile = MotionProfile::new(0.0, speed).then(Motion::SpeedRipple {
        ripple_rad_s: 4.6e-3 * speed,
        frequency_hz: 25.0,
        duration_s: turns / 25.0,
    });
    Scenario::generate(&profile, &harmonic_sensor(), SAMPLE_PERIOD_S, seed).unwrap()
}

/// Issue 23: the speed ripple and the 3rd and 4th harmonics, learned against the reference
/// on one capture, leave below 0.5 mrad RMS on a second, tracked by a loop that follows
/// the ripple (the shaft's motion); a self-calibration asked for order 1 learns the ripple
/// as the sensor's error (docs/theory.md §12: without a reference the two cannot be told
/// apart).
#[test]
fn against_the_reference_a_speed_ripple_is_not_learned_as_sensor_error() {
    // Tc = 1.5 ms: it passes 1.3 % of the 25 Hz ripple (0.06 mrad).
    let gains = third_order_butterworth(1.5e-3, SAMPLE_PERIOD_S, Discretisation::PoleMatching)
        .unwrap()
        .gains;
    let passed = error_transfer(&gains, TAU * 25.0 * SAMPLE_PERIOD_S).norm();
    assert!(passed < 0.02, "{passed}");
    let learning = rippling_slowly(30.0, 5);
    let learned = learn_angle_correction(
        &gains,
        &learning.y_c,
        &learning.y_s,
        Some(&learning.angle_rad),
        &Default::default(),
    )
    .unwrap();
    assert_eq!(learned.method, CalibrationMethod::Reference);
    // Order 1 holds what the ellipse's noise left of the offsets, not the ripple's 4.6 mrad.
    assert!(
        learned.orders[0].amplitude_rad < 2e-4,
        "{:?}",
        learned.orders[0]
    );
    for k in [3, 4] {
        assert_eq!(learned.orders[k - 1].status, OrderStatus::Learned);
        assert!((learned.orders[k - 1].amplitude_rad - 5e-3).abs() < 1e-4);
    }
    let test = rippling_slowly(20.0, 6);
    let after = tracked_rms(&gains, Some(&learned), &test);
    let forced = CalibrationOptions {
        lowest_order: Some(1),
        self_calibration: true,
        ..Default::default()
    };
    let fooled =
        learn_angle_correction(&gains, &learning.y_c, &learning.y_s, None, &forced).unwrap();
    let fooled_after = tracked_rms(&gains, Some(&fooled), &test);
    println!(
        "against the reference {after:.3e} rad; self-calibrated from order 1 {fooled_after:.3e} rad \
         (order 1 learned {:.3e} rad)",
        fooled.orders[0].amplitude_rad
    );
    // Measured: 0.22 mrad, and 3.26 mrad self-calibrated from order 1 (docs/theory.md §12.4),
    // each held within 2x.
    assert!(after < 4e-4, "{after}");
    assert!((fooled.orders[0].amplitude_rad - 4.6e-3).abs() < 1e-3);
    assert!(
        fooled_after > 1.6e-3 && fooled_after < 6.4e-3,
        "{fooled_after}"
    );
}

/// A sensor whose order 1 and 2 angle errors no ellipse shows: learned against the
/// reference, with the encoder's zero 0.7 rad away from the sensor's.
#[test]
fn orders_one_and_two_are_learned_against_a_reference_with_its_own_zero() {
    let mut sensor = harmonic_sensor();
    sensor.angle_error_harmonics[2] = (1, 3e-3, 0.5);
    sensor.angle_error_harmonics[3] = (2, 2e-3, -0.4);
    let profile = MotionProfile::new(0.0, SPEED_RAD_S).then(steady(20.0));
    let s = Scenario::generate(&profile, &sensor, SAMPLE_PERIOD_S, 7).unwrap();
    let reference: Vec<f64> = s.angle_rad.iter().map(|t| t - 0.7).collect();
    let learned = learn_angle_correction(
        &loop_gains(),
        &s.y_c,
        &s.y_s,
        Some(&reference),
        &Default::default(),
    )
    .unwrap();
    let (a, b) = learned.correction.coefficients();
    for (k, amplitude, phase) in [
        (1, 3e-3, 0.5),
        (2, 2e-3, -0.4),
        (3, 5e-3, 0.3),
        (4, 5e-3, 1.1),
    ] {
        let (a_true, b_true) = coefficients_of(amplitude, phase);
        let (da, db) = (a[k - 1] - a_true, b[k - 1] - b_true);
        let sigma = learned.orders[k - 1].uncertainty_rad;
        println!("order {k}: error {da:.2e} {db:.2e}, uncertainty {sigma:.2e}");
        // Order 2 also holds what the ellipse's noise left of the imbalance and quadrature
        // (measured: 1.1e-4 rad, the quadrature fitted 8e-5 rad off).
        let tolerance = if k == 2 { 2e-4 } else { 1e-4 };
        assert!(
            da.abs() < tolerance && db.abs() < tolerance,
            "order {k}: {da} {db}"
        );
        // 20 turns of 100 samples, 1e-3 of noise: sqrt(2/2000) 1e-3 = 3.2e-5 per coefficient.
        // docs/theory.md §12.4 quotes 3.05e-5 (3.2e-5 expected): held within 2x.
        assert!((1.6e-5..6.1e-5).contains(&sigma), "{sigma}");
    }
}

#[test]
fn a_capture_too_slow_for_the_gains_starts_above_their_bandwidth_or_is_refused_by_flag() {
    let gains = loop_gains();
    let profile = MotionProfile::new(0.0, TAU * 15.0).then(Motion::ConstantSpeed {
        speed_rad_s: TAU * 15.0,
        duration_s: 1.0,
    });
    let slow = Scenario::generate(&profile, &harmonic_sensor(), SAMPLE_PERIOD_S, 3).unwrap();
    let with_gains = CalibrationOptions {
        own_loop: false,
        ..Default::default()
    };
    let learned = learn_angle_correction(&gains, &slow.y_c, &slow.y_s, None, &with_gains).unwrap();
    assert_eq!(learned.method, CalibrationMethod::Gains);
    let statuses: Vec<OrderStatus> = learned.orders.iter().map(|q| q.status).collect();
    println!("{statuses:?}");
    // The lowest order learnable with the gains is above 3; those below are not learned.
    let learnable = (1..=8)
        .find(|&k| statuses[k - 1] != OrderStatus::WithinLoopBandwidth)
        .unwrap();
    assert!(learnable > 3, "{statuses:?}");
    assert!(
        statuses[learnable..8]
            .iter()
            .all(|&s| s != OrderStatus::WithinLoopBandwidth)
    );
    let asked = CalibrationOptions {
        lowest_order: Some(3),
        ..with_gains
    };
    let err = learn_angle_correction(&gains, &slow.y_c, &slow.y_s, None, &asked).unwrap_err();
    assert_eq!(err.option, "lowest_order");
    assert!(err.reason.contains("lowest learnable order is"), "{err}");
    // The calibration's own loop learns order 3 at that speed.
    let own =
        learn_angle_correction(&gains, &slow.y_c, &slow.y_s, None, &Default::default()).unwrap();
    assert_eq!(own.orders[2].status, OrderStatus::Learned);
    assert!((own.orders[2].amplitude_rad - 5e-3).abs() < 3e-4);
}

/// Issue 23: with a fast loop, the calibration learned spurious orders 6 to 8 of 0.13 to
/// 0.27 mrad where the sensor has none: the loop follows part of orders 3 and 4, and their
/// products with the error's slope show at orders 6 to 8 against its angle (measured before
/// `undo_loop_following`: 0.06 to 0.13 mrad at Tc = 0.2 to 0.5 ms, learned). None is
/// learned now, with the gains' loop or the calibration's own.
#[test]
fn no_spurious_order_is_learned_near_a_fast_loops_bandwidth() {
    let learning = capture(steady(100.0), 8);
    let gains_loop = CalibrationOptions {
        own_loop: false,
        ..Default::default()
    };
    for (tc, options) in [
        (1.5e-4, gains_loop),
        (2e-4, gains_loop),
        (3e-4, gains_loop),
        (5e-4, gains_loop),
        (5e-4, CalibrationOptions::default()),
    ] {
        let fast = third_order_butterworth(tc, SAMPLE_PERIOD_S, Discretisation::PoleMatching)
            .unwrap()
            .gains;
        let learned =
            learn_angle_correction(&fast, &learning.y_c, &learning.y_s, None, &options).unwrap();
        for (k, q) in learned.orders.iter().enumerate().take(8) {
            println!(
                "Tc {tc} s, {}: order {}: {:.3e} +- {:.1e} {:?}",
                learned.method,
                k + 1,
                q.amplitude_rad,
                q.uncertainty_rad,
                q.status
            );
            if k >= 4 {
                assert_ne!(q.status, OrderStatus::Learned, "Tc {tc}: order {}", k + 1);
                // Measured: at most 3.8e-5 rad, the noise of this capture.
                assert!(q.amplitude_rad < 6e-5, "Tc {tc}: order {}", k + 1);
            }
        }
        assert!((learned.orders[3].amplitude_rad - 5e-3).abs() < 2e-4);
    }
}

#[test]
fn learning_every_order_warns_of_those_below_their_uncertainty() {
    let learning = capture(steady(20.0), 9);
    let options = CalibrationOptions {
        min_significance: 0.0,
        ..Default::default()
    };
    let learned = learn_angle_correction(
        &loop_gains(),
        &learning.y_c,
        &learning.y_s,
        Some(&learning.angle_rad),
        &options,
    )
    .unwrap();
    let warnings = learned.warnings();
    println!("{warnings:?}");
    let doubtful: Vec<usize> = (1..=8)
        .filter(|&k| learned.orders[k - 1].is_doubtful())
        .collect();
    assert!(!doubtful.is_empty() && doubtful.iter().all(|&k| k != 3 && k != 4));
    assert_eq!(warnings.len(), doubtful.len());
    assert!(warnings[0].contains("below its uncertainty"));
}

#[test]
fn options_and_captures_out_of_range_are_refused_naming_the_option() {
    let options = CalibrationOptions {
        highest_order: 9,
        ..Default::default()
    };
    let err = learn_angle_correction(&loop_gains(), &[1.0], &[0.0], None, &options).unwrap_err();
    assert_eq!(err.option, "highest_order");
    let short = capture(steady(3.0), 3);
    let err = learn_angle_correction(
        &loop_gains(),
        &short.y_c,
        &short.y_s,
        None,
        &Default::default(),
    )
    .unwrap_err();
    assert_eq!(err.option, "capture");
    assert!(err.reason.contains("at least 5"), "{err}");
    // 8 turns: the fifth left to settle leaves 6.4, half of them 4.
    let eight = capture(steady(8.0), 3);
    let settle = CalibrationOptions {
        settle_fraction: 0.5,
        ..Default::default()
    };
    let err =
        learn_angle_correction(&loop_gains(), &eight.y_c, &eight.y_s, None, &settle).unwrap_err();
    assert_eq!(err.option, "settle_fraction");
    let standstill = vec![0.3; 5000];
    let err = learn_angle_correction(
        &loop_gains(),
        &standstill,
        &standstill,
        None,
        &Default::default(),
    )
    .unwrap_err();
    assert_eq!(err.option, "capture");
}

/// Issue 21: the amplitude is measured, not assumed: the same capture in int16 counts of
/// amplitude 1800 and in volts of amplitude 0.455 on a 2.5 V bias teaches the same
/// harmonics, its offsets in its own units.
#[test]
fn captures_in_counts_and_in_volts_are_learned_as_the_normalised_one() {
    let gains = loop_gains();
    let learning = capture(steady(50.0), 1);
    let normalised = learn_angle_correction(
        &gains,
        &learning.y_c,
        &learning.y_s,
        None,
        &Default::default(),
    )
    .unwrap();
    let (a, b) = normalised.correction.coefficients();
    for (scale, bias, round) in [(1800.0, 0.0, true), (0.455, 2.5, false)] {
        let scaled = |y: &[f64]| -> Vec<f64> {
            y.iter()
                .map(|v| {
                    if round {
                        (v * scale).round()
                    } else {
                        bias + v * scale
                    }
                })
                .collect()
        };
        let (y_c, y_s) = (scaled(&learning.y_c), scaled(&learning.y_s));
        let learned = learn_angle_correction(&gains, &y_c, &y_s, None, &Default::default())
            .unwrap_or_else(|e| panic!("amplitude {scale}: {e}"));
        let (a_scaled, b_scaled) = learned.correction.coefficients();
        let largest = (0..MAX_CORRECTION_ORDER)
            .map(|k| (a_scaled[k] - a[k]).abs().max((b_scaled[k] - b[k]).abs()))
            .fold(0.0, f64::max);
        println!(
            "amplitude {scale}: coefficients within {largest:.2e} rad of the normalised capture's"
        );
        assert!(
            largest < 5e-5,
            "{scale}: {a_scaled:?} {b_scaled:?} against {a:?} {b:?}"
        );
        let (o_c, o_s) = learned.sensor.offsets();
        assert!(
            ((o_c - bias) / scale - 0.05).abs() < 1e-3
                && ((o_s - bias) / scale + 0.05).abs() < 1e-3
        );
    }
}

#[test]
fn a_reference_that_runs_the_other_way_or_at_another_multiple_is_named() {
    let profile = MotionProfile::new(0.0, SPEED_RAD_S).then(steady(20.0));
    let s = Scenario::generate(&profile, &harmonic_sensor(), SAMPLE_PERIOD_S, 8).unwrap();
    let learn = |reference: Vec<f64>| {
        learn_angle_correction(
            &loop_gains(),
            &s.y_c,
            &s.y_s,
            Some(&reference),
            &Default::default(),
        )
    };
    // An encoder counting the other way, with its own zero.
    let e = learn(s.angle_rad.iter().map(|t| 0.3 - t).collect()).unwrap_err();
    assert_eq!(e.option, "reference");
    assert!(
        e.reason.starts_with("it runs opposite to the sensor"),
        "{}",
        e.reason
    );
    // A mechanical reference of a sensor with 4 pole pairs, the pole pairs not stated.
    let e = learn(s.angle_rad.iter().map(|t| t / 4.0).collect()).unwrap_err();
    assert!(
        e.reason
            .starts_with("the sensor's angle turns 4 times as fast"),
        "{}",
        e.reason
    );
    // Pole pairs stated twice over: the reference turns twice as fast.
    let e = learn(s.angle_rad.iter().map(|t| t * 2.0).collect()).unwrap_err();
    assert!(
        e.reason.starts_with("the reference turns 2 times as fast"),
        "{}",
        e.reason
    );
}
