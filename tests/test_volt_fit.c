/**
 * @file test_volt_fit.c
 * @brief The voltage equation's fit (firmware/estimator/volt_fit.h) against data built from known
 *        constants: exact recovery, the least-squares standard deviation worked out by hand, the
 *        sliding window of blocks, the gates (undriven periods, collinear regressors, non-finite
 *        values) and the configuration's validation.
 *
 * Built against the double estimator and, as test_volt_fit_f32, the float one (the ECU's).
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "tv_status.h"
#include "tv_test.h"
#include "volt_fit.h"

#define L_H 0.002
#define TS_S 0.001

/* Period k of a drive whose current and velocity are not collinear: two sines of different
 * frequencies, the voltage above 1 V throughout; the voltage is what the averaged equation gives for R and nke (the currents and
 * velocities at the period's start and end: i(k), i(k + 1), w(k), w(k + 1)). */
static double cur(int k) { return 2.0 + 0.8 * sin(0.21 * k); }
static double vel(int k) { return 6.0 * sin(0.13 * k + 0.4); }
static double volt(int k, double R, double nke)
{
    return R * 0.5 * (cur(k) + cur(k + 1)) + L_H / TS_S * (cur(k + 1) - cur(k)) + nke * 0.5 * (vel(k) + vel(k + 1));
}
static int feed(vfit_t *f, int k, double R, double nke)
{
    return vfit_step(f, (tv_real_t)volt(k, R, nke), (tv_real_t)cur(k), (tv_real_t)cur(k + 1), (tv_real_t)vel(k),
                     (tv_real_t)vel(k + 1));
}

static void cfg_small(vfit_config_t *c)
{
    vfit_config_default(c);
    c->block = 100u;
    c->blocks = 3u;
}

/* Exact data: R and n Ke come back (float: to its rounding), sigma ~0, a result each block
 * once three are complete, none before. */
static void test_exact_recovery(void)
{
    vfit_config_t c;
    vfit_t f;
    int k;
    int taken = 0;
    int first = -1;
    cfg_small(&c);
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S), TV_OK);
    for (k = 0; k < 1000; ++k) {
        if (feed(&f, k, 4.3, 0.68)) {
            ++taken;
            if (first < 0) {
                first = k;
            }
        }
    }
    TV_CHECK_EQ_INT(first, 299);   /* the third block's last period */
    TV_CHECK_EQ_INT(taken, 8);     /* blocks 3 .. 10 */
    TV_CHECK_EQ_INT((int)f.windows, 8);
    TV_CHECK(f.valid == 1u);
    TV_CHECK_NEAR(f.r_ohm, 4.3, TV_REAL_IS_DOUBLE ? 1e-9 : 2e-3);
    TV_CHECK_NEAR(f.nke_V_s, 0.68, TV_REAL_IS_DOUBLE ? 1e-10 : 5e-4);
    TV_CHECK_LE(f.r_sigma_ohm, TV_REAL_IS_DOUBLE ? 1e-6 : 0.05);
}

/* The window slides: a resistance step after 600 periods is read fully once the window's three
 * blocks all lie after it, in between as a mixture of both. */
static void test_window_slides(void)
{
    vfit_config_t c;
    vfit_t f;
    int k;
    cfg_small(&c);
    (void)vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S);
    for (k = 0; k < 700; ++k) {
        (void)feed(&f, k, k < 600 ? 4.0 : 5.0, 0.68);
    }
    TV_CHECK(f.r_ohm > (tv_real_t)4.05 && f.r_ohm < (tv_real_t)4.95); /* blocks 5, 6 (4 ohm) and 7 (5 ohm) */
    for (; k < 900; ++k) {
        (void)feed(&f, k, 5.0, 0.68);
    }
    TV_CHECK_NEAR(f.r_ohm, 5.0, TV_REAL_IS_DOUBLE ? 1e-9 : 2e-3);
}

/* Periods below u_min_V, and non-finite values, are left out: a window then needs more periods. */
static void test_gates(void)
{
    vfit_config_t c;
    vfit_t f;
    int k;
    cfg_small(&c);
    c.u_min_V = (tv_real_t)0.5;
    (void)vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S);
    for (k = 0; k < 300; ++k) {
        TV_CHECK(vfit_step(&f, (tv_real_t)0.49, (tv_real_t)1.0, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
        TV_CHECK(vfit_step(&f, (tv_real_t)NAN, (tv_real_t)1.0, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
        TV_CHECK(vfit_step(&f, (tv_real_t)3.0, (tv_real_t)INFINITY, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
    }
    TV_CHECK(f.n == 0u && f.full == 0u && f.valid == 0u);
    TV_CHECK(vfit_step(NULL, (tv_real_t)3.0, (tv_real_t)1.0, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
    /* a negative drive counts like a positive one */
    TV_CHECK(vfit_step(&f, (tv_real_t)-0.5, (tv_real_t)1.0, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
    TV_CHECK_EQ_INT((int)f.n, 1);
}

/* Current proportional to velocity: R and n Ke cannot be told apart. Once the window holds
 * nothing else (three blocks in), no window is taken and the last result stays. */
static void test_collinear_not_taken(void)
{
    vfit_config_t c;
    vfit_t f;
    int k;
    cfg_small(&c);
    (void)vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S);
    for (k = 0; k < 300; ++k) {
        (void)feed(&f, k, 4.3, 0.68);
    }
    TV_CHECK(f.valid == 1u);
    for (k = 0; k < 600; ++k) {
        const double w = 6.0 * sin(0.13 * k);
        const double ic = 0.2 * w; /* through the origin: collinear with w */
        const int r = vfit_step(&f, (tv_real_t)(4.3 * ic + 0.68 * w + 1.0), (tv_real_t)ic, (tv_real_t)ic, (tv_real_t)w,
                                (tv_real_t)w);
        if (k >= 300) {
            TV_CHECK(r == 0);
        }
    }
    {
        const uint32_t n = f.windows;
        const tv_real_t r_last = f.r_ohm;
        for (k = 0; k < 300; ++k) {
            const double w = 6.0 * sin(0.13 * k);
            (void)vfit_step(&f, (tv_real_t)(4.3 * 0.2 * w + 0.68 * w + 1.0), (tv_real_t)(0.2 * w), (tv_real_t)(0.2 * w),
                            (tv_real_t)w, (tv_real_t)w);
        }
        TV_CHECK_EQ_INT((int)f.windows, (int)n);
        TV_CHECK_NEAR(f.r_ohm, r_last, 0.0);
    }
}

/* Sigma against the least-squares formula worked out here in double precision: data with a
 * known residual (a square wave of +-0.1 V, uncorrelated enough with the regressors), sigma_R^2 =
 * s^2 corr S_ww / det with s^2 = RSS / (n - 2). */
static void test_sigma_formula(void)
{
    vfit_config_t c;
    vfit_t f;
    double s[6] = {0, 0, 0, 0, 0, 0};
    double det;
    double r;
    double kk;
    double var;
    int k;
    vfit_config_default(&c);
    c.block = 200u;
    c.blocks = 1u;
    c.corr_periods = (tv_real_t)10.0;
    (void)vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S);
    for (k = 0; k < 200; ++k) {
        const double e = (k / 7) % 2 ? 0.1 : -0.1;
        const double u = volt(k, 4.3, 0.68) + e;
        const double i = 0.5 * (cur(k) + cur(k + 1));
        const double w = 0.5 * (vel(k) + vel(k + 1));
        const double y = u - L_H / TS_S * (cur(k + 1) - cur(k));
        s[0] += i * i;
        s[1] += i * w;
        s[2] += w * w;
        s[3] += i * y;
        s[4] += w * y;
        s[5] += y * y;
        (void)vfit_step(&f, (tv_real_t)u, (tv_real_t)cur(k), (tv_real_t)cur(k + 1), (tv_real_t)vel(k), (tv_real_t)vel(k + 1));
    }
    det = s[0] * s[2] - s[1] * s[1];
    r = (s[2] * s[3] - s[1] * s[4]) / det;
    kk = (s[0] * s[4] - s[1] * s[3]) / det;
    var = (s[5] - r * s[3] - kk * s[4]) / 198.0 * 10.0;
    TV_CHECK(f.valid == 1u);
    TV_CHECK_NEAR(f.r_ohm, r, TV_REAL_IS_DOUBLE ? 1e-9 : 5e-3);
    TV_CHECK_NEAR(f.nke_V_s, kk, TV_REAL_IS_DOUBLE ? 1e-10 : 1e-3);
    TV_CHECK_NEAR(f.r_sigma_ohm, sqrt(var * s[2] / det), TV_REAL_IS_DOUBLE ? 1e-9 : 0.1 * sqrt(var * s[2] / det));
    TV_CHECK_NEAR(f.nke_sigma_V_s, sqrt(var * s[0] / det), TV_REAL_IS_DOUBLE ? 1e-10 : 0.1 * sqrt(var * s[0] / det));
    TV_CHECK(f.r_sigma_ohm > (tv_real_t)0.0);
}

static void test_config_validation(void)
{
    vfit_config_t c;
    vfit_t f;
    vfit_config_default(&c);
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S), TV_OK);
    TV_CHECK_EQ_INT(vfit_init(NULL, &c, (tv_real_t)L_H, (tv_real_t)TS_S), TV_ERR_NULL);
    TV_CHECK_EQ_INT(vfit_init(&f, NULL, (tv_real_t)L_H, (tv_real_t)TS_S), TV_ERR_NULL);
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)0.0, (tv_real_t)TS_S), TV_ERR_CONFIG);
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)NAN), TV_ERR_NONFINITE);
    c.block = 99u;
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S), TV_ERR_CONFIG);
    vfit_config_default(&c);
    c.blocks = 0u;
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S), TV_ERR_CONFIG);
    c.blocks = VFIT_BLOCKS_MAX + 1u;
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S), TV_ERR_CONFIG);
    vfit_config_default(&c);
    c.rho2_max = (tv_real_t)1.0;
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S), TV_ERR_CONFIG);
    vfit_config_default(&c);
    c.corr_periods = (tv_real_t)0.5;
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S), TV_ERR_CONFIG);
    vfit_config_default(&c);
    c.u_min_V = (tv_real_t)-1.0;
    TV_CHECK_EQ_INT(vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S), TV_ERR_CONFIG);
    vfit_config_default(&c);
    TV_CHECK_EQ_INT((int)c.block, 250);
    TV_CHECK_EQ_INT((int)c.blocks, 4);
}

int main(void)
{
    TV_TEST_RUN(test_exact_recovery);
    TV_TEST_RUN(test_window_slides);
    TV_TEST_RUN(test_gates);
    TV_TEST_RUN(test_collinear_not_taken);
    TV_TEST_RUN(test_sigma_formula);
    TV_TEST_RUN(test_config_validation);
    return tv_test_summary();
}
