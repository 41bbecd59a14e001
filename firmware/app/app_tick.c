/**
 * @file app_tick.c
 * @brief The platform-facing 1 ms tick: HAL inputs -> app_step() -> HAL outputs. Every platform
 *        calls app_tick() from its 1 kHz source (timer ISR, clock_nanosleep loop, simulator).
 */
#include "app_tick.h"

#include <stddef.h>

#include "hal.h"
#include "tv_status.h"

int app_tick(app_t *app, app_output_t *out)
{
    hal_adc_sample_t s;
    app_input_t in;
    int fault = 0;
    int rc;
    int k;
    if (app == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    rc = hal_adc_read(&s);
    if (rc != TV_OK) {
        /* No sample: outputs to the safe state; the application sees nothing this period. */
        (void)hal_pwm_set_duty(0.0f);
        (void)hal_bridge_enable(0);
        app_sample_missed(app);
        return rc;
    }
    for (k = 0; k < 4; ++k) {
        in.adc[k] = s.counts[k];
    }
    in.t_us = s.t_us;
    if (hal_driver_fault(&fault) != TV_OK) {
        fault = 1; /* an unreadable fault input is a fault */
    }
    in.driver_fault = fault ? 1u : 0u;
    in.duty_ext = 0.0f; /* no external controller on a platform tick */
    in.bridge_ext = 0u;
    app_step(app, &in, out);
    if (out->bridge_enable) {
        rc = hal_pwm_set_duty(out->duty);
        if (rc == TV_OK) {
            rc = hal_bridge_enable(1);
        }
    } else {
        (void)hal_pwm_set_duty(0.0f);
        rc = hal_bridge_enable(0);
    }
    if (rc != TV_OK) {
        /* A failed write: force the outputs off and tell the estimator. */
        (void)hal_pwm_set_duty(0.0f);
        (void)hal_bridge_enable(0);
        app_outputs_forced_off(app);
    }
    return rc;
}
