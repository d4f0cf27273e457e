//! The firmware test's Rust reference (feature `count-reference`, never in a shipped
//! library): the core's `Tracker` of order 3 called as Rust firmware calls it, on the chain and
//! state a C struct holds, without the door's checks, so that tests/firmware/c/run.sh counts
//! the same chain on the same replayed signal in Rust and through the C door. Not in the
//! header (the counting image declares them).
#![allow(unsafe_code, missing_docs)]

use crate::chain_fixed::{ChainFixed, StateFixed, at_chain_fixed, at_chain_state_fixed};

/// The chain and state `chain` and `state` hold, read without a check.
///
/// # Safety
/// Both made by this build for order 3 (the counting image tracked one sample first).
#[inline(always)]
unsafe fn parts<'a>(
    chain: *const at_chain_fixed,
    state: *mut at_chain_state_fixed,
) -> (&'a ChainFixed<3>, &'a mut StateFixed<3>) {
    // SAFETY: the caller's contract.
    unsafe {
        (
            &*(*chain).storage.as_ptr().cast::<ChainFixed<3>>(),
            &mut *(*state).storage.as_mut_ptr().cast::<StateFixed<3>>(),
        )
    }
}

/// `Tracker::track` on raw counts, as `at_chain_fixed_track_u16` runs it.
///
/// # Safety
/// See `parts`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_reference_track_u16(
    chain: *const at_chain_fixed,
    state: *mut at_chain_state_fixed,
    raw_c: u16,
    raw_s: u16,
) {
    // SAFETY: the caller's contract.
    let (chain, state) = unsafe { parts(chain, state) };
    chain.track(state, (raw_c, raw_s));
}

/// `Tracker::track` on `int16` samples, as `at_chain_fixed_track_i16` runs it.
///
/// # Safety
/// See `parts`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_reference_track_i16(
    chain: *const at_chain_fixed,
    state: *mut at_chain_state_fixed,
    raw_c: i16,
    raw_s: i16,
) {
    // SAFETY: the caller's contract.
    let (chain, state) = unsafe { parts(chain, state) };
    chain.track(state, (raw_c, raw_s));
}
