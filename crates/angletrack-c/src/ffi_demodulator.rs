//! The `extern "C"` functions of the synchronous demodulator (`at_demodulator_*`): each
//! checks its pointers, turns them into references, and calls the safe code of
//! `demodulator` (or the core). The caller's contract is `ffi`'s.
#![allow(unsafe_code)]

use angletrack_core::DemodulatorSettings;

use crate::chain::{AnyChain, at_chain_f32};
use crate::demodulator::{
    at_demodulated_pair_f32, at_demodulator_f32, at_demodulator_settings_f32,
    at_demodulator_state_f32, with_demodulator,
};
use crate::faults::AT_FAULT_INVALID_ARGUMENT;
use crate::status::{AT_ERR_NULL_POINTER, at_status, status_of_result};

/// The demodulator's settings for a carrier of `carrier_hz` (Hz) and amplitude
/// `carrier_amplitude_counts` (counts, peak) at an ADC whose codes run from `adc_min_code` to
/// `adc_max_code`, with the core's defaults for the rest (clip margin 1/256 of the range,
/// loss of excitation below 0.25, phase drift bound 44 degrees, expected delay 0, delay
/// tracking factor 0.01, start-up over 16 periods).
#[unsafe(no_mangle)]
pub extern "C" fn at_demodulator_settings_f32_new(
    carrier_hz: f32,
    carrier_amplitude_counts: f32,
    adc_min_code: f32,
    adc_max_code: f32,
) -> at_demodulator_settings_f32 {
    DemodulatorSettings::new(
        carrier_hz,
        carrier_amplitude_counts,
        adc_min_code,
        adc_max_code,
    )
    .into()
}

/// Checks `settings` for `samples_per_period` ADC samples per carrier period (8, 16 or 32:
/// `AT_ERR_SAMPLES_PER_PERIOD` otherwise) and writes the demodulator to `out` (unchanged on
/// error; `AT_ERR_CARRIER_HZ`, `AT_ERR_ADC_RANGE`, ... name the refused setting).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_demodulator_f32_new(
    settings: *const at_demodulator_settings_f32,
    samples_per_period: u32,
    out: *mut at_demodulator_f32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (settings.as_ref(), out.as_mut()) } {
        (Some(settings), Some(out)) => out.set(settings, samples_per_period),
        _ => AT_ERR_NULL_POINTER,
    }
}

/// Checks that `chain` runs at the demodulator's pair rate: its observer's sample period is
/// the carrier period (to a relative 1e-4), else `AT_ERR_SAMPLE_PERIOD_S`.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_demodulator_f32_check_chain(
    demodulator: *const at_demodulator_f32,
    chain: *const at_chain_f32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    let (Some(demodulator), Some(chain)) = (unsafe { (demodulator.as_ref(), chain.as_ref()) })
    else {
        return AT_ERR_NULL_POINTER;
    };
    let (demodulator, chain) = match (demodulator.get(), chain.get()) {
        (Ok(d), Ok(c)) => (d, c),
        (Err(refused), _) | (_, Err(refused)) => return refused.status(),
    };
    with_demodulator!(demodulator, |d| match chain {
        AnyChain::Two(c) => status_of_result(d.check_gains(&c.chain.observer)),
        AnyChain::Three(c) => status_of_result(d.check_gains(&c.chain.observer)),
    })
}

/// One ADC sample of each winding (`raw_c` of the cosine winding, `raw_s` of the sine
/// winding, in counts), taken at the excitation phase `2 pi k / N` of the `k`-th sample of
/// the carrier period. Once per period (after the start-up delay estimate) writes a pair to
/// `out` and returns 1; else returns 0 (`out` untouched). Refused arguments (NULL, a
/// demodulator not made, a struct of another build): `AT_FAULT_INVALID_ARGUMENT`, nothing
/// changed. Feed the pair's `y_c`, `y_s` to a chain whose gains run at the carrier period
/// (`at_demodulator_f32_check_chain`).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_demodulator_f32_push(
    demodulator: *const at_demodulator_f32,
    state: *mut at_demodulator_state_f32,
    raw_c: f32,
    raw_s: f32,
    out: *mut at_demodulated_pair_f32,
) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    let (Some(demodulator), Some(state), Some(out)) =
        (unsafe { (demodulator.as_ref(), state.as_mut(), out.as_mut()) })
    else {
        return AT_FAULT_INVALID_ARGUMENT;
    };
    let (Ok(demodulator), Ok(state)) = (demodulator.get(), state.get_mut()) else {
        return AT_FAULT_INVALID_ARGUMENT;
    };
    match with_demodulator!(demodulator, |d| d.push(state, raw_c, raw_s)) {
        Some(pair) => {
            *out = pair.into();
            1
        }
        None => 0,
    }
}

/// Makes `state` fresh: its next sample is the first of a carrier period, the delay not yet
/// measured. NULL is ignored.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_demodulator_state_f32_reset(state: *mut at_demodulator_state_f32) {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    if let Some(state) = unsafe { state.as_mut() } {
        *state = at_demodulator_state_f32::FRESH;
    }
}

/// Returns the front-end faults latched in `state` (`AT_FRONT_END_FAULT_*` bits) and clears
/// them. 0 for NULL (or another build's state).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_demodulator_state_f32_clear_faults(
    state: *mut at_demodulator_state_f32,
) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    unsafe { state.as_mut() }
        .and_then(|s| s.get_mut().ok())
        .map_or(0, |s| u32::from(s.clear_faults().bits()))
}
