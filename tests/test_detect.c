/**
 * @file test_detect.c
 * @brief The first fault detectors in the application (firmware/diag/diag_detect.h, called from
 *        app.c) against the simulated plant with injected faults (host_sim/plant/plant_fault.h):
 *        each fault detected by its code within issue 12's time, the faulty track named, and no
 *        code confirmed on healthy population units (the benchmark's evaluation units, after
 *        their start-up stop learning, as tools/run_population.sh runs them).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "plant_draw.h"
#include "plant_fault.h"
#include "sim.h"
#include "sim_unit.h"
#include "tv_status.h"
#include "tv_test.h"
#include "sim_fault_run.h"

/* A unit of the population configured as the benchmark does: drawn, the ECU calibrated for it,
 * its stops and contact law learned by the start-up routine (population_main.c learn_stops()).
 * Returns 0 when the routine failed (the unit is then skipped by the caller). */
static int unit_config(uint64_t unit, plant_spread_t spread, plant_config_t *pc, app_config_t *ac, sim_result_t *learn)
{
    const plant_class_t cls = unit % 3u == 2u ? PLANT_CLASS_B : PLANT_CLASS_A;
    sim_options_t opt;
    TV_CHECK_EQ_INT(plant_draw(cls, spread, unit, pc), TV_OK);
    TV_CHECK_EQ_INT(sim_app_config_for_unit(cls, pc, ac), TV_OK);
    sim_options_default(&opt);
    opt.scenario = SIM_SCN_STOP_LEARN;
    opt.plant = pc;
    opt.app = ac;
    TV_CHECK_EQ_INT(sim_run(&opt, learn), TV_OK);
    if (learn->stop_learn_phase != (int)SL_DONE) {
        return 0;
    }
    TV_CHECK_EQ_INT(sim_apply_stop_learning(learn, ac), TV_OK);
    return 1;
}

/* One run of the scenario's own length with one fault (spec NULL: healthy). */
static void run_with(const plant_config_t *pc, const app_config_t *ac, sim_scenario_t scn, uint64_t seed, const char *spec,
                     sim_result_t *r)
{
    sim_fault_run(pc, ac, scn, seed, spec, 0.0, r);
}

/* One run of duration_s with noise seed `seed` of plant pc under ac with FAULT (NULL: healthy) from
 * its onset, the application told the winding's temperature (the plant's), as in the fault matrix. */
static void told_run_seed(const plant_config_t *pc, const app_config_t *ac, const char *fault, sim_scenario_t scenario,
                          double duration_s, uint64_t seed, sim_result_t *r)
{
    sim_options_t opt;
    sim_options_default(&opt);
    opt.duration_s = duration_s;
    opt.scenario = scenario;
    opt.seed = seed;
    opt.plant = pc;
    opt.app = ac;
    opt.temp_reading = 1;
    opt.temp_reading_C = opt.winding_temp_C;
    sim_fault_run_opt(&opt, fault, r);
}

/* The same with seed 1: the fault matrix's runs. */
static void told_run(const plant_config_t *pc, const app_config_t *ac, const char *fault, sim_scenario_t scenario,
                     double duration_s, sim_result_t *r)
{
    told_run_seed(pc, ac, fault, scenario, duration_s, 1u, r);
}

/* A healthy learning run as population's baselines take them (seed 900002, the temperature told). */
static void learning_run(const plant_config_t *pc, const app_config_t *ac, sim_scenario_t scenario, double duration_s,
                         sim_result_t *r)
{
    told_run_seed(pc, ac, NULL, scenario, duration_s, 900002u, r);
}

/* A track-offset run: the faulty track's code confirmed, the other's never pending, no P2135;
 * counts it in *named and its confirmation delay after 1.0 s in *worst_s. */
static void score_named(const sim_result_t *r, int track1, const char *what, int *named, double *worst_s)
{
    const diag_dtc_t good = track1 ? DIAG_DTC_P0121 : DIAG_DTC_P0221;
    const diag_dtc_t other = track1 ? DIAG_DTC_P0221 : DIAG_DTC_P0121;
    if (isfinite(r->dtc_confirm_t_s[good]) && !sim_dtc_ever(r, other) && !isfinite(r->dtc_confirm_t_s[DIAG_DTC_P2135])) {
        ++*named;
        *worst_s = fmax(*worst_s, r->dtc_confirm_t_s[good] - 1.0);
    } else {
        fprintf(stderr, "  %s: not named\n", what);
    }
}

/* A 1 % track offset (50 mV, 0.018 rad; both signs, each track) from 1.0 s on: confirmed within
 * 50 ms (the code confirms at its 20th failing sample), the faulty track's code, never the
 * other's, never P2135. Nominal unit over 25 seeds and three scenarios (closed-loop steps and
 * ramp, the 12 V / 5 Hz open-loop sine: the plate at full speed), and 8 population units. */
static void test_track_offset_named_within_50_ms(void)
{
    static const char *const spec[4] = {"tps1_offset:1@1.0", "tps1_offset:-1@1.0", "tps2_offset:1@1.0", "tps2_offset:-1@1.0"};
    static const sim_scenario_t scn[3] = {SIM_SCN_CLOSED_STEPS, SIM_SCN_CLOSED_RAMP, SIM_SCN_PAPER_SINE};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    int runs = 0;
    int named = 0;
    double worst_s = 0.0;
    int f;
    int s;
    uint64_t seed;
    uint64_t unit;
    plant_config_default(&pc);
    app_config_default(&ac);
    for (f = 0; f < 4; ++f) {
        for (s = 0; s < 3; ++s) {
            for (seed = 1u; seed <= 25u; ++seed) {
                run_with(&pc, &ac, scn[s], seed, spec[f], &r);
                ++runs;
                score_named(&r, f < 2, spec[f], &named, &worst_s);
            }
        }
    }
    for (unit = 1000u; unit < 1008u; ++unit) {
        sim_result_t learn;
        if (!unit_config(unit, unit % 2u ? PLANT_SPREAD_ALL : PLANT_SPREAD_STOPS, &pc, &ac, &learn)) {
            continue;
        }
        for (f = 0; f < 4; ++f) {
            run_with(&pc, &ac, SIM_SCN_CLOSED_STEPS, 1u, spec[f], &r);
            ++runs;
            score_named(&r, f < 2, spec[f], &named, &worst_s);
        }
    }
    printf("  track offset 1 %%: faulty track named in %d of %d runs, confirmed at most %.0f ms after the onset\n", named, runs,
           worst_s * 1e3);
    TV_CHECK_EQ_INT(named, runs);
    TV_CHECK_LE(worst_s, 0.050 + 1e-9);
}

/* A jam (10 N m holding torque) in closed_steps: at 1.01 s, the plate on its way from 0.8 to
 * 0.05 rad: P2111 (cannot close) within 100 ms; at 1.3 s, the plate at rest at 0.05 rad and the
 * target stepping to 1.2 rad at 1.5 s: P2112 (cannot open) within 100 ms of the step. Nominal
 * unit, 10 seeds each, and 6 population units. */
static void test_jam_confirmed_within_100_ms(void)
{
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    uint64_t seed;
    uint64_t unit;
    double worst_close = 0.0;
    double worst_open = 0.0;
    double worst_steps = 0.0;
    double worst_sine = 0.0;
    plant_config_default(&pc);
    app_config_default(&ac);
    for (unit = 0u; unit < 7u; ++unit) {
        const int n_seeds = unit == 0u ? 10 : 1;
        if (unit > 0u) {
            sim_result_t learn;
            if (!unit_config(999u + unit, unit % 2u ? PLANT_SPREAD_ALL : PLANT_SPREAD_STOPS, &pc, &ac, &learn)) {
                continue;
            }
        }
        for (seed = 1u; seed <= (uint64_t)n_seeds; ++seed) {
            run_with(&pc, &ac, SIM_SCN_CLOSED_STEPS, seed, "jam:10@1.01", &r);
            TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2111]));
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2112]));
            worst_close = fmax(worst_close, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2111]) ? r.dtc_confirm_t_s[DIAG_DTC_P2111] - 1.01 : 1e9);
            run_with(&pc, &ac, SIM_SCN_CLOSED_STEPS, seed, "jam:10@1.3", &r);
            TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2112]));
            worst_open = fmax(worst_open, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2112]) ? r.dtc_confirm_t_s[DIAG_DTC_P2112] - 1.5 : 1e9);
        }
        /* Open loop (sine, steps, chirp) has no target: the check takes the stop the voltage
         * pushes toward. open_steps switches to +10 V at 1.0 s and the plate leaves the closed
         * stop: blocked at 1.02 s, commanded to open, P2112 (never P2111) within 100 ms; the
         * 12 V / 5 Hz sine blocked at 1.0 s (zero crossing, then opening): a jam code within 100 ms. */
        run_with(&pc, &ac, SIM_SCN_OPEN_STEPS, 1u, "jam:10@1.02", &r);
        TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2112]));
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2111]));
        worst_steps = fmax(worst_steps, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2112]) ? r.dtc_confirm_t_s[DIAG_DTC_P2112] - 1.02 : 1e9);
        run_with(&pc, &ac, SIM_SCN_PAPER_SINE, 1u, "jam:10@1.0", &r);
        {
            const double t = fmin(r.dtc_confirm_t_s[DIAG_DTC_P2111], r.dtc_confirm_t_s[DIAG_DTC_P2112]);
            TV_CHECK(isfinite(t));
            worst_sine = fmax(worst_sine, isfinite(t) ? t - 1.0 : 1e9);
        }
    }
    printf("  jam: P2111 at most %.0f ms after the onset (plate moving), P2112 at most %.0f ms after the target step\n",
           worst_close * 1e3, worst_open * 1e3);
    printf("  open-loop jam: open_steps P2112 at most %.0f ms after the onset, paper_sine at most %.0f ms\n",
           worst_steps * 1e3, worst_sine * 1e3);
    TV_CHECK_LE(worst_close, 0.100);
    TV_CHECK_LE(worst_open, 0.100);
    TV_CHECK_LE(worst_steps, 0.100);
    TV_CHECK_LE(worst_sine, 0.100);
}

/* The stall tracker for the sticky-plate test: from the onset on, a run of ticks in which the
 * bridge drives, the plate (plant truth) is at least 0.035 rad from the target (clamped 0.05 rad
 * inside the plant's stops, as the application clamps it inside the learned ones) and has moved
 * less than 0.5 mrad over 8 ticks; the stall's start when the first jam code confirms. */
typedef struct {
    double onset_s;
    double lo_rad;
    double hi_rad;
    double phi[8];
    unsigned n;
    double stall_start_s; /* NaN: not stalled */
    double delay_s;       /* first jam confirmation - stall start (NaN: none, or not during a stall) */
    int confirmed;
} stall_track_t;

static void stall_row(const sim_row_t *row, void *user)
{
    stall_track_t *st = (stall_track_t *)user;
    const double phi = row->truth[TVM_PHI];
    const uint32_t jam_bits = (1u << DIAG_DTC_P2111) | (1u << DIAG_DTC_P2112);
    const double oldest = st->phi[st->n % 8u];
    int still;
    st->phi[st->n % 8u] = phi;
    ++st->n;
    if (row->t_s < st->onset_s || st->confirmed) {
        return;
    }
    if ((row->dtc_confirmed & jam_bits) != 0u) {
        st->confirmed = 1;
        st->delay_s = row->t_s - st->stall_start_s; /* NaN when the plate was not stalled */
        return;
    }
    still = st->n > 8u && fabs(phi - oldest) < 5e-4;
    if (row->bridge_enable && isfinite(row->target_rad) && still &&
        fabs(fmin(fmax(row->target_rad, st->lo_rad), st->hi_rad) - phi) >= 0.035) {
        if (!isfinite(st->stall_start_s)) {
            st->stall_start_s = row->t_s;
        }
    } else {
        st->stall_start_s = NAN;
    }
}

/* A sticky plate: jam:1 (1 N m of holding torque: the plate breaks free under a strong push
 * and slides against Coulomb friction + 1 N m) on the nominal unit in closed loop. The
 * controller drives it most of the way at full voltage, then it stops 0.045-0.055 rad short of
 * the target, where the controller's bounded integral leaves some 6 V toward limp-home: below
 * twice the spring-opposed breakaway (7-8 V) that the jam check asked for before, and the plate
 * stayed there (P2119 came a second later instead). The check's gate in the push's direction
 * (diag_jam_breakaway_Nm()) judges it: a jam code (never P2119) within 100 ms of the stall, in
 * closed_steps and drive, onsets at 2.0 and 2.3 s, 3 seeds. And the 5 V slow sine, whose plate
 * jammed on the closed side was never judged (5 V < 7 V): a jam code, never another. */
static void test_sticky_plate_jam_within_100_ms_of_stall(void)
{
    static const sim_scenario_t scn[2] = {SIM_SCN_CLOSED_STEPS, SIM_SCN_DRIVE};
    static const char *const spec[2] = {"jam:1@2.0", "jam:1@2.3"};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    double worst = 0.0;
    int runs = 0;
    int s;
    int f;
    uint64_t seed;
    plant_config_default(&pc);
    app_config_default(&ac);
    for (s = 0; s < 2; ++s) {
        for (f = 0; f < 2; ++f) {
            for (seed = 1u; seed <= 3u; ++seed) {
                sim_options_t opt;
                static plant_fault_list_t l;
                stall_track_t st;
                memset(&st, 0, sizeof st);
                st.onset_s = f == 0 ? 2.0 : 2.3;
                st.lo_rad = pc.phi_closed_rad + 0.05;
                st.hi_rad = pc.phi_open_rad - 0.05;
                st.stall_start_s = NAN;
                st.delay_s = NAN;
                sim_options_default(&opt);
                opt.scenario = scn[s];
                opt.duration_s = 4.0;
                opt.seed = seed;
                opt.plant = &pc;
                opt.app = &ac;
                plant_fault_list_clear(&l);
                TV_CHECK_EQ_INT(plant_fault_list_add(&l, spec[f], NULL, 0u), TV_OK);
                opt.faults = &l;
                opt.row_fn = stall_row;
                opt.row_user = &st;
                TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
                ++runs;
                TV_CHECK(st.confirmed);
                TV_CHECK(isfinite(st.delay_s));
                TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2119]));
                TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A02]));
                worst = fmax(worst, isfinite(st.delay_s) ? st.delay_s : 1e9);
            }
        }
    }
    printf("  sticky plate (jam:1): a jam code at most %.0f ms after the plate stalled >= 0.035 rad from its target (%d runs), never P2119\n",
           worst * 1e3, runs);
    TV_CHECK_LE(worst, 0.100);
    for (seed = 1u; seed <= 3u; ++seed) {
        int k;
        int others = 0;
        sim_fault_run(&pc, &ac, SIM_SCN_SLOW_SINE, seed, "jam:10@2.0", 4.0, &r);
        TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2112]));
        for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
            others += k != (int)DIAG_DTC_P2112 && isfinite(r.dtc_confirm_t_s[k]);
        }
        TV_CHECK_EQ_INT(others, 0);
        printf("  slow_sine jam:10 from 2.0 s (seed %u): P2112 at %.3f s\n", (unsigned)seed, r.dtc_confirm_t_s[DIAG_DTC_P2112]);
    }
}

/* An open winding: P2100 within 10 ms when the bridge drives at least 3 V (closed_steps at a
 * target step, 1.0 s; the sine at its crest, 1.05 s); from the sine's zero crossing (1.0 s) the
 * check waits for |u| >= 3 V: 12 sin(2 pi 5 t) >= 3 from t = 8.04 ms, so the first such command
 * is the 9 ms tick's, judged with the current sampled at 10 ms; its 5th failing sample is 14 ms. */
static void test_open_winding_confirmed_within_10_ms(void)
{
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    uint64_t seed;
    double worst = 0.0;
    plant_config_default(&pc);
    app_config_default(&ac);
    for (seed = 1u; seed <= 10u; ++seed) {
        run_with(&pc, &ac, SIM_SCN_CLOSED_STEPS, seed, "winding_open@1.0", &r);
        worst = fmax(worst, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2100]) ? r.dtc_confirm_t_s[DIAG_DTC_P2100] - 1.0 : 1e9);
        run_with(&pc, &ac, SIM_SCN_PAPER_SINE, seed, "winding_open@1.05", &r);
        worst = fmax(worst, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2100]) ? r.dtc_confirm_t_s[DIAG_DTC_P2100] - 1.05 : 1e9);
    }
    run_with(&pc, &ac, SIM_SCN_PAPER_SINE, 1u, "winding_open@1.0", &r);
    printf("  open winding: P2100 at most %.0f ms after the onset under drive; from the sine's zero crossing %.0f ms\n", worst * 1e3,
           (r.dtc_confirm_t_s[DIAG_DTC_P2100] - 1.0) * 1e3);
    TV_CHECK_LE(worst, 0.010 + 1e-9);
    TV_CHECK_NEAR(r.dtc_confirm_t_s[DIAG_DTC_P2100] - 1.0, 0.014, 1e-9);
}

/* Winding resistance x1.5 from 1.0 s: P2101 in every scenario that drives current, within
 * 0.7 s (the estimator's R + dR must first cross 1.35 R, then 200 ms confirm), never P1A01;
 * half the turns shorted (R x 0.5): P1A01 where the estimate follows (closed-loop steps, open-loop
 * steps, slow sine), never P2101. Nominal unit, 5 seeds. (paper_sine with shorted turns
 * confirms P2100 as well: README's signature table.) */
static void test_winding_resistance_out_of_range(void)
{
    static const sim_scenario_t scn_hi[4] = {SIM_SCN_CLOSED_STEPS, SIM_SCN_PAPER_SINE, SIM_SCN_OPEN_STEPS, SIM_SCN_SLOW_SINE};
    static const sim_scenario_t scn_lo[3] = {SIM_SCN_CLOSED_STEPS, SIM_SCN_OPEN_STEPS, SIM_SCN_SLOW_SINE};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    uint64_t seed;
    int s;
    double worst_hi = 0.0;
    double worst_lo = 0.0;
    plant_config_default(&pc);
    app_config_default(&ac);
    for (seed = 1u; seed <= 5u; ++seed) {
        for (s = 0; s < 4; ++s) {
            run_with(&pc, &ac, scn_hi[s], seed, "winding_resistance_high:1.5@1.0", &r);
            worst_hi = fmax(worst_hi, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]) ? r.dtc_confirm_t_s[DIAG_DTC_P2101] - 1.0 : 1e9);
            TV_CHECK(!sim_dtc_ever(&r, DIAG_DTC_P1A01));
        }
        for (s = 0; s < 3; ++s) {
            run_with(&pc, &ac, scn_lo[s], seed, "winding_short:0.5@1.0", &r);
            worst_lo = fmax(worst_lo, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A01]) ? r.dtc_confirm_t_s[DIAG_DTC_P1A01] - 1.0 : 1e9);
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
        }
    }
    printf("  winding resistance: x1.5 P2101 at most %.0f ms after the onset; half the turns shorted P1A01 at most %.0f ms\n",
           worst_hi * 1e3, worst_lo * 1e3);
    TV_CHECK_LE(worst_hi, 0.7);
    TV_CHECK_LE(worst_lo, 0.7);
}

/* A doubled winding resistance is not a jam. At twice R the plate needs twice the model's
 * breakaway voltage, where the jam check (twice the model's breakaway) sat: it saw a plate that
 * could not move and confirmed P2112 / P2111 (safe state) besides P2101 in 9 of the fault
 * matrix's 150 such runs, these two all_varied class-b units in closed-loop steps and the 5 V
 * slow sine among them. The breakaway is now reckoned through the adapted resistance where that
 * is the larger (app.c): P2101 confirmed, no jam code. The winding at 20 degC and the application
 * told so, as tools/run_fault_matrix.sh runs it. */
static void test_winding_resistance_not_a_jam(void)
{
    static const uint64_t units[2] = {1001u, 1004u};
    static const sim_scenario_t scn[2] = {SIM_SCN_CLOSED_STEPS, SIM_SCN_SLOW_SINE};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    int u;
    int s;
    int runs = 0;
    int jams = 0;
    int p2101 = 0;
    for (u = 0; u < 2; ++u) {
        sim_result_t learn;
        TV_CHECK(unit_config(units[u], PLANT_SPREAD_ALL, &pc, &ac, &learn));
        for (s = 0; s < 2; ++s) {
            told_run(&pc, &ac, "winding_resistance_high:2@2.0", scn[s], 8.0, &r);
            ++runs;
            jams += isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2111]) || isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2112]);
            p2101 += isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]);
        }
    }
    printf("  winding resistance x2 on all_varied units 1001, 1004: P2101 confirmed in %d of %d runs, a jam code in %d\n", p2101,
           runs, jams);
    TV_CHECK_EQ_INT(jams, 0);
    TV_CHECK_EQ_INT(p2101, runs);
}

/* A doubled winding braking is not a lost bridge direction. P1A03 reckons the terminal voltage
 * the current implies with the model's R; on all_varied unit 1000 (its winding 1.16 times the
 * model's), R x 2 from 2 s, the plate braking in closed-loop steps and in `drive` read v / u = 0.15
 * and confirmed P1A03 (safe state: the bridge off) at 2.11 and 2.10 s, before P2101 could. Such
 * samples are not judged for P1A03 now (DIAG_BRIDGE_BRAKE_FRAC): P2101 is confirmed, P1A03 never.
 * The winding at 20 degC and the application told so, as tools/run_fault_matrix.sh runs it. */
static void test_winding_resistance_braking_not_bridge(void)
{
    static const sim_scenario_t scn[2] = {SIM_SCN_CLOSED_STEPS, SIM_SCN_DRIVE};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t learn;
    sim_result_t r;
    int s;
    TV_CHECK(unit_config(1000u, PLANT_SPREAD_ALL, &pc, &ac, &learn));
    for (s = 0; s < 2; ++s) {
        told_run(&pc, &ac, "winding_resistance_high:2@2.0", scn[s], 8.0, &r);
        printf("  winding resistance x2, all_varied unit 1000, %s: P2101 at %.3f s, P1A03 %s\n", sim_scenario_name(scn[s]),
               r.dtc_confirm_t_s[DIAG_DTC_P2101], isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A03]) ? "confirmed" : "never confirmed");
        TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A03]));
    }
}

/* One closed-loop steps run (6 s) of the nominal unit, its winding at plant_C; the application
 * told told_C (NaN: not told); a fault spec or NULL. */
static void run_warm(const app_config_t *ac, double plant_C, double told_C, const char *spec, sim_result_t *r)
{
    sim_options_t opt;
    sim_options_default(&opt);
    opt.scenario = SIM_SCN_CLOSED_STEPS;
    opt.duration_s = 6.0;
    opt.app = ac;
    opt.winding_temp_C = plant_C;
    opt.temp_reading = isfinite(told_C);
    opt.temp_reading_C = told_C;
    sim_fault_run_opt(&opt, spec, r);
}

/* The winding's temperature (app_set_winding_temp()). The plant's R follows copper from its 20 degC
 * value (4.3 ohm: 5.821 ohm at 110 degC, worked by hand), the estimator follows it through dR, and
 * the application refers it back to 20 degC with the temperature it is told. A healthy winding at
 * 110 degC reads 1.35 R: without the temperature the resistance check confirms P2101 (why the
 * temperature is an input), with it nothing. On a unit whose model is its own (identified), with
 * the temperature known, the bound is 1.15 R: a resistance +25 % confirms P2101, which the class's
 * 1.35 misses; a reading 10 K off (the plant at 90 degC, told 80) does not. */
static void test_winding_temperature(void)
{
    static app_config_t ac;
    sim_result_t r;
    app_config_default(&ac);
    run_warm(&ac, 110.0, (double)NAN, NULL, &r);
    TV_CHECK_NEAR(r.r_true_ohm, 5.82091, 1e-4);
    TV_CHECK_NEAR(r.r_est_ohm, 5.82091, 0.02 * 5.82091);
    TV_CHECK(isnan(r.r_20_ohm));
    TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
    run_warm(&ac, 110.0, 110.0, NULL, &r);
    TV_CHECK_NEAR(r.r_20_ohm, 4.3, 0.02 * 4.3);
    TV_CHECK_NEAR(r.r_true_20_ohm, 4.3, 1e-9);
    TV_CHECK(!sim_dtc_ever(&r, DIAG_DTC_P2101));
    /* the class's model: +30 % stays below the estimator's bound (1.35 R) but the voltage
     * equation's fit reads it above 1.25 R with the temperature known (diag_fit_resistance_check());
     * without the temperature nothing */
    run_warm(&ac, 20.0, 20.0, "winding_resistance_high:1.3@1.0", &r);
    TV_CHECK_LE(r.r_est_ohm / 4.3, 1.35);
    TV_CHECK_NEAR(r.r_est_ohm / 4.3, 1.3, 0.03);
    TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
    printf("  class's model, 20 degC told: resistance +30 %% confirmed P2101 %.0f ms after the onset (the fit's R)\n",
           (r.dtc_confirm_t_s[DIAG_DTC_P2101] - 1.0) * 1e3);
    TV_CHECK_LE(r.dtc_confirm_t_s[DIAG_DTC_P2101] - 1.0, 2.0);
    run_warm(&ac, 20.0, (double)NAN, "winding_resistance_high:1.3@1.0", &r);
    TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
    run_warm(&ac, 20.0, 20.0, NULL, &r);
    TV_CHECK(!sim_dtc_ever(&r, DIAG_DTC_P2101));
    diag_detect_config_identified(&ac.diag);
    run_warm(&ac, 20.0, 20.0, "winding_resistance_high:1.25@1.0", &r);
    TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
    printf("  identified, 20 degC told: resistance +25 %% confirmed P2101 %.0f ms after the onset\n",
           (r.dtc_confirm_t_s[DIAG_DTC_P2101] - 1.0) * 1e3);
    TV_CHECK_LE(r.dtc_confirm_t_s[DIAG_DTC_P2101] - 1.0, 1.0);
    run_warm(&ac, 20.0, (double)NAN, "winding_resistance_high:1.25@1.0", &r);
    TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
    run_warm(&ac, 90.0, 80.0, NULL, &r);
    TV_CHECK(!sim_dtc_ever(&r, DIAG_DTC_P2101));
    run_warm(&ac, 90.0, 80.0, "winding_resistance_high:1.25@1.0", &r);
    TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
}

/* The adapted-mechanics check on scripted estimates (no estimator, no torque signature fed):
 * it runs at every DIAG_PARAM_DECIM-th call only, never while the plate is slower than
 * param_excite_rad_s, the estimate's sigma above its bound or the check inactive; a level beyond
 * its bound fails only from the param_slow_hold-th (95th) check in a row (not run before), so
 * P2119 (confirm count 10) confirms at the 104th check (1,040 calls), P1A02 (count 3) at the
 * 97th (970 calls); both heal after 100 consecutive passing checks. Expectations from the code
 * table's counts (diag.c) and the defaults (diag_detect.c). */
static void test_mechanics_check_timing(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    int k;
    int first = -1;
    int first_m = -1;
    diag_detect_config_default(&cfg);
    TV_CHECK_EQ_INT(cfg.param_slow_hold, 95);
    TV_CHECK_EQ_INT(diag_dtc_info(DIAG_DTC_P2119)->confirm_count, 10);
    TV_CHECK_EQ_INT(diag_dtc_info(DIAG_DTC_P1A02)->confirm_count, 3);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_init(&d);
    memset(&snap, 0, sizeof snap);
    /* not informed: slow plate, wide sigma, inactive: nothing happens however high the level */
    for (k = 0; k < 5000; ++k) {
        diag_param_check(&dd, &d, 1, TV_R(0.49), TV_R(1.79), TV_R(0.01), TV_R(0.2), TV_R(0.01), &snap);
        diag_param_check(&dd, &d, 1, TV_R(2.0), TV_R(1.79), TV_R(0.051), TV_R(0.2), TV_R(0.031), &snap);
        diag_param_check(&dd, &d, 0, TV_R(2.0), TV_R(1.79), TV_R(0.01), TV_R(0.2), TV_R(0.01), &snap);
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P2119) && !diag_confirmed(&d, DIAG_DTC_P2119));
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_confirmed(&d, DIAG_DTC_P1A02));
    /* informed: friction 1.71 > 1.7, preload 0.39 < 0.4 */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 1; k <= 2000 && first < 0; ++k) {
        snap.t_us = (uint64_t)k * 1000u;
        diag_param_check(&dd, &d, 1, TV_R(-1.0), TV_R(1.71), TV_R(0.02), TV_R(0.39), TV_R(0.01), &snap);
        if (k == 94 * (int)DIAG_PARAM_DECIM) {
            TV_CHECK(!diag_pending(&d, DIAG_DTC_P2119) && !diag_pending(&d, DIAG_DTC_P1A02)); /* held 94 checks */
        }
        if (k == 95 * (int)DIAG_PARAM_DECIM) {
            TV_CHECK(diag_pending(&d, DIAG_DTC_P2119) && diag_pending(&d, DIAG_DTC_P1A02));
        }
        if (diag_confirmed(&d, DIAG_DTC_P1A02) && first_m < 0) {
            first_m = k;
        }
        if (diag_confirmed(&d, DIAG_DTC_P2119)) {
            first = k;
        }
    }
    TV_CHECK_EQ_INT(first, 104 * (int)DIAG_PARAM_DECIM);
    TV_CHECK_EQ_INT(first_m, 97 * (int)DIAG_PARAM_DECIM);
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P1A02));
    TV_CHECK_EQ_INT(diag_action(&d), DIAG_ACTION_LIMITED); /* the weak spring's action; friction's is none */
    TV_CHECK_NEAR(d.code[DIAG_DTC_P2119].freeze.value, 1.71, 1e-6);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A02].freeze.value, 0.39, 1e-6);
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P2119].freeze.t_us, 1040000u);
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P1A02].freeze.t_us, 970000u);
    /* healing: 99 passing checks keep it, the 100th heals */
    for (k = 0; k < 99 * (int)DIAG_PARAM_DECIM; ++k) {
        diag_param_check(&dd, &d, 1, TV_R(1.0), TV_R(1.3), TV_R(0.02), TV_R(0.9), TV_R(0.01), &snap);
    }
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P2119) && diag_confirmed(&d, DIAG_DTC_P1A02));
    for (k = 0; k < (int)DIAG_PARAM_DECIM; ++k) {
        diag_param_check(&dd, &d, 1, TV_R(1.0), TV_R(1.3), TV_R(0.02), TV_R(0.9), TV_R(0.01), &snap);
    }
    TV_CHECK(!diag_confirmed(&d, DIAG_DTC_P2119) && !diag_confirmed(&d, DIAG_DTC_P1A02));
    /* a level that leaves its bound for 94 checks and comes back never fails */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 3; ++k) {
        int j;
        for (j = 0; j < 94 * (int)DIAG_PARAM_DECIM; ++j) {
            diag_param_check(&dd, &d, 1, TV_R(1.0), TV_R(1.75), TV_R(0.02), TV_R(0.35), TV_R(0.01), &snap);
        }
        for (j = 0; j < (int)DIAG_PARAM_DECIM; ++j) {
            diag_param_check(&dd, &d, 1, TV_R(1.0), TV_R(1.3), TV_R(0.02), TV_R(0.9), TV_R(0.01), &snap);
        }
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P2119) && !diag_pending(&d, DIAG_DTC_P1A02));
    /* the friction bounds: positive (a unit whose friction reads below its model's has its own
     * bound below 1: "A per-unit bound of the friction check"); the preload's below 1 */
    cfg.friction_high_rel = TV_R(0.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    cfg.friction_high_rel = TV_R(0.9);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_detect_config_default(&cfg);
    cfg.friction_fast_high = TV_R(0.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    diag_detect_config_default(&cfg);
    cfg.preload_low_rel = TV_R(1.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    diag_detect_config_default(&cfg);
    cfg.torque_corr_max = TV_R(1.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    diag_detect_config_default(&cfg);
    cfg.param_slow_hold = 0u;
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
}

/* Feeds the torque signature one synthetic sample and calls the check: the plate slides at
 * w (|w| = 2 rad/s), the estimated angle moves 1 mrad a sample, the unexplained torque is that of a
 * spring deficit a and a friction excess e on the model's spring torque s and friction level
 * 0.2 N m. */
static void feed_synthetic(diag_detect_t *dd, diag_t *d, diag_snapshot_t *snap, int k, tv_real_t a, tv_real_t e,
                           tv_real_t pre_rel, tv_real_t fr_rel)
{
    /* a triangle wave: 40 samples opening, 40 closing, on one side of limp-home then the other */
    const int ph = k % 160;
    const tv_real_t w = (ph % 80) < 40 ? TV_R(2.0) : TV_R(-2.0);
    const tv_real_t phi = (ph < 80 ? TV_R(0.5) : TV_R(-0.06)) + TV_R(0.001) * (tv_real_t)((ph % 80) < 40 ? ph % 40 : 40 - ph % 40);
    const tv_real_t s = (phi > TV_R(0.0) ? TV_R(0.25) : TV_R(-0.25)) + TV_R(0.059) * phi;
    const tv_real_t fr = TV_R(0.2);
    const tv_real_t xf = w > TV_R(0.0) ? -fr : fr;
    snap->t_us = (uint64_t)k * 1000u;
    diag_jam_check(dd, d, 0, TV_R(0.0), TV_R(0.001) * (tv_real_t)k, TV_R(0.0), TV_R(1.0), snap); /* the motion history */
    diag_torque_feed(dd, 1, w, a * s + e * xf, TV_R(0.0), s, fr, TV_R(0.0));
    diag_param_check(dd, d, 1, w, fr_rel, TV_R(0.02), pre_rel, TV_R(0.01), snap);
}

/* The torque signature (diag_torque_feed()) on synthetic data whose answer is known: a healthy
 * plate (a = e = 0) passes and is judged at 1; a spring deficit of 0.7 (a spring at 30 %) with the
 * estimator's preload at 1 reads (1 + m)(1 - a) = 0.3, fails P1A02 from the first check at which
 * the decayed estimate is below 0.5 and confirms 2 checks later, without P2119; a friction excess
 * e = 1 over the estimator's level 1.3 (which has begun to follow: friction_fast_level_min) reads
 * up to 2.6 and confirms P2119 after 10 failing checks, without P1A02 (the same excess over a
 * level of 1.0 is not judged a fault: tested below); samples that do not
 * move the angle, or carry more than torque_clip_Nm, or whose regressors are collinear (only
 * one direction of motion on one side), are not judged; a stale signature (not fed for
 * DIAG_TORQUE_FRESH steps) judges nothing; a pending motor-circuit code inhibits the check. */
static void test_torque_signature(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    int k;
    int pend = -1;
    int conf = -1;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    /* healthy: judged, passes */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 2000; ++k) {
        feed_synthetic(&dd, &d, &snap, k, TV_R(0.0), TV_R(0.0), TV_R(1.0), TV_R(1.0));
    }
    TV_CHECK_NEAR(dd.preload_fast, 1.0, 1e-4);
    TV_CHECK_NEAR(dd.friction_fast, 1.0, 1e-4);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P2119) && !diag_pending(&d, DIAG_DTC_P1A02));
    /* spring at 30 % from sample 2000 */
    for (k = 2000; k < 4000 && conf < 0; ++k) {
        feed_synthetic(&dd, &d, &snap, k, TV_R(0.7), TV_R(0.0), TV_R(1.0), TV_R(1.0));
        if (pend < 0 && diag_pending(&d, DIAG_DTC_P1A02)) {
            pend = k;
        }
        if (diag_confirmed(&d, DIAG_DTC_P1A02)) {
            conf = k;
        }
    }
    printf("  signature: spring at 30 %% pending %d ms, confirmed %d ms after the onset (preload read %.3f)\n", pend - 2000,
           conf - 2000, (double)dd.preload_fast);
    TV_CHECK(pend > 2000 && conf == pend + 2 * (int)DIAG_PARAM_DECIM);
    TV_CHECK_LE(conf - 2000, 300);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P2119) && !diag_confirmed(&d, DIAG_DTC_P2119));
    TV_CHECK((double)d.code[DIAG_DTC_P1A02].freeze.value < 0.5 && (double)d.code[DIAG_DTC_P1A02].freeze.value > 0.3 - 1e-3);
    for (k = conf + 1; k < conf + 1000; ++k) {
        feed_synthetic(&dd, &d, &snap, k, TV_R(0.7), TV_R(0.0), TV_R(1.0), TV_R(1.0));
    }
    TV_CHECK_NEAR(dd.preload_fast, 0.3, 1e-3);
    /* the estimator's own preload scales the reading: (1 + m)(1 - a) */
    for (k = 0; k < 1000; ++k) {
        feed_synthetic(&dd, &d, &snap, 10000 + k, TV_R(0.5), TV_R(0.0), TV_R(0.8), TV_R(1.0));
    }
    TV_CHECK_NEAR(dd.preload_fast, 0.4, 1e-3);
    /* friction x2 */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    pend = -1;
    conf = -1;
    for (k = 0; k < 4000 && conf < 0; ++k) {
        feed_synthetic(&dd, &d, &snap, k, TV_R(0.0), k >= 2000 ? TV_R(1.0) : TV_R(0.0), TV_R(1.0), TV_R(1.3));
        if (pend < 0 && diag_pending(&d, DIAG_DTC_P2119)) {
            pend = k;
        }
        if (diag_confirmed(&d, DIAG_DTC_P2119)) {
            conf = k;
        }
    }
    printf("  signature: friction x2 pending %d ms, confirmed %d ms after the onset\n", pend - 2000, conf - 2000);
    TV_CHECK(pend > 2000 && conf == pend + 9 * (int)DIAG_PARAM_DECIM);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_confirmed(&d, DIAG_DTC_P1A02));
    TV_CHECK((double)d.code[DIAG_DTC_P2119].freeze.value > 1.6 && (double)d.code[DIAG_DTC_P2119].freeze.value < 2.6 + 1e-3);
    for (k = conf + 1; k < conf + 1000; ++k) {
        feed_synthetic(&dd, &d, &snap, k, TV_R(0.0), TV_R(1.0), TV_R(1.0), TV_R(1.3));
    }
    TV_CHECK_NEAR(dd.friction_fast, 2.6, 1e-3);
    /* the same excess while the estimator's own level stays at 1.0: no code */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 4000; ++k) {
        feed_synthetic(&dd, &d, &snap, k, TV_R(0.0), k >= 2000 ? TV_R(1.0) : TV_R(0.0), TV_R(1.0), TV_R(1.0));
    }
    TV_CHECK_NEAR(dd.friction_fast, 2.0, 1e-3);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P2119));
    /* not judged: one direction of motion on one side only (collinear regressors; closing, toward
     * limp-home: the away reading, tested below, does not run either) */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 2000; ++k) {
        feed_synthetic(&dd, &d, &snap, 40 + (k % 40), TV_R(0.7), TV_R(0.0), TV_R(1.0), TV_R(1.0));
    }
    TV_CHECK(dd.preload_fast == TV_R(0.0) && !diag_pending(&d, DIAG_DTC_P1A02));
    /* not fed: the angle does not move (a blocked plate), or the torque exceeds the clip */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 2000; ++k) {
        const tv_real_t w = (k % 80) < 40 ? TV_R(2.0) : TV_R(-2.0);
        diag_jam_check(&dd, &d, 0, TV_R(0.0), TV_R(0.5), TV_R(0.0), TV_R(1.0), &snap);
        diag_torque_feed(&dd, 1, w, TV_R(-0.2), TV_R(0.0), TV_R(0.28), TV_R(0.2), TV_R(0.0));
        diag_torque_feed(&dd, 1, w, TV_R(0.61), TV_R(0.0), TV_R(0.28), TV_R(0.2), TV_R(0.0));
        diag_param_check(&dd, &d, 1, w, TV_R(1.0), TV_R(0.02), TV_R(1.0), TV_R(0.01), &snap);
    }
    TV_CHECK(dd.tq_w == TV_R(0.0) && !diag_pending(&d, DIAG_DTC_P1A02));
    /* stale: fed with a broken spring, then only checked (no feed) for longer than DIAG_TORQUE_FRESH */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 2000; ++k) {
        feed_synthetic(&dd, &d, &snap, k, TV_R(0.0), TV_R(0.0), TV_R(1.0), TV_R(1.0));
    }
    for (k = 0; k < 3; ++k) {
        feed_synthetic(&dd, &d, &snap, 2000 + k, TV_R(0.7), TV_R(0.0), TV_R(1.0), TV_R(1.0));
    }
    for (k = 0; k < 2000; ++k) {
        diag_param_check(&dd, &d, 1, TV_R(2.0), TV_R(1.0), TV_R(0.02), TV_R(1.0), TV_R(0.01), &snap);
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02));
    /* a pending open-winding code inhibits the check */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    snap.t_us = 1u;
    TV_CHECK_EQ_INT(diag_report(&d, DIAG_DTC_P2100, DIAG_FAIL, &snap, TV_R(0.0)), TV_OK);
    for (k = 0; k < 4000; ++k) {
        feed_synthetic(&dd, &d, &snap, k, TV_R(0.7), TV_R(0.0), TV_R(1.0), TV_R(1.0));
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_confirmed(&d, DIAG_DTC_P1A02));
}

/* A low preload read with the signature's friction above DIAG_PRELOAD_FAST_CLEAR (1.3) is
 * ambiguous (on some units more friction leaks into the spring column): it fails P1A02 only from
 * the DIAG_PRELOAD_FAST_AMBIG_HOLD-th (3rd) such check in a row. A spring at 30 % (a = 0.7) on a
 * plate whose friction is already 1.5x (e = 0.5 from the start: below friction_fast_high, no
 * P2119) goes pending 2 checks after its first low reading and confirms 2 checks later (5 checks
 * in all, as before P1A02's count of 3); with the friction 1.2x (clear) it goes pending at its
 * first low reading. Meanwhile the ambiguous checks neither fail nor pass. */
static void test_torque_signature_ambiguous(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    static const double excess[] = {0.2, 0.5};
    size_t c;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    TV_CHECK_NEAR(DIAG_PRELOAD_FAST_CLEAR, 1.3, 1e-6);
    TV_CHECK_EQ_INT(DIAG_PRELOAD_FAST_AMBIG_HOLD, 3);
    TV_CHECK_NEAR(cfg.preload_fast_friction_max, 2.0, 1e-6);
    for (c = 0; c < sizeof excess / sizeof excess[0]; ++c) {
        const tv_real_t e = (tv_real_t)excess[c];
        const int held = excess[c] > 0.3 ? 2 : 0; /* checks before the first failure */
        int k;
        int low = -1;
        int pend = -1;
        int conf = -1;
        diag_init(&d);
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
        for (k = 0; k < 2000; ++k) {
            feed_synthetic(&dd, &d, &snap, k, TV_R(0.0), e, TV_R(1.0), TV_R(1.0));
        }
        TV_CHECK_NEAR(dd.preload_fast, 1.0, 1e-3);
        TV_CHECK_NEAR(dd.friction_fast, 1.0 + excess[c], 1e-3);
        TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_pending(&d, DIAG_DTC_P2119));
        for (k = 2000; k < 4000 && conf < 0; ++k) {
            feed_synthetic(&dd, &d, &snap, k, TV_R(0.7), e, TV_R(1.0), TV_R(1.0));
            if (low < 0 && dd.preload_fast < TV_R(0.5)) {
                low = k;
                /* the first low reading: its friction on the side of the bound this case is about */
                TV_CHECK_EQ_INT(dd.friction_fast > DIAG_PRELOAD_FAST_CLEAR, held > 0);
                TV_CHECK(dd.friction_fast <= cfg.preload_fast_friction_max);
            }
            if (low >= 0 && k < low + held * (int)DIAG_PARAM_DECIM) {
                TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && d.code[DIAG_DTC_P1A02].counter == 0u);
            }
            if (pend < 0 && diag_pending(&d, DIAG_DTC_P1A02)) {
                pend = k;
            }
            if (diag_confirmed(&d, DIAG_DTC_P1A02)) {
                conf = k;
            }
        }
        printf("  signature, spring at 30 %% with friction %.1fx: first low reading %d ms, pending %d ms, confirmed %d ms "
               "after the onset (friction read %.3f)\n",
               1.0 + excess[c], low - 2000, pend - 2000, conf - 2000, (double)dd.friction_fast);
        TV_CHECK(low > 2000);
        TV_CHECK_EQ_INT(pend, low + held * (int)DIAG_PARAM_DECIM);
        TV_CHECK_EQ_INT(conf, pend + 2 * (int)DIAG_PARAM_DECIM);
        TV_CHECK(!diag_pending(&d, DIAG_DTC_P2119) && !diag_confirmed(&d, DIAG_DTC_P2119));
    }
}

/* Records the sample k at which P1A02 is first pending and first confirmed (-1 until then). */
static void first_p1a02(const diag_t *d, int k, int *pend, int *conf)
{
    if (*pend < 0 && diag_pending(d, DIAG_DTC_P1A02)) {
        *pend = k;
    }
    if (*conf < 0 && diag_confirmed(d, DIAG_DTC_P1A02)) {
        *conf = k;
    }
}

/* A fresh detector fed n synthetic samples (feed_synthetic(), sample k % k_mod, or k when k_mod is
 * 0) of a spring deficit a and a friction excess e at the estimator's levels pre and fr; the
 * first samples at which P1A02 went pending and confirmed (-1: never). */
static void synthetic_p1a02(diag_detect_t *dd, diag_t *d, const diag_detect_config_t *cfg, diag_snapshot_t *snap, int n,
                            int k_mod, double a, double e, double pre, double fr, int *pend, int *conf)
{
    int k;
    *pend = -1;
    *conf = -1;
    diag_init(d);
    TV_CHECK_EQ_INT(diag_detect_init(dd, cfg), TV_OK);
    for (k = 0; k < n; ++k) {
        feed_synthetic(dd, d, snap, k_mod > 0 ? k % k_mod : k, (tv_real_t)a, (tv_real_t)e, (tv_real_t)pre, (tv_real_t)fr);
        first_p1a02(d, k, pend, conf);
    }
}

/* DIAG_PRELOAD_BOTH_LOW / DIAG_FRICTION_BOTH_LOW: synthetic samples whose 2x2 answer is exact
 * (feed_synthetic(), the estimator's levels at 1): a preload of 0.55 with a friction of 0.45
 * (a = 0.45, e = -0.55) fails P1A02 although 0.55 is above preload_fast_low 0.5, and confirms;
 * the same preload with a friction of 0.55, or a friction of 0.4 with a preload of 0.65, is
 * judged (read exactly) and passes. The away reading is kept out (its speed bound below the
 * samples' 2 rad/s): its opening samples read each of these spring deficits alone, and fail. */
static void test_torque_signature_both_low(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    static const struct {
        double a, e, pf, ff;
        int fails;
    } cases[] = {{0.45, -0.55, 0.55, 0.45, 1}, {0.45, -0.45, 0.55, 0.55, 0}, {0.35, -0.6, 0.65, 0.4, 0}};
    size_t c;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    TV_CHECK_NEAR(DIAG_PRELOAD_BOTH_LOW, 0.6, 1e-6);
    TV_CHECK_NEAR(DIAG_FRICTION_BOTH_LOW, 0.5, 1e-6);
    TV_CHECK_NEAR(cfg.preload_fast_low, 0.5, 1e-6);
    cfg.away_w_max_rad_s = TV_R(1.0);
    for (c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        int pend;
        int conf;
        synthetic_p1a02(&dd, &d, &cfg, &snap, 3000, 0, cases[c].a, cases[c].e, 1.0, 1.0, &pend, &conf);
        TV_CHECK_NEAR(dd.preload_fast, cases[c].pf, 1e-4);
        TV_CHECK_NEAR(dd.friction_fast, cases[c].ff, 1e-4);
        if (cases[c].fails) {
            TV_CHECK(pend >= 0 && conf == pend + 2 * (int)DIAG_PARAM_DECIM);
            TV_CHECK_NEAR(d.code[DIAG_DTC_P1A02].freeze.value, cases[c].pf, 1e-4);
        } else {
            TV_CHECK(pend < 0 && conf < 0);
        }
    }
}

/* Opening moves alone (feed_synthetic()'s first 40 samples of each 80: w = +2 rad/s at phi =
 * 0.5..0.54 rad, moving away from limp-home) with a spring deficit a: spring and friction both
 * oppose the move, so the signature cannot split them; the AWAY READING takes the friction they
 * imply. Per sample y = a s with s = 0.25 + 0.059 phi (0.2795 N m at its mean) and the friction
 * regressor -0.2 N m, so the implied friction is (1 + f)(1 - a s / 0.2); worked by hand with the
 * mean of s over the angles 0.500..0.539 rad (0.2806 N m; the weighting moves it by < 0.1 %):
 *   - spring at 30 % (a = 0.7): 1 - 0.982 = 0.018 < 0.35: P1A02 fails at every check from the
 *     first with enough weight and confirms at the 3rd (value: the reading);
 *   - spring at 70 % (a = 0.3): 1 - 0.421 = 0.58: no failure (a weaker spring is left to the
 *     signature and the adapted level);
 *   - a spring deficit partly taken up by the adapted friction, 1 + f = 0.6 with a = 0.2:
 *     0.6 (1 - 0.281) = 0.43: no failure (and it is no friction fault); with 1 + f = 0.4 the
 *     reading is 0.4 (1 - 0.281) = 0.29, below the bound: fails (a plate sliding on 29 % of its
 *     model's friction; the healthy soak's lowest reading is 0.52);
 *   - a preload adapted high with the friction low, as on a healthy class-a unit in the chirp
 *     (1 + m = 1.47, 1 + f = 0.6) and a = 0.6 left: as adapted 0.6 (1 - 0.842) = 0.095, with the
 *     nominal spring the adapted share m M0 = 0.47 x 0.25 goes back to the friction,
 *     + 0.6 x 0.1175 / 0.2 = 0.35 (the mean friction regressor is 0.2 N m here): 0.447, the
 *     larger is judged, no failure; the same with 1 + m = 1 fails (0.095). Samples faster than
 *     away_w_max_rad_s are not fed: none here (2 rad/s). */
static void test_away_reading(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    static const struct {
        double a, pre_rel, fr_rel;
        double fails_at; /* the reading in the freeze frame; 0: no failure */
    } cases[] = {{0.7, 1.0, 1.0, 0.018}, {0.3, 1.0, 1.0, 0.0}, {0.2, 1.0, 0.6, 0.0}, {0.2, 1.0, 0.4, 0.288}, {0.6, 1.47, 0.6, 0.0},
                 {0.6, 1.0, 0.6, 0.095}};
    size_t c;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    for (c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        int pend;
        int conf;
        synthetic_p1a02(&dd, &d, &cfg, &snap, 2000, 40, cases[c].a, 0.0, cases[c].pre_rel, cases[c].fr_rel, &pend, &conf);
        TV_CHECK(dd.preload_fast == TV_R(0.0)); /* the 2x2 signature never judged: collinear */
        if (cases[c].fails_at > 0.0) {
            /* fed from sample 7 (the jam window's 8 angles); the weight 50 (1 - 0.98^n) reaches
             * torque_min_weight 30 at the 46th feed (sample 52); checks run at samples 9, 19, ...:
             * the first judged is sample 59, the 3rd failing one confirms at 79 */
            TV_CHECK_EQ_INT(pend, 59);
            TV_CHECK_EQ_INT(conf, 79);
            TV_CHECK_NEAR(d.code[DIAG_DTC_P1A02].freeze.value, cases[c].fails_at, 0.002);
        } else {
            TV_CHECK(pend < 0 && conf < 0);
        }
    }
    /* the same spring at 30 % with the threshold below its reading (0.018): never fails */
    cfg.away_friction_min = TV_R(0.01);
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    {
        int k;
        int pended = 0;
        for (k = 0; k < 2000; ++k) {
            feed_synthetic(&dd, &d, &snap, k % 40, TV_R(0.7), TV_R(0.0), TV_R(1.0), TV_R(1.0));
            pended |= diag_pending(&d, DIAG_DTC_P1A02);
        }
        TV_CHECK(!pended);
    }
    /* faster than away_w_max_rad_s (6 rad/s > 5): not fed to the away reading (the viscous
     * friction's spread), while the signature's own sums still are */
    diag_detect_config_default(&cfg);
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    {
        int k;
        for (k = 0; k < 200; ++k) {
            diag_jam_check(&dd, &d, 0, TV_R(0.0), TV_R(0.5) + TV_R(0.006) * (tv_real_t)k, TV_R(0.0), TV_R(1.0), &snap);
            diag_torque_feed(&dd, 1, TV_R(6.0), TV_R(0.2), TV_R(0.0), TV_R(0.28), TV_R(0.2), TV_R(0.0));
        }
        TV_CHECK(dd.aw_w == TV_R(0.0) && dd.tq_w > TV_R(30.0));
    }
}

/* DIAG_AWAY_STALE_CHECKS: the away reading keeps its verdict for 2 checks after its newest
 * away sample. A spring at 30 % (a = 0.7) read on opening moves (feed_synthetic()'s first 40
 * samples: reading 0.018) until sample `last`, then samples too fast for the reading (6 rad/s >
 * away_w_max_rad_s: fed to the signature, collinear there, not to the away reading). Checks run
 * at samples 9, 19, ...; the reading has its weight (30) from sample 52. Away samples to 62: the
 * check at 59 fails with a fresh sample, 69 and 79 (1 and 2 checks stale) fail too, confirmed at
 * 79, as with away samples throughout. Away samples to 52: 59 and 69 (stale 1, 2) fail, 79 (stale
 * 3) is not judged: pending from 59, never confirmed (before this rule the first case stayed
 * pending too: only a check whose newest sample was an away one judged). */
static void test_away_stale(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    static const int last[2] = {62, 52};
    int c;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    TV_CHECK_EQ_INT((int)DIAG_AWAY_STALE_CHECKS, 2);
    for (c = 0; c < 2; ++c) {
        int k;
        int pend = -1;
        int conf = -1;
        diag_init(&d);
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
        for (k = 0; k < 300; ++k) {
            if (k <= last[c]) {
                feed_synthetic(&dd, &d, &snap, k % 40, TV_R(0.7), TV_R(0.0), TV_R(1.0), TV_R(1.0));
            } else {
                snap.t_us = (uint64_t)k * 1000u;
                diag_jam_check(&dd, &d, 0, TV_R(0.0), TV_R(0.001) * (tv_real_t)k, TV_R(0.0), TV_R(1.0), &snap);
                diag_torque_feed(&dd, 1, TV_R(6.0), TV_R(0.7) * TV_R(0.28), TV_R(0.0), TV_R(0.28), TV_R(0.2), TV_R(0.0));
                diag_param_check(&dd, &d, 1, TV_R(6.0), TV_R(1.0), TV_R(0.02), TV_R(1.0), TV_R(0.01), &snap);
            }
            first_p1a02(&d, k, &pend, &conf);
        }
        printf("  away samples to %d: P1A02 pending at %d, confirmed at %d\n", last[c], pend, conf);
        TV_CHECK(dd.aw_stale > DIAG_AWAY_STALE_CHECKS); /* stale since */
        TV_CHECK(dd.preload_fast == TV_R(0.0));         /* the 2x2 signature never judged */
        TV_CHECK_EQ_INT(pend, 59);
        TV_CHECK_EQ_INT(conf, c == 0 ? 79 : -1);
    }
}

/* Feeds n away-moving samples (w = +2 rad/s, the angle rising 2 mrad a sample from phi0) with
 * unexplained torque y, spring torque 0.28 N m, friction 0.2 N m. Returns the next angle. */
static tv_real_t feed_away(diag_detect_t *dd, diag_t *d, diag_snapshot_t *snap, tv_real_t phi0, int n, tv_real_t y)
{
    int k;
    for (k = 0; k < n; ++k, phi0 += TV_R(0.002)) {
        diag_jam_check(dd, d, 0, TV_R(0.0), phi0, TV_R(0.0), TV_R(1.0), snap);
        diag_torque_feed(dd, 1, TV_R(2.0), y, TV_R(0.0), TV_R(0.28), TV_R(0.2), TV_R(0.0));
    }
    return phi0;
}

/* DIAG_TORQUE_PAUSE: 300 healthy away-moving steps (fed from the 8th: weight 50 (1 - 0.98^293) = 49.9), then
 * the feed pauses. After DIAG_TORQUE_PAUSE + 1 steps without a sample, the next sample first
 * scales the sums from before to torque_min_weight (30) samples, keeping their ratios: weight
 * 30 x 0.98 + 1 = 30.4 in the signature's and the away reading's sums (the spring probe's
 * opening reading to probe_min_weight: 5 x 0.98 + 1 = 5.9), the away friction sum 0.2
 * per sample; after a pause of exactly DIAG_TORQUE_PAUSE steps nothing is rescaled (weight
 * 0.98 x 49.9 + 1). A broken spring's samples (y = +0.28 along the motion: the spring torque the
 * model opposes the move with is gone) then bring the away reading 1 + sum(-y) / sum(F) below
 * away_friction_min 0.35. By hand, after the long pause (sums 30 samples: F 6, y 0) the n-th
 * sample gives sum F = 10 - 4 x 0.98^n and sum(-y) = -14 (1 - 0.98^n), below T = 0.35 once
 * (1 - T) sum F < 14 (1 - 0.98^n), i.e. 0.98^n < 7.5 / 11.4: n = 21; without the rescale (F 0.2 x
 * 49.9 x 0.98^n, F0 = 9.984) once 0.98^n < 7.5 / (14 - 0.65 x 0.016) = 7.5 / 13.9896: n = 31. */
static void test_torque_pause(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    int pause;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    TV_CHECK_EQ_INT((int)DIAG_TORQUE_PAUSE, 250);
    TV_CHECK_NEAR(cfg.torque_min_weight, 30.0, 1e-9);
    for (pause = (int)DIAG_TORQUE_PAUSE; pause <= (int)DIAG_TORQUE_PAUSE + 1; ++pause) {
        const int long_pause = pause > (int)DIAG_TORQUE_PAUSE;
        const double w0 = 50.0 * (1.0 - pow(0.98, 293.0)); /* fed from the 8th (the jam window's) */
        tv_real_t phi;
        int k;
        int n;
        diag_init(&d);
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
        phi = feed_away(&dd, &d, &snap, TV_R(0.2), 300, TV_R(0.0));
        TV_CHECK_NEAR(dd.aw_w, w0, 1e-3);
        TV_CHECK_NEAR(dd.tq_w, w0, 1e-3);
        for (k = 0; k < pause; ++k) { /* no sample: the age grows at every step's check */
            diag_param_check(&dd, &d, 0, TV_R(0.0), TV_R(1.0), TV_R(0.01), TV_R(1.0), TV_R(0.01), &snap);
        }
        /* the jam window must see the plate move again before the next sample counts */
        for (k = 0; k < (int)DIAG_JAM_WINDOW - 1; ++k, phi += TV_R(0.002)) {
            diag_jam_check(&dd, &d, 0, TV_R(0.0), phi, TV_R(0.0), TV_R(1.0), &snap);
        }
        TV_CHECK_NEAR(dd.aw_w, w0, 1e-3); /* not fed yet */
        phi = feed_away(&dd, &d, &snap, phi, 1, TV_R(0.28));
        TV_CHECK_NEAR(dd.aw_w, long_pause ? 30.0 * 0.98 + 1.0 : 0.98 * w0 + 1.0, 1e-3);
        TV_CHECK_NEAR(dd.tq_w, long_pause ? 30.0 * 0.98 + 1.0 : 0.98 * w0 + 1.0, 1e-3);
        TV_CHECK_NEAR(dd.aw_fs, TV_R(0.2) * dd.aw_w, 1e-4);
        /* the spring probe's opening reading (these samples move away from limp-home): rescaled
         * to probe_min_weight (5), its spring sums with it (s = 0.28 in every sample) */
        TV_CHECK_NEAR(dd.po.w, long_pause ? 5.0 * 0.98 + 1.0 : 0.98 * w0 + 1.0, 1e-3);
        TV_CHECK_NEAR(dd.po.ss, TV_R(0.28) * TV_R(0.28) * dd.po.w, 1e-4);
        TV_CHECK(dd.pc.w == TV_R(0.0));
        /* the away reading with the model's levels (1 + f = 1 + m = 1) */
        n = 1;
        while (!(TV_R(1.0) + dd.aw_fy / dd.aw_fs < cfg.away_friction_min) && n < 200) {
            phi = feed_away(&dd, &d, &snap, phi, 1, TV_R(0.28));
            ++n;
        }
        printf("  pause %d steps: away reading below %.2f after %d samples of a broken spring\n", pause,
               (double)cfg.away_friction_min, n);
        TV_CHECK(n < 200);
        TV_CHECK_EQ_INT(n, long_pause ? 21 : 31);
    }
}

/* Latencies of one adapted-mechanics fault over a set of runs. */
typedef struct {
    int detected;
    double best_s;
    double worst_s; /* 1e9 once a run misses */
} latency_t;

/* One 12 s run of the nominal unit with spec from 1.0 s: the latency of code `own` into *l;
 * the other mechanics code `other` must not confirm. */
static void mechanics_run(const plant_config_t *pc, const app_config_t *ac, sim_scenario_t scn, uint64_t seed,
                          const char *spec, diag_dtc_t own, diag_dtc_t other, latency_t *l)
{
    sim_result_t r;
    double t;
    sim_fault_run(pc, ac, scn, seed, spec, 12.0, &r);
    t = isfinite(r.dtc_confirm_t_s[own]) ? r.dtc_confirm_t_s[own] - 1.0 : 1e9;
    l->detected += t < 1e9 ? 1 : 0;
    l->worst_s = fmax(l->worst_s, t);
    l->best_s = fmin(l->best_s, t);
    TV_CHECK(!isfinite(r.dtc_confirm_t_s[other]));
}

/* Friction x2 (Coulomb and static) and a return spring at 30 % (preload and rate) from 1.0 s,
 * in the scenarios whose plate slides fast enough for the estimator to follow (closed-loop
 * steps, the 12 V sine, open-loop steps, chirp), nominal unit, 3 seeds, 12 s runs: the fault's
 * own code confirmed within 8 s of the onset (since the torque signature: within about 1 s),
 * never the other's. */
static void test_friction_and_spring_codes(void)
{
    static const sim_scenario_t scn[4] = {SIM_SCN_CLOSED_STEPS, SIM_SCN_PAPER_SINE, SIM_SCN_OPEN_STEPS, SIM_SCN_CHIRP};
    static plant_config_t pc;
    static app_config_t ac;
    latency_t lf = {0, 1e9, 0.0};
    latency_t lm = {0, 1e9, 0.0};
    uint64_t seed;
    int s;
    int runs = 0;
    plant_config_default(&pc);
    app_config_default(&ac);
    for (seed = 1u; seed <= 3u; ++seed) {
        for (s = 0; s < 4; ++s) {
            mechanics_run(&pc, &ac, scn[s], seed, "friction_high:2@1.0", DIAG_DTC_P2119, DIAG_DTC_P1A02, &lf);
            mechanics_run(&pc, &ac, scn[s], seed, "spring_weak:0.3@1.0", DIAG_DTC_P1A02, DIAG_DTC_P2119, &lm);
            ++runs;
        }
    }
    printf("  friction x2: P2119 in %d of %d runs, %.2f..%.2f s after the onset; spring at 30 %%: P1A02 in %d of %d, "
           "%.2f..%.2f s\n",
           lf.detected, runs, lf.best_s, lf.worst_s, lm.detected, runs, lm.best_s, lm.worst_s);
    TV_CHECK_EQ_INT(lf.detected, runs);
    TV_CHECK_EQ_INT(lm.detected, runs);
    TV_CHECK_LE(lf.worst_s, 8.0);
    TV_CHECK_LE(lm.worst_s, 8.0);
}

/* A scripted current for the current-sensor checks: period 50 samples, i sweeps -0.25..+0.25 A
 * (a triangle) and w a different triangle (period 34 samples, -3..+3 rad/s): both regressors
 * vary independently, so the window's intercept is well determined. */
static tv_real_t isens_i(int k)
{
    const int p = k % 50;
    return (tv_real_t)((p < 25 ? p : 50 - p) - 12.5) * TV_R(0.02);
}
static tv_real_t isens_w(int k)
{
    const int p = k % 34;
    return (tv_real_t)((p < 17 ? p : 34 - p) - 8.5) * (TV_R(3.0) / TV_R(8.5));
}

/* The current-sensor checks' timing on scripted inputs (P1A04, diag_detect.h):
 * ZERO CHECK: the bridge off; the first DIAG_ISENS_SETTLE - 1 calls do not count (the current
 * decays), then every DIAG_ISENS_ZERO_N counted samples are one check: a mean of 0.05 A fails,
 * and the 6th failing check (the code's confirm count) confirms, i.e. at counted sample 6 x 32 =
 * 192, with the mean in the freeze frame; a healthy sensor reading +-0.01 A of noise (mean 0)
 * passes; 8 passing checks heal. IN SERVICE: y = b + 0.2 i + 0.01 w (a resistance error of 20 %
 * of 1/R and a back-EMF error, the healthy spread; i the predicted current, measured = i + y) with
 * b = 0.05 A fails every window of DIAG_ISENS_WIN samples and confirms at the 6th (sample 3,000),
 * the intercept 0.05 in the freeze
 * frame; with b = 0 it passes however large the slopes; samples above 0.3 A are skipped, a
 * constant current is not judged. */
static void test_current_sensor_check_timing(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    diag_event_t ev;
    int k;
    int first = -1;
    diag_detect_config_default(&cfg);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_init(&d);
    memset(&snap, 0, sizeof snap);
    /* zero check, healthy: noise of +-0.01 A around 0 never fails */
    for (k = 0; k < 5000; ++k) {
        diag_current_sensor_check(&dd, &d, 0, 1, 0, (k & 1) ? TV_R(0.01) : TV_R(-0.01), TV_R(0.0), TV_R(0.0), &snap);
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_confirmed(&d, DIAG_DTC_P1A04));
    /* zero check, an offset of 0.05 A from a fresh start with the bridge off */
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_init(&d);
    for (k = 1; k <= 400 && first < 0; ++k) {
        snap.t_us = (uint64_t)k * 1000u;
        diag_current_sensor_check(&dd, &d, 0, 1, 0, TV_R(0.05), TV_R(0.0), TV_R(0.0), &snap);
        if (k == (int)DIAG_ISENS_SETTLE - 1 + 32) {
            TV_CHECK(diag_pending(&d, DIAG_DTC_P1A04)); /* the first check (32 counted samples) failed */
        }
        if (diag_confirmed(&d, DIAG_DTC_P1A04)) {
            first = k;
        }
    }
    TV_CHECK_EQ_INT(first, (int)DIAG_ISENS_SETTLE - 1 + 6 * 32);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A04].freeze.value, 0.05, 1e-5);
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P1A04].freeze.t_us, (uint64_t)first * 1000u);
    /* an implausible sample is not counted: healing needs 8 x 32 counted zero samples */
    for (k = 0; k < 100; ++k) {
        diag_current_sensor_check(&dd, &d, 0, 0, 0, TV_R(0.0), TV_R(0.0), TV_R(0.0), &snap);
    }
    for (k = 1; k <= 8 * 32; ++k) {
        TV_CHECK(diag_confirmed(&d, DIAG_DTC_P1A04));
        diag_current_sensor_check(&dd, &d, 0, 1, 0, TV_R(0.0), TV_R(0.0), TV_R(0.0), &snap);
    }
    TV_CHECK(!diag_confirmed(&d, DIAG_DTC_P1A04));
    while (diag_event_pop(&d, &ev)) {
        if (ev.dtc == DIAG_DTC_P1A04 && ev.kind == DIAG_EV_HEALED) {
            first = -2;
        }
    }
    TV_CHECK_EQ_INT(first, -2);

    /* in service, healthy: large slopes on i and w, no intercept: passes (judged: no pending) */
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_init(&d);
    for (k = 0; k < 20 * (int)DIAG_ISENS_WIN; ++k) {
        const tv_real_t i = isens_i(k);
        const tv_real_t w = isens_w(k);
        const tv_real_t y = TV_R(0.2) * i + TV_R(0.01) * w;
        diag_current_sensor_check(&dd, &d, 1, 1, 1, i + y, y, w, &snap); /* measured = predicted + innovation */
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_confirmed(&d, DIAG_DTC_P1A04));
    /* healthy, with stop impacts: every 25th sample a -1.45 A innovation at a small predicted
     * current (class-b unit 1001's impacts in the 12 V sine, README "P1A04 and stop impacts").
     * Beyond isens_innov_max_A they are skipped and the windows pass; with the gate opened
     * (10 A) the same samples shift each intercept by -1.45 / 25 = -0.058 A and P1A04 confirms:
     * the gate is what keeps it quiet. */
    for (first = 0; first < 2; ++first) {
        diag_detect_config_t c2 = cfg;
        if (first == 1) {
            c2.isens_innov_max_A = TV_R(10.0);
        }
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &c2), TV_OK);
        diag_init(&d);
        for (k = 0; k < 10 * (int)DIAG_ISENS_WIN; ++k) {
            const tv_real_t i = isens_i(k);
            const tv_real_t w = isens_w(k);
            const tv_real_t y = k % 25 == 24 ? TV_R(-1.45) : TV_R(0.2) * i + TV_R(0.01) * w;
            diag_current_sensor_check(&dd, &d, 1, 1, 1, i + y, y, w, &snap);
        }
        TV_CHECK(first == 0 ? !diag_pending(&d, DIAG_DTC_P1A04) : diag_confirmed(&d, DIAG_DTC_P1A04));
    }
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_init(&d);
    /* a constant current (one sign, one speed): the intercept is not determined, not judged */
    for (k = 0; k < 10 * (int)DIAG_ISENS_WIN; ++k) {
        diag_current_sensor_check(&dd, &d, 1, 1, 1, TV_R(0.2), TV_R(0.1), TV_R(1.0), &snap);
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_confirmed(&d, DIAG_DTC_P1A04));
    /* in service, an offset of 0.05 A: the 4th window confirms; samples above 0.3 A interleaved
     * are skipped (they would pull the intercept: y = 1 there) and do not count */
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_init(&d);
    first = -1;
    for (k = 0; k < 8 * (int)DIAG_ISENS_WIN && first < 0; ++k) {
        const tv_real_t i = isens_i(k);
        const tv_real_t w = isens_w(k);
        snap.t_us = (uint64_t)k * 1000u;
        diag_current_sensor_check(&dd, &d, 1, 1, 1, TV_R(2.0), TV_R(1.0), w, &snap);
        const tv_real_t y = TV_R(0.05) + TV_R(0.2) * i + TV_R(0.01) * w;
        diag_current_sensor_check(&dd, &d, 1, 1, 1, i + y, y, w, &snap);
        if (diag_confirmed(&d, DIAG_DTC_P1A04)) {
            first = k;
        }
    }
    /* the first DIAG_ISENS_SETTLE - 1 calls (bridge just on) do not count: the 3,000th counted
     * sample is the call pair k = 2,999 */
    TV_CHECK_EQ_INT(first, 6 * (int)DIAG_ISENS_WIN - 1);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A04].freeze.value, 0.05, 1e-4);
    /* a window interrupted by the bridge switching off waits and goes on when it drives again
     * (limp_home's cycles drive too briefly to fill a window between two offs: an identified
     * unit's current gain went unjudged there): every 500 calls, 100 with the bridge off reading
     * 0 A (zero checks that pass), then 400 driving with an offset of 0.05 A, the first of them
     * not counted (DIAG_ISENS_SETTLE); 399 counted in the first drive, the window's 500th is the
     * 101st counted of the second, call 500 + 100 + 1 + 100 = 701, where P1A04 goes pending */
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_init(&d);
    first = -1;
    for (k = 0; k < 4 * (int)DIAG_ISENS_WIN && first < 0; ++k) {
        const int on = k % 500 >= 100;
        const tv_real_t i = isens_i(k);
        const tv_real_t w = isens_w(k);
        diag_current_sensor_check(&dd, &d, on, 1, 1, on ? TV_R(0.05) + i : TV_R(0.0), TV_R(0.05), w, &snap);
        if (diag_pending(&d, DIAG_DTC_P1A04)) {
            first = k;
        }
    }
    TV_CHECK_EQ_INT(first, 701);
    /* an estimator that did not correct with the current (innov_ok = 0) does restart it */
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_init(&d);
    for (k = 0; k < 10 * (int)DIAG_ISENS_WIN; ++k) {
        const tv_real_t i = isens_i(k);
        const tv_real_t w = isens_w(k);
        diag_current_sensor_check(&dd, &d, 1, 1, k % 400 != 0, TV_R(0.05) + i, TV_R(0.05), w, &snap);
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
    /* the band scales with the preload-holding current (diag_detect_set_preload()): the same
     * offset (a 10 % slope on i) with the current sweeping +-0.5 A. Until set, the paper's band (0.8 x 0.25 / (40 x
     * 0.017) = 0.294 A) counts 29 of every 50 samples, so the 3,000th call pair has not confirmed;
     * with the hold current of class b (0.32 / (40 x 0.011) = 0.727 A: a band of 0.58 A) every
     * sample counts and it confirms exactly there. A hold current that is not > 0 is refused and
     * leaves the band as it was. */
    for (first = 0; first < 2; ++first) {
        int confirmed_at = -1;
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
        diag_init(&d);
        if (first == 1) {
            TV_CHECK_EQ_INT(diag_detect_set_preload(&dd, TV_R(0.32), TV_R(40.0) * TV_R(0.011)), TV_OK);
            TV_CHECK_EQ_INT(diag_detect_set_preload(&dd, TV_R(0.0), TV_R(0.44)), TV_ERR_CONFIG);
            TV_CHECK_EQ_INT(diag_detect_set_preload(&dd, TV_R(0.32), TV_R(-1.0)), TV_ERR_CONFIG);
            TV_CHECK_EQ_INT(diag_detect_set_preload(NULL, TV_R(0.32), TV_R(0.44)), TV_ERR_NULL);
        }
        for (k = 0; k < 6 * (int)DIAG_ISENS_WIN && confirmed_at < 0; ++k) {
            const tv_real_t i = TV_R(2.0) * isens_i(k);
            const tv_real_t w = isens_w(k);
            const tv_real_t y = TV_R(0.05) + TV_R(0.1) * i + TV_R(0.01) * w; /* |y| <= 0.13: inside the impact gate */
            diag_current_sensor_check(&dd, &d, 1, 1, 1, TV_R(2.0), TV_R(1.0), w, &snap);
            diag_current_sensor_check(&dd, &d, 1, 1, 1, i + y, y, w, &snap);
            if (diag_confirmed(&d, DIAG_DTC_P1A04)) {
                confirmed_at = k;
            }
        }
        TV_CHECK_EQ_INT(confirmed_at, first == 1 ? 6 * (int)DIAG_ISENS_WIN - 1 : -1);
        TV_CHECK(first == 1 || diag_pending(&d, DIAG_DTC_P1A04)); /* the paper's band: judged, just later */
    }
    /* thresholds out of range are refused */
    cfg.isens_vif_max = TV_R(0.5);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    diag_detect_config_default(&cfg);
    cfg.isens_i_max_hold = TV_R(0.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    diag_detect_config_default(&cfg);
    cfg.isens_innov_max_A = TV_R(0.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
}

/* Scripted in-service samples from a fresh detector on cfg: the counted sample j (the first
 * DIAG_ISENS_SETTLE - 1 calls, the bridge just on, are not counted) has predicted current cur(j),
 * velocity isens_w(j) and innovation y = bias + ki i + 0.01 w; up to n_win windows. Returns the
 * call index at which P1A04 is confirmed, -1 if never; *d holds the codes. */
static int isens_scripted(const diag_detect_config_t *cfg, tv_real_t (*cur)(int), tv_real_t bias, tv_real_t ki, int n_win,
                          diag_t *d)
{
    static diag_detect_t dd;
    diag_snapshot_t snap;
    int k;
    memset(&snap, 0, sizeof snap);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, cfg), TV_OK);
    diag_init(d);
    for (k = 0; k < n_win * (int)DIAG_ISENS_WIN + (int)DIAG_ISENS_SETTLE; ++k) {
        const int j = k < (int)DIAG_ISENS_SETTLE - 1 ? 0 : k - ((int)DIAG_ISENS_SETTLE - 1);
        const tv_real_t i = cur(j);
        const tv_real_t w = isens_w(j);
        const tv_real_t y = bias + ki * i + TV_R(0.01) * w;
        diag_current_sensor_check(&dd, d, 1, 1, 1, i + y, y, w, &snap);
        if (diag_confirmed(d, DIAG_DTC_P1A04)) {
            return k;
        }
    }
    return -1;
}

/* The in-service window's variance-inflation bound (isens_vif_max, default 6): an offset of
 * 0.05 A seen through a current that alternates between c - 0.05 and c + 0.05 A (one sign) and a
 * zero-mean velocity. The inflation 1 + m' C^-1 m, worked out here from the window's samples in
 * double precision (independently of the detector's sums), is about 1 + (c / 0.05)^2: c = 0.1
 * gives 5, judged (P1A04 confirmed at the 6th window: all_varied units 1006 and 1008 in `drive`
 * read +-50 mA at 4.2 - 5.8); c = 0.1225 gives 7, not judged. The two currents: */
static tv_real_t isens_i_c1(int j)
{
    return (tv_real_t)(0.1 + ((j & 1) ? 0.05 : -0.05));
}
static tv_real_t isens_i_c2(int j)
{
    return (tv_real_t)(0.1225 + ((j & 1) ? 0.05 : -0.05));
}

static double isens_vif_of(tv_real_t (*cur)(int))
{
    double si = 0.0, sw = 0.0, sii = 0.0, siw = 0.0, sww = 0.0;
    double mi, mw, cii, ciw, cww, det;
    const double n = (double)DIAG_ISENS_WIN;
    int k;
    for (k = 0; k < (int)DIAG_ISENS_WIN; ++k) {
        const double i = (double)cur(k);
        const double w = (double)isens_w(k);
        si += i;
        sw += w;
        sii += i * i;
        siw += i * w;
        sww += w * w;
    }
    mi = si / n;
    mw = sw / n;
    cii = sii / n - mi * mi;
    ciw = siw / n - mi * mw;
    cww = sww / n - mw * mw;
    det = cii * cww - ciw * ciw;
    return 1.0 + (cww * mi * mi - 2.0 * ciw * mi * mw + cii * mw * mw) / det;
}

static void test_current_sensor_vif_bound(void)
{
    static diag_t d;
    diag_detect_config_t cfg;
    diag_detect_config_default(&cfg);
    TV_CHECK_NEAR(cfg.isens_vif_max, 6.0, 1e-6);
    TV_CHECK_NEAR(isens_vif_of(isens_i_c1), 5.0, 0.2);
    TV_CHECK_NEAR(isens_vif_of(isens_i_c2), 7.0, 0.2);
    TV_CHECK_EQ_INT(isens_scripted(&cfg, isens_i_c1, TV_R(0.05), TV_R(0.1), 8, &d),
                    6 * (int)DIAG_ISENS_WIN + (int)DIAG_ISENS_SETTLE - 2);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A04].freeze.value, 0.05, 1e-4);
    TV_CHECK_EQ_INT(isens_scripted(&cfg, isens_i_c2, TV_R(0.05), TV_R(0.1), 8, &d), -1);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
}

/* A current-sensor offset of +-50 mA from 1.0 s (issue 12's target) on the nominal unit, seed 1
 * and 2: P1A04 confirmed and no other code. With the bridge off (limp_home: off from 0.6 s to
 * 1.2 s) the zero check confirms within 6 x 32 ms + 2 ms of the onset; in service (standstill,
 * closed-loop steps, 12 s) the regression needs 6 windows of 500 samples at |i| <= 0.3 A:
 * within 10 s of the onset. A current-gain error of 5 % is not detected (README: it is a
 * resistance / torque-constant error inside the population's spread): asserted here so that a
 * change of the statistic that starts seeing it is noticed, and so that it does not confirm
 * another code. */
static void test_current_sensor_offset_detected(void)
{
    static const char *const spec[2] = {"current_offset:0.05@1.0", "current_offset:-0.05@1.0"};
    static const sim_scenario_t scn[3] = {SIM_SCN_LIMP_HOME, SIM_SCN_STANDSTILL, SIM_SCN_CLOSED_STEPS};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    uint64_t seed;
    int s;
    int f;
    int d;
    int detected = 0;
    int runs = 0;
    double worst_zero = 0.0;
    double worst_service = 0.0;
    plant_config_default(&pc);
    app_config_default(&ac);
    for (seed = 1u; seed <= 2u; ++seed) {
        for (s = 0; s < 3; ++s) {
            for (f = 0; f < 2; ++f) {
                sim_fault_run(&pc, &ac, scn[s], seed, spec[f], s == 0 ? 0.0 : 12.0, &r);
                ++runs;
                if (isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04])) {
                    const double t = r.dtc_confirm_t_s[DIAG_DTC_P1A04] - 1.0;
                    ++detected;
                    if (s == 0) {
                        worst_zero = fmax(worst_zero, t);
                    } else {
                        worst_service = fmax(worst_service, t);
                    }
                }
                for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
                    TV_CHECK(d == (int)DIAG_DTC_P1A04 || !isfinite(r.dtc_confirm_t_s[d]));
                }
            }
        }
        sim_fault_run(&pc, &ac, SIM_SCN_CLOSED_STEPS, seed, "current_gain:5@1.0", 12.0, &r);
        for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[d]));
        }
    }
    printf("  current offset +-50 mA: P1A04 in %d of %d runs, zero check within %.3f s, in service within %.2f s\n",
           detected, runs, worst_zero, worst_service);
    TV_CHECK_EQ_INT(detected, runs);
    TV_CHECK_LE(worst_zero, 0.195);
    TV_CHECK_LE(worst_service, 10.0);
}

/* Feeds the torque signature one closing sample (w = -2 rad/s, the angle falling 1 mrad a sample
 * from 0.4 rad) whose unexplained torque is y, with the model's spring torque s = 0.28 N m. */
static void feed_closing(diag_detect_t *dd, diag_t *d, diag_snapshot_t *snap, int k, tv_real_t y)
{
    snap->t_us = (uint64_t)k * 1000u;
    diag_jam_check(dd, d, 0, TV_R(0.0), TV_R(0.4) - TV_R(0.001) * (tv_real_t)k, TV_R(0.0), TV_R(1.0), snap);
    diag_torque_feed(dd, 1, TV_R(-2.0), y, TV_R(0.0), TV_R(0.28), TV_R(0.2), TV_R(0.0));
}

/* One step of a held plate at phi (the jam check's history, then the probe with the nominal
 * class-a model: M0 0.25, c phi, Mc 0.2). Returns the probe's answer, *T the torque asked for. */
static int probe_step_w(diag_detect_t *dd, diag_t *d, diag_snapshot_t *snap, int k, int allowed, tv_real_t phi, tv_real_t w,
                        tv_real_t pre_rel, tv_real_t fr_rel, tv_real_t *T)
{
    snap->t_us = (uint64_t)k * 1000u;
    diag_jam_check(dd, d, 0, TV_R(0.0), phi, TV_R(0.0), TV_R(1.0), snap);
    return diag_spring_probe(dd, d, allowed, phi, w, TV_R(0.25), TV_R(0.059) * phi, TV_R(0.2), pre_rel, fr_rel, T, snap);
}

/* probe_step_w() with the estimated speed 0 */
static int probe_step(diag_detect_t *dd, diag_t *d, diag_snapshot_t *snap, int k, int allowed, tv_real_t phi, tv_real_t pre_rel,
                      tv_real_t fr_rel, tv_real_t *T)
{
    return probe_step_w(dd, d, snap, k, allowed, phi, TV_R(0.0), pre_rel, fr_rel, T);
}

/* One opening sample at angle 0.1 + 0.001 k (away from limp-home, w = +2 rad/s), the model's
 * spring torque 0.28 N m, unexplained torque y (the jam window's history first). */
static void feed_opening(diag_detect_t *dd, diag_t *d, diag_snapshot_t *snap, int k, tv_real_t y)
{
    snap->t_us = (uint64_t)k * 1000u;
    diag_jam_check(dd, d, 0, TV_R(0.0), TV_R(0.1) + TV_R(0.001) * (tv_real_t)k, TV_R(0.0), TV_R(1.0), snap);
    diag_torque_feed(dd, 1, TV_R(2.0), y, TV_R(0.0), TV_R(0.28), TV_R(0.2), TV_R(0.0));
}

/* The probe's opening reading. A spring deficit leaves y = a s whichever way the plate moves:
 * 30 opening samples with y = 0.3 x 0.28 alone raise the suspicion (reading 0.3), and a probe
 * starts on the held plate. More friction (+30 %: 0.3 x 0.2 N m against the motion) reads
 * -0.06 / 0.28 = -0.21 over opening samples: no suspicion, no probe. Less friction (-30 %) reads
 * +0.21 there: a probe, which a healthy plate holds: no verdict, and both readings start over. */
static void test_spring_probe_opening(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    tv_real_t T = TV_R(0.0);
    int k;
    int n = 0;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 30; ++k) {
        feed_opening(&dd, &d, &snap, k, TV_R(0.3) * TV_R(0.28));
    }
    TV_CHECK(dd.po.w >= cfg.probe_min_weight);
    TV_CHECK_NEAR(dd.po.sy / dd.po.ss, 0.3, 1e-5);
    TV_CHECK(dd.pc.w == TV_R(0.0)); /* no closing sample */
    {
        /* below limp-home the directions swap: moving down (w < 0, the spring torque -0.28 N m)
         * is away from limp-home, fed to the opening reading; moving up is toward it */
        static diag_detect_t below;
        int j;
        TV_CHECK_EQ_INT(diag_detect_init(&below, &cfg), TV_OK);
        for (j = 0; j < 20; ++j) {
            snap.t_us = (uint64_t)j * 1000u;
            diag_jam_check(&below, &d, 0, TV_R(0.0), -TV_R(0.06) - TV_R(0.001) * (tv_real_t)j, TV_R(0.0), TV_R(1.0), &snap);
            diag_torque_feed(&below, 1, -TV_R(2.0), -TV_R(0.3) * TV_R(0.28), TV_R(0.0), -TV_R(0.28), TV_R(0.2), TV_R(0.0));
        }
        TV_CHECK(below.po.w > TV_R(0.0) && below.pc.w == TV_R(0.0));
        TV_CHECK_NEAR(below.po.sy / below.po.ss, 0.3, 1e-5);
        for (j = 20; j < 40; ++j) {
            snap.t_us = (uint64_t)j * 1000u;
            diag_jam_check(&below, &d, 0, TV_R(0.0), -TV_R(0.08) + TV_R(0.001) * (tv_real_t)(j - 20), TV_R(0.0), TV_R(1.0), &snap);
            diag_torque_feed(&below, 1, TV_R(2.0), TV_R(0.0), TV_R(0.0), -TV_R(0.28), TV_R(0.2), TV_R(0.0));
        }
        TV_CHECK(below.pc.w > TV_R(0.0));
    }
    for (k = 30; k < 30 + (int)DIAG_JAM_WINDOW + 1 && n == 0; ++k) {
        n = probe_step(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 1);
    /* more friction while opening: a negative reading, no probe however long the plate rests */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 30; ++k) {
        feed_opening(&dd, &d, &snap, k, -TV_R(0.3) * TV_R(0.2));
    }
    TV_CHECK(dd.po.w >= cfg.probe_min_weight);
    TV_CHECK_NEAR(dd.po.sy / dd.po.ss, -0.06 / 0.28, 1e-5);
    n = 0;
    for (k = 30; k < 200; ++k) {
        n += probe_step(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 0);
    /* less friction while opening: probed; the plate holds for DIAG_PROBE_MAX_STEPS steps, no
     * verdict, and the suspicion is over (no further probe) */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 30; ++k) {
        feed_opening(&dd, &d, &snap, k, TV_R(0.3) * TV_R(0.2));
    }
    n = 0;
    for (k = 30; k < 400; ++k) {
        n += probe_step(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, (int)DIAG_PROBE_MAX_STEPS);
    TV_CHECK(dd.po.w == TV_R(0.0) && dd.pc.w == TV_R(0.0));
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_confirmed(&d, DIAG_DTC_P1A02));
}

/* A fresh detector suspecting a weak spring: 50 closing samples whose unexplained torque is 0.2
 * of the spring's (above probe_trigger). */
static void suspect_spring(diag_detect_t *dd, diag_t *d, const diag_detect_config_t *cfg, diag_snapshot_t *snap)
{
    int k;
    diag_init(d);
    TV_CHECK_EQ_INT(diag_detect_init(dd, cfg), TV_OK);
    for (k = 0; k < 50; ++k) {
        feed_closing(dd, d, snap, k, TV_R(0.2));
    }
}

/* The probe's reference levels (DIAG_PROBE_REF_LAG): a held plate with nothing suspected is
 * offered the probe (diag_spring_probe() latches 1 + m and 1 + f every 32 calls); then the
 * closing samples of suspect_spring() raise the suspicion and the probe asks for
 * dir (pre_ref M0 + 0.65 fr_ref Mc) + c phi at phi 0.35 rad (M0 0.25, Mc 0.2, c 0.059, by hand).
 * 100 calls at 1 + m = 1 and then 40 at 0.5 (a broken spring pulls the estimator's preload down
 * within the move that raises the suspicion): latches at calls 32, 64, 96 (1.0) and 128 (0.5, the
 * newest), so the probe takes 1.0: 0.25 + 0.13 + 0.02065 = 0.40065 N m (with the level of the
 * last call, 0.5, it would be 0.27565, which held a plate without its spring in the fault matrix:
 * all_varied 1002, drive). 140 calls at 0.5 after the 100: the latches from call 128 on hold 0.5,
 * and the probe takes the slow change: 0.27565 N m. */
static void test_spring_probe_reference_lag(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    int late;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    TV_CHECK_EQ_INT((int)DIAG_PROBE_REF_LAG, 32);
    for (late = 40; late <= 140; late += 100) {
        tv_real_t T = TV_R(0.0);
        int k;
        int n = 0;
        diag_init(&d);
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
        for (k = 0; k < 100 + late; ++k) {
            /* nothing suspected: no probe, the levels latched */
            TV_CHECK_EQ_INT(probe_step(&dd, &d, &snap, k, 1, TV_R(0.35), k < 100 ? TV_R(1.0) : TV_R(0.5), TV_R(1.0), &T), 0);
        }
        for (k = 0; k < 50; ++k) {
            /* suspect_spring()'s closing samples, on this detector (no call of the probe) */
            feed_closing(&dd, &d, &snap, k, TV_R(0.2));
        }
        TV_CHECK(dd.pc.w >= cfg.probe_min_weight && dd.pc.sy >= cfg.probe_trigger * dd.pc.ss);
        for (k = 50; k < 50 + 4 * (int)DIAG_JAM_WINDOW && n == 0; ++k) {
            n = probe_step(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(0.5), TV_R(1.0), &T);
        }
        TV_CHECK_EQ_INT(n, 1);
        TV_CHECK_NEAR(T, late == 40 ? 0.40065 : 0.27565, 1e-6);
    }
}

/* One sample of a plate closing from 0.8 rad by step rad per step (the jam window's history
 * first), estimated speed w, the model's spring torque 0.3 N m, unexplained torque y, the bridge
 * applying u. */
static void feed_slow(diag_detect_t *dd, diag_t *d, diag_snapshot_t *snap, int k, tv_real_t w, tv_real_t step, tv_real_t y,
                      tv_real_t u)
{
    snap->t_us = (uint64_t)k * 1000u;
    diag_jam_check(dd, d, 0, TV_R(0.0), TV_R(0.8) - step * (tv_real_t)k, TV_R(0.0), TV_R(1.0), snap);
    diag_torque_feed(dd, 1, w, y, TV_R(0.0), TV_R(0.3), TV_R(0.2), u);
}

/* The spring probe's closing reading from SLOW samples (diag_torque_feed()): a plate creeping
 * toward limp-home at 0.3 rad/s (0.3 mrad a step: 2.1 mrad over the 8-sample jam window) while the
 * drive pulls that way too (u = -1 V above limp-home), with an unexplained torque 0.3 x the
 * spring's (a spring deficit a = 0.3). The signature takes none of these samples (slower than
 * 1 rad/s, and 2.1 < 4 mrad); the closing reading takes every one from the 8th step (the window
 * full), reads a = 0.3, reaches probe_min_weight and a probe starts once the plate rests. Not fed:
 * the drive pushing away from limp-home (+1 V); the plate moving away from it; slower than
 * DIAG_PROBE_SLOW_W_RAD_S (0.1 rad/s); a window that moved less than DIAG_PROBE_SLOW_MOVE_RAD (0.1
 * mrad a step: 0.7 mrad); while a probe runs. A sample fast enough for the signature (2 rad/s,
 * 1 mrad a step) is fed once, as before: the closing reading's weight equals the signature's. */
static void test_spring_probe_slow_feed(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    static const struct {
        double w, step, u;
    } not_fed[] = {{-0.3, 0.0003, 1.0}, {0.3, -0.0003, -1.0}, {-0.1, 0.0003, -1.0}, {-0.3, 0.0001, -1.0}};
    tv_real_t T = TV_R(0.0);
    size_t c;
    int k;
    int n = 0;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    TV_CHECK_NEAR(DIAG_PROBE_SLOW_W_RAD_S, 0.15, 1e-6);
    TV_CHECK_NEAR(DIAG_PROBE_SLOW_MOVE_RAD, 0.0008, 1e-9);
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 7; ++k) {
        feed_slow(&dd, &d, &snap, k, TV_R(-0.3), TV_R(0.0003), TV_R(0.3) * TV_R(0.3), TV_R(-1.0));
    }
    TV_CHECK(dd.pc.w == TV_R(0.0)); /* the window not yet full */
    feed_slow(&dd, &d, &snap, 7, TV_R(-0.3), TV_R(0.0003), TV_R(0.3) * TV_R(0.3), TV_R(-1.0));
    TV_CHECK_NEAR(dd.pc.w, 1.0, 1e-6);
    for (k = 8; k < 40; ++k) {
        feed_slow(&dd, &d, &snap, k, TV_R(-0.3), TV_R(0.0003), TV_R(0.3) * TV_R(0.3), TV_R(-1.0));
    }
    TV_CHECK(dd.tq_w == TV_R(0.0) && dd.po.w == TV_R(0.0)); /* neither the signature nor the opening reading */
    TV_CHECK(dd.pc.w >= cfg.probe_min_weight);
    TV_CHECK_NEAR(dd.pc.sy / dd.pc.ss, 0.3, 1e-4);
    /* the plate rests at 0.768 rad: a probe starts once the jam window is still */
    for (k = 40; k < 40 + (int)DIAG_JAM_WINDOW + 1 && n == 0; ++k) {
        n = probe_step(&dd, &d, &snap, k, 1, TV_R(0.8) - TV_R(0.0003) * TV_R(40.0), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 1);
    TV_CHECK(dd.probe_t > 0u);
    {
        /* while the probe runs: not fed, though the window moves 2.1 mrad toward limp-home (the
         * same sample with no probe running is: the control) */
        const tv_real_t w0 = dd.pc.w;
        int j;
        for (j = 1; j <= (int)DIAG_JAM_WINDOW; ++j) {
            snap.t_us += 1000u;
            diag_jam_check(&dd, &d, 0, TV_R(0.0), TV_R(0.788) - TV_R(0.0003) * (tv_real_t)j, TV_R(0.0), TV_R(1.0), &snap);
        }
        diag_torque_feed(&dd, 1, TV_R(-0.3), TV_R(0.09), TV_R(0.0), TV_R(0.3), TV_R(0.2), TV_R(-1.0));
        TV_CHECK(dd.pc.w == w0);
        dd.probe_t = 0u;
        diag_torque_feed(&dd, 1, TV_R(-0.3), TV_R(0.09), TV_R(0.0), TV_R(0.3), TV_R(0.2), TV_R(-1.0));
        TV_CHECK(dd.pc.w > w0);
    }
    for (c = 0; c < sizeof not_fed / sizeof not_fed[0]; ++c) {
        diag_init(&d);
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
        for (k = 0; k < 40; ++k) {
            feed_slow(&dd, &d, &snap, k, (tv_real_t)not_fed[c].w, (tv_real_t)not_fed[c].step, TV_R(0.09), (tv_real_t)not_fed[c].u);
        }
        TV_CHECK(dd.pc.w == TV_R(0.0) && dd.po.w == TV_R(0.0) && dd.tq_w == TV_R(0.0));
    }
    /* fast enough for the signature: fed once */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 40; ++k) {
        feed_slow(&dd, &d, &snap, k, TV_R(-2.0), TV_R(0.001), TV_R(0.09), TV_R(-1.0));
    }
    TV_CHECK(dd.tq_w > TV_R(0.0));
    TV_CHECK_NEAR(dd.pc.w, dd.tq_w, 1e-6);
}

/* A plate CREEPING toward limp-home (0.25 mrad per step, estimated 0.25 rad/s: the window moved
 * 1.75 mrad, below DIAG_PROBE_CREEP_RAD 8 mrad) is probed. Without its spring it goes on 0.75 mrad
 * toward limp-home, turns, and moves 0.4 mrad per step away: its motion counts from the turn, so
 * the 4th step away (1.6 mrad from the turn, 0.85 from the probe's start) fails P1A02. A 2nd
 * creeping plate that stops and holds gives no verdict and keeps the suspicion (the next probe
 * starts), since a creeping probe that holds proves nothing; DIAG_PROBE_MAX_N such end it. */
static void test_spring_probe_creeping(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    tv_real_t T = TV_R(0.0);
    tv_real_t phi = TV_R(0.40);
    int k;
    int n = 0;
    int holds = 0;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    suspect_spring(&dd, &d, &cfg, &snap);
    for (k = 50; k < 70 && n == 0; ++k) {
        phi -= TV_R(0.00025);
        n = probe_step_w(&dd, &d, &snap, k, 1, phi, TV_R(-0.25), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 1);
    TV_CHECK_EQ_INT(dd.probe_creep, 1);
    for (n = 0; n < 3; ++n, ++k) {
        phi -= TV_R(0.00025);
        TV_CHECK_EQ_INT(probe_step_w(&dd, &d, &snap, k, 1, phi, TV_R(-0.25), TV_R(1.0), TV_R(1.0), &T), 1);
    }
    for (n = 0; n < 3; ++n, ++k) {
        phi += TV_R(0.0004);
        TV_CHECK_EQ_INT(probe_step_w(&dd, &d, &snap, k, 1, phi, TV_R(0.4), TV_R(1.0), TV_R(1.0), &T), 1);
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02));
    phi += TV_R(0.0004);
    TV_CHECK_EQ_INT(probe_step_w(&dd, &d, &snap, k, 1, phi, TV_R(0.4), TV_R(1.0), TV_R(1.0), &T), 0);
    TV_CHECK(diag_pending(&d, DIAG_DTC_P1A02));
    TV_CHECK_EQ_INT(dd.probe_n, 1);
    /* creeping plates that stop and hold: no verdict, the suspicion stays for DIAG_PROBE_MAX_N of them */
    suspect_spring(&dd, &d, &cfg, &snap);
    phi = TV_R(0.40);
    for (k = 50; k < 2000 && dd.pc.w > TV_R(0.0);) {
        int p;
        for (p = 0; p < (int)DIAG_JAM_WINDOW; ++p, ++k) { /* creeps (no probe allowed meanwhile) */
            phi -= TV_R(0.00025);
            TV_CHECK_EQ_INT(probe_step_w(&dd, &d, &snap, k, 0, phi, TV_R(-0.25), TV_R(1.0), TV_R(1.0), &T), 0);
        }
        phi -= TV_R(0.00025);
        TV_CHECK_EQ_INT(probe_step_w(&dd, &d, &snap, k++, 1, phi, TV_R(-0.25), TV_R(1.0), TV_R(1.0), &T), 1);
        TV_CHECK_EQ_INT(dd.probe_creep, 1);
        for (p = 0; p < (int)DIAG_PROBE_MAX_STEPS + 1 && probe_step_w(&dd, &d, &snap, k, 1, phi, TV_R(0.0), TV_R(1.0),
                                                                        TV_R(1.0), &T); ++p, ++k) {
        }
        ++k;
        ++holds; /* then holds */
        TV_CHECK_EQ_INT(dd.probe_creep_n, holds < (int)DIAG_PROBE_MAX_N ? holds : 0);
    }
    TV_CHECK_EQ_INT(holds, (int)DIAG_PROBE_MAX_N);
    TV_CHECK(dd.pc.w == TV_R(0.0)); /* then the suspicion is over */
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_confirmed(&d, DIAG_DTC_P1A02));
}

/* The spring probe (diag_spring_probe()) on scripted inputs. Nothing suspected (healthy closing
 * samples, y = 0): no probe. Closing samples whose unexplained torque is 0.3 of the spring's
 * (the closing reading a = 0.3, above probe_trigger; the estimator's levels meanwhile pulled to
 * 0.5 and 1.4) and a plate at rest: a probe starts at the first step at rest, asking for the
 * levels from BEFORE the suspicion: 1.0 x 0.25 + 0.65 x 1.1 x 0.2 + 0.059 x 0.35 = 0.41365 N m;
 * a plate that moves 1.8 mrad (at least probe_move_rad) away from limp-home fails P1A02 once per
 * probe, and the 3rd such probe confirms it (freeze value 1 - a = 0.7); a plate that stays for
 * DIAG_PROBE_MAX_STEPS
 * steps gives no verdict and ends the suspicion (no further probe); not allowed: no probe. */
static void test_spring_probe(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    tv_real_t T = TV_R(0.0);
    tv_real_t phi = TV_R(0.35);
    int k;
    int n;
    int fails = 0;
    diag_detect_config_default(&cfg);
    memset(&snap, 0, sizeof snap);
    TV_CHECK_NEAR(cfg.probe_trigger, 0.1, 1e-6);
    TV_CHECK_NEAR(cfg.probe_friction_frac, 0.65, 1e-6);
    /* healthy closing: nothing suspected, no probe however long the plate rests */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 50; ++k) {
        feed_closing(&dd, &d, &snap, k, TV_R(0.0));
    }
    for (k = 50; k < 200; ++k) {
        TV_CHECK_EQ_INT(probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.1), TV_R(1.1), &T), 0);
    }
    /* from a fresh start: the levels before the suspicion, 1 + m = 1.0 and 1 + f = 1.1 (latched
     * while nothing is suspected; after 2 DIAG_PROBE_REF_LAG calls they are the probe's reference:
     * test_spring_probe_reference_lag), then closing samples with y = 0.3 s: suspected */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 200 - 2 * (int)DIAG_PROBE_REF_LAG; k <= 200; ++k) {
        TV_CHECK_EQ_INT(probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.1), &T), 0);
    }
    for (k = 201; k < 251; ++k) {
        feed_closing(&dd, &d, &snap, k, TV_R(0.3) * TV_R(0.28));
    }
    TV_CHECK(dd.pc.w >= cfg.probe_min_weight);
    /* the plate comes to rest: the jam window must see it still first (DIAG_JAM_WINDOW samples) */
    n = 0;
    for (k = 251; k < 251 + (int)DIAG_JAM_WINDOW + 1 && n == 0; ++k) {
        n = probe_step(&dd, &d, &snap, k, 1, phi, TV_R(0.5), TV_R(1.4), &T);
    }
    TV_CHECK_EQ_INT(n, 1);
    TV_CHECK_EQ_INT(k, 251 + (int)DIAG_JAM_WINDOW); /* the first step whose 8-sample window is still */
    TV_CHECK_NEAR(T, 0.25 + 0.65 * 1.1 * 0.2 + 0.059 * 0.35, 1e-5);
    /* three probes that each move the plate 1.8 mrad (in 3 steps) confirm P1A02 at the 3rd */
    TV_CHECK_EQ_INT(diag_dtc_info(DIAG_DTC_P1A02)->confirm_count, 3);
    while (fails < 3 && k < 2000) {
        int p;
        for (p = 0; p < 3; ++p, ++k) {
            phi += TV_R(0.0006);
            (void)probe_step(&dd, &d, &snap, k, 1, phi, TV_R(0.5), TV_R(1.4), &T);
        }
        ++fails;
        TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P1A02), fails >= 3);
        TV_CHECK(diag_pending(&d, DIAG_DTC_P1A02) || diag_confirmed(&d, DIAG_DTC_P1A02));
        /* at rest again: the next probe starts once the window is still */
        for (p = 0; p < (int)DIAG_JAM_WINDOW + 1 && fails < 3; ++p, ++k) {
            if (probe_step(&dd, &d, &snap, k, 1, phi, TV_R(0.5), TV_R(1.4), &T)) {
                ++k;
                break;
            }
        }
    }
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P1A02));
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A02].freeze.value, 0.7, 1e-4);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P2119) && !diag_confirmed(&d, DIAG_DTC_P2119));
    /* one moving probe (P1A02 pending), then healthy closing motion: once the reading falls below
     * probe_trigger the sequence is over and the adapted level passes P1A02 again (one check of
     * DIAG_PARAM_DECIM calls leaks the counter back to 0) */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    for (k = 0; k < 50; ++k) {
        feed_closing(&dd, &d, &snap, k, TV_R(0.3) * TV_R(0.28));
    }
    phi = TV_R(0.35);
    n = 0;
    for (k = 50; k < 80 && n == 0; ++k) {
        n = probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 1);
    for (n = 0; n < 3; ++n, ++k) {
        phi += TV_R(0.0006);
        (void)probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK(diag_pending(&d, DIAG_DTC_P1A02) && dd.probe_n == 1u);
    for (n = 0; n < (int)DIAG_PARAM_DECIM; ++n) {
        diag_param_check(&dd, &d, 1, TV_R(1.0), TV_R(1.0), TV_R(0.02), TV_R(1.0), TV_R(0.01), &snap);
    }
    TV_CHECK(diag_pending(&d, DIAG_DTC_P1A02)); /* the sequence decides: no pass */
    for (n = 0; n < 400; ++n, ++k) {
        feed_closing(&dd, &d, &snap, k, TV_R(0.0));
    }
    TV_CHECK(dd.pc.sy < cfg.probe_trigger * dd.pc.ss);
    TV_CHECK_EQ_INT(probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.0), &T), 0);
    TV_CHECK_EQ_INT(dd.probe_n, 0);
    for (n = 0; n < (int)DIAG_PARAM_DECIM; ++n) {
        diag_param_check(&dd, &d, 1, TV_R(1.0), TV_R(1.0), TV_R(0.02), TV_R(1.0), TV_R(0.01), &snap);
    }
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_confirmed(&d, DIAG_DTC_P1A02));
    /* the same suspicion (more friction also reads so in closing) on a plate that holds: no
     * verdict after DIAG_PROBE_MAX_STEPS steps, and the suspicion ends */
    suspect_spring(&dd, &d, &cfg, &snap);
    n = 0;
    for (k = 50; k < 400; ++k) {
        n += probe_step(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(1.0), TV_R(1.0), &T);
    }
    /* the first probe begins while the jam window still holds the closing samples' motion
     * toward limp-home (creeping: its hold is no evidence), the second on the still plate */
    TV_CHECK_EQ_INT(n, 2 * (int)DIAG_PROBE_MAX_STEPS);
    TV_CHECK(dd.pc.w == TV_R(0.0));
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_confirmed(&d, DIAG_DTC_P1A02));
    /* not allowed (limited authority, near a stop or limp-home, open loop): no probe */
    suspect_spring(&dd, &d, &cfg, &snap);
    n = 0;
    for (k = 50; k < 400; ++k) {
        n += probe_step(&dd, &d, &snap, k, 0, TV_R(0.35), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 0);
    /* a pending jam code inhibits it as it does the signature */
    TV_CHECK_EQ_INT(diag_report(&d, DIAG_DTC_P2112, DIAG_FAIL, &snap, TV_R(0.0)), TV_OK);
    for (k = 400; k < 600; ++k) {
        n += probe_step(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 0);
    /* below limp-home the probe pushes the other way: spring torque -M0 + c phi, minus the friction share */
    suspect_spring(&dd, &d, &cfg, &snap);
    n = 0;
    for (k = 50; k < 70 && n == 0; ++k) {
        n = probe_step(&dd, &d, &snap, k, 1, TV_R(-0.07), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 1);
    TV_CHECK_NEAR(T, -0.25 - 0.65 * 0.2 - 0.059 * 0.07, 1e-5);
    /* the rest gate's speed bound (DIAG_PROBE_REST_W_RAD_S 0.5): a still angle whose estimated
     * speed is 0.3 rad/s toward limp-home (a plate held without the spring the model pulls with)
     * is at rest, the probe starts at the first still window; at 0.6 rad/s it is not */
    TV_CHECK_NEAR(DIAG_PROBE_REST_W_RAD_S, 0.5, 1e-6);
    suspect_spring(&dd, &d, &cfg, &snap);
    n = 0;
    for (k = 50; k < 70 && n == 0; ++k) {
        n = probe_step_w(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(-0.3), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 1);
    /* at once, step 50 (the loop's k one past it): the jam window moved 7 mrad toward limp-home
     * (the closing samples, 1 mrad a step), less than DIAG_PROBE_CREEP_RAD */
    TV_CHECK_EQ_INT(k, 51);
    suspect_spring(&dd, &d, &cfg, &snap);
    n = 0;
    for (k = 50; k < 400; ++k) {
        n += probe_step_w(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(0.6), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 0);
    /* toward limp-home the bound is DIAG_PROBE_CREEP_W_RAD_S (1.0): 0.6 rad/s is probed, 1.2 not */
    TV_CHECK_NEAR(DIAG_PROBE_CREEP_W_RAD_S, 1.0, 1e-6);
    suspect_spring(&dd, &d, &cfg, &snap);
    n = 0;
    for (k = 50; k < 70 && n == 0; ++k) {
        n = probe_step_w(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(-0.6), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 1);
    suspect_spring(&dd, &d, &cfg, &snap);
    n = 0;
    for (k = 50; k < 400; ++k) {
        n += probe_step_w(&dd, &d, &snap, k, 1, TV_R(0.35), TV_R(-1.2), TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 0);
    /* a probe that moves the plate 0.8 mrad (between DIAG_PROBE_UNSURE_FRAC x probe_move_rad =
     * 0.45 mrad and probe_move_rad) gives no verdict but keeps the suspicion: the next probe
     * starts once the window is still again; one that then moves 0.4 mrad (below 0.45) holds:
     * the suspicion ends, no code */
    TV_CHECK_NEAR(DIAG_PROBE_UNSURE_FRAC, 0.3, 1e-6);
    suspect_spring(&dd, &d, &cfg, &snap);
    phi = TV_R(0.35);
    n = 0;
    for (k = 50; k < 70 && n == 0; ++k) {
        n = probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 1);
    for (n = 0; n < 8; ++n, ++k) { /* 0.1 mrad a step, 8 steps, then still: the probe runs out */
        phi += TV_R(0.0001);
        TV_CHECK_EQ_INT(probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.0), &T), 1);
    }
    while (probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.0), &T) && k < 200) {
        ++k;
    }
    /* started at step 50 (the window moved 7 mrad toward limp-home, less than
     * DIAG_PROBE_CREEP_RAD), ended DIAG_PROBE_MAX_STEPS steps later */
    TV_CHECK_EQ_INT(k, 50 + (int)DIAG_PROBE_MAX_STEPS);
    TV_CHECK_EQ_INT(dd.probe_n, 1);
    TV_CHECK(dd.pc.w >= cfg.probe_min_weight); /* still suspected */
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_confirmed(&d, DIAG_DTC_P1A02));
    n = 0;
    for (++k; k < 300 && n == 0; ++k) {
        n = probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.0), &T);
    }
    TV_CHECK_EQ_INT(n, 1); /* the second probe */
    for (n = 0; n < 4; ++n, ++k) {
        phi += TV_R(0.0001);
        (void)probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.0), &T);
    }
    while (probe_step(&dd, &d, &snap, k, 1, phi, TV_R(1.0), TV_R(1.0), &T) && k < 400) {
        ++k;
    }
    TV_CHECK_EQ_INT(dd.probe_n, 0);
    TV_CHECK(dd.pc.w == TV_R(0.0)); /* held: the suspicion is over */
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A02) && !diag_confirmed(&d, DIAG_DTC_P1A02));
}

/* The spring probe in closed loop on the nominal unit, seeds 1-3, 3 s runs, the fault at 2.0 s
 * where both closed-loop benchmark scenarios begin a closing move (drive 0.45 -> 0.30 rad,
 * closed_steps 1.2 -> 0.2 rad), after which the plate HOLDS (the signature has no opening motion to
 * judge until 3.0 / 2.5 s): a broken spring confirms P1A02 within 300 ms of the onset, never
 * P2119; friction x2 and x3 (which read the same in closing) confirm no P1A02; the healthy unit
 * confirms no code. */
static void test_spring_break_while_holding(void)
{
    static const sim_scenario_t scn[2] = {SIM_SCN_DRIVE, SIM_SCN_CLOSED_STEPS};
    static const char *const other[2] = {"friction_high:2@2.0", "friction_high:3@2.0"};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    double worst = 0.0;
    uint64_t seed;
    int s;
    int k;
    plant_config_default(&pc);
    app_config_default(&ac);
    for (s = 0; s < 2; ++s) {
        for (seed = 1u; seed <= 3u; ++seed) {
            sim_fault_run(&pc, &ac, scn[s], seed, "spring_weak:0@2.0", 3.0, &r);
            worst = fmax(worst, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A02]) ? r.dtc_confirm_t_s[DIAG_DTC_P1A02] - 2.0 : 1e9);
            TV_CHECK(!sim_dtc_ever(&r, DIAG_DTC_P2119));
            for (k = 0; k < 2; ++k) {
                sim_fault_run(&pc, &ac, scn[s], seed, other[k], 3.0, &r);
                TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A02]));
            }
            sim_fault_run(&pc, &ac, scn[s], seed, NULL, 3.0, &r);
            for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
                TV_CHECK(!isfinite(r.dtc_confirm_t_s[k]));
            }
        }
    }
    printf("  broken spring while holding (drive, closed_steps): P1A02 at most %.0f ms after the onset\n", worst * 1e3);
    TV_CHECK_LE(worst, 0.3);
}

/* The fault matrix's late broken springs of the release before this test (all_varied units on
 * their class's model, spring_weak:0 at 2.0 s, seed 1, the winding temperature told): unit 1002
 * in closed-loop driving (the plate came to rest at 0.30 rad right after the break, and the probe
 * that followed took 1 + m as the break had already pulled it, 0.56 instead of 0.79, too little to
 * move the plate without its spring: 1,049 ms, DIAG_PROBE_REF_LAG), units 1001 and 1004 in
 * limp_home (the opening move of the return at 2.4 s fed the opening reading 4.8 - 5.7 samples,
 * short of the old probe_min_weight 8: 346 and 1,249 ms after the bridge drove again), and units
 * 1001 and 1004 in the 12 V sine (389 and 379 ms: the signature's preload fell below 0.5 over four
 * half-periods; with its friction read far below the model's too, DIAG_FRICTION_BOTH_LOW, it fails
 * from 0.6). Each within 300 ms of when the actuator operates (2.0 s; limp_home: 2.4 s, the
 * bridge off until then), and the healthy runs confirm nothing. */
static void test_spring_break_late_units(void)
{
    static const uint64_t units[5] = {1002u, 1001u, 1004u, 1001u, 1004u};
    static const sim_scenario_t scn[5] = {SIM_SCN_DRIVE, SIM_SCN_LIMP_HOME, SIM_SCN_LIMP_HOME, SIM_SCN_PAPER_SINE,
                                          SIM_SCN_PAPER_SINE};
    static const double operates_s[5] = {2.0, 2.4, 2.4, 2.0, 2.0};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    double worst = 0.0;
    int u;
    int k;
    for (u = 0; u < 5; ++u) {
        sim_result_t learn;
        TV_CHECK(unit_config(units[u], PLANT_SPREAD_ALL, &pc, &ac, &learn));
        told_run(&pc, &ac, "spring_weak:0@2.0", scn[u], 4.0, &r);
        TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A02]));
        worst = fmax(worst, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A02]) ? r.dtc_confirm_t_s[DIAG_DTC_P1A02] - operates_s[u] : 1e9);
        told_run(&pc, &ac, NULL, scn[u], 4.0, &r);
        for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[k]));
        }
    }
    printf("  broken spring on all_varied 1002 (drive), 1001 and 1004 (limp_home, 12 V sine): P1A02 at most %.0f ms after the "
           "actuator operates\n",
           worst * 1e3);
    TV_CHECK_LE(worst, 0.3);
}

/* A broken or weak return spring during continuous motion (the 12 V sine), nominal unit, seeds
 * 1-3, from 1.0 s: P1A02 confirmed within 300 ms of the onset (issue 12's target), never
 * P2119. */
static void test_spring_break_within_300_ms(void)
{
    static plant_config_t pc;
    static app_config_t ac;
    static const char *const spec[2] = {"spring_weak:0@1.0", "spring_weak:0.3@1.0"};
    sim_result_t r;
    double worst = 0.0;
    uint64_t seed;
    int k;
    plant_config_default(&pc);
    app_config_default(&ac);
    for (k = 0; k < 2; ++k) {
        for (seed = 1u; seed <= 3u; ++seed) {
            run_with(&pc, &ac, SIM_SCN_PAPER_SINE, seed, spec[k], &r);
            worst = fmax(worst, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A02]) ? r.dtc_confirm_t_s[DIAG_DTC_P1A02] - 1.0 : 1e9);
            TV_CHECK(!sim_dtc_ever(&r, DIAG_DTC_P2119));
        }
    }
    printf("  spring at 0 and 30 %% in the 12 V sine: P1A02 at most %.0f ms after the onset\n", worst * 1e3);
    TV_CHECK_LE(worst, 0.3);
}

/* With the unit's own model in the filter (the nominal plant and the default filter: the
 * identified case) and diag_detect_config_identified(): friction +25 % (Coulomb and static) from
 * 1.0 s confirms P2119 within 5 s in the scenarios that slide the plate (12 V sine, closed- and
 * open-loop steps), seed 1, 6 s runs, never P1A02; the healthy unit confirms no code in any
 * benchmark scenario, seed 1 (kept short for the sanitizer build's time limit; the population
 * figures are in the README). */
static void test_friction_plus_25_percent_identified(void)
{
    static const sim_scenario_t scn[3] = {SIM_SCN_PAPER_SINE, SIM_SCN_CLOSED_STEPS, SIM_SCN_OPEN_STEPS};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    double worst = 0.0;
    uint64_t seed;
    int s;
    int runs = 0;
    int confirmed = 0;
    plant_config_default(&pc);
    app_config_default(&ac);
    diag_detect_config_identified(&ac.diag);
    TV_CHECK(ac.diag.friction_fast_high < TV_R(1.25));
    for (seed = 1u; seed <= 1u; ++seed) {
        for (s = 0; s < 3; ++s) {
            sim_fault_run(&pc, &ac, scn[s], seed, "friction_high:1.25@1.0", 6.0, &r);
            worst = fmax(worst, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2119]) ? r.dtc_confirm_t_s[DIAG_DTC_P2119] - 1.0 : 1e9);
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A02]));
        }
    }
    for (seed = 1u; seed <= 1u; ++seed) {
        for (s = 0; s < (int)SIM_SCN_COUNT; ++s) {
            int d;
            if (s == (int)SIM_SCN_STOP_LEARN || s == (int)SIM_SCN_STUCK_RELEASE) {
                continue;
            }
            run_with(&pc, &ac, (sim_scenario_t)s, seed, NULL, &r);
            ++runs;
            for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
                confirmed += isfinite(r.dtc_confirm_t_s[d]) ? 1 : 0;
            }
        }
    }
    printf("  identified unit: friction +25 %% P2119 at most %.2f s after the onset; healthy: %d codes in %d runs\n", worst,
           confirmed, runs);
    TV_CHECK_LE(worst, 5.0);
    TV_CHECK_EQ_INT(confirmed, 0);
}

/* The motor-constant signature on scripted inputs (diag_detect.h, identified units only): the
 * resistance check reads (R + dR) / R = 0.9 (a current gain of 1.11, or shorted turns), one
 * in-service window is then judged (its back-EMF slope kw), and the adapted friction and preload
 * both read 1.1: with kw = 0 (the back-EMF intact: a gain error) P1A04 fails every check and
 * confirms at the 6th (its confirm count; 60 calls of diag_param_check()), P2119 never pending
 * although the signature's friction would fail it; with kw = 0.02 A s/rad (the back-EMF constant
 * down: shorted turns) P1A01 fails instead. Nothing without the identified bounds, with the
 * resistance in range, with only one of friction and preload up, or before a window was judged;
 * friction up alone with the resistance low fails P2119 after gain_hold_checks checks. */
/* The detectors set up (identified bounds or the class's) with one resistance check at RATIO of
 * the model's 4.3 ohm, then WINDOWS in-service windows whose innovation is KW times the velocity. */
static void sig_setup(diag_detect_t *dd, int identified, int temp_known, tv_real_t ratio, tv_real_t kw, int windows, diag_t *d,
                      diag_snapshot_t *snap)
{
    diag_detect_config_t cfg;
    int k;
    diag_detect_config_default(&cfg);
    if (identified) {
        diag_detect_config_identified(&cfg);
    }
    TV_CHECK_EQ_INT(diag_detect_init(dd, &cfg), TV_OK);
    diag_init(d);
    memset(snap, 0, sizeof *snap);
    diag_resistance_check(dd, d, 1, TV_R(1.0), ratio * TV_R(4.3), TV_R(0.01), TV_R(4.3), temp_known, snap);
    for (k = 0; k < windows * (int)DIAG_ISENS_WIN + (int)DIAG_ISENS_SETTLE; ++k) {
        const tv_real_t i = isens_i(k);
        const tv_real_t w = isens_w(k);
        const tv_real_t y = kw * w;
        diag_current_sensor_check(dd, d, 1, 1, 1, i + y, y, w, snap);
    }
}

static void sig_case(int identified, int temp_known, tv_real_t ratio, tv_real_t kw, tv_real_t f, tv_real_t m, int windows, diag_t *d)
{
    static diag_detect_t dd;
    diag_snapshot_t snap;
    int k;
    sig_setup(&dd, identified, temp_known, ratio, kw, windows, d, &snap);
    for (k = 1; k <= 6 * (int)DIAG_PARAM_DECIM; ++k) {
        snap.t_us = (uint64_t)k * 1000u;
        diag_param_check(&dd, d, 1, TV_R(1.0), f, TV_R(0.02), m, TV_R(0.01), &snap);
        TV_CHECK(!diag_pending(d, DIAG_DTC_P2119));
    }
}

static void test_motor_constant_signature(void)
{
    static diag_t d;
    sig_case(1, 0, TV_R(0.9), TV_R(0.0), TV_R(1.1), TV_R(1.1), 1, &d);
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P1A04));
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A04].freeze.value, 0.9, 1e-6);
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P1A04].freeze.t_us, (uint64_t)(6u * DIAG_PARAM_DECIM) * 1000u);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A01));
    sig_case(1, 0, TV_R(0.9), TV_R(0.02), TV_R(1.1), TV_R(1.1), 1, &d);
    TV_CHECK(diag_pending(&d, DIAG_DTC_P1A01));
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_confirmed(&d, DIAG_DTC_P1A04));
    /* no verdict: the class's bounds; the resistance in range; one level up only; no window */
    sig_case(0, 0, TV_R(0.9), TV_R(0.0), TV_R(1.1), TV_R(1.1), 1, &d);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_pending(&d, DIAG_DTC_P1A01));
    sig_case(1, 0, TV_R(0.99), TV_R(0.0), TV_R(1.1), TV_R(1.1), 1, &d);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_pending(&d, DIAG_DTC_P1A01));
    sig_case(1, 0, TV_R(0.9), TV_R(0.0), TV_R(1.1), TV_R(1.0), 1, &d);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_pending(&d, DIAG_DTC_P1A01));
    sig_case(1, 0, TV_R(0.9), TV_R(0.0), TV_R(1.1), TV_R(1.1), 0, &d);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_pending(&d, DIAG_DTC_P1A01));
    /* the winding's temperature known: the resistance low is no cold winding, so friction up
     * alone suffices (a gain's excess torque taken up by the friction state alone) */
    sig_case(1, 1, TV_R(0.9), TV_R(0.0), TV_R(1.1), TV_R(1.0), 1, &d);
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P1A04) && !diag_pending(&d, DIAG_DTC_P1A01));
    sig_case(1, 1, TV_R(0.9), TV_R(0.02), TV_R(1.1), TV_R(1.0), 1, &d);
    TV_CHECK(diag_pending(&d, DIAG_DTC_P1A01) && !diag_pending(&d, DIAG_DTC_P1A04));
    sig_case(1, 1, TV_R(0.9), TV_R(0.0), TV_R(1.1), TV_R(1.0), 0, &d); /* still a window needed */
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_pending(&d, DIAG_DTC_P1A01));
    {
        /* a window begun before the resistance went low gives no back-EMF slope: 400 healthy
         * samples (kw = 0), then shorted turns (R reads 0.9, kw = 0.02 A s/rad). Over all 500, the
         * first window's slope reads about 0.004, below gain_kw_max (0.006): P1A04 would be the
         * wrong code (measured on class b unit 1001); so the slope comes from the next window,
         * the fault's alone, and P1A01 is pending, P1A04 never. The window itself goes on (its
         * intercept judges an offset as before) */
        static diag_detect_t dd;
        diag_detect_config_t cfg;
        diag_snapshot_t snap;
        int k;
        diag_detect_config_default(&cfg);
        diag_detect_config_identified(&cfg);
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
        diag_init(&d);
        memset(&snap, 0, sizeof snap);
        for (k = 0; k < 400 + (int)DIAG_ISENS_SETTLE; ++k) {
            diag_current_sensor_check(&dd, &d, 1, 1, 1, isens_i(k), TV_R(0.0), isens_w(k), &snap);
        }
        diag_resistance_check(&dd, &d, 1, TV_R(1.0), TV_R(0.9) * TV_R(4.3), TV_R(0.01), TV_R(4.3), 0, &snap);
        TV_CHECK_EQ_INT(dd.isens_n, 401); /* the settling call not counted */
        for (k = 401; k < (int)DIAG_ISENS_WIN; ++k) {
            const tv_real_t w = isens_w(k);
            const tv_real_t y = TV_R(0.02) * w;
            diag_current_sensor_check(&dd, &d, 1, 1, 1, isens_i(k) + y, y, w, &snap);
        }
        TV_CHECK(dd.isens_n == 0u && !dd.kw_ok); /* the mixed window: complete, no slope taken */
        for (k = 0; k < (int)DIAG_ISENS_WIN; ++k) {
            const tv_real_t w = isens_w(k);
            const tv_real_t y = TV_R(0.02) * w;
            diag_current_sensor_check(&dd, &d, 1, 1, 1, isens_i(k) + y, y, w, &snap);
        }
        TV_CHECK_NEAR(dd.isens_kw, 0.02, 1e-4);
        for (k = 1; k <= 6 * (int)DIAG_PARAM_DECIM; ++k) {
            diag_param_check(&dd, &d, 1, TV_R(1.0), TV_R(1.1), TV_R(0.02), TV_R(1.1), TV_R(0.01), &snap);
        }
        TV_CHECK(diag_pending(&d, DIAG_DTC_P1A01) && !diag_pending(&d, DIAG_DTC_P1A04));
    }
    {
        /* friction up alone (1 + f = 1.3 above the identified bound 1.15, the preload at 1) with
         * the apparent resistance low (a cold winding): P2119 is held for gain_hold_checks
         * checks, then fails as before (the slow level's run of 95 checks is long past); with
         * the winding's temperature known a resistance below 0.96 is no cold winding (the current
         * sensor or shorted turns), and P2119 stays held over the 400 checks; 0.965 may be a
         * reading 9 K too high: held for gain_hold_checks as without the temperature */
        static diag_detect_t dd;
        diag_detect_config_t cfg;
        diag_snapshot_t snap;
        int c;
        for (c = 0; c < 3; ++c) {
            const int known = c > 0;
            const tv_real_t ratio = c == 2 ? TV_R(0.965) : TV_R(0.9);
            int k;
            int first = -1;
            diag_detect_config_default(&cfg);
            diag_detect_config_identified(&cfg);
            TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
            diag_init(&d);
            memset(&snap, 0, sizeof snap);
            diag_resistance_check(&dd, &d, 1, TV_R(1.0), ratio * TV_R(4.3), TV_R(0.01), TV_R(4.3), known, &snap);
            for (k = 1; k <= 400 * (int)DIAG_PARAM_DECIM && first < 0; ++k) {
                diag_param_check(&dd, &d, 1, TV_R(1.0), TV_R(1.3), TV_R(0.02), TV_R(1.0), TV_R(0.01), &snap);
                if (diag_pending(&d, DIAG_DTC_P2119)) {
                    first = k / (int)DIAG_PARAM_DECIM;
                }
            }
            TV_CHECK_EQ_INT(first, c == 1 ? -1 : (int)cfg.gain_hold_checks + 1);
            TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_pending(&d, DIAG_DTC_P1A01));
        }
    }
}

/* Shorted turns at the resistance check's rate (identified units, the winding's temperature
 * known): diag_resistance_check() with the apparent resistance RATIO, then one in-service window
 * whose innovation is KW times the velocity (sig_case()'s), then 250 calls of
 * diag_resistance_check() at RATIO. Returns the call at which P1A01 confirmed (0: never). */
static int short_case(int identified, int temp_known, tv_real_t ratio, tv_real_t kw, diag_t *d)
{
    static diag_detect_t dd;
    diag_snapshot_t snap;
    int k;
    sig_setup(&dd, identified, temp_known, ratio, kw, 1, d, &snap);
    TV_CHECK(!diag_pending(d, DIAG_DTC_P1A01));
    for (k = 1; k <= 250; ++k) {
        diag_resistance_check(&dd, d, 1, TV_R(1.0), ratio * TV_R(4.3), TV_R(0.01), TV_R(4.3), temp_known, &snap);
        TV_CHECK(!diag_pending(d, DIAG_DTC_P2101) && !diag_pending(d, DIAG_DTC_P1A04));
        if (diag_confirmed(d, DIAG_DTC_P1A01)) {
            return k;
        }
    }
    return 0;
}

/* With the temperature known an identified unit's resistance below r_low_frac_known (0.85) with a
 * back-EMF deficit (kw 0.02 A s/rad) confirms P1A01 at the resistance check's 200th failing
 * sample (its confirmation count), without waiting for the motor-constant signature's 200 checks
 * of motion; not with the back-EMF intact (kw 0: a current-sensor gain, P1A04's), not above the
 * bound (0.86), not without the temperature (a cold winding) nor on the class's bounds (0.65). */
static void test_shorted_turns_known_temperature(void)
{
    static diag_t d;
    TV_CHECK_EQ_INT(short_case(1, 1, TV_R(0.8), TV_R(0.02), &d), 200);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A01].freeze.value, 0.8, 1e-6);
    TV_CHECK_EQ_INT(short_case(1, 1, TV_R(0.8), TV_R(0.0), &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A01));
    TV_CHECK_EQ_INT(short_case(1, 1, TV_R(0.86), TV_R(0.02), &d), 0);
    TV_CHECK_EQ_INT(short_case(1, 0, TV_R(0.8), TV_R(0.02), &d), 0);
    TV_CHECK_EQ_INT(short_case(0, 1, TV_R(0.8), TV_R(0.02), &d), 0);
}

/* The driven back-EMF window (MOTOR-CONSTANT SIGNATURE, diag_detect.h) on scripted samples: an
 * identified unit whose resistance reads r0 with the temperature known; `n` driven samples with
 * the scripted current and velocity (isens_i / isens_w, the velocity scaled by w_scale, or made
 * nearly collinear with the current), the current innovation kw1 w over the first window and kw2 w
 * after it; the resistance check runs before every sample at r0 + drift k / n. Returns the resistance check's sample at which P1A01 confirmed
 * (0: never). */
enum { KW_PLAIN = 0, KW_COLLINEAR };
static int kw_case(int n, int mode, tv_real_t w_scale, tv_real_t r0, tv_real_t drift, tv_real_t kw1, tv_real_t kw2,
                   diag_detect_t *dd, diag_t *d)
{
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    int k;
    int at = 0;
    diag_detect_config_default(&cfg);
    diag_detect_config_identified(&cfg);
    TV_CHECK_EQ_INT(diag_detect_init(dd, &cfg), TV_OK);
    diag_init(d);
    memset(&snap, 0, sizeof snap);
    for (k = 0; k < n + (int)DIAG_ISENS_SETTLE; ++k) {
        const tv_real_t i = isens_i(k);
        /* nearly collinear: 12 i plus a little of the independent triangle (rho^2 0.92) */
        const tv_real_t w = mode == KW_COLLINEAR ? TV_R(12.0) * i + TV_R(0.3) * isens_w(k) : w_scale * isens_w(k);
        /* the first DIAG_KW_WIN counted samples carry kw1, the rest kw2 */
        const tv_real_t y = (k < (int)(DIAG_KW_WIN + DIAG_ISENS_SETTLE) ? kw1 : kw2) * w;
        diag_resistance_check(dd, d, 1, TV_R(1.0), (r0 + drift * (tv_real_t)k / (tv_real_t)n) * TV_R(4.3),
                              TV_R(0.01), TV_R(4.3), 1, &snap);
        if (at == 0 && diag_confirmed(d, DIAG_DTC_P1A01)) {
            at = k;
        }
        diag_current_sensor_check(dd, d, 1, 1, 1, i + y, y, w, &snap);
    }
    return at;
}

/* The window takes every driven sample while the resistance reads low (these currents sit inside
 * the in-service band too, whose 500-sample window never fills here). It proves a back-EMF
 * deficit only: shorted turns' kw = +0.03 A s/rad sets kw_short at the second judged window (two
 * in a row above gain_kw_max), and the resistance check then confirms P1A01 200 samples later
 * (its count); not set: the first window alone, a velocity of variance 0.27 (creep), current and
 * velocity nearly collinear (rho^2 0.92), the resistance ratio moving 0.15 over each window, a
 * window at +0.03 followed by one at 0; and windows at 0 or at -0.03 (no deficit; a negative
 * slope is no shorted turns) give no verdict at all: neither kw_short nor a gain's slope (kw_ok),
 * which stays with the band window. */
static void test_driven_backemf_window(void)
{
    static diag_detect_t dd;
    static diag_t d;
    const int win = (int)DIAG_KW_WIN;
    const tv_real_t r = TV_R(0.8);
    int at;
    at = kw_case(win, KW_PLAIN, TV_R(1.0), r, TV_R(0.0), TV_R(0.03), TV_R(0.03), &dd, &d);
    TV_CHECK(!dd.kw_short && at == 0);
    at = kw_case(2 * win, KW_PLAIN, TV_R(1.0), r, TV_R(0.0), TV_R(0.03), TV_R(0.03), &dd, &d);
    TV_CHECK(dd.kw_short != 0u && !dd.kw_ok);
    /* the second window's last sample is call SETTLE - 1 + 2 win - 1; the resistance check fails
     * from the next call on and confirms at its 200th failure */
    at = kw_case(3 * win, KW_PLAIN, TV_R(1.0), r, TV_R(0.0), TV_R(0.03), TV_R(0.03), &dd, &d);
    TV_CHECK_EQ_INT(at, (int)DIAG_ISENS_SETTLE - 1 + 2 * win - 1 + 200);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
    /* not judged (two windows each, fewer samples than the band window's DIAG_ISENS_WIN, which
     * would judge a slope of its own) */
    at = kw_case(2 * win, KW_PLAIN, TV_R(0.3), r, TV_R(0.0), TV_R(0.03), TV_R(0.03), &dd, &d);
    TV_CHECK(!dd.kw_short && at == 0);
    at = kw_case(2 * win, KW_COLLINEAR, TV_R(1.0), r, TV_R(0.0), TV_R(0.03), TV_R(0.03), &dd, &d);
    TV_CHECK(!dd.kw_short && at == 0);
    at = kw_case(2 * win, KW_PLAIN, TV_R(1.0), TV_R(0.66), TV_R(0.3), TV_R(0.03), TV_R(0.03), &dd, &d);
    TV_CHECK(!dd.kw_short && at == 0);
    at = kw_case(2 * win, KW_PLAIN, TV_R(1.0), r, TV_R(0.0), TV_R(0.03), TV_R(0.0), &dd, &d);
    TV_CHECK(!dd.kw_short && at == 0);
    at = kw_case(2 * win, KW_PLAIN, TV_R(1.0), r, TV_R(0.0), TV_R(0.0), TV_R(0.0), &dd, &d);
    TV_CHECK(!dd.kw_short && !dd.kw_ok && at == 0);
    at = kw_case(2 * win, KW_PLAIN, TV_R(1.0), r, TV_R(0.0), TV_R(-0.03), TV_R(-0.03), &dd, &d);
    TV_CHECK(!dd.kw_short && !dd.kw_ok && at == 0);
}

/* Driven samples as kw_case()'s (kw 0.03 A s/rad: shorted turns) in three phases: one driven
 * window (DIAG_KW_WIN samples after the settling) at 0.8 R, n_exc samples at 1.17 R (the excursion
 * above gain_r_max that shorted turns give the resistance state as the plate leaves a stop), then
 * samples at 0.8 R again: a second window, then the resistance check until P1A01 confirms.
 * Returns the sample after the excursion at which it confirmed (0: not within 2 windows + 300). */
static int excursion_case(int n_exc, diag_detect_t *dd, diag_t *d)
{
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    const int n1 = (int)DIAG_KW_WIN + (int)DIAG_ISENS_SETTLE;
    int k;
    diag_detect_config_default(&cfg);
    diag_detect_config_identified(&cfg);
    TV_CHECK_EQ_INT(diag_detect_init(dd, &cfg), TV_OK);
    diag_init(d);
    memset(&snap, 0, sizeof snap);
    for (k = 0; k < n1 + n_exc + 2 * (int)DIAG_KW_WIN + 300; ++k) {
        /* 1 A more than kw_case()'s: outside the in-service band, whose window (which would
         * judge a slope of its own over these longer runs) never fills; the driven window's
         * regression is centred, the shift changes nothing there */
        const tv_real_t i = TV_R(1.0) + isens_i(k);
        const tv_real_t w = isens_w(k);
        const tv_real_t y = TV_R(0.03) * w;
        const tv_real_t ratio = k >= n1 && k < n1 + n_exc ? TV_R(1.17) : TV_R(0.8);
        diag_resistance_check(dd, d, 1, TV_R(1.0), ratio * TV_R(4.3), TV_R(0.01), TV_R(4.3), 1, &snap);
        if (diag_confirmed(d, DIAG_DTC_P1A01)) {
            return k - (n1 + n_exc) + 1;
        }
        diag_current_sensor_check(dd, d, 1, 1, 1, i + y, y, w, &snap);
        if (k == n1 - 1) {
            TV_CHECK(dd->kw_prev_ok != 0u && !dd->kw_short); /* one judged window: half the pair */
        }
    }
    return 0;
}

/* The driven window's reading survives an excursion above gain_r_max shorter than
 * DIAG_R_LOW_EXIT checks (220 samples here, as measured on class b in the 5 V slow sine): the
 * next judged window completes the pair, kw_short is set at its last sample (DIAG_KW_WIN after the
 * excursion) and P1A01 confirms at the resistance check's 200th failure after it, as with no
 * excursion at all; from DIAG_R_LOW_EXIT checks on the reading is dropped and one window is again
 * only half the pair. */
static void test_resistance_excursion(void)
{
    static diag_detect_t dd;
    static diag_t d;
    /* after an excursion: the second window's DIAG_KW_WIN samples, kw_short at its last, then
     * 200 failures; without one the second window began a sample earlier (the first counted
     * sample is the call DIAG_ISENS_SETTLE - 1, so the first window ends a call before n1) */
    const int at = (int)DIAG_KW_WIN + 200;
    TV_CHECK_EQ_INT(excursion_case(0, &dd, &d), at - 1);
    TV_CHECK_EQ_INT(excursion_case(220, &dd, &d), at);
    TV_CHECK_EQ_INT(excursion_case((int)DIAG_R_LOW_EXIT - 1, &dd, &d), at);
    TV_CHECK_EQ_INT(excursion_case((int)DIAG_R_LOW_EXIT, &dd, &d), (int)DIAG_KW_WIN + at);
}

/* The offset signature (diag_detect.h, identified units) on scripted estimates: every step
 * diag_param_check() then diag_resistance_check() (temperature known: P2101's bound 1.15) with
 * the apparent resistance ratio, friction f and preload m held, for `checks` mechanics checks.
 * Returns the mechanics check at which P1A04 confirmed (0: never). */
static int offset_case(int identified, int temp_known, tv_real_t ratio, tv_real_t f, tv_real_t m, int checks, int flicker, diag_t *d)
{
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    int k;
    int confirmed_at = 0;
    diag_detect_config_default(&cfg);
    if (identified) {
        diag_detect_config_identified(&cfg);
    }
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    TV_CHECK_EQ_INT((int)cfg.isens_sig_checks, 30);
    diag_init(d);
    memset(&snap, 0, sizeof snap);
    for (k = 1; k <= checks * (int)DIAG_PARAM_DECIM; ++k) {
        const int check = (k - 1) / (int)DIAG_PARAM_DECIM + 1;
        /* flicker: every flicker-th check the preload reads 1 (the run of checks starts over) */
        const tv_real_t mk = flicker > 0 && check % flicker == 0 ? TV_R(1.0) : m;
        snap.t_us = (uint64_t)k * 1000u;
        diag_param_check(&dd, d, 1, TV_R(1.0), f, TV_R(0.02), mk, TV_R(0.01), &snap);
        diag_resistance_check(&dd, d, 1, TV_R(1.0), ratio * TV_R(4.3), TV_R(0.01), TV_R(4.3), temp_known, &snap);
        if (confirmed_at == 0 && diag_confirmed(d, DIAG_DTC_P1A04)) {
            confirmed_at = check;
        }
    }
    return confirmed_at;
}

/* A current sensor that reads too little (an offset of -b, or a gain below 1) makes an identified
 * unit's apparent resistance read high on the holding current's side, as a raised resistance
 * does, but also leaves the torque per measured ampere short, which lowers the adapted preload;
 * a positive offset the reverse, with the friction as it was (a gain above 1 or shorted turns
 * raise it too). Measured before this check: an offset of -0.1 A confirmed P2101 first in 15 of
 * 50 runs of the fault matrix's identified section. Scripted: the resistance 1.2 with the
 * preload 0.95 confirms P1A04 at the 35th check (30 in a row, then its 6 failing checks), never
 * P2101; with the preload 1.0, P2101 and never P1A04; the resistance 0.9 with the preload 1.05
 * and the friction 1.0: P1A04 at the 35th; with the friction 1.05 too: no P1A04 without a back-
 * EMF window (the motor-constant signature's case); a preload that reads 1 every 29th check:
 * never (the run of 30 in a row); the class's bounds: never. */
static void test_offset_signature(void)
{
    static diag_t d;
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.2), TV_R(1.0), TV_R(0.95), 60, 0, &d), 35);
    TV_CHECK(!diag_confirmed(&d, DIAG_DTC_P2101));
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A04].freeze.value, 1.2, 1e-5);
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.2), TV_R(0.9), TV_R(0.95), 60, 0, &d), 35); /* a gain below 1 */
    /* a gain below 1 whose deficit the friction alone takes up (the 12 V sine): the friction's
     * deficit (0.25) larger than the resistance's excess (0.2): P1A04, and P2101 held although R
     * is above its bound; a deficit of 0.1 (a resistance step dips the friction by a fraction of
     * its own step) or a friction above 0.95: P2101 as ever */
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.2), TV_R(0.75), TV_R(1.0), 60, 0, &d), 35);
    TV_CHECK(!diag_confirmed(&d, DIAG_DTC_P2101));
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.2), TV_R(0.9), TV_R(1.0), 60, 0, &d), 0);
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P2101));
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.04), TV_R(0.96), TV_R(1.0), 60, 0, &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.2), TV_R(1.0), TV_R(1.0), 60, 0, &d), 0);
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P2101));
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
    /* R's excess at most DIAG_ISENS_SIG_EXCESS_PER_DEFICIT (6) times the level's deficit: 0.25
     * with the preload 0.05 low (an offset, 6 x 0.05 = 0.3) P1A04; 0.35 or a doubled winding (1.0)
     * with the same dip not: P2101 (identified unit 1004, closed-loop steps, R x 2: 30 checks of
     * the reading held while the estimator caught up, P1A04 confirmed before P2101) */
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.25), TV_R(1.0), TV_R(0.95), 60, 0, &d), 35);
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.35), TV_R(1.0), TV_R(0.95), 60, 0, &d), 0);
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P2101) && !diag_pending(&d, DIAG_DTC_P1A04));
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(2.0), TV_R(1.0), TV_R(0.95), 60, 0, &d), 0);
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P2101) && !diag_pending(&d, DIAG_DTC_P1A04));
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(0.9), TV_R(1.0), TV_R(1.05), 60, 0, &d), 35);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A01) && !diag_confirmed(&d, DIAG_DTC_P1A01));
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(0.9), TV_R(1.05), TV_R(1.05), 60, 0, &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.2), TV_R(1.0), TV_R(0.95), 120, 29, &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
    TV_CHECK_EQ_INT(offset_case(0, 1, TV_R(1.2), TV_R(1.0), TV_R(0.95), 60, 0, &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && !diag_pending(&d, DIAG_DTC_P2101));
    /* the temperature unknown: a resistance 1.2 may be a warm winding, and the preload low a
     * weak spring: no P1A04 */
    TV_CHECK_EQ_INT(offset_case(1, 0, TV_R(1.2), TV_R(1.0), TV_R(0.95), 60, 0, &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
    /* a friction above its range (1.2 > 1.15: a sticky plate's drag) is not the sensor */
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.2), TV_R(1.2), TV_R(0.95), 60, 0, &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
    /* the preload up (1.05) with the friction as it was and R as it was (class b's holding
     * currents hide +50 mA in R): P1A04 at the 35th, with the temperature known or not (no
     * fault raises a spring); both gave 0 before the reading without R */
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.0), TV_R(1.0), TV_R(1.05), 60, 0, &d), 35);
    TV_CHECK_EQ_INT(offset_case(1, 0, TV_R(1.0), TV_R(1.0), TV_R(1.05), 60, 0, &d), 35);
    /* ... but not with R read high (1.2: the sensor would read too little, not too much; P2101),
     * not on the low side with R as it was (0.95: a fatigued spring reads the same), not on the
     * class's bounds */
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.2), TV_R(1.0), TV_R(1.05), 60, 0, &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04) && diag_confirmed(&d, DIAG_DTC_P2101));
    TV_CHECK_EQ_INT(offset_case(1, 1, TV_R(1.0), TV_R(1.0), TV_R(0.95), 60, 0, &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
    TV_CHECK_EQ_INT(offset_case(0, 1, TV_R(1.0), TV_R(1.0), TV_R(1.05), 60, 0, &d), 0);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
}

/* One 12 s closed-loop driving run (seed 1) of the identified nominal unit (the nominal plant
 * with the default filter, as in test_friction_plus_25_percent_identified, and
 * diag_detect_config_identified()) with FAULT from 1.0 s; the application is told the winding's
 * temperature (the plant's 20 degC), as in the fault matrix. */
static void identified_run_in(const char *fault, sim_scenario_t scenario, sim_result_t *r);
static void identified_run(const char *fault, sim_result_t *r)
{
    identified_run_in(fault, SIM_SCN_DRIVE, r);
}

/* identified_run() in another scenario */
static void identified_run_in(const char *fault, sim_scenario_t scenario, sim_result_t *r)
{
    static plant_config_t pc;
    static app_config_t ac;
    plant_config_default(&pc);
    app_config_default(&ac);
    diag_detect_config_identified(&ac.diag);
    told_run(&pc, &ac, fault, scenario, 12.0, r);
}

/* identified_run() of each of the n faults: each confirms P1A04 within 10 s of the onset and
 * never NEVER; then OTHER confirms OTHER_CODE and never P1A04. WHAT names them in the printout. */
static void identified_case(const char *const *fault, int n, diag_dtc_t never, const char *other, diag_dtc_t other_code,
                            const char *what)
{
    sim_result_t r;
    int k;
    double worst = 0.0;
    for (k = 0; k < n; ++k) {
        identified_run(fault[k], &r);
        worst = fmax(worst, isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]) ? r.dtc_confirm_t_s[DIAG_DTC_P1A04] - 1.0 : 1e9);
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[never]));
    }
    identified_run(other, &r);
    TV_CHECK(isfinite(r.dtc_confirm_t_s[other_code]));
    TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]));
    printf("  identified unit: %s: P1A04 at most %.2f s after the onset; %s: %s at %.2f s\n", what, worst, other,
           diag_dtc_info(other_code)->code, r.dtc_confirm_t_s[other_code] - 1.0);
    TV_CHECK_LE(worst, 10.0);
}

/* The offset signature on the plant, identified_run(): a current offset of -0.1 A and +0.1 A and
 * a gain of -10 % confirm P1A04, never P2101; a resistance x2 confirms P2101, never P1A04 (its
 * step dips the adapted preload for a few checks). */
static void test_current_offset_identified(void)
{
    static const char *const fault[3] = {"current_offset:-0.1@1.0", "current_offset:0.1@1.0", "current_gain:-10@1.0"};
    identified_case(fault, 3, DIAG_DTC_P2101, "winding_resistance_high:2@1.0", DIAG_DTC_P2101,
                    "current offset -0.1 / +0.1 A, gain -10 %");
}

/* The in-service window's intercept bound on identified units (diag_detect_config_identified():
 * 0.025 A against the default 0.035): scripted windows whose intercept is 0.030 A (the reading of
 * a 50 mA offset in the 12 V sine of identified class b units 1001, 1004 and 1007: -0.030 ...
 * -0.034) pass with the default bounds and confirm P1A04 at the 6th window with the identified
 * ones; 0.020 A passes both (healthy identified units read within 0.013 in every scenario but
 * single windows of closed-loop driving). */
static void test_current_offset_bound_identified(void)
{
    static const double b[2] = {0.030, 0.020};
    static diag_t d;
    int m;
    for (m = 0; m < 4; ++m) {
        const int ident = m & 1;
        diag_detect_config_t cfg;
        int first;
        diag_detect_config_default(&cfg);
        if (ident) {
            diag_detect_config_identified(&cfg);
        }
        first = isens_scripted(&cfg, isens_i, -(tv_real_t)b[m >> 1], TV_R(0.2), 10, &d);
        if (ident && m >> 1 == 0) {
            /* the first DIAG_ISENS_SETTLE - 1 calls do not count: the 3,000th counted sample */
            TV_CHECK_EQ_INT(first, 6 * (int)DIAG_ISENS_WIN + (int)DIAG_ISENS_SETTLE - 2);
            TV_CHECK_NEAR(d.code[DIAG_DTC_P1A04].freeze.value, -0.030, 1e-4);
        } else {
            TV_CHECK_EQ_INT(first, -1);
            TV_CHECK(!diag_pending(&d, DIAG_DTC_P1A04));
        }
    }
}

/* The same on class b's nominal unit with its own model (an identified class b unit):
 * closed-loop steps, +50 mA and +100 mA from 1.0 s. Its holding currents (about 1 A) move the
 * apparent resistance by only 1 - 3 %, inside gain_r_max's margin, while the adapted preload
 * reads 1.04: before the reading without R neither confirmed a code in 12 s (the fault matrix's
 * identified class b units in closed-loop steps, 30 s: 0 of 3 at +50 mA). Both confirm P1A04
 * within 10 s and nothing else; healthy, nothing is confirmed or pending. */
static void test_current_offset_identified_class_b(void)
{
    static const char *const fault[3] = {"current_offset:0.05@1.0", "current_offset:0.1@1.0", NULL};
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    int k;
    int c;
    TV_CHECK_EQ_INT(plant_class_nominal(PLANT_CLASS_B, &pc), TV_OK);
    TV_CHECK_EQ_INT(sim_app_config_for_unit(PLANT_CLASS_B, &pc, &ac), TV_OK);
    diag_detect_config_identified(&ac.diag);
    for (k = 0; k < 3; ++k) {
        told_run(&pc, &ac, fault[k], SIM_SCN_CLOSED_STEPS, 12.0, &r);
        for (c = 0; c < (int)DIAG_DTC_COUNT; ++c) {
            if (fault[k] == NULL) {
                TV_CHECK(!sim_dtc_ever(&r, (diag_dtc_t)c));
            } else if (c != (int)DIAG_DTC_P1A04) {
                TV_CHECK(!isfinite(r.dtc_confirm_t_s[c]));
            }
        }
        if (fault[k] != NULL) {
            TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]));
            TV_CHECK_LE(r.dtc_confirm_t_s[DIAG_DTC_P1A04] - 1.0, 10.0);
            printf("  identified class b, closed-loop steps: %s: P1A04 %.2f s after the onset\n", fault[k],
                   r.dtc_confirm_t_s[DIAG_DTC_P1A04] - 1.0);
        }
    }
}

/* 20 % of the turns shorted on the identified unit, identified_run(): P1A01 confirmed (by the
 * resistance check's known-temperature bound; before it, the motor-constant signature's 200 checks
 * of motion did not come within the 11 s), never P1A04 or P2119; and in limp_home, whose 0.6 s
 * drives never filled the in-service band window: confirmed by the driven back-EMF window (before
 * it, nothing in the 11 s). */
static void test_winding_short_20_identified(void)
{
    sim_result_t r;
    identified_run("winding_short:0.2@1.0", &r);
    printf("  identified unit: winding_short:0.2: P1A01 at %.2f s after the onset\n", r.dtc_confirm_t_s[DIAG_DTC_P1A01] - 1.0);
    TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A01]));
    TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]) && !isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2119]));
    identified_run_in("winding_short:0.2@1.0", SIM_SCN_LIMP_HOME, &r);
    printf("  identified unit, limp_home: winding_short:0.2: P1A01 at %.2f s after the onset\n",
           r.dtc_confirm_t_s[DIAG_DTC_P1A01] - 1.0);
    TV_CHECK_LE(r.dtc_confirm_t_s[DIAG_DTC_P1A01] - 1.0, 10.0);
    TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]) && !isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2119]));
}

/* A current-sensor gain on an identified unit, identified_run(): +5 % and +20 % confirm P1A04
 * (the motor-constant signature; before it, 20 % confirmed P2119, friction, on every identified
 * population unit: README), never P2119; 35 % of the turns shorted confirms P1A01 and never
 * P1A04. */
static void test_current_gain_identified(void)
{
    static const char *const gain[2] = {"current_gain:5@1.0", "current_gain:20@1.0"};
    sim_result_t r;
    identified_case(gain, 2, DIAG_DTC_P2119, "winding_short:0.35@1.0", DIAG_DTC_P1A01, "current gain +5 % / +20 %");
    /* in limp_home, whose drives between the bridge's offs are too short to fill an in-service
     * window: +20 % confirmed since the window waits through the offs (before, nothing in 11 s) */
    identified_run_in("current_gain:20@1.0", SIM_SCN_LIMP_HOME, &r);
    printf("  identified unit, limp_home: current gain +20 %%: P1A04 at %.2f s after the onset\n",
           r.dtc_confirm_t_s[DIAG_DTC_P1A04] - 1.0);
    TV_CHECK_LE(r.dtc_confirm_t_s[DIAG_DTC_P1A04] - 1.0, 10.0);
    TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2119]) && !isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A01]));
}

/* No code confirmed on healthy units: 12 evaluation units per spread (every third of class b),
 * every benchmark scenario, seed 1, after stop learning (which must not confirm one either). */
static void test_no_code_confirmed_on_healthy_units(void)
{
    static plant_config_t pc;
    static app_config_t ac;
    sim_result_t r;
    int spread;
    uint64_t unit;
    int k;
    int runs = 0;
    int confirmed = 0;
    for (spread = 0; spread < 2; ++spread) {
        for (unit = 1000u; unit < 1012u; ++unit) {
            sim_result_t learn;
            if (!unit_config(unit, spread ? PLANT_SPREAD_ALL : PLANT_SPREAD_STOPS, &pc, &ac, &learn)) {
                continue;
            }
            ++runs;
            for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
                confirmed += isfinite(learn.dtc_confirm_t_s[k]) ? 1 : 0;
            }
            for (k = 0; k < (int)SIM_SCN_COUNT; ++k) {
                int d;
                if (k == (int)SIM_SCN_STOP_LEARN || k == (int)SIM_SCN_STUCK_RELEASE) {
                    continue;
                }
                run_with(&pc, &ac, (sim_scenario_t)k, 1u, NULL, &r);
                ++runs;
                for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
                    if (isfinite(r.dtc_confirm_t_s[d])) {
                        ++confirmed;
                        fprintf(stderr, "  unit %llu %s: %s confirmed at %.3f s\n", (unsigned long long)unit,
                                sim_scenario_name((sim_scenario_t)k), diag_dtc_info((diag_dtc_t)d)->code, r.dtc_confirm_t_s[d]);
                    }
                }
            }
        }
    }
    printf("  healthy: %d confirmed codes in %d runs (stop learning included)\n", confirmed, runs);
    TV_CHECK(runs >= 2 * 12 * 9 - 9); /* at most one unit per spread may fail its stop learning */
    TV_CHECK_EQ_INT(confirmed, 0);
}

/* The back-EMF check (diag_backemf_check(), the voltage equation's fit): scripted windows
 * (R ratio, n Ke ratio, its sigma), then the resistance check at an apparent resistance of 0.9 of
 * the model's (inside every bound: alone it passes P1A01) for 300 calls. Returns the call at which
 * P1A01 confirmed (0: never). */
static int backemf_case(int identified, const tv_real_t (*win)[3], int n_win, int p2100, diag_detect_t *dd)
{
    static diag_t d;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    int k;
    diag_detect_config_default(&cfg);
    if (identified) {
        diag_detect_config_identified(&cfg);
    }
    TV_CHECK_EQ_INT(diag_detect_init(dd, &cfg), TV_OK);
    diag_init(&d);
    memset(&snap, 0, sizeof snap);
    if (p2100) {
        (void)diag_report(&d, DIAG_DTC_P2100, DIAG_FAIL, &snap, TV_R(0.0));
    }
    for (k = 0; k < n_win; ++k) {
        diag_backemf_check(dd, &d, win[k][0], win[k][1], win[k][2]);
    }
    for (k = 1; k <= 300; ++k) {
        snap.t_us = (uint64_t)k * 1000u;
        diag_resistance_check(dd, &d, 1, TV_R(1.0), TV_R(0.9) * TV_R(4.3), TV_R(0.01), TV_R(4.3), 0, &snap);
        if (diag_confirmed(&d, DIAG_DTC_P1A01)) {
            return k;
        }
    }
    return 0;
}

static void test_backemf_short(void)
{
    static diag_detect_t dd;
    /* defaults (class model): bound 0.86, two windows in a row, n Ke + 2 sigma below it */
    static const tv_real_t two_low[2][3] = {{TV_R(0.8), TV_R(0.81), TV_R(0.01)}, {TV_R(0.8), TV_R(0.82), TV_R(0.01)}};
    static const tv_real_t one_low[2][3] = {{TV_R(0.8), TV_R(0.81), TV_R(0.01)}, {TV_R(0.8), TV_R(0.90), TV_R(0.01)}};
    static const tv_real_t low_ok[3][3] = {{TV_R(0.8), TV_R(0.81), TV_R(0.01)},
                                           {TV_R(0.8), TV_R(0.2), TV_R(0.5)}, /* not counted: sigma */
                                           {TV_R(0.8), TV_R(0.82), TV_R(0.01)}};
    static const tv_real_t within_2sigma[2][3] = {{TV_R(0.8), TV_R(0.84), TV_R(0.015)}, {TV_R(0.8), TV_R(0.84), TV_R(0.015)}};
    static const tv_real_t r_high[2][3] = {{TV_R(1.05), TV_R(0.81), TV_R(0.01)}, {TV_R(1.05), TV_R(0.81), TV_R(0.01)}};
    static const tv_real_t ident[2][3] = {{TV_R(0.93), TV_R(0.93), TV_R(0.005)}, {TV_R(0.93), TV_R(0.93), TV_R(0.005)}};
    TV_CHECK_EQ_INT(backemf_case(0, two_low, 0, 0, &dd), 0); /* no window: R at 0.9 alone passes */
    TV_CHECK_EQ_INT(backemf_case(0, two_low, 2, 0, &dd), 200); /* P1A01's confirmation count */
    TV_CHECK(dd.ke_low_n >= DIAG_KE_SHORT_WINDOWS);
    TV_CHECK_EQ_INT(backemf_case(0, one_low, 2, 0, &dd), 0);
    TV_CHECK(dd.ke_low_n < DIAG_KE_SHORT_WINDOWS && dd.ke_low_n == 0u);
    TV_CHECK_EQ_INT(backemf_case(0, low_ok, 3, 0, &dd), 200); /* an undetermined window between: state kept */
    TV_CHECK_EQ_INT(backemf_case(0, within_2sigma, 2, 0, &dd), 0); /* 0.84 + 0.03 is not below 0.86 */
    TV_CHECK_EQ_INT(backemf_case(0, r_high, 2, 0, &dd), 0);  /* R above the model's: no short */
    TV_CHECK_EQ_INT(backemf_case(0, two_low, 2, 1, &dd), 0); /* the open-winding code active: cleared */
    TV_CHECK(dd.ke_low_n < DIAG_KE_SHORT_WINDOWS);
    TV_CHECK_EQ_INT(backemf_case(0, ident, 2, 0, &dd), 0);   /* 0.93 on the class's bound: healthy spread */
    TV_CHECK_EQ_INT(backemf_case(1, ident, 2, 0, &dd), 200); /* on an identified unit's 0.95: shorted */
    {
        /* an identified unit: R must read below the bound too (a current offset's onset reads n Ke
         * low for a second with R at 0.98) */
        static const tv_real_t ke_only[2][3] = {{TV_R(0.98), TV_R(0.86), TV_R(0.02)}, {TV_R(0.98), TV_R(0.90), TV_R(0.015)}};
        TV_CHECK_EQ_INT(backemf_case(1, ke_only, 2, 0, &dd), 0);
        TV_CHECK_EQ_INT(backemf_case(0, ke_only, 2, 0, &dd), 0); /* 0.90 + 0.03 above the class's 0.86 */
    }
    {
        diag_detect_config_t cfg;
        diag_detect_config_default(&cfg);
        TV_CHECK_NEAR(cfg.ke_short_max, 0.86, 1e-6);
        TV_CHECK_NEAR(cfg.ke_sigma_max, 0.03, 1e-6);
        cfg.ke_short_max = TV_R(1.0);
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
        diag_detect_config_default(&cfg);
        cfg.ke_sigma_max = TV_R(0.0);
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    }
}

/* The fit's resistance check (diag_fit_resistance_check()) feeding the resistance check: three
 * windows in a row above 1.25 of the model's R make diag_resistance_check() fail P2101 at every
 * driven step, also below its current threshold and with the estimator's R + dR inside its bound
 * (P2101 confirms at the 200th: diag.c's count), the freeze frame holding the fit's ratio; two
 * windows then one below, a window not judged (the temperature unknown, the model not in service)
 * or the current sensor's code pending clear the count; with it cleared, R + dR passes again. */
static int fit_r_case(const tv_real_t *win, int n_win, int temp_known, int p1a04, tv_real_t current_A, diag_t *d,
                      diag_detect_t *dd)
{
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    int k;
    diag_detect_config_default(&cfg);
    TV_CHECK_EQ_INT(diag_detect_init(dd, &cfg), TV_OK);
    diag_init(d);
    memset(&snap, 0, sizeof snap);
    if (p1a04) {
        (void)diag_report(d, DIAG_DTC_P1A04, DIAG_FAIL, &snap, TV_R(0.05));
    }
    for (k = 0; k < n_win; ++k) {
        diag_fit_resistance_check(dd, d, win[k] > TV_R(0.0) && temp_known, win[k], TV_R(1.0), 0);
    }
    for (k = 1; k <= 300; ++k) {
        snap.t_us = (uint64_t)k * 1000u;
        /* R + dR at 1.1 R: inside the class's 1.35 */
        diag_resistance_check(dd, d, 1, current_A, TV_R(1.1) * TV_R(4.3), TV_R(0.01), TV_R(4.3), temp_known, &snap);
        if (diag_confirmed(d, DIAG_DTC_P2101)) {
            return k;
        }
    }
    return 0;
}

static void test_fit_resistance(void)
{
    static diag_t d;
    static diag_detect_t dd;
    static const tv_real_t three[3] = {TV_R(1.3), TV_R(1.27), TV_R(1.26)};
    static const tv_real_t two_then_low[3] = {TV_R(1.3), TV_R(1.27), TV_R(1.24)};
    static const tv_real_t low_between[4] = {TV_R(1.3), TV_R(1.3), TV_R(1.2), TV_R(1.3)};
    static const tv_real_t not_judged[4] = {TV_R(1.3), TV_R(1.3), TV_R(0.0), TV_R(1.3)}; /* 0: active = 0 */
    static const tv_real_t four[4] = {TV_R(1.3), TV_R(1.3), TV_R(1.3), TV_R(1.3)};
    static const tv_real_t at_bound[3] = {TV_R(1.25), TV_R(1.25), TV_R(1.25)};
    diag_detect_config_t cfg;
    diag_detect_config_default(&cfg);
    TV_CHECK_NEAR(cfg.r_fit_high_frac, 1.25, 1e-6);
    TV_CHECK_EQ_INT(DIAG_R_FIT_HIGH_WINDOWS, 3);
    TV_CHECK_EQ_INT(fit_r_case(three, 3, 1, 0, TV_R(1.0), &d, &dd), 200);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P2101].freeze.value, 1.26, 1e-6); /* the last window's ratio */
    TV_CHECK_EQ_INT(fit_r_case(three, 3, 1, 0, TV_R(0.1), &d, &dd), 200); /* below r_excite_A too */
    TV_CHECK_EQ_INT(fit_r_case(four, 4, 1, 0, TV_R(1.0), &d, &dd), 200);
    TV_CHECK_EQ_INT(fit_r_case(two_then_low, 3, 1, 0, TV_R(1.0), &d, &dd), 0);
    TV_CHECK(dd.r_fit_high_n == 0u && d.code[DIAG_DTC_P2101].counter == 0u); /* R + dR passes */
    TV_CHECK_EQ_INT(fit_r_case(low_between, 4, 1, 0, TV_R(1.0), &d, &dd), 0);
    TV_CHECK_EQ_INT(fit_r_case(not_judged, 4, 1, 0, TV_R(1.0), &d, &dd), 0);
    TV_CHECK_EQ_INT(fit_r_case(at_bound, 3, 1, 0, TV_R(1.0), &d, &dd), 0); /* above, not at */
    TV_CHECK_EQ_INT(fit_r_case(three, 3, 0, 0, TV_R(1.0), &d, &dd), 0);    /* temperature unknown */
    TV_CHECK_EQ_INT(fit_r_case(three, 3, 1, 1, TV_R(1.0), &d, &dd), 0);    /* P1A04 pending */
    TV_CHECK(dd.r_fit_high_n == 0u);
    /* a count reached, then the temperature lost: the resistance check does not use it */
    TV_CHECK_EQ_INT(fit_r_case(three, 3, 1, 0, TV_R(1.0), &d, &dd), 200);
    {
        diag_snapshot_t snap;
        int k;
        memset(&snap, 0, sizeof snap);
        diag_init(&d);
        for (k = 0; k < 300; ++k) {
            diag_resistance_check(&dd, &d, 1, TV_R(1.0), TV_R(1.1) * TV_R(4.3), TV_R(0.01), TV_R(4.3), 0, &snap);
        }
        TV_CHECK(!diag_confirmed(&d, DIAG_DTC_P2101) && d.code[DIAG_DTC_P2101].counter == 0u);
    }
    cfg.r_fit_high_frac = TV_R(1.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    cfg.r_fit_high_frac = (tv_real_t)NAN;
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_NONFINITE);
}

/* The fit against a per-unit baseline (base = 1: the ratios are the fit's over the baseline's):
 * P2101 from three windows in a row above r_fit_base_high_frac (1.10) rather than 1.25; P1A04
 * (a current gain: R down, n Ke intact) from five windows in a row below gain_fit_base_max (0.97)
 * with n Ke above ke_short_max, failed by the resistance check at each driven step (6 confirm),
 * the freeze frame holding the fit's ratio. Not with n Ke down as well (shorted turns), nor
 * without a baseline, nor with the temperature unknown, nor at the bounds; the open winding's
 * code clears the gain's count. Returns the step P2101 (code 0) or P1A04 (code 1) confirmed at,
 * 0 for none within 300. */
static int fit_base_case(const tv_real_t *r, const tv_real_t *ke, int n_win, int base, int temp_known, int code,
                         diag_t *d, diag_detect_t *dd)
{
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    const diag_dtc_t dtc = code == 0 ? DIAG_DTC_P2101 : DIAG_DTC_P1A04;
    int k;
    diag_detect_config_default(&cfg);
    TV_CHECK_EQ_INT(diag_detect_init(dd, &cfg), TV_OK);
    diag_init(d);
    memset(&snap, 0, sizeof snap);
    for (k = 0; k < n_win; ++k) {
        diag_fit_resistance_check(dd, d, temp_known, r[k], ke[k], base);
    }
    for (k = 1; k <= 300; ++k) {
        snap.t_us = (uint64_t)k * 1000u;
        /* R + dR at the model's: passes P2101 and P1A01 on its own */
        diag_resistance_check(dd, d, 1, TV_R(1.0), TV_R(4.3), TV_R(0.01), TV_R(4.3), temp_known, &snap);
        if (diag_confirmed(d, dtc)) {
            return k;
        }
    }
    return 0;
}

static void test_fit_baseline(void)
{
    static diag_t d;
    static diag_detect_t dd;
    static const tv_real_t high[3] = {TV_R(1.12), TV_R(1.15), TV_R(1.11)};
    static const tv_real_t at_high[3] = {TV_R(1.10), TV_R(1.10), TV_R(1.10)};
    static const tv_real_t gain[5] = {TV_R(0.955), TV_R(0.96), TV_R(0.95), TV_R(0.955), TV_R(0.95)};
    static const tv_real_t gain_four[5] = {TV_R(0.955), TV_R(0.96), TV_R(0.95), TV_R(0.955), TV_R(0.99)};
    static const tv_real_t at_low[5] = {TV_R(0.97), TV_R(0.97), TV_R(0.97), TV_R(0.97), TV_R(0.97)};
    static const tv_real_t ke_ok[5] = {TV_R(1.0), TV_R(0.99), TV_R(1.01), TV_R(1.0), TV_R(1.0)};
    static const tv_real_t ke_short[5] = {TV_R(0.8), TV_R(0.8), TV_R(0.8), TV_R(0.8), TV_R(0.8)};
    /* the windows across the onset of shorted turns: R down first, n Ke after (then both) */
    static const tv_real_t r_onset[5] = {TV_R(0.96), TV_R(0.93), TV_R(0.9), TV_R(0.85), TV_R(0.8)};
    static const tv_real_t ke_onset[5] = {TV_R(0.99), TV_R(0.97), TV_R(0.93), TV_R(0.88), TV_R(0.81)};
    diag_detect_config_t cfg;
    diag_detect_config_default(&cfg);
    TV_CHECK_NEAR(cfg.r_fit_base_high_frac, 1.10, 1e-6);
    TV_CHECK_NEAR(cfg.gain_fit_base_max, 0.97, 1e-6);
    TV_CHECK(cfg.fit_base_r_ohm == TV_R(0.0) && cfg.fit_base_nke_V_s == TV_R(0.0) && cfg.fit_base_windows == 0u);
    /* P2101 above 1.10 of the baseline (200 failing steps confirm); at it, or without a baseline, not */
    TV_CHECK_EQ_INT(fit_base_case(high, ke_ok, 3, 1, 1, 0, &d, &dd), 200);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P2101].freeze.value, 1.11, 1e-6);
    TV_CHECK_EQ_INT(fit_base_case(at_high, ke_ok, 3, 1, 1, 0, &d, &dd), 0);
    TV_CHECK_EQ_INT(fit_base_case(high, ke_ok, 3, 0, 1, 0, &d, &dd), 0);
    /* P1A04: a gain, R below 0.97 of the baseline with n Ke intact in 5 windows in a row: 6
     * failing steps confirm */
    TV_CHECK_EQ_INT(DIAG_R_FIT_LOW_WINDOWS, 5);
    TV_CHECK_EQ_INT(fit_base_case(gain, ke_ok, 5, 1, 1, 1, &d, &dd), 6);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A04].freeze.value, 0.95, 1e-6);
    TV_CHECK(!diag_pending(&d, DIAG_DTC_P2101) && !diag_confirmed(&d, DIAG_DTC_P2101));
    TV_CHECK_EQ_INT(fit_base_case(gain, ke_ok, 4, 1, 1, 1, &d, &dd), 0);      /* four */
    TV_CHECK_EQ_INT(fit_base_case(gain_four, ke_ok, 5, 1, 1, 1, &d, &dd), 0); /* four, then one back */
    TV_CHECK_EQ_INT(fit_base_case(at_low, ke_ok, 5, 1, 1, 1, &d, &dd), 0);    /* below, not at */
    TV_CHECK_EQ_INT(fit_base_case(gain, ke_short, 5, 1, 1, 1, &d, &dd), 0);   /* shorted turns */
    TV_CHECK_EQ_INT(fit_base_case(r_onset, ke_onset, 5, 1, 1, 1, &d, &dd), 0); /* ... across their onset */
    TV_CHECK_EQ_INT(fit_base_case(gain, ke_ok, 5, 0, 1, 1, &d, &dd), 0);      /* no baseline */
    TV_CHECK_EQ_INT(fit_base_case(gain, ke_ok, 5, 1, 0, 1, &d, &dd), 0);      /* temperature unknown */
    /* the open winding's code pending clears the gain's count */
    (void)fit_base_case(gain, ke_ok, 5, 1, 1, 1, &d, &dd);
    {
        diag_snapshot_t snap;
        memset(&snap, 0, sizeof snap);
        diag_init(&d);
        (void)diag_report(&d, DIAG_DTC_P2100, DIAG_FAIL, &snap, TV_R(0.0));
        diag_fit_resistance_check(&dd, &d, 1, gain[0], ke_ok[0], 1);
        TV_CHECK(dd.r_fit_low_n == 0u);
    }
    /* configuration: a baseline needs both values, each >= 0 and finite; the bounds on their side of 1 */
    cfg.fit_base_r_ohm = TV_R(4.3);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    cfg.fit_base_nke_V_s = TV_R(0.68);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    cfg.fit_base_nke_V_s = TV_R(-0.68);
    cfg.fit_base_r_ohm = TV_R(-4.3);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    cfg.fit_base_r_ohm = (tv_real_t)NAN;
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    diag_detect_config_default(&cfg);
    cfg.r_fit_base_high_frac = TV_R(1.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    diag_detect_config_default(&cfg);
    cfg.gain_fit_base_max = TV_R(1.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
}

/* The baseline learned and used end to end (app.c fit_base_learn(), population_main.c
 * learn_fit_base()): 30 s of closed-loop driving at 20 degC, told, with fit_base_windows = 16
 * learn R within 1 % of the plant's and n Ke within 1.5 % on a unit of each class (all_varied);
 * nothing is learned with the temperature unknown, nor kept when it lies outside the model's
 * +-30 % (the model's R set 1.45 times too small); with the baseline, a current gain of +5 %
 * (which the class's bounds do not see on these units) confirms P1A04 and R x 1.25 confirms P2101
 * in 30 s of driving, and the healthy unit confirms nothing. The output's state (TV_HEALTH_5
 * FitBaseState) reads learning until the baseline is learned, in force after (and given), and its
 * count of windows summed is 0 with the temperature unknown, between 1 and 15 after 3 s of the
 * drive, 0 again once learned. */
static void test_fit_baseline_learned_and_used(void)
{
    static const uint64_t units[2] = {1000u, 1001u};
    int u;
    for (u = 0; u < 2; ++u) {
        static plant_config_t pc;
        static app_config_t ac;
        static app_config_t lc;
        static sim_result_t r;
        sim_options_t opt;
        int d;
        if (!unit_config(units[u], PLANT_SPREAD_ALL, &pc, &ac, &r)) {
            TV_CHECK(0); /* both units learn their stops */
            continue;
        }
        lc = ac;
        lc.diag.fit_base_windows = 16u;
        sim_options_default(&opt);
        opt.scenario = SIM_SCN_DRIVE;
        opt.duration_s = 30.0;
        opt.seed = 900002u;
        opt.plant = &pc;
        opt.app = &lc;
        /* temperature unknown: no baseline */
        TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
        TV_CHECK(!isfinite(r.fit_base_r_ohm) && !isfinite(r.fit_base_nke_V_s));
        TV_CHECK_EQ_INT(r.fit_base_state, APP_FIT_BASE_LEARNING); /* (TV_HEALTH_5) learning, nothing summed */
        TV_CHECK_EQ_INT(r.fit_base_windows, 0);
        /* implausible: the model's R 1.45 times too small */
        opt.temp_reading = 1;
        opt.temp_reading_C = opt.winding_temp_C;
        lc.model.R_ohm = ac.model.R_ohm / TV_R(1.45);
        TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
        TV_CHECK(!isfinite(r.fit_base_r_ohm));
        TV_CHECK_EQ_INT(r.fit_base_state, APP_FIT_BASE_LEARNING);
        lc.model.R_ohm = ac.model.R_ohm;
        /* 3 s of the drive: still learning, some of the 16 windows summed */
        opt.duration_s = 3.0;
        TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
        TV_CHECK(!isfinite(r.fit_base_r_ohm));
        TV_CHECK_EQ_INT(r.fit_base_state, APP_FIT_BASE_LEARNING);
        TV_CHECK(r.fit_base_windows > 0u && r.fit_base_windows < 16u && r.fit_base_windows <= r.fit_windows);
        printf("  unit %llu: after 3 s, %u of 16 windows summed (%u taken)\n", (unsigned long long)units[u],
               (unsigned)r.fit_base_windows, (unsigned)r.fit_windows);
        opt.duration_s = 30.0;
        TV_CHECK_EQ_INT(sim_run(&opt, &r), TV_OK);
        TV_CHECK_EQ_INT(r.fit_base_state, APP_FIT_BASE_IN_FORCE); /* learned: the count back to 0 */
        TV_CHECK_EQ_INT(r.fit_base_windows, 0);
        TV_CHECK(isfinite(r.fit_base_r_ohm) && fabs(r.fit_base_r_ohm / r.r_true_20_ohm - 1.0) < 0.01);
        TV_CHECK(isfinite(r.fit_base_nke_V_s) && fabs(r.fit_base_nke_V_s / r.nke_true_V_s - 1.0) < 0.015);
        printf("  unit %llu: baseline R %.4f of the plant's, n Ke %.4f\n", (unsigned long long)units[u],
               r.fit_base_r_ohm / r.r_true_20_ohm, r.fit_base_nke_V_s / r.nke_true_V_s);
        /* learned once: a winding drifting slowly, +50 % over 200 s from 8 s into the run, after
         * the baseline was learned, is judged against the healthy unit (a baseline that kept
         * learning would follow the drift, and P2101 would not confirm) and the baseline stays */
        {
            const double r_learned = r.fit_base_r_ohm;
            opt.duration_s = 120.0;
            sim_fault_run_opt(&opt, "winding_resistance_high:1.5@8.0:200", &r);
            opt.duration_s = 30.0;
            TV_CHECK(r.fit_base_r_ohm == r_learned);
            TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]) && r.dtc_confirm_t_s[DIAG_DTC_P2101] > 8.0);
            /* and no current-sensor code on the way: unit 1000's levels read below the class's, but
             * a drift is no step of the fit's R (DIAG_R_FIT_UP_ONSET; without it P1A04 at 24 s) */
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]));
            printf("  unit %llu: R drifting +50 %% over 200 s from 8 s: P2101 at %.2f s (R x %.3f then)\n",
                   (unsigned long long)units[u], r.dtc_confirm_t_s[DIAG_DTC_P2101],
                   1.0 + 0.5 * (r.dtc_confirm_t_s[DIAG_DTC_P2101] - 8.0) / 200.0);
        }
        lc.diag.fit_base_r_ohm = (tv_real_t)r.fit_base_r_ohm;
        lc.diag.fit_base_nke_V_s = (tv_real_t)r.fit_base_nke_V_s;
        /* the class's bounds: a gain of +5 % not confirmed (its R reads inside the class's spread) */
        told_run(&pc, &ac, "current_gain:5@2.0", SIM_SCN_DRIVE, 30.0, &r);
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]));
        /* with the baseline */
        ac.diag.fit_base_r_ohm = lc.diag.fit_base_r_ohm;
        ac.diag.fit_base_nke_V_s = lc.diag.fit_base_nke_V_s;
        told_run(&pc, &ac, "current_gain:5@2.0", SIM_SCN_DRIVE, 30.0, &r);
        TV_CHECK_EQ_INT(r.fit_base_state, APP_FIT_BASE_IN_FORCE); /* given */
        TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]) && r.dtc_confirm_t_s[DIAG_DTC_P1A04] > 2.0);
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
        printf("  unit %llu: current gain +5 %%: P1A04 %.2f s after the onset\n", (unsigned long long)units[u],
               r.dtc_confirm_t_s[DIAG_DTC_P1A04] - 2.0);
        /* a gain of -5 %: the fit's R 5 % up with n Ke intact; the mechanics decide (README "A current
         * gain below 1 from the fit"): unit 1000's read below the class's (friction 0.80, preload
         * 0.78 of it), so its levels' deficit stands for the gain's: P1A04; unit 1001's sit at the
         * class's (1.01, 1.02), which a raised winding would leave too: no verdict */
        told_run(&pc, &ac, "current_gain:-5@2.0", SIM_SCN_DRIVE, 30.0, &r);
        if (u == 0) {
            TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]) && r.dtc_confirm_t_s[DIAG_DTC_P1A04] > 2.0);
        } else {
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]));
        }
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]));
        printf("  unit %llu: current gain -5 %%: P1A04 %.2f s after the onset (friction %.3f, preload %.3f)\n",
               (unsigned long long)units[u], r.dtc_confirm_t_s[DIAG_DTC_P1A04] - 2.0, r.friction_rel, r.preload_rel);
        told_run(&pc, &ac, "winding_resistance_high:1.25@2.0", SIM_SCN_DRIVE, 30.0, &r);
        TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2101]) && r.dtc_confirm_t_s[DIAG_DTC_P2101] > 2.0);
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]));
        printf("  unit %llu: R x 1.25: P2101 %.2f s after the onset\n", (unsigned long long)units[u],
               r.dtc_confirm_t_s[DIAG_DTC_P2101] - 2.0);
        told_run(&pc, &ac, NULL, SIM_SCN_DRIVE, 30.0, &r);
        for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[d]));
        }
    }
}

/* The fit's per-unit baseline as population --fit-baseline learns it (30 s of healthy driving,
 * 16 windows summed) into ac's diag.fit_base_r_ohm and diag.fit_base_nke_V_s. */
static void learn_fit_baseline(const plant_config_t *pc, app_config_t *ac)
{
    static app_config_t lc;
    static sim_result_t r;
    lc = *ac;
    lc.diag.fit_base_windows = 16u;
    learning_run(pc, &lc, SIM_SCN_DRIVE, 30.0, &r);
    TV_CHECK(isfinite(r.fit_base_r_ohm) && isfinite(r.fit_base_nke_V_s));
    ac->diag.fit_base_r_ohm = (tv_real_t)r.fit_base_r_ohm;
    ac->diag.fit_base_nke_V_s = (tv_real_t)r.fit_base_nke_V_s;
}

/* The friction check's per-unit bounds as population --friction-baseline learns them, from 15 s
 * learning runs of the n scenarios on the healthy unit: *uc = *ac with diag.friction_high_rel 1.12 x
 * the largest level the check judged, diag.friction_fast_high 1.12 x the largest signature friction,
 * diag.friction_fast_level_min 0.05 below the first. Returns that largest level. */
static double learn_friction_bound(const plant_config_t *pc, const app_config_t *ac, const sim_scenario_t *scn, int n,
                                   app_config_t *uc)
{
    static sim_result_t r;
    double seen = 0.0;
    double seen_fast = 0.0;
    int k;
    for (k = 0; k < n; ++k) {
        learning_run(pc, ac, scn[k], 15.0, &r);
        TV_CHECK(isfinite(r.friction_check_max) && r.friction_check_max >= r.friction_rel - 1e-12);
        TV_CHECK(isfinite(r.friction_fast_max));
        seen = fmax(seen, r.friction_check_max);
        seen_fast = fmax(seen_fast, r.friction_fast_max);
    }
    *uc = *ac;
    uc->diag.friction_high_rel = (tv_real_t)(1.12 * seen);
    uc->diag.friction_fast_high = (tv_real_t)(1.12 * seen_fast);
    uc->diag.friction_fast_level_min = (tv_real_t)(1.12 * seen - 0.05);
    printf("  unit's healthy friction level up to %.3f, signature %.3f: bounds %.3f, %.3f\n", seen, seen_fast,
           (double)uc->diag.friction_high_rel, (double)uc->diag.friction_fast_high);
    return seen;
}

/* A per-unit bound of the friction check (README "A per-unit bound of the friction check"): on a
 * stops_varied unit (the model's friction is the unit's) the adapted level reads 1.25 under friction
 * x 1.25 but the class's bound, 1.7, covers the units' +-30 % spread: no P2119. The unit's bound,
 * 1.12 x the largest level (and signature friction) its check judged in healthy runs of two
 * scenarios (population --friction-baseline takes five), catches it in the paper sine and the
 * drive, and the healthy unit in the same runs confirms nothing. sim_result_t::friction_check_max
 * is the level the check judged: at least the end's level, never NaN once the check ran. */
static void test_friction_bound_per_unit(void)
{
    static plant_config_t pc;
    static app_config_t ac;
    static app_config_t uc;
    static sim_result_t r;
    static const sim_scenario_t learn[2] = {SIM_SCN_DRIVE, SIM_SCN_PAPER_SINE};
    double seen;
    int k;
    if (!unit_config(1000u, PLANT_SPREAD_STOPS, &pc, &ac, &r)) {
        TV_CHECK(0);
        return;
    }
    seen = learn_friction_bound(&pc, &ac, learn, 2, &uc);
    /* a healthy stops_varied unit: its friction reads its model's */
    TV_CHECK(seen > 0.95 && seen < 1.06);
    for (k = 0; k < 2; ++k) {
        int d;
        told_run(&pc, &ac, "friction_high:1.25@2.0", learn[k], 8.0, &r);
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2119]));
        TV_CHECK(r.friction_rel > 1.2 && r.friction_rel < 1.3);
        told_run(&pc, &uc, "friction_high:1.25@2.0", learn[k], 8.0, &r);
        TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2119]) && r.dtc_confirm_t_s[DIAG_DTC_P2119] > 2.0);
        printf("  %s, friction x 1.25 at 2 s: P2119 at %.2f s with the unit's bound, none with the class's\n",
               sim_scenario_name(learn[k]), r.dtc_confirm_t_s[DIAG_DTC_P2119]);
        for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[d]) || d == (int)DIAG_DTC_P2119);
        }
        told_run(&pc, &uc, NULL, learn[k], 8.0, &r);
        for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
            TV_CHECK(!isfinite(r.dtc_confirm_t_s[d]));
        }
    }
    /* a current-sensor gain of +20 % raises the friction level too (the torque per measured ampere
     * too large); with the fit's per-unit baseline the fit reads R low with n Ke intact, P2119 is
     * held and P1A04 confirms first (without the hold P2119 came first in the paper sine, closed-loop
     * steps and slow sine on every stops_varied unit of the fault matrix) */
    {
        learn_fit_baseline(&pc, &uc);
        for (k = 0; k < 2; ++k) {
            static const sim_scenario_t scn[2] = {SIM_SCN_PAPER_SINE, SIM_SCN_CLOSED_STEPS};
            told_run(&pc, &uc, "current_gain:20@2.0", scn[k], 8.0, &r);
            TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]) && r.dtc_confirm_t_s[DIAG_DTC_P1A04] > 2.0);
            TV_CHECK(!(r.dtc_confirm_t_s[DIAG_DTC_P2119] <= r.dtc_confirm_t_s[DIAG_DTC_P1A04]));
            printf("  %s, current gain +20 %% at 2 s: P1A04 at %.2f s, P2119 %s\n", sim_scenario_name(scn[k]),
                   r.dtc_confirm_t_s[DIAG_DTC_P1A04], isfinite(r.dtc_confirm_t_s[DIAG_DTC_P2119]) ? "after it" : "never");
        }
    }
}

/* A current gain below 1 from the fit (README "A current gain below 1 from the fit"): on a
 * stops_varied unit with the fit's per-unit baseline, a gain of -5 % reads the fit's R 5 % up with n
 * Ke intact and the adapted friction and preload down with it (the torque per measured ampere too
 * large): P1A04. A winding raised by 5 % reads the same R with the mechanics as they were: no code
 * (P2101's bound is 1.10 of the baseline). Without the baseline (the class's bounds) the gain is
 * not seen. */
static void test_current_gain_below_one_fit(void)
{
    static plant_config_t pc;
    static app_config_t ac;
    static sim_result_t r;
    int d;
    if (!unit_config(1000u, PLANT_SPREAD_STOPS, &pc, &ac, &r)) {
        TV_CHECK(0);
        return;
    }
    told_run(&pc, &ac, "current_gain:-5@2.0", SIM_SCN_DRIVE, 30.0, &r);
    TV_CHECK(!isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]));
    learn_fit_baseline(&pc, &ac);
    told_run(&pc, &ac, "current_gain:-5@2.0", SIM_SCN_DRIVE, 30.0, &r);
    TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A04]) && r.dtc_confirm_t_s[DIAG_DTC_P1A04] > 2.0);
    for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[d]) || d == (int)DIAG_DTC_P1A04);
    }
    TV_CHECK(r.friction_rel < 0.975 && r.preload_rel < 0.975);
    printf("  stops_varied 1000, drive, current gain -5 %% at 2 s: P1A04 at %.2f s (friction %.3f, preload %.3f)\n",
           r.dtc_confirm_t_s[DIAG_DTC_P1A04], r.friction_rel, r.preload_rel);
    told_run(&pc, &ac, "winding_resistance_high:1.05@2.0", SIM_SCN_DRIVE, 30.0, &r);
    for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[d]));
    }
    TV_CHECK(r.r_fit_ohm > 1.031 * (double)ac.diag.fit_base_r_ohm); /* above 1 / gain_fit_base_max */
    printf("  the winding raised 5 %%: the fit's R %.4f of the baseline's, friction %.3f, preload %.3f: no code\n",
           r.r_fit_ohm / (double)ac.diag.fit_base_r_ohm, r.friction_rel, r.preload_rel);
}

/* Shorted turns on a unit with its own friction bound and fit baseline (README "A per-unit bound of
 * the friction check"): 20 % of the turns shorted lower Kt with R and Ke, and the friction state
 * takes up the missing torque; in the slow sine it rose above the unit's bound and P2119 confirmed
 * 0.4 s before the back-EMF check's P1A01 on stops_varied units 1001, 1005, 1007 and 1008 of the
 * fault matrix. P2119 is held while the fit reads n Ke below the baseline's (diag_backemf_check()'s
 * count): P1A01 first. The healthy unit with the same bounds confirms nothing. */
static void test_shorted_turns_own_friction_bound(void)
{
    static plant_config_t pc;
    static app_config_t ac;
    static app_config_t uc;
    static sim_result_t r;
    static const sim_scenario_t learn[2] = {SIM_SCN_DRIVE, SIM_SCN_SLOW_SINE};
    int d;
    if (!unit_config(1001u, PLANT_SPREAD_STOPS, &pc, &ac, &r)) {
        TV_CHECK(0);
        return;
    }
    (void)learn_friction_bound(&pc, &ac, learn, 2, &uc);
    learn_fit_baseline(&pc, &uc);
    told_run(&pc, &uc, "winding_short:0.2@2.0", SIM_SCN_SLOW_SINE, 8.0, &r);
    TV_CHECK(isfinite(r.dtc_confirm_t_s[DIAG_DTC_P1A01]) && r.dtc_confirm_t_s[DIAG_DTC_P1A01] > 2.0);
    TV_CHECK(!(r.dtc_confirm_t_s[DIAG_DTC_P2119] <= r.dtc_confirm_t_s[DIAG_DTC_P1A01]));
    printf("  stops_varied 1001, slow sine, 20 %% of the turns shorted at 2 s: P1A01 at %.3f s, P2119 at %.3f s\n",
           r.dtc_confirm_t_s[DIAG_DTC_P1A01], r.dtc_confirm_t_s[DIAG_DTC_P2119]);
    told_run(&pc, &uc, NULL, SIM_SCN_SLOW_SINE, 8.0, &r);
    for (d = 0; d < (int)DIAG_DTC_COUNT; ++d) {
        TV_CHECK(!isfinite(r.dtc_confirm_t_s[d]));
    }
}

/* The offset check of the voltage equation's fit (diag_isens_fit_check()): windows reading
 * |b| >= 35 mA fail P1A04 (6 confirm), below 17.5 mA pass (the leaky counter's decrement), in
 * between nothing; a window whose variance inflation is above 50 is not judged, nor any while the
 * open-winding code is active. The freeze frame's value is the offset. */
static void test_isens_fit_offset(void)
{
    static diag_t d;
    static diag_detect_t dd;
    diag_detect_config_t cfg;
    diag_snapshot_t snap;
    int k;
    diag_detect_config_default(&cfg);
    TV_CHECK_NEAR(cfg.isens_fit_max_A, 0.035, 1e-6);
    TV_CHECK_NEAR(cfg.isens_fit_vif_max, 50.0, 1e-6);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_OK);
    diag_init(&d);
    memset(&snap, 0, sizeof snap);
    /* five failing windows: pending, not confirmed; a sixth confirms */
    for (k = 0; k < 5; ++k) {
        snap.t_us = (uint64_t)(k + 1) * 250000u;
        diag_isens_fit_check(&d, &dd, TV_R(-0.05), TV_R(10.0), &snap);
    }
    TV_CHECK(!diag_confirmed(&d, DIAG_DTC_P1A04) && d.code[DIAG_DTC_P1A04].counter == 5u);
    /* in between (20 mA) and ill-determined (inflation 60): nothing */
    diag_isens_fit_check(&d, &dd, TV_R(0.02), TV_R(1.0), &snap);
    diag_isens_fit_check(&d, &dd, TV_R(0.2), TV_R(60.0), &snap);
    diag_isens_fit_check(&d, &dd, (tv_real_t)NAN, TV_R(1.0), &snap);
    TV_CHECK(d.code[DIAG_DTC_P1A04].counter == 5u);
    /* a passing window (10 mA) takes one back */
    diag_isens_fit_check(&d, &dd, TV_R(0.01), TV_R(1.0), &snap);
    TV_CHECK(d.code[DIAG_DTC_P1A04].counter == 4u);
    diag_isens_fit_check(&d, &dd, TV_R(0.035), TV_R(50.0), &snap); /* at both bounds: fails */
    TV_CHECK(d.code[DIAG_DTC_P1A04].counter == 5u);
    snap.t_us = 3000000u;
    diag_isens_fit_check(&d, &dd, TV_R(-0.06), TV_R(2.0), &snap);
    TV_CHECK(diag_confirmed(&d, DIAG_DTC_P1A04));
    TV_CHECK_NEAR(d.code[DIAG_DTC_P1A04].freeze.value, -0.06, 1e-6);
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P1A04].freeze.t_us, 3000000u);
    /* the open winding's code active: not judged */
    diag_init(&d);
    (void)diag_report(&d, DIAG_DTC_P2100, DIAG_FAIL, &snap, TV_R(0.0));
    for (k = 0; k < 10; ++k) {
        diag_isens_fit_check(&d, &dd, TV_R(0.1), TV_R(1.0), &snap);
    }
    TV_CHECK(d.code[DIAG_DTC_P1A04].counter == 0u && !diag_confirmed(&d, DIAG_DTC_P1A04));
    /* the configuration's validation */
    cfg.isens_fit_vif_max = TV_R(0.5);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
    diag_detect_config_default(&cfg);
    cfg.isens_fit_max_A = TV_R(0.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &cfg), TV_ERR_CONFIG);
}

int main(void)
{
    TV_TEST_RUN(test_track_offset_named_within_50_ms);
    TV_TEST_RUN(test_backemf_short);
    TV_TEST_RUN(test_isens_fit_offset);
    TV_TEST_RUN(test_fit_resistance);
    TV_TEST_RUN(test_fit_baseline);
    TV_TEST_RUN(test_friction_bound_per_unit);
    TV_TEST_RUN(test_shorted_turns_own_friction_bound);
    TV_TEST_RUN(test_current_gain_below_one_fit);
    TV_TEST_RUN(test_fit_baseline_learned_and_used);
    TV_TEST_RUN(test_jam_confirmed_within_100_ms);
    TV_TEST_RUN(test_sticky_plate_jam_within_100_ms_of_stall);
    TV_TEST_RUN(test_open_winding_confirmed_within_10_ms);
    TV_TEST_RUN(test_winding_resistance_out_of_range);
    TV_TEST_RUN(test_winding_resistance_not_a_jam);
    TV_TEST_RUN(test_winding_resistance_braking_not_bridge);
    TV_TEST_RUN(test_winding_temperature);
    TV_TEST_RUN(test_mechanics_check_timing);
    TV_TEST_RUN(test_torque_signature);
    TV_TEST_RUN(test_torque_signature_ambiguous);
    TV_TEST_RUN(test_torque_signature_both_low);
    TV_TEST_RUN(test_away_reading);
    TV_TEST_RUN(test_away_stale);
    TV_TEST_RUN(test_torque_pause);
    TV_TEST_RUN(test_friction_and_spring_codes);
    TV_TEST_RUN(test_current_sensor_check_timing);
    TV_TEST_RUN(test_current_sensor_offset_detected);
    TV_TEST_RUN(test_spring_break_within_300_ms);
    TV_TEST_RUN(test_spring_probe);
    TV_TEST_RUN(test_spring_probe_opening);
    TV_TEST_RUN(test_spring_probe_reference_lag);
    TV_TEST_RUN(test_spring_probe_creeping);
    TV_TEST_RUN(test_spring_probe_slow_feed);
    TV_TEST_RUN(test_spring_break_while_holding);
    TV_TEST_RUN(test_spring_break_late_units);
    TV_TEST_RUN(test_friction_plus_25_percent_identified);
    TV_TEST_RUN(test_motor_constant_signature);
    TV_TEST_RUN(test_current_gain_identified);
    TV_TEST_RUN(test_shorted_turns_known_temperature);
    TV_TEST_RUN(test_driven_backemf_window);
    TV_TEST_RUN(test_resistance_excursion);
    TV_TEST_RUN(test_winding_short_20_identified);
    TV_TEST_RUN(test_offset_signature);
    TV_TEST_RUN(test_current_offset_identified);
    TV_TEST_RUN(test_current_offset_bound_identified);
    TV_TEST_RUN(test_current_sensor_vif_bound);
    TV_TEST_RUN(test_current_offset_identified_class_b);
    TV_TEST_RUN(test_no_code_confirmed_on_healthy_units);
    return tv_test_summary();
}
