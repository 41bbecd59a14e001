/**
 * @file params.c
 * @brief `key = value` parameter files for host_sim and replay (see params.h).
 */
#include "params.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "ekf.h"
#include "tv_param_table.h"
#include "tv_status.h"

/* Key indices (the order of the table and of params_write()). */
enum {
    K_R = 0, K_L, K_KE, K_KT, K_J, K_N, K_MC, K_M0, K_C, K_KV, K_MS, K_WS, K_PHI_CLOSED, K_PHI_OPEN, K_K_STOP,
    K_D_STOP, K_STOP_EXP, K_E_PHI, K_E_W, K_SUBSTEPS,
    K_QU, K_QT, K_R_CURRENT, K_R_VELOCITY, K_R_ANGLE, K_CONTACT_BAND, K_QC, K_STOP_LEARN, K_QD_CONTACT, K_QD_FREE, K_D_TAU, K_CONTACT_GATE, K_CONTACT_COUPLING, K_QT_REL, K_IMPACT_TIMING, K_IL_ENABLE, K_IL_GAIN, K_SL_E_MIN, K_SL_E_MAX, K_SL_LAMBDA, K_SL_K_MIN, K_SL_K_MAX,
    K_QR, K_R_SIGMA0, K_DR_MAX, K_DR_EXCITE, K_QF, K_F_SIGMA0, K_F_MAX, K_F_EXCITE, K_QM, K_M_SIGMA0, K_M_MAX, K_NIS_ALPHA, K_NIS_TH, K_NIS_MAX, K_WHITE_TH, K_STUCK_Q_MIN, K_STUCK_HOLD, K_DIAG_IDENTIFIED, K_DIAG_R_FIT, K_DIAG_FRIC_HIGH, K_DIAG_FRIC_FAST, K_DIAG_FRIC_LEVEL,
    K_DIAG_FIT_BASE_R, K_DIAG_FIT_BASE_NKE, K_DIAG_FIT_BASE_WINDOWS, K_DIAG_R_FIT_BASE, K_DIAG_GAIN_FIT_BASE,
    K_CAL_CUR_OFF, K_CAL_CUR_GAIN, K_CAL_TPS1_ZERO, K_CAL_TPS1_GAIN, K_CAL_TPS2_ZERO, K_CAL_TPS2_GAIN, K_CAL_SUPPLY,
    K_LIM_CUR_MIN, K_LIM_CUR_MAX, K_LIM_TPS_MIN, K_LIM_TPS_MAX, K_LIM_DISAGREE, K_LIM_SUP_MIN, K_LIM_SUP_MAX,
    K_LIM_DEBOUNCE, K_LIM_MAX_GAP,
    K_COUNT
};

typedef char params_nkeys_matches[(K_COUNT == PARAMS_NKEYS) ? 1 : -1];

/* Keys, units, ranges and documentation: the project's one parameter table
 * (firmware/params/tv_param_table.h), in the order of the K_ ids above. */
typedef char params_table_matches[(K_COUNT == (int)TVP_COUNT) ? 1 : -1];

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

const char *params_key_name(int k)
{
    return k >= 0 && k < K_COUNT ? tvp_desc(k)->key : NULL;
}

int params_key_index(const char *name)
{
    int k;
    if (name == NULL) {
        return -1;
    }
    for (k = 0; k < K_COUNT; ++k) {
        if (strcmp(name, tvp_desc(k)->key) == 0) {
            return k;
        }
    }
    return -1;
}

void params_init(params_t *p, const char *file)
{
    if (p == NULL) {
        return;
    }
    memset(p, 0, sizeof *p);
    (void)snprintf(p->file, sizeof p->file, "%s", file != NULL ? file : "<params>");
}

int params_is_set(const params_t *p, const char *key)
{
    const int k = params_key_index(key);
    return p != NULL && k >= 0 && p->line[k] != 0u;
}

/* The range of key k as text, e.g. "(0, 1000]". */
static void range_text(int k, char *out, size_t cap)
{
    tvp_range_text(k, out, cap);
}

/* Check v against key k. 0 ok, else a status and a message "<where>: key = text ...". */
static int check_value(int k, double v, const char *text, const char *where, char *err, size_t cap)
{
    const int rc = tvp_check(k, v);
    char head[PARAMS_MSG_MAX];
    (void)snprintf(head, sizeof head, "%s: %s = %s", where, tvp_desc(k)->key, text);
    if (rc == -1) {
        msg(err, cap, "%s is not finite", head);
        return TV_ERR_NONFINITE;
    }
    if (rc == -3) {
        msg(err, cap, "%s is not an integer", head);
        return TV_ERR_FORMAT;
    }
    if (rc != 0) {
        char rng[96];
        range_text(k, rng, sizeof rng);
        msg(err, cap, "%s is out of range, allowed %s", head, rng);
        return TV_ERR_RANGE;
    }
    return TV_OK;
}

/* One line (NUL-terminated, no newline). */
static int parse_line(params_t *p, unsigned long line_no, char *s, char *err, size_t cap)
{
    char where[PARAMS_NAME_MAX + 32];
    char *key;
    char *eq;
    char *val;
    char *end = NULL;
    size_t n;
    double v;
    int k;
    int rc;
    (void)snprintf(where, sizeof where, "%s:%lu", p->file, line_no);
    /* strip a comment and surrounding blanks */
    {
        char *hash = strchr(s, '#');
        if (hash != NULL) {
            *hash = '\0';
        }
    }
    while (*s == ' ' || *s == '\t' || *s == '\r') {
        ++s;
    }
    n = strlen(s);
    while (n > 0u && (s[n - 1u] == ' ' || s[n - 1u] == '\t' || s[n - 1u] == '\r')) {
        s[--n] = '\0';
    }
    if (n == 0u) {
        return TV_OK;
    }
    eq = strchr(s, '=');
    if (eq == NULL) {
        msg(err, cap, "%s:%lu: expected 'key = value', found '%.60s'", p->file, line_no, s);
        return TV_ERR_FORMAT;
    }
    key = s;
    val = eq + 1;
    *eq = '\0';
    n = strlen(key);
    while (n > 0u && (key[n - 1u] == ' ' || key[n - 1u] == '\t')) {
        key[--n] = '\0';
    }
    while (*val == ' ' || *val == '\t') {
        ++val;
    }
    if (n == 0u) {
        msg(err, cap, "%s:%lu: missing key before '=' (value '%.60s')", p->file, line_no, val);
        return TV_ERR_FORMAT;
    }
    k = params_key_index(key);
    if (k < 0) {
        msg(err, cap, "%s:%lu: unknown key '%.80s' (replay --print-params lists the keys)", p->file, line_no, key);
        return TV_ERR_FORMAT;
    }
    if (*val == '\0') {
        msg(err, cap, "%s:%lu: key '%s' has no value", p->file, line_no, tvp_desc(k)->key);
        return TV_ERR_FORMAT;
    }
    if (p->line[k] != 0u) {
        char first[32];
        (void)snprintf(first, sizeof first, "%lu", (unsigned long)p->line[k]);
        msg(err, cap, "%s:%lu: duplicate key '%s' (first set on line %s)", p->file, line_no, tvp_desc(k)->key, first);
        return TV_ERR_FORMAT;
    }
    errno = 0;
    v = strtod(val, &end);
    if (end == val || *end != '\0') {
        msg(err, cap, "%s:%lu: %s = %.60s is not a number", p->file, line_no, tvp_desc(k)->key, val);
        return TV_ERR_FORMAT;
    }
    if (errno == ERANGE && (v - v != 0.0)) {
        v = v > 0.0 ? 1e308 * 10.0 : -1e308 * 10.0; /* overflow: reported as not finite */
    }
    rc = check_value(k, v, val, where, err, cap);
    if (rc != TV_OK) {
        return rc;
    }
    p->value[k] = v;
    p->line[k] = (uint32_t)(line_no > 0xFFFFFFFFul ? 0xFFFFFFFFul : line_no);
    return TV_OK;
}

/* One raw line of len bytes (may hold NULs, no newline): bounded copy, checks, parse. */
static int handle_line(params_t *p, unsigned long line_no, const char *raw, size_t len, char *err, size_t cap)
{
    char line[PARAMS_LINE_MAX + 1u];
    if (len > PARAMS_LINE_MAX) {
        msg(err, cap, "%s:%lu: line longer than %u bytes", p->file, line_no, PARAMS_LINE_MAX);
        return TV_ERR_FORMAT;
    }
    if (len > 0u && memchr(raw, '\0', len) != NULL) {
        msg(err, cap, "%s:%lu: NUL byte in the line (binary data?)", p->file, line_no);
        return TV_ERR_FORMAT;
    }
    if (len > 0u) {
        memcpy(line, raw, len);
    }
    line[len] = '\0';
    return parse_line(p, line_no, line, err, cap);
}

int params_parse_text(params_t *p, const char *text, size_t n, char *err, size_t cap)
{
    size_t pos = 0;
    unsigned long line_no = 0;
    if (p == NULL || (text == NULL && n > 0u)) {
        return TV_ERR_NULL;
    }
    while (pos < n) {
        const char *nl = (const char *)memchr(text + pos, '\n', n - pos);
        const size_t len = nl != NULL ? (size_t)(nl - (text + pos)) : n - pos;
        const int rc = handle_line(p, ++line_no, text + pos, len, err, cap);
        if (rc != TV_OK) {
            return rc;
        }
        pos += len + 1u;
    }
    return TV_OK;
}

int params_load(params_t *p, const char *path, char *err, size_t cap)
{
    char line[PARAMS_LINE_MAX + 1u];
    size_t len = 0;
    size_t total = 0; /* length of the current line, also beyond the buffer */
    unsigned long line_no = 0;
    FILE *f;
    int rc = TV_OK;
    if (p == NULL || path == NULL) {
        return TV_ERR_NULL;
    }
    f = fopen(path, "rb");
    if (f == NULL) {
        msg(err, cap, "%s: cannot open: %s", path, strerror(errno));
        return TV_ERR_IO;
    }
    while (rc == TV_OK) {
        const int c = fgetc(f);
        if (c == EOF || c == '\n') {
            if (c == EOF && total == 0u) {
                break;
            }
            rc = handle_line(p, ++line_no, line, total, err, cap);
            len = total = 0u;
            if (c == EOF) {
                break;
            }
            continue;
        }
        if (c == '\0') {
            msg(err, cap, "%s:%lu: NUL byte in the line (not a text parameter file)", path, line_no + 1u);
            rc = TV_ERR_FORMAT;
            break;
        }
        if (len < sizeof line) {
            line[len++] = (char)c;
        }
        ++total;
        if (total > PARAMS_LINE_MAX) {
            /* stop at once: a file without newlines (e.g. /dev/zero) would be read forever */
            msg(err, cap, "%s:%lu: line longer than %u bytes", path, line_no + 1u, PARAMS_LINE_MAX);
            rc = TV_ERR_FORMAT;
            break;
        }
    }
    if (rc == TV_OK && ferror(f)) {
        msg(err, cap, "%s: read error", path);
        rc = TV_ERR_IO;
    }
    (void)fclose(f);
    return rc;
}

int params_set(params_t *p, const char *key, double value, char *err, size_t cap)
{
    char text[40];
    int k;
    int rc;
    if (p == NULL || key == NULL) {
        return TV_ERR_NULL;
    }
    k = params_key_index(key);
    if (k < 0) {
        msg(err, cap, "unknown key '%s'", key);
        return TV_ERR_FORMAT;
    }
    (void)snprintf(text, sizeof text, "%.17g", value);
    rc = check_value(k, value, text, "command line", err, cap);
    if (rc != TV_OK) {
        return rc;
    }
    p->value[k] = value;
    p->line[k] = 0xFFFFFFFFu; /* set, not from a file line */
    return TV_OK;
}

/* Where key k was set, for cross-field messages. */
static void origin(const params_t *p, int k, char *out, size_t cap)
{
    if (p->line[k] == 0xFFFFFFFFu) {
        (void)snprintf(out, cap, "%s (command line)", tvp_desc(k)->key);
    } else if (p->line[k] != 0u) {
        (void)snprintf(out, cap, "%s (%s:%lu)", tvp_desc(k)->key, p->file, (unsigned long)p->line[k]);
    } else {
        (void)snprintf(out, cap, "%s (default)", tvp_desc(k)->key);
    }
}

/* Rule a <= b (strict: a < b) on the applied configuration; message names both keys. */
static int rule(const params_t *p, int ka, double a, int kb, double b, int strict, char *err, size_t cap)
{
    char oa[PARAMS_NAME_MAX + 64];
    char ob[PARAMS_NAME_MAX + 64];
    if (strict ? a < b : a <= b) {
        return TV_OK;
    }
    origin(p, ka, oa, sizeof oa);
    origin(p, kb, ob, sizeof ob);
    /* the values as written where they were given (not their float rounding) */
    msg(err, cap, "%s: %s = %.9g must be %s %s = %.9g", p->file, oa, p->line[ka] != 0u ? p->value[ka] : a,
        strict ? "<" : "<=", ob, p->line[kb] != 0u ? p->value[kb] : b);
    return TV_ERR_RANGE;
}

/* tv_real_t of v; fails when the scalar type cannot hold it (float overflow or underflow to 0). */
static int to_real(const params_t *p, int k, tv_real_t *out, char *err, size_t cap)
{
    const double v = p->value[k];
    const tv_real_t r = (tv_real_t)v;
    if (!TV_IS_FINITE(r) || (v != 0.0 && r == TV_R(0.0))) {
        char o[PARAMS_NAME_MAX + 64];
        origin(p, k, o, sizeof o);
        msg(err, cap, "%s: %s = %.9g cannot be represented in this build's scalar type", p->file, o, v);
        return TV_ERR_RANGE;
    }
    *out = r;
    return TV_OK;
}

/* Destination of real key k in cfg, NULL for the integer and noise-density keys. */
static tv_real_t *real_field(app_config_t *c, int k)
{
    switch (k) {
    case K_R: return &c->model.R_ohm;
    case K_L: return &c->model.L_H;
    case K_KE: return &c->model.Ke_V_s_rad;
    case K_KT: return &c->model.Kt_Nm_A;
    case K_J: return &c->model.J_kg_m2;
    case K_N: return &c->model.n_gear;
    case K_MC: return &c->model.Mc_Nm;
    case K_M0: return &c->model.M0_Nm;
    case K_C: return &c->model.c_Nm_rad;
    case K_KV: return &c->model.Kv_Nm_s_rad;
    case K_MS: return &c->model.Ms_Nm;
    case K_WS: return &c->model.ws_rad_s;
    case K_PHI_CLOSED: return &c->model.phi_closed_rad;
    case K_PHI_OPEN: return &c->model.phi_open_rad;
    case K_K_STOP: return &c->model.k_stop_Nm_rad;
    case K_D_STOP: return &c->model.d_stop_Nm_s_rad;
    case K_STOP_EXP: return &c->model.stop_exponent;
    case K_E_PHI: return &c->model.e_phi_rad;
    case K_E_W: return &c->model.e_w_rad_s;
    case K_R_CURRENT: return &c->ekf.r[EKF_CH_CURRENT];
    case K_R_VELOCITY: return &c->ekf.r[EKF_CH_VELOCITY];
    case K_R_ANGLE: return &c->ekf.r[EKF_CH_ANGLE];
    case K_CONTACT_BAND: return &c->ekf.contact_band_rad;
    case K_QC: return &c->ekf.qc_Nm2_s;
    case K_STOP_LEARN: return &c->ekf.stop_learn_margin_rad;
    case K_QD_CONTACT: return &c->ekf.qd_contact_Nm2_s;
    case K_QD_FREE: return &c->ekf.qd_free_Nm2_s;
    case K_D_TAU: return &c->ekf.d_tau_s;
    case K_CONTACT_GATE: return &c->ekf.contact_nis_gate;
    case K_CONTACT_COUPLING: return &c->ekf.contact_w_coupling;
    case K_QT_REL: return &c->ekf.qT_rel_s;
    case K_IMPACT_TIMING: return &c->ekf.impact_timing;
    case K_IL_GAIN: return &c->impact_learn.gain;
    case K_SL_E_MIN: return &c->stop_learn.e_min;
    case K_SL_E_MAX: return &c->stop_learn.e_max;
    case K_SL_LAMBDA: return &c->stop_learn.lambda_per_k_s_rad;
    case K_SL_K_MIN: return &c->stop_learn.k_min;
    case K_SL_K_MAX: return &c->stop_learn.k_max;
    case K_DIAG_R_FIT: return &c->diag.r_fit_high_frac;
    case K_DIAG_FRIC_HIGH: return &c->diag.friction_high_rel;
    case K_DIAG_FRIC_FAST: return &c->diag.friction_fast_high;
    case K_DIAG_FRIC_LEVEL: return &c->diag.friction_fast_level_min;
    case K_DIAG_FIT_BASE_R: return &c->diag.fit_base_r_ohm;
    case K_DIAG_FIT_BASE_NKE: return &c->diag.fit_base_nke_V_s;
    case K_DIAG_R_FIT_BASE: return &c->diag.r_fit_base_high_frac;
    case K_DIAG_GAIN_FIT_BASE: return &c->diag.gain_fit_base_max;
    case K_QR: return &c->ekf.qr_ohm2_s;
    case K_R_SIGMA0: return &c->ekf.r_sigma0_ohm;
    case K_DR_MAX: return &c->ekf.dr_abs_max_ohm;
    case K_DR_EXCITE: return &c->ekf.dr_excite_A;
    case K_QF: return &c->ekf.qf_1_s;
    case K_F_SIGMA0: return &c->ekf.f_sigma0;
    case K_F_MAX: return &c->ekf.f_abs_max;
    case K_F_EXCITE: return &c->ekf.f_excite_rad_s;
    case K_QM: return &c->ekf.qm_1_s;
    case K_M_SIGMA0: return &c->ekf.m_sigma0;
    case K_M_MAX: return &c->ekf.m_abs_max;
    case K_NIS_ALPHA: return &c->ekf.nis_inflate_alpha;
    case K_NIS_TH: return &c->ekf.nis_inflate_threshold;
    case K_NIS_MAX: return &c->ekf.nis_inflate_max;
    case K_WHITE_TH: return &c->ekf.white_threshold;
    case K_STUCK_Q_MIN: return &c->ekf.stuck_q_min;
    case K_STUCK_HOLD: return &c->ekf.stuck_hold_frac;
    case K_CAL_CUR_OFF: return &c->calib.current_offset_counts;
    case K_CAL_CUR_GAIN: return &c->calib.current_A_per_count;
    case K_CAL_TPS1_ZERO: return &c->calib.tps1_counts_at_zero;
    case K_CAL_TPS1_GAIN: return &c->calib.tps1_rad_per_count;
    case K_CAL_TPS2_ZERO: return &c->calib.tps2_counts_at_zero;
    case K_CAL_TPS2_GAIN: return &c->calib.tps2_rad_per_count;
    case K_CAL_SUPPLY: return &c->calib.supply_V_per_count;
    case K_LIM_DISAGREE: return &c->limits.tps_disagree_max_rad;
    case K_LIM_SUP_MIN: return &c->limits.supply_min_V;
    case K_LIM_SUP_MAX: return &c->limits.supply_max_V;
    default: return NULL;
    }
}

/* Destination of integer key k (16-bit fields), NULL otherwise. */
static uint16_t *u16_field(app_config_t *c, int k)
{
    switch (k) {
    case K_LIM_CUR_MIN: return &c->limits.current_min_counts;
    case K_LIM_CUR_MAX: return &c->limits.current_max_counts;
    case K_LIM_TPS_MIN: return &c->limits.tps_min_counts;
    case K_LIM_TPS_MAX: return &c->limits.tps_max_counts;
    case K_LIM_DEBOUNCE: return &c->limits.debounce_trip;
    case K_LIM_MAX_GAP: return &c->limits.max_gap_periods;
    case K_DIAG_FIT_BASE_WINDOWS: return &c->diag.fit_base_windows;
    default: return NULL;
    }
}

int params_apply(const params_t *p, app_config_t *cfg, char *err, size_t cap)
{
    app_config_t c;
    int model_set = 0;
    int k;
    int rc;
    if (p == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    c = *cfg;
    for (k = 0; k < K_COUNT; ++k) {
        tv_real_t *rf;
        uint16_t *uf;
        if (p->line[k] == 0u) {
            continue;
        }
        if (k <= K_SUBSTEPS) {
            model_set = 1;
        }
        rf = real_field(&c, k);
        uf = u16_field(&c, k);
        if (rf != NULL) {
            rc = to_real(p, k, rf, err, cap);
            if (rc != TV_OK) {
                return rc;
            }
        } else if (uf != NULL) {
            *uf = (uint16_t)p->value[k];
        } else if (k == K_SUBSTEPS) {
            c.model.substeps = (int)p->value[k];
        } else if (k == K_IL_ENABLE) {
            c.impact_learn.enable = (uint8_t)p->value[k];
        } else if (k == K_DIAG_IDENTIFIED) {
            /* the unit's own model: the diagnostic bounds relative to it; 0: the class's */
            if (p->value[k] != 0.0) {
                diag_detect_config_identified(&c.diag);
            } else {
                diag_detect_config_default(&c.diag);
            }
        }
    }
    if (p->line[K_PHI_CLOSED] != 0u || p->line[K_PHI_OPEN] != 0u) {
        /* a file that names the stops gives known (learned or identified) stops: the envelope of
         * never-learned stops is off (stop_track.h) */
        c.stop_track.envelope = 0u;
    }
    rc = rule(p, K_MC, (double)c.model.Mc_Nm, K_MS, (double)c.model.Ms_Nm, 0, err, cap);
    if (rc == TV_OK) {
        rc = rule(p, K_LIM_CUR_MIN, (double)c.limits.current_min_counts, K_LIM_CUR_MAX,
                  (double)c.limits.current_max_counts, 1, err, cap);
    }
    if (rc == TV_OK) {
        rc = rule(p, K_LIM_TPS_MIN, (double)c.limits.tps_min_counts, K_LIM_TPS_MAX, (double)c.limits.tps_max_counts,
                  1, err, cap);
    }
    if (rc == TV_OK) {
        rc = rule(p, K_LIM_SUP_MIN, (double)c.limits.supply_min_V, K_LIM_SUP_MAX, (double)c.limits.supply_max_V, 1,
                  err, cap);
    }
    if (rc == TV_OK) {
        rc = rule(p, K_SL_E_MIN, (double)c.stop_learn.e_min, K_SL_E_MAX, (double)c.stop_learn.e_max, 0, err, cap);
    }
    if (rc == TV_OK) {
        rc = rule(p, K_SL_K_MIN, (double)c.stop_learn.k_min, K_SL_K_MAX, (double)c.stop_learn.k_max, 1, err, cap);
    }
    if (rc != TV_OK) {
        return rc;
    }
    if (model_set || p->line[K_QU] != 0u || p->line[K_QT] != 0u) {
        /* from the densities in force (an earlier file's, or the defaults), not the defaults:
         * a model-only file applied on top of one that set them keeps them */
        tv_real_t qu = c.ekf.qu_V2_s;
        tv_real_t qT = c.ekf.qT_Nm2_s;
        if (p->line[K_QU] != 0u) {
            rc = to_real(p, K_QU, &qu, err, cap);
        }
        if (rc == TV_OK && p->line[K_QT] != 0u) {
            rc = to_real(p, K_QT, &qT, err, cap);
        }
        if (rc == TV_OK) {
            rc = ekf_q_from_spectral(&c.model, qu, qT, c.ekf.Q);
            c.ekf.qu_V2_s = qu;
            c.ekf.qT_Nm2_s = qT;
            if (rc != TV_OK) {
                msg(err, cap, "%s: Q from qu, qT and the model: %s", p->file, tv_status_str(rc));
            }
        }
        if (rc != TV_OK) {
            return rc;
        }
    }
    *cfg = c;
    return TV_OK;
}

/* The shortest %.Ng (N = 1..17) that reads back as exactly v: 4.3, not 4.2999999999999998. */
static void shortest_g(char *out, size_t cap, double v)
{
    int prec;
    for (prec = 1; prec <= 17; ++prec) {
        (void)snprintf(out, cap, "%.*g", prec, v);
        if (strtod(out, NULL) == v) {
            return;
        }
    }
}

int params_write(FILE *f, const app_config_t *cfg)
{
    app_config_t c;
    int k;
    if (f == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    c = *cfg;
    fputs("# Parameter file of host_sim and replay (host_sim/replay/params.h, LOG_FORMATS.md): key = value.\n"
          "# Every key is optional; a key not given keeps its default.\n",
          f);
    for (k = 0; k < K_COUNT; ++k) {
        const tv_real_t *rf = real_field(&c, k);
        const uint16_t *uf = u16_field(&c, k);
        char rng[96];
        char num[32];
        double v;
        if (k == K_R || k == K_QU || k == K_DIAG_IDENTIFIED || k == K_CAL_CUR_OFF || k == K_LIM_CUR_MIN) {
            fputs(k == K_R ? "\n# estimator model (firmware/estimator/tv_model.h)\n"
                  : k == K_DIAG_IDENTIFIED ? "\n# diagnostic bounds (firmware/diag/diag_detect.h)\n"
                  : k == K_QU ? "\n# estimator noise: process-noise densities and measurement VARIANCES (firmware/estimator/ekf.h)\n"
                  : k == K_CAL_CUR_OFF ? "\n# count calibration (firmware/app/app.h, app_calib_t); replay takes it from the log unless set here\n"
                                       : "\n# plausibility limits (firmware/app/app.h, app_limits_t)\n",
                  f);
        }
        if (rf != NULL) {
            v = (double)*rf;
        } else if (uf != NULL) {
            v = (double)*uf;
        } else if (k == K_SUBSTEPS) {
            v = (double)c.model.substeps;
        } else if (k == K_IL_ENABLE) {
            v = (double)c.impact_learn.enable;
        } else if (k == K_DIAG_IDENTIFIED) {
            v = (double)c.diag.identified;
        } else if (k == K_QU) {
            v = (double)c.ekf.qu_V2_s; /* the density in force (a file's, else the default) */
        } else {
            v = (double)c.ekf.qT_Nm2_s;
        }
        range_text(k, rng, sizeof rng);
        shortest_g(num, sizeof num, v);
        fprintf(f, "%s = %s    # [%s] %s; %s\n", tvp_desc(k)->key, num, tvp_desc(k)->unit, rng, tvp_desc(k)->doc);
    }
    return ferror(f) ? TV_ERR_IO : TV_OK;
}

void params_calib_to_header(const app_calib_t *c, rawlog_header_t *h)
{
    h->current_offset_counts = (double)c->current_offset_counts;
    h->current_A_per_count = (double)c->current_A_per_count;
    h->tps1_counts_at_zero = (double)c->tps1_counts_at_zero;
    h->tps1_rad_per_count = (double)c->tps1_rad_per_count;
    h->tps2_counts_at_zero = (double)c->tps2_counts_at_zero;
    h->tps2_rad_per_count = (double)c->tps2_rad_per_count;
    h->supply_V_per_count = (double)c->supply_V_per_count;
}
