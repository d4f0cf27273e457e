//! The roundness check a capture's first samples support when no amplitude is stated
//! (`docs/guide/diagnostics.md`, "The roundness check"): the monitor flags a pair off the
//! circle of the nominal amplitude, which needs a circle to compare with. A measured one is
//! trusted in two cases only, so that a healthy sensor is never flagged for a shape it has
//! from the start (an imbalance or offsets a calibration would remove, or a standstill's
//! point on it):
//!
//! * the first samples go all round (each eighth of a turn holds [`OCTANT_SHARE`] of
//!   them or more), and the median magnitude of each eighth is within
//!   [`ROUND_HEAD_SPREAD`] of their mean: a round sensor centred on zero, whose pair
//!   leaving that circle later is a fault (a channel dying, an imbalance or quadrature
//!   growing). The circle is the eighths' mean;
//! * the pairs lie along a line: across it they swing at most [`DEAD_CHANNEL_FRACTION`] of
//!   what they swing along it, centred on zero along it, and their magnitudes are not
//!   round (the 10th percentile below 3/4 of the 90th: not an arc of a turning shaft). A
//!   dead, open, stuck or shorted channel from the start, beyond any calibration (its
//!   bounds hold a 20 % imbalance). The circle is the swing along the line (the healthy
//!   channel's amplitude beside a dead or stuck one).

use std::f64::consts::PI;

/// The share of the first samples each eighth of a turn must hold for a round head.
pub const OCTANT_SHARE: f64 = 0.04;

/// The largest spread of a round head's eighths' median magnitudes about their mean, as a
/// fraction of it: about an 8 % imbalance, or 3 % offsets, at most.
pub const ROUND_HEAD_SPREAD: f64 = 0.03;

/// The swing across a line of a dead channel's pairs at most, as a fraction of their swing
/// along it.
pub const DEAD_CHANNEL_FRACTION: f64 = 0.25;

/// The roundness tolerance on a measured circle: 0.1 (as on a stated amplitude), or 8 times
/// the signal's noise `noise` (as a fraction of the amplitude) where that is more, so that
/// noise alone does not leave the band (the tracking-error level's rule).
fn tolerance(noise: f64) -> f64 {
    (8.0 * noise).max(0.1)
}

/// Half the span of `values` from their 1st to their 99th percentile, and its centre.
fn swing(mut values: Vec<f64>) -> Option<(f64, f64)> {
    values.sort_unstable_by(f64::total_cmp);
    let last = values.len().checked_sub(1)?;
    let (low, high) = (values[last / 100], values[last - last / 100]);
    Some((0.5 * (high - low), 0.5 * (high + low)))
}

/// The circle of a round head (see the module), if `pairs` are one.
fn round_circle(pairs: &[(f64, f64)]) -> Option<f64> {
    let mut eighths: [Vec<f64>; 8] = Default::default();
    for &(c, s) in pairs {
        let eighth = ((s.atan2(c) + PI) * (4.0 / PI)) as usize;
        eighths[eighth.min(7)].push(c.hypot(s));
    }
    let mut medians = [0.0; 8];
    for (median, magnitudes) in medians.iter_mut().zip(eighths.iter_mut()) {
        if (magnitudes.len() as f64) < OCTANT_SHARE * pairs.len() as f64 {
            return None;
        }
        magnitudes.sort_unstable_by(f64::total_cmp);
        *median = super::calibrated::median(magnitudes)?;
    }
    let mean = medians.iter().sum::<f64>() / 8.0;
    let round = medians
        .iter()
        .all(|m| (m - mean).abs() <= ROUND_HEAD_SPREAD * mean);
    (round && mean > 0.0).then_some(mean)
}

/// The circle of pairs along a line (see the module), if `pairs` are such.
fn line_circle(pairs: &[(f64, f64)]) -> Option<f64> {
    let n = pairs.len() as f64;
    let (mx, my) = pairs
        .iter()
        .fold((0.0, 0.0), |(x, y), (c, s)| (x + c / n, y + s / n));
    let (sxx, syy, sxy) = pairs.iter().fold((0.0, 0.0, 0.0), |(a, b, d), (c, s)| {
        let (x, y) = (c - mx, s - my);
        (a + x * x, b + y * y, d + x * y)
    });
    // The major axis of the pairs' spread.
    let direction = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let (sin, cos) = direction.sin_cos();
    let along = swing(pairs.iter().map(|(c, s)| c * cos + s * sin).collect())?;
    let across = swing(pairs.iter().map(|(c, s)| s * cos - c * sin).collect())?;
    let mut magnitudes: Vec<f64> = pairs.iter().map(|(c, s)| c.hypot(*s)).collect();
    magnitudes.sort_unstable_by(f64::total_cmp);
    let last = magnitudes.len().checked_sub(1)?;
    let not_round = magnitudes[last / 10] < 0.75 * magnitudes[last - last / 10];
    let line = across.0 <= DEAD_CHANNEL_FRACTION * along.0 && along.1.abs() <= 0.1 * along.0;
    (line && not_round && along.0 > 0.0).then_some(along.0)
}

/// The circle `(nominal amplitude, magnitude tolerance)` that the first samples `pairs`
/// (as [`capture_fault_thresholds`](crate::capture_fault_thresholds) takes them), of angle
/// noise `noise`, support (see the module); `None` where they support none.
pub(super) fn measured_circle(pairs: &[(f64, f64)], noise: f64) -> Option<(f64, f64)> {
    round_circle(pairs)
        .or_else(|| line_circle(pairs))
        .map(|nominal| (nominal, tolerance(noise)))
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
        // An imbalance of 10 %, an offset of 6 % of the amplitude, a 2.5 V bias: no circle.
        assert_eq!(
            measured_circle(&pairs(4096, 3.0, 0.3, (1.0, 1.10), (0.0, 0.0)), 0.001),
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

    #[test]
    fn a_standstill_then_a_turn_of_an_imbalanced_sensor_gives_none() {
        // Half the head still at the sensor's largest magnitude, then one turn: every eighth
        // of a turn is covered, but their medians spread by the 10 % imbalance.
        let mut head = vec![(0.0, 1.1); 2048];
        head.extend(pairs(2048, 1.0, 0.0, (1.0, 1.1), (0.0, 0.0)));
        assert_eq!(measured_circle(&head, 0.001), None);
        // Three quarters of a turn after the standstill: an eighth is not covered.
        let mut head = vec![(1.0, 0.0); 2048];
        head.extend(pairs(2048, 0.75, 0.0, (1.0, 1.0), (0.0, 0.0)));
        assert_eq!(measured_circle(&head, 0.001), None);
    }

    #[test]
    fn a_stuck_or_shorted_channel_from_the_start_gives_the_swing_along_its_line() {
        // Stuck at 0.3 of the amplitude: the healthy channel's swing.
        let stuck: Vec<(f64, f64)> = pairs(4096, 3.0, 0.3, (0.0, 1800.0), (540.0, 0.0));
        let (nominal, _) = measured_circle(&stuck, 0.001).unwrap();
        assert!((nominal - 1800.0).abs() < 2.0, "{nominal}");
        // Shorted to the other channel: the pairs on the diagonal, sqrt 2 times as long.
        let shorted: Vec<(f64, f64)> = pairs(4096, 3.0, 0.3, (1.0, 1.0), (0.0, 0.0))
            .into_iter()
            .map(|(c, _)| (c, c))
            .collect();
        let (nominal, _) = measured_circle(&shorted, 0.001).unwrap();
        assert!(
            (nominal - std::f64::consts::SQRT_2).abs() < 2e-3,
            "{nominal}"
        );
    }
}
