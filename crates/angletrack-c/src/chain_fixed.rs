//! The signal chain in fixed point (the core's [`Chain`] on [`FixedGains`]), for cores
//! without an FPU: `at_chain_fixed`, the configuration of one chain (the ADC's counts to the
//! observer's 16-bit samples, an optional stored sensor calibration and an optional angle
//! correction table, both applied in integers, and the fixed-point observer with its
//! monitor); `at_chain_state_fixed`, one channel's state; and `at_adc_counts`, the plain
//! ADC settings (the core's `AdcCounts`).
//!
//! The chain is the core's `Chain<(AdcCounts, (Option<FrontEndCheck<i16>>,
//! (Option<HeldRailCheck>, (Option<FixedCalibration>,
//! Option<FixedAngleCorrectionTable<256>>)))), FixedGains<N>>`: with a stated range of codes
//! (`at_chain_fixed_with_adc_range`) the core's `FrontEndCheck` flags clipping against it,
//! in the observer's 16-bit units (the codes through the ADC's own shift, exact); with an ADC
//! and no range the core's `HeldRailCheck` flags it against the rails it measures on those
//! units. A chain without an ADC takes `int16` samples through the
//! identity of `AdcCounts::twos_complement(16)` (a widening, two comparisons and a shift by
//! 0); an absent calibration or table is skipped by the core's `Option` stage (one test of its flag), not
//! run as an identity.

use core::mem::MaybeUninit;

use angletrack_core::{
    AdcCounts, AdcSample, Chain, ChainState, ConfigError, FixedCalibration, FixedGains, FixedState,
    FrontEndCheck, FrontEndCheckState, HeldRailCheck, HeldRails, Order, SensorCalibration,
    SupportedOrder,
};

use crate::calibration::at_sensor_calibration_f32;
use crate::fixed::{AnyFixed, at_fixed_estimate, at_fixed_gains};
use crate::slot::{self, Refused, Stored};
use crate::status::{AT_OK, at_status, status_of};
use crate::table::{TableFixed, at_angle_table_fixed};

/// The 8-byte words of an `at_chain_fixed`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CHAIN_FIXED_WORDS: usize = 77;
/// The 8-byte words of an `at_chain_state_fixed`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CHAIN_STATE_FIXED_WORDS: usize = 12;

/// The ADC of a fixed-point chain (the core's `AdcCounts`): each count less
/// `mid_scale_counts`, shifted left by `shift` (0 to 15) bits to the observer's 16-bit range,
/// saturated. Plain: write it (`{2048, 4}` for a 12-bit offset-binary ADC), or fill it with
/// `at_adc_counts_offset_binary` or `at_adc_counts_twos_complement`; `at_chain_fixed_new`
/// checks it.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct at_adc_counts {
    /// The count of a zero signal (at most 2^30 in magnitude): `2^(bits-1)` for an offset
    /// binary ADC, 0 for a two's complement one.
    pub mid_scale_counts: i32,
    /// The left shift (0 to 15) to the observer's 16 bits: `16 - bits`.
    pub shift: u32,
}

impl at_adc_counts {
    /// The settings of an ADC of `bits` bits (2 to 16), offset binary or two's complement.
    pub(crate) fn of_bits(bits: u32, offset_binary: bool) -> Result<Self, ConfigError> {
        let adc = if offset_binary {
            AdcCounts::offset_binary(bits)
        } else {
            AdcCounts::twos_complement(bits)
        };
        adc.map(|_| Self {
            mid_scale_counts: if offset_binary { 1 << (bits - 1) } else { 0 },
            shift: 16 - bits,
        })
    }

    /// The conversion, checked by the core's `AdcCounts`.
    fn checked(&self) -> Result<AdcCounts, ConfigError> {
        AdcCounts::new(self.mid_scale_counts, self.shift)?;
        AdcCounts::new(self.mid_scale_counts, self.shift)
    }
}

/// The checked configuration of one fixed-point signal chain, made by `at_chain_fixed_new`.
/// Immutable once made: one serves any number of channels (`at_chain_state_fixed`). Place it
/// anywhere; copy it by assignment; never write its fields. A zeroed one is refused.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_chain_fixed {
    /// Private: which Rust value `storage` holds (0: none).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_CHAIN_FIXED_WORDS],
}

slot::slot_struct!(at_chain_fixed, AT_CHAIN_FIXED_WORDS);

/// One channel's state of a fixed-point chain (the observer's: the stages keep none). A
/// zeroed one is fresh (as after `at_chain_state_fixed_reset`): the observer initialises
/// itself from its first sample. Place it anywhere; copy it by assignment; never write its
/// fields.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_chain_state_fixed {
    /// Private: which Rust value `storage` holds (0: a fresh state).
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_CHAIN_STATE_FIXED_WORDS],
}

slot::slot_struct!(at_chain_state_fixed, AT_CHAIN_STATE_FIXED_WORDS);

/// The front end of a fixed-point chain: the ADC, the clipping check against a stated
/// range or (with an ADC and no range) against the rails measured, the stored calibration
/// and the angle table.
type FrontEnd = (
    AdcCounts,
    (
        Option<FrontEndCheck<i16>>,
        (
            Option<HeldRailCheck>,
            (Option<FixedCalibration>, Option<TableFixed>),
        ),
    ),
);

/// What an `at_chain_fixed` holds: the core's chain of order `N`, and whether its ADC was
/// given (else `u16` and `i32` counts are refused).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ChainFixed<const N: usize> {
    /// Whether C gave the ADC (else it is the `int16` identity).
    pub(crate) has_adc: bool,
    /// The core's chain.
    pub(crate) chain: Chain<FrontEnd, FixedGains<N>>,
}

/// The state of a fixed-point chain of order `N`.
pub(crate) type StateFixed<const N: usize> =
    ChainState<((), ((FrontEndCheckState, ()), (HeldRails<i16>, ((), ())))), FixedState<N>>;

impl Stored for ChainFixed<2> {
    const TAG: u32 = 0x4154_7102; // "ATq", order 2
}
impl Stored for ChainFixed<3> {
    const TAG: u32 = 0x4154_7103; // "ATq", order 3
}
impl Stored for StateFixed<2> {
    const TAG: u32 = 0x4154_5102; // "ATQ", order 2
}
impl Stored for StateFixed<3> {
    const TAG: u32 = 0x4154_5103; // "ATQ", order 3
}

/// The optional stages `at_chain_fixed_new` takes, as references.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FixedStages<'a> {
    /// The ADC.
    pub(crate) adc: Option<&'a at_adc_counts>,
    /// A stored calibration, in the observer's 16-bit counts.
    pub(crate) calibration: Option<&'a at_sensor_calibration_f32>,
    /// The angle correction table.
    pub(crate) table: Option<&'a at_angle_table_fixed>,
}

/// The chain of `gains` (its monitor for `nominal_amplitude_counts`, off for 0) and the
/// checked `stages`.
fn build<const N: usize>(
    gains: &FixedGains<N>,
    stages: FixedStages<'_>,
    nominal_amplitude_counts: f64,
) -> Result<ChainFixed<N>, ConfigError>
where
    Order<N>: SupportedOrder,
{
    let adc = stages.adc.map(at_adc_counts::checked).transpose()?;
    let calibration = match stages.calibration {
        Some(c) => Some(FixedCalibration::new(&SensorCalibration::<f64>::new(
            c.offset_c.into(),
            c.offset_s.into(),
            c.amplitude_c.into(),
            c.amplitude_s.into(),
            c.quadrature_rad.into(),
        )?)?),
        None => None,
    };
    let table = stages
        .table
        .map(at_angle_table_fixed::checked)
        .transpose()?;
    let nominal = (nominal_amplitude_counts != 0.0).then_some(nominal_amplitude_counts);
    let observer = gains.with_monitor(nominal)?;
    // Counts from an ADC with no stated range: clipping against the rails measured.
    let held_rails = adc.is_some().then_some(HeldRailCheck::new());
    Ok(ChainFixed {
        has_adc: adc.is_some(),
        chain: Chain::new(
            (
                adc.unwrap_or(IDENTITY),
                (None, (held_rails, (calibration, table))),
            ),
            observer,
        ),
    })
}

impl<const N: usize> ChainFixed<N> {
    /// The chain with clipping flagged at the codes `min` and `max` (the core's
    /// `FrontEndCheck::of_adc_codes`: through the ADC to the observer's 16 bits, exact).
    fn with_adc_range(mut self, min: i32, max: i32) -> Result<Self, ConfigError> {
        let check = FrontEndCheck::of_adc_codes(&self.chain.front_end.0, min, max)?;
        self.chain.front_end.1.0 = Some(check);
        self.chain.front_end.1.1.0 = None;
        Ok(self)
    }
}

/// An `at_chain_fixed`'s chain of either order.
#[derive(Debug, Clone, Copy)]
pub(crate) enum AnyChainFixed<'a> {
    /// Order 2.
    Two(&'a ChainFixed<2>),
    /// Order 3.
    Three(&'a ChainFixed<3>),
}

impl at_chain_fixed {
    /// Builds and stores the chain (`self` unchanged on error).
    pub(crate) fn set(
        &mut self,
        gains: &at_fixed_gains,
        stages: FixedStages<'_>,
        nominal_amplitude_counts: f64,
    ) -> at_status {
        let result = match gains.get() {
            Ok(AnyFixed::Two(g)) => {
                build(g, stages, nominal_amplitude_counts).map(|c| self.slot_put(c))
            }
            Ok(AnyFixed::Three(g)) => {
                build(g, stages, nominal_amplitude_counts).map(|c| self.slot_put(c))
            }
            Err(refused) => return refused.status(),
        };
        result.err().map_or(AT_OK, status_of)
    }

    /// Stores `chain` with clipping flagged at the codes `min` and `max` (`self` unchanged
    /// on error).
    pub(crate) fn set_with_adc_range(
        &mut self,
        chain: &at_chain_fixed,
        min: i32,
        max: i32,
    ) -> at_status {
        let result = match chain.get() {
            Ok(AnyChainFixed::Two(c)) => c.with_adc_range(min, max).map(|c| self.slot_put(c)),
            Ok(AnyChainFixed::Three(c)) => c.with_adc_range(min, max).map(|c| self.slot_put(c)),
            Err(refused) => return refused.status(),
        };
        result.err().map_or(AT_OK, status_of)
    }

    /// The chain, if made by `at_chain_fixed_new` of this build.
    #[inline(always)]
    pub(crate) fn get(&self) -> Result<AnyChainFixed<'_>, Refused> {
        if self.tag == <ChainFixed<2> as Stored>::TAG {
            self.slot_get().map(AnyChainFixed::Two)
        } else {
            self.slot_get().map(AnyChainFixed::Three)
        }
    }
}

impl at_chain_state_fixed {
    /// A fresh state (all zero, as C static memory holds).
    pub(crate) const FRESH: Self = Self::ZEROED;

    /// The state of a chain of order `N`: the one held, or a fresh one; refused if another
    /// build's.
    #[inline(always)]
    pub(crate) fn of_order<const N: usize>(&mut self) -> Result<&mut StateFixed<N>, Refused>
    where
        StateFixed<N>: Stored,
    {
        self.slot_get_or_put(|| ChainState {
            front_end: (
                (),
                (
                    (FrontEndCheckState::default(), ()),
                    (HeldRails::default(), ((), ())),
                ),
            ),
            observer: FixedState::new(),
        })
    }

    /// Returns the latched faults (`AT_FAULT_*` bits) and clears them; 0 for a fresh state
    /// (or another build's).
    pub(crate) fn clear_faults(&mut self) -> u32 {
        /// The faults of the state of order `N`.
        fn of<const N: usize>(s: &mut at_chain_state_fixed) -> Option<u32>
        where
            StateFixed<N>: Stored,
        {
            s.of_order::<N>().ok().map(|s| {
                let f = s.observer.latched_faults();
                s.observer.clear_faults();
                u32::from(f.bits())
            })
        }
        let faults = match self.tag {
            t if t == <StateFixed<2> as Stored>::TAG => of::<2>(self),
            t if t == <StateFixed<3> as Stored>::TAG => of::<3>(self),
            _ => None,
        };
        faults.unwrap_or(0)
    }

    /// Returns the front-end faults latched by the clipping checks, against the stated
    /// range or the rails measured (`AT_FRONT_END_FAULT_*` bits), and clears them; 0 for a
    /// fresh state (or another build's).
    pub(crate) fn clear_front_end_faults(&mut self) -> u32 {
        /// Both checks' latched faults, cleared.
        fn of<const N: usize>(state: &mut StateFixed<N>) -> u32 {
            let checks = &mut state.front_end.1;
            u32::from((checks.0.0.clear_faults() | checks.1.0.clear_faults()).bits())
        }
        match self.tag {
            t if t == <StateFixed<2> as Stored>::TAG => self.of_order::<2>().map_or(0, of),
            t if t == <StateFixed<3> as Stored>::TAG => self.of_order::<3>().map_or(0, of),
            _ => 0,
        }
    }
}

/// The ADC of a chain without one: the identity of `int16` samples.
const IDENTITY: AdcCounts = match AdcCounts::twos_complement(16) {
    Ok(adc) => adc,
    Err(_) => panic!("the identity is a valid ADC"),
};

/// Counts of a fixed-point chain: `int16` (through the identity if the chain has no ADC),
/// `uint16` and `int32` (refused without an ADC).
pub(crate) trait FixedInput: AdcSample {
    /// Whether a chain without an ADC takes this type.
    const WITHOUT_ADC: bool;
}
impl FixedInput for i16 {
    const WITHOUT_ADC: bool = true;
}
impl FixedInput for u16 {
    const WITHOUT_ADC: bool = false;
}
impl FixedInput for i32 {
    const WITHOUT_ADC: bool = false;
}

/// One sample through `chain` on `state`: `$body` with the chain `$c` and state `$s` of
/// order `N`; `None` (and nothing changed) if refused: a chain not made, another build's
/// state, counts the chain cannot take.
macro_rules! through_fixed {
    ($chain:expr, $state:expr, $input:ty, |$c:ident, $s:ident| $body:expr) => {
        match $chain.get() {
            Ok($crate::chain_fixed::AnyChainFixed::Two($c))
                if <$input as FixedInput>::WITHOUT_ADC || $c.has_adc =>
            {
                $state.of_order::<2>().ok().map(|$s| $body)
            }
            Ok($crate::chain_fixed::AnyChainFixed::Three($c))
                if <$input as FixedInput>::WITHOUT_ADC || $c.has_adc =>
            {
                $state.of_order::<3>().ok().map(|$s| $body)
            }
            _ => None,
        }
    };
}

/// One sample of counts through the chain, the state only: `false` if refused.
#[inline(always)]
pub(crate) fn track_fixed<I: FixedInput>(
    chain: &at_chain_fixed,
    state: &mut at_chain_state_fixed,
    raw_c: I,
    raw_s: I,
) -> bool {
    through_fixed!(chain, state, I, |c, s| c.chain.track(s, (raw_c, raw_s))).is_some()
}

/// One sample of counts through the chain, then the estimate.
#[inline(always)]
pub(crate) fn update_fixed<I: FixedInput>(
    chain: &at_chain_fixed,
    state: &mut at_chain_state_fixed,
    raw_c: I,
    raw_s: I,
) -> at_fixed_estimate {
    through_fixed!(chain, state, I, |c, s| c
        .chain
        .update(s, (raw_c, raw_s))
        .into())
    .unwrap_or(at_fixed_estimate::INVALID)
}

/// The estimate `state` holds for `chain`: a fresh state's for a fresh state.
pub(crate) fn estimate_fixed(
    chain: &at_chain_fixed,
    state: &at_chain_state_fixed,
) -> at_fixed_estimate {
    /// The estimate of a chain of order `N`.
    fn of<const N: usize>(c: &ChainFixed<N>, state: &at_chain_state_fixed) -> at_fixed_estimate
    where
        StateFixed<N>: Stored,
    {
        match state.slot_get::<StateFixed<N>>() {
            Ok(s) => c.chain.estimate(s).into(),
            Err(Refused::NotInitialised) => FixedGains::<N>::estimate(&FixedState::new()).into(),
            Err(Refused::OtherBuild) => at_fixed_estimate::INVALID,
        }
    }
    match chain.get() {
        Ok(AnyChainFixed::Two(c)) => of(c, state),
        Ok(AnyChainFixed::Three(c)) => of(c, state),
        Err(_) => at_fixed_estimate::INVALID,
    }
}

/// The sample period (s) of a chain, 0 if not made.
pub(crate) fn sample_period_fixed(chain: &at_chain_fixed) -> f64 {
    match chain.get() {
        Ok(AnyChainFixed::Two(c)) => c.chain.observer.sample_period(),
        Ok(AnyChainFixed::Three(c)) => c.chain.observer.sample_period(),
        Err(_) => 0.0,
    }
}
