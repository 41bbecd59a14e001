/**
 * @file sim_fault_cond.h
 * @brief When an injected fault first becomes observable in the way issue 12's targets phrase it,
 *        found in the plant's truth (a row callback of sim_run()).
 *
 * Three targets count their delay from a condition, not from the onset:
 *   - jam ("jam or stuck plate, >= 0.035 rad from target: confirmed <= 100 ms"): the jammed plate
 *     is first STALLED >= SIM_COND_JAM_ERR_RAD from its target: the bridge drives, the plate moved
 *     < SIM_COND_STILL_RAD over SIM_COND_STILL_N samples, and the target is that far away
 *     (closed loop: the target clamped SIM_COND_STOP_MARGIN_RAD inside the plant's stops, as the
 *     application clamps it inside the learned ones; open loop, which has no target: the stop the
 *     voltage pushes toward, counted only while the voltage exceeds the healthy unit's own
 *     breakaway in that direction, Ms plus the springs where they oppose, so that a healthy plate
 *     would move), the stall lasting SIM_COND_STALL_S or until a code is confirmed during it;
 *     the condition's time is the stall's start (tools/jam_runs.py applies the same rule to traces);
 *   - winding_open ("open winding: <= 10 ms"): the first sample at or after the onset at which the
 *     bridge applies |u| >= SIM_COND_OPEN_V and the back-EMF leaves |u - n Ke w| >= SIM_COND_OPEN_V
 *     across the winding (w the plant's true velocity: a healthy winding would carry at least
 *     3 V / R). A winding that only the back-EMF would drive (the plate swept by its spring with the
 *     bridge near 0 V) does not count: the detector (P2100) asks for both as well, since a velocity
 *     estimate that is off against a stop could make a small voltage look large.
 *   - spring_weak ("spring break during normal operation: <= 300 ms"): the first sample at or after
 *     the onset at which the bridge drives (a spring that breaks while the bridge is off, the
 *     plate resting at limp-home, changes nothing until the actuator operates again; with the
 *     bridge on at the onset the condition is the onset).
 *   - supply_sag (P0562, "system voltage low"): the first sample at or after the onset at which the
 *     plant's bridge supply is below SIM_COND_SUPPLY_LOW_V, the level the code is specified for
 *     (README, code table). A sag on a unit whose supply stays at or above it (a 2 V sag from
 *     14 V) leaves a healthy supply: no code is due. Issue 12 sets no delay target for it.
 * Other fault kinds have no such condition (their delay counts from the onset).
 */
#ifndef SIM_FAULT_COND_H
#define SIM_FAULT_COND_H

#include "plant.h"
#include "plant_fault.h"
#include "sim.h"

#define SIM_COND_JAM_ERR_RAD 0.035    /**< target error of a stalled jammed plate [rad] */
#define SIM_COND_STOP_MARGIN_RAD 0.05 /**< closed-loop target clamp inside the stops [rad] */
#define SIM_COND_STILL_RAD 5e-4       /**< motion below which the plate is still [rad] ... */
#define SIM_COND_STILL_N 8u           /**< ... over this many samples */
#define SIM_COND_STALL_S 0.1          /**< a stall lasts this long, or until a code confirms [s] */
#define SIM_COND_OPEN_V 3.0           /**< voltage across an open winding that marks its condition [V] */
#define SIM_COND_SUPPLY_LOW_V 11.5    /**< bridge supply below which P0562 is due [V] (diag_detect_t's supply_low_V default) */

/** Tracker state (caller-owned; sim_cond_init() before the run). */
typedef struct {
    plant_config_t pc;           /**< the healthy unit (stops, friction, springs, motor) */
    plant_fault_kind_t kind;     /**< the tracked fault (PLANT_FAULT_KIND_COUNT: none) */
    double onset_s;              /**< its onset [s] */
    double phi[SIM_COND_STILL_N + 1u]; /**< the last true angles (ring) [rad] */
    unsigned n;                  /**< angles seen */
    double seg_start_s;          /**< start of the stall being timed (NaN: none) [s] */
    uint32_t dtc_prev;           /**< codes confirmed at the previous row */
    double t_s;                  /**< the condition's time (NaN: not met) [s] */
} sim_cond_t;

/**
 * Set up for one run: the first fault of faults that has a condition (jam, winding_open,
 * spring_weak, supply_sag) is tracked; none (or faults NULL): sim_cond_time() stays NaN.
 * @param pc the unit's healthy plant configuration (not NULL)
 */
void sim_cond_init(sim_cond_t *c, const plant_config_t *pc, const plant_fault_list_t *faults);

/** sim_run() row callback (sim_options_t::row_fn, row_user = the sim_cond_t). */
void sim_cond_row(const sim_row_t *row, void *user);

/** The condition's time [s] (the run's clock, as the codes' times), NaN if never met. */
double sim_cond_time(const sim_cond_t *c);

#endif /* SIM_FAULT_COND_H */
