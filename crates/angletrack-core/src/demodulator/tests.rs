use super::*;
use core::f64::consts::{PI, TAU};

const N: usize = 16;
const AMPLITUDE: f64 = 1800.0;

fn demodulator(delay_expected: f64) -> Demodulator<f64, N> {
    let mut settings = DemodulatorSettings::new(1e4, AMPLITUDE, 0.0, 4095.0);
    settings.expected_delay_rad = delay_expected;
    Demodulator::new(settings).unwrap()
}

/// Raw samples of both windings at ADC sample `j` (160 kHz) for a shaft turning at `speed`
/// (rad/s) from `theta0`, carrier delay `delay`, offsets `(off_c, off_s)` around mid-scale.
fn raw(j: usize, theta0: f64, speed: f64, delay: f64, off: (f64, f64)) -> (f64, f64) {
    let t = j as f64 / 1.6e5;
    let theta = theta0 + speed * t;
    let carrier = AMPLITUDE * (TAU * (j % N) as f64 / N as f64 + delay).sin();
    (
        2048.0 + off.0 + theta.cos() * carrier,
        2048.0 + off.1 + theta.sin() * carrier,
    )
}

/// Runs `samples` ADC samples; returns every pair with its true angle at the window centre.
fn run(
    d: &Demodulator<f64, N>,
    state: &mut DemodulatorState<f64>,
    samples: usize,
    signal: impl Fn(usize) -> (f64, f64),
) -> std::vec::Vec<DemodulatedPair<f64>> {
    (0..samples)
        .filter_map(|j| {
            let (c, s) = signal(j);
            d.push(state, c, s)
        })
        .collect()
}

extern crate std;

#[test]
fn every_delay_is_measured_modulo_pi_and_resolved_near_the_expected_one() {
    for degrees in (0..360).step_by(30).chain([305]) {
        let delay = (degrees as f64).to_radians();
        // The user's coarse knowledge: 40 degrees off.
        let d = demodulator(delay + 0.7);
        let mut state = DemodulatorState::new();
        let pairs = run(&d, &mut state, 16 * 40, |j| {
            raw(j, 0.3, 300.0, delay, (0.0, 0.0))
        });
        assert!(state.is_delay_ready() && !pairs.is_empty());
        let error = (state.startup_delay_rad() - delay + PI).rem_euclid(TAU) - PI;
        assert!(error.abs() < 1e-4, "{degrees} deg: error {error}");
    }
}

#[test]
fn pairs_hold_at_the_window_centre_for_any_delay() {
    // At 300 rad/s a one-window demodulator would be off by up to 1.3 samples (2.4 mrad).
    for degrees in [0.0, 45.0, 100.0, 305.0] {
        let delay = f64::to_radians(degrees);
        let d = demodulator(delay);
        let mut state = DemodulatorState::new();
        let speed = 300.0;
        let pairs = run(&d, &mut state, 16 * 60, |j| {
            raw(j, 0.3, speed, delay, (37.0, -51.0))
        });
        for pair in &pairs {
            let theta = 0.3 + speed * d.window_centre_s(pair.window);
            let angle = pair.y_s.atan2(pair.y_c);
            let error = (angle - theta + PI).rem_euclid(TAU) - PI;
            assert!(
                error.abs() < 2e-5,
                "{degrees}: window {} error {error}",
                pair.window
            );
            let amplitude = pair.y_c.hypot(pair.y_s);
            assert!((amplitude - 1.0).abs() < 1e-4 && pair.faults.is_empty());
            assert!(pair.quadrature_c.abs() < 1e-4 && pair.quadrature_s.abs() < 1e-4);
        }
    }
}

#[test]
fn a_delay_off_by_pi_flips_the_angle_by_half_a_turn() {
    let d = demodulator(0.0);
    let mut state = DemodulatorState::new();
    let delay = 2.5; // 143 degrees: resolved as -37 degrees
    let pairs = run(&d, &mut state, 16 * 30, |j| {
        raw(j, 0.3, 0.0, delay, (0.0, 0.0))
    });
    let angle = pairs[5].y_s.atan2(pairs[5].y_c);
    assert!(((angle - 0.3).rem_euclid(TAU) - PI).abs() < 1e-5);
}

#[test]
fn the_delay_is_tracked_and_its_drift_flagged() {
    let d = demodulator(0.0);
    let mut state = DemodulatorState::new();
    // The delay drifts from 0.2 rad by 1 rad over the run.
    let total = 16 * 2000;
    let delay = |j: usize| 0.2 + j as f64 / total as f64;
    let pairs = run(&d, &mut state, total, |j| {
        raw(j, 0.3, 50.0, delay(j), (0.0, 0.0))
    });
    // The tracking loop's time constant is 1 / factor = 100 periods: it lags a ramp of
    // 1/2000 rad per period by 0.05 rad.
    let tracked = state.carrier_delay_rad();
    assert!((tracked - 1.15).abs() < 0.01, "tracked {tracked}");
    assert!(
        pairs
            .last()
            .unwrap()
            .faults
            .contains(FrontEndFaults::PHASE_DRIFT)
    );
    assert!(!pairs[100].faults.contains(FrontEndFaults::PHASE_DRIFT));
    assert!(state.latched_faults().contains(FrontEndFaults::PHASE_DRIFT));
}

#[test]
fn clipping_loss_of_excitation_and_nan_are_flagged() {
    let d = demodulator(0.0);
    let mut state = DemodulatorState::new();
    run(&d, &mut state, 16 * 20, |j| {
        raw(j, 0.3, 0.0, 0.0, (0.0, 0.0))
    });
    // A sample at the top rail.
    let pairs = run(&d, &mut state, 16 * 4, |j| {
        if j == 20 {
            (4095.0, 2048.0)
        } else {
            raw(j, 0.3, 0.0, 0.0, (0.0, 0.0))
        }
    });
    assert!(
        pairs
            .iter()
            .any(|p| p.faults.contains(FrontEndFaults::CLIPPING))
    );
    assert!(pairs.last().unwrap().faults.is_empty());
    // The excitation stops.
    let pairs = run(&d, &mut state, 16 * 3, |_| (2048.0, 2048.0));
    assert!(
        pairs
            .last()
            .unwrap()
            .faults
            .contains(FrontEndFaults::LOSS_OF_EXCITATION)
    );
    // A NaN sample: flagged, and the delay is unharmed.
    let pairs = run(&d, &mut state, 16 * 3, |j| {
        if j == 3 {
            (f64::NAN, 2048.0)
        } else {
            raw(j, 0.3, 0.0, 0.0, (0.0, 0.0))
        }
    });
    let both = FrontEndFaults::CLIPPING | FrontEndFaults::LOSS_OF_EXCITATION;
    assert!(pairs[0].faults.contains(both) && pairs[1].faults.contains(both));
    assert!(pairs[0].y_c.is_nan() && pairs[2].faults.is_empty());
    assert!(state.carrier_delay_rad().abs() < 1e-3);
    assert!(
        state
            .clear_faults()
            .contains(FrontEndFaults::LOSS_OF_EXCITATION)
    );
    assert!(state.latched_faults().is_empty());
}

#[test]
fn refuses_each_bad_setting_by_name() {
    let good = DemodulatorSettings::<f32>::new(1e4, 1800.0, 0.0, 4095.0);
    let refused =
        |s: DemodulatorSettings<f32>| Demodulator::<f32, 16>::new(s).unwrap_err().parameter();
    assert_eq!(
        refused(DemodulatorSettings {
            carrier_hz: 0.0,
            ..good
        }),
        Parameter::CarrierFrequency
    );
    assert_eq!(
        refused(DemodulatorSettings {
            carrier_amplitude_counts: f32::NAN,
            ..good
        }),
        Parameter::CarrierAmplitude
    );
    assert_eq!(
        refused(DemodulatorSettings {
            adc_max_code: 0.0,
            ..good
        }),
        Parameter::AdcRange
    );
    assert_eq!(
        refused(DemodulatorSettings {
            clip_margin_counts: 3000.0,
            ..good
        }),
        Parameter::AdcRange
    );
    assert_eq!(
        refused(DemodulatorSettings {
            loss_of_excitation: 1.0,
            ..good
        }),
        Parameter::LossOfExcitationThreshold
    );
    assert_eq!(
        refused(DemodulatorSettings {
            phase_drift_bound_rad: 4.0,
            ..good
        }),
        Parameter::PhaseDriftBound
    );
    assert_eq!(
        refused(DemodulatorSettings {
            expected_delay_rad: f32::INFINITY,
            ..good
        }),
        Parameter::ExpectedDelay
    );
    assert_eq!(
        refused(DemodulatorSettings {
            delay_tracking_factor: -0.1,
            ..good
        }),
        Parameter::DelayTrackingFactor
    );
    assert_eq!(
        refused(DemodulatorSettings {
            startup_periods: 0,
            ..good
        }),
        Parameter::StartupPeriods
    );
    assert_eq!(
        Demodulator::<f32, 6>::new(good).unwrap_err().parameter(),
        Parameter::SamplesPerPeriod
    );
    let d = Demodulator::<f32, 16>::new(good).unwrap();
    let gains = crate::Gains::<f32, 2>::new([0.05, 0.0012], 2e-4).unwrap();
    assert_eq!(
        d.check_gains(&gains).unwrap_err().parameter(),
        Parameter::SamplePeriod
    );
}

#[test]
fn a_block_gives_the_pairs_of_single_pushes_whatever_its_cuts() {
    let d = demodulator(0.3);
    let signal: std::vec::Vec<(f64, f64)> = (0..16 * 40 + 7)
        .map(|j| raw(j, 0.3, 200.0, 0.3, (5.0, -3.0)))
        .collect();
    let mut single = DemodulatorState::new();
    let expected: std::vec::Vec<_> = signal
        .iter()
        .filter_map(|&(c, s)| d.push(&mut single, c, s))
        .collect();
    for cut in [1, 3, 4, 5, 16, 17, 100, 1000] {
        let mut state = DemodulatorState::new();
        let mut pairs = std::vec::Vec::new();
        for chunk in signal.chunks(cut) {
            let (c, s): (std::vec::Vec<f64>, std::vec::Vec<f64>) = chunk.iter().copied().unzip();
            assert_eq!(
                d.push_block(&mut state, &c, &s, |p| pairs.push(p)),
                chunk.len()
            );
        }
        assert_eq!(pairs, expected, "blocks of {cut}");
        assert_eq!(state, single);
    }
}
