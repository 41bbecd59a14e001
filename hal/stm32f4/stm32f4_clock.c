/**
 * @file stm32f4_clock.c
 * @brief Clock set-up (see stm32f4_clock.h). Sequence of RM0090 section 7.2 / 3.5.1: raise the
 *        flash latency before the frequency, prescalers before the switch, wait for every
 *        ready flag with a bounded loop (no timer runs yet: loop counts at HSI 16 MHz).
 */
#include "stm32f4_clock.h"

#include <stddef.h>

#include "stm32f4_regs.h"
#include "tv_status.h"

#define HSI_HZ 16000000u
#define PLL_N 336u         /**< VCO = 1 MHz x 336 */
#define PLL_P_DIV2 0u      /**< PLLP field 00: /2 -> 168 MHz */
#define PLL_Q 7u           /**< 336 / 7 = 48 MHz */
#define SYSCLK_PLL_HZ 168000000u
/** Ready-flag polls: about 4 cycles each at 16 MHz, so 50 ms for HSE (typ. 2 ms), 25 ms for PLL. */
#define HSE_READY_POLLS 200000u
#define PLL_READY_POLLS 100000u
#define SWITCH_POLLS 10000u

static stm32f4_clock_t s_clock = {HSI_HZ, HSI_HZ, HSI_HZ, HSI_HZ, HSI_HZ, HSI_HZ, 0u, 0u};

static int wait_set(const volatile uint32_t *reg, uint32_t mask, uint32_t value, uint32_t polls)
{
    while (polls-- > 0u) {
        if ((*reg & mask) == value) {
            return 1;
        }
    }
    return 0;
}

/* Timer clock: x1 when the APB prescaler is 1, else x2 (RM0090 section 7.2, "timer clock"). */
static uint32_t timer_clock(uint32_t hclk, uint32_t pclk)
{
    return pclk == hclk ? pclk : 2u * pclk;
}

static void run_on_hsi(stm32f4_clock_t *c)
{
    /* All prescalers 1: 16 MHz is within every bus limit. */
    RCC->CFGR = (RCC->CFGR & ~(RCC_CFGR_SW_Msk | RCC_CFGR_HPRE_Msk | RCC_CFGR_PPRE1_Msk | RCC_CFGR_PPRE2_Msk)) |
                RCC_CFGR_SW_HSI | RCC_CFGR_HPRE_DIV1 | RCC_CFGR_PPRE1_DIV1 | RCC_CFGR_PPRE2_DIV1;
    c->sysclk_Hz = HSI_HZ;
    c->hclk_Hz = HSI_HZ;
    c->pclk1_Hz = HSI_HZ;
    c->pclk2_Hz = HSI_HZ;
}

int stm32f4_clock_init(uint32_t hse_Hz, stm32f4_clock_t *out)
{
    stm32f4_clock_t c = s_clock;
    uint32_t pll_m;
    uint32_t pll_src = RCC_PLLCFGR_PLLSRC_HSE;
    int rc = TV_OK;

    c.reset_flags = RCC->CSR & 0xFF000000u;
    RCC->CSR |= RCC_CSR_RMVF;
    c.flags = 0u;
    if (hse_Hz < 4000000u || hse_Hz > 26000000u || hse_Hz % 1000000u != 0u) {
        if (out != NULL) {
            *out = s_clock;
        }
        return TV_ERR_CONFIG;
    }
    pll_m = hse_Hz / 1000000u;

    /* Regulator scale 1, then flash latency for 168 MHz (read back: it must be in force
     * before the frequency rises). */
    RCC->APB1ENR |= RCC_APB1ENR_PWREN;
    (void)RCC->APB1ENR;
    PWR->CR |= PWR_CR_VOS;
    FLASH->ACR = FLASH_ACR_LATENCY_5WS | FLASH_ACR_PRFTEN | FLASH_ACR_ICEN | FLASH_ACR_DCEN;
    (void)FLASH->ACR;

    /* HSE, or the HSI fallback (16 MHz / 16 = the same 1 MHz PLL input). */
    RCC->CR |= RCC_CR_HSEON;
    if (!wait_set(&RCC->CR, RCC_CR_HSERDY, RCC_CR_HSERDY, HSE_READY_POLLS)) {
        RCC->CR &= ~RCC_CR_HSEON;
        c.flags |= STM32F4_CLOCK_HSE_FAILED;
        pll_src = 0u;
        pll_m = HSI_HZ / 1000000u;
        rc = TV_ERR_IO;
    }

    /* PLL (must be off while configured). */
    RCC->CR &= ~RCC_CR_PLLON;
    /* cppcheck-suppress badBitmaskCheck ; PLLP = 00 (/2) is a zero field, kept for the layout */
    RCC->PLLCFGR = (pll_m << RCC_PLLCFGR_PLLM_Pos) | (PLL_N << RCC_PLLCFGR_PLLN_Pos) |
                   (PLL_P_DIV2 << RCC_PLLCFGR_PLLP_Pos) | pll_src | (PLL_Q << RCC_PLLCFGR_PLLQ_Pos);
    /* Bus prescalers before the switch: AHB /1, APB1 /4 (max 42 MHz), APB2 /2 (max 84 MHz). */
    RCC->CFGR = (RCC->CFGR & ~(RCC_CFGR_HPRE_Msk | RCC_CFGR_PPRE1_Msk | RCC_CFGR_PPRE2_Msk)) | RCC_CFGR_HPRE_DIV1 |
                RCC_CFGR_PPRE1_DIV4 | RCC_CFGR_PPRE2_DIV2;
    RCC->CR |= RCC_CR_PLLON;
    if (wait_set(&RCC->CR, RCC_CR_PLLRDY, RCC_CR_PLLRDY, PLL_READY_POLLS)) {
        RCC->CFGR = (RCC->CFGR & ~RCC_CFGR_SW_Msk) | RCC_CFGR_SW_PLL;
        if (wait_set(&RCC->CFGR, RCC_CFGR_SWS_Msk, RCC_CFGR_SWS_PLL, SWITCH_POLLS)) {
            c.sysclk_Hz = SYSCLK_PLL_HZ;
            c.hclk_Hz = SYSCLK_PLL_HZ;
            c.pclk1_Hz = SYSCLK_PLL_HZ / 4u;
            c.pclk2_Hz = SYSCLK_PLL_HZ / 2u;
        } else {
            c.flags |= STM32F4_CLOCK_PLL_FAILED;
            run_on_hsi(&c);
            rc = TV_ERR_IO;
        }
    } else {
        RCC->CR &= ~RCC_CR_PLLON;
        c.flags |= STM32F4_CLOCK_PLL_FAILED;
        run_on_hsi(&c);
        rc = TV_ERR_IO;
    }
    if ((c.flags & (STM32F4_CLOCK_HSE_FAILED | STM32F4_CLOCK_PLL_FAILED)) == 0u) {
        RCC->CR |= RCC_CR_CSSON;
    }
    c.tim_apb1_Hz = timer_clock(c.hclk_Hz, c.pclk1_Hz);
    c.tim_apb2_Hz = timer_clock(c.hclk_Hz, c.pclk2_Hz);
    s_clock = c;
    if (out != NULL) {
        *out = c;
    }
    return rc;
}

const stm32f4_clock_t *stm32f4_clock_get(void)
{
    return &s_clock;
}
