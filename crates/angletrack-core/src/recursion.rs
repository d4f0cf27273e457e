//! The one predictor-corrector recursion of every observer (`docs/theory.md §5`), written
//! once over its arithmetic: [`Arithmetic`] is what a number format must provide (predict,
//! wrap, detect, normalise, correct) and [`step`] is the recursion itself. The floats
//! (`f32`, `f64`) implement it through [`Gains`](crate::Gains); the integers of the fixed-point path
//! (`docs/theory.md §14`) through [`FixedGains`](crate::FixedGains).

use crate::real::sincos::Detection;
use crate::wrap::Wrap;

/// What one step of the recursion gives besides the new state.
#[derive(Clone, Copy)]
pub(crate) struct Step<T> {
    /// Normalised phase-detector output `eps / sqrt(y_c^2 + y_s^2)`, about the sine of the
    /// phase error (0 for a sample that was not used).
    pub(crate) eps: T,
    /// Whole turns the wrap of the predicted angle removed.
    pub(crate) whole: i32,
    /// `(sin, cos)` of the predicted angle (for the calibration's estimator; the plain
    /// update leaves them unused and the compiler drops them).
    pub(crate) sin_cos: (T, T),
}

/// One sample as the recursion takes it: the signals, their `y_c^2 + y_s^2` (from the input
/// check) and whether the sample is used.
#[derive(Clone, Copy)]
pub(crate) struct Sample<T> {
    pub(crate) y_c: T,
    pub(crate) y_s: T,
    pub(crate) amplitude2: T,
    pub(crate) valid: bool,
}

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
/// [`Gains::step`](crate::Gains::step) for the equations). `W` wraps the predicted angle of the floats.
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
