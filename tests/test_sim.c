/**
 * @file test_sim.c
 * @brief Tests of the host simulation: the simulation HAL (host_sim/sim/sim_hal.h), the firmware
 *        application's safe state driven through it, the simulation core (host_sim/sim/sim.h) and
 *        its statistics. Built against the double (sim_f64) and the float (sim_f32) application.
 *        Accuracy targets are not tested here (they belong to the tuning of Q and R).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "app_tick.h"
#include "sim.h"
#include "sim_hal.h"
#include "sim_internal.h"
#include "tv_status.h"
#include "tv_test.h"

#define TEST_NAN ((double)NAN)

/* ------------------------------------------------------------------------------------------ */
/* helpers                                                                                     */
/* ------------------------------------------------------------------------------------------ */

static void configure_default(uint64_t seed)
{
    plant_config_t pc;
    plant_config_default(&pc);
    TV_CHECK_EQ_INT(sim_hal_configure(&pc, seed), TV_OK);
    TV_CHECK_EQ_INT(hal_init(), TV_OK);
}

/* One application period: tick, then the plant integrates the commanded bridge for 1 ms. */
static int tick(app_t *app, app_output_t *out)
{
    const int rc = app_tick(app, out);
    TV_CHECK_EQ_INT(sim_hal_advance(1e-3), TV_OK);
    return rc;
}

static void init_app_sine(app_t *app)
{
    app_config_t cfg;
    app_config_default(&cfg); /* the paper's 12 V / 5 Hz sine */
    TV_CHECK_EQ_INT(app_init(app, &cfg), TV_OK);
}

static int all_finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* ------------------------------------------------------------------------------------------ */
/* simulation HAL                                                                              */
/* ------------------------------------------------------------------------------------------ */

static void test_hal_rejects_bad_duty_and_zeroes_the_output(void)
{
    float duty = -2.0f;
    int en = -1;
    configure_default(1u);
    TV_CHECK_EQ_INT(hal_bridge_enable(1), TV_OK);
    TV_CHECK_EQ_INT(hal_pwm_set_duty(0.5f), TV_OK);
    sim_hal_outputs(&duty, &en);
    TV_CHECK_NEAR(duty, 0.5, 0.0); /* stored as given */
    TV_CHECK_EQ_INT(en, 1);

    TV_CHECK_EQ_INT(hal_pwm_set_duty(NAN), TV_ERR_NONFINITE);
    sim_hal_outputs(&duty, NULL);
    TV_CHECK_NEAR(duty, 0.0, 0.0); /* hal.h: a rejected duty sets the output to 0 */

    TV_CHECK_EQ_INT(hal_pwm_set_duty(0.7f), TV_OK);
    TV_CHECK_EQ_INT(hal_pwm_set_duty(INFINITY), TV_ERR_NONFINITE);
    sim_hal_outputs(&duty, NULL);
    TV_CHECK_NEAR(duty, 0.0, 0.0);

    TV_CHECK_EQ_INT(hal_pwm_set_duty(0.7f), TV_OK);
    TV_CHECK_EQ_INT(hal_pwm_set_duty(1.0001f), TV_ERR_RANGE);
    sim_hal_outputs(&duty, NULL);
    TV_CHECK_NEAR(duty, 0.0, 0.0);
    TV_CHECK_EQ_INT(hal_pwm_set_duty(-1.5f), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(hal_pwm_set_duty(-1.0f), TV_OK); /* the limits themselves are valid */
    TV_CHECK_EQ_INT(hal_pwm_set_duty(1.0f), TV_OK);

    /* An enable other than 0/1 is refused and leaves the bridge off. */
    TV_CHECK_EQ_INT(hal_bridge_enable(2), TV_ERR_RANGE);
    sim_hal_outputs(NULL, &en);
    TV_CHECK_EQ_INT(en, 0);
    TV_CHECK_EQ_INT(hal_driver_fault(NULL), TV_ERR_NULL);
    TV_CHECK_EQ_INT(hal_adc_read(NULL), TV_ERR_NULL);
}

static void test_hal_duty_drives_the_plant(void)
{
    /* 0.5 duty of the 13.5 V default supply for 20 ms: the winding sees 6.75 V (averaged bridge;
     * the mean over the last ms equals duty * supply to rounding). */
    plant_state_t s;
    double u_V = 0.0;
    int k;
    configure_default(2u);
    TV_CHECK_EQ_INT(hal_pwm_set_duty(0.5f), TV_OK);
    TV_CHECK_EQ_INT(hal_bridge_enable(1), TV_OK);
    for (k = 0; k < 20; ++k) {
        TV_CHECK_EQ_INT(sim_hal_advance(1e-3), TV_OK);
    }
    TV_CHECK_EQ_INT(sim_hal_bridge_voltage(&u_V), TV_OK);
    TV_CHECK_NEAR(u_V, 6.75, 1e-9);
    TV_CHECK_EQ_INT(sim_hal_truth(&s), TV_OK);
    TV_CHECK(s.current_A > 0.1); /* 6.75 V drives current into the winding */
}

static void test_can_loopback_is_fifo_and_overflow_is_counted(void)
{
    hal_can_frame_t f;
    hal_can_frame_t g;
    uint32_t k;
    configure_default(3u);
    memset(&f, 0, sizeof f);
    TV_CHECK_EQ_INT(hal_can_receive(&g), 0); /* empty */
    for (k = 0; k < SIM_HAL_CAN_QUEUE_LEN; ++k) {
        f.id = 0x100u + k;
        f.dlc = 2u;
        f.data[0] = (uint8_t)k;
        f.data[5] = 0xAAu; /* beyond dlc: must come back as 0 */
        TV_CHECK_EQ_INT(hal_can_send(&f), TV_OK);
    }
    TV_CHECK_EQ_INT(sim_hal_can_pending(), SIM_HAL_CAN_QUEUE_LEN);
    TV_CHECK_EQ_INT(hal_can_send(&f), TV_ERR_IO);
    TV_CHECK_EQ_INT(hal_can_send(&f), TV_ERR_IO);
    TV_CHECK_EQ_INT(sim_hal_can_overflows(), 2);
    for (k = 0; k < SIM_HAL_CAN_QUEUE_LEN; ++k) {
        TV_CHECK_EQ_INT(hal_can_receive(&g), 1);
        TV_CHECK_EQ_INT(g.id, 0x100u + k);
        TV_CHECK_EQ_INT(g.data[0], k);
        TV_CHECK_EQ_INT(g.data[5], 0);
    }
    TV_CHECK_EQ_INT(hal_can_receive(&g), 0);
    /* frame validation */
    f.dlc = 9u;
    TV_CHECK_EQ_INT(hal_can_send(&f), TV_ERR_RANGE);
    f.dlc = 8u;
    f.id = 0x800u; /* > 11 bits */
    TV_CHECK_EQ_INT(hal_can_send(&f), TV_ERR_RANGE);
    f.extended = 1u;
    TV_CHECK_EQ_INT(hal_can_send(&f), TV_OK);
    f.id = 0x20000000u; /* > 29 bits */
    TV_CHECK_EQ_INT(hal_can_send(&f), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(hal_can_send(NULL), TV_ERR_NULL);
    TV_CHECK_EQ_INT(hal_can_receive(NULL), TV_ERR_NULL);
    TV_CHECK_EQ_INT(sim_hal_can_overflows(), 2); /* refused frames are not overflows */
}

static void test_time_is_monotonic_and_adc_is_stamped_with_plant_time(void)
{
    hal_adc_sample_t s;
    uint64_t prev;
    int k;
    configure_default(4u);
    prev = hal_time_us();
    TV_CHECK_EQ_INT(prev, 0);
    for (k = 1; k <= 2000; ++k) {
        uint64_t now;
        TV_CHECK_EQ_INT(sim_hal_advance(k % 7 == 0 ? 0.0 : 1e-3), TV_OK);
        now = hal_time_us();
        TV_CHECK(now >= prev);
        prev = now;
    }
    /* 2000 - 285 advances of exactly 1 ms (every 7th is 0): the plant grid is exact (50 whole
     * sub-steps per ms), the conversion rounds to the nearest us */
    TV_CHECK_EQ_INT(prev, (2000 - 2000 / 7) * 1000);
    TV_CHECK_EQ_INT(hal_adc_read(&s), TV_OK);
    TV_CHECK_EQ_INT(s.t_us, prev);
    TV_CHECK_EQ_INT(sim_hal_advance(-1e-3), TV_ERR_RANGE); /* time never goes back */
    TV_CHECK_EQ_INT(hal_time_us(), prev);
}

static void test_forced_adc_channel_reads_the_forced_counts(void)
{
    hal_adc_sample_t s;
    configure_default(5u);
    TV_CHECK_EQ_INT(sim_hal_force_adc(HAL_ADC_TPS1, 0u), TV_OK);
    TV_CHECK_EQ_INT(hal_adc_read(&s), TV_OK);
    TV_CHECK_EQ_INT(s.counts[HAL_ADC_TPS1], 0);
    TV_CHECK(s.counts[HAL_ADC_TPS2] > 3000u); /* limp-home on the falling track: ~3463 counts */
    TV_CHECK_EQ_INT(sim_hal_release_adc(HAL_ADC_TPS1), TV_OK);
    TV_CHECK_EQ_INT(hal_adc_read(&s), TV_OK);
    TV_CHECK(s.counts[HAL_ADC_TPS1] > 500u); /* ~633 counts at limp-home */
    TV_CHECK_EQ_INT(sim_hal_force_adc(4, 0u), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(sim_hal_force_adc(HAL_ADC_SUPPLY, 4096u), TV_ERR_RANGE); /* 12-bit max is 4095 */
    TV_CHECK_EQ_INT(sim_hal_release_adc(-1), TV_ERR_RANGE);
}

/* ------------------------------------------------------------------------------------------ */
/* the application's safe state through the HAL                                                */
/* ------------------------------------------------------------------------------------------ */

static void test_tps1_open_circuit_trips_safe_state_within_debounce_and_latches(void)
{
    static app_t app;
    app_output_t out;
    float duty = 1.0f;
    int en = 0;
    int k;
    int trip_tick = -1;
    configure_default(6u);
    init_app_sine(&app);
    for (k = 0; k < 100; ++k) {
        TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
    }
    TV_CHECK_EQ_INT(out.faults, 0);
    sim_hal_outputs(&duty, &en);
    TV_CHECK_EQ_INT(en, 1); /* the sine is being driven */

    /* track 1 open circuit: its pin reads 0 counts */
    TV_CHECK_EQ_INT(sim_hal_force_adc(HAL_ADC_TPS1, 0u), TV_OK);
    for (k = 1; k <= 20 && trip_tick < 0; ++k) {
        TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
        if (out.faults & APP_FAULT_TPS1_RANGE) {
            trip_tick = k;
        } else {
            sim_hal_outputs(NULL, &en);
            TV_CHECK_EQ_INT(en, 1); /* debouncing: still driving */
        }
    }
    /* exactly the debounce count of consecutive failing samples (app.h, app_limits_t) */
    TV_CHECK_EQ_INT(trip_tick, app.cfg.limits.debounce_trip);
    sim_hal_outputs(&duty, &en);
    TV_CHECK_NEAR(duty, 0.0, 0.0);
    TV_CHECK_EQ_INT(en, 0);
    TV_CHECK_NEAR(out.duty, 0.0, 0.0);
    TV_CHECK_EQ_INT(out.bridge_enable, 0);

    /* the wire comes back: the fault stays latched, the outputs stay safe */
    TV_CHECK_EQ_INT(sim_hal_release_adc(HAL_ADC_TPS1), TV_OK);
    for (k = 0; k < 200; ++k) {
        TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
        sim_hal_outputs(&duty, &en);
        if (en != 0 || duty != 0.0f || (out.faults & APP_FAULT_TPS1_RANGE) == 0u) {
            break;
        }
    }
    TV_CHECK_EQ_INT(k, 200);
    TV_CHECK((out.faults & APP_FAULT_TPS1_RANGE) != 0u);
    TV_CHECK_EQ_INT(en, 0);
}

static void test_driver_fault_trips_safe_state_at_once(void)
{
    static app_t app;
    app_output_t out;
    float duty = 1.0f;
    int en = 1;
    int k;
    configure_default(7u);
    init_app_sine(&app);
    for (k = 0; k < 50; ++k) {
        TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
    }
    sim_hal_set_driver_fault(1);
    TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
    TV_CHECK((out.faults & APP_FAULT_DRIVER) != 0u);
    sim_hal_outputs(&duty, &en);
    TV_CHECK_NEAR(duty, 0.0, 0.0);
    TV_CHECK_EQ_INT(en, 0);
    sim_hal_set_driver_fault(0);
    for (k = 0; k < 20; ++k) {
        TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
    }
    TV_CHECK((out.faults & APP_FAULT_DRIVER) != 0u); /* latched */
    sim_hal_outputs(NULL, &en);
    TV_CHECK_EQ_INT(en, 0);
}

static void test_failed_adc_read_forces_safe_outputs(void)
{
    static app_t app;
    app_output_t out;
    float duty = 1.0f;
    int en = 1;
    int k;
    configure_default(8u);
    init_app_sine(&app);
    for (k = 0; k < 30; ++k) {
        TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
    }
    sim_hal_fail_adc_reads(1u);
    TV_CHECK_EQ_INT(tick(&app, &out), TV_ERR_IO);
    sim_hal_outputs(&duty, &en);
    TV_CHECK_NEAR(duty, 0.0, 0.0);
    TV_CHECK_EQ_INT(en, 0);
    /* the next sample arrives 2 ms after the previous: one missing sample, predicted across */
    TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
    TV_CHECK_EQ_INT(out.missing_samples, 1);
    TV_CHECK_EQ_INT(out.faults, 0);
}

/* After a failed ADC read the period that had run with duty d must be predicted with d's voltage
 * (the bridge is opened only from then on): predicting it with the open bridge left a current
 * innovation of about 2.6 sigma on the next sample (issue 9). Averaged over 12 seeds at the crest
 * of the sine (|u| ~ 11 V), the normalised current innovation must look like noise: its mean
 * absolute value is 0.80 for a standard normal; 1.5 leaves room for 12 samples (its standard
 * error is 0.17) and is far below the 2.6 of the bias. */
static void test_missed_sample_predicts_the_period_that_ran_with_its_voltage(void)
{
    static app_t app;
    app_output_t out;
    double sum_abs = 0.0;
    uint64_t seed;
    int k;
    for (seed = 1u; seed <= 12u; ++seed) {
        configure_default(seed);
        init_app_sine(&app);
        for (k = 0; k < 249; ++k) { /* t = 0.249 s: sin(2 pi 5 t) = -1 at 0.25 s, the crest */
            TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
        }
        TV_CHECK(fabs((double)app.u_applied_V) > 10.0);
        sim_hal_fail_adc_reads(1u);
        TV_CHECK_EQ_INT(tick(&app, &out), TV_ERR_IO);
        TV_CHECK_EQ_INT(tick(&app, &out), TV_OK);
        TV_CHECK_EQ_INT(out.missing_samples, 1);
        TV_CHECK(out.innov.used[EKF_CH_CURRENT] != 0u);
        sum_abs += fabs((double)out.innov.innov[EKF_CH_CURRENT]) / sqrt((double)out.innov.innov_var[EKF_CH_CURRENT]);
    }
    printf("mean |current innovation| / sigma after a missed sample: %.2f (12 seeds)\n", sum_abs / 12.0);
    TV_CHECK(sum_abs / 12.0 < 1.5);
}

/* Tracking figures against a hand-computed synthetic step response: target 0 -> 1 rad at 0.1 s;
 * the angle jumps to 1.1 (10 % overshoot) for 100 samples (0.100 .. 0.199 s), then sits on 1.0
 * to 1.0 s. By sim_tracking.h's definitions: overshoot 10 %; band max(2 % of 1, 5 mrad) = 0.02,
 * last sample outside it 0.199 s, settling 0.099 s; steady-state error 0; RMS error over the 1001
 * samples with a target: sqrt(100 x 0.1^2 / 1001). A ramp afterwards ends the step and adds only
 * to the RMS. */
static void test_tracking_figures_of_a_synthetic_step(void)
{
    static sim_tracking_t tk;
    int k;
    sim_tracking_init(&tk);
    for (k = 0; k <= 1000; ++k) {
        const double t = k * 1e-3;
        const double target = k < 100 ? 0.0 : 1.0;
        const double angle = k < 100 ? 0.0 : (k < 200 ? 1.1 : 1.0);
        sim_tracking_add(&tk, t, target, angle);
    }
    sim_tracking_finish(&tk);
    TV_CHECK_EQ_INT(tk.n_steps, 1);
    TV_CHECK_NEAR(tk.step[0].t_step_s, 0.1, 1e-12);
    TV_CHECK_NEAR(tk.step[0].overshoot_pct, 10.0, 1e-9);
    TV_CHECK_NEAR(tk.step[0].settling_s, 0.099, 1e-12);
    TV_CHECK_NEAR(tk.step[0].settled, 1.0, 0.0);
    TV_CHECK_NEAR(tk.step[0].ss_error_rad, 0.0, 1e-15);
    TV_CHECK_NEAR(tk.rms_error_rad, sqrt(100.0 * 0.01 / 1001.0), 1e-12);
    /* open loop (no target): nothing */
    sim_tracking_init(&tk);
    sim_tracking_add(&tk, 0.0, (double)NAN, 0.3);
    sim_tracking_finish(&tk);
    TV_CHECK_EQ_INT(tk.n_steps, 0);
    TV_CHECK_EQ_INT(tk.n, 0);
}

/* ------------------------------------------------------------------------------------------ */
/* simulation core                                                                             */
/* ------------------------------------------------------------------------------------------ */

static void test_short_default_scenario_runs_clean_with_finite_metrics(void)
{
    sim_options_t o;
    sim_result_t r;
    int e;
    sim_options_default(&o);
    o.duration_s = 0.6;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_OK);
    TV_CHECK_EQ_INT(r.scenario, SIM_SCN_PAPER_SINE);
    TV_CHECK_EQ_INT(r.n_ticks, 600);
    TV_CHECK_EQ_INT(r.n_scored, 400); /* t >= SIM_TRANSIENT_S = 0.2 s */
    TV_CHECK_EQ_INT(r.faults, 0);
    TV_CHECK_EQ_INT(r.fault_ticks, 0);
    TV_CHECK_EQ_INT(r.ekf_rejections, 0);
    TV_CHECK_EQ_INT(r.missing_samples, 0);
    TV_CHECK_EQ_INT(r.hal_errors, 0);
    for (e = 0; e < (int)SIM_EST_COUNT; ++e) {
        TV_CHECK(all_finite3(r.rmse[e]));
    }
    TV_CHECK(isfinite(r.nees_avg) && isfinite(r.nis_avg));
    TV_CHECK(r.nees_lo < 3.0 && r.nees_hi > 3.0); /* the band of an average of chi2(3) holds 3 */
    TV_CHECK_NEAR(r.nis_dof_avg, 2.0, 0.0);      /* current + angle set-up */
    /* Sanity, not accuracy: the measured angle's error is the sensor's (noise 1e-4 rad and
     * 12-bit quantisation 4.5e-4 rad / sqrt(12)), so its RMSE is ~1.7e-4 rad; within 2x. */
    TV_CHECK_LE(r.rmse[SIM_EST_MEASURED][2], 3.4e-4);
    TV_CHECK(r.rmse[SIM_EST_MEASURED][2] > 0.85e-4);
    /* and the measured current's RMSE is the 0.01 A noise (+ 8 mA/count quantisation) */
    TV_CHECK_NEAR(r.rmse[SIM_EST_MEASURED][0], 0.0104, 0.002);
    /* the application filter tracks: angle error below the measurement's */
    TV_CHECK_LE(r.rmse[SIM_EST_APP][2], r.rmse[SIM_EST_MEASURED][2]);
}

static void test_same_seed_reproduces_identical_metrics(void)
{
    sim_options_t o;
    sim_result_t a;
    sim_result_t b;
    sim_result_t c;
    sim_options_default(&o);
    o.duration_s = 0.4;
    o.seed = 42u;
    TV_CHECK_EQ_INT(sim_run(&o, &a), TV_OK);
    TV_CHECK_EQ_INT(sim_run(&o, &b), TV_OK);
    /* bit-identical: same seed, same code path, no uninitialised state */
    TV_CHECK(memcmp(a.rmse, b.rmse, sizeof a.rmse) == 0);
    TV_CHECK(memcmp(&a.nees_avg, &b.nees_avg, sizeof a.nees_avg) == 0);
    TV_CHECK(memcmp(&a.nis_avg, &b.nis_avg, sizeof a.nis_avg) == 0);
    TV_CHECK(memcmp(a.meas_bias, b.meas_bias, sizeof a.meas_bias) == 0);
    o.seed = 43u;
    TV_CHECK_EQ_INT(sim_run(&o, &c), TV_OK);
    TV_CHECK(c.rmse[SIM_EST_APP][1] != a.rmse[SIM_EST_APP][1]); /* another seed, other noise */
}

static void test_drive_targets(void)
{
    /* the driving cycle's pedal positions, worked out by hand from the table (0.15, 0.45, ...,
     * 0.75 rad, one per second, ramps at 3 rad/s) */
    TV_CHECK_NEAR(sim_target_rad(SIM_SCN_DRIVE, 0.0), 0.15, 1e-12);
    TV_CHECK_NEAR(sim_target_rad(SIM_SCN_DRIVE, 0.5), 0.15, 1e-12);
    TV_CHECK_NEAR(sim_target_rad(SIM_SCN_DRIVE, 1.05), 0.30, 1e-9);  /* 0.15 + 3 * 0.05 */
    TV_CHECK_NEAR(sim_target_rad(SIM_SCN_DRIVE, 1.2), 0.45, 1e-12);  /* reached after 0.1 s */
    TV_CHECK_NEAR(sim_target_rad(SIM_SCN_DRIVE, 5.2), 0.80, 1e-9);   /* 0.20 -> 1.20: 0.20 + 3 * 0.2 */
    TV_CHECK_NEAR(sim_target_rad(SIM_SCN_DRIVE, 6.1), 0.90, 1e-9);   /* 1.20 -> 0.60 descending: 1.20 - 0.3 */
    TV_CHECK_NEAR(sim_target_rad(SIM_SCN_DRIVE, 9.9), 0.75, 1e-12);
    TV_CHECK_NEAR(sim_target_rad(SIM_SCN_DRIVE, 10.1), 0.45, 1e-9);  /* repeating: 0.75 -> 0.15 */
}

static void test_all_scenarios_run(void)
{
    int s;
    for (s = 0; s < (int)SIM_SCN_COUNT; ++s) {
        sim_options_t o;
        sim_result_t r;
        sim_scenario_t back;
        sim_options_default(&o);
        o.scenario = (sim_scenario_t)s;
        TV_CHECK_EQ_INT(sim_scenario_from_name(sim_scenario_name(o.scenario), &back), TV_OK);
        TV_CHECK_EQ_INT(back, s);
        TV_CHECK_EQ_INT(sim_run(&o, &r), TV_OK);
        TV_CHECK_EQ_INT(r.faults, 0);
        TV_CHECK_EQ_INT(r.ekf_rejections, 0);
        TV_CHECK(all_finite3(r.rmse[SIM_EST_APP]));
        TV_CHECK_NEAR(r.duration_s, sim_scenario_duration_s(o.scenario), 1e-9);
    }
}

static void test_stuck_plate_stays_at_rest_with_the_bridge_off(void)
{
    /* stuck_release for 0.45 s: before the pulse the plate must not move (stiction holds). */
    sim_options_t o;
    sim_result_t r;
    plant_state_t s;
    sim_options_default(&o);
    o.scenario = SIM_SCN_STUCK_RELEASE;
    o.duration_s = 0.45;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_OK);
    TV_CHECK_EQ_INT(sim_hal_truth(&s), TV_OK);
    TV_CHECK_NEAR(s.angle_rad, 0.5, 0.0);
    TV_CHECK_NEAR(s.velocity_rad_s, 0.0, 0.0);
    /* the estimator holds still too: velocity RMSE far below one differentiated count
     * (4.5e-4 rad / 1 ms = 0.45 rad/s) */
    TV_CHECK_LE(r.rmse[SIM_EST_APP][1], 0.05);
}

static void test_missing_samples_are_counted(void)
{
    sim_options_t o;
    sim_result_t r;
    sim_options_default(&o);
    o.duration_s = 0.5;
    o.drop_tick_every = 10u;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_OK);
    /* ticks 9, 19, ..., 499 dropped (50); the gap after the last one is never seen: 49 */
    TV_CHECK_EQ_INT(r.n_ticks, 450);
    TV_CHECK_EQ_INT(r.missing_samples, 49);
    TV_CHECK_EQ_INT(r.faults, 0);
    o.drop_tick_every = 1u; /* would drop every tick */
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_RANGE);
}

/* What test_warmup_precedes_the_scenario_and_its_scoring records of each row. */
typedef struct {
    double phi_min_warm;
    double phi_max_warm;
    int targets_warm;  /* rows with a target (closed loop) during the warm-up */
    int targets_after; /* rows with a target after it */
    double last_target;
    double last_phi;
} trace_t;

static void trace_row(const sim_row_t *row, void *user)
{
    trace_t *t = (trace_t *)user;
    const int has_target = isfinite(row->target_rad);
    if (row->t_s < 1.0 - 1e-9) {
        if (row->truth[2] < t->phi_min_warm) {
            t->phi_min_warm = row->truth[2];
        }
        if (row->truth[2] > t->phi_max_warm) {
            t->phi_max_warm = row->truth[2];
        }
        t->targets_warm += has_target;
    } else {
        t->targets_after += has_target;
        t->last_target = row->target_rad;
        t->last_phi = row->truth[2];
    }
}

static void test_options_are_validated(void)
{
    sim_options_t o;
    sim_result_t r;
    sim_options_default(&o);
    o.duration_s = -1.0;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_RANGE);
    o.duration_s = TEST_NAN;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_NONFINITE);
    sim_options_default(&o);
    o.scenario = SIM_SCN_COUNT;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_RANGE);
    sim_options_default(&o);
    o.q_override = 1;
    o.qu_V2_s = -1.0;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_RANGE);
    TV_CHECK_EQ_INT(sim_run(NULL, &r), TV_ERR_NULL);
    TV_CHECK_EQ_INT(sim_scenario_from_name("nope", &o.scenario), TV_ERR_RANGE);
    /* warm-up: finite, within its bound, not before a scenario that sets the plate's state */
    sim_options_default(&o);
    o.warmup_s = TEST_NAN;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_NONFINITE);
    o.warmup_s = -0.1;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_RANGE);
    o.warmup_s = SIM_WARMUP_MAX_S + 1.0;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_RANGE);
    o.warmup_s = 1.0;
    o.scenario = SIM_SCN_STUCK_RELEASE;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_RANGE);
    o.scenario = SIM_SCN_STOP_LEARN;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_ERR_RANGE);
}

/* A warm-up runs the warm-up excitation first (6 V, 1 Hz: the plate moves), then the scenario
 * from its own time 0, scored from SIM_TRANSIENT_S after the warm-up; the scenario part is the
 * same closed-loop steps (the first target is held after the warm-up's end). */
static void test_warmup_precedes_the_scenario_and_its_scoring(void)
{
    sim_options_t o;
    sim_result_t r;
    trace_t tr;
    sim_options_default(&o);
    o.scenario = SIM_SCN_CLOSED_STEPS;
    o.duration_s = 0.45; /* the first target holds for 0.5 s */
    o.warmup_s = 1.0;
    memset(&tr, 0, sizeof tr);
    o.row_fn = trace_row;
    o.row_user = &tr;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_OK);
    TV_CHECK_EQ_INT(r.n_ticks, 1450);
    TV_CHECK_EQ_INT(r.n_scored, 250); /* scenario time >= 0.2 s */
    TV_CHECK_EQ_INT(r.faults, 0);
    /* warm-up: open loop (no target), the plate swept over more than 0.3 rad */
    TV_CHECK(tr.phi_max_warm - tr.phi_min_warm > 0.3);
    TV_CHECK_EQ_INT(tr.targets_warm, 0);
    /* after it: the closed loop on the scenario's first target (0.2 rad), reached */
    TV_CHECK_EQ_INT(tr.targets_after, 450);
    TV_CHECK_NEAR(tr.last_target, 0.2, 1e-7); /* stored as tv_real_t */
    TV_CHECK_NEAR(tr.last_phi, 0.2, 0.02);
}

static void test_chi2_quantile_matches_tables(void)
{
    /* normal quantile: Acklam + one Halley step is accurate to ~1e-12 */
    TV_CHECK_NEAR(sim_normal_quantile(0.975), 1.959963984540054, 1e-9);
    TV_CHECK_NEAR(sim_normal_quantile(0.025), -1.959963984540054, 1e-9);
    TV_CHECK_NEAR(sim_normal_quantile(0.5), 0.0, 1e-12);
    TV_CHECK(isnan(sim_normal_quantile(0.0)));
    /* Wilson-Hilferty against tabulated chi-square quantiles: relative error < 1e-4 for
     * d = 300 (table: 253.912, 349.874), < 5e-3 for d = 3 at the upper tail (9.348) */
    TV_CHECK_NEAR(sim_chi2_quantile(0.025, 300.0), 253.912, 253.912 * 1e-4);
    TV_CHECK_NEAR(sim_chi2_quantile(0.975, 300.0), 349.874, 349.874 * 1e-4);
    TV_CHECK_NEAR(sim_chi2_quantile(0.975, 3.0), 9.348, 9.348 * 5e-3);
    /* d = 3 lower tail: WH gives 0.18 vs 0.216 (documented) */
    TV_CHECK_NEAR(sim_chi2_quantile(0.025, 3.0), 0.216, 0.04);
    TV_CHECK(isnan(sim_chi2_quantile(0.5, 0.0)));
}

static void test_monte_carlo_aggregates_the_runs(void)
{
    sim_options_t o;
    sim_mc_result_t m;
    sim_result_t r;
    double mean_w = 0.0;
    uint32_t s;
    sim_options_default(&o);
    o.duration_s = 0.4;
    o.seed = 100u;
    TV_CHECK_EQ_INT(sim_monte_carlo(&o, 3u, NULL, NULL, &m), TV_OK);
    for (s = 0; s < 3u; ++s) {
        o.seed = 100u + s;
        TV_CHECK_EQ_INT(sim_run(&o, &r), TV_OK);
        mean_w += r.rmse[SIM_EST_APP][1] / 3.0;
    }
    /* the same runs: the mean agrees to rounding of the summation order */
    TV_CHECK_NEAR(m.rmse_mean[SIM_EST_APP][1], mean_w, 1e-12 * (1.0 + mean_w));
    TV_CHECK_EQ_INT(m.n_seeds, 3);
    TV_CHECK_EQ_INT(m.n_ticks_scored, 200);
    TV_CHECK(isfinite(m.anees) && m.anees > 0.0);
    TV_CHECK(m.band_lo < 3.0 && m.band_hi > 3.0);
    /* the band of a 3-run average: chi2(9)/3 quantiles, 2.70/3 and 19.02/3 (tables) */
    TV_CHECK_NEAR(m.band_hi, 19.023 / 3.0, 0.05);
    TV_CHECK(m.frac_ticks_in_band >= 0.0 && m.frac_ticks_in_band <= 1.0);
    TV_CHECK_EQ_INT(sim_monte_carlo(&o, 0u, NULL, NULL, &m), TV_ERR_RANGE);
}

int main(void)
{
    TV_TEST_RUN(test_hal_rejects_bad_duty_and_zeroes_the_output);
    TV_TEST_RUN(test_hal_duty_drives_the_plant);
    TV_TEST_RUN(test_can_loopback_is_fifo_and_overflow_is_counted);
    TV_TEST_RUN(test_time_is_monotonic_and_adc_is_stamped_with_plant_time);
    TV_TEST_RUN(test_forced_adc_channel_reads_the_forced_counts);
    TV_TEST_RUN(test_tps1_open_circuit_trips_safe_state_within_debounce_and_latches);
    TV_TEST_RUN(test_driver_fault_trips_safe_state_at_once);
    TV_TEST_RUN(test_failed_adc_read_forces_safe_outputs);
    TV_TEST_RUN(test_missed_sample_predicts_the_period_that_ran_with_its_voltage);
    TV_TEST_RUN(test_tracking_figures_of_a_synthetic_step);
    TV_TEST_RUN(test_short_default_scenario_runs_clean_with_finite_metrics);
    TV_TEST_RUN(test_same_seed_reproduces_identical_metrics);
    TV_TEST_RUN(test_drive_targets);
    TV_TEST_RUN(test_all_scenarios_run);
    TV_TEST_RUN(test_stuck_plate_stays_at_rest_with_the_bridge_off);
    TV_TEST_RUN(test_missing_samples_are_counted);
    TV_TEST_RUN(test_options_are_validated);
    TV_TEST_RUN(test_warmup_precedes_the_scenario_and_its_scoring);
    TV_TEST_RUN(test_chi2_quantile_matches_tables);
    TV_TEST_RUN(test_monte_carlo_aggregates_the_runs);
    return tv_test_summary();
}
