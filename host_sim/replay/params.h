/**
 * @file params.h
 * @brief Parameter files of host_sim and replay: the estimator's model (tvm_params_t), its
 *        noise (process-noise densities qu, qT and the measurement variances R), the ECU's
 *        count calibration and its plausibility limits, as plain `key = value` text.
 *
 * FORMAT (one setting per line; `replay --print-params` / `host_sim --print-params` write every
 * key with its default):
 *     # comment                      blank lines and comments are ignored
 *     model.R_ohm = 4.3              key = value; a value may be followed by "# comment"
 *     ekf.qu_V2_s = 5e-06
 * Keys are listed with their units and ranges in host_sim/replay/LOG_FORMATS.md ("Parameter files")
 * and by params_key_*(); values are decimal numbers (integers where the key says so).
 * Errors name the file, the line and the key: a line that is not `key = value`, an unknown key,
 * a missing value, a value that is not a number / not finite / not an integer, a value out of
 * the key's range, a key given twice, a line longer than PARAMS_LINE_MAX. Cross-field rules
 * (Ms >= Mc, min < max of the limits) are checked by params_apply() and name both keys.
 *
 * Keys not in the file keep their defaults: app_config_default(), or for replay the log's
 * calibration. When a model key or qu / qT is given, Q is recomputed by ekf_q_from_spectral()
 * from the densities in force (defaults EKF_DEFAULT_QU_V2_S, EKF_DEFAULT_QT_NM2_S) and the model
 * in force. This module is compiled per scalar type (params_apply() fills tv_real_t fields).
 */
#ifndef PARAMS_H
#define PARAMS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "app.h"
#include "rawlog.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest line of a parameter file, terminator excluded [bytes]. */
#define PARAMS_LINE_MAX 1024u
/** Number of keys. */
#define PARAMS_NKEYS 85
/** Room for the file name kept for messages [bytes]. */
#define PARAMS_NAME_MAX 256u
/** Room a message needs [bytes]. */
#define PARAMS_MSG_MAX 512u

/** Parsed settings: a value per key and the line that set it. */
typedef struct {
    double value[PARAMS_NKEYS];   /**< value of each key (valid where line != 0) */
    uint32_t line[PARAMS_NKEYS];  /**< line that set it, 0 = not set */
    char file[PARAMS_NAME_MAX];   /**< file name for messages */
} params_t;

/** Empty settings (nothing set), file name for messages (may be NULL). */
void params_init(params_t *p, const char *file);

/**
 * Parse a parameter text (all lines), adding to p. Stops at the first error.
 * @param err receives "FILE:LINE: problem" on error (cap bytes, may be NULL)
 * @return 0; TV_ERR_NULL; TV_ERR_FORMAT (syntax, unknown or duplicate key, missing value, not a
 *         number / integer); TV_ERR_NONFINITE; TV_ERR_RANGE (out of the key's range).
 */
int params_parse_text(params_t *p, const char *text, size_t n, char *err, size_t cap);

/**
 * Read a parameter file (streaming, one bounded line at a time) into p (params_init() first).
 * @return as params_parse_text(), and TV_ERR_IO when the file cannot be read.
 */
int params_load(params_t *p, const char *path, char *err, size_t cap);

/**
 * Set a key from the command line (overrides what a file set; the line is reported as 0).
 * @return 0; TV_ERR_NULL; TV_ERR_FORMAT (unknown key); TV_ERR_NONFINITE; TV_ERR_RANGE.
 */
int params_set(params_t *p, const char *key, double value, char *err, size_t cap);

/** 1 when key was set (file or params_set()), 0 otherwise or when the key is unknown. */
int params_is_set(const params_t *p, const char *key);

/**
 * Apply the settings on top of cfg (defaults, or a log's calibration already in it): copy the
 * keys that are set, recompute Q when a model key or a density is set (from the densities in
 * force, cfg->ekf.qu_V2_s and qT_Nm2_s, for those the file does not set; both are then stored
 * there), check the cross-field rules. cfg is only written on success.
 * @return 0; TV_ERR_NULL; TV_ERR_RANGE (a cross-field rule, or a value the scalar type of this
 *         build cannot hold: err names the keys); the status of ekf_q_from_spectral().
 */
int params_apply(const params_t *p, app_config_t *cfg, char *err, size_t cap);

/**
 * Write every key with its value in cfg (qu, qT: the densities Q was built from,
 * cfg->ekf.qu_V2_s and qT_Nm2_s) as a parameter file that params_load() reads back to the same
 * configuration.
 * @return 0; TV_ERR_NULL; TV_ERR_IO.
 */
int params_write(FILE *f, const app_config_t *cfg);

/** Name of key k (0 .. PARAMS_NKEYS - 1), NULL outside. */
const char *params_key_name(int k);

/** Index of a key, -1 if unknown. */
int params_key_index(const char *name);

/**
 * Write an application calibration into a raw-log header (the seven calibration fields; the
 * other fields are left as they are): the one mapping host_sim --raw-log, rawlog_gen and the
 * tests use, the inverse of what replay reads back.
 */
void params_calib_to_header(const app_calib_t *c, rawlog_header_t *h);

#ifdef __cplusplus
}
#endif

#endif /* PARAMS_H */
