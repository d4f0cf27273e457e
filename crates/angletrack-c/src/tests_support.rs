//! Test access to the private words of the C API's structs: a test makes a struct of
//! another build or holding another type, and checks that a refused call left one as it
//! was.

use crate::*;

/// The private tag and layout words of a C struct.
pub(crate) trait Words {
    /// The tag.
    fn clone_tag(&self) -> u32;
    /// Writes the tag (a struct holding another type).
    fn set_tag_for_test(&mut self, tag: u32);
    /// Writes the layout word (a struct of another build).
    fn set_layout_for_test(&mut self, layout: u32);
}

/// [`Words`] for each struct.
macro_rules! words {
    ($($t:ty),*) => {$(
        impl Words for $t {
            fn clone_tag(&self) -> u32 {
                self.tag
            }
            fn set_tag_for_test(&mut self, tag: u32) {
                self.tag = tag;
            }
            fn set_layout_for_test(&mut self, layout: u32) {
                self.layout = layout;
            }
        }
    )*};
}

words!(
    at_adc_f32,
    at_chain_f32,
    at_chain_state_f32,
    at_chain_fixed,
    at_chain_state_fixed,
    at_demodulator_f32,
    at_demodulator_state_f32
);

impl at_gains_f32 {
    /// All zero, as C static memory holds (refused by the chain: order 0).
    pub(crate) const ZEROED: Self = Self {
        gains: [0.0; 3],
        order: 0,
        sample_period_s: 0.0,
        thresholds: at_fault_thresholds_f32 {
            nominal_amplitude: 0.0,
            max_input_amplitude: 0.0,
            loss_of_signal: 0.0,
            degradation_low: 0.0,
            degradation_high: 0.0,
            loss_of_tracking: 0.0,
            max_speed_rad_s: 0.0,
            filter_factor: 0.0,
            false_lock: 0.0,
            monitor: 0,
            re_acquire: 0,
            magnitude_tolerance: 0.0,
            tracking_error: 0.0,
        },
    };
}

impl at_fixed_gains {
    /// All zero, as C static memory holds (refused by the chain: order 0).
    pub(crate) const ZEROED: Self = Self {
        multiplier: [0; 3],
        order: 0,
        acceleration_shift: 0,
        sample_period_s: 0.0,
    };
}

/// The layout word a build of the layout version `version`, otherwise this one, writes in
/// a C struct of `size` bytes: for tests that make a struct of the previous version.
pub(crate) const fn layout_of_version(version: u32, size: usize) -> u32 {
    crate::slot::hash(crate::slot::build_of(version), size as u32) | 1
}
