/**
 * @file sim_run.c
 * @brief One simulation run: the application against the plant, comparison estimators, metrics.
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_internal.h"

#include "app_tick.h"
#include "diag_csv.h"
#include "paper_filter.h"
#include "sim_hal.h"
#include "tv_status.h"

/* ------------------------------------------------------------------------------------------ */
/* One run                                                                                     */
/* ------------------------------------------------------------------------------------------ */

static void sim_result_clear(sim_result_t *res)
{
    int e;
    int a;
    memset(res, 0, sizeof *res);
    for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
        for (a = 0; a < TVM_NX; ++a) {
            res->rmse[e][a] = SIM_NAN;
        }
    }
    for (a = 0; a < TVM_NX; ++a) {
        res->meas_bias[a] = SIM_NAN;
    }
    res->nees_avg = res->nees_lo = res->nees_hi = SIM_NAN;
    res->nis_avg = res->nis_lo = res->nis_hi = res->nis_dof_avg = SIM_NAN;
    res->first_fault_t_s = SIM_NAN;
    res->nees_window_max = SIM_NAN;
    res->stop_learn_closed_rad = res->stop_learn_open_rad = SIM_NAN;
    res->stop_learn_onset_closed_rad = res->stop_learn_onset_open_rad = res->stop_learn_k = res->stop_learn_exponent = SIM_NAN;
    res->stop_contact_speed_max = SIM_NAN;
    res->friction_check_max = SIM_NAN;
    res->friction_fast_max = SIM_NAN;
    for (e = 0; e < (int)DIAG_DTC_COUNT; ++e) {
        res->dtc_confirm_t_s[e] = SIM_NAN;
        res->dtc_pending_t_s[e] = SIM_NAN;
    }
    sim_tracking_init(&res->tracking);
}

int sim_check_options(const sim_options_t *opt)
{
    if ((unsigned)opt->scenario >= (unsigned)SIM_SCN_COUNT || opt->drop_tick_every == 1u) {
        return TV_ERR_RANGE;
    }
    if (!sim_finite(opt->duration_s) || !sim_finite(opt->r_current_A2) || !sim_finite(opt->r_angle_rad2) ||
        !sim_finite(opt->r_velocity_rad2_s2) || (opt->q_override && (!sim_finite(opt->qu_V2_s) || !sim_finite(opt->qT_Nm2_s)))) {
        return TV_ERR_NONFINITE;
    }
    if (opt->duration_s < 0.0 || opt->duration_s > SIM_DURATION_MAX_S || opt->r_current_A2 < 0.0 ||
        opt->r_angle_rad2 < 0.0 || opt->r_velocity_rad2_s2 < 0.0 ||
        (opt->q_override && (opt->qu_V2_s < 0.0 || opt->qT_Nm2_s < 0.0))) {
        return TV_ERR_RANGE;
    }
    if (opt->setup != EKF_SETUP_CURRENT_ANGLE && opt->setup != EKF_SETUP_PAPER_3MEAS) {
        return TV_ERR_RANGE;
    }
    if (!sim_finite(opt->warmup_s)) {
        return TV_ERR_NONFINITE;
    }
    if (opt->warmup_s < 0.0 || opt->warmup_s > SIM_WARMUP_MAX_S ||
        (opt->warmup_s > 0.0 && !sim_scenario_takes_warmup(opt->scenario))) {
        return TV_ERR_RANGE;
    }
    return TV_OK;
}

/* Application configuration of a run: base, scenario control, overrides. */
static int sim_app_config(const sim_options_t *opt, app_config_t *cfg)
{
    if (opt->app != NULL) {
        *cfg = *opt->app;
    } else {
        app_config_default(cfg);
    }
    sim_scenario_control0(opt->scenario, &cfg->control);
    cfg->ekf.setup = opt->setup;
    if (opt->q_override) {
        const int rc = ekf_q_from_spectral(&cfg->model, (tv_real_t)opt->qu_V2_s, (tv_real_t)opt->qT_Nm2_s, cfg->ekf.Q);
        cfg->ekf.qu_V2_s = (tv_real_t)opt->qu_V2_s;
        cfg->ekf.qT_Nm2_s = (tv_real_t)opt->qT_Nm2_s;
        if (rc != TV_OK) {
            return rc;
        }
    }
    if (opt->r_current_A2 > 0.0) {
        cfg->ekf.r[EKF_CH_CURRENT] = (tv_real_t)opt->r_current_A2;
    }
    if (opt->r_angle_rad2 > 0.0) {
        cfg->ekf.r[EKF_CH_ANGLE] = (tv_real_t)opt->r_angle_rad2;
    }
    if (opt->r_velocity_rad2_s2 > 0.0) {
        cfg->ekf.r[EKF_CH_VELOCITY] = (tv_real_t)opt->r_velocity_rad2_s2;
    }
    return TV_OK;
}

/* Everything a run carries besides the application. */
typedef struct {
    ekf_t paper_setup;
    paper_filter_t printed;
    paper_filter_t eq12;
    paper_filter_t eq12x;
    double sse[SIM_EST_COUNT][TVM_NX];
    double bias_sum[TVM_NX];
    double nees_sum;
    double nis_sum;
    double nis_dof_sum;
    double nis_ch_sum[EKF_NCH];
    uint32_t nis_ch_n[EKF_NCH];
    double nees_ring[SIM_NEES_WINDOW]; /**< last scored NEES values (window average) */
    double nees_ring_sum;
    uint32_t nees_ring_n;
} sim_side_t;

/* Every fault of the list at its full size must be one the plant accepts (a supply sag below
 * the unit's supply, ...): tried once at the start, then the healthy plant is restored. */
static int sim_faults_check(const plant_fault_list_t *list, const plant_config_t *pcfg)
{
    plant_faults_t f;
    plant_fault_list_t full;
    unsigned k;
    int rc;
    if (list == NULL || list->n == 0u) {
        return TV_OK;
    }
    if (list->n > PLANT_FAULT_LIST_MAX) {
        return TV_ERR_RANGE;
    }
    full = *list;
    for (k = 0; k < full.n; ++k) {
        full.spec[k].t_s = 0.0;
        full.spec[k].ramp_s = 0.0;
    }
    (void)plant_fault_at(&full, 0.0, pcfg->tps_supply_V, &f);
    rc = sim_hal_set_faults(&f);
    plant_faults_none(&f);
    (void)sim_hal_set_faults(&f);
    return rc == TV_OK ? TV_OK : TV_ERR_CONFIG;
}

/* Field by field: the faults in force did not change. */
static int sim_faults_equal(const plant_faults_t *a, const plant_faults_t *b)
{
    int ch;
    for (ch = 0; ch < 2; ++ch) {
        if (a->tps_offset_V[ch] != b->tps_offset_V[ch] || a->tps_gain_err[ch] != b->tps_gain_err[ch] ||
            a->tps_stuck[ch] != b->tps_stuck[ch] || a->tps_dropout_prob[ch] != b->tps_dropout_prob[ch]) {
            return 0;
        }
    }
    return a->friction_factor == b->friction_factor && a->jam_Nm == b->jam_Nm && a->spring_factor == b->spring_factor &&
           a->resistance_factor == b->resistance_factor && a->short_fraction == b->short_fraction &&
           a->winding_open == b->winding_open && a->bridge_lost == b->bridge_lost && a->supply_drop_V == b->supply_drop_V &&
           a->current_offset_A == b->current_offset_A && a->current_gain_err == b->current_gain_err;
}

/* The faults in force at t_s into the plant (only when they change). */
static int sim_faults_apply(const plant_fault_list_t *list, const plant_config_t *pcfg, double t_s)
{
    static plant_faults_t s_last;
    static int s_have_last;
    plant_faults_t f;
    int rc;
    if (list == NULL || list->n == 0u) {
        s_have_last = 0;
        return TV_OK;
    }
    (void)plant_fault_at(list, t_s, pcfg->tps_supply_V, &f);
    if (t_s > 0.0 && s_have_last && sim_faults_equal(&f, &s_last)) {
        return TV_OK;
    }
    rc = sim_hal_set_faults(&f);
    if (rc != TV_OK) {
        return TV_ERR_CONFIG;
    }
    s_last = f;
    s_have_last = 1;
    return TV_OK;
}

static int sim_ekf_row_is_used(const ekf_innov_t *in, int ch)
{
    return in->used[ch] != 0u;
}

int sim_run(const sim_options_t *opt, sim_result_t *res)
{
    static app_t s_app; /* large; one run at a time (the HAL is static too) */
    static sim_side_t s_side;
    app_t *app = &s_app;
    sim_side_t *side = &s_side;
    app_config_t acfg;
    plant_config_t pcfg;
    ekf_config_t paper_cfg;
    paper_filter_config_t pfc;
    double duration_s;
    uint32_t n_ticks;
    uint32_t k;
    int rc;
    app_control_t scenario_control;
    int scenario_started = 0;

    if (opt == NULL || res == NULL) {
        if (res != NULL) {
            sim_result_clear(res);
        }
        return TV_ERR_NULL;
    }
    sim_result_clear(res);
    rc = sim_check_options(opt);
    if (rc != TV_OK) {
        return rc;
    }
    duration_s = opt->duration_s > 0.0 ? opt->duration_s : sim_scenario_duration_s(opt->scenario);
    duration_s += opt->warmup_s;
    n_ticks = (uint32_t)floor(duration_s / SIM_TICK_S + 0.5);
    res->scenario = opt->scenario;
    res->seed = opt->seed;
    res->duration_s = (double)n_ticks * SIM_TICK_S;

    /* plant and HAL */
    if (opt->plant != NULL) {
        pcfg = *opt->plant;
    } else {
        plant_config_default(&pcfg);
    }
    if (opt->pwm_ripple) {
        pcfg.pwm_ripple = 1;
    }
    if (!(opt->winding_temp_C >= SIM_WINDING_TEMP_MIN_C && opt->winding_temp_C <= SIM_WINDING_TEMP_MAX_C)) {
        return TV_ERR_RANGE;
    }
    pcfg.R_ohm *= 1.0 + APP_COPPER_ALPHA_PER_K * (opt->winding_temp_C - APP_R_REF_TEMP_C);
    rc = sim_hal_configure(&pcfg, opt->seed);
    if (rc != TV_OK) {
        return rc;
    }
    if (opt->scenario == SIM_SCN_STUCK_RELEASE) {
        plant_state_t st;
        st.current_A = 0.0;
        st.velocity_rad_s = 0.0;
        st.angle_rad = SIM_STUCK_ANGLE_RAD;
        rc = sim_hal_set_state(&st);
        if (rc != TV_OK) {
            return rc;
        }
    }
    rc = hal_init();
    if (rc != TV_OK) {
        return rc;
    }
    rc = sim_faults_check(opt->faults, &pcfg);
    if (rc != TV_OK) {
        return rc;
    }

    /* the application and the comparison estimators */
    rc = sim_app_config(opt, &acfg);
    if (rc != TV_OK) {
        return rc;
    }
    scenario_control = acfg.control;
    if (opt->warmup_s > 0.0) {
        /* the warm-up first; the scenario's own control at its start (below) */
        acfg.control.mode = APP_MODE_SINE;
        acfg.control.amplitude_V = (tv_real_t)SIM_WARMUP_AMPLITUDE_V;
        acfg.control.freq_Hz = (tv_real_t)SIM_WARMUP_FREQ_HZ;
    }
    rc = app_init(app, &acfg);
    if (rc != TV_OK) {
        return rc;
    }
    if (opt->temp_reading) {
        rc = app_set_winding_temp(app, 1, (tv_real_t)opt->temp_reading_C);
        if (rc != TV_OK) {
            return rc;
        }
    }
    memset(side, 0, sizeof *side);
    ekf_config_paper(&paper_cfg);
    rc = ekf_init(&side->paper_setup, &acfg.model, &paper_cfg);
    if (rc != TV_OK) {
        return rc;
    }
    paper_filter_config_default(&pfc);
    rc = paper_filter_init(&side->printed, &pfc);
    if (rc == TV_OK) {
        pfc.predict = PAPER_PREDICT_EQ12;
        rc = paper_filter_init(&side->eq12, &pfc);
    }
    if (rc == TV_OK) {
        pfc.jacobian = PAPER_JACOBIAN_EQ12_EXACT;
        rc = paper_filter_init(&side->eq12x, &pfc);
    }
    if (rc != TV_OK) {
        return rc;
    }
    if (opt->csv != NULL) {
        rc = sim_csv_header(opt->csv);
        if (rc != TV_OK) {
            return rc;
        }
    }
    if (opt->events != NULL) {
        rc = diag_csv_header(opt->events);
        if (rc != TV_OK) {
            return rc;
        }
    }

    for (k = 0; k < n_ticks; ++k) {
        const double t_s = (double)k * SIM_TICK_S;
        /* the scenario's own time (after the warm-up) */
        const double tau_s = t_s - opt->warmup_s;
        const int scored = tau_s >= SIM_TRANSIENT_S - 1e-9;
        const uint32_t steps_before = app->n_steps;
        const double u_prev_V = (double)app->u_applied_V;
        app_output_t out;
        plant_state_t truth;
        sim_row_t row;
        double tr[TVM_NX];
        double est[SIM_EST_COUNT][TVM_NX];
        int a;

        if (tau_s < -1e-9) {
            rc = TV_OK; /* warming up */
        } else if (opt->warmup_s > 0.0 && !scenario_started) {
            scenario_started = 1;
            rc = app_set_control(app, &scenario_control);
            if (rc == TV_OK) {
                rc = sim_scenario_update(opt->scenario, app, tau_s);
            }
        } else {
            rc = sim_scenario_update(opt->scenario, app, tau_s);
        }
        if (rc == TV_OK) {
            rc = sim_faults_apply(opt->faults, &pcfg, t_s);
        }
        if (rc != TV_OK) {
            return rc;
        }
        if (opt->drop_tick_every > 1u && (k + 1u) % opt->drop_tick_every == 0u) {
            /* a missing sample: the application does not run this period */
            rc = sim_hal_advance(SIM_TICK_S);
            if (rc != TV_OK) {
                return TV_ERR_NUMERIC;
            }
            continue;
        }
        memset(&out, 0, sizeof out);
        if (app_tick(app, &out) != TV_OK) {
            ++res->hal_errors;
        }
        if (app->n_steps == steps_before) {
            /* no sample this period (HAL read failed): the application did not step */
            rc = sim_hal_advance(SIM_TICK_S);
            if (rc != TV_OK) {
                return TV_ERR_NUMERIC;
            }
            continue;
        }
        ++res->n_ticks;
        res->fit_base_state = out.fit_base_state; /* the last step's (TV_HEALTH_5) */
        res->fit_base_windows = out.fit_base_windows;
        (void)sim_hal_truth(&truth);
        tr[TVM_I] = truth.current_A;
        tr[TVM_W] = truth.velocity_rad_s;
        tr[TVM_PHI] = truth.angle_rad;

        /* comparison estimators on the application's inputs */
        {
            const uint32_t n_pred = out.missing_samples + 1u;
            const int corrected = out.ekf_status == TV_OK && out.innov.n_used > 0u;
            double z[EKF_NCH];
            uint32_t p;
            int prc = TV_OK;
            for (a = 0; a < EKF_NCH; ++a) {
                z[a] = (double)out.z[a];
            }
            for (p = 0; p < n_pred; ++p) {
                if (prc == TV_OK) {
                    prc = ekf_predict(&side->paper_setup, (tv_real_t)u_prev_V);
                }
                (void)paper_filter_predict(&side->printed, u_prev_V);
                (void)paper_filter_predict(&side->eq12, u_prev_V);
                (void)paper_filter_predict(&side->eq12x, u_prev_V);
            }
            if (prc == TV_OK && corrected) {
                ekf_meas_t m;
                for (a = 0; a < EKF_NCH; ++a) {
                    m.z[a] = out.z[a];
                }
                prc = ekf_correct(&side->paper_setup, &m, NULL);
            }
            if (prc != TV_OK) {
                ++res->paper_setup_rejections;
            }
            if (corrected) {
                double innov_dummy[PAPER_NX];
                (void)paper_filter_correct(&side->printed, z, innov_dummy);
                (void)paper_filter_correct(&side->eq12, z, innov_dummy);
                (void)paper_filter_correct(&side->eq12x, z, innov_dummy);
            }
        }

        /* the row */
        memset(&row, 0, sizeof row);
        row.t_s = t_s;
        for (a = 0; a < TVM_NX; ++a) {
            row.truth[a] = tr[a];
            row.x[a] = (double)out.x[a];
            row.sigma[a] = (double)out.sigma[a];
            row.x_paper[a] = (double)side->paper_setup.x[a];
            row.sigma_paper[a] = sqrt((double)side->paper_setup.P[a][a]);
            row.x_printed[a] = side->printed.x[a];
            row.x_eq12[a] = side->eq12.x[a];
            row.x_eq12x[a] = side->eq12x.x[a];
        }
        {
            plant_adc_t adc;
            if (sim_hal_last_adc(&adc) == TV_OK) {
                row.adc[0] = adc.current_counts;
                row.adc[1] = adc.tps1_counts;
                row.adc[2] = adc.tps2_counts;
                row.adc[3] = adc.supply_counts;
            }
        }
        (void)sim_hal_last_adc_time_us(&row.t_us);
        {
            plant_config_t pcf;
            row.supply_V = sim_hal_config_in_force(&pcf) == TV_OK ? pcf.supply_V : (double)NAN;
        }
        {
            int drv = 0;
            row.driver_fault = hal_driver_fault(&drv) == TV_OK && drv ? 1u : 0u;
        }
        row.duty_f = out.duty;
        row.u_applied_V = (double)app->u_applied_V;
        row.duty = (double)out.duty;
        row.bridge_enable = out.bridge_enable;
        row.r_est_ohm = (double)out.r_est_ohm;
        row.target_rad = app->cfg.control.mode == APP_MODE_POSITION ? (double)app->cfg.control.target_rad : SIM_NAN;
        for (a = 0; a < EKF_NCH; ++a) {
            row.z[a] = (double)out.z[a];
            if (sim_ekf_row_is_used(&out.innov, a)) {
                row.innov[a] = (double)out.innov.innov[a];
                row.innov_sigma[a] = sqrt((double)out.innov.innov_var[a]);
            }
        }
        row.nis_dof = out.innov.n_used;
        row.nis = out.innov.n_used > 0u ? (double)out.innov.nis_total : SIM_NAN;
        {
            double P[TVM_NX][TVM_NX];
            tv_real_t Pf[TVM_NX][TVM_NX];
            double err[TVM_NX];
            int b;
            ekf_covariance(&app->ekf, Pf);
            for (a = 0; a < TVM_NX; ++a) {
                err[a] = row.x[a] - tr[a];
                for (b = 0; b < TVM_NX; ++b) {
                    P[a][b] = (double)Pf[a][b];
                }
            }
            row.nees = sim_mahalanobis3(P, err);
        }
        row.mode = (int)app->cfg.control.mode;
        row.faults = out.faults;
        row.dtc_confirmed = out.dtc_confirmed;
        {
            /* the diagnostic events of this step (the application's queue, drained every tick) */
            diag_event_t ev;
            while (diag_event_pop(&app->diag, &ev)) {
                double *first = ev.kind == DIAG_EV_CONFIRMED ? &res->dtc_confirm_t_s[ev.dtc]
                                : ev.kind == DIAG_EV_PENDING ? &res->dtc_pending_t_s[ev.dtc]
                                                             : NULL;
                ++res->dtc_events;
                if (first != NULL && !sim_finite(*first)) {
                    *first = t_s;
                }
                if (opt->events != NULL) {
                    rc = diag_csv_event(opt->events, &ev);
                    if (rc != TV_OK) {
                        return rc;
                    }
                }
            }
        }
        row.ekf_status = out.ekf_status;
        row.missing_samples = out.missing_samples;

        /* counters and metrics */
        if (out.faults != 0u) {
            ++res->fault_ticks;
            if (!sim_finite(res->first_fault_t_s)) {
                res->first_fault_t_s = t_s;
            }
        }
        if (out.ekf_status != TV_OK) {
            ++res->ekf_rejections;
        }
        if (out.consistency != 0u) {
            ++res->consistency_flag_ticks;
        }
        if (out.friction_rel_sigma > TV_R(0.0) && out.friction_rel_sigma <= app->cfg.diag.friction_sigma_max &&
            !(res->friction_check_max >= (double)out.friction_rel)) {
            res->friction_check_max = (double)out.friction_rel;
        }
        if (app->ddet.friction_fast > TV_R(0.0) && !(res->friction_fast_max >= (double)app->ddet.friction_fast)) {
            res->friction_fast_max = (double)app->ddet.friction_fast;
        }
        if (sl_running(app_stop_learn(app)) || row.mode == (int)APP_MODE_STOP_LEARN) {
            res->stop_learn_s += SIM_TICK_S;
            /* speed INTO a stop (moving away from it, released by the routine, does not count) */
            const double v = tr[TVM_PHI] <= pcfg.phi_closed_rad + SIM_CONTACT_NEAR_RAD   ? -tr[TVM_W]
                             : tr[TVM_PHI] >= pcfg.phi_open_rad - SIM_CONTACT_NEAR_RAD ? tr[TVM_W]
                                                                                        : 0.0;
            if (v > 0.0) {
                if (!sim_finite(res->stop_contact_speed_max) || v > res->stop_contact_speed_max) {
                    res->stop_contact_speed_max = v;
                }
            }
        }
        res->missing_samples += out.missing_samples;
        if (scored) {
            int e;
            for (a = 0; a < TVM_NX; ++a) {
                est[SIM_EST_APP][a] = row.x[a];
                est[SIM_EST_PAPER_SETUP][a] = row.x_paper[a];
                est[SIM_EST_PAPER_PRINTED][a] = row.x_printed[a];
                est[SIM_EST_PAPER_EQ12][a] = row.x_eq12[a];
                est[SIM_EST_PAPER_EQ12_EXACT][a] = row.x_eq12x[a];
                est[SIM_EST_MEASURED][a] = row.z[a]; /* EKF_CH_* equal TVM_* for (i, w, phi) */
            }
            for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
                for (a = 0; a < TVM_NX; ++a) {
                    const double d = est[e][a] - tr[a];
                    side->sse[e][a] += d * d;
                }
            }
            for (a = 0; a < TVM_NX; ++a) {
                side->bias_sum[a] += row.z[a] - tr[a];
            }
            ++res->n_scored;
            if (sim_finite(row.nees)) {
                const uint32_t slot = side->nees_ring_n % SIM_NEES_WINDOW;
                side->nees_sum += row.nees;
                ++res->nees_n;
                if (side->nees_ring_n >= SIM_NEES_WINDOW) {
                    side->nees_ring_sum -= side->nees_ring[slot];
                }
                side->nees_ring[slot] = row.nees;
                side->nees_ring_sum += row.nees;
                ++side->nees_ring_n;
                if (side->nees_ring_n >= SIM_NEES_WINDOW) {
                    const double w = side->nees_ring_sum / (double)SIM_NEES_WINDOW;
                    if (!sim_finite(res->nees_window_max) || w > res->nees_window_max) {
                        res->nees_window_max = w;
                    }
                }
            }
            if (out.innov.n_used > 0u && sim_finite(row.nis)) {
                side->nis_sum += row.nis;
                side->nis_dof_sum += (double)out.innov.n_used;
                ++res->nis_n;
                for (a = 0; a < EKF_NCH; ++a) {
                    if (sim_ekf_row_is_used(&out.innov, a)) {
                        side->nis_ch_sum[a] += (double)out.innov.nis[a];
                        ++side->nis_ch_n[a];
                    }
                }
            }
        }

        /* the plant integrates the period just commanded */
        rc = sim_hal_advance(SIM_TICK_S);
        if (rc != TV_OK) {
            return TV_ERR_NUMERIC;
        }
        (void)sim_hal_bridge_voltage(&row.u_bridge_V);
        if (opt->csv != NULL) {
            rc = sim_csv_row(opt->csv, &row);
            if (rc != TV_OK) {
                return rc;
            }
        }
        sim_tracking_add(&res->tracking, t_s, row.target_rad, tr[TVM_PHI]);
        if (opt->row_fn != NULL) {
            opt->row_fn(&row, opt->row_user);
        }
    }
    sim_tracking_finish(&res->tracking);

    /* summary */
    if (res->n_scored > 0u) {
        int e;
        int a;
        for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
            for (a = 0; a < TVM_NX; ++a) {
                res->rmse[e][a] = sqrt(side->sse[e][a] / (double)res->n_scored);
            }
        }
        for (a = 0; a < TVM_NX; ++a) {
            res->meas_bias[a] = side->bias_sum[a] / (double)res->n_scored;
        }
    }
    if (res->nees_n > 0u) {
        const double n = (double)res->nees_n;
        res->nees_avg = side->nees_sum / n;
        res->nees_lo = sim_chi2_quantile(SIM_BAND_P_LO, 3.0 * n) / n;
        res->nees_hi = sim_chi2_quantile(SIM_BAND_P_HI, 3.0 * n) / n;
    }
    {
        int ch;
        for (ch = 0; ch < EKF_NCH; ++ch) {
            res->nis_ch_avg[ch] =
                side->nis_ch_n[ch] > 0u ? side->nis_ch_sum[ch] / (double)side->nis_ch_n[ch] : SIM_NAN;
        }
    }
    if (res->nis_n > 0u) {
        const double n = (double)res->nis_n;
        res->nis_avg = side->nis_sum / n;
        res->nis_dof_avg = side->nis_dof_sum / n;
        res->nis_lo = sim_chi2_quantile(SIM_BAND_P_LO, side->nis_dof_sum) / n;
        res->nis_hi = sim_chi2_quantile(SIM_BAND_P_HI, side->nis_dof_sum) / n;
    }
    res->faults = app->faults;
    res->dtc_confirmed = 0u;
    {
        int d;
        for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
            if (diag_confirmed(&app->diag, (diag_dtc_t)d)) {
                res->dtc_confirmed |= 1u << d;
            }
        }
    }
    res->dtc_events_lost = app->diag.events_lost;
    /* the "true" parameters are the plant's in force at the end: with an injected fault's */
    (void)sim_hal_config_in_force(&pcfg);
    {
        tv_real_t dR;
        tv_real_t sR;
        ekf_resistance_error(&app->ekf, &dR, &sR);
        res->r_est_ohm = (double)(app->ekf.model.p.R_ohm + dR);
        res->r_sigma_ohm = (double)sR;
        res->r_true_ohm = pcfg.R_ohm;
        res->r_true_20_ohm = pcfg.R_ohm / (1.0 + APP_COPPER_ALPHA_PER_K * (opt->winding_temp_C - APP_R_REF_TEMP_C));
        res->r_20_ohm = app->winding_temp_known ? res->r_est_ohm * (double)app->r_temp_inv : (double)NAN;
    }
    {
        const vfit_t *vf = &app->vfit;
        res->fit_windows = vf->windows;
        res->r_fit_ohm = vf->valid ? (double)vf->r_ohm : (double)NAN;
        res->r_fit_sigma_ohm = vf->valid ? (double)vf->r_sigma_ohm : (double)NAN;
        res->nke_fit_V_s = vf->valid ? (double)vf->nke_V_s : (double)NAN;
        res->nke_fit_sigma_V_s = vf->valid ? (double)vf->nke_sigma_V_s : (double)NAN;
        res->nke_true_V_s = pcfg.n_gear * pcfg.Ke_V_s_rad;
        res->i_off_fit_A = vf->off_valid ? (double)vf->i_off_A : (double)NAN;
        res->i_off_fit_sigma_A = vf->off_valid ? (double)vf->i_off_sigma_A : (double)NAN;
        res->fit_base_r_ohm = app->fit_base_r_ohm > TV_R(0.0) ? (double)app->fit_base_r_ohm : (double)NAN;
        res->fit_base_nke_V_s = app->fit_base_r_ohm > TV_R(0.0) ? (double)app->fit_base_nke_V_s : (double)NAN;
    }
    {
        tv_real_t f;
        tv_real_t sf;
        ekf_friction_error(&app->ekf, &f, &sf);
        res->friction_rel = 1.0 + (double)f;
        res->friction_rel_sigma = (double)sf;
        res->friction_rel_true = app->ekf.model.p.Mc_Nm > TV_R(0.0) ? pcfg.Mc_Nm / (double)app->ekf.model.p.Mc_Nm : 1.0;
    }
    {
        tv_real_t mp;
        tv_real_t sm;
        ekf_preload_error(&app->ekf, &mp, &sm);
        res->preload_rel = 1.0 + (double)mp;
        res->preload_rel_sigma = (double)sm;
        res->preload_rel_true = app->ekf.model.p.M0_Nm > TV_R(0.0) ? pcfg.M0_Nm / (double)app->ekf.model.p.M0_Nm : 1.0;
    }
    res->stop_onset_rad[0] = (double)app->ekf.model.p.phi_closed_rad;
    res->stop_onset_rad[1] = (double)app->ekf.model.p.phi_open_rad;
    res->stop_track_accepted = app->st.n_accepted;
    res->stop_track_refused = app->st.n_refused;
    res->impact_learned = app->il.n_learned;
    res->impact_k_updates = app->il.n_k;
    res->impact_abandoned = app->il.n_abandoned;
    res->contact_k = (double)app->ekf.model.p.k_stop_Nm_rad;
    res->contact_alpha_s_rad = app->ekf.model.p.k_stop_Nm_rad > TV_R(0.0)
                                   ? (double)(app->ekf.model.p.d_stop_Nm_s_rad / app->ekf.model.p.k_stop_Nm_rad)
                                   : SIM_NAN;
    res->contact_exponent = (double)app->ekf.model.p.stop_exponent;
    res->contact_w_coupling = (double)app->ekf.cfg.contact_w_coupling;
    res->impact_rebound_err_last = app->il.n_learned > 0u ? (double)app->il.rebound_err_last : SIM_NAN;
    res->stop_learn_phase = (int)app->sl.phase;
    res->stop_learn_error = (int)app->sl.error;
    if (app->sl.phase == SL_DONE) {
        res->stop_learn_closed_rad = (double)app->sl.phi_closed_rad;
        res->stop_learn_open_rad = (double)app->sl.phi_open_rad;
        res->stop_learn_onset_closed_rad = (double)app->sl.onset_closed_rad;
        res->stop_learn_onset_open_rad = (double)app->sl.onset_open_rad;
        res->stop_learn_k = (double)app->sl.k_stop;
        res->stop_learn_exponent = (double)app->sl.exponent;
    }
    res->consistency_episodes = app->nism.episodes;
    res->paper_printed_resets = side->printed.n_resets;
    res->paper_eq12_resets = side->eq12.n_resets;
    res->paper_eq12x_resets = side->eq12x.n_resets;
    if (opt->events != NULL && fflush(opt->events) != 0) {
        return TV_ERR_IO;
    }
    if (opt->csv != NULL && fflush(opt->csv) != 0) {
        return TV_ERR_IO;
    }
    return TV_OK;
}
