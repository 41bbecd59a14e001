/**
 * @file lx_adc.h
 * @brief The four ADC channels through IIO sysfs: <device>/in_voltageN_raw, one decimal count
 *        per read (Documentation/ABI/testing/sysfs-bus-iio). Each file is opened once and read
 *        with pread() at offset 0, which makes the driver convert again on every read.
 */
#ifndef LX_ADC_H
#define LX_ADC_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** An opened set of channels. Zero-initialise, then lx_adc_open(). */
typedef struct {
    int fd[4];           /**< in_voltageN_raw of current, tps1, tps2, supply (hal.h order), -1 when closed */
    uint32_t max_counts; /**< largest valid raw value */
    int is_open;         /**< 1 between a successful open and close */
} lx_adc_t;

/**
 * Open the four channel files and read each once (values checked).
 * @param device     IIO device directory (config key adc.device)
 * @param channel    N of in_voltageN_raw per channel (adc.channel.current, .tps1, .tps2, .supply)
 * @param max_counts largest valid raw value (adc.max_counts)
 * @param err        receives a message naming the config key and value on error
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (device or channel file missing or unreadable, or
 *         its first reading not a count within range). On error nothing stays open.
 */
int lx_adc_open(lx_adc_t *adc, const char *device, const uint32_t channel[4], uint32_t max_counts, char *err,
                size_t err_len);

/**
 * Read the four channels.
 * @param counts receives current, tps1, tps2, supply (hal.h order)
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG when not open; TV_ERR_IO (read failed);
 *         TV_ERR_FORMAT (not a decimal count); TV_ERR_RANGE (count > max_counts).
 *         On error counts is not written.
 */
int lx_adc_read(lx_adc_t *adc, uint16_t counts[4]);

/** Close the files. Safe to call twice. */
void lx_adc_close(lx_adc_t *adc);

/**
 * Parse one sysfs count: optional leading blanks, decimal digits, optional trailing blanks /
 * newline, nothing else.
 * @return TV_OK; TV_ERR_FORMAT; TV_ERR_RANGE (above max).
 */
int lx_adc_parse_count(const char *text, uint32_t max, uint32_t *value);

#ifdef __cplusplus
}
#endif

#endif /* LX_ADC_H */
