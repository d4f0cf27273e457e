//! The `extern "C"` functions of the fixed-point chain (`at_fixed_gains_*`, `at_chain_fixed_*`,
//! `at_chain_state_fixed_*`, `at_adc_counts_*`) and of the angle-correction tables
//! (`at_angle_table_fixed_*`, `at_angle_correction_table_f32_*`): each checks its pointers,
//! turns them into references, and calls the safe code of `chain_fixed` and `table`. The
//! caller's contract is `ffi`'s.
#![allow(unsafe_code)]

use crate::calibration::at_sensor_calibration_f32;
use crate::chain::at_angle_correction_f32;
use crate::chain_fixed::{
    at_adc_counts, at_chain_fixed, at_chain_fixed_constants, at_chain_state_fixed,
    at_fixed_estimate,
};
use crate::door::per_sample;
use crate::ffi::{construct, extern_c, write};
use crate::gains::at_fixed_gains;
use crate::status::{AT_ERR_NULL_POINTER, at_status, status_of_result};
use crate::table::{AT_ANGLE_TABLE_LENGTH, at_angle_correction_table_f32, at_angle_table_fixed};

/// Checks the integer constants of a fixed-point observer of order `order` (2 or 3), as
/// `angletrack design --dtype fixed --format c --name NAME` prints them (`NAME_gain_multiplier`,
/// `NAME_ORDER`, `NAME_ACCELERATION_SHIFT`, `NAME_SAMPLE_PERIOD_S`): each multiplier
/// positive, the shift 1 to 15 (0 at order 2), the loop they represent stable. Writes them
/// to the plain `out` (the monitor's thresholds are the chain's: `at_chain_fixed_new`);
/// `out` is unchanged on error (`AT_ERR_GAINS_0`..`_2` naming the gain,
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
        construct(multiplier, order, out, |m| {
            at_fixed_gains::checked(m, acceleration_shift, sample_period_s)
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
        construct(gains, order, out, |g| {
            at_fixed_gains::quantised(g, sample_period_s)
        })
    }
}

extern_c! {
    /// Builds a fixed-point signal chain into `out`: the fixed-point observer `gains` (required;
    /// its monitor set here for `nominal_amplitude_counts`, the amplitude of the observer's
    /// 16-bit input after the stages, 16384 to 46341, with the roundness check at a tolerance
    /// of 0.1, or off for 0: `AT_ERR_NOMINAL_AMPLITUDE`)
    /// after the optional stages, each NULL when absent: the ADC `adc` (then the chain takes
    /// counts of any width, `at_chain_fixed_track_u16`, `_i32`, ...; without it, `int16`
    /// samples only), a stored `calibration` (offsets and amplitudes in the observer's 16-bit
    /// counts, after the ADC's shift; converted to integers: `AT_ERR_OFFSET_C`, ...,
    /// `AT_ERR_AMPLITUDE_S` for a sine channel less than half the cosine's), and the angle
    /// correction `table` (`AT_ERR_ANGLE_CORRECTION`). `out` unchanged on error; the stages are
    /// copied, so they need not outlive the call. Double-precision arithmetic: at start-up.
    fn at_chain_fixed_new(gains: *const at_fixed_gains, adc: Option<&at_adc_counts>,
        calibration: Option<&at_sensor_calibration_f32>, table: Option<&at_angle_table_fixed>,
        nominal_amplitude_counts: f64, out: *mut at_chain_fixed) -> at_status
        = out.set(gains, adc, calibration, table, nominal_amplitude_counts);
        else AT_ERR_NULL_POINTER;
    /// Builds the fixed-point chain of `constants` into `out`: the configuration as
    /// `angletrack export --format c` writes it (`NAME_chain`, `static const`), checked by
    /// integer comparisons only (`AT_ERR_GAINS_0`.., `AT_ERR_SAMPLE_PERIOD_S`, a threshold's
    /// or a stage's status), without floating-point arithmetic: what a firmware without an
    /// FPU calls at start-up. The loop's stability is not checked again (the export
    /// checked it). `out` unchanged on error.
    fn at_chain_fixed_from_constants(constants: *const at_chain_fixed_constants,
        out: *mut at_chain_fixed) -> at_status
        = out.set_from_constants(constants); else AT_ERR_NULL_POINTER;
    /// The settings of an offset-binary (unsigned) ADC of `bits` bits (2 to 16): mid-scale
    /// `2^(bits-1)`, shifted by `16 - bits`, to `out` (`AT_ERR_BITS`; `out` unchanged on error).
    fn at_adc_counts_offset_binary(bits: u32, out: *mut at_adc_counts) -> at_status
        = write(at_adc_counts::of_bits(bits, true), out); else AT_ERR_NULL_POINTER;
    /// The settings of a two's complement (signed) ADC of `bits` bits (2 to 16): mid-scale 0,
    /// shifted by `16 - bits`, to `out` (`AT_ERR_BITS`; `out` unchanged on error).
    fn at_adc_counts_twos_complement(bits: u32, out: *mut at_adc_counts) -> at_status
        = write(at_adc_counts::of_bits(bits, false), out); else AT_ERR_NULL_POINTER;
    /// Writes to `out` the chain `chain` with the ADC's range of codes stated: its lowest
    /// `min_counts` and highest `max_counts` (raw counts, as the chain takes them;
    /// `AT_ERR_ADC_RANGE` unless `min_counts < max_counts`). A sample with a channel at or
    /// beyond a rail is flagged `AT_FAULT_FRONT_END` (`AT_FRONT_END_FAULT_CLIPPING`), and one
    /// with both there is coasted through. `out` unchanged on error. Without a stated range a
    /// chain with an ADC measures the rails on the counts as they come (the core's
    /// `HeldRailCheck`, as `at_adc_f32_set_range` says of the float chain), a weaker test.
    fn at_chain_fixed_with_adc_range(chain: *const at_chain_fixed, min_counts: i32, max_counts: i32,
        out: *mut at_chain_fixed) -> at_status
        = out.set_with_adc_range(chain, min_counts, max_counts); else AT_ERR_NULL_POINTER;
    /// Returns the front-end faults latched in `state` (`AT_FRONT_END_FAULT_*` bits: clipping
    /// against the ADC's stated range or the rails measured) and clears them. 0 for NULL.
    fn at_chain_state_fixed_clear_front_end_faults(state: *mut at_chain_state_fixed) -> u32
        = state.clear_front_end_faults(); else 0;
    /// The multi-turn position of `estimate` (rad): `2 pi (turns + angle / 2^32)`; 0 for NULL.
    /// Double-precision arithmetic: for a host, or out of the sample loop.
    fn at_chain_fixed_position_rad(chain: *const at_chain_fixed, estimate: *const at_fixed_estimate
        ) -> f64
        = chain.in_units(estimate, false); else 0.0;
    /// The speed of `estimate` (rad/s) at the sample period of `chain`'s observer; 0 for NULL
    /// or a chain not made. Double-precision arithmetic: for a host, or out of the sample loop.
    fn at_chain_fixed_speed_rad_s(chain: *const at_chain_fixed, estimate: *const at_fixed_estimate
        ) -> f64
        = chain.in_units(estimate, true); else 0.0;
    /// Makes `state` fresh: the observer initialises itself from its next sample. NULL is
    /// ignored.
    fn at_chain_state_fixed_reset(state: *mut at_chain_state_fixed)
        = *state = at_chain_state_fixed::FRESH; else ();
    /// Returns the faults latched in `state` (`AT_FAULT_*` bits) and clears them. 0 for NULL.
    fn at_chain_state_fixed_clear_faults(state: *mut at_chain_state_fixed) -> u32
        = state.clear_faults(); else 0;
    /// The fixed-point table of the harmonic angle error `harmonics` (as `angletrack calibrate`
    /// learns it; checked as `at_chain_f32_new` checks it: `AT_ERR_ANGLE_CORRECTION`), rounded to
    /// Q15, to `out` (unchanged on error).
    fn at_angle_table_fixed_from_harmonics(harmonics: *const at_angle_correction_f32,
        out: *mut at_angle_table_fixed) -> at_status
        = write(at_angle_table_fixed::from_harmonics(harmonics), out); else AT_ERR_NULL_POINTER;
    /// The float table of the harmonic angle error `harmonics` (checked:
    /// `AT_ERR_ANGLE_CORRECTION`), to `out` (unchanged on error).
    fn at_angle_correction_table_f32_from_harmonics(harmonics: *const at_angle_correction_f32,
        out: *mut at_angle_correction_table_f32) -> at_status
        = write(at_angle_correction_table_f32::from_harmonics(harmonics), out);
        else AT_ERR_NULL_POINTER;
    /// Checks a float table (each entry finite and within 0.25 rad): `AT_OK` or
    /// `AT_ERR_ANGLE_CORRECTION` (`at_chain_f32_new` checks it again).
    fn at_angle_correction_table_f32_check(table: *const at_angle_correction_table_f32) -> at_status
        = status_of_result(table.checked()); else AT_ERR_NULL_POINTER;
    /// The estimate `state` holds for `chain` (its last sample's; all zero for a fresh state).
    /// Refused arguments: `AT_FAULT_INVALID_ARGUMENT`.
    fn at_chain_fixed_estimate(chain: *const at_chain_fixed, state: *const at_chain_state_fixed
    ) -> at_fixed_estimate
        = chain.estimate(state); else at_fixed_estimate::invalid();
}

/// The fixed-point table of `errors_rad` (`AT_ANGLE_TABLE_LENGTH` errors in rad at the
/// angles `-pi + 2 pi k / 256`, each finite and within 0.25 rad: `AT_ERR_ANGLE_CORRECTION`),
/// rounded to Q15, to `out` (unchanged on error).
///
/// # Safety
/// `errors_rad` points to `AT_ANGLE_TABLE_LENGTH` floats; see the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_angle_table_fixed_from_errors(
    errors_rad: *const f32,
    out: *mut at_angle_table_fixed,
) -> at_status {
    // SAFETY: the caller's contract: NULL, or `AT_ANGLE_TABLE_LENGTH` floats.
    match unsafe {
        (
            errors_rad.cast::<[f32; AT_ANGLE_TABLE_LENGTH]>().as_ref(),
            out.as_mut(),
        )
    } {
        (Some(errors), Some(out)) => write(at_angle_table_fixed::from_errors(errors), out),
        _ => AT_ERR_NULL_POINTER,
    }
}

/// The float table of a measured error curve: `curve[j]` (rad) at the angle
/// `-pi + 2 pi j / points` (`points` at least 2: `AT_ERR_CURVE`), resampled by periodic linear
/// interpolation (entries finite and within 0.25 rad: `AT_ERR_ANGLE_CORRECTION`), to `out`
/// (unchanged on error).
///
/// # Safety
/// `curve` points to `points` floats; see the header's introduction.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn at_angle_correction_table_f32_from_curve(
    curve: *const f32,
    points: usize,
    out: *mut at_angle_correction_table_f32,
) -> at_status {
    match unsafe { out.as_mut() } {
        // SAFETY: `curve` is not NULL and points to `points` floats (the caller's contract).
        Some(out) if !curve.is_null() => write(
            at_angle_correction_table_f32::from_curve(unsafe {
                core::slice::from_raw_parts(curve, points)
            }),
            out,
        ),
        _ => AT_ERR_NULL_POINTER,
    }
}

per_sample! {
    at_chain_fixed, at_chain_state_fixed;
    /// One sample of `int16` counts through the chain's stages and observer, the state only (the
    /// cheapest per-sample call; `at_chain_fixed_estimate` reads the estimate on demand). A
    /// chain without an ADC takes `int16` samples as they are. Returns 0, or
    /// `AT_FAULT_INVALID_ARGUMENT` (nothing changed) for a NULL pointer, a chain not made or a
    /// struct of another build.
    at_chain_fixed_track_i16(raw_c: i16, raw_s: i16) -> u32 = track((raw_c, raw_s));
    /// `at_chain_fixed_track_i16`, then the estimate; on refused arguments an estimate whose
    /// faults are `AT_FAULT_INVALID_ARGUMENT` (the rest 0).
    at_chain_fixed_update_i16(raw_c: i16, raw_s: i16) -> at_fixed_estimate = update((raw_c, raw_s));
    /// `at_chain_fixed_track_i16` on `uint16` counts, through the chain's ADC
    /// (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
    at_chain_fixed_track_u16(raw_c: u16, raw_s: u16) -> u32 = track((raw_c, raw_s));
    /// `at_chain_fixed_track_u16`, then the estimate; on refused arguments an estimate whose
    /// faults are `AT_FAULT_INVALID_ARGUMENT` (the rest 0).
    at_chain_fixed_update_u16(raw_c: u16, raw_s: u16) -> at_fixed_estimate = update((raw_c, raw_s));
    /// `at_chain_fixed_track_i16` on `int32` counts, through the chain's ADC
    /// (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
    at_chain_fixed_track_i32(raw_c: i32, raw_s: i32) -> u32 = track((raw_c, raw_s));
    /// `at_chain_fixed_track_i32`, then the estimate; on refused arguments an estimate whose
    /// faults are `AT_FAULT_INVALID_ARGUMENT` (the rest 0).
    at_chain_fixed_update_i32(raw_c: i32, raw_s: i32) -> at_fixed_estimate = update((raw_c, raw_s));
    /// `at_chain_fixed_track_i16` for a chain of order 2 only: no dispatch on the
    /// order (the checks, then the chain's body), and an image that calls no other order's
    /// links one body.
    /// `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
    at_chain_fixed_track_i16_order2(raw_c: i16, raw_s: i16) -> u32
        = track_order::<2>((raw_c, raw_s));
    /// `at_chain_fixed_track_i16` for a chain of order 3 only: no dispatch on the
    /// order (the checks, then the chain's body), and an image that calls no other order's
    /// links one body.
    /// `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
    at_chain_fixed_track_i16_order3(raw_c: i16, raw_s: i16) -> u32
        = track_order::<3>((raw_c, raw_s));
    /// `at_chain_fixed_track_u16` for a chain of order 2 only: no dispatch on the
    /// order (the checks, then the chain's body), and an image that calls no other order's
    /// links one body.
    /// `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
    at_chain_fixed_track_u16_order2(raw_c: u16, raw_s: u16) -> u32
        = track_order::<2>((raw_c, raw_s));
    /// `at_chain_fixed_track_u16` for a chain of order 3 only: no dispatch on the
    /// order (the checks, then the chain's body), and an image that calls no other order's
    /// links one body.
    /// `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
    at_chain_fixed_track_u16_order3(raw_c: u16, raw_s: u16) -> u32
        = track_order::<3>((raw_c, raw_s));
    /// `at_chain_fixed_track_i32` for a chain of order 2 only: no dispatch on the
    /// order (the checks, then the chain's body), and an image that calls no other order's
    /// links one body.
    /// `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
    at_chain_fixed_track_i32_order2(raw_c: i32, raw_s: i32) -> u32
        = track_order::<2>((raw_c, raw_s));
    /// `at_chain_fixed_track_i32` for a chain of order 3 only: no dispatch on the
    /// order (the checks, then the chain's body), and an image that calls no other order's
    /// links one body.
    /// `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
    at_chain_fixed_track_i32_order3(raw_c: i32, raw_s: i32) -> u32
        = track_order::<3>((raw_c, raw_s));
}
