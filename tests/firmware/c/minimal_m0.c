/* The flash the C API's fixed-point chain adds to a minimal Cortex-M0 image (run.sh
 * `flash`): a firmware that builds the 3rd-order chain from counts with a stored
 * calibration and an angle-correction table, all its configuration constants in flash
 * (the integer gains of fixed_ato3.h, the ADC's settings, the calibration and the table),
 * then tracks the counts an ADC register gives. Built with -DWITHOUT_LIBRARY, the same
 * image without any call of the library (the register read and its result kept): the
 * difference of the two images' flash is what the library adds. */
#include <stdint.h>

#include "angletrack.h"
#include "fixed_ato3.h"

/* The ADC's two result registers, as a firmware reads them (here: RAM QEMU leaves be). */
static volatile uint16_t adc_c, adc_s;
/* Where the firmware would use the tracked faults. */
static volatile uint32_t used;

#ifndef WITHOUT_LIBRARY
static const at_adc_counts adc = {2048, 4};
static const at_sensor_calibration_f32 calibration = {576.0f, -432.0f, 28800.0f, 30240.0f,
                                                      0.03f};
/* A table of angle errors in Q15 (its values do not matter to the size). */
static const at_angle_table_fixed table = {{0}};
static at_fixed_gains gains;
static at_chain_fixed chain;
static at_chain_state_fixed state;
#endif

int main(void) {
#ifndef WITHOUT_LIBRARY
  if (at_fixed_gains_from_constants(fixed3_gain_multiplier, FIXED3_ORDER,
                                    FIXED3_ACCELERATION_SHIFT, FIXED3_SAMPLE_PERIOD_S,
                                    &gains) != AT_OK ||
      at_chain_fixed_new(&gains, &adc, &calibration, &table, 28800.0, &chain) != AT_OK) {
    return 1;
  }
#endif
  for (int k = 0; k < 100; k++) {
#ifndef WITHOUT_LIBRARY
    used = at_chain_fixed_track_u16_order3(&chain, &state, adc_c, adc_s);
#else
    used = (uint32_t)adc_c + adc_s;
#endif
  }
  return 0;
}
