//! Tests of the fixed-point chain and the tables through their `extern "C"` functions: the
//! chain without stages is the fixed-point observer bit for bit, its ADC is the C-side
//! conversion it replaces, the stored calibration and the table correct an imperfect
//! sensor, and every bad parameter is refused with its status.
#![allow(unsafe_code)]

use core::f64::consts::{PI, TAU};
use core::ptr::null;

use angletrack_core::{Chain, ChainState, FixedGains, FixedState};

use crate::chain_fixed::{ChainFixed, StateFixed};
use crate::tests::tests_chain::SAMPLES;
use crate::tests::tests_support::Words;
use crate::*;

const GAINS_3: [f32; 3] = [0.094_326_17, 0.000_562_075, 1.213_522e-5];

fn fixed_gains() -> at_fixed_gains {
    let mut gains = at_fixed_gains::ZEROED;
    // SAFETY: valid pointers to live values.
    assert_eq!(
        unsafe { at_fixed_gains_new(GAINS_3.as_ptr(), 3, 1e-4, &mut gains) },
        AT_OK
    );
    gains
}

/// The chain of the 3rd-order gains and the stages given (NULL when `None`).
fn chain_of(
    adc: Option<&at_adc_counts>,
    calibration: Option<&at_sensor_calibration_f32>,
    table: Option<&at_angle_table_fixed>,
    nominal: f64,
) -> Result<at_chain_fixed, at_status> {
    let gains = fixed_gains();
    let mut chain = at_chain_fixed::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    let status =
        unsafe { at_chain_fixed_new(&gains, adc, calibration, table, nominal, &mut chain) };
    if status == AT_OK {
        Ok(chain)
    } else {
        Err(status)
    }
}

fn adc_12() -> at_adc_counts {
    let mut adc = at_adc_counts::default();
    // SAFETY: a valid pointer.
    assert_eq!(unsafe { at_adc_counts_offset_binary(12, &mut adc) }, AT_OK);
    adc
}

/// The true angle of sample `k` (50 Hz electrical at 10 kHz from 0.3 rad).
fn theta(k: u32) -> f64 {
    0.3 + TAU * 50.0 * f64::from(k) * 1e-4
}

/// The binary angle's error against `truth` (rad), wrapped.
fn error_rad(angle: i32, truth: f64) -> f64 {
    let e = f64::from(angle) * TAU / 4_294_967_296.0 - truth;
    (e + 3.0 * PI).rem_euclid(TAU) - PI
}

/// The core's fixed-point observer of the 3rd-order gains, its monitor for `nominal` (a
/// chain with no front end).
fn core_observer(nominal: f64) -> (Chain<(), FixedGains<3>>, ChainState<(), FixedState<3>>) {
    let gains = GAINS_3.map(f64::from);
    let observer = FixedGains::<3>::new(gains, 1e-4).and_then(|g| g.with_monitor(Some(nominal)));
    (Chain::new((), observer.unwrap()), ChainState::new())
}

#[test]
fn without_stages_it_is_the_observer_bit_for_bit() {
    let chain = chain_of(None, None, None, 16384.0).unwrap();
    let (gains, mut plain) = core_observer(16384.0);
    let mut state = at_chain_state_fixed::FRESH;
    for k in 0..SAMPLES.min(1000) {
        let (y_c, y_s) = (
            (16000.0 * theta(k).cos()) as i16,
            (16000.0 * theta(k).sin()) as i16,
        );
        // SAFETY: valid pointers to live values.
        let (a, b) = unsafe {
            (
                at_chain_fixed_update_i16(&chain, &mut state, y_c, y_s),
                at_fixed_estimate::from(gains.update(&mut plain, (y_c, y_s))),
            )
        };
        assert_eq!(a, b, "{k}");
    }
    // SAFETY: as above.
    unsafe {
        let estimate = at_fixed_estimate::from(FixedGains::<3>::estimate(&plain.observer));
        assert_eq!(at_chain_fixed_estimate(&chain, &state), estimate);
        assert_eq!(
            at_chain_fixed_track_u16(&chain, &mut state, 0, 0),
            AT_FAULT_INVALID_ARGUMENT
        );
        assert_eq!(
            at_chain_fixed_track_i32(&chain, &mut state, 0, 0),
            AT_FAULT_INVALID_ARGUMENT
        );
        let second = at_fixed_estimate {
            speed: 1 << 22,
            ..estimate
        };
        let speed = at_chain_fixed_speed_rad_s(&chain, &second);
        assert!((speed - TAU / 1024.0 / 1e-4).abs() < 1e-9, "{speed}");
    }
}

#[test]
fn the_adc_is_the_conversion_it_replaces() {
    let chain = chain_of(Some(&adc_12()), None, None, 28_800.0).unwrap();
    let (gains, mut plain) = core_observer(28_800.0);
    let mut state = at_chain_state_fixed::FRESH;
    for k in 0..SAMPLES.min(1000) {
        let raw = |x: f64| (2048.0 + 1800.0 * x).round() as u16;
        let (c, s) = (raw(theta(k).cos()), raw(theta(k).sin()));
        let shifted = |r: u16| ((i32::from(r) - 2048) << 4) as i16;
        // SAFETY: valid pointers to live values.
        let (a, b, i) = unsafe {
            let mut again = state;
            let a = at_chain_fixed_update_u16(&chain, &mut state, c, s);
            let b = gains.update(&mut plain, (shifted(c), shifted(s))).into();
            at_chain_fixed_track_i32(&chain, &mut again, c.into(), s.into());
            (a, b, at_chain_fixed_estimate(&chain, &again))
        };
        assert_eq!(a, b, "{k}");
        assert_eq!(i, a, "{k}");
    }
}

/// The worst angle error over the last fifth of a synthetic 12-bit sensor (offsets,
/// imbalance, quadrature, a 3rd-harmonic angle error) through `chain`.
fn worst_error(chain: &at_chain_fixed) -> f64 {
    let mut state = at_chain_state_fixed::FRESH;
    let mut worst = 0.0f64;
    for k in 0..SAMPLES {
        let t = theta(k);
        let m = t + 0.004 * (3.0 * t).sin();
        let c = (2048.0 + 36.0 + 1800.0 * m.cos()).round() as u16;
        let s = (2048.0 - 27.0 + 1890.0 * (m + 0.03).sin()).round() as u16;
        // SAFETY: valid pointers to live values.
        assert_eq!(
            unsafe { at_chain_fixed_track_u16(chain, &mut state, c, s) },
            0
        );
        if k >= SAMPLES * 4 / 5 {
            // SAFETY: as above.
            let e = unsafe { at_chain_fixed_estimate(chain, &state) };
            worst = worst.max(error_rad(e.angle, t).abs());
        }
    }
    worst
}

#[test]
fn the_stored_calibration_and_the_table_correct_a_sensor() {
    let calibration = at_sensor_calibration_f32 {
        offset_c: 36.0 * 16.0,
        offset_s: -27.0 * 16.0,
        amplitude_c: 1800.0 * 16.0,
        amplitude_s: 1890.0 * 16.0,
        quadrature_rad: 0.03,
    };
    let mut harmonics = at_angle_correction_f32::default();
    harmonics.sin_coefficients[2] = 0.004;
    let mut table = at_angle_table_fixed {
        errors_q15: [0; AT_ANGLE_TABLE_LENGTH],
    };
    // SAFETY: valid pointers to live values.
    assert_eq!(
        unsafe { at_angle_table_fixed_from_harmonics(&harmonics, &mut table) },
        AT_OK
    );
    let adc = adc_12();
    let corrected = chain_of(Some(&adc), Some(&calibration), Some(&table), 28_800.0).unwrap();
    let plain = chain_of(Some(&adc), None, None, 0.0).unwrap();
    let (good, bad) = (worst_error(&corrected), worst_error(&plain));
    // Under Miri, too few samples to settle: the calls only.
    if !cfg!(miri) {
        assert!(good < 1e-3, "{good}");
        assert!(bad > 10.0 * good && bad > 0.02, "{bad} against {good}");
    }
}

#[test]
fn refuses_each_bad_parameter_with_its_status() {
    let mut adc = at_adc_counts::default();
    // SAFETY: valid pointers, or NULL.
    unsafe {
        assert_eq!(at_adc_counts_offset_binary(17, &mut adc), AT_ERR_BITS);
        assert_eq!(at_adc_counts_twos_complement(1, &mut adc), AT_ERR_BITS);
        assert_eq!(
            at_adc_counts_twos_complement(12, core::ptr::null_mut()),
            AT_ERR_NULL_POINTER
        );
        assert_eq!(at_adc_counts_twos_complement(12, &mut adc), AT_OK);
    }
    assert_eq!(
        adc,
        at_adc_counts {
            mid_scale_counts: 0,
            shift: 4
        }
    );
    let shift = at_adc_counts {
        mid_scale_counts: 0,
        shift: 16,
    };
    assert_eq!(
        chain_of(Some(&shift), None, None, 0.0).err(),
        Some(AT_ERR_SHIFT)
    );
    let mid = at_adc_counts {
        mid_scale_counts: i32::MIN,
        shift: 0,
    };
    assert_eq!(
        chain_of(Some(&mid), None, None, 0.0).err(),
        Some(AT_ERR_MID_SCALE_COUNTS)
    );
    let good = at_sensor_calibration_f32 {
        offset_c: 0.0,
        offset_s: 0.0,
        amplitude_c: 16000.0,
        amplitude_s: 16000.0,
        quadrature_rad: 0.0,
    };
    for (bad, status) in [
        (
            at_sensor_calibration_f32 {
                offset_c: 40_000.0,
                ..good
            },
            AT_ERR_OFFSET_C,
        ),
        (
            at_sensor_calibration_f32 {
                offset_s: f32::NAN,
                ..good
            },
            AT_ERR_OFFSET_S,
        ),
        (
            at_sensor_calibration_f32 {
                amplitude_c: 0.0,
                ..good
            },
            AT_ERR_AMPLITUDE_C,
        ),
        (
            at_sensor_calibration_f32 {
                amplitude_s: 7000.0,
                ..good
            },
            AT_ERR_AMPLITUDE_S,
        ),
        (
            at_sensor_calibration_f32 {
                quadrature_rad: 1.0,
                ..good
            },
            AT_ERR_QUADRATURE_RAD,
        ),
    ] {
        assert_eq!(
            chain_of(None, Some(&bad), None, 0.0).err(),
            Some(status),
            "{bad:?}"
        );
    }
    let table = at_angle_table_fixed {
        errors_q15: [8193; AT_ANGLE_TABLE_LENGTH],
    };
    assert_eq!(
        chain_of(None, None, Some(&table), 0.0).err(),
        Some(AT_ERR_ANGLE_CORRECTION)
    );
    assert_eq!(
        chain_of(None, None, None, 2000.0).err(),
        Some(AT_ERR_NOMINAL_AMPLITUDE)
    );
    assert_eq!(
        chain_of(None, None, None, f64::NAN).err(),
        Some(AT_ERR_NOMINAL_AMPLITUDE)
    );
    let mut chain = at_chain_fixed::ZEROED;
    // SAFETY: valid pointers, or NULL.
    unsafe {
        let zeroed = at_fixed_gains::ZEROED;
        assert_eq!(
            at_chain_fixed_new(&zeroed, None, None, None, 0.0, &mut chain),
            AT_ERR_ORDER
        );
        assert_eq!(
            at_chain_fixed_new(null(), None, None, None, 0.0, &mut chain),
            AT_ERR_NULL_POINTER
        );
        let mut state = at_chain_state_fixed::FRESH;
        assert_eq!(
            at_chain_fixed_track_i16(&chain, &mut state, 0, 0),
            AT_FAULT_INVALID_ARGUMENT
        );
        assert_eq!(
            at_chain_fixed_estimate(&chain, &state).faults,
            AT_FAULT_INVALID_ARGUMENT
        );
        assert_eq!(at_chain_state_fixed_clear_faults(&mut state), 0);
        at_chain_state_fixed_reset(core::ptr::null_mut());
    }
}

#[test]
fn structs_of_another_build_are_refused() {
    let mut chain = chain_of(None, None, None, 0.0).unwrap();
    let mut state = at_chain_state_fixed::FRESH;
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!(at_chain_fixed_track_i16(&chain, &mut state, 0, 16000), 0);
        let mut other = state;
        other.set_layout_for_test(0x1234_5679);
        let before = other.clone_tag();
        assert_eq!(
            at_chain_fixed_track_i16(&chain, &mut other, 0, 16000),
            AT_FAULT_INVALID_ARGUMENT
        );
        assert_eq!(
            at_chain_fixed_estimate(&chain, &other).faults,
            AT_FAULT_INVALID_ARGUMENT
        );
        assert_eq!(other.clone_tag(), before);
        chain.set_layout_for_test(0x1234_5679);
        assert_eq!(
            at_chain_fixed_update_i16(&chain, &mut state, 0, 16000).faults,
            AT_FAULT_INVALID_ARGUMENT
        );
    }
}

#[test]
fn the_storage_is_tight() {
    use core::mem::size_of;
    for (size, words) in [
        (
            size_of::<ChainFixed<2>>().max(size_of::<ChainFixed<3>>()),
            AT_CHAIN_FIXED_WORDS,
        ),
        (
            size_of::<crate::chain::ChainF32<2>>().max(size_of::<crate::chain::ChainF32<3>>()),
            AT_CHAIN_F32_WORDS,
        ),
        (
            size_of::<StateFixed<2>>().max(size_of::<StateFixed<3>>()),
            AT_CHAIN_STATE_FIXED_WORDS,
        ),
    ] {
        assert!(
            size > (words - 1) * 8 && size <= words * 8,
            "{size} bytes in {words} words"
        );
    }
}

#[test]
fn float_tables_from_the_c_functions() {
    let mut table = at_angle_correction_table_f32 {
        errors_rad: [0.0; AT_ANGLE_TABLE_LENGTH],
    };
    let curve = [0.0f32, 0.002, 0.0, -0.002];
    // SAFETY: valid pointers to live values, or NULL.
    unsafe {
        assert_eq!(
            at_angle_correction_table_f32_from_curve(curve.as_ptr(), 1, &mut table),
            AT_ERR_CURVE
        );
        assert_eq!(
            at_angle_correction_table_f32_from_curve(null(), 4, &mut table),
            AT_ERR_NULL_POINTER
        );
        assert_eq!(
            at_angle_correction_table_f32_from_curve(curve.as_ptr(), 4, &mut table),
            AT_OK
        );
        assert!((table.errors_rad[64] - 0.002).abs() < 1e-7);
        assert_eq!(at_angle_correction_table_f32_check(&table), AT_OK);
        let mut fixed = at_angle_table_fixed {
            errors_q15: [0; AT_ANGLE_TABLE_LENGTH],
        };
        assert_eq!(
            at_angle_table_fixed_from_errors(table.errors_rad.as_ptr(), &mut fixed),
            AT_OK
        );
        assert_eq!(fixed.errors_q15[64], 66);
        table.errors_rad[3] = 0.3;
        assert_eq!(
            at_angle_correction_table_f32_check(&table),
            AT_ERR_ANGLE_CORRECTION
        );
        assert_eq!(
            at_angle_table_fixed_from_errors(table.errors_rad.as_ptr(), &mut fixed),
            AT_ERR_ANGLE_CORRECTION
        );
        assert_eq!(fixed.errors_q15[64], 66, "unchanged on error");
        let mut h = at_angle_correction_f32::default();
        h.cos_coefficients[0] = 0.01;
        assert_eq!(
            at_angle_correction_table_f32_from_harmonics(&h, &mut table),
            AT_OK
        );
        assert!((table.errors_rad[0] + 0.01).abs() < 1e-7, "cos(-pi) = -1");
    }
}

#[test]
fn the_chains_integers_are_checked_with_their_statuses() {
    let gains = fixed_gains();
    let observer = FixedGains::<3>::from_constants(gains.constants(), gains.sample_period_s);
    let monitor = observer.unwrap().with_monitor(Some(28_800.0)).unwrap();
    let constants = at_chain_fixed_constants {
        gains,
        monitor: monitor.monitor_words(),
        adc: None,
        calibration_q14: None,
        table: None,
    };
    let build = |c: *const at_chain_fixed_constants| {
        let mut chain = at_chain_fixed::ZEROED;
        // SAFETY: a valid pointer to a live value, or NULL.
        unsafe { at_chain_fixed_from_constants(c, &mut chain) }
    };
    assert_eq!(build(&constants), AT_OK);
    assert_eq!(build(null()), AT_ERR_NULL_POINTER);
    let no_sine = [0, 0, 0, 0];
    let calibration_q14 = Some(&no_sine);
    let bad = at_chain_fixed_constants {
        calibration_q14,
        ..constants
    };
    assert_eq!(build(&bad), AT_ERR_AMPLITUDE_S);
    let mut bad = constants;
    bad.monitor[1] = bad.monitor[2] + 1;
    assert_eq!(build(&bad), AT_ERR_LOSS_OF_SIGNAL);
    // A tracking-error level beyond Q15's (`MAX_TRACKING_ERROR_Q15`), or none.
    for level in [0, 32765] {
        let mut bad = constants;
        bad.monitor[8] = level;
        assert_eq!(build(&bad), AT_ERR_TRACKING_ERROR, "{level}");
    }
    let mut bad = constants;
    bad.gains.sample_period_s = f64::NAN;
    assert_eq!(build(&bad), AT_ERR_SAMPLE_PERIOD_S);
    bad.gains.order = 4;
    assert_eq!(build(&bad), AT_ERR_ORDER);
}
