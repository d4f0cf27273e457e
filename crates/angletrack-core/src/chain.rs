//! The signal chain: front-end stages composed with the observer, with one
//! [`Chain::track`] and one [`Chain::update`] for every combination (`docs/theory.md §15`).
//!
//! The composition, the feedback interface and an example are on [`Chain`].

use crate::faults::Faults;
use crate::fixed::{FixedEstimate, FixedGains, FixedState};
use crate::gains::Gains;
use crate::real::sincos::SinCos;
use crate::real::{ChainNumber, Float};
use crate::state::{Estimate, ObserverState};

mod bank;
mod front_end_check;
mod held_rails;
mod observers;
mod stages;
mod unit;

pub use front_end_check::{FrontEndCheck, FrontEndCheckState, WindingCheck};
pub use held_rails::{
    HELD_RAIL_SAMPLES, HeldRailCheck, HeldRails, RAIL_BAND_PER_SPAN, RailSample,
    is_piled_up_at_rail,
};
pub use stages::OnlineCalibration;
pub use unit::UnitGains;

/// The observer's prediction for the sample a stage is processing, in the observer's
/// number format: for the float observers the angle in rad and `(sin, cos)` in `T`; for
/// the fixed-point observer the binary angle (2^32 per turn) and `(sin, cos)` in Q15.
pub trait Prediction<V: ChainNumber> {
    /// The observer's predicted angle for this sample: within one turn while the observer
    /// tracks (for the floats, possibly a turn outside [-pi, pi) on the sample that starts
    /// tracking: a stage that needs one turn wraps it).
    fn angle(&self) -> V::Angle;
    /// `(sin, cos)` of the predicted angle (by the observer's phase-detector sin/cos).
    fn sin_cos(&self) -> (V, V);
}

/// What the observer made of a sample it used, for the stages before it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Feedback<V> {
    /// `(sin, cos)` of the sample's predicted angle (Q15 for the fixed-point observer).
    pub sin_cos: (V, V),
    /// The corrected speed per sample: rad for the float observers (`Ts Omega`; 0 at
    /// order 1), 2^-16 turn for the fixed-point observer (saturated).
    pub scaled_speed: V,
    /// The sample's faults, as the observer's monitor flagged them.
    pub faults: Faults,
    /// The sample's normalised phase error: the sine of the angle between the sample and
    /// its prediction (Q15 for the fixed-point observer, saturated).
    pub phase_error: V,
}

/// A front-end stage: `&self` is its immutable configuration, [`Stage::State`] its mutable
/// state; it turns an input `X` into the `(y_c, y_s)` pair of values `V` the next stage (or
/// the observer) takes. See [`Chain`] for the composition and the feedback interface.
pub trait Stage<V: ChainNumber, X> {
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
        prediction: &impl Prediction<V>,
        input: X,
    ) -> ((V, V), Self::Memo);

    /// What the observer made of the sample: `Some` for a sample it used, `None` for one it
    /// did not. The default does nothing.
    #[inline(always)]
    fn feedback(&self, _state: &mut Self::State, _memo: Self::Memo, _used: Option<Feedback<V>>) {}

    /// The stage's own faults (the default: none), carried by the estimate of
    /// [`Chain::update`] and latched in the observer's state.
    #[inline(always)]
    fn faults(&self, _state: &mut Self::State) -> Faults {
        Faults::NONE
    }

    /// Whether the sample the stage last forwarded is not a measurement (a front-end fault
    /// that invalidates it: loss of excitation, a winding open or shorted, both channels
    /// clipped; the default: never). The observer then does not use the sample but coasts
    /// on its prediction (the recursion's prediction step alone: speed and acceleration
    /// held), and re-acquires at the first sample after the fault as after a rejected one
    /// (a false-lock check on that sample alone). Read only on the out-of-line path: a
    /// stage that coasts is not [`Stage::quiet`] on that sample.
    #[inline(always)]
    fn coasts(&self, _state: &Self::State) -> bool {
        false
    }

    /// Whether [`Stage::quiet`] depends on the sample the stage just forwarded (a check of
    /// the input, as [`FrontEndCheck`]): the chain then asks after the forward pass, and
    /// otherwise before it (the default, `false`: the out-of-line path then holds the whole
    /// sample, the cheapest layout). A constant, so that a chain compiles one of the two.
    const QUIET_FROM_INPUT: bool = false;

    /// Whether the stage, in its `state`, neither learns from the sample nor flags a fault
    /// (`true` for a stage that has neither; an online calibration that is off; a front-end
    /// check that found nothing in the sample it just forwarded, asked after the forward
    /// pass: [`Stage::QUIET_FROM_INPUT`]): the chain then runs the observer without [`Stage::feedback`] and
    /// [`Stage::faults`], at the cost of the stages' forward pass alone, and otherwise out
    /// of line with them. Required, so that no stage that learns is silently left quiet.
    fn quiet(&self, state: &Self::State) -> bool;
}

/// No stage: the pair goes to the observer as it is.
impl<V: ChainNumber> Stage<V, (V, V)> for () {
    type State = ();
    type Memo = ();

    #[inline(always)]
    fn forward(&self, _: &mut (), _: &impl Prediction<V>, input: (V, V)) -> ((V, V), ()) {
        (input, ())
    }

    #[inline(always)]
    fn quiet(&self, _: &()) -> bool {
        true
    }
}

/// A stage that may be absent (a firmware's configuration chosen at start-up): skipped, at
/// the cost of one test, when `None`; it learns, flags and is quiet as the stage it holds.
impl<V: ChainNumber, S: Stage<V, (V, V)>> Stage<V, (V, V)> for Option<S> {
    type State = S::State;
    type Memo = Option<S::Memo>;
    const QUIET_FROM_INPUT: bool = S::QUIET_FROM_INPUT;

    #[inline(always)]
    fn forward(
        &self,
        state: &mut S::State,
        prediction: &impl Prediction<V>,
        input: (V, V),
    ) -> ((V, V), Self::Memo) {
        match self {
            Some(stage) => {
                let (pair, memo) = stage.forward(state, prediction, input);
                (pair, Some(memo))
            }
            None => (input, None),
        }
    }

    #[inline(always)]
    fn feedback(&self, state: &mut S::State, memo: Self::Memo, used: Option<Feedback<V>>) {
        if let (Some(stage), Some(memo)) = (self, memo) {
            stage.feedback(state, memo, used);
        }
    }

    #[inline(always)]
    fn faults(&self, state: &mut S::State) -> Faults {
        match self {
            Some(stage) => stage.faults(state),
            None => Faults::NONE,
        }
    }

    #[inline(always)]
    fn coasts(&self, state: &S::State) -> bool {
        match self {
            Some(stage) => stage.coasts(state),
            None => false,
        }
    }

    #[inline(always)]
    fn quiet(&self, state: &S::State) -> bool {
        match self {
            Some(stage) => stage.quiet(state),
            None => true,
        }
    }
}

/// `A` then `B`.
impl<V: ChainNumber, X, A: Stage<V, X>, B: Stage<V, (V, V)>> Stage<V, X> for (A, B) {
    type State = (A::State, B::State);
    type Memo = (A::Memo, B::Memo);
    const QUIET_FROM_INPUT: bool = A::QUIET_FROM_INPUT || B::QUIET_FROM_INPUT;

    #[inline(always)]
    fn forward(
        &self,
        state: &mut Self::State,
        prediction: &impl Prediction<V>,
        input: X,
    ) -> ((V, V), Self::Memo) {
        let (pair, first) = self.0.forward(&mut state.0, prediction, input);
        let (pair, second) = self.1.forward(&mut state.1, prediction, pair);
        (pair, (first, second))
    }

    #[inline(always)]
    fn feedback(&self, state: &mut Self::State, memo: Self::Memo, used: Option<Feedback<V>>) {
        self.0.feedback(&mut state.0, memo.0, used);
        self.1.feedback(&mut state.1, memo.1, used);
    }

    #[inline(always)]
    fn faults(&self, state: &mut Self::State) -> Faults {
        self.0.faults(&mut state.0) | self.1.faults(&mut state.1)
    }

    #[inline(always)]
    fn coasts(&self, state: &Self::State) -> bool {
        self.0.coasts(&state.0) || self.1.coasts(&state.1)
    }

    #[inline(always)]
    fn quiet(&self, state: &Self::State) -> bool {
        self.0.quiet(&state.0) && self.1.quiet(&state.1)
    }
}

/// A front end `F` (a [`Stage`], or a nest of pairs of them) and an observer `O` (the float
/// observers' [`Gains`], or the fixed-point [`FixedGains`]): the immutable configuration of
/// one signal chain. `Copy` where its stages are, so one
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
///   in the observer's state;
/// - [`Stage::coasts`]: the sample is not a measurement (a front-end fault, as a
///   [`FrontEndCheck`] finds): the observer coasts on its prediction instead of using it.
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
///
// `repr(C)`, the observer first: the per-sample path reads the observer's gains and state
// most, and at offset 0 a Cortex-M0 reaches them by its loads' immediate offsets instead of
// a base address computed and kept per sample (ChainState likewise).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub struct Chain<F, O> {
    /// The observer.
    pub observer: O,
    /// The stages before the observer.
    pub front_end: F,
}

/// The mutable state of one channel of a [`Chain`]: its front end's `F` (a nest of pairs,
/// as the front end's stages) and its observer's `O`.
// `repr(C)`, the observer first: see `Chain`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub struct ChainState<F, O> {
    /// The observer's state.
    pub observer: O,
    /// The front end's state.
    pub front_end: F,
}

impl<F: Default, O: Default> Default for ChainState<F, O> {
    fn default() -> Self {
        Self::new()
    }
}

impl<F: Default, O: Default> ChainState<F, O> {
    /// The state of a chain that has seen no sample: each stage's default state, and an
    /// observer that initialises itself from its first sample.
    ///
    /// ```
    /// use angletrack_core::{Calibrator, ChainState, ObserverState};
    /// let state: ChainState<Calibrator<f32>, ObserverState<f32, 3>> = ChainState::new();
    /// assert!(!state.observer.is_initialised());
    /// ```
    pub fn new() -> Self {
        Self {
            front_end: F::default(),
            observer: O::default(),
        }
    }
}

impl<F, O> Chain<F, O> {
    /// The chain of the front end `front_end` and the observer `observer` (both checked
    /// when they were made: a chain cannot be invalid).
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
    pub const fn new(front_end: F, observer: O) -> Self {
        Self {
            front_end,
            observer,
        }
    }
}

/// The chain's per-sample forms for one observer type: `track` (the state only, the
/// cheapest per-sample form, the front end's faults latched), `update` (`track`, then the
/// estimate, which carries the front end's faults) and `update_block` (`update` on each
/// input); `estimate` reads the estimate on demand.
macro_rules! chain_forms {
    ($value:ty, $state:ty, $estimate:ty) => {
        /// One sample `input` through the front end and the observer: the state only (the
        /// cheapest per-sample form; [`Chain::estimate`] reads the estimate on demand).
        /// The front end's faults are latched in the observer's state.
        #[inline]
        pub fn track<X>(&self, state: &mut ChainState<F::State, $state>, input: X)
        where
            F: Stage<$value, X>,
        {
            observers::track::<_, _, _, _, ()>(self, state, input)
        }

        /// [`Chain::track`], then the estimate, which carries the front end's faults.
        #[inline]
        pub fn update<X>(&self, state: &mut ChainState<F::State, $state>, input: X) -> $estimate
        where
            F: Stage<$value, X>,
        {
            observers::track(self, state, input)
        }

        /// [`Chain::update`] on each of `inputs` (a slice's `iter().copied()`, or two
        /// slices of `y_c` and `y_s` zipped), the estimates written to `estimates`: the
        /// shorter of the two sets the count, which is returned. The observer's state is
        /// kept in a local copy over the block, so that it can live in registers.
        ///
        /// ```
        /// use angletrack_core::{Chain, ChainState, Estimate, Gains};
        /// let chain = Chain::new((), Gains::<f64, 2>::new([0.05, 0.0012], 1e-4)?);
        /// let mut state = ChainState::new();
        /// let (y_c, y_s) = ([1.0, 1.0, 1.0], [0.0, 0.0, 0.0]);
        /// let mut out = [Estimate::default(); 3];
        /// let inputs = y_c.iter().copied().zip(y_s.iter().copied());
        /// assert_eq!(chain.update_block(&mut state, inputs, &mut out), 3);
        /// # Ok::<(), angletrack_core::ConfigError>(())
        /// ```
        #[inline]
        pub fn update_block<X>(
            &self,
            state: &mut ChainState<F::State, $state>,
            inputs: impl IntoIterator<Item = X>,
            estimates: &mut [$estimate],
        ) -> usize
        where
            F: Stage<$value, X>,
        {
            let mut observer = state.observer;
            let mut states = (&mut state.front_end, &mut observer);
            let mut count = 0;
            for (input, estimate) in inputs.into_iter().zip(estimates.iter_mut()) {
                *estimate = observers::track(self, &mut states, input);
                count += 1;
            }
            state.observer = observer;
            count
        }
    };
}

impl<F, T: Float, const N: usize, S: SinCos<T>> Chain<F, Gains<T, N, S>> {
    chain_forms!(T, ObserverState<T, N>, Estimate<T>);

    /// [`Chain::update`] on the front end's and the observer's states kept apart (the
    /// core's tests of the online calibration keep its calibrator apart).
    #[cfg(test)]
    pub(crate) fn update_parts<X>(
        &self,
        front_end: &mut F::State,
        observer: &mut ObserverState<T, N>,
        input: X,
    ) -> Estimate<T>
    where
        F: Stage<T, X>,
    {
        observers::track(self, &mut (front_end, observer), input)
    }

    /// The estimate held by `state`, in physical units (the observer's faults; the front
    /// end's are latched in the state).
    #[inline]
    pub fn estimate<St>(&self, state: &ChainState<St, ObserverState<T, N>>) -> Estimate<T> {
        self.observer.estimate(&state.observer)
    }
}

impl<F, const N: usize> Chain<F, FixedGains<N>> {
    chain_forms!(i16, FixedState<N>, FixedEstimate);

    /// The estimate held by `state` (the observer's faults; the front end's are latched
    /// in the state).
    #[inline]
    pub fn estimate<St>(&self, state: &ChainState<St, FixedState<N>>) -> FixedEstimate {
        FixedGains::estimate(&state.observer)
    }
}

#[cfg(test)]
mod coast_tests;
#[cfg(test)]
mod held_rail_tests;
#[cfg(test)]
mod jump_tests;
#[cfg(test)]
mod tests;
