//! The observers at the end of a chain: what a chain needs of one (its prediction, a sample
//! tracked with the front end's feedback, faults latched), for the float observers'
//! [`Gains`] and the fixed-point [`FixedGains`], and the one per-sample body of every chain.

use core::marker::PhantomData;

use super::{Chain, ChainState, Feedback, Prediction, Stage};
use crate::faults::Faults;
use crate::fixed::{FixedEstimate, FixedGains, FixedState};
use crate::gains::Gains;
use crate::real::ChainNumber;
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::state::{Estimate, ObserverState};
use crate::update::{SampleObserver, UsedSample};
use crate::wrap::wrap_angle;

/// What a chain needs of its observer, in the observer's sample type `V`.
pub(crate) trait Observe<V: ChainNumber> {
    /// The observer's state.
    type State;
    /// The observer's estimate.
    type Estimate;
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

    /// A sample that is not a measurement: the state coasts on its prediction (nothing for
    /// a state that has no angle yet) and re-acquires at the next sample.
    fn coast(&self, state: &mut Self::State);

    /// Latches `faults` in `state`.
    fn latch(state: &mut Self::State, faults: Faults);

    /// The estimate `state` holds, with `faults` added.
    fn estimate_with(&self, state: &Self::State, faults: Faults) -> Self::Estimate;
}

/// The float observers' prediction: computed only if a stage asks for it.
pub(crate) struct FloatPrediction<'a, T, const N: usize, S> {
    state: &'a ObserverState<T, N>,
    sin_cos: PhantomData<S>,
}

impl<T: Float, const N: usize, S: SinCos<T>> Prediction<T> for FloatPrediction<'_, T, N, S> {
    /// The predicted angle as the observer keeps it: in [-pi, pi) while it tracks (the
    /// usual path), otherwise possibly a turn outside (a stage that needs one turn wraps it,
    /// as [`Prediction::sin_cos`] does; a table indexes it modulo its length).
    #[inline(always)]
    fn angle(&self) -> T {
        self.state.predicted_angle()
    }

    #[inline(always)]
    fn sin_cos(&self) -> (T, T) {
        let mut angle = self.state.predicted_angle();
        wrap_angle(&mut angle);
        S::sin_cos(angle)
    }
}

impl<T: Float, const N: usize, S: SinCos<T>> Observe<T> for Gains<T, N, S> {
    type State = ObserverState<T, N>;
    type Estimate = Estimate<T>;
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
    fn coast(&self, state: &mut ObserverState<T, N>) {
        self.coast_front_end(state);
    }

    #[inline(always)]
    fn latch(state: &mut ObserverState<T, N>, faults: Faults) {
        state.monitor.latched |= faults;
    }

    #[inline(always)]
    fn estimate_with(&self, state: &ObserverState<T, N>, faults: Faults) -> Estimate<T> {
        let mut estimate = self.estimate(state);
        estimate.faults |= faults;
        estimate
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
    type Estimate = FixedEstimate;
    type Prediction<'a> = FixedPrediction<'a, N>;

    #[inline(always)]
    fn prediction<'a>(&'a self, state: &'a FixedState<N>) -> FixedPrediction<'a, N> {
        FixedPrediction { state }
    }

    /// [`FixedGains::track`], the feedback taken from the state around it (every integer
    /// sample is used): the Q15 `(sin, cos)` of the predicted angle, the corrected speed in
    /// 2^-16 turn per sample (saturated) and the faults. Where nothing reads it (`()`), the
    /// compiler drops it: the observer's own update is untouched.
    #[inline(always)]
    fn track_observing(
        &self,
        state: &mut FixedState<N>,
        y_c: i16,
        y_s: i16,
        observer: impl SampleObserver<i16>,
    ) {
        if !observer.observes() {
            // The observer's own track alone: the prediction's sin/cos below, though unread,
            // would otherwise be merged with the recursion's and kept live across it (spilled
            // on a Cortex-M0).
            return self.track(state, y_c, y_s);
        }
        let sin_cos = crate::fixed::sin_cos_q15(state.next_angle);
        self.track(state, y_c, y_s);
        let speed = FixedGains::<N>::corrected_speed(&state.x) >> 16;
        observer.observe(Some(UsedSample {
            sin_cos,
            scaled_speed: speed.clamp(-32768, 32767) as i16,
            faults: state.faults,
            phase_error: state.phase_error.clamp(-32768, 32767) as i16,
        }));
    }

    #[inline(always)]
    fn coast(&self, state: &mut FixedState<N>) {
        self.coast_front_end(state);
    }

    #[inline(always)]
    fn latch(state: &mut FixedState<N>, faults: Faults) {
        state.latched |= faults;
    }

    #[inline(always)]
    fn estimate_with(&self, state: &FixedState<N>, faults: Faults) -> FixedEstimate {
        let mut estimate = FixedGains::estimate(state);
        estimate.faults |= faults;
        estimate
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
            phase_error: u.phase_error,
        });
        self.front_end.feedback(self.state, self.memo, used);
    }
}

/// What a chain's per-sample form returns: nothing (`track`) or the estimate (`update`).
pub(crate) trait Output<V: ChainNumber, O: Observe<V>> {
    /// The result for the observer's `state` after a sample, with the front end's `faults`.
    fn of(observer: &O, state: &O::State, faults: Faults) -> Self;
}

impl<V: ChainNumber, O: Observe<V>> Output<V, O> for () {
    #[inline(always)]
    fn of(_: &O, _: &O::State, _: Faults) {}
}

/// The front end's faults alone (a bank's lane, whose estimate is read apart).
impl<V: ChainNumber, O: Observe<V>> Output<V, O> for Faults {
    #[inline(always)]
    fn of(_: &O, _: &O::State, faults: Faults) -> Faults {
        faults
    }
}

/// The float observers' estimate, as [`Observe::estimate_with`].
impl<T: Float, const N: usize, S: SinCos<T>> Output<T, Gains<T, N, S>> for Estimate<T> {
    #[inline(always)]
    fn of(observer: &Gains<T, N, S>, state: &ObserverState<T, N>, faults: Faults) -> Self {
        observer.estimate_with(state, faults)
    }
}

/// The fixed-point observer's estimate, as [`Observe::estimate_with`].
impl<const N: usize> Output<i16, FixedGains<N>> for FixedEstimate {
    #[inline(always)]
    fn of(observer: &FixedGains<N>, state: &FixedState<N>, faults: Faults) -> Self {
        observer.estimate_with(state, faults)
    }
}

/// A chain's states, held together ([`ChainState`]: one pointer through the out-of-line
/// path) or apart (a pair of references: a bank's lane, a block's local copy of the
/// observer's state).
pub(crate) trait States<F, O> {
    /// The front end's state and the observer's, borrowed together.
    fn split(&mut self) -> (&mut F, &mut O);
}

impl<F, O> States<F, O> for ChainState<F, O> {
    #[inline(always)]
    fn split(&mut self) -> (&mut F, &mut O) {
        (&mut self.front_end, &mut self.observer)
    }
}

impl<F, O> States<F, O> for (&mut F, &mut O) {
    #[inline(always)]
    fn split(&mut self) -> (&mut F, &mut O) {
        (&mut *self.0, &mut *self.1)
    }
}

/// The body of every chain's `track` and `update`: the front end's forward pass with the
/// observer's prediction, then the observer's step, and the result `R`; unless the front
/// end is quiet, out of line with the feedback to the front end, its faults latched (which
/// the result then carries) and the observer coasting where the front end says the sample
/// is not a measurement. Quiet is asked before the forward pass (the out-of-line path then
/// holds the whole sample), or after it for a front end whose quiet depends on the sample
/// ([`Stage::QUIET_FROM_INPUT`], a constant: one of the two is compiled).
#[inline(always)]
pub(crate) fn track<V, X, F, O, R>(
    chain: &Chain<F, O>,
    states: &mut impl States<F::State, O::State>,
    input: X,
) -> R
where
    V: ChainNumber,
    F: Stage<V, X>,
    O: Observe<V>,
    R: Output<V, O>,
{
    if !F::QUIET_FROM_INPUT && !chain.front_end.quiet(states.split().0) {
        // A call in tail position: the quiet path calls nothing and saves no register.
        return track_with_feedback(chain, states, input);
    }
    let (pair, memo) = {
        let (front_end, observer) = states.split();
        let prediction = chain.observer.prediction(observer);
        chain.front_end.forward(front_end, &prediction, input)
    };
    if F::QUIET_FROM_INPUT && !chain.front_end.quiet(states.split().0) {
        return finish_with_feedback_out_of_line(chain, states, pair, memo);
    }
    let observer = states.split().1;
    chain.observer.track_observing(observer, pair.0, pair.1, ());
    R::of(&chain.observer, observer, Faults::NONE)
}

/// [`track`] on a sample that a stage learns from or flags (out of line, as the online
/// calibration's learning: the registers it needs are saved here only; `cold`, so that
/// the quiet path is laid out first and costs its one test).
#[cold]
#[inline(never)]
fn track_with_feedback<V, X, F, O, R>(
    chain: &Chain<F, O>,
    states: &mut impl States<F::State, O::State>,
    input: X,
) -> R
where
    V: ChainNumber,
    F: Stage<V, X>,
    O: Observe<V>,
    R: Output<V, O>,
{
    let (pair, memo) = {
        let (front_end, observer) = states.split();
        let prediction = chain.observer.prediction(observer);
        chain.front_end.forward(front_end, &prediction, input)
    };
    finish_with_feedback(&chain.front_end, &chain.observer, states, pair, memo)
}

/// [`finish_with_feedback`] out of line, for a front end that is quiet or not after the
/// forward pass.
#[cold]
#[inline(never)]
fn finish_with_feedback_out_of_line<V, X, F, O, R>(
    chain: &Chain<F, O>,
    states: &mut impl States<F::State, O::State>,
    pair: (V, V),
    memo: F::Memo,
) -> R
where
    V: ChainNumber,
    F: Stage<V, X>,
    O: Observe<V>,
    R: Output<V, O>,
{
    finish_with_feedback(&chain.front_end, &chain.observer, states, pair, memo)
}

/// The observer's step on the front end's `pair` with the feedback of `memo` to the front
/// end (or its coast, where the front end says the sample is not a measurement), then the
/// front end's faults, latched and carried by the result.
#[inline(always)]
pub(super) fn finish_with_feedback<V, X, F, O, R>(
    front_end: &F,
    observer: &O,
    states: &mut impl States<F::State, O::State>,
    (y_c, y_s): (V, V),
    memo: F::Memo,
) -> R
where
    V: ChainNumber,
    F: Stage<V, X>,
    O: Observe<V>,
    R: Output<V, O>,
{
    let (front_end_state, observer_state) = states.split();
    if front_end.coasts(front_end_state) {
        observer.coast(observer_state);
        front_end.feedback(front_end_state, memo, None);
    } else {
        let to_front_end = ToFrontEnd {
            front_end,
            state: &mut *front_end_state,
            memo,
            input: PhantomData,
        };
        observer.track_observing(observer_state, y_c, y_s, to_front_end);
    }
    let faults = front_end.faults(front_end_state);
    // Latched unconditionally: cheaper than a test.
    O::latch(observer_state, faults);
    R::of(observer, observer_state, faults)
}
