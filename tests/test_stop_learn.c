/**
 * @file test_stop_learn.c
 * @brief Start-up stop learning (firmware/app/stop_learn.h): the routine's rules on scripted
 *        angles (result, timeout, implausible results rejected, bad input), the unit's
 *        non-volatile record (CRC-32 against its published check value; version 2 with the fit's
 *        baseline byte by byte and round trip, version 1 still read; corruption and implausible
 *        values rejected), app_set_stops()
 *        validation, and the routine through the application against population plants (angles
 *        within 5 mrad of the plant's own stops, never into a stop faster than 1 rad/s).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
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

/* Write a little-endian u32 into a record built by hand. */
static void put_le32(uint8_t *b, uint32_t v)
{
    b[0] = (uint8_t)v;
    b[1] = (uint8_t)(v >> 8);
    b[2] = (uint8_t)(v >> 16);
    b[3] = (uint8_t)(v >> 24);
}

static void put_f32(uint8_t *b, float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    put_le32(b, u);
}

/* A record rejected: TV_ERR_FORMAT, *rec not written. */
static void nvm_rejected(const uint8_t buf[SL_NVM_BYTES], const char *what)
{
    sl_nvm_t back;
    memset(&back, 0xA5, sizeof back);
    if (sl_nvm_unpack(buf, &back) != TV_ERR_FORMAT || back.n_learns != 0xA5A5A5A5u || back.magic != 0xA5A5A5A5u) {
        fprintf(stderr, "  record accepted or written: %s\n", what);
        TV_CHECK(0);
    }
}

/* A version-2 record packed from rec with its baseline changed: rejected, as the baseline is
 * implausible or half of one. */
static void nvm_bad_baseline(sl_nvm_t rec, float r_ohm, float nke_V_s, const char *what)
{
    uint8_t buf[SL_NVM_BYTES];
    rec.fit_base_r_ohm = r_ohm;
    rec.fit_base_nke_V_s = nke_V_s;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, buf), TV_OK);
    nvm_rejected(buf, what);
}

/* The unit's record (version 2, 32 bytes): the layout byte by byte, the round trip of the stops
 * and the fit's baseline (and of none), a version-1 record built by hand (24 bytes, its CRC via
 * sl_crc32 at offset 20, erased flash after it) accepted with its stops and no baseline; every
 * field corrupted, a wrong CRC, magic or version, implausible angles, half a baseline, NaN,
 * infinities, zero-or-negative and out-of-range baselines rejected without writing *rec. */
static void test_nvm_record(void)
{
    static const uint8_t check[] = "123456789";
    sl_nvm_t rec;
    sl_nvm_t back;
    uint8_t buf[SL_NVM_BYTES];
    uint8_t bad[SL_NVM_BYTES];
    uint8_t v1[SL_NVM_BYTES];
    unsigned i;
    /* the published check value of CRC-32/ISO-HDLC */
    TV_CHECK(sl_crc32(check, 9u) == 0xCBF43926u);
    TV_CHECK_EQ_INT(SL_NVM_VERSION, 2);
    TV_CHECK_EQ_INT(SL_NVM_BYTES, 32);
    memset(&rec, 0, sizeof rec);
    rec.magic = SL_NVM_MAGIC;
    rec.version = SL_NVM_VERSION;
    rec.phi_closed_rad = -0.0912f;
    rec.phi_open_rad = 1.4021f;
    rec.fit_base_r_ohm = 4.1237f;
    rec.fit_base_nke_V_s = 0.6543f;
    rec.n_learns = 7u;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, buf), TV_OK);
    /* the layout, field by field, against the same record written by hand */
    memset(bad, 0, sizeof bad);
    put_le32(bad, 0x53544F50u);
    put_le32(bad + 4, 2u);
    put_f32(bad + 8, -0.0912f);
    put_f32(bad + 12, 1.4021f);
    put_f32(bad + 16, 4.1237f);
    put_f32(bad + 20, 0.6543f);
    put_le32(bad + 24, 7u);
    put_le32(bad + 28, sl_crc32(bad, 28u));
    TV_CHECK(memcmp(buf, bad, SL_NVM_BYTES) == 0);
    TV_CHECK(buf[0] == 0x50u && buf[1] == 0x4Fu && buf[2] == 0x54u && buf[3] == 0x53u); /* little-endian "STOP" */
    memset(&back, 0xA5, sizeof back);
    TV_CHECK_EQ_INT(sl_nvm_unpack(buf, &back), TV_OK);
    TV_CHECK(back.magic == SL_NVM_MAGIC && back.version == 2u && back.reserved == 0u);
    TV_CHECK(back.phi_closed_rad == rec.phi_closed_rad && back.phi_open_rad == rec.phi_open_rad);
    TV_CHECK(back.fit_base_r_ohm == rec.fit_base_r_ohm && back.fit_base_nke_V_s == rec.fit_base_nke_V_s);
    TV_CHECK(back.n_learns == 7u);
    TV_CHECK(back.crc32 == sl_crc32(buf, 28u));
    /* no baseline: 0, 0 round trips */
    rec.fit_base_r_ohm = 0.0f;
    rec.fit_base_nke_V_s = 0.0f;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    memset(&back, 0xA5, sizeof back);
    TV_CHECK_EQ_INT(sl_nvm_unpack(bad, &back), TV_OK);
    TV_CHECK(back.fit_base_r_ohm == 0.0f && back.fit_base_nke_V_s == 0.0f && back.n_learns == 7u);
    /* the bounds themselves are plausible */
    rec.fit_base_r_ohm = SL_NVM_FIT_BASE_R_MAX_OHM;
    rec.fit_base_nke_V_s = SL_NVM_FIT_BASE_NKE_MAX_V_S;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    TV_CHECK_EQ_INT(sl_nvm_unpack(bad, &back), TV_OK);
    TV_CHECK(back.fit_base_r_ohm == 1000.0f && back.fit_base_nke_V_s == 100.0f);
    rec.fit_base_r_ohm = 4.1237f;
    rec.fit_base_nke_V_s = 0.6543f;

    /* a version-1 record, as units in the field hold it: magic, version 1, the angles, n_learns,
     * the CRC-32 of its 20 bytes at offset 20; the flash after it erased (0xFF), then anything */
    memset(v1, 0xFF, sizeof v1);
    put_le32(v1, 0x53544F50u);
    put_le32(v1 + 4, 1u);
    put_f32(v1 + 8, -0.0733f);
    put_f32(v1 + 12, 1.3877f);
    put_le32(v1 + 16, 3u);
    put_le32(v1 + 20, sl_crc32(v1, 20u));
    for (i = 0; i < 2u; ++i) {
        memset(&back, 0xA5, sizeof back);
        TV_CHECK_EQ_INT(sl_nvm_unpack(v1, &back), TV_OK);
        TV_CHECK(back.magic == SL_NVM_MAGIC && back.version == 1u);
        TV_CHECK(back.phi_closed_rad == -0.0733f && back.phi_open_rad == 1.3877f);
        TV_CHECK(back.fit_base_r_ohm == 0.0f && back.fit_base_nke_V_s == 0.0f); /* none */
        TV_CHECK(back.n_learns == 3u);
        memset(v1 + SL_NVM_V1_BYTES, 0x5A, SL_NVM_BYTES - SL_NVM_V1_BYTES); /* ignored */
    }
    /* written back as version 2: the same stops, the baseline still none, then one learned */
    back.version = SL_NVM_VERSION;
    TV_CHECK_EQ_INT(sl_nvm_pack(&back, bad), TV_OK);
    memset(&rec, 0, sizeof rec);
    TV_CHECK_EQ_INT(sl_nvm_unpack(bad, &rec), TV_OK);
    TV_CHECK(rec.version == 2u && rec.phi_closed_rad == -0.0733f && rec.phi_open_rad == 1.3877f &&
             rec.fit_base_r_ohm == 0.0f && rec.n_learns == 3u);
    /* version 1's bytes under version 2 (its CRC where version 2 keeps R), and version 2's bytes
     * under version 1: rejected */
    memcpy(bad, v1, sizeof bad);
    put_le32(bad + 4, 2u);
    nvm_rejected(bad, "a version-1 record labelled 2");
    memcpy(bad, buf, sizeof bad);
    put_le32(bad + 4, 1u);
    nvm_rejected(bad, "a version-2 record labelled 1");
    /* a version-1 record: every bit of its 24 bytes flipped in turn */
    for (i = 0; i < SL_NVM_V1_BYTES * 8u; ++i) {
        memcpy(bad, v1, sizeof bad);
        bad[i / 8u] ^= (uint8_t)(1u << (i % 8u));
        nvm_rejected(bad, "a version-1 record with a bit flipped");
    }
    /* a version-1 record with a valid CRC over an implausible angle */
    memcpy(bad, v1, sizeof bad);
    put_f32(bad + 12, 3.0f);
    put_le32(bad + 20, sl_crc32(bad, 20u));
    nvm_rejected(bad, "a version-1 record, open stop 3 rad");

    /* version 2: every bit of the 32 bytes flipped in turn (magic, version, reserved, each field,
     * the CRC): rejected, nothing written */
    for (i = 0; i < SL_NVM_BYTES * 8u; ++i) {
        memcpy(bad, buf, sizeof bad);
        bad[i / 8u] ^= (uint8_t)(1u << (i % 8u));
        nvm_rejected(bad, "a version-2 record with a bit flipped");
    }
    /* a valid CRC over a wrong magic or version, or implausible angles */
    rec.magic = SL_NVM_MAGIC;
    rec.version = SL_NVM_VERSION;
    rec.reserved = 0u;
    rec.phi_closed_rad = -0.0912f;
    rec.phi_open_rad = 1.4021f;
    rec.fit_base_r_ohm = 4.1237f;
    rec.fit_base_nke_V_s = 0.6543f;
    rec.n_learns = 7u;
    rec.magic = 0x53544F51u;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    nvm_rejected(bad, "magic");
    rec.magic = SL_NVM_MAGIC;
    rec.version = 0u;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    nvm_rejected(bad, "version 0");
    rec.version = 3u;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    nvm_rejected(bad, "version 3");
    rec.version = SL_NVM_VERSION;
    rec.phi_open_rad = 3.0f;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    nvm_rejected(bad, "open stop 3 rad");
    rec.phi_open_rad = (float)NAN;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    nvm_rejected(bad, "open stop NaN");
    rec.phi_open_rad = 1.4021f;
    rec.phi_closed_rad = 0.1f;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    nvm_rejected(bad, "closed stop +0.1 rad");
    rec.phi_closed_rad = -0.0912f;
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, bad), TV_OK);
    TV_CHECK_EQ_INT(sl_nvm_unpack(bad, &back), TV_OK); /* restored: accepted */
    /* the baseline: half of one, NaN, infinities, zero or negative, beyond the bounds */
    nvm_bad_baseline(rec, 4.1237f, 0.0f, "R without n Ke");
    nvm_bad_baseline(rec, 0.0f, 0.6543f, "n Ke without R");
    nvm_bad_baseline(rec, (float)NAN, 0.6543f, "R NaN");
    nvm_bad_baseline(rec, 4.1237f, (float)NAN, "n Ke NaN");
    nvm_bad_baseline(rec, (float)NAN, (float)NAN, "both NaN");
    nvm_bad_baseline(rec, (float)INFINITY, 0.6543f, "R infinite");
    nvm_bad_baseline(rec, 4.1237f, (float)INFINITY, "n Ke infinite");
    nvm_bad_baseline(rec, -4.1237f, 0.6543f, "R negative");
    nvm_bad_baseline(rec, 4.1237f, -0.6543f, "n Ke negative");
    nvm_bad_baseline(rec, -4.1237f, -0.6543f, "both negative");
    nvm_bad_baseline(rec, 1000.001f, 0.6543f, "R above 1000 ohm");
    nvm_bad_baseline(rec, 4.1237f, 100.001f, "n Ke above 100 V s/rad");
    nvm_bad_baseline(rec, 1e30f, 1e30f, "both far out");
    TV_CHECK_EQ_INT(sl_nvm_unpack(NULL, &back), TV_ERR_NULL);
    TV_CHECK_EQ_INT(sl_nvm_unpack(buf, NULL), TV_ERR_NULL);
    TV_CHECK_EQ_INT(sl_nvm_pack(NULL, buf), TV_ERR_NULL);
    TV_CHECK_EQ_INT(sl_nvm_pack(&rec, NULL), TV_ERR_NULL);
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
