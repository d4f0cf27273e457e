//! Every combination of the standard chain's stages built in constant evaluation (inputs
//! in units and in counts, with clipping unchecked, stated and measured; the winding check
//! or none; calibration none, stored and online; correction none, harmonics and table; in
//! `f32`, `f64` and fixed point), each then run on a sensor with the imperfections its
//! stages remove: the angle within the quantisation's reach of the truth, nothing flagged.

use crate::*;

/// The sample period (s) and the 3rd-order gains of the tests' observers.
const SAMPLE_PERIOD_S: f64 = 50e-6;
const GAINS: [f64; 3] = [0.1578, 0.0126, 0.000_34];
/// The electrical speed (rad/s) of the test signal: 20 turns per second.
const SPEED_RAD_S: f64 = 2.0 * core::f64::consts::PI * 20.0;
/// The float signals' amplitude, as a fraction of the ADC's full scale.
const AMPLITUDE: f64 = 0.8;
/// The stored calibration's sensor: offsets, amplitudes (relative) and quadrature (rad).
const SENSOR: (f64, f64, f64, f64, f64) = (0.02, -0.01, 1.0, 1.05, 0.01);

const fn ok<V: Copy>(result: Result<V, ConfigError>) -> V {
    match result {
        Ok(value) => value,
        Err(_) => panic!("refused"),
    }
}

/// An input and, for counts, the ADC's mid-scale and counts per unit.
type InputCase<A, V> = (Input<A, V>, Option<(i32, f64)>);

/// How the test drives a chain: the input kind and what the sensor is.
#[derive(Clone, Copy, Debug)]
struct Case {
    /// `Some((mid_scale, counts_per_unit))` for counts, `None` for units.
    counts: Option<(i32, f64)>,
    /// The stored calibration's sensor imperfections are in the signal.
    imperfect: bool,
    /// The amplitude, as a fraction of the ADC's full scale.
    amplitude: f64,
}

/// Defines the float combinations for `$t` in a `const` array and a test running them.
macro_rules! float_combinations {
    ($t:ident, $test:ident, $tolerance_rad:expr) => {
        mod $t {
            use super::*;
            type T = $t;

            /// The inputs: units (unchecked, stated, measured) and counts of three ADCs.
            const INPUTS: [InputCase<AdcScaling<T>, T>; 6] = [
                (
                    Input::Units {
                        rails: Rails::Unchecked,
                    },
                    None,
                ),
                (
                    Input::Units {
                        rails: Rails::Stated {
                            min: -1.0,
                            max: 1.0,
                        },
                    },
                    None,
                ),
                (
                    Input::Units {
                        rails: Rails::Measured,
                    },
                    None,
                ),
                (
                    Input::Counts {
                        adc: ok(AdcScaling::<T>::offset_binary_const(12)),
                        rails: Rails::Stated { min: 0, max: 4095 },
                    },
                    Some((2048, 2048.0)),
                ),
                (
                    Input::Counts {
                        adc: ok(AdcScaling::<T>::twos_complement_const(16)),
                        rails: Rails::Measured,
                    },
                    Some((0, 32768.0)),
                ),
                (
                    Input::Counts {
                        adc: ok(AdcScaling::<T>::new_const(2000, 1800.0)),
                        rails: Rails::Unchecked,
                    },
                    Some((2000, 1800.0)),
                ),
            ];
            const WINDINGS: [Option<WindingCheck<T>>; 2] =
                [None, Some(ok(WindingCheck::<T>::new_const(AMPLITUDE as T)))];
            const CALIBRATIONS: [CalibrationStage<T>; 3] = [
                CalibrationStage::None,
                CalibrationStage::Stored(ok(SensorCalibration::<T>::new_const(
                    SENSOR.0 as T,
                    SENSOR.1 as T,
                    SENSOR.2 as T,
                    SENSOR.3 as T,
                    SENSOR.4 as T,
                ))),
                CalibrationStage::Online(ok(OnlineCalibration::<T>::new_const(
                    CalibrationSettings::<T>::default_const(),
                    SAMPLE_PERIOD_S as T,
                ))),
            ];
            const CORRECTIONS: [CorrectionStage<T>; 3] = [
                CorrectionStage::None,
                CorrectionStage::Harmonics(ok(AngleCorrection::<T>::new_const(
                    [0.0, 0.0, 0.0, 0.002, 0.0, 0.0, 0.0, 0.0],
                    [0.0, 0.0, 0.003, 0.0, 0.0, 0.0, 0.0, 0.0],
                ))),
                CorrectionStage::Table(ok(
                    AngleCorrectionTable::<T, TRACKER_TABLE_LENGTH>::new_const({
                        // A saw of +-4 mrad, two teeth per turn.
                        let mut errors = [0.0; TRACKER_TABLE_LENGTH];
                        let mut k = 0;
                        while k < TRACKER_TABLE_LENGTH {
                            let phase = (k % 128) as T / 128.0;
                            errors[k] =
                                0.008 * (if phase < 0.5 { phase } else { 1.0 - phase }) - 0.002;
                            k += 1;
                        }
                        errors
                    }),
                )),
            ];
            const COUNT: usize =
                INPUTS.len() * WINDINGS.len() * CALIBRATIONS.len() * CORRECTIONS.len();

            /// The settings of combination `n`.
            pub(super) const fn settings(n: usize) -> TrackerSettings<T> {
                let (input, winding) = (n % INPUTS.len(), n / INPUTS.len() % WINDINGS.len());
                let rest = n / (INPUTS.len() * WINDINGS.len());
                TrackerSettings {
                    input: INPUTS[input].0,
                    winding: WINDINGS[winding],
                    calibration: CALIBRATIONS[rest % CALIBRATIONS.len()],
                    correction: CORRECTIONS[rest / CALIBRATIONS.len()],
                }
            }

            /// Every combination's tracker, built in constant evaluation.
            static TRACKERS: [Tracker<T, Gains<T, 3>>; COUNT] = {
                let gains = ok(Gains::<T, 3>::new_const(
                    [GAINS[0] as T, GAINS[1] as T, GAINS[2] as T],
                    SAMPLE_PERIOD_S as T,
                ));
                let first = Tracker::new(ok(TrackerFrontEnd::<T>::new_const(settings(0))), gains);
                let mut trackers = [first; COUNT];
                let mut n = 1;
                while n < COUNT {
                    trackers[n] =
                        Tracker::new(ok(TrackerFrontEnd::<T>::new_const(settings(n))), gains);
                    n += 1;
                }
                trackers
            };

            #[test]
            fn $test() {
                assert_eq!(COUNT, 108);
                for (n, tracker) in TRACKERS.iter().enumerate() {
                    let s = settings(n);
                    let case = Case {
                        counts: INPUTS[n % INPUTS.len()].1,
                        imperfect: matches!(s.calibration, CalibrationStage::Stored(_)),
                        amplitude: AMPLITUDE,
                    };
                    let error_at = |angle: f64| match s.correction {
                        CorrectionStage::None => 0.0,
                        CorrectionStage::Harmonics(h) => f64::from(h.error_at(angle as T)),
                        CorrectionStage::Table(t) => f64::from(t.error_at(angle as T)),
                    };
                    let mut state = TrackerState::new();
                    let mut worst: f64 = 0.0;
                    for k in 0..4000 {
                        let truth = wrap(SPEED_RAD_S * k as f64 * SAMPLE_PERIOD_S);
                        let (y_c, y_s) = signal(truth + error_at(truth), case);
                        let e = match case.counts {
                            Some((mid, per_unit)) => tracker.update(
                                &mut state,
                                (counts(y_c, mid, per_unit), counts(y_s, mid, per_unit)),
                            ),
                            None => tracker.update(&mut state, (y_c as T, y_s as T)),
                        };
                        if k >= 2000 {
                            assert!(
                                e.faults.is_empty(),
                                "combination {n} ({s:?}): {:?}",
                                e.faults
                            );
                            worst = worst.max(wrap(f64::from(e.angle) - truth).abs());
                        }
                    }
                    assert!(
                        worst < $tolerance_rad,
                        "combination {n} ({s:?}): {worst} rad"
                    );
                }
            }
        }
    };
}

/// `angle` wrapped to [-pi, pi).
fn wrap(angle: f64) -> f64 {
    let tau = 2.0 * core::f64::consts::PI;
    angle - tau * libm::floor((angle + core::f64::consts::PI) / tau)
}

/// The sensor's pair at its angle `reading` (the truth plus its angle error), in units of
/// the ADC's full scale: with the stored calibration's imperfections when the case has them.
fn signal(reading: f64, case: Case) -> (f64, f64) {
    let (o_c, o_s, a_c, a_s, phi) = if case.imperfect {
        SENSOR
    } else {
        (0.0, 0.0, 1.0, 1.0, 0.0)
    };
    (
        o_c + case.amplitude * a_c * libm::cos(reading),
        o_s + case.amplitude * a_s * libm::sin(reading + phi),
    )
}

/// `value` (units) as the ADC's code, rounded.
fn counts(value: f64, mid_scale: i32, counts_per_unit: f64) -> i32 {
    mid_scale + libm::round(value * counts_per_unit) as i32
}

float_combinations!(
    f32,
    every_f32_combination_built_in_const_context_tracks,
    1.5e-3
);
float_combinations!(
    f64,
    every_f64_combination_built_in_const_context_tracks,
    1.5e-3
);

/// The fixed-point combinations: inputs in 16-bit samples (unchecked, stated, measured) and
/// counts of two ADCs; calibration none or stored; correction none or the table.
mod fixed {
    use super::*;

    const INPUTS: [InputCase<AdcCounts, i16>; 5] = [
        (
            Input::Units {
                rails: Rails::Unchecked,
            },
            None,
        ),
        (
            Input::Units {
                rails: Rails::Stated {
                    min: -32768,
                    max: 32767,
                },
            },
            None,
        ),
        (
            Input::Units {
                rails: Rails::Measured,
            },
            None,
        ),
        (
            Input::Counts {
                adc: ok(AdcCounts::offset_binary(12)),
                rails: Rails::Stated { min: 0, max: 4095 },
            },
            Some((2048, 2048.0)),
        ),
        (
            Input::Counts {
                adc: ok(AdcCounts::twos_complement(16)),
                rails: Rails::Measured,
            },
            Some((0, 32768.0)),
        ),
    ];
    /// The stored calibration in the 16-bit samples' counts (full scale 32768).
    const LEARNED: SensorCalibration<f64> = ok(SensorCalibration::<f64>::new_const(
        SENSOR.0 * 32768.0,
        SENSOR.1 * 32768.0,
        SENSOR.2,
        SENSOR.3,
        SENSOR.4,
    ));
    const CALIBRATIONS: [FixedCalibrationStage; 2] =
        [None, Some(ok(FixedCalibration::new_const(&LEARNED)))];
    const CORRECTIONS: [FixedCorrectionStage; 2] = [
        None,
        Some(ok(FixedAngleCorrectionTable::new({
            // A saw of +-4 mrad (131 in Q15 rad), two teeth per turn.
            let mut errors = [0; TRACKER_TABLE_LENGTH];
            let mut k = 0;
            while k < TRACKER_TABLE_LENGTH {
                let phase = (k % 128) as i32;
                errors[k] = (if phase < 64 { phase } else { 128 - phase } * 4 - 66) as i16;
                k += 1;
            }
            errors
        }))),
    ];
    const COUNT: usize = INPUTS.len() * CALIBRATIONS.len() * CORRECTIONS.len();
    const FIXED_GAINS: crate::fixed::FixedConstants<3> = crate::fixed::FixedConstants {
        multiplier: [215_733_201, 17_225_845, 1_903_920_691],
        acceleration_shift: 3,
    };

    pub(super) const fn settings(n: usize) -> TrackerSettings<i16> {
        let rest = n / INPUTS.len();
        TrackerSettings {
            input: INPUTS[n % INPUTS.len()].0,
            winding: (),
            calibration: CALIBRATIONS[rest % CALIBRATIONS.len()],
            correction: CORRECTIONS[rest / CALIBRATIONS.len()],
        }
    }

    static TRACKERS: [Tracker<i16, FixedGains<3>>; COUNT] = {
        let gains = ok(FixedGains::from_constants(FIXED_GAINS, SAMPLE_PERIOD_S));
        let first = Tracker::new(ok(TrackerFrontEnd::<i16>::new_const(settings(0))), gains);
        let mut trackers = [first; COUNT];
        let mut n = 1;
        while n < COUNT {
            trackers[n] = Tracker::new(ok(TrackerFrontEnd::<i16>::new_const(settings(n))), gains);
            n += 1;
        }
        trackers
    };

    #[test]
    fn every_fixed_point_combination_built_in_const_context_tracks() {
        assert_eq!(COUNT, 20);
        for (n, tracker) in TRACKERS.iter().enumerate() {
            let s = settings(n);
            let case = Case {
                counts: INPUTS[n % INPUTS.len()].1,
                imperfect: s.calibration.is_some(),
                // The fixed-point monitor's nominal amplitude, 2^14 of 2^15.
                amplitude: 0.5,
            };
            let error_at = |angle: f64| match s.correction {
                None => 0.0,
                Some(table) => {
                    let binary = libm::round(angle / (2.0 * core::f64::consts::PI) * 4294967296.0)
                        as i64 as i32;
                    f64::from(table.error_at(binary)) / 32768.0
                }
            };
            let mut state = TrackerState::new();
            let mut worst: f64 = 0.0;
            for k in 0..4000 {
                let truth = wrap(SPEED_RAD_S * k as f64 * SAMPLE_PERIOD_S);
                let (y_c, y_s) = signal(truth + error_at(truth), case);
                let e = match case.counts {
                    Some((mid, per_unit)) => tracker.update(
                        &mut state,
                        (counts(y_c, mid, per_unit), counts(y_s, mid, per_unit)),
                    ),
                    None => tracker.update(
                        &mut state,
                        (
                            counts(y_c, 0, 32768.0) as i16,
                            counts(y_s, 0, 32768.0) as i16,
                        ),
                    ),
                };
                if k >= 2000 {
                    assert!(
                        e.faults.is_empty(),
                        "combination {n} ({s:?}): {:?}",
                        e.faults
                    );
                    let angle = f64::from(e.angle) / 4294967296.0 * 2.0 * core::f64::consts::PI;
                    worst = worst.max(wrap(angle - truth).abs());
                }
            }
            assert!(worst < 1.5e-3, "combination {n} ({s:?}): {worst} rad");
        }
    }
}

/// The `const` constructors and the run-time ones (generic, in the layers below) are two
/// bodies of the same operations: they must give the same bits, for every float type.
macro_rules! same_bits {
    ($t:ident, $test:ident) => {
        #[test]
        fn $test() {
            type T = $t;
            for k in -40_i32..=40 {
                let phi = k as T * 0.019; // beyond pi/4 at the ends: refused by both
                let offset = k as T * 0.013;
                assert_eq!(
                    SensorCalibration::<T>::new_const(offset, -offset, 1.0, 1.0 + phi.abs(), phi),
                    SensorCalibration::<T>::new(offset, -offset, 1.0, 1.0 + phi.abs(), phi),
                    "phi {phi}"
                );
                let errors: [T; 16] = core::array::from_fn(|j| (j as T - 7.5) * k as T * 4e-4);
                assert_eq!(
                    AngleCorrectionTable::<T, 16>::new_const(errors),
                    AngleCorrectionTable::<T, 16>::new(errors),
                    "k {k}"
                );
                let mut a = [0.0; 8];
                a[(k.unsigned_abs() % 8) as usize] = k as T * 7e-3;
                assert_eq!(
                    AngleCorrection::<T>::new_const(a, a),
                    AngleCorrection::<T>::new(a, a)
                );
                assert_eq!(
                    WindingCheck::<T>::new_const(k as T),
                    WindingCheck::<T>::new(k as T)
                );
                let counts = 1.0 + (k + 40) as T * 37.5;
                assert_eq!(
                    AdcScaling::<T>::new_const(k * 97, counts),
                    AdcScaling::<T>::new(k * 97, counts)
                );
            }
            for bits in 0..34 {
                assert_eq!(
                    AdcScaling::<T>::offset_binary_const(bits),
                    AdcScaling::<T>::offset_binary(bits)
                );
                assert_eq!(
                    AdcScaling::<T>::twos_complement_const(bits),
                    AdcScaling::<T>::twos_complement(bits)
                );
            }
            for n in 0..108 {
                let s = $t::settings(n);
                assert_eq!(
                    TrackerFrontEnd::<T>::new_const(s),
                    TrackerFrontEnd::<T>::new(s),
                    "{n}"
                );
                let counts = TrackerSettings::<T> {
                    input: Input::Counts {
                        adc: AdcScaling::<T>::offset_binary(12).unwrap(),
                        rails: Rails::Stated {
                            min: n as i32 * 40,
                            max: 4095 - n as i32 * 40,
                        },
                    },
                    ..s
                };
                assert_eq!(
                    TrackerFrontEnd::<T>::new_const(counts),
                    TrackerFrontEnd::<T>::new(counts),
                    "{n}"
                );
            }
        }
    };
}

same_bits!(
    f32,
    the_f32_const_and_run_time_constructors_give_the_same_bits
);
same_bits!(
    f64,
    the_f64_const_and_run_time_constructors_give_the_same_bits
);

#[test]
fn the_fixed_point_const_and_run_time_front_ends_are_the_same() {
    for n in 0..20 {
        let s = fixed::settings(n);
        assert_eq!(
            TrackerFrontEnd::<i16>::new_const(s),
            TrackerFrontEnd::<i16>::new(s),
            "{n}"
        );
        for (min, max) in [
            (0, 4095),
            (4095, 0),
            (-70_000, 70_000),
            (2048, 2049),
            (5, 5),
        ] {
            let counts = TrackerSettings::<i16> {
                input: Input::Counts {
                    adc: AdcCounts::offset_binary(12).unwrap(),
                    rails: Rails::Stated { min, max },
                },
                ..s
            };
            assert_eq!(
                TrackerFrontEnd::<i16>::new_const(counts),
                TrackerFrontEnd::<i16>::new(counts),
                "{n} {min} {max}"
            );
        }
    }
}
