//! The floats' arithmetic of the one recursion (`recursion.rs`, `docs/theory.md §5`):
//! [`Arithmetic`] for [`Gains`] on `f32` and `f64`.

use crate::gains::Gains;
use crate::real::Float;
use crate::real::sincos::{Detection, SinCos, SinCosUnit};
use crate::recursion::{Arithmetic, Sample};
use crate::state::predict;
use crate::wrap::Wrap;

impl<T: Float, const N: usize, S: SinCos<T>, U: SinCosUnit<T>> Arithmetic<U, N> for Gains<T, N, S> {
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
    /// [`Float::FEWEST_INSTRUCTIONS`]), summed in another order, `(A X_p)[0] + (A L)[0] eps`,
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
