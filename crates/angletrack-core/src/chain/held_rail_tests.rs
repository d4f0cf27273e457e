//! The measured rails' thresholds at their stated values (`docs/guide/diagnostics.md`,
//! "Front-end faults"): a channel held at an extreme for [`HELD_RAIL_SAMPLES`] samples in a
//! row is clipped, one sample fewer is not; the samples at it must be more than four times
//! those in the band just inside it; and the samples must span more than 1.5 times the
//! larger channel of the sample judged.

extern crate std;
use std::vec::Vec;

use crate::*;

/// The samples flagged by a [`HeldRailCheck`] on a cosine channel that climbs from -1 to
/// 0.9 in steps of 0.1, reaches 0.995 `near` times, then 1 `held` times in a row, the
/// sine channel moving throughout (the samples span 2, more than 1.5 times either channel).
fn flagged(near: usize, held: usize) -> Vec<usize> {
    let gains = Gains::<f64, 3>::new([0.3, 0.04, 0.002], 1e-4).unwrap();
    let chain = Chain::new(HeldRailCheck::new(), gains);
    let mut state = ChainState::new();
    let climb = (0..20).map(|k| -1.0 + 0.1 * k as f64);
    let cosine: Vec<f64> = climb
        .chain(core::iter::repeat_n(0.995, near))
        .chain(core::iter::repeat_n(1.0, held))
        .collect();
    let mut flagged = Vec::new();
    for (k, &c) in cosine.iter().enumerate() {
        let e = chain.update(&mut state, (c, -0.5 + 0.01 * k as f64));
        if e.faults.contains(Faults::FRONT_END) {
            flagged.push(k - 20 - near);
        }
    }
    flagged
}

#[test]
fn a_channel_held_at_an_extreme_for_four_samples_is_clipped_from_the_fourth() {
    assert_eq!(HELD_RAIL_SAMPLES, 4);
    assert_eq!(flagged(0, 3), Vec::<usize>::new());
    assert_eq!(flagged(0, 5), [3, 4]);
}

#[test]
fn a_rail_has_more_than_four_times_the_samples_of_the_band_inside_it() {
    // Half a percent of the span 2 is 0.01: the samples at 0.995 are in the band below 1.
    // One there: the fifth at 1 is the first clipped; two: the ninth.
    assert_eq!(flagged(1, 4), Vec::<usize>::new());
    assert_eq!(flagged(1, 5), [4]);
    assert_eq!(flagged(2, 8), Vec::<usize>::new());
    assert_eq!(flagged(2, 9), [8]);
}

/// The samples flagged among five held at `rail` on a cosine channel that climbs to it
/// from `lowest` in ten equal steps, the sine channel moving inside that span; `update`
/// runs one pair through a chain with a [`HeldRailCheck`] and says whether it is flagged.
fn held_flagged<T>(
    lowest: f64,
    rail: f64,
    round: impl Fn(f64) -> T,
    mut update: impl FnMut((T, T)) -> bool,
) -> Vec<usize> {
    let mut flagged = Vec::new();
    for k in 0..15 {
        let c = lowest + (rail - lowest) * (k.min(10) as f64) / 10.0;
        let s = 0.1 * rail * (k % 3) as f64;
        if update((round(c), round(s))) && k >= 10 {
            flagged.push(k - 10);
        }
    }
    flagged
}

#[test]
fn a_rail_is_one_on_samples_spanning_more_than_one_and_a_half_times_the_larger_channel() {
    // Held at 1 from -0.52 (a span of 1.52) the fourth sample at it is clipped; from -0.48
    // (1.48) none is.
    let gains = Gains::<f64, 3>::new([0.3, 0.04, 0.002], 1e-4).unwrap();
    let chain = Chain::new(HeldRailCheck::new(), gains);
    let run = |lowest: f64| {
        let mut state = ChainState::new();
        held_flagged(
            lowest,
            1.0,
            |v| v,
            |pair| {
                chain
                    .update(&mut state, pair)
                    .faults
                    .contains(Faults::FRONT_END)
            },
        )
    };
    assert_eq!(run(-0.52), [3, 4]);
    assert_eq!(run(-0.48), Vec::<usize>::new());
    // In fixed point the same rule in integers: held at 20000 from -10100 (2 x 30100 >
    // 3 x 20000) clipped, from -9900 (2 x 29900) not.
    let gains = FixedGains::<3>::new([0.1578, 0.0126, 0.000_34], 50e-6).unwrap();
    let chain = Chain::new(HeldRailCheck::new(), gains);
    let run = |lowest: f64| {
        let mut state = ChainState::new();
        held_flagged(
            lowest,
            20000.0,
            |v| v.round() as i16,
            |pair| {
                chain
                    .update(&mut state, pair)
                    .faults
                    .contains(Faults::FRONT_END)
            },
        )
    };
    assert_eq!(run(-10100.0), [3, 4]);
    assert_eq!(run(-9900.0), Vec::<usize>::new());
}
