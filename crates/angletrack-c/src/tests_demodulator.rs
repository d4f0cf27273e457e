//! Tests of the synchronous demodulator through its `extern "C"` functions: resolver
//! windings to pairs, which a chain tracks, and the refusals.
#![allow(unsafe_code)]

use core::f32::consts::TAU;
use core::ptr::null;

use crate::tests::tests_support::Words;
use crate::*;

const GAINS_3: [f32; 3] = [0.094_326_17, 0.000_562_075, 1.213_522e-5];

/// A chain of the benchmark's gains at `sample_period_s`, no stage.
fn chain_at(sample_period_s: f32) -> at_chain_f32 {
    let mut gains = at_gains_f32::ZEROED;
    let mut chain = at_chain_f32::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        assert_eq!(
            at_gains_f32_new(GAINS_3.as_ptr(), 3, sample_period_s, &mut gains),
            AT_OK
        );
        assert_eq!(
            at_chain_f32_new(&gains, None, None, None, None, None, &mut chain),
            AT_OK
        );
    }
    chain
}

#[test]
fn windings_to_pairs_to_the_angle() {
    // A 10 kHz carrier sampled 16 times per period by a 12-bit ADC, amplitude 1800 counts.
    let settings = at_demodulator_settings_f32_new(10e3, 160e3, 1800.0, 0.0, 4095.0);
    let mut demodulator = at_demodulator_f32::ZEROED;
    let mut state = at_demodulator_state_f32::FRESH;
    let chain = chain_at(1e-4);
    let mut chain_state = at_chain_state_f32::FRESH;
    let mut pair = at_demodulated_pair_f32::default();
    let theta = 0.6_f32;
    let periods = if cfg!(miri) { 40 } else { 400 };
    let mut pairs = 0;
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!(at_demodulator_f32_new(&settings, &mut demodulator), AT_OK);
        assert_eq!(at_demodulator_f32_check_chain(&demodulator, &chain), AT_OK);
        assert!(at_demodulator_state_f32_carrier_delay_rad(&mut state).is_nan());
        for k in 0..16 * periods {
            let carrier = 1800.0 * (TAU * (k % 16) as f32 / 16.0).sin();
            let (raw_c, raw_s) = (
                2048.0 + theta.cos() * carrier,
                2048.0 + theta.sin() * carrier,
            );
            if at_demodulator_f32_push(&demodulator, &mut state, raw_c, raw_s, &mut pair) == 1 {
                assert_eq!(
                    at_chain_f32_track(&chain, &mut chain_state, pair.y_c, pair.y_s),
                    0
                );
                pairs += 1;
            }
        }
        let e = at_chain_f32_estimate(&chain, &chain_state);
        assert!((e.angle - theta).abs() < 1e-3, "{e:?}");
        assert!(
            (pair.y_c - theta.cos()).abs() < 1e-3 && pair.faults == 0,
            "{pair:?}"
        );
        // One pair per period once the 24 start-up windows have acquired the carrier (a
        // window completes a quarter period after its period).
        assert_eq!(pairs, periods - 24);
        assert_eq!(at_demodulator_state_f32_clear_faults(&mut state), 0);
        let delay = at_demodulator_state_f32_carrier_delay_rad(&mut state);
        // Taken back to the first sample at the tracked frequency: within a few degrees.
        assert!(delay.abs() < 0.06, "delay {delay}");
    }
}

#[test]
fn refusals_name_the_setting() {
    let mut settings = at_demodulator_settings_f32_new(10e3, 30e3, 1800.0, 0.0, 4095.0);
    let mut demodulator = at_demodulator_f32::ZEROED;
    let mut state = at_demodulator_state_f32::FRESH;
    let mut pair = at_demodulated_pair_f32::default();
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        assert_eq!(
            at_demodulator_f32_new(&settings, &mut demodulator),
            AT_ERR_ADC_RATE_HZ
        );
        settings.adc_rate_hz = 150e3;
        assert_eq!(
            at_demodulator_f32_push(&demodulator, &mut state, 0.0, 0.0, &mut pair),
            AT_FAULT_INVALID_ARGUMENT,
            "a demodulator not made"
        );
        settings.weak_excitation = 0.1;
        assert_eq!(
            at_demodulator_f32_new(&settings, &mut demodulator),
            AT_ERR_WEAK_EXCITATION
        );
        settings.weak_excitation = 0.7;
        settings.adc_max_code = settings.adc_min_code;
        assert_eq!(
            at_demodulator_f32_new(&settings, &mut demodulator),
            AT_ERR_ADC_RANGE
        );
        let settings = at_demodulator_settings_f32_new(10e3, 150e3, 1800.0, 0.0, 4095.0);
        assert_eq!(at_demodulator_f32_new(&settings, &mut demodulator), AT_OK);
        assert_eq!(
            at_demodulator_f32_check_chain(&demodulator, &chain_at(2e-4)),
            AT_ERR_SAMPLE_PERIOD_S
        );
        assert_eq!(
            at_demodulator_f32_new(null(), &mut demodulator),
            AT_ERR_NULL_POINTER
        );
        demodulator.set_layout_for_test(1);
        assert_eq!(
            at_demodulator_f32_check_chain(&demodulator, &chain_at(1e-4)),
            AT_ERR_OTHER_BUILD
        );
    }
}

/// A small deterministic noise in [-1, 1) (what an unexcited winding reads).
fn noise(k: u64) -> f32 {
    let x = k
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    (x >> 40) as f32 / (1u64 << 23) as f32 - 1.0
}

/// The largest angle error (rad) and relative speed error, from the loss's start on, of a
/// 12-bit resolver at 50 electrical rev/s (10 kHz carrier, 160 kHz ADC, amplitude 1800
/// counts) whose excitation is lost for 10 ms after 0.2 s, through the demodulator and a
/// chain that takes each pair with `update`; and the lost pairs' count, those whose estimate
/// carries `AT_FAULT_FRONT_END`, and the pairs after the loss that carry it.
fn through_a_loss(
    chain: &at_chain_f32,
    mut update: impl FnMut(&at_demodulated_pair_f32) -> at_estimate_f32,
) -> (f32, f32, u32, u32, u32) {
    const ADC_HZ: f64 = 160e3;
    const SPEED: f64 = core::f64::consts::TAU * 50.0;
    let (loss_start, loss_end) = (0.2, 0.21);
    let settings = at_demodulator_settings_f32_new(10e3, ADC_HZ as f32, 1800.0, 0.0, 4095.0);
    let mut demodulator = at_demodulator_f32::ZEROED;
    let mut state = at_demodulator_state_f32::FRESH;
    let mut pair = at_demodulated_pair_f32::default();
    let (mut worst_angle, mut worst_speed) = (0.0_f32, 0.0_f32);
    let (mut lost, mut flagged, mut after) = (0, 0, 0);
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!(at_demodulator_f32_new(&settings, &mut demodulator), AT_OK);
        assert_eq!(at_demodulator_f32_check_chain(&demodulator, chain), AT_OK);
        for k in 0..(0.26 * ADC_HZ) as u64 {
            let t = k as f64 / ADC_HZ;
            let theta = SPEED * t;
            let excitation = if (loss_start..loss_end).contains(&t) {
                0.0
            } else {
                1800.0 * (core::f64::consts::TAU * 10e3 * t).sin()
            };
            let raw_c = 2048.0 + (theta.cos() * excitation) as f32 + 2.0 * noise(2 * k);
            let raw_s = 2048.0 + (theta.sin() * excitation) as f32 + 2.0 * noise(2 * k + 1);
            if at_demodulator_f32_push(&demodulator, &mut state, raw_c, raw_s, &mut pair) != 1 {
                continue;
            }
            let e = update(&pair);
            let centre_s = pair.centre_sample / ADC_HZ;
            if centre_s >= loss_start {
                let truth = (SPEED * centre_s) as f32;
                worst_angle = worst_angle.max(wrapped(e.angle - truth).abs());
                worst_speed = worst_speed.max((e.speed / SPEED as f32 - 1.0).abs());
            }
            if pair.faults & AT_FRONT_END_FAULT_LOSS_OF_EXCITATION != 0 {
                lost += 1;
                flagged += u32::from(e.faults & AT_FAULT_FRONT_END != 0);
            } else if centre_s > loss_end + 2e-3 {
                after += u32::from(e.faults & AT_FAULT_FRONT_END != 0);
            }
        }
    }
    (worst_angle, worst_speed, lost, flagged, after)
}

/// `x` wrapped to [-pi, pi).
fn wrapped(x: f32) -> f32 {
    (x + core::f32::consts::PI).rem_euclid(TAU) - core::f32::consts::PI
}

#[test]
fn a_10_ms_loss_of_excitation_through_the_demodulator_is_coasted_through() {
    // The gains of the core's coasting tests, at the carrier period.
    let mut gains = at_gains_f32::ZEROED;
    let mut chain = at_chain_f32::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        assert_eq!(
            at_gains_f32_new([0.3, 0.04, 0.002].as_ptr(), 3, 1e-4, &mut gains),
            AT_OK
        );
        assert_eq!(
            at_chain_f32_new(&gains, None, None, None, None, None, &mut chain),
            AT_OK
        );
    }
    let mut state = at_chain_state_f32::FRESH;
    // SAFETY: valid pointers to live values.
    let (angle, speed, lost, flagged, after) = through_a_loss(&chain, |pair| unsafe {
        at_chain_f32_update_demodulated(&chain, &mut state, pair)
    });
    assert!(angle < 0.02, "angle error {angle} rad");
    assert!(speed < 0.02, "speed error {speed}");
    // The 10 ms hold 100 carrier periods: the windows wholly in it, at least.
    assert!((98..=102).contains(&lost), "{lost} pairs lost");
    assert_eq!(flagged, lost);
    assert_eq!(after, 0);
    // The same pairs without their faults: the observer follows the noise.
    let mut state = at_chain_state_f32::FRESH;
    // SAFETY: valid pointers to live values.
    let (angle, _, _, flagged, _) = through_a_loss(&chain, |pair| unsafe {
        at_chain_f32_update(&chain, &mut state, pair.y_c, pair.y_s)
    });
    assert!(angle > 0.1, "angle error {angle} rad without the faults");
    assert_eq!(flagged, 0);
}
