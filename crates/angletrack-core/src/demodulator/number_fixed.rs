//! The fixed point's arithmetic of the [`Demodulator`](crate::Demodulator)
//! (`docs/theory.md §13`): `i16` samples, the Q10 sine table, `i32` sums and window values,
//! exact 64-bit products of 32-bit values and no division; the ranges that keep each value
//! within its type.

use super::number::{DemodulatorNumber, FIXED_PAIR_UNIT, SINE_Q10, TABLE_LEN};
use crate::fixed::wide_product;

/// The fixed point's unit of a window's products of samples and the reference: `2^3` (a
/// segment's sum is rounded to it when it joins a window), so that a window's products fit an
/// `i32` (`docs/theory.md §13`).
const PRODUCT_SHIFT: u32 = 3;

/// The fixed point: `i16` samples (counts), the Q10 table, `i32` segment sums and `i32`
/// window values (the products of samples and the reference in units of `2^3`, the sums of
/// samples and of the reference exact); the means in Q15 and the pairs in Q14, through the
/// reciprocal `2^32 / w` of the window's weight `w` (from a table) and exact 64-bit products
/// of 32-bit values (`wide_product`: four 16-bit products on a Cortex-M0).
///
/// The ranges (`docs/theory.md §13`): at most 64 samples per period, and a carrier at most
/// 20 % slower ([`DemodulatorSettings::max_carrier_error`](crate::DemodulatorSettings)), so
/// at most `n = 80` samples a tracked period; a segment covers at most 7/8 of a turn (the
/// rest of a period after a correction back, `begin_segment`), at most 70 samples, and a
/// window's weight is at most `20 + 2 * 70 + 20 = 180` (below 184 with the segments' rounding
/// up), at least 4 (a sample in each of its three segments).
impl DemodulatorNumber for i16 {
    type Real = f32;
    type Sum = i32;
    type Wide = i32;
    // A segment's products: |x| <= 2^15 times the Q10 reference, whose magnitudes summed over
    // samples spaced 2 pi / n apart across at most 7/8 of a turn are at most 1024 (n / (2 pi)
    // times the integral of |sin| over 7/8 of a turn, 3.71, plus one for each of its at most
    // four monotone pieces): for n = 80, 51.2 * 1024 * 2^15 < 2^30.7, within an i32 (the test
    // `full_scale_samples_at_the_most_samples_per_period_do_not_overflow`).
    const MAX_SAMPLES_PER_PERIOD: u32 = 64;

    #[inline(always)]
    fn sine_table() -> &'static [i16; TABLE_LEN] {
        &SINE_Q10
    }
    #[inline(always)]
    fn mac(sum: &mut i32, x: i16, r: i16) {
        *sum += i32::from(x) * i32::from(r);
    }
    #[inline(always)]
    fn accumulate(sum: &mut i32, x: i16) {
        *sum += i32::from(x);
    }
    #[inline(always)]
    fn prepare(x: i16, centre: i16, half_span: i16) -> (i16, u32) {
        // Negative (the sign bit set) when x is outside [centre - half_span, centre +
        // half_span]: x - low and high - x ORed.
        let (x32, centre, half_span) = (i32::from(x), i32::from(centre), i32::from(half_span));
        let clip = ((x32 - (centre - half_span)) | (centre + half_span - x32)) as u32;
        (x, clip)
    }
    #[inline(always)]
    fn is_finite(_: i32) -> bool {
        true
    }
    #[inline(always)]
    fn product_sum(x: i32) -> i32 {
        // Rounded (half up) to units of 2^3: floor((x + 4) / 8) without the addition's
        // overflow. A window's products are then at most 2^15 * 1024 * 184 / 8 < 2^29.6 in
        // that unit; the window's sums of samples at most 2^15 * 184 < 2^23 and of the
        // reference 1024 * 184 < 2^18, exact.
        ((x >> (PRODUCT_SHIFT - 1)) + 1) >> 1
    }
    #[inline(always)]
    fn widen(x: i32) -> i32 {
        x
    }
    #[inline(always)]
    fn add_sum(acc: i32, x: i32) -> i32 {
        acc.wrapping_add(x)
    }
    #[inline(always)]
    fn add_twice(acc: i32, x: i32) -> i32 {
        acc.wrapping_add(x.wrapping_shl(1))
    }
    #[inline(always)]
    fn per_weight(weight: u32) -> i32 {
        // floor((2^32 - 1) / w) for 2^32 / w, at most 2^30 (w >= 4), from a table (a 32-bit
        // division is some 100 instructions on a Cortex-M0); the weights beyond it, which a
        // window cannot have, divided.
        match RECIPROCALS.get(weight as usize) {
            Some(&reciprocal) => reciprocal as i32,
            None => (u32::MAX / weight) as i32,
        }
    }
    #[inline(always)]
    fn component(xr: i32, x: i32, r: i32, per_weight: i32) -> i32 {
        // `xr - x r / w` in units of 2^3, not divided by w: a window's two excitation
        // components share the factor, and only their ratio and signs are used. It is
        // `sum w_k (x_k - mean) ref_k`, at most 2^16 * 1024 * 184 / 8 < 2^30.6 in magnitude
        // (and so is `I cos - Q sin` for any angle): `times_fraction` keeps it within an i32.
        centred(xr, Self::mean(x, per_weight), r)
    }
    #[inline(always)]
    fn mean(x: i32, per_weight: i32) -> i32 {
        // Q15: |x| <= 2^15 w times 2^32 / w, at most 2^47 before the shift, 2^30 after.
        (wide_product(x, per_weight) >> 17) as i32
    }
    #[inline(always)]
    fn window_scale(per_weight: i32, gain: i32) -> i32 {
        // 2^32 / w times gain < 2^24 (Q24) over 2^23: 2^9 gain / w, below 2^31 (w >= 4), so
        // that a component in units of 2^3 times it over 2^30 is the component times
        // gain / w over 2^24 (`pair_component`).
        (wide_product(per_weight, gain) >> 23) as i32
    }
    #[inline(always)]
    fn pair_component(xr: i32, mean: i32, r: i32, scale: i32) -> i16 {
        // The component is envelope * amplitude * 512 (Q10 / 2) times w; gain = 2^38 / (512
        // amplitude): the component times gain / w over 2^24 is envelope * 2^14. The centred
        // component (below 2^30.6, `component`) times the scale (below 2^31) is below 2^62.
        let v = wide_product(centred(xr, mean, r), scale) >> 30;
        v.clamp(i64::from(i16::MIN), i64::from(i16::MAX)) as i16
    }
    #[inline(always)]
    fn negate(x: i16) -> i16 {
        x.saturating_neg()
    }
    #[inline(always)]
    fn product(a: i16, b: i16) -> i32 {
        // Over 2^4: a product of two i16 is at most 2^30 in magnitude, a window's power (four
        // of them) at most 2^28, and the window's test 4 p < 3 p_last within an i32.
        (i32::from(a) * i32::from(b)) >> 4
    }
    #[inline(always)]
    fn add(a: i32, b: i32) -> i32 {
        a.wrapping_add(b)
    }
    #[inline(always)]
    fn sub(a: i32, b: i32) -> i32 {
        a.wrapping_sub(b)
    }
    #[inline(always)]
    fn times_fraction(a: i32, fraction: i32) -> i32 {
        // A Q16 fraction within [-1, 1]: at most |a| (a power, or an excitation component,
        // `component`), an i32.
        (wide_product(a, fraction) >> 16) as i32
    }
    #[inline(always)]
    fn ratio_q31(num: i32, den: i32) -> i32 {
        if den <= 0 {
            return 0;
        }
        // The detector's ratios are within [-1, 1], den <= 2^28 (four products of pair
        // components over 2^4). Without a division (some 100 instructions on a Cortex-M0):
        // den shifted up by e into [2^27, 2^28] (num with it, within +-den), its reciprocal
        // 2^42 / den from the table by its top 8 bits (to 2^-8 of the value: the loop's gain
        // that much off, its zero exact), num over 2^13 (at most 2^15) times it (at most
        // 2^15) over 2^15: the ratio in Q14.
        let num = num.max(-den).min(den);
        let (mut d, mut e) = (den as u32, 0);
        if d < 1 << 12 {
            (d, e) = (d << 16, e + 16);
        }
        if d < 1 << 20 {
            (d, e) = (d << 8, e + 8);
        }
        if d < 1 << 24 {
            (d, e) = (d << 4, e + 4);
        }
        if d < 1 << 26 {
            (d, e) = (d << 2, e + 2);
        }
        if d < 1 << 27 {
            (d, e) = (d << 1, e + 1);
        }
        let index = ((d >> 20).wrapping_sub(128)) as usize;
        let reciprocal = i32::from(RATIO_RECIPROCALS.get(index).copied().unwrap_or(1 << 14));
        let ratio = (((num << e) >> 13) * reciprocal) >> 15;
        ratio.clamp(-(1 << 14), (1 << 14) - 1) << 17
    }
    fn to_real(x: i16) -> f32 {
        f32::from(x) / f32::from(FIXED_PAIR_UNIT)
    }
    fn wide_to_real(x: i32) -> f32 {
        x as f32
    }
    fn demodulator(
        settings: crate::DemodulatorSettings<f32>,
    ) -> Result<crate::Demodulator<i16>, crate::ConfigError> {
        crate::Demodulator::<i16>::new_const(settings)
    }
}

/// A fixed-point window's component with the channel's mean removed, `xr - mean r` (`xr` in
/// units of 2^3; `mean` in Q15 and `r` the reference's sum, so `mean r / 2^18` in units of
/// 2^3, rounded): below 2^30.6 in magnitude (`component`).
#[inline(always)]
fn centred(xr: i32, mean: i32, r: i32) -> i32 {
    // |mean r| <= 2^30 * 1024 * 184 < 2^48.
    let half = 1 << (14 + PRODUCT_SHIFT);
    let removed = (wide_product(mean, r) + half) >> (15 + PRODUCT_SHIFT);
    (i64::from(xr) - removed) as i32
}

/// `floor((2^32 - 1) / w)` for the weights `w` of windows, 4 to 255 (the weights below 4,
/// which a window cannot have, as 4).
static RECIPROCALS: [u32; 256] = {
    let mut table = [0; 256];
    let mut w = 0;
    while w < 256 {
        table[w] = u32::MAX / if w < 4 { 4 } else { w as u32 };
        w += 1;
    }
    table
};

/// `2^42 / d` for `d` in [2^27, 2^28] by its top 8 bits (`d / 2^20` less 128, 0 to 128),
/// at the middle of each step, rounded: within 2^-8 of the value.
static RATIO_RECIPROCALS: [u16; 129] = {
    let mut table = [0; 129];
    let mut i = 0;
    while i < 129 {
        // 2^42 / ((128.5 + i) 2^20) = 2^23 / (257 + 2 i).
        let d = 257 + 2 * i as u32;
        table[i] = ((2 * (1 << 23) + d) / (2 * d)) as u16;
        i += 1;
    }
    table
};

#[cfg(test)]
mod tests {
    use super::{DemodulatorNumber, PRODUCT_SHIFT, centred};
    use proptest::prelude::*;

    proptest! {
        /// `centred` gives the rounded `xr - mean r / 2^18` over the values' ranges.
        #[test]
        fn centred_is_the_rounded_difference(
            xr in -(1 << 30)..(1 << 30),
            mean in -(1 << 30)..=(1 << 30),
            r in -(1 << 18)..(1 << 18),
        ) {
            let shift = 15 + PRODUCT_SHIFT;
            let removed = (i128::from(mean) * i128::from(r) + (1 << (shift - 1))) >> shift;
            prop_assert_eq!(i128::from(centred(xr, mean, r)), i128::from(xr) - removed);
        }

        /// A window's component in the pair's unit through the window's scale: the exact
        /// `d 2^9 gain / w / 2^30` to 2^-13 of it and a unit, saturated to an `i16`, for
        /// every weight and gain.
        #[test]
        fn the_scaled_component_is_the_exact_one(
            d in -(1 << 30)..(1 << 30),
            weight in 4..=184_u32,
            gain in 1..(1 << 24),
        ) {
            let per_weight = <i16 as DemodulatorNumber>::per_weight(weight);
            let scale = <i16 as DemodulatorNumber>::window_scale(per_weight, gain);
            let pair = <i16 as DemodulatorNumber>::pair_component(d, 0, 0, scale);
            let exact = (f64::from(d) * f64::from(per_weight) * f64::from(gain)
                / 2f64.powi(53))
            .clamp(f64::from(i16::MIN), f64::from(i16::MAX));
            prop_assert!(
                (f64::from(pair) - exact).abs() <= exact.abs() / 8192.0 + 1.0,
                "{} {}", pair, exact
            );
        }
    }
}
