/**
 * @file test_replay_roundtrip.c
 * @brief Round trip: a host_sim run (the firmware application against the plant) written to a
 *        raw log, in both formats, and replayed through replay_run() gives the live run's
 *        estimates, standard deviations, innovations, innovation sigmas, NIS, fault flags,
 *        EKF status and missing-sample counts EXACTLY (bit for bit: memcmp of the doubles).
 *        Same build, same scalar type: built for the double (sim_f64 + replay_core_f64) and the
 *        float (sim_f32 + replay_core_f32) application.
 *
 * Also the application's APP_MODE_EXTERNAL itself: the external duty drives the prediction
 * exactly as the application's own command does; an invalid one latches APP_FAULT_EXT_CMD.
 *
 * Cases: the paper's sine (set-up 2); closed-loop steps with the paper's 3 measurements and an
 * R override; stuck-release (bridge disabled, mode switches: the open-bridge voltage); a chirp
 * with dropped ticks (gaps predicted across); a 25 V supply (plausibility fault, safe state);
 * a parameter file changing model, noise and calibration.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "params.h"
#include "rawlog_write.h"
#include "replay.h"
#include "sim.h"
#include "tv_status.h"
#include "tv_test.h"

/* Longest run of a case [ticks]. */
#define RT_MAX 3000

/* What is compared, per sample. */
typedef struct {
    double x[TVM_NX];
    double sigma[TVM_NX];
    double innov[EKF_NCH];
    double innov_sigma[EKF_NCH];
    double nis; /* NaN without correction */
    uint32_t faults;
    int ekf_status;
    uint32_t missing;
    uint64_t t_us;
} rt_sample_t;

static rt_sample_t s_live[RT_MAX];
static rt_sample_t s_replayed[RT_MAX];
static int s_n_live;
static int s_n_replayed;
static rlw_t s_w;
static rlr_t s_r;
static int s_write_rc;

static void live_row(const sim_row_t *row, void *user)
{
    rawlog_record_t r;
    rt_sample_t *s;
    int a;
    (void)user;
    memset(&r, 0, sizeof r);
    r.t_us = row->t_us;
    r.duty = row->duty_f;
    for (a = 0; a < 4; ++a) {
        r.adc[a] = row->adc[a];
    }
    r.driver_fault = row->driver_fault;
    r.bridge_enable = row->bridge_enable ? 1u : 0u;
    for (a = 0; a < 3; ++a) {
        r.truth[a] = row->truth[a];
    }
    if (s_write_rc == TV_OK) {
        s_write_rc = rlw_put(&s_w, &r);
    }
    if (s_n_live >= RT_MAX) {
        return;
    }
    s = &s_live[s_n_live++];
    memset(s, 0, sizeof *s);
    memcpy(s->x, row->x, sizeof s->x);
    memcpy(s->sigma, row->sigma, sizeof s->sigma);
    memcpy(s->innov, row->innov, sizeof s->innov);
    memcpy(s->innov_sigma, row->innov_sigma, sizeof s->innov_sigma);
    s->nis = row->nis;
    s->faults = row->faults;
    s->ekf_status = row->ekf_status;
    s->missing = row->missing_samples;
    s->t_us = row->t_us;
}

/* The same quantities from the replay's app_output_t, computed as sim.c computes them. */
static void replayed_sample(const rawlog_record_t *rec, const app_output_t *out, void *user)
{
    rt_sample_t *s;
    int a;
    (void)user;
    if (s_n_replayed >= RT_MAX) {
        return;
    }
    s = &s_replayed[s_n_replayed++];
    memset(s, 0, sizeof *s);
    for (a = 0; a < TVM_NX; ++a) {
        s->x[a] = (double)out->x[a];
        s->sigma[a] = (double)out->sigma[a];
    }
    for (a = 0; a < EKF_NCH; ++a) {
        if (out->innov.used[a]) {
            s->innov[a] = (double)out->innov.innov[a];
            s->innov_sigma[a] = sqrt((double)out->innov.innov_var[a]);
        }
    }
    s->nis = out->innov.n_used > 0u ? (double)out->innov.nis_total : (double)NAN;
    s->faults = out->faults;
    s->ekf_status = out->ekf_status;
    s->missing = out->missing_samples;
    s->t_us = rec->t_us;
}

/* Raw-log header for a run's application calibration. */
static void header_for(const app_config_t *cfg, rawlog_header_t *h)
{
    const app_calib_t *c = &cfg->calib;
    rawlog_header_default(h);
    h->flags = RAWLOG_FLAG_TRUTH;
    h->records_per_block = 50u;
    params_calib_to_header(c, h);
}

/*
 * Run opt live with a raw log in format fmt, replay it with ropt, compare every sample.
 * Returns the number of samples compared.
 */
static int round_trip(const sim_options_t *opt_in, rlr_format_t fmt, const replay_options_t *ropt_in,
                      uint32_t *faults_seen, uint64_t *missing_seen)
{
    sim_options_t opt = *opt_in;
    replay_options_t ropt = *ropt_in;
    replay_stats_t st;
    sim_result_t res;
    rawlog_header_t h;
    app_config_t cfg;
    FILE *f = tmpfile();
    int k;
    int differ = 0;
    TV_CHECK(f != NULL);
    if (f == NULL) {
        return 0;
    }
    if (opt.app != NULL) {
        cfg = *opt.app;
    } else {
        app_config_default(&cfg);
    }
    header_for(&cfg, &h);
    TV_CHECK_EQ_INT(rlw_open(&s_w, f, fmt, &h, "round trip"), TV_OK);
    s_write_rc = TV_OK;
    s_n_live = 0;
    s_n_replayed = 0;
    opt.row_fn = live_row;
    TV_CHECK_EQ_INT(sim_run(&opt, &res), TV_OK);
    TV_CHECK_EQ_INT(s_write_rc, TV_OK);
    TV_CHECK_EQ_INT(rlw_close(&s_w), TV_OK);
    rewind(f);
    TV_CHECK_EQ_INT(rlr_open_file(&s_r, f, "roundtrip", fmt, 0u), TV_OK);
    ropt.on_sample = replayed_sample;
    TV_CHECK_EQ_INT(replay_run(&s_r, &ropt, &st), TV_OK);
    (void)fclose(f);
    TV_CHECK_EQ_INT(replay_exit_code(&st), RLR_EXIT_OK);
    TV_CHECK(s_n_live > 100 && s_n_live < RT_MAX);
    TV_CHECK_EQ_INT(s_n_replayed, s_n_live);
    for (k = 0; k < s_n_live && k < s_n_replayed; ++k) {
        const rt_sample_t *a = &s_live[k];
        const rt_sample_t *b = &s_replayed[k];
        const int same_nis = (isnan(a->nis) && isnan(b->nis)) || memcmp(&a->nis, &b->nis, sizeof a->nis) == 0;
        if (memcmp(a->x, b->x, sizeof a->x) != 0 || memcmp(a->sigma, b->sigma, sizeof a->sigma) != 0 ||
            memcmp(a->innov, b->innov, sizeof a->innov) != 0 ||
            memcmp(a->innov_sigma, b->innov_sigma, sizeof a->innov_sigma) != 0 || !same_nis ||
            a->faults != b->faults || a->ekf_status != b->ekf_status || a->missing != b->missing || a->t_us != b->t_us) {
            if (differ < 3) {
                fprintf(stderr, "sample %d (t_us %llu): live x %.17g %.17g %.17g faults %lx, replay x %.17g %.17g %.17g faults %lx\n",
                        k, (unsigned long long)a->t_us, a->x[0], a->x[1], a->x[2], (unsigned long)a->faults, b->x[0], b->x[1],
                        b->x[2], (unsigned long)b->faults);
            }
            ++differ;
        }
    }
    TV_CHECK_EQ_INT(differ, 0); /* exact: the same code on the same inputs */
    if (faults_seen != NULL) {
        *faults_seen = st.faults;
    }
    if (missing_seen != NULL) {
        *missing_seen = st.missing_samples;
    }
    return s_n_live;
}

static void both_formats(const sim_options_t *opt, const replay_options_t *ropt, uint32_t *faults, uint64_t *missing)
{
    TV_CHECK(round_trip(opt, RLR_FMT_CSV, ropt, faults, missing) > 0);
    TV_CHECK(round_trip(opt, RLR_FMT_BIN, ropt, faults, missing) > 0);
}

static void test_paper_sine_replays_exactly(void)
{
    sim_options_t opt;
    replay_options_t ropt;
    sim_options_default(&opt);
    replay_options_default(&ropt);
    both_formats(&opt, &ropt, NULL, NULL);
}

static void test_closed_steps_with_three_measurements_and_r_override_replay_exactly(void)
{
    sim_options_t opt;
    replay_options_t ropt;
    static params_t p;
    char err[PARAMS_MSG_MAX];
    sim_options_default(&opt);
    opt.scenario = SIM_SCN_CLOSED_STEPS;
    opt.setup = EKF_SETUP_PAPER_3MEAS;
    opt.r_velocity_rad2_s2 = 0.5;
    opt.q_override = 1;
    opt.qu_V2_s = 2e-5;
    params_init(&p, "overrides");
    TV_CHECK_EQ_INT(params_set(&p, "ekf.r_velocity_rad2_s2", 0.5, err, sizeof err), TV_OK);
    TV_CHECK_EQ_INT(params_set(&p, "ekf.qu_V2_s", 2e-5, err, sizeof err), TV_OK);
    replay_options_default(&ropt);
    ropt.setup = EKF_SETUP_PAPER_3MEAS;
    ropt.params = &p;
    both_formats(&opt, &ropt, NULL, NULL);
}

static void test_stuck_release_with_the_bridge_disabled_replays_exactly(void)
{
    sim_options_t opt;
    replay_options_t ropt;
    sim_options_default(&opt);
    opt.scenario = SIM_SCN_STUCK_RELEASE;
    replay_options_default(&ropt);
    both_formats(&opt, &ropt, NULL, NULL);
}

static void test_chirp_with_missing_samples_replays_exactly(void)
{
    sim_options_t opt;
    replay_options_t ropt;
    uint64_t missing = 0;
    sim_options_default(&opt);
    opt.scenario = SIM_SCN_CHIRP;
    opt.drop_tick_every = 7u;
    replay_options_default(&ropt);
    both_formats(&opt, &ropt, NULL, &missing);
    TV_CHECK_EQ_INT(missing, 2000 / 7); /* every 7th tick of 2000 is missing */
}

static void test_supply_fault_and_safe_state_replay_exactly(void)
{
    sim_options_t opt;
    replay_options_t ropt;
    plant_config_t pc;
    uint32_t faults = 0;
    plant_config_default(&pc);
    pc.supply_V = 25.0; /* above the 18 V window: APP_FAULT_SUPPLY_RANGE, bridge off */
    sim_options_default(&opt);
    opt.plant = &pc;
    opt.duration_s = 0.5;
    replay_options_default(&ropt);
    both_formats(&opt, &ropt, &faults, NULL);
    TV_CHECK((faults & APP_FAULT_SUPPLY_RANGE) != 0u);
}

static void test_parameter_file_changes_replay_exactly(void)
{
    static const char text[] = "model.L_H = 0.0025\nmodel.Kv_Nm_s_rad = 0.012\nekf.qT_Nm2_s = 1e-5\n"
                               "ekf.r_current_A2 = 2e-4\ncalib.tps1_counts_at_zero = 640.5\n"
                               "calib.supply_V_per_count = 0.00485\n";
    static params_t p;
    static app_config_t cfg;
    char err[PARAMS_MSG_MAX];
    sim_options_t opt;
    replay_options_t ropt;
    params_init(&p, "inline");
    TV_CHECK_EQ_INT(params_parse_text(&p, text, sizeof text - 1u, err, sizeof err), TV_OK);
    app_config_default(&cfg);
    TV_CHECK_EQ_INT(params_apply(&p, &cfg, err, sizeof err), TV_OK);
    sim_options_default(&opt);
    opt.app = &cfg; /* host_sim --params */
    replay_options_default(&ropt);
    ropt.params = &p; /* replay --params: the log's calibration is the same */
    both_formats(&opt, &ropt, NULL, NULL);
}

/* One APP_MODE_EXTERNAL step at rest with the given external command. */
static void external_step(app_t *app, uint64_t t_us, float duty, uint8_t bridge, app_output_t *out)
{
    app_input_t in;
    const app_calib_t *c = &app->cfg.calib;
    in.adc[0] = (uint16_t)(c->current_offset_counts + TV_R(0.5));
    in.adc[1] = (uint16_t)(c->tps1_counts_at_zero + TV_R(0.5));
    in.adc[2] = (uint16_t)(c->tps2_counts_at_zero + TV_R(0.5));
    in.adc[3] = (uint16_t)(TV_R(13.5) / c->supply_V_per_count + TV_R(0.5));
    in.t_us = t_us;
    in.driver_fault = 0u;
    in.duty_ext = duty;
    in.bridge_ext = bridge;
    app_step(app, &in, out);
}

/* The open-bridge input of the model, computed independently of app.c: the constant voltage that
 * takes the current to 0 at the end of a period, exact armature solution over Ts with the
 * back-EMF held (a_T = exp(-R Ts / L), b_T = (1 - a_T) / R). Relative tolerance 1e-4: app.c
 * builds a_T as a product of the N sub-step factors, which rounds differently in float. */
static int is_open_bridge_voltage(const app_t *app)
{
    const tvm_params_t *p = &app->cfg.model;
    const double a_T = exp(-(double)p->R_ohm * (double)p->Ts_s / (double)p->L_H);
    const double b_T = (1.0 - a_T) / (double)p->R_ohm;
    const double u = (double)p->n_gear * (double)p->Ke_V_s_rad * (double)app->ekf.x[TVM_W] -
                     a_T / b_T * (double)app->ekf.x[TVM_I];
    return fabs((double)app->u_applied_V - u) <= 1e-4 * (fabs(u) + 1e-3);
}

static void test_external_mode_predicts_with_the_external_command(void)
{
    static app_t app;
    app_config_t cfg;
    app_output_t out;
    app_config_default(&cfg);
    cfg.control.mode = APP_MODE_EXTERNAL;
    TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
    external_step(&app, 0u, 0.25f, 1u, &out);
    TV_CHECK_EQ_INT(out.faults, 0);
    TV_CHECK(out.duty == 0.25f && out.bridge_enable == 1u); /* echoed */
    /* exactly the live application's input of the next predict: (float) duty x measured supply */
    TV_CHECK(app.u_applied_V == (tv_real_t)0.25f * out.supply_V);
    external_step(&app, 1000u, -1.0f, 0u, &out);
    TV_CHECK(out.duty == 0.0f && out.bridge_enable == 0u);
    /* bridge open: the voltage that ends the current within the period, as the live application models it */
    TV_CHECK(is_open_bridge_voltage(&app));
    TV_CHECK_EQ_INT(out.faults, 0);
}

static void test_external_mode_rejects_an_invalid_command_with_a_fault(void)
{
    static const float bad_duty[] = {NAN, INFINITY, -INFINITY, 1.5f, -1.0000001f};
    static app_t app;
    app_config_t cfg;
    app_output_t out;
    size_t k;
    app_config_default(&cfg);
    cfg.control.mode = APP_MODE_EXTERNAL;
    for (k = 0; k <= sizeof bad_duty / sizeof bad_duty[0]; ++k) {
        const float d = k < sizeof bad_duty / sizeof bad_duty[0] ? bad_duty[k] : 0.5f;
        const uint8_t bridge = k < sizeof bad_duty / sizeof bad_duty[0] ? 1u : 2u; /* last: enable 2 */
        TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
        external_step(&app, 0u, 0.1f, 1u, &out);
        external_step(&app, 1000u, d, bridge, &out);
        TV_CHECK((out.faults & APP_FAULT_EXT_CMD) != 0u);
        TV_CHECK(out.duty == 0.0f && out.bridge_enable == 0u); /* safe state */
        TV_CHECK(TV_IS_FINITE(app.u_applied_V));                /* never used as a number */
        TV_CHECK(is_open_bridge_voltage(&app));
        /* the estimator goes on with the next valid sample; the fault stays latched */
        external_step(&app, 2000u, 0.2f, 1u, &out);
        TV_CHECK_EQ_INT(out.ekf_status, TV_OK);
        TV_CHECK((out.faults & APP_FAULT_EXT_CMD) != 0u && out.bridge_enable == 0u);
    }
    /* other modes never read the external fields */
    cfg.control.mode = APP_MODE_SINE;
    TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
    external_step(&app, 0u, NAN, 7u, &out);
    TV_CHECK_EQ_INT(out.faults, 0);
}

int main(void)
{
    TV_TEST_RUN(test_external_mode_predicts_with_the_external_command);
    TV_TEST_RUN(test_external_mode_rejects_an_invalid_command_with_a_fault);
    TV_TEST_RUN(test_paper_sine_replays_exactly);
    TV_TEST_RUN(test_closed_steps_with_three_measurements_and_r_override_replay_exactly);
    TV_TEST_RUN(test_stuck_release_with_the_bridge_disabled_replays_exactly);
    TV_TEST_RUN(test_chirp_with_missing_samples_replays_exactly);
    TV_TEST_RUN(test_supply_fault_and_safe_state_replay_exactly);
    TV_TEST_RUN(test_parameter_file_changes_replay_exactly);
    return tv_test_summary();
}
