//! `at_adc_f32`: the ADC front end (the core's `AdcScaling<f32>`), which makes raw integer
//! samples the observer's input: `y = (raw - mid_scale_counts) / counts_per_unit`.

use core::mem::MaybeUninit;

use angletrack_core::{AdcScaling, ConfigError};

use crate::slot::{self, Refused};
use crate::status::{at_status, status_of_result};

/// The 8-byte words of an `at_adc_f32`'s storage (checked against the Rust type at compile
/// time, on every target).
pub const AT_ADC_F32_WORDS: usize = 2;

/// The checked ADC front end, made by `at_adc_f32_new`, `at_adc_f32_offset_binary` or
/// `at_adc_f32_twos_complement`. Immutable once made; place it anywhere; copy it by
/// assignment; never write its fields. A zeroed one is refused.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct at_adc_f32 {
    /// Private: whether `storage` holds it.
    tag: u32,
    /// Private: the layout of the build that wrote it.
    layout: u32,
    /// Private: the Rust value.
    storage: [MaybeUninit<u64>; AT_ADC_F32_WORDS],
}

slot::slot_struct!(at_adc_f32, AT_ADC_F32_WORDS);

impl at_adc_f32 {
    /// The front end, if made by a constructor of this build.
    pub(crate) fn get(&self) -> Result<&AdcScaling<f32>, Refused> {
        self.slot_get()
    }

    /// Stores a checked front end; on error `self` is left as it was.
    pub(crate) fn set(&mut self, adc: Result<AdcScaling<f32>, ConfigError>) -> at_status {
        if let Ok(adc) = adc {
            self.slot_put(adc);
        }
        status_of_result(adc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::status::{AT_ERR_BITS, AT_OK};

    #[test]
    fn stores_the_checked_front_end() {
        let mut adc = at_adc_f32::ZEROED;
        assert!(adc.get().is_err());
        assert_eq!(adc.set(AdcScaling::offset_binary(40)), AT_ERR_BITS);
        assert!(adc.get().is_err());
        assert_eq!(adc.set(AdcScaling::offset_binary(12)), AT_OK);
        assert_eq!(
            adc.get().map(|a| a.sample(4095u16, 0u16)),
            Ok((2047.0 / 2048.0, -1.0))
        );
    }
}
