/**
 * @file lx_config.c
 * @brief Configuration file parser of the Linux controller (see lx_config.h).
 */
#define _POSIX_C_SOURCE 200809L

#include "lx_config.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lx_err.h"
#include "tv_param_table.h"
#include "tv_status.h"

/* Value types of the keys. */
typedef enum { K_INT, K_UINT, K_U16, K_U8, K_DOUBLE, K_BOOL, K_STR, K_MODE } key_type_t;

/* One key: name, type, range (numbers) or capacity (strings), where it goes, required. */
typedef struct {
    const char *name;
    double min;
    double max;
    size_t offset;
    size_t size; /* capacity of K_STR fields */
    key_type_t type;
    int required;
} key_desc_t;

#define OFF(field) offsetof(lx_config_t, field)
#define NUM(name, type, lo, hi, field, req) {(name), (lo), (hi), OFF(field), 0u, (type), (req)}
#define STR(name, field, req) {(name), 0.0, 0.0, OFF(field), sizeof(((lx_config_t *)0)->field), K_STR, (req)}

static const key_desc_t s_keys[] = {
    NUM("rt.priority", K_INT, 0, 99, rt_priority, 0),
    NUM("rt.cpu", K_INT, -1, 1023, rt_cpu, 0),
    NUM("rt.lock_memory", K_BOOL, 0, 1, rt_lock_memory, 0),
    NUM("rt.duration_s", K_UINT, 0, 1e7, rt_duration_s, 0),
    NUM("rt.max_io_errors", K_UINT, 1, 1000, rt_max_io_errors, 0),
    STR("pwm.chip", dev.pwm_chip, 1),
    NUM("pwm.channel_a", K_UINT, 0, 1023, dev.pwm_channel_a, 1),
    NUM("pwm.channel_b", K_UINT, 0, 1023, dev.pwm_channel_b, 1),
    NUM("pwm.period_ns", K_UINT, 1000, 1e9, dev.pwm_period_ns, 0),
    STR("adc.device", dev.adc_device, 1),
    NUM("adc.channel.current", K_UINT, 0, 255, dev.adc_channel[0], 0),
    NUM("adc.channel.tps1", K_UINT, 0, 255, dev.adc_channel[1], 0),
    NUM("adc.channel.tps2", K_UINT, 0, 255, dev.adc_channel[2], 0),
    NUM("adc.channel.supply", K_UINT, 0, 255, dev.adc_channel[3], 0),
    NUM("adc.max_counts", K_UINT, 1, 65535, dev.adc_max_counts, 0),
    STR("gpio.chip", dev.gpio_chip, 1),
    STR("gpio.consumer", dev.gpio_consumer, 0),
    NUM("gpio.bridge_enable.line", K_UINT, 0, 65535, dev.gpio_enable_line, 1),
    NUM("gpio.bridge_enable.active_low", K_BOOL, 0, 1, dev.gpio_enable_active_low, 0),
    NUM("gpio.driver_fault.line", K_UINT, 0, 65535, dev.gpio_fault_line, 1),
    NUM("gpio.driver_fault.active_low", K_BOOL, 0, 1, dev.gpio_fault_active_low, 0),
    STR("can.interface", dev.can_interface, 1),
    NUM("can.cmd_timeout_ms", K_UINT, 0, CAN_PROTO_TIMEOUT_MAX_MS, can.cmd_timeout_ms, 0),
    NUM("can.max_counter_delta", K_U8, 1, 14, can.max_counter_delta, 0),
    NUM("can.period_ms.est_state", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_EST_STATE], 0),
    NUM("can.period_ms.est_sigma", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_EST_SIGMA], 0),
    NUM("can.period_ms.est_innov", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_EST_INNOV], 0),
    NUM("can.period_ms.status", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_STATUS], 0),
    NUM("can.period_ms.meas", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_MEAS], 0),
    NUM("can.period_ms.loop", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_LOOP], 0),
    NUM("can.period_ms.cmd_stats", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_CMD_STATS], 0),
    NUM("can.period_ms.ekf_stats", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_EKF_STATS], 0),
    NUM("can.period_ms.time", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_TIME], 0),
    NUM("can.period_ms.health_1", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_HEALTH_1], 0),
    NUM("can.period_ms.health_2", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_HEALTH_2], 0),
    NUM("can.period_ms.diag", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_DIAG], 0),
    NUM("can.period_ms.diag_freeze", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_DIAG_FREEZE], 0),
    NUM("can.period_ms.health_3", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_HEALTH_3], 0),
    NUM("can.period_ms.health_4", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_HEALTH_4], 0),
    NUM("can.period_ms.health_5", K_U16, 0, 60000, can.period_ms[CAN_PROTO_TX_HEALTH_5], 0),
    NUM("app.mode", K_MODE, 0, 7, app_mode, 0),
    STR("app.stops_file", app_stops_file, 0),
    /* the ranges of the command frames (can_proto.h), so a configuration can be commanded */
    NUM("app.amplitude_V", K_DOUBLE, 0, 24, app_amplitude_V, 0),
    NUM("app.freq_Hz", K_DOUBLE, 0, 200, app_freq_Hz, 0),
    NUM("app.chirp_f1_Hz", K_DOUBLE, 0, 200, app_chirp_f1_Hz, 0),
    NUM("app.chirp_period_s", K_DOUBLE, 0.1, 25.5, app_chirp_period_s, 0),
    NUM("app.target_rad", K_DOUBLE, -0.5, 2.0, app_target_rad, 0),
    NUM("app.duty_limit", K_DOUBLE, 0.005, 1.0, app_duty_limit, 0),
    NUM("calib.current_offset_counts", K_DOUBLE, 0, 65535, calib_current_offset_counts, 0),
    NUM("calib.current_A_per_count", K_DOUBLE, -1, 1, calib_current_A_per_count, 0),
    NUM("calib.tps1_counts_at_zero", K_DOUBLE, -65535, 65535, calib_tps1_counts_at_zero, 0),
    NUM("calib.tps1_rad_per_count", K_DOUBLE, 1e-9, 1, calib_tps1_rad_per_count, 0),
    NUM("calib.tps2_counts_at_zero", K_DOUBLE, -65535, 65535, calib_tps2_counts_at_zero, 0),
    NUM("calib.tps2_rad_per_count", K_DOUBLE, -1, -1e-9, calib_tps2_rad_per_count, 0),
    NUM("calib.supply_V_per_count", K_DOUBLE, 1e-9, 1, calib_supply_V_per_count, 0),
    /* the model keys identify writes; ranges those of tv_param_table.c (an open bound 0 as 1e-9) */
    NUM("model.R_ohm", K_DOUBLE, 1e-9, 1000, model_R_ohm, 0),
    NUM("model.L_H", K_DOUBLE, 1e-9, 10, model_L_H, 0),
    NUM("model.Ke_V_s_rad", K_DOUBLE, 0, 10, model_Ke_V_s_rad, 0),
    NUM("model.Kt_Nm_A", K_DOUBLE, 0, 10, model_Kt_Nm_A, 0),
    NUM("model.J_kg_m2", K_DOUBLE, 1e-9, 10, model_J_kg_m2, 0),
    NUM("model.n_gear", K_DOUBLE, 1e-9, 1000, model_n_gear, 0),
    NUM("model.Mc_Nm", K_DOUBLE, 0, 100, model_Mc_Nm, 0),
    NUM("model.M0_Nm", K_DOUBLE, 0, 100, model_M0_Nm, 0),
    NUM("model.c_Nm_rad", K_DOUBLE, 0, 1000, model_c_Nm_rad, 0),
    NUM("model.Kv_Nm_s_rad", K_DOUBLE, 0, 100, model_Kv_Nm_s_rad, 0),
    NUM("model.Ms_Nm", K_DOUBLE, 0, 100, model_Ms_Nm, 0),
    NUM("model.ws_rad_s", K_DOUBLE, 1e-9, 1000, model_ws_rad_s, 0),
    NUM("model.phi_closed_rad", K_DOUBLE, -1, -1e-9, model_phi_closed_rad, 0),
    NUM("model.phi_open_rad", K_DOUBLE, 1e-9, 2.5, model_phi_open_rad, 0),
    NUM("model.k_stop_Nm_rad", K_DOUBLE, 0, 1e7, model_k_stop_Nm_rad, 0),
    NUM("model.d_stop_Nm_s_rad", K_DOUBLE, 0, 1e7, model_d_stop_Nm_s_rad, 0),
    NUM("model.stop_exponent", K_DOUBLE, 0, 3, model_stop_exponent, 0),
    /* the rest of what identify writes (ranges from tv_param_table.c) */
    NUM("stop_learn.e_min", K_DOUBLE, 1, 3, sl_e_min, 0),
    NUM("stop_learn.e_max", K_DOUBLE, 1, 3, sl_e_max, 0),
    NUM("stop_learn.lambda_per_k_s_rad", K_DOUBLE, 0, 10, sl_lambda_per_k_s_rad, 0),
    NUM("stop_learn.k_min_Nm_rad", K_DOUBLE, 1e-9, 1e7, sl_k_min_Nm_rad, 0),
    NUM("stop_learn.k_max_Nm_rad", K_DOUBLE, 1e-9, 1e7, sl_k_max_Nm_rad, 0),
    NUM("diag.identified", K_BOOL, 0, 1, diag_identified, 0),
    NUM("diag.r_fit_high_frac", K_DOUBLE, 1, 3, diag_r_fit_high_frac, 0),
    NUM("diag.friction_high_rel", K_DOUBLE, 0, 3, diag_friction_high_rel, 0),
    NUM("diag.friction_fast_high", K_DOUBLE, 0, 3, diag_friction_fast_high, 0),
    NUM("diag.friction_fast_level_min", K_DOUBLE, 0, 3, diag_friction_fast_level_min, 0),
    NUM("diag.fit_base_r_ohm", K_DOUBLE, 0, 1000, diag_fit_base_r_ohm, 0),
    NUM("diag.fit_base_nke_V_s", K_DOUBLE, 0, 100, diag_fit_base_nke_V_s, 0),
    NUM("diag.fit_base_windows", K_U16, 0, 65535, diag_fit_base_windows, 0),
    NUM("diag.r_fit_base_high_frac", K_DOUBLE, 1, 3, diag_r_fit_base_high_frac, 0),
    NUM("diag.gain_fit_base_max", K_DOUBLE, 0, 1, diag_gain_fit_base_max, 0),
};

/* Where an optional real key goes: its double in lx_config_t (NaN = not given) and its tv_real_t
 * in the application's structure. */
typedef struct {
    size_t lx;
    size_t dst;
} real_key_t;

/* The model keys: where each goes in lx_config_t and in tvm_params_t. */
static const real_key_t s_model_keys[] = {
    {OFF(model_R_ohm), offsetof(tvm_params_t, R_ohm)},
    {OFF(model_L_H), offsetof(tvm_params_t, L_H)},
    {OFF(model_Ke_V_s_rad), offsetof(tvm_params_t, Ke_V_s_rad)},
    {OFF(model_Kt_Nm_A), offsetof(tvm_params_t, Kt_Nm_A)},
    {OFF(model_J_kg_m2), offsetof(tvm_params_t, J_kg_m2)},
    {OFF(model_n_gear), offsetof(tvm_params_t, n_gear)},
    {OFF(model_Mc_Nm), offsetof(tvm_params_t, Mc_Nm)},
    {OFF(model_M0_Nm), offsetof(tvm_params_t, M0_Nm)},
    {OFF(model_c_Nm_rad), offsetof(tvm_params_t, c_Nm_rad)},
    {OFF(model_Kv_Nm_s_rad), offsetof(tvm_params_t, Kv_Nm_s_rad)},
    {OFF(model_Ms_Nm), offsetof(tvm_params_t, Ms_Nm)},
    {OFF(model_ws_rad_s), offsetof(tvm_params_t, ws_rad_s)},
    {OFF(model_phi_closed_rad), offsetof(tvm_params_t, phi_closed_rad)},
    {OFF(model_phi_open_rad), offsetof(tvm_params_t, phi_open_rad)},
    {OFF(model_k_stop_Nm_rad), offsetof(tvm_params_t, k_stop_Nm_rad)},
    {OFF(model_d_stop_Nm_s_rad), offsetof(tvm_params_t, d_stop_Nm_s_rad)},
    {OFF(model_stop_exponent), offsetof(tvm_params_t, stop_exponent)},
};
#define N_MODEL_KEYS (sizeof s_model_keys / sizeof s_model_keys[0])

/* The stop-learning keys: where each goes in lx_config_t and in sl_config_t. */
static const real_key_t s_sl_keys[] = {
    {OFF(sl_e_min), offsetof(sl_config_t, e_min)},
    {OFF(sl_e_max), offsetof(sl_config_t, e_max)},
    {OFF(sl_lambda_per_k_s_rad), offsetof(sl_config_t, lambda_per_k_s_rad)},
    {OFF(sl_k_min_Nm_rad), offsetof(sl_config_t, k_min)},
    {OFF(sl_k_max_Nm_rad), offsetof(sl_config_t, k_max)},
};
#define N_SL_KEYS (sizeof s_sl_keys / sizeof s_sl_keys[0])

/* The diagnostic bounds given as numbers: where each goes in lx_config_t and in diag_detect_config_t
 * (after diag.identified, which selects the set they amend). */
static const real_key_t s_diag_keys[] = {
    {OFF(diag_r_fit_high_frac), offsetof(diag_detect_config_t, r_fit_high_frac)},
    {OFF(diag_friction_high_rel), offsetof(diag_detect_config_t, friction_high_rel)},
    {OFF(diag_friction_fast_high), offsetof(diag_detect_config_t, friction_fast_high)},
    {OFF(diag_friction_fast_level_min), offsetof(diag_detect_config_t, friction_fast_level_min)},
    {OFF(diag_fit_base_r_ohm), offsetof(diag_detect_config_t, fit_base_r_ohm)},
    {OFF(diag_fit_base_nke_V_s), offsetof(diag_detect_config_t, fit_base_nke_V_s)},
    {OFF(diag_r_fit_base_high_frac), offsetof(diag_detect_config_t, r_fit_base_high_frac)},
    {OFF(diag_gain_fit_base_max), offsetof(diag_detect_config_t, gain_fit_base_max)},
};
#define N_DIAG_KEYS (sizeof s_diag_keys / sizeof s_diag_keys[0])

/* Every key of map[0..n) not given (NaN in cfg). */
static void real_keys_unset(lx_config_t *cfg, const real_key_t *map, size_t n)
{
    const double nan_v = (double)NAN;
    size_t k;
    for (k = 0; k < n; ++k) {
        memcpy((char *)cfg + map[k].lx, &nan_v, sizeof nan_v);
    }
}

/* The keys of map[0..n) given in cfg, into dst; returns 1 when any was given. */
static int real_keys_copy(const lx_config_t *cfg, const real_key_t *map, size_t n, void *dst)
{
    int any = 0;
    size_t k;
    for (k = 0; k < n; ++k) {
        double v;
        memcpy(&v, (const char *)cfg + map[k].lx, sizeof v);
        if (!isnan(v)) {
            const tv_real_t r = (tv_real_t)v;
            memcpy((char *)dst + map[k].dst, &r, sizeof r);
            any = 1;
        }
    }
    return any;
}

#define N_KEYS (sizeof s_keys / sizeof s_keys[0])
/* Longest line accepted [bytes]. */
#define LINE_MAX_LEN 1024u
/* Largest file read by lx_config_load() [bytes]. */
#define FILE_MAX_LEN ((size_t)64 * 1024u)

/* The modes a configuration can start in, by name. */
static const struct {
    const char *name;
    app_mode_t mode;
} s_modes[] = {{"off", APP_MODE_OFF},     {"sine", APP_MODE_SINE},         {"steps", APP_MODE_STEPS},
               {"chirp", APP_MODE_CHIRP}, {"position", APP_MODE_POSITION}, {"ident", APP_MODE_IDENT}};

void lx_config_default(lx_config_t *cfg)
{
    tvm_params_t p;
    app_calib_t c;
    if (cfg == NULL) {
        return;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->rt_priority = 80;
    cfg->rt_cpu = -1;
    cfg->rt_lock_memory = 1;
    cfg->rt_duration_s = 0u;
    cfg->rt_max_io_errors = 10u;
    cfg->dev.pwm_period_ns = 50000u;
    cfg->dev.adc_channel[0] = 0u;
    cfg->dev.adc_channel[1] = 1u;
    cfg->dev.adc_channel[2] = 2u;
    cfg->dev.adc_channel[3] = 3u;
    cfg->dev.adc_max_counts = 4095u;
    (void)snprintf(cfg->dev.gpio_consumer, sizeof cfg->dev.gpio_consumer, "%s", "throttle");
    can_proto_config_default(&cfg->can);
    cfg->app_mode = (int32_t)APP_MODE_OFF;
    cfg->app_amplitude_V = 12.0;
    cfg->app_freq_Hz = 5.0;
    cfg->app_chirp_f1_Hz = 20.0;
    cfg->app_chirp_period_s = 2.0;
    cfg->app_target_rad = 0.3;
    cfg->app_duty_limit = 0.95;
    tvm_params_default(&p);
    app_calib_default(&c, &p);
    cfg->calib_current_offset_counts = (double)c.current_offset_counts;
    cfg->calib_current_A_per_count = (double)c.current_A_per_count;
    cfg->calib_tps1_counts_at_zero = (double)c.tps1_counts_at_zero;
    cfg->calib_tps1_rad_per_count = (double)c.tps1_rad_per_count;
    cfg->calib_tps2_counts_at_zero = (double)c.tps2_counts_at_zero;
    cfg->calib_tps2_rad_per_count = (double)c.tps2_rad_per_count;
    cfg->calib_supply_V_per_count = (double)c.supply_V_per_count;
    /* not given: the application's defaults */
    real_keys_unset(cfg, s_model_keys, N_MODEL_KEYS);
    real_keys_unset(cfg, s_sl_keys, N_SL_KEYS);
    real_keys_unset(cfg, s_diag_keys, N_DIAG_KEYS);
}

static char *trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t' || *s == '\r') {
        ++s;
    }
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' || e[-1] == '\n')) {
        --e;
    }
    *e = '\0';
    return s;
}

/* Store one value. Returns TV_OK, TV_ERR_FORMAT or TV_ERR_RANGE with *why set. */
static int store(const key_desc_t *k, const char *v, lx_config_t *cfg, const char **why)
{
    char *base = (char *)cfg + k->offset;
    char *end = NULL;
    double d = 0.0;
    if (k->type == K_STR) {
        if (v[0] == '\0') {
            *why = "empty";
            return TV_ERR_FORMAT;
        }
        if (strlen(v) >= k->size) {
            *why = "too long";
            return TV_ERR_RANGE;
        }
        memcpy(base, v, strlen(v) + 1u);
        return TV_OK;
    }
    if (k->type == K_MODE) {
        size_t i;
        for (i = 0; i < sizeof s_modes / sizeof s_modes[0]; ++i) {
            if (strcmp(v, s_modes[i].name) == 0) {
                int32_t m = (int32_t)s_modes[i].mode;
                memcpy(base, &m, sizeof m);
                return TV_OK;
            }
        }
        *why = "not one of off, sine, steps, chirp, position, ident";
        return TV_ERR_FORMAT;
    }
    if (k->type == K_BOOL) {
        int32_t b;
        if (strcmp(v, "1") == 0 || strcmp(v, "yes") == 0 || strcmp(v, "true") == 0) {
            b = 1;
        } else if (strcmp(v, "0") == 0 || strcmp(v, "no") == 0 || strcmp(v, "false") == 0) {
            b = 0;
        } else {
            *why = "not a boolean (0/1, no/yes, false/true)";
            return TV_ERR_FORMAT;
        }
        memcpy(base, &b, sizeof b);
        return TV_OK;
    }
    if (strchr(v, 'x') != NULL || strchr(v, 'X') != NULL) {
        /* decimal only: strtod reads hexadecimal floats, base-0 strtoll reads 0x50 as 80 */
        *why = "not a decimal number (no 0x prefix)";
        return TV_ERR_FORMAT;
    }
    errno = 0;
    if (k->type == K_DOUBLE) {
        d = strtod(v, &end);
    } else {
        /* base 10: a leading zero is not octal ("010" is ten, as everyone reading it expects) */
        const long long n = strtoll(v, &end, 10);
        d = (double)n;
        if (errno == ERANGE) {
            *why = "out of range";
            return TV_ERR_RANGE;
        }
    }
    if (end == v || *end != '\0') {
        *why = k->type == K_DOUBLE ? "not a number" : "not an integer";
        return TV_ERR_FORMAT;
    }
    if (errno == ERANGE || !(d == d) || d - d != 0.0) {
        *why = "not a finite number";
        return TV_ERR_RANGE;
    }
    {
        /* A quantity the project's parameter table knows has its range from there, the same as
         * in every other configuration reader (tv_param_table.h); the others from s_keys. */
        const int id = tvp_find(k->name);
        if (id >= 0 ? tvp_check(id, d) != 0 : (d < k->min || d > k->max)) {
            *why = "out of range";
            return TV_ERR_RANGE;
        }
    }
    switch (k->type) {
    case K_INT: {
        const int32_t x = (int32_t)d;
        memcpy(base, &x, sizeof x);
        break;
    }
    case K_UINT: {
        const uint32_t x = (uint32_t)d;
        memcpy(base, &x, sizeof x);
        break;
    }
    case K_U16: {
        const uint16_t x = (uint16_t)d;
        memcpy(base, &x, sizeof x);
        break;
    }
    case K_U8: {
        const uint8_t x = (uint8_t)d;
        memcpy(base, &x, sizeof x);
        break;
    }
    default: /* K_DOUBLE */
        memcpy(base, &d, sizeof d);
        break;
    }
    return TV_OK;
}

static int check_conflicts(const lx_config_t *cfg, const char *name, char *err, size_t err_len)
{
    int i;
    int j;
    static const char *const adc_keys[4] = {"adc.channel.current", "adc.channel.tps1", "adc.channel.tps2",
                                            "adc.channel.supply"};
    if (cfg->dev.pwm_channel_a == cfg->dev.pwm_channel_b) {
        lx_err_set(err, err_len, "%s: pwm.channel_a and pwm.channel_b are both %u (the bridge needs two channels)", name,
                (unsigned)cfg->dev.pwm_channel_a);
        return TV_ERR_CONFIG;
    }
    for (i = 0; i < 4; ++i) {
        for (j = i + 1; j < 4; ++j) {
            if (cfg->dev.adc_channel[i] == cfg->dev.adc_channel[j]) {
                lx_err_set(err, err_len, "%s: %s and %s are both %u", name, adc_keys[i], adc_keys[j],
                        (unsigned)cfg->dev.adc_channel[i]);
                return TV_ERR_CONFIG;
            }
        }
    }
    if (cfg->dev.gpio_enable_line == cfg->dev.gpio_fault_line) {
        lx_err_set(err, err_len, "%s: gpio.bridge_enable.line and gpio.driver_fault.line are both %u", name,
                (unsigned)cfg->dev.gpio_enable_line);
        return TV_ERR_CONFIG;
    }
    /* the stop learning's ranges where both sides are given (one side against a default is
     * judged, with its status, by app_init(): sl_config_valid()) */
    if (!isnan(cfg->sl_e_min) && !isnan(cfg->sl_e_max) && cfg->sl_e_min > cfg->sl_e_max) {
        lx_err_set(err, err_len, "%s: stop_learn.e_min (%g) is above stop_learn.e_max (%g)", name, cfg->sl_e_min,
                   cfg->sl_e_max);
        return TV_ERR_CONFIG;
    }
    if (!isnan(cfg->sl_k_min_Nm_rad) && !isnan(cfg->sl_k_max_Nm_rad) && !(cfg->sl_k_min_Nm_rad < cfg->sl_k_max_Nm_rad)) {
        lx_err_set(err, err_len, "%s: stop_learn.k_min_Nm_rad (%g) is not below stop_learn.k_max_Nm_rad (%g)", name,
                   cfg->sl_k_min_Nm_rad, cfg->sl_k_max_Nm_rad);
        return TV_ERR_CONFIG;
    }
    return TV_OK;
}

/* The lines of a configuration text into cfg (not reset); seen[] marks the keys given. With
 * model_only, only "model." keys and the fit's baseline (diag.fit_base_r_ohm, diag.fit_base_nke_V_s)
 * are allowed (an overlay, lx_config_overlay_model(): the stops file). */
static int parse_lines(const char *text, const char *name, lx_config_t *cfg, unsigned char seen[N_KEYS], int model_only,
                       char *err, size_t err_len)
{
    const char *p;
    unsigned line_no = 0u;
    size_t i;
    for (i = 0; i < N_KEYS; ++i) {
        seen[i] = 0u;
    }
    p = text;
    while (*p != '\0') {
        char line[LINE_MAX_LEN];
        const char *nl = strchr(p, '\n');
        const size_t len = nl != NULL ? (size_t)(nl - p) : strlen(p);
        char *key;
        char *val;
        char *eq;
        char *hash;
        const key_desc_t *k = NULL;
        const char *why = NULL;
        int rc;
        ++line_no;
        if (len >= sizeof line) {
            lx_err_set(err, err_len, "%s:%u: line longer than %u characters", name, line_no, (unsigned)(sizeof line - 1u));
            return TV_ERR_FORMAT;
        }
        memcpy(line, p, len);
        line[len] = '\0';
        p = nl != NULL ? nl + 1 : p + len;
        hash = strchr(line, '#');
        if (hash != NULL) {
            *hash = '\0';
        }
        key = trim(line);
        if (*key == '\0') {
            continue;
        }
        eq = strchr(key, '=');
        if (eq == NULL) {
            lx_err_set(err, err_len, "%s:%u: '%s': expected 'key = value'", name, line_no, key);
            return TV_ERR_FORMAT;
        }
        *eq = '\0';
        val = trim(eq + 1);
        key = trim(key);
        if (val[0] == '"') {
            const size_t vl = strlen(val);
            if (vl < 2u || val[vl - 1u] != '"') {
                lx_err_set(err, err_len, "%s:%u: %s = %s: unterminated quote", name, line_no, key, val);
                return TV_ERR_FORMAT;
            }
            val[vl - 1u] = '\0';
            ++val;
        }
        for (i = 0; i < N_KEYS; ++i) {
            if (strcmp(key, s_keys[i].name) == 0) {
                k = &s_keys[i];
                break;
            }
        }
        if (k == NULL) {
            lx_err_set(err, err_len, "%s:%u: unknown key '%s'", name, line_no, key);
            return TV_ERR_FORMAT;
        }
        if (model_only && strncmp(key, "model.", 6u) != 0 && strcmp(key, "diag.fit_base_r_ohm") != 0 &&
            strcmp(key, "diag.fit_base_nke_V_s") != 0) {
            lx_err_set(err, err_len, "%s:%u: key '%s' is not allowed here (model.* keys and the fit's baseline only)", name,
                       line_no, key);
            return TV_ERR_FORMAT;
        }
        if (seen[i]) {
            lx_err_set(err, err_len, "%s:%u: key '%s' given twice", name, line_no, key);
            return TV_ERR_FORMAT;
        }
        seen[i] = 1u;
        rc = store(k, val, cfg, &why);
        if (rc != TV_OK) {
            if (rc == TV_ERR_RANGE && tvp_find(key) >= 0) {
                char rng[96];
                tvp_range_text(tvp_find(key), rng, sizeof rng);
                lx_err_set(err, err_len, "%s:%u: %s = '%s': %s, allowed %s", name, line_no, key, val, why, rng);
            } else if (rc == TV_ERR_RANGE && k->type != K_STR && k->type != K_BOOL && k->type != K_MODE) {
                lx_err_set(err, err_len, "%s:%u: %s = '%s': %s [%g, %g]", name, line_no, key, val, why, k->min, k->max);
            } else if (k->type == K_STR && rc == TV_ERR_RANGE) {
                lx_err_set(err, err_len, "%s:%u: %s = '%s': %s (at most %u characters)", name, line_no, key, val, why,
                        (unsigned)(k->size - 1u));
            } else {
                lx_err_set(err, err_len, "%s:%u: %s = '%s': %s", name, line_no, key, val, why);
            }
            return rc;
        }
    }
    return TV_OK;
}

int lx_config_parse(const char *text, const char *name, lx_config_t *cfg, char *err, size_t err_len)
{
    unsigned char seen[N_KEYS];
    size_t i;
    int rc;
    if (text == NULL || cfg == NULL) {
        lx_err_set(err, err_len, "lx_config_parse: NULL argument");
        return TV_ERR_NULL;
    }
    if (name == NULL) {
        name = "config";
    }
    lx_err_set(err, err_len, "%s", "");
    lx_config_default(cfg);
    rc = parse_lines(text, name, cfg, seen, 0, err, err_len);
    if (rc != TV_OK) {
        return rc;
    }
    for (i = 0; i < N_KEYS; ++i) {
        if (s_keys[i].required && !seen[i]) {
            lx_err_set(err, err_len, "%s: missing required key '%s'", name, s_keys[i].name);
            return TV_ERR_CONFIG;
        }
    }
    return check_conflicts(cfg, name, err, err_len);
}

int lx_config_overlay_model(const char *text, const char *name, lx_config_t *cfg, char *err, size_t err_len)
{
    unsigned char seen[N_KEYS];
    lx_config_t tmp;
    int rc;
    if (text == NULL || cfg == NULL) {
        lx_err_set(err, err_len, "lx_config_overlay_model: NULL argument");
        return TV_ERR_NULL;
    }
    lx_err_set(err, err_len, "%s", "");
    tmp = *cfg; /* cfg changes only when the whole file is good */
    rc = parse_lines(text, name != NULL ? name : "model file", &tmp, seen, 1, err, err_len);
    if (rc == TV_OK) {
        *cfg = tmp;
    }
    return rc;
}

/* The whole text file path into buf (NUL-terminated); what is read as in lx_config_load(). */
static int read_text(const char *path, const char *what, char *buf, char *err, size_t err_len)
{
    FILE *f;
    size_t n;
    f = fopen(path, "r");
    if (f == NULL) {
        const int e = errno;
        lx_err_set(err, err_len, "%s: cannot open %s: %s", path, what, strerror(e));
        errno = e;
        return TV_ERR_IO;
    }
    n = fread(buf, 1u, FILE_MAX_LEN + 1u, f);
    if (ferror(f)) {
        lx_err_set(err, err_len, "%s: read error: %s", path, strerror(errno));
        (void)fclose(f);
        return TV_ERR_IO;
    }
    (void)fclose(f);
    if (n > FILE_MAX_LEN) {
        lx_err_set(err, err_len, "%s: larger than %u bytes", path, (unsigned)FILE_MAX_LEN);
        return TV_ERR_FORMAT;
    }
    if (memchr(buf, '\0', n) != NULL) {
        lx_err_set(err, err_len, "%s: contains a NUL byte (not a text file)", path);
        return TV_ERR_FORMAT;
    }
    buf[n] = '\0';
    return TV_OK;
}

int lx_config_load(const char *path, lx_config_t *cfg, char *err, size_t err_len)
{
    static char buf[FILE_MAX_LEN + 1u];
    int rc;
    if (path == NULL || cfg == NULL) {
        lx_err_set(err, err_len, "lx_config_load: NULL argument");
        return TV_ERR_NULL;
    }
    rc = read_text(path, "configuration file", buf, err, err_len);
    return rc != TV_OK ? rc : lx_config_parse(buf, path, cfg, err, err_len);
}

int lx_config_overlay_model_file(const char *path, lx_config_t *cfg, char *err, size_t err_len)
{
    static char buf[FILE_MAX_LEN + 1u];
    int rc;
    if (path == NULL || cfg == NULL) {
        lx_err_set(err, err_len, "lx_config_overlay_model_file: NULL argument");
        return TV_ERR_NULL;
    }
    rc = read_text(path, "model file", buf, err, err_len);
    return rc != TV_OK ? rc : lx_config_overlay_model(buf, path, cfg, err, err_len);
}

int lx_config_write_stops(const char *path, double phi_closed_rad, double phi_open_rad, double k_stop,
                          double stop_exponent, double d_stop, double fit_base_r_ohm, double fit_base_nke_V_s, char *err,
                          size_t err_len)
{
    char tmp[LX_PATH_LEN + 8];
    FILE *f;
    int ok;
    if (path == NULL) {
        lx_err_set(err, err_len, "lx_config_write_stops: NULL argument");
        return TV_ERR_NULL;
    }
    if (!isfinite(phi_closed_rad) || !isfinite(phi_open_rad) || !isfinite(k_stop) || !isfinite(stop_exponent) ||
        !isfinite(d_stop)) {
        lx_err_set(err, err_len, "%s: not written: a stop value is not finite", path);
        return TV_ERR_NONFINITE;
    }
    if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp", path) >= sizeof tmp) {
        lx_err_set(err, err_len, "%s: path too long", path);
        return TV_ERR_IO;
    }
    f = fopen(tmp, "w");
    if (f == NULL) {
        lx_err_set(err, err_len, "%s: cannot write: %s", tmp, strerror(errno));
        return TV_ERR_IO;
    }
    ok = fprintf(f,
                 "# The stops and contact law throttle_linux learned (start-up routine, then online tracking),\n"
                 "# written at its last clean stop and read at its next start (app.stops_file).\n"
                 "model.phi_closed_rad = %.9g\nmodel.phi_open_rad = %.9g\nmodel.k_stop_Nm_rad = %.9g\n"
                 "model.stop_exponent = %.9g\nmodel.d_stop_Nm_s_rad = %.9g\n",
                 phi_closed_rad, phi_open_rad, k_stop, stop_exponent, d_stop) > 0;
    if (ok && fit_base_r_ohm > 0.0 && fit_base_nke_V_s > 0.0 && isfinite(fit_base_r_ohm) && isfinite(fit_base_nke_V_s)) {
        ok = fprintf(f,
                     "# the voltage equation's fit's per-unit baseline (learned healthy: diag.fit_base_windows)\n"
                     "diag.fit_base_r_ohm = %.9g\ndiag.fit_base_nke_V_s = %.9g\n",
                     fit_base_r_ohm, fit_base_nke_V_s) > 0;
    }
    ok = ok && fflush(f) == 0 && fsync(fileno(f)) == 0;
    if (fclose(f) != 0) {
        ok = 0;
    }
    if (!ok || rename(tmp, path) != 0) {
        lx_err_set(err, err_len, "%s: cannot write: %s", path, strerror(errno));
        (void)remove(tmp);
        return TV_ERR_IO;
    }
    return TV_OK;
}

void lx_config_apply_app(const lx_config_t *cfg, app_config_t *app)
{
    if (cfg == NULL || app == NULL) {
        return;
    }
    app->control.mode = (app_mode_t)cfg->app_mode;
    app->control.amplitude_V = (tv_real_t)cfg->app_amplitude_V;
    app->control.freq_Hz = (tv_real_t)cfg->app_freq_Hz;
    app->control.chirp_f1_Hz = (tv_real_t)cfg->app_chirp_f1_Hz;
    app->control.chirp_period_s = (tv_real_t)cfg->app_chirp_period_s;
    app->control.target_rad = (tv_real_t)cfg->app_target_rad;
    app->control.duty_limit = (tv_real_t)cfg->app_duty_limit;
    app->calib.current_offset_counts = (tv_real_t)cfg->calib_current_offset_counts;
    app->calib.current_A_per_count = (tv_real_t)cfg->calib_current_A_per_count;
    app->calib.tps1_counts_at_zero = (tv_real_t)cfg->calib_tps1_counts_at_zero;
    app->calib.tps1_rad_per_count = (tv_real_t)cfg->calib_tps1_rad_per_count;
    app->calib.tps2_counts_at_zero = (tv_real_t)cfg->calib_tps2_counts_at_zero;
    app->calib.tps2_rad_per_count = (tv_real_t)cfg->calib_tps2_rad_per_count;
    app->calib.supply_V_per_count = (tv_real_t)cfg->calib_supply_V_per_count;
    app->calib.adc_max_counts = (uint16_t)cfg->dev.adc_max_counts;
    {
        /* the model keys given; Q follows the model, as in a parameter file (params.h) */
        const int any = real_keys_copy(cfg, s_model_keys, N_MODEL_KEYS, &app->model);
        if (!isnan(cfg->model_phi_closed_rad) || !isnan(cfg->model_phi_open_rad)) {
            /* stops given (configuration or app.stops_file): known, so the envelope of
             * never-learned stops is off (stop_track.h) */
            app->stop_track.envelope = 0u;
        }
        if (any) {
            /* an invalid model fails here and again, with its status, in app_init() */
            (void)ekf_q_from_spectral(&app->model, app->ekf.qu_V2_s, app->ekf.qT_Nm2_s, app->ekf.Q);
        }
        (void)real_keys_copy(cfg, s_sl_keys, N_SL_KEYS, &app->stop_learn);
        if (cfg->diag_identified != 0) {
            diag_detect_config_identified(&app->diag);
        }
        (void)real_keys_copy(cfg, s_diag_keys, N_DIAG_KEYS, &app->diag);
        app->diag.fit_base_windows = cfg->diag_fit_base_windows;
    }
}
