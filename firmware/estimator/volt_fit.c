/**
 * @file volt_fit.c
 * @brief Instrumental-variable fits of the voltage equation over windows of driven periods (see volt_fit.h).
 */
#include "volt_fit.h"

#include <stddef.h>
#include <string.h>

#include "tv_status.h"

void vfit_config_default(vfit_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->block = 250u;
    cfg->blocks = 4u;
    cfg->u_min_V = TV_R(0.5);
    cfg->rho2_max = TV_R(0.98);
    cfg->corr_periods = TV_R(36.0);
}

int vfit_init(vfit_t *f, const vfit_config_t *cfg, tv_real_t L_H, tv_real_t Ts_s)
{
    if (f == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    if (!TV_IS_FINITE(cfg->u_min_V) || !TV_IS_FINITE(cfg->rho2_max) || !TV_IS_FINITE(cfg->corr_periods) ||
        !TV_IS_FINITE(L_H) || !TV_IS_FINITE(Ts_s)) {
        return TV_ERR_NONFINITE;
    }
    if (cfg->block < 100u || cfg->block > VFIT_BLOCK_MAX || cfg->blocks == 0u || cfg->blocks > VFIT_BLOCKS_MAX || !(cfg->u_min_V >= TV_R(0.0)) ||
        !(cfg->rho2_max > TV_R(0.0)) || !(cfg->rho2_max < TV_R(1.0)) || !(cfg->corr_periods >= TV_R(1.0)) ||
        !(L_H > TV_R(0.0)) || !(Ts_s > TV_R(0.0))) {
        return TV_ERR_CONFIG;
    }
    memset(f, 0, sizeof *f);
    f->cfg = *cfg;
    f->l_over_t = L_H / Ts_s;
    return TV_OK;
}

/* 1 when two regressors whose (centred or raw) sums of squares are a, c and cross sum b are apart
 * enough to fit both: neither constant, not (nearly) collinear (rho^2 = b^2 / (a c) at most
 * rho2_max), a positive determinant det = a c - b^2 of the normal equations. */
static int vfit_apart(const vfit_t *f, tv_real_t a, tv_real_t b, tv_real_t c, tv_real_t det)
{
    return a > TV_R(0.0) && c > TV_R(0.0) && b * b <= f->cfg.rho2_max * a * c && det > TV_R(0.0);
}

/* x when positive, else 0: a sum of squares that rounding of a near-perfect fit left a little
 * below 0. */
static tv_real_t vfit_nonneg(tv_real_t x)
{
    return x > TV_R(0.0) ? x : TV_R(0.0);
}

/* The 2 x 2 instrumental-variable solve A (r, k)' = b, A = [a00 a01; a10 a11] (rows: the
 * instruments i, w; columns: the regressors i, x), det its determinant. */
static void vfit_iv2(tv_real_t a00, tv_real_t a01, tv_real_t a10, tv_real_t a11, tv_real_t b0, tv_real_t b1,
                     tv_real_t det, tv_real_t *r, tv_real_t *k)
{
    *r = (a11 * b0 - a01 * b1) / det;
    *k = (a00 * b1 - a10 * b0) / det;
}

/* The residual sum of squares of y - r i - k x from the (raw or centred) sums y y, i y, x y,
 * i i, i x, x x. */
static tv_real_t vfit_rss(tv_real_t yy, tv_real_t iy, tv_real_t xy, tv_real_t ii, tv_real_t ix, tv_real_t xx,
                          tv_real_t r, tv_real_t k)
{
    return yy - TV_R(2.0) * (r * iy + k * xy) + r * r * ii + TV_R(2.0) * r * k * ix + k * k * xx;
}

/* The window's 2 x 2 solve over the sums s of n driven periods (volt_fit.h): R and n Ke by
 * instrumental variables, A theta = Z'y with A = Z'X, Z = (i, w), X = (i, v); their standard
 * deviations sqrt(var [A^-1 Z'Z A^-T]_jj), the variance per degree of freedom of the residual
 * on w (the model's errors, which last for many periods) times the correlation length, plus
 * that of the residual on v (the differentiated angle's noise, white). 1 when taken. */
static int vfit_solve(vfit_t *f, const tv_real_t *s, uint32_t n)
{
    /* A = [S_ii S_iv; S_wi S_wv] */
    const tv_real_t det = s[0] * s[10] - s[9] * s[1];
    const tv_real_t dof = (tv_real_t)(n - 2u);
    tv_real_t r;
    tv_real_t k;
    tv_real_t rss_w;
    tv_real_t rss_v;
    tv_real_t var;
    tv_real_t q_r;
    tv_real_t q_k;
    /* the instruments (nearly) collinear, or either constant: R and n Ke not apart */
    if (!vfit_apart(f, s[0], s[1], s[2], det)) {
        return 0;
    }
    vfit_iv2(s[0], s[9], s[1], s[10], s[3], s[4], det, &r, &k);
    rss_w = vfit_rss(s[5], s[3], s[4], s[0], s[1], s[2], r, k);
    rss_v = vfit_rss(s[5], s[3], s[12], s[0], s[9], s[11], r, k);
    var = (vfit_nonneg(rss_w) * f->cfg.corr_periods + vfit_nonneg(rss_v)) / dof;
    /* [A^-1 Z'Z A^-T]: A^-1's rows (S_wv, -S_iv) / det and (-S_wi, S_ii) / det */
    q_r = (s[10] * s[10] * s[0] - TV_R(2.0) * s[10] * s[9] * s[1] + s[9] * s[9] * s[2]) / (det * det);
    q_k = s[0] * (s[0] * s[2] - s[1] * s[1]) / (det * det);
    if (!TV_IS_FINITE(r) || !TV_IS_FINITE(k) || !TV_IS_FINITE(var) || !TV_IS_FINITE(q_r) || !TV_IS_FINITE(q_k)) {
        return 0;
    }
    f->r_ohm = r;
    f->nke_V_s = k;
    f->r_sigma_ohm = TV_SQRT(var * vfit_nonneg(q_r));
    f->nke_sigma_V_s = TV_SQRT(var * vfit_nonneg(q_k));
    f->valid = 1u;
    ++f->windows;
    return VFIT_TOOK_FIT;
}

/* The same window's instrumental-variable fit with an intercept (volt_fit.h): the centred sums
 * C_ab = S_ab - S_a S_b / n of the instruments z = (i, w) against the regressors x = (i, v) and
 * y, theta = (R_c, n Ke_c) from A theta = c with A = C_zx, c = C_zy; u0 = mean y - theta' mean x;
 * var(u0) = s^2 (1 / n + q' C_zz q) = s^2 vif / n, q = A^-T mean x. The offset b = -u0 / R_c. */
static int vfit_offset(vfit_t *f, const tv_real_t *s, uint32_t n)
{
    const tv_real_t inv_n = TV_R(1.0) / (tv_real_t)n;
    const tv_real_t mi = s[6] * inv_n;
    const tv_real_t mw = s[7] * inv_n;
    const tv_real_t my = s[8] * inv_n;
    const tv_real_t mv = s[13] * inv_n;
    const tv_real_t cii = s[0] - s[6] * mi;
    const tv_real_t ciw = s[1] - s[6] * mw;
    const tv_real_t cww = s[2] - s[7] * mw;
    const tv_real_t ciy = s[3] - s[6] * my;
    const tv_real_t cwy = s[4] - s[7] * my;
    const tv_real_t cyy = s[5] - s[8] * my;
    const tv_real_t civ = s[9] - s[6] * mv;
    const tv_real_t cwv = s[10] - s[7] * mv;
    const tv_real_t cvv = s[11] - s[13] * mv;
    const tv_real_t cvy = s[12] - s[13] * my;
    /* A = [cii civ; ciw cwv] */
    const tv_real_t det = cii * cwv - civ * ciw;
    tv_real_t r;
    tv_real_t k;
    tv_real_t var;
    tv_real_t q0;
    tv_real_t q1;
    tv_real_t b;
    tv_real_t vif;
    /* the instruments (nearly) collinear, or either constant (A's determinant, not the
     * instruments' own, must be positive) */
    if (!vfit_apart(f, cii, ciw, cww, det)) {
        return 0;
    }
    vfit_iv2(cii, civ, ciw, cwv, ciy, cwy, det, &r, &k);
    if (!(r > TV_R(0.0))) {
        return 0;
    }
    /* residual sum of squares of y - r i - k v (centred), per degree of freedom, times the correlation length */
    var = vfit_rss(cyy, ciy, cvy, cii, civ, cvv, r, k) / (tv_real_t)(n - 3u) * f->cfg.corr_periods;
    if (var < TV_R(0.0)) {
        var = TV_R(0.0); /* rounding of a near-perfect fit */
    }
    q0 = (cwv * mi - ciw * mv) / det;
    q1 = (cii * mv - civ * mi) / det;
    b = -(my - r * mi - k * mv) / r;
    vif = TV_R(1.0) + (tv_real_t)n * (q0 * q0 * cii + TV_R(2.0) * q0 * q1 * ciw + q1 * q1 * cww);
    if (!TV_IS_FINITE(b) || !TV_IS_FINITE(vif)) {
        return 0;
    }
    f->i_off_A = b;
    f->i_off_vif = vif;
    f->i_off_sigma_A = TV_SQRT(var * inv_n * vif) / r;
    f->off_valid = 1u;
    return VFIT_TOOK_OFFSET;
}

int vfit_step(vfit_t *f, tv_real_t u_V, tv_real_t i0_A, tv_real_t i1_A, tv_real_t w0_rad_s, tv_real_t w1_rad_s,
              tv_real_t v_rad_s)
{
    tv_real_t i;
    tv_real_t w;
    tv_real_t y;
    tv_real_t win[sizeof f->s / sizeof f->s[0]];
    unsigned b;
    unsigned c;
    uint32_t n;
    if (f == NULL || !(u_V >= f->cfg.u_min_V || u_V <= -f->cfg.u_min_V)) {
        return 0;
    }
    i = TV_R(0.5) * (i0_A + i1_A);
    w = TV_R(0.5) * (w0_rad_s + w1_rad_s);
    y = u_V - f->l_over_t * (i1_A - i0_A);
    if (!TV_IS_FINITE(i) || !TV_IS_FINITE(w) || !TV_IS_FINITE(y) || !TV_IS_FINITE(v_rad_s)) {
        return 0;
    }
    f->s[0] += i * i;
    f->s[1] += i * w;
    f->s[2] += w * w;
    f->s[3] += i * y;
    f->s[4] += w * y;
    f->s[5] += y * y;
    f->s[6] += i;
    f->s[7] += w;
    f->s[8] += y;
    f->s[9] += i * v_rad_s;
    f->s[10] += w * v_rad_s;
    f->s[11] += v_rad_s * v_rad_s;
    f->s[12] += v_rad_s * y;
    f->s[13] += v_rad_s;
    if (++f->n < f->cfg.block) {
        return 0;
    }
    /* a complete block: into the ring, and the window over the last `blocks` of them */
    memcpy(f->ring[f->next], f->s, sizeof f->s);
    f->next = (uint8_t)(f->next + 1u < f->cfg.blocks ? f->next + 1u : 0u);
    if (f->full < f->cfg.blocks) {
        ++f->full;
    }
    memset(f->s, 0, sizeof f->s);
    f->n = 0u;
    if (f->full < f->cfg.blocks) {
        return 0;
    }
    memset(win, 0, sizeof win);
    for (b = 0u; b < f->cfg.blocks; ++b) {
        for (c = 0u; c < sizeof win / sizeof win[0]; ++c) {
            win[c] += f->ring[b][c];
        }
    }
    n = (uint32_t)f->cfg.blocks * f->cfg.block;
    return vfit_offset(f, win, n) | vfit_solve(f, win, n);
}
