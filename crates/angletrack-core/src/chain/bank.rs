//! The bank form of a chain: `L` channels through one chain configuration, each lane with
//! its front end's state, the observers' states side by side in a [`ChannelBank`] so that
//! the recursion runs on every lane at once (`Gains::update_bank`, vectorised).

use core::marker::PhantomData;

use super::observers::{Observe, finish_with_feedback};
use super::{Chain, ChainState, Prediction, Stage};
use crate::bank::ChannelBank;
use crate::faults::Faults;
use crate::gains::Gains;
use crate::real::Float;
use crate::real::sincos::SinCos;
use crate::state::{Estimate, ObserverState};
use crate::wrap::wrap_angle;

/// A lane's prediction, as the single observer's: its predicted angle (a bank keeps it
/// live for every lane) and, on demand, its `(sin, cos)`.
struct LanePrediction<T, S> {
    angle: T,
    sin_cos: PhantomData<S>,
}

impl<T: Float, S: SinCos<T>> Prediction<T> for LanePrediction<T, S> {
    #[inline(always)]
    fn angle(&self) -> T {
        self.angle
    }

    #[inline(always)]
    fn sin_cos(&self) -> (T, T) {
        let mut angle = self.angle;
        wrap_angle(&mut angle);
        S::sin_cos(angle)
    }
}

impl<F: Default, T: Float, const N: usize, const L: usize>
    ChainState<[F; L], ChannelBank<T, N, L>>
{
    /// The state of a chain's bank of `L` channels that have seen no sample: each lane's
    /// front end in its default state, and a [`ChannelBank`] whose lanes initialise
    /// themselves from their first valid sample.
    ///
    /// ```
    /// use angletrack_core::{AdcScaling, Chain, ChainState, Gains};
    /// let gains = Gains::<f64, 3>::new([0.06, 0.0019, 3e-5], 1e-4)?;
    /// let chain = Chain::new(AdcScaling::<f64>::offset_binary(12)?, gains);
    /// let mut bank = ChainState::new_bank();
    /// chain.track_bank(&mut bank, &[(4095u16, 2048u16); 64]);
    /// assert!(bank.observer.angles().iter().all(|a| a.abs() < 1e-3));
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    pub fn new_bank() -> Self {
        Self {
            front_end: core::array::from_fn(|_| F::default()),
            observer: ChannelBank::new(),
        }
    }
}

impl<F, T: Float, const N: usize, S: SinCos<T>> Chain<F, Gains<T, N, S>> {
    /// [`Chain::track`] on `L` channels at once, lane `j` taking `inputs[j]`: each lane's
    /// front end forwards its input with its lane's prediction; where every lane's front
    /// end is quiet ([`Stage::quiet`]) the observers run side by side
    /// (vectorised), otherwise lane by lane with the feedback to
    /// the front end, its faults latched and the coast of a sample that is not a
    /// measurement, exactly as [`Chain::track`] with the monitor off (a bank runs no
    /// monitor). The front ends' faults are latched per lane
    /// ([`ChannelBank::latched_faults`]).
    ///
    /// ```
    /// use angletrack_core::{
    ///     CalibrationSettings, Calibrator, Chain, ChainState, ChannelBank, Gains, OnlineCalibration,
    /// };
    /// let gains = Gains::<f32, 3>::new([0.06, 0.0019, 3e-5], 1e-4)?;
    /// let online = OnlineCalibration::new(CalibrationSettings::default(), 1e-4)?;
    /// let chain = Chain::new(online, gains);
    /// let mut bank = ChainState::<[Calibrator<f32>; 2], ChannelBank<f32, 3, 2>>::new_bank();
    /// bank.front_end[1].enable(); // lane 1 learns its offsets, lane 0 does not
    /// // A shaft at rest at 1 rad, read by two sensors.
    /// for _ in 0..100 {
    ///     chain.track_bank(&mut bank, &[(0.5403, 0.8415); 2]);
    /// }
    /// assert!(bank.observer.angles().iter().all(|a| (a - 1.0).abs() < 1e-3));
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    #[inline]
    pub fn track_bank<X: Copy, const L: usize>(
        &self,
        state: &mut ChainState<[F::State; L], ChannelBank<T, N, L>>,
        inputs: &[X; L],
    ) where
        F: Stage<T, X>,
    {
        bank_track(self, state, inputs);
    }

    /// [`Chain::track_bank`], then each lane's estimate, which carries its front end's
    /// faults of the sample (as [`Chain::update`]).
    #[inline]
    pub fn update_bank<X: Copy, const L: usize>(
        &self,
        state: &mut ChainState<[F::State; L], ChannelBank<T, N, L>>,
        inputs: &[X; L],
    ) -> [Estimate<T>; L]
    where
        F: Stage<T, X>,
    {
        let faults = bank_track(self, state, inputs);
        core::array::from_fn(|lane| {
            let mut estimate = self.observer.lane_estimate(&state.observer, lane);
            estimate.faults |= faults[lane];
            estimate
        })
    }
}

/// The body of [`Chain::track_bank`]: the front ends' forward pass, then the observers side
/// by side if every front end is quiet, else lane by lane with the feedback. Returns the
/// front ends' faults of the sample.
#[inline(always)]
fn bank_track<F: Stage<T, X>, X: Copy, T: Float, const N: usize, S: SinCos<T>, const L: usize>(
    chain: &Chain<F, Gains<T, N, S>>,
    state: &mut ChainState<[F::State; L], ChannelBank<T, N, L>>,
    inputs: &[X; L],
) -> [Faults; L] {
    let front_end = &chain.front_end;
    if !F::QUIET_FROM_INPUT && !state.front_end.iter().all(|s| front_end.quiet(s)) {
        return lanes_with_feedback(chain, state, inputs);
    }
    let mut y_c = [T::ZERO; L];
    let mut y_s = [T::ZERO; L];
    let forward = |lane: usize, front_end_state: &mut F::State| {
        let prediction = LanePrediction::<T, S> {
            angle: state.observer.predicted_angle(lane),
            sin_cos: PhantomData,
        };
        front_end.forward(front_end_state, &prediction, inputs[lane])
    };
    if F::QUIET_FROM_INPUT {
        let memos: [F::Memo; L] = core::array::from_fn(|lane| {
            let ((c, s), memo) = forward(lane, &mut state.front_end[lane]);
            (y_c[lane], y_s[lane]) = (c, s);
            memo
        });
        if !state.front_end.iter().all(|s| front_end.quiet(s)) {
            return forwarded_lanes_with_feedback(chain, state, (&y_c, &y_s), memos);
        }
    } else {
        // A plain loop (the memos are not needed: the front end is quiet), which the
        // compiler vectorises where the stages' forward passes allow.
        for lane in 0..L {
            ((y_c[lane], y_s[lane]), _) = forward(lane, &mut state.front_end[lane]);
        }
    }
    chain.observer.update_bank(&mut state.observer, &y_c, &y_s);
    [Faults::NONE; L]
}

/// [`bank_track`] on a sample some lane's front end learns from or flags: each lane as
/// [`Chain::track`] with the monitor off (out of line).
#[cold]
#[inline(never)]
fn lanes_with_feedback<
    F: Stage<T, X>,
    X: Copy,
    T: Float,
    const N: usize,
    S: SinCos<T>,
    const L: usize,
>(
    chain: &Chain<F, Gains<T, N, S>>,
    state: &mut ChainState<[F::State; L], ChannelBank<T, N, L>>,
    inputs: &[X; L],
) -> [Faults; L] {
    let gains = chain.observer.unmonitored();
    each_lane(state, |lane, front_end, observer| {
        let (pair, memo) = {
            let prediction = Observe::prediction(&gains, observer);
            chain
                .front_end
                .forward(front_end, &prediction, inputs[lane])
        };
        finish_with_feedback(
            &chain.front_end,
            &gains,
            &mut (front_end, observer),
            pair,
            memo,
        )
    })
}

/// [`lanes_with_feedback`] after the forward pass (for a front end whose quiet depends on
/// the sample: [`Stage::QUIET_FROM_INPUT`]).
#[cold]
#[inline(never)]
fn forwarded_lanes_with_feedback<
    F: Stage<T, X>,
    X,
    T: Float,
    const N: usize,
    S: SinCos<T>,
    const L: usize,
>(
    chain: &Chain<F, Gains<T, N, S>>,
    state: &mut ChainState<[F::State; L], ChannelBank<T, N, L>>,
    (y_c, y_s): (&[T; L], &[T; L]),
    memos: [F::Memo; L],
) -> [Faults; L] {
    let gains = chain.observer.unmonitored();
    each_lane(state, |lane, front_end, observer| {
        let pair = (y_c[lane], y_s[lane]);
        finish_with_feedback(
            &chain.front_end,
            &gains,
            &mut (front_end, observer),
            pair,
            memos[lane],
        )
    })
}

/// Runs `lane_step` on each lane's front-end state and its lane as a single observer's
/// state, which is written back with the front end's faults it returns (latched).
#[inline(always)]
fn each_lane<FS, T: Float, const N: usize, const L: usize>(
    state: &mut ChainState<[FS; L], ChannelBank<T, N, L>>,
    mut lane_step: impl FnMut(usize, &mut FS, &mut ObserverState<T, N>) -> Faults,
) -> [Faults; L] {
    let bank = &mut state.observer;
    let faults = core::array::from_fn(|lane| {
        let mut observer = bank.lane_state(lane);
        let faults = lane_step(lane, &mut state.front_end[lane], &mut observer);
        bank.set_lane(lane, &observer);
        bank.latch(lane, faults);
        faults
    });
    bank.update_rare();
    faults
}

#[cfg(test)]
mod tests;
