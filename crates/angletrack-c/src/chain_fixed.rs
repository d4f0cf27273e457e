//! The signal chain in fixed point (the core's `Tracker` on `FixedGains`), for cores
//! without an FPU: `at_fixed_estimate`, what the observer reports; `at_chain_fixed`, the
//! configuration of one chain (the ADC's counts to the
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

use angletrack_core::{
    AdcCounts, ConfigError, FixedCalibration, FixedEstimate, FixedGains, FixedState, Input, Rails,
    Tracker, TrackerFrontEnd, TrackerSettings, TrackerState,
};

use crate::calibration::at_sensor_calibration_f32;
use crate::faults::AT_FAULT_INVALID_ARGUMENT;
use crate::gains::{at_fixed_gains, with_order};
use crate::mirror::mirror;
use crate::slot::{self, Slot, Stored, by_order};
use crate::status::{AT_OK, at_status, status_of};
use crate::table::at_angle_table_fixed;

mirror! {
    /// What the fixed-point observer knows after a sample, in its integers.
    #[derive(Default, Eq)]
    at_fixed_estimate: FixedEstimate = |_: &Self| FixedEstimate::default();
    /// Binary angle: 2^32 per turn, `INT32_MIN` is -pi (rad = angle * 2 pi / 2^32).
    angle: i32 = angle,
    /// Whole turns since initialisation: the position is `turns + angle / 2^32` turns.
    turns: i64 = turns,
    /// Speed (2^-32 turn per sample).
    speed: i32 = speed,
    /// Acceleration (2^-63 turn per sample^2); 0 for a 2nd-order observer.
    acceleration: i64 = acceleration,
    /// Normalised phase error (Q15: 32768 is 1), about the sine of the phase error.
    phase_error: i32 = phase_error,
    /// The monitor's last window's faults (`AT_FAULT_*` bits), or
    /// `AT_FAULT_INVALID_ARGUMENT` alone when the call's arguments were refused.
    faults: u32 = faults,
}

impl at_fixed_estimate {
    /// The estimate of a call whose arguments were refused (NULL, not made, another
    /// build's): `AT_FAULT_INVALID_ARGUMENT`, the rest 0.
    pub(crate) fn invalid() -> Self {
        Self {
            faults: AT_FAULT_INVALID_ARGUMENT,
            ..Self::default()
        }
    }
}

/// The 8-byte words of an `at_chain_fixed`'s storage (checked against the Rust type at
/// compile time, on every target).
pub const AT_CHAIN_FIXED_WORDS: usize = 77;
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
        // Both kinds take the same widths (2 to 16).
        AdcCounts::twos_complement(bits).map(|_| Self {
            mid_scale_counts: if offset_binary { 1 << (bits - 1) } else { 0 },
            shift: 16 - bits,
        })
    }

    /// The conversion, checked by the core's `AdcCounts`.
    fn checked(&self) -> Result<AdcCounts, ConfigError> {
        AdcCounts::new(self.mid_scale_counts, self.shift)
    }
}

slot::slot_struct! {
    /// The checked configuration of one fixed-point signal chain, made by `at_chain_fixed_new`.
    /// Immutable once made: one serves any number of channels (`at_chain_state_fixed`). Place it
    /// anywhere; copy it by assignment; never write its fields. A zeroed one is refused.
    at_chain_fixed[AT_CHAIN_FIXED_WORDS]
}

slot::slot_struct! {
    /// One channel's state of a fixed-point chain (the observer's: the stages keep none). A
    /// zeroed one is fresh (as after `at_chain_state_fixed_reset`): the observer initialises
    /// itself from its first sample. Place it anywhere; copy it by assignment; never write its
    /// fields.
    at_chain_state_fixed[AT_CHAIN_STATE_FIXED_WORDS]
}

/// What an `at_chain_fixed` holds: the core's standard chain of order `N`.
pub(crate) type ChainFixed<const N: usize> = Tracker<i16, FixedGains<N>>;

/// The state of a fixed-point chain of order `N`.
pub(crate) type StateFixed<const N: usize> = TrackerState<i16, FixedState<N>>;

impl<const N: usize> Stored for ChainFixed<N> {
    const TAG: u32 = 0x4154_7100 | N as u32; // "ATq", the order
}
impl<const N: usize> Stored for StateFixed<N> {
    const TAG: u32 = 0x4154_5100 | N as u32; // "ATQ", the order
}

/// The whole configuration of a fixed-point chain in integers, as `angletrack export
/// --format c` writes it (`static const`, in flash) for `at_chain_fixed_from_constants`:
/// the observer's `gains`, the words of its monitor's thresholds (`monitor`: enabled,
/// loss of signal, degradation low and high, roundness low and high, loss of tracking,
/// the largest speed, the per-sample tracking-error level in Q15; the core's
/// `FixedGains::monitor_words`) and the optional stages,
/// each NULL when absent: the ADC, a stored calibration and the angle-correction table.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_chain_fixed_constants<'a> {
    /// The observer's integer gains.
    pub gains: at_fixed_gains,
    /// The monitor's threshold words.
    pub monitor: [u32; 9],
    /// The ADC, or NULL (then the chain takes `int16` samples).
    pub adc: Option<&'a at_adc_counts>,
    /// The stored calibration in its integers, or NULL: the offsets in the observer's
    /// 16-bit counts, the sine gain `A_c / (A_s cos phi)` (positive) and the cross gain
    /// `tan phi` (within +-16384), both Q14 (the core's `FixedCalibration::q14_words`).
    pub calibration_q14: Option<&'a [i16; 4]>,
    /// The angle correction table, or NULL.
    pub table: Option<&'a at_angle_table_fixed>,
}

/// The front end of the stages: the ADC `adc` (checked; clipping against the rails
/// measured, or `int16` samples without it), the checked `calibration` and the `table`
/// (checked). Of no order: one copy in an image of both.
fn front_end(
    adc: Option<&at_adc_counts>,
    calibration: Option<Result<FixedCalibration, ConfigError>>,
    table: Option<&at_angle_table_fixed>,
) -> Result<TrackerFrontEnd<i16>, ConfigError> {
    let calibration = calibration.transpose()?;
    let input = match adc.map(at_adc_counts::checked).transpose()? {
        Some(adc) => Input::Counts {
            adc,
            rails: Rails::Measured,
        },
        None => Input::Units {
            rails: Rails::Unchecked,
        },
    };
    let correction = table.map(at_angle_table_fixed::checked).transpose()?;
    TrackerFrontEnd::new(TrackerSettings {
        input,
        winding: (),
        calibration,
        correction,
    })
}

impl at_chain_fixed {
    /// Builds and stores the chain of the observer `gains` (its monitor for
    /// `nominal_amplitude_counts`, off for 0) after the stages (`self` unchanged on error).
    pub(crate) fn set(
        &mut self,
        gains: &at_fixed_gains,
        adc: Option<&at_adc_counts>,
        calibration: Option<&at_sensor_calibration_f32>,
        table: Option<&at_angle_table_fixed>,
        nominal_amplitude_counts: f64,
    ) -> at_status {
        let calibration = calibration.map(|c| FixedCalibration::new(&c.checked::<f64>()?));
        let nominal = (nominal_amplitude_counts != 0.0).then_some(nominal_amplitude_counts);
        // With a nominal amplitude, the roundness check at its default tolerance (0.1), as the
        // core's `with_monitor` and the Rust export of a tracker file set it.
        let built = front_end(adc, calibration, table).map_err(status_of).and_then(|f| {
            with_order!(gains.order, N => FixedGains::<N>::from_constants(gains.constants(), gains.sample_period_s)
                .and_then(|g| g.with_monitor(nominal))
                .map(|g| self.slot_put(Tracker::new(f, g))))
        });
        built.map_or_else(|status| status, |()| AT_OK)
    }

    /// Builds and stores the chain of `c`, checked by integer comparisons only (`self`
    /// unchanged on error).
    pub(crate) fn set_from_constants(&mut self, c: &at_chain_fixed_constants) -> at_status {
        let (g, q14) = (&c.gains, c.calibration_q14.copied());
        let front = front_end(c.adc, q14.map(FixedCalibration::from_q14), c.table);
        let built = front.map_err(status_of).and_then(|f| {
            with_order!(g.order, N => FixedGains::<N>::from_words(g.constants(), g.sample_period_s, c.monitor)
                .map(|g| self.slot_put(Tracker::new(f, g))))
        });
        built.map_or_else(|status| status, |()| AT_OK)
    }

    /// Stores `chain` with clipping flagged at the codes `min` and `max` (`self` unchanged
    /// on error).
    pub(crate) fn set_with_adc_range(
        &mut self,
        chain: &at_chain_fixed,
        min: i32,
        max: i32,
    ) -> at_status {
        // Clipping flagged at the codes through the ADC to the observer's 16 bits, exact.
        let rails = Rails::Stated { min, max };
        match chain.get() {
            Ok(c) => by_order!(c, |c| self.slot_store(
                (c.front_end.with_rails(rails)).map(|f| Tracker::new(f, c.observer))
            )),
            Err(refused) => refused.status(),
        }
    }

    /// The estimate `e` in physical units by the chain's observer: its speed (rad/s) if
    /// `speed`, else its position (rad); 0 for a chain not made.
    pub(crate) fn in_units(&self, e: &at_fixed_estimate, speed: bool) -> f64 {
        let e = e.to_core();
        self.get().map_or(0.0, |c| {
            by_order!(c, |c| if speed {
                c.observer.speed_rad_s(&e)
            } else {
                c.observer.position_rad(&e)
            })
        })
    }
}

impl at_chain_state_fixed {
    /// Returns the latched faults (`AT_FAULT_*` bits) and clears them; 0 for a fresh state
    /// (or another build's).
    pub(crate) fn clear_faults(&mut self) -> u32 {
        self.held().map_or(0, |s| {
            by_order!(s, |s| {
                let faults = s.observer.latched_faults();
                s.observer.clear_faults();
                u32::from(faults.bits())
            })
        })
    }
}
