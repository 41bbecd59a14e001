/**
 * @file sim_hal.h
 * @brief Host-simulation implementation of hal/hal.h on ONE static plant (host_sim/plant/plant.h),
 *        and the simulation-only controls the HAL functions cannot express: configuring the
 *        plant, advancing plant time, reading the true state, and injecting faults.
 *
 * The hal_* functions of hal.h are defined in sim_hal.c:
 *   hal_init()           nothing to bring up; when sim_hal_configure() was not called yet it
 *                        configures plant_config_default() with seed 1;
 *   hal_adc_read()       samples the plant at the current plant time (plant_sample()), counts as
 *                        the plant's ADC produces them (unless a channel is forced, see below),
 *                        t_us = plant time in microseconds (rounded to the nearest us);
 *   hal_pwm_set_duty(),  command the plant's H-bridge (plant_set_bridge()); a NaN/Inf duty
 *   hal_bridge_enable()  returns TV_ERR_NONFINITE, |duty| > 1 TV_ERR_RANGE, and both set the
 *                        duty to 0 (hal.h); an enable other than 0 or 1 returns TV_ERR_RANGE and
 *                        disables the bridge (the safe reading of a bad argument);
 *   hal_driver_fault()   reads a simulated flag, sim_hal_set_driver_fault();
 *   hal_time_us()        plant time in microseconds (monotonic: plant time never goes back);
 *   hal_can_send(),      an in-memory loopback: frames sent are the frames received, FIFO, in a
 *   hal_can_receive()    fixed queue of SIM_HAL_CAN_QUEUE_LEN frames (no heap); a send into a
 *                        full queue returns TV_ERR_IO and is counted (sim_hal_can_overflows()).
 * Time moves only when the simulation calls sim_hal_advance(): the application's tick reads
 * the ADC and writes the bridge at one plant instant, and the plant then integrates the
 * commanded bridge over the period.
 *
 * Not reentrant: there is one plant per process, as there is one actuator per ECU.
 */
#ifndef SIM_HAL_H
#define SIM_HAL_H

#include <stdint.h>

#include "hal.h"
#include "plant.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Capacity of the CAN loopback queue [frames]. */
#define SIM_HAL_CAN_QUEUE_LEN 32u

/**
 * (Re)initialise the simulated platform: plant_init(cfg, seed) (plant at rest at limp-home,
 * bridge disabled, time 0), driver-fault flag cleared, no forced ADC channel, no pending ADC
 * failures, CAN queue emptied and its overflow count zeroed.
 * @param cfg   plant configuration (copied; validated by plant_init())
 * @param seed  noise seed of the plant's sensors (same seed, same run)
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE / TV_ERR_CONFIG when plant_init() rejects cfg
 *         (plant_config_check() names the field). On error the previous set-up is kept.
 */
int sim_hal_configure(const plant_config_t *cfg, uint64_t seed);

/**
 * Integrate the plant over dt_s with the bridge command in force (plant_advance()).
 * @param dt_s time to advance [s], 0..PLANT_ADVANCE_MAX_S
 * @return TV_OK; TV_ERR_CONFIG before sim_hal_configure(); otherwise plant_advance()'s status.
 */
int sim_hal_advance(double dt_s);

/**
 * True state of the plant now.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG before sim_hal_configure().
 */
int sim_hal_truth(plant_state_t *out);

/**
 * Overwrite the true state (scenarios start the plate somewhere else than limp-home).
 * @return TV_OK; TV_ERR_CONFIG before sim_hal_configure(); otherwise plant_set_state()'s status.
 */
int sim_hal_set_state(const plant_state_t *state);

/** The plant's parameters in force now: the unit's with the injected faults applied (a winding
 *  resistance fault's R, a friction fault's Mc, ...). TV_OK, TV_ERR_NULL, or TV_ERR_CONFIG before
 *  sim_hal_configure(). */
int sim_hal_config_in_force(plant_config_t *out);

/**
 * Mean terminal voltage of the winding over the last sim_hal_advance() [V] (the input the
 * plant really received, diode conduction and open winding included).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG before sim_hal_configure().
 */
int sim_hal_bridge_voltage(double *mean_V);

/** Plant time [s]; 0 before sim_hal_configure(). */
double sim_hal_time_s(void);

/**
 * The HAL outputs in force: the duty last accepted (0 after a rejected one) and the enable.
 * Either pointer may be NULL.
 */
void sim_hal_outputs(float *duty, int *enable);

/**
 * Put plant faults into force (plant_set_faults(); the schedule is plant_fault.h's).
 * @return TV_OK; TV_ERR_CONFIG before sim_hal_configure(); otherwise plant_set_faults()'s status.
 */
int sim_hal_set_faults(const plant_faults_t *faults);

/** Set the driver-fault input that hal_driver_fault() reports (nonzero: fault active). */
void sim_hal_set_driver_fault(int active);

/**
 * Force an ADC channel to a fixed count (a track open circuit is tps1 = 0, a short to the
 * sensor supply is full scale). Stays forced until sim_hal_release_adc() or sim_hal_configure().
 * @param channel  HAL_ADC_CURRENT .. HAL_ADC_SUPPLY
 * @param counts   0 .. 2^adc_bits - 1 of the configured plant
 * @return TV_OK; TV_ERR_RANGE (bad channel or counts); TV_ERR_CONFIG before sim_hal_configure().
 */
int sim_hal_force_adc(int channel, uint16_t counts);

/**
 * Stop forcing a channel (it reads the plant again).
 * @return TV_OK; TV_ERR_RANGE for a bad channel.
 */
int sim_hal_release_adc(int channel);

/**
 * Make the next n_reads calls of hal_adc_read() fail with TV_ERR_IO (a conversion that did
 * not complete); they do not sample the plant.
 */
void sim_hal_fail_adc_reads(uint32_t n_reads);

/**
 * The last conversion hal_adc_read() took, with the analogue pin voltages (host diagnostics),
 * counts as returned (forced channels included).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG when no conversion was taken since configuring.
 */
int sim_hal_last_adc(plant_adc_t *out);

/**
 * Time stamp hal_adc_read() gave the last conversion [us] (what the application saw as t_us).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG when no conversion was taken since configuring.
 */
int sim_hal_last_adc_time_us(uint64_t *t_us);

/** Frames refused by hal_can_send() because the loopback queue was full, since configuring. */
uint32_t sim_hal_can_overflows(void);

/** Frames waiting in the loopback queue. */
uint32_t sim_hal_can_pending(void);

#ifdef __cplusplus
}
#endif

#endif /* SIM_HAL_H */
