//! Unit tests of the C API's conversions, module by module: the status table, the fault
//! bits, the gains, the ADC, the fixed-point gains and the angle-correction tables.

use angletrack_core::{AdcScaling, ConfigError, Faults, FixedGains, Parameter};

use crate::faults::{NAMES, name};
use crate::status::{PARAMETERS, message, status_of};
use crate::*;

/// Each parameter's status names it as the core does, and the codes are distinct.
#[test]
fn messages_are_the_core_parameter_names() {
    for (i, (parameter, status, _)) in PARAMETERS.iter().enumerate() {
        assert_eq!(
            message(*status).to_str(),
            Ok(parameter.name()),
            "{parameter:?}"
        );
        assert_eq!(status_of(ConfigError::NotFinite(*parameter)), *status);
        assert!(PARAMETERS[..i].iter().all(|(_, s, _)| s != status));
    }
    assert_eq!(message(AT_OK).to_str(), Ok("ok"));
    assert_eq!(message(-7).to_str(), Ok("unknown status"));
}

/// The C constants are the core's bits with the core's names, in the core's order.
#[test]
fn bits_and_names_match_the_core() {
    assert_eq!(Faults::NAMES.len() + 1, NAMES.len());
    for ((flag, core_name), (bit, c_name)) in Faults::NAMES.iter().zip(&NAMES) {
        assert_eq!(u32::from(flag.bits()), *bit);
        assert_eq!(c_name.to_str(), Ok(*core_name));
        assert_eq!(name(*bit), *c_name);
    }
    let all_core = Faults::NAMES
        .iter()
        .fold(0, |all, (f, _)| all | u32::from(f.bits()));
    assert_eq!(all_core & AT_FAULT_INVALID_ARGUMENT, 0);
    assert_eq!(name(0).to_str(), Ok("unknown fault"));
    assert_eq!(name(3).to_str(), Ok("unknown fault"));
}

#[test]
fn gains_check_as_the_core_and_keep_the_order() {
    assert_eq!(
        at_gains_f32::of(&[0.3, 0.04, -0.002], 1e-4),
        Err(AT_ERR_GAINS_2)
    );
    assert_eq!(
        at_gains_f32::of(&[0.3, 0.04], 0.0),
        Err(AT_ERR_SAMPLE_PERIOD_S)
    );
    assert_eq!(at_gains_f32::of(&[0.3], 1e-4), Err(AT_ERR_ORDER));
    let two = at_gains_f32::of(&[0.05, 0.0012], 1e-4).unwrap();
    assert_eq!((two.order, two.gains), (2, [0.05, 0.0012, 0.0]));
    assert_eq!(two.core::<2>().map(|g| g.gains()), Ok([0.05, 0.0012]));
    let mut three = at_gains_f32::of(&[0.3, 0.04, 0.002], 1e-4).unwrap();
    let core = three.core::<3>().unwrap().fault_thresholds();
    assert_eq!(
        three.thresholds,
        at_fault_thresholds_f32::from(core),
        "the core's defaults"
    );
    three.thresholds = at_fault_thresholds_f32::for_amplitude(1800.0);
    three.thresholds.max_speed_rad_s = 1000.0;
    three.thresholds.monitor = 0;
    three.thresholds.tracking_error = 0.02;
    let core = three.core::<3>().unwrap().fault_thresholds();
    assert_eq!(
        (core.max_speed, core.monitor, core.loss_of_signal),
        (Some(1000.0), false, 450.0)
    );
    assert_eq!(core.tracking_error, 0.02);
    assert_eq!(at_fault_thresholds_f32::from(core), three.thresholds);
    three.thresholds.tracking_error = 0.0;
    let refused = three.core::<3>().map_err(status_of);
    assert_eq!(refused.err(), Some(AT_ERR_TRACKING_ERROR));
    three.thresholds.tracking_error = 0.02;
    three.thresholds.filter_factor = 1.5;
    let refused = three.core::<3>().map_err(status_of);
    assert_eq!(refused.err(), Some(AT_ERR_FILTER_FACTOR));
}

#[test]
fn stores_the_checked_front_end() {
    let mut adc = at_adc_f32::ZEROED;
    assert!(adc.stage().is_err());
    assert_eq!(adc.set_range(0, 4095), AT_ERR_NOT_INITIALISED);
    assert_eq!(adc.set(AdcScaling::offset_binary(40), None), AT_ERR_BITS);
    assert!(adc.stage().is_err());
    assert_eq!(adc.set(AdcScaling::offset_binary(12), None), AT_OK);
    assert_eq!(
        adc.stage().map(|a| a.scaling.sample(4095u16, 0u16)),
        Ok((2047.0 / 2048.0, -1.0))
    );
    assert_eq!(adc.stage().map(|a| a.range), Ok(None));
    assert_eq!(adc.set_range(4095, 4095), AT_ERR_ADC_RANGE);
    assert_eq!(adc.set_range(0, 4095), AT_OK);
    assert_eq!(adc.stage().map(|a| a.range), Ok(Some((0, 4095))));
}

#[test]
fn constants_and_gains_check_as_the_core() {
    let quantised = at_fixed_gains::quantised(&[0.1578, 0.0126, 0.000_34], 50e-6).unwrap();
    let designed = FixedGains::<3>::new(
        [0.1578f32.into(), 0.0126f32.into(), 0.000_34f32.into()],
        50e-6,
    )
    .unwrap()
    .constants();
    assert_eq!(quantised.constants::<3>(), designed);
    let again = at_fixed_gains::checked(&designed.multiplier, designed.acceleration_shift, 50e-6);
    assert_eq!(again, Ok(quantised));
    let shift_0 = at_fixed_gains::checked(&[1, 1, 1], 0, 50e-6);
    assert_eq!(
        shift_0,
        Err(AT_ERR_GAINS_2),
        "the shift of a 3rd-order observer is 1 to 15"
    );
    assert_eq!(
        at_fixed_gains::checked(&[1, 1], 0, 0.0),
        Err(AT_ERR_SAMPLE_PERIOD_S)
    );
    assert_eq!(at_fixed_gains::checked(&[1], 0, 1e-4), Err(AT_ERR_ORDER));
    assert_eq!(
        at_fixed_gains::quantised(&[1e-30, 1e-3], 1e-4),
        Err(AT_ERR_GAINS_0)
    );
}

fn third_harmonic(b3: f32) -> at_angle_correction_f32 {
    let mut h = at_angle_correction_f32::default();
    h.sin_coefficients[2] = b3;
    h
}

#[test]
fn tables_agree_with_their_harmonics() {
    let h = third_harmonic(0.004);
    let float = at_angle_correction_table_f32::from_harmonics(&h).unwrap();
    let fixed = at_angle_table_fixed::from_harmonics(&h).unwrap();
    for k in 0..AT_ANGLE_TABLE_LENGTH {
        let angle = -core::f64::consts::PI + core::f64::consts::TAU * k as f64 / 256.0;
        let d = 0.004 * (3.0 * angle).sin();
        assert!((f64::from(float.errors_rad[k]) - d).abs() < 1e-7, "{k}");
        assert!((f64::from(fixed.errors_q15[k]) / 32768.0 - d).abs() <= 0.5 / 32768.0);
    }
    assert_eq!(fixed.checked().unwrap().errors_q15(), fixed.errors_q15);
    assert!(float.checked().is_ok());
    let again = at_angle_table_fixed::from_errors(&float.errors_rad).unwrap();
    assert_eq!(again, fixed);
}

#[test]
fn refuses_what_the_core_refuses() {
    let angle_correction = |e: ConfigError| e.parameter() == Parameter::AngleCorrection;
    assert!(
        at_angle_table_fixed::from_harmonics(&third_harmonic(0.3)).is_err_and(angle_correction)
    );
    let mut errors = [0.0; AT_ANGLE_TABLE_LENGTH];
    errors[7] = f32::NAN;
    assert!(at_angle_table_fixed::from_errors(&errors).is_err_and(angle_correction));
    let bad = at_angle_table_fixed {
        errors_q15: [9000; AT_ANGLE_TABLE_LENGTH],
    };
    assert!(bad.checked().is_err_and(angle_correction));
    let curve = at_angle_correction_table_f32::from_curve(&[0.0]);
    assert!(curve.is_err_and(|e| e.parameter() == Parameter::AngleErrorCurve));
    let curve = at_angle_correction_table_f32::from_curve(&[0.0, 0.002, 0.0, -0.002]).unwrap();
    assert!((curve.errors_rad[64] - 0.002).abs() < 1e-7);
}

/// The pairs' `faults` are the core's bits: each constant is its flag's.
#[test]
fn front_end_fault_bits_are_the_core_s() {
    use angletrack_core::FrontEndFaults;
    let flags = [
        (
            AT_FRONT_END_FAULT_LOSS_OF_EXCITATION,
            FrontEndFaults::LOSS_OF_EXCITATION,
        ),
        (AT_FRONT_END_FAULT_PHASE_DRIFT, FrontEndFaults::PHASE_DRIFT),
        (AT_FRONT_END_FAULT_CLIPPING, FrontEndFaults::CLIPPING),
        (
            AT_FRONT_END_FAULT_WEAK_EXCITATION,
            FrontEndFaults::WEAK_EXCITATION,
        ),
        (AT_FRONT_END_FAULT_WINDING, FrontEndFaults::WINDING),
        (
            AT_FRONT_END_FAULT_EXCITATION_REFERENCE,
            FrontEndFaults::EXCITATION_REFERENCE,
        ),
    ];
    assert_eq!(flags.len(), FrontEndFaults::NAMES.len());
    for (bit, flag) in flags {
        assert_eq!(bit, u32::from(flag.bits()));
    }
}
