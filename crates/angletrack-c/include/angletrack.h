/*
 * angletrack.h: the C API of angletrack-core, angle tracking observers
 * (resolver-to-digital conversion) for firmware. Generated from crates/angletrack-c by
 * cbindgen: do not edit. Link with libangletrack_c.a (cargo build -p angletrack-c --release
 * [--target thumbv7em-none-eabihf or thumbv6m-none-eabi]).
 *
 * Once, at start-up, build a signal chain: at_gains_f32_new() checks the gains that
 * `angletrack design --format c` writes (NAME_gains, NAME_ORDER, NAME_SAMPLE_PERIOD_S), and
 * at_chain_f32_new() puts them after the optional stages (the ADC, at_adc_f32; a stored
 * calibration or the online calibration; the harmonic angle correction or its table; NULL
 * when absent). Every sample: at_chain_f32_track() (or _update(), which returns an
 * at_estimate_f32) on floats, _i16/_u16/_i32 on raw ADC counts; at_chain_f32_estimate() on
 * demand. With the ADC's range stated (its bits, or at_adc_f32_set_range()), a clipped
 * sample is flagged AT_FAULT_FRONT_END. From raw resolver windings,
 * at_demodulator_f32_push() gives one (y_c, y_s) pair per carrier period, which
 * at_chain_f32_update_demodulated() takes with its faults (the observer coasts through a
 * loss of excitation; at_chain_f32_with_winding_check() adds a winding open or shorted).
 * On a core without an FPU (Cortex-M0), the fixed-point chain: at_fixed_gains_from_constants()
 * checks the integer constants of `angletrack design --dtype fixed --format c`
 * (NAME_gain_multiplier, NAME_ORDER, NAME_ACCELERATION_SHIFT, NAME_SAMPLE_PERIOD_S), and
 * at_chain_fixed_new() puts them after the ADC's at_adc_counts, a stored calibration in the
 * observer's 16-bit counts and the Q15 at_angle_table_fixed, with the monitor's amplitude
 * (at_chain_fixed_with_adc_range() flags clipped counts); every sample,
 * at_chain_fixed_track_u16() (or _i16, _i32, and their _update_ forms) on raw counts, or
 * the form of the chain's order, at_chain_fixed_track_u16_order3() (_order2), whose body
 * is inlined and links one order's code; at_chain_fixed_estimate() on demand. The structs are plain and sized: place them in
 * static memory.
 * A zeroed at_chain_state_f32, at_chain_state_fixed or at_demodulator_state_f32 is a fresh
 * one; zeroed at_gains_f32, at_fixed_gains, at_chain_f32, at_chain_fixed, at_adc_f32 or
 * at_demodulator_f32 are refused until made by their constructor.
 *
 * Layout: every struct made by the library starts with its private tag (which Rust value it
 * holds) and layout word (a fingerprint of the build that wrote it: AT_LAYOUT_VERSION, the
 * library's version, the struct's size, the target). A struct written by another build of
 * the library is refused with AT_ERR_OTHER_BUILD (AT_FAULT_INVALID_ARGUMENT from an update),
 * never read; at start-up, at_layout_version() == AT_LAYOUT_VERSION checks that the header
 * is the library's.
 *
 * Contract of every function taking pointers: NULL is refused (AT_ERR_NULL_POINTER, or
 * AT_FAULT_INVALID_ARGUMENT from an update), never undefined behaviour; a non-NULL pointer
 * points to a live object of its type (`gains` to `order` floats) that nothing else reads
 * or writes during the call (no aliasing between arguments, no concurrent call on the same
 * state from an interrupt); each struct was zeroed, made by its constructor, or copied whole
 * from one that was; its private fields (tag, layout, storage) are never written by C code. No call
 * panics, allocates or blocks.
 */

#ifndef ANGLETRACK_H
#define ANGLETRACK_H

#include <stddef.h>
#include <stdint.h>

/**
 * The 8-byte words of an `at_adc_f32`'s storage (checked against the Rust type at compile
 * time, on every target).
 */
#define AT_ADC_F32_WORDS 3

/**
 * `at_chain_state_f32_calibration_mode`: neither corrects nor learns (a fresh calibrator's mode).
 */
#define AT_CALIBRATION_OFF 0

/**
 * `at_chain_state_f32_calibration_mode`: corrects each sample and learns while the observer tracks.
 */
#define AT_CALIBRATION_LEARNING 1

/**
 * `at_chain_state_f32_calibration_mode`: corrects each sample, learns nothing.
 */
#define AT_CALIBRATION_FROZEN 2

/**
 * `at_chain_state_f32_calibration_status`: the channels' centres are not found yet (the rotor has not
 * turned a whole turn while learning, or is at rest); nothing is learned (a fresh
 * calibrator's status).
 */
#define AT_CALIBRATION_FINDING_CENTRE 0

/**
 * `at_chain_state_f32_calibration_status`: the centre is known (found, or loaded); learning, or ready to.
 */
#define AT_CALIBRATION_CENTRED 1

/**
 * `at_chain_state_f32_calibration_status`: 16 electrical turns at speed without a turn learned (the
 * observer not locked within 0.29 of phase error, or the speed not steady).
 */
#define AT_CALIBRATION_STALLED 2

/**
 * The 8-byte words of an `at_chain_f32`'s storage (checked against the Rust type at
 * compile time, on every target).
 */
#define AT_CHAIN_F32_WORDS 284

/**
 * The 8-byte words of an `at_chain_state_f32`'s storage (checked against the Rust type at
 * compile time, on every target).
 */
#define AT_CHAIN_STATE_F32_WORDS 32

/**
 * The harmonic orders an `at_angle_correction_f32` holds (the core's
 * `MAX_CORRECTION_ORDER`: the struct's arrays are the core's, checked at compile time).
 */
#define AT_CORRECTION_ORDER 8

/**
 * The 8-byte words of an `at_chain_fixed`'s storage (checked against the Rust type at
 * compile time, on every target).
 */
#define AT_CHAIN_FIXED_WORDS 77

/**
 * The 8-byte words of an `at_chain_state_fixed`'s storage (checked against the Rust type at
 * compile time, on every target).
 */
#define AT_CHAIN_STATE_FIXED_WORDS 18

/**
 * The 8-byte words of an `at_demodulator_f32`'s storage (checked against the Rust types at
 * compile time, on every target).
 */
#define AT_DEMODULATOR_F32_WORDS 9

/**
 * The 8-byte words of an `at_demodulator_state_f32`'s storage (checked against the Rust
 * type at compile time, on every target).
 */
#define AT_DEMODULATOR_STATE_F32_WORDS 24

/**
 * A pair's front-end fault: loss of excitation (the carrier amplitude at the windings
 * below its threshold).
 */
#define AT_FRONT_END_FAULT_LOSS_OF_EXCITATION 1

/**
 * A pair's front-end fault: the tracked carrier delay drifted beyond its bound.
 */
#define AT_FRONT_END_FAULT_PHASE_DRIFT (1 << 1)

/**
 * A pair's front-end fault: a raw sample of the window was within the margin of the ADC's
 * rails (or not a number).
 */
#define AT_FRONT_END_FAULT_CLIPPING (1 << 2)

/**
 * A pair's front-end fault: weak excitation (the carrier amplitude at the windings below
 * its threshold, above the loss of excitation's).
 */
#define AT_FRONT_END_FAULT_WEAK_EXCITATION (1 << 3)

/**
 * A front-end fault: a winding open or shorted (the chain's winding check,
 * `at_chain_f32_with_winding_check`).
 */
#define AT_FRONT_END_FAULT_WINDING (1 << 4)

/**
 * A pair's front-end fault: the recorded excitation (`at_demodulator_f32_push_with_excitation`)
 * unusable in this window (its carrier below an eighth of the windings' nominal amplitude,
 * or not a number), or none usable since the start-up: the carrier's half turn is not
 * checked against it.
 */
#define AT_FRONT_END_FAULT_EXCITATION_REFERENCE (1 << 5)

/**
 * Loss of signal: a window's RMS amplitude is below the loss-of-signal threshold.
 */
#define AT_FAULT_LOSS_OF_SIGNAL 1

/**
 * Degradation of signal: a window's RMS amplitude is outside [degradation_low, degradation_high].
 */
#define AT_FAULT_DEGRADATION_OF_SIGNAL (1 << 1)

/**
 * Loss of tracking: a window's mean phase error or its last speed is above its threshold.
 */
#define AT_FAULT_LOSS_OF_TRACKING (1 << 2)

/**
 * The sample was rejected (NaN, infinite, or above the input bound); the observer coasted.
 */
#define AT_FAULT_BAD_SAMPLE (1 << 3)

/**
 * A lock about 180 degrees off was detected (and the angle re-acquired, by default).
 */
#define AT_FAULT_FALSE_LOCK (1 << 4)

/**
 * The online calibration's amplitude ratio is beyond its bound.
 */
#define AT_FAULT_AMPLITUDE_MISMATCH (1 << 5)

/**
 * An offset or the quadrature angle of the online calibration is beyond its bound.
 */
#define AT_FAULT_OFFSET_OR_QUADRATURE (1 << 6)

/**
 * A front-end fault: a stage before the observer flagged the sample (the core's
 * `FrontEndCheck`, `WindingCheck`: clipping against the ADC's stated range, a
 * demodulator's fault, a winding open or shorted), and while the fault invalidates it the
 * observer coasted on its prediction.
 */
#define AT_FAULT_FRONT_END (1 << 7)

/**
 * Not the sensor's: the call's chain or state was NULL, not made by its constructor or
 * another build's (or the chain cannot take the input); nothing was computed and the
 * estimate's other fields are 0.
 */
#define AT_FAULT_INVALID_ARGUMENT 2147483648

/**
 * The version of the C structs' layout, bumped whenever a struct of the header or a Rust
 * value the library stores in one changes; part of every struct's layout word (with the
 * crate's version and the sizes, which change it without a bump). `at_layout_version()`
 * returns the library's, to compare with the header's at start-up.
 */
#define AT_LAYOUT_VERSION 10

/**
 * The entries of an angle-correction table (`at_angle_correction_table_f32`,
 * `at_angle_table_fixed`): the error at the angles `-pi + 2 pi k / 256`, `k = 0..255`,
 * interpolated linearly between them at the observer's predicted angle.
 */
#define AT_ANGLE_TABLE_LENGTH 256

/**
 * The thresholds of the diagnostics and of the input check, in the input's units
 * (amplitudes) unless stated: the core's `FaultThresholds`. Start from
 * `at_fault_thresholds_f32_for_amplitude(nominal)` (the defaults scaled to the nominal
 * amplitude), change fields, and write it to `at_gains_f32::thresholds`.
 */
typedef struct at_fault_thresholds_f32 {
  /**
   * The amplitude of a healthy signal (default 1).
   */
  float nominal_amplitude;
  /**
   * A sample with `sqrt(y_c^2 + y_s^2)` above this is rejected (default 4 x nominal).
   */
  float max_input_amplitude;
  /**
   * A window's RMS amplitude below this: loss of signal (default 0.25 x nominal).
   */
  float loss_of_signal;
  /**
   * A window's RMS amplitude below this: degradation of signal (default 0.5 x nominal).
   */
  float degradation_low;
  /**
   * A window's RMS amplitude above this: degradation of signal (default 1.5 x nominal).
   */
  float degradation_high;
  /**
   * A window's mean normalised phase error above this: loss of tracking (default 0.1).
   */
  float loss_of_tracking;
  /**
   * Estimated |speed| (rad/s) above this: loss of tracking; 0 for the default, a
   * quarter turn per sample (`pi / (2 Ts)`).
   */
  float max_speed_rad_s;
  /**
   * 1 / W for the diagnostics' window of W used samples (1 / filter_factor rounded down
   * to a power of two, at most 4096), in (0, 1] (default 1/16: a fault is flagged within
   * 31 samples).
   */
  float filter_factor;
  /**
   * The in-phase component at a window's end below this: false lock (default 0).
   */
  float false_lock;
  /**
   * Nonzero: compute the flags (loss of signal, degradation, loss of tracking, false
   * lock); 0: only the input check runs (default 1).
   */
  uint32_t monitor;
  /**
   * Nonzero: re-acquire the angle on a false lock (default 1).
   */
  uint32_t re_acquire;
  /**
   * The roundness check's tolerance `r`: a window whose last pair's magnitude is outside
   * `(1 +- r)` x nominal raises degradation of signal, held for
   * `ROUNDNESS_HOLD_WINDOWS` windows (default 0.1); 0: no check.
   */
  float magnitude_tolerance;
  /**
   * One sample's normalised phase error (about the sine of its angle error, electrical)
   * above this: loss of tracking at once, on that sample, held while it stays above a
   * fraction of this (the loop re-converging) and latched (default 0.05, positive).
   */
  float tracking_error;
} at_fault_thresholds_f32;

/**
 * What a call that can fail returns: `AT_OK` (0), or the `AT_ERR_*` code of what was
 * refused. `at_status_message` gives its text.
 */
typedef int32_t at_status;

/**
 * The gains, sample period and fault thresholds of an observer (order 2 or 3): filled by
 * `at_gains_f32_new` (checked, with the default fault thresholds) from the gains
 * `angletrack design --format c` writes, or written. Change `thresholds` as needed;
 * `at_chain_f32_new` checks it all (a zeroed one is refused: `AT_ERR_ORDER`).
 */
typedef struct at_gains_f32 {
  /**
   * `l1`, `l2`, `l3` (dimensionless; `l3` unused at order 2).
   */
  float gains[3];
  /**
   * The observer's order, 2 or 3.
   */
  uint32_t order;
  /**
   * The sample period (s).
   */
  float sample_period_s;
  /**
   * The fault thresholds.
   */
  struct at_fault_thresholds_f32 thresholds;
} at_gains_f32;

/**
 * The checked ADC front end, made by `at_adc_f32_new`, `at_adc_f32_offset_binary` or
 * `at_adc_f32_twos_complement`, with its range of codes (stated by the last two, or by
 * `at_adc_f32_set_range` at start-up). Immutable once made but for its range; place it
 * anywhere; copy it by assignment; never write its fields. A zeroed one is refused.
 */
typedef struct at_adc_f32 {
  /**
   * Private: which Rust value `storage` holds (0: none; in a state, a fresh one).
   */
  uint32_t tag;
  /**
   * Private: the layout of the build that wrote it.
   */
  uint32_t layout;
  /**
   * Private: the Rust value.
   */
  uint64_t storage[AT_ADC_F32_WORDS];
} at_adc_f32;

/**
 * The online calibration's settings (the core's `CalibrationSettings`): when it learns and
 * the bounds beyond which its estimates raise a fault. Start from
 * `at_calibration_settings_f32_default()`.
 */
typedef struct at_calibration_settings_f32 {
  /**
   * Learns only above this electrical speed (rad/s); 0 for the default, one turn in
   * 4096 samples.
   */
  float min_speed_rad_s;
  /**
   * An offset above this fraction of its channel's amplitude flags
   * `AT_FAULT_OFFSET_OR_QUADRATURE` (default 0.1).
   */
  float max_offset;
  /**
   * `|A_s / A_c - 1|` above this flags `AT_FAULT_AMPLITUDE_MISMATCH` (default 0.2).
   */
  float max_amplitude_mismatch;
  /**
   * `|quadrature|` (rad) above this flags `AT_FAULT_OFFSET_OR_QUADRATURE` (default 0.1).
   */
  float max_quadrature_rad;
} at_calibration_settings_f32;

/**
 * A sensor's calibration, `y_c = offset_c + amplitude_c cos(theta)`,
 * `y_s = offset_s + amplitude_s sin(theta + quadrature_rad)` (input units, rad): plain
 * floats to store in flash. `at_chain_f32_new` and `at_chain_state_f32_load_calibration` check them.
 */
typedef struct at_sensor_calibration_f32 {
  /**
   * Offset of the cosine channel.
   */
  float offset_c;
  /**
   * Offset of the sine channel.
   */
  float offset_s;
  /**
   * Amplitude of the cosine channel (positive).
   */
  float amplitude_c;
  /**
   * Amplitude of the sine channel (positive).
   */
  float amplitude_s;
  /**
   * Quadrature (non-orthogonality) angle (rad), below pi/4 in magnitude.
   */
  float quadrature_rad;
} at_sensor_calibration_f32;

/**
 * A harmonic angle error `d(theta) = sum_k a_k cos(k theta) + b_k sin(k theta)`, `k = 1..8`
 * (rad), as `angletrack calibrate` learns it: the chain rotates each sample by `-d` at the
 * observer's predicted angle. All zero corrects nothing.
 */
typedef struct at_angle_correction_f32 {
  /**
   * `a_k` at index `k - 1` (rad).
   */
  float cos_coefficients[AT_CORRECTION_ORDER];
  /**
   * `b_k` at index `k - 1` (rad).
   */
  float sin_coefficients[AT_CORRECTION_ORDER];
} at_angle_correction_f32;

/**
 * The sensor's angle error `d` (rad) at the angles `-pi + 2 pi k / 256`: the f32 chain
 * rotates each sample by `-d` at the observer's predicted angle, `d` interpolated linearly
 * (an alternative to the harmonic `at_angle_correction_f32`: the same cost whatever the
 * error's shape). Each entry finite and within 0.25 rad; all zero corrects nothing. Made by
 * `at_angle_correction_table_f32_from_harmonics` or `_from_curve`, or written directly.
 */
typedef struct at_angle_correction_table_f32 {
  /**
   * `d` (rad) at the angle `-pi + 2 pi k / 256`, index `k`.
   */
  float errors_rad[AT_ANGLE_TABLE_LENGTH];
} at_angle_correction_table_f32;

/**
 * The checked configuration of one signal chain, made by `at_chain_f32_new` from the
 * observer's gains and optional stages. Immutable once made: one serves any number of
 * channels (`at_chain_state_f32`). Place it anywhere; copy it by assignment; never write its
 * fields. A zeroed one is refused.
 */
typedef struct at_chain_f32 {
  /**
   * Private: which Rust value `storage` holds (0: none; in a state, a fresh one).
   */
  uint32_t tag;
  /**
   * Private: the layout of the build that wrote it.
   */
  uint32_t layout;
  /**
   * Private: the Rust value.
   */
  uint64_t storage[AT_CHAIN_F32_WORDS];
} at_chain_f32;

/**
 * What the observer knows after a sample.
 */
typedef struct at_estimate_f32 {
  /**
   * Estimated angle (rad), wrapped to [-pi, pi).
   */
  float angle;
  /**
   * Whole turns counted since initialisation (positive counter-clockwise); the
   * multi-turn position is `turns * 2 pi + angle` (rad).
   */
  int64_t turns;
  /**
   * Estimated speed (rad/s).
   */
  float speed;
  /**
   * Estimated acceleration (rad/s^2); 0 for a 2nd-order observer.
   */
  float acceleration;
  /**
   * Normalised phase-detector output of this sample (about the sine of the phase
   * error, dimensionless); 0 when the sample was rejected.
   */
  float phase_error;
  /**
   * This sample's faults (`AT_FAULT_*` bits); the state also latches them.
   */
  uint32_t faults;
} at_estimate_f32;

/**
 * One channel's state of a signal chain: the observer's state and the online
 * calibration's estimator. A zeroed one is fresh (as after `at_chain_state_f32_reset`): the
 * observer initialises itself from its first sample, the online calibration is off until
 * `at_chain_state_f32_set_calibration_mode`. Place it anywhere; copy it by assignment;
 * never write its fields.
 */
typedef struct at_chain_state_f32 {
  /**
   * Private: which Rust value `storage` holds (0: none; in a state, a fresh one).
   */
  uint32_t tag;
  /**
   * Private: the layout of the build that wrote it.
   */
  uint32_t layout;
  /**
   * Private: the Rust value.
   */
  uint64_t storage[AT_CHAIN_STATE_F32_WORDS];
} at_chain_state_f32;

/**
 * One demodulated pair: the windings' envelopes at the centroid of their window.
 */
typedef struct at_demodulated_pair_f32 {
  /**
   * The cosine winding's envelope, `~ cos theta` (nominal amplitude 1).
   */
  float y_c;
  /**
   * The sine winding's envelope, `~ sin theta`.
   */
  float y_s;
  /**
   * The cosine winding's quadrature component (about 0).
   */
  float quadrature_c;
  /**
   * The sine winding's quadrature component (about 0).
   */
  float quadrature_s;
  /**
   * The index of the window (start-up windows included).
   */
  uint64_t window;
  /**
   * The ADC sample index (from 0, the first sample pushed) at which the pair holds, its
   * samples weighted by their share of it (the window's centroid at a multiple of 4
   * samples a carrier period; exact at any ratio; divide by the ADC rate for seconds).
   */
  double centre_sample;
  /**
   * This window's front-end faults (`AT_FRONT_END_FAULT_*` bits).
   */
  uint32_t faults;
} at_demodulated_pair_f32;

/**
 * The integer constants of a fixed-point observer (order 2 or 3), as `angletrack design
 * --dtype fixed --format c` prints them: filled by `at_fixed_gains_from_constants`
 * (checked) or `at_fixed_gains_new` (quantised from float gains), or written;
 * `at_chain_fixed_new` checks them (a zeroed one is refused: `AT_ERR_ORDER`).
 */
typedef struct at_fixed_gains {
  /**
   * The gains' integer multipliers (`m3` unused at order 2).
   */
  int32_t multiplier[3];
  /**
   * The observer's order, 2 or 3.
   */
  uint32_t order;
  /**
   * The acceleration's shift (1 to 15 at order 3, 0 at order 2).
   */
  uint32_t acceleration_shift;
  /**
   * The sample period (s).
   */
  double sample_period_s;
} at_fixed_gains;

/**
 * The ADC of a fixed-point chain (the core's `AdcCounts`): each count less
 * `mid_scale_counts`, shifted left by `shift` (0 to 15) bits to the observer's 16-bit range,
 * saturated. Plain: write it (`{2048, 4}` for a 12-bit offset-binary ADC), or fill it with
 * `at_adc_counts_offset_binary` or `at_adc_counts_twos_complement`; `at_chain_fixed_new`
 * checks it.
 */
typedef struct at_adc_counts {
  /**
   * The count of a zero signal (at most 2^30 in magnitude): `2^(bits-1)` for an offset
   * binary ADC, 0 for a two's complement one.
   */
  int32_t mid_scale_counts;
  /**
   * The left shift (0 to 15) to the observer's 16 bits: `16 - bits`.
   */
  uint32_t shift;
} at_adc_counts;

/**
 * The sensor's angle error `d` in Q15 rad (2^-15 rad) at the angles `-pi + 2 pi k / 256`
 * (the top 8 bits of the binary angle, offset by half a turn), for the fixed-point chain,
 * which rotates each sample by `-d` in integers at the predicted binary angle. Each entry
 * within 8192 (0.25 rad); all zero corrects nothing. Made by
 * `at_angle_table_fixed_from_errors` or `_from_harmonics`, or kept `const`.
 */
typedef struct at_angle_table_fixed {
  /**
   * `d` (Q15 rad) at the angle `-pi + 2 pi k / 256`, index `k`.
   */
  int16_t errors_q15[AT_ANGLE_TABLE_LENGTH];
} at_angle_table_fixed;

/**
 * The checked configuration of one fixed-point signal chain, made by `at_chain_fixed_new`.
 * Immutable once made: one serves any number of channels (`at_chain_state_fixed`). Place it
 * anywhere; copy it by assignment; never write its fields. A zeroed one is refused.
 */
typedef struct at_chain_fixed {
  /**
   * Private: which Rust value `storage` holds (0: none; in a state, a fresh one).
   */
  uint32_t tag;
  /**
   * Private: the layout of the build that wrote it.
   */
  uint32_t layout;
  /**
   * Private: the Rust value.
   */
  uint64_t storage[AT_CHAIN_FIXED_WORDS];
} at_chain_fixed;

/**
 * The whole configuration of a fixed-point chain in integers, as `angletrack export
 * --format c` writes it (`static const`, in flash) for `at_chain_fixed_from_constants`:
 * the observer's `gains`, the words of its monitor's thresholds (`monitor`: enabled,
 * loss of signal, degradation low and high, roundness low and high, loss of tracking,
 * the largest speed, the per-sample tracking-error level in Q15; the core's
 * `FixedGains::monitor_words`) and the optional stages,
 * each NULL when absent: the ADC, a stored calibration and the angle-correction table.
 */
typedef struct at_chain_fixed_constants {
  /**
   * The observer's integer gains.
   */
  struct at_fixed_gains gains;
  /**
   * The monitor's threshold words.
   */
  uint32_t monitor[9];
  /**
   * The ADC, or NULL (then the chain takes `int16` samples).
   */
  const struct at_adc_counts *adc;
  /**
   * The stored calibration in its integers, or NULL: the offsets in the observer's
   * 16-bit counts, the sine gain `A_c / (A_s cos phi)` (positive) and the cross gain
   * `tan phi` (within +-16384), both Q14 (the core's `FixedCalibration::q14_words`).
   */
  const int16_t (*calibration_q14)[4];
  /**
   * The angle correction table, or NULL.
   */
  const struct at_angle_table_fixed *table;
} at_chain_fixed_constants;

/**
 * One channel's state of a fixed-point chain (the observer's: the stages keep none). A
 * zeroed one is fresh (as after `at_chain_state_fixed_reset`): the observer initialises
 * itself from its first sample. Place it anywhere; copy it by assignment; never write its
 * fields.
 */
typedef struct at_chain_state_fixed {
  /**
   * Private: which Rust value `storage` holds (0: none; in a state, a fresh one).
   */
  uint32_t tag;
  /**
   * Private: the layout of the build that wrote it.
   */
  uint32_t layout;
  /**
   * Private: the Rust value.
   */
  uint64_t storage[AT_CHAIN_STATE_FIXED_WORDS];
} at_chain_state_fixed;

/**
 * What the fixed-point observer knows after a sample, in its integers.
 */
typedef struct at_fixed_estimate {
  /**
   * Binary angle: 2^32 per turn, `INT32_MIN` is -pi (rad = angle * 2 pi / 2^32).
   */
  int32_t angle;
  /**
   * Whole turns since initialisation: the position is `turns + angle / 2^32` turns.
   */
  int64_t turns;
  /**
   * Speed (2^-32 turn per sample).
   */
  int32_t speed;
  /**
   * Acceleration (2^-63 turn per sample^2); 0 for a 2nd-order observer.
   */
  int64_t acceleration;
  /**
   * Normalised phase error (Q15: 32768 is 1), about the sine of the phase error.
   */
  int32_t phase_error;
  /**
   * The monitor's last window's faults (`AT_FAULT_*` bits), or
   * `AT_FAULT_INVALID_ARGUMENT` alone when the call's arguments were refused.
   */
  uint32_t faults;
} at_fixed_estimate;

/**
 * The demodulator's settings (the core's `DemodulatorSettings`): start from
 * `at_demodulator_settings_f32_new`, which fills in the defaults.
 */
typedef struct at_demodulator_settings_f32 {
  /**
   * The declared excitation carrier frequency (Hz), tracked within `max_carrier_error`.
   */
  float carrier_hz;
  /**
   * The ADC's sample rate (Hz): at least 4 times the carrier, any ratio.
   */
  float adc_rate_hz;
  /**
   * A winding's nominal carrier amplitude at the ADC (counts, peak): the pairs are
   * divided by it (nominal amplitude 1).
   */
  float carrier_amplitude_counts;
  /**
   * The lowest ADC code.
   */
  float adc_min_code;
  /**
   * The highest ADC code.
   */
  float adc_max_code;
  /**
   * A raw sample within this many counts of a rail counts as clipped (default 1/256 of
   * the range).
   */
  float clip_margin_counts;
  /**
   * Loss of excitation below this carrier amplitude, relative to nominal (default 0.25).
   */
  float loss_of_excitation;
  /**
   * Weak excitation below this carrier amplitude, relative to nominal (default 0.7).
   */
  float weak_excitation;
  /**
   * Phase drift (the carrier loop out of lock) beyond this phase error (rad, default
   * 44 degrees, at most pi/2).
   */
  float phase_drift_bound_rad;
  /**
   * The carrier delay (rad, positive when the windings lag) the half turn is resolved
   * around (default 0): after the excitation when its samples are pushed, else after a
   * carrier of phase 0 at the first sample.
   */
  float expected_delay_rad;
  /**
   * The carrier loop's natural frequency times the carrier period (rad, default 0.3).
   */
  float carrier_loop_bandwidth;
  /**
   * The largest relative carrier frequency error tracked (default 0.03).
   */
  float max_carrier_error;
  /**
   * The carrier periods the loop acquires over before the first pair (default 24).
   */
  uint32_t startup_periods;
} at_demodulator_settings_f32;

/**
 * The checked configuration of a synchronous demodulator, made by `at_demodulator_f32_new`
 * (reference tables, scale, thresholds). Immutable once made; place it anywhere; copy it by
 * assignment; never write its fields. A zeroed one is refused.
 */
typedef struct at_demodulator_f32 {
  /**
   * Private: which Rust value `storage` holds (0: none; in a state, a fresh one).
   */
  uint32_t tag;
  /**
   * Private: the layout of the build that wrote it.
   */
  uint32_t layout;
  /**
   * Private: the Rust value.
   */
  uint64_t storage[AT_DEMODULATOR_F32_WORDS];
} at_demodulator_f32;

/**
 * One channel's demodulator state: partial sums, the carrier delay, latched front-end
 * faults. A zeroed one is fresh (as after `at_demodulator_state_f32_reset`): its next
 * sample is the first of a carrier period (excitation phase 0). Place it anywhere; copy it
 * by assignment; never write its fields.
 */
typedef struct at_demodulator_state_f32 {
  /**
   * Private: which Rust value `storage` holds (0: none; in a state, a fresh one).
   */
  uint32_t tag;
  /**
   * Private: the layout of the build that wrote it.
   */
  uint32_t layout;
  /**
   * Private: the Rust value.
   */
  uint64_t storage[AT_DEMODULATOR_STATE_F32_WORDS];
} at_demodulator_state_f32;

/**
 * Success.
 */
#define AT_OK 0

/**
 * A pointer argument was NULL; nothing was written.
 */
#define AT_ERR_NULL_POINTER 1

/**
 * The observer order was not 2 or 3.
 */
#define AT_ERR_ORDER 2

/**
 * A struct argument was not made by its constructor (`at_chain_f32_new`, `at_adc_f32_new`, ...).
 */
#define AT_ERR_NOT_INITIALISED 3

/**
 * The calibration mode was not one of `AT_CALIBRATION_*`.
 */
#define AT_ERR_MODE 4

/**
 * A struct argument was made by another build of the library (its layout word, written
 * with its tag, is not this build's: another layout version `AT_LAYOUT_VERSION`, library
 * version, struct size or target); it was not read. Make it again with this build.
 */
#define AT_ERR_OTHER_BUILD 5

/**
 * `at_chain_f32_new` was given both a stored calibration and the online calibration's
 * settings (a chain has one calibration stage), or both the harmonic angle correction and
 * its table (one angle correction).
 */
#define AT_ERR_STAGES 6

/**
 * A parameter this version of the C API has no code for (a newer core's).
 */
#define AT_ERR_OTHER_PARAMETER 63

/**
 * `sample_period_s`: not finite, not positive, or outside [1 ps, 1000 s].
 */
#define AT_ERR_SAMPLE_PERIOD_S 16

/**
 * `gains[0]` (l1): not finite, or outside the stability region of the discrete loop.
 */
#define AT_ERR_GAINS_0 17

/**
 * `gains[1]` (l2): not finite, or outside the stability region of the discrete loop.
 */
#define AT_ERR_GAINS_1 18

/**
 * `gains[2]` (l3): not finite, or outside the stability region of the discrete loop.
 */
#define AT_ERR_GAINS_2 19

/**
 * Fault threshold `max_input_amplitude`.
 */
#define AT_ERR_MAX_INPUT_AMPLITUDE 20

/**
 * Fault threshold `loss_of_signal`.
 */
#define AT_ERR_LOSS_OF_SIGNAL 21

/**
 * Fault threshold `degradation_high`.
 */
#define AT_ERR_DEGRADATION_HIGH 22

/**
 * Fault threshold `degradation_low`.
 */
#define AT_ERR_DEGRADATION_LOW 23

/**
 * Fault threshold `loss_of_tracking`.
 */
#define AT_ERR_LOSS_OF_TRACKING 24

/**
 * Fault threshold `filter_factor`.
 */
#define AT_ERR_FILTER_FACTOR 25

/**
 * Fault threshold `false_lock`.
 */
#define AT_ERR_FALSE_LOCK 26

/**
 * Fault threshold `nominal_amplitude`.
 */
#define AT_ERR_NOMINAL_AMPLITUDE 27

/**
 * Fault threshold `max_speed_rad_s`.
 */
#define AT_ERR_MAX_SPEED_RAD_S 28

/**
 * ADC `mid_scale_counts`.
 */
#define AT_ERR_MID_SCALE_COUNTS 29

/**
 * ADC `counts_per_unit`.
 */
#define AT_ERR_COUNTS_PER_UNIT 30

/**
 * ADC resolution `bits`.
 */
#define AT_ERR_BITS 31

/**
 * Sensor calibration `offset_c`.
 */
#define AT_ERR_OFFSET_C 32

/**
 * Sensor calibration `offset_s`.
 */
#define AT_ERR_OFFSET_S 33

/**
 * Sensor calibration `amplitude_c`.
 */
#define AT_ERR_AMPLITUDE_C 34

/**
 * Sensor calibration `amplitude_s`.
 */
#define AT_ERR_AMPLITUDE_S 35

/**
 * Sensor calibration `quadrature_rad`.
 */
#define AT_ERR_QUADRATURE_RAD 36

/**
 * Calibration setting `min_speed_rad_s`.
 */
#define AT_ERR_MIN_SPEED_RAD_S 37

/**
 * Calibration setting `max_offset`.
 */
#define AT_ERR_MAX_OFFSET 38

/**
 * Calibration setting `max_amplitude_mismatch`.
 */
#define AT_ERR_MAX_AMPLITUDE_MISMATCH 39

/**
 * Calibration setting `max_quadrature_rad`.
 */
#define AT_ERR_MAX_QUADRATURE_RAD 40

/**
 * Angle correction: a coefficient not finite, or their total `sum |a_k| + |b_k|` above
 * 0.25 rad.
 */
#define AT_ERR_ANGLE_CORRECTION 41

/**
 * Demodulator setting `carrier_hz`.
 */
#define AT_ERR_CARRIER_HZ 42

/**
 * Samples per carrier period (the excitation's schedule; the demodulator takes `adc_rate_hz`).
 */
#define AT_ERR_SAMPLES_PER_PERIOD 43

/**
 * Demodulator setting `carrier_amplitude_counts`.
 */
#define AT_ERR_CARRIER_AMPLITUDE_COUNTS 44

/**
 * Demodulator settings `adc_min_code`, `adc_max_code`, `clip_margin_counts`.
 */
#define AT_ERR_ADC_RANGE 45

/**
 * Demodulator setting `loss_of_excitation`.
 */
#define AT_ERR_LOSS_OF_EXCITATION 46

/**
 * Demodulator setting `phase_drift_bound_rad`.
 */
#define AT_ERR_PHASE_DRIFT_BOUND_RAD 47

/**
 * Demodulator setting `expected_delay_rad`.
 */
#define AT_ERR_EXPECTED_DELAY_RAD 48

/**
 * Demodulator setting `carrier_loop_bandwidth`.
 */
#define AT_ERR_CARRIER_LOOP_BANDWIDTH 49

/**
 * Demodulator setting `adc_rate_hz` (at least 4 times the carrier).
 */
#define AT_ERR_ADC_RATE_HZ 53

/**
 * Demodulator setting `weak_excitation`.
 */
#define AT_ERR_WEAK_EXCITATION 54

/**
 * Demodulator setting `max_carrier_error`.
 */
#define AT_ERR_MAX_CARRIER_ERROR 55

/**
 * Demodulator setting `startup_periods`.
 */
#define AT_ERR_STARTUP_PERIODS 50

/**
 * ADC setting `shift` (0 to 15).
 */
#define AT_ERR_SHIFT 51

/**
 * An angle error `curve` of fewer than 2 points.
 */
#define AT_ERR_CURVE 52

/**
 * Fault threshold `tracking_error`.
 */
#define AT_ERR_TRACKING_ERROR 56

/**
 * Fault threshold `magnitude_tolerance`.
 */
#define AT_ERR_MAGNITUDE_TOLERANCE 57

#ifdef __cplusplus
extern "C" {
#endif // __cplusplus

/**
 * The default fault thresholds for signals of amplitude `nominal_amplitude` (input units:
 * 1 for samples in units of full scale, as an ADC stage of `at_adc_f32_offset_binary`
 * gives them).
 */
struct at_fault_thresholds_f32 at_fault_thresholds_f32_for_amplitude(float nominal_amplitude);

/**
 * The C structs' layout version of the library (`AT_LAYOUT_VERSION` of the header it was
 * built with): a firmware compares it with the header's at start-up. Every struct also
 * carries its build's layout beside its tag, so that one written by another build is
 * refused (`AT_ERR_OTHER_BUILD`) rather than read.
 */
uint32_t at_layout_version(void);

/**
 * The text of a status (static, NUL-terminated): the name of the refused parameter as the
 * Rust core names it (`"gains[2] (l3)"`, `"sample_period_s"`, ...), or what went wrong.
 */
const char *at_status_message(at_status status);

/**
 * The name of one `AT_FAULT_*` bit (static, NUL-terminated: `"loss of signal"`, ...), or
 * `"unknown fault"`.
 */
const char *at_fault_name(uint32_t bit);

/**
 * Checks `order` (2 or 3) discrete gains `gains` (l1, l2[, l3], dimensionless, as
 * `angletrack design --format c` writes them) and the sample period `sample_period_s` (s),
 * and writes them, with the core's default fault thresholds, to the plain `out`.
 * Returns `AT_OK`, or the status naming the refused parameter (`AT_ERR_GAINS_2` for an
 * unstable `l3`, ...); `out` is unchanged on error.
 *
 * # Safety
 * `gains` points to `order` floats; see the header's introduction.
 */
at_status at_gains_f32_new(const float *gains,
                           size_t order,
                           float sample_period_s,
                           struct at_gains_f32 *out);

/**
 * Writes to `out` an ADC front end removing `mid_scale_counts` (the reading of a zero
 * signal, at most 2^30 in magnitude) and dividing by `counts_per_unit` (positive), with no
 * range of codes stated (`at_adc_f32_set_range` states it; without it a chain measures
 * the rails as the extremes held flat).
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_adc_f32_new(int32_t mid_scale_counts, float counts_per_unit, struct at_adc_f32 *out);

/**
 * Writes to `out` the front end of an unsigned (offset binary) ADC of `bits` bits (2 to
 * 31): samples in units of full scale (+-1), its range of codes stated (0 to
 * `2^bits - 1`: a chain flags clipping at them, `at_adc_f32_set_range`).
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_adc_f32_offset_binary(uint32_t bits, struct at_adc_f32 *out);

/**
 * Writes to `out` the front end of a signed (two's complement) ADC of `bits` bits (2 to
 * 32): samples in units of full scale (+-1), its range of codes stated (`-2^(bits-1)` to
 * `2^(bits-1) - 1`: a chain flags clipping at them, `at_adc_f32_set_range`).
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_adc_f32_twos_complement(uint32_t bits, struct at_adc_f32 *out);

/**
 * States the range of codes of the ADC `adc`: its lowest `min_counts` and highest
 * `max_counts` (`AT_ERR_ADC_RANGE` unless `min_counts < max_counts`; `adc` unchanged on
 * error). A chain with this ADC (`at_chain_f32_new`) flags a sample with a channel at or
 * beyond a rail `AT_FAULT_FRONT_END` (`AT_FRONT_END_FAULT_CLIPPING`), and coasts on its
 * prediction through one with both channels there. Without a stated range the chain
 * measures the rails on the counts as they come (the core's `HeldRailCheck`: an extreme a
 * channel holds for 4 consecutive samples while the other moves, the samples piled up
 * there, on a signal spanning both sides of mid-scale), a weaker test.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_adc_f32_set_range(struct at_adc_f32 *adc, int32_t min_counts, int32_t max_counts);

/**
 * The online calibration's default settings (the core's `CalibrationSettings::default`).
 */
struct at_calibration_settings_f32 at_calibration_settings_f32_default(void);

/**
 * Builds a signal chain into `out`: the observer `gains` (required) after the optional
 * stages, each NULL when absent, in this order: the ADC front end `adc` (then the chain
 * takes counts: `at_chain_f32_track_u16`, ...; with its range stated, a sample with a
 * channel at or beyond a rail is flagged `AT_FAULT_FRONT_END` and one with both there is
 * coasted through: `at_adc_f32_set_range`), the front-end faults a demodulator gave its
 * pairs (`at_chain_f32_track_demodulated`: the observer coasts through a loss of
 * excitation), one calibration stage (a stored calibration
 * `stored`, applied to every sample, or the online calibration with its `settings`,
 * learning per channel in `at_chain_state_f32`; not both: `AT_ERR_STAGES`), and one angle
 * correction (the harmonic `correction` or its `table`, the same cost whatever the error's
 * shape; not both: `AT_ERR_STAGES`). Every stage is checked (`AT_ERR_*` naming the
 * refused parameter, `AT_ERR_ANGLE_CORRECTION`, ...; `out` unchanged on error); the stages
 * are copied, so they need not outlive the call.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_chain_f32_new(const struct at_gains_f32 *gains,
                           const struct at_adc_f32 *adc,
                           const struct at_sensor_calibration_f32 *stored,
                           const struct at_calibration_settings_f32 *settings,
                           const struct at_angle_correction_f32 *correction,
                           const struct at_angle_correction_table_f32 *table,
                           struct at_chain_f32 *out);

/**
 * The estimate `state` holds for `chain` (its last sample's; the observer's faults, the
 * stages' latched in the state). Refused arguments: `AT_FAULT_INVALID_ARGUMENT`.
 *
 * # Safety
 * See the header's introduction.
 */
struct at_estimate_f32 at_chain_f32_estimate(const struct at_chain_f32 *chain,
                                             const struct at_chain_state_f32 *state);

/**
 * Makes `state` fresh: the observer initialises itself from its next sample, the online
 * calibration is off with nothing learned. NULL is ignored.
 *
 * # Safety
 * See the header's introduction.
 */
void at_chain_state_f32_reset(struct at_chain_state_f32 *state);

/**
 * Returns the faults latched in `state` (the observer's and the stages', `AT_FAULT_*`
 * bits) and clears them. 0 for NULL.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_state_f32_clear_faults(struct at_chain_state_f32 *state);

/**
 * Sets the mode of the online calibration in `state`: `AT_CALIBRATION_LEARNING`,
 * `_FROZEN` or `_OFF` (the calibration is kept). Effective in a chain with the online
 * calibration stage.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_chain_state_f32_set_calibration_mode(struct at_chain_state_f32 *state, uint32_t mode);

/**
 * The mode of the online calibration in `state` (`AT_CALIBRATION_*`; off for NULL).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_state_f32_calibration_mode(const struct at_chain_state_f32 *state);

/**
 * Loads a stored calibration into the online calibration of `state` (checked; unchanged on
 * error), frozen: it corrects and learns nothing until set to learn, continuing from it.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_chain_state_f32_load_calibration(struct at_chain_state_f32 *state,
                                              const struct at_sensor_calibration_f32 *stored);

/**
 * Writes the calibration the online calibration of `state` applies (to store in flash) to
 * `out`.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_chain_state_f32_calibration(const struct at_chain_state_f32 *state,
                                         struct at_sensor_calibration_f32 *out);

/**
 * The turns the online calibration of `state` has learned since started or loaded; 0 for
 * NULL.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_state_f32_turns_learned(const struct at_chain_state_f32 *state);

/**
 * Where the online calibration of `state` stands: `AT_CALIBRATION_FINDING_CENTRE`,
 * `AT_CALIBRATION_CENTRED` or `AT_CALIBRATION_STALLED`; `AT_CALIBRATION_FINDING_CENTRE`
 * for NULL or another build's state.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_state_f32_calibration_status(const struct at_chain_state_f32 *state);

/**
 * Writes to `out` the chain `chain` with a winding check: a winding open or shorted (one
 * winding reading below a quarter of `nominal_amplitude` where the observer's prediction
 * puts at least half of it, the other agreeing with the prediction) is flagged
 * `AT_FAULT_FRONT_END` (`AT_FRONT_END_FAULT_WINDING`) and coasted through while it holds.
 * `nominal_amplitude` is the windings' peak in the chain's input units after the
 * calibration (1 for a demodulator's pairs; `AT_ERR_NOMINAL_AMPLITUDE` unless finite and
 * positive). `out` unchanged on error.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_chain_f32_with_winding_check(const struct at_chain_f32 *chain,
                                          float nominal_amplitude,
                                          struct at_chain_f32 *out);

/**
 * Returns the front-end faults latched in `state` (`AT_FRONT_END_FAULT_*` bits: clipping
 * against the ADC's range, the demodulator's faults, a winding open or shorted) and clears
 * them. 0 for NULL.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_state_f32_clear_front_end_faults(struct at_chain_state_f32 *state);

/**
 * One sample `(y_c, y_s)` through the chain's stages and observer, the state only (the
 * cheapest per-sample call; `at_chain_f32_estimate` reads the estimate on demand, the
 * stages' faults are latched in the state). Returns 0, or `AT_FAULT_INVALID_ARGUMENT`
 * (nothing changed) for a NULL pointer, a chain not made or a struct of another build. A
 * chain with an ADC stage takes `y_c`, `y_s` as already scaled (the ADC is for counts).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_f32_track(const struct at_chain_f32 *chain,
                            struct at_chain_state_f32 *state,
                            float y_c,
                            float y_s);

/**
 * `at_chain_f32_track`, then the estimate, which carries the stages' faults.
 *
 * # Safety
 * See the header's introduction.
 */
struct at_estimate_f32 at_chain_f32_update(const struct at_chain_f32 *chain,
                                           struct at_chain_state_f32 *state,
                                           float y_c,
                                           float y_s);

/**
 * `at_chain_f32_track` on raw `i16` ADC counts, through the chain's ADC stage
 * (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_f32_track_i16(const struct at_chain_f32 *chain,
                                struct at_chain_state_f32 *state,
                                int16_t raw_c,
                                int16_t raw_s);

/**
 * `at_chain_f32_update` on raw `i16` ADC counts, through the chain's ADC stage
 * (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
 *
 * # Safety
 * See the header's introduction.
 */
struct at_estimate_f32 at_chain_f32_update_i16(const struct at_chain_f32 *chain,
                                               struct at_chain_state_f32 *state,
                                               int16_t raw_c,
                                               int16_t raw_s);

/**
 * `at_chain_f32_track` on raw `u16` ADC counts, through the chain's ADC stage
 * (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_f32_track_u16(const struct at_chain_f32 *chain,
                                struct at_chain_state_f32 *state,
                                uint16_t raw_c,
                                uint16_t raw_s);

/**
 * `at_chain_f32_update` on raw `u16` ADC counts, through the chain's ADC stage
 * (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
 *
 * # Safety
 * See the header's introduction.
 */
struct at_estimate_f32 at_chain_f32_update_u16(const struct at_chain_f32 *chain,
                                               struct at_chain_state_f32 *state,
                                               uint16_t raw_c,
                                               uint16_t raw_s);

/**
 * `at_chain_f32_track` on raw `i32` ADC counts, through the chain's ADC stage
 * (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_f32_track_i32(const struct at_chain_f32 *chain,
                                struct at_chain_state_f32 *state,
                                int32_t raw_c,
                                int32_t raw_s);

/**
 * `at_chain_f32_update` on raw `i32` ADC counts, through the chain's ADC stage
 * (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
 *
 * # Safety
 * See the header's introduction.
 */
struct at_estimate_f32 at_chain_f32_update_i32(const struct at_chain_f32 *chain,
                                               struct at_chain_state_f32 *state,
                                               int32_t raw_c,
                                               int32_t raw_s);

/**
 * `at_chain_f32_track` on a demodulator's pair (`at_demodulator_f32_push`), with the
 * front-end faults of its window: while one invalidates the pair (loss of excitation, a
 * winding open or shorted) the observer coasts on its prediction instead of using it, and
 * every fault is latched as `AT_FAULT_FRONT_END` (`at_chain_state_f32_clear_front_end_faults`
 * gives the front-end bits). Returns 0, or `AT_FAULT_INVALID_ARGUMENT` (nothing changed)
 * for refused arguments, a chain with an ADC stage among them (the demodulator takes the
 * counts: build the chain without one).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_f32_track_demodulated(const struct at_chain_f32 *chain,
                                        struct at_chain_state_f32 *state,
                                        const struct at_demodulated_pair_f32 *pair);

/**
 * `at_chain_f32_track_demodulated`, then the estimate, which carries `AT_FAULT_FRONT_END`
 * while the pair has a front-end fault.
 *
 * # Safety
 * See the header's introduction.
 */
struct at_estimate_f32 at_chain_f32_update_demodulated(const struct at_chain_f32 *chain,
                                                       struct at_chain_state_f32 *state,
                                                       const struct at_demodulated_pair_f32 *pair);

/**
 * Checks the integer constants of a fixed-point observer of order `order` (2 or 3), as
 * `angletrack design --dtype fixed --format c --name NAME` prints them (`NAME_gain_multiplier`,
 * `NAME_ORDER`, `NAME_ACCELERATION_SHIFT`, `NAME_SAMPLE_PERIOD_S`): each multiplier
 * positive, the shift 1 to 15 (0 at order 2), the loop they represent stable. Writes them
 * to the plain `out` (the monitor's thresholds are the chain's: `at_chain_fixed_new`);
 * `out` is unchanged on error (`AT_ERR_GAINS_0`..`_2` naming the gain,
 * `AT_ERR_SAMPLE_PERIOD_S`, ...).
 *
 * # Safety
 * `multiplier` points to `order` integers; see the header's introduction.
 */
at_status at_fixed_gains_from_constants(const int32_t *multiplier,
                                        size_t order,
                                        uint32_t acceleration_shift,
                                        double sample_period_s,
                                        struct at_fixed_gains *out);

/**
 * Quantises `order` (2 or 3) float gains `gains` (l1, l2[, l3], as `angletrack design
 * --format c` writes them and `at_gains_f32_new` takes them) at the sample period
 * `sample_period_s` (s) into a fixed-point observer's configuration, checked (a gain that
 * rounds to zero or does not fit is refused, naming it), to `out` (unchanged on error).
 * Costs double-precision arithmetic: at start-up, or on the host (then embed the
 * constants and use `at_fixed_gains_from_constants`).
 *
 * # Safety
 * `gains` points to `order` floats; see the header's introduction.
 */
at_status at_fixed_gains_new(const float *gains,
                             size_t order,
                             double sample_period_s,
                             struct at_fixed_gains *out);

/**
 * Builds a fixed-point signal chain into `out`: the fixed-point observer `gains` (required;
 * its monitor set here for `nominal_amplitude_counts`, the amplitude of the observer's
 * 16-bit input after the stages, 16384 to 46341, with the roundness check at a tolerance
 * of 0.1, or off for 0: `AT_ERR_NOMINAL_AMPLITUDE`)
 * after the optional stages, each NULL when absent: the ADC `adc` (then the chain takes
 * counts of any width, `at_chain_fixed_track_u16`, `_i32`, ...; without it, `int16`
 * samples only), a stored `calibration` (offsets and amplitudes in the observer's 16-bit
 * counts, after the ADC's shift; converted to integers: `AT_ERR_OFFSET_C`, ...,
 * `AT_ERR_AMPLITUDE_S` for a sine channel less than half the cosine's), and the angle
 * correction `table` (`AT_ERR_ANGLE_CORRECTION`). `out` unchanged on error; the stages are
 * copied, so they need not outlive the call. Double-precision arithmetic: at start-up.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_chain_fixed_new(const struct at_fixed_gains *gains,
                             const struct at_adc_counts *adc,
                             const struct at_sensor_calibration_f32 *calibration,
                             const struct at_angle_table_fixed *table,
                             double nominal_amplitude_counts,
                             struct at_chain_fixed *out);

/**
 * Builds the fixed-point chain of `constants` into `out`: the configuration as
 * `angletrack export --format c` writes it (`NAME_chain`, `static const`), checked by
 * integer comparisons only (`AT_ERR_GAINS_0`.., `AT_ERR_SAMPLE_PERIOD_S`, a threshold's
 * or a stage's status), without floating-point arithmetic: what a firmware without an
 * FPU calls at start-up. The loop's stability is not checked again (the export
 * checked it). `out` unchanged on error.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_chain_fixed_from_constants(const struct at_chain_fixed_constants *constants,
                                        struct at_chain_fixed *out);

/**
 * The settings of an offset-binary (unsigned) ADC of `bits` bits (2 to 16): mid-scale
 * `2^(bits-1)`, shifted by `16 - bits`, to `out` (`AT_ERR_BITS`; `out` unchanged on error).
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_adc_counts_offset_binary(uint32_t bits, struct at_adc_counts *out);

/**
 * The settings of a two's complement (signed) ADC of `bits` bits (2 to 16): mid-scale 0,
 * shifted by `16 - bits`, to `out` (`AT_ERR_BITS`; `out` unchanged on error).
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_adc_counts_twos_complement(uint32_t bits, struct at_adc_counts *out);

/**
 * Writes to `out` the chain `chain` with the ADC's range of codes stated: its lowest
 * `min_counts` and highest `max_counts` (raw counts, as the chain takes them;
 * `AT_ERR_ADC_RANGE` unless `min_counts < max_counts`). A sample with a channel at or
 * beyond a rail is flagged `AT_FAULT_FRONT_END` (`AT_FRONT_END_FAULT_CLIPPING`), and one
 * with both there is coasted through. `out` unchanged on error. Without a stated range a
 * chain with an ADC measures the rails on the counts as they come (the core's
 * `HeldRailCheck`, as `at_adc_f32_set_range` says of the float chain), a weaker test.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_chain_fixed_with_adc_range(const struct at_chain_fixed *chain,
                                        int32_t min_counts,
                                        int32_t max_counts,
                                        struct at_chain_fixed *out);

/**
 * Returns the front-end faults latched in `state` (`AT_FRONT_END_FAULT_*` bits: clipping
 * against the ADC's stated range or the rails measured) and clears them. 0 for NULL.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_state_fixed_clear_front_end_faults(struct at_chain_state_fixed *state);

/**
 * The multi-turn position of `estimate` (rad): `2 pi (turns + angle / 2^32)`; 0 for NULL.
 * Double-precision arithmetic: for a host, or out of the sample loop.
 *
 * # Safety
 * See the header's introduction.
 */
double at_chain_fixed_position_rad(const struct at_chain_fixed *chain,
                                   const struct at_fixed_estimate *estimate);

/**
 * The speed of `estimate` (rad/s) at the sample period of `chain`'s observer; 0 for NULL
 * or a chain not made. Double-precision arithmetic: for a host, or out of the sample loop.
 *
 * # Safety
 * See the header's introduction.
 */
double at_chain_fixed_speed_rad_s(const struct at_chain_fixed *chain,
                                  const struct at_fixed_estimate *estimate);

/**
 * Makes `state` fresh: the observer initialises itself from its next sample. NULL is
 * ignored.
 *
 * # Safety
 * See the header's introduction.
 */
void at_chain_state_fixed_reset(struct at_chain_state_fixed *state);

/**
 * Returns the faults latched in `state` (`AT_FAULT_*` bits) and clears them. 0 for NULL.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_state_fixed_clear_faults(struct at_chain_state_fixed *state);

/**
 * The fixed-point table of the harmonic angle error `harmonics` (as `angletrack calibrate`
 * learns it; checked as `at_chain_f32_new` checks it: `AT_ERR_ANGLE_CORRECTION`), rounded to
 * Q15, to `out` (unchanged on error).
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_angle_table_fixed_from_harmonics(const struct at_angle_correction_f32 *harmonics,
                                              struct at_angle_table_fixed *out);

/**
 * The float table of the harmonic angle error `harmonics` (checked:
 * `AT_ERR_ANGLE_CORRECTION`), to `out` (unchanged on error).
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_angle_correction_table_f32_from_harmonics(const struct at_angle_correction_f32 *harmonics,
                                                       struct at_angle_correction_table_f32 *out);

/**
 * Checks a float table (each entry finite and within 0.25 rad): `AT_OK` or
 * `AT_ERR_ANGLE_CORRECTION` (`at_chain_f32_new` checks it again).
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_angle_correction_table_f32_check(const struct at_angle_correction_table_f32 *table);

/**
 * The estimate `state` holds for `chain` (its last sample's; all zero for a fresh state).
 * Refused arguments: `AT_FAULT_INVALID_ARGUMENT`.
 *
 * # Safety
 * See the header's introduction.
 */
struct at_fixed_estimate at_chain_fixed_estimate(const struct at_chain_fixed *chain,
                                                 const struct at_chain_state_fixed *state);

/**
 * The fixed-point table of `errors_rad` (`AT_ANGLE_TABLE_LENGTH` errors in rad at the
 * angles `-pi + 2 pi k / 256`, each finite and within 0.25 rad: `AT_ERR_ANGLE_CORRECTION`),
 * rounded to Q15, to `out` (unchanged on error).
 *
 * # Safety
 * `errors_rad` points to `AT_ANGLE_TABLE_LENGTH` floats; see the header's introduction.
 */
at_status at_angle_table_fixed_from_errors(const float *errors_rad,
                                           struct at_angle_table_fixed *out);

/**
 * The float table of a measured error curve: `curve[j]` (rad) at the angle
 * `-pi + 2 pi j / points` (`points` at least 2: `AT_ERR_CURVE`), resampled by periodic linear
 * interpolation (entries finite and within 0.25 rad: `AT_ERR_ANGLE_CORRECTION`), to `out`
 * (unchanged on error).
 *
 * # Safety
 * `curve` points to `points` floats; see the header's introduction.
 */
at_status at_angle_correction_table_f32_from_curve(const float *curve,
                                                   size_t points,
                                                   struct at_angle_correction_table_f32 *out);

/**
 * One sample of `int16` counts through the chain's stages and observer, the state only (the
 * cheapest per-sample call; `at_chain_fixed_estimate` reads the estimate on demand). A
 * chain without an ADC takes `int16` samples as they are. Returns 0, or
 * `AT_FAULT_INVALID_ARGUMENT` (nothing changed) for a NULL pointer, a chain not made or a
 * struct of another build.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_fixed_track_i16(const struct at_chain_fixed *chain,
                                  struct at_chain_state_fixed *state,
                                  int16_t raw_c,
                                  int16_t raw_s);

/**
 * `at_chain_fixed_track_i16`, then the estimate; on refused arguments an estimate whose
 * faults are `AT_FAULT_INVALID_ARGUMENT` (the rest 0).
 *
 * # Safety
 * See the header's introduction.
 */
struct at_fixed_estimate at_chain_fixed_update_i16(const struct at_chain_fixed *chain,
                                                   struct at_chain_state_fixed *state,
                                                   int16_t raw_c,
                                                   int16_t raw_s);

/**
 * `at_chain_fixed_track_i16` on `uint16` counts, through the chain's ADC
 * (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_fixed_track_u16(const struct at_chain_fixed *chain,
                                  struct at_chain_state_fixed *state,
                                  uint16_t raw_c,
                                  uint16_t raw_s);

/**
 * `at_chain_fixed_track_u16`, then the estimate; on refused arguments an estimate whose
 * faults are `AT_FAULT_INVALID_ARGUMENT` (the rest 0).
 *
 * # Safety
 * See the header's introduction.
 */
struct at_fixed_estimate at_chain_fixed_update_u16(const struct at_chain_fixed *chain,
                                                   struct at_chain_state_fixed *state,
                                                   uint16_t raw_c,
                                                   uint16_t raw_s);

/**
 * `at_chain_fixed_track_i16` on `int32` counts, through the chain's ADC
 * (`AT_FAULT_INVALID_ARGUMENT` for a chain without one).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_fixed_track_i32(const struct at_chain_fixed *chain,
                                  struct at_chain_state_fixed *state,
                                  int32_t raw_c,
                                  int32_t raw_s);

/**
 * `at_chain_fixed_track_i32`, then the estimate; on refused arguments an estimate whose
 * faults are `AT_FAULT_INVALID_ARGUMENT` (the rest 0).
 *
 * # Safety
 * See the header's introduction.
 */
struct at_fixed_estimate at_chain_fixed_update_i32(const struct at_chain_fixed *chain,
                                                   struct at_chain_state_fixed *state,
                                                   int32_t raw_c,
                                                   int32_t raw_s);

/**
 * `at_chain_fixed_track_i16` for a chain of order 2 only: no dispatch on the
 * order (the checks, then the chain's body), and an image that calls no other order's
 * links one body.
 * `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_fixed_track_i16_order2(const struct at_chain_fixed *chain,
                                         struct at_chain_state_fixed *state,
                                         int16_t raw_c,
                                         int16_t raw_s);

/**
 * `at_chain_fixed_track_i16` for a chain of order 3 only: no dispatch on the
 * order (the checks, then the chain's body), and an image that calls no other order's
 * links one body.
 * `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_fixed_track_i16_order3(const struct at_chain_fixed *chain,
                                         struct at_chain_state_fixed *state,
                                         int16_t raw_c,
                                         int16_t raw_s);

/**
 * `at_chain_fixed_track_u16` for a chain of order 2 only: no dispatch on the
 * order (the checks, then the chain's body), and an image that calls no other order's
 * links one body.
 * `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_fixed_track_u16_order2(const struct at_chain_fixed *chain,
                                         struct at_chain_state_fixed *state,
                                         uint16_t raw_c,
                                         uint16_t raw_s);

/**
 * `at_chain_fixed_track_u16` for a chain of order 3 only: no dispatch on the
 * order (the checks, then the chain's body), and an image that calls no other order's
 * links one body.
 * `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_fixed_track_u16_order3(const struct at_chain_fixed *chain,
                                         struct at_chain_state_fixed *state,
                                         uint16_t raw_c,
                                         uint16_t raw_s);

/**
 * `at_chain_fixed_track_i32` for a chain of order 2 only: no dispatch on the
 * order (the checks, then the chain's body), and an image that calls no other order's
 * links one body.
 * `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_fixed_track_i32_order2(const struct at_chain_fixed *chain,
                                         struct at_chain_state_fixed *state,
                                         int32_t raw_c,
                                         int32_t raw_s);

/**
 * `at_chain_fixed_track_i32` for a chain of order 3 only: no dispatch on the
 * order (the checks, then the chain's body), and an image that calls no other order's
 * links one body.
 * `AT_FAULT_INVALID_ARGUMENT` for a chain of the other order.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_chain_fixed_track_i32_order3(const struct at_chain_fixed *chain,
                                         struct at_chain_state_fixed *state,
                                         int32_t raw_c,
                                         int32_t raw_s);

/**
 * The demodulator's settings for a carrier of `carrier_hz` (Hz) sampled at `adc_rate_hz`
 * (Hz, at least 4 times the carrier, any ratio) with amplitude `carrier_amplitude_counts`
 * (counts, peak) at an ADC whose codes run from `adc_min_code` to `adc_max_code`, with the
 * core's defaults for the rest (clip margin 1/256 of the range, loss of excitation below
 * 0.25, weak excitation below 0.7, phase drift bound 44 degrees, expected delay 0, carrier
 * loop bandwidth 0.3, carrier error up to 3 %, start-up over 24 periods).
 */
struct at_demodulator_settings_f32 at_demodulator_settings_f32_new(float carrier_hz,
                                                                   float adc_rate_hz,
                                                                   float carrier_amplitude_counts,
                                                                   float adc_min_code,
                                                                   float adc_max_code);

/**
 * Checks `settings` and writes the demodulator to `out` (unchanged on error;
 * `AT_ERR_CARRIER_HZ`, `AT_ERR_ADC_RATE_HZ`, `AT_ERR_ADC_RANGE`, ... name the refused
 * setting).
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_demodulator_f32_new(const struct at_demodulator_settings_f32 *settings,
                                 struct at_demodulator_f32 *out);

/**
 * Checks that `chain` runs at the demodulator's pair rate: its observer's sample period is
 * the declared carrier period (to a relative 1e-4), else `AT_ERR_SAMPLE_PERIOD_S`.
 *
 * # Safety
 * See the header's introduction.
 */
at_status at_demodulator_f32_check_chain(const struct at_demodulator_f32 *demodulator,
                                         const struct at_chain_f32 *chain);

/**
 * One ADC sample of each winding (`raw_c` of the cosine winding, `raw_s` of the sine
 * winding, in counts). Once per tracked carrier period (after the start-up) writes a pair to
 * `out` and returns 1; else returns 0 (`out` untouched). Refused arguments (NULL, a
 * demodulator not made, a struct of another build): `AT_FAULT_INVALID_ARGUMENT`, nothing
 * changed. Feed the pair's `y_c`, `y_s` to a chain whose gains run at the declared carrier
 * period (`at_demodulator_f32_check_chain`).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_demodulator_f32_push(const struct at_demodulator_f32 *demodulator,
                                 struct at_demodulator_state_f32 *state,
                                 float raw_c,
                                 float raw_s,
                                 struct at_demodulated_pair_f32 *out);

/**
 * `at_demodulator_f32_push` with the excitation's sample taken at the same instant (any
 * offset and amplitude): the carrier's half-turn ambiguity is then resolved from it. Push
 * all samples of a run with it or all without.
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_demodulator_f32_push_with_excitation(const struct at_demodulator_f32 *demodulator,
                                                 struct at_demodulator_state_f32 *state,
                                                 float raw_c,
                                                 float raw_s,
                                                 float excitation,
                                                 struct at_demodulated_pair_f32 *out);

/**
 * The carrier delay the demodulator chose (rad, in [-pi, pi)): with the excitation pushed,
 * the windings' carrier after it; without, after a carrier of phase 0 at the first sample,
 * as resolved at the end of the start-up around `expected_delay_rad`. The other half turn
 * gives the same windings with the shaft half a turn further. NaN for NULL, another build's
 * state or before the start-up's end.
 *
 * # Safety
 * See the header's introduction.
 */
float at_demodulator_state_f32_carrier_delay_rad(struct at_demodulator_state_f32 *state);

/**
 * Makes `state` fresh: its next sample is the first of a carrier period, the delay not yet
 * measured. NULL is ignored.
 *
 * # Safety
 * See the header's introduction.
 */
void at_demodulator_state_f32_reset(struct at_demodulator_state_f32 *state);

/**
 * Returns the front-end faults latched in `state` (`AT_FRONT_END_FAULT_*` bits) and clears
 * them. 0 for NULL (or another build's state).
 *
 * # Safety
 * See the header's introduction.
 */
uint32_t at_demodulator_state_f32_clear_faults(struct at_demodulator_state_f32 *state);

#ifdef __cplusplus
}  // extern "C"
#endif  // __cplusplus

#endif  /* ANGLETRACK_H */
