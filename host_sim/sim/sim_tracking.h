/**
 * @file sim_tracking.h
 * @brief Tracking figures of a closed-loop run, computed as the samples stream by: for every
 *        step of the target (a change larger than SIM_TRK_STEP_MIN_RAD) the overshoot, the
 *        settling time and the steady-state error of the plate angle; over the whole run the RMS
 *        tracking error. Pure: fed (t, target, angle) by the run loop, no other state.
 *
 * Definitions, per step from the previous target r0 (the plate's angle for the first target) to
 * r1 (size A = |r1 - r0|), over the segment until the target moves again (a next step, or the
 * start of a ramp) or the run ends:
 *   overshoot [%]       max over the segment of (phi - r1) sign(r1 - r0), as % of A (0 if never past r1);
 *   settling time [s]   from the step to the last sample outside the band |phi - r1| <= max(2 % of
 *                       A, SIM_TRK_BAND_MIN_RAD); the segment length when it never settles;
 *   steady-state error  mean |phi - r1| over the last SIM_TRK_SS_SAMPLES samples of the segment [rad].
 */
#ifndef SIM_TRACKING_H
#define SIM_TRACKING_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SIM_TRK_STEP_MIN_RAD 0.01 /**< a target change larger than this is a step [rad] */
#define SIM_TRK_BAND_MIN_RAD 0.005 /**< narrowest settling band [rad] (~10 ADC counts) */
#define SIM_TRK_SS_SAMPLES 100     /**< samples of the steady-state average (100 ms at 1 kHz) */
#define SIM_TRK_MAX_STEPS 64       /**< steps kept; later ones are counted in the worst figures only */

/** One step's figures. */
typedef struct {
    double t_step_s;        /**< time of the step [s] */
    double from_rad, to_rad; /**< target before and after [rad] */
    double overshoot_pct;   /**< overshoot [% of the step] */
    double settling_s;      /**< settling time [s] */
    double settled;         /**< 1 when it settled within the segment */
    double ss_error_rad;    /**< steady-state error [rad] */
} sim_trk_step_t;

/** Streaming state and results. */
typedef struct {
    uint32_t n_steps;                       /**< steps seen */
    sim_trk_step_t step[SIM_TRK_MAX_STEPS]; /**< the first SIM_TRK_MAX_STEPS of them */
    double worst_overshoot_pct;             /**< over all steps */
    double worst_settling_s;
    double worst_ss_error_rad;
    double rms_error_rad;                   /**< RMS of target - angle over every sample with a target */
    /* running state */
    int active;             /**< a segment is open */
    double r0, r1, t_step, t_last, t_out, max_over, band;
    double ring[SIM_TRK_SS_SAMPLES];
    uint32_t ring_n;
    double sse;
    uint32_t n;
    double last_target;
    int have_target;
} sim_tracking_t;

/** Start empty. */
void sim_tracking_init(sim_tracking_t *tk);

/** One sample: time [s], target [rad] (NaN: no target, e.g. open loop), plate angle [rad]. */
void sim_tracking_add(sim_tracking_t *tk, double t_s, double target_rad, double angle_rad);

/** Close the open segment and compute the summary; call once after the last sample. */
void sim_tracking_finish(sim_tracking_t *tk);

#ifdef __cplusplus
}
#endif

#endif /* SIM_TRACKING_H */
