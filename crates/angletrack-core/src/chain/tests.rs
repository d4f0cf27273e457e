//! The chain on a sensor as it is on the bench (offsets, imbalance, quadrature, a harmonic
//! angle error, ADC counts), the online calibration through the feedback interface, and the
//! front end's faults.

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
    assert!(plain > 0.03, "plain {plain}");
    assert!(corrected < 3.5e-4, "corrected {corrected}");
}

#[test]
fn the_online_calibration_learns_through_the_feedback() {
    let gains = Gains::<f32, 3>::new([0.06, 0.0019, 3e-5], 1e-4).unwrap();
    let online = OnlineCalibration::new(CalibrationSettings::default(), 1e-4).unwrap();
    let chain = Chain::new(online, gains);
    let mut state: ChainState<Calibrator<f32>, f32, 3> = ChainState::new();
    state.front_end.enable();
    // The entry point the chain replaces, as a second witness.
    let (mut twin, mut twin_calibrator) = (ObserverState::new(), Calibrator::new());
    twin_calibrator.enable();
    let speed = 2.0 * core::f32::consts::PI * 50.0;
    for k in 0..4000 {
        let theta = speed * k as f32 * 1e-4;
        let (y_c, y_s) = (0.05 + theta.cos(), -0.05 + 1.1 * (theta + 0.05).sin());
        let e = chain.update(&mut state, (y_c, y_s));
        let f = gains.update_calibrated(&mut twin, &mut twin_calibrator, y_c, y_s);
        assert_eq!(e, f, "sample {k}");
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
