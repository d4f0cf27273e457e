//! The chain on a sensor as it is on the bench (offsets, imbalance, quadrature, a harmonic
//! angle error, ADC counts), the online calibration through the feedback interface, and the
//! front end's faults.

use crate::fixed::{binary_angle, binary_angle_to_rad};
use crate::*;

const KALMAN: [f32; 3] = [0.1578, 0.0126, 0.000_34];
const TS: f32 = 50e-6;
/// 50 Hz electrical at 20 kHz (rad per sample).
const STEP: f64 = 2.0 * core::f64::consts::PI * 50.0 * TS as f64;

/// The imperfect sensor: offsets 2 % and -1.5 %, the sine channel 3 % larger and 0.02 rad
/// out of quadrature, a 3rd-harmonic angle error of 4 mrad; amplitude 0.8 of full scale.
fn sensor(theta: f64) -> (f64, f64) {
    let measured = theta + 0.004 * libm::sin(3.0 * theta);
    (
        0.8 * (0.02 + libm::cos(measured)),
        0.8 * (-0.015 + 1.03 * libm::sin(measured + 0.02)),
    )
}

/// The sample as 12-bit offset-binary counts.
fn counts(theta: f64) -> (u16, u16) {
    let (c, s) = sensor(theta);
    let count = |v: f64| libm::round(2048.0 + 2048.0 * v) as u16;
    (count(c), count(s))
}

/// The largest angle error (rad, wrapped) over the last half of 8000 samples of `track`.
fn worst_error(mut track: impl FnMut((u16, u16)) -> f32) -> f64 {
    let mut worst = 0.0_f64;
    for k in 0..8000 {
        let theta = STEP * k as f64;
        let angle = track(counts(theta)) as f64;
        if k >= 4000 {
            worst = worst.max(libm::sin(angle - theta).abs());
        }
    }
    worst
}

#[test]
fn the_whole_front_end_removes_what_the_sensor_adds() {
    let gains = Gains::<f32, 3>::new(KALMAN, TS).unwrap();
    let adc = AdcScaling::offset_binary(12).unwrap();
    // The stored calibration in full-scale units, and the angle correction.
    let calibration = SensorCalibration::new(0.016, -0.012, 0.8, 0.824, 0.02).unwrap();
    let mut b = [0.0; MAX_CORRECTION_ORDER];
    b[2] = 0.004;
    let correction = AngleCorrection::new([0.0; MAX_CORRECTION_ORDER], b).unwrap();

    let full = Chain::new((adc, (calibration, correction)), gains);
    let mut state = ChainState::new();
    let corrected = worst_error(|raw| full.update(&mut state, raw).angle);

    let adc_only = Chain::new(adc, gains);
    let mut plain_state = ChainState::new();
    let plain = worst_error(|raw| adc_only.update(&mut plain_state, raw).angle);

    // Uncorrected, the 1x and 2x errors of the offsets, imbalance and quadrature and the
    // 3x error reach 47 mrad at the worst; corrected, 0.18 mrad is left (the 12-bit
    // quantisation and the loop's lag). Each bound within a factor 2 of the measured.
    assert!(plain > 0.03 && plain < 0.094, "plain {plain}");
    assert!(corrected < 3.5e-4, "corrected {corrected}");
}

#[test]
fn the_online_calibration_learns_through_the_feedback() {
    let gains = Gains::<f32, 3>::new([0.06, 0.0019, 3e-5], 1e-4).unwrap();
    let online = OnlineCalibration::new(CalibrationSettings::default(), 1e-4).unwrap();
    let chain = Chain::new(online, gains);
    let mut state: ChainState<Calibrator<f32>, ObserverState<f32, 3>> = ChainState::new();
    state.front_end.enable();
    let speed = 2.0 * core::f32::consts::PI * 50.0;
    for k in 0..6000 {
        let theta = speed * k as f32 * 1e-4;
        let (y_c, y_s) = (0.05 + theta.cos(), -0.05 + 1.1 * (theta + 0.05).sin());
        chain.update(&mut state, (y_c, y_s));
    }
    let learned = state.front_end.calibration();
    let (o_c, o_s) = learned.offsets();
    assert!((o_c - 0.05).abs() < 5e-3 && (o_s + 0.05).abs() < 5e-3);
    assert!((learned.amplitude_ratio() - 1.1).abs() < 5e-3);
    assert!(state.front_end.turns_learned() > 10);
}

#[test]
fn a_calibration_beyond_its_bounds_is_a_fault_of_the_estimate_and_latched() {
    let gains = Gains::<f64, 2>::new([0.05, 0.0012], 1e-4).unwrap();
    let online = OnlineCalibration::new(CalibrationSettings::default(), 1e-4).unwrap();
    let chain = Chain::new(online, gains);
    // A stored calibration of 30 % imbalance (the default bound is 20 %), frozen.
    let stored = SensorCalibration::new(0.0, 0.0, 1.0, 1.3, 0.0).unwrap();
    let mut state = ChainState {
        front_end: Calibrator::from_calibration(stored),
        observer: ObserverState::new(),
    };
    let e = chain.update(&mut state, (1.0, 0.0));
    assert!(e.faults.contains(Faults::AMPLITUDE_MISMATCH));
    assert!(
        state
            .observer
            .latched_faults()
            .contains(Faults::AMPLITUDE_MISMATCH)
    );
    // Off, the calibration neither corrects nor flags.
    state.front_end.disable();
    state.observer.clear_faults();
    let e = chain.update(&mut state, (1.0, 0.0));
    assert!(!e.faults.contains(Faults::AMPLITUDE_MISMATCH));
}

/// The sensor's stored calibration in units of full scale, and its harmonics.
fn sensor_corrections() -> (SensorCalibration<f32>, AngleCorrection<f32>) {
    let calibration = SensorCalibration::new(0.016, -0.012, 0.8, 0.824, 0.02).unwrap();
    let mut b = [0.0; MAX_CORRECTION_ORDER];
    b[2] = 0.004;
    (
        calibration,
        AngleCorrection::new([0.0; MAX_CORRECTION_ORDER], b).unwrap(),
    )
}

#[test]
fn a_table_corrects_as_the_harmonics_do() {
    let gains = Gains::<f32, 3>::new(KALMAN, TS).unwrap();
    let adc = AdcScaling::offset_binary(12).unwrap();
    let (calibration, harmonics) = sensor_corrections();
    let table = AngleCorrectionTable::<f32, 256>::from_harmonics(&harmonics);
    let chain = Chain::new((adc, (calibration, table)), gains);
    let mut state = ChainState::new();
    let worst = worst_error(|raw| chain.update(&mut state, raw).angle);
    // 0.174 mrad, as the harmonics' 0.176 (the table's interpolation adds at most
    // h^2 max|d''| / 8 = 2.7e-6 rad at L = 256).
    assert!(worst < 3.45e-4, "{worst}");

    // The same error measured as a curve of 64 points: linear between them, off by up to
    // 4 mrad (1 - cos(3 pi / 64)) = 0.04 mrad: 0.176 mrad measured.
    let curve: [f32; 64] = core::array::from_fn(|j| {
        harmonics.error_at(-core::f32::consts::PI + core::f32::consts::TAU * j as f32 / 64.0)
    });
    let from_curve = AngleCorrectionTable::<f32, 256>::from_curve(&curve).unwrap();
    let chain = Chain::new((adc, (calibration, from_curve)), gains);
    let mut state = ChainState::new();
    let worst = worst_error(|raw| chain.update(&mut state, raw).angle);
    assert!(worst < 3.5e-4, "{worst}");
}

/// The fixed-point chain's worst angle error (rad) over the last half of 8000 samples.
fn fixed_worst_error<F: Stage<i16, (u16, u16)>>(front_end: F, state: F::State) -> f64 {
    let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)
        .unwrap()
        .with_monitor(Some(26_214.0))
        .unwrap();
    let chain = Chain::new(front_end, gains);
    let mut state = ChainState {
        front_end: state,
        observer: FixedState::new(),
    };
    let mut worst = 0.0_f64;
    for k in 0..8000 {
        let theta = STEP * k as f64;
        let e = chain.update(&mut state, counts(theta));
        if k >= 4000 {
            worst = worst.max(libm::sin(binary_angle_to_rad(e.angle) - theta).abs());
            assert_eq!(e.faults, Faults::NONE, "sample {k}");
        }
    }
    worst
}

#[test]
fn the_fixed_point_chain_corrects_in_integers() {
    let adc = AdcCounts::offset_binary(12).unwrap();
    // The calibration in the observer's 16-bit counts (full scale 32768), and the table.
    let f = 32768.0 * 0.8;
    let stored = SensorCalibration::<f64>::new(0.02 * f, -0.015 * f, f, 1.03 * f, 0.02).unwrap();
    let calibration = FixedCalibration::new(&stored).unwrap();
    let mut b = [0.0; MAX_CORRECTION_ORDER];
    b[2] = 0.004;
    let harmonics = AngleCorrection::<f64>::new([0.0; MAX_CORRECTION_ORDER], b).unwrap();
    let table = FixedAngleCorrectionTable::from_table(
        &AngleCorrectionTable::<f64, 256>::from_harmonics(&harmonics),
    );
    let corrected = fixed_worst_error((adc, (calibration, table)), ((), ((), ())));
    let plain = fixed_worst_error(adc, ());
    // As the f32 chain: 47 mrad uncorrected; 0.188 mrad corrected (0.174 in f32, plus the
    // 16-bit quantisation of the calibration and of the table).
    assert!(plain > 0.03 && plain < 0.094, "plain {plain}");
    assert!(corrected < 3.75e-4, "corrected {corrected}");
}

#[test]
fn the_fixed_rotation_follows_the_float_one() {
    let errors: [f64; 8] = core::array::from_fn(|k| 0.24 * libm::sin(k as f64));
    let table = AngleCorrectionTable::<f64, 8>::new(errors).unwrap();
    let fixed = FixedAngleCorrectionTable::from_table(&table);
    let mut worst = 0.0_f64;
    for i in 0..1000 {
        let angle = -core::f64::consts::PI + 6.28e-3 * i as f64;
        let (y_c, y_s) = (
            30000.0 * libm::cos(2.0 * angle),
            30000.0 * libm::sin(2.0 * angle),
        );
        let (c, s) = table.rotate(angle, y_c, y_s);
        let (fc, fs) = fixed.rotate(binary_angle(angle), y_c as i16, y_s as i16);
        worst = worst
            .max((f64::from(fc) - c).abs())
            .max((f64::from(fs) - s).abs());
    }
    // The Q15 error of 2^-15 rad times 30000 counts, and the roundings: 2.2 counts.
    assert!(worst < 4.0, "{worst}");
}

#[test]
fn an_absent_stage_is_skipped_and_a_present_one_learns() {
    let gains = Gains::<f32, 3>::new([0.06, 0.0019, 3e-5], 1e-4).unwrap();
    let online = OnlineCalibration::new(CalibrationSettings::default(), 1e-4).unwrap();
    let present = Chain::new(Some(online), gains);
    let absent = Chain::new(None::<OnlineCalibration<f32>>, gains);
    let mut learning: ChainState<Calibrator<f32>, ObserverState<f32, 3>> = ChainState::new();
    let mut plain: ChainState<Calibrator<f32>, ObserverState<f32, 3>> = ChainState::new();
    learning.front_end.enable();
    let mut bare = ObserverState::new();
    let speed = 2.0 * core::f32::consts::PI * 50.0;
    for k in 0..4000 {
        let theta = speed * k as f32 * 1e-4;
        let (y_c, y_s) = (0.05 + theta.cos(), -0.05 + 1.1 * (theta + 0.05).sin());
        present.update(&mut learning, (y_c, y_s));
        let e = absent.update(&mut plain, (y_c, y_s));
        assert_eq!(e, gains.update(&mut bare, y_c, y_s), "sample {k}");
    }
    let (o_c, o_s) = learning.front_end.calibration().offsets();
    assert!((o_c - 0.05).abs() < 5e-3 && (o_s + 0.05).abs() < 5e-3);
    assert!(learning.front_end.turns_learned() > 10);
}
