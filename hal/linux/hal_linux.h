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
 * Every device name and path comes from a hal_linux_devices_t given to
 * hal_linux_configure() before hal_init() (the controller fills it from its configuration
 * file, firmware/linux_rt/lx_config.h). The HAL depends on hal.h and the status codes only.
 *
 * Not reentrant: the real-time thread is the only caller between hal_init() and
 * hal_linux_close().
 */
#ifndef HAL_LINUX_H
#define HAL_LINUX_H

#include <stdint.h>

#include "hal.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest path or device name stored [bytes, with the terminating 0]. */
#define LX_PATH_LEN 256u
/** Longest CAN interface name [bytes, with the terminating 0] (IFNAMSIZ). */
#define LX_IFNAME_LEN 16u

/** The devices hal_init() opens (set from the controller's configuration file, lx_config.h). */
typedef struct {
    /* PWM (sysfs PWM class) */
    char pwm_chip[LX_PATH_LEN];   /**< pwm.chip: e.g. /sys/class/pwm/pwmchip0 */
    uint32_t pwm_channel_a;       /**< pwm.channel_a: channel driving the bridge for duty > 0 */
    uint32_t pwm_channel_b;       /**< pwm.channel_b: channel driving the bridge for duty < 0 */
    uint32_t pwm_period_ns;       /**< pwm.period_ns: PWM period [ns] */
    /* ADC (IIO) */
    char adc_device[LX_PATH_LEN]; /**< adc.device: e.g. /sys/bus/iio/devices/iio:device0 */
    uint32_t adc_channel[4];      /**< adc.channel.{current,tps1,tps2,supply}: N of in_voltageN_raw */
    uint32_t adc_max_counts;      /**< adc.max_counts: largest valid raw value (4095 for 12 bits) */
    /* GPIO (libgpiod) */
    char gpio_chip[LX_PATH_LEN];  /**< gpio.chip: name, number, label or /dev path (gpiod_chip_open_lookup) */
    char gpio_consumer[32];       /**< gpio.consumer: consumer label shown by gpioinfo */
    uint32_t gpio_enable_line;    /**< gpio.bridge_enable.line: offset on the chip */
    int32_t gpio_enable_active_low; /**< gpio.bridge_enable.active_low: 1 = low enables */
    uint32_t gpio_fault_line;     /**< gpio.driver_fault.line: offset on the chip */
    int32_t gpio_fault_active_low; /**< gpio.driver_fault.active_low: 1 = low means fault (nFAULT pins) */
    /* CAN (SocketCAN) */
    char can_interface[LX_IFNAME_LEN]; /**< can.interface: e.g. can0, vcan0 */
} hal_linux_devices_t;

/**
 * Give the configuration hal_init() will use (copied).
 * @return TV_OK; TV_ERR_NULL.
 */
int hal_linux_configure(const hal_linux_devices_t *dev);

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
