/**
 * @file diag.c
 * @brief Diagnostic trouble codes: table, leaky-counter state machine, freeze frame, event queue
 *        (see diag.h).
 */
#include "diag.h"

#include <stddef.h>
#include <string.h>

#include "tv_status.h"

/* The code table (README "Diagnostic codes" documents the detection of each). Confirmation
 * times at 1 kHz: P0121 / P0221 / P2135 20 ms (inside the 50 ms target for a track offset),
 * P2111 / P2112 50 ms (inside the 100 ms jam target, and 25x the 2 ms a healthy plate needs to
 * move after a max-slew step), P2100 5 ms (inside the 10 ms open-winding target), P2101 / P1A01
 * 200 ms (the estimated resistance is a slow, filtered quantity). Healing: 1 s of consecutive
 * passes. P2119 / P1A02 are checked every DIAG_PARAM_DECIM steps (10 ms, diag_detect.h) and
 * only while the plate moves: their counts are checks. They confirm after 10 / 3 failed checks
 * (100 / 30 ms of motion): the torque signature behind them is already an average over some 50
 * fed samples, and the slowly adapted levels fail only after param_slow_hold checks in a row
 * (diag_detect.h); 100 passed checks heal. P1A02's 3 (5 before): no healthy run of the fault
 * matrix's soak (2,430 x 70 s) ever failed one check of it, and an ambiguous signature (its
 * friction also high) fails only from its 3rd check in a row, so 5 checks as before. P1A03
 * 10 ms (failing checks need a current under a lost direction, a discriminating sample; 1 s to
 * heal). P0562 is checked every DIAG_SUPPLY_DECIM steps (10 ms):
 * 50 checks = 500 ms below the threshold confirm, 100 checks (1 s) above it heal. P0122 / P0222
 * count low samples (a failed check each) and pass once per fixed DIAG_TPS_CLEAN_WINDOW (500 ms)
 * without one: 5 dropouts confirm unless clean windows come between them (a steady 0 V in 5 ms,
 * as the range check's latch), 2 clean windows (1-1.5 s) heal. */
static const diag_dtc_info_t s_dtc[DIAG_DTC_COUNT] = {
    {"P0121", "tps1_fault", "throttle position sensor 1 range/performance (track 1 named by the estimator's vote)", 20u, 1000u,
     DIAG_ACTION_LIMITED},
    {"P0221", "tps2_fault", "throttle position sensor 2 range/performance (track 2 named by the estimator's vote)", 20u, 1000u,
     DIAG_ACTION_LIMITED},
    {"P2135", "tps_correlation", "throttle position sensor 1/2 correlation (neither track agrees with the estimator)", 20u, 1000u,
     DIAG_ACTION_SAFE},
    {"P2111", "jam", "throttle actuator stuck open (commanded to close, the plate does not move)", 50u, 1000u,
     DIAG_ACTION_SAFE},
    {"P2112", "jam", "throttle actuator stuck closed (commanded to open, the plate does not move)", 50u, 1000u,
     DIAG_ACTION_SAFE},
    {"P2100", "winding_open", "throttle actuator motor circuit open (no current under a large voltage)", 5u, 1000u,
     DIAG_ACTION_SAFE},
    {"P2101", "winding_resistance_high", "throttle actuator motor circuit range/performance (winding resistance above its range)",
     200u, 1000u, DIAG_ACTION_NONE},
    /* P1A01: the resistance check fails it per sample (200 ms); the motor-constant signature
     * (identified units) at each 10 ms check (2 s) */
    {"P1A01", "winding_short", "winding resistance below its range (shorted turns suspected; project code)", 200u, 1000u,
     DIAG_ACTION_LIMITED},
    {"P2119", "friction_high", "throttle actuator control throttle body range/performance (friction level above its range)",
     10u, 100u, DIAG_ACTION_NONE},
    {"P1A02", "spring_weak", "return-spring preload below its range (limp-home position not assured; project code)", 3u, 100u,
     DIAG_ACTION_LIMITED},
    {"P1A03", "bridge_fault", "H-bridge: one drive direction lost (current flows, the terminals see no voltage; project code)", 10u,
     1000u, DIAG_ACTION_SAFE},
    {"P0562", "supply_sag", "system voltage low (measured supply below its threshold)", 50u, 100u, DIAG_ACTION_NONE},
    {"P0122", "tps1_fault", "throttle position sensor 1 circuit low (track below its range, intermittent dropouts included)", 5u, 2u,
     DIAG_ACTION_LIMITED},
    {"P0222", "tps2_fault", "throttle position sensor 2 circuit low (track below its range, intermittent dropouts included)", 5u, 2u,
     DIAG_ACTION_LIMITED},
    /* P1A04: each check is one window (DIAG_ISENS_ZERO_N samples at rest or DIAG_ISENS_WIN driven
     * samples, diag_detect.h): 6 failing windows confirm (192 ms at rest, 3,000 samples at small
     * currents in service), 8 passing ones heal; the motor-constant signature (a gain error, on
     * identified units) fails it at each 10 ms check: 60 ms */
    {"P1A04", "current_sensor_fault", "motor current sensor range/performance (offset or gain; project code)", 6u, 8u,
     DIAG_ACTION_NONE},
};

const diag_dtc_info_t *diag_dtc_info(diag_dtc_t dtc)
{
    return (unsigned)dtc < (unsigned)DIAG_DTC_COUNT ? &s_dtc[dtc] : NULL;
}

const char *diag_event_name(diag_event_kind_t kind)
{
    switch (kind) {
    case DIAG_EV_PENDING:
        return "pending";
    case DIAG_EV_CONFIRMED:
        return "confirmed";
    case DIAG_EV_HEALED:
        return "healed";
    default:
        return "?";
    }
}

void diag_init(diag_t *d)
{
    if (d != NULL) {
        memset(d, 0, sizeof *d);
        d->last_confirmed = (uint8_t)DIAG_DTC_COUNT;
    }
}

/* Append an event; a full queue drops it and counts the loss. */
static void diag_push(diag_t *d, uint64_t t_us, diag_dtc_t dtc, diag_event_kind_t kind)
{
    diag_event_t *e;
    if (d->q_count >= DIAG_EVENT_QUEUE_LEN) {
        if (d->events_lost < 0xFFFFFFFFu) {
            ++d->events_lost;
        }
        return;
    }
    e = &d->queue[(d->q_head + d->q_count) % DIAG_EVENT_QUEUE_LEN];
    e->t_us = t_us;
    e->dtc = dtc;
    e->kind = kind;
    ++d->q_count;
}

int diag_report(diag_t *d, diag_dtc_t dtc, diag_result_t res, const diag_snapshot_t *snap, tv_real_t value)
{
    const diag_dtc_info_t *info;
    diag_code_state_t *c;
    uint64_t t_us;
    if (d == NULL) {
        return TV_ERR_NULL;
    }
    if ((unsigned)dtc >= (unsigned)DIAG_DTC_COUNT || (res != DIAG_NOT_RUN && res != DIAG_PASS && res != DIAG_FAIL)) {
        return TV_ERR_RANGE;
    }
    if (res == DIAG_FAIL && snap == NULL) {
        return TV_ERR_NULL;
    }
    if (res == DIAG_NOT_RUN) {
        return TV_OK;
    }
    info = &s_dtc[dtc];
    c = &d->code[dtc];
    t_us = snap != NULL ? snap->t_us : 0u;
    if (c->confirmed) {
        if (res == DIAG_FAIL) {
            c->passes = 0u;
        } else if (++c->passes >= info->heal_count) {
            c->confirmed = 0u;
            c->counter = 0u;
            c->passes = 0u;
            diag_push(d, t_us, dtc, DIAG_EV_HEALED);
        }
        return TV_OK;
    }
    if (res == DIAG_PASS) {
        if (c->counter > 0u) {
            --c->counter;
        }
        return TV_OK;
    }
    /* a failed check while not confirmed */
    if (c->counter == 0u) {
        diag_push(d, t_us, dtc, DIAG_EV_PENDING);
    }
    if (c->counter < info->confirm_count) {
        ++c->counter;
    }
    if (c->counter >= info->confirm_count) {
        c->confirmed = 1u;
        c->passes = 0u;
        {
            int a;
            c->freeze.t_us = snap->t_us;
            for (a = 0; a < TVM_NX; ++a) {
                c->freeze.x[a] = snap->x[a];
                c->freeze.sigma[a] = snap->var[a] > TV_R(0.0) ? TV_SQRT(snap->var[a]) : TV_R(0.0);
            }
            c->freeze.r_est_ohm = snap->r_est_ohm;
            c->freeze.supply_V = snap->supply_V;
            c->freeze.duty = snap->duty;
            c->freeze.value = value;
        }
        c->has_freeze = 1u;
        d->last_confirmed = (uint8_t)dtc;
        if (c->confirmations < 0xFFFFFFFFu) {
            ++c->confirmations;
        }
        diag_push(d, t_us, dtc, DIAG_EV_CONFIRMED);
    }
    return TV_OK;
}

int diag_confirmed(const diag_t *d, diag_dtc_t dtc)
{
    return d != NULL && (unsigned)dtc < (unsigned)DIAG_DTC_COUNT && d->code[dtc].confirmed != 0u;
}

int diag_pending(const diag_t *d, diag_dtc_t dtc)
{
    return d != NULL && (unsigned)dtc < (unsigned)DIAG_DTC_COUNT && !d->code[dtc].confirmed && d->code[dtc].counter > 0u;
}

diag_action_t diag_summary(const diag_t *d, uint32_t *confirmed)
{
    diag_action_t a = DIAG_ACTION_NONE;
    uint32_t mask = 0u;
    if (d != NULL) {
        int k;
        for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
            if (d->code[k].confirmed) {
                mask |= 1u << k;
                if (s_dtc[k].action > a) {
                    a = s_dtc[k].action;
                }
            }
        }
    }
    if (confirmed != NULL) {
        *confirmed = mask;
    }
    return a;
}

diag_action_t diag_action(const diag_t *d)
{
    return diag_summary(d, NULL);
}

int diag_event_pop(diag_t *d, diag_event_t *ev)
{
    if (d == NULL || ev == NULL || d->q_count == 0u) {
        return 0;
    }
    *ev = d->queue[d->q_head];
    d->q_head = (d->q_head + 1u) % DIAG_EVENT_QUEUE_LEN;
    --d->q_count;
    return 1;
}

void diag_clear(diag_t *d)
{
    int k;
    if (d == NULL) {
        return;
    }
    for (k = 0; k < (int)DIAG_DTC_COUNT; ++k) {
        d->code[k].counter = 0u;
        d->code[k].passes = 0u;
        d->code[k].confirmed = 0u;
    }
}
