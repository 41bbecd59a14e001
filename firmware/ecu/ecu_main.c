/**
 * @file ecu_main.c
 * @brief The throttle ECU image for STM32F405/407: clock set-up, application and CAN protocol
 *        node, HAL, watchdog, then the 1 kHz control interrupt does the work:
 *
 *   TIM2 update (1 kHz, phase-locked to the PWM)  -> TIM2_IRQHandler() -> ecu_control_tick():
 *       app_tick()            ADC -> app_step() -> PWM / bridge enable, timed with the DWT
 *       CAN commands in       can_proto_node_receive() for each queued frame
 *       watchdog of commands  can_proto_node_update()
 *       telemetry out         can_proto_node_transmit() + the ECU's TV_ECU_CPU frame
 *   main loop: reload the IWDG when control ticks keep coming, otherwise sleep (WFI).
 *
 * Boot state: the protocol node starts in link state WAITING with the application forced to
 * APP_MODE_OFF (PWM 0, bridge disabled, estimator running) until a valid TV_CMD_CONTROL
 * arrives; a clock fault (HSE or PLL failed) keeps it OFF for good.
 *
 * Built a second time as ecu_trace.elf with ECU_TRACE: the same code, plus semihosting prints
 * of the boot and of the first ECU_TRACE_TICKS control ticks, then exit - for QEMU's
 * netduinoplus2 (STM32F405). That build must not run on a board without a debugger.
 */
#include <stddef.h>
#include <stdint.h>

#include "app.h"
#include "app_tick.h"
#include "can_proto.h"
#include "cycle_stats.h"
#include "hal.h"
#include "startup.h"
#include "stm32f4_board.h"
#include "stm32f4_hal.h"
#include "stm32f4_regs.h"
#include "tv_status.h"

#ifdef ECU_TRACE
#include "semihost.h"
#ifndef ECU_TRACE_TICKS
#define ECU_TRACE_TICKS 20u
#endif
#endif

/* The largest burst of one tick (after a stall every telemetry frame is due, and TV_ECU_CPU may
 * be too) fits the HAL's software transmit queue, empty or nearly so at the start of a tick. */
typedef char ecu_can_burst_fits_t[CAN_PROTO_N_TX + 1u <= STM32F4_CAN_QUEUE_LEN ? 1 : -1];

static app_t s_app;
static app_output_t s_out;
static can_proto_node_t s_node;
static cycle_stats_t s_cycles;    /**< app_tick() execution time */
static volatile uint32_t s_ticks; /**< control ticks run */
static uint32_t s_cycles_per_us;  /**< HCLK / 1 MHz */
static uint32_t s_period_cycles;  /**< HCLK / 1 kHz */
static uint32_t s_clock_degraded; /**< 1: not on the 168 MHz HSE clock: outputs stay OFF */
static int s_last_rc;             /**< app_tick() result of the last tick */
static uint8_t s_cpu_counter;
static uint64_t s_cpu_due_us;

static void force_off(void)
{
    if (s_app.cfg.control.mode != APP_MODE_OFF) {
        app_control_t ctl = s_app.cfg.control;
        ctl.mode = APP_MODE_OFF;
        (void)app_set_control(&s_app, &ctl);
    }
}

static void ecu_control_tick(void)
{
    hal_can_frame_t frames[CAN_PROTO_N_TX];
    hal_can_frame_t f;
    can_proto_loop_stats_t loop;
    stm32f4_status_t st;
    uint32_t c0;
    uint32_t cycles;
    uint64_t t_us;
    size_t k;
    size_t n;

    /* The step, timed. */
    t_us = hal_time_us(); /* within a few us of the ADC read in app_tick() */
    loop.sample_time_us = (uint32_t)t_us;
    c0 = stm32f4_cycles();
    s_last_rc = app_tick(&s_app, &s_out);
    cycles = stm32f4_cycles() - c0;
    cycle_stats_add(&s_cycles, cycles, cycles > s_period_cycles);

    /* Commands, command watchdog, telemetry. */
    for (n = 0u; n < CAN_PROTO_RX_MAX_PER_TICK && hal_can_receive(&f) == 1; ++n) {
        (void)can_proto_node_receive(&s_node, &s_app, &f, t_us);
    }
    can_proto_node_update(&s_node, &s_app, s_last_rc == TV_OK ? &s_out : NULL, t_us);
    if (s_clock_degraded) {
        force_off();
    }
    stm32f4_status(&st);
    loop.overruns = st.deadline_missed;
    loop.latency_max_us = st.tick_latency_max_us;
    loop.exec_max_us = (s_cycles.max_cycles + s_cycles_per_us - 1u) / s_cycles_per_us;
    n = can_proto_node_transmit(&s_node, &s_app, &s_out, &loop, s_last_rc != TV_OK, t_us, frames);
    for (k = 0u; k < n; ++k) {
        (void)hal_can_send(&frames[k]);
    }
    if (t_us >= s_cpu_due_us) {
        if (can_proto_encode_ecu_cpu(s_cycles.max_cycles, cycle_stats_mean(&s_cycles), s_cycles.over_budget,
                                     s_cpu_counter, &f) == TV_OK) {
            (void)hal_can_send(&f);
        }
        s_cpu_counter = (uint8_t)((s_cpu_counter + 1u) & 15u);
        s_cpu_due_us = t_us + (uint64_t)1000u * CAN_PROTO_ECU_CPU_PERIOD_MS;
    }
    ++s_ticks;
}

/* Unrecoverable start-up error: outputs safe, wait here (no watchdog started: no reset loop). */
static void halt_safe(void)
{
    stm32f4_emergency_stop();
    for (;;) {
        __asm__ volatile("wfi");
    }
}

#ifdef ECU_TRACE
/** Initialised data: QEMU's ELF loader puts its initial value only at its flash (load)
 * address, so reading it back from RAM shows whether the reset handler copied .data. */
static volatile uint32_t s_data_probe = 0xC0DEDA7Au;
/** Zero-initialised: the reset handler zeroes .bss (painted non-zero before main by nothing
 * else; QEMU's RAM starts zeroed, so this one only shows that .bss is addressable). */
static volatile uint32_t s_bss_probe;

static void trace_kv(const char *k, uint32_t v)
{
    sh_puts(k);
    sh_put_u32(v);
    sh_puts("\n");
}

static void trace_boot(const stm32f4_clock_t *clk, int clk_rc)
{
    const uint32_t *vt = startup_vector_words();
    sh_puts("ecu: main() entered from the reset handler\n");
    /* cppcheck-suppress knownConditionTrueFalse ; volatile, set by the reset handler's copy */
    sh_puts(s_data_probe == 0xC0DEDA7Au ? "ecu: .data initialised in RAM (copied from flash by the reset handler)\n"
                                       : "ecu: .data NOT initialised\n");
    /* cppcheck-suppress knownConditionTrueFalse ; volatile, zeroed by the reset handler */
    sh_puts(s_bss_probe == 0u ? "ecu: .bss zero\n" : "ecu: .bss NOT zero\n");
    sh_puts((SCB_CPACR & SCB_CPACR_CP10_CP11_FULL) == SCB_CPACR_CP10_CP11_FULL ? "ecu: FPU enabled (CPACR CP10/CP11 full access)\n"
                                                                            : "ecu: FPU NOT enabled\n");
    sh_puts("ecu: vector table at ");
    sh_put_hex32((uint32_t)(uintptr_t)vt);
    sh_puts(", VTOR ");
    sh_put_hex32(SCB->VTOR);
    sh_puts(", reset vector ");
    sh_put_hex32(vt[1]);
    sh_puts(", TIM2 vector ");
    sh_put_hex32(vt[16 + IRQN_TIM2]);
    sh_puts("\n");
    sh_puts("ecu: clock set-up rc ");
    sh_put_i32(clk_rc);
    sh_puts(", flags ");
    sh_put_hex32(clk->flags);
    sh_puts((clk->flags & STM32F4_CLOCK_HSE_FAILED) != 0u ? " (HSE did not start" : " (HSE ok");
    sh_puts((clk->flags & STM32F4_CLOCK_PLL_FAILED) != 0u ? ", PLL did not lock: running on HSI)\n"
                                                          : ", PLL locked)\n");
    trace_kv("ecu: SYSCLK Hz ", clk->sysclk_Hz);
    trace_kv("ecu: APB1 timer clock Hz ", clk->tim_apb1_Hz);
    trace_kv("ecu: APB2 timer clock Hz ", clk->tim_apb2_Hz);
}

static void trace_ticks(void)
{
    stm32f4_status_t st;
    stm32f4_status(&st);
    trace_kv("ecu: control ticks (TIM2 interrupt -> app_tick) ", s_ticks);
    sh_puts("ecu: last app_tick rc ");
    sh_put_i32(s_last_rc);
    sh_puts(" (");
    sh_puts(tv_status_str(s_last_rc));
    sh_puts(")\n");
    trace_kv("ecu: ticks without a fresh ADC conversion ", st.adc_stale);
    trace_kv("ecu: deadline misses ", st.deadline_missed);
    trace_kv("ecu: DWT cycles of app_tick, max ", s_cycles.max_cycles);
    trace_kv("ecu: CAN controller ready ", st.can_ok);
    trace_kv("ecu: hal_time_us ", (uint32_t)hal_time_us());
    trace_kv("ecu: stack high-water bytes ", startup_stack_high_water_bytes());
    trace_kv("ecu: app mode ", (uint32_t)s_app.cfg.control.mode);
}
#endif

int main(void)
{
    stm32f4_clock_t clk;
    app_config_t cfg;
    can_proto_config_t pcfg;
    uint32_t seen = 0u;
    int clk_rc;

    /* The vector table is at the start of flash; make that explicit (the boot alias at 0 is
     * only there when booting from flash). */
    SCB->VTOR = FLASH_BASE_ADDR;
    SCB->CCR |= SCB_CCR_DIV_0_TRP;
    SCB->SHCSR |= SCB_SHCSR_MEMFAULTENA | SCB_SHCSR_BUSFAULTENA | SCB_SHCSR_USGFAULTENA;

    clk_rc = stm32f4_clock_init(STM32F4_HSE_HZ, &clk);
    s_clock_degraded = clk.flags != 0u ? 1u : 0u;
    s_cycles_per_us = clk.hclk_Hz / 1000000u;
    s_period_cycles = clk.hclk_Hz / 1000u;
    cycle_stats_init(&s_cycles, s_period_cycles / 10u); /* 10 % of the core: 16800 at 168 MHz */
#ifdef ECU_TRACE
    trace_boot(&clk, clk_rc);
#else
    (void)clk_rc;
#endif

    app_config_default(&cfg);
    /* Bound the control interrupt's worst case: at most 1 missed period is predicted across in
     * one step (2 predictions; firmware_report, "after lost samples": about 10,700 QEMU-counted
     * instructions with the resistance and friction error states, and at most 2 x 5,700 + 2,100
     * with both predictions in contact under a learned Hunt-Crossley law, of the 16,800-cycle
     * budget; 4 predictions, the former limit, took 18,500); a longer gap latches
     * APP_FAULT_TIMING (and still predicts only 2 periods). */
    cfg.limits.max_gap_periods = 2u;
    can_proto_config_default(&pcfg);
    if (app_init(&s_app, &cfg) != TV_OK || can_proto_node_init(&s_node, &pcfg, &s_app) != TV_OK) {
        halt_safe();
    }
    if (s_clock_degraded) {
        force_off();
    }
    if (hal_init() != TV_OK) {
        halt_safe();
    }
    stm32f4_watchdog_start(STM32F4_WATCHDOG_DEFAULT_MS);
    stm32f4_control_start();
#ifdef ECU_TRACE
    sh_puts("ecu: HAL up, watchdog started, control interrupt enabled\n");
#endif

    for (;;) {
        const uint32_t now = s_ticks;
        if (now != seen) {
            seen = now;
            stm32f4_watchdog_kick();
#ifdef ECU_TRACE
            if (now >= ECU_TRACE_TICKS) {
                trace_ticks();
                sh_exit(0);
            }
#endif
        }
        __asm__ volatile("wfi");
    }
}

/* The control interrupt is the application's (stm32f4_hal.h): the HAL acknowledges it and keeps
 * the latency and deadline statistics, the step is ours. Overrides the vector table's weak
 * default. */
void TIM2_IRQHandler(void);
void TIM2_IRQHandler(void)
{
    stm32f4_control_irq_begin();
    ecu_control_tick();
    stm32f4_control_irq_end();
}
