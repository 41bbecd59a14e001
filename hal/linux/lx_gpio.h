/**
 * @file lx_gpio.h
 * @brief H-bridge enable output and driver-fault input through the GPIO character device,
 *        with libgpiod 1.6 (the API Debian 12 ships: gpiod_chip_open_lookup(),
 *        gpiod_line_request_output_flags(), gpiod_line_set_value(), ...).
 *
 * Polarity is handled by the kernel (GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW): the functions here
 * work in logical values, 1 = bridge enabled, 1 = fault present.
 */
#ifndef LX_GPIO_H
#define LX_GPIO_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct gpiod_chip;
struct gpiod_line;

/** The two requested lines. Zero-initialise, then lx_gpio_open(). */
typedef struct {
    struct gpiod_chip *chip;   /**< the opened chip, NULL when closed */
    struct gpiod_line *enable; /**< bridge enable output, requested */
    struct gpiod_line *fault;  /**< driver fault input, requested */
} lx_gpio_t;

/**
 * Open the chip and request the enable line as an output driven inactive (bridge disabled)
 * and the fault line as an input.
 * @param chip      chip name, number, label or /dev path (config key gpio.chip)
 * @param consumer  consumer label (gpio.consumer)
 * @param enable_line, enable_active_low  gpio.bridge_enable.line / .active_low
 * @param fault_line, fault_active_low    gpio.driver_fault.line / .active_low
 * @param err       receives a message naming the config key and value on error
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (no such chip, line beyond the chip, line busy,
 *         request refused). On error nothing stays open.
 */
int lx_gpio_open(lx_gpio_t *gpio, const char *chip, const char *consumer, uint32_t enable_line, int enable_active_low,
                 uint32_t fault_line, int fault_active_low, char *err, size_t err_len);

/**
 * Drive the enable output (logical value).
 * @param enable 0 or 1; anything else returns TV_ERR_RANGE after disabling (the safe reading)
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG when not open; TV_ERR_IO when the kernel refused.
 */
int lx_gpio_set_enable(lx_gpio_t *gpio, int enable);

/**
 * Read the fault input (logical value: 1 = fault).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG when not open; TV_ERR_IO when the read failed.
 */
int lx_gpio_get_fault(lx_gpio_t *gpio, int *fault_active);

/** Drive the enable output inactive, release both lines, close the chip. Safe to call twice. */
void lx_gpio_close(lx_gpio_t *gpio);

#ifdef __cplusplus
}
#endif

#endif /* LX_GPIO_H */
