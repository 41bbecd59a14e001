/**
 * @file plant_fault.h
 * @brief Fault injection for the host simulation: the fault specification of the command line
 *        (`--fault KIND[:MAGNITUDE]@T_S[:RAMP_S]`), its strict parser, and the schedule that
 *        turns a list of specifications into the plant_faults_t in force at a time.
 *
 * SYNTAX. KIND:MAGNITUDE@T_S for a fault of a size, KIND@T_S for one without (winding_open,
 * tpsN_stuck, bridge_pos_lost, bridge_neg_lost); :RAMP_S after the time makes it a drift that
 * grows linearly from healthy at T_S to the full magnitude at T_S + RAMP_S (kinds with a size,
 * except jam). Numbers are decimal (strtod), finite; T_S 0..PLANT_FAULT_T_MAX_S, RAMP_S
 * (0, PLANT_FAULT_T_MAX_S]. The fault is in force at every simulation tick t >= T_S (the 1 kHz
 * grid: an onset between ticks takes effect at the next one).
 *
 * KINDS (fault class of issue 12 in brackets; magnitude, unit and accepted range):
 *   friction_high            [friction_high]   factor on Coulomb Mc and static Ms [-], (1, 10]
 *   jam                      [jam]             holding torque [N m], (0, 100]: the plate stops
 *                                              where it is and stays while |net torque| <= Ms + it
 *   spring_weak              [spring_weak]     remaining fraction of preload M0 and rate c [-], [0, 1)
 *   winding_resistance_high  [winding_resistance_high] factor on R [-], (1, 10]
 *   winding_open             [winding_open]    none: the current is 0 from T_S on
 *   winding_short            [winding_short]   shorted fraction s of the turns [-], (0, 0.9]:
 *                                              R, Kt, Ke x (1 - s), L x (1 - s)^2
 *   tps1_offset, tps2_offset [tps1_fault / tps2_fault] offset of the track's output in % of
 *                                              the sensor supply (its full output range), signed,
 *                                              0 < |m| <= 50 (1 % = 50 mV = 40.96 counts at the
 *                                              default front end)
 *   tps1_gain, tps2_gain     [tps1_fault / tps2_fault] gain error of the track's output [%],
 *                                              signed, 0 < |m|, -100 < m <= 100
 *   tps1_stuck, tps2_stuck   [tps1_fault / tps2_fault] none: the output stays at its value of the
 *                                              first conversion at or after T_S
 *   tps1_intermittent, tps2_intermittent [tps1_fault / tps2_fault] probability per conversion
 *                                              that the wiper loses contact and the track reads
 *                                              0 V [-], (0, 1]
 *   current_offset           [current_sensor_fault] offset referred to the winding current [A],
 *                                              signed, 0 < |m| <= 10
 *   current_gain             [current_sensor_fault] gain error [%], signed, 0 < |m|, -100 < m <= 100
 *   bridge_pos_lost, bridge_neg_lost [bridge_fault] none: the bridge applies 0 V when positive
 *                                              (opening) / negative duty is commanded
 *   supply_sag               [supply_sag]      drop of the bridge supply [V], (0, 100]; it must
 *                                              stay below the unit's supply (checked when applied)
 * Several faults may be combined; a kind may appear once (and bridge_pos_lost not with bridge_neg_lost).
 */
#ifndef PLANT_FAULT_H
#define PLANT_FAULT_H

#include <stddef.h>

#include "plant.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest onset time and ramp of a fault [s] (the longest simulation). */
#define PLANT_FAULT_T_MAX_S 600.0
/** Largest number of faults in one list. */
#define PLANT_FAULT_LIST_MAX 8u
/** Size of an error-message buffer that never truncates a message of the parser [chars]. */
#define PLANT_FAULT_MSG_MAX 256u

/** Fault kinds (see the file comment for the magnitude of each). */
typedef enum {
    PLANT_FAULT_FRICTION_HIGH = 0,
    PLANT_FAULT_JAM,
    PLANT_FAULT_SPRING_WEAK,
    PLANT_FAULT_WINDING_R_HIGH,
    PLANT_FAULT_WINDING_OPEN,
    PLANT_FAULT_WINDING_SHORT,
    PLANT_FAULT_TPS1_OFFSET,
    PLANT_FAULT_TPS1_GAIN,
    PLANT_FAULT_TPS1_STUCK,
    PLANT_FAULT_TPS1_INTERMITTENT,
    PLANT_FAULT_TPS2_OFFSET,
    PLANT_FAULT_TPS2_GAIN,
    PLANT_FAULT_TPS2_STUCK,
    PLANT_FAULT_TPS2_INTERMITTENT,
    PLANT_FAULT_CURRENT_OFFSET,
    PLANT_FAULT_CURRENT_GAIN,
    PLANT_FAULT_BRIDGE_POS_LOST,
    PLANT_FAULT_BRIDGE_NEG_LOST,
    PLANT_FAULT_SUPPLY_SAG,
    PLANT_FAULT_KIND_COUNT /**< number of kinds (not a kind) */
} plant_fault_kind_t;

/** One fault: what, how large, from when, over how long it grows. */
typedef struct {
    plant_fault_kind_t kind;
    double magnitude;   /**< in the kind's unit (1 for kinds without a magnitude) */
    double t_s;         /**< onset [s], 0..PLANT_FAULT_T_MAX_S */
    double ramp_s;      /**< 0: abrupt; > 0: linear from healthy at t_s to magnitude at t_s + ramp_s [s] */
} plant_fault_spec_t;

/** A list of faults (caller-owned). */
typedef struct {
    plant_fault_spec_t spec[PLANT_FAULT_LIST_MAX];
    unsigned n; /**< faults in spec[] */
} plant_fault_list_t;

/** Kind name as written on the command line ("friction_high", ...); "?" if invalid. */
const char *plant_fault_kind_name(plant_fault_kind_t kind);

/** Fault class of issue 12 the kind belongs to ("tps1_fault" for tps1_offset, ...); "?" if invalid. */
const char *plant_fault_kind_class(plant_fault_kind_t kind);

/** Unit and range of the kind's magnitude, one line for --help ("factor on Mc and Ms [-], (1, 10]"). */
const char *plant_fault_kind_help(plant_fault_kind_t kind);

/**
 * Parse one specification (see the file comment).
 * @param text  the specification, e.g. "friction_high:2.0@1.5" or "tps1_offset:1@0.5:0.2"
 * @param out   the parsed fault (written only on success)
 * @param msg   NULL, or a buffer for a message saying what is wrong (never names the option:
 *              the caller prefixes it); PLANT_FAULT_MSG_MAX characters always suffice
 * @param cap   size of msg [chars]
 * @return TV_OK; TV_ERR_NULL (text or out NULL); TV_ERR_FORMAT (syntax, unknown kind, a
 *         magnitude given to a kind without one or missing, a ramp on a kind that cannot
 *         drift); TV_ERR_RANGE (a number outside its range); TV_ERR_NONFINITE (nan, inf).
 */
int plant_fault_parse(const char *text, plant_fault_spec_t *out, char *msg, size_t cap);

/** Empty the list. Does nothing when list is NULL. */
void plant_fault_list_clear(plant_fault_list_t *list);

/**
 * Parse text and append it to the list.
 * @return plant_fault_parse()'s status; TV_ERR_NULL; TV_ERR_RANGE when the list is full or
 *         the kind is already in it (msg says which). On error the list is unchanged.
 */
int plant_fault_list_add(plant_fault_list_t *list, const char *text, char *msg, size_t cap);

/**
 * Level of a fault at time t_s: 0 before the onset, (t - t_s) / ramp_s during the ramp, 1 after.
 * 0 when spec is NULL.
 */
double plant_fault_level(const plant_fault_spec_t *spec, double t_s);

/**
 * The faults in force at time t_s: plant_faults_none() with each fault of the list applied at
 * its level (a factor f at level a is 1 + a (f - 1), an offset m is a m, a fault without a
 * magnitude is on at any level > 0). The tracks' offsets are in volts of the given sensor supply.
 * @param list          the faults (NULL or empty: healthy)
 * @param t_s           time [s]
 * @param tps_supply_V  the unit's sensor supply [V] (plant_config_t::tps_supply_V)
 * @param out           the faults in force
 * @return TV_OK; TV_ERR_NULL (out NULL).
 */
int plant_fault_at(const plant_fault_list_t *list, double t_s, double tps_supply_V, plant_faults_t *out);

#ifdef __cplusplus
}
#endif

#endif /* PLANT_FAULT_H */
