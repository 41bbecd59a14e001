/**
 * @file test_stop_track.c
 * @brief Online stop tracking (firmware/app/stop_track.h): the configuration validated; on rest
 *        angles written from the contact law with pow() (not the code under test) the tracked
 *        onset converges to the true one at either stop; no update from a moving plate, a small
 *        push, an abandoned block or a stop beyond the window (refused and counted); in the
 *        application over the simulated plant, the onsets move only inside their window, and the
 *        start-up routine's result becomes the new reference.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "plant_draw.h"
#include "sim.h"
#include "sim_unit.h"
#include "stop_track.h"
#include "tv_status.h"
#include "tv_test.h"
#include "hc_law_model.h"

/* a literal or a double in the build's real type */
#define R(x) ((tv_real_t)(x))

/* A model with a learned Hunt-Crossley law (k = 5,000 N m/rad^1.25, e = 1.25). */
static tvm_params_t law_model(void) { return hc_law_model(5000.0, 1.25); }

/* The current that makes the net torque into stop `side` (+1 open, -1 closed) equal push_Nm at
 * angle phi, from the model's springs written out here. */
static double current_for_push(const tvm_params_t *p, int side, double phi, double push_Nm)
{
    const double e = (double)p->e_phi_rad;
    const double springs = (double)p->M0_Nm * phi / sqrt(phi * phi + e * e) + (double)p->c_Nm_rad * phi;
    return ((double)side * push_Nm + springs) / ((double)p->n_gear * (double)p->Kt_Nm_A);
}

/* Feed n_blocks rest blocks at stop `side` whose true onset is onset_true, under push_Nm; the
 * angle carries a +-0.2 mrad alternating ripple (inside the rest band). Returns the blocks that
 * moved an onset. */
static int feed(st_t *t, const tvm_params_t *p, int side, double onset_true, double push_Nm, int n_blocks)
{
    const double pen = pow(push_Nm / (double)p->k_stop_Nm_rad, 1.0 / (double)p->stop_exponent);
    const double phi = onset_true + (double)side * pen;
    const double i = current_for_push(p, side, phi, push_Nm);
    int moved = 0;
    int k;
    for (k = 0; k < n_blocks * (int)t->cfg.block; ++k) {
        moved += st_step(t, p, R(phi + ((k % 2) != 0 ? 2e-4 : -2e-4)), 1, R(i), R(0.01));
    }
    return moved;
}

static void test_configuration_is_validated(void)
{
    st_config_t c;
    st_t t;
    st_config_default(&c);
    TV_CHECK_EQ_INT(st_config_check(&c), TV_OK);
    TV_CHECK_EQ_INT(st_config_check(NULL), TV_ERR_NULL);
    c.block = 10u;
    TV_CHECK_EQ_INT(st_config_check(&c), TV_ERR_CONFIG);
    st_config_default(&c);
    c.gain = R(0.0);
    TV_CHECK_EQ_INT(st_config_check(&c), TV_ERR_CONFIG);
    c.gain = R(1.5);
    TV_CHECK_EQ_INT(st_config_check(&c), TV_ERR_CONFIG);
    st_config_default(&c);
    c.push_max_Nm = c.push_min_Nm;
    TV_CHECK_EQ_INT(st_config_check(&c), TV_ERR_CONFIG);
    st_config_default(&c);
    c.window_rad = (tv_real_t)NAN;
    TV_CHECK_EQ_INT(st_config_check(&c), TV_ERR_NONFINITE);
    st_config_default(&c);
    c.enable = 2u;
    TV_CHECK_EQ_INT(st_config_check(&c), TV_ERR_CONFIG);
    st_config_default(&c);
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(0.01), R(1.3)), TV_ERR_CONFIG); /* closed must be below limp-home */
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.1), (tv_real_t)INFINITY), TV_ERR_NONFINITE);
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.1), R(1.3)), TV_OK);
    TV_CHECK(t.onset[ST_CLOSED] == (tv_real_t)-0.1 && t.onset[ST_OPEN] == (tv_real_t)1.3);
}

static void test_onsets_converge_to_the_true_ones(void)
{
    const tvm_params_t p = law_model();
    st_config_t c;
    st_t t;
    int moved;
    st_config_default(&c);
    c.envelope = 0u; /* learned stops: the envelope of unlearned ones is off */
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.100), R(1.366)), TV_OK);
    /* the open stop 3 mrad farther out than its reference, pressed with 1 N m */
    moved = feed(&t, &p, +1, 1.369, 1.0, 40);
    printf("  open stop: reference 1.36600, true 1.36900, tracked %.5f after %d blocks\n", (double)t.onset[ST_OPEN], moved);
    TV_CHECK_EQ_INT(moved, 40);
    TV_CHECK_NEAR(t.onset[ST_OPEN], 1.369, TV_REAL_IS_DOUBLE ? 1e-5 : 2e-5);
    TV_CHECK(t.onset[ST_CLOSED] == (tv_real_t)-0.100);
    /* the closed stop 2 mrad higher (a deposit on the seat), pressed with 0.5 N m */
    moved = feed(&t, &p, -1, -0.098, 0.5, 40);
    printf("  closed stop: reference -0.10000, true -0.09800, tracked %.5f after %d blocks\n", (double)t.onset[ST_CLOSED], moved);
    TV_CHECK_EQ_INT(moved, 40);
    TV_CHECK_NEAR(t.onset[ST_CLOSED], -0.098, TV_REAL_IS_DOUBLE ? 1e-5 : 2e-5);
    TV_CHECK_EQ_INT((int)t.n_accepted, 80);
    TV_CHECK_EQ_INT((int)t.n_refused, 0);
}

static void test_no_update_without_a_resting_pressed_plate(void)
{
    const tvm_params_t p = law_model();
    st_config_t c;
    st_t t;
    int k;
    int moved = 0;
    st_config_default(&c);
    c.envelope = 0u; /* learned stops: the envelope of unlearned ones is off */
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.100), R(1.366)), TV_OK);
    /* a push below push_min_Nm */
    TV_CHECK_EQ_INT(feed(&t, &p, +1, 1.369, 0.1, 10), 0);
    /* a plate creeping 3 mrad per block (outside the rest band) */
    for (k = 0; k < 10 * (int)c.block; ++k) {
        const double phi = 1.367 + 3e-3 * (double)k / (double)c.block;
        moved += st_step(&t, &p, R(phi), 1, R(current_for_push(&p, +1, phi, 1.0)), R(0.03));
    }
    TV_CHECK_EQ_INT(moved, 0);
    /* the estimate says it moves fast (beyond the sanity bound; a jitter of +-1 rad/s against
     * the stop is accepted: the angle range is the rest test) */
    for (k = 0; k < 10 * (int)c.block; ++k) {
        moved += st_step(&t, &p, R(1.3675), 1, R(current_for_push(&p, +1, 1.3675, 1.0)), c.w_rest_rad_s * R(1.2));
    }
    TV_CHECK_EQ_INT(moved, 0);
    /* a block with one invalid angle is abandoned: 99 + 1 invalid + 99 samples move nothing */
    for (k = 0; k < 199; ++k) {
        moved += st_step(&t, &p, R(1.3675), k != 99, R(current_for_push(&p, +1, 1.3675, 1.0)), R(0.0));
    }
    TV_CHECK_EQ_INT(moved, 0);
    /* far from both stops (mid-travel, held by the motor against the springs) */
    TV_CHECK_EQ_INT(feed(&t, &p, +1, 0.6, 1.0, 5), 0);
    TV_CHECK_EQ_INT((int)t.n_accepted, 0);
    TV_CHECK(t.onset[ST_OPEN] == (tv_real_t)1.366);
    /* disabled: nothing either */
    c.enable = 0u;
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.100), R(1.366)), TV_OK);
    TV_CHECK_EQ_INT(feed(&t, &p, +1, 1.369, 1.0, 5), 0);
}

static void test_a_stop_beyond_the_window_is_refused(void)
{
    const tvm_params_t p = law_model();
    st_config_t c;
    st_t t;
    st_config_default(&c);
    c.envelope = 0u; /* learned stops: the envelope of unlearned ones is off */
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.100), R(1.366)), TV_OK);
    /* 8 mrad beyond the reference, window 5 mrad */
    TV_CHECK_EQ_INT(feed(&t, &p, +1, 1.374, 1.0, 10), 0);
    TV_CHECK_EQ_INT((int)t.n_refused, 10);
    TV_CHECK(t.onset[ST_OPEN] == (tv_real_t)1.366);
}

/* In the application: the nominal unit in open_steps (0.5 s against each stop at 10 V, the
 * filter on the default Kelvin-Voigt law the plant does not have): blocks are accepted and the
 * onsets stay inside their window; after the start-up routine, the learned onsets are the
 * reference. */
static void test_in_the_application(void)
{
    sim_options_t o;
    sim_result_t r;
    tvm_params_t d;
    tvm_params_default(&d);
    sim_options_default(&o);
    o.scenario = SIM_SCN_OPEN_STEPS;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_OK);
    printf("  open_steps: %lu blocks accepted, %lu refused; onsets %.5f / %.5f rad (model %.5f / %.5f)\n",
           (unsigned long)r.stop_track_accepted, (unsigned long)r.stop_track_refused, r.stop_onset_rad[0],
           r.stop_onset_rad[1], (double)d.phi_closed_rad, (double)d.phi_open_rad);
    TV_CHECK(r.stop_track_accepted >= 10u);
    TV_CHECK(fabs(r.stop_onset_rad[0] - (double)d.phi_closed_rad) <= 0.005 + 1e-9);
    TV_CHECK(fabs(r.stop_onset_rad[1] - (double)d.phi_open_rad) <= 0.005 + 1e-9);
    TV_CHECK(r.stop_onset_rad[0] != (double)d.phi_closed_rad || r.stop_onset_rad[1] != (double)d.phi_open_rad);
    /* app_set_stops(): a new reference, tracked = reference */
    {
        static app_t app;
        app_config_t cfg;
        app_config_default(&cfg);
        TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
        TV_CHECK_EQ_INT(app_set_stops(&app, R(-0.12), R(1.40)), TV_OK);
        TV_CHECK(app.st.ref[ST_CLOSED] == (tv_real_t)-0.12 && app.st.onset[ST_OPEN] == (tv_real_t)1.40);
        cfg.stop_track.gain = R(0.0);
        TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_ERR_CONFIG);
    }
}

/* The stop envelope (stops never learned), worked by hand: env_min_rad 1 mrad. */
static void test_envelope_of_unlearned_stops(void)
{
    const tvm_params_t p = law_model();
    st_config_t c;
    st_t t;
    st_config_default(&c);
    TV_CHECK_EQ_INT((int)c.envelope, 1); /* on by default: the class's stops are not the unit's */
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.100), R(1.366)), TV_OK);
    TV_CHECK_EQ_INT(st_model_in_doubt(&t), 0); /* nothing seen yet */
    /* measured 5 mrad beyond the open onset, the prediction held at the onset, a 2 mrad step:
     * the onset goes to 1.371 + 0.002 + 0.001 = 1.374 */
    TV_CHECK_EQ_INT(st_envelope(&t, R(1.371), R(1.366), R(0.002)), 1);
    TV_CHECK_NEAR(t.onset[ST_OPEN], 1.374, 1e-6);
    TV_CHECK_NEAR(t.ref[ST_OPEN], 1.374, 1e-6);
    /* 8 mrad from where it started, more than window_rad (5 mrad): the model's stops are in doubt */
    TV_CHECK_EQ_INT(st_model_in_doubt(&t), 1);
    TV_CHECK(t.onset[ST_CLOSED] == (tv_real_t)-0.100);
    /* the closed stop: measured -0.120, predicted -0.101, step -1 mrad: -0.120 - 0.001 - 0.001 */
    TV_CHECK_EQ_INT(st_envelope(&t, R(-0.120), R(-0.101), R(-0.001)), 1);
    TV_CHECK_NEAR(t.onset[ST_CLOSED], -0.122, 1e-6);
    TV_CHECK_EQ_INT((int)t.n_envelope, 2);
    /* a penetration the model predicted (measured within 1 mrad of the prediction): no move */
    TV_CHECK_EQ_INT(st_envelope(&t, R(1.378), R(1.3775), R(0.0)), 0);
    /* beyond the prediction but not 1 mrad beyond the onset: no move */
    TV_CHECK_EQ_INT(st_envelope(&t, R(1.3745), R(1.370), R(0.0)), 0);
    /* inward (the plate short of the onset, the prediction beyond it): never moves inward */
    TV_CHECK_EQ_INT(st_envelope(&t, R(1.360), R(1.380), R(0.0)), 0);
    TV_CHECK_NEAR(t.onset[ST_OPEN], 1.374, 1e-6);
    TV_CHECK_EQ_INT(st_envelope(&t, (tv_real_t)NAN, R(1.37), R(0.0)), 0);
    /* unlearned stops may lie farther than window_rad: a rest block 8 mrad beyond the reference is
     * accepted (the learned-stop case refuses it: test_a_stop_beyond_the_window_is_refused), and
     * so is one whose velocity estimate is biased (0.8 rad/s at rest) */
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.100), R(1.366)), TV_OK);
    TV_CHECK_EQ_INT(feed(&t, &p, +1, 1.374, 1.0, 10), 10);
    TV_CHECK_EQ_INT((int)t.n_refused, 0);
    TV_CHECK(t.onset[ST_OPEN] > (tv_real_t)1.366 + R(0.005));
    {
        int k;
        int moved = 0;
        for (k = 0; k < (int)c.block; ++k) {
            moved += st_step(&t, &p, R(1.3675), 1, R(current_for_push(&p, +1, 1.3675, 1.0)), R(0.8));
        }
        TV_CHECK_EQ_INT(moved, 1);
    }
    /* a move of 3 mrad is no doubt (within window_rad) */
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.100), R(1.366)), TV_OK);
    TV_CHECK_EQ_INT(st_envelope(&t, R(1.3675), R(1.366), R(0.0005)), 1); /* 1.3675 + 0.0005 + 0.001 = 1.369 */
    TV_CHECK_NEAR(t.onset[ST_OPEN], 1.369, 1e-6);
    TV_CHECK_EQ_INT(st_model_in_doubt(&t), 0);
    TV_CHECK_EQ_INT(st_model_in_doubt(NULL), 0);
    /* off: nothing, and never in doubt (the stops are learned) */
    c.envelope = 0u;
    TV_CHECK_EQ_INT(st_reset(&t, &c, R(-0.100), R(1.366)), TV_OK);
    TV_CHECK_EQ_INT(st_envelope(&t, R(1.371), R(1.366), R(0.002)), 0);
    TV_CHECK(t.onset[ST_OPEN] == (tv_real_t)1.366);
    t.onset[ST_OPEN] = R(1.40);
    TV_CHECK_EQ_INT(st_model_in_doubt(&t), 0);
    c.env_min_rad = R(0.0);
    TV_CHECK_EQ_INT(st_config_check(&c), TV_ERR_CONFIG);
    st_config_default(&c);
    c.env_window_rad = (tv_real_t)NAN;
    TV_CHECK_EQ_INT(st_config_check(&c), TV_ERR_NONFINITE);
}

/* In the application, stops never learned: unit 1005 (class a, stops spread) has its stops 49 and
 * 112 mrad beyond the class's; in open_steps the envelope and the unlearned rest blocks bring both
 * onsets within 10 mrad of the plant's, where they stay put without it. app_set_stops() (stored
 * or learned stops) turns the envelope off. */
static void test_unlearned_stops_in_the_application(void)
{
    static plant_config_t pc;
    static app_config_t ac;
    sim_options_t o;
    sim_result_t r;
    TV_CHECK_EQ_INT(plant_draw(PLANT_CLASS_A, PLANT_SPREAD_STOPS, 1005u, &pc), TV_OK);
    TV_CHECK_EQ_INT(sim_app_config_for_unit(PLANT_CLASS_A, &pc, &ac), TV_OK);
    sim_options_default(&o);
    o.scenario = SIM_SCN_OPEN_STEPS;
    o.plant = &pc;
    o.app = &ac;
    TV_CHECK_EQ_INT(sim_run(&o, &r), TV_OK);
    printf("  unit 1005 unlearned: onsets %.4f / %.4f rad, plant %.4f / %.4f; velocity RMSE %.3f rad/s (differentiation %.3f)\n",
           r.stop_onset_rad[0], r.stop_onset_rad[1], pc.phi_closed_rad, pc.phi_open_rad, r.rmse[SIM_EST_APP][TVM_W],
           r.rmse[SIM_EST_MEASURED][TVM_W]);
    TV_CHECK(fabs(r.stop_onset_rad[0] - pc.phi_closed_rad) <= 0.010);
    TV_CHECK(fabs(r.stop_onset_rad[1] - pc.phi_open_rad) <= 0.010);
    {
        sim_result_t off;
        ac.stop_track.envelope = 0u;
        TV_CHECK_EQ_INT(sim_run(&o, &off), TV_OK);
        printf("  without the envelope: onsets %.4f / %.4f rad; velocity RMSE %.3f rad/s\n", off.stop_onset_rad[0],
               off.stop_onset_rad[1], off.rmse[SIM_EST_APP][TVM_W]);
        TV_CHECK(fabs(off.stop_onset_rad[1] - pc.phi_open_rad) > 0.05);
        TV_CHECK(r.rmse[SIM_EST_APP][TVM_W] < off.rmse[SIM_EST_APP][TVM_W]);
    }
    {
        static app_t app;
        app_config_t cfg;
        app_config_default(&cfg);
        TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
        TV_CHECK_EQ_INT((int)app.st.cfg.envelope, 1);
        TV_CHECK_EQ_INT(app_set_stops(&app, R(-0.12), R(1.40)), TV_OK);
        TV_CHECK_EQ_INT((int)app.st.cfg.envelope, 0);
    }
}

int main(void)
{
    printf("online stop tracking (%s)\n", TV_REAL_IS_DOUBLE ? "double" : "float");
    TV_TEST_RUN(test_configuration_is_validated);
    TV_TEST_RUN(test_onsets_converge_to_the_true_ones);
    TV_TEST_RUN(test_no_update_without_a_resting_pressed_plate);
    TV_TEST_RUN(test_a_stop_beyond_the_window_is_refused);
    TV_TEST_RUN(test_in_the_application);
    TV_TEST_RUN(test_envelope_of_unlearned_stops);
    TV_TEST_RUN(test_unlearned_stops_in_the_application);
    return tv_test_summary();
}
