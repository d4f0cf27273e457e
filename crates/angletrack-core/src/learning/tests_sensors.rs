//! The online calibration on the sensors of issue 23, synthesised here: the imperfect
//! sensor (offsets 5 %, gain imbalance 10 %, quadrature 3 degrees, noise 1 %) at 60 Hz
//! electrical, sampled at 20 kHz, tracked by the Kalman ATO designed for a jerk of 1e5
//! rad/s^3 and a noise of 0.01; in volts on a 2.5 V bias, in 12-bit counts centred at 3100,
//! and with 20 % offsets.

extern crate std;

use std::vec::Vec;

use crate::test_support::{Bits, wrap};
use crate::*;

/// The sample period (s): 20 kHz.
const TS: f64 = 5e-5;
/// The electrical speed (rad/s): 60 Hz.
const SPEED: f64 = 2.0 * core::f64::consts::PI * 60.0;
/// Samples per electrical turn (333.3).
const SAMPLES_PER_TURN: f64 = 2.0 * core::f64::consts::PI / (SPEED * TS);

/// A sensor: `y_c = centre_c + A (offset_c + cos theta)`,
/// `y_s = centre_s + A (offset_s + g sin(theta + phi))`, each with Gaussian-like noise of
/// `noise A`, rounded to whole counts when `counts`.
#[derive(Clone, Copy)]
struct Sensor {
    centre: (f64, f64),
    amplitude: f64,
    offsets: (f64, f64),
    imbalance: f64,
    quadrature_rad: f64,
    noise: f64,
    counts: bool,
}

impl Sensor {
    /// The imperfect sensor of issue 23, amplitude 1, centred on 0.
    const IMPERFECT: Self = Self {
        centre: (0.0, 0.0),
        amplitude: 1.0,
        offsets: (0.05, -0.05),
        imbalance: 1.1,
        quadrature_rad: 3.0 * core::f64::consts::PI / 180.0,
        noise: 0.01,
        counts: false,
    };

    fn sample(&self, theta: f64, bits: &mut Bits) -> (f64, f64) {
        let mut noise = || (0..12).map(|_| bits.unit()).sum::<f64>() - 6.0; // unit variance
        let a = self.amplitude;
        let y_c = self.centre.0 + a * (self.offsets.0 + theta.cos() + self.noise * noise());
        let y_s = self.centre.1
            + a * (self.offsets.1
                + self.imbalance * (theta + self.quadrature_rad).sin()
                + self.noise * noise());
        if self.counts {
            (y_c.round(), y_s.round())
        } else {
            (y_c, y_s)
        }
    }
}

/// The Kalman ATO of the issue: jerk 1e5 rad/s^3 (`q = (j Ts^3)^2`), noise 0.01
/// (`r = 0.01^2`), 20 kHz.
fn gains<T: Real>() -> Gains<T, 3> {
    let q = (1e5 * TS * TS * TS) * (1e5 * TS * TS * TS);
    Gains::kalman(T::from_f64(q), T::from_f64(1e-4), T::from_f64(TS)).unwrap()
}

/// Runs `samples` samples of `sensor` at the angle `theta(k)` through a learning
/// calibrator in `T` (fault thresholds for the sensor's amplitude), returns the angle
/// errors (wrapped, f64), the calibrator and the faults latched.
fn run_at<T: Real>(
    sensor: Sensor,
    samples: usize,
    theta: impl Fn(usize) -> f64,
) -> (Vec<f64>, Calibrator<T>, Faults) {
    let gains = gains::<T>()
        .with_fault_thresholds(FaultThresholds::for_amplitude(T::from_f64(
            sensor.amplitude,
        )))
        .unwrap();
    let mut state = ObserverState::new();
    let mut calibrator = Calibrator::new();
    calibrator.enable();
    let mut bits = Bits(0x0123_4567_89ab_cdef);
    let errors = (0..samples)
        .map(|k| {
            let (y_c, y_s) = sensor.sample(theta(k), &mut bits);
            let e = Chain::new(gains.online_calibration(), gains).update_parts(
                &mut calibrator,
                &mut state,
                (T::from_f64(y_c), T::from_f64(y_s)),
            );
            wrap(theta(k) - e.angle.to_f64())
        })
        .collect();
    (errors, calibrator, state.latched_faults())
}

/// [`run_at`] over `turns` turns at 60 Hz.
fn run<T: Real>(sensor: Sensor, turns: f64) -> (Vec<f64>, Calibrator<T>, Faults) {
    let samples = (turns * SAMPLES_PER_TURN) as usize;
    run_at(sensor, samples, |k| 0.3 + SPEED * TS * k as f64)
}

/// The RMS of `errors` from turn `from` to the end.
fn rms_from(errors: &[f64], from: f64) -> f64 {
    let tail = &errors[(from * SAMPLES_PER_TURN) as usize..];
    (tail.iter().map(|e| e * e).sum::<f64>() / tail.len() as f64).sqrt()
}

/// The angle error's RMS over turns 20 to 40 of `sensor` through the learning calibrator is
/// below 2 mrad in `f64` and `f32` (measured 1.28 to 1.36 mrad, mostly the noise's), with
/// at least 30 turns learned and the status centred.
fn assert_calibrated(name: &str, sensor: Sensor) {
    let (errors, calibrator, _) = run::<f64>(sensor, 40.0);
    let (errors_f32, calibrator_f32, _) = run::<f32>(sensor, 40.0);
    let (rms, rms_f32) = (rms_from(&errors, 20.0), rms_from(&errors_f32, 20.0));
    std::println!(
        "{name}: RMS over turns 20 to 40 {rms:.3e} rad (f32 {rms_f32:.3e}), {} turns learned, \
         calibration {:?}",
        calibrator.turns_learned(),
        calibrator.calibration().parameters()
    );
    assert!(rms < 2e-3 && rms_f32 < 2e-3, "{name}: {rms} {rms_f32}");
    for learned in [calibrator.turns_learned(), calibrator_f32.turns_learned()] {
        assert!(learned >= 30, "{name}: {learned} turns");
    }
    assert_eq!(calibrator.status(), CalibrationStatus::Centred);
}

/// The imperfect sensor: uncorrected, its 1x error trips the loss of tracking (0.1 rad) and
/// leaves 40 mrad RMS or more (the issue measured 63); calibrated, below 2 mrad, although
/// the loss of tracking was latched on the way.
#[test]
fn the_imperfect_sensor_tracks_within_2_mrad() {
    let sensor = Sensor::IMPERFECT;
    assert_calibrated("imperfect", sensor);
    let gains = gains::<f64>();
    let mut state = ObserverState::new();
    let mut bits = Bits(5);
    let samples = (40.0 * SAMPLES_PER_TURN) as usize;
    let mut squares = 0.0;
    for k in 0..samples {
        let theta = 0.3 + SPEED * TS * k as f64;
        let (y_c, y_s) = sensor.sample(theta, &mut bits);
        let e = gains.update(&mut state, y_c, y_s);
        if k >= samples / 2 {
            squares += wrap(theta - e.angle).powi(2);
        }
    }
    let uncorrected = (squares / (samples - samples / 2) as f64).sqrt();
    assert!(uncorrected > 0.04, "{uncorrected}");
    assert!(state.latched_faults().contains(Faults::LOSS_OF_TRACKING));
    let (_, calibrator, latched) = run::<f64>(sensor, 40.0);
    assert!(latched.contains(Faults::LOSS_OF_TRACKING) && calibrator.turns_learned() >= 30);
}

/// Volts on a 2.5 V bias (amplitude 1 V): the centre is found, then learned.
#[test]
fn volts_on_a_bias_track_within_2_mrad() {
    let sensor = Sensor {
        centre: (2.5, 2.5),
        ..Sensor::IMPERFECT
    };
    assert_calibrated("volts on 2.5 V", sensor);
}

/// 12-bit counts centred at 3100 (amplitude 900 counts), rounded to whole counts.
#[test]
fn counts_off_mid_scale_track_within_2_mrad() {
    let sensor = Sensor {
        centre: (3100.0, 3100.0),
        amplitude: 900.0,
        counts: true,
        ..Sensor::IMPERFECT
    };
    assert_calibrated("counts at 3100", sensor);
}

/// Offsets of 20 % of the amplitude.
#[test]
fn offsets_of_20_percent_track_within_2_mrad() {
    let sensor = Sensor {
        offsets: (0.2, -0.2),
        ..Sensor::IMPERFECT
    };
    assert_calibrated("offsets 20 %", sensor);
}

/// A centre that cannot be found is reported, not guessed: a biased sensor at rest, and one
/// that turns 0.9 of a turn and stops, stay [`CalibrationStatus::FindingCentre`] with the
/// identity calibration and nothing learned; the same sensor turning finds its centre
/// within three turns (to 1 % of the amplitude).
#[test]
fn a_centre_that_cannot_be_found_is_reported() {
    let sensor = Sensor {
        centre: (2.5, 2.5),
        ..Sensor::IMPERFECT
    };
    let stop = (0.9 * SAMPLES_PER_TURN) as usize;
    let samples = (20.0 * SAMPLES_PER_TURN) as usize;
    for (what, turning) in [("at rest", 0), ("0.9 turn", stop)] {
        let (_, calibrator, _) = run_at::<f64>(sensor, samples, |k| {
            0.3 + SPEED * TS * k.min(turning) as f64
        });
        assert_eq!(
            calibrator.status(),
            CalibrationStatus::FindingCentre,
            "{what}"
        );
        assert_eq!(
            calibrator.calibration(),
            SensorCalibration::IDENTITY,
            "{what}"
        );
        assert_eq!(calibrator.turns_learned(), 0, "{what}");
    }
    let (_, calibrator, _) = run::<f64>(sensor, 3.0);
    assert_ne!(calibrator.status(), CalibrationStatus::FindingCentre);
    let (o_c, o_s) = calibrator.calibration().offsets();
    assert!(
        (o_c - 2.55).abs() < 0.01 && (o_s - 2.45).abs() < 0.01,
        "{o_c} {o_s}"
    );
}

/// A calibrator that learns nothing says so: on a rotor accelerating steadily (its speed
/// changes by 8 % a turn, so every turn fails the steady-speed test) the status turns
/// [`CalibrationStatus::Stalled`] after [`Calibrator::STALL_TURNS`] turns at speed, and
/// not before; at a steady speed the same sensor learns and stays centred.
#[test]
fn a_calibrator_that_learns_nothing_says_so() {
    let sensor = Sensor::IMPERFECT;
    // From 30 Hz, +8 % of 30 Hz per turn at 30 Hz: alpha = 0.08 w0 / (2 pi / w0).
    let w0 = SPEED / 2.0;
    let alpha = 0.08 * w0 * w0 / (2.0 * core::f64::consts::PI);
    let theta = |k: usize| {
        let t = TS * k as f64;
        0.3 + w0 * t + alpha * t * t / 2.0
    };
    let turns_at = |k: usize| (theta(k) - 0.3) / (2.0 * core::f64::consts::PI);
    let samples_for = |turns: f64| (0..).find(|&k| turns_at(k) >= turns).unwrap_or(0);
    let (_, early, _) = run_at::<f64>(sensor, samples_for(10.0), theta);
    assert_eq!(early.status(), CalibrationStatus::Centred);
    let (_, late, _) = run_at::<f64>(sensor, samples_for(24.0), theta);
    assert_eq!(late.turns_learned(), 0);
    assert_eq!(late.status(), CalibrationStatus::Stalled);
}
