/**
 * @file app.c
 * @brief The 1 kHz application step (see app.h).
 */
#include "app.h"

#include <stddef.h>
#include <string.h>

#include "tv_status.h"

#define APP_PI TV_R(3.14159265358979)

/* Index of each plausibility check's debounce counter. */
enum { CHK_CURRENT = 0, CHK_TPS1, CHK_TPS2, CHK_DISAGREE, CHK_SUPPLY, CHK_N };

static const uint32_t s_check_fault[CHK_N] = {APP_FAULT_CURRENT_RANGE, APP_FAULT_TPS1_RANGE, APP_FAULT_TPS2_RANGE,
                                              APP_FAULT_TPS_DISAGREE, APP_FAULT_SUPPLY_RANGE};

void app_calib_default(app_calib_t *c, const tvm_params_t *p)
{
    /* Front end of host_sim/plant/plant.h: ADC 12 bit, Vref 3.3 V, LSB = Vref / 4096.
     * current: V = 1.65 + 0.1 i -> counts = 4096/3.3 (1.65 + 0.1 i) = 2048 + 124.12 i
     * tracks:  V = 0.66 * 5 (0.1 + 0.8 s), s = (phi - closed)/(open - closed)
     *          -> counts1 = 4096 (0.1 + 0.8 s), counts2 = 4096 (0.9 - 0.8 s)
     * supply:  V/6 -> counts = 4096/3.3 V / 6 */
    const tv_real_t full = TV_R(4096.0);
    const tv_real_t travel = p->phi_open_rad - p->phi_closed_rad;
    const tv_real_t s0 = -p->phi_closed_rad / travel;
    c->adc_max_counts = 4095u;
    c->current_offset_counts = full * TV_R(1.65) / TV_R(3.3);
    c->current_A_per_count = TV_R(3.3) / (full * TV_R(0.1));
    c->tps1_counts_at_zero = full * (TV_R(0.1) + TV_R(0.8) * s0);
    c->tps1_rad_per_count = travel / (full * TV_R(0.8));
    c->tps2_counts_at_zero = full * (TV_R(0.9) - TV_R(0.8) * s0);
    c->tps2_rad_per_count = -travel / (full * TV_R(0.8));
    c->supply_V_per_count = TV_R(6.0) * TV_R(3.3) / full;
}

void app_config_default(app_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    memset(cfg, 0, sizeof *cfg);
    tvm_params_default(&cfg->model);
    ekf_config_default(&cfg->ekf, EKF_SETUP_CURRENT_ANGLE);
    nism_config_default(&cfg->nism);
    vfit_config_default(&cfg->vfit);
    sl_config_default(&cfg->stop_learn);
    st_config_default(&cfg->stop_track);
    il_config_default(&cfg->impact_learn);
    diag_detect_config_default(&cfg->diag);
    app_calib_default(&cfg->calib, &cfg->model);
    /* Tracks span 0.1..0.9 of full scale over the travel; a stop penetration of a few mrad
     * stays far inside 2..98 %. Outside it the track is open or shorted. */
    cfg->limits.current_min_counts = 20u;
    cfg->limits.current_max_counts = 4075u;
    cfg->limits.tps_min_counts = 82u;
    cfg->limits.tps_max_counts = 4013u;
    cfg->limits.tps_disagree_max_rad = TV_R(0.035); /* 2 deg */
    cfg->limits.supply_min_V = TV_R(8.0);
    cfg->limits.supply_max_V = TV_R(18.0);
    cfg->limits.debounce_trip = 5u;
    cfg->limits.max_gap_periods = (uint16_t)APP_MAX_GAP_PERIODS;
    cfg->control.mode = APP_MODE_SINE;
    cfg->control.amplitude_V = TV_R(12.0);
    cfg->control.freq_Hz = TV_R(5.0);
    cfg->control.chirp_f1_Hz = TV_R(20.0);
    cfg->control.chirp_period_s = TV_R(2.0);
    cfg->control.target_rad = TV_R(0.3);
    cfg->control.target_margin_rad = TV_R(0.05);
    cfg->control.kp_V_rad = TV_R(60.0);
    cfg->control.ki_V_rad_s = TV_R(300.0);
    cfg->control.kd_V_s_rad = TV_R(1.2);
    cfg->control.i_limit_V = TV_R(4.0);
    cfg->control.duty_limit = TV_R(0.95);
}

static int finite_all(const tv_real_t *v, size_t n)
{
    size_t k;
    for (k = 0; k < n; ++k) {
        if (!TV_IS_FINITE(v[k])) {
            return 0;
        }
    }
    return 1;
}

static int check_control(const app_control_t *c)
{
    const tv_real_t v[] = {c->amplitude_V, c->freq_Hz,    c->chirp_f1_Hz, c->chirp_period_s, c->target_rad,
                           c->target_margin_rad, c->kp_V_rad, c->ki_V_rad_s, c->kd_V_s_rad, c->i_limit_V,
                           c->duty_limit};
    if (!finite_all(v, sizeof v / sizeof v[0])) {
        return TV_ERR_NONFINITE;
    }
    if ((unsigned)c->mode > (unsigned)APP_MODE_IDENT || c->amplitude_V < TV_R(0.0) ||
        c->freq_Hz < TV_R(0.0) || c->chirp_f1_Hz < TV_R(0.0) || !(c->chirp_period_s > TV_R(0.0)) ||
        c->target_margin_rad < TV_R(0.0) || c->kp_V_rad < TV_R(0.0) || c->ki_V_rad_s < TV_R(0.0) ||
        c->kd_V_s_rad < TV_R(0.0) || c->i_limit_V < TV_R(0.0) || !(c->duty_limit > TV_R(0.0)) ||
        c->duty_limit > TV_R(1.0)) {
        return TV_ERR_CONFIG;
    }
    return TV_OK;
}

static void armature_period(const tvm_t *m, tv_real_t *a_T, tv_real_t *b_T);

int app_init(app_t *app, const app_config_t *cfg)
{
    ekf_t ekf;
    int rc;
    if (app == NULL || cfg == NULL) {
        return TV_ERR_NULL;
    }
    {
        const app_calib_t *c = &cfg->calib;
        const tv_real_t v[] = {c->current_offset_counts, c->current_A_per_count, c->tps1_counts_at_zero,
                               c->tps1_rad_per_count,    c->tps2_counts_at_zero, c->tps2_rad_per_count,
                               c->supply_V_per_count,    cfg->limits.tps_disagree_max_rad,
                               cfg->limits.supply_min_V, cfg->limits.supply_max_V};
        if (!finite_all(v, sizeof v / sizeof v[0])) {
            return TV_ERR_NONFINITE;
        }
        if (c->adc_max_counts == 0u || c->current_A_per_count == TV_R(0.0) || !(c->tps1_rad_per_count > TV_R(0.0)) ||
            !(c->tps2_rad_per_count < TV_R(0.0)) || !(c->supply_V_per_count > TV_R(0.0)) ||
            cfg->limits.current_min_counts >= cfg->limits.current_max_counts ||
            cfg->limits.tps_min_counts >= cfg->limits.tps_max_counts ||
            cfg->limits.current_max_counts > c->adc_max_counts || cfg->limits.tps_max_counts > c->adc_max_counts ||
            !(cfg->limits.tps_disagree_max_rad > TV_R(0.0)) ||
            !(cfg->limits.supply_max_V > cfg->limits.supply_min_V) || cfg->limits.supply_min_V <= TV_R(0.0) ||
            cfg->limits.debounce_trip == 0u || cfg->limits.max_gap_periods == 0u ||
            cfg->limits.max_gap_periods > APP_MAX_GAP_PERIODS) {
            return TV_ERR_CONFIG;
        }
    }
    rc = check_control(&cfg->control);
    if (rc != TV_OK) {
        return rc;
    }
    rc = ekf_init(&ekf, &cfg->model, &cfg->ekf);
    if (rc != TV_OK) {
        return rc;
    }
    {
        sl_t probe;
        if (sl_start(&probe, &cfg->stop_learn, &cfg->model) != TV_OK) {
            return TV_ERR_CONFIG;
        }
    }
    {
        nism_t probe;
        rc = nism_init(&probe, &cfg->nism);
        if (rc != TV_OK) {
            return rc;
        }
    }
    {
        vfit_t probe;
        rc = vfit_init(&probe, &cfg->vfit, cfg->model.L_H, cfg->model.Ts_s);
        if (rc != TV_OK) {
            return rc;
        }
    }
    {
        st_t probe;
        rc = st_reset(&probe, &cfg->stop_track, cfg->model.phi_closed_rad, cfg->model.phi_open_rad);
        if (rc != TV_OK) {
            return rc;
        }
    }
    rc = il_config_check(&cfg->impact_learn);
    if (rc != TV_OK) {
        return rc;
    }
    {
        diag_detect_t probe;
        rc = diag_detect_init(&probe, &cfg->diag);
        if (rc != TV_OK) {
            return rc;
        }
    }
    memset(app, 0, sizeof *app);
    app->cfg = *cfg;
    app->ekf = ekf;
    (void)nism_init(&app->nism, &cfg->nism); /* validated above */
    (void)vfit_init(&app->vfit, &cfg->vfit, cfg->model.L_H, cfg->model.Ts_s); /* likewise */
    (void)st_reset(&app->st, &cfg->stop_track, cfg->model.phi_closed_rad, cfg->model.phi_open_rad); /* likewise */
    (void)il_reset(&app->il, &cfg->impact_learn, &app->ekf.model.p); /* a law without stiffness: never learns */
    app->il.coupling = cfg->ekf.contact_w_coupling; /* as learned before (a parameter file), validated */
    (void)app_set_winding_temp(app, 0, TV_R(0.0)); /* unknown until told */
    diag_init(&app->diag);
    (void)diag_detect_init(&app->ddet, &cfg->diag); /* validated above */
    app->fit_base_r_ohm = cfg->diag.fit_base_r_ohm;
    app->fit_base_nke_V_s = cfg->diag.fit_base_nke_V_s;
    app->fit_base_state = (uint8_t)(app->fit_base_r_ohm > TV_R(0.0)    ? APP_FIT_BASE_IN_FORCE
                                    : cfg->diag.fit_base_windows > 0u ? APP_FIT_BASE_LEARNING
                                                                      : APP_FIT_BASE_NONE);
    {
        /* the bridge check's armature (the model's R and L do not change in service) */
        tv_real_t a_T;
        tv_real_t b_T;
        armature_period(&app->ekf.model, &a_T, &b_T);
        /* refused (not set: no bridge check) only for a degenerate model */
        (void)diag_detect_set_armature(&app->ddet, a_T, b_T);
    }
    /* the current sensor's in-service band scales with the current that holds the preload, the
     * away reading takes the adapted preload's share in N m; refused (the paper's kept) for a
     * model without preload or torque */
    (void)diag_detect_set_preload(&app->ddet, app->ekf.model.p.M0_Nm, app->ekf.model.nKt_Nm_A);
    if (cfg->control.mode == APP_MODE_STOP_LEARN) {
        (void)sl_start(&app->sl, &cfg->stop_learn, &cfg->model); /* validated above */
    }
    return TV_OK;
}

static tv_real_t open_bridge_voltage(const app_t *app);

void app_clear_faults(app_t *app)
{
    if (app == NULL) {
        return;
    }
    if ((app->faults & APP_FAULT_ESTIMATOR) != 0u) {
        /* The filter refused its inputs again and again: its state or covariance went where the
         * map cannot take it (each refused call leaves them as they are), so clearing the flag
         * alone let it fail on. Start it afresh from its configured x0 and P0: the configuration
         * was validated by app_init(), so ekf_init() cannot refuse it here. */
        (void)ekf_init(&app->ekf, &app->cfg.model, &app->cfg.ekf);
        (void)nism_init(&app->nism, &app->cfg.nism); /* the old estimate's innovations are void */
        app->have_last_angle = 0u;
        app->vf_prev_ok = 0u; /* the fresh estimate's velocity does not continue the old one */
        /* the outputs are off while a fault is latched: the period now running is open-bridge,
         * seen from the fresh estimate (the old input was computed from the refused one) */
        app->u_applied_V = open_bridge_voltage(app);
        app->open_after_missed = 0u;
        ++app->n_estimator_resets;
    }
    app->faults = 0u;
    memset(app->debounce, 0, sizeof app->debounce);
    app->ekf_fail_run = 0u;
}

int app_set_control(app_t *app, const app_control_t *ctl)
{
    int rc;
    if (app == NULL || ctl == NULL) {
        return TV_ERR_NULL;
    }
    rc = check_control(ctl);
    if (rc == TV_OK && ctl->mode == APP_MODE_STOP_LEARN && app->cfg.control.mode != APP_MODE_STOP_LEARN) {
        rc = sl_start(&app->sl, &app->cfg.stop_learn, &app->cfg.model);
    }
    if (rc == TV_OK) {
        app->cfg.control = *ctl;
        app->integ_V = TV_R(0.0);
    }
    return rc;
}

const sl_t *app_stop_learn(const app_t *app)
{
    return app == NULL ? NULL : &app->sl;
}

/* The impact learning's contact-inflation coupling to the estimator, and to cfg.ekf (persisted
 * with the parameters) when the estimator takes it. */
static void use_coupling(app_t *app)
{
    if (ekf_set_contact_w_coupling(&app->ekf, app->il.coupling) == TV_OK) {
        app->cfg.ekf.contact_w_coupling = app->il.coupling;
    }
}

/* The stops in use: the estimator's model and the position limits (cfg.model). */
static int use_stops(app_t *app, tv_real_t phi_closed_rad, tv_real_t phi_open_rad)
{
    const int rc = ekf_set_stops(&app->ekf, phi_closed_rad, phi_open_rad);
    if (rc == TV_OK) {
        app->cfg.model.phi_closed_rad = phi_closed_rad;
        app->cfg.model.phi_open_rad = phi_open_rad;
    }
    return rc;
}

int app_set_stops(app_t *app, tv_real_t phi_closed_rad, tv_real_t phi_open_rad)
{
    int rc;
    if (app == NULL) {
        return TV_ERR_NULL;
    }
    rc = use_stops(app, phi_closed_rad, phi_open_rad);
    if (rc == TV_OK) {
        /* the new stops are the tracker's reference (its window is around them); they are
         * learned or stored stops, so the envelope of unlearned ones is off from now on */
        app->cfg.stop_track.envelope = 0u;
        (void)st_reset(&app->st, &app->cfg.stop_track, phi_closed_rad, phi_open_rad);
    }
    return rc;
}

int app_set_target(app_t *app, tv_real_t target_rad)
{
    if (app == NULL) {
        return TV_ERR_NULL;
    }
    if (!TV_IS_FINITE(target_rad)) {
        return TV_ERR_NONFINITE;
    }
    app->cfg.control.target_rad = target_rad;
    return TV_OK;
}

int app_set_winding_temp(app_t *app, int known, tv_real_t temp_C)
{
    if (app == NULL) {
        return TV_ERR_NULL;
    }
    if (!known) {
        app->winding_temp_known = 0u;
        app->winding_temp_C = ((tv_real_t)APP_R_REF_TEMP_C);
        app->r_temp_factor = TV_R(1.0);
        app->r_temp_inv = TV_R(1.0);
        return TV_OK;
    }
    if (!TV_IS_FINITE(temp_C)) {
        return TV_ERR_NONFINITE;
    }
    if (temp_C < ((tv_real_t)APP_WINDING_TEMP_MIN_C) || temp_C > ((tv_real_t)APP_WINDING_TEMP_MAX_C)) {
        return TV_ERR_RANGE;
    }
    app->winding_temp_known = 1u;
    app->winding_temp_C = temp_C;
    app->r_temp_factor = TV_R(1.0) + ((tv_real_t)APP_COPPER_ALPHA_PER_K) * (temp_C - ((tv_real_t)APP_R_REF_TEMP_C));
    app->r_temp_inv = TV_R(1.0) / app->r_temp_factor;
    return TV_OK;
}

/*
 * Voltage the model sees over a period with the bridge disabled. The real winding is open: the
 * current decays through the body diodes against the supply (di/dt ~ -(Vs + 2 Vd) / L, ~7 A/ms
 * here) in well under a period and then stays 0 whatever the plate does. The model has no
 * open-circuit state; the constant voltage that takes the predicted current from i0 to exactly
 * 0 at the end of the period (the exact armature solution over Ts with the back-EMF n Ke w held:
 * i1 = a_T i0 + b_T (u - n Ke w) = 0) is the closest constant input: the current ends at 0 as
 * in reality, and a current already at 0 stays there while the plate moves (u = n Ke w). With
 * u = n Ke w alone the current decayed with L/R = 0.47 ms and 12 % of it was still predicted
 * after a period.
 */
/* The model's armature over one period: i1 = a_T i0 + b_T (u - n Ke w). */
static void armature_period(const tvm_t *m, tv_real_t *a_T, tv_real_t *b_T)
{
    tv_real_t a = TV_R(1.0);
    int k;
    for (k = 0; k < m->p.substeps; ++k) { /* a_T = a^N: N <= TVM_SUBSTEPS_MAX, bounded */
        a *= m->a;
    }
    *a_T = a;
    /* b_T = b (1 + a + ... + a^(N-1)) */
    *b_T = m->a < TV_R(1.0) ? m->b_A_V * (TV_R(1.0) - a) / (TV_R(1.0) - m->a) : m->b_A_V * (tv_real_t)m->p.substeps;
}

static tv_real_t open_bridge_voltage(const app_t *app)
{
    const tvm_t *m = &app->ekf.model;
    tv_real_t a_T;
    tv_real_t b_T;
    tv_real_t x[TVM_NX];
    armature_period(m, &a_T, &b_T);
    ekf_state(&app->ekf, x);
    return m->nKe_V_s * x[TVM_W] - a_T / b_T * x[TVM_I];
}

void app_outputs_forced_off(app_t *app)
{
    if (app != NULL) {
        app->u_applied_V = open_bridge_voltage(app);
        app->open_after_missed = 0u;
        app->integ_V = TV_R(0.0);
    }
}

void app_sample_missed(app_t *app)
{
    if (app != NULL) {
        app->open_after_missed = 1u; /* u_applied_V stays: the ending period ran with it */
        app->integ_V = TV_R(0.0);
    }
}

/* Debounce one check: consecutive failures trip (and latch) its fault. */
static void debounce(app_t *app, int chk, int failed)
{
    if (failed) {
        if (app->debounce[chk] < 0xFFFFu) {
            ++app->debounce[chk];
        }
        if (app->debounce[chk] >= app->cfg.limits.debounce_trip) {
            app->faults |= s_check_fault[chk];
        }
    } else {
        app->debounce[chk] = 0u;
    }
}

static tv_real_t clamp(tv_real_t v, tv_real_t lo, tv_real_t hi) { return v < lo ? lo : (v > hi ? hi : v); }

/* sin() of the scalar type. */
static tv_real_t app_sin(tv_real_t a)
{
#if TV_REAL_IS_DOUBLE
    return sin(a);
#else
    return sinf(a);
#endif
}

/*
 * Time within the current period of an excitation [s], from the integer microseconds since start:
 * the modulo is taken in integers, so only a number below one period is ever converted to the
 * scalar type. (Converting the microseconds since boot to float seconds left 256 us of
 * resolution after an hour and 8 ms after a day.) The period is realised as a whole number of
 * microseconds: 5 Hz exactly, 3 Hz as 3.000003 Hz (1 ppm, below any crystal's tolerance).
 */
static tv_real_t time_in_period_s(uint64_t elapsed_us, tv_real_t period_s)
{
    const tv_real_t p_us = period_s * TV_R(1e6) + TV_R(0.5);
    /* 32-bit conversions and modulo whenever the values fit (a period below 71 minutes; the
     * first 71 minutes since start), which the Cortex-M4 does in single instructions: the
     * 64-bit ones are library calls (the float to 64-bit conversion through double arithmetic
     * in software), about 300 instructions per call together. Same results. */
    if (p_us < TV_R(4294967296.0)) {
        const uint32_t period_us = p_us >= TV_R(1.0) ? (uint32_t)p_us : 1u;
        const uint64_t r = elapsed_us <= (uint64_t)UINT32_MAX ? (uint64_t)((uint32_t)elapsed_us % period_us)
                                                               : elapsed_us % period_us;
        return (tv_real_t)(uint32_t)r * TV_R(1e-6);
    }
    return (tv_real_t)(elapsed_us % (uint64_t)p_us) * TV_R(1e-6);
}

/* The APP_MODE_IDENT sequence (app.h): segments of a fixed table, voltages as fractions of the
 * amplitude. Sines and squares run a whole number of cycles per segment, so every segment starts
 * and ends at its offset (no jump but the designed ones). */
typedef enum { IDENT_CONST = 0, IDENT_SINE, IDENT_SQUARE, IDENT_SETTLE } ident_kind_t;
typedef struct {
    uint32_t dur_ms;   /* segment length [ms] */
    uint8_t kind;      /* ident_kind_t */
    uint8_t cycles;    /* sine / square cycles over the segment */
    float level;       /* constant level (IDENT_CONST, IDENT_SETTLE) or amplitude, fraction of amplitude_V */
} ident_seg_t;

/* IDENT_SETTLE: a constant level, reached through a 100 Hz square dither that decays linearly
 * from IDENT_SETTLE_FRAC x amplitude_V to nothing over the first IDENT_SETTLE_MS: 2.4 V at 12 V,
 * above either class's static friction in torque (0.38 and 0.66 N m). The plate is shaken free of
 * the friction its arrival left and comes to rest where the stop balances the push (as stop
 * learning settles). The highest level, 0.75, plus the dither stays within the amplitude: a
 * dither the duty limit clips leaves friction behind (measured 0.8 Mc at a 1.0 level). */
#define IDENT_SETTLE_FRAC 0.2f
#define IDENT_SETTLE_MS 300u

static const ident_seg_t s_ident[] = {
    {500u, IDENT_CONST, 0u, 0.0f},    /* at rest at limp-home: the current's zero */
    {4000u, IDENT_SINE, 2u, 0.40f},   /* 0.5 Hz, 4.8 V: slow swings, breakaway from limp-home, reversals */
    {4000u, IDENT_SINE, 4u, 0.65f},   /* 1 Hz, 7.8 V */
    {2000u, IDENT_SINE, 5u, 1.0f},    /* 2.5 Hz, 12 V: fast travel, inertia */
    {2000u, IDENT_SINE, 10u, 1.0f},   /* 5 Hz, 12 V (the paper's sine) */
    {4000u, IDENT_SQUARE, 4u, 0.8f},  /* +-9.6 V steps at 1 Hz: accelerations, dwells at both stops */
    /* open stop, unloaded in four levels, each settled by a decaying dither: contact law, stop
     * angle, R at stall */
    {750u, IDENT_SETTLE, 0u, 0.75f},
    {750u, IDENT_SETTLE, 0u, 0.5f},
    {750u, IDENT_SETTLE, 0u, 0.35f},
    {750u, IDENT_SETTLE, 0u, 0.25f},
    {500u, IDENT_CONST, 0u, 0.0f},    /* spring return */
    {750u, IDENT_SETTLE, 0u, -0.75f},   /* closed stop, the same four levels */
    {750u, IDENT_SETTLE, 0u, -0.5f},
    {750u, IDENT_SETTLE, 0u, -0.35f},
    {750u, IDENT_SETTLE, 0u, -0.25f},
    {500u, IDENT_CONST, 0u, 0.0f},
    {6500u, IDENT_SINE, 2u, 0.35f},   /* 0.31 Hz, 4.2 V: slow motion, low-speed reversals */
};
#define IDENT_NSEG (sizeof s_ident / sizeof s_ident[0])

tv_real_t app_ident_voltage(uint32_t t_ms, tv_real_t amplitude_V)
{
    uint32_t t = t_ms % APP_IDENT_PERIOD_MS;
    size_t k;
    for (k = 0; k < IDENT_NSEG; ++k) { /* bounded: the table's length */
        const ident_seg_t *g = &s_ident[k];
        if (t < g->dur_ms) {
            const tv_real_t a = (tv_real_t)g->level * amplitude_V;
            if (g->kind == (uint8_t)IDENT_SINE) {
                return a * app_sin(TV_R(2.0) * APP_PI * (tv_real_t)(t * g->cycles) / (tv_real_t)g->dur_ms);
            }
            if (g->kind == (uint8_t)IDENT_SQUARE) {
                return ((t * 2u * g->cycles) / g->dur_ms) % 2u == 0u ? a : -a;
            }
            if (g->kind == (uint8_t)IDENT_SETTLE && t < IDENT_SETTLE_MS) {
                const tv_real_t dv = (tv_real_t)IDENT_SETTLE_FRAC * amplitude_V *
                                     (tv_real_t)(IDENT_SETTLE_MS - t) / (tv_real_t)IDENT_SETTLE_MS;
                return (t / 5u) % 2u == 0u ? a + dv : a - dv; /* 5 ms half periods: 100 Hz */
            }
            return a;
        }
        t -= g->dur_ms;
    }
    return TV_R(0.0); /* not reached: the table fills the period (test_app checks the sum) */
}

/* Voltage command of the active mode, elapsed_us [us] after the start. */
static tv_real_t control_law(app_t *app, uint64_t elapsed_us)
{
    const app_control_t *c = &app->cfg.control;
    const tvm_params_t *p = &app->cfg.model;
    switch (c->mode) {
    case APP_MODE_SINE: {
        if (!(c->freq_Hz > TV_R(0.0))) {
            return TV_R(0.0); /* sin(0): a 0 Hz sine never leaves its start */
        }
        const tv_real_t period_s = TV_R(1.0) / c->freq_Hz;
        return c->amplitude_V * app_sin(TV_R(2.0) * APP_PI * time_in_period_s(elapsed_us, period_s) / period_s);
    }
    case APP_MODE_STEPS: {
        /* first half of each period +A, second half -A; 0 Hz: the first half lasts for ever */
        if (!(c->freq_Hz > TV_R(0.0))) {
            return c->amplitude_V;
        }
        const tv_real_t period_s = TV_R(1.0) / c->freq_Hz;
        return time_in_period_s(elapsed_us, period_s) < TV_R(0.5) * period_s ? c->amplitude_V : -c->amplitude_V;
    }
    case APP_MODE_CHIRP: {
        /* linear sweep f0 -> f1 over chirp_period, restarting: phase = 2 pi (f0 tau + (f1-f0) tau^2 / 2T) */
        const tv_real_t T = c->chirp_period_s;
        const tv_real_t tau = time_in_period_s(elapsed_us, T);
        const tv_real_t ph = TV_R(2.0) * APP_PI * (c->freq_Hz * tau + (c->chirp_f1_Hz - c->freq_Hz) * tau * tau / (TV_R(2.0) * T));
        return c->amplitude_V * app_sin(ph);
    }
    case APP_MODE_POSITION: {
        /* PID on the estimated angle with model feed-forward of the springs and of Coulomb
         * friction; the derivative acts on the estimated velocity (no derivative kick). */
        const tv_real_t lo = p->phi_closed_rad + c->target_margin_rad;
        const tv_real_t hi = p->phi_open_rad - c->target_margin_rad;
        const tv_real_t target = clamp(c->target_rad, lo, hi);
        tv_real_t x[TVM_NX];
        ekf_state(&app->ekf, x);
        const tv_real_t phi = x[TVM_PHI];
        const tv_real_t w = x[TVM_W];
        const tv_real_t e = target - phi;
        const tv_real_t nkt = p->n_gear * p->Kt_Nm_A;
        tv_real_t torque_ff = tvm_spring_torque(p, target);
        tv_real_t u;
        if (e > TV_R(0.002)) {
            torque_ff += p->Mc_Nm;
        } else if (e < TV_R(-0.002)) {
            torque_ff -= p->Mc_Nm;
        }
        app->integ_V = clamp(app->integ_V + c->ki_V_rad_s * e * p->Ts_s, -c->i_limit_V, c->i_limit_V);
        u = p->R_ohm * torque_ff / nkt + p->n_gear * p->Ke_V_s_rad * w + c->kp_V_rad * e + app->integ_V -
            c->kd_V_s_rad * w;
        return u;
    }
    case APP_MODE_STOP_LEARN: {
        /* the last plausible measured angle (the estimate before any: the routine must not
         * start from nothing) */
        tv_real_t x[TVM_NX];
        tv_real_t u;
        ekf_state(&app->ekf, x);
        u = sl_step(&app->sl, app->have_last_angle ? app->last_angle_rad : x[TVM_PHI]);
        if (!sl_running(&app->sl)) {
            if (app->sl.phase == SL_DONE) {
                /* the fitted contact onsets and law go to the estimator (README "Stop contact") */
                if (app_set_stops(app, app->sl.onset_closed_rad, app->sl.onset_open_rad) == TV_OK &&
                    ekf_set_contact_law(&app->ekf, app->sl.k_stop, app->sl.exponent,
                                        app->sl.cfg.lambda_per_k_s_rad * app->sl.k_stop) == TV_OK) {
                    app->cfg.model.k_stop_Nm_rad = app->sl.k_stop;
                    app->cfg.model.stop_exponent = app->sl.exponent;
                    app->cfg.model.d_stop_Nm_s_rad = app->sl.cfg.lambda_per_k_s_rad * app->sl.k_stop;
                    /* impacts refine the new law from here, and the inflation's coupling with it */
                    (void)il_reset(&app->il, &app->cfg.impact_learn, &app->ekf.model.p);
                    use_coupling(app);
                }
            }
            app->cfg.control.mode = APP_MODE_OFF;
            u = TV_R(0.0);
        }
        return u;
    }
    case APP_MODE_IDENT:
        return app_ident_voltage((uint32_t)((elapsed_us / 1000u) % APP_IDENT_PERIOD_MS), c->amplitude_V);
    case APP_MODE_OFF:
    default:
        return TV_R(0.0);
    }
}

/* ------------------------------------------------------------------------------------------ */
/* Diagnostic codes (firmware/diag/): the detectors' calls and the codes' actions              */
/* ------------------------------------------------------------------------------------------ */

/* The torque signature (diag_torque_feed()) is fed only this far inside the learned stops (the
 * contact torque is no friction or spring) and this far from limp-home (where the preload's sign
 * turns) [rad]. The limp-home margin is also what keeps an angle offset common to both tracks
 * from reading as a preload change: an offset d moves the measured limp-home by d, and within d
 * of it the model's preload pushes the wrong way (measured: with 0.02 rad a common offset of 2 %
 * of the sensor supply, 0.042 rad, confirmed P1A02 in 9 of 160 runs; with 0.05 in none, at the
 * cost of 5 of 126 spring-break detections). */
#define APP_TQ_STOP_MARGIN_RAD TV_R(0.05)
#define APP_TQ_LIMP_MARGIN_RAD TV_R(0.05)

/* What a confirmation freezes (one snapshot per step): time, the estimate before this sample
 * and its variances, R + dR, supply, the duty of the period that ended. */
static void app_diag_snapshot(const app_t *app, const app_input_t *in, const app_output_t *out, diag_snapshot_t *s)
{
    tv_real_t P[TVM_NX][TVM_NX];
    tv_real_t dR;
    tv_real_t sR;
    int a;
    s->t_us = in->t_us;
    ekf_state(&app->ekf, s->x);
    ekf_covariance(&app->ekf, P);
    for (a = 0; a < TVM_NX; ++a) {
        s->var[a] = P[a][a];
    }
    ekf_resistance_error(&app->ekf, &dR, &sR);
    s->r_est_ohm = app->ekf.model.p.R_ohm + dR;
    s->supply_V = out->supply_V;
    s->duty = out->supply_V > TV_R(0.0) ? app->u_applied_V / out->supply_V : TV_R(0.0);
}

/* Before the estimator: the tracks' low-circuit counters and the supply check on the raw
 * samples, and the track vote against the estimate moved on by one period (the estimator has not
 * seen this sample). */
static diag_tps_use_t app_diag_pre(app_t *app, const app_input_t *in, tv_real_t phi1, tv_real_t phi2, const diag_snapshot_t *snap)
{
    const app_limits_t *lim = &app->cfg.limits;
    const int in_range = in->adc[1] >= lim->tps_min_counts && in->adc[1] <= lim->tps_max_counts &&
                         in->adc[2] >= lim->tps_min_counts && in->adc[2] <= lim->tps_max_counts &&
                         (app->faults & (APP_FAULT_TPS1_RANGE | APP_FAULT_TPS2_RANGE)) == 0u &&
                         !app->diag.code[DIAG_DTC_P0122].confirmed && !app->diag.code[DIAG_DTC_P0222].confirmed;
    diag_circuit_check(&app->ddet, &app->diag, in->adc[1] < lim->tps_min_counts, in->adc[2] < lim->tps_min_counts,
                       snap->supply_V, snap);
    return diag_tps_vote(&app->ddet, &app->diag, in_range && app->n_steps > 0u, phi1, phi2,
                         snap->x[TVM_PHI] + snap->x[TVM_W] * app->cfg.model.Ts_s, snap);
}

/* Before the estimator, once the angle of this sample is chosen: the open-winding and bridge
 * check on the period that ended, with the back-EMF of the measured motion (the differentiated
 * angle the estimator gets: the same tracks as the last angle, so a named track's offset does
 * not look like motion; valid when there is an angle now and one before). */
static void app_diag_motor(app_t *app, const app_input_t *in, tv_real_t current, int motion_ok, tv_real_t w_meas,
                           const diag_snapshot_t *snap)
{
    const app_limits_t *lim = &app->cfg.limits;
    const int cur_ok = in->adc[0] >= lim->current_min_counts && in->adc[0] <= lim->current_max_counts;
    diag_open_check(&app->ddet, &app->diag, app->n_steps > 0u && app->diag_bridge_on && cur_ok, app->u_applied_V,
                    app->ekf.model.nKe_V_s * snap->x[TVM_W], motion_ok, app->ekf.model.nKe_V_s * w_meas, current, snap);
}

/* 1 while the model is the one in service: not while the stops are learned nor during the
 * identification sequence (both drive the plate into its stops on purpose). */
static int model_in_service(const app_control_t *c)
{
    return c->mode != APP_MODE_STOP_LEARN && c->mode != APP_MODE_IDENT;
}

/* The fit's per-unit baseline, learned (diag_detect_config_t::fit_base_windows): the window just
 * taken (the model in service, the winding's temperature known) joins the mean while no code is
 * pending or confirmed and its n Ke is determined; after fit_base_windows of them the mean is the
 * baseline, kept when it lies inside APP_FIT_BASE_R_BAND / APP_FIT_BASE_K_BAND of the model's
 * (the class's spread and the temperature's error), else the learning starts over. */
static void fit_base_learn(app_t *app)
{
    const uint16_t need = app->cfg.diag.fit_base_windows;
    const tv_real_t k_nom = app->ekf.model.nKe_V_s;
    int k;
    if (need == 0u || !(app->vfit.nke_sigma_V_s <= app->cfg.diag.ke_sigma_max * k_nom)) {
        return;
    }
    for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
        if (app->diag.code[k].counter > 0u || app->diag.code[k].confirmed) {
            return;
        }
    }
    app->fit_base_sum_r += app->vfit.r_ohm * app->r_temp_inv;
    app->fit_base_sum_k += app->vfit.nke_V_s;
    if (++app->fit_base_n >= need) {
        const tv_real_t r = app->fit_base_sum_r / (tv_real_t)app->fit_base_n;
        const tv_real_t kk = app->fit_base_sum_k / (tv_real_t)app->fit_base_n;
        const tv_real_t r_rel = r / app->ekf.model.p.R_ohm;
        const tv_real_t k_rel = kk / k_nom;
        if (TV_FABS(r_rel - TV_R(1.0)) <= (tv_real_t)APP_FIT_BASE_R_BAND &&
            TV_FABS(k_rel - TV_R(1.0)) <= (tv_real_t)APP_FIT_BASE_K_BAND) {
            app->fit_base_r_ohm = r;
            app->fit_base_nke_V_s = kk;
            app->fit_base_state = (uint8_t)APP_FIT_BASE_IN_FORCE;
        }
        app->fit_base_n = 0u;
        app->fit_base_sum_r = TV_R(0.0);
        app->fit_base_sum_k = TV_R(0.0);
    }
}

/* After the control law: the action of the confirmed codes on the outputs, then the jam check
 * on what is really applied (a plate the bridge no longer drives is not judged). */
static void app_diag_post(app_t *app, const diag_snapshot_t *snap, app_output_t *out, int tq_ok, tv_real_t w_pred)
{
    const app_control_t *c = &app->cfg.control;
    const tvm_params_t *p = &app->cfg.model;
    const uint8_t was_on = app->diag_bridge_on;
    diag_action_t action = diag_action(&app->diag);
    if (c->mode == APP_MODE_EXTERNAL) {
        /* another controller drives: the outputs echo it (or are safe), the model keeps what it applies */
        if (action == DIAG_ACTION_SAFE) {
            out->duty = 0.0f;
            out->bridge_enable = 0u;
        }
        app->diag_bridge_on = out->u_cmd_V != TV_R(0.0);
    } else {
        if (action == DIAG_ACTION_SAFE) {
            out->duty = 0.0f;
            out->bridge_enable = 0u;
            app->integ_V = TV_R(0.0);
            app->u_applied_V = open_bridge_voltage(app);
        } else if (action == DIAG_ACTION_LIMITED && out->bridge_enable) {
            const float lim = (float)DIAG_LIMITED_DUTY;
            out->duty = out->duty > lim ? lim : (out->duty < -lim ? -lim : out->duty);
            app->u_applied_V = (tv_real_t)out->duty * out->supply_V;
        }
        if (out->bridge_enable && action != DIAG_ACTION_SAFE) {
            /* the bridge check's reverse pulse: one period the other way at the limited duty
             * (no current and no motion under drive: an open winding or a lost direction) */
            const int dir = app->ddet.probe_req ? diag_probe_direction(&app->ddet) : 0;
            if (dir != 0) {
                out->duty = dir > 0 ? (float)DIAG_LIMITED_DUTY : -(float)DIAG_LIMITED_DUTY;
                app->u_applied_V = (tv_real_t)out->duty * out->supply_V;
                diag_probe_done(&app->ddet);
            }
        }
        if (c->mode == APP_MODE_POSITION && out->bridge_enable && was_on && action == DIAG_ACTION_NONE && tq_ok &&
            (app->ddet.pc.w > TV_R(0.0) || app->ddet.po.w > TV_R(0.0))) {
            /* the spring probe: a plate held after motion that read as a weak spring (or, closing,
             * as more friction; opening, as less) gets the model's spring torque plus 0.65 of its
             * sliding friction (the adapted levels from before the suspicion) for a few periods,
             * through the adapted resistance (a healthy plate, or one with more friction, stays: its
             * static friction is at least the sliding one; one without its spring moves away from
             * limp-home) */
            const tv_real_t phi = out->x[TVM_PHI];
            tv_real_t torque = TV_R(0.0);
            const int away = phi > out->stop_closed_rad + APP_TQ_STOP_MARGIN_RAD &&
                             phi < out->stop_open_rad - APP_TQ_STOP_MARGIN_RAD && TV_FABS(phi) > APP_TQ_LIMP_MARGIN_RAD &&
                             !st_model_in_doubt(&app->st) && c->mode != APP_MODE_STOP_LEARN;
            if (diag_spring_probe(&app->ddet, &app->diag, away, phi, out->x[TVM_W], p->M0_Nm, p->c_Nm_rad * phi, p->Mc_Nm,
                                  out->preload_rel, out->friction_rel, &torque, snap)) {
                const tv_real_t dl = c->duty_limit;
                const tv_real_t u = out->r_est_ohm * torque / (p->n_gear * p->Kt_Nm_A) + p->n_gear * p->Ke_V_s_rad * out->x[TVM_W];
                out->duty = (float)clamp(u / out->supply_V, -dl, dl);
                app->u_applied_V = (tv_real_t)out->duty * out->supply_V;
            }
        }
        app->diag_bridge_on = out->bridge_enable;
    }
    {
        /* the model's breakaway voltage here in the push's direction: static friction, and the
         * springs' preload and rate where they oppose the push (diag_jam_breakaway_Nm()), through
         * the larger of the model's resistance (at the winding's temperature, when known) and the
         * adapted one: a warm or corroded winding needs more voltage for the same torque, and an
         * identified unit's tighter jam_break_factor must not take that for a jam */
        const tv_real_t r_model = p->R_ohm * app->r_temp_factor;
        const tv_real_t r_brk = out->r_est_ohm > r_model ? out->r_est_ohm : r_model;
        const tv_real_t u_break_V = r_brk / (p->n_gear * p->Kt_Nm_A) *
                                    diag_jam_breakaway_Nm(&app->ddet, app->u_applied_V, out->x[TVM_PHI], p->Ms_Nm, p->M0_Nm,
                                                          p->c_Nm_rad);
        /* closed loop: the target; open loop (sine, steps, chirp): the stop the voltage pushes
         * toward, the farthest the plate can go that way (at that stop it rightly stays) */
        const int open_loop = c->mode == APP_MODE_SINE || c->mode == APP_MODE_STEPS || c->mode == APP_MODE_CHIRP;
        const tv_real_t goal = open_loop ? (app->u_applied_V >= TV_R(0.0) ? TV_R(1e3) : TV_R(-1e3)) : c->target_rad;
        /* stops never learned (the envelope on): in open loop the real stop may lie up to
         * env_window_rad nearer than the model's, where a healthy plate rightly rests */
        const tv_real_t margin =
            c->target_margin_rad + (open_loop && app->st.cfg.envelope ? app->st.cfg.env_window_rad : TV_R(0.0));
        diag_jam_check(&app->ddet, &app->diag, (c->mode == APP_MODE_POSITION || open_loop) && out->bridge_enable && was_on,
                       clamp(goal, p->phi_closed_rad + margin, p->phi_open_rad - margin), out->x[TVM_PHI],
                       app->u_applied_V, u_break_V, snap);
    }
    diag_resistance_check(&app->ddet, &app->diag, was_on && app->diag_bridge_on && c->mode != APP_MODE_STOP_LEARN,
                          out->z[EKF_CH_CURRENT], out->r_est_ohm, out->r_sigma_ohm,
                          app->ekf.model.p.R_ohm * app->r_temp_factor, app->winding_temp_known, snap);
    {
        /* the torque signature: the velocity correction of this sample is the torque the model did
         * not explain; fed away from the stops (contact) and from limp-home (the preload's sign) */
        const tv_real_t phi = out->x[TVM_PHI];
        const tv_real_t w = out->x[TVM_W];
        const int away = phi > out->stop_closed_rad + APP_TQ_STOP_MARGIN_RAD && phi < out->stop_open_rad - APP_TQ_STOP_MARGIN_RAD &&
                         TV_FABS(phi) > APP_TQ_LIMP_MARGIN_RAD;
        if (tq_ok && away) {
            const tv_real_t aw = TV_FABS(w) / p->ws_rad_s;
            /* g(w) with exp(-x) ~ 1 / (1 + x + x^2 / 2): within 0.02 N m, no libm call on the ECU */
            const tv_real_t g = p->Mc_Nm + (p->Ms_Nm - p->Mc_Nm) / (TV_R(1.0) + aw + TV_R(0.5) * aw * aw);
            const tv_real_t m0 = p->M0_Nm * out->preload_rel;
            const tv_real_t j_ts = p->J_kg_m2 / p->Ts_s;
            const tv_real_t spring = (phi > TV_R(0.0) ? m0 : -m0) + p->c_Nm_rad * phi;
            diag_torque_feed(&app->ddet, 1, w, j_ts * (w - w_pred), j_ts * (w_pred - snap->x[TVM_W]), spring,
                             out->friction_rel * g, app->u_applied_V);
        }
    }
    /* the mechanics are judged in service only: not while the stops are learned, nor during the
     * identification sequence (tq_ok above); and the adapted friction and preload take up the
     * error of a stop model never learned and found wrong (measured: P2119 confirmed in 118 of
     * 1,440 healthy runs without stop learning): held while st_model_in_doubt() */
    diag_param_check(&app->ddet, &app->diag,
                     model_in_service(c) && out->ekf_status == TV_OK && !st_model_in_doubt(&app->st),
                     out->x[TVM_W],
                     out->friction_rel, out->friction_rel_sigma, out->preload_rel, out->preload_rel_sigma, snap);
    /* the current sensor: zero at rest, no offset in the current innovation under drive */
    diag_current_sensor_check(&app->ddet, &app->diag, was_on, (out->degraded & APP_DEGRADED_CURRENT) == 0u,
                              c->mode != APP_MODE_STOP_LEARN && out->ekf_status == TV_OK &&
                                  out->innov.used[EKF_CH_CURRENT] != 0u,
                              out->z[EKF_CH_CURRENT],
                              out->innov.innov[EKF_CH_CURRENT], snap->x[TVM_W], snap);
    out->dtc_action = (uint8_t)diag_summary(&app->diag, &out->dtc_confirmed);
}

void app_step(app_t *app, const app_input_t *in, app_output_t *out)
{
    const app_calib_t *cal;
    const app_limits_t *lim;
    uint32_t periods = 1u;
    int sample_ok;
    int angle_ok;
    unsigned use_mask;
    tv_real_t phi1;
    tv_real_t phi2;
    tv_real_t angle;
    tv_real_t current;
    ekf_meas_t meas;
    diag_snapshot_t dsnap; /* the diagnostic codes' snapshot of this step */
    tv_real_t w_pred;      /* the estimated velocity predicted for this sample, before its correction */
    int tq_ok;             /* 1: this sample's velocity correction feeds the torque signature */
    uint32_t k;
    if (app == NULL || in == NULL || out == NULL) {
        return;
    }
    memset(out, 0, sizeof *out);
    cal = &app->cfg.calib;
    lim = &app->cfg.limits;

    /* Timing: the number of periods since the last sample; gaps are predicted across. */
    if (!app->started) {
        app->started = 1u;
        app->t0_us = in->t_us;
    } else if (in->t_us <= app->last_t_us) {
        app->faults |= APP_FAULT_TIMING;
        periods = 0u;
    } else {
        const uint64_t dt = in->t_us - app->last_t_us;
        /* in 32 bits whenever it fits (always but after a 71-minute gap): the Cortex-M4 divides
         * those in one instruction, a 64-bit division is a library call of about 70 */
        const uint64_t n = dt <= (uint64_t)(UINT32_MAX - APP_PERIOD_US / 2u)
                               ? (uint64_t)(((uint32_t)dt + APP_PERIOD_US / 2u) / APP_PERIOD_US)
                               : (dt + APP_PERIOD_US / 2u) / APP_PERIOD_US;
        if (n == 0u || n > lim->max_gap_periods) {
            app->faults |= APP_FAULT_TIMING;
            periods = n == 0u ? 0u : lim->max_gap_periods;
        } else {
            periods = (uint32_t)n;
        }
        out->missing_samples = periods > 0u ? periods - 1u : 0u;
    }
    if (periods > 0u || !app->started) {
        app->last_t_us = in->t_us;
    }

    /* Counts to units. */
    current = ((tv_real_t)in->adc[0] - cal->current_offset_counts) * cal->current_A_per_count;
    phi1 = ((tv_real_t)in->adc[1] - cal->tps1_counts_at_zero) * cal->tps1_rad_per_count;
    phi2 = ((tv_real_t)in->adc[2] - cal->tps2_counts_at_zero) * cal->tps2_rad_per_count;
    angle = (phi1 + phi2) * TV_R(0.5);
    out->supply_V = (tv_real_t)in->adc[3] * cal->supply_V_per_count;

    /* Plausibility, debounced into latched faults; per channel, what this sample can correct
     * with (app.h, APP_DEGRADED_*): an implausible channel is left out, the others correct. */
    {
        const int f_cur = in->adc[0] < lim->current_min_counts || in->adc[0] > lim->current_max_counts;
        const int f_t1 = in->adc[1] < lim->tps_min_counts || in->adc[1] > lim->tps_max_counts;
        const int f_t2 = in->adc[2] < lim->tps_min_counts || in->adc[2] > lim->tps_max_counts;
        /* a track whose low-circuit code is confirmed (intermittent dropouts) stays out */
        const int t1_lost = f_t1 || (app->faults & APP_FAULT_TPS1_RANGE) != 0u || app->diag.code[DIAG_DTC_P0122].confirmed;
        const int t2_lost = f_t2 || (app->faults & APP_FAULT_TPS2_RANGE) != 0u || app->diag.code[DIAG_DTC_P0222].confirmed;
        /* the tracks can only disagree when both are there */
        const int f_dis = !t1_lost && !t2_lost && TV_FABS(phi1 - phi2) > lim->tps_disagree_max_rad;
        const int f_sup = out->supply_V < lim->supply_min_V || out->supply_V > lim->supply_max_V;
        if (!t1_lost && !t2_lost && app->n_steps % APP_TPS_AGREE_DECIM == 0u) {
            /* track agreement: a running mean and variance of phi1 - phi2 over the first
             * APP_TPS_AGREE_N samples, exponentially weighted with 1 / that after */
            const tv_real_t d = phi1 - phi2 - app->tps_diff_mean;
            tv_real_t a;
            if (app->tps_diff_n < APP_TPS_AGREE_N) {
                ++app->tps_diff_n;
            }
            a = TV_R(1.0) / (tv_real_t)app->tps_diff_n;
            app->tps_diff_mean += a * d;
            app->tps_diff_var = (TV_R(1.0) - a) * (app->tps_diff_var + a * d * d);
            app->tps_diff_sd = TV_SQRT(app->tps_diff_var);
        }
        debounce(app, CHK_CURRENT, f_cur);
        debounce(app, CHK_TPS1, f_t1);
        debounce(app, CHK_TPS2, f_t2);
        debounce(app, CHK_DISAGREE, f_dis);
        debounce(app, CHK_SUPPLY, f_sup);
        use_mask = EKF_CH_BIT(EKF_CH_CURRENT) | EKF_CH_BIT(EKF_CH_VELOCITY) | EKF_CH_BIT(EKF_CH_ANGLE);
        if (f_cur) {
            use_mask &= ~EKF_CH_BIT(EKF_CH_CURRENT);
            out->degraded |= APP_DEGRADED_CURRENT;
        }
        if (t1_lost && !t2_lost) {
            angle = phi2;
            out->degraded |= APP_DEGRADED_TPS1;
        } else if (t2_lost && !t1_lost) {
            angle = phi1;
            out->degraded |= APP_DEGRADED_TPS2;
        } else if ((t1_lost && t2_lost) || f_dis) {
            use_mask &= ~(EKF_CH_BIT(EKF_CH_ANGLE) | EKF_CH_BIT(EKF_CH_VELOCITY));
            out->degraded |= APP_DEGRADED_ANGLE;
        }
    }
    if (in->driver_fault) {
        app->faults |= APP_FAULT_DRIVER;
    }

    /* ---- Diagnostics before the estimator (firmware/diag/diag_detect.h) ---- */
    app_diag_snapshot(app, in, out, &dsnap);
    {
        switch (app_diag_pre(app, in, phi1, phi2, &dsnap)) {
        case DIAG_TPS_ONLY1: /* track 2 named: track 1 alone */
            angle = phi1;
            use_mask |= EKF_CH_BIT(EKF_CH_ANGLE) | EKF_CH_BIT(EKF_CH_VELOCITY);
            out->degraded = (out->degraded & ~APP_DEGRADED_ANGLE) | APP_DEGRADED_TPS2;
            break;
        case DIAG_TPS_ONLY2: /* track 1 named: track 2 alone */
            angle = phi2;
            use_mask |= EKF_CH_BIT(EKF_CH_ANGLE) | EKF_CH_BIT(EKF_CH_VELOCITY);
            out->degraded = (out->degraded & ~APP_DEGRADED_ANGLE) | APP_DEGRADED_TPS1;
            break;
        case DIAG_TPS_NONE: /* P2135: neither track agrees with the estimator */
            use_mask &= ~(EKF_CH_BIT(EKF_CH_ANGLE) | EKF_CH_BIT(EKF_CH_VELOCITY));
            out->degraded |= APP_DEGRADED_ANGLE;
            break;
        case DIAG_TPS_BOTH:
        default:
            break;
        }
    }
    /* what this sample can correct with (after the plausibility checks and the track vote); the
     * supply only scales the voltage of the next period: it does not spoil this sample */
    sample_ok = (use_mask & (EKF_CH_BIT(EKF_CH_CURRENT) | EKF_CH_BIT(EKF_CH_ANGLE))) != 0u;
    angle_ok = (use_mask & EKF_CH_BIT(EKF_CH_ANGLE)) != 0u;

    /* Estimator: predict across every elapsed period with the voltage that was applied, then
     * correct with this sample if it is plausible. */
    meas.z[EKF_CH_CURRENT] = current;
    meas.z[EKF_CH_ANGLE] = angle;
    /* Differentiated velocity (the paper's third measurement): against the last plausible
     * angle and its own time, so a rejected or missing sample does not distort it. */
    meas.z[EKF_CH_VELOCITY] = TV_R(0.0);
    if (app->have_last_angle && in->t_us > app->last_angle_t_us) {
        meas.z[EKF_CH_VELOCITY] = (angle - app->last_angle_rad) / ((tv_real_t)(in->t_us - app->last_angle_t_us) * TV_R(1e-6));
    }
    app_diag_motor(app, in, current, angle_ok && app->have_last_angle && in->t_us > app->last_angle_t_us,
                   meas.z[EKF_CH_VELOCITY], &dsnap); /* diagnostics: open winding, bridge */
    out->ekf_status = TV_OK;
    for (k = 0u; k < periods; ++k) {
        /* After a missed sample the outputs were forced off: the first period ran with the
         * voltage chosen for it, the later ones with the bridge open. */
        const tv_real_t u_V = k > 0u && app->open_after_missed ? open_bridge_voltage(app) : app->u_applied_V;
        const int rc = ekf_predict(&app->ekf, u_V);
        if (rc != TV_OK) {
            out->ekf_status = rc;
            break;
        }
    }
    app->open_after_missed = 0u;
    w_pred = app->ekf.x[TVM_W];
    /* not while the stops are learned nor during the identification sequence, which drives the
     * plate hard into its stops to measure the very parameters the signature would judge
     * (measured: a healthy all_varied unit 1003 confirmed P1A02 in it, and its limited
     * authority then kept the plate from the open stop that identify needs) */
    tq_ok = out->ekf_status == TV_OK && sample_ok && angle_ok && periods == 1u && model_in_service(&app->cfg.control);
    if (out->ekf_status == TV_OK && sample_ok && periods > 0u) {
        out->ekf_status = ekf_correct_channels(&app->ekf, &meas, use_mask, &out->innov);
    }
    tq_ok = tq_ok && out->ekf_status == TV_OK;
    if (out->ekf_status != TV_OK) {
        if (app->ekf_fail_run < 0xFFFFu) {
            ++app->ekf_fail_run;
        }
        if (app->ekf_fail_run >= lim->debounce_trip) {
            app->faults |= APP_FAULT_ESTIMATOR;
        }
    } else {
        app->ekf_fail_run = 0u;
        if (out->innov.n_used > 0u) {
            (void)nism_update(&app->nism, &out->innov);
        }
    }
    out->consistency = app->nism.flags;
    {
        /* the voltage equation's fit (volt_fit.h) over the period that ended: the voltage the
         * bridge applied, the measured current and the corrected velocity at both its ends */
        const tv_real_t w1 = app->ekf.x[TVM_W];
        const uint8_t ok = out->ekf_status == TV_OK && angle_ok && (out->degraded & APP_DEGRADED_CURRENT) == 0u ? 1u : 0u;
        if (ok && app->vf_prev_ok && periods == 1u && app->diag_bridge_on) {
            /* (the differentiated angle is over this period: the last sample's angle was plausible) */
            const int took = vfit_step(&app->vfit, app->u_applied_V, app->vf_i_prev, current, app->vf_w_prev, w1,
                                       meas.z[EKF_CH_VELOCITY]);
            /* (judged only on a step that took a window) */
            const int in_service = took != 0 && model_in_service(&app->cfg.control);
            if (took & VFIT_TOOK_FIT) {
                /* a window taken: the back-EMF check against the model's constants (the unit's
                 * baseline when it has one), and its R against the model's (the baseline's)
                 * while the winding's temperature is known */
                const int base = app->fit_base_r_ohm > TV_R(0.0);
                const tv_real_t k_nom = base ? app->fit_base_nke_V_s : app->ekf.model.nKe_V_s;
                const tv_real_t r_ratio =
                    app->vfit.r_ohm / ((base ? app->fit_base_r_ohm : app->ekf.model.p.R_ohm) * app->r_temp_factor);
                const tv_real_t ke_ratio = app->vfit.nke_V_s / k_nom;
                diag_backemf_check(&app->ddet, &app->diag, r_ratio, ke_ratio, app->vfit.nke_sigma_V_s / k_nom);
                diag_fit_resistance_check(&app->ddet, &app->diag, in_service && app->winding_temp_known, r_ratio, ke_ratio,
                                          base);
                if (!base && in_service && app->winding_temp_known) {
                    fit_base_learn(app);
                }
            }
            if ((took & VFIT_TOOK_OFFSET) && in_service) {
                /* the model in service only (diag_isens_fit_check()) */
                diag_isens_fit_check(&app->diag, &app->ddet, app->vfit.i_off_A, app->vfit.i_off_vif, &dsnap);
            }
        }
        app->vf_prev_ok = ok;
        app->vf_i_prev = current;
        app->vf_w_prev = w1;
    }
    /* Online stop tracking (stop_track.h), in service: not while the start-up routine runs, which
     * owns the stops then. A moved onset goes to the estimator; the tracker keeps its reference. */
    if (app->cfg.control.mode != APP_MODE_STOP_LEARN && out->ekf_status == TV_OK && periods > 0u) {
        tv_real_t xs[TVM_NX];
        ekf_state(&app->ekf, xs);
        /* the stop envelope (unlearned stops): this sample's angle against the prediction it corrected */
        const int moved = angle_ok && out->innov.used[EKF_CH_ANGLE]
                              ? st_envelope(&app->st, angle, angle - out->innov.innov[EKF_CH_ANGLE],
                                            app->have_last_angle ? angle - app->last_angle_rad : TV_R(0.0))
                              : 0;
        if (st_step(&app->st, &app->ekf.model.p, angle, angle_ok, xs[TVM_I], xs[TVM_W]) || moved) {
            (void)use_stops(app, app->st.onset[ST_CLOSED], app->st.onset[ST_OPEN]);
        }
        /* impact learning (impact_learn.h): the law the impacts show goes to the estimator */
        if (il_step(&app->il, &app->ekf.model.p, angle, angle_ok, xs, w_pred)) {
            const tv_real_t e = app->ekf.model.p.stop_exponent;
            if (ekf_set_contact_law(&app->ekf, app->il.k, e, app->il.alpha * app->il.k) == TV_OK) {
                app->cfg.model.k_stop_Nm_rad = app->il.k;
                app->cfg.model.d_stop_Nm_s_rad = app->il.alpha * app->il.k;
            }
            use_coupling(app);
        }
    }
    if (angle_ok && periods > 0u) {
        app->last_angle_rad = angle;
        app->last_angle_t_us = in->t_us;
        app->have_last_angle = 1u;
    }

    /* Control and output. Any latched fault: safe state. */
    if (app->cfg.control.mode == APP_MODE_EXTERNAL) {
        /* Another controller drives the bridge: predict with what it applies. NaN fails both
         * comparisons, +-Inf the range. */
        const float d = in->duty_ext;
        const int valid = d >= -1.0f && d <= 1.0f && in->bridge_ext <= 1u;
        const int enabled = valid && in->bridge_ext == 1u;
        if (!valid) {
            app->faults |= APP_FAULT_EXT_CMD;
        }
        app->integ_V = TV_R(0.0);
        out->u_cmd_V = enabled ? (tv_real_t)d * out->supply_V : TV_R(0.0);
        out->duty = enabled && app->faults == 0u ? d : 0.0f;
        out->bridge_enable = enabled && app->faults == 0u ? 1u : 0u;
        app->u_applied_V = enabled ? (tv_real_t)d * out->supply_V : open_bridge_voltage(app);
    } else {
        tv_real_t duty = TV_R(0.0);
        uint8_t enable = 0u;
        if (app->faults == 0u && app->cfg.control.mode != APP_MODE_OFF && out->supply_V > TV_R(0.0)) {
            const tv_real_t dl = app->cfg.control.duty_limit;
            out->u_cmd_V = control_law(app, in->t_us - app->t0_us);
            duty = clamp(out->u_cmd_V / out->supply_V, -dl, dl);
            enable = 1u;
        } else {
            app->integ_V = TV_R(0.0);
        }
        out->duty = (float)duty;
        out->bridge_enable = enable;
        /* What the model will see over the next period: the duty as the PWM gets it (float), so
         * a log of duties replays to the same estimates. */
        app->u_applied_V = enable ? (tv_real_t)out->duty * out->supply_V : open_bridge_voltage(app);
    }

    memcpy(out->z, meas.z, sizeof out->z);
    ekf_state(&app->ekf, out->x);
    ekf_sigma(&app->ekf, out->sigma);
    {
        tv_real_t dR;
        ekf_resistance_error(&app->ekf, &dR, &out->r_sigma_ohm);
        out->r_est_ohm = app->ekf.model.p.R_ohm + dR;
        out->r_20_ohm = app->winding_temp_known ? out->r_est_ohm * app->r_temp_inv : TV_R(0.0);
    }
    {
        tv_real_t f;
        ekf_friction_error(&app->ekf, &f, &out->friction_rel_sigma);
        out->friction_rel = TV_R(1.0) + f;
    }
    {
        tv_real_t mp;
        ekf_preload_error(&app->ekf, &mp, &out->preload_rel_sigma);
        out->preload_rel = TV_R(1.0) + mp;
    }
    ekf_stops(&app->ekf, &out->stop_closed_rad, &out->stop_open_rad);
    out->tps_diff_rad = app->tps_diff_mean;
    out->tps_diff_sd_rad = app->tps_diff_sd;
    /* the voltage equation's fit (TV_HEALTH_4): 0 until its first window, the offset until one read it */
    out->fit_r_ohm = app->vfit.valid ? app->vfit.r_ohm : TV_R(0.0);
    out->fit_r_sigma_ohm = app->vfit.valid ? app->vfit.r_sigma_ohm : TV_R(0.0);
    out->fit_nke_V_s = app->vfit.valid ? app->vfit.nke_V_s : TV_R(0.0);
    out->fit_i_off_A = app->vfit.off_valid ? app->vfit.i_off_A : TV_R(0.0);
    /* the fit's per-unit baseline, its state and the learning's progress (TV_HEALTH_5) */
    out->fit_base_r_ohm = app->fit_base_r_ohm;
    out->fit_base_nke_V_s = app->fit_base_nke_V_s;
    out->fit_base_state = app->fit_base_state;
    out->fit_base_windows = app->fit_base_n;
    app_diag_post(app, &dsnap, out, tq_ok, w_pred); /* diagnostics after the control law: the codes' actions, jam check */
    out->faults = app->faults;
    ++app->n_steps;
}
