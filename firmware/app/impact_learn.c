/**
 * @file impact_learn.c
 * @brief Impact learning (impact_learn.h).
 */
#include "impact_learn.h"

#include "tv_status.h"

#include <stddef.h>

void il_config_default(il_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->enable = 1u; /* on: README "Impact learning" (off while it led P1A04 to a false alarm in the
                       * healthy soak; since P1A04 skips impact innovations, none in 170,100 s) */
    cfg->v_min_rad_s = TV_R(6.0);
    cfg->arm_margin_rad = TV_R(0.002);
    cfg->contact_max = 30u;
    cfg->settle = 3u;
    cfg->gain = TV_R(0.3);
    cfg->alpha_min = TV_R(0.04);
    cfg->alpha_max = TV_R(0.8);
    cfg->p_min_rad = TV_R(0.0015);
    cfg->k_sec_min = TV_R(100.0);
    cfg->k_sec_max = TV_R(1.0e4);
}

int il_config_check(const il_config_t *cfg)
{
    if (cfg == NULL) {
        return TV_ERR_NULL;
    }
    if (!TV_IS_FINITE(cfg->v_min_rad_s) || !TV_IS_FINITE(cfg->arm_margin_rad) || !TV_IS_FINITE(cfg->gain) ||
        !TV_IS_FINITE(cfg->alpha_min) || !TV_IS_FINITE(cfg->alpha_max) || !TV_IS_FINITE(cfg->p_min_rad) ||
        !TV_IS_FINITE(cfg->k_sec_min) || !TV_IS_FINITE(cfg->k_sec_max)) {
        return TV_ERR_NONFINITE;
    }
    if (cfg->enable > 1u || !(cfg->v_min_rad_s > TV_R(0.0)) || !(cfg->arm_margin_rad > TV_R(0.0)) ||
        cfg->contact_max < 2u || cfg->contact_max > 1000u || cfg->settle < (uint16_t)(IL_FIT_N - 1) || cfg->settle > 20u ||
        !(cfg->gain > TV_R(0.0)) || cfg->gain > TV_R(1.0) || !(cfg->alpha_min > TV_R(0.0)) ||
        !(cfg->alpha_max > cfg->alpha_min) || !(cfg->p_min_rad > TV_R(0.0)) || !(cfg->k_sec_min > TV_R(0.0)) ||
        !(cfg->k_sec_max > cfg->k_sec_min)) {
        return TV_ERR_CONFIG;
    }
    return TV_OK;
}

/* The per-impact accumulators at 0 (a new impact, or none). */
static void impact_restart(il_t *il)
{
    il->n = 0u;
    il->n_contact = 0u;
    il->p_max = TV_R(0.0);
    il->pen_last = TV_R(0.0);
    il->pen_before = TV_R(0.0);
    il->pen_after = TV_R(0.0);
    il->have_after = 0u;
    il->push_sum = TV_R(0.0);
    il->push_n = TV_R(0.0);
    il->dw_sum = TV_R(0.0);
}

int il_reset(il_t *il, const il_config_t *cfg, const tvm_params_t *model)
{
    int rc;
    if (il == NULL || cfg == NULL || model == NULL) {
        return TV_ERR_NULL;
    }
    rc = il_config_check(cfg);
    if (rc != TV_OK) {
        return rc;
    }
    if (!(model->k_stop_Nm_rad > TV_R(0.0)) || !TV_IS_FINITE(model->d_stop_Nm_s_rad)) {
        return TV_ERR_CONFIG;
    }
    il->cfg = *cfg;
    il->phase = IL_IDLE;
    il->stop = 0u;
    il->v_in = TV_R(0.0);
    impact_restart(il);
    il->k = model->k_stop_Nm_rad;
    il->alpha = model->d_stop_Nm_s_rad / model->k_stop_Nm_rad;
    il->rebound_err_last = TV_R(0.0);
    il->coupling = TV_R(1.0);
    il->n_learned = 0u;
    il->n_k = 0u;
    il->n_abandoned = 0u;
    return TV_OK;
}

/* Net torque the model puts into stop q (0 closed, 1 open) from the estimate: motor minus the
 * springs, > 0 pressing into it [N m]. */
static tv_real_t push_into(const tvm_params_t *m, int q, const tv_real_t x[TVM_NX])
{
    const tv_real_t drive = m->n_gear * m->Kt_Nm_A * x[TVM_I] - tvm_spring_torque(m, x[TVM_PHI]);
    return q == 0 ? -drive : drive;
}

/* A velocity (change), or an angle, as its component away from stop q (0 closed: positive; 1 open). */
static tv_real_t q_away(uint8_t q, tv_real_t w)
{
    return q == 0u ? w : -w;
}

static void abandon(il_t *il)
{
    ++il->n_abandoned;
    il->phase = IL_IDLE;
}

static tv_real_t clampr(tv_real_t v, tv_real_t lo, tv_real_t hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

/* The deepest penetration between the samples: the vertex of the parabola through the deepest
 * sampled one and its two neighbours (a 1 kHz sample lands at the deepest point only by
 * chance, and the energy balance takes the power e + 1 of it: the sampled maximum made k_obs
 * stiffer than the unit, measured); the sampled maximum where the neighbours do not bracket a
 * vertex within half a period of it. */
static tv_real_t peak_penetration(const il_t *il)
{
    const tv_real_t pm = il->p_max;
    const tv_real_t curv = il->pen_before - TV_R(2.0) * pm + il->pen_after;
    tv_real_t d;
    if (!il->have_after || !(curv < TV_R(0.0))) {
        return pm;
    }
    d = TV_R(0.5) * (il->pen_before - il->pen_after) / curv; /* vertex offset [periods] */
    if (!(d > TV_R(-0.5) && d < TV_R(0.5))) {
        return pm;
    }
    return pm - TV_R(0.25) * (il->pen_before - il->pen_after) * d;
}

/* The impact is over and settled: learn from it. Returns 1 when the law changed. */
static int learn(il_t *il, const tvm_params_t *m)
{
    const tv_real_t J = m->J_kg_m2;
    /* the mean net torque into the stop over the impact's compression */
    const tv_real_t push = il->push_n > TV_R(0.0) ? il->push_sum / il->push_n : TV_R(0.0);
    tv_real_t step;
    const tv_real_t e = m->stop_exponent;
    const tv_real_t g = il->cfg.gain;
    if (il->n_contact < 2u) {
        /* over within a sample: the rebound seen in hindsight, the speed at the ending sample of
         * the quadratic least-squares fit through it and the settle samples (weights of the
         * slope at t = 0 for t = 0, 1, 2, 3), against the model's own rebound (the prior) */
        const tv_real_t w_fit = (TV_R(-21.0) * il->phi_after[0] + TV_R(13.0) * il->phi_after[1] +
                                 TV_R(17.0) * il->phi_after[2] - TV_R(9.0) * il->phi_after[3]) /
                                (TV_R(20.0) * m->Ts_s);
        const tv_real_t made = il->w_end - il->w_prior_end; /* the correction the estimator made */
        const tv_real_t lack = w_fit - il->w_prior_end;     /* ... and the one that would have reached w_fit */
        step = -g * lack / (IL_REST_SENS * il->v_in);
        il->rebound_err_last = lack / il->v_in;
        if (TV_FABS(made) >= TV_R(0.05) * il->v_in) {
            /* the share of that correction that would have reached w_fit */
            const tv_real_t rho = clampr(lack / made, TV_R(0.25), TV_R(2.0));
            il->coupling = clampr(il->coupling * TV_EXP(IL_COUPLING_GAIN * TV_LOG(rho)), IL_COUPLING_MIN, TV_R(1.0));
        }
    } else {
        /* resolved: the estimator's velocity corrections over the impact and the settle samples
         * after it, away from the stop: < 0 when the measurements took speed the model's
         * rebound had given (too little damping), > 0 when they added what its rebound lacked */
        step = -g * il->dw_sum / il->v_in;
        il->rebound_err_last = il->dw_sum / il->v_in;
    }
    step = clampr(step, -TV_R(0.69314718055994531), TV_R(0.69314718055994531)); /* ln 2 */
    il->alpha = clampr(il->alpha * TV_EXP(step), il->cfg.alpha_min, il->cfg.alpha_max);
    ++il->n_learned;
    if (il->p_max >= il->cfg.p_min_rad && il->n_contact >= 2u) {
        /* k p^(e+1) / (e+1) = J (x - ln(1 + x)) / alpha^2 + push p  (x = alpha v_in) */
        const tv_real_t pk = peak_penetration(il);
        const tv_real_t xa = il->alpha * il->v_in;
        const tv_real_t energy = J * (xa - TV_LOG1P(xa)) / (il->alpha * il->alpha) + push * pk;
        const tv_real_t k_obs = (e + TV_R(1.0)) * energy / TV_POWP(pk, e + TV_R(1.0));
        const tv_real_t ref = TV_POWP(IL_P_REF_RAD, TV_R(1.0) - e);
        if (TV_IS_FINITE(k_obs) && k_obs > TV_R(0.0)) {
            il->k = clampr(il->k * TV_EXP(g * TV_LOG(k_obs / il->k)), il->cfg.k_sec_min * ref, il->cfg.k_sec_max * ref);
            ++il->n_k;
        }
    }
    il->phase = IL_IDLE;
    return 1;
}

int il_step(il_t *il, const tvm_params_t *model, tv_real_t phi_meas, int phi_valid, const tv_real_t x[TVM_NX],
            tv_real_t w_prior)
{
    const tv_real_t onset[2] = {model != NULL ? model->phi_closed_rad : TV_R(0.0),
                                model != NULL ? model->phi_open_rad : TV_R(0.0)};
    tv_real_t pen;
    tv_real_t toward;
    int q;
    if (il == NULL || model == NULL || x == NULL || !il->cfg.enable || !(model->stop_exponent >= TV_R(1.0))) {
        return 0;
    }
    if (!phi_valid || !TV_IS_FINITE(phi_meas) || !TV_IS_FINITE(x[TVM_W]) || !TV_IS_FINITE(x[TVM_PHI]) ||
        !TV_IS_FINITE(x[TVM_I]) || !TV_IS_FINITE(w_prior)) {
        if (il->phase != IL_IDLE) {
            abandon(il);
        }
        return 0;
    }
    switch (il->phase) {
    case IL_IDLE:
        /* armed: moving fast toward a stop that the next sample reaches */
        for (q = 0; q < 2; ++q) {
            const tv_real_t dist = q == 0 ? x[TVM_PHI] - onset[0] : onset[1] - x[TVM_PHI];
            toward = q == 0 ? -x[TVM_W] : x[TVM_W];
            if (toward >= il->cfg.v_min_rad_s && dist < toward * model->Ts_s + il->cfg.arm_margin_rad) {
                il->phase = IL_ARMED;
                il->stop = (uint8_t)q;
                il->v_in = toward;
                impact_restart(il);
                il->toward_last = toward;
                break;
            }
        }
        return 0;
    case IL_ARMED:
        q = (int)il->stop;
        ++il->n;
        pen = q == 0 ? onset[0] - phi_meas : phi_meas - onset[1];
        toward = q == 0 ? -x[TVM_W] : x[TVM_W];
        if (toward > TV_R(0.0)) {
            /* the push of the compression phase only (the estimate still moving into the stop):
             * the energy balance is the compression's, and the back-EMF brakes the plate while it
             * goes in, then pushes it out while it rebounds; averaged over both, that braking
             * cancelled, k_obs came out stiffer than the unit (README "Impact learning") */
            il->push_sum += push_into(model, q, x);
            il->push_n += TV_R(1.0);
        }
        il->dw_sum += q_away(il->stop, x[TVM_W] - w_prior);
        if (pen > TV_R(0.0) && pen > il->p_max) {
            il->pen_before = il->pen_last; /* a new deepest sample: its neighbours start over */
            il->have_after = 0u;
        } else if (!il->have_after && il->p_max > TV_R(0.0)) {
            il->pen_after = pen;
            il->have_after = 1u;
        }
        il->pen_last = pen;
        if (pen > TV_R(0.0)) {
            ++il->n_contact;
            il->p_max = pen > il->p_max ? pen : il->p_max;
        }
        if (toward < TV_R(0.0) && !(pen > TV_R(0.0))) {
            /* moving away, outside: the impact is over, if there was one (a contact seen, or a
             * reversal within this sample of an estimate still moving in at half the impact speed
             * or more: no drive does that; it may come one sample after the arming one or two) */
            if (il->n_contact == 0u && !(il->toward_last >= TV_R(0.5) * il->v_in)) {
                abandon(il);
                return 0;
            }
            il->phase = IL_AFTER;
            il->n = 0u;
            il->w_end = q_away(il->stop, x[TVM_W]);
            il->w_prior_end = q_away(il->stop, w_prior);
            il->phi_after[0] = q_away(il->stop, phi_meas);
            return 0;
        }
        il->toward_last = toward;
        if (il->n >= il->cfg.contact_max || (il->n_contact == 0u && il->n > 3u)) {
            abandon(il); /* rests against the stop, or never reached it */
        }
        return 0;
    case IL_AFTER:
    default:
        il->dw_sum += q_away(il->stop, x[TVM_W] - w_prior);
        ++il->n;
        if (il->n < (uint16_t)IL_FIT_N) {
            il->phi_after[il->n] = q_away(il->stop, phi_meas);
        }
        if (il->n >= il->cfg.settle) {
            return learn(il, model);
        }
        return 0;
    }
}
