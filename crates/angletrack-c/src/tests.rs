//! Tests of the whole API through its `extern "C"` functions, called as C calls them.

#![allow(unsafe_code)]

// The crate's other test modules, in files of their own beside this one.
#[path = "tests_chain.rs"]
mod tests_chain;
#[path = "tests_chain_fixed.rs"]
mod tests_chain_fixed;
#[path = "tests_demodulator.rs"]
mod tests_demodulator;
#[path = "tests_front_end.rs"]
mod tests_front_end;
#[path = "tests_support.rs"]
pub(crate) mod tests_support;
#[path = "tests_units.rs"]
mod tests_units;

use core::f32::consts::{PI, TAU};
use core::ptr::{null, null_mut};

use crate::slot::Slot;
use crate::tests::tests_support::Words;
use crate::*;

/// The 3rd-order gains of the repository's benchmark (10 kHz).
const GAINS_3: [f32; 3] = [0.094_326_17, 0.000_562_075, 1.213_522e-5];
/// The 2nd-order gains of the repository's benchmark (10 kHz).
const GAINS_2: [f32; 2] = [0.060_898_63, 0.000_956_514_8];
const SAMPLE_PERIOD_S: f32 = 1e-4;
/// A calibration to write into: all zero.
const ZEROED: at_sensor_calibration_f32 = at_sensor_calibration_f32 {
    offset_c: 0.0,
    offset_s: 0.0,
    amplitude_c: 0.0,
    amplitude_s: 0.0,
    quadrature_rad: 0.0,
};

fn gains_of(l: &[f32]) -> at_gains_f32 {
    let mut gains = at_gains_f32::ZEROED;
    // SAFETY: valid pointers to live values.
    let status = unsafe { at_gains_f32_new(l.as_ptr(), l.len(), SAMPLE_PERIOD_S, &mut gains) };
    assert_eq!(status, AT_OK);
    gains
}

/// The chain of the gains `l` and the ADC `adc` (NULL when `None`), no other stage.
fn chain_of(l: &[f32], adc: Option<&at_adc_f32>) -> at_chain_f32 {
    let gains = gains_of(l);
    let mut chain = at_chain_f32::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    let status = unsafe { at_chain_f32_new(&gains, adc, None, None, None, None, &mut chain) };
    assert_eq!(status, AT_OK);
    chain
}

/// A chain to write into.
fn chain_out() -> at_chain_f32 {
    at_chain_f32::ZEROED
}

/// Tracks `speed` (rad/s) for 0.5 s from a zeroed state; returns the last estimate and the
/// true angle then, with `sample` making the call from the true angle.
fn track(speed: f32, mut sample: impl FnMut(f32) -> at_estimate_f32) -> (at_estimate_f32, f32) {
    let mut last = at_estimate_f32::default();
    let mut theta = 0.0_f32;
    for k in 0..5000 {
        theta = (0.3 + speed * k as f32 * SAMPLE_PERIOD_S) % TAU;
        last = sample(theta);
    }
    (last, theta)
}

fn angle_error(estimate: &at_estimate_f32, theta: f32) -> f32 {
    let e = (estimate.angle - theta) % TAU;
    (e + 3.0 * PI) % TAU - PI
}

#[test]
fn both_orders_track_a_constant_speed() {
    for l in [&GAINS_2[..], &GAINS_3[..]] {
        let chain = chain_of(l, None);
        let mut state = at_chain_state_f32::FRESH;
        let (e, theta) = track(300.0, |theta| unsafe {
            at_chain_f32_update(&chain, &mut state, theta.cos(), theta.sin())
        });
        let order = l.len();
        assert!(angle_error(&e, theta).abs() < 1e-3, "order {order}: {e:?}");
        assert!((e.speed - 300.0).abs() < 0.5, "order {order}: {e:?}");
        assert_eq!(e.faults, 0);
        // 0.3 + 300 x 0.4999 = 150.27 rad: 24 whole turns, the angle in [-pi, pi).
        assert_eq!(e.turns, 24);
    }
}

#[test]
fn a_state_follows_the_order_of_its_chain() {
    let (two, three) = (chain_of(&GAINS_2, None), chain_of(&GAINS_3, None));
    let mut state = at_chain_state_f32::FRESH;
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!((gains_of(&GAINS_2).order, gains_of(&GAINS_3).order), (2, 3));
        at_chain_f32_update(&three, &mut state, 1.0, 0.0);
        let e = at_chain_f32_update(&two, &mut state, 0.0, 1.0);
        assert!((e.angle - PI / 2.0).abs() < 1e-6, "started afresh: {e:?}");
    }
}

#[test]
fn null_and_zeroed_arguments_are_refused() {
    let chain = chain_of(&GAINS_3, None);
    let zeroed = at_chain_f32::ZEROED;
    let mut state = at_chain_state_f32::FRESH;
    let mut out = at_gains_f32::ZEROED;
    // SAFETY: NULL is what is tested; the other pointers are valid.
    unsafe {
        assert_eq!(
            at_gains_f32_new(null(), 3, 1e-4, &mut out),
            AT_ERR_NULL_POINTER
        );
        let l3 = GAINS_3.as_ptr();
        assert_eq!(
            at_gains_f32_new(l3, 3, 1e-4, null_mut()),
            AT_ERR_NULL_POINTER
        );
        assert_eq!(at_gains_f32_new(l3, 4, 1e-4, &mut out), AT_ERR_ORDER);
        let invalid = at_estimate_f32::invalid();
        assert_eq!(at_chain_f32_update(null(), &mut state, 1.0, 0.0), invalid);
        assert_eq!(at_chain_f32_update(&chain, null_mut(), 1.0, 0.0), invalid);
        assert_eq!(at_chain_f32_update(&zeroed, &mut state, 1.0, 0.0), invalid);
        let new = at_chain_f32_new(&out, None, None, None, None, None, &mut chain_out());
        assert_eq!(new, AT_ERR_ORDER, "zeroed gains");
        assert_eq!(at_chain_state_f32_clear_faults(null_mut()), 0);
        at_chain_state_f32_reset(null_mut());
        let mut thresholds = gains_of(&GAINS_3);
        thresholds.thresholds = at_fault_thresholds_f32_for_amplitude(1800.0);
        thresholds.thresholds.filter_factor = 1.5;
        let new = at_chain_f32_new(&thresholds, None, None, None, None, None, &mut chain_out());
        assert_eq!(new, AT_ERR_FILTER_FACTOR);
        let adc = at_adc_f32::ZEROED;
        let gains = gains_of(&GAINS_3);
        let mut counts = at_chain_f32::ZEROED;
        let new = at_chain_f32_new(&gains, Some(&adc), None, None, None, None, &mut counts);
        assert_eq!(new, AT_ERR_NOT_INITIALISED);
        let load = at_chain_state_f32_load_calibration(null_mut(), null());
        assert_eq!(load, AT_ERR_NULL_POINTER);
        assert_eq!(
            at_chain_state_f32_calibration_mode(null()),
            AT_CALIBRATION_OFF
        );
    }
    assert_eq!(state.clone_tag(), 0, "no refused call touched the state");
}

#[test]
fn faults_latch_and_clear() {
    let chain = chain_of(&GAINS_3, None);
    let mut state = at_chain_state_f32::FRESH;
    // SAFETY: valid pointers to live values.
    unsafe {
        at_chain_f32_update(&chain, &mut state, 1.0, 0.0);
        let e = at_chain_f32_update(&chain, &mut state, f32::NAN, 0.0);
        assert_eq!(e.faults, AT_FAULT_BAD_SAMPLE);
        at_chain_f32_update(&chain, &mut state, 1.0, 0.0);
        assert_eq!(
            at_chain_state_f32_clear_faults(&mut state),
            AT_FAULT_BAD_SAMPLE
        );
        assert_eq!(at_chain_state_f32_clear_faults(&mut state), 0);
    }
}

#[test]
fn adc_counts_track_as_floats_do() {
    let mut adc = at_adc_f32::ZEROED;
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!(at_adc_f32_offset_binary(40, &mut adc), AT_ERR_BITS);
        assert_eq!(at_adc_f32_offset_binary(12, &mut adc), AT_OK);
    }
    let chain = chain_of(&GAINS_3, Some(&adc));
    let mut state = at_chain_state_f32::FRESH;
    let counts = |x: f32| (2048.0 + 1800.0 * x).round() as u16;
    let (e, theta) = track(-200.0, |theta| unsafe {
        let (c, s) = (counts(theta.cos()), counts(theta.sin()));
        at_chain_f32_update_u16(&chain, &mut state, c, s)
    });
    assert!(angle_error(&e, theta).abs() < 2e-3, "{e:?}");
    assert!((e.speed + 200.0).abs() < 1.0, "{e:?}");
    assert_eq!(
        e.faults, 0,
        "1800 of 2048 counts is within the default thresholds"
    );
}

#[test]
fn calibration_learns_offsets_and_round_trips() {
    let gains = gains_of(&GAINS_3);
    let settings = at_calibration_settings_f32_default();
    let mut chain = at_chain_f32::ZEROED;
    let mut state = at_chain_state_f32::FRESH;
    let mut learned = ZEROED;
    // SAFETY: valid pointers to live values.
    unsafe {
        let new = at_chain_f32_new(&gains, None, None, Some(&settings), None, None, &mut chain);
        assert_eq!(new, AT_OK);
        let learning = at_chain_state_f32_set_calibration_mode(&mut state, AT_CALIBRATION_LEARNING);
        assert_eq!(learning, AT_OK);
        track(2.0 * PI * 50.0, |theta| {
            let (y_c, y_s) = (0.05 + theta.cos(), -0.05 + 1.1 * (theta + 0.05).sin());
            at_chain_f32_update(&chain, &mut state, y_c, y_s)
        });
        assert!(at_chain_state_f32_turns_learned(&state) > 5);
        let centred = at_chain_state_f32_calibration_status(&state);
        assert_eq!(centred, AT_CALIBRATION_CENTRED);
        let fresh = at_chain_state_f32_calibration_status(&at_chain_state_f32::FRESH);
        assert_eq!(fresh, AT_CALIBRATION_FINDING_CENTRE);
        assert_eq!(at_chain_state_f32_calibration(&state, &mut learned), AT_OK);
        assert!((learned.offset_c - 0.05).abs() < 5e-3 && (learned.offset_s + 0.05).abs() < 5e-3);
        let ratio = learned.amplitude_s / learned.amplitude_c;
        assert!((ratio - 1.1).abs() < 5e-3, "{learned:?}");
        assert_calibration_round_trips(&learned);
    }
}

/// A calibration stored in flash and loaded at the next start-up is the one stored, frozen.
/// Its own test too: Miri skips the learning tests (half a second of signal each takes it
/// minutes to interpret), not these calls.
fn assert_calibration_round_trips(stored: &at_sensor_calibration_f32) {
    let mut loaded = at_chain_state_f32::FRESH;
    let mut again = ZEROED;
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!(
            at_chain_state_f32_load_calibration(&mut loaded, stored),
            AT_OK
        );
        assert_eq!(
            at_chain_state_f32_calibration_mode(&loaded),
            AT_CALIBRATION_FROZEN
        );
        assert_eq!(at_chain_state_f32_calibration(&loaded, &mut again), AT_OK);
    }
    assert_eq!(&again, stored);
}

#[test]
fn a_stored_calibration_loads_frozen_and_reads_back() {
    assert_calibration_round_trips(&at_sensor_calibration_f32 {
        offset_c: 0.05,
        offset_s: -0.05,
        amplitude_c: 1.0,
        amplitude_s: 1.1,
        quadrature_rad: 0.05,
    });
}

#[test]
fn status_and_fault_texts_are_c_strings() {
    let text = |p: *const core::ffi::c_char| {
        // SAFETY: the API returns static NUL-terminated strings.
        unsafe { core::ffi::CStr::from_ptr(p) }.to_str().unwrap()
    };
    assert_eq!(text(at_status_message(AT_ERR_GAINS_2)), "gains[2] (l3)");
    assert_eq!(
        text(at_status_message(AT_ERR_STAGES)).split(' ').next(),
        Some("a")
    );
    assert_eq!(text(at_fault_name(AT_FAULT_FALSE_LOCK)), "false lock");
}

/// The benchmark's 3rd-order gains as fixed-point constants (tests/c/fixed_ato3.h).
const FIXED_3: [i32; 3] = [128_956_186, 768_430, 271_817_595];

#[test]
fn fixed_point_tracks_samples_and_reads_the_estimate_on_demand() {
    let mut gains = at_fixed_gains::ZEROED;
    let mut chain = at_chain_fixed::ZEROED;
    let mut state = at_chain_state_fixed::FRESH;
    // SAFETY: valid pointers to live values.
    unsafe {
        let m = FIXED_3.as_ptr();
        assert_eq!(
            at_fixed_gains_from_constants(m, 3, 1, 1e-4, &mut gains),
            AT_OK
        );
        assert_eq!(gains.order, 3);
        let new = at_chain_fixed_new(&gains, None, None, None, 28_800.0, &mut chain);
        assert_eq!(new, AT_OK);
        let speed = 2.0 * core::f64::consts::PI * 50.0;
        // Fewer samples under Miri, whose interpreter is slow: the loop settles in 0.3 s.
        let samples = if cfg!(miri) { 400 } else { 5000 };
        for k in 0..samples {
            let theta = 0.3 + speed * f64::from(k) * 1e-4;
            let count = |x: f64| ((1800.0 * x).round() * 16.0) as i16;
            let (c, s) = (count(theta.cos()), count(theta.sin()));
            assert_eq!(at_chain_fixed_track_i16(&chain, &mut state, c, s), 0);
        }
        let e = at_chain_fixed_estimate(&chain, &state);
        if !cfg!(miri) {
            assert!(
                (at_chain_fixed_speed_rad_s(&chain, &e) - speed).abs() < 0.1,
                "{e:?}"
            );
            let position = 0.3 + speed * 4999e-4;
            assert!(
                (at_chain_fixed_position_rad(&chain, &e) - position).abs() < 1e-3,
                "{e:?}"
            );
            assert_eq!(e.faults, 0);
        }
        assert_eq!(at_chain_fixed_speed_rad_s(null(), &e), 0.0);
        let copy = state;
        let angle = at_chain_fixed_update_i16(&chain, &mut state, 16384, 0).angle;
        assert_eq!(angle, at_chain_fixed_estimate(&chain, &state).angle);
        assert_ne!(
            at_chain_fixed_estimate(&chain, &copy),
            at_chain_fixed_estimate(&chain, &state)
        );
    }
}

#[test]
fn structs_of_another_build_are_refused_and_left_as_they_are() {
    let mut chain = chain_of(&GAINS_3, None);
    let mut other = chain;
    other.set_layout_for_test(1);
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!(at_layout_version(), AT_LAYOUT_VERSION);
        let new = at_chain_f32_with_winding_check(&other, 1.0, &mut chain);
        assert_eq!(new, AT_ERR_OTHER_BUILD);
        let mut state = at_chain_state_f32::FRESH;
        let learning = at_chain_state_f32_set_calibration_mode(&mut state, AT_CALIBRATION_LEARNING);
        assert_eq!(learning, AT_OK);
        state.set_layout_for_test(1);
        let before = state.clone_tag();
        let frozen = at_chain_state_f32_set_calibration_mode(&mut state, AT_CALIBRATION_FROZEN);
        assert_eq!(frozen, AT_ERR_OTHER_BUILD);
        assert_eq!(state.clone_tag(), before);
        assert_eq!(
            at_chain_state_f32_calibration_mode(&state),
            AT_CALIBRATION_OFF
        );
    }
    assert_ne!(
        at_chain_f32::LAYOUT,
        at_chain_fixed::LAYOUT,
        "the size is in the layout"
    );
}
