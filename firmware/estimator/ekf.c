/**
 * @file ekf.c
 * @brief EKF predict / sequential-scalar Joseph-form correct for the throttle valve.
 */
#include "ekf.h"

#include "tv_status.h"

#include <stddef.h>
#include <string.h>

typedef tv_real_t mat3_t[TVM_NX][TVM_NX];

/* The 3x3 loops of the 1 kHz path are unrolled completely (GCC and clang honour this pragma;
 * -O2 alone keeps the loop control, ~40 % of the filter's instructions). */
#if defined(__GNUC__)
#define TV_UNROLL3 _Pragma("GCC unroll 3")
#else
#define TV_UNROLL3
#endif
#if defined(__GNUC__)
#define TV_UNROLL_NA _Pragma("GCC unroll 4")
#else
#define TV_UNROLL_NA
#endif

/* Matrices cross function boundaries as flat row-major pointers (C99 does not convert
 * T (*)[3] to const T (*)[3] implicitly). */
#define M3(A, r, c) ((A)[(r) * TVM_NX + (c)])


static int all_finite(const tv_real_t *v, int n)
{
    int k;
    for (k = 0; k < n; ++k) {
        if (!TV_IS_FINITE(v[k])) {
            return 0;
        }
    }
    return 1;
}

/* Relative symmetry test: |A_ab - A_ba| <= 1e-6 * (|A_ab| + |A_ba|) (+ exact zero). */
static int is_symmetric(const tv_real_t *A)
{
    int a;
    int b;
    for (a = 0; a < TVM_NX; ++a) {
        for (b = a + 1; b < TVM_NX; ++b) {
            const tv_real_t d = TV_FABS(M3(A, a, b) - M3(A, b, a));
            if (d > TV_R(1e-6) * (TV_FABS(M3(A, a, b)) + TV_FABS(M3(A, b, a)))) {
                return 0;
            }
        }
    }
    return 1;
}

/* All principal minors of a symmetric 3x3 matrix: > 0 (strict) or >= -tol (semi). */
static int principal_minors_ok(const tv_real_t *A, int strict)
{
    const tv_real_t m1[3] = {M3(A, 0, 0), M3(A, 1, 1), M3(A, 2, 2)};
    const tv_real_t m2[3] = {M3(A, 0, 0) * M3(A, 1, 1) - M3(A, 0, 1) * M3(A, 1, 0),
                             M3(A, 0, 0) * M3(A, 2, 2) - M3(A, 0, 2) * M3(A, 2, 0),
                             M3(A, 1, 1) * M3(A, 2, 2) - M3(A, 1, 2) * M3(A, 2, 1)};
    const tv_real_t det = M3(A, 0, 0) * (M3(A, 1, 1) * M3(A, 2, 2) - M3(A, 1, 2) * M3(A, 2, 1)) -
                          M3(A, 0, 1) * (M3(A, 1, 0) * M3(A, 2, 2) - M3(A, 1, 2) * M3(A, 2, 0)) +
                          M3(A, 0, 2) * (M3(A, 1, 0) * M3(A, 2, 1) - M3(A, 1, 1) * M3(A, 2, 0));
    /* Tolerance for the semidefinite case: rounding in products of the diagonal scale. */
    const tv_real_t scale = m1[0] * m1[1] * m1[2] + m1[0] * m1[1] + m1[0] * m1[2] + m1[1] * m1[2];
    const tv_real_t tol = TV_R(1e-6) * scale;
    int k;
    if (strict) {
        return m1[0] > TV_R(0.0) && m2[0] > TV_R(0.0) && det > TV_R(0.0);
    }
    for (k = 0; k < 3; ++k) {
        if (m1[k] < TV_R(0.0) || m2[k] < -tol) {
            return 0;
        }
    }
    return det >= -tol;
}

/* Hold the variances inside [floor, ceil]; a ceiling scales row and column (keeps correlations). */
static void apply_variance_bounds(mat3_t P, const tv_real_t floor_[TVM_NX], const tv_real_t ceil_[TVM_NX],
                                  uint32_t n_floor[TVM_NX], uint32_t n_ceil[TVM_NX])
{
    int a;
    int b;
    TV_UNROLL3
    for (a = 0; a < TVM_NX; ++a) {
        if (P[a][a] < floor_[a]) {
            P[a][a] = floor_[a];
            ++n_floor[a];
        } else if (P[a][a] > ceil_[a]) {
            ++n_ceil[a];
            const tv_real_t s = TV_SQRT(ceil_[a] / P[a][a]);
            TV_UNROLL3
            for (b = 0; b < TVM_NX; ++b) {
                P[a][b] *= s;
                P[b][a] *= s;
            }
        }
    }
}

/*
 * Health of a new estimate: x and P finite, positive variances, |P_ab| <= sqrt(P_aa P_bb) (a
 * cheap necessary condition of positive semi-definiteness). Finiteness is tested on the sum of
 * all twelve values: a sum is NaN or Inf when any term is, and a sum of finite values cannot
 * overflow here (the variance ceilings hold P far below the float range), so one test on the
 * 1 kHz path replaces twelve.
 */
static int estimate_sane(const tv_real_t *x, const tv_real_t *P)
{
    const tv_real_t sum = x[0] + x[1] + x[2] + P[0] + P[1] + P[2] + P[3] + P[4] + P[5] + P[6] + P[7] + P[8];
    const tv_real_t slack = TV_R(1.0001);
    return TV_IS_FINITE(sum) && M3(P, 0, 0) > TV_R(0.0) && M3(P, 1, 1) > TV_R(0.0) && M3(P, 2, 2) > TV_R(0.0) &&
           M3(P, 0, 1) * M3(P, 0, 1) <= M3(P, 0, 0) * M3(P, 1, 1) * slack &&
           M3(P, 0, 2) * M3(P, 0, 2) <= M3(P, 0, 0) * M3(P, 2, 2) * slack &&
           M3(P, 1, 2) * M3(P, 1, 2) <= M3(P, 1, 1) * M3(P, 2, 2) * slack;
}

void ekf_config_default(ekf_config_t *cfg, ekf_setup_t setup)
{
    tvm_params_t p;
    int a;
    if (cfg == NULL) {
        return;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->setup = setup;
    cfg->P0[0][0] = TV_R(1.0);
    cfg->P0[1][1] = TV_R(100.0);
    cfg->P0[2][2] = TV_R(0.01);
    tvm_params_default(&p);
    cfg->qu_V2_s = EKF_DEFAULT_QU_V2_S;
    cfg->qT_Nm2_s = EKF_DEFAULT_QT_NM2_S;
    (void)ekf_q_from_spectral(&p, cfg->qu_V2_s, cfg->qT_Nm2_s, cfg->Q);
    cfg->r[EKF_CH_CURRENT] = TV_R(1.054e-4);
    cfg->r[EKF_CH_VELOCITY] = TV_R(1.0);
    cfg->r[EKF_CH_ANGLE] = TV_R(2.668e-8);
    for (a = 0; a < TVM_NX; ++a) {
        cfg->var_floor[a] = TV_R(1e-12);
    }
    cfg->var_ceil[TVM_I] = TV_R(1e4);
    cfg->var_ceil[TVM_W] = TV_R(1e6);
    cfg->var_ceil[TVM_PHI] = TV_R(10.0);
    cfg->u_abs_max_V = TV_R(60.0);
    cfg->i_abs_max_A = TV_R(50.0);
    cfg->w_abs_max_rad_s = TV_R(500.0);
    cfg->phi_min_rad = TV_R(-1.0);
    cfg->phi_max_rad = TV_R(2.5);
    cfg->contact_band_rad = EKF_DEFAULT_CONTACT_BAND_RAD;
    cfg->qc_Nm2_s = EKF_DEFAULT_QC_NM2_S;
    cfg->qT_rel_s = EKF_DEFAULT_QT_REL_S;
    cfg->impact_timing = EKF_DEFAULT_IMPACT_TIMING;
    cfg->stuck_q_min = EKF_DEFAULT_STUCK_Q_MIN;
    cfg->stuck_hold_frac = EKF_DEFAULT_STUCK_HOLD_FRAC;
    cfg->stop_learn_margin_rad = EKF_DEFAULT_STOP_LEARN_MARGIN_RAD;
    cfg->qd_contact_Nm2_s = EKF_DEFAULT_QD_CONTACT_NM2_S;
    cfg->qd_free_Nm2_s = EKF_DEFAULT_QD_FREE_NM2_S;
    cfg->d_tau_s = EKF_DEFAULT_D_TAU_S;
    cfg->d_var_ceil = TV_R(1e4);
    cfg->qr_ohm2_s = EKF_DEFAULT_QR_OHM2_S;
    cfg->r_sigma0_ohm = EKF_DEFAULT_R_SIGMA0_OHM;
    cfg->dr_abs_max_ohm = EKF_DEFAULT_DR_ABS_MAX_OHM;
    cfg->dr_excite_A = EKF_DEFAULT_DR_EXCITE_A;
    cfg->qf_1_s = EKF_DEFAULT_QF_1_S;
    cfg->f_sigma0 = EKF_DEFAULT_F_SIGMA0;
    cfg->f_abs_max = EKF_DEFAULT_F_ABS_MAX;
    cfg->f_excite_rad_s = EKF_DEFAULT_F_EXCITE_RAD_S;
    cfg->qm_1_s = EKF_DEFAULT_QM_1_S;
    cfg->m_sigma0 = EKF_DEFAULT_M_SIGMA0;
    cfg->m_abs_max = EKF_DEFAULT_M_ABS_MAX;
    cfg->contact_nis_gate = EKF_DEFAULT_CONTACT_NIS_GATE;
    cfg->contact_w_coupling = TV_R(1.0);
    cfg->nis_inflate_alpha = EKF_DEFAULT_NIS_INFLATE_ALPHA;
    cfg->nis_inflate_threshold = EKF_DEFAULT_NIS_INFLATE_THRESHOLD;
    cfg->nis_inflate_max = EKF_DEFAULT_NIS_INFLATE_MAX;
    cfg->white_threshold = EKF_DEFAULT_WHITE_THRESHOLD;
}

void ekf_config_paper(ekf_config_t *cfg)
{
    int a;
    int b;
    if (cfg == NULL) {
        return;
    }
    ekf_config_default(cfg, EKF_SETUP_PAPER_3MEAS);
    for (a = 0; a < TVM_NX; ++a) {
        cfg->x0[a] = TV_R(0.0);
        for (b = 0; b < TVM_NX; ++b) {
            cfg->P0[a][b] = a == b ? TV_R(100.0) : TV_R(0.0);
            cfg->Q[a][b] = a == b ? TV_R(0.01) : TV_R(0.0);
        }
    }
    cfg->r[EKF_CH_CURRENT] = TV_R(1e-4);
    cfg->r[EKF_CH_VELOCITY] = TV_R(1.0);
    cfg->r[EKF_CH_ANGLE] = TV_R(1e-8);
    cfg->contact_band_rad = TV_R(0.0);
    cfg->qc_Nm2_s = TV_R(0.0);
    cfg->qT_rel_s = TV_R(0.0);
    cfg->impact_timing = TV_R(0.0);
    cfg->stop_learn_margin_rad = TV_R(0.0);
    cfg->qd_contact_Nm2_s = TV_R(0.0);
    cfg->qd_free_Nm2_s = TV_R(0.0);
    cfg->qr_ohm2_s = TV_R(0.0);
    cfg->qf_1_s = TV_R(0.0);
    cfg->qm_1_s = TV_R(0.0);
    cfg->contact_nis_gate = TV_R(0.0);
    cfg->nis_inflate_alpha = TV_R(0.0);
    cfg->stuck_q_min = TV_R(1.0);
}

int ekf_q_from_spectral(const tvm_params_t *p, tv_real_t qu_V2_s, tv_real_t qT_Nm2_s,
                        tv_real_t Q[TVM_NX][TVM_NX])
{
    tv_real_t Ts;
    tv_real_t g;
    if (p == NULL || Q == NULL) {
        return TV_ERR_NULL;
    }
    if (!TV_IS_FINITE(qu_V2_s) || !TV_IS_FINITE(qT_Nm2_s) || !TV_IS_FINITE(p->Ts_s) ||
        !TV_IS_FINITE(p->L_H) || !TV_IS_FINITE(p->J_kg_m2)) {
        return TV_ERR_NONFINITE;
    }
    if (qu_V2_s < TV_R(0.0) || qT_Nm2_s < TV_R(0.0) || !(p->Ts_s > TV_R(0.0)) || !(p->L_H > TV_R(0.0)) ||
        !(p->J_kg_m2 > TV_R(0.0))) {
        return TV_ERR_CONFIG;
    }
    Ts = p->Ts_s;
    g = qT_Nm2_s / (p->J_kg_m2 * p->J_kg_m2);
    memset(Q, 0, sizeof(mat3_t));
    Q[TVM_I][TVM_I] = qu_V2_s * Ts / (p->L_H * p->L_H);
    Q[TVM_W][TVM_W] = g * Ts;
    Q[TVM_W][TVM_PHI] = g * Ts * Ts / TV_R(2.0);
    Q[TVM_PHI][TVM_W] = Q[TVM_W][TVM_PHI];
    Q[TVM_PHI][TVM_PHI] = g * Ts * Ts * Ts / TV_R(3.0);
    return TV_OK;
}

int ekf_init(ekf_t *ekf, const tvm_params_t *params, const ekf_config_t *cfg)
{
    tvm_t model;
    int rc;
    int a;
    if (ekf == NULL || params == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    rc = tvm_init(&model, params);
    if (rc != TV_OK) {
        return rc;
    }
    if (!all_finite(cfg->x0, TVM_NX) || !all_finite(&cfg->P0[0][0], TVM_NX * TVM_NX) ||
        !all_finite(&cfg->Q[0][0], TVM_NX * TVM_NX) || !all_finite(cfg->r, EKF_NCH) ||
        !all_finite(cfg->var_floor, TVM_NX) || !all_finite(cfg->var_ceil, TVM_NX) ||
        !TV_IS_FINITE(cfg->u_abs_max_V) || !TV_IS_FINITE(cfg->i_abs_max_A) ||
        !TV_IS_FINITE(cfg->w_abs_max_rad_s) || !TV_IS_FINITE(cfg->phi_min_rad) ||
        !TV_IS_FINITE(cfg->phi_max_rad) || !TV_IS_FINITE(cfg->contact_band_rad) || !TV_IS_FINITE(cfg->qc_Nm2_s) || !TV_IS_FINITE(cfg->qT_rel_s) ||
        !TV_IS_FINITE(cfg->impact_timing) ||
        !TV_IS_FINITE(cfg->stop_learn_margin_rad) || !TV_IS_FINITE(cfg->qd_contact_Nm2_s) ||
        !TV_IS_FINITE(cfg->qd_free_Nm2_s) || !TV_IS_FINITE(cfg->d_tau_s) || !TV_IS_FINITE(cfg->d_var_ceil) ||
        !TV_IS_FINITE(cfg->contact_nis_gate) || !TV_IS_FINITE(cfg->contact_w_coupling) || !TV_IS_FINITE(cfg->qr_ohm2_s) ||
        !TV_IS_FINITE(cfg->r_sigma0_ohm) || !TV_IS_FINITE(cfg->dr_abs_max_ohm) ||
        !TV_IS_FINITE(cfg->dr_excite_A) || !TV_IS_FINITE(cfg->qf_1_s) || !TV_IS_FINITE(cfg->f_sigma0) ||
        !TV_IS_FINITE(cfg->f_abs_max) || !TV_IS_FINITE(cfg->f_excite_rad_s) || !TV_IS_FINITE(cfg->qm_1_s) ||
        !TV_IS_FINITE(cfg->m_sigma0) || !TV_IS_FINITE(cfg->m_abs_max) || !TV_IS_FINITE(cfg->nis_inflate_alpha) ||
        !TV_IS_FINITE(cfg->nis_inflate_threshold) || !TV_IS_FINITE(cfg->nis_inflate_max) ||
        !TV_IS_FINITE(cfg->white_threshold) || !TV_IS_FINITE(cfg->stuck_q_min) || !TV_IS_FINITE(cfg->stuck_hold_frac)) {
        return TV_ERR_NONFINITE;
    }
    if (cfg->setup != EKF_SETUP_CURRENT_ANGLE && cfg->setup != EKF_SETUP_PAPER_3MEAS) {
        return TV_ERR_CONFIG;
    }
    for (a = 0; a < EKF_NCH; ++a) {
        if (!(cfg->r[a] > TV_R(0.0))) {
            return TV_ERR_CONFIG;
        }
    }
    for (a = 0; a < TVM_NX; ++a) {
        if (cfg->var_floor[a] < TV_R(0.0) || !(cfg->var_ceil[a] > cfg->var_floor[a])) {
            return TV_ERR_CONFIG;
        }
    }
    if (!(cfg->u_abs_max_V > TV_R(0.0)) || !(cfg->i_abs_max_A > TV_R(0.0)) ||
        !(cfg->w_abs_max_rad_s > TV_R(0.0)) || !(cfg->phi_max_rad > cfg->phi_min_rad) ||
        cfg->contact_band_rad < TV_R(0.0) || cfg->contact_band_rad > TV_R(0.5) || cfg->qc_Nm2_s < TV_R(0.0) || cfg->qT_rel_s < TV_R(0.0) || cfg->qT_rel_s > TV_R(1.0) ||
        cfg->impact_timing < TV_R(0.0) || cfg->impact_timing > TV_R(10.0) ||
        cfg->stop_learn_margin_rad < TV_R(0.0) || cfg->stop_learn_margin_rad > TV_R(0.5) ||
        cfg->qd_contact_Nm2_s < TV_R(0.0) || cfg->qd_free_Nm2_s < TV_R(0.0) || !(cfg->d_tau_s > TV_R(0.0)) ||
        !(cfg->d_var_ceil > TV_R(0.0)) || cfg->contact_nis_gate < TV_R(0.0) || cfg->contact_w_coupling < TV_R(0.0) ||
        cfg->contact_w_coupling > TV_R(1.0) || cfg->qr_ohm2_s < TV_R(0.0) ||
        cfg->r_sigma0_ohm < TV_R(0.0) || !(cfg->dr_abs_max_ohm > TV_R(0.0)) ||
        cfg->dr_excite_A < TV_R(0.0) || cfg->qf_1_s < TV_R(0.0) || cfg->f_sigma0 < TV_R(0.0) ||
        !(cfg->f_abs_max > TV_R(0.0) && cfg->f_abs_max < TV_R(1.0)) || cfg->f_excite_rad_s < TV_R(0.0) ||
        cfg->qm_1_s < TV_R(0.0) || cfg->m_sigma0 < TV_R(0.0) || !(cfg->m_abs_max > TV_R(0.0) && cfg->m_abs_max < TV_R(1.0)) ||
        cfg->nis_inflate_alpha < TV_R(0.0) || cfg->nis_inflate_alpha > TV_R(1.0) || !(cfg->nis_inflate_threshold > TV_R(0.0)) ||
        !(cfg->nis_inflate_max >= TV_R(1.0)) || cfg->white_threshold < TV_R(0.0) ||
        !(cfg->stuck_q_min > TV_R(0.0)) || cfg->stuck_q_min > TV_R(1.0) ||
        !(cfg->stuck_hold_frac > TV_R(0.0)) || cfg->stuck_hold_frac > TV_R(1.0)) {
        return TV_ERR_CONFIG;
    }
    /* the explicit resistance error must leave the current's decay per sub-step in (0, 1):
     * a - b dR >= a / 2 over the whole bound */
    if (model.b_A_V * cfg->dr_abs_max_ohm > TV_R(0.5) * model.a) {
        return TV_ERR_CONFIG;
    }
    if (!is_symmetric(&cfg->P0[0][0]) || !principal_minors_ok(&cfg->P0[0][0], 1) ||
        !is_symmetric(&cfg->Q[0][0]) || !principal_minors_ok(&cfg->Q[0][0], 0)) {
        return TV_ERR_CONFIG;
    }
    memset(ekf, 0, sizeof *ekf);
    ekf->model = model;
    ekf->cfg = *cfg;
    ekf->nis_avg = TV_R(1.0);
    ekf->q_scale = TV_R(1.0);
    ekf->q_scale_plate = TV_R(1.0);
    ekf->white_c = cfg->nis_inflate_alpha > TV_R(0.0) && cfg->white_threshold > TV_R(0.0)
                       ? (TV_R(2.0) - cfg->nis_inflate_alpha) / (cfg->nis_inflate_alpha * cfg->white_threshold)
                       : TV_R(0.0);
    /* Q is used symmetrised (validated symmetric to 1e-6 relative above). */
    {
        int b;
        for (a = 0; a < TVM_NX; ++a) {
            for (b = a + 1; b < TVM_NX; ++b) {
                const tv_real_t q = (cfg->Q[a][b] + cfg->Q[b][a]) * TV_R(0.5);
                ekf->cfg.Q[a][b] = q;
                ekf->cfg.Q[b][a] = q;
            }
        }
    }
    memcpy(ekf->Qs, ekf->cfg.Q, sizeof ekf->Qs);
    memcpy(ekf->x, cfg->x0, sizeof ekf->x);
    memcpy(ekf->P, cfg->P0, sizeof(mat3_t));
    /* the contact noise: a torque noise of density qc on the plate, nothing on the armature */
    (void)ekf_q_from_spectral(params, TV_R(0.0), cfg->qc_Nm2_s, ekf->Qc);
    (void)ekf_q_from_spectral(params, TV_R(0.0), TV_R(1.0), ekf->Qt1);
    ekf->aug_on = cfg->qd_contact_Nm2_s > TV_R(0.0) || cfg->qd_free_Nm2_s > TV_R(0.0) || cfg->qr_ohm2_s > TV_R(0.0) ||
                  cfg->qf_1_s > TV_R(0.0) || cfg->qm_1_s > TV_R(0.0);
    ekf->g_cols = ((cfg->qd_contact_Nm2_s > TV_R(0.0) || cfg->qd_free_Nm2_s > TV_R(0.0)) ? 1u << TVM_A_TORQUE : 0u) |
                  (cfg->qr_ohm2_s > TV_R(0.0) ? 1u << TVM_A_DR : 0u) | (cfg->qf_1_s > TV_R(0.0) ? 1u << TVM_A_FRIC : 0u) |
                  (cfg->qm_1_s > TV_R(0.0) ? 1u << TVM_A_PRELOAD : 0u);
    ekf->d_beta = TV_EXP(-params->Ts_s / cfg->d_tau_s);
    if (cfg->qr_ohm2_s > TV_R(0.0)) {
        ekf->Paa[TVM_A_DR][TVM_A_DR] = cfg->r_sigma0_ohm * cfg->r_sigma0_ohm;
    }
    if (cfg->qf_1_s > TV_R(0.0)) {
        ekf->Paa[TVM_A_FRIC][TVM_A_FRIC] = cfg->f_sigma0 * cfg->f_sigma0;
    }
    if (cfg->qm_1_s > TV_R(0.0)) {
        ekf->Paa[TVM_A_PRELOAD][TVM_A_PRELOAD] = cfg->m_sigma0 * cfg->m_sigma0;
    }
    return TV_OK;
}

/* The augmented states are indexed TVM_A_* (tv_model.h); only those in use (bit q of
 * ekf_t::g_cols) enter the loops below, which are unrolled with a test per state, so an unused
 * state costs a branch on the 1 kHz path; its estimate and (co)variances stay 0. */

/* The augmented part of an estimate: a and the (co)variances holding it, and which are in use. */
typedef struct {
    tv_real_t a[TVM_NA];
    tv_real_t Pxa[TVM_NX][TVM_NA];
    tv_real_t Paa[TVM_NA][TVM_NA];
    unsigned on;           /* the states in use (bit TVM_A_*: ekf_t::g_cols) */
} aug_part_t;

/* Zero the entries of ap that belong to the augmented states not in on (all of them for on = 0):
 * what a memset of ap would do to the entries the caller does not write, in fewer instructions
 * (the default filter leaves one state of four unused: 12 stores against 132 bytes). */
static void aug_zero_unused(aug_part_t *ap, unsigned on)
{
    int q;
    int r;
    for (q = 0; q < TVM_NA; ++q) {
        if ((on & (1u << q)) == 0u) {
            ap->a[q] = TV_R(0.0);
            for (r = 0; r < TVM_NX; ++r) {
                ap->Pxa[r][q] = TV_R(0.0);
            }
            for (r = 0; r < TVM_NA; ++r) {
                ap->Paa[q][r] = TV_R(0.0);
                ap->Paa[r][q] = TV_R(0.0);
            }
        }
    }
}

/* The augmented part is sane: finite, variances >= 0, |cov| <= sqrt(var var) with x and within. */
static int aug_sane(const tv_real_t *P, const aug_part_t *ap)
{
    const tv_real_t slack = TV_R(1.0001);
    tv_real_t sum = TV_R(0.0);
    int a;
    int q;
    int r;
    for (q = 0; q < TVM_NA; ++q) {
        if ((ap->on & (1u << q)) == 0u) {
            continue;
        }
        sum += ap->a[q];
        if (ap->Paa[q][q] < TV_R(0.0)) {
            return 0;
        }
        for (r = 0; r < TVM_NA; ++r) {
            sum += ap->Paa[q][r];
            if (r > q && ap->Paa[q][r] * ap->Paa[q][r] > ap->Paa[q][q] * ap->Paa[r][r] * slack) {
                return 0;
            }
        }
        for (a = 0; a < TVM_NX; ++a) {
            sum += ap->Pxa[a][q];
            if (ap->Pxa[a][q] * ap->Pxa[a][q] > M3(P, a, a) * ap->Paa[q][q] * slack) {
                return 0;
            }
        }
    }
    return TV_IS_FINITE(sum);
}

/* Each augmented variance held below its ceiling by scaling its row and column (as
 * apply_variance_bounds); the resistance and friction errors also held inside their bounds. */
static void bound_aug(aug_part_t *ap, const ekf_config_t *cfg)
{
    const tv_real_t ceil_[TVM_NA] = {cfg->d_var_ceil, cfg->dr_abs_max_ohm * cfg->dr_abs_max_ohm,
                                     cfg->f_abs_max * cfg->f_abs_max, cfg->m_abs_max * cfg->m_abs_max};
    /* the contact torque has no bound on its value (0: none), only on its variance */
    const tv_real_t bound[TVM_NA] = {TV_R(0.0), cfg->dr_abs_max_ohm, cfg->f_abs_max, cfg->m_abs_max};
    int q;
    int r;
    for (q = 0; q < TVM_NA; ++q) {
        if ((ap->on & (1u << q)) == 0u) {
            continue;
        }
        if (ap->Paa[q][q] > ceil_[q]) {
            const tv_real_t f = TV_SQRT(ceil_[q] / ap->Paa[q][q]);
            ap->Pxa[0][q] *= f;
            ap->Pxa[1][q] *= f;
            ap->Pxa[2][q] *= f;
            for (r = 0; r < TVM_NA; ++r) {
                if (r != q) {
                    ap->Paa[q][r] *= f;
                    ap->Paa[r][q] *= f;
                }
            }
            ap->Paa[q][q] = ceil_[q];
        }
        if (bound[q] > TV_R(0.0)) {
            if (ap->a[q] > bound[q]) {
                ap->a[q] = bound[q];
            } else if (ap->a[q] < -bound[q]) {
                ap->a[q] = -bound[q];
            }
        }
    }
}

static void aug_get(const ekf_t *ekf, aug_part_t *ap)
{
    memcpy(ap->a, ekf->aug, sizeof ap->a);
    memcpy(ap->Pxa, ekf->Pxa, sizeof ap->Pxa);
    memcpy(ap->Paa, ekf->Paa, sizeof ap->Paa);
    ap->on = ekf->g_cols;
}

static void aug_put(ekf_t *ekf, const aug_part_t *ap)
{
    memcpy(ekf->aug, ap->a, sizeof ekf->aug);
    memcpy(ekf->Pxa, ap->Pxa, sizeof ekf->Pxa);
    memcpy(ekf->Paa, ap->Paa, sizeof ekf->Paa);
}

/*
 * P = F P F^T + Q (+ Qc when contact, + qt Qt1, + qw on the velocity variance: impact timing),
 * bounds, sanity; see ekf_propagate(). With the augmented
 * states a (G = dx/da, NULL = 0; B = diag(beta): d decays outside the contact band, dR is a
 * random walk) the covariance [[P, Pxa], [Pxa^T, Paa]] goes through [[F, G], [0, B]]:
 *   P <- (F P + G Pxa^T) F^T + (F Pxa + G Paa) G^T,  Pxa <- (F Pxa + G Paa) B,
 *   Paa <- B Paa B + Qa Ts,  a <- B a.
 */
static int propagate(ekf_t *ekf, const tv_real_t x_pred[TVM_NX], tv_real_t F[TVM_NX][TVM_NX],
                     tv_real_t G[TVM_NX][TVM_NA], int contact, tv_real_t qt, tv_real_t qw, tv_real_t q_plate)
{
    mat3_t FP;
    mat3_t Pn;
    /* the band may be on (covariance inflation) with no contact noise: nothing to add then */
    const int add_qc = contact && ekf->cfg.qc_Nm2_s > TV_R(0.0);
    tv_real_t FPa[TVM_NX][TVM_NA] = {{TV_R(0.0), TV_R(0.0), TV_R(0.0), TV_R(0.0)},
                                     {TV_R(0.0), TV_R(0.0), TV_R(0.0), TV_R(0.0)},
                                     {TV_R(0.0), TV_R(0.0), TV_R(0.0), TV_R(0.0)}};
    aug_part_t ap;
    int a;
    int b;
    /* FP = F P */
    TV_UNROLL3
    for (a = 0; a < TVM_NX; ++a) {
        TV_UNROLL3
        for (b = 0; b < TVM_NX; ++b) {
            FP[a][b] = F[a][0] * ekf->P[0][b] + F[a][1] * ekf->P[1][b] + F[a][2] * ekf->P[2][b];
        }
    }
    /* the loops below write the entries of the states in use; those of the others are zero */
    aug_zero_unused(&ap, ekf->g_cols);
    ap.on = ekf->g_cols;
    if (ekf->aug_on) {
        const tv_real_t beta[TVM_NA] = {contact ? TV_R(1.0) : ekf->d_beta, TV_R(1.0), TV_R(1.0), TV_R(1.0)};
        const tv_real_t qa[TVM_NA] = {
            (contact ? ekf->cfg.qd_contact_Nm2_s : ekf->cfg.qd_free_Nm2_s) * ekf->model.p.Ts_s,
            ekf->cfg.qr_ohm2_s * ekf->model.p.Ts_s, ekf->cfg.qf_1_s * ekf->model.p.Ts_s,
            ekf->cfg.qm_1_s * ekf->model.p.Ts_s};
        const unsigned on = ap.on;
        int q;
        int r;
        TV_UNROLL3
        for (a = 0; a < TVM_NX; ++a) {
            TV_UNROLL_NA
            for (q = 0; q < TVM_NA; ++q) {
                if ((on & (1u << q)) != 0u) {
                    FPa[a][q] = F[a][0] * ekf->Pxa[0][q] + F[a][1] * ekf->Pxa[1][q] + F[a][2] * ekf->Pxa[2][q];
                    if (G != NULL) {
                        const tv_real_t g = G[a][q];
                        TV_UNROLL_NA
                        for (r = 0; r < TVM_NA; ++r) {
                            if ((on & (1u << r)) != 0u) {
                                FPa[a][q] += G[a][r] * ekf->Paa[r][q];
                            }
                        }
                        TV_UNROLL3
                        for (b = 0; b < TVM_NX; ++b) {
                            FP[a][b] += g * ekf->Pxa[b][q];
                        }
                    }
                }
            }
        }
        TV_UNROLL_NA
        for (q = 0; q < TVM_NA; ++q) {
            if ((on & (1u << q)) != 0u) {
                TV_UNROLL3
                for (a = 0; a < TVM_NX; ++a) {
                    ap.Pxa[a][q] = FPa[a][q] * beta[q];
                }
                TV_UNROLL_NA
                for (r = 0; r < TVM_NA; ++r) {
                    if ((on & (1u << r)) != 0u) {
                        ap.Paa[q][r] = beta[q] * beta[r] * ekf->Paa[q][r];
                    }
                }
                ap.Paa[q][q] += qa[q];
                ap.a[q] = beta[q] * ekf->aug[q];
            }
        }
    }
    /* Pn = FP F^T (+ FPa G^T) + Q, upper triangle computed once and mirrored: exactly symmetric. */
    TV_UNROLL3
    for (a = 0; a < TVM_NX; ++a) {
        TV_UNROLL3
        for (b = a; b < TVM_NX; ++b) {
            tv_real_t q = ekf->Qs[a][b];
            if (add_qc) {
                q += ekf->Qc[a][b];
            }
            if (qt > TV_R(0.0)) {
                q += qt * ekf->Qt1[a][b];
            }
            if (a != TVM_I) {
                q *= q_plate; /* the plate's block (Q has no current-plate terms) */
            }
            Pn[a][b] = FP[a][0] * F[b][0] + FP[a][1] * F[b][1] + FP[a][2] * F[b][2] + q;
            if (ekf->aug_on && G != NULL) {
                /* unused columns of FPa and G are 0: adding them is exact, and cheaper than a test */
                Pn[a][b] += FPa[a][0] * G[b][0] + FPa[a][1] * G[b][1] + FPa[a][2] * G[b][2] + FPa[a][3] * G[b][3];
            }
            Pn[b][a] = Pn[a][b];
        }
    }
    Pn[TVM_W][TVM_W] += qw;
    apply_variance_bounds(Pn, ekf->cfg.var_floor, ekf->cfg.var_ceil, ekf->n_floor, ekf->n_ceil);
    if (ekf->aug_on) {
        bound_aug(&ap, &ekf->cfg);
    }
    if (!estimate_sane(x_pred, &Pn[0][0]) || (ekf->aug_on && !aug_sane(&Pn[0][0], &ap))) {
        ++ekf->n_rejected;
        return TV_ERR_NUMERIC;
    }
    memcpy(ekf->x, x_pred, sizeof ekf->x);
    memcpy(ekf->P, Pn, sizeof(mat3_t));
    aug_put(ekf, &ap);
    ++ekf->n_predict;
    ekf->in_contact = contact;
    if (contact) {
        ++ekf->n_contact;
    }
    return TV_OK;
}

/*
 * The model-torque noise density of this step, qT_rel_s T^2 [N^2 m^2 s] (ekf_config_t::qT_rel_s),
 * from the state before the step: T = |n Kt i| + Kv |w|, the torques whose errors grow with the
 * motion (motor constant and, through the motor torque that accelerates the plate, inertia;
 * viscous friction). The springs' and Coulomb friction's errors are not in T: slowly varying,
 * they are what the preload and friction states adapt to, and at low speed stiction absorbs them
 * (with them in T the filter's sigma was 3x its error in slow motion: measured).
 */
static tv_real_t model_torque_noise(const ekf_t *ekf)
{
    tv_real_t T;
    if (!(ekf->cfg.qT_rel_s > TV_R(0.0))) {
        return TV_R(0.0);
    }
    T = TV_FABS(ekf->model.nKt_Nm_A * ekf->x[TVM_I]) + ekf->model.p.Kv_Nm_s_rad * TV_FABS(ekf->x[TVM_W]);
    return ekf->cfg.qT_rel_s * T * T;
}

/*
 * Impact timing (ekf_config_t::impact_timing): the velocity variance a period adds when its
 * prediction enters a stop (the angle before it, phi_prior, between the stops; a sub-step
 * starting inside one, peak_Nm > 0, or the predicted xn inside one). The map's stop torque
 * starts at a sub-step boundary, up to one sub-step after the plate's contact, so
 * impact_timing (h / J M)^2 with M the largest stop torque of the period's sub-steps (peak_Nm)
 * or the stop torque at xn, whichever is larger; 0 on every other period.
 */
static tv_real_t impact_timing_var(const ekf_t *ekf, tv_real_t phi_prior, const tv_real_t xn[TVM_NX], tv_real_t peak_Nm)
{
    const tvm_params_t *p = &ekf->model.p;
    tv_real_t m;
    tv_real_t dw;
    if (!(ekf->cfg.impact_timing > TV_R(0.0)) || phi_prior < p->phi_closed_rad || phi_prior > p->phi_open_rad ||
        !(peak_Nm > TV_R(0.0) || xn[TVM_PHI] < p->phi_closed_rad || xn[TVM_PHI] > p->phi_open_rad)) {
        return TV_R(0.0);
    }
    m = TV_FABS(tvm_stop_torque(&ekf->model, xn[TVM_PHI], xn[TVM_W]));
    dw = ekf->model.h_J * (peak_Nm > m ? peak_Nm : m);
    return ekf->cfg.impact_timing * dw * dw;
}

int ekf_propagate(ekf_t *ekf, const tv_real_t x_pred[TVM_NX], tv_real_t F[TVM_NX][TVM_NX])
{
    if (ekf == NULL || x_pred == NULL || F == NULL) {
        return TV_ERR_NULL;
    }
    return propagate(ekf, x_pred, F, NULL, 0, TV_R(0.0), TV_R(0.0), TV_R(1.0));
}

int ekf_predict(ekf_t *ekf, tv_real_t u_V)
{
    tv_real_t xn[TVM_NX];
    mat3_t F;
    tv_real_t G[TVM_NX][TVM_NA];
    tv_real_t peak = TV_R(0.0);
    tv_real_t hold = TV_R(-1.0);
    if (ekf == NULL) {
        return TV_ERR_NULL;
    }
    if (!TV_IS_FINITE(u_V)) {
        ++ekf->n_rejected;
        return TV_ERR_NONFINITE;
    }
    if (TV_FABS(u_V) > ekf->cfg.u_abs_max_V) {
        ++ekf->n_rejected;
        return TV_ERR_RANGE;
    }
    if (ekf->aug_on) {
        tvm_step_aug_peak(&ekf->model, ekf->x, ekf->aug, u_V, xn, F, G, ekf->g_cols, &peak, &hold);
    } else {
        static const tv_real_t a0[TVM_NA] = {TV_R(0.0), TV_R(0.0), TV_R(0.0), TV_R(0.0)};
        tvm_step_aug_peak(&ekf->model, ekf->x, a0, u_V, xn, F, NULL, 0u, &peak, &hold);
    }
    {
        /* in the contact band of a stop (either side) the contact law is uncertain */
        const tv_real_t band = ekf->cfg.contact_band_rad;
        const int contact = band > TV_R(0.0) && (xn[TVM_PHI] < ekf->model.p.phi_closed_rad + band ||
                                                 xn[TVM_PHI] > ekf->model.p.phi_open_rad - band);
        const tv_real_t qw = impact_timing_var(ekf, ekf->x[TVM_PHI], xn, peak);
        /* stuck-plate noise: the plate's process noise scaled by how firmly static friction holds it */
        tv_real_t q_plate = TV_R(1.0);
        if (hold > TV_R(0.0) && !contact && ekf->cfg.stuck_q_min < TV_R(1.0)) {
            const tv_real_t t = hold >= ekf->cfg.stuck_hold_frac ? TV_R(1.0) : hold / ekf->cfg.stuck_hold_frac;
            q_plate = TV_R(1.0) - (TV_R(1.0) - ekf->cfg.stuck_q_min) * t;
        }
        const int rc = propagate(ekf, xn, F, ekf->aug_on ? G : NULL, contact, model_torque_noise(ekf), qw, q_plate);
        if (rc == TV_OK && qw > TV_R(0.0)) {
            ++ekf->n_impact_timing;
        }
        return rc;
    }
}

/* Validate one measurement channel against its limits. */
static int check_channel(const ekf_config_t *cfg, int ch, tv_real_t z)
{
    if (!TV_IS_FINITE(z)) {
        return TV_ERR_NONFINITE;
    }
    switch (ch) {
    case EKF_CH_CURRENT:
        return TV_FABS(z) <= cfg->i_abs_max_A ? TV_OK : TV_ERR_RANGE;
    case EKF_CH_VELOCITY:
        return TV_FABS(z) <= cfg->w_abs_max_rad_s ? TV_OK : TV_ERR_RANGE;
    default:
        return (z >= cfg->phi_min_rad && z <= cfg->phi_max_rad) ? TV_OK : TV_ERR_RANGE;
    }
}

/*
 * One scalar update with H = e_j (the channel observes state j directly), Joseph form in its
 * product order, which keeps the diagonal non-negative even when K rounds to 1 (P_jj >> r, as
 * with the paper's P0 = 100 I and r = 1e-8 in float):
 *   A = (I - K e_j^T) P        A_ab = P_ab - K_a P_jb
 *   P = A (I - K e_j^T)^T + r K K^T,   P_ab = A_ab - A_aj K_b + r K_a K_b
 * The upper triangle is computed and mirrored, so P stays exactly symmetric.
 * Returns 0 on a non-positive innovation variance (nothing written).
 */
static int scalar_update(tv_real_t x[TVM_NX], mat3_t P, aug_part_t *ap, unsigned frozen, int j, tv_real_t z,
                         tv_real_t r, tv_real_t *innov, tv_real_t *innov_var)
{
    tv_real_t K[TVM_NX];
    mat3_t A;
    const tv_real_t s = P[j][j] + r;
    const tv_real_t y = z - x[j];
    tv_real_t inv_s;
    int a;
    int b;
    if (!(s > TV_R(0.0))) {
        return 0;
    }
    inv_s = TV_R(1.0) / s;
    TV_UNROLL3
    for (a = 0; a < TVM_NX; ++a) {
        K[a] = P[a][j] * inv_s;
    }
    if (ap != NULL) {
        /* the same Joseph form on the augmented rows (P_jq = Pxa_jq; old P throughout):
         *   A_aq = Pxa_aq - K_a Pxa_jq,  A_aj as below,  A_qj = Pxa_jq - Kq P_jj,  A_qr = Paa_qr - Kq Pxa_jr
         *   Pxa_aq <- A_aq - A_aj Kq + r K_a Kq,  Paa_qr <- A_qr - A_qj Kr + r Kq Kr
         * The Joseph form holds for any gain: a frozen state (bit q of frozen) gets gain 0
         * (Schmidt update). */
        tv_real_t Ka[TVM_NA] = {TV_R(0.0), TV_R(0.0), TV_R(0.0), TV_R(0.0)};
        tv_real_t A_qj[TVM_NA] = {TV_R(0.0), TV_R(0.0), TV_R(0.0), TV_R(0.0)};
        tv_real_t Pxa_j[TVM_NA]; /* the old row j of Pxa, read after Pxa is overwritten */
        tv_real_t A_aj[TVM_NX];
        int q;
        int rr;
        TV_UNROLL_NA
        for (q = 0; q < TVM_NA; ++q) {
            Pxa_j[q] = ap->Pxa[j][q];
            if ((ap->on & (1u << q)) != 0u) {
                Ka[q] = (frozen & (1u << q)) != 0u ? TV_R(0.0) : Pxa_j[q] * inv_s;
                A_qj[q] = Pxa_j[q] - Ka[q] * P[j][j];
            }
        }
        TV_UNROLL3
        for (a = 0; a < TVM_NX; ++a) {
            A_aj[a] = P[a][j] - K[a] * P[j][j];
        }
        /* Paa first (it reads the old row j of Pxa, saved above), then Pxa in place: each entry
         * reads only its own old value, row j's old values and A_aj; unused states keep 0 */
        TV_UNROLL_NA
        for (q = 0; q < TVM_NA; ++q) {
            if ((ap->on & (1u << q)) != 0u) {
                TV_UNROLL_NA
                for (rr = q; rr < TVM_NA; ++rr) {
                    if ((ap->on & (1u << rr)) != 0u) {
                        const tv_real_t A_qr = ap->Paa[q][rr] - Ka[q] * Pxa_j[rr];
                        ap->Paa[q][rr] = A_qr - A_qj[q] * Ka[rr] + r * Ka[q] * Ka[rr];
                        ap->Paa[rr][q] = ap->Paa[q][rr];
                    }
                }
                TV_UNROLL3
                for (a = 0; a < TVM_NX; ++a) {
                    const tv_real_t A_aq = ap->Pxa[a][q] - K[a] * Pxa_j[q];
                    ap->Pxa[a][q] = A_aq - A_aj[a] * Ka[q] + r * K[a] * Ka[q];
                }
                ap->a[q] += Ka[q] * y;
            }
        }
    }
    TV_UNROLL3
    for (a = 0; a < TVM_NX; ++a) {
        TV_UNROLL3
        for (b = 0; b < TVM_NX; ++b) {
            A[a][b] = P[a][b] - K[a] * P[j][b];
        }
    }
    TV_UNROLL3
    for (a = 0; a < TVM_NX; ++a) {
        TV_UNROLL3
        for (b = a; b < TVM_NX; ++b) {
            P[a][b] = A[a][b] - A[a][j] * K[b] + r * K[a] * K[b];
            P[b][a] = P[a][b];
        }
    }
    TV_UNROLL3
    for (a = 0; a < TVM_NX; ++a) {
        x[a] += K[a] * y;
    }
    *innov = y;
    *innov_var = s;
    return 1;
}

/*
 * Contact covariance inflation (ekf_config_t::contact_nis_gate). With y = z - phi and
 * s = P_pp + r, when y^2 / s > gate the contact law missed a torque over the last period: the
 * covariance gets the torque noise that explains the innovation at the gate, in the shape of
 * ekf_q_from_spectral()'s plate block (white torque integrated over Ts),
 *   P_pp += D,  P_wp += D 3 / (2 Ts),  P_ww += D 3 / Ts^2,   D = y^2 / gate - s,
 * which is positive semidefinite (the shape of [[Ts, Ts^2/2], [Ts^2/2, Ts^3/3]]), so the NIS of
 * this update is the gate, and the velocity correction is the one a torque impulse over one
 * period implies (not the far larger one the linearised stiff stop would). The P_wp term is
 * scaled by the coupling c in [0, 1] (ekf_config_t::contact_w_coupling; P_ww keeps its 3 D / Ts^2,
 * so the added block stays positive semidefinite: 3 >= (1.5 c)^2). Returns 1 when it inflated.
 */
static int inflate_at_contact(tv_real_t phi, mat3_t P, tv_real_t z, tv_real_t r, tv_real_t gate, tv_real_t Ts,
                              tv_real_t coupling)
{
    const tv_real_t y = z - phi;
    const tv_real_t s = P[TVM_PHI][TVM_PHI] + r;
    tv_real_t D;
    if (!(y * y > gate * s)) {
        return 0;
    }
    D = y * y / gate - s;
    P[TVM_PHI][TVM_PHI] += D;
    P[TVM_W][TVM_PHI] += coupling * D * TV_R(1.5) / Ts;
    P[TVM_PHI][TVM_W] = P[TVM_W][TVM_PHI];
    P[TVM_W][TVM_W] += D * TV_R(3.0) / (Ts * Ts);
    return 1;
}

/* The whiteness-driven inflation's ratio k (ekf_config_t::white_threshold) after an angle
 * correction of innovation y, variance S and NIS y^2 / S: y clipped at 3 sigma, as the NIS
 * average's input (a lasting bias of a few sigma is what this is for; a start-up transient or a
 * fault's jump is not), joins the low-pass mean m; k = m^2 (2 - alpha) / (alpha threshold S). */
static tv_real_t whiteness_ratio(ekf_t *ekf, tv_real_t y, tv_real_t S, tv_real_t nis)
{
    if (nis > EKF_NIS_INFLATE_CLIP) {
        const tv_real_t ymax = TV_SQRT(EKF_NIS_INFLATE_CLIP * S);
        y = y > TV_R(0.0) ? ymax : -ymax;
    }
    ekf->phi_innov_avg += ekf->cfg.nis_inflate_alpha * (y - ekf->phi_innov_avg);
    return ekf->phi_innov_avg * ekf->phi_innov_avg * ekf->white_c / S;
}

/* The factors on Q of the next predictions (the current's entry, the plate's block) and the
 * scaled Q they add (ekf_t::Qs; Q has no current-plate terms). */
static void set_q_scale(ekf_t *ekf, tv_real_t scale, tv_real_t scale_plate)
{
    int a;
    int b;
    ekf->q_scale = scale;
    ekf->q_scale_plate = scale_plate;
    for (a = 0; a < TVM_NX; ++a) {
        for (b = 0; b < TVM_NX; ++b) {
            ekf->Qs[a][b] = (a == TVM_I || b == TVM_I ? scale : scale_plate) * ekf->cfg.Q[a][b];
        }
    }
}

int ekf_correct(ekf_t *ekf, const ekf_meas_t *meas, ekf_innov_t *out)
{
    return ekf_correct_channels(ekf, meas, EKF_CH_BIT(EKF_CH_CURRENT) | EKF_CH_BIT(EKF_CH_VELOCITY) | EKF_CH_BIT(EKF_CH_ANGLE),
                                out);
}

int ekf_correct_channels(ekf_t *ekf, const ekf_meas_t *meas, unsigned mask, ekf_innov_t *out)
{
    static const int channel_state[EKF_NCH] = {TVM_I, TVM_W, TVM_PHI};
    ekf_innov_t res;
    tv_real_t x[TVM_NX];
    mat3_t P;
    aug_part_t ap;
    unsigned frozen;
    uint8_t use[EKF_NCH];
    uint32_t n_inflate = 0u;
    tv_real_t nis_clipped = TV_R(0.0); /* the channels' NIS, each at most EKF_NIS_INFLATE_CLIP */
    int ch;
    if (ekf == NULL || meas == NULL) {
        if (out != NULL) {
            memset(out, 0, sizeof *out);
        }
        return TV_ERR_NULL;
    }
    use[EKF_CH_CURRENT] = (mask & EKF_CH_BIT(EKF_CH_CURRENT)) != 0u ? 1u : 0u;
    use[EKF_CH_VELOCITY] = ekf->cfg.setup == EKF_SETUP_PAPER_3MEAS && (mask & EKF_CH_BIT(EKF_CH_VELOCITY)) != 0u ? 1u : 0u;
    use[EKF_CH_ANGLE] = (mask & EKF_CH_BIT(EKF_CH_ANGLE)) != 0u ? 1u : 0u;
    /* Validate every used channel before touching anything. */
    for (ch = 0; ch < EKF_NCH; ++ch) {
        if (use[ch]) {
            const int rc = check_channel(&ekf->cfg, ch, meas->z[ch]);
            if (rc != TV_OK) {
                ++ekf->n_rejected;
                if (out != NULL) {
                    memset(out, 0, sizeof *out);
                }
                return rc;
            }
        }
    }
    for (ch = 0; ch < EKF_NCH; ++ch) {
        res.innov[ch] = TV_R(0.0);
        res.innov_var[ch] = TV_R(0.0);
        res.nis[ch] = TV_R(0.0);
        res.used[ch] = 0;
    }
    res.nis_total = TV_R(0.0);
    res.n_used = 0;
    memcpy(x, ekf->x, sizeof x);
    memcpy(P, ekf->P, sizeof(mat3_t));
    aug_get(ekf, &ap);
    /* dR is observed through the voltage dR i: frozen while the current is small, predicted or
     * measured (a prediction the measurement contradicts, e.g. a current the held input drives
     * through an open bridge when the plate reverses at a stop, is the input's error, not the
     * winding's); the friction error through the sliding plate: frozen while it (nearly)
     * sticks, and in the contact band, where the innovations are the contact law's errors, not
     * friction's */
    frozen = (TV_FABS(x[TVM_I]) < ekf->cfg.dr_excite_A ||
                      (use[EKF_CH_CURRENT] && TV_FABS(meas->z[EKF_CH_CURRENT]) < ekf->cfg.dr_excite_A)
                  ? 1u << TVM_A_DR
                  : 0u) |
             (TV_FABS(x[TVM_W]) < ekf->cfg.f_excite_rad_s || ekf->in_contact ? (1u << TVM_A_FRIC) | (1u << TVM_A_PRELOAD) : 0u);
    for (ch = 0; ch < EKF_NCH; ++ch) {
        if (use[ch]) {
            /* the model's set-valued parts: a stop's contact, or a plate it predicts stuck (w
             * exactly 0) whose angle moved by less than the band (creep past a wrong stiction;
             * a larger jump is no creep, and inflating for it would turn it into a velocity) */
            const int stuck = ekf->x[TVM_W] == TV_R(0.0) &&
                              TV_FABS(meas->z[ch] - x[TVM_PHI]) <= ekf->cfg.contact_band_rad;
            if (ch == EKF_CH_ANGLE && (ekf->in_contact || stuck) && ekf->cfg.contact_nis_gate > TV_R(0.0) &&
                inflate_at_contact(x[TVM_PHI], P, meas->z[ch], ekf->cfg.r[ch], ekf->cfg.contact_nis_gate, ekf->model.p.Ts_s,
                                   ekf->cfg.contact_w_coupling)) {
                ++n_inflate;
            }
            if (!scalar_update(x, P, ekf->aug_on ? &ap : NULL, frozen, channel_state[ch], meas->z[ch], ekf->cfg.r[ch], &res.innov[ch],
                               &res.innov_var[ch])) {
                ++ekf->n_rejected;
                if (out != NULL) {
                    memset(out, 0, sizeof *out);
                }
                return TV_ERR_NUMERIC;
            }
            res.nis[ch] = res.innov[ch] * res.innov[ch] / res.innov_var[ch];
            res.nis_total += res.nis[ch];
            nis_clipped += res.nis[ch] < EKF_NIS_INFLATE_CLIP ? res.nis[ch] : EKF_NIS_INFLATE_CLIP;
            res.used[ch] = 1;
            ++res.n_used;
        }
    }
    apply_variance_bounds(P, ekf->cfg.var_floor, ekf->cfg.var_ceil, ekf->n_floor, ekf->n_ceil);
    if (ekf->aug_on) {
        bound_aug(&ap, &ekf->cfg);
    }
    if (!estimate_sane(x, &P[0][0]) || !TV_IS_FINITE(res.nis_total) ||
        (ekf->aug_on && !aug_sane(&P[0][0], &ap))) {
        ++ekf->n_rejected;
        if (out != NULL) {
            memset(out, 0, sizeof *out);
        }
        return TV_ERR_NUMERIC;
    }
    memcpy(ekf->x, x, sizeof x);
    memcpy(ekf->P, P, sizeof(mat3_t));
    aug_put(ekf, &ap);
    if (res.n_used > 0u) {
        ++ekf->n_correct;
        if (ekf->cfg.nis_inflate_alpha > TV_R(0.0)) {
            /* consistency-driven inflation (ekf_config_t::nis_inflate_alpha): the clipped NIS per
             * channel, low-pass; Q of the next predictions scaled by its square excess; the
             * plate's block also by the angle innovations' mean (white_threshold). The scaled Q
             * is formed here, only when a factor is above 1 or returns to it (a consistent
             * filter pays the averages alone) */
            const tv_real_t alpha = ekf->cfg.nis_inflate_alpha;
            const tv_real_t qmax = ekf->cfg.nis_inflate_max;
            tv_real_t s = TV_R(1.0);
            tv_real_t sp;
            ekf->nis_avg += alpha * (nis_clipped / (tv_real_t)res.n_used - ekf->nis_avg);
            if (ekf->nis_avg > ekf->cfg.nis_inflate_threshold) {
                const tv_real_t r = ekf->nis_avg / ekf->cfg.nis_inflate_threshold;
                s = r * r < qmax ? r * r : qmax;
            }
            sp = s;
            if (ekf->white_c > TV_R(0.0) && res.used[EKF_CH_ANGLE]) {
                const tv_real_t k = whiteness_ratio(ekf, res.innov[EKF_CH_ANGLE], res.innov_var[EKF_CH_ANGLE],
                                                    res.nis[EKF_CH_ANGLE]);
                if (k > sp) {
                    sp = k < qmax ? k : qmax;
                }
            }
            if (sp > TV_R(1.0)) {
                set_q_scale(ekf, s, sp);
                ++ekf->n_q_inflated;
            } else if (ekf->q_scale_plate != TV_R(1.0)) {
                set_q_scale(ekf, TV_R(1.0), TV_R(1.0));
            }
        }
    }
    ekf->n_inflate += n_inflate;
    if (res.used[EKF_CH_ANGLE] && ekf->cfg.stop_learn_margin_rad > TV_R(0.0)) {
        /* stops learned outward: the plate was seen beyond a stop, so that stop is at least
         * there (monotone: phi_closed only falls, phi_open only rises, so the model's ordering
         * phi_closed < 0 < phi_open holds); bounded by the angle measurement limits */
        const tv_real_t m = ekf->cfg.stop_learn_margin_rad;
        tvm_params_t *p = &ekf->model.p;
        if (x[TVM_PHI] - m > p->phi_open_rad && x[TVM_PHI] - m <= ekf->cfg.phi_max_rad) {
            p->phi_open_rad = x[TVM_PHI] - m;
            ++ekf->n_stop_moves;
        } else if (x[TVM_PHI] + m < p->phi_closed_rad && x[TVM_PHI] + m >= ekf->cfg.phi_min_rad) {
            p->phi_closed_rad = x[TVM_PHI] + m;
            ++ekf->n_stop_moves;
        }
    }
    if (out != NULL) {
        *out = res;
    }
    return TV_OK;
}

void ekf_sigma(const ekf_t *ekf, tv_real_t sigma[TVM_NX])
{
    int a;
    if (ekf == NULL || sigma == NULL) {
        return;
    }
    for (a = 0; a < TVM_NX; ++a) {
        sigma[a] = TV_SQRT(ekf->P[a][a]);
    }
}


void ekf_covariance(const ekf_t *ekf, tv_real_t P[TVM_NX][TVM_NX])
{
    memcpy(P, ekf->P, sizeof ekf->P);
}

int ekf_set_stops(ekf_t *ekf, tv_real_t phi_closed_rad, tv_real_t phi_open_rad)
{
    if (ekf == NULL) {
        return TV_ERR_NULL;
    }
    if (!TV_IS_FINITE(phi_closed_rad) || !TV_IS_FINITE(phi_open_rad)) {
        return TV_ERR_NONFINITE;
    }
    if (!(phi_closed_rad < TV_R(0.0)) || !(phi_open_rad > TV_R(0.0))) {
        return TV_ERR_CONFIG;
    }
    ekf->model.p.phi_closed_rad = phi_closed_rad;
    ekf->model.p.phi_open_rad = phi_open_rad;
    return TV_OK;
}

int ekf_set_contact_w_coupling(ekf_t *ekf, tv_real_t coupling)
{
    if (ekf == NULL) {
        return TV_ERR_NULL;
    }
    if (!TV_IS_FINITE(coupling)) {
        return TV_ERR_NONFINITE;
    }
    if (coupling < TV_R(0.0) || coupling > TV_R(1.0)) {
        return TV_ERR_CONFIG;
    }
    ekf->cfg.contact_w_coupling = coupling;
    return TV_OK;
}

int ekf_set_contact_law(ekf_t *ekf, tv_real_t k_stop, tv_real_t exponent, tv_real_t d_stop)
{
    tvm_params_t p;
    tvm_t m;
    int rc;
    if (ekf == NULL) {
        return TV_ERR_NULL;
    }
    p = ekf->model.p;
    p.k_stop_Nm_rad = k_stop;
    p.stop_exponent = exponent;
    p.d_stop_Nm_s_rad = d_stop;
    rc = tvm_init(&m, &p);
    if (rc == TV_OK) {
        ekf->model = m;
    }
    return rc;
}






void ekf_health(const ekf_t *ekf, ekf_health_t *h)
{
    h->n_contact = ekf->n_contact;
    h->n_impact_timing = ekf->n_impact_timing;
    h->n_stop_moves = ekf->n_stop_moves;
    h->n_inflate = ekf->n_inflate;
    h->n_q_inflated = ekf->n_q_inflated;
    h->q_scale = ekf->q_scale;
    h->q_scale_plate = ekf->q_scale_plate;
    h->n_predict = ekf->n_predict;
    h->n_correct = ekf->n_correct;
    h->n_rejected = ekf->n_rejected;
    memcpy(h->n_floor, ekf->n_floor, sizeof h->n_floor);
    memcpy(h->n_ceil, ekf->n_ceil, sizeof h->n_ceil);
}
