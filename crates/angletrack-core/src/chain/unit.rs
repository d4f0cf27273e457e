//! A chain's float observer whose phase detector's sin/cos is a unit with state
//! ([`SinCosUnit`]: a hardware CORDIC), the unit kept in the chain's state beside the
//! observer's: [`UnitGains`].

use core::marker::PhantomData;

use super::observers::{FloatPrediction, Observe, Output};
use super::{Chain, ChainState, Stage, observers};
use crate::faults::Faults;
use crate::gains::Gains;
use crate::real::Float;
use crate::real::sincos::{SinCos, SinCosUnit};
use crate::state::{Estimate, ObserverState};
use crate::update::SampleObserver;

/// [`Gains`] whose phase detector's `(sin, cos)` is computed by a unit with state `U`
/// (the CORDIC coprocessor of an STM32G4, whose registers are written and read; a table
/// with a cache) instead of the gains' `S`: the observer of a [`Chain`] whose state keeps
/// the observer's state and the unit side by side, `(ObserverState, U)`. The unit is used
/// once per used sample, on the wrapped predicted angle; the front end's stages that ask
/// for the prediction's `(sin, cos)` get the gains' `S`.
///
/// ```
/// use angletrack_core::{Chain, ChainState, Gains, ObserverState, SinCosUnit};
/// /// A unit that counts its uses (a real one would drive a peripheral).
/// #[derive(Default)]
/// struct CountingUnit {
///     uses: u32,
/// }
/// impl SinCosUnit<f32> for CountingUnit {
///     fn sin_cos(&mut self, angle: f32) -> (f32, f32) {
///         self.uses += 1;
///         (libm::sinf(angle), libm::cosf(angle))
///     }
/// }
/// let gains = Gains::<f32, 3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
/// let chain = Chain::new((), gains.with_unit::<CountingUnit>());
/// let mut state = ChainState { front_end: (), observer: (ObserverState::new(), CountingUnit::default()) };
/// for _ in 0..3 {
///     chain.update(&mut state, (0.5, 0.866));
/// }
/// // The first sample sets the angle from atan2; the second and third are used.
/// assert_eq!(state.observer.1.uses, 2);
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitGains<T: Float, const N: usize, U, S = <T as Float>::DefaultSinCos> {
    /// The gains.
    pub gains: Gains<T, N, S>,
    unit: PhantomData<fn() -> U>,
}

impl<T: Float, const N: usize, S: SinCos<T>> Gains<T, N, S> {
    /// These gains with the phase detector's `(sin, cos)` computed by a unit with state `U`
    /// (see [`UnitGains`]).
    ///
    /// ```
    /// use angletrack_core::{Chain, ChainState, Fast, Gains, ObserverState};
    /// let gains = Gains::<f32, 2>::new([0.05, 0.0012], 1e-4)?;
    /// // `Fast` is a unit too: the same bits as the gains' own sin/cos.
    /// let (plain, united) = (Chain::new((), gains), Chain::new((), gains.with_unit::<Fast>()));
    /// let mut state = ChainState::new();
    /// let mut unit_state = ChainState { front_end: (), observer: (ObserverState::new(), Fast) };
    /// for k in 0..10 {
    ///     let y = (0.1 * k as f32).sin_cos();
    ///     assert_eq!(plain.update(&mut state, (y.1, y.0)), united.update(&mut unit_state, (y.1, y.0)));
    /// }
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub const fn with_unit<U: SinCosUnit<T>>(self) -> UnitGains<T, N, U, S> {
        UnitGains {
            gains: self,
            unit: PhantomData,
        }
    }
}

impl<T: Float, const N: usize, U: SinCosUnit<T>, S: SinCos<T>> Observe<T>
    for UnitGains<T, N, U, S>
{
    type State = (ObserverState<T, N>, U);
    type Estimate = Estimate<T>;
    type Prediction<'a>
        = FloatPrediction<'a, T, N, S>
    where
        Self: 'a,
        U: 'a;

    #[inline(always)]
    fn prediction<'a>(&'a self, state: &'a Self::State) -> FloatPrediction<'a, T, N, S> {
        Observe::prediction(&self.gains, &state.0)
    }

    #[inline(always)]
    fn track_observing(
        &self,
        state: &mut Self::State,
        y_c: T,
        y_s: T,
        observer: impl SampleObserver<T>,
    ) {
        let (observer_state, unit) = state;
        self.gains
            .track_observing_with(observer_state, unit, y_c, y_s, observer);
    }

    #[inline(always)]
    fn coast(&self, state: &mut Self::State) {
        Observe::coast(&self.gains, &mut state.0);
    }

    #[inline(always)]
    fn latch(state: &mut Self::State, faults: Faults) {
        <Gains<T, N, S> as Observe<T>>::latch(&mut state.0, faults);
    }

    #[inline(always)]
    fn estimate_with(&self, state: &Self::State, faults: Faults) -> Estimate<T> {
        Observe::estimate_with(&self.gains, &state.0, faults)
    }
}

/// The estimate, as [`Observe::estimate_with`].
impl<T: Float, const N: usize, U: SinCosUnit<T>, S: SinCos<T>> Output<T, UnitGains<T, N, U, S>>
    for Estimate<T>
{
    #[inline(always)]
    fn of(
        observer: &UnitGains<T, N, U, S>,
        state: &(ObserverState<T, N>, U),
        faults: Faults,
    ) -> Self {
        observer.estimate_with(state, faults)
    }
}

impl<F, T: Float, const N: usize, U: SinCosUnit<T>, S: SinCos<T>> Chain<F, UnitGains<T, N, U, S>> {
    /// One sample `input` through the front end and the observer, its `(sin, cos)` by the
    /// unit in `state`: the state only, as [`Chain::track`] of the gains' own.
    #[inline]
    pub fn track<X>(&self, state: &mut ChainState<F::State, (ObserverState<T, N>, U)>, input: X)
    where
        F: Stage<T, X>,
    {
        observers::track::<_, _, _, _, ()>(self, state, input)
    }

    /// [`Chain::track`], then the estimate, which carries the front end's faults.
    #[inline]
    pub fn update<X>(
        &self,
        state: &mut ChainState<F::State, (ObserverState<T, N>, U)>,
        input: X,
    ) -> Estimate<T>
    where
        F: Stage<T, X>,
    {
        observers::track(self, state, input)
    }

    /// The estimate held by `state`, in physical units (see [`Chain::estimate`]).
    #[inline]
    pub fn estimate<St>(&self, state: &ChainState<St, (ObserverState<T, N>, U)>) -> Estimate<T> {
        self.observer.gains.estimate(&state.observer.0)
    }
}
