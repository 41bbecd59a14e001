/**
 * @file sim.c
 * @brief Host simulation core: scenarios, comparison estimators, metrics (see sim.h).
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "app_tick.h"
#include "paper_filter.h"
#include "sim_hal.h"
#include "tv_status.h"

#define SIM_NAN ((double)NAN)

/* ------------------------------------------------------------------------------------------ */
/* Names                                                                                       */
/* ------------------------------------------------------------------------------------------ */

static const char *const s_scn_names[SIM_SCN_COUNT] = {"paper_sine", "closed_steps", "closed_ramp", "chirp",
                                                       "stuck_release"};
static const double s_scn_duration_s[SIM_SCN_COUNT] = {2.0, 2.5, 2.5, 2.0, 2.2};
static const char *const s_est_names[SIM_EST_COUNT] = {"app filter", "paper set-up, our map", "paper as printed",
                                                       "paper, eq.12 predict", "paper, eq.12 + exact Jac.",
                                                       "measured / differentiated"};
static const char *const s_est_ids[SIM_EST_COUNT] = {"app", "paper_setup", "paper_printed", "paper_eq12",
                                                     "paper_eq12_exact", "measured"};

const char *sim_scenario_name(sim_scenario_t s)
{
    return (unsigned)s < (unsigned)SIM_SCN_COUNT ? s_scn_names[s] : "?";
}

int sim_scenario_from_name(const char *name, sim_scenario_t *out)
{
    int k;
    if (name == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    for (k = 0; k < (int)SIM_SCN_COUNT; ++k) {
        if (strcmp(name, s_scn_names[k]) == 0) {
            *out = (sim_scenario_t)k;
            return TV_OK;
        }
    }
    return TV_ERR_RANGE;
}

double sim_scenario_duration_s(sim_scenario_t s)
{
    return (unsigned)s < (unsigned)SIM_SCN_COUNT ? s_scn_duration_s[s] : 0.0;
}

const char *sim_est_name(sim_est_t e)
{
    return (unsigned)e < (unsigned)SIM_EST_COUNT ? s_est_names[e] : "?";
}

const char *sim_est_id(sim_est_t e)
{
    return (unsigned)e < (unsigned)SIM_EST_COUNT ? s_est_ids[e] : "?";
}

void sim_options_default(sim_options_t *opt)
{
    if (opt == NULL) {
        return;
    }
    memset(opt, 0, sizeof *opt);
    opt->scenario = SIM_SCN_PAPER_SINE;
    opt->duration_s = 0.0;
    opt->seed = 1u;
    opt->setup = EKF_SETUP_CURRENT_ANGLE;
    opt->qu_V2_s = (double)EKF_DEFAULT_QU_V2_S;
    opt->qT_Nm2_s = (double)EKF_DEFAULT_QT_NM2_S;
}

/* ------------------------------------------------------------------------------------------ */
/* Statistics                                                                                  */
/* ------------------------------------------------------------------------------------------ */

static int sim_finite(double v)
{
    return v == v && v - v == 0.0;
}

double sim_normal_quantile(double p)
{
    /* P. J. Acklam's rational approximation (relative error 1.15e-9), then one Halley step
     * on erfc for full double accuracy. */
    static const double a[6] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                                1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[5] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                6.680131188771972e+01,  -1.328068155288572e+01};
    static const double c[6] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
    static const double d[4] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                3.754408661907416e+00};
    const double p_low = 0.02425;
    double q;
    double r;
    double x;
    if (!(p > 0.0 && p < 1.0)) {
        return SIM_NAN;
    }
    if (p < p_low) {
        q = sqrt(-2.0 * log(p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    } else if (p <= 1.0 - p_low) {
        q = p - 0.5;
        r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
    } else {
        q = sqrt(-2.0 * log(1.0 - p));
        x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    }
    {
        const double e = 0.5 * erfc(-x / sqrt(2.0)) - p;
        const double u = e * sqrt(2.0 * 3.14159265358979323846) * exp(x * x / 2.0);
        x = x - u / (1.0 + x * u / 2.0);
    }
    return x;
}

double sim_chi2_quantile(double p, double dof)
{
    double z;
    double k;
    double t;
    if (!(p > 0.0 && p < 1.0) || !(dof > 0.0) || !sim_finite(dof)) {
        return SIM_NAN;
    }
    z = sim_normal_quantile(p);
    k = 2.0 / (9.0 * dof);
    t = 1.0 - k + z * sqrt(k);
    return t > 0.0 ? dof * t * t * t : 0.0;
}

/* e^T P^-1 e by Cholesky of the 3x3 P (double); NaN when P is not positive definite. */
static double sim_mahalanobis3(double P[TVM_NX][TVM_NX], const double e[TVM_NX])
{
    double Lc[TVM_NX][TVM_NX];
    double y[TVM_NX] = {0.0, 0.0, 0.0};
    double s = 0.0;
    int i;
    int j;
    int k;
    memset(Lc, 0, sizeof Lc);
    for (i = 0; i < TVM_NX; ++i) {
        for (j = 0; j <= i; ++j) {
            double v = 0.5 * (P[i][j] + P[j][i]);
            for (k = 0; k < j; ++k) {
                v -= Lc[i][k] * Lc[j][k];
            }
            if (i == j) {
                if (!(v > 0.0)) {
                    return SIM_NAN;
                }
                Lc[i][i] = sqrt(v);
            } else {
                Lc[i][j] = v / Lc[j][j];
            }
        }
    }
    for (i = 0; i < TVM_NX; ++i) {
        double v = e[i];
        for (k = 0; k < i; ++k) {
            v -= Lc[i][k] * y[k];
        }
        y[i] = v / Lc[i][i];
        s += y[i] * y[i];
    }
    return s;
}

/* ------------------------------------------------------------------------------------------ */
/* Scenarios                                                                                   */
/* ------------------------------------------------------------------------------------------ */

/* closed_steps: target sequence and dwell. */
static const double s_step_targets_rad[4] = {0.2, 0.8, 0.05, 1.2};
#define SIM_STEP_DWELL_S 0.5
/* closed_ramp: hold, ramp up, ramp down. */
#define SIM_RAMP_LO_RAD 0.1
#define SIM_RAMP_HI_RAD 1.2
#define SIM_RAMP_HOLD_S 0.25
#define SIM_RAMP_TIME_S 1.0
/* stuck_release: initial angle, pulse, ramp. */
#define SIM_STUCK_ANGLE_RAD 0.5
#define SIM_STUCK_PULSE_T_S 0.5
#define SIM_STUCK_PULSE_LEN_S 0.04
#define SIM_STUCK_PULSE_V 4.5
#define SIM_STUCK_RAMP_T_S 1.2
#define SIM_STUCK_RAMP_V_S 5.0

/* Initial control of a scenario (before app_init). */
static void sim_scenario_control0(sim_scenario_t scn, app_control_t *c)
{
    switch (scn) {
    case SIM_SCN_PAPER_SINE:
        c->mode = APP_MODE_SINE;
        c->amplitude_V = TV_R(12.0);
        c->freq_Hz = TV_R(5.0);
        break;
    case SIM_SCN_CLOSED_STEPS:
        c->mode = APP_MODE_POSITION;
        c->target_rad = (tv_real_t)s_step_targets_rad[0];
        break;
    case SIM_SCN_CLOSED_RAMP:
        c->mode = APP_MODE_POSITION;
        c->target_rad = (tv_real_t)SIM_RAMP_LO_RAD;
        break;
    case SIM_SCN_CHIRP:
        c->mode = APP_MODE_CHIRP;
        c->amplitude_V = TV_R(12.0);
        c->freq_Hz = TV_R(1.0);
        c->chirp_f1_Hz = TV_R(20.0);
        c->chirp_period_s = TV_R(2.0);
        break;
    case SIM_SCN_STUCK_RELEASE:
    case SIM_SCN_COUNT:
    default:
        c->mode = APP_MODE_OFF;
        break;
    }
}

/* Target angle of the closed-loop scenarios at t [s]. */
static double sim_target_rad(sim_scenario_t scn, double t_s)
{
    if (scn == SIM_SCN_CLOSED_STEPS) {
        const long n = (long)floor(t_s / SIM_STEP_DWELL_S + 1e-9);
        return s_step_targets_rad[n % 4];
    }
    /* closed_ramp */
    if (t_s < SIM_RAMP_HOLD_S) {
        return SIM_RAMP_LO_RAD;
    }
    if (t_s < SIM_RAMP_HOLD_S + SIM_RAMP_TIME_S) {
        return SIM_RAMP_LO_RAD + (SIM_RAMP_HI_RAD - SIM_RAMP_LO_RAD) * (t_s - SIM_RAMP_HOLD_S) / SIM_RAMP_TIME_S;
    }
    if (t_s < SIM_RAMP_HOLD_S + 2.0 * SIM_RAMP_TIME_S) {
        return SIM_RAMP_HI_RAD -
               (SIM_RAMP_HI_RAD - SIM_RAMP_LO_RAD) * (t_s - SIM_RAMP_HOLD_S - SIM_RAMP_TIME_S) / SIM_RAMP_TIME_S;
    }
    return SIM_RAMP_LO_RAD;
}

/*
 * Update the application's control for tick time t [s]. Closed-loop targets move through
 * app_set_target() (keeps the PID integrator); mode changes go through app_set_control().
 */
static int sim_scenario_update(sim_scenario_t scn, app_t *app, double t_s)
{
    switch (scn) {
    case SIM_SCN_CLOSED_STEPS:
    case SIM_SCN_CLOSED_RAMP:
        return app_set_target(app, (tv_real_t)sim_target_rad(scn, t_s));
    case SIM_SCN_STUCK_RELEASE: {
        app_control_t c = app->cfg.control;
        if (t_s >= SIM_STUCK_PULSE_T_S && t_s < SIM_STUCK_PULSE_T_S + SIM_STUCK_PULSE_LEN_S - 1e-9) {
            c.mode = APP_MODE_STEPS; /* freq 0: constant +amplitude */
            c.freq_Hz = TV_R(0.0);
            c.amplitude_V = (tv_real_t)SIM_STUCK_PULSE_V;
        } else if (t_s >= SIM_STUCK_RAMP_T_S - 1e-9) {
            c.mode = APP_MODE_STEPS;
            c.freq_Hz = TV_R(0.0);
            c.amplitude_V = (tv_real_t)(SIM_STUCK_RAMP_V_S * (t_s - SIM_STUCK_RAMP_T_S));
            if (c.amplitude_V < TV_R(0.0)) {
                c.amplitude_V = TV_R(0.0);
            }
        } else {
            c.mode = APP_MODE_OFF;
        }
        if (c.mode != app->cfg.control.mode || c.amplitude_V != app->cfg.control.amplitude_V ||
            c.freq_Hz != app->cfg.control.freq_Hz) {
            return app_set_control(app, &c);
        }
        return TV_OK;
    }
    case SIM_SCN_PAPER_SINE:
    case SIM_SCN_CHIRP:
    case SIM_SCN_COUNT:
    default:
        return TV_OK;
    }
}

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
}

static int sim_check_options(const sim_options_t *opt)
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
} sim_side_t;

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

    /* the application and the comparison estimators */
    rc = sim_app_config(opt, &acfg);
    if (rc != TV_OK) {
        return rc;
    }
    rc = app_init(app, &acfg);
    if (rc != TV_OK) {
        return rc;
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

    for (k = 0; k < n_ticks; ++k) {
        const double t_s = (double)k * SIM_TICK_S;
        const int scored = t_s >= SIM_TRANSIENT_S - 1e-9;
        const uint32_t steps_before = app->n_steps;
        const double u_prev_V = (double)app->u_applied_V;
        app_output_t out;
        plant_state_t truth;
        sim_row_t row;
        double tr[TVM_NX];
        double est[SIM_EST_COUNT][TVM_NX];
        int a;

        rc = sim_scenario_update(opt->scenario, app, t_s);
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
            int drv = 0;
            row.driver_fault = hal_driver_fault(&drv) == TV_OK && drv ? 1u : 0u;
        }
        row.duty_f = out.duty;
        row.u_applied_V = (double)app->u_applied_V;
        row.duty = (double)out.duty;
        row.bridge_enable = out.bridge_enable;
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
            double err[TVM_NX];
            int b;
            for (a = 0; a < TVM_NX; ++a) {
                err[a] = row.x[a] - tr[a];
                for (b = 0; b < TVM_NX; ++b) {
                    P[a][b] = (double)app->ekf.P[a][b];
                }
            }
            row.nees = sim_mahalanobis3(P, err);
        }
        row.mode = (int)app->cfg.control.mode;
        row.faults = out.faults;
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
                side->nees_sum += row.nees;
                ++res->nees_n;
            }
            if (out.innov.n_used > 0u && sim_finite(row.nis)) {
                side->nis_sum += row.nis;
                side->nis_dof_sum += (double)out.innov.n_used;
                ++res->nis_n;
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
        if (opt->row_fn != NULL) {
            opt->row_fn(&row, opt->row_user);
        }
    }

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
    if (res->nis_n > 0u) {
        const double n = (double)res->nis_n;
        res->nis_avg = side->nis_sum / n;
        res->nis_dof_avg = side->nis_dof_sum / n;
        res->nis_lo = sim_chi2_quantile(SIM_BAND_P_LO, side->nis_dof_sum) / n;
        res->nis_hi = sim_chi2_quantile(SIM_BAND_P_HI, side->nis_dof_sum) / n;
    }
    res->faults = app->faults;
    res->paper_printed_resets = side->printed.n_resets;
    res->paper_eq12_resets = side->eq12.n_resets;
    res->paper_eq12x_resets = side->eq12x.n_resets;
    if (opt->csv != NULL && fflush(opt->csv) != 0) {
        return TV_ERR_IO;
    }
    return TV_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* Monte Carlo                                                                                 */
/* ------------------------------------------------------------------------------------------ */

/* Per-tick accumulation across seeds. */
typedef struct {
    double *nees_sum;  /* per tick index */
    uint32_t *nees_cnt;
    uint32_t n_slots;
    double nees_total;
    double nees_n;
    double nis_total;
    double nis_dof_total;
    double nis_n;
} sim_mc_acc_t;

static void sim_mc_row(const sim_row_t *row, void *user)
{
    sim_mc_acc_t *acc = (sim_mc_acc_t *)user;
    const uint32_t idx = (uint32_t)floor(row->t_s / SIM_TICK_S + 0.5);
    if (row->t_s < SIM_TRANSIENT_S - 1e-9 || idx >= acc->n_slots) {
        return;
    }
    if (sim_finite(row->nees)) {
        acc->nees_sum[idx] += row->nees;
        ++acc->nees_cnt[idx];
        acc->nees_total += row->nees;
        acc->nees_n += 1.0;
    }
    if (row->nis_dof > 0 && sim_finite(row->nis)) {
        acc->nis_total += row->nis;
        acc->nis_dof_total += (double)row->nis_dof;
        acc->nis_n += 1.0;
    }
}

int sim_monte_carlo(const sim_options_t *opt, uint32_t n_seeds, sim_progress_fn progress, void *user,
                    sim_mc_result_t *out)
{
    sim_options_t o;
    sim_mc_acc_t acc;
    sim_result_t r;
    double duration_s;
    uint32_t s;
    int e;
    int a;
    int rc = TV_OK;
    if (opt == NULL || out == NULL) {
        return TV_ERR_NULL;
    }
    memset(out, 0, sizeof *out);
    if (n_seeds == 0u || n_seeds > SIM_MC_SEEDS_MAX) {
        return TV_ERR_RANGE;
    }
    rc = sim_check_options(opt);
    if (rc != TV_OK) {
        return rc;
    }
    duration_s = opt->duration_s > 0.0 ? opt->duration_s : sim_scenario_duration_s(opt->scenario);
    memset(&acc, 0, sizeof acc);
    acc.n_slots = (uint32_t)floor(duration_s / SIM_TICK_S + 0.5) + 1u;
    acc.nees_sum = (double *)calloc(acc.n_slots, sizeof *acc.nees_sum);
    acc.nees_cnt = (uint32_t *)calloc(acc.n_slots, sizeof *acc.nees_cnt);
    if (acc.nees_sum == NULL || acc.nees_cnt == NULL) {
        free(acc.nees_sum);
        free(acc.nees_cnt);
        return TV_ERR_IO;
    }
    o = *opt;
    o.csv = NULL;
    o.row_fn = sim_mc_row;
    o.row_user = &acc;
    out->scenario = opt->scenario;
    out->n_seeds = n_seeds;
    out->first_seed = opt->seed;
    for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
        for (a = 0; a < TVM_NX; ++a) {
            out->rmse_max[e][a] = 0.0;
        }
    }
    for (s = 0; s < n_seeds; ++s) {
        o.seed = opt->seed + s;
        rc = sim_run(&o, &r);
        if (rc != TV_OK) {
            break;
        }
        out->duration_s = r.duration_s;
        out->n_ticks_scored = r.n_scored;
        for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
            for (a = 0; a < TVM_NX; ++a) {
                out->rmse_mean[e][a] += r.rmse[e][a] / (double)n_seeds;
                if (!(r.rmse[e][a] <= out->rmse_max[e][a])) {
                    out->rmse_max[e][a] = r.rmse[e][a]; /* NaN propagates */
                }
            }
        }
        if (r.faults != 0u) {
            ++out->runs_with_faults;
        }
        out->ekf_rejections += r.ekf_rejections;
        out->missing_samples += r.missing_samples;
        out->paper_printed_resets += r.paper_printed_resets;
        if (progress != NULL) {
            progress(s + 1u, n_seeds, user);
        }
    }
    if (rc == TV_OK) {
        const double m = (double)n_seeds;
        uint32_t in_band = 0u;
        uint32_t scored = 0u;
        uint32_t k;
        out->band_lo = sim_chi2_quantile(SIM_BAND_P_LO, 3.0 * m) / m;
        out->band_hi = sim_chi2_quantile(SIM_BAND_P_HI, 3.0 * m) / m;
        for (k = 0; k < acc.n_slots; ++k) {
            if ((double)k * SIM_TICK_S < SIM_TRANSIENT_S - 1e-9) {
                continue;
            }
            if (acc.nees_cnt[k] == 0u) {
                continue; /* no run ticked here (beyond the end, or a dropped tick) */
            }
            ++scored;
            if (acc.nees_cnt[k] == n_seeds) {
                const double avg = acc.nees_sum[k] / m;
                if (avg >= out->band_lo && avg <= out->band_hi) {
                    ++in_band;
                }
            }
        }
        out->frac_ticks_in_band = scored > 0u ? (double)in_band / (double)scored : SIM_NAN;
        out->anees = acc.nees_n > 0.0 ? acc.nees_total / acc.nees_n : SIM_NAN;
        out->anees_lo = acc.nees_n > 0.0 ? sim_chi2_quantile(SIM_BAND_P_LO, 3.0 * acc.nees_n) / acc.nees_n : SIM_NAN;
        out->anees_hi = acc.nees_n > 0.0 ? sim_chi2_quantile(SIM_BAND_P_HI, 3.0 * acc.nees_n) / acc.nees_n : SIM_NAN;
        out->anis = acc.nis_n > 0.0 ? acc.nis_total / acc.nis_n : SIM_NAN;
        out->nis_dof_avg = acc.nis_n > 0.0 ? acc.nis_dof_total / acc.nis_n : SIM_NAN;
    }
    free(acc.nees_sum);
    free(acc.nees_cnt);
    return rc;
}

/* ------------------------------------------------------------------------------------------ */
/* Output                                                                                      */
/* ------------------------------------------------------------------------------------------ */

static const char *const s_csv_columns =
    "t_s,i_true_A,w_true_rad_s,phi_true_rad,adc_current,adc_tps1,adc_tps2,adc_supply,u_applied_V,u_bridge_V,"
    "duty,bridge_enable,target_rad,i_meas_A,w_meas_rad_s,phi_meas_rad,i_est_A,w_est_rad_s,phi_est_rad,"
    "i_sigma_A,w_sigma_rad_s,phi_sigma_rad,innov_i_A,innov_w_rad_s,innov_phi_rad,innov_i_sigma_A,"
    "innov_w_sigma_rad_s,innov_phi_sigma_rad,nis,nis_dof,nees,mode,faults,ekf_status,missing_samples,"
    "i_paper_A,w_paper_rad_s,phi_paper_rad,i_paper_sigma_A,w_paper_sigma_rad_s,phi_paper_sigma_rad,"
    "i_printed_A,w_printed_rad_s,phi_printed_rad,i_eq12_A,w_eq12_rad_s,phi_eq12_rad,i_eq12x_A,w_eq12x_rad_s,"
    "phi_eq12x_rad\n";

int sim_csv_header(FILE *f)
{
    if (f == NULL) {
        return TV_ERR_NULL;
    }
    return fputs(s_csv_columns, f) < 0 ? TV_ERR_IO : TV_OK;
}

int sim_csv_row(FILE *f, const sim_row_t *r)
{
    int n;
    if (f == NULL || r == NULL) {
        return TV_ERR_NULL;
    }
    n = fprintf(f,
                "%.9g,%.9g,%.9g,%.9g,%u,%u,%u,%u,%.9g,%.9g,%.9g,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,"
                "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%d,%.9g,%d,%lu,%d,%lu,"
                "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                r->t_s, r->truth[0], r->truth[1], r->truth[2], (unsigned)r->adc[0], (unsigned)r->adc[1],
                (unsigned)r->adc[2], (unsigned)r->adc[3], r->u_applied_V, r->u_bridge_V, r->duty, r->bridge_enable,
                r->target_rad, r->z[EKF_CH_CURRENT], r->z[EKF_CH_VELOCITY], r->z[EKF_CH_ANGLE], r->x[0], r->x[1],
                r->x[2], r->sigma[0], r->sigma[1], r->sigma[2], r->innov[EKF_CH_CURRENT], r->innov[EKF_CH_VELOCITY],
                r->innov[EKF_CH_ANGLE], r->innov_sigma[EKF_CH_CURRENT], r->innov_sigma[EKF_CH_VELOCITY],
                r->innov_sigma[EKF_CH_ANGLE], r->nis, r->nis_dof, r->nees, r->mode, (unsigned long)r->faults,
                r->ekf_status, (unsigned long)r->missing_samples, r->x_paper[0], r->x_paper[1], r->x_paper[2],
                r->sigma_paper[0], r->sigma_paper[1], r->sigma_paper[2], r->x_printed[0], r->x_printed[1],
                r->x_printed[2], r->x_eq12[0], r->x_eq12[1], r->x_eq12[2], r->x_eq12x[0], r->x_eq12x[1], r->x_eq12x[2]);
    return n < 0 ? TV_ERR_IO : TV_OK;
}

/* JSON number or null. */
static void sim_jnum(FILE *f, double v)
{
    if (sim_finite(v)) {
        fprintf(f, "%.9g", v);
    } else {
        fputs("null", f);
    }
}

/* rmse: SIM_EST_COUNT x TVM_NX, row-major */
static void sim_print_rmse_rows(FILE *f, const double *rmse)
{
    int e;
    fprintf(f, "  %-28s %13s %17s %13s\n", "estimator", "current [A]", "velocity [rad/s]", "angle [rad]");
    for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
        const double *r = rmse + (size_t)e * TVM_NX;
        fprintf(f, "  %-28s %13.6g %17.6g %13.6g\n", s_est_names[e], r[0], r[1], r[2]);
    }
}

static void sim_json_rmse(FILE *f, const char *key, const double *rmse)
{
    int e;
    fprintf(f, "  \"%s\": {\n", key);
    for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
        fprintf(f, "    \"%s\": {\"label\": \"%s\", \"current_A\": ", s_est_ids[e], s_est_names[e]);
        sim_jnum(f, rmse[(size_t)e * TVM_NX + 0]);
        fputs(", \"velocity_rad_s\": ", f);
        sim_jnum(f, rmse[(size_t)e * TVM_NX + 1]);
        fputs(", \"angle_rad\": ", f);
        sim_jnum(f, rmse[(size_t)e * TVM_NX + 2]);
        fprintf(f, "}%s\n", e + 1 < (int)SIM_EST_COUNT ? "," : "");
    }
    fputs("  },\n", f);
}

int sim_result_print(FILE *f, const sim_result_t *r)
{
    if (f == NULL || r == NULL) {
        return TV_ERR_NULL;
    }
    fprintf(f, "scenario %s, seed %llu, %.3f s simulated, %lu ticks, %lu scored (t >= %.2f s)\n",
            sim_scenario_name(r->scenario), (unsigned long long)r->seed, r->duration_s, (unsigned long)r->n_ticks,
            (unsigned long)r->n_scored, SIM_TRANSIENT_S);
    fputs("RMSE against the plant truth:\n", f);
    sim_print_rmse_rows(f, &r->rmse[0][0]);
    fprintf(f, "  %-28s %13.6g %17.6g %13.6g\n", "measurement bias (mean err)", r->meas_bias[0], r->meas_bias[1],
            r->meas_bias[2]);
    fprintf(f, "app filter consistency:\n");
    fprintf(f, "  NEES average %.4g (3 dof, N = %lu), 95%% band of the average [%.4g, %.4g]%s\n", r->nees_avg,
            (unsigned long)r->nees_n, r->nees_lo, r->nees_hi,
            sim_finite(r->nees_avg) ? (r->nees_avg >= r->nees_lo && r->nees_avg <= r->nees_hi ? "  inside" : "  OUTSIDE")
                                    : "");
    fprintf(f, "  NIS  average %.4g (%.3g dof, N = %lu), 95%% band of the average [%.4g, %.4g]%s\n", r->nis_avg,
            r->nis_dof_avg, (unsigned long)r->nis_n, r->nis_lo, r->nis_hi,
            sim_finite(r->nis_avg) ? (r->nis_avg >= r->nis_lo && r->nis_avg <= r->nis_hi ? "  inside" : "  OUTSIDE")
                                   : "");
    fprintf(f, "events:\n");
    fprintf(f, "  faults latched 0x%02lx (%lu ticks with a fault", (unsigned long)r->faults, (unsigned long)r->fault_ticks);
    if (sim_finite(r->first_fault_t_s)) {
        fprintf(f, ", first at %.3f s", r->first_fault_t_s);
    }
    fprintf(f, "), EKF rejections %lu, missing samples %lu, HAL errors %lu\n", (unsigned long)r->ekf_rejections,
            (unsigned long)r->missing_samples, (unsigned long)r->hal_errors);
    fprintf(f, "  divergence-guard resets: paper as printed %lu, eq.12 predict %lu, eq.12 + exact Jac. %lu; "
               "paper set-up rejections %lu\n",
            (unsigned long)r->paper_printed_resets, (unsigned long)r->paper_eq12_resets,
            (unsigned long)r->paper_eq12x_resets, (unsigned long)r->paper_setup_rejections);
    return ferror(f) ? TV_ERR_IO : TV_OK;
}

int sim_result_json(FILE *f, const sim_result_t *r)
{
    if (f == NULL || r == NULL) {
        return TV_ERR_NULL;
    }
    fprintf(f, "{\n  \"scenario\": \"%s\",\n  \"seed\": %llu,\n  \"duration_s\": %.9g,\n  \"ticks\": %lu,\n",
            sim_scenario_name(r->scenario), (unsigned long long)r->seed, r->duration_s, (unsigned long)r->n_ticks);
    fprintf(f, "  \"transient_s\": %.9g,\n  \"scored_ticks\": %lu,\n", SIM_TRANSIENT_S, (unsigned long)r->n_scored);
    sim_json_rmse(f, "rmse", &r->rmse[0][0]);
    fputs("  \"measurement_bias\": {\"current_A\": ", f);
    sim_jnum(f, r->meas_bias[0]);
    fputs(", \"velocity_rad_s\": ", f);
    sim_jnum(f, r->meas_bias[1]);
    fputs(", \"angle_rad\": ", f);
    sim_jnum(f, r->meas_bias[2]);
    fputs("},\n  \"nees\": {\"average\": ", f);
    sim_jnum(f, r->nees_avg);
    fputs(", \"dof\": 3, \"band95\": [", f);
    sim_jnum(f, r->nees_lo);
    fputs(", ", f);
    sim_jnum(f, r->nees_hi);
    fprintf(f, "], \"n\": %lu},\n  \"nis\": {\"average\": ", (unsigned long)r->nees_n);
    sim_jnum(f, r->nis_avg);
    fputs(", \"dof\": ", f);
    sim_jnum(f, r->nis_dof_avg);
    fputs(", \"band95\": [", f);
    sim_jnum(f, r->nis_lo);
    fputs(", ", f);
    sim_jnum(f, r->nis_hi);
    fprintf(f, "], \"n\": %lu},\n", (unsigned long)r->nis_n);
    fprintf(f, "  \"faults\": %lu,\n  \"fault_ticks\": %lu,\n  \"first_fault_t_s\": ", (unsigned long)r->faults,
            (unsigned long)r->fault_ticks);
    sim_jnum(f, r->first_fault_t_s);
    fprintf(f, ",\n  \"ekf_rejections\": %lu,\n  \"missing_samples\": %lu,\n  \"hal_errors\": %lu,\n",
            (unsigned long)r->ekf_rejections, (unsigned long)r->missing_samples, (unsigned long)r->hal_errors);
    fprintf(f,
            "  \"paper_setup_rejections\": %lu,\n  \"paper_printed_resets\": %lu,\n  \"paper_eq12_resets\": %lu,\n"
            "  \"paper_eq12_exact_resets\": %lu\n}\n",
            (unsigned long)r->paper_setup_rejections, (unsigned long)r->paper_printed_resets,
            (unsigned long)r->paper_eq12_resets, (unsigned long)r->paper_eq12x_resets);
    return ferror(f) ? TV_ERR_IO : TV_OK;
}

int sim_mc_print(FILE *f, const sim_mc_result_t *m)
{
    if (f == NULL || m == NULL) {
        return TV_ERR_NULL;
    }
    fprintf(f, "Monte Carlo: scenario %s, %lu seeds from %llu, %.3f s each, %lu scored ticks per run (t >= %.2f s)\n",
            sim_scenario_name(m->scenario), (unsigned long)m->n_seeds, (unsigned long long)m->first_seed,
            m->duration_s, (unsigned long)m->n_ticks_scored, SIM_TRANSIENT_S);
    fputs("mean RMSE over seeds:\n", f);
    sim_print_rmse_rows(f, &m->rmse_mean[0][0]);
    fputs("largest RMSE over seeds:\n", f);
    sim_print_rmse_rows(f, &m->rmse_max[0][0]);
    fprintf(f, "app filter consistency:\n");
    fprintf(f, "  ANEES %.4g (3 dof); 95%% band of the %lu-run average per tick [%.4g, %.4g]; ticks inside: %.1f %%\n",
            m->anees, (unsigned long)m->n_seeds, m->band_lo, m->band_hi, 100.0 * m->frac_ticks_in_band);
    fprintf(f, "  (band of the grand average if all samples were independent: [%.4g, %.4g])\n", m->anees_lo,
            m->anees_hi);
    fprintf(f, "  ANIS %.4g (%.3g dof)\n", m->anis, m->nis_dof_avg);
    fprintf(f, "events: runs with faults %lu, EKF rejections %lu, missing samples %lu, paper-as-printed resets %lu\n",
            (unsigned long)m->runs_with_faults, (unsigned long)m->ekf_rejections, (unsigned long)m->missing_samples,
            (unsigned long)m->paper_printed_resets);
    return ferror(f) ? TV_ERR_IO : TV_OK;
}

int sim_mc_json(FILE *f, const sim_mc_result_t *m)
{
    if (f == NULL || m == NULL) {
        return TV_ERR_NULL;
    }
    fprintf(f, "{\n  \"scenario\": \"%s\",\n  \"seeds\": %lu,\n  \"first_seed\": %llu,\n  \"duration_s\": %.9g,\n",
            sim_scenario_name(m->scenario), (unsigned long)m->n_seeds, (unsigned long long)m->first_seed, m->duration_s);
    fprintf(f, "  \"transient_s\": %.9g,\n  \"scored_ticks_per_run\": %lu,\n", SIM_TRANSIENT_S,
            (unsigned long)m->n_ticks_scored);
    sim_json_rmse(f, "rmse_mean", &m->rmse_mean[0][0]);
    sim_json_rmse(f, "rmse_max", &m->rmse_max[0][0]);
    fputs("  \"anees\": ", f);
    sim_jnum(f, m->anees);
    fputs(",\n  \"band95_m_run_average\": [", f);
    sim_jnum(f, m->band_lo);
    fputs(", ", f);
    sim_jnum(f, m->band_hi);
    fputs("],\n  \"fraction_ticks_in_band\": ", f);
    sim_jnum(f, m->frac_ticks_in_band);
    fputs(",\n  \"band95_grand_average\": [", f);
    sim_jnum(f, m->anees_lo);
    fputs(", ", f);
    sim_jnum(f, m->anees_hi);
    fputs("],\n  \"anis\": ", f);
    sim_jnum(f, m->anis);
    fputs(",\n  \"nis_dof\": ", f);
    sim_jnum(f, m->nis_dof_avg);
    fprintf(f, ",\n  \"runs_with_faults\": %lu,\n  \"ekf_rejections\": %lu,\n  \"missing_samples\": %lu,\n",
            (unsigned long)m->runs_with_faults, (unsigned long)m->ekf_rejections, (unsigned long)m->missing_samples);
    fprintf(f, "  \"paper_printed_resets\": %lu\n}\n", (unsigned long)m->paper_printed_resets);
    return ferror(f) ? TV_ERR_IO : TV_OK;
}
