/**
 * @file hal_linux.c
 * @brief hal/hal.h on Linux: sysfs PWM, IIO ADC, libgpiod GPIO, SocketCAN (see hal_linux.h).
 */
#define _POSIX_C_SOURCE 200809L

#include "hal_linux.h"

#include "lx_err.h"

#include <stdio.h>
#include <string.h>
#include <time.h>

#include "lx_adc.h"
#include "lx_can.h"
#include "lx_gpio.h"
#include "lx_pwm.h"
#include "tv_status.h"

static hal_linux_devices_t s_cfg;
static int s_configured;
static lx_pwm_t s_pwm;
static lx_adc_t s_adc;
static lx_gpio_t s_gpio;
static lx_can_t s_can;
static uint64_t s_t0_ns;
static uint64_t s_sample_ns;
static uint64_t s_last_read_us;
static char s_err[LX_ERR_LEN];

static uint64_t mono_ns(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

int hal_linux_configure(const hal_linux_devices_t *cfg)
{
    if (cfg == NULL) {
        return TV_ERR_NULL;
    }
    s_cfg = *cfg;
    s_configured = 1;
    return TV_OK;
}

void hal_linux_set_sample_time(uint64_t mono_ns)
{
    s_sample_ns = mono_ns;
}

uint64_t hal_linux_last_read_us(void)
{
    return s_last_read_us;
}

uint64_t hal_linux_t0_ns(void)
{
    return s_t0_ns;
}

const char *hal_linux_error(void)
{
    return s_err;
}

int hal_init(void)
{
    int rc;
    s_err[0] = '\0';
    if (!s_configured) {
        (void)snprintf(s_err, sizeof s_err, "hal_init: hal_linux_configure() was not called");
        return TV_ERR_CONFIG;
    }
    hal_linux_close();
    s_t0_ns = mono_ns();
    s_sample_ns = 0u;
    /* The bridge first, so it is held disabled while the rest comes up. */
    rc = lx_gpio_open(&s_gpio, s_cfg.gpio_chip, s_cfg.gpio_consumer, s_cfg.gpio_enable_line,
                      s_cfg.gpio_enable_active_low, s_cfg.gpio_fault_line, s_cfg.gpio_fault_active_low, s_err,
                      sizeof s_err);
    if (rc == TV_OK) {
        rc = lx_pwm_open(&s_pwm, s_cfg.pwm_chip, s_cfg.pwm_channel_a, s_cfg.pwm_channel_b, s_cfg.pwm_period_ns, s_err,
                         sizeof s_err);
    }
    if (rc == TV_OK) {
        rc = lx_adc_open(&s_adc, s_cfg.adc_device, s_cfg.adc_channel, s_cfg.adc_max_counts, s_err, sizeof s_err);
    }
    if (rc == TV_OK) {
        rc = lx_can_open(&s_can, s_cfg.can_interface, s_err, sizeof s_err);
    }
    if (rc != TV_OK) {
        char keep[LX_ERR_LEN];
        memcpy(keep, s_err, sizeof keep);
        hal_linux_close();
        memcpy(s_err, keep, sizeof s_err);
    }
    return rc;
}

int hal_pwm_set_duty(float duty)
{
    return lx_pwm_set(&s_pwm, duty);
}

int hal_bridge_enable(int enable)
{
    return lx_gpio_set_enable(&s_gpio, enable);
}

int hal_driver_fault(int *fault_active)
{
    return lx_gpio_get_fault(&s_gpio, fault_active);
}

int hal_adc_read(hal_adc_sample_t *sample)
{
    uint64_t t;
    int rc;
    if (sample == NULL) {
        return TV_ERR_NULL;
    }
    s_last_read_us = hal_time_us();
    t = s_sample_ns > s_t0_ns ? (s_sample_ns - s_t0_ns) / 1000u : s_last_read_us;
    rc = lx_adc_read(&s_adc, sample->counts);
    if (rc == TV_OK) {
        sample->t_us = t;
    }
    return rc;
}

uint64_t hal_time_us(void)
{
    return (mono_ns() - s_t0_ns) / 1000u;
}

int hal_can_send(const hal_can_frame_t *frame)
{
    return lx_can_send(&s_can, frame);
}

int hal_can_receive(hal_can_frame_t *frame)
{
    return lx_can_receive(&s_can, frame);
}

int hal_linux_safe_state(void)
{
    int rc = TV_OK;
    if (s_pwm.is_open && lx_pwm_off(&s_pwm) != TV_OK) {
        (void)snprintf(s_err, sizeof s_err, "safe state: writing the PWM channels of '%s' failed", s_cfg.pwm_chip);
        rc = TV_ERR_IO;
    }
    if (s_gpio.enable != NULL && lx_gpio_set_enable(&s_gpio, 0) != TV_OK) {
        (void)snprintf(s_err, sizeof s_err, "safe state: driving gpio.bridge_enable.line = %u inactive failed",
                       (unsigned)s_cfg.gpio_enable_line);
        rc = TV_ERR_IO;
    }
    return rc;
}

void hal_linux_close(void)
{
    (void)hal_linux_safe_state();
    lx_can_close(&s_can);
    lx_adc_close(&s_adc);
    lx_pwm_close(&s_pwm);
    lx_gpio_close(&s_gpio);
}
