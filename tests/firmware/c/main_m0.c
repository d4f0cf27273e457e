/* The C API's fixed-point observer on a Cortex-M0 (no FPU): a firmware written in C against
 * angletrack.h, linked with the static library built for thumbv6m-none-eabi, run under QEMU
 * microbit (run.sh). It takes the integer constants `angletrack design --dtype fixed
 * --format c` prints (fixed_ato3.h), checks them once at start-up, and tracks a synthetic
 * resolver given as 12-bit offset-binary ADC counts (amplitude 1800 counts) sample by sample
 * as an ADC interrupt would: the counts to the observer's int16 input (mid-scale removed,
 * shifted left by 4: amplitude 28,800, done here in C: the core's fixed-point path has no
 * ADC stage), then at_fixed_track, with the estimate read on demand. Two checks against the
 * true angle and speed over the last 0.1 s, each printing PASS or FAIL:
 *  1. the 3rd-order observer from its integer constants (at_fixed_gains_from_constants),
 *     at_fixed_track + at_fixed_state_estimate;
 *  2. the 2nd-order observer quantised on the target from the float gains `angletrack design
 *     --format c` writes (at_fixed_gains_new), at_fixed_update.
 * The image exits 0 if both pass. */
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
/* 12-bit offset-binary counts: mid-scale 2048, amplitude 1800 counts. */
#define AMPLITUDE_COUNTS 1800.0f
/* The observer's input: counts less mid-scale, shifted left by 4 (amplitude 28,800), the
 * monitor's nominal amplitude. */
#define INPUT_SHIFT 4
#define NOMINAL_AMPLITUDE (1800.0 * 16.0)
/* Tolerances over the window: 12-bit quantisation (1/1800 of the amplitude, about 0.6 mrad
 * per sample, filtered by the loop) and the fixed point's sine table. Measured (printed):
 * 85 and 59 urad, 18 and 5 mrad/s; a 1 % error of the speed is 3.1 rad/s. */
#define ANGLE_TOLERANCE_RAD 3e-4
#define SPEED_TOLERANCE_RAD_S 0.1

/* Static memory, zeroed at start-up: the states are fresh. */
static at_fixed_gains gains3, gains2;
static at_fixed_state state;

/* The 12-bit ADC reading of amplitude * x, offset binary. */
static uint16_t adc_counts(float x) {
  return (uint16_t)lrintf(2048.0f + AMPLITUDE_COUNTS * x);
}

/* An offset-binary 12-bit reading as the observer's input: mid-scale removed, shifted. */
static int16_t observer_input(uint16_t raw) {
  return (int16_t)(((int32_t)raw - 2048) * (1 << INPUT_SHIFT));
}

/* The true angle of sample k as a binary angle (2^32 per turn, wrapping). */
static int32_t true_binary_angle(long k) {
  double turns = (0.3 + SPEED_RAD_S * (double)k * SIGNAL_PERIOD_S) / (2.0 * PI);
  turns -= floor(turns);
  return (int32_t)(uint32_t)(turns * 4294967296.0);
}

/* Tracks the scenario through `gains` (via at_fixed_update if `with_update`, else
 * at_fixed_track and the estimate on demand) from a fresh state; prints and returns the
 * check's verdict. */
static int track(const char *name, const at_fixed_gains *gains, int with_update) {
  double worst_angle = 0.0, worst_speed = 0.0;
  uint32_t faults = 0;
  at_fixed_state_reset(&state);
  for (long k = 0; k < SAMPLES; k++) {
    double theta = (0.3 + SPEED_RAD_S * (double)k * SIGNAL_PERIOD_S);
    int16_t y_c = observer_input(adc_counts(cosf((float)theta)));
    int16_t y_s = observer_input(adc_counts(sinf((float)theta)));
    at_fixed_estimate e;
    if (with_update) {
      e = at_fixed_update(gains, &state, y_c, y_s);
    } else {
      faults |= at_fixed_track(gains, &state, y_c, y_s);
      if (k < SAMPLES - WINDOW) continue;
      e = at_fixed_state_estimate(&state);
    }
    if (k < SAMPLES - WINDOW) continue;
    faults |= e.faults;
    /* The difference of binary angles wraps to the nearest turn exactly. */
    int32_t error = (int32_t)((uint32_t)e.angle - (uint32_t)true_binary_angle(k));
    double angle_error = fabs((double)error * (2.0 * PI / 4294967296.0));
    double speed_error = fabs(at_fixed_speed_rad_s(gains, &e) - SPEED_RAD_S);
    if (angle_error > worst_angle) worst_angle = angle_error;
    if (speed_error > worst_speed) worst_speed = speed_error;
  }
  int pass = worst_angle <= ANGLE_TOLERANCE_RAD && worst_speed <= SPEED_TOLERANCE_RAD_S &&
             faults == 0u;
  char line[200];
  snprintf(line, sizeof line,
           "%s %s: worst angle error %ld urad (tolerance %ld), worst speed error %ld mrad/s "
           "(tolerance %ld), faults 0x%lx\n",
           pass ? "PASS" : "FAIL", name, (long)lround(worst_angle * 1e6),
           (long)lround(ANGLE_TOLERANCE_RAD * 1e6), (long)lround(worst_speed * 1e3),
           (long)lround(SPEED_TOLERANCE_RAD_S * 1e3), (unsigned long)faults);
  semihosting_write(line);
  return pass;
}

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

int main(void) {
  if (at_layout_version() != AT_LAYOUT_VERSION) {
    semihosting_write("FAIL: the library's struct layout is not the header's\n");
    return 1;
  }
  if (!accepted("the fixed-point constants",
                at_fixed_gains_from_constants(fixed3_gain_multiplier, FIXED3_ORDER,
                                              FIXED3_ACCELERATION_SHIFT, FIXED3_SAMPLE_PERIOD_S,
                                              &gains3)) ||
      !accepted("the monitor's amplitude", at_fixed_gains_set_monitor(&gains3, NOMINAL_AMPLITUDE)) ||
      !accepted("the float gains",
                at_fixed_gains_new(ato2_gains, ATO2_ORDER, ATO2_SAMPLE_PERIOD_S, &gains2)) ||
      !accepted("the monitor's amplitude", at_fixed_gains_set_monitor(&gains2, NOMINAL_AMPLITUDE))) {
    return 1;
  }
  int pass = track("cortex-m0 fixed point, 3rd order from constants, 12-bit counts", &gains3, 0);
  pass &= track("cortex-m0 fixed point, 2nd order from float gains, 12-bit counts", &gains2, 1);
  return pass ? 0 : 1;
}
