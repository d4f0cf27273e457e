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

use angletrack_core::{AdcSample, AdcScaling};

use crate::adc::{at_adc_f32, codes_of};
use crate::calibration::{
    AT_CALIBRATION_FINDING_CENTRE, at_calibrator_f32, at_sensor_calibration_f32, status_of,
};
use crate::faults;
use crate::gains::{at_fault_thresholds_f32, at_gains_f32, with_gains};
use crate::observer::{Calibrated, Counts, Signals, at_estimate_f32, at_state_f32, run};
use crate::slot::AT_LAYOUT_VERSION;
use crate::status::{AT_ERR_NULL_POINTER, AT_ERR_ORDER, AT_OK, at_status, message_ptr};

/// Checks `order` (2 or 3) discrete gains `gains` (l1, l2[, l3], dimensionless, as
/// `angletrack design --format c` writes them) and the sample period `sample_period_s` (s),
/// and writes the observer's configuration, with the default fault thresholds, to `out`.
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
    // SAFETY: the caller's contract (module documentation); NULL is checked by `as_mut`.
    let Some(out) = (unsafe { out.as_mut() }) else {
        return AT_ERR_NULL_POINTER;
    };
    if gains.is_null() {
        return AT_ERR_NULL_POINTER;
    }
    if !(order == 2 || order == 3) {
        return AT_ERR_ORDER;
    }
    // SAFETY: `gains` is not NULL and points to `order` floats (the caller's contract);
    // `order` is 2 or 3, so the slice is small and its length cannot overflow.
    let gains = unsafe { core::slice::from_raw_parts(gains, order) };
    out.set(gains, sample_period_s)
}

/// The order (2 or 3) of gains made by `at_gains_f32_new`; 0 for NULL or gains not made.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_gains_f32_order(gains: *const at_gains_f32) -> usize {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    let gains = unsafe { gains.as_ref() };
    gains
        .and_then(|g| g.get().ok())
        .map_or(0, |any| with_gains!(any, |g| g.order()))
}

/// The default fault thresholds for signals of amplitude `nominal_amplitude` (input units:
/// 1 for samples in units of full scale, as `at_update_f32_adc_*` gives them).
#[unsafe(no_mangle)]
pub extern "C" fn at_fault_thresholds_f32_for_amplitude(
    nominal_amplitude: f32,
) -> at_fault_thresholds_f32 {
    at_fault_thresholds_f32::for_amplitude(nominal_amplitude)
}

/// Replaces the fault thresholds of `gains` (checked: `AT_OK`, or the status naming the
/// refused threshold; `gains` is unchanged on error). Not while another call uses `gains`.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_gains_f32_set_fault_thresholds(
    gains: *mut at_gains_f32,
    thresholds: *const at_fault_thresholds_f32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_mut` and `as_ref`.
    match unsafe { (gains.as_mut(), thresholds.as_ref()) } {
        (Some(gains), Some(thresholds)) => gains.set_fault_thresholds(thresholds),
        _ => AT_ERR_NULL_POINTER,
    }
}

/// Writes the fault thresholds of `gains` to `out`.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_gains_f32_fault_thresholds(
    gains: *const at_gains_f32,
    out: *mut at_fault_thresholds_f32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    let (Some(gains), Some(out)) = (unsafe { (gains.as_ref(), out.as_mut()) }) else {
        return AT_ERR_NULL_POINTER;
    };
    match gains.fault_thresholds() {
        Ok(thresholds) => {
            *out = thresholds;
            AT_OK
        }
        Err(refused) => refused.status(),
    }
}

/// Makes `state` fresh: it initialises itself from its next sample (angle from
/// `atan2(y_s, y_c)`, speed 0), with no faults latched. A zeroed state is fresh too. NULL is
/// ignored.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_state_f32_reset(state: *mut at_state_f32) {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    if let Some(state) = unsafe { state.as_mut() } {
        *state = at_state_f32::FRESH;
    }
}

/// Returns the faults latched in `state` since they were last cleared (`AT_FAULT_*` bits)
/// and clears them; a fault still present is flagged again at the next sample. 0 for NULL.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_state_f32_clear_faults(state: *mut at_state_f32) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    unsafe { state.as_mut() }.map_or(0, at_state_f32::clear_faults)
}

/// One sample of the demodulated signals `y_c ~ cos(theta)`, `y_s ~ sin(theta)` (any unit:
/// the loop is amplitude-invariant; the fault thresholds are in the same unit): predict,
/// detect the phase error, correct, monitor. Never fails: a bad sample (NaN, infinite, too
/// large) is flagged `AT_FAULT_BAD_SAMPLE` and the state coasts. NULL or gains not made:
/// `AT_FAULT_INVALID_ARGUMENT`, and `state` is unchanged.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_update_f32(
    gains: *const at_gains_f32,
    state: *mut at_state_f32,
    y_c: f32,
    y_s: f32,
) -> at_estimate_f32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (gains.as_ref(), state.as_mut()) } {
        (Some(gains), Some(state)) => run(gains, state, Signals(y_c, y_s)),
        _ => at_estimate_f32::INVALID,
    }
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
    message_ptr(status)
}

/// The name of one `AT_FAULT_*` bit (static, NUL-terminated: `"loss of signal"`, ...), or
/// `"unknown fault"`.
#[unsafe(no_mangle)]
pub extern "C" fn at_fault_name(bit: u32) -> *const c_char {
    faults::name(bit).as_ptr()
}

/// Writes to `out` an ADC front end removing `mid_scale_counts` (the reading of a zero
/// signal, at most 2^30 in magnitude) and dividing by `counts_per_unit` (positive), with no
/// range of codes stated (`at_adc_f32_set_range` states it; without it a chain measures
/// the rails as the extremes held flat).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_adc_f32_new(
    mid_scale_counts: i32,
    counts_per_unit: f32,
    out: *mut at_adc_f32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    unsafe { out.as_mut() }.map_or(AT_ERR_NULL_POINTER, |out| {
        out.set(AdcScaling::new(mid_scale_counts, counts_per_unit), None)
    })
}

/// Writes to `out` the front end of an unsigned (offset binary) ADC of `bits` bits (2 to
/// 31): samples in units of full scale (+-1), its range of codes stated (0 to
/// `2^bits - 1`: a chain flags clipping at them, `at_adc_f32_set_range`).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_adc_f32_offset_binary(bits: u32, out: *mut at_adc_f32) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    unsafe { out.as_mut() }.map_or(AT_ERR_NULL_POINTER, |out| {
        out.set(AdcScaling::offset_binary(bits), codes_of(bits, false))
    })
}

/// Writes to `out` the front end of a signed (two's complement) ADC of `bits` bits (2 to
/// 32): samples in units of full scale (+-1), its range of codes stated (`-2^(bits-1)` to
/// `2^(bits-1) - 1`: a chain flags clipping at them, `at_adc_f32_set_range`).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_adc_f32_twos_complement(bits: u32, out: *mut at_adc_f32) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    unsafe { out.as_mut() }.map_or(AT_ERR_NULL_POINTER, |out| {
        out.set(AdcScaling::twos_complement(bits), codes_of(bits, true))
    })
}

/// States the range of codes of the ADC `adc`: its lowest `min_counts` and highest
/// `max_counts` (`AT_ERR_ADC_RANGE` unless `min_counts < max_counts`; `adc` unchanged on
/// error). A chain with this ADC (`at_chain_f32_new`) flags a sample with a channel at or
/// beyond a rail `AT_FAULT_FRONT_END` (`AT_FRONT_END_FAULT_CLIPPING`), and coasts on its
/// prediction through one with both channels there. Without a stated range the chain
/// measures the rails on the counts as they come (the core's `HeldRailCheck`: an extreme a
/// channel holds for 4 consecutive samples while the other moves, the samples piled up
/// there, on a signal spanning both sides of mid-scale), a weaker test. The plain
/// observer's `at_update_f32_adc_*` check neither.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_adc_f32_set_range(
    adc: *mut at_adc_f32,
    min_counts: i32,
    max_counts: i32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    unsafe { adc.as_mut() }.map_or(AT_ERR_NULL_POINTER, |adc| {
        adc.set_range(min_counts, max_counts)
    })
}

/// The body of the `at_update_f32_adc_*` functions.
///
/// # Safety
/// As theirs.
unsafe fn update_adc<I: AdcSample>(
    gains: *const at_gains_f32,
    state: *mut at_state_f32,
    adc: *const at_adc_f32,
    raw_c: I,
    raw_s: I,
) -> at_estimate_f32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (gains.as_ref(), state.as_mut(), adc.as_ref()) } {
        (Some(gains), Some(state), Some(adc)) => match adc.get() {
            Ok(adc) => run(gains, state, Counts(adc, raw_c, raw_s)),
            Err(_) => at_estimate_f32::INVALID,
        },
        _ => at_estimate_f32::INVALID,
    }
}

/// `at_update_f32` on raw signed 16-bit ADC samples, through the front end `adc`.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_update_f32_adc_i16(
    gains: *const at_gains_f32,
    state: *mut at_state_f32,
    adc: *const at_adc_f32,
    raw_c: i16,
    raw_s: i16,
) -> at_estimate_f32 {
    // SAFETY: the same contract.
    unsafe { update_adc(gains, state, adc, raw_c, raw_s) }
}

/// `at_update_f32` on raw unsigned 16-bit ADC samples, through the front end `adc`.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_update_f32_adc_u16(
    gains: *const at_gains_f32,
    state: *mut at_state_f32,
    adc: *const at_adc_f32,
    raw_c: u16,
    raw_s: u16,
) -> at_estimate_f32 {
    // SAFETY: the same contract.
    unsafe { update_adc(gains, state, adc, raw_c, raw_s) }
}

/// `at_update_f32` on raw signed 32-bit ADC samples, through the front end `adc`.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_update_f32_adc_i32(
    gains: *const at_gains_f32,
    state: *mut at_state_f32,
    adc: *const at_adc_f32,
    raw_c: i32,
    raw_s: i32,
) -> at_estimate_f32 {
    // SAFETY: the same contract.
    unsafe { update_adc(gains, state, adc, raw_c, raw_s) }
}

/// Makes `calibrator` fresh: off, no correction, nothing learned (a zeroed one is fresh
/// too). NULL is ignored.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_calibrator_f32_reset(calibrator: *mut at_calibrator_f32) {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    if let Some(calibrator) = unsafe { calibrator.as_mut() } {
        *calibrator = at_calibrator_f32::FRESH;
    }
}

/// Loads a stored calibration into `calibrator` (checked: `AT_OK`, or the status naming
/// the refused field; unchanged on error), frozen: it corrects each sample and learns
/// nothing until `at_calibrator_f32_enable`, which continues from it.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_calibrator_f32_load(
    calibrator: *mut at_calibrator_f32,
    stored: *const at_sensor_calibration_f32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_mut` and `as_ref`.
    match unsafe { (calibrator.as_mut(), stored.as_ref()) } {
        (Some(calibrator), Some(stored)) => calibrator.load(stored),
        _ => AT_ERR_NULL_POINTER,
    }
}

/// Writes the calibration `calibrator` applies (to store in flash) to `out`.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_calibrator_f32_calibration(
    calibrator: *const at_calibrator_f32,
    out: *mut at_sensor_calibration_f32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (calibrator.as_ref(), out.as_mut()) } {
        (Some(calibrator), Some(out)) => match calibrator.value() {
            Ok(calibrator) => {
                *out = calibrator.calibration().into();
                AT_OK
            }
            Err(refused) => refused.status(),
        },
        _ => AT_ERR_NULL_POINTER,
    }
}

/// Sets the mode of `calibrator`: `AT_CALIBRATION_LEARNING` (correct and learn),
/// `AT_CALIBRATION_FROZEN` (correct only) or `AT_CALIBRATION_OFF`; the calibration is kept.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_calibrator_f32_set_mode(
    calibrator: *mut at_calibrator_f32,
    mode: u32,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    let Some(calibrator) = (unsafe { calibrator.as_mut() }) else {
        return AT_ERR_NULL_POINTER;
    };
    calibrator.set_mode(mode)
}

/// The mode of `calibrator` (`AT_CALIBRATION_*`); `AT_CALIBRATION_OFF` for NULL.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_calibrator_f32_mode(calibrator: *const at_calibrator_f32) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    unsafe { calibrator.as_ref() }.map_or(0, at_calibrator_f32::mode)
}

/// The number of turns `calibrator` has learned since it was started or loaded; 0 for NULL.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_calibrator_f32_turns_learned(
    calibrator: *const at_calibrator_f32,
) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    unsafe { calibrator.as_ref() }
        .and_then(|c| c.value().ok())
        .map_or(0, |c| c.turns_learned())
}

/// Where the online calibration of `calibrator` stands: `AT_CALIBRATION_FINDING_CENTRE`,
/// `AT_CALIBRATION_CENTRED` or `AT_CALIBRATION_STALLED`; `AT_CALIBRATION_FINDING_CENTRE`
/// for NULL or another build's calibrator.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_calibrator_f32_status(calibrator: *const at_calibrator_f32) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    unsafe { calibrator.as_ref() }
        .and_then(|c| c.value().ok())
        .map_or(AT_CALIBRATION_FINDING_CENTRE, |c| status_of(&c))
}

/// `at_update_f32` through the online calibration `calibrator`: unless it is off, the
/// sample is corrected before the phase detector and, while learning, the calibration is
/// learned from the observer's angle (applied once per completed turn). The estimate
/// carries `AT_FAULT_AMPLITUDE_MISMATCH` and `AT_FAULT_OFFSET_OR_QUADRATURE` when the
/// calibration is beyond its bounds.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_update_f32_calibrated(
    gains: *const at_gains_f32,
    state: *mut at_state_f32,
    calibrator: *mut at_calibrator_f32,
    y_c: f32,
    y_s: f32,
) -> at_estimate_f32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (gains.as_ref(), state.as_mut(), calibrator.as_mut()) } {
        (Some(gains), Some(state), Some(calibrator)) => {
            run(gains, state, Calibrated(calibrator, y_c, y_s))
        }
        _ => at_estimate_f32::INVALID,
    }
}
