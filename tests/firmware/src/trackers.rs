//! The trackers of the firmware test's variants: what one variant runs per sample
//! ([`Tracker`]), the core's `f32` entry points ([`EntryPoint`]: `Plain`, the observer
//! alone, a chain with no front end; the signal chains with stages in `chains.rs`), those
//! that return no estimate (`Track`), the fixed-point observer alone (`Fixed`, `FixedTrack`)
//! and the baselines' PLL. Shared, like `variants.rs`, by
//! the build script and the firmware.

use angletrack_core::fixed::binary_angle_to_rad;
use angletrack_core::{
    Chain, ChainState, Estimate, FixedEstimate, FixedGains, FixedState, Gains, ObserverState,
    Order, SinCos, SupportedOrder,
};

use crate::baseline::{Atan2, PhaseLockedLoop, PllState};
use crate::variants::Record;

/// What a variant runs per sample, and how its result compares with the host's.
pub trait Tracker {
    /// The per-channel state.
    type State;
    /// One input sample as the entry point takes it.
    type Input: Copy + PartialEq + 'static;
    /// What one update returns.
    type Output: Copy + Default;
    /// Whether [`Tracker::update_block`] is the core's block form (else it runs nothing).
    const BLOCK: bool = false;
    /// A fresh state.
    fn new_state(&self) -> Self::State;
    /// An input sample (amplitude about 1) as the entry point takes it (`check` mode and
    /// the build script convert with it).
    fn input(y: f32) -> Self::Input;
    /// The samples of `count` mode's runs as the entry point takes them, `[y_c, y_s]`:
    /// [`Tracker::input`] of the signal, converted before the run (by the build script), so
    /// that no conversion runs in the counted range (`check` mode verifies them).
    fn counted_inputs(inputs: &Inputs) -> [&'static [Self::Input]; 2];
    /// One sample.
    fn update(&self, state: &mut Self::State, y_c: Self::Input, y_s: Self::Input) -> Self::Output;
    /// The estimate after an update, as compared with the host's (read outside the counted
    /// update: an entry point that returns no estimate computes it here, on demand).
    fn record(&self, state: &Self::State, output: &Self::Output) -> Record;
    /// The estimate's integers (angle, turns, speed, acceleration, phase error, faults) of a
    /// tracker that computes in integers, which `check` compares with the host's exactly
    /// (through [`fold_integers`](crate::variants::fold_integers)); `None` for the float ones,
    /// compared within tolerances.
    fn integers(&self, _state: &Self::State, _output: &Self::Output) -> Option<[i64; 6]> {
        None
    }
    /// All samples in one call, if [`Tracker::BLOCK`]; returns the number of outputs.
    fn update_block(
        &self,
        _state: &mut Self::State,
        _y_c: &[f32],
        _y_s: &[f32],
        _out: &mut [Self::Output],
    ) -> usize {
        0
    }
}

/// One of the core's `Gains` entry points on an `f32` observer ([`Plain`], [`Calibrated`],
/// [`Adc`], [`Corrected`]): what differs between them. Each is a [`Tracker`] through the one
/// implementation below, which returns the core's estimate and records it.
pub trait EntryPoint {
    /// The per-channel state.
    type State: Default;
    /// One input sample as the entry point takes it.
    type Input: Sample;
    /// Whether [`EntryPoint::update_block`] is the core's block form (else it runs nothing).
    const BLOCK: bool = false;
    /// A fresh state.
    fn new_state(&self) -> Self::State {
        Self::State::default()
    }
    /// One sample.
    fn update(&self, state: &mut Self::State, y_c: Self::Input, y_s: Self::Input) -> Estimate<f32>;
    /// All samples in one call, if [`EntryPoint::BLOCK`]; returns the number of outputs.
    fn update_block(
        &self,
        _state: &mut Self::State,
        _y_c: &[f32],
        _y_s: &[f32],
        _out: &mut [Estimate<f32>],
    ) -> usize {
        0
    }
}

/// The simulated signal's samples in each form a tracker takes, `[y_c, y_s]`, converted
/// before `count` mode's runs (by the build script): a conversion inside the loop would run
/// in the counted range whenever the update calls the same routines (on the Cortex-M0 the
/// soft-float multiply and float-to-int conversion of [`adc_counts`], which the ADC
/// stage calls too).
#[derive(Debug, Clone, Copy)]
pub struct Inputs {
    /// The signal (amplitude about 1).
    pub signal: [&'static [f32]; 2],
    /// [`adc_counts`] of the signal.
    pub adc: [&'static [i16]; 2],
    /// [`fixed_counts`] of the signal.
    pub fixed: [&'static [i16]; 2],
}

/// An input sample's form, from the simulated signal's sample (amplitude about 1).
pub trait Sample: Copy + PartialEq + 'static {
    /// The signal's sample `y` in this form.
    fn from_signal(y: f32) -> Self;
    /// The signal in this form ([`Tracker::counted_inputs`]).
    fn counted(inputs: &Inputs) -> [&'static [Self]; 2];
}

impl Sample for f32 {
    fn from_signal(y: f32) -> f32 {
        y
    }
    fn counted(inputs: &Inputs) -> [&'static [f32]; 2] {
        inputs.signal
    }
}

/// The ADC chain's input: [`adc_counts`].
impl Sample for i16 {
    fn from_signal(y: f32) -> i16 {
        adc_counts(y)
    }
    fn counted(inputs: &Inputs) -> [&'static [i16]; 2] {
        inputs.adc
    }
}

impl<E: EntryPoint> Tracker for E {
    type State = E::State;
    type Input = E::Input;
    type Output = Estimate<f32>;
    const BLOCK: bool = E::BLOCK;
    fn new_state(&self) -> E::State {
        EntryPoint::new_state(self)
    }
    fn input(y: f32) -> E::Input {
        E::Input::from_signal(y)
    }
    fn counted_inputs(inputs: &Inputs) -> [&'static [E::Input]; 2] {
        E::Input::counted(inputs)
    }
    #[inline(always)]
    fn update(&self, state: &mut E::State, y_c: E::Input, y_s: E::Input) -> Estimate<f32> {
        EntryPoint::update(self, state, y_c, y_s)
    }
    fn record(&self, _: &E::State, output: &Estimate<f32>) -> Record {
        Record::of(output)
    }
    #[inline(always)]
    fn update_block(
        &self,
        state: &mut E::State,
        y_c: &[f32],
        y_s: &[f32],
        out: &mut [Estimate<f32>],
    ) -> usize {
        EntryPoint::update_block(self, state, y_c, y_s, out)
    }
}

/// The observer alone: the core's `Chain::update` with no front end (and its
/// `Chain::update_block`).
#[derive(Debug, Clone, Copy)]
pub struct Plain<const N: usize, S>(pub Chain<(), Gains<f32, N, S>>);

impl<const N: usize, S: SinCos<f32>> EntryPoint for Plain<N, S>
where
    Order<N>: SupportedOrder,
{
    type State = ChainState<(), ObserverState<f32, N>>;
    type Input = f32;
    const BLOCK: bool = true;
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: f32, y_s: f32) -> Estimate<f32> {
        self.0.update(state, (y_c, y_s))
    }
    #[inline(always)]
    fn update_block(
        &self,
        state: &mut Self::State,
        y_c: &[f32],
        y_s: &[f32],
        out: &mut [Estimate<f32>],
    ) -> usize {
        let inputs = y_c.iter().copied().zip(y_s.iter().copied());
        self.0.update_block(state, inputs, out)
    }
}

/// The observer alone through the core's `Chain::track` with no front end: the state
/// only, the estimate read on demand (`Chain::estimate`) where it is checked, outside the
/// counted update.
#[derive(Debug, Clone, Copy)]
pub struct Track<const N: usize, S>(pub Chain<(), Gains<f32, N, S>>);

impl<const N: usize, S: SinCos<f32>> Tracker for Track<N, S>
where
    Order<N>: SupportedOrder,
{
    type State = ChainState<(), ObserverState<f32, N>>;
    type Input = f32;
    type Output = ();
    fn new_state(&self) -> Self::State {
        ChainState::new()
    }
    fn input(y: f32) -> f32 {
        y
    }
    fn counted_inputs(inputs: &Inputs) -> [&'static [f32]; 2] {
        inputs.signal
    }
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: f32, y_s: f32) {
        self.0.track(state, (y_c, y_s))
    }
    fn record(&self, state: &Self::State, _: &()) -> Record {
        Record::of(&self.0.estimate(state))
    }
}

/// The baseline: an arctangent and a 2nd-order PLL; its state is its estimate.
impl<A: Atan2> Tracker for PhaseLockedLoop<A> {
    type State = PllState;
    type Input = f32;
    type Output = ();
    fn new_state(&self) -> PllState {
        PllState::default()
    }
    fn input(y: f32) -> f32 {
        y
    }
    fn counted_inputs(inputs: &Inputs) -> [&'static [f32]; 2] {
        inputs.signal
    }
    #[inline(always)]
    fn update(&self, state: &mut PllState, y_c: f32, y_s: f32) {
        PhaseLockedLoop::update(self, state, y_c, y_s)
    }
    fn record(&self, state: &PllState, _: &()) -> Record {
        Record {
            angle: state.angle,
            turns: state.turns,
            speed: state.speed,
            acceleration: 0.0,
        }
    }
}

/// An input sample (amplitude about 1) as a 12-bit two's complement ADC reading (full
/// scale +-2048 counts), truncated: the same on the host and on the target.
pub fn adc_counts(y: f32) -> i16 {
    (y * 2048.0) as i16
}

/// An input sample (amplitude about 1) in the fixed-point variant's counts: amplitude 2^14,
/// rounded; the same on the host and on the target.
pub fn fixed_counts(y: f32) -> i16 {
    let scaled = y * 16384.0;
    (if scaled >= 0.0 {
        scaled + 0.5
    } else {
        scaled - 0.5
    }) as i16
}

/// The core's fixed-point observer alone (`Chain::update` with no front end,
/// `docs/theory.md §14`) on 16-bit counts ([`fixed_counts`]), with its default diagnostics.
#[derive(Debug, Clone, Copy)]
pub struct Fixed<const N: usize>(pub Chain<(), FixedGains<N>>);

impl<const N: usize> Tracker for Fixed<N>
where
    Order<N>: SupportedOrder,
{
    type State = ChainState<(), FixedState<N>>;
    type Input = i16;
    type Output = FixedEstimate;
    fn new_state(&self) -> Self::State {
        ChainState::new()
    }
    fn input(y: f32) -> i16 {
        fixed_counts(y)
    }
    fn counted_inputs(inputs: &Inputs) -> [&'static [i16]; 2] {
        inputs.fixed
    }
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: i16, y_s: i16) -> FixedEstimate {
        self.0.update(state, (y_c, y_s))
    }
    fn record(&self, _: &Self::State, e: &FixedEstimate) -> Record {
        // The core's conversions to physical units (in f64, outside the counted update).
        Record {
            angle: binary_angle_to_rad(e.angle) as f32,
            turns: e.turns as i32,
            speed: self.0.observer.speed_rad_s(e) as f32,
            acceleration: self.0.observer.acceleration_rad_s2(e) as f32,
        }
    }
    fn integers(&self, _: &Self::State, e: &FixedEstimate) -> Option<[i64; 6]> {
        Some([
            i64::from(e.angle),
            e.turns,
            i64::from(e.speed),
            e.acceleration,
            i64::from(e.phase_error),
            i64::from(e.faults.bits()),
        ])
    }
}

/// The core's fixed-point observer alone through `Chain::track` (the state updated, no
/// estimate returned), the estimate read on demand outside the counted update.
#[derive(Debug, Clone, Copy)]
pub struct FixedTrack<const N: usize>(pub Fixed<N>);

impl<const N: usize> Tracker for FixedTrack<N>
where
    Order<N>: SupportedOrder,
{
    type State = ChainState<(), FixedState<N>>;
    type Input = i16;
    type Output = ();
    fn new_state(&self) -> Self::State {
        ChainState::new()
    }
    fn input(y: f32) -> i16 {
        fixed_counts(y)
    }
    fn counted_inputs(inputs: &Inputs) -> [&'static [i16]; 2] {
        inputs.fixed
    }
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: i16, y_s: i16) {
        self.0.0.track(state, (y_c, y_s));
    }
    fn record(&self, state: &Self::State, _: &()) -> Record {
        self.0.record(state, &self.0.0.estimate(state))
    }
    fn integers(&self, state: &Self::State, _: &()) -> Option<[i64; 6]> {
        self.0.integers(state, &self.0.0.estimate(state))
    }
}
