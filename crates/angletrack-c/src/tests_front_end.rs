//! Tests of the float chain's front-end checks through the `extern "C"` functions: clipping
//! against the ADC's stated range, a demodulator's faults and a winding open or shorted,
//! each flagged `AT_FAULT_FRONT_END` and coasted through where it invalidates the sample;
//! and structs of the previous layout or holding another type, refused.
#![allow(unsafe_code)]

use core::ptr::null;

use crate::tests::tests_support::Words;
use crate::tests::tests_support::layout_of_version;
use crate::*;

const GAINS_3: [f32; 3] = [0.094_326_17, 0.000_562_075, 1.213_522e-5];

/// The chain of the benchmark's gains (10 kHz) after `adc` (NULL for `None`).
fn chain_after(adc: Option<&at_adc_f32>) -> at_chain_f32 {
    let mut gains = at_gains_f32::ZEROED;
    let mut chain = at_chain_f32::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        assert_eq!(
            at_gains_f32_new(GAINS_3.as_ptr(), 3, 1e-4, &mut gains),
            AT_OK
        );
        assert_eq!(
            at_chain_f32_new(&gains, adc, None, None, None, None, &mut chain),
            AT_OK
        );
    }
    chain
}

/// The counts of amplitude `amplitude` at `angle` less mid-scale, rounded.
fn counts_at(angle: f32, amplitude: f32) -> (i32, i32) {
    (
        (amplitude * angle.cos()).round() as i32,
        (amplitude * angle.sin()).round() as i32,
    )
}

/// 40 samples of a still shaft at 1 rad (1500 counts from `mid`: past the tracking check's
/// start-up of two monitor windows), then `clipped`: its estimate and the estimate before
/// it. `update` takes counts from mid-scale.
fn after_a_still_shaft(
    mut update: impl FnMut(i32, i32) -> at_estimate_f32,
    clipped: (i32, i32),
) -> (at_estimate_f32, at_estimate_f32) {
    let (c, s) = counts_at(1.0, 1500.0);
    let mut before = at_estimate_f32::default();
    for _ in 0..40 {
        before = update(c, s);
        assert_eq!(before.faults, 0, "{before:?}");
    }
    (update(clipped.0, clipped.1), before)
}

#[test]
fn signed_12_bit_counts_clipped_at_2047_are_flagged_against_the_stated_range() {
    let mut adc = at_adc_f32::ZEROED;
    let mut unstated = at_adc_f32::ZEROED;
    // SAFETY: valid pointers to live values.
    unsafe {
        // Its bits and signedness state the range: -2048 to 2047.
        assert_eq!(at_adc_f32_twos_complement(12, &mut adc), AT_OK);
        assert_eq!(at_adc_f32_new(0, 2048.0, &mut unstated), AT_OK);
    }
    let chain = chain_after(Some(&adc));
    let plain = chain_after(Some(&unstated));
    let mut state = at_chain_state_f32::FRESH;
    let mut plain_state = at_chain_state_f32::FRESH;
    // SAFETY: valid pointers to live values.
    let update = |state: &mut at_chain_state_f32, chain: &at_chain_f32, c: i32, s: i32| unsafe {
        at_chain_f32_update_i16(chain, state, c as i16, s as i16)
    };
    // Both channels at a rail (-45 degrees, far from the shaft's 1 rad): not a
    // measurement, the observer coasts; without the range it is used.
    let (e, before) = after_a_still_shaft(|c, s| update(&mut state, &chain, c, s), (2047, -2048));
    assert_eq!(e.faults, AT_FAULT_FRONT_END);
    assert!((e.angle - before.angle).abs() < 1e-4, "{e:?} {before:?}");
    let (used, before) =
        after_a_still_shaft(|c, s| update(&mut plain_state, &plain, c, s), (2047, -2048));
    // Used: the per-sample tracking check flags the jump it makes (no front-end fault).
    assert_eq!(used.faults, AT_FAULT_LOSS_OF_TRACKING);
    assert!((used.angle - before.angle).abs() > 0.05, "{used:?}");
    // One channel at a rail: flagged, and used (the angle leaves the coasted 1 rad for the
    // sample's 0.15 rad).
    let e = update(&mut state, &chain, 2047, 300);
    assert_eq!(e.faults, AT_FAULT_FRONT_END);
    assert!((e.angle - 1.0).abs() > 0.05, "{e:?}");
    // Inside the rails: no front-end fault (the loop's jump to it is its tracking check's).
    let e = update(&mut state, &chain, 2046, -2047);
    assert_eq!(e.faults & AT_FAULT_FRONT_END, 0);
    // SAFETY: a valid pointer to a live value.
    unsafe {
        assert_eq!(
            at_chain_state_f32_clear_front_end_faults(&mut state),
            AT_FRONT_END_FAULT_CLIPPING
        );
        assert_eq!(at_chain_state_f32_clear_front_end_faults(&mut state), 0);
        assert_eq!(
            at_chain_state_f32_clear_faults(&mut state) & AT_FAULT_FRONT_END,
            AT_FAULT_FRONT_END
        );
        assert_eq!(
            at_chain_state_f32_clear_front_end_faults(&mut plain_state),
            0
        );
    }
}

#[test]
fn offset_binary_counts_are_flagged_at_0_and_4095() {
    let mut by_bits = at_adc_f32::ZEROED;
    let mut stated = at_adc_f32::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        assert_eq!(at_adc_f32_offset_binary(12, &mut by_bits), AT_OK);
        assert_eq!(at_adc_f32_new(2048, 2048.0, &mut stated), AT_OK);
        assert_eq!(at_adc_f32_set_range(&mut stated, 4095, 0), AT_ERR_ADC_RANGE);
        assert_eq!(
            at_adc_f32_set_range(core::ptr::null_mut(), 0, 4095),
            AT_ERR_NULL_POINTER
        );
        let mut zeroed = at_adc_f32::ZEROED;
        assert_eq!(
            at_adc_f32_set_range(&mut zeroed, 0, 4095),
            AT_ERR_NOT_INITIALISED
        );
        assert_eq!(at_adc_f32_set_range(&mut stated, 0, 4095), AT_OK);
    }
    for adc in [by_bits, stated] {
        let chain = chain_after(Some(&adc));
        let mut state = at_chain_state_f32::FRESH;
        // SAFETY: valid pointers to live values.
        let mut update = |c: i32, s: i32| unsafe {
            at_chain_f32_update_u16(&chain, &mut state, (2048 + c) as u16, (2048 + s) as u16)
        };
        let (e, before) = after_a_still_shaft(&mut update, (-2048, 2047));
        assert_eq!(e.faults, AT_FAULT_FRONT_END);
        assert!((e.angle - before.angle).abs() < 1e-4, "{e:?}");
        assert_eq!(update(2047, 0).faults, AT_FAULT_FRONT_END);
        assert_eq!(update(2046, -2047).faults & AT_FAULT_FRONT_END, 0);
        // The same counts as i32: the same rails.
        // SAFETY: valid pointers to live values.
        let e = unsafe { at_chain_f32_update_i32(&chain, &mut state, 4095, 2048) };
        assert_eq!(e.faults & AT_FAULT_FRONT_END, AT_FAULT_FRONT_END);
    }
}

/// Counts of a resolver at 50 rev/s (10 kHz) and amplitude `amplitude`, rounded and
/// clipped to a signed 12-bit ADC's codes, through a chain after an ADC of no stated range:
/// the samples of the second turn flagged `AT_FAULT_FRONT_END`, and the front-end faults
/// latched.
fn flagged_without_a_range(amplitude: f32) -> (u32, u32) {
    let mut adc = at_adc_f32::ZEROED;
    // SAFETY: valid pointers to live values.
    assert_eq!(unsafe { at_adc_f32_new(0, 2048.0, &mut adc) }, AT_OK);
    let chain = chain_after(Some(&adc));
    let mut state = at_chain_state_f32::FRESH;
    let mut flagged = 0;
    let count = |x: f32| (amplitude * x).round().clamp(-2048.0, 2047.0) as i16;
    for k in 0..400 {
        let theta = 0.3 + 0.0314 * k as f32;
        // SAFETY: valid pointers to live values.
        let e = unsafe {
            at_chain_f32_update_i16(&chain, &mut state, count(theta.cos()), count(theta.sin()))
        };
        if k >= 200 {
            flagged += u32::from(e.faults & AT_FAULT_FRONT_END != 0);
        }
    }
    // SAFETY: a valid pointer to a live value.
    (flagged, unsafe {
        at_chain_state_f32_clear_front_end_faults(&mut state)
    })
}

#[test]
fn without_a_stated_range_the_rails_held_flat_are_found() {
    // Amplitude 1.4 where the rails are at 0.9: one channel at least at a rail at every
    // angle, found in the first turn.
    let (flagged, faults) = flagged_without_a_range(3184.0);
    assert!(flagged >= 195, "{flagged} of 200");
    assert_eq!(faults, AT_FRONT_END_FAULT_CLIPPING);
    // A clean signal: its extremes are no rails.
    assert_eq!(flagged_without_a_range(1800.0), (0, 0));
}

/// A demodulator's pair at `angle` (nominal amplitude 1) with the front-end `faults`.
fn pair_at(angle: f32, faults: u32) -> at_demodulated_pair_f32 {
    at_demodulated_pair_f32 {
        y_c: angle.cos(),
        y_s: angle.sin(),
        faults,
        ..Default::default()
    }
}

#[test]
fn a_demodulator_s_loss_of_excitation_is_flagged_and_coasted_through() {
    let chain = chain_after(None);
    let mut state = at_chain_state_f32::FRESH;
    let mut plain = at_chain_state_f32::FRESH;
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        for _ in 0..20 {
            let e = at_chain_f32_update_demodulated(&chain, &mut state, &pair_at(0.6, 0));
            assert_eq!(e.faults, 0);
            at_chain_f32_track(&chain, &mut plain, 0.6_f32.cos(), 0.6_f32.sin());
        }
        // The excitation lost: the windings read noise (here 2 % at 2.5 rad).
        let lost = at_demodulated_pair_f32 {
            y_c: 0.02 * 2.5_f32.cos(),
            y_s: 0.02 * 2.5_f32.sin(),
            faults: AT_FRONT_END_FAULT_LOSS_OF_EXCITATION,
            ..Default::default()
        };
        // 12 pairs: a short coast (a long one is followed by the core's fit, flagged).
        for _ in 0..12 {
            let e = at_chain_f32_update_demodulated(&chain, &mut state, &lost);
            assert_eq!(e.faults & AT_FAULT_FRONT_END, AT_FAULT_FRONT_END);
            assert!((e.angle - 0.6).abs() < 1e-3, "{e:?}");
            // The same pairs, their faults dropped: the observer follows the noise.
            at_chain_f32_track(&chain, &mut plain, lost.y_c, lost.y_s);
        }
        let drifted = at_chain_f32_estimate(&chain, &plain);
        assert!((drifted.angle - 0.6).abs() > 0.3, "{drifted:?}");
        // Weak excitation is flagged, and the pair used.
        let weak = pair_at(0.6, AT_FRONT_END_FAULT_WEAK_EXCITATION);
        let e = at_chain_f32_update_demodulated(&chain, &mut state, &weak);
        assert_eq!(e.faults & AT_FAULT_FRONT_END, AT_FAULT_FRONT_END);
        assert_eq!(
            at_chain_state_f32_clear_front_end_faults(&mut state),
            AT_FRONT_END_FAULT_LOSS_OF_EXCITATION | AT_FRONT_END_FAULT_WEAK_EXCITATION
        );
        assert_eq!(
            at_chain_f32_track_demodulated(&chain, &mut state, &pair_at(0.6, 0)),
            0
        );
        assert_eq!(at_chain_f32_estimate(&chain, &state).faults, 0);
        assert_eq!(
            at_chain_f32_track_demodulated(&chain, &mut state, null()),
            AT_FAULT_INVALID_ARGUMENT
        );
        let mut adc = at_adc_f32::ZEROED;
        assert_eq!(at_adc_f32_offset_binary(12, &mut adc), AT_OK);
        assert_eq!(
            at_chain_f32_track_demodulated(&chain_after(Some(&adc)), &mut state, &lost),
            AT_FAULT_INVALID_ARGUMENT,
            "a chain with an ADC stage refuses pairs"
        );
        assert_eq!(
            at_chain_f32_update_demodulated(&chain, &mut state, null()).faults,
            AT_FAULT_INVALID_ARGUMENT
        );
    }
}

#[test]
fn a_winding_open_at_50_degrees_is_flagged_on_its_first_pair() {
    // 50 degrees: the prediction puts 0.64 of the amplitude on the cosine winding, clear of
    // the check's half (at 60 degrees, exactly half, the flag would hang on the last bit of
    // the prediction's cosine, which Miri's imprecise `cos` moves).
    const ANGLE: f32 = 50.0 * core::f32::consts::PI / 180.0;
    let chain = chain_after(None);
    let mut checked = at_chain_f32::ZEROED;
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!(
            at_chain_f32_with_winding_check(&chain, 0.0, &mut checked),
            AT_ERR_NOMINAL_AMPLITUDE
        );
        assert_eq!(checked.clone_tag(), 0, "unchanged on error");
        assert_eq!(
            at_chain_f32_with_winding_check(&chain, 1.0, &mut checked),
            AT_OK
        );
        let mut state = at_chain_state_f32::FRESH;
        for _ in 0..20 {
            at_chain_f32_update_demodulated(&checked, &mut state, &pair_at(ANGLE, 0));
        }
        // The cosine winding opens: it reads 0 where the prediction puts half the amplitude.
        let mut open = pair_at(ANGLE, 0);
        open.y_c = 0.0;
        let e = at_chain_f32_update_demodulated(&checked, &mut state, &open);
        assert_eq!(e.faults & AT_FAULT_FRONT_END, AT_FAULT_FRONT_END);
        assert!((e.angle - ANGLE).abs() < 1e-3, "{e:?}");
        assert_eq!(
            at_chain_state_f32_clear_front_end_faults(&mut state),
            AT_FRONT_END_FAULT_WINDING
        );
        // Without the check: no flag, and the open winding pulls the angle.
        let mut plain = at_chain_state_f32::FRESH;
        for _ in 0..20 {
            at_chain_f32_update_demodulated(&chain, &mut plain, &pair_at(ANGLE, 0));
        }
        let e = at_chain_f32_update_demodulated(&chain, &mut plain, &open);
        assert_eq!(e.faults & AT_FAULT_FRONT_END, 0);
        assert!((e.angle - ANGLE).abs() > 0.02, "{e:?}");
    }
}

#[test]
fn structs_of_the_previous_layout_or_holding_another_type_are_refused() {
    let mut adc = at_adc_f32::ZEROED;
    let mut gains = at_gains_f32::ZEROED;
    let mut chain = at_chain_f32::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        assert_eq!(at_adc_f32_offset_binary(12, &mut adc), AT_OK);
        assert_eq!(
            at_gains_f32_new(GAINS_3.as_ptr(), 3, 1e-4, &mut gains),
            AT_OK
        );
        let new = |adc: &at_adc_f32, chain: &mut at_chain_f32| {
            at_chain_f32_new(&gains, Some(adc), None, None, None, None, chain)
        };
        // The ADC as the previous layout (version 3, without its range) wrote it: its tag
        // and layout word.
        let mut previous = adc;
        previous.set_tag_for_test(0x4154_4101);
        previous.set_layout_for_test(layout_of_version(
            AT_LAYOUT_VERSION - 1,
            size_of::<at_adc_f32>(),
        ));
        assert_eq!(new(&previous, &mut chain), AT_ERR_OTHER_BUILD);
        // Its previous tag in this build's layout: it holds no ADC of this layout.
        let mut retagged = adc;
        retagged.set_tag_for_test(0x4154_4101);
        assert_eq!(new(&retagged, &mut chain), AT_ERR_NOT_INITIALISED);
        assert_eq!(chain.clone_tag(), 0, "unchanged when refused");
        assert_eq!(new(&adc, &mut chain), AT_OK);
        // A chain and its state of the previous layout version.
        let mut state = at_chain_state_f32::FRESH;
        at_chain_f32_track_u16(&chain, &mut state, 3000, 2048);
        let mut old_state = state;
        old_state.set_layout_for_test(layout_of_version(
            AT_LAYOUT_VERSION - 1,
            size_of::<at_chain_state_f32>(),
        ));
        assert_eq!(
            at_chain_f32_update_u16(&chain, &mut old_state, 3000, 2048).faults,
            AT_FAULT_INVALID_ARGUMENT
        );
        assert_eq!(at_chain_state_f32_clear_front_end_faults(&mut old_state), 0);
        let mut old_chain = chain;
        old_chain.set_layout_for_test(layout_of_version(
            AT_LAYOUT_VERSION - 1,
            size_of::<at_chain_f32>(),
        ));
        let mut out = at_chain_f32::ZEROED;
        assert_eq!(
            at_chain_f32_with_winding_check(&old_chain, 1.0, &mut out),
            AT_ERR_OTHER_BUILD
        );
        assert_eq!(
            at_chain_f32_track_u16(&old_chain, &mut state, 3000, 2048),
            AT_FAULT_INVALID_ARGUMENT
        );
    }
}

#[test]
fn the_fixed_point_chain_flags_signed_12_bit_counts_at_its_stated_rails() {
    let mut gains = at_fixed_gains::ZEROED;
    let mut adc = at_adc_counts::default();
    let mut plain = at_chain_fixed::ZEROED;
    let mut chain = at_chain_fixed::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        assert_eq!(
            at_fixed_gains_new(GAINS_3.as_ptr(), 3, 1e-4, &mut gains),
            AT_OK
        );
        assert_eq!(at_adc_counts_twos_complement(12, &mut adc), AT_OK);
        assert_eq!(
            at_chain_fixed_new(&gains, Some(&adc), None, None, 0.0, &mut plain),
            AT_OK
        );
        assert_eq!(
            at_chain_fixed_with_adc_range(&plain, 2047, -2048, &mut chain),
            AT_ERR_ADC_RANGE
        );
        assert_eq!(chain.clone_tag(), 0, "unchanged on error");
        assert_eq!(
            at_chain_fixed_with_adc_range(&plain, -2048, 2047, &mut chain),
            AT_OK
        );
        let (c, s) = counts_at(1.0, 1500.0);
        let run = |chain: &at_chain_fixed, state: &mut at_chain_state_fixed| {
            for _ in 0..20 {
                let e = at_chain_fixed_update_i16(chain, state, c as i16, s as i16);
                assert_eq!(e.faults, 0);
            }
            let before = at_chain_fixed_estimate(chain, state);
            (before, at_chain_fixed_update_i16(chain, state, 2047, -2048))
        };
        // Both channels at a rail: flagged, the angle held; without the range, used.
        let mut state = at_chain_state_fixed::FRESH;
        let (before, e) = run(&chain, &mut state);
        assert_eq!(e.faults, AT_FAULT_FRONT_END);
        assert_eq!(e.angle, before.angle.wrapping_add(before.speed));
        let mut plain_state = at_chain_state_fixed::FRESH;
        let (before, used) = run(&plain, &mut plain_state);
        assert_eq!(used.faults, 0);
        // More than 0.05 rad (2^32 per turn).
        assert!(used.angle.wrapping_sub(before.angle).unsigned_abs() > 34_000_000);
        // One channel at a rail: flagged; inside: not.
        assert_eq!(
            at_chain_fixed_update_i16(&chain, &mut state, 300, 2047).faults,
            AT_FAULT_FRONT_END
        );
        assert_eq!(
            at_chain_fixed_update_i16(&chain, &mut state, 300, 2046).faults,
            0
        );
        assert_eq!(
            at_chain_state_fixed_clear_front_end_faults(&mut state),
            AT_FRONT_END_FAULT_CLIPPING
        );
        assert_eq!(at_chain_state_fixed_clear_front_end_faults(&mut state), 0);
        assert_eq!(
            at_chain_state_fixed_clear_front_end_faults(&mut plain_state),
            0
        );
        // A chain of the previous layout version: refused.
        let mut old = plain;
        old.set_layout_for_test(layout_of_version(
            AT_LAYOUT_VERSION - 1,
            size_of::<at_chain_fixed>(),
        ));
        assert_eq!(
            at_chain_fixed_with_adc_range(&old, -2048, 2047, &mut chain),
            AT_ERR_OTHER_BUILD
        );
    }
}

#[test]
fn the_fixed_point_chain_without_a_range_flags_counts_held_at_their_rails() {
    let mut gains = at_fixed_gains::ZEROED;
    let mut adc = at_adc_counts::default();
    let mut chain = at_chain_fixed::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        assert_eq!(
            at_fixed_gains_new(GAINS_3.as_ptr(), 3, 1e-4, &mut gains),
            AT_OK
        );
        assert_eq!(at_adc_counts_offset_binary(12, &mut adc), AT_OK);
        assert_eq!(
            at_chain_fixed_new(&gains, Some(&adc), None, None, 0.0, &mut chain),
            AT_OK
        );
        // 50 rev/s at 10 kHz (200 samples a turn), amplitude 3184 counts on a 12-bit ADC
        // (codes 0 to 4095): one channel at least at a rail at every angle, flagged from the
        // first turn on. Fewer samples under Miri, whose interpreter is slow.
        let samples: u32 = if cfg!(miri) { 300 } else { 2000 };
        let run = |amplitude: f64| {
            let mut state = at_chain_state_fixed::FRESH;
            let mut flagged = 0;
            for k in 0..samples {
                let theta = 0.3 + 0.0314 * f64::from(k);
                let code = |x: f64| (2048.0 + amplitude * x).round().clamp(0.0, 4095.0) as u16;
                let e = at_chain_fixed_update_u16(
                    &chain,
                    &mut state,
                    code(theta.cos()),
                    code(theta.sin()),
                );
                flagged += usize::from(e.faults & AT_FAULT_FRONT_END != 0);
            }
            (
                flagged,
                at_chain_state_fixed_clear_front_end_faults(&mut state),
            )
        };
        let (flagged, latched) = run(3184.0);
        assert!(flagged > samples as usize - 250, "{flagged} of {samples}");
        assert_eq!(latched, AT_FRONT_END_FAULT_CLIPPING);
        // A clean signal of 1800 counts: nothing.
        assert_eq!(run(1800.0), (0, 0));
    }
}
