/* A minimal Cortex-M start-up for the C examples under QEMU (the Cortex-M4F's and the
 * Cortex-M0's): the vector table, the reset handler (the FPU on where there is one, .data
 * copied, .bss zeroed, main called) and the two semihosting calls
 * the example needs: write a string to the host's console, and exit QEMU with a status. */
#include <stdint.h>

#include "semihosting.h"

extern uint32_t _data_start, _data_end, _data_load, _bss_start, _bss_end, _stack_top;
int main(void);

/* One semihosting call: the operation in r0, its argument in r1, `bkpt 0xab`. */
static uint32_t semihosting_call(uint32_t operation, const void *argument) {
  register uint32_t r0 __asm__("r0") = operation;
  register const void *r1 __asm__("r1") = argument;
  __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

void semihosting_write(const char *text) {
  semihosting_call(0x04u /* SYS_WRITE0 */, text);
}

void semihosting_exit(int status) {
  /* SYS_EXIT with ADP_Stopped_ApplicationExit: QEMU exits 0; any other reason: 1. */
  uint32_t reason = status == 0 ? 0x20026u : 0x20023u /* ADP_Stopped_RunTimeErrorUnknown */;
  semihosting_call(0x18u, (const void *)(uintptr_t)reason);
  for (;;) {
  }
}

void Reset_Handler(void) {
#if defined(__ARM_FP)
  /* Full access to CP10 and CP11 (the FPU) before any floating-point instruction. */
  *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20;
  __asm__ volatile("dsb\n isb" ::: "memory");
#endif
  for (uint32_t *from = &_data_load, *to = &_data_start; to < &_data_end;) *to++ = *from++;
  for (uint32_t *to = &_bss_start; to < &_bss_end;) *to++ = 0u;
  semihosting_exit(main());
}

static void Fault_Handler(void) {
  semihosting_write("FAIL: fault exception\n");
  semihosting_exit(1);
}

/* The initial stack pointer, then the exception handlers (reset and the faults). */
__attribute__((section(".vectors"), used)) static const void *const vectors[16] = {
    &_stack_top,   Reset_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler,
};
