//! The `extern "C"` functions of the float signal chain (`at_chain_f32_*`,
//! `at_chain_state_f32_*`, `at_calibration_settings_f32_default`): each checks its
//! pointers, turns them into references, and calls the safe code of `chain` (or the core).
//! The caller's contract is `ffi`'s.
#![allow(unsafe_code)]

use angletrack_core::CalibrationSettings;

use crate::adc::at_adc_f32;
use crate::calibration::{
    AT_CALIBRATION_FINDING_CENTRE, at_calibration_settings_f32, at_sensor_calibration_f32,
    calibration_status, mode_of, set_mode_of,
};
use crate::chain::{
    Stages, at_angle_correction_f32, at_chain_f32, at_chain_state_f32, at_estimate_f32,
};
use crate::demodulator::at_demodulated_pair_f32;
use crate::door::per_sample;
use crate::ffi::extern_c;
use crate::gains::at_gains_f32;
use crate::slot::Refused;
use crate::status::{AT_ERR_NULL_POINTER, AT_OK, at_status};
use crate::table::at_angle_correction_table_f32;

/// The online calibration's default settings (the core's `CalibrationSettings::default`).
#[unsafe(no_mangle)]
pub extern "C" fn at_calibration_settings_f32_default() -> at_calibration_settings_f32 {
    CalibrationSettings::default().into()
}

extern_c! {
    /// Builds a signal chain into `out`: the observer `gains` (required) after the optional
    /// stages, each NULL when absent, in this order: the ADC front end `adc` (then the chain
    /// takes counts: `at_chain_f32_track_u16`, ...; with its range stated, a sample with a
    /// channel at or beyond a rail is flagged `AT_FAULT_FRONT_END` and one with both there is
    /// coasted through: `at_adc_f32_set_range`), the front-end faults a demodulator gave its
    /// pairs (`at_chain_f32_track_demodulated`: the observer coasts through a loss of
    /// excitation), one calibration stage (a stored calibration
    /// `stored`, applied to every sample, or the online calibration with its `settings`,
    /// learning per channel in `at_chain_state_f32`; not both: `AT_ERR_STAGES`), and one angle
    /// correction (the harmonic `correction` or its `table`, the same cost whatever the error's
    /// shape; not both: `AT_ERR_STAGES`). Every stage is checked (`AT_ERR_*` naming the
    /// refused parameter, `AT_ERR_ANGLE_CORRECTION`, ...; `out` unchanged on error); the stages
    /// are copied, so they need not outlive the call.
    fn at_chain_f32_new(gains: *const at_gains_f32, adc: Option<&at_adc_f32>,
        stored: Option<&at_sensor_calibration_f32>, settings: Option<&at_calibration_settings_f32>,
        correction: Option<&at_angle_correction_f32>, table: Option<&at_angle_correction_table_f32>,
        out: *mut at_chain_f32) -> at_status
        = match adc.map(at_adc_f32::stage).transpose() {
            Ok(adc) => {
                out.set(gains, Stages { adc, stored, online: settings, correction, table })
            }
            Err(refused) => refused.status(),
        }; else AT_ERR_NULL_POINTER;
    /// The estimate `state` holds for `chain` (its last sample's; the observer's faults, the
    /// stages' latched in the state). Refused arguments: `AT_FAULT_INVALID_ARGUMENT`.
    fn at_chain_f32_estimate(chain: *const at_chain_f32, state: *const at_chain_state_f32
    ) -> at_estimate_f32
        = chain.estimate(state); else at_estimate_f32::invalid();
    /// Makes `state` fresh: the observer initialises itself from its next sample, the online
    /// calibration is off with nothing learned. NULL is ignored.
    fn at_chain_state_f32_reset(state: *mut at_chain_state_f32)
        = *state = at_chain_state_f32::FRESH; else ();
    /// Returns the faults latched in `state` (the observer's and the stages', `AT_FAULT_*`
    /// bits) and clears them. 0 for NULL.
    fn at_chain_state_f32_clear_faults(state: *mut at_chain_state_f32) -> u32
        = state.clear_faults(); else 0;
    /// Sets the mode of the online calibration in `state`: `AT_CALIBRATION_LEARNING`,
    /// `_FROZEN` or `_OFF` (the calibration is kept). Effective in a chain with the online
    /// calibration stage.
    fn at_chain_state_f32_set_calibration_mode(state: *mut at_chain_state_f32, mode: u32
        ) -> at_status
        = state.calibrator().map_or_else(Refused::status, |c| set_mode_of(c, mode));
        else AT_ERR_NULL_POINTER;
    /// The mode of the online calibration in `state` (`AT_CALIBRATION_*`; off for NULL).
    fn at_chain_state_f32_calibration_mode(state: *const at_chain_state_f32) -> u32
        = state.calibrator_value().map_or(0, |c| mode_of(&c)); else 0;
    /// Loads a stored calibration into the online calibration of `state` (checked; unchanged on
    /// error), frozen: it corrects and learns nothing until set to learn, continuing from it.
    fn at_chain_state_f32_load_calibration(state: *mut at_chain_state_f32,
        stored: *const at_sensor_calibration_f32) -> at_status
        = state.load_calibration(stored); else AT_ERR_NULL_POINTER;
    /// Writes the calibration the online calibration of `state` applies (to store in flash) to
    /// `out`.
    fn at_chain_state_f32_calibration(state: *const at_chain_state_f32,
        out: *mut at_sensor_calibration_f32) -> at_status
        = state.calibrator_value().map_or_else(Refused::status, |c| {
            *out = c.calibration().into();
            AT_OK
        }); else AT_ERR_NULL_POINTER;
    /// The turns the online calibration of `state` has learned since started or loaded; 0 for
    /// NULL.
    fn at_chain_state_f32_turns_learned(state: *const at_chain_state_f32) -> u32
        = state.calibrator_value().map_or(0, |c| c.turns_learned()); else 0;
    /// Where the online calibration of `state` stands: `AT_CALIBRATION_FINDING_CENTRE`,
    /// `AT_CALIBRATION_CENTRED` or `AT_CALIBRATION_STALLED`; `AT_CALIBRATION_FINDING_CENTRE`
    /// for NULL or another build's state.
    fn at_chain_state_f32_calibration_status(state: *const at_chain_state_f32) -> u32
        = state.calibrator_value().map_or(AT_CALIBRATION_FINDING_CENTRE, |c| {
            calibration_status(&c)
        });
        else AT_CALIBRATION_FINDING_CENTRE;
    /// Writes to `out` the chain `chain` with a winding check: a winding open or shorted (one
    /// winding reading below a quarter of `nominal_amplitude` where the observer's prediction
    /// puts at least half of it, the other agreeing with the prediction) is flagged
    /// `AT_FAULT_FRONT_END` (`AT_FRONT_END_FAULT_WINDING`) and coasted through while it holds.
    /// `nominal_amplitude` is the windings' peak in the chain's input units after the
    /// calibration (1 for a demodulator's pairs; `AT_ERR_NOMINAL_AMPLITUDE` unless finite and
    /// positive). `out` unchanged on error.
    fn at_chain_f32_with_winding_check(chain: *const at_chain_f32, nominal_amplitude: f32,
        out: *mut at_chain_f32) -> at_status
        = out.set_with_winding_check(chain, nominal_amplitude); else AT_ERR_NULL_POINTER;
    /// Returns the front-end faults latched in `state` (`AT_FRONT_END_FAULT_*` bits: clipping
    /// against the ADC's range, the demodulator's faults, a winding open or shorted) and clears
    /// them. 0 for NULL.
    fn at_chain_state_f32_clear_front_end_faults(state: *mut at_chain_state_f32) -> u32
        = state.clear_front_end_faults(); else 0;
}

per_sample! {
    at_chain_f32, at_chain_state_f32;
    /// One sample `(y_c, y_s)` through the chain's stages and observer, the state only (the
    /// cheapest per-sample call; `at_chain_f32_estimate` reads the estimate on demand, the
    /// stages' faults are latched in the state). Returns 0, or `AT_FAULT_INVALID_ARGUMENT`
    /// (nothing changed) for a NULL pointer, a chain not made or a struct of another build. A
    /// chain with an ADC stage takes `y_c`, `y_s` as already scaled (the ADC is for counts).
    at_chain_f32_track(y_c: f32, y_s: f32) -> u32 = track((y_c, y_s));
    /// `at_chain_f32_track`, then the estimate, which carries the stages' faults.
    at_chain_f32_update(y_c: f32, y_s: f32) -> at_estimate_f32 = update((y_c, y_s));
    /// `at_chain_f32_track` on raw `i16` ADC counts, through the chain's ADC stage
    /// (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
    at_chain_f32_track_i16(raw_c: i16, raw_s: i16) -> u32 = track((raw_c, raw_s));
    /// `at_chain_f32_update` on raw `i16` ADC counts, through the chain's ADC stage
    /// (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
    at_chain_f32_update_i16(raw_c: i16, raw_s: i16) -> at_estimate_f32 = update((raw_c, raw_s));
    /// `at_chain_f32_track` on raw `u16` ADC counts, through the chain's ADC stage
    /// (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
    at_chain_f32_track_u16(raw_c: u16, raw_s: u16) -> u32 = track((raw_c, raw_s));
    /// `at_chain_f32_update` on raw `u16` ADC counts, through the chain's ADC stage
    /// (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
    at_chain_f32_update_u16(raw_c: u16, raw_s: u16) -> at_estimate_f32 = update((raw_c, raw_s));
    /// `at_chain_f32_track` on raw `i32` ADC counts, through the chain's ADC stage
    /// (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
    at_chain_f32_track_i32(raw_c: i32, raw_s: i32) -> u32 = track((raw_c, raw_s));
    /// `at_chain_f32_update` on raw `i32` ADC counts, through the chain's ADC stage
    /// (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
    at_chain_f32_update_i32(raw_c: i32, raw_s: i32) -> at_estimate_f32 = update((raw_c, raw_s));
    /// `at_chain_f32_track` on a demodulator's pair (`at_demodulator_f32_push`), with the
    /// front-end faults of its window: while one invalidates the pair (loss of excitation, a
    /// winding open or shorted) the observer coasts on its prediction instead of using it, and
    /// every fault is latched as `AT_FAULT_FRONT_END` (`at_chain_state_f32_clear_front_end_faults`
    /// gives the front-end bits). Returns 0, or `AT_FAULT_INVALID_ARGUMENT` (nothing changed)
    /// for refused arguments, a chain with an ADC stage among them (the demodulator takes the
    /// counts: build the chain without one).
    at_chain_f32_track_demodulated(pair: *const at_demodulated_pair_f32) -> u32 = track(pair);
    /// `at_chain_f32_track_demodulated`, then the estimate, which carries `AT_FAULT_FRONT_END`
    /// while the pair has a front-end fault.
    at_chain_f32_update_demodulated(pair: *const at_demodulated_pair_f32) -> at_estimate_f32
        = update(pair);
}
