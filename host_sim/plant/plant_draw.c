/**
 * @file plant_draw.c
 * @brief Throttle classes and seeded random units (see plant_draw.h for the ranges).
 */
#include "plant_draw.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "tv_status.h"

/** Penetration at which a drawn stop's secant stiffness is specified [rad]. */
#define DRAW_STOP_P_REF_RAD 0.0025

static const char *const s_class_names[PLANT_CLASS_COUNT] = {"a", "b"};
static const char *const s_spread_names[PLANT_SPREAD_COUNT] = {"none", "stops", "all"};

const char *plant_class_name(plant_class_t c)
{
    return (unsigned)c < (unsigned)PLANT_CLASS_COUNT ? s_class_names[c] : "?";
}

const char *plant_spread_name(plant_spread_t s)
{
    return (unsigned)s < (unsigned)PLANT_SPREAD_COUNT ? s_spread_names[s] : "?";
}

/* Index of name in names[0..n), or -1. */
static int name_index(const char *const *names, int n, const char *name)
{
    int k;
    for (k = 0; k < n; ++k) {
        if (strcmp(name, names[k]) == 0) {
            return k;
        }
    }
    return -1;
}

int plant_class_from_name(const char *name, plant_class_t *out)
{
    int k;
    if (name == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    k = name_index(s_class_names, (int)PLANT_CLASS_COUNT, name);
    if (k < 0) {
        return TV_ERR_RANGE;
    }
    *out = (plant_class_t)k;
    return TV_OK;
}

int plant_spread_from_name(const char *name, plant_spread_t *out)
{
    int k;
    if (name == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    k = name_index(s_spread_names, (int)PLANT_SPREAD_COUNT, name);
    if (k < 0) {
        return TV_ERR_RANGE;
    }
    *out = (plant_spread_t)k;
    return TV_OK;
}

int plant_class_nominal(plant_class_t c, plant_config_t *cfg)
{
    if (cfg == NULL) {
        return TV_ERR_NULL;
    }
    if ((unsigned)c >= (unsigned)PLANT_CLASS_COUNT) {
        return TV_ERR_RANGE;
    }
    plant_config_default(cfg);
    if (c == PLANT_CLASS_B) {
        cfg->R_ohm = 1.6;
        cfg->L_H = 1.0e-3;
        cfg->Ke_V_s_rad = 0.011;
        cfg->Kt_Nm_A = 0.011;
        cfg->J_kg_m2 = 1.2e-3;
        cfg->n_gear = 40.0;
        cfg->Mc_Nm = 0.15;
        cfg->Ms_Nm = 0.22;
        cfg->ws_rad_s = 1.5;
        cfg->Kv_Nm_s_rad = 0.008;
        cfg->M0_Nm = 0.32;
        cfg->c_Nm_rad = 0.09;
        cfg->phi_closed_rad = -0.08;
        cfg->phi_open_rad = 1.42;
        cfg->tps_ref_closed_rad = cfg->phi_closed_rad;
        cfg->tps_ref_open_rad = cfg->phi_open_rad;
        cfg->current_gain_V_A = 0.075;
    }
    return TV_OK;
}

/* splitmix64: a small, well-mixed generator; the draw needs a few dozen numbers. */
static uint64_t draw_next(uint64_t *x)
{
    uint64_t z = (*x += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

/* Uniform in [lo, hi). */
static double draw_u(uint64_t *x, double lo, double hi)
{
    const double u = (double)(draw_next(x) >> 11) * (1.0 / 9007199254740992.0);
    return lo + (hi - lo) * u;
}

/* Log-uniform in [lo, hi), lo > 0. */
static double draw_lu(uint64_t *x, double lo, double hi)
{
    return exp(draw_u(x, log(lo), log(hi)));
}

int plant_draw(plant_class_t c, plant_spread_t s, uint64_t unit_id, plant_config_t *cfg)
{
    plant_config_t p;
    uint64_t st;
    double k_eff;
    int rc;
    if (cfg == NULL) {
        return TV_ERR_NULL;
    }
    if ((unsigned)s >= (unsigned)PLANT_SPREAD_COUNT) {
        return TV_ERR_RANGE;
    }
    rc = plant_class_nominal(c, &p);
    if (rc != TV_OK) {
        return rc;
    }
    if (s == PLANT_SPREAD_NONE) {
        *cfg = p;
        return TV_OK;
    }
    /* One stream per (class, spread, unit): every quantity is drawn in a fixed order, whether
     * or not the spread uses it, so a unit's stops are the same in both spreads. */
    st = unit_id * UINT64_C(0x100000001B3) ^ ((uint64_t)c << 56) ^ UINT64_C(0x5EED0F7A11E5);
    (void)draw_next(&st);
    p.phi_closed_rad = draw_u(&st, -0.15, -0.05);
    p.phi_open_rad = draw_u(&st, 1.30, 1.50);
    k_eff = draw_lu(&st, 1e2, 1e5);
    p.stop_exponent = draw_u(&st, 1.0, 1.5);
    p.stop_k_Nm_rad = k_eff / pow(DRAW_STOP_P_REF_RAD, p.stop_exponent - 1.0);
    p.stop_lambda_Nm_s_rad = draw_lu(&st, 0.05, 0.5) * p.stop_k_Nm_rad;
    p.current_offset_V += draw_u(&st, -0.05, 0.05);
    p.current_gain_V_A *= draw_u(&st, 0.97, 1.03);
    p.tps_offset_frac = draw_u(&st, 0.085, 0.115);
    p.tps_span_frac = draw_u(&st, 0.78, 0.82);
    p.tps_ref_closed_rad = p.phi_closed_rad;
    p.tps_ref_open_rad = p.phi_open_rad;
    p.tps_supply_V *= draw_u(&st, 0.98, 1.02);
    p.tps_divider_gain *= draw_u(&st, 0.99, 1.01);
    p.supply_divider_gain *= draw_u(&st, 0.99, 1.01);
    p.supply_V += draw_u(&st, -1.0, 1.0);
    {
        /* motor, friction and springs: drawn always, used by PLANT_SPREAD_ALL */
        const double fR = draw_u(&st, 0.8, 1.2);
        const double fL = draw_u(&st, 0.8, 1.2);
        const double fK = draw_u(&st, 0.9, 1.1);
        const double fJ = draw_u(&st, 0.8, 1.2);
        const double fMc = draw_u(&st, 0.7, 1.3);
        const double fMs = draw_u(&st, 0.7, 1.3);
        const double fws = draw_lu(&st, 0.5, 2.0);
        const double fKv = draw_u(&st, 0.5, 1.5);
        const double fc = draw_u(&st, 0.8, 1.2);
        const double fM0 = draw_u(&st, 0.8, 1.2);
        if (s == PLANT_SPREAD_ALL) {
            p.R_ohm *= fR;
            p.L_H *= fL;
            p.Kt_Nm_A *= fK;
            p.Ke_V_s_rad *= fK;
            p.J_kg_m2 *= fJ;
            p.Mc_Nm *= fMc;
            p.Ms_Nm *= fMs;
            if (p.Ms_Nm < p.Mc_Nm) {
                p.Ms_Nm = p.Mc_Nm;
            }
            p.ws_rad_s *= fws;
            p.Kv_Nm_s_rad *= fKv;
            p.c_Nm_rad *= fc;
            p.M0_Nm *= fM0;
        }
    }
    /* drawn after everything above, so that the earlier draws of a unit did not change when it
     * was added: the limp-home detent's half-width (a contact, as the stops: both spreads) */
    p.limp_home_width_rad = draw_lu(&st, 3e-5, 3e-4);
    /* the integration step the draw needs (bounded: at most PLANT_SUBSTEPS_PER_MS_MAX / 25 tries) */
    while (plant_config_check(&p, &rc) != NULL) {
        if (rc != TV_ERR_CONFIG || p.substeps_per_ms + 25 > PLANT_SUBSTEPS_PER_MS_MAX) {
            return TV_ERR_CONFIG;
        }
        p.substeps_per_ms += 25;
    }
    *cfg = p;
    return TV_OK;
}
