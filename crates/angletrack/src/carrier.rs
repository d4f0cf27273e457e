//! The carrier frequency of a resolver's raw windings, measured in the capture itself, so
//! that a declared carrier or sample ratio that contradicts it is refused (`docs/theory.md
//! §13`).
//!
//! The windings are `y_c = A cos(theta) c(t)` and `y_s = A sin(theta) c(t)` for the carrier
//! `c(t)`: their squares sum to `A^2 c(t)^2` whatever the shaft does (the angle modulation
//! cancels), periodic at the carrier's period `T`; for a sine carrier a tone at twice the
//! carrier, `A^2 (1 - cos(4 pi f t - 2 d)) / 2`. A carrier harmonic (a 2nd harmonic from an
//! excitation amplifier) adds components at the carrier and three times it, which move
//! the tone's zero crossings by up to a tenth of its period and hide some of them: so the
//! measurement reads the period from the power's autocorrelation (each channel's mean
//! removed first, so that an offset adds nothing), whose peaks sit at the multiples of
//! `T / 2` (of `T` where a harmonic makes the halves differ) however the waveform is
//! shaped: the first peak near `T / 2`, then the peak near ever larger multiples of it,
//! each predicted from the last, the last one divided by its multiple. A stretch without
//! carrier (an excitation fault) lowers the peaks, not where they are.

/// A peak of the power's normalised autocorrelation is the carrier's only above this: white
/// noise stays near 0; a sine carrier gives 1 at `T / 2`, one with a 15 % 2nd harmonic 0.7,
/// but at 5 samples a period (`T / 2` of 2.5 samples) the whole lags either side read 0.31.
const PEAK_CORRELATION: f64 = 0.25;

/// The fewest carrier periods a measurement spans.
const MIN_PERIODS: f64 = 8.0;

/// The carrier frequency of the raw windings `y_c`, `y_s` (equal lengths, any offset) in
/// cycles per sample: the period of `y_c^2 + y_s^2` (each channel's mean removed) read from
/// its autocorrelation, any carrier harmonics included. `None` when the samples span fewer
/// than 8 carrier periods, when the power has no period (no carrier: its autocorrelation
/// never reaches 0.25), or below 5 samples per carrier period (where the tone at twice the
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
    let level = mean(power);
    if n < 16 || !(level.is_finite() && level > 0.0) {
        return None;
    }
    let x: Vec<f64> = power.iter().map(|p| p - level).collect();
    let energy = x.iter().map(|v| v * v).sum::<f64>() / n as f64;
    if !(energy.is_finite() && energy > 0.0) {
        return None;
    }
    // The normalised autocorrelation at a whole lag (below n).
    let correlation = |lag: usize| {
        let products = x.iter().zip(&x[lag..]).map(|(a, b)| a * b).sum::<f64>();
        products / (n - lag) as f64 / energy
    };
    // The first peak above the threshold: half the carrier's period. Its lag at most a
    // sixteenth of the samples (8 periods).
    let longest = n / 16;
    let (mut before, mut at) = (correlation(1), correlation(2));
    let mut first = None;
    for lag in 2..longest {
        let after = correlation(lag + 1);
        if at > PEAK_CORRELATION && at >= before && at >= after {
            first = Some(lag as f64 + vertex(before, at, after));
            break;
        }
        (before, at) = (at, after);
    }
    let mut half_period = first?;
    // Refined on the peak near ever larger multiples of it, each within a sample or two of
    // its prediction, up to half the samples.
    let mut multiple = 2.0;
    while multiple * half_period + 2.0 < n as f64 / 2.0 {
        let predicted = multiple * half_period;
        let (low, high) = (
            predicted.round() as usize - 2,
            predicted.round() as usize + 2,
        );
        let values: Vec<f64> = (low..=high).map(correlation).collect();
        let best = (1..values.len() - 1)
            .max_by(|&a, &b| values[a].total_cmp(&values[b]))
            .unwrap_or(2);
        let lag = (low + best) as f64 + vertex(values[best - 1], values[best], values[best + 1]);
        half_period = lag / multiple;
        multiple *= 2.0;
    }
    let period = 2.0 * half_period;
    (period >= 5.0 && n as f64 >= MIN_PERIODS * period).then(|| 1.0 / period)
}

/// The offset (within half a sample) of the vertex of the parabola through three equally
/// spaced values, from the middle one.
fn vertex(before: f64, at: f64, after: f64) -> f64 {
    let curvature = before - 2.0 * at + after;
    if curvature < 0.0 {
        (0.5 * (before - after) / curvature).clamp(-0.5, 0.5)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn windings(
        samples_per_period: f64,
        n: usize,
        lost: core::ops::Range<usize>,
    ) -> (Vec<f64>, Vec<f64>) {
        windings_with_harmonic(samples_per_period, n, lost, 0.0)
    }

    /// The windings of a carrier with a 2nd harmonic of relative amplitude `harmonic`.
    fn windings_with_harmonic(
        samples_per_period: f64,
        n: usize,
        lost: core::ops::Range<usize>,
        harmonic: f64,
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
                let carrier = if lost.contains(&k) {
                    0.0
                } else {
                    phase.sin() + harmonic * (2.0 * phase + 0.4).sin()
                };
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
        for samples_per_period in [5.2, 6.0, 9.6, 15.0, 16.0, 16.0 * 1.005, 64.0] {
            let (c, s) = windings(samples_per_period, 16_000, 0..0);
            let measured = measured_carrier_cycles_per_sample(&c, &s).unwrap();
            let error = measured * samples_per_period - 1.0;
            assert!(error.abs() < 2e-4, "{samples_per_period}: {error}");
        }
    }

    #[test]
    fn a_carrier_harmonic_does_not_move_the_measurement() {
        for samples_per_period in [5.2, 6.0, 9.6, 16.0] {
            let (c, s) = windings_with_harmonic(samples_per_period, 16_000, 0..0, 0.15);
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
