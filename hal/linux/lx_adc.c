/**
 * @file lx_adc.c
 * @brief ADC channels through IIO sysfs (see lx_adc.h).
 */
#define _POSIX_C_SOURCE 200809L

#include "lx_adc.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "lx_err.h"
#include "tv_status.h"

static const char *const s_key[4] = {"adc.channel.current", "adc.channel.tps1", "adc.channel.tps2",
                                     "adc.channel.supply"};

int lx_adc_parse_count(const char *text, uint32_t max, uint32_t *value)
{
    const char *p = text;
    uint64_t v = 0u;
    int digits = 0;
    if (text == NULL || value == NULL) {
        return TV_ERR_NULL;
    }
    while (*p == ' ' || *p == '\t') {
        ++p;
    }
    while (*p >= '0' && *p <= '9') {
        v = v * 10u + (uint64_t)(*p - '0');
        if (v > 0xFFFFFFFFu) {
            return TV_ERR_RANGE;
        }
        ++p;
        ++digits;
    }
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') {
        ++p;
    }
    if (digits == 0 || *p != '\0') {
        return TV_ERR_FORMAT;
    }
    if (v > max) {
        return TV_ERR_RANGE;
    }
    *value = (uint32_t)v;
    return TV_OK;
}

/* Read one channel. TV_OK, TV_ERR_IO, TV_ERR_FORMAT or TV_ERR_RANGE; text receives what was read. */
static int read_one(int fd, uint32_t max, uint32_t *value, char text[32])
{
    const ssize_t n = pread(fd, text, 31u, 0);
    if (n < 0) {
        text[0] = '\0';
        return TV_ERR_IO;
    }
    text[n] = '\0';
    return lx_adc_parse_count(text, max, value);
}

static void close_fds(lx_adc_t *adc)
{
    int k;
    for (k = 0; k < 4; ++k) {
        if (adc->fd[k] >= 0) {
            (void)close(adc->fd[k]);
        }
        adc->fd[k] = -1;
    }
    adc->is_open = 0;
}

int lx_adc_open(lx_adc_t *adc, const char *device, const uint32_t channel[4], uint32_t max_counts, char *err,
                size_t err_len)
{
    struct stat st;
    int k;
    if (adc == NULL || device == NULL || channel == NULL) {
        lx_err_set(err, err_len, "lx_adc_open: NULL argument");
        return TV_ERR_NULL;
    }
    memset(adc, 0, sizeof *adc);
    adc->fd[0] = adc->fd[1] = adc->fd[2] = adc->fd[3] = -1;
    if (stat(device, &st) != 0 || !S_ISDIR(st.st_mode)) {
        lx_err_set(err, err_len, "adc.device = '%s': %s", device, errno == ENOENT ? "no such directory" : "not a directory");
        return TV_ERR_CONFIG;
    }
    adc->max_counts = max_counts;
    for (k = 0; k < 4; ++k) {
        char path[512];
        char text[32];
        uint32_t v = 0u;
        int rc;
        (void)snprintf(path, sizeof path, "%s/in_voltage%u_raw", device, (unsigned)channel[k]);
        adc->fd[k] = open(path, O_RDONLY | O_CLOEXEC);
        if (adc->fd[k] < 0) {
            lx_err_set(err, err_len, "%s = %u: cannot open '%s': %s", s_key[k], (unsigned)channel[k], path, strerror(errno));
            close_fds(adc);
            return TV_ERR_CONFIG;
        }
        rc = read_one(adc->fd[k], max_counts, &v, text);
        if (rc != TV_OK) {
            const size_t tl = strlen(text);
            if (tl > 0u && text[tl - 1u] == '\n') {
                text[tl - 1u] = '\0';
            }
            if (rc == TV_ERR_IO) {
                lx_err_set(err, err_len, "%s = %u: reading '%s': %s", s_key[k], (unsigned)channel[k], path, strerror(errno));
            } else if (rc == TV_ERR_RANGE) {
                lx_err_set(err, err_len, "%s = %u: '%s' reads '%s', above adc.max_counts = %u", s_key[k],
                        (unsigned)channel[k], path, text, (unsigned)max_counts);
            } else {
                lx_err_set(err, err_len, "%s = %u: '%s' reads '%s', not a count", s_key[k], (unsigned)channel[k], path, text);
            }
            close_fds(adc);
            return TV_ERR_CONFIG;
        }
    }
    adc->is_open = 1;
    return TV_OK;
}

int lx_adc_read(lx_adc_t *adc, uint16_t counts[4])
{
    uint16_t c[4];
    int k;
    if (adc == NULL || counts == NULL) {
        return TV_ERR_NULL;
    }
    if (!adc->is_open) {
        return TV_ERR_CONFIG;
    }
    for (k = 0; k < 4; ++k) {
        char text[32];
        uint32_t v = 0u;
        const int rc = read_one(adc->fd[k], adc->max_counts, &v, text);
        if (rc != TV_OK) {
            return rc;
        }
        c[k] = (uint16_t)v;
    }
    memcpy(counts, c, sizeof c);
    return TV_OK;
}

void lx_adc_close(lx_adc_t *adc)
{
    if (adc == NULL || !adc->is_open) {
        return;
    }
    close_fds(adc);
}
