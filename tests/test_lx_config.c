/**
 * @file test_lx_config.c
 * @brief Tests of the Linux controller's configuration parser (firmware/linux_rt/lx_config.h): the
 *        example file parses to the documented defaults, and every kind of bad input is refused
 *        with a message that names the key and the value (what an operator needs to fix it).
 *
 *   test_lx_config <path of firmware/linux_rt/throttle_linux.conf>
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "lx_config.h"
#include "tv_status.h"
#include "params.h"
#include "tv_param_table.h"
#include "tv_test.h"

static const char *s_example_path;

/* The required keys with valid values; tests append or replace lines. */
static const char s_minimal[] = "pwm.chip = /sys/class/pwm/pwmchip0\n"
                                "pwm.channel_a = 0\n"
                                "pwm.channel_b = 1\n"
                                "adc.device = /sys/bus/iio/devices/iio:device0\n"
                                "gpio.chip = gpiochip0\n"
                                "gpio.bridge_enable.line = 4\n"
                                "gpio.driver_fault.line = 5\n"
                                "can.interface = can0\n";

/* Parse minimal + extra; return the status, message in err. */
static int parse_with(const char *extra, lx_config_t *cfg, char *err, size_t n)
{
    char text[4096];
    (void)snprintf(text, sizeof text, "%s%s", s_minimal, extra);
    return lx_config_parse(text, "t.conf", cfg, err, n);
}

/* status and every fragment of the message */
static void expect_error(const char *extra, int status, const char *frag1, const char *frag2)
{
    static lx_config_t cfg;
    char err[LX_ERR_LEN];
    const int rc = parse_with(extra, &cfg, err, sizeof err);
    TV_CHECK_EQ_INT(rc, status);
    TV_CHECK(strstr(err, frag1) != NULL);
    TV_CHECK(frag2 == NULL || strstr(err, frag2) != NULL);
    if (rc != status || strstr(err, frag1) == NULL || (frag2 != NULL && strstr(err, frag2) == NULL)) {
        fprintf(stderr, "  input %s -> '%s'\n", extra, err);
    }
}

/* The example configuration lists every key; it parses, and its calibration is the
 * application's default calibration (to the 10 significant digits written in the file). */
static void test_example_file_parses_to_defaults(void)
{
    static lx_config_t cfg;
    static lx_config_t def;
    char err[LX_ERR_LEN];
    TV_CHECK_EQ_INT(lx_config_load(s_example_path, &cfg, err, sizeof err), TV_OK);
    if (err[0] != '\0') {
        fprintf(stderr, "  %s\n", err);
    }
    lx_config_default(&def);
    TV_CHECK(strcmp(cfg.dev.pwm_chip, "/sys/class/pwm/pwmchip0") == 0);
    TV_CHECK_EQ_INT(cfg.dev.pwm_channel_b, 1);
    TV_CHECK(strcmp(cfg.dev.adc_device, "/sys/bus/iio/devices/iio:device0") == 0);
    TV_CHECK(strcmp(cfg.dev.gpio_chip, "gpiochip0") == 0);
    TV_CHECK_EQ_INT(cfg.dev.gpio_fault_active_low, 1);
    TV_CHECK(strcmp(cfg.dev.can_interface, "can0") == 0);
    TV_CHECK_EQ_INT(cfg.rt_priority, def.rt_priority);
    TV_CHECK_EQ_INT(cfg.dev.pwm_period_ns, def.dev.pwm_period_ns);
    TV_CHECK_EQ_INT(cfg.can.cmd_timeout_ms, def.can.cmd_timeout_ms);
    TV_CHECK_EQ_INT(cfg.can.period_ms[CAN_PROTO_TX_LOOP], 100);
    TV_CHECK_EQ_INT(cfg.can.period_ms[CAN_PROTO_TX_TIME], 10);
    TV_CHECK_EQ_INT(cfg.can.period_ms[CAN_PROTO_TX_HEALTH_1], 100);
    TV_CHECK_EQ_INT(cfg.can.period_ms[CAN_PROTO_TX_DIAG_FREEZE], 100);
    TV_CHECK_EQ_INT(cfg.can.period_ms[CAN_PROTO_TX_HEALTH_5], 1000);
    TV_CHECK_EQ_INT(cfg.can.period_ms[CAN_PROTO_TX_HEALTH_5], def.can.period_ms[CAN_PROTO_TX_HEALTH_5]);
    TV_CHECK_EQ_INT(cfg.app_mode, APP_MODE_OFF);
    TV_CHECK(strcmp(cfg.app_stops_file, "/var/lib/throttle_linux/stops.params") == 0);
    TV_CHECK_NEAR(cfg.calib_current_offset_counts, def.calib_current_offset_counts, 1e-9);
    TV_CHECK_NEAR(cfg.calib_current_A_per_count, def.calib_current_A_per_count, 1e-12);
    TV_CHECK_NEAR(cfg.calib_tps1_counts_at_zero, def.calib_tps1_counts_at_zero, 1e-6);
    TV_CHECK_NEAR(cfg.calib_tps1_rad_per_count, def.calib_tps1_rad_per_count, 1e-12);
    TV_CHECK_NEAR(cfg.calib_tps2_counts_at_zero, def.calib_tps2_counts_at_zero, 1e-6);
    TV_CHECK_NEAR(cfg.calib_tps2_rad_per_count, def.calib_tps2_rad_per_count, 1e-12);
    TV_CHECK_NEAR(cfg.calib_supply_V_per_count, def.calib_supply_V_per_count, 1e-12);
}

/* Values of every type are stored where they belong; comments, blanks, quotes, hex. */
static void test_values_stored(void)
{
    static lx_config_t cfg;
    char err[LX_ERR_LEN];
    app_config_t app;
    const char extra[] = "# a comment\n"
                         "\n"
                         "   rt.priority = 0   # SCHED_OTHER\n"
                         "rt.cpu=-1\n"
                         "rt.lock_memory = no\n"
                         "pwm.period_ns = 010000\n" /* decimal: ten thousand (octal would be 4096) */
                         "gpio.consumer = \"tv bench\"\n"
                         "can.period_ms.meas = 0\n"
                         "can.period_ms.health_5 = 500\n"
                         "can.max_counter_delta = 1\n"
                         "app.mode = position\n"
                         "app.target_rad = -0.05\n"
                         "calib.tps1_rad_per_count = 5e-4\r\n";
    TV_CHECK_EQ_INT(parse_with(extra, &cfg, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(cfg.rt_priority, 0);
    TV_CHECK_EQ_INT(cfg.rt_cpu, -1);
    TV_CHECK_EQ_INT(cfg.rt_lock_memory, 0);
    TV_CHECK_EQ_INT(cfg.dev.pwm_period_ns, 10000);
    TV_CHECK(strcmp(cfg.dev.gpio_consumer, "tv bench") == 0);
    TV_CHECK_EQ_INT(cfg.can.period_ms[CAN_PROTO_TX_MEAS], 0);
    TV_CHECK_EQ_INT(cfg.can.period_ms[CAN_PROTO_TX_HEALTH_5], 500);
    TV_CHECK_EQ_INT(cfg.can.max_counter_delta, 1);
    TV_CHECK_EQ_INT(cfg.app_mode, APP_MODE_POSITION);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK_EQ_INT(app.control.mode, APP_MODE_POSITION);
    TV_CHECK_NEAR(app.control.target_rad, -0.05, 1e-6);
    TV_CHECK_NEAR(app.calib.tps1_rad_per_count, 5e-4, 1e-9);
    /* the identification excitation by name (README "Identification") */
    TV_CHECK_EQ_INT(parse_with("app.mode = ident\n", &cfg, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(cfg.app_mode, APP_MODE_IDENT);
}

/* Syntax errors: the message names the file, the line and what is wrong. */
static void test_syntax_errors_named(void)
{
    expect_error("bogus.key = 1\n", TV_ERR_FORMAT, "t.conf:9:", "unknown key 'bogus.key'");
    /* numbers are decimal: 0x50 is refused (it was read as 80), 010 is ten (it was octal 8) */
    expect_error("rt.cpu = 0x50\n", TV_ERR_FORMAT, "t.conf:9:", "rt.cpu");
    expect_error("app.freq_Hz = 0x1p3\n", TV_ERR_FORMAT, "t.conf:9:", "not a decimal number");
    expect_error("pwm.chip = /x\n", TV_ERR_FORMAT, "t.conf:9:", "key 'pwm.chip' given twice");
    expect_error("rt.priority 80\n", TV_ERR_FORMAT, "t.conf:9:", "expected 'key = value'");
    expect_error("gpio.consumer = \"open\n", TV_ERR_FORMAT, "gpio.consumer", "unterminated quote");
    expect_error("gpio.consumer =\n", TV_ERR_FORMAT, "gpio.consumer = ''", "empty");
    {
        char long_line[1200];
        memset(long_line, 'x', sizeof long_line - 2u);
        long_line[sizeof long_line - 2u] = '\n';
        long_line[sizeof long_line - 1u] = '\0';
        expect_error(long_line, TV_ERR_FORMAT, "t.conf:9:", "line longer than");
    }
}

/* Bad values: the message names the key and the value, and the range where there is one. */
static void test_bad_values_named(void)
{
    expect_error("rt.priority = 100\n", TV_ERR_RANGE, "rt.priority = '100'", "out of range [0, 99]");
    expect_error("rt.priority = high\n", TV_ERR_FORMAT, "rt.priority = 'high'", "not an integer");
    expect_error("rt.priority = 8.5\n", TV_ERR_FORMAT, "rt.priority = '8.5'", "not an integer");
    expect_error("rt.cpu = -2\n", TV_ERR_RANGE, "rt.cpu = '-2'", "out of range");
    expect_error("rt.lock_memory = maybe\n", TV_ERR_FORMAT, "rt.lock_memory = 'maybe'", "not a boolean");
    expect_error("rt.max_io_errors = 0\n", TV_ERR_RANGE, "rt.max_io_errors = '0'", "[1, 1000]");
    expect_error("pwm.period_ns = 999\n", TV_ERR_RANGE, "pwm.period_ns = '999'", "out of range");
    expect_error("pwm.period_ns = 99999999999999999999999\n", TV_ERR_RANGE, "pwm.period_ns", "out of range");
    expect_error("adc.channel.tps1 = -1\n", TV_ERR_RANGE, "adc.channel.tps1 = '-1'", "out of range");
    expect_error("adc.max_counts = 65536\n", TV_ERR_RANGE, "adc.max_counts = '65536'", "out of range");
    expect_error("can.cmd_timeout_ms = 60001\n", TV_ERR_RANGE, "can.cmd_timeout_ms = '60001'", "out of range");
    expect_error("can.max_counter_delta = 15\n", TV_ERR_RANGE, "can.max_counter_delta = '15'", "[1, 14]");
    expect_error("can.period_ms.status = 70000\n", TV_ERR_RANGE, "can.period_ms.status = '70000'", NULL);
    expect_error("app.mode = fast\n", TV_ERR_FORMAT, "app.mode = 'fast'", "off, sine, steps, chirp, position");
    expect_error("app.amplitude_V = nan\n", TV_ERR_RANGE, "app.amplitude_V = 'nan'", "not a finite number");
    expect_error("app.amplitude_V = inf\n", TV_ERR_RANGE, "app.amplitude_V = 'inf'", "not a finite number");
    expect_error("app.amplitude_V = 25\n", TV_ERR_RANGE, "app.amplitude_V = '25'", "[0, 24]");
    expect_error("app.freq_Hz = 5Hz\n", TV_ERR_FORMAT, "app.freq_Hz = '5Hz'", "not a number");
    expect_error("app.duty_limit = 0\n", TV_ERR_RANGE, "app.duty_limit = '0'", "out of range");
    expect_error("calib.tps2_rad_per_count = 0.0004\n", TV_ERR_RANGE, "calib.tps2_rad_per_count", "out of range");
    {
        char line[400];
        char path[300];
        memset(path, 'a', sizeof path - 1u);
        path[sizeof path - 1u] = '\0';
        (void)snprintf(line, sizeof line, "adc.device = %s\n", path);
        /* replaces nothing: a second adc.device is a duplicate; test the length on its own */
        {
            char text[1000];
            static lx_config_t cfg;
            char err[LX_ERR_LEN];
            (void)snprintf(text, sizeof text, "%s", line);
            TV_CHECK_EQ_INT(lx_config_parse(text, "t.conf", &cfg, err, sizeof err), TV_ERR_RANGE);
            TV_CHECK(strstr(err, "adc.device") != NULL && strstr(err, "too long") != NULL);
        }
    }
    expect_error("", TV_OK, "", NULL);
}

/* Each required key, left out, is named. */
static void test_missing_required_keys_named(void)
{
    static const char *const req[] = {"pwm.chip", "pwm.channel_a", "pwm.channel_b", "adc.device",
                                      "gpio.chip", "gpio.bridge_enable.line", "gpio.driver_fault.line",
                                      "can.interface"};
    size_t i;
    for (i = 0; i < sizeof req / sizeof req[0]; ++i) {
        char text[2048];
        char want[128];
        char err[LX_ERR_LEN];
        static lx_config_t cfg;
        const char *src = s_minimal;
        char *out = text;
        /* copy the minimal text without the line of this key */
        while (*src != '\0') {
            const char *nl = strchr(src, '\n');
            const size_t len = (size_t)(nl - src) + 1u;
            if (strncmp(src, req[i], strlen(req[i])) != 0 || src[strlen(req[i])] != ' ') {
                memcpy(out, src, len);
                out += len;
            }
            src += len;
        }
        *out = '\0';
        (void)snprintf(want, sizeof want, "missing required key '%s'", req[i]);
        TV_CHECK_EQ_INT(lx_config_parse(text, "t.conf", &cfg, err, sizeof err), TV_ERR_CONFIG);
        TV_CHECK(strstr(err, want) != NULL);
    }
}

/* Keys that contradict each other are named together. */
static void test_conflicts_named(void)
{
    static lx_config_t cfg;
    char err[LX_ERR_LEN];
    char text[2048];
    (void)snprintf(text, sizeof text, "%s", s_minimal);
    {
        char *p = strstr(text, "pwm.channel_b = 1");
        p[16] = '0';
    }
    TV_CHECK_EQ_INT(lx_config_parse(text, "t.conf", &cfg, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "pwm.channel_a and pwm.channel_b are both 0") != NULL);
    expect_error("adc.channel.supply = 1\n", TV_ERR_CONFIG, "adc.channel.tps1 and adc.channel.supply are both 1",
                 NULL);
    (void)snprintf(text, sizeof text, "%s", s_minimal);
    {
        char *p = strstr(text, "gpio.driver_fault.line = 5");
        p[25] = '4';
    }
    TV_CHECK_EQ_INT(lx_config_parse(text, "t.conf", &cfg, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "gpio.bridge_enable.line and gpio.driver_fault.line are both 4") != NULL);
}

/* A file that cannot be read, or is not text, is named. */
static void test_file_errors_named(void)
{
    static lx_config_t cfg;
    char err[LX_ERR_LEN];
    char path[] = "/tmp/test_lx_config_XXXXXX";
    FILE *f;
    TV_CHECK_EQ_INT(lx_config_load("/nonexistent/throttle.conf", &cfg, err, sizeof err), TV_ERR_IO);
    TV_CHECK(strstr(err, "/nonexistent/throttle.conf: cannot open") != NULL);
    TV_CHECK_EQ_INT(lx_config_parse(NULL, "x", &cfg, err, sizeof err), TV_ERR_NULL);
    f = fopen(path, "wb");
    TV_CHECK(f != NULL);
    if (f != NULL) {
        static const char bin[] = "pwm.chip = a\0b\n";
        (void)fwrite(bin, 1u, sizeof bin, f);
        (void)fclose(f);
        TV_CHECK_EQ_INT(lx_config_load(path, &cfg, err, sizeof err), TV_ERR_FORMAT);
        TV_CHECK(strstr(err, "NUL byte") != NULL);
        (void)remove(path);
    }
}

/* One range per quantity: for every parameter of the table that the controller's configuration
 * also sets, the controller and the host parameter files (params.c) both accept the bounds (or,
 * for an open bound, a value just inside) and both refuse a value just outside (issue 9: they
 * accepted different ranges, e.g. tps1_counts_at_zero [-65535, 65535] against [-1e6, 1e6]). */
static void test_shared_keys_have_one_range(void)
{
    int id;
    int shared = 0;
    for (id = 0; id < (int)TVP_COUNT; ++id) {
        const tvp_desc_t *d = tvp_desc(id);
        const double scale = fabs(d->hi - d->lo) > 0.0 ? fabs(d->hi - d->lo) : 1.0;
        const double eps = (d->flags & TVP_INTEGER) != 0u ? 1.0 : 1e-6 * scale;
        const double in_lo = (d->flags & TVP_LO_OPEN) != 0u ? d->lo + eps : d->lo;
        const double in_hi = (d->flags & TVP_HI_OPEN) != 0u ? d->hi - eps : d->hi;
        const double out_lo = (d->flags & TVP_LO_OPEN) != 0u ? d->lo : d->lo - eps;
        const double out_hi = (d->flags & TVP_HI_OPEN) != 0u ? d->hi : d->hi + eps;
        const double vals[4] = {in_lo, in_hi, out_lo, out_hi};
        static lx_config_t cfg;
        char line[160];
        char err[LX_ERR_LEN];
        int k;
        (void)snprintf(line, sizeof line, "%s = 1\n", d->key);
        if (parse_with(line, &cfg, err, sizeof err) != TV_OK && strstr(err, "unknown key") != NULL) {
            continue; /* not a key of the controller's configuration */
        }
        ++shared;
        for (k = 0; k < 4; ++k) {
            static params_t pf;
            char perr[PARAMS_MSG_MAX];
            const int want_ok = k < 2 && !((d->flags & TVP_NONZERO) != 0u && vals[k] == 0.0);
            int lx_rc;
            int pf_rc;
            (void)snprintf(line, sizeof line, "%s = %.17g\n", d->key, vals[k]);
            lx_rc = parse_with(line, &cfg, err, sizeof err);
            params_init(&pf, "p.txt");
            pf_rc = params_parse_text(&pf, line, strlen(line), perr, sizeof perr);
            TV_CHECK_EQ_INT(lx_rc == TV_OK, want_ok);
            TV_CHECK_EQ_INT(pf_rc == TV_OK, want_ok);
            if ((lx_rc == TV_OK) != want_ok || (pf_rc == TV_OK) != want_ok) {
                fprintf(stderr, "  %s: controller '%s', parameter file '%s'\n", line, err, perr);
            }
        }
    }
    printf("  %d keys shared by the controller's configuration and the parameter files\n", shared);
    TV_CHECK_LE(7.0, (double)shared); /* the seven calib.* keys at least */
}

/* The model keys of a parameter file written by identify (its comment lines included) set the
 * application's model, and Q follows it; keys not given keep the defaults. */
static void test_identified_model_keys_applied(void)
{
    static lx_config_t cfg;
    app_config_t app;
    app_config_t def;
    app_t a;
    ekf_config_t e;
    char err[LX_ERR_LEN];
    const char *extra = "# Parameter file written by identify from unit.bin\n"
                        "model.R_ohm = 1.61    # identified, sigma 4.6e-05 ohm\n"
                        "# model.L_H: not identified (too little excitation): the default is kept\n"
                        "model.Kt_Nm_A = 0.0112\n"
                        "model.Ke_V_s_rad = 0.0112\n"
                        "model.J_kg_m2 = 0.0012\n"
                        "model.Mc_Nm = 0.15\n"
                        "model.Ms_Nm = 0.22\n"
                        "model.phi_closed_rad = -0.08\n"
                        "model.phi_open_rad = 1.42\n"
                        "model.stop_exponent = 1.25\n"
                        "model.k_stop_Nm_rad = 5000\n"
                        "model.d_stop_Nm_s_rad = 800\n";
    TV_CHECK_EQ_INT(parse_with(extra, &cfg, err, sizeof err), TV_OK);
    app_config_default(&app);
    app_config_default(&def);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK_NEAR(app.model.R_ohm, 1.61, 1e-12);
    TV_CHECK_NEAR(app.model.Kt_Nm_A, 0.0112, 1e-12);
    TV_CHECK_NEAR(app.model.J_kg_m2, 0.0012, 1e-12);
    TV_CHECK_NEAR(app.model.Ms_Nm, 0.22, 1e-12);
    TV_CHECK_NEAR(app.model.phi_open_rad, 1.42, 1e-12);
    TV_CHECK_NEAR(app.model.stop_exponent, 1.25, 1e-12);
    TV_CHECK_NEAR(app.model.L_H, def.model.L_H, 0.0);   /* not given: the default */
    TV_CHECK_NEAR(app.model.c_Nm_rad, def.model.c_Nm_rad, 0.0);
    /* Q is the one the densities give for the new model (ekf_q_from_spectral, as params.h does) */
    e = def.ekf;
    TV_CHECK_EQ_INT(ekf_q_from_spectral(&app.model, EKF_DEFAULT_QU_V2_S, EKF_DEFAULT_QT_NM2_S, e.Q), TV_OK);
    TV_CHECK_NEAR(app.ekf.Q[1][1], e.Q[1][1], 0.0);
    TV_CHECK(app.ekf.Q[1][1] != def.ekf.Q[1][1]); /* J changed */
    TV_CHECK_EQ_INT(app_init(&a, &app), TV_OK);
    /* the defaults of a configuration without model keys leave the model alone */
    TV_CHECK_EQ_INT(parse_with("", &cfg, err, sizeof err), TV_OK);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK(memcmp(&app.model, &def.model, sizeof app.model) == 0);
    TV_CHECK(memcmp(&app.stop_learn, &def.stop_learn, sizeof app.stop_learn) == 0);
    TV_CHECK(app.diag.identified == 0u);
}

/* The rest of an identify file: the start-up stop learning keeps the identified contact law
 * (stop_learn.* keys: exponent fixed, stiffness band, damping ratio) and diag.identified = 1 puts
 * the identified unit's diagnostic bounds in force (values written out here, as
 * diag_detect.h documents them); ranges crossed over are named. */
static void test_identified_stop_learning_and_bounds_applied(void)
{
    static lx_config_t cfg;
    app_config_t app;
    app_t a;
    char err[LX_ERR_LEN];
    const char *extra = "stop_learn.e_min = 1.3    # the exponent identified\n"
                        "stop_learn.e_max = 1.3\n"
                        "stop_learn.lambda_per_k_s_rad = 0.226\n"
                        "stop_learn.k_min_Nm_rad = 1510\n"
                        "stop_learn.k_max_Nm_rad = 1540\n"
                        "diag.identified = 1\n";
    TV_CHECK_EQ_INT(parse_with(extra, &cfg, err, sizeof err), TV_OK);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK_NEAR(app.stop_learn.e_min, 1.3, 1e-6);
    TV_CHECK_NEAR(app.stop_learn.e_max, 1.3, 1e-6);
    TV_CHECK_NEAR(app.stop_learn.lambda_per_k_s_rad, 0.226, 1e-6);
    TV_CHECK_NEAR(app.stop_learn.k_min, 1510.0, 1e-3);
    TV_CHECK_NEAR(app.stop_learn.k_max, 1540.0, 1e-3);
    TV_CHECK(app.diag.identified == 1u && app.diag.friction_high_rel == (tv_real_t)1.15);
    TV_CHECK(app.diag.r_fit_high_frac == (tv_real_t)1.25); /* not given: the default */
    TV_CHECK_EQ_INT(app_init(&a, &app), TV_OK);
    /* the fit's P2101 bound, given with the identified bounds: both in force */
    TV_CHECK_EQ_INT(parse_with("diag.identified = 1\ndiag.r_fit_high_frac = 1.32\n", &cfg, err, sizeof err), TV_OK);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK(app.diag.identified == 1u && app.diag.r_fit_high_frac == (tv_real_t)1.32);
    TV_CHECK_EQ_INT(parse_with("diag.r_fit_high_frac = 0.9\n", &cfg, err, sizeof err), TV_ERR_RANGE);
    TV_CHECK(strstr(err, "diag.r_fit_high_frac") != NULL);
    /* the friction check's per-unit bounds, amending the identified set's */
    TV_CHECK_EQ_INT(parse_with("diag.identified = 1\ndiag.friction_high_rel = 0.875\ndiag.friction_fast_high = 1.375\n"
                               "diag.friction_fast_level_min = 0.825\n",
                               &cfg, err, sizeof err),
                    TV_OK);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK(app.diag.identified == 1u && app.diag.friction_high_rel == (tv_real_t)0.875 &&
             app.diag.friction_fast_high == (tv_real_t)1.375 && app.diag.friction_fast_level_min == (tv_real_t)0.825);
    TV_CHECK_EQ_INT(app_init(&a, &app), TV_OK);
    TV_CHECK_EQ_INT(parse_with("diag.friction_high_rel = 3.5\n", &cfg, err, sizeof err), TV_ERR_RANGE);
    TV_CHECK(strstr(err, "diag.friction_high_rel") != NULL);
    /* the fit's per-unit baseline and its bounds (diag_detect.h), also with the identified bounds */
    TV_CHECK_EQ_INT(parse_with("diag.identified = 1\ndiag.fit_base_r_ohm = 4.375\ndiag.fit_base_nke_V_s = 0.625\n"
                               "diag.fit_base_windows = 24\ndiag.r_fit_base_high_frac = 1.125\n"
                               "diag.gain_fit_base_max = 0.9375\n",
                               &cfg, err, sizeof err),
                    TV_OK);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK(app.diag.identified == 1u && app.diag.fit_base_r_ohm == (tv_real_t)4.375 &&
             app.diag.fit_base_nke_V_s == (tv_real_t)0.625 && app.diag.fit_base_windows == 24u);
    TV_CHECK(app.diag.r_fit_base_high_frac == (tv_real_t)1.125 && app.diag.gain_fit_base_max == (tv_real_t)0.9375);
    TV_CHECK_EQ_INT(app_init(&a, &app), TV_OK);
    TV_CHECK_EQ_INT(parse_with("diag.fit_base_r_ohm = -0.5\n", &cfg, err, sizeof err), TV_ERR_RANGE);
    TV_CHECK(strstr(err, "diag.fit_base_r_ohm") != NULL);
    /* not given: no baseline, not learned, the default bounds */
    TV_CHECK_EQ_INT(parse_with("", &cfg, err, sizeof err), TV_OK);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK(app.diag.fit_base_r_ohm == TV_R(0.0) && app.diag.fit_base_windows == 0u &&
             app.diag.r_fit_base_high_frac == (tv_real_t)1.10);
    /* crossed ranges given in the file are named; one against a default fails app_init() */
    TV_CHECK_EQ_INT(parse_with("stop_learn.e_min = 1.6\nstop_learn.e_max = 1.2\n", &cfg, err, sizeof err), TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "stop_learn.e_min (1.6) is above stop_learn.e_max (1.2)") != NULL);
    TV_CHECK_EQ_INT(parse_with("stop_learn.k_min_Nm_rad = 2e4\nstop_learn.k_max_Nm_rad = 1e4\n", &cfg, err, sizeof err),
                    TV_ERR_CONFIG);
    TV_CHECK(strstr(err, "stop_learn.k_min_Nm_rad (20000) is not below stop_learn.k_max_Nm_rad (10000)") != NULL);
    TV_CHECK_EQ_INT(parse_with("stop_learn.k_min_Nm_rad = 2e4\n", &cfg, err, sizeof err), TV_OK);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK(app_init(&a, &app) != TV_OK);
}

/*
 * The stops file (app.stops_file): written atomically with the stops and contact law, read back
 * as an overlay of model.* keys onto a configuration, the application then running on them;
 * a file not written yet is ENOENT; a key other than model.*, a duplicate or an out-of-range
 * value is named by file and line and leaves the configuration unchanged; a non-finite value is
 * not written.
 */
static void test_stops_file_round_trip_and_errors(void)
{
    static lx_config_t cfg;
    static lx_config_t before;
    static app_t a;
    app_config_t app;
    char err[LX_ERR_LEN];
    char path[64];
    char tmp[80];
    FILE *f;
    (void)snprintf(path, sizeof path, "/tmp/tv_stops_%ld.params", (long)getpid());
    (void)snprintf(tmp, sizeof tmp, "%s.tmp", path);
    (void)remove(path);
    TV_CHECK_EQ_INT(parse_with("", &cfg, err, sizeof err), TV_OK);
    errno = 0;
    TV_CHECK_EQ_INT(lx_config_overlay_model_file(path, &cfg, err, sizeof err), TV_ERR_IO);
    TV_CHECK_EQ_INT(errno, ENOENT);
    TV_CHECK(strstr(err, path) != NULL);
    TV_CHECK_EQ_INT(lx_config_write_stops(path, -0.0812, 1.4207, 4321.5, 1.3, 691.44, 4.3125, 0.6875, err, sizeof err), TV_OK);
    TV_CHECK(access(tmp, F_OK) != 0); /* renamed away */
    TV_CHECK_EQ_INT(lx_config_overlay_model_file(path, &cfg, err, sizeof err), TV_OK);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK_NEAR(app.model.phi_closed_rad, -0.0812, 1e-12);
    TV_CHECK_NEAR(app.model.phi_open_rad, 1.4207, 1e-12);
    TV_CHECK_NEAR(app.model.k_stop_Nm_rad, 4321.5, 1e-9);
    TV_CHECK_NEAR(app.model.stop_exponent, 1.3, 1e-12);
    TV_CHECK_NEAR(app.model.d_stop_Nm_s_rad, 691.44, 1e-9);
    TV_CHECK(app.diag.fit_base_r_ohm == (tv_real_t)4.3125 && app.diag.fit_base_nke_V_s == (tv_real_t)0.6875);
    TV_CHECK_EQ_INT(app_init(&a, &app), TV_OK);
    /* no baseline yet: its lines are not written */
    TV_CHECK_EQ_INT(lx_config_write_stops(path, -0.0812, 1.4207, 4321.5, 1.3, 691.44, 0.0, 0.0, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(parse_with("", &cfg, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(lx_config_overlay_model_file(path, &cfg, err, sizeof err), TV_OK);
    app_config_default(&app);
    lx_config_apply_app(&cfg, &app);
    TV_CHECK(app.diag.fit_base_r_ohm == TV_R(0.0) && app.diag.fit_base_nke_V_s == TV_R(0.0));
    TV_CHECK_NEAR(app.model.phi_open_rad, 1.4207, 1e-12);
    /* bad contents: named, nothing changed */
    before = cfg;
    TV_CHECK_EQ_INT(lx_config_overlay_model("model.phi_open_rad = 1.4\nrt.priority = 3\n", "stops", &cfg, err, sizeof err),
                    TV_ERR_FORMAT);
    TV_CHECK(strstr(err, "stops:2") != NULL && strstr(err, "model.* keys and the fit's baseline only") != NULL);
    TV_CHECK(memcmp(&before, &cfg, sizeof cfg) == 0);
    TV_CHECK_EQ_INT(lx_config_overlay_model("model.phi_open_rad = 1.4\nmodel.phi_open_rad = 1.41\n", "stops", &cfg, err,
                                            sizeof err),
                    TV_ERR_FORMAT);
    TV_CHECK(strstr(err, "stops:2") != NULL && strstr(err, "twice") != NULL);
    TV_CHECK(lx_config_overlay_model("model.phi_closed_rad = 0.1\n", "stops", &cfg, err, sizeof err) != TV_OK);
    TV_CHECK(strstr(err, "stops:1") != NULL && strstr(err, "model.phi_closed_rad") != NULL);
    TV_CHECK(memcmp(&before, &cfg, sizeof cfg) == 0);
    /* a non-finite value is not written: the old file stays */
    TV_CHECK_EQ_INT(lx_config_write_stops(path, (double)NAN, 1.4, 1.0, 1.0, 1.0, 0.0, 0.0, err, sizeof err), TV_ERR_NONFINITE);
    f = fopen(path, "r");
    TV_CHECK(f != NULL);
    if (f != NULL) {
        char line[128];
        int found = 0;
        while (fgets(line, sizeof line, f) != NULL) {
            found += strstr(line, "model.phi_open_rad = 1.4207") != NULL;
        }
        (void)fclose(f);
        TV_CHECK_EQ_INT(found, 1);
    }
    /* an unwritable place is an error that names the file */
    TV_CHECK_EQ_INT(lx_config_write_stops("/nonexistent_dir_tv/stops.params", -0.1, 1.4, 1.0, 1.0, 1.0, 0.0, 0.0, err, sizeof err),
                    TV_ERR_IO);
    TV_CHECK(strstr(err, "/nonexistent_dir_tv/stops.params") != NULL);
    (void)remove(path);
}

int main(int argc, char **argv)
{
    s_example_path = argc > 1 ? argv[1] : "firmware/linux_rt/throttle_linux.conf";
    TV_TEST_RUN(test_example_file_parses_to_defaults);
    TV_TEST_RUN(test_values_stored);
    TV_TEST_RUN(test_syntax_errors_named);
    TV_TEST_RUN(test_bad_values_named);
    TV_TEST_RUN(test_missing_required_keys_named);
    TV_TEST_RUN(test_conflicts_named);
    TV_TEST_RUN(test_file_errors_named);
    TV_TEST_RUN(test_shared_keys_have_one_range);
    TV_TEST_RUN(test_identified_model_keys_applied);
    TV_TEST_RUN(test_identified_stop_learning_and_bounds_applied);
    TV_TEST_RUN(test_stops_file_round_trip_and_errors);
    return tv_test_summary();
}
