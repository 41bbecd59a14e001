/**
 * @file stop_learn.c
 * @brief Start-up stop learning (see stop_learn.h).
 */
#include "stop_learn.h"

#include <stddef.h>
#include <string.h>

#include "rawlog.h"
#include "tv_status.h"

enum { STAGE_SEEK = 0, STAGE_SETTLE = 1, STAGE_MEASURE = 2, STAGE_FIT = 3 };

/** Weight of a new sample in the velocity low-pass (time constant 10 ms at 1 kHz). */
#define SL_W_ALPHA TV_R(0.1)

void sl_config_default(sl_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->approach_rad_s = TV_R(0.5);
    cfg->overshoot_rad = TV_R(0.15);
    cfg->push_V = TV_R(6.0);
    cfg->hold_Nm = TV_R(0.15);
    cfg->kp_V_rad = TV_R(40.0);
    cfg->kd_V_s_rad = TV_R(1.0);
    cfg->still_rad = TV_R(0.002);
    cfg->lead_rad = TV_R(0.03);
    cfg->ki_V_rad_s = TV_R(200.0);
    cfg->block_ms = 100u;
    cfg->timeout_s = TV_R(8.0);
    cfg->closed_min_rad = TV_R(-0.30);
    cfg->closed_max_rad = TV_R(-0.02);
    cfg->open_min_rad = TV_R(1.10);
    cfg->open_max_rad = TV_R(1.70);
    cfg->travel_min_rad = TV_R(1.20);
    cfg->travel_max_rad = TV_R(1.80);
    cfg->level_Nm[0] = TV_R(0.7);
    cfg->level_Nm[1] = TV_R(0.45);
    cfg->level_Nm[2] = TV_R(0.3);
    cfg->dither_Nm = TV_R(0.3);
    cfg->dither_half_ms = 5u;
    cfg->e_min = TV_R(1.0);
    cfg->e_max = TV_R(2.0);
    cfg->k_min = TV_R(100.0);
    cfg->k_max = TV_R(1.0e4);
    cfg->lambda_per_k_s_rad = TV_R(0.16);
    cfg->level_V_max = TV_R(10.0);
    cfg->preload_Nm = TV_R(0.6);
}

static int finite_pos(tv_real_t v)
{
    return TV_IS_FINITE(v) && v > TV_R(0.0);
}

static int config_ok(const sl_config_t *c)
{
    const tv_real_t vals[] = {c->approach_rad_s, c->overshoot_rad, c->push_V, c->hold_Nm, c->kp_V_rad,
                              c->kd_V_s_rad, c->still_rad, c->lead_rad, c->ki_V_rad_s, c->timeout_s,
                              c->closed_min_rad, c->closed_max_rad, c->open_min_rad, c->open_max_rad,
                              c->travel_min_rad, c->travel_max_rad, c->level_Nm[0], c->level_Nm[1],
                              c->level_Nm[2], c->dither_Nm, c->e_min, c->e_max, c->k_min, c->k_max, c->lambda_per_k_s_rad,
                              c->level_V_max, c->preload_Nm};
    size_t k;
    for (k = 0; k < sizeof vals / sizeof vals[0]; ++k) {
        if (!TV_IS_FINITE(vals[k])) {
            return 0;
        }
    }
    return finite_pos(c->approach_rad_s) && c->approach_rad_s <= TV_R(1.0) && finite_pos(c->overshoot_rad) &&
           finite_pos(c->push_V) && c->hold_Nm >= TV_R(0.0) && finite_pos(c->kp_V_rad) && c->kd_V_s_rad >= TV_R(0.0) &&
           finite_pos(c->still_rad) && finite_pos(c->lead_rad) && c->ki_V_rad_s >= TV_R(0.0) && finite_pos(c->timeout_s) &&
           c->block_ms >= 10u && c->block_ms <= SL_BLOCK_MAX && c->closed_min_rad < c->closed_max_rad &&
           c->open_min_rad < c->open_max_rad && c->travel_min_rad < c->travel_max_rad &&
           c->level_Nm[0] > c->level_Nm[1] && c->level_Nm[1] > c->level_Nm[2] && c->level_Nm[2] > c->hold_Nm &&
           c->hold_Nm > TV_R(0.0) && c->dither_Nm >= TV_R(0.0) && c->dither_half_ms >= 1u && c->e_min >= TV_R(1.0) &&
           c->e_max >= c->e_min && c->e_max <= TV_R(3.0) && finite_pos(c->k_min) && c->k_max > c->k_min &&
           c->lambda_per_k_s_rad >= TV_R(0.0) && c->level_V_max >= c->push_V && c->preload_Nm >= TV_R(0.0);
}

int sl_start(sl_t *sl, const sl_config_t *cfg, const tvm_params_t *model)
{
    tvm_t probe;
    if (sl == NULL || cfg == NULL || model == NULL) {
        return TV_ERR_NULL;
    }
    if (!config_ok(cfg) || tvm_init(&probe, model) != TV_OK) {
        return TV_ERR_CONFIG;
    }
    memset(sl, 0, sizeof *sl);
    sl->cfg = *cfg;
    sl->model = *model;
    sl->phase = SL_CLOSED;
    sl->error = SL_ERR_NONE;
    return TV_OK;
}

int sl_running(const sl_t *sl)
{
    return sl != NULL && (sl->phase == SL_CLOSED || sl->phase == SL_OPEN);
}

static tv_real_t clampv(tv_real_t v, tv_real_t lim)
{
    return v > lim ? lim : (v < -lim ? -lim : v);
}

static void block_reset(sl_t *sl)
{
    sl->blk_n = 0u;
    sl->n_sat = 0u;
    sl->blk_sum = TV_R(0.0);
}

/* Add a sample; 1 when the block is complete (min, max, sum valid). */
static int block_add(sl_t *sl, tv_real_t phi)
{
    if (sl->blk_n == 0u) {
        sl->blk_min = phi;
        sl->blk_max = phi;
    } else {
        sl->blk_min = phi < sl->blk_min ? phi : sl->blk_min;
        sl->blk_max = phi > sl->blk_max ? phi : sl->blk_max;
    }
    sl->blk_sum += phi;
    ++sl->blk_n;
    return sl->blk_n >= sl->cfg.block_ms;
}

static tv_real_t fail(sl_t *sl, sl_error_t e)
{
    sl->phase = SL_FAILED;
    sl->error = e;
    return TV_R(0.0);
}

/* Rest angles a[j] (j < n) at forces F[j]: finite and positive respectively, 2 <= n <= SL_LEVELS. */
static int fit_inputs_ok(const tv_real_t *F_Nm, const tv_real_t *a_rad, unsigned n)
{
    unsigned j;
    if (n < 2u || n > SL_LEVELS) {
        return 0;
    }
    for (j = 0; j < n; ++j) {
        if (!(F_Nm[j] > TV_R(0.0)) || !TV_IS_FINITE(a_rad[j])) {
            return 0;
        }
    }
    return 1;
}

/*
 * The fit of sl_contact_fit() on g[j] = F[j]^(1/e) (penetration = k^(-1/e) g), with the sum of
 * squared residuals of the result into *sse. Inputs checked by the callers. TV_ERR_CONFIG when
 * all g are equal.
 */
static int fit_law(const tv_real_t *g, const tv_real_t *a_rad, unsigned n, tv_real_t dir, tv_real_t e, tv_real_t k_min,
                   tv_real_t k_max, tv_real_t *a0_rad, tv_real_t *k, tv_real_t *sse)
{
    tv_real_t gm = TV_R(0.0);
    tv_real_t am = TV_R(0.0);
    tv_real_t sgg = TV_R(0.0);
    tv_real_t sga = TV_R(0.0);
    tv_real_t ss = TV_R(0.0);
    tv_real_t c;
    tv_real_t kk;
    unsigned j;
    for (j = 0; j < n; ++j) {
        gm += g[j];
        am += a_rad[j];
    }
    gm /= (tv_real_t)n;
    am /= (tv_real_t)n;
    for (j = 0; j < n; ++j) {
        sgg += (g[j] - gm) * (g[j] - gm);
        sga += (g[j] - gm) * (a_rad[j] - am) * dir;
    }
    if (!(sgg > TV_R(0.0))) {
        return TV_ERR_CONFIG;
    }
    c = sga / sgg; /* k^(-1/e) */
    kk = c > TV_R(0.0) ? TV_POWP(c, -e) : k_max;
    kk = kk > k_max ? k_max : (kk < k_min ? k_min : kk);
    c = TV_POWP(kk, -TV_R(1.0) / e);
    *k = kk;
    *a0_rad = am - dir * c * gm;
    for (j = 0; j < n; ++j) {
        const tv_real_t r = a_rad[j] - *a0_rad - dir * c * g[j];
        ss += r * r;
    }
    *sse = ss;
    return TV_OK;
}

int sl_contact_fit(const tv_real_t *F_Nm, const tv_real_t *a_rad, unsigned n, tv_real_t dir, tv_real_t e,
                   tv_real_t k_min, tv_real_t k_max, tv_real_t *a0_rad, tv_real_t *k)
{
    tv_real_t g[SL_LEVELS];
    tv_real_t sse;
    unsigned j;
    if (F_Nm == NULL || a_rad == NULL || a0_rad == NULL || k == NULL) {
        return TV_ERR_NULL;
    }
    if (!fit_inputs_ok(F_Nm, a_rad, n) || !(e >= TV_R(1.0) && e <= TV_R(3.0)) || !(k_min > TV_R(0.0)) ||
        !(k_max > k_min)) {
        return TV_ERR_CONFIG;
    }
    for (j = 0; j < n; ++j) {
        g[j] = TV_POWP(F_Nm[j], TV_R(1.0) / e);
    }
    return fit_law(g, a_rad, n, dir, e, k_min, k_max, a0_rad, k, &sse);
}

/* Net torque of level j [N m]. */
static tv_real_t level_torque(const sl_config_t *c, unsigned j)
{
    return j + 1u < SL_LEVELS ? c->level_Nm[j] : c->hold_Nm;
}

/* Validation shared by the joint fit and the routine's fitting stage. */
static int joint_inputs_ok(const tv_real_t *F_Nm, const tv_real_t a_rad[2][SL_LEVELS], unsigned n, tv_real_t e_min,
                           tv_real_t e_max, tv_real_t k_min, tv_real_t k_max)
{
    return e_min >= TV_R(1.0) && e_max >= e_min && e_max <= TV_R(3.0) && fit_inputs_ok(F_Nm, a_rad[0], n) &&
           fit_inputs_ok(F_Nm, a_rad[1], n) && k_min > TV_R(0.0) && k_max > k_min;
}

/* Exponent g of the joint fit's grid (one value, e_min, when e_max = e_min). */
static tv_real_t grid_exponent(tv_real_t e_min, tv_real_t e_max, unsigned g)
{
    return e_min + (e_max - e_min) * (tv_real_t)g / (tv_real_t)(SL_EXP_GRID - 1u);
}

/* Number of exponents of the grid: SL_EXP_GRID, or 1 for a fixed exponent. */
static unsigned grid_size(tv_real_t e_min, tv_real_t e_max)
{
    return e_max > e_min ? SL_EXP_GRID : 1u;
}

/* Both stops' laws for the exponent eg; their sum of squared residuals into *sse. */
static int fit_exponent(const tv_real_t *F_Nm, const tv_real_t a_rad[2][SL_LEVELS], unsigned n, tv_real_t eg,
                        tv_real_t k_min, tv_real_t k_max, tv_real_t a0[2], tv_real_t kk[2], tv_real_t *sse)
{
    /* the bounds are secant stiffnesses at SL_P_REF_RAD: k p_ref^(e-1) in [k_min, k_max] */
    const tv_real_t to_law = TV_POWP(SL_P_REF_RAD, TV_R(1.0) - eg);
    tv_real_t gF[SL_LEVELS];
    unsigned s;
    unsigned j;
    *sse = TV_R(0.0);
    for (j = 0; j < n; ++j) {
        gF[j] = TV_POWP(F_Nm[j], TV_R(1.0) / eg); /* shared by both stops */
    }
    for (s = 0; s < 2u; ++s) {
        tv_real_t sse_s;
        const int rc = fit_law(gF, a_rad[s], n, s == 0u ? TV_R(-1.0) : TV_R(1.0), eg, k_min * to_law, k_max * to_law,
                               &a0[s], &kk[s], &sse_s);
        if (rc != TV_OK) {
            return rc;
        }
        *sse += sse_s;
    }
    return TV_OK;
}

int sl_contact_fit_joint(const tv_real_t *F_Nm, const tv_real_t a_rad[2][SL_LEVELS], unsigned n, tv_real_t e_min,
                         tv_real_t e_max, tv_real_t k_min, tv_real_t k_max, tv_real_t onset_rad[2], tv_real_t k[2],
                         tv_real_t *e)
{
    tv_real_t best = TV_R(-1.0);
    unsigned g;
    if (F_Nm == NULL || a_rad == NULL || onset_rad == NULL || k == NULL || e == NULL) {
        return TV_ERR_NULL;
    }
    if (!joint_inputs_ok(F_Nm, a_rad, n, e_min, e_max, k_min, k_max)) {
        return TV_ERR_CONFIG;
    }
    for (g = 0; g < grid_size(e_min, e_max); ++g) {
        const tv_real_t eg = grid_exponent(e_min, e_max, g);
        tv_real_t a0[2];
        tv_real_t kk[2];
        tv_real_t sse;
        const int rc = fit_exponent(F_Nm, a_rad, n, eg, k_min, k_max, a0, kk, &sse);
        if (rc != TV_OK) {
            return rc;
        }
        if (best < TV_R(0.0) || sse < best) {
            best = sse;
            onset_rad[0] = a0[0];
            onset_rad[1] = a0[1];
            k[0] = kk[0];
            k[1] = kk[1];
            *e = eg;
        }
    }
    return TV_OK;
}

/* The routine's net torques, level by level [N m]. */
static void level_torques(const sl_config_t *c, tv_real_t F[SL_LEVELS])
{
    unsigned j;
    for (j = 0; j < SL_LEVELS; ++j) {
        F[j] = level_torque(c, j);
    }
}

/* The fitting stage: up to SL_FIT_PER_STEP exponents of the joint fit this period (the same
 * grid and choice as sl_contact_fit_joint(), spread over periods); when the grid is done, the
 * result and SL_DONE. */
static void fit_step(sl_t *sl)
{
    const sl_config_t *c = &sl->cfg;
    const unsigned n_grid = grid_size(c->e_min, c->e_max);
    tv_real_t F[SL_LEVELS];
    unsigned m;
    level_torques(c, F);
    for (m = 0; m < SL_FIT_PER_STEP && sl->fit_g < n_grid; ++m, ++sl->fit_g) {
        const tv_real_t eg = grid_exponent(c->e_min, c->e_max, sl->fit_g);
        tv_real_t a0[2];
        tv_real_t kk[2];
        tv_real_t sse;
        if (fit_exponent(F, (const tv_real_t(*)[SL_LEVELS])sl->rest_rad, SL_LEVELS, eg, c->k_min, c->k_max, a0, kk,
                         &sse) != TV_OK) {
            (void)fail(sl, SL_ERR_IMPLAUSIBLE_OPEN);
            return;
        }
        if (sl->fit_sse_best < TV_R(0.0) || sse < sl->fit_sse_best) {
            sl->fit_sse_best = sse;
            sl->fit_onset[0] = a0[0];
            sl->fit_onset[1] = a0[1];
            sl->k_fit[0] = kk[0];
            sl->k_fit[1] = kk[1];
            sl->exponent = eg;
        }
    }
    if (sl->fit_g >= n_grid) {
        sl->onset_closed_rad = sl->fit_onset[0];
        sl->onset_open_rad = sl->fit_onset[1];
        sl->k_stop = TV_SQRT(sl->k_fit[0] * sl->k_fit[1]);
        sl->phase = SL_DONE;
    }
}

/* A stop was measured at phi: record it, move on (or finish with the plausibility checks). */
static void stop_measured(sl_t *sl, tv_real_t phi)
{
    const sl_config_t *c = &sl->cfg;
    if (sl->phase == SL_CLOSED) {
        if (phi < c->closed_min_rad || phi > c->closed_max_rad) {
            (void)fail(sl, SL_ERR_IMPLAUSIBLE_CLOSED);
            return;
        }
        sl->phi_closed_rad = phi;
        sl->phase = SL_OPEN;
        sl->n_phase = 0u;
        sl->stage = STAGE_SEEK;
        sl->integ_V = TV_R(0.0);
        block_reset(sl);
        return;
    }
    if (phi < c->open_min_rad || phi > c->open_max_rad) {
        (void)fail(sl, SL_ERR_IMPLAUSIBLE_OPEN);
        return;
    }
    if (phi - sl->phi_closed_rad < c->travel_min_rad || phi - sl->phi_closed_rad > c->travel_max_rad) {
        (void)fail(sl, SL_ERR_IMPLAUSIBLE_TRAVEL);
        return;
    }
    sl->phi_open_rad = phi;
    {
        tv_real_t F[SL_LEVELS];
        level_torques(c, F);
        if (!joint_inputs_ok(F, (const tv_real_t(*)[SL_LEVELS])sl->rest_rad, SL_LEVELS, c->e_min, c->e_max, c->k_min,
                             c->k_max)) {
            (void)fail(sl, SL_ERR_IMPLAUSIBLE_OPEN);
            return;
        }
    }
    /* the joint fit of both laws runs over the next periods (fit_step()) */
    sl->stage = STAGE_FIT;
    sl->fit_g = 0u;
    sl->fit_sse_best = TV_R(-1.0);
}

tv_real_t sl_step(sl_t *sl, tv_real_t phi)
{
    const sl_config_t *c;
    const tvm_params_t *p;
    tv_real_t dir;
    tv_real_t goal;
    tv_real_t v_per_Nm;
    if (sl == NULL || !sl_running(sl)) {
        return TV_R(0.0);
    }
    c = &sl->cfg;
    p = &sl->model;
    tv_real_t w;
    if (!TV_IS_FINITE(phi)) {
        return fail(sl, SL_ERR_INPUT);
    }
    if ((tv_real_t)sl->n_phase * p->Ts_s > c->timeout_s) {
        return fail(sl, sl->phase == SL_CLOSED ? SL_ERR_TIMEOUT_CLOSED : SL_ERR_TIMEOUT_OPEN);
    }
    ++sl->n_total;
    dir = sl->phase == SL_CLOSED ? TV_R(-1.0) : TV_R(1.0);
    goal = sl->phase == SL_CLOSED ? p->phi_closed_rad - c->overshoot_rad : p->phi_open_rad + c->overshoot_rad;
    v_per_Nm = p->R_ohm / (p->n_gear * p->Kt_Nm_A);
    if (sl->n_phase++ == 0u) {
        sl->target_rad = phi; /* start from where the plate is */
        sl->phi_prev = phi;
        sl->w_f = TV_R(0.0);
        block_reset(sl);
    }
    /* velocity for the D term: the differentiated measured angle through a first-order low-pass
     * (time constant Ts / SL_W_ALPHA); the sensor alone, so a filter whose stops are wrong (the
     * reason for learning them) cannot upset the routine */
    sl->w_f += SL_W_ALPHA * ((phi - sl->phi_prev) / p->Ts_s - sl->w_f);
    sl->phi_prev = phi;
    w = sl->w_f;
    if (sl->stage == STAGE_FIT) {
        /* both stops measured: the plate is held at the last level while the law is fitted */
        fit_step(sl);
        return sl_running(sl) ? sl->u_hold_V : TV_R(0.0);
    }
    if (sl->stage == STAGE_SEEK) {
        tv_real_t u;
        tv_real_t e;
        const tv_real_t step = c->approach_rad_s * p->Ts_s;
        tv_real_t v_t = dir * c->approach_rad_s;
        if (dir * (goal - sl->target_rad) > step) {
            sl->target_rad += dir * step;
        } else {
            sl->target_rad = goal;
            v_t = TV_R(0.0);
        }
        /* the target never leads the plate by more than lead_rad: a plate held by friction
         * waits for the integral to break it away, and then cannot run far ahead */
        if (dir * (sl->target_rad - phi) > c->lead_rad) {
            sl->target_rad = phi + dir * c->lead_rad;
            v_t = TV_R(0.0);
        }
        e = sl->target_rad - phi;
        sl->integ_V = clampv(sl->integ_V + c->ki_V_rad_s * e * p->Ts_s, c->push_V);
        u = v_per_Nm * tvm_spring_torque(p, sl->target_rad) + p->n_gear * p->Ke_V_s_rad * v_t + c->kp_V_rad * e +
            sl->integ_V - c->kd_V_s_rad * w;
        if (dir * u >= c->push_V) {
            ++sl->n_sat;
        }
        if (block_add(sl, phi)) {
            const tv_real_t mean = sl->blk_sum / (tv_real_t)sl->blk_n;
            /* still through a whole block with the full push toward the stop: pressed against
             * it (or jammed: the plausibility windows tell) */
            if (sl->n_sat >= sl->blk_n && sl->blk_max - sl->blk_min < c->still_rad) {
                sl->stage = STAGE_SETTLE;
                sl->level = 0u;
                sl->contact_phi_rad = mean;
                sl->u_hold_V = clampv(v_per_Nm * (tvm_spring_torque(p, mean) + dir * level_torque(c, 0u)), c->level_V_max);
            }
            block_reset(sl);
        }
        return clampv(u, c->push_V);
    }
    {
        /* settling: a square dither around the level's voltage shakes the plate free of
         * stiction, so it comes to rest where the stop balances the level's torque */
        const int dither_on = sl->stage == STAGE_SETTLE && sl->blk_n + c->dither_half_ms * 2u <= c->block_ms;
        const tv_real_t dither_V = v_per_Nm * c->dither_Nm;
        const tv_real_t dither = dither_on ? (((sl->blk_n / c->dither_half_ms) & 1u) != 0u ? -dither_V : dither_V)
                                           : TV_R(0.0);
        /* before the first level, a preload at the full level voltage: every level is then
         * reached by UNLOADING (the plate moves out to its rest), whose rest angle friction does
         * not bias; reached by loading, a rest angle is short by about the static friction */
        const int preload = sl->stage == STAGE_SETTLE && sl->level == 0u && sl->blk_n < 2u * (c->block_ms / 4u);
        if (block_add(sl, phi)) {
            const tv_real_t mean = sl->blk_sum / (tv_real_t)sl->blk_n;
            const int still = sl->blk_max - sl->blk_min < c->still_rad;
            block_reset(sl);
            if (sl->stage == STAGE_SETTLE) {
                sl->stage = STAGE_MEASURE;
            } else if (still) {
                sl->rest_rad[sl->phase == SL_CLOSED ? 0 : 1][sl->level] = mean;
                if (sl->level + 1u < SL_LEVELS) {
                    ++sl->level;
                    sl->stage = STAGE_SETTLE;
                    sl->u_hold_V = clampv(v_per_Nm * (tvm_spring_torque(p, sl->contact_phi_rad) + dir * level_torque(c, sl->level)),
                                          c->level_V_max);
                    return sl->u_hold_V;
                }
                stop_measured(sl, mean);
                return sl_running(sl) ? sl->u_hold_V : TV_R(0.0);
            }
        }
        if (preload) {
            /* preload_Nm above the first level, a triangle over half a block (up a quarter, down a
             * quarter): a soft stop is compressed and released slowly, never struck */
            const uint32_t q = c->block_ms / 4u;
            const tv_real_t frac = sl->blk_n < q ? (tv_real_t)sl->blk_n / (tv_real_t)q
                                                 : (tv_real_t)(2u * q - sl->blk_n) / (tv_real_t)q;
            const tv_real_t u_pre =
                clampv(v_per_Nm * (tvm_spring_torque(p, sl->contact_phi_rad) + dir * (level_torque(c, 0u) + c->preload_Nm)),
                       c->level_V_max);
            return sl->u_hold_V + frac * (u_pre - sl->u_hold_V);
        }
        return clampv(sl->u_hold_V + dither, c->level_V_max);
    }
}

const char *sl_phase_name(sl_phase_t ph)
{
    static const char *const names[] = {"idle", "closed", "open", "done", "failed"};
    return (unsigned)ph < sizeof names / sizeof names[0] ? names[ph] : "?";
}

const char *sl_error_name(sl_error_t e)
{
    static const char *const names[] = {"none",
                                        "timeout at the closed stop",
                                        "timeout at the open stop",
                                        "closed stop outside its plausible window",
                                        "open stop outside its plausible window",
                                        "travel outside its plausible window",
                                        "non-finite input"};
    return (unsigned)e < sizeof names / sizeof names[0] ? names[e] : "?";
}

uint32_t sl_crc32(const uint8_t *data, uint32_t n)
{
    return data == NULL ? 0u : rawlog_crc32(0u, data, (size_t)n);
}

static void put_u32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)v;
    b[1] = (uint8_t)(v >> 8);
    b[2] = (uint8_t)(v >> 16);
    b[3] = (uint8_t)(v >> 24);
}

static uint32_t get_u32(const uint8_t *b)
{
    return (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) | ((uint32_t)b[3] << 24);
}

static uint32_t f32_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float bits_f32(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

int sl_nvm_pack(const sl_nvm_t *rec, uint8_t buf[SL_NVM_BYTES])
{
    if (rec == NULL || buf == NULL) {
        return TV_ERR_NULL;
    }
    put_u32(buf, rec->magic);
    put_u32(buf + 4, (uint32_t)rec->version | ((uint32_t)rec->reserved << 16));
    put_u32(buf + 8, f32_bits(rec->phi_closed_rad));
    put_u32(buf + 12, f32_bits(rec->phi_open_rad));
    put_u32(buf + 16, f32_bits(rec->fit_base_r_ohm));
    put_u32(buf + 20, f32_bits(rec->fit_base_nke_V_s));
    put_u32(buf + 24, rec->n_learns);
    put_u32(buf + 28, sl_crc32(buf, 28u));
    return TV_OK;
}

int sl_nvm_unpack(const uint8_t buf[SL_NVM_BYTES], sl_nvm_t *rec)
{
    sl_nvm_t r;
    sl_config_t d;
    uint32_t vw;
    uint32_t crc_n;
    if (buf == NULL || rec == NULL) {
        return TV_ERR_NULL;
    }
    sl_config_default(&d);
    r.magic = get_u32(buf);
    vw = get_u32(buf + 4);
    r.version = (uint16_t)(vw & 0xFFFFu);
    r.reserved = (uint16_t)(vw >> 16);
    r.phi_closed_rad = bits_f32(get_u32(buf + 8));
    r.phi_open_rad = bits_f32(get_u32(buf + 12));
    if (r.version == 1u) {
        /* the stops alone: the baseline none */
        r.fit_base_r_ohm = 0.0f;
        r.fit_base_nke_V_s = 0.0f;
        r.n_learns = get_u32(buf + 16);
        r.crc32 = get_u32(buf + 20);
        crc_n = 20u;
    } else {
        r.fit_base_r_ohm = bits_f32(get_u32(buf + 16));
        r.fit_base_nke_V_s = bits_f32(get_u32(buf + 20));
        r.n_learns = get_u32(buf + 24);
        r.crc32 = get_u32(buf + 28);
        crc_n = 28u;
    }
    if (r.magic != SL_NVM_MAGIC || (r.version != 1u && r.version != SL_NVM_VERSION) || r.crc32 != sl_crc32(buf, crc_n)) {
        return TV_ERR_FORMAT;
    }
    /* NaN fails every comparison below */
    if (!((tv_real_t)r.phi_closed_rad >= d.closed_min_rad && (tv_real_t)r.phi_closed_rad <= d.closed_max_rad &&
          (tv_real_t)r.phi_open_rad >= d.open_min_rad && (tv_real_t)r.phi_open_rad <= d.open_max_rad)) {
        return TV_ERR_FORMAT;
    }
    /* the baseline: none, or both plausible (NaN and infinities fail the bounds) */
    if (!((r.fit_base_r_ohm == 0.0f && r.fit_base_nke_V_s == 0.0f) ||
          (r.fit_base_r_ohm > 0.0f && r.fit_base_r_ohm <= SL_NVM_FIT_BASE_R_MAX_OHM && r.fit_base_nke_V_s > 0.0f &&
           r.fit_base_nke_V_s <= SL_NVM_FIT_BASE_NKE_MAX_V_S))) {
        return TV_ERR_FORMAT;
    }
    *rec = r;
    return TV_OK;
}
