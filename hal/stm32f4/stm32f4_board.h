/**
 * @file stm32f4_board.h
 * @brief Pin map and fixed hardware facts of the throttle ECU board (STM32F405/407, LQFP64 or
 *        larger). Change a pin here and nowhere else.
 *
 *   PA0  ADC123_IN0   motor current-sense amplifier output   HAL_ADC_CURRENT
 *   PA1  ADC123_IN1   throttle position track 1 (rising)      HAL_ADC_TPS1
 *   PA2  ADC123_IN2   throttle position track 2 (falling)     HAL_ADC_TPS2
 *   PA3  ADC123_IN3   supply voltage divider                  HAL_ADC_SUPPLY
 *   PA8  TIM1_CH1 AF1 H-bridge input IN1 (forward PWM)
 *   PA9  TIM1_CH2 AF1 H-bridge input IN2 (reverse PWM)
 *   PB0  GPIO out     H-bridge enable, active high (low = outputs floating)
 *   PB1  GPIO in      H-bridge fault, active low, open drain (internal pull-up)
 *   PB8  CAN1_RX AF9, PB9 CAN1_TX AF9  to the CAN transceiver
 * The H-bridge driver is an IN1/IN2 type: IN1 = PWM, IN2 = 0 drives forward and recirculates
 * through the low sides in the off-time (slow decay, 0 V across the winding, as the plant
 * model assumes); IN1 = IN2 = 0 with enable high is the low-side brake; enable low floats.
 */
#ifndef STM32F4_BOARD_H
#define STM32F4_BOARD_H

#ifdef __cplusplus
extern "C" {
#endif

/** HSE crystal [Hz]; 4..26 MHz and a whole number of MHz (PLL input 1 MHz). */
#ifndef STM32F4_HSE_HZ
#define STM32F4_HSE_HZ 8000000u
#endif

/** ADC channel of each HAL_ADC_* input (ADC1_INx on PA0..PA3). */
#define BOARD_ADC_CH_CURRENT 0u
#define BOARD_ADC_CH_TPS1 1u
#define BOARD_ADC_CH_TPS2 2u
#define BOARD_ADC_CH_SUPPLY 3u

#define BOARD_PWM_IN1_PIN 8u   /**< GPIOA, TIM1_CH1 */
#define BOARD_PWM_IN2_PIN 9u   /**< GPIOA, TIM1_CH2 */
#define BOARD_PWM_AF 1u
#define BOARD_BRIDGE_EN_PIN 0u /**< GPIOB */
#define BOARD_BRIDGE_FAULT_PIN 1u /**< GPIOB, active low */
#define BOARD_CAN_RX_PIN 8u    /**< GPIOB */
#define BOARD_CAN_TX_PIN 9u    /**< GPIOB */
#define BOARD_CAN_AF 9u

#ifdef __cplusplus
}
#endif

#endif /* STM32F4_BOARD_H */
