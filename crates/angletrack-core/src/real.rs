//! The sealed floating-point trait that makes every observer generic over `f32` and `f64`.
//!
//! All transcendental functions go through [`libm`], so the crate stays `no_std`. The `f32`
//! implementation never touches `f64` arithmetic: a Cortex-M4F has a single-precision FPU
//! only, and any `f64` operation there becomes a slow software call. The coefficients of
//! the fast sin/cos polynomials are constants of each type; their evaluation is in
//! `sincos.rs` (`docs/theory.md §11`).

use core::fmt::{Debug, Display};
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

pub(crate) mod saturate;
pub(crate) mod sincos;

use crate::error::{ConfigError, Parameter};
use sincos::{F32_COS_POLY, F32_SIN_POLY, F64_COS_POLY, F64_SIN_POLY};

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A floating-point type the observers run on: `f32` (firmware) or `f64` (host).
///
/// The trait is sealed: only `f32` and `f64` implement it. It carries the constants and the
/// few functions the recursion needs, each implemented once per type with [`libm`].
pub trait Float:
    sealed::Sealed
    + ChainNumber<Angle = Self>
    + Copy
    + Default
    + PartialOrd
    + Debug
    + Display
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 1/2.
    const HALF: Self;
    /// 2.
    const TWO: Self;
    /// -2.
    const NEG_TWO: Self;
    /// pi (rad).
    const PI: Self;
    /// pi/2 (rad).
    const FRAC_PI_2: Self;
    /// 2 pi (rad), one turn.
    const TAU: Self;
    /// 2 pi rounded to the type: `x - TAU_HI` is exact for `x` in [pi, 4 pi] (Sterbenz).
    const TAU_HI: Self;
    /// Low part of 2 pi: `TAU_HI + TAU_LO` is 2 pi to about twice the type's precision.
    const TAU_LO: Self;
    /// 1 / (2 pi) (turns per rad).
    const FRAC_1_TAU: Self;
    /// Machine epsilon.
    const EPSILON: Self;
    /// The smallest positive normal number: added to `y_c^2 + y_s^2` in the amplitude
    /// tracker so that it never divides by zero (`docs/theory.md §12`).
    const MIN_POSITIVE: Self;
    /// Positive infinity: a level no finite number exceeds.
    const INFINITY: Self;
    /// Coefficients of the odd minimax polynomial for sin on [-pi/2, pi/2], lowest first.
    #[doc(hidden)]
    const SIN_POLY: &'static [Self];
    /// Coefficients of the even minimax polynomial for cos on [-pi/2, pi/2], lowest first.
    #[doc(hidden)]
    const COS_POLY: &'static [Self];
    /// The phase detector's sin/cos when none is named: [`Fast`](crate::Fast) for `f32`
    /// (firmware), [`Exact`](crate::Exact) for `f64` (host).
    type DefaultSinCos: sincos::SinCos<Self>;
    /// Whether a one-turn wrap `(a - TAU_HI) - TAU_LO` of an angle just above pi (or its
    /// mirror) can round to just outside [-pi, pi) and needs a second move: `false` for
    /// `f32` (`PI` above pi, `TAU_LO < 0`: the exact result is inside and rounding is
    /// monotone), `true` for `f64` (`PI` below pi).
    #[doc(hidden)]
    const ONE_TURN_EDGE_FIX: bool;
    /// Documented bound of the absolute error of [`Float::fast_sin_cos`] over [-pi, pi].
    const FAST_SIN_COS_MAX_ERROR: Self;
    /// How the update is written where the two differ: `true` for `f32` on a bare-metal Arm
    /// core (a Cortex-M's in-order pipeline pays per instruction; its FPU is single
    /// precision), for the fewest instructions; `false` elsewhere (a host's out-of-order core,
    /// whose loop over one channel's samples waits on each sample's result) for the shortest
    /// chain of dependent operations from one sample's phase error to the next sample's.
    #[doc(hidden)]
    const FEWEST_INSTRUCTIONS: bool;

    /// Conversion from `f32` (exact for both types).
    fn from_f32(x: f32) -> Self;
    /// Conversion from `f64` (rounds for `f32`); meant for host-side code, not the
    /// per-sample path.
    fn from_f64(x: f64) -> Self;
    /// Conversion to `f64` (exact for both types); meant for host-side code.
    fn to_f64(self) -> f64;
    /// The largest integer not greater than `self`, as a saturating `i32` (NaN gives 0).
    /// Pure arithmetic (a truncating conversion and a comparison), no library call.
    fn floor_to_i32(self) -> i32;
    /// `self` rounded toward zero, as a saturating `i32` (NaN gives 0): one conversion
    /// instruction on a Cortex-M4F, the floor for `self >= 0`.
    fn truncate_to_i32(self) -> i32;
    /// Conversion from `i32` (exact in `f64`, rounded in `f32` above 2^24).
    fn from_i32(n: i32) -> Self;
    /// `exp(self) - 1`, accurate for small arguments, from [`libm`] (gain design: pole
    /// matching, `docs/theory.md §7`).
    fn exp_m1(self) -> Self;
    /// Square root, from [`libm`] (in software on a Cortex-M4F: meant for the rare paths,
    /// such as the first sample, not for every sample).
    fn sqrt(self) -> Self;
    /// The magnitude `sqrt(amplitude2)` the phase error of a used sample is normalised by,
    /// from the previous sample's `previous` (`docs/theory.md §12`): in `f32` (firmware,
    /// where a Cortex-M4F computes square roots in software) one Heron step from `previous`,
    /// exact for a steady amplitude; in `f64` (hosts, which have a square-root instruction)
    /// the square root itself, so the normalised error is exactly `eps / |y|`.
    fn track_magnitude(previous: Self, amplitude2: Self) -> Self;
    /// `true` unless the value is NaN or infinite.
    fn is_finite(self) -> bool;
    /// Absolute value.
    fn abs(self) -> Self;
    /// The bits of the value as a signed integer: for values that are not NaN, ordered as
    /// the values are among non-negative ones, and negative for negative ones (a comparison
    /// of non-negative floats with integer instructions: no library call on a Cortex-M0).
    type OrderedBits: Copy + PartialOrd + Eq + core::fmt::Debug;
    /// See [`Float::OrderedBits`].
    fn ordered_bits(self) -> Self::OrderedBits;
    /// Four-quadrant arctangent of `self / x` (rad, in [-pi, pi]).
    fn atan2(self, x: Self) -> Self;
    /// `(sin, cos)` correctly rounded to within an ulp, from [`libm`].
    fn sin_cos(self) -> (Self, Self);
    /// The smaller of two values (the other one if either is NaN).
    fn min(self, other: Self) -> Self;
    /// The larger of two values (the other one if either is NaN).
    fn max(self, other: Self) -> Self;

    /// `self` times the sign of `sign` (`-self` if `sign` is negative, including -0): the
    /// sign bit of `sign` flips that of `self`, no multiplication and no branch (on a
    /// Cortex-M4F fewer instructions than a comparison and a select).
    fn times_sign_of(self, sign: Self) -> Self;

    /// `|self| <= bound` for a `bound` that is finite and not negative; `false` for a NaN
    /// `self`. One integer comparison of the bits (the sign bit cleared): a float comparison
    /// is a library call on a core without an FPU (Cortex-M0).
    fn abs_at_most(self, bound: Self) -> bool;

    /// `true` when the sign bit is set (negative numbers, -0 and NaNs with it): one bit test.
    fn sign_bit(self) -> bool;

    /// Checks that a parameter is finite and strictly positive: the type's `const fn` of
    /// `error.rs`, which the `const` constructors call directly.
    #[doc(hidden)]
    fn check_positive(value: Self, parameter: Parameter) -> Result<Self, ConfigError>;
    /// Coefficients `c[k]` of the closed-loop characteristic polynomial in `s = z - 1`,
    /// `s^N + c[N-1] s^(N-1) + ... + c[0]`, for gains `l` (`docs/theory.md §6`): the type's
    /// `const fn` of `stability.rs`. With `D = A - I` (nilpotent) and the rank-one
    /// correction, `det(s I - D + A L e1^T) = s^N + sum_k s^(N-1-k) e1^T D^k A L`; the
    /// coefficients are linear in the gains.
    #[doc(hidden)]
    fn characteristic_polynomial_in_s<const N: usize>(l: &[Self; N]) -> [Self; N];
    /// The gains whose loop has the characteristic polynomial `c` (in `s = z - 1`, as
    /// [`Float::characteristic_polynomial_in_s`] gives it): the type's `const fn` of
    /// `stability.rs`. The map from gains to coefficients is linear and triangular:
    /// `c[N-1-k]` depends on `l[k..N]` only, with a unit coefficient on `l[k]`, so back
    /// substitution solves it.
    #[doc(hidden)]
    fn gains_of_loop_polynomial<const N: usize>(c: &[Self; N]) -> [Self; N];

    /// `(sin, cos)` by a branch-free polynomial, for arguments in [-pi, pi].
    ///
    /// With `w = pi/2 - |x|` in [-pi/2, pi/2], `sin x = sign(x) cos w` and `cos x = sin w`;
    /// `sin w = w P(w^2)` and `cos w = Q(w^2)` are minimax polynomials sharing `w^2`. The
    /// absolute error over [-pi, pi] is below [`Float::FAST_SIN_COS_MAX_ERROR`] (tested).
    /// Outside that range the result is wrong; the observer only calls it on a wrapped angle.
    #[inline(always)]
    fn fast_sin_cos(self) -> (Self, Self) {
        sincos::fast_sin_cos(self)
    }

    /// The heterodyne phase detector on the angle `self` (in [-pi, pi]) with the
    /// [`Float::fast_sin_cos`] polynomials: `(y_s cos x - y_c sin x, y_c cos x + y_s sin x)`,
    /// the phase error `eps` and the in-phase component.
    ///
    /// The inputs are folded into the polynomials' factors, `eps = (y_s w) P(w^2) -
    /// (sign(x) y_c) Q(w^2)`, so that `y_s w` and `sign(x) y_c` are ready before the
    /// polynomials are: one multiplication less on the chain from one sample's angle to its
    /// phase error, which is what a single observer's loop waits for.
    #[inline(always)]
    fn fast_phase_detector(self, y_c: Self, y_s: Self) -> (Self, Self) {
        sincos::fast_phase_detector(self, y_c, y_s)
    }
}

/// The number format of a chain's samples, and the format of its angles: rad in the same
/// float for `f32` and `f64`; the binary angle (`i32`, 2^32 per turn) for the fixed-point
/// observer's `i16` samples.
pub trait ChainNumber: Copy {
    /// The format of an angle.
    type Angle: Copy;
}

impl ChainNumber for f32 {
    type Angle = f32;
}

impl ChainNumber for f64 {
    type Angle = f64;
}

impl ChainNumber for i16 {
    type Angle = i32;
}

macro_rules! impl_real {
    ($t:ident, bits $bits:ident, signed $signed:ident, default $default:ident, tau_lo $tau_lo:expr,
     one_turn_edge_fix $edge_fix:expr, fast_error $eps_fast:expr, fewest_instructions $fewest:expr,
     polynomials $sin_poly:path, $cos_poly:path, libm $atan2:ident, $sincos:ident, $sqrt:ident, $expm1:ident,
     track_magnitude $track:expr, checks $m:ident) => {
        impl Float for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const HALF: Self = 0.5;
            const TWO: Self = 2.0;
            const NEG_TWO: Self = -2.0;
            const PI: Self = core::$t::consts::PI;
            const FRAC_PI_2: Self = core::$t::consts::FRAC_PI_2;
            const TAU: Self = core::$t::consts::TAU;
            const TAU_HI: Self = core::$t::consts::TAU;
            const TAU_LO: Self = $tau_lo;
            const FRAC_1_TAU: Self = 1.0 / core::$t::consts::TAU;
            const EPSILON: Self = $t::EPSILON;
            const MIN_POSITIVE: Self = $t::MIN_POSITIVE;
            const INFINITY: Self = $t::INFINITY;
            const SIN_POLY: &'static [Self] = &$sin_poly;
            const COS_POLY: &'static [Self] = &$cos_poly;
            const FAST_SIN_COS_MAX_ERROR: Self = $eps_fast;
            const ONE_TURN_EDGE_FIX: bool = $edge_fix;
            const FEWEST_INSTRUCTIONS: bool = $fewest;
            type DefaultSinCos = sincos::$default;

            #[inline(always)]
            fn from_f32(x: f32) -> Self {
                x as $t
            }
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn floor_to_i32(self) -> i32 {
                let truncated = self as i32;
                truncated.wrapping_sub(((truncated as $t) > self) as i32)
            }
            #[inline(always)]
            fn truncate_to_i32(self) -> i32 {
                self as i32
            }
            #[inline(always)]
            fn from_i32(n: i32) -> Self {
                n as $t
            }
            #[inline]
            fn exp_m1(self) -> Self {
                libm::$expm1(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                libm::$sqrt(self)
            }
            #[inline(always)]
            fn track_magnitude(previous: Self, amplitude2: Self) -> Self {
                $track(previous, amplitude2)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                $t::is_finite(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                $t::abs(self)
            }
            type OrderedBits = $signed;
            #[inline(always)]
            fn ordered_bits(self) -> $signed {
                self.to_bits() as $signed
            }
            #[inline(always)]
            fn atan2(self, x: Self) -> Self {
                libm::$atan2(self, x)
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                libm::$sincos(self)
            }
            #[inline(always)]
            fn times_sign_of(self, sign: Self) -> Self {
                const SIGN_BIT: $bits = 1 << ($bits::BITS - 1);
                $t::from_bits(self.to_bits() ^ (sign.to_bits() & SIGN_BIT))
            }
            #[inline(always)]
            fn abs_at_most(self, bound: Self) -> bool {
                // Not negative floats order as their bits; a NaN's are above infinity's.
                const MAGNITUDE: $bits = <$bits>::MAX >> 1;
                self.to_bits() & MAGNITUDE <= bound.to_bits()
            }
            #[inline(always)]
            fn sign_bit(self) -> bool {
                self.to_bits() >> ($bits::BITS - 1) != 0
            }
            #[inline]
            fn check_positive(value: Self, parameter: Parameter) -> Result<Self, ConfigError> {
                crate::error::$m::check_positive(value, parameter)
            }
            #[inline]
            fn characteristic_polynomial_in_s<const N: usize>(l: &[Self; N]) -> [Self; N] {
                crate::stability::$m::characteristic_polynomial_in_s(l)
            }
            #[inline]
            fn gains_of_loop_polynomial<const N: usize>(c: &[Self; N]) -> [Self; N] {
                crate::stability::$m::gains_of_loop_polynomial(c)
            }
            #[inline(always)]
            fn min(self, other: Self) -> Self {
                $t::min(self, other)
            }
            #[inline(always)]
            fn max(self, other: Self) -> Self {
                $t::max(self, other)
            }
        }
    };
}

// The constants and `libm` functions of each type; the polynomials' error bounds are
// explained with their coefficients in `sincos.rs`.
impl_real! {
    f32, bits u32, signed i32, default Fast, tau_lo -1.748_455_6e-7_f32, one_turn_edge_fix false,
    fast_error 3e-7, fewest_instructions cfg!(all(target_arch = "arm", target_os = "none")), polynomials F32_SIN_POLY, F32_COS_POLY, libm atan2f, sincosf, sqrtf, expm1f,
    track_magnitude heron_step::<f32>, checks for_f32
}

impl_real! {
    f64, bits u64, signed i64, default Exact, tau_lo 2.449_293_598_294_706_4e-16_f64, one_turn_edge_fix true,
    fast_error 2e-13, fewest_instructions false, polynomials F64_SIN_POLY, F64_COS_POLY, libm atan2, sincos, sqrt, expm1,
    track_magnitude |_previous, amplitude2| sqrt_f64(amplitude2), checks for_f64
}

/// The square root of the `f64` magnitude ([`Float::track_magnitude`]): with the `std`
/// feature the standard library's (the compiler's own operation, which the loop over a
/// [`ChannelBank`](crate::ChannelBank)'s lanes vectorises: `sqrtpd`), else `libm`'s (on
/// x86-64 an inline `sqrtsd` that no loop around it can vectorise). Both are correctly
/// rounded: the same bits.
#[inline(always)]
fn sqrt_f64(x: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrt(x)
    }
}

/// One Heron (Newton) step of `sqrt(amplitude2)` from `previous` (> 0): the mean of
/// `previous` and `amplitude2 / previous`, never below `sqrt(amplitude2)` (arithmetic and
/// geometric means); `amplitude2` includes `m` = [`Float::MIN_POSITIVE`], so the magnitude
/// is never below `sqrt(m)`, never zero.
#[inline(always)]
pub(crate) fn heron_step<T: Float>(previous: T, amplitude2: T) -> T {
    (previous + amplitude2 / previous) * T::HALF
}

/// Checks that a parameter is finite and strictly positive ([`Float::check_positive`]).
pub(crate) fn check_positive<T: Float>(value: T, parameter: Parameter) -> Result<T, ConfigError> {
    T::check_positive(value, parameter)
}
