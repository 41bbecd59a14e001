/**
 * @file lx_pwm.h
 * @brief H-bridge PWM through the kernel's sysfs PWM class (Documentation/driver-api/pwm.rst):
 *        <chip>/export, <chip>/pwmN/{period,duty_cycle,enable}, values in nanoseconds.
 *
 * Two channels drive the bridge sign-magnitude, as IN1/IN2 bridges (DRV887x, VNH-style with
 * PWM on both inputs) expect: duty > 0 puts |duty| on channel A and 0 on channel B, duty < 0
 * the reverse. The channel going to 0 is written first, so both inputs are never high
 * together because of the write order.
 *
 * The files are opened once and written with pwrite() at offset 0, which is how sysfs
 * attributes take a new value; a value is written only when it changed. The same code works on
 * a plain directory tree with those files (the VM test's plant simulation reads them).
 */
#ifndef LX_PWM_H
#define LX_PWM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** An opened pair of PWM channels. Zero-initialise, then lx_pwm_open(). */
typedef struct {
    int fd_duty[2];      /**< pwmN/duty_cycle of channels A and B, -1 when closed */
    int fd_enable[2];    /**< pwmN/enable of channels A and B, -1 when closed */
    uint32_t period_ns;  /**< PWM period [ns] */
    uint32_t duty_ns[2]; /**< last value written to each duty_cycle [ns] */
    int is_open;         /**< 1 between a successful open and close */
} lx_pwm_t;

/**
 * Open (exporting when needed) channels A and B of a PWM chip, set duty 0, the period, then
 * enable both with duty 0.
 * @param chip  sysfs directory of the chip (config key pwm.chip)
 * @param ch_a  channel for positive duty (pwm.channel_a); ch_b for negative (pwm.channel_b)
 * @param period_ns  period (pwm.period_ns)
 * @param err   receives a message naming the config key and value on error
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (chip missing, not a directory, channel beyond
 *         npwm or not exportable, period refused by the driver); TV_ERR_IO (a write failed).
 *         On error everything opened is closed again.
 */
int lx_pwm_open(lx_pwm_t *pwm, const char *chip, uint32_t ch_a, uint32_t ch_b, uint32_t period_ns, char *err,
                size_t err_len);

/**
 * Apply a signed duty.
 * @param duty in [-1, 1]; NaN/Inf -> TV_ERR_NONFINITE and |duty| > 1 -> TV_ERR_RANGE, both
 *        after setting duty 0 (hal.h semantics)
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG when not open; TV_ERR_IO when a write failed.
 */
int lx_pwm_set(lx_pwm_t *pwm, float duty);

/**
 * Safe state: duty 0 and enable 0 on both channels (every write attempted even if one fails).
 * @return TV_OK, or TV_ERR_IO when a write failed; TV_ERR_CONFIG when not open.
 */
int lx_pwm_off(lx_pwm_t *pwm);

/** lx_pwm_off(), then close the files (the channels stay exported). Safe to call twice. */
void lx_pwm_close(lx_pwm_t *pwm);

#ifdef __cplusplus
}
#endif

#endif /* LX_PWM_H */
