/**
 * @file test_app.c
 * @brief Application step: gaps are predicted across one period at a time up to
 *        limits.max_gap_periods (which bounds the step's worst-case time), beyond it the timing
 *        fault latches; the limit is validated; the excitation keeps its phase after a day of
 *        running, in the float build too.
 */
#include <math.h>
#include <string.h>

#include "app.h"
#include "tv_status.h"
#include "tv_test.h"

/* A plausible sample at time t: mid-scale current, tracks at limp-home, 13.5 V supply. */
static app_input_t sample_at(const app_t *app, uint64_t t_us)
{
    app_input_t in;
    memset(&in, 0, sizeof in);
    in.adc[0] = (uint16_t)(app->cfg.calib.current_offset_counts + TV_R(0.5));
    in.adc[1] = (uint16_t)(app->cfg.calib.tps1_counts_at_zero + TV_R(0.5));
    in.adc[2] = (uint16_t)(app->cfg.calib.tps2_counts_at_zero + TV_R(0.5));
    in.adc[3] = 2793u; /* 13.5 V through 1/6 on a 3.3 V, 12-bit ADC */
    in.t_us = t_us;
    return in;
}

static void test_gap_is_predicted_across_one_period_at_a_time(void)
{
    app_config_t cfg;
    app_t app;
    app_output_t out;
    app_input_t in;
    uint32_t before;
    app_config_default(&cfg);
    cfg.control.mode = APP_MODE_OFF;
    cfg.limits.max_gap_periods = 4u;
    TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
    in = sample_at(&app, 1000u);
    app_step(&app, &in, &out);
    in = sample_at(&app, 2000u);
    app_step(&app, &in, &out);
    TV_CHECK_EQ_INT(out.missing_samples, 0);
    /* 3 missing samples: 4 periods elapsed, 4 predictions, no fault (within the bound). */
    before = app.ekf.n_predict;
    in = sample_at(&app, 6000u);
    app_step(&app, &in, &out);
    TV_CHECK_EQ_INT(out.missing_samples, 3);
    TV_CHECK_EQ_INT(app.ekf.n_predict - before, 4);
    TV_CHECK_EQ_INT(out.faults & APP_FAULT_TIMING, 0);
    /* 5 periods elapsed > 4: the timing fault latches and only 4 predictions run, so the
     * step's time stays bounded. */
    before = app.ekf.n_predict;
    in = sample_at(&app, 11000u);
    app_step(&app, &in, &out);
    TV_CHECK_EQ_INT(app.ekf.n_predict - before, 4);
    TV_CHECK(out.faults & APP_FAULT_TIMING);
}

static void test_gap_limit_is_validated(void)
{
    app_config_t cfg;
    app_t app;
    app_config_default(&cfg);
    TV_CHECK_EQ_INT(cfg.limits.max_gap_periods, APP_MAX_GAP_PERIODS);
    cfg.limits.max_gap_periods = 0u;
    TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_ERR_CONFIG);
    cfg.limits.max_gap_periods = (uint16_t)(APP_MAX_GAP_PERIODS + 1u);
    TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_ERR_CONFIG);
    cfg.limits.max_gap_periods = 1u;
    TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
}

/* The excitation's phase is exact however long the controller has run: the float build used to
 * turn the microseconds since start into float seconds (256 us of resolution after an hour, 8 ms
 * after a day: a 5 Hz sine off by up to 2.9 V). Set the start one hour and one day back (white
 * box: t0_us is the excitation's origin; no gap is seen) and compare the command with the sine
 * computed in double. Tolerance 2e-3 V: the float sine of an argument below 2 pi is good to a
 * few 1e-7 relative, 12 V x 1e-6 = 1.2e-5 V, with room; one hour of the old float time was off
 * by up to 0.09 V, one day by volts. */
static void test_excitation_phase_is_exact_after_an_hour_and_a_day(void)
{
    static const uint64_t back_us[] = {3600000000ull, 86400000000ull, 86400000000ull * 30ull};
    const double pi = 3.14159265358979323846;
    size_t k;
    for (k = 0; k < sizeof back_us / sizeof back_us[0]; ++k) {
        app_config_t cfg;
        app_t app;
        app_output_t out;
        app_input_t in;
        uint64_t t_us;
        app_config_default(&cfg); /* the paper's 12 V / 5 Hz sine */
        TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
        in = sample_at(&app, 1000u);
        app_step(&app, &in, &out);
        app.t0_us -= back_us[k] + 37u; /* 37 us: not a whole number of milliseconds */
        for (t_us = 2000u; t_us <= 60000u; t_us += 1000u) {
            const double elapsed_s = (double)(t_us - app.t0_us) * 1e-6;
            const double expect_V = 12.0 * sin(2.0 * pi * 5.0 * fmod(elapsed_s, 0.2));
            in = sample_at(&app, t_us);
            app_step(&app, &in, &out);
            TV_CHECK_EQ_INT(out.faults, 0);
            TV_CHECK_NEAR((double)out.u_cmd_V, expect_V, 2e-3);
        }
    }
}

/* An estimator that latched APP_FAULT_ESTIMATOR is running again after app_clear_faults() (it
 * kept failing until a reset, issue 9). A diverged estimate (white box: a velocity of 1e30
 * rad/s, where the map's output is not finite, so every predict is refused and the state stays
 * as it is) makes every step fail; after the clear the next steps succeed, no fault comes back,
 * and the health record shows the restart. */
static void test_clearing_the_estimator_fault_restarts_the_estimator(void)
{
    app_config_t cfg;
    app_t app;
    app_output_t out;
    app_input_t in;
    ekf_health_t h;
    uint64_t t_us = 1000u;
    int k;
    app_config_default(&cfg);
    cfg.control.mode = APP_MODE_OFF;
    TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
    in = sample_at(&app, t_us);
    app_step(&app, &in, &out);
    app.ekf.x[TVM_W] = TV_R(1e30);
    for (k = 0; k < 2 * (int)cfg.limits.debounce_trip + 2; ++k) {
        t_us += 1000u;
        in = sample_at(&app, t_us);
        app_step(&app, &in, &out);
    }
    TV_CHECK(out.ekf_status != TV_OK);
    TV_CHECK((out.faults & APP_FAULT_ESTIMATOR) != 0u);
    app_clear_faults(&app);
    TV_CHECK_EQ_INT(app.n_estimator_resets, 1);
    for (k = 0; k < 20; ++k) {
        t_us += 1000u;
        in = sample_at(&app, t_us);
        app_step(&app, &in, &out);
        TV_CHECK_EQ_INT(out.ekf_status, TV_OK);
    }
    TV_CHECK_EQ_INT(out.faults, 0);
    ekf_health(&app.ekf, &h);
    TV_CHECK_EQ_INT(h.n_predict, 20);
    TV_CHECK_EQ_INT(h.n_rejected, 0);
}

/* The health record counts each engagement of the variance bounds: a velocity-variance ceiling
 * of 1e-6 (rad/s)^2, far below the filter's steady 1.6e-3, engages on every predict and correct. */
static void test_health_record_counts_variance_bounds(void)
{
    app_config_t cfg;
    app_t app;
    app_output_t out;
    app_input_t in;
    ekf_health_t h;
    app_config_default(&cfg);
    cfg.control.mode = APP_MODE_OFF;
    cfg.ekf.var_ceil[TVM_W] = TV_R(1e-6);
    cfg.ekf.P0[TVM_W][TVM_W] = TV_R(1e-7);
    TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
    in = sample_at(&app, 1000u);
    app_step(&app, &in, &out);
    in = sample_at(&app, 2000u);
    app_step(&app, &in, &out);
    ekf_health(&app.ekf, &h);
    TV_CHECK(h.n_ceil[TVM_W] >= 1u);
    TV_CHECK_EQ_INT(h.n_ceil[TVM_I], 0);
    TV_CHECK_EQ_INT(h.n_floor[TVM_W], 0);
    TV_CHECK_EQ_INT(h.n_predict, 2);
}

/* A sample with both tracks at angle phi1 / phi2 [rad] and the current channel at cur counts. */
static app_input_t sample_tracks(const app_t *app, uint64_t t_us, tv_real_t phi1, tv_real_t phi2, uint16_t cur)
{
    app_input_t in = sample_at(app, t_us);
    const app_calib_t *c = &app->cfg.calib;
    in.adc[0] = cur;
    in.adc[1] = (uint16_t)(c->tps1_counts_at_zero + phi1 / c->tps1_rad_per_count + TV_R(0.5));
    in.adc[2] = (uint16_t)(c->tps2_counts_at_zero + phi2 / c->tps2_rad_per_count + TV_R(0.5));
    return in;
}

/* Run n samples from t_us on; check each step's correction used exactly the expected channels
 * and flags. Returns the last output. */
static app_output_t run_channels(app_t *app, uint64_t *t_us, int n, app_input_t (*make)(const app_t *, uint64_t),
                                 int want_current, int want_angle, uint32_t want_degraded)
{
    app_output_t out;
    int k;
    memset(&out, 0, sizeof out);
    for (k = 0; k < n; ++k) {
        app_input_t in;
        *t_us += 1000u;
        in = make(app, *t_us);
        app_step(app, &in, &out);
        TV_CHECK_EQ_INT(out.ekf_status, TV_OK);
        TV_CHECK_EQ_INT(out.innov.used[EKF_CH_CURRENT], want_current);
        TV_CHECK_EQ_INT(out.innov.used[EKF_CH_ANGLE], want_angle);
        TV_CHECK_EQ_INT(out.degraded, want_degraded);
    }
    return out;
}

static app_input_t in_current_at_rail(const app_t *app, uint64_t t)
{
    return sample_tracks(app, t, TV_R(0.3), TV_R(0.3), 4095u);
}
static app_input_t in_tps1_open(const app_t *app, uint64_t t)
{
    app_input_t in = sample_tracks(app, t, TV_R(0.3), TV_R(0.3), 2048u);
    in.adc[1] = 0u; /* open circuit: the pin reads 0 */
    return in;
}
static app_input_t in_tps1_back_but_wrong(const app_t *app, uint64_t t)
{
    return sample_tracks(app, t, TV_R(0.1), TV_R(0.3), 2048u); /* in range, 0.2 rad off */
}
static app_input_t in_tps2_shorted(const app_t *app, uint64_t t)
{
    app_input_t in = sample_tracks(app, t, TV_R(0.3), TV_R(0.3), 2048u);
    in.adc[2] = 4095u; /* short to the reference */
    return in;
}
static app_input_t in_both_open(const app_t *app, uint64_t t)
{
    app_input_t in = sample_tracks(app, t, TV_R(0.3), TV_R(0.3), 2048u);
    in.adc[1] = 0u;
    in.adc[2] = 0u;
    return in;
}
static app_input_t in_disagree(const app_t *app, uint64_t t)
{
    return sample_tracks(app, t, TV_R(0.3), TV_R(0.6), 2048u);
}

static void start_at_rest(app_t *app, uint64_t *t_us)
{
    app_config_t cfg;
    app_output_t out;
    app_input_t in;
    app_config_default(&cfg);
    cfg.control.mode = APP_MODE_OFF;
    TV_CHECK_EQ_INT(app_init(app, &cfg), TV_OK);
    *t_us = 1000u;
    in = sample_at(app, *t_us);
    app_step(app, &in, &out);
}

/* Graceful loss of a channel, per channel (issue 10): the lost one is left out of the
 * correction, the other keeps correcting, the step says what it did without. The current at its
 * ADC rail used to latch the range fault and stop EVERY correction. The angle estimate must
 * reach the angle the good channels give (0.3 rad) within 2 mrad over 60 samples (4 ADC counts:
 * the estimate follows a direct angle measurement in a few samples). */
static void test_current_at_rail_leaves_the_angle_correcting(void)
{
    static app_t app;
    uint64_t t_us;
    app_output_t out;
    start_at_rest(&app, &t_us);
    out = run_channels(&app, &t_us, 60, in_current_at_rail, 0, 1, APP_DEGRADED_CURRENT);
    TV_CHECK((out.faults & APP_FAULT_CURRENT_RANGE) != 0u); /* debounced and latched, as before */
    TV_CHECK_NEAR(out.x[TVM_PHI], 0.3, 2e-3);
}

static void test_one_lost_track_continues_on_the_other(void)
{
    static app_t app;
    uint64_t t_us;
    app_output_t out;
    start_at_rest(&app, &t_us);
    out = run_channels(&app, &t_us, 60, in_tps1_open, 1, 1, APP_DEGRADED_TPS1);
    TV_CHECK((out.faults & APP_FAULT_TPS1_RANGE) != 0u);
    TV_CHECK_EQ_INT(out.faults & APP_FAULT_TPS_DISAGREE, 0); /* a lost track cannot disagree */
    TV_CHECK_NEAR(out.x[TVM_PHI], 0.3, 2e-3);
    /* the track comes back in range but wrong: latched lost, it stays out */
    out = run_channels(&app, &t_us, 30, in_tps1_back_but_wrong, 1, 1, APP_DEGRADED_TPS1);
    TV_CHECK_NEAR(out.x[TVM_PHI], 0.3, 2e-3);
    /* the other track */
    start_at_rest(&app, &t_us);
    out = run_channels(&app, &t_us, 60, in_tps2_shorted, 1, 1, APP_DEGRADED_TPS2);
    TV_CHECK((out.faults & APP_FAULT_TPS2_RANGE) != 0u);
    TV_CHECK_NEAR(out.x[TVM_PHI], 0.3, 2e-3);
}

static void test_no_usable_angle_leaves_the_current_correcting(void)
{
    static app_t app;
    uint64_t t_us;
    app_output_t out;
    start_at_rest(&app, &t_us);
    out = run_channels(&app, &t_us, 30, in_both_open, 1, 0, APP_DEGRADED_ANGLE);
    TV_CHECK((out.faults & (APP_FAULT_TPS1_RANGE | APP_FAULT_TPS2_RANGE)) == (APP_FAULT_TPS1_RANGE | APP_FAULT_TPS2_RANGE));
    TV_CHECK_EQ_INT(out.bridge_enable, 0);
    /* both in range and 0.3 rad apart: nothing tells which is right, the angle is left out */
    start_at_rest(&app, &t_us);
    out = run_channels(&app, &t_us, 30, in_disagree, 1, 0, APP_DEGRADED_ANGLE);
    TV_CHECK((out.faults & APP_FAULT_TPS_DISAGREE) != 0u);
}

/* APP_MODE_IDENT's sequence (app.h, README "Identification"): the documented levels at their
 * documented times, the period of 30 s filled exactly (the last segment ends at 29.999 s and the
 * sequence restarts at 30 s), never beyond the amplitude, and scaled by it. */
static void test_ident_sequence_is_the_documented_table(void)
{
    const tv_real_t A = TV_R(12.0);
    tv_real_t vmax = TV_R(0.0);
    uint32_t t;
    TV_CHECK_NEAR(app_ident_voltage(0u, A), 0.0, 0.0);        /* at rest */
    TV_CHECK_NEAR(app_ident_voltage(1000u, A), 4.8, 1e-5);    /* 0.5 Hz sine, 4.8 V from 0.5 s: peak at 1 s */
    TV_CHECK_NEAR(app_ident_voltage(12600u, A), 9.6, 1e-5);  /* +-9.6 V steps from 12.5 s (0.8f x 12) */
    TV_CHECK_NEAR(app_ident_voltage(13100u, A), -9.6, 1e-5);
    /* open stop levels 9, 6, 4.2, 3 V, each reached through a 100 Hz dither of 2.4 V decaying
     * to nothing over 300 ms */
    TV_CHECK_NEAR(app_ident_voltage(16500u, A), 11.4, 1e-5);
    TV_CHECK_NEAR(app_ident_voltage(16505u, A), 9.0 - 2.4 * 295.0 / 300.0, 1e-5);
    TV_CHECK_NEAR(app_ident_voltage(16800u, A), 9.0, 1e-5);
    TV_CHECK_NEAR(app_ident_voltage(17550u, A), 6.0, 1e-5);
    TV_CHECK_NEAR(app_ident_voltage(18300u, A), 4.2, 1e-5);
    TV_CHECK_NEAR(app_ident_voltage(19050u, A), 3.0, 1e-5);
    TV_CHECK_NEAR(app_ident_voltage(19500u, A), 0.0, 0.0);    /* spring return */
    TV_CHECK_NEAR(app_ident_voltage(20300u, A), -9.0, 1e-5); /* closed stop levels */
    TV_CHECK_NEAR(app_ident_voltage(22550u, A), -3.0, 1e-5);
    TV_CHECK_NEAR(app_ident_voltage(23000u, A), 0.0, 0.0);
    /* the last segment: 2 cycles of a 4.2 V sine over 6.5 s, from 23.5 s to the end of the period */
    TV_CHECK_NEAR(app_ident_voltage(23500u + 1625u / 2u, A), 4.2 * sin(2.0 * 3.14159265358979 * 2.0 * 812.0 / 6500.0), 1e-5);
    TV_CHECK_NEAR(app_ident_voltage(29999u, A), 4.2 * sin(2.0 * 3.14159265358979 * 2.0 * 6499.0 / 6500.0), 1e-5);
    TV_CHECK_NEAR(app_ident_voltage(APP_IDENT_PERIOD_MS, A), 0.0, 0.0);
    for (t = 0; t < APP_IDENT_PERIOD_MS; ++t) {
        const tv_real_t v = app_ident_voltage(t, A);
        vmax = TV_FABS(v) > vmax ? TV_FABS(v) : vmax;
        TV_CHECK_NEAR(app_ident_voltage(t + APP_IDENT_PERIOD_MS, A), v, 0.0);
        TV_CHECK_NEAR(app_ident_voltage(t, TV_R(6.0)), 0.5 * (double)v, 1e-5);
    }
    TV_CHECK_NEAR(vmax, 12.0, 1e-5);
}

int main(void)
{
    TV_TEST_RUN(test_gap_is_predicted_across_one_period_at_a_time);
    TV_TEST_RUN(test_gap_limit_is_validated);
    TV_TEST_RUN(test_excitation_phase_is_exact_after_an_hour_and_a_day);
    TV_TEST_RUN(test_clearing_the_estimator_fault_restarts_the_estimator);
    TV_TEST_RUN(test_health_record_counts_variance_bounds);
    TV_TEST_RUN(test_current_at_rail_leaves_the_angle_correcting);
    TV_TEST_RUN(test_one_lost_track_continues_on_the_other);
    TV_TEST_RUN(test_no_usable_angle_leaves_the_current_correcting);
    TV_TEST_RUN(test_ident_sequence_is_the_documented_table);
    return tv_test_summary();
}
