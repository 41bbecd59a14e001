/**
 * @file stop_learn.h
 * @brief Start-up stop learning: where the plate rests against each hard stop, as ECUs learn it.
 *
 * The estimator's model puts the stops at fixed angles; a real unit's stops sit a few
 * hundredths of a radian elsewhere, and a model stop a few milliradians off makes the filter
 * worse than differentiating the angle (README "Stop contact"). This routine measures them,
 * through the position sensor alone, the way ECUs do their throttle "adaptation" at key-on and
 * end of line:
 *
 *   1. CLOSED: a position target moves from where the plate is toward the closed stop at
 *      approach_rad_s (<= 1 rad/s) and on past it by overshoot_rad, never leading the plate by
 *      more than lead_rad; a PID law on the measured angle alone (D on its low-passed
 *      derivative: the estimator, whose stops are what is being learned, is not used; the
 *      model's spring and back-EMF as feed-forward) follows it with |u| <= push_V, so the plate
 *      reaches the stop no faster than the target moves, and a plate held by friction is broken
 *      away by the integral, not by a jump of the target.
 *   2. When the plate has been still for one block (block_ms samples spread less than
 *      still_rad) with the full push_V toward the stop throughout, it is pressed against the
 *      stop (or jammed: the plausibility windows tell); the push is lowered to hold_Nm of net
 *      torque (spring included, from the model) to keep the penetration of a soft stop small,
 *      and after one block to settle the next still block's mean measured angle is the learned
 *      stop.
 *   3. OPEN: the same toward the open stop from there.
 *   4. DONE (0 V): the springs return the plate to limp-home.
 *
 * Every phase has a timeout (timeout_s); a learned angle outside its plausibility window, or a
 * travel (open - closed) outside its window, ends the routine with an error and learns nothing.
 * The module is pure (no hardware, no globals, no heap, bounded work per step): the application
 * (APP_MODE_STOP_LEARN, app.h) feeds it every sample and applies its voltage.
 *
 * Persistence: sl_nvm_t is the unit's record an ECU keeps in non-volatile memory (magic,
 * version, the two angles, the voltage equation fit's per-unit baseline, CRC-32); sl_nvm_pack()
 * / sl_nvm_unpack() write and validate it (below: how an ECU uses it). Hosts and the Linux
 * controller write the angles as model.phi_closed_rad / model.phi_open_rad and the baseline as
 * diag.fit_base_r_ohm / diag.fit_base_nke_V_s in a parameter file instead.
 */
#ifndef STOP_LEARN_H
#define STOP_LEARN_H

#include <stdint.h>

#include "tv_model.h"
#include "tv_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest block length [samples] (bounds the work of a step: none, a block is O(1) per sample). */
#define SL_BLOCK_MAX 1000u

/** Net-torque levels at which each stop's rest angle is measured (the last one is hold_Nm). */
#define SL_LEVELS 4u

/** Exponents the joint fit tries: e_min + j (e_max - e_min) / (SL_EXP_GRID - 1), j < SL_EXP_GRID. */
#define SL_EXP_GRID 21u
/** Exponents of the grid the routine fits per period once both stops are measured: the joint fit
 *  (about 1,650 Cortex-M4F instructions per exponent, firmware_report) is spread over
 *  ceil(SL_EXP_GRID / SL_FIT_PER_STEP) periods so that no step exceeds the control budget. */
#define SL_FIT_PER_STEP 3u

/** Penetration at which the stiffness bounds k_min, k_max are secant stiffnesses [rad]. */
#define SL_P_REF_RAD TV_R(0.0025)

/** Phases. */
typedef enum {
    SL_IDLE = 0,     /**< not started */
    SL_CLOSED = 1,   /**< seeking and measuring the closed stop */
    SL_OPEN = 2,     /**< seeking and measuring the open stop */
    SL_DONE = 3,     /**< both learned and plausible (result valid) */
    SL_FAILED = 4    /**< timeout or implausible result (sl_t::error says which) */
} sl_phase_t;

/** Why the routine failed. */
typedef enum {
    SL_ERR_NONE = 0,
    SL_ERR_TIMEOUT_CLOSED = 1,   /**< the plate did not come to rest at the closed stop in time */
    SL_ERR_TIMEOUT_OPEN = 2,     /**< ... at the open stop */
    SL_ERR_IMPLAUSIBLE_CLOSED = 3, /**< closed-stop angle outside [closed_min_rad, closed_max_rad] */
    SL_ERR_IMPLAUSIBLE_OPEN = 4,   /**< open-stop angle outside [open_min_rad, open_max_rad] */
    SL_ERR_IMPLAUSIBLE_TRAVEL = 5, /**< open - closed outside [travel_min_rad, travel_max_rad] */
    SL_ERR_INPUT = 6               /**< a non-finite angle, velocity or supply was fed */
} sl_error_t;

/** Configuration (units in the names). sl_config_default() gives the documented defaults. */
typedef struct {
    tv_real_t approach_rad_s;  /**< target speed toward a stop, (0, 1]; default 0.5 */
    tv_real_t overshoot_rad;   /**< the target goes this far beyond the model's stop, > 0; default 0.15 */
    tv_real_t push_V;          /**< |u| limit while seeking, > 0; default 6 */
    tv_real_t hold_Nm;         /**< net torque into the stop while measuring, >= 0; default 0.15 */
    tv_real_t kp_V_rad;        /**< proportional gain on the measured angle error, > 0; default 40 */
    tv_real_t kd_V_s_rad;      /**< derivative gain on the low-passed differentiated angle, >= 0; default 1 */
    tv_real_t still_rad;       /**< max spread of a still block, > 0; default 0.002 */
    tv_real_t lead_rad;        /**< the target leads the plate by at most this, > 0; default 0.03 */
    tv_real_t ki_V_rad_s;      /**< integral gain on the angle error, >= 0; default 200 */
    uint32_t block_ms;         /**< samples per block, 10..SL_BLOCK_MAX; default 100 */
    tv_real_t timeout_s;       /**< per phase, > 0; default 8 */
    tv_real_t closed_min_rad, closed_max_rad; /**< plausible closed stop; default -0.30 .. -0.02 (limp-home, 0, is not a stop) */
    tv_real_t open_min_rad, open_max_rad;     /**< plausible open stop; default 1.10 .. 1.70 */
    tv_real_t travel_min_rad, travel_max_rad; /**< plausible open - closed; default 1.20 .. 1.80 */
    /* the contact law (README "Stop contact"): rest angles at SL_LEVELS net torques, highest
     * first, the plate shaken free of stiction by a square dither before each measurement */
    tv_real_t level_Nm[SL_LEVELS - 1u]; /**< the levels above hold_Nm, descending, > hold_Nm; default 1.2, 0.6, 0.3
                                              (a decade up to about the stall torque of open-loop 10 V: the
                                              law is learned over the forces the stops see in service) */
    tv_real_t dither_Nm;       /**< square torque dither while settling at a level, >= 0; default 0.3 (~ stiction) */
    uint32_t dither_half_ms;   /**< dither half period [samples], >= 1; default 5 (100 Hz) */
    tv_real_t e_min, e_max;    /**< range of the Hunt-Crossley exponent the joint fit searches, 1 <= e_min <= e_max <= 3;
                                    default 1.0 .. 2.0 (e_min = e_max: the exponent is fixed) */
    tv_real_t k_min, k_max;    /**< bounds of the fitted stiffness as a SECANT stiffness at SL_P_REF_RAD,
                                    k p_ref^(e-1) [N m/rad]; default 100 .. 1e4. k_max is also what a
                                    stop too stiff for the sensor to resolve gets, and keeps the
                                    model's contact stable at its integration step */
    tv_real_t lambda_per_k_s_rad; /**< contact damping lambda = this x k [s/rad]; default 0.16 */
    tv_real_t level_V_max;     /**< |u| limit while the plate is held against a stop at a level,
                                    >= push_V; default 10 (the plate already rests there: the
                                    level's torque moves it by the stop's penetration only) */
    tv_real_t preload_Nm;      /**< before the first level the net torque rises this far above it and
                                    falls back (a triangle over half a block), so that every level is
                                    reached by unloading, >= 0; default 0.6 (twice a typical static
                                    friction: reached by loading, a rest angle is short by about the
                                    static friction) */
} sl_config_t;

/** Routine state (caller-owned). */
typedef struct {
    sl_config_t cfg;
    tvm_params_t model;      /**< model for the feed-forward (springs, back-EMF, R, n Kt) */
    sl_phase_t phase;
    sl_error_t error;
    uint32_t n_phase;        /**< samples in this phase */
    uint8_t stage;           /**< 0 seek, 1 settle at hold, 2 measure, 3 fit the contact law */
    tv_real_t target_rad;    /**< current position target */
    tv_real_t u_hold_V;      /**< hold voltage of this stop */
    tv_real_t integ_V;       /**< integral term [V] */
    tv_real_t phi_prev;      /**< last angle [rad] */
    tv_real_t w_f;           /**< low-passed differentiated angle [rad/s] */
    uint32_t n_sat;          /**< samples of this block with the full push toward the stop */
    /* current block */
    uint32_t blk_n;
    tv_real_t blk_min, blk_max, blk_sum;
    /* results */
    tv_real_t phi_closed_rad;  /**< learned closed stop (valid in SL_OPEN, SL_DONE) */
    tv_real_t phi_open_rad;    /**< learned open stop (valid in SL_DONE) */
    uint32_t n_total;          /**< samples since sl_start() */
    /* the contact law */
    uint8_t level;             /**< level being measured at this stop, 0..SL_LEVELS-1 */
    tv_real_t contact_phi_rad; /**< mean angle of the contact block (spring feed-forward) */
    tv_real_t rest_rad[2][SL_LEVELS]; /**< rest angles [closed/open][level] [rad] */
    tv_real_t onset_closed_rad; /**< fitted contact onset, closed stop (valid in SL_DONE) */
    tv_real_t onset_open_rad;   /**< fitted contact onset, open stop (valid in SL_DONE) */
    tv_real_t k_fit[2];         /**< fitted stiffness per stop [N m/rad^e] */
    tv_real_t k_stop;           /**< the model's stiffness: geometric mean of k_fit (valid in SL_DONE) */
    tv_real_t exponent;         /**< the fitted exponent, common to both stops (valid in SL_DONE) */
    /* the joint fit in progress (stage 3): next exponent, best sum of squared residuals so far,
     * its onsets */
    uint8_t fit_g;
    tv_real_t fit_sse_best;
    tv_real_t fit_onset[2];
} sl_t;

/**
 * Fit of one stop's contact law from rest angles a[j] at net torques F[j] (j < n, n >= 2,
 * distinct F): a = a0 + dir (F / k)^(1/e) (dir = -1 closed, +1 open), least squares in
 * (a0, k^(-1/e)), k held in [k_min, k_max] (a slope the sensor cannot resolve, or of the wrong
 * sign, gives k_max) and a0 refitted for the held k. Pure; exposed for tests.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (n < 2, e outside [1, 3], bad bounds, F not > 0 or all equal).
 */
int sl_contact_fit(const tv_real_t *F_Nm, const tv_real_t *a_rad, unsigned n, tv_real_t dir, tv_real_t e,
                   tv_real_t k_min, tv_real_t k_max, tv_real_t *a0_rad, tv_real_t *k);

/**
 * Joint fit of both stops' contact laws with a common exponent: for each exponent of the grid
 * e_min .. e_max (SL_EXP_GRID values; one value when e_min = e_max), sl_contact_fit() per stop,
 * and the exponent with the smallest sum of squared residuals over both stops is kept. a[0][j]
 * are the closed stop's rest angles, a[1][j] the open stop's, at net torques F[j]. Pure, bounded
 * (SL_EXP_GRID x 2 fits); k_min, k_max are secant stiffnesses at SL_P_REF_RAD (for exponent e
 * the law's k is held in [k_min, k_max] p_ref^(1-e)). Exposed for tests.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (as sl_contact_fit(), or a bad exponent range).
 */
int sl_contact_fit_joint(const tv_real_t *F_Nm, const tv_real_t a_rad[2][SL_LEVELS], unsigned n, tv_real_t e_min,
                         tv_real_t e_max, tv_real_t k_min, tv_real_t k_max, tv_real_t onset_rad[2], tv_real_t k[2],
                         tv_real_t *e);

/** Defaults documented in sl_config_t. */
void sl_config_default(sl_config_t *cfg);

/**
 * Validate cfg and model and arm the routine (phase SL_CLOSED from the next sl_step()).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG (a value outside its documented range). On error
 *         *sl is not written.
 */
int sl_start(sl_t *sl, const sl_config_t *cfg, const tvm_params_t *model);

/**
 * One 1 ms sample of the measured angle [rad] (both tracks). Returns the voltage to apply over
 * the next period [V] (0 once DONE or FAILED). A non-finite angle fails the routine.
 */
tv_real_t sl_step(sl_t *sl, tv_real_t phi_meas_rad);

/** 1 while the routine is running (CLOSED or OPEN). */
int sl_running(const sl_t *sl);

/** Name of a phase / error, for logs. */
const char *sl_phase_name(sl_phase_t p);
const char *sl_error_name(sl_error_t e);

/**
 * The unit's non-volatile record: the learned stops and the voltage equation fit's per-unit
 * baseline (README "A per-unit baseline of the fit"). Little-endian, 32 bytes when packed:
 *
 *   offset  0  magic            u32  SL_NVM_MAGIC ("STOP")
 *           4  version          u16  SL_NVM_VERSION (2)
 *           6  reserved         u16  0
 *           8  phi_closed_rad   f32  (IEEE 754 single)
 *          12  phi_open_rad     f32
 *          16  fit_base_r_ohm   f32
 *          20  fit_base_nke_V_s f32
 *          24  n_learns         u32
 *          28  crc32            u32  CRC-32 of bytes 0..27
 *
 * Version 1 (the stops alone, 24 bytes: n_learns at 16, the CRC-32 of bytes 0..19 at 20) is
 * still read, so a unit in the field keeps its stops; its baseline reads as none (0, 0).
 *
 * How an ECU uses it:
 *   - at start, sl_nvm_unpack() the stored bytes; on TV_OK put the baseline into use by setting
 *     cfg.diag.fit_base_r_ohm / fit_base_nke_V_s to the record's before app_init() (app_init()
 *     takes the configuration's baseline as the one in force, app.c; both 0 leave none, and
 *     with diag.fit_base_windows > 0 the application then learns one), and the stops by
 *     app_set_stops() after it. On TV_ERR_FORMAT keep the configuration's (the model's stops,
 *     no baseline) and write a fresh record once there is something to store.
 *   - write the record (stops and baseline in use, n_learns counted, version SL_NVM_VERSION)
 *     when app_output_t::fit_base_state turns APP_FIT_BASE_IN_FORCE with a baseline
 *     (app_output_t::fit_base_r_ohm, fit_base_nke_V_s, compared as these floats) other than the
 *     stored one, and after a stop learning that succeeded; a version-1 record is rewritten as
 *     version 2 then. (The ECU image of this release does not write flash: a tester reads the
 *     baseline off TV_HEALTH_5 and the stops off TV_HEALTH_2.)
 */
typedef struct {
    uint32_t magic;          /**< SL_NVM_MAGIC */
    uint16_t version;        /**< SL_NVM_VERSION; sl_nvm_unpack() reports the record's (1 for an old one) */
    uint16_t reserved;       /**< 0 */
    float phi_closed_rad;    /**< learned closed stop [rad] */
    float phi_open_rad;      /**< learned open stop [rad] */
    float fit_base_r_ohm;    /**< the fit's per-unit baseline: R at 20 degC [ohm]; 0 = none (both or neither) */
    float fit_base_nke_V_s;  /**< its n Ke at the plate [V s/rad]; 0 = none */
    uint32_t n_learns;       /**< learns since the record was created */
    uint32_t crc32;          /**< CRC-32 (IEEE 802.3) of the 28 bytes before it (version 1: of 20) */
} sl_nvm_t;

#define SL_NVM_MAGIC 0x53544F50u /* "STOP" */
#define SL_NVM_VERSION 2u
#define SL_NVM_BYTES 32u
/** A version-1 record's length [bytes] (no baseline; its CRC at offset 20). */
#define SL_NVM_V1_BYTES 24u
/** The baseline a record may hold: both 0 (none), or R in (0, SL_NVM_FIT_BASE_R_MAX_OHM] and
 *  n Ke in (0, SL_NVM_FIT_BASE_NKE_MAX_V_S], the ranges of the parameter files and the Linux
 *  configuration (diag.fit_base_r_ohm, diag.fit_base_nke_V_s). stop_learn knows no model: the
 *  application's +-30 % / +-15 % of the model's (APP_FIT_BASE_R_BAND, _K_BAND) apply to a
 *  learned baseline, not to a stored one. */
#define SL_NVM_FIT_BASE_R_MAX_OHM 1000.0f
#define SL_NVM_FIT_BASE_NKE_MAX_V_S 100.0f

/** CRC-32 (IEEE 802.3, reflected, init and final xor 0xFFFFFFFF) of n bytes: rawlog_crc32(), the
 *  log format's CRC, from the start value 0. */
uint32_t sl_crc32(const uint8_t *data, uint32_t n);

/** Pack rec into buf[SL_NVM_BYTES] (little-endian, the version-2 layout; magic and version as
 *  rec has them), computing its CRC. Nothing is validated. TV_OK or TV_ERR_NULL. */
int sl_nvm_pack(const sl_nvm_t *rec, uint8_t buf[SL_NVM_BYTES]);

/**
 * Unpack and validate buf: magic, version (2, or 1: its 24-byte layout, only buf[0..23] read,
 * the rest of the buffer, erased flash or anything, ignored; the baseline then 0, 0), CRC,
 * angles finite and inside the default plausibility windows, the baseline both 0 or both
 * finite, > 0 and within SL_NVM_FIT_BASE_R_MAX_OHM / SL_NVM_FIT_BASE_NKE_MAX_V_S.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_FORMAT (any check failed: *rec is not written, the caller
 *         keeps its model's stops and no baseline).
 */
int sl_nvm_unpack(const uint8_t buf[SL_NVM_BYTES], sl_nvm_t *rec);

#ifdef __cplusplus
}
#endif

#endif /* STOP_LEARN_H */
