/**
 * @file lx_gpio.c
 * @brief Bridge enable and driver fault through libgpiod 1.6 (see lx_gpio.h).
 */
#define _POSIX_C_SOURCE 200809L

#include "lx_gpio.h"

#include <errno.h>
#include <gpiod.h>
#include <stdio.h>
#include <string.h>

#include "lx_err.h"
#include "tv_status.h"

/* Get and request one line; output (driven inactive) or input. */
static int request_line(lx_gpio_t *gpio, const char *key, uint32_t offset, int active_low, int output,
                        const char *consumer, struct gpiod_line **out, char *err, size_t err_len)
{
    const unsigned n_lines = gpiod_chip_num_lines(gpio->chip);
    const int flags = active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
    struct gpiod_line *line;
    int rc;
    if (offset >= n_lines) {
        lx_err_set(err, err_len, "%s = %u: chip '%s' (%s) has %u lines", key, (unsigned)offset,
                gpiod_chip_name(gpio->chip), gpiod_chip_label(gpio->chip), n_lines);
        return TV_ERR_CONFIG;
    }
    line = gpiod_chip_get_line(gpio->chip, offset);
    if (line == NULL) {
        lx_err_set(err, err_len, "%s = %u: cannot get the line: %s", key, (unsigned)offset, strerror(errno));
        return TV_ERR_CONFIG;
    }
    if (gpiod_line_is_used(line)) {
        const char *who = gpiod_line_consumer(line);
        lx_err_set(err, err_len, "%s = %u: line busy on chip '%s', used by '%s'", key, (unsigned)offset,
                gpiod_chip_name(gpio->chip), who != NULL ? who : "the kernel");
        return TV_ERR_CONFIG;
    }
    rc = output ? gpiod_line_request_output_flags(line, consumer, flags, 0)
                : gpiod_line_request_input_flags(line, consumer, flags);
    if (rc != 0) {
        lx_err_set(err, err_len, "%s = %u: request as %s on chip '%s' refused: %s", key, (unsigned)offset,
                output ? "output" : "input", gpiod_chip_name(gpio->chip), strerror(errno));
        return TV_ERR_CONFIG;
    }
    *out = line;
    return TV_OK;
}

int lx_gpio_open(lx_gpio_t *gpio, const char *chip, const char *consumer, uint32_t enable_line, int enable_active_low,
                 uint32_t fault_line, int fault_active_low, char *err, size_t err_len)
{
    int rc;
    if (gpio == NULL || chip == NULL || consumer == NULL) {
        lx_err_set(err, err_len, "lx_gpio_open: NULL argument");
        return TV_ERR_NULL;
    }
    memset(gpio, 0, sizeof *gpio);
    if (enable_line == fault_line) {
        lx_err_set(err, err_len, "gpio.bridge_enable.line and gpio.driver_fault.line are both %u", (unsigned)enable_line);
        return TV_ERR_CONFIG;
    }
    errno = 0;
    gpio->chip = gpiod_chip_open_lookup(chip);
    if (gpio->chip == NULL) {
        lx_err_set(err, err_len, "gpio.chip = '%s': no GPIO chip with that name, number, label or path (%s)", chip,
                errno != 0 ? strerror(errno) : "not found");
        return TV_ERR_CONFIG;
    }
    rc = request_line(gpio, "gpio.bridge_enable.line", enable_line, enable_active_low, 1, consumer, &gpio->enable, err,
                      err_len);
    if (rc == TV_OK) {
        rc = request_line(gpio, "gpio.driver_fault.line", fault_line, fault_active_low, 0, consumer, &gpio->fault, err,
                          err_len);
    }
    if (rc != TV_OK) {
        lx_gpio_close(gpio);
    }
    return rc;
}

int lx_gpio_set_enable(lx_gpio_t *gpio, int enable)
{
    int rc = TV_OK;
    if (gpio == NULL) {
        return TV_ERR_NULL;
    }
    if (gpio->enable == NULL) {
        return TV_ERR_CONFIG;
    }
    if (enable != 0 && enable != 1) {
        enable = 0;
        rc = TV_ERR_RANGE;
    }
    if (gpiod_line_set_value(gpio->enable, enable) != 0) {
        return TV_ERR_IO;
    }
    return rc;
}

int lx_gpio_get_fault(lx_gpio_t *gpio, int *fault_active)
{
    int v;
    if (gpio == NULL || fault_active == NULL) {
        return TV_ERR_NULL;
    }
    if (gpio->fault == NULL) {
        return TV_ERR_CONFIG;
    }
    v = gpiod_line_get_value(gpio->fault);
    if (v < 0) {
        return TV_ERR_IO;
    }
    *fault_active = v != 0;
    return TV_OK;
}

void lx_gpio_close(lx_gpio_t *gpio)
{
    if (gpio == NULL) {
        return;
    }
    if (gpio->enable != NULL) {
        (void)gpiod_line_set_value(gpio->enable, 0);
        gpiod_line_release(gpio->enable);
        gpio->enable = NULL;
    }
    if (gpio->fault != NULL) {
        gpiod_line_release(gpio->fault);
        gpio->fault = NULL;
    }
    if (gpio->chip != NULL) {
        gpiod_chip_close(gpio->chip);
        gpio->chip = NULL;
    }
}
