//! The sin/cos of the phase detector: exact ([`libm`]) or fast (a short polynomial).

use crate::real::Real;

/// How the phase detector computes `(sin, cos)` of the predicted angle.
///
/// The argument is always the wrapped predicted angle, in [-pi, pi). Implement it to plug
/// in a hardware unit or a table; [`Exact`] and [`Fast`] are provided.
pub trait SinCos<T: Real>:
    Copy + core::fmt::Debug + Default + PartialEq + Send + Sync + 'static
{
    /// `(sin angle, cos angle)` for `angle` in [-pi, pi) (rad).
    fn sin_cos(angle: T) -> (T, T);

    /// The heterodyne phase detector on `angle` (rad, in [-pi, pi)): the phase error
    /// `eps = y_s cos(angle) - y_c sin(angle)` and the in-phase component
    /// `y_c cos(angle) + y_s sin(angle)` (about `A cos(theta - angle)`).
    ///
    /// The default computes [`SinCos::sin_cos`] first; [`Fast`] folds the inputs into its
    /// polynomials ([`Real::fast_phase_detector`]).
    #[inline(always)]
    fn phase_detector(angle: T, y_c: T, y_s: T) -> (T, T) {
        let (sin, cos) = Self::sin_cos(angle);
        (y_s * cos - y_c * sin, y_c * cos + y_s * sin)
    }
}

/// sin/cos from [`libm`], correct to an ulp. On a Cortex-M4F, `libm`'s `sinf`/`cosf`
/// compute in software `f64`: thousands of instructions per sample.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Exact;

/// sin/cos by a branch-free minimax polynomial valid on [-pi, pi]
/// ([`Real::fast_sin_cos`]): absolute error below [`Real::FAST_SIN_COS_MAX_ERROR`]
/// (3e-7 in `f32`, 2e-13 in `f64`), a few tens of single-precision instructions.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Fast;

impl<T: Real> SinCos<T> for Exact {
    #[inline(always)]
    fn sin_cos(angle: T) -> (T, T) {
        angle.sin_cos()
    }
}

impl<T: Real> SinCos<T> for Fast {
    #[inline(always)]
    fn sin_cos(angle: T) -> (T, T) {
        angle.fast_sin_cos()
    }

    #[inline(always)]
    fn phase_detector(angle: T, y_c: T, y_s: T) -> (T, T) {
        angle.fast_phase_detector(y_c, y_s)
    }
}
