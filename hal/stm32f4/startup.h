/**
 * @file startup.h
 * @brief Cortex-M4F start-up shared by the ECU image and the QEMU test images: the reset
 *        handler enables the FPU, copies .data from flash, zeroes .bss, paints the stack and
 *        calls main(). Symbols come from the linker script (stm32f405.ld, tests' mps2_an386.ld).
 */
#ifndef STARTUP_H
#define STARTUP_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Word written over the unused stack at reset; the high-water mark is where it stops. */
#define STARTUP_STACK_PAINT 0xA5A5A5A5u

/** Stack size reserved by the linker script [bytes]. */
uint32_t startup_stack_size_bytes(void);

/**
 * Deepest stack use since reset [bytes]: the stack is painted at reset and scanned here from
 * its bottom for the first overwritten word. Slow (walks the whole stack): call it from the
 * main loop, not from an interrupt.
 */
uint32_t startup_stack_high_water_bytes(void);

/**
 * Called by every fault and unexpected-interrupt handler with the active exception number
 * (IPSR). Weak default: nothing. The ECU overrides it to put the bridge into its safe state;
 * the QEMU images override it to report the fault and exit. It must not return normally for a
 * fault to be safe: the caller then waits forever (for the watchdog).
 */
void startup_fault_hook(uint32_t exception_number);

/** The vector table as words: [0] initial stack pointer, [1] reset handler, [16 + n] IRQ n. */
const uint32_t *startup_vector_words(void);

/** The C entry point, called by the reset handler. */
int main(void);

#ifdef __cplusplus
}
#endif

#endif /* STARTUP_H */
