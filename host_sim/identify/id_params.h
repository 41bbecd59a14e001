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
 * only, so the reader keeps its default. Kt = Ke = nKe / gear. The contact damping is the
 * identified ratio x k (identify.h step 4), else the stop-learning rule's 0.16 s/rad x k. When the
 * impacts identified the law, the start-up stop learning is told to keep it: stop_learn.e_min =
 * e_max = the exponent, stop_learn.k_min/k_max_Nm_rad = the stiffness as a secant at
 * SL_P_REF_RAD -1 % / +1 %, stop_learn.lambda_per_k_s_rad = the ratio (it then re-learns the
 * onsets only, which move with wear and temperature). When the motor, inertia, friction and springs
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
