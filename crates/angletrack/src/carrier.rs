//! The carrier frequency of a resolver's raw windings, measured in the capture itself, so
//! that a declared carrier or sample ratio that contradicts it is refused (`docs/theory.md
//! §13`).
//!
//! The windings are `y_c = A cos(theta) c(t)` and `y_s = A sin(theta) c(t)` for the carrier
//! `c(t) = sin(2 pi f t - d)`: their squares sum to `A^2 c(t)^2 = A^2 (1 - cos(4 pi f t -
//! 2 d)) / 2`, a tone at twice the carrier whatever the shaft does (the angle modulation
//! cancels). The measurement times the upward zero crossings of that tone (each channel's
//! mean removed first, so that an offset adds nothing at twice the carrier), with
//! hysteresis against noise, and averages the crossing intervals near their median, so
//! that a stretch without carrier (an excitation fault) does not count as a long period.

/// The median interval's fraction within which crossing intervals are averaged.
const INTERVAL_TOLERANCE: f64 = 0.2;

/// The fewest crossing intervals a measurement averages.
const MIN_INTERVALS: usize = 8;

/// The carrier frequency of the raw windings `y_c`, `y_s` (equal lengths, any offset) in
/// cycles per sample: half the rate of the upward zero crossings of `y_c^2 + y_s^2`, each
/// channel's mean removed. `None` when the samples hold fewer than 8 clean crossing
/// intervals, or fewer than half of its intervals near their median (too short, no
/// carrier, or fewer than about 5 samples per carrier period, where the tone at twice the
/// carrier is not resolved).
///
/// ```
/// use angletrack::measured_carrier_cycles_per_sample;
/// // A 10 kHz carrier at 160 kHz, 1 % off: 10.1 kHz, the shaft turning.
/// let n = 4000;
/// let (mut y_c, mut y_s) = (vec![0.0; n], vec![0.0; n]);
/// for k in 0..n {
///     let t = k as f64 / 160e3;
///     let carrier = (2.0 * std::f64::consts::PI * 10.1e3 * t).sin();
///     let theta = 2.0 * std::f64::consts::PI * 50.0 * t;
///     y_c[k] = 2048.0 + 1800.0 * theta.cos() * carrier;
///     y_s[k] = 2048.0 + 1800.0 * theta.sin() * carrier;
/// }
/// let f = measured_carrier_cycles_per_sample(&y_c, &y_s).unwrap() * 160e3;
/// assert!((f / 10.1e3 - 1.0).abs() < 1e-3, "{f}");
/// ```
pub fn measured_carrier_cycles_per_sample(y_c: &[f64], y_s: &[f64]) -> Option<f64> {
    cycles_of_power(&centred_power(y_c, y_s))
}

/// The windings' power about their means, sample by sample, over the samples both have:
/// `(y_c - mean_c)^2 + (y_s - mean_s)^2`, whose mean is `A^2 / 2` at every shaft angle for
/// the carrier amplitude `A` (the tone at twice the carrier about it).
pub(crate) fn centred_power(y_c: &[f64], y_s: &[f64]) -> Vec<f64> {
    let n = y_c.len().min(y_s.len());
    let (y_c, y_s) = (&y_c[..n], &y_s[..n]);
    let (mean_c, mean_s) = (mean(y_c), mean(y_s));
    y_c.iter()
        .zip(y_s)
        .map(|(c, s)| (c - mean_c).powi(2) + (s - mean_s).powi(2))
        .collect()
}

/// The mean of `values` (0 for none).
pub(crate) fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

/// [`measured_carrier_cycles_per_sample`] from the windings' [`centred_power`].
pub(crate) fn cycles_of_power(power: &[f64]) -> Option<f64> {
    let n = power.len();
    if n < 2 {
        return None;
    }
    let level = mean(power);
    if !(level.is_finite() && level > 0.0) {
        return None;
    }
    // The tone's amplitude is the mean power itself (A^2 / 2 about A^2 / 2): a quarter of it
    // is far above the noise.
    let hysteresis = 0.25 * level;
    let mut crossings = Vec::new();
    let mut armed = false;
    for k in 1..n {
        let (before, after) = (power[k - 1] - level, power[k] - level);
        if before < -hysteresis {
            armed = true;
        }
        if armed && before < 0.0 && after >= 0.0 {
            crossings.push((k - 1) as f64 + before / (before - after));
            armed = false;
        }
    }
    let mut intervals: Vec<f64> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
    if intervals.len() < MIN_INTERVALS {
        return None;
    }
    let mut sorted = intervals.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let all = intervals.len();
    intervals.retain(|i| (i / median - 1.0).abs() <= INTERVAL_TOLERANCE);
    // A carrier's crossings are regular: most intervals are near the median (noise alone
    // leaves a minority there).
    if intervals.len() < MIN_INTERVALS || 2 * intervals.len() < all {
        return None;
    }
    let tone_period = intervals.iter().sum::<f64>() / intervals.len() as f64;
    // Below about 5 samples per carrier period the tone at twice the carrier is sampled
    // below 2.5 per cycle and its crossings are not its own.
    (tone_period >= 2.5).then(|| 0.5 / tone_period)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn windings(
        samples_per_period: f64,
        n: usize,
        lost: core::ops::Range<usize>,
    ) -> (Vec<f64>, Vec<f64>) {
        let mut noise = 12345_u64;
        let mut next = || {
            noise = noise
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            (noise >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        (0..n)
            .map(|k| {
                let phase = 2.0 * std::f64::consts::PI * k as f64 / samples_per_period - 0.6;
                let carrier = if lost.contains(&k) { 0.0 } else { phase.sin() };
                let theta = 0.3 + 2.0 * std::f64::consts::PI * 50.0 * k as f64 / 160e3;
                (
                    2048.0 + 1800.0 * theta.cos() * carrier + 2.0 * next(),
                    2000.0 + 1750.0 * theta.sin() * carrier + 2.0 * next(),
                )
            })
            .unzip()
    }

    #[test]
    fn the_carrier_is_measured_through_the_angle_modulation_imbalance_and_noise() {
        for samples_per_period in [6.0, 9.6, 15.0, 16.0, 16.0 * 1.005, 64.0] {
            let (c, s) = windings(samples_per_period, 16_000, 0..0);
            let measured = measured_carrier_cycles_per_sample(&c, &s).unwrap();
            let error = measured * samples_per_period - 1.0;
            assert!(error.abs() < 2e-4, "{samples_per_period}: {error}");
        }
    }

    #[test]
    fn a_stretch_without_carrier_does_not_lengthen_the_period() {
        let (c, s) = windings(16.0, 16_000, 4000..5600);
        let measured = measured_carrier_cycles_per_sample(&c, &s).unwrap();
        assert!((measured * 16.0 - 1.0).abs() < 2e-4, "{measured}");
    }

    #[test]
    fn no_carrier_or_too_few_samples_per_period_measure_nothing() {
        let (c, s) = windings(16.0, 16_000, 0..16_000);
        assert_eq!(measured_carrier_cycles_per_sample(&c, &s), None);
        let (c, s) = windings(4.0, 16_000, 0..0);
        assert_eq!(measured_carrier_cycles_per_sample(&c, &s), None);
        assert_eq!(measured_carrier_cycles_per_sample(&c[..40], &s[..40]), None);
    }
}
