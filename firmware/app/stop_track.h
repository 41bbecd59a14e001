/**
 * @file stop_track.h
 * @brief Online stop tracking: the contact onsets of the estimator's stops follow the unit in
 *        service, from the rest angles of the plate held against a stop under a sustained torque
 *        (issue 11, item 2: "an online update while the plate rests against a stop under
 *        sustained torque"). Pure C99, no heap, no globals; float and double builds.
 *
 * The start-up routine (stop_learn.h) learns each stop's contact onset a0 and its contact law
 * (k, e): a plate pressed into the stop by a net torque P rests at a0 + s (P / k)^(1/e) (s = -1
 * closed, +1 open; Kelvin-Voigt e = 1 with k in N m/rad). In service, a stop moves (wear of the
 * plate's seat, deposits, temperature, ice): the filter's contact then sits a few mrad off, which
 * is what broke it before the start-up learning (README "Stop contact"). The tracker watches for
 * blocks of st_config_t::block samples in which
 *   - the measured angle (both tracks, or the one left) is valid in every sample,
 *   - the plate rests: the angle's range within the block is at most rest_band_rad (and the
 *     estimated |w| stays below the loose sanity bound w_rest_rad_s),
 *   - the block's mean angle lies beyond the tracked onset, or within near_rad before it,
 *   - the mean net torque into that stop, P = s (n Kt i - M0 sp(phi) - c phi) from the estimated
 *     current and the model's springs, lies in [push_min_Nm, push_max_Nm] (a torque large enough
 *     that the static friction, unknown at rest, is a small part of it);
 * and for such a block computes the onset a = phi_mean - s (P / k)^(1/e) and moves the tracked
 * onset toward it by gain x (a - onset): a first-order low-pass over blocks, so one block's
 * friction error is averaged out. The tracked onset never leaves reference +- window_rad
 * (reference: the start-up routine's, or the stops the application was given): a block that
 * would put it outside is refused and counted (a stop that moved farther needs the start-up
 * routine again, and a fault detector should look at it).
 *
 * Cost: per sample a few comparisons and sums; per accepted block one power (exp, log).
 */
#ifndef STOP_TRACK_H
#define STOP_TRACK_H

#include <stdint.h>

#include "tv_model.h"
#include "tv_real.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Stop index: closed (below limp-home), open. */
enum { ST_CLOSED = 0, ST_OPEN = 1, ST_NSTOPS = 2 };

/** Largest block length [samples]. */
#define ST_BLOCK_MAX 1000u

/** Configuration. Units SI. */
typedef struct {
    uint8_t enable;           /**< 1: track (default); 0: the onsets stay as given */
    uint16_t block;           /**< samples per rest block, 20..ST_BLOCK_MAX; default 100 (0.1 s) */
    tv_real_t rest_band_rad;  /**< largest range of the measured angle within a rest block, > 0; default 1.5e-3 */
    tv_real_t w_rest_rad_s;   /**< |estimated w| below this in every sample of the block, > 0; default 5: a sanity
                                   bound only. The angle range is the rest test (1.5 mrad over 0.1 s is a mean
                                   speed below 0.015 rad/s); the estimate flips by +-1 rad/s against a soft stop
                                   whose rest angle under a large push the model misplaces by a mrad, which is
                                   the very error the tracker must remove (with 0.5 it refused every block of a
                                   class-b unit held against its open stop at 10 V: measured, README "Stop
                                   contact") */
    tv_real_t near_rad;       /**< the block's mean may lie this far before the onset, >= 0; default 0.01 */
    tv_real_t push_min_Nm;    /**< least mean net torque into the stop, > 0; default 0.3 */
    tv_real_t push_max_Nm;    /**< largest, > push_min_Nm; default 3 */
    tv_real_t gain;           /**< low-pass gain per accepted block, (0, 1]; default 0.2 */
    tv_real_t window_rad;     /**< the onsets stay within this of their reference, > 0; default 0.005 */
    uint8_t envelope;         /**< 1: the stop envelope runs (st_envelope()): the stops are not learned yet
                                   (the default: the class's nominal stops); 0: off. app_set_stops() (learned
                                   or stored stops) turns it off, and so must a configuration whose stops were
                                   learned (sim_apply_stop_learning(), parameter key stop_track.envelope) */
    tv_real_t env_min_rad;    /**< envelope: least distance of the measured angle beyond an onset AND beyond the
                                   estimator's prediction [rad], > 0; default 0.001 (10 x the angle noise of a
                                   12-bit track; the innovation's own sigma is NOT used: inflated by the very
                                   contact error, it kept the envelope from acting: measured) */
    tv_real_t env_window_rad; /**< while the stops were never learned (envelope on), a rest block may lie this far
                                   before an onset and move it this far from its reference (near_rad and
                                   window_rad apply to learned stops) [rad], > 0; default 0.1 (the population's
                                   stops spread 0.1 rad); also, while unlearned, a block needs neither
                                   |estimated w| < w_rest_rad_s (the estimate is what a stop the model does not
                                   know biases) nor a push below push_max_Nm */
} st_config_t;

/** Tracker state. */
typedef struct {
    st_config_t cfg;
    tv_real_t ref[ST_NSTOPS];    /**< reference onsets [rad] */
    tv_real_t onset[ST_NSTOPS];  /**< tracked onsets [rad] */
    /* the block under way */
    uint16_t n;                  /**< samples in it */
    tv_real_t phi_sum;           /**< sum of the measured angles */
    tv_real_t phi_min, phi_max;  /**< their range */
    tv_real_t push_sum[ST_NSTOPS]; /**< sum of the net torque into each stop */
    /* counters */
    uint32_t n_accepted;         /**< blocks that moved an onset */
    uint32_t n_refused;          /**< blocks at a stop that would have left the window */
    uint32_t n_envelope;         /**< samples whose measured angle pushed an onset out (st_envelope()) */
    tv_real_t start[ST_NSTOPS];  /**< the onsets given at st_reset() [rad] */
} st_t;

/** Defaults as documented at st_config_t. */
void st_config_default(st_config_t *cfg);

/** @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE; TV_ERR_CONFIG (a value outside its documented range). */
int st_config_check(const st_config_t *cfg);

/**
 * Start (or restart) from reference onsets (closed < 0 < open): tracked = reference, no block
 * under way, counters at 0.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_NONFINITE; TV_ERR_CONFIG (configuration invalid or not closed < 0 < open).
 */
int st_reset(st_t *t, const st_config_t *cfg, tv_real_t closed_rad, tv_real_t open_rad);

/**
 * One sample. model: the estimator's model (springs, n Kt, contact law k and exponent);
 * phi_valid: 0 when this sample has no usable angle (the block is abandoned); i_A and w_rad_s:
 * the estimated current and velocity. Non-finite inputs abandon the block.
 * @return 1 when a block was accepted and an onset moved (read t->onset), 0 otherwise.
 */
int st_step(st_t *t, const tvm_params_t *model, tv_real_t phi_rad, int phi_valid, tv_real_t i_A, tv_real_t w_rad_s);

/**
 * 1 when the stops were never learned (envelope on) AND the unit has shown them to be elsewhere:
 * an onset moved more than window_rad from where st_reset() put it (by the envelope or by a rest
 * block). The model's stops, and with them its contact, are then in doubt until the start-up
 * routine runs; the application holds the diagnostic checks that judge against the model's
 * mechanics (the adapted friction and preload, the open-loop jam) meanwhile. 0 otherwise, and
 * for NULL. A unit whose stops are the defaults (the nominal unit) never raises it.
 */
int st_model_in_doubt(const st_t *t);

/**
 * The stop envelope, for stops that were never learned. The plate cannot be measured far beyond
 * a stop: when the measured angle phi_meas lies more than env_min_rad beyond an onset (s (phi_meas
 * - onset) > env_min_rad, s = -1 closed, +1 open) AND beyond the estimator's predicted angle
 * phi_pred by more than env_min_rad as well (so a penetration the model's own contact law
 * predicts, at an impact, is not
 * taken for a misplaced stop), that stop is farther out than the model's, and its onset moves out
 * at once to phi_meas + s (step_rad + env_min_rad), step_rad being the plate's last measured step
 * |phi - phi_previous| (so a plate still travelling toward the real stop does not run into the
 * model's again at the next sample: each such sample puts a wrong contact torque into the
 * prediction); the tracker's reference moves with it (the rest blocks of st_step() then
 * refine it within window_rad). Outward only: a stop nearer than the model's holds the plate
 * before the model's onset, which st_step() sees within near_rad. A soft stop is left at the
 * deepest angle the plate reached in it (its impact). With learned stops it is off (a learned
 * soft law lets the plate in farther): st_config_t::envelope. This is what keeps a filter whose
 * stops were never learned from predicting the contact force of a stop the plate has already
 * passed (README "Stop contact": without it, worse than differentiating the angle on units whose
 * stops lie a few hundredths beyond the defaults).
 * @return 1 when an onset moved (read t->onset), 0 otherwise (also for invalid input or envelope off).
 */
int st_envelope(st_t *t, tv_real_t phi_meas, tv_real_t phi_pred, tv_real_t step_rad);

#ifdef __cplusplus
}
#endif

#endif /* STOP_TRACK_H */
