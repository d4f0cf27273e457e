//! The ADC range of a capture measured on its samples, against which clipping is flagged
//! when no range is stated: an extreme that is a rail, as a clipped signal's is and a clean
//! one's is not (`docs/theory.md §15`). The same test as the core's streaming
//! [`HeldRailCheck`](angletrack_core::HeldRailCheck), made on a whole block of samples: held
//! flat over [`HELD_RAIL_SAMPLES`] consecutive samples of a channel while the other channel
//! moves (a still shaft holds both channels flat, at no rail), and reached by more than four
//! times the samples of the band just inside it (half a percent of the span).

use angletrack_core::{HELD_RAIL_SAMPLES, RAIL_BAND_PER_SPAN, is_piled_up_at_rail};

/// Which samples of a channel count toward holding it at an extreme.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Holding {
    /// Those at which the other channel moved since its previous sample (the core's count,
    /// in which a sample where the other channel stood still adds nothing and breaks
    /// nothing): a still shaft holds both channels of a resolver's pairs.
    WhileTheOtherMoves,
    /// All: a resolver's raw windings carry the carrier, which a still shaft does not stop.
    Always,
}

/// Whether `y` sits at `value` for at least [`HELD_RAIL_SAMPLES`] consecutive samples that
/// count by `holding` (`other`: the other channel).
fn held_flat(y: &[f64], other: &[f64], value: f64, holding: Holding) -> bool {
    let mut run = 0usize;
    let moved = core::iter::once(holding == Holding::Always).chain(
        other
            .windows(2)
            .map(|w| holding == Holding::Always || w[0] != w[1]),
    );
    for (&v, moved) in y.iter().zip(moved) {
        run = if v == value {
            run + usize::from(moved)
        } else {
            0
        };
        if run >= usize::from(HELD_RAIL_SAMPLES) {
            return true;
        }
    }
    false
}

/// Whether the extreme `value` of `y_c` and `y_s` is a rail: held flat in a channel while
/// the other moves, and piled up against the samples within `band` inside it ([`is_piled_up_at_rail`];
/// `inward`: the direction of the inside, `+1` above a low extreme, `-1` below a high one).
fn is_rail(y_c: &[f64], y_s: &[f64], value: f64, band: f64, inward: f64, holding: Holding) -> bool {
    if !(held_flat(y_c, y_s, value, holding) || held_flat(y_s, y_c, value, holding)) {
        return false;
    }
    let (mut at, mut near) = (0u64, 0u64);
    for &v in y_c.iter().chain(y_s) {
        let inside = (v - value) * inward;
        if v == value {
            at += 1;
        } else if inside > 0.0 && inside <= band {
            near += 1;
        }
    }
    is_piled_up_at_rail(at, near)
}

/// The ADC range measured on a resolver's pairs `y_c`, `y_s` (any lengths; NaNs ignored):
/// each extreme of both channels that is a rail (a channel held at it while the other
/// moves); an extreme that is not is put one span beyond,
/// so that it flags nothing. `None` when neither extreme is a rail (or the samples hold no
/// two distinct finite values): clipping is then not checked.
///
/// ```
/// use angletrack::measured_adc_range;
/// // Windings clipped at 0.9 of their amplitude: the rails are found.
/// let clipped = |f: fn(f64) -> f64| -> Vec<f64> {
///     (0..2000).map(|k| f(0.01 * k as f64).clamp(-0.9, 0.9)).collect()
/// };
/// assert_eq!(measured_adc_range(&clipped(f64::cos), &clipped(f64::sin)), Some((-0.9, 0.9)));
/// // Clean ones have none.
/// let clean = |f: fn(f64) -> f64| -> Vec<f64> { (0..2000).map(|k| f(0.01 * k as f64)).collect() };
/// assert_eq!(measured_adc_range(&clean(f64::cos), &clean(f64::sin)), None);
/// // Nor has a still shaft, whose channels hold their values throughout.
/// assert_eq!(measured_adc_range(&[2948.0; 100], &[3607.0; 100]), None);
/// ```
pub fn measured_adc_range(y_c: &[f64], y_s: &[f64]) -> Option<(f64, f64)> {
    measured_range(y_c, y_s, Holding::WhileTheOtherMoves)
}

/// The ADC range measured on a resolver's raw windings `c`, `s` as [`measured_adc_range`]
/// measures it on pairs, but with a winding held at an extreme whatever the other does: the
/// carrier moves both windings even on a still shaft, and one of them may read a constant
/// (0 at a multiple of a quarter turn) while the other clips.
pub(crate) fn measured_winding_range(c: &[f64], s: &[f64]) -> Option<(f64, f64)> {
    measured_range(c, s, Holding::Always)
}

/// The ADC range measured on `y_c`, `y_s` with the channels held by `holding`.
fn measured_range(y_c: &[f64], y_s: &[f64], holding: Holding) -> Option<(f64, f64)> {
    let finite = y_c.iter().chain(y_s).copied().filter(|v| v.is_finite());
    let (low, high) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !(low < high) {
        return None;
    }
    let span = high - low;
    let band = span / f64::from(RAIL_BAND_PER_SPAN);
    let low_rail = is_rail(y_c, y_s, low, band, 1.0, holding);
    let high_rail = is_rail(y_c, y_s, high, band, -1.0, holding);
    if !(low_rail || high_rail) {
        return None;
    }
    Some((
        if low_rail { low } else { low - span },
        if high_rail { high } else { high + span },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 12-bit counts of a sine of 1800 counts about 2048, offset by `offset`, clipped to the
    /// codes 0..=4095, and a cosine channel unclipped.
    fn counts(offset: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let y = |k: usize, phase: f64| {
            (2048.0 + offset + 1800.0 * (0.003 * k as f64 + phase).sin())
                .round()
                .clamp(0.0, 4095.0)
        };
        (
            (0..n).map(|k| y(k, 0.0)).collect(),
            (0..n).map(|k| y(k, 1.57)).collect(),
        )
    }

    #[test]
    fn a_rail_held_at_one_side_is_found_and_the_other_side_put_beyond() {
        // 400 counts high: the top clips at 4095 for many samples; the bottom (648) is a
        // clean peak.
        let (c, s) = counts(400.0, 5000);
        let (low, high) = measured_adc_range(&c, &s).unwrap();
        assert_eq!(high, 4095.0);
        assert!(low < 648.0 - 3000.0, "{low}");
        // Unclipped quantised counts repeat their peak codes but thin out toward them.
        let (c, s) = counts(0.0, 5000);
        assert_eq!(measured_adc_range(&c, &s), None);
    }

    #[test]
    fn a_still_shaft_has_no_rail() {
        // 12-bit offset-binary counts at rest at 60 degrees, noise-free: each channel holds
        // its one value (an extreme of the capture) throughout, the other never moving.
        let (c, s) = (vec![2048.0 + 900.0; 20_000], vec![2048.0 + 1559.0; 20_000]);
        assert_eq!(measured_adc_range(&c, &s), None);
        // Still, then turning into a rail: the rail is found once the other channel moves.
        let (mut c, mut s) = counts(400.0, 5000);
        c.splice(0..0, [c[0]; 100]);
        s.splice(0..0, [s[0]; 100]);
        assert_eq!(measured_adc_range(&c, &s).map(|r| r.1), Some(4095.0));
    }

    #[test]
    fn too_few_values_measure_nothing() {
        assert_eq!(measured_adc_range(&[], &[]), None);
        assert_eq!(measured_adc_range(&[1.0; 8], &[1.0; 8]), None);
        assert_eq!(measured_adc_range(&[f64::NAN, 2.0], &[2.0, f64::NAN]), None);
    }
}
