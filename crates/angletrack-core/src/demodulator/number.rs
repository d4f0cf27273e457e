//! The arithmetic a [`Demodulator`](crate::Demodulator) runs in (`docs/theory.md §13`): the
//! sums of one segment of ADC samples, the window's offset-free and normalised components,
//! and the products of the carrier loop's phase detector, for `f32`, `f64` and `i16`
//! samples (fixed point: a Q10 sine table, `i32` sums, `i64` window values, two 32-bit
//! divisions per window). The demodulator's logic is written once over this trait.

use core::fmt::Debug;
use core::ops::AddAssign;

use crate::fixed::{round_to_i64, taylor_sin};
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
    /// window removed and divided by the window's weight: `(xr - x r / w) / w`.
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

/// The fixed point: `i16` samples (counts), the Q10 table, `i32` segment sums, `i64`
/// window values; a component is `2^32 (xr - x r / w) / w` for the weight `w`, divided by
/// the window's weight through its reciprocal `2^32 / w` (one division per window); the pairs
/// are Q14.
impl DemodulatorNumber for i16 {
    type Real = f32;
    type Sum = i32;
    type Wide = i64;
    // A segment (at most three quarters of a period) of samples of 16 bits times Q10
    // entries: 48 * 2^15 * 2^10 < 2^31.
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
    fn is_finite(_: i64) -> bool {
        true
    }
    #[inline(always)]
    fn widen(x: i32) -> i64 {
        i64::from(x)
    }
    #[inline(always)]
    fn add_sum(acc: i64, x: i32) -> i64 {
        acc + i64::from(x)
    }
    #[inline(always)]
    fn add_twice(acc: i64, x: i32) -> i64 {
        acc + 2 * i64::from(x)
    }
    #[inline(always)]
    fn per_weight(weight: u32) -> i64 {
        // (2^32 - 1) / w for 2^32 / w: a 32-bit division (a weight is at least 8: 4 samples
        // per period or more), and the difference below 2^-32 of the value.
        i64::from(u32::MAX / weight.max(1))
    }
    #[inline(always)]
    fn component(xr: i64, x: i64, r: i64, per_weight: i64) -> i64 {
        // |x| <= 2^15 w, |r| <= 2^10 w, w <= 2^8 (160 for 64 samples per period): |x r| <= 2^41,
        // then times 2^32 / w over 2^32 in two steps of 2^16, below 2^63 throughout.
        let mean = (((x * r) >> 16) * per_weight) >> 16;
        // |xr - mean| <= 2^33 (2^15 2^10 w) and 2^32 / w <= 2^29 (w >= 8): below 2^62.
        ((xr - mean) * per_weight) >> 32
    }
    #[inline(always)]
    fn mean(x: i64, per_weight: i64) -> i64 {
        // Q15: |x| <= 2^15 w and 2^32 / w give at most 2^47 before the shift, 2^30 after.
        (x * per_weight) >> 17
    }
    #[inline(always)]
    fn window_scale(per_weight: i64, gain: i64) -> i64 {
        // 2^32 / w times gain < 2^24 (Q24), over 2^24: 2^32 gain / w, at most 2^53 / w.
        (per_weight * gain) >> 24
    }
    #[inline(always)]
    fn pair_component(xr: i64, mean: i64, r: i64, scale: i64) -> i16 {
        // |mean| <= 2^30 (Q15) and |r| <= 2^10 w: |mean r| / 2^15 <= 2^25 w, as |xr|; their
        // difference (at most 2^26 w) times the scale (at most 2^8 gain / w, gain < 2^24)
        // is below 2^58. The component is envelope * amplitude * 512 (Q10 / 2) times w;
        // gain = 2^38 / (512 amplitude): envelope * 2^14 after the shifts of 24 and 32.
        let v = ((xr - ((mean * r) >> 15)) * scale) >> 32;
        v.clamp(i64::from(i16::MIN), i64::from(i16::MAX)) as i16
    }
    #[inline(always)]
    fn negate(x: i16) -> i16 {
        x.saturating_neg()
    }
    #[inline(always)]
    fn product(a: i16, b: i16) -> i64 {
        i64::from(i32::from(a) * i32::from(b))
    }
    #[inline(always)]
    fn add(a: i64, b: i64) -> i64 {
        a.wrapping_add(b)
    }
    #[inline(always)]
    fn sub(a: i64, b: i64) -> i64 {
        a.wrapping_sub(b)
    }
    #[inline(always)]
    fn times_fraction(a: i64, fraction: i64) -> i64 {
        (a * fraction) >> 16
    }
    #[inline(always)]
    fn ratio_q31(num: i64, den: i64) -> i32 {
        if den > 0 {
            // The detector's ratios are within [-1, 1] and den <= 2^32 (two windings' powers
            // of at most 2^31 each): both over 2^16 (rounded), a 32-bit division gives the
            // ratio in Q14. Its resolution is 2^16 / den: 2^-12 at the nominal amplitude
            // (den = 2^28), 2^-8 at the loss-of-excitation threshold; the carrier loop
            // averages it over windows.
            let num = num.max(-den).min(den);
            let den = ((den + (1 << 15)) >> 16).max(1) as i32;
            let num = ((num + (1 << 15)) >> 16) as i32;
            let num = num.max(-den).min(den);
            (i64::from((num << 14) / den) << 17).clamp(i64::from(i32::MIN), i64::from(i32::MAX))
                as i32
        } else {
            0
        }
    }
    fn to_real(x: i16) -> f32 {
        f32::from(x) / f32::from(FIXED_PAIR_UNIT)
    }
    fn wide_to_real(x: i64) -> f32 {
        x as f32
    }
    fn demodulator(
        settings: crate::DemodulatorSettings<f32>,
    ) -> Result<crate::Demodulator<i16>, crate::ConfigError> {
        crate::Demodulator::<i16>::new_const(settings)
    }
}
