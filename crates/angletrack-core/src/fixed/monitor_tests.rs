//! The fixed-point monitor's latency per fault (`docs/theory.md §14`): each fault, begun at
//! every offset within the monitor's window, is flagged within its documented bound, and
//! nothing is flagged before it.

use super::gains::FixedThresholds;
use super::update::MONITOR_WINDOW;
use super::*;
use crate::Faults;

const KALMAN: [f64; 3] = [0.1578, 0.0126, 0.000_34];

/// The window (samples).
const W: usize = MONITOR_WINDOW as usize;

/// The signal of amplitude `amplitude` (counts) at `theta` (rad), rounded to counts.
fn counts(amplitude: f64, theta: f64) -> (i16, i16) {
    (
        libm::round(amplitude * libm::cos(theta)) as i16,
        libm::round(amplitude * libm::sin(theta)) as i16,
    )
}

/// The worst number of samples, over every start within the window, from the first sample
/// of the fault to the first estimate that shows `flag`, asserted below `bound`. The signal
/// is healthy (16384 counts, 0.01 rad per sample) for 200 samples plus the offset, then
/// `fault(k, theta)` (k from 0 at the fault's start).
fn worst_latency(flag: Faults, bound: usize, fault: impl Fn(usize, f64) -> (i16, i16)) -> usize {
    let gains = FixedGains::<3>::new(KALMAN, 50e-6).unwrap();
    let mut worst = 0;
    for offset in 0..W {
        let mut state = FixedState::new();
        let healthy = 200 + offset;
        for k in 0..healthy {
            let (c, s) = counts(16384.0, 0.01 * k as f64);
            gains.track(&mut state, c, s);
        }
        assert_eq!(state.latched_faults(), Faults::NONE, "offset {offset}");
        let latency = (0..4 * W).find(|&k| {
            let (c, s) = fault(k, 0.01 * (healthy + k) as f64);
            gains.track(&mut state, c, s);
            FixedGains::estimate(&state).faults.contains(flag)
        });
        let latency = latency.map_or(usize::MAX, |k| k + 1);
        assert!(latency <= bound, "{flag:?}, offset {offset}: {latency}");
        worst = worst.max(latency);
    }
    worst
}

#[test]
fn loss_of_signal_is_flagged_at_the_end_of_its_window() {
    // The sensor disconnected: 2000 counts left (below a quarter of 16384). The amplitude
    // is read from the window's last sample: a fault begun at a window's first sample is
    // flagged at its last, the worst case.
    let worst = worst_latency(Faults::LOSS_OF_SIGNAL, W, |_, theta| counts(2000.0, theta));
    assert_eq!(worst, W);
}

#[test]
fn degradation_of_signal_is_flagged_both_ways() {
    // 6000 counts (below half of nominal, above a quarter) and 30000 (above 3/2).
    for amplitude in [6000.0, 30000.0] {
        let worst = worst_latency(Faults::DEGRADATION_OF_SIGNAL, W, |_, theta| {
            counts(amplitude, theta)
        });
        assert_eq!(worst, W);
    }
}

#[test]
fn loss_of_tracking_is_flagged_at_the_first_sample_beyond_the_tracking_error() {
    // The angle alternating by a quarter turn each sample: the loop cannot follow. The
    // first faulty sample is the healthy angle; the second's residual, about sin(90
    // degrees), is beyond the tracking-error level (0.05) and flagged at once, whatever the
    // window's phase.
    let worst = worst_latency(Faults::LOSS_OF_TRACKING, 2, |k, theta| {
        counts(
            16384.0,
            theta
                + if k % 2 == 0 {
                    0.0
                } else {
                    core::f64::consts::FRAC_PI_2
                },
        )
    });
    assert_eq!(worst, 2);
}

#[test]
fn false_lock_is_flagged_within_a_window_and_re_acquired() {
    // A half-turn jump: the phase error is zero, the in-phase component negative.
    let worst = worst_latency(Faults::FALSE_LOCK, W, |_, theta| {
        counts(16384.0, theta + core::f64::consts::PI)
    });
    assert!(worst >= W / 2, "{worst}");
    // After the flag, the angle is the signal's.
    let gains = FixedGains::<3>::new(KALMAN, 50e-6).unwrap();
    let mut state = FixedState::new();
    for _ in 0..100 {
        gains.track(&mut state, 16384, 0);
    }
    for _ in 0..W {
        gains.track(&mut state, -16384, 0);
    }
    assert!(state.latched_faults().contains(Faults::FALSE_LOCK));
    gains.track(&mut state, -16384, 0);
    let angle = FixedGains::estimate(&state).angle;
    assert!(angle.wrapping_sub(i32::MIN).abs() < 1 << 20, "{angle}");
}

#[test]
fn speed_beyond_a_quarter_turn_per_sample_is_loss_of_tracking() {
    // The loop locked on a signal at 0.3 turn per sample (its phase error near zero): only
    // the speed check flags it, at the window's end.
    let gains = FixedGains::<3>::new(KALMAN, 50e-6).unwrap();
    let speed_turns = 0.3;
    let theta = |k: usize| core::f64::consts::TAU * speed_turns * k as f64;
    let mut state = FixedState::new();
    gains.track(&mut state, 16384, 0);
    state.x.speed = binary_angle(core::f64::consts::TAU * speed_turns);
    state.next_angle = state.x.angle.wrapping_add(state.x.speed);
    let mut flagged = None;
    for k in 1..=W {
        let (c, s) = counts(16384.0, theta(k));
        gains.track(&mut state, c, s);
        assert!(
            state.phase_error.abs() < 100,
            "k {k}: {}",
            state.phase_error
        );
        // The latched register: the estimates carry the start-up's flag from the first
        // sample (the tracking-error check's, not latched).
        if flagged.is_none() && state.latched_faults() != Faults::NONE {
            flagged = Some((k, state.latched_faults()));
        }
    }
    // The first window starts after the first sample (which sets the angle).
    assert_eq!(flagged, Some((W, Faults::LOSS_OF_TRACKING)));
}

/// The faults latched over 2000 samples of 12-bit counts of amplitude 1800 shifted by 4
/// (28,800 counts), 0.01 rad per sample, after the first 200, with `gains`.
fn latched_on_shifted_counts<const N: usize>(gains: FixedGains<N>) -> Faults {
    let mut state = FixedState::new();
    for k in 0..2200 {
        let (c, s) = counts(1800.0, 0.01 * k as f64);
        gains.track(&mut state, c << 4, s << 4);
        if k == 200 {
            state.clear_faults();
        }
    }
    state.latched_faults()
}

#[test]
fn the_nominal_amplitude_of_shifted_counts_is_set_in_a_static() {
    // The README's fixed-point example: the monitor's amplitude in the same `static` as the
    // gains. With the default 16384, 28,800 counts are above 3/2 of nominal: degraded.
    const CONSTANTS: FixedConstants<2> = FixedConstants {
        multiplier: [68_356_528, 1_640_557],
        acceleration_shift: 0,
    };
    static SHIFTED: FixedGains<2> = match FixedGains::<2>::from_constants(CONSTANTS, 1e-4) {
        Ok(gains) => match gains.with_monitor(Some(28_800.0)) {
            Ok(gains) => gains,
            Err(_) => panic!("bad amplitude"),
        },
        Err(_) => panic!("unstable gains"),
    };
    assert_eq!(latched_on_shifted_counts(SHIFTED), Faults::NONE);
    let default = FixedGains::<2>::from_constants(CONSTANTS, 1e-4).unwrap();
    assert!(latched_on_shifted_counts(default).contains(Faults::DEGRADATION_OF_SIGNAL));
}

/// A jump of the measured angle by `factor` times `asin(level)` after 4000 healthy samples,
/// tracked by `gains` whose level is `level`: flagged on its own sample and held a few
/// samples if `flagged`, never flagged else; with the flag clear the estimate is within
/// `asin(level)`.
fn jump_at_the_tracking_error(gains: FixedGains<3>, level: f64, factor: f64, flagged: bool) {
    let threshold = libm::asin(level);
    let jump = factor * threshold;
    let mut state = FixedState::new();
    let (start, end) = (4000, 6000);
    let mut held = 0;
    for k in 0..end {
        let theta = 0.01 * k as f64 + if k >= start { jump } else { 0.0 };
        let (c, s) = counts(16384.0, theta);
        gains.track(&mut state, c, s);
        let e = FixedGains::estimate(&state);
        let tracking = e.faults.contains(Faults::LOSS_OF_TRACKING);
        if k + 1 == start {
            assert_eq!(state.latched_faults(), Faults::NONE);
        }
        if k == start {
            assert_eq!(tracking, flagged, "level {level}, factor {factor}");
        }
        held += usize::from(k > start && tracking);
        if k >= start && !tracking {
            let error = binary_angle::binary_angle_to_rad(
                e.angle.wrapping_sub(binary_angle::binary_angle(theta)),
            );
            assert!(
                error.abs() < threshold,
                "level {level}, factor {factor}, sample {k}: {error}"
            );
        }
    }
    assert_eq!(
        state.latched_faults().contains(Faults::LOSS_OF_TRACKING),
        flagged
    );
    assert!(
        if flagged {
            (3..60).contains(&held)
        } else {
            held == 0
        },
        "level {level}, held {held}"
    );
}

/// The per-sample tracking-error check at its level (0.05, held down to 0.025: 1638 and
/// 819 in Q15), as the floats' (`monitor/tracking_tests.rs`): a jump of the measured angle
/// by 1.1 `asin(0.05)` is flagged on its own sample and held a few samples; one by 0.9
/// `asin(0.05)` is never flagged; with the flag clear the estimate is within `asin(0.05)`.
#[test]
fn a_jump_beyond_the_tracking_error_is_flagged_at_once_and_one_within_never() {
    let gains = FixedGains::<3>::new(KALMAN, 50e-6).unwrap();
    let trip = gains.monitor.tracking_error;
    assert_eq!(
        (trip, crate::monitor::tracking::Residual::release(trip)),
        (1638, 819)
    );
    for (factor, flagged) in [(1.1, true), (0.9, false)] {
        jump_at_the_tracking_error(gains, 0.05, factor, flagged);
    }
}

/// The level set above the default ([`FixedGains::with_tracking_error`], 0.08 as for a
/// sensor of 1 % noise: 2621 in Q15, held down to 1310): a jump by 1.1 `asin(0.08)` is
/// flagged at once, one by 0.9 `asin(0.08)` (beyond the default level) never.
#[test]
fn a_jump_beyond_a_set_tracking_error_is_flagged_and_one_within_never() {
    let gains = FixedGains::<3>::new(KALMAN, 50e-6)
        .and_then(|g| g.with_monitor(Some(16384.0)))
        .and_then(|g| g.with_tracking_error(0.08))
        .unwrap();
    assert_eq!(gains.monitor.tracking_error, 2621);
    assert!(0.9 * libm::asin(0.08) > libm::asin(0.05));
    for (factor, flagged) in [(1.1, true), (0.9, false)] {
        jump_at_the_tracking_error(gains, 0.08, factor, flagged);
    }
    // The words carry the level: the gains built from them are the same.
    let back = FixedGains::<3>::from_words(gains.constants(), 50e-6, gains.monitor_words());
    assert_eq!(back, Ok(gains));
}

/// The level's range: refused, naming the tracking-error threshold, when not finite, not
/// positive, rounding to 0 in Q15 or beyond [`MAX_TRACKING_ERROR_Q15`] (as a level and as
/// a word); with the monitor off, no effect.
#[test]
fn a_tracking_error_level_outside_q15_is_refused() {
    use crate::error::{ConfigError, Parameter};
    let gains = FixedGains::<2>::new([0.05, 0.0012], 1e-4).unwrap();
    let p = Parameter::TrackingErrorThreshold;
    let cases = [
        (f64::NAN, ConfigError::NotFinite(p)),
        (f64::INFINITY, ConfigError::NotFinite(p)),
        (0.0, ConfigError::NotPositive(p)),
        (-0.05, ConfigError::NotPositive(p)),
        (1e-6, ConfigError::OutOfRange(p)),
        (32764.6 / 32768.0, ConfigError::OutOfRange(p)),
        (1e300, ConfigError::OutOfRange(p)),
    ];
    for (level, refusal) in cases {
        assert_eq!(gains.with_tracking_error(level), Err(refusal), "{level}");
    }
    let top = gains.with_tracking_error(32764.4 / 32768.0).unwrap();
    assert_eq!(top.monitor_words()[8], MAX_TRACKING_ERROR_Q15 as u32);
    assert_eq!(
        gains
            .with_tracking_error(0.6 / 32768.0)
            .unwrap()
            .monitor_words()[8],
        1
    );
    let off = gains.with_monitor(None).unwrap();
    assert_eq!(off.with_tracking_error(0.08), Ok(off));
    for word in [0, MAX_TRACKING_ERROR_Q15 as u32 + 1] {
        let mut words = gains.monitor_words();
        words[8] = word;
        let refused = FixedGains::<2>::from_words(gains.constants(), 1e-4, words);
        assert_eq!(refused, Err(ConfigError::OutOfRange(p)), "{word}");
        words[0] = 0;
        // With the monitor off, the word is not read.
        let unread = FixedGains::<2>::from_words(gains.constants(), 1e-4, words).unwrap();
        assert_eq!(
            unread.monitor.tracking_error,
            FixedThresholds::OFF.tracking_error
        );
    }
}
