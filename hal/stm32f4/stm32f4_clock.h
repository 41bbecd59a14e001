/**
 * @file stm32f4_clock.h
 * @brief Clock tree of the STM32F405/407 (RM0090 section 7.2): 168 MHz from the HSE crystal
 *        through the main PLL, with bounded waits and a fallback, and the resulting bus and
 *        timer clocks that the HAL derives its dividers from.
 *
 *   HSE 8 MHz / M=8 -> 1 MHz x N=336 -> VCO 336 MHz / P=2 -> SYSCLK = HCLK = 168 MHz
 *                                                   / Q=7 -> 48 MHz (USB/SDIO, unused)
 *   APB1 = HCLK/4 = 42 MHz (CAN, TIM2/TIM5 at 2 x 42 = 84 MHz)
 *   APB2 = HCLK/2 = 84 MHz (ADC, TIM1 at 2 x 84 = 168 MHz)
 *   flash: 5 wait states, prefetch, instruction and data caches (RM0090 Table 10, 2.7-3.6 V)
 *   regulator: scale 1 (PWR_CR VOS), needed above 144 MHz
 * Fallbacks, each flagged: HSE does not start -> PLL from HSI (16 MHz / 16) at 168 MHz;
 * PLL does not lock -> run on HSI 16 MHz with all bus prescalers 1. The clock security system
 * is armed when running from HSE (an HSE failure then raises NMI -> safe state).
 */
#ifndef STM32F4_CLOCK_H
#define STM32F4_CLOCK_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Clock fault flags (stm32f4_clock_t::flags). */
enum {
    STM32F4_CLOCK_HSE_FAILED = 1u << 0,   /**< HSE did not become ready: PLL fed from HSI */
    STM32F4_CLOCK_PLL_FAILED = 1u << 1,   /**< PLL did not lock or the switch failed: on HSI */
};

/** The clock tree in force. */
typedef struct {
    uint32_t sysclk_Hz;   /**< SYSCLK */
    uint32_t hclk_Hz;     /**< AHB, core (the DWT counts these) */
    uint32_t pclk1_Hz;    /**< APB1 */
    uint32_t pclk2_Hz;    /**< APB2 */
    uint32_t tim_apb1_Hz; /**< clock of TIM2..TIM7, TIM12..14 */
    uint32_t tim_apb2_Hz; /**< clock of TIM1, TIM8..TIM11 */
    uint32_t flags;       /**< STM32F4_CLOCK_* */
    uint32_t reset_flags; /**< RCC_CSR at boot (RCC_CSR_IWDGRSTF, ..._PORRSTF, ...), then cleared */
} stm32f4_clock_t;

/**
 * Configure the clock tree as above. Call first thing in main(), once.
 * @param hse_Hz crystal frequency, a whole number of MHz in 4..26 MHz
 * @param out    the resulting clocks (also kept for stm32f4_clock_get())
 * @return 0 at 168 MHz from HSE; TV_ERR_CONFIG for a bad hse_Hz (nothing changed, HSI 16 MHz);
 *         TV_ERR_IO when a fallback was taken (see out->flags).
 */
int stm32f4_clock_init(uint32_t hse_Hz, stm32f4_clock_t *out);

/** The clocks set by stm32f4_clock_init() (HSI 16 MHz reset values before it). */
const stm32f4_clock_t *stm32f4_clock_get(void);

#ifdef __cplusplus
}
#endif

#endif /* STM32F4_CLOCK_H */
