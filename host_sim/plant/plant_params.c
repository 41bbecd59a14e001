/**
 * @file plant_params.c
 * @brief Plant parameter files (see plant_params.h).
 */
#include "plant_params.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tv_status.h"

typedef struct {
    const char *key;
    size_t off;
} plant_key_t;

#define PK(f) {"plant." #f, offsetof(plant_config_t, f)}
static const plant_key_t s_keys[] = {
    PK(R_ohm), PK(L_H), PK(Ke_V_s_rad), PK(Kt_Nm_A), PK(J_kg_m2), PK(n_gear), PK(Mc_Nm), PK(Ms_Nm),
    PK(ws_rad_s), PK(Kv_Nm_s_rad), PK(M0_Nm), PK(c_Nm_rad), PK(limp_home_width_rad), PK(phi_closed_rad),
    PK(phi_open_rad), PK(stop_k_Nm_rad), PK(stop_exponent), PK(stop_lambda_Nm_s_rad), PK(supply_V),
    PK(diode_drop_V), PK(current_offset_V), PK(current_gain_V_A), PK(current_noise_A), PK(tps_supply_V),
    PK(tps_offset_frac), PK(tps_span_frac), PK(tps_ref_closed_rad), PK(tps_ref_open_rad), PK(angle_noise_rad),
    PK(tps_noise_V), PK(tps_divider_gain), PK(supply_divider_gain), PK(supply_noise_V), PK(adc_ref_V),
};
#define NKEYS (sizeof s_keys / sizeof s_keys[0])

static void msg(char *err, size_t cap, const char *fmt, ...)
{
    if (err != NULL && cap > 0u) {
        va_list ap;
        va_start(ap, fmt);
        /* va_start is right above: a false positive of clang-analyzer-valist.Uninitialized */
        (void)vsnprintf(err, cap, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized) */
        va_end(ap);
    }
}

static char *trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t' || *s == '\r') {
        ++s;
    }
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r')) {
        *--e = '\0';
    }
    return s;
}

int plant_params_parse(const char *text, size_t n, const char *name, plant_config_t *cfg, char *err, size_t cap)
{
    plant_config_t c;
    unsigned long seen[NKEYS];
    unsigned long line_no = 0;
    size_t pos = 0;
    int st = TV_OK;
    const char *bad;
    if (text == NULL || cfg == NULL || name == NULL) {
        return TV_ERR_NULL;
    }
    c = *cfg;
    memset(seen, 0, sizeof seen);
    while (pos < n) {
        char line[PLANT_PARAMS_LINE_MAX + 1u];
        size_t len = 0;
        char *s;
        char *eq;
        char *key;
        char *val;
        char *end = NULL;
        double v;
        size_t k;
        ++line_no;
        while (pos < n && text[pos] != '\n') {
            if (text[pos] == '\0') {
                msg(err, cap, "%s:%lu: NUL byte in the line (not a text parameter file)", name, line_no);
                return TV_ERR_FORMAT;
            }
            if (len >= PLANT_PARAMS_LINE_MAX) {
                msg(err, cap, "%s:%lu: line longer than %u bytes", name, line_no, PLANT_PARAMS_LINE_MAX);
                return TV_ERR_FORMAT;
            }
            line[len++] = text[pos++];
        }
        ++pos; /* the newline */
        line[len] = '\0';
        s = strchr(line, '#');
        if (s != NULL) {
            *s = '\0';
        }
        s = trim(line);
        if (*s == '\0') {
            continue;
        }
        eq = strchr(s, '=');
        if (eq == NULL) {
            msg(err, cap, "%s:%lu: expected 'key = value', got '%.60s'", name, line_no, s);
            return TV_ERR_FORMAT;
        }
        *eq = '\0';
        key = trim(s);
        val = trim(eq + 1);
        for (k = 0; k < NKEYS; ++k) {
            if (strcmp(key, s_keys[k].key) == 0) {
                break;
            }
        }
        if (k == NKEYS) {
            msg(err, cap, "%s:%lu: unknown key '%.60s' (plant keys are plant.FIELD, see plant_params_write)", name,
                line_no, key);
            return TV_ERR_FORMAT;
        }
        if (seen[k] != 0u) {
            msg(err, cap, "%s:%lu: duplicate key '%s' (first set on line %lu)", name, line_no, key, seen[k]);
            return TV_ERR_FORMAT;
        }
        seen[k] = line_no;
        if (*val == '\0' || strchr(val, 'x') != NULL || strchr(val, 'X') != NULL) {
            msg(err, cap, "%s:%lu: %s = '%.60s' is not a decimal number", name, line_no, key, val);
            return TV_ERR_FORMAT;
        }
        errno = 0;
        v = strtod(val, &end);
        if (end == val || *end != '\0') {
            msg(err, cap, "%s:%lu: %s = '%.60s' is not a number", name, line_no, key, val);
            return TV_ERR_FORMAT;
        }
        if (errno == ERANGE || !(v == v) || v - v != 0.0) {
            msg(err, cap, "%s:%lu: %s = '%.60s' is not finite", name, line_no, key, val);
            return TV_ERR_NONFINITE;
        }
        memcpy((char *)&c + s_keys[k].off, &v, sizeof v);
    }
    bad = plant_config_check(&c, &st);
    if (bad != NULL) {
        size_t k;
        char where[64] = "";
        for (k = 0; k < NKEYS; ++k) {
            if (strcmp(s_keys[k].key + 6, bad) == 0 && seen[k] != 0u) {
                (void)snprintf(where, sizeof where, " (line %lu)", seen[k]);
            }
        }
        msg(err, cap, "%s: plant.%s%s: the plant refuses this value or combination (%s)", name, bad, where,
            tv_status_str(st));
        return st;
    }
    *cfg = c;
    return TV_OK;
}

int plant_params_load(const char *path, plant_config_t *cfg, char *err, size_t cap)
{
    static char s_buf[65536];
    size_t n;
    FILE *f;
    if (path == NULL) {
        return TV_ERR_NULL;
    }
    f = fopen(path, "rb");
    if (f == NULL) {
        msg(err, cap, "%s: cannot open: %s", path, strerror(errno));
        return TV_ERR_IO;
    }
    n = fread(s_buf, 1u, sizeof s_buf, f);
    if (ferror(f)) {
        (void)fclose(f);
        msg(err, cap, "%s: read error", path);
        return TV_ERR_IO;
    }
    if (n == sizeof s_buf && memchr(s_buf, '\0', n) == NULL) { /* a NUL byte: parse names it */
        (void)fclose(f);
        msg(err, cap, "%s: larger than %lu bytes (not a plant parameter file?)", path, (unsigned long)sizeof s_buf);
        return TV_ERR_FORMAT;
    }
    (void)fclose(f);
    return plant_params_parse(s_buf, n, path, cfg, err, cap);
}

int plant_params_write(FILE *f, const plant_config_t *cfg)
{
    size_t k;
    fputs("# Plant parameter file of host_sim --plant-params (host_sim/plant/plant_params.h): key = value.\n"
          "# Units and ranges: host_sim/plant/plant.h (plant_config_t). Every key is optional.\n",
          f);
    for (k = 0; k < NKEYS; ++k) {
        double v;
        memcpy(&v, (const char *)cfg + s_keys[k].off, sizeof v);
        char num[32];
        int prec;
        for (prec = 1; prec <= 17; ++prec) { /* the shortest text that reads back exactly */
            (void)snprintf(num, sizeof num, "%.*g", prec, v);
            if (strtod(num, NULL) == v) {
                break;
            }
        }
        fprintf(f, "%s = %s\n", s_keys[k].key, num);
    }
    return ferror(f) ? TV_ERR_IO : TV_OK;
}
