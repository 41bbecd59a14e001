/**
 * @file tv_param_table.h
 * @brief The one table of configuration parameters: key, unit, range and meaning of every value
 *        a parameter file (host_sim, replay), the Linux controller's configuration file and the
 *        raw-log header can set. Every reader checks a value with tvp_check(), so a quantity has
 *        one range wherever it is configured. No scalar type, no heap: usable by any image.
 */
#ifndef TV_PARAM_TABLE_H
#define TV_PARAM_TABLE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Parameter ids, in table order (the order of a written parameter file). */
typedef enum {
    TVP_MODEL_R_OHM,
    TVP_MODEL_L_H,
    TVP_MODEL_KE_V_S_RAD,
    TVP_MODEL_KT_NM_A,
    TVP_MODEL_J_KG_M2,
    TVP_MODEL_N_GEAR,
    TVP_MODEL_MC_NM,
    TVP_MODEL_M0_NM,
    TVP_MODEL_C_NM_RAD,
    TVP_MODEL_KV_NM_S_RAD,
    TVP_MODEL_MS_NM,
    TVP_MODEL_WS_RAD_S,
    TVP_MODEL_PHI_CLOSED_RAD,
    TVP_MODEL_PHI_OPEN_RAD,
    TVP_MODEL_K_STOP_NM_RAD,
    TVP_MODEL_D_STOP_NM_S_RAD,
    TVP_MODEL_STOP_EXPONENT,
    TVP_MODEL_E_PHI_RAD,
    TVP_MODEL_E_W_RAD_S,
    TVP_MODEL_SUBSTEPS,
    TVP_EKF_QU_V2_S,
    TVP_EKF_QT_NM2_S,
    TVP_EKF_R_CURRENT_A2,
    TVP_EKF_R_VELOCITY_RAD2_S2,
    TVP_EKF_R_ANGLE_RAD2,
    TVP_EKF_CONTACT_BAND_RAD,
    TVP_EKF_QC_NM2_S,
    TVP_EKF_STOP_LEARN_MARGIN_RAD,
    TVP_EKF_QD_CONTACT_NM2_S,
    TVP_EKF_QD_FREE_NM2_S,
    TVP_EKF_D_TAU_S,
    TVP_EKF_CONTACT_NIS_GATE,
    TVP_EKF_CONTACT_W_COUPLING,
    TVP_EKF_QT_REL_S,
    TVP_EKF_IMPACT_TIMING,
    TVP_IMPACT_LEARN_ENABLE,
    TVP_IMPACT_LEARN_GAIN,
    TVP_STOP_LEARN_E_MIN,
    TVP_STOP_LEARN_E_MAX,
    TVP_STOP_LEARN_LAMBDA_PER_K_S_RAD,
    TVP_STOP_LEARN_K_MIN_NM_RAD,
    TVP_STOP_LEARN_K_MAX_NM_RAD,
    TVP_EKF_QR_OHM2_S,
    TVP_EKF_R_SIGMA0_OHM,
    TVP_EKF_DR_ABS_MAX_OHM,
    TVP_EKF_DR_EXCITE_A,
    TVP_EKF_QF_1_S,
    TVP_EKF_F_SIGMA0,
    TVP_EKF_F_ABS_MAX,
    TVP_EKF_F_EXCITE_RAD_S,
    TVP_EKF_QM_1_S,
    TVP_EKF_M_SIGMA0,
    TVP_EKF_M_ABS_MAX,
    TVP_EKF_NIS_INFLATE_ALPHA,
    TVP_EKF_NIS_INFLATE_THRESHOLD,
    TVP_EKF_NIS_INFLATE_MAX,
    TVP_EKF_WHITE_THRESHOLD,
    TVP_EKF_STUCK_Q_MIN,
    TVP_EKF_STUCK_HOLD_FRAC,
    TVP_DIAG_IDENTIFIED,
    TVP_DIAG_R_FIT_HIGH_FRAC,
    TVP_DIAG_FRICTION_HIGH_REL,
    TVP_DIAG_FRICTION_FAST_HIGH,
    TVP_DIAG_FRICTION_FAST_LEVEL_MIN,
    TVP_DIAG_FIT_BASE_R_OHM,
    TVP_DIAG_FIT_BASE_NKE_V_S,
    TVP_DIAG_FIT_BASE_WINDOWS,
    TVP_DIAG_R_FIT_BASE_HIGH_FRAC,
    TVP_DIAG_GAIN_FIT_BASE_MAX,
    TVP_CALIB_CURRENT_OFFSET_COUNTS,
    TVP_CALIB_CURRENT_A_PER_COUNT,
    TVP_CALIB_TPS1_COUNTS_AT_ZERO,
    TVP_CALIB_TPS1_RAD_PER_COUNT,
    TVP_CALIB_TPS2_COUNTS_AT_ZERO,
    TVP_CALIB_TPS2_RAD_PER_COUNT,
    TVP_CALIB_SUPPLY_V_PER_COUNT,
    TVP_LIMITS_CURRENT_MIN_COUNTS,
    TVP_LIMITS_CURRENT_MAX_COUNTS,
    TVP_LIMITS_TPS_MIN_COUNTS,
    TVP_LIMITS_TPS_MAX_COUNTS,
    TVP_LIMITS_TPS_DISAGREE_MAX_RAD,
    TVP_LIMITS_SUPPLY_MIN_V,
    TVP_LIMITS_SUPPLY_MAX_V,
    TVP_LIMITS_DEBOUNCE_TRIP,
    TVP_LIMITS_MAX_GAP_PERIODS,
    TVP_COUNT
} tvp_id_t;

/* Range flags. */
#define TVP_LO_OPEN 1u /**< value > lo (else >= lo) */
#define TVP_HI_OPEN 2u /**< value < hi (else <= hi) */
#define TVP_INTEGER 4u /**< integral values only */
#define TVP_NONZERO 8u /**< 0 excluded */

/** One parameter. */
typedef struct {
    const char *key;  /**< "group.name_unit", e.g. "calib.tps1_rad_per_count" */
    const char *unit; /**< SI unit (or counts, samples, "-") */
    double lo;        /**< lower bound (open with TVP_LO_OPEN) */
    double hi;        /**< upper bound (open with TVP_HI_OPEN) */
    unsigned flags;   /**< TVP_* flags */
    const char *doc;  /**< what it is, one line */
} tvp_desc_t;

/** The descriptor of id (NULL when id >= TVP_COUNT). */
const tvp_desc_t *tvp_desc(int id);

/** The id of a key, or -1 when no parameter has that key. */
int tvp_find(const char *key);

/**
 * Check a value against its parameter's range and flags.
 * @return 0 when allowed; -1 not finite; -2 outside the range (or 0 where TVP_NONZERO);
 *         -3 not an integer where one is needed; -4 no such id.
 */
int tvp_check(int id, double v);

/** The range as text, e.g. "(0, 1000]", "[1, 50], an integer" or "[-1, 1], not 0". */
void tvp_range_text(int id, char *out, size_t cap);

#ifdef __cplusplus
}
#endif

#endif /* TV_PARAM_TABLE_H */
