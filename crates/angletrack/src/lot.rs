//! Screening a production lot: the units of a lot whose value of one quantity (an offset, a
//! residual error) lies beyond stated limits or beyond the lot's own spread.

/// The factor that makes the median absolute deviation of a normal population an estimate
/// of its standard deviation.
pub(crate) const MAD_TO_STD: f64 = 1.482_602_218_505_602;

/// The outliers of a lot's `values` (one per unit; NaN for a unit without one, never an
/// outlier): those below `low` or above `high` when given, and those further from the
/// lot's median than `spread_factor` times its scaled median absolute deviation (about
/// standard deviations for a normal lot, unmoved by the outliers themselves). Returns the
/// median, the scaled deviation (NaN without a finite value) and one flag per value.
///
/// ```
/// let offsets = [0.010, 0.012, 0.009, 0.011, 0.010, 0.080, f64::NAN];
/// let (median, scale, flags) = angletrack::lot::outliers(&offsets, 5.0, None, Some(0.05));
/// assert!((median - 0.0105).abs() < 1e-15);
/// assert!(scale > 0.0 && scale < 0.003);
/// assert_eq!(flags, [false, false, false, false, false, true, false]);
/// ```
pub fn outliers(
    values: &[f64],
    spread_factor: f64,
    low: Option<f64>,
    high: Option<f64>,
) -> (f64, f64, Vec<bool>) {
    let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    let median = median_of(&mut finite);
    let mut deviations: Vec<f64> = finite.iter().map(|v| (v - median).abs()).collect();
    let scale = MAD_TO_STD * median_of(&mut deviations);
    let flags = values
        .iter()
        .map(|&v| {
            v.is_finite()
                && (low.is_some_and(|l| v < l)
                    || high.is_some_and(|h| v > h)
                    || (v - median).abs() > spread_factor * scale)
        })
        .collect();
    (median, scale, flags)
}

/// The median of `values` (reordered); NaN for none.
pub(crate) fn median_of(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_unstable_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}
