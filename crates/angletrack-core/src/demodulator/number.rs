//! The arithmetic a [`Demodulator`](crate::Demodulator) runs in (`docs/theory.md §13`): the
//! sums of one segment of ADC samples, the window's offset-free and normalised components,
//! and the products of the carrier loop's phase detector, for `f32`, `f64` and `i16`
//! samples (fixed point: a Q10 sine table, `i32` sums and window values, exact 64-bit
//! products of 32-bit values, no division). The demodulator's logic is written once over this trait.

use core::fmt::Debug;
use core::ops::AddAssign;

use crate::fixed::{round_to_i64, taylor_sin, wide_product};
use crate::real::{ChainNumber, Float};

/// Entries of the reference sine table per turn: the index is the top 8 bits of the
/// carrier loop's phase.
pub(crate) const TABLE_STEPS: usize = 256;
/// The table's length: one turn and a quarter, so that `cos` is the entry 64 further.
pub(crate) const TABLE_LEN: usize = TABLE_STEPS + TABLE_STEPS / 4;

/// `sin(2 pi k / 256)` for `k` in `0..320`, in `f64`.
const SINE_F64: [f64; TABLE_LEN] = sine_f64();
/// The same in `f32`.
static SINE_F32: [f32; TABLE_LEN] = sine_f32();
/// The same in `f64` (a `static`: one copy in the image).
static SINE_F64_STATIC: [f64; TABLE_LEN] = SINE_F64;
/// The same in Q10 (`round(1024 sin)`): a sample of 16 bits times an entry fits 26 bits,
/// and a segment of up to 48 of them an `i32` (`docs/theory.md §13`).
static SINE_Q10: [i16; TABLE_LEN] = sine_q10();

/// The fixed-point output unit: a pair's envelope 1 is this many counts (Q14), so that an
/// envelope of up to 2 fits an `i16`.
pub const FIXED_PAIR_UNIT: i16 = 1 << 14;

const fn sine_f64() -> [f64; TABLE_LEN] {
    let mut table = [0.0; TABLE_LEN];
    let mut k = 0;
    while k < TABLE_LEN {
        // Reduced to [-pi, pi), where the series is accurate.
        let step = (k % TABLE_STEPS) as i64;
        let step = if step >= 128 { step - 256 } else { step };
        table[k] = taylor_sin(core::f64::consts::TAU * (step as f64) / (TABLE_STEPS as f64));
        k += 1;
    }
    table
}

const fn sine_f32() -> [f32; TABLE_LEN] {
    let mut table = [0.0; TABLE_LEN];
    let mut k = 0;
    while k < TABLE_LEN {
        table[k] = SINE_F64[k] as f32;
        k += 1;
    }
    table
}

const fn sine_q10() -> [i16; TABLE_LEN] {
    let mut table = [0; TABLE_LEN];
    let mut k = 0;
    while k < TABLE_LEN {
        table[k] = round_to_i64(1024.0 * SINE_F64[k]) as i16;
        k += 1;
    }
    table
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
    impl Sealed for i16 {}
}

/// A number type the [`Demodulator`](crate::Demodulator) runs in: `f32` (firmware with an
/// FPU), `f64` (hosts) or `i16` (fixed point, for cores without an FPU; the pairs are then
/// Q14, envelope 1 = [`FIXED_PAIR_UNIT`], for the fixed-point observer).
///
/// Sealed; the methods are the arithmetic the demodulator's one implementation needs, each
/// written once per type.
pub trait DemodulatorNumber:
    sealed::Sealed + ChainNumber + Copy + Debug + PartialEq + Default + Send + Sync + 'static
{
    /// The float type of the settings and of the diagnostics (`f32` for `f32` and `i16`).
    type Real: Float;
    /// A segment's sum of samples or of products of samples and the reference.
    #[doc(hidden)]
    type Sum: Copy + Debug + PartialEq + Default + AddAssign + Send + Sync;
    /// A window's values and the products of pair components.
    #[doc(hidden)]
    type Wide: Copy + Debug + PartialEq + PartialOrd + Default + Send + Sync;
    /// The most ADC samples per carrier period the type's sums hold without overflow.
    const MAX_SAMPLES_PER_PERIOD: u32;

    /// The reference sine table, [`TABLE_LEN`] entries.
    #[doc(hidden)]
    fn sine_table() -> &'static [Self; TABLE_LEN];
    /// `sum += x r`.
    #[doc(hidden)]
    fn mac(sum: &mut Self::Sum, x: Self, r: Self);
    /// `sum += x`.
    #[doc(hidden)]
    fn accumulate(sum: &mut Self::Sum, x: Self);
    /// A winding's sample as it is summed, and a word whose sign bit is set when `x` is
    /// more than `half_span` from `centre`: the words of a segment's samples are ORed, one
    /// branch-free operation per sample (a NaN is caught by the window's power instead).
    /// The floats sum `x - centre` (the subtraction the clipping test makes anyway: smaller
    /// sums, less rounding); the fixed point sums `x` (its range bounds the sums).
    #[doc(hidden)]
    fn prepare(x: Self, centre: Self, half_span: Self) -> (Self, u32);
    /// A segment's sum of products of samples and the reference in the unit of a window's
    /// (the same for the floats; rounded to units of `2^3` for `i16`).
    #[doc(hidden)]
    fn product_sum(x: Self::Sum) -> Self::Sum;
    /// `false` for a window value that is NaN or infinite.
    #[doc(hidden)]
    fn is_finite(x: Self::Wide) -> bool;
    /// A segment's sum as a window's.
    #[doc(hidden)]
    fn widen(x: Self::Sum) -> Self::Wide;
    /// `acc + x`: a segment's sum into a window's.
    #[doc(hidden)]
    fn add_sum(acc: Self::Wide, x: Self::Sum) -> Self::Wide;
    /// `acc + 2 x`: a segment's sum into a window's at weight 2.
    #[doc(hidden)]
    fn add_twice(acc: Self::Wide, x: Self::Sum) -> Self::Wide;
    /// The reciprocal of a window's weight (its count of samples, doubled), in the form
    /// [`DemodulatorNumber::component`] takes.
    #[doc(hidden)]
    fn per_weight(weight: u32) -> Self::Wide;
    /// A channel's component (in-phase or quadrature) with the channel's mean over the
    /// window removed and divided by the window's weight: `(xr - x r / w) / w` (for the fixed
    /// point, times a positive factor common to a window's components: their ratio and signs
    /// are what is used).
    #[doc(hidden)]
    fn component(
        xr: Self::Wide,
        x: Self::Wide,
        r: Self::Wide,
        per_weight: Self::Wide,
    ) -> Self::Wide;
    /// A channel's mean over the window, `x / w`, in the form
    /// [`DemodulatorNumber::pair_component`] takes.
    #[doc(hidden)]
    fn mean(x: Self::Wide, per_weight: Self::Wide) -> Self::Wide;
    /// The factor from a window's sums to the pair's unit: `gain / w` (`gain` from
    /// [`DemodulatorNumber::pair_gain`]), one per window.
    #[doc(hidden)]
    fn window_scale(per_weight: Self::Wide, gain: Self::Wide) -> Self::Wide;
    /// A winding's component in the pair's unit: `(xr - mean r) gain / w`, with `mean`
    /// from [`DemodulatorNumber::mean`] and `scale` from
    /// [`DemodulatorNumber::window_scale`].
    #[doc(hidden)]
    fn pair_component(xr: Self::Wide, mean: Self::Wide, r: Self::Wide, scale: Self::Wide) -> Self;
    /// `-x` (saturated for `i16`).
    #[doc(hidden)]
    fn negate(x: Self) -> Self;
    /// `a b` of two pair components.
    #[doc(hidden)]
    fn product(a: Self, b: Self) -> Self::Wide;
    /// `a + b`.
    #[doc(hidden)]
    fn add(a: Self::Wide, b: Self::Wide) -> Self::Wide;
    /// `a - b`.
    #[doc(hidden)]
    fn sub(a: Self::Wide, b: Self::Wide) -> Self::Wide;
    /// A window value or a product of pair components times a fraction in [-1, 1] (from
    /// [`DemodulatorNumber::fraction`]).
    #[doc(hidden)]
    fn times_fraction(a: Self::Wide, fraction: Self::Wide) -> Self::Wide;
    /// `num / den` in Q31 (`2^31` = 1), saturated to `i32`; 0 unless `den > 0`.
    #[doc(hidden)]
    fn ratio_q31(num: Self::Wide, den: Self::Wide) -> i32;
    /// A pair value in the pair's unit as a float (1 = envelope 1), for diagnostics.
    fn to_real(x: Self) -> Self::Real;
    /// A window value as a float (any common scale), for diagnostics.
    #[doc(hidden)]
    fn wide_to_real(x: Self::Wide) -> Self::Real;
    /// [`Demodulator::new`](crate::Demodulator::new): the type's `const` constructor.
    #[doc(hidden)]
    fn demodulator(
        settings: crate::DemodulatorSettings<Self::Real>,
    ) -> Result<crate::Demodulator<Self>, crate::ConfigError>;
}

macro_rules! float_number {
    ($t:ident, $table:ident) => {
        impl DemodulatorNumber for $t {
            type Real = $t;
            type Sum = $t;
            type Wide = $t;
            const MAX_SAMPLES_PER_PERIOD: u32 = 1 << 16;

            #[inline(always)]
            fn sine_table() -> &'static [Self; TABLE_LEN] {
                &$table
            }
            #[inline(always)]
            fn mac(sum: &mut $t, x: $t, r: $t) {
                *sum += x * r;
            }
            #[inline(always)]
            fn accumulate(sum: &mut $t, x: $t) {
                *sum += x;
            }
            #[inline(always)]
            fn prepare(x: $t, centre: $t, half_span: $t) -> ($t, u32) {
                let x = x - centre;
                // The sign bit of the float; its top 32 bits for `f64`.
                let clip = ((half_span - x.abs()).to_bits()
                    >> (8 * core::mem::size_of::<$t>() - 32)) as u32;
                (x, clip)
            }
            #[inline(always)]
            fn is_finite(x: $t) -> bool {
                Float::is_finite(x)
            }
            #[inline(always)]
            fn product_sum(x: $t) -> $t {
                x
            }
            #[inline(always)]
            fn widen(x: $t) -> $t {
                x
            }
            #[inline(always)]
            fn add_sum(acc: $t, x: $t) -> $t {
                acc + x
            }
            #[inline(always)]
            fn add_twice(acc: $t, x: $t) -> $t {
                acc + (x + x)
            }
            #[inline(always)]
            fn per_weight(weight: u32) -> $t {
                1.0 / weight as $t
            }
            #[inline(always)]
            fn component(xr: $t, x: $t, r: $t, per_weight: $t) -> $t {
                (xr - x * r * per_weight) * per_weight
            }
            #[inline(always)]
            fn mean(x: $t, per_weight: $t) -> $t {
                x * per_weight
            }
            #[inline(always)]
            fn window_scale(per_weight: $t, gain: $t) -> $t {
                per_weight * gain
            }
            #[inline(always)]
            fn pair_component(xr: $t, mean: $t, r: $t, scale: $t) -> $t {
                (xr - mean * r) * scale
            }
            #[inline(always)]
            fn negate(x: $t) -> $t {
                -x
            }
            #[inline(always)]
            fn product(a: $t, b: $t) -> $t {
                a * b
            }
            #[inline(always)]
            fn add(a: $t, b: $t) -> $t {
                a + b
            }
            #[inline(always)]
            fn sub(a: $t, b: $t) -> $t {
                a - b
            }
            #[inline(always)]
            fn times_fraction(a: $t, fraction: $t) -> $t {
                a * fraction
            }
            #[inline(always)]
            fn ratio_q31(num: $t, den: $t) -> i32 {
                if den > 0.0 {
                    // `as` saturates, and gives 0 for NaN.
                    (num / den * 2_147_483_648.0) as i32
                } else {
                    0
                }
            }
            fn to_real(x: $t) -> $t {
                x
            }
            fn wide_to_real(x: $t) -> $t {
                x
            }
            fn demodulator(
                settings: crate::DemodulatorSettings<$t>,
            ) -> Result<crate::Demodulator<$t>, crate::ConfigError> {
                crate::Demodulator::<$t>::new_const(settings)
            }
        }
    };
}

float_number!(f32, SINE_F32);
float_number!(f64, SINE_F64_STATIC);

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
    let removed = (wide_product(mean, r) + (1 << (14 + PRODUCT_SHIFT))) >> (15 + PRODUCT_SHIFT);
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
