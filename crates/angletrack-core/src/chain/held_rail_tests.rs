//! The measured rails' thresholds at their stated values (`docs/guide/diagnostics.md`,
//! "Front-end faults"): a channel held at an extreme for [`HELD_RAIL_SAMPLES`] samples in a
//! row is clipped, one sample fewer is not; the samples at it must be more than four times
//! those in the band just inside it.

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
