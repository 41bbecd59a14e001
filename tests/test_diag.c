/**
 * @file test_diag.c
 * @brief Diagnostic codes (firmware/diag/diag.h) and the detectors' rules (diag_detect.h) on
 *        scripted inputs: confirmation at exactly the documented number of failing samples
 *        (consecutive and leaky), pending / confirmed / healed events with their times, healing
 *        after exactly heal_count passes (a failure restarting it), the freeze frame of the
 *        confirming sample, the queue's overflow counted, the actions; the vote naming the
 *        offset track, the jam and open-winding rules at their thresholds. Built float and double.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "diag.h"
#include "diag_detect.h"
#include "tv_status.h"
#include "tv_test.h"

static diag_snapshot_t snap_at(uint64_t t_us)
{
    diag_snapshot_t s;
    memset(&s, 0, sizeof s);
    s.t_us = t_us;
    s.x[0] = (tv_real_t)t_us * TV_R(1e-3);
    s.x[2] = TV_R(0.5);
    s.var[2] = TV_R(1e-8);
    s.r_est_ohm = TV_R(4.3);
    s.supply_V = TV_R(13.5);
    s.duty = TV_R(0.25);
    return s;
}

static void test_table_is_complete(void)
{
    int k;
    for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
        const diag_dtc_info_t *i = diag_dtc_info((diag_dtc_t)k);
        TV_CHECK(i != NULL);
        TV_CHECK(strlen(i->code) == 5u && i->code[0] == 'P');
        TV_CHECK(i->confirm_count >= 1u && i->heal_count >= 1u);
    }
    TV_CHECK(diag_dtc_info(DIAG_DTC_COUNT) == NULL);
    /* the README's documented times (1 kHz): track codes 20 ms, jam 50 ms, open winding 5 ms */
    TV_CHECK_EQ_INT(diag_dtc_info(DIAG_DTC_P0121)->confirm_count, 20);
    TV_CHECK_EQ_INT(diag_dtc_info(DIAG_DTC_P2112)->confirm_count, 50);
    TV_CHECK_EQ_INT(diag_dtc_info(DIAG_DTC_P2100)->confirm_count, 5);
    TV_CHECK_EQ_INT(diag_dtc_info(DIAG_DTC_P2101)->confirm_count, 200);
    TV_CHECK(strcmp(diag_event_name(DIAG_EV_HEALED), "healed") == 0);
}

static void test_confirms_at_exactly_the_documented_failing_sample(void)
{
    int k;
    for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
        static diag_t d;
        const unsigned n = diag_dtc_info((diag_dtc_t)k)->confirm_count;
        unsigned s;
        diag_event_t ev;
        diag_init(&d);
        for (s = 1u; s < n; ++s) {
            diag_snapshot_t sn = snap_at(s);
            TV_CHECK_EQ_INT(diag_report(&d, (diag_dtc_t)k, DIAG_FAIL, &sn, (tv_real_t)sn.t_us), TV_OK);
        }
        TV_CHECK_EQ_INT(diag_confirmed(&d, (diag_dtc_t)k), 0);
        TV_CHECK_EQ_INT(diag_pending(&d, (diag_dtc_t)k), n > 1u);
        {
            diag_snapshot_t sn = snap_at(n);
            TV_CHECK_EQ_INT(diag_report(&d, (diag_dtc_t)k, DIAG_FAIL, &sn, (tv_real_t)sn.t_us), TV_OK);
        }
        TV_CHECK_EQ_INT(diag_confirmed(&d, (diag_dtc_t)k), 1);
        TV_CHECK_EQ_INT(diag_event_pop(&d, &ev), 1);
        TV_CHECK_EQ_INT(ev.kind, DIAG_EV_PENDING);
        TV_CHECK_EQ_INT(ev.t_us, 1);
        TV_CHECK_EQ_INT(ev.dtc, k);
        TV_CHECK_EQ_INT(diag_event_pop(&d, &ev), 1);
        TV_CHECK_EQ_INT(ev.kind, DIAG_EV_CONFIRMED);
        TV_CHECK_EQ_INT(ev.t_us, n);
        TV_CHECK_EQ_INT(diag_event_pop(&d, &ev), 0);
        /* the freeze frame is the confirming sample's snapshot */
        TV_CHECK_EQ_INT(d.code[k].has_freeze, 1);
        TV_CHECK_EQ_INT(d.code[k].freeze.t_us, n);
        TV_CHECK_NEAR(d.code[k].freeze.x[0], (double)((tv_real_t)n * TV_R(1e-3)), 0.0);
        TV_CHECK_NEAR(d.code[k].freeze.value, (double)n, 0.0);
        TV_CHECK_NEAR(d.code[k].freeze.supply_V, 13.5, 0.0);
        TV_CHECK_NEAR(d.code[k].freeze.sigma[2], 1e-4, 1e-4 * 1e-6); /* sqrt of the variance 1e-8 */
        TV_CHECK_NEAR(d.code[k].freeze.sigma[0], 0.0, 0.0);
        TV_CHECK_NEAR(d.code[k].freeze.duty, 0.25, 0.0);
        TV_CHECK_EQ_INT(d.code[k].confirmations, 1);
    }
}

static void test_leaky_counter_confirms_late_and_forgets(void)
{
    /* P2100 (confirm_count N = 5). Fail-pass alternation never confirms (the counter goes 1, 0,
     * 1, 0, ...), and each 0 -> 1 is a new pending event. Fail-fail-pass gains one per cycle and
     * confirms at the second failure of cycle N - 1, sample 3 (N - 2) + 2 = 11. */
    static diag_t d;
    diag_event_t ev;
    uint64_t t;
    int pend = 0;
    diag_init(&d);
    for (t = 1u; t <= 200u; ++t) {
        diag_snapshot_t sn = snap_at(t);
        (void)diag_report(&d, DIAG_DTC_P2100, (t % 2u) ? DIAG_FAIL : DIAG_PASS, &sn, (tv_real_t)sn.t_us);
        while (diag_event_pop(&d, &ev)) {
            pend += ev.kind == DIAG_EV_PENDING;
            TV_CHECK(ev.kind == DIAG_EV_PENDING);
        }
    }
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P2100), 0);
    TV_CHECK_EQ_INT(pend, 100);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2100), 0); /* leaked back to idle */
    diag_init(&d);
    for (t = 1u; t <= 30u && !diag_confirmed(&d, DIAG_DTC_P2100); ++t) {
        diag_snapshot_t sn = snap_at(t);
        (void)diag_report(&d, DIAG_DTC_P2100, (t % 3u) == 0u ? DIAG_PASS : DIAG_FAIL, &sn, (tv_real_t)sn.t_us);
    }
    TV_CHECK_EQ_INT(t - 1u, 3u * (5u - 2u) + 2u);
    /* DIAG_NOT_RUN changes nothing, whatever it is given */
    {
        const diag_t before = d;
        TV_CHECK_EQ_INT(diag_report(&d, DIAG_DTC_P2100, DIAG_NOT_RUN, NULL, TV_R(0.0)), TV_OK);
        TV_CHECK(memcmp(&before, &d, sizeof d) == 0);
        TV_CHECK_EQ_INT(diag_report(&d, DIAG_DTC_COUNT, DIAG_FAIL, NULL, TV_R(0.0)), TV_ERR_RANGE);
        TV_CHECK_EQ_INT(diag_report(&d, DIAG_DTC_P0121, (diag_result_t)7, NULL, TV_R(0.0)), TV_ERR_RANGE);
        TV_CHECK_EQ_INT(diag_report(&d, DIAG_DTC_P0121, DIAG_FAIL, NULL, TV_R(0.0)), TV_ERR_NULL);
        TV_CHECK_EQ_INT(diag_report(NULL, DIAG_DTC_P0121, DIAG_PASS, NULL, TV_R(0.0)), TV_ERR_NULL);
        TV_CHECK(memcmp(&before, &d, sizeof d) == 0);
    }
}

static void test_heals_after_exactly_heal_count_passes(void)
{
    static diag_t d;
    diag_event_t ev;
    const unsigned n = diag_dtc_info(DIAG_DTC_P0121)->confirm_count;
    const unsigned h = diag_dtc_info(DIAG_DTC_P0121)->heal_count;
    uint64_t t = 0u;
    unsigned k;
    diag_init(&d);
    for (k = 0; k < n; ++k) {
        diag_snapshot_t sn = snap_at(++t);
        (void)diag_report(&d, DIAG_DTC_P0121, DIAG_FAIL, &sn, (tv_real_t)sn.t_us);
    }
    TV_CHECK_EQ_INT(diag_action(&d), DIAG_ACTION_LIMITED);
    /* h - 1 passes, a failure (restarts the count), then h - 1 passes: still confirmed */
    for (k = 0; k + 1u < h; ++k) {
        diag_snapshot_t sn = snap_at(++t);
        (void)diag_report(&d, DIAG_DTC_P0121, DIAG_PASS, &sn, (tv_real_t)sn.t_us);
    }
    {
        diag_snapshot_t sn = snap_at(++t);
        (void)diag_report(&d, DIAG_DTC_P0121, DIAG_FAIL, &sn, (tv_real_t)sn.t_us);
    }
    for (k = 0; k + 1u < h; ++k) {
        diag_snapshot_t sn = snap_at(++t);
        (void)diag_report(&d, DIAG_DTC_P0121, DIAG_PASS, &sn, (tv_real_t)sn.t_us);
    }
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P0121), 1);
    /* the freeze frame is still the first confirmation's: a failure while confirmed does not retake it */
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P0121].freeze.t_us, n);
    {
        diag_snapshot_t sn = snap_at(++t);
        (void)diag_report(&d, DIAG_DTC_P0121, DIAG_PASS, &sn, (tv_real_t)sn.t_us);
    }
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P0121), 0);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P0121), 0);
    TV_CHECK_EQ_INT(diag_action(&d), DIAG_ACTION_NONE);
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P0121].has_freeze, 1); /* history kept */
    TV_CHECK_EQ_INT(diag_event_pop(&d, &ev), 1);
    TV_CHECK_EQ_INT(ev.kind, DIAG_EV_PENDING);
    TV_CHECK_EQ_INT(diag_event_pop(&d, &ev), 1);
    TV_CHECK_EQ_INT(ev.kind, DIAG_EV_CONFIRMED);
    TV_CHECK_EQ_INT(diag_event_pop(&d, &ev), 1);
    TV_CHECK_EQ_INT(ev.kind, DIAG_EV_HEALED);
    TV_CHECK_EQ_INT(ev.t_us, n + 2u * h);
    /* the largest action wins */
    for (k = 0; k < n; ++k) {
        diag_snapshot_t sn = snap_at(++t);
        (void)diag_report(&d, DIAG_DTC_P0221, DIAG_FAIL, &sn, (tv_real_t)sn.t_us);
        (void)diag_report(&d, DIAG_DTC_P2100, DIAG_FAIL, &sn, (tv_real_t)sn.t_us);
    }
    TV_CHECK_EQ_INT(diag_action(&d), DIAG_ACTION_SAFE);
    diag_clear(&d);
    TV_CHECK_EQ_INT(diag_action(&d), DIAG_ACTION_NONE);
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P2100].confirmations, 1);
}

static void test_queue_overflow_is_counted(void)
{
    /* DIAG_EVENT_QUEUE_LEN + 4 pending events, nothing drained: 4 lost, the first ones kept in order */
    static diag_t d;
    diag_event_t ev;
    unsigned k;
    diag_init(&d);
    for (k = 0; k < DIAG_EVENT_QUEUE_LEN + 4u; ++k) {
        diag_snapshot_t sn = snap_at(k + 1u);
        (void)diag_report(&d, DIAG_DTC_P2100, DIAG_FAIL, &sn, (tv_real_t)sn.t_us);
        (void)diag_report(&d, DIAG_DTC_P2100, DIAG_PASS, &sn, (tv_real_t)sn.t_us);
    }
    TV_CHECK_EQ_INT(d.events_lost, 4);
    for (k = 0; k < DIAG_EVENT_QUEUE_LEN; ++k) {
        TV_CHECK_EQ_INT(diag_event_pop(&d, &ev), 1);
        TV_CHECK_EQ_INT(ev.t_us, k + 1u);
    }
    TV_CHECK_EQ_INT(diag_event_pop(&d, &ev), 0);
    diag_init(&d);
    TV_CHECK_EQ_INT(d.events_lost, 0);
}

/* Fresh codes and detectors on the default thresholds. */
static void fresh_detectors(diag_t *d, diag_detect_t *dd, diag_detect_config_t *c)
{
    diag_init(d);
    diag_detect_config_default(c);
    TV_CHECK_EQ_INT(diag_detect_init(dd, c), TV_OK);
}

static void test_vote_names_the_track_away_from_the_prediction(void)
{
    static diag_t d;
    diag_detect_t dd;
    diag_detect_config_t c;
    diag_snapshot_t sn = snap_at(1u);
    unsigned k;
    fresh_detectors(&d, &dd, &c);
    /* agreeing tracks: both kept, all pass */
    TV_CHECK_EQ_INT(diag_tps_vote(&dd, &d, 1, TV_R(0.500), TV_R(0.5004), TV_R(0.5002), &sn), DIAG_TPS_BOTH);
    /* track 1 off by 0.0183 rad (1 % of the supply): named; track 2 kept from the first sample */
    for (k = 0; k < 20u; ++k) {
        TV_CHECK_EQ_INT(diag_tps_vote(&dd, &d, 1, TV_R(0.5183), TV_R(0.5), TV_R(0.5001), &sn), DIAG_TPS_ONLY2);
    }
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P0121), 1);
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P0221) + diag_pending(&d, DIAG_DTC_P0221), 0);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2135) + diag_confirmed(&d, DIAG_DTC_P2135), 0);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P0121].freeze.value, 0.0183, 1e-6);
    /* the prediction half-way: nobody can be named, P2135 fails and no angle is used */
    fresh_detectors(&d, &dd, &c);
    TV_CHECK_EQ_INT(diag_tps_vote(&dd, &d, 1, TV_R(0.52), TV_R(0.50), TV_R(0.51), &sn), DIAG_TPS_NONE);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2135), 1);
    /* a track out of range: the vote does not run */
    diag_init(&d);
    TV_CHECK_EQ_INT(diag_tps_vote(&dd, &d, 0, TV_R(0.52), TV_R(0.50), TV_R(0.50), &sn), DIAG_TPS_BOTH);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P0121), 0);
    /* bad thresholds refused */
    c.tps_vote_frac = TV_R(0.6);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &c), TV_ERR_CONFIG);
    diag_detect_config_default(&c);
    c.open_i_max_A = TV_R(0.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &c), TV_ERR_CONFIG);
}

static void test_jam_and_open_winding_rules(void)
{
    static diag_t d;
    diag_detect_t dd;
    diag_detect_config_t c;
    diag_snapshot_t sn = snap_at(1u);
    unsigned k;
    fresh_detectors(&d, &dd, &c);
    /* a still plate 0.04 rad below its target under +4 V: the first DIAG_JAM_WINDOW calls fill the
     * history, then P2112 (stuck closed) fails once per call: confirmed at call WINDOW + 50 */
    for (k = 1; k <= DIAG_JAM_WINDOW + 49u; ++k) {
        diag_jam_check(&dd, &d, 1, TV_R(0.54), TV_R(0.5), TV_R(4.0), TV_R(1.9), &sn);
    }
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P2112), 0);
    diag_jam_check(&dd, &d, 1, TV_R(0.54), TV_R(0.5), TV_R(4.0), TV_R(1.9), &sn);
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P2112), 1);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2111) + diag_confirmed(&d, DIAG_DTC_P2111), 0);
    /* just inside the error, or pushing the wrong way, too weakly, or below twice the breakaway: no failure */
    diag_init(&d);
    diag_jam_check(&dd, &d, 1, TV_R(0.534), TV_R(0.5), TV_R(4.0), TV_R(1.9), &sn);
    diag_jam_check(&dd, &d, 1, TV_R(0.54), TV_R(0.5), TV_R(-4.0), TV_R(1.9), &sn);
    diag_jam_check(&dd, &d, 1, TV_R(0.54), TV_R(0.5), TV_R(2.9), TV_R(1.0), &sn);
    diag_jam_check(&dd, &d, 0, TV_R(0.54), TV_R(0.5), TV_R(4.0), TV_R(1.9), &sn);
    diag_jam_check(&dd, &d, 1, TV_R(0.54), TV_R(0.5), TV_R(4.0), TV_R(2.01), &sn); /* below 2x breakaway */
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2112), 0);
    /* the breakaway in the push's direction: away from limp-home (u phi > 0) or within
     * jam_limp_margin_rad of it the springs oppose (Ms + M0 + c |phi|); toward it from beyond the
     * margin only Ms counts */
    TV_CHECK_NEAR(diag_jam_breakaway_Nm(&dd, TV_R(4.0), TV_R(0.5), TV_R(0.3), TV_R(0.25), TV_R(0.06)), 0.58, 1e-6);
    TV_CHECK_NEAR(diag_jam_breakaway_Nm(&dd, TV_R(-4.0), TV_R(-0.1), TV_R(0.3), TV_R(0.25), TV_R(0.06)), 0.556, 1e-6);
    TV_CHECK_NEAR(diag_jam_breakaway_Nm(&dd, TV_R(-4.0), TV_R(0.5), TV_R(0.3), TV_R(0.25), TV_R(0.06)), 0.3, 1e-6);
    TV_CHECK_NEAR(diag_jam_breakaway_Nm(&dd, TV_R(4.0), TV_R(-0.1), TV_R(0.3), TV_R(0.25), TV_R(0.06)), 0.3, 1e-6);
    TV_CHECK_NEAR(diag_jam_breakaway_Nm(&dd, TV_R(-4.0), TV_R(0.04), TV_R(0.3), TV_R(0.25), TV_R(0.06)), 0.5524, 1e-6);
    TV_CHECK_NEAR(diag_jam_breakaway_Nm(NULL, TV_R(-4.0), TV_R(0.5), TV_R(0.3), TV_R(0.25), TV_R(0.06)), 0.58, 1e-6);
    c.jam_limp_margin_rad = TV_R(0.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &c), TV_ERR_CONFIG);
    /* the window is judged only once the push held through all of it. After a bridge-off pause
     * (active = 0) a still plate under +4 V fails at the WINDOW-th driven call, not before; one
     * call off restarts the count */
    fresh_detectors(&d, &dd, &c);
    for (k = 0; k < 20u; ++k) {
        diag_jam_check(&dd, &d, 0, TV_R(0.54), TV_R(0.5), TV_R(0.0), TV_R(1.9), &sn);
    }
    for (k = 1; k < DIAG_JAM_WINDOW; ++k) {
        diag_jam_check(&dd, &d, 1, TV_R(0.54), TV_R(0.5), TV_R(4.0), TV_R(1.9), &sn);
    }
    diag_jam_check(&dd, &d, 0, TV_R(0.54), TV_R(0.5), TV_R(4.0), TV_R(1.9), &sn);
    for (k = 1; k < DIAG_JAM_WINDOW; ++k) {
        diag_jam_check(&dd, &d, 1, TV_R(0.54), TV_R(0.5), TV_R(4.0), TV_R(1.9), &sn);
    }
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2112), 0);
    diag_jam_check(&dd, &d, 1, TV_R(0.54), TV_R(0.5), TV_R(4.0), TV_R(1.9), &sn);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2112), 1);
    /* a target step: the plate rests at 0.5 rad under 1 V, 0.01 rad below its target (within
     * error: not a drive toward it), then the target steps to 0.6 under +4 V; the plate starts 2
     * samples later at 1 mrad a sample, so the window ending at the drive's 8th sample saw 6 mrad:
     * no failure at any sample (judged from the first sample of the drive, the window of resting
     * angles failed once). A drive that turns (-4 V toward a target below) restarts the count,
     * and it waits while the plate still coasts the old way: it goes on to 0.529 and 0.530 and
     * stays; the motion over 3 samples against the drive is 3, 3, 2 mrad (coasting: above 1.5),
     * then 1 mrad (the count's first sample), so the 8th counted sample, the reversal's 11th, is
     * the first failure (0 mrad over a window of driven samples at rest) */
    fresh_detectors(&d, &dd, &c);
    for (k = 0; k < 20u; ++k) {
        diag_jam_check(&dd, &d, 1, TV_R(0.51), TV_R(0.5), TV_R(1.0), TV_R(1.9), &sn);
    }
    for (k = 1; k <= 30u; ++k) {
        const tv_real_t phi = TV_R(0.5) + (k > 2u ? TV_R(0.001) * (tv_real_t)(k - 2u) : TV_R(0.0));
        diag_jam_check(&dd, &d, 1, TV_R(0.6), phi, TV_R(4.0), TV_R(1.9), &sn);
        TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2112) + diag_pending(&d, DIAG_DTC_P2111), 0);
    }
    for (k = 1; k <= 10u; ++k) {
        diag_jam_check(&dd, &d, 1, TV_R(0.4), k == 1u ? TV_R(0.529) : TV_R(0.530), TV_R(-4.0), TV_R(1.9), &sn);
        TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2111), 0);
    }
    diag_jam_check(&dd, &d, 1, TV_R(0.4), TV_R(0.530), TV_R(-4.0), TV_R(1.9), &sn);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2111), 1);
    /* moving by >= 2 mrad over the window passes */
    fresh_detectors(&d, &dd, &c);
    for (k = 0; k < 100u; ++k) {
        diag_jam_check(&dd, &d, 1, TV_R(1.2), TV_R(0.3) + (tv_real_t)k * TV_R(0.0003), TV_R(10.0), TV_R(1.9), &sn);
    }
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2112), 0);
    /* open winding: 5 samples of no current under |u| >= 3 V with |u - e| >= 3 V, e the back-EMF
     * moved 0.35 V toward 0, confirm: the 4th u 3 V against an emf of 0.3 V (within the
     * allowance: e = 0), the 5th 12 V against 9.3 V (e = 8.95 V, 3.05 V of drive). Not run in
     * between: -3 V against -0.5 V (e = -0.15 V, 2.85 V), 12 V against 9.4 V (2.95 V), 2.9 V
     * applied however large u - emf is, the bridge off. (A sample below the voltage gate first:
     * the check compares the current with the one a period ago, and a current that changed by
     * more than 0.05 A is not judged.) */
    diag_init(&d);
    TV_CHECK_NEAR(c.open_u_min_V, 3.0, 1e-6);
    TV_CHECK_NEAR(c.open_emf_allow_V, 0.35, 1e-6);
    diag_open_check(&dd, &d, 1, TV_R(1.0), TV_R(0.0), 0, TV_R(0.0), TV_R(0.149), &sn);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2100), 0);
    for (k = 0; k < 3u; ++k) {
        diag_open_check(&dd, &d, 1, TV_R(3.0), TV_R(0.0), 0, TV_R(0.0), TV_R(0.149), &sn);
    }
    diag_open_check(&dd, &d, 1, TV_R(3.0), TV_R(0.3), 0, TV_R(0.0), TV_R(0.149), &sn);
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P2100].counter, 4);
    diag_open_check(&dd, &d, 1, TV_R(-3.0), TV_R(-0.5), 0, TV_R(0.0), TV_R(0.149), &sn);
    diag_open_check(&dd, &d, 1, TV_R(12.0), TV_R(9.4), 0, TV_R(0.0), TV_R(0.149), &sn);
    diag_open_check(&dd, &d, 1, TV_R(2.9), TV_R(-40.0), 0, TV_R(0.0), TV_R(0.149), &sn);
    diag_open_check(&dd, &d, 0, TV_R(12.0), TV_R(0.0), 0, TV_R(0.0), TV_R(0.0), &sn);
    TV_CHECK_EQ_INT(d.code[DIAG_DTC_P2100].counter, 4);
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P2100), 0);
    diag_open_check(&dd, &d, 1, TV_R(12.0), TV_R(9.3), 0, TV_R(0.0), TV_R(0.0), &sn);
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P2100), 1);
    diag_init(&d);
    diag_open_check(&dd, &d, 1, TV_R(3.0), TV_R(0.0), 0, TV_R(0.0), TV_R(0.15), &sn);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P2100), 0);
    c.open_emf_allow_V = TV_R(-0.1);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &c), TV_ERR_CONFIG);
    c.open_emf_allow_V = TV_R(3.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &c), TV_ERR_CONFIG);
    c.open_emf_allow_V = TV_R(0.0);
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &c), TV_OK);
}

static void test_winding_resistance_rule(void)
{
    /* R = 4.3: above 1.35 R = 5.805 fails P2101, below 0.65 R = 2.795 fails P1A01; not run with
     * the bridge off, under 0.4 A, or with sigma above 0.05 R = 0.215 ohm */
    static diag_t d;
    diag_detect_t dd;
    diag_detect_config_t c;
    diag_snapshot_t sn = snap_at(1u);
    unsigned k;
    fresh_detectors(&d, &dd, &c);
    for (k = 0; k < 199u; ++k) {
        diag_resistance_check(&dd, &d, 1, TV_R(1.0), TV_R(5.81), TV_R(0.05), TV_R(4.3), 0, &sn);
    }
    diag_resistance_check(&dd, &d, 0, TV_R(1.0), TV_R(9.0), TV_R(0.05), TV_R(4.3), 0, &sn);
    diag_resistance_check(&dd, &d, 1, TV_R(0.39), TV_R(9.0), TV_R(0.05), TV_R(4.3), 0, &sn);
    diag_resistance_check(&dd, &d, 1, TV_R(1.0), TV_R(9.0), TV_R(0.22), TV_R(4.3), 0, &sn);
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P2101), 0);
    diag_resistance_check(&dd, &d, 1, TV_R(-1.0), TV_R(5.81), TV_R(0.05), TV_R(4.3), 0, &sn);
    TV_CHECK_EQ_INT(diag_confirmed(&d, DIAG_DTC_P2101), 1);
    TV_CHECK_NEAR(d.code[DIAG_DTC_P2101].freeze.value, 5.81 / 4.3, 1e-6);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P1A01) + diag_confirmed(&d, DIAG_DTC_P1A01), 0);
    TV_CHECK_EQ_INT(diag_action(&d), DIAG_ACTION_NONE); /* P2101 is recorded only */
    fresh_detectors(&d, &dd, &c);
    diag_resistance_check(&dd, &d, 1, TV_R(1.0), TV_R(2.79), TV_R(0.05), TV_R(4.3), 0, &sn);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P1A01), 1);
    fresh_detectors(&d, &dd, &c);
    diag_resistance_check(&dd, &d, 1, TV_R(1.0), TV_R(2.80), TV_R(0.05), TV_R(4.3), 0, &sn);
    diag_resistance_check(&dd, &d, 1, TV_R(1.0), TV_R(5.80), TV_R(0.05), TV_R(4.3), 0, &sn);
    TV_CHECK_EQ_INT(diag_pending(&d, DIAG_DTC_P1A01) + diag_pending(&d, DIAG_DTC_P2101), 0);
}

/* 200 checks at (R + dR) / R = ratio; returns P2101's state after them: 2 confirmed, 1 pending, 0 neither */
static int p2101_after(int identified, int temp_known, double ratio)
{
    static diag_t d;
    diag_detect_t dd;
    diag_detect_config_t c;
    diag_snapshot_t sn = snap_at(1u);
    unsigned k;
    diag_init(&d);
    diag_detect_config_default(&c);
    if (identified) {
        diag_detect_config_identified(&c);
    }
    TV_CHECK_EQ_INT(diag_detect_init(&dd, &c), TV_OK);
    for (k = 0; k < 200u; ++k) {
        diag_resistance_check(&dd, &d, 1, TV_R(1.0), (tv_real_t)ratio * TV_R(4.3), TV_R(0.05), TV_R(4.3), temp_known, &sn);
    }
    return diag_confirmed(&d, DIAG_DTC_P2101) ? 2 : diag_pending(&d, DIAG_DTC_P2101);
}

static void test_winding_resistance_bound_with_a_known_temperature(void)
{
    /* the class's units: 1.35 with or without the temperature */
    TV_CHECK_EQ_INT(p2101_after(0, 1, 1.34), 0);
    TV_CHECK_EQ_INT(p2101_after(0, 1, 1.36), 2);
    TV_CHECK_EQ_INT(p2101_after(0, 0, 1.36), 2);
    /* an identified unit: 1.15 only while the temperature is known (a warm winding's +27 % at
     * 90 degC reads as a drift otherwise) */
    TV_CHECK_EQ_INT(p2101_after(1, 1, 1.14), 0);
    TV_CHECK_EQ_INT(p2101_after(1, 1, 1.16), 2);
    TV_CHECK_EQ_INT(p2101_after(1, 0, 1.30), 0);
    TV_CHECK_EQ_INT(p2101_after(1, 0, 1.36), 2);
    {
        /* the bound is validated like the others */
        diag_detect_config_t c;
        diag_detect_t dd;
        diag_detect_config_default(&c);
        c.r_high_frac_known = TV_R(1.0);
        TV_CHECK_EQ_INT(diag_detect_init(&dd, &c), TV_ERR_CONFIG);
    }
}

int main(void)
{
    TV_TEST_RUN(test_table_is_complete);
    TV_TEST_RUN(test_confirms_at_exactly_the_documented_failing_sample);
    TV_TEST_RUN(test_leaky_counter_confirms_late_and_forgets);
    TV_TEST_RUN(test_heals_after_exactly_heal_count_passes);
    TV_TEST_RUN(test_queue_overflow_is_counted);
    TV_TEST_RUN(test_vote_names_the_track_away_from_the_prediction);
    TV_TEST_RUN(test_jam_and_open_winding_rules);
    TV_TEST_RUN(test_winding_resistance_rule);
    TV_TEST_RUN(test_winding_resistance_bound_with_a_known_temperature);
    return tv_test_summary();
}
