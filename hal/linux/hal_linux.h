/**
 * @file hal_linux.h
 * @brief Linux real-time controller implementation of hal/hal.h, and its Linux-only controls.
 *
 * The hal_* functions of hal.h are defined in hal_linux.c on top of:
 *   hal_pwm_set_duty()   lx_pwm: two sysfs PWM channels, sign-magnitude (lx_pwm.h)
 *   hal_bridge_enable()  lx_gpio: libgpiod output line (lx_gpio.h)
 *   hal_driver_fault()   lx_gpio: libgpiod input line
 *   hal_adc_read()       lx_adc: four IIO in_voltageN_raw files (lx_adc.h); t_us = the nominal
 *                        sample instant of the period, i.e. its deadline as given by
 *                        hal_linux_set_sample_time() (the files are read at wake-up, the
 *                        loop's latency later: rt_loop reports it), or hal_time_us() before
 *                        the first call. So scheduling jitter shows up as latency and
 *                        overruns (whole periods missed), not as uneven sample spacing.
 *   hal_time_us()        CLOCK_MONOTONIC since hal_init()
 *   hal_can_send(),      lx_can: one non-blocking raw SocketCAN socket (lx_can.h); a full
 *   hal_can_receive()    transmit queue returns TV_ERR_IO (the frame is dropped)
 * Every device name and path comes from the configuration (lx_config.h), given to
 * hal_linux_configure() before hal_init().
 *
 * Not reentrant: the real-time thread is the only caller between hal_init() and
 * hal_linux_close().
 */
#ifndef HAL_LINUX_H
#define HAL_LINUX_H

#include "hal.h"
#include "lx_config.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Give the configuration hal_init() will use (copied).
 * @return TV_OK; TV_ERR_NULL.
 */
int hal_linux_configure(const lx_config_t *cfg);

/**
 * The nominal time of the samples of the period about to run: its CLOCK_MONOTONIC deadline
 * [ns] (rt_loop_stats_t::deadline_ns). 0 returns to stamping samples with the read time.
 */
void hal_linux_set_sample_time(uint64_t mono_ns);

/** When hal_adc_read() last read the files, hal_time_us() clock [us] (for TV_TIME). */
uint64_t hal_linux_last_read_us(void);

/** CLOCK_MONOTONIC at hal_init() [ns]: hal_time_us() counts from here. */
uint64_t hal_linux_t0_ns(void);

/**
 * Message of the last failure of hal_init() (names the configuration key and value), or of
 * hal_linux_safe_state(); "" when none.
 */
const char *hal_linux_error(void);

/**
 * Safe state: PWM duty 0 and disabled on both channels, bridge enable inactive. Every step is
 * attempted even if one fails.
 * @return TV_OK; TV_ERR_IO when a write failed (hal_linux_error() says which).
 */
int hal_linux_safe_state(void);

/** Safe state, then close every device. Safe to call at any time and more than once. */
void hal_linux_close(void);

#ifdef __cplusplus
}
#endif

#endif /* HAL_LINUX_H */
