//! Tests of the fixed-point path (`docs/theory.md §14`): the table and the phase detector's
//! accuracy, the integer atan2, the quantisation checks, tracking and turn counting, and
//! (property tests, in a build with overflow checks) that no input overflows anything.

use proptest::prelude::*;

use super::binary_angle::{SIN_Q15, atan2, detect};
use super::update::track_reciprocal;
use super::*;
use crate::{ConfigError, Faults, Parameter};

/// Samples at and next to the ends of the `i16` range.
const EXTREMES: [i16; 6] = [i16::MIN, -32767, -1, 0, 1, 32767];

const KALMAN: [f64; 3] = [0.1578, 0.0126, 0.000_34];

#[test]
fn sine_table_is_within_half_a_unit_of_q15() {
    for (k, &v) in SIN_Q15.iter().enumerate() {
        let exact = 32767.0 * libm::sin(core::f64::consts::TAU * k as f64 / 256.0);
        assert!((f64::from(v) - exact).abs() <= 0.5 + 1e-9, "entry {k}");
    }
}

#[test]
fn phase_detector_error_is_below_4e_5_of_the_amplitude() {
    // The signal at theta, the detector at theta - err for errors up to 0.2 rad: the output
    // over (amplitude 2^15) against sin(err), across the whole turn.
    let amplitude = 30000.0;
    let mut worst: f64 = 0.0;
    for k in 0..20_000 {
        let angle = (k as i64 * 214_748_367) as i32;
        let err = 0.2 * libm::sin(k as f64 * 0.37);
        let theta = binary_angle_to_rad(angle) + err;
        let y_c = libm::round(amplitude * libm::cos(theta)) as i32;
        let y_s = libm::round(amplitude * libm::sin(theta)) as i32;
        let (phase_error, _, _, _) = detect(angle, y_c, y_s);
        let got = f64::from(phase_error) / (amplitude * 32767.0);
        worst = worst.max((got - libm::sin(err)).abs());
    }
    // Table rounding (0.5 / 32767 per entry, up to 2.2e-5 on the pair), input rounding
    // (0.5 / 30000 per channel, up to 2.4e-5) and the residual's neglected terms (3e-7).
    assert!(worst < 4.7e-5, "worst {worst}");
}

#[test]
fn atan2_is_within_2_to_the_minus_25_of_a_turn() {
    for k in 0..10_000 {
        let theta = core::f64::consts::PI * (2.0 * k as f64 / 10_000.0 - 1.0);
        let (c, s) = (
            libm::round(20000.0 * libm::cos(theta)) as i32,
            libm::round(20000.0 * libm::sin(theta)) as i32,
        );
        let exact = binary_angle(libm::atan2(f64::from(s), f64::from(c)));
        let error = atan2(s, c).wrapping_sub(exact);
        // docs/theory.md §14 quotes 2^-26 of a turn: held within 2x.
        assert!(error.abs() < 1 << 7, "theta {theta}: error {error}");
    }
    assert_eq!(atan2(0, 0), 0);
    assert!(atan2(0, -32768).wrapping_sub(i32::MIN).abs() < 1 << 7);
}

#[test]
fn reciprocal_converges_on_every_amplitude_in_range() {
    for amplitude in [4100.0, 8192.0, 16384.0, 30000.0, 46340.0] {
        let half2 = (amplitude * amplitude / 2.0) as i32;
        let mut r = MAX_RECIPROCAL;
        for _ in 0..40 {
            r = track_reciprocal(r, half2);
        }
        let exact = 134_217_728.0 / amplitude;
        assert!(
            (f64::from(r) / exact - 1.0).abs() < 2e-3,
            "{amplitude}: {r} vs {exact}"
        );
    }
}

#[test]
fn reciprocal_stays_in_range_without_a_lower_clamp() {
    // The lowest step of every r in range is at the largest amplitude2_half, 2^30 (both
    // samples -32768): the tracker has no lower clamp.
    let lowest = (MIN_RECIPROCAL..=MAX_RECIPROCAL)
        .map(|r| track_reciprocal(r, 1 << 30))
        .min();
    assert_eq!(lowest, Some(MIN_RECIPROCAL));
    let largest = (MIN_RECIPROCAL..=MAX_RECIPROCAL)
        .map(|r| track_reciprocal(r, 0))
        .max();
    assert_eq!(largest, Some(MAX_RECIPROCAL));
}

#[test]
fn quantisation_is_within_2_to_the_minus_18_and_refuses_gains_that_round_to_zero() {
    let gains = FixedGains::<3>::new(KALMAN, 50e-6).unwrap();
    for (q, l) in gains.gains().iter().zip(KALMAN) {
        // The smallest multiplier, l3's, is about 232,000: half a unit is below 2^-18 of it.
        assert!((q / l - 1.0).abs() <= 2f64.powi(-18), "{q} vs {l}");
    }
    let err = FixedGains::<2>::new([0.05, 1e-25], 1e-4).unwrap_err();
    assert_eq!(err, ConfigError::OutOfRange(Parameter::SpeedGain));
    assert_eq!(err.parameter().name(), "gains[1] (l2)");
    let err = FixedGains::<3>::new([0.1, 0.01, -1e-6], 1e-4).unwrap_err();
    assert_eq!(err.parameter().name(), "gains[2] (l3)");
    let err = FixedGains::<2>::new([3.5, 0.1], 1e-4).unwrap_err();
    assert_eq!(err, ConfigError::OutOfRange(Parameter::AngleGain));
    let err = FixedGains::<2>::new([1.5, 1.1], 1e-4).unwrap_err();
    assert!(matches!(
        err,
        ConfigError::Unstable {
            parameter: Parameter::AngleGain,
            ..
        }
    ));
    let err = FixedGains::<2>::new([0.05, 0.001], f64::NAN).unwrap_err();
    assert_eq!(err, ConfigError::NotFinite(Parameter::SamplePeriod));
}

#[test]
fn quantised_loop_leaving_the_stability_region_is_refused() {
    // On the edge 2 l1 + l2 = 4: some l2 just inside it in f64 is pushed out by the
    // rounding of the quantised gains (a unit of the multipliers is 2 pi 2^-33 = 7.3e-10),
    // and refused with the condition that fails.
    let mut candidates = (0..50).flat_map(|i| {
        let l1 = 1.22 + 0.006 * f64::from(i);
        (1..100).map(move |k| (l1, 4.0 - 2.0 * l1 - f64::from(k) * 1e-11))
    });
    let refused = candidates.find_map(|(l1, l2)| {
        assert!(crate::Gains::<f64, 2>::new([l1, l2], 1e-4).is_ok());
        FixedGains::<2>::new([l1, l2], 1e-4).err()
    });
    assert_eq!(
        refused,
        Some(ConfigError::Unstable {
            parameter: Parameter::AngleGain,
            condition: "2 l1 + l2 < 4"
        })
    );
}

/// Samples of amplitude `amplitude` at the angles `theta(k)`.
fn sample(amplitude: f64, theta: f64) -> (i16, i16) {
    (
        libm::round(amplitude * libm::cos(theta)) as i16,
        libm::round(amplitude * libm::sin(theta)) as i16,
    )
}

/// The reciprocal `2^27 / amplitude` the state holds, relative to the exact one.
fn reciprocal_error(state: &FixedState<3>, amplitude: f64) -> f64 {
    f64::from(state.reciprocal()) * amplitude / 134_217_728.0 - 1.0
}

#[test]
fn reciprocal_is_set_by_the_first_sample_and_follows_an_amplitude_step_in_ten_windows() {
    let gains = FixedGains::<3>::new(KALMAN, 50e-6).unwrap();
    let window = MONITOR_WINDOW as usize;
    for (before, after) in [(16384.0, 8192.0), (16384.0, 30000.0), (30000.0, 16384.0)] {
        let mut state = FixedState::new();
        let (c, s) = sample(before, 0.3);
        gains.track(&mut state, c, s);
        assert!(reciprocal_error(&state, before).abs() < 2e-3, "{before}");
        let theta = |k: usize| 0.3 + 0.01 * k as f64;
        for k in 1..=10 * window {
            let (c, s) = sample(before, theta(k));
            gains.track(&mut state, c, s);
        }
        assert!(reciprocal_error(&state, before).abs() < 2e-3, "{before}");
        // Half a Newton step (itself at most a factor 3/2) per window's end: halving the
        // amplitude takes 9 windows to within 1 %; bounded here by 10.
        for k in 1..=10 * window {
            let (c, s) = sample(after, theta(10 * window + k));
            gains.track(&mut state, c, s);
        }
        let error = reciprocal_error(&state, after);
        assert!(error.abs() < 0.01, "{before} to {after}: {error}");
    }
}

#[test]
fn tracks_a_ramp_over_hundreds_of_turns_with_exact_turns() {
    let gains = FixedGains::<3>::new(KALMAN, 50e-6).unwrap();
    let mut state = FixedState::new();
    // A constant acceleration of 5e-5 rad per sample^2: 1 rad per sample (3.2 turns per
    // millisecond) after 20000 samples, 1592 turns on the way.
    let acceleration = 5e-5;
    let theta = |k: f64| 0.5 * acceleration * k * k;
    let n = 20_000;
    let mut e = FixedEstimate::default();
    for k in 0..n {
        let (c, s) = sample(16384.0, theta(k as f64));
        e = gains.update(&mut state, c, s);
        // After the first millisecond (the loop starts from rest), within 2e-4 rad.
        let position = gains.position_rad(&e);
        assert!(
            k < 1000 || (position - theta(k as f64)).abs() < 2e-4,
            "k {k}: {position}"
        );
    }
    let last = (n - 1) as f64;
    assert_eq!(
        e.turns,
        libm::round(theta(last) / core::f64::consts::TAU) as i64
    );
    assert!((gains.speed_rad_s(&e) - acceleration * last / 50e-6).abs() < 0.05);
    assert_eq!(state.latched_faults(), Faults::NONE);
}

#[test]
fn monitor_flags_loss_of_signal_and_false_lock() {
    let gains = FixedGains::<3>::new(KALMAN, 50e-6).unwrap();
    let mut state = FixedState::new();
    for k in 0..200 {
        let (c, s) = sample(16384.0, 0.01 * k as f64);
        gains.update(&mut state, c, s);
    }
    assert_eq!(state.latched_faults(), Faults::NONE);
    let mut lost = FixedEstimate::default();
    for _ in 0..50 {
        lost = gains.update(&mut state, 10, -3);
    }
    assert!(lost.faults.contains(Faults::LOSS_OF_SIGNAL));
    // A 180 degree jump of the signal: false lock, then re-acquired and clean.
    let mut state = FixedState::new();
    for _ in 0..100 {
        gains.update(&mut state, 16384, 0);
    }
    for _ in 0..40 {
        gains.update(&mut state, -16384, 0);
    }
    assert!(state.latched_faults().contains(Faults::FALSE_LOCK));
    let e = gains.update(&mut state, -16384, 0);
    assert!(
        (e.angle.wrapping_sub(i32::MIN)).abs() < 1 << 20,
        "{}",
        e.angle
    );
}

#[test]
fn unmonitored_gains_flag_nothing() {
    let gains = FixedGains::<2>::new([0.05, 0.0012], 1e-4)
        .unwrap()
        .with_monitor(None)
        .unwrap();
    let mut state = FixedState::new();
    for _ in 0..100 {
        assert_eq!(gains.update(&mut state, 3, 0).faults, Faults::NONE);
    }
}

proptest! {
    // Any samples, any gains in the stability region: in a test build (overflow checks on)
    // an overflow would panic; the state's bounds hold after every sample.
    #[test]
    fn no_input_overflows_or_leaves_the_bounds(
        samples in prop::collection::vec((any::<i16>(), any::<i16>()), 1..400),
        l1 in 1e-4_f64..1.55,
        l2_fraction in 1e-6_f64..1.0,
        l3_fraction in 1e-6_f64..1.0,
    ) {
        // Gains inside the order-3 region: l2 < 4 - 2 l1, l3 a fraction of its bound.
        let l2 = l2_fraction * (4.0 - 2.0 * l1) * 0.5;
        let l3 = l3_fraction * 2.0 * l2 * 4.0 * l1 / (8.0 - 4.0 * l1 - 2.0 * l2 + 2.0 * l2) * 0.5;
        if let Ok(gains) = FixedGains::<3>::new([l1, l2, l3], 1e-4) {
            let mut state = FixedState::new();
            for &(c, s) in &samples {
                let e = gains.update(&mut state, c, s);
                prop_assert!(e.phase_error.abs() <= 1 << 15);
                prop_assert!((MIN_RECIPROCAL..=MAX_RECIPROCAL).contains(&state.reciprocal()));
            }
        }
        // The 2nd-order gains are always accepted (l2 within the format): never vacuous.
        let gains = FixedGains::<2>::new([l1, l2.min(1.5)], 1e-4);
        prop_assert!(gains.is_ok(), "{:?}", gains);
        if let Ok(gains) = gains {
            let mut state = FixedState::new();
            for &(c, s) in &samples {
                let e = gains.update(&mut state, c, s);
                prop_assert!(e.phase_error.abs() <= 1 << 15);
            }
        }
    }

    #[test]
    fn extreme_samples_do_not_overflow(
        samples in prop::collection::vec(
            (prop::sample::select(&EXTREMES[..]),
             prop::sample::select(&EXTREMES[..])), 1..300),
        angle in any::<i32>(),
    ) {
        for &(c, s) in &samples {
            let (phase_error, in_phase, _, _) = detect(angle, c.into(), s.into());
            prop_assert!(phase_error.abs() < 1_540_000_000 && in_phase.abs() < 1_520_000_000);
        }
        let gains = FixedGains::<3>::new([1.5, 0.05, 0.001], 1e-4).unwrap();
        let mut state = FixedState::new();
        for &(c, s) in &samples {
            gains.update(&mut state, c, s);
        }
    }
}

#[test]
fn binary_angle_turns_agree_with_the_floats_turns() {
    // The turn arithmetic the first sample, the re-acquisition and the turn count share:
    // from every angle of a grid to every other within 0.9 pi (each kept 1e-6 turn off the
    // edge), the binary angle's carries (i16's `TurnArithmetic`) and the f64 wrap count the
    // same turns, and re-acquiring a sample lands on the same angle with the same turns.
    use crate::wrap::{crossed_turns, re_acquired};
    let step = core::f64::consts::TAU / 97.0;
    let mut crossings = [0; 3];
    for i in 0..97 {
        let from = -core::f64::consts::PI + (f64::from(i) + 0.5) * step;
        for j in -43..=43 {
            let change = f64::from(j) * 0.9 * core::f64::consts::PI / 43.0 + 1e-3;
            let mut to = from + change;
            let float_turns = crossed_turns::<f64>(from, to);
            to -= f64::from(float_turns) * core::f64::consts::TAU;
            let binary_turns = crossed_turns::<i16>(binary_angle(from), binary_angle(to));
            assert_eq!(binary_turns, float_turns, "{from} -> {to}");
            crossings[(float_turns + 1) as usize] += 1;
            let (c, s) = (
                libm::round(16384.0 * libm::cos(to)) as i16,
                libm::round(16384.0 * libm::sin(to)) as i16,
            );
            let (float_angle, float_whole) = re_acquired(from, f64::from(c), f64::from(s));
            let (angle, whole) = re_acquired::<i16>(binary_angle(from), c, s);
            assert_eq!(whole, float_whole, "{from} -> {to}");
            assert!(
                (binary_angle_to_rad(angle) - float_angle).abs() < 1e-6,
                "{from} -> {to}"
            );
        }
    }
    // Both ways across the edge, and mostly no crossing.
    assert!(
        crossings[0] > 100 && crossings[2] > 100 && crossings[1] > 4000,
        "{crossings:?}"
    );
}

#[test]
fn the_words_give_back_the_observer_and_each_bad_one_is_named() {
    let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6).unwrap();
    let (c, off) = (gains.constants(), gains.with_monitor(None).unwrap());
    assert_eq!(
        FixedGains::from_words(c, 50e-6, off.monitor_words()),
        Ok(off)
    );
    let words = gains.with_monitor(Some(28_800.0)).unwrap().monitor_words();
    let refused = |k: usize, v: u32| {
        let mut w = words;
        w[k] = v;
        FixedGains::from_words(c, 50e-6, w).unwrap_err().parameter()
    };
    assert_eq!(refused(0, 2), Parameter::NominalAmplitude);
    assert_eq!(refused(1, words[2] + 1), Parameter::LossOfSignalThreshold);
    assert_eq!(refused(2, words[3] + 1), Parameter::DegradationLowThreshold);
    assert_eq!(refused(4, words[5] + 1), Parameter::MagnitudeTolerance);
    assert_eq!(refused(6, 1 << 31), Parameter::LossOfTrackingThreshold);
    for (period, finite) in [
        (f64::NAN, false),
        (-f64::INFINITY, false),
        (-0.0, true),
        (-1e-4, true),
    ] {
        let err = FixedGains::from_words(c, period, words).unwrap_err();
        let expected = if finite {
            ConfigError::NotPositive(Parameter::SamplePeriod)
        } else {
            ConfigError::NotFinite(Parameter::SamplePeriod)
        };
        assert_eq!(err, expected, "{period}");
    }
    let zero = FixedConstants {
        multiplier: [0, 1, 1],
        acceleration_shift: 3,
    };
    let err = FixedGains::from_words(zero, 50e-6, words).unwrap_err();
    assert_eq!(err.parameter(), Parameter::AngleGain);
    let tilted = crate::FixedCalibration::from_q14([0, 0, 16384, 16385]).unwrap_err();
    assert_eq!(tilted.parameter(), Parameter::Quadrature);
}
