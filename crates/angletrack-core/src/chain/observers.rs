//! The observers at the end of a chain: what a chain needs of one (its prediction, a sample
//! tracked with the front end's feedback, faults latched), for the float observers'
//! [`Gains`] and the fixed-point [`FixedGains`], and the one per-sample body of every chain.

use core::marker::PhantomData;

use super::{Feedback, Prediction, Stage};
use crate::faults::Faults;
use crate::fixed::{FixedGains, FixedState};
use crate::gains::Gains;
use crate::real::ChainNumber;
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::state::ObserverState;
use crate::update::{SampleObserver, UsedSample};
use crate::wrap::wrap_angle;

/// What a chain needs of its observer, in the observer's sample type `V`.
pub(crate) trait Observe<V: ChainNumber> {
    /// The observer's state.
    type State;
    /// The prediction the front end sees.
    type Prediction<'a>: Prediction<V>
    where
        Self: 'a,
        Self::State: 'a;

    /// The prediction for the next sample of `state`.
    fn prediction<'a>(&'a self, state: &'a Self::State) -> Self::Prediction<'a>;

    /// One sample, shown to `observer` after the recursion.
    fn track_observing(
        &self,
        state: &mut Self::State,
        y_c: V,
        y_s: V,
        observer: impl SampleObserver<V>,
    );

    /// Latches `faults` in `state`.
    fn latch(state: &mut Self::State, faults: Faults);
}

/// The float observers' prediction: computed only if a stage asks for it.
pub(crate) struct FloatPrediction<'a, T, const N: usize, S> {
    state: &'a ObserverState<T, N>,
    sin_cos: PhantomData<S>,
}

impl<T: Float, const N: usize, S: SinCos<T>> Prediction<T> for FloatPrediction<'_, T, N, S> {
    #[inline(always)]
    fn angle(&self) -> T {
        let mut angle = self.state.predicted_angle();
        wrap_angle(&mut angle);
        angle
    }

    #[inline(always)]
    fn sin_cos(&self) -> (T, T) {
        S::sin_cos(self.angle())
    }
}

impl<T: Float, const N: usize, S: SinCos<T>> Observe<T> for Gains<T, N, S> {
    type State = ObserverState<T, N>;
    type Prediction<'a>
        = FloatPrediction<'a, T, N, S>
    where
        Self: 'a;

    #[inline(always)]
    fn prediction<'a>(&'a self, state: &'a ObserverState<T, N>) -> FloatPrediction<'a, T, N, S> {
        FloatPrediction {
            state,
            sin_cos: PhantomData,
        }
    }

    #[inline(always)]
    fn track_observing(
        &self,
        state: &mut ObserverState<T, N>,
        y_c: T,
        y_s: T,
        observer: impl SampleObserver<T>,
    ) {
        Gains::track_observing(self, state, y_c, y_s, observer);
    }

    #[inline(always)]
    fn latch(state: &mut ObserverState<T, N>, faults: Faults) {
        state.monitor.latched |= faults;
    }
}

/// The fixed-point observer's prediction: the binary angle and its Q15 sin/cos.
pub(crate) struct FixedPrediction<'a, const N: usize> {
    state: &'a FixedState<N>,
}

impl<const N: usize> Prediction<i16> for FixedPrediction<'_, N> {
    #[inline(always)]
    fn angle(&self) -> i32 {
        self.state.next_angle
    }

    #[inline(always)]
    fn sin_cos(&self) -> (i16, i16) {
        crate::fixed::sin_cos_q15(self.state.next_angle)
    }
}

impl<const N: usize> Observe<i16> for FixedGains<N> {
    type State = FixedState<N>;
    type Prediction<'a> = FixedPrediction<'a, N>;

    #[inline(always)]
    fn prediction<'a>(&'a self, state: &'a FixedState<N>) -> FixedPrediction<'a, N> {
        FixedPrediction { state }
    }

    #[inline(always)]
    fn track_observing(
        &self,
        state: &mut FixedState<N>,
        y_c: i16,
        y_s: i16,
        observer: impl SampleObserver<i16>,
    ) {
        FixedGains::track_observing(self, state, y_c, y_s, observer);
    }

    #[inline(always)]
    fn latch(state: &mut FixedState<N>, faults: Faults) {
        state.latched |= faults;
    }
}

/// Hands what the observer made of a sample back to the front end `F` (of input `X`).
struct ToFrontEnd<'a, V: ChainNumber, X, F: Stage<V, X>> {
    front_end: &'a F,
    state: &'a mut F::State,
    memo: F::Memo,
    input: PhantomData<fn(X) -> V>,
}

impl<V: ChainNumber, X, F: Stage<V, X>> SampleObserver<V> for ToFrontEnd<'_, V, X, F> {
    #[inline(always)]
    fn observe(self, used: Option<UsedSample<V>>) {
        let used = used.map(|u| Feedback {
            sin_cos: u.sin_cos,
            scaled_speed: u.scaled_speed,
            faults: u.faults,
        });
        self.front_end.feedback(self.state, self.memo, used);
    }
}

/// The body of every chain's `track`: the front end's forward pass with the observer's
/// prediction, the observer's step, the feedback to the front end, its faults latched.
#[inline(always)]
pub(crate) fn track<V: ChainNumber, X, F: Stage<V, X>, O: Observe<V>>(
    observer: &O,
    state: &mut O::State,
    front_end: &F,
    front_state: &mut F::State,
    input: X,
) {
    let ((y_c, y_s), memo) = front_end.forward(front_state, &observer.prediction(state), input);
    let to_front_end = ToFrontEnd {
        front_end,
        state: &mut *front_state,
        memo,
        input: PhantomData,
    };
    observer.track_observing(state, y_c, y_s, to_front_end);
    let faults = front_end.faults(front_state);
    if !faults.is_empty() {
        O::latch(state, faults);
    }
}
