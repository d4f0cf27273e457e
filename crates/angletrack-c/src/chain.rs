//! The signal chain in `f32` (the core's [`Chain`]): `at_chain_f32`, the configuration of
//! one chain built from optional stages (the ADC, a stored sensor calibration or the online
//! calibration with its settings, the harmonic angle correction or its table) and the
//! observer's gains;
//! `at_chain_state_f32`, one channel's state (the observer's, the front-end checks' and the
//! online calibration's);
//! and the plain C mirrors of the stages' settings, `at_angle_correction_f32` and
//! `at_calibration_settings_f32`.
//!
//! The chain is the core's standard chain, `Tracker<f32, Gains<f32, N>>`, built by the
//! core's `TrackerFrontEnd::new` from the stages given: counts through the ADC's scaling
//! with clipping at its stated codes (or its rails measured when none are stated), a
//! demodulator's faults, the winding check if asked for, the calibration (none, stored or
//! online) and the angle correction (none, harmonics or table). This file only converts.

use core::mem::MaybeUninit;

use angletrack_core::{
    AdcSample, AngleCorrection, CalibrationSettings, CalibrationStage, Calibrator, ChainState,
    ConfigError, CorrectionStage, FrontEndFaults, Gains, Input as CoreInput, MAX_CORRECTION_ORDER,
    ObserverState, OnlineCalibration, Order, Rails, SupportedOrder, Tracker, TrackerFrontEnd,
    TrackerInput, TrackerSettings, TrackerState, WindingCheck,
};

use crate::adc::AdcF32;
use crate::calibration::at_sensor_calibration_f32;
use crate::demodulator::at_demodulated_pair_f32;
use crate::gains::{AnyGains, at_gains_f32};
use crate::observer::at_estimate_f32;
use crate::slot::{self, Refused, Stored};
use crate::status::{AT_ERR_STAGES, at_status, status_of};
use crate::table::at_angle_correction_table_f32;

/// The 8-byte words of an `at_chain_f32`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CHAIN_F32_WORDS: usize = 282;
/// The 8-byte words of an `at_chain_state_f32`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CHAIN_STATE_F32_WORDS: usize = 32;

/// The checked configuration of one signal chain, made by `at_chain_f32_new` from the
/// observer's gains and optional stages. Immutable once made: one serves any number of
/// channels (`at_chain_state_f32`). Place it anywhere; copy it by assignment; never write its
/// fields. A zeroed one is refused.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_chain_f32 {
    /// Private: which Rust value `storage` holds (0: none).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_CHAIN_F32_WORDS],
}

slot::slot_struct!(at_chain_f32, AT_CHAIN_F32_WORDS);

/// One channel's state of a signal chain: the observer's state and the online
/// calibration's estimator. A zeroed one is fresh (as after `at_chain_state_f32_reset`): the
/// observer initialises itself from its first sample, the online calibration is off until
/// `at_chain_state_f32_set_calibration_mode`. Place it anywhere; copy it by assignment;
/// never write its fields.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_chain_state_f32 {
    /// Private: which Rust value `storage` holds (0: a fresh state).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_CHAIN_STATE_F32_WORDS],
}

slot::slot_struct!(at_chain_state_f32, AT_CHAIN_STATE_F32_WORDS);

/// The harmonic orders an `at_angle_correction_f32` holds (the core's
/// `MAX_CORRECTION_ORDER`: the struct's arrays are the core's, checked at compile time).
pub const AT_CORRECTION_ORDER: usize = 8;

const _: () = assert!(AT_CORRECTION_ORDER == MAX_CORRECTION_ORDER);

/// A harmonic angle error `d(theta) = sum_k a_k cos(k theta) + b_k sin(k theta)`, `k = 1..8`
/// (rad), as `angletrack calibrate` learns it: the chain rotates each sample by `-d` at the
/// observer's predicted angle. All zero corrects nothing.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct at_angle_correction_f32 {
    /// `a_k` at index `k - 1` (rad).
    pub cos_coefficients: [f32; AT_CORRECTION_ORDER],
    /// `b_k` at index `k - 1` (rad).
    pub sin_coefficients: [f32; AT_CORRECTION_ORDER],
}

/// The online calibration's settings (the core's `CalibrationSettings`): when it learns and
/// the bounds beyond which its estimates raise a fault. Start from
/// `at_calibration_settings_f32_default()`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct at_calibration_settings_f32 {
    /// Learns only above this electrical speed (rad/s); 0 for the default, one turn in
    /// 4096 samples.
    pub min_speed_rad_s: f32,
    /// An offset above this fraction of its channel's amplitude flags
    /// `AT_FAULT_OFFSET_OR_QUADRATURE` (default 0.1).
    pub max_offset: f32,
    /// `|A_s / A_c - 1|` above this flags `AT_FAULT_AMPLITUDE_MISMATCH` (default 0.2).
    pub max_amplitude_mismatch: f32,
    /// `|quadrature|` (rad) above this flags `AT_FAULT_OFFSET_OR_QUADRATURE` (default 0.1).
    pub max_quadrature_rad: f32,
}

impl at_calibration_settings_f32 {
    /// The core's defaults.
    pub(crate) fn default_settings() -> Self {
        let d = CalibrationSettings::<f32>::default();
        Self {
            min_speed_rad_s: d.min_speed_rad_s.unwrap_or(0.0),
            max_offset: d.max_offset,
            max_amplitude_mismatch: d.max_amplitude_mismatch,
            max_quadrature_rad: d.max_quadrature_rad,
        }
    }

    /// The core's settings, field by field (from the core's defaults, so that fields it
    /// may add keep them).
    fn to_core(self) -> CalibrationSettings<f32> {
        let mut s = CalibrationSettings::default();
        s.min_speed_rad_s = (self.min_speed_rad_s != 0.0).then_some(self.min_speed_rad_s);
        s.max_offset = self.max_offset;
        s.max_amplitude_mismatch = self.max_amplitude_mismatch;
        s.max_quadrature_rad = self.max_quadrature_rad;
        s
    }
}

/// What an `at_chain_f32` holds: the core's standard chain of order `N`.
pub(crate) type ChainF32<const N: usize> = Tracker<f32, Gains<f32, N>>;

/// The state of a chain of order `N`.
pub(crate) type StateF32<const N: usize> = TrackerState<f32, ObserverState<f32, N>>;

impl Stored for ChainF32<2> {
    const TAG: u32 = 0x4154_4b02; // "ATK", order 2
}
impl Stored for ChainF32<3> {
    const TAG: u32 = 0x4154_4b03; // "ATK", order 3
}
impl Stored for StateF32<2> {
    const TAG: u32 = 0x4154_6b02; // "ATk", order 2
}
impl Stored for StateF32<3> {
    const TAG: u32 = 0x4154_6b03; // "ATk", order 3
}

/// The optional stages `at_chain_f32_new` takes, as references.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stages<'a> {
    /// The ADC front end, with its stated range.
    pub(crate) adc: Option<&'a AdcF32>,
    /// A stored calibration.
    pub(crate) stored: Option<&'a at_sensor_calibration_f32>,
    /// The online calibration's settings.
    pub(crate) online: Option<&'a at_calibration_settings_f32>,
    /// The harmonic angle correction.
    pub(crate) correction: Option<&'a at_angle_correction_f32>,
    /// The angle correction's table.
    pub(crate) table: Option<&'a at_angle_correction_table_f32>,
}

/// The chain of `gains` and the checked `stages`.
fn build<const N: usize>(
    gains: &Gains<f32, N>,
    stages: Stages<'_>,
) -> Result<ChainF32<N>, ConfigError> {
    let calibration = match (stages.stored, stages.online) {
        (Some(stored), _) => CalibrationStage::Stored(stored.checked()?),
        (None, Some(settings)) => CalibrationStage::Online(OnlineCalibration::new(
            settings.to_core(),
            gains.sample_period(),
        )?),
        (None, None) => CalibrationStage::None,
    };
    let correction = match (stages.correction, stages.table) {
        (Some(c), _) => CorrectionStage::Harmonics(AngleCorrection::new(
            c.cos_coefficients,
            c.sin_coefficients,
        )?),
        (None, Some(table)) => CorrectionStage::Table(table.checked()?),
        (None, None) => CorrectionStage::None,
    };
    let input = match stages.adc {
        Some(adc) => CoreInput::Counts {
            adc: adc.scaling,
            rails: adc
                .range
                .map_or(Rails::Measured, |(min, max)| Rails::Stated { min, max }),
        },
        None => CoreInput::Units {
            rails: Rails::Unchecked,
        },
    };
    let front_end = TrackerFrontEnd::new(TrackerSettings {
        input,
        winding: None,
        calibration,
        correction,
    })?;
    Ok(Tracker::new(front_end, *gains))
}

/// `chain` with the core's winding check for windings of `amplitude` (checked).
fn with_winding_check<const N: usize>(
    chain: &ChainF32<N>,
    amplitude: f32,
) -> Result<ChainF32<N>, ConfigError> {
    let winding = Some(WindingCheck::new(amplitude)?);
    Ok(Tracker::new(
        chain.front_end.with_winding(winding),
        chain.observer,
    ))
}

impl at_chain_f32 {
    /// Builds and stores the chain (`self` unchanged on error).
    pub(crate) fn set(&mut self, gains: &at_gains_f32, stages: Stages<'_>) -> at_status {
        if (stages.stored.is_some() && stages.online.is_some())
            || (stages.correction.is_some() && stages.table.is_some())
        {
            return AT_ERR_STAGES;
        }
        let result = match gains.get() {
            Ok(AnyGains::Two(g)) => build(g, stages).map(|c| self.slot_put(c)),
            Ok(AnyGains::Three(g)) => build(g, stages).map(|c| self.slot_put(c)),
            Err(refused) => return refused.status(),
        };
        result.err().map_or(crate::status::AT_OK, status_of)
    }

    /// Stores `chain` with the core's winding check for windings of `amplitude` (`self`
    /// unchanged on error).
    pub(crate) fn set_with_winding_check(
        &mut self,
        chain: &at_chain_f32,
        amplitude: f32,
    ) -> at_status {
        let result = match chain.get() {
            Ok(AnyChain::Two(c)) => with_winding_check(c, amplitude).map(|c| self.slot_put(c)),
            Ok(AnyChain::Three(c)) => with_winding_check(c, amplitude).map(|c| self.slot_put(c)),
            Err(refused) => return refused.status(),
        };
        result.err().map_or(crate::status::AT_OK, status_of)
    }

    /// The chain, if made by `at_chain_f32_new` of this build.
    #[inline(always)]
    pub(crate) fn get(&self) -> Result<AnyChain<'_>, Refused> {
        match self.slot_get() {
            Ok(c) => Ok(AnyChain::Two(c)),
            Err(Refused::NotInitialised) => self.slot_get().map(AnyChain::Three),
            Err(refused) => Err(refused),
        }
    }
}

/// A chain of either order, borrowed from an `at_chain_f32`.
#[derive(Debug, Clone, Copy)]
pub(crate) enum AnyChain<'a> {
    /// A 2nd-order observer.
    Two(&'a ChainF32<2>),
    /// A 3rd-order observer.
    Three(&'a ChainF32<3>),
}

impl at_chain_state_f32 {
    /// A fresh state (all zero, as C static memory holds).
    pub(crate) const FRESH: Self = Self::ZEROED;

    /// The state of a chain of order `N`: the one held, or a fresh one; refused if another
    /// build's.
    #[inline(always)]
    pub(crate) fn of_order<const N: usize>(&mut self) -> Result<&mut StateF32<N>, Refused>
    where
        StateF32<N>: Stored,
    {
        self.slot_get_or_put(ChainState::new)
    }

    /// The calibrator of the state held (of either order), or a fresh one's; refused if
    /// another build's.
    pub(crate) fn calibrator(&mut self) -> Result<&mut Calibrator<f32>, Refused> {
        if self.tag == <StateF32<2> as Stored>::TAG {
            return self.of_order::<2>().map(|s| s.front_end.calibrator_mut());
        }
        self.of_order::<3>().map(|s| s.front_end.calibrator_mut())
    }

    /// A copy of the calibrator held (a fresh one's for a fresh state).
    pub(crate) fn calibrator_value(&self) -> Result<Calibrator<f32>, Refused> {
        match self.slot_get::<StateF32<2>>() {
            Ok(s) => return Ok(*s.front_end.calibrator()),
            Err(Refused::OtherBuild) => return Err(Refused::OtherBuild),
            Err(Refused::NotInitialised) => {}
        }
        match self.slot_get::<StateF32<3>>() {
            Ok(s) => Ok(*s.front_end.calibrator()),
            Err(Refused::NotInitialised) => Ok(Calibrator::new()),
            Err(refused) => Err(refused),
        }
    }

    /// Returns the latched faults (`AT_FAULT_*` bits) and clears them; 0 for a fresh state
    /// (or another build's).
    pub(crate) fn clear_faults(&mut self) -> u32 {
        let faults = match self.tag {
            t if t == <StateF32<2> as Stored>::TAG => {
                self.of_order::<2>().map(|s| s.observer.clear_faults())
            }
            t if t == <StateF32<3> as Stored>::TAG => {
                self.of_order::<3>().map(|s| s.observer.clear_faults())
            }
            _ => return 0,
        };
        faults.map_or(0, |f| u32::from(f.bits()))
    }

    /// Returns the front-end faults latched by the front-end and winding checks
    /// (`AT_FRONT_END_FAULT_*` bits) and clears them; 0 for a fresh state (or another
    /// build's).
    pub(crate) fn clear_front_end_faults(&mut self) -> u32 {
        /// The checks' latched faults, cleared.
        fn of(front_end: &mut angletrack_core::TrackerFrontEndState<f32>) -> u32 {
            u32::from(front_end.clear_faults().bits())
        }
        match self.tag {
            t if t == <StateF32<2> as Stored>::TAG => {
                self.of_order::<2>().map_or(0, |s| of(&mut s.front_end))
            }
            t if t == <StateF32<3> as Stored>::TAG => {
                self.of_order::<3>().map_or(0, |s| of(&mut s.front_end))
            }
            _ => 0,
        }
    }
}

/// An input of the chain: a `(y_c, y_s)` pair, a demodulated pair with its front-end
/// faults, or ADC counts for a chain with an ADC stage, as the core's input.
pub(crate) trait Input: Copy {
    /// The core's input.
    type Core: TrackerInput<f32>;
    /// The core's input; `None` if a chain of counts (`counts`) or of pairs cannot take it.
    fn core(self, counts: bool) -> Option<Self::Core>;
}

/// A `(y_c, y_s)` pair in the input's units (the ADC stage, if any, is for counts).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pair(pub(crate) f32, pub(crate) f32);

impl Input for Pair {
    type Core = (f32, f32);
    #[inline(always)]
    fn core(self, _: bool) -> Option<(f32, f32)> {
        Some((self.0, self.1))
    }
}

/// A demodulator's pair, with the front-end faults of its window (`faults`: the
/// `AT_FRONT_END_FAULT_*` bits, the core's `FrontEndFaults`), for a chain without an ADC
/// stage (the demodulator took the counts; the ADC's range, in counts, says nothing of a
/// pair).
impl Input for &at_demodulated_pair_f32 {
    type Core = ((f32, f32), FrontEndFaults);
    #[inline(always)]
    fn core(self, counts: bool) -> Option<Self::Core> {
        // The core's flags fit 8 bits; higher bits are none of its.
        let faults = FrontEndFaults::from_bits((self.faults & 0xff) as u8);
        (!counts).then_some(((self.y_c, self.y_s), faults))
    }
}

/// Raw counts `(raw_c, raw_s)`, for a chain with an ADC stage.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Counts<I>(pub(crate) I, pub(crate) I);

impl<I: AdcSample> Input for Counts<I>
where
    (I, I): TrackerInput<f32>,
{
    type Core = (I, I);
    #[inline(always)]
    fn core(self, counts: bool) -> Option<(I, I)> {
        counts.then_some((self.0, self.1))
    }
}

/// One sample through `chain` on `state`: `finish` called with the chain of order `N` and
/// the pair on the state of order `N`; `None` (and nothing changed) if refused: a chain not
/// made, another build's state, counts without an ADC stage.
macro_rules! through {
    ($chain:expr, $state:expr, $input:expr, |$c:ident, $s:ident, $pair:ident| $body:expr) => {
        match $chain.get() {
            Ok($crate::chain::AnyChain::Two($c)) => {
                match (
                    $input.core($c.front_end.adc().is_some()),
                    $state.of_order::<2>(),
                ) {
                    (Some($pair), Ok($s)) => Some($body),
                    _ => None,
                }
            }
            Ok($crate::chain::AnyChain::Three($c)) => {
                match (
                    $input.core($c.front_end.adc().is_some()),
                    $state.of_order::<3>(),
                ) {
                    (Some($pair), Ok($s)) => Some($body),
                    _ => None,
                }
            }
            Err(_) => None,
        }
    };
}

/// One sample through the chain, the state only: `false` if refused (nothing changed).
#[inline(always)]
pub(crate) fn track(
    chain: &at_chain_f32,
    state: &mut at_chain_state_f32,
    input: impl Input,
) -> bool {
    through!(chain, state, input, |c, s, pair| c.track(s, pair)).is_some()
}

/// One sample through the chain, then the estimate (with the front end's faults).
#[inline(always)]
pub(crate) fn update(
    chain: &at_chain_f32,
    state: &mut at_chain_state_f32,
    input: impl Input,
) -> at_estimate_f32 {
    through!(chain, state, input, |c, s, pair| c.update(s, pair).into())
        .unwrap_or(at_estimate_f32::INVALID)
}

/// The estimate `state` holds for `chain` (the observer's faults; the front end's are
/// latched in the state): a fresh state's for a fresh state.
pub(crate) fn estimate(chain: &at_chain_f32, state: &at_chain_state_f32) -> at_estimate_f32 {
    /// The estimate of a chain of order `N`.
    fn of<const N: usize>(c: &ChainF32<N>, state: &at_chain_state_f32) -> at_estimate_f32
    where
        Order<N>: SupportedOrder,
        StateF32<N>: Stored,
    {
        match state.slot_get::<StateF32<N>>() {
            Ok(s) => c.estimate(s).into(),
            Err(Refused::NotInitialised) => c.estimate(&StateF32::<N>::new()).into(),
            Err(Refused::OtherBuild) => at_estimate_f32::INVALID,
        }
    }
    match chain.get() {
        Ok(AnyChain::Two(c)) => of(c, state),
        Ok(AnyChain::Three(c)) => of(c, state),
        Err(_) => at_estimate_f32::INVALID,
    }
}
