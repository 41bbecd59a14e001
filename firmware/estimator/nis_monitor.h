/**
 * @file nis_monitor.h
 * @brief Consistency monitor: a windowed test of the normalised innovations squared (NIS) per
 *        measurement channel, the first brick of fault detection. It says when the model no
 *        longer explains the data: a consistent filter's per-channel NIS is chi-square with one
 *        degree of freedom (mean 1), so a block of W corrections has mean 1 +- sqrt(2 / W).
 *
 * Rule (per channel, independently): the NIS of every correction that used the channel is
 * summed over blocks of `window` such corrections; a block whose mean exceeds `threshold` is a
 * failed block; `trip_blocks` failed blocks in a row raise the channel's flag, and the flag stays
 * raised until a block passes. Each raise counts one episode. With the defaults (100
 * corrections = 0.1 s at 1 kHz, threshold 10, 3 blocks) a flag means: for 0.3 s the channel's
 * innovations were on average more than 3 sigma. The flag is a report, not an action (the
 * diagnostic codes decide actions).
 *
 * No heap, no globals, fixed cost per call (three channels).
 */
#ifndef NIS_MONITOR_H
#define NIS_MONITOR_H

#include <stdint.h>

#include "ekf.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Flag bits per channel (the EKF_CH_BIT of the channel). */
#define NISM_FLAG(ch) EKF_CH_BIT(ch)
/** Longest block [corrections]. */
#define NISM_WINDOW_MAX 10000u

/** Monitor configuration. */
typedef struct {
    uint16_t window;       /**< corrections per block, 1..NISM_WINDOW_MAX (default 100) */
    tv_real_t threshold;   /**< failed block: mean NIS above this [-], > 0 (default 10) */
    uint16_t trip_blocks;  /**< failed blocks in a row that raise the flag, >= 1 (default 3) */
} nism_config_t;

/** Monitor state. */
typedef struct {
    nism_config_t cfg;
    tv_real_t sum[EKF_NCH];     /**< NIS summed over the current block */
    uint16_t n[EKF_NCH];        /**< corrections in the current block */
    uint16_t failed[EKF_NCH];   /**< failed blocks in a row */
    tv_real_t last_mean[EKF_NCH]; /**< mean NIS of the last completed block (0 before the first) */
    unsigned flags;             /**< NISM_FLAG bits raised now */
    uint32_t episodes;          /**< times any channel's flag was raised */
} nism_t;

/** Defaults: window 100, threshold 10, trip_blocks 3. */
void nism_config_default(nism_config_t *cfg);

/** Validate and start. @return TV_OK, TV_ERR_NULL, TV_ERR_NONFINITE, TV_ERR_CONFIG. */
int nism_init(nism_t *m, const nism_config_t *cfg);

/**
 * Add one correction's innovations (channels with used = 0 are skipped; NaN or negative NIS
 * values are not added). @return the flags raised after this update.
 */
unsigned nism_update(nism_t *m, const ekf_innov_t *in);

#ifdef __cplusplus
}
#endif

#endif /* NIS_MONITOR_H */
