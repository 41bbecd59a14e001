/**
 * @file hal.h
 * @brief Hardware abstraction: the plain functions the 1 kHz application needs from a platform.
 *
 * One implementation per executable, chosen at link time (STYLE.md): host simulation
 * (host_sim/sim/sim_hal.c), Cortex-M4 ECU, Linux real-time controller, test fakes. No dispatch
 * tables: exactly one definition of each function is linked.
 *
 * All functions return 0 on success and a negative tv_status_t on error unless documented
 * otherwise. None of them blocks longer than its documented bound.
 */
#ifndef HAL_H
#define HAL_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Number of ADC channels the application reads. */
#define HAL_ADC_CHANNELS 4

/** ADC channel indices (raw counts in hal_adc_sample_t::counts). */
enum {
    HAL_ADC_CURRENT = 0, /**< motor current-sense amplifier output */
    HAL_ADC_TPS1 = 1,    /**< position track 1 (rising with opening) */
    HAL_ADC_TPS2 = 2,    /**< position track 2 (falling with opening) */
    HAL_ADC_SUPPLY = 3   /**< supply voltage through its divider */
};

/** One set of ADC conversions, taken together (the PWM-centre trigger on the ECU). */
typedef struct {
    uint16_t counts[HAL_ADC_CHANNELS]; /**< raw counts, 0 .. (2^bits - 1) */
    uint64_t t_us;                     /**< monotonic time of the conversion [us] */
} hal_adc_sample_t;

/** A classic CAN frame (11-bit or 29-bit identifier, up to 8 data bytes). */
typedef struct {
    uint32_t id;      /**< identifier (11 or 29 bits) */
    uint8_t extended; /**< 1: 29-bit identifier */
    uint8_t dlc;      /**< data length 0..8 */
    uint8_t data[8];  /**< payload, bytes beyond dlc are 0 */
} hal_can_frame_t;

/** Bring up the platform's peripherals. Call once before any other hal_ function. */
int hal_init(void);

/**
 * Set the H-bridge PWM duty: sign = direction, magnitude 0..1 of the supply.
 * @param duty in [-1, 1]; values outside, NaN or Inf return TV_ERR_RANGE / TV_ERR_NONFINITE
 *        and set the output to 0.
 */
int hal_pwm_set_duty(float duty);

/** Enable (1) or disable (0) the H-bridge driver (GPIO output). Disabled = outputs floating. */
int hal_bridge_enable(int enable);

/**
 * Read the H-bridge driver's fault input (GPIO).
 * @param fault_active set to 1 when the driver reports a fault (over-current, over-temperature).
 */
int hal_driver_fault(int *fault_active);

/** Read the latest set of ADC conversions (the ones taken in this control period). */
int hal_adc_read(hal_adc_sample_t *sample);

/** Monotonic time [us] since hal_init(). Never goes backwards. */
uint64_t hal_time_us(void);

/** Queue one CAN frame for transmission. @return 0, or TV_ERR_IO when the queue is full. */
int hal_can_send(const hal_can_frame_t *frame);

/**
 * Take one received CAN frame, without waiting.
 * @return 1 when a frame was written to *frame, 0 when none is pending, < 0 on error.
 */
int hal_can_receive(hal_can_frame_t *frame);

#ifdef __cplusplus
}
#endif

#endif /* HAL_H */
