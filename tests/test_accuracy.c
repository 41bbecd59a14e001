/**
 * @file test_accuracy.c
 * @brief Issue 3's accuracy targets on the default scenario (the paper's 12 V / 5 Hz experiment,
 *        paper parameters, current noise 0.01 A, angle noise 1e-4 rad, 12-bit ADC), current +
 *        angle set-up, with the default Q and R of firmware/estimator/ekf.h (chosen by
 *        tools/tune_noise.py on TRAINING seeds 1001..1050; this test uses the disjoint
 *        EVALUATION seeds 1..50, so it checks the tuning rather than repeating it).
 *
 * Built twice: test_accuracy (double application) and test_accuracy_f32 (the float arithmetic
 * of the Cortex-M4F build).
 */
#include <stdio.h>

#include "sim.h"
#include "tv_test.h"

#define N_SEEDS 50u

static sim_mc_result_t s_mc;
static int s_mc_rc = -1;

static void run_monte_carlo(void)
{
    sim_options_t opt;
    sim_options_default(&opt);
    opt.seed = 1u;
    s_mc_rc = sim_monte_carlo(&opt, N_SEEDS, NULL, NULL, &s_mc);
}

static void print_row(const char *name, const double *r)
{
    printf("  %-28s current %.5f A   velocity %.4f rad/s   angle %.3e rad\n", name, r[0], r[1], r[2]);
}

static void test_velocity_rmse_within_target_and_4x_better_than_differentiation(void)
{
    const double *app = s_mc.rmse_mean[SIM_EST_APP];
    const double *meas = s_mc.rmse_mean[SIM_EST_MEASURED];
    TV_CHECK_EQ_INT(s_mc_rc, 0);
    printf("  mean RMSE over %u evaluation seeds:\n", N_SEEDS);
    print_row("app filter (current+angle)", app);
    print_row("paper set-up, our map", s_mc.rmse_mean[SIM_EST_PAPER_SETUP]);
    print_row("paper as printed", s_mc.rmse_mean[SIM_EST_PAPER_PRINTED]);
    print_row("measured / differentiated", meas);
    print_row("app filter, worst seed", s_mc.rmse_max[SIM_EST_APP]);
    /* Target: velocity RMSE <= 0.10 rad/s. Asserted on the WORST seed, not only the mean, so the
     * margin is the spread over seeds (measured: mean 0.040, worst 0.044). */
    TV_CHECK_LE(s_mc.rmse_max[SIM_EST_APP][1], 0.10);
    /* At least 4x lower than differentiating the measured angle (measured ratio ~18). */
    TV_CHECK_LE(4.0 * app[1], meas[1]);
}

static void test_angle_and_current_beat_their_sensors(void)
{
    const double *app = s_mc.rmse_mean[SIM_EST_APP];
    const double *meas = s_mc.rmse_mean[SIM_EST_MEASURED];
    TV_CHECK_EQ_INT(s_mc_rc, 0);
    /* Angle RMSE below the angle sensor's own error (noise + quantisation of the tracks);
     * current RMSE at most the current sensor's. Also on the worst seed against the mean
     * sensor error minus nothing: strict inequality per the issue. */
    TV_CHECK_LE(app[2], meas[2]);
    TV_CHECK(app[2] < meas[2]);
    TV_CHECK_LE(app[0], meas[0]);
    TV_CHECK_LE(s_mc.rmse_max[SIM_EST_APP][2], meas[2]);
}

static void test_nees_inside_95_percent_chi_square_band(void)
{
    TV_CHECK_EQ_INT(s_mc_rc, 0);
    printf("  ANEES %.3f over %u seeds x %u ticks; 95%% chi-square band of an %u-run average "
           "[%.3f, %.3f]; ANIS %.3f (%.1f dof)\n",
           s_mc.anees, N_SEEDS, s_mc.n_ticks_scored, N_SEEDS, s_mc.band_lo, s_mc.band_hi, s_mc.anis,
           s_mc.nis_dof_avg);
    /* The filter's sigma tells the truth: the average NEES (3 states) lies inside the two-sided
     * 95 % band chi2(3M)/M of an M-run average, M = 50. */
    TV_CHECK_LE(s_mc.band_lo, s_mc.anees);
    TV_CHECK_LE(s_mc.anees, s_mc.band_hi);
    TV_CHECK_EQ_INT(s_mc.runs_with_faults, 0);
    TV_CHECK_EQ_INT(s_mc.ekf_rejections, 0);
}

int main(void)
{
    run_monte_carlo();
    TV_TEST_RUN(test_velocity_rmse_within_target_and_4x_better_than_differentiation);
    TV_TEST_RUN(test_angle_and_current_beat_their_sensors);
    TV_TEST_RUN(test_nees_inside_95_percent_chi_square_band);
    return tv_test_summary();
}
