/* The C API on a Cortex-M4F: a firmware written in C against angletrack.h, linked with the
 * static library built for thumbv7em-none-eabihf, run under QEMU mps2-an386 (run.sh). It
 * takes the gains `angletrack design --format c` writes (gains_ato3.h), checks them once
 * at start-up with the chains it puts them in, tracks the synthetic resolver of the host
 * test (scenario.h: floats, then 12-bit ADC counts, then through the online calibration)
 * sample by sample as an ADC interrupt would, and exits 0 if the estimates are within the host test's tolerances. */
#include "angletrack.h"
#include "gains_ato3.h"
/* Built with -DTAMPER, run.sh checks that every check can fail, each on one corrupted
 * input: the sample period of the synthetic signal 1 % longer than the gains' (the true
 * speed per sample is 1 % above the speed the tracking checks expect), and the learned
 * sensor's cosine offset 0.06 where the calibration check expects 0.05. */
#ifdef TAMPER
#define SIGNAL_PERIOD_S (ATO3_SAMPLE_PERIOD_S * 1.01)
#define SCENARIO_SIGNAL_OFFSET_C 0.06f
#else
#define SIGNAL_PERIOD_S ATO3_SAMPLE_PERIOD_S
#endif

#include "scenario.h"
#include "semihosting.h"

/* Static memory, zeroed at start-up: the states are fresh. */
static at_gains_f32 gains;
static at_adc_f32 adc;
static at_chain_f32 plain, counts, calibrated;
static at_chain_state_f32 state;

static int track(const char *name, const at_chain_f32 *chain, int from_counts,
                 float angle_tolerance_rad, float speed_tolerance_rad_s) {
  char line[256];
  scenario_result r = scenario_track(chain, &state, from_counts, SCENARIO_SPEED_RAD_S,
                                     SIGNAL_PERIOD_S, SCENARIO_AMPLITUDE, SCENARIO_SAMPLES,
                                     SCENARIO_WINDOW);
  int pass = scenario_passes(name, r, angle_tolerance_rad, speed_tolerance_rad_s, line,
                             sizeof line);
  semihosting_write(line);
  return pass;
}

int main(void) {
  at_status status = at_gains_f32_new(ato3_gains, ATO3_ORDER, ATO3_SAMPLE_PERIOD_S, &gains);
  if (status != AT_OK) {
    semihosting_write("FAIL: gains refused: ");
    semihosting_write(at_status_message(status));
    semihosting_write("\n");
    return 1;
  }
  /* Three chains, built once: the observer alone, after the 12-bit ADC, after the online
   * calibration. */
  at_calibration_settings_f32 settings = at_calibration_settings_f32_default();
  if (at_adc_f32_offset_binary(12, &adc) != AT_OK ||
      at_chain_f32_new(&gains, NULL, NULL, NULL, NULL, NULL, &plain) != AT_OK ||
      at_chain_f32_new(&gains, &adc, NULL, NULL, NULL, NULL, &counts) != AT_OK ||
      at_chain_f32_new(&gains, NULL, NULL, &settings, NULL, NULL, &calibrated) != AT_OK) {
    semihosting_write("FAIL: a chain refused\n");
    return 1;
  }
  /* The host test's tolerances. */
  int pass = track("cortex-m4f 3rd order, 50 Hz", &plain, 0, SCENARIO_ANGLE_TOLERANCE_RAD,
                   SCENARIO_SPEED_TOLERANCE_RAD_S);
  pass &= track("cortex-m4f 3rd order, 12-bit ADC counts", &counts, 1,
                SCENARIO_ADC_ANGLE_TOLERANCE_RAD, SCENARIO_ADC_SPEED_TOLERANCE_RAD_S);
  char line[256];
  at_sensor_calibration_f32 learned;
  pass &= scenario_calibrate(&calibrated, &state, SIGNAL_PERIOD_S, &learned, line, sizeof line);
  semihosting_write(line);
  return pass ? 0 : 1;
}
