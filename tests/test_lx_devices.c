/**
 * @file test_lx_devices.c
 * @brief Host tests of the Linux HAL's device modules (hal/linux) where the host allows:
 *        sysfs PWM and IIO against directory trees of plain files (which is what those sysfs
 *        interfaces look like to user space), the GPIO and SocketCAN error paths (the build
 *        host has no GPIO chip and no CAN: the VM test covers them against a real kernel),
 *        hal_init() without configuration, and the periodic loop under SCHED_OTHER.
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hal_linux.h"
#include "lx_adc.h"
#include "lx_config.h"
#include "lx_err.h"
#include "lx_can.h"
#include "lx_gpio.h"
#include "lx_pwm.h"
#include "rt_loop.h"
#include "tv_status.h"
#include "tv_test.h"

static char s_root[64];

static void write_file(const char *dir, const char *name, const char *text)
{
    char path[512];
    FILE *f;
    (void)snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "w");
    TV_CHECK(f != NULL);
    if (f != NULL) {
        (void)fputs(text, f);
        (void)fclose(f);
    }
}

/* The first number in a file (values written with pwrite() at offset 0 may leave a longer
 * old value's tail after a newline; the reader stops at the newline, as the plant does). */
static long read_number(const char *dir, const char *name)
{
    char path[512];
    char buf[64];
    FILE *f;
    long v = -1;
    (void)snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "r");
    if (f != NULL) {
        if (fgets(buf, sizeof buf, f) != NULL) {
            v = strtol(buf, NULL, 10);
        }
        (void)fclose(f);
    }
    return v;
}

static void make_dir(const char *path)
{
    TV_CHECK(mkdir(path, 0755) == 0);
}

static void make_pwm_channel(const char *chip, int n)
{
    char dir[256];
    (void)snprintf(dir, sizeof dir, "%s/pwm%d", chip, n);
    make_dir(dir);
    write_file(dir, "period", "0\n");
    write_file(dir, "duty_cycle", "0\n");
    write_file(dir, "enable", "0\n");
}

/* ---- PWM ---------------------------------------------------------------------------------- */

static void test_pwm_on_a_file_tree(void)
{
    char chip[256];
    char ch0[300];
    char ch1[300];
    char err[LX_ERR_LEN];
    lx_pwm_t pwm;
    (void)snprintf(chip, sizeof chip, "%s/pwmchip0", s_root);
    (void)snprintf(ch0, sizeof ch0, "%s/pwm0", chip);
    (void)snprintf(ch1, sizeof ch1, "%s/pwm1", chip);
    /* a chip that does not exist */
    TV_CHECK_EQ_INT(lx_pwm_open(&pwm, chip, 0u, 1u, 50000u, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "pwm.chip = '") != NULL && strstr(err, "no such directory") != NULL);
    make_dir(chip);
    write_file(chip, "export", "");
    write_file(chip, "npwm", "2\n");
    make_pwm_channel(chip, 0);
    /* channel beyond npwm */
    TV_CHECK_EQ_INT(lx_pwm_open(&pwm, chip, 0u, 2u, 50000u, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "pwm.channel_b = 2") != NULL && strstr(err, "has 2 channels (npwm)") != NULL);
    /* channel 1 not exported, and writing to this plain 'export' file does not create it */
    TV_CHECK_EQ_INT(lx_pwm_open(&pwm, chip, 0u, 1u, 50000u, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "pwm.channel_b = 1") != NULL && strstr(err, "did not appear after export") != NULL);
    TV_CHECK_EQ_INT(read_number(chip, "export"), 1); /* it did try to export channel 1 */
    make_pwm_channel(chip, 1);
    TV_CHECK_EQ_INT(lx_pwm_open(&pwm, chip, 0u, 1u, 50000u, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(read_number(ch0, "period"), 50000);
    TV_CHECK_EQ_INT(read_number(ch1, "period"), 50000);
    TV_CHECK_EQ_INT(read_number(ch0, "enable"), 1);
    TV_CHECK_EQ_INT(read_number(ch1, "enable"), 1);
    TV_CHECK_EQ_INT(read_number(ch0, "duty_cycle"), 0);
    /* sign-magnitude: positive duty on channel A, negative on B; rounding to the nearest ns */
    TV_CHECK_EQ_INT(lx_pwm_set(&pwm, 0.5f), TV_OK);
    TV_CHECK_EQ_INT(read_number(ch0, "duty_cycle"), 25000);
    TV_CHECK_EQ_INT(read_number(ch1, "duty_cycle"), 0);
    TV_CHECK_EQ_INT(lx_pwm_set(&pwm, -0.25f), TV_OK);
    TV_CHECK_EQ_INT(read_number(ch0, "duty_cycle"), 0);
    TV_CHECK_EQ_INT(read_number(ch1, "duty_cycle"), 12500);
    TV_CHECK_EQ_INT(lx_pwm_set(&pwm, 1.0f), TV_OK);
    TV_CHECK_EQ_INT(read_number(ch0, "duty_cycle"), 50000);
    /* bad duty: error and both channels at 0 (hal.h) */
    TV_CHECK_EQ_INT(lx_pwm_set(&pwm, 1.5f), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(read_number(ch0, "duty_cycle"), 0);
    TV_CHECK_EQ_INT(lx_pwm_set(&pwm, -0.5f), TV_OK);
    TV_CHECK_EQ_INT(lx_pwm_set(&pwm, (float)NAN), TV_ERR_NONFINITE);
    TV_CHECK_EQ_INT(read_number(ch1, "duty_cycle"), 0);
    /* safe state: duty 0 and disabled */
    TV_CHECK_EQ_INT(lx_pwm_set(&pwm, 0.3f), TV_OK);
    TV_CHECK_EQ_INT(lx_pwm_off(&pwm), TV_OK);
    TV_CHECK_EQ_INT(read_number(ch0, "duty_cycle"), 0);
    TV_CHECK_EQ_INT(read_number(ch0, "enable"), 0);
    TV_CHECK_EQ_INT(read_number(ch1, "enable"), 0);
    lx_pwm_close(&pwm);
    lx_pwm_close(&pwm);
    TV_CHECK_EQ_INT(lx_pwm_set(&pwm, 0.1f), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(lx_pwm_open(&pwm, chip, 1u, 1u, 50000u, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(lx_pwm_open(NULL, chip, 0u, 1u, 50000u, err, sizeof err), TV_ERR_NULL);
}

/* ---- ADC ---------------------------------------------------------------------------------- */

static void test_adc_parse_count(void)
{
    uint32_t v = 0u;
    TV_CHECK_EQ_INT(lx_adc_parse_count("2048\n", 4095u, &v), TV_OK);
    TV_CHECK_EQ_INT(v, 2048);
    TV_CHECK_EQ_INT(lx_adc_parse_count("  17 \n", 4095u, &v), TV_OK);
    TV_CHECK_EQ_INT(v, 17);
    TV_CHECK_EQ_INT(lx_adc_parse_count("4095", 4095u, &v), TV_OK);
    TV_CHECK_EQ_INT(lx_adc_parse_count("4096\n", 4095u, &v), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(lx_adc_parse_count("99999999999\n", 4095u, &v), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(lx_adc_parse_count("", 4095u, &v), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(lx_adc_parse_count("\n", 4095u, &v), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(lx_adc_parse_count("-1\n", 4095u, &v), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(lx_adc_parse_count("12a\n", 4095u, &v), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(lx_adc_parse_count("1 2\n", 4095u, &v), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(v, 4095); /* untouched by the failures */
}

static void test_adc_on_a_file_tree(void)
{
    char dev[256];
    char err[LX_ERR_LEN];
    const uint32_t ch[4] = {0u, 1u, 2u, 5u};
    uint16_t counts[4] = {0u, 0u, 0u, 0u};
    lx_adc_t adc;
    (void)snprintf(dev, sizeof dev, "%s/iio:device0", s_root);
    TV_CHECK_EQ_INT(lx_adc_open(&adc, dev, ch, 4095u, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "adc.device = '") != NULL && strstr(err, "no such directory") != NULL);
    make_dir(dev);
    write_file(dev, "in_voltage0_raw", "2048\n");
    write_file(dev, "in_voltage1_raw", "633\n");
    write_file(dev, "in_voltage2_raw", "3463\n");
    TV_CHECK_EQ_INT(lx_adc_open(&adc, dev, ch, 4095u, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "adc.channel.supply = 5") != NULL && strstr(err, "in_voltage5_raw") != NULL);
    write_file(dev, "in_voltage5_raw", "garbage\n");
    TV_CHECK_EQ_INT(lx_adc_open(&adc, dev, ch, 4095u, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "adc.channel.supply = 5") != NULL && strstr(err, "reads 'garbage', not a count") != NULL);
    write_file(dev, "in_voltage5_raw", "5000\n");
    TV_CHECK_EQ_INT(lx_adc_open(&adc, dev, ch, 4095u, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "above adc.max_counts = 4095") != NULL);
    write_file(dev, "in_voltage5_raw", "2793\n");
    TV_CHECK_EQ_INT(lx_adc_open(&adc, dev, ch, 4095u, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(lx_adc_read(&adc, counts), TV_OK);
    TV_CHECK_EQ_INT(counts[0], 2048);
    TV_CHECK_EQ_INT(counts[1], 633);
    TV_CHECK_EQ_INT(counts[2], 3463);
    TV_CHECK_EQ_INT(counts[3], 2793);
    /* every read sees the current content (the file is read again at offset 0) */
    write_file(dev, "in_voltage1_raw", "700\n");
    TV_CHECK_EQ_INT(lx_adc_read(&adc, counts), TV_OK);
    TV_CHECK_EQ_INT(counts[1], 700);
    /* run-time failures leave counts untouched */
    write_file(dev, "in_voltage2_raw", "4096\n");
    TV_CHECK_EQ_INT(lx_adc_read(&adc, counts), TV_ERR_RANGE);
    write_file(dev, "in_voltage2_raw", "x\n");
    TV_CHECK_EQ_INT(lx_adc_read(&adc, counts), TV_ERR_FORMAT);
    write_file(dev, "in_voltage2_raw", "");
    TV_CHECK_EQ_INT(lx_adc_read(&adc, counts), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(counts[2], 3463);
    lx_adc_close(&adc);
    lx_adc_close(&adc);
    TV_CHECK_EQ_INT(lx_adc_read(&adc, counts), TV_ERR_CONFIG);
}

/* ---- GPIO, CAN, hal_init: error paths the host can reach -------------------------------------- */

static void test_gpio_errors_named(void)
{
    lx_gpio_t g;
    char err[LX_ERR_LEN];
    int fault = 0;
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "no-such-chip-xyz", "t", 4u, 0, 5u, 1, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "gpio.chip = 'no-such-chip-xyz'") != NULL);
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "/dev/null", "t", 4u, 0, 5u, 1, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "gpio.chip = '/dev/null'") != NULL);
    TV_CHECK_EQ_INT(lx_gpio_open(&g, "gpiochip0", "t", 4u, 0, 4u, 1, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "both 4") != NULL);
    TV_CHECK_EQ_INT(lx_gpio_set_enable(&g, 1), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(lx_gpio_get_fault(&g, &fault), TV_ERR_CONFIG);
    lx_gpio_close(&g);
    TV_CHECK_EQ_INT(lx_gpio_open(NULL, "x", "t", 4u, 0, 5u, 1, err, sizeof err), TV_ERR_NULL);
}

static void test_can_errors_named(void)
{
    lx_can_t c;
    hal_can_frame_t f;
    char err[LX_ERR_LEN];
    memset(&f, 0, sizeof f);
    TV_CHECK_EQ_INT(lx_can_open(&c, "tvnosuch0", err, sizeof err), TV_ERR_CONFIG);
    /* without SocketCAN (this build host) or without the interface: both name the key */
    TV_CHECK(strstr(err, "can.interface = 'tvnosuch0'") != NULL);
    TV_CHECK(strstr(err, "no raw CAN sockets") != NULL || strstr(err, "no such network interface") != NULL);
    printf("  host: %s\n", err);
    TV_CHECK_EQ_INT(lx_can_open(&c, "a-name-far-too-long-for-ifnamsiz", err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "not a valid interface name") != NULL);
    TV_CHECK_EQ_INT(lx_can_open(&c, "", err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(lx_can_send(&c, &f), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(lx_can_receive(&c, &f), TV_ERR_CONFIG);
    lx_can_close(&c);
}

static void test_hal_init_reports_configuration_errors(void)
{
    static lx_config_t cfg;
    hal_adc_sample_t s;
    char text[1024];
    char err[LX_ERR_LEN];
    TV_CHECK_EQ_INT(hal_init(), TV_ERR_CONFIG);
    TV_CHECK(strstr(hal_linux_error(), "hal_linux_configure") != NULL);
    (void)snprintf(text, sizeof text,
                   "pwm.chip = %s/pwmchip0\npwm.channel_a = 0\npwm.channel_b = 1\nadc.device = %s/iio:device0\n"
                   "gpio.chip = tv-missing-chip\ngpio.bridge_enable.line = 0\ngpio.driver_fault.line = 1\n"
                   "can.interface = vcan0\n",
                   s_root, s_root);
    TV_CHECK_EQ_INT(lx_config_parse(text, "t.conf", &cfg, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(hal_linux_configure(&cfg.dev), TV_OK);
    TV_CHECK_EQ_INT(hal_init(), TV_ERR_CONFIG);
    TV_CHECK(strstr(hal_linux_error(), "gpio.chip = 'tv-missing-chip'") != NULL);
    /* nothing is open: every HAL call reports it instead of touching a device */
    TV_CHECK_EQ_INT(hal_pwm_set_duty(0.5f), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(hal_bridge_enable(1), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(hal_adc_read(&s), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(hal_linux_safe_state(), TV_OK);
    hal_linux_close();
}

/* ---- the loop ----------------------------------------------------------------------------- */

typedef struct {
    int stop_after;
    int stop_value;
    int calls;
} tick_ctx_t;

static int tick(void *vctx, const rt_loop_stats_t *st)
{
    tick_ctx_t *c = (tick_ctx_t *)vctx;
    (void)st;
    ++c->calls;
    return c->calls == c->stop_after ? c->stop_value : 0;
}

/* Under SCHED_OTHER (no privileges needed): max_ticks ends the loop, a tick's return value
 * ends it with that value, statistics are consistent, bad settings are named. */
static void test_loop_runs_and_stops(void)
{
    rt_loop_t loop;
    rt_loop_config_t c = {0, -1, 0, 1000u, 50u};
    tick_ctx_t ctx = {0, 0, 0};
    char err[LX_ERR_LEN];
    uint64_t hist_total = 0u;
    unsigned b;
    TV_CHECK_EQ_INT(rt_loop_start(&loop, &c, tick, &ctx, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(rt_loop_join(&loop), 0);
    TV_CHECK_EQ_INT(ctx.calls, 50);
    TV_CHECK_EQ_INT(loop.stats.ticks, 50);
    TV_CHECK(rt_loop_is_done(&loop));
    for (b = 0; b < RT_LOOP_HIST_BINS; ++b) {
        hist_total += loop.stats.hist[b];
    }
    TV_CHECK_EQ_INT(hist_total, 50);
    TV_CHECK(rt_loop_latency_quantile_us(&loop.stats, 1.0) <= loop.stats.latency_max_us + RT_LOOP_HIST_BIN_US);
    printf("  host SCHED_OTHER: 50 ticks, latency max %u us, overruns %llu\n", (unsigned)loop.stats.latency_max_us,
           (unsigned long long)loop.stats.overruns);

    ctx.calls = 0;
    ctx.stop_after = 5;
    ctx.stop_value = -1;
    c.max_ticks = 0u;
    TV_CHECK_EQ_INT(rt_loop_start(&loop, &c, tick, &ctx, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(rt_loop_join(&loop), -1);
    TV_CHECK_EQ_INT(loop.stats.ticks, 5);

    ctx.calls = 0;
    ctx.stop_after = -1;
    TV_CHECK_EQ_INT(rt_loop_start(&loop, &c, tick, &ctx, err, sizeof err), TV_OK);
    rt_loop_request_stop(&loop);
    TV_CHECK_EQ_INT(rt_loop_join(&loop), 0);

    c.period_us = 0u;
    TV_CHECK_EQ_INT(rt_loop_start(&loop, &c, tick, &ctx, err, sizeof err), TV_ERR_CONFIG);
    c.period_us = 1000u;
    c.cpu = 100000;
    TV_CHECK_EQ_INT(rt_loop_start(&loop, &c, tick, &ctx, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "rt.cpu = 100000") != NULL);
    c.cpu = -1;
    c.priority = 100;
    TV_CHECK_EQ_INT(rt_loop_start(&loop, &c, tick, &ctx, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "rt.priority = 100") != NULL);
    TV_CHECK_EQ_INT(rt_loop_join(&loop), TV_ERR_CONFIG);
}

static void test_latency_quantile(void)
{
    rt_loop_stats_t st;
    memset(&st, 0, sizeof st);
    st.hist[0] = 90u;  /* 0..10 us */
    st.hist[4] = 9u;   /* 40..50 us */
    st.hist[RT_LOOP_HIST_BINS - 1u] = 1u;
    st.latency_max_us = 5000u;
    TV_CHECK_EQ_INT(rt_loop_latency_quantile_us(&st, 0.5), 10);
    TV_CHECK_EQ_INT(rt_loop_latency_quantile_us(&st, 0.99), 50);
    TV_CHECK_EQ_INT(rt_loop_latency_quantile_us(&st, 1.0), 5000);
}

static void remove_tree(void)
{
    char cmd[128];
    (void)snprintf(cmd, sizeof cmd, "rm -rf '%s'", s_root);
    if (system(cmd) != 0) {
        fprintf(stderr, "could not remove %s\n", s_root);
    }
}

int main(void)
{
    (void)snprintf(s_root, sizeof s_root, "/tmp/test_lx_devices_XXXXXX");
    if (mkdtemp(s_root) == NULL) {
        perror("mkdtemp");
        return 1;
    }
    TV_TEST_RUN(test_pwm_on_a_file_tree);
    TV_TEST_RUN(test_adc_parse_count);
    TV_TEST_RUN(test_adc_on_a_file_tree);
    TV_TEST_RUN(test_gpio_errors_named);
    TV_TEST_RUN(test_can_errors_named);
    TV_TEST_RUN(test_hal_init_reports_configuration_errors);
    TV_TEST_RUN(test_loop_runs_and_stops);
    TV_TEST_RUN(test_latency_quantile);
    remove_tree();
    return tv_test_summary();
}
