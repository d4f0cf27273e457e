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
    at_gains_f32,
    at_adc_f32,
    at_chain_f32,
    at_chain_state_f32,
    at_fixed_gains,
    at_chain_fixed,
    at_chain_state_fixed,
    at_demodulator_f32,
    at_demodulator_state_f32
);
