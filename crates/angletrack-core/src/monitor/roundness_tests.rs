//! The roundness check (`FaultThresholds::magnitude_tolerance`, `docs/guide/diagnostics.md`):
//! a window's last sample further than the tolerance from the nominal magnitude is flagged
//! `DEGRADATION_OF_SIGNAL` at that window's end, on either side of the stated threshold (10 %
//! by default), in floats and fixed point, and the flag holds for `ROUNDNESS_HOLD_WINDOWS`
//! window ends in a row on the circle.

extern crate std;

use crate::fixed::{FixedGains, FixedState, MONITOR_WINDOW};
use crate::test_support::TS;
use crate::*;

/// The float monitor's default window (used samples).
const W: usize = 16;

/// The fixed-point monitor's window.
const FW: usize = MONITOR_WINDOW as usize;

/// Shaft speed (rad per sample).
const STEP_RAD: f64 = 0.01;

/// The Kalman gains of the latency tests, per sample.
const KALMAN: [f64; 3] = [0.06, 0.0019, 3e-5];

/// The float observer (thresholds for the stated amplitude 1) after 10 windows of a
/// healthy shaft, then `windows` windows of the pair `pair(theta)`: the faults of each
/// estimate of the second part.
fn float_faults(windows: usize, pair: impl Fn(f64) -> (f64, f64)) -> std::vec::Vec<Faults> {
    let gains = Gains::<f64, 3>::new(KALMAN, TS)
        .unwrap()
        .with_fault_thresholds(FaultThresholds::for_amplitude(1.0))
        .unwrap();
    let mut state = ObserverState::at(0.0, STEP_RAD / TS, 0.0, TS).unwrap();
    let theta = |k: usize| STEP_RAD * k as f64;
    for k in 1..=10 * W {
        let e = gains.update(&mut state, theta(k).cos(), theta(k).sin());
        assert_eq!(e.faults, Faults::NONE, "healthy sample {k}");
    }
    (10 * W + 1..=(10 + windows) * W)
        .map(|k| {
            let (c, s) = pair(theta(k));
            gains.update(&mut state, c, s).faults
        })
        .collect()
}

/// The fixed-point observer (monitor at the stated 16384 counts) likewise, on pairs in
/// counts.
fn fixed_faults(windows: usize, pair: impl Fn(f64) -> (f64, f64)) -> std::vec::Vec<Faults> {
    let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6)
        .and_then(|g| g.with_monitor(Some(16384.0)))
        .unwrap();
    let mut state = FixedState::new();
    let theta = |k: usize| STEP_RAD * k as f64;
    let counts = |(c, s): (f64, f64)| {
        (
            libm::round(16384.0 * c) as i16,
            libm::round(16384.0 * s) as i16,
        )
    };
    for k in 0..10 * FW {
        let (c, s) = counts((theta(k).cos(), theta(k).sin()));
        gains.track(&mut state, c, s);
    }
    state.clear_faults();
    (10 * FW..(10 + windows) * FW)
        .map(|k| {
            let (c, s) = counts(pair(theta(k)));
            gains.track(&mut state, c, s);
            FixedGains::estimate(&state).faults
        })
        .collect()
}

/// A round pair of magnitude `m`.
fn scaled(m: f64) -> impl Fn(f64) -> (f64, f64) {
    move |theta: f64| (m * theta.cos(), m * theta.sin())
}

/// Whether every estimate from the end of the first window (of `w` samples) on carries
/// degradation.
fn flagged_from_first_window_end(faults: &[Faults], w: usize) -> bool {
    faults[w - 1..]
        .iter()
        .all(|f| f.contains(Faults::DEGRADATION_OF_SIGNAL))
}

#[test]
fn a_magnitude_within_the_tolerance_is_not_flagged_and_beyond_it_is() {
    for m in [0.915, 1.085] {
        assert!(
            float_faults(8, scaled(m)).iter().all(|f| f.is_empty()),
            "float {m}"
        );
        assert!(
            fixed_faults(8, scaled(m)).iter().all(|f| f.is_empty()),
            "fixed {m}"
        );
    }
    for m in [0.885, 1.115] {
        assert!(
            flagged_from_first_window_end(&float_faults(8, scaled(m)), W),
            "float {m}"
        );
        assert!(
            flagged_from_first_window_end(&fixed_faults(8, scaled(m)), FW),
            "fixed {m}"
        );
    }
}

#[test]
fn the_tolerance_is_the_callers() {
    let thresholds = FaultThresholds::for_amplitude(1.0).with_magnitude_tolerance(Some(0.3));
    let gains = Gains::<f64, 3>::new(KALMAN, TS)
        .unwrap()
        .with_fault_thresholds(thresholds)
        .unwrap();
    let mut state = ObserverState::at(0.0, STEP_RAD / TS, 0.0, TS).unwrap();
    for k in 1..=20 * W {
        let theta = STEP_RAD * k as f64;
        // 20 % off: within a tolerance of 30 %.
        let e = gains.update(&mut state, 1.2 * theta.cos(), 1.2 * theta.sin());
        assert_eq!(e.faults, Faults::NONE, "sample {k}");
    }
    for bad in [0.0, -0.1, f64::NAN] {
        let err = Gains::<f64, 3>::new(KALMAN, TS)
            .unwrap()
            .with_fault_thresholds(thresholds.with_magnitude_tolerance(Some(bad)))
            .unwrap_err();
        assert_eq!(err.parameter().name(), "magnitude_tolerance", "{bad}");
    }
}

#[test]
fn a_dead_channel_followed_by_the_loop_is_flagged_and_held() {
    // The cosine channel dead: the loop follows the pair (its residual small), whose
    // magnitude |sin theta| departs from 1 at most angles. From the first window end that
    // sees it (the loop's jump at the onset, or the pair off the circle), every estimate is
    // flagged while the fault lasts: the pair looks round
    // (within 10 %) for |theta - pi/2| <= acos(0.9) = 0.45 rad, 90 samples at this speed,
    // fewer than the hold's 8 windows (128 samples in floats, 256 in fixed point).
    let dead = |theta: f64| (0.0, theta.sin());
    for faults in [float_faults(60, dead), fixed_faults(30, dead)] {
        // Within a quarter turn (157 samples) of the onset, the pair off the circle.
        let first = faults.iter().position(|f| !f.is_empty()).unwrap();
        assert!(first < 160, "{first}");
        let unflagged = faults[first..].iter().filter(|f| f.is_empty()).count();
        assert_eq!(unflagged, 0, "of {}", faults.len() - first);
    }
}

#[test]
fn the_flag_holds_for_the_stated_windows_on_the_circle() {
    // Three windows off the circle (magnitude 0.5), then round again: the flag set at the
    // last window end that saw the fault holds for ROUNDNESS_HOLD_WINDOWS window ends on
    // the circle, and the next clears it.
    let hold = ROUNDNESS_HOLD_WINDOWS as usize;
    for name in ["float", "fixed"] {
        let w = if name == "float" { W } else { FW };
        let fault_end = 3 * w;
        // The pair by the sample's index in the faulty part (its first angle known).
        let start = if name == "float" { 10 * W + 1 } else { 10 * FW };
        let pair = move |theta: f64| {
            let k = libm::round(theta / STEP_RAD) as usize - start;
            scaled(if k < fault_end { 0.5 } else { 1.0 })(theta)
        };
        let faults = if name == "float" {
            float_faults(hold + 6, pair)
        } else {
            fixed_faults(hold + 6, pair)
        };
        let flagged: std::vec::Vec<usize> = faults
            .iter()
            .enumerate()
            .filter(|(_, f)| f.contains(Faults::DEGRADATION_OF_SIGNAL))
            .map(|(k, _)| k)
            .collect();
        let (first, last) = (flagged[0], *flagged.last().unwrap());
        assert!(first < w, "{name}: {first}");
        assert_eq!(flagged.len(), last - first + 1, "{name}: a gap");
        // The last window end off the circle is within the window before `fault_end`.
        assert!(
            last + 1 >= fault_end + hold * w && last + 1 < fault_end + (hold + 1) * w,
            "{name}: flagged to {last}"
        );
    }
}

#[test]
fn without_a_stated_amplitude_there_is_no_roundness_check() {
    // The default thresholds (amplitude 1, a placeholder): a round pair of 0.8 is not
    // flagged, nor in fixed point by `FixedGains::new`'s monitor at 0.8 of 16384 counts.
    let gains = Gains::<f64, 3>::new(KALMAN, TS).unwrap();
    assert_eq!(gains.fault_thresholds().magnitude_tolerance, None);
    let mut state = ObserverState::at(0.0, STEP_RAD / TS, 0.0, TS).unwrap();
    let fixed = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6).unwrap();
    let mut fixed_state = FixedState::new();
    for k in 1..=20 * FW {
        let theta = STEP_RAD * k as f64;
        let e = gains.update(&mut state, 0.8 * theta.cos(), 0.8 * theta.sin());
        assert_eq!(e.faults, Faults::NONE, "float sample {k}");
        let (c, s) = (
            libm::round(0.8 * 16384.0 * theta.cos()) as i16,
            libm::round(0.8 * 16384.0 * theta.sin()) as i16,
        );
        fixed.track(&mut fixed_state, c, s);
        if k > FW {
            assert_eq!(
                FixedGains::estimate(&fixed_state).faults,
                Faults::NONE,
                "fixed {k}"
            );
        }
    }
}
