/**
 * @file sim_unit.h
 * @brief The ECU configuration for a simulated unit of the population (plant_draw.h): the
 *        filter's model from its class's NOMINAL plant (the filter never sees the unit's own
 *        motor, friction, spring or stop values), and the end-of-line calibration of that unit's
 *        front end (current zero with the bridge off, tracks at limp-home with their slope), with
 *        the measurement noise variances that follow from it.
 */
#ifndef SIM_UNIT_H
#define SIM_UNIT_H

#include "app.h"
#include "plant.h"
#include "plant_draw.h"
#include "sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Estimator model parameters from a plant configuration: the physical values (R, L, Ke, Kt, J,
 * n, friction, springs, stop angles) copied; the contact law, smoothing widths, Ts and sub-steps
 * at tvm_params_default()'s values (the filter's stop model is its own).
 */
void sim_model_from_plant(const plant_config_t *plant, tvm_params_t *p);

/**
 * The calibration an end-of-line test gives the ECU of this unit: offsets and slopes of its
 * front end (current sense, both tracks referred to phi = 0, supply divider, ADC), exact.
 */
void sim_calib_from_plant(const plant_config_t *plant, app_calib_t *c);

/**
 * Application configuration for a unit of class cls: app_config_default(), the model of the
 * class nominal (sim_model_from_plant()), Q rebuilt for that model's L and J from the default
 * densities, the unit's calibration, and R from the sensor model of that calibration (noise of
 * the class nominal + LSB^2/12 in the channel's units).
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE (class); TV_ERR_CONFIG (Q).
 */
int sim_app_config_for_unit(plant_class_t cls, const plant_config_t *unit, app_config_t *cfg);

/**
 * What the start-up stop learning of run r (scenario stop_learn) learned, put into cfg's model as
 * the application puts it into its estimator when the routine ends (app.c): the fitted contact
 * onsets as the stops, the contact law (k, exponent) and its damping lambda_per_k x k.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_CONFIG when the routine did not finish (SL_DONE), cfg unchanged.
 */
int sim_apply_stop_learning(const sim_result_t *r, app_config_t *cfg);

#ifdef __cplusplus
}
#endif

#endif /* SIM_UNIT_H */
