/**
 * @file id_params.h
 * @brief An identification's result as a parameter file in the project's key = value format
 *        (host_sim/replay/params.h): what `identify -o` writes, and what the population
 *        benchmark's identified section (host_sim/sim/population_main.c) applies to each unit.
 */
#ifndef ID_PARAMS_H
#define ID_PARAMS_H

#include <stdio.h>

#include "identify.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Write the identified parameters of r as key = value lines, each with its standard deviation
 * as a comment; a parameter not identified (or outside its key's range) is written as a comment
 * only, so the reader keeps its default. Kt = Ke = nKe / gear. The contact damping follows the
 * stop-learning rule (lambda = 0.16 s/rad x k). When the motor, inertia, friction and springs
 * (R, nKe, J, M0, c, Mc, Ms, Kv) are all identified it also writes diag.identified = 1: the
 * diagnostic bounds then judge friction and preload relative to this model
 * (diag_detect_config_identified()). log_name names the source in the header comment.
 * @return TV_OK, or TV_ERR_IO when the stream failed.
 */
int id_write_params(FILE *f, const char *log_name, const id_result_t *r, double gear);

#ifdef __cplusplus
}
#endif

#endif /* ID_PARAMS_H */
