//! Tests of the calibrated run and of the nominal-amplitude estimate (`docs/theory.md §12`).

use std::f64::consts::{PI, TAU};

use crate::paper::{BENCHMARK_KALMAN_GAINS, BENCHMARK_SAMPLE_PERIOD_S};
use crate::*;

const AMPLITUDE: f64 = 1800.0;
const SPEED_RAD_S: f64 = TAU * 10.0;

/// The sensor at 1800 counts: offsets 5 %, imbalance 10 %, quadrature 3 degrees,
/// noise 1 % of the amplitude.
fn imperfect_sensor() -> SensorModel {
    SensorModel {
        amplitude: AMPLITUDE,
        offset_cos: 0.05 * AMPLITUDE,
        offset_sin: -0.05 * AMPLITUDE,
        amplitude_imbalance: 0.1,
        quadrature_error_rad: 3f64.to_radians(),
        noise_std: 0.01 * AMPLITUDE,
        ..SensorModel::default()
    }
}

/// 60 electrical turns at 10 Hz, well below the loop's 100 Hz bandwidth: the loop follows
/// the sensor's angle error, which is then the sensor's own (about 62 mrad RMS).
fn constant_speed(sensor: &SensorModel) -> Scenario {
    let profile = MotionProfile::new(0.3, SPEED_RAD_S).then(Motion::ConstantSpeed {
        speed_rad_s: SPEED_RAD_S,
        duration_s: 60.0 / 10.0,
    });
    Scenario::generate(&profile, sensor, BENCHMARK_SAMPLE_PERIOD_S, 5).unwrap()
}

fn gains(scenario: &Scenario) -> Gains<f64, 3> {
    Gains::new(BENCHMARK_KALMAN_GAINS, BENCHMARK_SAMPLE_PERIOD_S)
        .and_then(|g| {
            g.with_fault_thresholds(capture_fault_thresholds(&scenario.y_c, &scenario.y_s))
        })
        .unwrap()
}

/// RMS of the wrapped angle error after removing its mean, from electrical turn `turn` on.
fn rms_without_mean(scenario: &Scenario, run: &Run, turn: f64) -> f64 {
    let first = (turn * TAU / SPEED_RAD_S / scenario.sample_period_s) as usize;
    let errors: Vec<f64> = scenario.angle_rad[first..]
        .iter()
        .zip(&run.angle_rad[first..])
        .map(|(t, e)| (t - e + PI).rem_euclid(TAU) - PI)
        .collect();
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    (errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / errors.len() as f64).sqrt()
}

#[test]
fn the_calibrated_run_learns_the_sensor_and_removes_its_error() {
    let sensor = imperfect_sensor();
    let scenario = constant_speed(&sensor);
    let gains = gains(&scenario);
    let plain = rms_without_mean(&scenario, &run(&gains, &scenario), 20.0);
    let mut calibrator = Calibrator::new();
    calibrator.enable();
    let (calibrated, calibrator) = run_calibrated(&gains, calibrator, &scenario);
    let corrected = rms_without_mean(&scenario, &calibrated, 20.0);
    println!(
        "uncorrected {:.3} mrad, calibrated {:.3} mrad",
        plain * 1e3,
        corrected * 1e3
    );
    assert!(plain > 0.03, "the sensor's own error: {plain}");
    assert!(corrected < 3e-3 && corrected < plain / 10.0, "{corrected}");
    let learned = calibrator.calibration();
    let truth = sensor.calibration().unwrap();
    let (o, t) = (learned.offsets(), truth.offsets());
    assert!((o.0 - t.0).abs() < 0.005 * AMPLITUDE && (o.1 - t.1).abs() < 0.005 * AMPLITUDE);
    assert!((learned.amplitude_ratio() - truth.amplitude_ratio()).abs() < 5e-3);
    assert!((learned.quadrature_rad() - truth.quadrature_rad()).abs() < 5e-3);
    // Frozen at what it learned, from the first sample: as good from turn 2 on.
    let (frozen, after) = run_calibrated(&gains, Calibrator::from_calibration(learned), &scenario);
    assert_eq!(after.calibration(), learned);
    assert!(rms_without_mean(&scenario, &frozen, 2.0) < 3e-3);
}

#[test]
fn runs_at_any_amplitude_give_the_same_angles_with_thresholds_from_the_capture() {
    let unit = SensorModel::with_noise(0.01);
    let reference = constant_speed(&unit);
    let reference_run = run(&gains(&reference), &reference);
    for amplitude in [1e-3, AMPLITUDE, 1e5] {
        let scaled = constant_speed(&SensorModel {
            amplitude,
            noise_std: 0.01 * amplitude,
            ..unit
        });
        let thresholds = capture_fault_thresholds(&scaled.y_c, &scaled.y_s);
        let ratio = thresholds.nominal_amplitude / amplitude;
        assert!((ratio - 1.0).abs() < 0.01, "{amplitude}: {ratio}");
        let scaled_run = run(&gains(&scaled), &scaled);
        let worst = reference_run
            .angle_rad
            .iter()
            .zip(&scaled_run.angle_rad)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "amplitude {amplitude}: {worst}");
    }
}

#[test]
fn the_nominal_amplitude_is_the_median_of_the_first_samples() {
    let n = NOMINAL_AMPLITUDE_SAMPLES + 100;
    let mut y_c: Vec<f64> = (0..n).map(|k| 2.0 * (0.1 * k as f64).cos()).collect();
    let y_s: Vec<f64> = (0..n).map(|k| 2.0 * (0.1 * k as f64).sin()).collect();
    // A few bad and huge samples, and a different amplitude after the first samples.
    y_c[10] = f64::NAN;
    y_c[11] = 1e9;
    for v in &mut y_c[NOMINAL_AMPLITUDE_SAMPLES..] {
        *v *= 100.0;
    }
    let amplitude = nominal_amplitude(&y_c, &y_s).unwrap();
    // Around the figure's centre, found from the samples' percentiles (within 1e-6 here).
    assert!((amplitude - 2.0).abs() < 1e-5, "{amplitude}");
    // A bias of twice the amplitude moves it no more; a standstill on it is its magnitude.
    let biased: Vec<f64> = y_s.iter().map(|v| v + 4.0).collect();
    let amplitude = nominal_amplitude(&y_c, &biased).unwrap();
    assert!((amplitude - 2.0).abs() < 1e-5, "{amplitude}");
    assert_eq!(nominal_amplitude(&[3.0; 8], &[4.0; 8]), Some(5.0));
    assert_eq!(nominal_amplitude::<f32>(&[f32::NAN], &[0.0]), None);
    assert_eq!(nominal_amplitude::<f64>(&[], &[]), None);
    let defaults = capture_fault_thresholds::<f64>(&[0.0; 4], &[0.0; 4]);
    assert_eq!(defaults, FaultThresholds::default());
}

#[test]
fn the_sensor_model_maps_onto_the_core_calibration() {
    let sensor = imperfect_sensor();
    let calibration = sensor.calibration().unwrap();
    assert_eq!(
        calibration.parameters(),
        (90.0, -90.0, AMPLITUDE, AMPLITUDE * 1.1, 3f64.to_radians())
    );
    // The calibration undoes the model exactly (no noise, no 3rd harmonic).
    let exact = SensorModel {
        noise_std: 0.0,
        ..sensor
    };
    for k in 0..100 {
        let theta = 0.07 * k as f64;
        let (y_c, y_s) = exact.signals(theta, 0.0, 0.0);
        let (c, s) = calibration.correct(y_c, y_s);
        assert!((c - AMPLITUDE * theta.cos()).abs() < 1e-9);
        assert!((s - AMPLITUDE * theta.sin()).abs() < 1e-9, "{k}");
    }
    let beyond = SensorModel {
        quadrature_error_rad: 1.0,
        ..sensor
    };
    let err = beyond.calibration().unwrap_err();
    assert_eq!(err.argument(), Some(Argument::QuadratureError));
}

/// The capture of `sensor` at [`constant_speed`] as an ADC gives it: each sample rounded
/// to its count.
fn counts_of(sensor: &SensorModel) -> (Vec<f64>, Vec<f64>) {
    let scenario = constant_speed(sensor);
    scenario
        .y_c
        .iter()
        .zip(&scenario.y_s)
        .map(|(c, s)| (c.round(), s.round()))
        .unzip()
}

/// The sensor, uncalibrated, with 1 % noise, tracked as `angletrack track` tracks
/// its counts (`TrackerRun`, thresholds measured on the capture): the tracking-error level
/// follows its noise (8 times its angle noise, about 0.0095 rad), and no sample is flagged
/// and no fault latched over its 60 turns. At the fixed default of 0.05 (5 standard
/// deviations) the end of the loop's acquisition was flagged and latched.
#[test]
fn a_noisy_sensor_is_not_flagged_with_the_thresholds_measured_on_it() {
    use crate::tracker_file::TrackerFile;
    let (y_c, y_s) = counts_of(&imperfect_sensor());
    let measured = capture_fault_thresholds(&y_c, &y_s);
    let noise = angle_noise(&y_c, &y_s).unwrap();
    assert!((noise - 0.0095).abs() < 5e-4, "{noise}");
    assert_eq!(measured.tracking_error, 8.0 * noise);
    let flagged = |fault_thresholds| {
        let file = TrackerFile {
            fault_thresholds,
            ..benchmark_file()
        };
        let rows = tracked(&file, &y_c, &y_s);
        let flagged = rows.0.faults.iter().filter(|&&f| f != 0).count();
        (flagged, rows.1)
    };
    assert_eq!(flagged(None), (0, Faults::NONE));
    let (at_default, latched) = flagged(Some(measured.with_tracking_error(0.05)));
    assert!(
        at_default > 10 && latched == Faults::LOSS_OF_TRACKING,
        "{at_default}"
    );
    // At 50 Hz electrical the loop no longer follows the uncalibrated sensor's distortion
    // (its angle up to about 90 mrad off): its residual shows it, and the level, which
    // follows the noise only, flags it.
    let speed = 5.0 * SPEED_RAD_S;
    let profile = MotionProfile::new(0.3, speed).then(Motion::ConstantSpeed {
        speed_rad_s: speed,
        duration_s: 0.2,
    });
    let fast =
        Scenario::generate(&profile, &imperfect_sensor(), BENCHMARK_SAMPLE_PERIOD_S, 5).unwrap();
    let (_, latched) = tracked(&benchmark_file(), &fast.y_c, &fast.y_s);
    assert_eq!(latched, Faults::LOSS_OF_TRACKING);
}

/// The benchmark's Kalman gains as a tracker file that states no thresholds: they are
/// measured on the capture, as `angletrack track` runs it.
fn benchmark_file() -> crate::tracker_file::TrackerFile {
    crate::tracker_file::TrackerFile::new(crate::export::GainsFile {
        gains: BENCHMARK_KALMAN_GAINS.to_vec(),
        sample_period_s: BENCHMARK_SAMPLE_PERIOD_S,
        design: None,
    })
}

/// The rows of `(y_c, y_s)` tracked by `file`'s `TrackerRun`, and the faults it latched.
fn tracked(
    file: &crate::tracker_file::TrackerFile,
    y_c: &[f64],
    y_s: &[f64],
) -> (crate::tracker_file::TrackedRows, Faults) {
    let head = crate::tracker_file::CaptureHead {
        y_c,
        y_s,
        counts: None,
    };
    let mut run = crate::tracker_file::TrackerRun::new(file, "t.json", &head).unwrap();
    let rows = run.track(y_c, y_s);
    (rows, run.latched_faults().0)
}

/// A sin/cos sensor at 50 Hz electrical, 10 kHz, noise 0.2 %, its sine channel dead (noise
/// alone) from sample `dead_from`, tracked as `angletrack track` tracks it (no thresholds
/// stated: measured, with the roundness check on the circle the first samples show,
/// `sim/roundness.rs`): the rows from the 1000th (or the channel's death) whose angle is
/// more than 50 mrad off, and of them those not flagged.
fn dead_sine_channel_run(dead_from: usize) -> (usize, usize) {
    let mut seed = 1u64;
    let mut noise = || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.007
    };
    let theta: Vec<f64> = (0..20_000)
        .map(|k| 0.3 + TAU * 50.0 * k as f64 * BENCHMARK_SAMPLE_PERIOD_S)
        .collect();
    let y_c: Vec<f64> = theta.iter().map(|t| t.cos() + noise()).collect();
    let y_s: Vec<f64> = theta
        .iter()
        .enumerate()
        .map(|(k, t)| if k >= dead_from { 0.0 } else { t.sin() } + noise())
        .collect();
    let (rows, _) = tracked(&benchmark_file(), &y_c, &y_s);
    let (mut wrong, mut unflagged) = (0, 0);
    for (k, truth) in theta.iter().enumerate().skip(1000.max(dead_from)) {
        let error = (rows.angle_rad[k] - truth + PI).rem_euclid(TAU) - PI;
        if error.abs() > 0.05 {
            wrong += 1;
            unflagged += usize::from(rows.faults[k] == 0 && rows.front_end_faults[k] == 0);
        }
    }
    (wrong, unflagged)
}

#[test]
fn a_channel_dead_from_the_start_or_mid_run_is_flagged_on_every_wrong_row() {
    for dead_from in [0, 10_000] {
        let (wrong, unflagged) = dead_sine_channel_run(dead_from);
        assert!(
            wrong > 5_000 && unflagged == 0,
            "{dead_from}: {unflagged} of {wrong}"
        );
    }
}

/// The rows a healthy sensor's capture (1800 counts, round, Gaussian noise of
/// `noise_fraction` of the amplitude, 60 turns at 10 Hz) as 12-bit counts flags in fixed
/// point (`number_type: "fixed"`, as `angletrack track` tracks them): the level measured on
/// it, the rows flagged with the thresholds measured (none stated), with the default ones
/// at the measured level, and at the default level (0.05), each with the faults latched.
fn fixed_point_flags(noise_fraction: f64) -> (f64, [(usize, Faults); 3]) {
    let healthy = SensorModel {
        amplitude: AMPLITUDE,
        noise_std: noise_fraction * AMPLITUDE,
        ..SensorModel::default()
    };
    fixed_point_flags_of(&healthy)
}

/// [`fixed_point_flags`] of the capture of `sensor`.
fn fixed_point_flags_of(sensor: &SensorModel) -> (f64, [(usize, Faults); 3]) {
    use crate::tracker_file::{CaptureHead, TrackerFile, TrackerRun};
    let (y_c, y_s) = counts_of(sensor);
    let measured = capture_fault_thresholds(&y_c, &y_s);
    let head = CaptureHead {
        y_c: &y_c,
        y_s: &y_s,
        counts: None,
    };
    let file = fixed_point_file();
    let flagged = |fault_thresholds| {
        let file = TrackerFile {
            fault_thresholds,
            ..file.clone()
        };
        let mut run = TrackerRun::new(&file, "t.json", &head).unwrap();
        assert!(run.is_fixed());
        let rows = run.track(&y_c, &y_s);
        let flagged = rows.faults.iter().filter(|&&f| f != 0).count();
        (flagged, run.latched_faults().0)
    };
    let stated = FaultThresholds::for_amplitude(measured.nominal_amplitude);
    let level = measured.tracking_error;
    let runs = [
        flagged(None),
        flagged(Some(stated.with_tracking_error(level))),
        flagged(Some(stated)),
    ];
    (level, runs)
}

/// A healthy sensor with noise tracked in fixed point with the thresholds measured on its
/// capture: the fixed-point monitor takes the floats' level (8 times the angle noise,
/// `FaultThresholds::with_tracking_error_above_noise`), as the file's stated level, and
/// nothing is flagged or latched (the start-up is never flagged). With 1 % noise the level
/// is 0.080 (2627 in Q15) and the default 0.05 is about 5 standard deviations of the
/// residual: over these 60 turns neither flags a row (the largest residual is 0.043). With
/// 2 % noise (level 0.16) the default level flags about a thousand rows (1048) and latches
/// loss of tracking; the measured level none.
#[test]
fn a_noisy_sensor_in_fixed_point_is_not_flagged_with_the_thresholds_measured_on_it() {
    let none = (0, Faults::NONE);
    let (level, [measured, stated, default]) = fixed_point_flags(0.01);
    assert!((level - 0.080).abs() < 0.004, "{level}");
    assert_eq!((measured, stated, default), (none, none, none));
    let (level, [measured, stated, default]) = fixed_point_flags(0.02);
    assert!((level - 0.16).abs() < 0.008, "{level}");
    assert_eq!((measured, stated), (none, none));
    println!("2 % noise, default level: {default:?}");
    assert!(
        default.0 > 500 && default.1 == Faults::LOSS_OF_TRACKING,
        "{default:?}"
    );
}

/// The uncalibrated imperfect sensor (offsets 5 %, imbalance 10 %, quadrature 3 degrees,
/// 1 % noise) in fixed point with the thresholds measured on its capture: nothing flagged
/// or latched, as in `f32`. The measured thresholds state no roundness check (the pair
/// before a calibration need not be round) and the fixed-point monitor takes none either;
/// with the stated default thresholds, whose roundness check the imbalance leaves, rows
/// are flagged.
#[test]
fn an_uncalibrated_sensor_in_fixed_point_is_not_flagged_with_the_thresholds_measured_on_it() {
    let (_, [measured, _, default]) = fixed_point_flags_of(&imperfect_sensor());
    assert_eq!(measured, (0, Faults::NONE));
    assert!(
        default.1.contains(Faults::DEGRADATION_OF_SIGNAL),
        "{default:?}"
    );
}

/// The rows of a clean capture (100 Hz, then an acceleration of 2e5 rad/s^2 for 20 ms) more
/// than 50 / `pole_pairs` mrad off, tracked with the thresholds measured for a motor of
/// `pole_pairs` (its electrical angle more than 50 mrad off), and of them those not flagged.
fn acceleration_step_misses(pole_pairs: u32) -> (usize, usize) {
    let profile = MotionProfile::new(0.3, TAU * 100.0)
        .then(Motion::ConstantSpeed {
            speed_rad_s: TAU * 100.0,
            duration_s: 0.5,
        })
        .then(Motion::ConstantAcceleration {
            acceleration_rad_s2: 2e5,
            duration_s: 0.02,
        })
        .then(Motion::ConstantSpeed {
            speed_rad_s: TAU * 100.0 + 4e3,
            duration_s: 0.2,
        });
    let sensor = SensorModel {
        noise_std: 1e-4,
        ..SensorModel::default()
    };
    let s = Scenario::generate(&profile, &sensor, BENCHMARK_SAMPLE_PERIOD_S, 3).unwrap();
    let file = crate::tracker_file::TrackerFile {
        pole_pairs: Some(pole_pairs),
        ..benchmark_file()
    };
    let (rows, _) = tracked(&file, &s.y_c, &s.y_s);
    let bound = 0.05 / f64::from(pole_pairs);
    let (mut wrong, mut unflagged) = (0, 0);
    for (k, truth) in s.angle_rad.iter().enumerate().skip(2000) {
        if ((rows.angle_rad[k] - truth + PI).rem_euclid(TAU) - PI).abs() > bound {
            wrong += 1;
            unflagged += usize::from(rows.faults[k] == 0 && rows.front_end_faults[k] == 0);
        }
    }
    (wrong, unflagged)
}

#[test]
fn thresholds_measured_for_a_motors_pole_pairs_bound_its_electrical_angle() {
    // At 4 pole pairs the loop's lag through the step is beyond the electrical bound on
    // some rows, every one of them flagged; the thresholds of 1 pole pair let them through.
    let (wrong, unflagged) = acceleration_step_misses(4);
    assert!(wrong > 10 && unflagged == 0, "{unflagged} of {wrong}");
    let one = capture_fault_thresholds_for_pole_pairs(&[1.0, 0.0, -1.0], &[0.0, 1.0, 0.0], 1);
    assert_eq!(
        one,
        capture_fault_thresholds(&[1.0, 0.0, -1.0], &[0.0, 1.0, 0.0])
    );
}

/// A healthy capture of 12-bit signed counts of `amplitude` tracked in fixed point with the
/// width stated (`input.bits` 12: a 4-bit shift) and the thresholds measured.
fn fixed_point_run_of_amplitude(
    amplitude: f64,
) -> Result<crate::tracker_file::TrackerRun, crate::json_file::JsonFileError> {
    use crate::tracker_file::{CaptureHead, TrackerRun};
    let (y_c, y_s) = counts_of(&SensorModel {
        amplitude,
        noise_std: 0.002 * amplitude,
        ..SensorModel::default()
    });
    let head = CaptureHead {
        y_c: &y_c,
        y_s: &y_s,
        counts: None,
    };
    TrackerRun::new(&fixed_point_file(), "t.json", &head)
}

/// [`benchmark_file`] in fixed point, on 12-bit signed counts (`input.bits` 12: shifted
/// left by 4 bits to 16).
fn fixed_point_file() -> crate::tracker_file::TrackerFile {
    use crate::tracker_file::{Input, NumberType, TrackerFile};
    TrackerFile {
        number_type: NumberType::Fixed,
        input: Input::Bits {
            bits: 12,
            signed: true,
        },
        ..benchmark_file()
    }
}

#[test]
fn a_signal_too_small_for_the_fixed_point_monitor_at_its_stated_width_is_refused() {
    // 400 counts are 6400 in 16 bits, below 0.6 of the monitor's 16384 (9830): refused,
    // naming the width, rather than every row flagged. 700 counts (11200) run unflagged.
    let e = fixed_point_run_of_amplitude(400.0)
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("input.bits") && e.contains("is 6400.51 in 16 bits"),
        "{e}"
    );
    let mut run = fixed_point_run_of_amplitude(700.0).unwrap();
    let (y_c, y_s) = counts_of(&SensorModel {
        amplitude: 700.0,
        noise_std: 1.4,
        ..SensorModel::default()
    });
    let rows = run.track(&y_c, &y_s);
    assert_eq!(rows.faults[4000..].iter().filter(|&&f| f != 0).count(), 0);
}
