//! The `extern "C"` functions of the fixed-point observer (`at_fixed_*`): each checks its pointers, turns them into references, and
//! calls the safe code of `fixed`. The caller's contract is `ffi`'s.
#![allow(unsafe_code)]

use crate::faults::AT_FAULT_INVALID_ARGUMENT;
use crate::fixed::{at_fixed_estimate, at_fixed_gains, at_fixed_state, track, with_fixed};
use crate::status::{AT_ERR_NULL_POINTER, AT_ERR_ORDER, at_status};

/// The body of the constructors: `out` and the `order` values at `values` checked, then
/// `set` on them.
///
/// # Safety
/// As the constructors'.
unsafe fn construct<V>(
    values: *const V,
    order: usize,
    out: *mut at_fixed_gains,
    set: impl FnOnce(&mut at_fixed_gains, &[V]) -> at_status,
) -> at_status {
    // SAFETY: the caller's contract (see `ffi`); NULL is checked by `as_mut`.
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
    set(out, values)
}

/// Checks the integer constants of a fixed-point observer of order `order` (2 or 3), as
/// `angletrack design --dtype fixed --format c --name NAME` prints them (`NAME_gain_multiplier`,
/// `NAME_ORDER`, `NAME_ACCELERATION_SHIFT`, `NAME_SAMPLE_PERIOD_S`): each multiplier
/// positive, the shift 1 to 15 (0 at order 2), the loop they represent stable. Writes the
/// configuration, with the monitor's thresholds for a nominal amplitude of 16384 counts, to
/// `out`; `out` is unchanged on error (`AT_ERR_GAINS_0`..`_2` naming the gain,
/// `AT_ERR_SAMPLE_PERIOD_S`, ...).
///
/// # Safety
/// `multiplier` points to `order` integers; see the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_gains_from_constants(
    multiplier: *const i32,
    order: usize,
    acceleration_shift: u32,
    sample_period_s: f64,
    out: *mut at_fixed_gains,
) -> at_status {
    // SAFETY: the same contract.
    unsafe {
        construct(multiplier, order, out, |out, m| {
            out.set_constants(m, acceleration_shift, sample_period_s)
        })
    }
}

/// Quantises `order` (2 or 3) float gains `gains` (l1, l2[, l3], as `angletrack design
/// --format c` writes them and `at_gains_f32_new` takes them) at the sample period
/// `sample_period_s` (s) into a fixed-point observer's configuration, checked (a gain that
/// rounds to zero or does not fit is refused, naming it), to `out` (unchanged on error).
/// Costs double-precision arithmetic: at start-up, or on the host (then embed the
/// constants and use `at_fixed_gains_from_constants`).
///
/// # Safety
/// `gains` points to `order` floats; see the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_gains_new(
    gains: *const f32,
    order: usize,
    sample_period_s: f64,
    out: *mut at_fixed_gains,
) -> at_status {
    // SAFETY: the same contract.
    unsafe {
        construct(gains, order, out, |out, g| {
            out.set_gains(g, sample_period_s)
        })
    }
}

/// Sets the monitor of `gains` for signals of `nominal_amplitude_counts` (16384 to 46341
/// counts: a 12-bit reading shifted left by 4 is about 28,800), or turns it off with 0 (only
/// the input's handling remains). `AT_OK`, or `AT_ERR_NOMINAL_AMPLITUDE` (`gains` unchanged).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_gains_set_monitor(
    gains: *mut at_fixed_gains,
    nominal_amplitude_counts: f64,
) -> at_status {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    unsafe { gains.as_mut() }.map_or(AT_ERR_NULL_POINTER, |g| {
        g.set_monitor(nominal_amplitude_counts)
    })
}

/// The order (2 or 3) of fixed-point gains; 0 for NULL or gains not made (or another
/// build's).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_gains_order(gains: *const at_fixed_gains) -> usize {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    unsafe { gains.as_ref() }
        .and_then(|g| g.get().ok())
        .map_or(0, |any| with_fixed!(any, |g| g.gains().len()))
}

/// Makes `state` fresh (it initialises itself from its next sample); a zeroed state is
/// fresh too. NULL is ignored.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_state_reset(state: *mut at_fixed_state) {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    if let Some(state) = unsafe { state.as_mut() } {
        *state = at_fixed_state::FRESH;
    }
}

/// Returns the faults latched in `state` since they were last cleared (`AT_FAULT_*` bits)
/// and clears them. 0 for NULL.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_state_clear_faults(state: *mut at_fixed_state) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_mut`.
    unsafe { state.as_mut() }.map_or(0, at_fixed_state::clear_faults)
}

/// One sample of the integer signals `y_c ~ cos(theta)`, `y_s ~ sin(theta)` (counts, the
/// ADC's mid-scale removed; amplitudes from 4096 to 46341 counts are normalised exactly, so
/// a 12-bit reading is shifted left by 3 or 4), the state only: the cheapest per-sample
/// call (`at_fixed_state_estimate` reads the estimate on demand). Returns 0, or
/// `AT_FAULT_INVALID_ARGUMENT` when a pointer is NULL, the gains were not made or a struct
/// is another build's (then `state` is unchanged).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_track(
    gains: *const at_fixed_gains,
    state: *mut at_fixed_state,
    y_c: i16,
    y_s: i16,
) -> u32 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (gains.as_ref(), state.as_mut()) } {
        (Some(gains), Some(state)) => {
            if track(gains, state, y_c, y_s) {
                0
            } else {
                AT_FAULT_INVALID_ARGUMENT
            }
        }
        _ => AT_FAULT_INVALID_ARGUMENT,
    }
}

/// `at_fixed_track`, then the estimate (`at_fixed_state_estimate`); on refused arguments
/// an estimate whose faults are `AT_FAULT_INVALID_ARGUMENT` (the rest 0).
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_update(
    gains: *const at_fixed_gains,
    state: *mut at_fixed_state,
    y_c: i16,
    y_s: i16,
) -> at_fixed_estimate {
    // SAFETY: the caller's contract; NULL is checked by `as_ref` and `as_mut`.
    match unsafe { (gains.as_ref(), state.as_mut()) } {
        (Some(gains), Some(state)) => {
            if track(gains, state, y_c, y_s) {
                state.estimate().unwrap_or(at_fixed_estimate::INVALID)
            } else {
                at_fixed_estimate::INVALID
            }
        }
        _ => at_fixed_estimate::INVALID,
    }
}

/// The estimate `state` holds (its last sample's; all zero for a fresh state). NULL or
/// another build's state: `AT_FAULT_INVALID_ARGUMENT`.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_state_estimate(
    state: *const at_fixed_state,
) -> at_fixed_estimate {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    unsafe { state.as_ref() }
        .and_then(|s| s.estimate().ok())
        .unwrap_or(at_fixed_estimate::INVALID)
}

/// The multi-turn position of `estimate` (rad): `2 pi (turns + angle / 2^32)`. 0 for NULL.
/// Double-precision arithmetic: for a host, or out of the sample loop.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_position_rad(estimate: *const at_fixed_estimate) -> f64 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    unsafe { estimate.as_ref() }.map_or(0.0, |e| {
        (e.turns as f64 + f64::from(e.angle) / 4_294_967_296.0) * core::f64::consts::TAU
    })
}

/// The speed of `estimate` (rad/s) at the sample period of `gains`. 0 for NULL or gains
/// not made. Double-precision arithmetic: for a host, or out of the sample loop.
///
/// # Safety
/// See the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_fixed_speed_rad_s(
    gains: *const at_fixed_gains,
    estimate: *const at_fixed_estimate,
) -> f64 {
    // SAFETY: the caller's contract; NULL is checked by `as_ref`.
    match unsafe { (gains.as_ref(), estimate.as_ref()) } {
        (Some(gains), Some(e)) => gains.get().map_or(0.0, |any| {
            with_fixed!(any, |g| f64::from(e.speed) / 4_294_967_296.0
                * core::f64::consts::TAU
                / g.sample_period())
        }),
        _ => 0.0,
    }
}
