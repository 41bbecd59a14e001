/**
 * @file stop_track.c
 * @brief Online stop tracking (stop_track.h).
 */
#include "stop_track.h"

#include "tv_status.h"

#include <stddef.h>
#include <string.h>

void st_config_default(st_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->enable = 1u;
    cfg->block = 100u;
    cfg->rest_band_rad = TV_R(1.5e-3);
    cfg->w_rest_rad_s = TV_R(5.0);
    cfg->near_rad = TV_R(0.01);
    cfg->push_min_Nm = TV_R(0.3);
    cfg->push_max_Nm = TV_R(3.0);
    cfg->gain = TV_R(0.2);
    cfg->window_rad = TV_R(0.005);
    cfg->envelope = 1u;
    cfg->env_min_rad = TV_R(0.001);
    cfg->env_window_rad = TV_R(0.1);
}

int st_config_check(const st_config_t *cfg)
{
    if (cfg == NULL) {
        return TV_ERR_NULL;
    }
    if (!TV_IS_FINITE(cfg->rest_band_rad) || !TV_IS_FINITE(cfg->w_rest_rad_s) || !TV_IS_FINITE(cfg->near_rad) ||
        !TV_IS_FINITE(cfg->push_min_Nm) || !TV_IS_FINITE(cfg->push_max_Nm) || !TV_IS_FINITE(cfg->gain) ||
        !TV_IS_FINITE(cfg->window_rad) || !TV_IS_FINITE(cfg->env_min_rad) ||
        !TV_IS_FINITE(cfg->env_window_rad)) {
        return TV_ERR_NONFINITE;
    }
    if (cfg->enable > 1u || cfg->block < 20u || cfg->block > ST_BLOCK_MAX || !(cfg->rest_band_rad > TV_R(0.0)) ||
        !(cfg->w_rest_rad_s > TV_R(0.0)) || cfg->near_rad < TV_R(0.0) || !(cfg->push_min_Nm > TV_R(0.0)) ||
        !(cfg->push_max_Nm > cfg->push_min_Nm) || !(cfg->gain > TV_R(0.0)) || cfg->gain > TV_R(1.0) ||
        !(cfg->window_rad > TV_R(0.0)) || cfg->envelope > 1u || !(cfg->env_min_rad > TV_R(0.0)) ||
        !(cfg->env_window_rad > TV_R(0.0))) {
        return TV_ERR_CONFIG;
    }
    return TV_OK;
}

static void block_restart(st_t *t)
{
    t->n = 0u;
    t->phi_sum = TV_R(0.0);
    t->phi_min = TV_R(0.0);
    t->phi_max = TV_R(0.0);
    t->push_sum[ST_CLOSED] = TV_R(0.0);
    t->push_sum[ST_OPEN] = TV_R(0.0);
}

int st_reset(st_t *t, const st_config_t *cfg, tv_real_t closed_rad, tv_real_t open_rad)
{
    int rc;
    if (t == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    rc = st_config_check(cfg);
    if (rc != TV_OK) {
        return rc;
    }
    if (!TV_IS_FINITE(closed_rad) || !TV_IS_FINITE(open_rad)) {
        return TV_ERR_NONFINITE;
    }
    if (!(closed_rad < TV_R(0.0)) || !(open_rad > TV_R(0.0))) {
        return TV_ERR_CONFIG;
    }
    t->cfg = *cfg;
    t->ref[ST_CLOSED] = closed_rad;
    t->ref[ST_OPEN] = open_rad;
    t->onset[ST_CLOSED] = closed_rad;
    t->onset[ST_OPEN] = open_rad;
    t->start[ST_CLOSED] = closed_rad;
    t->start[ST_OPEN] = open_rad;
    t->n_accepted = 0u;
    t->n_refused = 0u;
    t->n_envelope = 0u;
    block_restart(t);
    return TV_OK;
}

/* Penetration of the model's contact law under a push P > 0 [N m]: (P / k)^(1/e), P / k for
 * Kelvin-Voigt (exponent 0). 0 when the law has no stiffness. */
static tv_real_t penetration(const tvm_params_t *m, tv_real_t push_Nm)
{
    const tv_real_t k = m->k_stop_Nm_rad;
    if (!(k > TV_R(0.0))) {
        return TV_R(0.0);
    }
    if (m->stop_exponent > TV_R(0.0)) {
        return TV_POWP(push_Nm / k, TV_R(1.0) / m->stop_exponent);
    }
    return push_Nm / k;
}

/* The block just completed: accept it at a stop, or not. Returns 1 when an onset moved. */
static int block_done(st_t *t, const tvm_params_t *model)
{
    const tv_real_t n = (tv_real_t)t->n;
    const tv_real_t phi = t->phi_sum / n;
    /* the stop the block is nearer to, by its tracked onset */
    const int q = (phi - t->onset[ST_CLOSED]) < (t->onset[ST_OPEN] - phi) ? ST_CLOSED : ST_OPEN;
    const tv_real_t s = q == ST_CLOSED ? TV_R(-1.0) : TV_R(1.0);
    const tv_real_t push = t->push_sum[q] / n;
    tv_real_t a;
    if (t->phi_max - t->phi_min > t->cfg.rest_band_rad) {
        return 0; /* not at rest */
    }
    /* beyond the onset, or within near_rad before it: s (phi - onset) >= -near; stops never
     * learned (envelope on) may lie anywhere within env_window_rad */
    const tv_real_t near = t->cfg.envelope ? t->cfg.env_window_rad : t->cfg.near_rad;
    const tv_real_t window = t->cfg.envelope ? t->cfg.env_window_rad : t->cfg.window_rad;
    if (s * (phi - t->onset[q]) < -near) {
        return 0;
    }
    if (push < t->cfg.push_min_Nm || (!t->cfg.envelope && push > t->cfg.push_max_Nm)) {
        return 0;
    }
    a = phi - s * penetration(model, push);
    if (!TV_IS_FINITE(a)) {
        return 0;
    }
    if (TV_FABS(a - t->ref[q]) > window) {
        ++t->n_refused;
        return 0;
    }
    t->onset[q] += t->cfg.gain * (a - t->onset[q]);
    ++t->n_accepted;
    return 1;
}

int st_step(st_t *t, const tvm_params_t *model, tv_real_t phi_rad, int phi_valid, tv_real_t i_A, tv_real_t w_rad_s)
{
    tv_real_t drive;
    int moved = 0;
    if (t == NULL || model == NULL || !t->cfg.enable) {
        return 0;
    }
    /* the estimated velocity is a rest criterion only with learned stops: against a stop the model
     * does not know yet the estimate is what is wrong (it holds a steady bias), the measured angle
     * range then decides alone */
    if (!phi_valid || !TV_IS_FINITE(phi_rad) || !TV_IS_FINITE(i_A) || !TV_IS_FINITE(w_rad_s) ||
        (!t->cfg.envelope && TV_FABS(w_rad_s) >= t->cfg.w_rest_rad_s)) {
        block_restart(t);
        return 0;
    }
    /* net torque toward opening: motor minus the springs (preload sign smoothed as the model's) */
    drive = model->n_gear * model->Kt_Nm_A * i_A - tvm_spring_torque(model, phi_rad);
    if (t->n == 0u) {
        t->phi_min = phi_rad;
        t->phi_max = phi_rad;
    } else {
        t->phi_min = phi_rad < t->phi_min ? phi_rad : t->phi_min;
        t->phi_max = phi_rad > t->phi_max ? phi_rad : t->phi_max;
    }
    t->phi_sum += phi_rad;
    t->push_sum[ST_OPEN] += drive;
    t->push_sum[ST_CLOSED] -= drive;
    ++t->n;
    if (t->n >= t->cfg.block) {
        moved = block_done(t, model);
        block_restart(t);
    }
    return moved;
}

int st_envelope(st_t *t, tv_real_t phi_meas, tv_real_t phi_pred, tv_real_t step_rad)
{
    tv_real_t thr;
    int q;
    if (t == NULL || !t->cfg.enable || !t->cfg.envelope || !TV_IS_FINITE(phi_meas) || !TV_IS_FINITE(phi_pred) ||
        !TV_IS_FINITE(step_rad)) {
        return 0;
    }
    thr = t->cfg.env_min_rad;
    for (q = 0; q < ST_NSTOPS; ++q) {
        const tv_real_t s = q == ST_CLOSED ? TV_R(-1.0) : TV_R(1.0);
        /* an onset never crosses zero (limp-home lies between the stops): the sign test */
        if (s * (phi_meas - t->onset[q]) > t->cfg.env_min_rad && s * (phi_meas - phi_pred) > thr && s * phi_meas > TV_R(0.0)) {
            const tv_real_t o = phi_meas + s * (TV_FABS(step_rad) + t->cfg.env_min_rad);
            t->onset[q] = o;
            t->ref[q] = o;
            ++t->n_envelope;
            block_restart(t);
            return 1;
        }
    }
    return 0;
}

int st_model_in_doubt(const st_t *t)
{
    if (t == NULL || !t->cfg.envelope) {
        return 0;
    }
    return TV_FABS(t->onset[ST_CLOSED] - t->start[ST_CLOSED]) > t->cfg.window_rad ||
           TV_FABS(t->onset[ST_OPEN] - t->start[ST_OPEN]) > t->cfg.window_rad;
}
