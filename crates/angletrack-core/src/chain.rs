//! The signal chain: front-end stages composed with the observer, with one
//! [`Chain::track`] and one [`Chain::update`] for every combination (`docs/theory.md §12`).
//!
//! The composition, the feedback interface and an example are on [`Chain`].

use crate::faults::Faults;
use crate::gains::Gains;
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::state::{Estimate, ObserverState};
use crate::update::{SampleObserver, UsedSample};
use crate::wrap::wrap_angle;

/// The observer's prediction for the sample a stage is processing.
pub trait Prediction<T> {
    /// `(sin, cos)` of the observer's predicted angle for this sample (the angle wrapped to
    /// [-pi, pi), by the observer's phase-detector sin/cos).
    fn sin_cos(&self) -> (T, T);
}

/// What the observer made of a sample it used, for the stages before it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Feedback<T> {
    /// `(sin, cos)` of the sample's predicted angle.
    pub sin_cos: (T, T),
    /// The corrected speed in rad per sample (`Ts Omega`; 0 at order 1).
    pub scaled_speed: T,
    /// The sample's faults, as the observer's monitor flagged them.
    pub faults: Faults,
}

/// A front-end stage: `&self` is its immutable configuration, [`Stage::State`] its mutable
/// state; it turns an input `X` into the `(y_c, y_s)` pair the next stage (or the observer)
/// takes. See [`Chain`] for the composition and the feedback interface.
pub trait Stage<T: Float, X> {
    /// The stage's mutable state (`()` for a stage without one).
    type State;
    /// What [`Stage::forward`] keeps of a sample for [`Stage::feedback`] (`()` where the
    /// stage learns nothing: no cost).
    type Memo: Copy;

    /// One sample `input`, with the observer's `prediction` for it: the pair for the next
    /// stage, and what to keep for the feedback.
    fn forward(
        &self,
        state: &mut Self::State,
        prediction: &impl Prediction<T>,
        input: X,
    ) -> ((T, T), Self::Memo);

    /// What the observer made of the sample: `Some` for a sample it used, `None` for one it
    /// did not. The default does nothing.
    #[inline(always)]
    fn feedback(&self, _state: &mut Self::State, _memo: Self::Memo, _used: Option<Feedback<T>>) {}

    /// The stage's own faults (the default: none), carried by the estimate of
    /// [`Chain::update`] and latched in the observer's state.
    #[inline(always)]
    fn faults(&self, _state: &mut Self::State) -> Faults {
        Faults::NONE
    }
}

/// No stage: the pair goes to the observer as it is.
impl<T: Float> Stage<T, (T, T)> for () {
    type State = ();
    type Memo = ();

    #[inline(always)]
    fn forward(&self, _: &mut (), _: &impl Prediction<T>, input: (T, T)) -> ((T, T), ()) {
        (input, ())
    }
}

/// `A` then `B`.
impl<T: Float, X, A: Stage<T, X>, B: Stage<T, (T, T)>> Stage<T, X> for (A, B) {
    type State = (A::State, B::State);
    type Memo = (A::Memo, B::Memo);

    #[inline(always)]
    fn forward(
        &self,
        state: &mut Self::State,
        prediction: &impl Prediction<T>,
        input: X,
    ) -> ((T, T), Self::Memo) {
        let (pair, first) = self.0.forward(&mut state.0, prediction, input);
        let (pair, second) = self.1.forward(&mut state.1, prediction, pair);
        (pair, (first, second))
    }

    #[inline(always)]
    fn feedback(&self, state: &mut Self::State, memo: Self::Memo, used: Option<Feedback<T>>) {
        self.0.feedback(&mut state.0, memo.0, used);
        self.1.feedback(&mut state.1, memo.1, used);
    }

    #[inline(always)]
    fn faults(&self, state: &mut Self::State) -> Faults {
        self.0.faults(&mut state.0) | self.1.faults(&mut state.1)
    }
}

/// A front end `F` (a [`Stage`], or a nest of pairs of them) and the observer's [`Gains`]:
/// the immutable configuration of one signal chain. `Copy` where its stages are, so one
/// chain serves many channels, each with its [`ChainState`].
///
/// A [`Stage`] is an immutable `Copy` configuration (the `&self` of its methods) with a
/// separate mutable [`Stage::State`], in the manner of a `Process` block with a split
/// configuration and state: stages compose by their types, a pair `(A, B)` being the stage
/// that runs `A` then `B`, at no cost beyond the stages' own (the composition is resolved at
/// compile time and inlined). The front end turns an input `X` (ADC counts, or a `(y_c,
/// y_s)` pair in any unit) into the `(y_c, y_s)` pair the observer's phase detector takes.
///
/// The stages that need the observer reach it through one feedback interface, not through
/// entry points of their own:
/// - before the observer, [`Prediction`]: the `(sin, cos)` of the observer's predicted angle
///   for the sample (the angle correction rotates the sample by the error there);
/// - after it, [`Stage::feedback`] with [`Feedback`]: what the observer made of the sample
///   (the online calibration learns from it), or `None` for a sample it did not use;
/// - [`Stage::faults`]: the stage's own faults, carried by the sample's estimate and latched
///   in the observer's state.
///
/// ```
/// use angletrack_core::{AdcScaling, AngleCorrection, Chain, ChainState, Gains, SensorCalibration};
/// // A 12-bit ADC, the sensor's stored calibration, its harmonic angle error, the observer.
/// let adc = AdcScaling::<f32>::offset_binary(12)?;
/// let calibration = SensorCalibration::new(0.02, -0.01, 1.0, 1.05, 0.01)?;
/// let correction = AngleCorrection::new([0.0; 8], [0.0, 0.0, 0.004, 0.0, 0.0, 0.0, 0.0, 0.0])?;
/// let gains = Gains::<f32, 3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
/// let chain = Chain::new((adc, (calibration, correction)), gains);
/// let mut state = ChainState::new();
/// let estimate = chain.update(&mut state, (2048u16 + 900, 2048u16 + 1559));
/// assert!((estimate.angle - 1.05).abs() < 0.05);
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chain<F, T: Float, const N: usize, S = <T as Float>::DefaultSinCos> {
    /// The stages before the observer.
    pub front_end: F,
    /// The observer.
    pub gains: Gains<T, N, S>,
}

/// The mutable state of one channel of a [`Chain`]: its front end's and its observer's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainState<F, T, const N: usize> {
    /// The front end's state (a nest of pairs, as the front end's stages).
    pub front_end: F,
    /// The observer's state.
    pub observer: ObserverState<T, N>,
}

impl<F: Default, T: Float, const N: usize> Default for ChainState<F, T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<F: Default, T: Float, const N: usize> ChainState<F, T, N> {
    /// The state of a chain that has seen no sample: each stage's default state, and an
    /// observer that initialises itself from its first sample.
    ///
    /// ```
    /// use angletrack_core::{ChainState, Calibrator};
    /// let state: ChainState<Calibrator<f32>, f32, 3> = ChainState::new();
    /// assert!(!state.observer.is_initialised());
    /// ```
    pub fn new() -> Self {
        Self {
            front_end: F::default(),
            observer: ObserverState::new(),
        }
    }
}

/// The observer's prediction, computed only if a stage asks for it.
struct ObserverPrediction<'a, T, const N: usize, S> {
    state: &'a ObserverState<T, N>,
    sin_cos: core::marker::PhantomData<S>,
}

impl<T: Float, const N: usize, S: SinCos<T>> Prediction<T> for ObserverPrediction<'_, T, N, S> {
    #[inline(always)]
    fn sin_cos(&self) -> (T, T) {
        let mut angle = self.state.predicted_angle();
        wrap_angle(&mut angle);
        S::sin_cos(angle)
    }
}

/// Hands what the observer made of a sample back to the front end `F` (of input `X`).
struct ToFrontEnd<'a, T: Float, X, F: Stage<T, X>> {
    front_end: &'a F,
    state: &'a mut F::State,
    memo: F::Memo,
    input: core::marker::PhantomData<fn(X) -> T>,
}

impl<T: Float, X, F: Stage<T, X>> SampleObserver<T> for ToFrontEnd<'_, T, X, F> {
    #[inline(always)]
    fn observe(self, used: Option<UsedSample<T>>) {
        let used = used.map(|u| Feedback {
            sin_cos: u.sin_cos,
            scaled_speed: u.scaled_speed,
            faults: u.faults,
        });
        self.front_end.feedback(self.state, self.memo, used);
    }
}

impl<F, T: Float, const N: usize, S: SinCos<T>> Chain<F, T, N, S> {
    /// The chain of the front end `front_end` and the observer `gains` (both checked when
    /// they were made: a chain cannot be invalid).
    ///
    /// ```
    /// use angletrack_core::{AdcScaling, Chain, ChainState, Gains};
    /// let gains = Gains::<f32, 2>::new([0.05, 0.0012], 1e-4)?;
    /// let chain = Chain::new(AdcScaling::offset_binary(12)?, gains);
    /// let mut state = ChainState::new();
    /// chain.track(&mut state, (4095u16, 2048u16));
    /// assert!(chain.estimate(&state).angle.abs() < 1e-3);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn new(front_end: F, gains: Gains<T, N, S>) -> Self {
        Self { front_end, gains }
    }

    /// One sample `input` through the front end and the observer: the state only, the
    /// cheapest per-sample form ([`Chain::estimate`] reads the estimate on demand). The
    /// front end's faults are latched in the observer's state.
    #[inline]
    pub fn track<X>(&self, state: &mut ChainState<F::State, T, N>, input: X)
    where
        F: Stage<T, X>,
    {
        let prediction = ObserverPrediction::<T, N, S> {
            state: &state.observer,
            sin_cos: core::marker::PhantomData,
        };
        let ((y_c, y_s), memo) = self
            .front_end
            .forward(&mut state.front_end, &prediction, input);
        let to_front_end = ToFrontEnd {
            front_end: &self.front_end,
            state: &mut state.front_end,
            memo,
            input: core::marker::PhantomData,
        };
        self.gains
            .track_observing(&mut state.observer, y_c, y_s, to_front_end);
        let faults = self.front_end.faults(&mut state.front_end);
        if !faults.is_empty() {
            state.observer.monitor.latched |= faults;
        }
    }

    /// [`Chain::track`], then the estimate, which carries the front end's faults.
    #[inline]
    pub fn update<X>(&self, state: &mut ChainState<F::State, T, N>, input: X) -> Estimate<T>
    where
        F: Stage<T, X>,
    {
        self.track(state, input);
        let mut estimate = self.gains.estimate(&state.observer);
        estimate.faults |= self.front_end.faults(&mut state.front_end);
        estimate
    }

    /// The estimate held by `state`, in physical units (the observer's faults; the front
    /// end's are latched).
    #[inline]
    pub fn estimate<St>(&self, state: &ChainState<St, T, N>) -> Estimate<T> {
        self.gains.estimate(&state.observer)
    }

    /// [`Chain::update`] on each of `inputs`, the estimates written to `estimates` (the
    /// shorter of the two sets the count, which is returned).
    pub fn update_block<X: Copy>(
        &self,
        state: &mut ChainState<F::State, T, N>,
        inputs: &[X],
        estimates: &mut [Estimate<T>],
    ) -> usize
    where
        F: Stage<T, X>,
    {
        let count = inputs.len().min(estimates.len());
        for (input, estimate) in inputs.iter().zip(estimates.iter_mut()) {
            *estimate = self.update(state, *input);
        }
        count
    }
}

mod stages;

pub use stages::OnlineCalibration;

#[cfg(test)]
mod tests;
