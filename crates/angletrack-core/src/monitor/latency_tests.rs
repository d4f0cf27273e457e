//! The monitor's fault-detection latency (`docs/theory.md §10`): each fault, injected at
//! every position within the monitor's window, is flagged within `2 W - 1` used samples
//! (`W` = 16 by default), and a rejected sample at once.

extern crate std;

use crate::test_support::TS;
use crate::*;

/// The default window (used samples) and the latency bound it gives.
const WINDOW: usize = 16;
const BOUND: usize = 2 * WINDOW - 1;

/// The Kalman ATO's gains as `angletrack design` gives them for 10 kHz, fixed per sample
/// (not designed for `TS`, which Miri changes), with the default diagnostics.
fn kalman() -> Gains<f64, 3> {
    Gains::new([0.06, 0.0019, 3e-5], TS).unwrap()
}

/// Shaft speed of the runs (rad per sample): 0.01 (100 rad/s at 10 kHz).
const STEP_RAD: f64 = 0.01;

/// Runs the Kalman ATO with default diagnostics on a healthy shaft for `warm_up` samples
/// (no flag may be raised), then on the faulty signal `fault(k)` (`k` counting from the
/// fault's first sample, `theta` the true angle) until `flag` is raised; returns the
/// number of samples from the fault's first sample to the one whose estimate carries
/// `flag` (0: that sample itself).
fn samples_to_flag(
    warm_up: usize,
    flag: Faults,
    fault: impl Fn(usize, f64) -> (f64, f64),
) -> usize {
    let gains = kalman();
    let mut state = ObserverState::at(0.0, STEP_RAD / TS, 0.0, TS).unwrap();
    let healthy = |theta: f64| (theta.cos(), theta.sin());
    for k in 1..=warm_up {
        let (c, s) = healthy(STEP_RAD * k as f64);
        let e = gains.update(&mut state, c, s);
        assert_eq!(e.faults, Faults::NONE, "healthy sample {k}");
    }
    for k in 0..10 * WINDOW {
        let theta = STEP_RAD * (warm_up + 1 + k) as f64;
        let (c, s) = fault(k, theta);
        if gains.update(&mut state, c, s).faults.contains(flag) {
            assert!(state.latched_faults().contains(flag));
            return k;
        }
    }
    panic!("{flag} not flagged within {} samples", 10 * WINDOW);
}

/// `samples_to_flag` for the fault starting at each position of the window (warm-ups of
/// 4 W to 5 W - 1 samples): the largest latency, checked against the bound.
fn worst_latency(flag: Faults, fault: impl Fn(usize, f64) -> (f64, f64)) -> usize {
    let worst = (0..WINDOW)
        .map(|offset| samples_to_flag(4 * WINDOW + offset, flag, &fault))
        .max()
        .unwrap();
    assert!(
        worst < BOUND,
        "{flag}: flagged {worst} samples after it began"
    );
    worst
}

#[test]
fn loss_of_signal_is_flagged_within_two_windows() {
    // The sensor disconnected: the signal drops to 2 % of its amplitude (noise left).
    let worst = worst_latency(Faults::LOSS_OF_SIGNAL, |_, theta| {
        (0.02 * theta.cos(), 0.02 * theta.sin())
    });
    // The worst case: a window that began one sample before the fault is not enough.
    assert!(worst >= WINDOW, "{worst}");
}

#[test]
fn degradation_of_signal_is_flagged_within_two_windows_both_ways() {
    for amplitude in [0.4, 1.7] {
        worst_latency(Faults::DEGRADATION_OF_SIGNAL, |_, theta| {
            (amplitude * theta.cos(), amplitude * theta.sin())
        });
    }
}

#[test]
fn loss_of_tracking_is_flagged_within_two_windows() {
    // The shaft angle slips by 60 degrees (a slipping coupling): the phase error starts
    // at sin 60 = 0.87 and takes the loop's settling time to fall below 0.1.
    let slip = 60f64.to_radians();
    worst_latency(Faults::LOSS_OF_TRACKING, |_, theta| {
        ((theta + slip).cos(), (theta + slip).sin())
    });
}

#[test]
fn over_speed_is_flagged_within_one_window() {
    // Speed above a quarter turn per sample, the loop tracking it: only the speed check
    // can see it, at the end of each window.
    let o2 = Gains::<f64, 2>::new([0.06, 0.001], TS).unwrap();
    let step = 0.6 * core::f64::consts::PI;
    for offset in 0..WINDOW {
        let mut state = ObserverState::at(0.0, STEP_RAD / TS, 0.0, TS).unwrap();
        for k in 1..=4 * WINDOW + offset {
            let theta = STEP_RAD * k as f64;
            o2.update(&mut state, theta.cos(), theta.sin());
        }
        assert!(state.latched_faults().is_empty());
        let (angle, turns) = (state.angle(), state.turns() as f64);
        let mut fast = ObserverState::at(angle, step / TS, 0.0, TS).unwrap();
        fast.monitor = state.monitor;
        let flagged = (1..=WINDOW).find(|&k| {
            let theta = angle + turns * core::f64::consts::TAU + step * k as f64;
            o2.update(&mut fast, theta.cos(), theta.sin())
                .faults
                .contains(Faults::LOSS_OF_TRACKING)
        });
        assert!(
            flagged.is_some_and(|k| k <= WINDOW),
            "offset {offset}: {flagged:?}"
        );
    }
}

#[test]
fn false_lock_is_flagged_within_two_windows() {
    // The true angle jumps by 180 degrees (a wiring swap, a counting slip): the loop sits
    // on its unstable equilibrium, eps = 0, until the detector sees it (and re-acquires,
    // which `monitor::tests` checks).
    let worst = worst_latency(Faults::FALSE_LOCK, |_, theta| {
        let theta = theta + core::f64::consts::PI;
        (theta.cos(), theta.sin())
    });
    assert!(worst >= WINDOW - 1, "{worst}");
}

#[test]
fn a_rejected_sample_is_flagged_at_once_and_only_for_itself() {
    let gains = kalman();
    let mut state = ObserverState::at(0.0, STEP_RAD / TS, 0.0, TS).unwrap();
    for k in 1..200usize {
        let theta = STEP_RAD * k as f64;
        let bad = k % 37 == 0;
        let c = if bad { f64::NAN } else { theta.cos() };
        let e = gains.update(&mut state, c, theta.sin());
        assert_eq!(
            e.faults,
            Faults::when(bad, Faults::BAD_SAMPLE),
            "sample {k}"
        );
        assert_eq!(gains.estimate(&state).faults, e.faults);
    }
    assert_eq!(state.latched_faults(), Faults::BAD_SAMPLE);
}

#[test]
fn the_window_is_the_power_of_two_of_the_filter_factor() {
    let gains = kalman();
    for (factor, window) in [
        (1.0, 1),
        (0.3, 2),
        (0.25, 4),
        (0.0625, 16),
        (0.05, 16),
        (1e-9, 4096),
    ] {
        let thresholds = FaultThresholds {
            filter_factor: factor,
            ..FaultThresholds::default()
        };
        let checked = gains.with_fault_thresholds(thresholds).unwrap().thresholds;
        assert_eq!(checked.window, window, "filter factor {factor}");
        assert_eq!(checked.window_inverse * window as f64, 1.0);
    }
}

#[test]
fn a_start_180_degrees_off_is_flagged_at_the_first_used_sample() {
    // A state started at a known angle that is wrong by 179 degrees: the first window is
    // the first used sample alone, which flags the false lock and re-acquires.
    let gains = kalman();
    let truth = 179f64.to_radians();
    let mut state = ObserverState::at(0.0, 0.0, 0.0, TS).unwrap();
    let e = gains.update(&mut state, truth.cos(), truth.sin());
    assert!(e.faults.contains(Faults::FALSE_LOCK), "{}", e.faults);
    assert!((e.angle - truth).abs() < 0.05, "re-acquired at {}", e.angle);
}
