/**
 * @file plant_fault.c
 * @brief Fault specifications: parser, list, schedule (see plant_fault.h).
 */
#include "plant_fault.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tv_status.h"

/** How a kind's magnitude enters plant_faults_t. */
typedef enum {
    PF_FACTOR,    /**< a multiplicative factor: 1 + a (m - 1) */
    PF_ADDITIVE,  /**< an additive size: a m */
    PF_SWITCH     /**< no magnitude: on at any level > 0 */
} pf_shape_t;

/** One row of the kind table. */
typedef struct {
    const char *name;
    const char *fault_class;
    const char *help;
    double lo;      /**< magnitude > lo (or >= lo when lo_incl) */
    double hi;      /**< magnitude <= hi (< hi when not hi_incl) */
    pf_shape_t shape;
    int lo_incl;
    int hi_incl;
    int signed_mag; /**< 1: |magnitude| is checked against (lo, hi], the sign is free */
    int ramp_ok;    /**< 1: a ramp is allowed */
} pf_kind_info_t;

static const pf_kind_info_t s_kinds[PLANT_FAULT_KIND_COUNT] = {
    {"friction_high", "friction_high", "factor on Coulomb Mc and static Ms [-], (1, 10]", 1.0, 10.0, PF_FACTOR, 0, 1, 0, 1},
    {"jam", "jam", "holding torque [N m], (0, 100]; no ramp", 0.0, 100.0, PF_ADDITIVE, 0, 1, 0, 0},
    {"spring_weak", "spring_weak", "remaining fraction of preload M0 and rate c [-], [0, 1)", 0.0, 1.0, PF_FACTOR, 1, 0, 0, 1},
    {"winding_resistance_high", "winding_resistance_high", "factor on R [-], (1, 10]", 1.0, 10.0, PF_FACTOR, 0, 1, 0, 1},
    {"winding_open", "winding_open", "no magnitude; no ramp", 0.0, 0.0, PF_SWITCH, 0, 1, 0, 0},
    {"winding_short", "winding_short", "shorted fraction of the turns [-], (0, 0.9]", 0.0, 0.9, PF_ADDITIVE, 0, 1, 0, 1},
    {"tps1_offset", "tps1_fault", "offset [% of the sensor supply], signed, 0 < |m| <= 50", 0.0, 50.0, PF_ADDITIVE, 0, 1, 1, 1},
    {"tps1_gain", "tps1_fault", "gain error [%], signed, 0 < |m|, -100 < m <= 100", 0.0, 100.0, PF_ADDITIVE, 0, 1, 1, 1},
    {"tps1_stuck", "tps1_fault", "no magnitude; no ramp", 0.0, 0.0, PF_SWITCH, 0, 1, 0, 0},
    {"tps1_intermittent", "tps1_fault", "probability per conversion of reading 0 V [-], (0, 1]", 0.0, 1.0, PF_ADDITIVE, 0, 1, 0, 1},
    {"tps2_offset", "tps2_fault", "offset [% of the sensor supply], signed, 0 < |m| <= 50", 0.0, 50.0, PF_ADDITIVE, 0, 1, 1, 1},
    {"tps2_gain", "tps2_fault", "gain error [%], signed, 0 < |m|, -100 < m <= 100", 0.0, 100.0, PF_ADDITIVE, 0, 1, 1, 1},
    {"tps2_stuck", "tps2_fault", "no magnitude; no ramp", 0.0, 0.0, PF_SWITCH, 0, 1, 0, 0},
    {"tps2_intermittent", "tps2_fault", "probability per conversion of reading 0 V [-], (0, 1]", 0.0, 1.0, PF_ADDITIVE, 0, 1, 0, 1},
    {"current_offset", "current_sensor_fault", "offset referred to the winding current [A], signed, 0 < |m| <= 10", 0.0, 10.0, PF_ADDITIVE, 0, 1, 1, 1},
    {"current_gain", "current_sensor_fault", "gain error [%], signed, 0 < |m|, -100 < m <= 100", 0.0, 100.0, PF_ADDITIVE, 0, 1, 1, 1},
    {"bridge_pos_lost", "bridge_fault", "no magnitude; no ramp (positive duty gives 0 V)", 0.0, 0.0, PF_SWITCH, 0, 1, 0, 0},
    {"bridge_neg_lost", "bridge_fault", "no magnitude; no ramp (negative duty gives 0 V)", 0.0, 0.0, PF_SWITCH, 0, 1, 0, 0},
    {"supply_sag", "supply_sag", "drop of the bridge supply [V], (0, 100], below the unit's supply", 0.0, 100.0, PF_ADDITIVE, 0, 1, 0, 1},
};

const char *plant_fault_kind_name(plant_fault_kind_t kind)
{
    return (unsigned)kind < (unsigned)PLANT_FAULT_KIND_COUNT ? s_kinds[kind].name : "?";
}

const char *plant_fault_kind_class(plant_fault_kind_t kind)
{
    return (unsigned)kind < (unsigned)PLANT_FAULT_KIND_COUNT ? s_kinds[kind].fault_class : "?";
}

const char *plant_fault_kind_help(plant_fault_kind_t kind)
{
    return (unsigned)kind < (unsigned)PLANT_FAULT_KIND_COUNT ? s_kinds[kind].help : "?";
}

/* printf into msg (if any); returns rc. */
static int pf_fail(char *msg, size_t cap, int rc, const char *fmt, ...)
{
    if (msg != NULL && cap > 0u) {
        va_list ap;
        va_start(ap, fmt);
        /* va_start is right above: a false positive of clang-analyzer-valist.Uninitialized (as in params.c) */
        (void)vsnprintf(msg, cap, fmt, ap); /* NOLINT(clang-analyzer-valist.Uninitialized) */
        va_end(ap);
    }
    return rc;
}

/* A decimal number filling [s, s + n): TV_OK, TV_ERR_FORMAT or TV_ERR_NONFINITE. */
static int pf_number(const char *s, size_t n, double *out)
{
    char buf[64];
    char *end = NULL;
    double v;
    if (n == 0u || n >= sizeof buf) {
        return TV_ERR_FORMAT;
    }
    memcpy(buf, s, n);
    buf[n] = '\0';
    if (buf[0] == ' ' || buf[0] == '\t') {
        return TV_ERR_FORMAT;
    }
    v = strtod(buf, &end);
    if (end == buf || *end != '\0') {
        return TV_ERR_FORMAT;
    }
    if (!isfinite(v)) {
        return TV_ERR_NONFINITE;
    }
    *out = v;
    return TV_OK;
}

int plant_fault_parse(const char *text, plant_fault_spec_t *out, char *msg, size_t cap)
{
    const char *at;
    const char *colon;
    const char *ramp_colon;
    size_t name_len;
    int kind = -1;
    int k;
    int rc;
    plant_fault_spec_t f;
    const pf_kind_info_t *info;
    if (text == NULL || out == NULL) {
        return pf_fail(msg, cap, TV_ERR_NULL, "no specification");
    }
    at = strchr(text, '@');
    if (at == NULL) {
        return pf_fail(msg, cap, TV_ERR_FORMAT, "'%s': expected KIND[:MAGNITUDE]@T_S[:RAMP_S] (no '@')", text);
    }
    if (strchr(at + 1, '@') != NULL) {
        return pf_fail(msg, cap, TV_ERR_FORMAT, "'%s': more than one '@'", text);
    }
    colon = memchr(text, ':', (size_t)(at - text));
    name_len = (size_t)((colon != NULL ? colon : at) - text);
    for (k = 0; k < (int)PLANT_FAULT_KIND_COUNT; ++k) {
        if (strlen(s_kinds[k].name) == name_len && strncmp(text, s_kinds[k].name, name_len) == 0) {
            kind = k;
            break;
        }
    }
    if (kind < 0) {
        return pf_fail(msg, cap, TV_ERR_FORMAT, "'%.*s' is not a fault kind (host_sim --help lists them)", (int)name_len, text);
    }
    info = &s_kinds[kind];
    f.kind = (plant_fault_kind_t)kind;
    f.magnitude = 1.0;
    f.ramp_s = 0.0;
    if (info->shape == PF_SWITCH) {
        if (colon != NULL) {
            return pf_fail(msg, cap, TV_ERR_FORMAT, "%s takes no magnitude (write %s@T_S)", info->name, info->name);
        }
    } else {
        if (colon == NULL) {
            return pf_fail(msg, cap, TV_ERR_FORMAT, "%s needs a magnitude: %s:MAGNITUDE@T_S, %s", info->name, info->name, info->help);
        }
        rc = pf_number(colon + 1, (size_t)(at - colon - 1), &f.magnitude);
        if (rc != TV_OK) {
            return pf_fail(msg, cap, rc, "%s: magnitude '%.*s' is not a finite number", info->name, (int)(at - colon - 1), colon + 1);
        }
        {
            const double m = info->signed_mag ? fabs(f.magnitude) : f.magnitude;
            const int lo_ok = info->lo_incl ? m >= info->lo : m > info->lo;
            const int hi_ok = info->hi_incl ? m <= info->hi : m < info->hi;
            const int gain_ok = !(kind == PLANT_FAULT_TPS1_GAIN || kind == PLANT_FAULT_TPS2_GAIN ||
                                  kind == PLANT_FAULT_CURRENT_GAIN) ||
                                f.magnitude > -100.0;
            if (!lo_ok || !hi_ok || !gain_ok) {
                return pf_fail(msg, cap, TV_ERR_RANGE, "%s: magnitude %g is out of range: %s", info->name, f.magnitude, info->help);
            }
        }
    }
    ramp_colon = strchr(at + 1, ':');
    rc = pf_number(at + 1, ramp_colon != NULL ? (size_t)(ramp_colon - at - 1) : strlen(at + 1), &f.t_s);
    if (rc != TV_OK) {
        return pf_fail(msg, cap, rc, "%s: onset time '%.*s' is not a finite number of seconds", info->name,
                       (int)(ramp_colon != NULL ? (size_t)(ramp_colon - at - 1) : strlen(at + 1)), at + 1);
    }
    if (f.t_s < 0.0 || f.t_s > PLANT_FAULT_T_MAX_S) {
        return pf_fail(msg, cap, TV_ERR_RANGE, "%s: onset time %g s is out of range (0 .. %g)", info->name, f.t_s, PLANT_FAULT_T_MAX_S);
    }
    if (ramp_colon != NULL) {
        if (!info->ramp_ok) {
            return pf_fail(msg, cap, TV_ERR_FORMAT, "%s cannot drift: no ramp (:RAMP_S) allowed", info->name);
        }
        rc = pf_number(ramp_colon + 1, strlen(ramp_colon + 1), &f.ramp_s);
        if (rc != TV_OK) {
            return pf_fail(msg, cap, rc, "%s: ramp '%s' is not a finite number of seconds", info->name, ramp_colon + 1);
        }
        if (!(f.ramp_s > 0.0) || f.ramp_s > PLANT_FAULT_T_MAX_S) {
            return pf_fail(msg, cap, TV_ERR_RANGE, "%s: ramp %g s is out of range (0 < RAMP_S <= %g)", info->name, f.ramp_s, PLANT_FAULT_T_MAX_S);
        }
    }
    *out = f;
    return TV_OK;
}

void plant_fault_list_clear(plant_fault_list_t *list)
{
    if (list != NULL) {
        memset(list, 0, sizeof *list);
    }
}

int plant_fault_list_add(plant_fault_list_t *list, const char *text, char *msg, size_t cap)
{
    plant_fault_spec_t f = {PLANT_FAULT_KIND_COUNT, 0.0, 0.0, 0.0};
    unsigned k;
    int rc;
    if (list == NULL) {
        return pf_fail(msg, cap, TV_ERR_NULL, "no list");
    }
    rc = plant_fault_parse(text, &f, msg, cap);
    if (rc != TV_OK) {
        return rc;
    }
    if (list->n >= PLANT_FAULT_LIST_MAX) {
        return pf_fail(msg, cap, TV_ERR_RANGE, "more than %u faults", PLANT_FAULT_LIST_MAX);
    }
    for (k = 0; k < list->n; ++k) {
        const plant_fault_kind_t o = list->spec[k].kind;
        if (o == f.kind) {
            return pf_fail(msg, cap, TV_ERR_RANGE, "%s given twice", plant_fault_kind_name(f.kind));
        }
        if ((o == PLANT_FAULT_BRIDGE_POS_LOST && f.kind == PLANT_FAULT_BRIDGE_NEG_LOST) ||
            (o == PLANT_FAULT_BRIDGE_NEG_LOST && f.kind == PLANT_FAULT_BRIDGE_POS_LOST)) {
            return pf_fail(msg, cap, TV_ERR_RANGE, "bridge_pos_lost and bridge_neg_lost together: the bridge drives nothing (use winding_open)");
        }
    }
    list->spec[list->n++] = f;
    return TV_OK;
}

double plant_fault_level(const plant_fault_spec_t *spec, double t_s)
{
    /* the tick grid: an onset within 1 ns of a tick is at that tick */
    const double eps_s = 1e-9;
    double a;
    if (spec == NULL || t_s < spec->t_s - eps_s) {
        return 0.0;
    }
    if (!(spec->ramp_s > 0.0)) {
        return 1.0;
    }
    a = (t_s - spec->t_s) / spec->ramp_s;
    return a < 0.0 ? 0.0 : (a > 1.0 ? 1.0 : a);
}

int plant_fault_at(const plant_fault_list_t *list, double t_s, double tps_supply_V, plant_faults_t *out)
{
    unsigned k;
    if (out == NULL) {
        return TV_ERR_NULL;
    }
    plant_faults_none(out);
    if (list == NULL) {
        return TV_OK;
    }
    for (k = 0; k < list->n && k < PLANT_FAULT_LIST_MAX; ++k) {
        const plant_fault_spec_t *s = &list->spec[k];
        const double a = plant_fault_level(s, t_s);
        const double m = s->magnitude;
        const double fac = 1.0 + a * (m - 1.0); /* PF_FACTOR */
        const double add = a * m;               /* PF_ADDITIVE */
        const int on = a > 0.0;
        if (a <= 0.0) {
            continue;
        }
        switch (s->kind) {
        case PLANT_FAULT_FRICTION_HIGH: out->friction_factor = fac; break;
        case PLANT_FAULT_JAM: out->jam_Nm = m; break; /* no ramp: on at full size */
        case PLANT_FAULT_SPRING_WEAK: out->spring_factor = fac; break;
        case PLANT_FAULT_WINDING_R_HIGH: out->resistance_factor = fac; break;
        case PLANT_FAULT_WINDING_OPEN: out->winding_open = on; break;
        case PLANT_FAULT_WINDING_SHORT: out->short_fraction = add; break;
        case PLANT_FAULT_TPS1_OFFSET: out->tps_offset_V[0] = add * 0.01 * tps_supply_V; break;
        case PLANT_FAULT_TPS1_GAIN: out->tps_gain_err[0] = add * 0.01; break;
        case PLANT_FAULT_TPS1_STUCK: out->tps_stuck[0] = on; break;
        case PLANT_FAULT_TPS1_INTERMITTENT: out->tps_dropout_prob[0] = add; break;
        case PLANT_FAULT_TPS2_OFFSET: out->tps_offset_V[1] = add * 0.01 * tps_supply_V; break;
        case PLANT_FAULT_TPS2_GAIN: out->tps_gain_err[1] = add * 0.01; break;
        case PLANT_FAULT_TPS2_STUCK: out->tps_stuck[1] = on; break;
        case PLANT_FAULT_TPS2_INTERMITTENT: out->tps_dropout_prob[1] = add; break;
        case PLANT_FAULT_CURRENT_OFFSET: out->current_offset_A = add; break;
        case PLANT_FAULT_CURRENT_GAIN: out->current_gain_err = add * 0.01; break;
        case PLANT_FAULT_BRIDGE_POS_LOST: out->bridge_lost = on ? 1 : out->bridge_lost; break;
        case PLANT_FAULT_BRIDGE_NEG_LOST: out->bridge_lost = on ? -1 : out->bridge_lost; break;
        case PLANT_FAULT_SUPPLY_SAG: out->supply_drop_V = add; break;
        case PLANT_FAULT_KIND_COUNT:
        default: break;
        }
    }
    return TV_OK;
}
