//! The demodulator's `const` constructors: a configuration built in constant evaluation (a
//! firmware's `static`), its derived constants, and settings refused there.

use super::*;
use core::f64::consts::{PI, TAU};

/// A firmware's demodulator in a `static`, built in constant evaluation.
static FIXED: Demodulator<i16> = match Demodulator::<i16>::new_const(DemodulatorSettings {
    expected_delay_rad: 5.3,
    ..DemodulatorSettings::<f32>::new_const(10e3, 150e3, 1800.0, 0.0, 4095.0)
}) {
    Ok(demodulator) => demodulator,
    Err(_) => panic!("bad demodulator settings"),
};

#[test]
fn the_const_constructors_build_the_configuration_and_refuse_bad_settings() {
    // 15 samples per period: 2^32 / 15 phase units per sample, 3 % either side (to f32's
    // resolution, 2^-24 of the value); the clipping range the codes' middle and half the
    // span less the margin (4095 / 256); 2^29 / 1800 (Q24).
    let near = |step: u32, turns: f64| (f64::from(step) - turns * 4_294_967_296.0).abs() < 64.0;
    assert!(near(FIXED.step, 1.0 / 15.0), "{}", FIXED.step);
    assert!(near(FIXED.step_min, 0.97 / 15.0) && near(FIXED.step_max, 1.03 / 15.0));
    assert_eq!((FIXED.clip_centre, FIXED.clip_half_span), (2047, 2031));
    assert_eq!(FIXED.pair_gain, 298_261);
    const F32: Result<Demodulator<f32>, ConfigError> = Demodulator::<f32>::new_const(
        DemodulatorSettings::<f32>::new_const(10e3, 48e3, 1800.0, -2048.0, 2047.0),
    );
    let d = F32.unwrap();
    assert_eq!(
        (d.clip_centre, d.clip_half_span),
        (-0.5, 2047.5 - 4095.0 / 256.0)
    );
    assert_eq!(d.samples_per_period(), 4.8);
    const F64: Result<Demodulator<f64>, ConfigError> =
        Demodulator::<f64>::new_const(DemodulatorSettings {
            max_carrier_error: 0.3,
            ..DemodulatorSettings::<f64>::new_const(10e3, 48e3, 1800.0, 0.0, 4095.0)
        });
    assert_eq!(
        F64,
        Err(ConfigError::OutOfRange(Parameter::MaxCarrierError))
    );
    // The expected delay as the windings' carrier phase, wrapped, and its sine and cosine,
    // by series in constant evaluation: a delay of 5.3 rad is a phase of -5.3 rad, 0.98 rad,
    // its cosine and sine in Q16.
    let expected = f64::from(FIXED.expected as i32) * PI / 2_147_483_648.0;
    assert!((expected - (TAU - 5.3)).abs() < 1e-6, "{expected}");
    let (cos, sin) = (((-5.3_f64).cos() * 65_536.0), ((-5.3_f64).sin() * 65_536.0));
    assert!(
        (FIXED.expected_cos as f64 - cos).abs() <= 2.0,
        "{}",
        FIXED.expected_cos
    );
    assert!(
        (FIXED.expected_sin as f64 - sin).abs() <= 2.0,
        "{}",
        FIXED.expected_sin
    );
}
