//! The demodulator's fault thresholds at their stated values (`docs/guide/diagnostics.md`,
//! "Front-end faults"): a carrier just inside each is not flagged, one just outside is, and
//! a fault's onset is flagged on the first window that holds it.

extern crate std;
use std::vec::Vec;

use super::*;
use crate::FrontEndFaults;
use core::f64::consts::TAU;

/// 10 kHz carrier at 160 kHz, 1800 counts a winding, a 12-bit ADC.
const SAMPLES_PER_PERIOD: usize = 16;
const AMPLITUDE: f64 = 1800.0;
/// The shaft's angle (rad): both windings carry the carrier.
const ANGLE_RAD: f64 = 0.7;

fn settings() -> DemodulatorSettings<f64> {
    DemodulatorSettings::new(10e3, 160e3, AMPLITUDE, 0.0, 4095.0)
}

/// The windings' samples `j`: the carrier at `level` of nominal and `phase_rad` (both of
/// the sample), the shaft still.
fn windings(j: usize, level: f64, phase_rad: f64) -> (f64, f64) {
    let psi = TAU * j as f64 / SAMPLES_PER_PERIOD as f64 + phase_rad;
    let carrier = AMPLITUDE * level * psi.sin();
    (
        2048.0 + ANGLE_RAD.cos() * carrier,
        2048.0 + ANGLE_RAD.sin() * carrier,
    )
}

/// The pairs of `samples` samples `sample(j)` through `d`.
fn run(
    d: &Demodulator<f64>,
    samples: usize,
    sample: impl Fn(usize) -> (f64, f64),
) -> Vec<DemodulatedPair<f64>> {
    let mut state = DemodulatorState::new();
    (0..samples)
        .filter_map(|j| {
            let (c, s) = sample(j);
            d.push(&mut state, c, s)
        })
        .collect()
}

/// Whether the pair's window holds sample `j`.
fn holds(pair: &DemodulatedPair<f64>, j: usize) -> bool {
    let length: u32 = pair.segment_samples.iter().sum();
    (pair.first_sample..pair.first_sample + u64::from(length)).contains(&(j as u64))
}

/// 40 periods at full excitation, then `level` of it: the faults of the pairs from the
/// second whose window holds only the new level on, ORed and ANDed; the first flagged
/// `flag`, counted from the first pair whose window holds the step; and the pairs of the
/// step flagged `LOSS_OF_EXCITATION` (the window that holds it and the next: a weak window
/// with under 3/4 of the last one's power is taken for a loss's onset).
fn after_a_step_to(
    level: f64,
    flag: FrontEndFaults,
) -> (FrontEndFaults, FrontEndFaults, usize, usize) {
    let d = Demodulator::new(settings()).unwrap();
    // The step in the middle of a period.
    let step = 40 * SAMPLES_PER_PERIOD + 7;
    let pairs = run(&d, 80 * SAMPLES_PER_PERIOD, |j| {
        windings(j, if j < step { 1.0 } else { level }, 0.0)
    });
    let first_holding = pairs.iter().position(|p| holds(p, step)).unwrap();
    let first_flagged = pairs.iter().position(|p| p.faults.contains(flag));
    let after: Vec<FrontEndFaults> = pairs
        .iter()
        .filter(|p| p.first_sample > (step + SAMPLES_PER_PERIOD) as u64)
        .map(|p| p.faults)
        .collect();
    assert!(after.len() > 30);
    let onset_lost = pairs[first_holding..first_holding + 2]
        .iter()
        .filter(|p| p.faults.contains(FrontEndFaults::LOSS_OF_EXCITATION))
        .count();
    let any = after.iter().fold(FrontEndFaults::NONE, |a, f| a | *f);
    let all = after.iter().fold(FrontEndFaults::from_bits(0x3f), |a, f| {
        FrontEndFaults::from_bits(a.bits() & f.bits())
    });
    let latency = first_flagged.map_or(usize::MAX, |i| i.saturating_sub(first_holding));
    (any, all, latency, onset_lost)
}

#[test]
fn loss_of_excitation_is_flagged_below_a_quarter_of_nominal_on_the_first_window() {
    // 0.23 of nominal: lost (and weak), from the first window holding the step on.
    let lost = FrontEndFaults::LOSS_OF_EXCITATION | FrontEndFaults::WEAK_EXCITATION;
    let (_, all, latency, onset) = after_a_step_to(0.23, FrontEndFaults::LOSS_OF_EXCITATION);
    assert!(all.contains(lost), "{all}");
    assert_eq!((latency, onset), (0, 2));
    // 0.27: weak, not lost, once the step's two windows have passed (the window that holds
    // it and the next, the first at 0.27 all through, under 3/4 of its power).
    let (any, all, _, onset) = after_a_step_to(0.27, FrontEndFaults::LOSS_OF_EXCITATION);
    let weak = FrontEndFaults::WEAK_EXCITATION;
    assert_eq!((any, all, onset), (weak, weak, 2));
}

#[test]
fn weak_excitation_is_flagged_below_0_7_of_nominal_on_the_first_window() {
    // The window that holds the step is above 0.7 in power (most of it at full excitation);
    // the next, the first at 0.68 all through, is weak and, under 3/4 of the last window's
    // power, taken for a loss's onset: one pair lost.
    let weak = FrontEndFaults::WEAK_EXCITATION;
    let (any, all, latency, onset) = after_a_step_to(0.68, weak);
    assert_eq!((any, all, latency, onset), (weak, weak, 1, 1));
    let (any, _, latency, onset) = after_a_step_to(0.72, weak);
    assert_eq!((any, latency, onset), (FrontEndFaults::NONE, usize::MAX, 0));
}

/// The faults of the pairs after the carrier's phase steps by `step_deg` (at a period's
/// start, after 40 periods), through a loop too slow to correct it (a bandwidth of 1e-6:
/// the phase error stays the step), with the drift bound `bound_deg` (`None`: the
/// default); ORed and ANDed.
fn after_a_phase_step(step_deg: f64, bound_deg: Option<f64>) -> (FrontEndFaults, FrontEndFaults) {
    let default = settings().phase_drift_bound_rad;
    let d = Demodulator::new(DemodulatorSettings {
        carrier_loop_bandwidth: 1e-6,
        phase_drift_bound_rad: bound_deg.map_or(default, f64::to_radians),
        ..settings()
    })
    .unwrap();
    let step = 40 * SAMPLES_PER_PERIOD;
    let pairs = run(&d, 80 * SAMPLES_PER_PERIOD, |j| {
        windings(j, 1.0, if j < step { 0.0 } else { step_deg.to_radians() })
    });
    let before = pairs.iter().filter(|p| p.first_sample + 24 < step as u64);
    assert!(before.clone().count() > 10);
    assert!(before.clone().all(|p| p.faults.is_empty()), "{step_deg}");
    let after: Vec<FrontEndFaults> = pairs
        .iter()
        .filter(|p| p.first_sample >= step as u64)
        .map(|p| p.faults)
        .collect();
    assert!(after.len() > 30);
    let any = after.iter().fold(FrontEndFaults::NONE, |a, f| a | *f);
    let all = after.iter().fold(FrontEndFaults::PHASE_DRIFT, |a, f| {
        FrontEndFaults::from_bits(a.bits() & f.bits())
    });
    (any, all)
}

#[test]
fn phase_drift_is_flagged_beyond_the_bound_of_carrier_phase_error() {
    // The default bound, 44 degrees, and a stated one of 20.
    for (bound, stated) in [(44.0, None), (20.0, Some(20.0))] {
        let (any, _) = after_a_phase_step(bound - 2.0, stated);
        assert_eq!(any, FrontEndFaults::NONE, "{bound}");
        let (any, all) = after_a_phase_step(bound + 2.0, stated);
        assert_eq!(
            (any, all),
            (FrontEndFaults::PHASE_DRIFT, FrontEndFaults::PHASE_DRIFT)
        );
    }
}

#[test]
fn phase_drift_is_flagged_from_the_first_window_out_of_lock_to_the_one_after_the_last() {
    // 46 degrees of carrier phase from period 40 to period 60, the loop frozen: windows 40 to
    // 58 are out of lock; 39 and 59 hold an eighth of their weight on the other side of a
    // step (6 degrees off and 41: in lock), and 59, after an out-of-lock one, is flagged
    // too (the loop's correction of the last would have moved its timing).
    let d = Demodulator::new(DemodulatorSettings {
        carrier_loop_bandwidth: 1e-6,
        ..settings()
    })
    .unwrap();
    let out = 40 * SAMPLES_PER_PERIOD..60 * SAMPLES_PER_PERIOD;
    let pairs = run(&d, 80 * SAMPLES_PER_PERIOD, |j| {
        windings(
            j,
            1.0,
            if out.contains(&j) {
                46f64.to_radians()
            } else {
                0.0
            },
        )
    });
    let flagged: Vec<u64> = pairs
        .iter()
        .filter(|p| !p.faults.is_empty())
        .map(|p| p.first_sample / SAMPLES_PER_PERIOD as u64)
        .collect();
    assert_eq!(flagged, (40..60).collect::<Vec<u64>>());
    assert!(
        pairs
            .iter()
            .all(|p| p.faults.is_empty() || p.faults == FrontEndFaults::PHASE_DRIFT)
    );
}

#[test]
fn a_carrier_beyond_the_carrier_error_allowed_is_phase_drift() {
    // 3 % allowed by default: 2.8 % off is tracked without a flag, 3.2 % is flagged on
    // every pair.
    let d = Demodulator::new(settings()).unwrap();
    for (error, flagged) in [
        (0.028, false),
        (-0.028, false),
        (0.032, true),
        (-0.032, true),
    ] {
        let pairs = run(&d, 200 * SAMPLES_PER_PERIOD, |j| {
            let psi = TAU * (1.0 + error) * j as f64 / SAMPLES_PER_PERIOD as f64;
            let carrier = AMPLITUDE * psi.sin();
            (
                2048.0 + ANGLE_RAD.cos() * carrier,
                2048.0 + ANGLE_RAD.sin() * carrier,
            )
        });
        assert!(pairs.len() > 150);
        let drift = pairs
            .iter()
            .filter(|p| p.faults.contains(FrontEndFaults::PHASE_DRIFT))
            .count();
        let expected = if flagged { pairs.len() } else { 0 };
        assert_eq!(drift, expected, "{error}");
    }
}

#[test]
fn a_sample_within_the_clip_margin_of_a_rail_is_flagged_on_the_windows_that_hold_it() {
    // The default margin: 1/256 of the 4095-count range (16 counts). One sample of the sine
    // winding half a count inside the margin's edge, or half a count beyond it, at each rail.
    let d = Demodulator::new(settings()).unwrap();
    let margin = 4095.0 / 256.0;
    let at = 50 * SAMPLES_PER_PERIOD + 5;
    for (value, clipped) in [
        (4095.0 - margin - 0.5, false),
        (4095.0 - margin + 0.5, true),
        (margin + 0.5, false),
        (margin - 0.5, true),
    ] {
        let pairs = run(&d, 80 * SAMPLES_PER_PERIOD, |j| {
            let (c, s) = windings(j, 1.0, 0.0);
            (c, if j == at { value } else { s })
        });
        for p in &pairs {
            let flagged = p.faults.contains(FrontEndFaults::CLIPPING);
            assert_eq!(flagged, clipped && holds(p, at), "{value}: {}", p.window);
        }
        assert!(pairs.iter().any(|p| holds(p, at)));
    }
}
