//! What the standard chain is made of for each number type ([`TrackerNumber`]: the float
//! observers' `f32` and `f64`, the fixed-point observer's `i16`), and the inputs it takes
//! ([`TrackerInput`]: pairs in the observer's units, raw ADC counts, pairs with a
//! demodulator's faults).

use core::fmt::Debug;

use super::choices::{
    CalibrationStage, CorrectionStage, FixedCalibrationStage, FixedCorrectionStage,
};
use crate::adc::{AdcCounts, AdcSample, AdcScaling};
use crate::chain::{FrontEndCheck, FrontEndCheckState, RailSample, Stage, WindingCheck};
use crate::demodulator::DemodulatedPair;
use crate::error::{ConfigError, Parameter};
use crate::front_end_faults::FrontEndFaults;
use crate::learning::Calibrator;
use crate::real::{ChainNumber, Float};

mod sealed {
    /// Only the crate's number types make a standard chain.
    pub trait Sealed {}
    impl<T: crate::Float> Sealed for T {}
    impl Sealed for i16 {}

    /// A winding check's state as the chain's state reports it.
    pub trait WindingStatus {
        /// The last sample's faults, the faults latched, and whether it coasted.
        fn status(&self) -> (super::FrontEndFaults, super::FrontEndFaults, bool);
        /// Clears the latched faults.
        fn clear(&mut self);
    }

    impl WindingStatus for super::FrontEndCheckState {
        fn status(&self) -> (super::FrontEndFaults, super::FrontEndFaults, bool) {
            (self.faults(), self.latched_faults(), self.coasting())
        }
        fn clear(&mut self) {
            self.clear_faults();
        }
    }

    /// No winding check: never a fault.
    impl WindingStatus for () {
        fn status(&self) -> (super::FrontEndFaults, super::FrontEndFaults, bool) {
            (
                super::FrontEndFaults::NONE,
                super::FrontEndFaults::NONE,
                false,
            )
        }
        fn clear(&mut self) {}
    }
}

pub(super) use sealed::WindingStatus;

/// A number type of the standard chain (sealed): `f32` and `f64` for the float observers'
/// [`Gains`](crate::Gains), `i16` for the fixed-point [`FixedGains`](crate::FixedGains).
/// It names the stages the chain holds in that type; the chain's code is one for all.
pub trait TrackerNumber:
    sealed::Sealed + ChainNumber + RailSample + PartialOrd + Copy + Debug + PartialEq + Default
{
    /// The ADC's scaling of raw counts into the observer's samples: [`AdcScaling`] for the
    /// floats, [`AdcCounts`] for `i16`.
    type Adc: Copy + Debug + PartialEq;
    /// The winding check: `Option<`[`WindingCheck`]`>` for the floats, `()` (none) for
    /// `i16`.
    type Winding: Stage<Self, (Self, Self), State = Self::WindingState>
        + Copy
        + Debug
        + PartialEq
        + Default;
    /// The winding check's state.
    type WindingState: sealed::WindingStatus + Copy + Debug + PartialEq + Default;
    /// The calibration stage: [`CalibrationStage`] for the floats,
    /// [`FixedCalibrationStage`] for `i16`.
    type Calibration: Stage<Self, (Self, Self), State = Self::Calibrator>
        + Copy
        + Debug
        + PartialEq
        + Default;
    /// The calibration's state: the online calibration's [`Calibrator`] for the floats,
    /// `()` for `i16`.
    type Calibrator: Copy + Debug + PartialEq + Default;
    /// The angle correction: [`CorrectionStage`] for the floats, [`FixedCorrectionStage`]
    /// for `i16`.
    type Correction: Stage<Self, (Self, Self), State = ()> + Copy + Debug + PartialEq + Default;

    /// The ADC that passes counts through as they are (mid-scale 0, one count per unit).
    fn unscaled_adc() -> Self::Adc;

    /// One pair of raw counts through `adc`.
    fn scale<I: AdcSample>(adc: &Self::Adc, raw_c: I, raw_s: I) -> (Self, Self);

    /// The ADC codes `min_counts` to `max_counts` (its lowest and highest) as the
    /// observer's samples, exactly as `adc` scales them. Refuses codes that are not
    /// ordered, or that the scaling joins ([`Parameter::AdcRange`]).
    fn range_of_codes(
        adc: &Self::Adc,
        min_counts: i32,
        max_counts: i32,
    ) -> Result<(Self, Self), ConfigError>;
}

impl<T: Float> TrackerNumber for T {
    type Adc = AdcScaling<T>;
    type Winding = Option<WindingCheck<T>>;
    type WindingState = FrontEndCheckState;
    type Calibration = CalibrationStage<T>;
    type Calibrator = Calibrator<T>;
    type Correction = CorrectionStage<T>;

    fn unscaled_adc() -> AdcScaling<T> {
        AdcScaling::UNSCALED
    }

    #[inline(always)]
    fn scale<I: AdcSample>(adc: &AdcScaling<T>, raw_c: I, raw_s: I) -> (T, T) {
        adc.sample(raw_c, raw_s)
    }

    fn range_of_codes(
        adc: &AdcScaling<T>,
        min_counts: i32,
        max_counts: i32,
    ) -> Result<(T, T), ConfigError> {
        let (min, max) = adc.sample(min_counts, max_counts);
        if !(min_counts < max_counts && min < max) {
            return Err(ConfigError::OutOfRange(Parameter::AdcRange));
        }
        Ok((min, max))
    }
}

impl TrackerNumber for i16 {
    type Adc = AdcCounts;
    type Winding = ();
    type WindingState = ();
    type Calibration = FixedCalibrationStage;
    type Calibrator = ();
    type Correction = FixedCorrectionStage;

    fn unscaled_adc() -> AdcCounts {
        AdcCounts::UNSCALED
    }

    #[inline(always)]
    fn scale<I: AdcSample>(adc: &AdcCounts, raw_c: I, raw_s: I) -> (i16, i16) {
        adc.sample(raw_c, raw_s)
    }

    fn range_of_codes(
        adc: &AdcCounts,
        min_counts: i32,
        max_counts: i32,
    ) -> Result<(i16, i16), ConfigError> {
        let check = FrontEndCheck::of_adc_codes(adc, min_counts, max_counts)?;
        check
            .adc_range()
            .ok_or(ConfigError::OutOfRange(Parameter::AdcRange))
    }
}

/// An input the standard chain takes: the pair of samples in the observer's units (and the
/// front-end faults given with it, if any), from what the caller has.
pub trait TrackerInput<V: TrackerNumber>: Copy {
    /// Whether the input comes with front-end faults (else the front-end check has
    /// nothing to do without a stated range, and is skipped).
    const GIVES_FAULTS: bool = false;
    /// Whether the input may be samples as they are (`int16`: the fixed-point observer's),
    /// for a chain without an ADC: its ADC is then the unscaled one, a constant that the
    /// compiler folds away (the saturation of an `int16` to the `int16` range), where the
    /// stored one costs its loads, subtractions, saturations and shifts on every sample.
    const SAMPLES: bool = false;
    /// The pair, through `adc` if it is raw counts, and the faults given with it.
    fn pair(self, adc: &V::Adc) -> ((V, V), FrontEndFaults);
}

/// A pair in the observer's units, as it is (a float chain's volts or fractions of full
/// scale).
impl<T: Float> TrackerInput<T> for (T, T) {
    #[inline(always)]
    fn pair(self, _: &AdcScaling<T>) -> ((T, T), FrontEndFaults) {
        (self, FrontEndFaults::NONE)
    }
}

/// A pair with the front-end faults found before the chain (a demodulator's), as it is.
impl<V: TrackerNumber> TrackerInput<V> for ((V, V), FrontEndFaults) {
    const GIVES_FAULTS: bool = true;
    #[inline(always)]
    fn pair(self, _: &V::Adc) -> ((V, V), FrontEndFaults) {
        self
    }
}

/// A demodulator's pair, with its window's faults.
impl<V: TrackerNumber> TrackerInput<V> for DemodulatedPair<V> {
    const GIVES_FAULTS: bool = true;
    #[inline(always)]
    fn pair(self, _: &V::Adc) -> ((V, V), FrontEndFaults) {
        ((self.y_c, self.y_s), self.faults)
    }
}

/// Raw ADC counts of each width the ADC stages take, through the chain's ADC.
macro_rules! counts_input {
    ($($int:ty: $samples:expr),*) => {$(
        impl<V: TrackerNumber> TrackerInput<V> for ($int, $int) {
            const SAMPLES: bool = $samples;
            #[inline(always)]
            fn pair(self, adc: &V::Adc) -> ((V, V), FrontEndFaults) {
                (V::scale(adc, self.0, self.1), FrontEndFaults::NONE)
            }
        }
    )*};
}

counts_input!(u16: false, i16: true, i32: false);
