/**
 * @file app_tick.h
 * @brief One 1 ms tick of the application against the HAL (hal.h), for the platforms.
 */
#ifndef APP_TICK_H
#define APP_TICK_H

#include "app.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Read the ADC and the driver-fault input, run app_step(), write duty and bridge enable.
 * @param out filled with the step's outputs (for logging / telemetry).
 * @return TV_OK; the HAL's error when a read or write failed (outputs then forced safe).
 */
int app_tick(app_t *app, app_output_t *out);

#ifdef __cplusplus
}
#endif

#endif /* APP_TICK_H */
