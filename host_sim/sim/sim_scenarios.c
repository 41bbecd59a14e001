/**
 * @file sim_scenarios.c
 * @brief Scenario and estimator names, scenario controls and targets (see sim.h).
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_internal.h"
#include "tv_status.h"

/* ------------------------------------------------------------------------------------------ */
/* Names                                                                                       */
/* ------------------------------------------------------------------------------------------ */

static const char *const s_scn_names[SIM_SCN_COUNT] = {"paper_sine", "closed_steps", "closed_ramp", "chirp",
                                                       "stuck_release", "slow_sine", "open_steps", "standstill",
                                                       "limp_home", "stop_learn", "ident", "drive"};
static const double s_scn_duration_s[SIM_SCN_COUNT] = {2.0, 2.5, 2.5, 2.0, 2.2, 4.0, 4.0, 2.0, 2.4, 12.0, 30.0, 10.0};
static const char *const s_est_names[SIM_EST_COUNT] = {"app filter", "paper set-up, our map", "paper as printed",
                                                       "paper, eq.12 predict", "paper, eq.12 + exact Jac.",
                                                       "measured / differentiated"};
static const char *const s_est_ids[SIM_EST_COUNT] = {"app", "paper_setup", "paper_printed", "paper_eq12",
                                                     "paper_eq12_exact", "measured"};

static const char *const s_scn_descriptions[SIM_SCN_COUNT] = {
    "the paper's experiment: open-loop 12 V / 5 Hz sine, 2 s (touches both stops)",
    "closed loop: position steps 0.2, 0.8, 0.05, 1.2 rad, 0.5 s each, 2.5 s (tracking figures per step)",
    "closed loop: hold 0.1 rad, ramp to 1.2 rad over 1 s and back, 2.5 s (tracking error)",
    "open-loop 12 V chirp 1 -> 20 Hz over 2 s",
    "stick-slip: plate stuck at 0.5 rad, a 4.5 V pulse at 0.5 s, a 5 V/s ramp from 1.2 s, 2.2 s",
    "open-loop 5 V / 0.5 Hz sine, 4 s (slow motion, stick-slip at each reversal)",
    "open-loop +-10 V steps at 1 Hz, 4 s (dwells 0.5 s against each stop)",
    "open-loop 1.5 V / 2 Hz sine, 2 s (too small to break away from limp-home)",
    "closed loop to 0.8 rad, bridge off (spring return to limp-home), to the lowest target, off; 2.4 s",
    "start-up stop learning (APP_MODE_STOP_LEARN): slowly into each stop, learned angles reported; 12 s",
    "identification excitation (APP_MODE_IDENT, 12 V): swings at 0.5-5 Hz, steps, four levels against each stop, slow sine; 30 s",
    "closed-loop normal driving: ten pedal positions 0.05..1.2 rad, one per second, ramps at 3 rad/s; 10 s"};

const char *sim_scenario_description(sim_scenario_t s)
{
    return (unsigned)s < (unsigned)SIM_SCN_COUNT ? s_scn_descriptions[s] : "?";
}

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

int sim_scenario_takes_warmup(sim_scenario_t s)
{
    return (unsigned)s < (unsigned)SIM_SCN_COUNT && s != SIM_SCN_STUCK_RELEASE && s != SIM_SCN_STOP_LEARN;
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
    opt->winding_temp_C = APP_R_REF_TEMP_C;
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
#define SIM_STUCK_PULSE_T_S 0.5
#define SIM_STUCK_PULSE_LEN_S 0.04
#define SIM_STUCK_PULSE_V 4.5
#define SIM_STUCK_RAMP_T_S 1.2
#define SIM_STUCK_RAMP_V_S 5.0
/* limp_home: phase length, the two targets (the second is clamped to the lowest allowed) */
#define SIM_LIMP_PHASE_S 0.6
#define SIM_LIMP_TARGET_HI_RAD 0.8
#define SIM_LIMP_TARGET_LO_RAD (-1.0)
/* drive: the pedal positions, one per SIM_DRIVE_SEG_S, each reached by a ramp at SIM_DRIVE_RATE_RAD_S */
static const double s_drive_targets_rad[10] = {0.15, 0.45, 0.30, 0.90, 0.20, 1.20, 0.60, 0.05, 0.35, 0.75};
#define SIM_DRIVE_SEG_S 1.0
#define SIM_DRIVE_RATE_RAD_S 3.0

/* Initial control of a scenario (before app_init). */
void sim_scenario_control0(sim_scenario_t scn, app_control_t *c)
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
    case SIM_SCN_SLOW_SINE:
        c->mode = APP_MODE_SINE;
        c->amplitude_V = TV_R(5.0);
        c->freq_Hz = TV_R(0.5);
        break;
    case SIM_SCN_OPEN_STEPS:
        c->mode = APP_MODE_STEPS;
        c->amplitude_V = TV_R(10.0);
        c->freq_Hz = TV_R(1.0);
        break;
    case SIM_SCN_STANDSTILL:
        c->mode = APP_MODE_SINE;
        c->amplitude_V = TV_R(1.5);
        c->freq_Hz = TV_R(2.0);
        break;
    case SIM_SCN_LIMP_HOME:
        c->mode = APP_MODE_POSITION;
        c->target_rad = (tv_real_t)SIM_LIMP_TARGET_HI_RAD;
        break;
    case SIM_SCN_DRIVE:
        c->mode = APP_MODE_POSITION;
        c->target_rad = (tv_real_t)sim_target_rad(SIM_SCN_DRIVE, 0.0);
        break;
    case SIM_SCN_STOP_LEARN:
        c->mode = APP_MODE_STOP_LEARN;
        break;
    case SIM_SCN_IDENT:
        c->mode = APP_MODE_IDENT;
        c->amplitude_V = TV_R(12.0);
        break;
    case SIM_SCN_STUCK_RELEASE:
    case SIM_SCN_COUNT:
    default:
        c->mode = APP_MODE_OFF;
        break;
    }
}

/* Target angle of the closed-loop scenarios at t [s]. */
double sim_target_rad(sim_scenario_t scn, double t_s)
{
    if (scn == SIM_SCN_CLOSED_STEPS) {
        const long n = (long)floor(t_s / SIM_STEP_DWELL_S + 1e-9);
        return s_step_targets_rad[n % 4];
    }
    if (scn == SIM_SCN_DRIVE) {
        /* segment n holds target n after a ramp from target n - 1 (the last one before the first) */
        const long n = (long)floor(t_s / SIM_DRIVE_SEG_S + 1e-9);
        const double from = s_drive_targets_rad[(n + 9) % 10];
        const double to = s_drive_targets_rad[n % 10];
        const double moved = SIM_DRIVE_RATE_RAD_S * (t_s - (double)n * SIM_DRIVE_SEG_S);
        if (n <= 0 && t_s < SIM_DRIVE_SEG_S) {
            return s_drive_targets_rad[0]; /* the first segment starts at its target */
        }
        return moved >= fabs(to - from) ? to : from + (to > from ? moved : -moved);
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
int sim_scenario_update(sim_scenario_t scn, app_t *app, double t_s)
{
    switch (scn) {
    case SIM_SCN_CLOSED_STEPS:
    case SIM_SCN_CLOSED_RAMP:
    case SIM_SCN_DRIVE:
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
    case SIM_SCN_LIMP_HOME: {
        /* phases: 0 closed loop high, 1 off, 2 closed loop low, 3 off (then repeating) */
        const long phase = (long)floor(t_s / SIM_LIMP_PHASE_S + 1e-9) % 4;
        app_control_t c = app->cfg.control;
        c.mode = (phase % 2 == 0) ? APP_MODE_POSITION : APP_MODE_OFF;
        if (c.mode != app->cfg.control.mode) {
            int rc;
            c.target_rad = phase == 0 ? (tv_real_t)SIM_LIMP_TARGET_HI_RAD : (tv_real_t)SIM_LIMP_TARGET_LO_RAD;
            rc = app_set_control(app, &c);
            return rc;
        }
        return TV_OK;
    }
    case SIM_SCN_PAPER_SINE:
    case SIM_SCN_CHIRP:
    case SIM_SCN_SLOW_SINE:
    case SIM_SCN_OPEN_STEPS:
    case SIM_SCN_STANDSTILL:
    case SIM_SCN_IDENT:
    case SIM_SCN_COUNT:
    default:
        return TV_OK;
    }
}
