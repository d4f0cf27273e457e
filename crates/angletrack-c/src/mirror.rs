//! Plain C mirrors of the core's settings structs (`at_fault_thresholds_f32`,
//! `at_calibration_settings_f32`, `at_demodulator_settings_f32`): `mirror!` writes each
//! struct and its conversions both ways from one list of its fields, each converted by
//! [`Mirror`] (an optional value is 0 when absent, a flag nonzero when set), and of the
//! estimates (`at_estimate_f32`, `at_fixed_estimate`).

use angletrack_core::Faults;

/// A field of a C mirror (`Self`) as the core's field of type `Core`.
pub(crate) trait Mirror<Core> {
    /// The core's value.
    fn to_core(self) -> Core;
    /// The C value of the core's.
    fn from_core(core: Core) -> Self;
}

impl<T> Mirror<T> for T {
    fn to_core(self) -> T {
        self
    }
    fn from_core(core: T) -> T {
        core
    }
}

/// An optional float: 0 when absent.
impl Mirror<Option<f32>> for f32 {
    fn to_core(self) -> Option<f32> {
        (self != 0.0).then_some(self)
    }
    fn from_core(core: Option<f32>) -> f32 {
        core.unwrap_or(0.0)
    }
}

/// A flag: nonzero when set.
impl Mirror<bool> for u32 {
    fn to_core(self) -> bool {
        self != 0
    }
    fn from_core(core: bool) -> u32 {
        u32::from(core)
    }
}

/// Fault bits: the core's flags fit the low 8 bits; higher bits are the C API's own.
impl Mirror<Faults> for u32 {
    fn to_core(self) -> Faults {
        Faults::from_bits_truncate(self as u8)
    }
    fn from_core(core: Faults) -> u32 {
        u32::from(core.bits())
    }
}

/// The C struct `$name` (docs `$doc`) mirroring the core's `$core` field by field (each
/// `c_field: type = core_field`), with `From<$core>` and `to_core`, which assigns the fields
/// onto `$base(&self)` (the core's defaults for the struct's first settings, so that fields
/// the core may add keep their defaults).
macro_rules! mirror {
    (
        $(#[$doc:meta])*
        $name:ident: $core:ty = $base:expr;
        $($(#[$field_doc:meta])* $field:ident: $t:ty = $core_field:ident,)*
    ) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct $name {
            $($(#[$field_doc])* pub $field: $t,)*
        }

        impl From<$core> for $name {
            fn from(core: $core) -> Self {
                Self {
                    $($field: $crate::mirror::Mirror::from_core(core.$core_field),)*
                }
            }
        }

        impl $name {
            /// The core's settings, field by field.
            #[allow(dead_code, reason = "the float estimate is not converted back")]
            pub(crate) fn to_core(self) -> $core {
                let mut core: $core = ($base)(&self);
                $(core.$core_field = $crate::mirror::Mirror::to_core(self.$field);)*
                core
            }
        }
    };
}
pub(crate) use mirror;
