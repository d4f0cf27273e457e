//! The arithmetic a [`Demodulator`](crate::Demodulator) runs in (`docs/theory.md §13`): the
//! sums of one segment of ADC samples, the window's offset-free and normalised components,
//! and the products of the carrier loop's phase detector, for `f32`, `f64` and `i16`
//! samples (the fixed point's in `number_fixed.rs`: a Q10 sine table, `i32` sums and
//! window values, exact 64-bit products of 32-bit values, no division). The demodulator's
//! logic is written once over this trait.

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
/// and a segment of them an `i32` (`number_fixed.rs`, `docs/theory.md §13`).
pub(super) static SINE_Q10: [i16; TABLE_LEN] = sine_q10();

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
