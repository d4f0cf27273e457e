/* The synthetic resolver that the C tests track (the host test, test_host.c, and the
 * Cortex-M4F example, tests/firmware/c/main.c): y_c = A cos(theta), y_s = A sin(theta) at a
 * constant speed, and the check of the estimates against the true angle and speed once the
 * loop has settled. Header-only (static functions), so that both include it by path. */
#ifndef ANGLETRACK_SCENARIO_H
#define ANGLETRACK_SCENARIO_H

#include <math.h>
#include <stdio.h>

#include "angletrack.h"

#define SCENARIO_PI 3.14159265358979323846

/* The scenario: 3000 rpm electrical, amplitude 0.9, 0.5 s at 10 kHz (the 3rd-order
 * benchmark loop settles within 0.3 s), the last 0.1 s checked. */
#define SCENARIO_SPEED_RAD_S (2.0 * SCENARIO_PI * 50.0)
#define SCENARIO_AMPLITUDE 0.9f
#define SCENARIO_SAMPLES 5000L
#define SCENARIO_WINDOW 1000L
/* Tolerances over the window: a settled type II or III loop has no error at constant
 * speed; what is left is f32 rounding (of the angle near pi, 2.4e-7 rad) and the fast
 * sin/cos (3e-7); the ADC path adds 12-bit quantisation (1/2048 of full scale). */
#define SCENARIO_ANGLE_TOLERANCE_RAD 1e-4f
#define SCENARIO_SPEED_TOLERANCE_RAD_S 0.05f
#define SCENARIO_ADC_ANGLE_TOLERANCE_RAD 5e-4f
#define SCENARIO_ADC_SPEED_TOLERANCE_RAD_S 0.2f

/* What the check found over its window. */
typedef struct {
  float max_angle_error_rad; /* largest |estimated - true angle| */
  float max_speed_error_rad_s; /* largest |estimated - true speed| */
  uint32_t faults; /* union of the faults flagged */
  int64_t turns; /* the last estimate's turn count */
} scenario_result;

/* The true angle (rad, in [-pi, pi)) of sample k at speed_rad_s from 0.3 rad, computed in
 * double so that the reference stays exact over many turns. */
static double scenario_angle(long k, double speed_rad_s, double sample_period_s) {
  double theta = fmod(0.3 + speed_rad_s * (double)k * sample_period_s, 2.0 * SCENARIO_PI);
  if (theta < 0.0) theta += 2.0 * SCENARIO_PI;
  return theta >= SCENARIO_PI ? theta - 2.0 * SCENARIO_PI : theta;
}

/* The angle error wrapped to [-pi, pi). */
static float scenario_wrapped(double error) {
  error = fmod(error + 3.0 * SCENARIO_PI, 2.0 * SCENARIO_PI);
  if (error < 0.0) error += 2.0 * SCENARIO_PI;
  return (float)(error - SCENARIO_PI);
}

/* Tracks `samples` samples of amplitude `amplitude` at `speed_rad_s` through `chain` from
 * a fresh state `state`, as floats (at_chain_f32_update), or, if `counts`, as 12-bit
 * offset-binary counts (at_chain_f32_update_u16: a chain with the 12-bit ADC stage); checks
 * the last `window` samples. */
static scenario_result scenario_track(const at_chain_f32 *chain, at_chain_state_f32 *state,
                                      int counts, double speed_rad_s, double sample_period_s,
                                      float amplitude, long samples, long window) {
  scenario_result r = {0.0f, 0.0f, 0u, 0};
  at_chain_state_f32_reset(state);
  for (long k = 0; k < samples; k++) {
    double theta = scenario_angle(k, speed_rad_s, sample_period_s);
    float y_c = amplitude * cosf((float)theta);
    float y_s = amplitude * sinf((float)theta);
    at_estimate_f32 e;
    if (counts) {
      e = at_chain_f32_update_u16(chain, state, (uint16_t)lrintf(2048.0f + 2048.0f * y_c),
                                  (uint16_t)lrintf(2048.0f + 2048.0f * y_s));
    } else {
      e = at_chain_f32_update(chain, state, y_c, y_s);
    }
    if (k < samples - window) continue;
    float angle_error = fabsf(scenario_wrapped((double)e.angle - theta));
    float speed_error = fabsf(e.speed - (float)speed_rad_s);
    if (angle_error > r.max_angle_error_rad) r.max_angle_error_rad = angle_error;
    if (speed_error > r.max_speed_error_rad_s) r.max_speed_error_rad_s = speed_error;
    r.faults |= e.faults;
    r.turns = e.turns;
  }
  return r;
}

/* 1 (and a PASS line in `line`) if the result is within the tolerances, else 0 (FAIL). */
static int scenario_passes(const char *name, scenario_result r, float angle_tolerance_rad,
                           float speed_tolerance_rad_s, char *line, size_t len) {
  int pass = r.max_angle_error_rad <= angle_tolerance_rad &&
             r.max_speed_error_rad_s <= speed_tolerance_rad_s && r.faults == 0u;
  snprintf(line, len,
           "%s %s: max angle error %.3g rad (tolerance %.3g), max speed error %.3g rad/s "
           "(tolerance %.3g), faults 0x%lx, turns %ld\n",
           pass ? "PASS" : "FAIL", name, (double)r.max_angle_error_rad,
           (double)angle_tolerance_rad, (double)r.max_speed_error_rad_s,
           (double)speed_tolerance_rad_s, (unsigned long)r.faults, (long)r.turns);
  return pass;
}

/* The cosine offset of the sensor that scenario_calibrate's signal comes from; its check
 * expects 0.05. A firmware test defines it otherwise before the include to see the check
 * fail (tests/firmware/c/main.c, -DTAMPER). */
#ifndef SCENARIO_SIGNAL_OFFSET_C
#define SCENARIO_SIGNAL_OFFSET_C 0.05f
#endif

/* Learns a sensor with offsets 0.05 and -0.05, amplitude ratio 1.1 and quadrature 0.05 rad
 * through `chain` (with the online calibration stage) at the scenario's speed, from a fresh
 * state `state` set to learn; writes the learned calibration to `learned` and a line to
 * `line`; 1 (PASS) if it is within 5e-3 of the sensor's. */
static int scenario_calibrate(const at_chain_f32 *chain, at_chain_state_f32 *state,
                              double sample_period_s, at_sensor_calibration_f32 *learned,
                              char *line, size_t len) {
  at_chain_state_f32_reset(state);
  int pass = at_chain_state_f32_set_calibration_mode(state, AT_CALIBRATION_LEARNING) == AT_OK;
  for (long k = 0; k < SCENARIO_SAMPLES; k++) {
    float theta = (float)scenario_angle(k, SCENARIO_SPEED_RAD_S, sample_period_s);
    at_chain_f32_track(chain, state, SCENARIO_SIGNAL_OFFSET_C + cosf(theta),
                       -0.05f + 1.1f * sinf(theta + 0.05f));
  }
  pass &= at_chain_state_f32_calibration(state, learned) == AT_OK;
  float ratio = learned->amplitude_s / learned->amplitude_c;
  pass &= fabsf(learned->offset_c - 0.05f) < 5e-3f && fabsf(learned->offset_s + 0.05f) < 5e-3f &&
          fabsf(ratio - 1.1f) < 5e-3f && fabsf(learned->quadrature_rad - 0.05f) < 5e-3f;
  snprintf(line, len,
           "%s online calibration: learned in %u turns offsets %.4f %.4f, amplitude ratio %.4f, "
           "quadrature %.4f rad (sensor: 0.05 -0.05, 1.1, 0.05; tolerance 5e-3)\n",
           pass ? "PASS" : "FAIL", (unsigned)at_chain_state_f32_turns_learned(state),
           (double)learned->offset_c, (double)learned->offset_s, (double)ratio,
           (double)learned->quadrature_rad);
  return pass;
}

#endif /* ANGLETRACK_SCENARIO_H */
