//! `at_adc_f32`: the ADC front end (the core's `AdcScaling<f32>`), which makes raw integer
//! samples the observer's input: `y = (raw - mid_scale_counts) / counts_per_unit`, with
//! the ADC's stated range (its lowest and highest codes), against which a chain flags
//! clipping (the core's `FrontEndCheck`, in `chain`).

use angletrack_core::{AdcScaling, ConfigError, FrontEndCheck, Rails};

use crate::slot::{self, Refused, Slot, Stored};
use crate::status::at_status;

/// The 8-byte words of an `at_adc_f32`'s storage (checked against the Rust type at compile
/// time, on every target).
pub const AT_ADC_F32_WORDS: usize = 3;

/// What an `at_adc_f32` holds: the scaling and the stated range of codes, if any.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AdcF32 {
    /// Counts to units.
    pub(crate) scaling: AdcScaling<f32>,
    /// The lowest and highest codes (counts), checked ordered.
    pub(crate) range: Option<(i32, i32)>,
}

impl Stored for AdcF32 {
    // "ATA" 2: the scaling with its range (a struct holding the scaling alone is refused).
    const TAG: u32 = 0x4154_4102;
}

/// The codes of an ADC of `bits` bits, signed (two's complement) or not (offset binary), by
/// the core's rule (`Rails::of_adc_bits`); `None` for a width it refuses.
pub(crate) fn codes_of(bits: u32, signed: bool) -> Option<(i32, i32)> {
    match Rails::of_adc_bits(bits, signed) {
        Ok(Rails::Stated { min, max }) => Some((min, max)),
        _ => None,
    }
}

slot::slot_struct! {
    /// The checked ADC front end, made by `at_adc_f32_new`, `at_adc_f32_offset_binary` or
    /// `at_adc_f32_twos_complement`, with its range of codes (stated by the last two, or by
    /// `at_adc_f32_set_range` at start-up). Immutable once made but for its range; place it
    /// anywhere; copy it by assignment; never write its fields. A zeroed one is refused.
    at_adc_f32[AT_ADC_F32_WORDS]
}

impl at_adc_f32 {
    /// The scaling and its range, if made by a constructor of this build.
    pub(crate) fn stage(&self) -> Result<&AdcF32, Refused> {
        self.slot_get()
    }

    /// Stores a checked front end with `range` (`None`: no range stated); on error `self`
    /// is left as it was.
    pub(crate) fn set(
        &mut self,
        scaling: Result<AdcScaling<f32>, ConfigError>,
        range: Option<(i32, i32)>,
    ) -> at_status {
        self.slot_store(scaling.map(|scaling| AdcF32 { scaling, range }))
    }

    /// States the range of codes `min` to `max` (checked by the core's `FrontEndCheck`:
    /// `AT_ERR_ADC_RANGE` unless `min < max`); refused, and `self` unchanged, for an ADC not
    /// made.
    pub(crate) fn set_range(&mut self, min: i32, max: i32) -> at_status {
        let range = Some((min, max));
        match self.stage() {
            Ok(&AdcF32 { scaling, .. }) => {
                self.set(FrontEndCheck::around((), range).map(|_| scaling), range)
            }
            Err(refused) => refused.status(),
        }
    }
}
