/**
 * @file sim_internal.h
 * @brief Functions shared between the files of the simulation core (sim_*.c); not part of the
 *        sim.h interface.
 */
#ifndef SIM_INTERNAL_H
#define SIM_INTERNAL_H

#include <math.h>

#include "sim.h"

#define SIM_NAN ((double)NAN)

/** stuck_release: the angle [rad] the plate starts at, held by stiction. */
#define SIM_STUCK_ANGLE_RAD 0.5

/** 1 when v is finite (no NaN, no infinity). */
int sim_finite(double v);

/** e^T P^-1 e by Cholesky of the 3x3 P; NaN when P is not positive definite (sim_stats.c). */
double sim_mahalanobis3(double P[TVM_NX][TVM_NX], const double e[TVM_NX]);

/** TV_OK when the options of a run are valid, else the error (sim_run.c). */
int sim_check_options(const sim_options_t *opt);

/** Initial control of a scenario, before app_init (sim_scenarios.c). */
void sim_scenario_control0(sim_scenario_t scn, app_control_t *c);

/** Target angle [rad] of the closed-loop scenarios at t [s] (sim_scenarios.c). */
double sim_target_rad(sim_scenario_t scn, double t_s);

/** Updates the application's control for time t [s]; TV_OK or an error (sim_scenarios.c). */
int sim_scenario_update(sim_scenario_t scn, app_t *app, double t_s);

#endif /* SIM_INTERNAL_H */
