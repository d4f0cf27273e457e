/* The flash the C API's fixed-point chain adds to a minimal Cortex-M0 image (run.sh
 * `flash`): a firmware that builds the 3rd-order chain from counts with a stored
 * calibration and an angle-correction table from the integers `angletrack export --format
 * c` writes (identity/motor_fixed.h, the C door's identity test's tracker file:
 * motor_fixed_chain, `static const` in flash) by at_chain_fixed_from_constants (no
 * floating-point arithmetic), then tracks the counts an ADC register gives. Built with
 * -DWITHOUT_LIBRARY, the same image without any call of the library (the register read and
 * its result kept): the difference of the two images' flash is what the library adds. */
#include <stdint.h>

#include "angletrack.h"
#include "identity/motor_fixed.h"

/* The ADC's two result registers, as a firmware reads them (here: RAM QEMU leaves be). */
static volatile uint16_t adc_c, adc_s;
/* Where the firmware would use the tracked faults. */
static volatile uint32_t used;

#ifndef WITHOUT_LIBRARY
static at_chain_fixed chain;
static at_chain_state_fixed state;
#endif

int main(void) {
#ifndef WITHOUT_LIBRARY
  if (at_chain_fixed_from_constants(&motor_fixed_chain, &chain) != AT_OK) {
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
