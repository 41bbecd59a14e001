/**
 * @file test_volt_fit.c
 * @brief The voltage equation's fit (firmware/estimator/volt_fit.h) against data built from known
 *        constants: exact recovery, the instrumental variables' estimates and standard deviations
 *        worked out by hand (and the bias of least squares they remove), the
 *        sliding window of blocks, the gates (undriven periods, collinear regressors, non-finite
 *        values) and the configuration's validation.
 *
 * Built against the double estimator and, as test_volt_fit_f32, the float one (the ECU's).
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include <gsl/gsl_linalg.h>

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
                     (tv_real_t)vel(k + 1), (tv_real_t)(0.5 * (vel(k) + vel(k + 1))));
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
        TV_CHECK(vfit_step(&f, (tv_real_t)0.49, (tv_real_t)1.0, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
        TV_CHECK(vfit_step(&f, (tv_real_t)NAN, (tv_real_t)1.0, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
        TV_CHECK(vfit_step(&f, (tv_real_t)3.0, (tv_real_t)INFINITY, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
        TV_CHECK(vfit_step(&f, (tv_real_t)3.0, (tv_real_t)1.0, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0, (tv_real_t)NAN) == 0);
    }
    TV_CHECK(f.n == 0u && f.full == 0u && f.valid == 0u);
    TV_CHECK(vfit_step(NULL, (tv_real_t)3.0, (tv_real_t)1.0, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
    /* a negative drive counts like a positive one */
    TV_CHECK(vfit_step(&f, (tv_real_t)-0.5, (tv_real_t)1.0, (tv_real_t)1.0, (tv_real_t)0.0, (tv_real_t)0.0, (tv_real_t)0.0) == 0);
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
                                (tv_real_t)w, (tv_real_t)w);
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
                            (tv_real_t)w, (tv_real_t)w, (tv_real_t)w);
        }
        TV_CHECK_EQ_INT((int)f.windows, (int)n);
        TV_CHECK_NEAR(f.r_ohm, r_last, 0.0);
    }
}

/* The samples of test_iv_bias_and_sigma, kept to form the residuals afterwards. */
static double s_i[1000];
static double s_w[1000];
static double s_v[1000];
static double s_y[1000];

/* R and n Ke by instrumental variables, against the 2 x 2 formulas worked out here in double
 * precision from the kept samples (theta = (Z'X)^-1 Z'y, Z = (i, w), X = (i, v); var = (corr
 * RSS_w + RSS_v) / (n - 2) with the residuals y - theta' (i, w) and y - theta' (i, v) formed
 * sample by sample; sigma_j^2 = var [A^-1 Z'Z A^-T]_jj). The data: an estimated velocity whose
 * error follows the motion (0.3 rad/s with the velocity's sign, what a unit's friction, not the
 * model's, does to the estimate), a differentiated angle with noise (+-0.3 rad/s, a fixed
 * pseudo-random sequence) and a residual square wave of +-0.1 V. Least squares on w reads n Ke
 * biased by that error (checked here: more than 3 % off; R within 0.3 %, as the current here
 * barely follows the velocity's sign: in closed loop it does, and R takes a share of the bias);
 * the instrumental variables read R within 0.3 % and n Ke within 1 %. */
static void test_iv_bias_and_sigma(void)
{
    vfit_config_t c;
    vfit_t f;
    double zx[2][2] = {{0}};
    double zz[2][2] = {{0}};
    double zy[2] = {0};
    double det;
    double r;
    double kk;
    double rss_w = 0.0;
    double rss_v = 0.0;
    double var;
    double qr;
    double qk;
    uint32_t lcg = 777u;
    int k;
    int took = 0;
    vfit_config_default(&c);
    c.block = 250u;
    c.blocks = 4u;
    c.corr_periods = (tv_real_t)10.0;
    (void)vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S);
    for (k = 0; k < 1000; ++k) {
        const double e = (k / 7) % 2 ? 0.1 : -0.1;
        const double u = volt(k, 4.3, 0.68) + e;
        const double w0 = vel(k) + (vel(k) >= 0.0 ? 0.3 : -0.3);
        const double w1 = vel(k + 1) + (vel(k + 1) >= 0.0 ? 0.3 : -0.3);
        lcg = lcg * 1664525u + 1013904223u;
        s_v[k] = 0.5 * (vel(k) + vel(k + 1)) + 0.6 * ((double)(lcg >> 8) / 16777216.0 - 0.5);
        s_i[k] = 0.5 * (cur(k) + cur(k + 1));
        s_w[k] = 0.5 * (w0 + w1);
        s_y[k] = u - L_H / TS_S * (cur(k + 1) - cur(k));
        took |= vfit_step(&f, (tv_real_t)u, (tv_real_t)cur(k), (tv_real_t)cur(k + 1), (tv_real_t)w0, (tv_real_t)w1,
                          (tv_real_t)s_v[k]);
    }
    TV_CHECK(took & VFIT_TOOK_FIT);
    TV_CHECK(f.valid == 1u);
    for (k = 0; k < 1000; ++k) {
        zx[0][0] += s_i[k] * s_i[k];
        zx[0][1] += s_i[k] * s_v[k];
        zx[1][0] += s_w[k] * s_i[k];
        zx[1][1] += s_w[k] * s_v[k];
        zz[0][0] += s_i[k] * s_i[k];
        zz[0][1] += s_i[k] * s_w[k];
        zz[1][1] += s_w[k] * s_w[k];
        zy[0] += s_i[k] * s_y[k];
        zy[1] += s_w[k] * s_y[k];
    }
    zz[1][0] = zz[0][1];
    {
        /* least squares on w, for the bias the instruments remove */
        const double dls = zz[0][0] * zz[1][1] - zz[0][1] * zz[0][1];
        const double r_ls = (zz[1][1] * zy[0] - zz[0][1] * zy[1]) / dls;
        const double k_ls = (zz[0][0] * zy[1] - zz[0][1] * zy[0]) / dls;
        TV_CHECK(fabs(k_ls / 0.68 - 1.0) > 0.03);
        TV_CHECK(fabs(r_ls / 4.3 - 1.0) < 0.003);
    }
    det = zx[0][0] * zx[1][1] - zx[0][1] * zx[1][0];
    r = (zx[1][1] * zy[0] - zx[0][1] * zy[1]) / det;
    kk = (zx[0][0] * zy[1] - zx[1][0] * zy[0]) / det;
    for (k = 0; k < 1000; ++k) {
        const double ew = s_y[k] - r * s_i[k] - kk * s_w[k];
        const double ev = s_y[k] - r * s_i[k] - kk * s_v[k];
        rss_w += ew * ew;
        rss_v += ev * ev;
    }
    var = (10.0 * rss_w + rss_v) / 998.0;
    {
        /* the rows of A^-1, g_R and g_K, and g' Z'Z g */
        const double gr[2] = {zx[1][1] / det, -zx[0][1] / det};
        const double gk[2] = {-zx[1][0] / det, zx[0][0] / det};
        int a;
        int j;
        qr = 0.0;
        qk = 0.0;
        for (a = 0; a < 2; ++a) {
            for (j = 0; j < 2; ++j) {
                qr += gr[a] * zz[a][j] * gr[j];
                qk += gk[a] * zz[a][j] * gk[j];
            }
        }
    }
    TV_CHECK_NEAR(r, 4.3, 0.013);
    TV_CHECK_NEAR(kk, 0.68, 0.0068);
    TV_CHECK_NEAR(f.r_ohm, r, TV_REAL_IS_DOUBLE ? 1e-9 : 5e-3);
    TV_CHECK_NEAR(f.nke_V_s, kk, TV_REAL_IS_DOUBLE ? 1e-10 : 1e-3);
    TV_CHECK_NEAR(f.r_sigma_ohm, sqrt(var * qr), TV_REAL_IS_DOUBLE ? 1e-6 * sqrt(var * qr) : 0.1 * sqrt(var * qr));
    TV_CHECK_NEAR(f.nke_sigma_V_s, sqrt(var * qk), TV_REAL_IS_DOUBLE ? 1e-6 * sqrt(var * qk) : 0.1 * sqrt(var * qk));
    TV_CHECK(f.r_sigma_ohm > (tv_real_t)0.0);
}

/* x = a^-1 b for a 3 x 3 system, by GSL's LU decomposition with partial pivoting (a is
 * overwritten). */
static void solve3(double a[3][3], double b[3], double x[3])
{
    gsl_matrix_view m = gsl_matrix_view_array(&a[0][0], 3, 3);
    gsl_vector_view bv = gsl_vector_view_array(b, 3);
    gsl_vector_view xv = gsl_vector_view_array(x, 3);
    size_t pdata[3];
    gsl_permutation perm;
    int sign;
    perm.size = 3;
    perm.data = pdata;
    TV_CHECK(gsl_linalg_LU_decomp(&m.matrix, &perm, &sign) == 0);
    TV_CHECK(gsl_linalg_LU_solve(&m.matrix, &perm, &bv.vector, &xv.vector) == 0);
}

/* The samples of test_offset_iv, kept to form the residuals afterwards. */
static double s_zs[1000][3];
static double s_xs[1000][3];
static double s_ys[1000];

/* The current's offset: a sensor that reads i + 0.05 A, an estimated velocity whose error follows
 * the motion (0.15 rad/s with the velocity's sign: what a unit's friction, not the model's, does to
 * the estimate) and a differentiated angle with noise (+-0.3 rad/s, a fixed pseudo-random
 * sequence). The instrumental-variable fit reads the offset within 2 mA (float: 3 mA); against the
 * non-centred 3 x 3 formulas worked out here in double precision (theta = (Z'X)^-1 Z'y, var(u0) =
 * s^2 [A^-1 Z'Z A^-T]_33, A = Z'X), b = -u0 / R_c and its sigma agree. */
static void test_offset_iv(void)
{
    vfit_config_t c;
    vfit_t f;
    double zx[3][3] = {{0}};
    double zz[3][3] = {{0}};
    double zy[3] = {0};
    double th[3];
    double rss = 0.0;
    uint32_t lcg = 12345u;
    int k;
    int took = 0;
    const double b_true = 0.05;
    vfit_config_default(&c);
    c.corr_periods = (tv_real_t)10.0;
    (void)vfit_init(&f, &c, (tv_real_t)L_H, (tv_real_t)TS_S);
    for (k = 0; k < 1000; ++k) {
        const double i0 = cur(k) + b_true;
        const double i1 = cur(k + 1) + b_true;
        const double w0 = vel(k) + (vel(k) >= 0.0 ? 0.15 : -0.15);
        const double w1 = vel(k + 1) + (vel(k + 1) >= 0.0 ? 0.15 : -0.15);
        const double u = volt(k, 4.3, 0.68);
        double v;
        lcg = lcg * 1664525u + 1013904223u;
        v = 0.5 * (vel(k) + vel(k + 1)) + 0.6 * ((double)(lcg >> 8) / 16777216.0 - 0.5);
        s_zs[k][0] = 0.5 * (i0 + i1);
        s_zs[k][1] = 0.5 * (w0 + w1);
        s_zs[k][2] = 1.0;
        s_xs[k][0] = s_zs[k][0];
        s_xs[k][1] = v;
        s_xs[k][2] = 1.0;
        s_ys[k] = u - L_H / TS_S * (i1 - i0);
        took |= vfit_step(&f, (tv_real_t)u, (tv_real_t)i0, (tv_real_t)i1, (tv_real_t)w0, (tv_real_t)w1, (tv_real_t)v);
    }
    TV_CHECK(took & VFIT_TOOK_OFFSET);
    TV_CHECK(f.off_valid == 1u);
    TV_CHECK_NEAR(f.i_off_A, b_true, TV_REAL_IS_DOUBLE ? 0.002 : 0.003);
    for (k = 0; k < 1000; ++k) {
        int a;
        int j;
        for (a = 0; a < 3; ++a) {
            for (j = 0; j < 3; ++j) {
                zx[a][j] += s_zs[k][a] * s_xs[k][j];
                zz[a][j] += s_zs[k][a] * s_zs[k][j];
            }
            zy[a] += s_zs[k][a] * s_ys[k];
        }
    }
    {
        double a[3][3];
        double rhs[3];
        memcpy(a, zx, sizeof a);
        memcpy(rhs, zy, sizeof rhs);
        solve3(a, rhs, th);
    }
    for (k = 0; k < 1000; ++k) {
        const double e = s_ys[k] - th[0] * s_xs[k][0] - th[1] * s_xs[k][1] - th[2];
        rss += e * e;
    }
    {
        /* [A^-1 Z'Z A^-T]_33 = g' Z'Z g with g the third row of A^-1: A^T g = e3 */
        double at[3][3];
        double e3[3] = {0.0, 0.0, 1.0};
        double g[3];
        double q = 0.0;
        int a;
        int j;
        for (a = 0; a < 3; ++a) {
            for (j = 0; j < 3; ++j) {
                at[a][j] = zx[j][a];
            }
        }
        solve3(at, e3, g);
        for (a = 0; a < 3; ++a) {
            for (j = 0; j < 3; ++j) {
                q += g[a] * zz[a][j] * g[j];
            }
        }
        {
            const double b_ref = -th[2] / th[0];
            const double sb_ref = sqrt(rss / 997.0 * 10.0 * q) / th[0];
            TV_CHECK_NEAR(f.i_off_A, b_ref, TV_REAL_IS_DOUBLE ? 1e-9 : 2e-3);
            TV_CHECK_NEAR(f.i_off_sigma_A, sb_ref, TV_REAL_IS_DOUBLE ? 1e-6 * sb_ref : 0.2 * sb_ref);
            TV_CHECK(f.i_off_sigma_A > (tv_real_t)0.0);
        }
    }
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
    TV_TEST_RUN(test_iv_bias_and_sigma);
    TV_TEST_RUN(test_offset_iv);
    TV_TEST_RUN(test_config_validation);
    return tv_test_summary();
}
