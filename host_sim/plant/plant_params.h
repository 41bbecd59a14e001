/**
 * @file plant_params.h
 * @brief Plant parameter files for host_sim --plant-params: the same "key = value" format as the
 *        application's parameter files, with keys "plant.FIELD" for the physical fields of
 *        plant_config_t (motor, friction, springs, stops and contact, sensors, noise). So the
 *        simulated throttle can differ from the estimator's model: the filter keeps its own
 *        parameters (--params), the plant gets these.
 *
 * Every key is optional; a key not given keeps plant_config_default()'s value. Errors name the
 * file, the line and the key: not "key = value", an unknown or duplicate key, a value that is
 * not a finite number, a line over PLANT_PARAMS_LINE_MAX bytes or with a NUL byte; then
 * plant_config_check() names the field whose value (or combination) the plant refuses.
 */
#ifndef PLANT_PARAMS_H
#define PLANT_PARAMS_H

#include <stddef.h>
#include <stdio.h>

#include "plant.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PLANT_PARAMS_LINE_MAX 1024u /**< longest line [bytes] */
#define PLANT_PARAMS_MSG_MAX 512u   /**< longest error message [bytes] */

/**
 * Apply the text of a plant parameter file (n bytes) to *cfg (start from plant_config_default()).
 * @param name  file name for messages
 * @return TV_OK; TV_ERR_FORMAT (syntax, unknown or duplicate key, not a number, line too long,
 *         NUL byte); TV_ERR_NONFINITE; TV_ERR_CONFIG (plant_config_check() refused). On error
 *         *cfg is unchanged and err says where and what.
 */
int plant_params_parse(const char *text, size_t n, const char *name, plant_config_t *cfg, char *err, size_t cap);

/** Read a file (at most 64 KiB) and apply it as plant_params_parse(); TV_ERR_IO naming the file. */
int plant_params_load(const char *path, plant_config_t *cfg, char *err, size_t cap);

/** Write every key with its value in *cfg (a plant parameter file). @return TV_OK or TV_ERR_IO. */
int plant_params_write(FILE *f, const plant_config_t *cfg);

#ifdef __cplusplus
}
#endif

#endif /* PLANT_PARAMS_H */
