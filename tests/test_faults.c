/**
 * @file test_faults.c
 * @brief Fault injection (host_sim/plant/plant_fault.h, plant_set_faults()): the specification
 *        parser (every kind, every kind of bad input), the schedule (onset, ramp), and each
 *        fault's physical effect on the plant against an expectation worked out by hand from
 *        the plant's documented equations (plant.h), not from the code under test; then one
 *        closed-loop simulation with a jam.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "plant.h"
#include "plant_fault.h"
#include "sim.h"
#include "tv_status.h"
#include "tv_test.h"

/* Default plant with every noise off, so counts and voltages are exact. */
static void quiet_cfg(plant_config_t *c)
{
    plant_config_default(c);
    c->current_noise_A = 0.0;
    c->angle_noise_rad = 0.0;
    c->supply_noise_V = 0.0;
}

static void quiet_plant(plant_t *p)
{
    plant_config_t c;
    quiet_cfg(&c);
    TV_CHECK_EQ_INT(plant_init(p, &c, 1u), TV_OK);
}

/* One fault at full size, from now on. */
static int set_fault(plant_t *p, const char *spec)
{
    plant_fault_list_t l;
    plant_faults_t f;
    plant_fault_list_clear(&l);
    if (plant_fault_list_add(&l, spec, NULL, 0u) != TV_OK) {
        return -100;
    }
    l.spec[0].t_s = 0.0;
    l.spec[0].ramp_s = 0.0;
    (void)plant_fault_at(&l, 0.0, p->cfg_nominal.tps_supply_V, &f);
    return plant_set_faults(p, &f);
}

static void set_angle(plant_t *p, double phi)
{
    plant_state_t s = {0.0, 0.0, 0.0};
    s.angle_rad = phi;
    TV_CHECK_EQ_INT(plant_set_state(p, &s), TV_OK);
}

static double angle(const plant_t *p)
{
    plant_state_t s;
    (void)plant_truth(p, &s);
    return s.angle_rad;
}

static void test_parser_accepts_every_kind_with_its_numbers(void)
{
    plant_fault_spec_t f;
    TV_CHECK_EQ_INT(plant_fault_parse("friction_high:2.0@1.5", &f, NULL, 0u), TV_OK);
    TV_CHECK_EQ_INT(f.kind, PLANT_FAULT_FRICTION_HIGH);
    TV_CHECK_NEAR(f.magnitude, 2.0, 0.0);
    TV_CHECK_NEAR(f.t_s, 1.5, 0.0);
    TV_CHECK_NEAR(f.ramp_s, 0.0, 0.0);
    TV_CHECK_EQ_INT(plant_fault_parse("tps1_offset:-1@0.5:0.25", &f, NULL, 0u), TV_OK);
    TV_CHECK_EQ_INT(f.kind, PLANT_FAULT_TPS1_OFFSET);
    TV_CHECK_NEAR(f.magnitude, -1.0, 0.0);
    TV_CHECK_NEAR(f.ramp_s, 0.25, 0.0);
    TV_CHECK_EQ_INT(plant_fault_parse("winding_open@0", &f, NULL, 0u), TV_OK);
    TV_CHECK_EQ_INT(f.kind, PLANT_FAULT_WINDING_OPEN);
    TV_CHECK_NEAR(f.magnitude, 1.0, 0.0);
    {
        /* every kind by its own name, with a magnitude inside its range where it takes one */
        static const char *const ok[PLANT_FAULT_KIND_COUNT] = {
            "friction_high:3@1",    "jam:5@1",           "spring_weak:0@1",         "winding_resistance_high:2@1",
            "winding_open@1",       "winding_short:0.3@1", "tps1_offset:1@1",       "tps1_gain:-5@1",
            "tps1_stuck@1",         "tps1_intermittent:0.5@1", "tps2_offset:-2@1",   "tps2_gain:5@1",
            "tps2_stuck@1",         "tps2_intermittent:1@1", "current_offset:0.05@1", "current_gain:5@1",
            "bridge_pos_lost@1",    "bridge_neg_lost@1", "supply_sag:4@1"};
        int k;
        for (k = 0; k < (int)PLANT_FAULT_KIND_COUNT; ++k) {
            TV_CHECK_EQ_INT(plant_fault_parse(ok[k], &f, NULL, 0u), TV_OK);
            TV_CHECK_EQ_INT(f.kind, k);
            TV_CHECK(strcmp(plant_fault_kind_class(f.kind), "?") != 0);
        }
        TV_CHECK(strcmp(plant_fault_kind_class(PLANT_FAULT_TPS2_STUCK), "tps2_fault") == 0);
        TV_CHECK(strcmp(plant_fault_kind_class(PLANT_FAULT_CURRENT_GAIN), "current_sensor_fault") == 0);
    }
}

static void test_parser_rejects_bad_specs_and_says_why(void)
{
    static const struct {
        const char *text;
        int status;
        const char *says;
    } bad[] = {
        {"friction_high:2", TV_ERR_FORMAT, "no '@'"},
        {"friction_high:2@1@2", TV_ERR_FORMAT, "more than one '@'"},
        {"friction:2@1", TV_ERR_FORMAT, "'friction' is not a fault kind"},
        {"friction_high@1", TV_ERR_FORMAT, "needs a magnitude"},
        {"friction_high:@1", TV_ERR_FORMAT, "magnitude '' is not"},
        {"friction_high:2x@1", TV_ERR_FORMAT, "magnitude '2x' is not"},
        {"friction_high:inf@1", TV_ERR_NONFINITE, "not a finite number"},
        {"friction_high:1@1", TV_ERR_RANGE, "out of range"},
        {"friction_high:10.5@1", TV_ERR_RANGE, "out of range"},
        {"spring_weak:1@1", TV_ERR_RANGE, "[0, 1)"},
        {"spring_weak:-0.1@1", TV_ERR_RANGE, "out of range"},
        {"tps1_offset:0@1", TV_ERR_RANGE, "out of range"},
        {"tps1_offset:51@1", TV_ERR_RANGE, "out of range"},
        {"tps1_gain:-100@1", TV_ERR_RANGE, "out of range"},
        {"current_gain:-150@1", TV_ERR_RANGE, "out of range"},
        {"jam:0@1", TV_ERR_RANGE, "out of range"},
        {"jam:5@1:0.1", TV_ERR_FORMAT, "cannot drift"},
        {"winding_open:1@1", TV_ERR_FORMAT, "takes no magnitude"},
        {"tps1_stuck@1:0.5", TV_ERR_FORMAT, "cannot drift"},
        {"friction_high:2@-1", TV_ERR_RANGE, "onset time -1 s is out of range"},
        {"friction_high:2@601", TV_ERR_RANGE, "onset time 601 s"},
        {"friction_high:2@nan", TV_ERR_NONFINITE, "onset time"},
        {"friction_high:2@1:0", TV_ERR_RANGE, "ramp 0 s is out of range"},
        {"friction_high:2@1:", TV_ERR_FORMAT, "ramp '' is not"},
        {"friction_high:2@ 1", TV_ERR_FORMAT, "onset time ' 1'"},
        {"", TV_ERR_FORMAT, "no '@'"},
    };
    size_t k;
    plant_fault_spec_t f;
    plant_fault_spec_t keep;
    memset(&keep, 0x5A, sizeof keep);
    for (k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        char msg[PLANT_FAULT_MSG_MAX];
        msg[0] = '\0';
        f = keep;
        TV_CHECK_EQ_INT(plant_fault_parse(bad[k].text, &f, msg, sizeof msg), bad[k].status);
        if (strstr(msg, bad[k].says) == NULL) {
            fprintf(stderr, "  '%s': message '%s' lacks '%s'\n", bad[k].text, msg, bad[k].says);
        }
        TV_CHECK(strstr(msg, bad[k].says) != NULL);
        TV_CHECK(memcmp(&f, &keep, sizeof f) == 0); /* not written on error */
    }
    TV_CHECK_EQ_INT(plant_fault_parse(NULL, &f, NULL, 0u), TV_ERR_NULL);
    {
        plant_fault_list_t l;
        char msg[PLANT_FAULT_MSG_MAX];
        plant_fault_list_clear(&l);
        TV_CHECK_EQ_INT(plant_fault_list_add(&l, "jam:5@1", msg, sizeof msg), TV_OK);
        TV_CHECK_EQ_INT(plant_fault_list_add(&l, "jam:6@2", msg, sizeof msg), TV_ERR_RANGE);
        TV_CHECK(strstr(msg, "jam given twice") != NULL);
        TV_CHECK_EQ_INT(plant_fault_list_add(&l, "bridge_pos_lost@1", msg, sizeof msg), TV_OK);
        TV_CHECK_EQ_INT(plant_fault_list_add(&l, "bridge_neg_lost@1", msg, sizeof msg), TV_ERR_RANGE);
        TV_CHECK_EQ_INT(l.n, 2);
    }
}

static void test_schedule_onset_and_ramp(void)
{
    plant_fault_list_t l;
    plant_faults_t f;
    plant_fault_list_clear(&l);
    TV_CHECK_EQ_INT(plant_fault_list_add(&l, "friction_high:3@1:2", NULL, 0u), TV_OK);
    TV_CHECK_EQ_INT(plant_fault_list_add(&l, "tps2_offset:-2@0.5", NULL, 0u), TV_OK);
    (void)plant_fault_at(&l, 0.499, 5.0, &f);
    TV_CHECK_NEAR(f.friction_factor, 1.0, 0.0);
    TV_CHECK_NEAR(f.tps_offset_V[1], 0.0, 0.0);
    (void)plant_fault_at(&l, 0.5, 5.0, &f);
    TV_CHECK_NEAR(f.tps_offset_V[1], -0.1, 1e-15); /* -2 % of 5 V */
    TV_CHECK_NEAR(f.friction_factor, 1.0, 0.0);
    (void)plant_fault_at(&l, 2.0, 5.0, &f); /* half-way: 1 + 0.5 (3 - 1) */
    TV_CHECK_NEAR(f.friction_factor, 2.0, 1e-15);
    (void)plant_fault_at(&l, 3.0, 5.0, &f); /* T + RAMP: the full magnitude */
    TV_CHECK_NEAR(f.friction_factor, 3.0, 1e-15);
    (void)plant_fault_at(&l, 100.0, 5.0, &f);
    TV_CHECK_NEAR(f.friction_factor, 3.0, 0.0);
}

/* Drive the plant with a duty for dt_s (1 ms steps). */
static void drive(plant_t *p, double duty, double dt_s)
{
    int k;
    const int n = (int)(dt_s * 1e3 + 0.5);
    TV_CHECK_EQ_INT(plant_set_bridge(p, duty, 1), TV_OK);
    for (k = 0; k < n; ++k) {
        TV_CHECK_EQ_INT(plant_advance(p, 1e-3), TV_OK);
    }
}

static void test_jam_blocks_the_plate_at_its_angle(void)
{
    /* full duty both ways: the motor's stall torque n Kt Vs / R = 40 0.017 13.5 / 4.3 = 2.13 N m,
     * plus springs < 0.4 N m, is far below Ms + 10 N m: the plate cannot move at all. */
    plant_t p;
    double phi0;
    int k;
    quiet_plant(&p);
    drive(&p, 0.6, 0.03); /* moving */
    TV_CHECK(fabs(p.velocity_rad_s) > 1.0);
    TV_CHECK_EQ_INT(set_fault(&p, "jam:10@0"), TV_OK);
    phi0 = angle(&p);
    TV_CHECK_NEAR(p.velocity_rad_s, 0.0, 0.0);
    for (k = 0; k < 10; ++k) {
        drive(&p, k % 2 ? -1.0 : 1.0, 0.05);
        TV_CHECK_NEAR(angle(&p), phi0, 0.0);
    }
}

static void test_winding_open_current_zero(void)
{
    plant_t p;
    plant_adc_t a;
    quiet_plant(&p);
    drive(&p, 0.5, 0.02);
    TV_CHECK(fabs(p.current_A) > 0.5);
    TV_CHECK_EQ_INT(set_fault(&p, "winding_open@0"), TV_OK);
    drive(&p, 0.9, 0.05);
    TV_CHECK_NEAR(p.current_A, 0.0, 0.0);
    TV_CHECK_EQ_INT(plant_sample(&p, &a), TV_OK);
    TV_CHECK_EQ_INT(a.current_counts, 2048); /* 1.65 V at 4096 / 3.3 counts/V */
}

/* Plate at 0.5 rad at rest, constant motor torque net_Nm above the springs; returns |moved| after 0.2 s. */
static double breakaway_move(const char *fault, double net_Nm)
{
    plant_t p;
    double phi0;
    /* springs at 0.5 rad: M0 + c phi = 0.25 + 0.059 * 0.5; stall torque n Kt u / R */
    const double u_V = (net_Nm + 0.25 + 0.059 * 0.5) * 4.3 / (40.0 * 0.017);
    quiet_plant(&p);
    set_angle(&p, 0.5);
    if (fault != NULL) {
        TV_CHECK_EQ_INT(set_fault(&p, fault), TV_OK);
    }
    phi0 = angle(&p);
    drive(&p, u_V / 13.5, 0.2);
    return fabs(angle(&p) - phi0);
}

static void test_friction_high_scales_the_breakaway_torque(void)
{
    /* healthy Ms = 0.3 N m: 0.45 N m of net torque breaks away; x2 (0.6 N m) holds it, 0.75 breaks */
    TV_CHECK(breakaway_move(NULL, 0.45) > 0.01);
    TV_CHECK_NEAR(breakaway_move("friction_high:2@0", 0.45), 0.0, 0.0);
    TV_CHECK(breakaway_move("friction_high:2@0", 0.75) > 0.01);
    TV_CHECK_NEAR(breakaway_move("friction_high:2@0", 0.55), 0.0, 0.0);
}

static void test_spring_weak_no_longer_returns_the_plate(void)
{
    /* bridge off at 1.0 rad: healthy spring torque 0.25 + 0.059 = 0.309 N m > Ms 0.3: the plate
     * returns; at 50 % it is 0.155 N m < 0.3: it stays exactly. */
    plant_t p;
    int k;
    quiet_plant(&p);
    set_angle(&p, 1.0);
    for (k = 0; k < 500; ++k) {
        (void)plant_advance(&p, 1e-3);
    }
    TV_CHECK(angle(&p) < 0.9);
    quiet_plant(&p);
    set_angle(&p, 1.0);
    TV_CHECK_EQ_INT(set_fault(&p, "spring_weak:0.5@0"), TV_OK);
    for (k = 0; k < 500; ++k) {
        (void)plant_advance(&p, 1e-3);
    }
    TV_CHECK_NEAR(angle(&p), 1.0, 0.0);
}

/* Steady current under u = 1 V with the plate held at limp-home (0.16 N m < the preload 0.25). */
static double locked_current(const char *fault)
{
    plant_t p;
    quiet_plant(&p);
    if (fault != NULL) {
        TV_CHECK_EQ_INT(set_fault(&p, fault), TV_OK);
    }
    drive(&p, 1.0 / 13.5, 0.05);
    TV_CHECK_NEAR(p.velocity_rad_s, 0.0, 0.0);
    return p.current_A;
}

static void test_winding_resistance_and_short_change_the_locked_current(void)
{
    /* i = u / R at rest after 100 L/R; 1 V / 4.3 ohm; x1.5; a 30 % short: R x 0.7 */
    TV_CHECK_NEAR(locked_current(NULL), 1.0 / 4.3, 1e-9);
    TV_CHECK_NEAR(locked_current("winding_resistance_high:1.5@0"), 1.0 / (4.3 * 1.5), 1e-9);
    TV_CHECK_NEAR(locked_current("winding_short:0.3@0"), 1.0 / (4.3 * 0.7), 1e-9);
}

static void test_bridge_direction_lost_and_supply_sag(void)
{
    plant_t p;
    double v;
    plant_adc_t a;
    quiet_plant(&p);
    TV_CHECK_EQ_INT(set_fault(&p, "bridge_pos_lost@0"), TV_OK);
    drive(&p, 0.5, 0.01);
    (void)plant_bridge_voltage(&p, &v);
    TV_CHECK_NEAR(v, 0.0, 0.0);
    drive(&p, -0.5, 0.001);
    (void)plant_bridge_voltage(&p, &v);
    TV_CHECK_NEAR(v, -6.75, 1e-12);
    quiet_plant(&p);
    TV_CHECK_EQ_INT(set_fault(&p, "supply_sag:3@0"), TV_OK);
    drive(&p, 0.5, 0.001);
    (void)plant_bridge_voltage(&p, &v);
    TV_CHECK_NEAR(v, 0.5 * 10.5, 1e-12);
    TV_CHECK_EQ_INT(plant_sample(&p, &a), TV_OK);
    TV_CHECK_EQ_INT(a.supply_counts, (int)floor(10.5 / 6.0 * 4096.0 / 3.3 + 0.5));
    /* a sag larger than the supply is refused and changes nothing */
    TV_CHECK_EQ_INT(set_fault(&p, "supply_sag:14@0"), TV_ERR_RANGE);
    TV_CHECK_NEAR(p.cfg.supply_V, 10.5, 0.0);
}

static void test_sensor_faults_move_the_counts_as_documented(void)
{
    plant_t h;
    plant_t f;
    plant_adc_t ah;
    plant_adc_t af;
    const double cpv = 4096.0 / 3.3;
    int k;
    int zeros = 0;
    /* track 1 offset 1 % of 5 V = 50 mV at the track, 33 mV at the pin: 40.96 counts */
    quiet_plant(&h);
    quiet_plant(&f);
    set_angle(&h, 0.4);
    set_angle(&f, 0.4);
    TV_CHECK_EQ_INT(set_fault(&f, "tps1_offset:1@0"), TV_OK);
    (void)plant_sample(&h, &ah);
    (void)plant_sample(&f, &af);
    TV_CHECK_NEAR(af.tps1_pin_V - ah.tps1_pin_V, 0.033, 1e-12);
    TV_CHECK_NEAR((double)af.tps1_counts - (double)ah.tps1_counts, 40.96, 0.5 + 1e-9);
    TV_CHECK_EQ_INT(af.tps2_counts, ah.tps2_counts);
    /* track 1 gain +5 %: the pin voltage x 1.05 */
    quiet_plant(&f);
    set_angle(&f, 0.4);
    TV_CHECK_EQ_INT(set_fault(&f, "tps1_gain:5@0"), TV_OK);
    (void)plant_sample(&f, &af);
    TV_CHECK_NEAR(af.tps1_pin_V, 1.05 * ah.tps1_pin_V, 1e-12);
    /* current offset 50 mA: + 0.1 V/A x 0.05 A at the pin; gain 5 %: (pin - 1.65) x 1.05 */
    quiet_plant(&h);
    quiet_plant(&f);
    TV_CHECK_EQ_INT(set_fault(&f, "current_offset:0.05@0"), TV_OK);
    drive(&h, 0.3, 0.005);
    drive(&f, 0.3, 0.005);
    (void)plant_sample(&h, &ah);
    (void)plant_sample(&f, &af);
    TV_CHECK_NEAR(af.current_pin_V - ah.current_pin_V, 0.005, 1e-12);
    quiet_plant(&f);
    TV_CHECK_EQ_INT(set_fault(&f, "current_gain:5@0"), TV_OK);
    drive(&f, 0.3, 0.005);
    (void)plant_sample(&f, &af);
    TV_CHECK_NEAR(af.current_pin_V - 1.65, 1.05 * (ah.current_pin_V - 1.65), 1e-12);
    /* track 2 stuck: its counts stay while the plate moves 0.3 rad; track 1 follows */
    quiet_plant(&f);
    set_angle(&f, 0.2);
    TV_CHECK_EQ_INT(set_fault(&f, "tps2_stuck@0"), TV_OK);
    (void)plant_sample(&f, &ah);
    set_angle(&f, 0.5);
    (void)plant_sample(&f, &af);
    TV_CHECK_EQ_INT(af.tps2_counts, ah.tps2_counts);
    TV_CHECK((double)af.tps1_counts - (double)ah.tps1_counts > 0.3 / (1.4660766 / (0.8 * 4096.0)) - 2.0);
    /* intermittent track 1 at 20 %: the share of 0-count samples over 20,000 within 5 sigma of
     * the binomial (sigma = sqrt(0.2 0.8 / 20000) = 0.0028) */
    quiet_plant(&f);
    set_angle(&f, 0.4);
    TV_CHECK_EQ_INT(set_fault(&f, "tps1_intermittent:0.2@0"), TV_OK);
    for (k = 0; k < 20000; ++k) {
        (void)plant_sample(&f, &af);
        zeros += af.tps1_counts == 0u;
        TV_CHECK(af.tps2_counts > 1000u || k > 0); /* track 2 untouched (one check suffices) */
    }
    TV_CHECK_NEAR((double)zeros / 20000.0, 0.2, 5.0 * 0.0028);
    (void)cpv;
}

static void test_ramp_reaches_the_magnitude_at_onset_plus_ramp(void)
{
    /* supply_sag:4@0.1:0.2: bridge voltage at full duty 13.5 - 4 a, a = (t - 0.1) / 0.2 */
    plant_fault_list_t l;
    plant_faults_t f;
    plant_t p;
    double v;
    const double t[] = {0.05, 0.1, 0.2, 0.3, 0.5};
    const double expect_V[] = {13.5, 13.5, 11.5, 9.5, 9.5};
    int k;
    plant_fault_list_clear(&l);
    TV_CHECK_EQ_INT(plant_fault_list_add(&l, "supply_sag:4@0.1:0.2", NULL, 0u), TV_OK);
    quiet_plant(&p);
    for (k = 0; k < 5; ++k) {
        (void)plant_fault_at(&l, t[k], 5.0, &f);
        TV_CHECK_EQ_INT(plant_set_faults(&p, &f), TV_OK);
        drive(&p, 1.0, 0.001);
        (void)plant_bridge_voltage(&p, &v);
        TV_CHECK_NEAR(v, expect_V[k], 1e-12);
    }
}

/* row callback: the plant angle from the first tick at or after 1.01 s */
typedef struct {
    double phi_at;
    double max_dev;
    int seen;
} jam_watch_t;

static void jam_row(const sim_row_t *row, void *user)
{
    jam_watch_t *w = (jam_watch_t *)user;
    if (row->t_s >= 1.01 - 1e-9) {
        if (!w->seen) {
            w->phi_at = row->truth[TVM_PHI];
            w->seen = 1;
        }
        if (fabs(row->truth[TVM_PHI] - w->phi_at) > w->max_dev) {
            w->max_dev = fabs(row->truth[TVM_PHI] - w->phi_at);
        }
    }
}

static void test_sim_run_injects_at_the_onset_tick(void)
{
    /* closed_steps, a jam at 1.01 s (the plate is moving from 0.8 toward 0.05 rad then): the plant angle is
     * exactly constant from the 1.01 s tick on, while the controller pushes */
    sim_options_t opt;
    sim_result_t r;
    sim_result_t r0;
    sim_result_t r1;
    plant_fault_list_t l;
    jam_watch_t w = {0.0, 0.0, 0};
    sim_options_default(&opt);
    opt.scenario = SIM_SCN_CLOSED_STEPS;
    plant_fault_list_clear(&l);
    TV_CHECK_EQ_INT(plant_fault_list_add(&l, "jam:10@1.01", NULL, 0u), TV_OK);
    opt.faults = &l;
    opt.row_fn = jam_row;
    opt.row_user = &w;
    TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
    TV_CHECK(w.seen);
    TV_CHECK_NEAR(w.max_dev, 0.0, 0.0);
    TV_CHECK(fabs(w.phi_at - 0.05) > 0.1); /* blocked before reaching its target */
    /* a fault after the end of the run changes nothing: bit-identical to the healthy run */
    opt.row_fn = NULL;
    plant_fault_list_clear(&l);
    TV_CHECK_EQ_INT(plant_fault_list_add(&l, "friction_high:3@100", NULL, 0u), TV_OK);
    TV_CHECK_EQ_INT(sim_run(&opt, &r1), TV_OK);
    opt.faults = NULL;
    TV_CHECK_EQ_INT(sim_run(&opt, &r0), TV_OK);
    TV_CHECK(memcmp(r0.rmse, r1.rmse, sizeof r0.rmse) == 0);
    TV_CHECK_NEAR(r0.nees_avg, r1.nees_avg, 0.0);
    /* a sag above the unit's supply is refused before the run */
    plant_fault_list_clear(&l);
    TV_CHECK_EQ_INT(plant_fault_list_add(&l, "supply_sag:20@1", NULL, 0u), TV_OK);
    opt.faults = &l;
    TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_ERR_CONFIG);
}

int main(void)
{
    TV_TEST_RUN(test_parser_accepts_every_kind_with_its_numbers);
    TV_TEST_RUN(test_parser_rejects_bad_specs_and_says_why);
    TV_TEST_RUN(test_schedule_onset_and_ramp);
    TV_TEST_RUN(test_jam_blocks_the_plate_at_its_angle);
    TV_TEST_RUN(test_winding_open_current_zero);
    TV_TEST_RUN(test_friction_high_scales_the_breakaway_torque);
    TV_TEST_RUN(test_spring_weak_no_longer_returns_the_plate);
    TV_TEST_RUN(test_winding_resistance_and_short_change_the_locked_current);
    TV_TEST_RUN(test_bridge_direction_lost_and_supply_sag);
    TV_TEST_RUN(test_sensor_faults_move_the_counts_as_documented);
    TV_TEST_RUN(test_ramp_reaches_the_magnitude_at_onset_plus_ramp);
    TV_TEST_RUN(test_sim_run_injects_at_the_onset_tick);
    return tv_test_summary();
}
