/* The host C test's checks of the float chain's front-end faults (linked with test_host.c,
 * which calls front_end_checks): clipping against the ADC's stated range (its bits, or
 * at_adc_f32_set_range) and, without one, against the rails measured as extremes held
 * flat; the fixed-point chain's clipping against its stated range; a 10 ms loss of
 * excitation through the demodulator, coasted through; an ADC with a wrong tag or of
 * another build, refused. */
#include <math.h>
#include <stdio.h>

#include "angletrack.h"
#include "test_checks.h"
#include "test_host_front_end.h"

#define PI 3.14159265358979323846

static at_chain_state_f32 chain_state;

/* `error` wrapped to [-pi, pi) (rad). */
static double wrapped(double error) {
  error = fmod(error + 3.0 * PI, 2.0 * PI);
  if (error < 0.0) error += 2.0 * PI;
  return error - PI;
}

/* `count` samples of a still shaft at 1 rad (1500 counts from mid-scale `mid`) through
 * `c`, then (`clip_c`, `clip_s`): whether that estimate carries AT_FAULT_FRONT_END with the
 * angle held (the observer coasted), every estimate before it without a fault. */
static int coasts_through(const at_chain_f32 *c, int32_t mid, int32_t clip_c, int32_t clip_s) {
  at_chain_state_f32_reset(&chain_state);
  at_estimate_f32 before = {0};
  uint32_t faults = 0u;
  for (int k = 0; k < 200; k++) {
    before = at_chain_f32_update_i32(c, &chain_state, mid + (int32_t)lrint(1500.0 * cos(1.0)),
                                     mid + (int32_t)lrint(1500.0 * sin(1.0)));
    faults |= before.faults;
  }
  at_estimate_f32 e = at_chain_f32_update_i32(c, &chain_state, clip_c, clip_s);
  return faults == 0u && e.faults == AT_FAULT_FRONT_END && fabs(e.angle - before.angle) < 1e-4;
}

/* Counts of a resolver at 50 rev/s (10 kHz) of amplitude `amplitude`, clipped to a signed
 * 12-bit ADC's codes, through `c`: the samples of the second turn flagged front end. */
static long flagged_in_the_second_turn(const at_chain_f32 *c, double amplitude) {
  long flagged = 0;
  at_chain_state_f32_reset(&chain_state);
  for (int k = 0; k < 400; k++) {
    double theta = 0.3 + 0.0314 * k;
    double count_c = fmin(fmax(round(amplitude * cos(theta)), -2048.0), 2047.0);
    double count_s = fmin(fmax(round(amplitude * sin(theta)), -2048.0), 2047.0);
    at_estimate_f32 e = at_chain_f32_update_i16(c, &chain_state, (int16_t)count_c, (int16_t)count_s);
    if (k >= 200 && (e.faults & AT_FAULT_FRONT_END)) flagged++;
  }
  return flagged;
}

/* The windings of a 12-bit resolver at 50 electrical rev/s (10 kHz carrier sampled at
 * 160 kHz, amplitude 1800 counts, 2 counts of noise) whose excitation is lost for 10 ms
 * after 0.2 s, through the demodulator into `c` with each pair's faults: the worst angle
 * error from the loss on (rad), and the lost pairs and those of them flagged. */
static double through_a_loss(const at_chain_f32 *c, const at_demodulator_f32 *demodulator,
                             long *lost, long *flagged) {
  static at_demodulator_state_f32 demodulator_state;
  at_demodulator_state_f32_reset(&demodulator_state);
  at_chain_state_f32_reset(&chain_state);
  at_demodulated_pair_f32 pair;
  double worst = 0.0;
  unsigned noise = 12345u;
  *lost = *flagged = 0;
  for (long k = 0; k < 41600; k++) {
    double t = (double)k / 160e3, theta = 2.0 * PI * 50.0 * t;
    double excitation = t >= 0.2 && t < 0.21 ? 0.0 : 1800.0 * sin(2.0 * PI * 10e3 * t);
    noise = noise * 1103515245u + 12345u;
    float n_c = (float)((noise >> 16) % 5u) - 2.0f;
    noise = noise * 1103515245u + 12345u;
    float n_s = (float)((noise >> 16) % 5u) - 2.0f;
    float raw_c = (float)(2048.0 + cos(theta) * excitation) + n_c;
    float raw_s = (float)(2048.0 + sin(theta) * excitation) + n_s;
    if (at_demodulator_f32_push(demodulator, &demodulator_state, raw_c, raw_s, &pair) != 1u) continue;
    at_estimate_f32 e = at_chain_f32_update_demodulated(c, &chain_state, &pair);
    double centre_s = pair.centre_sample / 160e3;
    if (centre_s >= 0.2) {
      double error = fabs(wrapped((double)e.angle - 2.0 * PI * 50.0 * centre_s));
      if (error > worst) worst = error;
    }
    if (pair.faults & AT_FRONT_END_FAULT_LOSS_OF_EXCITATION) {
      (*lost)++;
      *flagged += (e.faults & AT_FAULT_FRONT_END) != 0u;
    }
  }
  return worst;
}

/* The front end's faults in the float chain: clipping against the ADC's stated range (its
 * bits, or at_adc_f32_set_range), a demodulator's loss of excitation coasted through. */
int front_end_checks(const at_gains_f32 *gains3) {
  char line[300];
  static at_adc_f32 signed_adc, stated_adc, unstated_adc;
  static at_chain_f32 clipping_chain;
  check_status(at_adc_f32_twos_complement(12, &signed_adc), AT_OK, "signed 12-bit ADC");
  check_status(at_chain_f32_new(gains3, &signed_adc, NULL, NULL, NULL, NULL, &clipping_chain),
               AT_OK, "chain: signed 12-bit ADC, observer");
  check(coasts_through(&clipping_chain, 0, 2047, -2048),
        "signed 12-bit counts at 2047 and -2048: flagged front end, coasted through");
  check(at_chain_f32_update_i16(&clipping_chain, &chain_state, 2047, 300).faults ==
                AT_FAULT_FRONT_END &&
            at_chain_f32_update_i16(&clipping_chain, &chain_state, 2046, 300).faults == 0u,
        "one channel at 2047 flagged, 2046 not");
  check(at_chain_state_f32_clear_front_end_faults(&chain_state) == AT_FRONT_END_FAULT_CLIPPING &&
            at_chain_state_f32_clear_front_end_faults(&chain_state) == 0u,
        "clipping latched in the state, then cleared");
  check_status(at_adc_f32_new(2048, 2048.0f, &stated_adc), AT_OK, "ADC, no range stated");
  unstated_adc = stated_adc;
  check_status(at_adc_f32_set_range(&stated_adc, 4095, 0), AT_ERR_ADC_RANGE,
               "ADC range 4095 to 0 refused");
  check_status(at_adc_f32_set_range(&stated_adc, 0, 4095), AT_OK, "ADC range 0 to 4095 stated");
  check_status(at_chain_f32_new(gains3, &stated_adc, NULL, NULL, NULL, NULL, &clipping_chain),
               AT_OK, "chain: offset-binary ADC with its range, observer");
  check(coasts_through(&clipping_chain, 2048, 4095, 0),
        "offset-binary counts at 4095 and 0: flagged front end, coasted through");
  check_status(at_chain_f32_new(gains3, &unstated_adc, NULL, NULL, NULL, NULL, &clipping_chain),
               AT_OK, "chain: offset-binary ADC without a range, observer");
  check(!coasts_through(&clipping_chain, 2048, 4095, 0), "without the range: not flagged");
  /* Without a stated range, the rails measured: extremes held flat. */
  check_status(at_adc_f32_new(0, 2048.0f, &unstated_adc), AT_OK, "signed ADC, no range stated");
  check_status(at_chain_f32_new(gains3, &unstated_adc, NULL, NULL, NULL, NULL, &clipping_chain),
               AT_OK, "chain: signed ADC without a range, observer");
  long clipped = flagged_in_the_second_turn(&clipping_chain, 3184.0);
  uint32_t latched = at_chain_state_f32_clear_front_end_faults(&chain_state);
  long clean = flagged_in_the_second_turn(&clipping_chain, 1800.0);
  snprintf(line, sizeof line,
           "no range stated: amplitude 1.4 clipped at 0.9 (2047 counts), %ld of 200 samples of "
           "the second turn flagged (latched 0x%x); a clean 1800 counts, %ld",
           clipped, (unsigned)latched, clean);
  check(clipped >= 195 && latched == AT_FRONT_END_FAULT_CLIPPING && clean == 0, line);

  /* The fixed-point chain with its ADC's range stated: signed 12-bit counts. */
  static at_fixed_gains fixed;
  static at_chain_fixed plain_fixed, fixed_chain;
  static at_chain_state_fixed fixed_state;
  const float fixed_gains[3] = {0.094326f, 0.000562075f, 1.213522e-5f};
  at_adc_counts counts;
  check_status(at_fixed_gains_new(fixed_gains, 3, 1e-4f, &fixed), AT_OK, "fixed-point gains");
  check_status(at_adc_counts_twos_complement(12, &counts), AT_OK, "signed 12-bit counts");
  check_status(at_chain_fixed_new(&fixed, &counts, NULL, NULL, 0.0, &plain_fixed), AT_OK,
               "fixed chain: ADC, observer");
  check_status(at_chain_fixed_with_adc_range(&plain_fixed, 2047, -2048, &fixed_chain),
               AT_ERR_ADC_RANGE, "fixed chain: range 2047 to -2048 refused");
  check_status(at_chain_fixed_with_adc_range(&plain_fixed, -2048, 2047, &fixed_chain), AT_OK,
               "fixed chain: range -2048 to 2047");
  uint32_t still = 0u;
  for (int k = 0; k < 20; k++) {
    still |= at_chain_fixed_update_i16(&fixed_chain, &fixed_state, (int16_t)lrint(1500.0 * cos(1.0)),
                                       (int16_t)lrint(1500.0 * sin(1.0))).faults;
  }
  at_fixed_estimate held = at_chain_fixed_estimate(&fixed_chain, &fixed_state);
  at_fixed_estimate e = at_chain_fixed_update_i16(&fixed_chain, &fixed_state, 2047, -2048);
  check(still == 0u && e.faults == AT_FAULT_FRONT_END && (uint32_t)e.angle == (uint32_t)held.angle + (uint32_t)held.speed &&
            at_chain_fixed_update_i16(&fixed_chain, &fixed_state, 300, 2047).faults ==
                AT_FAULT_FRONT_END &&
            at_chain_fixed_update_i16(&fixed_chain, &fixed_state, 300, 2046).faults == 0u &&
            at_chain_state_fixed_clear_front_end_faults(&fixed_state) == AT_FRONT_END_FAULT_CLIPPING,
        "fixed chain: counts at 2047 and -2048 flagged and coasted through, one at 2047 flagged");

  /* An ADC with another struct's tag, or of another build: refused. The private fields
   * are written here only to make such a struct. */
  at_adc_f32 other = stated_adc;
  other.tag ^= 1u;
  check_status(at_chain_f32_new(gains3, &other, NULL, NULL, NULL, NULL, &clipping_chain),
               AT_ERR_NOT_INITIALISED, "ADC with a wrong tag refused");
  other = stated_adc;
  other.layout += 2;
  check_status(at_chain_f32_new(gains3, &other, NULL, NULL, NULL, NULL, &clipping_chain),
               AT_ERR_OTHER_BUILD, "ADC of another build refused");
  check_status(at_adc_f32_set_range(&other, 0, 4095), AT_ERR_OTHER_BUILD,
               "range of an ADC of another build refused");

  /* A 10 ms loss of excitation at 50 rev/s through the demodulator. */
  static at_demodulator_f32 demodulator;
  static at_gains_f32 coast_gains;
  static at_chain_f32 resolver_chain;
  const float gains[3] = {0.3f, 0.04f, 0.002f};
  at_demodulator_settings_f32 settings = at_demodulator_settings_f32_new(10e3f, 160e3f, 1800.0f, 0.0f, 4095.0f);
  check_status(at_demodulator_f32_new(&settings, &demodulator), AT_OK, "demodulator: 160 kHz");
  check_status(at_gains_f32_new(gains, 3, 1e-4f, &coast_gains), AT_OK, "gains 0.3, 0.04, 0.002");
  check_status(at_chain_f32_new(&coast_gains, NULL, NULL, NULL, NULL, NULL, &resolver_chain), AT_OK,
               "chain: observer at the carrier period");
  long lost, flagged;
  double worst = through_a_loss(&resolver_chain, &demodulator, &lost, &flagged);
  snprintf(line, sizeof line,
           "10 ms loss of excitation at 50 rev/s: worst angle error %.4f rad from the loss on, "
           "%ld pairs lost, %ld flagged front end",
           worst, lost, flagged);
  check(worst < 0.02 && lost >= 98 && lost <= 102 && flagged == lost, line);
  return failures;
}
