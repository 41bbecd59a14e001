/**
 * @file lx_pwm.c
 * @brief H-bridge PWM through the sysfs PWM class (see lx_pwm.h).
 */
#define _POSIX_C_SOURCE 200809L

#include "lx_pwm.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "lx_err.h"
#include "tv_status.h"

/* How long to wait for pwmN/ to appear after writing to export [ms] (udev may chmod it). */
#define EXPORT_WAIT_MS 500

static const char *const s_ch_key[2] = {"pwm.channel_a", "pwm.channel_b"};

static int is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* Write "value\n" at offset 0. 0 or -1 (errno set). */
static int write_u32(int fd, uint32_t value)
{
    char buf[16];
    const int n = snprintf(buf, sizeof buf, "%u\n", (unsigned)value);
    const ssize_t w = pwrite(fd, buf, (size_t)n, 0);
    if (w != (ssize_t)n) {
        if (w >= 0) {
            errno = EIO;
        }
        return -1;
    }
    return 0;
}

/* Write a value to a file by path. 0 or -1 (errno set). */
static int write_path_u32(const char *path, uint32_t value)
{
    const int fd = open(path, O_WRONLY | O_CLOEXEC);
    int rc;
    int saved;
    if (fd < 0) {
        return -1;
    }
    rc = write_u32(fd, value);
    saved = errno;
    (void)close(fd);
    errno = saved;
    return rc;
}

static void sleep_ms(long ms)
{
    struct timespec ts;
    ts.tv_sec = ms / 1000;
    ts.tv_nsec = (ms % 1000) * 1000000L;
    (void)nanosleep(&ts, NULL);
}

static void close_fds(lx_pwm_t *pwm)
{
    int k;
    for (k = 0; k < 2; ++k) {
        if (pwm->fd_duty[k] >= 0) {
            (void)close(pwm->fd_duty[k]);
        }
        if (pwm->fd_enable[k] >= 0) {
            (void)close(pwm->fd_enable[k]);
        }
        pwm->fd_duty[k] = -1;
        pwm->fd_enable[k] = -1;
    }
    pwm->is_open = 0;
}

/* Export (if needed) and set up one channel; opens its duty_cycle and enable files. */
static int open_channel(lx_pwm_t *pwm, int k, const char *chip, uint32_t ch, uint32_t period_ns, char *err,
                        size_t err_len)
{
    char dir[512];
    char path[600];
    (void)snprintf(dir, sizeof dir, "%s/pwm%u", chip, (unsigned)ch);
    if (!is_dir(dir)) {
        int waited = 0;
        (void)snprintf(path, sizeof path, "%s/export", chip);
        if (write_path_u32(path, ch) != 0 && errno != EBUSY) {
            lx_err_set(err, err_len, "%s = %u: cannot export it through '%s': %s", s_ch_key[k], (unsigned)ch, path,
                    strerror(errno));
            return TV_ERR_CONFIG;
        }
        while (!is_dir(dir) && waited < EXPORT_WAIT_MS) {
            sleep_ms(1);
            ++waited;
        }
        if (!is_dir(dir)) {
            lx_err_set(err, err_len, "%s = %u: '%s' did not appear after export", s_ch_key[k], (unsigned)ch, dir);
            return TV_ERR_CONFIG;
        }
    }
    (void)snprintf(path, sizeof path, "%s/duty_cycle", dir);
    pwm->fd_duty[k] = open(path, O_WRONLY | O_CLOEXEC);
    if (pwm->fd_duty[k] < 0) {
        lx_err_set(err, err_len, "%s = %u: cannot open '%s': %s", s_ch_key[k], (unsigned)ch, path, strerror(errno));
        return TV_ERR_CONFIG;
    }
    (void)snprintf(path, sizeof path, "%s/enable", dir);
    pwm->fd_enable[k] = open(path, O_WRONLY | O_CLOEXEC);
    if (pwm->fd_enable[k] < 0) {
        lx_err_set(err, err_len, "%s = %u: cannot open '%s': %s", s_ch_key[k], (unsigned)ch, path, strerror(errno));
        return TV_ERR_CONFIG;
    }
    /* duty 0 first (a shorter new period must not be below the old duty), then the period */
    if (write_u32(pwm->fd_duty[k], 0u) != 0) {
        lx_err_set(err, err_len, "%s = %u: writing 0 to '%s/duty_cycle': %s", s_ch_key[k], (unsigned)ch, dir,
                strerror(errno));
        return TV_ERR_IO;
    }
    (void)snprintf(path, sizeof path, "%s/period", dir);
    if (write_path_u32(path, period_ns) != 0) {
        lx_err_set(err, err_len, "pwm.period_ns = %u: refused by '%s': %s", (unsigned)period_ns, path, strerror(errno));
        return TV_ERR_CONFIG;
    }
    if (write_u32(pwm->fd_enable[k], 1u) != 0) {
        lx_err_set(err, err_len, "%s = %u: writing 1 to '%s/enable': %s", s_ch_key[k], (unsigned)ch, dir,
                strerror(errno));
        return TV_ERR_IO;
    }
    pwm->duty_ns[k] = 0u;
    return TV_OK;
}

int lx_pwm_open(lx_pwm_t *pwm, const char *chip, uint32_t ch_a, uint32_t ch_b, uint32_t period_ns, char *err,
                size_t err_len)
{
    char path[512];
    FILE *f;
    const uint32_t ch[2] = {ch_a, ch_b};
    int k;
    if (pwm == NULL || chip == NULL) {
        lx_err_set(err, err_len, "lx_pwm_open: NULL argument");
        return TV_ERR_NULL;
    }
    memset(pwm, 0, sizeof *pwm);
    pwm->fd_duty[0] = pwm->fd_duty[1] = pwm->fd_enable[0] = pwm->fd_enable[1] = -1;
    if (!is_dir(chip)) {
        lx_err_set(err, err_len, "pwm.chip = '%s': %s", chip, errno == ENOENT ? "no such directory" : "not a directory");
        return TV_ERR_CONFIG;
    }
    if (ch_a == ch_b) {
        lx_err_set(err, err_len, "pwm.channel_a and pwm.channel_b are both %u", (unsigned)ch_a);
        return TV_ERR_CONFIG;
    }
    if (period_ns == 0u) {
        lx_err_set(err, err_len, "pwm.period_ns = 0: must be positive");
        return TV_ERR_CONFIG;
    }
    (void)snprintf(path, sizeof path, "%s/npwm", chip);
    f = fopen(path, "r");
    if (f != NULL) {
        char line[32];
        char *end = NULL;
        unsigned long npwm = 0u;
        int got = 0;
        if (fgets(line, sizeof line, f) != NULL) {
            npwm = strtoul(line, &end, 10);
            got = end != line;
        }
        (void)fclose(f);
        for (k = 0; k < 2 && got; ++k) {
            if (ch[k] >= npwm) {
                lx_err_set(err, err_len, "%s = %u: '%s' has %lu channels (npwm)", s_ch_key[k], (unsigned)ch[k], chip, npwm);
                return TV_ERR_CONFIG;
            }
        }
    }
    pwm->period_ns = period_ns;
    for (k = 0; k < 2; ++k) {
        const int rc = open_channel(pwm, k, chip, ch[k], period_ns, err, err_len);
        if (rc != TV_OK) {
            pwm->is_open = 1;
            lx_pwm_close(pwm);
            return rc;
        }
    }
    pwm->is_open = 1;
    return TV_OK;
}

static int set_ns(lx_pwm_t *pwm, int k, uint32_t ns, int force)
{
    if (!force && pwm->duty_ns[k] == ns) {
        return TV_OK;
    }
    if (write_u32(pwm->fd_duty[k], ns) != 0) {
        return TV_ERR_IO;
    }
    pwm->duty_ns[k] = ns;
    return TV_OK;
}

int lx_pwm_set(lx_pwm_t *pwm, float duty)
{
    uint32_t ns[2] = {0u, 0u};
    int first;
    int rc;
    int bad = TV_OK;
    if (pwm == NULL) {
        return TV_ERR_NULL;
    }
    if (!pwm->is_open) {
        return TV_ERR_CONFIG;
    }
    if (!(duty == duty) || duty - duty != 0.0f) {
        bad = TV_ERR_NONFINITE;
    } else if (duty > 1.0f || duty < -1.0f) {
        bad = TV_ERR_RANGE;
    } else {
        const float mag = duty < 0.0f ? -duty : duty;
        const uint32_t v = (uint32_t)(mag * (float)pwm->period_ns + 0.5f);
        ns[duty < 0.0f ? 1 : 0] = v > pwm->period_ns ? pwm->period_ns : v;
    }
    /* the channel that goes to (or stays at) zero first */
    first = ns[0] == 0u ? 0 : 1;
    rc = set_ns(pwm, first, ns[first], 0);
    if (rc == TV_OK) {
        rc = set_ns(pwm, 1 - first, ns[1 - first], 0);
    }
    return bad != TV_OK ? bad : rc;
}

int lx_pwm_off(lx_pwm_t *pwm)
{
    int rc = TV_OK;
    int k;
    if (pwm == NULL) {
        return TV_ERR_NULL;
    }
    if (!pwm->is_open) {
        return TV_ERR_CONFIG;
    }
    for (k = 0; k < 2; ++k) {
        if (pwm->fd_duty[k] >= 0 && set_ns(pwm, k, 0u, 1) != TV_OK) {
            rc = TV_ERR_IO;
        }
    }
    for (k = 0; k < 2; ++k) {
        if (pwm->fd_enable[k] >= 0 && write_u32(pwm->fd_enable[k], 0u) != 0) {
            rc = TV_ERR_IO;
        }
    }
    return rc;
}

void lx_pwm_close(lx_pwm_t *pwm)
{
    if (pwm == NULL || !pwm->is_open) {
        return;
    }
    (void)lx_pwm_off(pwm);
    close_fds(pwm);
}
