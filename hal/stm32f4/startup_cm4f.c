/**
 * @file startup_cm4f.c
 * @brief Reset handler and fault entry for Cortex-M4F images (see startup.h).
 *
 * Order matters: the FPU is enabled before anything that could touch a floating-point
 * register (CPACR, PM0214 section 4.6.1: "you must enable the FPU before any floating-point
 * instruction"), then .data is copied and .bss zeroed with plain word loops (no library call,
 * nothing that assumes initialised memory), then the stack below the current frame is painted.
 */
#include "startup.h"

#include "stm32f4_regs.h"

/* Linker-script symbols (addresses only; their "values" are meaningless). */
extern uint32_t _sidata; /**< load address of .data in flash */
extern uint32_t _sdata;  /**< start of .data in RAM */
extern uint32_t _edata;  /**< end of .data in RAM */
extern uint32_t _sbss;   /**< start of .bss */
extern uint32_t _ebss;   /**< end of .bss */
extern uint32_t _sstack; /**< lowest address of the stack region */
extern uint32_t _estack; /**< initial stack pointer (top of the stack region) */

void Reset_Handler(void);

static uint32_t current_sp(void)
{
    uint32_t sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

void Reset_Handler(void)
{
    volatile uint32_t *dst;
    const volatile uint32_t *src;
    uint32_t sp;
    /* Compared as addresses: the linker symbols are distinct objects to the C language. */
    const uintptr_t data_end = (uintptr_t)&_edata;
    const uintptr_t bss_end = (uintptr_t)&_ebss;

    /* 1. FPU: full access for CP10 and CP11, then barriers so the next instruction sees it. */
    SCB_CPACR |= SCB_CPACR_CP10_CP11_FULL;
    __asm__ volatile("dsb\n\tisb" ::: "memory");

    /* 2. .data: copy the initial values from flash. volatile keeps the compiler from turning
     * these loops into memcpy/memset calls (the library is not ready to be called yet). */
    src = &_sidata;
    for (dst = &_sdata; (uintptr_t)dst < data_end; ++dst, ++src) {
        *dst = *src;
    }
    /* 3. .bss: zero. */
    for (dst = &_sbss; (uintptr_t)dst < bss_end; ++dst) {
        *dst = 0u;
    }
    /* 4. Paint the free stack, leaving a margin below this frame. */
    sp = current_sp() - 64u;
    for (dst = &_sstack; (uint32_t)dst < sp; ++dst) {
        *dst = STARTUP_STACK_PAINT;
    }

    (void)main();
    /* main() does not return on the ECU; if it does, stop here. */
    for (;;) {
        __asm__ volatile("wfi");
    }
}

uint32_t startup_stack_size_bytes(void)
{
    return (uint32_t)((uintptr_t)&_estack - (uintptr_t)&_sstack);
}

uint32_t startup_stack_high_water_bytes(void)
{
    const volatile uint32_t *p = &_sstack;
    while ((uintptr_t)p < (uintptr_t)&_estack && *p == STARTUP_STACK_PAINT) {
        ++p;
    }
    return (uint32_t)((uintptr_t)&_estack - (uintptr_t)p);
}

__attribute__((weak)) void startup_fault_hook(uint32_t exception_number)
{
    (void)exception_number;
}
