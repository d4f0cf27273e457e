/* The C API on the host: a C program written against angletrack.h, linked with
 * libangletrack_c.a, that designs nothing: it takes the gains `angletrack design --format c`
 * writes (gains_ato3.h, gains_ato2.h), tracks a synthetic resolver (scenario.h) through the
 * signal chain and checks the refusals (invalid gains, NULL pointers, zeroed structs, structs
 * of another build); the fixed-point chain from the constants `angletrack design --dtype fixed --format c`
 * prints (fixed_ato3.h) on 12-bit counts, and its chain with the angle-correction tables
 * (test_host_tables.c); the float chain's front-end faults (test_host_front_end.c). Prints one line per check
 * and exits 0 if all pass. Built and run by scripts/test.d/16-c-api.sh. */
#include <stdio.h>
#include <string.h>

#include "angletrack.h"
#include "test_checks.h"
#include "fixed_ato3.h"
#include "gains_ato2.h"
#include "gains_ato3.h"
#include "scenario.h"
#include "test_host_front_end.h"
#include "test_host_tables.h"

/* Statically allocated, as firmware would: zeroed, so the states are fresh. */
static at_gains_f32 gains3, gains2;
static at_adc_f32 adc;
static at_fixed_gains fixed3, zeroed_fixed;
static at_chain_fixed fixed_chain, zeroed_fixed_chain;
static at_chain_state_fixed fixed_state;
static at_chain_f32 chain, plain_chain, zeroed_chain;
static at_chain_state_f32 chain_state;

/* The scenario through the chain of `gains` and the ADC `adc_or_null` (counts if not NULL). */
static void track(const char *name, const at_gains_f32 *gains, const at_adc_f32 *adc_or_null,
                  double sample_period_s, float angle_tolerance, float speed_tolerance) {
  char line[300];
  check_status(at_chain_f32_new(gains, adc_or_null, NULL, NULL, NULL, NULL, &chain), AT_OK, name);
  scenario_result r = scenario_track(&chain, &chain_state, adc_or_null != NULL, SCENARIO_SPEED_RAD_S,
                                     sample_period_s, SCENARIO_AMPLITUDE, SCENARIO_SAMPLES,
                                     SCENARIO_WINDOW);
  int pass = scenario_passes(name, r, angle_tolerance, speed_tolerance, line, sizeof line);
  fputs(line, stdout);
  failures += !pass;
}

/* The fixed-point chain without stages (the observer alone on int16 samples): the
 * constants accepted, the scenario tracked from 12-bit counts shifted left by 4 (amplitude
 * 28,800), the refusals. */
static void fixed_point(void) {
  char line[300];
  check_status(at_fixed_gains_from_constants(fixed3_gain_multiplier, FIXED3_ORDER,
                                             FIXED3_ACCELERATION_SHIFT, FIXED3_SAMPLE_PERIOD_S,
                                             &fixed3),
               AT_OK, "fixed-point constants accepted");
  check_status(at_chain_fixed_new(&fixed3, NULL, NULL, NULL, 1800.0 * 16.0, &fixed_chain), AT_OK,
               "fixed-point chain: the observer alone, its monitor at 28,800 counts");
  check(fixed3.order == 3 && fixed3.acceleration_shift == FIXED3_ACCELERATION_SHIFT,
        "fixed-point constants: order 3, the shift");
  double worst_angle = 0.0, worst_speed = 0.0;
  uint32_t faults = 0;
  for (long k = 0; k < SCENARIO_SAMPLES; k++) {
    double theta = scenario_angle(k, SCENARIO_SPEED_RAD_S, FIXED3_SAMPLE_PERIOD_S);
    int16_t y_c = (int16_t)(lrint(1800.0 * cos(theta)) * 16);
    int16_t y_s = (int16_t)(lrint(1800.0 * sin(theta)) * 16);
    faults |= at_chain_fixed_track_i16(&fixed_chain, &fixed_state, y_c, y_s);
    if (k < SCENARIO_SAMPLES - SCENARIO_WINDOW) continue;
    at_fixed_estimate e = at_chain_fixed_estimate(&fixed_chain, &fixed_state);
    double angle = e.angle * (2.0 * SCENARIO_PI / 4294967296.0);
    double angle_error = fabs(scenario_wrapped(angle - theta));
    double speed_error = fabs(at_chain_fixed_speed_rad_s(&fixed_chain, &e) - SCENARIO_SPEED_RAD_S);
    if (angle_error > worst_angle) worst_angle = angle_error;
    if (speed_error > worst_speed) worst_speed = speed_error;
    faults |= e.faults;
  }
  snprintf(line, sizeof line,
           "fixed point from 12-bit counts: worst angle error %.3g rad, speed error %.3g rad/s, "
           "faults 0x%x",
           worst_angle, worst_speed, (unsigned)faults);
  check(worst_angle < 3e-4 && worst_speed < 0.1 && faults == 0u, line);
  at_fixed_estimate e = at_chain_fixed_estimate(&fixed_chain, &fixed_state);
  double position = at_chain_fixed_position_rad(&fixed_chain, &e);
  check(fabs(position - (0.3 + SCENARIO_SPEED_RAD_S * 4999 * 1e-4)) < 1e-3,
        "fixed-point multi-turn position");

  /* Refusals. */
  at_fixed_gains out = fixed3;
  const int32_t zero_l1[3] = {0, 768430, 271817595};
  check_status(at_fixed_gains_from_constants(zero_l1, 3, 1, 1e-4, &out), AT_ERR_GAINS_0,
               "fixed-point multiplier 0 refused");
  check_status(at_fixed_gains_from_constants(fixed3_gain_multiplier, 3, 0, 1e-4, &out),
               AT_ERR_GAINS_2, "fixed-point shift 0 at order 3 refused");
  check_status(at_fixed_gains_from_constants(fixed3_gain_multiplier, 4, 1, 1e-4, &out),
               AT_ERR_ORDER, "fixed-point order 4 refused");
  check(memcmp(&out, &fixed3, sizeof out) == 0, "refused constants leave out unchanged");
  const float too_small[2] = {1e-30f, 1e-3f};
  check_status(at_fixed_gains_new(too_small, 2, 1e-4, &out), AT_ERR_GAINS_0,
               "fixed-point l1 rounding to 0 refused");
  at_chain_fixed refused;
  check_status(at_chain_fixed_new(&fixed3, NULL, NULL, NULL, 2000.0, &refused),
               AT_ERR_NOMINAL_AMPLITUDE, "fixed-point monitor at 2000 counts refused");
  check_status(at_chain_fixed_new(&zeroed_fixed, NULL, NULL, NULL, 20000.0, &refused),
               AT_ERR_ORDER, "zeroed fixed-point gains refused");
  check_status(at_fixed_gains_new(NULL, 2, 1e-4, &out), AT_ERR_NULL_POINTER,
               "NULL fixed-point gains");
  check(at_chain_fixed_track_i16(&zeroed_fixed_chain, &fixed_state, 1, 0) ==
                AT_FAULT_INVALID_ARGUMENT &&
            at_chain_fixed_track_i16(&fixed_chain, NULL, 1, 0) == AT_FAULT_INVALID_ARGUMENT &&
            at_chain_fixed_update_i16(NULL, &fixed_state, 1, 0).faults == AT_FAULT_INVALID_ARGUMENT,
        "fixed-point track and update with NULL or zeroed arguments refused");
}

/* The worst angle error over the last 0.1 s of the scenario's sensor with 2 % offsets, 5 %
 * imbalance, 0.01 rad of quadrature and 5 mrad of 3rd harmonic, as 12-bit counts through
 * `chain` (which has the 12-bit ADC stage). */
static double chain_worst_error(const at_chain_f32 *c, uint32_t *faults) {
  double worst = 0.0;
  *faults = 0u;
  at_chain_state_f32_reset(&chain_state);
  for (long k = 0; k < SCENARIO_SAMPLES; k++) {
    double theta = scenario_angle(k, SCENARIO_SPEED_RAD_S, ATO3_SAMPLE_PERIOD_S);
    double d = theta + 5e-3 * sin(3.0 * theta);
    double y_c = 0.02 + 0.8 * cos(d), y_s = -0.01 + 0.84 * sin(d + 0.01);
    at_chain_f32_track_u16(c, &chain_state, (uint16_t)lrint(2048.0 + 2048.0 * y_c),
                           (uint16_t)lrint(2048.0 + 2048.0 * y_s));
    if (k < SCENARIO_SAMPLES - SCENARIO_WINDOW) continue;
    at_estimate_f32 e = at_chain_f32_estimate(c, &chain_state);
    double error = fabs(scenario_wrapped((double)e.angle - theta));
    if (error > worst) worst = error;
    *faults |= e.faults;
  }
  return worst;
}

/* The signal chain: stages chosen at run time, one track for every combination. */
static void chains(void) {
  char line[300];
  /* The sensor's stored calibration (in units of full scale) and harmonic error. */
  at_sensor_calibration_f32 stored = {0.02f, -0.01f, 0.8f, 0.84f, 0.01f};
  at_angle_correction_f32 correction;
  memset(&correction, 0, sizeof correction);
  correction.sin_coefficients[2] = 5e-3f;
  check_status(at_chain_f32_new(&gains3, &adc, &stored, NULL, &correction, NULL, &chain), AT_OK,
               "chain: ADC, stored calibration, angle correction, observer");
  check_status(at_chain_f32_new(&gains3, &adc, NULL, NULL, NULL, NULL, &plain_chain), AT_OK,
               "chain: ADC, observer");
  uint32_t faults, plain_faults;
  double corrected = chain_worst_error(&chain, &faults);
  double plain = chain_worst_error(&plain_chain, &plain_faults);
  snprintf(line, sizeof line,
           "chain from 12-bit counts of an imperfect sensor: worst angle error %.3g rad "
           "corrected (faults 0x%x), %.3g rad without the calibration and correction",
           corrected, (unsigned)faults, plain);
  check(corrected < 2e-4 && faults == 0u && plain > 0.02, line);

  /* The online calibration as a stage: learns per channel, in the chain's state. */
  at_calibration_settings_f32 settings = at_calibration_settings_f32_default();
  check_status(at_chain_f32_new(&gains3, NULL, &stored, &settings, NULL, NULL, &chain), AT_ERR_STAGES,
               "chain: stored and online calibration refused");
  check_status(at_chain_f32_new(&gains3, NULL, NULL, &settings, NULL, NULL, &chain), AT_OK,
               "chain: online calibration, observer");
  at_chain_state_f32_reset(&chain_state);
  check_status(at_chain_state_f32_set_calibration_mode(&chain_state, AT_CALIBRATION_LEARNING),
               AT_OK, "chain: online calibration learning");
  for (long k = 0; k < SCENARIO_SAMPLES; k++) {
    double theta = scenario_angle(k, SCENARIO_SPEED_RAD_S, ATO3_SAMPLE_PERIOD_S);
    at_chain_f32_track(&chain, &chain_state, (float)(0.05 + cos(theta)),
                       (float)(-0.05 + 1.1 * sin(theta + 0.05)));
  }
  at_sensor_calibration_f32 learned;
  check_status(at_chain_state_f32_calibration(&chain_state, &learned), AT_OK,
               "chain: the learned calibration read");
  snprintf(line, sizeof line, "chain: learned in %u turns offsets %.4f %.4f, ratio %.4f",
           (unsigned)at_chain_state_f32_turns_learned(&chain_state), learned.offset_c,
           learned.offset_s, learned.amplitude_s / learned.amplitude_c);
  check(fabs(learned.offset_c - 0.05) < 5e-3 && fabs(learned.offset_s + 0.05) < 5e-3 &&
            fabs(learned.amplitude_s / learned.amplitude_c - 1.1) < 5e-3,
        line);
  settings.max_offset = -1.0f;
  check_status(at_chain_f32_new(&gains3, NULL, NULL, &settings, NULL, NULL, &chain),
               AT_ERR_MAX_OFFSET, "chain: negative max_offset refused");
  correction.cos_coefficients[7] = 0.3f;
  check_status(at_chain_f32_new(&gains3, NULL, NULL, NULL, &correction, NULL, &chain),
               AT_ERR_ANGLE_CORRECTION, "chain: angle correction above 0.25 rad refused");
  check(at_chain_f32_track_u16(&plain_chain, NULL, 1, 2) == AT_FAULT_INVALID_ARGUMENT,
        "chain: NULL state refused");

  /* The state-only form: the estimate on demand is the update's. */
  check_status(at_chain_f32_new(&gains3, NULL, NULL, NULL, NULL, NULL, &chain), AT_OK,
               "chain: the observer alone");
  at_chain_state_f32 tracked, updated;
  at_chain_state_f32_reset(&tracked);
  at_chain_state_f32_reset(&updated);
  int same = 1;
  for (long k = 0; k < 100; k++) {
    double theta = scenario_angle(k, SCENARIO_SPEED_RAD_S, ATO3_SAMPLE_PERIOD_S);
    at_estimate_f32 e = at_chain_f32_update(&chain, &updated, (float)cos(theta), (float)sin(theta));
    same &= at_chain_f32_track(&chain, &tracked, (float)cos(theta), (float)sin(theta)) == 0u;
    at_estimate_f32 on_demand = at_chain_f32_estimate(&chain, &tracked);
    same &= e.angle == on_demand.angle && e.turns == on_demand.turns &&
            e.speed == on_demand.speed && e.acceleration == on_demand.acceleration &&
            e.phase_error == on_demand.phase_error && e.faults == on_demand.faults;
  }
  check(same, "at_chain_f32_track + at_chain_f32_estimate give at_chain_f32_update's estimates");
}

/* The demodulator: resolver windings sampled 16 times per 10 kHz carrier period by a 12-bit
 * ADC, one pair per period into a chain running at the carrier period. */
static void demodulation(void) {
  at_demodulator_settings_f32 settings = at_demodulator_settings_f32_new(10e3f, 30e3f, 1800.0f, 0.0f, 4095.0f);
  static at_demodulator_f32 demodulator;
  static at_demodulator_state_f32 demodulator_state;
  check_status(at_demodulator_f32_new(&settings, &demodulator), AT_ERR_ADC_RATE_HZ,
               "demodulator: 3 samples per period refused");
  settings.adc_rate_hz = 160e3f;
  check_status(at_demodulator_f32_new(&settings, &demodulator), AT_OK,
               "demodulator: 16 samples per period");
  check_status(at_chain_f32_new(&gains3, NULL, NULL, NULL, NULL, NULL, &chain), AT_OK, "chain: observer");
  check_status(at_demodulator_f32_check_chain(&demodulator, &chain), AT_OK,
               "demodulator: the chain runs at the carrier period");
  at_chain_state_f32_reset(&chain_state);
  at_demodulated_pair_f32 pair;
  double theta = 0.6;
  long pairs = 0;
  for (long k = 0; k < 16 * 400; k++) {
    double carrier = 1800.0 * sin(2.0 * SCENARIO_PI * (double)(k % 16) / 16.0);
    float raw_c = (float)lrint(2048.0 + cos(theta) * carrier);
    float raw_s = (float)lrint(2048.0 + sin(theta) * carrier);
    if (at_demodulator_f32_push(&demodulator, &demodulator_state, raw_c, raw_s, &pair) == 1u) {
      at_chain_f32_track(&chain, &chain_state, pair.y_c, pair.y_s);
      pairs++;
    }
  }
  at_estimate_f32 e = at_chain_f32_estimate(&chain, &chain_state);
  char line[200];
  snprintf(line, sizeof line, "demodulator: %ld pairs, angle %.5f rad (true %.5f), faults 0x%x",
           pairs, e.angle, theta, (unsigned)(e.faults | pair.faults));
  check(fabs(e.angle - theta) < 1e-3 && pairs == 376 && (e.faults | pair.faults) == 0u, line);
}

/* Structs of another build (another layout version, struct size, library version or
 * target: another layout word beside an "AT" tag) are refused, never read. The private
 * `layout` field is written here only to make such a struct. */
static void layouts(void) {
  check(at_layout_version() == AT_LAYOUT_VERSION, "the library's layout version is the header's");
  at_chain_f32 other = plain_chain;
  other.layout += 2;
  check_status(at_chain_f32_with_winding_check(&other, 1.0f, &chain), AT_ERR_OTHER_BUILD,
               "a chain of another build refused");
  at_chain_state_fixed other_state = fixed_state;
  other_state.layout += 2;
  at_chain_state_fixed before = other_state;
  check(at_chain_fixed_track_i16(&fixed_chain, &other_state, 1, 0) == AT_FAULT_INVALID_ARGUMENT &&
            at_chain_fixed_estimate(&fixed_chain, &other_state).faults == AT_FAULT_INVALID_ARGUMENT &&
            memcmp(&before, &other_state, sizeof before) == 0,
        "a fixed-point state of another build refused and left unchanged");
  at_chain_state_fixed_reset(&other_state);
  check(at_chain_fixed_track_i16(&fixed_chain, &other_state, 1, 0) == 0u,
        "reset, it is this build's");
  at_chain_state_f32 other_chain_state = chain_state;
  other_chain_state.layout += 2;
  check_status(at_chain_state_f32_set_calibration_mode(&other_chain_state, AT_CALIBRATION_LEARNING),
               AT_ERR_OTHER_BUILD, "a chain state of another build refused");
  printf("sizeof: at_fixed_gains %zu, at_chain_state_fixed %zu, at_fixed_estimate %zu bytes\n",
         sizeof(at_fixed_gains), sizeof(at_chain_state_fixed), sizeof(at_fixed_estimate));
}

int main(void) {
  printf("sizeof: at_gains_f32 %zu, at_chain_f32 %zu, at_chain_state_f32 %zu, at_adc_f32 %zu, "
         "at_estimate_f32 %zu bytes\n",
         sizeof(at_gains_f32), sizeof(at_chain_f32), sizeof(at_chain_state_f32),
         sizeof(at_adc_f32), sizeof(at_estimate_f32));

  /* The gains exactly as `angletrack design --format c` writes them. */
  check_status(at_gains_f32_new(ato3_gains, ATO3_ORDER, ATO3_SAMPLE_PERIOD_S, &gains3), AT_OK,
               "ato3 gains accepted");
  check_status(at_gains_f32_new(ato2_gains, ATO2_ORDER, ATO2_SAMPLE_PERIOD_S, &gains2), AT_OK,
               "ato2 gains accepted");
  check(gains3.order == 3 && gains2.order == 2, "orders 3 and 2");

  track("3rd order, 50 Hz", &gains3, NULL, ATO3_SAMPLE_PERIOD_S, SCENARIO_ANGLE_TOLERANCE_RAD,
        SCENARIO_SPEED_TOLERANCE_RAD_S);
  track("2nd order, 50 Hz", &gains2, NULL, ATO2_SAMPLE_PERIOD_S, SCENARIO_ANGLE_TOLERANCE_RAD,
        SCENARIO_SPEED_TOLERANCE_RAD_S);
  check_status(at_adc_f32_offset_binary(12, &adc), AT_OK, "12-bit offset-binary ADC");
  track("3rd order, 12-bit ADC counts", &gains3, &adc, ATO3_SAMPLE_PERIOD_S,
        SCENARIO_ADC_ANGLE_TOLERANCE_RAD, SCENARIO_ADC_SPEED_TOLERANCE_RAD_S);

  /* Refusals: the status names the parameter, and `out` is unchanged. */
  at_gains_f32 out = gains3;
  const float unstable[3] = {0.3f, 0.04f, -0.002f};
  check_status(at_gains_f32_new(unstable, 3, 1e-4f, &out), AT_ERR_GAINS_2, "l3 < 0 refused");
  check(strcmp(at_status_message(AT_ERR_GAINS_2), "gains[2] (l3)") == 0, "message names l3");
  check(memcmp(&out, &gains3, sizeof out) == 0, "refused gains leave out unchanged");
  check_status(at_gains_f32_new(ato3_gains, 3, 0.0f, &out), AT_ERR_SAMPLE_PERIOD_S,
               "zero sample period refused");
  check_status(at_gains_f32_new(ato3_gains, 4, 1e-4f, &out), AT_ERR_ORDER, "order 4 refused");
  out.thresholds = at_fault_thresholds_f32_for_amplitude(0.9f);
  out.thresholds.filter_factor = 1.5f;
  check_status(at_chain_f32_new(&out, NULL, NULL, NULL, NULL, NULL, &chain), AT_ERR_FILTER_FACTOR,
               "filter factor 1.5 refused by the chain");

  /* NULL pointers and zeroed structs: an error, never a crash. */
  check_status(at_gains_f32_new(NULL, 3, 1e-4f, &out), AT_ERR_NULL_POINTER, "NULL gains");
  check_status(at_gains_f32_new(ato3_gains, 3, 1e-4f, NULL), AT_ERR_NULL_POINTER, "NULL out");
  check_status(at_chain_f32_new(&gains3, NULL, NULL, NULL, NULL, NULL, &plain_chain), AT_OK,
               "chain: the observer alone");
  check(at_chain_f32_update(NULL, &chain_state, 1.0f, 0.0f).faults == AT_FAULT_INVALID_ARGUMENT,
        "update with a NULL chain flags AT_FAULT_INVALID_ARGUMENT");
  check(at_chain_f32_update(&plain_chain, NULL, 1.0f, 0.0f).faults == AT_FAULT_INVALID_ARGUMENT,
        "update with a NULL state flags AT_FAULT_INVALID_ARGUMENT");
  check(at_chain_f32_update(&zeroed_chain, &chain_state, 1.0f, 0.0f).faults ==
            AT_FAULT_INVALID_ARGUMENT,
        "update with a zeroed chain flags AT_FAULT_INVALID_ARGUMENT");
  check(at_chain_state_f32_clear_faults(NULL) == 0u, "clear faults of NULL");
  at_chain_state_f32_reset(NULL);
  check_status(at_chain_state_f32_load_calibration(NULL, NULL), AT_ERR_NULL_POINTER,
               "NULL chain state");

  /* Faults: a NaN sample is flagged, latched, and cleared. */
  at_chain_state_f32_reset(&chain_state);
  at_chain_f32_update(&plain_chain, &chain_state, 1.0f, 0.0f);
  check(at_chain_f32_update(&plain_chain, &chain_state, NAN, 0.0f).faults == AT_FAULT_BAD_SAMPLE,
        "NaN sample flagged bad sample");
  check(at_chain_state_f32_clear_faults(&chain_state) == AT_FAULT_BAD_SAMPLE &&
            at_chain_state_f32_clear_faults(&chain_state) == 0u,
        "bad sample latched, then cleared");
  check(strcmp(at_fault_name(AT_FAULT_BAD_SAMPLE), "bad sample") == 0, "fault name");

  /* Online calibration: learn a sensor's offsets, store them, load them. */
  at_calibration_settings_f32 settings = at_calibration_settings_f32_default();
  check_status(at_chain_f32_new(&gains3, NULL, NULL, &settings, NULL, NULL, &chain), AT_OK,
               "chain: the online calibration, the observer");
  at_sensor_calibration_f32 learned;
  char line[300];
  int pass = scenario_calibrate(&chain, &chain_state, ATO3_SAMPLE_PERIOD_S, &learned, line,
                                sizeof line);
  fputs(line, stdout);
  failures += !pass;
  check(at_chain_state_f32_calibration_status(&chain_state) == AT_CALIBRATION_CENTRED,
        "the online calibration centred");
  at_chain_state_f32 loaded;
  at_chain_state_f32_reset(&loaded);
  check_status(at_chain_state_f32_load_calibration(&loaded, &learned), AT_OK,
               "stored calibration loaded");
  check(at_chain_state_f32_calibration_mode(&loaded) == AT_CALIBRATION_FROZEN,
        "loaded calibration frozen");

  fixed_point();
  chains();
  demodulation();
  failures += front_end_checks(&gains3);
  layouts();
  failures += fixed_chain_checks(&gains3);

  printf("%s: %d check(s) failed\n", failures ? "FAIL" : "PASS", failures);
  return failures ? 1 : 0;
}
