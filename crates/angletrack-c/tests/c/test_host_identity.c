/* The same tracker file through the C door and through the Rust crate (issue 35, item 5):
 * a C program that builds the float and the fixed-point chains from the constants
 * `angletrack export --format c` wrote for two tracker files (identity/motor_f32.h and
 * identity/motor_fixed.h: 12-bit offset-binary counts, the ADC's full scale as its range, a
 * stored calibration and a 3rd-harmonic angle correction), tracks the capture
 * identity/capture.bin (9000 pairs of 12-bit codes: a standstill, an acceleration, a clipped
 * stretch, a dead sine channel) and compares a hash of every sample's angle bits and faults
 * with the one the Rust crate's TrackerRun gives on the same file and capture
 * (identity/expected.h, written and held by crates/angletrack/tests/tracker_rust_export.rs).
 * The fixed-point chain twice: from the exported gains and calibration by
 * at_chain_fixed_new, and from the exported integers (motor_fixed_chain, with the monitor's
 * thresholds) by at_chain_fixed_from_constants. The f32 header does not carry fault
 * thresholds yet: the program states the amplitude the files state (1800 counts). Usage: test_host_identity CAPTURE.bin; exits 0 if both agree.
 * Built and run by scripts/test.d/16-c-api.sh. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "angletrack.h"
#include "identity/expected.h"
#include "identity/motor_f32.h"
#include "identity/motor_fixed.h"

static uint16_t codes[IDENTITY_SAMPLES][2];
static at_gains_f32 gains;
static at_adc_f32 adc;
static at_chain_f32 chain;
static at_chain_state_f32 state;
static at_fixed_gains fixed_gains;
static at_adc_counts counts;
static at_chain_fixed fixed_chain, fixed_chain_ranged;
static at_chain_state_fixed fixed_state;

static uint64_t hash_bytes(uint64_t hash, uint32_t bits, uint32_t faults) {
  unsigned char bytes[5] = {(unsigned char)bits, (unsigned char)(bits >> 8), (unsigned char)(bits >> 16),
                            (unsigned char)(bits >> 24), (unsigned char)faults};
  for (int i = 0; i < 5; i++) hash = (hash ^ bytes[i]) * 0x00000100000001b3ULL;
  return hash;
}

static int report(const char *name, at_status status, uint64_t hash, uint64_t expected, long flagged,
                  long expected_flagged) {
  int pass = status == AT_OK && hash == expected && flagged == expected_flagged;
  printf("%s %s: status %d, hash 0x%016llx (Rust 0x%016llx), %ld samples flagged (Rust %ld)\n",
         pass ? "ok  " : "FAIL", name, (int)status, (unsigned long long)hash, (unsigned long long)expected,
         flagged, expected_flagged);
  return pass;
}

static at_angle_correction_f32 harmonics(const float *cos_coefficients, const float *sin_coefficients) {
  at_angle_correction_f32 h;
  for (int k = 0; k < AT_CORRECTION_ORDER; k++) {
    h.cos_coefficients[k] = cos_coefficients[k];
    h.sin_coefficients[k] = sin_coefficients[k];
  }
  return h;
}

/* The float chain: counts tracked as counts (mid-scale 2048, one count per unit), as the
 * tracker file's input says. */
static int float_chain(void) {
  at_status s = at_gains_f32_new(motor_f32_gains, MOTOR_F32_ORDER, MOTOR_F32_SAMPLE_PERIOD_S, &gains);
  gains.thresholds = at_fault_thresholds_f32_for_amplitude((float)IDENTITY_AMPLITUDE_COUNTS);
  if (s == AT_OK) s = at_adc_f32_new(2048, 1.0f, &adc);
  if (s == AT_OK) s = at_adc_f32_set_range(&adc, 0, 4095);
  at_sensor_calibration_f32 sensor = {motor_f32_sensor[0], motor_f32_sensor[1], motor_f32_sensor[2],
                                      motor_f32_sensor[3], motor_f32_sensor[4]};
  at_angle_correction_f32 correction = harmonics(motor_f32_angle_cos, motor_f32_angle_sin);
  if (s == AT_OK) s = at_chain_f32_new(&gains, &adc, &sensor, NULL, &correction, NULL, &chain);
  uint64_t hash = 0xcbf29ce484222325ULL;
  long flagged = 0;
  for (long k = 0; s == AT_OK && k < IDENTITY_SAMPLES; k++) {
    at_estimate_f32 e = at_chain_f32_update_u16(&chain, &state, codes[k][0], codes[k][1]);
    uint32_t bits;
    memcpy(&bits, &e.angle, sizeof bits);
    hash = hash_bytes(hash, bits, e.faults);
    flagged += e.faults != 0;
  }
  return report("f32 chain from the exported constants", s, hash, IDENTITY_F32_HASH, flagged,
                IDENTITY_F32_FLAGGED);
}

/* Tracks the capture through `chain` (made with status `s`) with the ADC's full scale as its
 * range, from a fresh state. */
static int track_fixed(const char *name, at_status s, const at_chain_fixed *chain) {
  if (s == AT_OK) s = at_chain_fixed_with_adc_range(chain, 0, 4095, &fixed_chain_ranged);
  at_chain_state_fixed_reset(&fixed_state);
  uint64_t hash = 0xcbf29ce484222325ULL;
  long flagged = 0;
  for (long k = 0; s == AT_OK && k < IDENTITY_SAMPLES; k++) {
    at_fixed_estimate e = at_chain_fixed_update_u16(&fixed_chain_ranged, &fixed_state, codes[k][0], codes[k][1]);
    hash = hash_bytes(hash, (uint32_t)e.angle, e.faults);
    flagged += e.faults != 0;
  }
  return report(name, s, hash, IDENTITY_FIXED_HASH, flagged, IDENTITY_FIXED_FLAGGED);
}

/* The fixed-point chain from the exported gains and calibration: counts shifted by 16 - 12
 * bits, the calibration (learned on the counts) and the monitor's amplitude in the shifted
 * counts. */
static int fixed_point_chain(void) {
  at_status s = at_fixed_gains_from_constants(motor_fixed_gain_multiplier, MOTOR_FIXED_ORDER,
                                              MOTOR_FIXED_ACCELERATION_SHIFT, MOTOR_FIXED_SAMPLE_PERIOD_S,
                                              &fixed_gains);
  if (s == AT_OK) s = at_adc_counts_offset_binary(12, &counts);
  const double shift = 16.0;
  at_sensor_calibration_f32 sensor = {(float)(motor_fixed_sensor[0] * shift), (float)(motor_fixed_sensor[1] * shift),
                                      (float)(motor_fixed_sensor[2] * shift), (float)(motor_fixed_sensor[3] * shift),
                                      (float)motor_fixed_sensor[4]};
  float cos_coefficients[AT_CORRECTION_ORDER], sin_coefficients[AT_CORRECTION_ORDER];
  for (int k = 0; k < AT_CORRECTION_ORDER; k++) {
    cos_coefficients[k] = (float)motor_fixed_angle_cos[k];
    sin_coefficients[k] = (float)motor_fixed_angle_sin[k];
  }
  at_angle_correction_f32 correction = harmonics(cos_coefficients, sin_coefficients);
  static at_angle_table_fixed table;
  if (s == AT_OK) s = at_angle_table_fixed_from_harmonics(&correction, &table);
  if (s == AT_OK)
    s = at_chain_fixed_new(&fixed_gains, &counts, &sensor, &table, IDENTITY_AMPLITUDE_COUNTS * shift, &fixed_chain);
  return track_fixed("fixed-point chain from the exported gains and calibration", s, &fixed_chain);
}

int main(int argc, char **argv) {
  FILE *f = argc == 2 ? fopen(argv[1], "rb") : NULL;
  unsigned char raw[4];
  for (long k = 0; f != NULL && k < IDENTITY_SAMPLES; k++) {
    if (fread(raw, 1, 4, f) != 4) {
      fclose(f);
      f = NULL;
      break;
    }
    codes[k][0] = (uint16_t)(raw[0] | raw[1] << 8);
    codes[k][1] = (uint16_t)(raw[2] | raw[3] << 8);
  }
  if (f == NULL) {
    fprintf(stderr, "usage: test_host_identity CAPTURE.bin (%d pairs of little-endian uint16)\n", IDENTITY_SAMPLES);
    return 2;
  }
  fclose(f);
  int pass = float_chain();
  pass &= fixed_point_chain();
  /* The whole chain in the exported integers (motor_fixed_chain), as a firmware builds it. */
  at_status s = at_chain_fixed_from_constants(&motor_fixed_chain, &fixed_chain);
  pass &= track_fixed("fixed-point chain from the exported integers", s, &fixed_chain);
  return pass ? 0 : 1;
}
