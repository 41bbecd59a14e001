/**
 * @file paper_filter.c
 * @brief The paper's EKF as printed, for comparison only (see paper_filter.h). Deliberately
 *        keeps the paper's errors; do not "fix" anything here, fix it in firmware/ instead.
 */
#include "paper_filter.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "tv_paper.h"
#include "tv_status.h"

#define PAPER_PI 3.14159265358979323846

static int paper_finite(double v)
{
    return v == v && v - v == 0.0;
}

void paper_filter_config_default(paper_filter_config_t *cfg)
{
    int a;
    int b;
    if (cfg == NULL) {
        return;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->R_ohm = TV_PAPER_R_OHM;
    cfg->L_H = TV_PAPER_L_H;
    cfg->Ke_V_s_rad = TV_PAPER_KE_V_S_RAD;
    cfg->Kt_Nm_A = TV_PAPER_KT_NM_A;
    cfg->J_kg_m2 = TV_PAPER_J_KG_M2;
    cfg->n_gear = TV_PAPER_N_GEAR;
    cfg->Mc_Nm = TV_PAPER_MC_NM;
    cfg->M0_Nm = TV_PAPER_M0_NM;
    cfg->c_Nm_rad = TV_PAPER_C_NM_RAD;
    cfg->Kv_Nm_s_rad = TV_PAPER_KV_NM_S_RAD;
    cfg->Ms_Nm = TV_PAPER_MS_NM;
    cfg->ws_rad_s = TV_PAPER_WS_RAD_S;
    cfg->Ts_s = TV_PAPER_TS_S;
    cfg->sign_gain = 1e3;
    cfg->predict = PAPER_PREDICT_EQ21;
    cfg->jacobian = PAPER_JACOBIAN_EQ27;
    for (a = 0; a < PAPER_NX; ++a) {
        cfg->x0[a] = 0.0;
        for (b = 0; b < PAPER_NX; ++b) {
            cfg->P0[a][b] = a == b ? 100.0 : 0.0;
            cfg->Q[a][b] = a == b ? 0.01 : 0.0;
        }
    }
    cfg->r[0] = 1e-4;
    cfg->r[1] = 1.0;
    cfg->r[2] = 1e-8;
    cfg->x_abs_max[0] = 1e3;
    cfg->x_abs_max[1] = 1e4;
    cfg->x_abs_max[2] = 1e3;
    cfg->var_max = 1e12;
}

int paper_filter_init(paper_filter_t *pf, const paper_filter_config_t *cfg)
{
    size_t k;
    if (pf == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    {
        const double v[] = {cfg->R_ohm, cfg->L_H, cfg->Ke_V_s_rad, cfg->Kt_Nm_A, cfg->J_kg_m2, cfg->n_gear,
                            cfg->Mc_Nm, cfg->M0_Nm, cfg->c_Nm_rad, cfg->Kv_Nm_s_rad, cfg->Ms_Nm, cfg->ws_rad_s,
                            cfg->Ts_s, cfg->sign_gain, cfg->var_max};
        for (k = 0; k < sizeof v / sizeof v[0]; ++k) {
            if (!paper_finite(v[k])) {
                return TV_ERR_NONFINITE;
            }
        }
    }
    for (k = 0; k < PAPER_NX; ++k) {
        size_t j;
        if (!paper_finite(cfg->x0[k]) || !paper_finite(cfg->r[k]) || !paper_finite(cfg->x_abs_max[k])) {
            return TV_ERR_NONFINITE;
        }
        for (j = 0; j < PAPER_NX; ++j) {
            if (!paper_finite(cfg->P0[k][j]) || !paper_finite(cfg->Q[k][j])) {
                return TV_ERR_NONFINITE;
            }
        }
        if (!(cfg->r[k] > 0.0) || !(cfg->x_abs_max[k] > 0.0) || cfg->P0[k][k] < 0.0 || cfg->Q[k][k] < 0.0) {
            return TV_ERR_CONFIG;
        }
    }
    if (!(cfg->L_H > 0.0) || !(cfg->J_kg_m2 > 0.0) || !(cfg->Ts_s > 0.0) || !(cfg->sign_gain > 0.0) ||
        !(cfg->ws_rad_s > 0.0) || !(cfg->var_max > 0.0) ||
        (cfg->predict != PAPER_PREDICT_EQ21 && cfg->predict != PAPER_PREDICT_EQ12) ||
        (cfg->jacobian != PAPER_JACOBIAN_EQ27 && cfg->jacobian != PAPER_JACOBIAN_EQ12_EXACT)) {
        return TV_ERR_CONFIG;
    }
    memset(pf, 0, sizeof *pf);
    pf->cfg = *cfg;
    memcpy(pf->x, cfg->x0, sizeof pf->x);
    memcpy(&pf->P, &cfg->P0, sizeof pf->P);
    return TV_OK;
}

/* sign(x) ~ (2/pi) atan(a x), section 3.3 */
static double paper_sign(const paper_filter_config_t *c, double x)
{
    return 2.0 / PAPER_PI * atan(c->sign_gain * x);
}

void paper_filter_f_eq12(const paper_filter_config_t *c, const double x[PAPER_NX], double u_V,
                         double x_next[PAPER_NX])
{
    double i;
    double w;
    double phi;
    double Ts;
    if (c == NULL || x == NULL || x_next == NULL) {
        return;
    }
    i = x[0];
    w = x[1];
    phi = x[2];
    Ts = c->Ts_s;
    /* eq. 12, term by term; M_Stop omitted (never defined in the paper) */
    x_next[0] = i - c->R_ohm / c->L_H * i * Ts - c->n_gear * c->Ke_V_s_rad / c->L_H * w * Ts + 1.0 / c->L_H * u_V * Ts;
    x_next[1] = c->n_gear * c->Kt_Nm_A / c->J_kg_m2 * i * Ts + w - c->Kv_Nm_s_rad / c->J_kg_m2 * w * Ts -
                c->c_Nm_rad / c->J_kg_m2 * phi * Ts - c->M0_Nm / c->J_kg_m2 * paper_sign(c, phi) * Ts -
                1.0 / c->J_kg_m2 * (c->Mc_Nm + (c->Ms_Nm - c->Mc_Nm) * exp(-fabs(w) / c->ws_rad_s)) *
                    paper_sign(c, w) * Ts;
    x_next[2] = w * Ts + phi;
}

void paper_filter_phi_eq27(const paper_filter_config_t *c, const double x[PAPER_NX],
                           double Phi[PAPER_NX][PAPER_NX])
{
    double Ts;
    double w;
    double phi;
    double a;
    if (c == NULL || x == NULL || Phi == NULL) {
        return;
    }
    Ts = c->Ts_s;
    w = x[1];
    phi = x[2];
    a = c->sign_gain; /* the printed 10^3 and 10^6 are a and a^2 */
    Phi[0][0] = 1.0 - c->R_ohm / c->L_H * Ts;
    Phi[0][1] = c->n_gear * c->Ke_V_s_rad / c->L_H * Ts; /* printed positive */
    Phi[0][2] = 0.0;
    Phi[1][0] = c->n_gear * c->Kt_Nm_A / c->J_kg_m2 * Ts;
    Phi[1][1] = 1.0 - c->Kv_Nm_s_rad / c->J_kg_m2 * Ts -
                a * Ts * (c->Mc_Nm + (c->Ms_Nm - c->Mc_Nm)) / (c->J_kg_m2 * PAPER_PI * (1.0 + a * a * w * w)) *
                    exp(-fabs(w / c->ws_rad_s));
    Phi[1][2] = -c->c_Nm_rad / c->J_kg_m2 * Ts -
                a * Ts * c->M0_Nm / (c->J_kg_m2 * PAPER_PI * (1.0 + a * a * phi * phi)) * Ts; /* extra Ts as printed */
    Phi[2][0] = 0.0;
    Phi[2][1] = Ts;
    Phi[2][2] = 1.0;
}

void paper_filter_phi_eq12_exact(const paper_filter_config_t *c, const double x[PAPER_NX],
                                 double Phi[PAPER_NX][PAPER_NX])
{
    double Ts;
    double w;
    double phi;
    double a;
    double e;
    double g;
    double dg;
    double ds_w;
    double ds_phi;
    if (c == NULL || x == NULL || Phi == NULL) {
        return;
    }
    Ts = c->Ts_s;
    w = x[1];
    phi = x[2];
    a = c->sign_gain;
    e = exp(-fabs(w) / c->ws_rad_s);
    g = c->Mc_Nm + (c->Ms_Nm - c->Mc_Nm) * e;
    dg = -(c->Ms_Nm - c->Mc_Nm) / c->ws_rad_s * (w > 0.0 ? 1.0 : (w < 0.0 ? -1.0 : 0.0)) * e;
    ds_w = 2.0 / PAPER_PI * a / (1.0 + a * a * w * w);
    ds_phi = 2.0 / PAPER_PI * a / (1.0 + a * a * phi * phi);
    Phi[0][0] = 1.0 - c->R_ohm / c->L_H * Ts;
    Phi[0][1] = -c->n_gear * c->Ke_V_s_rad / c->L_H * Ts;
    Phi[0][2] = 0.0;
    Phi[1][0] = c->n_gear * c->Kt_Nm_A / c->J_kg_m2 * Ts;
    Phi[1][1] = 1.0 - c->Kv_Nm_s_rad / c->J_kg_m2 * Ts - Ts / c->J_kg_m2 * (dg * paper_sign(c, w) + g * ds_w);
    Phi[1][2] = -c->c_Nm_rad / c->J_kg_m2 * Ts - c->M0_Nm / c->J_kg_m2 * ds_phi * Ts;
    Phi[2][0] = 0.0;
    Phi[2][1] = Ts;
    Phi[2][2] = 1.0;
}

/* Reset to x0, P0 when the filter has left any sane range (not in the paper; see the header). */
static void paper_guard(paper_filter_t *pf, int force)
{
    int bad = force;
    int a;
    int b;
    for (a = 0; a < PAPER_NX && !bad; ++a) {
        if (!paper_finite(pf->x[a]) || fabs(pf->x[a]) > pf->cfg.x_abs_max[a] || !(pf->P[a][a] <= pf->cfg.var_max)) {
            bad = 1;
        }
        for (b = 0; b < PAPER_NX && !bad; ++b) {
            if (!paper_finite(pf->P[a][b])) {
                bad = 1;
            }
        }
    }
    if (bad) {
        memcpy(pf->x, pf->cfg.x0, sizeof pf->x);
        memcpy(&pf->P, &pf->cfg.P0, sizeof pf->P);
        ++pf->n_resets;
    }
}

int paper_filter_predict(paper_filter_t *pf, double u_V)
{
    double Phi[PAPER_NX][PAPER_NX];
    double xn[PAPER_NX];
    double T[PAPER_NX][PAPER_NX];
    int a;
    int b;
    int k;
    if (pf == NULL) {
        return TV_ERR_NULL;
    }
    if (!paper_finite(u_V)) {
        return TV_ERR_NONFINITE;
    }
    if (pf->cfg.jacobian == PAPER_JACOBIAN_EQ27) {
        paper_filter_phi_eq27(&pf->cfg, pf->x, Phi);
    } else {
        paper_filter_phi_eq12_exact(&pf->cfg, pf->x, Phi);
    }
    if (pf->cfg.predict == PAPER_PREDICT_EQ21) {
        /* eq. 21: x^- = Phi x + G u, G = Ts B = (Ts / L, 0, 0) */
        for (a = 0; a < PAPER_NX; ++a) {
            xn[a] = 0.0;
            for (k = 0; k < PAPER_NX; ++k) {
                xn[a] += Phi[a][k] * pf->x[k];
            }
        }
        xn[0] += pf->cfg.Ts_s / pf->cfg.L_H * u_V;
    } else {
        paper_filter_f_eq12(&pf->cfg, pf->x, u_V, xn);
    }
    /* eq. 22: P^- = Phi P Phi^T + Q */
    for (a = 0; a < PAPER_NX; ++a) {
        for (b = 0; b < PAPER_NX; ++b) {
            T[a][b] = 0.0;
            for (k = 0; k < PAPER_NX; ++k) {
                T[a][b] += Phi[a][k] * pf->P[k][b];
            }
        }
    }
    for (a = 0; a < PAPER_NX; ++a) {
        for (b = 0; b < PAPER_NX; ++b) {
            double s = pf->cfg.Q[a][b];
            for (k = 0; k < PAPER_NX; ++k) {
                s += T[a][k] * Phi[b][k];
            }
            pf->P[a][b] = s;
        }
    }
    memcpy(pf->x, xn, sizeof pf->x);
    ++pf->n_predict;
    paper_guard(pf, 0);
    return TV_OK;
}

/* Inverse of a general 3x3 matrix by the adjugate; 0 when singular or not finite. */
static int paper_inv3(double A[PAPER_NX][PAPER_NX], double Ai[PAPER_NX][PAPER_NX])
{
    double det;
    int a;
    int b;
    Ai[0][0] = A[1][1] * A[2][2] - A[1][2] * A[2][1];
    Ai[0][1] = A[0][2] * A[2][1] - A[0][1] * A[2][2];
    Ai[0][2] = A[0][1] * A[1][2] - A[0][2] * A[1][1];
    Ai[1][0] = A[1][2] * A[2][0] - A[1][0] * A[2][2];
    Ai[1][1] = A[0][0] * A[2][2] - A[0][2] * A[2][0];
    Ai[1][2] = A[0][2] * A[1][0] - A[0][0] * A[1][2];
    Ai[2][0] = A[1][0] * A[2][1] - A[1][1] * A[2][0];
    Ai[2][1] = A[0][1] * A[2][0] - A[0][0] * A[2][1];
    Ai[2][2] = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    det = A[0][0] * Ai[0][0] + A[0][1] * Ai[1][0] + A[0][2] * Ai[2][0];
    if (!paper_finite(det) || det == 0.0) {
        return 0;
    }
    for (a = 0; a < PAPER_NX; ++a) {
        for (b = 0; b < PAPER_NX; ++b) {
            Ai[a][b] /= det;
            if (!paper_finite(Ai[a][b])) {
                return 0;
            }
        }
    }
    return 1;
}

int paper_filter_correct(paper_filter_t *pf, const double z[PAPER_NX], double innov[PAPER_NX])
{
    double S[PAPER_NX][PAPER_NX];
    double Si[PAPER_NX][PAPER_NX];
    double K[PAPER_NX][PAPER_NX];
    double Pn[PAPER_NX][PAPER_NX];
    double y[PAPER_NX];
    int a;
    int b;
    int k;
    if (pf == NULL || z == NULL) {
        return TV_ERR_NULL;
    }
    for (a = 0; a < PAPER_NX; ++a) {
        if (!paper_finite(z[a])) {
            return TV_ERR_NONFINITE;
        }
    }
    /* eq. 30 residual and eq. 18 gain with H = I */
    for (a = 0; a < PAPER_NX; ++a) {
        y[a] = z[a] - pf->x[a];
        if (innov != NULL) {
            innov[a] = y[a];
        }
        for (b = 0; b < PAPER_NX; ++b) {
            S[a][b] = pf->P[a][b] + (a == b ? pf->cfg.r[a] : 0.0);
        }
    }
    if (!paper_inv3(S, Si)) {
        paper_guard(pf, 1);
        ++pf->n_correct;
        return TV_OK;
    }
    for (a = 0; a < PAPER_NX; ++a) {
        for (b = 0; b < PAPER_NX; ++b) {
            K[a][b] = 0.0;
            for (k = 0; k < PAPER_NX; ++k) {
                K[a][b] += pf->P[a][k] * Si[k][b];
            }
        }
    }
    /* eq. 19 */
    for (a = 0; a < PAPER_NX; ++a) {
        for (k = 0; k < PAPER_NX; ++k) {
            pf->x[a] += K[a][k] * y[k];
        }
    }
    /* eq. 20: P = (I - K H) P^- */
    for (a = 0; a < PAPER_NX; ++a) {
        for (b = 0; b < PAPER_NX; ++b) {
            double s = pf->P[a][b];
            for (k = 0; k < PAPER_NX; ++k) {
                s -= K[a][k] * pf->P[k][b];
            }
            Pn[a][b] = s;
        }
    }
    for (a = 0; a < PAPER_NX; ++a) {
        for (b = 0; b < PAPER_NX; ++b) {
            pf->P[a][b] = Pn[a][b];
        }
    }
    ++pf->n_correct;
    paper_guard(pf, 0);
    return TV_OK;
}
