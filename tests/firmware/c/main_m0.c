/* The C API's fixed-point signal chain on a Cortex-M0 (no FPU): a firmware written in C
 * against angletrack.h, linked with the static library built for thumbv6m-none-eabi, run
 * under QEMU microbit (run.sh). It takes the integer constants `angletrack design --dtype
 * fixed --format c` prints (fixed_ato3.h), builds its chains once at start-up, and tracks a
 * synthetic resolver given as raw 12-bit offset-binary ADC counts sample by sample, as an ADC
 * interrupt would: the counts go to at_chain_fixed_track_u16 as they are read (the chain's
 * ADC removes mid-scale and shifts them to 16 bits; no conversion in C), the estimate is read
 * on demand. Two checks against the true angle and speed over the last 0.1 s, each printing
 * PASS or FAIL:
 *  1. an imperfect sensor (offsets 36 and -27 counts, the sine channel 5 % larger,
 *     quadrature 30 mrad, and a 3rd-harmonic angle error of 4 mrad) through the 3rd-order
 *     chain from its integer constants with its stored calibration (the sensor's parameters
 *     in the observer's 16-bit counts) and the angle-correction table (from the error's
 *     harmonics, Q15): the angle within ANGLE_TOLERANCE_RAD, and the same sensor through
 *     the chain without the two corrections at least UNCORRECTED_FACTOR times worse;
 *  2. an ideal sensor through the 2nd-order chain quantised on the target from the float
 *     gains `angletrack design --format c` writes (at_fixed_gains_new), with
 *     at_chain_fixed_update_u16.
 * The image exits 0 if both pass. Built with -DCOUNT_SAMPLES=N, it only runs the corrected
 * chain of check 1 for N samples (run.sh counts its instructions per sample): from its
 * counts through at_chain_fixed_track_u16_order3, or, with -DCOUNT_INT16, the same chain
 * without its ADC on the same samples as int16 through at_chain_fixed_track_i16_order3; with
 * -DCOUNT_REFERENCE, the same through the library's Rust reference (the core's Tracker
 * called without the door, at_reference_track_u16 and _i16: the library built with its
 * feature count-reference), the state made by one call of the door first in both; with
 * -DCOUNT_REFERENCE -DCOUNT_INT16 -DCOUNT_COMPOSED, the same stages composed as a plain
 * Chain (at_reference_composed_track_i16). */
#include <math.h>
#include <stdio.h>

#include "angletrack.h"
#include "fixed_ato3.h"
#include "gains_ato2.h"
#include "semihosting.h"

/* Built with -DTAMPER, run.sh checks that both checks can fail: the synthetic signal's
 * sample period 1 % longer than the gains' (the true speed per sample 1 % above what the
 * checks expect). */
#ifdef TAMPER
#define SIGNAL_PERIOD_S (FIXED3_SAMPLE_PERIOD_S * 1.01)
#else
#define SIGNAL_PERIOD_S FIXED3_SAMPLE_PERIOD_S
#endif

#define PI 3.14159265358979323846
/* 3000 rpm electrical (50 Hz), 0.5 s at 10 kHz, the last 0.1 s checked. */
#define SPEED_RAD_S (2.0 * PI * 50.0)
#define SAMPLES 5000L
#define WINDOW 1000L
/* 12-bit offset-binary counts: mid-scale 2048, the cosine channel's amplitude 1800 counts
 * (28,800 in the observer's 16-bit counts: the monitor's nominal amplitude). */
#define AMPLITUDE_COUNTS 1800.0
#define ADC_SHIFT 4
#define NOMINAL_AMPLITUDE (AMPLITUDE_COUNTS * (1 << ADC_SHIFT))
/* The imperfect sensor of check 1 (12-bit counts, rad). */
#define OFFSET_C 36.0
#define OFFSET_S (-27.0)
#define AMPLITUDE_S 1890.0
#define QUADRATURE_RAD 0.03
#define HARMONIC_3_RAD 0.004
/* Tolerances over the window: 12-bit quantisation (1/1800 of the amplitude, about 0.6 mrad
 * per sample, filtered by the loop), the fixed point's sine table, the calibration's Q14
 * coefficients and the table's Q15 entries. Measured (printed): 106 urad corrected, 60 mrad
 * uncorrected (at least 20 times the tolerance required); 57 urad for the ideal sensor;
 * speeds within 21 mrad/s; a 1 % error of the speed is 3.1 rad/s. */
#define ANGLE_TOLERANCE_RAD 5e-4
#define UNCORRECTED_FACTOR 20.0
#define SPEED_TOLERANCE_RAD_S 0.1

/* Static memory, zeroed at start-up: the states are fresh. */
static at_fixed_gains gains3, gains2;
static at_chain_fixed corrected, uncorrected, ideal, samples_corrected;
static at_chain_state_fixed state;
static at_angle_table_fixed table;

/* The 12-bit ADC reading of `offset + amplitude * x`, offset binary. */
static uint16_t adc_counts(double offset, double amplitude, double x) {
  return (uint16_t)lrint(2048.0 + offset + amplitude * x);
}

/* The true angle of sample k (rad). */
static double true_angle(long k) { return 0.3 + SPEED_RAD_S * (double)k * SIGNAL_PERIOD_S; }

#ifndef COUNT_SAMPLES
/* The true angle of sample k as a binary angle (2^32 per turn, wrapping). */
static int32_t true_binary_angle(long k) {
  double turns = true_angle(k) / (2.0 * PI);
  turns -= floor(turns);
  return (int32_t)(uint32_t)(turns * 4294967296.0);
}
#endif

#ifdef COUNT_SAMPLES
#ifdef COUNT_REFERENCE
void at_reference_track_u16(const at_chain_fixed *chain, at_chain_state_fixed *state,
                            uint16_t raw_c, uint16_t raw_s);
void at_reference_track_i16(const at_chain_fixed *chain, at_chain_state_fixed *state,
                            int16_t raw_c, int16_t raw_s);
#define TRACK_U16(c, s, x, y) (at_reference_track_u16(c, s, x, y), 0u)
#ifdef COUNT_COMPOSED
/* The same stages composed (a Chain of the calibration, the table and the observer), in
 * words of this image's. */
_Bool at_reference_composed_new(const at_chain_fixed *chain, uint64_t *out, uint64_t *state);
void at_reference_composed_track_i16(const uint64_t *chain, uint64_t *state, int16_t raw_c,
                                     int16_t raw_s);
static uint64_t composed[100], composed_state[20];
#define TRACK_I16(c, s, x, y) (at_reference_composed_track_i16(composed, composed_state, x, y), 0u)
#else
#define TRACK_I16(c, s, x, y) (at_reference_track_i16(c, s, x, y), 0u)
#endif
#else
/* The chain is of order 3 (fixed_ato3.h): the per-order forms, as a firmware calls them. */
#define TRACK_U16 at_chain_fixed_track_u16_order3
#define TRACK_I16 at_chain_fixed_track_i16_order3
#endif
/* One period of the counted signal: 5 turns at 50 Hz sampled at 10 kHz. */
#define COUNTED_PERIOD 1000L
static uint16_t counted_c[COUNTED_PERIOD], counted_s[COUNTED_PERIOD];
#endif

/* The raw counts of sample k of the imperfect sensor (`imperfect`) or the ideal one. */
static void sensor(long k, int imperfect, uint16_t *raw_c, uint16_t *raw_s) {
  double theta = true_angle(k);
  if (!imperfect) {
    *raw_c = adc_counts(0.0, AMPLITUDE_COUNTS, cos(theta));
    *raw_s = adc_counts(0.0, AMPLITUDE_COUNTS, sin(theta));
    return;
  }
  double measured = theta + HARMONIC_3_RAD * sin(3.0 * theta);
  *raw_c = adc_counts(OFFSET_C, AMPLITUDE_COUNTS, cos(measured));
  *raw_s = adc_counts(OFFSET_S, AMPLITUDE_S, sin(measured + QUADRATURE_RAD));
}

#ifndef COUNT_SAMPLES
/* The worst errors of angle (rad) and speed (rad/s) over the last WINDOW samples, and the
 * faults there. */
struct result {
  double angle, speed;
  uint32_t faults;
};

/* Tracks the sensor through `chain` from a fresh state (at_chain_fixed_update_u16 if
 * `with_update`, else at_chain_fixed_track_u16 and the estimate on demand). */
static struct result track(const at_chain_fixed *chain, int imperfect, int with_update) {
  struct result r = {0.0, 0.0, 0u};
  at_chain_state_fixed_reset(&state);
  for (long k = 0; k < SAMPLES; k++) {
    uint16_t raw_c, raw_s;
    sensor(k, imperfect, &raw_c, &raw_s);
    at_fixed_estimate e;
    if (with_update) {
      e = at_chain_fixed_update_u16(chain, &state, raw_c, raw_s);
    } else {
      r.faults |= at_chain_fixed_track_u16(chain, &state, raw_c, raw_s);
      if (k < SAMPLES - WINDOW) continue;
      e = at_chain_fixed_estimate(chain, &state);
    }
    if (k < SAMPLES - WINDOW) continue;
    r.faults |= e.faults;
    /* The difference of binary angles wraps to the nearest turn exactly. */
    int32_t error = (int32_t)((uint32_t)e.angle - (uint32_t)true_binary_angle(k));
    double angle_error = fabs((double)error * (2.0 * PI / 4294967296.0));
    double speed_error = fabs(at_chain_fixed_speed_rad_s(chain, &e) - SPEED_RAD_S);
    if (angle_error > r.angle) r.angle = angle_error;
    if (speed_error > r.speed) r.speed = speed_error;
  }
  return r;
}

/* Prints a check's verdict line and returns it. */
static int verdict(int pass, const char *name, const struct result *r, const char *extra) {
  char line[300];
  snprintf(line, sizeof line,
           "%s %s: worst angle error %ld urad (tolerance %ld), worst speed error %ld mrad/s "
           "(tolerance %ld), faults 0x%lx%s\n",
           pass ? "PASS" : "FAIL", name, (long)lround(r->angle * 1e6),
           (long)lround(ANGLE_TOLERANCE_RAD * 1e6), (long)lround(r->speed * 1e3),
           (long)lround(SPEED_TOLERANCE_RAD_S * 1e3), (unsigned long)r->faults, extra);
  semihosting_write(line);
  return pass;
}

/* Whether `r` is within the tolerances, without faults. */
static int within(const struct result *r) {
  return r->angle <= ANGLE_TOLERANCE_RAD && r->speed <= SPEED_TOLERANCE_RAD_S && r->faults == 0u;
}

#endif

/* Writes the refusal of a constructor and returns 0, or returns 1 for AT_OK. */
static int accepted(const char *what, at_status status) {
  if (status == AT_OK) return 1;
  semihosting_write("FAIL: ");
  semihosting_write(what);
  semihosting_write(" refused: ");
  semihosting_write(at_status_message(status));
  semihosting_write("\n");
  return 0;
}

/* Builds the three chains: the sensor's calibration in the observer's 16-bit counts (as
 * `angletrack calibrate` learns it from those samples), its angle error's harmonics. */
static int build(void) {
  at_adc_counts adc;
  at_sensor_calibration_f32 calibration = {
      .offset_c = (float)(OFFSET_C * (1 << ADC_SHIFT)),
      .offset_s = (float)(OFFSET_S * (1 << ADC_SHIFT)),
      .amplitude_c = (float)(AMPLITUDE_COUNTS * (1 << ADC_SHIFT)),
      .amplitude_s = (float)(AMPLITUDE_S * (1 << ADC_SHIFT)),
      .quadrature_rad = (float)QUADRATURE_RAD,
  };
  at_angle_correction_f32 harmonics = {{0.0f}, {0.0f, 0.0f, (float)HARMONIC_3_RAD}};
  return accepted("the ADC", at_adc_counts_offset_binary(12, &adc)) &&
         accepted("the fixed-point constants",
                  at_fixed_gains_from_constants(fixed3_gain_multiplier, FIXED3_ORDER,
                                                FIXED3_ACCELERATION_SHIFT, FIXED3_SAMPLE_PERIOD_S,
                                                &gains3)) &&
         accepted("the float gains",
                  at_fixed_gains_new(ato2_gains, ATO2_ORDER, ATO2_SAMPLE_PERIOD_S, &gains2)) &&
         accepted("the table", at_angle_table_fixed_from_harmonics(&harmonics, &table)) &&
         accepted("the corrected chain", at_chain_fixed_new(&gains3, &adc, &calibration, &table,
                                                            NOMINAL_AMPLITUDE, &corrected)) &&
         accepted("the uncorrected chain",
                  at_chain_fixed_new(&gains3, &adc, NULL, NULL, NOMINAL_AMPLITUDE, &uncorrected)) &&
         accepted("the ideal sensor's chain",
                  at_chain_fixed_new(&gains2, &adc, NULL, NULL, NOMINAL_AMPLITUDE, &ideal)) &&
         accepted("the corrected chain without its ADC",
                  at_chain_fixed_new(&gains3, NULL, &calibration, &table, NOMINAL_AMPLITUDE,
                                     &samples_corrected));
}

int main(void) {
  if (at_layout_version() != AT_LAYOUT_VERSION) {
    semihosting_write("FAIL: the library's struct layout is not the header's\n");
    return 1;
  }
  if (!build()) return 1;
#ifdef COUNT_SAMPLES
  /* Counted: the instructions inside at_chain_fixed_track_u16 and what it calls (run.sh).
   * The counts are computed first, for one period of the signal, and replayed: the
   * harness's double arithmetic then costs the 1000- and 2000-sample runs the same, so that
   * a library routine the chain shares with it (a 64-bit multiply) is not counted for it. */
  uint32_t faults = 0;
  for (long k = 0; k < COUNTED_PERIOD; k++) sensor(k, 1, &counted_c[k], &counted_s[k]);
  long i = 0;
#ifdef COUNT_INT16
  /* The chain without its ADC on the same samples as int16 (mid-scale removed, shifted by
   * 4, as its ADC stage would), through at_chain_fixed_track_i16. */
  static int16_t samples_c[COUNTED_PERIOD], samples_s[COUNTED_PERIOD];
  for (long k = 0; k < COUNTED_PERIOD; k++) {
    samples_c[k] = (int16_t)((counted_c[k] - 2048) * (1 << ADC_SHIFT));
    samples_s[k] = (int16_t)((counted_s[k] - 2048) * (1 << ADC_SHIFT));
  }
  faults |= at_chain_fixed_track_i16(&samples_corrected, &state, samples_c[0], samples_s[0]);
#ifdef COUNT_COMPOSED
  if (!at_reference_composed_new(&samples_corrected, composed, composed_state)) return 1;
  at_reference_composed_track_i16(composed, composed_state, samples_c[0], samples_s[0]);
#endif
  for (long k = 0; k < COUNT_SAMPLES; k++) {
    faults |= TRACK_I16(&samples_corrected, &state, samples_c[i], samples_s[i]);
    if (++i == COUNTED_PERIOD) i = 0;
  }
#else
  faults |= at_chain_fixed_track_u16(&corrected, &state, counted_c[0], counted_s[0]);
  for (long k = 0; k < COUNT_SAMPLES; k++) {
    faults |= TRACK_U16(&corrected, &state, counted_c[i], counted_s[i]);
    if (++i == COUNTED_PERIOD) i = 0;
  }
#endif
  return faults == 0u ? 0 : 1;
#else
  struct result good = track(&corrected, 1, 0);
  struct result bad = track(&uncorrected, 1, 0);
  char extra[120];
  int worse = bad.angle >= UNCORRECTED_FACTOR * ANGLE_TOLERANCE_RAD;
  snprintf(extra, sizeof extra, "; without the corrections %ld urad (at least %ld)",
           (long)lround(bad.angle * 1e6), (long)lround(UNCORRECTED_FACTOR * ANGLE_TOLERANCE_RAD * 1e6));
  int pass = verdict(within(&good) && worse,
                     "cortex-m0 fixed-point chain, 3rd order from constants, 12-bit counts, "
                     "stored calibration and angle table",
                     &good, extra);
  struct result plain = track(&ideal, 0, 1);
  pass &= verdict(within(&plain),
                  "cortex-m0 fixed-point chain, 2nd order from float gains, 12-bit counts", &plain,
                  "");
  return pass ? 0 : 1;
#endif
}
