//! The `extern "C"` functions of the float chain's front-end checks: a chain with the
//! winding check (`at_chain_f32_with_winding_check`), a demodulator's pairs taken with their
//! faults (`at_chain_f32_track_demodulated`, `_update_demodulated`), and the front-end
//! faults latched (`at_chain_state_f32_clear_front_end_faults`). Each checks its pointers,
//! turns them into references, and calls the safe code of `chain`. The caller's contract is
//! `ffi`'s.
#![allow(unsafe_code)]

use crate::chain::{at_chain_f32, at_chain_state_f32};
use crate::demodulator::at_demodulated_pair_f32;
use crate::faults::AT_FAULT_INVALID_ARGUMENT;
use crate::ffi_chain::{track_input, update_input};
use crate::observer::at_estimate_f32;
use crate::status::{AT_ERR_NULL_POINTER, at_status};

/// Writes to `out` the chain `chain` with a winding check: a winding open or shorted (one
/// winding reading below a quarter of `nominal_amplitude` where the observer's prediction
/// puts at least half of it, the other agreeing with the prediction) is flagged
/// `AT_FAULT_FRONT_END` (`AT_FRONT_END_FAULT_WINDING`) and coasted through while it holds.
/// `nominal_amplitude` is the windings' peak in the chain's input units after the
/// calibration (1 for a demodulator's pairs; `AT_ERR_NOMINAL_AMPLITUDE` unless finite and
/// positive). `out` unchanged on error.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_chain_f32_with_winding_check(
    chain: *const at_chain_f32,
    nominal_amplitude: f32,
    out: *mut at_chain_f32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (chain.as_ref(), out.as_mut()) } {
        (Some(chain), Some(out)) => out.set_with_winding_check(chain, nominal_amplitude),
        _ => AT_ERR_NULL_POINTER,
    }
}

/// `at_chain_f32_track` on a demodulator's pair (`at_demodulator_f32_push`), with the
/// front-end faults of its window: while one invalidates the pair (loss of excitation, a
/// winding open or shorted) the observer coasts on its prediction instead of using it, and
/// every fault is latched as `AT_FAULT_FRONT_END` (`at_chain_state_f32_clear_front_end_faults`
/// gives the front-end bits). Returns 0, or `AT_FAULT_INVALID_ARGUMENT` (nothing changed)
/// for refused arguments, a chain with an ADC stage among them (the demodulator takes the
/// counts: build the chain without one).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_chain_f32_track_demodulated(
    chain: *const at_chain_f32,
    state: *mut at_chain_state_f32,
    pair: *const at_demodulated_pair_f32,
) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    match unsafe { pair.as_ref() } {
        // SAFETY: the same contract.
        Some(pair) => unsafe { track_input(chain, state, pair) },
        None => AT_FAULT_INVALID_ARGUMENT,
    }
}

/// `at_chain_f32_track_demodulated`, then the estimate, which carries `AT_FAULT_FRONT_END`
/// while the pair has a front-end fault.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_chain_f32_update_demodulated(
    chain: *const at_chain_f32,
    state: *mut at_chain_state_f32,
    pair: *const at_demodulated_pair_f32,
) -> at_estimate_f32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    match unsafe { pair.as_ref() } {
        // SAFETY: the same contract.
        Some(pair) => unsafe { update_input(chain, state, pair) },
        None => at_estimate_f32::INVALID,
    }
}

/// Returns the front-end faults latched in `state` (`AT_FRONT_END_FAULT_*` bits: clipping
/// against the ADC's range, the demodulator's faults, a winding open or shorted) and clears
/// them. 0 for NULL.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_chain_state_f32_clear_front_end_faults(
    state: *mut at_chain_state_f32,
) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    unsafe { state.as_mut() }.map_or(0, at_chain_state_f32::clear_front_end_faults)
}
