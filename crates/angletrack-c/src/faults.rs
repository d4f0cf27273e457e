//! The fault bits of the estimates' `faults` and of `at_chain_state_f32_clear_faults`: the core's
//! [`Faults`](angletrack_core::Faults) bits, and one bit of the C API's own.

use core::ffi::CStr;

/// Loss of signal: a window's RMS amplitude is below the loss-of-signal threshold.
pub const AT_FAULT_LOSS_OF_SIGNAL: u32 = 1;
/// Degradation of signal: a window's RMS amplitude is outside [degradation_low, degradation_high].
pub const AT_FAULT_DEGRADATION_OF_SIGNAL: u32 = 1 << 1;
/// Loss of tracking: a window's mean phase error or its last speed is above its threshold.
pub const AT_FAULT_LOSS_OF_TRACKING: u32 = 1 << 2;
/// The sample was rejected (NaN, infinite, or above the input bound); the observer coasted.
pub const AT_FAULT_BAD_SAMPLE: u32 = 1 << 3;
/// A lock about 180 degrees off was detected (and the angle re-acquired, by default).
pub const AT_FAULT_FALSE_LOCK: u32 = 1 << 4;
/// The online calibration's amplitude ratio is beyond its bound.
pub const AT_FAULT_AMPLITUDE_MISMATCH: u32 = 1 << 5;
/// An offset or the quadrature angle of the online calibration is beyond its bound.
pub const AT_FAULT_OFFSET_OR_QUADRATURE: u32 = 1 << 6;
/// A front-end fault: a stage before the observer flagged the sample (the core's
/// `FrontEndCheck`, `WindingCheck`: clipping against the ADC's stated range, a
/// demodulator's fault, a winding open or shorted), and while the fault invalidates it the
/// observer coasted on its prediction.
pub const AT_FAULT_FRONT_END: u32 = 1 << 7;
/// Not the sensor's: the call's chain or state was NULL, not made by its constructor or
/// another build's (or the chain cannot take the input); nothing was computed and the
/// estimate's other fields are 0.
pub const AT_FAULT_INVALID_ARGUMENT: u32 = 0x8000_0000;

/// The C API's fault bits with their names, in bit order (the core's `Faults::NAMES`,
/// then the C API's own).
pub(crate) const NAMES: [(u32, &CStr); 9] = [
    (AT_FAULT_LOSS_OF_SIGNAL, c"loss of signal"),
    (AT_FAULT_DEGRADATION_OF_SIGNAL, c"degradation of signal"),
    (AT_FAULT_LOSS_OF_TRACKING, c"loss of tracking"),
    (AT_FAULT_BAD_SAMPLE, c"bad sample"),
    (AT_FAULT_FALSE_LOCK, c"false lock"),
    (AT_FAULT_AMPLITUDE_MISMATCH, c"amplitude mismatch"),
    (AT_FAULT_OFFSET_OR_QUADRATURE, c"offset or quadrature"),
    (AT_FAULT_FRONT_END, c"front end"),
    (AT_FAULT_INVALID_ARGUMENT, c"invalid argument"),
];

/// The name of one fault bit, or `"unknown fault"` for anything else (no bit, several).
pub(crate) fn name(bit: u32) -> &'static CStr {
    NAMES
        .iter()
        .find(|(b, _)| *b == bit)
        .map_or(c"unknown fault", |(_, name)| name)
}
