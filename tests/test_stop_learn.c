/**
 * @file test_stop_learn.c
 * @brief Start-up stop learning (firmware/app/stop_learn.h): the routine's rules on scripted
 *        angles (result, timeout, implausible results rejected, bad input), the non-volatile
 *        record (CRC-32 against its published check value, corruption rejected), app_set_stops()
 *        validation, and the routine through the application against population plants (angles
 *        within 5 mrad of the plant's own stops, never into a stop faster than 1 rad/s).
 */
#include <math.h>
#include <string.h>

#include "app.h"
#include "plant_draw.h"
#include "sim.h"
#include "sim_unit.h"
#include "stop_learn.h"
#include "tv_status.h"
#include "tv_test.h"

/* Feed a constant angle while the phase is `phase` (at most n samples); returns the voltage of
 * largest magnitude seen. */
static double feed_const(sl_t *sl, double phi, unsigned n, sl_phase_t phase)
{
    double u_big = 0.0;
    unsigned k;
    for (k = 0; k < n && sl->phase == phase; ++k) {
        const double u = (double)sl_step(sl, (tv_real_t)phi);
        if (fabs(u) > fabs(u_big)) {
            u_big = u;
        }
    }
    return u_big;
}

static void test_config_is_validated(void)
{
    sl_config_t c;
    tvm_params_t p;
    sl_t sl;
    sl_config_default(&c);
    tvm_params_default(&p);
    TV_CHECK_EQ_INT(sl_start(NULL, &c, &p), TV_ERR_NULL);
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_OK);
    TV_CHECK_EQ_INT(sl.phase, SL_CLOSED);
    c.approach_rad_s = TV_R(1.5); /* the routine never approaches faster than 1 rad/s */
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_ERR_CONFIG);
    sl_config_default(&c);
    c.block_ms = 5u;
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_ERR_CONFIG);
    sl_config_default(&c);
    c.push_V = (tv_real_t)NAN;
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_ERR_CONFIG);
    sl_config_default(&c);
    c.closed_min_rad = c.closed_max_rad;
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_ERR_CONFIG);
    sl_config_default(&c);
    p.R_ohm = TV_R(-1.0);
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_ERR_CONFIG);
}

static void test_scripted_stops_are_learned(void)
{
    /* The plate "rests" at -0.0873 rad, then at 1.4211 rad: the routine pushes with the full
     * voltage toward each stop, lowers to the hold voltage, and learns exactly those angles. */
    sl_config_t c;
    tvm_params_t p;
    sl_t sl;
    double u;
    const double closed = -0.0873;
    const double open = 1.4211;
    sl_config_default(&c);
    tvm_params_default(&p);
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_OK);
    /* the integral builds the push up to push_V; a full still block, a settling block, a
     * measuring block: about 1 s */
    u = feed_const(&sl, closed, 3000u, SL_CLOSED);
    /* toward the closed stop; the levels and their preload push harder than the seek's push_V,
     * never beyond level_V_max */
    TV_CHECK(u < -(double)c.push_V && u >= -(double)c.level_V_max - 1e-6);
    TV_CHECK_EQ_INT(sl.phase, SL_OPEN);
    TV_CHECK_NEAR((double)sl.phi_closed_rad, closed, 1e-6);
    /* the hold voltage balances the spring plus hold_Nm into the stop (model of tv_paper.h):
     * independent arithmetic: sp(-0.0873) with e_phi, M0, c, R / (n Kt) */
    {
        const double e = (double)p.e_phi_rad;
        const double spring = (double)p.M0_Nm * closed / sqrt(closed * closed + e * e) + (double)p.c_Nm_rad * closed;
        const double hold = (double)p.R_ohm / ((double)p.n_gear * (double)p.Kt_Nm_A) * (spring - (double)c.hold_Nm);
        TV_CHECK_NEAR((double)sl.u_hold_V, hold, 1e-5);
        TV_CHECK(hold < 0.0);
    }
    u = feed_const(&sl, open, 3000u, SL_OPEN);
    TV_CHECK(u > (double)c.push_V && u <= (double)c.level_V_max + 1e-6); /* toward the open stop */
    TV_CHECK_EQ_INT(sl.phase, SL_DONE);
    TV_CHECK_EQ_INT(sl.error, SL_ERR_NONE);
    TV_CHECK_NEAR((double)sl.phi_open_rad, open, 1e-6);
    /* a plate that rests at the same angle under every level: a stop too stiff to resolve, so
     * the stiffest law; of the exponents the flattest (e_min) explains a constant angle best */
    TV_CHECK_NEAR((double)sl.k_stop, (double)c.k_max, 1e-6 * (double)c.k_max);
    TV_CHECK_NEAR((double)sl.exponent, (double)c.e_min, 1e-6);
    {
        /* onset = rest angle less the stiffest law's mean penetration over the levels */
        const double e = (double)c.e_min;
        const double kp = pow((double)c.k_max, -1.0 / e);
        const double g = (pow((double)c.level_Nm[0], 1.0 / e) + pow((double)c.level_Nm[1], 1.0 / e) +
                          pow((double)c.level_Nm[2], 1.0 / e) + pow((double)c.hold_Nm, 1.0 / e)) / 4.0;
        TV_CHECK_NEAR((double)sl.onset_closed_rad, closed + kp * g, 1e-6);
        TV_CHECK_NEAR((double)sl.onset_open_rad, open - kp * g, 1e-6);
    }
    TV_CHECK_NEAR((double)sl_step(&sl, TV_R(1.0)), 0.0, 0.0); /* done: 0 V */
    TV_CHECK(!sl_running(&sl));
}

/*
 * The routine's fitting stage (stage 3, sl_t): with both stops' rest angles written from a
 * Hunt-Crossley law with pow() (onsets -0.102 / 1.371 rad, k 3e4, e 1.4), it takes
 * ceil(SL_EXP_GRID / SL_FIT_PER_STEP) = 7 periods holding the last level's voltage, and ends in
 * SL_DONE with exactly what the one-shot sl_contact_fit_joint() gives on the same angles (the
 * fit spread over periods so that no control step carries the whole grid).
 */
static void test_fit_is_spread_over_periods(void)
{
    sl_config_t c;
    tvm_params_t p;
    sl_t sl;
    tv_real_t F[SL_LEVELS];
    tv_real_t onset[2];
    tv_real_t k[2];
    tv_real_t e;
    unsigned j;
    unsigned periods = 0u;
    sl_config_default(&c);
    tvm_params_default(&p);
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_OK);
    for (j = 0; j < SL_LEVELS; ++j) {
        F[j] = j + 1u < SL_LEVELS ? c.level_Nm[j] : c.hold_Nm;
        sl.rest_rad[0][j] = (tv_real_t)(-0.102 - pow((double)F[j] / 3e4, 1.0 / 1.4));
        sl.rest_rad[1][j] = (tv_real_t)(1.371 + pow((double)F[j] / 3e4, 1.0 / 1.4));
    }
    TV_CHECK_EQ_INT(sl_contact_fit_joint(F, (const tv_real_t(*)[SL_LEVELS])sl.rest_rad, SL_LEVELS, c.e_min, c.e_max,
                                         c.k_min, c.k_max, onset, k, &e),
                    TV_OK);
    /* the state stop_measured() leaves when the open stop's last level is measured */
    sl.phase = SL_OPEN;
    sl.phi_closed_rad = sl.rest_rad[0][SL_LEVELS - 1u];
    sl.phi_open_rad = sl.rest_rad[1][SL_LEVELS - 1u];
    sl.u_hold_V = TV_R(1.25);
    sl.n_phase = 1u;
    sl.stage = 3u;
    sl.fit_g = 0u;
    sl.fit_sse_best = TV_R(-1.0);
    while (sl.phase == SL_OPEN && periods < 100u) {
        TV_CHECK_NEAR((double)sl_step(&sl, sl.phi_open_rad), periods + 1u < 7u ? 1.25 : 0.0, 0.0);
        ++periods;
    }
    TV_CHECK_EQ_INT((int)periods, (int)((SL_EXP_GRID + SL_FIT_PER_STEP - 1u) / SL_FIT_PER_STEP));
    TV_CHECK_EQ_INT(sl.phase, SL_DONE);
    TV_CHECK_NEAR((double)sl.exponent, (double)e, 0.0);
    TV_CHECK_NEAR((double)sl.onset_closed_rad, (double)onset[0], 0.0);
    TV_CHECK_NEAR((double)sl.onset_open_rad, (double)onset[1], 0.0);
    TV_CHECK_NEAR((double)sl.k_fit[0], (double)k[0], 0.0);
    TV_CHECK_NEAR((double)sl.k_fit[1], (double)k[1], 0.0);
    TV_CHECK_NEAR((double)sl.k_stop, sqrt((double)k[0] * (double)k[1]), 1e-12 * (double)sl.k_stop);
    /* and the law it found is the one the angles were written from */
    TV_CHECK_NEAR((double)e, 1.4, 0.051);
    TV_CHECK_NEAR((double)onset[0], -0.102, 2e-4);
    TV_CHECK_NEAR((double)onset[1], 1.371, 2e-4);
}

/* The contact-law fit against rest angles written from the law itself, a = a0 + dir (F/k)^(1/e)
 * (pow from libm, not the fit's exp/log), and its bounds. */
static void test_contact_fit(void)
{
    const tv_real_t F[3] = {TV_R(0.6), TV_R(0.35), TV_R(0.15)};
    tv_real_t a[3];
    tv_real_t a0 = TV_R(0.0);
    tv_real_t k = TV_R(0.0);
    int j;
    int s;
    for (s = 0; s < 2; ++s) {
        const double dir = s == 0 ? -1.0 : 1.0;
        const double a0_true = s == 0 ? -0.0912 : 1.4377;
        for (j = 0; j < 3; ++j) {
            a[j] = (tv_real_t)(a0_true + dir * pow((double)F[j] / 2000.0, 1.0 / 1.25));
        }
        TV_CHECK_EQ_INT(sl_contact_fit(F, a, 3u, (tv_real_t)dir, TV_R(1.25), TV_R(450.0), TV_R(4.5e4), &a0, &k), TV_OK);
        TV_CHECK_NEAR((double)k, 2000.0, 2000.0 * (TV_REAL_IS_DOUBLE ? 1e-9 : 2e-2));
        TV_CHECK_NEAR((double)a0, a0_true, TV_REAL_IS_DOUBLE ? 1e-12 : 2e-6);
        /* softer than k_min: held at k_min, onset refitted (mean residual 0 for that k) */
        for (j = 0; j < 3; ++j) {
            a[j] = (tv_real_t)(a0_true + dir * pow((double)F[j] / 100.0, 1.0 / 1.25));
        }
        TV_CHECK_EQ_INT(sl_contact_fit(F, a, 3u, (tv_real_t)dir, TV_R(1.25), TV_R(450.0), TV_R(4.5e4), &a0, &k), TV_OK);
        TV_CHECK_NEAR((double)k, 450.0, 450.0 * 1e-5);
        /* the wrong slope (noise on a rigid stop): the stiffest law */
        a[0] = (tv_real_t)(a0_true - dir * 1e-4);
        a[1] = (tv_real_t)a0_true;
        a[2] = (tv_real_t)(a0_true + dir * 1e-4);
        TV_CHECK_EQ_INT(sl_contact_fit(F, a, 3u, (tv_real_t)dir, TV_R(1.25), TV_R(450.0), TV_R(4.5e4), &a0, &k), TV_OK);
        TV_CHECK_NEAR((double)k, 4.5e4, 4.5e4 * 1e-6);
    }
    TV_CHECK_EQ_INT(sl_contact_fit(F, a, 1u, TV_R(1.0), TV_R(1.25), TV_R(450.0), TV_R(4.5e4), &a0, &k), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(sl_contact_fit(F, a, 3u, TV_R(1.0), TV_R(0.5), TV_R(450.0), TV_R(4.5e4), &a0, &k), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(sl_contact_fit(F, a, 3u, TV_R(1.0), TV_R(1.25), TV_R(450.0), TV_R(400.0), &a0, &k), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(sl_contact_fit(NULL, a, 3u, TV_R(1.0), TV_R(1.25), TV_R(450.0), TV_R(4.5e4), &a0, &k), TV_ERR_NULL);
}

/* The joint fit finds the common exponent of two stops whose rest angles were written from
 * one law with pow() (e = 1.4, on the default grid 1.0 .. 2.0 in steps of 0.05), their onsets and
 * stiffnesses; a fixed exponent (e_min = e_max) gives one fit; a bad range is refused. */
/* Rest angles of both stops from the law a = onset + dir (F / k)^(1/e), written out here (not by
 * the code under test): dir = -1 at the closed stop (s = 0), +1 at the open one. */
static void law_rest_angles(const tv_real_t F[SL_LEVELS], double e, const double onset[2], const double k[2],
                            tv_real_t a[2][SL_LEVELS])
{
    unsigned s;
    unsigned j;
    for (s = 0; s < 2u; ++s) {
        for (j = 0; j < SL_LEVELS; ++j) {
            a[s][j] = (tv_real_t)(onset[s] + (s == 0u ? -1.0 : 1.0) * pow((double)F[j] / k[s], 1.0 / e));
        }
    }
}

/* A law kept from identification (identify's parameter file: stop_learn.e_min = e_max = the
 * identified exponent, stop_learn.k_min/k_max = the identified stiffness as a secant at
 * SL_P_REF_RAD, +-1 %): the joint fit then keeps the exponent and the stiffness within the band
 * and only places the onsets. Rest angles written from a law with e = 1.3, k = 900 N m/rad^1.3 and
 * onsets moved by wear (-0.0812, 1.3215 rad) give those onsets; rest angles of a 30 % stiffer
 * stop still give k inside the band. */
static void test_contact_fit_keeps_an_identified_law(void)
{
    const tv_real_t F[SL_LEVELS] = {TV_R(1.35), TV_R(0.75), TV_R(0.45), TV_R(0.30)};
    const double e = 1.3;
    const double k_law = 900.0;
    const double ksec = k_law * pow((double)SL_P_REF_RAD, e - 1.0);
    const double onset[2] = {-0.0812, 1.3215};
    tv_real_t a[2][SL_LEVELS];
    tv_real_t on[2];
    tv_real_t kk[2];
    tv_real_t eg = TV_R(0.0);
    int s;
    int stiff;
    for (stiff = 0; stiff < 2; ++stiff) {
        const double k_true[2] = {stiff ? 1.3 * k_law : k_law, stiff ? 1.3 * k_law : k_law};
        law_rest_angles(F, e, onset, k_true, a);
        TV_CHECK_EQ_INT(sl_contact_fit_joint(F, (const tv_real_t(*)[SL_LEVELS])a, SL_LEVELS, (tv_real_t)e, (tv_real_t)e,
                                             (tv_real_t)(0.99 * ksec), (tv_real_t)(1.01 * ksec), on, kk, &eg),
                        TV_OK);
        TV_CHECK_NEAR((double)eg, e, 1e-6);
        for (s = 0; s < 2; ++s) {
            TV_CHECK((double)kk[s] >= 0.99 * k_law * (1.0 - 1e-5) && (double)kk[s] <= 1.01 * k_law * (1.0 + 1e-5));
            if (!stiff) {
                TV_CHECK_NEAR((double)on[s], onset[s], TV_REAL_IS_DOUBLE ? 1e-9 : 2e-5);
            } else {
                /* the law is held: the onset absorbs the difference, within the rest angles' span */
                TV_CHECK(fabs((double)on[s] - onset[s]) < 2e-3);
            }
        }
    }
}

static void test_contact_fit_joint(void)
{
    const tv_real_t F[SL_LEVELS] = {TV_R(0.7), TV_R(0.45), TV_R(0.3), TV_R(0.15)};
    const double a0_true[2] = {-0.0912, 1.4377};
    const double k_true[2] = {800.0, 2500.0};
    tv_real_t a[2][SL_LEVELS];
    tv_real_t onset[2];
    tv_real_t k[2];
    tv_real_t e = TV_R(0.0);
    unsigned s;
    law_rest_angles(F, 1.4, a0_true, k_true, a);
    TV_CHECK_EQ_INT(sl_contact_fit_joint(F, (const tv_real_t(*)[SL_LEVELS])a, SL_LEVELS, TV_R(1.0), TV_R(2.0), TV_R(50.0),
                                         TV_R(1e6), onset, k, &e),
                    TV_OK);
    TV_CHECK_NEAR((double)e, 1.4, 1e-6);
    for (s = 0; s < 2u; ++s) {
        TV_CHECK_NEAR((double)k[s], k_true[s], k_true[s] * (TV_REAL_IS_DOUBLE ? 1e-6 : 5e-2));
        TV_CHECK_NEAR((double)onset[s], a0_true[s], TV_REAL_IS_DOUBLE ? 1e-9 : 5e-6);
    }
    /* a fixed, wrong exponent still fits (with residuals): one value, k bounded */
    TV_CHECK_EQ_INT(sl_contact_fit_joint(F, (const tv_real_t(*)[SL_LEVELS])a, SL_LEVELS, TV_R(1.25), TV_R(1.25),
                                         TV_R(50.0), TV_R(1e6), onset, k, &e),
                    TV_OK);
    TV_CHECK_NEAR((double)e, 1.25, 0.0);
    TV_CHECK(k[0] >= TV_R(50.0) && k[0] <= TV_R(1e6));
    TV_CHECK_EQ_INT(sl_contact_fit_joint(F, (const tv_real_t(*)[SL_LEVELS])a, SL_LEVELS, TV_R(2.0), TV_R(1.5), TV_R(50.0),
                                         TV_R(1e6), onset, k, &e),
                    TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(sl_contact_fit_joint(F, (const tv_real_t(*)[SL_LEVELS])a, SL_LEVELS, TV_R(0.5), TV_R(1.5), TV_R(50.0),
                                         TV_R(1e6), onset, k, &e),
                    TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(sl_contact_fit_joint(NULL, (const tv_real_t(*)[SL_LEVELS])a, SL_LEVELS, TV_R(1.0), TV_R(2.0),
                                         TV_R(50.0), TV_R(1e6), onset, k, &e),
                    TV_ERR_NULL);
}

static void test_timeout_and_implausible_results_learn_nothing(void)
{
    sl_config_t c;
    tvm_params_t p;
    sl_t sl;
    unsigned k;
    sl_config_default(&c);
    tvm_params_default(&p);
    /* a plate that never comes to rest (5 mrad of jitter) times out after timeout_s */
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_OK);
    for (k = 0; k < 20000u && sl_running(&sl); ++k) {
        (void)sl_step(&sl, (tv_real_t)(-0.05 + ((k & 1u) ? 0.005 : 0.0)));
    }
    TV_CHECK_EQ_INT(sl.phase, SL_FAILED);
    TV_CHECK_EQ_INT(sl.error, SL_ERR_TIMEOUT_CLOSED);
    TV_CHECK_NEAR((double)k, (double)c.timeout_s * 1000.0 + 1.0, 1.5);
    TV_CHECK_NEAR((double)sl_step(&sl, TV_R(-0.05)), 0.0, 0.0);
    /* a plate held at limp-home (0 rad: jammed, or the spring lever) is no closed stop */
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_OK);
    (void)feed_const(&sl, 0.0, 5000u, SL_CLOSED);
    TV_CHECK_EQ_INT(sl.phase, SL_FAILED);
    TV_CHECK_EQ_INT(sl.error, SL_ERR_IMPLAUSIBLE_CLOSED);
    /* an open stop at 1.0 rad is outside its window */
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_OK);
    (void)feed_const(&sl, -0.1, 5000u, SL_CLOSED);
    (void)feed_const(&sl, 1.0, 5000u, SL_OPEN);
    TV_CHECK_EQ_INT(sl.error, SL_ERR_IMPLAUSIBLE_OPEN);
    /* both inside their windows, but 1.17 rad of travel is not a throttle's */
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_OK);
    (void)feed_const(&sl, -0.05, 5000u, SL_CLOSED);
    (void)feed_const(&sl, 1.12, 5000u, SL_OPEN);
    TV_CHECK_EQ_INT(sl.phase, SL_FAILED);
    TV_CHECK_EQ_INT(sl.error, SL_ERR_IMPLAUSIBLE_TRAVEL);
    /* a NaN angle ends it */
    TV_CHECK_EQ_INT(sl_start(&sl, &c, &p), TV_OK);
    TV_CHECK_NEAR((double)sl_step(&sl, (tv_real_t)NAN), 0.0, 0.0);
    TV_CHECK_EQ_INT(sl.error, SL_ERR_INPUT);
    TV_CHECK(strcmp(sl_error_name(SL_ERR_IMPLAUSIBLE_TRAVEL), "travel outside its plausible window") == 0);
}

static void test_nvm_record(void)
{
    static const uint8_t check[] = "123456789";
    sl_nvm_t rec;
    sl_nvm_t back;
    uint8_t buf[SL_NVM_BYTES];
    uint8_t bad[SL_NVM_BYTES];
    /* the published check value of CRC-32/ISO-HDLC */
    TV_CHECK(sl_crc32(check, 9u) == 0xCBF43926u);
    memset(&rec, 0, sizeof rec);
    rec.magic = SL_NVM_MAGIC;
    rec.version = SL_NVM_VERSION;
    rec.phi_closed_rad = -0.0912f;
    rec.phi_open_rad = 1.4021f;
    rec.n_learns = 7u;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, buf), TV_OK);
    TV_CHECK(buf[0] == 0x50u && buf[1] == 0x4Fu && buf[2] == 0x54u && buf[3] == 0x53u); /* little-endian "STOP" */
    TV_CHECK_EQ_INT(sl_nvm_unpack(buf, &back), TV_OK);
    TV_CHECK(back.phi_closed_rad == rec.phi_closed_rad && back.phi_open_rad == rec.phi_open_rad);
    TV_CHECK(back.n_learns == 7u);
    /* one flipped bit anywhere: rejected, nothing written */
    memcpy(bad, buf, sizeof bad);
    bad[9] ^= 0x01u;
    memset(&back, 0xA5, sizeof back);
    TV_CHECK_EQ_INT(sl_nvm_unpack(bad, &back), TV_ERR_FORMAT);
    TV_CHECK(back.n_learns == 0xA5A5A5A5u);
    /* a valid CRC over an implausible angle or a wrong version: rejected */
    rec.phi_open_rad = 3.0f;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    TV_CHECK_EQ_INT(sl_nvm_unpack(bad, &back), TV_ERR_FORMAT);
    rec.phi_open_rad = (float)NAN;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    TV_CHECK_EQ_INT(sl_nvm_unpack(bad, &back), TV_ERR_FORMAT);
    rec.phi_open_rad = 1.4021f;
    rec.version = 2u;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    TV_CHECK_EQ_INT(sl_nvm_unpack(bad, &back), TV_ERR_FORMAT);
    TV_CHECK_EQ_INT(sl_nvm_unpack(NULL, &back), TV_ERR_NULL);
}

static void test_app_set_stops_is_validated(void)
{
    static app_config_t cfg;
    static app_t app;
    tv_real_t lo;
    tv_real_t hi;
    app_config_default(&cfg);
    TV_CHECK_EQ_INT(app_init(&app, &cfg), TV_OK);
    TV_CHECK_EQ_INT(app_set_stops(&app, TV_R(-0.08), TV_R(1.45)), TV_OK);
    ekf_stops(&app.ekf, &lo, &hi);
    TV_CHECK_NEAR((double)lo, -0.08, 1e-6);
    TV_CHECK_NEAR((double)hi, 1.45, 1e-6);
    TV_CHECK_NEAR((double)app.cfg.model.phi_open_rad, 1.45, 1e-6);
    TV_CHECK_EQ_INT(app_set_stops(&app, TV_R(0.01), TV_R(1.45)), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(app_set_stops(&app, TV_R(-0.1), (tv_real_t)NAN), TV_ERR_NONFINITE);
    ekf_stops(&app.ekf, &lo, &hi);
    TV_CHECK_NEAR((double)lo, -0.08, 1e-6); /* unchanged by the refused calls */
    TV_CHECK_NEAR((double)hi, 1.45, 1e-6);
    TV_CHECK(app_stop_learn(&app)->phase == SL_IDLE);
}

/* Last mode the application was in, seen per tick. */
static void last_mode(const sim_row_t *row, void *user)
{
    *(int *)user = row->mode;
}

static void test_routine_on_population_plants(void)
{
    /* the application's APP_MODE_STOP_LEARN against the plant: the nominal unit and units of
     * both classes and spreads (evaluation IDs); the plant's own stops are the reference */
    static const uint64_t units[] = {1000u, 1002u, 1011u, 1017u, 1022u};
    int sp;
    unsigned k;
    for (sp = 0; sp < 2; ++sp) {
        for (k = 0; k < sizeof units / sizeof units[0]; ++k) {
            const plant_class_t cls = units[k] % 3u == 2u ? PLANT_CLASS_B : PLANT_CLASS_A;
            static plant_config_t pc;
            static app_config_t ac;
            sim_options_t o;
            sim_result_t r;
            int mode = -1;
            TV_CHECK_EQ_INT(plant_draw(cls, sp == 0 ? PLANT_SPREAD_STOPS : PLANT_SPREAD_ALL, units[k], &pc), TV_OK);
            TV_CHECK_EQ_INT(sim_app_config_for_unit(cls, &pc, &ac), TV_OK);
            sim_options_default(&o);
            o.scenario = SIM_SCN_STOP_LEARN;
            o.plant = &pc;
            o.app = &ac;
            o.row_fn = last_mode;
            o.row_user = &mode;
            TV_CHECK_EQ_INT(sim_run(&o, &r), TV_OK);
            TV_CHECK_EQ_INT(r.stop_learn_phase, SL_DONE);
            TV_CHECK_LE(fabs(r.stop_learn_closed_rad - pc.phi_closed_rad), 0.005);
            TV_CHECK_LE(fabs(r.stop_learn_open_rad - pc.phi_open_rad), 0.005);
            TV_CHECK(r.stop_contact_speed_max > 0.0); /* it did reach both stops */
            TV_CHECK_LE(r.stop_contact_speed_max, 1.0);
            TV_CHECK_EQ_INT(mode, APP_MODE_OFF); /* the mode ends by itself */
            TV_CHECK_EQ_INT(r.faults, 0);
        }
    }
}

int main(void)
{
    TV_TEST_RUN(test_config_is_validated);
    TV_TEST_RUN(test_scripted_stops_are_learned);
    TV_TEST_RUN(test_contact_fit);
    TV_TEST_RUN(test_contact_fit_joint);
    TV_TEST_RUN(test_contact_fit_keeps_an_identified_law);
    TV_TEST_RUN(test_fit_is_spread_over_periods);
    TV_TEST_RUN(test_timeout_and_implausible_results_learn_nothing);
    TV_TEST_RUN(test_nvm_record);
    TV_TEST_RUN(test_app_set_stops_is_validated);
    TV_TEST_RUN(test_routine_on_population_plants);
    return tv_test_summary();
}
