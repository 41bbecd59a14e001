/**
 * @file stm32f4_hal.h
 * @brief What the STM32F405/407 implementation of hal.h adds for the ECU: its configuration,
 *        the phase-locked 1 kHz control interrupt, the independent watchdog, the DWT cycle
 *        counter, the emergency stop and status counters.
 *
 * Peripherals (pins in stm32f4_board.h):
 *  - TIM1, centre-aligned PWM (mode 1, up/down), f = TIMCLK / (2 ARR), 20 kHz default. IN1 and
 *    IN2 use PWM mode 2, so each on-pulse is centred on the counter peak. Duty changes are
 *    preloaded (take effect at the next update, glitch-free).
 *  - ADC1 injected group of 4 (current, track 1, track 2, supply; 15-cycle sampling at 21 MHz,
 *    about 5 us for the group), hardware-triggered by TIM1 CC4 one timer tick after the peak:
 *    the current is sampled at the middle of the on-pulse, i.e. its average over the period.
 *  - TIM2, 1 MHz counter, update every 1 ms: the control interrupt. It is started together
 *    with TIM1 (same clock source) so the two stay phase-locked: the tick always comes
 *    ADC_READY_US after a PWM peak, when that peak's conversions are complete.
 *  - TIM5, 32-bit free-running 1 MHz counter: hal_time_us(), extended to 64 bits.
 *  - bxCAN1 with software queues (24 frames each way) served by the CAN1_TX / CAN1_RX0
 *    interrupts; accepts every identifier into FIFO 0, automatic bus-off recovery.
 *  - IWDG (LSI 32 kHz nominal / 32): reset when the main loop stops seeing control ticks.
 *  - DWT CYCCNT: core cycles, for execution-time statistics.
 *
 * Interrupt priorities (lower = more urgent): TIM2 control 1; CAN1 TX/RX 1 (same level: the
 * queues need no locking against each other; hal_can_* also mask interrupts briefly so they
 * may be called from thread mode).
 */
#ifndef STM32F4_HAL_H
#define STM32F4_HAL_H

#include <stdint.h>

#include "stm32f4_clock.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Default PWM frequency [Hz]. */
#ifndef STM32F4_PWM_DEFAULT_HZ
#define STM32F4_PWM_DEFAULT_HZ 20000u
#endif
/** Default CAN bit rate [bit/s]. */
#ifndef STM32F4_CAN_DEFAULT_BPS
#define STM32F4_CAN_DEFAULT_BPS 500000u
#endif
/** Default watchdog timeout [ms] at the nominal LSI (32 kHz; 17..47 kHz: 34..94 ms at 50). */
#ifndef STM32F4_WATCHDOG_DEFAULT_MS
#define STM32F4_WATCHDOG_DEFAULT_MS 50u
#endif
/** Control tick period [us]. */
#define STM32F4_CONTROL_PERIOD_US 1000u
/** Delay of the control tick after a PWM peak [us]: the 4 conversions take about 5 us. */
#define STM32F4_ADC_READY_US 10u
/** Software CAN queue lengths [frames]. The largest burst is the tick after a stall, when every
 * telemetry frame is due at once: can_proto's 16 (CAN_PROTO_N_TX, TV_HEALTH_5 the 16th) and
 * TV_ECU_CPU, 17 frames, of which the 3 transmit mailboxes take the first; 24 leaves room for 7
 * more frames without a drop (a drop is counted: stm32f4_status_t::can_tx_dropped; ecu_main.c
 * checks the burst against this length at compile time). */
#define STM32F4_CAN_QUEUE_LEN 24u

/** Platform configuration. */
typedef struct {
    uint32_t pwm_frequency_Hz; /**< 2..50 kHz, a multiple of 1 kHz that divides TIM1's clock / 2 exactly (20 kHz default) */
    uint32_t can_bitrate_bps;  /**< 125000, 250000, 500000 (default) or 1000000 */
} stm32f4_hal_config_t;

/** Status and counters of the platform. */
typedef struct {
    uint32_t clock_flags;    /**< STM32F4_CLOCK_* of the clock set-up */
    uint32_t reset_flags;    /**< RCC_CSR reset flags at boot (RCC_CSR_IWDGRSTF: watchdog reset) */
    uint32_t can_ok;         /**< 1: bxCAN left initialisation mode */
    uint32_t can_tx_dropped; /**< frames refused because the transmit queue was full */
    uint32_t can_rx_dropped; /**< frames lost: software queue full or FIFO 0 overrun */
    uint32_t can_bus_off;    /**< 1: bus-off at the last check (recovers automatically) */
    uint32_t adc_stale;      /**< control ticks without a new conversion */
    uint32_t deadline_missed; /**< control ticks that began before the previous one ended */
    uint32_t tick_latency_max_us; /**< worst delay from the timer update to the handler [us] */
} stm32f4_status_t;

/** Defaults: 20 kHz PWM, 500 kbit/s CAN. */
void stm32f4_hal_config_default(stm32f4_hal_config_t *cfg);

/**
 * Bring up GPIO, TIM1 PWM (outputs at 0 %, bridge disabled), ADC1, TIM2 (not started), TIM5,
 * bxCAN and the DWT for the clocks of stm32f4_clock_get(). hal_init() is this with the defaults.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (PWM frequency or bit rate not realisable at these
 *         clocks: nothing started). A CAN controller that does not leave initialisation is not
 *         an error here: can_ok stays 0 and hal_can_send() returns TV_ERR_IO.
 */
int stm32f4_hal_init(const stm32f4_hal_config_t *cfg);

/**
 * The 1 kHz control interrupt (TIM2) belongs to the application image, not to this HAL: the
 * image defines TIM2_IRQHandler (overriding the weak default of the vector table) as
 *     stm32f4_control_irq_begin(); <the application's 1 ms step>; stm32f4_control_irq_end();
 * so the HAL never calls back into the application. begin acknowledges the interrupt and records
 * the entry latency (stm32f4_status_t::tick_latency_max_us); end counts a missed deadline when
 * the next period began while the step ran (stm32f4_status_t::deadline_missed).
 */
void stm32f4_control_irq_begin(void);
/** See stm32f4_control_irq_begin(). */
void stm32f4_control_irq_end(void);

/** Start TIM1 and TIM2 together (phase-locked) and enable the control interrupt. */
void stm32f4_control_start(void);

/**
 * Start the independent watchdog (cannot be stopped afterwards; frozen while a debugger halts
 * the core). @param timeout_ms 1..4095 at the nominal LSI frequency.
 */
void stm32f4_watchdog_start(uint32_t timeout_ms);

/** Reload the watchdog. */
void stm32f4_watchdog_kick(void);

/** The DWT cycle counter (core clock cycles, wraps every 2^32 cycles = 25.6 s at 168 MHz). */
uint32_t stm32f4_cycles(void);

/**
 * Emergency stop, callable from any context including fault handlers: TIM1 main output enable
 * cleared (IN1 = IN2 = idle low), bridge enable low, and latched: hal_bridge_enable(1) fails
 * with TV_ERR_FAULT afterwards until reset.
 */
void stm32f4_emergency_stop(void);

/** Copy of the status counters (consistent: taken with interrupts masked). */
void stm32f4_status(stm32f4_status_t *st);

/** Mask interrupts; returns the previous PRIMASK for stm32f4_irq_restore(). */
uint32_t stm32f4_irq_save(void);

/** Restore PRIMASK as returned by stm32f4_irq_save(). */
void stm32f4_irq_restore(uint32_t primask);

#ifdef __cplusplus
}
#endif

#endif /* STM32F4_HAL_H */
