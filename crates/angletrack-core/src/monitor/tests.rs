//! The diagnostics (`docs/theory.md §10`): re-lock after a false lock, the flags and their
//! latch, and the checks of the thresholds.

extern crate std;

use crate::test_support::{TS, designs, n, settling_samples, wrap};
use crate::*;

/// The designs' gains with the default diagnostics; under Miri, whose loops are 10 times
/// faster in samples, with a 4 times faster filter so that the filter stays much faster
/// than the loop, as it is by default.
fn with_default_monitor<const N: usize>(gains: Gains<f64, N>) -> Gains<f64, N> {
    let filter_factor = if cfg!(miri) { 0.25 } else { 0.0625 };
    gains
        .with_fault_thresholds(FaultThresholds {
            filter_factor,
            ..FaultThresholds::default()
        })
        .unwrap()
}

/// Samples until the observer is locked (error below 2 % of pi, and staying so) on a shaft
/// turning at `speed` (rad/s) from `theta0`, after starting from `state`.
fn samples_to_lock<const N: usize>(
    gains: &Gains<f64, N>,
    mut state: ObserverState<f64, N>,
    theta0: f64,
    speed: f64,
    samples: usize,
) -> usize {
    let mut last_outside = 0;
    for k in 1..samples {
        let theta = theta0 + speed * k as f64 * TS;
        let e = gains.update(&mut state, theta.cos(), theta.sin());
        assert!(e.angle.is_finite() && e.speed.is_finite());
        if wrap(theta - e.angle).abs() > 0.02 * core::f64::consts::PI {
            last_outside = k;
        }
    }
    last_outside
}

#[test]
fn every_observer_relocks_within_its_settling_time_from_179_9_degrees_off() {
    let (o2, o3, ok) = designs();
    fn check<const N: usize>(gains: Gains<f64, N>, name: &str) {
        let gains = with_default_monitor(gains);
        let settling = settling_samples(&gains);
        let filter = 1.0 / gains.fault_thresholds().filter_factor;
        let off = 179.9f64.to_radians();
        let state = ObserverState::at(1.0 - off, 50.0, 0.0, TS).unwrap();
        let lock = samples_to_lock(&gains, state, 1.0, 50.0, 4 * settling);
        assert!(
            lock < settling,
            "{name}: locked after {lock} samples, settling time {settling}"
        );
        assert!(
            settling as f64 > 2.0 * filter,
            "{name}: settling {settling} vs filter {filter}"
        );
    }
    check(o2, "2nd order");
    check(o3, "3rd order");
    check(ok, "Kalman");
}

#[test]
fn every_observer_relocks_within_its_settling_time_after_a_180_degree_jump() {
    let (o2, o3, ok) = designs();
    fn check<const N: usize>(gains: Gains<f64, N>, name: &str) {
        let gains = with_default_monitor(gains);
        let settling = settling_samples(&gains);
        let speed = 80.0;
        let mut state = ObserverState::at(0.3, speed, 0.0, TS).unwrap();
        let warm_up = n(2000);
        for k in 1..warm_up {
            let theta = 0.3 + speed * k as f64 * TS;
            gains.update(&mut state, theta.cos(), theta.sin());
        }
        state.clear_faults();
        // The shaft angle jumps by 180 degrees (a resolver wiring swap, a counting slip).
        let theta0 = 0.3 + speed * warm_up as f64 * TS + core::f64::consts::PI - speed * TS;
        let lock = samples_to_lock(&gains, state, theta0, speed, 4 * settling);
        assert!(
            lock < settling,
            "{name}: locked after {lock} samples, settling time {settling}"
        );
        let mut flagged = state;
        let theta = theta0 + speed * TS;
        for _ in 0..settling {
            gains.update(&mut flagged, theta.cos(), theta.sin());
        }
        assert!(
            flagged.latched_faults().contains(Faults::FALSE_LOCK),
            "{name}: false lock flagged"
        );
    }
    check(o2, "2nd order");
    check(o3, "3rd order");
    check(ok, "Kalman");
}

#[test]
fn exactly_180_degrees_off_the_bare_loop_lingers_and_the_detector_does_not() {
    // At 180 degrees off eps = 0: the bare loop leaves this unstable equilibrium only as
    // fast as rounding errors grow. The false-lock detector re-acquires at once.
    let (_, _, ok) = designs();
    let bare = ok
        .with_fault_thresholds(FaultThresholds::disabled())
        .unwrap();
    let settling = settling_samples(&ok);
    let start = ObserverState::at(-1.0 + core::f64::consts::PI, 0.0, 0.0, TS).unwrap();
    let bare_lock = samples_to_lock(&bare, start, -1.0, 0.0, 20 * settling);
    let lock = samples_to_lock(&ok, start, -1.0, 0.0, 20 * settling);
    assert!(lock < settling / 4, "detector: {lock} samples");
    assert!(
        bare_lock > settling,
        "bare loop: {bare_lock} samples, settling {settling}"
    );
}

#[test]
fn diagnostics_flag_loss_and_degradation_of_signal_and_latch_them() {
    let (_, _, ok) = designs();
    // Started at the shaft's speed: from rest, the pull-in to 100 rad/s peaks at a phase
    // error of 5.9 degrees, which the window's mean rightly flags as loss of tracking.
    let mut state = ObserverState::at(0.0, 0.01 / TS, 0.0, TS).unwrap();
    let mut k = 0usize;
    let runs = if cfg!(miri) { 150 } else { 500 };
    let mut run = |state: &mut ObserverState<f64, 3>, amplitude: f64, n: usize| {
        let mut last = Faults::NONE;
        for _ in 0..n {
            let theta = 0.01 * k as f64; // 100 rad/s
            k += 1;
            last = ok
                .update(state, amplitude * theta.cos(), amplitude * theta.sin())
                .faults;
        }
        last
    };
    assert_eq!(run(&mut state, 1.0, runs), Faults::NONE);
    assert!(
        state.latched_faults().is_empty(),
        "{}",
        state.latched_faults()
    );
    let lost = run(&mut state, 0.1, runs);
    assert!(
        lost.contains(Faults::LOSS_OF_SIGNAL | Faults::DEGRADATION_OF_SIGNAL),
        "{lost}"
    );
    assert_eq!(run(&mut state, 1.0, runs), Faults::NONE);
    assert!(
        state.latched_faults().contains(Faults::LOSS_OF_SIGNAL),
        "latched until cleared"
    );
    assert!(state.clear_faults().contains(Faults::LOSS_OF_SIGNAL));
    assert!(state.latched_faults().is_empty());
    let high = run(&mut state, 2.0, runs);
    assert_eq!(high, Faults::DEGRADATION_OF_SIGNAL);
    // Above the input bound (4 by default): rejected; the monitor's flags of its last
    // window hold over rejected samples (they feed no window).
    assert_eq!(
        run(&mut state, 5.0, 10),
        Faults::BAD_SAMPLE | Faults::DEGRADATION_OF_SIGNAL
    );
    let text = std::format!("{}", state.latched_faults());
    assert_eq!(text, "degradation of signal, bad sample");
}

#[test]
fn diagnostics_flag_loss_of_tracking_on_a_speed_the_loop_cannot_follow() {
    let (o2, _, _) = designs();
    let mut state = ObserverState::new();
    // A speed step from 0 to 2000 rad/s: far beyond the 50 Hz loop's pull-in.
    let mut flagged = false;
    for k in 0..n(3000) {
        let theta = 2000.0 * k as f64 * TS;
        flagged |= o2
            .update(&mut state, theta.cos(), theta.sin())
            .faults
            .contains(Faults::LOSS_OF_TRACKING);
    }
    assert!(flagged);
    // The speed check alone: over pi/2 rad per sample, seen at the first used sample (the
    // monitor's first window is that sample alone).
    let mut fast = ObserverState::at(0.0, 0.6 * core::f64::consts::PI / TS, 0.0, TS).unwrap();
    let theta = 0.6 * core::f64::consts::PI;
    let e = o2.update(&mut fast, theta.cos(), theta.sin());
    assert!(e.faults.contains(Faults::LOSS_OF_TRACKING), "{}", e.faults);
}

#[test]
fn fault_thresholds_are_checked_naming_the_parameter() {
    let (_, _, ok) = designs();
    let base = FaultThresholds::<f64>::default();
    let cases = [
        (
            FaultThresholds {
                nominal_amplitude: f64::NAN,
                ..base
            },
            Parameter::NominalAmplitude,
        ),
        (
            FaultThresholds {
                loss_of_signal: 0.6,
                ..base
            },
            Parameter::LossOfSignalThreshold,
        ),
        (
            FaultThresholds {
                degradation_high: 0.9,
                ..base
            },
            Parameter::DegradationHighThreshold,
        ),
        (
            FaultThresholds {
                max_input_amplitude: 1.2,
                ..base
            },
            Parameter::MaxInputAmplitude,
        ),
        (
            FaultThresholds {
                max_input_amplitude: 1e300,
                ..base
            },
            Parameter::MaxInputAmplitude,
        ),
        (
            FaultThresholds {
                filter_factor: 0.0,
                ..base
            },
            Parameter::FilterFactor,
        ),
        (
            FaultThresholds {
                max_speed: Some(-1.0),
                ..base
            },
            Parameter::MaxSpeed,
        ),
        (
            FaultThresholds {
                false_lock: 1.0,
                ..base
            },
            Parameter::FalseLockThreshold,
        ),
        (
            FaultThresholds {
                loss_of_tracking: f64::INFINITY,
                ..base
            },
            Parameter::LossOfTrackingThreshold,
        ),
    ];
    for (thresholds, parameter) in cases {
        assert_eq!(
            ok.with_fault_thresholds(thresholds)
                .unwrap_err()
                .parameter(),
            parameter
        );
    }
    assert!(
        ok.with_fault_thresholds(FaultThresholds::for_amplitude(3.3))
            .is_ok()
    );
}
