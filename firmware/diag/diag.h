/**
 * @file diag.h
 * @brief Diagnostic trouble codes (DTCs) as ECUs keep them: a table of codes, a per-code state
 *        machine pending -> confirmed -> healed driven by a leaky counter, a freeze frame taken
 *        at confirmation, and a bounded event queue the application drains.
 *
 * PER CODE, each 1 ms step a detector reports one result (diag_report()):
 *   DIAG_FAIL     the counter goes up by 1 (saturating at the code's confirm_count);
 *   DIAG_PASS     the counter goes down by 1 (not below 0);
 *   DIAG_NOT_RUN  the test's conditions were not met: nothing changes.
 * States:
 *   idle       counter 0, not confirmed;
 *   pending    from the first failed check (counter 0 -> 1: event DIAG_EV_PENDING) until the
 *              counter reaches confirm_count or leaks back to 0 (back to idle without an event:
 *              a pending code that does not mature is forgotten, as an ECU's pending code is at
 *              the next passed cycle);
 *   confirmed  when the counter reaches confirm_count: event DIAG_EV_CONFIRMED, freeze frame
 *              captured, the code's action in force (diag_action()). Consecutive failures confirm
 *              at exactly the confirm_count-th failing sample (confirm_count ms at 1 kHz);
 *   healed     heal_count CONSECUTIVE passed checks after confirmation: event DIAG_EV_HEALED,
 *              the code returns to idle and its action ends; the freeze frame and the count of
 *              confirmations stay (the ECU's history). A failure while confirmed restarts the
 *              count of passes.
 *
 * EVENTS go into a ring of DIAG_EVENT_QUEUE_LEN; when it is full the new event is dropped and
 * counted (diag_t::events_lost, never lost silently). diag_event_pop() drains it.
 *
 * Pure C99: no heap, no globals (the code table is a constant), fixed cost per call; the scalar
 * type is the estimator's (float build diag_f32, double build diag_f64).
 */
#ifndef DIAG_H
#define DIAG_H

#include <stdint.h>

#include "tv_model.h"
#include "tv_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Capacity of the event queue [events]. */
#define DIAG_EVENT_QUEUE_LEN 16u

/** The codes this firmware keeps (rows of the table, diag_dtc_info()). */
typedef enum {
    DIAG_DTC_P0121 = 0, /**< throttle position sensor 1 (A) range/performance: track 1 named faulty by the vote */
    DIAG_DTC_P0221,     /**< throttle position sensor 2 (B) range/performance: track 2 named faulty */
    DIAG_DTC_P2135,     /**< TPS 1/2 voltage correlation: the tracks disagree and neither agrees with the estimator */
    DIAG_DTC_P2111,     /**< throttle actuator stuck open: commanded to close, the plate does not move */
    DIAG_DTC_P2112,     /**< throttle actuator stuck closed: commanded to open, the plate does not move */
    DIAG_DTC_P2100,     /**< throttle actuator motor circuit open: no current under a large voltage */
    DIAG_DTC_P2101,     /**< throttle actuator motor circuit range/performance: winding resistance above its range */
    DIAG_DTC_P1A01,     /**< project code: winding resistance below its range (shorted turns) */
    DIAG_DTC_P2119,     /**< throttle actuator control throttle body range/performance: friction level above its range */
    DIAG_DTC_P1A02,     /**< project code: return-spring preload below its range (limp-home not assured) */
    DIAG_DTC_P1A03 = 10, /**< project code: H-bridge, one drive direction lost (current, but no voltage at the terminals) */
    DIAG_DTC_P0562 = 11, /**< system voltage low: the measured supply below its threshold */
    DIAG_DTC_P0122 = 12, /**< throttle position sensor 1 (A) circuit low, including intermittent dropouts */
    DIAG_DTC_P0222 = 13, /**< throttle position sensor 2 (B) circuit low, including intermittent dropouts */
    DIAG_DTC_P1A04 = 14, /**< project code: motor current sensor range/performance (an offset: the zero check at
                             rest and the in-service bias of the current innovation) */
    DIAG_DTC_COUNT      /**< number of codes (not a code) */
} diag_dtc_t;

/** Action of a confirmed code (ordered: the largest in force wins). */
typedef enum {
    DIAG_ACTION_NONE = 0,    /**< recorded only */
    DIAG_ACTION_LIMITED = 1, /**< limited authority: |duty| <= DIAG_LIMITED_DUTY */
    DIAG_ACTION_SAFE = 2     /**< safe state: PWM 0, bridge disabled (the springs return the plate) */
} diag_action_t;

/** Duty limit under DIAG_ACTION_LIMITED [-]. */
#define DIAG_LIMITED_DUTY TV_R(0.4)

/** Result of one check. */
typedef enum {
    DIAG_NOT_RUN = 0, /**< conditions not met: the code's state does not change */
    DIAG_PASS = 1,
    DIAG_FAIL = 2
} diag_result_t;

/** Event kinds (the CSV status column: pending, confirmed, healed). */
typedef enum {
    DIAG_EV_PENDING = 0,
    DIAG_EV_CONFIRMED = 1,
    DIAG_EV_HEALED = 2
} diag_event_kind_t;

/** One row of the code table. */
typedef struct {
    const char *code;        /**< "P0121", ... */
    const char *fault_class; /**< issue 12's fault class the code reports ("tps1_fault", "jam", ...) */
    const char *meaning;     /**< one line */
    uint16_t confirm_count;  /**< failed checks (leaky) that confirm; at 1 kHz the confirmation time in ms */
    uint16_t heal_count;     /**< consecutive passed checks that heal a confirmed code */
    diag_action_t action;    /**< what the code does while confirmed */
} diag_dtc_info_t;

/** What the application knows at a step; a confirmation freezes it (diag_freeze_t). */
typedef struct {
    uint64_t t_us;                /**< sample time [us] */
    tv_real_t x[TVM_NX];          /**< estimate (A, rad/s, rad) */
    tv_real_t var[TVM_NX];        /**< its VARIANCES (the diagonal of P; square roots are taken only at a confirmation) */
    tv_real_t r_est_ohm;          /**< winding resistance R + dR [ohm] */
    tv_real_t supply_V;           /**< measured supply [V] */
    tv_real_t duty;               /**< duty applied over the period that ended [-] */
} diag_snapshot_t;

/** Freeze frame: the snapshot of the confirming check. */
typedef struct {
    uint64_t t_us;                /**< sample time [us] */
    tv_real_t x[TVM_NX];          /**< estimate (A, rad/s, rad) */
    tv_real_t sigma[TVM_NX];      /**< its standard deviations */
    tv_real_t r_est_ohm;          /**< winding resistance R + dR [ohm] */
    tv_real_t supply_V;           /**< measured supply [V] */
    tv_real_t duty;               /**< duty applied over the period that ended [-] */
    tv_real_t value;              /**< the detector's test statistic (unit per code: the README's DTC table) */
} diag_freeze_t;

/** One event. */
typedef struct {
    uint64_t t_us;           /**< time of the check that caused it [us] */
    diag_dtc_t dtc;
    diag_event_kind_t kind;
} diag_event_t;

/** State of one code. */
typedef struct {
    uint16_t counter;        /**< leaky counter, 0..confirm_count */
    uint16_t passes;         /**< consecutive passes while confirmed */
    uint8_t confirmed;       /**< 1: confirmed (action in force) */
    uint8_t has_freeze;      /**< 1: freeze holds the last confirmation's frame */
    uint32_t confirmations;  /**< times confirmed since diag_init() */
    diag_freeze_t freeze;    /**< freeze frame of the last confirmation */
} diag_code_state_t;

/** All codes and the event queue. Allocate statically; diag_init() before use. */
typedef struct {
    diag_code_state_t code[DIAG_DTC_COUNT];
    diag_event_t queue[DIAG_EVENT_QUEUE_LEN];
    uint32_t q_head;         /**< index of the oldest event */
    uint32_t q_count;        /**< events waiting */
    uint32_t events_lost;    /**< events dropped because the queue was full */
    uint8_t last_confirmed;  /**< the code confirmed most recently (diag_dtc_t; DIAG_DTC_COUNT: none since diag_init()) */
} diag_t;

/** Row of the code table; NULL for an invalid code. */
const diag_dtc_info_t *diag_dtc_info(diag_dtc_t dtc);

/** "pending", "confirmed", "healed"; "?" if invalid. */
const char *diag_event_name(diag_event_kind_t kind);

/** Every code idle, no freeze frames, queue empty, nothing lost, no code confirmed yet
 *  (last_confirmed = DIAG_DTC_COUNT). Does nothing when d is NULL. */
void diag_init(diag_t *d);

/**
 * Report one check of a code (see the file comment for the state machine).
 * @param d     the codes
 * @param dtc   which code
 * @param res   DIAG_PASS, DIAG_FAIL or DIAG_NOT_RUN
 * @param snap  the step's snapshot (the freeze frame at confirmation); may be NULL only with
 *              DIAG_NOT_RUN or DIAG_PASS (a pass then has time 0 in its healed event)
 * @param value the detector's test statistic (kept in the freeze frame)
 * @return TV_OK; TV_ERR_NULL (d NULL, or snap NULL with DIAG_FAIL); TV_ERR_RANGE (bad dtc or
 *         res). On error nothing changes.
 */
int diag_report(diag_t *d, diag_dtc_t dtc, diag_result_t res, const diag_snapshot_t *snap, tv_real_t value);

/** 1 when the code is confirmed, else 0 (also for NULL or a bad code). */
int diag_confirmed(const diag_t *d, diag_dtc_t dtc);

/** 1 when the code is pending (counter > 0, not confirmed), else 0. */
int diag_pending(const diag_t *d, diag_dtc_t dtc);

/** The largest action of the confirmed codes (DIAG_ACTION_NONE when none, or d NULL). */
diag_action_t diag_action(const diag_t *d);

/**
 * diag_action() and the confirmed codes in one pass (the application's step).
 * @param confirmed  NULL, or receives bit (1u << dtc) of every confirmed code
 */
diag_action_t diag_summary(const diag_t *d, uint32_t *confirmed);

/**
 * Take the oldest event.
 * @return 1 and *ev written; 0 when the queue is empty or an argument is NULL.
 */
int diag_event_pop(diag_t *d, diag_event_t *ev);

/**
 * Clear every code (a tester's "clear DTCs"): confirmed codes return to idle WITHOUT a healed
 * event, counters and passes to 0; freeze frames and confirmation counts are kept; the queue is
 * not touched. Does nothing when d is NULL.
 */
void diag_clear(diag_t *d);

#ifdef __cplusplus
}
#endif

#endif /* DIAG_H */
