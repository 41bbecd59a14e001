/**
 * @file test_fault_cond.c
 * @brief host_sim/sim/sim_fault_cond.h on scripted rows: the time each fault's observable
 *        condition is met, worked out by hand per case (independent of any simulation).
 */
#include <math.h>
#include <string.h>

#include "diag_detect.h"
#include "sim_fault_cond.h"
#include "tv_test.h"

/* The default plant: stops -0.10 / 1.366 rad, Ms 0.3 N m, M0 0.25 N m, c 0.059 N m/rad,
 * R 4.3 ohm, n 40, Kt = Ke 0.017. */
static plant_config_t s_pc;

static void faults_one(plant_fault_list_t *l, plant_fault_kind_t kind, double t_s)
{
    memset(l, 0, sizeof *l);
    l->spec[0].kind = kind;
    l->spec[0].magnitude = 1.0;
    l->spec[0].t_s = t_s;
    l->n = 1u;
}

/* One row at k ms: true angle phi, true velocity w, applied voltage u, bridge, target (NaN: open
 * loop), confirmed codes. */
static void row_at(sim_cond_t *c, int k, double phi, double w, double u, int bridge, double target, uint32_t dtc)
{
    sim_row_t r;
    memset(&r, 0, sizeof r);
    r.t_s = (double)k * 1e-3;
    r.truth[TVM_PHI] = phi;
    r.truth[TVM_W] = w;
    r.u_applied_V = u;
    r.bridge_enable = bridge;
    r.target_rad = target;
    r.dtc_confirmed = dtc;
    sim_cond_row(&r, c);
}

/* A fault of kind at 0.1 s, then rows 0..400 ms with constant values: the condition's time. */
static double constant_run(plant_fault_kind_t kind, double phi, double w, double u, int bridge, double target)
{
    sim_cond_t c;
    plant_fault_list_t l;
    int k;
    faults_one(&l, kind, 0.1);
    sim_cond_init(&c, &s_pc, &l);
    for (k = 0; k <= 400; ++k) {
        row_at(&c, k, phi, w, u, bridge, target, 0u);
    }
    return sim_cond_time(&c);
}

/* No fault, or one without a condition (a track offset): never met. */
static void test_no_condition(void)
{
    sim_cond_t c;
    int k;
    sim_cond_init(&c, &s_pc, NULL);
    for (k = 0; k < 300; ++k) {
        row_at(&c, k, 0.3, 0.0, 12.0, 1, 1.0, 0u);
    }
    TV_CHECK(isnan(sim_cond_time(&c)));
    TV_CHECK(isnan(constant_run(PLANT_FAULT_TPS1_OFFSET, 0.3, 0.0, 12.0, 1, 1.0)));
    TV_CHECK(isnan(sim_cond_time(NULL)));
}

/* Jam at 0.1 s, closed loop. The plate moves 1 mrad per ms until 0.150 s, then stays at 0.2 rad
 * with the target at 0.5 rad: still (< 0.5 mrad over 8 samples) from the 9th sample after the
 * last move, i.e. at 0.158 s (the angle of 0.150 s is 0.2 rad too: from 0.158 s back to 0.150 s);
 * the stall lasts 100 ms, so the condition is met at 0.258 s and dated 0.158 s. The same with the
 * target 0.02 rad away (0.22 rad): never. A code confirmed 30 ms into the stall ends it there:
 * dated 0.158 s at 0.188 s. A target beyond the stops is clamped 0.05 rad inside: plate at
 * 1.29 rad, target 1.5 rad -> 1.316 rad, 0.026 rad away: never. */
static void test_jam_closed_loop(void)
{
    static const double target[3] = {0.5, 0.22, 0.5};
    sim_cond_t c;
    plant_fault_list_t l;
    int v;
    int k;
    faults_one(&l, PLANT_FAULT_JAM, 0.1);
    for (v = 0; v < 3; ++v) {
        double met_at = (double)NAN;
        sim_cond_init(&c, &s_pc, &l);
        for (k = 0; k <= 400; ++k) {
            const double phi = k <= 150 ? 0.05 + 0.001 * (double)k : 0.2;
            const uint32_t dtc = v == 2 && k >= 188 ? 1u << 3 : 0u;
            row_at(&c, k, phi, 0.0, 6.0, 1, target[v], dtc);
            if (isnan(met_at) && !isnan(sim_cond_time(&c))) {
                met_at = (double)k * 1e-3;
            }
        }
        if (v == 0) {
            TV_CHECK_NEAR(sim_cond_time(&c), 0.158, 1e-9);
            TV_CHECK_NEAR(met_at, 0.258, 1e-9);
        } else if (v == 1) {
            TV_CHECK(isnan(sim_cond_time(&c)));
        } else {
            TV_CHECK_NEAR(sim_cond_time(&c), 0.158, 1e-9);
            TV_CHECK_NEAR(met_at, 0.188, 1e-9);
        }
    }
    TV_CHECK(isnan(constant_run(PLANT_FAULT_JAM, 1.29, 0.0, 6.0, 1, 1.5)));
    /* a stall before the onset does not count: the plate still from 0, onset 0.1 s -> from 0.1 s */
    TV_CHECK_NEAR(constant_run(PLANT_FAULT_JAM, 0.2, 0.0, 6.0, 1, 0.5), 0.1, 1e-9);
    /* the bridge off: no demand */
    TV_CHECK(isnan(constant_run(PLANT_FAULT_JAM, 0.2, 0.0, 0.0, 0, 0.5)));
}

/* Jam, open loop (target NaN), plate held at 0.2 rad (above limp-home: pushing open, the springs
 * oppose). The healthy breakaway toward the open stop: Ms + M0 + c phi = 0.3 + 0.25 + 0.0118 =
 * 0.5618 N m, i.e. u >= 0.5618 x 4.3 / (40 x 0.017) = 3.5526 V. At 3.5 V: never; at 3.6 V: from the
 * onset (the plate is still throughout), met 100 ms later. Pushing closed (-1 V) from 0.2 rad:
 * the springs help, the breakaway is Ms alone, 0.3 x 4.3 / 0.68 = 1.897 V: at -1.8 V never, at
 * -2.0 V yes. */
static void test_jam_open_loop(void)
{
    static const double u[4] = {3.5, 3.6, -1.8, -2.0};
    static const int met[4] = {0, 1, 0, 1};
    int v;
    for (v = 0; v < 4; ++v) {
        const double t = constant_run(PLANT_FAULT_JAM, 0.2, 0.0, u[v], 1, (double)NAN);
        TV_CHECK(met[v] ? fabs(t - 0.1) < 1e-9 : isnan(t));
    }
}

/* Open winding at 0.1 s: the back-EMF n Ke w = 0.68 w. u = 2.9 V, w = -5 rad/s (|u - emf| =
 * 6.3 V, |u| < 3): never; u = 3.0 V, w = 0.1 (|u - emf| = 2.932 < 3): never; u = 3.2 V, w = 0.1
 * (3.132): at the first sample from the onset; the same with the bridge off: never. */
static void test_winding_open(void)
{
    static const double u[4] = {2.9, 3.0, 3.2, 3.2};
    static const double w[4] = {-5.0, 0.1, 0.1, 0.1};
    static const int bridge[4] = {1, 1, 1, 0};
    static const int met[4] = {0, 0, 1, 0};
    int v;
    for (v = 0; v < 4; ++v) {
        const double t = constant_run(PLANT_FAULT_WINDING_OPEN, 0.3, w[v], u[v], bridge[v], (double)NAN);
        TV_CHECK(met[v] ? fabs(t - 0.1) < 1e-9 : isnan(t));
    }
}

/* Spring weak at 0.1 s: the bridge off until 0.25 s, on from there: met at 0.25 s. */
static void test_spring(void)
{
    sim_cond_t c;
    plant_fault_list_t l;
    int k;
    faults_one(&l, PLANT_FAULT_SPRING_WEAK, 0.1);
    sim_cond_init(&c, &s_pc, &l);
    for (k = 0; k <= 400; ++k) {
        row_at(&c, k, 0.0, 0.0, k >= 250 ? 1.0 : 0.0, k >= 250 || k < 50, 0.8, 0u);
    }
    TV_CHECK_NEAR(sim_cond_time(&c), 0.25, 1e-9);
}

/* Supply sag at 0.1 s, supply sup_V(k) per row: the first row at or after the onset below 11.5 V. */
static double supply_run(double before_V, double after_V, int k_after)
{
    sim_cond_t c;
    plant_fault_list_t l;
    int k;
    faults_one(&l, PLANT_FAULT_SUPPLY_SAG, 0.1);
    sim_cond_init(&c, &s_pc, &l);
    for (k = 0; k <= 400; ++k) {
        sim_row_t r;
        memset(&r, 0, sizeof r);
        r.t_s = (double)k * 1e-3;
        r.bridge_enable = 1;
        r.target_rad = 0.5;
        r.supply_V = k >= k_after ? after_V : before_V;
        sim_cond_row(&r, &c);
    }
    return sim_cond_time(&c);
}

/* Supply sag: met where the supply falls below 11.5 V (the level P0562 is specified for), not
 * where a sag leaves it at or above that, not before the onset. */
static void test_supply(void)
{
    TV_CHECK_NEAR(supply_run(13.5, 11.4, 250), 0.25, 1e-9);
    TV_CHECK(isnan(supply_run(13.5, 11.5, 250)));        /* at the level: a healthy supply */
    TV_CHECK(isnan(supply_run(14.3, 12.3, 100)));        /* a 2 V sag from 14.3 V */
    TV_CHECK_NEAR(supply_run(11.0, 11.0, 0), 0.1, 1e-9); /* low from the start: counted from the onset */
    {
        diag_detect_config_t dc; /* the condition's level is P0562's default threshold */
        diag_detect_config_default(&dc);
        TV_CHECK_NEAR(SIM_COND_SUPPLY_LOW_V, (double)dc.supply_low_V, 1e-6);
    }
}

int main(void)
{
    plant_config_default(&s_pc);
    TV_CHECK_NEAR(s_pc.Ms_Nm, 0.3, 1e-12);
    TV_CHECK_NEAR(s_pc.M0_Nm, 0.25, 1e-12);
    TV_CHECK_NEAR(s_pc.c_Nm_rad, 0.059, 1e-12);
    TV_CHECK_NEAR(s_pc.R_ohm, 4.3, 1e-12);
    TV_CHECK_NEAR(s_pc.n_gear * s_pc.Kt_Nm_A, 0.68, 1e-12);
    TV_CHECK_NEAR(s_pc.n_gear * s_pc.Ke_V_s_rad, 0.68, 1e-12);
    TV_TEST_RUN(test_no_condition);
    TV_TEST_RUN(test_jam_closed_loop);
    TV_TEST_RUN(test_jam_open_loop);
    TV_TEST_RUN(test_winding_open);
    TV_TEST_RUN(test_spring);
    TV_TEST_RUN(test_supply);
    return tv_test_summary();
}
