/* The host C test's checks of the fixed-point chain and the angle-correction tables (linked
 * with test_host.c, which calls fixed_chain_checks): a synthetic 12-bit resolver with
 * offsets, imbalance, quadrature and a 3rd-harmonic angle error through the fixed-point chain
 * (raw counts of each width, a stored calibration, the Q15 table), the float table in the
 * f32 chain, each bad parameter refused with its status, and structs of another build. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "angletrack.h"
#include "test_checks.h"
#include "fixed_ato3.h"
#include "test_host_tables.h"

#define PI 3.14159265358979323846
#define SAMPLES 5000L
#define WINDOW 1000L

static at_fixed_gains gains;
static at_chain_fixed corrected, uncorrected, bare;
static at_chain_state_fixed state;
static at_angle_table_fixed table;

/* Sample k's true angle (50 Hz at 10 kHz) and the imperfect sensor's 12-bit counts. */
static double sensor(long k, uint16_t *raw_c, uint16_t *raw_s) {
  double theta = 0.3 + 2.0 * PI * 50.0 * (double)k * FIXED3_SAMPLE_PERIOD_S;
  double m = theta + 0.004 * sin(3.0 * theta);
  *raw_c = (uint16_t)lrint(2048.0 + 36.0 + 1800.0 * cos(m));
  *raw_s = (uint16_t)lrint(2048.0 - 27.0 + 1890.0 * sin(m + 0.03));
  return theta;
}

/* The worst angle error (rad) over the last WINDOW samples through `chain` (track_u16,
 * track_i32 or update_u16 by k), and the faults there. */
static double worst_error(const at_chain_fixed *chain, uint32_t *faults) {
  double worst = 0.0;
  *faults = 0u;
  at_chain_state_fixed_reset(&state);
  for (long k = 0; k < SAMPLES; k++) {
    uint16_t c, s;
    double theta = sensor(k, &c, &s);
    at_fixed_estimate e;
    if (k % 3 == 0) {
      e = at_chain_fixed_update_u16(chain, &state, c, s);
    } else {
      *faults |= k % 3 == 1 ? at_chain_fixed_track_u16(chain, &state, c, s)
                            : at_chain_fixed_track_i32(chain, &state, c, s);
      e = at_chain_fixed_estimate(chain, &state);
    }
    if (k < SAMPLES - WINDOW) continue;
    *faults |= e.faults;
    double error = (double)e.angle * (2.0 * PI / 4294967296.0) - theta;
    error = fmod(error + 3.0 * PI, 2.0 * PI);
    error = fabs((error < 0.0 ? error + 2.0 * PI : error) - PI);
    if (error > worst) worst = error;
  }
  return worst;
}

/* Refusals of at_chain_fixed_new: each bad parameter with its status, `out` unchanged. */
static void refusals(const at_adc_counts *adc, const at_sensor_calibration_f32 *good) {
  at_chain_fixed out = bare;
  at_adc_counts bad_adc = {0, 16};
  check_status(at_chain_fixed_new(&gains, &bad_adc, NULL, NULL, 0.0, &out), AT_ERR_SHIFT,
               "fixed chain: ADC shift 16 refused");
  bad_adc = (at_adc_counts){INT32_MIN, 4};
  check_status(at_chain_fixed_new(&gains, &bad_adc, NULL, NULL, 0.0, &out), AT_ERR_MID_SCALE_COUNTS,
               "fixed chain: mid-scale beyond 2^30 refused");
  check_status(at_adc_counts_offset_binary(17, &bad_adc), AT_ERR_BITS, "fixed ADC: 17 bits refused");
  check_status(at_adc_counts_twos_complement(1, &bad_adc), AT_ERR_BITS, "fixed ADC: 1 bit refused");
  struct {
    at_sensor_calibration_f32 calibration;
    at_status status;
    const char *what;
  } bad[] = {
      {*good, AT_ERR_OFFSET_C, "fixed chain: offset_c beyond 16 bits refused"},
      {*good, AT_ERR_OFFSET_S, "fixed chain: offset_s NaN refused"},
      {*good, AT_ERR_AMPLITUDE_C, "fixed chain: amplitude_c 0 refused"},
      {*good, AT_ERR_AMPLITUDE_S, "fixed chain: sine channel under half the cosine's refused"},
      {*good, AT_ERR_QUADRATURE_RAD, "fixed chain: quadrature 1 rad refused"},
  };
  bad[0].calibration.offset_c = 40000.0f;
  bad[1].calibration.offset_s = NAN;
  bad[2].calibration.amplitude_c = 0.0f;
  bad[3].calibration.amplitude_s = 0.4f * good->amplitude_c;
  bad[4].calibration.quadrature_rad = 1.0f;
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    check_status(at_chain_fixed_new(&gains, adc, &bad[i].calibration, NULL, 28800.0, &out),
                 bad[i].status, bad[i].what);
  }
  at_angle_table_fixed too_large = table;
  too_large.errors_q15[5] = 8193;
  check_status(at_chain_fixed_new(&gains, adc, NULL, &too_large, 28800.0, &out),
               AT_ERR_ANGLE_CORRECTION, "fixed chain: table entry beyond 0.25 rad refused");
  check_status(at_chain_fixed_new(&gains, adc, NULL, NULL, 2000.0, &out), AT_ERR_NOMINAL_AMPLITUDE,
               "fixed chain: monitor amplitude 2000 refused");
  at_fixed_gains zeroed;
  memset(&zeroed, 0, sizeof zeroed);
  check_status(at_chain_fixed_new(&zeroed, adc, NULL, NULL, 0.0, &out), AT_ERR_ORDER,
               "fixed chain: zeroed gains refused");
  check_status(at_chain_fixed_new(&gains, adc, NULL, NULL, 0.0, NULL), AT_ERR_NULL_POINTER,
               "fixed chain: NULL out refused");
  check(memcmp(&out, &bare, sizeof out) == 0, "fixed chain: out unchanged by the refusals");
  check(at_chain_fixed_track_u16(&bare, &state, 1, 2) == AT_FAULT_INVALID_ARGUMENT &&
            at_chain_fixed_track_i32(&bare, &state, 1, 2) == AT_FAULT_INVALID_ARGUMENT,
        "fixed chain without an ADC: uint16 and int32 counts refused");
  check(at_chain_fixed_track_i16(NULL, &state, 1, 2) == AT_FAULT_INVALID_ARGUMENT &&
            at_chain_fixed_update_i16(&bare, NULL, 1, 2).faults == AT_FAULT_INVALID_ARGUMENT,
        "fixed chain: NULL pointers refused");
}

/* The table constructors and the float table in the f32 chain. */
static void tables(const at_gains_f32 *gains3) {
  static at_angle_correction_table_f32 float_table;
  static at_chain_f32 chain;
  const float curve[4] = {0.0f, 0.002f, 0.0f, -0.002f};
  check_status(at_angle_correction_table_f32_from_curve(curve, 1, &float_table), AT_ERR_CURVE,
               "float table: a curve of 1 point refused");
  check_status(at_angle_correction_table_f32_from_curve(curve, 4, &float_table), AT_OK,
               "float table from a measured curve");
  check(fabsf(float_table.errors_rad[64] - 0.002f) < 1e-7f, "float table: the curve at -pi/2");
  at_angle_correction_f32 harmonics;
  memset(&harmonics, 0, sizeof harmonics);
  harmonics.sin_coefficients[2] = 0.004f;
  check_status(at_angle_correction_table_f32_from_harmonics(&harmonics, &float_table), AT_OK,
               "float table from harmonics");
  at_angle_table_fixed from_errors;
  check_status(at_angle_table_fixed_from_errors(float_table.errors_rad, &from_errors), AT_OK,
               "fixed table from errors in rad");
  check(memcmp(&from_errors, &table, sizeof table) == 0,
        "fixed table: from the float table's errors as from the harmonics");
  check_status(at_chain_f32_new(gains3, NULL, NULL, NULL, NULL, &float_table, &chain), AT_OK,
               "f32 chain with the float table");
  check_status(at_chain_f32_new(gains3, NULL, NULL, NULL, &harmonics, &float_table, &chain),
               AT_ERR_STAGES, "f32 chain: harmonics and table together refused");
  float_table.errors_rad[3] = 0.3f;
  check_status(at_angle_correction_table_f32_check(&float_table), AT_ERR_ANGLE_CORRECTION,
               "float table: an entry of 0.3 rad refused");
  check_status(at_chain_f32_new(gains3, NULL, NULL, NULL, NULL, &float_table, &chain),
               AT_ERR_ANGLE_CORRECTION, "f32 chain: a table entry of 0.3 rad refused");
  harmonics.cos_coefficients[7] = 0.3f;
  check_status(at_angle_table_fixed_from_harmonics(&harmonics, &from_errors),
               AT_ERR_ANGLE_CORRECTION, "fixed table: harmonics above 0.25 rad refused");
}

int fixed_chain_checks(const at_gains_f32 *gains3) {
  char line[300];
  at_adc_counts adc;
  check_status(at_adc_counts_offset_binary(12, &adc), AT_OK, "fixed ADC: 12 bits offset binary");
  check(adc.mid_scale_counts == 2048 && adc.shift == 4, "fixed ADC: mid-scale 2048, shift 4");
  /* The sensor's parameters in the observer's 16-bit counts (12-bit counts shifted by 4). */
  at_sensor_calibration_f32 calibration = {36.0f * 16, -27.0f * 16, 1800.0f * 16, 1890.0f * 16, 0.03f};
  at_angle_correction_f32 harmonics;
  memset(&harmonics, 0, sizeof harmonics);
  harmonics.sin_coefficients[2] = 0.004f;
  check_status(at_fixed_gains_from_constants(fixed3_gain_multiplier, FIXED3_ORDER,
                                             FIXED3_ACCELERATION_SHIFT, FIXED3_SAMPLE_PERIOD_S,
                                             &gains),
               AT_OK, "fixed chain: the constants");
  check_status(at_angle_table_fixed_from_harmonics(&harmonics, &table), AT_OK,
               "fixed table from harmonics");
  check_status(at_chain_fixed_new(&gains, &adc, &calibration, &table, 28800.0, &corrected), AT_OK,
               "fixed chain: ADC, stored calibration, table, observer");
  check_status(at_chain_fixed_new(&gains, &adc, NULL, NULL, 0.0, &uncorrected), AT_OK,
               "fixed chain: ADC, observer, monitor off");
  check_status(at_chain_fixed_new(&gains, NULL, NULL, NULL, 16384.0, &bare), AT_OK,
               "fixed chain: observer alone");
  uint32_t faults, plain_faults;
  double good = worst_error(&corrected, &faults);
  double plain = worst_error(&uncorrected, &plain_faults);
  snprintf(line, sizeof line,
           "fixed chain from 12-bit counts of an imperfect sensor: worst angle error %.3g rad "
           "corrected (faults 0x%x), %.3g rad without the calibration and table",
           good, (unsigned)faults, plain);
  check(good < 5e-4 && faults == 0u && plain > 20.0 * good, line);
  at_fixed_estimate one_turn_a_second = {0, 0, (int32_t)lrint(4294967296.0 * FIXED3_SAMPLE_PERIOD_S), 0, 0, 0u};
  check(fabs(at_chain_fixed_speed_rad_s(&corrected, &one_turn_a_second) - 2.0 * 3.14159265358979) < 1e-5,
        "fixed chain: a speed in rad/s at its sample period");
  refusals(&adc, &calibration);
  tables(gains3);

  /* Structs of another build: refused, never read. */
  at_chain_fixed other = corrected;
  other.layout += 2;
  at_chain_state_fixed other_state = state;
  check(at_chain_fixed_track_u16(&other, &other_state, 1, 2) == AT_FAULT_INVALID_ARGUMENT &&
            at_chain_fixed_estimate(&other, &state).faults == AT_FAULT_INVALID_ARGUMENT,
        "a fixed chain of another build refused");
  other_state.layout += 2;
  at_chain_state_fixed before = other_state;
  check(at_chain_fixed_track_u16(&corrected, &other_state, 1, 2) == AT_FAULT_INVALID_ARGUMENT &&
            memcmp(&before, &other_state, sizeof before) == 0,
        "a fixed chain state of another build refused and left unchanged");
  at_chain_state_fixed_reset(&other_state);
  check(at_chain_fixed_track_u16(&corrected, &other_state, 2048, 2048) == 0u &&
            at_chain_state_fixed_clear_faults(&other_state) == 0u,
        "reset, it is this build's");
  printf("sizeof: at_chain_fixed %zu, at_chain_state_fixed %zu, at_angle_table_fixed %zu bytes\n",
         sizeof(at_chain_fixed), sizeof(at_chain_state_fixed), sizeof(at_angle_table_fixed));
  return failures;
}
