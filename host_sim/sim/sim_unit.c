/**
 * @file sim_unit.c
 * @brief ECU configuration for a simulated unit (see sim_unit.h).
 */
#include "sim_unit.h"

#include <math.h>
#include <stddef.h>

#include "tv_status.h"

void sim_model_from_plant(const plant_config_t *plant, tvm_params_t *p)
{
    tvm_params_default(p);
    p->R_ohm = (tv_real_t)plant->R_ohm;
    p->L_H = (tv_real_t)plant->L_H;
    p->Ke_V_s_rad = (tv_real_t)plant->Ke_V_s_rad;
    p->Kt_Nm_A = (tv_real_t)plant->Kt_Nm_A;
    p->J_kg_m2 = (tv_real_t)plant->J_kg_m2;
    p->n_gear = (tv_real_t)plant->n_gear;
    p->Mc_Nm = (tv_real_t)plant->Mc_Nm;
    p->Ms_Nm = (tv_real_t)plant->Ms_Nm;
    p->ws_rad_s = (tv_real_t)plant->ws_rad_s;
    p->Kv_Nm_s_rad = (tv_real_t)plant->Kv_Nm_s_rad;
    p->M0_Nm = (tv_real_t)plant->M0_Nm;
    p->c_Nm_rad = (tv_real_t)plant->c_Nm_rad;
    p->phi_closed_rad = (tv_real_t)plant->phi_closed_rad;
    p->phi_open_rad = (tv_real_t)plant->phi_open_rad;
}

void sim_calib_from_plant(const plant_config_t *plant, app_calib_t *c)
{
    const double full = ldexp(1.0, plant->adc_bits);
    const double lsb_V = plant->adc_ref_V / full;
    const double travel = plant->tps_ref_open_rad - plant->tps_ref_closed_rad;
    const double x0 = -plant->tps_ref_closed_rad / travel; /* track input at phi = 0 */
    const double track_V_per_frac = plant->tps_divider_gain * plant->tps_supply_V / lsb_V; /* counts per supply fraction */
    c->adc_max_counts = (uint16_t)(full - 1.0);
    c->current_offset_counts = (tv_real_t)(plant->current_offset_V / lsb_V);
    c->current_A_per_count = (tv_real_t)(lsb_V / plant->current_gain_V_A);
    c->tps1_counts_at_zero = (tv_real_t)(track_V_per_frac * (plant->tps_offset_frac + plant->tps_span_frac * x0));
    c->tps1_rad_per_count = (tv_real_t)(travel / (track_V_per_frac * plant->tps_span_frac));
    c->tps2_counts_at_zero =
        (tv_real_t)(track_V_per_frac * (1.0 - plant->tps_offset_frac - plant->tps_span_frac * x0));
    c->tps2_rad_per_count = -c->tps1_rad_per_count;
    c->supply_V_per_count = (tv_real_t)(lsb_V / plant->supply_divider_gain);
}

int sim_app_config_for_unit(plant_class_t cls, const plant_config_t *unit, app_config_t *cfg)
{
    plant_config_t nominal;
    double a;
    int rc;
    if (unit == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    rc = plant_class_nominal(cls, &nominal);
    if (rc != TV_OK) {
        return rc;
    }
    app_config_default(cfg);
    sim_model_from_plant(&nominal, &cfg->model);
    rc = ekf_q_from_spectral(&cfg->model, cfg->ekf.qu_V2_s, cfg->ekf.qT_Nm2_s, cfg->ekf.Q);
    if (rc != TV_OK) {
        return rc;
    }
    sim_calib_from_plant(unit, &cfg->calib);
    a = (double)cfg->calib.current_A_per_count;
    cfg->ekf.r[EKF_CH_CURRENT] = (tv_real_t)(nominal.current_noise_A * nominal.current_noise_A + a * a / 12.0);
    a = (double)cfg->calib.tps1_rad_per_count;
    cfg->ekf.r[EKF_CH_ANGLE] = (tv_real_t)(nominal.angle_noise_rad * nominal.angle_noise_rad + a * a / 12.0);
    return TV_OK;
}

int sim_apply_stop_learning(const sim_result_t *r, app_config_t *cfg)
{
    if (r == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    if (r->stop_learn_phase != (int)SL_DONE) {
        return TV_ERR_CONFIG;
    }
    cfg->model.phi_closed_rad = (tv_real_t)r->stop_learn_onset_closed_rad;
    cfg->model.phi_open_rad = (tv_real_t)r->stop_learn_onset_open_rad;
    cfg->stop_track.envelope = 0u; /* learned stops: the envelope of unlearned ones is off */
    cfg->model.k_stop_Nm_rad = (tv_real_t)r->stop_learn_k;
    cfg->model.stop_exponent = (tv_real_t)r->stop_learn_exponent;
    cfg->model.d_stop_Nm_s_rad = cfg->stop_learn.lambda_per_k_s_rad * (tv_real_t)r->stop_learn_k;
    return TV_OK;
}
