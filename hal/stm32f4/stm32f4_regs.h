/**
 * @file stm32f4_regs.h
 * @brief The STM32F405/407 registers this firmware uses, written from the reference manual
 *        RM0090 (Rev 19) and, for the Cortex-M4 core, the programming manual PM0214 / ARMv7-M
 *        ARM. Register and bit names are the manuals' names: `RCC->CR`, `RCC_CR_HSEON`,
 *        `ADC1->JSQR`, `TIM_BDTR_MOE`, ... Only what the HAL needs is defined; offsets of every
 *        register block are checked at compile time (the _Static_assert-free C99 way: a negative
 *        array size on mismatch).
 *
 * No vendor header is used (none is packaged for Debian); nothing here allocates or executes.
 */
#ifndef STM32F4_REGS_H
#define STM32F4_REGS_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Register access qualifier. */
#define REG32 volatile uint32_t

/** Compile-time check (C99): a typedef of a negative-size array fails to compile. */
#define STM32_CHECK(name, cond) typedef char stm32_check_##name[(cond) ? 1 : -1]

/* ------------------------------------------------------------------------------------------ */
/* Memory map (RM0090 section 2.3, Table 1)                                                   */
/* ------------------------------------------------------------------------------------------ */
#define FLASH_BASE_ADDR 0x08000000u /**< main flash, 1 MiB on the 405/407 xG */
#define SRAM1_BASE_ADDR 0x20000000u /**< SRAM1 112 KiB + SRAM2 16 KiB, contiguous */
#define CCMRAM_BASE_ADDR 0x10000000u /**< 64 KiB core-coupled data RAM (D-bus only) */

#define TIM2_BASE 0x40000000u
#define TIM5_BASE 0x40000C00u
#define IWDG_BASE 0x40003000u
#define CAN1_BASE 0x40006400u
#define PWR_BASE 0x40007000u
#define TIM1_BASE 0x40010000u
#define ADC1_BASE 0x40012000u
#define ADC_COMMON_BASE 0x40012300u
#define GPIOA_BASE 0x40020000u
#define GPIOB_BASE 0x40020400u
#define RCC_BASE 0x40023800u
#define FLASH_R_BASE 0x40023C00u
#define DBGMCU_BASE 0xE0042000u

/* ------------------------------------------------------------------------------------------ */
/* RCC: reset and clock control (RM0090 section 7.3)                                          */
/* ------------------------------------------------------------------------------------------ */
/** RCC register block. */
typedef struct {
    REG32 CR;          /**< 0x00 clock control */
    REG32 PLLCFGR;     /**< 0x04 PLL configuration */
    REG32 CFGR;        /**< 0x08 clock configuration */
    REG32 CIR;         /**< 0x0C clock interrupt */
    REG32 AHB1RSTR;    /**< 0x10 */
    REG32 AHB2RSTR;    /**< 0x14 */
    REG32 AHB3RSTR;    /**< 0x18 */
    REG32 RESERVED0;   /**< 0x1C */
    REG32 APB1RSTR;    /**< 0x20 */
    REG32 APB2RSTR;    /**< 0x24 */
    REG32 RESERVED1[2]; /**< 0x28 */
    REG32 AHB1ENR;     /**< 0x30 AHB1 peripheral clock enable */
    REG32 AHB2ENR;     /**< 0x34 */
    REG32 AHB3ENR;     /**< 0x38 */
    REG32 RESERVED2;   /**< 0x3C */
    REG32 APB1ENR;     /**< 0x40 APB1 peripheral clock enable */
    REG32 APB2ENR;     /**< 0x44 APB2 peripheral clock enable */
    REG32 RESERVED3[2]; /**< 0x48 */
    REG32 AHB1LPENR;   /**< 0x50 */
    REG32 AHB2LPENR;   /**< 0x54 */
    REG32 AHB3LPENR;   /**< 0x58 */
    REG32 RESERVED4;   /**< 0x5C */
    REG32 APB1LPENR;   /**< 0x60 */
    REG32 APB2LPENR;   /**< 0x64 */
    REG32 RESERVED5[2]; /**< 0x68 */
    REG32 BDCR;        /**< 0x70 backup domain control */
    REG32 CSR;         /**< 0x74 clock control & status (reset flags) */
    REG32 RESERVED6[2]; /**< 0x78 */
    REG32 SSCGR;       /**< 0x80 */
    REG32 PLLI2SCFGR;  /**< 0x84 */
} rcc_regs_t;
STM32_CHECK(rcc_csr, offsetof(rcc_regs_t, CSR) == 0x74u);
STM32_CHECK(rcc_apb2enr, offsetof(rcc_regs_t, APB2ENR) == 0x44u);

#define RCC ((rcc_regs_t *)RCC_BASE)

#define RCC_CR_HSION (1u << 0)
#define RCC_CR_HSIRDY (1u << 1)
#define RCC_CR_HSEON (1u << 16)
#define RCC_CR_HSERDY (1u << 17)
#define RCC_CR_HSEBYP (1u << 18)
#define RCC_CR_CSSON (1u << 19)
#define RCC_CR_PLLON (1u << 24)
#define RCC_CR_PLLRDY (1u << 25)

#define RCC_PLLCFGR_PLLM_Pos 0u  /**< PLLM[5:0]: VCO input = source / M, 2..63 */
#define RCC_PLLCFGR_PLLN_Pos 6u  /**< PLLN[14:6]: VCO output = input * N, 50..432 */
#define RCC_PLLCFGR_PLLP_Pos 16u /**< PLLP[17:16]: SYSCLK = VCO / P, 00: 2, 01: 4, 10: 6, 11: 8 */
#define RCC_PLLCFGR_PLLSRC_HSE (1u << 22)
#define RCC_PLLCFGR_PLLQ_Pos 24u /**< PLLQ[27:24]: 48 MHz clock = VCO / Q, 2..15 */

#define RCC_CFGR_SW_Msk (3u << 0)
#define RCC_CFGR_SW_HSI (0u << 0)
#define RCC_CFGR_SW_HSE (1u << 0)
#define RCC_CFGR_SW_PLL (2u << 0)
#define RCC_CFGR_SWS_Msk (3u << 2)
#define RCC_CFGR_SWS_PLL (2u << 2)
#define RCC_CFGR_HPRE_Msk (0xFu << 4)
#define RCC_CFGR_HPRE_DIV1 (0u << 4)
#define RCC_CFGR_PPRE1_Msk (7u << 10)
#define RCC_CFGR_PPRE1_DIV1 (0u << 10)
#define RCC_CFGR_PPRE1_DIV4 (5u << 10)
#define RCC_CFGR_PPRE2_Msk (7u << 13)
#define RCC_CFGR_PPRE2_DIV1 (0u << 13)
#define RCC_CFGR_PPRE2_DIV2 (4u << 13)

#define RCC_AHB1ENR_GPIOAEN (1u << 0)
#define RCC_AHB1ENR_GPIOBEN (1u << 1)
#define RCC_AHB1ENR_CCMDATARAMEN (1u << 20)
#define RCC_APB1ENR_TIM2EN (1u << 0)
#define RCC_APB1ENR_TIM5EN (1u << 3)
#define RCC_APB1ENR_CAN1EN (1u << 25)
#define RCC_APB1ENR_PWREN (1u << 28)
#define RCC_APB2ENR_TIM1EN (1u << 0)
#define RCC_APB2ENR_ADC1EN (1u << 8)

#define RCC_CSR_LSION (1u << 0)
#define RCC_CSR_LSIRDY (1u << 1)
#define RCC_CSR_RMVF (1u << 24)
#define RCC_CSR_BORRSTF (1u << 25)
#define RCC_CSR_PINRSTF (1u << 26)
#define RCC_CSR_PORRSTF (1u << 27)
#define RCC_CSR_SFTRSTF (1u << 28)
#define RCC_CSR_IWDGRSTF (1u << 29)
#define RCC_CSR_WWDGRSTF (1u << 30)
#define RCC_CSR_LPWRRSTF (1u << 31)

/* ------------------------------------------------------------------------------------------ */
/* FLASH interface and PWR (RM0090 sections 3.9 and 5.4)                                      */
/* ------------------------------------------------------------------------------------------ */
/** Flash interface register block. */
typedef struct {
    REG32 ACR;     /**< 0x00 access control (latency, caches) */
    REG32 KEYR;    /**< 0x04 */
    REG32 OPTKEYR; /**< 0x08 */
    REG32 SR;      /**< 0x0C */
    REG32 CR;      /**< 0x10 */
    REG32 OPTCR;   /**< 0x14 */
} flash_regs_t;
#define FLASH ((flash_regs_t *)FLASH_R_BASE)
#define FLASH_ACR_LATENCY_Msk (7u << 0)
#define FLASH_ACR_LATENCY_5WS (5u << 0) /**< 150 < HCLK <= 168 MHz at 2.7..3.6 V (Table 10) */
#define FLASH_ACR_PRFTEN (1u << 8)
#define FLASH_ACR_ICEN (1u << 9)
#define FLASH_ACR_DCEN (1u << 10)

/** Power controller register block. */
typedef struct {
    REG32 CR;  /**< 0x00 */
    REG32 CSR; /**< 0x04 */
} pwr_regs_t;
#define PWR ((pwr_regs_t *)PWR_BASE)
#define PWR_CR_VOS (1u << 14) /**< regulator scale 1 (needed above 144 MHz on the 405/407) */

/* ------------------------------------------------------------------------------------------ */
/* GPIO (RM0090 section 8.4)                                                                  */
/* ------------------------------------------------------------------------------------------ */
/** GPIO port register block. */
typedef struct {
    REG32 MODER;   /**< 0x00 mode: 00 input, 01 output, 10 alternate function, 11 analog */
    REG32 OTYPER;  /**< 0x04 output type: 0 push-pull */
    REG32 OSPEEDR; /**< 0x08 output speed */
    REG32 PUPDR;   /**< 0x0C pull-up/pull-down: 01 pull-up, 10 pull-down */
    REG32 IDR;     /**< 0x10 input data */
    REG32 ODR;     /**< 0x14 output data */
    REG32 BSRR;    /**< 0x18 bit set (15:0) / reset (31:16) */
    REG32 LCKR;    /**< 0x1C configuration lock */
    REG32 AFR[2];  /**< 0x20 AFRL (pins 0-7), 0x24 AFRH (pins 8-15), 4 bits per pin */
} gpio_regs_t;
STM32_CHECK(gpio_afr, offsetof(gpio_regs_t, AFR) == 0x20u);
#define GPIOA ((gpio_regs_t *)GPIOA_BASE)
#define GPIOB ((gpio_regs_t *)GPIOB_BASE)
#define GPIO_MODER_INPUT 0u
#define GPIO_MODER_OUTPUT 1u
#define GPIO_MODER_AF 2u
#define GPIO_MODER_ANALOG 3u
#define GPIO_PUPDR_PULLUP 1u
#define GPIO_OSPEEDR_HIGH 2u

/* ------------------------------------------------------------------------------------------ */
/* Timers: TIM1 (advanced, section 17.4) and TIM2..TIM5 (general purpose, section 18.4)       */
/* share one layout; RCR and BDTR exist on TIM1/TIM8 only.                                    */
/* ------------------------------------------------------------------------------------------ */
/** Timer register block. */
typedef struct {
    REG32 CR1;   /**< 0x00 */
    REG32 CR2;   /**< 0x04 */
    REG32 SMCR;  /**< 0x08 */
    REG32 DIER;  /**< 0x0C DMA/interrupt enable */
    REG32 SR;    /**< 0x10 status (rc_w0) */
    REG32 EGR;   /**< 0x14 event generation */
    REG32 CCMR1; /**< 0x18 capture/compare mode, channels 1-2 */
    REG32 CCMR2; /**< 0x1C capture/compare mode, channels 3-4 */
    REG32 CCER;  /**< 0x20 capture/compare enable */
    REG32 CNT;   /**< 0x24 counter (32 bits on TIM2/TIM5) */
    REG32 PSC;   /**< 0x28 prescaler: f_cnt = f_tim / (PSC + 1) */
    REG32 ARR;   /**< 0x2C auto-reload */
    REG32 RCR;   /**< 0x30 repetition counter (TIM1/TIM8) */
    REG32 CCR1;  /**< 0x34 */
    REG32 CCR2;  /**< 0x38 */
    REG32 CCR3;  /**< 0x3C */
    REG32 CCR4;  /**< 0x40 */
    REG32 BDTR;  /**< 0x44 break and dead-time (TIM1/TIM8) */
    REG32 DCR;   /**< 0x48 */
    REG32 DMAR;  /**< 0x4C */
    REG32 OR;    /**< 0x50 option (TIM2/TIM5) */
} tim_regs_t;
STM32_CHECK(tim_bdtr, offsetof(tim_regs_t, BDTR) == 0x44u);
#define TIM1 ((tim_regs_t *)TIM1_BASE)
#define TIM2 ((tim_regs_t *)TIM2_BASE)
#define TIM5 ((tim_regs_t *)TIM5_BASE)

#define TIM_CR1_CEN (1u << 0)
#define TIM_CR1_URS (1u << 2)
#define TIM_CR1_CMS_CENTER1 (1u << 5) /**< centre-aligned mode 1: output-compare flags set counting down */
#define TIM_CR1_ARPE (1u << 7)
#define TIM_DIER_UIE (1u << 0)
#define TIM_SR_UIF (1u << 0)
#define TIM_EGR_UG (1u << 0)
/** OCxM field values (3 bits) for CCMRx output compare. */
#define TIM_OCM_FORCED_INACTIVE 4u
#define TIM_OCM_PWM1 6u
#define TIM_OCM_PWM2 7u
#define TIM_CCMR1_OC1PE (1u << 3)
#define TIM_CCMR1_OC1M_Pos 4u
#define TIM_CCMR1_OC2PE (1u << 11)
#define TIM_CCMR1_OC2M_Pos 12u
#define TIM_CCMR2_OC4PE (1u << 11)
#define TIM_CCMR2_OC4M_Pos 12u
#define TIM_CCER_CC1E (1u << 0)
#define TIM_CCER_CC2E (1u << 4)
#define TIM_CCER_CC4E (1u << 12)
#define TIM_BDTR_OSSI (1u << 10)
#define TIM_BDTR_OSSR (1u << 11)
#define TIM_BDTR_MOE (1u << 15)

/* ------------------------------------------------------------------------------------------ */
/* ADC (RM0090 section 13.13)                                                                 */
/* ------------------------------------------------------------------------------------------ */
/** One ADC's register block. */
typedef struct {
    REG32 SR;      /**< 0x00 status (rc_w0) */
    REG32 CR1;     /**< 0x04 */
    REG32 CR2;     /**< 0x08 */
    REG32 SMPR1;   /**< 0x0C sample time, channels 10-18 */
    REG32 SMPR2;   /**< 0x10 sample time, channels 0-9, 3 bits each */
    REG32 JOFR[4]; /**< 0x14 injected offsets */
    REG32 HTR;     /**< 0x24 */
    REG32 LTR;     /**< 0x28 */
    REG32 SQR1;    /**< 0x2C */
    REG32 SQR2;    /**< 0x30 */
    REG32 SQR3;    /**< 0x34 */
    REG32 JSQR;    /**< 0x38 injected sequence */
    REG32 JDR[4];  /**< 0x3C JDR1..JDR4 injected data */
    REG32 DR;      /**< 0x4C regular data */
} adc_regs_t;
STM32_CHECK(adc_jdr, offsetof(adc_regs_t, JDR) == 0x3Cu);
/** Registers common to the three ADCs. */
typedef struct {
    REG32 CSR; /**< 0x00 common status */
    REG32 CCR; /**< 0x04 common control (prescaler) */
    REG32 CDR; /**< 0x08 */
} adc_common_regs_t;
#define ADC1 ((adc_regs_t *)ADC1_BASE)
#define ADC_COMMON ((adc_common_regs_t *)ADC_COMMON_BASE)

#define ADC_SR_JEOC (1u << 2)  /**< injected group conversion complete */
#define ADC_SR_JSTRT (1u << 3) /**< injected group conversion started */
#define ADC_CR1_SCAN (1u << 8)
#define ADC_CR2_ADON (1u << 0)
#define ADC_CR2_JEXTSEL_Pos 16u
#define ADC_CR2_JEXTSEL_TIM1_CC4 0u /**< JEXTSEL = 0000: timer 1 CC4 event */
#define ADC_CR2_JEXTEN_RISING (1u << 20)
#define ADC_JSQR_JL_Pos 20u /**< JL[21:20] = conversions - 1 */
#define ADC_JSQR_JSQ1_Pos 0u
#define ADC_JSQR_JSQ2_Pos 5u
#define ADC_JSQR_JSQ3_Pos 10u
#define ADC_JSQR_JSQ4_Pos 15u
#define ADC_SMPR_15CYC 1u     /**< SMPx = 001: 15 ADC clock cycles */
#define ADC_CCR_ADCPRE_DIV4 (1u << 16) /**< ADCCLK = PCLK2 / 4 (21 MHz at PCLK2 = 84 MHz, max 36) */

/* ------------------------------------------------------------------------------------------ */
/* bxCAN (RM0090 section 32.9)                                                                */
/* ------------------------------------------------------------------------------------------ */
/** Transmit mailbox. */
typedef struct {
    REG32 TIR;  /**< identifier (STID[31:21] / EXID[31:3], IDE, RTR, TXRQ) */
    REG32 TDTR; /**< DLC[3:0] */
    REG32 TDLR; /**< data bytes 0-3 */
    REG32 TDHR; /**< data bytes 4-7 */
} can_tx_mailbox_t;
/** Receive FIFO mailbox. */
typedef struct {
    REG32 RIR;  /**< identifier */
    REG32 RDTR; /**< DLC[3:0], FMI */
    REG32 RDLR; /**< data bytes 0-3 */
    REG32 RDHR; /**< data bytes 4-7 */
} can_fifo_mailbox_t;
/** Filter bank (two 32-bit registers). */
typedef struct {
    REG32 FR1;
    REG32 FR2;
} can_filter_t;
/** bxCAN register block. */
typedef struct {
    REG32 MCR;                    /**< 0x000 master control */
    REG32 MSR;                    /**< 0x004 master status */
    REG32 TSR;                    /**< 0x008 transmit status */
    REG32 RF0R;                   /**< 0x00C receive FIFO 0 */
    REG32 RF1R;                   /**< 0x010 receive FIFO 1 */
    REG32 IER;                    /**< 0x014 interrupt enable */
    REG32 ESR;                    /**< 0x018 error status */
    REG32 BTR;                    /**< 0x01C bit timing */
    REG32 RESERVED0[88];          /**< 0x020 */
    can_tx_mailbox_t TX[3];       /**< 0x180 transmit mailboxes 0-2 */
    can_fifo_mailbox_t RX[2];     /**< 0x1B0 receive FIFOs 0-1 */
    REG32 RESERVED1[12];          /**< 0x1D0 */
    REG32 FMR;                    /**< 0x200 filter master */
    REG32 FM1R;                   /**< 0x204 filter mode (0 mask, 1 list) */
    REG32 RESERVED2;              /**< 0x208 */
    REG32 FS1R;                   /**< 0x20C filter scale (1: 32 bit) */
    REG32 RESERVED3;              /**< 0x210 */
    REG32 FFA1R;                  /**< 0x214 filter FIFO assignment */
    REG32 RESERVED4;              /**< 0x218 */
    REG32 FA1R;                   /**< 0x21C filter activation */
    REG32 RESERVED5[8];           /**< 0x220 */
    can_filter_t FB[28];          /**< 0x240 filter banks */
} can_regs_t;
STM32_CHECK(can_tx, offsetof(can_regs_t, TX) == 0x180u);
STM32_CHECK(can_rx, offsetof(can_regs_t, RX) == 0x1B0u);
STM32_CHECK(can_fmr, offsetof(can_regs_t, FMR) == 0x200u);
STM32_CHECK(can_fb, offsetof(can_regs_t, FB) == 0x240u);
#define CAN1 ((can_regs_t *)CAN1_BASE)

#define CAN_MCR_INRQ (1u << 0)
#define CAN_MCR_SLEEP (1u << 1)
#define CAN_MCR_TXFP (1u << 2) /**< transmit in request order */
#define CAN_MCR_ABOM (1u << 6) /**< automatic bus-off recovery */
#define CAN_MSR_INAK (1u << 0)
#define CAN_MSR_SLAK (1u << 1)
#define CAN_TSR_TME0 (1u << 26)
#define CAN_TSR_TME_Msk (7u << 26)
#define CAN_TSR_CODE_Pos 24u
#define CAN_IER_TMEIE (1u << 0)
#define CAN_IER_FMPIE0 (1u << 1)
#define CAN_RF0R_FMP0_Msk (3u << 0)
#define CAN_RF0R_FOVR0 (1u << 4)
#define CAN_RF0R_RFOM0 (1u << 5)
#define CAN_ESR_BOFF (1u << 2)
#define CAN_ESR_TEC_Pos 16u
#define CAN_ESR_REC_Pos 24u
#define CAN_BTR_BRP_Pos 0u
#define CAN_BTR_TS1_Pos 16u
#define CAN_BTR_TS2_Pos 20u
#define CAN_BTR_SJW_Pos 24u
#define CAN_TIR_TXRQ (1u << 0)
#define CAN_TIR_RTR (1u << 1)
#define CAN_TIR_IDE (1u << 2)
#define CAN_TIR_STID_Pos 21u
#define CAN_TIR_EXID_Pos 3u
#define CAN_FMR_FINIT (1u << 0)

/* ------------------------------------------------------------------------------------------ */
/* IWDG (RM0090 section 21.4) and DBGMCU (section 38.16)                                      */
/* ------------------------------------------------------------------------------------------ */
/** Independent watchdog register block. */
typedef struct {
    REG32 KR;  /**< 0x00 key */
    REG32 PR;  /**< 0x04 prescaler: 0 = /4 ... 6 = /256 */
    REG32 RLR; /**< 0x08 reload, 12 bits */
    REG32 SR;  /**< 0x0C PVU, RVU update-in-progress flags */
} iwdg_regs_t;
#define IWDG ((iwdg_regs_t *)IWDG_BASE)
#define IWDG_KEY_RELOAD 0xAAAAu
#define IWDG_KEY_ENABLE 0xCCCCu
#define IWDG_KEY_WRITE_ACCESS 0x5555u
#define IWDG_SR_PVU (1u << 0)
#define IWDG_SR_RVU (1u << 1)

/** MCU debug component. */
typedef struct {
    REG32 IDCODE;  /**< 0x00 */
    REG32 CR;      /**< 0x04 */
    REG32 APB1_FZ; /**< 0x08 freeze APB1 peripherals while the core is halted */
    REG32 APB2_FZ; /**< 0x0C */
} dbgmcu_regs_t;
#define DBGMCU ((dbgmcu_regs_t *)DBGMCU_BASE)
#define DBGMCU_APB1_FZ_DBG_TIM2_STOP (1u << 0)
#define DBGMCU_APB1_FZ_DBG_IWDG_STOP (1u << 12)
#define DBGMCU_APB2_FZ_DBG_TIM1_STOP (1u << 0)

/* ------------------------------------------------------------------------------------------ */
/* Cortex-M4 core (PM0214, ARMv7-M ARM): SCB, NVIC, FPU, DWT                                  */
/* ------------------------------------------------------------------------------------------ */
/** System control block. */
typedef struct {
    REG32 CPUID; /**< 0x00 */
    REG32 ICSR;  /**< 0x04 */
    REG32 VTOR;  /**< 0x08 vector table offset */
    REG32 AIRCR; /**< 0x0C */
    REG32 SCR;   /**< 0x10 */
    REG32 CCR;   /**< 0x14 configuration and control */
    REG32 SHPR[3]; /**< 0x18 system handler priorities */
    REG32 SHCSR; /**< 0x24 system handler control and state */
    REG32 CFSR;  /**< 0x28 configurable fault status */
    REG32 HFSR;  /**< 0x2C hard fault status */
    REG32 DFSR;  /**< 0x30 */
    REG32 MMFAR; /**< 0x34 */
    REG32 BFAR;  /**< 0x38 */
    REG32 AFSR;  /**< 0x3C */
} scb_regs_t;
#define SCB ((scb_regs_t *)0xE000ED00u)
#define SCB_AIRCR_VECTKEY (0x05FAu << 16)
#define SCB_AIRCR_SYSRESETREQ (1u << 2)
#define SCB_CCR_DIV_0_TRP (1u << 4)
#define SCB_SHCSR_MEMFAULTENA (1u << 16)
#define SCB_SHCSR_BUSFAULTENA (1u << 17)
#define SCB_SHCSR_USGFAULTENA (1u << 18)

/** Coprocessor access control (CP10/CP11 = the FPU: bits 23:20). */
#define SCB_CPACR (*(REG32 *)0xE000ED88u)
#define SCB_CPACR_CP10_CP11_FULL (0xFu << 20)
/** Debug exception and monitor control: TRCENA gates the DWT. */
#define CORE_DEMCR (*(REG32 *)0xE000EDFCu)
#define CORE_DEMCR_TRCENA (1u << 24)
/** DWT cycle counter. */
#define DWT_CTRL (*(REG32 *)0xE0001000u)
#define DWT_CTRL_CYCCNTENA (1u << 0)
#define DWT_CYCCNT (*(REG32 *)0xE0001004u)

/** NVIC: set-enable, clear-enable, clear-pending and byte-wide priority registers. */
#define NVIC_ISER ((REG32 *)0xE000E100u)
#define NVIC_ICER ((REG32 *)0xE000E180u)
#define NVIC_ICPR ((REG32 *)0xE000E280u)
#define NVIC_IPR ((volatile uint8_t *)0xE000E400u)
/** STM32F4 implements the upper 4 priority bits. */
#define NVIC_PRIO_BITS 4u

/** STM32F405/407 interrupt numbers used here (RM0090 Table 61). */
enum {
    IRQN_CAN1_TX = 19,
    IRQN_CAN1_RX0 = 20,
    IRQN_TIM2 = 28,
    IRQN_TIM5 = 50,
    IRQN_COUNT = 82 /**< positions 0..81 (81 = FPU) */
};

#ifdef __cplusplus
}
#endif

#endif /* STM32F4_REGS_H */
