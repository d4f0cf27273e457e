//! The standard chain, one type for every door (`docs/theory.md §15`): a [`Tracker`] is a
//! [`Chain`] whose front end is the [`TrackerFrontEnd`], the stages every sensor setup is
//! made of, named and in their order: the input (pairs in the observer's units, or raw
//! ADC counts through the ADC's scaling), clipping (against a stated range, or the rails
//! measured), the front-end faults a demodulator gives its pairs, the winding check, the
//! sensor calibration (none, stored or online) and the angle correction (none, harmonics
//! or table), before the observer (`f32`, `f64` or fixed point). Its settings
//! ([`TrackerSettings`]) are checked together, once, by [`TrackerFrontEnd::new`]; its
//! per-sample forms are the chain's ([`Chain::track`], [`Chain::update`],
//! [`Chain::update_block`]). A custom chain still composes its own stages: the tracker is
//! one such front end, not a parallel path.

use crate::adc::AdcCounts;
use crate::chain::{Chain, ChainState, FrontEndCheck, HeldRailCheck};
use crate::error::{ConfigError, Parameter};

mod choices;
mod front_end;
mod number;

pub use choices::{
    CalibrationStage, CorrectionStage, FixedCalibrationStage, FixedCorrectionStage,
    TRACKER_TABLE_LENGTH,
};
pub use front_end::{TrackerFrontEnd, TrackerFrontEndState};
pub use number::{TrackerInput, TrackerNumber};

/// The standard chain: the [`TrackerFrontEnd`] before the observer `O` ([`Gains`] for
/// `f32` and `f64`, [`FixedGains`] for fixed point, on `i16` samples).
///
/// ```
/// use angletrack_core::{
///     AdcScaling, CalibrationStage, CorrectionStage, Gains, Input, Rails, Tracker,
///     TrackerFrontEnd, TrackerSettings, TrackerState,
/// };
/// // A 12-bit offset-binary ADC whose rails are its codes 0 and 4095, no calibration.
/// let settings = TrackerSettings::<f32> {
///     input: Input::Counts {
///         adc: AdcScaling::offset_binary(12)?,
///         rails: Rails::Stated { min: 0, max: 4095 },
///     },
///     winding: None,
///     calibration: CalibrationStage::None,
///     correction: CorrectionStage::None,
/// };
/// let gains = Gains::<f32, 3>::new([0.1578, 0.0126, 0.000_34], 50e-6)?;
/// let tracker: Tracker<f32, _> = Tracker::new(TrackerFrontEnd::new(settings)?, gains);
/// let mut state = TrackerState::new();
/// let estimate = tracker.update(&mut state, (2048u16 + 900, 2048u16 + 1559));
/// assert!((estimate.angle - 1.0472).abs() < 1e-3 && estimate.faults.is_empty());
/// // At a rail: clipping.
/// tracker.update(&mut state, (4095u16, 2048u16 + 1559));
/// assert!(!state.front_end.faults().is_empty());
/// # Ok::<(), angletrack_core::ConfigError>(())
/// ```
///
/// [`Gains`]: crate::Gains
/// [`FixedGains`]: crate::FixedGains
pub type Tracker<V, O> = Chain<TrackerFrontEnd<V>, O>;

/// One channel's state of a [`Tracker`] whose observer's state is `S`
/// ([`ObserverState`](crate::ObserverState) or [`FixedState`](crate::FixedState)).
pub type TrackerState<V, S> = ChainState<TrackerFrontEndState<V>, S>;

/// Where clipping is looked for, in the units of the input `X` (ADC codes for counts).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Rails<X> {
    /// Not looked for (signals that cannot clip, or checked before the chain).
    #[default]
    Unchecked,
    /// The rails measured on the samples as they come ([`HeldRailCheck`]): for an ADC
    /// whose range nobody stated.
    Measured,
    /// The lowest and highest values the input can take (an ADC's codes): a sample at or
    /// beyond either is clipped ([`FrontEndCheck`]).
    Stated {
        /// The lowest value (code).
        min: X,
        /// The highest value (code).
        max: X,
    },
}

impl Rails<i32> {
    /// The codes of an ADC of `bits` bits (1 to 32) stated as its rails: `0` to
    /// `2^bits - 1` unsigned (offset binary), `-2^(bits-1)` to `2^(bits-1) - 1` signed
    /// (two's complement). Refuses other widths ([`Parameter::AdcBits`]).
    ///
    /// ```
    /// use angletrack_core::Rails;
    /// assert_eq!(Rails::of_adc_bits(12, false)?, Rails::Stated { min: 0, max: 4095 });
    /// assert_eq!(Rails::of_adc_bits(12, true)?, Rails::Stated { min: -2048, max: 2047 });
    /// assert_eq!(Rails::of_adc_bits(32, false)?, Rails::Stated { min: 0, max: i32::MAX });
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    ///
    /// [`Parameter::AdcBits`]: crate::Parameter::AdcBits
    pub const fn of_adc_bits(bits: u32, signed: bool) -> Result<Self, ConfigError> {
        if bits < 1 || bits > 32 {
            return Err(ConfigError::OutOfRange(crate::error::Parameter::AdcBits));
        }
        let span = 1_i64 << bits;
        let (min, max) = if signed {
            (-span / 2, span / 2 - 1)
        } else {
            (0, span - 1)
        };
        // An unsigned 32-bit ADC's upper codes are beyond what the chain's counts (`i32`)
        // hold: its rail is the largest of them.
        let max = if max > i32::MAX as i64 {
            i32::MAX
        } else {
            max as i32
        };
        Ok(Rails::Stated {
            min: min as i32,
            max,
        })
    }
}

/// What the chain's samples are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Input<A, V> {
    /// Pairs in the observer's units (floats: volts, fractions of full scale; fixed
    /// point: its 16-bit samples).
    Units {
        /// Where clipping is looked for, in those units.
        rails: Rails<V>,
    },
    /// Raw ADC counts, scaled by `adc` ([`AdcScaling`](crate::AdcScaling) for the floats,
    /// [`AdcCounts`](crate::AdcCounts) for fixed point), whose signedness and mid-scale
    /// the caller states through it.
    Counts {
        /// The ADC's scaling.
        adc: A,
        /// Where clipping is looked for, in ADC codes.
        rails: Rails<i32>,
    },
}

/// The settings of a [`TrackerFrontEnd`], in the number type `V` of its observer: every
/// stage of the standard chain. `Copy`: a firmware keeps it in flash.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackerSettings<V: TrackerNumber> {
    /// The input and its clipping.
    pub input: Input<V::Adc, V>,
    /// The winding check (floats: `Some(WindingCheck::new(amplitude)?)`, the windings'
    /// amplitude in the observer's units; fixed point: `()`, none).
    pub winding: V::Winding,
    /// The sensor calibration.
    pub calibration: V::Calibration,
    /// The angle correction.
    pub correction: V::Correction,
}

impl<V: TrackerNumber> Default for TrackerSettings<V> {
    /// Pairs in the observer's units, no clipping check, no winding check, calibration or
    /// correction.
    fn default() -> Self {
        Self {
            input: Input::Units {
                rails: Rails::Unchecked,
            },
            winding: V::Winding::default(),
            calibration: V::Calibration::default(),
            correction: V::Correction::default(),
        }
    }
}

impl<V: TrackerNumber> TrackerFrontEnd<V> {
    /// The front end of `settings`, checked: a stated range must be ordered, and for
    /// counts stay ordered through the ADC's scaling ([`Parameter::AdcRange`]). The stages
    /// were checked when they were made.
    ///
    /// ```
    /// use angletrack_core::{AdcCounts, Input, Parameter, Rails, TrackerFrontEnd, TrackerSettings};
    /// let settings = TrackerSettings::<i16> {
    ///     input: Input::Counts { adc: AdcCounts::offset_binary(12)?, rails: Rails::Stated { min: 4095, max: 0 } },
    ///     ..TrackerSettings::default()
    /// };
    /// assert_eq!(TrackerFrontEnd::new(settings).unwrap_err().parameter(), Parameter::AdcRange);
    /// # Ok::<(), angletrack_core::ConfigError>(())
    /// ```
    ///
    /// [`Parameter::AdcRange`]: crate::Parameter::AdcRange
    pub fn new(settings: TrackerSettings<V>) -> Result<Self, ConfigError> {
        let (adc, counts, rails) = match settings.input {
            Input::Units { rails } => (V::unscaled_adc(), false, rails),
            Input::Counts { adc, rails } => (adc, true, in_samples(&adc, rails)?),
        };
        let (range, measured) = match rails {
            Rails::Unchecked => (None, false),
            Rails::Measured => (None, true),
            Rails::Stated { min, max } => (Some((min, max)), false),
        };
        Ok(Self {
            adc,
            counts,
            check: FrontEndCheck::around((), range)?,
            rails: measured.then_some(HeldRailCheck::new()),
            winding: settings.winding,
            calibration: settings.calibration,
            correction: settings.correction,
        })
    }

    /// The same front end with clipping looked for at `rails`, in ADC codes (for a chain
    /// of pairs in units, the codes are taken as the units' values): for a chain whose
    /// range is stated after it was made. Refuses a range as [`TrackerFrontEnd::new`]
    /// does ([`Parameter::AdcRange`]).
    ///
    /// [`Parameter::AdcRange`]: crate::Parameter::AdcRange
    pub fn with_rails(self, rails: Rails<i32>) -> Result<Self, ConfigError> {
        let mut settings = TrackerSettings {
            input: Input::Counts {
                adc: self.adc,
                rails,
            },
            winding: self.winding,
            calibration: self.calibration,
            correction: self.correction,
        };
        if !self.counts {
            settings.input = Input::Units {
                rails: in_samples(&self.adc, rails)?,
            };
        }
        Self::new(settings)
    }

    /// The same front end with the winding check `winding`.
    pub fn with_winding(self, winding: V::Winding) -> Self {
        Self { winding, ..self }
    }

    /// The ADC's scaling, when the input is counts.
    pub fn adc(&self) -> Option<V::Adc> {
        self.counts.then_some(self.adc)
    }

    /// The stated range in the observer's samples (through the ADC for counts), if any.
    pub fn adc_range(&self) -> Option<(V, V)> {
        self.check.adc_range()
    }

    /// Whether the rails are measured ([`Rails::Measured`]).
    pub fn measures_rails(&self) -> bool {
        self.rails.is_some()
    }

    /// The winding check.
    pub fn winding(&self) -> V::Winding {
        self.winding
    }

    /// The sensor calibration stage.
    pub fn calibration(&self) -> V::Calibration {
        self.calibration
    }

    /// The angle correction stage.
    pub fn correction(&self) -> V::Correction {
        self.correction
    }
}

impl TrackerFrontEnd<i16> {
    /// [`TrackerFrontEnd::new`] for the fixed-point chain, as a `const fn`: a firmware's
    /// standard chain in a `static`, checked when it compiles (the floats' is
    /// `TrackerFrontEnd::<f32>::new_const`).
    ///
    /// ```
    /// use angletrack_core::{
    ///     AdcCounts, FixedAngleCorrectionTable, FixedGains, Input, Rails, Tracker,
    ///     TrackerFrontEnd, TrackerSettings, fixed::FixedConstants,
    /// };
    /// const fn ok<V: Copy>(r: Result<V, angletrack_core::ConfigError>) -> V {
    ///     match r {
    ///         Ok(v) => v,
    ///         Err(_) => panic!("refused"),
    ///     }
    /// }
    /// const GAINS: FixedConstants<3> = FixedConstants {
    ///     multiplier: [215_733_201, 17_225_845, 1_903_920_691],
    ///     acceleration_shift: 3,
    /// };
    /// static TRACKER: Tracker<i16, FixedGains<3>> = Tracker::new(
    ///     ok(TrackerFrontEnd::<i16>::new_const(TrackerSettings {
    ///         input: Input::Counts {
    ///             adc: ok(AdcCounts::offset_binary(12)),
    ///             rails: Rails::Stated { min: 0, max: 4095 },
    ///         },
    ///         winding: (),
    ///         calibration: None,
    ///         correction: Some(ok(FixedAngleCorrectionTable::new([0; 256]))),
    ///     })),
    ///     ok(FixedGains::from_constants(GAINS, 50e-6)),
    /// );
    /// assert_eq!(TRACKER.front_end.adc_range(), Some((-32768, 32752)));
    /// ```
    pub const fn new_const(settings: TrackerSettings<i16>) -> Result<Self, ConfigError> {
        let (adc, counts, range) = match settings.input {
            Input::Units { rails } => (AdcCounts::UNSCALED, false, rails),
            Input::Counts { adc, rails } => {
                let range = match rails {
                    Rails::Unchecked => Rails::Unchecked,
                    Rails::Measured => Rails::Measured,
                    Rails::Stated { min, max } => {
                        // Ordered in codes first: the ADC's saturation keeps the order, but
                        // may join them.
                        if min >= max {
                            return Err(ConfigError::OutOfRange(Parameter::AdcRange));
                        }
                        Rails::Stated {
                            min: adc.code_sample(min),
                            max: adc.code_sample(max),
                        }
                    }
                };
                (adc, true, range)
            }
        };
        if let Rails::Stated { min, max } = range
            && min >= max
        {
            return Err(ConfigError::OutOfRange(Parameter::AdcRange));
        }
        Ok(Self::of_checked(adc, counts, range, settings))
    }
}

impl<V: TrackerNumber> TrackerFrontEnd<V> {
    /// The front end of its checked parts (the `const` constructors' common end): the ADC
    /// (`counts`: whether the input goes through it), the rails in the observer's samples
    /// (a stated range found ordered) and the stages of `settings`.
    pub(crate) const fn of_checked(
        adc: V::Adc,
        counts: bool,
        rails: Rails<V>,
        settings: TrackerSettings<V>,
    ) -> Self {
        let (range, rails) = match rails {
            Rails::Unchecked => (None, None),
            Rails::Measured => (None, Some(HeldRailCheck::new())),
            Rails::Stated { min, max } => (Some((min, max)), None),
        };
        Self {
            adc,
            counts,
            check: FrontEndCheck::of_ordered_range(range),
            rails,
            winding: settings.winding,
            calibration: settings.calibration,
            correction: settings.correction,
        }
    }
}

/// `rails` in ADC codes as the observer's samples, through `adc`.
fn in_samples<V: TrackerNumber>(adc: &V::Adc, rails: Rails<i32>) -> Result<Rails<V>, ConfigError> {
    Ok(match rails {
        Rails::Unchecked => Rails::Unchecked,
        Rails::Measured => Rails::Measured,
        Rails::Stated { min, max } => {
            let (min, max) = V::range_of_codes(adc, min, max)?;
            Rails::Stated { min, max }
        }
    })
}

#[cfg(test)]
mod tests;
