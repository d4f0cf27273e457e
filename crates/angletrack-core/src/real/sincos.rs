//! The sin/cos of the heterodyne phase detector (`docs/theory.md §1`): exact ([`libm`]) or
//! fast, by branch-free minimax polynomials (`docs/theory.md §11`) whose coefficients and
//! evaluation are here.

// The polynomial coefficients are written as fitted (in f64); the compiler rounds them.
#![allow(clippy::excessive_precision)]

use crate::real::Float;

/// How the phase detector computes `(sin, cos)` of the predicted angle.
///
/// The argument is always the wrapped predicted angle, in [-pi, pi). Implement it to plug
/// in a hardware unit or a table; [`Exact`] and [`Fast`] are provided.
pub trait SinCos<T: Float>:
    Copy + core::fmt::Debug + Default + PartialEq + Send + Sync + 'static
{
    /// `(sin angle, cos angle)` for `angle` in [-pi, pi) (rad).
    fn sin_cos(angle: T) -> (T, T);

    /// The heterodyne phase detector on `angle` (rad, in [-pi, pi)): the phase error
    /// `eps = y_s cos(angle) - y_c sin(angle)` and the in-phase component
    /// `y_c cos(angle) + y_s sin(angle)` (about `A cos(theta - angle)`).
    ///
    /// The default computes [`SinCos::sin_cos`] first; [`Fast`] folds the inputs into its
    /// polynomials ([`Float::fast_phase_detector`]).
    #[inline(always)]
    fn phase_detector(angle: T, y_c: T, y_s: T) -> (T, T) {
        let (sin, cos) = Self::sin_cos(angle);
        (y_s * cos - y_c * sin, y_c * cos + y_s * sin)
    }

    /// The phase detector as the observer runs it: [`SinCos::phase_detector`]'s phase
    /// error and in-phase component together with the `(sin, cos)` of `angle`, which the
    /// online calibration's estimator reuses (`docs/theory.md §12`); where nothing reads
    /// them the compiler drops their computation.
    ///
    /// The default computes [`SinCos::sin_cos`] once and the two products from it; an
    /// implementation that overrides [`SinCos::phase_detector`] should override this too.
    #[inline(always)]
    fn detect(angle: T, y_c: T, y_s: T) -> Detection<T> {
        let (sin, cos) = Self::sin_cos(angle);
        Detection::of(sin, cos, y_c, y_s)
    }
}

/// A phase detector's sin/cos computed by a unit with state: a hardware coprocessor (the
/// CORDIC of an STM32G4, whose registers are written and read), a table with a cache, or a
/// counter for tests. The observer of a chain uses one through
/// [`UnitGains`](crate::UnitGains), the unit kept in the chain's state.
///
/// Every [`SinCos`] (the zero-sized [`Fast`] and [`Exact`]) is a unit for free, and the
/// gains' own observer runs through the same code with its `S`, which costs nothing: the
/// unit has no size.
pub trait SinCosUnit<T: Float> {
    /// `(sin angle, cos angle)` for `angle` in [-pi, pi) (rad).
    fn sin_cos(&mut self, angle: T) -> (T, T);

    /// The phase detector on `angle` (see [`SinCos::detect`]); the default computes
    /// [`SinCosUnit::sin_cos`] once and the two products from it.
    #[inline(always)]
    fn detect(&mut self, angle: T, y_c: T, y_s: T) -> Detection<T> {
        let (sin, cos) = self.sin_cos(angle);
        Detection::of(sin, cos, y_c, y_s)
    }
}

impl<T: Float, S: SinCos<T>> SinCosUnit<T> for S {
    #[inline(always)]
    fn sin_cos(&mut self, angle: T) -> (T, T) {
        S::sin_cos(angle)
    }

    #[inline(always)]
    fn detect(&mut self, angle: T, y_c: T, y_s: T) -> Detection<T> {
        S::detect(angle, y_c, y_s)
    }
}

/// What the phase detector gives for one sample ([`SinCos::detect`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Detection<T> {
    /// `y_s cos(angle) - y_c sin(angle)`, about `A sin(theta - angle)`.
    pub phase_error: T,
    /// `y_c cos(angle) + y_s sin(angle)`, about `A cos(theta - angle)`.
    pub in_phase: T,
    /// `sin(angle)`.
    pub sin: T,
    /// `cos(angle)`.
    pub cos: T,
}

impl<T: Float> Detection<T> {
    /// The phase detector's outputs from the `(sin, cos)` of its angle.
    #[inline(always)]
    fn of(sin: T, cos: T, y_c: T, y_s: T) -> Self {
        Detection {
            phase_error: y_s * cos - y_c * sin,
            in_phase: y_c * cos + y_s * sin,
            sin,
            cos,
        }
    }
}

/// sin/cos from [`libm`], correct to an ulp. On a Cortex-M4F, `libm`'s `sinf`/`cosf`
/// compute in software `f64`: thousands of instructions per sample.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Exact;

/// sin/cos by a branch-free minimax polynomial valid on [-pi, pi]
/// ([`Float::fast_sin_cos`]): absolute error below [`Float::FAST_SIN_COS_MAX_ERROR`]
/// (3e-7 in `f32`, 2e-13 in `f64`), a few tens of single-precision instructions.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Fast;

impl<T: Float> SinCos<T> for Exact {
    #[inline(always)]
    fn sin_cos(angle: T) -> (T, T) {
        angle.sin_cos()
    }
}

impl<T: Float> SinCos<T> for Fast {
    #[inline(always)]
    fn sin_cos(angle: T) -> (T, T) {
        angle.fast_sin_cos()
    }

    #[inline(always)]
    fn phase_detector(angle: T, y_c: T, y_s: T) -> (T, T) {
        angle.fast_phase_detector(y_c, y_s)
    }

    #[inline(always)]
    fn detect(angle: T, y_c: T, y_s: T) -> Detection<T> {
        // Both share the reduction and the polynomials, which the compiler computes once.
        let (phase_error, in_phase) = angle.fast_phase_detector(y_c, y_s);
        let (sin, cos) = fast_sin_cos(angle);
        Detection {
            phase_error,
            in_phase,
            sin,
            cos,
        }
    }
}

/// `sin w = w P(w^2)` on [-pi/2, pi/2] in `f32`, the coefficients of `P` lowest first: a
/// degree 9 minimax fit (error 3.3e-9), whose constant coefficient rounds to 1 in `f32`
/// ([`times_sin_polynomial`] saves an instruction by it). With `f32` rounding the fast
/// sin/cos's measured error over [-pi, pi] is 2.5e-7 (2 ulp of 1), hence its bound 3e-7.
pub(crate) const F32_SIN_POLY: [f32; 5] = [
    0.999_999_976_589_421_1,
    -0.166_666_476_343_451_5,
    0.008_332_899_818_388_598,
    -0.000_198_008_974_585_745,
    2.590_487_887_643_711e-6,
];

/// `cos w = Q(w^2)` on [-pi/2, pi/2] in `f32`, lowest first: a degree 8 minimax fit (error
/// 4.7e-8).
pub(crate) const F32_COS_POLY: [f32; 5] = [
    0.999_999_953_465_633_9,
    -0.499_999_053_454_307_2,
    0.041_663_584_653_655_84,
    -0.001_385_370_401_288_166,
    2.315_392_487_334_255_7e-5,
];

/// `sin w = w P(w^2)` on [-pi/2, pi/2] in `f64`, lowest first: a degree 13 minimax fit. With
/// [`F64_COS_POLY`] the measured error over [-pi, pi] is below 2e-13, the bound.
pub(crate) const F64_SIN_POLY: [f64; 7] = [
    0.999_999_999_999_581_1,
    -0.166_666_666_660_421_6,
    0.008_333_333_306_421_803,
    -0.000_198_412_647_213_031_67,
    2.755_681_878_744_559e-6,
    -2.502_587_063_968_331_2e-8,
    1.535_579_996_492_231_2e-10,
];

/// `cos w = Q(w^2)` on [-pi/2, pi/2] in `f64`, lowest first: a degree 14 minimax fit.
pub(crate) const F64_COS_POLY: [f64; 8] = [
    0.999_999_999_999_992_2,
    -0.500_000_000_000_023_1,
    0.041_666_666_666_174_38,
    -0.001_388_888_886_794_840_3,
    2.480_158_351_217_398_6e-5,
    -2.755_696_539_430_419e-7,
    2.085_897_288_228_722e-9,
    -1.101_291_280_392_047_2e-11,
];

/// [`Float::fast_sin_cos`]: `(sign(x) Q(w^2), w P(w^2))` with `w = pi/2 - |x|`.
#[inline(always)]
pub(crate) fn fast_sin_cos<T: Float>(x: T) -> (T, T) {
    fast_sin_cos_by(x, T::FEWEST_INSTRUCTIONS)
}

/// [`fast_sin_cos`] with its polynomials by Horner's rule or not (`horner`, a constant
/// where it is called: the branches fold away), so that the tests check both rules on
/// every target.
#[inline(always)]
pub(crate) fn fast_sin_cos_by<T: Float>(x: T, horner: bool) -> (T, T) {
    let (w, w2, q) = fast_reduced(x, horner);
    (q.times_sign_of(x), times_sin_polynomial(w, w2, horner))
}

/// [`Float::fast_phase_detector`]: the phase error and the in-phase component with the
/// inputs folded into the polynomials' factors.
#[inline(always)]
pub(crate) fn fast_phase_detector<T: Float>(x: T, y_c: T, y_s: T) -> (T, T) {
    fast_phase_detector_by(x, y_c, y_s, T::FEWEST_INSTRUCTIONS)
}

/// [`fast_phase_detector`] with its polynomials by Horner's rule or not (as
/// [`fast_sin_cos_by`]).
#[inline(always)]
pub(crate) fn fast_phase_detector_by<T: Float>(x: T, y_c: T, y_s: T, horner: bool) -> (T, T) {
    let (w, w2, q) = fast_reduced(x, horner);
    // One sign, +-1, multiplied into both inputs: exact, and on a Cortex-M4F one move to
    // the integer unit and back for the pair instead of one for each input.
    let sign = T::ONE.times_sign_of(x);
    let eps = times_sin_polynomial(y_s * w, w2, horner) - (y_c * sign) * q;
    let in_phase = times_sin_polynomial(y_c * w, w2, horner) + (y_s * sign) * q;
    (eps, in_phase)
}

/// The shared part of [`fast_sin_cos`] and [`fast_phase_detector`]: `w = pi/2 - |x|`,
/// `w^2` and `Q(w^2)`.
#[inline(always)]
fn fast_reduced<T: Float>(x: T, horner: bool) -> (T, T, T) {
    let w = T::FRAC_PI_2 - x.abs();
    let w2 = w * w;
    (w, w2, polynomial(w2, T::COS_POLY, horner))
}

/// `y P(t)`, `P` the sin polynomial ([`Float::SIN_POLY`]). Where its constant coefficient
/// is 1 (the `f32` one, 0.999_999_977 rounded), as `y + (y t) P1(t)` with `P1` the
/// polynomial of the other coefficients, `(P(t) - 1) / t`: the same polynomial, the 1
/// neither loaded nor multiplied (one instruction fewer on a Cortex-M4F), and `y t` ready
/// before `P1` is (one operation less on the chain).
#[inline(always)]
fn times_sin_polynomial<T: Float>(y: T, t: T, horner: bool) -> T {
    match T::SIN_POLY {
        [one, rest @ ..] if *one == T::ONE => y + (y * t) * polynomial(t, rest, horner),
        all => y * polynomial(t, all, horner),
    }
}

/// Evaluation of `c[0] + c[1] t + ... + c[7] t^7` (`c` has at most 8 coefficients; its
/// length is a constant, so the branches fold away).
///
/// With `horner` (`f32` on a Cortex-M, [`Float::FEWEST_INSTRUCTIONS`]) by Horner's rule:
/// one multiply-add per coefficient and no powers of `t`, two instructions fewer per sample
/// than a split into halves, and one coefficient live at a time, so that on a Cortex-M4F
/// the phase detector fits in the scratch float registers (none saved and restored). There
/// every instruction counts and the chain's length hardly does.
///
/// Otherwise (hosts, whose loop is latency-bound) Estrin-like: pairs `c[2i] + c[2i+1] t`
/// combined with powers of `t`, a chain of dependent operations about half as long as
/// Horner's.
#[inline(always)]
fn polynomial<T: Float>(t: T, c: &[T], horner: bool) -> T {
    if horner {
        let Some((&highest, lower)) = c.split_last() else {
            return T::ZERO;
        };
        return lower.iter().rev().fold(highest, |sum, &ck| sum * t + ck);
    }
    let pair = |i: usize| match (c.get(2 * i), c.get(2 * i + 1)) {
        (Some(&low), Some(&high)) => low + high * t,
        (Some(&low), None) => low,
        _ => T::ZERO,
    };
    let t2 = t * t;
    match *c {
        [_] | [_, _] => pair(0),
        [_, _, _] | [_, _, _, _] => pair(0) + t2 * pair(1),
        [_, _, _, _, _] | [_, _, _, _, _, _] => (pair(0) + t2 * pair(1)) + (t2 * t2) * pair(2),
        _ => (pair(0) + t2 * pair(1)) + (t2 * t2) * (pair(2) + t2 * pair(3)),
    }
}

#[cfg(test)]
mod doc_claims_tests;
#[cfg(test)]
mod tests;
