//! The per-sample tracking-error check at its stated threshold
//! ([`FaultThresholds::tracking_error`], `docs/guide/diagnostics.md`): a jump of the
//! measured angle just beyond `asin(tracking_error)` is flagged on its own sample and the
//! flag held through the loop's re-convergence; one just within it is never flagged; and
//! whenever the flag is clear the estimate is within the threshold of the measured angle.
//! The fixed-point observer's is in `fixed/monitor_tests.rs`.

use crate::test_support::wrap;
use crate::*;

/// The campaign's gains (third order) at 20 kHz.
const GAINS: [f64; 3] = [0.1578, 0.0126, 0.000_34];
const TS: f64 = 50e-6;

/// What a run with a jump of the measured angle by `jump` (rad) at a speed of 50 Hz
/// electrical showed: the flag on the jump's sample, the samples flagged after it, whether
/// it was latched, and the largest error of an estimate with the flag clear (rad, from
/// the jump on).
struct Run {
    flagged_at_jump: bool,
    held: usize,
    latched: bool,
    worst_clear_error: f64,
}

macro_rules! run_with_jump {
    ($name:ident, $t:ty) => {
        fn $name(jump: f64) -> Run {
            let gains = Gains::<$t, 3>::new(GAINS.map(|g| g as $t), TS as $t)
                .and_then(|g| g.with_fault_thresholds(FaultThresholds::for_amplitude(1.0)))
                .unwrap();
            let speed = core::f64::consts::TAU * 50.0;
            let mut state = ObserverState::<$t, 3>::new();
            let (start, end) = (4000, 6000);
            let mut run = Run {
                flagged_at_jump: false,
                held: 0,
                latched: false,
                worst_clear_error: 0.0,
            };
            for k in 0..end {
                let theta = speed * k as f64 * TS + if k >= start { jump } else { 0.0 };
                let e = gains.update(&mut state, theta.cos() as $t, theta.sin() as $t);
                let flagged = e.faults.contains(Faults::LOSS_OF_TRACKING);
                // The acquisition from rest is flagged; the locked loop before the jump is not.
                if k == start / 2 {
                    state.clear_faults();
                }
                if k + 1 == start {
                    assert!(state.clear_faults().is_empty(), "locked before the jump");
                }
                if k == start {
                    run.flagged_at_jump = flagged;
                } else if k > start && flagged {
                    run.held += 1;
                }
                if k >= start && !flagged {
                    let error = wrap(theta - f64::from(e.angle)).abs();
                    run.worst_clear_error = run.worst_clear_error.max(error);
                }
            }
            run.latched = state.latched_faults().contains(Faults::LOSS_OF_TRACKING);
            run
        }
    };
}

run_with_jump!(run_f64, f64);
run_with_jump!(run_f32, f32);

#[test]
fn a_jump_beyond_the_tracking_error_is_flagged_at_once_and_held_through_the_reconvergence() {
    let threshold = 0.05f64.asin();
    for (name, run) in [("f64", run_f64 as fn(f64) -> Run), ("f32", run_f32)] {
        let beyond = run(1.1 * threshold);
        assert!(beyond.flagged_at_jump && beyond.latched, "{name}");
        // Held while |eps| > 0.025: the loop's error decays by about (1 - l1) a sample.
        assert!(
            (3..60).contains(&beyond.held),
            "{name}: held {}",
            beyond.held
        );
        assert!(
            beyond.worst_clear_error < threshold,
            "{name}: {} rad with the flag clear",
            beyond.worst_clear_error
        );
        let within = run(0.9 * threshold);
        assert!(
            !within.flagged_at_jump && within.held == 0 && !within.latched,
            "{name}: a jump within the threshold was flagged"
        );
        assert!(within.worst_clear_error < threshold, "{name}");
    }
}

/// The acquisition from rest of a shaft turning at 50 Hz electrical is the check's start-up:
/// its samples are neither flagged nor latched although their residuals pass the trip
/// level while the loop's speed catches up (`docs/guide/diagnostics.md`, start-up).
#[test]
fn the_acquisition_from_rest_is_a_start_up_neither_flagged_nor_latched() {
    let gains = Gains::<f64, 3>::new(GAINS, TS)
        .and_then(|g| g.with_fault_thresholds(FaultThresholds::for_amplitude(1.0)))
        .unwrap();
    let speed = core::f64::consts::TAU * 50.0;
    let mut state = ObserverState::<f64, 3>::new();
    let mut largest_residual = 0.0f64;
    for k in 0..2000 {
        let theta = speed * k as f64 * TS;
        let e = gains.update(&mut state, theta.cos(), theta.sin());
        largest_residual = largest_residual.max(state.phase_error.abs());
        assert!(!e.faults.contains(Faults::LOSS_OF_TRACKING), "sample {k}");
    }
    assert!(
        largest_residual > 0.05,
        "{largest_residual}: the start-up passes the trip level"
    );
    assert!(!state.clear_faults().contains(Faults::LOSS_OF_TRACKING));
}
