/**
 * @file plant_draw.h
 * @brief A population of throttles for the host simulation: two throttle classes with their
 *        nominal parameters, and seeded random units drawn around a class's nominal from the
 *        documented ranges below, independent of the estimator's parameters.
 *
 * CLASSES (nominal plant_config_t):
 *   A  the paper's throttle (Table 1, plant_config_default()): R 4.3 ohm, L 2 mH, Kt = Ke 0.017,
 *      J 1.6e-3, n 40, Mc 0.2, Ms 0.3, ws 1 rad/s, Kv 0.01, M0 0.25, c 0.059; stops -0.10 and
 *      -0.10 + 84 deg rad; current sense 0.1 V/A.
 *   B  a second type with a low-resistance motor (higher current) and other springs: R 1.6 ohm,
 *      L 1.0 mH, Kt = Ke 0.011 N m/A, J 1.2e-3 kg m^2, n 40, Mc 0.15, Ms 0.22 N m, ws 1.5 rad/s,
 *      Kv 0.008 N m s/rad, M0 0.32 N m, c 0.09 N m/rad; stops -0.08 and 1.42 rad; current
 *      sense 0.075 V/A (stall current at 13.5 V: 8.4 A). Its filter runs with these nominal
 *      values (sim_model_from_plant()).
 *
 * SPREADS (plant_draw(); U = uniform, LU = log-uniform, factors multiply the class nominal):
 *   PLANT_SPREAD_NONE   the class nominal;
 *   PLANT_SPREAD_STOPS  motor, friction and springs nominal; varied:
 *       closed stop U(-0.15, -0.05) rad, open stop U(1.30, 1.50) rad,
 *       stop stiffness: secant stiffness k_eff at 2.5 mrad penetration LU(1e2, 1e5) N m/rad,
 *           Hunt-Crossley exponent U(1.0, 1.5), k = k_eff / 0.0025^(e - 1),
 *       stop damping lambda = alpha k, alpha LU(0.05, 0.5) s/rad (restitution at a 10 rad/s
 *           impact from about 0.85 down to 0.2; the default 0.143 gives 0.5),
 *       sensor front end within a realistic spec: current-sense offset 1.65 V +- 50 mV and gain
 *           +- 3 %; track 1 at the unit's closed stop 0.10 +- 0.015 of the sensor supply and
 *           its rise to the open stop 0.80 +- 0.02 (the sensor is adjusted to the unit's travel
 *           at end of line, tps_ref_* = the drawn stops); sensor supply 5 V +- 2 %; divider
 *           gains +- 1 %; bridge supply 13.5 V +- 1 V;
 *       limp-home detent half-width LU(3e-5, 3e-4) rad (the class nominal 1e-4: the preload
 *           acts through the contact of the two springs' levers; the filter smooths it over
 *           its own e_phi, 1e-4 rad);
 *   PLANT_SPREAD_ALL    everything of STOPS, and: R, L, J, c, M0 x U(0.8, 1.2); Kt = Ke
 *       x U(0.9, 1.1) (one factor); Mc x U(0.7, 1.3), Ms x U(0.7, 1.3) then Ms >= Mc; ws
 *       x LU(0.5, 2); Kv x U(0.5, 1.5).
 * The sensor's transfer is tied to the plate angle: a soft stop's penetration is seen. The ECU of a unit is calibrated at end of line (current zero with the bridge off, tracks at
 * limp-home with their datasheet slope): sim_calib_from_plant() gives that calibration, so the
 * sensor spread moves counts, rails and quantisation, not the meaning of the measurement.
 * Stiff draws get more integration sub-steps (plant_config_check()'s stability bound).
 */
#ifndef PLANT_DRAW_H
#define PLANT_DRAW_H

#include <stdint.h>

#include "plant.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Throttle classes. */
typedef enum { PLANT_CLASS_A = 0, PLANT_CLASS_B = 1, PLANT_CLASS_COUNT } plant_class_t;

/** What a draw varies. */
typedef enum { PLANT_SPREAD_NONE = 0, PLANT_SPREAD_STOPS = 1, PLANT_SPREAD_ALL = 2, PLANT_SPREAD_COUNT } plant_spread_t;

/** Class name ("a", "b"); "?" if invalid. */
const char *plant_class_name(plant_class_t c);
/** Spread name ("none", "stops", "all"); "?" if invalid. */
const char *plant_spread_name(plant_spread_t s);
/** Class by name. @return TV_OK, TV_ERR_NULL, TV_ERR_RANGE (unknown: *out unchanged). */
int plant_class_from_name(const char *name, plant_class_t *out);
/** Spread by name. @return TV_OK, TV_ERR_NULL, TV_ERR_RANGE. */
int plant_spread_from_name(const char *name, plant_spread_t *out);

/** The nominal configuration of a class. @return TV_OK, TV_ERR_NULL, TV_ERR_RANGE (class). */
int plant_class_nominal(plant_class_t c, plant_config_t *cfg);

/**
 * Draw unit number unit_id of a class with a spread: the same (class, spread, unit_id) always
 * gives the same unit; the draw does not depend on the plant's noise seed.
 * @return TV_OK; TV_ERR_NULL; TV_ERR_RANGE (class or spread); TV_ERR_CONFIG if no sub-step count
 *         up to PLANT_SUBSTEPS_PER_MS_MAX makes the draw stable (cannot happen with these ranges).
 */
int plant_draw(plant_class_t c, plant_spread_t s, uint64_t unit_id, plant_config_t *cfg);

#ifdef __cplusplus
}
#endif

#endif /* PLANT_DRAW_H */
