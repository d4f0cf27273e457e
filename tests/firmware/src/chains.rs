//! The signal chains of the firmware test's variants (the core's `Chain`): the front-end
//! stages with the `f32` observer (`ChainUpdate`, `ChainTrack`) and with the fixed-point
//! observer (`FixedChainTrack`). Shared, like `trackers.rs`, by the build script and the
//! firmware.

use angletrack_core::{
    AdcScaling, AngleCorrection, AngleCorrectionTable, Calibrator, Chain, ChainState, Estimate,
    FixedAngleCorrectionTable, FixedCalibration, FixedGains, FixedState, Gains, ObserverState,
    OnlineCalibration, Order, SensorCalibration, SinCos, Stage, SupportedOrder,
};

use crate::trackers::{EntryPoint, Fixed, Inputs, Sample, Tracker, fixed_counts};
use crate::variants::Record;

/// A chain's front end as the variants build it: the input it takes and its fresh state.
pub trait FrontEnd: Copy {
    /// One channel's input sample.
    type Input: Sample;
    /// The front end's state.
    type FrontState;
    /// The front end's fresh state.
    fn new_front_state(&self) -> Self::FrontState;
}

impl FrontEnd for AdcScaling<f32> {
    type Input = i16;
    type FrontState = ();
    fn new_front_state(&self) {}
}

impl FrontEnd for AngleCorrection<f32> {
    type Input = f32;
    type FrontState = ();
    fn new_front_state(&self) {}
}

/// The online calibration, learning or off (its calibrator's mode).
#[derive(Debug, Clone, Copy)]
pub struct Online {
    /// The settings.
    pub calibration: OnlineCalibration<f32>,
    /// Learning (else off).
    pub learning: bool,
}

impl Stage<f32, (f32, f32)> for Online {
    type State = Calibrator<f32>;
    type Memo = <OnlineCalibration<f32> as Stage<f32, (f32, f32)>>::Memo;
    #[inline(always)]
    fn forward(
        &self,
        state: &mut Calibrator<f32>,
        prediction: &impl angletrack_core::Prediction<f32>,
        input: (f32, f32),
    ) -> ((f32, f32), Self::Memo) {
        self.calibration.forward(state, prediction, input)
    }
    #[inline(always)]
    fn feedback(
        &self,
        state: &mut Calibrator<f32>,
        memo: Self::Memo,
        used: Option<angletrack_core::Feedback<f32>>,
    ) {
        self.calibration.feedback(state, memo, used)
    }
    #[inline(always)]
    fn faults(&self, state: &mut Calibrator<f32>) -> angletrack_core::Faults {
        self.calibration.faults(state)
    }
    #[inline(always)]
    fn quiet(&self, state: &Calibrator<f32>) -> bool {
        self.calibration.quiet(state)
    }
}

impl FrontEnd for Online {
    type Input = f32;
    type FrontState = Calibrator<f32>;
    fn new_front_state(&self) -> Calibrator<f32> {
        let mut calibrator = Calibrator::new();
        if self.learning {
            calibrator.enable();
        }
        calibrator
    }
}

/// A stored calibration and the angle error's table.
pub type StoredCorrections = (SensorCalibration<f32>, AngleCorrectionTable<f32, 256>);

impl FrontEnd for StoredCorrections {
    type Input = f32;
    type FrontState = ((), ());
    fn new_front_state(&self) -> ((), ()) {
        ((), ())
    }
}

/// The online calibration with `settings` of `gains`, learning or off.
pub fn online<const N: usize, S: SinCos<f32>>(
    gains: &Gains<f32, N, S>,
    learning: bool,
) -> Result<Online, angletrack_core::ConfigError> {
    Ok(Online {
        calibration: OnlineCalibration::new(gains.calibration_settings(), gains.sample_period())?,
        learning,
    })
}

/// The sensor calibration and angle-error table of the corrected variants: a few
/// thousandths of offset, imbalance and quadrature, and the harmonics of
/// `variants::correction` as a table of 256 entries.
pub fn stored_corrections(
    harmonics: &AngleCorrection<f32>,
) -> Result<StoredCorrections, angletrack_core::ConfigError> {
    let calibration = SensorCalibration::new(0.002, -0.003, 1.0, 1.004, 0.003)?;
    Ok((calibration, AngleCorrectionTable::from_harmonics(harmonics)))
}

/// The core's `Chain::update` of a front end `F` and an `f32` observer.
#[derive(Debug, Clone, Copy)]
pub struct ChainUpdate<F, const N: usize, S>(pub Chain<F, Gains<f32, N, S>>);

impl<F, const N: usize, S: SinCos<f32>> EntryPoint for ChainUpdate<F, N, S>
where
    F: FrontEnd + Stage<f32, (F::Input, F::Input), State = F::FrontState>,
    F::FrontState: Default,
{
    type State = ChainState<F::FrontState, ObserverState<f32, N>>;
    type Input = F::Input;
    fn new_state(&self) -> Self::State {
        ChainState {
            front_end: self.0.front_end.new_front_state(),
            observer: ObserverState::new(),
        }
    }
    #[inline(always)]
    fn update(&self, state: &mut Self::State, y_c: F::Input, y_s: F::Input) -> Estimate<f32> {
        self.0.update(state, (y_c, y_s))
    }
}

/// The core's `Chain::track` of a front end `F` and an `f32` observer: the state only,
/// the estimate read on demand where it is checked, outside the counted update.
#[derive(Debug, Clone, Copy)]
pub struct ChainTrack<F, const N: usize, S>(pub Chain<F, Gains<f32, N, S>>);

impl<F, const N: usize, S: SinCos<f32>> Tracker for ChainTrack<F, N, S>
where
    F: FrontEnd<Input = f32> + Stage<f32, (f32, f32), State = F::FrontState>,
{
    type State = ChainState<F::FrontState, ObserverState<f32, N>>;
    type Input = f32;
    type Output = ();
    fn new_state(&self) -> Self::State {
        ChainState {
            front_end: self.0.front_end.new_front_state(),
            observer: ObserverState::new(),
        }
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

/// The fixed-point chain's front end: a stored calibration in integers and the angle
/// error's table in Q15.
pub type FixedCorrections = (FixedCalibration, FixedAngleCorrectionTable<256>);

/// [`stored_corrections`] in integers, for counts of amplitude 2^14 ([`fixed_counts`]).
pub fn fixed_corrections(
    harmonics: &AngleCorrection<f32>,
) -> Result<FixedCorrections, angletrack_core::ConfigError> {
    let f = 16384.0;
    let stored = SensorCalibration::<f64>::new(0.002 * f, -0.003 * f, f, 1.004 * f, 0.003)?;
    let (cos, sin) = harmonics.coefficients();
    let harmonics = AngleCorrection::<f64>::new(cos.map(f64::from), sin.map(f64::from))?;
    Ok((
        FixedCalibration::new(&stored)?,
        FixedAngleCorrectionTable::from_harmonics(&harmonics),
    ))
}

/// The core's `Chain::track` of the fixed-point front end and observer on 16-bit counts
/// ([`fixed_counts`]), the estimate read on demand outside the counted update.
#[derive(Debug, Clone, Copy)]
pub struct FixedChainTrack<const N: usize>(pub Chain<FixedCorrections, FixedGains<N>>);

impl<const N: usize> Tracker for FixedChainTrack<N>
where
    Order<N>: SupportedOrder,
{
    type State = ChainState<((), ()), FixedState<N>>;
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
        self.0.track(state, (y_c, y_s))
    }
    fn record(&self, state: &Self::State, _: &()) -> Record {
        let alone = ChainState::new();
        Fixed(Chain::new((), self.0.observer)).record(&alone, &self.0.estimate(state))
    }
    fn integers(&self, state: &Self::State, _: &()) -> Option<[i64; 6]> {
        let alone = ChainState::new();
        Fixed(Chain::new((), self.0.observer)).integers(&alone, &self.0.estimate(state))
    }
}
