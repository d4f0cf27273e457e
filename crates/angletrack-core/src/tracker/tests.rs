//! The standard chain on a sensor as it is on the bench: 12-bit counts with offsets,
//! imbalance, quadrature and a harmonic angle error; clipping at stated and measured
//! rails; an open winding; a demodulator's lost excitation; in f32 and fixed point.

use crate::fixed::{binary_angle, binary_angle_to_rad};
use crate::*;

const KALMAN: [f32; 3] = [0.1578, 0.0126, 0.000_34];
const TS: f32 = 50e-6;
/// 50 Hz electrical at 20 kHz (rad per sample).
const STEP: f64 = 2.0 * core::f64::consts::PI * 50.0 * TS as f64;

/// The imperfect sensor, amplitude `amplitude` of full scale: offsets 2 % and -1.5 %, the
/// sine channel 3 % larger and 0.02 rad out of quadrature, a 3rd-harmonic error of 4 mrad.
fn sensor(theta: f64, amplitude: f64) -> (f64, f64) {
    let measured = theta + 0.004 * libm::sin(3.0 * theta);
    (
        amplitude * (0.02 + libm::cos(measured)),
        amplitude * (-0.015 + 1.03 * libm::sin(measured + 0.02)),
    )
}

/// A sample as 12-bit offset-binary counts, clipped to the ADC's codes.
fn counts(theta: f64, amplitude: f64) -> (u16, u16) {
    let (c, s) = sensor(theta, amplitude);
    let count = |v: f64| libm::round(2048.0 + 2048.0 * v).clamp(0.0, 4095.0) as u16;
    (count(c), count(s))
}

fn gains() -> Gains<f32, 3> {
    Gains::new(KALMAN, TS).unwrap()
}

fn counts_input(rails: Rails<i32>) -> Input<AdcScaling<f32>, f32> {
    Input::Counts {
        adc: AdcScaling::offset_binary(12).unwrap(),
        rails,
    }
}

/// The sensor's stored calibration in full-scale units (amplitude 0.8) and its correction.
fn stored() -> (SensorCalibration<f32>, AngleCorrection<f32>) {
    let calibration = SensorCalibration::new(0.016, -0.012, 0.8, 0.824, 0.02).unwrap();
    let mut b = [0.0; MAX_CORRECTION_ORDER];
    b[2] = 0.004;
    (
        calibration,
        AngleCorrection::new([0.0; MAX_CORRECTION_ORDER], b).unwrap(),
    )
}

/// The largest angle error (rad) over the last half of 8000 samples, and the samples with
/// a fault in that half.
fn run<O>(tracker: &Tracker<f32, Gains<f32, 3>>, amplitude: f64, mut each: O) -> (f64, usize)
where
    O: FnMut(&TrackerState<f32, ObserverState<f32, 3>>),
{
    let mut state = TrackerState::new();
    let (mut worst, mut flagged) = (0.0_f64, 0);
    for k in 0..8000 {
        let theta = STEP * k as f64;
        let e = tracker.update(&mut state, counts(theta, amplitude));
        each(&state);
        if k >= 4000 {
            worst = worst.max(libm::sin(e.angle as f64 - theta).abs());
            flagged += usize::from(!e.faults.is_empty());
        }
    }
    (worst, flagged)
}

#[test]
fn stored_calibration_and_either_correction_remove_what_the_sensor_adds() {
    let (calibration, harmonics) = stored();
    let table = AngleCorrectionTable::from_harmonics(&harmonics);
    let plain = TrackerFrontEnd::new(TrackerSettings {
        input: counts_input(Rails::Stated { min: 0, max: 4095 }),
        ..TrackerSettings::default()
    })
    .unwrap();
    let (plain_error, plain_flagged) = run(&Tracker::new(plain, gains()), 0.8, |_| {});
    assert!(plain_error > 0.02, "{plain_error}");
    assert_eq!(plain_flagged, 0);
    for correction in [
        CorrectionStage::Harmonics(harmonics),
        CorrectionStage::Table(table),
    ] {
        let settings = TrackerSettings {
            input: counts_input(Rails::Stated { min: 0, max: 4095 }),
            calibration: CalibrationStage::Stored(calibration),
            correction,
            ..TrackerSettings::default()
        };
        let tracker = Tracker::new(TrackerFrontEnd::new(settings).unwrap(), gains());
        let (error, flagged) = run(&tracker, 0.8, |_| {});
        assert!(error < 5e-4, "{correction:?}: {error}");
        assert_eq!(flagged, 0);
    }
}

#[test]
fn the_online_calibration_learns_in_the_tracker_state() {
    let settings = TrackerSettings {
        input: counts_input(Rails::Measured),
        calibration: CalibrationStage::Online(gains().online_calibration()),
        ..TrackerSettings::default()
    };
    let tracker = Tracker::new(TrackerFrontEnd::new(settings).unwrap(), gains());
    let mut state: TrackerState<f32, ObserverState<f32, 3>> = TrackerState::new();
    state.front_end.calibrator_mut().enable();
    for k in 0..20_000 {
        tracker.update(&mut state, counts(STEP * k as f64, 0.8));
    }
    let (o_c, o_s) = state.front_end.calibrator().calibration().offsets();
    assert!(
        (o_c - 0.016).abs() < 2e-3 && (o_s + 0.012).abs() < 2e-3,
        "{o_c} {o_s}"
    );
}

#[test]
fn clipping_is_flagged_at_stated_and_at_measured_rails() {
    // Amplitude 1.3 of full scale: a channel clips at the ADC's codes for most of a turn.
    let at_rail = |(c, s): (u16, u16)| [c, s].iter().any(|&v| v == 0 || v == 4095);
    for rails in [Rails::Stated { min: 0, max: 4095 }, Rails::Measured] {
        let settings = TrackerSettings {
            input: counts_input(rails),
            ..TrackerSettings::default()
        };
        let tracker = Tracker::new(TrackerFrontEnd::new(settings).unwrap(), gains());
        let mut state = TrackerState::new();
        let (mut clipped, mut missed, mut false_alarms) = (0, 0, 0);
        for k in 0..8000 {
            let raw = counts(STEP * k as f64, 1.3);
            tracker.update(&mut state, raw);
            let flagged = state.front_end.faults().contains(FrontEndFaults::CLIPPING);
            if k >= 4000 {
                clipped += usize::from(at_rail(raw));
                missed += usize::from(at_rail(raw) && !flagged);
                false_alarms += usize::from(!at_rail(raw) && flagged);
            }
        }
        assert!(clipped > 2000, "{clipped}");
        // Stated: exact. Measured: the rails found within the first turns.
        assert_eq!((missed, false_alarms), (0, 0), "{rails:?} of {clipped}");
    }
}

#[test]
fn a_still_shaft_is_not_clipping_with_measured_rails() {
    let settings = TrackerSettings {
        input: counts_input(Rails::Measured),
        ..TrackerSettings::default()
    };
    let tracker = Tracker::new(TrackerFrontEnd::new(settings).unwrap(), gains());
    let mut state = TrackerState::new();
    let mut e = tracker.update(&mut state, (2048u16 + 900, 2048u16 + 1559));
    for _ in 0..20_000 {
        e = tracker.update(&mut state, (2048u16 + 900, 2048u16 + 1559));
        assert!(e.faults.is_empty(), "{:?}", state.front_end.faults());
    }
    assert!(
        (e.angle - libm::atan2f(1559.0, 900.0)).abs() < 1e-4,
        "{}",
        e.angle
    );
}

#[test]
fn an_open_winding_is_flagged_and_the_observer_coasts() {
    let settings = TrackerSettings {
        input: counts_input(Rails::Stated { min: 0, max: 4095 }),
        winding: Some(WindingCheck::new(0.8).unwrap()),
        ..TrackerSettings::default()
    };
    let tracker = Tracker::new(TrackerFrontEnd::new(settings).unwrap(), gains());
    let mut state = TrackerState::new();
    let mut theta = 0.0;
    for k in 0..4000 {
        theta = STEP * k as f64;
        tracker.update(&mut state, counts(theta, 0.8));
    }
    // The cosine winding opens at 0 rad electrical, where it carries the whole amplitude.
    let (_, raw_s) = counts(theta + STEP, 0.8);
    let e = tracker.update(&mut state, (2048u16, raw_s));
    assert!(e.faults.contains(Faults::FRONT_END));
    assert_eq!(state.front_end.faults(), FrontEndFaults::WINDING);
    assert!(state.front_end.coasting());
    assert_eq!(state.front_end.clear_faults(), FrontEndFaults::WINDING);
    assert_eq!(state.front_end.latched_faults(), FrontEndFaults::NONE);
}

#[test]
fn a_lost_excitation_coasts_and_is_latched() {
    let tracker: Tracker<f32, _> = Tracker::new(
        TrackerFrontEnd::new(TrackerSettings::default()).unwrap(),
        gains(),
    );
    let mut state = TrackerState::new();
    let speed = 0.0157_f32;
    for k in 0..4000 {
        let theta = speed * k as f32;
        tracker.update(
            &mut state,
            ((theta.cos(), theta.sin()), FrontEndFaults::NONE),
        );
    }
    for _ in 0..50 {
        let e = tracker.update(&mut state, ((0.0, 0.0), FrontEndFaults::LOSS_OF_EXCITATION));
        assert!(e.faults.contains(Faults::FRONT_END));
    }
    let theta = speed * 4050.0;
    let e = tracker.update(
        &mut state,
        ((theta.cos(), theta.sin()), FrontEndFaults::NONE),
    );
    assert!(libm::remainderf(e.angle - theta, core::f32::consts::TAU).abs() < 0.01);
    assert!(
        state
            .front_end
            .latched_faults()
            .contains(FrontEndFaults::LOSS_OF_EXCITATION)
    );
}

#[test]
fn fixed_point_counts_with_stored_calibration_and_table() {
    let (calibration, harmonics) = stored();
    let (o_c, o_s) = calibration.offsets();
    let (a_c, a_s) = calibration.amplitudes();
    let in_counts = SensorCalibration::<f64>::new(
        f64::from(o_c) * 32768.0,
        f64::from(o_s) * 32768.0,
        f64::from(a_c) * 32768.0,
        f64::from(a_s) * 32768.0,
        f64::from(calibration.quadrature_rad()),
    )
    .unwrap();
    let harmonics = AngleCorrection::<f64>::new(
        harmonics.coefficients().0.map(f64::from),
        harmonics.coefficients().1.map(f64::from),
    )
    .unwrap();
    let adc = AdcCounts::offset_binary(12).unwrap();
    let settings = TrackerSettings::<i16> {
        input: Input::Counts {
            adc,
            rails: Rails::Stated { min: 0, max: 4095 },
        },
        winding: (),
        calibration: Some(FixedCalibration::new(&in_counts).unwrap()),
        correction: Some(FixedAngleCorrectionTable::from_harmonics(&harmonics)),
    };
    let front_end = TrackerFrontEnd::new(settings).unwrap();
    assert_eq!(front_end.adc_range(), Some((-32768, 32752)));
    let observer = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)
        .and_then(|g| g.with_monitor(Some(0.8 * 32768.0)))
        .unwrap();
    let tracker = Tracker::new(front_end, observer);
    let mut state = TrackerState::new();
    let mut worst = 0.0_f64;
    for k in 0..8000 {
        let theta = STEP * k as f64;
        let e = tracker.update(&mut state, counts(theta, 0.8));
        if k >= 4000 {
            let error = binary_angle_to_rad(e.angle.wrapping_sub(binary_angle(theta)));
            worst = worst.max(error.abs());
            assert!(
                e.faults.is_empty(),
                "{k}: {:?} {:?}",
                e.faults,
                state.front_end.faults()
            );
        }
    }
    assert!(worst < 2e-3, "{worst}");
    // A code at a rail clips, exactly.
    tracker.update(&mut state, (4095u16, 2048u16));
    assert_eq!(state.front_end.faults(), FrontEndFaults::CLIPPING);
}

#[test]
fn ranges_that_are_not_ordered_are_refused() {
    let units = TrackerSettings::<f64> {
        input: Input::Units {
            rails: Rails::Stated {
                min: 1.0,
                max: -1.0,
            },
        },
        ..TrackerSettings::default()
    };
    assert_eq!(
        TrackerFrontEnd::new(units).unwrap_err().parameter(),
        Parameter::AdcRange
    );
    let nan = TrackerSettings::<f64> {
        input: Input::Units {
            rails: Rails::Stated {
                min: f64::NAN,
                max: 1.0,
            },
        },
        ..TrackerSettings::default()
    };
    assert_eq!(
        TrackerFrontEnd::new(nan).unwrap_err().parameter(),
        Parameter::AdcRange
    );
    // Two codes the fixed-point ADC's saturation joins (both beyond 16 bits).
    let joined = TrackerSettings::<i16> {
        input: Input::Counts {
            adc: AdcCounts::offset_binary(12).unwrap(),
            rails: Rails::Stated {
                min: 5000,
                max: 6000,
            },
        },
        ..TrackerSettings::default()
    };
    assert_eq!(
        TrackerFrontEnd::new(joined).unwrap_err().parameter(),
        Parameter::AdcRange
    );
}
