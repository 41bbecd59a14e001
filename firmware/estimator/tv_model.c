/**
 * @file tv_model.c
 * @brief Throttle-valve model and the sub-stepped, implicit-friction prediction map with its
 *        analytic Jacobian. The map is specified in tv_model.h.
 */
#include "tv_model.h"

#include "tv_paper.h"
#include "tv_status.h"

#include <stddef.h>
#include <string.h>

void tvm_params_default(tvm_params_t *p)
{
    if (p == NULL) {
        return;
    }
    p->R_ohm = (tv_real_t)TV_PAPER_R_OHM;
    p->L_H = (tv_real_t)TV_PAPER_L_H;
    p->Ke_V_s_rad = (tv_real_t)TV_PAPER_KE_V_S_RAD;
    p->Kt_Nm_A = (tv_real_t)TV_PAPER_KT_NM_A;
    p->J_kg_m2 = (tv_real_t)TV_PAPER_J_KG_M2;
    p->n_gear = (tv_real_t)TV_PAPER_N_GEAR;
    p->Mc_Nm = (tv_real_t)TV_PAPER_MC_NM;
    p->M0_Nm = (tv_real_t)TV_PAPER_M0_NM;
    p->c_Nm_rad = (tv_real_t)TV_PAPER_C_NM_RAD;
    p->Kv_Nm_s_rad = (tv_real_t)TV_PAPER_KV_NM_S_RAD;
    p->Ms_Nm = (tv_real_t)TV_PAPER_MS_NM;
    p->ws_rad_s = (tv_real_t)TV_PAPER_WS_RAD_S;
    p->phi_closed_rad = TV_R(-0.10);
    p->phi_open_rad = TV_R(1.3660766); /* -0.10 + 84 deg */
    p->k_stop_Nm_rad = TV_R(1.0e4);
    p->d_stop_Nm_s_rad = TV_R(2.4);
    p->stop_exponent = TV_R(0.0);
    p->e_phi_rad = TV_R(1.0e-4);
    p->e_w_rad_s = TV_R(1.0e-3);
    p->Ts_s = (tv_real_t)TV_PAPER_TS_S;
    p->substeps = 10;
}

static int positive(tv_real_t v) { return v > TV_R(0.0); }
static int nonneg(tv_real_t v) { return v >= TV_R(0.0); }

int tvm_init(tvm_t *m, const tvm_params_t *p)
{
    if (m == NULL || p == NULL) {
        return TV_ERR_NULL;
    }
    {
        const tv_real_t vals[] = {p->R_ohm,          p->L_H,           p->Ke_V_s_rad,    p->Kt_Nm_A,
                                  p->J_kg_m2,        p->n_gear,        p->Mc_Nm,         p->M0_Nm,
                                  p->c_Nm_rad,       p->Kv_Nm_s_rad,   p->Ms_Nm,         p->ws_rad_s,
                                  p->phi_closed_rad, p->phi_open_rad,  p->k_stop_Nm_rad, p->d_stop_Nm_s_rad,
                                  p->e_phi_rad,      p->e_w_rad_s,     p->Ts_s,          p->stop_exponent};
        size_t k;
        for (k = 0; k < sizeof vals / sizeof vals[0]; ++k) {
            if (!TV_IS_FINITE(vals[k])) {
                return TV_ERR_NONFINITE;
            }
        }
    }
    if (!positive(p->R_ohm) || !positive(p->L_H) || !nonneg(p->Ke_V_s_rad) || !nonneg(p->Kt_Nm_A) ||
        !positive(p->J_kg_m2) || !positive(p->n_gear) || !nonneg(p->Mc_Nm) || !nonneg(p->M0_Nm) ||
        !nonneg(p->c_Nm_rad) || !nonneg(p->Kv_Nm_s_rad) || p->Ms_Nm < p->Mc_Nm || !positive(p->ws_rad_s) ||
        !(p->phi_closed_rad < TV_R(0.0)) || !(p->phi_open_rad > TV_R(0.0)) || !nonneg(p->k_stop_Nm_rad) ||
        !nonneg(p->d_stop_Nm_s_rad) || !(p->stop_exponent == TV_R(0.0) ||
                                         (p->stop_exponent >= TV_R(1.0) && p->stop_exponent <= TV_R(3.0))) ||
        !positive(p->e_phi_rad) || !positive(p->e_w_rad_s) ||
        !positive(p->Ts_s) || p->substeps < 1 || p->substeps > TVM_SUBSTEPS_MAX) {
        return TV_ERR_CONFIG;
    }
    m->p = *p;
    m->h_s = p->Ts_s / (tv_real_t)p->substeps;
    m->a = TV_EXP(-p->R_ohm * m->h_s / p->L_H);
    m->b_A_V = (TV_R(1.0) - m->a) / p->R_ohm;
    m->h_J = m->h_s / p->J_kg_m2;
    m->kappa = TV_R(1.0) / (TV_R(1.0) + m->h_J * p->Kv_Nm_s_rad);
    m->nKt_Nm_A = p->n_gear * p->Kt_Nm_A;
    m->nKe_V_s = p->n_gear * p->Ke_V_s_rad;
    return TV_OK;
}

/* |w|_e = sqrt(w^2 + e^2) - e and its derivative w / sqrt(w^2 + e^2). */
static tv_real_t smooth_abs(tv_real_t w, tv_real_t e, tv_real_t *d_dw)
{
    const tv_real_t r = TV_SQRT(w * w + e * e);
    if (d_dw != NULL) {
        *d_dw = w / r;
    }
    return r - e;
}

/* g(w) and dg/dw. */
static tv_real_t friction_level(const tvm_t *m, tv_real_t w, tv_real_t *dg_dw)
{
    tv_real_t dabs;
    const tv_real_t aw = smooth_abs(w, m->p.e_w_rad_s, &dabs);
    const tv_real_t ex = TV_EXP_NEG(aw / m->p.ws_rad_s);
    const tv_real_t dM = m->p.Ms_Nm - m->p.Mc_Nm;
    if (dg_dw != NULL) {
        *dg_dw = -dM / m->p.ws_rad_s * ex * dabs;
    }
    return m->p.Mc_Nm + dM * ex;
}

tv_real_t tvm_friction_level(const tvm_t *m, tv_real_t w_rad_s)
{
    return friction_level(m, w_rad_s, NULL);
}

/* Stop torque and its partial derivatives (positive = opening); *peak (unless NULL) is raised to
 * the torque's magnitude in contact (only there, so free motion pays nothing for it). */
static tv_real_t stop_torque(const tvm_t *m, tv_real_t phi, tv_real_t w, tv_real_t *dT_dphi,
                             tv_real_t *dT_dw, tv_real_t *peak)
{
    const tv_real_t k = m->p.k_stop_Nm_rad;
    const tv_real_t d = m->p.d_stop_Nm_s_rad;
    tv_real_t torque = TV_R(0.0);
    tv_real_t dphi = TV_R(0.0);
    tv_real_t dw = TV_R(0.0);
    if (m->p.stop_exponent > TV_R(0.0)) {
        /* Hunt-Crossley: M = s p^e (k - s d w), s = +1 closed / -1 open, p = penetration */
        const tv_real_t e = m->p.stop_exponent;
        const tv_real_t s = phi < m->p.phi_closed_rad ? TV_R(1.0) : TV_R(-1.0);
        const tv_real_t p = phi < m->p.phi_closed_rad ? m->p.phi_closed_rad - phi : phi - m->p.phi_open_rad;
        if (p > TV_R(0.0)) {
            const tv_real_t pe = TV_POWP(p, e);
            const tv_real_t f = k - s * d * w;
            if (f > TV_R(0.0)) {
                torque = s * pe * f;
                dphi = -e * (pe / p) * f;
                dw = -d * pe;
                if (peak != NULL && pe * f > *peak) {
                    *peak = pe * f;
                }
            }
        }
    } else if (phi < m->p.phi_closed_rad) {
        const tv_real_t push = k * (m->p.phi_closed_rad - phi) - d * w;
        if (push > TV_R(0.0)) {
            torque = push;
            dphi = -k;
            dw = -d;
            if (peak != NULL && push > *peak) {
                *peak = push;
            }
        }
    } else if (phi > m->p.phi_open_rad) {
        const tv_real_t push = k * (phi - m->p.phi_open_rad) + d * w;
        if (push > TV_R(0.0)) {
            torque = -push;
            dphi = -k;
            dw = -d;
            if (peak != NULL && push > *peak) {
                *peak = push;
            }
        }
    }
    if (dT_dphi != NULL) {
        *dT_dphi = dphi;
    }
    if (dT_dw != NULL) {
        *dT_dw = dw;
    }
    return torque;
}

tv_real_t tvm_stop_torque(const tvm_t *m, tv_real_t phi_rad, tv_real_t w_rad_s)
{
    return stop_torque(m, phi_rad, w_rad_s, NULL, NULL, NULL);
}

/* Smoothed preload sign sp(phi) = phi / sqrt(phi^2 + e^2) and its derivative e^2 / r^3. */
static tv_real_t preload_sign(tv_real_t phi, tv_real_t e, tv_real_t *d_dphi)
{
    const tv_real_t r = TV_SQRT(phi * phi + e * e);
    if (d_dphi != NULL) {
        *d_dphi = (e * e) / (r * r * r);
    }
    return phi / r;
}

void tvm_step(const tvm_t *m, const tv_real_t x[TVM_NX], tv_real_t u_V, tv_real_t x_next[TVM_NX],
              tv_real_t F[TVM_NX][TVM_NX])
{
    tvm_step_dist(m, x, TV_R(0.0), u_V, x_next, F, NULL);
}

void tvm_step_dist(const tvm_t *m, const tv_real_t x[TVM_NX], tv_real_t d_Nm, tv_real_t u_V,
                   tv_real_t x_next[TVM_NX], tv_real_t F[TVM_NX][TVM_NX], tv_real_t G[TVM_NX])
{
    const tv_real_t a_in[TVM_NA] = {d_Nm, TV_R(0.0), TV_R(0.0), TV_R(0.0)};
    tv_real_t Gaug[TVM_NX][TVM_NA];
    tvm_step_aug(m, x, a_in, u_V, x_next, F, G != NULL ? Gaug : NULL, 1u << TVM_A_TORQUE);
    if (F != NULL && G != NULL) {
        G[0] = Gaug[0][TVM_A_TORQUE];
        G[1] = Gaug[1][TVM_A_TORQUE];
        G[2] = Gaug[2][TVM_A_TORQUE];
    }
}

/* One column q of G = dx/da through a sub-step: G <- S G + (di1/da, dw1/da, h dw1/da), with S's
 * structure as in tvm_step_aug() (row 0 = (a_i, di1/dw, 0), row 1 = s1, row 2 = e_phi + h row 1). */
static void chain_g(tv_real_t Ga[TVM_NX][TVM_NA], int q, tv_real_t a_i, tv_real_t di1_dw, const tv_real_t s1[TVM_NX],
                    tv_real_t h, tv_real_t di1_da, tv_real_t dw1_da)
{
    const tv_real_t g0 = a_i * Ga[0][q] + di1_dw * Ga[1][q] + di1_da;
    const tv_real_t g1 = s1[0] * Ga[0][q] + s1[1] * Ga[1][q] + s1[2] * Ga[2][q] + dw1_da;
    Ga[0][q] = g0;
    Ga[1][q] = g1;
    Ga[2][q] += h * g1;
}

void tvm_step_aug(const tvm_t *m, const tv_real_t x[TVM_NX], const tv_real_t a_in[TVM_NA], tv_real_t u_V,
                  tv_real_t x_next[TVM_NX], tv_real_t F[TVM_NX][TVM_NX], tv_real_t G[TVM_NX][TVM_NA],
                  unsigned g_cols)
{
    tvm_step_aug_peak(m, x, a_in, u_V, x_next, F, G, g_cols, NULL, NULL);
}

void tvm_step_aug_peak(const tvm_t *m, const tv_real_t x[TVM_NX], const tv_real_t a_in[TVM_NA], tv_real_t u_V,
                       tv_real_t x_next[TVM_NX], tv_real_t F[TVM_NX][TVM_NX], tv_real_t G[TVM_NX][TVM_NA],
                       unsigned g_cols, tv_real_t *peak_stop_Nm, tv_real_t *hold_frac)
{
    const tvm_params_t *p = &m->p;
    const tv_real_t d_Nm = a_in[TVM_A_TORQUE];
    const tv_real_t dR = a_in[TVM_A_DR];
    /* the friction error's torque f Mc: the level is g(w) + f Mc (Coulomb Mc (1 + f)) */
    const tv_real_t fMc = a_in[TVM_A_FRIC] * p->Mc_Nm;
    /* spring preload (1 + m) M0 */
    const tv_real_t M0 = p->M0_Nm * (TV_R(1.0) + a_in[TVM_A_PRELOAD]);
    /* current decay per sub-step with the resistance error taken explicitly */
    const tv_real_t a_i = m->a - m->b_A_V * dR;
    tv_real_t i = x[TVM_I];
    tv_real_t w = x[TVM_W];
    tv_real_t phi = x[TVM_PHI];
    tv_real_t Fa[TVM_NX][TVM_NX] = {{TV_R(1.0), TV_R(0.0), TV_R(0.0)},
                                    {TV_R(0.0), TV_R(1.0), TV_R(0.0)},
                                    {TV_R(0.0), TV_R(0.0), TV_R(1.0)}};
    /* d x / d a, accumulated through the sub-steps: Ga <- S Ga + (di1/da, dw1/da, h dw1/da) */
    tv_real_t Ga[TVM_NX][TVM_NA] = {{TV_R(0.0), TV_R(0.0), TV_R(0.0), TV_R(0.0)},
                                    {TV_R(0.0), TV_R(0.0), TV_R(0.0), TV_R(0.0)},
                                    {TV_R(0.0), TV_R(0.0), TV_R(0.0), TV_R(0.0)}};
    tv_real_t peak = TV_R(0.0);
    /* whether any sub-step slipped; the last one's friction reserve D - |z| and its D */
    tv_real_t res_min = TV_R(-1.0);
    tv_real_t res_D = TV_R(0.0);
    int any_slip = 0;
    int k;

    for (k = 0; k < p->substeps; ++k) {
        tv_real_t dsp;
        tv_real_t dMs_dphi;
        tv_real_t dMs_dw;
        tv_real_t dg_dw;
        const tv_real_t i1 = a_i * i + m->b_A_V * (u_V - m->nKe_V_s * w);
        const tv_real_t sp = preload_sign(phi, p->e_phi_rad, &dsp);
        const tv_real_t mstop = stop_torque(m, phi, w, &dMs_dphi, &dMs_dw, &peak);
        const tv_real_t torque = m->nKt_Nm_A * i1 - M0 * sp - p->c_Nm_rad * phi + mstop + d_Nm;
        const tv_real_t z = w + m->h_J * torque;
        const tv_real_t g_lvl = friction_level(m, w, &dg_dw);
        const tv_real_t D = m->h_J * (g_lvl + fMc);
        const tv_real_t az = TV_FABS(z);
        const int slipping = az > D;
        const tv_real_t sz = z >= TV_R(0.0) ? TV_R(1.0) : TV_R(-1.0);
        const tv_real_t w1 = slipping ? m->kappa * sz * (az - D) : TV_R(0.0);
        const tv_real_t phi1 = phi + m->h_s * w1;
        any_slip |= slipping;
        res_min = D - az;
        res_D = D;

        if (F != NULL) {
            /* Sub-step Jacobian S = d(i1, w1, phi1)/d(i, w, phi), chained as Fa <- S Fa. Its
             * structure is used: row 0 is (a_i, di1/dw, 0) (the armature does not see the angle),
             * row 1 is dw1/dx, row 2 is e_phi + h row 1 (phi1 = phi + h w1). So per column
             * T0 = a_i Fa0 + di1/dw Fa1, T1 = S1 . Fa, T2 = Fa2 + h T1: 18 multiply-adds instead
             * of the 27 of a full 3x3 product. The columns of G chain the same way, plus each
             * augmented input's direct effect on (i1, w1). */
            const tv_real_t di1_dw = -m->b_A_V * m->nKe_V_s;
            tv_real_t s1[TVM_NX] = {TV_R(0.0), TV_R(0.0), TV_R(0.0)};
            int c;
            if (slipping) {
                /* w1 = kappa (z - sz D(w)) */
                const tv_real_t dT_di = m->nKt_Nm_A * a_i;
                const tv_real_t dT_dw = m->nKt_Nm_A * di1_dw + dMs_dw;
                const tv_real_t dT_dphi = -M0 * dsp - p->c_Nm_rad + dMs_dphi;
                s1[0] = m->kappa * (m->h_J * dT_di);
                s1[1] = m->kappa * (TV_R(1.0) + m->h_J * dT_dw - sz * m->h_J * dg_dw);
                s1[2] = m->kappa * (m->h_J * dT_dphi);
            }
            for (c = 0; c < TVM_NX; ++c) {
                const tv_real_t t0 = a_i * Fa[0][c] + di1_dw * Fa[1][c];
                const tv_real_t t1 = s1[0] * Fa[0][c] + s1[1] * Fa[1][c] + s1[2] * Fa[2][c];
                Fa[0][c] = t0;
                Fa[1][c] = t1;
                Fa[2][c] += m->h_s * t1;
            }
            if (G != NULL) {
                /* direct effects of this sub-step: the torque acts on w1 alone; the resistance
                 * error on i1 (-b i) and, through the torque n Kt i1, on w1; the friction error
                 * on w1 through D (w1 = kappa (z - sz D), dD/df = (h / J) g). Only the columns
                 * asked for are computed. */
                const tv_real_t dw1_dT = slipping ? m->kappa * m->h_J : TV_R(0.0);
                if ((g_cols & (1u << TVM_A_TORQUE)) != 0u) {
                    chain_g(Ga, TVM_A_TORQUE, a_i, di1_dw, s1, m->h_s, TV_R(0.0), dw1_dT);
                }
                if ((g_cols & (1u << TVM_A_DR)) != 0u) {
                    const tv_real_t di1_ddr = -m->b_A_V * i;
                    chain_g(Ga, TVM_A_DR, a_i, di1_dw, s1, m->h_s, di1_ddr, dw1_dT * m->nKt_Nm_A * di1_ddr);
                }
                if ((g_cols & (1u << TVM_A_FRIC)) != 0u) {
                    chain_g(Ga, TVM_A_FRIC, a_i, di1_dw, s1, m->h_s, TV_R(0.0), -sz * dw1_dT * p->Mc_Nm);
                }
                if ((g_cols & (1u << TVM_A_PRELOAD)) != 0u) {
                    chain_g(Ga, TVM_A_PRELOAD, a_i, di1_dw, s1, m->h_s, TV_R(0.0), -dw1_dT * p->M0_Nm * sp);
                }
            }
        }
        i = i1;
        w = w1;
        phi = phi1;
    }
    if (peak_stop_Nm != NULL) {
        *peak_stop_Nm = peak;
    }
    if (hold_frac != NULL) {
        *hold_frac = !any_slip && res_D > TV_R(0.0) ? res_min / res_D : TV_R(-1.0);

    }
    x_next[TVM_I] = i;
    x_next[TVM_W] = w;
    x_next[TVM_PHI] = phi;
    if (F != NULL) {
        int r;
        int c;
        for (r = 0; r < TVM_NX; ++r) {
            for (c = 0; c < TVM_NX; ++c) {
                F[r][c] = Fa[r][c];
            }
        }
        if (G != NULL) {
            memcpy(G, Ga, sizeof Ga);
        }
    }
}
