//! The signal chain in fixed point (the core's [`Chain`] on [`FixedGains`]), for cores
//! without an FPU: `at_chain_fixed`, the configuration of one chain (the ADC's counts to the
//! observer's 16-bit samples, an optional stored sensor calibration and an optional angle
//! correction table, both applied in integers, and the fixed-point observer with its
//! monitor); `at_chain_state_fixed`, one channel's state; and `at_adc_counts`, the plain
//! ADC settings (the core's `AdcCounts`).
//!
//! The chain is the core's standard chain in fixed point, `Tracker<i16, FixedGains<N>>`,
//! built by the core's `TrackerFrontEnd::new`: counts through the ADC with clipping at a
//! stated range of codes (`at_chain_fixed_with_adc_range`: exact in the observer's 16-bit
//! units) or, with an ADC and no range, at the rails measured; a chain without an ADC takes
//! `int16` samples as they are. This file only converts.

use core::mem::MaybeUninit;

use angletrack_core::{
    AdcCounts, AdcSample, ConfigError, FixedCalibration, FixedGains, FixedState, Input, Order,
    Rails, SensorCalibration, SupportedOrder, Tracker, TrackerFrontEnd, TrackerInput,
    TrackerSettings, TrackerState,
};

use crate::calibration::at_sensor_calibration_f32;
use crate::fixed::{AnyFixed, at_fixed_estimate, at_fixed_gains};
use crate::slot::{self, Refused, Stored};
use crate::status::{AT_OK, at_status, status_of};
use crate::table::at_angle_table_fixed;

/// The 8-byte words of an `at_chain_fixed`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CHAIN_FIXED_WORDS: usize = 76;
/// The 8-byte words of an `at_chain_state_fixed`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CHAIN_STATE_FIXED_WORDS: usize = 18;

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

/// What an `at_chain_fixed` holds: the core's standard chain of order `N`.
pub(crate) type ChainFixed<const N: usize> = Tracker<i16, FixedGains<N>>;

/// The state of a fixed-point chain of order `N`.
pub(crate) type StateFixed<const N: usize> = TrackerState<i16, FixedState<N>>;

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
    let input = match adc {
        Some(adc) => Input::Counts {
            adc,
            rails: Rails::Measured,
        },
        None => Input::Units {
            rails: Rails::Unchecked,
        },
    };
    let front_end = TrackerFrontEnd::new(TrackerSettings {
        input,
        winding: (),
        calibration,
        correction: table,
    })?;
    Ok(Tracker::new(front_end, observer))
}

/// `chain` with clipping flagged at the codes `min` and `max` (through the ADC to the
/// observer's 16 bits, exact).
fn with_adc_range<const N: usize>(
    chain: &ChainFixed<N>,
    min: i32,
    max: i32,
) -> Result<ChainFixed<N>, ConfigError> {
    let front_end = chain.front_end.with_rails(Rails::Stated { min, max })?;
    Ok(Tracker::new(front_end, chain.observer))
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
            Ok(AnyChainFixed::Two(c)) => with_adc_range(c, min, max).map(|c| self.slot_put(c)),
            Ok(AnyChainFixed::Three(c)) => with_adc_range(c, min, max).map(|c| self.slot_put(c)),
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
        self.slot_get_or_put(StateFixed::<N>::new)
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
        /// The checks' latched faults, cleared.
        fn of<const N: usize>(state: &mut StateFixed<N>) -> u32 {
            u32::from(state.front_end.clear_faults().bits())
        }
        match self.tag {
            t if t == <StateFixed<2> as Stored>::TAG => self.of_order::<2>().map_or(0, of),
            t if t == <StateFixed<3> as Stored>::TAG => self.of_order::<3>().map_or(0, of),
            _ => 0,
        }
    }
}

/// Counts of a fixed-point chain: `int16` (through the identity if the chain has no ADC),
/// `uint16` and `int32` (refused without an ADC).
pub(crate) trait FixedInput: AdcSample {
    /// Whether a chain without an ADC takes this type.
    const WITHOUT_ADC: bool;
    /// The pair as the core's chain takes it.
    type Pair: TrackerInput<i16>;
    /// The pair of `raw_c` and `raw_s`.
    fn pair(raw_c: Self, raw_s: Self) -> Self::Pair;
}

/// The counts types C passes, each with its flag.
macro_rules! fixed_input {
    ($($int:ty: $without_adc:expr),*) => {$(
        impl FixedInput for $int {
            const WITHOUT_ADC: bool = $without_adc;
            type Pair = ($int, $int);
            #[inline(always)]
            fn pair(raw_c: $int, raw_s: $int) -> ($int, $int) {
                (raw_c, raw_s)
            }
        }
    )*};
}

fixed_input!(i16: true, u16: false, i32: false);

/// One sample through `chain` on `state`: `$body` with the chain `$c` and state `$s` of
/// order `N`; `None` (and nothing changed) if refused: a chain not made, another build's
/// state, counts the chain cannot take.
macro_rules! through_fixed {
    ($chain:expr, $state:expr, $input:ty, |$c:ident, $s:ident| $body:expr) => {
        match $chain.get() {
            Ok($crate::chain_fixed::AnyChainFixed::Two($c))
                if <$input as FixedInput>::WITHOUT_ADC || $c.front_end.adc().is_some() =>
            {
                $state.of_order::<2>().ok().map(|$s| $body)
            }
            Ok($crate::chain_fixed::AnyChainFixed::Three($c))
                if <$input as FixedInput>::WITHOUT_ADC || $c.front_end.adc().is_some() =>
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
    through_fixed!(chain, state, I, |c, s| c.track(s, I::pair(raw_c, raw_s))).is_some()
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
        .update(s, I::pair(raw_c, raw_s))
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
            Ok(s) => c.estimate(s).into(),
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
        Ok(AnyChainFixed::Two(c)) => c.observer.sample_period(),
        Ok(AnyChainFixed::Three(c)) => c.observer.sample_period(),
        Err(_) => 0.0,
    }
}
