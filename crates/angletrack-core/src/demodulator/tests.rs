//! The demodulator against windings synthesised here, sample by sample, from the resolver's
//! equations (not the `angletrack` crate's simulator): carrier frequency errors, sample
//! ratios that are not whole, delays of any size and drifting, a recorded excitation, weak
//! and lost excitation, clipping, and the fixed point against `f32`.

extern crate std;
use std::vec::Vec;

use super::*;
use crate::FrontEndFaults;
use core::f64::consts::{PI, TAU};

const AMPLITUDE: f64 = 1800.0;

/// A bench: the true carrier and its delay, the ADC rate, the shaft's motion.
#[derive(Clone, Copy)]
struct Bench {
    carrier_hz: f64,
    adc_hz: f64,
    /// The carrier's phase (rad) at the first sample, and its drift (rad/s).
    delay: f64,
    delay_drift: f64,
    theta0: f64,
    speed: f64,
    offsets: (f64, f64),
    /// The carrier's amplitude relative to nominal.
    level: f64,
    /// Uniform noise of this peak (counts).
    noise: f64,
}

impl Bench {
    fn new(carrier_hz: f64, adc_hz: f64) -> Self {
        Bench {
            carrier_hz,
            adc_hz,
            delay: 0.0,
            delay_drift: 0.0,
            theta0: 0.3,
            speed: 300.0,
            offsets: (37.0, -51.0),
            level: 1.0,
            noise: 0.0,
        }
    }

    fn theta(&self, t: f64) -> f64 {
        self.theta0 + self.speed * t
    }

    /// Samples `j` of the windings and the excitation (the excitation leads the windings by
    /// the resolver's own delay, taken as 0 here: the delay is the capture's, after a
    /// carrier of phase 0 at the first sample).
    fn sample(&self, j: usize, seed: &mut u64) -> (f64, f64, f64) {
        let t = j as f64 / self.adc_hz;
        let psi = TAU * self.carrier_hz * t - self.delay - self.delay_drift * t;
        let carrier = AMPLITUDE * self.level * psi.sin();
        let mut noise = || {
            *seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2.0 * self.noise
        };
        let theta = self.theta(t);
        (
            2048.0 + self.offsets.0 + theta.cos() * carrier + noise(),
            2048.0 + self.offsets.1 + theta.sin() * carrier + noise(),
            2048.0 + 1500.0 * psi.sin(),
        )
    }
}

fn settings(carrier_hz: f64, adc_hz: f64) -> DemodulatorSettings<f64> {
    DemodulatorSettings::new(carrier_hz, adc_hz, AMPLITUDE, 0.0, 4095.0)
}

/// The demodulator of a 10 kHz carrier at 160 kHz expecting the bench's delay plus
/// `offset_rad`.
fn expecting(bench: &Bench, offset_rad: f64) -> Demodulator<f64> {
    Demodulator::new(DemodulatorSettings {
        expected_delay_rad: bench.delay + offset_rad,
        ..settings(10e3, 160e3)
    })
    .unwrap()
}

/// Runs `samples` samples (with the excitation if `excitation`); every pair with its angle
/// error against the truth at its centre (rad, wrapped).
fn run(
    d: &Demodulator<f64>,
    state: &mut DemodulatorState<f64>,
    bench: &Bench,
    samples: usize,
    excitation: bool,
) -> Vec<(DemodulatedPair<f64>, f64)> {
    let mut seed = 1;
    let mut out = Vec::new();
    // The bench's time runs on from the samples the state has seen.
    let start = state.samples() as usize;
    for j in start..start + samples {
        let (c, s, e) = bench.sample(j, &mut seed);
        let pair = if excitation {
            d.push_with_excitation(state, c, s, e)
        } else {
            d.push(state, c, s)
        };
        if let Some(pair) = pair {
            let truth = bench.theta(d.centre_s(&pair));
            let error = (pair.y_s.atan2(pair.y_c) - truth + PI).rem_euclid(TAU) - PI;
            out.push((pair, error));
        }
    }
    out
}

/// The RMS and the largest magnitude of the errors after the first `skip` pairs.
fn rms_max(pairs: &[(DemodulatedPair<f64>, f64)], skip: usize) -> (f64, f64) {
    let errors: Vec<f64> = pairs.iter().skip(skip).map(|p| p.1).collect();
    assert!(errors.len() > 20, "{} pairs", errors.len());
    let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
    (rms, errors.iter().fold(0.0_f64, |m, e| m.max(e.abs())))
}

#[test]
fn a_carrier_half_a_percent_off_tracks_within_3_mrad() {
    let mut bench = Bench::new(10_050.0, 160e3);
    bench.delay = 305f64.to_radians();
    bench.noise = 2.0;
    let d = expecting(&bench, 0.0);
    let mut state = DemodulatorState::new();
    let pairs = run(&d, &mut state, &bench, 160 * 100, false);
    let (rms, max) = rms_max(&pairs, 10);
    assert!(rms < 3e-3 && max < 1e-2, "rms {rms} max {max}");
    let tracked = d.tracked_carrier_hz(&state);
    assert!((tracked - 10_050.0).abs() < 1.0, "tracked {tracked} Hz");
    assert!(pairs.iter().all(|p| p.0.faults.is_empty()));
}

#[test]
fn a_carrier_two_percent_off_either_way_tracks() {
    for carrier in [9_800.0, 10_200.0] {
        let bench = Bench::new(carrier, 160e3);
        let d = Demodulator::new(settings(10e3, 160e3)).unwrap();
        let mut state = DemodulatorState::new();
        let pairs = run(&d, &mut state, &bench, 160 * 100, false);
        let (rms, max) = rms_max(&pairs, 10);
        assert!(
            rms < 1e-3 && max < 3e-3,
            "{carrier} Hz: rms {rms} max {max}"
        );
        assert!((d.tracked_carrier_hz(&state) - carrier).abs() < 1.0);
    }
}

#[test]
fn a_carrier_beyond_the_error_allowed_is_flagged_on_every_pair() {
    // 5 % and 4 % off, beyond the 3 % allowed: the loop's step is held at its bound, and the
    // half turn chosen at the end of the start-up may be the wrong one (5 %: it is, here).
    for carrier in [10_500.0, 9_600.0, 10_400.0] {
        let mut bench = Bench::new(carrier, 160e3);
        bench.delay = 305f64.to_radians();
        let d = expecting(&bench, 0.0);
        let mut state = DemodulatorState::new();
        let pairs = run(&d, &mut state, &bench, 160 * 100, false);
        assert!(pairs.len() > 50);
        assert!(
            pairs
                .iter()
                .all(|p| p.0.faults.intersects(FrontEndFaults::PHASE_DRIFT)),
            "{carrier} Hz"
        );
        assert!(
            state
                .latched_faults()
                .intersects(FrontEndFaults::PHASE_DRIFT)
        );
    }
}

#[test]
fn any_sample_ratio_is_demodulated_without_bias_and_stamped_at_its_instant() {
    // 150 kHz / 10 kHz = 15, 48 kHz / 5 kHz = 9.6, 4.5, and the whole ratios 5 and 6 that
    // are not multiples of 4 (where the window's centroid is off by up to a quarter sample,
    // depending on the delay: 4.8 us, 18 mrad at this speed); offsets; 150 rev/s at 4 pole
    // pairs (3770 rad/s electrical), so that a time-stamp error of 0.27 us is 1 mrad.
    for (carrier, adc, bound) in [
        (10e3, 150e3, 2e-3),
        (5e3, 48e3, 2e-3),
        (10e3, 45e3, 4e-3),
        (10e3, 50e3, 4e-3),
        (10e3, 60e3, 4e-3),
    ] {
        for delay in [
            0.0,
            45f64.to_radians(),
            100f64.to_radians(),
            305f64.to_radians(),
        ] {
            let mut bench = Bench::new(carrier, adc);
            bench.delay = delay;
            bench.noise = 2.0;
            bench.speed = 3770.0;
            let d = Demodulator::new(DemodulatorSettings {
                expected_delay_rad: delay,
                ..settings(carrier, adc)
            })
            .unwrap();
            let mut state = DemodulatorState::new();
            let pairs = run(&d, &mut state, &bench, (adc * 0.01) as usize, false);
            let (rms, max) = rms_max(&pairs, 5);
            let mean = pairs.iter().skip(5).map(|p| p.1).sum::<f64>() / (pairs.len() - 5) as f64;
            assert!(
                rms < bound && mean.abs() < 1e-3,
                "{adc}/{carrier}, {delay}: rms {rms} max {max} mean {mean}"
            );
        }
    }
}

#[test]
fn a_delay_drifting_by_turns_is_tracked() {
    let mut bench = Bench::new(10e3, 160e3);
    // Two turns a second: 0.2 turns over the 0.1 s run.
    bench.delay_drift = 2.0 * TAU;
    let d = Demodulator::new(settings(10e3, 160e3)).unwrap();
    let mut state = DemodulatorState::new();
    let pairs = run(&d, &mut state, &bench, 16_000, false);
    let (rms, max) = rms_max(&pairs, 10);
    assert!(rms < 1e-3 && max < 3e-3, "rms {rms} max {max}");
    assert!(
        pairs
            .iter()
            .all(|p| !p.0.faults.contains(FrontEndFaults::PHASE_DRIFT))
    );
}

#[test]
fn without_excitation_the_expected_delay_resolves_the_half_turn_and_the_delay_is_exposed() {
    for degrees in [0.0, 60.0, 200.0, 305.0] {
        let mut bench = Bench::new(10_030.0, 160e3);
        bench.delay = f64::to_radians(degrees);
        // Expected 40 degrees off: resolved to the truth.
        let d = expecting(&bench, 0.7);
        let mut state = DemodulatorState::new();
        let pairs = run(&d, &mut state, &bench, 16_000, false);
        let (rms, _) = rms_max(&pairs, 5);
        assert!(rms < 2e-3, "{degrees}: rms {rms}");
        let error = (state.carrier_delay_rad() - bench.delay + PI).rem_euclid(TAU) - PI;
        std::println!("{degrees}: delay error {error}");
        assert!(error.abs() < 0.05, "{degrees}: delay error {error}");
        // Expected 180 degrees off: the angle is half a turn off, as the delay says.
        let d = expecting(&bench, PI);
        let mut state = DemodulatorState::new();
        let pairs = run(&d, &mut state, &bench, 16_000, false);
        assert!(pairs.iter().skip(5).all(|p| (p.1.abs() - PI).abs() < 0.01));
    }
}

#[test]
fn a_recorded_excitation_resolves_any_delay_without_a_half_turn_error() {
    for degrees in [200.0, 100.0, 305.0] {
        let mut bench = Bench::new(10e3, 150e3);
        bench.delay = f64::to_radians(degrees);
        // The expected delay (after the excitation) is 0, the default: the capture's delay
        // of 200 degrees is the excitation's too.
        let d = Demodulator::new(settings(10e3, 150e3)).unwrap();
        let mut state = DemodulatorState::new();
        let pairs = run(&d, &mut state, &bench, 15_000, true);
        let (rms, max) = rms_max(&pairs, 5);
        assert!(rms < 2e-3 && max < 5e-3, "{degrees}: rms {rms} max {max}");
        assert!(state.has_excitation() && state.carrier_delay_rad().abs() < 0.02);
    }
}

#[test]
fn weak_and_lost_excitation_clipping_and_nan_are_flagged() {
    let mut bench = Bench::new(10e3, 160e3);
    let d = Demodulator::new(settings(10e3, 160e3)).unwrap();
    let mut state = DemodulatorState::new();
    let pairs = run(&d, &mut state, &bench, 8000, false);
    assert!(pairs.iter().all(|p| p.0.faults.is_empty()));
    // At half amplitude: weak, not lost.
    bench.level = 0.5;
    let pairs = run(&d, &mut state, &bench, 1600, false);
    assert!(
        pairs
            .iter()
            .skip(2)
            .all(|p| p.0.faults == FrontEndFaults::WEAK_EXCITATION)
    );
    // At 0.8: nothing.
    bench.level = 0.8;
    let pairs = run(&d, &mut state, &bench, 1600, false);
    assert!(pairs.iter().skip(2).all(|p| p.0.faults.is_empty()));
    // Gone: lost (and weak).
    bench.level = 0.0;
    let pairs = run(&d, &mut state, &bench, 1600, false);
    let both = FrontEndFaults::LOSS_OF_EXCITATION | FrontEndFaults::WEAK_EXCITATION;
    assert!(pairs.iter().skip(2).all(|p| p.0.faults.contains(both)));
    // Back: the loop held its carrier, no fault.
    bench.level = 1.0;
    let pairs = run(&d, &mut state, &bench, 1600, false);
    assert!(
        pairs
            .iter()
            .skip(2)
            .all(|p| p.0.faults.is_empty() && p.1.abs() < 2e-3)
    );
    // A sample on the rail, and a NaN.
    let mut seed = 1;
    let mut clipped = FrontEndFaults::NONE;
    let start = state.samples() as usize;
    for j in start..start + 800 {
        let (c, s, _) = bench.sample(j, &mut seed);
        let c = match j - start {
            100 => 4095.0,
            400 => f64::NAN,
            _ => c,
        };
        if let Some(pair) = d.push(&mut state, c, s) {
            clipped |= pair.faults;
        }
    }
    assert!(clipped.contains(FrontEndFaults::CLIPPING | FrontEndFaults::LOSS_OF_EXCITATION));
    let pairs = run(&d, &mut state, &bench, 1600, false);
    assert!(
        pairs
            .iter()
            .skip(2)
            .all(|p| p.0.faults.is_empty() && p.1.abs() < 2e-3)
    );
    assert!(
        state
            .clear_faults()
            .contains(FrontEndFaults::WEAK_EXCITATION)
            && state.latched_faults().is_empty()
    );
}

#[test]
fn the_fixed_point_agrees_with_f32() {
    let mut bench = Bench::new(10_040.0, 150e3);
    bench.delay = 1.0;
    bench.noise = 1.0;
    let s32 = DemodulatorSettings::<f32>::new(10e3, 150e3, AMPLITUDE as f32, 0.0, 4095.0);
    let (d32, d16) = (
        Demodulator::<f32>::new(s32).unwrap(),
        Demodulator::<i16>::new(s32).unwrap(),
    );
    let (mut st32, mut st16) = (DemodulatorState::new(), DemodulatorState::new());
    let mut seed = 1;
    // Each pair's angle error against the truth at its centre, by window: the two loops
    // cut their segments one sample apart now and then, so the pairs are compared there.
    let (mut e32, mut e16) = (Vec::new(), Vec::new());
    let error = |y_c: f64, y_s: f64, centre: f64| {
        (y_s.atan2(y_c) - bench.theta(centre) + PI).rem_euclid(TAU) - PI
    };
    for j in 0..15_000 {
        let (c, s, _) = bench.sample(j, &mut seed);
        let (c, s) = (c.round(), s.round());
        if let Some(a) = d32.push(&mut st32, c as f32, s as f32) {
            e32.push((
                (a.window, a.first_sample, a.weight),
                error(f64::from(a.y_c), f64::from(a.y_s), d32.centre_s(&a)),
                f64::from(a.y_c).hypot(f64::from(a.y_s)),
            ));
        }
        if let Some(b) = d16.push(&mut st16, c as i16, s as i16) {
            let unit = f64::from(FIXED_PAIR_UNIT);
            let (y_c, y_s) = (f64::from(b.y_c) / unit, f64::from(b.y_s) / unit);
            e16.push((
                (b.window, b.first_sample, b.weight),
                error(y_c, y_s, d16.centre_s(&b)),
                y_c.hypot(y_s),
            ));
            assert!(b.faults.is_empty());
        }
    }
    assert_eq!(e32.len(), e16.len());
    let (mut worst, mut same) = ((0.0_f64, 0.0_f64), 0);
    for (a, b) in e32.iter().zip(&e16).skip(5) {
        // Both within the bounds of the tests above; where their windows are the same
        // samples, within the fixed point's resolution (2^-14 of the amplitude per
        // component, a Q10 table) of each other.
        assert!(
            a.0.0 == b.0.0 && a.1.abs() < 2e-3 && b.1.abs() < 2e-3,
            "{a:?} {b:?}"
        );
        if a.0 == b.0 {
            worst = (
                worst.0.max((a.1 - b.1).abs()),
                worst.1.max((a.2 - b.2).abs()),
            );
            same += 1;
        }
    }
    assert!(
        same > 500 && worst.0 < 2e-4 && worst.1 < 5e-3,
        "{same} of {} pairs, worst {worst:?}",
        e32.len()
    );
}

#[test]
fn a_block_gives_the_pairs_of_single_pushes_whatever_its_cuts() {
    let mut bench = Bench::new(10_020.0, 48e3);
    bench.delay = 0.3;
    let d = Demodulator::new(settings(10e3, 48e3)).unwrap();
    let mut seed = 3;
    let signal: Vec<(f64, f64, f64)> = (0..48 * 40 + 7)
        .map(|j| bench.sample(j, &mut seed))
        .collect();
    for excitation in [false, true] {
        let mut single = DemodulatorState::new();
        let expected: Vec<_> = signal
            .iter()
            .filter_map(|&(c, s, e)| {
                if excitation {
                    d.push_with_excitation(&mut single, c, s, e)
                } else {
                    d.push(&mut single, c, s)
                }
            })
            .collect();
        assert!(expected.len() > 10);
        for cut in [1, 3, 4, 5, 16, 17, 100, 1000] {
            let mut state = DemodulatorState::new();
            let mut pairs = Vec::new();
            for chunk in signal.chunks(cut) {
                let c: Vec<f64> = chunk.iter().map(|x| x.0).collect();
                let s: Vec<f64> = chunk.iter().map(|x| x.1).collect();
                let e: Vec<f64> = chunk.iter().map(|x| x.2).collect();
                let n = if excitation {
                    d.push_block_with_excitation(&mut state, &c, &s, &e, |p| pairs.push(p))
                } else {
                    d.push_block(&mut state, &c, &s, |p| pairs.push(p))
                };
                assert_eq!(n, chunk.len());
            }
            assert_eq!(pairs, expected, "blocks of {cut}");
            assert_eq!(state, single);
        }
    }
}

#[test]
fn refuses_each_bad_setting_by_name() {
    let good = DemodulatorSettings::<f32>::new(1e4, 1.6e5, 1800.0, 0.0, 4095.0);
    let refused = |s: DemodulatorSettings<f32>| Demodulator::<f32>::new(s).unwrap_err().parameter();
    let cases = [
        (
            DemodulatorSettings {
                carrier_hz: 0.0,
                ..good
            },
            Parameter::CarrierFrequency,
        ),
        (
            DemodulatorSettings {
                adc_rate_hz: 3.9e4,
                ..good
            },
            Parameter::AdcRate,
        ),
        (
            DemodulatorSettings {
                adc_rate_hz: f32::NAN,
                ..good
            },
            Parameter::AdcRate,
        ),
        (
            DemodulatorSettings {
                carrier_amplitude_counts: f32::NAN,
                ..good
            },
            Parameter::CarrierAmplitude,
        ),
        (
            DemodulatorSettings {
                adc_max_code: 0.0,
                ..good
            },
            Parameter::AdcRange,
        ),
        (
            DemodulatorSettings {
                clip_margin_counts: 3000.0,
                ..good
            },
            Parameter::AdcRange,
        ),
        (
            DemodulatorSettings {
                loss_of_excitation: 1.0,
                ..good
            },
            Parameter::LossOfExcitationThreshold,
        ),
        (
            DemodulatorSettings {
                weak_excitation: 0.2,
                ..good
            },
            Parameter::WeakExcitationThreshold,
        ),
        (
            DemodulatorSettings {
                phase_drift_bound_rad: 1.6,
                ..good
            },
            Parameter::PhaseDriftBound,
        ),
        (
            DemodulatorSettings {
                expected_delay_rad: f32::INFINITY,
                ..good
            },
            Parameter::ExpectedDelay,
        ),
        (
            DemodulatorSettings {
                carrier_loop_bandwidth: 0.0,
                ..good
            },
            Parameter::CarrierLoopBandwidth,
        ),
        (
            DemodulatorSettings {
                max_carrier_error: 0.5,
                ..good
            },
            Parameter::MaxCarrierError,
        ),
        (
            DemodulatorSettings {
                startup_periods: 0,
                ..good
            },
            Parameter::StartupPeriods,
        ),
    ];
    for (settings, parameter) in cases {
        assert_eq!(refused(settings), parameter);
    }
    // 65 samples per period: beyond what the fixed point's sums hold.
    let fast = DemodulatorSettings {
        adc_rate_hz: 6.5e5,
        ..good
    };
    assert_eq!(
        Demodulator::<i16>::new(fast).unwrap_err().parameter(),
        Parameter::AdcRate
    );
    assert!(Demodulator::<f32>::new(fast).is_ok());
    let d = Demodulator::<f32>::new(good).unwrap();
    let gains = crate::Gains::<f32, 2>::new([0.05, 0.0012], 2e-4).unwrap();
    assert_eq!(
        d.check_gains(&gains).unwrap_err().parameter(),
        Parameter::SamplePeriod
    );
}
