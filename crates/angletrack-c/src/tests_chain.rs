//! Tests of the signal chain through its `extern "C"` functions: each combination is the
//! core's tracker of the same stages, bit for bit (the door only converts), and the stages
//! correct an imperfect sensor.
#![allow(unsafe_code)]

use core::f32::consts::{PI, TAU};

use angletrack_core::{
    AdcScaling, CalibrationSettings, CalibrationStage, Gains, Input, OnlineCalibration, Rails,
    SensorCalibration, Tracker, TrackerFrontEnd, TrackerSettings,
};

use crate::chain::{ChainF32, StateF32};
use crate::tests::tests_support::Words;
use crate::*;

/// A calibration to write into: all zero.
const ZEROED: at_sensor_calibration_f32 = at_sensor_calibration_f32 {
    offset_c: 0.0,
    offset_s: 0.0,
    amplitude_c: 0.0,
    amplitude_s: 0.0,
    quadrature_rad: 0.0,
};

const GAINS_3: [f32; 3] = [0.094_326_17, 0.000_562_075, 1.213_522e-5];
/// Fewer samples under Miri, whose interpreter is slow: Miri checks the calls (their
/// pointers, the slots' layouts), which a few dozen samples make as the full run does;
/// `cargo test` checks what the full run computes.
pub(crate) const SAMPLES: u32 = if cfg!(miri) { 60 } else { 5000 };

fn gains() -> at_gains_f32 {
    let mut gains = at_gains_f32::ZEROED;
    // SAFETY: valid pointers to live values.
    assert_eq!(
        unsafe { at_gains_f32_new(GAINS_3.as_ptr(), 3, 1e-4, &mut gains) },
        AT_OK
    );
    gains
}

/// The chain of `gains` and the stages given (NULL when `None`).
fn chain_of(
    adc: Option<&at_adc_f32>,
    stored: Option<&at_sensor_calibration_f32>,
    settings: Option<&at_calibration_settings_f32>,
    correction: Option<&at_angle_correction_f32>,
) -> Result<at_chain_f32, at_status> {
    let gains = gains();
    let mut chain = at_chain_f32::ZEROED;
    // SAFETY: valid pointers to live values, or NULL.
    let status =
        unsafe { at_chain_f32_new(&gains, adc, stored, settings, correction, None, &mut chain) };
    if status == AT_OK {
        Ok(chain)
    } else {
        Err(status)
    }
}

/// The chain of `gains`, `stored`, `correction` and `table` (NULL when `None`): its status.
fn chain_with_table(
    stored: Option<&at_sensor_calibration_f32>,
    correction: Option<&at_angle_correction_f32>,
    table: &at_angle_correction_table_f32,
    out: &mut at_chain_f32,
) -> at_status {
    let gains = gains();
    // SAFETY: valid pointers to live values, or NULL.
    unsafe { at_chain_f32_new(&gains, None, stored, None, correction, Some(table), out) }
}

/// The angle of sample `k` at 50 Hz electrical from 0.3 rad, in [0, 2 pi).
fn theta(k: u32) -> f32 {
    (0.3 + 2.0 * PI * 50.0 * k as f32 * 1e-4) % TAU
}

fn wrapped(e: f32) -> f32 {
    (e % TAU + 3.0 * PI) % TAU - PI
}

/// The core's standard chain of the benchmark's 3rd-order gains and `settings`.
fn core_chain(settings: TrackerSettings<f32>) -> ChainF32<3> {
    let gains = Gains::<f32, 3>::new(GAINS_3, 1e-4).unwrap();
    Tracker::new(TrackerFrontEnd::new(settings).unwrap(), gains)
}

#[test]
fn each_combination_is_the_core_tracker_bit_for_bit() {
    let mut adc = at_adc_f32::ZEROED;
    let settings = at_calibration_settings_f32_default();
    let online = CalibrationSettings::default();
    let core = [
        core_chain(TrackerSettings::default()),
        core_chain(TrackerSettings {
            input: Input::Counts {
                adc: AdcScaling::offset_binary(12).unwrap(),
                rails: Rails::Stated { min: 0, max: 4095 },
            },
            ..TrackerSettings::default()
        }),
        core_chain(TrackerSettings {
            calibration: CalibrationStage::Online(OnlineCalibration::new(online, 1e-4).unwrap()),
            ..TrackerSettings::default()
        }),
    ];
    let mut core_states = [(); 3].map(|()| StateF32::<3>::new());
    core_states[2].front_end.calibrator_mut().enable();
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!(at_adc_f32_offset_binary(12, &mut adc), AT_OK);
        let plain = chain_of(None, None, None, None).unwrap();
        let counts = chain_of(Some(&adc), None, None, None).unwrap();
        let online = chain_of(None, None, Some(&settings), None).unwrap();
        let mut states = [at_chain_state_f32::FRESH; 3];
        at_chain_state_f32_set_calibration_mode(&mut states[2], AT_CALIBRATION_LEARNING);
        for k in 0..SAMPLES {
            let t = theta(k);
            let (y_c, y_s) = (0.05 + t.cos(), -0.05 + 1.1 * (t + 0.05).sin());
            let raw = |x: f32| (2048.0 + 1800.0 * x / 1.2).round() as u16;
            let [s0, s1, s2] = &mut states;
            let [c0, c1, c2] = &mut core_states;
            let e = at_chain_f32_update(&plain, s0, y_c, y_s);
            assert_eq!(e, core[0].update(c0, (y_c, y_s)).into());
            let e = at_chain_f32_update_u16(&counts, s1, raw(y_c), raw(y_s));
            assert_eq!(e, core[1].update(c1, (raw(y_c), raw(y_s))).into());
            let e = at_chain_f32_update(&online, s2, y_c, y_s);
            assert_eq!(e, core[2].update(c2, (y_c, y_s)).into());
            assert_eq!(at_chain_f32_track(&plain, s0, y_c, y_s), 0);
            core[0].track(c0, (y_c, y_s));
            assert_eq!(
                at_chain_f32_estimate(&plain, s0),
                core[0].estimate(c0).into()
            );
        }
        let mut learned = ZEROED;
        assert_eq!(
            at_chain_state_f32_calibration(&states[2], &mut learned),
            AT_OK
        );
        let expected = core_states[2].front_end.calibrator().calibration();
        assert_eq!(learned, expected.into());
        let turns = core_states[2].front_end.calibrator().turns_learned();
        assert_eq!(at_chain_state_f32_turns_learned(&states[2]), turns);
        let mode = at_chain_state_f32_calibration_mode(&states[2]);
        assert_eq!(mode, AT_CALIBRATION_LEARNING);
        // Counts into a chain without an ADC stage are refused, the state unchanged.
        let before = at_chain_f32_estimate(&plain, &states[0]);
        let refused = at_chain_f32_track_u16(&plain, &mut states[0], 1, 2);
        assert_eq!(refused, AT_FAULT_INVALID_ARGUMENT);
        assert_eq!(at_chain_f32_estimate(&plain, &states[0]), before);
    }
}

#[test]
fn a_stored_calibration_and_the_angle_correction_remove_the_sensor_errors() {
    // The sensor: offsets, imbalance, quadrature and 5 mrad of 3rd harmonic.
    let stored = at_sensor_calibration_f32 {
        offset_c: 0.02,
        offset_s: -0.01,
        amplitude_c: 1.0,
        amplitude_s: 1.05,
        quadrature_rad: 0.01,
    };
    let mut correction = at_angle_correction_f32::default();
    correction.sin_coefficients[2] = 5e-3;
    let sensor = |t: f32| {
        let d = t + 5e-3 * (3.0 * t).sin();
        (0.02 + d.cos(), -0.01 + 1.05 * (d + 0.01).sin())
    };
    let worst = |chain: &at_chain_f32| {
        let mut state = at_chain_state_f32::FRESH;
        let mut worst = 0.0_f32;
        for k in 0..SAMPLES {
            let (y_c, y_s) = sensor(theta(k));
            // SAFETY: valid pointers to live values.
            let e = unsafe { at_chain_f32_update(chain, &mut state, y_c, y_s) };
            // The loop settles within 0.3 s: the last 0.1 s.
            if k >= SAMPLES - SAMPLES / 5 {
                worst = worst.max(wrapped(e.angle - theta(k)).abs());
            }
        }
        worst
    };
    let plain = worst(&chain_of(None, None, None, None).unwrap());
    let corrected = worst(&chain_of(None, Some(&stored), None, Some(&correction)).unwrap());
    let mut table = at_angle_correction_table_f32 {
        errors_rad: [0.0; AT_ANGLE_TABLE_LENGTH],
    };
    // SAFETY: valid pointers to live values.
    let status = unsafe { at_angle_correction_table_f32_from_harmonics(&correction, &mut table) };
    assert_eq!(status, AT_OK);
    let mut tabled = at_chain_f32::ZEROED;
    assert_eq!(
        chain_with_table(Some(&stored), None, &table, &mut tabled),
        AT_OK
    );
    let tabled = worst(&tabled);
    if !cfg!(miri) {
        assert!(plain > 0.02, "{plain}");
        assert!(corrected < 1e-4, "{corrected}");
        assert!(tabled < 1e-4, "{tabled}");
    }
    // One angle correction: not both.
    let mut chain = at_chain_f32::ZEROED;
    let both = chain_with_table(None, Some(&correction), &table, &mut chain);
    assert_eq!(both, AT_ERR_STAGES);
    table.errors_rad[9] = f32::INFINITY;
    let bad = chain_with_table(None, None, &table, &mut chain);
    assert_eq!(bad, AT_ERR_ANGLE_CORRECTION);
    assert_eq!(chain.clone_tag(), 0, "unchanged on error");
}

#[test]
fn refusals_name_the_stage() {
    let stored = at_sensor_calibration_f32::from(SensorCalibration::IDENTITY);
    let mut settings = at_calibration_settings_f32_default();
    assert_eq!(
        chain_of(None, Some(&stored), Some(&settings), None).err(),
        Some(AT_ERR_STAGES)
    );
    let mut correction = at_angle_correction_f32::default();
    correction.cos_coefficients[7] = 0.3;
    assert_eq!(
        chain_of(None, None, None, Some(&correction)).err(),
        Some(AT_ERR_ANGLE_CORRECTION)
    );
    settings.min_speed_rad_s = 1e-3;
    assert_eq!(
        chain_of(None, None, Some(&settings), None).err(),
        Some(AT_ERR_MIN_SPEED_RAD_S)
    );
    let bad = at_sensor_calibration_f32 {
        amplitude_c: 0.0,
        ..stored
    };
    assert_eq!(
        chain_of(None, Some(&bad), None, None).err(),
        Some(AT_ERR_AMPLITUDE_C)
    );
    let zeroed = at_chain_f32::ZEROED;
    let mut state = at_chain_state_f32::FRESH;
    // SAFETY: valid pointers to live values.
    unsafe {
        assert_eq!(
            at_chain_f32_track(&zeroed, &mut state, 1.0, 0.0),
            AT_FAULT_INVALID_ARGUMENT
        );
        let chain = chain_of(None, None, None, None).unwrap();
        assert_eq!(at_chain_f32_track(&chain, &mut state, 1.0, 0.0), 0);
        state.set_layout_for_test(1);
        assert_eq!(
            at_chain_f32_update(&chain, &mut state, 1.0, 0.0),
            at_estimate_f32::invalid()
        );
        assert_eq!(
            at_chain_state_f32_set_calibration_mode(&mut state, AT_CALIBRATION_LEARNING),
            AT_ERR_OTHER_BUILD
        );
    }
}
