//! The `extern "C"` functions of the synchronous demodulator (`at_demodulator_*`): each
//! checks its pointers, turns them into references, and calls the safe code of
//! `demodulator` (or the core). The caller's contract is `ffi`'s.
#![allow(unsafe_code)]

use angletrack_core::DemodulatorSettings;

use crate::chain::at_chain_f32;
use crate::demodulator::{
    at_demodulated_pair_f32, at_demodulator_f32, at_demodulator_settings_f32,
    at_demodulator_state_f32,
};
use crate::faults::AT_FAULT_INVALID_ARGUMENT;
use crate::ffi::extern_c;
use crate::status::{AT_ERR_NULL_POINTER, at_status};

/// The demodulator's settings for a carrier of `carrier_hz` (Hz) sampled at `adc_rate_hz`
/// (Hz, at least 4 times the carrier, any ratio) with amplitude `carrier_amplitude_counts`
/// (counts, peak) at an ADC whose codes run from `adc_min_code` to `adc_max_code`, with the
/// core's defaults for the rest (clip margin 1/256 of the range, loss of excitation below
/// 0.25, weak excitation below 0.7, phase drift bound 44 degrees, expected delay 0, carrier
/// loop bandwidth 0.3, carrier error up to 3 %, start-up over 24 periods).
#[unsafe(no_mangle)]
pub extern "C" fn at_demodulator_settings_f32_new(
    carrier_hz: f32,
    adc_rate_hz: f32,
    carrier_amplitude_counts: f32,
    adc_min_code: f32,
    adc_max_code: f32,
) -> at_demodulator_settings_f32 {
    DemodulatorSettings::new(
        carrier_hz,
        adc_rate_hz,
        carrier_amplitude_counts,
        adc_min_code,
        adc_max_code,
    )
    .into()
}

extern_c! {
    /// Checks `settings` and writes the demodulator to `out` (unchanged on error;
    /// `AT_ERR_CARRIER_HZ`, `AT_ERR_ADC_RATE_HZ`, `AT_ERR_ADC_RANGE`, ... name the refused
    /// setting).
    fn at_demodulator_f32_new(settings: *const at_demodulator_settings_f32,
        out: *mut at_demodulator_f32) -> at_status
        = out.set(settings); else AT_ERR_NULL_POINTER;
    /// Checks that `chain` runs at the demodulator's pair rate: its observer's sample period is
    /// the declared carrier period (to a relative 1e-4), else `AT_ERR_SAMPLE_PERIOD_S`.
    fn at_demodulator_f32_check_chain(demodulator: *const at_demodulator_f32,
        chain: *const at_chain_f32) -> at_status
        = demodulator.check_chain(chain); else AT_ERR_NULL_POINTER;
    /// One ADC sample of each winding (`raw_c` of the cosine winding, `raw_s` of the sine
    /// winding, in counts). Once per tracked carrier period (after the start-up) writes a pair to
    /// `out` and returns 1; else returns 0 (`out` untouched). Refused arguments (NULL, a
    /// demodulator not made, a struct of another build): `AT_FAULT_INVALID_ARGUMENT`, nothing
    /// changed. Feed the pair's `y_c`, `y_s` to a chain whose gains run at the declared carrier
    /// period (`at_demodulator_f32_check_chain`).
    fn at_demodulator_f32_push(demodulator: *const at_demodulator_f32,
        state: *mut at_demodulator_state_f32, raw_c: f32, raw_s: f32,
        out: *mut at_demodulated_pair_f32) -> u32
        = demodulator.push_to(state, raw_c, raw_s, None, out); else AT_FAULT_INVALID_ARGUMENT;
    /// `at_demodulator_f32_push` with the excitation's sample taken at the same instant (any
    /// offset and amplitude): the carrier's half-turn ambiguity is then resolved from it. Push
    /// all samples of a run with it or all without.
    fn at_demodulator_f32_push_with_excitation(demodulator: *const at_demodulator_f32,
        state: *mut at_demodulator_state_f32, raw_c: f32, raw_s: f32, excitation: f32,
        out: *mut at_demodulated_pair_f32) -> u32
        = demodulator.push_to(state, raw_c, raw_s, Some(excitation), out);
        else AT_FAULT_INVALID_ARGUMENT;
    /// The carrier delay the demodulator chose (rad, in [-pi, pi)): with the excitation pushed,
    /// the windings' carrier after it; without, after a carrier of phase 0 at the first sample,
    /// as resolved at the end of the start-up around `expected_delay_rad`. The other half turn
    /// gives the same windings with the shaft half a turn further. NaN for NULL, another build's
    /// state or before the start-up's end.
    fn at_demodulator_state_f32_carrier_delay_rad(state: *mut at_demodulator_state_f32) -> f32
        = state.get_mut().ok().filter(|s| s.is_delay_ready())
            .map_or(f32::NAN, |s| s.carrier_delay_rad());
        else f32::NAN;
    /// Makes `state` fresh: its next sample is the first of a carrier period, the delay not yet
    /// measured. NULL is ignored.
    fn at_demodulator_state_f32_reset(state: *mut at_demodulator_state_f32)
        = *state = at_demodulator_state_f32::FRESH; else ();
    /// Returns the front-end faults latched in `state` (`AT_FRONT_END_FAULT_*` bits) and clears
    /// them. 0 for NULL (or another build's state).
    fn at_demodulator_state_f32_clear_faults(state: *mut at_demodulator_state_f32) -> u32
        = state.get_mut().map_or(0, |s| u32::from(s.clear_faults().bits())); else 0;
}
