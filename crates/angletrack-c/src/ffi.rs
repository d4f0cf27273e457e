//! The `extern "C"` functions: each checks its pointers (NULL gives an error status, or
//! `AT_FAULT_INVALID_ARGUMENT` from an update, never undefined behaviour), turns them into
//! references, and calls the safe code of the other modules.
//!
//! The contract every function states in its `# Safety` section, the C caller's part:
//! each non-NULL pointer points to a live object of its type (a `const float *gains` to
//! `order` floats), which nothing else reads or writes during the call (no aliasing between
//! the arguments, no concurrent call on the same state from an interrupt), and each struct
//! was zeroed, made by its constructor, or copied whole from one that was.
#![allow(unsafe_code)]

use core::ffi::c_char;

use angletrack_core::{AdcScaling, ConfigError};

use crate::adc::{at_adc_f32, codes_of};
use crate::faults;
use crate::gains::{at_fault_thresholds_f32, at_gains_f32};
use crate::slot::AT_LAYOUT_VERSION;
use crate::status::{
    AT_ERR_NULL_POINTER, AT_ERR_ORDER, AT_OK, at_status, message, status_of_result,
};

/// An argument of an `extern "C"` function as its body takes it: a pointer as a reference
/// (`None` for NULL), a value as it is.
pub(crate) trait Checked<'a> {
    /// The argument as the body takes it.
    type Checked;
    /// The argument; `None` for NULL.
    ///
    /// # Safety
    /// A pointer is NULL or valid for its access for `'a` (the header's contract).
    unsafe fn checked(self) -> Option<Self::Checked>;
}

impl<'a, T: 'a> Checked<'a> for *const T {
    type Checked = &'a T;
    unsafe fn checked(self) -> Option<&'a T> {
        // SAFETY: the caller's contract; NULL is checked by `as_ref`.
        unsafe { self.as_ref() }
    }
}

/// An optional pointer (a stage absent when NULL), passed as it is.
impl<'a, T> Checked<'a> for Option<&'a T> {
    type Checked = Self;
    unsafe fn checked(self) -> Option<Self> {
        Some(self)
    }
}

impl<'a, T: 'a> Checked<'a> for *mut T {
    type Checked = &'a mut T;
    unsafe fn checked(self) -> Option<&'a mut T> {
        // SAFETY: the caller's contract; NULL is checked by `as_mut`.
        unsafe { self.as_mut() }
    }
}

/// [`Checked`] for the value types the `extern "C"` functions take.
macro_rules! values {
    ($($t:ty),*) => {$(
        impl Checked<'_> for $t {
            type Checked = Self;
            unsafe fn checked(self) -> Option<Self> {
                Some(self)
            }
        }
    )*};
}

values!(i32, u32, f32, f64, usize);

/// `extern "C"` functions whose pointer arguments are all required: each
/// `fn name(args) -> ret = body; else null;` returns `null` if a pointer is NULL, else
/// `body` with every pointer argument a reference of the same name. The caller's contract
/// is the header's (this module's).
macro_rules! extern_c {
    ($(
        $(#[$doc:meta])*
        fn $name:ident($($arg:ident: $t:ty),*) $(-> $ret:ty)? = $body:expr; else $null:expr;
    )*) => {$(
        $(#[$doc])*
        ///
        /// # Safety
        /// See the header's introduction.
        #[unsafe(no_mangle)]
        #[allow(clippy::unused_unit, reason = "`else ()` of the functions that return nothing")]
        pub unsafe extern "C" fn $name($($arg: $t),*) $(-> $ret)? {
            // SAFETY: the caller's contract; NULL is checked by `checked`.
            let ($(Some($arg),)*) = (unsafe { ($($crate::ffi::Checked::checked($arg),)*) }) else {
                return $null;
            };
            $body
        }
    )*};
}
pub(crate) use extern_c;

/// The body of the gains' constructors: `out` and the `order` values at `values` checked,
/// then `make` of them written to `out` (unchanged on error).
///
/// # Safety
/// `values` is NULL or points to `order` values, `out` is NULL or valid for writes (the
/// header's contract).
pub(crate) unsafe fn construct<V, T>(
    values: *const V,
    order: usize,
    out: *mut T,
    make: impl FnOnce(&[V]) -> Result<T, at_status>,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    let Some(out) = (unsafe { out.as_mut() }) else {
        return AT_ERR_NULL_POINTER;
    };
    if values.is_null() {
        return AT_ERR_NULL_POINTER;
    }
    if !(order == 2 || order == 3) {
        return AT_ERR_ORDER;
    }
    // SAFETY: `values` is not NULL and points to `order` values (the caller's contract);
    // `order` is 2 or 3, so the slice is small.
    let values = unsafe { core::slice::from_raw_parts(values, order) };
    make(values).map_or_else(
        |status| status,
        |value| {
            *out = value;
            AT_OK
        },
    )
}

/// Writes `result` to `out` (unchanged on error); its status.
pub(crate) fn write<T>(result: Result<T, ConfigError>, out: &mut T) -> at_status {
    status_of_result(result.map(|value| *out = value))
}

/// The default fault thresholds for signals of amplitude `nominal_amplitude` (input units:
/// 1 for samples in units of full scale, as an ADC stage of `at_adc_f32_offset_binary`
/// gives them).
#[unsafe(no_mangle)]
pub extern "C" fn at_fault_thresholds_f32_for_amplitude(
    nominal_amplitude: f32,
) -> at_fault_thresholds_f32 {
    at_fault_thresholds_f32::for_amplitude(nominal_amplitude)
}

/// The C structs' layout version of the library (`AT_LAYOUT_VERSION` of the header it was
/// built with): a firmware compares it with the header's at start-up. Every struct also
/// carries its build's layout beside its tag, so that one written by another build is
/// refused (`AT_ERR_OTHER_BUILD`) rather than read.
#[unsafe(no_mangle)]
pub extern "C" fn at_layout_version() -> u32 {
    AT_LAYOUT_VERSION
}

/// The text of a status (static, NUL-terminated): the name of the refused parameter as the
/// Rust core names it (`"gains[2] (l3)"`, `"sample_period_s"`, ...), or what went wrong.
#[unsafe(no_mangle)]
pub extern "C" fn at_status_message(status: at_status) -> *const c_char {
    message(status).as_ptr()
}

/// The name of one `AT_FAULT_*` bit (static, NUL-terminated: `"loss of signal"`, ...), or
/// `"unknown fault"`.
#[unsafe(no_mangle)]
pub extern "C" fn at_fault_name(bit: u32) -> *const c_char {
    faults::name(bit).as_ptr()
}

/// Checks `order` (2 or 3) discrete gains `gains` (l1, l2[, l3], dimensionless, as
/// `angletrack design --format c` writes them) and the sample period `sample_period_s` (s),
/// and writes them, with the core's default fault thresholds, to the plain `out`.
/// Returns `AT_OK`, or the status naming the refused parameter (`AT_ERR_GAINS_2` for an
/// unstable `l3`, ...); `out` is unchanged on error.
///
/// # Safety
/// `gains` points to `order` floats; see the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_gains_f32_new(
    gains: *const f32,
    order: usize,
    sample_period_s: f32,
    out: *mut at_gains_f32,
) -> at_status {
    // SAFETY: the same contract.
    unsafe { construct(gains, order, out, |g| at_gains_f32::of(g, sample_period_s)) }
}

extern_c! {
    /// Writes to `out` an ADC front end removing `mid_scale_counts` (the reading of a zero
    /// signal, at most 2^30 in magnitude) and dividing by `counts_per_unit` (positive), with no
    /// range of codes stated (`at_adc_f32_set_range` states it; without it a chain measures
    /// the rails as the extremes held flat).
    fn at_adc_f32_new(mid_scale_counts: i32, counts_per_unit: f32, out: *mut at_adc_f32
        ) -> at_status
        = out.set(AdcScaling::new(mid_scale_counts, counts_per_unit), None);
        else AT_ERR_NULL_POINTER;
    /// Writes to `out` the front end of an unsigned (offset binary) ADC of `bits` bits (2 to
    /// 31): samples in units of full scale (+-1), its range of codes stated (0 to
    /// `2^bits - 1`: a chain flags clipping at them, `at_adc_f32_set_range`).
    fn at_adc_f32_offset_binary(bits: u32, out: *mut at_adc_f32) -> at_status
        = out.set(AdcScaling::offset_binary(bits), codes_of(bits, false)); else AT_ERR_NULL_POINTER;
    /// Writes to `out` the front end of a signed (two's complement) ADC of `bits` bits (2 to
    /// 32): samples in units of full scale (+-1), its range of codes stated (`-2^(bits-1)` to
    /// `2^(bits-1) - 1`: a chain flags clipping at them, `at_adc_f32_set_range`).
    fn at_adc_f32_twos_complement(bits: u32, out: *mut at_adc_f32) -> at_status
        = out.set(AdcScaling::twos_complement(bits), codes_of(bits, true));
        else AT_ERR_NULL_POINTER;
    /// States the range of codes of the ADC `adc`: its lowest `min_counts` and highest
    /// `max_counts` (`AT_ERR_ADC_RANGE` unless `min_counts < max_counts`; `adc` unchanged on
    /// error). A chain with this ADC (`at_chain_f32_new`) flags a sample with a channel at or
    /// beyond a rail `AT_FAULT_FRONT_END` (`AT_FRONT_END_FAULT_CLIPPING`), and coasts on its
    /// prediction through one with both channels there. Without a stated range the chain
    /// measures the rails on the counts as they come (the core's `HeldRailCheck`: an extreme a
    /// channel holds for 4 consecutive samples while the other moves, the samples piled up
    /// there, on a signal spanning both sides of mid-scale), a weaker test.
    fn at_adc_f32_set_range(adc: *mut at_adc_f32, min_counts: i32, max_counts: i32) -> at_status
        = adc.set_range(min_counts, max_counts); else AT_ERR_NULL_POINTER;
}
