//! The firmware test's Rust references (feature `count-reference`, never in a shipped
//! library), counted by tests/firmware/c/run.sh on the same replayed signal as the C door:
//! the core's `Tracker` of order 3 called as Rust firmware calls it, on the chain and state
//! a C struct holds, without the door's checks; and the same stages composed as a plain
//! `Chain` (its stored calibration and table, then the observer), the Tracker's own cost
//! beside it. Not in the header (the counting image declares them).
#![allow(unsafe_code, missing_docs, clippy::missing_safety_doc)]

use angletrack_core::{
    Chain, ChainState, FixedAngleCorrectionTable, FixedCalibration, FixedGains, FixedState,
};

use crate::chain_fixed::{ChainFixed, StateFixed, at_chain_fixed, at_chain_state_fixed};

/// The same stages composed.
type Composed = Chain<(FixedCalibration, FixedAngleCorrectionTable<256>), FixedGains<3>>;
/// Its state.
type ComposedState = ChainState<((), ()), FixedState<3>>;

/// The chain `chain` holds, read without a check (made by this build, of order 3).
#[inline(always)]
unsafe fn tracker<'a>(chain: *const at_chain_fixed) -> &'a ChainFixed<3> {
    // SAFETY: the caller's contract.
    unsafe { &*(*chain).storage.as_ptr().cast::<ChainFixed<3>>() }
}

/// `Tracker::track` as `at_chain_fixed_track_u16` and `_i16` run it, on the state made by
/// one call of the door.
macro_rules! reference {
    ($($name:ident: $int:ty;)*) => {$(
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            chain: *const at_chain_fixed,
            state: *mut at_chain_state_fixed,
            raw_c: $int,
            raw_s: $int,
        ) {
            // SAFETY: the caller's contract (the state made by this build, of order 3).
            let (chain, state) = unsafe {
                (
                    tracker(chain),
                    &mut *(*state).storage.as_mut_ptr().cast::<StateFixed<3>>(),
                )
            };
            chain.track(state, (raw_c, raw_s));
        }
    )*};
}

reference! {
    at_reference_track_u16: u16;
    at_reference_track_i16: i16;
}

/// Writes to `out` and `state` (words of the caller's, aligned and large enough) the
/// stages of `chain` (a stored calibration and a table, no ADC) composed, and a fresh state.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_reference_composed_new(
    chain: *const at_chain_fixed,
    out: *mut u64,
    state: *mut u64,
) -> bool {
    // SAFETY: the caller's contract.
    let chain = unsafe { tracker(chain) };
    let (Some(calibration), Some(table)) =
        (chain.front_end.calibration(), chain.front_end.correction())
    else {
        return false;
    };
    const { assert!(size_of::<Composed>() <= 800 && size_of::<ComposedState>() <= 160) };
    // SAFETY: the caller's contract: 800 and 160 bytes, aligned for u64 (as both types).
    unsafe {
        out.cast::<Composed>()
            .write(Chain::new((calibration, table), chain.observer));
        state.cast::<ComposedState>().write(ChainState::new());
    }
    true
}

/// `Chain::track` of the composed stages on `int16` samples.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_reference_composed_track_i16(
    chain: *const u64,
    state: *mut u64,
    raw_c: i16,
    raw_s: i16,
) {
    // SAFETY: the caller's contract: written by `at_reference_composed_new`.
    let (chain, state) = unsafe {
        (
            &*chain.cast::<Composed>(),
            &mut *state.cast::<ComposedState>(),
        )
    };
    chain.track(state, (raw_c, raw_s));
}
