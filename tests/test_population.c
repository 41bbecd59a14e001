/**
 * @file test_population.c
 * @brief The throttle population (host_sim/plant/plant_draw.h), the per-unit ECU configuration
 *        (sim_unit.h), the consistency monitor (nis_monitor.h), the estimator's optional contact
 *        band and stop learning, and a small subset of the population benchmark (issue 10).
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "nis_monitor.h"
#include "plant.h"
#include "plant_draw.h"
#include "sim.h"
#include "sim_unit.h"
#include "tv_status.h"
#include "tv_test.h"

/* Every draw lies in the documented ranges, is reproducible, and is a valid plant. */
static void test_draws_stay_in_the_documented_ranges(void)
{
    uint64_t id;
    int c;
    for (c = 0; c < (int)PLANT_CLASS_COUNT; ++c) {
        plant_config_t nom;
        TV_CHECK_EQ_INT(plant_class_nominal((plant_class_t)c, &nom), TV_OK);
        for (id = 0; id < 200u; ++id) {
            plant_config_t s;
            plant_config_t a;
            plant_config_t again;
            const char *bad;
            double keff;
            TV_CHECK_EQ_INT(plant_draw((plant_class_t)c, PLANT_SPREAD_STOPS, id, &s), TV_OK);
            TV_CHECK_EQ_INT(plant_draw((plant_class_t)c, PLANT_SPREAD_ALL, id, &a), TV_OK);
            TV_CHECK_EQ_INT(plant_draw((plant_class_t)c, PLANT_SPREAD_ALL, id, &again), TV_OK);
            TV_CHECK(memcmp(&a, &again, sizeof a) == 0);
            bad = plant_config_check(&a, NULL);
            TV_CHECK(bad == NULL);
            TV_CHECK(s.phi_closed_rad >= -0.15 && s.phi_closed_rad <= -0.05);
            TV_CHECK(s.phi_open_rad >= 1.30 && s.phi_open_rad <= 1.50);
            keff = s.stop_k_Nm_rad * pow(0.0025, s.stop_exponent - 1.0);
            TV_CHECK(keff >= 1e2 * (1.0 - 1e-9) && keff <= 1e5 * (1.0 + 1e-9));
            TV_CHECK(s.stop_exponent >= 1.0 && s.stop_exponent <= 1.5);
            /* stops_varied keeps motor, friction and springs at the class nominal */
            TV_CHECK(s.R_ohm == nom.R_ohm && s.Mc_Nm == nom.Mc_Nm && s.M0_Nm == nom.M0_Nm && s.J_kg_m2 == nom.J_kg_m2);
            /* the same unit has the same stops in both spreads */
            TV_CHECK(a.phi_closed_rad == s.phi_closed_rad && a.phi_open_rad == s.phi_open_rad);
            TV_CHECK(a.R_ohm >= 0.8 * nom.R_ohm && a.R_ohm <= 1.2 * nom.R_ohm);
            TV_CHECK(a.L_H >= 0.8 * nom.L_H && a.L_H <= 1.2 * nom.L_H);
            TV_CHECK(a.Kt_Nm_A >= 0.9 * nom.Kt_Nm_A && a.Kt_Nm_A <= 1.1 * nom.Kt_Nm_A);
            TV_CHECK(fabs(a.Kt_Nm_A / nom.Kt_Nm_A - a.Ke_V_s_rad / nom.Ke_V_s_rad) < 1e-12);
            TV_CHECK(a.J_kg_m2 >= 0.8 * nom.J_kg_m2 && a.J_kg_m2 <= 1.2 * nom.J_kg_m2);
            TV_CHECK(a.Mc_Nm >= 0.7 * nom.Mc_Nm && a.Mc_Nm <= 1.3 * nom.Mc_Nm && a.Ms_Nm >= a.Mc_Nm);
            TV_CHECK(a.ws_rad_s >= 0.5 * nom.ws_rad_s && a.ws_rad_s <= 2.0 * nom.ws_rad_s);
            TV_CHECK(a.Kv_Nm_s_rad >= 0.5 * nom.Kv_Nm_s_rad && a.Kv_Nm_s_rad <= 1.5 * nom.Kv_Nm_s_rad);
            TV_CHECK(a.c_Nm_rad >= 0.8 * nom.c_Nm_rad && a.c_Nm_rad <= 1.2 * nom.c_Nm_rad);
            TV_CHECK(a.M0_Nm >= 0.8 * nom.M0_Nm && a.M0_Nm <= 1.2 * nom.M0_Nm);
        }
    }
    {
        plant_config_t x;
        TV_CHECK_EQ_INT(plant_draw(PLANT_CLASS_COUNT, PLANT_SPREAD_ALL, 1u, &x), TV_ERR_RANGE);
        TV_CHECK_EQ_INT(plant_draw(PLANT_CLASS_A, PLANT_SPREAD_COUNT, 1u, &x), TV_ERR_RANGE);
        TV_CHECK_EQ_INT(plant_draw(PLANT_CLASS_A, PLANT_SPREAD_ALL, 1u, NULL), TV_ERR_NULL);
    }
}

/* The ECU calibration of a unit reads the plant's angle and current back: checked against the
 * plant's own ADC conversion (noise off) at known states, within one count. */
static void test_unit_calibration_reads_the_plant_back(void)
{
    uint64_t id;
    for (id = 0; id < 20u; ++id) {
        const plant_class_t cls = id % 2u ? PLANT_CLASS_B : PLANT_CLASS_A;
        plant_config_t pc;
        app_config_t ac;
        plant_t p;
        double phi;
        TV_CHECK_EQ_INT(plant_draw(cls, PLANT_SPREAD_ALL, id, &pc), TV_OK);
        TV_CHECK_EQ_INT(sim_app_config_for_unit(cls, &pc, &ac), TV_OK);
        pc.current_noise_A = pc.angle_noise_rad = pc.tps_noise_V = pc.supply_noise_V = 0.0;
        TV_CHECK_EQ_INT(plant_init(&p, &pc, 1u), TV_OK);
        for (phi = pc.phi_closed_rad; phi <= pc.phi_open_rad; phi += 0.1) {
            plant_state_t st = {1.5, 0.0, 0.0};
            plant_adc_t adc;
            double a1;
            double a2;
            double i;
            st.angle_rad = phi;
            TV_CHECK_EQ_INT(plant_set_state(&p, &st), TV_OK);
            TV_CHECK_EQ_INT(plant_sample(&p, &adc), TV_OK);
            a1 = ((double)adc.tps1_counts - (double)ac.calib.tps1_counts_at_zero) * (double)ac.calib.tps1_rad_per_count;
            a2 = ((double)adc.tps2_counts - (double)ac.calib.tps2_counts_at_zero) * (double)ac.calib.tps2_rad_per_count;
            i = ((double)adc.current_counts - (double)ac.calib.current_offset_counts) * (double)ac.calib.current_A_per_count;
            TV_CHECK_LE(fabs(a1 - phi), 0.5 * (double)ac.calib.tps1_rad_per_count + 1e-9);
            TV_CHECK_LE(fabs(a2 - phi), 0.5 * -(double)ac.calib.tps2_rad_per_count + 1e-9);
            TV_CHECK_LE(fabs(i - 1.5), 0.5 * (double)ac.calib.current_A_per_count + 1e-9);
        }
        /* the filter runs on the class nominal, not on the unit */
        {
            plant_config_t nom;
            TV_CHECK_EQ_INT(plant_class_nominal(cls, &nom), TV_OK);
            TV_CHECK_NEAR((double)ac.model.R_ohm, nom.R_ohm, 1e-12);
            TV_CHECK_NEAR((double)ac.model.phi_open_rad, nom.phi_open_rad, 1e-12);
        }
    }
}

static void feed(nism_t *m, int ch, double nis, int n)
{
    int k;
    for (k = 0; k < n; ++k) {
        ekf_innov_t in;
        memset(&in, 0, sizeof in);
        in.used[ch] = 1u;
        in.nis[ch] = (tv_real_t)nis;
        in.n_used = 1u;
        (void)nism_update(m, &in);
    }
}

/* The monitor: silent at mean NIS 1, raises after trip_blocks failed blocks (not before), clears
 * on a passing block, counts episodes, and keeps channels apart. */
static void test_consistency_monitor_rule(void)
{
    nism_config_t c;
    nism_t m;
    nism_config_default(&c);
    TV_CHECK_EQ_INT(c.window, 100);
    TV_CHECK_EQ_INT(c.trip_blocks, 3);
    TV_CHECK_EQ_INT(nism_init(&m, &c), TV_OK);
    feed(&m, EKF_CH_ANGLE, 1.0, 1000);
    TV_CHECK_EQ_INT(m.flags, 0);
    feed(&m, EKF_CH_ANGLE, 20.0, 299);
    TV_CHECK_EQ_INT(m.flags, 0); /* two blocks and 99 corrections: not yet */
    feed(&m, EKF_CH_ANGLE, 20.0, 1);
    TV_CHECK_EQ_INT(m.flags, NISM_FLAG(EKF_CH_ANGLE));
    TV_CHECK_EQ_INT(m.episodes, 1);
    TV_CHECK_NEAR((double)m.last_mean[EKF_CH_ANGLE], 20.0, 1e-4);
    feed(&m, EKF_CH_CURRENT, 20.0, 300); /* the current channel on its own count */
    TV_CHECK_EQ_INT(m.flags, NISM_FLAG(EKF_CH_ANGLE) | NISM_FLAG(EKF_CH_CURRENT));
    feed(&m, EKF_CH_ANGLE, 1.0, 100);
    TV_CHECK_EQ_INT(m.flags, NISM_FLAG(EKF_CH_CURRENT));
    TV_CHECK_EQ_INT(m.episodes, 2);
    c.window = 0u;
    TV_CHECK_EQ_INT(nism_init(&m, &c), TV_ERR_CONFIG);
    nism_config_default(&c);
    c.threshold = TV_R(0.0);
    TV_CHECK_EQ_INT(nism_init(&m, &c), TV_ERR_CONFIG);
}

/* Contact band: the contact noise is added exactly when the predicted angle is within the band
 * of a stop (P with and without differ by Qc there and are equal elsewhere). The stuck-plate
 * noise is off in both filters (it does not act in the band: test_ekf's test_stuck_plate_noise). */
static void test_contact_band_adds_contact_noise_only_near_a_stop(void)
{
    tvm_params_t p;
    ekf_config_t c0;
    ekf_config_t c1;
    ekf_t a;
    ekf_t b;
    const double phis[3] = {0.5, -0.095, 1.36};
    int k;
    tvm_params_default(&p);
    ekf_config_default(&c0, EKF_SETUP_CURRENT_ANGLE);
    c0.stuck_q_min = TV_R(1.0);
    c1 = c0;
    c1.contact_band_rad = TV_R(0.02);
    c1.qc_Nm2_s = TV_R(1e-3);
    for (k = 0; k < 3; ++k) {
        int r;
        int s;
        const int near = k > 0;
        c0.x0[TVM_PHI] = c1.x0[TVM_PHI] = (tv_real_t)phis[k];
        TV_CHECK_EQ_INT(ekf_init(&a, &p, &c0), TV_OK);
        TV_CHECK_EQ_INT(ekf_init(&b, &p, &c1), TV_OK);
        TV_CHECK_EQ_INT(ekf_predict(&a, TV_R(0.0)), TV_OK);
        TV_CHECK_EQ_INT(ekf_predict(&b, TV_R(0.0)), TV_OK);
        for (r = 0; r < TVM_NX; ++r) {
            for (s = 0; s < TVM_NX; ++s) {
                const double expect = near ? (double)b.Qc[r][s] : 0.0;
                TV_CHECK_NEAR((double)(b.P[r][s] - a.P[r][s]), expect, 1e-6 * fabs(expect) + 1e-9 * fabs((double)a.P[r][s]) + 1e-15);
            }
        }
        TV_CHECK_EQ_INT(b.n_contact, near ? 1 : 0);
    }
    /* Qc is the torque-noise form: qc Ts / J^2 on the velocity */
    TV_CHECK_NEAR((double)b.Qc[TVM_W][TVM_W], 1e-3 * 1e-3 / (0.0016 * 0.0016), 1e-6);
    TV_CHECK_NEAR((double)b.Qc[TVM_I][TVM_I], 0.0, 0.0);
    c1.contact_band_rad = TV_R(-0.01);
    TV_CHECK_EQ_INT(ekf_init(&b, &p, &c1), TV_ERR_CONFIG);
}

/* Stop learning: a stop moves out to where the plate is seen beyond it (minus the margin) and
 * never moves in. */
static void test_stops_are_learned_outward_only(void)
{
    tvm_params_t p;
    ekf_config_t c;
    ekf_t e;
    ekf_meas_t m;
    tv_real_t lo;
    tv_real_t hi;
    int k;
    tvm_params_default(&p);
    ekf_config_default(&c, EKF_SETUP_CURRENT_ANGLE);
    c.stop_learn_margin_rad = TV_R(0.005);
    c.x0[TVM_PHI] = TV_R(1.42);
    c.P0[TVM_PHI][TVM_PHI] = TV_R(1e-6);
    TV_CHECK_EQ_INT(ekf_init(&e, &p, &c), TV_OK);
    m.z[EKF_CH_CURRENT] = TV_R(0.0);
    m.z[EKF_CH_VELOCITY] = TV_R(0.0);
    m.z[EKF_CH_ANGLE] = TV_R(1.42);
    TV_CHECK_EQ_INT(ekf_correct(&e, &m, NULL), TV_OK);
    ekf_stops(&e, &lo, &hi);
    TV_CHECK_NEAR((double)hi, (double)e.x[TVM_PHI] - 0.005, 1e-6);
    TV_CHECK_NEAR((double)lo, (double)p.phi_closed_rad, 0.0);
    TV_CHECK_EQ_INT(e.n_stop_moves, 1);
    /* the plate back inside: the stop stays where it was learned */
    for (k = 0; k < 50; ++k) {
        m.z[EKF_CH_ANGLE] = TV_R(0.5);
        (void)ekf_predict(&e, TV_R(0.0));
        (void)ekf_correct(&e, &m, NULL);
    }
    {
        tv_real_t hi2;
        ekf_stops(&e, &lo, &hi2);
        TV_CHECK_NEAR((double)hi2, (double)hi, 0.0);
    }
    /* off by default: the stops are the model's (or the start-up routine's); the contact band
     * is on, for the covariance inflation and the contact noise (EKF_DEFAULT_QC_NM2_S) */
    ekf_config_default(&c, EKF_SETUP_CURRENT_ANGLE);
    TV_CHECK_NEAR((double)c.stop_learn_margin_rad, 0.0, 0.0);
    TV_CHECK(c.contact_band_rad > TV_R(0.0) && c.qc_Nm2_s > TV_R(0.0));
}

/*
 * A subset of the population benchmark that the default filter passes today (issue 10 keeps
 * the targets of the full mix open): closed-loop steps and ramps and standstill on four
 * evaluation units of both classes, both spreads: no fault, the filter better than
 * differentiation by >= 1.3x in every run, run-average NEES in [1, 6] on the stops_varied
 * units. Figures of the full benchmark: tools/run_population.sh.
 */
static void test_population_subset_closed_loop_and_standstill(void)
{
    static const sim_scenario_t scn[3] = {SIM_SCN_CLOSED_STEPS, SIM_SCN_CLOSED_RAMP, SIM_SCN_STANDSTILL};
    uint64_t unit;
    int sp;
    for (sp = 0; sp < 2; ++sp) {
        const plant_spread_t spread = sp == 0 ? PLANT_SPREAD_STOPS : PLANT_SPREAD_ALL;
        for (unit = 1000u; unit < 1004u; ++unit) {
            const plant_class_t cls = unit % 3u == 2u ? PLANT_CLASS_B : PLANT_CLASS_A;
            static plant_config_t pc;
            static app_config_t ac;
            int k;
            TV_CHECK_EQ_INT(plant_draw(cls, spread, unit, &pc), TV_OK);
            TV_CHECK_EQ_INT(sim_app_config_for_unit(cls, &pc, &ac), TV_OK);
            for (k = 0; k < 3; ++k) {
                sim_options_t opt;
                sim_result_t r;
                double ratio;
                sim_options_default(&opt);
                opt.scenario = scn[k];
                opt.plant = &pc;
                opt.app = &ac;
                TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
                ratio = r.rmse[SIM_EST_MEASURED][TVM_W] / r.rmse[SIM_EST_APP][TVM_W];
                TV_CHECK_EQ_INT(r.faults, 0);
                TV_CHECK(ratio >= 1.3);
                if (spread == PLANT_SPREAD_STOPS) {
                    TV_CHECK(r.nees_avg >= 1.0 && r.nees_avg <= 6.0);
                }
                if (!(ratio >= 1.3) || r.faults != 0u) {
                    fprintf(stderr, "  unit %llu %s %s: ratio %.3g NEES %.3g faults 0x%x\n", (unsigned long long)unit,
                            plant_spread_name(spread), sim_scenario_name(opt.scenario), ratio, r.nees_avg,
                            (unsigned)r.faults);
                }
            }
        }
    }
}

/*
 * The case the winding-resistance error state was made for (README "Winding-resistance error
 * state"): all_varied evaluation unit 1020, whose winding is 3.59 ohm against the model's 4.3,
 * in open_steps (10 V against each stop for 0.5 s), after the start-up stop learning as the
 * benchmark runs it. With the state (the default) the filter beats differentiating the angle
 * (measured 2.13x) and its R + dR ends within 3 % of the plant's R (measured 0.0 %); without it
 * (ekf.qr_ohm2_s = 0) and without the consistency-driven inflation (ekf.nis_inflate_alpha = 0)
 * the current the model cannot explain is read as velocity at rest (measured 0.17x, the old
 * worst run of the benchmark); the inflation alone, its sigma widened by the large current
 * innovations, keeps it at 1.76x but does not know the winding.
 */
/* An all_varied unit, its filter configured for it and run through the start-up stop learning,
 * whose result goes into the filter as the application puts it (as the benchmark runs it). */
static void learned_unit(plant_class_t cls, uint64_t unit, plant_config_t *pc, app_config_t *ac)
{
    sim_options_t opt;
    sim_result_t r;
    TV_CHECK_EQ_INT(plant_draw(cls, PLANT_SPREAD_ALL, unit, pc), TV_OK);
    TV_CHECK_EQ_INT(sim_app_config_for_unit(cls, pc, ac), TV_OK);
    sim_options_default(&opt);
    opt.scenario = SIM_SCN_STOP_LEARN;
    opt.plant = pc;
    opt.app = ac;
    TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
    TV_CHECK_EQ_INT(r.stop_learn_phase, SL_DONE);
    TV_CHECK_EQ_INT(sim_apply_stop_learning(&r, ac), TV_OK);
}

static double unit_1020_open_steps_ratio(int with_dr, int with_inflation, double *r_err_rel)
{
    static plant_config_t pc;
    static app_config_t ac;
    sim_options_t opt;
    sim_result_t r;
    learned_unit(PLANT_CLASS_A, 1020u, &pc, &ac);
    if (!with_dr) {
        ac.ekf.qr_ohm2_s = TV_R(0.0);
    }
    if (!with_inflation) {
        ac.ekf.nis_inflate_alpha = TV_R(0.0);
    }
    sim_options_default(&opt);
    opt.scenario = SIM_SCN_OPEN_STEPS;
    opt.plant = &pc;
    opt.app = &ac;
    TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
    TV_CHECK_EQ_INT(r.faults, 0);
    *r_err_rel = (r.r_est_ohm - r.r_true_ohm) / r.r_true_ohm;
    return r.rmse[SIM_EST_MEASURED][TVM_W] / r.rmse[SIM_EST_APP][TVM_W];
}

static void test_resistance_error_state_on_a_low_resistance_unit(void)
{
    double r_err;
    double r_err_off;
    double r_err_bare;
    const double with_dr = unit_1020_open_steps_ratio(1, 1, &r_err);
    const double without = unit_1020_open_steps_ratio(0, 1, &r_err_off);
    const double bare = unit_1020_open_steps_ratio(0, 0, &r_err_bare);
    printf("  unit 1020 (all_varied) open_steps: %.2fx differentiation with dR (R estimated within %+.2f %% of the "
           "plant's), %.2fx without it (R off by %+.1f %%; the consistency-driven inflation widens sigma), %.2fx "
           "without either\n",
           with_dr, 100.0 * r_err, without, 100.0 * r_err_off, bare);
    TV_CHECK(with_dr >= 1.5);
    /* the winding 20 % off the model with neither remedy: worse than differentiating the angle;
     * the inflation alone keeps the filter useful, the dR state also knows the winding */
    TV_CHECK(bare < 1.0);
    TV_CHECK(without >= 1.5);
    /* the estimate against the plant's own R (plant_draw), issue 11's +-5 % with margin */
    TV_CHECK(fabs(r_err) <= 0.03);
}

/*
 * The resistance estimate holds while the bridge is open. Found on all_varied unit 1013 (class b)
 * in limp_home: the plate, returning under its springs with the bridge off, hits the closed stop
 * at 13 rad/s; the voltage the model holds for the open bridge (the back-EMF of the period before)
 * then drives a predicted current of -2.5 A through the reversing plate, which the plant does not
 * carry (the bridge is open), and the update read the 2.5 A innovation as a winding 0.45 ohm
 * higher. dR is now frozen when the measured current is small as well.
 */
typedef struct {
    double r_first;  /* R + dR at the first tick of an open-bridge phase */
    double dr_max;   /* largest change of R + dR within one open-bridge phase */
    int open;        /* in an open-bridge phase */
} open_bridge_t;

static void open_bridge_row(const sim_row_t *row, void *user)
{
    open_bridge_t *o = (open_bridge_t *)user;
    if (row->bridge_enable) {
        o->open = 0;
        return;
    }
    if (!o->open) {
        o->open = 1;
        o->r_first = row->r_est_ohm;
    }
    if (fabs(row->r_est_ohm - o->r_first) > o->dr_max) {
        o->dr_max = fabs(row->r_est_ohm - o->r_first);
    }
}

static void test_resistance_holds_while_the_bridge_is_open(void)
{
    static plant_config_t pc;
    static app_config_t ac;
    sim_options_t opt;
    sim_result_t r;
    open_bridge_t o = {0.0, 0.0, 0};
    learned_unit(PLANT_CLASS_B, 1013u, &pc, &ac);
    sim_options_default(&opt);
    opt.scenario = SIM_SCN_LIMP_HOME;
    opt.plant = &pc;
    opt.app = &ac;
    opt.row_fn = open_bridge_row;
    opt.row_user = &o;
    TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
    printf("  unit 1013 (class b) limp_home: R + dR moved at most %.4f ohm while the bridge was open; %.4f ohm at the "
           "end (plant %.4f)\n",
           o.dr_max, r.r_est_ohm, r.r_true_ohm);
    TV_CHECK_LE(o.dr_max, 0.01);
    TV_CHECK(fabs(r.r_est_ohm - r.r_true_ohm) <= 0.05 * r.r_true_ohm);
}

int main(void)
{
    TV_TEST_RUN(test_draws_stay_in_the_documented_ranges);
    TV_TEST_RUN(test_unit_calibration_reads_the_plant_back);
    TV_TEST_RUN(test_consistency_monitor_rule);
    TV_TEST_RUN(test_contact_band_adds_contact_noise_only_near_a_stop);
    TV_TEST_RUN(test_stops_are_learned_outward_only);
    TV_TEST_RUN(test_population_subset_closed_loop_and_standstill);
    TV_TEST_RUN(test_resistance_holds_while_the_bridge_is_open);
    TV_TEST_RUN(test_resistance_error_state_on_a_low_resistance_unit);
    return tv_test_summary();
}
