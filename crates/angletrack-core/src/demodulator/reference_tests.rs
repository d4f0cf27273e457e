//! A recorded excitation that is no reference (`docs/theory.md §13`): flat, not a number, or
//! lost part way. Its windows are flagged `EXCITATION_REFERENCE`, the half turn is kept from
//! its last usable window (or, before any, taken from the expected delay), and a usable
//! reference again clears the flag.

extern crate std;
use std::vec::Vec;

use super::*;
use crate::FrontEndFaults;
use core::f64::consts::TAU;

/// 10 kHz carrier at 160 kHz, the windings' carrier 200 degrees after the ADC's first
/// sample, the shaft at 0.7 rad.
const SAMPLES_PER_PERIOD: f64 = 16.0;
const DELAY_RAD: f64 = 200.0 * TAU / 360.0;
const ANGLE_RAD: f64 = 0.7;

/// The pairs of `samples` samples, the excitation's sample `j` given by `excitation` (its
/// carrier's phase), with the expected delay `expected_rad`: each pair's angle (rad) and
/// faults, and the state after the run.
fn run(
    samples: usize,
    expected_rad: f64,
    excitation: impl Fn(usize, f64) -> f64,
) -> (Vec<(f64, FrontEndFaults)>, DemodulatorState<f64>) {
    let d = Demodulator::new(DemodulatorSettings {
        expected_delay_rad: expected_rad,
        ..DemodulatorSettings::new(10e3, 160e3, 1800.0, 0.0, 4095.0)
    })
    .unwrap();
    let mut state = DemodulatorState::new();
    let mut pairs = Vec::new();
    for j in 0..samples {
        let psi = TAU * j as f64 / SAMPLES_PER_PERIOD - DELAY_RAD;
        let carrier = 1800.0 * psi.sin();
        let (c, s) = (
            2048.0 + ANGLE_RAD.cos() * carrier,
            2048.0 + ANGLE_RAD.sin() * carrier,
        );
        if let Some(pair) = d.push_with_excitation(&mut state, c, s, excitation(j, psi)) {
            pairs.push((pair.y_s.atan2(pair.y_c), pair.faults));
        }
    }
    (pairs, state)
}

/// `true` when `angle` is the shaft's, to 1 mrad.
fn right(angle: f64) -> bool {
    (angle - ANGLE_RAD).abs() < 1e-3
}

#[test]
fn a_flat_or_nan_excitation_is_flagged_and_the_expected_delay_resolves_the_half_turn() {
    // The expected delay, 180 degrees, is within a quarter turn of the windings' 200: the
    // half turn it resolves is the right one.
    for flat in [2048.0, f64::NAN, 2048.0 + 1e-3] {
        let (pairs, state) = run(16 * 200, 180f64.to_radians(), |_, _| flat);
        assert!(pairs.len() > 150, "{flat}");
        assert!(
            pairs
                .iter()
                .all(|&(angle, faults)| right(angle)
                    && faults == FrontEndFaults::EXCITATION_REFERENCE),
            "{flat}: {:?}",
            &pairs[..3]
        );
        assert!(
            state
                .latched_faults()
                .intersects(FrontEndFaults::EXCITATION_REFERENCE)
        );
        // The delay chosen at start-up, not one measured against a flat line.
        // (To 0.05 rad, as without an excitation: `tests.rs`.)
        let error = (state.carrier_delay_rad() - DELAY_RAD).rem_euclid(TAU);
        assert!(error.min(TAU - error) < 0.05, "{flat}: delay error {error}");
    }
}

#[test]
fn a_reference_lost_part_way_keeps_the_half_turn_and_is_flagged_until_it_returns() {
    // The excitation in phase with the windings' carrier, flat from sample 1600 to 2400
    // (50 windows), with an expected delay that would choose the wrong half turn by itself.
    let lost = 1600..2400;
    let (pairs, _) = run(16 * 300, 20f64.to_radians(), |j, psi| {
        if lost.contains(&j) {
            2048.0
        } else {
            2048.0 + 1500.0 * psi.sin()
        }
    });
    assert!(pairs.iter().all(|&(angle, _)| right(angle)));
    let flagged = pairs
        .iter()
        .filter(|p| p.1 == FrontEndFaults::EXCITATION_REFERENCE)
        .count();
    // 50 windows without the reference and the two that straddle its edges, of at most
    // 51 + 2 pairs flagged; the others clean.
    assert!((49..=53).contains(&flagged), "{flagged} flagged");
    assert_eq!(
        flagged + pairs.iter().filter(|p| p.1.is_empty()).count(),
        pairs.len()
    );
}

#[test]
fn an_excitation_a_quarter_turn_from_the_expected_delay_decides_no_half_turn() {
    // The windings 89.7 degrees after a noisy excitation, 0 expected: each window's excitation
    // says a half turn by its noise (60 angles half a turn from the first when every
    // window chose). Flagged, the half turn kept: every angle the same (right or half a turn
    // off). 60 degrees after it decides.
    let noisy = |j: usize, psi: f64, after: f64| {
        let hash = (j as u64 + 1)
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let noise = ((hash >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 60.0;
        2048.0 + 1500.0 * (psi + after.to_radians()).sin() + noise
    };
    let (pairs, _) = run(16 * 300, 0.0, |j, psi| noisy(j, psi, 89.7));
    assert!(pairs.len() > 250);
    let first = pairs[0].0;
    let flips = pairs.iter().filter(|p| (p.0 - first).abs() > 2e-3).count();
    assert_eq!(flips, 0);
    assert!(
        pairs
            .iter()
            .all(|p| p.1 == FrontEndFaults::EXCITATION_REFERENCE)
    );
    let (pairs, state) = run(16 * 300, 0.0, |j, psi| noisy(j, psi, 60.0));
    assert!(pairs.iter().all(|p| right(p.0) && p.1.is_empty()));
    assert!((state.carrier_delay_rad() - 60f64.to_radians()).abs() < 0.05);
}

#[test]
fn an_excitation_below_an_eighth_of_the_windings_amplitude_is_flagged_on_every_pair() {
    // EXCITATION_REFERENCE_FRACTION: 0.125 of the windings' 1800 counts is 225 counts. In
    // phase with the windings' carrier (the delay after it 0, as expected), 0.13 of it
    // resolves every window's half turn, 0.12 none.
    for (fraction, flagged) in [(0.13, false), (0.12, true)] {
        let amplitude = fraction * 1800.0;
        let (pairs, _) = run(16 * 100, 0.0, |_, psi| 2048.0 + amplitude * psi.sin());
        assert!(pairs.len() > 50);
        let expected = if flagged {
            FrontEndFaults::EXCITATION_REFERENCE
        } else {
            FrontEndFaults::NONE
        };
        assert!(
            pairs.iter().all(|&(_, faults)| faults == expected),
            "{fraction}"
        );
    }
}

#[test]
fn a_delay_within_14_degrees_of_a_quarter_turn_from_the_expected_decides_no_half_turn() {
    // |tan| of the delay's error from the expected one at most 4: decided (up to 75.96
    // degrees); beyond, the window is flagged. A clean excitation 74 and 78 degrees before
    // the windings, 0 expected.
    for (after, flagged) in [
        (74.0_f64, false),
        (-74.0, false),
        (78.0, true),
        (-78.0, true),
    ] {
        let (pairs, _) = run(16 * 100, 0.0, |_, psi| {
            2048.0 + 1500.0 * (psi + after.to_radians()).sin()
        });
        assert!(pairs.len() > 50);
        assert!(
            pairs
                .iter()
                .all(|p| p.1.contains(FrontEndFaults::EXCITATION_REFERENCE) == flagged),
            "{after}"
        );
    }
}

#[test]
fn a_delay_is_positive_when_the_windings_lag_the_excitation() {
    // The windings 60 degrees behind the excitation (as a scope shows a resolver's phase
    // shift): stated as 60, every angle right and the delay measured 60; stated as -60, a
    // third of a turn away, the other half turn.
    let excitation = |_: usize, psi: f64| 2048.0 + 1500.0 * (psi + 60f64.to_radians()).sin();
    let (pairs, state) = run(16 * 100, 60f64.to_radians(), excitation);
    assert!(pairs.len() > 50 && pairs.iter().all(|p| right(p.0) && p.1.is_empty()));
    assert!((state.carrier_delay_rad() - 60f64.to_radians()).abs() < 0.05);
    let (pairs, _) = run(16 * 100, -60f64.to_radians(), excitation);
    assert!(pairs.iter().all(|p| !right(p.0)));
}
