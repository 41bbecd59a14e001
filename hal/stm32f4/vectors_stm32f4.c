/**
 * @file vectors_stm32f4.c
 * @brief Vector table of the STM32F405/407 (RM0090 Table 61: 16 system exceptions + 82
 *        interrupt positions, 0..81). Every handler is a weak alias of Default_Handler
 *        (startup_cm4f.c); a module that handles an interrupt defines the strong symbol.
 *        Placed first in flash by the linker script (section .isr_vector); the reset handler
 *        of the ECU sets VTOR to it.
 */
#include <stdint.h>

#include "startup.h"

/** Exception handler. */
typedef void (*vector_handler_t)(void);

/** Layout of the table: initial stack pointer, then the handlers. */
typedef struct {
    void *initial_sp;                 /**< loaded into MSP at reset */
    vector_handler_t system[15];      /**< Reset .. SysTick (exceptions 1..15) */
    vector_handler_t irq[82];         /**< IRQ 0..81 (exceptions 16..97) */
} vector_table_t;

extern uint32_t _estack;
void Reset_Handler(void);
void Default_Handler(void);

#define WEAK_ALIAS __attribute__((weak, alias("Default_Handler")))

/* Every fault and every interrupt without its own handler ends here (the alias target must be
 * in this translation unit). */
void Default_Handler(void)
{
    uint32_t ipsr;
    __asm__ volatile("mrs %0, ipsr" : "=r"(ipsr));
    startup_fault_hook(ipsr & 0x1FFu);
    for (;;) {
        /* Wait for the independent watchdog (if started) to reset the MCU. */
    }
}

void NMI_Handler(void) WEAK_ALIAS;
void HardFault_Handler(void) WEAK_ALIAS;
void MemManage_Handler(void) WEAK_ALIAS;
void BusFault_Handler(void) WEAK_ALIAS;
void UsageFault_Handler(void) WEAK_ALIAS;
void SVC_Handler(void) WEAK_ALIAS;
void DebugMon_Handler(void) WEAK_ALIAS;
void PendSV_Handler(void) WEAK_ALIAS;
void SysTick_Handler(void) WEAK_ALIAS;
void WWDG_IRQHandler(void) WEAK_ALIAS;
void PVD_IRQHandler(void) WEAK_ALIAS;
void TAMP_STAMP_IRQHandler(void) WEAK_ALIAS;
void RTC_WKUP_IRQHandler(void) WEAK_ALIAS;
void FLASH_IRQHandler(void) WEAK_ALIAS;
void RCC_IRQHandler(void) WEAK_ALIAS;
void EXTI0_IRQHandler(void) WEAK_ALIAS;
void EXTI1_IRQHandler(void) WEAK_ALIAS;
void EXTI2_IRQHandler(void) WEAK_ALIAS;
void EXTI3_IRQHandler(void) WEAK_ALIAS;
void EXTI4_IRQHandler(void) WEAK_ALIAS;
void DMA1_Stream0_IRQHandler(void) WEAK_ALIAS;
void DMA1_Stream1_IRQHandler(void) WEAK_ALIAS;
void DMA1_Stream2_IRQHandler(void) WEAK_ALIAS;
void DMA1_Stream3_IRQHandler(void) WEAK_ALIAS;
void DMA1_Stream4_IRQHandler(void) WEAK_ALIAS;
void DMA1_Stream5_IRQHandler(void) WEAK_ALIAS;
void DMA1_Stream6_IRQHandler(void) WEAK_ALIAS;
void ADC_IRQHandler(void) WEAK_ALIAS;
void CAN1_TX_IRQHandler(void) WEAK_ALIAS;
void CAN1_RX0_IRQHandler(void) WEAK_ALIAS;
void CAN1_RX1_IRQHandler(void) WEAK_ALIAS;
void CAN1_SCE_IRQHandler(void) WEAK_ALIAS;
void EXTI9_5_IRQHandler(void) WEAK_ALIAS;
void TIM1_BRK_TIM9_IRQHandler(void) WEAK_ALIAS;
void TIM1_UP_TIM10_IRQHandler(void) WEAK_ALIAS;
void TIM1_TRG_COM_TIM11_IRQHandler(void) WEAK_ALIAS;
void TIM1_CC_IRQHandler(void) WEAK_ALIAS;
void TIM2_IRQHandler(void) WEAK_ALIAS;
void TIM3_IRQHandler(void) WEAK_ALIAS;
void TIM4_IRQHandler(void) WEAK_ALIAS;
void I2C1_EV_IRQHandler(void) WEAK_ALIAS;
void I2C1_ER_IRQHandler(void) WEAK_ALIAS;
void I2C2_EV_IRQHandler(void) WEAK_ALIAS;
void I2C2_ER_IRQHandler(void) WEAK_ALIAS;
void SPI1_IRQHandler(void) WEAK_ALIAS;
void SPI2_IRQHandler(void) WEAK_ALIAS;
void USART1_IRQHandler(void) WEAK_ALIAS;
void USART2_IRQHandler(void) WEAK_ALIAS;
void USART3_IRQHandler(void) WEAK_ALIAS;
void EXTI15_10_IRQHandler(void) WEAK_ALIAS;
void RTC_Alarm_IRQHandler(void) WEAK_ALIAS;
void OTG_FS_WKUP_IRQHandler(void) WEAK_ALIAS;
void TIM8_BRK_TIM12_IRQHandler(void) WEAK_ALIAS;
void TIM8_UP_TIM13_IRQHandler(void) WEAK_ALIAS;
void TIM8_TRG_COM_TIM14_IRQHandler(void) WEAK_ALIAS;
void TIM8_CC_IRQHandler(void) WEAK_ALIAS;
void DMA1_Stream7_IRQHandler(void) WEAK_ALIAS;
void FSMC_IRQHandler(void) WEAK_ALIAS;
void SDIO_IRQHandler(void) WEAK_ALIAS;
void TIM5_IRQHandler(void) WEAK_ALIAS;
void SPI3_IRQHandler(void) WEAK_ALIAS;
void UART4_IRQHandler(void) WEAK_ALIAS;
void UART5_IRQHandler(void) WEAK_ALIAS;
void TIM6_DAC_IRQHandler(void) WEAK_ALIAS;
void TIM7_IRQHandler(void) WEAK_ALIAS;
void DMA2_Stream0_IRQHandler(void) WEAK_ALIAS;
void DMA2_Stream1_IRQHandler(void) WEAK_ALIAS;
void DMA2_Stream2_IRQHandler(void) WEAK_ALIAS;
void DMA2_Stream3_IRQHandler(void) WEAK_ALIAS;
void DMA2_Stream4_IRQHandler(void) WEAK_ALIAS;
void ETH_IRQHandler(void) WEAK_ALIAS;
void ETH_WKUP_IRQHandler(void) WEAK_ALIAS;
void CAN2_TX_IRQHandler(void) WEAK_ALIAS;
void CAN2_RX0_IRQHandler(void) WEAK_ALIAS;
void CAN2_RX1_IRQHandler(void) WEAK_ALIAS;
void CAN2_SCE_IRQHandler(void) WEAK_ALIAS;
void OTG_FS_IRQHandler(void) WEAK_ALIAS;
void DMA2_Stream5_IRQHandler(void) WEAK_ALIAS;
void DMA2_Stream6_IRQHandler(void) WEAK_ALIAS;
void DMA2_Stream7_IRQHandler(void) WEAK_ALIAS;
void USART6_IRQHandler(void) WEAK_ALIAS;
void I2C3_EV_IRQHandler(void) WEAK_ALIAS;
void I2C3_ER_IRQHandler(void) WEAK_ALIAS;
void OTG_HS_EP1_OUT_IRQHandler(void) WEAK_ALIAS;
void OTG_HS_EP1_IN_IRQHandler(void) WEAK_ALIAS;
void OTG_HS_WKUP_IRQHandler(void) WEAK_ALIAS;
void OTG_HS_IRQHandler(void) WEAK_ALIAS;
void DCMI_IRQHandler(void) WEAK_ALIAS;
void CRYP_IRQHandler(void) WEAK_ALIAS;
void HASH_RNG_IRQHandler(void) WEAK_ALIAS;
void FPU_IRQHandler(void) WEAK_ALIAS;

/** The table (const: it lives in flash). */
__attribute__((section(".isr_vector"), used)) const vector_table_t g_vector_table = {
    &_estack,
    {
        Reset_Handler,
        NMI_Handler,
        HardFault_Handler,
        MemManage_Handler,
        BusFault_Handler,
        UsageFault_Handler,
        0,
        0,
        0,
        0,
        SVC_Handler,
        DebugMon_Handler,
        0,
        PendSV_Handler,
        SysTick_Handler,
    },
    {
        WWDG_IRQHandler, /* 0 */
        PVD_IRQHandler, /* 1 */
        TAMP_STAMP_IRQHandler, /* 2 */
        RTC_WKUP_IRQHandler, /* 3 */
        FLASH_IRQHandler, /* 4 */
        RCC_IRQHandler, /* 5 */
        EXTI0_IRQHandler, /* 6 */
        EXTI1_IRQHandler, /* 7 */
        EXTI2_IRQHandler, /* 8 */
        EXTI3_IRQHandler, /* 9 */
        EXTI4_IRQHandler, /* 10 */
        DMA1_Stream0_IRQHandler, /* 11 */
        DMA1_Stream1_IRQHandler, /* 12 */
        DMA1_Stream2_IRQHandler, /* 13 */
        DMA1_Stream3_IRQHandler, /* 14 */
        DMA1_Stream4_IRQHandler, /* 15 */
        DMA1_Stream5_IRQHandler, /* 16 */
        DMA1_Stream6_IRQHandler, /* 17 */
        ADC_IRQHandler, /* 18 */
        CAN1_TX_IRQHandler, /* 19 */
        CAN1_RX0_IRQHandler, /* 20 */
        CAN1_RX1_IRQHandler, /* 21 */
        CAN1_SCE_IRQHandler, /* 22 */
        EXTI9_5_IRQHandler, /* 23 */
        TIM1_BRK_TIM9_IRQHandler, /* 24 */
        TIM1_UP_TIM10_IRQHandler, /* 25 */
        TIM1_TRG_COM_TIM11_IRQHandler, /* 26 */
        TIM1_CC_IRQHandler, /* 27 */
        TIM2_IRQHandler, /* 28 */
        TIM3_IRQHandler, /* 29 */
        TIM4_IRQHandler, /* 30 */
        I2C1_EV_IRQHandler, /* 31 */
        I2C1_ER_IRQHandler, /* 32 */
        I2C2_EV_IRQHandler, /* 33 */
        I2C2_ER_IRQHandler, /* 34 */
        SPI1_IRQHandler, /* 35 */
        SPI2_IRQHandler, /* 36 */
        USART1_IRQHandler, /* 37 */
        USART2_IRQHandler, /* 38 */
        USART3_IRQHandler, /* 39 */
        EXTI15_10_IRQHandler, /* 40 */
        RTC_Alarm_IRQHandler, /* 41 */
        OTG_FS_WKUP_IRQHandler, /* 42 */
        TIM8_BRK_TIM12_IRQHandler, /* 43 */
        TIM8_UP_TIM13_IRQHandler, /* 44 */
        TIM8_TRG_COM_TIM14_IRQHandler, /* 45 */
        TIM8_CC_IRQHandler, /* 46 */
        DMA1_Stream7_IRQHandler, /* 47 */
        FSMC_IRQHandler, /* 48 */
        SDIO_IRQHandler, /* 49 */
        TIM5_IRQHandler, /* 50 */
        SPI3_IRQHandler, /* 51 */
        UART4_IRQHandler, /* 52 */
        UART5_IRQHandler, /* 53 */
        TIM6_DAC_IRQHandler, /* 54 */
        TIM7_IRQHandler, /* 55 */
        DMA2_Stream0_IRQHandler, /* 56 */
        DMA2_Stream1_IRQHandler, /* 57 */
        DMA2_Stream2_IRQHandler, /* 58 */
        DMA2_Stream3_IRQHandler, /* 59 */
        DMA2_Stream4_IRQHandler, /* 60 */
        ETH_IRQHandler, /* 61 */
        ETH_WKUP_IRQHandler, /* 62 */
        CAN2_TX_IRQHandler, /* 63 */
        CAN2_RX0_IRQHandler, /* 64 */
        CAN2_RX1_IRQHandler, /* 65 */
        CAN2_SCE_IRQHandler, /* 66 */
        OTG_FS_IRQHandler, /* 67 */
        DMA2_Stream5_IRQHandler, /* 68 */
        DMA2_Stream6_IRQHandler, /* 69 */
        DMA2_Stream7_IRQHandler, /* 70 */
        USART6_IRQHandler, /* 71 */
        I2C3_EV_IRQHandler, /* 72 */
        I2C3_ER_IRQHandler, /* 73 */
        OTG_HS_EP1_OUT_IRQHandler, /* 74 */
        OTG_HS_EP1_IN_IRQHandler, /* 75 */
        OTG_HS_WKUP_IRQHandler, /* 76 */
        OTG_HS_IRQHandler, /* 77 */
        DCMI_IRQHandler, /* 78 */
        CRYP_IRQHandler, /* 79 */
        HASH_RNG_IRQHandler, /* 80 */
        FPU_IRQHandler, /* 81 */
    },
};

const uint32_t *startup_vector_words(void)
{
    return (const uint32_t *)(const void *)&g_vector_table;
}
