//! The roundness check a capture's first samples support when no amplitude is stated
//! (`docs/guide/diagnostics.md`, "The roundness check"): the monitor flags a pair off the
//! circle of the nominal amplitude, which needs a circle to compare with. A measured one is
//! trusted in two cases only, so that a healthy sensor is never flagged for a shape it has
//! from the start (an imbalance or offsets a calibration would remove):
//!
//! * the first samples go round a circle centred on zero, their magnitudes within
//!   [`ROUND_HEAD_SPREAD`] of their median: a round sensor, whose pair leaving the circle
//!   later is a fault (a channel dying, an imbalance or quadrature growing);
//! * one channel swings about zero while the other stays within
//!   [`DEAD_CHANNEL_FRACTION`] of its swing, centred on zero too: a dead, open or shorted
//!   channel from the start, beyond any calibration (its bounds hold a 20 % imbalance). The
//!   circle is the healthy channel's.

/// The largest spread of the first samples' magnitudes about their median (the 10th and
/// 90th percentiles, as a fraction of it) of a round head; and of its centre's distance from
/// zero.
pub const ROUND_HEAD_SPREAD: f64 = 0.05;

/// The swing of a dead channel at most, as a fraction of the healthy channel's.
pub const DEAD_CHANNEL_FRACTION: f64 = 0.25;

/// The roundness tolerance on a measured circle: 0.1 (as on a stated amplitude), or 8 times
/// the signal's noise `noise` (as a fraction of the amplitude) where that is more, so that
/// noise alone does not leave the band (the tracking-error level's rule).
fn tolerance(noise: f64) -> f64 {
    (8.0 * noise).max(0.1)
}

/// A channel's swing: half the span from its 1st to its 99th percentile, and its centre.
fn swing(mut values: Vec<f64>) -> Option<(f64, f64)> {
    values.sort_unstable_by(f64::total_cmp);
    let last = values.len().checked_sub(1)?;
    let (low, high) = (values[last / 100], values[last - last / 100]);
    Some((0.5 * (high - low), 0.5 * (high + low)))
}

/// The circle `(nominal amplitude, magnitude tolerance)` that the first samples `pairs`
/// (as [`capture_fault_thresholds`](crate::capture_fault_thresholds) takes them), of angle
/// noise `noise`, support (see the module); `None` where they support none.
pub(super) fn measured_circle(pairs: &[(f64, f64)], noise: f64) -> Option<(f64, f64)> {
    let mut magnitudes: Vec<f64> = pairs.iter().map(|(c, s)| c.hypot(*s)).collect();
    magnitudes.sort_unstable_by(f64::total_cmp);
    let last = magnitudes.len().checked_sub(1)?;
    let median = super::calibrated::median(&magnitudes)?;
    let (low, high) = (magnitudes[last / 10], magnitudes[last - last / 10]);
    if let Some((c, s)) = super::calibrated::lissajous_centre(pairs) {
        let centred = c.hypot(s) <= ROUND_HEAD_SPREAD * median;
        let round =
            low >= (1.0 - ROUND_HEAD_SPREAD) * median && high <= (1.0 + ROUND_HEAD_SPREAD) * median;
        if centred && round && median > 0.0 {
            return Some((median, tolerance(noise)));
        }
    }
    let (c, s) = (
        swing(pairs.iter().map(|p| p.0).collect())?,
        swing(pairs.iter().map(|p| p.1).collect())?,
    );
    let (healthy, dead) = if c.0 >= s.0 { (c, s) } else { (s, c) };
    let about_zero = |(_, centre): (f64, f64)| centre.abs() <= 0.1 * healthy.0;
    let dead_channel = dead.0 <= DEAD_CHANNEL_FRACTION * healthy.0
        && healthy.0 >= 0.5 * median
        && about_zero(healthy)
        && about_zero(dead);
    (dead_channel && healthy.0 > 0.0).then(|| (healthy.0, tolerance(noise)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` pairs of amplitudes `(a_c, a_s)` over `turns` turns from `start` (rad), offsets
    /// `(o_c, o_s)`.
    fn pairs(
        n: usize,
        turns: f64,
        start: f64,
        (a_c, a_s): (f64, f64),
        (o_c, o_s): (f64, f64),
    ) -> Vec<(f64, f64)> {
        (0..n)
            .map(|k| start + std::f64::consts::TAU * turns * k as f64 / n as f64)
            .map(|t| (o_c + a_c * t.cos(), o_s + a_s * t.sin()))
            .collect()
    }

    #[test]
    fn a_round_head_centred_on_zero_gives_its_circle() {
        let circle = measured_circle(&pairs(4096, 3.0, 0.3, (1800.0, 1800.0), (0.0, 0.0)), 0.001);
        assert_eq!(circle, Some((1800.0, 0.1)));
        // The noise widens the band: 8 times it.
        let (_, tolerance) =
            measured_circle(&pairs(4096, 3.0, 0.3, (1.0, 1.0), (0.0, 0.0)), 0.02).unwrap();
        assert!((tolerance - 0.16).abs() < 1e-12);
    }

    #[test]
    fn a_head_a_calibration_would_correct_gives_none() {
        // An imbalance of 11 %, an offset of 6 % of the amplitude, a 2.5 V bias: no circle.
        assert_eq!(
            measured_circle(&pairs(4096, 3.0, 0.3, (1.0, 1.11), (0.0, 0.0)), 0.001),
            None
        );
        assert_eq!(
            measured_circle(&pairs(4096, 3.0, 0.3, (1.0, 1.0), (0.06, 0.0)), 0.001),
            None
        );
        assert_eq!(
            measured_circle(&pairs(4096, 3.0, 0.3, (1.0, 1.0), (2.5, 2.5)), 0.001),
            None
        );
        // A head that does not go round: a quarter turn either side of zero, or about 90 degrees.
        assert_eq!(
            measured_circle(&pairs(4096, 0.25, -0.785, (1.0, 1.0), (0.0, 0.0)), 0.001),
            None
        );
        assert_eq!(
            measured_circle(&pairs(4096, 0.25, 0.785, (1.0, 1.0), (0.0, 0.0)), 0.001),
            None
        );
    }

    #[test]
    fn a_dead_channel_from_the_start_gives_the_healthy_channels_circle() {
        let dead = pairs(4096, 3.0, 0.3, (0.0, 1800.0), (0.0, 0.0));
        // The healthy channel's swing, its 1st to 99th percentiles: within 0.1 % of 1800.
        let (nominal, tolerance) = measured_circle(&dead, 0.001).unwrap();
        assert!(
            (nominal - 1800.0).abs() < 1.8 && tolerance == 0.1,
            "{nominal}"
        );
        // A quarter of the healthy swing is dead; a third is not (beyond a calibration's
        // bounds, yet not a dead channel: no circle).
        let weak = pairs(4096, 3.0, 0.3, (449.0, 1800.0), (0.0, 0.0));
        assert!(measured_circle(&weak, 0.001).is_some());
        let third = pairs(4096, 3.0, 0.3, (600.0, 1800.0), (0.0, 0.0));
        assert_eq!(measured_circle(&third, 0.001), None);
    }
}
