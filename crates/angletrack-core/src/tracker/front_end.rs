//! The standard chain's front end as one [`Stage`] with named stages, in the order a
//! sample meets them: the ADC, the front-end check (a demodulator's faults, clipping
//! against a stated range), the rails measured, the winding check, the sensor calibration
//! and the angle correction.

use super::number::{TrackerInput, TrackerNumber, WindingStatus};
use crate::chain::{
    Feedback, FrontEndCheck, FrontEndCheckState, HeldRailCheck, HeldRails, Prediction, Stage,
};
use crate::faults::Faults;
use crate::front_end_faults::FrontEndFaults;

/// The standard chain's front end: the stages of [`Tracker`](super::Tracker), checked
/// together by [`TrackerFrontEnd::new`](super::TrackerFrontEnd::new). Immutable and
/// `Copy`; each channel's mutable part is a [`TrackerFrontEndState`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackerFrontEnd<V: TrackerNumber> {
    pub(crate) adc: V::Adc,
    pub(crate) counts: bool,
    pub(crate) check: FrontEndCheck<V>,
    pub(crate) rails: Option<HeldRailCheck>,
    pub(crate) winding: V::Winding,
    pub(crate) calibration: V::Calibration,
    pub(crate) correction: V::Correction,
}

/// One channel's state of a [`TrackerFrontEnd`]: the front-end check's, the rails
/// measured, the winding check's and the online calibration's [`Calibrator`](crate::Calibrator) (floats).
/// The default is fresh: no fault, no rail found, the online calibration off.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrackerFrontEndState<V: TrackerNumber> {
    check: (FrontEndCheckState, ()),
    rails: HeldRails<V>,
    winding: V::WindingState,
    calibrator: V::Calibrator,
}

impl<V: TrackerNumber> TrackerFrontEndState<V> {
    /// A fresh state (as [`Default`]).
    pub fn new() -> Self {
        Self::default()
    }

    /// The front-end faults of the last sample (a demodulator's, clipping, a winding).
    pub fn faults(&self) -> FrontEndFaults {
        self.check.0.faults() | self.rails.check().faults() | self.winding.status().0
    }

    /// The front-end faults latched since the last [`TrackerFrontEndState::clear_faults`].
    pub fn latched_faults(&self) -> FrontEndFaults {
        self.check.0.latched_faults()
            | self.rails.check().latched_faults()
            | self.winding.status().1
    }

    /// Clears the latched front-end faults and returns them.
    pub fn clear_faults(&mut self) -> FrontEndFaults {
        let latched = self.latched_faults();
        self.check.0.clear_faults();
        self.rails.clear_faults();
        self.winding.clear();
        latched
    }

    /// Whether the observer coasted through the last sample (not a measurement).
    pub fn coasting(&self) -> bool {
        self.check.0.coasting() || self.rails.check().coasting() || self.winding.status().2
    }

    /// The rails measured so far, `(low, high)` in the observer's samples, each `None`
    /// while not found (or when the rails are stated or not checked).
    pub fn rails(&self) -> (Option<V>, Option<V>) {
        self.rails.rails()
    }

    /// The online calibration's estimator (`()` for the fixed-point chain).
    pub fn calibrator(&self) -> &V::Calibrator {
        &self.calibrator
    }

    /// The online calibration's estimator, to enable, freeze or load it.
    pub fn calibrator_mut(&mut self) -> &mut V::Calibrator {
        &mut self.calibrator
    }
}

type Memo<V> = (
    <<V as TrackerNumber>::Winding as Stage<V, (V, V)>>::Memo,
    <<V as TrackerNumber>::Calibration as Stage<V, (V, V)>>::Memo,
    <<V as TrackerNumber>::Correction as Stage<V, (V, V)>>::Memo,
);

impl<V: TrackerNumber, X: TrackerInput<V>> Stage<V, X> for TrackerFrontEnd<V> {
    type State = TrackerFrontEndState<V>;
    type Memo = Memo<V>;
    const QUIET_FROM_INPUT: bool = true;

    #[inline(always)]
    fn forward(
        &self,
        s: &mut TrackerFrontEndState<V>,
        prediction: &impl Prediction<V>,
        input: X,
    ) -> ((V, V), Memo<V>) {
        // A chain without an ADC holds the unscaled one: samples go through it as a
        // constant (the same numbers, without the stored ADC's arithmetic).
        let given = if X::SAMPLES && !self.counts {
            input.pair(&V::unscaled_adc())
        } else {
            input.pair(&self.adc)
        };
        // Without a stated range, an input that gives no faults leaves the check nothing
        // to do, once its state is clear (a state fed a demodulator's faulted pair before).
        let pair = if X::GIVES_FAULTS
            || self.check.adc_range().is_some()
            || !s.check.0.faults().is_empty()
        {
            self.check.forward(&mut s.check, prediction, given).0
        } else {
            given.0
        };
        let (pair, _) = self.rails.forward(&mut s.rails, prediction, pair);
        let (pair, winding) = self.winding.forward(&mut s.winding, prediction, pair);
        let (pair, calibration) = self
            .calibration
            .forward(&mut s.calibrator, prediction, pair);
        let (pair, correction) = self.correction.forward(&mut (), prediction, pair);
        (pair, (winding, calibration, correction))
    }

    #[inline(always)]
    fn feedback(&self, s: &mut TrackerFrontEndState<V>, memo: Memo<V>, used: Option<Feedback<V>>) {
        self.winding.feedback(&mut s.winding, memo.0, used);
        self.calibration.feedback(&mut s.calibrator, memo.1, used);
        self.correction.feedback(&mut (), memo.2, used);
    }

    #[inline(always)]
    fn faults(&self, s: &mut TrackerFrontEndState<V>) -> Faults {
        Stage::<V, ((V, V), FrontEndFaults)>::faults(&self.check, &mut s.check)
            | Stage::<V, (V, V)>::faults(&self.rails, &mut s.rails)
            | self.winding.faults(&mut s.winding)
            | self.calibration.faults(&mut s.calibrator)
            | self.correction.faults(&mut ())
    }

    #[inline(always)]
    fn coasts(&self, s: &TrackerFrontEndState<V>) -> bool {
        Stage::<V, ((V, V), FrontEndFaults)>::coasts(&self.check, &s.check)
            || Stage::<V, (V, V)>::coasts(&self.rails, &s.rails)
            || self.winding.coasts(&s.winding)
            || self.calibration.coasts(&s.calibrator)
            || self.correction.coasts(&())
    }

    #[inline(always)]
    fn quiet(&self, s: &TrackerFrontEndState<V>) -> bool {
        Stage::<V, ((V, V), FrontEndFaults)>::quiet(&self.check, &s.check)
            && Stage::<V, (V, V)>::quiet(&self.rails, &s.rails)
            && self.winding.quiet(&s.winding)
            && self.calibration.quiet(&s.calibrator)
            && self.correction.quiet(&())
    }
}
