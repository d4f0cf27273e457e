//! The `const` constructors (and the generic ones, which reach the same checks through
//! `ConstChecks`) against values worked out by hand from `docs/theory.md §6` and the
//! documented defaults: the gains' fields and loop polynomial, and for each invalid
//! configuration the error and the parameter it names.

use crate::error::{ConfigError, Parameter};
use crate::*;

use ConfigError::{NotFinite, NotPositive, OutOfRange, Unstable};

/// Sample periods and the refusal each gets whatever the gains: not finite, not positive,
/// or outside 1 ps to 1000 s.
const PERIODS: [(f64, Option<ConfigError>); 9] = [
    (1e-6, None),
    (50e-6, None),
    (1e-3, None),
    (0.5, None),
    (0.0, Some(NotPositive(Parameter::SamplePeriod))),
    (-1.0, Some(NotPositive(Parameter::SamplePeriod))),
    (f64::NAN, Some(NotFinite(Parameter::SamplePeriod))),
    (1e-13, Some(OutOfRange(Parameter::SamplePeriod))),
    (1e4, Some(OutOfRange(Parameter::SamplePeriod))),
];

/// 3rd-order gains and the first of the conditions of `docs/theory.md §6` each breaks,
/// worked out by hand: l3 > 0, l2 > 0, 4 l1 > l3, 4 l1 + 2 l2 < 8, then the Hurwitz
/// determinant 2 l2 (4 l1 - l3) > l3 (8 - 4 l1 - 2 l2).
const GAIN_SETS_3: [([f64; 3], Option<ConfigError>); 7] = [
    // Hurwitz: 0.0252 (0.6312 - 0.00034) = 0.0159 > 0.00034 (8 - 0.6564) = 0.0025.
    ([0.1578, 0.0126, 0.000_34], None),
    // 0.08 (1.2 - 0.002) = 0.0958 > 0.002 (8 - 1.28) = 0.0134.
    ([0.3, 0.04, 0.002], None),
    // The loop polynomial's constant term is l3 < 0: a real pole beyond z = 1.
    (
        [0.3, 0.04, -0.002],
        Some(Unstable {
            parameter: Parameter::AccelerationGain,
            condition: "l3 > 0",
        }),
    ),
    // 4 * 1.9 + 2 * 0.5 = 8.6: P(-1) = 0.6 > 0 and P(-inf) < 0, a real pole beyond z = -1.
    (
        [1.9, 0.5, 0.9],
        Some(Unstable {
            parameter: Parameter::AngleGain,
            condition: "4 l1 + 2 l2 < 8",
        }),
    ),
    // l1 = 0: the product of the poles is 1 - l1 = 1, one of them on or outside the circle.
    (
        [0.0, 0.01, 0.001],
        Some(Unstable {
            parameter: Parameter::AngleGain,
            condition: "4 l1 > l3",
        }),
    ),
    (
        [f64::NAN, 0.01, 0.001],
        Some(NotFinite(Parameter::AngleGain)),
    ),
    (
        [0.3, f64::INFINITY, 0.002],
        Some(NotFinite(Parameter::SpeedGain)),
    ),
];

/// 2nd-order gains and the first condition each breaks: l2 > 0, l1 > 0, 2 l1 + l2 < 4.
const GAIN_SETS_2: [([f64; 2], Option<ConfigError>); 5] = [
    ([0.05, 0.0012], None),
    // 4 + 2e-9 (in f32 exactly 4, still not below 4).
    (
        [1.5, 1.0 + 1e-9],
        Some(Unstable {
            parameter: Parameter::AngleGain,
            condition: "2 l1 + l2 < 4",
        }),
    ),
    // P(1) = l2 < 0: a real pole beyond z = 1.
    (
        [0.1, -0.01],
        Some(Unstable {
            parameter: Parameter::SpeedGain,
            condition: "l2 > 0",
        }),
    ),
    (
        [1.9, 0.3],
        Some(Unstable {
            parameter: Parameter::AngleGain,
            condition: "2 l1 + l2 < 4",
        }),
    ),
    ([0.05, f64::NAN], Some(NotFinite(Parameter::SpeedGain))),
];

/// `|a - b| <= tolerance |b|`, elementwise.
fn close<const N: usize>(a: [f64; N], b: [f64; N], tolerance: f64) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (x - y).abs() <= tolerance * y.abs())
}

/// The loop polynomial in `s = z - 1` (lowest power first, monic) of `docs/theory.md §6`,
/// expanded by hand from `P(z)`: order 3 `z^3 + (l1 + l2 + l3/2 - 3) z^2 + (3 - 2 l1 - l2 +
/// l3/2) z + l1 - 1`, order 2 `z^2 + (l1 + l2 - 2) z + 1 - l1`.
fn loop_polynomial_3([l1, l2, l3]: [f64; 3]) -> [f64; 3] {
    [l3, l2 + 1.5 * l3, l1 + l2 + 0.5 * l3]
}

fn loop_polynomial_2([l1, l2]: [f64; 2]) -> [f64; 2] {
    [l2, l1 + l2]
}

/// Checks `Gains::<$t, N>` built by `new_const`, `new` and `from_loop_polynomial_const`
/// against the tables: the refusal of the period, else of the gains, else the fields.
macro_rules! check_gains {
    ($t:ident, $n:literal, $sets:expr, $polynomial:ident, $tolerance:expr) => {
        for (ts, period_error) in PERIODS {
            for (l, gains_error) in $sets {
                let lt = l.map(|x| x as $t);
                let tst = ts as $t;
                let expected = period_error.or(gains_error);
                let built = [
                    Gains::<$t, $n>::new_const(lt, tst),
                    Gains::<$t, $n>::new(lt, tst),
                ];
                for gains in built {
                    match (expected, gains) {
                        (Some(e), got) => assert_eq!(got.err(), Some(e), "{l:?} at {ts}"),
                        (None, Ok(g)) => {
                            assert_eq!(g.gains(), lt);
                            assert_eq!(g.sample_period(), tst);
                            assert_eq!(g.sample_rate, 1.0 / tst);
                            assert_eq!(g.sample_rate_squared, g.sample_rate * g.sample_rate);
                            // (A L)[0]: l1 + l2 (+ l3 / 2).
                            let next: f64 = l[0] + l[1] + l.get(2).map_or(0.0, |l3| 0.5 * l3);
                            assert!(close([g.next_angle_gain as f64], [next], $tolerance));
                            let c = g.loop_polynomial().map(|x| x as f64);
                            assert!(close(c, $polynomial(l), $tolerance), "{c:?} of {l:?}");
                        }
                        (None, Err(e)) => panic!("{l:?} at {ts} refused: {e}"),
                    }
                }
                // The gains back from their loop polynomial (of the finite sets): an
                // unstable set is refused as from its gains.
                if l.iter().all(|x| x.is_finite()) {
                    let c = $polynomial(l).map(|x| x as $t);
                    match (
                        expected,
                        Gains::<$t, $n>::from_loop_polynomial_const(c, tst),
                    ) {
                        (None, Ok(g)) => {
                            let back = g.gains().map(|x| x as f64);
                            assert!(close(back, l, $tolerance), "{back:?} from {c:?}");
                        }
                        (Some(e), got) => assert_eq!(got.err(), Some(e), "{c:?} at {ts}"),
                        (None, Err(e)) => panic!("{c:?} at {ts} refused: {e}"),
                    }
                }
            }
        }
    };
}

#[test]
fn gains_have_the_hand_computed_fields_and_refusals_on_both_types_and_orders() {
    check_gains!(f64, 3, GAIN_SETS_3, loop_polynomial_3, 1e-12);
    check_gains!(f32, 3, GAIN_SETS_3, loop_polynomial_3, 1e-4);
    check_gains!(f64, 2, GAIN_SETS_2, loop_polynomial_2, 1e-12);
    check_gains!(f32, 2, GAIN_SETS_2, loop_polynomial_2, 1e-4);
}

/// `FaultThresholds::for_amplitude` as documented: input limit 4 A, loss of signal 0.25 A,
/// degradation 0.5 A to 1.5 A, loss of tracking 0.1 rad (a window's mean) and 0.05 (one
/// sample's `|eps|`), a 1/16 filter, false lock at 0, a
/// sample's magnitude within 10 % of A.
fn documented_thresholds(a: f32) -> FaultThresholds<f32> {
    FaultThresholds {
        nominal_amplitude: a,
        max_input_amplitude: 4.0 * a,
        loss_of_signal: 0.25 * a,
        degradation_low: 0.5 * a,
        degradation_high: 1.5 * a,
        loss_of_tracking: 0.1,
        tracking_error: 0.05,
        max_speed: None,
        filter_factor: 1.0 / 16.0,
        false_lock: 0.0,
        magnitude_tolerance: Some(0.1),
        monitor: true,
        re_acquire: true,
    }
}

#[test]
fn thresholds_and_settings_have_the_documented_values_and_refusals() {
    let gains = Gains::<f32, 3>::new_const([0.3, 0.04, 0.002], 1e-4).unwrap();
    // Per amplitude, the refusal of the default thresholds (an amplitude whose input limit
    // squared overflows f32, or a NaN one); the three variants are refused for their own
    // field first.
    for (amplitude, default_error) in [
        (1e-30_f32, None),
        (1.0, None),
        (1800.0, None),
        (1e30, Some(OutOfRange(Parameter::MaxInputAmplitude))),
        (f32::NAN, Some(NotFinite(Parameter::NominalAmplitude))),
    ] {
        let t = FaultThresholds::<f32>::for_amplitude_const(amplitude);
        if amplitude.is_nan() {
            assert!(t.nominal_amplitude.is_nan() && t.max_input_amplitude.is_nan());
        } else {
            assert_eq!(t, documented_thresholds(amplitude));
            assert_eq!(FaultThresholds::for_amplitude(amplitude), t);
        }
        let nan_first = |e: ConfigError| default_error.filter(|_| amplitude.is_nan()).or(Some(e));
        for (variant, error) in [
            (t, default_error),
            (
                FaultThresholds {
                    filter_factor: 1.5,
                    ..t
                },
                nan_first(OutOfRange(Parameter::FilterFactor)),
            ),
            (
                FaultThresholds {
                    false_lock: -2.0 * amplitude,
                    ..t
                },
                nan_first(OutOfRange(Parameter::FalseLockThreshold)),
            ),
            (
                FaultThresholds {
                    max_speed: Some(-1.0),
                    ..t
                },
                nan_first(NotPositive(Parameter::MaxSpeed)),
            ),
        ] {
            for built in [
                gains.with_fault_thresholds_const(variant),
                gains.with_fault_thresholds(variant),
            ] {
                match (error, built) {
                    (Some(e), got) => assert_eq!(got.err(), Some(e), "{variant:?}"),
                    (None, Ok(g)) => {
                        assert_eq!(g.fault_thresholds(), variant);
                        // The default filter factor 1/16 is a window of 16 samples.
                        assert_eq!(g.thresholds.window, 16);
                    }
                    (None, Err(e)) => panic!("{variant:?} refused: {e}"),
                }
            }
            assert_eq!(variant.check_const(1e-4).err(), error);
        }
    }
    let t64 = FaultThresholds::<f64>::for_amplitude_const(3.0);
    assert_eq!(t64.max_input_amplitude, 12.0);
    assert_eq!(t64.loss_of_signal, 0.75);
    assert_eq!(t64.degradation_low, 1.5);
    assert_eq!(t64.degradation_high, 4.5);
    assert_eq!(t64.loss_of_tracking, 0.1_f32 as f64);
    // The online calibration's documented defaults.
    let defaults = CalibrationSettings::<f64>::default_const();
    assert_eq!(defaults.min_speed_rad_s, None);
    assert_eq!(defaults.max_offset, 0.1_f32 as f64);
    assert_eq!(defaults.max_amplitude_mismatch, 0.2_f32 as f64);
    assert_eq!(defaults.max_quadrature_rad, 0.1_f32 as f64);
    // The minimum speed at 10 kHz: from 2 pi / 2^20 to pi / 2 rad per sample, 0.06 to
    // 15708 rad/s.
    for (speed, error) in [
        (None, None),
        (Some(50.0), None),
        (Some(1e-3), Some(OutOfRange(Parameter::MinSpeed))),
        (Some(1e5), Some(OutOfRange(Parameter::MinSpeed))),
        (Some(f32::INFINITY), Some(NotFinite(Parameter::MinSpeed))),
    ] {
        let s = CalibrationSettings {
            min_speed_rad_s: speed,
            ..CalibrationSettings::<f32>::default_const()
        };
        for built in [
            gains.with_calibration_settings_const(s),
            gains.with_calibration_settings(s),
        ] {
            match (error, built) {
                (Some(e), got) => assert_eq!(got.err(), Some(e), "{speed:?}"),
                (None, Ok(g)) => assert_eq!(g.calibration_settings(), s),
                (None, Err(e)) => panic!("{speed:?} refused: {e}"),
            }
        }
    }
}

#[test]
fn square_root_of_the_smallest_normal_is_exact() {
    assert_eq!(f32::from_bits(0x2000_0000), libm::sqrtf(f32::MIN_POSITIVE));
    assert_eq!(
        f64::from_bits(0x2000_0000_0000_0000),
        libm::sqrt(f64::MIN_POSITIVE)
    );
}

/// A complete firmware configuration as a `static`, evaluated by the compiler.
static FIRMWARE_GAINS: Gains<f32, 3> =
    match Gains::<f32, 3>::new_const([0.1578, 0.0126, 0.000_34], 50e-6) {
        Ok(gains) => {
            match gains
                .with_fault_thresholds_const(FaultThresholds::<f32>::for_amplitude_const(0.88))
            {
                Ok(gains) => gains,
                Err(_) => panic!("bad thresholds"),
            }
        }
        Err(_) => panic!("unstable gains"),
    };

#[test]
fn a_static_configuration_runs() {
    let mut state = ObserverState::new();
    let estimate = FIRMWARE_GAINS.update(&mut state, 0.44, 0.762);
    assert!((estimate.angle - core::f32::consts::FRAC_PI_3).abs() < 1e-3);
    assert!(estimate.faults.is_empty());
}
