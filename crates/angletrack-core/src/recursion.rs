//! The one predictor-corrector recursion of every observer (`docs/theory.md §5`), written
//! once over its arithmetic: [`Arithmetic`] is what a number format must provide (predict,
//! wrap, detect, normalise, correct) and [`step`] is the recursion itself. The floats
//! (`f32`, `f64`) implement it through [`Gains`]; the integers of the fixed-point path
//! (`docs/theory.md §14`) through [`FixedGains`](crate::FixedGains).

use crate::gains::Gains;
use crate::real::Real;
use crate::sincos::{Detection, SinCos, SinCosUnit};
use crate::state::predict;
use crate::update::{Sample, Step};
use crate::wrap::Wrap;

/// The operations of one step of the recursion in one number format, with `U` the unit that
/// computes the phase detector's sin/cos and `N` the order.
pub(crate) trait Arithmetic<U, const N: usize> {
    /// A state component, the angle and the signals (`T` for the floats; `i32` for the
    /// fixed-point path, whose components have their own scales).
    type Value: Copy;
    /// What tracks the signal's magnitude from one sample to the next (the magnitude for
    /// the floats, its reciprocal for the fixed-point path).
    type Magnitude: Copy;
    /// The state vector (`[T; N]` for the floats; the fixed-point path keeps its
    /// acceleration in 64 bits).
    type Vector: Copy;

    /// The Taylor step `A x` of the state (`docs/theory.md §5`), with its angle replaced by
    /// `angle`, the prediction the previous sample left (wrapped).
    fn predict(&self, x: &Self::Vector, angle: Self::Value) -> Self::Vector;

    /// Wraps the predicted angle into one turn; returns the whole turns removed.
    fn wrap<W: Wrap>(angle: &mut Self::Value) -> i32;

    /// The heterodyne phase detector at the (wrapped) predicted angle.
    fn detect(
        unit: &mut U,
        angle: Self::Value,
        y_c: Self::Value,
        y_s: Self::Value,
    ) -> Detection<Self::Value>;

    /// The phase error normalised by the signal's magnitude (`docs/theory.md §12`), the
    /// tracked magnitude updated; zero for a sample that is not used.
    fn normalise(
        magnitude: &mut Self::Magnitude,
        sample: &Sample<Self::Value>,
        phase_error: Self::Value,
    ) -> Self::Value;

    /// The correction `X_e = X_p + L eps` of the predicted state `p` (the previous corrected
    /// state being `x`); returns the next sample's predicted angle and the whole turns the
    /// corrected angle crossed (0 where the angle is wrapped by [`Arithmetic::wrap`]).
    fn correct(
        &self,
        x: &Self::Vector,
        p: &mut Self::Vector,
        eps: Self::Value,
    ) -> (Self::Value, i32);
}

/// The recursion, on one channel's state `x`, the predicted angle `next_angle` the previous
/// sample left and the tracked `magnitude`: predict, wrap, detect, normalise, correct (see
/// [`Gains::step`] for the equations). `W` wraps the predicted angle of the floats.
#[inline(always)]
pub(crate) fn step<A: Arithmetic<U, N>, U, W: Wrap, const N: usize>(
    arithmetic: &A,
    unit: &mut U,
    x: &mut A::Vector,
    next_angle: &mut A::Value,
    magnitude: &mut A::Magnitude,
    sample: Sample<A::Value>,
) -> Step<A::Value> {
    let mut angle = *next_angle;
    let wrapped = A::wrap::<W>(&mut angle);
    let detection = A::detect(unit, angle, sample.y_c, sample.y_s);
    let eps = A::normalise(magnitude, &sample, detection.phase_error);
    let mut p = arithmetic.predict(x, angle);
    let (next, crossed) = arithmetic.correct(x, &mut p, eps);
    *next_angle = next;
    *x = p;
    Step {
        eps,
        whole: wrapped + crossed,
        sin_cos: (detection.sin, detection.cos),
    }
}

impl<T: Real, const N: usize, S: SinCos<T>, U: SinCosUnit<T>> Arithmetic<U, N> for Gains<T, N, S> {
    type Value = T;
    type Magnitude = T;
    type Vector = [T; N];

    #[inline(always)]
    fn predict(&self, x: &[T; N], angle: T) -> [T; N] {
        let mut p = predict(x);
        p[0] = angle;
        p
    }

    #[inline(always)]
    fn wrap<W: Wrap>(angle: &mut T) -> i32 {
        W::wrap(angle)
    }

    #[inline(always)]
    fn detect(unit: &mut U, angle: T, y_c: T, y_s: T) -> Detection<T> {
        unit.detect(angle, y_c, y_s)
    }

    #[inline(always)]
    fn normalise(amplitude: &mut T, sample: &Sample<T>, phase_error: T) -> T {
        let tracked = T::track_magnitude(*amplitude, sample.amplitude2);
        if sample.valid {
            *amplitude = tracked;
            phase_error / tracked
        } else {
            T::ZERO
        }
    }

    /// `next_angle = (A X_e)[0]`, the prediction of the corrected state; where the chain of
    /// dependent operations counts more than the instructions (`f64`,
    /// [`Real::FEWEST_INSTRUCTIONS`]), summed in another order, `(A X_p)[0] + (A L)[0] eps`,
    /// so that the phase error reaches the next phase detector through one multiplication
    /// and one addition (`f32` saves that multiplication and the load of `(A L)[0]`). The
    /// corrected angle is not wrapped (it is wrapped when read).
    #[inline(always)]
    fn correct(&self, _x: &[T; N], p: &mut [T; N], eps: T) -> (T, i32) {
        let short_chain = predict(p)[0] + self.next_angle_gain * eps;
        let mut i = 0;
        while i < N {
            p[i] += self.l[i] * eps;
            i += 1;
        }
        let next = if T::FEWEST_INSTRUCTIONS {
            predict(p)[0]
        } else {
            short_chain
        };
        (next, 0)
    }
}
